// tests/bb/test_bb.cpp -- BB-form on a tetrahedron: indices, de Casteljau, blossoms, derivatives, restriction
#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <string>

#include "bb/test_scalars.hpp"
#include "quadcast/bb/bb.hpp"

using namespace quadcast;
using namespace quadcast::bb;

namespace {

using LD = long double;

std::string order_string(int q) {
    std::string s;
    auto put = [&](const auto& all) {
        for (const MultiIndex& m : all) {
            if (!s.empty()) s += ' ';
            s += std::to_string(m.i) + std::to_string(m.j) + std::to_string(m.k) + std::to_string(m.l);
        }
    };
    if (q == 2) put(multi_indices<2>());
    if (q == 3) put(multi_indices<3>());
    return s;
}

LD factorial(int n) { return n <= 1 ? 1.0L : n * factorial(n - 1); }

/// Σ c_α q!/α! λ^α in long double, and Σ |c_α B_α| (for error bounds).
template <int Q, class T>
std::array<LD, 2> bernstein_sum(const BezierTet<T, Q>& c, const std::array<LD, 4>& l) {
    LD s = 0, a = 0;
    const auto idx = multi_indices<Q>();
    for (int n = 0; n < c.size; ++n) {
        LD b = factorial(Q);
        for (int m = 0; m < 4; ++m) b = b / factorial(idx[n][m]) * std::pow(l[m], idx[n][m]);
        s += static_cast<LD>(c[n]) * b;
        a += std::fabs(static_cast<LD>(c[n]) * b);
    }
    return {s, a};
}

/// ∂/∂λm of the Bernstein sum in long double.
template <int Q, class T>
LD bernstein_partial(const BezierTet<T, Q>& c, const std::array<LD, 4>& l, int m) {
    LD s = 0;
    const auto idx = multi_indices<Q>();
    for (int n = 0; n < c.size; ++n) {
        if (idx[n][m] == 0) continue;
        LD b = factorial(Q);
        for (int k = 0; k < 4; ++k) {
            const int e = idx[n][k] - (k == m ? 1 : 0);
            b = b / factorial(idx[n][k]) * std::pow(l[k], e);
        }
        s += static_cast<LD>(c[n]) * b * idx[n][m];
    }
    return s;
}

template <class T, int Q>
BezierTet<T, Q> random_tet(std::mt19937& rng) {
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    BezierTet<T, Q> c{};
    for (int n = 0; n < c.size; ++n) c[n] = T(u(rng));
    return c;
}

/// A barycentric point: inside the tetrahedron (all λ >= 0) or anywhere in a box around it.
template <class T>
Vec<T, 4> random_bary(std::mt19937& rng, bool inside) {
    std::uniform_real_distribution<double> u(inside ? 0.0 : -0.5, 1.0);
    Vec<T, 4> l{};
    double a = u(rng), b = u(rng), c = u(rng);
    if (inside) {
        // uniform on the simplex by sorting
        double x[3] = {a, b, c};
        std::sort(x, x + 3);
        l = {{T(x[0]), T(x[1] - x[0]), T(x[2] - x[1]), T(1.0 - x[2])}};
    } else {
        l = {{T(a), T(b), T(c), T(1.0 - a - b - c)}};
    }
    return l;
}

template <class T>
std::array<LD, 4> to_ld(const Vec<T, 4>& l) {
    return {static_cast<LD>(l[0]), static_cast<LD>(l[1]), static_cast<LD>(l[2]), static_cast<LD>(l[3])};
}

template <class T>
constexpr double eps() { return static_cast<double>(std::numeric_limits<T>::epsilon()); }

}  // namespace

TEST_CASE("multi-indices follow the storage order of the spec") {
    CHECK(order_string(2) == "2000 1100 1010 1001 0200 0110 0101 0020 0011 0002");
    CHECK(order_string(3) ==
          "3000 2100 2010 2001 1200 1110 1101 1020 1011 1002 0300 0210 0201 0120 0111 0102 0030 0021 0012 0003");
    static_assert(coefficient_count(2) == 10 && coefficient_count(3) == 20 && coefficient_count(0) == 1);
    const auto i3 = multi_indices<3>();
    for (int n = 0; n < 20; ++n) CHECK(index_of(3, i3[n]) == n);
    const auto i2 = multi_indices<2>();
    for (int n = 0; n < 10; ++n) CHECK(index_of(2, i2[n]) == n);
    // the step table points at α + e_m
    const auto st = step_table<3>();
    for (int n = 0; n < 10; ++n)
        for (int m = 0; m < 4; ++m) CHECK(i3[st[n][m]][m] == i2[n][m] + 1);
}

TEST_CASE_TEMPLATE("de Casteljau evaluation equals the Bernstein sum", T, float, double) {
    double worst[4] = {0, 0, 0, 0};
    for (int it = 0; it < 2000; ++it) {
        std::mt19937 rng(1000 + it);
        const bool inside = it % 2 == 0;
        const Vec<T, 4> l = random_bary<T>(rng, inside);
        auto check = [&](auto c, int q) {
            const T v = evaluate(c, l);
            const auto ref = bernstein_sum(c, to_ld(l));
            const double err = static_cast<double>(std::fabs(static_cast<LD>(v) - ref[0]) / ref[1]) / eps<T>();
            worst[q] = std::max(worst[q], err);
        };
        check(random_tet<T, 1>(rng), 1);
        check(random_tet<T, 2>(rng), 2);
        check(random_tet<T, 3>(rng), 3);
    }
    MESSAGE("max |p - p_ref| / (eps Σ|c B|): q=1 ", worst[1], ", q=2 ", worst[2], ", q=3 ", worst[3]);
    // inside the tetrahedron de Casteljau is a convex combination: error ~ q·eps; outside the
    // amplification is bounded by the (λ-weighted) absolute sums, still a small multiple.
    CHECK(worst[1] < 8);
    CHECK(worst[2] < 16);
    CHECK(worst[3] < 24);
}

TEST_CASE_TEMPLATE("the blossom is symmetric and multi-affine and reproduces values and coefficients", T, float, double) {
    for (int it = 0; it < 500; ++it) {
        std::mt19937 rng(2000 + it);
        const auto c = random_tet<T, 3>(rng);
        const Vec<T, 4> a = random_bary<T>(rng, true), b = random_bary<T>(rng, true), d = random_bary<T>(rng, true);
        // diagonal = value, bit for bit (same operations)
        const Vec<T, 4> diag[3] = {a, a, a};
        CHECK(blossom(c, diag) == evaluate(c, a));
        // vertices give the coefficients exactly
        const auto idx = multi_indices<3>();
        for (int n = 0; n < 20; ++n) {
            Vec<T, 4> args[3];
            int k = 0;
            for (int m = 0; m < 4; ++m)
                for (int r = 0; r < idx[n][m]; ++r) {
                    args[k] = {{T(0), T(0), T(0), T(0)}};
                    args[k][m] = T(1);
                    ++k;
                }
            CHECK(blossom(c, args) == c[n]);
        }
        // symmetric: all 6 orders agree to rounding
        const Vec<T, 4> o1[3] = {a, b, d}, o2[3] = {d, a, b}, o3[3] = {b, d, a};
        const T ref = blossom(c, o1);
        const T tol = T(64) * T(eps<T>());
        CHECK(std::fabs(blossom(c, o2) - ref) <= tol);
        CHECK(std::fabs(blossom(c, o3) - ref) <= tol);
        // affine in the first argument: p[(1-s)a + s b, ...] = (1-s) p[a,...] + s p[b,...]
        const T s = T(0.375);
        Vec<T, 4> mix{};
        for (int m = 0; m < 4; ++m) mix[m] = (T(1) - s) * a[m] + s * b[m];
        const Vec<T, 4> am[3] = {mix, d, d}, aa[3] = {a, d, d}, ab[3] = {b, d, d};
        CHECK(std::fabs(blossom(c, am) - ((T(1) - s) * blossom(c, aa) + s * blossom(c, ab))) <= tol);
    }
}

TEST_CASE_TEMPLATE("partial derivatives from the (q-1)-th step equal those of the Bernstein sum", T, float, double) {
    double worst = 0;
    for (int it = 0; it < 1000; ++it) {
        std::mt19937 rng(3000 + it);
        const auto c = random_tet<T, 3>(rng);
        const Vec<T, 4> l = random_bary<T>(rng, true);
        const ValueAndPartials<T> vp = value_and_partials(c, l);
        CHECK(vp.value == evaluate(c, l));
        for (int m = 0; m < 4; ++m) {
            const LD ref = bernstein_partial(c, to_ld(l), m);
            worst = std::max(worst, static_cast<double>(std::fabs(static_cast<LD>(vp.partials[m]) - ref)) / eps<T>());
        }
        // a direction e_m - e_0 is the derivative along the edge v0 -> vm
        const Vec<T, 4> dir = {{T(-1), T(1), T(0), T(0)}};
        CHECK(directional_derivative(vp, dir) == doctest::Approx(static_cast<double>(vp.partials[1] - vp.partials[0])));
    }
    MESSAGE("max |∂p/∂λm - ref| / eps = ", worst);
    CHECK(worst < 64);
}

TEST_CASE_TEMPLATE("the gradient from the barycentric directions of x, y, z matches finite differences", T, float, double) {
    // A general tetrahedron in space; λ(x) etc. are the barycentric coordinates of the axis vectors.
    const double V[4][3] = {{0.1, -0.2, 0.05}, {1.3, 0.1, -0.2}, {0.2, 1.1, 0.3}, {-0.1, 0.25, 1.2}};
    // barycentric map: λ = M^{-1} (x, 1); build with long double Gauss elimination
    auto bary = [&](const std::array<LD, 3>& x) {
        LD A[4][5];
        for (int r = 0; r < 3; ++r) {
            for (int m = 0; m < 4; ++m) A[r][m] = static_cast<LD>(V[m][r]);
            A[r][4] = x[r];
        }
        for (int m = 0; m < 4; ++m) A[3][m] = 1;
        A[3][4] = 1;
        for (int p = 0; p < 4; ++p) {
            int best = p;
            for (int r = p + 1; r < 4; ++r)
                if (std::fabs(A[r][p]) > std::fabs(A[best][p])) best = r;
            for (int k = 0; k < 5; ++k) std::swap(A[p][k], A[best][k]);
            for (int r = 0; r < 4; ++r) {
                if (r == p) continue;
                const LD f = A[r][p] / A[p][p];
                for (int k = 0; k < 5; ++k) A[r][k] -= f * A[p][k];
            }
        }
        std::array<LD, 4> l{};
        for (int m = 0; m < 4; ++m) l[m] = A[m][4] / A[m][m];
        return l;
    };
    const std::array<LD, 4> l0 = bary({0, 0, 0});
    Mat<T, 4, 3> dirs{};
    for (int a = 0; a < 3; ++a) {
        std::array<LD, 3> e{0, 0, 0};
        e[a] = 1;
        const std::array<LD, 4> l1 = bary(e);
        for (int m = 0; m < 4; ++m) dirs[a][m] = T(static_cast<double>(l1[m] - l0[m]));
    }
    double worst = 0;
    for (int it = 0; it < 200; ++it) {
        std::mt19937 rng(4000 + it);
        const auto c = random_tet<T, 3>(rng);
        const Vec<T, 4> l = random_bary<T>(rng, true);
        const Vec<T, 3> g = gradient(value_and_partials(c, l), dirs);
        // Cartesian point of l, then central differences of the long double Bernstein sum
        std::array<LD, 3> x{0, 0, 0};
        for (int m = 0; m < 4; ++m)
            for (int a = 0; a < 3; ++a) x[a] += static_cast<LD>(l[m]) * static_cast<LD>(V[m][a]);
        for (int a = 0; a < 3; ++a) {
            const LD hstep = 1e-5L;
            std::array<LD, 3> xp = x, xm = x;
            xp[a] += hstep;
            xm[a] -= hstep;
            const LD fd = (bernstein_sum(c, bary(xp))[0] - bernstein_sum(c, bary(xm))[0]) / (2 * hstep);
            worst = std::max(worst, static_cast<double>(std::fabs(fd - static_cast<LD>(g[a]))));
        }
    }
    MESSAGE("max |grad - finite difference| = ", worst);
    CHECK(worst < (sizeof(T) == 4 ? 2e-4 : 1e-8));
}

TEST_CASE_TEMPLATE("the restriction to a segment by blossoming equals evaluation on the segment", T, float, double) {
    double worst = 0;
    for (int it = 0; it < 500; ++it) {
        std::mt19937 rng(5000 + it);
        const auto c2 = random_tet<T, 2>(rng);
        const auto c3 = random_tet<T, 3>(rng);
        const Vec<T, 4> la = random_bary<T>(rng, it % 3 != 0), lb = random_bary<T>(rng, it % 3 != 0);
        const Vec<T, 3> r2 = restrict_to_segment(c2, la, lb);
        const Vec<T, 4> r3 = restrict_to_segment(c3, la, lb);
        // end coefficients are the values at the ends, bit for bit
        CHECK(r3[0] == evaluate(c3, la));
        CHECK(r2[2] == dot(lb, Vec<T, 4>{{de_casteljau_step(c2, lb)[0], de_casteljau_step(c2, lb)[1],
                                             de_casteljau_step(c2, lb)[2], de_casteljau_step(c2, lb)[3]}}));
        for (int k = 0; k <= 16; ++k) {
            const double t = k / 16.0;
            std::array<LD, 4> lt{};
            for (int m = 0; m < 4; ++m) lt[m] = (1 - static_cast<LD>(t)) * static_cast<LD>(la[m]) + static_cast<LD>(t) * static_cast<LD>(lb[m]);
            const auto ref2 = bernstein_sum(c2, lt), ref3 = bernstein_sum(c3, lt);
            const LD e2 = std::fabs(static_cast<LD>(evaluate_univariate(r2, T(t)).value) - ref2[0]) / (ref2[1] + 1);
            const LD e3 = std::fabs(static_cast<LD>(evaluate_univariate(r3, T(t)).value) - ref3[0]) / (ref3[1] + 1);
            worst = std::max(worst, static_cast<double>(std::max(e2, e3)) / eps<T>());
        }
        // the paper's fragment-stage path: first steps at both ends are given (interpolated)
        const Vec<T, 4> r3b = restrict_from_first_step(de_casteljau_step(c3, la), de_casteljau_step(c3, lb), la, lb);
        for (int i = 0; i < 4; ++i) CHECK(r3b[i] == r3[i]);
        // the derivative of the univariate form is the directional derivative along lb - la
        Vec<T, 4> dir{};
        for (int m = 0; m < 4; ++m) dir[m] = lb[m] - la[m];
        const T slope0 = evaluate_univariate(r3, T(0)).slope;
        CHECK(slope0 == doctest::Approx(static_cast<double>(directional_derivative(value_and_partials(c3, la), dir))).epsilon(sizeof(T) == 4 ? 1e-3 : 1e-9).scale(1.0));
    }
    MESSAGE("max restriction error / (eps (Σ|cB| + 1)) = ", worst);
    CHECK(worst < 64);
}

TEST_CASE("the shared templates compile with a tracer-like scalar and give the same bits; operation counts") {
    using C = qtest::Counted<float>;
    std::mt19937 rng(6000);
    const auto cf = random_tet<float, 3>(rng);
    BezierTet<C, 3> cc{};
    for (int n = 0; n < 20; ++n) cc[n] = C::raw(cf[n]);
    const Vec<float, 4> la = random_bary<float>(rng, true), lb = random_bary<float>(rng, true);
    Vec<C, 4> ca{}, cb{};
    for (int m = 0; m < 4; ++m) {
        ca[m] = C::raw(la[m]);
        cb[m] = C::raw(lb[m]);
    }
    qtest::op_counts = {};
    const C v = evaluate(cc, ca);
    const long ops_eval = qtest::op_counts.total();
    CHECK(v.v == evaluate(cf, la));
    qtest::op_counts = {};
    const auto vp = value_and_partials(cc, ca);
    const long ops_vp = qtest::op_counts.total();
    const auto vpf = value_and_partials(cf, la);
    for (int m = 0; m < 4; ++m) CHECK(vp.partials[m].v == vpf.partials[m]);
    const auto s1a = de_casteljau_step(cc, ca), s1b = de_casteljau_step(cc, cb);
    qtest::op_counts = {};
    const Vec<C, 4> r = restrict_from_first_step(s1a, s1b, ca, cb);
    const long ops_frag = qtest::op_counts.total();
    const Vec<float, 4> rf = restrict_to_segment(cf, la, lb);
    for (int i = 0; i < 4; ++i) CHECK(r[i].v == rf[i]);
    const BezierTet<C, 2> c2 = {{cc[0], cc[1], cc[2], cc[3], cc[4], cc[5], cc[6], cc[7], cc[8], cc[9]}};
    const auto s2a = de_casteljau_step(c2, ca), s2b = de_casteljau_step(c2, cb);
    qtest::op_counts = {};
    const Vec<C, 3> r2 = restrict_from_first_step(s2a, s2b, ca, cb);
    const long ops_frag2 = qtest::op_counts.total();
    (void)r2;
    MESSAGE("ops: cubic evaluate ", ops_eval, ", value+partials ", ops_vp,
            "; fragment-stage blossoming from b^[1]: q=3 ", ops_frag, " (16 dot4; paper: 16 elementary de Casteljau operations), q=2 ",
            ops_frag2, " (3 dot4; paper: 3)");
    CHECK(ops_frag2 == 3 * 7);
    CHECK(ops_frag == 16 * 7);
}
