// src/volume/spline_stencil.cpp -- BB-coefficients of the 24 tetrahedra of one cube from its 27-point stencil
#include "quadcast/volume/spline_stencil.hpp"

#include <cctype>
#include <charconv>
#include <cmath>
#include <stdexcept>

#include <mpreal.h>

#include "quadcast/spline/masks.hpp"

namespace quadcast::volume {

SplineScheme parse_scheme(const std::string& name) {
    std::string l;
    for (char c : name) l += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    if (l == "qss") return SplineScheme::qss;
    if (l == "s31") return SplineScheme::s31;
    throw std::invalid_argument("unknown scheme '" + name + "' (expected qss or s31)");
}

const char* scheme_name(SplineScheme s) { return s == SplineScheme::qss ? "qss" : "s31"; }

std::array<double, 27> parse_stencil(const std::string& text) {
    std::vector<std::string> items;
    std::string cur;
    for (char c : text) {
        if (c == ',') {
            items.push_back(cur);
            cur.clear();
        } else {
            cur += c;
        }
    }
    items.push_back(cur);
    std::array<double, 27> f{};
    if (items.size() != 27)
        throw std::invalid_argument("the stencil needs 27 comma-separated values (flat order 9(a+1) + 3(b+1) + (c+1)), found " +
                                    std::to_string(items.size()));
    for (std::size_t n = 0; n < items.size(); ++n) {
        std::string s = items[n];
        while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.pop_back();
        std::size_t b = 0;
        while (b < s.size() && std::isspace(static_cast<unsigned char>(s[b]))) ++b;
        s = s.substr(b);
        if (!s.empty() && s[0] == '+') s = s.substr(1);
        double v = 0.0;
        const auto [p, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
        const std::string which = "stencil value " + std::to_string(n + 1) + " of 27";
        if (s.empty()) throw std::invalid_argument(which + " is empty");
        if (ec == std::errc::result_out_of_range) throw std::invalid_argument(which + " ('" + s + "') is out of the range of double");
        if (ec != std::errc() || p != s.data() + s.size()) throw std::invalid_argument(which + " ('" + s + "') is not a number");
        if (std::isnan(v)) throw std::invalid_argument(which + " is NaN");
        if (std::isinf(v)) throw std::invalid_argument(which + " is infinite");
        f[n] = v;
    }
    return f;
}

namespace {

template <int Q>
std::vector<std::vector<double>> coefficients(const std::array<double, 27>& f) {
    // Exact sums: doubles span 2^-1074 .. 2^1024 and weights < 2^8, so 2200 bits hold every
    // partial sum exactly; the division by 128 or 192 = 3 * 64 then rounds once.
    const mpfr_prec_t prec = 2200;
    static constexpr auto perm = spline::stencil_permutations();
    const int den = spline::coefficient_mask_denominator(Q);
    std::vector<std::vector<double>> r(spline::tets_per_cube);
    for (int t = 0; t < spline::tets_per_cube; ++t) {
        for (int n = 0; n < bb::coefficient_count(Q); ++n) {
            mpfr::mpreal acc(0, prec);
            for (int s = 0; s < spline::stencil_size; ++s) {
                const int w = spline::tet0_mask<Q>(n, s);
                if (w != 0) acc += mpfr::mpreal(f[std::size_t(perm[std::size_t(t)][std::size_t(s)])], prec) * w;
            }
            acc /= den;
            const double c = acc.toDouble(MPFR_RNDN);
            if (!std::isfinite(c))
                throw std::invalid_argument("coefficient " + std::to_string(n) + " of tetrahedron " + std::to_string(t) +
                                            " overflows double");
            r[std::size_t(t)].push_back(c);
        }
    }
    return r;
}

}  // namespace

std::vector<std::vector<double>> cube_tet_coefficients(SplineScheme scheme, const std::array<double, 27>& stencil) {
    return scheme == SplineScheme::qss ? coefficients<2>(stencil) : coefficients<3>(stencil);
}

std::string coefficients_json(SplineScheme scheme, const std::vector<std::vector<double>>& tets) {
    std::string s = "{\"scheme\": \"" + std::string(scheme_name(scheme)) + "\", \"tets\": [";
    for (std::size_t t = 0; t < tets.size(); ++t) {
        s += t ? ",\n  [" : "\n  [";
        for (std::size_t n = 0; n < tets[t].size(); ++n) {
            char buf[32];
            const auto res = std::to_chars(buf, buf + sizeof buf, tets[t][n]);
            if (n) s += ", ";
            s.append(buf, res.ptr);
        }
        s += "]";
    }
    return s + "\n]}\n";
}

}  // namespace quadcast::volume
