// tests/gl/test_pyramid_index.cpp -- the shaders' packed-pyramid index (qc_pyramid_index) against gl::pyramid_index
#include "quadcast/gl/compute.hpp"
#include "quadcast/gl/depth_pyramid.hpp"
#include "quadcast/gl/osmesa_context.hpp"

#include <doctest/doctest.h>

#include <array>
#include <cstdint>
#include <random>
#include <vector>

using quadcast::gl::ComputeRunner;

TEST_CASE("pyramid index: the shaders' qc_pyramid_index addresses the texels gl::pyramid_index does, and the levels pack without gaps") {
    quadcast::gl::OsmesaContext ctx;
    // Input per case: offset, width, height of a level, then x, y; output: the index.
    const std::string source = ComputeRunner::prologue() + quadcast::gl::pyramid_index_glsl() +
                               "void main()\n{\n"
                               "    uint i;\n"
                               "    if (!qc_index(i)) return;\n"
                               "    uvec3 level = uvec3(qc_in[5u * i], qc_in[5u * i + 1u], qc_in[5u * i + 2u]);\n"
                               "    qc_out[i] = qc_pyramid_index(level, uvec2(qc_in[5u * i + 3u], qc_in[5u * i + 4u]));\n"
                               "}\n";
    ComputeRunner runner(ctx.api(), source, "pyramid index");
    std::mt19937 rng(7);
    // Viewports and shadow maps from a pixel to the largest pyramid GL_MAX_TEXTURE_BUFFER_SIZE
    // (2^27 texels on llvmpipe) allows: 10000 x 10000 packs 133.3M texels, past float's exact 2^24.
    const std::array<std::array<std::uint32_t, 2>, 9> sizes{{{1, 1}, {1, 9}, {7, 1}, {5, 3}, {1024, 768}, {1021, 9}, {2048, 2048}, {4097, 3001}, {10000, 10000}}};
    std::vector<std::uint32_t> in;
    std::vector<std::size_t> want;
    for (const auto& s : sizes) {
        const auto levels = quadcast::gl::pyramid_levels(s[0], s[1]);
        std::size_t next = 0;
        for (const auto& l : levels) {
            // Packed without gaps or overlap: each level starts where the one below ends, the last
            // texel of the last level is the buffer's last.
            CHECK(l[0] == next);
            next = quadcast::gl::pyramid_index(l, l[1] - 1, l[2] - 1) + 1;
            std::uniform_int_distribution<std::uint32_t> ux(0, l[1] - 1), uy(0, l[2] - 1);
            std::vector<std::array<std::uint32_t, 2>> texels{{0, 0}, {l[1] - 1, 0}, {0, l[2] - 1}, {l[1] - 1, l[2] - 1}};
            for (int k = 0; k < 64; ++k) texels.push_back({ux(rng), uy(rng)});
            for (const auto& t : texels) {
                in.insert(in.end(), {l[0], l[1], l[2], t[0], t[1]});
                want.push_back(quadcast::gl::pyramid_index(l, t[0], t[1]));
            }
        }
        CHECK(next == quadcast::gl::pyramid_texels(levels));
    }
    const auto out = runner.run(in, want.size(), want.size()).output;
    std::size_t wrong = 0, beyond_float = 0;
    for (std::size_t i = 0; i < want.size(); ++i) {
        wrong += out[i] != want[i];
        beyond_float += want[i] > (std::size_t(1) << 24);
    }
    CHECK(wrong == 0);
    CHECK(beyond_float > 100);  // (the indices a float index would round)
}
