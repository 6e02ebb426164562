// tests/gl/test_sphere_variant.cpp -- the sphere-specialised variant: GL against the CPU reference and against the general variant
#include <doctest/doctest.h>

#include <cmath>
#include <cstdio>
#include <random>

#include "quadcast/gl/osmesa_context.hpp"
#include "quadcast/gl/quadric_renderer.hpp"
#include "quadcast/render/cpu_renderer.hpp"
#include "quadcast/render/point_sprites.hpp"
#include "render/render_testing.hpp"

using namespace quadcast;
using namespace quadcast::render;

namespace {

/// n random spheres in [-2, 2]^3 (radius 0.05 to 0.6, overlapping), as the sphere or the closed variant.
std::vector<render::Primitive> random_spheres(unsigned seed, int n, Variant variant) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(-2.0f, 2.0f), s(0.05f, 0.6f), c(0.1f, 1.0f);
    std::vector<render::Primitive> out;
    for (int i = 0; i < n; ++i) {
        const Vec3<float> p = vec3(u(rng), u(rng), u(rng));
        const float r = s(rng);
        render::Primitive sp = qc_render_test::sphere(p, r, vec3(c(rng), c(rng), c(rng)));
        sp.variant = variant;
        out.push_back(sp);
    }
    return out;
}

}  // namespace

TEST_CASE("sphere variant: the GL renderer draws what the CPU reference draws, and what the general variant draws") {
    gl::OsmesaContext ctx;
    gl::QuadricRenderer sphere_r(ctx.api()), closed_r(ctx.api());
    const std::vector<render::Primitive> spheres = random_spheres(21, 300, Variant::sphere), closed = random_spheres(21, 300, Variant::ellipsoid);
    sphere_r.set_primitives(spheres);
    closed_r.set_primitives(closed);
    Light light;
    light.direction = vec3(-0.4f, -0.6f, -1.0f);
    for (bool ortho : {false, true})
        for (bool cull : {true, false})
            for (bool deferred : {false, true}) {
                RenderOptions o;
                o.width = 320;
                o.height = 240;
                o.culling = cull;
                o.deferred = deferred;
                const Camera cam = ortho ? qc_render_test::look_at(vec3(0.5, 1.0, 8.0), vec3(0.0, 0.0, 0.0), vec3(0.0, 1.0, 0.0), qc_render_test::orthographic(-4, 4, -3, 3, 1, 20), true)
                                         : qc_render_test::look_at(vec3(0.5, 1.0, 8.0), vec3(0.0, 0.0, 0.0), vec3(0.0, 1.0, 0.0), qc_render_test::perspective(50, 320.0 / 240.0, 1, 20));
                sphere_r.draw(cam, light, o);
                const Image g = sphere_r.read();
                closed_r.draw(cam, light, o);
                const Image gc = closed_r.read();
                const Image c = render_cpu(spheres, cam, light, o);
                const qc_render_test::ImageDiff d = qc_render_test::image_diff(g, c, 1), dv = qc_render_test::image_diff(g, gc);
                std::printf("[sphere variant] %s, culling %s, %s: %ld covered px; GL vs CPU: %ld coverage differences, %ld px > 1 LSB (max %d), "
                            "max depth difference %.3g; vs the closed variant: %ld coverage differences, max %d LSB\n",
                            ortho ? "orthographic" : "perspective", cull ? "on" : "off", deferred ? "deferred" : "forward", d.covered,
                            d.coverage_diff, d.color_diff, d.max_lsb, d.max_depth, dv.coverage_diff, dv.max_lsb);
                CHECK(d.covered > 20000);
                CHECK(d.coverage_diff == 0);
                CHECK(d.color_diff <= d.covered / 1000);
                CHECK(d.max_depth < 1e-5);
                CHECK(dv.coverage_diff <= d.covered / 1000);
            }
}

TEST_CASE("sphere variant: an eye inside a sphere sees its inside only with culling off") {
    gl::OsmesaContext ctx;
    gl::QuadricRenderer r(ctx.api());
    render::Primitive big = qc_render_test::sphere(vec3(0.0f, 0.0f, 0.0f), 3.0f);
    big.variant = Variant::sphere;
    r.set_primitives({big});
    Light light;
    light.direction = vec3(-0.4f, -0.6f, -1.0f);
    const Camera cam = qc_render_test::look_at(vec3(0.5, 0.2, 1.0), vec3(0.0, 0.0, -1.0), vec3(0.0, 1.0, 0.0), qc_render_test::perspective(50, 4.0 / 3.0, 0.1, 20));
    for (bool cull : {true, false}) {
        RenderOptions o;
        o.width = 160;
        o.height = 120;
        o.culling = cull;
        r.draw(cam, light, o);
        const Image g = r.read();
        const Image c = render_cpu(std::vector<render::Primitive>{big}, cam, light, o);
        const qc_render_test::ImageDiff d = qc_render_test::image_diff(g, c, 1);
        CHECK(d.covered == (cull ? 0 : 160 * 120));
        CHECK(d.coverage_diff == 0);
    }
}

TEST_CASE("sphere variant: no edge pixel is lost: 10k random spheres at 1024x768 as the CPU reference draws them") {
    // The scene of `quadcast bench spheres` (10k). Before the bounding quads were grown for the
    // rasteriser (`rasterised_sphere_quad`) one pixel, whose centre lies 6e-5 pixel inside the exact
    // quad, was lost to llvmpipe's sub-pixel snapping and showed the sphere behind.
    gl::OsmesaContext ctx;
    gl::QuadricRenderer r(ctx.api());
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> u(0.0f, 1.0f), c(0.2f, 1.0f);
    const int n = 10000;
    const float radius = 0.3f * std::pow(float(n), -1.0f / 3.0f);
    std::vector<render::Primitive> spheres;
    for (int i = 0; i < n; ++i) {
        const Vec3<float> p = vec3(u(rng), u(rng), u(rng));
        spheres.push_back(qc_render_test::sphere(p, radius, vec3(c(rng), c(rng), c(rng))));  // (the sphere variant)
    }
    r.set_primitives(spheres);
    const Camera cam = qc_render_test::look_at(vec3(0.5, 0.5, 3.0), vec3(0.5, 0.5, 0.5), vec3(0.0, 1.0, 0.0), qc_render_test::perspective(30, 1024.0 / 768.0, 1, 5));
    Light light;
    light.direction = vec3(-0.4f, -0.6f, -1.0f);
    RenderOptions o;
    o.occlusion_culling = false;
    r.draw(cam, light, o);
    const Image g = r.read();
    const Image cpu = render_cpu(spheres, cam, light, o);
    const qc_render_test::ImageDiff d = qc_render_test::image_diff(g, cpu, 1);
    long depth_diff = 0;
    for (std::size_t i = 0; i < g.depth.size(); ++i) depth_diff += g.depth[i] < 1.0f && g.depth[i] != cpu.depth[i];
    std::printf("[sphere variant] 10k spheres, 1024x768: %ld covered px; GL vs CPU: %ld coverage differences, %ld depth differences, %ld px > 1 LSB\n",
                d.covered, d.coverage_diff, depth_diff, d.color_diff);
    CHECK(d.covered > 400000);
    CHECK(d.coverage_diff == 0);
    CHECK(depth_diff == 0);
    CHECK(d.color_diff <= 10);
}

TEST_CASE("sphere variant: point sprites draw the picture quads draw, and only where every sphere fits") {
    // QuadricRenderer::set_point_sprites: one vertex per sphere (`quadcast::point_sprite`) where
    // render::sphere_points_fit holds for the frame, else quads. 4000 random spheres in the unit
    // cube (the scene of `bench spheres`, radius 0.3 N^(-1/3)) at 512x384: perspective and
    // orthographic, forward, deferred with shadows (the light's orthographic camera draws sprites
    // too) and silhouettes, without and with the cull pass (its indirect command then counts
    // points), three frames each (the third reuses the shown set); and a close-up whose spheres
    // cross the view's edges, which must draw quads. Against the same renderer with sprites off:
    // 0 coverage, colour and depth differences.
    gl::OsmesaContext ctx;
    gl::QuadricRenderer points_r(ctx.api()), quads_r(ctx.api());
    quads_r.set_point_sprites(false);
    // (the frames that draw the picture's records alone draw their spheres, not shading them from the ids target)
    points_r.set_reshade(false);
    quads_r.set_reshade(false);
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> u(0.0f, 1.0f), c(0.2f, 1.0f);
    const int n = 4000;
    const float radius = 0.3f * std::pow(float(n), -1.0f / 3.0f);
    std::vector<render::Primitive> spheres;
    for (int i = 0; i < n; ++i) spheres.push_back(qc_render_test::sphere(vec3(u(rng), u(rng), u(rng)), radius, vec3(c(rng), c(rng), c(rng))));
    points_r.set_primitives(spheres);
    quads_r.set_primitives(spheres);
    Light light;
    light.direction = vec3(-0.4f, -0.6f, -1.0f);
    struct View {
        const char* name;
        Camera cam;
        bool points;
    };
    const View views[] = {
        {"perspective", qc_render_test::look_at(vec3(0.5, 0.5, 3.0), vec3(0.5, 0.5, 0.5), vec3(0.0, 1.0, 0.0), qc_render_test::perspective(35, 4.0 / 3.0, 1, 5)), true},
        {"orthographic", qc_render_test::look_at(vec3(0.6, 0.4, 3.0), vec3(0.5, 0.5, 0.5), vec3(0.0, 1.0, 0.0), qc_render_test::orthographic(-0.9, 0.9, -0.7, 0.7, 1, 5), true), true},
        {"close-up across the edges", qc_render_test::look_at(vec3(0.5, 0.5, 1.6), vec3(0.5, 0.5, 0.5), vec3(0.0, 1.0, 0.0), qc_render_test::perspective(30, 4.0 / 3.0, 0.1, 5)), false},
    };
    long compared = 0;
    for (const View& v : views)
        for (int mode = 0; mode < 3; ++mode) {
            RenderOptions o;
            o.width = 512;
            o.height = 384;
            o.occlusion_culling = mode != 0;
            o.occlusion_min_overlap = 0.0f;  // (the cull pass in every frame)
            o.shadows = o.silhouettes = mode == 2;
            for (int frame = 0; frame < 3; ++frame) {
                points_r.draw(v.cam, light, o);
                quads_r.draw(v.cam, light, o);
                CHECK(points_r.drew_points() == v.points);
                CHECK_FALSE(quads_r.drew_points());
                const Image a = points_r.read(), b = quads_r.read();
                const qc_render_test::ImageDiff d = qc_render_test::image_diff(a, b);
                long depth_diff = 0;
                for (std::size_t i = 0; i < a.depth.size(); ++i) depth_diff += a.depth[i] != b.depth[i];
                if (frame == 2)
                    std::printf("[sphere variant] sprites against quads, %s, %s: %ld covered px, %ld coverage, %ld colour, %ld depth differences%s\n", v.name,
                                mode == 0 ? "no cull pass" : mode == 1 ? "cull pass" : "cull pass, deferred with shadows and silhouettes", d.covered, d.coverage_diff,
                                d.color_diff, depth_diff, points_r.reused_shown_set() ? " (shown set reused)" : "");
                CHECK(d.covered > 30000);
                CHECK(d.coverage_diff == 0);
                CHECK(d.color_diff == 0);
                CHECK(depth_diff == 0);
                compared += d.covered;
            }
        }
    CHECK(compared > 1000000);
    // A ball of 3000 spheres framed by the camera: the box of their centres reaches out of the view
    // (its corners), each sphere lies inside it (render::each_sphere_points_fit): sprites.
    std::vector<render::Primitive> ball;
    while (ball.size() < 3000) {
        const Vec3<float> p = vec3(u(rng) * 2 - 1, u(rng) * 2 - 1, u(rng) * 2 - 1);
        if (dot(p, p) <= 1.0f) ball.push_back(qc_render_test::sphere(p, 0.06f, vec3(c(rng), c(rng), c(rng))));
    }
    points_r.set_primitives(ball);
    quads_r.set_primitives(ball);
    const Camera framed = qc_render_test::look_at(vec3(0.0, 0.0, 4.6), vec3(0.0, 0.0, 0.0), vec3(0.0, 1.0, 0.0), qc_render_test::perspective(30, 4.0 / 3.0, 1, 10));
    const Vec3<float> corner = vec3(1.0f, 1.0f, 1.0f);
    CHECK_FALSE(render::sphere_points_fit(framed, 512, 384, -corner, corner, 0.06f, 255.0f));  // (the box does not fit)
    RenderOptions o;
    o.width = 512;
    o.height = 384;
    points_r.draw(framed, light, o);
    quads_r.draw(framed, light, o);
    CHECK(points_r.drew_points());
    const Image a = points_r.read(), b = quads_r.read();
    const qc_render_test::ImageDiff d = qc_render_test::image_diff(a, b);
    long depth_diff = 0;
    for (std::size_t i = 0; i < a.depth.size(); ++i) depth_diff += a.depth[i] != b.depth[i];
    std::printf("[sphere variant] sprites against quads, a ball of spheres framed by the camera: %ld covered px, %ld coverage, %ld colour, %ld depth differences\n",
                d.covered, d.coverage_diff, d.color_diff, depth_diff);
    CHECK(d.covered > 50000);
    CHECK(d.coverage_diff == 0);
    CHECK(d.color_diff == 0);
    CHECK(depth_diff == 0);
}
