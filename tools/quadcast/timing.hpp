// tools/quadcast/timing.hpp -- the timing helpers of the `quadcast` commands
#pragma once

#include <algorithm>
#include <chrono>
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

}  // namespace quadcast::cli
