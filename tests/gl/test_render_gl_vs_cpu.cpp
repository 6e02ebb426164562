// tests/gl/test_render_gl_vs_cpu.cpp -- the GL renderer against the CPU reference on mixed scenes
#include <doctest/doctest.h>

#include <cmath>
#include <cstdio>
#include <random>

#include "quadcast/gl/osmesa_context.hpp"
#include "quadcast/gl/quadric_renderer.hpp"
#include "quadcast/render/cpu_renderer.hpp"
#include "render/render_testing.hpp"

using namespace quadcast;
using namespace quadcast::render;

TEST_CASE("the GL renderer draws what the CPU reference draws") {
    gl::OsmesaContext ctx;
    gl::QuadricRenderer r(ctx.api());
    const std::vector<render::Primitive> prims = qc_render_test::mixed_scene(3, {60, 30, 10, false, true});
    r.set_primitives(prims);
    Light light;
    light.direction = vec3(-0.4f, -0.6f, -1.0f);
    for (bool ortho : {false, true})
        for (bool cull : {true, false}) {
            RenderOptions o;
            o.width = 240;
            o.height = 180;
            o.culling = cull;
            const Camera cam = ortho ? qc_render_test::look_at(vec3(0.5, 1.0, 8.0), vec3(0.0, 0.0, 0.0), vec3(0.0, 1.0, 0.0), qc_render_test::orthographic(-4, 4, -3, 3, 1, 20), true)
                                     : qc_render_test::look_at(vec3(0.5, 1.0, 8.0), vec3(0.0, 0.0, 0.0), vec3(0.0, 1.0, 0.0), qc_render_test::perspective(50, 240.0 / 180.0, 1, 20));
            r.draw(cam, light, o);
            const Image g = r.read();
            const Image c = render_cpu(prims, cam, light, o);
            const qc_render_test::ImageDiff d = qc_render_test::image_diff(g, c, 1);
            std::printf("[gl vs cpu] %s, culling %s: %ld covered px, %ld coverage differences, %ld colour differences > 1 LSB, max depth difference %.3g\n",
                        ortho ? "orthographic" : "perspective", cull ? "on" : "off", d.covered, d.coverage_diff, d.color_diff, d.max_depth);
            CHECK(d.covered > 5000);
            // Silhouette pixels may flip (interpolated rays differ from per-pixel rays by rounding).
            CHECK(d.coverage_diff <= d.covered / 200);
            CHECK(d.color_diff <= d.covered / 100);
            CHECK(d.max_depth < 1e-4);
        }
}
