// tests/spline/test_partition.cpp -- type-6 partition: tetra table, rotations, point location, barycentrics, D-sets
#include <doctest/doctest.h>

#include <array>
#include <cmath>
#include <random>
#include <set>
#include <string>

#include "quadcast/spline/spline.hpp"

using namespace quadcast;
using namespace quadcast::spline;

namespace {

// The table of spec §1.2 (v2, v3, R_t u), transcribed as text.
const char* const spec_table[24][3] = {
    {"(1,-1,-1)", "(1,1,-1)", "(ux,uy,uz)"},       {"(1,1,-1)", "(1,1,1)", "(ux,-uz,uy)"},
    {"(1,1,1)", "(1,-1,1)", "(ux,-uy,-uz)"},       {"(1,-1,1)", "(1,-1,-1)", "(ux,uz,-uy)"},
    {"(-1,-1,-1)", "(-1,-1,1)", "(-ux,uz,uy)"},    {"(-1,-1,1)", "(-1,1,1)", "(-ux,uy,-uz)"},
    {"(-1,1,1)", "(-1,1,-1)", "(-ux,-uz,-uy)"},    {"(-1,1,-1)", "(-1,-1,-1)", "(-ux,-uy,uz)"},
    {"(-1,1,-1)", "(-1,1,1)", "(uz,ux,uy)"},       {"(-1,1,1)", "(1,1,1)", "(uy,ux,-uz)"},
    {"(1,1,1)", "(1,1,-1)", "(-uz,ux,-uy)"},       {"(1,1,-1)", "(-1,1,-1)", "(-uy,ux,uz)"},
    {"(-1,-1,-1)", "(1,-1,-1)", "(uy,-ux,uz)"},    {"(1,-1,-1)", "(1,-1,1)", "(-uz,-ux,uy)"},
    {"(1,-1,1)", "(-1,-1,1)", "(-uy,-ux,-uz)"},    {"(-1,-1,1)", "(-1,-1,-1)", "(uz,-ux,-uy)"},
    {"(-1,-1,1)", "(1,-1,1)", "(uy,uz,ux)"},       {"(1,-1,1)", "(1,1,1)", "(-uz,uy,ux)"},
    {"(1,1,1)", "(-1,1,1)", "(-uy,-uz,ux)"},       {"(-1,1,1)", "(-1,-1,1)", "(uz,-uy,ux)"},
    {"(-1,-1,-1)", "(-1,1,-1)", "(uz,uy,-ux)"},    {"(-1,1,-1)", "(1,1,-1)", "(uy,-uz,-ux)"},
    {"(1,1,-1)", "(1,-1,-1)", "(-uz,-uy,-ux)"},    {"(1,-1,-1)", "(-1,-1,-1)", "(-uy,uz,-ux)"},
};

IVec3 parse_point(const std::string& s) {
    IVec3 p{};
    int k = 0, sign = 1;
    for (char ch : s) {
        if (ch == '-') sign = -1;
        if (ch == '1') { p[k++] = sign; sign = 1; }
    }
    return p;
}

IMat3 parse_rotation(const std::string& s) {
    IMat3 m{};
    int row = 0, sign = 1;
    for (std::size_t i = 0; i < s.size(); ++i) {
        if (s[i] == '-') sign = -1;
        if (s[i] == 'u') {
            const int col = s[i + 1] - 'x';
            m[row][col] = sign;
            sign = 1;
            ++row;
        }
    }
    return m;
}

int det3(const IMat3& m) {
    return m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
           m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
}

}  // namespace

TEST_CASE("the 24 tetrahedra and rotations match the table of the spec") {
    for (int t = 0; t < 24; ++t) {
        CAPTURE(t);
        const auto v = tet_vertices(t);
        CHECK(v[0] == IVec3{0, 0, 0});
        CHECK(v[1] == face_normal(t / 4));
        CHECK(v[2] == parse_point(spec_table[t][0]));
        CHECK(v[3] == parse_point(spec_table[t][1]));
        CHECK(rotation(t) == parse_rotation(spec_table[t][2]));
        CHECK(det3(rotation(t)) == 1);
        // same orientation: det[v1 - v0, v2 - v0, v3 - v0] = +2
        const IMat3 e = {IVec3{v[1][0], v[2][0], v[3][0]}, IVec3{v[1][1], v[2][1], v[3][1]}, IVec3{v[1][2], v[2][2], v[3][2]}};
        CHECK(det3(e) == 2);
        const auto v0 = tet_vertices(0);
        for (int m = 0; m < 4; ++m) CHECK(mat_apply(rotation(t), v0[m]) == v[m]);
    }
}

TEST_CASE_TEMPLATE("point location and barycentric coordinates are consistent", T, float, double) {
    std::mt19937 rng(31);
    std::uniform_real_distribution<double> u(-1, 1);
    double worst = 0;
    for (int it = 0; it < 200000; ++it) {
        const Vec<T, 3> p = {{T(u(rng)), T(u(rng)), T(u(rng))}};
        const int t = locate_tet(p);
        const Vec<T, 4> l = barycentric(t, p);
        const T tol = T(4) * std::numeric_limits<T>::epsilon();
        CHECK(l[0] >= -tol);
        CHECK(l[1] >= -tol);
        CHECK(l[2] >= -tol);
        CHECK(l[3] >= -tol);
        // Σλ = 1 and Σ λm vm = p
        const auto v = tet_vertices(t);
        double back[3] = {0, 0, 0}, sum = 0;
        for (int m = 0; m < 4; ++m) {
            sum += static_cast<double>(l[m]);
            for (int a = 0; a < 3; ++a) back[a] += static_cast<double>(l[m]) * v[m][a];
        }
        worst = std::max(worst, std::fabs(sum - 1));
        for (int a = 0; a < 3; ++a) worst = std::max(worst, std::fabs(back[a] - static_cast<double>(p[a])));
        if (it > 2000) continue;  // the frame round trip is exact; checking a few suffices
        const Vec<T, 3> q = from_tet0_frame(t, to_tet0_frame(t, p));
        CHECK(q[0] == p[0]);
        CHECK(q[1] == p[1]);
        CHECK(q[2] == p[2]);
    }
    MESSAGE("max |Σλ - 1|, |Σλ v - u| = ", worst);
    CHECK(worst < 8 * std::numeric_limits<T>::epsilon());
}

TEST_CASE("barycentric directions are the derivatives of the barycentric coordinates") {
    for (int t = 0; t < 24; ++t) {
        const Mat<double, 4, 3> d = barycentric_directions<double>(t);
        const Vec<double, 3> p = {{0.375, -0.25, 0.125}};  // dyadic: differences are exact
        const Vec<double, 4> l0 = barycentric(t, p);
        for (int a = 0; a < 3; ++a) {
            Vec<double, 3> q = p;
            q[a] += 1.0;  // barycentrics are affine: the difference is exact
            const Vec<double, 4> l1 = barycentric(t, q);
            for (int m = 0; m < 4; ++m) CHECK(d[a][m] == l1[m] - l0[m]);
        }
    }
}

TEST_CASE("determining sets have 20 and 56 distinct points and the permutations are bijections") {
    for (int q : {2, 3}) {
        std::set<IVec3> pts;
        for (int k = 0; k < d_count(q); ++k) {
            const IVec3 p = d_point(q, k);
            pts.insert(p);
            CHECK(d_index(q, p) == k);
            // every D point lies on the cube surface (ring q)
            CHECK(std::max({iabs(p[0]), iabs(p[1]), iabs(p[2])}) == q);
        }
        CHECK(static_cast<int>(pts.size()) == d_count(q));
    }
    // D2 edge midpoints have two coordinates ±2 and one 0; D3 triangle points one ±3, one ±2, one 0
    for (int k = 8; k < 20; ++k) {
        const IVec3 p = d_point(2, k);
        CHECK(iabs(p[0]) + iabs(p[1]) + iabs(p[2]) == 4);
    }
    for (int k = 32; k < 56; ++k) {
        const IVec3 p = d_point(3, k);
        CHECK(iabs(p[0]) + iabs(p[1]) + iabs(p[2]) == 5);
    }
    const auto p2 = d_permutations<2>();
    const auto p3 = d_permutations<3>();
    const auto ps = stencil_permutations();
    for (int t = 0; t < 24; ++t) {
        std::set<int> a(p2[t].begin(), p2[t].end()), b(p3[t].begin(), p3[t].end()), c(ps[t].begin(), ps[t].end());
        CHECK(a.size() == 20);
        CHECK(*a.begin() == 0);
        CHECK(b.size() == 56);
        CHECK(*b.begin() == 0);
        CHECK(c.size() == 27);
        // the triangle point of T_0 maps to the triangle point of T_t
        CHECK(p3[t][32] == 32 + t);
    }
    // storage: per cube D2 / D3 against all BB data of the 24 pieces (paper: "about 8% and 12%")
    static_assert(d_count(2) == 20 && d_count(3) == 56);
    static_assert(24 * bb::coefficient_count(2) == 240 && 24 * bb::coefficient_count(3) == 480);
    MESSAGE("D2 = 20 / 240 = ", 20.0 / 240.0 * 100, " %, D3 = 56 / 480 = ", 56.0 / 480.0 * 100, " % of the full per-cube BB data");
}
