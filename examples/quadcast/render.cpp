// examples/quadcast/render.cpp -- `quadcast render SCENE.json -o out.png`
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "commands.hpp"
#include "diagnostics.hpp"
#include "image_io.hpp"
#include "quadcast/gl/osmesa_context.hpp"
#include "quadcast/gl/quadric_renderer.hpp"
#include "quadcast/render/cpu_renderer.hpp"
#include "scene_json.hpp"
#include "scene_render.hpp"

namespace quadcast::cli {

namespace {

struct RenderArgs {
    std::string scene, output, depth;
    int width = 1024, height = 768, frames = 0;
    bool cpu = false;
};

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v.empty() ? 0.0 : v[v.size() / 2];
}

int write_outputs(const RenderArgs& a, const render::Image& img) {
    try {
        render::write_png(a.output, img);
        if (!a.depth.empty()) render::write_pfm(a.depth, img);
    } catch (const std::exception& e) {
        std::cerr << "quadcast render: " << e.what() << "\n";
        return 1;
    }
    return 0;
}

int run_render(const RenderArgs& a) {
    scene::Scene sc;
    try {
        sc = scene::load_scene(a.scene);
    } catch (const scene::ParseError& e) {
        std::cerr << e.what() << "\n";
        return 1;
    }
    for (const auto& w : sc.warnings) std::cerr << w.to_string() << "\n";
    render::Frame fr = render::build_frame(sc, a.width, a.height);
    for (const auto& n : fr.notes) std::cerr << a.scene << ": note: " << n << "\n";
    render::Image img;
    if (a.cpu) {
        render::FrameStats st;
        img = render::render_cpu(fr.primitives, fr.camera, fr.light, fr.options, &st);
        if (a.frames > 0) {
            std::vector<double> ms;
            for (int i = 0; i < a.frames; ++i) {
                const auto t0 = std::chrono::steady_clock::now();
                img = render::render_cpu(fr.primitives, fr.camera, fr.light, fr.options);
                ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
            }
            std::printf("%s: %zu primitives, %dx%d, median frame %.2f ms over %d frames (CPU reference), %llu casts, %llu culled\n", a.scene.c_str(),
                        fr.primitives.size(), a.width, a.height, median(ms), a.frames, static_cast<unsigned long long>(st.fragments),
                        static_cast<unsigned long long>(st.culled));
        }
        return write_outputs(a, img);
    }
    std::unique_ptr<gl::OsmesaContext> ctx;
    try {
        ctx = std::make_unique<gl::OsmesaContext>();
    } catch (const std::exception& e) {
        std::cerr << "quadcast render: " << e.what() << " (use --cpu to render without OpenGL)\n";
        return 2;
    }
    gl::QuadricRenderer r(ctx->api());
    r.set_primitives(fr.primitives);
    r.draw(fr.camera, fr.light, fr.options);  // warm-up: compiles the variants the scene uses
    if (a.frames > 0) {
        std::vector<double> ms;
        for (int i = 0; i < a.frames; ++i) {
            const auto t0 = std::chrono::steady_clock::now();
            r.draw(fr.camera, fr.light, fr.options);
            ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
        }
        std::printf("%s: %zu primitives, %dx%d, median frame %.2f ms over %d frames (%s)\n", a.scene.c_str(), fr.primitives.size(), a.width,
                    a.height, median(ms), a.frames, ctx->info().renderer.c_str());
    }
    img = r.read();
    return write_outputs(a, img);
}

}  // namespace

void add_render(CLI::App& app) {
    auto a = std::make_shared<RenderArgs>();
    CLI::App* cmd = app.add_subcommand("render", "render a JSON scene to a PNG");
    cmd->add_option("scene", a->scene, "scene file (JSON)")->required();
    cmd->add_option("-o,--output", a->output, "output PNG")->required();
    cmd->add_option("--width", a->width, "image width")->check(CLI::Range(1, 16384));
    cmd->add_option("--height", a->height, "image height")->check(CLI::Range(1, 16384));
    cmd->add_flag("--cpu", a->cpu, "render with the CPU reference renderer");
    cmd->add_option("--depth", a->depth, "also write window depth as PFM (1.0 = background)");
    cmd->add_option("--frames", a->frames, "time this many frames after a warm-up; print the median")->check(CLI::Range(0, 100000));
    cmd->callback([a] {
        const int rc = run_render(*a);
        if (rc) throw CLI::RuntimeError(rc);
    });
}

}  // namespace quadcast::cli
