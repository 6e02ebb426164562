// quadcast/gl/depth_pyramid.hpp -- host plumbing of the occlusion passes: pyramid layout, pyramid build, dispatch in rows
#pragma once
// Host-only. Shared by the quadric renderer's cull pass and the isosurface renderer's phases
// (and their shown sets).

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "quadcast/gl/loader.hpp"
#include "quadcast/gl/program.hpp"

namespace quadcast::gl {

/// The levels of a max-depth pyramid over a w x h base down to 1 x 1, packed in one buffer:
/// per level (offset, width, height); each level halves the one below, rounding up.
inline std::vector<std::array<std::uint32_t, 3>> pyramid_levels(std::uint32_t w, std::uint32_t h) {
    std::vector<std::array<std::uint32_t, 3>> levels{{0u, w, h}};
    while (levels.back()[1] > 1 || levels.back()[2] > 1) {
        const auto& b = levels.back();
        levels.push_back({b[0] + b[1] * b[2], (b[1] + 1) / 2, (b[2] + 1) / 2});
    }
    return levels;
}

/// The packed buffer's index of texel (x, y) of a pyramid level (offset, width, height): offset +
/// y width + x. The shaders' twin is `qc_pyramid_index` (`pyramid_index_glsl`), in uint
/// arithmetic (not traced: the float tracer is exact below 2^24 only, and a pyramid may hold up to
/// GL_MAX_TEXTURE_BUFFER_SIZE texels, `view_depth_texels`).
inline std::size_t pyramid_index(const std::array<std::uint32_t, 3>& level, std::uint32_t x, std::uint32_t y) {
    return std::size_t(level[0]) + std::size_t(y) * level[1] + x;
}

/// GLSL of `qc_pyramid_index(level, p)`, `pyramid_index` for texel p of a level (offset, width,
/// height) in uint arithmetic: every pass that reads or writes the packed pyramid addresses it so
/// (tests/gl/test_pyramid_index.cpp runs it against `pyramid_index`).
inline std::string pyramid_index_glsl() {
    return "// Texel p of a pyramid level (offset, width, height) in the packed buffer (quadcast::gl::pyramid_index).\n"
           "uint qc_pyramid_index(uvec3 level, uvec2 p) { return level.x + p.y * level.y + p.x; }\n\n";
}

/// Texels of all `levels` (the buffer's size in uints).
inline std::size_t pyramid_texels(const std::vector<std::array<std::uint32_t, 3>>& levels) {
    const auto& l = levels.back();
    return std::size_t(l[0]) + std::size_t(l[1]) * l[2];
}

/// The texture unit at which the cull passes and the early discard read the max-depth pyramid,
/// through a texture-buffer view of its storage buffer (`view_depth_texels`): llvmpipe loads a
/// storage-buffer word lane by lane, and fetches texels for all lanes at once.
inline constexpr GLuint depth_texels_unit = 8;

/// Points the texture-buffer view `view` (made when 0) at all of `buffer`, a pyramid of `texels`
/// GL_R32UI texels; again after each new data store of `buffer`. A pyramid larger than
/// GL_MAX_TEXTURE_BUFFER_SIZE (2^27 texels on llvmpipe: viewports and shadow maps up to about
/// 10000 x 10000) is an error: fetches beyond it would read 0, "behind", and drop what shows.
inline void view_depth_texels(const Api& gl, GLuint& view, GLuint buffer, std::size_t texels) {
    GLint max_texels = 0;
    gl.GetIntegerv(GL_MAX_TEXTURE_BUFFER_SIZE, &max_texels);
    if (texels > static_cast<std::size_t>(std::max(max_texels, 0)))
        throw std::runtime_error("quadcast::gl: occlusion culling needs a max-depth pyramid of " + std::to_string(texels) + " texels, more than this GL's GL_MAX_TEXTURE_BUFFER_SIZE (" +
                                 std::to_string(max_texels) + "): the viewport or shadow map is too large (turn occlusion culling off)");
    if (view == 0) gl.CreateTextures(GL_TEXTURE_BUFFER, 1, &view);
    gl.TextureBuffer(view, GL_R32UI, buffer);
}

/// Levels `written` + 1 .. of a pyramid whose levels up to `written` are written, in the buffer
/// bound at binding 3, each the max of the texels below it (`pyr`: the program of
/// OcclusionPass::pyramid), with the barriers between them and after the last (for storage-buffer
/// reads and for texel fetches through `view_depth_texels`).
inline void build_pyramid(const Api& gl, const Program& pyr, const std::vector<std::array<std::uint32_t, 3>>& levels, std::size_t written = 0) {
    gl.UseProgram(pyr.id());
    for (std::size_t l = written + 1; l < levels.size(); ++l) {
        gl.MemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
        gl.Uniform3ui(pyr.uniform_location("qc_src"), levels[l - 1][0], levels[l - 1][1], levels[l - 1][2]);
        gl.Uniform3ui(pyr.uniform_location("qc_dst"), levels[l][0], levels[l][1], levels[l][2]);
        gl.DispatchCompute((levels[l][1] + 7) / 8, (levels[l][2] + 7) / 8, 1);
    }
    gl.MemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT);
}

/// Sets the cull passes' uniforms qc_levels[16] and qc_level_count of `p` (bound) from `levels`
/// (at most the first 16).
inline void set_pyramid_uniforms(const Api& gl, const Program& p, const std::vector<std::array<std::uint32_t, 3>>& levels) {
    std::vector<GLuint> lv;
    for (const auto& l : levels) lv.insert(lv.end(), l.begin(), l.end());
    const int level_count = static_cast<int>(std::min<std::size_t>(levels.size(), 16));
    gl.Uniform3uiv(p.uniform_location("qc_levels"), level_count, lv.data());
    gl.Uniform1i(p.uniform_location("qc_level_count"), level_count);
}

/// Dispatches n workgroups of a pass over records (none for n = 0) in rows of at most
/// `row_limit` (65535, GL's guaranteed limit per dimension); the shaders number a workgroup
/// gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x and return past their records.
inline void dispatch_rows(const Api& gl, std::uint32_t n, std::uint32_t row_limit = 65535u) {
    if (n == 0) return;
    const std::uint32_t x = std::min<std::uint32_t>(n, row_limit);
    gl.DispatchCompute(x, (n + x - 1) / x, 1);
}

/// Of the shown sets a renderer keeps per depth target (RenderOptions::occlusion_reuse; a `Set`
/// has the fields `target` and `valid`), the one of `target`, or else the slot replaced in turn
/// (`next`), given to `target` and not valid.
template <class Set, std::size_t N, class Target>
Set& shown_set_of(Set (&slots)[N], int& next, Target target) {
    for (Set& s : slots)
        if (s.target == target) return s;
    Set& s = slots[next];
    next = (next + 1) % static_cast<int>(N);
    s.target = target;
    s.valid = false;
    return s;
}

}  // namespace quadcast::gl
