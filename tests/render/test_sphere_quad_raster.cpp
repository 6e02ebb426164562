// tests/render/test_sphere_quad_raster.cpp -- every pixel the fragment stage's cast hits lies inside the
// rasterised bounding quad of its sphere by more than a rasteriser's sub-pixel snapping
//
// The GL vertex stage draws a sphere over `rasterised_sphere_quad` (traced as primitive_bound_*),
// and the fragment stage keeps the pixels whose float cast hits (`cast_fragment` here is the same
// template, bit-identical to GL by `quadcast verify`). A hit pixel centre outside the quad -- or so
// close to its edge that snapping the corners to 1/256 pixel moves it out -- is lost by the
// rasteriser while the CPU reference draws it. The margin of each hit centre to the quad's edges is
// measured in double from the float corners, as the rasteriser sees them.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>

#include "quadcast/bounds.hpp"
#include "quadcast/camera.hpp"
#include "quadcast/render/cpu_renderer.hpp"
#include "render_testing.hpp"

using namespace quadcast;

namespace {

struct Margins {
    long hits = 0, outside = 0, below = 0;  ///< hit pixels, outside the quad, within `min_margin` of its edge
    double worst = 1e300;                   ///< smallest margin, pixels (negative: outside)
};

/// Random spheres of radius 10^-2.5 .. 10^-0.5 in [-2, 2]^3 seen by `cameras` random cameras
/// (perspective 20-80 degrees or orthographic, 1024x768): the margins of the hit pixel centres to
/// the projected quad, with the pad of `rasterised_sphere_quad` or without it.
Margins measure(bool ortho, bool padded, int cameras, int spheres, double min_margin) {
    const int w = 1024, h = 768;
    std::mt19937 rng(ortho ? 71u : 70u);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    Margins m;
    for (int ci = 0; ci < cameras; ++ci) {
        render::Camera cam;
        const Vec3<double> eye = vec3(double(u(rng)) * 4 - 2, double(u(rng)) * 4 - 2, 5.0 + double(u(rng)) * 5);
        cam.view = cast<float>(look_at(eye, vec3(0.0, 0.0, 0.0), vec3(0.0, 1.0, 0.0)));
        cam.projection = ortho ? cast<float>(orthographic(4.5, double(w) / h, 0.5, 30.0)) : cast<float>(perspective(20.0 + 60.0 * double(u(rng)), double(w) / h, 0.5, 30.0));
        cam.eye = cast<float>(eye);
        cam.orthographic = ortho;
        const render::FrameSetup f = render::frame_setup(cam, w, h);
        for (int si = 0; si < spheres; ++si) {
            const float r = std::pow(10.0f, -2.5f + 2.0f * u(rng));
            const Vec3<float> centre = vec3(u(rng) * 4 - 2, u(rng) * 4 - 2, u(rng) * 4 - 2);
            const render::Primitive p = qc_render_test::sphere(centre, r);
            // The vertex stage's corners (primitive_bound_*): view-space centre, quad, clip positions, in float
            const Vec3<float> c = xyz(cam.view * vec4(p.shape.center, 1.0f));
            SphereQuad<float> sq = ortho ? ortho_sphere_square(c, r) : sphere_quad(c, r);
            if (padded) sq = rasterised_sphere_quad(sq, c);
            if (!sq.valid) continue;
            double wx[4], wy[4];
            bool in_front = true;
            for (int k = 0; k < 4; ++k) {
                const Vec4<float> q = clip_position(cam.projection, sq.corner[k]);
                in_front = in_front && q[3] > 0;
                wx[k] = (double(q[0]) / double(q[3]) + 1) * 0.5 * w;
                wy[k] = (double(q[1]) / double(q[3]) + 1) * 0.5 * h;
            }
            if (!in_front) continue;
            const double x0 = *std::min_element(wx, wx + 4), x1 = *std::max_element(wx, wx + 4);
            const double y0 = *std::min_element(wy, wy + 4), y1 = *std::max_element(wy, wy + 4);
            if (x1 - x0 > 150 || x0 < -10 || x1 > w + 10 || y0 < -10 || y1 > h + 10) continue;
            double area = 0;
            for (int k = 0; k < 4; ++k) area += wx[k] * wy[(k + 1) % 4] - wx[(k + 1) % 4] * wy[k];
            const double orient = area > 0 ? 1.0 : -1.0;
            // Every pixel around the quad: a hit must lie inside it
            for (int y = std::max(0, int(std::floor(y0)) - 2); y <= std::min(h - 1, int(std::ceil(y1)) + 2); ++y)
                for (int x = std::max(0, int(std::floor(x0)) - 2); x <= std::min(w - 1, int(std::ceil(x1)) + 2); ++x) {
                    if (!render::cast_fragment(p, render::pixel_ray(f, x, y), f, true).hit) continue;
                    ++m.hits;
                    double margin = 1e300;
                    for (int k = 0; k < 4; ++k) {
                        const int l = (k + 1) % 4;
                        const double ex = wx[l] - wx[k], ey = wy[l] - wy[k];
                        margin = std::min(margin, orient * (ex * (y + 0.5 - wy[k]) - ey * (x + 0.5 - wx[k])) / std::hypot(ex, ey));
                    }
                    m.worst = std::min(m.worst, margin);
                    m.outside += margin < 0;
                    m.below += margin < min_margin;
                }
        }
    }
    return m;
}

}  // namespace

TEST_CASE("the rasterised sphere quad holds every pixel the cast hits, by more than 1/128 pixel") {
    const double min_margin = 1.0 / 128;  // twice llvmpipe's sub-pixel snapping
    for (bool ortho : {false, true}) {
        const Margins padded = measure(ortho, true, 6, 1500, min_margin);
        const Margins exact = measure(ortho, false, 6, 1500, min_margin);
        std::printf("[sphere quad raster] %s: %ld hit pixels; padded quad: %ld outside, %ld within 1/128 px of an edge, smallest margin %.4f px; "
                    "exact quad (negative control): %ld within 1/128 px, smallest margin %.6f px\n",
                    ortho ? "orthographic" : "perspective", padded.hits, padded.outside, padded.below, padded.worst, exact.below, exact.worst);
        CHECK(padded.hits > 1000000);
        CHECK(padded.outside == 0);
        CHECK(padded.below == 0);
        // Without the pad, hit centres lie within snapping distance of the exact quad's edges
        CHECK(exact.below > 0);
        CHECK(exact.worst < 1.0 / 256);
    }
}

TEST_CASE("the rasterised sphere quad grows the half size by R/128 + |c|/32768 about the centre") {
    const Vec3<double> c = vec3(0.0, 0.0, -5.0);
    const SphereQuad<double> sq = sphere_quad(c, 3.0);  // R = 3.75
    const SphereQuad<double> g = rasterised_sphere_quad(sq, c);
    CHECK(g.valid);
    const double s = 1.0 + 1.0 / 128 + (5.0 / 32768) / 3.75;
    CHECK(g.half_size == doctest::Approx(3.75 * s).epsilon(1e-15));
    for (int k = 0; k < 4; ++k)
        for (int i = 0; i < 3; ++i) CHECK(g.corner[k][i] == doctest::Approx(c[i] + (sq.corner[k][i] - c[i]) * s).epsilon(1e-15));
    const SphereQuad<double> inside = rasterised_sphere_quad(sphere_quad(vec3(0.0, 0.0, -1.0), 2.0), vec3(0.0, 0.0, -1.0));
    CHECK_FALSE(inside.valid);
    CHECK(std::isfinite(inside.half_size));
}
