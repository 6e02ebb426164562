// tools/quadcast/bench_spheres.cpp -- `quadcast bench spheres`: frame time against sphere count
//
// N random spheres in the unit cube, radius 0.3 N^(-1/3), seen at 1024x768 with a 30 degree
// perspective camera, rendered by the GL quadric renderer (Mesa llvmpipe here) with the
// sphere-specialised variant (Variant::sphere). Prints the median frame time over the frames
// after a warm-up, and the ratio to the fps quoted for VTK 9.1's vtkOpenGLSphereMapper on this
// machine (10.1 / 3.6 / 0.46 fps at 10k/100k/1M). With --compare the general closed-quadric
// variant (Variant::ellipsoid) draws the same spheres too, frame by frame interleaved with the
// sphere variant in one run (the machine's load changes both alike), and the ratio is printed.
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
#include "timing.hpp"
#include "quadcast/gl/osmesa_context.hpp"
#include "quadcast/gl/quadric_renderer.hpp"
#include "quadcast/scene/scene_render.hpp"

namespace quadcast::cli {

namespace {

struct SpheresOptions {
    std::vector<int> counts{10000, 100000, 1000000};
    int frames = 5, width = 1024, height = 768;
    bool culling = true;
    bool compare = false;
};

std::vector<render::Primitive> random_spheres(int n, unsigned seed, render::Variant variant) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(0.0f, 1.0f), c(0.2f, 1.0f);
    const float r = 0.3f * std::pow(static_cast<float>(n), -1.0f / 3.0f);
    std::vector<render::Primitive> out(static_cast<std::size_t>(n));
    for (auto& p : out) {
        p.shape.q.q = identity<float, 4>();
        p.shape.q.q[3][3] = -r * r;
        p.shape.center = vec3(u(rng), u(rng), u(rng));
        p.shape.radius = r;
        p.shape.axis = vec3(0.0f, 0.0f, 1.0f);
        p.shape.half_length = std::numeric_limits<float>::infinity();
        p.variant = variant;
        p.color = vec3(c(rng), c(rng), c(rng));
    }
    return out;
}

void run_spheres(const SpheresOptions& o) {
    gl::OsmesaContext ctx;
    std::printf("quadcast bench spheres: %dx%d, 30 degree perspective, random spheres in the unit cube, r = 0.3 N^(-1/3)\n", o.width, o.height);
    std::printf("%s\n", ctx.info().summary().c_str());
    if (o.compare)
        std::printf("%10s %16s %16s %12s %12s %14s %16s\n", "spheres", "closed median ms", "sphere median ms", "closed fps", "sphere fps",
                    "sphere/closed", "sphere / VTK");
    else
        std::printf("%10s %12s %10s %14s %16s\n", "spheres", "median ms", "fps", "VTK 9.1 fps", "quadcast / VTK");
    gl::QuadricRenderer r(ctx.api());
    std::unique_ptr<gl::QuadricRenderer> general;  // --compare: the closed-quadric variant
    if (o.compare) general = std::make_unique<gl::QuadricRenderer>(ctx.api());
    render::Camera cam;
    const double aspect = static_cast<double>(o.width) / o.height;
    cam.view = cast<float>(quadcast::look_at(vec3(0.5, 0.5, 3.2), vec3(0.5, 0.5, 0.5), vec3(0.0, 1.0, 0.0)));
    cam.projection = cast<float>(quadcast::perspective(30.0, aspect, 1.0, 5.0));
    cam.eye = vec3(0.5f, 0.5f, 3.2f);
    render::Light light;
    light.direction = vec3(-0.4f, -0.6f, -1.0f);
    render::RenderOptions ro;
    ro.width = o.width;
    ro.height = o.height;
    ro.culling = o.culling;
    auto time_frame = [&](gl::QuadricRenderer& renderer) {
        const auto t0 = std::chrono::steady_clock::now();
        renderer.draw(cam, light, ro);
        return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    };
    for (int n : o.counts) {
        r.set_primitives(random_spheres(n, 7, render::Variant::sphere));
        r.draw(cam, light, ro);  // warm-up
        if (general) {
            general->set_primitives(random_spheres(n, 7, render::Variant::ellipsoid));
            general->draw(cam, light, ro);
        }
        std::vector<double> ms, ms_general;
        for (int i = 0; i < o.frames; ++i) {
            if (general) ms_general.push_back(time_frame(*general));
            ms.push_back(time_frame(r));
        }
        const double med = median(ms);
        const double vtk = n == 10000 ? 10.1 : n == 100000 ? 3.6 : n == 1000000 ? 0.46 : 0.0;
        if (general) {
            const double med_general = median(ms_general);
            std::printf("%10d %16.1f %16.1f %12.2f %12.2f %13.2fx %15.2fx\n", n, med_general, med, 1000.0 / med_general, 1000.0 / med,
                        med_general / med, vtk > 0 ? 1000.0 / med / vtk : 0.0);
            continue;
        }
        if (vtk > 0)
            std::printf("%10d %12.1f %10.2f %14.2f %15.2fx\n", n, med, 1000.0 / med, vtk, 1000.0 / med / vtk);
        else
            std::printf("%10d %12.1f %10.2f %14s %16s\n", n, med, 1000.0 / med, "-", "-");
    }
}

}  // namespace

void add_bench_spheres(CLI::App& bench) {
    auto o = std::make_shared<SpheresOptions>();
    CLI::App* cmd = bench.add_subcommand("spheres", "frame time of N random spheres (10k / 100k / 1M) against VTK's sphere mapper");
    cmd->add_option("--counts", o->counts, "sphere counts");
    cmd->add_option("--frames", o->frames, "timed frames per count")->check(CLI::Range(1, 1000));
    cmd->add_flag("--compare", o->compare, "also time the general closed-quadric variant, interleaved, and print the ratio");
    cmd->callback([o] { run_spheres(*o); });
}

}  // namespace quadcast::cli
