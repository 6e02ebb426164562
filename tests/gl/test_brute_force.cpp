// tests/gl/test_brute_force.cpp -- the brute-force and pass-through fragment stages (quadcast bench fragments)
#include <doctest/doctest.h>

#include <cmath>
#include <cstdio>
#include <random>

#include "quadcast/gl/osmesa_context.hpp"
#include "quadcast/gl/quadric_renderer.hpp"
#include "render/render_testing.hpp"

using namespace quadcast;
using namespace quadcast::render;

TEST_CASE("the brute-force fragment stage renders the image of the incremental one") {
    using Stage = gl::QuadricRenderer::FragmentStage;
    gl::OsmesaContext ctx;
    gl::QuadricRenderer r(ctx.api());
    // The brute-force stage has no sphere variant: the scene's spheres go through the ellipsoid one.
    std::vector<Primitive> prims = qc_render_test::mixed_scene(5, {60, 30, 10, false, false});
    for (Primitive& p : prims)
        if (p.variant == Variant::sphere) p.variant = Variant::ellipsoid;
    r.set_primitives(prims);
    Light light;
    light.direction = vec3(-0.4f, -0.6f, -1.0f);
    const Camera cam = qc_render_test::look_at(vec3(0.5, 1.0, 8.0), vec3(0.0, 0.0, 0.0), vec3(0.0, 1.0, 0.0), qc_render_test::perspective(50, 240.0 / 180.0, 1, 20));
    for (bool cull : {true, false}) {
        RenderOptions o;
        o.occlusion_min_overlap = 0.0f;  // (the cull pass and its indirect draws with both fragment stages, however sparse the scene)
        o.width = 240;
        o.height = 180;
        o.culling = cull;
        r.set_fragment_stage(Stage::incremental);
        r.draw(cam, light, o);
        const Image a = r.read();
        r.set_fragment_stage(Stage::brute_force);
        r.draw(cam, light, o);
        const Image b = r.read();
        long covered = 0, coverage_diff = 0, same_colour = 0, both = 0;
        double max_depth = 0;
        for (std::size_t i = 0; i < a.depth.size(); ++i) {
            const bool ca = a.depth[i] < 1.0f, cb = b.depth[i] < 1.0f;
            covered += ca;
            if (ca != cb) { ++coverage_diff; continue; }
            if (!ca) continue;
            ++both;
            max_depth = std::max(max_depth, static_cast<double>(std::fabs(a.depth[i] - b.depth[i])));
            bool ok = true;
            for (int c = 0; c < 3; ++c) ok = ok && std::abs(int(a.rgba[i * 4 + c]) - int(b.rgba[i * 4 + c])) <= 1;
            same_colour += ok;
        }
        std::printf("[brute vs incremental] culling %s: %ld covered px, %ld coverage differences, %ld of %ld within 1 LSB, max depth difference %.3g\n",
                    cull ? "on" : "off", covered, coverage_diff, same_colour, both, max_depth);
        CHECK(covered > 5000);
        CHECK(static_cast<double>(coverage_diff) <= 0.005 * static_cast<double>(covered));
        CHECK(static_cast<double>(same_colour) >= 0.99 * static_cast<double>(both));
        CHECK(max_depth < 1e-4);
    }
}

TEST_CASE("the pass-through fragment stage fills every bounding quad and counts its fragments") {
    using Stage = gl::QuadricRenderer::FragmentStage;
    gl::OsmesaContext ctx;
    gl::QuadricRenderer r(ctx.api());
    r.set_primitives(qc_render_test::mixed_scene(6, {60, 30, 10, false, false}));
    Light light;
    const Camera cam = qc_render_test::look_at(vec3(0.5, 1.0, 8.0), vec3(0.0, 0.0, 0.0), vec3(0.0, 1.0, 0.0), qc_render_test::perspective(50, 240.0 / 180.0, 1, 20));
    RenderOptions o;
    o.width = 240;
    o.height = 180;
    o.culling = false;
    // Coverage with the depth test on (it is what writes depth); counts with it off.
    r.set_fragment_stage(Stage::incremental);
    r.draw(cam, light, o);
    const Image a = r.read();
    r.set_fragment_stage(Stage::passthrough);
    r.draw(cam, light, o);
    const Image b = r.read();
    r.set_depth_test(false);
    r.draw(cam, light, o);
    const std::uint64_t frags = r.samples_passed();
    r.set_fragment_stage(Stage::incremental);
    r.draw(cam, light, o);
    const std::uint64_t hits = r.samples_passed();
    r.set_depth_test(true);
    long covered_a = 0, covered_b = 0, missing = 0;
    for (std::size_t i = 0; i < a.depth.size(); ++i) {
        covered_a += a.depth[i] < 1.0f;
        covered_b += b.depth[i] < 1.0f;
        missing += a.depth[i] < 1.0f && !(b.depth[i] < 1.0f);
    }
    std::printf("[pass-through] %llu fragments (%llu hit), %ld px covered by quads, %ld by quadrics\n",
                static_cast<unsigned long long>(frags), static_cast<unsigned long long>(hits), covered_b, covered_a);
    CHECK(missing == 0);              // every quadric pixel lies in a bounding quad
    CHECK(covered_b > covered_a);     // quads cover more than the quadrics
    CHECK(frags > hits);
    CHECK(hits >= static_cast<std::uint64_t>(covered_a));  // overlapping hits count more than once
    CHECK(frags >= static_cast<std::uint64_t>(covered_b));
}
