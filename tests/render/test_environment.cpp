// tests/render/test_environment.cpp -- environment reflection: reflection vector, atan2, latitude-longitude lookup
#include <doctest/doctest.h>

#include <cmath>
#include <cstdio>

#include "quadcast/render/environment.hpp"
#include "quadcast/shading.hpp"
#include "render/render_testing.hpp"

using namespace qc_render_test;
using quadcast::atan2_poly;
using quadcast::latlong_texel;
using quadcast::reflect_view;
using quadcast::vec2;

TEST_CASE("reflect_view: unit length, angle of reflection = angle of incidence, in the plane of n and e (against long double)") {
    double worst_len = 0, worst_angle = 0, worst_plane = 0, worst_exact = 0;
    for (std::uint32_t it = 0; it < 200000; ++it) {
        auto rng = rng_for(91, it);
        // Any lengths (neither input need be unit), some grazing views.
        const Vec3<double> nd = random_dir(rng) * std::exp(uniform(rng, -5, 5));
        Vec3<double> ed = random_dir(rng);
        if (it % 4 == 0) ed = normalize(ed - nd * (dot(ed, nd) / dot(nd, nd)) + nd * (1e-3 / std::sqrt(dot(nd, nd))));
        ed = ed * std::exp(uniform(rng, -5, 5));
        const Vec3<float> n = cast<float>(nd), e = cast<float>(ed);
        const Vec3<float> r = reflect_view(n, e);
        // Exact reflection of the float inputs in long double (two-sided: n flipped towards e).
        V3 nl = ld(n), el = ld(e);
        nl = nl * (LD(1) / norm_ld(nl));
        el = el * (LD(1) / norm_ld(el));
        if (dot_ld(nl, el) < 0) nl = -nl;
        const V3 rx = nl * (LD(2) * dot_ld(nl, el)) - el;
        const V3 rl = ld(r);
        const LD len = norm_ld(rl);
        // Angle of incidence (between e and n) vs angle of reflection (between r and n), as cosines.
        const LD cos_in = dot_ld(el, nl), cos_out = dot_ld(rl, nl) / len;
        // r lies in the plane of n and e: its component along n x e vanishes.
        const V3 ax = quadcast::cross(nl, el);
        const LD axl = norm_ld(ax);
        worst_len = std::max(worst_len, double(std::fabs(len - 1)));
        worst_angle = std::max(worst_angle, double(std::fabs(cos_in - cos_out)));
        if (axl > 1e-3L) worst_plane = std::max(worst_plane, double(std::fabs(dot_ld(rl, ax) / axl)));
        worst_exact = std::max(worst_exact, double(norm_ld(rl - rx)));
    }
    std::printf("[reflect_view] max | |r| - 1 | %.3g, max |cos in - cos out| %.3g, max out of plane %.3g, max |r - exact| %.3g\n",
                worst_len, worst_angle, worst_plane, worst_exact);
    // A few float roundings of unit-size quantities (eps = 6e-8).
    CHECK(worst_len < 1e-6);
    CHECK(worst_angle < 1e-6);
    CHECK(worst_plane < 1e-6);
    CHECK(worst_exact < 1e-6);
}

TEST_CASE("atan2_poly is within 1.5e-5 rad of atan2 over every octant, exact on the axes") {
    double worst = 0;
    for (std::uint32_t it = 0; it < 200000; ++it) {
        auto rng = rng_for(92, it);
        const float y = static_cast<float>(uniform(rng, -1, 1) * std::exp(uniform(rng, -10, 10)));
        const float x = static_cast<float>(uniform(rng, -1, 1) * std::exp(uniform(rng, -10, 10)));
        const long double exact = std::atan2(static_cast<long double>(y), static_cast<long double>(x));
        worst = std::max(worst, double(std::fabs(atan2_poly(y, x) - exact)));
    }
    std::printf("[atan2_poly] max error %.3g rad\n", worst);
    CHECK(worst < 1.5e-5);  // 1e-5 (Abramowitz and Stegun) plus float rounding
    CHECK(atan2_poly(0.0f, 1.0f) == 0.0f);
    CHECK(atan2_poly(0.0f, 0.0f) == 0.0f);
    CHECK(std::fabs(atan2_poly(1.0f, 0.0f) - 1.5707964f) == 0.0f);
    CHECK(std::fabs(atan2_poly(0.0f, -1.0f) - 3.1415927f) == 0.0f);
}

TEST_CASE("latlong_texel: the view direction at the centre column, up at the top row, +x to the right") {
    const auto size = vec2(1024.0f, 512.0f);
    const auto ahead = latlong_texel(vec3(0.0f, 0.0f, -1.0f), size);
    CHECK(ahead[0] == doctest::Approx(511.5).epsilon(1e-6));
    CHECK(ahead[1] == doctest::Approx(255.5).epsilon(1e-6));
    CHECK(latlong_texel(vec3(0.0f, 1.0f, 0.0f), size)[1] == doctest::Approx(-0.5).epsilon(1e-5));
    CHECK(latlong_texel(vec3(0.0f, -2.0f, 0.0f), size)[1] == doctest::Approx(511.5).epsilon(1e-5));
    CHECK(latlong_texel(vec3(1.0f, 0.0f, 0.0f), size)[0] == doctest::Approx(767.5).epsilon(1e-5));
    CHECK(latlong_texel(vec3(-1.0f, 0.0f, 0.0f), size)[0] == doctest::Approx(255.5).epsilon(1e-5));
}

TEST_CASE("reflect_environment: a uniform environment gives its colour, reflectivity 0 the shaded colour, columns wrap") {
    EnvironmentMap env;
    env.width = 8;
    env.height = 4;
    env.rgb.assign(8 * 4 * 3, 0.25f);
    const Vec3<float> rgb = vec3(0.8f, 0.1f, 0.3f);
    for (std::uint32_t it = 0; it < 10000; ++it) {
        auto rng = rng_for(93, it);
        const Vec3<float> n = cast<float>(random_dir(rng)), e = cast<float>(random_dir(rng));
        const Vec3<float> a = reflect_environment(env, rgb, n, e, 1.0f), b = reflect_environment(env, rgb, n, e, 0.0f);
        for (int k = 0; k < 3; ++k) {
            REQUIRE(a[k] == 0.25f);
            REQUIRE(b[k] == rgb[k]);
        }
    }
    // Behind the viewer (azimuth +-pi) the lookup blends the last and the first column.
    for (int j = 0; j < 4; ++j) {
        env.rgb[(std::size_t(j) * 8 + 0) * 3] = 1.0f;
        env.rgb[(std::size_t(j) * 8 + 7) * 3] = 1.0f;
    }
    // n = +z, e = +z: the reflection is +z, straight behind.
    const Vec3<float> behind = reflect_environment(env, rgb, vec3(0.0f, 0.0f, 1.0f), vec3(0.0f, 0.0f, 1.0f), 1.0f);
    CHECK(behind[0] == doctest::Approx(1.0).epsilon(1e-4));
}

TEST_CASE("procedural_environment: sky above, ground below, in [0, 1]") {
    const EnvironmentMap env = procedural_environment({}, 64, 32);
    REQUIRE(env.rgb.size() == std::size_t(64 * 32 * 3));
    for (float c : env.rgb) REQUIRE((c >= 0.0f && c <= 1.0f));
    const ProceduralSky sky;
    // Top row: near the zenith colour (blue), bottom row: the ground (darker than the horizon).
    CHECK(env.rgb[2] > env.rgb[0]);
    CHECK(std::fabs(env.rgb[2] - sky.zenith[2]) < 0.05f);
    const float* bottom = &env.rgb[(std::size_t(31) * 64) * 3];
    CHECK(bottom[0] < sky.horizon[0]);
}
