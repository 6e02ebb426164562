// quadcast/volume/spline_stencil.hpp -- BB-coefficients of the 24 tetrahedra of one cube from its 27-point stencil
#pragma once

// Host side of `quadcast spline-coeffs`. Conventions of the spline spec (§1.1-§1.3): the stencil
// in flat order 9(a+1) + 3(b+1) + (c+1) (a slowest), tetrahedra t = 4 phi + eps, coefficients in
// multi-index order (i, then j, then k descending).

#include <array>
#include <string>
#include <vector>

namespace quadcast::volume {

enum class SplineScheme { qss, s31 };

/// "qss" or "s31" (case-insensitive); throws std::invalid_argument otherwise.
SplineScheme parse_scheme(const std::string& name);
const char* scheme_name(SplineScheme s);

/// Parses 27 numbers separated by commas (spaces allowed around them). Throws
/// std::invalid_argument naming the value (1-based) for a non-number, NaN or infinity, and the
/// count when it is not 27.
std::array<double, 27> parse_stencil(const std::string& text);

/// The BB-coefficients of the 24 tetrahedra (24 x 10 for QSS, 24 x 20 for S31), each
/// c^(t)_n = Σ_s W_n(s) f[R_t s] by the data masks of tetrahedron 0 (spec §2.3, §3.3), summed
/// exactly (MPFR) and rounded once to double: the correctly rounded value of the exact
/// coefficient. Throws std::invalid_argument when a coefficient overflows double.
std::vector<std::vector<double>> cube_tet_coefficients(SplineScheme scheme, const std::array<double, 27>& stencil);

/// {"scheme": "qss", "tets": [[c_0, c_1, ...], ... 24 arrays]} with every number in the
/// shortest form that reads back to the same double.
std::string coefficients_json(SplineScheme scheme, const std::vector<std::vector<double>>& tets);

}  // namespace quadcast::volume
