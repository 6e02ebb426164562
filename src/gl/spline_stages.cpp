// src/gl/spline_stages.cpp -- vertex/fragment shaders of the isosurface renderer (QSS, S31,
// trilinear), assembled per variant key around the generated kernels. The plumbing here only moves data (records, the
// determining set gathered through the rotation tables, varyings, uniforms); every number it
// outputs comes from a traced function (Kalbe & Zeilfelder 2008, Sect. 5).
#include <array>
#include <sstream>

#include "quadcast/bb/multi_index.hpp"
#include "quadcast/spline/masks.hpp"
#include "quadcast/spline/partition.hpp"
#include "stage_builder.hpp"

namespace quadcast::gl {

namespace {

using detail::add_kernel;
using detail::Stage;
using detail::stage_text;
using Scheme = render::VolumeScheme;

const char* scheme_name(Scheme s) { return render::volume_scheme_name(s); }
int degree(Scheme s) { return s == Scheme::qss ? 2 : 3; }

/// Flat varyings of a cell's data: the BB-coefficients (10 or 20) or the 8 trilinear corners,
/// as vec4 groups named like the traced kernels' parameters (`qc_c0` ... or `qc_corners0`, ...).
struct Groups {
    std::string name;
    std::array<int, 5> sizes{};
    int count = 0;
};

Groups cell_groups(Scheme s) {
    if (s == Scheme::trilinear) return {"corners", {4, 4}, 2};
    if (s == Scheme::qss) return {"c", {4, 4, 2}, 3};
    return {"c", {4, 4, 4, 4, 4}, 5};
}

const char* vec_type(int n) { return n == 1 ? "float" : n == 2 ? "vec2" : n == 3 ? "vec3" : "vec4"; }

/// The vertices of tetrahedron t (spec §1.2) in an order of positive orientation
/// (det(v1 - v0, v2 - v0, v3 - v0) > 0; vertices 2 and 3 swapped where needed), so that one index
/// pattern lists the four faces counter-clockwise seen from outside.
std::array<spline::IVec3, 4> oriented_tet(int t) {
    auto v = spline::tet_vertices(t);
    const auto sub = [](const spline::IVec3& a, const spline::IVec3& b) { return spline::IVec3{a[0] - b[0], a[1] - b[1], a[2] - b[2]}; };
    const spline::IVec3 a = sub(v[1], v[0]), b = sub(v[2], v[0]), c = sub(v[3], v[0]);
    const int det = a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) + a[2] * (b[0] * c[1] - b[1] * c[0]);
    if (det == 0) throw std::logic_error("quadcast::gl: degenerate tetrahedron");
    if (det < 0) std::swap(v[2], v[3]);
    return v;
}

std::string ivec3_literal(const spline::IVec3& v) {
    std::ostringstream s;
    s << "vec3(" << v[0] << ".0, " << v[1] << ".0, " << v[2] << ".0)";
    return s.str();
}

/// The cube-local vertices of the 24 tetrahedra as a GLSL table `qc_tet_vertices` (4 t + k).
std::string tet_vertex_table() {
    std::ostringstream m;
    m << "// Cube-local vertices of tetrahedron t (quadcast::spline::tet_vertices), positively oriented.\n"
         "const vec3 qc_tet_vertices[" << 4 * spline::tets_per_cube << "] = vec3[](";
    for (int t = 0; t < spline::tets_per_cube; ++t) {
        const auto v = oriented_tet(t);
        for (int k = 0; k < 4; ++k) m << (t == 0 && k == 0 ? "\n    " : k == 0 ? ",\n    " : ", ") << ivec3_literal(v[static_cast<std::size_t>(k)]);
    }
    m << ");\n";
    return m.str();
}

/// The rotation of the determining set as a gather table (`d_rot[k] = d[qc_perm[n t + k]]`).
std::string permutation_table(Scheme scheme) {
    const int n = spline::d_count(degree(scheme));
    std::ostringstream m;
    m << "// d_rot[k] = d[qc_perm[" << n << " t + k]]: the determining set seen from tetrahedron t\n"
         "// (quadcast::spline::d_permutations).\n"
         "const int qc_perm[" << spline::tets_per_cube * n << "] = int[](";
    static constexpr auto perm2 = spline::d_permutations<2>();
    static constexpr auto perm3 = spline::d_permutations<3>();
    for (int t = 0; t < spline::tets_per_cube; ++t)
        for (int k = 0; k < n; ++k) {
            const auto ti = static_cast<std::size_t>(t), ki = static_cast<std::size_t>(k);
            const int v = degree(scheme) == 2 ? perm2[ti][ki] : perm3[ti][ki];
            m << (t == 0 && k == 0 ? "" : ", ") << ((t * n + k) % 24 == 0 ? "\n    " : "") << v;
        }
    m << ");\n";
    return m.str();
}

/// The statements that gather tetrahedron t's view of the determining set of cube `slot` and
/// call the repeated averaging into the outputs `out0`, `out1`, ... (vec4 groups).
std::string averaging_call(Scheme scheme, const std::string& out) {
    const int n = spline::d_count(degree(scheme));
    const Groups g = cell_groups(scheme);
    std::ostringstream m;
    m << "    float d[" << n << "];\n"
         "    for (int j = 0; j < " << n << "; ++j) d[j] = qc_dsets[slot * " << n << "u + uint(qc_perm[" << n << " * t + j])];\n"
         "    qc_spline_" << scheme_name(scheme) << "_tet0_coefficients(";
    for (int j = 0; j < n / 4; ++j) m << (j ? ", " : "") << "vec4(d[" << 4 * j << "], d[" << 4 * j + 1 << "], d[" << 4 * j + 2 << "], d[" << 4 * j + 3 << "])";
    for (int i = 0; i < g.count; ++i) m << ", " << out << i;
    m << ");\n";
    return m.str();
}

/// Declarations shared by the vertex stages: the drawn cells and the camera/volume uniforms.
const char* vertex_uniforms =
    "// One record per drawn element (a relevant tetrahedron or an active trilinear cell):\n"
    "// xyz = integer anchor (cube centre or cell corner, index space), w = slot << 5 | tetrahedron.\n"
    "layout(std430, binding = 0) readonly buffer qc_Elements { uvec4 qc_elements[]; };\n"
    "uniform uint qc_first;\n"
    "uniform vec3 qc_eye_index;      // the eye in index space\n"
    "uniform vec3 qc_eye_world;\n"
    "uniform vec3 qc_forward_world;  // viewing direction (orthographic cameras)\n"
    "uniform vec3 qc_origin;         // world position of sample (0,0,0)\n"
    "uniform vec3 qc_spacing;        // world distance of neighbouring samples per axis\n"
    "uniform mat4 qc_view_proj;\n"
    "uniform vec3 qc_vz_row;         // third row of the world->view rotation\n\n";

/// `precomputed`: the coefficients come from the storage buffer the compute pre-pass
/// (`coefficient_shader`) filled, one record per element, instead of being averaged per vertex.
Stage vertex_shader(Scheme scheme, bool ortho, bool precomputed = false) {
    Stage s;
    std::ostringstream fns;
    const std::string proj = ortho ? "ortho" : "perspective";
    const bool tri = scheme == Scheme::trilinear;
    if (!tri && !precomputed) add_kernel(s, fns, std::string("spline_") + scheme_name(scheme) + "_tet0_coefficients");
    add_kernel(s, fns, "spline_cell_vertex_" + proj);
    const Groups g = cell_groups(scheme);
    // The face point o is interpolated; its ray parameter w is 1 for perspective cameras, the
    // direction is constant for orthographic ones.
    const char* oq = ortho ? "" : "flat ";
    const char* vq = ortho ? "flat " : "";
    std::ostringstream m;
    m << vertex_uniforms;
    if (tri) {
        m << "layout(std430, binding = 1) readonly buffer qc_Samples { float qc_samples[]; };  // i fastest\n"
             "uniform ivec3 qc_dims;\n\n"
             "// Corner k of a cell: offset (k & 1, (k >> 1) & 1, (k >> 2) & 1).\n";
    } else {
        const int n = spline::d_count(degree(scheme));
        if (precomputed)
            m << "layout(std430, binding = 2) readonly buffer qc_Coefficients { float qc_coeffs[]; };  // "
              << bb::coefficient_count(degree(scheme)) << " per element\n\n";
        else
            m << "layout(std430, binding = 1) readonly buffer qc_DeterminingSets { float qc_dsets[]; };  // " << n << " per active cube\n\n"
              << permutation_table(scheme);
        m << tet_vertex_table() << "\n";
    }
    m << "// The depth floors of the elements (`occlusion_bound_shader`, a later phase's kept ones), read when qc_occlusion is 1.\n"
         "layout(std430, binding = 10) readonly buffer qc_Floors { float qc_floors[]; };\n"
         "uniform int qc_occlusion;\n\n";
    for (int i = 0; i < g.count; ++i) m << "flat out " << vec_type(g.sizes[static_cast<std::size_t>(i)]) << " qc_" << g.name << i << ";\n";
    if (!tri) m << "flat out uint qc_tet;\n";
    m << "flat out float qc_floor;      // no hit in the element is nearer (occlusion test)\n";
    m << "out vec3 qc_o;\n" << oq << "out float qc_w;\n" << vq << "out vec3 qc_v;\n" << vq << "out vec3 qc_dir;\n" << vq << "out float qc_vz;\n\n";
    m << fns.str();
    const int per = tri ? 8 : 4;
    m << "// Indexed draw: vertex " << per << " e + k is vertex k of element qc_first + e.\n"
         "void main()\n{\n"
         "    uint e = qc_first + uint(gl_VertexID) / " << per << "u;\n"
         "    int k = gl_VertexID % " << per << ";\n"
         "    uvec4 rec = qc_elements[e];\n"
         "    qc_floor = qc_occlusion != 0 ? qc_floors[e] : 0.0;\n";
    if (tri) {
        m << "    ivec3 c = ivec3(rec.xyz);\n"
             "    float f[8];\n"
             "    for (int j = 0; j < 8; ++j) {\n"
             "        ivec3 q = c + ivec3(j & 1, (j >> 1) & 1, (j >> 2) & 1);\n"
             "        f[j] = qc_samples[q.x + qc_dims.x * (q.y + qc_dims.y * q.z)];\n"
             "    }\n"
             "    qc_corners0 = vec4(f[0], f[1], f[2], f[3]);\n"
             "    qc_corners1 = vec4(f[4], f[5], f[6], f[7]);\n"
             "    vec3 offset = vec3(float(k & 1), float((k >> 1) & 1), float((k >> 2) & 1));\n"
             "    vec2 scale = vec2(1.0, 1.0);\n";
    } else {
        m << "    uint slot = rec.w >> 5u;\n"
             "    int t = int(rec.w & 31u);\n";
        if (precomputed) {
            const int nc = bb::coefficient_count(degree(scheme));
            for (int i = 0; i < g.count; ++i) {
                const int size = g.sizes[static_cast<std::size_t>(i)];
                m << "    qc_c" << i << " = " << vec_type(size) << "(";
                for (int j = 0; j < size; ++j) m << (j ? ", " : "") << "qc_coeffs[" << nc << "u * e + " << 4 * i + j << "u]";
                m << ");\n";
            }
        } else {
            m << averaging_call(scheme, "qc_c");
        }
        m << "    qc_tet = uint(t);\n"

             "    vec3 offset = qc_tet_vertices[4 * t + k];\n"
             "    vec2 scale = vec2(0.5, 2.0);\n";
    }
    m << "    vec4 clip;\n"
         "    qc_spline_cell_vertex_" << proj << "(vec3(rec.xyz), offset, scale, qc_eye_index, qc_eye_world, qc_forward_world, qc_origin, qc_spacing,\n"
         "        qc_view_proj, qc_vz_row, clip, qc_o, qc_w, qc_v, qc_dir, qc_vz);\n"
         "    gl_Position = clip;\n"
         "}\n";
    s.text = m.str();
    return s;
}

/// The isosurface pass: forward (cast and shade) or, with `gbuffer`, cast and write the quadric
/// renderer's geometry buffer (normal + depth, ray direction, colour), so its deferred pass,
/// shadows and silhouettes apply unchanged.
Stage fragment_shader(Scheme scheme, bool ortho, bool gbuffer) {
    Stage s;
    std::ostringstream fns;
    const bool tri = scheme == Scheme::trilinear;
    const std::string kernel = tri ? std::string("trilinear_fragment") : std::string("spline_fragment_q") + std::to_string(degree(scheme));
    add_kernel(s, fns, kernel);
    if (!gbuffer) add_kernel(s, fns, "shade_blinn_phong");
    const Groups g = cell_groups(scheme);
    const char* oq = ortho ? "" : "flat ";
    const char* vq = ortho ? "flat " : "";
    std::ostringstream m;
    m << "uniform vec4 qc_pz;           // P22, P32, P23, P33 of the projection\n"
         "uniform float qc_rho;         // the isovalue\n"
         "uniform vec3 qc_grad_scale;   // cube-local gradient -> world gradient, per axis\n"
         "uniform float qc_pixel;       // a pixel's angle (perspective) or world width (orthographic): 2 / (P11 height)\n"
         "uniform vec3 qc_color;\n";
    if (!gbuffer) m << "uniform vec3 qc_light_dir;    // towards the scene\nuniform vec3 qc_light_color;\n";
    m << "uniform vec4 qc_material;     // ambient, diffuse, specular, shininess\n";
    if (!tri) {
        m << "// R_t (quadcast::spline::rotation), column-major.\n"
             "const mat3 qc_rotations[" << spline::tets_per_cube << "] = mat3[](";
        for (int t = 0; t < spline::tets_per_cube; ++t) {
            const spline::IMat3 r = spline::rotation(t);
            m << (t ? ",\n    " : "\n    ") << "mat3(";
            for (int j = 0; j < 3; ++j)
                for (int i = 0; i < 3; ++i) m << (i || j ? ", " : "") << r[static_cast<std::size_t>(i)][static_cast<std::size_t>(j)] << ".0";
            m << ")";
        }
        m << ");\n";
    }
    m << "\n";
    for (int i = 0; i < g.count; ++i) m << "flat in " << vec_type(g.sizes[static_cast<std::size_t>(i)]) << " qc_" << g.name << i << ";\n";
    if (!tri) m << "flat in uint qc_tet;\n";
    m << "flat in float qc_floor;\n"
         "uniform int qc_occlusion;                // 1: test qc_floor against qc_drawn_depth\n"
         "uniform sampler2D qc_drawn_depth;        // the window depth the earlier phases drew\n";
    m << "in vec3 qc_o;\n" << oq << "in float qc_w;\n" << vq << "in vec3 qc_v;\n" << vq << "in vec3 qc_dir;\n" << vq << "in float qc_vz;\n";
    if (gbuffer)
        m << "layout(location = 0) out vec4 qc_gnormal;  // normal (unnormalised), window depth\n"
             "layout(location = 1) out vec4 qc_gview;    // ray direction, shininess (> 0: covered)\n"
             "layout(location = 2) out vec4 qc_gcolor;   // colour, specular\n\n";
    else
        m << "layout(location = 0) out vec4 qc_color_out;\n\n";
    m << fns.str();
    m << "void main()\n{\n";
    m << "    // Occlusion: every hit here would lie behind what the earlier phases drew (the depth test would drop it)\n"
         "    if (qc_occlusion != 0 && qc_floor > texelFetch(qc_drawn_depth, ivec2(gl_FragCoord.xy), 0).r) discard;\n";
    m << "    bool hit;\n    float depth;\n    vec3 n;\n"
         "    qc_" << kernel << "(";
    for (int i = 0; i < g.count; ++i) m << "qc_" << g.name << i << ", ";
    if (!tri) m << "qc_rotations[qc_tet], ";
    m << "qc_o, qc_w, qc_v, qc_vz, qc_pz, qc_rho, qc_grad_scale, qc_pixel, hit, depth, n);\n"
         "    if (!hit) discard;\n"
         "    gl_FragDepth = depth;\n";
    if (gbuffer)
        m << "    qc_gnormal = vec4(n, depth);\n"
             "    qc_gview = vec4(qc_dir, qc_material.w);\n"
             "    qc_gcolor = vec4(qc_color, qc_material.z);\n"
             "}\n";
    else
        m << "    vec3 rgb;\n"
             "    qc_shade_blinn_phong(n, -qc_light_dir, -qc_dir, qc_color, qc_light_color, qc_material, rgb);\n"
             "    qc_color_out = vec4(rgb, 1.0);\n"
             "}\n";
    s.text = m.str();
    return s;
}

/// The compute pre-pass of the `precomputed` vertex stages: per element (relevant tetrahedron)
/// of the frame, or of a phase's survivors of occlusion culling, the coefficients by
/// repeated averaging, once instead of once per vertex, written to the storage buffer the vertex
/// stage reads.
Stage coefficient_shader(Scheme scheme) {
    Stage s;
    std::ostringstream fns;
    add_kernel(s, fns, std::string("spline_") + scheme_name(scheme) + "_tet0_coefficients");
    const Groups g = cell_groups(scheme);
    const int nc = bb::coefficient_count(degree(scheme)), n = spline::d_count(degree(scheme));
    std::ostringstream m;
    m << "layout(local_size_x = 64) in;\n\n"
         "layout(std430, binding = 0) readonly buffer qc_Elements { uvec4 qc_elements[]; };\n"
         "layout(std430, binding = 1) readonly buffer qc_DeterminingSets { float qc_dsets[]; };  // " << n << " per active cube\n"
         "layout(std430, binding = 2) writeonly buffer qc_Coefficients { float qc_coeffs[]; };  // " << nc << " per element\n"
         "uniform uint qc_first;        // the elements qc_first .. qc_first + qc_count - 1 (a phase of occlusion culling, or all)\n"
         "uniform uint qc_count;\n\n"
      << permutation_table(scheme) << "\n" << fns.str()
      << "void main()\n{\n"
         "    uint i = (gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x) * 64u + gl_LocalInvocationID.x;\n"
         "    if (i >= qc_count) return;\n"
         "    uint e = qc_first + i;\n"
         "    uvec4 rec = qc_elements[e];\n"
         "    uint slot = rec.w >> 5u;\n"
         "    int t = int(rec.w & 31u);\n";
    for (int i = 0; i < g.count; ++i) m << "    " << vec_type(g.sizes[static_cast<std::size_t>(i)]) << " c" << i << ";\n";
    m << averaging_call(scheme, "c");
    for (int i = 0; i < g.count; ++i)
        for (int j = 0; j < g.sizes[static_cast<std::size_t>(i)]; ++j)
            m << "    qc_coeffs[" << nc << "u * e + " << 4 * i + j << "u] = c" << i << "." << "xyzw"[j] << ";\n";
    m << "}\n";
    s.text = m.str();
    return s;
}

/// Occlusion culling, pass 1 of a later phase: level 0 of the max-depth pyramid, the window
/// depths of the copy of the depth buffer (viewport region) as uint bits (non-negative floats
/// order as their bits do); the quadric renderer's pyramid pass (OcclusionPass::pyramid) makes
/// the levels above.
const char* pyramid_base_shader =
    "layout(local_size_x = 8, local_size_y = 8) in;\n\n"
    "layout(std430, binding = 3) writeonly buffer qc_Depths { uint qc_depth[]; };\n"
    "uniform sampler2D qc_drawn_depth;  // the copy of the depth buffer\n"
    "uniform ivec4 qc_viewport_rect;    // x, y, width, height\n\n"
    "void main()\n{\n"
    "    ivec2 t = ivec2(gl_GlobalInvocationID.xy);\n"
    "    if (t.x >= qc_viewport_rect.z || t.y >= qc_viewport_rect.w) return;\n"
    "    float d = texelFetch(qc_drawn_depth, qc_viewport_rect.xy + t, 0).r;\n"
    "    qc_depth[qc_pyramid_index(uvec3(0u, uvec2(qc_viewport_rect.zw)), uvec2(t))] = floatBitsToUint(d > 0.0 ? d : 0.0);  // (never -0.0, whose bits would be largest)\n"
    "}\n";

/// Occlusion culling, pass 2 of a later phase: per element (relevant tetrahedron) of the phase
/// its `tet_occlusion_bound`; an element whose rectangle (`pixel_span`, grown by a pixel for the
/// rasteriser's snapping) holds no pixel of the viewport, or only pixels whose drawn depths (the
/// pyramid level where they span at most 4 x 4 texels) all lie nearer than its floor, is culled
/// (qc_keep 0), else it keeps its floor (qc_floors), which the fragment stage tests against
/// the depth drawn at its pixel; the kept ones are flagged and counted per workgroup of 64 as in
/// the quadric renderer's cull pass, for the scan and `phase_compact_shader`. Whether each element
/// was culled goes to qc_passed (the next frame's shown set, RenderOptions::occlusion_reuse); the
/// elements before qc_draw_from (drawn already: the shown set) are tested, never kept.
Stage occlusion_bound_shader(bool ortho, bool tri) {
    Stage s;
    std::ostringstream fns;
    const std::string proj = ortho ? "ortho" : "perspective";
    add_kernel(s, fns, (tri ? "cell_occlusion_bound_" : "tet_occlusion_bound_") + proj);
    add_kernel(s, fns, "pixel_span");
    std::ostringstream m;
    m << "layout(local_size_x = 64) in;\n\n"
      << vertex_uniforms
      << detail::depth_texels_glsl()
      << "layout(std430, binding = 10) writeonly buffer qc_Floors { float qc_floors[]; };\n"
         "uniform uint qc_count;        // the phase's elements, from qc_first on\n"
         "uniform uint qc_draw_from;    // of these, the first that may be kept (the ones before it are drawn already)\n"
         "uniform vec4 qc_pz;           // P22, P32, P23, P33 of the projection\n"
         "uniform float qc_pixel;       // a pixel's angle (perspective) or world width (orthographic): 2 / (P11 height)\n"
         "uniform vec2 qc_viewport;     // width, height\n"
         "uniform uvec3 qc_levels[16];  // offset, width, height of each pyramid level\n"
         "uniform int qc_level_count;\n\n"
      << "layout(std430, binding = 6) writeonly buffer qc_Keep { uint qc_keep[]; };     // per element of the phase: 0 culled, else 1 + its slot in the workgroup\n"
         "layout(std430, binding = 7) writeonly buffer qc_Groups { uint qc_groups[]; };  // per workgroup of 64 elements: the kept ones\n"
         "layout(std430, binding = 13) writeonly buffer qc_Passed { uint qc_passed[]; };  // per element of the phase: 1 not culled (the next frame's shown set)\n"
         "shared uint qc_flags[64];\n\n"
      << (tri ? std::string() : tet_vertex_table() + "\n") << fns.str() << detail::pyramid_farthest_glsl(4)
      << "void main()\n{\n"
         "    uint t = gl_LocalInvocationID.x;\n"
         "    uint group = gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x;\n"
         "    if (group >= (qc_count + 63u) / 64u) return;  // (a whole workgroup past the elements: the dispatch's last row)\n"
         "    uint i = group * 64u + t;\n"
         "    bool inside = i < qc_count;\n"
         "    bool culled = true;\n"
         "    if (inside) {\n"
         "        uint e = qc_first + i;\n"
         "        uvec4 rec = qc_elements[e];\n"
         "        float floor_depth;\n        vec2 lo, hi;\n        bool visible;\n";
    if (tri)
        m << "        qc_cell_occlusion_bound_" << proj << "(vec3(rec.xyz), qc_eye_index, qc_eye_world, qc_forward_world, qc_origin, qc_spacing, qc_view_proj, qc_vz_row,\n"
             "            qc_pz, qc_pixel, floor_depth, lo, hi, visible);\n";
    else
        m << "        int t = int(rec.w & 31u);\n"
             "        qc_tet_occlusion_bound_" << proj << "(vec3(rec.xyz), qc_tet_vertices[4 * t], qc_tet_vertices[4 * t + 1], qc_tet_vertices[4 * t + 2], qc_tet_vertices[4 * t + 3],\n"
             "            qc_eye_index, qc_eye_world, qc_forward_world, qc_origin, qc_spacing, qc_view_proj, qc_vz_row, qc_pz, qc_pixel, floor_depth, lo, hi, visible);\n";
    m << "        culled = false;\n"
         "        if (visible && floor_depth > 0.0 && all(lessThan(abs(vec4(lo, hi)), vec4(64.0)))) {\n"
         "            vec4 span;\n"
         "            qc_pixel_span(lo, hi, qc_viewport, span);\n"
         "            // a pixel more on each side: the rasteriser snaps the corners to its sub-pixel grid\n"
         "            span = vec4(max(span.xy - 1.0, vec2(0.0)), min(span.zw + 1.0, qc_viewport - 1.0));\n"
         "            if (span.x > span.z || span.y > span.w) culled = true;  // no pixel of the viewport\n"
         "            else culled = floor_depth > uintBitsToFloat(qc_pyramid_farthest(uvec4(span)));  // behind what is drawn over all its pixels\n"
         "        }\n"
         "        qc_floors[e] = floor_depth;  // (the kept ones' go with them into the survivors' list)\n"
         "        qc_passed[i] = culled ? 0u : 1u;\n"
         "    }\n"
         "    bool kept = inside && !culled && i >= qc_draw_from;\n"
      << detail::keep_flags_glsl("i") << "}\n";
    s.text = m.str();
    return s;
}

/// GLSL of the element list's frustum test of a box: its 8 corners `anchor + offset * scale`
/// (offset: a GLSL expression of the corner number k) through the vertex stage's kernel
/// (`cell_vertex`, perspective: the clip position is the same for both cameras), then
/// `clip_outside` into the bool `outside`; `indent` spaces before each line.
std::string box_outside_glsl(const std::string& anchor, const std::string& offset, const char* scale, int indent) {
    const std::string in(static_cast<std::size_t>(indent), ' ');
    std::ostringstream m;
    m << in << "vec4 corner[8];\n"
      << in << "for (int k = 0; k < 8; ++k) {\n"
      << in << "    vec3 o, v, dir;\n" << in << "    float w, vz;\n"
      << in << "    qc_spline_cell_vertex_perspective(" << anchor << ", " << offset << ", " << scale
      << ", vec3(0.0), vec3(0.0), vec3(0.0, 0.0, -1.0), qc_origin, qc_spacing,\n"
      << in << "        qc_view_proj, vec3(0.0, 0.0, 1.0), corner[k], o, w, v, dir, vz);\n"
      << in << "}\n"
      << in << "bool outside;\n"
      << in << "qc_clip_outside(corner[0], corner[1], corner[2], corner[3], corner[4], corner[5], corner[6], corner[7], outside);\n";
    return m.str();
}

/// The GPU element list (IsosurfaceRenderer::ElementList::gpu), pass 0 (splines): per active cube
/// (slot) of the volume, the clip positions of its box's corners as the vertex stage computes its
/// vertices (`cell_vertex`, offsets +-1 at scale 1/2: every vertex of its tetrahedra lies in the
/// box; the perspective kernel, the clip position being the same for both cameras) and whether the
/// box lies wholly outside the clip volume (`clip_outside`): qc_cube_kept 0, else 1.
Stage cube_cull_shader() {
    Stage s;
    std::ostringstream fns;
    add_kernel(s, fns, "spline_cell_vertex_perspective");
    add_kernel(s, fns, "clip_outside");
    std::ostringstream m;
    m << "layout(local_size_x = 64) in;\n\n"
         "layout(std430, binding = 8) readonly buffer qc_Cubes { int qc_cubes[]; };        // per slot its cube (i fastest)\n"
         "layout(std430, binding = 9) writeonly buffer qc_CubeKept { uint qc_cube_kept[]; };\n"
         "uniform uint qc_count;          // active cubes\n"
         "uniform ivec3 qc_dims;          // the cube grid\n"
         "uniform vec3 qc_origin;         // world position of sample (0,0,0)\n"
         "uniform vec3 qc_spacing;        // world distance of neighbouring samples per axis\n"
         "uniform mat4 qc_view_proj;\n\n"
      << fns.str()
      << "void main()\n{\n"
         "    uint e = (gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x) * 64u + gl_LocalInvocationID.x;\n"
         "    if (e >= qc_count) return;\n"
         "    int c = qc_cubes[e];\n"
         "    vec3 anchor = vec3(float(c % qc_dims.x), float((c / qc_dims.x) % qc_dims.y), float(c / (qc_dims.x * qc_dims.y)));\n"
      << box_outside_glsl("anchor", "vec3(float((k & 1) * 2 - 1), float(((k >> 1) & 1) * 2 - 1), float(((k >> 2) & 1) * 2 - 1))", "vec2(0.5, 2.0)", 4)
      << "    qc_cube_kept[e] = outside ? 0u : 1u;\n"
         "}\n";
    s.text = m.str();
    return s;
}

/// The GPU element list, pass 1: per record of the volume's list of all its relevant tetrahedra
/// (or active cells), whether it is kept: a tetrahedron when its cube's box is (pass 0), a cell
/// when its own box is not wholly outside the clip volume (its corners as the vertex stage
/// computes them, `cell_vertex`, and `clip_outside`); the kept ones flagged (qc_keep 1 + the kept
/// records before it in its workgroup of 64) and counted per workgroup, as in the quadric
/// renderer's cull pass.
Stage element_cull_shader(bool tri) {
    Stage s;
    std::ostringstream fns;
    if (tri) {
        add_kernel(s, fns, "spline_cell_vertex_perspective");
        add_kernel(s, fns, "clip_outside");
    }
    std::ostringstream m;
    m << "layout(local_size_x = 64) in;\n\n"
         "layout(std430, binding = 3) readonly buffer qc_All { uvec4 qc_all[]; };      // every relevant element of the volume\n"
         "layout(std430, binding = 6) writeonly buffer qc_Keep { uint qc_keep[]; };     // per record: 0 culled, else 1 + its slot in the workgroup\n"
         "layout(std430, binding = 7) writeonly buffer qc_Groups { uint qc_groups[]; };  // per workgroup of 64 records: the kept ones\n"
         "uniform uint qc_count;\n";
    if (tri)
        m << "uniform vec3 qc_origin;         // world position of sample (0,0,0)\n"
             "uniform vec3 qc_spacing;        // world distance of neighbouring samples per axis\n"
             "uniform mat4 qc_view_proj;\n\n";
    else
        m << "layout(std430, binding = 9) readonly buffer qc_CubeKept { uint qc_cube_kept[]; };  // per slot (pass 0)\n\n";
    m << fns.str()
      << "shared uint qc_flags[64];\n\n"
         "void main()\n{\n"
         "    uint t = gl_LocalInvocationID.x;\n"
         "    uint group = gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x;\n"
         "    if (group >= (qc_count + 63u) / 64u) return;  // (a whole workgroup past the records: the dispatch's last row)\n"
         "    uint e = group * 64u + t;\n"
         "    bool inside = e < qc_count;\n"
         "    bool kept = false;\n"
         "    if (inside) {\n"
         "        uvec4 rec = qc_all[e];\n";
    if (tri)
        m << box_outside_glsl("vec3(rec.xyz)", "vec3(float(k & 1), float((k >> 1) & 1), float((k >> 2) & 1))", "vec2(1.0, 1.0)", 8) << "        kept = !outside;\n";
    else
        m << "        kept = qc_cube_kept[rec.w >> 5u] != 0u;\n";
    m << "    }\n" << detail::keep_flags_glsl("e") << "}\n";
    s.text = m.str();
    return s;
}

/// The GPU element list, pass 3 (after the quadric renderer's scan, OcclusionPass::scan, has made
/// the workgroup counts their first slots): each kept record copied, in the order of the volume's
/// list, into the frame's element list the vertex stage and the coefficient pre-pass read.
const char* element_compact_shader =
    "layout(local_size_x = 64) in;\n\n"
    "layout(std430, binding = 0) writeonly buffer qc_Elements { uvec4 qc_elements[]; };\n"
    "layout(std430, binding = 3) readonly buffer qc_All { uvec4 qc_all[]; };\n"
    "layout(std430, binding = 6) readonly buffer qc_Keep { uint qc_keep[]; };\n"
    "layout(std430, binding = 7) readonly buffer qc_Groups { uint qc_groups[]; };\n"
    "uniform uint qc_count;\n\n"
    "void main()\n{\n"
    "    uint group = gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x;\n"
    "    uint e = group * 64u + gl_LocalInvocationID.x;\n"
    "    if (e >= qc_count) return;\n"
    "    uint k = qc_keep[e];\n"
    "    if (k != 0u) qc_elements[qc_groups[group] + k - 1u] = qc_all[e];\n"
    "}\n";

/// Occlusion culling of a later phase, after the bound pass and the quadric renderer's scan
/// (OcclusionPass::scan): the phase's kept elements, in order, with their depth floors, into the
/// survivors' list from slot qc_to on (the phase's first kept element's slot), which the phase then draws (the culled ones
/// cost no vertex work).
const char* phase_compact_shader =
    "layout(local_size_x = 64) in;\n\n"
    "layout(std430, binding = 0) readonly buffer qc_Elements { uvec4 qc_elements[]; };  // the frame's elements\n"
    "layout(std430, binding = 10) readonly buffer qc_Floors { float qc_floors[]; };      // their depth floors\n"
    "layout(std430, binding = 6) readonly buffer qc_Keep { uint qc_keep[]; };\n"
    "layout(std430, binding = 7) readonly buffer qc_Groups { uint qc_groups[]; };\n"
    "layout(std430, binding = 11) writeonly buffer qc_Survivors { uvec4 qc_survivors[]; };\n"
    "layout(std430, binding = 12) writeonly buffer qc_SurvivorFloors { float qc_survivor_floors[]; };\n"
    "uniform uint qc_first;  // the phase's first element\n"
    "uniform uint qc_count;  // its elements\n"
    "uniform uint qc_to;     // the survivors' first slot\n\n"
    "void main()\n{\n"
    "    uint group = gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x;\n"
    "    uint i = group * 64u + gl_LocalInvocationID.x;\n"
    "    if (i >= qc_count) return;\n"
    "    uint k = qc_keep[i];\n"
    "    if (k == 0u) return;\n"
    "    uint to = qc_to + qc_groups[group] + k - 1u;\n"
    "    qc_survivors[to] = qc_elements[qc_first + i];\n"
    "    qc_survivor_floors[to] = qc_floors[qc_first + i];\n"
    "}\n";

}  // namespace

namespace {

std::string kind_name(Scheme scheme) {
    return scheme == Scheme::trilinear ? "trilinear cells" : std::string(scheme == Scheme::qss ? "QSS" : "S31") + " tetrahedra";
}

}  // namespace

std::vector<StageText> program_stages(const render::IsoKey& k) {
    render::check(k);
    const Scheme scheme = k.scheme;
    const std::string what = std::string(scheme_name(scheme)) + "_" + (k.ortho ? "ortho" : "perspective");
    const std::string cam = std::string(k.ortho ? "orthographic" : "perspective") + " camera";
    const std::string kind = kind_name(scheme);
    std::vector<StageText> out;
    if (k.precomputed)
        out.push_back(stage_text(StageText::Kind::vertex, "qc_iso_" + what + "_precomputed.vert", vertex_shader(scheme, k.ortho, true),
                                 "isosurface renderer: vertex stage reading the coefficients of the compute pre-pass, " + kind + ", " + cam));
    else
        out.push_back(stage_text(StageText::Kind::vertex, "qc_iso_" + what + ".vert", vertex_shader(scheme, k.ortho), "isosurface renderer: vertex stage, " + kind + ", " + cam));
    if (k.gbuffer)
        out.push_back(stage_text(StageText::Kind::fragment, "qc_iso_gbuffer_" + what + ".frag", fragment_shader(scheme, k.ortho, true),
                                 "isosurface renderer: geometry-buffer fragment stage (deferred shading), " + kind + ", " + cam));
    else
        out.push_back(stage_text(StageText::Kind::fragment, "qc_iso_" + what + ".frag", fragment_shader(scheme, k.ortho, false),
                                 "isosurface renderer: fragment stage, " + kind + ", " + cam));
    return out;
}

StageText element_list_stage(render::OcclusionPass pass) {
    switch (pass) {
    case render::OcclusionPass::element_cull_tets:
    case render::OcclusionPass::element_cull_cells: {
        const bool tri = pass == render::OcclusionPass::element_cull_cells;
        return stage_text(StageText::Kind::compute, tri ? "qc_iso_element_cull_cells.comp" : "qc_iso_element_cull_tets.comp", element_cull_shader(tri),
                          tri ? "isosurface renderer, GPU element list: the frustum test of every active trilinear cell"
                              : "isosurface renderer, GPU element list: every relevant tetrahedron kept with its cube");
    }
    case render::OcclusionPass::element_cull_cubes:
        return stage_text(StageText::Kind::compute, "qc_iso_element_cull_cubes.comp", cube_cull_shader(),
                          "isosurface renderer, GPU element list: the frustum test of every active cube's box");
    case render::OcclusionPass::element_compact: {
        Stage c;
        c.text = element_compact_shader;
        return stage_text(StageText::Kind::compute, "qc_iso_element_compact.comp", c, "isosurface renderer, GPU element list: the kept elements in order into the frame's list");
    }
    case render::OcclusionPass::phase_compact: {
        Stage c;
        c.text = phase_compact_shader;
        return stage_text(StageText::Kind::compute, "qc_iso_phase_compact.comp", c,
                          "isosurface renderer, occlusion culling: the kept elements of a later phase, with their depth floors, in order into the survivors' list");
    }
    default:
        throw std::invalid_argument("quadcast::gl::element_list_stage: not a pass of the element list");
    }
}

StageText occlusion_bound_stage(bool ortho, bool cells) {
    return stage_text(StageText::Kind::compute, std::string("qc_iso_occlusion_bounds_") + (cells ? "cells_" : "") + (ortho ? "ortho" : "perspective") + ".comp",
                      occlusion_bound_shader(ortho, cells),
                      std::string("isosurface renderer, occlusion culling: each ") + (cells ? "trilinear cell" : "tetrahedron") +
                          " of a phase culled against the max-depth pyramid, else its depth floor, " + (ortho ? "orthographic" : "perspective") + " camera");
}

StageText pyramid_base_stage() {
    Stage p;
    p.text = gl::pyramid_index_glsl() + pyramid_base_shader;
    return stage_text(StageText::Kind::compute, "qc_iso_pyramid_base.comp", p, "isosurface renderer, occlusion culling: level 0 of the max-depth pyramid from the copy of the depth buffer");
}

StageText coefficient_stage(Scheme scheme) {
    if (scheme == Scheme::trilinear) throw std::invalid_argument("quadcast::gl::coefficient_stage: trilinear cells have no coefficients");
    return stage_text(StageText::Kind::compute, std::string("qc_iso_") + scheme_name(scheme) + "_coefficients.comp", coefficient_shader(scheme),
                      std::string("isosurface renderer: compute pre-pass, the ") + (scheme == Scheme::qss ? "QSS" : "S31") +
                          " coefficients of every drawn tetrahedron by repeated averaging");
}

}  // namespace quadcast::gl
