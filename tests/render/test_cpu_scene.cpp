// tests/render/test_cpu_scene.cpp -- capped cylinders, culling, and the tiled renderer against a per-pixel brute force
#include <doctest/doctest.h>

#include <algorithm>
#include <cstdio>
#include <stdexcept>

#include "render/render_testing.hpp"

using namespace qc_render_test;

namespace {

constexpr LD eps_f = 1.1920928955078125e-07L;  // 2^-23

RenderOptions options(int w, int h, bool culling = true) {
    RenderOptions o;
    o.width = w;
    o.height = h;
    o.culling = culling;
    o.background = vec3(0.1f, 0.2f, 0.3f);
    return o;
}

const Light light{vec3(-0.3f, -0.5f, -1.0f), vec3(1.0f, 0.95f, 0.9f)};

/// Exact coverage of a capped cylinder for every pixel, and whether the exact test is within
/// `tol` (absolute, in world units) of flipping: grown and shrunk cylinders disagree.
struct CylinderCompare {
    int covered = 0, mismatches = 0, boundary = 0, unexplained = 0;
};

/// The radius of a circular cylinder primitive as the renderer sees it: its quadric is
/// s (I - a a^T) x.x - s r^2 (shapes normalise it by some s > 0), so r^2 = -2 Q33 / trace(A).
LD cylinder_radius(const Primitive& p) {
    const LD tr = LD(p.shape.q.q[0][0]) + LD(p.shape.q.q[1][1]) + LD(p.shape.q.q[2][2]);
    return std::sqrt(-2 * LD(p.shape.q.q[3][3]) / tr);
}

CylinderCompare compare_cylinder(const Image& img, const Camera& cam, const Primitive& p, LD tol) {
    CylinderCompare out;
    const ExactCamera ex(cam, img.width, img.height);
    const V3 c = ld(p.shape.center), a = ld(p.shape.axis);
    const LD r = cylinder_radius(p), h = LD(p.shape.half_length);
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x) {
            V3 o, d;
            ex.ray(x, y, o, d);
            auto hit_in_range = [&](LD rr, LD hh) {
                const LD t = cylinder_hit(o, d, c, a, rr, hh);
                if (!(t > 0)) return false;
                const LD depth = exact_depth(cam.projection, ex.view_z(o + d * t));
                return depth >= 0 && depth <= 1;
            };
            const bool exact = hit_in_range(r, h);
            const bool boundary = hit_in_range(r + tol, h + tol) != hit_in_range(r - tol, h - tol);
            out.covered += exact;
            out.boundary += boundary;
            if (exact != covered(img, x, y)) {
                ++out.mismatches;
                out.unexplained += !boundary;
            }
        }
    return out;
}

}  // namespace

TEST_CASE("a capped cylinder seen end-on shows exactly its cap disc") {
    // Perspective, the eye on the axis beyond the +h cap: the covered pixels are those whose
    // exact ray crosses the cap disc (the wall is seen from inside its silhouette only), and
    // every hit is on the cap: normal = +axis exactly. Boundary tolerance 8 eps (|e - c| + radius).
    // (With the eye inside the infinite cylinder, `cull_sphere` of the quadric alone says "cull":
    // per-quadric culling must spare slab primitives, whose caps can face the eye.)
    const int w = 160, h = 120;
    int covered_px = 0, mismatches = 0, boundary = 0;
    std::uint32_t it = 0;
    for (double dist : {0.05, 0.5, 3.0, 40.0, 150.0})
        for (double fov : {25.0, 90.0}) {
            std::mt19937 rng = rng_for(201, it++);
            const Vec3<double> axis = random_dir(rng);
            const Vec3<double> c = vec3(uniform(rng, -3, 3), uniform(rng, -3, 3), uniform(rng, -3, 3));
            const double r = 0.7, hl = 1.3;
            const Primitive p = cylinder(cast<float>(c), cast<float>(axis), float(r), float(hl));
            const Vec3<double> eye = c + axis * (hl + dist);
            const Camera cam = look_at(eye, c, normalize(cross(axis, random_dir(rng))), perspective(fov, double(w) / h, 0.01 * dist, 2 * (dist + 4)));
            const Image img = render_cpu({p}, cam, light, options(w, h), nullptr, 2);
            const CylinderCompare cmp = compare_cylinder(img, cam, p, 8 * eps_f * (norm_ld(ld(cam.eye) - ld(p.shape.center)) + LD(p.shape.radius)));
            CHECK_MESSAGE(cmp.unexplained == 0, "dist=" << dist << " fov=" << fov);
            covered_px += cmp.covered;
            mismatches += cmp.mismatches;
            boundary += cmp.boundary;
            // Every hit is the cap's
            const FrameSetup f = frame_setup(cam, w, h);
            int cap = 0, hits = 0;
            for (int y = 0; y < h; ++y)
                for (int x = 0; x < w; ++x) {
                    const Fragment fr = cast_fragment(p, pixel_ray(f, x, y), f, true);
                    if (!fr.hit) continue;
                    ++hits;
                    cap += fr.normal[0] == p.shape.axis[0] && fr.normal[1] == p.shape.axis[1] && fr.normal[2] == p.shape.axis[2];
                }
            if (cmp.covered > cmp.boundary) CHECK(hits > 0);
            CHECK(cap == hits);
        }
    std::printf("[render] cylinder end-on: %d covered pixels, %d near the boundary, %d mismatches\n", covered_px, boundary, mismatches);
    CHECK(mismatches <= 10);
}

TEST_CASE("a capped cylinder seen from the side is a rectangle (orthographic) and its exact projection (perspective)") {
    const int w = 256, h = 192;
    // Orthographic, one world unit per pixel, the axis along the screen's y: |dx| <= r, |dy| <= h.
    long rect_px = 0, rect_mismatch = 0;
    for (std::uint32_t it = 0; it < 4; ++it) {
        std::mt19937 rng = rng_for(202, it);
        const Vec3<double> dir = random_dir(rng);
        const Vec3<double> u = normalize(cross(dir, random_dir(rng)));
        const Vec3<double> eye = vec3(0.5, 1.0, -2.0) + dir * 400.0;
        const Camera cam = look_at(eye, eye - dir, u, orthographic(-w / 2.0, w / 2.0, -h / 2.0, h / 2.0, 1.0, 1000.0), true);
        const Vec3<double> sx = vec3(double(cam.view[0][0]), double(cam.view[1][0]), double(cam.view[2][0]));
        const Vec3<double> sy = vec3(double(cam.view[0][1]), double(cam.view[1][1]), double(cam.view[2][1]));
        const double cx = uniform(rng, -30, 30), cy = uniform(rng, -20, 20), r = uniform(rng, 5, 40), hl = uniform(rng, 5, 60);
        const Vec3<double> c = cast<double>(cam.eye) - dir * 400.0 + sx * cx + sy * cy;
        const Primitive p = cylinder(cast<float>(c), cast<float>(sy), float(r), float(hl));
        const Image img = render_cpu({p}, cam, light, options(w, h), nullptr, 2);
        const V3 cc = ld(p.shape.center) - ld(cam.eye);
        const LD px = w / 2.0L + dot_ld(cc, ld(sx)), py = h / 2.0L + dot_ld(cc, ld(sy));
        const LD rr = cylinder_radius(p), hh = LD(p.shape.half_length);
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                const LD dx = std::fabs(x + 0.5L - px), dy = std::fabs(y + 0.5L - py);
                const bool exact = dx <= rr && dy <= hh;
                rect_px += exact;
                if (exact != covered(img, x, y)) {
                    ++rect_mismatch;
                    CHECK_MESSAGE(std::min(std::fabs(dx - rr), std::fabs(dy - hh)) < 1e-3L, "(" << x << ", " << y << ")");
                }
            }
    }
    // Perspective from random directions against the exact capped-cylinder test.
    int persp_px = 0, persp_mismatch = 0;
    for (std::uint32_t it = 0; it < 8; ++it) {
        std::mt19937 rng = rng_for(203, it);
        const Vec3<double> axis = random_dir(rng), c = vec3(1.0, 2.0, 3.0);
        const Primitive p = cylinder(cast<float>(c), cast<float>(axis), 0.5f, float(uniform(rng, 0.3, 2.0)));
        const double dist = std::pow(10.0, uniform(rng, 0.4, 2.5));
        const Vec3<double> dir = random_dir(rng);
        const Camera cam = look_at(c + dir * dist, c, normalize(cross(dir, random_dir(rng))),
                                   perspective(uniform(rng, 20, 100), double(w) / h, 0.05, 2 * dist + 10));
        const Image img = render_cpu({p}, cam, light, options(w, h), nullptr, 2);
        const CylinderCompare cmp = compare_cylinder(img, cam, p, 8 * eps_f * LD(dist + double(p.shape.radius)));
        CHECK_MESSAGE(cmp.unexplained == 0, "it=" << it);
        persp_px += cmp.covered;
        persp_mismatch += cmp.mismatches;
    }
    std::printf("[render] cylinder side: orthographic %ld covered pixels, %ld mismatches; perspective %d covered, %d mismatches\n",
                rect_px, rect_mismatch, persp_px, persp_mismatch);
    CHECK(rect_px > 5000);
    CHECK(rect_mismatch <= 2);
    CHECK(persp_mismatch <= 10);
}

namespace {

/// Random closed convex primitives (spheres, ellipsoids, capped cylinders) in [-5, 5]^3.
std::vector<Primitive> convex_scene(std::mt19937& rng, int n) {
    std::vector<Primitive> prims;
    for (int i = 0; i < n; ++i) {
        const Vec3<float> c = vec3(float(uniform(rng, -5, 5)), float(uniform(rng, -5, 5)), float(uniform(rng, -5, 5)));
        const Vec3<float> color = vec3(float(uniform(rng, 0, 1)), float(uniform(rng, 0, 1)), float(uniform(rng, 0, 1)));
        switch (i % 3) {
            case 0: prims.push_back(sphere(c, float(uniform(rng, 0.2, 1.2)), color)); break;
            case 1: {
                const Vec3<double> e0 = random_dir(rng);
                const Vec3<double> e1 = normalize(cross(e0, random_dir(rng)));
                const Vec3<double> e[3] = {e0, e1, cross(e0, e1)};
                prims.push_back(ellipsoid(c, e, vec3(uniform(rng, 0.2, 1.5), uniform(rng, 0.2, 1.5), uniform(rng, 0.2, 1.5)), color));
                break;
            }
            default:
                prims.push_back(cylinder(c, cast<float>(random_dir(rng)), float(uniform(rng, 0.1, 0.6)), float(uniform(rng, 0.2, 2.0)), color));
        }
    }
    return prims;
}

int differing_pixels(const Image& a, const Image& b) {
    int n = 0;
    for (std::size_t i = 0; i < a.depth.size(); ++i)
        n += a.depth[i] != b.depth[i] || !std::equal(&a.rgba[4 * i], &a.rgba[4 * i + 4], &b.rgba[4 * i]);
    return n;
}

}  // namespace

TEST_CASE("culling on and off give the same image for closed convex primitives seen from outside") {
    const int w = 200, h = 150;
    int total_diff = 0;
    long total_cover = 0;
    for (std::uint32_t it = 0; it < 6; ++it) {
        std::mt19937 rng = rng_for(204, it);
        const std::vector<Primitive> prims = convex_scene(rng, 90);
        const Vec3<double> dir = random_dir(rng);
        const bool ortho = it % 2 == 1;
        const Mat4<float> proj = ortho ? orthographic(-8, 8, -6, 6, 1, 60) : perspective(uniform(rng, 30, 80), double(w) / h, 0.5, 60);
        const Camera cam = look_at(dir * 20.0, vec3(0.0, 0.0, 0.0), normalize(cross(dir, random_dir(rng))), proj, ortho);
        FrameStats on_stats, off_stats;
        const Image on = render_cpu(prims, cam, light, options(w, h, true), &on_stats, 2);
        const Image off = render_cpu(prims, cam, light, options(w, h, false), &off_stats, 2);
        CHECK(on_stats.culled == 0);  // every primitive has front faces in its bound
        CHECK(off_stats.culled == 0);
        const int diff = differing_pixels(on, off);
        total_diff += diff;
        for (float d : on.depth) total_cover += d < 1.0f;
        CHECK_MESSAGE(diff <= 3, "it=" << it);
    }
    std::printf("[render] culling on vs off: %ld covered pixels, %d differ\n", total_cover, total_diff);
}

TEST_CASE("per-quadric culling skips a disc seen from its back and keeps it seen from its front") {
    // A plane f = n . x (A = 0, b = n / 2) clipped to a sphere: a disc whose front side faces +n.
    const Vec3<float> n = vec3(0.0f, 0.0f, 1.0f);
    const Primitive disc = bounded(vec3(0.0f, 0.0f, 0.0f),
                                   quadric_from_abc(zero_mat<float, 3, 3>(), n * 0.5f, 0.0f), 1.0f);
    const int w = 64, h = 48;
    auto count = [&](const Image& img) {
        int k = 0;
        for (float d : img.depth) k += d < 1.0f;
        return k;
    };
    const Mat4<float> proj = perspective(60, double(w) / h, 0.1, 20);
    for (double side : {1.0, -1.0}) {
        const Camera cam = look_at(vec3(0.3, -0.2, 4.0 * side), vec3(0.0, 0.0, 0.0), vec3(0.0, 1.0, 0.0), proj);
        FrameStats on_stats, off_stats;
        const Image on = render_cpu({disc}, cam, light, options(w, h, true), &on_stats, 1);
        const Image off = render_cpu({disc}, cam, light, options(w, h, false), &off_stats, 1);
        CHECK(count(off) > 300);
        CHECK(off_stats.culled == 0);
        if (side > 0) {
            CHECK(on_stats.culled == 0);
            CHECK(differing_pixels(on, off) == 0);
        } else {
            CHECK(on_stats.culled == 1);
            CHECK(on_stats.fragments == 0);
            CHECK(count(on) == 0);
        }
    }
}

namespace {

/// Everything at once, including the hard cases of the screen bounds: huge primitives, the eye
/// inside a bounding sphere, spheres straddling the eye plane, behind the eye, beyond the far
/// plane, off screen; general quadrics clipped to their sphere.
std::vector<Primitive> mixed_scene(std::mt19937& rng, const Vec3<double>& eye, int n) {
    std::vector<Primitive> prims = convex_scene(rng, n);
    for (int i = 0; i < n / 4; ++i) {
        // A random quadric through the bound's centre region (hyperboloids, cones, paraboloids ...)
        Mat3<float> A{};
        for (int j = 0; j < 3; ++j)
            for (int k = 0; k <= j; ++k) A[j][k] = A[k][j] = float(uniform(rng, -1, 1));
        const Vec3<float> b = vec3(float(uniform(rng, -0.3, 0.3)), float(uniform(rng, -0.3, 0.3)), float(uniform(rng, -0.3, 0.3)));
        const Vec3<float> c = vec3(float(uniform(rng, -6, 6)), float(uniform(rng, -6, 6)), float(uniform(rng, -6, 6)));
        prims.push_back(bounded(c, quadric_from_abc(A, b, float(uniform(rng, -0.5, 0.5))), float(uniform(rng, 0.5, 2.0))));
    }
    prims.push_back(sphere(cast<float>(eye + vec3(0.3, 0.1, -0.2)), 1.0f));            // contains the eye
    prims.push_back(bounded(cast<float>(eye + vec3(-0.2, 0.3, 0.1)),                    // the eye inside its bound
                            quadric_from_abc(identity<float, 3>(), vec3(0.0f, 0.0f, 0.0f), -4.0f), 1.5f));
    prims.push_back(sphere(cast<float>(eye * 0.5), 25.0f));                              // huge, around the scene
    prims.push_back(sphere(cast<float>(eye * 1.5), 2.0f));                               // behind the eye
    prims.push_back(sphere(cast<float>(eye * -20.0), 3.0f));                             // beyond the far plane
    prims.push_back(sphere(cast<float>(eye * 1.02 + vec3(3.0, 0.0, 0.0)), 1.0f));      // straddling the eye plane
    return prims;
}

/// The renderer's definition, written as a per-pixel loop over every primitive.
Image brute_force(const std::vector<Primitive>& prims, const Camera& cam, const RenderOptions& opt) {
    const FrameSetup f = frame_setup(cam, opt.width, opt.height);
    Image img;
    img.width = opt.width;
    img.height = opt.height;
    img.rgba.resize(std::size_t(opt.width) * opt.height * 4);
    img.depth.resize(std::size_t(opt.width) * opt.height);
    for (int y = 0; y < opt.height; ++y)
        for (int x = 0; x < opt.width; ++x) {
            const PixelRay ray = pixel_ray(f, x, y);
            float best = 1.0f;
            int who = -1;
            Vec3<float> normal{};
            for (std::size_t i = 0; i < prims.size(); ++i) {
                if (opt.culling && culled(prims[i], f)) continue;
                const Fragment fr = cast_fragment(prims[i], ray, f, opt.culling);
                if (fr.hit && fr.depth < best) {
                    best = fr.depth;
                    who = int(i);
                    normal = fr.normal;
                }
            }
            const std::size_t o = std::size_t(opt.height - 1 - y) * opt.width + x;
            img.depth[o] = best;
            if (who >= 0) {
                shade_pixel(prims[who], normal, ray.dir, light, opt, &img.rgba[4 * o]);
            } else {
                for (int k = 0; k < 3; ++k) img.rgba[4 * o + k] = std::uint8_t(std::lround(opt.background[k] * 255.0f));
                img.rgba[4 * o + 3] = 255;
            }
        }
    return img;
}

}  // namespace

TEST_CASE("the tiled multi-threaded renderer equals a per-pixel loop over all primitives") {
    const int w = 150, h = 110;
    for (std::uint32_t it = 0; it < 4; ++it) {
        std::mt19937 rng = rng_for(205, it);
        const bool ortho = it >= 2, culling = it % 2 == 0;
        const Vec3<double> eye = random_dir(rng) * 9.0;
        const Mat4<float> proj = ortho ? orthographic(-9, 9, -6.6, 6.6, -5, 40) : perspective(70, double(w) / h, 0.2, 40);
        const Camera cam = look_at(eye, vec3(0.5, -0.3, 0.2), normalize(cross(eye, random_dir(rng))), proj, ortho);
        const std::vector<Primitive> prims = mixed_scene(rng, eye, 120);
        const RenderOptions opt = options(w, h, culling);
        FrameStats s1, s3;
        const Image one = render_cpu(prims, cam, light, opt, &s1, 1);
        const Image three = render_cpu(prims, cam, light, opt, &s3, 3);
        const Image ref = brute_force(prims, cam, opt);
        int covered_px = 0;
        for (float d : ref.depth) covered_px += d < 1.0f;
        INFO("ortho=" << ortho << " culling=" << culling);
        CHECK(covered_px > 1000);
        CHECK(one.rgba == ref.rgba);
        CHECK(one.depth == ref.depth);
        CHECK(three.rgba == one.rgba);
        CHECK(three.depth == one.depth);
        CHECK(s1.primitives == prims.size());
        CHECK(s1.culled == s3.culled);
        CHECK(s1.fragments == s3.fragments);
        CHECK(s1.hits == s3.hits);
        CHECK(s1.hits <= s1.fragments);
        CHECK(s1.fragments < std::uint64_t(prims.size()) * w * h / 2);
    }
}

TEST_CASE("binning keeps the work proportional to the primitives' screen area") {
    // 2000 small spheres: the casts are a small multiple of the covered pixels, far below
    // primitives x pixels.
    std::mt19937 rng = rng_for(206, 0);
    std::vector<Primitive> prims;
    for (int i = 0; i < 2000; ++i)
        prims.push_back(sphere(vec3(float(uniform(rng, -10, 10)), float(uniform(rng, -10, 10)), float(uniform(rng, -10, 10))), 0.15f));
    const int w = 320, h = 240;
    const Camera cam = look_at(vec3(0.0, 5.0, 35.0), vec3(0.0, 0.0, 0.0), vec3(0.0, 1.0, 0.0), perspective(45, double(w) / h, 1, 100));
    FrameStats st;
    render_cpu(prims, cam, light, options(w, h), &st, 2);
    std::printf("[render] 2000 spheres at 320x240: %llu casts, %llu hits\n", (unsigned long long)st.fragments, (unsigned long long)st.hits);
    CHECK(st.hits > 5000);
    CHECK(st.fragments < 4 * st.hits);
}

TEST_CASE("bad image sizes and singular cameras are rejected") {
    const Camera cam = look_at(vec3(0.0, 0.0, 5.0), vec3(0.0, 0.0, 0.0), vec3(0.0, 1.0, 0.0), perspective(45, 1.0, 1, 10));
    CHECK_THROWS_AS(render_cpu({}, cam, light, options(0, 10)), std::invalid_argument);
    Camera bad = cam;
    bad.projection = zero_mat<float, 4, 4>();
    CHECK_THROWS_AS(render_cpu({}, bad, light, options(10, 10)), std::invalid_argument);
    bad = cam;
    bad.view[0][0] = std::nanf("");
    CHECK_THROWS_AS(render_cpu({}, bad, light, options(10, 10)), std::invalid_argument);
    // An empty scene is the background at depth 1
    const Image img = render_cpu({}, cam, light, options(8, 6));
    CHECK(img.width == 8);
    CHECK(img.height == 6);
    CHECK(std::all_of(img.depth.begin(), img.depth.end(), [](float d) { return d == 1.0f; }));
    CHECK(img.rgba[0] == 26);   // 0.1 * 255 + 0.5 = 26.0
    CHECK(img.rgba[1] == 51);   // 0.2 * 255 = 51.0
    CHECK(img.rgba[2] == 77);   // 0.3 * 255 + 0.5 = 77.0
    CHECK(img.rgba[3] == 255);
}
