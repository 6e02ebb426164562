// tools/quadcast/bench_spline_preprocess.cpp -- `quadcast bench spline-preprocess`: the CPU
// preprocessing of QSS and S31 splines per data set, in the shape of Kalbe & Zeilfelder 2008, Table 1
//
// Per model and scheme, one run on `--threads` threads:
//   determining sets  build_spline<Q> (D2 = 20 / D3 = 56 values per cube, from the 27-point stencils)
//   ranges            cube_coefficient_ranges<Q> (per cube the range of all BB-coefficients)
//   octree            MinMaxOctree over those ranges
//   active cubes      cubes whose coefficient range contains the stated isovalue (octree query)
//   memory            float storage of the determining sets of all cubes (what the renderer keeps)
//                     against the full per-tetrahedron BB-form of all cubes (24 tetrahedra x 10
//                     (QSS) or 20 (S31) coefficients), and their ratio; and the BB-form of the
//                     active cubes only (what the CPU renderer keeps per isovalue)
// Loading (and the signed distance of the bunny) is not part of the preprocessing and is timed
// apart. A model whose file is missing from --data is skipped with a message; a scheme whose
// determining sets alone would exceed --max-memory-gb is skipped with its sizes printed.
#include <algorithm>
#include <bit>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "commands.hpp"
#include "quadcast/render/spline_cpu_renderer.hpp"
#include "quadcast/volume/load.hpp"
#include "quadcast/spline/octree.hpp"

namespace quadcast::cli {

namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

struct PreprocessOptions {
    std::string data = "build/data";
    unsigned threads = 0;
    int sdf_size = 96;
    double max_memory_gb = 4.0;
};

struct Model {
    std::string name;
    volume::VolumeRequest request;
    double iso;
    std::string iso_note;
    bool file;  ///< read from --data (may be missing)
};

double mib(double bytes) { return bytes / (1024.0 * 1024.0); }

template <int Q>
void run_scheme(const std::string& name, const volume::VolumeData& v, double iso, const PreprocessOptions& opt) {
    const double cubes = double(v.voxel_count());
    const double d_bytes = cubes * spline::d_count(Q) * sizeof(float);
    const double bb_bytes = cubes * spline::tets_per_cube * bb::coefficient_count(Q) * sizeof(float);
    const char* scheme = Q == 2 ? "QSS" : "S31";
    if (d_bytes > opt.max_memory_gb * 1024.0 * 1024.0 * 1024.0) {
        std::printf("%-12s %-4s %9.1f %9.1f %6.2f %10s %9s %9s %9s %10s %9s   skipped: the determining sets need %.2f GiB > --max-memory-gb %g\n",
                    name.c_str(), scheme, mib(d_bytes), mib(bb_bytes), bb_bytes / d_bytes, "-", "-", "-", "-", "-", "-", d_bytes / (1u << 30),
                    opt.max_memory_gb);
        return;
    }
    auto t0 = Clock::now();
    const spline::SplineGrid<Q, float> g = spline::build_spline<Q>(v.grid, Vec<double, 3>{{0.0, 0.0, 0.0}}, 1.0, opt.threads);
    const double t_d = seconds_since(t0);
    t0 = Clock::now();
    std::vector<spline::Range<float>> ranges = spline::cube_coefficient_ranges<Q>(g, opt.threads);
    const double t_r = seconds_since(t0);
    t0 = Clock::now();
    const spline::MinMaxOctree<float> tree(g.nx, g.ny, g.nz, std::move(ranges), g.origin, g.h);
    const double t_o = seconds_since(t0);
    const std::size_t active = tree.active_cubes(float(iso)).size();
    const double active_bb = double(active) * spline::tets_per_cube * bb::coefficient_count(Q) * sizeof(float);
    std::printf("%-12s %-4s %9.1f %9.1f %6.2f %10.1f %9.3f %9.3f %9.3f %10zu %9.3f\n", name.c_str(), scheme, mib(d_bytes), mib(bb_bytes),
                bb_bytes / d_bytes, mib(active_bb), t_d, t_r, t_o, active, t_d + t_r + t_o);
    std::fflush(stdout);
}

/// What the renderer keeps: `render::prepare_volume` for the GL renderer (streaming over the
/// cubes, the cheap data-range test first, the determining sets of the active cubes only).
void run_renderer_prep(const std::string& name, const volume::VolumeData& v, double iso, render::VolumeScheme scheme, const PreprocessOptions& opt) {
    const auto t0 = Clock::now();
    const render::VolumeModel m = render::prepare_volume(v.grid, v.origin, v.spacing, scheme, float(iso), {{0.8f, 0.8f, 0.8f}}, opt.threads, false);
    const double t = seconds_since(t0);
    std::size_t relevant = 0;
    for (std::uint32_t mask : m.tet_mask) relevant += static_cast<std::size_t>(std::popcount(mask));
    std::size_t octree_bytes = 0;
    for (int l = 0; l < m.octree.level_count(); ++l) octree_bytes += m.octree.level(l).range.size() * sizeof(spline::Range<float>);
    const double kept = double(m.dsets.size() * sizeof(float) + m.cubes.size() * sizeof(std::int32_t) + m.tet_mask.size() * sizeof(std::uint32_t));
    const int q = scheme == render::VolumeScheme::qss ? 2 : 3;
    const double full = double(m.active) * spline::tets_per_cube * bb::coefficient_count(q) * sizeof(float);
    std::printf("%-12s %-4s %9.3f %10zu %10zu %12.2f %12.2f %9.2f %12.2f\n", name.c_str(), q == 2 ? "QSS" : "S31", t, m.active, relevant, mib(kept),
                mib(full), full / kept, mib(double(octree_bytes) + double(m.slot.size() * sizeof(std::int32_t))));
    std::fflush(stdout);
}

void run_spline_preprocess(const PreprocessOptions& opt) {
    const std::filesystem::path dir(opt.data);
    auto file_request = [&](const char* file, int size = 0) {
        volume::VolumeRequest r;
        r.input = (dir / file).string();
        r.size = size;
        return r;
    };
    auto synthetic = [](const char* input, int size) {
        volume::VolumeRequest r;
        r.input = input;
        r.size = size;
        return r;
    };
    const std::vector<Model> models = {
        {"skull", file_request("skull_2.9.inr"), 2.9, "2.9 (the file's name)", true},
        {"liver", file_request("liver.inr.gz"), 128.0, "128 (label 255 against 0/85/127)", true},
        {"ML 64", synthetic("marschner-lobb", 64), 0.5, "0.5", false},
        {"ML 128", synthetic("marschner-lobb", 128), 0.5, "0.5", false},
        {"bunny SDF", file_request("bunny00.off", opt.sdf_size), 0.0, "0 (the surface)", true},
    };
    const unsigned hw = std::max(1u, std::thread::hardware_concurrency());
    std::printf("quadcast bench spline-preprocess: data %s, %u threads (one run; times in seconds, memory in MiB of float storage)\n",
                opt.data.c_str(), opt.threads ? opt.threads : hw);
    std::vector<std::string> skipped;
    struct Loaded {
        std::string label;
        volume::VolumeData v;
        double iso;
    };
    std::vector<Loaded> loaded;
    std::printf("\n%-16s %-14s %-8s %-34s %10s %9s\n", "model", "samples", "type", "isovalue", "load s", "data MiB");
    for (const Model& m : models) {
        if (m.file && !std::filesystem::exists(m.request.input)) {
            skipped.push_back(m.name + ": " + m.request.input + " not found");
            continue;
        }
        const auto t0 = Clock::now();
        volume::VolumeData v;
        try {
            v = volume::load_volume(m.request);
        } catch (const std::exception& e) {
            skipped.push_back(m.name + ": " + e.what());
            continue;
        }
        const double t_load = seconds_since(t0);
        const std::string dims = volume::dims_string(v.nx(), v.ny(), v.nz());
        const double data_bytes = double(v.voxel_count()) * volume::sample_bytes(volume::parse_sample_type(v.sample_type));
        std::printf("%-16s %-14s %-8s %-34s %10.2f %9.2f\n", m.name.c_str(), dims.c_str(), v.sample_type.c_str(), m.iso_note.c_str(), t_load,
                    mib(data_bytes));
        loaded.push_back({m.name, std::move(v), m.iso});
    }
    std::printf("\n%-12s %-4s %9s %9s %6s %10s %9s %9s %9s %10s %9s\n", "model", "", "D-sets", "full BB", "ratio", "active BB", "D-sets s",
                "ranges s", "octree s", "active", "total s");
    for (const Loaded& l : loaded) {
        run_scheme<2>(l.label, l.v, l.iso, opt);
        run_scheme<3>(l.label, l.v, l.iso, opt);
    }
    std::printf("\nThe GL renderer's preparation (render::prepare_volume: one streaming pass, no whole-volume spline kept):\n");
    std::printf("%-12s %-4s %9s %10s %10s %12s %12s %9s %12s\n", "model", "", "time s", "active", "rel. tets", "kept MiB", "active BB MiB", "ratio",
                "octree MiB");
    for (const Loaded& l : loaded) {
        run_renderer_prep(l.label, l.v, l.iso, render::VolumeScheme::qss, opt);
        run_renderer_prep(l.label, l.v, l.iso, render::VolumeScheme::s31, opt);
    }
    std::printf("(kept: the active cubes' determining sets, indices and tetrahedron masks -- what goes to the GPU; active BB: the same cubes'\n"
                " full per-tetrahedron coefficients; octree: the min-max pyramid and the per-cube slot table)\n");
    for (const std::string& s : skipped) std::printf("skipped %s\n", s.c_str());
    if (!skipped.empty()) std::printf("(fetch the data files with `make data` or tools/fetch_cgal_data.sh, or point --data at them)\n");
}

}  // namespace

void add_bench_spline_preprocess(CLI::App& bench) {
    auto o = std::make_shared<PreprocessOptions>();
    CLI::App* cmd = bench.add_subcommand("spline-preprocess",
                                         "QSS/S31 preprocessing per data set: determining sets, coefficient ranges, min-max octree, memory, active cubes");
    cmd->add_option("--data", o->data, "directory of skull_2.9.inr, liver.inr.gz, bunny00.off (default build/data)");
    cmd->add_option("--threads", o->threads, "threads (0: all cores)");
    cmd->add_option("--sdf-size", o->sdf_size, "samples along the longest side of the bunny's signed distance volume")->check(CLI::Range(8, 1024));
    cmd->add_option("--max-memory-gb", o->max_memory_gb, "skip a scheme whose determining sets exceed this many GiB")->check(CLI::PositiveNumber);
    cmd->callback([o] {
        try {
            run_spline_preprocess(*o);
        } catch (const std::exception& e) {
            std::fprintf(stderr, "quadcast bench spline-preprocess: %s\n", e.what());
            throw CLI::RuntimeError(2);
        }
    });
}

}  // namespace quadcast::cli
