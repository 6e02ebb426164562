// tests/bb/test_roots.cpp -- roots in [0,1]: stable quadratic; cubic Newton-5 (paper) vs isolation + bracketing
#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "bb/test_scalars.hpp"
#include "quadcast/bb/bb.hpp"

using namespace quadcast;
using namespace quadcast::bb;

namespace {

using LD = long double;

template <std::size_t N>
LD bern(const std::array<LD, N>& c, LD t) {
    std::array<LD, N> w = c;
    for (std::size_t l = N - 1; l >= 1; --l)
        for (std::size_t i = 0; i < l; ++i) w[i] = (1 - t) * w[i] + t * w[i + 1];
    return w[0];
}

/// Reference: all roots in [0,1] of Σ c_i B_i^{N-1} in long double (critical points split [0,1]
/// into monotone pieces; 200 bisection steps each; a critical point with |p| below 1e-16·scale
/// counts as a (tangential) root). Also |p'| at the first root (conditioning).
struct Ref {
    std::vector<LD> roots;
    LD slope_first = 0;
    bool first_tangent = false;
};

template <std::size_t N>
Ref reference_roots(const std::array<LD, N>& c) {
    static_assert(N == 3 || N == 4);
    LD scale = 0;
    for (LD x : c) scale = std::max(scale, std::fabs(x));
    std::vector<LD> brk = {0};
    if constexpr (N == 4) {
        // p'/3 = Σ d_i B_i^2, monomial A t^2 + B t + C
        const LD d0 = c[1] - c[0], d1 = c[2] - c[1], d2 = c[3] - c[2];
        const LD A = d0 - 2 * d1 + d2, B = 2 * (d1 - d0), C = d0;
        if (A != 0) {
            const LD D = B * B - 4 * A * C;
            if (D >= 0) {
                const LD q = -0.5L * (B + std::copysign(std::sqrt(D), B));
                for (LD r : {q / A, q != 0 ? C / q : -1.0L})
                    if (r > 0 && r < 1) brk.push_back(r);
            }
        } else if (B != 0) {
            const LD r = -C / B;
            if (r > 0 && r < 1) brk.push_back(r);
        }
    } else {
        const LD d0 = c[1] - c[0], d1 = c[2] - c[1];
        if (d0 != d1) {
            const LD r = d0 / (d0 - d1);
            if (r > 0 && r < 1) brk.push_back(r);
        }
    }
    brk.push_back(1);
    std::sort(brk.begin(), brk.end());
    Ref ref;
    auto push = [&](LD r, bool tangent) {
        if (!ref.roots.empty() && std::fabs(ref.roots.back() - r) < 1e-30L) return;
        if (ref.roots.empty()) ref.first_tangent = tangent;
        ref.roots.push_back(r);
    };
    for (std::size_t k = 0; k + 1 < brk.size(); ++k) {
        LD a = brk[k], b = brk[k + 1];
        LD fa = bern(c, a), fb = bern(c, b);
        const bool interior_a = k > 0;
        if (fa == 0 || (interior_a && std::fabs(fa) <= 1e-16L * scale)) push(a, interior_a);
        if ((fa < 0 && fb > 0) || (fa > 0 && fb < 0)) {
            for (int i = 0; i < 200; ++i) {
                const LD m = 0.5L * (a + b), fm = bern(c, m);
                if ((fm < 0) == (fa < 0)) { a = m; fa = fm; } else { b = m; }
            }
            push(0.5L * (a + b), false);
        }
        if (k + 2 == brk.size() && fb == 0) push(b, false);
    }
    if (!ref.roots.empty()) {
        const LD t = ref.roots.front(), e = 1e-7L;
        ref.slope_first = std::fabs(bern(c, std::min<LD>(1, t + e)) - bern(c, std::max<LD>(0, t - e))) / (2 * e) / std::max(scale, 1e-300L);
    }
    return ref;
}

std::array<LD, 4> bb_from_monomial(LD a0, LD a1, LD a2, LD a3) {
    return {a0, a0 + a1 / 3, a0 + 2 * a1 / 3 + a2 / 3, a0 + a1 + a2 + a3};
}
/// k (t - r1)(t - r2)(t - r3) + delta in BB-form.
std::array<LD, 4> bb_from_roots(LD k, LD r1, LD r2, LD r3, LD delta) {
    const LD a3 = k, a2 = -k * (r1 + r2 + r3), a1 = k * (r1 * r2 + r1 * r3 + r2 * r3), a0 = -k * r1 * r2 * r3 + delta;
    return bb_from_monomial(a0, a1, a2, a3);
}

struct Tally {
    long n = 0, ok = 0, miss = 0, false_hit = 0, wrong = 0;
    double max_err_ok = 0;  // over well-conditioned ok cases
    void add(bool ref_has, LD tref, bool hit, double t, bool well) {
        ++n;
        if (!ref_has && !hit) { ++ok; return; }
        if (ref_has && !hit) { ++miss; return; }
        if (!ref_has && hit) { ++false_hit; return; }
        const double e = static_cast<double>(std::fabs(static_cast<LD>(t) - tref));
        if (e > 1e-3) { ++wrong; return; }
        ++ok;
        if (well) max_err_ok = std::max(max_err_ok, e);
    }
};

template <class T>
using Method = std::function<UnitRoot<T>(const Vec<T, 4>&)>;

template <class T>
std::vector<std::pair<std::string, Method<T>>> cubic_methods() {
    return {
        {"newton5 (paper: no residual test)", [](const Vec<T, 4>& c) { return cubic_first_root_newton<5>(c, std::numeric_limits<T>::infinity()); }},
        {"newton5 |p|<=1e-3 max|c|", [](const Vec<T, 4>& c) { return cubic_first_root_newton<5>(c, T(1e-3)); }},
        {"newton5 |p|<=1e-5 max|c|", [](const Vec<T, 4>& c) { return cubic_first_root_newton<5>(c, T(1e-5)); }},
        {"newton8 |p|<=1e-5 max|c|", [](const Vec<T, 4>& c) { return cubic_first_root_newton<8>(c, T(1e-5)); }},
        {"isolated, 2 iterations", [](const Vec<T, 4>& c) { return cubic_first_root_isolated<2>(c); }},
        {"isolated, 4 iterations", [](const Vec<T, 4>& c) { return cubic_first_root_isolated<4>(c); }},
        {"isolated, 6 iterations (default)", [](const Vec<T, 4>& c) { return cubic_first_root_isolated<6>(c); }},
        {"isolated, 10 iterations", [](const Vec<T, 4>& c) { return cubic_first_root_isolated<10>(c); }},
        {"isolated, 6 it., touch_tol 1e-6 max|c|", [](const Vec<T, 4>& c) {
             const T s = std::max(std::max(std::fabs(c[0]), std::fabs(c[1])), std::max(std::fabs(c[2]), std::fabs(c[3])));
             return cubic_first_root_isolated<6>(c, T(1e-6) * s); }},
    };
}

/// Cases: name and generator of long double BB coefficients from a seeded rng.
struct CaseKind {
    const char* name;
    std::function<std::array<LD, 4>(std::mt19937&)> make;
};

std::vector<CaseKind> cubic_cases() {
    auto U = [](std::mt19937& r, double a, double b) { return static_cast<LD>(std::uniform_real_distribution<double>(a, b)(r)); };
    auto K = [U](std::mt19937& r) { return (U(r, 0, 1) < 0.5L ? -1 : 1) * U(r, 0.5, 4); };
    return {
        {"random coefficients in [-1,1]", [U](std::mt19937& r) { return std::array<LD, 4>{U(r, -1, 1), U(r, -1, 1), U(r, -1, 1), U(r, -1, 1)}; }},
        {"3 simple roots in [-0.5,1.5]", [U, K](std::mt19937& r) { return bb_from_roots(K(r), U(r, -0.5, 1.5), U(r, -0.5, 1.5), U(r, -0.5, 1.5), 0); }},
        {"double root in [0,1] (tangent)", [U, K](std::mt19937& r) { const LD x = U(r, 0.05, 0.95); return bb_from_roots(K(r), x, x, U(r, -1, 2), 0); }},
        {"near-tangent, gap 1e-6 (no root: hit is false)", [U, K](std::mt19937& r) {
             // k (t-x)^2 (t-s), s > 1, has the sign of -k on [0,1]; lift it away from 0.
             const LD x = U(r, 0.05, 0.95), k = K(r), s = U(r, 1.2, 2);
             return bb_from_roots(k, x, x, s, (k > 0 ? -1 : 1) * 1e-6L * std::fabs(k)); }},
        {"two roots 1e-3 apart", [U, K](std::mt19937& r) { const LD x = U(r, 0.05, 0.9); return bb_from_roots(K(r), x, x + 1e-3L, U(r, -1, 2), 0); }},
        {"two roots 1e-5 apart", [U, K](std::mt19937& r) { const LD x = U(r, 0.05, 0.9); return bb_from_roots(K(r), x, x + 1e-5L, U(r, -1, 2), 0); }},
        {"triple root in [0,1]", [U, K](std::mt19937& r) { const LD x = U(r, 0.05, 0.95); return bb_from_roots(K(r), x, x, x, 0); }},
        {"root within 1e-6 of an end", [U, K](std::mt19937& r) { const LD x = U(r, 0, 1) < 0.5L ? U(r, 0, 1e-6) : 1 - U(r, 0, 1e-6); return bb_from_roots(K(r), x, U(r, -1, 2), U(r, -1, 2), 0); }},
        {"simple root late, extremum early", [U, K](std::mt19937& r) { const LD a = U(r, 0.7, 0.98); return bb_from_roots(K(r), a, U(r, -3, -1.5), U(r, -3, -1.5), 0); }},
    };
}

template <class T>
void cubic_comparison(int per_case) {
    const auto methods = cubic_methods<T>();
    const auto cases = cubic_cases();
    const bool is_float = sizeof(T) == 4;
    std::printf("\n== cubic first root in [0,1], T = %s, %d polynomials per case; truth = long double roots of the T-rounded coefficients ==\n",
                is_float ? "float" : "double", per_case);
    std::printf("   columns: ok / miss (truth has a root, method none) / false hit / wrong root (|dt| > 1e-3) / max |dt| on well-conditioned ok\n");
    std::vector<std::vector<Tally>> tallies(cases.size(), std::vector<Tally>(methods.size()));
    for (std::size_t k = 0; k < cases.size(); ++k) {
        for (int it = 0; it < per_case; ++it) {
            std::mt19937 rng(static_cast<unsigned>(100000 * (k + 1) + it));
            const auto cl = cases[k].make(rng);
            Vec<T, 4> c{};
            std::array<LD, 4> cr{};
            for (int i = 0; i < 4; ++i) {
                c[i] = T(static_cast<double>(cl[i]));
                cr[i] = static_cast<LD>(c[i]);
            }
            const Ref ref = reference_roots(cr);
            const bool has = !ref.roots.empty();
            const LD tref = has ? ref.roots.front() : 0;
            const bool well = has && !ref.first_tangent && ref.slope_first > 1e-2L;
            for (std::size_t m = 0; m < methods.size(); ++m) {
                const UnitRoot<T> r = methods[m].second(c);
                tallies[k][m].add(has, tref, r.hit, static_cast<double>(r.t), well);
            }
        }
    }
    for (std::size_t k = 0; k < cases.size(); ++k) {
        std::printf("  -- %s\n", cases[k].name);
        for (std::size_t m = 0; m < methods.size(); ++m) {
            const Tally& t = tallies[k][m];
            std::printf("     %-36s %6ld / %5ld / %5ld / %5ld / %.2e\n", methods[m].first.c_str(), t.ok, t.miss, t.false_hit, t.wrong, t.max_err_ok);
        }
    }
    // Cost: operation counts (Counted scalar) and time per call.
    std::printf("  -- cost per call (ops = + - * / sqrt abs; cmp/select/logic counted separately), time on random coefficients\n");
    std::vector<Vec<T, 4>> sample(20000);
    std::mt19937 rng(77);
    std::uniform_real_distribution<double> u(-1, 1);
    for (auto& c : sample) c = {{T(u(rng)), T(u(rng)), T(u(rng)), T(u(rng))}};
    using C = qtest::Counted<T>;
    const Vec<C, 4> cc = {{C::raw(sample[0][0]), C::raw(sample[0][1]), C::raw(sample[0][2]), C::raw(sample[0][3])}};
    auto count = [&](auto f) {
        qtest::op_counts = {};
        f();
        return qtest::op_counts;
    };
    const qtest::OpCounts oc[] = {
        count([&] { (void)cubic_first_root_newton<5>(cc, C(1e-5)); }),
        count([&] { (void)cubic_first_root_isolated<4>(cc); }),
        count([&] { (void)cubic_first_root_isolated<6>(cc); }),
        count([&] { (void)quadratic_first_root(Vec<C, 3>{{cc[0], cc[1], cc[2]}}, C(0)); }),
    };
    const char* names[] = {"newton5", "isolated<4>", "isolated<6>", "quadratic (q=2)"};
    for (int i = 0; i < 4; ++i)
        std::printf("     %-16s arith %4ld (div %3ld, sqrt %ld)  cmp %3ld  select %3ld  logic %3ld\n", names[i], oc[i].arith(), oc[i].div, oc[i].sqrt,
                    oc[i].cmp, oc[i].sel, oc[i].logic);
    auto time_it = [&](auto f) {
        volatile double sink = 0;
        const auto t0 = std::chrono::steady_clock::now();
        for (int rep = 0; rep < 5; ++rep)
            for (const auto& c : sample) sink = sink + static_cast<double>(f(c).t);
        const auto t1 = std::chrono::steady_clock::now();
        return std::chrono::duration<double, std::nano>(t1 - t0).count() / (5.0 * sample.size());
    };
    std::printf("     time: newton5 %.1f ns, isolated<4> %.1f ns, isolated<6> %.1f ns, isolated<10> %.1f ns per call\n",
                time_it([](const Vec<T, 4>& c) { return cubic_first_root_newton<5>(c, T(1e-5)); }),
                time_it([](const Vec<T, 4>& c) { return cubic_first_root_isolated<4>(c); }),
                time_it([](const Vec<T, 4>& c) { return cubic_first_root_isolated<6>(c); }),
                time_it([](const Vec<T, 4>& c) { return cubic_first_root_isolated<10>(c); }));

    // What is asserted: the robust method (default, 6 iterations) never misses or invents a root on the
    // well-separated cases and is accurate there; Newton is only reported.
    const std::size_t iso8 = 6;  // "isolated, 6 iterations (default)"
    for (std::size_t k : {std::size_t(0), std::size_t(1), std::size_t(4), std::size_t(7), std::size_t(8)}) {
        CAPTURE(cases[k].name);
        const Tally& t = tallies[k][iso8];
        CHECK(t.false_hit == 0);
        // random coefficients can be tangent by chance; allow a handful of such misses
        CHECK(t.miss <= (k == 0 ? per_case / 2000 : 0));
        // two roots 1e-3 apart: in float the extremum between them (~1e-7) can round to the
        // wrong sign, then the second root is found; that is a conditioning limit, not a bug
        CHECK(t.wrong <= (k == 4 && is_float ? per_case / 1000 : 0));
        // random coefficients include flat inflections, where 6 steps are not yet converged
        CHECK(t.max_err_ok < (k == 0 ? (is_float ? 2e-5 : 1e-6) : (is_float ? 5e-6 : 1e-13)));
    }
    // tangent and triple roots: found (maybe with reduced accuracy) in most cases
    CHECK(tallies[2][iso8].miss + tallies[2][iso8].wrong < per_case / 2);
    CHECK(tallies[6][iso8].miss == 0);
}

}  // namespace

TEST_CASE_TEMPLATE("the stable quadratic formula finds the roots in [0,1]", T, float, double) {
    long miss = 0, false_hit = 0, wrong = 0, well_n = 0, tangent_n = 0, tangent_found = 0;
    double max_err = 0;
    for (int it = 0; it < 40000; ++it) {
        std::mt19937 rng(9000 + it);
        std::uniform_real_distribution<double> u(-1, 1);
        std::array<LD, 3> cl{};
        const int kind = it % 4;
        if (kind == 0) {
            cl = {static_cast<LD>(u(rng)), static_cast<LD>(u(rng)), static_cast<LD>(u(rng))};
        } else {
            // k (t - r1)(t - r2): BB b0 = a0, b1 = a0 + a1/2, b2 = a0 + a1 + a2
            const LD k = static_cast<LD>(u(rng) < 0 ? -1 - u(rng) : 1 + u(rng));
            const LD r1 = 0.5L + static_cast<LD>(u(rng)), r2 = kind == 3 ? r1 : (kind == 2 ? r1 + 1e-4L : 0.5L + static_cast<LD>(u(rng)));
            const LD a2 = k, a1 = -k * (r1 + r2), a0 = k * r1 * r2;
            cl = {a0, a0 + a1 / 2, a0 + a1 + a2};
        }
        Vec<T, 3> c{};
        std::array<LD, 3> cr{};
        for (int i = 0; i < 3; ++i) {
            c[i] = T(static_cast<double>(cl[i]));
            cr[i] = static_cast<LD>(c[i]);
        }
        const Ref ref = reference_roots(cr);
        const UnitRoots2<T> r = quadratic_roots(c);
        const bool has = !ref.roots.empty();
        if (kind == 3) {
            ++tangent_n;
            if (r.hit[0]) ++tangent_found;
            continue;
        }
        const bool well = has && ref.slope_first > 1e-2L;
        if (!well) continue;
        ++well_n;
        if (!r.hit[0]) { ++miss; continue; }
        const double e = static_cast<double>(std::fabs(static_cast<LD>(r.t[0]) - ref.roots.front()));
        if (e > 1e-3) ++wrong;
        else max_err = std::max(max_err, e);
        if (ref.roots.size() == 2 && r.hit[1]) max_err = std::max(max_err, static_cast<double>(std::fabs(static_cast<LD>(r.t[1]) - ref.roots[1])));
        if (ref.roots.size() == 2 && !r.hit[1]) ++miss;
        if (ref.roots.size() == 1 && r.hit[1]) ++false_hit;
    }
    MESSAGE("quadratic: well-conditioned ", well_n, " misses ", miss, " false ", false_hit, " wrong ", wrong, " max |dt| ", max_err,
            "; exact double roots (rounded to T) reported as hits: ", tangent_found, "/", tangent_n);
    CHECK(miss == 0);
    CHECK(false_hit == 0);
    CHECK(wrong == 0);
    CHECK(max_err < (sizeof(T) == 4 ? 2e-5 : 1e-13));
    // degenerate inputs stay finite and exact where they should
    const UnitRoots2<T> lin = quadratic_roots(Vec<T, 3>{{T(-1), T(0), T(1)}});  // linear, root 1/2
    CHECK(lin.hit[0]);
    CHECK(lin.t[0] == T(0.5));
    CHECK(!lin.hit[1]);
    const UnitRoots2<T> none = quadratic_roots(Vec<T, 3>{{T(1), T(1), T(1)}});
    CHECK(!none.hit[0]);
    CHECK(std::isfinite(none.t[0]));
    const UnitRoots2<T> zero0 = quadratic_roots(Vec<T, 3>{{T(0), T(1), T(-1)}});  // roots 0 and 2/3
    CHECK(zero0.hit[0]);
    CHECK(zero0.t[0] == T(0));
    CHECK(zero0.hit[1]);
    CHECK(zero0.t[1] == doctest::Approx(2.0 / 3.0));
}

TEST_CASE_TEMPLATE("cubic roots: Newton-5 of the paper against isolation + safeguarded Newton", T, float, double) {
    cubic_comparison<T>(sizeof(T) == 4 ? 20000 : 10000);
}

TEST_CASE("root finders compile with the tracer-like scalar and give the same bits") {
    using C = qtest::Counted<float>;
    for (int it = 0; it < 500; ++it) {
        std::mt19937 rng(12000 + it);
        std::uniform_real_distribution<double> u(-1, 1);
        const Vec<float, 4> f = {{float(u(rng)), float(u(rng)), float(u(rng)), float(u(rng))}};
        const Vec<C, 4> c = {{C::raw(f[0]), C::raw(f[1]), C::raw(f[2]), C::raw(f[3])}};
        const auto a = cubic_first_root_isolated<6>(f);
        const auto b = cubic_first_root_isolated<6>(c);
        CHECK(a.hit == b.hit.v);
        CHECK(a.t == b.t.v);
        const auto n1 = cubic_first_root_newton<5>(f, 1e-4f);
        const auto n2 = cubic_first_root_newton<5>(c, C(1e-4));
        CHECK(n1.hit == n2.hit.v);
        CHECK(n1.t == n2.t.v);
        const auto q1 = quadratic_first_root(Vec<float, 3>{{f[0], f[1], f[2]}}, f[3]);
        const auto q2 = quadratic_first_root(Vec<C, 3>{{c[0], c[1], c[2]}}, c[3]);
        CHECK(q1.hit == q2.hit.v);
        CHECK(q1.t == q2.t.v);
    }
}
