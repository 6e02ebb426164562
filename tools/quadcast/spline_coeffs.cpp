// tools/quadcast/spline_coeffs.cpp -- `quadcast spline-coeffs`: BB-coefficients of the 24 tetrahedra of one cube
#include <iostream>
#include <memory>
#include <stdexcept>
#include <string>

#include "commands.hpp"
#include "quadcast/volume/spline_stencil.hpp"

namespace quadcast::cli {

void add_spline_coeffs(CLI::App& app) {
    struct Options {
        std::string scheme, stencil;
    };
    auto opt = std::make_shared<Options>();
    CLI::App* cmd = app.add_subcommand(
        "spline-coeffs",
        "print, as JSON, the BB-coefficients of the 24 tetrahedra of one cube (QSS: 10 each, S31: 20 each) for 27 data "
        "values; tetrahedra and coefficients ordered as in the spline spec (t = 4 phi + eps; multi-indices i, j, k "
        "descending); each value is the exact mask sum rounded once to double");
    cmd->add_option("--scheme", opt->scheme, "qss (quadratic super splines) or s31 (cubic C1 splines)")->required();
    cmd->add_option("--stencil", opt->stencil,
                    "27 comma-separated values f[a,b,c], flat order 9(a+1) + 3(b+1) + (c+1), a slowest "
                    "(write --stencil=-1,... when the first value is negative)")
        ->required();
    cmd->callback([opt] {
        try {
            const volume::SplineScheme s = volume::parse_scheme(opt->scheme);
            const auto f = volume::parse_stencil(opt->stencil);
            std::cout << volume::coefficients_json(s, volume::cube_tet_coefficients(s, f));
        } catch (const std::exception& e) {
            std::cerr << "quadcast spline-coeffs: " << e.what() << "\n";
            throw CLI::RuntimeError(2);
        }
    });
}

}  // namespace quadcast::cli
