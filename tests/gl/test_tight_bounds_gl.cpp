// tests/gl/test_tight_bounds_gl.cpp -- the GL renderer draws the same image over tight screen
// rectangles as over bounding-sphere quads (forward and deferred, culling on and off, perspective
// and orthographic, eye inside bounds, near plane crossing), with fewer fragments
#include <doctest/doctest.h>

#include <cstdio>

#include "quadcast/gl/osmesa_context.hpp"
#include "quadcast/gl/quadric_renderer.hpp"
#include "quadcast/render/cpu_renderer.hpp"
#include "render/bounds_scenes.hpp"

using namespace qc_bounds_test;

TEST_CASE("tight bounds change no pixel of the GL renderer and rasterise fewer fragments") {
    gl::OsmesaContext ctx;
    gl::QuadricRenderer r(ctx.api());
    const bool stats = gl::has_extension(ctx.api(), "GL_ARB_pipeline_statistics_query");
    if (stats) r.set_count_fragments(true);
    const int w = 320, h = 240;
    Light light;
    light.direction = vec3(-0.4f, -0.6f, -1.0f);
    for (const BoundsScene& s : bounds_scenes(w, h)) {
        r.set_primitives(s.prims);
        for (bool cull : {true, false})
            for (bool deferred : {false, true}) {
                RenderOptions o;
                o.width = w;
                o.height = h;
                o.culling = cull;
                o.deferred = deferred;
                o.tight_bounds = true;
                // (every primitive drawn in both frames: with occlusion culling the second frame,
                // of the same view, would draw a smaller shown set alone)
                o.occlusion_culling = false;
                r.draw(s.camera, light, o);
                const Image tight = r.read();
                const std::uint64_t f_tight = r.fragment_invocations();
                o.tight_bounds = false;
                r.draw(s.camera, light, o);
                const Image sphere = r.read();
                const std::uint64_t f_sphere = r.fragment_invocations();
                const ImageDiff d = image_diff(tight, sphere);
                o.tight_bounds = true;
                const ImageDiff c = image_diff(tight, render_cpu(s.prims, s.camera, light, o));
                std::printf("[gl tight bounds] %s, culling %s, %s: %ld covered px, %ld coverage / %ld colour / %ld depth differences; "
                            "fragment shader invocations %llu -> %llu; against the CPU reference %ld coverage / %ld colour differences\n",
                            s.name.c_str(), cull ? "on" : "off", deferred ? "deferred" : "forward", d.covered, d.coverage_diff, d.color_diff, d.depth_diff,
                            static_cast<unsigned long long>(f_sphere), static_cast<unsigned long long>(f_tight), c.coverage_diff, c.color_diff);
                CAPTURE(s.name);
                CHECK(d.covered > 1000);
                CHECK(d.coverage_diff == 0);
                CHECK(d.color_diff == 0);
                CHECK(d.depth_diff == 0);
                if (stats) CHECK(f_tight < f_sphere);
            }
    }
}
