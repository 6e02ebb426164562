// tests/spline/test_exact.cpp -- QSS and S31 in exact rational arithmetic: the checks of spec §6
#include <doctest/doctest.h>

#include <array>
#include <cstdio>
#include <map>
#include <random>
#include <vector>

#include "bb/test_scalars.hpp"
#include "quadcast/spline/spline.hpp"

using namespace quadcast;
using namespace quadcast::spline;
using qtest::Rational;

namespace {

template <int Q>
using Tet = bb::BezierTet<Rational, Q>;

Stencil<Rational> unit_stencil(int s) {
    Stencil<Rational> f{};
    for (int i = 0; i < 27; ++i) f[i] = Rational(i == s ? 1 : 0);
    return f;
}

Stencil<Rational> random_stencil(std::mt19937& rng) {
    std::uniform_int_distribution<int> u(-1000, 1000);
    Stencil<Rational> f{};
    for (int i = 0; i < 27; ++i) f[i] = Rational(u(rng));
    return f;
}

/// All 48 symmetries of the cube (signed permutation matrices).
std::vector<IMat3> cube_symmetries() {
    std::vector<IMat3> r;
    const int perms[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
    for (const auto& p : perms)
        for (int s = 0; s < 8; ++s) {
            IMat3 m{};
            for (int i = 0; i < 3; ++i) m[i][p[i]] = (s >> i & 1) ? -1 : 1;
            r.push_back(m);
        }
    return r;
}

/// mask[point][s]: the weight of stencil value s in the coefficient at the scaled point, from
/// the coefficients of all 24 tetrahedra (also checks that every tetrahedron sharing a point
/// gives it the same mask).
template <int Q>
std::map<IVec3, std::array<Rational, 27>> cube_masks(bool averaging, long& inconsistent) {
    const auto idx = bb::multi_indices<Q>();
    std::map<IVec3, std::vector<std::array<int, 2>>> owners;
    for (int t = 0; t < 24; ++t)
        for (int n = 0; n < bb::coefficient_count(Q); ++n) owners[bb::scaled_domain_point(idx[n], tet_vertices(t))].push_back({t, n});
    std::map<IVec3, std::array<Rational, 27>> m;
    for (int s = 0; s < 27; ++s) {
        const Stencil<Rational> f = unit_stencil(s);
        const DeterminingSet<Rational, Q> d = determining_set_from_stencil<Q>(f);
        std::array<Tet<Q>, 24> c{};
        for (int t = 0; t < 24; ++t) c[t] = averaging ? tet_from_determining_set<Q>(d, t) : tet_from_stencil<Q>(f, t);
        for (const auto& [p, own] : owners) {
            const Rational w = c[own[0][0]][own[0][1]];
            m[p][s] = w;
            for (const auto& o : own) inconsistent += c[o[0]][o[1]] != w;
        }
    }
    return m;
}

/// A 2x2x2 block of cubes with random integer data on the 4x4x4 grid around it.
template <int Q>
struct Block {
    std::array<std::array<Tet<Q>, 24>, 8> tets;
    static IVec3 offset(int c) { return {(c >> 2) & 1, (c >> 1) & 1, c & 1}; }
    explicit Block(unsigned seed) {
        std::mt19937 rng(seed);
        std::uniform_int_distribution<int> u(-1000, 1000);
        Rational data[4][4][4];
        for (auto& a : data)
            for (auto& b : a)
                for (auto& x : b) x = Rational(u(rng));
        for (int c = 0; c < 8; ++c) {
            const IVec3 o = offset(c);
            Stencil<Rational> f{};
            for (int s = 0; s < 27; ++s) {
                const IVec3 st = stencil_offset(s);
                f[s] = data[o[0] + st[0] + 1][o[1] + st[1] + 1][o[2] + st[2] + 1];
            }
            const DeterminingSet<Rational, Q> d = determining_set_from_stencil<Q>(f);
            for (int t = 0; t < 24; ++t) tets[c][t] = tet_from_determining_set<Q>(d, t);
        }
    }
    /// Global vertex m of tetrahedron t of cube c (local units, cube c centred at 2·offset).
    static IVec3 vertex(int c, int t, int m) {
        const IVec3 v = tet_vertices(t)[m], o = offset(c);
        return {v[0] + 2 * o[0], v[1] + 2 * o[1], v[2] + 2 * o[2]};
    }
};

/// Shared coefficients in the block: number of comparisons (k-1 per point shared by k cubes)
/// and mismatches.
template <int Q>
std::array<long, 2> block_sharing(const Block<Q>& b) {
    std::map<IVec3, std::map<int, Rational>> pts;  // global q·ξ -> cube -> value
    const auto idx = bb::multi_indices<Q>();
    long within = 0;
    for (int c = 0; c < 8; ++c)
        for (int t = 0; t < 24; ++t)
            for (int n = 0; n < bb::coefficient_count(Q); ++n) {
                std::array<IVec3, 4> v{};
                for (int m = 0; m < 4; ++m) v[m] = Block<Q>::vertex(c, t, m);
                const IVec3 p = bb::scaled_domain_point(idx[n], v);
                auto& per_cube = pts[p];
                auto it = per_cube.find(c);
                if (it == per_cube.end()) per_cube[c] = b.tets[c][t][n];
                else if (it->second != b.tets[c][t][n]) ++within;
            }
    long compared = 0, mismatched = within;
    for (const auto& [p, per_cube] : pts) {
        if (per_cube.size() < 2) continue;
        const Rational first = per_cube.begin()->second;
        for (const auto& [c, v] : per_cube) {
            if (c == per_cube.begin()->first) continue;
            ++compared;
            if (v != first) ++mismatched;
        }
    }
    return {compared, mismatched};
}

/// C1 conditions across every triangle shared by two tetrahedra of the block: for the piece
/// T and the neighbour T' with opposite vertex w', c'_{β + w'} = Σ_m λ_m(w') c_{β+e_m} for every
/// face multi-index β of degree q-1. Returns {conditions, violated, violated across cube faces}.
template <int Q>
std::array<long, 3> block_c1(const Block<Q>& b) {
    const auto idx = bb::multi_indices<Q>();
    const auto low = bb::multi_indices<Q - 1>();
    long conditions = 0, violated = 0, violated_faces = 0;
    for (int c1 = 0; c1 < 8; ++c1)
        for (int t1 = 0; t1 < 24; ++t1)
            for (int c2 = 0; c2 < 8; ++c2)
                for (int t2 = 0; t2 < 24; ++t2) {
                    if (c2 * 24 + t2 <= c1 * 24 + t1) continue;
                    std::array<IVec3, 4> v1{}, v2{};
                    for (int m = 0; m < 4; ++m) {
                        v1[m] = Block<Q>::vertex(c1, t1, m);
                        v2[m] = Block<Q>::vertex(c2, t2, m);
                    }
                    int shared = 0, opp1 = -1, opp2 = -1;
                    for (int m = 0; m < 4; ++m) {
                        bool in2 = false, in1 = false;
                        for (int k = 0; k < 4; ++k) {
                            in2 = in2 || v1[m] == v2[k];
                            in1 = in1 || v2[m] == v1[k];
                        }
                        if (in2) ++shared;
                        else opp1 = m;
                        if (!in1) opp2 = m;
                    }
                    if (shared != 3) continue;
                    // barycentric coordinates of w' = v2[opp2] w.r.t. T (exact)
                    const IVec3 o1 = Block<Q>::offset(c1);
                    const Vec<Rational, 3> u = {{Rational(v2[opp2][0] - 2 * o1[0]), Rational(v2[opp2][1] - 2 * o1[1]),
                                                 Rational(v2[opp2][2] - 2 * o1[2])}};
                    const Vec<Rational, 4> lam = barycentric(t1, u);
                    const auto step = bb::de_casteljau_step(b.tets[c1][t1], lam);
                    for (int n = 0; n < bb::coefficient_count(Q - 1); ++n) {
                        if (low[n][opp1] != 0) continue;
                        // domain point of β shifted by w'
                        IVec3 p{};
                        for (int a = 0; a < 3; ++a) {
                            p[a] = v2[opp2][a];
                            for (int m = 0; m < 4; ++m) p[a] += low[n][m] * v1[m][a];
                        }
                        int n2 = -1;
                        for (int k = 0; k < bb::coefficient_count(Q); ++k)
                            if (bb::scaled_domain_point(idx[k], v2) == p) n2 = k;
                        REQUIRE(n2 >= 0);
                        ++conditions;
                        if (step[n] != b.tets[c2][t2][n2]) {
                            ++violated;
                            if (c1 != c2) ++violated_faces;
                        }
                    }
                }
    return {conditions, violated, violated_faces};
}

/// The blossom of p(u) = uᵀAu + bᵀu + c (degree <= 2) as a polynomial of degree Q, at the
/// vertices with multiplicities α: (2/(Q(Q-1))) Σ_{i<j} x_iᵀ A x_j + (1/Q) Σ bᵀx_i + c.
template <int Q>
Rational blossom_quadratic(const int A[3][3], const int bvec[3], int c0, const bb::MultiIndex& alpha,
                           const std::array<IVec3, 4>& v) {
    std::vector<IVec3> args;
    for (int m = 0; m < 4; ++m)
        for (int r = 0; r < alpha[m]; ++r) args.push_back(v[m]);
    Rational quad(0), lin(0);
    for (int i = 0; i < Q; ++i) {
        for (int a = 0; a < 3; ++a) lin = lin + Rational(bvec[a] * args[i][a]);
        for (int j = i + 1; j < Q; ++j)
            for (int a = 0; a < 3; ++a)
                for (int k = 0; k < 3; ++k) quad = quad + Rational(args[i][a] * A[a][k] * args[j][k]);
    }
    return Rational(2) * quad / Rational(Q * (Q - 1)) + lin / Rational(Q) + Rational(c0);
}

template <int Q>
void check_scheme(const char* name, int expect_points, std::array<long, 2> expect_sharing, std::array<long, 3> expect_c1,
                  Rational expect_norm) {
    // Averaging (D-set + rules) == direct masks, for all 24 tetrahedra, on unit and random data.
    long mismatches = 0;
    std::mt19937 rng(Q * 1000);
    for (int s = 0; s < 27 + 20; ++s) {
        const Stencil<Rational> f = s < 27 ? unit_stencil(s) : random_stencil(rng);
        const DeterminingSet<Rational, Q> d = determining_set_from_stencil<Q>(f);
        for (int t = 0; t < 24; ++t) {
            const Tet<Q> a = tet_from_determining_set<Q>(d, t), b = tet_from_stencil<Q>(f, t);
            for (int n = 0; n < a.size; ++n) mismatches += a[n] != b[n];
        }
    }
    CHECK(mismatches == 0);

    // Per-cube masks: consistent between tetrahedra, 65/175 points, both paths equal, cube
    // coefficients equal, invariant under the 48 symmetries.
    long inconsistent_avg = 0, inconsistent_dir = 0;
    const auto mavg = cube_masks<Q>(true, inconsistent_avg);
    const auto mdir = cube_masks<Q>(false, inconsistent_dir);
    CHECK(inconsistent_avg == 0);
    CHECK(inconsistent_dir == 0);
    CHECK(static_cast<int>(mavg.size()) == expect_points);
    CHECK(mavg == mdir);
    long cube_mismatch = 0;
    for (int s = 0; s < 27; ++s) {
        const auto cc = cube_coefficients<Q>(determining_set_from_stencil<Q>(unit_stencil(s)));
        for (int n = 0; n < cube_point_count(Q); ++n) cube_mismatch += mavg.at(cc.point[n])[s] != cc.value[n];
    }
    CHECK(cube_mismatch == 0);
    long asym = 0;
    for (const IMat3& S : cube_symmetries()) {
        for (const auto& [p, w] : mavg) {
            const auto& ws = mavg.at(mat_apply(S, p));
            for (int s = 0; s < 27; ++s) asym += ws[stencil_index(mat_apply(S, stencil_offset(s)))] != w[s];
        }
        for (int k = 0; k < d_count(Q); ++k) {
            const DataMask a = d_mask(Q, k), b = d_mask(Q, d_index(Q, mat_apply(S, d_point(Q, k))));
            for (int i = 0; i < a.count; ++i) {
                const int si = stencil_index(mat_apply(S, stencil_offset(a.stencil[i])));
                int wb = 0;
                for (int j = 0; j < b.count; ++j)
                    if (b.stencil[j] == si) wb = b.weight[j];
                asym += wb != a.weight[i];
            }
        }
    }
    CHECK(asym == 0);

    // Weights: sums, operator norm, signs.
    Rational norm(0), most_negative(0);
    long negative_weights = 0;
    for (const auto& [p, w] : mavg) {
        Rational sum(0), abs_sum(0), neg(0);
        for (const Rational& x : w) {
            sum = sum + x;
            abs_sum = abs_sum + qtest::abs(x);
            if (x < Rational(0)) {
                neg = neg + x;
                ++negative_weights;
            }
        }
        CHECK(sum == Rational(1));
        if (norm < abs_sum) norm = abs_sum;
        if (neg < most_negative) most_negative = neg;
    }
    CHECK(norm == expect_norm);

    // 2x2x2 block: shared coefficients and C1 conditions.
    const Block<Q> block(4242);
    const auto sharing = block_sharing(block);
    const auto c1 = block_c1(block);
    CHECK(sharing[0] == expect_sharing[0]);
    CHECK(sharing[1] == expect_sharing[1]);
    CHECK(c1[0] == expect_c1[0]);
    CHECK(c1[1] == expect_c1[1]);
    CHECK(c1[2] == expect_c1[2]);

    // Reproduction: linear exact; quadratic p -> p + (h²/8)Δp, local units h = 2: shift tr(A)·1.
    long repro_bad = 0;
    Rational x2_shift(0);
    for (int it = 0; it < 12; ++it) {
        std::mt19937 r(777 + it);
        std::uniform_int_distribution<int> u(-5, 5);
        int A[3][3], bv[3], c0 = u(r);
        for (int a = 0; a < 3; ++a) {
            bv[a] = u(r);
            for (int k = a; k < 3; ++k) A[a][k] = A[k][a] = it < 4 ? 0 : u(r);
        }
        if (it == 4) {  // p = x²
            for (auto& row : A)
                for (int& x : row) x = 0;
            A[0][0] = 1;
            bv[0] = bv[1] = bv[2] = 0;
            c0 = 0;
        }
        const int trace = A[0][0] + A[1][1] + A[2][2];
        Stencil<Rational> f{};
        for (int s = 0; s < 27; ++s) {
            const IVec3 o = stencil_offset(s);
            int val = c0;
            for (int a = 0; a < 3; ++a) {
                val += bv[a] * 2 * o[a];
                for (int k = 0; k < 3; ++k) val += 2 * o[a] * A[a][k] * 2 * o[k];
            }
            f[s] = Rational(val);
        }
        const DeterminingSet<Rational, Q> d = determining_set_from_stencil<Q>(f);
        const auto idx = bb::multi_indices<Q>();
        for (int t = 0; t < 24; ++t) {
            const Tet<Q> c = tet_from_determining_set<Q>(d, t);
            for (int n = 0; n < c.size; ++n) {
                const Rational expect = blossom_quadratic<Q>(A, bv, c0 + trace, idx[n], tet_vertices(t));
                repro_bad += c[n] != expect;
                if (it == 4 && t == 0 && n == 0)
                    x2_shift = c[n] - blossom_quadratic<Q>(A, bv, c0, idx[n], tet_vertices(t));
            }
        }
    }
    CHECK(repro_bad == 0);
    CHECK(x2_shift == Rational(1));
    std::printf("%s (exact): %zu distinct points per cube; averaging == direct masks for 24 tets (mismatches %ld); "
                "masks invariant under 48 symmetries (violations %ld); operator norm %lld/%lld; negative weights %ld "
                "(most negative sum per mask %lld/%lld);\n    2x2x2 block: shared coefficients compared %ld, mismatches %ld; "
                "C1 conditions %ld, violated %ld (across cube faces %ld); linear/quadratic reproduction "
                "(p + h²Δp/8) failures %ld; x² coefficient shift %lld/%lld (local units)\n",
                name, mavg.size(), mismatches, asym, static_cast<long long>(norm.n), static_cast<long long>(norm.d), negative_weights,
                static_cast<long long>(most_negative.n), static_cast<long long>(most_negative.d), sharing[0], sharing[1], c1[0], c1[1],
                c1[2], repro_bad, static_cast<long long>(x2_shift.n), static_cast<long long>(x2_shift.d));
}

}  // namespace

TEST_CASE("QSS in exact arithmetic reproduces the verification figures of the spec") {
    // spec §6: 65 points; block 139 / 0; C1 1008 / 288, none across cube faces; norm 9/8.
    check_scheme<2>("QSS", 65, {139, 0}, {1008, 288, 0}, Rational(9) / Rational(8));
}

TEST_CASE("S31 in exact arithmetic reproduces the verification figures of the spec") {
    // spec §6: 175 points; block 277 / 0; C1 2016 / 0; norm 1 (all weights >= 0).
    check_scheme<3>("S31", 175, {277, 0}, {2016, 0, 0}, Rational(1));
}

TEST_CASE("constant data give constant coefficients in both schemes") {
    Stencil<Rational> f{};
    for (int s = 0; s < 27; ++s) f[s] = Rational(1);
    const auto d2 = determining_set_from_stencil<2>(f);
    const auto d3 = determining_set_from_stencil<3>(f);
    for (int t = 0; t < 24; ++t) {
        const auto a = tet_from_determining_set<2>(d2, t);
        const auto b = tet_from_determining_set<3>(d3, t);
        for (int n = 0; n < a.size; ++n) CHECK(a[n] == Rational(1));
        for (int n = 0; n < b.size; ++n) CHECK(b[n] == Rational(1));
    }
}

TEST_CASE("the S31 determining-set masks satisfy the relations of a C1 cubic on the split cube") {
    // D3 has 56 values but the C1 splines on one cube form a 52-dimensional space (spec §3.2):
    // every single-condition form of a rule must give the same coefficient as the averaged one.
    // S0.1: b(v_Q) = b((2v_Q+F1)/3) + b((2v_Q+F2)/3) - ½[b((2v_Q+v)/3) + b((2v_Q+w)/3)] for every edge.
    std::mt19937 rng(99);
    for (int it = 0; it < 5; ++it) {
        const auto f = random_stencil(rng);
        const auto cc = cube_coefficients<3>(determining_set_from_stencil<3>(f));
        std::map<IVec3, Rational> val;
        for (int n = 0; n < cube_point_count(3); ++n) val[cc.point[n]] = cc.value[n];
        for (int e = 0; e < 12; ++e) {
            const IVec3 v = vertex_of(cube_tables.edge_vertices[e][0]), w = vertex_of(cube_tables.edge_vertices[e][1]);
            const auto faces = edge_faces(e);
            const Rational rhs = val.at(face_normal(faces[0])) + val.at(face_normal(faces[1])) -
                                 Rational(1) / Rational(2) * (val.at(v) + val.at(w));
            CHECK(val.at({0, 0, 0}) == rhs);
        }
    }
}
