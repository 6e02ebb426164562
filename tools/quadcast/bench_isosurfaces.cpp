// tools/quadcast/bench_isosurfaces.cpp -- `quadcast bench isosurfaces`: GL frame time of QSS, S31 and
// trilinear isosurfaces against the CPU reference, and what the octree and frustum culling skip
//
// One volume (CGAL's skull by default, Marschner-Lobb when the file is missing), one run: per
// scheme the preparation time, the GL median frame time (1024x768, forward shading) and the CPU
// reference's on the same camera, and their ratio (Kalbe & Zeilfelder 2008 report the GPU 10-100x
// faster than their CPU ray caster). Then, for a view of the whole volume and a close-up, how
// many cubes the min-max octree (coefficient ranges vs ρ), the frustum test and the per-
// tetrahedron range test leave, and the frame time with each switched off (interleaved frames).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "quadcast/camera.hpp"
#include "commands.hpp"
#include "timing.hpp"
#include "quadcast/image/image_io.hpp"
#include "quadcast/volume/load.hpp"
#include "quadcast/gl/isosurface_renderer.hpp"
#include "quadcast/gl/osmesa_context.hpp"
#include "quadcast/gl/quadric_renderer.hpp"
#include "quadcast/isosurface.hpp"
#include "quadcast/render/record.hpp"
#include "quadcast/render/spline_cpu_renderer.hpp"
#include "quadcast/scene/scene_render.hpp"

namespace quadcast::cli {

namespace {

struct IsoBenchOptions {
    std::string input = "build/data/skull_2.9.inr", png;
    double iso = 2.9;
    bool iso_given = false;
    int frames = 7, cpu_frames = 2, width = 1024, height = 768;
};

/// A camera looking at the volume's box from direction (1, -0.8, 0.6) at `distance` times the
/// box's radius (1 = on the bounding sphere), 40° field of view.
render::Camera view_of(const render::VolumeModel& m, double distance, int w, int h) {
    Vec3<double> lo{}, hi{};
    m.world_box(lo, hi);
    const Vec3<double> c = 0.5 * (lo + hi);
    const double r = 0.5 * length(hi - lo);
    const Vec3<double> dir = normalize(Vec3<double>{{1.0, -0.8, 0.6}});
    const Vec3<double> eye = c + (distance * r) * dir;
    const double fov = 40.0;
    const double far = (distance + 1.5) * r, near = std::max(1e-3 * r, (distance - 1.2) * r);
    return render::Camera{cast<float>(quadcast::look_at(eye, c, Vec3<double>{{0.0, 0.0, 1.0}})),
                          cast<float>(quadcast::perspective(fov, double(w) / h, near, far)), cast<float>(eye), false};
}

struct Gl {
    gl::OsmesaContext ctx;
    gl::QuadricRenderer quadrics{ctx.api()};
    gl::IsosurfaceRenderer iso{ctx.api()};
    Gl() {
        quadrics.set_primitives({});
        quadrics.add_pass(iso);
    }
    double frame(const render::Camera& cam, const render::Light& light, const render::RenderOptions& o) {
        const auto t0 = std::chrono::steady_clock::now();
        quadrics.draw(cam, light, o);
        return ms_since(t0);
    }
};

/// Coverage and depth differences of two images of the same view.
struct Diff {
    long covered = 0, coverage = 0, isolated = 0, colour = 0;
    long deep = 0;       ///< pixels both cover whose window depths differ by more than 1e-3
    double depth = 0;
    int at_x = -1, at_y = -1;  ///< where the largest depth difference is (image rows top first)
};
Diff image_diff(const render::Image& a, const render::Image& b) {
    Diff d;
    const auto cov = [](const render::Image& im, int x, int y) { return im.depth[static_cast<std::size_t>(y) * im.width + x] < 1.0f; };
    for (int y = 0; y < a.height; ++y)
        for (int x = 0; x < a.width; ++x) {
            const std::size_t i = static_cast<std::size_t>(y) * a.width + x;
            const bool ca = cov(a, x, y), cb = cov(b, x, y);
            d.covered += ca;
            if (ca != cb) {
                ++d.coverage;
                bool edge = false;  // a silhouette: a neighbour differs in coverage in b
                for (int dy = -1; dy <= 1; ++dy)
                    for (int dx = -1; dx <= 1; ++dx) {
                        const int xx = x + dx, yy = y + dy;
                        if (xx >= 0 && yy >= 0 && xx < a.width && yy < a.height) edge = edge || cov(b, xx, yy) != cb;
                    }
                d.isolated += !edge;
                continue;
            }
            if (!ca) continue;
            const double dd = std::fabs(double(a.depth[i]) - double(b.depth[i]));
            d.deep += dd > 1e-3;
            if (dd > d.depth) {
                d.depth = dd;
                d.at_x = x;
                d.at_y = y;
            }
            for (int c = 0; c < 3; ++c)
                if (std::abs(int(a.rgba[4 * i + c]) - int(b.rgba[4 * i + c])) > 2) {
                    ++d.colour;
                    break;
                }
        }
    return d;
}

/// QSS drawn two ways on the same views, frames interleaved: Kalbe & Zeilfelder's per-cube
/// Bézier ray casting (the isosurface renderer) and Stoll et al.'s quadrics clipped to the
/// relevant tetrahedra (shapes::isosurface_quadrics drawn by the quadric renderer, with and
/// without its occlusion cull pass, and with the bounds written by its compute pass,
/// QuadricRenderer::set_compute_bounds).
void compare_qss_methods(Gl& gl, const render::VolumeModel& m, const render::Light& light, const render::RenderOptions& o, const IsoBenchOptions& a) {
    const auto t0 = std::chrono::steady_clock::now();
    const std::vector<render::Primitive> pieces = shapes::isosurface_quadrics(m);
    const double conv = ms_since(t0);
    gl::QuadricRenderer stoll(gl.ctx.api());
    stoll.set_primitives(pieces);
    std::size_t relevant = 0;
    for (const std::uint32_t mask : m.tet_mask) relevant += static_cast<std::size_t>(__builtin_popcount(mask));
    const double dset_bytes = double(m.dsets.size() * sizeof(float) + m.tet_mask.size() * 4 + m.cubes.size() * 4);
    const double record_bytes = double(render::record_slots * 4 * sizeof(float));
    std::printf("\nQSS two ways (%zu active cubes, %zu relevant tetrahedra; frames interleaved, ratios to the Bezier path):\n", m.active, relevant);
    std::printf("  bezier:  determining sets %.0f B per relevant tetrahedron kept on the GPU, plus per frame 16 B of element record per\n"
                "           tetrahedron drawn (the CPU element list; drawn in batches over an index buffer of 65536 tetrahedra, 3 MB)\n",
                dset_bytes / double(std::max<std::size_t>(relevant, 1)));
    std::printf("  quadric: %zu pieces built in %.0f ms from the prepared model, %.0f B of primitive record per piece kept on the GPU\n",
                pieces.size(), conv, record_bytes);
    std::printf("%-9s %12s %12s %8s %16s %8s %13s %8s %10s %10s %10s %10s %8s\n", "view", "bezier ms", "quadric ms", "ratio", "quadric no occl", "ratio",
                "quadric comp", "ratio", "covered", "cov diff", "isolated", "max depth", "deep");
    render::RenderOptions oq = o;
    oq.culling = false;  // isosurface pieces are two-sided (render::isosurface_culling_note)
    render::RenderOptions no_occl = oq;
    no_occl.occlusion_culling = false;
    for (double dist : {2.4, 0.8}) {
        const render::Camera cam = view_of(m, dist, a.width, a.height);
        gl.frame(cam, light, o);
        stoll.draw(cam, light, oq);  // warm-up: compiles the variants
        stoll.draw(cam, light, no_occl);
        stoll.set_compute_bounds(true);
        stoll.draw(cam, light, oq);
        const render::Image comp = stoll.read();
        stoll.set_compute_bounds(false);
        std::vector<double> tb, tq, tn, tc;
        for (int i = 0; i < a.frames; ++i) {
            tb.push_back(gl.frame(cam, light, o));
            auto t1 = std::chrono::steady_clock::now();
            stoll.draw(cam, light, oq);
            tq.push_back(ms_since(t1));
            t1 = std::chrono::steady_clock::now();
            stoll.draw(cam, light, no_occl);
            tn.push_back(ms_since(t1));
            stoll.set_compute_bounds(true);
            t1 = std::chrono::steady_clock::now();
            stoll.draw(cam, light, oq);
            tc.push_back(ms_since(t1));
            stoll.set_compute_bounds(false);
        }
        gl.frame(cam, light, o);
        const render::Image bez = gl.quadrics.read();
        stoll.draw(cam, light, oq);
        const render::Image quad = stoll.read();
        if (!a.png.empty()) {
            render::write_png(a.png + (dist > 1 ? "_whole" : "_closeup") + "_qss_bezier.png", bez);
            render::write_png(a.png + (dist > 1 ? "_whole" : "_closeup") + "_qss_quadric.png", quad);
        }
        const Diff d = image_diff(quad, bez);
        const Diff dc = image_diff(comp, quad);
        if (dc.coverage != 0 || dc.depth != 0)
            std::printf("the compute pass's bounds changed the quadric image: %ld coverage differences, max depth difference %.2g\n", dc.coverage, dc.depth);
        const double b = median(tb);
        std::printf("%-9s %12.1f %12.1f %7.2fx %16.1f %7.2fx %13.1f %7.2fx %10ld %10ld %10ld %10.2g %8ld", dist > 1 ? "whole" : "close-up", b, median(tq), b / median(tq),
                    median(tn), b / median(tn), median(tc), b / median(tc), d.covered, d.coverage, d.isolated, d.depth, d.deep);
        if (d.depth > 0) std::printf("  (largest at pixel %d, %d: bezier %.6f, quadric %.6f)", d.at_x, d.at_y,
                                     double(bez.depth[static_cast<std::size_t>(d.at_y) * bez.width + d.at_x]),
                                     double(quad.depth[static_cast<std::size_t>(d.at_y) * quad.width + d.at_x]));
        std::printf("\n");
    }
    std::printf("(ratio > 1: the quadrics are faster; cov diff: pixels covered by one image only, isolated: of those, the ones with no\n"
                " coverage edge next to them in the Bezier image; max depth: largest window-depth difference where both cover;\n"
                " deep: pixels both cover whose window depths differ by more than 1e-3)\n");
}

void run(const IsoBenchOptions& a) {
    volume::VolumeRequest req;
    double iso = a.iso;
    req.input = a.input;
    if (!std::filesystem::exists(a.input)) {
        std::printf("%s not found (run `make data`); using Marschner-Lobb 64^3, iso 0.5 instead\n", a.input.c_str());
        req.input = "marschner-lobb";
        req.size = 64;
        if (!a.iso_given) iso = 0.5;
    }
    const volume::VolumeData d = volume::load_volume(req);
    volume::check_isovalue(d, iso);
    std::printf("%s: %dx%dx%d %s samples, iso %g, %dx%d, GL %d frames (median), CPU reference %d frames, one run\n\n", req.input.c_str(), d.nx(),
                d.ny(), d.nz(), d.sample_type.c_str(), iso, a.width, a.height, a.frames, a.cpu_frames);
    Gl gl;
    render::Light light;
    light.direction = vec3(-0.4f, 0.7f, -0.6f);
    render::RenderOptions o;
    o.width = a.width;
    o.height = a.height;

    std::printf("%-10s %10s %12s %14s %12s %7s %14s %14s %16s %16s %16s %12s %10s %10s\n", "scheme", "prep ms", "active cubes", "elements", "GL ms", "coeffs", "GL vertex",
                "GL pre-pass", "GL no reuse", "GL no occlusion", "GL still", "CPU ms", "CPU/GL", "CPU/still");
    const render::VolumeScheme schemes[3] = {render::VolumeScheme::qss, render::VolumeScheme::s31, render::VolumeScheme::trilinear};
    std::vector<render::VolumeModel> models;
    models.reserve(3);
    for (render::VolumeScheme s : schemes) {
        const auto t0 = std::chrono::steady_clock::now();
        models.push_back(render::prepare_volume(d.grid, d.origin, d.spacing, s, float(iso), vec3(0.9f, 0.85f, 0.75f)));
        const double prep = ms_since(t0);
        const render::VolumeModel& m = models.back();
        const render::Camera cam = view_of(m, 2.4, a.width, a.height);
        gl.iso.clear();
        gl.iso.add_volume(m);
        using Stage = gl::IsosurfaceRenderer::CoefficientStage;
        for (Stage st : {Stage::compute, Stage::vertex, Stage::automatic}) {  // warm-up: compiles the programs
            gl.iso.set_coefficient_stage(st);
            gl.frame(cam, light, o);
        }
        render::RenderOptions no_occl = o, no_reuse = o;
        no_occl.occlusion_culling = false;
        no_reuse.occlusion_reuse = false;
        std::vector<double> g, gv, gc, gn, gr, c;
        bool pre = false;
        for (int i = 0; i < a.frames; ++i) {
            gl.iso.set_coefficient_stage(Stage::automatic);
            g.push_back(gl.frame(cam, light, o));
            pre = gl.iso.stats(0).pre_pass;
            gn.push_back(gl.frame(cam, light, no_occl));
            gr.push_back(gl.frame(cam, light, no_reuse));
            if (s == render::VolumeScheme::trilinear) continue;
            gl.iso.set_coefficient_stage(Stage::vertex);
            gv.push_back(gl.frame(cam, light, o));
            gl.iso.set_coefficient_stage(Stage::compute);
            gc.push_back(gl.frame(cam, light, o));
        }
        gl.iso.set_coefficient_stage(Stage::automatic);
        // The same view frame after frame: from the second on, the set drawn alone, untested
        std::vector<double> gs;
        bool still = true;
        gl.frame(cam, light, o);
        for (int i = 0; i < a.frames; ++i) {
            gs.push_back(gl.frame(cam, light, o));
            still = still && gl.iso.stats(0).unchanged_view;
        }
        for (int i = 0; i < a.cpu_frames; ++i) {
            const auto t1 = std::chrono::steady_clock::now();
            const render::Image img = render::render_volumes_cpu({&m}, cam, light, o);
            c.push_back(ms_since(t1));
        }
        if (!a.png.empty()) {
            const std::string stem = a.png + "_" + render::volume_scheme_name(s);
            render::write_png(stem + "_gl.png", gl.quadrics.read());
            render::write_png(stem + "_cpu.png", render::render_volumes_cpu({&m}, cam, light, o));
        }
        const gl::IsoDrawStats& st = gl.iso.stats(0);
        char vert[32] = "-", prepass[32] = "-", nocc[32] = "-", noreuse[32] = "-", stilled[32] = "-";
        std::snprintf(stilled, sizeof stilled, "%.1f (%.2fx)%s", median(gs), median(gs) / median(g), still ? "" : "*");
        if (!gv.empty()) std::snprintf(vert, sizeof vert, "%.1f (%.2fx)", median(gv), median(gv) / median(g));
        if (!gc.empty()) std::snprintf(prepass, sizeof prepass, "%.1f (%.2fx)", median(gc), median(gc) / median(g));
        if (!gn.empty()) std::snprintf(nocc, sizeof nocc, "%.1f (%.2fx)", median(gn), median(gn) / median(g));
        std::snprintf(noreuse, sizeof noreuse, "%.1f (%.2fx)", median(gr), median(gr) / median(g));
        std::printf("%-10s %10.0f %12zu %14zu %12.1f %7s %14s %14s %16s %16s %16s %12.1f %9.1fx %9.1fx\n", render::volume_scheme_name(s), prep, m.active, st.elements,
                    median(g), s == render::VolumeScheme::trilinear ? "-" : pre ? "pre" : "vertex", vert, prepass, noreuse, nocc, stilled, median(c),
                    median(c) / median(g), median(c) / median(gs));
    }

    std::printf("\nWhat is skipped (QSS; cubes of the whole grid; frame times interleaved, ratios to all culling on):\n");
    std::printf("%-9s %10s %14s %12s %14s %14s %14s %12s %14s %14s %14s %14s %14s\n", "view", "cubes", "range has rho", "in frustum", "tets drawn", "tets (GPU)", "tets (no test)",
                "all on ms", "no frustum", "no tet test", "GPU list", "occluded", "no occlusion");
    const render::VolumeModel& m = models[0];
    gl.iso.clear();
    gl.iso.add_volume(m);
    const std::size_t cubes = static_cast<std::size_t>(m.nx) * m.ny * m.nz;
    for (double dist : {2.4, 0.8}) {
        const render::Camera cam = view_of(m, dist, a.width, a.height);
        std::vector<double> t_on, t_nofr, t_notet, t_gpu, t_noocc;
        gl::IsoDrawStats on{}, nofr{}, notet{}, on_gpu{};
        render::RenderOptions no_occl = o;
        no_occl.occlusion_culling = false;
        using List = gl::IsosurfaceRenderer::ElementList;
        for (int i = 0; i < a.frames; ++i) {
            gl.iso.set_frustum_culling(true);
            gl.iso.set_tetrahedron_culling(true);
            gl.iso.set_element_list(List::gpu);
            t_gpu.push_back(gl.frame(cam, light, o));
            on_gpu = gl.iso.stats(0);
            gl.iso.set_element_list(List::cpu);
            gl.iso.set_frustum_culling(true);
            gl.iso.set_tetrahedron_culling(true);
            t_on.push_back(gl.frame(cam, light, o));
            t_noocc.push_back(gl.frame(cam, light, no_occl));
            gl.iso.set_frustum_culling(false);
            t_nofr.push_back(gl.frame(cam, light, o));
            nofr = gl.iso.stats(0);
            gl.iso.set_frustum_culling(true);
            gl.iso.set_tetrahedron_culling(false);
            t_notet.push_back(gl.frame(cam, light, o));
            notet = gl.iso.stats(0);
        }
        gl.iso.set_tetrahedron_culling(true);
        // (one more frame, not timed: the culled count, and the image against the unculled one)
        gl.frame(cam, light, o);
        on = gl.iso.stats(0);
        const render::Image img_on = gl.quadrics.read();
        gl.frame(cam, light, no_occl);
        const Diff od = image_diff(img_on, gl.quadrics.read());
        if (od.coverage != 0 || od.depth != 0 || od.colour != 0)
            std::printf("occlusion culling changed the %s image: %ld coverage, %ld colour differences, max depth difference %.2g\n", dist > 1 ? "whole" : "close-up",
                        od.coverage, od.colour, od.depth);
        const double base = median(t_on);
        std::printf("%-9s %10zu %8zu %4.1f%% %6zu %4.1f%% %14zu %14zu %14zu %12.1f %8.1f %4.2fx %8.1f %4.2fx %8.1f %4.2fx %7zu %5.1f%% %8.1f %4.2fx\n", dist > 1 ? "whole" : "close-up", cubes,
                    on.active, 100.0 * double(on.active) / double(cubes), on.visible, 100.0 * double(on.visible) / double(on.active), on.elements, on_gpu.elements,
                    notet.elements, base, median(t_nofr), median(t_nofr) / base, median(t_notet), median(t_notet) / base, median(t_gpu), median(t_gpu) / base,
                    on.occluded, 100.0 * double(on.occluded) / double(std::max<std::size_t>(1, on.elements)), median(t_noocc), median(t_noocc) / base);
        (void)nofr;
    }
    compare_qss_methods(gl, m, light, o, a);
    std::printf("\n(GL ms: the renderer's defaults, the last frame's shown set drawn first (RenderOptions::occlusion_reuse), the coefficients where\n"
                " CoefficientStage::automatic puts them ('coeffs': averaged in the vertex stage, or in the compute pre-pass); GL vertex, GL pre-pass:\n"
                " the coefficients always in the one or the other, and the ratio to GL ms (> 1: the default is faster); GL no reuse: occlusion\n"
                " culling in phases only, and its ratio; GL ms comes from frames interleaved with other settings, so each tests every element\n"
                " against the set's depth; GL still: the same view and settings frame after frame, the set drawn alone without a test\n"
                " (IsoDrawStats::unchanged_view; '*': not in every frame), its ratio to GL ms, and CPU/still)\n");
    std::printf("(range has rho: the octree keeps the cubes whose coefficient range contains the isovalue; in frustum: of these, the ones\n"
                " whose box is not outside the view; tets drawn: relevant tetrahedra of those cubes; tets (GPU): the relevant tetrahedra the GPU\n"
                " element list keeps (each cube's box tested on the GPU); no test: all 24 per cube; GPU list: the frame with the element list\n"
                " built on the GPU (IsosurfaceRenderer::ElementList::gpu) instead of the octree's uploaded from the CPU, and its ratio;\n"
                " occluded: tetrahedra outside the last frame's shown set culled behind what it drew, and their share of the tetrahedra;\n"
                " no occlusion: the frame with occlusion culling off, and its ratio; GL no occlusion likewise)\n");
}

}  // namespace

void add_bench_isosurfaces(CLI::App& bench) {
    auto a = std::make_shared<IsoBenchOptions>();
    CLI::App* cmd = bench.add_subcommand("isosurfaces", "GL isosurfaces (QSS, S31, trilinear) vs the CPU reference; octree and frustum culling");
    cmd->add_option("--volume", a->input, "volume file (INR, NRRD, OFF -> signed distance); default CGAL's skull");
    cmd->add_option("--iso", a->iso, "isovalue (default 2.9 for the skull)")->each([a](const std::string&) { a->iso_given = true; });
    cmd->add_option("--frames", a->frames, "GL frames per measurement")->check(CLI::Range(1, 1000));
    cmd->add_option("--cpu-frames", a->cpu_frames, "CPU reference frames per scheme")->check(CLI::Range(1, 100));
    cmd->add_option("--width", a->width)->check(CLI::Range(16, 8192));
    cmd->add_option("--height", a->height)->check(CLI::Range(16, 8192));
    cmd->add_option("--png", a->png, "also write PREFIX_<scheme>_gl.png and _cpu.png");
    cmd->callback([a] { run(*a); });
}

}  // namespace quadcast::cli
