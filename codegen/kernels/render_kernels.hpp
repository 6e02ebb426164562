// codegen/kernels/render_kernels.hpp -- the per-primitive and per-fragment kernels of the quadric renderer
#pragma once

#include <cmath>
#include <string>

#include "kernels/common.hpp"
#include "quadcast/bounds.hpp"
#include "quadcast/occlusion.hpp"
#include "quadcast/raycast.hpp"
#include "quadcast/render/variant_key.hpp"
#include "quadcast/shading.hpp"

namespace quadcast::codegen::kernels {

/// Reads a ClippedQuadric's fields as kernel inputs (the fragment stage reads them from the
/// primitive's record); the slab variants also read the caps, the planes variants the planes.
template <bool Planes = false, bool Slab = false, class IO>
ClippedQuadric<typename IO::T> primitive_inputs(IO& io) {
    using T = typename IO::T;
    ClippedQuadric<T> p{};
    p.q = Quadric<T>{io.template mat<4>("q")};
    p.center = io.template vec<3>("center");
    p.radius = io.scalar("radius");
    p.axis = io.template vec<3>("axis");
    p.half_length = io.scalar("half_length");
    if constexpr (Slab) p.caps = io.template vec<2>("caps");
    if constexpr (Planes)
        for (int i = 0; i < 4; ++i) p.planes[i] = io.template vec<4>("plane" + std::to_string(i));
    return p;
}

inline void put_primitive(std::mt19937& rng, std::span<float> in, std::size_t& p) {
    // A local quadric (centred), its bound and slab.
    Mat4<float> q = random_quadric(rng);
    for (int i = 0; i < 3; ++i) q[3][i] = q[i][3] = q[3][i] * 0.01f;
    put(in, p, q);
    put(in, p, random_point(rng, 50.0f));
    put(in, p, uniform(rng, 0.2f, 3.0f));
    put(in, p, random_direction(rng));
    put(in, p, uniform(rng, 0.1f, 2.0f));
}

/// The caps of a slab primitive: each end closed or open at random.
inline void put_caps(std::mt19937& rng, std::span<float> in, std::size_t& p) {
    put(in, p, vec2(uniform(rng, 0.0f, 1.0f) < 0.7f ? 1.0f : 0.0f, uniform(rng, 0.0f, 1.0f) < 0.7f ? 1.0f : 0.0f));
}

/// Per primitive, in the vertex stage: the bounding quad of the primitive's bounding sphere, in
/// view space (`sphere_quad` for perspective; the square of half-size r around the centre for
/// orthographic cameras).
template <bool Ortho>
struct PrimitiveBoundKernel {
    static constexpr const char* name = Ortho ? "primitive_bound_ortho" : "primitive_bound_perspective";
    static constexpr const char* source = Ortho ? "quadcast::ortho_sphere_square, quadcast::rasterised_sphere_quad (quadcast/bounds.hpp)" : "quadcast::sphere_quad, quadcast::rasterised_sphere_quad (quadcast/bounds.hpp)";
    static constexpr const char* summary = "view-space bounding quad of a primitive's bounding sphere";
    template <class IO> static void run(IO& io) {
        using T = typename IO::T;
        const Mat4<T> view = io.template mat<4>("view");
        const Vec3<T> center = io.template vec<3>("center");
        const T r = io.scalar("radius");
        const Vec3<T> c = xyz(view * vec4(center, T(1)));
        SphereQuad<T> sq{};
        if constexpr (Ortho) sq = ortho_sphere_square(c, r);
        else sq = sphere_quad(c, r);
        sq = rasterised_sphere_quad(sq, c);
        for (int i = 0; i < 4; ++i) io.out("corner" + std::to_string(i), sq.corner[i]);
        io.out("valid", sq.valid);
    }
    static void generate(std::mt19937& rng, std::span<float> in) {
        std::size_t p = 0;
        Mat4<float> v = identity<float, 4>();
        const Mat3<float> r = random_rotation(rng);
        for (int j = 0; j < 3; ++j) v[j] = vec4(r[j], 0.0f);
        v[3] = vec4(random_point(rng, 20.0f), 1.0f);
        put(in, p, v);
        put(in, p, random_point(rng, 30.0f));
        put(in, p, uniform(rng, 0.1f, 3.0f));
    }
};

/// Per vertex of the bounding geometry: its clip-space position (`clip_position`).
struct ClipPositionKernel {
    static constexpr const char* name = "clip_position";
    static constexpr const char* source = "quadcast::clip_position (quadcast/bounds.hpp)";
    static constexpr const char* summary = "clip-space position of a view-space vertex";
    template <class IO> static void run(IO& io) {
        using T = typename IO::T;
        const Mat4<T> projection = io.template mat<4>("projection");
        const Vec3<T> p = io.template vec<3>("p");
        io.out("clip", clip_position(projection, p));
    }
    static void generate(std::mt19937& rng, std::span<float> in) {
        std::size_t p = 0;
        // A perspective or orthographic projection and a point in front of the camera.
        Mat4<float> m = zero_mat<float, 4, 4>();
        const float n = uniform(rng, 0.01f, 1.0f), f = n * uniform(rng, 10.0f, 1e4f);
        m[0][0] = uniform(rng, 0.5f, 3.0f);
        m[1][1] = uniform(rng, 0.5f, 3.0f);
        m[2][0] = uniform(rng, -0.1f, 0.1f);
        m[2][1] = uniform(rng, -0.1f, 0.1f);
        m[2][2] = -(f + n) / (f - n);
        if (uniform(rng, 0.0f, 1.0f) < 0.5f) {
            m[2][3] = -1.0f;
            m[3][2] = -2.0f * f * n / (f - n);
        } else {
            m[3][2] = -(f + n) / (f - n);
            m[3][3] = 1.0f;
        }
        put(in, p, m);
        put(in, p, vec3(uniform(rng, -50.0f, 50.0f), uniform(rng, -50.0f, 50.0f), -uniform(rng, n, f)));
    }
};

/// Per sphere drawn as a point sprite: the sprite's centre and size from the quad's four clip-space
/// corners (`point_sprite`).
struct PointSpriteKernel {
    static constexpr const char* name = "point_sprite";
    static constexpr const char* source = "quadcast::point_sprite (quadcast/bounds.hpp)";
    static constexpr const char* summary = "point sprite (NDC centre, size in pixels) around a quad's four clip-space corners";
    template <class IO> static void run(IO& io) {
        using T = typename IO::T;
        const Vec4<T> c0 = io.template vec<4>("c0"), c1 = io.template vec<4>("c1"), c2 = io.template vec<4>("c2"), c3 = io.template vec<4>("c3");
        const Vec2<T> viewport = io.template vec<2>("viewport");
        Vec2<T> centre{};
        T size{};
        point_sprite(c0, c1, c2, c3, viewport, centre, size);
        io.out("centre", centre);
        io.out("size", size);
    }
    static void generate(std::mt19937& rng, std::span<float> in) {
        std::size_t p = 0;
        // Four corners around a random point, w > 0 (perspective) or 1 (orthographic).
        const bool ortho = uniform(rng, 0.0f, 1.0f) < 0.3f;
        const float cx = uniform(rng, -2.0f, 2.0f), cy = uniform(rng, -2.0f, 2.0f), w = ortho ? 1.0f : uniform(rng, 0.05f, 50.0f), e = uniform(rng, 1e-4f, 0.5f);
        for (int k = 0; k < 4; ++k)
            put(in, p, vec4((cx + uniform(rng, -e, e)) * w, (cy + uniform(rng, -e, e)) * w, uniform(rng, -w, w), ortho ? 1.0f : w * uniform(rng, 0.999f, 1.001f)));
        put(in, p, vec2(std::round(uniform(rng, 16.0f, 4096.0f)), std::round(uniform(rng, 16.0f, 4096.0f))));
    }
};

/// A random camera: a rigid view (world -> view) and a perspective or orthographic projection,
/// combined into view_projection; the eye (perspective) or a point of the camera plane.
inline void put_view_projection(std::mt19937& rng, std::span<float> in, std::size_t& p) {
    Mat4<float> v = identity<float, 4>();
    const Mat3<float> r = random_rotation(rng);
    for (int j = 0; j < 3; ++j) v[j] = vec4(r[j], 0.0f);
    v[3] = vec4(random_point(rng, 60.0f), 1.0f);
    Mat4<float> m = zero_mat<float, 4, 4>();
    const float n = uniform(rng, 0.01f, 1.0f), f = n * uniform(rng, 10.0f, 1e4f);
    m[0][0] = uniform(rng, 0.5f, 3.0f);
    m[1][1] = uniform(rng, 0.5f, 3.0f);
    m[2][0] = uniform(rng, -0.1f, 0.1f);
    m[2][1] = uniform(rng, -0.1f, 0.1f);
    m[2][2] = -(f + n) / (f - n);
    if (uniform(rng, 0.0f, 1.0f) < 0.5f) {
        m[2][3] = -1.0f;
        m[3][2] = -2.0f * f * n / (f - n);
    } else {
        for (int i = 0; i < 2; ++i) m[i][i] *= 0.02f;
        m[3][2] = -(f + n) / (f - n);
        m[3][3] = 1.0f;
    }
    put(in, p, m * v);
}

/// Per vertex of the bounding geometry: the primitive's tight NDC rectangle (`primitive_rect`:
/// the bounding sphere, the ellipsoid, or the hull of the slab sections), and whether it is tight
/// and visible.
template <RectBound Bound>
struct PrimitiveRectKernel {
    static constexpr const char* name = Bound == RectBound::sphere ? "primitive_rect_sphere" : Bound == RectBound::ellipsoid ? "primitive_rect_ellipsoid" : "primitive_rect_slab";
    static constexpr const char* source = "quadcast::primitive_rect, quadcast::dual_rect (quadcast/bounds.hpp)";
    static constexpr const char* summary = "tight NDC rectangle of a primitive (Sigg et al. 2006, eq. 5, dual form)";
    template <class IO> static void run(IO& io) {
        using T = typename IO::T;
        const Mat4<T> vp = io.template mat<4>("view_projection");
        const ClippedQuadric<T> p = primitive_inputs(io);
        const Vec2<T> viewport = io.template vec<2>("viewport");
        const ScreenRect<T> r = primitive_rect<Bound>(vp, p.q, p.center, p.radius, p.axis, p.half_length, viewport);
        io.out("lo", r.lo);
        io.out("hi", r.hi);
        io.out("tight", r.tight);
        io.out("visible", r.visible);
    }
    static void generate(std::mt19937& rng, std::span<float> in) {
        std::size_t p = 0;
        put_view_projection(rng, in, p);
        put_primitive(rng, in, p);
        put(in, p, vec2(1024.0f, 768.0f));
    }
};

/// Per vertex of the bounding geometry of slab-bounded primitives: the padded quadrilateral of the
/// slab sections' hull turned to the projected axis (`slab_quad`), and whether it is tight and
/// visible.
struct PrimitiveQuadSlabKernel {
    static constexpr const char* name = "primitive_quad_slab";
    static constexpr const char* source = "quadcast::slab_quad (quadcast/bounds.hpp)";
    static constexpr const char* summary = "screen quadrilateral of a slab-bounded primitive along its projected axis";
    template <class IO> static void run(IO& io) {
        using T = typename IO::T;
        const Mat4<T> vp = io.template mat<4>("view_projection");
        const ClippedQuadric<T> p = primitive_inputs(io);
        const Vec2<T> viewport = io.template vec<2>("viewport");
        const ScreenQuad<T> r = slab_quad(vp, p.q, p.center, p.axis, p.half_length, viewport);
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
        put_primitive(rng, in, p);
        put(in, p, vec2(1024.0f, 768.0f));
    }
};

/// Per vertex of the bounding geometry of the planes variant: the padded hull of the projected
/// tetrahedron its clip planes bound (`tetra_quad`), and whether it is tight and visible.
struct PrimitiveQuadTetraKernel {
    static constexpr const char* name = "primitive_quad_tetra";
    static constexpr const char* source = "quadcast::tetra_quad (quadcast/bounds.hpp)";
    static constexpr const char* summary = "screen quadrilateral of a primitive clipped to a tetrahedron: its projected hull";
    template <class IO> static void run(IO& io) {
        using T = typename IO::T;
        const Mat4<T> vp = io.template mat<4>("view_projection");
        Vec4<T> planes[4];
        for (int i = 0; i < 4; ++i) planes[i] = io.template vec<4>("plane" + std::to_string(i));
        const Vec3<T> center = io.template vec<3>("center");
        const Vec2<T> viewport = io.template vec<2>("viewport");
        const ScreenQuad<T> r = tetra_quad(vp, planes, center, viewport);
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
        // A tetrahedron around the local origin (some flat, some slivers): its barycentric planes.
        const double size = uniform(rng, 0.05f, 3.0f);
        BoundingTet<double> t{};
        for (int i = 0; i < 4; ++i) t.p[i] = cast<double>(random_point(rng, 1.0f)) * size;
        if (uniform(rng, 0.0f, 1.0f) < 0.2f) t.p[3] = (t.p[0] + t.p[1] + t.p[2]) / 3.0 + cast<double>(random_point(rng, 1.0f)) * (size * 0.01);
        const TetPlanes<double> pl = barycentric_planes(t);
        for (int i = 0; i < 4; ++i) put(in, p, cast<float>(pl.plane[i]));
        put(in, p, random_point(rng, 50.0f));
        put(in, p, vec2(1024.0f, 768.0f));
    }
};

/// Per primitive (perspective cameras): back-face culling against the bounding sphere (Stoll et
/// al. 2006, sec. 4.4.4; `cull_primitive`, and `cull_primitive_with_caps` for capped slabs) for
/// the eye's local position o = eye - center (`local_ray`'s o).
struct PrimitiveCullKernel {
    static constexpr const char* name = "primitive_cull";
    static constexpr const char* source = "quadcast::local_ray, quadcast::cull_primitive, quadcast::cull_primitive_with_caps (quadcast/raycast.hpp)";
    static constexpr const char* summary = "per-quadric back-face culling against the bounding sphere";
    template <class IO> static void run(IO& io) {
        using T = typename IO::T;
        const ClippedQuadric<T> p = primitive_inputs(io);
        const Vec3<T> eye = io.template vec<3>("eye");
        const LocalRay<T> r = local_ray(p, eye, vec3(T(0), T(0), T(-1)));
        io.out("culled", cull_primitive(p, r.o));
        io.out("culled_caps", cull_primitive_with_caps(p, r.o));
    }
    static void generate(std::mt19937& rng, std::span<float> in) {
        std::size_t p = 0;
        put_primitive(rng, in, p);
        put(in, p, random_point(rng, 60.0f));
    }
};

/// Per fragment: the world-space ray through the pixel centre (`window_ray`), from the frame's
/// affine terms; the same ray whatever geometry the primitive is drawn over.
template <bool Ortho>
struct FragmentRayKernel {
    static constexpr const char* name = Ortho ? "fragment_ray_ortho" : "fragment_ray_perspective";
    static constexpr const char* source = "quadcast::window_ray (quadcast/raycast.hpp)";
    static constexpr const char* summary = "the world ray of a pixel centre, affine in the window position";
    template <class IO> static void run(IO& io) {
        using T = typename IO::T;
        const Vec3<T> base = io.template vec<3>("base"), dx = io.template vec<3>("dx"), dy = io.template vec<3>("dy");
        const Vec3<T> fixed = io.template vec<3>("fixed");
        const Vec2<T> frag = io.template vec<2>("frag");
        const WorldRay<T> r = window_ray<Ortho>(base, dx, dy, fixed, frag);
        io.out("origin", r.origin);
        io.out("dir", r.dir);
    }
    static void generate(std::mt19937& rng, std::span<float> in) {
        std::size_t p = 0;
        put(in, p, random_point(rng, 2.0f));
        put(in, p, random_point(rng, 2.0f) * 0.001f);
        put(in, p, random_point(rng, 2.0f) * 0.001f);
        put(in, p, random_point(rng, 60.0f));
        put(in, p, vec2(std::floor(uniform(rng, 0.0f, 1024.0f)) + 0.5f, std::floor(uniform(rng, 0.0f, 768.0f)) + 0.5f));
    }
};

/// The outputs of every fragment-stage kernel.
template <class IO>
void output_fragment(IO& io, const FragmentHit<typename IO::T>& f) {
    io.out("hit", f.hit);
    io.out("depth", f.depth);
    io.out("normal", f.normal);
}

/// Per fragment: the local ray of the pixel's world ray (`local_ray`), its cast (`cast`), window
/// depth (`window_depth`) and normal. A hit must lie between the near and far planes (depth in [0, 1]).
/// The ray comes from `fragment_ray_*` (or `pixel_ray` in the brute-force benchmark stage).
template <CastOptions Opt>
struct FragmentCastKernel {
    static constexpr const char* name = render::fragment_kernel_name(Opt);
    static constexpr const char* source = "quadcast::local_ray, quadcast::cast_and_depth (quadcast/raycast.hpp)";
    static constexpr const char* summary = "ray casting: a fragment's local ray, hit, depth and normal (Stoll et al. 2006, sec. 4-5)";
    template <class IO> static void run(IO& io) {
        using T = typename IO::T;
        const ClippedQuadric<T> p = primitive_inputs<Opt.planes, Opt.slab>(io);
        const Vec3<T> origin = io.template vec<3>("origin");
        const Vec3<T> dir = io.template vec<3>("dir");
        const Vec3<T> vz_row = io.template vec<3>("vz_row");
        const Vec4<T> pz = io.template vec<4>("pz");
        output_fragment(io, cast_and_depth<Opt>(p, local_ray(p, origin, dir), vz_row, pz));
    }
    static void generate(std::mt19937& rng, std::span<float> in) {
        std::size_t p = 0;
        put_primitive(rng, in, p);
        if constexpr (Opt.slab) put_caps(rng, in, p);
        if constexpr (Opt.planes)
            for (int i = 0; i < 4; ++i) put(in, p, vec4(random_direction(rng), uniform(rng, 0.0f, 2.0f)));
        const Vec3<float> o = random_point(rng, 50.0f) + random_direction(rng) * uniform(rng, 1.0f, 100.0f);
        put(in, p, o);
        put(in, p, normalize(random_point(rng, 50.0f) - o));
        put(in, p, random_direction(rng));
        put(in, p, vec4(-1.002f, -0.2002f, -1.0f, 0.0f));
    }
};

/// Per fragment of a sphere (the sphere-specialised stage): `cast_and_depth` with
/// CastOptions::sphere, the closed form of `ray_quadratic_sphere`, of the local ray o = origin -
/// center, v = dir (`local_ray`'s o and v); reads only the radius and the centre.
template <bool Cull>
struct FragmentSphereKernel {
    static constexpr const char* name = render::fragment_kernel_name(render::FragmentShape::sphere, Cull);
    static constexpr const char* source = "quadcast::cast_and_depth with CastOptions::sphere (quadcast/raycast.hpp)";
    static constexpr const char* summary = "incremental ray casting of a sphere in closed form: a fragment's hit, depth and normal";
    template <class IO> static void run(IO& io) {
        using T = typename IO::T;
        ClippedQuadric<T> p{};
        p.radius = io.scalar("radius");
        p.center = io.template vec<3>("center");
        const Vec3<T> origin = io.template vec<3>("origin");
        const LocalRay<T> r{origin - p.center, io.template vec<3>("dir"), Vec3<T>{}, Vec3<T>{}};
        const Vec3<T> vz_row = io.template vec<3>("vz_row");
        const Vec4<T> pz = io.template vec<4>("pz");
        output_fragment(io, cast_and_depth<CastOptions{Cull, false, false, false, true}>(p, r, vz_row, pz));
    }
    static void generate(std::mt19937& rng, std::span<float> in) {
        std::size_t p = 0;
        const float radius = uniform(rng, 0.001f, 3.0f);
        put(in, p, radius);
        // Eyes outside, near and inside the sphere; rays around it.
        const float k = uniform(rng, 0.0f, 1.0f);
        const float d = k < 0.1f ? radius * uniform(rng, 0.0f, 1.0f) : k < 0.2f ? radius * uniform(rng, 0.999f, 1.001f) : uniform(rng, radius, 1000.0f);
        const Vec3<float> o = random_direction(rng) * d;
        const Vec3<float> center = random_point(rng, 50.0f);
        put(in, p, center);
        put(in, p, center + o);
        put(in, p, (random_point(rng, 1.2f * radius) - o) * uniform(rng, 0.01f, 10.0f));
        put(in, p, random_direction(rng));
        put(in, p, vec4(-1.002f, -0.2002f, -1.0f, 0.0f));
    }
};

/// Shading: Blinn-Phong with one directional light (`shade_blinn_phong`).
struct ShadeKernel {
    static constexpr const char* name = "shade_blinn_phong";
    static constexpr const char* source = "quadcast::shade_blinn_phong (quadcast/raycast.hpp)";
    static constexpr const char* summary = "Blinn-Phong shading, Schlick's rational specular lobe";
    template <class IO> static void run(IO& io) {
        using T = typename IO::T;
        const Vec3<T> n = io.template vec<3>("n"), l = io.template vec<3>("l"), e = io.template vec<3>("e");
        const Vec3<T> color = io.template vec<3>("color"), light = io.template vec<3>("light");
        const Vec4<T> material = io.template vec<4>("material");
        io.out("rgb", shade_blinn_phong(n, l, e, color, light, material));
    }
    static void generate(std::mt19937& rng, std::span<float> in) {
        std::size_t p = 0;
        put(in, p, random_direction(rng));
        put(in, p, random_direction(rng));
        put(in, p, random_direction(rng));
        put(in, p, vec3(uniform(rng, 0.0f, 1.0f), uniform(rng, 0.0f, 1.0f), uniform(rng, 0.0f, 1.0f)));
        put(in, p, vec3(1.0f, 1.0f, 1.0f));
        put(in, p, vec4(0.15f, 0.85f, 0.35f, uniform(rng, 1.0f, 128.0f)));
    }
};


/// Deferred pass: silhouette and crease outlines from a 3x3 neighbourhood of the geometry buffer
/// (`silhouette_weight`), blended over the shaded colour (`apply_outline`).
struct SilhouetteKernel {
    static constexpr const char* name = "silhouette";
    static constexpr const char* source = "quadcast::silhouette_weight, quadcast::apply_outline (quadcast/shading.hpp)";
    static constexpr const char* summary = "Sobel silhouettes (linearised depth) and creases (normals), outline blend";
    template <class IO> static void run(IO& io) {
        using T = typename IO::T;
        T d[9];
        Vec3<T> n[9];
        for (int i = 0; i < 9; ++i) d[i] = io.scalar("d" + std::to_string(i));
        for (int i = 0; i < 9; ++i) n[i] = io.template vec<3>("n" + std::to_string(i));
        const Vec4<T> pz = io.template vec<4>("pz");
        const Vec4<T> params = io.template vec<4>("params");
        const Vec3<T> rgb = io.template vec<3>("rgb");
        io.out("shaded", apply_outline(rgb, silhouette_weight(d, n, pz, params), params[2]));
    }
    static void generate(std::mt19937& rng, std::span<float> in) {
        std::size_t p = 0;
        const float base = uniform(rng, 0.9f, 0.999f);
        for (int i = 0; i < 9; ++i) put(in, p, uniform(rng, 0.0f, 1.0f) < 0.15f ? 1.0f : base + uniform(rng, -0.01f, 0.0f));
        for (int i = 0; i < 9; ++i) put(in, p, uniform(rng, 0.0f, 1.0f) < 0.1f ? vec3(0.0f, 0.0f, 0.0f) : random_direction(rng) * uniform(rng, 0.1f, 3.0f));
        put(in, p, vec4(-1.002f, -0.2002f, -1.0f, 0.0f));
        put(in, p, vec4(0.04f, 0.6f, uniform(rng, 0.0f, 1.0f), 0.0f));
        put(in, p, vec3(uniform(rng, 0.0f, 1.0f), uniform(rng, 0.0f, 1.0f), uniform(rng, 0.0f, 1.0f)));
    }
};


/// Soft shadows: the lit fraction of the first 8 PCF samples and whether they agree, from their
/// count (`pcf_first8_from_count`).
struct PcfFirst8FromCountKernel {
    static constexpr const char* name = "pcf_first8_from_count";
    static constexpr const char* source = "quadcast::pcf_first8_from_count (quadcast/shading.hpp)";
    static constexpr const char* summary = "percentage-closer filtering, 8-sample penumbra test from the count of lit samples (Sigg et al. 2006, sec. 4)";
    template <class IO> static void run(IO& io) {
        using T = typename IO::T;
        const PcfFirst<T> f = pcf_first8_from_count(io.scalar("count8"));
        io.out("lit", f.lit);
        io.out("decided", f.decided);
    }
    static void generate(std::mt19937& rng, std::span<float> in) {
        std::size_t p = 0;
        put(in, p, std::floor(uniform(rng, 0.0f, 8.999f)));
    }
};

/// Soft shadows: one sample's step of the PCF count (`pcf_count_step`).
struct PcfCountStepKernel {
    static constexpr const char* name = "pcf_count_step";
    static constexpr const char* source = "quadcast::pcf_count_step (quadcast/shading.hpp)";
    static constexpr const char* summary = "percentage-closer filtering: the count of lit samples after one more sample (Sigg et al. 2006, sec. 4)";
    template <class IO> static void run(IO& io) {
        using T = typename IO::T;
        const T count = io.scalar("count"), z = io.scalar("z"), bias = io.scalar("bias"), s = io.scalar("s");
        io.out("next", pcf_count_step(count, z, bias, s));
    }
    static void generate(std::mt19937& rng, std::span<float> in) {
        std::size_t p = 0;
        const float z = uniform(rng, 0.0f, 1.0f);
        put(in, p, std::floor(uniform(rng, 0.0f, 55.999f)));
        put(in, p, z);
        put(in, p, uniform(rng, 0.0f, 0.01f));
        put(in, p, z + uniform(rng, -0.02f, 0.02f));
    }
};

/// Soft shadows: the 64-sample lit fraction from the first 8 samples' fraction and the count of
/// the other 56 (`pcf_fraction64`).
struct PcfFraction64Kernel {
    static constexpr const char* name = "pcf_fraction64";
    static constexpr const char* source = "quadcast::pcf_fraction64 (quadcast/shading.hpp)";
    static constexpr const char* summary = "percentage-closer filtering with 64 samples: the lit fraction from the first 8 and the count of the rest (Sigg et al. 2006, sec. 4)";
    template <class IO> static void run(IO& io) {
        using T = typename IO::T;
        const T lit8 = io.scalar("lit8"), count56 = io.scalar("count56");
        io.out("lit", pcf_fraction64(lit8, count56));
    }
    static void generate(std::mt19937& rng, std::span<float> in) {
        std::size_t p = 0;
        put(in, p, std::floor(uniform(rng, 0.0f, 8.999f)) / 8.0f);
        put(in, p, std::floor(uniform(rng, 0.0f, 56.999f)));
    }
};

/// Soft shadows: the shadow-map texel of one PCF sample (`pcf_sample_texel`).
struct PcfSampleTexelKernel {
    static constexpr const char* name = "pcf_sample_texel";
    static constexpr const char* source = "quadcast::pcf_sample_texel (quadcast/shading.hpp)";
    static constexpr const char* summary = "percentage-closer filtering: the clamped texel of grid cell g around the shadow-map position";
    template <class IO> static void run(IO& io) {
        using T = typename IO::T;
        const Vec2<T> texel = io.template vec<2>("texel");
        const T g = io.scalar("g"), step = io.scalar("step"), last = io.scalar("last");
        io.out("index", pcf_sample_texel(texel, g, step, last));
    }
    static void generate(std::mt19937& rng, std::span<float> in) {
        std::size_t p = 0;
        // Positions inside the map, near and beyond its borders.
        put(in, p, vec2(uniform(rng, -40.0f, 1064.0f), uniform(rng, -40.0f, 1064.0f)));
        put(in, p, std::floor(uniform(rng, 0.0f, 63.999f)));
        put(in, p, std::floor(uniform(rng, 1.0f, 8.999f)));
        put(in, p, 1023.0f);
    }
};

/// Soft shadows: the map texel that a texel of the shadow map in phases holds (`phase_source_texel`).
struct PhaseSourceTexelKernel {
    static constexpr const char* name = "phase_source_texel";
    static constexpr const char* source = "quadcast::phase_source_texel (quadcast/shading.hpp)";
    static constexpr const char* summary = "percentage-closer filtering: the shadow-map texel held by a texel of the map in phases of the sample step";
    template <class IO> static void run(IO& io) {
        using T = typename IO::T;
        const T x = io.scalar("x"), step = io.scalar("step"), tile = io.scalar("tile"), inv_tile = io.scalar("inv_tile"), last = io.scalar("last");
        io.out("texel", phase_source_texel(x, step, tile, inv_tile, last));
    }
    static void generate(std::mt19937& rng, std::span<float> in) {
        std::size_t p = 0;
        const float step = std::floor(uniform(rng, 1.0f, 64.999f)), map = std::floor(uniform(rng, 64.0f, 8192.0f));
        const float tile = float(pcf_phase_tile(int(map), int(step)));
        put(in, p, std::floor(uniform(rng, 0.0f, step * tile - 0.001f)));
        put(in, p, step);
        put(in, p, tile);
        put(in, p, 1.0f / tile);
        put(in, p, map - 1.0f);
    }
};

/// Soft shadows: where a receiver's PCF samples lie in the shadow map in phases (`pcf_phase`).
struct PcfPhaseKernel {
    static constexpr const char* name = "pcf_phase";
    static constexpr const char* source = "quadcast::pcf_phase (quadcast/shading.hpp)";
    static constexpr const char* summary = "percentage-closer filtering: the first sample's texel in the shadow map in phases";
    template <class IO> static void run(IO& io) {
        using T = typename IO::T;
        const Vec2<T> texel = io.template vec<2>("texel");
        const T step = io.scalar("step"), inv_step = io.scalar("inv_step"), last = io.scalar("last"), tile = io.scalar("tile");
        io.out("cell", pcf_phase(texel, step, inv_step, last, tile));
    }
    static void generate(std::mt19937& rng, std::span<float> in) {
        std::size_t p = 0;
        const float step = std::floor(uniform(rng, 1.0f, 8.999f));
        // positions inside the map, near and beyond its borders
        put(in, p, vec2(uniform(rng, -80.0f, 1104.0f), uniform(rng, -80.0f, 1104.0f)));
        put(in, p, step);
        put(in, p, 1.0f / step);
        put(in, p, 1023.0f);
        put(in, p, float(pcf_phase_tile(1024, int(step))));
    }
};

/// Soft shadows: where textureGather reads four PCF samples of a phase layer (`pcf_gather_coord`).
struct PcfGatherCoordKernel {
    static constexpr const char* name = "pcf_gather_coord";
    static constexpr const char* source = "quadcast::pcf_gather_coord (quadcast/shading.hpp)";
    static constexpr const char* summary = "percentage-closer filtering: the normalised corner of a 2 x 2 block of samples in a phase layer";
    template <class IO> static void run(IO& io) {
        using T = typename IO::T;
        const Vec2<T> cell = io.template vec<2>("cell");
        const T gx = io.scalar("gx"), gy = io.scalar("gy"), inv_size = io.scalar("inv_size");
        io.out("uv", pcf_gather_coord(cell, gx, gy, inv_size));
    }
    static void generate(std::mt19937& rng, std::span<float> in) {
        std::size_t p = 0;
        const float size = std::floor(uniform(rng, 16.0f, 8192.0f));
        put(in, p, vec2(std::floor(uniform(rng, 0.0f, size - 8.0f)), std::floor(uniform(rng, 0.0f, size - 8.0f))));
        put(in, p, 2.0f * std::floor(uniform(rng, 0.0f, 3.999f)));
        put(in, p, 2.0f * std::floor(uniform(rng, 0.0f, 3.999f)));
        put(in, p, 1.0f / size);
    }
};

/// Soft shadows: the 64-sample lit fraction from the count of all 64 (`pcf_fraction_of64`).
struct PcfFractionOf64Kernel {
    static constexpr const char* name = "pcf_fraction_of64";
    static constexpr const char* source = "quadcast::pcf_fraction_of64 (quadcast/shading.hpp)";
    static constexpr const char* summary = "percentage-closer filtering with 64 samples: the lit fraction from the count of all 64";
    template <class IO> static void run(IO& io) {
        io.out("lit", pcf_fraction_of64(io.scalar("count64")));
    }
    static void generate(std::mt19937& rng, std::span<float> in) {
        std::size_t p = 0;
        put(in, p, std::floor(uniform(rng, 0.0f, 64.999f)));
    }
};

/// Silhouettes: one texel of the 3x3 neighbourhood, clamped to the image (`neighbour_texel`).
struct NeighbourTexelKernel {
    static constexpr const char* name = "neighbour_texel";
    static constexpr const char* source = "quadcast::neighbour_texel (quadcast/shading.hpp)";
    static constexpr const char* summary = "the clamped texel at an offset from a pixel (silhouette neighbourhood)";
    template <class IO> static void run(IO& io) {
        using T = typename IO::T;
        const Vec2<T> frag = io.template vec<2>("frag");
        const T dx = io.scalar("dx"), dy = io.scalar("dy");
        const Vec2<T> last = io.template vec<2>("last");
        io.out("index", neighbour_texel(frag, dx, dy, last));
    }
    static void generate(std::mt19937& rng, std::span<float> in) {
        std::size_t p = 0;
        // Pixel centres, a third of them on the border rows and columns.
        float x = std::floor(uniform(rng, 0.0f, 1023.999f)), y = std::floor(uniform(rng, 0.0f, 767.999f));
        if (uniform(rng, 0.0f, 1.0f) < 0.33f) x = uniform(rng, 0.0f, 1.0f) < 0.5f ? 0.0f : 1023.0f;
        if (uniform(rng, 0.0f, 1.0f) < 0.33f) y = uniform(rng, 0.0f, 1.0f) < 0.5f ? 0.0f : 767.0f;
        put(in, p, vec2(x + 0.5f, y + 0.5f));
        put(in, p, std::floor(uniform(rng, -1.0f, 1.999f)));
        put(in, p, std::floor(uniform(rng, -1.0f, 1.999f)));
        put(in, p, vec2(1023.0f, 767.0f));
    }
};

/// NDC rectangles around the viewport, some of them outside it, for the pixel-span kernels.
inline void pixel_span_inputs(std::mt19937& rng, std::span<float> in) {
    std::size_t p = 0;
    const Vec2<float> a = vec2(uniform(rng, -1.5f, 1.5f), uniform(rng, -1.5f, 1.5f));
    put(in, p, a);
    put(in, p, a + vec2(uniform(rng, 0.0f, 0.5f), uniform(rng, 0.0f, 0.5f)));
    put(in, p, vec2(1024.0f, 768.0f));
}

/// Occlusion culling, per occluder: its view distance (`view_distance`) and whether its disk
/// may be written (`occluder_usable`).
struct OccluderDepthKernel {
    static constexpr const char* name = "occluder_depth";
    static constexpr const char* source = "quadcast::view_distance, quadcast::occluder_usable, quadcast::nearest_distance, quadcast::window_depth_of (quadcast/occlusion.hpp)";
    static constexpr const char* summary = "an occluder's view distance and whether it lies between the near and far planes";
    template <class IO> static void run(IO& io) {
        using T = typename IO::T;
        const Vec3<T> vz_row = io.template vec<3>("vz_row");
        const T vz_t = io.scalar("vz_t");
        const Vec3<T> c = io.template vec<3>("c");
        const T r_in = io.scalar("r_in"), radius = io.scalar("radius"), near = io.scalar("near"), far = io.scalar("far"), gap = io.scalar("gap");
        const Vec4<T> pz = io.template vec<4>("pz");
        const T s = view_distance(vz_row, vz_t, c);
        io.out("s", s);
        io.out("usable", occluder_usable(s, r_in, radius, c, vz_t, near, far, gap, pz));
    }
    static void generate(std::mt19937& rng, std::span<float> in) {
        std::size_t p = 0;
        put(in, p, random_direction(rng));
        put(in, p, uniform(rng, -60.0f, 60.0f));
        put(in, p, random_point(rng, 60.0f));
        const float r = uniform(rng, 0.0f, 5.0f);
        put(in, p, r);
        put(in, p, r * uniform(rng, 1.0f, 1.2f));
        const float n = uniform(rng, 0.01f, 10.0f), f = n * uniform(rng, 2.0f, 1e3f);
        put(in, p, n);
        put(in, p, f);
        put(in, p, uniform(rng, 0.01f, 0.3f));
        put(in, p, vec4(-(f + n) / (f - n), -2.0f * f * n / (f - n), -1.0f, 0.0f));
    }
};

/// Occlusion culling from a depth buffer: a view distance no nearer than the surface it holds at
/// a window depth (`distance_of_window_depth`).
struct DepthDistanceKernel {
    static constexpr const char* name = "depth_distance";
    static constexpr const char* source = "quadcast::distance_of_window_depth (quadcast/occlusion.hpp)";
    static constexpr const char* summary = "a view distance no nearer than what a depth buffer holds at a window depth";
    template <class IO> static void run(IO& io) {
        using T = typename IO::T;
        const T w = io.scalar("w");
        const Vec4<T> pz = io.template vec<4>("pz");
        mask_t<T> far;
        const T s = distance_of_window_depth(w, pz, far);
        io.out("s", s);
        io.out("far", far);
    }
    static void generate(std::mt19937& rng, std::span<float> in) {
        std::size_t p = 0;
        put(in, p, uniform(rng, 0.0f, 1.0f));
        const float n = uniform(rng, 0.01f, 10.0f), f = n * uniform(rng, 2.0f, 1e3f);
        if (uniform(rng, 0.0f, 1.0f) < 0.25f)
            put(in, p, vec4(-2.0f / (f - n), -(f + n) / (f - n), 0.0f, 1.0f));  // orthographic
        else
            put(in, p, vec4(-(f + n) / (f - n), -2.0f * f * n / (f - n), -1.0f, 0.0f));
    }
};

/// Occlusion culling, per primitive: the nearest view distance of its bounding sphere
/// (`view_distance`, `nearest_distance`).
struct NearestDistanceKernel {
    static constexpr const char* name = "nearest_distance";
    static constexpr const char* source = "quadcast::view_distance, quadcast::nearest_distance (quadcast/occlusion.hpp)";
    static constexpr const char* summary = "the nearest view distance of a primitive's bounding sphere";
    template <class IO> static void run(IO& io) {
        using T = typename IO::T;
        const Vec3<T> vz_row = io.template vec<3>("vz_row");
        const T vz_t = io.scalar("vz_t");
        const Vec3<T> c = io.template vec<3>("c");
        const T radius = io.scalar("radius");
        io.out("s", nearest_distance(view_distance(vz_row, vz_t, c), radius));
    }
    static void generate(std::mt19937& rng, std::span<float> in) {
        std::size_t p = 0;
        put(in, p, random_direction(rng));
        put(in, p, uniform(rng, -60.0f, 60.0f));
        put(in, p, random_point(rng, 60.0f));
        put(in, p, uniform(rng, 0.0f, 5.0f));
    }
};

/// Occlusion culling, per occluder: the NDC ellipse its central disk projects to (`occluder_ellipse`).
struct OccluderEllipseKernel {
    static constexpr const char* name = "occluder_ellipse";
    static constexpr const char* source = "quadcast::occluder_ellipse (quadcast/occlusion.hpp)";
    static constexpr const char* summary = "the NDC ellipse an occluder's disk perpendicular to the viewing axis projects to";
    template <class IO> static void run(IO& io) {
        using T = typename IO::T;
        const Mat4<T> vp = io.template mat<4>("view_projection");
        const Vec3<T> c = io.template vec<3>("c"), right = io.template vec<3>("right"), up = io.template vec<3>("up");
        const T r_in = io.scalar("r_in");
        Vec2<T> centre{}, axes{}, lo{}, hi{};
        occluder_ellipse(vp, c, right, up, r_in, centre, axes, lo, hi);
        io.out("centre", centre);
        io.out("axes", axes);
        io.out("lo", lo);
        io.out("hi", hi);
    }
    static void generate(std::mt19937& rng, std::span<float> in) {
        std::size_t p = 0;
        put_view_projection(rng, in, p);
        put(in, p, random_point(rng, 60.0f));
        const Mat3<float> r = random_rotation(rng);
        put(in, p, r[0]);
        put(in, p, r[1]);
        put(in, p, uniform(rng, 0.01f, 3.0f));
    }
};

/// Occlusion culling, per occluder chain (capped cylinders): its number of disks
/// (`occluder_chain_count`).
struct OccluderChainCountKernel {
    static constexpr const char* name = "occluder_chain_count";
    static constexpr const char* source = "quadcast::occluder_chain_count (quadcast/occlusion.hpp)";
    static constexpr const char* summary = "the number of disks of an occluder chain along a cylinder";
    template <class IO> static void run(IO& io) {
        using T = typename IO::T;
        const Vec3<T> half_axis = io.template vec<3>("half_axis");
        const T r_in = io.scalar("r_in");
        io.out("n", occluder_chain_count(half_axis, r_in));
    }
    static void generate(std::mt19937& rng, std::span<float> in) {
        std::size_t p = 0;
        const float r = uniform(rng, 0.001f, 2.0f);
        put(in, p, random_direction(rng) * (r * uniform(rng, 0.0f, 40.0f)));
        put(in, p, r);
    }
};

/// Occlusion culling, per disk of an occluder chain: its centre and the radius of a ball around
/// it holding the primitive (`occluder_chain_disk`).
struct OccluderChainDiskKernel {
    static constexpr const char* name = "occluder_chain_disk";
    static constexpr const char* source = "quadcast::occluder_chain_disk (quadcast/occlusion.hpp)";
    static constexpr const char* summary = "one disk of an occluder chain along a cylinder";
    template <class IO> static void run(IO& io) {
        using T = typename IO::T;
        const Vec3<T> c = io.template vec<3>("c"), half_axis = io.template vec<3>("half_axis");
        const T radius = io.scalar("radius"), k = io.scalar("k"), n = io.scalar("n");
        Vec3<T> ck{};
        T radius_k{};
        occluder_chain_disk(c, half_axis, radius, k, n, ck, radius_k);
        io.out("ck", ck);
        io.out("radius_k", radius_k);
    }
    static void generate(std::mt19937& rng, std::span<float> in) {
        std::size_t p = 0;
        put(in, p, random_point(rng, 60.0f));
        put(in, p, random_direction(rng) * uniform(rng, 0.0f, 3.0f));
        put(in, p, uniform(rng, 0.01f, 4.0f));
        const float n = std::floor(uniform(rng, 1.0f, 65.0f));
        put(in, p, std::floor(uniform(rng, 0.0f, n)));
        put(in, p, n);
    }
};

/// Occlusion culling by the rasteriser, per vertex of an occluder quadrilateral: its clip
/// position and whether the record occludes (`occluder_corner`).
struct OccluderCornerKernel {
    static constexpr const char* name = "occluder_corner";
    static constexpr const char* source = "quadcast::occluder_corner (quadcast/occlusion.hpp)";
    static constexpr const char* summary = "a corner of the quadrilateral an occluder draws into the depth buffer, and whether it is usable";
    template <class IO> static void run(IO& io) {
        using T = typename IO::T;
        const Mat4<T> vp = io.template mat<4>("view_projection");
        const Vec3<T> vz_row = io.template vec<3>("vz_row");
        const T vz_t = io.scalar("vz_t");
        const Vec3<T> right = io.template vec<3>("right"), up = io.template vec<3>("up");
        const Vec4<T> ball = io.template vec<4>("ball"), more = io.template vec<4>("more");
        const Vec3<T> range = io.template vec<3>("range");
        const Vec4<T> pz = io.template vec<4>("pz");
        const T p11 = io.scalar("p11"), height = io.scalar("height"), k = io.scalar("k");
        Vec4<T> clip{};
        mask_t<T> usable{};
        occluder_corner(vp, vz_row, vz_t, right, up, ball, more, range, pz, p11, height, k, clip, usable);
        io.out("clip", clip);
        io.out("usable", usable);
    }
    static void generate(std::mt19937& rng, std::span<float> in) {
        std::size_t p = 0;
        put_view_projection(rng, in, p);
        const Mat3<float> r = random_rotation(rng);
        put(in, p, r[2]);
        put(in, p, uniform(rng, -60.0f, 60.0f));
        put(in, p, r[0]);
        put(in, p, r[1]);
        const float r_in = uniform(rng, 0.0f, 3.0f);
        put(in, p, vec4(random_point(rng, 60.0f), r_in));
        const float h = uniform(rng, 0.0f, 1.0f) < 0.3f ? 0.0f : r_in * uniform(rng, 0.0f, 20.0f);
        const Vec3<float> ha = random_direction(rng) * h;
        put(in, p, vec4(r_in * uniform(rng, 1.0f, 1.2f) + h, ha[0], ha[1], ha[2]));
        const float n = uniform(rng, 0.01f, 10.0f), f = n * uniform(rng, 2.0f, 1e3f);
        put(in, p, vec3(n, f, uniform(rng, 0.01f, 0.3f)));
        put(in, p, vec4(-(f + n) / (f - n), -2.0f * f * n / (f - n), -1.0f, 0.0f));
        put(in, p, uniform(rng, 0.5f, 3.0f));
        put(in, p, 768.0f);
        put(in, p, std::floor(uniform(rng, 0.0f, 4.0f)));
    }
};

/// Occlusion culling, per pixel of an occluder: whether its centre falls in the occluder's
/// ellipse (`ellipse_covers`).
struct EllipseCoversKernel {
    static constexpr const char* name = "ellipse_covers";
    static constexpr const char* source = "quadcast::ellipse_covers (quadcast/occlusion.hpp)";
    static constexpr const char* summary = "whether a pixel centre falls in an NDC ellipse";
    template <class IO> static void run(IO& io) {
        using T = typename IO::T;
        const Vec2<T> frag = io.template vec<2>("frag"), viewport = io.template vec<2>("viewport");
        const Vec2<T> centre = io.template vec<2>("centre"), axes = io.template vec<2>("axes");
        io.out("covered", ellipse_covers(frag, viewport, centre, axes));
    }
    static void generate(std::mt19937& rng, std::span<float> in) {
        std::size_t p = 0;
        const Vec2<float> frag = vec2(std::floor(uniform(rng, 0.0f, 1023.999f)) + 0.5f, std::floor(uniform(rng, 0.0f, 767.999f)) + 0.5f);
        const Vec2<float> axes = vec2(uniform(rng, 0.002f, 0.2f), uniform(rng, 0.002f, 0.2f));
        const Vec2<float> ndc = vec2(frag[0] / 512.0f - 1.0f, frag[1] / 384.0f - 1.0f);
        put(in, p, frag);
        put(in, p, vec2(1024.0f, 768.0f));
        put(in, p, ndc + vec2(axes[0] * uniform(rng, -1.3f, 1.3f), axes[1] * uniform(rng, -1.3f, 1.3f)));
        put(in, p, axes);
    }
};

/// Occlusion culling: the pixels an NDC rectangle can reach, clamped to the viewport (`pixel_span`).
struct PixelSpanKernel {
    static constexpr const char* name = "pixel_span";
    static constexpr const char* source = "quadcast::pixel_span (quadcast/occlusion.hpp)";
    static constexpr const char* summary = "the pixels whose centres an NDC rectangle can hold";
    template <class IO> static void run(IO& io) {
        using T = typename IO::T;
        const Vec2<T> lo = io.template vec<2>("lo"), hi = io.template vec<2>("hi"), viewport = io.template vec<2>("viewport");
        io.out("span", pixel_span(lo, hi, viewport));
    }
    static void generate(std::mt19937& rng, std::span<float> in) { pixel_span_inputs(rng, in); }
};

/// Occlusion culling: the texels of the level below that a pyramid texel takes the largest of
/// (`pyramid_children`).
struct PyramidChildrenKernel {
    static constexpr const char* name = "pyramid_children";
    static constexpr const char* source = "quadcast::pyramid_children (quadcast/occlusion.hpp)";
    static constexpr const char* summary = "the (up to) 2 x 2 texels below a texel of the max-depth pyramid, clamped";
    template <class IO> static void run(IO& io) {
        using T = typename IO::T;
        const Vec2<T> t = io.template vec<2>("t"), below = io.template vec<2>("below");
        io.out("children", pyramid_children(t, below));
    }
    static void generate(std::mt19937& rng, std::span<float> in) {
        std::size_t p = 0;
        // Levels up to 8192 wide, odd and even; texels anywhere in them, a third on the last.
        const Vec2<float> below = vec2(std::floor(uniform(rng, 1.0f, 8192.999f)), std::floor(uniform(rng, 1.0f, 8192.999f)));
        Vec2<float> t{};
        for (int k = 0; k < 2; ++k) {
            const float size = std::ceil(below[k] * 0.5f);
            t[k] = uniform(rng, 0.0f, 1.0f) < 0.33f ? size - 1.0f : std::floor(uniform(rng, 0.0f, size - 0.001f));
        }
        put(in, p, t);
        put(in, p, below);
    }
};

/// Outline tiles: whether a texel of the normal target holds the cleared value (`is_cleared_gnormal`).
struct ClearedGnormalKernel {
    static constexpr const char* name = "is_cleared_gnormal";
    static constexpr const char* source = "quadcast::is_cleared_gnormal (quadcast/shading.hpp)";
    static constexpr const char* summary = "whether a geometry-buffer normal texel is the cleared (0, 0, 0, 1)";
    template <class IO> static void run(IO& io) {
        io.out("cleared", is_cleared_gnormal(io.template vec<4>("g")));
    }
    static void generate(std::mt19937& rng, std::span<float> in) {
        std::size_t p = 0;
        // Each component 0, -0, 1, or a normal's or depth's value, so that all 16 patterns occur.
        Vec4<float> g{};
        for (int k = 0; k < 4; ++k) {
            const float r = uniform(rng, 0.0f, 1.0f);
            g[k] = r < 0.3f ? (k == 3 ? 1.0f : 0.0f) : r < 0.4f ? -0.0f : r < 0.5f ? 1.0f : uniform(rng, -1.0f, 1.0f);
        }
        put(in, p, g);
    }
};

/// Outline tiles: the pixels whose texels a tile's outlines read (`outline_tile_reach`).
struct OutlineTileReachKernel {
    static constexpr const char* name = "outline_tile_reach";
    static constexpr const char* source = "quadcast::outline_tile_reach (quadcast/shading.hpp)";
    static constexpr const char* summary = "an 8 x 8 outline tile grown by one pixel, clamped to the viewport";
    template <class IO> static void run(IO& io) {
        using T = typename IO::T;
        const Vec2<T> tile = io.template vec<2>("tile"), viewport = io.template vec<2>("viewport");
        io.out("reach", outline_tile_reach(tile, viewport));
    }
    static void generate(std::mt19937& rng, std::span<float> in) {
        std::size_t p = 0;
        const Vec2<float> viewport = vec2(std::floor(uniform(rng, 1.0f, 4096.999f)), std::floor(uniform(rng, 1.0f, 4096.999f)));
        put(in, p, vec2(std::floor(uniform(rng, 0.0f, std::ceil(viewport[0] / 8.0f) - 0.001f)), std::floor(uniform(rng, 0.0f, std::ceil(viewport[1] / 8.0f) - 0.001f))));
        put(in, p, viewport);
    }
};

/// Outline tiles: the centre of a tile's 8-pixel point (`outline_tile_centre`).
struct OutlineTileCentreKernel {
    static constexpr const char* name = "outline_tile_centre";
    static constexpr const char* source = "quadcast::outline_tile_centre (quadcast/shading.hpp)";
    static constexpr const char* summary = "the window position of an outline tile's 8-pixel point, kept in the view";
    template <class IO> static void run(IO& io) {
        using T = typename IO::T;
        const Vec2<T> tile = io.template vec<2>("tile"), viewport = io.template vec<2>("viewport");
        io.out("centre", outline_tile_centre(tile, viewport));
    }
    static void generate(std::mt19937& rng, std::span<float> in) { OutlineTileReachKernel::generate(rng, in); }
};

/// Soft shadows: a pixel's shadow-map texel position and light depth (`shadow_coord`).
struct ShadowCoordKernel {
    static constexpr const char* name = "shadow_coord";
    static constexpr const char* source = "quadcast::shadow_coord (quadcast/shading.hpp)";
    static constexpr const char* summary = "camera window position -> shadow-map texel and light depth";
    template <class IO> static void run(IO& io) {
        using T = typename IO::T;
        const Vec2<T> frag = io.template vec<2>("frag");
        const T d = io.scalar("depth");
        const Vec2<T> viewport = io.template vec<2>("viewport");
        const Mat4<T> m = io.template mat<4>("to_light");
        const T size = io.scalar("size");
        const ShadowCoord<T> c = shadow_coord(frag, d, viewport, m, size);
        io.out("texel", c.texel);
        io.out("z", c.z);
    }
    static void generate(std::mt19937& rng, std::span<float> in) {
        std::size_t p = 0;
        put(in, p, vec2(std::floor(uniform(rng, 0.0f, 1024.0f)) + 0.5f, std::floor(uniform(rng, 0.0f, 768.0f)) + 0.5f));
        put(in, p, uniform(rng, 0.0f, 1.0f));
        put(in, p, vec2(1024.0f, 768.0f));
        Mat4<float> m{};
        for (int j = 0; j < 4; ++j) m[j] = vec4(random_point(rng, 2.0f), uniform(rng, -1.0f, 1.0f));
        m[3][3] = uniform(rng, 0.5f, 2.0f);
        put(in, p, m);
        put(in, p, 1024.0f);
    }
};

/// Soft shadows: Blinn-Phong with diffuse and specular attenuated by the PCF visibility.
struct ShadeShadowedKernel {
    static constexpr const char* name = "shade_blinn_phong_shadowed";
    static constexpr const char* source = "quadcast::shade_blinn_phong_shadowed (quadcast/shading.hpp)";
    static constexpr const char* summary = "Blinn-Phong shading in partial shadow";
    template <class IO> static void run(IO& io) {
        using T = typename IO::T;
        const Vec3<T> n = io.template vec<3>("n"), l = io.template vec<3>("l"), e = io.template vec<3>("e");
        const Vec3<T> color = io.template vec<3>("color"), light = io.template vec<3>("light");
        const Vec4<T> material = io.template vec<4>("material");
        const T vis = io.scalar("vis");
        io.out("rgb", shade_blinn_phong_shadowed(n, l, e, color, light, material, vis));
    }
    static void generate(std::mt19937& rng, std::span<float> in) {
        ShadeKernel::generate(rng, in);
        in[19] = std::floor(uniform(rng, 0.0f, 65.0f)) / 64.0f;
    }
};

/// Brute-force fragment stage (benchmark baseline for incremental ray casting): the pixel's world
/// ray from its window position (`pixel_ray`).
struct PixelRayKernel {
    static constexpr const char* name = "pixel_ray";
    static constexpr const char* source = "quadcast::pixel_ray (quadcast/raycast.hpp)";
    static constexpr const char* summary = "brute-force ray casting: a pixel's world ray via the inverse view-projection";
    template <class IO> static void run(IO& io) {
        using T = typename IO::T;
        const Mat4<T> m = io.template mat<4>("inv_view_proj");
        const Vec3<T> eye = io.template vec<3>("eye");
        const Vec2<T> frag = io.template vec<2>("frag");
        const Vec2<T> viewport = io.template vec<2>("viewport");
        const WorldRay<T> r = pixel_ray(m, eye, frag, viewport);
        io.out("origin", r.origin);
        io.out("dir", r.dir);
    }
    static void generate(std::mt19937& rng, std::span<float> in) {
        std::size_t p = 0;
        Mat4<float> m{};
        for (int j = 0; j < 4; ++j) m[j] = vec4(random_point(rng, 2.0f), uniform(rng, -0.5f, 0.5f));
        m[3][3] = uniform(rng, 1.0f, 2.0f);
        put(in, p, m);
        put(in, p, random_point(rng, 10.0f));
        put(in, p, vec2(std::floor(uniform(rng, 0.0f, 1024.0f)) + 0.5f, std::floor(uniform(rng, 0.0f, 768.0f)) + 0.5f));
        put(in, p, vec2(1024.0f, 768.0f));
    }
};

/// Environment reflection: the mirror direction of the view ray about the normal (`reflect_view`).
struct ReflectViewKernel {
    static constexpr const char* name = "reflect_view";
    static constexpr const char* source = "quadcast::reflect_view (quadcast/shading.hpp)";
    static constexpr const char* summary = "environment reflection: mirror direction of the view ray";
    template <class IO> static void run(IO& io) {
        using T = typename IO::T;
        const Vec3<T> n = io.template vec<3>("n"), e = io.template vec<3>("e");
        io.out("r", reflect_view(n, e));
    }
    static void generate(std::mt19937& rng, std::span<float> in) {
        std::size_t p = 0;
        put(in, p, random_direction(rng) * uniform(rng, 0.01f, 10.0f));
        put(in, p, random_direction(rng) * uniform(rng, 0.01f, 100.0f));
    }
};

/// Environment reflection: the lookup position of the reflected view ray in a latitude-longitude
/// image (`reflect_view`, `latlong_texel`).
struct EnvironmentTexelKernel {
    static constexpr const char* name = "environment_texel";
    static constexpr const char* source = "quadcast::reflect_view, quadcast::latlong_texel (quadcast/shading.hpp)";
    static constexpr const char* summary = "environment reflection: latitude-longitude texel position of the reflected ray";
    template <class IO> static void run(IO& io) {
        using T = typename IO::T;
        const Vec3<T> n = io.template vec<3>("n"), e = io.template vec<3>("e");
        const Vec2<T> size = io.template vec<2>("size");
        io.out("texel", latlong_texel(reflect_view(n, e), size));
    }
    static void generate(std::mt19937& rng, std::span<float> in) {
        std::size_t p = 0;
        Vec3<float> n = random_direction(rng) * uniform(rng, 0.01f, 10.0f);
        // Adversarial: normals in the coordinate planes and along the axes (atan2 octant edges).
        if (uniform(rng, 0.0f, 1.0f) < 0.2f) n[static_cast<int>(uniform(rng, 0.0f, 2.999f))] = 0.0f;
        put(in, p, n);
        put(in, p, random_direction(rng) * uniform(rng, 0.01f, 100.0f));
        put(in, p, vec2(1024.0f, 512.0f));
    }
};

/// Environment reflection: the four texels around the lookup position (`latlong_texels`).
struct EnvironmentTexelsKernel {
    static constexpr const char* name = "environment_texels";
    static constexpr const char* source = "quadcast::latlong_texels (quadcast/shading.hpp)";
    static constexpr const char* summary = "environment reflection: base texel and the wrapped columns, clamped rows around the position";
    template <class IO> static void run(IO& io) {
        using T = typename IO::T;
        const Vec2<T> texel = io.template vec<2>("texel"), size = io.template vec<2>("size");
        const LatlongTexels<T> l = latlong_texels(texel, size);
        io.out("base", l.base);
        io.out("index", l.index);
    }
    static void generate(std::mt19937& rng, std::span<float> in) {
        std::size_t p = 0;
        // The range latlong_texel gives (-0.5 .. size - 0.5), and the seams.
        Vec2<float> t = vec2(uniform(rng, -0.5f, 1023.5f), uniform(rng, -0.5f, 511.5f));
        if (uniform(rng, 0.0f, 1.0f) < 0.2f) t[0] = uniform(rng, 0.0f, 1.0f) < 0.5f ? uniform(rng, -0.5f, 0.5f) : uniform(rng, 1022.5f, 1023.5f);
        put(in, p, t);
        put(in, p, vec2(1024.0f, 512.0f));
    }
};

/// Environment reflection: bilinear interpolation of the four fetched texels mixed into the
/// shaded colour by the reflectivity (`environment_mix`).
struct EnvironmentMixKernel {
    static constexpr const char* name = "environment_mix";
    static constexpr const char* source = "quadcast::environment_mix (quadcast/shading.hpp)";
    static constexpr const char* summary = "environment reflection: bilinear texel blend mixed into the Phong colour";
    template <class IO> static void run(IO& io) {
        using T = typename IO::T;
        const Vec3<T> rgb = io.template vec<3>("rgb");
        const Vec2<T> texel = io.template vec<2>("texel"), base = io.template vec<2>("base");
        const Vec3<T> c00 = io.template vec<3>("c00"), c10 = io.template vec<3>("c10");
        const Vec3<T> c01 = io.template vec<3>("c01"), c11 = io.template vec<3>("c11");
        const T k = io.scalar("reflectivity");
        io.out("mixed", environment_mix(rgb, texel, base, c00, c10, c01, c11, k));
    }
    static void generate(std::mt19937& rng, std::span<float> in) {
        std::size_t p = 0;
        auto colour = [&] { return vec3(uniform(rng, 0.0f, 1.0f), uniform(rng, 0.0f, 1.0f), uniform(rng, 0.0f, 1.0f)); };
        put(in, p, colour());
        const Vec2<float> t = vec2(uniform(rng, -0.5f, 1023.5f), uniform(rng, -0.5f, 511.5f));
        put(in, p, t);
        put(in, p, vec2(std::floor(t[0]), std::floor(t[1])));
        for (int i = 0; i < 4; ++i) put(in, p, colour());
        put(in, p, uniform(rng, 0.0f, 1.0f));
    }
};

}  // namespace quadcast::codegen::kernels
