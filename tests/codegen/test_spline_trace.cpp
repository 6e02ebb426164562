// tests/codegen/test_spline_trace.cpp -- the BB-form and spline templates trace with the real Expr and the trace computes the CPU's bits
#include <doctest/doctest.h>

#include <bit>
#include <cmath>
#include <random>
#include <string>

#include "kernels/spline_kernels.hpp"
#include "quadcast/codegen/generate.hpp"
#include "quadcast/codegen/interpret.hpp"
#include "quadcast/codegen/verify.hpp"

using namespace quadcast;
using namespace quadcast::codegen;

namespace {

bool same_word(std::uint32_t a, std::uint32_t b) {
    return a == b || (std::isnan(std::bit_cast<float>(a)) && std::isnan(std::bit_cast<float>(b)));
}

/// Interprets the trace of `k` on `count` verification inputs; returns the samples that differ
/// from the float instantiation.
std::size_t trace_mismatches(const KernelDef& k, std::size_t count, std::uint64_t seed) {
    TracedKernel traced(k);
    const auto in = make_inputs(k, count, seed);
    const auto cpu = run_cpu(k, in, count);
    const std::size_t nin = static_cast<std::size_t>(traced.signature().input_words());
    const std::size_t nout = static_cast<std::size_t>(traced.signature().output_words());
    std::vector<std::uint32_t> out(nout);
    std::size_t bad = 0;
    for (std::size_t s = 0; s < count; ++s) {
        traced.run(std::span<const std::uint32_t>(in).subspan(s * nin, nin), out);
        bool same = true;
        for (std::size_t j = 0; j < nout; ++j) same = same && same_word(out[j], cpu[s * nout + j]);
        bad += !same;
    }
    return bad;
}

/// Templates of quadcast/bb and quadcast/spline that the registry does not cover on their own:
/// the direct mask path and the D-set masks, point location in the frame of tetrahedron t,
/// evaluate/blossom, the gradient with compile-time barycentric directions (literal zeros),
/// both roots of a quadratic, and the root finders with their default arguments.
template <int Q, int Tet>
struct EverythingKernel {
    static constexpr const char* name = "test_spline_everything";
    static constexpr const char* source = "tests/codegen/test_spline_trace.cpp";
    static constexpr const char* summary = "spline template coverage";
    template <class IO> static void run(IO& io) {
        using T = typename IO::T;
        using namespace quadcast::codegen::kernels;
        const auto f = read_group<spline::stencil_size>(io, "f");
        const Vec3<T> u = io.template vec<3>("u");
        const auto c_direct = spline::tet_from_stencil<Q>(f, Tet);
        const auto d = spline::determining_set_from_stencil<Q>(f);
        const auto c_avg = spline::tet_from_determining_set<Q>(d, Tet);
        write_bezier<Q>(io, "direct", c_direct);
        write_bezier<Q>(io, "averaged", c_avg);
        const Vec<T, 4> lambda = spline::barycentric(Tet, u);
        io.out("lambda", lambda);
        io.out("back", spline::from_tet0_frame(Tet, spline::to_tet0_frame(Tet, u)));
        io.out("value", bb::evaluate(c_avg, lambda));
        Vec<T, 4> args[Q];
        for (int s = 0; s < Q; ++s) args[s] = s == 0 ? lambda : Vec<T, 4>{{T(0.25), T(0.25), T(0.25), T(0.25)}};
        io.out("blossom", bb::blossom(c_avg, args));
        const auto vp = bb::value_and_partials(c_avg, lambda);
        io.out("gradient", bb::gradient(vp, spline::barycentric_directions<T>(Tet)));
        io.out("ddir", bb::directional_derivative(vp, Vec<T, 4>{{T(1), T(-1), T(0), T(0)}}));
        const auto r = bb::restrict_to_segment(c_avg, lambda, Vec<T, 4>{{T(0.25), T(0.25), T(0.25), T(0.25)}});
        if constexpr (Q == 2) {
            const auto roots = bb::quadratic_roots(r);
            io.out("t0", roots.t[0]);
            io.out("t1", roots.t[1]);
            io.out("h0", roots.hit[0]);
            io.out("h1", roots.hit[1]);
        } else {
            const auto a = bb::cubic_first_root(r, c_avg[0]);
            const auto b = bb::cubic_first_root_newton(r, T(1e-4));
            io.out("ta", a.t);
            io.out("ha", a.hit);
            io.out("tb", b.t);
            io.out("hb", b.hit);
        }
    }
};

}  // namespace

TEST_CASE("every registered spline and BB kernel's trace computes the float instantiation's bits") {
    int kernels = 0;
    for (const KernelDef& k : registry()) {
        if (k.name.rfind("spline_", 0) != 0 && k.name.rfind("bb_", 0) != 0 && k.name.rfind("trilinear_", 0) != 0) continue;
        ++kernels;
        CAPTURE(k.name);
        CHECK(trace_mismatches(k, 4000, 3) == 0);
    }
    CHECK(kernels == 19);  // 11 + spline_piece_hit_q2/q3 + trilinear_cell_hit (quadcast/spline/raycast.hpp) + the isosurface renderer's 5 (quadcast/spline/render.hpp)
}

TEST_CASE("the rest of the spline templates trace too, for every tetrahedron position class") {
    // Rotations with and without sign flips, on three different faces.
    CHECK(trace_mismatches(make_kernel<EverythingKernel<2, 0>>(), 2000, 5) == 0);
    CHECK(trace_mismatches(make_kernel<EverythingKernel<2, 13>>(), 2000, 6) == 0);
    CHECK(trace_mismatches(make_kernel<EverythingKernel<3, 6>>(), 2000, 7) == 0);
    CHECK(trace_mismatches(make_kernel<EverythingKernel<3, 22>>(), 2000, 8) == 0);
}

TEST_CASE("the structured inputs of the root kernels mostly have a root in [0,1]") {
    // Otherwise `quadcast verify` would only compare the no-hit path of the root finders.
    for (const char* name : {"bb_quadratic_first_root", "bb_cubic_first_root", "bb_cubic_first_root_newton5"}) {
        const KernelDef* k = find_kernel(name);
        REQUIRE(k != nullptr);
        TracedKernel traced(*k);
        const std::size_t nin = static_cast<std::size_t>(traced.signature().input_words());
        std::vector<float> in(nin);
        std::vector<std::uint32_t> words(nin), out(static_cast<std::size_t>(traced.signature().output_words()));
        int hits = 0;
        const int n = 2000;
        for (int i = 0; i < n; ++i) {
            std::mt19937 rng(static_cast<std::uint32_t>(i));
            k->generate(rng, in);
            for (std::size_t j = 0; j < nin; ++j) words[j] = std::bit_cast<std::uint32_t>(in[j]);
            CpuIO io(words, out);
            k->cpu(io);
            hits += out[1] == 1u;
        }
        CAPTURE(name);
        CHECK(hits > n / 2);
        CHECK(hits < n);
    }
}

TEST_CASE("the coefficient kernel on a rotated determining set gives the coefficients of that tetrahedron") {
    // The GPU route (repeated averaging of the host-rotated D set, in float) against the direct
    // masks in double: a few ulps of the data scale.
    std::mt19937 rng(9);
    for (int it = 0; it < 200; ++it) {
        const auto f = kernels::random_stencil(rng);
        const int t = it % 24;
        const auto d = cast<float>(spline::determining_set_from_stencil<3>(f));
        const auto dr = spline::rotate_determining_set<3>(d, t);
        const auto c = spline::tet0_from_determining_set<3>(dr);
        const auto ref = spline::tet_from_stencil<3>(f, t);
        double scale = 0.0;
        for (int s = 0; s < 27; ++s) scale = std::max(scale, std::abs(f[s]));
        for (int n = 0; n < 20; ++n) CHECK(std::abs(static_cast<double>(c[n]) - ref[n]) <= 1e-5 * scale);
    }
}
