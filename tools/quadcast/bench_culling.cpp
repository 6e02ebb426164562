// tools/quadcast/bench_culling.cpp -- `quadcast bench culling`: per-quadric back-face culling on a
// closed surface of quadric patches (Stoll et al. 2006 report up to 2x)
//
// A torus tessellated into bilinear quads (each rendered as its quadric clipped to the quad's
// tetrahedron), drawn with culling on and off, interleaved, in one run. Prints median frame
// times, their ratio, and how many patches the per-quadric test culled (counted by the CPU
// reference renderer, which applies the same `cull_primitive`).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "commands.hpp"
#include "quadcast/gl/osmesa_context.hpp"
#include "quadcast/gl/quadric_renderer.hpp"
#include "quadcast/render/cpu_renderer.hpp"
#include "quadcast/image/image_io.hpp"
#include "quadcast/scene/scene_render.hpp"

namespace quadcast::cli {

namespace {

struct CullingOptions {
    int u = 96, v = 48, frames = 7, width = 1024, height = 768;
    std::string png;  ///< optional: the culled frame and the unculled frame (suffix .off.png)
};

scene::Scene torus(int nu, int nv) {
    scene::Scene s;
    const double R = 1.0, r = 0.4;
    // A helical grid (row j shifted by j/nv of a patch around the torus) closes up after one
    // turn and makes every patch a genuinely bilinear (non-planar) quad.
    auto point = [&](int i, int j) {
        const double a = 2 * M_PI * (i + static_cast<double>(j) / nv) / nu, b = 2 * M_PI * j / nv;
        return Vec3<double>{{(R + r * std::cos(b)) * std::cos(a), (R + r * std::cos(b)) * std::sin(a), r * std::sin(b)}};
    };
    for (int i = 0; i < nu; ++i)
        for (int j = 0; j < nv; ++j) {
            scene::BilinearQuad q;
            // Counter-clockwise seen from outside: the front side faces out.
            q.p = {point(i, j), point(i + 1, j), point(i + 1, j + 1), point(i, j + 1)};
            q.material.color = {{0.85, 0.6, 0.3}};
            s.quads.push_back(q);
        }
    s.camera.eye = {{0.3, -2.6, 1.6}};
    s.camera.target = {{0.0, 0.0, 0.0}};
    s.camera.up = {{0.0, 0.0, 1.0}};
    s.camera.fov_y_deg = 40;
    s.camera.near = 0.5;
    s.camera.far = 10;
    s.lights.push_back(scene::Light{});
    return s;
}

double time_frame(gl::QuadricRenderer& r, const render::Frame& f, bool culling) {
    render::RenderOptions o = f.options;
    o.culling = culling;
    const auto t0 = std::chrono::steady_clock::now();
    r.draw(f.camera, f.light, o);
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

void run_culling(const CullingOptions& opt) {
    const scene::Scene s = torus(opt.u, opt.v);
    const render::Frame f = render::build_frame(s, opt.width, opt.height);
    gl::OsmesaContext ctx;
    gl::QuadricRenderer r(ctx.api());
    r.set_primitives(f.primitives);
    time_frame(r, f, true);  // warm-up: compile both variants
    time_frame(r, f, false);
    std::vector<double> on, off;
    for (int i = 0; i < opt.frames; ++i) {
        on.push_back(time_frame(r, f, true));
        off.push_back(time_frame(r, f, false));
    }
    std::sort(on.begin(), on.end());
    std::sort(off.begin(), off.end());
    render::FrameStats st;
    render::RenderOptions o = f.options;
    o.culling = true;
    (void)render::render_cpu(f.primitives, f.camera, f.light, o, &st);
    const double m_on = on[on.size() / 2], m_off = off[off.size() / 2];
    if (!opt.png.empty()) {
        time_frame(r, f, true);
        const render::Image img_on = r.read();
        time_frame(r, f, false);
        const render::Image img_off = r.read();
        render::write_png(opt.png, img_on);
        render::write_png(opt.png + ".off.png", img_off);
        render::RenderOptions oc = f.options;
        oc.culling = true;
        render::write_png(opt.png + ".cpu.png", render::render_cpu(f.primitives, f.camera, f.light, oc));
        long differ = 0;
        for (std::size_t i = 0; i < img_on.depth.size(); ++i) differ += (img_on.depth[i] < 1.0f) != (img_off.depth[i] < 1.0f);
        std::printf("coverage differences culled vs unculled frame: %ld pixels\n", differ);
    }
    std::printf("quadcast bench culling: helical torus of %d bilinear patches (quadric + tetrahedron each), %dx%d, %s\n", opt.u * opt.v, opt.width,
                opt.height, ctx.info().renderer.c_str());
    std::printf("per-quadric culling culls %llu of %zu patches\n", static_cast<unsigned long long>(st.culled), f.primitives.size());
    std::printf("%-14s %12s\n", "culling", "median ms");
    std::printf("%-14s %12.2f\n", "off", m_off);
    std::printf("%-14s %12.2f\n", "on", m_on);
    std::printf("speed-up on/off: %.2fx (Stoll et al. 2006: up to 2x)\n", m_off / m_on);
}

}  // namespace

void add_bench_culling(CLI::App& bench) {
    auto o = std::make_shared<CullingOptions>();
    CLI::App* cmd = bench.add_subcommand("culling", "per-quadric back-face culling on vs off on a closed surface of quadric patches");
    cmd->add_option("--u", o->u, "patches around the torus")->check(CLI::Range(3, 2000));
    cmd->add_option("--v", o->v, "patches around the tube")->check(CLI::Range(3, 2000));
    cmd->add_option("--frames", o->frames, "timed frames per mode")->check(CLI::Range(1, 1000));
    cmd->add_option("--png", o->png, "write the frames (culling on; and PATH.off.png with culling off)");
    cmd->callback([o] { run_culling(*o); });
}

}  // namespace quadcast::cli
