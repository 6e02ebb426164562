// tools/quadcast/volume_info.cpp -- `quadcast volume-info`: load a volume (file, synthetic, mesh SDF), describe it
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>

#include "commands.hpp"
#include "quadcast/volume/load.hpp"

namespace quadcast::cli {

void add_volume_input_options(CLI::App& cmd, volume::VolumeRequest& r) {
    cmd.add_option("input", r.input,
                   "volume: an INR (.inr, .inr.gz), NRRD (.nrrd, .nhdr) or raw file, an OFF mesh (signed distance "
                   "volume, negative inside), or marschner-lobb / franke")
        ->required();
    cmd.add_option("--size", r.size,
                   "synthetic: samples per axis (default 41 for marschner-lobb, 64 for franke); mesh: samples along the "
                   "longest side (default 64)")
        ->check(CLI::Range(2, 2048));
    cmd.add_option("--sdf-padding", r.sdf_padding, "mesh: samples outside the bounding box on each side")->check(CLI::Range(0, 64));
    cmd.add_option_function<std::vector<int>>(
           "--raw-dims", [&r](const std::vector<int>& d) { r.raw.nx = d[0]; r.raw.ny = d[1]; r.raw.nz = d[2]; },
           "raw file: dimensions X,Y,Z (x fastest)")
        ->delimiter(',')
        ->expected(3)
        ->check(CLI::PositiveNumber);
    cmd.add_option_function<std::string>(
           "--raw-type", [&r](const std::string& t) { r.raw.type = volume::parse_sample_type(t); },
           "raw file: uint8 (default), int8, uint16, int16, uint32, int32, float32, float64");
    cmd.add_option_function<std::string>(
           "--raw-endian", [&r](const std::string& e) { r.raw.endian = e == "big" ? volume::Endian::big : volume::Endian::little; },
           "raw file: little (default) or big")
        ->check(CLI::IsMember({"little", "big"}));
    cmd.add_option("--raw-header", r.raw.header_bytes, "raw file: bytes to skip before the samples");
    cmd.add_option_function<std::string>(
           "--nan",
           [&r](const std::string& p) {
               r.read.nan = p == "min" ? volume::NanPolicy::replace_min : p == "zero" ? volume::NanPolicy::replace_zero : volume::NanPolicy::error;
           },
           "NaN/Inf samples in float files: error (default), min (replace by the minimum), zero")
        ->check(CLI::IsMember({"error", "min", "zero"}));
}

void add_volume_info(CLI::App& app) {
    struct Options {
        volume::VolumeRequest request;
        double isovalue = std::numeric_limits<double>::quiet_NaN();
        std::string write_inr;
    };
    auto opt = std::make_shared<Options>();
    CLI::App* cmd = app.add_subcommand("volume-info", "load a volume and print its dimensions, spacing, value range and load time");
    add_volume_input_options(*cmd, opt->request);
    cmd->add_option("--isovalue", opt->isovalue, "check that this isovalue lies in the data range");
    cmd->add_option("--write-inr", opt->write_inr, "write the volume as a float INR file (.gz: compressed)");
    cmd->callback([opt] {
        try {
            const auto t0 = std::chrono::steady_clock::now();
            const volume::VolumeData v = volume::load_volume(opt->request, volume::stderr_progress("quadcast: " + opt->request.input));
            const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
            for (const auto& w : v.warnings) std::cerr << "warning: " << w << "\n";
            std::cout << volume::describe(v) << "\n";
            std::printf("loaded in %.3f s\n", secs);
            if (!std::isnan(opt->isovalue)) {
                volume::check_isovalue(v, opt->isovalue);
                std::printf("isovalue %.9g lies in the data range\n", opt->isovalue);
            }
            if (!opt->write_inr.empty()) {
                const bool gz = opt->write_inr.size() > 3 && opt->write_inr.compare(opt->write_inr.size() - 3, 3, ".gz") == 0;
                volume::write_inr(opt->write_inr, v, volume::SampleType::f32, volume::Endian::little, gz);
                std::printf("wrote %s\n", opt->write_inr.c_str());
            }
        } catch (const std::bad_alloc&) {
            std::cerr << "quadcast volume-info: " << opt->request.input << ": out of memory while loading the volume\n";
            throw CLI::RuntimeError(2);
        } catch (const std::exception& e) {
            std::cerr << "quadcast volume-info: " << e.what() << "\n";
            throw CLI::RuntimeError(2);
        }
    });
}

}  // namespace quadcast::cli
