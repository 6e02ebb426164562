// tests/gl/test_shapes_gl.cpp -- the GL renderer against the CPU reference on the public shapes:
// open and capped slabs, per-primitive materials (forward and deferred), twisted quads, and
// primitives whose bounding quad lies outside the depth range
#include <doctest/doctest.h>

#include <cmath>
#include <cstdio>
#include <random>

#include "quadcast/gl/osmesa_context.hpp"
#include "quadcast/gl/quadric_renderer.hpp"
#include "quadcast/render/cpu_renderer.hpp"
#include "quadcast/shapes.hpp"
#include "render/render_testing.hpp"

using namespace qc_render_test;
namespace shapes = quadcast::shapes;

namespace {

/// Open and capped cylinders and cones, spheres and ellipsoids with random materials, twisted quads.
std::vector<Primitive> shape_scene(unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(-2.0f, 2.0f), s(0.2f, 0.5f), c(0.1f, 1.0f), sp(0.0f, 1.0f), sh(2.0f, 200.0f);
    auto look = [&] { return shapes::Appearance{{c(rng), c(rng), c(rng)}, sp(rng), sh(rng)}; };
    auto point = [&] { return glm::vec3(u(rng), u(rng), u(rng)); };
    std::vector<Primitive> out;
    for (int i = 0; i < 20; ++i) out.push_back(shapes::sphere(point(), s(rng), look()));
    for (int i = 0; i < 24; ++i) {
        const glm::vec3 a = point();
        const glm::vec3 b = a + glm::vec3(u(rng), u(rng), u(rng)) * 0.5f;
        const shapes::Ends ends[4] = {shapes::Ends::both, shapes::Ends::none, shapes::Ends::first, shapes::Ends::second};
        if (i % 2) out.push_back(shapes::cylinder(a, b, 0.6f * s(rng), ends[(i / 2) % 4], look()));
        else out.push_back(shapes::cone(a, b, s(rng), (i / 2) % 2 == 0, look()));
    }
    for (int i = 0; i < 6; ++i) {
        const glm::vec3 m = point();
        const float k = 0.2f + 0.3f * float(i);
        out.push_back(shapes::quad(m + glm::vec3(-0.5f, -0.5f, k), m + glm::vec3(0.5f, -0.5f, -k), m + glm::vec3(0.5f, 0.5f, k), m + glm::vec3(-0.5f, 0.5f, -k), look()));
    }
    return out;
}

}  // namespace

TEST_CASE("GL draws the public shapes as the CPU reference does (caps, materials, twisted quads)") {
    quadcast::gl::OsmesaContext ctx;
    quadcast::gl::QuadricRenderer r(ctx.api());
    const std::vector<Primitive> prims = shape_scene(11);
    r.set_primitives(prims);
    Light light;
    light.direction = vec3(-0.4f, -0.6f, -1.0f);
    for (bool ortho : {false, true})
        for (bool deferred : {false, true}) {
            RenderOptions o;
            o.width = 240;
            o.height = 180;
            o.deferred = deferred;
            const Camera cam = ortho ? look_at(vec3(0.5, 1.0, 8.0), vec3(0.0, 0.0, 0.0), vec3(0.0, 1.0, 0.0), orthographic(-4, 4, -3, 3, 1, 20), true)
                                     : look_at(vec3(0.5, 1.0, 8.0), vec3(0.0, 0.0, 0.0), vec3(0.0, 1.0, 0.0), perspective(50, 240.0 / 180.0, 1, 20));
            r.draw(cam, light, o);
            const Image g = r.read();
            const Image c = render_cpu(prims, cam, light, o);
            const ImageDiff d = image_diff(c, g, 1);
            std::printf("[shapes gl vs cpu] %s, %s: %ld covered px, %ld coverage differences, %ld colour differences > 1 LSB, max depth difference %.3g\n",
                        ortho ? "orthographic" : "perspective", deferred ? "deferred" : "forward", d.covered, d.coverage_diff, d.color_diff, d.max_depth);
            CHECK(d.covered > 5000);
            CHECK(d.coverage_diff <= d.covered / 200);
            CHECK(d.color_diff <= d.covered / 100);
            CHECK(d.max_depth < 1e-4);
        }
}

TEST_CASE("primitives whose bounding quad lies beyond the far plane or before the near plane are drawn") {
    // A large sphere and a long cylinder cut by the far plane (their centres beyond it) and an
    // ellipsoid cut by the near plane, for both camera models: GL must cover what the CPU covers.
    quadcast::gl::OsmesaContext ctx;
    quadcast::gl::QuadricRenderer r(ctx.api());
    const std::vector<Primitive> prims = {
        shapes::sphere({0.0f, 0.0f, -5.0f}, 3.0f, {{0.8f, 0.3f, 0.2f}}),
        shapes::cylinder({-2.0f, 1.0f, -1.0f}, {1.5f, -1.0f, -14.0f}, 0.6f, shapes::Ends::both, {{0.2f, 0.6f, 0.9f}}),
        shapes::ellipsoid({1.5f, -0.5f, 3.0f}, glm::vec3(1.0f, 0.7f, 1.2f), glm::mat3(1.0f), {{0.4f, 0.8f, 0.3f}}),
    };
    r.set_primitives(prims);
    Light light;
    for (bool ortho : {false, true})
        for (bool cull : {true, false}) {
            RenderOptions o;
            o.width = 200;
            o.height = 160;
            o.culling = cull;
            // view z of the far plane -8: the sphere's centre is at -9, the cylinder's at -11.5; near -1.5:
            // the ellipsoid's centre is at -1 (it spans -2.2 .. 0.2)
            const Camera cam = ortho ? look_at(vec3(0.0, 0.0, 4.0), vec3(0.0, 0.0, 0.0), vec3(0.0, 1.0, 0.0), orthographic(-4, 4, -3.2, 3.2, 1.5, 8), true)
                                     : look_at(vec3(0.0, 0.0, 4.0), vec3(0.0, 0.0, 0.0), vec3(0.0, 1.0, 0.0), perspective(60, 1.25, 1.5, 8));
            r.draw(cam, light, o);
            const Image g = r.read();
            const Image c = render_cpu(prims, cam, light, o);
            const ImageDiff d = image_diff(c, g, 1);
            std::printf("[depth range] %s, culling %s: %ld covered px (CPU), %ld coverage differences, max depth difference %.3g\n",
                        ortho ? "orthographic" : "perspective", cull ? "on" : "off", d.covered, d.coverage_diff, d.max_depth);
            CHECK(d.covered > 3000);
            CHECK(d.coverage_diff <= 30);
            CHECK(d.max_depth < 1e-4);
        }
}

TEST_CASE("a hand-made primitive that cannot be drawn is rejected before upload") {
    quadcast::gl::OsmesaContext ctx;
    quadcast::gl::QuadricRenderer r(ctx.api());
    Primitive p = shapes::sphere({0, 0, 0}, 1.0f);
    p.shape.radius = std::nanf("");
    CHECK_THROWS_WITH_AS(r.set_primitives({shapes::sphere({2, 0, 0}, 1.0f), p}), doctest::Contains("primitive 1: radius must be positive and finite"),
                         std::invalid_argument);
    CHECK(r.primitive_count() == 0);
}
