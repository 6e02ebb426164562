// codegen/kernels/slim_kernels.hpp -- the kernels of the GL SLIM renderer (quadcast/slim_blend.hpp)
#pragma once

#include <cmath>
#include <utility>
#include <string>

#include "kernels/common.hpp"
#include "kernels/render_kernels.hpp"
#include "quadcast/raycast.hpp"
#include "quadcast/slim_blend.hpp"

namespace quadcast::codegen::kernels {

/// The SLIM blending weight of t = |x - c| / r (`slim_weight`).
struct SlimWeightKernel {
    static constexpr const char* name = "slim_weight";
    static constexpr const char* source = "quadcast::slim_weight (quadcast/slim_blend.hpp)";
    static constexpr const char* summary = "SLIM blending weight: Gaussian core, quadratic tail, C1, 1 at the centre, 0 on the sphere";
    template <class IO> static void run(IO& io) { io.out("w", slim_weight(io.scalar("t"))); }
    static void generate(std::mt19937& rng, std::span<float> in) {
        std::size_t p = 0;
        put(in, p, uniform(rng, 0.0f, 1.0f) < 0.1f ? uniform(rng, 0.4999f, 0.5001f) : uniform(rng, 0.0f, 1.2f));
    }
};

/// Per fragment of a SLIM ball (the visibility and the accumulation pass): the local ray of the
/// pixel's world ray (`local_ray`), then `slim_fragment` (the quadric clipped to its ball and its
/// two planes): hit, window depth, the visibility pass's pushed depth, ray parameter, unit normal, weight.
template <bool Cull>
struct SlimFragmentKernel {
    static constexpr const char* name = Cull ? "slim_fragment" : "slim_fragment_nocull";
    static constexpr const char* source = "quadcast::local_ray (quadcast/raycast.hpp), quadcast::slim_fragment (quadcast/slim_blend.hpp)";
    static constexpr const char* summary = "SLIM ball: a fragment's hit, depth, pushed visibility depth, ray parameter, unit normal and weight";
    template <class IO> static void run(IO& io) {
        using T = typename IO::T;
        ClippedQuadric<T> p = primitive_inputs(io);
        p.planes[0] = io.template vec<4>("plane");
        p.planes[1] = io.template vec<4>("plane2");
        const Vec3<T> origin = io.template vec<3>("origin");
        const Vec3<T> dir = io.template vec<3>("dir");
        const Vec3<T> vz_row = io.template vec<3>("vz_row");
        const Vec4<T> pz = io.template vec<4>("pz");
        const SlimFragment<T> f = slim_fragment<Cull>(p, local_ray(p, origin, dir), vz_row, pz);
        io.out("hit", f.hit);
        io.out("depth", f.depth);
        io.out("visibility", f.visibility);
        io.out("lambda", f.lambda);
        io.out("normal", f.normal);
        io.out("weight", f.weight);
    }
    static void generate(std::mt19937& rng, std::span<float> in) {
        std::size_t p = 0;
        put_primitive(rng, in, p);
        // Two planes through the ball (or none) in local coordinates.
        for (int k = 0; k < 2; ++k) {
            if (uniform(rng, 0.0f, 1.0f) < (k == 0 ? 0.3f : 0.6f)) put(in, p, vec4(0.0f, 0.0f, 0.0f, 1.0f));
            else put(in, p, vec4(random_direction(rng), uniform(rng, -1.0f, 1.0f)));
        }
        const Vec3<float> o = random_point(rng, 50.0f) + random_direction(rng) * uniform(rng, 1.0f, 100.0f);
        put(in, p, o);
        put(in, p, normalize(random_point(rng, 50.0f) - o));
        put(in, p, random_direction(rng));
        put(in, p, vec4(-1.002f, -0.2002f, -1.0f, 0.0f));
    }
};

/// The accumulation pass's outputs of one fragment (`slim_terms`): the products the additive
/// blend sums into the three targets.
struct SlimTermsKernel {
    static constexpr const char* name = "slim_terms";
    static constexpr const char* source = "quadcast::slim_terms (quadcast/slim_blend.hpp)";
    static constexpr const char* summary = "SLIM accumulation: a fragment's weighted normal, weight, ray parameter, material and colour";
    template <class IO> static void run(IO& io) {
        using T = typename IO::T;
        const T w = io.scalar("weight");
        const Vec3<T> n = io.template vec<3>("normal");
        const T lambda = io.scalar("lambda");
        const Vec3<T> color = io.template vec<3>("color");
        const Vec2<T> material = io.template vec<2>("material");
        const SlimSums<T> s = slim_terms(w, n, lambda, color, material);
        io.out("normal_weight", s.normal_weight);
        io.out("lambda_material", s.lambda_material);
        io.out("color_sum", s.color);
    }
    static void generate(std::mt19937& rng, std::span<float> in) {
        std::size_t p = 0;
        put(in, p, uniform(rng, 0.0f, 1.0f));
        put(in, p, random_direction(rng));
        put(in, p, uniform(rng, 0.1f, 100.0f));
        put(in, p, vec3(uniform(rng, 0.0f, 1.0f), uniform(rng, 0.0f, 1.0f), uniform(rng, 0.0f, 1.0f)));
        put(in, p, vec2(uniform(rng, 0.0f, 1.0f), uniform(rng, 1.0f, 128.0f)));
    }
};

/// The shading pass's resolve of a SLIM pixel (`slim_resolve`): the accumulated sums divided by
/// the weight; vz = dot(vz_row, dir) of the pixel's ray.
struct SlimResolveKernel {
    static constexpr const char* name = "slim_resolve";
    static constexpr const char* source = "quadcast::slim_resolve (quadcast/slim_blend.hpp)";
    static constexpr const char* summary = "SLIM pixel: blended unit normal, ray parameter, window depth, colour and material from the weighted sums";
    template <class IO> static void run(IO& io) {
        using T = typename IO::T;
        const Vec4<T> nw = io.template vec<4>("normal_weight");
        const Vec4<T> lm = io.template vec<4>("lambda_material");
        const Vec3<T> color = io.template vec<3>("color_sum");
        const Vec3<T> dir = io.template vec<3>("dir");
        const Vec3<T> vz_row = io.template vec<3>("vz_row");
        const Vec4<T> pz = io.template vec<4>("pz");
        const SlimResolved<T> r = slim_resolve(nw, lm, color, dot(vz_row, dir), pz);
        io.out("covered", r.covered);
        io.out("normal", r.normal);
        io.out("lambda", r.lambda);
        io.out("depth", r.depth);
        io.out("color", r.color);
        io.out("material", r.material);
    }
    static void generate(std::mt19937& rng, std::span<float> in) {
        std::size_t p = 0;
        const float w = uniform(rng, 0.0f, 1.0f) < 0.05f ? 0.0f : uniform(rng, 0.001f, 6.0f);
        put(in, p, vec4(random_direction(rng) * w, w));
        put(in, p, vec4(uniform(rng, 0.5f, 50.0f) * w, uniform(rng, 0.0f, 1.0f) * w, uniform(rng, 1.0f, 128.0f) * w, 0.0f));
        put(in, p, vec3(uniform(rng, 0.0f, 1.0f), uniform(rng, 0.0f, 1.0f), uniform(rng, 0.0f, 1.0f)) * w);
        put(in, p, random_direction(rng));
        put(in, p, random_direction(rng));
        put(in, p, vec4(-1.002f, -0.2002f, -1.0f, 0.0f));
    }
};

/// A random `SlimPatch` of a ball of radius r: a unit axis, rho up to r, a slab inside [-r, r]
/// (empty in 5% of the draws), a cone of 0-90 degrees.
inline void put_slim_patch(std::mt19937& rng, std::span<float> in, std::size_t& p, float r) {
    put(in, p, vec4(random_direction(rng), uniform(rng, 0.0f, r)));
    float lo = uniform(rng, -r, r), hi = uniform(rng, -r, r);
    if (lo > hi && uniform(rng, 0.0f, 1.0f) < 0.95f) std::swap(lo, hi);
    const float theta = uniform(rng, 0.0f, 1.5707963f);
    put(in, p, vec4(lo, hi, std::cos(theta), std::sin(theta)));
}

/// Per vertex of a SLIM ball's bounding geometry: the padded screen quadrilateral of its patch
/// (`slim_patch_quad`), and whether it is tight and visible.
struct SlimPatchQuadKernel {
    static constexpr const char* name = "slim_patch_quad";
    static constexpr const char* source = "quadcast::slim_patch_quad (quadcast/slim_blend.hpp), quadcast::sections_quad (quadcast/bounds.hpp)";
    static constexpr const char* summary = "SLIM ball: the screen quadrilateral of its patch's slab cylinder, along its projected axis";
    template <class IO> static void run(IO& io) {
        using T = typename IO::T;
        const Mat4<T> vp = io.template mat<4>("view_projection");
        const Vec3<T> center = io.template vec<3>("center");
        const Vec4<T> axis_rho = io.template vec<4>("axis_rho");
        const Vec4<T> slab_cone = io.template vec<4>("slab_cone");
        const Vec2<T> viewport = io.template vec<2>("viewport");
        const ScreenQuad<T> r = slim_patch_quad(vp, center, axis_rho, slab_cone, viewport);
        io.out("c0", r.corner[0]);
        io.out("c1", r.corner[1]);
        io.out("c2", r.corner[2]);
        io.out("c3", r.corner[3]);
        io.out("tight", r.tight);
        io.out("visible", r.visible);
    }
    static void generate(std::mt19937& rng, std::span<float> in) {
        std::size_t p = 0;
        put_view_projection(rng, in, p);
        put(in, p, random_point(rng, 50.0f));
        put_slim_patch(rng, in, p, uniform(rng, 0.05f, 3.0f));
        put(in, p, vec2(1024.0f, 768.0f));
    }
};

/// Per SLIM ball: whether its whole patch faces away from the camera's rays
/// (`slim_patch_culled`); `fixed` is the eye (perspective) or the rays' direction (orthographic).
template <bool Ortho>
struct SlimPatchCullKernel {
    static constexpr const char* name = Ortho ? "slim_patch_cull_ortho" : "slim_patch_cull_perspective";
    static constexpr const char* source = "quadcast::slim_patch_culled (quadcast/slim_blend.hpp)";
    static constexpr const char* summary = "SLIM ball: its patch faces away from every ray (normal cone against the rays' directions)";
    template <class IO> static void run(IO& io) {
        using T = typename IO::T;
        const Vec3<T> center = io.template vec<3>("center");
        const T radius = io.scalar("radius");
        const Vec4<T> axis_rho = io.template vec<4>("axis_rho");
        const Vec4<T> slab_cone = io.template vec<4>("slab_cone");
        const Vec3<T> fixed = io.template vec<3>("fixed");
        io.out("culled", slim_patch_culled<Ortho>(center, radius, axis_rho, slab_cone, fixed));
    }
    static void generate(std::mt19937& rng, std::span<float> in) {
        std::size_t p = 0;
        put(in, p, random_point(rng, 50.0f));
        const float r = uniform(rng, 0.05f, 3.0f);
        put(in, p, r);
        put_slim_patch(rng, in, p, r);
        put(in, p, Ortho ? random_direction(rng) : random_point(rng, 60.0f));
    }
};

}  // namespace quadcast::codegen::kernels
