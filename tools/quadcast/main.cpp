// quadcast -- command-line front end: verify the GL driver, benchmarks, (later) rendering
#include <iostream>

#include "commands.hpp"
#include "quadcast/gl/allocator.hpp"

int main(int argc, char** argv) {
    // llvmpipe's per-draw buffers from the heap, not from fresh mmaps every frame (quadcast/gl/allocator.hpp)
    quadcast::gl::keep_freed_memory();
    CLI::App app{"quadcast: GPU ray casting of quadrics and trivariate splines"};
    app.require_subcommand(1);
    quadcast::cli::add_verify(app);
    quadcast::cli::add_render(app);
    quadcast::cli::add_spline_coeffs(app);
    quadcast::cli::add_volume_info(app);
    quadcast::cli::add_slim_build(app);
    CLI::App* bench = app.add_subcommand("bench", "benchmarks (ratios measured in one run)");
    bench->require_subcommand(1);
    quadcast::cli::add_bench_stability(*bench);
    quadcast::cli::add_bench_spheres(*bench);
    quadcast::cli::add_bench_culling(*bench);
    quadcast::cli::add_bench_fragments(*bench);
    quadcast::cli::add_bench_meshes(*bench);
    quadcast::cli::add_bench_spline_error(*bench);
    quadcast::cli::add_bench_spline_preprocess(*bench);
    quadcast::cli::add_bench_isosurfaces(*bench);
    quadcast::cli::add_bench_slim(*bench);
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        return app.exit(e);
    } catch (const std::exception& e) {
        std::cerr << "quadcast: " << e.what() << "\n";
        return 2;
    }
    return 0;
}
