// tools/quadcast/commands.hpp -- the subcommands of the `quadcast` command
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
/// `quadcast bench meshes`: sphere impostors against tessellated spheres of equal outline error.
void add_bench_meshes(CLI::App& bench);
/// `quadcast bench spline-error`: isosurface position error vs frame time of QSS, S31, trilinear
/// and marching cubes on analytic functions (bench_spline_error.cpp).
void add_bench_spline_error(CLI::App& bench);
/// `quadcast bench spline-preprocess`: determining sets, coefficient ranges, octree and memory per
/// data set (the shape of Kalbe & Zeilfelder 2008, Table 1).
void add_bench_spline_preprocess(CLI::App& bench);
/// `quadcast bench slim`: SLIM surfaces against CGAL-simplified meshes of the same error along
/// camera rays: build time, balls, error, GL frame time (bench_slim.cpp).
void add_bench_slim(CLI::App& bench);

/// `quadcast bench isosurfaces`: GL isosurfaces (QSS, S31, trilinear) against the CPU reference,
/// and what the octree, frustum and per-tetrahedron culling skip.
void add_bench_isosurfaces(CLI::App& bench);

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
/// `quadcast slim-build INPUT -o MODEL --error E`: a SLIM model from oriented points or a mesh
/// (slim_build.cpp).
void add_slim_build(CLI::App& app);

}  // namespace quadcast::cli
