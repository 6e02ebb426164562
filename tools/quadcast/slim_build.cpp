// tools/quadcast/slim_build.cpp -- `quadcast slim-build`: a SLIM model from an oriented point cloud or a mesh
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>
#include <string>

#include "commands.hpp"
#include "quadcast/slim/slim.hpp"

namespace quadcast::cli {

void add_slim_build(CLI::App& app) {
    struct Options {
        std::string input, output;
        double error = 0;
        slim::BuildOptions build;
        slim::ReadOptions read;
        bool no_sharp = false, no_corners = false, no_saddles = false, no_tangent_planes = false, no_support = false;
        bool quiet = false;
    };
    auto opt = std::make_shared<Options>();
    CLI::App* cmd = app.add_subcommand("slim-build", "build a SLIM model (balls holding quadrics) from oriented points (.xyz, .pwn, .ply) or an OFF mesh");
    cmd->add_option("input", opt->input, "oriented points (.xyz/.pwn 'x y z nx ny nz', .ply with nx ny nz) or an .off mesh (sampled)")->required();
    cmd->add_option("-o,--output", opt->output, "model file to write (quadcast-slim text format)")->required();
    cmd->add_option("--error", opt->error, "maximum fit distance, relative to the bounding-box diagonal (> 0), e.g. 1e-3")->required();
    cmd->add_option("--samples", opt->read.mesh_samples, "mesh input: oriented samples to draw (default: the vertex count, at least 100000)");
    cmd->add_option("--seed", opt->build.seed, "seed of the seed-point order (and of the mesh sampler)");
    cmd->add_option("--threads", opt->build.threads, "worker threads (0: all; the model is the same for any count)");
    cmd->add_option("--cover", opt->build.cover_fraction, "points within this fraction of a ball's radius are covered by it")->check(CLI::Range(0.05, 1.0));
    cmd->add_flag("--no-sharp", opt->no_sharp, "no sharp-feature pairs or corners (one quadric per ball)");
    cmd->add_flag("--no-corners", opt->no_corners, "sharp pairs but no corners (a corner's faces left to smaller balls)");
    cmd->add_flag("--no-saddles", opt->no_saddles, "corner triples but no saddle corners (four records; a saddle's faces left to smaller balls)");
    cmd->add_flag("--no-tangent-planes", opt->no_tangent_planes, "a sharp pair's faces both ended by one plane between them, not each by the other's tangent plane");
    cmd->add_flag("--no-support", opt->no_support, "accept fits whose zero set leaves the input points inside the ball (no support check)");
    cmd->add_flag("--quiet", opt->quiet, "no progress on stderr");
    cmd->callback([opt] {
        try {
            if (!(opt->error > 0) || !std::isfinite(opt->error))
                throw std::invalid_argument("--error must be positive and finite (got " + std::to_string(opt->error) + ")");
            opt->read.seed = opt->build.seed;
            const auto t0 = std::chrono::steady_clock::now();
            const slim::OrientedPoints pts = slim::read_points(opt->input, opt->read);
            const double read_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
            for (const auto& w : pts.warnings) std::cerr << w.to_string() << "\n";
            opt->build.error = opt->error;
            opt->build.sharp_features = !opt->no_sharp;
            opt->build.corners = !opt->no_corners;
            opt->build.saddle_corners = !opt->no_saddles;
            opt->build.pair_tangent_planes = !opt->no_tangent_planes;
            opt->build.support_check = !opt->no_support;
            if (!opt->quiet)
                opt->build.progress = [last = std::chrono::steady_clock::now()](const slim::BuildProgress& p) mutable {
                    const auto now = std::chrono::steady_clock::now();
                    if (now - last < std::chrono::seconds(1) && p.covered < p.total) return;
                    last = now;
                    std::fprintf(stderr, "\rslim-build: %zu / %zu points covered, %zu balls", p.covered, p.total, p.balls);
                    if (p.covered == p.total) std::fprintf(stderr, "\n");
                };
            const slim::BuildResult r = slim::build(pts, opt->build);
            slim::write_model(opt->output, r.model);
            const slim::BuildStats& s = r.stats;
            std::printf("input %s: %zu oriented points (read in %.3f s), bounding-box diagonal %.6g\n", opt->input.c_str(), s.points, read_s, s.diagonal);
            std::printf("threshold %.3g of the diagonal = %.6g\n", opt->error, s.threshold);
            std::printf("balls %zu (sharp pairs %zu, corners %zu of which saddles %zu, forced %zu over the threshold)\n", s.balls, s.sharp_pairs, s.corners,
                        s.saddles, s.forced);
            std::printf("build time %.3f s (%zu fits, %zu seeds dropped)\n", s.seconds, s.fits, s.dropped_seeds);
            std::printf("fit distance over the input points: rms %.6g (%.3g of the diagonal), max %.6g (%.3g), %zu points over the threshold\n",
                        s.rms_distance, s.rms_distance / s.diagonal, s.max_distance, s.max_distance / s.diagonal, s.over_threshold);
            std::printf("wrote %s\n", opt->output.c_str());
        } catch (const std::exception& e) {
            std::cerr << "quadcast slim-build: " << e.what() << "\n";
            throw CLI::RuntimeError(2);
        }
    });
}

}  // namespace quadcast::cli
