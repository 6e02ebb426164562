// examples/quadcast/commands.hpp -- the subcommands of the `quadcast` command
#pragma once

#include <CLI/CLI.hpp>

namespace quadcast::cli {

/// `quadcast verify`: runs every generated kernel on this machine's GL and compares with the CPU.
void add_verify(CLI::App& app);
/// `quadcast bench stability`: float error of the root formulations against an MPFR reference.
void add_bench_stability(CLI::App& bench);
/// `quadcast bench spheres`: frame time against the number of spheres.
void add_bench_spheres(CLI::App& bench);

/// `quadcast render SCENE.json -o out.png`: renders a scene with GL (or the CPU reference).
void add_render(CLI::App& app);

}  // namespace quadcast::cli
