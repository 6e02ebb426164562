// quadcast/primitives.hpp -- standard quadric primitives as parameter-space forms (D, T)
#pragma once

#include "quadcast/linalg.hpp"
#include "quadcast/quadric.hpp"
#include "quadcast/scalar.hpp"

namespace quadcast {

// Parameter space (Sigg et al. 2006, sec. 3.1, eq. 1-2): every primitive is a normalised
// diagonal quadric p^T D p = 0 (d_ii in {0, +1, -1}) seen through the variance matrix T, whose
// columns are the axes u, v, w and the centre c in object coordinates: x = T p and
// Q = T^-T D T^-1. Unbounded primitives are clipped to a slab z_lo <= p_z / p_w <= z_hi of
// parameter space; for cylinders and cones that is Sigg's unit-cube clipping (the clipped
// surface lies inside the cube anyway), for hyperboloids only z is clipped (x and y are not).
//
//   kind                      D               slab        surface in parameter space
//   ellipsoid                 ( 1, 1, 1,-1)   [-1, 1]     x^2 + y^2 + z^2 = 1 (slab unused)
//   cylinder                  ( 1, 1, 0,-1)   [-1, 1]     x^2 + y^2 = 1, caps at z = -1, +1
//   cone                      ( 1, 1,-1, 0)   [ 0, 1]     x^2 + y^2 = z^2, apex z = 0, base z = 1
//   paraboloid (projective T) ( 1, 1, 1,-1)   [-1, 0]     the unit sphere: see `paraboloid`
//   hyperboloid, one sheet    ( 1, 1,-1,-1)   [-h, h]     x^2 + y^2 = 1 + z^2
//   hyperboloid, two sheets   ( 1, 1,-1, 1)   [lo, hi]    x^2 + y^2 = z^2 - 1
//
// Sign convention: p^T D p < 0 on the side that holds the centre or the axis (inside an
// ellipsoid, cylinder, cone or paraboloid, inside each bowl of a two-sheet hyperboloid, in the
// hole of a one-sheet hyperboloid) and > 0 on the other side.

/// Class of a primitive. A host-side tag (plain C++, never traced): kernels are emitted per kind.
enum class PrimitiveKind : unsigned char {
    ellipsoid,
    cylinder,
    cone,
    paraboloid,
    hyperboloid_one_sheet,
    hyperboloid_two_sheets,
};

/// Every kind, in declaration order.
inline constexpr PrimitiveKind all_primitive_kinds[] = {
    PrimitiveKind::ellipsoid, PrimitiveKind::cylinder, PrimitiveKind::cone, PrimitiveKind::paraboloid,
    PrimitiveKind::hyperboloid_one_sheet, PrimitiveKind::hyperboloid_two_sheets,
};

/// A readable name ("hyperboloid (one sheet)").
inline const char* primitive_kind_name(PrimitiveKind k) {
    switch (k) {
    case PrimitiveKind::ellipsoid: return "ellipsoid";
    case PrimitiveKind::cylinder: return "cylinder";
    case PrimitiveKind::cone: return "cone";
    case PrimitiveKind::paraboloid: return "paraboloid";
    case PrimitiveKind::hyperboloid_one_sheet: return "hyperboloid (one sheet)";
    case PrimitiveKind::hyperboloid_two_sheets: return "hyperboloid (two sheets)";
    }
    return "?";
}

/// True for the kinds whose surface is cut off by the parameter-space slab.
constexpr bool is_clipped(PrimitiveKind k) { return k != PrimitiveKind::ellipsoid; }

/// True for ruled kinds: every point of the clipped surface lies on a segment between the two
/// cap curves, so the caps alone bound it (and the caps' bounds are tight).
constexpr bool is_ruled(PrimitiveKind k) {
    return k == PrimitiveKind::cylinder || k == PrimitiveKind::cone ||
           k == PrimitiveKind::hyperboloid_one_sheet;
}

/// True when T is projective (its last row is not (0, 0, 0, 1)): only the paraboloid.
constexpr bool is_projective(PrimitiveKind k) { return k == PrimitiveKind::paraboloid; }

/// A quadric primitive in Sigg's parameter-space form (Sigg et al. 2006, eq. 1-2): a renderer draws
/// it as a render::Primitive (quadcast/shapes.hpp builds one).
template <class T>
struct ParameterForm {
    PrimitiveKind kind;  ///< class of the primitive (host-side tag)
    Vec4<T> d;           ///< diagonal of D, entries 0, +1 or -1
    Mat4<T> t;           ///< variance matrix T: object = T * parameter (columns u, v, w, c)
    Vec2<T> slab;        ///< clip range [z_lo, z_hi] of the parameter-space z (unused for ellipsoids)
};

namespace detail {

/// Affine T = [u v w c; 0 0 0 1] from its columns.
template <class T>
Mat4<T> affine_columns(const Vec3<T>& u, const Vec3<T>& v, const Vec3<T>& w, const Vec3<T>& c) {
    Mat4<T> t{};
    t[0] = vec4(u, T(0));
    t[1] = vec4(v, T(0));
    t[2] = vec4(w, T(0));
    t[3] = vec4(c, T(1));
    return t;
}

}  // namespace detail

/// Two unit vectors that complete the unit vector `n` to a right-handed orthonormal basis
/// (b1, b2, n), branch-free (Duff et al. 2017, "Building an orthonormal basis, revisited").
/// Numerics: s = sign_nonzero(n_z); a = -1 / (s + n_z); b = (n_x * n_y) * a;
/// b1 = (1 + ((s * n_x) * n_x) * a, s * b, -(s * n_x)), b2 = (b, s + (n_y * n_y) * a, -n_y).
template <class T>
void orthonormal_basis(const Vec3<T>& n, Vec3<T>& b1, Vec3<T>& b2) {
    const T s = sign_nonzero(n[2]);
    const T a = T(-1) / (s + n[2]);
    const T b = (n[0] * n[1]) * a;
    const T sx = s * n[0];
    b1 = vec3(T(1) + (sx * n[0]) * a, s * b, -sx);
    b2 = vec3(b, s + (n[1] * n[1]) * a, -n[1]);
}

/// Ellipsoid with centre `c` and semi-axes `u`, `v`, `w` (need not be orthogonal):
/// x = c + X u + Y v + Z w with X^2 + Y^2 + Z^2 = 1. Sigg et al. 2006, eq. 2.
template <class T>
ParameterForm<T> ellipsoid(const Vec3<T>& c, const Vec3<T>& u, const Vec3<T>& v, const Vec3<T>& w) {
    return {PrimitiveKind::ellipsoid, vec4(T(1), T(1), T(1), T(-1)), detail::affine_columns(u, v, w, c),
            vec2(T(-1), T(1))};
}

/// Sphere with centre `c` and radius `r`: T = diag(r, r, r) with centre c.
template <class T>
ParameterForm<T> sphere(const Vec3<T>& c, T r) {
    return ellipsoid(c, vec3(r, T(0), T(0)), vec3(T(0), r, T(0)), vec3(T(0), T(0), r));
}

/// Elliptic cylinder around the segment c - w .. c + w with cross-section semi-axes `u`, `v`:
/// D = (1, 1, 0, -1), clipped to -1 <= z <= 1 (the caps are the ellipses c +- w + cos u + sin v).
template <class T>
ParameterForm<T> elliptic_cylinder(const Vec3<T>& c, const Vec3<T>& u, const Vec3<T>& v, const Vec3<T>& w) {
    return {PrimitiveKind::cylinder, vec4(T(1), T(1), T(0), T(-1)), detail::affine_columns(u, v, w, c),
            vec2(T(-1), T(1))};
}

/// Circular cylinder of radius `r` from `p0` to `p1` (caps are the discs at p0 and p1):
/// w = (p1 - p0) / 2, c = (p0 + p1) / 2, u and v = r times an orthonormal basis of w's normal plane.
/// Numerics: c = (p0 + p1) * 0.5, w = (p1 - p0) * 0.5, axis direction = w / |w|.
template <class T>
ParameterForm<T> cylinder(const Vec3<T>& p0, const Vec3<T>& p1, T r) {
    // Build the axis and a basis of the cross-section plane
    const Vec3<T> w = (p1 - p0) * T(0.5);
    const Vec3<T> c = (p0 + p1) * T(0.5);
    Vec3<T> b1{}, b2{};
    orthonormal_basis(normalize(w), b1, b2);
    return elliptic_cylinder(c, b1 * r, b2 * r, w);
}

/// Elliptic cone with apex `apex` and base ellipse apex + w + cos u + sin v:
/// D = (1, 1, -1, 0), T = [u v w apex], clipped to 0 <= z <= 1.
template <class T>
ParameterForm<T> elliptic_cone(const Vec3<T>& apex, const Vec3<T>& u, const Vec3<T>& v, const Vec3<T>& w) {
    return {PrimitiveKind::cone, vec4(T(1), T(1), T(-1), T(0)), detail::affine_columns(u, v, w, apex),
            vec2(T(0), T(1))};
}

/// Circular cone from `apex` to the disc of radius `base_radius` around `base_center`.
/// For a half-angle a, base_radius = |base_center - apex| * tan(a) (computed by the caller:
/// shared code has no trigonometry).
template <class T>
ParameterForm<T> cone(const Vec3<T>& apex, const Vec3<T>& base_center, T base_radius) {
    // Build the axis and a basis of the base plane
    const Vec3<T> w = base_center - apex;
    Vec3<T> b1{}, b2{};
    orthonormal_basis(normalize(w), b1, b2);
    return elliptic_cone(apex, b1 * base_radius, b2 * base_radius, w);
}

/// Elliptic paraboloid with vertex `vertex`, opening along `w`, rim ellipse
/// vertex + w + cos u + sin v: in the affine frame A = [u v w vertex] it is X^2 + Y^2 = Z W
/// (W = 1) with 0 <= Z <= 1.
///
/// D must be diagonal, so T is projective: X^2 + Y^2 - Z W = X^2 + Y^2 + ((Z - W)/2)^2 - ((Z + W)/2)^2,
/// i.e. with p = K s, s = (X, Y, Z, W), p_z = (Z - W)/2, p_w = (Z + W)/2 the paraboloid is the
/// unit sphere D = (1, 1, 1, -1) of parameter space, and T = A K^-1 has the columns
/// u, v, (w - vertex, -1), (w + vertex, 1). The vertex maps to the south pole p = (0, 0, -1, 1),
/// the rim (Z = 1) to the equator p_z = 0 and the point at infinity of the axis to the north
/// pole; so 0 <= Z <= 1 is the slab -1 <= p_z / p_w <= 0 (Z = (1 + z) / (1 - z), monotonic).
/// Numerics: the columns w - vertex and w + vertex are rounded once each; far from the origin
/// this costs relative precision |vertex| / |w| of the shape (like any object-space position).
template <class T>
ParameterForm<T> paraboloid(const Vec3<T>& vertex, const Vec3<T>& u, const Vec3<T>& v, const Vec3<T>& w) {
    Mat4<T> t{};
    t[0] = vec4(u, T(0));
    t[1] = vec4(v, T(0));
    t[2] = vec4(w - vertex, T(-1));
    t[3] = vec4(w + vertex, T(1));
    return {PrimitiveKind::paraboloid, vec4(T(1), T(1), T(1), T(-1)), t, vec2(T(-1), T(0))};
}

/// Circular paraboloid from `vertex` to the rim circle of radius `rim_radius` around `rim_center`.
template <class T>
ParameterForm<T> paraboloid(const Vec3<T>& vertex, const Vec3<T>& rim_center, T rim_radius) {
    // Build the axis and a basis of the rim plane
    const Vec3<T> w = rim_center - vertex;
    Vec3<T> b1{}, b2{};
    orthonormal_basis(normalize(w), b1, b2);
    return paraboloid(vertex, b1 * rim_radius, b2 * rim_radius, w);
}

/// Hyperboloid of one sheet x^2 + y^2 = 1 + z^2 with centre `c`, waist ellipse c + cos u + sin v
/// and axis w, clipped to -half_height <= z <= half_height (half_height = 1: unit-cube slab;
/// the caps are then the ellipses c +- w + sqrt(2) (cos u + sin v)). D = (1, 1, -1, -1).
template <class T>
ParameterForm<T> hyperboloid_one_sheet(const Vec3<T>& c, const Vec3<T>& u, const Vec3<T>& v, const Vec3<T>& w,
                                   T half_height) {
    return {PrimitiveKind::hyperboloid_one_sheet, vec4(T(1), T(1), T(-1), T(-1)),
            detail::affine_columns(u, v, w, c), vec2(-half_height, half_height)};
}

/// Hyperboloid of two sheets x^2 + y^2 = z^2 - 1 with centre `c`, vertices c -+ w, clipped to
/// z_lo <= z <= z_hi (e.g. [1, h] for one sheet, [-h, h] for both). D = (1, 1, -1, 1).
/// Bounds treat a slab end with |z| < 1 as the point (0, 0, z) (conservative): prefer |z| >= 1.
template <class T>
ParameterForm<T> hyperboloid_two_sheets(const Vec3<T>& c, const Vec3<T>& u, const Vec3<T>& v, const Vec3<T>& w,
                                    T z_lo, T z_hi) {
    return {PrimitiveKind::hyperboloid_two_sheets, vec4(T(1), T(1), T(-1), T(1)),
            detail::affine_columns(u, v, w, c), vec2(z_lo, z_hi)};
}

/// Squared radius of the slab section at parameter height z of a quadric with D = (1, 1, d2, d3):
/// x^2 + y^2 = -(d2 z^2 + d3). Negative when the plane misses the surface.
/// Numerics: -((d2 * z) * z + d3).
template <class T>
T section_radius2(const Vec4<T>& d, const T& z) {
    return -((d[2] * z) * z + d[3]);
}

/// Inverse of the variance matrix of `prim`, in closed form: for affine T = [L c; 0 1],
/// T^-1 = [L^-1, -(L^-1 c); 0 1] with L^-1 by the adjugate (`inverse` in linalg.hpp); for the
/// paraboloid T^-1 = K A^-1 with A = T K recovered from T's columns.
/// Numerics: A's columns (T2 + T3) * 0.5 and (T3 - T2) * 0.5; row 2 of K A^-1 is
/// (a2 - a3) * 0.5 and row 3 is (a2 + a3) * 0.5, a_i the rows of A^-1.
template <class T>
Mat4<T> inverse_variance(const ParameterForm<T>& prim) {
    // Recover the affine frame A (equal to T unless T is projective)
    Mat4<T> a = prim.t;
    if (is_projective(prim.kind)) {
        a[2] = (prim.t[2] + prim.t[3]) * T(0.5);
        a[3] = (prim.t[3] - prim.t[2]) * T(0.5);
    }
    // Invert the affine frame
    T det3 = T(0);
    const Mat3<T> linv = inverse(upper3(a), det3);
    const Vec3<T> ci = -(linv * xyz(a[3]));
    Mat4<T> r{};
    for (int j = 0; j < 3; ++j) r[j] = vec4(linv[j], T(0));
    r[3] = vec4(ci, T(1));
    if (is_projective(prim.kind)) {
        // Apply K: rows 2 and 3 become the half difference and the half sum of A^-1's rows 2 and 3
        for (int j = 0; j < 4; ++j) {
            const T a2 = r[j][2], a3 = r[j][3];
            r[j][2] = (a2 - a3) * T(0.5);
            r[j][3] = (a2 + a3) * T(0.5);
        }
    }
    return r;
}

/// Conic matrix Q = T^-T D T^-1 from D and T^-1 (Sigg et al. 2006, eq. 1), exactly symmetric.
/// Entry (i, j) = sum_k d_k Ti_ki Ti_kj with Ti = T^-1.
/// Numerics: `dot(cmul(d, col_i), col_j)` over the columns of T^-1 (left fold over k,
/// each term (d_k * Ti_ki) * Ti_kj); computed for i <= j and mirrored.
/// (Equals `transform_with_inverse(Quadric{diag(d)}, t_inv)` in exact arithmetic, with 4 instead
/// of 16 products per entry.)
template <class T>
Quadric<T> quadric_from_inverse(const Vec4<T>& d, const Mat4<T>& t_inv) {
    Quadric<T> q{};
    for (int i = 0; i < 4; ++i) {
        const Vec4<T> di = cmul(d, t_inv[i]);
        for (int j = i; j < 4; ++j) {
            q.q[j][i] = dot(di, t_inv[j]);
            q.q[i][j] = q.q[j][i];
        }
    }
    return q;
}

/// Conic matrix of `prim` in object coordinates: `quadric_from_inverse(d, inverse_variance(prim))`.
template <class T>
Quadric<T> to_quadric(const ParameterForm<T>& prim) {
    return quadric_from_inverse(prim.d, inverse_variance(prim));
}

}  // namespace quadcast
