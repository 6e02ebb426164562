// tools/quadcast/timing.hpp -- the timing helpers of the `quadcast` commands
#pragma once

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <utility>
#include <vector>

namespace quadcast::cli {

/// Milliseconds since t0 (steady clock).
inline double ms_since(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

/// The median of v (the upper one for an even count); 0 for none.
inline double median(std::vector<double> v) {
    if (v.empty()) return 0.0;
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
}

/// Frames timed in pairs, frame(false) then frame(true) (the default last, so that what follows
/// them is its frame): the medians of the two, {off, on}.
template <class Frame>
std::pair<double, double> interleaved_medians(int pairs, Frame&& frame) {
    std::vector<double> off, on;
    for (int i = 0; i < pairs; ++i)
        for (bool b : {false, true}) {
            const auto t0 = std::chrono::steady_clock::now();
            frame(b);
            (b ? on : off).push_back(ms_since(t0));
        }
    return {median(off), median(on)};
}

/// The process's peak and current resident memory in bytes (VmHWM, VmRSS of /proc/self/status;
/// 0 where there is none).
struct ResidentMemory {
    std::size_t peak = 0, current = 0;
};
inline ResidentMemory resident_memory() {
    ResidentMemory m;
    std::FILE* f = std::fopen("/proc/self/status", "r");
    if (!f) return m;
    char line[256];
    while (std::fgets(line, sizeof line, f)) {
        unsigned long long kb = 0;
        if (std::sscanf(line, "VmHWM: %llu kB", &kb) == 1) m.peak = static_cast<std::size_t>(kb) << 10;
        else if (std::sscanf(line, "VmRSS: %llu kB", &kb) == 1) m.current = static_cast<std::size_t>(kb) << 10;
    }
    std::fclose(f);
    return m;
}

/// Prints phase after phase to stderr with `--timing`: "timing: load 812.3 ms (resident 301 MB,
/// peak 512 MB)"; does nothing when off.
class PhaseTimer {
public:
    explicit PhaseTimer(bool on) : on_(on) {}
    void phase(const char* name) {
        if (!on_) return;
        const double ms = ms_since(t_);
        const ResidentMemory m = resident_memory();
        std::fprintf(stderr, "timing: %-8s %9.1f ms  (resident %zu MB, peak %zu MB)\n", name, ms, m.current >> 20, m.peak >> 20);
        t_ = std::chrono::steady_clock::now();
    }

private:
    bool on_;
    std::chrono::steady_clock::time_point t_ = std::chrono::steady_clock::now();
};

}  // namespace quadcast::cli
