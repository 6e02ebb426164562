// quadcast/render/variant_key.hpp -- the feature bits that name a shader variant (generator, GL renderers, tests)
#pragma once
// One typed key per pass instead of names parsed by prefix: the GL renderers ask for the program
// of a key, quadcast::gl::program_stages assembles its stages from the generated kernels, the
// kernel registry names the fragment kernels with `fragment_kernel_name`, and a test validates the
// stages of every key `all_*_keys` lists. Not GL-specific: no GL types here.

#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "quadcast/raycast.hpp"
#include "quadcast/render/types.hpp"

namespace quadcast::render {

/// Which reconstruction of the samples is rendered.
enum class VolumeScheme : std::uint8_t { qss, s31, trilinear };

/// "qss", "s31", "trilinear".
constexpr const char* volume_scheme_name(VolumeScheme s) {
    return s == VolumeScheme::qss ? "qss" : s == VolumeScheme::s31 ? "s31" : "trilinear";
}

/// The cast a quadric fragment stage does (quadcast::CastOptions without culling); open slabs use
/// the slab stages (their caps come from the record).
enum class FragmentShape : std::uint8_t { ellipsoid, slab, bounded, planes, sphere };
inline constexpr FragmentShape fragment_shapes[] = {FragmentShape::ellipsoid, FragmentShape::slab, FragmentShape::bounded,
                                                    FragmentShape::planes, FragmentShape::sphere};

/// "ellipsoid", "slab", "bounded", "planes", "sphere".
constexpr const char* shape_name(FragmentShape s) {
    switch (s) {
    case FragmentShape::ellipsoid: return "ellipsoid";
    case FragmentShape::slab: return "slab";
    case FragmentShape::bounded: return "bounded";
    case FragmentShape::planes: return "planes";
    case FragmentShape::sphere: return "sphere";
    }
    return "?";
}

constexpr FragmentShape fragment_shape(CastOptions o) {
    return o.sphere ? FragmentShape::sphere : o.planes ? FragmentShape::planes : o.slab ? FragmentShape::slab
         : o.bound ? FragmentShape::bounded : FragmentShape::ellipsoid;
}
constexpr FragmentShape fragment_shape(Variant v) { return fragment_shape(cast_options(v, true)); }

/// Name of the traced fragment kernel of a shape: fragment_<shape>[_nocull] (codegen/kernels);
/// every fragment stage (window ray or brute force) casts with it.
constexpr const char* fragment_kernel_name(FragmentShape s, bool cull) {
    switch (s) {
    case FragmentShape::ellipsoid: return cull ? "fragment_ellipsoid" : "fragment_ellipsoid_nocull";
    case FragmentShape::slab: return cull ? "fragment_slab" : "fragment_slab_nocull";
    case FragmentShape::bounded: return cull ? "fragment_bounded" : "fragment_bounded_nocull";
    case FragmentShape::planes: return cull ? "fragment_planes" : "fragment_planes_nocull";
    case FragmentShape::sphere: return cull ? "fragment_sphere" : "fragment_sphere_nocull";
    }
    return "?";
}
constexpr const char* fragment_kernel_name(CastOptions o) { return fragment_kernel_name(fragment_shape(o), o.cull); }

/// Which fragment stage the quadric pass uses: the pixel's ray from the frame's affine terms
/// (`window_ray`; `incremental`: the terms are computed once per frame, the fragment only adds
/// x dx + y dy), then `local_ray` and `cast`; brute force (the ray by unprojecting gl_FragCoord
/// with the inverse view-projection, `pixel_ray`; benchmark baseline, perspective camera, forward
/// shading, no sphere variant); or a pass-through stage (constant colour, rasterised depth: the
/// fill-rate ceiling).
enum class FragmentStage : std::uint8_t { incremental, brute_force, passthrough };

/// A program of the quadric pass.
struct QuadricKey {
    FragmentShape shape = FragmentShape::ellipsoid;
    bool cull = true;          ///< per-fragment (and, perspective, per-primitive) back-face culling
    bool ortho = false;        ///< orthographic camera
    bool gbuffer = false;      ///< write the geometry buffer of deferred shading instead of shading
    bool environment = false;  ///< forward shading mixes in the environment reflection
    FragmentStage stage = FragmentStage::incremental;
    /// The sphere variant drawn as point sprites, one vertex per sphere (QuadricRenderer, where
    /// `render::sphere_points_fit`), instead of quads of four.
    bool points = false;
    /// Counts the stage's fragments one by one (QuadricRenderer::set_count_fragments; a
    /// measurement, not for frames that are timed): an atomic add per fragment where it starts,
    /// where it passes the early discard against the occluder depth image, and where its ray hits.
    bool count = false;
    /// The stage first compares the primitive's nearest view distance with the cull pass's depth
    /// image at the pixel and discards behind it (QuadricRenderer::set_early_discard; frames that
    /// run the cull pass). Not the sphere variant, whose cast costs about what the test does.
    /// Without it the stage has no test at all: llvmpipe runs a test turned off by a uniform
    /// anyway, masked (1TII balls and sticks and 10k spheres were 3-10% slower with it).
    bool early = false;
    /// The stage also writes each pixel it covers the record's index + 1 (an R32UI target: location
    /// 1 forward, 3 into the geometry buffer), so that the depth test leaves in it the record each
    /// pixel shows (QuadricRenderer's shown set, OcclusionPass::owners). Not the pass-through stage.
    bool ids = false;
    /// The sphere variant shaded once per pixel from the ids target instead of drawn as sprites: a
    /// full-screen triangle whose fragment stage reads the record the pixel showed in the frame
    /// that wrote the ids (QuadricKey::ids), with the view unchanged since, and casts and shades it
    /// with the sprites' own code (QuadricRenderer::set_reshade; the same picture, one fragment per
    /// pixel, no vertex per sphere). Pixels showing no sphere discard after one read.
    bool reshade = false;
    friend constexpr bool operator==(const QuadricKey&, const QuadricKey&) = default;
};

/// The key of what a renderer asks for, with the bits that do not change the stages cleared: open
/// slabs are never culled, the geometry buffer and the benchmark stages do not shade (no
/// environment), the pass-through stage depends only on the vertex stage (sphere or not, camera).
constexpr QuadricKey canonical(QuadricKey k) {
    if (k.gbuffer || k.stage != FragmentStage::incremental) k.environment = false;
    if (k.shape != FragmentShape::sphere || k.stage == FragmentStage::brute_force) k.points = false;
    if (k.stage != FragmentStage::incremental) k.count = false;
    if (k.stage != FragmentStage::incremental || k.shape == FragmentShape::sphere) k.early = false;
    if (k.shape != FragmentShape::sphere || k.stage != FragmentStage::incremental) k.reshade = false;
    if (k.reshade) k.points = k.ids = false;
    if (k.stage == FragmentStage::passthrough) {
        k.ids = false;
        k.cull = true;
        if (k.shape != FragmentShape::sphere) k.shape = FragmentShape::ellipsoid;
    }
    return k;
}

constexpr QuadricKey quadric_key(Variant v, bool culling, bool ortho, bool gbuffer, bool environment,
                                 FragmentStage stage = FragmentStage::incremental, bool points = false, bool count = false, bool early = false,
                                 bool ids = false, bool reshade = false) {
    return canonical(QuadricKey{fragment_shape(v), cast_options(v, culling).cull, ortho, gbuffer, environment, stage, points, count, early, ids, reshade});
}

/// Throws std::invalid_argument naming why no stages exist for `k`.
inline void check(const QuadricKey& k) {
    if (k.stage == FragmentStage::incremental) return;
    const char* what = k.stage == FragmentStage::brute_force ? "the brute-force fragment stage" : "the pass-through fragment stage";
    if (k.gbuffer) throw std::invalid_argument(std::string(what) + " shades forward only (no geometry buffer)");
    if (k.stage == FragmentStage::brute_force && k.ortho) throw std::invalid_argument(std::string(what) + " needs a perspective camera");
    if (k.stage == FragmentStage::brute_force && k.shape == FragmentShape::sphere)
        throw std::invalid_argument(std::string(what) + " has no sphere variant (use Variant::ellipsoid)");
}

/// The deferred shading pass (Sigg et al. 2006, sec. 4).
struct DeferredKey {
    bool shadows = false;
    bool silhouettes = false;
    bool environment = false;
    /// The background's pixels only (the renderer selects them by the depth test): the background
    /// colour and, with `silhouettes`, the outlines; no shading (shadows and environment false).
    bool background = false;
    /// With `background` and `silhouettes`: drawn as one point per tile of the outline tiles'
    /// list (OcclusionPass::outline_tiles) instead of one full-screen triangle.
    bool tiles = false;
    /// With `shadows`: the penumbra's samples read four at a time (textureGather) from the shadow
    /// map's phases (OcclusionPass::shadow_phases, `pcf_phase`) where they all lie inside the map,
    /// one by one elsewhere; the same count.
    bool phases = false;
    friend constexpr bool operator==(const DeferredKey&, const DeferredKey&) = default;
};

/// A compute pass of occlusion culling (quadcast::gl::QuadricRenderer, quadcast/occlusion.hpp):
/// the occluders' disks into the depth image, one level of the max-depth pyramid, the cull test
/// of every record, the prefix sum of its workgroups' counts (and the indirect draw commands), or
/// the compaction of the kept records into the visible list, or (`bounds`, optional) for each
/// slot of the visible list what the vertex stage would compute per primitive (the clip positions
/// of its four corners and its nearest view distance, for the sphere-specialised vertex stage or
/// the general one, per camera), so that the vertex stage only fetches; or (`depth_image`, later
/// phases of phased drawing, and after `occluder_raster`) the depth buffer's view distances into
/// the depth image; or (`occluder_raster`, a vertex and a fragment stage) the occluders'
/// quadrilaterals drawn into the depth buffer by the rasteriser.
/// The isosurface renderer's GPU element list (IsosurfaceRenderer::ElementList::gpu) adds the
/// frustum test of every active cube (`element_cull_cubes`), of every relevant tetrahedron (by its
/// cube) or trilinear cell (`element_cull_tets`, `element_cull_cells`) and the copy of
/// the kept ones into the frame's element list (`element_compact`), around `scan`; its occlusion
/// culling the copy of a later phase's kept elements into the survivors' list (`phase_compact`).
/// The deferred pass lists the tiles of the image whose outlines may differ from the background
/// (`outline_tiles`; the background's pixels elsewhere keep the colour they are cleared to), and
/// its soft shadows read the shadow map in phases of the PCF step (`shadow_phases`,
/// DeferredKey::phases).
/// The quadric renderer's shown set is made from the picture (`owners`: the records the ids target
/// shows set their bits; `owner_count`: each word's bits in a variant's range; `owner_compact`:
/// those records in order into the set's list).
enum class OcclusionPass : std::uint8_t { occluders, pyramid, cull, scan, compact, bounds, depth_image, occluder_raster, element_cull_cubes, element_cull_tets, element_cull_cells, element_compact, phase_compact, outline_tiles, shadow_phases, owners, owner_count, owner_compact };
struct OcclusionKey {
    OcclusionPass pass = OcclusionPass::occluders;
    bool sphere = false;  ///< `bounds`: of the sphere-specialised vertex stage; `cull`: for the bounding sphere's rectangle (every bound but the ellipsoid and slab ones)
    bool ortho = false;   ///< `bounds`: orthographic camera
    friend constexpr bool operator==(const OcclusionKey&, const OcclusionKey&) = default;
};

/// A program of the isosurface pass; `precomputed` reads the coefficients the compute pre-pass
/// wrote (QSS and S31 only).
struct IsoKey {
    VolumeScheme scheme = VolumeScheme::qss;
    bool ortho = false;
    bool gbuffer = false;
    bool precomputed = false;
    friend constexpr bool operator==(const IsoKey&, const IsoKey&) = default;
};

inline void check(const IsoKey& k) {
    if (k.precomputed && k.scheme == VolumeScheme::trilinear)
        throw std::invalid_argument("trilinear cells have no precomputed coefficients");
}

/// A pass of the GL SLIM renderer (quadcast/gl/slim_renderer.hpp, Stoll et al. 2006, sec. 5.1.1):
/// the balls' pushed depth only (visibility), their weighted terms added into the float targets
/// (accumulate), or the full-screen division into the geometry buffer (resolve).
enum class SlimPass : std::uint8_t { visibility, accumulate, resolve };
struct SlimKey {
    SlimPass pass = SlimPass::visibility;
    bool cull = true;    ///< front root only (and per-quadric culling in the vertex stage)
    bool ortho = false;  ///< orthographic camera
    friend constexpr bool operator==(const SlimKey&, const SlimKey&) = default;
};

/// A unique, readable name of each key (program cache, error messages), e.g.
/// `quadric:slab_nocull:ortho:gbuffer`.
inline std::string key_name(const QuadricKey& k) {
    std::string s = std::string("quadric:") + shape_name(k.shape) + (k.cull ? "" : "_nocull") + (k.ortho ? ":ortho" : ":perspective");
    if (k.gbuffer) s += ":gbuffer";
    if (k.environment) s += ":environment";
    if (k.stage == FragmentStage::brute_force) s += ":brute";
    if (k.stage == FragmentStage::passthrough) s += ":passthrough";
    if (k.points) s += ":points";
    if (k.count) s += ":count";
    if (k.early) s += ":early";
    if (k.ids) s += ":ids";
    if (k.reshade) s += ":reshade";
    return s;
}
inline std::string key_name(const DeferredKey& k) {
    return std::string("deferred") + (k.shadows ? ":shadows" : "") + (k.silhouettes ? ":silhouettes" : "") + (k.environment ? ":environment" : "") +
           (k.background ? ":background" : "") + (k.tiles ? ":tiles" : "") + (k.phases ? ":phases" : "");
}
inline std::string key_name(const IsoKey& k) {
    return std::string("iso:") + volume_scheme_name(k.scheme) + (k.ortho ? ":ortho" : ":perspective") + (k.gbuffer ? ":gbuffer" : "") +
           (k.precomputed ? ":precomputed" : "");
}

inline std::string key_name(const OcclusionKey& k) {
    const char* pass = k.pass == OcclusionPass::occluders ? "occluders" : k.pass == OcclusionPass::pyramid ? "pyramid" : k.pass == OcclusionPass::cull ? "cull" : k.pass == OcclusionPass::scan ? "scan" : k.pass == OcclusionPass::compact ? "compact" : k.pass == OcclusionPass::depth_image ? "depth_image" : k.pass == OcclusionPass::occluder_raster ? "occluder_raster"
                     : k.pass == OcclusionPass::element_cull_cubes ? "element_cull_cubes" : k.pass == OcclusionPass::element_cull_tets ? "element_cull_tets" : k.pass == OcclusionPass::element_cull_cells ? "element_cull_cells"
                     : k.pass == OcclusionPass::element_compact ? "element_compact" : k.pass == OcclusionPass::phase_compact ? "phase_compact"
                     : k.pass == OcclusionPass::outline_tiles ? "outline_tiles" : k.pass == OcclusionPass::shadow_phases ? "shadow_phases"
                     : k.pass == OcclusionPass::owners ? "owners" : k.pass == OcclusionPass::owner_count ? "owner_count" : k.pass == OcclusionPass::owner_compact ? "owner_compact" : "bounds";
    if (k.pass == OcclusionPass::cull) return std::string("occlusion:") + pass + (k.sphere ? ":sphere" : ":ellipsoid_slab");
    if (k.pass != OcclusionPass::bounds) return std::string("occlusion:") + pass;
    return std::string("occlusion:") + pass + (k.sphere ? ":sphere" : ":quadric") + (k.ortho ? ":ortho" : ":perspective");
}

inline std::string key_name(const SlimKey& k) {
    const char* pass = k.pass == SlimPass::visibility ? "visibility" : k.pass == SlimPass::accumulate ? "accumulate" : "resolve";
    return std::string("slim:") + pass + (k.cull || k.pass == SlimPass::resolve ? "" : "_nocull") + (k.ortho ? ":ortho" : ":perspective");
}

/// Every SLIM key a renderer can ask for (the resolve pass does not cull: one key per camera).
inline std::vector<SlimKey> all_slim_keys() {
    std::vector<SlimKey> out;
    for (bool ortho : {false, true}) {
        for (SlimPass p : {SlimPass::visibility, SlimPass::accumulate})
            for (bool cull : {true, false}) out.push_back({p, cull, ortho});
        out.push_back({SlimPass::resolve, true, ortho});
    }
    return out;
}

/// Every occlusion key a renderer can ask for.
inline std::vector<OcclusionKey> all_occlusion_keys() {
    std::vector<OcclusionKey> out{{OcclusionPass::occluders}, {OcclusionPass::pyramid}, {OcclusionPass::cull, false}, {OcclusionPass::cull, true}, {OcclusionPass::scan}, {OcclusionPass::compact},
                                  {OcclusionPass::depth_image}, {OcclusionPass::occluder_raster},
                                  {OcclusionPass::element_cull_cubes}, {OcclusionPass::element_cull_tets}, {OcclusionPass::element_cull_cells}, {OcclusionPass::element_compact},
                                  {OcclusionPass::phase_compact}, {OcclusionPass::outline_tiles}, {OcclusionPass::shadow_phases},
                                  {OcclusionPass::owners}, {OcclusionPass::owner_count}, {OcclusionPass::owner_compact}};
    for (bool sphere : {false, true})
        for (bool ortho : {false, true}) out.push_back({OcclusionPass::bounds, sphere, ortho});
    return out;
}

/// Every canonical quadric key a renderer can ask for.
inline std::vector<QuadricKey> all_quadric_keys() {
    std::vector<QuadricKey> out;
    for (FragmentShape s : fragment_shapes)
        for (bool cull : {true, false})
            for (bool ortho : {false, true}) {
                out.push_back({s, cull, ortho, false, false});
                out.push_back({s, cull, ortho, false, true});
                out.push_back({s, cull, ortho, true, false});
                if (s == FragmentShape::sphere)
                    for (bool gbuffer : {false, true})
                        for (bool env : {false, true})
                            if (!(gbuffer && env)) {
                                out.push_back({s, cull, ortho, gbuffer, env, FragmentStage::incremental, true});
                                // (shaded from the ids target, QuadricKey::reshade; also counting)
                                out.push_back({s, cull, ortho, gbuffer, env, FragmentStage::incremental, false, false, false, false, true});
                                if (!env) out.push_back({s, cull, ortho, gbuffer, false, FragmentStage::incremental, false, true, false, false, true});
                            }
                if (!ortho && s != FragmentShape::sphere) out.push_back({s, cull, false, false, false, FragmentStage::brute_force});
                // (the counting stages of forward shading and of the geometry buffer; the stages with
                // the early discard, forward, with the environment, into the geometry buffer, counting)
                for (bool gbuffer : {false, true}) {
                    out.push_back({s, cull, ortho, gbuffer, false, FragmentStage::incremental, false, true});
                    if (s == FragmentShape::sphere) out.push_back({s, cull, ortho, gbuffer, false, FragmentStage::incremental, true, true});
                    if (s != FragmentShape::sphere) {
                        out.push_back({s, cull, ortho, gbuffer, false, FragmentStage::incremental, false, false, true});
                        out.push_back({s, cull, ortho, gbuffer, false, FragmentStage::incremental, false, true, true});
                        if (!gbuffer) out.push_back({s, cull, ortho, false, true, FragmentStage::incremental, false, false, true});
                    }
                }
            }
    for (bool ortho : {false, true})
        for (FragmentShape s : {FragmentShape::ellipsoid, FragmentShape::sphere}) {
            out.push_back({s, true, ortho, false, false, FragmentStage::passthrough});
            if (s == FragmentShape::sphere) out.push_back({s, true, ortho, false, false, FragmentStage::passthrough, true});
        }
    // (each stage but the pass-through one also writing the ids target)
    const std::size_t n = out.size();
    for (std::size_t i = 0; i < n; ++i)
        if (out[i].stage != FragmentStage::passthrough && !out[i].reshade) {
            QuadricKey k = out[i];
            k.ids = true;
            out.push_back(k);
        }
    return out;
}

inline std::vector<DeferredKey> all_deferred_keys() {
    std::vector<DeferredKey> out;
    for (bool env : {false, true})
        for (bool shadows : {false, true})
            for (bool sil : {false, true}) {
                out.push_back({shadows, sil, env, false});
                if (shadows) out.push_back({shadows, sil, env, false, false, true});
            }
    for (bool sil : {false, true}) out.push_back({false, sil, false, true});
    out.push_back({false, true, false, true, true});
    return out;
}

inline std::vector<IsoKey> all_iso_keys() {
    std::vector<IsoKey> out;
    for (VolumeScheme s : {VolumeScheme::qss, VolumeScheme::s31, VolumeScheme::trilinear})
        for (bool ortho : {false, true})
            for (bool gbuffer : {false, true})
                for (bool pre : {false, true})
                    if (!pre || s != VolumeScheme::trilinear) out.push_back({s, ortho, gbuffer, pre});
    return out;
}

}  // namespace quadcast::render
