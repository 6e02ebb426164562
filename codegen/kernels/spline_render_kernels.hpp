// codegen/kernels/spline_render_kernels.hpp -- kernels traced from quadcast/spline/raycast.hpp (ray vs spline piece, ray vs trilinear cell)
#pragma once

#include <string>

#include "kernels/common.hpp"
#include "kernels/spline_kernels.hpp"
#include "quadcast/spline/raycast.hpp"
#include "quadcast/spline/render.hpp"

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

// ---- The GPU isosurface renderer's stages (quadcast/spline/render.hpp) ---------------------------

/// A random camera for the isosurface stages: a view-space z of a ray direction in front of the
/// camera and a perspective or orthographic projection's depth terms pz.
inline void random_depth_terms(std::mt19937& rng, bool ortho, Vec4<float>& pz, float& vz) {
    vz = ortho ? -1.0f : -uniform(rng, 0.05f, 3.0f);
    // near and far planes at ray parameters λ in [0.001, 0.3] and 10..1000 times that
    const float n = uniform(rng, 0.001f, 0.3f) * -vz, f = n * uniform(rng, 10.0f, 1000.0f);
    if (ortho) pz = Vec4<float>{{-2.0f / (f - n), -(f + n) / (f - n), 0.0f, 1.0f}};
    else pz = Vec4<float>{{-(f + n) / (f - n), -2.0f * f * n / (f - n), -1.0f, 0.0f}};
}

/// The GPU element list's frustum test: whether an element's corners lie wholly beyond one plane
/// of the clip volume (`clip_outside`).
struct ClipOutsideKernel {
    static constexpr const char* name = "clip_outside";
    static constexpr const char* source = "quadcast::spline::clip_outside (quadcast/spline/render.hpp)";
    static constexpr const char* summary = "isosurface renderer, element list: whether an element's corners lie beyond one plane of the clip volume";
    template <class IO> static void run(IO& io) {
        std::array<Vec4<typename IO::T>, 8> c{};
        for (int k = 0; k < 8; ++k) c[static_cast<std::size_t>(k)] = io.template vec<4>(corner_names[k]);
        io.out("outside", spline::clip_outside(c));
    }
    static constexpr const char* corner_names[8] = {"c0", "c1", "c2", "c3", "c4", "c5", "c6", "c7"};
    static void generate(std::mt19937& rng, std::span<float> in) {
        std::size_t p = 0;
        // Corners around a random clip position, some clusters wholly beyond a plane, some across it
        const Vec4<float> base = vec4(uniform(rng, -3.0f, 3.0f), uniform(rng, -3.0f, 3.0f), uniform(rng, -3.0f, 3.0f), uniform(rng, -1.0f, 2.0f));
        const float spread = uniform(rng, 0.0f, 1.0f) < 0.5f ? 0.01f : 1.0f;
        for (int k = 0; k < 8; ++k)
            put(in, p, base + vec4(uniform(rng, -spread, spread), uniform(rng, -spread, spread), uniform(rng, -spread, spread), uniform(rng, -spread, spread)));
    }
};

/// The random camera and volume placement of the isosurface vertex-stage kernels' inputs: the eye
/// in index and world space, the viewing direction, origin, spacing, a view_proj and vz_row, put
/// in that order.
inline void put_cell_camera(std::mt19937& rng, std::span<float> in, std::size_t& p) {
    const Vec3<float> spacing = vec3(uniform(rng, 0.2f, 3.0f), uniform(rng, 0.2f, 3.0f), uniform(rng, 0.2f, 3.0f));
    const Vec3<float> origin = random_point(rng, 100.0f);
    const Vec3<float> eye_world = random_point(rng, 800.0f);
    Vec3<float> eye_index{};
    for (int a = 0; a < 3; ++a) eye_index[a] = (eye_world[a] - origin[a]) / spacing[a];
    const Mat3<float> rot = random_rotation(rng);  // world -> view
    const Vec3<float> vz_row = vec3(rot[0][2], rot[1][2], rot[2][2]);
    put(in, p, eye_index);
    put(in, p, eye_world);
    put(in, p, -vz_row);
    put(in, p, origin);
    put(in, p, spacing);
    Mat4<float> vp{};
    for (int j = 0; j < 4; ++j)
        for (int i = 0; i < 4; ++i) vp[j][i] = uniform(rng, -2.0f, 2.0f);
    put(in, p, vp);
    put(in, p, vz_row);
}

/// The isosurface renderer's occlusion culling: a lower bound of the window depth of an element's
/// hits and the NDC rectangle of its pixels, per camera kind: a tetrahedron of a spline cube
/// (`tet_occlusion_bound`, its cube-local corners as inputs) or a trilinear cell
/// (`cell_occlusion_bound`).
template <bool Ortho, bool Cell>
struct OcclusionBoundKernel {
    static constexpr const char* name = Cell ? (Ortho ? "cell_occlusion_bound_ortho" : "cell_occlusion_bound_perspective")
                                             : (Ortho ? "tet_occlusion_bound_ortho" : "tet_occlusion_bound_perspective");
    static constexpr const char* source = Cell ? "quadcast::spline::cell_occlusion_bound (quadcast/spline/render.hpp)"
                                               : "quadcast::spline::tet_occlusion_bound (quadcast/spline/render.hpp)";
    static constexpr const char* summary =
        Cell ? (Ortho ? "isosurface renderer, occlusion culling: depth floor and NDC rectangle of a trilinear cell's hits, orthographic camera"
                      : "isosurface renderer, occlusion culling: depth floor and NDC rectangle of a trilinear cell's hits, perspective camera")
             : (Ortho ? "isosurface renderer, occlusion culling: depth floor and NDC rectangle of a tetrahedron's hits, orthographic camera"
                      : "isosurface renderer, occlusion culling: depth floor and NDC rectangle of a tetrahedron's hits, perspective camera");
    template <class IO> static void run(IO& io) {
        const auto c = io.template vec<3>("anchor");
        std::array<Vec3<typename IO::T>, 4> u{};
        if constexpr (!Cell)
            for (int k = 0; k < 4; ++k) u[static_cast<std::size_t>(k)] = io.template vec<3>(corner_names[k]);
        const auto eye_index = io.template vec<3>("eye_index");
        const auto eye_world = io.template vec<3>("eye_world");
        const auto forward = io.template vec<3>("forward_world");
        const auto origin = io.template vec<3>("origin");
        const auto spacing = io.template vec<3>("spacing");
        const Mat4<typename IO::T> view_proj = io.template mat<4>("view_proj");
        const auto vz_row = io.template vec<3>("vz_row");
        const auto pz = io.template vec<4>("pz");
        const auto pixel = io.scalar("pixel");
        const spline::OcclusionBound<typename IO::T> b =
            Cell ? spline::cell_occlusion_bound(c, eye_index, eye_world, forward, origin, spacing, view_proj, vz_row, pz, pixel, Ortho)
                 : spline::tet_occlusion_bound(c, u, eye_index, eye_world, forward, origin, spacing, view_proj, vz_row, pz, pixel, Ortho);
        io.out("floor", b.floor);
        io.out("lo", b.lo);
        io.out("hi", b.hi);
        io.out("visible", b.visible);
    }
    static constexpr const char* corner_names[4] = {"u0", "u1", "u2", "u3"};
    static void generate(std::mt19937& rng, std::span<float> in) {
        std::size_t p = 0;
        const auto cell = [&] { return float(std::uniform_int_distribution<int>(0, 500)(rng)); };
        put(in, p, vec3(cell(), cell(), cell()));
        if constexpr (!Cell) {
            const auto v = spline::tet_vertices(std::uniform_int_distribution<int>(0, spline::tets_per_cube - 1)(rng));
            for (const auto& k : v) put(in, p, vec3(float(k[0]), float(k[1]), float(k[2])));
        }
        put_cell_camera(rng, in, p);
        Vec4<float> pz{};
        float vz = 0;
        random_depth_terms(rng, Ortho, pz, vz);
        put(in, p, pz);
        put(in, p, std::ldexp(1.0f, std::uniform_int_distribution<int>(-14, -6)(rng)) * uniform(rng, 1.0f, 2.0f));  // pixel
    }
};

template <bool Ortho>
struct SplineCellVertexKernel {
    static constexpr const char* name = Ortho ? "spline_cell_vertex_ortho" : "spline_cell_vertex_perspective";
    static constexpr const char* source = "quadcast::spline::cell_vertex (quadcast/spline/render.hpp)";
    static constexpr const char* summary = Ortho ? "isosurface renderer, vertex stage: clip position and cube-local ray of a vertex of a cell's implicit geometry, orthographic camera"
                                                 : "isosurface renderer, vertex stage: clip position and cube-local ray of a vertex of a cell's implicit geometry, perspective camera";
    template <class IO> static void run(IO& io) {
        using T = typename IO::T;
        const auto c = io.template vec<3>("anchor");
        const auto u = io.template vec<3>("offset");
        const auto s = io.template vec<2>("scale");  // s, 1/s
        const auto eye_index = io.template vec<3>("eye_index");
        const auto eye_world = io.template vec<3>("eye_world");
        const auto forward = io.template vec<3>("forward_world");
        const auto origin = io.template vec<3>("origin");
        const auto spacing = io.template vec<3>("spacing");
        const Mat4<T> view_proj = io.template mat<4>("view_proj");
        const auto vz_row = io.template vec<3>("vz_row");
        const spline::CellVertex<T> r = spline::cell_vertex(c, u, s[0], s[1], eye_index, eye_world, forward, origin, spacing, view_proj, vz_row, Ortho);
        io.out("clip", r.clip);
        io.out("o", r.o);
        io.out("w", r.w);
        io.out("v", r.v);
        io.out("dir", r.dir);
        io.out("vz", r.vz);
    }
    static void generate(std::mt19937& rng, std::span<float> in) {
        std::size_t p = 0;
        const bool half = std::uniform_int_distribution<int>(0, 1)(rng) != 0;
        const auto cell = [&] { return float(std::uniform_int_distribution<int>(0, 500)(rng)); };
        const auto unit = [&] { return float(std::uniform_int_distribution<int>(-1, 1)(rng)); };
        put(in, p, vec3(cell(), cell(), cell()));
        put(in, p, half ? vec3(unit(), unit(), unit()) : vec3(std::abs(unit()), std::abs(unit()), std::abs(unit())));
        put(in, p, half ? vec2(0.5f, 2.0f) : vec2(1.0f, 1.0f));
        put_cell_camera(rng, in, p);
    }
};

/// R_t as a column-major float matrix (entries 0, ±1).
inline Mat3<float> rotation_matrix(int t) {
    const spline::IMat3 r = spline::rotation(t);
    Mat3<float> m{};
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) m[j][i] = static_cast<float>(r[i][j]);
    return m;
}

template <int Q>
struct SplineFragmentKernel {
    static constexpr const char* name = Q == 2 ? "spline_fragment_q2" : "spline_fragment_q3";
    static constexpr const char* source = "quadcast::spline::spline_fragment (quadcast/spline/render.hpp)";
    static constexpr const char* summary = Q == 2 ? "isosurface renderer, fragment stage of a QSS tetrahedron: rotate the re-origined interpolated ray to T_0, clip, restrict, stable quadratic root, depth, world normal"
                                                  : "isosurface renderer, fragment stage of an S31 tetrahedron: rotate the re-origined interpolated ray to T_0, clip, restrict, robust cubic root, depth, world normal";
    template <class IO> static void run(IO& io) {
        using T = typename IO::T;
        const auto c = read_bezier<Q>(io, "c");
        const Mat3<T> rot = io.template mat<3>("rot");
        const auto o = io.template vec<3>("o");
        const auto w = io.scalar("w");
        const auto v = io.template vec<3>("v");
        const auto vz = io.scalar("vz");
        const auto pz = io.template vec<4>("pz");
        const auto rho = io.scalar("rho");
        const auto grad_scale = io.template vec<3>("grad_scale");
        const auto pixel = io.scalar("pixel");
        const spline::IsoFragment<T> f = spline::spline_fragment<Q>(c, rot, o, w, v, vz, pz, rho, grad_scale, pixel);
        io.out("hit", f.hit);
        io.out("depth", f.depth);
        io.out("normal", f.normal);
    }
    static void generate(std::mt19937& rng, std::span<float> in) {
        const int t = std::uniform_int_distribution<int>(0, spline::tets_per_cube - 1)(rng);
        const bb::BezierTet<float, Q> c = random_piece<Q>(rng);
        const bool ortho = std::uniform_int_distribution<int>(0, 3)(rng) == 0;
        Vec4<float> pz{};
        float vz = 0;
        random_depth_terms(rng, ortho, pz, vz);
        // The ray: re-origined at a point o of the cube (the drawn face), coming from a random
        // direction through a point `target` before it; w = the λ of o
        const Vec3<float> o = random_point(rng, 1.05f), target = random_point(rng, 1.0f);
        const float w = uniform(rng, 0.5f, 3.0f);
        const Vec3<float> v = (o - target) * (1.0f / uniform(rng, 0.5f, 2.0f));
        // rho: the value at the tetrahedron's point of the ray (often a hit), or random
        const Vec4<float> l = spline::barycentric(t, target);
        const float rho = std::uniform_int_distribution<int>(0, 3)(rng) ? bb::evaluate(c, l) : uniform(rng, -1.0f, 1.0f);
        std::size_t p = 0;
        put_bezier<Q>(in, p, c);
        put(in, p, rotation_matrix(t));
        put(in, p, o);
        put(in, p, w);
        put(in, p, v);
        put(in, p, vz);
        put(in, p, pz);
        put(in, p, rho);
        put(in, p, vec3(uniform(rng, 0.3f, 4.0f), uniform(rng, 0.3f, 4.0f), uniform(rng, 0.3f, 4.0f)));
        put(in, p, std::ldexp(1.0f, std::uniform_int_distribution<int>(-14, -6)(rng)) * uniform(rng, 1.0f, 2.0f));  // pixel
    }
};

struct TrilinearFragmentKernel {
    static constexpr const char* name = "trilinear_fragment";
    static constexpr const char* source = "quadcast::spline::trilinear_fragment (quadcast/spline/render.hpp)";
    static constexpr const char* summary = "isosurface renderer, fragment stage of a trilinear cell: clip the interpolated ray to the cell, cubic BB-form, robust root, depth, world normal";
    template <class IO> static void run(IO& io) {
        using T = typename IO::T;
        const auto v = read_group<8>(io, "corners");
        const auto o = io.template vec<3>("o");
        const auto w = io.scalar("w");
        const auto d = io.template vec<3>("v");
        const auto vz = io.scalar("vz");
        const auto pz = io.template vec<4>("pz");
        const auto rho = io.scalar("rho");
        const auto grad_scale = io.template vec<3>("grad_scale");
        const auto pixel = io.scalar("pixel");
        const spline::IsoFragment<T> f = spline::trilinear_fragment(v, o, w, d, vz, pz, rho, grad_scale, pixel);
        io.out("hit", f.hit);
        io.out("depth", f.depth);
        io.out("normal", f.normal);
    }
    static void generate(std::mt19937& rng, std::span<float> in) {
        spline::CellCorners<float> v{};
        for (int i = 0; i < 8; ++i) v[i] = uniform(rng, -1.0f, 1.0f);
        const bool ortho = std::uniform_int_distribution<int>(0, 3)(rng) == 0;
        Vec4<float> pz{};
        float vz = 0;
        random_depth_terms(rng, ortho, pz, vz);
        // Re-origined on a face point o of the cell, coming through `target` (as for the tetrahedra)
        const Vec3<float> target = vec3(uniform(rng, 0.0f, 1.0f), uniform(rng, 0.0f, 1.0f), uniform(rng, 0.0f, 1.0f));
        Vec3<float> o = vec3(uniform(rng, 0.0f, 1.0f), uniform(rng, 0.0f, 1.0f), uniform(rng, 0.0f, 1.0f));
        o[std::uniform_int_distribution<int>(0, 2)(rng)] = float(std::uniform_int_distribution<int>(0, 1)(rng));
        const float w = uniform(rng, 0.5f, 3.0f);
        const Vec3<float> d = (o - target) * (1.0f / uniform(rng, 0.5f, 2.0f));
        const float rho = std::uniform_int_distribution<int>(0, 3)(rng) ? spline::trilinear_value(v, target) : uniform(rng, -1.0f, 1.0f);
        std::size_t p = 0;
        put(in, p, v);
        put(in, p, o);
        put(in, p, w);
        put(in, p, d);
        put(in, p, vz);
        put(in, p, pz);
        put(in, p, rho);
        put(in, p, vec3(uniform(rng, 0.3f, 4.0f), uniform(rng, 0.3f, 4.0f), uniform(rng, 0.3f, 4.0f)));
        put(in, p, std::ldexp(1.0f, std::uniform_int_distribution<int>(-14, -6)(rng)) * uniform(rng, 1.0f, 2.0f));  // pixel
    }
};

}  // namespace quadcast::codegen::kernels
