// tests/volume/test_spline_coeffs.cpp -- `quadcast spline-coeffs`: stencil parsing, linear reproduction, JSON shape
#include <doctest/doctest.h>

#include <cmath>
#include <random>
#include <string>

#include <nlohmann/json.hpp>

#include "quadcast/spline/spline.hpp"
#include "quadcast/volume/spline_stencil.hpp"

using namespace quadcast;
using namespace quadcast::volume;

namespace {

/// The stencil of the linear function p(u) = g0 + g . u with data at local u = 2 (a, b, c).
std::array<double, 27> linear_stencil(double g0, const double (&g)[3]) {
    std::array<double, 27> f{};
    for (int s = 0; s < 27; ++s) {
        const auto o = spline::stencil_offset(s);
        f[std::size_t(s)] = g0 + 2.0 * (g[0] * o[0] + g[1] * o[1] + g[2] * o[2]);
    }
    return f;
}

template <int Q>
void check_linear(SplineScheme scheme) {
    // Dyadic gradient and offset: q p(ξ) = q g0 + g . (q ξ) is exact in double, and one
    // division by q rounds it like the exact coefficient is rounded.
    const double g0 = 0.375, g[3] = {1.25, -0.5, 3.0};
    const auto tets = cube_tet_coefficients(scheme, linear_stencil(g0, g));
    REQUIRE(tets.size() == 24);
    const auto mi = bb::multi_indices<Q>();
    for (int t = 0; t < 24; ++t) {
        REQUIRE(tets[std::size_t(t)].size() == mi.size());
        const auto v = spline::tet_vertices(t);
        for (std::size_t n = 0; n < mi.size(); ++n) {
            const auto qxi = bb::scaled_domain_point(mi[n], v);
            const double expected = (Q * g0 + ((g[0] * qxi[0] + g[1] * qxi[1]) + g[2] * qxi[2])) / Q;
            CAPTURE(t);
            CAPTURE(n);
            CHECK(tets[std::size_t(t)][n] == expected);
        }
    }
}

}  // namespace

TEST_CASE("spline-coeffs reproduces linear data in all 24 tetrahedra, QSS and S31") {
    check_linear<2>(SplineScheme::qss);
    check_linear<3>(SplineScheme::s31);
}

TEST_CASE("spline-coeffs agrees with the averaging path of the renderer on random data") {
    std::mt19937 rng(17);
    std::uniform_real_distribution<double> u(-100.0, 100.0);
    for (int it = 0; it < 50; ++it) {
        std::array<double, 27> f{};
        spline::Stencil<double> st{};
        for (int s = 0; s < 27; ++s) st[s] = f[std::size_t(s)] = u(rng);
        const auto q = cube_tet_coefficients(SplineScheme::qss, f);
        const auto c = cube_tet_coefficients(SplineScheme::s31, f);
        const auto d2 = spline::determining_set_from_stencil<2>(st);
        const auto d3 = spline::determining_set_from_stencil<3>(st);
        for (int t = 0; t < 24; ++t) {
            const auto a2 = spline::tet_from_determining_set<2>(d2, t);
            const auto a3 = spline::tet_from_determining_set<3>(d3, t);
            for (int n = 0; n < 10; ++n) CHECK(q[std::size_t(t)][std::size_t(n)] == doctest::Approx(a2[n]).epsilon(1e-12).scale(100));
            for (int n = 0; n < 20; ++n) CHECK(c[std::size_t(t)][std::size_t(n)] == doctest::Approx(a3[n]).epsilon(1e-12).scale(100));
        }
    }
}

TEST_CASE("spline-coeffs prints the issue's JSON: scheme and 24 arrays of 10 or 20 numbers") {
    std::array<double, 27> f{};
    for (int s = 0; s < 27; ++s) f[std::size_t(s)] = 0.1 * s - 1.3;
    for (SplineScheme sc : {SplineScheme::qss, SplineScheme::s31}) {
        const auto tets = cube_tet_coefficients(sc, f);
        const nlohmann::json j = nlohmann::json::parse(coefficients_json(sc, tets));
        CHECK(j.at("scheme") == scheme_name(sc));
        REQUIRE(j.at("tets").size() == 24);
        for (int t = 0; t < 24; ++t) {
            REQUIRE(j["tets"][std::size_t(t)].size() == (sc == SplineScheme::qss ? 10u : 20u));
            for (std::size_t n = 0; n < tets[std::size_t(t)].size(); ++n)
                CHECK(j["tets"][std::size_t(t)][n].get<double>() == tets[std::size_t(t)][n]);  // shortest form reads back exactly
        }
    }
    // Constant data: every coefficient is the constant (both schemes).
    std::array<double, 27> one{};
    one.fill(1.0);
    for (const auto& t : cube_tet_coefficients(SplineScheme::s31, one))
        for (double c : t) CHECK(c == 1.0);
}

TEST_CASE("bad stencils are rejected with the value's position") {
    std::string ok;
    for (int i = 0; i < 27; ++i) ok += (i ? "," : "") + std::to_string(i);
    CHECK(parse_stencil(ok)[26] == 26.0);
    std::string spaced = " 1e-3 , +2,-0.5";
    for (int i = 0; i < 24; ++i) spaced += ", 0";
    CHECK(parse_stencil(spaced)[0] == 1e-3);
    CHECK(parse_stencil(spaced)[1] == 2.0);
    CHECK_THROWS_WITH_AS(parse_stencil("1,2,3"), doctest::Contains("needs 27 comma-separated values"), std::invalid_argument);
    CHECK_THROWS_WITH_AS(parse_stencil(ok + ",27"), doctest::Contains("found 28"), std::invalid_argument);
    std::string bad = ok;
    bad.replace(bad.find(",5,"), 3, ",five,");
    CHECK_THROWS_WITH_AS(parse_stencil(bad), "stencil value 6 of 27 ('five') is not a number", std::invalid_argument);
    bad = ok;
    bad.replace(bad.find(",5,"), 3, ",nan,");
    CHECK_THROWS_WITH_AS(parse_stencil(bad), "stencil value 6 of 27 is NaN", std::invalid_argument);
    bad = ok;
    bad.replace(bad.find(",5,"), 3, ",-inf,");
    CHECK_THROWS_WITH_AS(parse_stencil(bad), "stencil value 6 of 27 is infinite", std::invalid_argument);
    bad = ok;
    bad.replace(bad.find(",5,"), 3, ",,");
    CHECK_THROWS_WITH_AS(parse_stencil(bad), "stencil value 6 of 27 is empty", std::invalid_argument);
    bad = ok;
    bad.replace(bad.find(",5,"), 3, ",1e999,");
    CHECK_THROWS_WITH_AS(parse_stencil(bad), doctest::Contains("out of the range of double"), std::invalid_argument);
    // QSS's centre mask has negative weights: data of magnitude 1.7e308 with the signs of the
    // weights give 9/8 * 1.7e308 > DBL_MAX.
    std::array<double, 27> huge{};
    for (int s = 0; s < 27; ++s) huge[std::size_t(s)] = spline::tet0_mask<2>(0, s) < 0 ? -1.7e308 : 1.7e308;
    CHECK_THROWS_WITH_AS((void)cube_tet_coefficients(SplineScheme::qss, huge), doctest::Contains("overflows double"), std::invalid_argument);
    CHECK_THROWS_AS((void)parse_scheme("cubic"), std::invalid_argument);
    CHECK(parse_scheme("QSS") == SplineScheme::qss);
}
