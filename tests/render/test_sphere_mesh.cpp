// tests/render/test_sphere_mesh.cpp -- geodesic spheres: counts, closed and outward, inscribed, sagitta
#include <doctest/doctest.h>

#include <cmath>
#include <map>
#include <utility>

#include "quadcast/render/sphere_mesh.hpp"

using namespace quadcast;
using namespace quadcast::render;

TEST_CASE("the geodesic sphere of frequency f is a closed, outward, inscribed mesh of 20 f^2 triangles") {
    double prev = 1.0;
    for (int f : {1, 2, 3, 4, 7, 16}) {
        const SphereMesh m = geodesic_sphere(f);
        CHECK(m.frequency == f);
        CHECK(m.vertices.size() == std::size_t(10 * f * f + 2));
        CHECK(m.triangles.size() == std::size_t(20 * f * f));
        for (const auto& v : m.vertices) CHECK(std::fabs(length(v) - 1.0) <= 1e-15);
        // Every directed edge once, its reverse once: closed and consistently oriented.
        std::map<std::pair<std::uint32_t, std::uint32_t>, int> edges;
        long inward = 0;
        for (const auto& t : m.triangles) {
            for (int k = 0; k < 3; ++k) ++edges[{t[k], t[(k + 1) % 3]}];
            const Vec3<double>& a = m.vertices[t[0]];
            inward += dot(cross(m.vertices[t[1]] - a, m.vertices[t[2]] - a), a) <= 0;
        }
        long unpaired = 0;
        for (const auto& [e, n] : edges) unpaired += n != 1 || edges.count({e.second, e.first}) != 1;
        CHECK(unpaired == 0);
        CHECK(inward == 0);
        // The sagitta falls like 1/f^2: the icosahedron's inradius is 0.7947 of its circumradius.
        const double s = sphere_mesh_sagitta(m);
        if (f == 1) CHECK(std::fabs(s - (1.0 - 0.79465447229176612)) < 1e-12);
        CHECK(s < prev);
        CHECK(s * f * f < 0.3);
        CHECK(s * f * f > 0.15);
        prev = s;
    }
    CHECK_THROWS_AS(geodesic_sphere(0), std::invalid_argument);
}
