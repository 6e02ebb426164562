// src/gl/stage_builder.hpp -- assembling a stage shader around generated kernels (internal to quadcast::gl)
#pragma once

#include <set>
#include <sstream>
#include <stdexcept>
#include <string>
#include <string_view>

#include "quadcast/generated/shaders.hpp"
#include "quadcast/gl/depth_pyramid.hpp"
#include "quadcast/gl/stages.hpp"
#include "quadcast/render/record.hpp"

namespace quadcast::gl::detail {

/// A stage shader under construction: the generated functions it calls, the operations they use
/// and the C++ templates they come from (for the banner).
struct Stage {
    std::string text;
    std::set<std::string> ops;
    std::string sources;
};

/// Appends generated kernel `qc_<name>` to `fns` and records its operations and templates in `s`;
/// a stage needing a kernel that is not generated is a bug (run `make regenerate`).
inline void add_kernel(Stage& s, std::ostringstream& fns, const std::string& name) {
    const generated::Kernel* k = generated::find_kernel("qc_" + name);
    if (!k) throw std::logic_error("quadcast::gl: a stage shader needs kernel qc_" + name + ", which is not generated");
    fns << k->function << "\n";
    std::string_view ops = k->operations;
    while (!ops.empty()) {
        const std::size_t sp = ops.find(' ');
        s.ops.insert(std::string(ops.substr(0, sp)));
        ops = sp == std::string_view::npos ? std::string_view() : ops.substr(sp + 1);
    }
    s.sources += (s.sources.empty() ? "" : "; ") + std::string(k->templates);
}

/// The banner of an assembled stage (what the generated files' banners say, for the whole stage).
inline std::string banner(const std::string& name, const Stage& s, const std::string& summary) {
    std::ostringstream b;
    b << "// " << name << " -- assembled by quadcast::gl::program_stages from the generated kernels (generated/glsl/kernels).\n";
    b << "// " << summary << "\n";
    b << "// Traced from: " << s.sources << "\n";
    b << "// Operations: ";
    bool first = true;
    for (auto& o : s.ops) { b << (first ? "" : " ") << o; first = false; }
    b << "\n// Numerics: float; every operation is its own `precise` statement (no contraction, no\n"
         "// reassociation); literals are exact; no built-in whose rounding differs from the CPU.\n";
    return b.str();
}

/// The complete text of stage `s`: version line, banner, text.
inline StageText stage_text(StageText::Kind kind, const std::string& name, const Stage& s, const std::string& summary) {
    return {kind, name, "#version 450 core\n" + banner(name, s, summary) + "\n" + s.text};
}

/// The bounding-sphere quad of record `p` (`primitive_bound_<proj>`): declares its view-space
/// corners `corners[4]` and `valid` (false: use the near-plane rectangle `qc_near_corners`).
std::string sphere_quad_glsl(const std::string& proj);

/// The vertex stages' uniforms of the bounding geometry (view, projection, near corners, ...).
std::string bound_uniforms_glsl();

/// The full-screen triangle of the deferred and resolve passes (positions from gl_VertexID; no
/// numbers; src/gl/stages.cpp).
extern const char* const fullscreen_vertex;

/// The primitive's record passed from the vertex stage to the fragment stage as flat varyings
/// (qc_record[k] = slot k of qc_Primitive) instead of read by every fragment from the storage
/// buffer: llvmpipe loads a storage buffer lane by lane, and the 7 slots per fragment cost more
/// than the cast (bench sticks, 50k sticks, three runs interleaved with the buffer reads: the frame
/// without a cull pass 243-267 ms against 338-390 ms, with it 138-166 against 172-201 ms).
/// The declaration (`dir` "out" or "in"), the vertex stage's copy from its record `p`, and the
/// fragment stage's `qc_Primitive p` rebuilt from them.
inline std::string record_varyings_glsl(const char* dir) {
    return std::string("flat ") + dir + " vec4 qc_record[" + std::to_string(render::record_slots) + "];  // the primitive's record (qc_Primitive's slots)\n";
}
inline std::string record_varyings_out() {
    std::string t;
    for (int k = 0; k < render::record_slots; ++k) t += "    qc_record[" + std::to_string(k) + "] = p.s" + std::to_string(k) + ";\n";
    return t;
}
inline std::string record_varyings_in() {
    std::string t = "    qc_Primitive p = qc_Primitive(";
    for (int k = 0; k < render::record_slots; ++k) t += std::string(k ? ", " : "") + "qc_record[" + std::to_string(k) + "]";
    return t + ");\n";
}

/// GLSL reading the max-depth pyramid (its levels packed, as the passes write them into their
/// storage buffer) through a texture-buffer view of that buffer (GL_R32UI, bound at unit
/// gl::depth_texels_unit of quadcast/gl/depth_pyramid.hpp): `qc_depth_texel(i)`. llvmpipe fetches
/// a texel for all the SIMD vector's lanes at once, where it loads a storage-buffer word lane by
/// lane: 64 reads per invocation over 1M invocations took 19-21 against 44-46 ms. Also declares
/// `qc_pyramid_index` (gl::pyramid_index_glsl).
inline std::string depth_texels_glsl() {
    return gl::pyramid_index_glsl() +
           "// The max-depth pyramid (levels packed), read through a texture-buffer view of its storage buffer.\n"
           "layout(binding = " + std::to_string(gl::depth_texels_unit) + ") uniform usamplerBuffer qc_depth_texels;\n"
           "uint qc_depth_texel(uint i) { return texelFetch(qc_depth_texels, int(i)).r; }\n\n";
}

/// GLSL of the max-depth pyramid lookup of the cull passes: `qc_pyramid_farthest(b)`, the largest
/// value over the pixels b = (x0, y0, x1, y1) (inclusive) read from the lowest level where they
/// span at most `span` x `span` texels; the stage declares `qc_depth_texel` (`depth_texels_glsl`),
/// qc_levels[16] (offset, width, height per level) and qc_level_count.
/// A finer level holds more of the occluders' detail (a texel is as far as the farthest pixel
/// under it) but costs span^2 reads: the quadric cull pass reads up to 8 x 8 (bench sticks: 8-9%
/// fewer primitives drawn than at 4 x 4, 16 x 16 cost more than it saved), the isosurfaces' up to 4 x 4.
/// With `behind`, `qc_pyramid_behind(b, bits)` instead: whether `bits` (float bits of a positive
/// view distance) lies behind that farthest value. It first reads the coarser level where b spans
/// at most 2 x 2 texels: a texel there is the farthest of those below it, so where `bits` already
/// lies behind those the finer read would say so too: the same answer in at most 4 loads.
inline std::string pyramid_farthest_glsl(unsigned span, bool behind = false) {
    const std::string limit = std::to_string(span - 1) + "u";
    std::string out =
        "// The lowest pyramid level where b spans at most limit + 1 texels a side, from `from`.\n"
        "int qc_pyramid_level(uvec4 b, int from, uint limit)\n{\n"
        "    int level = from;\n"
        "    while (level + 1 < qc_level_count && ((b.z >> level) - (b.x >> level) > limit || (b.w >> level) - (b.y >> level) > limit)) ++level;\n"
        "    return level;\n"
        "}\n\n"
        "// The farthest value of level `level` over the texels under b.\n"
        "uint qc_pyramid_max(uvec4 b, int level)\n{\n"
        "    uvec3 l = qc_levels[level];\n"
        "    uint farthest = 0u;\n"
        "    for (uint y = b.y >> level; y <= (b.w >> level); ++y)\n"
        "        for (uint x = b.x >> level; x <= (b.z >> level); ++x) farthest = max(farthest, qc_depth_texel(qc_pyramid_index(l, uvec2(x, y))));\n"
        "    return farthest;\n"
        "}\n\n";
    if (!behind)
        return out + "uint qc_pyramid_farthest(uvec4 b) { return qc_pyramid_max(b, qc_pyramid_level(b, 0, " + limit + ")); }\n\n";
    return out + "bool qc_pyramid_behind(uvec4 b, uint bits)\n{\n"
                 "    int level = qc_pyramid_level(b, 0, " + limit + ");\n"
                 "    if (bits > qc_pyramid_max(b, qc_pyramid_level(b, level, 1u))) return true;  // (the coarse read: at most 2 x 2 texels)\n"
                 "    return bits > qc_pyramid_max(b, level);\n"
                 "}\n\n";
}

/// The end of a cull pass over records in workgroups of 64 (the quadric renderer's and the
/// isosurface element list's): from `kept` and `inside` of invocation t of workgroup `group`, the
/// exclusive prefix sum of the workgroup's flags in shared qc_flags[64], the workgroup's count
/// into qc_groups[group] and per record qc_keep[`record`] = 0 (culled) or 1 + the kept records
/// before it in the workgroup (the compaction's slot).
inline std::string keep_flags_glsl(const std::string& record, bool listed = false) {
    // With `listed`, the same for the bool `listed` into qc_flags2, qc_groups2 and qc_keep2 where qc_list.
    const auto two = [&](const std::string& line) { return listed ? line : std::string(); };
    return "    qc_flags[t] = kept ? 1u : 0u;\n" + two("    qc_flags2[t] = listed ? 1u : 0u;\n") +
           "    barrier();\n"
           "    if (t == 0u) {  // exclusive prefix sums of the workgroup's flags, and its counts\n"
           "        uint run = 0u;\n" + two("        uint run2 = 0u;\n") +
           "        for (uint r = 0u; r < 64u; ++r) {\n"
           "            uint f = qc_flags[r];\n            qc_flags[r] = run;\n            run += f;\n" +
           two("            uint f2 = qc_flags2[r];\n            qc_flags2[r] = run2;\n            run2 += f2;\n") +
           "        }\n"
           "        qc_groups[group] = run;\n" + two("        if (qc_list) qc_groups2[group] = run2;\n") +
           "    }\n"
           "    barrier();\n"
           "    if (inside) qc_keep[" + record + "] = kept ? qc_flags[t] + 1u : 0u;  // 1 + the kept records before it in the workgroup\n" +
           two("    if (inside && qc_list) qc_keep2[" + record + "] = listed ? qc_flags2[t] + 1u : 0u;\n");
}

}  // namespace quadcast::gl::detail
