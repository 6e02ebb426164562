// The moving camera of `quadcast render --orbit`: render::orbit_camera against rotations written
// out by hand and against the invariants of an orbit (distance to the target, height along up);
// render::frame_camera against the camera build_frame gives.
#include <doctest/doctest.h>

#include <cmath>
#include <random>

#include "quadcast/scene/scene_render.hpp"

using namespace quadcast;

namespace {

double dist(const Vec3<double>& a, const Vec3<double>& b) { return length(a - b); }

}  // namespace

TEST_CASE("orbit_camera turns the eye about the target around up, right-handed") {
    scene::Camera c;
    c.eye = vec3(0.0, 0.0, 5.0);
    c.target = vec3(0.0, 0.0, 0.0);
    c.up = vec3(0.0, 2.0, 0.0);  // (not unit)
    CHECK(dist(render::orbit_camera(c, 0.0).eye, c.eye) == 0.0);
    CHECK(dist(render::orbit_camera(c, 90.0).eye, vec3(5.0, 0.0, 0.0)) < 1e-12);   // +z to +x about +y
    CHECK(dist(render::orbit_camera(c, 180.0).eye, vec3(0.0, 0.0, -5.0)) < 1e-12);
    CHECK(dist(render::orbit_camera(c, -90.0).eye, vec3(-5.0, 0.0, 0.0)) < 1e-12);
    CHECK(dist(render::orbit_camera(c, 360.0).eye, c.eye) < 1e-12);
    // The bench scene's camera, about (0.5, 0.5, 0.5): the eye stays in the plane y = 0.5
    c.eye = vec3(0.5, 0.5, 3.0);
    c.target = vec3(0.5, 0.5, 0.5);
    c.up = vec3(0.0, 1.0, 0.0);
    const scene::Camera o = render::orbit_camera(c, 30.0);
    CHECK(dist(o.eye, vec3(0.5 + 2.5 * 0.5, 0.5, 0.5 + 2.5 * std::sqrt(3.0) / 2.0)) < 1e-12);
    CHECK(dist(o.target, c.target) == 0.0);
    CHECK(dist(o.up, c.up) == 0.0);

    // Random cameras: distance to the target and height along up kept, the angle about up the one asked for
    std::mt19937 rng(42);
    std::uniform_real_distribution<double> u(-10.0, 10.0), ang(-360.0, 360.0);
    for (int k = 0; k < 1000; ++k) {
        c.eye = vec3(u(rng), u(rng), u(rng));
        c.target = vec3(u(rng), u(rng), u(rng));
        c.up = vec3(u(rng), u(rng), u(rng));
        const double a = ang(rng);
        const scene::Camera r = render::orbit_camera(c, a);
        const Vec3<double> k_up = c.up / length(c.up), v0 = c.eye - c.target, v1 = r.eye - c.target;
        CHECK(std::abs(length(v1) - length(v0)) < 1e-9 * (1.0 + length(v0)));
        CHECK(std::abs(dot(v1, k_up) - dot(v0, k_up)) < 1e-9 * (1.0 + length(v0)));
        // the signed angle between the parts across up
        const Vec3<double> p0 = v0 - k_up * dot(v0, k_up), p1 = v1 - k_up * dot(v1, k_up);
        if (length(p0) < 1e-3) continue;
        const double got = std::atan2(dot(cross(p0, p1), k_up), dot(p0, p1)) * 180.0 / 3.14159265358979323846;
        double want = std::remainder(a, 360.0);
        if (std::abs(std::abs(want) - 180.0) < 1e-6) continue;
        CHECK(std::abs(got - want) < 1e-7);
    }
}

TEST_CASE("frame_camera is the camera build_frame gives") {
    scene::Scene s;
    scene::Sphere a, b;
    a.center = vec3(1.0, 2.0, 3.0);
    a.radius = 0.5;
    b.center = vec3(-4.0, 0.0, 1.0);
    b.radius = 2.0;
    s.spheres = {a, b};
    s.camera.eye = vec3(0.0, 5.0, 20.0);
    s.camera.target = vec3(0.0, 1.0, 2.0);
    const render::Frame fr = render::build_frame(s, 320, 200);
    const render::Camera c = render::frame_camera(s.camera, fr.transform, 320, 200);
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) {
            CHECK(c.view[i][j] == fr.camera.view[i][j]);
            CHECK(c.projection[i][j] == fr.camera.projection[i][j]);
        }
}
