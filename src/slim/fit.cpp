// src/slim/fit.cpp -- one SLIM ball's quadric: weighted least squares on points and normals
#include "quadcast/slim/fit.hpp"

#include <Eigen/Dense>

#include <cmath>
#include <limits>

namespace quadcast::slim {

namespace {

Mat3<double> scaled(Mat3<double> a, double s) {
    for (int j = 0; j < 3; ++j) a[j] = a[j] * s;
    return a;
}

using Row = Eigen::Matrix<double, 10, 1>;

/// The monomials of Coefficients10's order at u: 1 x y z xy yz zx x^2 y^2 z^2.
Row monomials(const Vec3d& u) {
    Row v;
    v << 1, u[0], u[1], u[2], u[0] * u[1], u[1] * u[2], u[2] * u[0], u[0] * u[0], u[1] * u[1], u[2] * u[2];
    return v;
}

/// d/dx, d/dy, d/dz of the monomials at u.
void gradient_rows(const Vec3d& u, Row& gx, Row& gy, Row& gz) {
    const double x = u[0], y = u[1], z = u[2];
    gx << 0, 1, 0, 0, y, 0, z, 2 * x, 0, 0;
    gy << 0, 0, 1, 0, x, z, 0, 0, 2 * y, 0;
    gz << 0, 0, 0, 1, 0, y, x, 0, 0, 2 * z;
}

}  // namespace

double gradient_line_distance(const Quadric<double>& q, const Vec3d& x) {
    const double f = evaluate(q, x);
    const Vec3d g = gradient(q, x);
    const double gg = dot(g, g);
    if (f == 0) return 0;
    if (!std::isfinite(f) || !std::isfinite(gg)) return std::numeric_limits<double>::infinity();
    const double gl = std::sqrt(gg);
    // a = g^T A g / |g|^2 (the curvature term along the gradient line).
    const double a = gg > 0 ? dot(g, upper3(q.q) * g) / gg : 0.0;
    const double disc = gg - 4 * a * f;
    if (!(disc >= 0)) return std::numeric_limits<double>::infinity();
    const double den = gl + std::sqrt(disc);
    if (!(den > 0)) return std::numeric_limits<double>::infinity();
    return std::fabs(2 * f / den);
}

Quadric<double> local_to_world(const Quadric<double>& local, const Vec3d& c, double r) {
    const QuadricABC<double> l = to_abc(local);
    const Quadric<double> shifted = quadric_from_abc(scaled(l.A, 1 / r), l.b, l.c * r);
    return translate_to_eye(shifted, -c);
}

Quadric<double> world_to_local(const Quadric<double>& world, const Vec3d& c, double r) {
    const QuadricABC<double> y = to_abc(translate_to_eye(world, c));
    return quadric_from_abc(scaled(y.A, r), y.b, y.c / r);
}

LocalFit fit_ball(const std::vector<Vec3d>& positions, const std::vector<Vec3d>& normals,
                  const std::vector<std::uint32_t>& idx, const Vec3d& c, double r, const FitOptions& options) {
    LocalFit out;
    if (idx.size() < 10 || !(r > 0)) return out;
    const double inv_r = 1 / r;
    const double lambda2 = options.normal_weight * options.normal_weight;
    // Accumulate the normal matrix of the residuals and the constraint row, per unit weight.
    Eigen::Matrix<double, 10, 10> m = Eigen::Matrix<double, 10, 10>::Zero();
    Row h = Row::Zero();
    Row gx, gy, gz;
    for (const std::uint32_t i : idx) {
        const Vec3d u = (positions[i] - c) * inv_r;
        const Vec3d& n = normals[i];
        const Row v = monomials(u);
        gradient_rows(u, gx, gy, gz);
        // n x grad f, row by row.
        const Row c0 = n[1] * gz - n[2] * gy;
        const Row c1 = n[2] * gx - n[0] * gz;
        const Row c2 = n[0] * gy - n[1] * gx;
        m.noalias() += v * v.transpose();
        m.noalias() += lambda2 * (c0 * c0.transpose() + c1 * c1.transpose() + c2 * c2.transpose());
        h += n[0] * gx + n[1] * gy + n[2] * gz;
    }
    const double w = double(idx.size());
    m /= w;
    h /= w;
    for (int k = 4; k < 10; ++k) m(k, k) += options.regularization;
    // Solve the KKT system [M h; h^T 0] [k; l] = [0; 1].
    Eigen::Matrix<double, 11, 11> kkt = Eigen::Matrix<double, 11, 11>::Zero();
    kkt.topLeftCorner<10, 10>() = m;
    kkt.block<10, 1>(0, 10) = h;
    kkt.block<1, 10>(10, 0) = h.transpose();
    Eigen::Matrix<double, 11, 1> rhs = Eigen::Matrix<double, 11, 1>::Zero();
    rhs(10) = 1;
    const Eigen::FullPivLU<Eigen::Matrix<double, 11, 11>> lu(kkt);
    if (!lu.isInvertible()) return out;
    const Eigen::Matrix<double, 11, 1> sol = lu.solve(rhs);
    if (!sol.allFinite()) return out;
    Coefficients10<double> k{sol(0), sol(1), sol(2), sol(3), sol(4), sol(5), sol(6), sol(7), sol(8), sol(9)};
    Quadric<double> q = quadric_from_coefficients(k);
    // Scale so that the mean |grad f| over the points is 1.
    double mean_grad = 0;
    for (const std::uint32_t i : idx) mean_grad += length(gradient(q, (positions[i] - c) * inv_r));
    mean_grad /= w;
    if (!(mean_grad > 0) || !std::isfinite(mean_grad)) return out;
    for (int j = 0; j < 4; ++j)
        for (int i = 0; i < 4; ++i) q.q[j][i] /= mean_grad;
    // Measure: distance along the gradient line and orientation at every point.
    out.solved = true;
    out.local = q;
    out.oriented = true;
    out.min_normal_cos = 1;
    double sum2 = 0;
    for (const std::uint32_t i : idx) {
        const Vec3d u = (positions[i] - c) * inv_r;
        const double d = gradient_line_distance(q, u) * r;
        out.max_distance = std::max(out.max_distance, d);
        sum2 += d * d;
        const Vec3d g = gradient(q, u);
        if (!(dot(g, normals[i]) > 0)) out.oriented = false;
        const double gl = length(g);
        out.min_normal_cos = std::min(out.min_normal_cos, gl > 0 ? dot(g, normals[i]) / gl : -1.0);
    }
    out.rms_distance = std::sqrt(sum2 / w);
    return out;
}

}  // namespace quadcast::slim
