// tests/gl/test_fragment_counts.cpp -- the fragments the quadric pass counts one by one
// (QuadricRenderer::fragment_counts) against independent counts: the hits of lone primitives
// against the pixels whose rays meet them in the CPU reference, the started fragments against the
// rasteriser's own count of the same bounds (GL_SAMPLES_PASSED of a pass-through frame, depth test
// off); with the early discard, fewer cast than start in a dense scene, and the counting stages
// change no pixel
#include <doctest/doctest.h>

#include <cstdio>
#include <random>
#include <vector>

#include "quadcast/gl/osmesa_context.hpp"
#include "quadcast/gl/quadric_renderer.hpp"
#include "quadcast/render/cpu_renderer.hpp"
#include "core/param_test_util.hpp"
#include "render/bounds_scenes.hpp"

using namespace qc_bounds_test;

namespace {

long covered(const Image& im) {
    long n = 0;
    for (float d : im.depth) n += d < 1.0f;
    return n;
}

/// Rasterised fragments of the same frame's bounds, counted by GL (pass-through stage, no depth test).
std::uint64_t rasterised(gl::QuadricRenderer& r, const Camera& cam, const Light& light, RenderOptions o) {
    r.set_fragment_stage(gl::QuadricRenderer::FragmentStage::passthrough);
    r.set_depth_test(false);
    o.deferred = false;
    r.draw(cam, light, o);
    const std::uint64_t n = r.samples_passed();
    r.set_depth_test(true);
    r.set_fragment_stage(gl::QuadricRenderer::FragmentStage::incremental);
    return n;
}

}  // namespace

TEST_CASE("fragment counts: a lone primitive's hits are the pixels whose rays meet it, its started fragments what the rasteriser drew") {
    gl::OsmesaContext ctx;
    if (!gl::has_extension(ctx.api(), "GL_ARB_pipeline_statistics_query")) return;
    const int w = 320, h = 240;
    const Camera cam = qc_render_test::look_at(vec3(0.3, 0.2, 4.0), vec3(0.0, 0.0, 0.0), vec3(0.0, 1.0, 0.0), qc_render_test::perspective(35, double(w) / h, 1, 10));
    Light light;
    light.direction = vec3(-0.4f, -0.6f, -1.0f);
    const shapes::Appearance look{{0.8f, 0.5f, 0.3f}, 0.35f, 48.0f};
    const std::vector<std::pair<const char*, Primitive>> lone = {
        {"sphere variant", shapes::sphere(glm::vec3(0.2f, -0.1f, 0.0f), 0.7f, look)},
        {"ellipsoid", shapes::ellipsoid(glm::vec3(0.0f), glm::vec3(0.9f, 0.5f, 0.6f), glm::mat3(glm::rotate(glm::mat4(1.0f), 0.7f, glm::vec3(0.3f, 1.0f, 0.2f))), look)},
        {"capped cylinder", shapes::cylinder(glm::vec3(-0.8f, -0.3f, 0.0f), glm::vec3(0.7f, 0.4f, 0.2f), 0.3f, shapes::Ends::both, look)},
    };
    gl::QuadricRenderer r(ctx.api());
    for (const auto& [name, p] : lone)
        for (bool deferred : {false, true}) {
            r.set_primitives({p});
            RenderOptions o;
            o.width = w;
            o.height = h;
            o.deferred = deferred;
            r.draw(cam, light, o);
            const Image plain = r.read();
            r.set_count_fragments(true);
            r.draw(cam, light, o);
            r.set_count_fragments(false);
            const Image counted = r.read();
            const gl::FragmentCounts c = r.fragment_counts();
            const long cpu = covered(render_cpu({p}, cam, light, o));
            const std::uint64_t raster = rasterised(r, cam, light, o);
            std::printf("[fragment counts] %s, %s: %llu invocations, %llu started, %llu cast, %llu hit; rasterised %llu, CPU reference covers %ld\n", name,
                        deferred ? "deferred" : "forward", static_cast<unsigned long long>(c.invocations), static_cast<unsigned long long>(c.started),
                        static_cast<unsigned long long>(c.cast), static_cast<unsigned long long>(c.hit), static_cast<unsigned long long>(raster), cpu);
            CAPTURE(name);
            CAPTURE(deferred);
            CHECK(cpu > 5000);
            CHECK(c.hit == static_cast<std::uint64_t>(cpu));  // one fragment per pixel the ray meets
            CHECK(c.started == raster);
            CHECK(c.cast == c.started);  // (nothing to discard without a cull pass)
            CHECK(c.invocations >= c.started);
            const ImageDiff d = image_diff(plain, counted);
            CHECK(d.coverage_diff == 0);
            CHECK(d.color_diff == 0);
            CHECK(d.depth_diff == 0);
        }
}

TEST_CASE("fragment counts: the early discard casts fewer rays than start behind the occluders, and changes no pixel") {
    gl::OsmesaContext ctx;
    if (!gl::has_extension(ctx.api(), "GL_ARB_pipeline_statistics_query")) return;
    const int w = 320, h = 240;
    // Ellipsoids in a block (the sphere variant casts before it tests: no early discard there)
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> u(0.0f, 1.0f), ang(0.0f, 6.2831853f);
    std::vector<Primitive> prims;
    const float rad = 0.6f * std::cbrt(1.0f / 3000.0f);
    for (int i = 0; i < 3000; ++i) {
        const glm::vec3 d = glm::normalize(glm::vec3(u(rng) - 0.5f, u(rng) - 0.5f, u(rng) - 0.5f) + glm::vec3(0.01f));
        prims.push_back(shapes::ellipsoid(glm::vec3(u(rng), u(rng), u(rng)), glm::vec3(1.3f * rad, 0.8f * rad, rad), glm::mat3(glm::rotate(glm::mat4(1.0f), ang(rng), d)),
                                          {{0.4f + 0.5f * u(rng), 0.6f, 0.5f}, 0.35f, 48.0f}));
    }
    const Camera cam = qc_render_test::look_at(vec3(0.4, 0.7, 2.6), vec3(0.5, 0.5, 0.5), vec3(0.0, 1.0, 0.0), qc_render_test::perspective(35, double(w) / h, 1, 5));
    Light light;
    gl::QuadricRenderer r(ctx.api());
    r.set_primitives(prims);
    RenderOptions o;
    o.width = w;
    o.height = h;
    o.occlusion_min_overlap = 0.0f;  // (the cull pass in every frame)
    o.occlusion_reuse = false;
    r.draw(cam, light, o);
    const Image plain = r.read();
    r.set_count_fragments(true);
    r.draw(cam, light, o);
    const gl::FragmentCounts early = r.fragment_counts();
    const Image counted = r.read();
    r.set_early_discard(false);
    r.draw(cam, light, o);
    const gl::FragmentCounts late = r.fragment_counts();
    r.set_early_discard(true);
    r.set_count_fragments(false);
    const long pixels = covered(plain);
    std::printf("[fragment counts] 3000 ellipsoids, cull pass: %ld visible pixels; early discard: %llu started, %llu cast, %llu hit; without it: %llu started, %llu cast, %llu hit\n",
                pixels, static_cast<unsigned long long>(early.started), static_cast<unsigned long long>(early.cast), static_cast<unsigned long long>(early.hit),
                static_cast<unsigned long long>(late.started), static_cast<unsigned long long>(late.cast), static_cast<unsigned long long>(late.hit));
    CHECK(r.cull_pass_ran());
    CHECK(early.started == late.started);  // (the same primitives drawn)
    CHECK(late.cast == late.started);
    CHECK(early.cast < early.started);
    CHECK(early.hit <= early.cast);
    CHECK(early.hit < late.hit);
    CHECK(early.hit >= static_cast<std::uint64_t>(pixels));  // every visible pixel is some fragment's hit
    const ImageDiff d = image_diff(plain, counted);
    CHECK(d.coverage_diff == 0);
    CHECK(d.color_diff == 0);
    CHECK(d.depth_diff == 0);
}
