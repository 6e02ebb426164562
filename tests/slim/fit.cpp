// tests/slim/fit.cpp -- one ball's quadric fit: recovery, planes, orientation, the distance
#include <doctest/doctest.h>

#include <cmath>
#include <random>
#include <vector>

#include "quadcast/primitives.hpp"
#include "quadcast/slim/fit.hpp"

using namespace quadcast;
using namespace quadcast::slim;

namespace {

/// Points on the zero set of q inside the ball (c, r): random points of the ball projected by
/// Newton steps along the gradient; normals grad f / |grad f|.
void sample_quadric(const Quadric<double>& q, const Vec3d& c, double r, int n, std::uint64_t seed,
                    std::vector<Vec3d>& pos, std::vector<Vec3d>& nrm) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(-1, 1);
    int tries = 0;
    while (int(pos.size()) < n && ++tries < 100 * n) {
        Vec3d x = c + vec3(u(rng), u(rng), u(rng)) * r;
        for (int it = 0; it < 50; ++it) {
            const Vec3d g = gradient(q, x);
            const double gg = dot(g, g);
            if (!(gg > 0)) break;
            x = x - g * (evaluate(q, x) / gg);
        }
        const Vec3d g = gradient(q, x);
        if (!(std::fabs(evaluate(q, x)) < 1e-12 * (1 + length(g))) || length(x - c) > r || !(length(g) > 1e-6)) continue;
        pos.push_back(x);
        nrm.push_back(g / length(g));
    }
}

std::vector<std::uint32_t> all(std::size_t n) {
    std::vector<std::uint32_t> i(n);
    for (std::size_t k = 0; k < n; ++k) i[k] = std::uint32_t(k);
    return i;
}

/// The 10 coefficients as a unit vector with a positive dot product with `ref`.
std::vector<double> unit_coeffs(const Quadric<double>& q, const std::vector<double>* ref = nullptr) {
    const Coefficients10<double> k = coefficients(q);
    std::vector<double> v{k.k000, k.k100, k.k010, k.k001, k.k110, k.k011, k.k101, k.k200, k.k020, k.k002};
    double s = 0, d = 0;
    for (std::size_t i = 0; i < v.size(); ++i) { s += v[i] * v[i]; if (ref) d += v[i] * (*ref)[i]; }
    s = std::sqrt(s) * (d < 0 ? -1 : 1);
    for (double& x : v) x /= s;
    return v;
}

}  // namespace

TEST_CASE("fitting a quadric's own samples recovers it up to scale") {
    const Vec3d c = vec3(3.0, -2.0, 1.5);
    const double r = 0.8;
    struct Case { const char* name; Coefficients10<double> k; };
    // Local shapes (in u = (x - c) / r) that cross the unit ball, moved to world coordinates.
    const Case cases[] = {
        {"ellipsoid", {-0.5, 0.1, 0, 0.2, 0, 0, 0, 1.0, 2.0, 0.5}},
        {"hyperboloid of one sheet", {-0.2, 0, 0, 0, 0.3, 0, 0, 1.0, 1.0, -1.0}},
        {"paraboloid", {0.1, 0, 0, -1.0, 0, 0, 0, 0.7, 0.4, 0}},
        {"cylinder", {-0.3, 0, 0.2, 0, 0, 0, 0.1, 1.0, 0, 1.0}},
        {"saddle", {0.05, 0.3, 0, -1.0, 0.6, 0.2, 0, 0.5, -0.5, 0}},
    };
    for (const Case& k : cases) {
        CAPTURE(k.name);
        const Quadric<double> world = local_to_world(quadric_from_coefficients(k.k), c, r);
        std::vector<Vec3d> pos, nrm;
        sample_quadric(world, c, r, 200, 7, pos, nrm);
        REQUIRE(pos.size() == 200);
        const LocalFit fit = fit_ball(pos, nrm, all(pos.size()), c, r);
        REQUIRE(fit.solved);
        CHECK(fit.oriented);
        CHECK(fit.max_distance < 1e-5 * r);
        const std::vector<double> want = unit_coeffs(quadric_from_coefficients(k.k));
        const std::vector<double> got = unit_coeffs(fit.local, &want);
        for (std::size_t i = 0; i < want.size(); ++i) CHECK(got[i] == doctest::Approx(want[i]).epsilon(1e-4).scale(1));
    }
}

TEST_CASE("a plane stays a plane: the quadratic part is zero relative to the linear part") {
    std::mt19937_64 rng(3);
    std::uniform_real_distribution<double> u(-1, 1);
    for (int trial = 0; trial < 10; ++trial) {
        const Vec3d n = normalize(vec3(u(rng), u(rng), u(rng)));
        const Vec3d c = vec3(u(rng), u(rng), u(rng)) * 10.0;
        const double r = 0.05;
        Vec3d b1{}, b2{};
        orthonormal_basis(n, b1, b2);
        std::vector<Vec3d> pos, nrm;
        for (int i = 0; i < 60; ++i) {
            pos.push_back(c + b1 * (r * 0.7 * u(rng)) + b2 * (r * 0.7 * u(rng)));
            nrm.push_back(n);
        }
        const LocalFit fit = fit_ball(pos, nrm, all(pos.size()), c, r);
        REQUIRE(fit.solved);
        const Coefficients10<double> k = coefficients(fit.local);
        const double lin = std::sqrt(k.k100 * k.k100 + k.k010 * k.k010 + k.k001 * k.k001);
        for (double q : {k.k110, k.k011, k.k101, k.k200, k.k020, k.k002}) CHECK(std::fabs(q) < 1e-6 * lin);
        CHECK(lin == doctest::Approx(1.0));  // |grad f| = 1
        CHECK(fit.max_distance < 1e-12);
        // The world quadric is the signed distance to the plane, positive along n.
        const Quadric<double> w = local_to_world(fit.local, c, r);
        CHECK(evaluate(w, c + n * 0.01) == doctest::Approx(0.01).epsilon(1e-6));
    }
}

TEST_CASE("normals pointing outward make f negative inside") {
    // Points on a sphere of radius 2 around the origin, a ball at its north pole.
    std::vector<Vec3d> pos, nrm;
    const Quadric<double> s = quadric_from_abc(identity<double, 3>(), vec3(0.0, 0.0, 0.0), -4.0);
    const Vec3d c = vec3(0.0, 0.0, 2.0);
    sample_quadric(s, c, 0.5, 100, 11, pos, nrm);
    LocalFit fit = fit_ball(pos, nrm, all(pos.size()), c, 0.5);
    REQUIRE(fit.solved);
    CHECK(fit.oriented);
    const Quadric<double> w = local_to_world(fit.local, c, 0.5);
    CHECK(evaluate(w, vec3(0.0, 0.0, 1.9)) < 0);
    CHECK(evaluate(w, vec3(0.0, 0.0, 2.1)) > 0);
    // The fit of a sphere is exact: f = (|x|^2 - 4) / 4 has |grad f| = 1 on the sphere.
    CHECK(evaluate(w, vec3(0.0, 0.0, 2.1)) == doctest::Approx((2.1 * 2.1 - 4) / 4).epsilon(1e-4));
    // Flipped normals flip the sign, and the same points with them are still a surface.
    for (Vec3d& n : nrm) n = -n;
    fit = fit_ball(pos, nrm, all(pos.size()), c, 0.5);
    CHECK(evaluate(local_to_world(fit.local, c, 0.5), vec3(0.0, 0.0, 1.9)) > 0);
}

TEST_CASE("the gradient-line distance is exact for spheres and planes and infinite off the surface's reach") {
    const Quadric<double> s = quadric_from_abc(identity<double, 3>(), vec3(0.0, 0.0, 0.0), -1.0);
    for (double d : {1e-6, 0.01, 0.3, -0.5, 2.0}) CHECK(gradient_line_distance(s, vec3(0.0, 1.0 + d, 0.0)) == doctest::Approx(std::fabs(d)));
    const Quadric<double> p = quadric_from_coefficients(Coefficients10<double>{-1, 0, 0, 2, 0, 0, 0, 0, 0, 0});
    CHECK(gradient_line_distance(p, vec3(5.0, 5.0, 0.75)) == doctest::Approx(0.25));
    // x^2 + y^2 + z^2 + 1 = 0 has no real points: the line misses.
    const Quadric<double> e = quadric_from_abc(identity<double, 3>(), vec3(0.0, 0.0, 0.0), 1.0);
    CHECK(std::isinf(gradient_line_distance(e, vec3(0.3, 0.0, 0.0))));
}

TEST_CASE("local and world quadrics convert both ways and F(x) = r f((x - c) / r)") {
    const Quadric<double> l = quadric_from_coefficients(Coefficients10<double>{-0.5, 0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 1.0, 2.0, 0.5});
    const Vec3d c = vec3(1.0, 2.0, -3.0);
    const double r = 0.25;
    const Quadric<double> w = local_to_world(l, c, r);
    const Vec3d x = vec3(1.1, 1.9, -2.8);
    CHECK(evaluate(w, x) == doctest::Approx(r * evaluate(l, (x - c) * (1 / r))));
    const Quadric<double> back = world_to_local(w, c, r);
    for (int j = 0; j < 4; ++j)
        for (int i = 0; i < 4; ++i) CHECK(back.q[j][i] == doctest::Approx(l.q[j][i]).epsilon(1e-12).scale(1));
}

TEST_CASE("too few points are not a fit") {
    std::vector<Vec3d> pos(9, vec3(0.0, 0.0, 0.0)), nrm(9, vec3(0.0, 0.0, 1.0));
    CHECK_FALSE(fit_ball(pos, nrm, all(9), vec3(0.0, 0.0, 0.0), 1.0).solved);
}
