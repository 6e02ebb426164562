// quadcast/render/validate.hpp -- checks that a render::Primitive is drawable as it claims
#pragma once

// Host-only (double, Eigen). Both renderers call `validate_primitives` before drawing, so a
// hand-made primitive with a NaN, a bounding radius too small for its shape (the renderers
// rasterise the bounding sphere only, so the rest would be cropped silently) or an impossible
// material is an exception naming the primitive and the field, not a silent picture.

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "quadcast/linalg.hpp"
#include "quadcast/render/types.hpp"

namespace quadcast::render {

namespace validate_detail {

inline std::string num(double x) {
    std::ostringstream s;
    s.precision(9);
    s << x;
    return s.str();
}

[[noreturn]] inline void fail(std::size_t index, const std::string& what) {
    throw std::invalid_argument("quadcast::render: primitive " + std::to_string(index) + ": " + what);
}

inline Eigen::Matrix3d upper(const Mat4<float>& q) {
    Eigen::Matrix3d a;
    for (int j = 0; j < 3; ++j)
        for (int i = 0; i < 3; ++i) a(i, j) = 0.5 * (double(q[j][i]) + double(q[i][j]));
    return a;
}

inline Eigen::Vector3d linear(const Mat4<float>& q) { return {0.5 * (double(q[3][0]) + double(q[0][3])), 0.5 * (double(q[3][1]) + double(q[1][3])), 0.5 * (double(q[3][2]) + double(q[2][3]))}; }

/// Largest |x| over the ellipsoid x^T A x + 2 b.x + c <= 0 (A definite): the centre's distance
/// plus the longest semi-axis is an upper bound, exact when the centre is at the origin; the
/// exact value is the larger of that bound's two ends only then, so points on a 32 x 64 grid of
/// the surface give the lower bound that decides (within 1e-6 of the bound's scale).
inline double ellipsoid_extent(std::size_t index, const Mat4<float>& q) {
    Eigen::Matrix3d a = upper(q);
    Eigen::Vector3d b = linear(q);
    double c = q[3][3];
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(a);
    Eigen::Vector3d lam = es.eigenvalues();
    if (lam[0] < 0 && lam[2] < 0) {  // -f: the same surface with the inside f < 0
        a = -a;
        b = -b;
        c = -c;
        lam = -lam.reverse().eval();
    }
    if (!(lam[0] > 0)) fail(index, "variant ellipsoid needs a definite quadric (eigenvalues of A " + num(lam[0]) + ", " + num(lam[2]) + ")");
    const Eigen::Vector3d centre = -a.ldlt().solve(b);
    const double k0 = c + b.dot(centre);
    if (!(k0 < 0)) fail(index, "variant ellipsoid: the quadric's zero set is empty or a point");
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> e2(a);
    Eigen::Vector3d semi;
    for (int k = 0; k < 3; ++k) semi[k] = std::sqrt(-k0 / e2.eigenvalues()[k]);
    if (centre.norm() <= 1e-9 * semi.maxCoeff()) return semi.maxCoeff() + centre.norm();
    double best = 0;
    for (int i = 0; i <= 32; ++i)
        for (int j = 0; j < 64; ++j) {
            const double th = M_PI * i / 32, ph = 2 * M_PI * j / 64;
            const Eigen::Vector3d s(std::sin(th) * std::cos(ph) * semi[0], std::sin(th) * std::sin(ph) * semi[1], std::cos(th) * semi[2]);
            best = std::max(best, (centre + e2.eigenvectors() * s).norm());
        }
    return best;
}

/// Largest |x| over the slab part {f <= 0, |a.x| <= h} of a quadric whose cross-sections in the
/// slab are bounded (cylinders, cones, hyperboloids): on the two cap planes the section is an
/// ellipse (or empty, or a point), sampled at 720 points; the surface between is ruled, so the
/// caps bound it.
inline double slab_extent(std::size_t index, const Mat4<float>& q, const Vec3<float>& axis_f, double h) {
    const Eigen::Matrix3d a = upper(q);
    const Eigen::Vector3d b = linear(q);
    const double c = q[3][3];
    const Eigen::Vector3d ax(axis_f[0], axis_f[1], axis_f[2]);
    // A basis (e1, e2) of the cap planes.
    Eigen::Vector3d e1 = ax.unitOrthogonal(), e2 = ax.cross(e1);
    Eigen::Matrix<double, 3, 2> e;
    e.col(0) = e1;
    e.col(1) = e2;
    double best = 0;
    for (double z : {h, -h}) {
        // f(z a + E s) = s^T M s + 2 m.s + k
        const Eigen::Vector3d p0 = z * ax;
        const Eigen::Matrix2d m = e.transpose() * a * e;
        const Eigen::Vector2d mv = e.transpose() * (a * p0 + b);
        const double k = p0.dot(a * p0) + 2 * b.dot(p0) + c;
        const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> es(m);
        const Eigen::Vector2d lam = es.eigenvalues();
        const double scale = std::max(std::fabs(lam[0]), std::fabs(lam[1]));
        if (!(lam[0] > 1e-12 * scale) || !(scale > 0))
            fail(index, "variant slab: the quadric's cross-section at a cap is not bounded (the slab variants draw cylinders, cones and hyperboloids along their axis)");
        const Eigen::Vector2d s0 = -m.ldlt().solve(mv);
        const double k0 = k + mv.dot(s0);
        best = std::max(best, (p0 + e * s0).norm());
        if (k0 >= 0) continue;  // empty or a point
        for (int i = 0; i < 720; ++i) {
            const double t = 2 * M_PI * i / 720;
            const Eigen::Vector2d s = s0 + es.eigenvectors() * Eigen::Vector2d(std::cos(t) * std::sqrt(-k0 / lam[0]), std::sin(t) * std::sqrt(-k0 / lam[1]));
            best = std::max(best, (p0 + e * s).norm());
        }
    }
    return best;
}

/// Largest |x| over the corners of the tetrahedron of four planes (each corner on three of them).
inline double tet_extent(std::size_t index, const Vec4<float> (&planes)[4]) {
    double best = 0;
    for (int skip = 0; skip < 4; ++skip) {
        Eigen::Matrix3d m;
        Eigen::Vector3d r;
        int row = 0;
        for (int i = 0; i < 4; ++i) {
            if (i == skip) continue;
            m.row(row) = Eigen::Vector3d(planes[i][0], planes[i][1], planes[i][2]);
            r[row] = -double(planes[i][3]);
            ++row;
        }
        const Eigen::FullPivLU<Eigen::Matrix3d> lu(m);
        if (!lu.isInvertible()) fail(index, "variant planes: three clip planes do not meet in a point (a flat tetrahedron)");
        best = std::max(best, lu.solve(r).norm());
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
