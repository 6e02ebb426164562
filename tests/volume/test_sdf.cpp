// tests/volume/test_sdf.cpp -- signed distance volumes: exact point-triangle distance, box meshes against the analytic SDF
#include <doctest/doctest.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <fstream>
#include <random>

#include "helpers.hpp"
#include "quadcast/volume/sdf.hpp"

using namespace quadcast::volume;

namespace {

double dot(const Vec3d& a, const Vec3d& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
Vec3d cross(const Vec3d& a, const Vec3d& b) {
    return Vec3d{{a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]}};
}

/// Reference distance by a different route: the plane if the foot point is inside, else the
/// nearest edge (long double).
double reference_distance(const Vec3d& p, const Vec3d& a, const Vec3d& b, const Vec3d& c) {
    auto seg = [&](const Vec3d& u, const Vec3d& v) {
        long double best = 1e300L;
        const Vec3d d = v - u;
        const long double l2 = dot(d, d);
        long double t = l2 > 0 ? dot(p - u, d) / l2 : 0;
        t = std::clamp(t, 0.0L, 1.0L);
        long double s = 0;
        for (int k = 0; k < 3; ++k) {
            const long double x = p[k] - (u[k] + t * d[k]);
            s += x * x;
        }
        return std::min(best, std::sqrt(s));
    };
    const long double edges = std::min({seg(a, b), seg(b, c), seg(c, a)});
    const Vec3d n = cross(b - a, c - a);
    const double nn = dot(n, n);
    if (nn <= 1e-12 * dot(b - a, b - a) * dot(c - a, c - a)) return static_cast<double>(edges);
    const double dist = dot(p - a, n) / std::sqrt(nn);
    const Vec3d foot = p - n * (dot(p - a, n) / nn);
    const double w0 = dot(cross(b - foot, c - foot), n), w1 = dot(cross(c - foot, a - foot), n), w2 = dot(cross(a - foot, b - foot), n);
    if (w0 >= 0 && w1 >= 0 && w2 >= 0) return std::abs(dist);
    return static_cast<double>(edges);
}

/// Signed distance to the axis-aligned box [-s, s]^3 (negative inside).
double box_sdf(const Vec3d& p, double s) {
    double outside = 0.0, inside = -1e300;
    for (int a = 0; a < 3; ++a) {
        const double q = std::abs(p[a]) - s;
        outside += q > 0 ? q * q : 0.0;
        inside = std::max(inside, q);
    }
    return inside > 0 ? std::sqrt(outside) : inside;
}

/// The cube [-1,1]^3 as 12 triangles (diagonals through the face centres) or 6 quads in OFF.
TriangleMesh cube_mesh(const double (&rot)[3][3], const Vec3d& shift) {
    TriangleMesh m;
    m.source = "cube";
    for (int v = 0; v < 8; ++v) {
        const Vec3d p{{(v & 4) ? 1.0 : -1.0, (v & 2) ? 1.0 : -1.0, (v & 1) ? 1.0 : -1.0}};
        Vec3d q{};
        for (int i = 0; i < 3; ++i) q[i] = rot[i][0] * p[0] + rot[i][1] * p[1] + rot[i][2] * p[2] + shift[i];
        m.vertices.push_back(q);
    }
    const int quads[6][4] = {{0, 1, 3, 2}, {4, 6, 7, 5}, {0, 4, 5, 1}, {2, 3, 7, 6}, {0, 2, 6, 4}, {1, 5, 7, 3}};
    for (const auto& q : quads) {
        m.triangles.push_back({q[0], q[1], q[2]});
        m.triangles.push_back({q[0], q[2], q[3]});
    }
    return m;
}

}  // namespace

TEST_CASE("point-triangle distance matches a reference for random and degenerate triangles") {
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> u(-2.0, 2.0);
    auto rp = [&] { return Vec3d{{u(rng), u(rng), u(rng)}}; };
    double worst = 0.0;
    for (int it = 0; it < 20000; ++it) {
        const Vec3d a = rp(), p = rp();
        Vec3d b = rp(), c = rp();
        if (it % 10 == 1) c = a + (b - a) * u(rng);  // collinear
        if (it % 10 == 2) b = c = a;                 // a point
        if (it % 10 == 3) c = b;                     // a segment
        const double d = std::sqrt(point_triangle_distance2(p, a, b, c));
        const double r = reference_distance(p, a, b, c);
        worst = std::max(worst, std::abs(d - r) / std::max(1.0, r));
    }
    CHECK(worst < 1e-12);
}

TEST_CASE("the signed distance of an axis-aligned cube is the analytic box SDF, rows through edges included") {
    const double id[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    const TriangleMesh m = cube_mesh(id, Vec3d{{0, 0, 0}});
    SdfOptions o;
    o.resolution = 21;
    o.padding = 5;  // h = 0.2, samples at -2 + 0.2 k: rows along the face diagonals and edges
    std::atomic<int> calls{0};
    double last = 0.0;
    const VolumeData v = signed_distance_volume(m, o, [&](double f) { ++calls; last = std::max(last, f); });
    REQUIRE(v.nx() == 21);
    REQUIRE(v.nz() == 21);
    CHECK(v.spacing[0] == doctest::Approx(0.2));
    CHECK(calls.load() == 21);
    CHECK(last == 1.0);
    int wrong_sign = 0;
    double worst = 0.0;
    for (int k = 0; k < v.nz(); ++k)
        for (int j = 0; j < v.ny(); ++j)
            for (int i = 0; i < v.nx(); ++i) {
                const Vec3d p{{v.origin[0] + v.spacing[0] * i, v.origin[1] + v.spacing[1] * j, v.origin[2] + v.spacing[2] * k}};
                const double ref = box_sdf(p, 1.0), got = v.grid.at(i, j, k);
                worst = std::max(worst, std::abs(std::abs(got) - std::abs(ref)));
                if (std::abs(ref) > 1e-9 && (got < 0) != (ref < 0)) ++wrong_sign;
            }
    CHECK(worst < 1e-6);
    CHECK(wrong_sign == 0);
    CHECK(v.min == doctest::Approx(-1.0));
}

TEST_CASE("a rotated and moved cube read from OFF quads gives the analytic SDF") {
    vtest::TempDir dir;
    const double c = std::cos(0.7), s = std::sin(0.7), c2 = std::cos(0.3), s2 = std::sin(0.3);
    // rot = Rz(0.7) * Rx(0.3)
    const double rot[3][3] = {{c, -s * c2, s * s2}, {s, c * c2, -c * s2}, {0, s2, c2}};
    const Vec3d shift{{10.0, -3.0, 0.5}};
    const TriangleMesh tri = cube_mesh(rot, shift);
    {
        std::ofstream off(dir.file("cube.off"));
        off << "OFF\n8 6 0\n";
        off.precision(17);
        for (const auto& p : tri.vertices) off << p[0] << " " << p[1] << " " << p[2] << "\n";
        const int quads[6][4] = {{0, 1, 3, 2}, {4, 6, 7, 5}, {0, 4, 5, 1}, {2, 3, 7, 6}, {0, 2, 6, 4}, {1, 5, 7, 3}};
        for (const auto& q : quads) off << "4 " << q[0] << " " << q[1] << " " << q[2] << " " << q[3] << "\n";
    }
    const TriangleMesh m = read_off_mesh(dir.file("cube.off"));
    REQUIRE(m.triangles.size() == 12);
    SdfOptions o;
    o.resolution = 24;
    const VolumeData v = signed_distance_volume(m, o);
    int wrong_sign = 0;
    double worst = 0.0;
    for (int k = 0; k < v.nz(); ++k)
        for (int j = 0; j < v.ny(); ++j)
            for (int i = 0; i < v.nx(); ++i) {
                const Vec3d p{{v.origin[0] + v.spacing[0] * i - shift[0], v.origin[1] + v.spacing[1] * j - shift[1],
                               v.origin[2] + v.spacing[2] * k - shift[2]}};
                Vec3d q{};  // rot^T p
                for (int a = 0; a < 3; ++a) q[a] = rot[0][a] * p[0] + rot[1][a] * p[1] + rot[2][a] * p[2];
                const double ref = box_sdf(q, 1.0), got = v.grid.at(i, j, k);
                worst = std::max(worst, std::abs(got - ref));
                if (std::abs(ref) > 1e-9 && (got < 0) != (ref < 0)) ++wrong_sign;
            }
    CHECK(wrong_sign == 0);
    CHECK(worst < 1e-5);
}

TEST_CASE("bad meshes and options are clear errors") {
    TriangleMesh empty;
    empty.source = "empty.off";
    CHECK_THROWS_WITH_AS((void)signed_distance_volume(empty), "empty.off: the mesh has no faces", VolumeError);
    TriangleMesh point;
    point.source = "point.off";
    point.vertices = {Vec3d{{1, 1, 1}}};
    point.triangles = {{0, 0, 0}};
    CHECK_THROWS_WITH_AS((void)signed_distance_volume(point), doctest::Contains("no extent"), VolumeError);
    const double id[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    SdfOptions o;
    o.resolution = 4;
    CHECK_THROWS_WITH_AS((void)signed_distance_volume(cube_mesh(id, Vec3d{{0, 0, 0}}), o), doctest::Contains("resolution"), VolumeError);
}
