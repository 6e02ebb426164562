// quadcast/render/validate.hpp -- checks that a render::Primitive is drawable as it claims
#pragma once

// Host-only (double). Both renderers call `validate_primitives` before drawing, so a
// hand-made primitive with a NaN, a bounding radius too small for its shape (the renderers
// rasterise the bounding sphere only, so the rest would be cropped silently) or an impossible
// material is an exception naming the primitive and the field, not a silent picture.

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "quadcast/bounds.hpp"
#include "quadcast/linalg.hpp"
#include "quadcast/render/types.hpp"

namespace quadcast::render {

namespace validate_detail {

using V3 = Vec3<double>;
using M3 = Mat3<double>;

inline std::string num(double x) {
    std::ostringstream s;
    s.precision(9);
    s << x;
    return s.str();
}

[[noreturn]] inline void fail(std::size_t index, const std::string& what) {
    throw std::invalid_argument("quadcast::render: primitive " + std::to_string(index) + ": " + what);
}

/// A (symmetrised), b and c of Q = [A b; b^T c] in double.
inline void split(const Mat4<float>& q, M3& a, V3& b, double& c) {
    for (int j = 0; j < 3; ++j)
        for (int i = 0; i < 3; ++i) a[j][i] = 0.5 * (double(q[j][i]) + double(q[i][j]));
    for (int i = 0; i < 3; ++i) b[i] = 0.5 * (double(q[3][i]) + double(q[i][3]));
    c = q[3][3];
}

/// Eigenvalues of a symmetric 3x3 matrix, ascending (the trigonometric closed form of the
/// characteristic cubic; exact enough for a range check).
inline V3 symmetric_eigenvalues(const M3& a) {
    const double p1 = a[1][0] * a[1][0] + a[2][0] * a[2][0] + a[2][1] * a[2][1];
    const double q = (a[0][0] + a[1][1] + a[2][2]) / 3.0;
    const double p2 = (a[0][0] - q) * (a[0][0] - q) + (a[1][1] - q) * (a[1][1] - q) + (a[2][2] - q) * (a[2][2] - q) + 2.0 * p1;
    if (p2 == 0) return vec3(q, q, q);
    const double p = std::sqrt(p2 / 6.0);
    M3 bm = a;
    for (int i = 0; i < 3; ++i) bm[i][i] -= q;
    for (int j = 0; j < 3; ++j)
        for (int i = 0; i < 3; ++i) bm[j][i] /= p;
    const double det = bm[0][0] * (bm[1][1] * bm[2][2] - bm[2][1] * bm[1][2]) - bm[1][0] * (bm[0][1] * bm[2][2] - bm[2][1] * bm[0][2]) +
                       bm[2][0] * (bm[0][1] * bm[1][2] - bm[1][1] * bm[0][2]);
    const double r = std::clamp(det / 2.0, -1.0, 1.0);
    const double phi = std::acos(r) / 3.0;
    const double e_max = q + 2.0 * p * std::cos(phi), e_min = q + 2.0 * p * std::cos(phi + 2.0 * M_PI / 3.0);
    return vec3(e_min, 3.0 * q - e_min - e_max, e_max);
}

/// Solves a x = r for a symmetric positive-definite 3x3 a (`inverse` of linalg.hpp).
inline V3 solve(const M3& a, const V3& r) {
    double d = 0;
    const M3 inv = inverse(a, d);
    return inv * r;
}

/// Largest |x| over the ellipsoid x^T A x + 2 b.x + c <= 0 (A definite; the sign of Q may be
/// either): |centre| + longest semi-axis bounds it and is exact for a centred ellipsoid (the
/// renderers' case); off centre, points x = centre + s L^-T u with A = L L^T (Cholesky) and u on a
/// 64 x 128 grid of the unit sphere give the value to within 3e-4 of it.
inline double ellipsoid_extent(std::size_t index, const Mat4<float>& q) {
    M3 a{};
    V3 b{};
    double c = 0;
    split(q, a, b, c);
    V3 lam = symmetric_eigenvalues(a);
    if (lam[0] < 0 && lam[2] < 0) {  // -f: the same surface with the inside f < 0
        for (int j = 0; j < 3; ++j)
            for (int i = 0; i < 3; ++i) a[j][i] = -a[j][i];
        b = -b;
        c = -c;
        lam = vec3(-lam[2], -lam[1], -lam[0]);
    }
    if (!(lam[0] > 1e-12 * lam[2])) fail(index, "variant ellipsoid needs a definite quadric (eigenvalues of A " + num(lam[0]) + " .. " + num(lam[2]) + ")");
    const V3 centre = -solve(a, b);
    const double k0 = c + dot(b, centre);
    if (!(k0 < 0)) fail(index, "variant ellipsoid: the quadric's zero set is empty or a point");
    const double major = std::sqrt(-k0 / lam[0]);
    const double lc = length(centre);
    if (lc <= 1e-9 * major) return major + lc;
    // Cholesky A = L L^T (lower L, rows l[i]); x = centre + sqrt(-k0) L^-T u.
    double l[3][3] = {};
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j <= i; ++j) {
            double s = a[j][i];
            for (int k = 0; k < j; ++k) s -= l[i][k] * l[j][k];
            l[i][j] = i == j ? std::sqrt(std::max(s, 0.0)) : s / l[j][j];
        }
    double best = 0;
    for (int i = 0; i <= 64; ++i)
        for (int j = 0; j < 128; ++j) {
            const double th = M_PI * i / 64, ph = 2 * M_PI * j / 128;
            const double u[3] = {std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph), std::cos(th)};
            // back substitution L^T y = u
            double y[3];
            for (int r = 2; r >= 0; --r) {
                double s = u[r];
                for (int k = r + 1; k < 3; ++k) s -= l[k][r] * y[k];
                y[r] = s / l[r][r];
            }
            best = std::max(best, length(centre + std::sqrt(-k0) * vec3(y[0], y[1], y[2])));
        }
    return best;
}

/// Largest |x| over the slab part {f <= 0, |a.x| <= h} of a quadric whose cross-sections in the
/// slab are bounded (cylinders, cones, hyperboloids of one sheet): on the two cap planes the
/// section is an ellipse (or empty, or a point), sampled at 720 points. Every section of the
/// slab is an ellipse of the same shape (the in-plane part M of A) whose centre moves linearly
/// along the axis and whose squared size rho(z) = -k0(z) is quadratic in z, so the slab lies in
/// the convex hull of its two end sections (which the renderers' tight rectangles and this extent
/// use) exactly when sqrt(rho) stays below the straight line between its end values; since
/// rho(z) - line(z)^2 = (alpha - s^2)(z^2 - h^2), that holds everywhere when it holds at z = 0.
/// A quadric that bulges out between its ends (a sphere or an ellipsoid marked as a slab) is
/// rejected: use the ellipsoid variant.
inline double slab_extent(std::size_t index, const Mat4<float>& q, const Vec3<float>& axis_f, double h) {
    M3 a{};
    V3 b{};
    double c = 0;
    split(q, a, b, c);
    const V3 ax = normalize(cast<double>(axis_f));
    // An orthonormal basis (e1, e2) of the cap planes.
    V3 e1, e2;
    plane_basis(ax, e1, e2);
    double best = 0, size[3] = {0, 0, 0};  // sqrt(rho) at h, -h, 0
    int which = 0;
    for (double z : {h, -h, 0.0}) {
        // f(z a + s e1 + t e2) = [s t] M [s t]^T + 2 m.[s t] + k
        const V3 p0 = z * ax;
        const V3 ap0 = a * p0, ae1 = a * e1, ae2 = a * e2;
        const double m00 = dot(e1, ae1), m01 = dot(e1, ae2), m11 = dot(e2, ae2);
        const double m0 = dot(e1, ap0 + b), m1 = dot(e2, ap0 + b);
        const double k = dot(p0, ap0) + 2 * dot(b, p0) + c;
        // Eigen-decomposition of the 2x2 M.
        const double tr = 0.5 * (m00 + m11), dd = std::sqrt(0.25 * (m00 - m11) * (m00 - m11) + m01 * m01);
        const double l0 = tr - dd, l1 = tr + dd;
        const double scale = std::max(std::fabs(l0), std::fabs(l1));
        if (!(scale > 0) || !(l0 > 1e-12 * scale))
            fail(index, "variant slab: the quadric's cross-section at a cap is not bounded (the slab variants draw cylinders, cones and hyperboloids along their axis)");
        const double det = m00 * m11 - m01 * m01;
        const double s0 = -(m11 * m0 - m01 * m1) / det, t0 = -(m00 * m1 - m01 * m0) / det;
        const double k0 = k + m0 * s0 + m1 * t0;
        size[which++] = std::sqrt(std::max(-k0, 0.0));
        if (z == 0.0) break;
        best = std::max(best, length(p0 + s0 * e1 + t0 * e2));
        if (k0 >= 0) continue;  // empty or a point
        // Unit eigenvectors of M (v0 for l0, v1 = its perpendicular).
        double v0x = m01, v0y = l0 - m00;
        if (std::fabs(v0x) + std::fabs(v0y) < 1e-300) { v0x = m11 - l0; v0y = -m01; }
        if (std::fabs(v0x) + std::fabs(v0y) < 1e-300) { v0x = 1; v0y = 0; }
        const double ln = std::hypot(v0x, v0y);
        v0x /= ln;
        v0y /= ln;
        const double r0 = std::sqrt(-k0 / l0), r1 = std::sqrt(-k0 / l1);
        for (int i = 0; i < 720; ++i) {
            const double th = 2 * M_PI * i / 720;
            const double ss = s0 + r0 * std::cos(th) * v0x - r1 * std::sin(th) * v0y;
            const double tt = t0 + r0 * std::cos(th) * v0y + r1 * std::sin(th) * v0x;
            best = std::max(best, length(p0 + ss * e1 + tt * e2));
        }
    }
    if (size[2] > 0.5 * (size[0] + size[1]) + 1e-4 * std::max(size[0], size[1]))
        fail(index, "variant slab: the surface bulges out between its end sections (section size " + num(size[2]) + " halfway, " + num(size[0]) + " and " +
                        num(size[1]) + " at the ends; the slab variants draw cylinders, cones and hyperboloids of one sheet; a closed quadric is variant ellipsoid)");
    return best;
}

/// Largest |x| over the corners of the tetrahedron of four planes (each corner on three of them).
inline double tet_extent(std::size_t index, const Vec4<float> (&planes)[4]) {
    double best = 0;
    for (int skip = 0; skip < 4; ++skip) {
        M3 m{};
        V3 r{};
        int row = 0;
        for (int i = 0; i < 4; ++i) {
            if (i == skip) continue;
            for (int k = 0; k < 3; ++k) m[k][row] = planes[i][k];
            r[row] = -double(planes[i][3]);
            ++row;
        }
        double d = 0;
        const M3 inv = inverse(m, d);
        double scale = 0;
        for (int j = 0; j < 3; ++j)
            for (int i = 0; i < 3; ++i) scale = std::max(scale, std::fabs(m[j][i]));
        if (!(std::fabs(d) > 1e-12 * scale * scale * scale)) fail(index, "variant planes: three clip planes do not meet in a point (a flat tetrahedron)");
        best = std::max(best, length(inv * r));
    }
    return best;
}

}  // namespace validate_detail

/// Throws std::invalid_argument("quadcast::render: primitive <index>: ...") when `p` cannot be
/// drawn as it says: a field that is not finite (half_length may be +Inf where unused), a radius
/// that is not positive, a slab axis that is not a unit vector, caps other than 0 or 1, colour
/// or material out of range, or a bounding radius smaller than the shape's extent (ellipsoid
/// and slab variants, tetrahedron-bounded planes: the renderers would crop the rest).
inline void validate(const Primitive& p, std::size_t index = 0) {
    using namespace validate_detail;
    const int v = static_cast<int>(p.variant);
    if (v < 0 || v >= variant_count) fail(index, "unknown variant " + std::to_string(v));
    for (int j = 0; j < 4; ++j)
        for (int i = 0; i < 4; ++i)
            if (!std::isfinite(p.shape.q.q[j][i])) fail(index, "quadric coefficient [" + std::to_string(j) + "][" + std::to_string(i) + "] is not finite");
    for (int i = 0; i < 3; ++i) {
        if (!std::isfinite(p.shape.center[i])) fail(index, "center is not finite");
        if (!std::isfinite(p.shape.axis[i])) fail(index, "axis is not finite");
        if (!(std::isfinite(p.color[i]) && p.color[i] >= 0.0f)) fail(index, "color components must be finite and >= 0 (got " + num(p.color[i]) + ")");
    }
    if (!(p.shape.radius > 0) || !std::isfinite(p.shape.radius)) fail(index, "radius must be positive and finite (got " + num(p.shape.radius) + ")");
    if (!(p.material.specular >= 0.0f && p.material.specular <= 1.0f)) fail(index, "material.specular must be in [0, 1] (got " + num(p.material.specular) + ")");
    if (!(p.material.shininess > 0.0f) || !std::isfinite(p.material.shininess)) fail(index, "material.shininess must be positive and finite (got " + num(p.material.shininess) + ")");
    const double r = p.shape.radius, tol = 1e-4 * r;
    const bool slab = p.variant == Variant::slab || p.variant == Variant::open_slab;
    if (slab || p.variant == Variant::planes) {
        if (!(p.shape.half_length > 0)) fail(index, "half_length must be positive (got " + num(p.shape.half_length) + ")");
        if (std::fabs(length(cast<double>(p.shape.axis)) - 1.0) > 1e-3) fail(index, "axis must be a unit vector (length " + num(length(cast<double>(p.shape.axis))) + ")");
    }
    if (slab) {
        if (!std::isfinite(p.shape.half_length)) fail(index, "half_length must be finite for a slab variant");
        for (int i = 0; i < 2; ++i)
            if (!(p.shape.caps[i] == 0.0f || p.shape.caps[i] == 1.0f)) fail(index, "caps must be 0 (open) or 1 (closed) (got " + num(p.shape.caps[i]) + ")");
        if (p.variant == Variant::slab && !(p.shape.caps[0] == 1.0f || p.shape.caps[1] == 1.0f))
            fail(index, "variant slab is closed: an open end needs variant open_slab");
        const double e = slab_extent(index, p.shape.q.q, p.shape.axis, p.shape.half_length);
        if (e > r + tol) fail(index, "the bounding radius " + num(r) + " is smaller than the shape's extent " + num(e) + " (the renderers would crop it)");
    }
    if (p.variant == Variant::ellipsoid) {
        const double e = ellipsoid_extent(index, p.shape.q.q);
        if (e > r + tol) fail(index, "the bounding radius " + num(r) + " is smaller than the ellipsoid's extent " + num(e) + " (the renderers would crop it)");
    }
    if (p.variant == Variant::planes) {
        for (int i = 0; i < 4; ++i)
            for (int k = 0; k < 4; ++k)
                if (!std::isfinite(p.shape.planes[i][k])) fail(index, "plane " + std::to_string(i) + " is not finite");
        // Tetrahedron-bounded quadrics (no slab): the tetrahedron must lie in the bounding sphere.
        // (Quads' planes are the patch's own parameters or extruded edges: the patch spans the
        // sphere around its corners by construction.)
        if (std::isinf(p.shape.half_length)) {
            bool tet = true;
            for (int i = 0; i < 4; ++i) tet = tet && (p.shape.planes[i][0] != 0.0f || p.shape.planes[i][1] != 0.0f || p.shape.planes[i][2] != 0.0f);
            // A quad's director planes come in parallel pairs (u, 1 - u): no tetrahedron.
            const auto parallel = [&](int i, int j) {
                const Vec3<double> a = cast<double>(xyz(p.shape.planes[i])), b = cast<double>(xyz(p.shape.planes[j]));
                return length(cross(a, b)) <= 1e-6 * length(a) * length(b);
            };
            if (tet && !parallel(0, 2) && !parallel(1, 3)) {
                const double e = tet_extent(index, p.shape.planes);
                if (e > r + tol) fail(index, "the bounding radius " + num(r) + " is smaller than the clip tetrahedron's extent " + num(e) + " (the renderers would crop it)");
            }
        }
    }
}

/// `validate` for every primitive (indices as given).
inline void validate_primitives(const std::vector<Primitive>& prims) {
    for (std::size_t i = 0; i < prims.size(); ++i) validate(prims[i], i);
}

}  // namespace quadcast::render
