// src/gl/stages.cpp -- the vertex/fragment shaders of the quadric renderer and its deferred pass,
// assembled per variant key around the generated kernels. The plumbing here only moves data
// (records, varyings, uniforms, picks by index); every number it outputs comes from a traced function.
#include "quadcast/gl/stages.hpp"

#include <sstream>
#include <stdexcept>

#include "quadcast/render/record.hpp"
#include "quadcast/shading.hpp"
#include "stage_builder.hpp"

namespace quadcast::gl {

namespace {

using detail::add_kernel;
using detail::Stage;
using detail::stage_text;
using render::FragmentShape;

/// The record array and its accessors (quadcast::render::record_layout, which the GL renderer
/// packs with quadcast::render::pack_record).
const std::string record_glsl = render::record_glsl();

/// Environment reflection (forward and deferred shading): the latitude-longitude image and the
/// reflectivity, and the lookup around the traced kernels: `environment_texel` gives the position,
/// `environment_texels` the four texels around it (columns wrap, rows clamp), the plumbing
/// fetches them and `environment_mix` blends them into the colour.
/// quadcast::render::reflect_environment is the same on the CPU.
const char* environment_glsl =
    "vec3 qc_reflect_environment(vec3 rgb, vec3 n, vec3 e)\n{\n"
    "    ivec2 size = textureSize(qc_environment, 0);\n"
    "    vec2 t;\n"
    "    qc_environment_texel(n, e, vec2(size), t);\n"
    "    vec2 b;\n"
    "    vec4 x;  // columns x0, x1, rows y0, y1\n"
    "    qc_environment_texels(t, vec2(size), b, x);\n"
    "    vec3 mixed;\n"
    "    qc_environment_mix(rgb, t, b, texelFetch(qc_environment, ivec2(x.xz), 0).rgb, texelFetch(qc_environment, ivec2(x.yz), 0).rgb,\n"
    "        texelFetch(qc_environment, ivec2(x.xw), 0).rgb, texelFetch(qc_environment, ivec2(x.yw), 0).rgb, qc_reflectivity, mixed);\n"
    "    return mixed;\n}\n\n";

const char* environment_uniforms =
    "layout(binding = 4) uniform sampler2D qc_environment;  // latitude-longitude RGBA32F, row 0 = straight up\n"
    "uniform float qc_reflectivity;\n";

/// The bounding geometry of one primitive, shared by both vertex stages and the compute pass that
/// writes it for them (`all_corners`): with `qc_bound` 1 or 2
/// (quadcast::RectBound of the variant; general variants only) the NDC rectangle
/// `primitive_rect_ellipsoid` (corners (lo, lo), (hi, lo), (hi, hi), (lo, hi), at w = 1) or the
/// quadrilateral `primitive_quad_slab` (turned to the projected axis; with `qc_slab_quad`, else
/// the rectangle `primitive_rect_slab`), with `qc_bound` 3 the hull of the projected tetrahedron
/// of the clip planes (`primitive_quad_tetra`; record `prim`'s planes) when it is tight;
/// otherwise, and with `qc_bound` 0 (sphere-bound variants, or tight bounds off), the quad around
/// the bounding sphere (`primitive_bound_*`, the near-plane rectangle when the eye is inside the
/// sphere). The vertex stage picks corner k into `clip`; with `all_corners` the four corners go
/// into `clips[k]`, from the same kernels' same outputs.
std::string bound_glsl(const std::string& proj, bool rects, bool all_corners = false) {
    std::ostringstream m;
    m << "    vec2 lo, hi;\n    bool tight = false, visible = true;\n";
    if (rects)
        m << "    if (qc_bound == 1)\n"
             "        qc_primitive_rect_ellipsoid(qc_view_projection, q, qc_record_center(p), qc_record_radius(p), qc_record_axis(p), qc_record_half_length(p), qc_viewport, lo, hi, tight, visible);\n"
             "    else if (qc_bound == 2 && !qc_slab_quad)\n"
             "        qc_primitive_rect_slab(qc_view_projection, q, qc_record_center(p), qc_record_radius(p), qc_record_axis(p), qc_record_half_length(p), qc_viewport, lo, hi, tight, visible);\n"
             "    vec2 qd[4];\n"
             "    if (qc_bound == 2 && qc_slab_quad)\n"
             "        qc_primitive_quad_slab(qc_view_projection, q, qc_record_center(p), qc_record_radius(p), qc_record_axis(p), qc_record_half_length(p), qc_viewport, qd[0], qd[1], qd[2], qd[3], tight, visible);\n"
             "    else if (qc_bound == 3) {\n"
             "        qc_Planes pl = qc_planes[prim - qc_first];\n"
             "        qc_primitive_quad_tetra(qc_view_projection, pl.p[0], pl.p[1], pl.p[2], pl.p[3], qc_record_center(p), qc_viewport, qd[0], qd[1], qd[2], qd[3], tight, visible);\n"
             "    }\n"
             "    bool quad = (qc_bound == 2 && qc_slab_quad) || qc_bound == 3;\n";
    const std::string sphere_quad = detail::sphere_quad_glsl(proj);
    if (all_corners) {
        m << "    vec4 clips[4];\n";
        if (rects)
            m << "    if (tight && quad) {\n"
                 "        for (int k = 0; k < 4; ++k) clips[k] = vec4(qd[k], 0.0, 1.0);\n"
                 "    } else if (tight) {\n";
        else
            m << "    if (tight) {\n";
        m << "        for (int k = 0; k < 4; ++k) clips[k] = vec4(k == 1 || k == 2 ? hi.x : lo.x, k >= 2 ? hi.y : lo.y, 0.0, 1.0);\n"
             "    } else {\n" << sphere_quad
          << "        for (int k = 0; k < 4; ++k) qc_clip_position(qc_projection, valid ? corners[k] : qc_near_corners[k], clips[k]);\n"
             "    }\n";
        return m.str();
    }
    m << "    vec4 clip;\n";
    if (rects)
        m << "    if (tight && quad) {\n"
             "        clip = vec4(qd[k], 0.0, 1.0);\n"
             "    } else if (tight) {\n";
    else
        m << "    if (tight) {\n";
    m << "        clip = vec4(k == 1 || k == 2 ? hi.x : lo.x, k >= 2 ? hi.y : lo.y, 0.0, 1.0);\n"
         "    } else {\n" << sphere_quad
      << "        qc_clip_position(qc_projection, valid ? corners[k] : qc_near_corners[k], clip);\n"
         "    }\n";
    return m.str();
}

/// The workgroup's index along a record list: the passes over records dispatch their workgroups
/// in rows of at most 65535 (GL's guaranteed limit per dimension), so lists of more than 4M
/// records take several rows (`dispatch_rows` in quadric_renderer.cpp).
const char* linear_group_glsl =
    "uint qc_linear_group() { return gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x; }\n\n";

/// The clip planes of the planes variant (one set per record of the draw, index prim - qc_first),
/// read by the fragment stage's clip test and by the bounding geometry of `qc_bound` 3.
const char* planes_glsl =
    "// Clip planes of the `planes` variant, one set per primitive of the draw (index prim - qc_first).\n"
    "struct qc_Planes { vec4 p[4]; };\n"
    "layout(std430, binding = 1) readonly buffer qc_PlaneSets { qc_Planes qc_planes[]; };\n";

const char* bound_uniforms =
    "uniform mat4 qc_view;\nuniform mat4 qc_projection;\nuniform mat4 qc_view_projection;\n"
    "uniform vec3 qc_vz_row;           // third row of the world->view rotation\n"
    "uniform float qc_vz_t;            // the view matrix's z translation\n"
    "uniform vec3 qc_near_corners[4];  // view space, used when the eye is inside a bounding sphere\n"
    "uniform int qc_bound;             // quadcast::RectBound of the variant; 0: the bounding-sphere quad\n"
    "uniform vec2 qc_viewport;\nuniform uint qc_first;\n";

/// The visible primitives the occlusion cull pass lists (slot -> record index), read by both
/// vertex stages when the draw is indirect.
const char* visible_glsl =
    "layout(std430, binding = 4) readonly buffer qc_Visible { uint qc_visible[]; };\n"
    "uniform bool qc_indirect;\n\n";

/// What the cull pass's compaction (OcclusionPass::bounds) writes per slot of the visible list:
/// the clip positions of the primitive's four corners and its nearest view distance, read by both
/// vertex stages when `qc_fetch` is set (the draw is indirect and those were written for it).
const char* fetched_bounds_glsl =
    "layout(std430, binding = 8) readonly buffer qc_Corners { vec4 qc_corner[]; };     // 4 per slot\n"
    "layout(std430, binding = 9) readonly buffer qc_Nearests { float qc_nearests[]; };  // 1 per slot\n"
    "uniform bool qc_fetch;\n\n";

/// The vertex stage of the general variants: the bounding geometry (`bound_glsl`) and per-quadric
/// culling (`primitive_cull`, perspective cameras); the record, and with `planes` its four clip
/// planes, as flat varyings for the fragment stage.
Stage vertex_shader(bool ortho, bool planes) {
    Stage s;
    std::ostringstream fns;
    const std::string proj = ortho ? "ortho" : "perspective";
    add_kernel(s, fns, "primitive_rect_ellipsoid");
    add_kernel(s, fns, "primitive_rect_slab");
    add_kernel(s, fns, "primitive_quad_slab");
    add_kernel(s, fns, "primitive_quad_tetra");
    add_kernel(s, fns, "primitive_bound_" + proj);
    add_kernel(s, fns, "clip_position");
    if (!ortho) add_kernel(s, fns, "primitive_cull");
    add_kernel(s, fns, "nearest_distance");
    std::ostringstream m;
    m << record_glsl << planes_glsl;
    m << bound_uniforms << "uniform bool qc_slab_quad;        // slab bounds: the quadrilateral along the axis, else the rectangle\n"
         "uniform vec3 qc_eye;\nuniform bool qc_cull;\nuniform bool qc_caps;   // the variant closes a slab with caps\n\n"
         "flat out float qc_nearest;  // nearest view distance of the bounding sphere (the fragment stage's occlusion test)\n"
         "flat out uint qc_prim_id;   // the record's index (the ids target's, QuadricKey::ids)\n"
      << detail::record_varyings_glsl("out") << (planes ? "flat out vec4 qc_clip_planes[4];  // the planes variant's clip planes\n\n" : "\n");
    m << fns.str();
    m << visible_glsl << fetched_bounds_glsl;
    m << "// Indexed draw: vertex 4 i + k is corner k of primitive qc_first + i (two triangles share two);\n"
         "// with qc_indirect (occlusion culling) of the visible primitive in slot i (the draw's base vertex\n"
         "// is 4 qc_first); with qc_fetch the corner and the nearest distance the cull pass wrote for slot i.\n"
         "void main()\n{\n"
         "    uint slot = uint(gl_VertexID) / 4u;\n"
         "    uint prim = qc_indirect ? qc_visible[slot] : qc_first + slot;\n"
         "    int k = gl_VertexID % 4;\n"
         "    qc_Primitive p = qc_prims[prim];\n"
         "    qc_prim_id = prim;\n"
      << detail::record_varyings_out()
      << (planes ? "    for (int i = 0; i < 4; ++i) qc_clip_planes[i] = qc_planes[prim - qc_first].p[i];\n" : "")
      << "    if (qc_fetch) {\n"
         "        qc_nearest = qc_nearests[slot];\n"
         "        gl_Position = qc_corner[4u * slot + uint(k)];\n"
         "        return;\n"
         "    }\n"
         "    mat4 q = qc_record_quadric(p);\n"
      << bound_glsl(proj, true)
      << "    bool culled = false, culled_caps = false;\n";
    if (!ortho)
        m << "    if (qc_cull)\n"
             "        qc_primitive_cull(q, qc_record_center(p), qc_record_radius(p), qc_record_axis(p), qc_record_half_length(p), qc_eye, culled, culled_caps);\n";
    m << "    qc_nearest_distance(qc_vz_row, qc_vz_t, qc_record_center(p), qc_record_radius(p), qc_nearest);\n"
         "    gl_Position = (qc_cull && (qc_caps ? culled_caps : culled)) ? vec4(2.0, 2.0, 2.0, 1.0) : clip;\n"
         "}\n";
    s.text = m.str();
    return s;
}

/// What the sphere variant's fragment stage reads of record `p`: from the vertex stage's flat
/// varyings, or (QuadricKey::reshade) fetched by the fragment stage itself.
const char* const sphere_fields_glsl =
    "    qc_radius = qc_record_radius(p);\n"
    "    qc_center = qc_record_center(p);\n"
    "    qc_prim_color = qc_record_color(p);\n"
    "    qc_prim_material = qc_record_material(p);\n";

/// The vertex stage of the sphere-specialised variant: the bounding-sphere quad (the sphere is
/// its own bound), no per-primitive culling, and the radius, centre and
/// colour passed on as flat varyings (its fragment stage reads no record).
Stage sphere_vertex_shader(bool ortho, bool points) {
    Stage s;
    std::ostringstream fns;
    const std::string proj = ortho ? "ortho" : "perspective";
    add_kernel(s, fns, "primitive_bound_" + proj);
    add_kernel(s, fns, "clip_position");
    add_kernel(s, fns, "nearest_distance");
    if (points) add_kernel(s, fns, "point_sprite");
    // (both vertex stages: the record of `prim` and the varyings the fragment stage reads instead of it)
    const std::string sphere_varyings = std::string("    qc_Primitive p = qc_prims[prim];\n"
                                                    "    qc_prim_id = prim;\n") + sphere_fields_glsl;
    std::ostringstream m;
    m << record_glsl;
    m << bound_uniforms << "\n"
         "flat out float qc_nearest;  // nearest view distance of the sphere (the fragment stage's occlusion test)\n"
         "flat out uint qc_prim_id;   // the record's index (the ids target's, QuadricKey::ids)\n"
         "flat out float qc_radius;\nflat out vec3 qc_center;\nflat out vec3 qc_prim_color;\nflat out vec2 qc_prim_material;  // specular, shininess\n\n";
    m << fns.str();
    m << visible_glsl << fetched_bounds_glsl;
    if (points) {
        // (the renderer draws points only where render::sphere_points_fit: every sphere inside the
        // view's side planes and beyond the near plane, so the quad is valid and its corners in front)
        m << "// Point sprites: vertex i is primitive qc_first + i, or with qc_indirect the visible primitive in\n"
             "// slot i (the draw's first vertex is qc_first); the sprite around the bounding quad's corners.\n"
             "void main()\n{\n"
             "    uint slot = uint(gl_VertexID);\n"
             "    uint prim = qc_indirect ? qc_visible[slot] : qc_first + slot;\n"
          << sphere_varyings << bound_glsl(proj, false, true)
          << "    qc_nearest_distance(qc_vz_row, qc_vz_t, qc_record_center(p), qc_record_radius(p), qc_nearest);\n"
             "    vec2 centre;\n    float size;\n"
             "    qc_point_sprite(clips[0], clips[1], clips[2], clips[3], qc_viewport, centre, size);\n"
             "    gl_PointSize = size;\n"
             "    gl_Position = vec4(centre, 0.0, 1.0);\n"
             "}\n";
        s.text = m.str();
        return s;
    }
    m << "// Indexed draw: vertex 4 i + k is corner k of primitive qc_first + i (two triangles share two);\n"
         "// with qc_indirect (occlusion culling) of the visible primitive in slot i (the draw's base vertex\n"
         "// is 4 qc_first); with qc_fetch the corner and the nearest distance the cull pass wrote for slot i.\n"
         "void main()\n{\n"
         "    uint slot = uint(gl_VertexID) / 4u;\n"
         "    uint prim = qc_indirect ? qc_visible[slot] : qc_first + slot;\n"
         "    int k = gl_VertexID % 4;\n"
      << sphere_varyings <<
         "    if (qc_fetch) {\n"
         "        qc_nearest = qc_nearests[slot];\n"
         "        gl_Position = qc_corner[4u * slot + uint(k)];\n"
         "        return;\n"
         "    }\n"
      << bound_glsl(proj, false)
      << "    qc_nearest_distance(qc_vz_row, qc_vz_t, qc_record_center(p), qc_record_radius(p), qc_nearest);\n"
         "    gl_Position = clip;\n"
         "}\n";
    s.text = m.str();
    return s;
}

/// The quadric pass: forward (cast and shade) or, with `gbuffer`, cast and write the geometry
/// buffer of the deferred pass (Sigg et al. 2006, sec. 4): normal and window depth, ray direction
/// (the shading's eye vector) and colour.
/// With `env`, forward shading mixes in the environment reflection (`qc_reflect_environment`).
/// With `early`, the fragment is first discarded where the primitive's nearest distance lies behind
/// the cull pass's depth image. With `count`, atomic adds count the fragments that start, that
/// pass the early discard and cast their ray, and whose ray hits (binding 14).
Stage fragment_shader(const render::QuadricKey& k) {
    Stage s;
    const bool ortho = k.ortho, gbuffer = k.gbuffer, env = k.environment;
    const bool brute = k.stage == render::FragmentStage::brute_force;
    const bool planes = k.shape == FragmentShape::planes;
    const bool sphere = k.shape == FragmentShape::sphere;  // radius, colour, o, v from the vertex stage
    const bool slab = k.shape == FragmentShape::slab;
    const std::string kernel = render::fragment_kernel_name(k.shape, k.cull);
    std::ostringstream fns;
    add_kernel(s, fns, brute ? std::string("pixel_ray") : std::string("fragment_ray_") + (ortho ? "ortho" : "perspective"));
    add_kernel(s, fns, kernel);
    if (!gbuffer) add_kernel(s, fns, "shade_blinn_phong");
    if (env) {
        add_kernel(s, fns, "environment_texel");
        add_kernel(s, fns, "environment_texels");
        add_kernel(s, fns, "environment_mix");
        fns << environment_glsl;
    }
    std::ostringstream m;
    if (!sphere) m << record_glsl;
    if (planes) m << "flat in vec4 qc_clip_planes[4];  // the primitive's clip planes (from the vertex stage)\n\n";
    if (brute)
        m << "uniform mat4 qc_inv_view_proj;  // brute force: the pixel's ray from gl_FragCoord\n"
             "uniform vec3 qc_eye;\nuniform vec2 qc_viewport;\n";
    else
        m << "uniform vec3 qc_ray_base, qc_ray_dx, qc_ray_dy;  // the pixel's ray, affine in gl_FragCoord.xy (quadcast::window_ray)\n"
             "uniform vec3 qc_ray_fixed;    // the eye (perspective) or the viewing direction (orthographic)\n";
    m << "uniform vec3 qc_vz_row;       // third row of the world->view rotation\n"
         "uniform vec4 qc_pz;           // P22, P32, P23, P33 of the projection\n";
    if (!gbuffer)
        m << "uniform vec3 qc_light_dir;    // towards the scene\nuniform vec3 qc_light_color;\n"
             "uniform vec4 qc_material;     // ambient, diffuse, specular, shininess\n";
    if (env) m << environment_uniforms;
    if (k.early)
        m << "\n// Occlusion culling: the occluder depth image of the cull pass (level 0 of its pyramid: per pixel\n"
             "// the bits of a view distance no nearer than what the pixel shows, or all ones).\n"
             << detail::depth_texels_glsl()
             << "uniform int qc_depth_width;   // its width (the viewport's)\n";
    if (!k.reshade) m << "flat in float qc_nearest;     // the primitive's nearest view distance (quadcast::nearest_distance)\n";
    if (k.count)
        m << "// Fragment counts (a measurement): started, passed the early discard (cast their ray), hit\n"
             "layout(std430, binding = 14) buffer qc_FragmentCounts { uint qc_fragment_count[3]; };\n";
    if (k.reshade)
        m << "\n" << record_glsl
          << "// Shaded from the ids target (QuadricKey::reshade): per pixel the record it showed + 1 (0: none),\n"
             "// the sphere variant's records [qc_reshade_first, qc_reshade_first + qc_reshade_count).\n"
             "layout(binding = " << reshade_ids_unit << ") uniform usampler2D qc_ids;\n"
             "uniform uint qc_reshade_first, qc_reshade_count;\n"
             "float qc_radius;\nvec3 qc_center;\nvec3 qc_prim_color;\nvec2 qc_prim_material;  // the record's, as the sprites' varyings\n";
    else if (sphere)
        m << "\nflat in float qc_radius;\nflat in vec3 qc_center;\nflat in vec3 qc_prim_color;\nflat in vec2 qc_prim_material;\n";
    else
        m << "\n" << detail::record_varyings_glsl("in");
    if (gbuffer)
        m << "layout(location = 0) out vec4 qc_gnormal;  // normal (unnormalised), window depth\n"
             "layout(location = 1) out vec4 qc_gview;    // ray direction, shininess (> 0: covered)\n"
             "layout(location = 2) out vec4 qc_gcolor;   // colour, specular\n\n";
    else
        m << "layout(location = 0) out vec4 qc_color;\n\n";
    if (k.ids)
        m << "flat in uint qc_prim_id;\n"
             "layout(location = " << (gbuffer ? 3 : 1) << ") out uint qc_id;  // the record's index + 1 (0: no record)\n\n";
    m << fns.str();
    m << "void main()\n{\n";
    if (k.count) m << "    atomicAdd(qc_fragment_count[0], 1u);\n";
    if (k.reshade)
        m << "    uint qc_shown_id = texelFetch(qc_ids, ivec2(gl_FragCoord.xy), 0).r;\n"
             "    if (qc_shown_id == 0u || qc_shown_id - 1u - qc_reshade_first >= qc_reshade_count) discard;  // (no sphere here)\n"
             "    qc_Primitive p = qc_prims[qc_shown_id - 1u];\n"
          << sphere_fields_glsl;
    if (k.early)
        m << "    // Behind the occluders at this pixel: nothing of this primitive can show here (quadcast/occlusion.hpp)\n"
             "    if (qc_nearest > 0.0 && floatBitsToUint(qc_nearest) > qc_depth_texel(qc_pyramid_index(uvec3(0u, uint(qc_depth_width), 0u), uvec2(gl_FragCoord.xy)))) discard;\n";
    if (k.count) m << "    atomicAdd(qc_fragment_count[1], 1u);\n";
    m
      << (sphere ? "" : detail::record_varyings_in())
      << "    bool hit;\n    float depth;\n    vec3 n;\n";
    m << "    vec3 ro, rd;\n";
    if (brute) m << "    qc_pixel_ray(qc_inv_view_proj, qc_eye, gl_FragCoord.xy, qc_viewport, ro, rd);\n";
    else m << "    qc_fragment_ray_" << (ortho ? "ortho" : "perspective") << "(qc_ray_base, qc_ray_dx, qc_ray_dy, qc_ray_fixed, gl_FragCoord.xy, ro, rd);\n";
    const char* eye_vec = "rd";
    const char* color = sphere ? "qc_prim_color" : "qc_record_color(p)";
    const char* material = sphere ? "qc_prim_material" : "qc_record_material(p)";
    if (sphere)
        m << "    qc_" << kernel << "(qc_radius, qc_center, ro, rd, qc_vz_row, qc_pz, hit, depth, n);\n";
    else
        m << "    qc_" << kernel << "(qc_record_quadric(p), qc_record_center(p), qc_record_radius(p), qc_record_axis(p), qc_record_half_length(p),\n"
          << (slab ? "        qc_record_caps(p),\n" : "")
          << (planes ? "        qc_clip_planes[0], qc_clip_planes[1], qc_clip_planes[2], qc_clip_planes[3],\n" : "")
          << "        ro, rd, qc_vz_row, qc_pz, hit, depth, n);\n";
    m << "    if (!hit) discard;\n";
    if (k.count) m << "    atomicAdd(qc_fragment_count[2], 1u);\n";
    m << "    gl_FragDepth = depth;\n";
    if (k.ids) m << "    qc_id = qc_prim_id + 1u;\n";
    if (gbuffer)
        m << "    qc_gnormal = vec4(n, depth);\n"
             "    qc_gview = vec4(" << eye_vec << ", " << material << ".y);\n"
          << "    qc_gcolor = vec4(" << color << ", " << material << ".x);\n"
             "}\n";
    else
        m << "    vec3 rgb;\n"
             "    qc_shade_blinn_phong(n, -qc_light_dir, -" << eye_vec << ", " << color << ", qc_light_color, vec4(qc_material.xy, " << material << "), rgb);\n"
          << (env ? std::string("    rgb = qc_reflect_environment(rgb, n, -") + eye_vec + ");\n" : std::string())
          << "    qc_color = vec4(rgb, 1.0);\n"
             "}\n";
    s.text = m.str();
    return s;
}


/// The deferred pass (Sigg et al. 2006, sec. 4): per pixel, Blinn-Phong from the geometry buffer
/// (`shade_blinn_phong` with the same arguments as the forward pass: bit-identical colour), the
/// background where nothing was hit; with `silhouettes` the outline of `silhouette` from the 3x3
/// neighbourhood (texel coordinates clamped to the image); with `env` the environment reflection
/// mixed into the shaded colour before the outline. With `background`, the background colour and
/// the outline only (the renderer draws it where nothing was hit; no shading, shadows or
/// environment). With `phases` (and `shadows`) the penumbra's 64 samples are read four at a time
/// from the shadow map in phases (`shadow_phases_shader`, unit 5).
Stage deferred_shader(bool silhouettes, bool shadows, bool env, bool background, bool phases) {
    Stage s;
    std::ostringstream fns;
    if (!background) add_kernel(s, fns, shadows ? "shade_blinn_phong_shadowed" : "shade_blinn_phong");
    if (silhouettes) {
        add_kernel(s, fns, "silhouette");
        add_kernel(s, fns, "neighbour_texel");
    }
    if (shadows) {
        add_kernel(s, fns, "shadow_coord");
        add_kernel(s, fns, "pcf_first8_from_count");
        add_kernel(s, fns, "pcf_count_step");
        if (!phases) add_kernel(s, fns, "pcf_fraction64");  // (the one-by-one penumbra's)
        add_kernel(s, fns, "pcf_sample_texel");
        if (phases) {
            add_kernel(s, fns, "pcf_phase");
            add_kernel(s, fns, "pcf_gather_coord");
            add_kernel(s, fns, "pcf_fraction_of64");
        }
    }
    if (env) {
        add_kernel(s, fns, "environment_texel");
        add_kernel(s, fns, "environment_texels");
        add_kernel(s, fns, "environment_mix");
        fns << environment_glsl;
    }
    std::ostringstream m;
    m << "layout(binding = 0) uniform sampler2D qc_gnormal;  // normal, window depth (1 = background)\n"
         "layout(binding = 1) uniform sampler2D qc_gview;    // ray direction, shininess (0: background)\n"
         "layout(binding = 2) uniform sampler2D qc_gcolor;   // colour, specular\n"
         "uniform vec3 qc_light_dir;    // towards the scene\nuniform vec3 qc_light_color;\n"
         "uniform vec4 qc_material;     // ambient, diffuse, specular, shininess\n"
         "uniform vec3 qc_background;\n";
    if (silhouettes)
        m << "uniform vec4 qc_pz;           // P22, P32, P23, P33 of the projection\n"
             "uniform vec4 qc_silhouette_params;  // depth threshold, normal threshold, strength, unused\n";
    if (shadows) {
        m << "layout(binding = 3) uniform sampler2D qc_shadow_map;  // window depth from the light\n"
             "uniform mat4 qc_to_light;     // camera NDC -> light clip space\n"
             "uniform vec2 qc_viewport;\n"
             "uniform float qc_shadow_size;  // shadow map size (texels)\n"
             "uniform float qc_shadow_bias;  // light window depth\n"
             "uniform float qc_pcf_step;     // texels between PCF samples\n"
             "uniform int qc_pcf_samples;    // 64 (a uniform: the compiler keeps the penumbra's loop a loop)\n"
             "// PCF samples: grid cell (8x8) in quadcast::pcf_grid_order, the first 8 spread out.\n"
             "const float qc_pcf_order[64] = float[64](";
        for (int i = 0; i < 64; ++i) m << (i ? ", " : "") << pcf_grid_order[i] << ".0";
        m << ");\n";
        if (phases)
            m << "layout(binding = 5) uniform sampler2D qc_shadow_phases;  // the map in phases of the step (phase_source_texel)\n"
                 "uniform float qc_pcf_inv_step;    // 1 / qc_pcf_step\n"
                 "uniform float qc_phase_tile;      // texels per side of a tile of it\n"
                 "uniform float qc_phase_inv_size;  // 1 / its texels per side\n";
    }
    if (env) m << environment_uniforms;
    m << "layout(location = 0) out vec4 qc_color;\n\n";
    m << fns.str();
    if (shadows)
        m << "float qc_shadow_sample(vec2 st, int k)\n{\n"
             "    vec2 t;\n"
             "    qc_pcf_sample_texel(st, qc_pcf_order[k], qc_pcf_step, qc_shadow_size - 1.0, t);\n"
             "    return texelFetch(qc_shadow_map, ivec2(t), 0).r;\n"
             "}\n\n";
    m << "void main()\n{\n"
         "    ivec2 px = ivec2(gl_FragCoord.xy);\n"
         "    vec4 gn = texelFetch(qc_gnormal, px, 0);\n"
         "    vec4 gv = texelFetch(qc_gview, px, 0);\n"
         "    vec4 gc = texelFetch(qc_gcolor, px, 0);\n"
         "    vec3 rgb = qc_background;\n";
    if (shadows)  // (false for the background)
        // PCF (Sigg et al. 2006, sec. 4): the first 8 samples, then where they disagree (the
        // penumbra) the other 56, each counted as it is fetched. The 56 in a loop, not behind a
        // branch: llvmpipe runs both sides of a branch for every pixel of its SIMD group, but
        // leaves a loop once every pixel of the group has left it; so a group outside any
        // penumbra, or of background pixels, fetches 8 samples instead of 64 (and runs the loop
        // body once with every pixel masked off; the same picture).
        m << "    bool covered = gv.w != 0.0;\n"
             "    vec2 st;\n    float lz;\n"
             "    qc_shadow_coord(gl_FragCoord.xy, gn.w, qc_viewport, qc_to_light, qc_shadow_size, st, lz);\n"
             "    float count = 0.0;\n"
             "    for (int k = 0; k < 8; ++k) qc_pcf_count_step(count, lz, qc_shadow_bias, qc_shadow_sample(st, k), count);\n"
             "    float vis;\n    bool decided;\n"
             "    qc_pcf_first8_from_count(count, vis, decided);\n"
             "    decided = decided || !covered;\n"
             "    count = 0.0;\n";
    if (shadows && phases)
        // The penumbra's 64 samples: 16 gathers of 2 x 2 from the map in phases, where they are
        // 8 x 8 consecutive texels (`pcf_phase`), each counted as read, all 64 (the first 8
        // again). A loop, not a branch, for llvmpipe (above), its bound from the uniform (4 rows
        // of 4 gathers).
        m << "    vec2 cell;\n"
             "    qc_pcf_phase(st, qc_pcf_step, qc_pcf_inv_step, qc_shadow_size - 1.0, qc_phase_tile, cell);\n"
             "    for (int gy = 0; gy < (qc_pcf_samples >> 4); ++gy) {\n"
             "        if (decided) break;\n"
             "        for (int gx = 0; gx < 4; ++gx) {\n"
             "            vec2 uv;\n"
             "            qc_pcf_gather_coord(cell, float(2 * gx), float(2 * gy), qc_phase_inv_size, uv);\n"
             "            vec4 s4 = textureGather(qc_shadow_phases, uv);\n"
             "            for (int i = 0; i < 4; ++i) qc_pcf_count_step(count, lz, qc_shadow_bias, s4[i], count);\n"
             "        }\n"
             "    }\n"
             "    if (!decided) qc_pcf_fraction_of64(count, vis);\n";
    else if (shadows)
        m << "    for (int k = 8; k < qc_pcf_samples; ++k) {\n"
             "        if (decided) break;\n"
             "        qc_pcf_count_step(count, lz, qc_shadow_bias, qc_shadow_sample(st, k), count);\n"
             "    }\n"
             "    if (!decided) qc_pcf_fraction64(vis, count, vis);\n";
    if (!background) {
        m << "    if (gv.w != 0.0) {\n";
        if (shadows)
            m << "        qc_shade_blinn_phong_shadowed(gn.xyz, -qc_light_dir, -gv.xyz, gc.rgb, qc_light_color, vec4(qc_material.xy, gc.w, gv.w), vis, rgb);\n";
        else
            m << "        qc_shade_blinn_phong(gn.xyz, -qc_light_dir, -gv.xyz, gc.rgb, qc_light_color, vec4(qc_material.xy, gc.w, gv.w), rgb);\n";
        if (env) m << "        rgb = qc_reflect_environment(rgb, gn.xyz, -gv.xyz);\n";
        m << "    }\n";
    }
    if (silhouettes) {
        m << "    vec2 last = vec2(textureSize(qc_gnormal, 0) - 1);\n"
             "    vec4 t[9];\n"
             "    for (int r = 0; r < 3; ++r)\n"
             "        for (int c = 0; c < 3; ++c) {  // row 0 = top (window y + 1)\n"
             "            vec2 q;\n"
             "            qc_neighbour_texel(gl_FragCoord.xy, float(c - 1), float(1 - r), last, q);\n"
             "            t[3 * r + c] = texelFetch(qc_gnormal, ivec2(q), 0);\n"
             "        }\n"
             "    qc_silhouette(t[0].w, t[1].w, t[2].w, t[3].w, t[4].w, t[5].w, t[6].w, t[7].w, t[8].w,\n"
             "        t[0].xyz, t[1].xyz, t[2].xyz, t[3].xyz, t[4].xyz, t[5].xyz, t[6].xyz, t[7].xyz, t[8].xyz,\n"
             "        qc_pz, qc_silhouette_params, rgb, rgb);\n";
    }
    m << "    qc_color = vec4(rgb, 1.0);\n"
         "}\n";
    s.text = m.str();
    return s;
}

/// The pass-through fragment stage (benchmark baseline: the rasteriser's fill rate).
const char* passthrough_fragment =
    "layout(location = 0) out vec4 qc_color;\n\nvoid main()\n{\n    qc_color = vec4(0.5, 0.5, 0.5, 1.0);\n    gl_FragDepth = gl_FragCoord.z;\n}\n";

/// The buffers the occlusion passes share: the occluder of each record (its centre,
/// quadcast::render::occluder_radius (0: none), bounding radius and occluder_half_axis) and the max-depth pyramid (level 0: the occluder depth of
/// every pixel, float bits of positive view distances, which order as unsigned integers; no
/// occluder: 0xffffffff), each level at an offset with its size.
const char* occlusion_buffers =
    "layout(std430, binding = 2) readonly buffer qc_Occluders { vec4 qc_occluder[]; };  // per record: centre, ball radius (0: none); bounding radius, chain half axis\n"
    "layout(std430, binding = 3) buffer qc_Depths { uint qc_depth[]; };\n"
    "uniform uint qc_first;   // the variant's first record\n"
    "uniform uint qc_count;   // its records\n"
    "uniform vec3 qc_vz_row;  // third row of the world->view rotation\n"
    "uniform float qc_vz_t;   // the view matrix's z translation\n"
    "uniform vec2 qc_viewport;\n"
    "uniform mat4 qc_view_projection;\n";

/// Occlusion pass 1: per record with occluder balls (one, or a chain along a capped cylinder:
/// `occluder_chain_count`, `occluder_chain_disk`), per usable ball (`occluder_depth`: all of the
/// primitive beyond the near plane, the disk before the far plane, depths resolved), the pixels whose centres fall in the ellipse its disk projects to
/// (`occluder_ellipse`, `ellipse_covers`, over `pixel_span` of the ellipse's box) take the disk's
/// view distance where it is nearer than theirs. Plain loads and stores: any occluder's value is
/// conservative (quadcast/occlusion.hpp), so a lost race only loosens a pixel. Chains only with
/// qc_chains (not when the sticks are drawn in phases).
Stage occluder_shader() {
    Stage s;
    std::ostringstream fns;
    add_kernel(s, fns, "occluder_depth");
    add_kernel(s, fns, "occluder_ellipse");
    add_kernel(s, fns, "pixel_span");
    add_kernel(s, fns, "ellipse_covers");
    add_kernel(s, fns, "occluder_chain_count");
    add_kernel(s, fns, "occluder_chain_disk");
    std::ostringstream m;
    m << "layout(local_size_x = 64) in;\n\n" << record_glsl << occlusion_buffers << linear_group_glsl << gl::pyramid_index_glsl()
      << "uniform vec3 qc_right, qc_up;    // first two rows of the world->view rotation\n"
         "uniform vec3 qc_occluder_range;  // near and far view distances an occluder must lie between, gap (quadcast::render::occlusion_range)\n"
         "uniform vec4 qc_pz;             // P22, P32, P23, P33 of the projection\n"
         "uniform uint qc_max_pixels;     // larger boxes are left out\n"
         "uniform bool qc_chains;         // chains of disks too (false: single disks only; phased sticks)\n\n"
      << fns.str()
      << "// One disk: centre c, radius r_in, in a ball of radius `radius` holding the primitive.\n"
         "void qc_write_disk(vec3 c, float r_in, float radius)\n{\n"
         "    float s;\n    bool usable;\n"
         "    qc_occluder_depth(qc_vz_row, qc_vz_t, c, r_in, radius, qc_occluder_range.x, qc_occluder_range.y, qc_occluder_range.z, qc_pz, s, usable);\n"
         "    if (!usable) return;\n"
         "    vec2 centre, axes, lo, hi;\n"
         "    qc_occluder_ellipse(qc_view_projection, c, qc_right, qc_up, r_in, centre, axes, lo, hi);\n"
         "    vec4 span;\n"
         "    qc_pixel_span(lo, hi, qc_viewport, span);\n"
         "    if (!(span.x <= span.z && span.y <= span.w)) return;\n"
         "    ivec4 b = ivec4(span);\n"
         "    if (uint(b.z - b.x + 1) * uint(b.w - b.y + 1) > qc_max_pixels) return;\n"
         "    uint bits = floatBitsToUint(s);\n"
         "    uvec3 level0 = uvec3(0u, uint(qc_viewport.x), uint(qc_viewport.y));\n"
         "    for (int y = b.y; y <= b.w; ++y)\n"
         "        for (int x = b.x; x <= b.z; ++x) {\n"
         "            bool covered;\n"
         "            qc_ellipse_covers(vec2(x, y) + 0.5, qc_viewport, centre, axes, covered);\n"
         "            uint at = qc_pyramid_index(level0, uvec2(x, y));\n"
         "            if (covered && bits < qc_depth[at]) qc_depth[at] = bits;\n"
         "        }\n"
         "}\n\n"
         "void main()\n{\n"
         "    uint i = qc_linear_group() * 64u + gl_LocalInvocationID.x;\n"
         "    if (i >= qc_count) return;\n"
         "    uint prim = qc_first + i;\n"
         "    vec4 ball = qc_occluder[2u * prim];\n"
         "    vec4 more = qc_occluder[2u * prim + 1u];  // bounding radius, the chain's half axis\n"
         "    float r_in = ball.w;\n"
         "    if (!(r_in > 0.0)) return;\n"
         "    float n;\n"
         "    qc_occluder_chain_count(more.yzw, r_in, n);\n"
         "    if (n > 1.0 && !qc_chains) return;\n"
         "    for (float k = 0.0; k < n; k += 1.0) {\n"
         "        vec3 ck;\n        float radius_k;\n"
         "        qc_occluder_chain_disk(ball.xyz, more.yzw, more.x, k, n, ck, radius_k);\n"
         "        qc_write_disk(ck, r_in, radius_k);\n"
         "    }\n"
         "}\n";
    s.text = m.str();
    return s;
}

/// Occlusion pass 1 drawn by the rasteriser (OcclusionPass::occluder_raster): four vertices per
/// record of the drawn range (vertex k of record qc_first + i is vertex 4 i + k), each a corner of the
/// record's occluder quadrilateral (`occluder_corner`); a record without a usable occluder puts
/// all four outside the clip volume. The depth of the (planar) quadrilateral is rasterised, never
/// written by the fragment stage, so the depth test runs before it.
Stage occluder_raster_shader() {
    Stage s;
    std::ostringstream fns;
    add_kernel(s, fns, "occluder_corner");
    std::ostringstream m;
    m << "layout(std430, binding = 2) readonly buffer qc_Occluders { vec4 qc_occluder[]; };  // per record: centre, ball radius (0: none); bounding radius, chain half axis\n"
         "uniform uint qc_first;             // the drawn variant's first record\n"
         "uniform mat4 qc_view_projection;\n"
         "uniform vec3 qc_vz_row;            // third row of the world->view rotation\n"
         "uniform float qc_vz_t;             // the view matrix's z translation\n"
         "uniform vec3 qc_right, qc_up;      // first two rows of the world->view rotation\n"
         "uniform vec3 qc_occluder_range;    // near and far view distances an occluder must lie between, gap (quadcast::render::occlusion_range)\n"
         "uniform vec4 qc_pz;                // P22, P32, P23, P33 of the projection\n"
         "uniform float qc_p11;              // P11 of the projection\n"
         "uniform vec2 qc_viewport;\n\n"
      << fns.str()
      << "void main()\n{\n"
         "    uint prim = qc_first + uint(gl_VertexID) / 4u;\n"
         "    vec4 ball = qc_occluder[2u * prim];\n"
         "    vec4 more = qc_occluder[2u * prim + 1u];\n"
         "    vec4 clip = vec4(2.0, 2.0, 2.0, 1.0);\n"
         "    bool usable = false;\n"
         "    if (ball.w > 0.0)\n"
         "        qc_occluder_corner(qc_view_projection, qc_vz_row, qc_vz_t, qc_right, qc_up, ball, more, qc_occluder_range, qc_pz, qc_p11, qc_viewport.y,\n"
         "                           float(gl_VertexID & 3), clip, usable);\n"
         "    gl_Position = usable ? clip : vec4(2.0, 2.0, 2.0, 1.0);\n"
         "}\n";
    s.text = m.str();
    return s;
}

/// Occlusion pass 1 of a later phase of phased drawing: each pixel of the depth image takes the
/// view distance of what the depth buffer now holds there (`depth_distance`, no nearer than it)
/// where that is nearer than its value; the background and what lies at the far plane leave it.
/// What is drawn later can only bring a pixel nearer, so the value stays conservative. One
/// invocation per texel of pyramid level 1, which updates its (up to) 2 x 2 pixels
/// (`pyramid_children`, as the pyramid pass reads them) and writes the largest of them there: a
/// quarter of the invocations, and no pyramid pass for level 1.
Stage depth_image_shader() {
    Stage s;
    std::ostringstream fns;
    add_kernel(s, fns, "depth_distance");
    add_kernel(s, fns, "pyramid_children");
    std::ostringstream m;
    m << "layout(local_size_x = 8, local_size_y = 8) in;\n\n"
         "layout(std430, binding = 3) buffer qc_Depths { uint qc_depth[]; };\n"
         "uniform sampler2D qc_depth_buffer;  // the bound framebuffer's depth target (window depths)\n"
         "uniform uvec2 qc_size;              // the viewport, level 0 of the depth image\n"
         "uniform vec4 qc_pz;                 // P22, P32, P23, P33 of the projection\n"
         "uniform uvec3 qc_level1;            // offset, width, height of pyramid level 1 (a 1 x 1 image: level 0)\n\n"
      << gl::pyramid_index_glsl() << fns.str()
      << "void main()\n{\n"
         "    uvec2 t = gl_GlobalInvocationID.xy;  // a texel of level 1\n"
         "    if (t.x >= qc_level1.y || t.y >= qc_level1.z) return;\n"
         "    vec4 children;\n"
         "    qc_pyramid_children(vec2(t), vec2(qc_size), children);\n"
         "    uvec4 c = uvec4(children);\n"
         "    uint m = 0u;\n"
         "    for (uint k = 0u; k < 4u; ++k) {\n"
         "        uvec2 p = uvec2((k & 1u) == 0u ? c.x : c.z, k < 2u ? c.y : c.w);\n"
         "        uint at = qc_pyramid_index(uvec3(0u, qc_size), p);\n"
         "        uint v = qc_depth[at];\n"
         "        float s;\n        bool far;\n"
         "        qc_depth_distance(texelFetch(qc_depth_buffer, ivec2(p), 0).r, qc_pz, s, far);\n"
         "        if (!far && s > 0.0 && floatBitsToUint(s) < v) {\n"
         "            v = floatBitsToUint(s);\n"
         "            qc_depth[at] = v;\n"
         "        }\n"
         "        m = max(m, v);\n"
         "    }\n"
         "    qc_depth[qc_pyramid_index(qc_level1, t)] = m;\n"
         "}\n";
    s.text = m.str();
    return s;
}

/// Occlusion pass 2: one level of the max-depth pyramid, each texel the largest of the (up to)
/// 2 x 2 texels below it (`pyramid_children`; no arithmetic on depths).
Stage pyramid_shader() {
    Stage s;
    std::ostringstream fns;
    add_kernel(s, fns, "pyramid_children");
    std::ostringstream m;
    m << "layout(local_size_x = 8, local_size_y = 8) in;\n\n"
         "layout(std430, binding = 3) buffer qc_Depths { uint qc_depth[]; };\n"
         "uniform uvec3 qc_src;  // offset, width, height of the level below\n"
         "uniform uvec3 qc_dst;  // of the level written\n\n"
      << gl::pyramid_index_glsl() << fns.str()
      << "void main()\n{\n"
         "    uvec2 t = gl_GlobalInvocationID.xy;\n"
         "    if (t.x >= qc_dst.y || t.y >= qc_dst.z) return;\n"
         "    vec4 children;\n"
         "    qc_pyramid_children(vec2(t), vec2(qc_src.yz), children);\n"
         "    uvec4 c = uvec4(children);\n"
         "    uint m = max(max(qc_depth[qc_pyramid_index(qc_src, c.xy)], qc_depth[qc_pyramid_index(qc_src, c.zy)]),\n"
         "                 max(qc_depth[qc_pyramid_index(qc_src, c.xw)], qc_depth[qc_pyramid_index(qc_src, c.zw)]));\n"
         "    qc_depth[qc_pyramid_index(qc_dst, t)] = m;\n"
         "}\n";
    s.text = m.str();
    return s;
}

/// Occlusion pass 3: per record, its rectangle (`primitive_rect_*` of its variant's bound); a
/// record whose rectangle is tight and holds no pixel centre of the viewport (`pixel_span`), or
/// whose nearest view distance (`nearest_distance`) lies beyond the largest occluder depth over
/// its pixels (read from the pyramid level where they span at most 8 x 8 texels), is culled
/// (qc_keep 0, counted after the commands); the others are kept (qc_keep 1 + the kept records
/// before it in its workgroup of 64), and each workgroup counts its kept ones.
Stage cull_shader(bool sphere_bound) {
    Stage s;
    std::ostringstream fns;
    if (sphere_bound) {
        add_kernel(s, fns, "primitive_rect_sphere");
    } else {
        add_kernel(s, fns, "primitive_rect_ellipsoid");
        add_kernel(s, fns, "primitive_rect_slab");
    }
    add_kernel(s, fns, "pixel_span");
    add_kernel(s, fns, "nearest_distance");
    std::ostringstream m;
    m << "layout(local_size_x = 64) in;\n\n" << record_glsl << occlusion_buffers << linear_group_glsl
      << "layout(std430, binding = 5) buffer qc_Commands { uint qc_command[]; };  // DrawElementsIndirectCommand per variant, then statistics\n"
         "layout(std430, binding = 6) writeonly buffer qc_Keep { uint qc_keep[]; };   // per record: 0 culled, else 1 + its slot in the workgroup\n"
         "layout(std430, binding = 7) writeonly buffer qc_Groups { uint qc_groups[]; };  // per workgroup of 64 records: the kept ones\n"
         << (sphere_bound ? "" : "uniform int qc_bound;        // quadcast::RectBound of the variant (ellipsoid or slab)\n")
         << "uniform uint qc_stats_at;    // the counts of primitives culled outside the frustum and behind occluders (uint offset)\n"
         "uniform bool qc_occlusion;   // test against the pyramid (else only the frustum)\n"
         "uniform uvec3 qc_levels[16]; // offset, width, height of each pyramid level\n"
         "uniform int qc_level_count;\n"
         "// Phased drawing: this pass keeps only the records whose nearest view distance lies in the\n"
         "// phase's window [lo, hi) (the first phase from -infinity, NaN included; the last to +infinity).\n"
         "uniform bool qc_windowed;\nuniform vec2 qc_window;\nuniform bool qc_window_first, qc_window_last;\n"
         "// Reuse of the last frame's shown set (RenderOptions::occlusion_reuse): per record whether it\n"
         "// passed the last test against what was drawn. 0: not read; 1: the first phase, kept only if\n"
         "// shown (and in the view; no occlusion test); 2: the second, every record tested against the\n"
         "// first phase's depth, shown = the result, kept only if it was not shown (the first drew it);\n"
         "// 3: a frame drawn without reuse, shown = kept.\n"
         "layout(std430, binding = 10) buffer qc_Shown { uint qc_shown[]; };\n"
         "uniform int qc_reuse;\n"
         "// With qc_list (qc_reuse 2 or 3): the new shown set's flags as the kept ones' (qc_keep2, qc_groups2),\n"
         "// for its list (the scan and compaction passes), which the next frame draws first without a cull pass.\n"
         "layout(std430, binding = 11) writeonly buffer qc_Keep2 { uint qc_keep2[]; };\n"
         "layout(std430, binding = 12) writeonly buffer qc_Groups2 { uint qc_groups2[]; };\n"
         "uniform bool qc_list;\n\n"
      << fns.str() << detail::depth_texels_glsl() << detail::pyramid_farthest_glsl(8, true)
      << "// Counts a culled record (0: outside the view, 1: behind the occluders); with reuse only in the\n"
         "// second phase, and only the records the first did not draw (`shown`). The invocation notes it\n"
         "// (qc_culled_as: 1 + what) and its workgroup's first adds the workgroup's counts: one atomic add\n"
         "// per workgroup, not per record, which llvmpipe's threads would contend for.\n"
         "uint qc_culled_as = 0u;\n"
         "shared uint qc_culled[64];\n"
         "void qc_count_culled(uint what, bool shown)\n{\n"
         "    if (qc_reuse == 1 || (qc_reuse == 2 && shown)) return;\n"
         "    qc_culled_as = what + 1u;\n"
         "}\n\n"
         "bool qc_kept(uint prim, bool shown)\n{\n"
         "    // The centre and bounding radius from the occluder list (the record's own floats, 2 vec4 per\n"
         "    // record): the sphere bound needs no more, and llvmpipe loads a storage buffer lane by lane,\n"
         "    // so the whole record (7 vec4) is read only for the ellipsoid and slab bounds (a program of\n"
         "    // its own: a branch on a uniform still runs its loads, masked, on llvmpipe).\n"
         "    vec3 c = qc_occluder[2u * prim].xyz;\n"
         "    float radius = qc_occluder[2u * prim + 1u].x;\n"
         "    float nearest;\n"
         "    qc_nearest_distance(qc_vz_row, qc_vz_t, c, radius, nearest);\n"
         "    if (qc_windowed && !((qc_window_first || nearest >= qc_window.x) && (qc_window_last || !(nearest >= qc_window.y)))) return false;  // another phase's\n"
         "    vec2 lo, hi;\n    bool tight, visible;\n"
         << (sphere_bound ? "    qc_primitive_rect_sphere(qc_view_projection, mat4(0.0), c, radius, vec3(0.0), 0.0, qc_viewport, lo, hi, tight, visible);\n"
                          : "    qc_Primitive p = qc_prims[prim];\n"
                            "    mat4 q = qc_record_quadric(p);\n"
                            "    if (qc_bound == 1)\n"
                            "        qc_primitive_rect_ellipsoid(qc_view_projection, q, c, radius, qc_record_axis(p), qc_record_half_length(p), qc_viewport, lo, hi, tight, visible);\n"
                            "    else\n"
                            "        qc_primitive_rect_slab(qc_view_projection, q, c, radius, qc_record_axis(p), qc_record_half_length(p), qc_viewport, lo, hi, tight, visible);\n")
         << 
         "    if (!visible) { qc_count_culled(0u, shown); return false; }  // entirely behind the eye plane\n"
         "    if (tight) {\n"
         "        vec4 span;\n"
         "        qc_pixel_span(lo, hi, qc_viewport, span);\n"
         "        if (span.x > span.z || span.y > span.w) { qc_count_culled(0u, shown); return false; }  // no pixel centre of the viewport\n"
         "        if (qc_occlusion && nearest > 0.0) {\n"
         "            if (qc_pyramid_behind(uvec4(span), floatBitsToUint(nearest))) { qc_count_culled(1u, shown); return false; }  // behind every occluder over its pixels\n"
         "        }\n"
         "    }\n"
         "    return true;\n"
         "}\n\n"
         "shared uint qc_flags[64];\nshared uint qc_flags2[64];\n\n"
         "void main()\n{\n"
         "    uint t = gl_LocalInvocationID.x;\n"
         "    uint group = qc_linear_group();\n"
         "    if (group >= (qc_count + 63u) / 64u) return;  // (a whole workgroup past the records: the dispatch's last row)\n"
         "    uint prim = qc_first + group * 64u + t;\n"
         "    bool inside = group * 64u + t < qc_count;\n"
         "    bool shown = inside && qc_reuse != 0 && qc_shown[prim] != 0u;\n"
         "    // (the first phase of a reuse tests only the shown records)\n"
         "    bool kept = inside && (qc_reuse != 1 || shown) && qc_kept(prim, shown);\n"
         "    if (inside && qc_reuse >= 2) qc_shown[prim] = kept ? 1u : 0u;\n"
         "    bool listed = kept && qc_reuse >= 2;\n"
         "    if (qc_reuse == 2) kept = kept && !shown;  // (the first phase drew it)\n"
         "    qc_culled[t] = qc_culled_as;\n"
      << detail::keep_flags_glsl("prim", true)
      << "    if (t == 0u) {  // (the barriers of the keep flags are behind every qc_culled write)\n"
         "        uint outside = 0u, behind = 0u;\n"
         "        for (uint r = 0u; r < 64u; ++r) {\n"
         "            outside += qc_culled[r] == 1u ? 1u : 0u;\n"
         "            behind += qc_culled[r] == 2u ? 1u : 0u;\n"
         "        }\n"
         "        if (outside != 0u) atomicAdd(qc_command[qc_stats_at], outside);\n"
         "        if (behind != 0u) atomicAdd(qc_command[qc_stats_at + 1u], behind);\n"
         "    }\n"
         "}\n";
    s.text = m.str();
    return s;
}

/// Occlusion pass 4, one workgroup per variant: the workgroup counts of the cull pass become
/// their first slots in the visible list (an exclusive prefix sum: each of the 64 invocations
/// sums a contiguous run of counts, then adds the runs before it), and the total the variant's
/// indirect draw command (6 indices per primitive).
const char* scan_shader =
    "layout(local_size_x = 64) in;\n\n"
    "layout(std430, binding = 5) buffer qc_Commands { uint qc_command[]; };\n"
    "layout(std430, binding = 7) buffer qc_Groups { uint qc_groups[]; };\n"
    "uniform uint qc_group_count;  // workgroups of the variant's cull pass\n"
    "uniform uint qc_command_at;   // the variant's command (uint offset)\n"
    "uniform uint qc_per_kept;     // what the command counts per kept record (6 indices of a quad; 1: records)\n\n"
    "shared uint qc_runs[64];\n\n"
    "void main()\n{\n"
    "    uint t = gl_LocalInvocationID.x;\n"
    "    uint per = (qc_group_count + 63u) / 64u;\n"
    "    uint begin = min(t * per, qc_group_count), end = min(begin + per, qc_group_count);\n"
    "    uint run = 0u;\n"
    "    for (uint g = begin; g < end; ++g) { uint n = qc_groups[g]; qc_groups[g] = run; run += n; }\n"
    "    qc_runs[t] = run;\n"
    "    barrier();\n"
    "    uint before = 0u;\n"
    "    for (uint r = 0u; r < t; ++r) before += qc_runs[r];\n"
    "    for (uint g = begin; g < end; ++g) qc_groups[g] += before;\n"
    "    if (t == 63u) qc_command[qc_command_at] = qc_per_kept * (before + run);\n"
    "}\n";

/// Occlusion pass 5, a workgroup per 64 records as in the cull pass: each kept record into the
/// visible list at its workgroup's first slot plus its slot in the workgroup (qc_keep - 1).
/// In record order, so that primitives at exactly the same depth in a pixel are drawn, and win the
/// depth test, in the order they are without the cull pass.
const std::string compact_shader = std::string(
    "layout(local_size_x = 64) in;\n\n"
    "layout(std430, binding = 4) writeonly buffer qc_Visible { uint qc_visible[]; };\n"
    "layout(std430, binding = 6) readonly buffer qc_Keep { uint qc_keep[]; };\n"
    "layout(std430, binding = 7) readonly buffer qc_Groups { uint qc_groups[]; };\n"
    "uniform uint qc_first;  // the variant's first record\n"
    "uniform uint qc_count;  // its records\n\n") + linear_group_glsl +
    "void main()\n{\n"
    "    uint group = qc_linear_group();\n"
    "    uint i = group * 64u + gl_LocalInvocationID.x;\n"
    "    if (i >= qc_count) return;\n"
    "    uint k = qc_keep[qc_first + i];\n"
    "    if (k != 0u) qc_visible[qc_first + qc_groups[group] + k - 1u] = qc_first + i;\n"
    "}\n";

/// The shown set from the picture (QuadricRenderer, RenderOptions::occlusion_reuse): the records
/// the primitives' pass left in the ids target (QuadricKey::ids: each pixel the record + 1 it shows,
/// 0 none) set their bits, one per record in 32-bit words (record r: bit r % 32 of word r / 32),
/// and their flags in the shown set's buffer (both cleared before). A pixel showing the record of
/// the pixel to its left adds nothing: one atomic OR per run of a record along a row.
Stage owners_shader() {
    Stage s;
    s.text =
        "layout(local_size_x = 8, local_size_y = 8) in;\n\n"
        "layout(binding = 0) uniform usampler2D qc_ids;  // per pixel the record it shows + 1 (0: none)\n"
        "layout(std430, binding = 10) writeonly buffer qc_Shown { uint qc_shown[]; };\n"
        "layout(std430, binding = 13) buffer qc_Bits { uint qc_bits[]; };\n"
        "uniform uvec2 qc_size;   // the viewport\n"
        "uniform uint qc_records;  // the renderer's records (larger ids are not read)\n\n"
        "void main()\n{\n"
        "    uvec2 p = gl_GlobalInvocationID.xy;\n"
        "    if (p.x >= qc_size.x || p.y >= qc_size.y) return;\n"
        "    uint id = texelFetch(qc_ids, ivec2(p), 0).r;\n"
        "    if (id == 0u || id > qc_records) return;\n"
        "    if (p.x > 0u && texelFetch(qc_ids, ivec2(p) - ivec2(1, 0), 0).r == id) return;  // (that pixel sets it)\n"
        "    uint r = id - 1u;\n"
        "    qc_shown[r] = 1u;\n"
        "    atomicOr(qc_bits[r >> 5u], 1u << (r & 31u));\n"
        "}\n";
    return s;
}

/// The bits of a variant's records [qc_first, qc_first + qc_count) in word i of its range (word
/// qc_first / 32 + i), for the count and the compaction of the shown set's list.
const char* owner_words_glsl =
    "layout(local_size_x = 64) in;\n\n"
    "layout(std430, binding = 13) readonly buffer qc_Bits { uint qc_bits[]; };\n"
    "uniform uint qc_first;  // the variant's first record\n"
    "uniform uint qc_count;  // its records\n"
    "uniform uint qc_words;  // the words its bits span (the host's count, also the scan pass's)\n\n"
    "uint qc_owner_word(uint i)\n{\n"
    "    uint w = (qc_first >> 5u) + i;\n"
    "    uint lo = max(qc_first, w << 5u) - (w << 5u), hi = min(qc_first + qc_count - (w << 5u), 32u);  // the variant's bits [lo, hi)\n"
    "    uint below_hi = hi == 32u ? 0xffffffffu : (1u << hi) - 1u;\n"
    "    return qc_bits[w] & below_hi & ~((1u << lo) - 1u);\n"
    "}\n\n";

/// Per word of a variant's range its shown records (into qc_groups, which the scan pass turns into
/// each word's first slot and the count into the variant's command).
Stage owner_count_shader() {
    Stage s;
    s.text = std::string(owner_words_glsl) + linear_group_glsl +
             "layout(std430, binding = 7) writeonly buffer qc_Groups { uint qc_groups[]; };\n\n"
             "void main()\n{\n"
             "    uint i = qc_linear_group() * 64u + gl_LocalInvocationID.x;\n"
             "    if (i >= qc_words) return;\n"
             "    qc_groups[i] = uint(bitCount(qc_owner_word(i)));\n"
             "}\n";
    return s;
}

/// Per word of a variant's range its shown records in order into the set's list, from the word's
/// first slot (the variant's records from list slot qc_first, as the visible list's).
Stage owner_compact_shader() {
    Stage s;
    s.text = std::string(owner_words_glsl) + linear_group_glsl +
             "layout(std430, binding = 4) writeonly buffer qc_List { uint qc_list[]; };\n"
             "layout(std430, binding = 7) readonly buffer qc_Groups { uint qc_groups[]; };\n\n"
             "void main()\n{\n"
             "    uint i = qc_linear_group() * 64u + gl_LocalInvocationID.x;\n"
             "    if (i >= qc_words) return;\n"
             "    uint bits = qc_owner_word(i);\n"
             "    uint slot = qc_first + qc_groups[i];\n"
             "    uint base = ((qc_first >> 5u) + i) << 5u;\n"
             "    while (bits != 0u) {\n"
             "        qc_list[slot++] = base + uint(findLSB(bits));\n"
             "        bits &= bits - 1u;\n"
             "    }\n"
             "}\n";
    return s;
}

/// Occlusion pass 6, the vertex stage's per-primitive work (OcclusionPass::bounds), one invocation
/// per slot of a variant's visible list (its count from the variant's indirect command): for the
/// primitive in the slot, what the vertex stage of its variant (`sphere`: the sphere-specialised
/// one) computes per primitive from the same traced kernels -- the clip positions of its four
/// corners (`bound_glsl`; the general stage's per-quadric culling, perspective cameras, moves a
/// culled primitive's corners off screen as that stage does) and its nearest view distance
/// (`nearest_distance`). Run on all threads for the kept primitives only, packed; the vertex stage
/// then fetches (`qc_fetch`).
Stage bounds_shader(bool sphere, bool ortho) {
    Stage s;
    std::ostringstream fns;
    const std::string proj = ortho ? "ortho" : "perspective";
    if (!sphere) {
        add_kernel(s, fns, "primitive_rect_ellipsoid");
        add_kernel(s, fns, "primitive_rect_slab");
        add_kernel(s, fns, "primitive_quad_slab");
        add_kernel(s, fns, "primitive_quad_tetra");
    }
    add_kernel(s, fns, "primitive_bound_" + proj);
    add_kernel(s, fns, "clip_position");
    if (!sphere && !ortho) add_kernel(s, fns, "primitive_cull");
    add_kernel(s, fns, "nearest_distance");
    std::ostringstream m;
    m << "layout(local_size_x = 64) in;\n\n" << record_glsl << (sphere ? "" : planes_glsl) << bound_uniforms
      << "layout(std430, binding = 4) readonly buffer qc_Visible { uint qc_visible[]; };\n"
         "layout(std430, binding = 5) readonly buffer qc_Commands { uint qc_command[]; };\n"
         "layout(std430, binding = 8) writeonly buffer qc_Corners { vec4 qc_corner[]; };     // 4 per slot\n"
         "layout(std430, binding = 9) writeonly buffer qc_Nearests { float qc_nearests[]; };  // 1 per slot\n"
         "uniform uint qc_command_at;  // the variant's command (uint offset): 6 indices per kept primitive\n";
    if (!sphere)
        m << "uniform bool qc_slab_quad;        // slab bounds: the quadrilateral along the axis, else the rectangle\n"
             "uniform vec3 qc_eye;\nuniform bool qc_cull;\nuniform bool qc_caps;   // the variant closes a slab with caps\n";
    m << "\n" << fns.str()
      << linear_group_glsl << "void main()\n{\n"
         "    uint i = qc_linear_group() * 64u + gl_LocalInvocationID.x;\n"
         "    if (i >= qc_command[qc_command_at] / 6u) return;\n"
         "    uint slot = qc_first + i;\n"
         "    uint prim = qc_visible[slot];\n"
         "    qc_Primitive p = qc_prims[prim];\n";
    if (!sphere) m << "    mat4 q = qc_record_quadric(p);\n";
    m << bound_glsl(proj, !sphere, true);
    if (!sphere && !ortho)
        m << "    bool culled = false, culled_caps = false;\n"
             "    if (qc_cull)\n"
             "        qc_primitive_cull(q, qc_record_center(p), qc_record_radius(p), qc_record_axis(p), qc_record_half_length(p), qc_eye, culled, culled_caps);\n"
             "    if (qc_cull && (qc_caps ? culled_caps : culled))\n"
             "        for (int k = 0; k < 4; ++k) clips[k] = vec4(2.0, 2.0, 2.0, 1.0);\n";
    m << "    float nearest;\n"
         "    qc_nearest_distance(qc_vz_row, qc_vz_t, qc_record_center(p), qc_record_radius(p), nearest);\n"
         "    for (int k = 0; k < 4; ++k) qc_corner[4u * slot + uint(k)] = clips[k];\n"
         "    qc_nearests[slot] = nearest;\n"
         "}\n";
    s.text = m.str();
    return s;
}

}  // namespace

namespace {

/// The deferred pass's outline tiles: per 8 x 8 tile of the image, whether the background program
/// can draw anything but the background colour there. Its outline at a pixel reads only the
/// geometry buffer's normal target over the 3 x 3 neighbourhood (clamped to the image), and where
/// all nine texels hold the cleared value (`is_cleared_gnormal`) it is zero (`silhouette_weight`:
/// equal depths, zero normals) and the colour the background. So a tile is listed (its
/// x | y << 16, in any order) when a texel it reaches (`outline_tile_reach`) is not cleared, and
/// its count goes into a DrawArraysIndirectCommand (count, 1, 0, 0; zeroed by the renderer).
Stage outline_tiles_shader() {
    Stage s;
    std::ostringstream fns;
    add_kernel(s, fns, "outline_tile_reach");
    add_kernel(s, fns, "is_cleared_gnormal");
    std::ostringstream m;
    m << "layout(local_size_x = 8, local_size_y = 8) in;\n\n"
         "layout(binding = 0) uniform sampler2D qc_gnormal;  // normal, window depth\n"
         "layout(std430, binding = 0) writeonly buffer qc_Tiles { uint qc_tile[]; };\n"
         "layout(std430, binding = 1) buffer qc_TileCommand { uint qc_tile_command[4]; };\n"
         "uniform uvec2 qc_size;  // the viewport\n\n"
      << fns.str()
      << "void main()\n{\n"
         "    uvec2 t = gl_GlobalInvocationID.xy;\n"
         "    if (t.x >= (qc_size.x + 7u) / 8u || t.y >= (qc_size.y + 7u) / 8u) return;\n"
         "    vec4 reach;\n"
         "    qc_outline_tile_reach(vec2(t), vec2(qc_size), reach);\n"
         "    ivec4 r = ivec4(reach);\n"
         "    bool geometry = false;\n"
         "    for (int y = r.y; y <= r.w && !geometry; ++y)\n"
         "        for (int x = r.x; x <= r.z; ++x) {\n"
         "            bool cleared;\n"
         "            qc_is_cleared_gnormal(texelFetch(qc_gnormal, ivec2(x, y), 0), cleared);\n"
         "            if (!cleared) {\n"
         "                geometry = true;\n"
         "                break;\n"
         "            }\n"
         "        }\n"
         "    if (geometry) qc_tile[atomicAdd(qc_tile_command[0], 1u)] = t.x | (t.y << 16);\n"
         "}\n";
    s.text = m.str();
    return s;
}

/// The shadow map in phases for the deferred pass's gathered PCF samples (DeferredKey::phases,
/// `pcf_phase`): each texel of an R32F image of step x step tiles, margins included, holds the
/// map texel of `phase_source_texel` per axis.
Stage shadow_phases_shader() {
    Stage s;
    std::ostringstream fns;
    add_kernel(s, fns, "phase_source_texel");
    std::ostringstream m;
    m << "layout(local_size_x = 8, local_size_y = 8) in;\n\n"
         "layout(binding = 0) uniform sampler2D qc_shadow_map;\n"
         "layout(r32f, binding = 0) writeonly uniform image2D qc_phases;\n"
         "uniform int qc_size;            // the phase image's texels per side\n"
         "uniform float qc_last;          // the map's last texel\n"
         "uniform float qc_pcf_step;      // texels between PCF samples\n"
         "uniform float qc_phase_tile;    // texels per side of a tile\n"
         "uniform float qc_phase_inv_tile;  // 1 / qc_phase_tile\n\n"
      << fns.str()
      << "void main()\n{\n"
         "    ivec2 p = ivec2(gl_GlobalInvocationID.xy);\n"
         "    if (p.x >= qc_size || p.y >= qc_size) return;\n"
         "    float x, y;\n"
         "    qc_phase_source_texel(float(p.x), qc_pcf_step, qc_phase_tile, qc_phase_inv_tile, qc_last, x);\n"
         "    qc_phase_source_texel(float(p.y), qc_pcf_step, qc_phase_tile, qc_phase_inv_tile, qc_last, y);\n"
         "    imageStore(qc_phases, p, vec4(texelFetch(qc_shadow_map, ivec2(x, y), 0).r));\n"
         "}\n";
    s.text = m.str();
    return s;
}

/// The compute stage of an occlusion pass.
StageText occlusion_stage(const render::OcclusionKey& k) {
    switch (k.pass) {
    case render::OcclusionPass::shadow_phases:
        return stage_text(StageText::Kind::compute, "qc_shadow_phases.comp", shadow_phases_shader(),
                          "deferred shading: the shadow map in phases of the PCF step, for gathered samples");
    case render::OcclusionPass::owners:
        return stage_text(StageText::Kind::compute, "qc_owners.comp", owners_shader(), "occlusion culling: the records the picture shows, into the shown set's bits");
    case render::OcclusionPass::owner_count:
        return stage_text(StageText::Kind::compute, "qc_owner_count.comp", owner_count_shader(), "occlusion culling: the shown records per word of the shown set's bits");
    case render::OcclusionPass::owner_compact:
        return stage_text(StageText::Kind::compute, "qc_owner_compact.comp", owner_compact_shader(), "occlusion culling: the shown records in order into the shown set's list");
    case render::OcclusionPass::outline_tiles:
        return stage_text(StageText::Kind::compute, "qc_outline_tiles.comp", outline_tiles_shader(),
                          "deferred shading: the 8 x 8 tiles where the background's outlines may differ from the background colour");
    case render::OcclusionPass::occluder_raster:
        break;  // (two stages: program_stages)
    case render::OcclusionPass::element_cull_cubes:
    case render::OcclusionPass::element_cull_tets:
    case render::OcclusionPass::element_cull_cells:
    case render::OcclusionPass::element_compact:
    case render::OcclusionPass::phase_compact:
        return element_list_stage(k.pass);
    case render::OcclusionPass::occluders:
        return stage_text(StageText::Kind::compute, "qc_occluders.comp", occluder_shader(), "occlusion culling: occluder disks into the depth image");
    case render::OcclusionPass::depth_image:
        return stage_text(StageText::Kind::compute, "qc_depth_image.comp", depth_image_shader(),
                          "occlusion culling, later phases: the depth buffer's view distances into the depth image");
    case render::OcclusionPass::pyramid:
        return stage_text(StageText::Kind::compute, "qc_depth_pyramid.comp", pyramid_shader(), "occlusion culling: one level of the max-depth pyramid");
    case render::OcclusionPass::scan: {
        Stage p;
        p.text = scan_shader;
        return stage_text(StageText::Kind::compute, "qc_cull_scan.comp", p, "occlusion culling: first slots of the cull pass's workgroups, the indirect draw counts");
    }
    case render::OcclusionPass::compact: {
        Stage p;
        p.text = compact_shader;
        return stage_text(StageText::Kind::compute, "qc_compact.comp", p, "occlusion culling: the kept records in order into the visible list");
    }
    case render::OcclusionPass::bounds: {
        const std::string proj = k.ortho ? "ortho" : "perspective";
        return stage_text(StageText::Kind::compute, std::string("qc_cull_bounds_") + (k.sphere ? "sphere_" : "quadric_") + proj + ".comp",
                          bounds_shader(k.sphere, k.ortho),
                          std::string("occlusion culling: per kept primitive the ") + (k.sphere ? "sphere variant's" : "general") +
                              " vertex stage's corners and nearest distance, " + proj + " camera");
    }
    case render::OcclusionPass::cull:
        break;
    }
    return stage_text(StageText::Kind::compute, k.sphere ? "qc_cull_sphere.comp" : "qc_cull.comp", cull_shader(k.sphere),
                      std::string("occlusion culling: the frustum and occlusion test of every record") + (k.sphere ? " (bounding-sphere rectangles)" : " (ellipsoid and slab rectangles)"));
}

}  // namespace

std::vector<StageText> program_stages(const render::OcclusionKey& k) {
    if (k.pass == render::OcclusionPass::occluder_raster) {
        Stage f;
        f.text = "void main()\n{\n}\n";
        return {stage_text(StageText::Kind::vertex, "qc_occluder_raster.vert", occluder_raster_shader(),
                           "occlusion culling: the occluders' quadrilaterals into the depth buffer (vertex stage)"),
                stage_text(StageText::Kind::fragment, "qc_occluder_raster.frag", f, "occlusion culling: the occluders' quadrilaterals (depth only)")};
    }
    return {occlusion_stage(k)};
}


std::vector<StageText> program_stages(const render::QuadricKey& key) {
    render::check(key);
    const render::QuadricKey k = render::canonical(key);
    const bool sphere = k.shape == FragmentShape::sphere;
    const std::string proj = k.ortho ? "ortho" : "perspective";
    std::vector<StageText> out;
    const bool planes = k.shape == FragmentShape::planes;
    if (k.reshade) {
        Stage v;
        v.text = detail::fullscreen_vertex;
        out.push_back(stage_text(StageText::Kind::vertex, "qc_fullscreen.vert", v, "quadric renderer: the sphere variant shaded from the ids target, a full-screen triangle"));
        const std::string variant = std::string("sphere") + (k.cull ? "" : "_nocull");
        out.push_back(stage_text(StageText::Kind::fragment, (k.gbuffer ? "qc_gbuffer_" : "qc_quadric_") + variant + (k.environment ? "_environment" : "") + "_reshade_" + proj + ".frag",
                                 fragment_shader(k), "quadric renderer: " + std::string(k.gbuffer ? "geometry-buffer " : "") + "fragment stage, " + variant +
                                                         " shaded from the ids target (QuadricKey::reshade), " + proj + " camera"));
        return out;
    }
    const std::string vname = (sphere ? (k.points ? "qc_sphere_points_" : "qc_sphere_") : planes ? "qc_quadric_planes_" : "qc_quadric_") + proj + ".vert";
    out.push_back(stage_text(StageText::Kind::vertex, vname, sphere ? sphere_vertex_shader(k.ortho, k.points) : vertex_shader(k.ortho, planes),
                             sphere   ? "quadric renderer: vertex stage of the sphere variant" + std::string(k.points ? " (point sprites)" : "") + ", " + proj + " camera"
                             : planes ? "quadric renderer: vertex stage of the planes variant, " + proj + " camera"
                                      : "quadric renderer: vertex stage, " + proj + " camera"));
    if (k.stage == render::FragmentStage::passthrough) {
        Stage p;
        p.text = passthrough_fragment;
        out.push_back(stage_text(StageText::Kind::fragment, "qc_passthrough.frag", p, "pass-through fragment stage (benchmark baseline: the rasteriser's fill rate)"));
        return out;
    }
    const std::string variant = std::string(render::shape_name(k.shape)) + (k.cull ? "" : "_nocull");
    std::string fname, summary;
    if (k.stage == render::FragmentStage::brute_force) {
        // Benchmark baseline (quadcast bench fragments), perspective camera, forward shading: the
        // pixel's ray from gl_FragCoord (`pixel_ray`), then `local_ray` and `cast` per fragment.
        fname = "qc_quadric_" + variant + "_brute_perspective.frag";
        summary = "quadric renderer: brute-force fragment stage (benchmark baseline), " + variant + ", perspective camera";
    } else if (k.gbuffer) {
        fname = "qc_gbuffer_" + variant + "_" + proj + ".frag";
        summary = "quadric renderer: geometry-buffer fragment stage (deferred shading), " + variant + ", " + proj + " camera";
    } else if (k.environment) {
        fname = "qc_quadric_" + variant + "_environment_" + proj + ".frag";
        summary = "quadric renderer: fragment stage with environment reflection, " + variant + ", " + proj + " camera";
    } else {
        fname = "qc_quadric_" + variant + "_" + proj + ".frag";
        summary = "quadric renderer: fragment stage, " + variant + ", " + proj + " camera";
    }
    out.push_back(stage_text(StageText::Kind::fragment, fname, fragment_shader(k), summary));
    return out;
}

/// The deferred background pass over the outline tiles: one point per listed tile, 8 pixels square
/// on it (`outline_tile_centre`: a partial tile at the image's right or top edge moves the point
/// inwards to keep its centre in the view, where GL clips points; it then also covers pixels of
/// the tile beside it, which the program draws the same way).
Stage outline_tile_vertex() {
    Stage s;
    std::ostringstream fns;
    add_kernel(s, fns, "outline_tile_centre");
    std::ostringstream m;
    m << "layout(std430, binding = 0) readonly buffer qc_Tiles { uint qc_tile[]; };\n"
         "uniform vec2 qc_viewport;\n\n"
      << fns.str()
      << "void main()\n{\n"
         "    uint t = qc_tile[gl_VertexID];\n"
         "    vec2 c;\n"
         "    qc_outline_tile_centre(vec2(float(t & 0xffffu), float(t >> 16)), qc_viewport, c);\n"
         "    gl_Position = vec4(c / qc_viewport * 2.0 - 1.0, 0.0, 1.0);\n"
         "    gl_PointSize = 8.0;\n"
         "}\n";
    s.text = m.str();
    return s;
}

std::vector<StageText> program_stages(const render::DeferredKey& k) {
    Stage v;
    if (k.tiles)
        v = outline_tile_vertex();
    else
        v.text = detail::fullscreen_vertex;
    if (k.background && (k.shadows || k.environment)) throw std::invalid_argument("quadcast::gl::program_stages: the deferred background pass has no shading");
    if (k.tiles && !(k.background && k.silhouettes)) throw std::invalid_argument("quadcast::gl::program_stages: only the deferred background pass with outlines is drawn over tiles");
    if (k.phases && !k.shadows) throw std::invalid_argument("quadcast::gl::program_stages: the shadow map's phases serve the soft shadows only");
    const std::string dname = std::string("qc_deferred") + (k.shadows ? "_shadows" : "") + (k.silhouettes ? "_silhouettes" : "") + (k.environment ? "_environment" : "") +
                              (k.background ? "_background" : "") + (k.phases ? "_phases" : "") + ".frag";
    return {k.tiles ? stage_text(StageText::Kind::vertex, "qc_outline_tiles.vert", v, "deferred shading: a point on each outline tile")
                    : stage_text(StageText::Kind::vertex, "qc_fullscreen.vert", v, "deferred shading: full-screen triangle"),
            stage_text(StageText::Kind::fragment, dname, deferred_shader(k.silhouettes, k.shadows, k.environment, k.background, k.phases),
                       std::string(k.background ? "deferred shading: the background's pixels" : "deferred shading: Blinn-Phong from the geometry buffer") + (k.shadows ? ", soft shadows (64-sample PCF, 8-sample early-out)" : "") + (k.phases ? ", gathered from the map's phases" : "") +
                           (k.silhouettes ? ", silhouette and crease outlines" : "") + (k.environment ? ", environment reflection" : ""))};
}

}  // namespace quadcast::gl

namespace quadcast::gl::detail {

std::string sphere_quad_glsl(const std::string& proj) {
    return std::string("        vec3 c0, c1, c2, c3;\n        bool valid;\n        qc_primitive_bound_") + proj +
           "(qc_view, qc_record_center(p), qc_record_radius(p), c0, c1, c2, c3, valid);\n"
           "        vec3 corners[4] = vec3[4](c0, c1, c2, c3);\n";
}

std::string bound_uniforms_glsl() { return bound_uniforms; }

const char* const fullscreen_vertex =
    "void main()\n{\n"
    "    vec2 p = vec2(float((gl_VertexID & 1) * 4 - 1), float((gl_VertexID & 2) * 2 - 1));\n"
    "    gl_Position = vec4(p, 0.0, 1.0);\n"
    "}\n";

}  // namespace quadcast::gl::detail
