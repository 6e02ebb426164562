// quadcast/render/types.hpp -- what both renderers (GL and CPU reference) take and give
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "quadcast/linalg.hpp"
#include "quadcast/raycast.hpp"

namespace quadcast::render {

/// The fragment-stage variant a primitive needs (a scene compiles only the variants it uses).
enum class Variant : std::uint8_t {
    ellipsoid,     ///< closed quadric, no clipping (ellipsoids):            CastOptions{cull, slab=false, bound=false}
    slab,          ///< slab closed by both caps (cylinders, cones):          CastOptions{cull, slab=true,  bound=false}
    open_slab,     ///< slab with an open end (open cylinders and cones): both sides are visible, so never culled,
                   ///< and each end is closed only where shape.caps says:  CastOptions{cull=false, slab=true}
    bounded,       ///< clipped to its bounding sphere (general quadrics):   CastOptions{cull, slab=false, bound=true}
    planes,        ///< clipped to four planes (bilinear quads, planar quads, tetrahedral patches)
    sphere,        ///< the sphere |x| = radius in closed form (CastOptions::sphere): no quadric coefficients, no g, a
};
inline constexpr int variant_count = 6;

/// The CastOptions of a variant (open slabs are two-sided whatever `cull` says).
constexpr CastOptions cast_options(Variant v, bool cull) {
    const bool slab = v == Variant::slab || v == Variant::open_slab;
    return CastOptions{cull && v != Variant::open_slab, slab, v == Variant::bounded, v == Variant::planes, v == Variant::sphere};
}

/// Name of a variant: ellipsoid, slab, open_slab, bounded, planes, sphere.
constexpr const char* variant_name(Variant v) {
    switch (v) {
    case Variant::ellipsoid: return "ellipsoid";
    case Variant::slab: return "slab";
    case Variant::open_slab: return "open_slab";
    case Variant::bounded: return "bounded";
    case Variant::planes: return "planes";
    case Variant::sphere: return "sphere";
    }
    return "?";
}

/// Blinn-Phong material of one primitive (`shade_blinn_phong`): specular in [0, 1] scales the
/// highlight, shininess > 0 is its exponent. Ambient and diffuse weights are the frame's
/// (RenderOptions::material[0], [1]).
struct Material {
    float specular = 0.35f;
    float shininess = 48.0f;
};

/// One primitive to draw, in float as the GPU stores it. Ellipsoid, bounded and sphere
/// primitives have shape.half_length = +Inf. Build them with quadcast/shapes.hpp, which
/// validates; `validate` (quadcast/render/validate.hpp) checks a hand-made one.
struct Primitive {
    ClippedQuadric<float> shape;
    Variant variant;
    Vec3<float> color;
    Material material;
};

/// A camera as both renderers use it. view: world -> view (rigid); projection: OpenGL clip
/// matrix; eye: world position (perspective) -- for an orthographic camera the rays start in
/// the plane z_view = 0 through `eye`.
struct Camera {
    Mat4<float> view;
    Mat4<float> projection;
    Vec3<float> eye;
    bool orthographic = false;
};

struct Light {
    Vec3<float> direction{{-1.0f, -1.0f, -1.0f}};  ///< towards the scene (as in the JSON scene); shading uses -direction
    Vec3<float> color{{1.0f, 1.0f, 1.0f}};
};

/// A latitude-longitude (equirectangular) environment image for reflections: width x height RGB
/// texels as floats (8-bit images as c / 255), row 0 = straight up, column 0 = azimuth -pi
/// (behind the viewer of a camera looking along -z), texel centres at half-integers
/// (`latlong_texel` in quadcast/shading.hpp). quadcast/render/environment.hpp makes one.
struct EnvironmentMap {
    int width = 0, height = 0;
    std::vector<float> rgb;  ///< 3 floats per texel, rows top first
};

struct RenderOptions {
    int width = 1024, height = 768;
    bool culling = true;                                  ///< per-fragment front-root selection + per-quadric culling
    /// Draw ellipsoids and (open) slabs over their tight screen rectangles (`primitive_rect`: the
    /// ellipsoid, the hull of a slab's two end sections) where that is safe; false: over the quad
    /// around the bounding sphere, as every other variant. The same image either way.
    bool tight_bounds = true;
    /// GL: a compute cull pass before each frame's primitive pass draws only the primitives that
    /// can show: those whose screen rectangle holds a pixel of the viewport and is not hidden
    /// behind the conservative occluders of closed convex primitives (quadcast/occlusion.hpp).
    /// The picture is the same either way; the CPU reference does not need it.
    bool occlusion_culling = true;
    /// GL, with occlusion_culling: the cull pass runs only in frames whose expected overlap
    /// (`expected_overlap` in quadcast/render/occluder.hpp: the pixels the primitives cover,
    /// summed, over the viewport's pixels) is at least this; below it the primitives rarely hide
    /// one another and the pass costs more than it saves. 0: always. Tetrahedral pieces drawn in
    /// phases (occlusion_phases) are always culled. The same picture either way.
    float occlusion_min_overlap = 3.0f;
    /// GL, with occlusion_culling: primitives clipped to four planes (tetrahedral pieces: skins,
    /// quadratic finite elements, isosurfaces as quadrics) are drawn in this many phases (1-8) by
    /// the nearest view distance of their bounding balls, nearest first, when each shows only
    /// inside its ball (`quadcast::planes_within_ball`; bilinear quads do not) and there are at
    /// least 4096 of them; the cull pass of each later phase takes the depth buffer the earlier
    /// phases wrote into its depth image, so that pieces and fragments behind what is drawn are
    /// skipped. So are the other primitives, in frames whose cull pass runs, when there are at
    /// least 4096 and at least half of them do not occlude with one disk (sticks, whose chains of
    /// disks are then not written; open cylinders, cones, general quadrics). 1: one phase, against
    /// the occluders only. The same picture.
    int occlusion_phases = 3;
    /// GL, with occlusion_culling, where frames repeat: a frame draws first the primitives that
    /// passed the last frame's test against what it drew (its shown set, per depth target: the
    /// camera's, the shadow map's), then tests every primitive against the depth those drew and
    /// draws the rest that pass; the results are the next frame's set. Not in frames drawn in
    /// phases, nor into a host's framebuffer (QuadricRenderer::draw_primitives). The camera may
    /// move between frames: the test runs against this frame's own depth. Where the view (camera,
    /// viewport, back-face culling, primitives) is the one the set was last tested under, against
    /// what the set before it drew, the frame draws the set alone: that test already kept every
    /// primitive that can show in this view (QuadricRenderer::set_skip_unchanged_view_test). The
    /// same picture.
    bool occlusion_reuse = true;
    Vec3<float> background{{1.0f, 1.0f, 1.0f}};
    /// Ambient and diffuse weights of every primitive's shading ([2], [3]: the specular and
    /// shininess of geometry without a Material of its own, e.g. meshes).
    Vec4<float> material{{0.15f, 0.85f, 0.35f, 48.0f}};
    /// Deferred shading (Sigg et al. 2006, sec. 4): the quadric pass writes a geometry buffer
    /// (normal, depth, ray direction, colour) and a full-screen pass shades each pixel once. Same
    /// image as forward shading. The GL renderer uses it whenever `silhouettes` is set too; the
    /// CPU reference shades once per pixel either way.
    bool deferred = false;
    /// Silhouette and crease outlines (`silhouette_weight`, `apply_outline` in quadcast/shading.hpp).
    bool silhouettes = false;
    Vec4<float> silhouette{{0.03f, 3.0f, 0.7f, 0.0f}};  ///< depth threshold, normal threshold, strength, unused
    /// Soft shadows (Sigg et al. 2006, sec. 4): a shadow map from an orthographic light camera
    /// fitted to the primitives' bounding spheres (`light_camera` in quadcast/render/cpu_renderer.hpp),
    /// filtered with 64-sample PCF after an 8-sample penumbra test (`pcf_soft_shadow`).
    bool shadows = false;
    int shadow_map_size = 2048;   ///< texels per side
    int pcf_step = 2;             ///< texels between PCF samples (footprint (7 step) x (7 step))
    float shadow_bias = 10.0f;    ///< depth bias in shadow-map texels (light window depth shadow_bias / shadow_map_size)
    /// GL: keep the shadow map across frames. Its light camera is fitted to the scene's bounds and
    /// the light's direction, not to the view, so a frame draws it again only when something it
    /// depends on changed: the light, the map's size, `culling` or `tight_bounds`, the primitives
    /// (QuadricRenderer::set_primitives and its other setters), the passes or a pass's revision
    /// (ScenePass::revision; a pass that does not track one makes every frame draw it). The camera
    /// may move. The same picture either way.
    bool shadow_map_reuse = true;
    /// Environment reflection (`reflect_environment` in quadcast/render/environment.hpp): the
    /// mirror direction of the view ray looks up this image (bilinear) and the result is mixed
    /// into the Blinn-Phong colour by `reflectivity`. None: no reflection.
    std::shared_ptr<const EnvironmentMap> environment;
    float reflectivity = 0.3f;    ///< in [0, 1]
};

/// A rendered frame: RGBA8 (top row first) and window depth (1 = background), same layout.
struct Image {
    int width = 0, height = 0;
    std::vector<std::uint8_t> rgba;
    std::vector<float> depth;
};

/// Statistics of a frame.
struct FrameStats {
    std::uint64_t primitives = 0, culled = 0, fragments = 0;
    std::uint64_t hits = 0;  ///< fragments whose cast hit within the depth range (before the depth test)
    std::uint64_t shown = 0;  ///< primitives the picture shows (nearest at one pixel or more)
};

}  // namespace quadcast::render
