// quadcast/slim_blend.hpp -- SLIM surfaces: the blending weight, one ball's fragment and the per-pixel resolve
#pragma once

// Stoll et al. 2006, sec. 5.1.1 (after Ohtake, Belyaev & Alexa 2005): every ball of a SLIM surface
// holds a quadric clipped to the ball (and optionally to a plane). Per pixel ray the renderers
//   1. find the nearest hit of any ball and push its depth away from the eye by
//      `slim_depth_window` x the ball's radius (the visibility pass: `SlimFragment::visibility`,
//      the minimum over the balls),
//   2. sum w n, w lambda, w colour and w over every hit whose depth is <= that (the
//      accumulation pass: `SlimFragment`),
//   3. divide by the summed weight (`slim_resolve`): blended normal, ray parameter (the position
//      is origin + lambda dir: every hit of a pixel lies on its ray), window depth, colour.
// The same templates run on the CPU (quadcast/render/slim_cpu_renderer.hpp) and, traced, in the
// GL stages (codegen/kernels/slim_kernels.hpp).

#include "quadcast/bounds.hpp"
#include "quadcast/linalg.hpp"
#include "quadcast/raycast.hpp"
#include "quadcast/scalar.hpp"

namespace quadcast {

/// How far the visibility pass pushes a ball's depth away from the eye, relative to the ball's
/// radius, along the view axis (view-space z), for a hit at the ball's centre (weight 1). A hit of
/// another ball is blended when its window depth is at most the smallest pushed depth of the
/// pixel: one constant for the GL visibility pass and the CPU reference. Towards the sphere the
/// push grows linearly in 1 - w to the whole radius (`slim_fragment`): a small ball's rim hit a
/// little in front of the surface (its quadric's deviation at the rim, within the support
/// tolerance) would otherwise shut out the surface's own hits behind it, and the pixel would show
/// that one low-weight hit alone (a seam: 45-70 degree jumps of the blended normal measured on the
/// bunny, tests/slim/against_mesh.cpp).
inline constexpr float slim_depth_window = 0.25f;

/// exp(-u) for u in [0, 1] as its Taylor polynomial of degree 11 in Horner form:
/// e = 1; for k = 11 .. 1: e = 1 - (u / k) e. Truncation error <= 1/12! = 2.1e-9 on [0, 1] (below
/// float rounding); exactly 1 at u = 0.
/// Numerics: 11 divisions by integer literals, 11 multiplications, 11 subtractions.
template <class T>
T slim_exp_neg(const T& u) {
    T e = T(1);
    for (int k = 11; k >= 1; --k) e = T(1) - (u / T(k)) * e;
    return e;
}

/// The SLIM blending weight of a point at t = |x - c| / r of its ball (Ohtake et al. 2005: a
/// Gaussian in the first half, a quadratic in the second; Stoll et al. 2006, sec. 5.1.1):
///     w(t) = exp(-4 t^2)               for 0 <= t <= 1/2
///     w(t) = 4 exp(-1) (1 - t)^2       for 1/2 <= t <= 1
///     w(t) = 0                         for t >= 1.
/// The Gaussian's exponent 4 is the one that makes the quadratic, which vanishes with its
/// derivative at t = 1, meet it with equal value (e^-1) and slope (-4 e^-1) at t = 1/2: w is C1,
/// 1 at the centre, 0 on and beyond the sphere, decreasing. exp(-u) is `slim_exp_neg`, and the
/// tail's factor is 4 slim_exp_neg(1), so both pieces give the same number at t = 1/2.
/// Numerics: u = 4 (t t); tail = (4 E(1)) ((1 - t)(1 - t)); selects at t < 1/2 and t < 1.
template <class T>
T slim_weight(const T& t) {
    const T core = slim_exp_neg(T(4) * (t * t));
    const T s = T(1) - t;
    const T tail = (T(4) * slim_exp_neg(T(1))) * (s * s);
    return select(t < T(0.5), core, select(t < T(1), tail, T(0)));
}

/// One ball's fragment of a SLIM pixel ray.
template <class T>
struct SlimFragment {
    mask_t<T> hit;     ///< the quadric is hit in the ball (and on the kept side of its planes), depth in [0, 1]
    T depth;           ///< window depth of the hit
    T visibility;      ///< the depth the visibility pass writes: pushed away from the eye, at most 1
    T lambda;          ///< ray parameter of the hit
    Vec3<T> normal;    ///< unit outward normal of the quadric at the hit
    T weight;          ///< slim_weight(|x - c| / r)
};

/// The fragment of one SLIM ball (a quadric clipped to its bounding sphere and to the planes in
/// p.planes[0] and p.planes[1]; variant `bounded` plus CastOptions::clip_plane) for a ray whose origin lies in the
/// camera plane: `cast_ray` (front root only with `Cull`), `window_depth`, and the visibility
/// depth, window depth at view z = lambda vz - s r, s = slim_depth_window + (1 -
/// slim_depth_window) (1 - w) (0.25 at the centre, 1 on the sphere), clamped to 1.
/// Numerics: as `cast_ray` and `window_depth`; t = sqrt(x.x) / r; the normal is `normalize` of
/// g + lambda a (guarded: (0, 0, 1) where that is zero, which only a singular point gives).
template <bool Cull, class T>
SlimFragment<T> slim_fragment(const ClippedQuadric<T>& p, const LocalRay<T>& r, const Vec3<T>& vz_row, const Vec4<T>& pz) {
    constexpr CastOptions opt{Cull, false, true, false, false, true};
    const CastHit<T> h = cast_ray<opt>(p, r);
    const T t = sqrt(dot(h.x, h.x)) / p.radius;
    const T w = slim_weight(t);
    // Depth of the hit, and the pushed depth of the visibility pass
    const T vz = dot(vz_row, r.v);
    const T depth = window_depth(h.lambda, vz, pz);
    const T push = T(slim_depth_window) * (T(2) - w);
    const T z = h.lambda * vz - push * p.radius;
    const T pushed = T(0.5) * ((pz[0] * z + pz[1]) / (pz[2] * z + pz[3])) + T(0.5);
    // Unit normal
    const T n2 = dot(h.normal, h.normal);
    const mask_t<T> ok_n = n2 > T(0);
    const T len = sqrt(select(ok_n, n2, T(1)));
    const Vec3<T> n = select(ok_n, h.normal / len, vec3(T(0), T(0), T(1)));
    return {(h.hit && depth >= T(0)) && depth <= T(1), depth, min(pushed, T(1)), h.lambda, n, w};
}

/// A bound of the part of a SLIM ball that can be hit, its patch: the zero set of the quadric in
/// the ball, on the kept side of its clip plane (quadcast/render/slim_patch.hpp computes it once
/// per ball, by interval subdivision). In the ball's local coordinates x (x_world - centre), with
/// a unit axis a:
///   the slab       lo <= a . x <= hi over the patch (lo > hi: the patch is empty), so the patch
///                  lies in the cylinder of radius rho around a between the two planes;
///   the normal cone  every gradient of the quadric on the patch makes an angle of at most theta
///                  with a (cos theta, sin theta; (0, 1) when that bound is 90 degrees or more).
/// The renderers draw a ball over `slim_patch_quad` instead of its sphere's quad and skip it
/// where `slim_patch_culled` shows the whole patch facing away from the eye.
template <class T>
struct SlimPatch {
    Vec4<T> axis_rho;   ///< a, rho
    Vec4<T> slab_cone;  ///< lo, hi, cos theta, sin theta
};

/// The padded screen quadrilateral of a SLIM ball's patch (`SlimPatch`) under `view_projection`:
/// `sections_quad` of the two discs of radius rho around a at a . x = lo and hi, whose convex hull
/// is the cylinder that holds the patch (sides along the projected axis a and across it: a patch
/// seen edge-on covers a band, not the square around it). `tight` and `visible` as
/// `sections_quad`'s; an empty patch (lo > hi) is tight and not visible, every corner at (2, 2).
/// Numerics: disc i: e = a z_i, W = rho^2 (I - a a^T) entry by entry ((i == j) - a_i a_j) * rho^2;
/// `sections_quad`.
template <class T>
ScreenQuad<T> slim_patch_quad(const Mat4<T>& view_projection, const Vec3<T>& center, const Vec4<T>& axis_rho, const Vec4<T>& slab_cone,
                              const Vec2<T>& viewport) {
    const Vec3<T> a = xyz(axis_rho);
    const T rho2 = axis_rho[3] * axis_rho[3];
    // The two discs as dual forms
    DualBound<T> disc[2];
    for (int k = 0; k < 2; ++k) {
        disc[k].e = a * slab_cone[k];
        for (int j = 0; j < 3; ++j)
            for (int i = 0; i < 3; ++i) disc[k].w[j][i] = (T(i == j ? 1 : 0) - a[i] * a[j]) * rho2;
        disc[k].ok = mask_t<T>(true);
    }
    ScreenQuad<T> q = sections_quad(view_projection, center, a, disc[1], disc[0], viewport);
    // An empty patch draws nothing
    const mask_t<T> empty = slab_cone[0] > slab_cone[1];
    q.visible = q.visible && !empty;
    q.tight = q.tight || empty;
    for (int i = 0; i < 4; ++i) q.corner[i] = select(empty, vec2(T(2), T(2)), q.corner[i]);
    return q;
}

/// Whether the whole patch of a SLIM ball (`SlimPatch`) faces away from every ray of the camera,
/// so that no front root (per-fragment culling) can lie on it. `fixed` is the eye (perspective) or
/// the rays' direction (orthographic; `window_ray`'s `fixed`). With w = centre - eye
/// (perspective) or the direction, and any gradient n on the patch within theta of a, a point x of
/// the patch (|x| <= r) and its ray v = w + x: n . v >= |w| cos(angle(a, w) + theta) - r |n|. So
/// the patch is culled when (a . w) cos theta - |a x w| sin theta > r (1 + 2^-8) + 2^-10 |w|
/// (perspective; the eye lies outside the ball then), > 2^-10 |w| (orthographic): a margin of
/// about 0.06 degrees for the rounding of the rays and the roots.
/// Numerics: left-fold dots; |a x w| = sqrt(c . c).
template <bool Ortho, class T>
mask_t<T> slim_patch_culled(const Vec3<T>& center, const T& radius, const Vec4<T>& axis_rho, const Vec4<T>& slab_cone, const Vec3<T>& fixed) {
    const Vec3<T> a = xyz(axis_rho);
    const Vec3<T> w = Ortho ? fixed : center - fixed;
    const Vec3<T> c = cross(a, w);
    const T m = dot(a, w) * slab_cone[2] - sqrt(dot(c, c)) * slab_cone[3];
    const T margin = sqrt(dot(w, w)) * T(0.0009765625);
    if constexpr (Ortho) return m > margin;
    else return m > radius * T(1.00390625) + margin;
}

/// A SLIM pixel after the accumulation: sums over the blended fragments, in their order.
template <class T>
struct SlimSums {
    Vec4<T> normal_weight{};    ///< (sum w n, sum w)
    Vec4<T> lambda_material{};  ///< (sum w lambda, sum w specular, sum w shininess, 0)
    Vec3<T> color{};            ///< sum w colour
};

/// One fragment's terms of the sums: w n, w, w lambda, w specular, w shininess, w colour, each a
/// product per component (what the accumulation pass writes to its three targets).
template <class T>
SlimSums<T> slim_terms(const T& w, const Vec3<T>& n, const T& lambda, const Vec3<T>& color, const Vec2<T>& material) {
    return {vec4(w * n[0], w * n[1], w * n[2], w), vec4(w * lambda, w * material[0], w * material[1], T(0)),
            vec3(w * color[0], w * color[1], w * color[2])};
}

/// Adds one fragment's terms to the sums (the accumulation pass's additive blend, GL_ONE, GL_ONE:
/// sum + term per component, in the order the fragments come).
template <class T>
void slim_accumulate(SlimSums<T>& s, const SlimSums<T>& term) {
    s.normal_weight = s.normal_weight + term.normal_weight;
    s.lambda_material = s.lambda_material + term.lambda_material;
    s.color = s.color + term.color;
}

/// The blended surface of a pixel (the shading pass's input).
template <class T>
struct SlimResolved {
    mask_t<T> covered;   ///< sum w > 0
    Vec3<T> normal;      ///< normalize(sum w n)
    T lambda;            ///< sum w lambda / sum w: the blended position is origin + lambda dir
    T depth;             ///< window depth of the blended position
    Vec3<T> color;       ///< sum w colour / sum w
    Vec2<T> material;    ///< (specular, shininess), weighted means
};

/// Divides the sums by the weight (Stoll et al. 2006, sec. 5.1.1, shading pass). vz = view-space z
/// of the pixel ray's direction.
/// Numerics: each mean is (sum) / (sum w); the normal `normalize` of sum w n (guarded like
/// `slim_fragment`); depth `window_depth(lambda, vz, pz)`.
template <class T>
SlimResolved<T> slim_resolve(const Vec4<T>& normal_weight, const Vec4<T>& lambda_material, const Vec3<T>& color, const T& vz,
                             const Vec4<T>& pz) {
    const T w = normal_weight[3];
    const mask_t<T> covered = w > T(0);
    const T ws = select(covered, w, T(1));
    const Vec3<T> sn = xyz(normal_weight);
    const T n2 = dot(sn, sn);
    const mask_t<T> ok_n = n2 > T(0);
    const T len = sqrt(select(ok_n, n2, T(1)));
    const Vec3<T> n = select(ok_n, sn / len, vec3(T(0), T(0), T(1)));
    const T lambda = lambda_material[0] / ws;
    return {covered, n, lambda, window_depth(lambda, vz, pz), color / ws, vec2(lambda_material[1] / ws, lambda_material[2] / ws)};
}

}  // namespace quadcast
