// tests/core/test_quadric.cpp -- quadric representations, evaluation, transforms, eye origin, graph functions
#include <doctest/doctest.h>

#include <cmath>
#include <stdexcept>

#include "core/core_testing.hpp"
#include "quadcast/quadric.hpp"

using namespace quadcast;
using namespace qc_test;

namespace {

template <class T>
Coefficients10<T> random_coefficients(std::mt19937& rng) {
    auto r = [&] { return T(uniform(rng, -2, 2)); };
    return {r(), r(), r(), r(), r(), r(), r(), r(), r(), r()};
}

/// The monomial form in long double and the sum of |terms|.
template <class T>
LD monomials_ld(const Coefficients10<T>& k, const Vec3<T>& p, LD* mag) {
    const LD x = p[0], y = p[1], z = p[2];
    const LD t[10] = {LD(k.k000), k.k100 * x, k.k010 * y, k.k001 * z, k.k110 * x * y,
                      k.k011 * y * z, k.k101 * z * x, k.k200 * x * x, k.k020 * y * y, k.k002 * z * z};
    LD s = 0, m = 0;
    for (LD v : t) { s += v; m += std::fabs(v); }
    if (mag) *mag = m;
    return s;
}

template <class T>
bool is_symmetric(const Quadric<T>& q) {
    for (int j = 0; j < 4; ++j)
        for (int i = 0; i < 4; ++i)
            if (!(q.q[j][i] == q.q[i][j])) return false;
    return true;
}

/// A random well-conditioned affine map (diagonally dominant linear part).
template <class T>
Mat4<T> random_affine(std::mt19937& rng) {
    Mat4<T> m = identity<T, 4>();
    for (int j = 0; j < 3; ++j)
        for (int i = 0; i < 3; ++i) m[j][i] = T(uniform(rng, -1, 1) + (i == j ? 2.5 : 0.0));
    for (int i = 0; i < 3; ++i) m[3][i] = T(uniform(rng, -3, 3));
    return m;
}

Mat4<LD> inverse_ld(const Mat4<LD>& m) {
    // The host inverse rounds to its T; for references we want it in long double directly.
    LD a[4][8];
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) { a[i][j] = m[j][i]; a[i][4 + j] = i == j; }
    for (int k = 0; k < 4; ++k) {
        int p = k;
        for (int i = k + 1; i < 4; ++i) if (std::fabs(a[i][k]) > std::fabs(a[p][k])) p = i;
        for (int j = 0; j < 8; ++j) std::swap(a[p][j], a[k][j]);
        const LD piv = a[k][k];
        for (int j = 0; j < 8; ++j) a[k][j] /= piv;
        for (int i = 0; i < 4; ++i) {
            if (i == k) continue;
            const LD f = a[i][k];
            for (int j = 0; j < 8; ++j) a[i][j] -= f * a[k][j];
        }
    }
    Mat4<LD> r{};
    for (int i = 0; i < 4; ++i) for (int j = 0; j < 4; ++j) r[j][i] = a[i][4 + j];
    return r;
}

}  // namespace

TEST_CASE_TEMPLATE("the 10 coefficients round-trip exactly through the symmetric 4x4 matrix", T, float, double) {
    for (std::uint32_t it = 0; it < 500; ++it) {
        auto rng = rng_for(101, it);
        const Coefficients10<T> k = random_coefficients<T>(rng);
        const Quadric<T> q = quadric_from_coefficients(k);
        REQUIRE(is_symmetric(q));
        // The documented layout: A upper-left, b in column 3 and row 3, c at [3][3].
        CHECK(q.q[3][3] == k.k000);
        CHECK(q.q[3][0] == T(0.5) * k.k100);
        CHECK(q.q[0][3] == T(0.5) * k.k100);
        CHECK(q.q[3][2] == T(0.5) * k.k001);
        CHECK(q.q[1][0] == T(0.5) * k.k110);
        CHECK(q.q[2][1] == T(0.5) * k.k011);
        CHECK(q.q[0][2] == T(0.5) * k.k101);
        CHECK(q.q[1][1] == k.k020);
        const Coefficients10<T> back = coefficients(q);
        const T a[10] = {k.k000, k.k100, k.k010, k.k001, k.k110, k.k011, k.k101, k.k200, k.k020, k.k002};
        const T b[10] = {back.k000, back.k100, back.k010, back.k001, back.k110, back.k011, back.k101, back.k200, back.k020, back.k002};
        for (int i = 0; i < 10; ++i) CHECK(a[i] == b[i]);
        // (A, b, c) round trip.
        const QuadricABC<T> abc = to_abc(q);
        const Quadric<T> q2 = quadric_from_abc(abc.A, abc.b, abc.c);
        for (int j = 0; j < 4; ++j) for (int i = 0; i < 4; ++i) CHECK(q2.q[j][i] == q.q[j][i]);
    }
}

TEST_CASE_TEMPLATE("quadric_from_abc reads only the upper triangle of A", T, float, double) {
    Mat3<T> A{};
    A[0][1] = T(5);  // column 0, row 1: lower triangle, ignored
    A[1][0] = T(2);  // column 1, row 0: upper triangle
    const Quadric<T> q = quadric_from_abc(A, vec3(T(0), T(0), T(0)), T(0));
    CHECK(q.q[1][0] == T(2));
    CHECK(q.q[0][1] == T(2));
}

TEST_CASE_TEMPLATE("evaluate agrees with the monomial form to rounding", T, float, double) {
    const LD eps = std::numeric_limits<T>::epsilon();
    LD worst = 0;
    for (std::uint32_t it = 0; it < 2000; ++it) {
        auto rng = rng_for(102, it);
        const Coefficients10<T> k = random_coefficients<T>(rng);
        const Vec3<T> x = random_vec<T>(rng, -3, 3);
        LD mag = 0;
        const LD ref = monomials_ld(k, x, &mag);
        const LD err = std::fabs(LD(evaluate(quadric_from_coefficients(k), x)) - ref) / (eps * mag);
        worst = std::max(worst, err);
        REQUIRE(err <= 8);
    }
    MESSAGE(std::string(scalar_traits<T>::name) << ": max |f - f_ref| / (eps sum|terms|) = " << double(worst));
    CHECK(worst > 0);  // rounding is visible: the comparison really measures something
}

TEST_CASE_TEMPLATE("half_gradient is half the gradient of the monomial form", T, float, double) {
    const LD eps = std::numeric_limits<T>::epsilon();
    for (std::uint32_t it = 0; it < 1000; ++it) {
        auto rng = rng_for(103, it);
        const Coefficients10<T> k = random_coefficients<T>(rng);
        const Vec3<T> p = random_vec<T>(rng, -3, 3);
        const LD x = p[0], y = p[1], z = p[2];
        const LD g[3] = {k.k100 + k.k110 * y + k.k101 * z + 2 * k.k200 * x,
                         k.k010 + k.k110 * x + k.k011 * z + 2 * k.k020 * y,
                         k.k001 + k.k011 * y + k.k101 * x + 2 * k.k002 * z};
        const LD m[3] = {std::fabs(k.k100) + std::fabs(k.k110 * y) + std::fabs(k.k101 * z) + std::fabs(2 * k.k200 * x),
                         std::fabs(k.k010) + std::fabs(k.k110 * x) + std::fabs(k.k011 * z) + std::fabs(2 * k.k020 * y),
                         std::fabs(k.k001) + std::fabs(k.k011 * y) + std::fabs(k.k101 * x) + std::fabs(2 * k.k002 * z)};
        const Quadric<T> q = quadric_from_coefficients(k);
        const Vec3<T> h = half_gradient(q, p), full = gradient(q, p);
        for (int i = 0; i < 3; ++i) {
            CHECK(std::fabs(2 * LD(h[i]) - g[i]) <= 6 * eps * m[i]);
            CHECK(full[i] == T(2) * h[i]);
        }
    }
}

TEST_CASE_TEMPLATE("transforms commute with evaluation: f'(M x) = f(x)", T, float, double) {
    const LD eps = std::numeric_limits<T>::epsilon();
    LD worst = 0;
    for (std::uint32_t it = 0; it < 1000; ++it) {
        auto rng = rng_for(104, it);
        const Quadric<T> q = random_quadric<T>(rng);
        Mat4<T> m = random_affine<T>(rng);
        if (it % 2 == 1)  // a projective map too: y~ = M x~ has w != 1
            for (int j = 0; j < 4; ++j) m[j][3] = T(uniform(rng, -0.2, 0.2) + (j == 3 ? 1.0 : 0.0));
        const Quadric<T> qt = transform(q, m);
        REQUIRE(is_symmetric(qt));
        // Compare the homogeneous forms in long double: y~^T Q' y~ with y~ = M x~ against f(x).
        const Vec3<T> x = random_vec<T>(rng, -2, 2);
        const Mat4<LD> ml = cast<LD>(m), minv = inverse_ld(ml);
        const Vec4<LD> yh = ml * hom(cast<LD>(x));
        const Mat4<LD> qtl = to_ld(qt);
        LD lhs = 0;
        for (int i = 0; i < 4; ++i) for (int j = 0; j < 4; ++j) lhs += yh[i] * qtl[j][i] * yh[j];
        const LD rhs = eval_ld(to_ld(q), cast<LD>(x));
        // Scale: |y~|^T (|M^-1|^T |Q| |M^-1|) |y~|, the magnitudes that were summed into Q'.
        Mat4<LD> absq{}, absinv{};
        for (int j = 0; j < 4; ++j) for (int i = 0; i < 4; ++i) { absq[j][i] = std::fabs(LD(q.q[j][i])); absinv[j][i] = std::fabs(minv[j][i]); }
        Vec4<LD> ay{};
        for (int i = 0; i < 4; ++i) ay[i] = std::fabs(yh[i]);
        const Vec4<LD> t = absinv * ay;
        const LD mag = dot(t, absq * t);
        const LD err = std::fabs(lhs - rhs) / (eps * mag);
        worst = std::max(worst, err);
        REQUIRE(err <= 16);
    }
    MESSAGE(std::string(scalar_traits<T>::name) << ": max |f'(Mx) - f(x)| / (eps scale) = " << double(worst));
    CHECK(worst > 0);
}

TEST_CASE_TEMPLATE("host_inverse inverts and rejects singular or non-finite matrices", T, float, double) {
    auto rng = rng_for(105, 0);
    const Mat4<T> m = random_affine<T>(rng);
    const Mat4<T> p = m * host_inverse(m);
    for (int j = 0; j < 4; ++j)
        for (int i = 0; i < 4; ++i) CHECK(std::fabs(p[j][i] - (i == j ? T(1) : T(0))) <= T(16) * std::numeric_limits<T>::epsilon());
    Mat4<T> s = m;
    s[2] = s[0];  // two equal columns
    CHECK_THROWS_AS(host_inverse(s), std::invalid_argument);
    Mat4<T> n = m;
    n[1][1] = std::numeric_limits<T>::quiet_NaN();
    CHECK_THROWS_AS(host_inverse(n), std::invalid_argument);
}

TEST_CASE_TEMPLATE("the eye-origin quadric (eq. 9) is the quadric seen from the eye", T, float, double) {
    const LD eps = std::numeric_limits<T>::epsilon();
    LD worst_shift = 0, worst_c = 0;
    for (std::uint32_t it = 0; it < 1000; ++it) {
        auto rng = rng_for(106, it);
        const Quadric<T> q = random_quadric<T>(rng);
        const Vec3<T> e = random_vec<T>(rng, -10, 10);
        const Quadric<T> qe = translate_to_eye(q, e);
        REQUIRE(is_symmetric(qe));
        for (int j = 0; j < 3; ++j) for (int i = 0; i < 3; ++i) CHECK(qe.q[j][i] == q.q[j][i]);  // A' = A
        // f'(y) = f(y + e) in long double for random y.
        const Vec3<LD> y = cast<LD>(random_vec<T>(rng, -3, 3)), el = cast<LD>(e);
        const LD lhs = eval_ld(to_ld(qe), y), rhs = eval_ld(to_ld(q), y + el);
        Vec4<LD> amag{};
        for (int i = 0; i < 3; ++i) amag[i] = std::fabs(y[i]) + std::fabs(el[i]);
        amag[3] = 1;
        const LD err = std::fabs(lhs - rhs) / (eps * eval_mag_ld(to_ld(q), amag));
        worst_shift = std::max(worst_shift, err);
        REQUIRE(err <= 16);
        // c' = f(e) to rounding; and equal to the general transform with M^-1 = translation by e.
        const LD cerr = std::fabs(LD(qe.q[3][3]) - eval_ld(to_ld(q), el)) / (eps * eval_mag_ld(to_ld(q), hom(Vec3<LD>{{std::fabs(el[0]), std::fabs(el[1]), std::fabs(el[2])}})));
        worst_c = std::max(worst_c, cerr);
        REQUIRE(cerr <= 8);
        Mat4<T> tinv = identity<T, 4>();
        tinv[3] = vec4(e, T(1));
        const Quadric<T> qg = transform_with_inverse(q, tinv);
        for (int j = 0; j < 4; ++j)
            for (int i = 0; i < 4; ++i)
                CHECK(std::fabs(LD(qg.q[j][i]) - LD(qe.q[j][i])) <= 16 * eps * eval_mag_ld(to_ld(q), hom(Vec3<LD>{{std::fabs(el[0]), std::fabs(el[1]), std::fabs(el[2])}})));
    }
    MESSAGE(std::string(scalar_traits<T>::name) << ": eye origin: max |f'(y) - f(y+e)| / (eps scale) = " << double(worst_shift)
                                   << ", max |c' - f(e)| / (eps scale) = " << double(worst_c));
}

TEST_CASE_TEMPLATE("a graph function's implicit form z - f(x, y) vanishes on the graph and points up", T, float, double) {
    const LD eps = std::numeric_limits<T>::epsilon();
    for (std::uint32_t it = 0; it < 1000; ++it) {
        auto rng = rng_for(107, it);
        auto r = [&] { return T(uniform(rng, -2, 2)); };
        const GraphCoefficients<T> g{r(), r(), r(), r(), r(), r()};
        const Quadric<T> q = quadric_from_graph(g);
        REQUIRE(is_symmetric(q));
        const T x = r(), y = r();
        const LD terms[6] = {LD(g.k00), LD(g.k10) * x, LD(g.k01) * y, LD(g.k11) * x * y, LD(g.k20) * x * x, LD(g.k02) * y * y};
        LD z = 0, mag = 0;
        for (LD t : terms) { z += t; mag += std::fabs(t); }
        // On the graph: exactly zero in long double up to the long double rounding.
        CHECK(std::fabs(eval_ld(to_ld(q), Vec3<LD>{{LD(x), LD(y), z}})) <= 1e-15L * (mag + 1));
        // In T at the rounded height: within rounding.
        const T zt = T(z);
        CHECK(std::fabs(LD(evaluate(q, vec3(x, y, zt)))) <= 8 * eps * (mag + std::fabs(z) + 1));
        // Normal: d/dz (z - f) = 1, half of it in half_gradient.
        CHECK(half_gradient(q, vec3(x, y, zt))[2] == T(0.5));
        CHECK(evaluate(q, vec3(x, y, T(zt + T(1)))) > T(0));  // above the graph is outside
    }
}

TEST_CASE_TEMPLATE("machine_epsilon is the format's epsilon", T, float, double) {
    CHECK(machine_epsilon<T>() == std::numeric_limits<T>::epsilon());
}
