// tests/render/test_tight_bounds.cpp -- tight screen rectangles: the CPU reference draws the same
// image with them as with the bounding-sphere quads, and each rectangle holds every pixel an
// independent long-double ray tracer sees covered
#include <doctest/doctest.h>

#include <cmath>
#include <cstdio>
#include <random>

#include "quadcast/render/cpu_renderer.hpp"
#include "core/exact_tet.hpp"
#include "render/bounds_scenes.hpp"

using namespace qc_render_test;
using namespace qc_bounds_test;

TEST_CASE("tight bounds change no pixel of the CPU reference and cast fewer fragments") {
    const int w = 320, h = 240;
    Light light;
    light.direction = vec3(-0.4f, -0.6f, -1.0f);
    for (const BoundsScene& s : bounds_scenes(w, h))
        for (bool cull : {true, false}) {
            RenderOptions o;
            o.width = w;
            o.height = h;
            o.culling = cull;
            FrameStats tight_stats, sphere_stats;
            o.tight_bounds = true;
            const Image tight = render_cpu(s.prims, s.camera, light, o, &tight_stats);
            o.tight_bounds = false;
            const Image sphere = render_cpu(s.prims, s.camera, light, o, &sphere_stats);
            const ImageDiff d = image_diff(tight, sphere);
            std::printf("[cpu tight bounds] %s, culling %s: %ld covered px, %ld coverage / %ld colour / %ld depth differences; fragments cast %llu -> %llu (%.2fx fewer)\n",
                        s.name.c_str(), cull ? "on" : "off", d.covered, d.coverage_diff, d.color_diff, d.depth_diff,
                        static_cast<unsigned long long>(sphere_stats.fragments), static_cast<unsigned long long>(tight_stats.fragments),
                        double(sphere_stats.fragments) / double(std::max<std::uint64_t>(1, tight_stats.fragments)));
            CAPTURE(s.name);
            CHECK(d.covered > 1000);
            CHECK(d.coverage_diff == 0);
            CHECK(d.color_diff == 0);
            CHECK(d.depth_diff == 0);
            CHECK(tight_stats.fragments <= sphere_stats.fragments);
            CHECK(tight_stats.hits == sphere_stats.hits);
        }
}

namespace {

V3 ldg(const glm::vec3& v) { return vec3(LD(v[0]), LD(v[1]), LD(v[2])); }

/// One primitive with what an independent tracer needs to know of it.
struct Traced {
    Primitive prim;
    int kind;  // 0 sphere, 1 ellipsoid, 2 cylinder, 3 cone, 4 bounding sphere only, 5 sphere in a tetrahedron
    V3 a, b;   // centre / p0 / apex ; p1 / base
    V3 tet[4]; // kind 5: the tetrahedron's corners
    LD r = 0;
    glm::vec3 radii{};
    glm::mat3 rot{1.0f};
    bool cap0 = true, cap1 = true;
};

/// Nearest t > 0 where the ray meets the ellipsoid c + R diag(radii) u, |u| = 1 (or -1).
LD ellipsoid_hit(const V3& o, const V3& d, const Traced& t) {
    V3 ou{}, du{};
    const V3 oc = o - t.a;
    for (int k = 0; k < 3; ++k) {
        const V3 col = vec3(LD(t.rot[k][0]), LD(t.rot[k][1]), LD(t.rot[k][2]));
        ou[k] = dot_ld(oc, col) / LD(t.radii[k]);
        du[k] = dot_ld(d, col) / LD(t.radii[k]);
    }
    return sphere_hit(ou, du, vec3(LD(0), LD(0), LD(0)), 1);
}

/// Nearest t > 0 where the ray meets the sphere (centre a, radius r) inside the tetrahedron.
LD sphere_in_tet_hit(const V3& o, const V3& d, const Traced& t) {
    const V3 oc = o - t.a;
    const LD qa = dot_ld(d, d), qb = dot_ld(oc, d), qc = dot_ld(oc, oc) - t.r * t.r;
    const LD disc = qb * qb - qa * qc;
    if (disc < 0) return -1;
    const LD s = std::sqrt(disc);
    for (const LD th : {(-qb - s) / qa, (-qb + s) / qa})
        if (th > 0 && qc_exact::in_tetrahedron(t.tet, o + d * th)) return th;
    return -1;
}

LD traced_hit(const Traced& t, const V3& o, const V3& d) {
    switch (t.kind) {
    case 5: return sphere_in_tet_hit(o, d, t);
    case 0: return sphere_hit(o, d, t.a, t.r);
    case 1: return ellipsoid_hit(o, d, t);
    case 2: return tube_hit(o, d, t.a, t.b, t.r, t.cap0, t.cap1);
    case 3: return cone_hit(o, d, t.a, t.b, t.r, t.cap1);
    default: return sphere_hit(o, d, ld(t.prim.shape.center), LD(t.prim.shape.radius));
    }
}

Traced random_traced(std::mt19937& rng, int kind) {
    std::uniform_real_distribution<float> u(-1.0f, 1.0f), r(0.02f, 0.6f), ang(0.0f, 6.2831853f);
    Traced t;
    t.kind = kind;
    const glm::vec3 c(u(rng), u(rng), u(rng));
    const glm::vec3 dir = glm::normalize(glm::vec3(u(rng), u(rng), u(rng)) + glm::vec3(1e-3f));
    switch (kind) {
    case 0: {
        const float rr = r(rng);
        t.prim = shapes::sphere(c, rr);
        t.a = ldg(c);
        t.r = rr;
        break;
    }
    case 1: {
        t.radii = glm::vec3(r(rng), r(rng), 0.2f * r(rng));
        t.rot = glm::mat3(glm::rotate(glm::mat4(1.0f), ang(rng), dir));
        t.prim = shapes::ellipsoid(c, t.radii, t.rot);
        t.a = ldg(c);
        break;
    }
    case 2: {
        const float len = 4.0f * r(rng), rr = 0.1f * r(rng) + 0.002f;
        const shapes::Ends ends[4] = {shapes::Ends::both, shapes::Ends::none, shapes::Ends::first, shapes::Ends::second};
        const int e = std::uniform_int_distribution<int>(0, 3)(rng);
        t.prim = shapes::cylinder(c, c + dir * len, rr, ends[e]);
        t.a = ldg(c);
        t.b = ldg(c + dir * len);
        t.r = rr;
        t.cap0 = e == 0 || e == 2;
        t.cap1 = e == 0 || e == 3;
        break;
    }
    case 3: {
        const float len = 3.0f * r(rng), rr = r(rng);
        const bool cap = u(rng) < 0.3f;
        t.prim = shapes::cone(c, c + dir * len, rr, cap);
        t.a = ldg(c);
        t.b = ldg(c + dir * len);
        t.r = rr;
        t.cap1 = cap;
        break;
    }
    case 5: {
        // A sphere through a random tetrahedron (a regular-ish one, a flat one, a needle).
        const float e = 2.0f * r(rng);
        glm::vec3 q[4];
        for (int i = 0; i < 4; ++i) q[i] = c + glm::vec3(u(rng), u(rng), u(rng)) * e;
        const int shape = std::uniform_int_distribution<int>(0, 2)(rng);
        if (shape == 1) q[3] = (q[0] + q[1] + q[2]) / 3.0f + dir * (0.05f * e);
        if (shape == 2) q[1] = q[0] + (q[1] - q[0]) * 0.05f;
        const glm::vec3 inside = (q[0] + q[1] + q[2] + q[3]) * 0.25f;
        const glm::vec3 m = inside + glm::vec3(u(rng), u(rng), u(rng)) * e;
        const float rr = glm::length(inside - m) * (0.8f + 0.4f * (u(rng) + 1.0f) * 0.5f);
        glm::dmat4 qs(0.0);
        qs[0][0] = qs[1][1] = qs[2][2] = 1.0;
        qs[3][0] = qs[0][3] = -double(m.x); qs[3][1] = qs[1][3] = -double(m.y); qs[3][2] = qs[2][3] = -double(m.z);
        qs[3][3] = glm::dot(glm::dvec3(m), glm::dvec3(m)) - double(rr) * double(rr);
        t.prim = shapes::quadric(qs, shapes::TetrahedronBound{{q[0], q[1], q[2], q[3]}});
        t.a = ldg(m);
        t.r = rr;
        for (int i = 0; i < 4; ++i) t.tet[i] = ldg(q[i]);
        break;
    }
    default: {
        // A quad: its rectangle is the bounding sphere's (planar) or its tetrahedron's.
        const float w = r(rng);
        t.prim = shapes::quad(c, c + glm::vec3(w, 0, 0.3f * w), c + glm::vec3(w, w, -0.2f * w), c + glm::vec3(0, w, 0.4f * w));
        break;
    }
    }
    return t;
}

}  // namespace

TEST_CASE("a tight rectangle and a slab's quadrilateral hold every pixel an independent long-double tracer sees covered") {
    // Random primitives of each kind seen by random perspective and orthographic cameras, from
    // afar and (every fourth) from close by, where bounds straddle the eye and near planes; each
    // pixel's exact ray (ExactCamera, long double) against the primitive's exact surface; every
    // pixel with a hit in the depth range must be one `primitive_pixels` draws.
    const int w = 96, h = 72;
    long covered = 0, missed = 0, tight_count = 0, count = 0, area_tight = 0, area_sphere = 0;
    long quad_count = 0, quad_tight_count = 0, missed_quad = 0, area_rect_slab = 0, area_quad_slab = 0;
    long tet_count = 0, tet_tight_count = 0, missed_tet = 0, covered_tet = 0, area_rect_tet = 0, area_quad_tet = 0, area_sphere_tet = 0;
    for (int it = 0; it < 480; ++it) {
        std::mt19937 rng = rng_for(7, static_cast<std::uint32_t>(it));
        const int kind = it % 6;
        const Traced t = random_traced(rng, kind);
        const bool ortho = it % 3 == 2;
        const Vec3<double> dir = random_dir(rng);
        const double dist = it % 4 == 3 ? uniform(rng, 0.05, 1.0) : uniform(rng, 0.8, 8.0);
        const Vec3<double> target = cast<double>(t.prim.shape.center) + random_dir(rng) * uniform(rng, 0.0, 0.5);
        const Vec3<double> eye = target + dir * dist;
        const Mat4<float> proj = ortho ? qc_render_test::orthographic(-1.5, 1.5, -1.1, 1.1, 0.1, 30) : qc_render_test::perspective(uniform(rng, 20, 90), double(w) / h, 0.1, 30);
        const Camera cam = qc_render_test::look_at(eye, target, std::fabs(dir[1]) < 0.9 ? vec3(0.0, 1.0, 0.0) : vec3(1.0, 0.0, 0.0), proj, ortho);
        const FrameSetup f = frame_setup(cam, w, h);
        const PixelRect sphere = primitive_pixels(t.prim, f, false);
        const PixelRect tight = kind == 4 ? sphere : primitive_pixels(t.prim, f, true);
        ++count;
        const ClippedQuadric<float>& s = t.prim.shape;
        const Vec2<float> vp = vec2(float(w), float(h));
        bool is_tight = false;
        switch (rect_bound(t.prim.variant)) {
        case RectBound::sphere: is_tight = primitive_rect<RectBound::sphere>(f.view_projection, s.q, s.center, s.radius, s.axis, s.half_length, vp).tight; break;
        case RectBound::ellipsoid: is_tight = primitive_rect<RectBound::ellipsoid>(f.view_projection, s.q, s.center, s.radius, s.axis, s.half_length, vp).tight; break;
        case RectBound::slab: is_tight = primitive_rect<RectBound::slab>(f.view_projection, s.q, s.center, s.radius, s.axis, s.half_length, vp).tight; break;
        case RectBound::tetrahedron: is_tight = tetra_quad(f.view_projection, s.planes, s.center, vp).tight; break;
        }
        tight_count += is_tight;
        auto area = [](const PixelRect& r) { return r.x0 > r.x1 ? 0L : long(r.x1 - r.x0 + 1) * (r.y1 - r.y0 + 1); };
        area_tight += area(tight);
        area_sphere += area(sphere);
        // The slab kinds' quadrilateral along the projected axis, in window pixels
        bool has_quad = false;
        double qx[4], qy[4];
        // (Quads, kind 4, are traced as their bounding sphere: only the images with tight bounds on
        // and off check their quadrilaterals.)
        const bool tet_bound = kind == 5;
        if (rect_bound(t.prim.variant) == RectBound::slab || tet_bound) {
            const ScreenQuad<float> q = tet_bound ? tetra_quad(f.view_projection, s.planes, s.center, vp)
                                                  : slab_quad(f.view_projection, s.q, s.center, s.axis, s.half_length, vp);
            has_quad = q.tight && q.visible && is_tight;
            (tet_bound ? tet_tight_count : quad_tight_count) += q.tight;
            for (int i = 0; i < 4; ++i) {
                qx[i] = (double(q.corner[i][0]) + 1.0) * 0.5 * w;
                qy[i] = (double(q.corner[i][1]) + 1.0) * 0.5 * h;
            }
        }
        // Whether the pixel centre lies in the convex quadrilateral (counter-clockwise corners)
        auto in_quad = [&](int x, int y) {
            for (int i = 0; i < 4; ++i) {
                const int j = (i + 1) % 4;
                const double cr = (qx[j] - qx[i]) * (y + 0.5 - qy[i]) - (qy[j] - qy[i]) * (x + 0.5 - qx[i]);
                if (cr < 0) return false;
            }
            return true;
        };
        if (has_quad) {
            ++(tet_bound ? tet_count : quad_count);
            long& in_rect = tet_bound ? area_rect_tet : area_rect_slab;
            long& in_q = tet_bound ? area_quad_tet : area_quad_slab;
            for (int y = 0; y < h; ++y)
                for (int x = 0; x < w; ++x)
                    if (x >= tight.x0 && x <= tight.x1 && y >= tight.y0 && y <= tight.y1) {
                        ++in_rect;
                        in_q += in_quad(x, y);
                    }
        }
        if (tet_bound) area_sphere_tet += area(sphere);
        const ExactCamera ec(cam, w, h);
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                V3 o{}, d{};
                ec.ray(x, y, o, d);
                const LD th = traced_hit(t, o, d);
                if (!(th > 0)) continue;
                const LD depth = exact_depth(cam.projection, ec.view_z(o + d * th));
                if (!(depth >= 0 && depth <= 1)) continue;
                ++covered;
                const bool inside = x >= tight.x0 && x <= tight.x1 && y >= tight.y0 && y <= tight.y1;
                if (!inside) {
                    ++missed;
                    if (missed < 10)
                        std::printf("[tight rect] iteration %d kind %d %s: covered pixel (%d, %d) outside [%d, %d] x [%d, %d]\n", it, kind,
                                    ortho ? "ortho" : "perspective", x, y, tight.x0, tight.x1, tight.y0, tight.y1);
                }
                if (tet_bound) ++covered_tet;
                if (has_quad && !in_quad(x, y)) {
                    ++(tet_bound ? missed_tet : missed_quad);
                    if (missed_quad + missed_tet < 10)
                        std::printf("[%s quad] iteration %d kind %d %s: covered pixel (%d, %d) outside the quad\n", tet_bound ? "tetrahedron" : "slab", it, kind,
                                    ortho ? "ortho" : "perspective", x, y);
                }
            }
    }
    std::printf("[tight rect] %ld primitives (%ld tight), %ld covered pixels, %ld outside their rectangle; rectangle area %ld px against %ld px for the bounding-sphere quads' rectangles\n",
                count, tight_count, covered, missed, area_tight, area_sphere);
    std::printf("[slab quad] %ld slab primitives drawn over their quadrilateral (%ld tight), %ld covered pixels outside it; %ld px inside the quadrilaterals against %ld px in the rectangles\n",
                quad_count, quad_tight_count, missed_quad, area_quad_slab, area_rect_slab);
    std::printf("[tetrahedron quad] %ld primitives clipped to a tetrahedron drawn over their quadrilateral (%ld tight), %ld covered pixels, %ld outside it; "
                "%ld px inside the quadrilaterals, %ld px in their rectangles, %ld px in the bounding spheres' rectangles\n",
                tet_count, tet_tight_count, covered_tet, missed_tet, area_quad_tet, area_rect_tet, area_sphere_tet);
    CHECK(tet_count > 30);
    CHECK(covered_tet > 500);
    CHECK(missed_tet == 0);
    CHECK(area_quad_tet < area_rect_tet);
    CHECK(quad_count > 40);
    CHECK(missed_quad == 0);
    CHECK(area_quad_slab < area_rect_slab);
    CHECK(covered > 20000);
    CHECK(tight_count > count / 2);
    CHECK(tight_count < count);  // the close-by cameras need the fallback
    CHECK(missed == 0);
    CHECK(area_tight < area_sphere);
}
