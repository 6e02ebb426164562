// quadcast/spline/masks.hpp -- determining sets D2/D3, their data masks, and the masks of every coefficient
#pragma once

#include <array>

#include "quadcast/bb/multi_index.hpp"
#include "quadcast/spline/partition.hpp"

namespace quadcast::spline {

/// Spline degree of the two schemes: QSS (quadratic super splines) and S31 (cubic C1).
inline constexpr int qss = 2;
inline constexpr int s31 = 3;

/// |x| for ints, usable in constant expressions.
constexpr int iabs(int x) { return x < 0 ? -x : x; }

/// Size of the 27-point data stencil of a cube.
inline constexpr int stencil_size = 27;

/// Number of values in the determining set per cube: 20 (D2) or 56 (D3) (spec §1.4).
constexpr int d_count(int q) { return q == 2 ? 20 : 56; }

/// Flat index of stencil offset (a,b,c) ∈ {-1,0,1}^3: 9(a+1) + 3(b+1) + (c+1) (spec §1.1).
constexpr int stencil_index(const IVec3& s) { return 9 * (s[0] + 1) + 3 * (s[1] + 1) + (s[2] + 1); }
/// Inverse of `stencil_index`.
constexpr IVec3 stencil_offset(int n) { return {n / 9 - 1, (n / 3) % 3 - 1, n % 3 - 1}; }

// ---- Cube geometry shared by the rules --------------------------------------------------------
//
// Vertices are numbered 4·[x>0] + 2·[y>0] + [z>0]. The 12 cube edges are numbered by their axis
// e (x edges 0..3, y edges 4..7, z edges 8..11); within an axis by the signs of the two other
// coordinates (p, r) (axes in increasing order): (-,-), (-,+), (+,-), (+,+). Edge n runs from
// its vertex with coordinate -1 along e ("lo") to the one with +1 ("hi").

/// Vertex number of the cube vertex v ∈ {±1}^3.
constexpr int vertex_number(const IVec3& v) { return 4 * (v[0] > 0) + 2 * (v[1] > 0) + (v[2] > 0); }
/// Cube vertex of vertex number n.
constexpr IVec3 vertex_of(int n) { return {(n & 4) ? 1 : -1, (n & 2) ? 1 : -1, (n & 1) ? 1 : -1}; }

/// Axis of cube edge n.
constexpr int edge_axis(int n) { return n / 4; }
/// The two vertex numbers (lo, hi) of cube edge n.
constexpr std::array<int, 2> edge_vertices(int n) {
    const int e = n / 4, p = (e + 1) % 3 < (e + 2) % 3 ? (e + 1) % 3 : (e + 2) % 3;
    const int r = 3 - e - p;
    IVec3 lo{}, hi{};
    lo[p] = hi[p] = (n & 2) ? 1 : -1;
    lo[r] = hi[r] = (n & 1) ? 1 : -1;
    lo[e] = -1;
    hi[e] = 1;
    return {vertex_number(lo), vertex_number(hi)};
}
/// The cube edge joining vertex numbers v and w (-1 if they are not adjacent).
constexpr int edge_number(int v, int w) {
    for (int n = 0; n < 12; ++n) {
        const auto e = edge_vertices(n);
        if ((e[0] == v && e[1] == w) || (e[0] == w && e[1] == v)) return n;
    }
    return -1;
}
/// Vertex numbers of face φ in the order ε = 0..3 (`face_vertex`).
constexpr std::array<int, 4> face_vertices(int phi) {
    return {vertex_number(face_vertex(phi, 0)), vertex_number(face_vertex(phi, 1)),
            vertex_number(face_vertex(phi, 2)), vertex_number(face_vertex(phi, 3))};
}
/// The three edges at vertex v, in axis order x, y, z.
constexpr std::array<int, 3> vertex_edges(int v) {
    std::array<int, 3> r{};
    for (int n = 0; n < 12; ++n) {
        const auto e = edge_vertices(n);
        if (e[0] == v || e[1] == v) r[edge_axis(n)] = n;
    }
    return r;
}
/// The two faces containing cube edge n: first the one normal to the smaller other axis.
constexpr std::array<int, 2> edge_faces(int n) {
    const IVec3 v = vertex_of(edge_vertices(n)[0]);
    const int e = edge_axis(n);
    std::array<int, 2> r{};
    int k = 0;
    for (int a = 0; a < 3; ++a)
        if (a != e) r[k++] = 2 * a + (v[a] > 0 ? 0 : 1);
    return r;
}
/// Position ε of vertex number v in face φ (-1 if not in the face).
constexpr int face_position(int phi, int v) {
    const auto f = face_vertices(phi);
    for (int e = 0; e < 4; ++e)
        if (f[e] == v) return e;
    return -1;
}
/// The triangle [F_φ, vertex ε, vertex ε+1] of face φ containing cube edge [v, w]: its number
/// 4φ + ε is the tetrahedron having it as outer face.
constexpr int face_triangle(int phi, int v, int w) {
    const auto f = face_vertices(phi);
    for (int e = 0; e < 4; ++e)
        if ((f[e] == v && f[(e + 1) % 4] == w) || (f[e] == w && f[(e + 1) % 4] == v)) return 4 * phi + e;
    return -1;
}

// ---- Determining sets (spec §1.4) -----------------------------------------------------------
//
// Storage order per cube (our convention; the paper's texture layout is not legible):
//   D2 (20): 8 vertices (vertex numbers), then the 12 edge midpoints (edge numbers).
//   D3 (56): 8 vertices; then 24 edge points, 2 per edge: 8 + 2n is e(lo->hi) = (2lo+hi)/3,
//            8 + 2n + 1 is e(hi->lo); then 24 face-triangle points: 32 + t is the centroid
//            (F+v+w)/3 of the outer face of tetrahedron t.

/// The determining-set point k of degree q as the integer vector q·ξ (cube-local).
constexpr IVec3 d_point(int q, int k) {
    if (k < 8) {
        const IVec3 v = vertex_of(k);
        return {q * v[0], q * v[1], q * v[2]};
    }
    if (q == 2) {
        const auto e = edge_vertices(k - 8);
        const IVec3 a = vertex_of(e[0]), b = vertex_of(e[1]);
        return {a[0] + b[0], a[1] + b[1], a[2] + b[2]};
    }
    if (k < 32) {
        const auto e = edge_vertices((k - 8) / 2);
        const IVec3 a = vertex_of(e[(k - 8) % 2]), b = vertex_of(e[1 - (k - 8) % 2]);
        return {2 * a[0] + b[0], 2 * a[1] + b[1], 2 * a[2] + b[2]};
    }
    const auto v = tet_vertices(k - 32);
    return {v[1][0] + v[2][0] + v[3][0], v[1][1] + v[2][1] + v[3][1], v[1][2] + v[2][2] + v[3][2]};
}

/// Index of the determining-set point with q·ξ = p (-1 if p is not in D_q). Computed from the
/// coordinates (no search, so the permutation tables stay cheap constant expressions).
constexpr int d_index(int q, const IVec3& p) {
    int full = 0, zero = 0;
    for (int a = 0; a < 3; ++a) {
        full += iabs(p[a]) == q;
        zero += p[a] == 0;
    }
    int k = -1;
    auto edge = [&](int e) {  // cube edge along axis e through the other two coordinates
        const int a = (e + 1) % 3 < (e + 2) % 3 ? (e + 1) % 3 : (e + 2) % 3, b = 3 - e - a;
        return 4 * e + 2 * (p[a] > 0) + (p[b] > 0);
    };
    if (full == 3) {
        k = 4 * (p[0] > 0) + 2 * (p[1] > 0) + (p[2] > 0);
    } else if (full == 2) {
        int e = 0;
        while (iabs(p[e]) == q) ++e;
        k = q == 2 ? 8 + edge(e) : 8 + 2 * edge(e) + (p[e] > 0);
    } else if (q == 3 && full == 1 && zero == 1) {
        int a = 0;
        while (iabs(p[a]) != 3) ++a;
        const int s = p[a] > 0 ? 1 : -1;
        const int b = s > 0 ? (a + 1) % 3 : (a + 2) % 3, c = s > 0 ? (a + 2) % 3 : (a + 1) % 3;
        const int eps = p[c] == -2 ? 0 : p[b] == 2 ? 1 : p[c] == 2 ? 2 : 3;
        k = 32 + 4 * (2 * a + (s < 0)) + eps;
    }
    return (k >= 0 && k < d_count(q) && d_point(q, k) == p) ? k : -1;
}

/// D-index of the S31 edge point e(v->w) = (2v+w)/3 for adjacent vertex numbers v, w.
constexpr int d3_edge_point(int v, int w) {
    const int n = edge_number(v, w);
    return 8 + 2 * n + (edge_vertices(n)[0] == v ? 0 : 1);
}

/// One data mask: `count` terms (stencil index, integer weight), value = Σ weight·f / denominator.
/// Terms are sorted by stencil index, i.e. lexicographically by offset, so a point shared by
/// several cubes sums the same data in the same order in each of them (bit-identical values).
struct DataMask {
    int count = 0;
    std::array<int, 12> stencil{};
    std::array<int, 12> weight{};
};

/// Common denominator of the D masks: 8 for D2 (weights 1/8, 1/4), 192 for D3
/// (1/8, 5/24, 1/24, 13/48, 7/48, 1/32, 1/96).
constexpr int d_mask_denominator(int q) { return q == 2 ? 8 : 192; }

/// The data mask of determining-set point k (spec §2.1 for q = 2, §3.1 for q = 3; A_m(ξ) =
/// {0, sgn ξ_m} where |ξ_m| = 1, else {0}).
constexpr DataMask d_mask(int q, int k) {
    int w[27] = {};
    const IVec3 p = d_point(q, k);
    auto sgn = [](int x) { return x > 0 ? 1 : (x < 0 ? -1 : 0); };
    auto layers = [&](int a) {  // A_a as (count, values)
        return std::array<int, 3>{iabs(p[a]) == q ? 2 : 1, 0, sgn(p[a])};
    };
    auto add = [&](IVec3 s, int weight) { w[stencil_index(s)] += weight; };
    const int nfull = (iabs(p[0]) == q) + (iabs(p[1]) == q) + (iabs(p[2]) == q);
    if (nfull == 3) {
        // Cube vertex: mean of the 8 cubes sharing it.
        const int wt = q == 2 ? 1 : 24;
        for (int a = 0; a < 2; ++a)
            for (int b = 0; b < 2; ++b)
                for (int c = 0; c < 2; ++c) add({a * sgn(p[0]), b * sgn(p[1]), c * sgn(p[2])}, wt);
    } else if (nfull == 2) {
        // Cube-edge point: axis e along the edge.
        int e = 0;
        while (iabs(p[e]) == q) ++e;
        const int i = (e + 1) % 3, j = (e + 2) % 3;
        const auto ai = layers(i), aj = layers(j);
        for (int x = 0; x < 2; ++x)
            for (int y = 0; y < 2; ++y) {
                IVec3 s{};
                s[i] = x * ai[2];
                s[j] = y * aj[2];
                if (q == 2) {
                    s[e] = 0;
                    add(s, 2);  // 1/4
                } else {
                    s[e] = 0;
                    add(s, 40);  // 5/24
                    s[e] = sgn(p[e]);
                    add(s, 8);  // 1/24
                }
            }
    } else {
        // Face-triangle point (q = 3): normal axis n (ξ_n = s), in-face axis t (ξ_t = 2τ/3)
        // towards the triangle's cube edge, axis e along that edge (ξ_e = 0).
        int n = 0;
        while (iabs(p[n]) != q) ++n;
        int t = 0;
        while (t == n || p[t] == 0) ++t;
        const int e = 3 - n - t;
        const int s = sgn(p[n]), tau = sgn(p[t]);
        for (int an = 0; an < 2; ++an) {
            auto at = [&](int ta, int ea) {
                IVec3 o{};
                o[n] = an * s;
                o[t] = ta;
                o[e] = ea;
                return o;
            };
            add(at(0, 0), 52);    // 13/48
            add(at(tau, 0), 28);  // 7/48
            add(at(0, 1), 6);     // 1/32
            add(at(0, -1), 6);
            add(at(tau, 1), 2);  // 1/96
            add(at(tau, -1), 2);
        }
    }
    DataMask m{};
    for (int i = 0; i < 27; ++i) {
        if (w[i] != 0) {
            m.stencil[m.count] = i;
            m.weight[m.count] = w[i];
            ++m.count;
        }
    }
    return m;
}

/// All D masks of degree q.
template <int Q>
constexpr std::array<DataMask, d_count(Q)> d_masks() {
    std::array<DataMask, d_count(Q)> r{};
    for (int k = 0; k < d_count(Q); ++k) r[k] = d_mask(Q, k);
    return r;
}

// ---- Masks of every coefficient of T_0 (direct path, spec §2.3 / §3.3) ----------------------

/// Common denominator of the coefficient masks: 128 (QSS) and 192 (S31).
constexpr int coefficient_mask_denominator(int q) { return q == 2 ? 128 : 192; }

/// Mask numerators of the 10 QSS coefficients of T_0 (storage order of bb::multi_indices<2>),
/// over 128; column = flat stencil index. Transcribed mechanically from spec §2.3.
inline constexpr int qss_tet0_masks[10][27] = {
    {-1, 2, -1, 2, 12, 2, -1, 2, -1, 2, 12, 2, 12, 40, 12, 2, 12, 2, -1, 2, -1, 2, 12, 2, -1, 2, -1},  // c2000
    {0, 0, 0, 0, 0, 0, 0, 0, 0, 2, 12, 2, 12, 40, 12, 2, 12, 2, -2, 4, -2, 4, 24, 4, -2, 4, -2},      // c1100
    {0, 0, 0, 0, 0, 0, 0, 0, 0, 8, 24, 0, 24, 40, 0, 0, 0, 0, -8, 8, 0, 8, 24, 0, 0, 0, 0},           // c1010
    {0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 24, 40, 0, 8, 24, 0, 0, 0, 0, 8, 24, 0, -8, 8, 0},           // c1001
    {0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 8, 0, 8, 32, 8, 0, 8, 0, 0, 8, 0, 8, 32, 8, 0, 8, 0},              // c0200
    {0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 16, 0, 16, 32, 0, 0, 0, 0, 0, 16, 0, 16, 32, 0, 0, 0, 0},          // c0110
    {0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 16, 32, 0, 0, 16, 0, 0, 0, 0, 16, 32, 0, 0, 16, 0},          // c0101
    {0, 0, 0, 0, 0, 0, 0, 0, 0, 16, 16, 0, 16, 16, 0, 0, 0, 0, 16, 16, 0, 16, 16, 0, 0, 0, 0},        // c0020
    {0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 32, 32, 0, 0, 0, 0, 0, 0, 0, 32, 32, 0, 0, 0, 0},            // c0011
    {0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 16, 16, 0, 16, 16, 0, 0, 0, 0, 16, 16, 0, 16, 16, 0},        // c0002
};

/// Mask numerators of the 20 S31 coefficients of T_0, over 192; transcribed mechanically from
/// spec §3.3.
inline constexpr int s31_tet0_masks[20][27] = {
    {0, 2, 0, 2, 16, 2, 0, 2, 0, 2, 16, 2, 16, 72, 16, 2, 16, 2, 0, 2, 0, 2, 16, 2, 0, 2, 0},     // c3000
    {0, 1, 0, 1, 4, 1, 0, 1, 0, 2, 16, 2, 16, 72, 16, 2, 16, 2, 0, 3, 0, 3, 28, 3, 0, 3, 0},      // c2100
    {0, 2, 0, 2, 4, 0, 0, 0, 0, 4, 28, 2, 28, 72, 4, 2, 4, 0, 0, 4, 0, 4, 28, 2, 0, 2, 0},        // c2010
    {0, 0, 0, 2, 4, 0, 0, 2, 0, 2, 4, 0, 28, 72, 4, 4, 28, 2, 0, 2, 0, 4, 28, 2, 0, 4, 0},        // c2001
    {0, 0, 0, 0, 0, 0, 0, 0, 0, 2, 14, 2, 14, 64, 14, 2, 14, 2, 0, 6, 0, 6, 40, 6, 0, 6, 0},      // c1200
    {0, 0, 0, 0, 0, 0, 0, 0, 0, 4, 24, 2, 24, 64, 4, 2, 4, 0, 0, 10, 0, 10, 40, 2, 0, 2, 0},      // c1110
    {0, 0, 0, 0, 0, 0, 0, 0, 0, 2, 4, 0, 24, 64, 4, 4, 24, 2, 0, 2, 0, 10, 40, 2, 0, 10, 0},      // c1101
    {0, 0, 0, 0, 0, 0, 0, 0, 0, 16, 32, 0, 32, 48, 0, 0, 0, 0, 0, 16, 0, 16, 32, 0, 0, 0, 0},     // c1020
    {0, 0, 0, 0, 0, 0, 0, 0, 0, 4, 8, 0, 40, 64, 0, 4, 8, 0, 0, 4, 0, 16, 40, 0, 0, 4, 0},        // c1011
    {0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 32, 48, 0, 16, 32, 0, 0, 0, 0, 16, 32, 0, 0, 16, 0},     // c1002
    {0, 0, 0, 0, 0, 0, 0, 0, 0, 1, 10, 1, 10, 52, 10, 1, 10, 1, 1, 10, 1, 10, 52, 10, 1, 10, 1},  // c0300
    {0, 0, 0, 0, 0, 0, 0, 0, 0, 2, 17, 1, 17, 52, 3, 1, 3, 0, 2, 17, 1, 17, 52, 3, 1, 3, 0},      // c0210
    {0, 0, 0, 0, 0, 0, 0, 0, 0, 1, 3, 0, 17, 52, 3, 2, 17, 1, 1, 3, 0, 17, 52, 3, 2, 17, 1},      // c0201
    {0, 0, 0, 0, 0, 0, 0, 0, 0, 8, 24, 0, 24, 40, 0, 0, 0, 0, 8, 24, 0, 24, 40, 0, 0, 0, 0},      // c0120
    {0, 0, 0, 0, 0, 0, 0, 0, 0, 2, 6, 0, 28, 52, 0, 2, 6, 0, 2, 6, 0, 28, 52, 0, 2, 6, 0},        // c0111
    {0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 24, 40, 0, 8, 24, 0, 0, 0, 0, 24, 40, 0, 8, 24, 0},      // c0102
    {0, 0, 0, 0, 0, 0, 0, 0, 0, 24, 24, 0, 24, 24, 0, 0, 0, 0, 24, 24, 0, 24, 24, 0, 0, 0, 0},    // c0030
    {0, 0, 0, 0, 0, 0, 0, 0, 0, 8, 8, 0, 40, 40, 0, 0, 0, 0, 8, 8, 0, 40, 40, 0, 0, 0, 0},        // c0021
    {0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 40, 40, 0, 8, 8, 0, 0, 0, 0, 40, 40, 0, 8, 8, 0},        // c0012
    {0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 24, 24, 0, 24, 24, 0, 0, 0, 0, 24, 24, 0, 24, 24, 0},    // c0003
};

/// Mask numerator of coefficient n of T_0 at flat stencil index s.
template <int Q>
constexpr int tet0_mask(int n, int s) {
    if constexpr (Q == 2) return qss_tet0_masks[n][s];
    else return s31_tet0_masks[n][s];
}

// ---- Rotations of the cube data into the frame of T_0 ----------------------------------------

/// perm[t][k] = index of the determining-set point R_t ξ_k: for tetrahedron t, the rules of T_0
/// applied to d_rot[k] = d[perm[t][k]] give its coefficients (c^(t) uses b[R_t ξ], spec §2.4).
template <int Q>
constexpr std::array<std::array<int, d_count(Q)>, tets_per_cube> d_permutations() {
    std::array<std::array<int, d_count(Q)>, tets_per_cube> r{};
    std::array<IVec3, d_count(Q)> pts{};
    for (int k = 0; k < d_count(Q); ++k) pts[k] = d_point(Q, k);
    for (int t = 0; t < tets_per_cube; ++t) {
        const IMat3 rt = rotation(t);
        for (int k = 0; k < d_count(Q); ++k) r[t][k] = d_index(Q, mat_apply(rt, pts[k]));
    }
    return r;
}

/// perm[t][s] = flat index of R_t·offset(s): f_rot[s] = f[perm[t][s]] (spec §1.2:
/// c^(t) = Σ_s W^(0)(s) f[R_t s]).
constexpr std::array<std::array<int, stencil_size>, tets_per_cube> stencil_permutations() {
    std::array<std::array<int, stencil_size>, tets_per_cube> r{};
    for (int t = 0; t < tets_per_cube; ++t) {
        const IMat3 rt = rotation(t);
        for (int s = 0; s < stencil_size; ++s) r[t][s] = stencil_index(mat_apply(rt, stencil_offset(s)));
    }
    return r;
}

}  // namespace quadcast::spline
