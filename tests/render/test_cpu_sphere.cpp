// tests/render/test_cpu_sphere.cpp -- the CPU renderer draws a sphere where, as deep as, and with the normals that exact geometry says
#include <doctest/doctest.h>

#include <algorithm>
#include <cstdio>

#include "render/render_testing.hpp"

using namespace qc_render_test;

namespace {

constexpr LD eps_f = 1.1920928955078125e-07L;  // 2^-23

struct SphereView {
    Camera cam;
    Primitive prim;
    double k;    // eye distance / radius
    double fov;  // vertical, degrees
    bool off_axis;
};

/// A sphere seen from k r with vertical fov, on axis (looking at the centre) or off axis (the
/// centre 0.35 half-fovs off the view axis, in a random direction).
SphereView sphere_view(std::mt19937& rng, double k, double fov, bool off_axis, int w, int h) {
    const Vec3<double> c = vec3(3.7, -1.2, 2.5);
    const double r = 0.8;
    const Vec3<double> dir = random_dir(rng);
    const Vec3<double> eye = c + dir * (k * r);
    Vec3<double> u = normalize(cross(dir, random_dir(rng)));
    const double alpha = off_axis ? 0.35 * fov * M_PI / 360.0 : 0.0;
    const Vec3<double> target = c + u * (k * r * std::tan(alpha));
    const double near = 0.1 * (k - 1) * r, far = 2.0 * (k + 2) * r;
    SphereView v{look_at(eye, target, cross(dir, u), perspective(fov, double(w) / h, near, far)),
                 sphere(cast<float>(c), float(r)), k, fov, off_axis};
    return v;
}

}  // namespace

TEST_CASE("a sphere covers the pixels whose exact rays hit it, from 1.05 r to 1000 r, fov 20-120 degrees") {
    // Exact: the pixel ray (long double, from the float camera) passes within r of the centre
    // and its front hit lies in the depth range [0, 1]. A pixel may disagree only where the
    // exact test is within float rounding of its threshold: |dist - r| <= 8 eps (|e - c| + r),
    // or |depth| / |depth - 1| <= 8 eps.
    const int w = 200, h = 150;
    int configs = 0;
    long total_cover = 0, total_mismatch = 0, total_near_boundary = 0;
    double worst_margin = 0;  // largest |dist - r| / (eps (|e - c| + r)) of a mismatching pixel
    std::uint32_t it = 0;
    for (double k : {1.05, 1.5, 4.0, 30.0, 300.0, 1000.0})
        for (double fov : {20.0, 60.0, 120.0})
            for (bool off : {false, true}) {
                std::mt19937 rng = rng_for(101, it++);
                const SphereView v = sphere_view(rng, k, fov, off, w, h);
                RenderOptions opt;
                opt.width = w;
                opt.height = h;
                FrameStats st;
                const Image img = render_cpu({v.prim}, v.cam, Light{vec3(-0.3f, -0.5f, -1.0f)}, opt, &st, 2);
                const ExactCamera ex(v.cam, w, h);
                const V3 c = ld(v.prim.shape.center);
                const LD r = LD(v.prim.shape.radius);
                const LD scale = norm_ld(ex.eye - c) + r;
                int cover = 0, mismatch = 0, near_boundary = 0;
                for (int y = 0; y < h; ++y)
                    for (int x = 0; x < w; ++x) {
                        V3 o, d;
                        ex.ray(x, y, o, d);
                        const LD t = sphere_hit(o, d, c, r);
                        const LD depth = t > 0 ? exact_depth(v.cam.projection, ex.view_z(o + d * t)) : 2;
                        const bool exact = t > 0 && depth >= 0 && depth <= 1;
                        const LD margin_r = std::fabs(line_distance(o, d, c) - r) / (eps_f * scale);
                        const bool boundary = margin_r <= 8 || std::fabs(depth) <= 8 * eps_f || std::fabs(depth - 1) <= 8 * eps_f;
                        near_boundary += boundary;
                        cover += exact;
                        if (exact != covered(img, x, y)) {
                            ++mismatch;
                            worst_margin = std::max(worst_margin, double(margin_r));
                            CHECK_MESSAGE(boundary, "k=" << k << " fov=" << fov << " off=" << off << " pixel (" << x << ", " << y
                                                         << ") exact=" << exact << " margin=" << double(margin_r));
                        }
                    }
                CHECK(st.primitives == 1);
                CHECK(st.culled == 0);
                CHECK(st.hits <= st.fragments);
                ++configs;
                total_cover += cover;
                total_mismatch += mismatch;
                total_near_boundary += near_boundary;
            }
    std::printf("[render] sphere coverage: %d views, %ld covered pixels, %ld pixels within 8 eps of the threshold, "
                "%ld mismatches (worst margin %.2f eps(|e-c|+r))\n",
                configs, total_cover, total_near_boundary, total_mismatch, worst_margin);
    CHECK(total_cover > 100000);
    CHECK(total_mismatch <= 10);
}

TEST_CASE("sphere depths and normals match the exact hit of the pixel ray") {
    // The reference is the exact (long double) hit of the renderer's own float pixel ray
    // (`pixel_ray`), so this measures the cast, not the ray set-up; the ray itself is checked
    // against the exact pixel ray: angle <= 2 eps (1 + K), K = (|base| + x |dx| + |base + x dx| +
    // y |dy|) / |dir| (the terms of `window_ray` rounded once, its two products and two sums
    // rounded once each). Bounds of the cast, with s = |e - c| + r:
    //   |z - z_exact| <= 4 eps s / cos(theta)   (theta = angle of incidence: near the
    //                                            silhouette the hit slides along the surface)
    //   |depth - depth_exact| <= |d depth / dz| * that + 2 eps
    //   angle(n, n_exact) <= 2 eps s / (r cos(theta))
    // Pixels with cos(theta) < 1e-3 are skipped (grazing rays).
    const int w = 160, h = 120;
    double worst_ray = 0, worst_angle = 0, worst_depth = 0, worst_normal = 0;
    long samples = 0;
    std::uint32_t it = 0;
    for (double k : {1.05, 1.5, 4.0, 30.0, 300.0, 1000.0})
        for (double fov : {20.0, 60.0, 120.0})
            for (bool off : {false, true}) {
                std::mt19937 rng = rng_for(102, it++);
                const SphereView v = sphere_view(rng, k, fov, off, w, h);
                RenderOptions opt;
                opt.width = w;
                opt.height = h;
                const Image img = render_cpu({v.prim}, v.cam, Light{vec3(-0.3f, -0.5f, -1.0f)}, opt, nullptr, 2);
                const FrameSetup f = frame_setup(v.cam, w, h);
                const ExactCamera ex(v.cam, w, h);
                const V3 c = ld(v.prim.shape.center);
                const LD r = LD(v.prim.shape.radius);
                const LD s = norm_ld(ex.eye - c) + r;
                const Mat4<float>& P = v.cam.projection;
                for (int y = 0; y < h; ++y)
                    for (int x = 0; x < w; ++x) {
                        const PixelRay pr = pixel_ray(f, x, y);
                        // The float ray is the exact pixel ray rounded
                        V3 eo, ed;
                        ex.ray(x, y, eo, ed);
                        const V3 d = ld(pr.dir), o = ld(pr.origin);
                        const LD cosang = std::min(1.0L, dot_ld(d, ed) / (norm_ld(d) * norm_ld(ed)));
                        const double ray_angle = double(std::sqrt(2 * (1 - cosang)) / eps_f);
                        const V3 base = ld(f.rays.base), rdx = ld(f.rays.dx) * LD(x + 0.5), rdy = ld(f.rays.dy) * LD(y + 0.5);
                        const V3 moving = f.orthographic ? o : d;
                        const LD k_ray = (norm_ld(base) + norm_ld(rdx) + norm_ld(base + rdx) + norm_ld(rdy)) / norm_ld(moving);
                        worst_ray = std::max(worst_ray, ray_angle / double(1 + k_ray));
                        CHECK(ray_angle <= double(2 * (1 + k_ray)));
                        // The fragment the renderer kept is the cast of this ray
                        const Fragment fr = cast_fragment(v.prim, pr, f, true);
                        if (!fr.hit) {
                            CHECK(!covered(img, x, y));
                            continue;
                        }
                        CHECK(depth_at(img, x, y) == fr.depth);
                        const LD t = sphere_hit(o, d, c, r);
                        if (!(t > 0)) continue;  // a boundary pixel (counted in the coverage test)
                        const V3 xh = o + d * t;
                        const V3 n_exact = (xh - c) / r;
                        const LD cos_theta = -dot_ld(n_exact, d) / norm_ld(d);
                        if (cos_theta < 1e-3L) continue;
                        // Depth, through view z
                        const LD z = ex.view_z(xh);
                        const LD dex = exact_depth(P, z);
                        const LD dz_scale = std::fabs(exact_depth(P, z * (1 + 1e-6L)) - dex) / (1e-6L * std::fabs(z));
                        const LD zb = 4 * eps_f * s / cos_theta;
                        const double e_depth = double(std::fabs(LD(fr.depth) - dex) / (dz_scale * zb + 2 * eps_f));
                        worst_depth = std::max(worst_depth, e_depth);
                        CHECK_MESSAGE(e_depth <= 1.0, "k=" << k << " fov=" << fov << " (" << x << ", " << y << ")");
                        // Normal
                        const V3 n = ld(fr.normal);
                        const LD cn = std::min(1.0L, dot_ld(n, n_exact) / norm_ld(n));
                        const LD ang = std::sqrt(2 * (1 - cn));
                        const double e_normal = double(ang / (2 * eps_f * s / (r * cos_theta)));
                        worst_normal = std::max(worst_normal, e_normal);
                        CHECK_MESSAGE(e_normal <= 1.0, "k=" << k << " fov=" << fov << " (" << x << ", " << y << ")");
                        worst_angle = std::max(worst_angle, double(ang));
                        ++samples;
                    }
            }
    std::printf("[render] sphere hits: %ld samples; pixel ray angle <= %.2f eps (1 + K); depth error <= %.3f of its bound; "
                "normal angle <= %.3f of its bound (max %.2e rad)\n",
                samples, worst_ray, worst_depth, worst_normal, worst_angle);
    CHECK(samples > 50000);
}

TEST_CASE("an orthographic camera draws a sphere as a circle of its radius in pixels") {
    // One world unit per pixel: the sphere (centre at a non-half-integer pixel position) covers
    // exactly the pixel centres within r of its centre.
    const int w = 256, h = 192;
    long mismatches = 0, covered_px = 0;
    for (std::uint32_t it = 0; it < 6; ++it) {
        std::mt19937 rng = rng_for(103, it);
        const double r = uniform(rng, 3.0, 70.0);
        const double cx = uniform(rng, -60, 60), cy = uniform(rng, -40, 40);
        const Vec3<double> dir = random_dir(rng);
        Vec3<double> u = normalize(cross(dir, random_dir(rng)));
        const Vec3<double> vup = cross(dir, u);
        // World centre at screen offset (cx, cy) from the view axis through eye
        const Vec3<double> eye = vec3(1.5, -2.0, 0.25) + dir * 500.0;
        const Camera cam = look_at(eye, eye - dir, vup, orthographic(-w / 2.0, w / 2.0, -h / 2.0, h / 2.0, 1.0, 1000.0), true);
        // Screen axes: x = normalize(cross(up, dir)) = -u ... take them from the float view
        const Vec3<double> sx = vec3(double(cam.view[0][0]), double(cam.view[1][0]), double(cam.view[2][0]));
        const Vec3<double> sy = vec3(double(cam.view[0][1]), double(cam.view[1][1]), double(cam.view[2][1]));
        const Vec3<double> c = cast<double>(cam.eye) - dir * 500.0 + sx * cx + sy * cy;
        const Primitive prim = sphere(cast<float>(c), float(r));
        RenderOptions opt;
        opt.width = w;
        opt.height = h;
        const Image img = render_cpu({prim}, cam, Light{vec3(0.0f, 0.0f, -1.0f)}, opt, nullptr, 2);
        // Centre in pixels, from the float data
        const ExactCamera ex(cam, w, h);
        const V3 cc = ld(prim.shape.center) - ex.eye;
        const LD px = w / 2.0L + dot_ld(cc, ld(sx)), py = h / 2.0L + dot_ld(cc, ld(sy));
        const LD rr = LD(prim.shape.radius);
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                const LD dx = x + 0.5L - px, dy = y + 0.5L - py;
                const LD dist = std::sqrt(dx * dx + dy * dy);
                const bool exact = dist <= rr;
                covered_px += exact;
                if (exact != covered(img, x, y)) {
                    ++mismatches;
                    CHECK_MESSAGE(std::fabs(dist - rr) < 1e-3L, "r=" << r << " (" << x << ", " << y << ") dist-r=" << double(dist - rr));
                }
            }
    }
    std::printf("[render] orthographic circles: %ld covered pixels, %ld mismatches\n", covered_px, mismatches);
    CHECK(mismatches <= 2);
}
