// codegen/kernels/bounds_kernels.hpp -- kernels traced from quadcast/bounds.hpp and primitives.hpp
#pragma once

#include "kernels/common.hpp"
#include "quadcast/bounds.hpp"
#include "quadcast/primitives.hpp"

namespace quadcast::codegen::kernels {

/// A perspective projection times a view times a random affine variance matrix.
inline Mat4<float> random_pmt(std::mt19937& rng) {
    const float n = 0.1f, f = 100.0f, t = uniform(rng, 0.2f, 1.5f) * n, r = t * uniform(rng, 0.8f, 1.6f);
    const float sx = uniform(rng, -0.3f, 0.3f) * r, sy = uniform(rng, -0.3f, 0.3f) * t;  // off-axis frusta
    Mat4<float> p = zero_mat<float, 4, 4>();
    p[0][0] = 2 * n / (2 * r); p[1][1] = 2 * n / (2 * t);
    p[2][0] = (2 * sx) / (2 * r); p[2][1] = (2 * sy) / (2 * t);
    p[2][2] = -(f + n) / (f - n); p[2][3] = -1.0f; p[3][2] = -2 * f * n / (f - n);
    Mat4<float> mt = identity<float, 4>();
    for (int j = 0; j < 3; ++j) for (int i = 0; i < 3; ++i) mt[j][i] = uniform(rng, -1.0f, 1.0f);
    mt[3] = vec4(uniform(rng, -2.0f, 2.0f), uniform(rng, -2.0f, 2.0f), uniform(rng, -30.0f, -2.0f), 1.0f);
    return p * mt;
}

struct SiggBBoxKernel {
    static constexpr const char* name = "sigg_bbox";
    static constexpr const char* source = "quadcast::sigg_bbox, quadcast::sigg_center (quadcast/bounds.hpp)";
    static constexpr const char* summary = "screen-space bounding box of an ellipsoid and its centre (Sigg et al. 2006, eq. 4-5)";
    template <class IO> static void run(IO& io) {
        using T = typename IO::T;
        const Mat4<T> pmt = io.template mat<4>("pmt");
        const Vec4<T> d = io.template vec<4>("d");
        const ScreenBox<T> b = sigg_bbox(pmt, d);
        io.out("lo", b.lo);
        io.out("hi", b.hi);
        io.out("valid", b.valid);
        io.out("center", sigg_center(pmt, d));
    }
    static void generate(std::mt19937& rng, std::span<float> in) {
        std::size_t p = 0;
        put(in, p, random_pmt(rng));
        put(in, p, vec4(1.0f, 1.0f, 1.0f, -1.0f));
    }
};

/// Bounds of a primitive clipped to a slab in parameter space: the caps, plus the eq. 5
/// silhouette where `Silhouette` (non-ruled kinds: paraboloids, hyperboloids).
template <bool Silhouette>
struct SlabBBoxKernel {
    static constexpr const char* name = Silhouette ? "slab_bbox_silhouette" : "slab_bbox_ruled";
    static constexpr const char* source = "quadcast::slab_bbox (quadcast/bounds.hpp)";
    static constexpr const char* summary = Silhouette ? "screen bounds of a slab-clipped quadric: caps and silhouette (Sigg et al. 2006, sec. 3.2)"
                                                      : "screen bounds of a slab-clipped ruled quadric (cylinder, cone): the two caps";
    template <class IO> static void run(IO& io) {
        using T = typename IO::T;
        const Mat4<T> pmt = io.template mat<4>("pmt");
        const Vec4<T> d = io.template vec<4>("d");
        const Vec2<T> slab = io.template vec<2>("slab");
        const ScreenBox<T> b = slab_bbox(pmt, d, slab, Silhouette);
        io.out("lo", b.lo);
        io.out("hi", b.hi);
        io.out("valid", b.valid);
    }
    static void generate(std::mt19937& rng, std::span<float> in) {
        std::size_t p = 0;
        put(in, p, random_pmt(rng));
        put(in, p, Silhouette ? vec4(1.0f, 1.0f, 1.0f, -1.0f) : vec4(1.0f, 1.0f, 0.0f, -1.0f));
        put(in, p, Silhouette ? vec2(-1.0f, 0.0f) : vec2(-1.0f, 1.0f));
    }
};

struct WindowRayKernel {
    static constexpr const char* name = "intersect_window";
    static constexpr const char* source = "quadcast::intersect_window (quadcast/bounds.hpp)";
    static constexpr const char* summary = "ray-quadric intersection in window coordinates (Sigg et al. 2006, eq. 6-7)";
    template <class IO> static void run(IO& io) {
        using T = typename IO::T;
        const Mat4<T> vpmt_inv = io.template mat<4>("vpmt_inv");
        const Vec4<T> d = io.template vec<4>("d");
        const T xw = io.scalar("xw"), yw = io.scalar("yw");
        const WindowHit<T> h = intersect_window(vpmt_inv, d, xw, yw);
        io.out("hit", h.hit);
        io.out("z_near", h.z_near);
        io.out("z_far", h.z_far);
        io.out("p_near", h.p_near);
        io.out("p_far", h.p_far);
    }
    static void generate(std::mt19937& rng, std::span<float> in) {
        std::size_t p = 0;
        put(in, p, random_pmt(rng));  // a stand-in: any invertible matrix exercises the formula
        put(in, p, vec4(1.0f, 1.0f, 1.0f, -1.0f));
        put(in, p, uniform(rng, 0.0f, 1024.0f));
        put(in, p, uniform(rng, 0.0f, 768.0f));
    }
};

struct SphereQuadKernel {
    static constexpr const char* name = "sphere_quad";
    static constexpr const char* source = "quadcast::sphere_quad (quadcast/bounds.hpp)";
    static constexpr const char* summary = "view-space quad tightly enclosing the projection of a sphere";
    template <class IO> static void run(IO& io) {
        using T = typename IO::T;
        const Vec3<T> c = io.template vec<3>("center");
        const T r = io.scalar("radius");
        const SphereQuad<T> q = sphere_quad(c, r);
        for (int i = 0; i < 4; ++i) io.out("corner" + std::to_string(i), q.corner[i]);
        io.out("half_size", q.half_size);
        io.out("valid", q.valid);
    }
    static void generate(std::mt19937& rng, std::span<float> in) {
        std::size_t p = 0;
        put(in, p, random_direction(rng) * std::ldexp(1.0f, std::uniform_int_distribution<int>(-2, 12)(rng)));
        put(in, p, uniform(rng, 0.01f, 2.0f));
    }
};

}  // namespace quadcast::codegen::kernels
