// tests/gl/test_environment.cpp -- environment reflection: GL (forward and deferred) against the CPU reference
#include <doctest/doctest.h>

#include <cmath>
#include <cstdio>
#include <memory>

#include "quadcast/gl/osmesa_context.hpp"
#include "quadcast/gl/quadric_renderer.hpp"
#include "quadcast/render/cpu_renderer.hpp"
#include "quadcast/render/environment.hpp"
#include "render/render_testing.hpp"

using namespace quadcast;
using namespace quadcast::render;

namespace {

struct EnvDiff {
    long coverage = 0, coverage_diff = 0, over_1 = 0;
    int max = 0;
};

/// Coverage (depth < 1) and per-channel colour differences of two frames.
EnvDiff env_diff(const Image& a, const Image& b) {
    EnvDiff d;
    for (std::size_t i = 0; i < a.depth.size(); ++i) {
        const bool ca = a.depth[i] < 1.0f, cb = b.depth[i] < 1.0f;
        d.coverage += ca;
        if (ca != cb) { ++d.coverage_diff; continue; }
        int m = 0;
        for (int c = 0; c < 3; ++c) m = std::max(m, std::abs(int(a.rgba[i * 4 + c]) - int(b.rgba[i * 4 + c])));
        d.max = std::max(d.max, m);
        d.over_1 += m > 1;
    }
    return d;
}

}  // namespace

// The lookup reads RGB32F texels with texelFetch and interpolates them with the traced
// `environment_mix`, so GL and CPU compute the same bits from the same normal and view vector.
// They get those vectors by different rounding (the GPU interpolates the ray over the quad, the
// CPU builds it per pixel; see test_render_gl_vs_cpu), and the reflection turns a normal error
// of d into a direction error of 2d, which moves the lookup by 2d width / (2 pi) texels: with a
// 1024-texel map a pixel on a checkerboard edge can differ by more than 1 LSB. Measured on Mesa
// llvmpipe: no such pixel (max 1 LSB, the UNORM rounding of an ulp), forward and deferred, both
// cameras; the bound allows one pixel in a thousand.
TEST_CASE("environment reflection: the GL renderer (forward and deferred) draws what the CPU reference draws") {
    gl::OsmesaContext ctx;
    gl::QuadricRenderer r(ctx.api());
    const std::vector<render::Primitive> prims = qc_render_test::mixed_scene(14, {50, 25, 8, true, false});
    r.set_primitives(prims);
    Light light;
    light.direction = vec3(-0.4f, -0.6f, -1.0f);
    const auto env = std::make_shared<const EnvironmentMap>(procedural_environment());
    for (bool ortho : {false, true})
        for (bool deferred : {false, true}) {
            RenderOptions o;
            o.occlusion_min_overlap = 0.0f;  // (the cull pass too, however sparse the scene)
            o.width = 240;
            o.height = 180;
            o.background = vec3(0.2f, 0.3f, 0.4f);
            o.deferred = deferred;
            const Camera cam = ortho ? qc_render_test::look_at(vec3(0.5, 1.0, 8.0), vec3(0.0, 0.0, 0.0), vec3(0.0, 1.0, 0.0), qc_render_test::orthographic(-4, 4, -3, 3, 1, 20), true)
                                     : qc_render_test::look_at(vec3(0.5, 1.0, 8.0), vec3(0.0, 0.0, 0.0), vec3(0.0, 1.0, 0.0), qc_render_test::perspective(50, 240.0 / 180.0, 1, 20));
            r.draw(cam, light, o);
            const Image plain = r.read();
            const Image cpu_plain = render_cpu(prims, cam, light, o);
            o.environment = env;
            o.reflectivity = 0.5f;
            r.draw(cam, light, o);
            const Image g = r.read();
            const Image c = render_cpu(prims, cam, light, o);
            const EnvDiff gc = env_diff(g, c), base = env_diff(plain, cpu_plain), changed = env_diff(plain, g);
            std::printf("[environment] %s, %s: %ld covered px; GL vs CPU: %ld coverage differences (%ld without the environment), "
                        "%ld px > 1 LSB (%ld without), max %d LSB; %ld px changed by the reflection\n",
                        ortho ? "orthographic" : "perspective", deferred ? "deferred" : "forward", gc.coverage, gc.coverage_diff,
                        base.coverage_diff, gc.over_1, base.over_1, gc.max, changed.over_1);
            CHECK(gc.coverage > 5000);
            // The reflection changes colours only: the same coverage as without it, in both renderers.
            CHECK(changed.coverage_diff == 0);
            CHECK(gc.coverage_diff == base.coverage_diff);
            CHECK(changed.over_1 > gc.coverage / 2);
            CHECK(gc.over_1 <= gc.coverage / 1000);
        }
}

TEST_CASE("environment reflection: deferred shading draws the image forward shading draws") {
    gl::OsmesaContext ctx;
    gl::QuadricRenderer r(ctx.api());
    const std::vector<render::Primitive> prims = qc_render_test::mixed_scene(15, {50, 25, 8, true, false});
    r.set_primitives(prims);
    Light light;
    light.direction = vec3(-0.4f, -0.6f, -1.0f);
    RenderOptions o;
    o.width = 240;
    o.height = 180;
    o.environment = std::make_shared<const EnvironmentMap>(procedural_environment());
    const Camera cam = qc_render_test::look_at(vec3(0.5, 1.0, 8.0), vec3(0.0, 0.0, 0.0), vec3(0.0, 1.0, 0.0), qc_render_test::perspective(50, 240.0 / 180.0, 1, 20));
    r.draw(cam, light, o);
    const Image fwd = r.read();
    o.deferred = true;
    r.draw(cam, light, o);
    const Image def = r.read();
    const EnvDiff d = env_diff(fwd, def);
    std::printf("[environment] forward vs deferred: %ld covered px, %ld coverage differences, max %d LSB\n", d.coverage, d.coverage_diff, d.max);
    CHECK(d.coverage > 5000);
    CHECK(d.coverage_diff == 0);
    CHECK(d.max <= 1);
}
