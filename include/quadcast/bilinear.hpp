// quadcast/bilinear.hpp -- bilinear quadrilaterals as quadrics clipped by their tetrahedron
#pragma once

#include <algorithm>
#include <cmath>
#include <concepts>
#include <limits>

#include "quadcast/linalg.hpp"
#include "quadcast/quadric.hpp"
#include "quadcast/ray.hpp"
#include "quadcast/scalar.hpp"

namespace quadcast {

/// s(u, v) = (1 - v)((1 - u) p1 + u p2) + v((1 - u) p4 + u p3) (Stoll et al. 2006, eq. 1).
/// Numerics: exactly that association, componentwise.
template <class T>
Vec3<T> bilinear_point(const Vec3<T>& p1, const Vec3<T>& p2, const Vec3<T>& p3, const Vec3<T>& p4,
                       const T& u, const T& v) {
    const T one = T(1);
    return (one - v) * ((one - u) * p1 + u * p2) + v * ((one - u) * p4 + u * p3);
}

/// A bilinear quadrilateral as a quadric plus the tetrahedron (p1, p2, p3, p4) that clips it.
/// Inside the tetrahedron the zero set of `quadric` is exactly the patch s([0,1]^2): a point
/// s(U, V) of the surface has barycentric coordinates ((1-U)(1-V), U(1-V), UV, (1-U)V) in it,
/// all >= 0 only for (U, V) in [0,1]^2.
template <class T>
struct BilinearQuadric {
    Quadric<T> quadric;
    BoundingTet<T> bound;
};

/// A quadric given in local coordinates y = x - origin (f_world(x) = f_local(x - origin)).
/// Cast it with `translate_to_eye(quadric, eye - origin)`: that yields exactly the eye-origin
/// quadric of eq. 9 without ever forming world-space coefficients, whose constant term cancels
/// badly (relative error ~ eps |origin|^2 / L^2) when the patch is small and far from the origin.
template <class T>
struct LocalQuadric {
    Quadric<T> quadric;
    Vec3<T> origin;
};

/// The quadric through a NON-DEGENERATE bilinear quad (Stoll et al. 2006, sec. 4.5, eq. 20-29),
/// in local coordinates with origin p1 (eq. 23-25 with t = 0: A = M^-T A' M^-1, b = M^-T b',
/// c = 0). Use `quad_to_quadric` on the host, which classifies first and never divides by zero.
///
/// Steps: the affine map p = M p' + t, t = p1, M = (p2 - p1, p4 - p1, n^) takes p1, p2, p4 to
/// (0,0,0), (1,0,0), (0,1,0) and p3 to p3' = M^-1 (p3 - p1) = (1 + e, 1 + f, g) (eq. 22, 26-29).
/// There the patch is (x' g - z' e)(y' g - z' f) = z' g, i.e. (times 2, eq. 20)
///     A' = | 0    g^2  -fg  |     b' = (0, 0, -g),  c' = 0.
///          | g^2  0    -eg  |
///          | -fg  -eg  2ef  |
/// Erratum: eq. 21 prints A'_zz = 0, but eq. 20 has the term 2 e f z'^2, so A'_zz = 2ef (the
/// tests check that s(u, v) lies on the quadric; with 0 it does not unless e f = 0).
///
/// Orientation: the result is multiplied by -sign(g) (exact), so that grad f points along
/// s_u x s_v, which is (p2 - p1) x (p4 - p1) at p1: the front side is the one from which
/// p1, p2, p3, p4 appear counter-clockwise. (The paper's sign depends on which side p3 lies.)
///
/// Third column of M: the paper uses the unnormalised n = (p2 - p1) x (p4 - p1). Any nonzero
/// multiple gives the same zero set, because e, f, g are computed with the same M (the quadric
/// only changes by a positive factor), so the choice is about range, not about accuracy: with
/// |n| ~ L^2 (L = quad size) the coordinate z' has units 1/L and the whole quadric scales like
/// L^-4 (A ~ L^-4, c ~ |t|^2 L^-4); ray coefficients then square that (beta^2 ~ L^-8), which
/// overflows float for quads below ~1e-5 units. We use the unit normal n^ = n / |n| instead: z'
/// becomes a length, A' is O(1), A ~ 1 and b ~ L like a sphere's |x|^2 - r^2, and the usable range
/// of L doubles in exponent. Cost: one sqrt, 3 divisions.
///
/// Numerics: n = cross(a, b); n^ = n / sqrt(dot(n, n)); N = M^-1 by the adjugate (linalg
/// `inverse`); p3' = N (p3 - p1) (left folds); A = N^T (sigma A') N, upper triangle
/// A_ij = dot(N[i], sigma A' N[j]) mirrored (exactly symmetric), with the zero entries of A'
/// skipped; b = (sigma b'_z) * row 2 of N.
template <class T>
LocalQuadric<T> bilinear_to_local_quadric(const Vec3<T>& p1, const Vec3<T>& p2, const Vec3<T>& p3,
                                          const Vec3<T>& p4) {
    // Build M = (p2 - p1, p4 - p1, unit normal) and its inverse N (eq. 22).
    const Vec3<T> a = p2 - p1;
    const Vec3<T> b = p4 - p1;
    const Vec3<T> n = cross(a, b);
    Mat3<T> m{};
    m[0] = a;
    m[1] = b;
    m[2] = n / length(n);
    T det_m;
    const Mat3<T> inv = inverse(m, det_m);
    // Map p3 to (1 + e, 1 + f, g) (eq. 26-29).
    const Vec3<T> p3p = inv * (p3 - p1);
    const T e = p3p[0] - T(1);
    const T f = p3p[1] - T(1);
    const T g = p3p[2];
    // The oriented local quadric sigma (A', b') (eq. 20-21, A'_zz = 2ef), sigma = -sign(g).
    const T sigma = -sign_nonzero(g);
    const T axy = sigma * (g * g);
    const T axz = sigma * -(f * g);
    const T ayz = sigma * -(e * g);
    const T azz = sigma * (T(2) * (e * f));
    const T bz = sigma * -g;
    // A = N^T A' N (eq. 23), column j of A' N written out (A' has a zero diagonal in x, y).
    Vec3<T> w[3];
    for (int j = 0; j < 3; ++j) {
        const Vec3<T>& c = inv[j];
        w[j] = vec3(axy * c[1] + axz * c[2], axy * c[0] + ayz * c[2], (axz * c[0] + ayz * c[1]) + azz * c[2]);
    }
    Mat3<T> A{};
    for (int j = 0; j < 3; ++j)
        for (int i = 0; i <= j; ++i) {
            const T v = dot(inv[i], w[j]);
            A[j][i] = v;
            A[i][j] = v;
        }
    // b = N^T b' (eq. 24 with t = 0), c = c' = 0.
    const Vec3<T> bm = bz * vec3(inv[0][2], inv[1][2], inv[2][2]);
    return {quadric_from_abc(A, bm, T(0)), p1};
}

/// The quadric of a NON-DEGENERATE bilinear quad in world coordinates plus its clipping
/// tetrahedron (Stoll et al. 2006, eq. 20-29; see `bilinear_to_local_quadric`). The shift to the
/// world origin, eq. 24-25 (b = b_loc - A t, c = t^T (A t - 2 b_loc)), is eq. 9 with e = -t, so
/// it is computed as `translate_to_eye(local, -p1)`.
/// Numerics: those of `bilinear_to_local_quadric` and `translate_to_eye`.
template <class T>
BilinearQuadric<T> bilinear_to_quadric(const Vec3<T>& p1, const Vec3<T>& p2, const Vec3<T>& p3,
                                       const Vec3<T>& p4) {
    const LocalQuadric<T> local = bilinear_to_local_quadric(p1, p2, p3, p4);
    return {translate_to_eye(local.quadric, -p1), BoundingTet<T>{{p1, p2, p3, p4}}};
}

// Host side: classification and a conversion that never divides by zero -------------------------

/// What four points p1..p4 (cyclic) of a quad reduce to.
enum class QuadKind {
    bilinear,    ///< non-planar: representable as a quadric clipped by its tetrahedron
    planar,      ///< four distinct coplanar points (render as two triangles)
    triangle,    ///< three distinct points (one repeated)
    segment,     ///< all points on a line
    point,       ///< all points coincide
    non_finite,  ///< a NaN or infinite coordinate, or a conversion that over/underflows in T
};

/// Tolerances of `classify_quad`, relative to the quad size L (largest distance between two of
/// the points) plus an absolute part for the rounding of the coordinates (eps |p|max).
struct QuadTolerances {
    /// Points closer than this (times L, plus the absolute part) coincide; a point this close
    /// to a line lies on it. Default 64 eps: degeneracies up to rounding.
    long double degenerate;
    /// A quad whose points are all within planar * L of a common plane is planar. Default
    /// sqrt(eps): for a quad of height h out of plane seen from distance D, the quadric's
    /// hit depth error grows like eps D^2 / h (its two sheets meet as h -> 0), while two
    /// triangles are off by at most h; both are about sqrt(eps) L at h = sqrt(eps) L, D ~ L.
    /// Raise it for distant views.
    long double planar;
};

/// Default tolerances for quadrics computed in T (see QuadTolerances).
template <std::floating_point T>
QuadTolerances default_quad_tolerances() {
    const long double eps = std::numeric_limits<T>::epsilon();
    return {64.0L * eps, std::sqrt(eps)};
}

/// Host-only: what the quad p1..p4 reduces to (computed in long double). Order of checks:
/// non-finite coordinates; point (L <= tol); segment (all points within tol of the line through
/// the farthest pair); then the smallest height of a corner over the plane of the other three,
/// h = |det(p2-p1, p3-p1, p4-p1)| / max_i |face normal_i|: h <= planar L (+ abs) -> triangle if
/// only three points are distinct, planar otherwise; else bilinear.
template <std::floating_point T>
QuadKind classify_quad(const Vec3<T>& p1, const Vec3<T>& p2, const Vec3<T>& p3, const Vec3<T>& p4,
                       const QuadTolerances& tol = default_quad_tolerances<T>()) {
    using L = long double;
    using V = Vec3<L>;
    const V p[4] = {cast<L>(p1), cast<L>(p2), cast<L>(p3), cast<L>(p4)};
    for (const V& x : p)
        for (int k = 0; k < 3; ++k)
            if (!std::isfinite(x[k])) return QuadKind::non_finite;
    // Size and coordinate magnitude.
    L size = 0, mag = 0;
    int fa = 0, fb = 1;
    for (int i = 0; i < 4; ++i) {
        for (int k = 0; k < 3; ++k) mag = std::max(mag, std::fabs(p[i][k]));
        for (int j = i + 1; j < 4; ++j) {
            const L d = std::sqrt(length2(p[j] - p[i]));
            if (d > size) { size = d; fa = i; fb = j; }
        }
    }
    const L eps = std::numeric_limits<T>::epsilon();
    const L abs_tol = 64.0L * eps * mag;
    const L deg_tol = tol.degenerate * size + abs_tol;
    if (size <= abs_tol || size == 0) return QuadKind::point;
    // Collinear: distance of every point from the line through the farthest pair.
    const V dir = (p[fb] - p[fa]) / size;
    L line_dist = 0;
    for (const V& x : p) line_dist = std::max(line_dist, std::sqrt(length2(cross(x - p[fa], dir))));
    if (line_dist <= deg_tol) return QuadKind::segment;
    // Distinct points.
    int distinct = 0;
    for (int i = 0; i < 4; ++i) {
        bool repeated = false;
        for (int j = 0; j < i; ++j) repeated = repeated || std::sqrt(length2(p[i] - p[j])) <= deg_tol;
        distinct += repeated ? 0 : 1;
    }
    // Smallest height of a corner over the plane of the other three.
    const L vol6 = std::fabs(dot(p[1] - p[0], cross(p[2] - p[0], p[3] - p[0])));
    L face = 0;
    for (int i = 0; i < 4; ++i) {
        const V& a = p[(i + 1) % 4];
        face = std::max(face, std::sqrt(length2(cross(p[(i + 2) % 4] - a, p[(i + 3) % 4] - a))));
    }
    const L height = vol6 / face;  // face > 0: the points are not collinear
    if (height <= tol.planar * size + abs_tol) return distinct <= 3 ? QuadKind::triangle : QuadKind::planar;
    return distinct <= 3 ? QuadKind::triangle : QuadKind::bilinear;
}

/// Result of `quad_to_quadric`. `quadric` (world coordinates) and `local` (origin p1, the more
/// accurate input for `translate_to_eye(local.quadric, eye - local.origin)`) are meaningful only
/// for kind == bilinear; otherwise both quadrics are the zero matrix. `bound` holds the points.
template <class T>
struct QuadConversion {
    QuadKind kind;
    Quadric<T> quadric;
    LocalQuadric<T> local;
    BoundingTet<T> bound;
    bool ok() const { return kind == QuadKind::bilinear; }
};

/// Host-only: classify, then convert with `bilinear_to_local_quadric` and `bilinear_to_quadric`
/// only if the quad is bilinear. Never divides by zero and never returns NaN: if the conversion
/// in T over- or underflows (an extremely small or large quad: |(p2-p1) x (p4-p1)|^2 must be a
/// normal T, and every coefficient finite) the result is kind == non_finite with zero quadrics.
template <std::floating_point T>
QuadConversion<T> quad_to_quadric(const Vec3<T>& p1, const Vec3<T>& p2, const Vec3<T>& p3, const Vec3<T>& p4,
                                  const QuadTolerances& tol = default_quad_tolerances<T>()) {
    QuadConversion<T> r{classify_quad(p1, p2, p3, p4, tol), zero_quadric<T>(), {zero_quadric<T>(), p1},
                        BoundingTet<T>{{p1, p2, p3, p4}}};
    if (r.kind != QuadKind::bilinear) return r;
    // The normal must have a normal-range length in T, or n / |n| could divide by zero.
    const Vec3<T> n = cross(p2 - p1, p4 - p1);
    const T n2 = dot(n, n);
    if (!(n2 >= std::numeric_limits<T>::min() && n2 <= std::numeric_limits<T>::max())) {
        r.kind = QuadKind::non_finite;
        return r;
    }
    const LocalQuadric<T> local = bilinear_to_local_quadric(p1, p2, p3, p4);
    const Quadric<T> world = translate_to_eye(local.quadric, -p1);
    for (int j = 0; j < 4; ++j)
        for (int i = 0; i < 4; ++i)
            if (!std::isfinite(local.quadric.q[j][i]) || !std::isfinite(world.q[j][i])) {
                r.kind = QuadKind::non_finite;
                return r;
            }
    r.quadric = world;
    r.local = local;
    return r;
}

}  // namespace quadcast
