// tests/spline/test_marching_cubes.cpp -- the generated marching-cubes table and the meshes it makes
#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <map>
#include <set>
#include <utility>
#include <vector>

#include "quadcast/spline/marching_cubes.hpp"
#include "spline/spline_test_util.hpp"

using namespace quadcast;
using namespace quadcast::spline;

namespace {

bool above(int code, int c) { return ((code >> c) & 1) != 0; }
bool crosses(int code, int e) {
    const auto k = mc_edge_corners(e);
    return above(code, k[0]) != above(code, k[1]);
}

/// The faces (axis*2 + side) an edge lies on.
std::set<int> cell_edge_faces(int e) {
    const auto k = mc_edge_corners(e);
    std::set<int> f;
    for (int a = 0; a < 3; ++a) {
        const int b0 = (k[0] >> a) & 1, b1 = (k[1] >> a) & 1;
        if (b0 == b1) f.insert(2 * a + b0);
    }
    return f;
}

/// Checks a mesh: every edge shared by exactly two triangles in opposite directions, except edges
/// lying in a face of the grid box (then used once). Returns the number of such border edges.
long check_watertight(const McMesh& m, int nx, int ny, int nz) {
    std::map<std::pair<int, int>, int> directed;
    for (const auto& t : m.triangles) {
        REQUIRE(t[0] != t[1]);
        REQUIRE(t[1] != t[2]);
        REQUIRE(t[0] != t[2]);
        for (int s = 0; s < 3; ++s) ++directed[{t[s], t[(s + 1) % 3]}];
    }
    const int n[3] = {nx, ny, nz};
    auto on_border_face = [&](int a, int b) {
        for (int ax = 0; ax < 3; ++ax)
            for (const float side : {0.0f, float(n[ax] - 1)})
                if (m.positions[a][ax] == side && m.positions[b][ax] == side) return true;
        return false;
    };
    long border = 0, bad = 0;
    for (const auto& [e, count] : directed) {
        CHECK(count == 1);  // consistent orientation: an edge is never traversed twice the same way
        if (directed.count({e.second, e.first})) continue;
        if (on_border_face(e.first, e.second)) ++border;
        else ++bad;
    }
    CHECK(bad == 0);
    return border;
}

}  // namespace

TEST_CASE("marching cubes: every one of the 256 generated cases closes its polygons") {
    int ambiguous_faces = 0;
    for (int code = 0; code < 256; ++code) {
        const McCase& mc = mc_table[static_cast<std::size_t>(code)];
        CAPTURE(code);
        CHECK(mc.closed);
        // Every crossing edge is used exactly once, no other edge at all
        std::array<int, 12> uses{};
        int triangles = 0;
        for (int p = 0; p < mc.polygon_count; ++p) {
            const int n = mc.polygon_size[p];
            CHECK(n >= 3);
            triangles += n - 2;
            for (int i = 0; i < n; ++i) {
                const int e = mc.polygon[p][i], f = mc.polygon[p][(i + 1) % n];
                ++uses[e];
                // Consecutive polygon vertices lie on a common face (a segment of that face)
                std::set<int> common;
                const std::set<int> fe = cell_edge_faces(e), ff = cell_edge_faces(f);
                std::set_intersection(fe.begin(), fe.end(), ff.begin(), ff.end(), std::inserter(common, common.begin()));
                CHECK(common.size() == 1);
            }
        }
        for (int e = 0; e < 12; ++e) CHECK(uses[e] == (crosses(code, e) ? 1 : 0));
        CHECK(mc.triangle_count == triangles);
        // Triangle edges that are no polygon segment (diagonals) join crossings on no common face
        std::set<std::pair<int, int>> segments;
        for (int p = 0; p < mc.polygon_count; ++p)
            for (int i = 0; i < mc.polygon_size[p]; ++i) {
                const int e = mc.polygon[p][i], f = mc.polygon[p][(i + 1) % mc.polygon_size[p]];
                segments.insert({std::min(e, f), std::max(e, f)});
            }
        for (int t = 0; t < mc.triangle_count; ++t)
            for (int s = 0; s < 3; ++s) {
                const int e = mc.triangle[t][s], f = mc.triangle[t][(s + 1) % 3];
                if (segments.count({std::min(e, f), std::max(e, f)})) continue;
                std::set<int> common;
                const std::set<int> fe = cell_edge_faces(e), ff = cell_edge_faces(f);
                std::set_intersection(fe.begin(), fe.end(), ff.begin(), ff.end(), std::inserter(common, common.begin()));
                CHECK(common.empty());
            }
        if (code == 0 || code == 255) CHECK(mc.polygon_count == 0);
        // Count ambiguous faces seen (a face with 4 crossing edges)
        for (int f = 0; f < 6; ++f) {
            int cr = 0;
            for (int e = 0; e < 12; ++e)
                if (crosses(code, e) && cell_edge_faces(e).count(f)) ++cr;
            ambiguous_faces += cr == 4;
        }
    }
    CHECK(ambiguous_faces > 0);  // the rule for ambiguous faces was exercised
}

TEST_CASE("marching cubes: a single above corner gives one triangle facing the corner") {
    for (int c = 0; c < 8; ++c) {
        const McCase& mc = mc_table[static_cast<std::size_t>(1 << c)];
        REQUIRE(mc.triangle_count == 1);
        // The right-hand normal of the triangle (at edge midpoints) points towards the corner
        Vec3<double> p[3];
        for (int s = 0; s < 3; ++s) {
            const auto k = mc_edge_corners(mc.triangle[0][s]);
            for (int a = 0; a < 3; ++a) p[s][a] = 0.5 * (((k[0] >> a) & 1) + ((k[1] >> a) & 1));
        }
        const Vec3<double> nrm = cross(p[1] - p[0], p[2] - p[0]);
        const Vec3<double> corner{{double(c & 1), double((c >> 1) & 1), double((c >> 2) & 1)}};
        CHECK(dot(nrm, corner - p[0]) > 0);
    }
}

TEST_CASE("marching cubes: random data give a watertight, consistently oriented mesh on grid edges") {
    for (unsigned seed : {1u, 2u, 3u}) {
        const Volume<float> v = stest::random_volume<float>(9 + int(seed), 8, 7 + 2 * int(seed), seed);
        const float rho = seed == 3 ? 0.0f : 0.25f * float(seed) - 0.3f;
        const McMesh m = marching_cubes(v, rho);
        CAPTURE(seed);
        REQUIRE(m.triangles.size() > 100);
        REQUIRE(m.triangle_cell.size() == m.triangles.size());
        CHECK(std::is_sorted(m.triangle_cell.begin(), m.triangle_cell.end()));
        check_watertight(m, v.nx, v.ny, v.nz);
        // Each vertex: on its grid edge, where the linear interpolant equals ρ
        for (std::size_t i = 0; i < m.positions.size(); ++i) {
            const std::int64_t s = m.vertex_sample[i];
            const int a = m.vertex_axis[i];
            const int si = int(s % v.nx), sj = int((s / v.nx) % v.ny), sk = int(s / (std::int64_t(v.nx) * v.ny));
            const int p0[3] = {si, sj, sk};
            const double f0 = v.at(si, sj, sk), f1 = v.at(si + (a == 0), sj + (a == 1), sk + (a == 2)), r = rho;
            for (int b = 0; b < 3; ++b)
                if (b != a) CHECK(m.positions[i][b] == float(p0[b]));
            const double t = double(m.positions[i][a]) - p0[a];
            CHECK(t >= 0.0);
            CHECK(t <= 1.0);
            CHECK((f0 > r) != (f1 > r));
            CHECK(std::abs(f0 + t * (f1 - f0) - r) <= 1e-6 * (std::abs(f1 - f0) + 1.0));
        }
        // Triangles lie in their cells
        for (std::size_t t = 0; t < m.triangles.size(); ++t) {
            const int c = m.triangle_cell[t];
            const int ci[3] = {c % (v.nx - 1), (c / (v.nx - 1)) % (v.ny - 1), c / ((v.nx - 1) * (v.ny - 1))};
            for (int s = 0; s < 3; ++s)
                for (int a = 0; a < 3; ++a) {
                    CHECK(m.positions[m.triangles[t][s]][a] >= float(ci[a]));
                    CHECK(m.positions[m.triangles[t][s]][a] <= float(ci[a] + 1));
                }
        }
    }
}

TEST_CASE("marching cubes: samples equal to the isovalue (label data) still give a watertight mesh") {
    // Values in {0, 1, 2} with ρ = 1: many vertices sit on samples (t = 1) and triangles degenerate
    // geometrically, but the mesh stays combinatorially closed and consistently oriented
    Volume<float> v = stest::random_volume<float>(10, 9, 8, 7u, 0.0, 3.0);
    for (float& x : v.data) x = std::floor(x);
    const McMesh m = marching_cubes(v, 1.0f);
    REQUIRE(m.triangles.size() > 50);
    check_watertight(m, v.nx, v.ny, v.nz);
    for (const auto& p : m.positions)
        for (int a = 0; a < 3; ++a) CHECK(std::isfinite(p[a]));
}

namespace {

/// Samples of |x - c|^2 - R^2 on an (n+1)^3 grid of [0,1]^3 (h = 1/n), c off the grid's
/// symmetry: smooth but not linear along grid edges, so the vertices err by O(h^2).
Volume<float> sphere_volume(int n, double R, const Vec3<double>& c) {
    Volume<float> v(n + 1, n + 1, n + 1);
    for (int k = 0; k <= n; ++k)
        for (int j = 0; j <= n; ++j)
            for (int i = 0; i <= n; ++i) {
                const Vec3<double> x{{double(i) / n, double(j) / n, double(k) / n}};
                v.at(i, j, k) = float(dot(x - c, x - c) - R * R);
            }
    return v;
}

}  // namespace

TEST_CASE("marching cubes: sampled sphere is a closed oriented surface converging at O(h^2)") {
    const Vec3<double> c{{0.503, 0.497, 0.511}};
    const double R = 0.37;
    std::vector<double> mean_err, max_err;
    for (const int n : {16, 32, 64, 128}) {
        CAPTURE(n);
        const Volume<float> v = sphere_volume(n, R, c);
        const McMesh m = marching_cubes(v, 0.0f);
        CHECK(check_watertight(m, v.nx, v.ny, v.nz) == 0);  // closed: no border edges
        // Euler characteristic of a sphere: V - E + F = 2 (E = 3F/2 for a closed triangle mesh)
        const long V = long(m.positions.size()), F = long(m.triangles.size());
        CHECK(V - 3 * F / 2 + F == 2);
        // Orientation: the triangles face outwards (growing |x - c|), and so do the normals
        long outward = 0;
        for (const auto& t : m.triangles) {
            const Vec3<double> a = cast<double>(m.positions[t[0]]), b = cast<double>(m.positions[t[1]]), d = cast<double>(m.positions[t[2]]);
            const Vec3<double> centre = (a + b + d) * (1.0 / 3.0) * (1.0 / n) - c;
            outward += dot(cross(b - a, d - a), centre) > 0;
        }
        CHECK(outward == F);
        double sum = 0, mx = 0;
        for (std::size_t i = 0; i < m.positions.size(); ++i) {
            const Vec3<double> x = cast<double>(m.positions[i]) * (1.0 / n) - c;
            const double e = std::abs(std::sqrt(dot(x, x)) - R);
            sum += e;
            mx = std::max(mx, e);
            CHECK(dot(cast<double>(m.normals[i]), x) > 0.99 * std::sqrt(dot(x, x)));
        }
        mean_err.push_back(sum / double(V));
        max_err.push_back(mx);
    }
    for (std::size_t i = 1; i < mean_err.size(); ++i) {
        const double rm = mean_err[i - 1] / mean_err[i], rx = max_err[i - 1] / max_err[i];
        std::printf("marching cubes sphere, h -> h/2: mean distance ratio %.2f, max ratio %.2f\n", rm, rx);
        CHECK(rm > 3.5);
        CHECK(rm < 4.5);
        CHECK(rx > 3.0);
        CHECK(rx < 5.0);
    }
}

TEST_CASE("marching cubes: bad input is a clear error") {
    Volume<float> v(3, 3, 3);
    CHECK_THROWS_WITH_AS(marching_cubes(v, std::nanf("")), "quadcast::spline::marching_cubes: isovalue is not finite", std::invalid_argument);
    v.at(1, 2, 0) = INFINITY;
    CHECK_THROWS_WITH_AS(marching_cubes(v, 0.5f), "quadcast::spline::marching_cubes: sample (1,2,0) is not finite", std::invalid_argument);
    CHECK_THROWS_AS(marching_cubes(Volume<float>(1, 3, 3), 0.5f), std::invalid_argument);
}
