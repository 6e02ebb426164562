// examples/quadcast/commands.hpp -- the subcommands of the `quadcast` command
#pragma once

#include <CLI/CLI.hpp>

namespace quadcast::volume {
struct VolumeRequest;
}

namespace quadcast::cli {

/// `quadcast verify`: runs every generated kernel on this machine's GL and compares with the CPU.
void add_verify(CLI::App& app);
/// `quadcast bench stability`: float error of the root formulations against an MPFR reference.
void add_bench_stability(CLI::App& bench);
/// `quadcast bench spheres`: frame time against the number of spheres.
void add_bench_spheres(CLI::App& bench);
/// `quadcast bench culling`: per-quadric culling on vs off on a closed surface of patches.
void add_bench_culling(CLI::App& bench);
/// `quadcast bench fragments`: incremental vs brute-force vs pass-through fragment stage.
void add_bench_fragments(CLI::App& bench);

/// `quadcast render SCENE.json -o out.png`: renders a scene with GL (or the CPU reference).
void add_render(CLI::App& app);

/// Adds the volume input options (positional INPUT, --size, --raw-*, --nan, --sdf-padding) that
/// fill `request` (volume_info.cpp); `request` must outlive the command.
void add_volume_input_options(CLI::App& cmd, volume::VolumeRequest& request);
/// `quadcast spline-coeffs --scheme qss|s31 --stencil v0,...,v26`: the BB-coefficients of the 24
/// tetrahedra of one cube as JSON.
void add_spline_coeffs(CLI::App& app);
/// `quadcast volume-info INPUT`: loads a volume (INR, NRRD, raw, synthetic, OFF -> signed distance)
/// and describes it.
void add_volume_info(CLI::App& app);

}  // namespace quadcast::cli
