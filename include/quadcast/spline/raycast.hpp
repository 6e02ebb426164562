// quadcast/spline/raycast.hpp -- ray vs one spline piece (tetrahedron) and vs one trilinear cell: first hit of an isosurface
#pragma once

// Shared templates (traceable): no branches on T values, fixed trip counts, explicit association.
// The ray is given in a tetrahedron's barycentric coordinates as beta(s) = beta0 + s * delta
// (delta = barycentric direction, Σ delta_m = 0) for s in [s_min, s_max]; the part of the ray
// inside the tetrahedron is where every beta_m >= 0 (Kalbe & Zeilfelder 2008, Sect. 5.3: the
// ray segment [w, w̄] in the tetrahedron; clipping by barycentric coordinates is implicit).

#include "quadcast/bb/bezier.hpp"
#include "quadcast/bb/restrict.hpp"
#include "quadcast/bb/roots.hpp"
#include "quadcast/linalg.hpp"
#include "quadcast/scalar.hpp"

namespace quadcast::spline {

/// The part [s_in, s_out] of the parameter interval [s_min, s_max] where beta0 + s delta has no
/// negative component, and the barycentric coordinates la, lb at its ends. `valid` iff the part
/// is non-empty (s_in <= s_out).
template <class T>
struct TetSegment {
    Vec<T, 4> la, lb;
    T s_in, s_out;
    mask_t<T> valid;
};

/// Clips the ray beta(s) = beta0 + s delta to the tetrahedron (all beta_m >= 0) and to
/// [s_min, s_max]: for delta_m > 0 the bound s >= -beta0_m / delta_m, for delta_m < 0 the bound
/// s <= -beta0_m / delta_m, for delta_m = 0 the ray must have beta0_m >= 0.
/// With `pad`, the tetrahedron is grown to beta_m >= -pad (a renderer that casts the pieces of
/// one ray independently, with slightly different rounding each, loses no root on a shared face).
/// Numerics: bound_m = -beta0_m / delta_m (one division, guarded by select; with a pad
/// -(beta0_m + pad) / delta_m); la = beta0 + s_in * delta, lb = beta0 + s_out * delta
/// componentwise (one mul + one add each).
template <class T>
TetSegment<T> clip_ray_to_tet(const Vec<T, 4>& beta0, const Vec<T, 4>& delta, const T& s_min, const T& s_max, const T* pad = nullptr) {
    T s_in = s_min, s_out = s_max;
    mask_t<T> ok = s_min <= s_max;
    for (int m = 0; m < 4; ++m) {
        const mask_t<T> pos = delta[m] > T(0), neg = delta[m] < T(0);
        const mask_t<T> nz = pos || neg;
        const T b = pad ? beta0[m] + *pad : beta0[m];
        const T bound = -b / select(nz, delta[m], T(1));
        s_in = select(pos, max(s_in, bound), s_in);
        s_out = select(neg, min(s_out, bound), s_out);
        ok = ok && (nz || b >= T(0));
    }
    TetSegment<T> r{};
    r.s_in = s_in;
    r.s_out = s_out;
    r.valid = ok && s_in <= s_out;
    for (int m = 0; m < 4; ++m) {
        r.la[m] = beta0[m] + s_in * delta[m];
        r.lb[m] = beta0[m] + s_out * delta[m];
    }
    return r;
}

/// First isosurface hit of a ray in one piece.
template <class T>
struct PieceHit {
    mask_t<T> hit;
    T s;                 ///< ray parameter of the hit (same parametrisation as the input)
    Vec<T, 4> lambda;    ///< barycentric coordinates of the hit
    Vec<T, 3> gradient;  ///< gradient with respect to the frame of `dirs` (cube-local for a spline piece)
};

/// The first root t in [0,1] of the univariate BB-form r minus rho: `quadratic_first_root`
/// (Q = 2) or the robust cubic `cubic_first_root` (Q = 3).
template <int Q, class T>
bb::UnitRoot<T> first_root(const Vec<T, Q + 1>& r, const T& rho) {
    static_assert(Q == 2 || Q == 3, "quadratic or cubic pieces");
    if constexpr (Q == 2) return bb::quadratic_first_root(r, rho);
    else return bb::cubic_first_root(r, rho);
}

/// The first hit of the isosurface p = rho on the ray beta0 + s delta, s in [s_min, s_max],
/// within one tetrahedron with BB-coefficients `c` (Kalbe & Zeilfelder 2008, Sect. 5.3):
/// clip to the tetrahedron (`clip_ray_to_tet`), restrict p to the segment [la, lb]
/// (`bb::restrict_to_segment`, blossoming), the first root of (r - rho) in [0,1] (`first_root`),
/// hit point lambda = la + t (lb - la), gradient from the (q-1)-th de Casteljau step with the
/// barycentric axis directions `dirs` (`bb::value_and_partials`, `bb::gradient`); `pad` grows
/// the tetrahedron as in `clip_ray_to_tet`.
/// Numerics: s = s_in + t * (s_out - s_in); lambda_m = la_m + t * (lb_m - la_m).
template <int Q, class T>
PieceHit<T> intersect_piece(const bb::BezierTet<T, Q>& c, const Vec<T, 4>& beta0, const Vec<T, 4>& delta, const T& s_min,
                            const T& s_max, const T& rho, const Mat<T, 4, 3>& dirs, const T* pad = nullptr) {
    const TetSegment<T> seg = clip_ray_to_tet(beta0, delta, s_min, s_max, pad);
    const Vec<T, Q + 1> r = bb::restrict_to_segment(c, seg.la, seg.lb);
    const bb::UnitRoot<T> root = first_root<Q>(r, rho);
    const T t = root.t;
    PieceHit<T> h{};
    h.hit = seg.valid && root.hit;
    h.s = seg.s_in + t * (seg.s_out - seg.s_in);
    for (int m = 0; m < 4; ++m) h.lambda[m] = seg.la[m] + t * (seg.lb[m] - seg.la[m]);
    const bb::ValueAndPartials<T> vp = bb::value_and_partials(c, h.lambda);
    h.gradient = bb::gradient(vp, dirs);
    return h;
}

// ---- Trilinear interpolation -------------------------------------------------------------------

/// The 8 corner values of a cell [0,1]^3
/// (x fastest), i.e. corner (i,j,k) at v[i + 2*j + 4*k].
template <class T>
using CellCorners = Vec<T, 8>;

/// Trilinear interpolant on [0,1]^3 at w: lerp in x, then y, then z.
/// Numerics: lerp(a, b, x) = a + x * (b - a); x first (4 lerps), then y (2), then z (1).
template <class T>
T trilinear_value(const CellCorners<T>& v, const Vec<T, 3>& w) {
    const T x00 = v[0] + w[0] * (v[1] - v[0]);
    const T x10 = v[2] + w[0] * (v[3] - v[2]);
    const T x01 = v[4] + w[0] * (v[5] - v[4]);
    const T x11 = v[6] + w[0] * (v[7] - v[6]);
    const T y0 = x00 + w[1] * (x10 - x00);
    const T y1 = x01 + w[1] * (x11 - x01);
    return y0 + w[2] * (y1 - y0);
}

/// Gradient of the trilinear interpolant on [0,1]^3 at w (cell-local units).
/// Numerics: each partial is the interpolant of the corner differences along that axis,
/// by `trilinear_value`'s lerp order over the remaining two axes.
template <class T>
Vec<T, 3> trilinear_gradient(const CellCorners<T>& v, const Vec<T, 3>& w) {
    // d/dx: differences along x, bilinear in (y, z).
    const T dx0 = v[1] - v[0], dx1 = v[3] - v[2], dx2 = v[5] - v[4], dx3 = v[7] - v[6];
    const T gx0 = dx0 + w[1] * (dx1 - dx0), gx1 = dx2 + w[1] * (dx3 - dx2);
    // d/dy: differences along y, bilinear in (x, z).
    const T dy0 = v[2] - v[0], dy1 = v[3] - v[1], dy2 = v[6] - v[4], dy3 = v[7] - v[5];
    const T gy0 = dy0 + w[0] * (dy1 - dy0), gy1 = dy2 + w[0] * (dy3 - dy2);
    // d/dz: differences along z, bilinear in (x, y).
    const T dz0 = v[4] - v[0], dz1 = v[5] - v[1], dz2 = v[6] - v[2], dz3 = v[7] - v[3];
    const T gz0 = dz0 + w[0] * (dz1 - dz0), gz1 = dz2 + w[0] * (dz3 - dz2);
    return {{gx0 + w[2] * (gx1 - gx0), gy0 + w[2] * (gy1 - gy0), gz0 + w[1] * (gz1 - gz0)}};
}

/// Univariate cubic BB-form of the trilinear interpolant along the segment a -> b (cell-local
/// points): the interpolant is affine in each of x, y, z separately, so its blossom on the line
/// is the symmetrisation over which coordinates come from b: c0 = f(a), c3 = f(b),
/// c1 = (f(bx,ay,az) + f(ax,by,az) + f(ax,ay,bz)) / 3, c2 = (f(ax,by,bz) + f(bx,ay,bz) + f(bx,by,az)) / 3.
/// Numerics: the mixed values by `trilinear_value`; ((f1 + f2) + f3) * T(1/3) rounded to T.
template <class T>
Vec<T, 4> trilinear_restrict_to_segment(const CellCorners<T>& v, const Vec<T, 3>& a, const Vec<T, 3>& b) {
    const T third = T(1.0 / 3.0);
    const T c1 = ((trilinear_value(v, Vec<T, 3>{{b[0], a[1], a[2]}}) + trilinear_value(v, Vec<T, 3>{{a[0], b[1], a[2]}})) +
                  trilinear_value(v, Vec<T, 3>{{a[0], a[1], b[2]}})) *
                 third;
    const T c2 = ((trilinear_value(v, Vec<T, 3>{{a[0], b[1], b[2]}}) + trilinear_value(v, Vec<T, 3>{{b[0], a[1], b[2]}})) +
                  trilinear_value(v, Vec<T, 3>{{b[0], b[1], a[2]}})) *
                 third;
    return {{trilinear_value(v, a), c1, c2, trilinear_value(v, b)}};
}

/// First hit of the trilinear isosurface f = rho on the ray w(s) = w0 + s d (cell-local, the
/// cell is [0,1]^3) for s in [s_min, s_max] (the caller's clip of the ray to the cell): the
/// cubic BB-form on the segment (`trilinear_restrict_to_segment`), its first root by the robust
/// `bb::cubic_first_root`, gradient by `trilinear_gradient` (cell-local units).
/// Numerics: a = w0 + s_min d, b = w0 + s_max d componentwise; s = s_min + t (s_max - s_min).
template <class T>
PieceHit<T> intersect_trilinear_cell(const CellCorners<T>& v, const Vec<T, 3>& w0, const Vec<T, 3>& d, const T& s_min,
                                     const T& s_max, const T& rho) {
    Vec<T, 3> a{}, b{};
    for (int i = 0; i < 3; ++i) {
        a[i] = w0[i] + s_min * d[i];
        b[i] = w0[i] + s_max * d[i];
    }
    const Vec<T, 4> r = trilinear_restrict_to_segment(v, a, b);
    const bb::UnitRoot<T> root = bb::cubic_first_root(r, rho);
    PieceHit<T> h{};
    h.hit = root.hit && s_min <= s_max;
    h.s = s_min + root.t * (s_max - s_min);
    Vec<T, 3> w{};
    for (int i = 0; i < 3; ++i) w[i] = a[i] + root.t * (b[i] - a[i]);
    h.lambda = Vec<T, 4>{{w[0], w[1], w[2], T(0)}};
    h.gradient = trilinear_gradient(v, w);
    return h;
}

}  // namespace quadcast::spline
