// Percentage-closer filtering streamed one sample at a time (the deferred stage's form:
// `pcf_count_step`, `pcf_first8_from_count`, `pcf_fraction64`) against the whole-array filter
// (`pcf_lit_fraction<64>`, `pcf_soft_shadow`), bit for bit, and against a direct count in double;
// the shadow map in phases (`pcf_phase`, `phase_source_texel`) against `pcf_sample_texel`.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <vector>

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
            // The gathered form: all 64 counted again, in the phase map's order (rows of the grid)
            float count64 = 0.0f;
            for (int g = 0; g < 64; ++g)
                for (int k = 0; k < 64; ++k)
                    if (pcf_grid_order[k] == g) count64 = pcf_count_step(count64, z, bias, s[k]);
            CHECK(pcf_fraction_of64(count64) == vis);
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

TEST_CASE("the shadow map in phases holds every receiver's PCF samples as 8 x 8 consecutive texels") {
    // `pcf_phase` gives the texel of the map in phases where a receiver's first sample lies, and
    // `phase_source_texel` the map texel each texel of it holds: together they must give, for
    // sample (gx, gy) at cell + (gx, gy), exactly the clamped texel `pcf_sample_texel` reads for
    // grid cell 8 gy + gx, inside the map, across and far beyond its edges, and for NaN and
    // infinite positions; and every such texel must lie inside the image. Checked against
    // integer arithmetic too: the texel is clamp(floor(p) + g step - floor(7 step / 2)).
    std::mt19937 rng(20261206);
    long checked = 0;
    for (const int map : {64, 100, 257, 1024, 2048, 8192})
        for (const int step : {1, 2, 3, 4, 5, 7, 8, 13, 64}) {
            const float last = float(map - 1), fstep = float(step), inv_step = 1.0f / fstep;
            const int tile_i = pcf_phase_tile(map, step);
            const float tile = float(tile_i), inv_tile = 1.0f / tile;
            const int size = tile_i * step;
            std::uniform_real_distribution<float> pos(-1.5f * 8.0f * fstep - 20.0f, float(map) + 8.0f * fstep + 20.0f);
            std::vector<float> xs;
            for (int k = 0; k < 300; ++k) xs.push_back(pos(rng));
            for (const float x : {0.0f, 0.5f, last, last + 0.99f, float(map), -0.01f, 1e9f, -1e9f, std::numeric_limits<float>::infinity(),
                                  -std::numeric_limits<float>::infinity(), std::numeric_limits<float>::quiet_NaN()})
                xs.push_back(x);
            for (std::size_t k = 0; k < xs.size(); ++k) {
                const Vec2<float> texel = vec2(xs[k], xs[(k * 7 + 3) % xs.size()]);
                const Vec2<float> cell = pcf_phase(texel, fstep, inv_step, last, tile);
                for (int g = 0; g < 64; ++g) {
                    const int gx = g % 8, gy = g / 8;
                    const Vec2<float> ref = pcf_sample_texel(texel, float(g), fstep, last);
                    const float px = cell[0] + float(gx), py = cell[1] + float(gy);
                    REQUIRE(px >= 0.0f);
                    REQUIRE(py >= 0.0f);
                    REQUIRE(px < float(size));
                    REQUIRE(py < float(size));
                    const float sx = phase_source_texel(px, fstep, tile, inv_tile, last), sy = phase_source_texel(py, fstep, tile, inv_tile, last);
                    CAPTURE(map);
                    CAPTURE(step);
                    CAPTURE(texel[0]);
                    CAPTURE(texel[1]);
                    CAPTURE(g);
                    REQUIRE(sx == ref[0]);
                    REQUIRE(sy == ref[1]);
                    // integer arithmetic (finite positions)
                    if (std::isfinite(texel[0]) && std::abs(texel[0]) < 1e6f) {
                        const long long ix = static_cast<long long>(std::floor(texel[0])) + gx * step - (7 * step) / 2;
                        REQUIRE(sx == float(std::clamp<long long>(ix, 0, map - 1)));
                    }
                    ++checked;
                }
            }
        }
    std::printf("[pcf] shadow map in phases: %ld samples at the texels pcf_sample_texel reads\n", checked);
}

TEST_CASE("split_by_step is exact division with a non-negative remainder") {
    std::mt19937 rng(7);
    std::uniform_int_distribution<int> xs(-(1 << 21), 1 << 21), steps(1, 20000);
    for (int k = 0; k < 200000; ++k) {
        const int x = xs(rng), step = k % 3 == 0 ? 1 + k % 64 : steps(rng);
        const Vec2<float> qr = split_by_step(float(x), float(step), 1.0f / float(step));
        const int q = x >= 0 ? x / step : -((-x + step - 1) / step);
        REQUIRE(qr[0] == float(q));
        REQUIRE(qr[1] == float(x - q * step));
    }
}
