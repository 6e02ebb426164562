// codegen/kernels/spline_render_kernels.hpp -- kernels traced from quadcast/spline/raycast.hpp (ray vs spline piece, ray vs trilinear cell)
#pragma once

#include <string>

#include "kernels/common.hpp"
#include "kernels/spline_kernels.hpp"
#include "quadcast/spline/raycast.hpp"

namespace quadcast::codegen::kernels {

/// A random ray through a cube in the frame of tetrahedron t: beta0 = barycentric(t, u) at a
/// cube-local point u in [-1.2, 1.2]^3, delta = barycentric direction of a random ud, s in
/// [s_min, s_max] around 0.
inline void random_tet_ray(std::mt19937& rng, int t, Vec4<float>& beta0, Vec4<float>& delta, float& s_min, float& s_max) {
    const Vec3<float> u = random_point(rng, 1.2f), ud = random_point(rng, 1.0f);
    beta0 = spline::barycentric(t, u);
    delta = spline::barycentric_directions<float>(t) * ud;
    s_min = -uniform(rng, 0.0f, 1.0f);
    s_max = uniform(rng, 0.0f, 2.0f);
}

template <int Q>
struct SplinePieceHitKernel {
    static constexpr const char* name = Q == 2 ? "spline_piece_hit_q2" : "spline_piece_hit_q3";
    static constexpr const char* source = "quadcast::spline::intersect_piece (quadcast/spline/raycast.hpp)";
    static constexpr const char* summary = Q == 2 ? "first isosurface hit of a ray in a quadratic (QSS) piece: barycentric clip, restriction, stable quadratic root, gradient (Kalbe & Zeilfelder 2008, Sect. 5.3)"
                                                  : "first isosurface hit of a ray in a cubic (S31) piece: barycentric clip, restriction, robust cubic root, gradient (Kalbe & Zeilfelder 2008, Sect. 5.3)";
    template <class IO> static void run(IO& io) {
        using T = typename IO::T;
        const auto c = read_bezier<Q>(io, "c");
        const auto beta0 = io.template vec<4>("beta0"), delta = io.template vec<4>("delta");
        const auto s_range = io.template vec<2>("s_range");
        const auto rho = io.scalar("rho");
        Mat<T, 4, 3> dirs{};
        dirs[0] = io.template vec<4>("dir_x");
        dirs[1] = io.template vec<4>("dir_y");
        dirs[2] = io.template vec<4>("dir_z");
        const spline::PieceHit<T> h = spline::intersect_piece<Q>(c, beta0, delta, s_range[0], s_range[1], rho, dirs);
        io.out("hit", h.hit);
        io.out("s", h.s);
        io.out("lambda", h.lambda);
        io.out("gradient", h.gradient);
    }
    static void generate(std::mt19937& rng, std::span<float> in) {
        const int t = std::uniform_int_distribution<int>(0, spline::tets_per_cube - 1)(rng);
        const bb::BezierTet<float, Q> c = random_piece<Q>(rng);
        Vec4<float> beta0{}, delta{};
        float s_min = 0, s_max = 0;
        random_tet_ray(rng, t, beta0, delta, s_min, s_max);
        // rho: the value at a random point of the ray (often a hit), or random
        const float s = uniform(rng, s_min, s_max);
        Vec4<float> l{};
        for (int m = 0; m < 4; ++m) l[m] = beta0[m] + s * delta[m];
        const float rho = std::uniform_int_distribution<int>(0, 3)(rng) ? bb::evaluate(c, l) : uniform(rng, -1.0f, 1.0f);
        const Mat<float, 4, 3> dirs = spline::barycentric_directions<float>(t);
        std::size_t p = 0;
        put_bezier<Q>(in, p, c);
        put(in, p, beta0);
        put(in, p, delta);
        put(in, p, s_min);
        put(in, p, s_max);
        put(in, p, rho);
        for (int a = 0; a < 3; ++a) put(in, p, dirs[a]);
    }
};

struct TrilinearCellHitKernel {
    static constexpr const char* name = "trilinear_cell_hit";
    static constexpr const char* source = "quadcast::spline::intersect_trilinear_cell (quadcast/spline/raycast.hpp)";
    static constexpr const char* summary = "first isosurface hit of a ray in a trilinear cell: cubic BB-form on the segment by blossoming, robust cubic root, gradient";
    template <class IO> static void run(IO& io) {
        using T = typename IO::T;
        const auto v = read_group<8>(io, "v");
        const auto w0 = io.template vec<3>("w0"), d = io.template vec<3>("d");
        const auto s_range = io.template vec<2>("s_range");
        const auto rho = io.scalar("rho");
        const spline::PieceHit<T> h = spline::intersect_trilinear_cell(v, w0, d, s_range[0], s_range[1], rho);
        io.out("hit", h.hit);
        io.out("s", h.s);
        io.out("gradient", h.gradient);
    }
    static void generate(std::mt19937& rng, std::span<float> in) {
        spline::CellCorners<float> v{};
        for (int i = 0; i < 8; ++i) v[i] = uniform(rng, -1.0f, 1.0f);
        const Vec3<float> w0 = vec3(uniform(rng, 0.0f, 1.0f), uniform(rng, 0.0f, 1.0f), uniform(rng, 0.0f, 1.0f));
        const Vec3<float> d = random_point(rng, 1.0f);
        const float s_min = -uniform(rng, 0.0f, 0.5f), s_max = uniform(rng, 0.0f, 1.0f);
        const float s = uniform(rng, s_min, s_max);
        const Vec3<float> w = vec3(w0[0] + s * d[0], w0[1] + s * d[1], w0[2] + s * d[2]);
        const float rho = std::uniform_int_distribution<int>(0, 3)(rng) ? spline::trilinear_value(v, w) : uniform(rng, -1.0f, 1.0f);
        std::size_t p = 0;
        put(in, p, v);
        put(in, p, w0);
        put(in, p, d);
        put(in, p, s_min);
        put(in, p, s_max);
        put(in, p, rho);
    }
};

}  // namespace quadcast::codegen::kernels
