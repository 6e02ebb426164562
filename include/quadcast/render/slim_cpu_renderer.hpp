// quadcast/render/slim_cpu_renderer.hpp -- CPU reference renderer of SLIM surfaces (per-ray blending)
#pragma once

// Host-only. The same three steps as the GL SLIM renderer (quadcast/gl/slim_renderer.hpp), per
// pixel ray instead of per pass, with the same templates (quadcast/slim_blend.hpp):
//   visibility  the smallest `SlimFragment::visibility` over the balls hit (GL: depth-only pass,
//               GL_LESS);
//   accumulate  in ball order, every hit with depth <= that is added by `slim_accumulate` (GL:
//               GL_LEQUAL, no depth writes, additive blending into float targets);
//   resolve     `slim_resolve`, then `shade_blinn_phong` as the deferred pass shades.
// A ball is a Primitive of variant `bounded` (shapes::quadric with a SphereBound) whose
// shape.planes[0] is its clip plane in local coordinates ((0, 0, 0, 1): none) and shape.planes[1]
// a second one (a corner's; (0, 0, 0, 1) or (0, 0, 0, 0): none). Per-quadric
// back-face culling (`culled`) and per-fragment culling (front root only) follow
// RenderOptions::culling, as for the quadric renderer; with RenderOptions::tight_bounds a ball is
// bound by its patch (quadcast/render/slim_patch.hpp: `slim_pixels`, and with culling
// `slim_patch_cull`), else by `screen_rect` (its bounding sphere's quad); then binned into tiles.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "quadcast/render/cpu_renderer.hpp"
#include "quadcast/render/slim_patch.hpp"
#include "quadcast/slim_blend.hpp"

namespace quadcast::render {

/// What the CPU reference found at one pixel (window rows top first, like Image).
struct SlimPixel {
    bool covered = false;
    int blended = 0;            ///< fragments summed
    float weight = 0.0f;        ///< their summed weight
    Vec3<float> normal;         ///< blended unit normal
    float lambda = 0.0f;        ///< blended ray parameter: the position is origin + lambda dir
    float depth = 1.0f;
    float visibility = 1.0f;    ///< the visibility pass's depth (1: no hit)
    Vec3<float> origin, dir;    ///< the pixel's ray
};

/// Throws std::invalid_argument when a ball is not a `bounded` primitive with a finite clip plane
/// whose normal is not zero (or the plane (0, 0, 0, 1)) and a finite second clip plane whose normal
/// is not zero (or (0, 0, 0, d), d >= 0: none), or fails `validate_primitives`.
inline void validate_slim_balls(const std::vector<Primitive>& balls) {
    validate_primitives(balls);
    for (std::size_t i = 0; i < balls.size(); ++i) {
        const Primitive& b = balls[i];
        if (b.variant != Variant::bounded)
            throw std::invalid_argument("quadcast::render: SLIM ball " + std::to_string(i) + ": not a sphere-bounded quadric (variant " +
                                        variant_name(b.variant) + ")");
        const Vec4<float>& pl = b.shape.planes[0];
        for (int k = 0; k < 4; ++k)
            if (!std::isfinite(pl[k])) throw std::invalid_argument("quadcast::render: SLIM ball " + std::to_string(i) + ": clip plane is not finite");
        if (pl[0] == 0.0f && pl[1] == 0.0f && pl[2] == 0.0f && !(pl[3] > 0.0f))
            throw std::invalid_argument("quadcast::render: SLIM ball " + std::to_string(i) + ": clip plane has a zero normal and keeps nothing");
        const Vec4<float>& p2 = b.shape.planes[1];
        for (int k = 0; k < 4; ++k)
            if (!std::isfinite(p2[k])) throw std::invalid_argument("quadcast::render: SLIM ball " + std::to_string(i) + ": second clip plane is not finite");
        if (p2[0] == 0.0f && p2[1] == 0.0f && p2[2] == 0.0f && p2[3] < 0.0f)
            throw std::invalid_argument("quadcast::render: SLIM ball " + std::to_string(i) + ": second clip plane has a zero normal and keeps nothing");
    }
}

/// `slim_fragment` of a ball at a pixel ray, as the GL stages compute it.
inline SlimFragment<float> slim_cast(const Primitive& b, const PixelRay& ray, const FrameSetup& f, bool culling) {
    const LocalRay<float> r = local_ray(b.shape, ray.origin, ray.dir);
    return culling ? slim_fragment<true>(b.shape, r, f.vz_row, f.pz) : slim_fragment<false>(b.shape, r, f.vz_row, f.pz);
}

/// Renders SLIM balls (see the top of this file): RGBA8 as the GL deferred pass shades the blended
/// surface (`shade_blinn_phong(n, -light.direction, -dir, colour, light.color, (ambient, diffuse,
/// specular, shininess))`, background elsewhere) and the blended window depth (1 = background).
/// With `pixels`, what every pixel blended. `threads` 0: the hardware concurrency. `patches`: the
/// balls' `slim_patches` (computed here when null and options.tight_bounds is set). Throws
/// std::invalid_argument (`validate_slim_balls`, bad image size or camera, a patch count that is
/// not the ball count).
inline Image render_slim_cpu(const std::vector<Primitive>& balls, const Camera& camera, const Light& light, const RenderOptions& options,
                             std::vector<SlimPixel>* pixels = nullptr, int threads = 0, const std::vector<SlimPatch<float>>* patches = nullptr) {
    using namespace cpu_detail;
    validate_slim_balls(balls);
    const FrameSetup f = frame_setup(camera, options.width, options.height);
    if (threads <= 0) threads = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
    const int n = static_cast<int>(balls.size());
    const int tiles_x = (f.width + tile_size - 1) / tile_size, tiles_y = (f.height + tile_size - 1) / tile_size;
    const int n_tiles = tiles_x * tiles_y;
    // Bound and cull every ball (as the GL vertex stage), bin them into tiles in ball order
    std::vector<SlimPatch<float>> own;
    if (options.tight_bounds && !patches) {
        own = slim_patches(balls, threads);
        patches = &own;
    }
    if (patches && patches->size() != balls.size())
        throw std::invalid_argument("quadcast::render: " + std::to_string(patches->size()) + " SLIM patches for " + std::to_string(balls.size()) + " balls");
    std::vector<PixelRect> rects(balls.size());
    for (int i = 0; i < n; ++i) {
        const SlimPatch<float>* patch = patches ? &(*patches)[std::size_t(i)] : nullptr;
        if (slim_ball_culled(balls[i], patch, f, options)) continue;
        rects[i] = options.tight_bounds ? slim_pixels(balls[i], *patch, f) : screen_rect(balls[i].shape, f);
    }
    std::vector<std::vector<std::uint32_t>> bins(static_cast<std::size_t>(n_tiles));
    for (int i = 0; i < n; ++i) {
        const PixelRect& r = rects[i];
        if (r.x0 > r.x1) continue;
        for (int ty = r.y0 / tile_size; ty <= r.y1 / tile_size; ++ty)
            for (int tx = r.x0 / tile_size; tx <= r.x1 / tile_size; ++tx) bins[std::size_t(ty * tiles_x + tx)].push_back(static_cast<std::uint32_t>(i));
    }
    Image img;
    img.width = f.width;
    img.height = f.height;
    img.rgba.assign(std::size_t(f.width) * f.height * 4, 0);
    img.depth.assign(std::size_t(f.width) * f.height, 1.0f);
    if (pixels) pixels->assign(std::size_t(f.width) * f.height, SlimPixel{});
    const std::uint8_t bg[4] = {to_unorm8(options.background[0]), to_unorm8(options.background[1]), to_unorm8(options.background[2]), 255};
    parallel_for(n_tiles, std::max(1, std::min(threads, n_tiles)), [&](int t, int) {
        const int tx0 = (t % tiles_x) * tile_size, ty0 = (t / tiles_x) * tile_size;
        const int tx1 = std::min(f.width, tx0 + tile_size) - 1, ty1 = std::min(f.height, ty0 + tile_size) - 1;
        const std::vector<std::uint32_t>& bin = bins[std::size_t(t)];
        for (int y = ty0; y <= ty1; ++y)
            for (int x = tx0; x <= tx1; ++x) {
                const PixelRay ray = pixel_ray(f, x, y);
                auto inside = [&](const PixelRect& r) { return x >= r.x0 && x <= r.x1 && y >= r.y0 && y <= r.y1; };
                // Visibility: the smallest pushed depth (GL_LESS against a cleared 1)
                float vis = 1.0f;
                bool any = false;
                for (std::uint32_t i : bin) {
                    if (!inside(rects[i])) continue;
                    const SlimFragment<float> s = slim_cast(balls[i], ray, f, options.culling);
                    any = any || s.hit;
                    if (s.hit && s.visibility < vis) vis = s.visibility;
                }
                // Accumulation: every hit at or before it (GL_LEQUAL), in ball order. Where every
                // pushed depth lies at or beyond the far plane (clamped to 1, which GL_LESS does not
                // write) vis stays 1 and every hit in front of the far plane is added, as in GL.
                SlimSums<float> sums;
                int blended = 0;
                if (any)
                    for (std::uint32_t i : bin) {
                        if (!inside(rects[i])) continue;
                        const SlimFragment<float> s = slim_cast(balls[i], ray, f, options.culling);
                        if (!s.hit || !(s.depth <= vis)) continue;
                        const Primitive& b = balls[i];
                        slim_accumulate(sums, slim_terms(s.weight, s.normal, s.lambda, b.color, vec2(b.material.specular, b.material.shininess)));
                        ++blended;
                    }
                // Resolve and shade
                const SlimResolved<float> res = slim_resolve(sums.normal_weight, sums.lambda_material, sums.color, dot(f.vz_row, ray.dir), f.pz);
                const std::size_t o = std::size_t(f.height - 1 - y) * f.width + x;
                std::uint8_t* px = &img.rgba[o * 4];
                if (pixels) (*pixels)[o] = SlimPixel{res.covered, blended, sums.normal_weight[3], res.normal, res.lambda, res.covered ? res.depth : 1.0f, vis, ray.origin, ray.dir};
                if (!res.covered) {
                    std::copy(bg, bg + 4, px);
                    continue;
                }
                img.depth[o] = res.depth;
                const Vec4<float> material = vec4(options.material[0], options.material[1], res.material[0], res.material[1]);
                const Vec3<float> c = shade_blinn_phong(res.normal, -light.direction, -ray.dir, res.color, light.color, material);
                for (int k = 0; k < 3; ++k) px[k] = to_unorm8(c[k]);
                px[3] = 255;
            }
    });
    return img;
}

}  // namespace quadcast::render
