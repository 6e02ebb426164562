// tests/spline/test_spline.cpp -- QSS / S31 in floating point: paths, sharing, C0/C1, reproduction, rays, tracing
#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <random>
#include <vector>

#include "bb/test_scalars.hpp"
#include "quadcast/bb/bb.hpp"
#include "spline/spline_test_util.hpp"

using namespace quadcast;
using namespace quadcast::spline;
using stest::eval_piece;
using stest::random_volume;

namespace {

template <class T>
constexpr double eps() { return static_cast<double>(std::numeric_limits<T>::epsilon()); }

template <int Q, class T>
double averaging_vs_direct() {
    double worst = 0;
    for (int it = 0; it < 300; ++it) {
        std::mt19937 rng(100 + it);
        std::uniform_real_distribution<double> u(-1, 1);
        Stencil<T> f{};
        for (int s = 0; s < 27; ++s) f[s] = T(u(rng));
        const DeterminingSet<T, Q> d = determining_set_from_stencil<Q>(f);
        for (int t = 0; t < 24; ++t) {
            const auto a = tet_from_determining_set<Q>(d, t);
            const auto b = tet_from_stencil<Q>(f, t);
            for (int n = 0; n < a.size; ++n) worst = std::max(worst, std::fabs(static_cast<double>(a[n] - b[n])));
        }
    }
    return worst / eps<T>();
}

/// Max spread of the values given to one global domain point by all (cube, tetrahedron) pairs
/// of a grid, in units of eps (data in [-1,1]).
template <int Q, class T>
double sharing_spread(const SplineGrid<Q, T>& g) {
    std::map<IVec3, std::array<double, 2>> range;
    const auto idx = bb::multi_indices<Q>();
    for (int c = 0; c < g.cube_count(); ++c) {
        const IVec3 ijk = g.cube_ijk(c);
        for (int t = 0; t < 24; ++t) {
            const auto coef = tet_from_determining_set<Q>(g.cube_d(c), t);
            for (int n = 0; n < coef.size; ++n) {
                IVec3 p = bb::scaled_domain_point(idx[n], tet_vertices(t));
                for (int a = 0; a < 3; ++a) p[a] += 2 * Q * ijk[a];
                const double v = static_cast<double>(coef[n]);
                auto it = range.find(p);
                if (it == range.end()) range[p] = {v, v};
                else it->second = {std::min(it->second[0], v), std::max(it->second[1], v)};
            }
        }
    }
    double worst = 0;
    for (const auto& [p, r] : range) worst = std::max(worst, r[1] - r[0]);
    return worst / eps<T>();
}

struct Jumps {
    long triangles[3] = {0, 0, 0};
    double value[3] = {0, 0, 0};
    double grad[3] = {0, 0, 0};
};

/// Jumps of value and gradient across every triangle shared by two pieces of the 3x3x3 cubes
/// 1..3 of a 5x5x5 grid (h = 2: world units = cube-local units); 40 random points per
/// triangle. Category 0: cube faces, 1: interior [v_Q, v, w], 2: interior [v_Q, F, v].
template <int Q, class T>
Jumps c1_jumps(const SplineGrid<Q, T>& g, unsigned seed) {
    struct Owner { int cube, tet; };
    std::map<std::array<IVec3, 3>, std::vector<Owner>> tri;
    for (int k = 1; k <= 3; ++k)
        for (int j = 1; j <= 3; ++j)
            for (int i = 1; i <= 3; ++i) {
                const int c = g.cube_index(i, j, k);
                for (int t = 0; t < 24; ++t) {
                    const auto v = tet_vertices(t);
                    for (int skip = 0; skip < 4; ++skip) {
                        std::array<IVec3, 3> key{};
                        int n = 0;
                        for (int m = 0; m < 4; ++m)
                            if (m != skip) key[n++] = {v[m][0] + 2 * i, v[m][1] + 2 * j, v[m][2] + 2 * k};
                        std::sort(key.begin(), key.end());
                        tri[key].push_back({c, t});
                    }
                }
            }
    Jumps J;
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(0, 1);
    for (const auto& [key, own] : tri) {
        if (own.size() != 2) continue;
        int cat = 0;
        if (own[0].cube == own[1].cube) {
            // interior: contains the face centre F (exactly one coordinate odd-offset ±1 from v_Q)?
            const IVec3 ijk = g.cube_ijk(own[0].cube);
            bool has_face_centre = false;
            for (const IVec3& p : key) {
                const int nz = (p[0] != 2 * ijk[0]) + (p[1] != 2 * ijk[1]) + (p[2] != 2 * ijk[2]);
                has_face_centre = has_face_centre || nz == 1;
            }
            cat = has_face_centre ? 2 : 1;
        }
        ++J.triangles[cat];
        for (int s = 0; s < 40; ++s) {
            double a = u(rng), b = u(rng);
            if (a + b > 1) { a = 1 - a; b = 1 - b; }
            Vec<double, 3> x{};
            for (int d = 0; d < 3; ++d) x[d] = (1 - a - b) * key[0][d] + a * key[1][d] + b * key[2][d];
            ValueAndGradient<T> e[2];
            for (int o = 0; o < 2; ++o) {
                const IVec3 ijk = g.cube_ijk(own[o].cube);
                const Vec<double, 3> ul = {{x[0] - 2 * ijk[0], x[1] - 2 * ijk[1], x[2] - 2 * ijk[2]}};
                e[o] = eval_piece(g, own[o].cube, own[o].tet, ul);
            }
            J.value[cat] = std::max(J.value[cat], std::fabs(static_cast<double>(e[0].value - e[1].value)));
            for (int d = 0; d < 3; ++d)
                J.grad[cat] = std::max(J.grad[cat], std::fabs(static_cast<double>(e[0].gradient[d] - e[1].gradient[d])));
        }
    }
    return J;
}

}  // namespace

TEST_CASE_TEMPLATE("the averaging path equals the direct path to rounding", T, float, double) {
    const double q2 = averaging_vs_direct<2, T>(), q3 = averaging_vs_direct<3, T>();
    MESSAGE("max |averaging - direct| / eps (data in [-1,1]): QSS ", q2, ", S31 ", q3);
    CHECK(q2 < 8);
    CHECK(q3 < 8);
}

TEST_CASE_TEMPLATE("neighbouring tetrahedra and cubes share coefficients", T, float, double) {
    const Volume<T> vol = random_volume<T>(5, 4, 6, 7);
    const auto g2 = build_spline<2>(vol, {{0.0, 0.0, 0.0}}, 1.0);
    const auto g3 = build_spline<3>(vol, {{0.0, 0.0, 0.0}}, 1.0);
    const double s2 = sharing_spread(g2), s3 = sharing_spread(g3);
    MESSAGE("max spread of a shared coefficient / eps: QSS ", s2, ", S31 ", s3);
    CHECK(s2 < 4);
    CHECK(s3 < 4);
    // the determining-set values of shared points are bit-identical in neighbouring cubes
    long differ = 0, compared = 0;
    for (int c = 0; c < g3.cube_count(); ++c) {
        const IVec3 ijk = g3.cube_ijk(c);
        if (ijk[0] + 1 >= g3.nx) continue;
        const int c2 = g3.cube_index(ijk[0] + 1, ijk[1], ijk[2]);
        for (int k = 0; k < 56; ++k) {
            const IVec3 p = d_point(3, k);
            if (p[0] != 3) continue;
            const int k2 = d_index(3, {-3, p[1], p[2]});
            if (k2 < 0) continue;
            ++compared;
            differ += g3.d[static_cast<std::size_t>(c) * 56 + k] != g3.d[static_cast<std::size_t>(c2) * 56 + k2];
        }
    }
    CHECK(compared > 0);
    CHECK(differ == 0);
    // threads do not change the result
    const auto g3b = build_spline<3>(vol, {{0.0, 0.0, 0.0}}, 1.0, 1);
    CHECK(g3b.d == g3.d);
}

TEST_CASE_TEMPLATE("the splines are C0 everywhere; S31 is C1 everywhere and QSS across cube faces", T, float, double) {
    const Volume<T> vol = random_volume<T>(5, 5, 5, 2024);
    const auto g2 = build_spline<2>(vol, {{0.0, 0.0, 0.0}}, 2.0);
    const auto g3 = build_spline<3>(vol, {{0.0, 0.0, 0.0}}, 2.0);
    const Jumps a = c1_jumps(g2, 5), b = c1_jumps(g3, 5);
    const char* names[3] = {"cube faces", "interior [v_Q,v,w]", "interior [v_Q,F,v]"};
    std::printf("\nC0/C1 jumps, %s, 3x3x3 cubes, random data in [-1,1], 40 points per triangle (spec §6 double: faces 1.7e-16/1.6e-15 "
                "QSS, 1.7e-16/2.0e-15 S31; QSS interior gradient 3.1e-01 / 3.3e-01)\n", sizeof(T) == 4 ? "float" : "double");
    std::printf("  %-20s %6s %12s %12s %12s %12s\n", "triangles", "count", "QSS value", "QSS grad", "S31 value", "S31 grad");
    for (int k = 0; k < 3; ++k)
        std::printf("  %-20s %6ld %12.2e %12.2e %12.2e %12.2e\n", names[k], a.triangles[k], a.value[k], a.grad[k], b.value[k], b.grad[k]);
    CHECK(a.triangles[0] == 216);
    CHECK(a.triangles[1] == 324);
    CHECK(a.triangles[2] == 648);
    const double tol_v = 16 * eps<T>(), tol_g = 64 * eps<T>();
    for (int k = 0; k < 3; ++k) {
        CHECK(a.value[k] < tol_v);
        CHECK(b.value[k] < tol_v);
        CHECK(b.grad[k] < tol_g);
    }
    CHECK(a.grad[0] < tol_g);
    // QSS is not C1 across the interior triangles (by design): the jump is large
    CHECK(a.grad[1] > 0.05);
    CHECK(a.grad[2] > 0.05);
}

TEST_CASE_TEMPLATE("linear polynomials are reproduced and quadratics get the defect h^2/8 Δp", T, float, double) {
    const int n = 10;
    const double h = 1.0 / n;
    double lin_v = 0, lin_g = 0, quad_v = 0, quad_g = 0, quad_plain = 0;
    for (int poly = 0; poly < 5; ++poly) {
        std::mt19937 rng(500 + poly);
        std::uniform_real_distribution<double> u(-1, 1);
        double A[3][3], b[3], c0 = u(rng);
        for (int i = 0; i < 3; ++i) {
            b[i] = u(rng);
            for (int j = i; j < 3; ++j) A[i][j] = A[j][i] = u(rng);
        }
        const double lap = 2 * (A[0][0] + A[1][1] + A[2][2]);
        for (int quadratic = 0; quadratic < 2; ++quadratic) {
            auto p = [&](const double x[3]) {
                double v = c0;
                for (int i = 0; i < 3; ++i) {
                    v += b[i] * x[i];
                    if (quadratic)
                        for (int j = 0; j < 3; ++j) v += x[i] * A[i][j] * x[j];
                }
                return v;
            };
            auto grad = [&](const double x[3], int i) {
                double v = b[i];
                if (quadratic)
                    for (int j = 0; j < 3; ++j) v += 2 * A[i][j] * x[j];
                return v;
            };
            Volume<T> vol(n + 1, n + 1, n + 1);
            for (int k = 0; k <= n; ++k)
                for (int j = 0; j <= n; ++j)
                    for (int i = 0; i <= n; ++i) {
                        const double x[3] = {i * h, j * h, k * h};
                        vol.at(i, j, k) = T(p(x));
                    }
            const auto g2 = build_spline<2>(vol, {{0.0, 0.0, 0.0}}, h);
            const auto g3 = build_spline<3>(vol, {{0.0, 0.0, 0.0}}, h);
            std::uniform_real_distribution<double> inner(0.2, 0.8);
            for (int s = 0; s < 800; ++s) {
                const double x[3] = {inner(rng), inner(rng), inner(rng)};
                const Vec<double, 3> xv = {{x[0], x[1], x[2]}};
                for (const ValueAndGradient<T>& e : {evaluate(g2, xv), evaluate(g3, xv)}) {
                    const double expect = p(x) + (quadratic ? h * h / 8 * lap : 0.0);
                    double gerr = 0;
                    for (int i = 0; i < 3; ++i) gerr = std::max(gerr, std::fabs(static_cast<double>(e.gradient[i]) - grad(x, i)));
                    const double verr = std::fabs(static_cast<double>(e.value) - expect);
                    if (quadratic) {
                        quad_v = std::max(quad_v, verr);
                        quad_g = std::max(quad_g, gerr);
                        quad_plain = std::max(quad_plain, std::fabs(static_cast<double>(e.value) - p(x)));
                    } else {
                        lin_v = std::max(lin_v, verr);
                        lin_g = std::max(lin_g, gerr);
                    }
                }
            }
        }
    }
    std::printf("\nreproduction, %s, h = 1/10, 4000 points, 5 polynomials (spec §6 double: linear value <= 2.7e-15, gradient <= 1.4e-13; "
                "quadratic |s-p| up to 4.6e-3/3.6e-3, |s-p-h²Δp/8| <= 3.5e-15, gradient <= 1.8e-13):\n"
                "  linear: value %.2e gradient %.2e; quadratic: |s-p| %.2e, |s-p-h²Δp/8| %.2e, gradient %.2e\n",
                sizeof(T) == 4 ? "float" : "double", lin_v, lin_g, quad_plain, quad_v, quad_g);
    CHECK(lin_v < 64 * eps<T>());
    CHECK(quad_v < 64 * eps<T>());
    CHECK(lin_g < 2048 * eps<T>());
    CHECK(quad_g < 2048 * eps<T>());
    CHECK(quad_plain > 1e-3);  // the defect is real
}

TEST_CASE_TEMPLATE("the restriction of a spline piece to a ray by blossoming equals the spline on the ray", T, float, double) {
    const Volume<T> vol = random_volume<T>(6, 6, 6, 11);
    const auto g3 = build_spline<3>(vol, {{0.0, 0.0, 0.0}}, 1.0);
    const auto g2 = build_spline<2>(vol, {{0.0, 0.0, 0.0}}, 1.0);
    std::mt19937 rng(12);
    std::uniform_real_distribution<double> u(0, 1);
    double worst = 0, worst_root_residual = 0;
    long roots = 0;
    for (int it = 0; it < 400; ++it) {
        const int c = g3.cube_index(1 + it % 4, 1 + (it / 4) % 4, 1 + (it / 16) % 4), t = it % 24;
        const IVec3 ijk = g3.cube_ijk(c);
        // two points inside the tetrahedron (cube-local) -> barycentrics
        auto inside = [&] {
            double w[4], s = 0;
            for (double& x : w) s += (x = -std::log(u(rng) + 1e-300));
            const auto v = tet_vertices(t);
            Vec<double, 3> p{{0, 0, 0}};
            for (int m = 0; m < 4; ++m)
                for (int a = 0; a < 3; ++a) p[a] += w[m] / s * v[m][a];
            return p;
        };
        const Vec<double, 3> pa = inside(), pb = inside();
        const Vec<T, 4> la = barycentric(t, cast<T>(pa)), lb = barycentric(t, cast<T>(pb));
        const auto c3 = tet_from_determining_set<3>(g3.cube_d(c), t);
        const auto c2 = tet_from_determining_set<2>(g2.cube_d(c), t);
        const Vec<T, 4> r3 = bb::restrict_to_segment(c3, la, lb);
        const Vec<T, 3> r2 = bb::restrict_to_segment(c2, la, lb);
        for (int k = 0; k <= 8; ++k) {
            const double s = k / 8.0;
            Vec<double, 3> xw{};
            for (int a = 0; a < 3; ++a) xw[a] = ijk[a] + 0.5 * ((1 - s) * pa[a] + s * pb[a]);
            const T ref3 = evaluate(g3, xw).value, ref2 = evaluate(g2, xw).value;
            worst = std::max(worst, std::fabs(static_cast<double>(bb::evaluate_univariate(r3, T(s)).value - ref3)));
            worst = std::max(worst, std::fabs(static_cast<double>(bb::evaluate_univariate(r2, T(s)).value - ref2)));
        }
        // first crossing of the level through the middle of the segment
        const T rho = bb::evaluate_univariate(r3, T(0.5)).value;
        const bb::UnitRoot<T> root = bb::cubic_first_root(r3, rho);
        CHECK(root.hit);
        if (root.hit) {
            ++roots;
            Vec<double, 3> xw{};
            const double s = static_cast<double>(root.t);
            for (int a = 0; a < 3; ++a) xw[a] = ijk[a] + 0.5 * ((1 - s) * pa[a] + s * pb[a]);
            worst_root_residual = std::max(worst_root_residual, std::fabs(static_cast<double>(evaluate(g3, xw).value - rho)));
        }
    }
    MESSAGE("max |restriction - spline on the ray| = ", worst, ", max |s(root) - ρ| = ", worst_root_residual, " over ", roots, " rays");
    CHECK(worst < 64 * eps<T>());
    CHECK(worst_root_residual < 256 * eps<T>());
}

TEST_CASE("the per-cube templates compile with a tracer-like scalar and give the same bits; vertex-stage cost") {
    using C = qtest::Counted<float>;
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> u(-1, 1);
    Stencil<float> f{};
    Stencil<C> fc{};
    for (int s = 0; s < 27; ++s) {
        f[s] = float(u(rng));
        fc[s] = C::raw(f[s]);
    }
    qtest::op_counts = {};
    const auto d2c = determining_set_from_stencil<2>(fc);
    const long ops_d2 = qtest::op_counts.arith();
    qtest::op_counts = {};
    const auto d3c = determining_set_from_stencil<3>(fc);
    const long ops_d3 = qtest::op_counts.arith();
    const auto d2 = determining_set_from_stencil<2>(f);
    const auto d3 = determining_set_from_stencil<3>(f);
    for (int k = 0; k < 20; ++k) CHECK(d2c[k].v == d2[k]);
    for (int k = 0; k < 56; ++k) CHECK(d3c[k].v == d3[k]);
    long ops_q2 = 0, ops_q3 = 0, ops_direct3 = 0;
    for (int t = 0; t < 24; ++t) {
        qtest::op_counts = {};
        const auto a = tet0_from_determining_set<2>(rotate_determining_set<2>(d2c, t));
        ops_q2 = qtest::op_counts.arith();
        qtest::op_counts = {};
        const auto b = tet0_from_determining_set<3>(rotate_determining_set<3>(d3c, t));
        ops_q3 = qtest::op_counts.arith();
        qtest::op_counts = {};
        const auto e = tet0_from_stencil<3>(rotate_stencil(fc, t));
        ops_direct3 = qtest::op_counts.arith();
        const auto a0 = tet_from_determining_set<2>(d2, t);
        const auto b0 = tet_from_determining_set<3>(d3, t);
        const auto e0 = tet_from_stencil<3>(f, t);
        for (int n = 0; n < 10; ++n) CHECK(a[n].v == a0[n]);
        for (int n = 0; n < 20; ++n) CHECK(b[n].v == b0[n]);
        for (int n = 0; n < 20; ++n) CHECK(e[n].v == e0[n]);
    }
    const Vec<C, 4> l = barycentric_tet0(Vec<C, 3>{{C::raw(0.75f), C::raw(-0.25f), C::raw(-0.5f)}});
    CHECK(l[0].v == 0.25f);
    // point -> barycentrics -> value and gradient, all traced
    for (int t = 0; t < 24; t += 5) {
        const Vec<float, 3> uf = {{0.3f, -0.45f, 0.2f}};
        const Vec<C, 3> uc = {{C::raw(uf[0]), C::raw(uf[1]), C::raw(uf[2])}};
        const Vec<C, 4> lc = barycentric(t, uc);
        const Vec<float, 4> lf = barycentric(t, uf);
        const auto coef_c = tet0_from_determining_set<3>(rotate_determining_set<3>(d3c, t));
        const auto coef_f = tet_from_determining_set<3>(d3, t);
        const Vec<C, 3> gc = bb::gradient(bb::value_and_partials(coef_c, lc), barycentric_directions<C>(t));
        const Vec<float, 3> gf = bb::gradient(bb::value_and_partials(coef_f, lf), barycentric_directions<float>(t));
        for (int a = 0; a < 3; ++a) CHECK(gc[a].v == gf[a]);
        const Vec<C, 4> args[3] = {lc, lc, lc};
        CHECK(bb::blossom(coef_c, args).v == bb::evaluate(coef_f, lf));
    }
    MESSAGE("arithmetic ops: D2 from data ", ops_d2, ", D3 from data ", ops_d3, "; per tetrahedron: QSS repeated averaging ", ops_q2,
            ", S31 repeated averaging ", ops_q3, ", S31 direct masks ", ops_direct3);
}
