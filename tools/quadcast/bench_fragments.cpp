// tools/quadcast/bench_fragments.cpp -- `quadcast bench fragments`: the fragment stage's fill rate
//
// One scene (random spheres and capped cylinders in the unit cube, 1024x768, perspective) drawn
// with three fragment stages over the same bounding quads, interleaved frame by frame in one run:
// the renderer's stage (the pixel's ray from the frame's affine terms, `window_ray`: the ray terms
// of Stoll et al. 2006, sec. 5, who report 1.75x the fill rate of brute force, evaluated at
// gl_FragCoord instead of interpolated), the brute-force stage (the pixel's world ray
// from gl_FragCoord via the inverse view-projection, then `local_ray` and `cast` per fragment) and
// a pass-through stage (constant colour, rasterised depth: the rasteriser's ceiling). Fragments are
// counted with a GL_SAMPLES_PASSED query over a pass-through frame with the depth test off (every
// rasterised fragment of every quad passes), which is the number of fragment-shader invocations
// of all three stages (all write gl_FragDepth, so none is rejected early).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <random>
#include <vector>

#include "quadcast/camera.hpp"
#include "commands.hpp"
#include "quadcast/gl/osmesa_context.hpp"
#include "quadcast/gl/quadric_renderer.hpp"
#include "quadcast/scene/scene_render.hpp"

namespace quadcast::cli {

namespace {

struct FragmentsOptions {
    int spheres = 20000, cylinders = 2000, frames = 7, width = 1024, height = 768;
    float scale = 1.0f;  ///< radius multiplier
};

/// N random spheres (radius 0.5 scale N^(-1/3)) and M random capped cylinders in the unit cube.
std::vector<render::Primitive> fragments_scene(int n, int m, float scale, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(0.0f, 1.0f), c(0.2f, 1.0f), s(-1.0f, 1.0f);
    const float r = 0.5f * scale * std::pow(static_cast<float>(n), -1.0f / 3.0f);
    std::vector<render::Primitive> out;
    for (int i = 0; i < n; ++i) {
        render::Primitive p{};
        p.shape.q.q = identity<float, 4>();
        p.shape.q.q[3][3] = -r * r;
        p.shape.center = vec3(u(rng), u(rng), u(rng));
        p.shape.radius = r;
        p.shape.axis = vec3(0.0f, 0.0f, 1.0f);
        p.shape.half_length = std::numeric_limits<float>::infinity();
        p.variant = render::Variant::ellipsoid;
        p.color = vec3(c(rng), c(rng), c(rng));
        out.push_back(p);
    }
    for (int i = 0; i < m; ++i) {
        // x^T (I - a a^T) x = rc^2, capped at |a.x| <= h (slab variant).
        Vec3<float> a = vec3(s(rng), s(rng), s(rng));
        a = a * (1.0f / std::sqrt(dot(a, a) + 1e-12f));
        const float rc = 0.6f * r, h = 2.0f * r;
        render::Primitive p{};
        p.shape.q.q = identity<float, 4>();
        for (int j = 0; j < 3; ++j)
            for (int k = 0; k < 3; ++k) p.shape.q.q[j][k] -= a[j] * a[k];
        p.shape.q.q[3][3] = -rc * rc;
        p.shape.center = vec3(u(rng), u(rng), u(rng));
        p.shape.radius = std::sqrt(rc * rc + h * h);
        p.shape.axis = a;
        p.shape.half_length = h;
        p.variant = render::Variant::slab;
        p.color = vec3(c(rng), c(rng), c(rng));
        out.push_back(p);
    }
    return out;
}

double time_draw(gl::QuadricRenderer& r, gl::QuadricRenderer::FragmentStage st, const render::Camera& cam,
                 const render::Light& light, const render::RenderOptions& ro) {
    r.set_fragment_stage(st);
    const auto t0 = std::chrono::steady_clock::now();
    r.draw(cam, light, ro);
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

void run_fragments(const FragmentsOptions& o) {
    using Stage = gl::QuadricRenderer::FragmentStage;
    gl::OsmesaContext ctx;
    std::printf("quadcast bench fragments: %dx%d, 30 degree perspective, %d spheres + %d capped cylinders in the unit cube\n",
                o.width, o.height, o.spheres, o.cylinders);
    std::printf("%s\n", ctx.info().summary().c_str());
    gl::QuadricRenderer r(ctx.api());
    r.set_primitives(fragments_scene(o.spheres, o.cylinders, o.scale, 11));
    render::Camera cam;
    const double aspect = static_cast<double>(o.width) / o.height;
    cam.view = cast<float>(quadcast::look_at(vec3(0.5, 0.5, 2.4), vec3(0.5, 0.5, 0.5), vec3(0.0, 1.0, 0.0)));
    cam.projection = cast<float>(quadcast::perspective(30.0, aspect, 0.5, 5.0));
    cam.eye = vec3(0.5f, 0.5f, 2.4f);
    render::Light light;
    light.direction = vec3(-0.4f, -0.6f, -1.0f);
    render::RenderOptions ro;
    ro.width = o.width;
    ro.height = o.height;

    // Fragment counts (GL_SAMPLES_PASSED, depth test off): all rasterised fragments (pass-through),
    // and those whose ray hits (incremental stage: the others are discarded).
    r.set_depth_test(false);
    r.set_fragment_stage(Stage::passthrough);
    r.draw(cam, light, ro);
    const double frags = static_cast<double>(r.samples_passed());
    r.set_fragment_stage(Stage::incremental);
    r.draw(cam, light, ro);
    const double hits = static_cast<double>(r.samples_passed());
    r.set_fragment_stage(Stage::brute_force);
    r.draw(cam, light, ro);
    const double hits_brute = static_cast<double>(r.samples_passed());
    r.set_depth_test(true);

    const Stage stages[3] = {Stage::incremental, Stage::brute_force, Stage::passthrough};
    const char* names[3] = {"incremental", "brute force", "pass-through"};
    for (Stage st : stages) time_draw(r, st, cam, light, ro);  // warm-up (compiles the programs)
    std::vector<double> ms[3];
    for (int i = 0; i < o.frames; ++i)
        for (int k = 0; k < 3; ++k) ms[k].push_back(time_draw(r, stages[k], cam, light, ro));
    double med[3];
    for (int k = 0; k < 3; ++k) {
        std::sort(ms[k].begin(), ms[k].end());
        med[k] = ms[k][ms[k].size() / 2];
    }
    std::printf("fragments per frame (GL_SAMPLES_PASSED, depth test off): %.0f rasterised (%.2f per pixel), %.0f hit (incremental), %.0f hit (brute force)\n",
                frags, frags / (static_cast<double>(o.width) * o.height), hits, hits_brute);
    std::printf("median of %d frames each, interleaved; fragments/s = rasterised fragments / frame time (whole frame)\n", o.frames);
    std::printf("%-14s %12s %10s %16s\n", "fragment stage", "median ms", "fps", "Mfragments/s");
    for (int k = 0; k < 3; ++k)
        std::printf("%-14s %12.1f %10.2f %16.1f\n", names[k], med[k], 1000.0 / med[k], frags / (med[k] * 1e-3) * 1e-6);
    std::printf("incremental / brute force fill rate: %.2fx (Stoll et al. 2006 report 1.75x)\n", med[1] / med[0]);
    std::printf("incremental / pass-through fill rate: %.2f (pass-through %.2fx faster)\n", med[2] / med[0], med[0] / med[2]);
    std::printf("brute force / pass-through fill rate: %.2f\n", med[2] / med[1]);
}

}  // namespace

void add_bench_fragments(CLI::App& bench) {
    auto o = std::make_shared<FragmentsOptions>();
    CLI::App* cmd = bench.add_subcommand("fragments", "fill rate: incremental vs brute-force vs pass-through fragment stage");
    cmd->add_option("--spheres", o->spheres, "sphere count");
    cmd->add_option("--cylinders", o->cylinders, "capped cylinder count");
    cmd->add_option("--scale", o->scale, "radius multiplier");
    cmd->add_option("--frames", o->frames, "timed frames per stage")->check(CLI::Range(1, 1000));
    cmd->callback([o] { run_fragments(*o); });
}

}  // namespace quadcast::cli
