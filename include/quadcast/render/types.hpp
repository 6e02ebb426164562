// quadcast/render/types.hpp -- what both renderers (GL and CPU reference) take and give
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "quadcast/linalg.hpp"
#include "quadcast/raycast.hpp"

namespace quadcast::render {

/// The fragment-stage variant a primitive needs (a scene compiles only the variants it uses).
enum class Variant : std::uint8_t {
    closed,        ///< closed quadric, no clipping (spheres, ellipsoids): CastOptions{cull, slab=false, bound=false}
    slab,          ///< slab with caps (cylinders, cones):                   CastOptions{cull, slab=true,  bound=false}
    bounded,       ///< clipped to its bounding sphere (general quadrics):   CastOptions{cull, slab=false, bound=true}
    planes,        ///< clipped to four planes (bilinear quads, planar quads, tetrahedral patches)
};
inline constexpr int variant_count = 4;

/// The CastOptions of a variant.
constexpr CastOptions cast_options(Variant v, bool cull) {
    return CastOptions{cull, v == Variant::slab, v == Variant::bounded, v == Variant::planes};
}

/// Kernel/shader name of a variant: closed, slab, bounded, planes.
constexpr const char* variant_name(Variant v) {
    return v == Variant::closed ? "closed" : v == Variant::slab ? "slab" : v == Variant::bounded ? "bounded" : "planes";
}

/// One primitive to draw, in float as the GPU stores it. Closed and bounded primitives have
/// shape.half_length = +Inf.
struct Primitive {
    QuadricPrimitive<float> shape;
    Variant variant;
    Vec3<float> color;
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
    Vec3<float> direction;  ///< towards the scene (as in the JSON scene); shading uses -direction
    Vec3<float> color{{1.0f, 1.0f, 1.0f}};
};

struct RenderOptions {
    int width = 1024, height = 768;
    bool culling = true;                                  ///< per-fragment front-root selection + per-quadric culling
    Vec3<float> background{{1.0f, 1.0f, 1.0f}};
    Vec4<float> material{{0.15f, 0.85f, 0.35f, 48.0f}};   ///< ambient, diffuse, specular, shininess
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
    /// filtered with 64-sample PCF after an 8-sample penumbra test (`pcf_first8`, `pcf_lit_fraction`).
    bool shadows = false;
    int shadow_map_size = 2048;   ///< texels per side
    int pcf_step = 2;             ///< texels between PCF samples (footprint (7 step) x (7 step))
    float shadow_bias = 10.0f;    ///< depth bias in shadow-map texels (light window depth shadow_bias / shadow_map_size)
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
};

}  // namespace quadcast::render
