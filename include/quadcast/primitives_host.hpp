// quadcast/primitives_host.hpp -- host-only (Eigen, double): parameter-space form <-> conic matrix
#pragma once

#include <cmath>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>

#include <Eigen/Dense>

#include "quadcast/linalg.hpp"
#include "quadcast/primitives.hpp"
#include "quadcast/quadric.hpp"

// Not traced: these functions use Eigen, exceptions and strings and run on the CPU only.
namespace quadcast::host {

/// Eigen copy of a quadcast matrix (m(i, j) = a[j][i]).
inline Eigen::Matrix4d to_eigen(const Mat4<double>& a) {
    Eigen::Matrix4d m;
    for (int j = 0; j < 4; ++j)
        for (int i = 0; i < 4; ++i) m(i, j) = a[j][i];
    return m;
}

/// quadcast copy of an Eigen matrix.
inline Mat4<double> from_eigen(const Eigen::Matrix4d& m) {
    Mat4<double> a{};
    for (int j = 0; j < 4; ++j)
        for (int i = 0; i < 4; ++i) a[j][i] = m(i, j);
    return a;
}

/// Conic matrix Q = T^-T D T^-1 (Sigg et al. 2006, eq. 1) in double, T^-1 by `host_inverse`
/// (Gauss-Jordan with partial pivoting in long double). Works for projective T (paraboloids). Throws std::invalid_argument when T
/// is singular or not finite.
inline Quadric<double> quadric_from_form(const Vec4<double>& d, const Mat4<double>& t) {
    for (int j = 0; j < 4; ++j)
        for (int i = 0; i < 4; ++i)
            if (!std::isfinite(t[j][i])) throw std::invalid_argument("variance matrix T has a NaN or infinite entry");
    Mat4<double> t_inv;
    try {
        t_inv = host_inverse(t);
    } catch (const std::invalid_argument&) {
        throw std::invalid_argument("variance matrix T is singular");
    }
    const Eigen::Matrix4d ti = to_eigen(t_inv);
    const Eigen::Vector4d dv(d[0], d[1], d[2], d[3]);
    Eigen::Matrix4d q = ti.transpose() * dv.asDiagonal() * ti;
    q = ((q + q.transpose()) * 0.5).eval();  // eval: q is aliased
    return {from_eigen(q)};
}

/// `quadric_from_form(prim.d, prim.t)` for a primitive of any scalar type (converted to double).
template <class T>
Quadric<double> quadric_from_form(const ParameterForm<T>& prim) {
    return quadric_from_form(cast<double>(prim.d), cast<double>(prim.t));
}

/// A quadric put into parameter-space form: Q = scale * T^-T D T^-1.
struct Decomposition {
    ParameterForm<double> prim;  ///< kind, D, T; the slab is the kind's default (set it yourself)
    double scale;            ///< nonzero, may be negative
};

/// Result of `decompose_quadric`: a value, or a reason why there is none.
struct DecomposeResult {
    std::optional<Decomposition> value;
    std::string error;  ///< empty on success
    explicit operator bool() const { return value.has_value(); }
};

/// Parameter-space form of a general conic matrix Q = [A b; b^T c] (Sigg et al. 2006, eq. 1),
/// by the eigen-decomposition A = V diag(lambda) V^T (Eigen's SelfAdjointEigenSolver).
///
/// - A invertible (central): centre m = -A^-1 b, c' = c + b.m; D = signs of (lambda, c') up to a
///   common sign, axes v_i * sqrt(|c' / lambda_i|): ellipsoid (1,1,1,-1), one-sheet hyperboloid
///   (1,1,-1,-1), two-sheet hyperboloid (1,1,-1,1); c' = 0 and A indefinite: cone (1,1,-1,0)
///   with axes v_i / sqrt|lambda_i|.
/// - A of rank 2 (non-central), null vector n: b.n != 0 and the two eigenvalues of one sign:
///   elliptic paraboloid (projective T, see `quadcast::paraboloid`); b.n = 0: elliptic cylinder
///   (1,1,0,-1) with unit axis w = n around the least-squares centre -A^+ b.
/// - Everything else is an error with a reason: non-finite or non-symmetric input, empty
///   (imaginary) quadrics, a point, a line, plane pairs, planes, hyperbolic paraboloids and
///   cylinders, parabolic cylinders.
/// The axis order puts the axis of the odd sign last (w) and makes det[u v w] > 0.
/// `rel_tol`: eigenvalues below rel_tol * max|lambda| count as zero; b.n and c' count as zero
/// below rel_tol times the size of the terms they are computed from.
inline DecomposeResult decompose_quadric(const Quadric<double>& q_in, double rel_tol = 1e-9) {
    auto fail = [](std::string why) { return DecomposeResult{std::nullopt, std::move(why)}; };
    Eigen::Matrix4d q = to_eigen(q_in.q);
    // Reject bad input and normalise the scale
    if (!q.allFinite()) return fail("conic matrix has a NaN or infinite entry");
    const double s0 = q.cwiseAbs().maxCoeff();
    if (s0 == 0.0) return fail("conic matrix is zero");
    if ((q - q.transpose()).cwiseAbs().maxCoeff() > rel_tol * s0) return fail("conic matrix is not symmetric");
    q = ((q + q.transpose()) * (0.5 / s0)).eval();  // eval: q is aliased
    const Eigen::Matrix3d a = q.topLeftCorner<3, 3>();
    const Eigen::Vector3d b = q.block<3, 1>(0, 3);
    const double c = q(3, 3);

    // Diagonalise the quadratic part
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(a);
    if (es.info() != Eigen::Success) return fail("eigen-decomposition of the quadratic part failed");
    const Eigen::Vector3d lam = es.eigenvalues();
    const Eigen::Matrix3d vec = es.eigenvectors();
    const double lmax = lam.cwiseAbs().maxCoeff();
    if (lmax == 0.0) return fail("degenerate quadric: the quadratic part vanishes (a plane or nothing)");
    int sgn[3], rank = 0;
    for (int i = 0; i < 3; ++i) {
        sgn[i] = std::abs(lam[i]) <= rel_tol * lmax ? 0 : (lam[i] > 0 ? 1 : -1);
        rank += sgn[i] != 0;
    }
    auto v3 = [](const Eigen::Vector3d& e) { return vec3(e[0], e[1], e[2]); };
    auto sign = [](double x) { return x > 0 ? 1 : (x < 0 ? -1 : 0); };

    // Order three axes so that the odd sign comes last and the frame is right-handed
    auto order_axes = [&](const int dsign[3], Eigen::Vector3d axes[3]) {
        int odd = -1, npos = 0;
        for (int i = 0; i < 3; ++i) npos += dsign[i] > 0;
        for (int i = 0; i < 3; ++i)
            if ((npos == 2 && dsign[i] < 0) || (npos == 1 && dsign[i] > 0)) odd = i;
        if (odd >= 0 && odd != 2) std::swap(axes[odd], axes[2]);
        if (axes[0].cross(axes[1]).dot(axes[2]) < 0) axes[0] = -axes[0];
    };

    if (rank == 3) {
        // Central quadric: move the centre to the origin
        const Eigen::Vector3d m = -(vec * lam.cwiseInverse().asDiagonal() * vec.transpose() * b);
        const double bm = b.dot(m);
        const double cp = c + bm;
        const bool cone = std::abs(cp) <= rel_tol * std::max(std::abs(c), std::abs(bm));
        Eigen::Vector3d axes[3];
        int dsign[3];
        if (cone) {
            int npos = 0;
            for (int i = 0; i < 3; ++i) npos += sgn[i] > 0;
            if (npos == 3 || npos == 0) return fail("degenerate quadric: a single real point (definite A, c' = 0)");
            const int sigma = npos == 2 ? 1 : -1;
            for (int i = 0; i < 3; ++i) {
                axes[i] = vec.col(i) / std::sqrt(std::abs(lam[i]));
                dsign[i] = sigma * sgn[i];
            }
            order_axes(dsign, axes);
            ParameterForm<double> p = elliptic_cone(v3(m), v3(axes[0]), v3(axes[1]), v3(axes[2]));
            p.slab = vec2(-1.0, 1.0);
            return {Decomposition{p, s0 * sigma}, {}};
        }
        // Normalise the signature (D has two or three +1 entries, c' entry -1 where possible)
        int s4[4] = {sgn[0], sgn[1], sgn[2], sign(cp)};
        int npos = 0;
        for (int s : s4) npos += s > 0;
        if (npos == 4 || npos == 0) return fail("empty quadric: imaginary ellipsoid (no real points)");
        const int sigma = npos == 2 ? -s4[3] : (npos == 3 ? 1 : -1);
        for (int i = 0; i < 3; ++i) {
            axes[i] = vec.col(i) * std::sqrt(std::abs(cp / lam[i]));
            dsign[i] = sigma * sgn[i];
        }
        order_axes(dsign, axes);
        const int d3 = sigma * s4[3];
        int nneg = 0;
        for (int i = 0; i < 3; ++i) nneg += dsign[i] < 0;
        ParameterForm<double> p{};
        if (nneg == 0) p = ellipsoid(v3(m), v3(axes[0]), v3(axes[1]), v3(axes[2]));
        else if (d3 < 0) p = hyperboloid_one_sheet(v3(m), v3(axes[0]), v3(axes[1]), v3(axes[2]), 1.0);
        else p = hyperboloid_two_sheets(v3(m), v3(axes[0]), v3(axes[1]), v3(axes[2]), -2.0, 2.0);
        return {Decomposition{p, s0 * sigma * std::abs(cp)}, {}};
    }

    if (rank == 2) {
        // Non-central: split off the null direction n of A
        int k = 0;
        for (int i = 0; i < 3; ++i)
            if (sgn[i] == 0) k = i;
        const int i0 = k == 0 ? 1 : 0, i1 = k == 2 ? 1 : 2;
        const Eigen::Vector3d n = vec.col(k);
        const double beta = b.dot(n);
        const Eigen::Vector3d m0 = -(vec.col(i0) * (vec.col(i0).dot(b) / lam[i0]) +
                                     vec.col(i1) * (vec.col(i1).dot(b) / lam[i1]));
        const double bm = b.dot(m0);
        const double c0 = c + bm;
        const bool same = sgn[i0] == sgn[i1];
        const int sigma = sgn[i0];
        if (std::abs(beta) > rel_tol * std::max(b.norm(), lmax)) {
            if (!same) return fail("hyperbolic paraboloid: not supported (no primitive of this class)");
            // Elliptic paraboloid: sigma f = X^2 + Y^2 - Z in the frame [u v w vertex]
            Eigen::Vector3d axes[3] = {vec.col(i0) / std::sqrt(std::abs(lam[i0])),
                                       vec.col(i1) / std::sqrt(std::abs(lam[i1])),
                                       n * (-1.0 / (2.0 * sigma * beta))};
            if (axes[0].cross(axes[1]).dot(axes[2]) < 0) axes[0] = -axes[0];
            const Eigen::Vector3d vertex = m0 - n * (c0 / (2.0 * beta));
            const ParameterForm<double> p = paraboloid(v3(vertex), v3(axes[0]), v3(axes[1]), v3(axes[2]));
            return {Decomposition{p, s0 * sigma}, {}};
        }
        if (!same) {
            if (std::abs(c0) <= rel_tol * std::max(std::abs(c), std::abs(bm)))
                return fail("degenerate quadric: a pair of intersecting planes");
            return fail("hyperbolic cylinder: not supported (no primitive of this class)");
        }
        if (std::abs(c0) <= rel_tol * std::max(std::abs(c), std::abs(bm)))
            return fail("degenerate quadric: a single real line (elliptic cylinder of radius 0)");
        if (sigma * c0 > 0) return fail("empty quadric: imaginary elliptic cylinder (no real points)");
        // Elliptic cylinder around the least-squares centre
        Eigen::Vector3d axes[3] = {vec.col(i0) * std::sqrt(std::abs(c0 / lam[i0])),
                                   vec.col(i1) * std::sqrt(std::abs(c0 / lam[i1])), n};
        if (axes[0].cross(axes[1]).dot(axes[2]) < 0) axes[0] = -axes[0];
        const ParameterForm<double> p = elliptic_cylinder(v3(m0), v3(axes[0]), v3(axes[1]), v3(axes[2]));
        return {Decomposition{p, s0 * sigma * std::abs(c0)}, {}};
    }
    return fail("degenerate quadric: rank of the quadratic part is 1 (parabolic cylinder or parallel planes)");
}

}  // namespace quadcast::host
