// codegen/kernels/ray_kernels.hpp -- kernels traced from quadcast/ray.hpp, cull.hpp and bilinear.hpp
#pragma once

#include "kernels/common.hpp"
#include "quadcast/bilinear.hpp"
#include "quadcast/cull.hpp"
#include "quadcast/quadric.hpp"
#include "quadcast/ray.hpp"

namespace quadcast::codegen::kernels {

/// A quadric, an eye near or far from it, and a direction that mostly points at it.
inline void generate_quadric_ray(std::mt19937& rng, std::span<float> in) {
    std::size_t p = 0;
    const Mat4<float> q = random_quadric(rng);
    const float dist = std::ldexp(1.0f, std::uniform_int_distribution<int>(0, 16)(rng));
    const Vec3<float> eye = random_direction(rng) * dist;
    const Vec3<float> target = random_point(rng, 1.0f);
    Vec3<float> v = normalize(target - eye);
    if (std::uniform_int_distribution<int>(0, 3)(rng) == 0) v = random_direction(rng);
    put(in, p, q);
    put(in, p, eye);
    put(in, p, v);
}

/// Ray coefficients: mostly from real rays, some with alpha near 0 or grazing.
inline void generate_coefficients(std::mt19937& rng, std::span<float> in) {
    const int kind = std::uniform_int_distribution<int>(0, 3)(rng);
    float a = uniform(rng, -1.0f, 1.0f), b = uniform(rng, -1.0f, 1.0f), c = uniform(rng, -1.0f, 1.0f);
    if (kind == 1) a *= std::ldexp(1.0f, -std::uniform_int_distribution<int>(10, 40)(rng));  // alpha -> 0
    if (kind == 2) c = b * b / a * (1.0f + uniform(rng, -1e-5f, 1e-5f));                    // grazing
    in[0] = a; in[1] = b; in[2] = c;
}

struct RayCoefficientsKernel {
    static constexpr const char* name = "ray_coefficients";
    static constexpr const char* source = "quadcast::ray_coefficients (quadcast/ray.hpp)";
    static constexpr const char* summary = "alpha, beta, gamma of the ray e + lambda v (Stoll et al. 2006, eq. 6)";
    template <class IO> static void run(IO& io) {
        using T = typename IO::T;
        const Quadric<T> q{io.template mat<4>("q")};
        const Vec3<T> e = io.template vec<3>("eye"), v = io.template vec<3>("dir");
        const RayCoefficients<T> c = ray_coefficients(q, e, v);
        io.out("alpha", c.alpha);
        io.out("beta", c.beta);
        io.out("gamma", c.gamma);
    }
    static void generate(std::mt19937& rng, std::span<float> in) { generate_quadric_ray(rng, in); }
};

struct RayQuadraticLocalKernel {
    static constexpr const char* name = "ray_quadratic_local";
    static constexpr const char* source = "quadcast::ray_quadratic_local (quadcast/ray.hpp)";
    static constexpr const char* summary = "ray coefficients and the re-origined discriminant -alpha f(x0) (local coordinates)";
    template <class IO> static void run(IO& io) {
        using T = typename IO::T;
        const Quadric<T> q{io.template mat<4>("q_local")};
        const Vec3<T> o = io.template vec<3>("eye_local"), v = io.template vec<3>("dir");
        const RayQuadratic<T> r = ray_quadratic_local(q, o, v);
        io.out("alpha", r.c.alpha);
        io.out("beta", r.c.beta);
        io.out("gamma", r.c.gamma);
        io.out("disc", r.disc);
    }
    static void generate(std::mt19937& rng, std::span<float> in) { generate_quadric_ray(rng, in); }
};

template <RootFormula F>
struct FrontRootKernel {
    static constexpr const char* name = F == RootFormula::classic ? "ray_front_root_classic" : F == RootFormula::stoll ? "ray_front_root_stoll" : "ray_front_root";
    static constexpr const char* source = "quadcast::front_root (quadcast/ray.hpp)";
    static constexpr const char* summary = F == RootFormula::classic ? "front-facing root, Stoll et al. 2006 eq. 7 with the linear case"
                                         : F == RootFormula::stoll  ? "front-facing root, Stoll et al. 2006 eq. 15"
                                                                    : "front-facing root, cancellation-free (default)";
    template <class IO> static void run(IO& io) {
        using T = typename IO::T;
        const RayCoefficients<T> c{io.scalar("alpha"), io.scalar("beta"), io.scalar("gamma")};
        const RayHit<T> h = front_root<F>(c);
        io.out("lambda", h.lambda);
        io.out("hit", h.hit);
    }
    static void generate(std::mt19937& rng, std::span<float> in) { generate_coefficients(rng, in); }
};

struct RootsNearFirstKernel {
    static constexpr const char* name = "ray_roots_near_first";
    static constexpr const char* source = "quadcast::roots_near_first (quadcast/ray.hpp)";
    static constexpr const char* summary = "both roots, nearest positive first (Stoll et al. 2006, sec. 4.4.3, corrected)";
    template <class IO> static void run(IO& io) {
        using T = typename IO::T;
        const RayCoefficients<T> c{io.scalar("alpha"), io.scalar("beta"), io.scalar("gamma")};
        const RootPair<T> r = roots_near_first(c);
        io.out("lambda_near", r.lambda_near);
        io.out("lambda_far", r.lambda_far);
        io.out("near_valid", r.near_valid);
        io.out("far_valid", r.far_valid);
    }
    static void generate(std::mt19937& rng, std::span<float> in) { generate_coefficients(rng, in); }
};

struct CullSphereKernel {
    static constexpr const char* name = "cull_sphere";
    static constexpr const char* source = "quadcast::cull_sphere (quadcast/cull.hpp)";
    static constexpr const char* summary = "per-quadric back-face culling against a bounding sphere (Stoll et al. 2006, sec. 4.4.4)";
    template <class IO> static void run(IO& io) {
        using T = typename IO::T;
        const Quadric<T> q{io.template mat<4>("q")};
        const Vec3<T> e = io.template vec<3>("eye");
        const Vec3<T> c = io.template vec<3>("center");
        const T r = io.scalar("radius");
        io.out("culled", cull_sphere(q, e, c, r));
    }
    static void generate(std::mt19937& rng, std::span<float> in) {
        std::size_t p = 0;
        put(in, p, random_quadric(rng));
        put(in, p, random_direction(rng) * uniform(rng, 0.5f, 50.0f));
        put(in, p, random_point(rng, 1.0f));
        put(in, p, uniform(rng, 0.1f, 3.0f));
    }
};

struct CullTetKernel {
    static constexpr const char* name = "cull_tet";
    static constexpr const char* source = "quadcast::cull_tet (quadcast/cull.hpp)";
    static constexpr const char* summary = "per-quadric back-face culling against a bounding tetrahedron (Stoll et al. 2006, eq. 19)";
    template <class IO> static void run(IO& io) {
        using T = typename IO::T;
        const Quadric<T> q{io.template mat<4>("q")};
        const Vec3<T> e = io.template vec<3>("eye");
        const BoundingTet<T> t{{io.template vec<3>("p1"), io.template vec<3>("p2"), io.template vec<3>("p3"), io.template vec<3>("p4")}};
        io.out("culled", cull_tet(q, e, t));
    }
    static void generate(std::mt19937& rng, std::span<float> in) {
        std::size_t p = 0;
        put(in, p, random_quadric(rng));
        put(in, p, random_direction(rng) * uniform(rng, 0.5f, 50.0f));
        for (int i = 0; i < 4; ++i) put(in, p, random_point(rng, 1.0f));
    }
};

struct InsideTetKernel {
    static constexpr const char* name = "inside_tet";
    static constexpr const char* source = "quadcast::tet_planes, quadcast::inside_tet (quadcast/ray.hpp)";
    static constexpr const char* summary = "inward face planes of a tetrahedron and the point-in-tetrahedron test";
    template <class IO> static void run(IO& io) {
        using T = typename IO::T;
        const BoundingTet<T> t{{io.template vec<3>("p1"), io.template vec<3>("p2"), io.template vec<3>("p3"), io.template vec<3>("p4")}};
        const Vec3<T> x = io.template vec<3>("x");
        io.out("inside", inside_tet(tet_planes(t), x));
    }
    static void generate(std::mt19937& rng, std::span<float> in) {
        std::size_t p = 0;
        for (int i = 0; i < 5; ++i) put(in, p, random_point(rng, 1.0f));
    }
};

struct BilinearLocalKernel {
    static constexpr const char* name = "bilinear_to_local_quadric";
    static constexpr const char* source = "quadcast::bilinear_to_local_quadric (quadcast/bilinear.hpp)";
    static constexpr const char* summary = "bilinear quad -> quadric in coordinates relative to p1 (Stoll et al. 2006, eq. 20-29)";
    template <class IO> static void run(IO& io) {
        using T = typename IO::T;
        const Vec3<T> p1 = io.template vec<3>("p1"), p2 = io.template vec<3>("p2"), p3 = io.template vec<3>("p3"), p4 = io.template vec<3>("p4");
        const LocalQuadric<T> l = bilinear_to_local_quadric(p1, p2, p3, p4);
        io.out("q_local", l.quadric.q);
        io.out("origin", l.origin);
    }
    static void generate(std::mt19937& rng, std::span<float> in) {
        std::size_t p = 0;
        const Vec3<float> o = random_point(rng, 10.0f), a = random_direction(rng), b = random_direction(rng), w = random_direction(rng);
        const float h = std::ldexp(1.0f, -std::uniform_int_distribution<int>(0, 20)(rng));
        put(in, p, o);
        put(in, p, o + a);
        put(in, p, (o + a) + (b + w * h));
        put(in, p, o + b);
    }
};

}  // namespace quadcast::codegen::kernels
