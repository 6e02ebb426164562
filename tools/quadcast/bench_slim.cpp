// tools/quadcast/bench_slim.cpp -- `quadcast bench slim`: SLIM surfaces against edge-collapsed meshes of the same error
//
// Per mesh (CGAL's bunny00.off, ChineseDragon-10kv.off, armadillo.off from --data, or --mesh
// files) and per error threshold E (relative to the bounding-box diagonal):
//  - SLIM: the mesh sampled to oriented points (`slim::read_points`, default samples), built with
//    `slim::build` at E (build time, balls), drawn by the GL three-pass renderer
//    (`gl::SlimRenderer` in a `gl::QuadricRenderer`) with 32-bit float accumulation targets by
//    default: with 16-bit ones the blended ray parameter sum(w lambda) / sum(w) carries half-float
//    rounding, about 2^-11 lambda, which is more than the fit's error at E = 1e-3.
//  - The mesh simplified by CGAL's edge collapse (bench_slim_cgal.hpp; Lindstrom-Turk) to the
//    edge count whose error, measured as below, is closest to the SLIM surface's RMS error
//    (bisection on the logarithm of the edge count, each candidate collapsed from the original
//    mesh), drawn by `gl::MeshRenderer` (area-weighted vertex normals).
// The error of an approximation, along camera rays: an orthographic view of the mesh from the
// direction (0.35, 0.3, 1) (up +y); per pixel hit by both the original mesh (drawn by
// gl::MeshRenderer) and the approximation, the approximation's hit point (origin + λ dir, λ from
// its GL window depth, `lambda_from_depth`) and its Euclidean distance to the original mesh
// (CGAL AABB tree), relative to the bounding-box diagonal: RMS and maximum. Pixels hit by only
// one of the two are counted.
// Frame times: every renderer of a model (the original mesh, each SLIM surface, each simplified
// mesh) draws one frame in turn, `--frames` rounds (after one untimed round); medians. Ratios of
// one run.
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "bench_slim_cgal.hpp"
#include "bench_spline_error.hpp"
#include "commands.hpp"
#include "plot.hpp"
#include "timing.hpp"
#include "quadcast/camera.hpp"
#include "quadcast/gl/mesh_renderer.hpp"
#include "quadcast/gl/osmesa_context.hpp"
#include "quadcast/gl/quadric_renderer.hpp"
#include "quadcast/gl/slim_renderer.hpp"
#include "quadcast/image/image_io.hpp"
#include "quadcast/render/cpu_renderer.hpp"
#include "quadcast/scene/off.hpp"
#include "quadcast/scene/scene_render.hpp"
#include "quadcast/slim/slim.hpp"

namespace quadcast::cli {

namespace {

using Clock = std::chrono::steady_clock;

struct SlimBenchOptions {
    std::string data = "build/data";
    std::vector<std::string> meshes;  ///< --mesh: these instead of the three CGAL models
    std::vector<double> errors{4e-3, 2e-3, 1e-3};
    std::size_t samples = 0;          ///< oriented samples per mesh (0: slim::read_points' default)
    int frames = 5, width = 1024, height = 768, threads = 0, steps = 8;
    int slim_bits = 32;               ///< accumulation targets of the SLIM renderer
    std::string plot = "slim";
    std::string png;                  ///< PREFIX of the pictures ("": none)
};

struct ModelFile {
    std::string name;
    std::filesystem::path path;
};

/// The OFF mesh as triangles (polygons fanned from their first vertex).
TriangleMesh read_triangles(const std::filesystem::path& path) {
    const scene::OffMesh off = scene::read_off(path);
    TriangleMesh m;
    m.positions = off.vertices;
    for (const auto& f : off.faces)
        for (std::size_t k = 1; k + 1 < f.size(); ++k)
            m.triangles.push_back({std::uint32_t(f[0]), std::uint32_t(f[k]), std::uint32_t(f[k + 1])});
    return m;
}

/// A GL mesh: positions mapped by `to_frame`, area-weighted vertex normals (a vertex of no area
/// gets +z: the renderer rejects zero normals).
gl::Mesh gl_mesh(const TriangleMesh& m, const render::FrameTransform& to_frame) {
    gl::Mesh g;
    std::vector<Vec3<double>> n(m.positions.size(), Vec3<double>{{0.0, 0.0, 0.0}});
    for (const auto& t : m.triangles) {
        const Vec3<double> a = m.positions[t[0]], b = m.positions[t[1]], c = m.positions[t[2]];
        const Vec3<double> fn = cross(b - a, c - a);
        for (const std::uint32_t v : t) n[v] = n[v] + fn;
    }
    for (std::size_t i = 0; i < m.positions.size(); ++i) {
        g.positions.push_back(cast<float>(to_frame.point(m.positions[i])));
        const double l = length(n[i]);
        g.normals.push_back(l > 0 ? cast<float>(n[i] / l) : vec3(0.0f, 0.0f, 1.0f));
    }
    for (const auto& t : m.triangles) g.indices.insert(g.indices.end(), t.begin(), t.end());
    g.color = vec3(0.8f, 0.8f, 0.8f);
    return g;
}

/// The bench's view of a mesh with bounding box [lo, hi] (see the top of this file).
scene::Camera bench_camera(const Vec3<double>& lo, const Vec3<double>& hi) {
    const Vec3<double> centre = (lo + hi) * 0.5;
    const double diag = length(hi - lo);
    scene::Camera c;
    c.projection = scene::Projection::orthographic;
    c.target = centre;
    c.eye = centre + normalize(Vec3<double>{{0.35, 0.3, 1.0}}) * (1.5 * diag);
    c.up = Vec3<double>{{0.0, 1.0, 0.0}};
    c.height = 0.8 * diag;
    c.near = 0.5 * diag;
    c.far = 2.5 * diag;
    return c;
}

/// The distance statistics of an approximation against the original mesh (see the top).
struct Distance {
    long measured = 0, only_approx = 0, only_mesh = 0;
    double rms = 0, max = 0, median = 0;  ///< relative to the diagonal
    /// The distance per pixel (window order), -1 where only the approximation is hit, -2 where only
    /// the mesh, NaN where neither.
    std::vector<float> per_pixel;
};

Distance measure(const LambdaImage& approx, const render::Camera& cam, const render::FrameTransform& to_frame, const LambdaImage& reference,
                 const MeshDistance& mesh, double diagonal, int threads) {
    const render::FrameSetup f = render::frame_setup(cam, approx.width, approx.height);
    const int n_threads = threads > 0 ? threads : int(std::max(1u, std::thread::hardware_concurrency()));
    struct Acc {
        long measured = 0, only_approx = 0, only_mesh = 0;
        double sum2 = 0, max = 0;
        std::vector<double> all;
    };
    std::vector<Acc> per(static_cast<std::size_t>(n_threads));
    Distance out;
    out.per_pixel.assign(approx.lambda.size(), std::numeric_limits<float>::quiet_NaN());
    render::cpu_detail::parallel_for(approx.height, n_threads, [&](int y, int th) {
        Acc& a = per[static_cast<std::size_t>(th)];
        for (int x = 0; x < approx.width; ++x) {
            const std::size_t i = std::size_t(y) * approx.width + x;
            const bool hit = !std::isnan(approx.lambda[i]), ref = !std::isnan(reference.lambda[i]);
            if (hit != ref) {
                ++(hit ? a.only_approx : a.only_mesh);
                out.per_pixel[i] = hit ? -1.0f : -2.0f;
                continue;
            }
            if (!hit) continue;
            const render::PixelRay ray = render::pixel_ray(f, x, y);
            Vec3<double> p{};
            for (int k = 0; k < 3; ++k)
                p[k] = to_frame.offset[k] + to_frame.scale * (double(ray.origin[k]) + double(approx.lambda[i]) * double(ray.dir[k]));
            const double d = mesh.distance(p) / diagonal;
            ++a.measured;
            out.per_pixel[i] = float(d);
            a.all.push_back(d);
            a.sum2 += d * d;
            a.max = std::max(a.max, d);
        }
    });
    double sum2 = 0;
    std::vector<double> all;
    for (const Acc& a : per) {
        all.insert(all.end(), a.all.begin(), a.all.end());
        out.measured += a.measured;
        out.only_approx += a.only_approx;
        out.only_mesh += a.only_mesh;
        sum2 += a.sum2;
        out.max = std::max(out.max, a.max);
    }
    out.rms = out.measured ? std::sqrt(sum2 / double(out.measured)) : std::numeric_limits<double>::quiet_NaN();
    out.median = median(std::move(all));
    return out;
}

/// A picture of `Distance::per_pixel`: white where neither is hit, blue where only the
/// approximation is, green where only the mesh is; the distance d from light grey (0) to red
/// (d >= `full`).
render::Image error_map(const Distance& d, int width, int height, double full) {
    render::Image img;
    img.width = width;
    img.height = height;
    img.rgba.assign(std::size_t(width) * height * 4, 255);
    img.depth.assign(std::size_t(width) * height, 1.0f);
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            const float v = d.per_pixel[std::size_t(y) * width + x];
            std::uint8_t* px = &img.rgba[(std::size_t(height - 1 - y) * width + x) * 4];
            if (std::isnan(v)) continue;
            if (v == -1.0f) px[0] = 0, px[1] = 0, px[2] = 255;
            else if (v == -2.0f) px[0] = 0, px[1] = 160, px[2] = 0;
            else {
                const double t = std::min(1.0, double(v) / full);
                px[0] = std::uint8_t(std::lround(200 + 55 * t));
                px[1] = px[2] = std::uint8_t(std::lround(200 * (1 - t)));
            }
        }
    return img;
}

/// One GL mesh renderer with its mesh.
struct MeshDraw {
    std::unique_ptr<gl::MeshRenderer> r;
    std::size_t triangles = 0;
};

MeshDraw make_mesh_draw(gl::OsmesaContext& ctx, const TriangleMesh& m, const render::FrameTransform& to_frame) {
    MeshDraw d;
    d.r = std::make_unique<gl::MeshRenderer>(ctx.api());
    d.r->set_meshes({gl_mesh(m, to_frame)});
    d.triangles = m.triangles.size();
    return d;
}

render::RenderOptions mesh_options(const render::Frame& fr) {
    render::RenderOptions o;
    o.width = fr.options.width;
    o.height = fr.options.height;
    o.background = fr.options.background;
    o.material = fr.options.material;
    return o;
}

/// One SLIM surface: its build, its frame and its GL renderer.
struct SlimRow {
    double error = 0;
    slim::BuildStats stats;
    render::Frame frame;
    std::unique_ptr<gl::QuadricRenderer> quadrics;
    std::unique_ptr<gl::SlimRenderer> slim;
    Distance dist;
    // The matched simplified mesh
    MeshDraw mesh;
    std::size_t edges = 0;
    Distance mesh_dist;
    int mesh_candidates = 0;
    double simplify_s = 0;  ///< of the matched mesh, from the original
    double slim_ms = 0, mesh_ms = 0;
};

std::string fmt(const char* f, double v) {
    char buf[64];
    std::snprintf(buf, sizeof buf, f, v);
    return buf;
}

void run_bench_slim(const SlimBenchOptions& opt) {
    std::vector<ModelFile> models;
    if (opt.meshes.empty()) {
        const std::filesystem::path dir(opt.data);
        models = {{"bunny", dir / "bunny00.off"}, {"dragon", dir / "ChineseDragon-10kv.off"}, {"armadillo", dir / "armadillo.off"}};
    } else {
        for (const std::string& m : opt.meshes) models.push_back({std::filesystem::path(m).stem().string(), m});
    }
    for (const double e : opt.errors)
        if (!(e > 0) || !std::isfinite(e)) throw std::invalid_argument("--errors: every threshold must be positive and finite (got " + fmt("%g", e) + ")");
    if (!opt.plot.empty()) {
        const std::filesystem::path dir = std::filesystem::path(opt.plot).parent_path();
        if (!dir.empty() && !std::filesystem::is_directory(dir))
            throw std::invalid_argument("--plot " + opt.plot + ": directory '" + dir.string() + "' does not exist");
    }
    const unsigned hw = std::max(1u, std::thread::hardware_concurrency());
    gl::OsmesaContext ctx;
    std::printf("quadcast bench slim: %dx%d orthographic, view direction (0.35, 0.3, 1), %d timed rounds (median; every renderer one frame per round), "
                "%u threads, SLIM targets %d-bit float, %s\n",
                opt.width, opt.height, opt.frames, opt.threads > 0 ? unsigned(opt.threads) : hw, opt.slim_bits, ctx.info().renderer.c_str());
    std::printf("error = distance of each pixel's hit point to the original mesh (CGAL AABB tree), over the pixels both hit, relative to the "
                "bounding-box diagonal; the simplified mesh is CGAL's edge collapse (Lindstrom-Turk) to the edge count whose RMS error is "
                "closest to the SLIM surface's\n");
    std::vector<std::string> skipped;
    for (const ModelFile& mf : models) {
        if (!std::filesystem::exists(mf.path)) {
            skipped.push_back(mf.name + ": " + mf.path.string() + " not found");
            continue;
        }
        // The original mesh, its distance tree, the oriented samples
        const TriangleMesh original = read_triangles(mf.path);
        Vec3<double> lo = original.positions.front(), hi = lo;
        for (const Vec3<double>& p : original.positions)
            for (int k = 0; k < 3; ++k) lo[k] = std::min(lo[k], p[k]), hi[k] = std::max(hi[k], p[k]);
        const double diagonal = length(hi - lo);
        const std::size_t edges0 = original.edge_count();
        const MeshDistance tree(original);
        slim::ReadOptions ro;
        ro.mesh_samples = opt.samples;
        const slim::OrientedPoints pts = slim::read_points(mf.path, ro);
        const scene::Camera view = bench_camera(lo, hi);
        std::printf("\n%s (%s): %zu vertices, %zu triangles, %zu edges, diagonal %.6g, %zu oriented samples\n", mf.name.c_str(), mf.path.string().c_str(),
                    original.positions.size(), original.triangles.size(), edges0, diagonal, pts.size());
        std::fflush(stdout);

        // The reference: the original mesh, in the world frame (the camera of an empty scene)
        scene::Scene base;
        base.camera = view;
        base.lights.push_back(scene::Light{});
        const render::Frame world = render::build_frame(base, opt.width, opt.height);
        MeshDraw reference = make_mesh_draw(ctx, original, world.transform);
        reference.r->draw(world.camera, world.light, mesh_options(world));
        const LambdaImage ref_lambda = lambda_from_depth(reference.r->read(), world.camera);

        // The SLIM surfaces
        std::vector<SlimRow> rows;
        for (const double e : opt.errors) {
            SlimRow row;
            row.error = e;
            slim::BuildOptions bo;
            bo.error = e;
            bo.threads = opt.threads;
            const slim::BuildResult b = slim::build(pts, bo);
            row.stats = b.stats;
            scene::Scene s = base;
            scene::Slim so;
            so.material.color = Vec3<double>{{0.8, 0.8, 0.8}};
            so.balls = slim::scene_balls(b.model);
            s.slims.push_back(std::move(so));
            row.frame = render::build_frame(s, opt.width, opt.height);
            row.quadrics = std::make_unique<gl::QuadricRenderer>(ctx.api());
            row.slim = std::make_unique<gl::SlimRenderer>(ctx.api());
            row.slim->set_precision(opt.slim_bits);
            row.quadrics->set_primitives({});
            row.slim->set_balls(row.frame.slim_balls);
            row.quadrics->add_pass(*row.slim);
            row.quadrics->draw(row.frame.camera, row.frame.light, row.frame.options);
            const render::Image img = row.quadrics->read();
            row.dist = measure(lambda_from_depth(img, row.frame.camera), row.frame.camera, row.frame.transform, ref_lambda, tree, diagonal, opt.threads);
            if (!opt.png.empty()) {
                render::write_png(opt.png + "_" + mf.name + "_" + fmt("%g", e) + "_slim.png", img);
                render::write_png(opt.png + "_" + mf.name + "_" + fmt("%g", e) + "_slim_error.png", error_map(row.dist, opt.width, opt.height, e));
            }
            rows.push_back(std::move(row));
        }

        // The simplified meshes: bisection on log(edges) for the SLIM surface's RMS error
        for (SlimRow& row : rows) {
            const double target = row.dist.rms;
            double lo_e = std::max(12.0, double(edges0) / 4096.0), hi_e = double(edges0);  // (error above / below the target)
            double best_score = HUGE_VAL;
            TriangleMesh best;
            for (int step = 0; step < opt.steps; ++step) {
                const auto edges = static_cast<std::size_t>(std::llround(std::sqrt(lo_e * hi_e)));
                const auto t0 = Clock::now();
                TriangleMesh m = simplify_triangles(original, edges);
                const double simplify_s = ms_since(t0) / 1000.0;
                MeshDraw d = make_mesh_draw(ctx, m, world.transform);
                d.r->draw(world.camera, world.light, mesh_options(world));
                const Distance dist = measure(lambda_from_depth(d.r->read(), world.camera), world.camera, world.transform, ref_lambda, tree, diagonal,
                                              opt.threads);
                ++row.mesh_candidates;
                const double score = std::abs(std::log(dist.rms / target));
                if (score < best_score) {
                    best_score = score;
                    row.edges = edges;
                    row.mesh_dist = dist;
                    row.simplify_s = simplify_s;
                    best = std::move(m);
                }
                (dist.rms > target ? lo_e : hi_e) = double(edges);
            }
            row.mesh = make_mesh_draw(ctx, best, world.transform);
            if (!opt.png.empty()) {
                row.mesh.r->draw(world.camera, world.light, mesh_options(world));
                render::write_png(opt.png + "_" + mf.name + "_" + fmt("%g", row.error) + "_mesh.png", row.mesh.r->read());
                render::write_png(opt.png + "_" + mf.name + "_" + fmt("%g", row.error) + "_mesh_error.png",
                                  error_map(row.mesh_dist, opt.width, opt.height, row.error));
            }
        }

        // Frame times, interleaved: one frame of every renderer per round
        std::vector<double> ref_ms;
        std::vector<std::vector<double>> slim_ms(rows.size()), mesh_ms(rows.size());
        for (int round = -1; round < opt.frames; ++round) {
            auto t0 = Clock::now();
            reference.r->draw(world.camera, world.light, mesh_options(world));
            if (round >= 0) ref_ms.push_back(ms_since(t0));
            for (std::size_t i = 0; i < rows.size(); ++i) {
                t0 = Clock::now();
                rows[i].quadrics->draw(rows[i].frame.camera, rows[i].frame.light, rows[i].frame.options);
                if (round >= 0) slim_ms[i].push_back(ms_since(t0));
                t0 = Clock::now();
                rows[i].mesh.r->draw(world.camera, world.light, mesh_options(world));
                if (round >= 0) mesh_ms[i].push_back(ms_since(t0));
            }
        }
        for (std::size_t i = 0; i < rows.size(); ++i) {
            rows[i].slim_ms = median(slim_ms[i]);
            rows[i].mesh_ms = median(mesh_ms[i]);
        }

        std::printf("original mesh: %zu triangles, frame %.1f ms\n", original.triangles.size(), median(ref_ms));
        std::printf("%-10s %7s %6s %7s %8s %8s %8s %9s %8s | %9s %5s %8s %8s %8s %9s %8s | %7s\n", "model", "E", "balls", "build s", "median", "rms", "max",
                    "px only", "frame ms", "triangles", "cand.", "median", "rms", "max", "px only", "frame ms", "slim/mesh");
        for (const SlimRow& r : rows) {
            std::printf("%-10s %7.1e %6zu %7.2f %8.2e %8.2e %8.2e %4ld/%-4ld %8.1f | %9zu %5d %8.2e %8.2e %8.2e %4ld/%-4ld %8.1f | %7.2fx\n", mf.name.c_str(),
                        r.error, r.stats.balls, r.stats.seconds, r.dist.median, r.dist.rms, r.dist.max, r.dist.only_approx, r.dist.only_mesh, r.slim_ms,
                        r.mesh.triangles, r.mesh_candidates, r.mesh_dist.median, r.mesh_dist.rms, r.mesh_dist.max, r.mesh_dist.only_approx,
                        r.mesh_dist.only_mesh, r.mesh_ms, r.slim_ms / r.mesh_ms);
        }
        std::fflush(stdout);

        if (!opt.plot.empty()) {
            LogLogPlot p;
            p.title = mf.name + ": error along camera rays vs GL frame time";
            p.x_label = "frame time (ms, llvmpipe), " + std::to_string(opt.width) + "x" + std::to_string(opt.height);
            p.y_label = "RMS distance to the mesh / diagonal";
            PlotSeries ss, ms;
            ss.name = "SLIM (label: E)";
            ms.name = "CGAL edge collapse (label: triangles)";
            for (const SlimRow& r : rows) {
                ss.x.push_back(r.slim_ms);
                ss.y.push_back(r.dist.rms);
                ss.labels.push_back(fmt("%g", r.error));
                ms.x.push_back(r.mesh_ms);
                ms.y.push_back(r.mesh_dist.rms);
                ms.labels.push_back(std::to_string(r.mesh.triangles));
            }
            p.series = {ss, ms};
            const std::string path = opt.plot + "_" + mf.name + ".png";
            render::write_png(path, draw_loglog(p, 800, 600));
            std::printf("wrote %s\n", path.c_str());
        }
    }
    for (const std::string& s : skipped) std::printf("skipped %s\n", s.c_str());
    if (!skipped.empty()) std::printf("(fetch the data files with `make data` or tools/fetch_cgal_data.sh, or point --data at them)\n");
}

}  // namespace

void add_bench_slim(CLI::App& bench) {
    auto o = std::make_shared<SlimBenchOptions>();
    CLI::App* cmd = bench.add_subcommand("slim", "SLIM surfaces vs CGAL-simplified meshes of the same error along camera rays: build, balls, error, GL frame time");
    cmd->add_option("--data", o->data, "directory of bunny00.off, ChineseDragon-10kv.off, armadillo.off (default build/data)");
    cmd->add_option("--mesh", o->meshes, "OFF meshes to measure instead of the three CGAL models")->delimiter(',');
    cmd->add_option("--errors", o->errors, "SLIM error thresholds, relative to the bounding-box diagonal (default 4e-3,2e-3,1e-3)")->delimiter(',');
    cmd->add_option("--samples", o->samples, "oriented samples drawn from each mesh (default: slim-build's, the vertex count and at least 100000)");
    cmd->add_option("--frames", o->frames, "timed rounds (median)")->check(CLI::Range(1, 1000));
    cmd->add_option("--width", o->width, "image width")->check(CLI::Range(16, 8192));
    cmd->add_option("--height", o->height, "image height")->check(CLI::Range(16, 8192));
    cmd->add_option("--slim-bits", o->slim_bits, "SLIM accumulation targets: 32 (RGBA32F, default) or 16 (RGBA16F: the blended depth then carries "
                                                 "the half-float rounding of sum w lambda)")
        ->check(CLI::IsMember({16, 32}));
    cmd->add_option("--threads", o->threads, "threads of the build and of the error measurement (0: all cores)");
    cmd->add_option("--steps", o->steps, "bisection steps of the simplified mesh's edge count")->check(CLI::Range(1, 40));
    cmd->add_option("--plot", o->plot, "write PREFIX_<model>.png: log-log RMS error vs frame time (\"\": no plot)");
    cmd->add_option("--png", o->png, "write PREFIX_<model>_<E>_slim.png and ..._mesh.png (default: none)");
    cmd->callback([o] {
        try {
            run_bench_slim(*o);
        } catch (const std::exception& e) {
            std::fprintf(stderr, "quadcast bench slim: %s\n", e.what());
            throw CLI::RuntimeError(2);
        }
    });
}

}  // namespace quadcast::cli
