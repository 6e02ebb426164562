// codegen/kernels/spline_kernels.hpp -- kernels traced from quadcast/bb/ and quadcast/spline/ (QSS, S31)
#pragma once

#include <string>

#include "kernels/common.hpp"
#include "quadcast/bb/bb.hpp"
#include "quadcast/spline/spline.hpp"

namespace quadcast::codegen::kernels {

// Kernel I/O of coefficient sets: a set of N floats is passed as ceil(N/4) parameters
// `<name>0, <name>1, ...` of type vec4 (the last one vec2/vec3 when N is not a multiple of 4), in
// storage order: for a BezierTet the multi-index order of spec §1.3 (q = 2: c0 = (c2000, c1100,
// c1010, c1001), c1 = (c0200, c0110, c0101, c0020), c2 = (c0011, c0002)); for a determining set
// the order of quadcast::spline::d_point (masks.hpp).

/// Reads N floats as vec4 groups named `<name>0`, `<name>1`, ...
template <int N, class IO>
Vec<typename IO::T, N> read_group(IO& io, const std::string& name) {
    Vec<typename IO::T, N> r{};
    constexpr int groups = (N + 3) / 4;
    for (int g = 0; g < groups; ++g) {
        const std::string n = name + std::to_string(g);
        const int left = N - 4 * g;
        if (left >= 4) { const auto v = io.template vec<4>(n); for (int i = 0; i < 4; ++i) r[4 * g + i] = v[i]; }
        else if (left == 3) { const auto v = io.template vec<3>(n); for (int i = 0; i < 3; ++i) r[4 * g + i] = v[i]; }
        else if (left == 2) { const auto v = io.template vec<2>(n); for (int i = 0; i < 2; ++i) r[4 * g + i] = v[i]; }
        else r[4 * g] = io.scalar(n);
    }
    return r;
}

/// Writes N floats as vec4 groups named `<name>0`, `<name>1`, ... (layout of `read_group`).
template <int N, class IO>
void write_group(IO& io, const std::string& name, const Vec<typename IO::T, N>& v) {
    using T = typename IO::T;
    constexpr int groups = (N + 3) / 4;
    for (int g = 0; g < groups; ++g) {
        const std::string n = name + std::to_string(g);
        const int left = N - 4 * g;
        if (left >= 4) io.out(n, Vec<T, 4>{{v[4 * g], v[4 * g + 1], v[4 * g + 2], v[4 * g + 3]}});
        else if (left == 3) io.out(n, Vec<T, 3>{{v[4 * g], v[4 * g + 1], v[4 * g + 2]}});
        else if (left == 2) io.out(n, Vec<T, 2>{{v[4 * g], v[4 * g + 1]}});
        else io.out(n, v[4 * g]);
    }
}

template <int Q, class IO>
bb::BezierTet<typename IO::T, Q> read_bezier(IO& io, const std::string& name) {
    const auto v = read_group<bb::coefficient_count(Q)>(io, name);
    bb::BezierTet<typename IO::T, Q> b{};
    for (int n = 0; n < b.size; ++n) b[n] = v[n];
    return b;
}

template <int Q, class IO>
void write_bezier(IO& io, const std::string& name, const bb::BezierTet<typename IO::T, Q>& b) {
    Vec<typename IO::T, bb::coefficient_count(Q)> v{};
    for (int n = 0; n < b.size; ++n) v[n] = b[n];
    write_group<bb::coefficient_count(Q)>(io, name, v);
}

// ---- Structured inputs --------------------------------------------------------------------------

/// A random 27-point stencil in the regimes of volume data: noise at a random scale, samples of
/// a random linear or quadratic polynomial, constant data, 8-bit-like data (integers 0..255), and
/// a smooth bump around a large offset (cancellation in the averaging rules).
inline spline::Stencil<double> random_stencil(std::mt19937& rng) {
    spline::Stencil<double> f{};
    const int kind = std::uniform_int_distribution<int>(0, 5)(rng);
    const double scale = std::ldexp(1.0, std::uniform_int_distribution<int>(-10, 10)(rng));
    const double g[3] = {uniform(rng, -1.0f, 1.0f), uniform(rng, -1.0f, 1.0f), uniform(rng, -1.0f, 1.0f)};
    const double c0 = uniform(rng, -1.0f, 1.0f), k2 = uniform(rng, -1.0f, 1.0f);
    const double offset = uniform(rng, -1000.0f, 1000.0f);
    for (int s = 0; s < spline::stencil_size; ++s) {
        const spline::IVec3 o = spline::stencil_offset(s);
        const double x = o[0], y = o[1], z = o[2];
        switch (kind) {
        case 0: f[s] = static_cast<double>(uniform(rng, -1.0f, 1.0f)) * scale; break;
        case 1: f[s] = (c0 + g[0] * x + g[1] * y + g[2] * z) * scale; break;
        case 2: f[s] = (c0 + g[0] * x + g[1] * y + g[2] * z + k2 * (x * x - y * z)) * scale; break;
        case 3: f[s] = c0 * scale; break;
        case 4: f[s] = std::uniform_int_distribution<int>(0, 255)(rng); break;
        default: f[s] = offset + 1e-3 * (g[0] * x + g[1] * y * y + g[2] * z * x); break;
        }
        f[s] = static_cast<double>(static_cast<float>(f[s]));  // data are floats
    }
    return f;
}

/// Float coefficients of a random piece (tetrahedron t of a cube with a random stencil), by
/// the direct masks in double, rounded once.
template <int Q>
bb::BezierTet<float, Q> random_piece(std::mt19937& rng) {
    const int t = std::uniform_int_distribution<int>(0, spline::tets_per_cube - 1)(rng);
    const bb::BezierTet<double, Q> c = spline::tet_from_stencil<Q>(random_stencil(rng), t);
    bb::BezierTet<float, Q> r{};
    for (int n = 0; n < r.size; ++n) r[n] = static_cast<float>(c[n]);
    return r;
}

/// A barycentric point: inside the tetrahedron, on a face (where rays enter and leave), at a
/// vertex, or slightly outside.
inline Vec4<float> random_barycentric(std::mt19937& rng) {
    std::exponential_distribution<float> e(1.0f);
    Vec4<float> l = vec4(e(rng), e(rng), e(rng), e(rng));
    const int kind = std::uniform_int_distribution<int>(0, 5)(rng);
    if (kind <= 2) l[std::uniform_int_distribution<int>(0, 3)(rng)] = 0.0f;  // on a face
    if (kind == 3) { l = vec4(0.0f, 0.0f, 0.0f, 0.0f); l[std::uniform_int_distribution<int>(0, 3)(rng)] = 1.0f; }
    const float sum = ((l[0] + l[1]) + l[2]) + l[3];
    for (int m = 0; m < 4; ++m) l[m] = l[m] / sum;
    if (kind == 4) l[std::uniform_int_distribution<int>(0, 3)(rng)] -= uniform(rng, 0.0f, 1e-3f);  // outside
    return l;
}

template <int N>
void put_values(std::span<float> out, std::size_t& pos, const float (&v)[N]) { for (int i = 0; i < N; ++i) out[pos++] = v[i]; }

template <int Q>
void put_bezier(std::span<float> out, std::size_t& pos, const bb::BezierTet<float, Q>& b) { put_values(out, pos, b.c); }

/// Univariate coefficients of a random piece along a random segment, and an isovalue that
/// makes roots likely: the value at a random parameter, a coefficient (grazing the hull), or the
/// minimum of the end values (tangent regime); sometimes a double root built in.
template <int Q>
void random_univariate(std::mt19937& rng, float (&b)[Q + 1], float& rho) {
    const int kind = std::uniform_int_distribution<int>(0, 4)(rng);
    if (kind == 4) {
        // (t - t0)^2 (times (t - t1) for cubics) in BB form, shifted by rho: a double root.
        const double t0 = uniform(rng, 0.0f, 1.0f), t1 = uniform(rng, -1.0f, 2.0f), s = uniform(rng, -2.0f, 2.0f);
        rho = uniform(rng, -1.0f, 1.0f);
        double p[Q + 1];
        // Values of the BB coefficients of s (t - t0)^2 [(t - t1)] via the blossom: symmetric
        // products of (x_i - t0) terms with x_i in {0, 1}.
        for (int i = 0; i <= Q; ++i) {
            // blossom of (t - t0)(t - t0)[(t - t1)] at (0^(Q-i), 1^i), averaged over placements.
            double acc = 0.0;
            int count = 0;
            for (int mask = 0; mask < (1 << Q); ++mask) {
                if (__builtin_popcount(static_cast<unsigned>(mask)) != i) continue;
                const double roots[3] = {t0, t0, t1};
                double prod = 1.0;
                for (int k = 0; k < Q; ++k) prod *= (((mask >> k) & 1) ? 1.0 : 0.0) - roots[k];
                acc += prod;
                ++count;
            }
            p[i] = s * acc / count;
        }
        for (int i = 0; i <= Q; ++i) b[i] = static_cast<float>(p[i] + static_cast<double>(rho));
        return;
    }
    const bb::BezierTet<float, Q> c = random_piece<Q>(rng);
    const Vec4<float> la = random_barycentric(rng), lb = random_barycentric(rng);
    const Vec<float, Q + 1> r = bb::restrict_to_segment(c, la, lb);
    for (int i = 0; i <= Q; ++i) b[i] = r[i];
    if (kind == 0) rho = bb::evaluate_univariate(r, uniform(rng, 0.0f, 1.0f)).value;
    else if (kind == 1) rho = r[std::uniform_int_distribution<int>(0, Q)(rng)];
    else if (kind == 2) rho = std::min(r[0], r[Q]) - uniform(rng, 0.0f, 1e-3f) * std::abs(r[0] - r[Q]);
    else rho = uniform(rng, -1.0f, 1.0f) * std::max(std::abs(r[0]), std::abs(r[Q]));
}

// ---- Coefficients by repeated averaging -----------------------------------------------------------

/// The coefficients of tetrahedron 0 of a cube from its determining set, rotated into the frame
/// of T_0 on the host (d_rot[k] = d[perm_t[k]]; the same code serves all 24 tetrahedra).
template <int Q>
struct SplineTet0CoefficientsKernel {
    static constexpr const char* name = Q == 2 ? "spline_qss_tet0_coefficients" : "spline_s31_tet0_coefficients";
    static constexpr const char* source = Q == 2 ? "quadcast::spline::qss_tet0_from_d2 (quadcast/spline/quasi_interpolation.hpp)"
                                                 : "quadcast::spline::s31_tet0_from_d3 (quadcast/spline/quasi_interpolation.hpp)";
    static constexpr const char* summary = Q == 2 ? "QSS: the 10 BB-coefficients of a tetrahedron from the 20 rotated D2 values by repeated averaging (Kalbe & Zeilfelder 2008, Fig. 7)"
                                                  : "S31: the 20 BB-coefficients of a tetrahedron from the 56 rotated D3 values by repeated averaging (Kalbe & Zeilfelder 2008, Fig. 7)";
    template <class IO> static void run(IO& io) {
        const auto d = read_group<spline::d_count(Q)>(io, "d");
        write_bezier<Q>(io, "c", spline::tet0_from_determining_set<Q>(d));
    }
    static void generate(std::mt19937& rng, std::span<float> in) {
        const spline::DeterminingSet<double, Q> d = spline::determining_set_from_stencil<Q>(random_stencil(rng));
        const spline::DeterminingSet<float, Q> df = cast<float>(d);
        const int t = std::uniform_int_distribution<int>(0, spline::tets_per_cube - 1)(rng);
        const spline::DeterminingSet<float, Q> dr = spline::rotate_determining_set<Q>(df, t);
        std::size_t p = 0;
        for (int k = 0; k < spline::d_count(Q); ++k) put(in, p, dr[k]);
    }
};

/// Barycentric coordinates w.r.t. T_0 of a point in the frame of T_0 (u' = R_tᵀ u, host side).
struct SplineBarycentricKernel {
    static constexpr const char* name = "spline_barycentric_tet0";
    static constexpr const char* source = "quadcast::spline::barycentric_tet0 (quadcast/spline/partition.hpp)";
    static constexpr const char* summary = "barycentric coordinates w.r.t. T_0 of a cube-local point in the frame of T_0 (spec 1.5)";
    template <class IO> static void run(IO& io) {
        io.out("lambda", spline::barycentric_tet0(io.template vec<3>("u")));
    }
    static void generate(std::mt19937& rng, std::span<float> in) {
        std::size_t p = 0;
        put(in, p, random_point(rng, 1.0f));
    }
};

// ---- Restriction to a ray segment by blossoming ---------------------------------------------------

/// The univariate BB-form of a piece along the segment from barycentric `la` to `lb`.
template <int Q>
struct RestrictKernel {
    static constexpr const char* name = Q == 2 ? "bb_restrict_q2" : "bb_restrict_q3";
    static constexpr const char* source = "quadcast::bb::restrict_to_segment (quadcast/bb/restrict.hpp)";
    static constexpr const char* summary = Q == 2 ? "quadratic piece restricted to a segment: blossoms p[la^(2-i), lb^i] (Kalbe & Zeilfelder 2008, Sect. 5.3)"
                                                  : "cubic piece restricted to a segment: blossoms p[la^(3-i), lb^i] (Kalbe & Zeilfelder 2008, Sect. 5.3)";
    template <class IO> static void run(IO& io) {
        const auto c = read_bezier<Q>(io, "c");
        const auto la = io.template vec<4>("la"), lb = io.template vec<4>("lb");
        io.out("r", bb::restrict_to_segment(c, la, lb));
    }
    static void generate(std::mt19937& rng, std::span<float> in) {
        std::size_t p = 0;
        put_bezier<Q>(in, p, random_piece<Q>(rng));
        put(in, p, random_barycentric(rng));
        put(in, p, random_barycentric(rng));
    }
};

/// The fragment-stage half of the paper's restriction for q = 3: from the first de Casteljau
/// step at both ends (computed per vertex and interpolated), finish the blossoms.
struct RestrictFromFirstStepKernel {
    static constexpr const char* name = "bb_restrict_from_first_step_q3";
    static constexpr const char* source = "quadcast::bb::restrict_from_first_step (quadcast/bb/restrict.hpp)";
    static constexpr const char* summary = "cubic restriction from b^[1] at both segment ends: 12 + 4 de Casteljau steps (Kalbe & Zeilfelder 2008, Fig. 10)";
    template <class IO> static void run(IO& io) {
        const auto ba = read_bezier<2>(io, "ba"), bb = read_bezier<2>(io, "bb");
        const auto la = io.template vec<4>("la"), lb = io.template vec<4>("lb");
        io.out("r", bb::restrict_from_first_step(ba, bb, la, lb));
    }
    static void generate(std::mt19937& rng, std::span<float> in) {
        const auto c = random_piece<3>(rng);
        const Vec4<float> la = random_barycentric(rng), lb = random_barycentric(rng);
        std::size_t p = 0;
        put_bezier<2>(in, p, bb::de_casteljau_step(c, la));
        put_bezier<2>(in, p, bb::de_casteljau_step(c, lb));
        put(in, p, la);
        put(in, p, lb);
    }
};

// ---- First root in [0,1] --------------------------------------------------------------------------

struct QuadraticFirstRootKernel {
    static constexpr const char* name = "bb_quadratic_first_root";
    static constexpr const char* source = "quadcast::bb::quadratic_first_root (quadcast/bb/roots.hpp)";
    static constexpr const char* summary = "first root in [0,1] of a quadratic in BB-form minus rho, stable analytic formula";
    template <class IO> static void run(IO& io) {
        const auto b = io.template vec<3>("b");
        const auto r = bb::quadratic_first_root(b, io.scalar("rho"));
        io.out("t", r.t);
        io.out("hit", r.hit);
    }
    static void generate(std::mt19937& rng, std::span<float> in) {
        float b[3], rho;
        random_univariate<2>(rng, b, rho);
        std::size_t p = 0;
        put_values(in, p, b);
        put(in, p, rho);
    }
};

struct CubicFirstRootKernel {
    static constexpr const char* name = "bb_cubic_first_root";
    static constexpr const char* source = "quadcast::bb::cubic_first_root (quadcast/bb/roots.hpp)";
    static constexpr const char* summary = "first root in [0,1] of a cubic in BB-form minus rho: isolation by critical/inflection points, safeguarded Newton (6 steps)";
    template <class IO> static void run(IO& io) {
        const auto b = io.template vec<4>("b");
        const auto rho = io.scalar("rho"), touch = io.scalar("touch_tol");
        const auto r = bb::cubic_first_root(b, rho, touch);
        io.out("t", r.t);
        io.out("hit", r.hit);
    }
    static void generate(std::mt19937& rng, std::span<float> in) {
        float b[4], rho;
        random_univariate<3>(rng, b, rho);
        std::size_t p = 0;
        put_values(in, p, b);
        put(in, p, rho);
        put(in, p, std::uniform_int_distribution<int>(0, 1)(rng) ? 0.0f : 1e-6f * std::max(std::abs(b[0]), std::abs(b[3])));
    }
};

struct CubicFirstRootNewtonKernel {
    static constexpr const char* name = "bb_cubic_first_root_newton5";
    static constexpr const char* source = "quadcast::bb::cubic_first_root_newton<5> (quadcast/bb/roots.hpp)";
    static constexpr const char* summary = "first root in [0,1] of a cubic in BB-form minus rho: the paper's Newton, 3 starts x 5 steps (Kalbe & Zeilfelder 2008, Sect. 5.3)";
    template <class IO> static void run(IO& io) {
        using T = typename IO::T;
        const auto b = io.template vec<4>("b");
        const auto rho = io.scalar("rho"), tol = io.scalar("residual_tol");
        const auto r = bb::cubic_first_root_newton<5>(Vec<T, 4>{{b[0] - rho, b[1] - rho, b[2] - rho, b[3] - rho}}, tol);
        io.out("t", r.t);
        io.out("hit", r.hit);
    }
    static void generate(std::mt19937& rng, std::span<float> in) {
        float b[4], rho;
        random_univariate<3>(rng, b, rho);
        std::size_t p = 0;
        put_values(in, p, b);
        put(in, p, rho);
        put(in, p, std::ldexp(1.0f, -std::uniform_int_distribution<int>(6, 20)(rng)));
    }
};

// ---- Value and gradient ---------------------------------------------------------------------------

/// Value and gradient of a piece at λ by de Casteljau: Q-1 steps give the degree-1 coefficients,
/// value = their combination at λ, gradient component a = Q · dot(b^[Q-1], λ(e_a)) with the
/// barycentric directions λ(e_a) of the axes given as `dir_x`, `dir_y`, `dir_z` (world scale
/// 2/h applied by the caller).
template <int Q>
struct ValueGradientKernel {
    static constexpr const char* name = Q == 2 ? "bb_value_gradient_q2" : "bb_value_gradient_q3";
    static constexpr const char* source = "quadcast::bb::value_and_partials, quadcast::bb::gradient (quadcast/bb/bezier.hpp)";
    static constexpr const char* summary = Q == 2 ? "value and gradient of a quadratic piece by de Casteljau (Kalbe & Zeilfelder 2008, Sect. 3 and 5.3)"
                                                  : "value and gradient of a cubic piece by de Casteljau (Kalbe & Zeilfelder 2008, Sect. 3 and 5.3)";
    template <class IO> static void run(IO& io) {
        using T = typename IO::T;
        const auto c = read_bezier<Q>(io, "c");
        const auto lambda = io.template vec<4>("lambda");
        Mat<T, 4, 3> dirs{};
        dirs[0] = io.template vec<4>("dir_x");
        dirs[1] = io.template vec<4>("dir_y");
        dirs[2] = io.template vec<4>("dir_z");
        const bb::ValueAndPartials<T> vp = bb::value_and_partials(c, lambda);
        io.out("value", vp.value);
        io.out("gradient", bb::gradient(vp, dirs));
    }
    static void generate(std::mt19937& rng, std::span<float> in) {
        const int t = std::uniform_int_distribution<int>(0, spline::tets_per_cube - 1)(rng);
        const Mat<float, 4, 3> dirs = spline::barycentric_directions<float>(t);
        std::size_t p = 0;
        put_bezier<Q>(in, p, random_piece<Q>(rng));
        put(in, p, random_barycentric(rng));
        for (int a = 0; a < 3; ++a) put(in, p, dirs[a]);
    }
};

}  // namespace quadcast::codegen::kernels
