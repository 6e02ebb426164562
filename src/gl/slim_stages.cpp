// src/gl/slim_stages.cpp -- the stages of the GL SLIM renderer's three passes, assembled around the generated kernels
// (Stoll et al. 2006, sec. 5.1.1). The ball passes draw each ball over its patch's quadrilateral or its
// bounding sphere's quad, culled per quadric and by its patch's normal cone; their fragment stage casts the
// pixel's ray with `slim_fragment`. The plumbing moves data only: every number comes from a traced
// function (`slim_patch_quad`, `slim_patch_cull_*`, `fragment_ray_*`, `slim_fragment`, `slim_terms`, `slim_resolve`).
#include <sstream>

#include "quadcast/gl/stages.hpp"
#include "quadcast/render/record.hpp"
#include "stage_builder.hpp"

namespace quadcast::gl {

namespace {

using detail::add_kernel;
using detail::Stage;
using detail::stage_text;

const char* ray_uniforms =
    "uniform vec3 qc_ray_base, qc_ray_dx, qc_ray_dy;  // the pixel's ray, affine in gl_FragCoord.xy (quadcast::window_ray)\n"
    "uniform vec3 qc_ray_fixed;    // the eye (perspective) or the viewing direction (orthographic)\n"
    "uniform vec3 qc_vz_row;       // third row of the world->view rotation\n"
    "uniform vec4 qc_pz;           // P22, P32, P23, P33 of the projection\n";

/// The vertex stage of both ball passes: corner k of ball gl_VertexID / 4 over its patch's
/// quadrilateral (`slim_patch_quad`, with `qc_patch`) where that is tight, else its bounding sphere's
/// quad; a ball is sent off screen when per-quadric culling (`primitive_cull`, perspective, with
/// `qc_cull`) or its patch's normal cone (`slim_patch_cull_*`, with `qc_patch_cull`) culls it.
Stage ball_vertex_shader(bool ortho) {
    Stage s;
    std::ostringstream fns;
    const std::string proj = ortho ? "ortho" : "perspective";
    add_kernel(s, fns, "slim_patch_quad");
    add_kernel(s, fns, "slim_patch_cull_" + proj);
    add_kernel(s, fns, "primitive_bound_" + proj);
    add_kernel(s, fns, "clip_position");
    if (!ortho) add_kernel(s, fns, "primitive_cull");
    std::ostringstream m;
    m << render::record_glsl()
      << "// Per record its patch bound (quadcast::SlimPatch): axis, rho; slab lo, hi, cone cos, sin.\n"
         "layout(std430, binding = 2) readonly buffer qc_SlimPatches { vec4 qc_slim_patches[]; };\n"
      << detail::bound_uniforms_glsl()
      << "uniform vec3 qc_eye;\nuniform vec3 qc_ray_fixed;  // the eye (perspective) or the viewing direction (orthographic)\n"
         "uniform bool qc_cull;        // per-quadric culling (perspective)\n"
         "uniform bool qc_patch;       // draw over the patch's quadrilateral\n"
         "uniform bool qc_patch_cull;  // cull by the patch's normal cone\n"
         "// The record and its two clip planes for the fragment stage (detail::record_varyings_glsl).\n"
         "layout(std430, binding = 1) readonly buffer qc_SlimPlanes { vec4 qc_slim_planes[]; };\n"
         "flat out vec4 qc_slim_plane, qc_slim_plane2;\n"
      << detail::record_varyings_glsl("out") << "\n"
      << fns.str()
      << "void main()\n{\n"
         "    uint prim = uint(gl_VertexID) / 4u;\n"
         "    int k = gl_VertexID % 4;\n"
         "    qc_Primitive p = qc_prims[prim];\n"
      << detail::record_varyings_out()
      << "    qc_slim_plane = qc_slim_planes[2u * prim];\n"
         "    qc_slim_plane2 = qc_slim_planes[2u * prim + 1u];\n"
         "    vec4 axis_rho = qc_slim_patches[2u * prim], slab_cone = qc_slim_patches[2u * prim + 1u];\n"
         "    vec2 qd[4];\n    bool tight = false, visible = true;\n"
         "    if (qc_patch)\n"
         "        qc_slim_patch_quad(qc_view_projection, qc_record_center(p), axis_rho, slab_cone, qc_viewport, qd[0], qd[1], qd[2], qd[3], tight, visible);\n"
         "    vec4 clip;\n"
         "    if (tight) {\n"
         "        clip = vec4(qd[k], 0.0, 1.0);\n"
         "    } else {\n"
      << detail::sphere_quad_glsl(proj)
      << "        qc_clip_position(qc_projection, valid ? corners[k] : qc_near_corners[k], clip);\n"
         "    }\n"
      << "    bool culled = false, culled_caps = false, patch_culled = false;\n";
    if (!ortho)
        m << "    if (qc_cull)\n"
             "        qc_primitive_cull(qc_record_quadric(p), qc_record_center(p), qc_record_radius(p), qc_record_axis(p), qc_record_half_length(p), qc_eye, culled, culled_caps);\n";
    m << "    if (qc_patch_cull)\n"
         "        qc_slim_patch_cull_" << proj << "(qc_record_center(p), qc_record_radius(p), axis_rho, slab_cone, qc_ray_fixed, patch_culled);\n"
         "    gl_Position = (culled || patch_culled) ? vec4(2.0, 2.0, 2.0, 1.0) : clip;\n"
         "}\n";
    s.text = m.str();
    return s;
}

/// Visibility (depth only: the pushed depth) or accumulation (the fragment's terms into the three
/// float targets, which the blender adds; the depth test against the visibility pass's depth).
Stage ball_fragment_shader(const render::SlimKey& k) {
    Stage s;
    std::ostringstream fns;
    const std::string proj = k.ortho ? "ortho" : "perspective";
    const bool accumulate = k.pass == render::SlimPass::accumulate;
    add_kernel(s, fns, "fragment_ray_" + proj);
    add_kernel(s, fns, k.cull ? "slim_fragment" : "slim_fragment_nocull");
    if (accumulate) add_kernel(s, fns, "slim_terms");
    std::ostringstream m;
    m << render::record_glsl()
      << ray_uniforms << "\n" << detail::record_varyings_glsl("in")
      << "flat in vec4 qc_slim_plane, qc_slim_plane2;  // the record's clip planes in local coordinates ((0, 0, 0, 1): none)\n";
    if (accumulate)
        m << "layout(location = 0) out vec4 qc_slim_normal_weight;    // w n, w\n"
             "layout(location = 1) out vec4 qc_slim_lambda_material;  // w lambda, w specular, w shininess, 0\n"
             "layout(location = 2) out vec4 qc_slim_color;            // w colour, 0\n";
    m << "\n" << fns.str()
      << "void main()\n{\n"
      << detail::record_varyings_in()
      << "    vec3 ro, rd;\n"
         "    qc_fragment_ray_" << proj << "(qc_ray_base, qc_ray_dx, qc_ray_dy, qc_ray_fixed, gl_FragCoord.xy, ro, rd);\n"
         "    bool hit;\n    float depth, visibility, lambda, w;\n    vec3 n;\n"
         "    qc_" << (k.cull ? "slim_fragment" : "slim_fragment_nocull")
      << "(qc_record_quadric(p), qc_record_center(p), qc_record_radius(p), qc_record_axis(p), qc_record_half_length(p),\n"
         "        qc_slim_plane, qc_slim_plane2, ro, rd, qc_vz_row, qc_pz, hit, depth, visibility, lambda, n, w);\n"
         "    if (!hit) discard;\n";
    if (accumulate)
        m << "    gl_FragDepth = depth;\n"
             "    vec4 nw, lm;\n    vec3 c;\n"
             "    qc_slim_terms(w, n, lambda, qc_record_color(p), qc_record_material(p), nw, lm, c);\n"
             "    qc_slim_normal_weight = nw;\n"
             "    qc_slim_lambda_material = lm;\n"
             "    qc_slim_color = vec4(c, 0.0);\n";
    else
        m << "    gl_FragDepth = visibility;\n";
    m << "}\n";
    s.text = m.str();
    return s;
}

/// The resolve: per pixel the sums divided by the weight (`slim_resolve`) into the geometry
/// buffer of the quadric renderer's deferred pass (normal + window depth, ray direction +
/// shininess, colour + specular) and the depth target; pixels without weight are left alone.
Stage resolve_shader(bool ortho) {
    Stage s;
    std::ostringstream fns;
    const std::string proj = ortho ? "ortho" : "perspective";
    add_kernel(s, fns, "fragment_ray_" + proj);
    add_kernel(s, fns, "slim_resolve");
    std::ostringstream m;
    m << "layout(binding = 0) uniform sampler2D qc_slim_normal_weight;\n"
         "layout(binding = 1) uniform sampler2D qc_slim_lambda_material;\n"
         "layout(binding = 2) uniform sampler2D qc_slim_color;\n"
      << ray_uniforms
      << "layout(location = 0) out vec4 qc_gnormal;  // normal, window depth\n"
         "layout(location = 1) out vec4 qc_gview;    // ray direction, shininess (> 0: covered)\n"
         "layout(location = 2) out vec4 qc_gcolor;   // colour, specular\n\n"
      << fns.str()
      << "void main()\n{\n"
         "    ivec2 px = ivec2(gl_FragCoord.xy);\n"
         "    vec4 nw = texelFetch(qc_slim_normal_weight, px, 0);\n"
         "    vec4 lm = texelFetch(qc_slim_lambda_material, px, 0);\n"
         "    vec3 cs = texelFetch(qc_slim_color, px, 0).rgb;\n"
         "    vec3 ro, rd;\n"
         "    qc_fragment_ray_" << proj << "(qc_ray_base, qc_ray_dx, qc_ray_dy, qc_ray_fixed, gl_FragCoord.xy, ro, rd);\n"
         "    bool covered;\n    vec3 n, color;\n    float lambda, depth;\n    vec2 material;\n"
         "    qc_slim_resolve(nw, lm, cs, rd, qc_vz_row, qc_pz, covered, n, lambda, depth, color, material);\n"
         "    if (!covered) discard;\n"
         "    gl_FragDepth = depth;\n"
         "    qc_gnormal = vec4(n, depth);\n"
         "    qc_gview = vec4(rd, material.y);\n"
         "    qc_gcolor = vec4(color, material.x);\n"
         "}\n";
    s.text = m.str();
    return s;
}

}  // namespace

std::vector<StageText> program_stages(const render::SlimKey& k) {
    const std::string proj = k.ortho ? "ortho" : "perspective";
    if (k.pass == render::SlimPass::resolve) {
        Stage v;
        v.text = detail::fullscreen_vertex;
        return {stage_text(StageText::Kind::vertex, "qc_fullscreen.vert", v, "SLIM resolve: full-screen triangle"),
                stage_text(StageText::Kind::fragment, "qc_slim_resolve_" + proj + ".frag", resolve_shader(k.ortho),
                           "SLIM renderer: the weighted sums divided into the geometry buffer, " + proj + " camera")};
    }
    const std::string pass = k.pass == render::SlimPass::visibility ? "visibility" : "accumulate";
    const std::string variant = pass + (k.cull ? "" : "_nocull");
    return {stage_text(StageText::Kind::vertex, "qc_slim_" + proj + ".vert", ball_vertex_shader(k.ortho),
                       "SLIM renderer: vertex stage of the balls (patch quadrilateral, culling), " + proj + " camera"),
            stage_text(StageText::Kind::fragment, "qc_slim_" + variant + "_" + proj + ".frag", ball_fragment_shader(k),
                       "SLIM renderer: " + pass + " pass of the balls, " + proj + " camera")};
}

}  // namespace quadcast::gl
