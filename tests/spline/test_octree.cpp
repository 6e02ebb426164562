// tests/spline/test_octree.cpp -- min-max octree on coefficient ranges and hierarchical frustum culling
#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <random>
#include <set>
#include <vector>

#include "quadcast/bb/bb.hpp"
#include "spline/spline_test_util.hpp"

using namespace quadcast;
using namespace quadcast::spline;

namespace {

/// A smooth random field (a few Gaussian bumps) plus noise: isosurfaces cross many cubes.
Volume<float> bumpy_volume(int nx, int ny, int nz, unsigned seed) {
    Volume<float> v(nx, ny, nz);
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(0, 1);
    std::array<std::array<double, 5>, 6> bumps{};
    for (auto& b : bumps) b = {u(rng) * nx, u(rng) * ny, u(rng) * nz, 1.5 + 3 * u(rng), u(rng) < 0.5 ? -1.0 : 1.0};
    for (int k = 0; k < nz; ++k)
        for (int j = 0; j < ny; ++j)
            for (int i = 0; i < nx; ++i) {
                double f = 0.3 * (u(rng) - 0.5);
                for (const auto& b : bumps) {
                    const double d2 = (i - b[0]) * (i - b[0]) + (j - b[1]) * (j - b[1]) + (k - b[2]) * (k - b[2]);
                    f += b[4] * std::exp(-d2 / (b[3] * b[3]));
                }
                v.at(i, j, k) = static_cast<float>(f);
            }
    return v;
}

/// Range of the spline on each cube, sampled at the points of the degree-6 barycentric lattice
/// of all 24 pieces (84 points per piece, all coefficients of the pieces included separately).
template <int Q>
void sample_ranges(const SplineGrid<Q, float>& g, std::vector<Range<float>>& samples, std::vector<Range<float>>& coefs) {
    samples.assign(g.cube_count(), {1e30f, -1e30f});
    coefs.assign(g.cube_count(), {1e30f, -1e30f});
    const auto lattice = bb::multi_indices<6>();
    for (int c = 0; c < g.cube_count(); ++c) {
        for (int t = 0; t < 24; ++t) {
            const auto coef = tet_from_determining_set<Q>(g.cube_d(c), t);
            for (int n = 0; n < coef.size; ++n) {
                coefs[c].lo = std::min(coefs[c].lo, coef[n]);
                coefs[c].hi = std::max(coefs[c].hi, coef[n]);
            }
            for (const auto& m : lattice) {
                const Vec<float, 4> l = {{m.i / 6.0f, m.j / 6.0f, m.k / 6.0f, m.l / 6.0f}};
                const float v = bb::evaluate(coef, l);
                samples[c].lo = std::min(samples[c].lo, v);
                samples[c].hi = std::max(samples[c].hi, v);
            }
        }
    }
}

Mat<double, 4, 4> perspective(double fovy, double aspect, double n, double f) {
    const double t = 1.0 / std::tan(fovy / 2);
    const Vec<double, 4> rows[4] = {{{t / aspect, 0, 0, 0}}, {{0, t, 0, 0}}, {{0, 0, (f + n) / (n - f), 2 * f * n / (n - f)}}, {{0, 0, -1, 0}}};
    return from_rows<double, 4, 4>(rows);
}

Mat<double, 4, 4> look_at(const Vec<double, 3>& eye, const Vec<double, 3>& centre, const Vec<double, 3>& up) {
    const Vec<double, 3> f = normalize(centre - eye), s = normalize(cross(f, up)), u = cross(s, f);
    const Vec<double, 4> rows[4] = {{{s[0], s[1], s[2], -dot(s, eye)}}, {{u[0], u[1], u[2], -dot(u, eye)}},
                                    {{-f[0], -f[1], -f[2], dot(f, eye)}}, {{0, 0, 0, 1}}};
    return from_rows<double, 4, 4>(rows);
}

template <int Q>
void check_octree(const char* name) {
    const Volume<float> vol = bumpy_volume(21, 17, 13, 5);
    const auto g = build_spline<Q>(vol, {{0.0, 0.0, 0.0}}, 1.0);
    const auto tree = MinMaxOctree<float>::from_spline(g);
    CHECK(tree.level_count() == 6);  // 21 -> 11 -> 6 -> 3 -> 2 -> 1
    std::vector<Range<float>> samples, coefs;
    sample_ranges(g, samples, coefs);
    // cube ranges contain every coefficient of the per-tetrahedron path
    long not_contained = 0;
    for (int c = 0; c < g.cube_count(); ++c)
        not_contained += !(tree.level(0).range[c].lo <= coefs[c].lo && coefs[c].hi <= tree.level(0).range[c].hi);
    CHECK(not_contained == 0);
    // data ranges (the paper's octree: min/max of the 27-stencil data)
    std::vector<Range<float>> data(g.cube_count());
    for (int c = 0; c < g.cube_count(); ++c) {
        const IVec3 ijk = g.cube_ijk(c);
        const Stencil<float> f = stencil(vol, ijk[0], ijk[1], ijk[2]);
        data[c] = {f[0], f[0]};
        for (int s = 1; s < 27; ++s) data[c] = {std::min(data[c].lo, f[s]), std::max(data[c].hi, f[s])};
    }
    long skipped = 0, with_surface = 0, active = 0, data_misses = 0, data_active = 0, tet_misses = 0;
    for (int r = 0; r < 15; ++r) {
        const float rho = -0.9f + 0.13f * r;
        const std::vector<int> act = tree.active_cubes(rho);
        const std::set<int> aset(act.begin(), act.end());
        active += static_cast<long>(act.size());
        for (int c = 0; c < g.cube_count(); ++c) {
            CHECK(aset.count(c) == (tree.cube_may_contain(c, rho) ? 1u : 0u));
            const bool surface = samples[c].lo <= rho && rho <= samples[c].hi;
            with_surface += surface;
            if (surface && !aset.count(c)) ++skipped;
            data_active += data[c].contains(rho);
            if (surface && !data[c].contains(rho)) ++data_misses;
            if (surface) {
                // the relevant-tetrahedra mask keeps every piece whose samples straddle rho
                const unsigned mask = relevant_tets<Q>(g.cube_d(c), rho);
                for (int t = 0; t < 24; ++t) {
                    const auto coef = tet_from_determining_set<Q>(g.cube_d(c), t);
                    float lo = 1e30f, hi = -1e30f;
                    for (const auto& m : bb::multi_indices<6>()) {
                        const float v = bb::evaluate(coef, Vec<float, 4>{{m.i / 6.0f, m.j / 6.0f, m.k / 6.0f, m.l / 6.0f}});
                        lo = std::min(lo, v);
                        hi = std::max(hi, v);
                    }
                    if (lo <= rho && rho <= hi && !(mask >> t & 1u)) ++tet_misses;
                }
            }
        }
    }
    std::printf("%s octree on %d cubes, 15 isovalues: cubes with the isosurface (sampled) %ld, active by coefficient ranges %ld, "
                "skipped with surface %ld; data-range octree: active %ld, would skip %ld cubes that contain the isosurface\n",
                name, g.cube_count(), with_surface, active, skipped, data_active, data_misses);
    CHECK(skipped == 0);
    CHECK(tet_misses == 0);
    CHECK(with_surface > 1000);  // the test exercises many cubes
    if (Q == 3) CHECK(data_misses == 0);  // S31: convex masks, data range is conservative

    // Hierarchical frustum culling against a brute-force box test, from several cameras.
    long total_visited = 0, total_out = 0, total_cubes = 0;
    for (int cam = 0; cam < 8; ++cam) {
        std::mt19937 rng(900 + cam);
        std::uniform_real_distribution<double> u(-1, 1);
        const Vec<double, 3> centre = {{10 + 6 * u(rng), 8 + 5 * u(rng), 6 + 4 * u(rng)}};
        const Vec<double, 3> eye = {{centre[0] + 15 * u(rng), centre[1] + 15 * u(rng), centre[2] + 25}};
        const Mat<double, 4, 4> clip = perspective(0.5 + 0.5 * (u(rng) + 1), 1.3, 1.0, 35.0 + 10 * u(rng)) * look_at(eye, centre, {{0, 1, 0}});
        const Frustum fr = frustum_from_clip_matrix(clip);
        const float rho = 0.1f * static_cast<float>(cam) - 0.3f;
        std::size_t visited = 0;
        const std::vector<int> got = tree.active_cubes(rho, &fr, &visited);
        std::vector<int> expect;
        long must = 0, must_missing = 0;
        const std::set<int> gs(got.begin(), got.end());
        for (int c = 0; c < g.cube_count(); ++c) {
            const IVec3 ijk = g.cube_ijk(c);
            const Vec<double, 3> lo = {{ijk[0] - 0.5, ijk[1] - 0.5, ijk[2] - 0.5}}, hi = {{ijk[0] + 0.5, ijk[1] + 0.5, ijk[2] + 0.5}};
            if (tree.cube_may_contain(c, rho) && classify_box(fr, lo, hi) != Containment::outside) expect.push_back(c);
            // conservative: a cube with a point inside the frustum is never culled
            if (!tree.cube_may_contain(c, rho)) continue;
            bool seen = false;
            for (int s = 0; s < 27 && !seen; ++s) {
                const IVec3 o = stencil_offset(s);
                const Vec<double, 4> p = {{ijk[0] + 0.49 * o[0], ijk[1] + 0.49 * o[1], ijk[2] + 0.49 * o[2], 1.0}};
                const Vec<double, 4> q = clip * p;
                seen = std::fabs(q[0]) <= q[3] && std::fabs(q[1]) <= q[3] && std::fabs(q[2]) <= q[3];
            }
            if (seen) {
                ++must;
                must_missing += !gs.count(c);
            }
        }
        CHECK(got == expect);
        CHECK(must_missing == 0);
        // nodes on a fixed level cover the active cubes
        const std::vector<int> nodes = tree.active_nodes(2, rho, &fr);
        std::set<int> ns(nodes.begin(), nodes.end());
        for (int c : got) {
            const IVec3 ijk = g.cube_ijk(c);
            const auto& L2 = tree.level(2);
            CHECK(ns.count(ijk[0] / 4 + L2.nx * (ijk[1] / 4 + L2.ny * (ijk[2] / 4))) == 1u);
        }
        total_visited += static_cast<long>(visited);
        total_out += static_cast<long>(got.size());
        total_cubes += g.cube_count();
        (void)must;
    }
    std::printf("%s frustum culling, 8 cameras: %ld of %ld cubes drawn, %ld octree nodes tested (brute force: %ld cube tests)\n", name,
                total_out, total_cubes, total_visited, total_cubes);
}

}  // namespace

TEST_CASE("the QSS octree never skips a cube that contains the isosurface; frustum culling is exact on boxes") {
    check_octree<2>("QSS");
}

TEST_CASE("the S31 octree never skips a cube that contains the isosurface; frustum culling is exact on boxes") {
    check_octree<3>("S31");
}

TEST_CASE("a box is classified against a frustum conservatively") {
    const Mat<double, 4, 4> clip = perspective(1.0, 1.0, 1.0, 10.0);  // camera at 0 looking down -z
    const Frustum f = frustum_from_clip_matrix(clip);
    CHECK(classify_box(f, {{-0.1, -0.1, -3.1}}, {{0.1, 0.1, -2.9}}) == Containment::inside);
    CHECK(classify_box(f, {{-0.1, -0.1, 0.5}}, {{0.1, 0.1, 0.9}}) == Containment::outside);   // behind the camera
    CHECK(classify_box(f, {{-0.1, -0.1, -12}}, {{0.1, 0.1, -11}}) == Containment::outside);   // beyond far
    CHECK(classify_box(f, {{-0.1, -0.1, -10.5}}, {{0.1, 0.1, -9.5}}) == Containment::intersecting);
    CHECK(classify_box(f, {{50, -0.1, -3}}, {{51, 0.1, -2}}) == Containment::outside);
}

TEST_CASE("QSS can leave the data range, the coefficient-range octree keeps such cubes") {
    // 1 at the 8 corners of the 3x3x3 block, 0 elsewhere: the QSS centre coefficient is
    // -8/128 = -1/16 (spec §2.5), so s(v_Q) < min(data) = 0 and the level -1/32 exists there.
    Volume<float> vol(3, 3, 3);
    for (int k : {0, 2})
        for (int j : {0, 2})
            for (int i : {0, 2}) vol.at(i, j, k) = 1.0f;
    const auto g = build_spline<2>(vol, {{0.0, 0.0, 0.0}}, 1.0);
    const int c = g.cube_index(1, 1, 1);
    const ValueAndGradient<float> centre = evaluate(g, {{1.0, 1.0, 1.0}});
    CHECK(centre.value == doctest::Approx(-1.0 / 16.0));
    const auto tree = MinMaxOctree<float>::from_spline(g);
    const float rho = -1.0f / 32.0f;
    CHECK(tree.cube_may_contain(c, rho));  // the data range [0, 1] would say no
    const auto g3 = build_spline<3>(vol, {{0.0, 0.0, 0.0}}, 1.0);
    CHECK(evaluate(g3, {{1.0, 1.0, 1.0}}).value >= 0.0f);  // S31 stays in the data range
}
