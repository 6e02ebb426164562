// quadcast/codegen/src/verify.cpp -- verification inputs, CPU reference runs and comparison
#include "quadcast/codegen/verify.hpp"

#include <bit>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>

namespace quadcast::codegen {

namespace {

/// SplitMix64: a small, fast, well-mixed generator; one per sample keeps samples independent.
struct SplitMix {
    std::uint64_t s;
    using result_type = std::uint32_t;
    static constexpr result_type min() { return 0; }
    static constexpr result_type max() { return UINT32_MAX; }
    std::uint64_t next64() {
        std::uint64_t z = (s += 0x9E3779B97F4A7C15ull);
        z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
        z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
        return z ^ (z >> 31);
    }
    result_type operator()() { return static_cast<result_type>(next64() >> 32); }
    float uniform(float lo, float hi) { return lo + (hi - lo) * static_cast<float>((next64() >> 40) * 0x1.0p-24); }
    int below(int n) { return static_cast<int>(next64() % static_cast<std::uint64_t>(n)); }
};

float adversarial(SplitMix& r, float scale) {
    constexpr float inf = std::numeric_limits<float>::infinity();
    switch (r.below(14)) {
    case 0: return 0.0f;
    case 1: return -0.0f;
    case 2: return 1.0f;
    case 3: return -1.0f;
    case 4: return inf;
    case 5: return -inf;
    case 6: return std::numeric_limits<float>::quiet_NaN();
    case 7: return std::numeric_limits<float>::denorm_min() * static_cast<float>(1 + r.below(1000));
    case 8: return std::numeric_limits<float>::max() * r.uniform(-1.0f, 1.0f);
    case 9: return std::numeric_limits<float>::min() * r.uniform(-4.0f, 4.0f);
    case 10: return r.uniform(-1.0f, 1.0f) * 1e-20f;
    default: return r.uniform(-1.0f, 1.0f) * scale;
    }
}

}  // namespace

std::vector<std::uint32_t> make_inputs(const KernelDef& k, std::size_t count, std::uint64_t seed) {
    Recorder rec;
    TraceIO io(rec);
    {
        Recording scope(rec);
        k.trace(io);
    }
    const int n = io.signature().input_words();
    std::vector<std::uint32_t> words(count * static_cast<std::size_t>(n));
    std::vector<float> sample(static_cast<std::size_t>(n));
    std::mt19937 mt(static_cast<std::uint32_t>(seed));  // one engine for the structured samples (seeding is costly)
    for (std::size_t i = 0; i < count; ++i) {
        SplitMix r{seed * 0x2545F4914F6CDD1Dull + i};
        const int kind = r.below(100);
        const float scale = std::ldexp(1.0f, r.below(81) - 40);
        if (kind < 40 && k.generate) {
            k.generate(mt, sample);
        } else if (kind < 70) {
            for (float& v : sample) v = r.uniform(-1.0f, 1.0f) * scale;
        } else if (kind < 90) {
            for (float& v : sample) v = r.below(3) == 0 ? adversarial(r, scale) : r.uniform(-1.0f, 1.0f) * scale;
        } else {
            for (float& v : sample) v = std::bit_cast<float>(r());
        }
        for (int j = 0; j < n; ++j) words[i * static_cast<std::size_t>(n) + static_cast<std::size_t>(j)] = std::bit_cast<std::uint32_t>(sample[static_cast<std::size_t>(j)]);
    }
    return words;
}

std::vector<std::uint32_t> run_cpu(const KernelDef& k, std::span<const std::uint32_t> inputs, std::size_t count) {
    Recorder rec;
    TraceIO io(rec);
    {
        Recording scope(rec);
        k.trace(io);
    }
    const std::size_t nin = static_cast<std::size_t>(io.signature().input_words());
    const std::size_t nout = static_cast<std::size_t>(io.signature().output_words());
    std::vector<std::uint32_t> out(count * nout);
    for (std::size_t i = 0; i < count; ++i) {
        CpuIO cpu(inputs.subspan(i * nin, nin), std::span<std::uint32_t>(out).subspan(i * nout, nout));
        k.cpu(cpu);
    }
    return out;
}

std::uint64_t ulp_distance(std::uint32_t a, std::uint32_t b) {
    const bool na = std::isnan(std::bit_cast<float>(a)), nb = std::isnan(std::bit_cast<float>(b));
    if (na || nb) return na && nb ? 0 : UINT64_MAX;
    auto ordered = [](std::uint32_t w) -> std::int64_t {
        return (w & 0x80000000u) ? -static_cast<std::int64_t>(w & 0x7FFFFFFFu) : static_cast<std::int64_t>(w);
    };
    const std::int64_t d = ordered(a) - ordered(b);
    return static_cast<std::uint64_t>(d < 0 ? -d : d);
}

Comparison compare(const Signature& sig, std::span<const std::uint32_t> inputs, std::span<const std::uint32_t> expected,
                   std::span<const std::uint32_t> actual, std::size_t count) {
    Comparison c;
    c.samples = count;
    const std::size_t nin = static_cast<std::size_t>(sig.input_words());
    const std::size_t nout = static_cast<std::size_t>(sig.output_words());
    std::vector<bool> is_mask;
    for (const Param& p : sig.outputs)
        for (int i = 0; i < components(p.kind); ++i) is_mask.push_back(p.kind == Kind::boolean);
    for (std::size_t s = 0; s < count; ++s) {
        bool same = true;
        for (std::size_t j = 0; j < nout; ++j) {
            const std::uint32_t e = expected[s * nout + j], a = actual[s * nout + j];
            if (is_mask[j]) {
                if (e != a) { same = false; ++c.mask_differences; }
                continue;
            }
            const std::uint64_t d = ulp_distance(e, a);
            if (d != 0) { same = false; c.max_ulp = std::max(c.max_ulp, d); }
        }
        if (same) { ++c.identical; continue; }
        if (c.first_difference == SIZE_MAX) {
            c.first_difference = s;
            std::ostringstream r;
            r << "sample " << s << " inputs:";
            char buf[48];
            for (std::size_t j = 0; j < nin; ++j) {
                std::snprintf(buf, sizeof buf, " %.9g", static_cast<double>(std::bit_cast<float>(inputs[s * nin + j])));
                r << buf;
            }
            r << "\n  cpu:";
            for (std::size_t j = 0; j < nout; ++j) { std::snprintf(buf, sizeof buf, " %08X", expected[s * nout + j]); r << buf; }
            r << "\n  gpu:";
            for (std::size_t j = 0; j < nout; ++j) { std::snprintf(buf, sizeof buf, " %08X", actual[s * nout + j]); r << buf; }
            c.first_report = r.str();
        }
    }
    return c;
}

}  // namespace quadcast::codegen
