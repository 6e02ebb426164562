// quadcast/render/slim_patch.hpp -- the patch bound of a SLIM ball (`SlimPatch`), by interval subdivision
#pragma once

// Host-only. A SLIM ball's bounding sphere is a loose bound of what it draws: its quadric's zero
// set in the ball (its patch) is a sheet, often nearly flat, and half of a closed surface's sheets
// face away from the eye. `slim_patch` bounds the patch once per ball by a slab along an axis and
// a cone of its gradients (quadcast/slim_blend.hpp: `SlimPatch`, `slim_patch_quad`,
// `slim_patch_culled`), rigorously: in coordinates u = x / R of the ball enlarged to
// R = r (1 + 2^-8) (room for the rounding of the renderers' float hits), the cube [-1, 1]^3 is
// split `depth` times into 8, and a box is kept while it may hold a point of the patch:
//   - it meets the unit ball: sum_i max(|p_i| - s, 0)^2 <= 1 (box centre p, half-size s);
//   - it reaches the kept side of each clip plane n . x + d >= 0 within 2^-8 R:
//     n' . p + d + s |n'|_1 >= -2^-8 R |n| (n' = R n);
//   - the quadric F(u) = f(R u) may vanish in it: |F(p)| <= 2 s |g|_1 + s^2 sum |A'_ij| + slack,
//     g = A' p + b' (F(p + e) = F(p) + 2 g . e + e^T A' e for |e|_inf <= s), the slack
//     2^-40 (|c| + 2 |b'|_1 + sum |A'_ij|) for the double rounding.
// The patch lies in the union of the last level's boxes. The axis a is the normalised sum of the
// unit gradients at the box centres of a first subdivision of depth 3; the patch is then subdivided
// again in the frame (e1, e2, a) (M orthonormal: the same tests with M^T A' M, M^T b', M^T n'),
// where the slab is the range of u'_z over the boxes (p_z +- s, clamped to [-1, 1]), times R and
// widened by 2^-8 R on each side; rho = R where the slab holds the centre plane, else
// sqrt(R^2 - z^2) for its nearer end z. The cone: over a box the gradient 2 (A' (p + e) + b') lies in
// the box G +- 2 s (row sums of |A'|), whose angle with a is at most
// acos((a . G - |2 s rowsum|_2) / (|G| + |2 s rowsum|_2)); theta is the largest over the boxes
// (90 degrees, no culling, where a box's gradients may vanish or turn past 90 degrees), its cosine
// rounded down and sine up to float. No box left: the patch is empty (lo > hi).
// Depth 6 (boxes of 1/64 of the enlarged ball's diameter) widens the slab by at most 1/32 of R on
// each side against the exact patch, plus the 2^-8 R margin; about 0.1 ms per ball (README: depth
// against time and culled balls).

#include <algorithm>
#include <cmath>
#include <thread>
#include <vector>

#include "quadcast/bounds.hpp"
#include "quadcast/render/cpu_renderer.hpp"
#include "quadcast/slim_blend.hpp"

namespace quadcast::render {

/// Subdivision levels of `slim_patch` (boxes of 2^-depth of the enlarged ball's diameter).
inline constexpr int slim_patch_depth = 6;

namespace slim_patch_detail {

/// The quadric F(u) = u^T A u + 2 b . u + c and the plane n . u + d >= 0 in unit coordinates of
/// the enlarged ball, and the boxes (centre u, half-size s) that may hold a point of the patch.
struct UnitPatch {
    Mat3<double> A;
    Vec3<double> b, n, n2;
    double c, d, d2, plane_tol, plane_tol2;

    Vec3<double> gradient_half(const Vec3<double>& u) const { return A * u + b; }

    /// The centres of the surviving boxes of the cube [-1, 1]^3 split `depth` times (top of this file).
    std::vector<Vec3<double>> boxes(int depth) const {
        double abs_sum = 0.0;
        for (int j = 0; j < 3; ++j)
            for (int i = 0; i < 3; ++i) abs_sum += std::abs(A[j][i]);
        const double slack = std::ldexp(std::abs(c) + 2.0 * norm1(b) + abs_sum, -40);
        const double n1 = norm1(n), n21 = norm1(n2);
        auto may_hold = [&](const Vec3<double>& u, double s) {
            double dist2 = 0.0;
            for (int i = 0; i < 3; ++i) {
                const double e = std::max(std::abs(u[i]) - s, 0.0);
                dist2 += e * e;
            }
            if (dist2 > 1.0) return false;
            if (dot(n, u) + d + s * n1 < -plane_tol) return false;
            if (dot(n2, u) + d2 + s * n21 < -plane_tol2) return false;
            const Vec3<double> g = gradient_half(u);
            const double f = (dot(g, u) + dot(b, u)) + c;
            return std::abs(f) <= 2.0 * s * norm1(g) + s * s * abs_sum + slack;
        };
        std::vector<Vec3<double>> cur{vec3(0.0, 0.0, 0.0)}, next;
        double s = 1.0;
        for (int level = 0; level < depth && !cur.empty(); ++level) {
            const double h = s * 0.5;
            next.clear();
            for (const Vec3<double>& box : cur)
                for (int k = 0; k < 8; ++k) {
                    const Vec3<double> child = box + vec3((k & 1) ? h : -h, (k & 2) ? h : -h, (k & 4) ? h : -h);
                    if (may_hold(child, h)) next.push_back(child);
                }
            cur.swap(next);
            s = h;
        }
        return cur;
    }

    /// The same patch in the frame u = M u' (M orthonormal).
    UnitPatch rotated(const Mat3<double>& M) const {
        const Mat3<double> mt = transpose(M);
        UnitPatch r = *this;
        r.A = mt * A * M;
        r.b = mt * b;
        r.n = mt * n;
        r.n2 = mt * n2;
        return r;
    }

    static double norm1(const Vec3<double>& v) { return (std::abs(v[0]) + std::abs(v[1])) + std::abs(v[2]); }
};

}  // namespace slim_patch_detail

/// The bound of one SLIM ball's patch (see the top of this file). `p`: the ball as the renderers
/// hold it (`ClippedQuadric` of a `bounded` primitive, the clip planes in planes[0] and planes[1]).
inline SlimPatch<float> slim_patch(const ClippedQuadric<float>& p, int depth = slim_patch_depth) {
    using slim_patch_detail::UnitPatch;
    // The quadric and the plane in unit coordinates of the enlarged ball
    const double R = double(p.radius) * (1.0 + 1.0 / 256.0);
    UnitPatch up{};
    up.A = cast<double>(upper3(p.q.q));
    for (int j = 0; j < 3; ++j) up.A[j] = up.A[j] * (R * R);
    up.b = cast<double>(xyz(p.q.q[3])) * R;
    up.c = double(p.q.q[3][3]);
    up.n = cast<double>(xyz(p.planes[0])) * R;
    up.d = double(p.planes[0][3]);
    up.plane_tol = std::ldexp(length(up.n), -8);
    up.n2 = cast<double>(xyz(p.planes[1])) * R;
    up.d2 = double(p.planes[1][3]);
    up.plane_tol2 = std::ldexp(length(up.n2), -8);
    SlimPatch<float> out{};
    out.axis_rho = vec4(0.0f, 0.0f, 1.0f, 0.0f);
    out.slab_cone = vec4(1.0f, -1.0f, 0.0f, 1.0f);  // empty
    // The axis: the mean unit gradient at the centres of a coarse subdivision's boxes
    Vec3<double> a = vec3(0.0, 0.0, 0.0);
    {
        const std::vector<Vec3<double>> boxes = up.boxes(std::min(depth, 3));
        if (boxes.empty()) return out;
        for (const Vec3<double>& box : boxes) {
            const Vec3<double> g = up.gradient_half(box);
            const double len = length(g);
            if (len > 0) a = a + g / len;
        }
        const double len = length(a);
        a = len > 1e-6 ? a / len : vec3(0.0, 0.0, 1.0);
    }
    // Subdivide in the frame (e1, e2, a), where the slab is the range of u'_z
    Mat3<double> M{};
    plane_basis(a, M[0], M[1]);
    M[2] = a;
    const UnitPatch fr = up.rotated(M);
    const std::vector<Vec3<double>> boxes = fr.boxes(depth);
    if (boxes.empty()) return out;
    const double s = std::ldexp(1.0, -depth);
    Vec3<double> row_abs{};
    for (int i = 0; i < 3; ++i) row_abs[i] = UnitPatch::norm1(row(fr.A, i));
    const double spread = 2.0 * s * length(row_abs);
    double lo = 1.0, hi = -1.0, cos_min = 1.0;
    for (const Vec3<double>& box : boxes) {
        lo = std::min(lo, box[2] - s);
        hi = std::max(hi, box[2] + s);
        const Vec3<double> g = fr.gradient_half(box) * 2.0;
        const double along = g[2] - spread;
        cos_min = std::min(cos_min, along > 0.0 ? along / (length(g) + spread) : 0.0);
    }
    lo = std::max(lo, -1.0) * R - R / 256.0;
    hi = std::min(hi, 1.0) * R + R / 256.0;
    const double zmin = (lo <= 0.0 && hi >= 0.0) ? 0.0 : std::min(std::abs(lo), std::abs(hi));
    const double rho = zmin >= R ? 0.0 : std::sqrt(R * R - zmin * zmin);
    // Round outwards to float
    const double cos_t = std::max(0.0, cos_min * (1.0 - 1e-6) - 1e-7);
    const double sin_t = std::min(1.0, std::sqrt(std::max(0.0, 1.0 - cos_t * cos_t)) * (1.0 + 1e-6) + 1e-7);
    out.axis_rho = vec4(float(a[0]), float(a[1]), float(a[2]), std::nextafter(float(rho), 1e30f));
    out.slab_cone = vec4(std::nextafter(float(lo), -1e30f), std::nextafter(float(hi), 1e30f), float(cos_t), float(sin_t));
    return out;
}

/// `slim_patch` of every ball, on `threads` threads (0: the hardware concurrency).
inline std::vector<SlimPatch<float>> slim_patches(const std::vector<Primitive>& balls, int threads = 0, int depth = slim_patch_depth) {
    std::vector<SlimPatch<float>> out(balls.size());
    if (threads <= 0) threads = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
    const int n = static_cast<int>(balls.size());
    const int chunk = 64;
    cpu_detail::parallel_for((n + chunk - 1) / chunk, std::max(1, threads), [&](int k, int) {
        for (int i = k * chunk; i < std::min(n, (k + 1) * chunk); ++i) out[std::size_t(i)] = slim_patch(balls[std::size_t(i)].shape, depth);
    });
    return out;
}

/// Whether the renderers skip a ball for its patch's normal cone (`slim_patch_culled` for the
/// frame's camera: the eye, or the rays' direction), as the GL vertex stage does with culling and
/// tight bounds on.
inline bool slim_patch_cull(const Primitive& b, const SlimPatch<float>& patch, const FrameSetup& f) {
    return f.orthographic ? bool(slim_patch_culled<true>(b.shape.center, b.shape.radius, patch.axis_rho, patch.slab_cone, f.rays.fixed))
                          : bool(slim_patch_culled<false>(b.shape.center, b.shape.radius, patch.axis_rho, patch.slab_cone, f.rays.fixed));
}

/// Whether the renderers skip ball `b` in a frame: with RenderOptions::culling, per-quadric culling
/// (`culled`, perspective cameras) or, with tight bounds, its patch's normal cone (`slim_patch_cull`;
/// `patch` may be null without tight bounds).
inline bool slim_ball_culled(const Primitive& b, const SlimPatch<float>* patch, const FrameSetup& f, const RenderOptions& options) {
    if (!options.culling) return false;
    return culled(b, f) || (options.tight_bounds && slim_patch_cull(b, *patch, f));
}

/// The pixels the renderers draw a ball over with tight bounds: `screen_rect` (its bounding
/// sphere's quad) intersected with the rectangle around its patch's quadrilateral
/// (`slim_patch_quad`, the floats the GL vertex stage computes) where that is tight (empty where it
/// is not visible).
inline PixelRect slim_pixels(const Primitive& b, const SlimPatch<float>& patch, const FrameSetup& f) {
    const PixelRect sphere = screen_rect(b.shape, f);
    if (sphere.x0 > sphere.x1) return sphere;
    const ScreenRect<float> r =
        quad_rect(slim_patch_quad(f.view_projection, b.shape.center, patch.axis_rho, patch.slab_cone, vec2(float(f.width), float(f.height))));
    return within_rect(sphere, r, f);
}

}  // namespace quadcast::render
