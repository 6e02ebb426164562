// Percentage-closer filtering streamed one sample at a time (the deferred stage's form:
// `pcf_count_step`, `pcf_first8_from_count`, `pcf_fraction64`) against the whole-array filter
// (`pcf_lit_fraction<64>`, `pcf_soft_shadow`), bit for bit, and against a direct count in double.
#include <doctest/doctest.h>

#include <cstdio>
#include <random>

#include "quadcast/shading.hpp"

using namespace quadcast;

TEST_CASE("streamed PCF equals the 64-sample filter and the early-out, bit for bit") {
    std::mt19937 rng(20261206);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    long decided = 0, penumbra = 0, ties = 0;
    for (int trial = 0; trial < 200000; ++trial) {
        const float z = u(rng), bias = trial % 7 == 0 ? 0.0f : 0.01f * u(rng);
        // Receivers fully lit, fully shadowed, and in a penumbra; some samples exactly at z - bias.
        const int kind = trial % 4;
        float s[64];
        for (float& x : s) {
            const float spread = kind == 0 ? 0.0f : kind == 1 ? 0.002f : 0.03f;
            x = z - bias + (kind == 3 ? -0.5f : 0.0f) * spread + spread * (2.0f * u(rng) - 1.0f);
            if (u(rng) < 0.05f) {
                x = z - bias;
                ++ties;
            }
        }
        // The deferred stage's order: the first 8, then the other 56 where they do not agree
        float count = 0.0f;
        for (int k = 0; k < 8; ++k) count = pcf_count_step(count, z, bias, s[k]);
        const PcfFirst<float> first = pcf_first8_from_count(count);
        float vis = first.lit;
        if (!first.decided) {
            float count56 = 0.0f;
            for (int k = 8; k < 64; ++k) count56 = pcf_count_step(count56, z, bias, s[k]);
            vis = pcf_fraction64(first.lit, count56);
            ++penumbra;
            CHECK(vis == pcf_lit_fraction<64>(z, bias, s));
        } else {
            ++decided;
        }
        // The CPU reference's filter
        REQUIRE(vis == pcf_soft_shadow(z, bias, s));
        // A direct count in double (z - bias rounded in float, as every form does)
        const float zb = z - bias;
        int lit8 = 0, lit64 = 0;
        for (int k = 0; k < 64; ++k) {
            const int lit = zb <= s[k] ? 1 : 0;
            lit64 += lit;
            if (k < 8) lit8 += lit;
        }
        const double expect = lit8 == 0 || lit8 == 8 ? lit8 / 8.0 : lit64 / 64.0;
        REQUIRE(double(vis) == expect);
    }
    std::printf("[pcf] 200000 receivers: %ld decided by the first 8, %ld in a penumbra, %ld samples at exactly z - bias\n", decided, penumbra, ties);
    CHECK(decided > 50000);
    CHECK(penumbra > 50000);
}
