// quadcast/render/cpu_renderer.hpp -- multi-threaded CPU reference renderer of quadric primitives (tile-binned ray casting)
#pragma once

// Host-only. The numbers come from the shared templates the GL stages are traced from
// (codegen/src/stages.cpp): `sphere_quad` bounds a primitive, `local_ray` builds the ray terms,
// `cull_sphere` culls per quadric, `cast_ray<cast_options(variant, culling)>` finds the hit,
// `window_depth` its depth and `shade_blinn_phong` its colour. What is written here is only the
// plumbing around them: pixel rays, screen tiles, a depth test, 8-bit conversion, threads.
//
// Where it differs from the GPU on purpose or by nature:
// - A primitive is bounded by a conservative pixel rectangle around its `sphere_quad` (widened
//   by 1/16 pixel) instead of the rasterised quad, intersected with its tight rectangle
//   (`primitive_pixels`: the same `primitive_rect` floats as the GL vertex stage, every pixel
//   centre in it); pixels outside the quad but inside the rectangle are cast too. Like the GPU
//   this assumes the clipped surface lies in the bounding sphere (true for every primitive the
//   scene builder makes) and that a slab's surface lies between its two sections (cylinders,
//   cones, one-sheet hyperboloids).
// - Rays are the same on both: `window_ray` of the frame's terms at the pixel centre.
// - Depth is kept in float (a GL depth buffer may be 24-bit); the depth test is GL_LESS against
//   a cleared depth of 1, first primitive (lowest index) wins ties.
// - Per-quadric culling is `cull_primitive` (`cull_primitive_with_caps` for the capped slab
//   variant; never for open slabs), the rule the GL vertex stage uses.

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "quadcast/bounds.hpp"
#include "quadcast/cull.hpp"
#include "quadcast/linalg.hpp"
#include "quadcast/quadric.hpp"
#include "quadcast/raycast.hpp"
#include "quadcast/render/environment.hpp"
#include "quadcast/render/light_camera.hpp"
#include "quadcast/render/types.hpp"
#include "quadcast/render/validate.hpp"
#include "quadcast/render/window_ray.hpp"
#include "quadcast/shading.hpp"

namespace quadcast::render {

/// Everything a frame derives from its camera once: the uniforms the GL stages get (view
/// rotation inverse, third view row, projection's depth terms) and, in double, the matrices
/// the CPU needs to unproject pixel centres and bound primitives.
struct FrameSetup {
    int width = 0, height = 0;
    bool orthographic = false;
    Vec3<float> eye;
    Mat3<float> view_rot_inv;   ///< R^T, R = upper-left 3x3 of the view matrix (world -> view rotation)
    Vec3<float> vz_row;         ///< third row of R (qc_vz_row)
    Vec4<float> pz;             ///< (P22, P32, P23, P33), P[col][row] naming as `window_depth` (qc_pz)
    Mat4<double> view;          ///< the view matrix in double
    Mat4<double> projection;    ///< the projection matrix in double
    Mat4<double> projection_inv;
    WindowRayTerms rays;        ///< the pixel rays (`window_ray`; qc_ray_* of the GL fragment stage)
    Mat4<float> view_projection;  ///< `primitive_rect`'s world -> clip matrix (qc_view_projection)
};

/// A pixel's world-space ray as the GPU's vertex stage builds it at a quad corner.
struct PixelRay {
    Vec3<float> origin;
    Vec3<float> dir;
};

/// A closed pixel rectangle [x0, x1] x [y0, y1] in window coordinates (y up); empty if x0 > x1.
struct PixelRect {
    int x0 = 0, y0 = 0, x1 = -1, y1 = -1;
};

/// One primitive cast at one pixel ray: the fragment stage's outputs (hit already includes
/// 0 <= depth <= 1; normal unnormalised, outward).
struct Fragment {
    bool hit = false;
    float depth = 1.0f;
    Vec3<float> normal;
};

namespace cpu_detail {

using render::detail::inverse4;

/// The pixel index range whose centres (i + 0.5) lie in the window interval [lo, hi] widened
/// by 1/16 pixel plus 1e-5 of its length (far more than the rounding of a float cast near a
/// silhouette), clamped to [0, n - 1].
inline void pixel_span(double lo, double hi, int n, int& i0, int& i1) {
    const double pad = 0.0625 + 1e-5 * (hi - lo);
    lo = std::clamp(lo - pad, -4.0, double(n) + 4.0);
    hi = std::clamp(hi + pad, -4.0, double(n) + 4.0);
    i0 = std::max(0, static_cast<int>(std::ceil(lo - 0.5)));
    i1 = std::min(n - 1, static_cast<int>(std::floor(hi - 0.5)));
}

/// 8-bit UNORM conversion as a GL framebuffer does it: round to nearest of clamp(c, 0, 1) * 255
/// (NaN gives 0).
inline std::uint8_t to_unorm8(float c) {
    if (!(c > 0.0f)) return 0;
    if (c >= 1.0f) return 255;
    return static_cast<std::uint8_t>(c * 255.0f + 0.5f);
}

/// `cast_and_depth` of one variant at one pixel ray, as the GL fragment stage computes it.
template <CastOptions Opt>
Fragment cast_variant(const ClippedQuadric<float>& p, const PixelRay& ray, const FrameSetup& f) {
    const FragmentHit<float> h = cast_and_depth<Opt>(p, local_ray(p, ray.origin, ray.dir), f.vz_row, f.pz);
    return {h.hit, h.depth, h.normal};
}

/// Calls fn.template operator()<cast_options(v, cull)>() for the runtime variant v. Every
/// variant below `variant_count` is instantiated, so a new variant needs no change here.
template <int I = 0, class Fn>
auto dispatch_variant(Variant v, bool cull, Fn&& fn) {
    if constexpr (I + 1 < variant_count) {
        if (v != static_cast<Variant>(I)) return dispatch_variant<I + 1>(v, cull, fn);
    }
    return cull ? fn.template operator()<cast_options(static_cast<Variant>(I), true)>()
                : fn.template operator()<cast_options(static_cast<Variant>(I), false)>();
}

}  // namespace cpu_detail

/// The frame constants of a camera for a width x height image.
/// Throws std::invalid_argument for an empty image, a non-finite camera or a singular projection.
inline FrameSetup frame_setup(const Camera& camera, int width, int height) {
    if (width <= 0 || height <= 0) throw std::invalid_argument("quadcast::render: image size must be positive");
    for (int j = 0; j < 4; ++j)
        for (int i = 0; i < 4; ++i)
            if (!std::isfinite(camera.view[j][i]) || !std::isfinite(camera.projection[j][i]))
                throw std::invalid_argument("quadcast::render: camera matrix is not finite");
    for (int i = 0; i < 3; ++i)
        if (!std::isfinite(camera.eye[i])) throw std::invalid_argument("quadcast::render: camera eye is not finite");
    FrameSetup f;
    f.width = width;
    f.height = height;
    f.orthographic = camera.orthographic;
    f.eye = camera.eye;
    f.view_rot_inv = transpose(upper3(camera.view));
    f.vz_row = row(upper3(camera.view), 2);
    f.pz = vec4(camera.projection[2][2], camera.projection[3][2], camera.projection[2][3], camera.projection[3][3]);
    f.view = cast<double>(camera.view);
    f.projection = cast<double>(camera.projection);
    f.projection_inv = cpu_detail::inverse4(f.projection);
    f.rays = window_ray_terms(camera, width, height);
    f.view_projection = render::view_projection(camera);
    return f;
}

/// The ray of the pixel whose centre is (x + 0.5, y + 0.5) in WINDOW coordinates (y = 0 is the
/// bottom row), as the GPU's fragment stage builds it (`fragment_ray_*`): `window_ray` of the
/// frame's terms (`window_ray_terms`) at the pixel centre, in float.
inline PixelRay pixel_ray(const FrameSetup& f, int x, int y) {
    const Vec2<float> frag = vec2(float(x) + 0.5f, float(y) + 0.5f);
    const WindowRayTerms& t = f.rays;
    const WorldRay<float> r = f.orthographic ? window_ray<true>(t.base, t.dx, t.dy, t.fixed, frag) : window_ray<false>(t.base, t.dx, t.dy, t.fixed, frag);
    return {r.origin, r.dir};
}

/// The fragment stage for one primitive at one pixel ray: `cast_ray` of the primitive's variant
/// (front root only when `culling`), `window_depth`, hit = hit && 0 <= depth <= 1.
/// (Per-quadric culling is not applied here; see `culled`.)
inline Fragment cast_fragment(const Primitive& p, const PixelRay& ray, const FrameSetup& f, bool culling) {
    return cpu_detail::dispatch_variant(p.variant, culling, [&]<CastOptions Opt>() {
        return cpu_detail::cast_variant<Opt>(p.shape, ray, f);
    });
}

/// Per-quadric back-face culling as the GPU's vertex stage does it: perspective cameras only,
/// `cull_sphere(q, o, 0, radius)` with the local eye o = eye - center (`local_ray`'s o).
/// Not for the `slab` variant: `cull_sphere` tests the quadric alone, but a slab's caps can
/// face the eye when its wall does not (a cylinder seen end-on from inside its infinite
/// extension would vanish). Not for the `sphere` variant either, as its vertex stage: from outside
/// a sphere shows its front, from inside the fragment stage finds no front root. Never for an
/// `open_slab`, whose inside shows through its open ends.
inline bool culled(const Primitive& p, const FrameSetup& f) {
    if (f.orthographic || p.variant == Variant::sphere || p.variant == Variant::open_slab) return false;
    const LocalRay<float> r = local_ray(p.shape, f.eye, vec3(0.0f, 0.0f, -1.0f));
    return p.variant == Variant::slab ? cull_primitive_with_caps(p.shape, r.o) : cull_primitive(p.shape, r.o);
}

/// The Blinn-Phong material vector of a primitive: the frame's ambient and diffuse weights, the
/// primitive's specular and shininess (what the GL stages assemble from the record).
inline Vec4<float> shading_material(const Primitive& p, const RenderOptions& options) {
    return vec4(options.material[0], options.material[1], p.material.specular, p.material.shininess);
}

/// The RGBA8 of a fragment: `shade_blinn_phong(n, -light.direction, -dir, color, light.color,
/// shading_material(p, options))`, with options.environment its `reflect_environment(..., n, -dir,
/// reflectivity)`, converted as a GL UNORM8 framebuffer does, alpha 255.
inline void shade_pixel(const Primitive& p, const Vec3<float>& normal, const Vec3<float>& dir, const Light& light,
                        const RenderOptions& options, std::uint8_t* rgba) {
    Vec3<float> c = shade_blinn_phong(normal, -light.direction, -dir, p.color, light.color, shading_material(p, options));
    if (options.environment) c = reflect_environment(*options.environment, c, normal, -dir, options.reflectivity);
    for (int i = 0; i < 3; ++i) rgba[i] = cpu_detail::to_unorm8(c[i]);
    rgba[3] = 255;
}

/// Window-pixel rectangle that contains every pixel whose ray can hit the primitive's bounding
/// sphere, or an empty one when no hit can survive (off screen, behind the eye, outside the
/// depth range). Host-side, in double: `sphere_quad` of the view-space centre (`ortho_sphere_square`
/// for orthographic cameras), grown as the GPU's bounding quad (`rasterised_sphere_quad`), its corners projected by P,
/// widened by 1/16 pixel (`pixel_span`); the full screen when the eye is inside the sphere or
/// a corner lies on or behind the eye plane.
inline PixelRect screen_rect(const ClippedQuadric<float>& p, const FrameSetup& f) {
    using namespace cpu_detail;
    PixelRect empty;
    const double r = static_cast<double>(p.radius);
    if (!(r > 0) || !std::isfinite(r) || !std::isfinite(p.center[0]) || !std::isfinite(p.center[1]) ||
        !std::isfinite(p.center[2]))
        return empty;
    const Vec3<double> c = xyz(f.view * vec4(double(p.center[0]), double(p.center[1]), double(p.center[2]), 1.0));
    // Behind the eye plane (rays go to view z < 0 from z = 0): nothing to hit
    if (!f.orthographic && c[2] - r > 0) return empty;
    // Entirely outside the depth range [0, 1] (depth is monotonic in z between its poles)
    {
        const Vec4<double> pz = vec4(f.projection[2][2], f.projection[3][2], f.projection[2][3], f.projection[3][3]);
        const double z0 = c[2] - r, z1 = c[2] + r;
        const double w0 = pz[2] * z0 + pz[3], w1 = pz[2] * z1 + pz[3];
        if ((w0 > 0 && w1 > 0) || (w0 < 0 && w1 < 0)) {
            const double d0 = window_depth(1.0, z0, pz), d1 = window_depth(1.0, z1, pz);
            const double margin = 1e-4;
            if ((d0 < -margin && d1 < -margin) || (d0 > 1 + margin && d1 > 1 + margin)) return empty;
        }
    }
    // Bound the sphere by its quad and project the corners
    Vec3<double> corner[4];
    bool full = false;
    const SphereQuad<double> sq = rasterised_sphere_quad(f.orthographic ? ortho_sphere_square(c, r) : sphere_quad(c, r), c);
    full = !sq.valid;
    for (int i = 0; i < 4; ++i) corner[i] = sq.corner[i];
    double lo[2] = {1e300, 1e300}, hi[2] = {-1e300, -1e300};
    for (int i = 0; i < 4 && !full; ++i) {
        const Vec4<double> h = clip_position(f.projection, corner[i]);
        if (!(h[3] > 0) || !std::isfinite(h[0]) || !std::isfinite(h[1])) {
            full = true;
            break;
        }
        for (int k = 0; k < 2; ++k) {
            const double ndc = h[k] / h[3];
            lo[k] = std::min(lo[k], ndc);
            hi[k] = std::max(hi[k], ndc);
        }
    }
    // Turn NDC into a pixel rectangle
    PixelRect rect;
    if (full) return PixelRect{0, 0, f.width - 1, f.height - 1};
    pixel_span((lo[0] + 1) * (0.5 * f.width), (hi[0] + 1) * (0.5 * f.width), f.width, rect.x0, rect.x1);
    pixel_span((lo[1] + 1) * (0.5 * f.height), (hi[1] + 1) * (0.5 * f.height), f.height, rect.y0, rect.y1);
    if (rect.x0 > rect.x1 || rect.y0 > rect.y1) return empty;
    return rect;
}

/// The pixels of an NDC rectangle: those whose centres (i + 0.5) lie in the closed window
/// rectangle (a superset of what a rasteriser fills), clamped to the image.
inline PixelRect ndc_pixels(const Vec2<float>& lo, const Vec2<float>& hi, const FrameSetup& f) {
    PixelRect r;
    const int n[2] = {f.width, f.height};
    int* i0[2] = {&r.x0, &r.y0};
    int* i1[2] = {&r.x1, &r.y1};
    for (int k = 0; k < 2; ++k) {
        const double a = std::clamp((double(lo[k]) + 1.0) * (0.5 * n[k]), -4.0, n[k] + 4.0);
        const double b = std::clamp((double(hi[k]) + 1.0) * (0.5 * n[k]), -4.0, n[k] + 4.0);
        *i0[k] = std::max(0, static_cast<int>(std::ceil(a - 0.5)));
        *i1[k] = std::min(n[k] - 1, static_cast<int>(std::floor(b - 0.5)));
    }
    if (r.x0 > r.x1 || r.y0 > r.y1) return PixelRect{};
    return r;
}

/// The rectangle around a `ScreenQuad`'s corners (the CPU reference draws rectangles; the GL
/// vertex stage the quadrilateral itself).
inline ScreenRect<float> quad_rect(const ScreenQuad<float>& q) {
    ScreenRect<float> r{};
    r.lo = r.hi = q.corner[0];
    for (int i = 1; i < 4; ++i)
        for (int k = 0; k < 2; ++k) {
            r.lo[k] = std::min(r.lo[k], q.corner[i][k]);
            r.hi[k] = std::max(r.hi[k], q.corner[i][k]);
        }
    r.tight = q.tight;
    r.visible = q.visible;
    return r;
}

/// The pixels of `sphere` (a `screen_rect`) within a primitive's tighter rectangle `r`: all of them
/// where `r` is not tight, none where it is not visible, else the intersection with `ndc_pixels(r)`.
inline PixelRect within_rect(const PixelRect& sphere, const ScreenRect<float>& r, const FrameSetup& f) {
    if (!r.tight) return sphere;
    if (!r.visible) return PixelRect{};
    const PixelRect t = ndc_pixels(r.lo, r.hi, f);
    const PixelRect both{std::max(t.x0, sphere.x0), std::max(t.y0, sphere.y0), std::min(t.x1, sphere.x1), std::min(t.y1, sphere.y1)};
    if (both.x0 > both.x1 || both.y0 > both.y1) return PixelRect{};
    return both;
}

/// The pixels the renderers draw a primitive over: `screen_rect` (the bounding sphere's quad,
/// with the early-outs behind the eye and outside the depth range), and with `tight` for the
/// ellipsoid and slab variants its intersection with the primitive's rectangle (`primitive_rect`
/// of `rect_bound(variant)`, the floats the GL vertex stage computes), for the planes variant with
/// the rectangle around its tetrahedron's quadrilateral (`tetra_quad`), where that is tight
/// (empty where it is not visible).
inline PixelRect primitive_pixels(const Primitive& p, const FrameSetup& f, bool tight) {
    const PixelRect sphere = screen_rect(p.shape, f);
    if (!tight || sphere.x0 > sphere.x1 || rect_bound(p.variant) == RectBound::sphere) return sphere;
    const ClippedQuadric<float>& s = p.shape;
    const Vec2<float> viewport = vec2(float(f.width), float(f.height));
    ScreenRect<float> r{};
    switch (rect_bound(p.variant)) {
    case RectBound::sphere: return sphere;
    case RectBound::ellipsoid: r = primitive_rect<RectBound::ellipsoid>(f.view_projection, s.q, s.center, s.radius, s.axis, s.half_length, viewport); break;
    case RectBound::slab: r = primitive_rect<RectBound::slab>(f.view_projection, s.q, s.center, s.radius, s.axis, s.half_length, viewport); break;
    case RectBound::tetrahedron: r = quad_rect(tetra_quad(f.view_projection, s.planes, s.center, viewport)); break;
    }
    return within_rect(sphere, r, f);
}

namespace cpu_detail {

/// A shadow map (window depth from `light_camera`, rows top first) and what a lookup needs.
struct ShadowLookup {
    std::vector<float> map;
    int size = 0, step = 2;
    float bias = 0.0f;
    Mat4<float> to_light;
    Vec2<float> viewport;
};

/// Soft-shadow visibility of the surface at window position (fx, fy) and depth d, as the GL
/// deferred pass computes it: `shadow_coord`, the 64 texels of `pcf_sample_texel` (grid cells in
/// `pcf_grid_order`), `pcf_soft_shadow` (the first 8, then all 64 if they disagree).
inline float shadow_visibility(const ShadowLookup& sh, float fx, float fy, float d) {
    const ShadowCoord<float> c = shadow_coord(vec2(fx, fy), d, sh.viewport, sh.to_light, static_cast<float>(sh.size));
    float smp[64];
    for (int k = 0; k < 64; ++k) {
        const Vec2<float> t = pcf_sample_texel(c.texel, static_cast<float>(pcf_grid_order[k]), static_cast<float>(sh.step),
                                               static_cast<float>(sh.size - 1));
        const int x = static_cast<int>(t[0]), y = static_cast<int>(t[1]);
        smp[k] = sh.map[std::size_t(sh.size - 1 - y) * sh.size + x];
    }
    return pcf_soft_shadow(c.z, sh.bias, smp);
}

inline constexpr int tile_size = 16;

/// Per-thread state of the tile loop.
struct TileScratch {
    PixelRay ray[tile_size * tile_size];
    float depth[tile_size * tile_size];
    std::int32_t prim[tile_size * tile_size];
    Vec3<float> normal[tile_size * tile_size];
    std::uint64_t fragments = 0, hits = 0;
    std::vector<std::int32_t> winners;  ///< with stats: the primitives nearest at the thread's pixels (runs along rows once)
};

/// Casts primitive `index` at the pixels of `r` (clipped to the tile at (tx0, ty0)) and keeps
/// the nearest hit per pixel (GL_LESS).
template <CastOptions Opt>
void cast_rect(const Primitive& p, std::int32_t index, const PixelRect& r, int tx0, int ty0, const FrameSetup& f,
               TileScratch& s) {
    for (int y = r.y0; y <= r.y1; ++y) {
        for (int x = r.x0; x <= r.x1; ++x) {
            const int k = (y - ty0) * tile_size + (x - tx0);
            const Fragment frag = cast_variant<Opt>(p.shape, s.ray[k], f);
            ++s.fragments;
            if (!frag.hit) continue;
            ++s.hits;
            if (frag.depth < s.depth[k]) {
                s.depth[k] = frag.depth;
                s.prim[k] = index;
                s.normal[k] = frag.normal;
            }
        }
    }
}

/// Runs fn(i) for i in [0, n) on `threads` threads taking indices from a shared counter.
template <class Fn>
void parallel_for(int n, int threads, Fn&& fn) {
    threads = std::max(1, std::min(threads, n));
    std::atomic<int> next{0};
    auto work = [&](int t) {
        for (int i = next.fetch_add(1); i < n; i = next.fetch_add(1)) fn(i, t);
    };
    if (threads == 1) {
        work(0);
        return;
    }
    std::vector<std::thread> pool;
    pool.reserve(threads - 1);
    for (int t = 1; t < threads; ++t) pool.emplace_back(work, t);
    work(0);
    for (std::thread& th : pool) th.join();
}

}  // namespace cpu_detail

/// Renders the primitives with the CPU, pixel for pixel what the GL stages compute
/// (codegen/src/stages.cpp) up to the rounding of the ray set-up (see the top of this file):
/// per primitive (perspective, options.culling) `culled` skips it; per pixel centre the ray of
/// `pixel_ray`, per primitive whose screen rectangle covers the pixel `cast_fragment`, the
/// nearest hit with 0 <= depth <= 1 and depth < 1 wins (lowest index on ties) and is shaded by
/// `shade_pixel`; elsewhere the background colour (alpha 255) and depth 1.
/// Primitives are binned into 16x16 tiles by `screen_rect`; `threads` threads (0: the
/// hardware concurrency) take tiles. Rows of the result are top first (row 0 = window y =
/// height - 1). Throws std::invalid_argument for a bad image size or camera.
/// options.silhouettes: the colours stay float and a post-pass blends the outline of
/// `silhouette_weight` over the 3x3 neighbourhood of depths and normals (clamped at the border;
/// background pixels have depth 1 and normal 0), as the GL deferred pass does; options.deferred
/// changes nothing here (every pixel is shaded once anyway). options.environment: the reflection
/// is mixed into the shaded colour (before the outline), as both GL paths do.
/// FrameStats: primitives = input count, culled = per-quadric culled, fragments = cast() calls,
/// hits = casts with a hit in the depth range (before the depth test). Throws like `validate` for a
/// primitive that cannot be drawn as it says.
inline Image render_cpu(const std::vector<Primitive>& prims, const Camera& camera, const Light& light,
                        const RenderOptions& options, FrameStats* stats = nullptr, int threads = 0);

namespace cpu_detail {

/// `render_cpu` of primitives that `validate_primitives` accepted (the shadow pass renders the
/// same primitives again without checking them twice).
inline Image render_validated(const std::vector<Primitive>& prims, const Camera& camera, const Light& light,
                              const RenderOptions& options, FrameStats* stats, int threads) {
    const FrameSetup f = frame_setup(camera, options.width, options.height);
    if (threads <= 0) threads = std::max(1u, std::thread::hardware_concurrency());
    const int n = static_cast<int>(prims.size());
    const int tiles_x = (f.width + tile_size - 1) / tile_size, tiles_y = (f.height + tile_size - 1) / tile_size;
    const int n_tiles = tiles_x * tiles_y;

    // Bound and cull every primitive
    std::vector<PixelRect> rects(prims.size());
    std::vector<std::uint8_t> is_culled(prims.size(), 0);
    constexpr int chunk = 1024;
    parallel_for((n + chunk - 1) / chunk, threads, [&](int c, int) {
        for (int i = c * chunk; i < std::min(n, (c + 1) * chunk); ++i) {
            if (options.culling && culled(prims[i], f)) {
                is_culled[i] = 1;
                continue;
            }
            rects[i] = primitive_pixels(prims[i], f, options.tight_bounds);
        }
    });

    // Bin them into tiles (counting sort: each tile's list is in primitive order)
    std::vector<std::uint32_t> offsets(n_tiles + 1, 0);
    auto for_tiles = [&](const PixelRect& r, auto&& fn) {
        if (r.x0 > r.x1) return;
        for (int ty = r.y0 / tile_size; ty <= r.y1 / tile_size; ++ty)
            for (int tx = r.x0 / tile_size; tx <= r.x1 / tile_size; ++tx) fn(ty * tiles_x + tx);
    };
    for (int i = 0; i < n; ++i) for_tiles(rects[i], [&](int t) { ++offsets[t + 1]; });
    for (int t = 0; t < n_tiles; ++t) offsets[t + 1] += offsets[t];
    std::vector<std::uint32_t> items(offsets[n_tiles]);
    {
        std::vector<std::uint32_t> fill(offsets.begin(), offsets.end() - 1);
        for (int i = 0; i < n; ++i) for_tiles(rects[i], [&](int t) { items[fill[t]++] = static_cast<std::uint32_t>(i); });
    }

    // Render the tiles
    Image img;
    img.width = f.width;
    img.height = f.height;
    img.rgba.assign(std::size_t(f.width) * f.height * 4, 0);
    img.depth.assign(std::size_t(f.width) * f.height, 1.0f);
    std::uint8_t bg[4] = {to_unorm8(options.background[0]), to_unorm8(options.background[1]), to_unorm8(options.background[2]), 255};
    // Shadow map: the same renderer from the light camera (depth only is used)
    ShadowLookup shadow;
    if (options.shadows) {
        const Camera lc = light_camera(prims, light);
        RenderOptions lo;
        lo.width = lo.height = options.shadow_map_size;
        lo.culling = options.culling;
        lo.tight_bounds = options.tight_bounds;
        shadow.map = render_validated(prims, lc, light, lo, nullptr, threads).depth;
        shadow.size = options.shadow_map_size;
        shadow.step = options.pcf_step;
        shadow.bias = options.shadow_bias / static_cast<float>(options.shadow_map_size);
        shadow.to_light = camera_to_light(camera, lc);
        shadow.viewport = vec2(static_cast<float>(f.width), static_cast<float>(f.height));
    }
    std::vector<Vec3<float>> normals, shaded;  // per pixel, only for the outline pass
    if (options.silhouettes) {
        normals.resize(img.depth.size());
        shaded.resize(img.depth.size());
    }
    const int n_threads = std::max(1, std::min(threads, n_tiles));
    std::vector<TileScratch> scratch(n_threads);
    parallel_for(n_tiles, n_threads, [&](int t, int thread) {
        TileScratch& s = scratch[thread];
        const int tx0 = (t % tiles_x) * tile_size, ty0 = (t / tiles_x) * tile_size;
        const int tx1 = std::min(f.width, tx0 + tile_size) - 1, ty1 = std::min(f.height, ty0 + tile_size) - 1;
        // Set up the tile's rays and clear it
        for (int y = ty0; y <= ty1; ++y)
            for (int x = tx0; x <= tx1; ++x) {
                const int k = (y - ty0) * tile_size + (x - tx0);
                s.ray[k] = pixel_ray(f, x, y);
                s.depth[k] = 1.0f;
                s.prim[k] = -1;
            }
        // Cast every primitive binned here at the pixels of its rectangle
        for (std::uint32_t j = offsets[t]; j < offsets[t + 1]; ++j) {
            const std::int32_t i = static_cast<std::int32_t>(items[j]);
            const PixelRect& pr = rects[i];
            const PixelRect r{std::max(pr.x0, tx0), std::max(pr.y0, ty0), std::min(pr.x1, tx1), std::min(pr.y1, ty1)};
            const Primitive& p = prims[i];
            dispatch_variant(p.variant, options.culling, [&]<CastOptions Opt>() { cast_rect<Opt>(p, i, r, tx0, ty0, f, s); });
        }
        // (with stats, the tile's winners: what the picture shows)
        if (stats)
            for (int y = ty0; y <= ty1; ++y)
                for (int x = tx0; x <= tx1; ++x) {
                    const std::int32_t w = s.prim[(y - ty0) * tile_size + (x - tx0)];
                    if (w >= 0 && (s.winners.empty() || s.winners.back() != w)) s.winners.push_back(w);
                }
        // Shade the winners and write the tile (row 0 of the image is the top)
        for (int y = ty0; y <= ty1; ++y)
            for (int x = tx0; x <= tx1; ++x) {
                const int k = (y - ty0) * tile_size + (x - tx0);
                const std::size_t o = std::size_t(f.height - 1 - y) * f.width + x;
                std::uint8_t* px = &img.rgba[o * 4];
                img.depth[o] = s.depth[k];
                if (options.silhouettes || options.shadows) {
                    Vec3<float> c = options.background;
                    if (s.prim[k] >= 0) {
                        const Primitive& p = prims[s.prim[k]];
                        if (options.shadows) {
                            const float vis = shadow_visibility(shadow, float(x) + 0.5f, float(y) + 0.5f, s.depth[k]);
                            c = shade_blinn_phong_shadowed(s.normal[k], -light.direction, -s.ray[k].dir, p.color, light.color, shading_material(p, options), vis);
                        } else {
                            c = shade_blinn_phong(s.normal[k], -light.direction, -s.ray[k].dir, p.color, light.color, shading_material(p, options));
                        }
                        if (options.environment)
                            c = reflect_environment(*options.environment, c, s.normal[k], -s.ray[k].dir, options.reflectivity);
                    }
                    if (options.silhouettes) {
                        // Keep the geometry buffer's normal and the float colour for the outline pass.
                        normals[o] = s.prim[k] < 0 ? vec3(0.0f, 0.0f, 0.0f) : s.normal[k];
                        shaded[o] = c;
                    } else {
                        for (int i = 0; i < 3; ++i) px[i] = to_unorm8(c[i]);
                        px[3] = 255;
                    }
                    continue;
                }
                if (s.prim[k] < 0) std::copy(bg, bg + 4, px);
                else shade_pixel(prims[s.prim[k]], s.normal[k], s.ray[k].dir, light, options, px);
            }
    });

    // Silhouette and crease outlines from the 3x3 neighbourhoods (clamped at the image border),
    // as the GL deferred pass does
    if (options.silhouettes) {
        const Vec2<float> last = vec2(float(f.width - 1), float(f.height - 1));
        parallel_for(f.height, threads, [&](int yi, int) {
            for (int xi = 0; xi < f.width; ++xi) {
                float d[9];
                Vec3<float> nb[9];
                for (int r = 0; r < 3; ++r)
                    for (int c = 0; c < 3; ++c) {
                        // (image rows top first: row r - 1 down; the GL pass counts window rows up)
                        const Vec2<float> t = neighbour_texel(vec2(xi + 0.5f, yi + 0.5f), float(c - 1), float(r - 1), last);
                        const int xx = static_cast<int>(t[0]), yy = static_cast<int>(t[1]);
                        const std::size_t q = std::size_t(yy) * f.width + xx;
                        d[3 * r + c] = img.depth[q];
                        nb[3 * r + c] = normals[q];
                    }
                const std::size_t o = std::size_t(yi) * f.width + xi;
                const Vec3<float> c = apply_outline(shaded[o], silhouette_weight(d, nb, f.pz, options.silhouette), options.silhouette[2]);
                for (int i = 0; i < 3; ++i) img.rgba[o * 4 + i] = to_unorm8(c[i]);
                img.rgba[o * 4 + 3] = 255;
            }
        });
    }

    if (stats) {
        *stats = FrameStats{};
        stats->primitives = prims.size();
        for (std::uint8_t c : is_culled) stats->culled += c;
        std::vector<std::uint8_t> shown(prims.size(), 0);
        for (const TileScratch& s : scratch) {
            stats->fragments += s.fragments;
            stats->hits += s.hits;
            for (std::int32_t w : s.winners) shown[static_cast<std::size_t>(w)] = 1;
        }
        for (std::uint8_t c : shown) stats->shown += c;
    }
    return img;
}

}  // namespace cpu_detail

inline Image render_cpu(const std::vector<Primitive>& prims, const Camera& camera, const Light& light, const RenderOptions& options,
                        FrameStats* stats, int threads) {
    validate_primitives(prims);
    return cpu_detail::render_validated(prims, camera, light, options, stats, threads);
}

}  // namespace quadcast::render
