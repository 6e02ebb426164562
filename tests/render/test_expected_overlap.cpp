// The expected overlap the GL renderer decides on whether to run its cull pass
// (render::expected_overlap, quadcast/render/occluder.hpp), against pixel counts of the exact
// shapes: each pixel centre's ray, built here from the camera's eye, basis and field of view (not
// from its matrices), tested in long double against the sphere or the capped cylinder
// (render_testing.hpp's `sphere_hit`, `cylinder_hit`).
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include "quadcast/render/occluder.hpp"
#include "quadcast/shapes.hpp"
#include "render_testing.hpp"

using namespace quadcast;
using namespace quadcast::render;

namespace {

/// A camera given by eye, target, up and a vertical field of view (perspective) or half height
/// (orthographic), with both the renderer's Camera and its own pixel rays.
struct TestView {
    Vec3<double> eye, x, y, z;  // z: towards the eye
    double tan_half = 0.0, half_height = 0.0, aspect = 1.0;
    bool ortho = false;
    int width = 320, height = 240;
    Camera cam;

    TestView(const Vec3<double>& e, const Vec3<double>& target, double fov_or_half_height, bool orthographic, int w = 320, int h = 240)
        : ortho(orthographic), width(w), height(h) {
        eye = cast<double>(cast<float>(e));
        z = normalize(eye - target);
        x = normalize(cross(Vec3<double>{{0.0, 1.0, 0.0}}, z));
        y = cross(z, x);
        aspect = double(w) / h;
        if (ortho) {
            half_height = fov_or_half_height;
            cam = qc_render_test::look_at(e, target, {{0.0, 1.0, 0.0}},
                                          qc_render_test::orthographic(-half_height * aspect, half_height * aspect, -half_height, half_height, 0.1, 100.0), true);
        } else {
            tan_half = std::tan(fov_or_half_height * M_PI / 360.0);
            cam = qc_render_test::look_at(e, target, {{0.0, 1.0, 0.0}}, qc_render_test::perspective(fov_or_half_height, aspect, 0.1, 100.0));
        }
    }

    /// The ray of pixel (i, j) (j = 0 the bottom row), through its centre.
    void ray(int i, int j, Vec3<double>& o, Vec3<double>& d) const {
        const double u = (2.0 * (i + 0.5) / width - 1.0), v = (2.0 * (j + 0.5) / height - 1.0);
        if (ortho) {
            o = eye + x * (u * half_height * aspect) + y * (v * half_height);
            d = -z;
        } else {
            o = eye;
            d = normalize(x * (u * tan_half * aspect) + y * (v * tan_half) - z);
        }
    }

    /// The pixels whose rays `hit` accepts, among those of the box around the projection of the
    /// ball (c, R) holding the shape (the whole image for a ball reaching the eye plane).
    template <class Hit>
    long count(const Hit& hit, const Vec3<double>& c, double R) const {
        int i0 = 0, i1 = width - 1, j0 = 0, j1 = height - 1;
        const Vec3<double> d = c - eye;
        const double vx = dot(d, x), vy = dot(d, y), depth = -dot(d, z);
        if (ortho || depth > 1.01 * R) {
            const double sx = ortho ? half_height * aspect : depth * tan_half * aspect, sy = ortho ? half_height : depth * tan_half;
            const double grow = ortho ? 1.0 : depth / (depth - R);  // (the ball's silhouette lies within R depth / (depth - R) of its centre's ray)
            auto px = [](double ndc, int size) { return (ndc + 1.0) * 0.5 * size; };
            i0 = std::max(i0, int(std::floor(px((vx - R * grow) / sx, width))) - 1);
            i1 = std::min(i1, int(std::ceil(px((vx + R * grow) / sx, width))) + 1);
            j0 = std::max(j0, int(std::floor(px((vy - R * grow) / sy, height))) - 1);
            j1 = std::min(j1, int(std::ceil(px((vy + R * grow) / sy, height))) + 1);
        }
        long n = 0;
        for (int j = j0; j <= j1; ++j)
            for (int i = i0; i <= i1; ++i) {
                Vec3<double> o, d;
                ray(i, j, o, d);
                n += hit(o, d);
            }
        return n;
    }
};

/// Whether the ray o + t d, t > 0, meets the ball (c, r) (`qc_render_test::sphere_hit`, long double).
bool hits_ball(const Vec3<double>& o, const Vec3<double>& d, const Vec3<double>& c, double r) {
    using namespace qc_render_test;
    return sphere_hit(ld(o), ld(d), ld(c), r) > 0;
}

/// Whether the ray meets the solid capped cylinder of radius r around the segment c +- h a (|a| = 1)
/// (`qc_render_test::cylinder_hit`, long double).
bool hits_cylinder(const Vec3<double>& o, const Vec3<double>& d, const Vec3<double>& c, const Vec3<double>& a, double h, double r) {
    using namespace qc_render_test;
    return cylinder_hit(ld(o), ld(d), ld(c), ld(a), r, h) > 0;
}

Vec3<double> vd(const glm::vec3& v) { return {{v.x, v.y, v.z}}; }

}  // namespace

TEST_CASE("capsule_pixels estimates the pixels of a sphere and of a capped cylinder") {
    const TestView views[] = {
        TestView({{0.3, 0.4, 6.0}}, {{0.0, 0.0, 0.0}}, 40.0, false),
        TestView({{2.0, 1.0, 5.0}}, {{0.0, 0.0, 0.0}}, 2.0, true),
    };
    struct Ball { Vec3<double> c; double r; const char* what; };
    const Ball balls[] = {{{{0.0, 0.0, 0.0}}, 0.5, "centred"}, {{{0.6, -0.3, 0.2}}, 0.25, "off centre"}, {{{0.1, 0.2, -3.0}}, 0.8, "far"}};
    for (const TestView& v : views)
        for (const Ball& b : balls) {
            const Primitive p = shapes::sphere({float(b.c[0]), float(b.c[1]), float(b.c[2])}, float(b.r));
            const double est = capsule_pixels(v.cam, v.width, v.height, overlap_capsule(p));
            const long exact = v.count([&](const Vec3<double>& o, const Vec3<double>& d) { return hits_ball(o, d, b.c, b.r); }, b.c, b.r);
            std::printf("[overlap] sphere %s, %s: estimate %.0f px, exact %ld px\n", b.what, v.ortho ? "orthographic" : "perspective", est, exact);
            REQUIRE(exact > 200);
            // Perspective: the ellipse of an off-axis ball is larger than the disk at its depth by
            // up to 1 / cos^3 of its angle off the axis (at most 20 degrees here: 1.21).
            CHECK(est >= 0.8 * double(exact));
            CHECK(est <= 1.1 * double(exact));
        }
    struct Stick { glm::vec3 a, b; float r; const char* what; };
    const Stick sticks[] = {{{-0.8f, 0.0f, 0.0f}, {0.8f, 0.0f, 0.0f}, 0.1f, "side on"},
                            {{-0.5f, -0.4f, -0.6f}, {0.4f, 0.5f, 0.5f}, 0.08f, "oblique"},
                            {{0.0f, 0.0f, -0.6f}, {0.0f, 0.0f, 0.6f}, 0.3f, "nearly end on"}};
    for (const TestView& v : views)
        for (const Stick& s : sticks) {
            const Primitive p = shapes::cylinder(s.a, s.b, s.r, shapes::Ends::both, {{0.5f, 0.5f, 0.5f}});
            const double est = capsule_pixels(v.cam, v.width, v.height, overlap_capsule(p));
            const Vec3<double> a = vd(s.a), b = vd(s.b), c = (a + b) * 0.5, axis = normalize(b - a);
            const double h = 0.5 * length(b - a);
            const long exact = v.count([&](const Vec3<double>& o, const Vec3<double>& d) { return hits_cylinder(o, d, c, axis, h, s.r); }, c, std::hypot(h, double(s.r)));
            std::printf("[overlap] cylinder %s, %s: estimate %.0f px, exact %ld px\n", s.what, v.ortho ? "orthographic" : "perspective", est, exact);
            REQUIRE(exact > 200);
            // The capsule's round ends add pi r^2 to a side-on cylinder's 4 r h (10% for the first
            // stick, h = 8 r); perspective foreshortening across it, as for balls.
            CHECK(est >= 0.75 * double(exact));
            CHECK(est <= 1.3 * double(exact));
        }
}

TEST_CASE("capsule_pixels: off screen, half on screen, behind the eye, around the eye") {
    const TestView v({{0.0, 0.0, 6.0}}, {{0.0, 0.0, 0.0}}, 40.0, false);
    const double tan_half = std::tan(20.0 * M_PI / 180.0), edge_x = 6.0 * tan_half * v.aspect;  // the view's right edge at z = 0
    auto est = [&](const Vec3<double>& c, double r) {
        return capsule_pixels(v.cam, v.width, v.height, overlap_capsule(shapes::sphere({float(c[0]), float(c[1]), float(c[2])}, float(r))));
    };
    auto exact = [&](const Vec3<double>& c, double r) {
        return double(v.count([&](const Vec3<double>& o, const Vec3<double>& d) { return hits_ball(o, d, c, r); }, c, r));
    };
    CHECK(est({{edge_x + 1.0, 0.0, 0.0}}, 0.5) == 0.0);  // beyond the right edge
    CHECK(est({{0.0, 0.0, 9.0}}, 0.5) == 0.0);           // behind the eye
    CHECK(est({{0.0, 0.0, 6.2}}, 0.5) == double(v.width) * v.height);  // the eye inside
    const double half = est({{edge_x, 0.0, 0.0}}, 0.5), half_exact = exact({{edge_x, 0.0, 0.0}}, 0.5);
    std::printf("[overlap] sphere across the right edge: estimate %.0f px, exact %.0f px\n", half, half_exact);
    CHECK(half >= 0.8 * half_exact);
    CHECK(half <= 1.25 * half_exact);
}

TEST_CASE("expected_overlap of random spheres and sticks: the sampled sum against every primitive's exact pixels") {
    const TestView v({{0.5, 0.5, 3.0}}, {{0.5, 0.5, 0.5}}, 30.0, false, 256, 192);
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> u(0.0f, 1.0f), s(-1.0f, 1.0f);
    std::vector<Primitive> prims;
    double exact = 0.0;
    for (int i = 0; i < 6000; ++i) {
        const glm::vec3 c(u(rng), u(rng), u(rng));
        if (i % 2 == 0) {
            const float r = 0.02f;
            prims.push_back(shapes::sphere(c, r));
            exact += double(v.count([&](const Vec3<double>& o, const Vec3<double>& d) { return hits_ball(o, d, vd(c), r); }, vd(c), r));
        } else {
            glm::vec3 d(s(rng), s(rng), s(rng));
            if (glm::length(d) < 0.1f) d = glm::vec3(1.0f, 0.0f, 0.0f);
            d = glm::normalize(d);
            prims.push_back(shapes::cylinder(c - 0.04f * d, c + 0.04f * d, 0.008f, shapes::Ends::both, {{0.5f, 0.5f, 0.5f}}));
            exact += double(v.count([&](const Vec3<double>& o, const Vec3<double>& dir) { return hits_cylinder(o, dir, vd(c), vd(d), 0.04, 0.008); }, vd(c),
                                    std::hypot(0.04, 0.008)));
        }
    }
    const OverlapSample sample = overlap_sample(prims);
    CHECK(sample.capsules.size() == 3000);  // stride 2
    CHECK(sample.weight == doctest::Approx(2.0));
    const OverlapSample all = overlap_sample(prims, prims.size());
    const double pixels = double(v.width) * v.height;
    const double est_all = expected_overlap(all, v.cam, v.width, v.height), est = expected_overlap(sample, v.cam, v.width, v.height);
    std::printf("[overlap] 3000 spheres + 3000 sticks: expected overlap %.3f (sampled every 2nd: %.3f), exact %.3f\n", est_all, est, exact / pixels);
    CHECK(est_all >= 0.9 * exact / pixels);
    CHECK(est_all <= 1.2 * exact / pixels);
    CHECK(est >= 0.85 * exact / pixels);
    CHECK(est <= 1.25 * exact / pixels);
    CHECK(expected_overlap(OverlapSample{}, v.cam, v.width, v.height) == 0.0);
}
