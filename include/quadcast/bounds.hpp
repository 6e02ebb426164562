// quadcast/bounds.hpp -- screen-space bounds and window-space ray casting of parameter-space quadrics
#pragma once

#include "quadcast/linalg.hpp"
#include "quadcast/primitives.hpp"
#include "quadcast/quadric.hpp"
#include "quadcast/scalar.hpp"

namespace quadcast {

// Coordinates follow Sigg et al. 2006, fig. 3: parameter (p) -T-> object -M-> eye -P-> clip
// -divide-> NDC -V-> window. `pmt` is the compound P * M * T, `vpmt_inv` is (V * P * M * T)^-1.
//
// The box of eq. 5 is in NDC. The paper says "clip coordinates", but the half-space
// n_c^T x_c <= 0 with n_c = (1, 0, 0, -b_x) reads x_c <= b_x w_c, i.e. x_c / w_c <= b_x for
// w_c > 0: b_x is the NDC coordinate x_c / w_c of the bounding line. Every such plane contains
// the eye (clip (0, 0, z, 0)), so it is a plane through the eye touching the quadric. The same
// holds for Sigg's centre v_c = (r1 D r4, r2 D r4, 0, r4 D r4): divided by its w it is the NDC
// midpoint (b_1 + b_2) / 2 = (r1 D r4) / (r4 D r4) of the two roots.

/// Axis-aligned NDC rectangle [lo.x, hi.x] x [lo.y, hi.y] with a validity mask.
/// `valid` is true when the (clipped) primitive lies strictly in front of the eye plane
/// (w_c > 0 everywhere on it) and the rectangle bounds its projection. When it is false the
/// rectangle is the full screen [-1, 1]^2, a safe fallback (the primitive straddles or lies
/// behind the eye plane, contains the eye, or the input was degenerate).
template <class T>
struct ScreenBox {
    Vec2<T> lo;
    Vec2<T> hi;
    mask_t<T> valid;
};

/// NDC midpoint of a box.
/// Numerics: (lo + hi) * 0.5 per component.
template <class T>
Vec2<T> box_center(const ScreenBox<T>& b) {
    return vec2((b.lo[0] + b.hi[0]) * T(0.5), (b.lo[1] + b.hi[1]) * T(0.5));
}

/// Window rectangle (x0, y0, x1, y1) of an NDC box for the viewport (x, y, width, height):
/// x_w = x + (x_ndc + 1) * width / 2.
/// Numerics: x + ((x_ndc + 1) * (width * 0.5)).
template <class T>
Vec4<T> window_rect(const ScreenBox<T>& b, const Vec4<T>& viewport) {
    const T hw = viewport[2] * T(0.5), hh = viewport[3] * T(0.5);
    return vec4(viewport[0] + (b.lo[0] + T(1)) * hw, viewport[1] + (b.lo[1] + T(1)) * hh,
                viewport[0] + (b.hi[0] + T(1)) * hw, viewport[1] + (b.hi[1] + T(1)) * hh);
}

/// Coefficients of the pencil quadratic a b^2 - 2 beta b + c = 0 of two vectors x, y under the
/// diagonal metric w: a = y^T W y, beta = x^T W y, c = x^T W x, and its discriminant
/// disc = beta^2 - a c.
template <class T>
struct PencilQuadratic {
    T a, beta, c, disc;
};

/// `PencilQuadratic` of x and y with weights w (Sigg et al. 2006, eq. 5 with W = D).
/// The discriminant is evaluated by the Lagrange identity
/// beta^2 - a c = -sum_{i<j} w_i w_j (x_i y_j - x_j y_i)^2,
/// which avoids the cancellation of beta^2 against a c for small or distant quadrics.
/// Numerics: a, beta, c are `dot(cmul(w, .), .)` (left folds); disc is a left fold over the
/// pairs (0,1), (0,2), ... (N-2,N-1) of -((w_i * w_j) * (m_ij * m_ij)), m_ij = x_i * y_j - x_j * y_i.
template <class T, int N>
PencilQuadratic<T> pencil_quadratic(const Vec<T, N>& x, const Vec<T, N>& y, const Vec<T, N>& w) {
    // Evaluate the three bilinear forms
    const Vec<T, N> wy = cmul(w, y);
    const T a = dot(wy, y);
    const T beta = dot(wy, x);
    const T c = dot(cmul(w, x), x);
    // Sum the weighted squared 2x2 minors
    T disc{};
    for (int i = 0; i < N; ++i) {
        for (int j = i + 1; j < N; ++j) {
            const T m = x[i] * y[j] - x[j] * y[i];
            const T term = (w[i] * w[j]) * (m * m);
            if (i == 0 && j == 1) disc = -term;
            else disc = disc - term;
        }
    }
    return {a, beta, c, disc};
}

/// The two roots of a b^2 - 2 beta b + c = 0, sorted, and whether they are real and finite.
template <class T>
struct PencilRoots {
    T lo, hi;
    mask_t<T> real;
};

/// Roots of `PencilQuadratic` by the stable formula q = beta + sign(beta) sqrt(disc),
/// b_1 = q / a, b_2 = c / q (no cancellation in q). A vanishing a leaves the single root c / q
/// (both outputs); a vanishing q (beta = disc = 0) the double root 0 = q / a.
/// `real` is false when disc < 0 or a = q = 0. Unselected divisions are guarded.
/// Numerics: q = beta + sign_nonzero(beta) * sqrt(max(disc, 0)); then one division each.
template <class T>
PencilRoots<T> pencil_roots(const PencilQuadratic<T>& pq) {
    // Take the root of larger magnitude without cancellation, the other by Vieta
    const T s = sqrt(max(pq.disc, T(0)));
    const T q = pq.beta + sign_nonzero(pq.beta) * s;
    const mask_t<T> a_ok = pq.a != T(0);
    const mask_t<T> q_ok = q != T(0);
    const T by_q = pq.c / select(q_ok, q, T(1));
    const T by_a = q / select(a_ok, pq.a, T(1));
    const T r1 = select(a_ok, by_a, by_q);
    const T r2 = select(q_ok, by_q, by_a);
    return {min(r1, r2), max(r1, r2), (pq.disc >= T(0)) && (a_ok || q_ok)};
}

namespace detail {

/// Bounds of one axis of a nondegenerate ellipsoid-type form: roots of eq. 5 and the midpoint.
template <class T>
struct AxisSpan {
    T lo, hi, mid;
};

template <class T>
ScreenBox<T> full_screen(const mask_t<T>& valid) {
    return {vec2(T(-1), T(-1)), vec2(T(1), T(1)), valid};
}

template <class T>
ScreenBox<T> or_full_screen(const ScreenBox<T>& b) {
    return {select(b.valid, b.lo, vec2(T(-1), T(-1))), select(b.valid, b.hi, vec2(T(1), T(1))), b.valid};
}

/// Slab membership of a homogeneous parameter-space point given by z = num / den, without the
/// division: den != 0, (num - lo den) den >= 0 and (hi den - num) den >= 0.
template <class T>
mask_t<T> in_slab_ratio(const T& num, const T& den, const Vec2<T>& slab) {
    return (den != T(0)) && ((num - slab[0] * den) * den >= T(0)) && ((slab[1] * den - num) * den >= T(0));
}

}  // namespace detail

/// Sigg's screen-space bounding box of an ellipsoid (Sigg et al. 2006, eq. 3-5): the NDC lines
/// x = b touching the quadric are the roots of (r4 D r4) b^2 - 2 (r1 D r4) b + (r1 D r1) = 0 (r2
/// for y), r_i the rows of `pmt` = P * M * T. `d` must be (1, 1, 1, -1) (D = D^-1 is also the
/// dual quadric of the unit sphere, so n^T D n = 0 is the tangency condition of eq. 4).
/// Valid iff the eye plane w_c = 0 (the plane r4 in parameter space) misses the unit sphere,
/// r4 D r4 < 0, and the centre is in front, r4_w > 0; otherwise the full screen with valid = false.
/// Numerics: `pencil_quadratic` (Lagrange-identity discriminant) and `pencil_roots`.
template <class T>
ScreenBox<T> sigg_bbox(const Mat4<T>& pmt, const Vec4<T>& d) {
    // Pull the clip-space planes x_c = 0, y_c = 0, w_c = 0 back to parameter space
    const Vec4<T> r1 = row(pmt, 0), r2 = row(pmt, 1), r4 = row(pmt, 3);
    const PencilQuadratic<T> qx = pencil_quadratic(r1, r4, d);
    const PencilQuadratic<T> qy = pencil_quadratic(r2, r4, d);
    // Accept only a quadric strictly in front of the eye plane
    const mask_t<T> valid = (qx.a < T(0)) && (r4[3] > T(0));
    const PencilRoots<T> bx = pencil_roots(qx), by = pencil_roots(qy);
    return detail::or_full_screen(ScreenBox<T>{vec2(bx.lo, by.lo), vec2(bx.hi, by.hi), valid && bx.real && by.real});
}

/// Sigg's point-sprite centre in homogeneous clip coordinates (Sigg et al. 2006, sec. 3.2):
/// v_c = (r1 D r4, r2 D r4, 0, r4 D r4). Divided by its w it is the midpoint of `sigg_bbox`.
/// Numerics: each entry `dot(cmul(d, r4), r_i)`.
template <class T>
Vec4<T> sigg_center(const Mat4<T>& pmt, const Vec4<T>& d) {
    const Vec4<T> dr4 = cmul(d, row(pmt, 3));
    return vec4(dot(dr4, row(pmt, 0)), dot(dr4, row(pmt, 1)), T(0), dot(dr4, row(pmt, 3)));
}

/// Bounding box of the planar slab section ("ellipsoidal cap") of a primitive with
/// D = (1, 1, d2, d3) at parameter height z = h: the ellipse x^2 + y^2 = rho2, z = h (a point
/// when rho2 = 0). Its dual is C = diag(rho2, rho2, 0, 0) - e e^T with e = (0, 0, h, 1): a plane
/// n touches the ellipse iff rho2 (n_x^2 + n_y^2) = (h n_z + n_w)^2. Substituting n = r1 - b r4
/// gives eq. 5 with C in place of D (Sigg et al. 2006, sec. 3.2, cylinders).
/// Valid iff the eye plane misses the cap disc (r4 C r4 < 0) and the cap centre is in front
/// (e . r4 > 0). rho2 < 0 (no section) is treated as the point rho2 = 0.
/// Numerics: with x' = (x_0, x_1, e . x) and weights (rho2, rho2, -1), `pencil_quadratic` on
/// the 3-vectors; e . x = (h * x_z) + x_w.
template <class T>
ScreenBox<T> cap_bbox(const Mat4<T>& pmt, const T& h, const T& rho2_in) {
    // Reduce the rows to the cap's 3-dimensional dual form
    const T rho2 = max(rho2_in, T(0));
    const Vec4<T> r1 = row(pmt, 0), r2 = row(pmt, 1), r4 = row(pmt, 3);
    const Vec3<T> w = vec3(rho2, rho2, T(-1));
    const Vec3<T> x1 = vec3(r1[0], r1[1], h * r1[2] + r1[3]);
    const Vec3<T> x2 = vec3(r2[0], r2[1], h * r2[2] + r2[3]);
    const Vec3<T> x4 = vec3(r4[0], r4[1], h * r4[2] + r4[3]);
    const PencilQuadratic<T> qx = pencil_quadratic(x1, x4, w);
    const PencilQuadratic<T> qy = pencil_quadratic(x2, x4, w);
    // Accept only a cap strictly in front of the eye plane
    const mask_t<T> valid = (qx.a < T(0)) && (x4[2] > T(0));
    const PencilRoots<T> bx = pencil_roots(qx), by = pencil_roots(qy);
    return detail::or_full_screen(ScreenBox<T>{vec2(bx.lo, by.lo), vec2(bx.hi, by.hi), valid && bx.real && by.real});
}

/// Smallest box containing both; valid only if both are.
template <class T>
ScreenBox<T> box_union(const ScreenBox<T>& a, const ScreenBox<T>& b) {
    return detail::or_full_screen(ScreenBox<T>{vec2(min(a.lo[0], b.lo[0]), min(a.lo[1], b.lo[1])),
                                               vec2(max(a.hi[0], b.hi[0]), max(a.hi[1], b.hi[1])),
                                               a.valid && b.valid});
}

/// Bounding box of a slab-clipped primitive with D = (1, 1, d2, d3) and parameter-space clip
/// range z_lo <= z <= z_hi: the union of the two cap boxes (`cap_bbox`), and, when
/// `silhouette` is set, the roots of eq. 5 whose touching point lies inside the slab.
/// The extreme of x_ndc over the clipped surface is either on a cap curve or an interior point
/// where the plane x = b w touches the surface (a root of eq. 5), so the box is tight.
/// For ruled kinds (cylinder, cone, one-sheet hyperboloid) every surface point lies on a segment
/// between the caps: pass `silhouette = false`. Otherwise (paraboloid, two-sheet hyperboloid,
/// clipped ellipsoid; requires d2, d3 != 0 so that D^-1 = D) the touching point of the plane
/// n = r1 - b r4 is p = D n, inside iff z_lo <= d2 n_z / (d3 n_w) <= z_hi.
/// Validity: both caps in front, and (silhouette) every in-slab critical point of w_c on the
/// surface in front: the levels s = r4_w -+ sqrt(-d3 (n_x^2 + n_y^2 + d2 n_z^2)) (n = r4) where
/// the plane r4 . p = s p_w touches the surface, their touching points p = D (r4 - s e_w).
/// `silhouette` is a host-side switch (plain bool), not traced data.
/// Numerics: as `cap_bbox` and `pencil_roots`; the touching point of a root b is
/// n = r1 - b * r4 (per component).
template <class T>
ScreenBox<T> slab_bbox(const Mat4<T>& pmt, const Vec4<T>& d, const Vec2<T>& slab, bool silhouette) {
    // Bound the two caps
    const ScreenBox<T> lo_cap = cap_bbox(pmt, slab[0], section_radius2(d, slab[0]));
    const ScreenBox<T> hi_cap = cap_bbox(pmt, slab[1], section_radius2(d, slab[1]));
    ScreenBox<T> box = box_union(lo_cap, hi_cap);
    if (!silhouette) return box;

    const Vec4<T> r4 = row(pmt, 3);
    // Check the in-slab extremes of w_c on the surface
    const T g = -(d[3] * ((r4[0] * r4[0] + r4[1] * r4[1]) + (d[2] * r4[2]) * r4[2]));
    const mask_t<T> g_ok = g >= T(0);
    const T sg = sqrt(select(g_ok, g, T(0)));
    const T zn = d[2] * r4[2];
    mask_t<T> valid = box.valid;
    for (int k = 0; k < 2; ++k) {
        const T root = k == 0 ? -sg : sg;           // x_w - s
        const T level = r4[3] - root;               // s
        const mask_t<T> inside = g_ok && detail::in_slab_ratio(zn, d[3] * root, slab);
        valid = valid && !(inside && (level <= T(0)));
    }

    // Add the touching points of eq. 5 that lie inside the slab
    Vec2<T> lo = box.lo, hi = box.hi;
    for (int axis = 0; axis < 2; ++axis) {
        const Vec4<T> ri = row(pmt, axis);
        const PencilRoots<T> b = pencil_roots(pencil_quadratic(ri, r4, d));
        for (int k = 0; k < 2; ++k) {
            const T bk = k == 0 ? b.lo : b.hi;
            const Vec4<T> n = ri - r4 * bk;
            const mask_t<T> inside = b.real && detail::in_slab_ratio(d[2] * n[2], d[3] * n[3], slab);
            lo[axis] = select(inside, min(lo[axis], bk), lo[axis]);
            hi[axis] = select(inside, max(hi[axis], bk), hi[axis]);
        }
    }
    return detail::or_full_screen(ScreenBox<T>{lo, hi, valid});
}

/// Screen-space bounding box of a primitive for the compound matrix `pmt` = P * M * prim.t:
/// `sigg_bbox` for ellipsoids, `slab_bbox` (caps, plus the silhouette for non-ruled kinds)
/// otherwise. Dispatches on the host-side kind.
template <class T>
ScreenBox<T> primitive_bbox(const Mat4<T>& pmt, const ParameterForm<T>& prim) {
    if (!is_clipped(prim.kind)) return sigg_bbox(pmt, prim.d);
    return slab_bbox(pmt, prim.d, prim.slab, !is_ruled(prim.kind));
}

// Ray casting in window coordinates ------------------------------------------------------------

/// Both intersections of the viewing ray of a pixel with a quadric, parametrised by window
/// depth z_w (Sigg et al. 2006, eq. 6-7).
template <class T>
struct WindowHit {
    mask_t<T> hit;   ///< the ray meets the (unclipped) quadric: real roots
    T z_near, z_far; ///< window depths, z_near <= z_far (equal for a tangent or linear case)
    Vec4<T> p_near;  ///< homogeneous parameter-space point x'_p + z_near c_3
    Vec4<T> p_far;   ///< homogeneous parameter-space point x'_p + z_far c_3
};

/// Ray-quadric intersection in window coordinates (Sigg et al. 2006, eq. 6-7): the ray
/// x_w = (x_w, y_w, 0, 1) + z_w (0, 0, 1, 0) is x_p = x'_p + z_w c_3 in parameter space, with
/// x'_p = (VPMT)^-1 (x_w, y_w, 0, 1) and c_3 the third column of (VPMT)^-1; then
/// (c3 D c3) z^2 + 2 (x'_p D c3) z + (x'_p D x'_p) = 0.
/// Roots by the stable formula q = -(B + sign(B) sqrt(B^2 - A C)), z = q / A and C / q, sorted
/// ascending: for points in front of the eye a smaller window depth is closer (points behind the
/// eye map beyond the far plane, z_w > 1), so z_near is the visible hit when it is in [0, 1].
/// Conditioning: for a distant hit x'_p and z c_3 nearly cancel (window depth crowds towards 1),
/// so in float the hit point carries an error of order eps * (distance / near) relative to
/// the hit distance, as the depth buffer does; the window-space form cannot do better.
/// Numerics: x'_p = (m0 * x_w + m1 * y_w) + m3 per component; A, B, C and the discriminant as
/// `pencil_quadratic(x'_p, c3, d)` (b = -z, Lagrange-identity discriminant); `pencil_roots`;
/// p = x'_p + c3 * z per component.
template <class T>
WindowHit<T> intersect_window(const Mat4<T>& vpmt_inv, const Vec4<T>& d, const T& xw, const T& yw) {
    // Transform the front-plane point and the ray direction to parameter space
    const Vec4<T> c3 = vpmt_inv[2];
    Vec4<T> x0{};
    for (int i = 0; i < 4; ++i) x0[i] = (vpmt_inv[0][i] * xw + vpmt_inv[1][i] * yw) + vpmt_inv[3][i];
    // Solve (c3 D c3) z^2 + 2 (x0 D c3) z + x0 D x0 = 0, i.e. eq. 5's form in b = -z
    const PencilQuadratic<T> pq = pencil_quadratic(x0, c3, d);
    const PencilRoots<T> b = pencil_roots(pq);
    const T z_near = -b.hi, z_far = -b.lo;
    return {b.real, z_near, z_far, x0 + c3 * z_near, x0 + c3 * z_far};
}

/// The nearest of the two hits whose parameter-space point lies in the slab z_lo <= z <= z_hi
/// (for clipped primitives; an ellipsoid lies inside its slab [-1, 1], so it gets `z_near`).
template <class T>
struct SurfaceHit {
    mask_t<T> hit;
    T z;          ///< window depth
    Vec4<T> p;    ///< homogeneous parameter-space point
};

/// First root of `intersect_window` whose point is inside the slab (near, else far).
/// Numerics: slab test without division, (p_z - lo p_w) p_w >= 0 and (hi p_w - p_z) p_w >= 0.
template <class T>
SurfaceHit<T> nearest_in_slab(const WindowHit<T>& h, const Vec2<T>& slab) {
    const mask_t<T> near_in = h.hit && detail::in_slab_ratio(h.p_near[2], h.p_near[3], slab);
    const mask_t<T> far_in = h.hit && detail::in_slab_ratio(h.p_far[2], h.p_far[3], slab);
    return {near_in || far_in, select(near_in, h.z_near, h.z_far), select(near_in, h.p_near, h.p_far)};
}

/// Homogeneous eye-space position of a window point (Sigg et al. 2006, eq. 8):
/// p_e = (V P)^-1 (x_w, y_w, z_w, 1). Divide by its w for the 3D point.
/// Numerics: ((m0 * x_w + m1 * y_w) + m2 * z_w) + m3 per component.
template <class T>
Vec4<T> window_to_eye(const Mat4<T>& vp_inv, const T& xw, const T& yw, const T& zw) {
    Vec4<T> r{};
    for (int i = 0; i < 4; ++i) r[i] = ((vp_inv[0][i] * xw + vp_inv[1][i] * yw) + vp_inv[2][i] * zw) + vp_inv[3][i];
    return r;
}

/// Eye-space surface normal (Sigg et al. 2006, eq. 9): n_e = (M T)^-T n_p with the
/// parameter-space tangent plane n_p = D p, oriented outwards (towards p^T D p > 0) by the sign
/// of the eye-space homogeneous w of the same point (`window_to_eye(...)[3]`; positive for
/// points in front of the eye). Not normalised.
/// Numerics: `mt_inv_t * cmul(d, p)` (row dot products, left folds), xyz times sign_nonzero(w_e).
template <class T>
Vec3<T> eye_normal(const Mat4<T>& mt_inv_t, const Vec4<T>& d, const Vec4<T>& p, const T& w_e) {
    return xyz(mt_inv_t * cmul(d, p)) * sign_nonzero(w_e);
}

// Tight screen rectangles of the renderers' primitives ------------------------------------------

/// The NDC rectangle [lo, hi] over which a renderer draws a primitive.
/// `tight`: the rectangle bounds the primitive's projection, padded (`dual_rect`); where that is
/// not safe (the bound reaches the near plane or contains the eye, a degenerate form, non-finite
/// numbers) it is false and the renderer draws its bounding-sphere quad instead.
/// `visible` is false when the bound lies entirely behind the eye plane (nothing can be hit);
/// the rectangle is then the empty point (2, 2).
template <class T>
struct ScreenRect {
    Vec2<T> lo, hi;
    mask_t<T> tight;
    mask_t<T> visible;
};

/// A convex bound given by its dual: the set {e + U z : |z| <= 1} (an ellipsoid, or a flat
/// ellipse, or a point) for W = U U^T, in the primitive's local coordinates. A plane n (homogeneous,
/// local) misses it iff (n . (e, 1))^2 > n_xyz^T W n_xyz, and touches it iff they are equal.
template <class T>
struct DualBound {
    Vec3<T> e;
    Mat3<T> w;
    mask_t<T> ok;  ///< the form is usable (finite, non-degenerate where that matters)
};

/// The `DualBound` of a sphere of radius r around the local origin (e = 0, W = r^2 I), kept apart
/// so that no product with a zero is traced.
template <class T>
struct SphereDual {
    T r2;
    mask_t<T> ok;
};

/// n . (e, 1) and W v of each dual form.
template <class T>
T dual_center_dot(const DualBound<T>& d, const Vec4<T>& n) { return dot(xyz(n), d.e) + n[3]; }
template <class T>
T dual_center_dot(const SphereDual<T>&, const Vec4<T>& n) { return n[3]; }
template <class T>
Vec3<T> dual_apply(const DualBound<T>& d, const Vec3<T>& v) { return d.w * v; }
template <class T>
Vec3<T> dual_apply(const SphereDual<T>& d, const Vec3<T>& v) { return v * d.r2; }

namespace detail {

/// One NDC axis of a `DualBound` for the local -> clip rows r_i (axis) and r_4 (w): the lines
/// x_ndc = b touching the bound are the planes n = r_i - b r_4 with (n . e~)^2 = n W n. Around
/// the centre's own coordinate b0 = (r_i . e~) / (r_4 . e~) (e~ = (e, 1)), b = b0 + t gives
/// a t^2 + 2 beta t - c = 0 with a = x4^2 - v W v, beta = u W v, c = u W u (x4 = r_4 . e~,
/// u = r_i,xyz - b0 r_4,xyz, v = r_4,xyz): a > 0 iff the eye plane misses the bound, and then
/// both roots are real and the discriminant beta^2 + a c is a sum of non-negative terms (no
/// cancellation however small or distant the bound). `clear`: a > 2^-10 x4^2 and x4 > 0.
/// Numerics: dots are left folds; roots by q = beta + sign(beta) sqrt(beta^2 + a c),
/// t = -q / a and c / q.
template <class T, class D>
void dual_span(const Vec4<T>& ri, const Vec4<T>& r4, const D& d, T& lo, T& hi, T& b0_abs, mask_t<T>& clear) {
    // Project the centre
    const Vec3<T> v = xyz(r4);
    const T x4 = dual_center_dot(d, r4);
    const T xi = dual_center_dot(d, ri);
    const mask_t<T> x4_ok = x4 > T(0);
    const T b0 = xi / select(x4_ok, x4, T(1));
    // Solve for the offsets of the two touching lines
    const Vec3<T> u = xyz(ri) - v * b0;
    const Vec3<T> wv = dual_apply(d, v);
    const T a = x4 * x4 - dot(v, wv);
    const T beta = dot(u, wv);
    const T c = max(dot(u, dual_apply(d, u)), T(0));
    clear = x4_ok && (a > T(0.0009765625) * (x4 * x4));
    const T a_safe = select(clear, a, T(1));
    const T s = sqrt(max(beta * beta + a_safe * c, T(0)));
    const T q = beta + sign_nonzero(beta) * s;
    const mask_t<T> q_ok = q != T(0);
    const T t1 = -q / a_safe;
    const T t2 = select(q_ok, c / select(q_ok, q, T(1)), T(0));
    lo = b0 + min(t1, t2);
    hi = b0 + max(t1, t2);
    b0_abs = abs(b0);
}

/// Whether the plane n (local, homogeneous) leaves the bound strictly on its positive side, with
/// a margin: n . e~ > 0 and (n . e~)^2 > (1 + 2^-10) n W n.
template <class T, class D>
mask_t<T> dual_beyond(const Vec4<T>& n, const D& d) {
    const T x = dual_center_dot(d, n);
    const T nwn = dot(xyz(n), dual_apply(d, xyz(n)));
    return (x > T(0)) && (x * x > nwn + T(0.0009765625) * nwn);
}

/// The rows of the local -> clip matrix: rows of view_projection translated by the centre
/// (r_xyz, r_xyz . center + r_w).
template <class T>
Vec4<T> local_clip_row(const Mat4<T>& view_projection, const Vec3<T>& center, int i) {
    const Vec4<T> r = row(view_projection, i);
    return vec4(r[0], r[1], r[2], dot(xyz(r), center) + r[3]);
}

}  // namespace detail

/// The padded NDC rectangle of a `DualBound` (local coordinates around `center`) under
/// `view_projection` (world -> clip, perspective or orthographic), for a viewport of
/// `viewport` = (width, height) pixels (Sigg et al. 2006, eq. 5, in the dual-ellipsoid form of
/// `detail::dual_span`).
/// tight iff the bound lies beyond the near plane with a margin (`detail::dual_beyond` of the
/// plane z_c + w_c = 0; it then lies in front of the eye plane too) and both spans are clear
/// and finite. visible is false iff the bound lies behind the eye plane (w_c < 0).
/// Padding per axis: 1/16 pixel + 2^-10 of the span + 2^-16 |b0| (the rounding of the centre's
/// coordinate; the float rounding of the whole computation is of order 2^-20 of these), then
/// clamped to [-2, 2] (beyond the screen, a smaller rectangle rasterises alike).
/// Numerics: as `detail::dual_span`; the pixel is 2 / width in NDC.
template <class T, class D>
ScreenRect<T> dual_rect(const Mat4<T>& view_projection, const Vec3<T>& center, const D& d, const Vec2<T>& viewport) {
    // Pull the clip-space rows back to local coordinates
    const Vec4<T> r1 = detail::local_clip_row(view_projection, center, 0);
    const Vec4<T> r2 = detail::local_clip_row(view_projection, center, 1);
    const Vec4<T> r3 = detail::local_clip_row(view_projection, center, 2);
    const Vec4<T> r4 = detail::local_clip_row(view_projection, center, 3);
    // Bound both axes
    T lo[2], hi[2], b0[2];
    mask_t<T> clear[2];
    detail::dual_span(r1, r4, d, lo[0], hi[0], b0[0], clear[0]);
    detail::dual_span(r2, r4, d, lo[1], hi[1], b0[1], clear[1]);
    const mask_t<T> beyond_near = detail::dual_beyond(r3 + r4, d);
    const mask_t<T> behind = detail::dual_beyond(-r4, d);
    // Pad, clamp and check
    ScreenRect<T> out{};
    mask_t<T> tight = ((d.ok && beyond_near) && clear[0]) && clear[1];
    for (int k = 0; k < 2; ++k) {
        const T pixel = T(2) / viewport[k];
        const T pad = (pixel * T(0.0625) + (hi[k] - lo[k]) * T(0.0009765625)) + b0[k] * T(0.0000152587890625);
        const T l = lo[k] - pad, h = hi[k] + pad;
        tight = tight && (l <= h);  // false for NaN
        out.lo[k] = select(behind, T(2), min(max(l, T(-2)), T(2)));
        out.hi[k] = select(behind, T(2), min(max(h, T(-2)), T(2)));
    }
    out.tight = tight || behind;
    out.visible = !behind;
    return out;
}

/// `SphereDual` of a sphere of radius r around the local origin: e = 0, W = r^2 I.
template <class T>
SphereDual<T> sphere_dual(const T& r) {
    const T r2 = r * r;
    return {r2, r2 > T(0)};
}

/// `DualBound` of the ellipsoid x^T A x + 2 b.x + c <= 0 (either sign of Q; local coordinates):
/// centre m = -A^-1 b, W = -s A^-1 with s = c + b.m (Q^-1 scaled by s is [W' + m m^T, m; m^T, 1]
/// up to sign, so a plane n touches it iff (n . (m, 1))^2 = n^T W n). A is divided by its trace
/// before the inverse (scale-free determinant); ok iff that determinant exceeds 2^-30 and W is
/// positive (the ellipsoid is real).
/// Numerics: `inverse` (adjugate) of A / tr(A); then divisions by tr(A).
template <class T>
DualBound<T> ellipsoid_dual(const Quadric<T>& q) {
    // Invert A at unit scale
    const Mat3<T> a = upper3(q.q);
    const Vec3<T> b = xyz(q.q[3]);
    const T tr = (a[0][0] + a[1][1]) + a[2][2];
    const mask_t<T> tr_ok = tr != T(0);
    const T trs = select(tr_ok, tr, T(1));
    Mat3<T> an{};
    for (int j = 0; j < 3; ++j) an[j] = a[j] / trs;
    T det_n = T(0);
    const T dt = det(an);
    const mask_t<T> det_ok = tr_ok && (dt > T(0.000000000931322574615478515625));
    Mat3<T> m_safe = an;
    for (int i = 0; i < 3; ++i) m_safe[i][i] = select(det_ok, an[i][i], T(1));
    for (int j = 0; j < 3; ++j)
        for (int i = 0; i < 3; ++i)
            if (i != j) m_safe[j][i] = select(det_ok, an[j][i], T(0));
    const Mat3<T> inv_n = inverse(m_safe, det_n);  // tr A^-1
    // Centre and dual metric
    const Vec3<T> m = -(inv_n * b) / trs;
    const T s = q.q[3][3] + dot(b, m);
    const T k = -s / trs;
    DualBound<T> d{};
    d.e = m;
    for (int j = 0; j < 3; ++j) d.w[j] = inv_n[j] * k;
    d.ok = det_ok && (k > T(0));
    return d;
}

/// An orthonormal basis (e1, e2) of the planes normal to the unit `axis`: e1 = normalize(axis x t)
/// with t = x if |axis_x| < 0.9 else y, e2 = axis x e1 (the cap planes of slab primitives,
/// `slab_cap_dual` and `render::slab_extent`; the frame of a SLIM patch, `render::slim_patch`).
/// Numerics: `cross`, `normalize`.
template <class T>
void plane_basis(const Vec3<T>& axis, Vec3<T>& e1, Vec3<T>& e2) {
    const mask_t<T> use_x = abs(axis[0]) < T(0.9);
    const Vec3<T> t = select(use_x, vec3(T(1), T(0), T(0)), vec3(T(0), T(1), T(0)));
    e1 = normalize(cross(axis, t));
    e2 = cross(axis, e1);
}

/// The section of a quadric by the plane axis . x = h (local coordinates) as a `DualBound`:
/// with an orthonormal basis (e1, e2) of the plane and p0 = h axis, f(p0 + s e1 + t e2) =
/// [s t] M [s t]^T + 2 m . [s t] + k; its centre p0 + (e1, e2) c with c = -M^-1 m, its value there
/// k0 = k + m . c, and W = -k0 (e1, e2) M^-1 (e1, e2)^T (an ellipse; 0, the centre point, when the
/// section is empty or a point). M is divided by its trace before the inverse; ok iff that
/// determinant exceeds 2^-30 (the section is bounded). (e1, e2): `plane_basis` of the axis.
/// Numerics: dots are left folds; the 2x2 inverse by its adjugate.
template <class T>
DualBound<T> slab_cap_dual(const Quadric<T>& q, const Vec3<T>& axis, const T& h) {
    // Build the basis of the cap plane
    Vec3<T> e1, e2;
    plane_basis(axis, e1, e2);
    // Restrict the quadric to the plane
    const Mat3<T> a = upper3(q.q);
    const Vec3<T> b = xyz(q.q[3]);
    const Vec3<T> p0 = axis * h;
    const Vec3<T> g = a * p0 + b;
    const Vec3<T> ae1 = a * e1, ae2 = a * e2;
    const T m00 = dot(e1, ae1), m01 = dot(e1, ae2), m11 = dot(e2, ae2);
    const T m0 = dot(e1, g), m1 = dot(e2, g);
    const T k = (dot(p0, g) + dot(b, p0)) + q.q[3][3];
    // Invert M at unit scale
    const T tr = m00 + m11;
    const mask_t<T> tr_ok = tr != T(0);
    const T trs = select(tr_ok, tr, T(1));
    const T n00 = m00 / trs, n01 = m01 / trs, n11 = m11 / trs;
    const T dn = n00 * n11 - n01 * n01;
    const mask_t<T> ok = tr_ok && (dn > T(0.000000000931322574615478515625));
    const T dns = select(ok, dn, T(1));
    // Centre c = -M^-1 m = -(adj(N) m) / (dn tr)
    const T scale = dns * trs;
    const T cs = -(n11 * m0 - n01 * m1) / scale;
    const T ct = -(n00 * m1 - n01 * m0) / scale;
    const T k0 = (k + m0 * cs) + m1 * ct;
    const T gk = -k0 / scale;                       // W = gk (e1, e2) adj(N) (e1, e2)^T
    const T gw = select(ok && (gk * n11 > T(0)), gk, T(0));
    const T w11 = gw * n11, w12 = -(gw * n01), w22 = gw * n00;
    DualBound<T> d{};
    d.e = (p0 + e1 * cs) + e2 * ct;
    for (int j = 0; j < 3; ++j)
        for (int i = 0; i < 3; ++i)
            d.w[j][i] = ((e1[i] * e1[j]) * w11 + (e1[i] * e2[j] + e2[i] * e1[j]) * w12) + (e2[i] * e2[j]) * w22;
    d.ok = ok;
    return d;
}

/// The rectangle of the convex hull of two bounds: the smallest rectangle containing both. Tight
/// only if both are tight and visible (a hull with one part behind the eye plane reaches across
/// it), or both are behind the eye plane (then not visible, the empty point (2, 2)).
template <class T>
ScreenRect<T> rect_union(const ScreenRect<T>& a, const ScreenRect<T>& b) {
    ScreenRect<T> r{};
    for (int k = 0; k < 2; ++k) {
        r.lo[k] = min(a.lo[k], b.lo[k]);
        r.hi[k] = max(a.hi[k], b.hi[k]);
    }
    r.visible = a.visible || b.visible;
    r.tight = ((a.tight && b.tight) && (a.visible && b.visible)) || !r.visible;
    return r;
}

/// Which bound the renderers draw a primitive over (render::Variant decides, `primitive_rect`).
enum class RectBound : int {
    /// No rectangle: the quad around its bounding sphere (sphere, bounded and planes variants).
    /// For a sphere that quad already touches its projection on four sides; the sphere's own
    /// padded rectangle (`dual_rect` of `sphere_dual`) rasterised 6.5 fragments per covered pixel
    /// against the quad's 6.1 on the 10k-sphere benchmark scene.
    sphere = 0,
    ellipsoid = 1,  ///< the ellipsoid itself (`ellipsoid_dual`)
    slab = 2,       ///< the convex hull of the two slab sections (`slab_cap_dual`): cylinders, cones and
                    ///< one-sheet hyperboloids, which are ruled between their caps    /// The hull of the projected tetrahedron the four clip planes bound (`tetra_quad`): the
    /// `planes` variant (quadric pieces of finite elements, isosurfaces and skins; bilinear quads,
    /// whose planes bound their corners' tetrahedron). Planes that bound no tetrahedron (a planar
    /// quad's extruded edges) fall back to the bounding sphere's quad.
    tetrahedron = 3,
};

/// The screen rectangle of a primitive (`ClippedQuadric` fields; local coordinates around
/// `center`) for `bound`: `dual_rect` of the bounding sphere, of the ellipsoid, or the union of
/// the rectangles of the two slab sections at +-half_length. The renderers draw it instead of the
/// bounding-sphere quad when it is tight (ellipsoid and slab bounds; see RectBound::sphere).
template <RectBound Bound, class T>
ScreenRect<T> primitive_rect(const Mat4<T>& view_projection, const Quadric<T>& q, const Vec3<T>& center, const T& radius,
                             const Vec3<T>& axis, const T& half_length, const Vec2<T>& viewport) {
    if constexpr (Bound == RectBound::sphere) return dual_rect(view_projection, center, sphere_dual(radius), viewport);
    else if constexpr (Bound == RectBound::ellipsoid) return dual_rect(view_projection, center, ellipsoid_dual(q), viewport);
    else
        return rect_union(dual_rect(view_projection, center, slab_cap_dual(q, axis, half_length), viewport),
                          dual_rect(view_projection, center, slab_cap_dual(q, axis, -half_length), viewport));
}

/// A screen quadrilateral bounding a primitive's projection: NDC corners in counter-clockwise
/// order, with `tight` and `visible` as `ScreenRect`'s.
template <class T>
struct ScreenQuad {
    Vec2<T> corner[4];
    mask_t<T> tight;
    mask_t<T> visible;
};

/// The padded screen rectangle of a slab-bounded primitive (cylinder, cone, one-sheet
/// hyperboloid: ruled between its caps) turned to the projection of its axis: the sides of the
/// convex hull of the two slab sections (`slab_cap_dual` at +-half_length) supported along u, the
/// pixel-space direction of the projected axis at the centre, and along v = (-u_y, u_x). A thin
/// stick seen across its axis covers a few pixels either side of the segment, where the
/// axis-aligned `primitive_rect` of a diagonal stick covers the square around it.
/// Directions: with the local -> clip rows r_i (`detail::local_clip_row`), the window position's
/// pixel offset from the screen centre is P = (W/2 r_1.x~ / r_4.x~, H/2 r_2.x~ / r_4.x~); the
/// lines n . P = b for a unit n are the planes n_x W/2 r_1 + n_y H/2 r_2 - b r_4, so
/// `detail::dual_span` with the row n_x W/2 r_1 + n_y H/2 r_2 bounds n . P over a section. The
/// projected axis direction is the derivative of P along the axis at the centre,
/// u ~ (W/2 (r_1a x_4 - x_1 r_4a), H/2 (r_2a x_4 - x_2 r_4a)) (r_ia = r_i,xyz . axis, x_i = r_i,w);
/// u = (1, 0) when that has no length (the axis points at the eye).
/// Corners: P = (a u + b v) / |u|^2 for (a, b) = (lo_u, lo_v), (hi_u, lo_v), (hi_u, hi_v),
/// (lo_u, hi_v), then NDC = P / (W/2, H/2).
/// Padding per direction (pixels): 1/16 + 2^-10 of the span + 2^-15 of the sum of |b0| over both
/// sections and directions (the rounding of the centre's position, which the combined rows carry
/// into either direction).
/// tight iff both sections are usable and beyond the near plane with a margin, all four spans
/// clear and finite, and every corner within 64 in NDC (beyond, the fallback quad rasterises
/// alike); visible iff either section lies in front of the eye plane; not visible: every corner
/// at (2, 2).
/// Numerics: as `detail::dual_span`; u normalised by `normalize`.
template <class T>
ScreenQuad<T> sections_quad(const Mat4<T>& view_projection, const Vec3<T>& center, const Vec3<T>& axis, const DualBound<T>& d0,
                            const DualBound<T>& d1, const Vec2<T>& viewport);

template <class T>
ScreenQuad<T> slab_quad(const Mat4<T>& view_projection, const Quadric<T>& q, const Vec3<T>& center, const Vec3<T>& axis,
                        const T& half_length, const Vec2<T>& viewport) {
    return sections_quad(view_projection, center, axis, slab_cap_dual(q, axis, half_length), slab_cap_dual(q, axis, -half_length), viewport);
}

/// `slab_quad`'s quadrilateral for any two sections d0, d1 (convex bounds in local coordinates)
/// along `axis`: the sides of their convex hull supported along the projected axis and across it.
template <class T>
ScreenQuad<T> sections_quad(const Mat4<T>& view_projection, const Vec3<T>& center, const Vec3<T>& axis, const DualBound<T>& d0,
                            const DualBound<T>& d1, const Vec2<T>& viewport) {
    // Pull the clip-space rows back to local coordinates
    const Vec4<T> r1 = detail::local_clip_row(view_projection, center, 0);
    const Vec4<T> r2 = detail::local_clip_row(view_projection, center, 1);
    const Vec4<T> r3 = detail::local_clip_row(view_projection, center, 2);
    const Vec4<T> r4 = detail::local_clip_row(view_projection, center, 3);
    const T half_w = viewport[0] * T(0.5), half_h = viewport[1] * T(0.5);
    // Turn the frame to the projected axis
    const T a4 = dot(xyz(r4), axis);
    const T du = half_w * (dot(xyz(r1), axis) * r4[3] - r1[3] * a4);
    const T dv = half_h * (dot(xyz(r2), axis) * r4[3] - r2[3] * a4);
    const T dl2 = du * du + dv * dv;
    const mask_t<T> dir_ok = (dl2 > T(0)) && (dl2 < T(3.4e38));
    const Vec2<T> u = select(dir_ok, normalize(vec2(select(dir_ok, du, T(1)), select(dir_ok, dv, T(0)))), vec2(T(1), T(0)));
    const Vec2<T> v = vec2(-u[1], u[0]);
    const Vec4<T> ru = r1 * (u[0] * half_w) + r2 * (u[1] * half_h);
    const Vec4<T> rv = r1 * (v[0] * half_w) + r2 * (v[1] * half_h);
    // Bound both directions over both sections
    T lo[2][2], hi[2][2], b0[2][2];
    mask_t<T> clear[2][2];
    detail::dual_span(ru, r4, d0, lo[0][0], hi[0][0], b0[0][0], clear[0][0]);
    detail::dual_span(rv, r4, d0, lo[0][1], hi[0][1], b0[0][1], clear[0][1]);
    detail::dual_span(ru, r4, d1, lo[1][0], hi[1][0], b0[1][0], clear[1][0]);
    detail::dual_span(rv, r4, d1, lo[1][1], hi[1][1], b0[1][1], clear[1][1]);
    const mask_t<T> near0 = detail::dual_beyond(r3 + r4, d0), near1 = detail::dual_beyond(r3 + r4, d1);
    const mask_t<T> behind0 = detail::dual_beyond(-r4, d0), behind1 = detail::dual_beyond(-r4, d1);
    // Pad the hull's spans
    mask_t<T> tight = (((d0.ok && d1.ok) && (near0 && near1)) && (clear[0][0] && clear[0][1])) && (clear[1][0] && clear[1][1]);
    const T centre_pad = ((b0[0][0] + b0[0][1]) + (b0[1][0] + b0[1][1])) * T(0.000030517578125);
    T l[2], h[2];
    for (int k = 0; k < 2; ++k) {
        const T lk = min(lo[0][k], lo[1][k]), hk = max(hi[0][k], hi[1][k]);
        const T pad = (T(0.0625) + (hk - lk) * T(0.0009765625)) + centre_pad;
        l[k] = lk - pad;
        h[k] = hk + pad;
        tight = tight && (l[k] <= h[k]);  // false for NaN
    }
    // Place the corners
    const T u2 = dot(u, u);
    const T as[4] = {l[0], h[0], h[0], l[0]};
    const T bs[4] = {l[1], l[1], h[1], h[1]};
    const mask_t<T> behind = behind0 && behind1;
    ScreenQuad<T> out{};
    for (int i = 0; i < 4; ++i) {
        const Vec2<T> pc = (u * as[i] + v * bs[i]) / u2;
        const Vec2<T> ndc = vec2(pc[0] / half_w, pc[1] / half_h);
        tight = tight && (max(abs(ndc[0]), abs(ndc[1])) <= T(64));
        out.corner[i] = select(behind, vec2(T(2), T(2)), ndc);
    }
    out.tight = tight || behind;
    out.visible = !behind;
    return out;
}

/// The slack of the `planes` variants' clip test (`inside_planes`): a point is inside when every
/// plane's value is at least -clip_plane_slack (2^-12; the planes are scaled as barycentric
/// coordinates, so the slack is relative to the element's size).
inline constexpr double clip_plane_slack = 0.000244140625;

/// Twice the signed area of the triangle (a, b, c): positive when counter-clockwise.
/// Numerics: (b - a).x (c - a).y - (b - a).y (c - a).x.
template <class T>
T orient2(const Vec2<T>& a, const Vec2<T>& b, const Vec2<T>& c) {
    return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
}

namespace detail {

/// Vertex v of a counter-clockwise convex polygon, between the edges from `prev` and to `next`,
/// moved so that both edges lie `pad` further out: v + pad (n0 + n1) / (1 + n0 . n1) for the
/// edges' unit outward normals n0, n1 (the miter). `ok` turns false where the miter would be
/// longer than 16 pad (an angle sharper than about 7 degrees) or an edge has no length.
/// Numerics: normals by `normalize`.
template <class T>
Vec2<T> miter_vertex(const Vec2<T>& prev, const Vec2<T>& v, const Vec2<T>& next, const T& pad, mask_t<T>& ok) {
    const Vec2<T> e0 = v - prev, e1 = next - v;
    const Vec2<T> n0 = normalize(vec2(e0[1], -e0[0])), n1 = normalize(vec2(e1[1], -e1[0]));
    const T k = T(1) + dot(n0, n1);
    const mask_t<T> k_ok = k >= T(0.0078125);  // false for NaN
    ok = ok && k_ok;
    return v + (n0 + n1) * (pad / select(k_ok, k, T(1)));
}

}  // namespace detail

/// Corner j of the region four planes accept (inward planes `pl`, each shifted by the clip test's
/// slack by the caller): where the three planes other than j meet,
/// x_j = -(d_a (n_b x n_c) + d_b (n_c x n_a) + d_c (n_a x n_b)) / (n_a . (n_b x n_c)) for
/// a, b, c = planes j + 1, j + 2, j + 3 (mod 4). `ok` when the three meet at an angle,
/// |n_a . (n_b x n_c)| > min_sine |n_a| |n_b| |n_c| (2^-8 for float corners), and plane j is
/// positive there; the four half-spaces bound exactly the tetrahedron of these corners when all
/// four are ok.
/// Numerics: dots are left folds; cross products as `cross`.
template <class T>
Vec3<T> tetra_corner(const Vec4<T> (&pl)[4], int j, mask_t<T>& ok, const T& min_sine = T(0.00390625)) {
    const Vec4<T>& a = pl[(j + 1) % 4];
    const Vec4<T>& b = pl[(j + 2) % 4];
    const Vec4<T>& c = pl[(j + 3) % 4];
    const Vec3<T> na = xyz(a), nb = xyz(b), nc = xyz(c);
    const Vec3<T> bc = cross(nb, nc), ca = cross(nc, na), ab = cross(na, nb);
    const T d = dot(na, bc);
    const mask_t<T> d_ok = abs(d) > min_sine * ((length(na) * length(nb)) * length(nc));  // false for NaN
    const Vec3<T> x = -((bc * a[3] + ca * b[3]) + ab * c[3]) / select(d_ok, d, T(1));
    ok = d_ok && (dot(pl[j], vec4(x, T(1))) > T(0));
    return x;
}

/// Whether all the surface a `planes` primitive can show lies in its bounding ball (`radius`
/// around its centre; `planes` local): the planes, shifted by `clip_plane_slack` as the clip test
/// accepts, bound a tetrahedron (`tetra_corner` ok for all four corners) whose corners lie within
/// radius (1 + 2^-11), inside the ball of `nearest_distance`. Bilinear quads' extruded edge planes
/// bound no tetrahedron: their saddle may show outside the ball, inside their screen quad.
/// Host-side (double; corners of planes meeting at any angle above 2^-40, slivers included).
inline bool planes_within_ball(const Vec4<double> (&planes)[4], double radius) {
    Vec4<double> pl[4];
    for (int i = 0; i < 4; ++i) pl[i] = planes[i] + vec4(0.0, 0.0, 0.0, clip_plane_slack);
    const double limit = radius * (1.0 + 1.0 / 2048.0);
    for (int j = 0; j < 4; ++j) {
        bool ok = false;
        const Vec3<double> x = tetra_corner(pl, j, ok, 1.0 / 1099511627776.0);
        if (!ok || !(dot(x, x) <= limit * limit)) return false;
    }
    return true;
}

/// The padded screen quadrilateral of a primitive clipped to four planes that bound a
/// tetrahedron (`planes`, inward, local coordinates around `center`; the `planes` variants):
/// the convex hull of the projected corners of the region the clip test accepts
/// (every plane's value >= -`clip_plane_slack`), instead of the square around the bounding
/// sphere, which covers several times the tetrahedron's projection.
/// Corners: corner j is where the three planes other than j meet,
/// x_j = -(d_a (n_b x n_c) + d_b (n_c x n_a) + d_c (n_a x n_b)) / (n_a . (n_b x n_c)), usable when
/// |n_a . (n_b x n_c)| > 2^-8 |n_a| |n_b| |n_c| (the three planes meet at an angle) and plane j
/// is positive there (then the four half-spaces bound exactly that tetrahedron; bilinear quads'
/// extruded edge planes do not: they get tight = false).
/// Hull: P_j = (W/2 x_c / w_c, H/2 y_c / w_c) pixels from the screen centre; the triangle of
/// three corners with the largest area, made counter-clockwise, and the fourth corner inserted
/// after the one edge it lies beyond (a quadrilateral), or, when it lies inside, the midpoint of
/// the closing edge as the fourth vertex (the triangle).
/// Padding: every edge moved out by 1/16 pixel + 2^-10 of the larger side of the corners'
/// bounding box + 2^-15 of their largest coordinate (`detail::miter_vertex`).
/// tight iff all four corners are usable and lie beyond the near plane with a margin
/// (z_c + w_c > 2^-10 w_c, w_c > 0), the hull has an area, no miter is too long and every corner
/// lies within 64 in NDC; visible iff some corner lies in front of the eye plane or the corners
/// are not usable; not visible: every corner at (2, 2).
/// Numerics: dots are left folds; cross products as `cross`.
template <class T>
ScreenQuad<T> tetra_quad(const Mat4<T>& view_projection, const Vec4<T> (&planes)[4], const Vec3<T>& center, const Vec2<T>& viewport) {
    // Pull the clip-space rows back to local coordinates
    const Vec4<T> r1 = detail::local_clip_row(view_projection, center, 0);
    const Vec4<T> r2 = detail::local_clip_row(view_projection, center, 1);
    const Vec4<T> r3 = detail::local_clip_row(view_projection, center, 2);
    const Vec4<T> r4 = detail::local_clip_row(view_projection, center, 3);
    const T half_w = viewport[0] * T(0.5), half_h = viewport[1] * T(0.5);
    // Find and project the corners of the accepted region
    Vec4<T> pl[4];
    for (int i = 0; i < 4; ++i) pl[i] = planes[i] + vec4(T(0), T(0), T(0), T(clip_plane_slack));
    mask_t<T> ok = mask_t<T>(true), front = mask_t<T>(true), behind = mask_t<T>(true);
    Vec2<T> px[4];
    for (int j = 0; j < 4; ++j) {
        mask_t<T> corner_ok;
        const Vec3<T> x = tetra_corner(pl, j, corner_ok);
        ok = ok && corner_ok;
        const Vec4<T> xh = vec4(x, T(1));
        const T cx = dot(r1, xh), cy = dot(r2, xh), cz = dot(r3, xh), cw = dot(r4, xh);
        front = (front && (cw > T(0))) && (cz + cw > T(0.0009765625) * cw);
        behind = behind && (cw < T(0));
        const T ws = select(cw > T(0), cw, T(1));
        px[j] = vec2(half_w * (cx / ws), half_h * (cy / ws));
    }
    // Pick the largest triangle of three corners and the fourth
    const T area[4] = {orient2(px[1], px[2], px[3]), orient2(px[0], px[2], px[3]), orient2(px[0], px[1], px[3]),
                       orient2(px[0], px[1], px[2])};
    Vec2<T> a = px[1], b = px[2], c = px[3], q = px[0];
    T best = abs(area[0]), signed_area = area[0];
    for (int m = 1; m < 4; ++m) {
        const mask_t<T> larger = abs(area[m]) > best;
        a = select(larger, px[0], a);
        b = select(larger, px[m == 1 ? 2 : 1], b);
        c = select(larger, px[m == 3 ? 2 : 3], c);
        q = select(larger, px[m], q);
        best = select(larger, abs(area[m]), best);
        signed_area = select(larger, area[m], signed_area);
    }
    const mask_t<T> flip = signed_area < T(0);
    const Vec2<T> b_ccw = select(flip, c, b), c_ccw = select(flip, b, c);
    // Insert the fourth corner after the edge it lies beyond
    const mask_t<T> out0 = orient2(a, b_ccw, q) < T(0), out1 = orient2(b_ccw, c_ccw, q) < T(0), out2 = orient2(c_ccw, a, q) < T(0);
    ok = ((ok && (best > T(0))) && !(out0 && out1)) && (!(out1 && out2) && !(out2 && out0));
    Vec2<T> v[4];
    v[0] = a;
    v[1] = select(out0, q, b_ccw);
    v[2] = select(out0, b_ccw, select(out1, q, c_ccw));
    v[3] = select(out0 || out1, c_ccw, select(out2, q, (c_ccw + a) * T(0.5)));
    // Pad the hull
    T lo[2], hi[2];
    T mag = T(0);
    for (int k = 0; k < 2; ++k) {
        lo[k] = min(min(px[0][k], px[1][k]), min(px[2][k], px[3][k]));
        hi[k] = max(max(px[0][k], px[1][k]), max(px[2][k], px[3][k]));
        mag = max(mag, max(abs(lo[k]), abs(hi[k])));
    }
    const T pad = (T(0.0625) + max(hi[0] - lo[0], hi[1] - lo[1]) * T(0.0009765625)) + mag * T(0.000030517578125);
    mask_t<T> tight = ok && front;
    ScreenQuad<T> out{};
    for (int i = 0; i < 4; ++i) {
        const Vec2<T> pc = detail::miter_vertex(v[(i + 3) % 4], v[i], v[(i + 1) % 4], pad, tight);
        const Vec2<T> ndc = vec2(pc[0] / half_w, pc[1] / half_h);
        tight = tight && (max(abs(ndc[0]), abs(ndc[1])) <= T(64));
        out.corner[i] = select(behind && ok, vec2(T(2), T(2)), ndc);
    }
    out.visible = !(behind && ok);
    out.tight = tight || !out.visible;
    return out;
}

// Sphere-bound quads --------------------------------------------------------------------------

/// A view-space quad whose perspective projection tightly encloses the projection of a sphere.
template <class T>
struct SphereQuad {
    Vec3<T> corner[4];  ///< counter-clockwise seen from the eye: (-,-), (+,-), (+,+), (-,+) in (e1, e2)
    T half_size;        ///< R = r L / sqrt(L^2 - r^2), L = |centre|
    mask_t<T> valid;    ///< false when the eye is inside or on the sphere (fall back to full screen)
};

/// The bounding square of a sphere (centre `c` in view space, radius `r`) for an orthographic
/// camera: the square c +- r in view x and y at the centre's depth, corners in `sphere_quad`'s
/// order (-,-), (+,-), (+,+), (-,+); always valid. Its projection bounds the sphere's (a disc).
/// Numerics: corner = (c_x + s1 r, c_y + s2 r, c_z) with s1, s2 = -+1 (exact products).
template <class T>
SphereQuad<T> ortho_sphere_square(const Vec3<T>& c, const T& r) {
    SphereQuad<T> q{};
    const T s1[4] = {T(-1), T(1), T(1), T(-1)};
    const T s2[4] = {T(-1), T(-1), T(1), T(1)};
    for (int i = 0; i < 4; ++i) q.corner[i] = vec3(c[0] + s1[i] * r, c[1] + s2[i] * r, c[2]);
    q.half_size = r;
    q.valid = mask_t<T>(true);
    return q;
}

/// The clip-space position of the view-space point p: projection * (p, 1).
/// Numerics: the matrix-vector product of linalg (a left fold over the columns), not GLSL's
/// built-in `*`, so the GL vertex stage and the CPU round alike.
template <class T>
Vec4<T> clip_position(const Mat4<T>& projection, const Vec3<T>& p) {
    return projection * vec4(p[0], p[1], p[2], T(1));
}

/// The point sprite that stands in for a quad of the bounding geometry (the sphere variant's four
/// clip-space corners c0..c3, each with w > 0; QuadricRenderer draws one vertex per sphere where
/// `render::sphere_points_fit`): centred on the box of the corners' NDC positions, of side in
/// pixels the box's larger extent plus 1/4 pixel, so that every pixel centre inside the quad lies
/// at least 1/8 pixel inside the sprite's square (a rasteriser snaps to 1/256 pixel on llvmpipe;
/// the quad itself is already grown by `rasterised_sphere_quad`). `viewport`: width, height.
/// Numerics: ndc_k = c_k.xy / c_k.w; lo, hi by min and max in corner order; centre = (lo + hi) * 0.5;
/// extent = (hi - lo) * viewport * 0.5 per axis; size = max(extent.x, extent.y) + 0.25.
template <class T>
void point_sprite(const Vec4<T>& c0, const Vec4<T>& c1, const Vec4<T>& c2, const Vec4<T>& c3, const Vec2<T>& viewport, Vec2<T>& centre, T& size) {
    const Vec4<T> c[4] = {c0, c1, c2, c3};
    Vec2<T> lo = vec2(c0[0] / c0[3], c0[1] / c0[3]), hi = lo;
    for (int k = 1; k < 4; ++k) {
        const Vec2<T> n = vec2(c[k][0] / c[k][3], c[k][1] / c[k][3]);
        lo = vec2(min(lo[0], n[0]), min(lo[1], n[1]));
        hi = vec2(max(hi[0], n[0]), max(hi[1], n[1]));
    }
    centre = vec2((lo[0] + hi[0]) * T(0.5), (lo[1] + hi[1]) * T(0.5));
    const T ex = (hi[0] - lo[0]) * viewport[0] * T(0.5), ey = (hi[1] - lo[1]) * viewport[1] * T(0.5);
    size = max(ex, ey) + T(0.25);
}

/// Tight bounding quad of a sphere (centre `c` in view space, eye at the origin, radius `r`), in
/// the spirit of Stoll et al. 2006 sec. 3 (area of interest tightly enclosing the projection of
/// the bounding sphere): the silhouette cone from the eye (half-angle a, sin a = r / L) meets the
/// plane through the centre perpendicular to d = c / L in the circle of radius
/// R = L tan a = r L / sqrt((L - r)(L + r)); the circumscribed square c +- R e1 +- R e2 projects
/// to a quadrilateral whose four edges touch the projected silhouette ellipse.
/// Correct however close the eye is and whatever the view direction: every ray through the
/// sphere crosses the quad's plane inside the square, at a distance beyond its front hit (so near
/// plane clipping of the quad never removes a pixel whose front hit survives it; far plane
/// clipping can: render with depth clamping or write depth in the fragment stage).
/// e1 = (-d_z, 0, d_x) / |(d_x, d_z)| (the screen x direction when d = -z), (1, 0, 0) if d = +-y;
/// e2 = cross(e1, d).
/// Numerics: L = sqrt(dot(c, c)); k2 = (L - r) * (L + r); R = (r * L) / sqrt(k2);
/// corner = c + (e1 * (s1 * R) + e2 * (s2 * R)).
template <class T>
SphereQuad<T> sphere_quad(const Vec3<T>& c, const T& r) {
    // Measure the distance to the centre and the silhouette circle in the centre plane
    const T l = length(c);
    const T k2 = (l - r) * (l + r);
    const mask_t<T> valid = k2 > T(0);
    const T k = sqrt(select(valid, k2, T(1)));
    const T big_r = select(valid, (r * l) / k, T(0));
    // Build a basis of the plane through the centre perpendicular to the view direction
    const Vec3<T> dir = c / select(l > T(0), l, T(1));
    const T e_len2 = dir[0] * dir[0] + dir[2] * dir[2];
    const mask_t<T> e_ok = e_len2 > T(0);
    const T e_len = sqrt(select(e_ok, e_len2, T(1)));
    const Vec3<T> e1 = select(e_ok, vec3(-dir[2] / e_len, T(0), dir[0] / e_len), vec3(T(1), T(0), T(0)));
    const Vec3<T> e2 = cross(e1, dir);
    // Place the corners of the circumscribed square
    SphereQuad<T> q{};
    const T s1[4] = {T(-1), T(1), T(1), T(-1)};
    const T s2[4] = {T(-1), T(-1), T(1), T(1)};
    for (int i = 0; i < 4; ++i) q.corner[i] = c + (e1 * (s1[i] * big_r) + e2 * (s2[i] * big_r));
    q.half_size = big_r;
    q.valid = valid;
    return q;
}

/// A sphere quad (`sphere_quad`, `ortho_sphere_square`) grown about the sphere's view-space centre
/// `c` for the rasteriser: its half size R gains R 2^-7 + |c| 2^-15. The exact quad touches the
/// silhouette, and the fragment stage's float cast hits pixel centres up to a hair outside it
/// (down to 6e-5 pixel inside the exact quad's edges at 1024x768, measured), which a
/// rasteriser's sub-pixel snapping (1/256 pixel in llvmpipe) can push out of the quad: the GL
/// renderer missed 1-4 such edge pixels per frame of 10k-1M random spheres. The pad is about 1/50
/// pixel for a 30 degree view 768 pixels high (the |c| term, an angle of 2^-15) and at least 1/128
/// of R; what it adds is rasterised and discarded by the cast.
/// Numerics: s = 1 + 2^-7 + (|c| 2^-15) / R (1 + 2^-7 where R is 0); corner = c + (corner - c) s.
template <class T>
SphereQuad<T> rasterised_sphere_quad(const SphereQuad<T>& q, const Vec3<T>& c) {
    const mask_t<T> sized = q.half_size > T(0);
    const T grow = select(sized, (length(c) * T(1.0 / 32768.0)) / select(sized, q.half_size, T(1)), T(0));
    const T s = (T(1) + T(1.0 / 128.0)) + grow;
    SphereQuad<T> out = q;
    for (int i = 0; i < 4; ++i) out.corner[i] = c + (q.corner[i] - c) * s;
    out.half_size = q.half_size * s;
    return out;
}

}  // namespace quadcast
