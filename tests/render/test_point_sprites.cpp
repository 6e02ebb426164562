// tests/render/test_point_sprites.cpp -- the sphere variant's point sprites: every pixel the cast hits lies
// inside its sprite, and `sphere_points_fit` admits only frames where every sprite is drawable
//
// The GL renderer draws a sphere as one point sprite (`point_sprite` of the grown bounding quad's
// clip-space corners, traced into its vertex stage) where `render::sphere_points_fit` holds for the
// frame. GL clips a point by its centre, and a sprite is at most GL_POINT_SIZE_RANGE's largest size,
// so a frame it admits must have, for every sphere: a valid quad with its corners in front of the eye,
// the sprite's centre inside the view, and its size within the limit. The checks run the float
// templates as the vertex stage does and measure in double, independently of the fit's own bound.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>

#include "quadcast/bounds.hpp"
#include "quadcast/camera.hpp"
#include "quadcast/render/cpu_renderer.hpp"
#include "quadcast/render/point_sprites.hpp"
#include "render_testing.hpp"

using namespace quadcast;

namespace {

struct Sprite {
    bool drawable = false;  ///< a valid quad with every corner in front of the eye
    double cx = 0, cy = 0;  ///< centre, window pixels
    double ndc_x = 0, ndc_y = 0;
    double size = 0;        ///< pixels
};

/// The sprite of sphere (c, r) as the vertex stage computes it (float templates), in window pixels.
Sprite sprite_of(const render::Camera& cam, const Vec3<float>& centre, float r, int w, int h) {
    Sprite s;
    const Vec3<float> c = xyz(cam.view * vec4(centre, 1.0f));
    SphereQuad<float> sq = cam.orthographic ? ortho_sphere_square(c, r) : sphere_quad(c, r);
    sq = rasterised_sphere_quad(sq, c);
    if (!sq.valid) return s;
    Vec4<float> q[4];
    for (int k = 0; k < 4; ++k) {
        q[k] = clip_position(cam.projection, sq.corner[k]);
        if (!(q[k][3] > 0.0f)) return s;
    }
    Vec2<float> ndc{};
    float size = 0.0f;
    point_sprite(q[0], q[1], q[2], q[3], vec2(float(w), float(h)), ndc, size);
    s.drawable = true;
    s.ndc_x = ndc[0];
    s.ndc_y = ndc[1];
    s.cx = (double(ndc[0]) + 1) * 0.5 * w;
    s.cy = (double(ndc[1]) + 1) * 0.5 * h;
    s.size = size;
    return s;
}

render::Camera random_camera(std::mt19937& rng, bool ortho, int w, int h) {
    std::uniform_real_distribution<double> u(0.0, 1.0);
    render::Camera cam;
    const Vec3<double> eye = vec3(u(rng) * 4 - 2, u(rng) * 4 - 2, 5.0 + u(rng) * 5);
    cam.view = cast<float>(look_at(eye, vec3(0.0, 0.0, 0.0), vec3(0.0, 1.0, 0.0)));
    cam.projection = ortho ? cast<float>(orthographic(4.5, double(w) / h, 0.5, 30.0)) : cast<float>(perspective(20.0 + 60.0 * u(rng), double(w) / h, 0.5, 30.0));
    cam.eye = cast<float>(eye);
    cam.orthographic = ortho;
    return cam;
}

}  // namespace

TEST_CASE("a point sprite holds every pixel the cast hits, by 1/8 pixel") {
    // As the sphere quad test (test_sphere_quad_raster.cpp): random spheres of radius 10^-2.5 ..
    // 10^-0.5 in [-2, 2]^3, 6 random perspective (20-80 degrees) and 6 orthographic cameras at
    // 1024x768, every pixel around each sprite cast with the fragment stage's template.
    const int w = 1024, h = 768;
    for (bool ortho : {false, true}) {
        std::mt19937 rng(ortho ? 81u : 80u);
        std::uniform_real_distribution<float> u(0.0f, 1.0f);
        long hits = 0, below = 0, sprites = 0;
        double worst = 1e300;
        for (int ci = 0; ci < 6; ++ci) {
            const render::Camera cam = random_camera(rng, ortho, w, h);
            const render::FrameSetup f = render::frame_setup(cam, w, h);
            for (int si = 0; si < 1500; ++si) {
                const float r = std::pow(10.0f, -2.5f + 2.0f * u(rng));
                const render::Primitive p = qc_render_test::sphere(vec3(u(rng) * 4 - 2, u(rng) * 4 - 2, u(rng) * 4 - 2), r);
                const Sprite s = sprite_of(cam, p.shape.center, r, w, h);
                if (!s.drawable || s.size > 150) continue;
                ++sprites;
                const double half = s.size * 0.5;
                for (int y = std::max(0, int(std::floor(s.cy - half)) - 2); y <= std::min(h - 1, int(std::ceil(s.cy + half)) + 2); ++y)
                    for (int x = std::max(0, int(std::floor(s.cx - half)) - 2); x <= std::min(w - 1, int(std::ceil(s.cx + half)) + 2); ++x) {
                        if (!render::cast_fragment(p, render::pixel_ray(f, x, y), f, true).hit) continue;
                        ++hits;
                        const double margin = half - std::max(std::fabs(x + 0.5 - s.cx), std::fabs(y + 0.5 - s.cy));
                        worst = std::min(worst, margin);
                        below += margin < 0.125 - 1e-4;
                    }
            }
        }
        std::printf("[point sprites] %s: %ld sprites, %ld hit pixels, %ld within 1/8 px of the sprite's edge, smallest margin %.4f px\n",
                    ortho ? "orthographic" : "perspective", sprites, hits, below, worst);
        CHECK(hits > 1000000);
        CHECK(below == 0);
        CHECK(worst >= 0.125 - 1e-4);
    }
}

TEST_CASE("sphere_points_fit admits only frames whose every sphere has a drawable sprite inside the view") {
    // Random boxes of centres and radii seen by random cameras. Where the fit holds, spheres
    // sampled in the box (its corners, its centre and random points; radius the largest or
    // random below it) must each have a valid quad in front of the eye, a sprite centre inside
    // NDC [-1, 1] and a sprite no larger than the limit.
    const int w = 1024, h = 768;
    for (bool ortho : {false, true}) {
        std::mt19937 rng(ortho ? 91u : 90u);
        std::uniform_real_distribution<float> u(0.0f, 1.0f);
        int frames = 0, admitted = 0;
        long checked = 0, bad = 0;
        double largest = 0.0, extreme_ndc = 0.0;
        for (int ci = 0; ci < 400; ++ci) {
            const render::Camera cam = random_camera(rng, ortho, w, h);
            const Vec3<float> a = vec3(u(rng) * 4 - 2, u(rng) * 4 - 2, u(rng) * 4 - 2);
            const float extent = std::pow(10.0f, -2.0f + 2.3f * u(rng));
            const Vec3<float> lo = a - vec3(extent, extent, extent) * u(rng), hi = a + vec3(extent, extent, extent) * u(rng);
            const float radius = std::pow(10.0f, -3.0f + 2.5f * u(rng));
            const float max_size = u(rng) < 0.5f ? 255.0f : 8.0f + 64.0f * u(rng);
            ++frames;
            if (!render::sphere_points_fit(cam, w, h, lo, hi, radius, max_size)) continue;
            ++admitted;
            for (int si = 0; si < 60; ++si) {
                Vec3<float> c;
                for (int i = 0; i < 3; ++i) {
                    const float t = si < 8 ? float((si >> i) & 1) : si == 8 ? 0.5f : u(rng);
                    c[i] = lo[i] + (hi[i] - lo[i]) * t;
                }
                const float r = si % 2 == 0 ? radius : radius * u(rng);
                const Sprite s = sprite_of(cam, c, r, w, h);
                ++checked;
                const bool ok = s.drawable && std::fabs(s.ndc_x) < 1.0 && std::fabs(s.ndc_y) < 1.0 && s.size <= double(max_size);
                bad += !ok;
                if (s.drawable) {
                    largest = std::max(largest, s.size / double(max_size));
                    extreme_ndc = std::max({extreme_ndc, std::fabs(s.ndc_x), std::fabs(s.ndc_y)});
                }
            }
        }
        std::printf("[point sprites] %s: %d of %d frames admitted; %ld spheres checked, %ld not drawable as sprites; "
                    "largest sprite %.3f of the limit, farthest centre %.4f NDC\n",
                    ortho ? "orthographic" : "perspective", admitted, frames, checked, bad, largest, extreme_ndc);
        CHECK(admitted >= frames / 5);
        CHECK(admitted < frames);
        CHECK(bad == 0);
    }
}

TEST_CASE("sphere_points_fit refuses spheres across the view's edge, behind the near plane, too large, or none") {
    const int w = 400, h = 300;
    const render::Camera cam = qc_render_test::look_at(vec3(0.0, 0.0, 10.0), vec3(0.0, 0.0, 0.0), vec3(0.0, 1.0, 0.0), qc_render_test::perspective(30, 4.0 / 3.0, 1, 50));
    const Vec3<float> o = vec3(0.0f, 0.0f, 0.0f);
    CHECK(render::sphere_points_fit(cam, w, h, o, o, 0.5f, 255.0f));
    // The view's half height at the origin is 10 tan 15 deg = 2.68: a sphere at y = 2.5 of radius 0.5 crosses the edge
    CHECK_FALSE(render::sphere_points_fit(cam, w, h, o, vec3(0.0f, 2.5f, 0.0f), 0.5f, 255.0f));
    // Reaching to the near plane (view distance 1)
    CHECK_FALSE(render::sphere_points_fit(cam, w, h, o, vec3(0.0f, 0.0f, 8.8f), 0.1f, 255.0f));
    // A sprite larger than the limit: radius 0.5 at distance 10 is about 2 * 0.5 / 10 / (2 tan 15 deg) * 300 = 56 pixels
    CHECK_FALSE(render::sphere_points_fit(cam, w, h, o, o, 0.5f, 40.0f));
    CHECK(render::sphere_points_fit(cam, w, h, o, o, 0.5f, 130.0f));  // (the fit bounds the sprite by 113 pixels: a ball of 1.5 r, conservative)
    // No spheres (an empty box), or no point sizes
    CHECK_FALSE(render::sphere_points_fit(cam, w, h, vec3(1.0f, 0.0f, 0.0f), o, 0.5f, 255.0f));
    CHECK_FALSE(render::sphere_points_fit(cam, w, h, o, o, 0.5f, 1.0f));
}
