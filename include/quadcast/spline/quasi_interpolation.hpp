// quadcast/spline/quasi_interpolation.hpp -- QSS / S31 coefficients: D-sets from data, repeated averaging, direct masks
#pragma once

#include <array>

#include "quadcast/bb/bezier.hpp"
#include "quadcast/linalg.hpp"
#include "quadcast/scalar.hpp"
#include "quadcast/spline/masks.hpp"
#include "quadcast/spline/partition.hpp"

namespace quadcast::spline {

/// The determining-set values of one cube (20 for QSS, 56 for S31), in the order of `d_point`.
template <class T, int Q>
using DeterminingSet = Vec<T, d_count(Q)>;
/// The 27 data values of a cube's stencil, flat index 9(a+1) + 3(b+1) + (c+1).
template <class T>
using Stencil = Vec<T, stencil_size>;

/// Integer tables of the cube used by the averaging rules (see masks.hpp for the numbering).
struct CubeTables {
    int vertex_edges[8][3];     ///< the 3 edges at a vertex, axis order
    int vertex_neighbours[8][3];  ///< the other ends of those edges
    int face_vertices[6][4];    ///< ε order
    int face_edges[6][4];       ///< edge ε joins face vertices ε and ε+1
    int edge_vertices[12][2];   ///< (lo, hi)
    int edge_triangles[12][2];  ///< the two boundary triangles (= tetrahedra) containing the edge
    int edge_point[8][8];       ///< D3 index of e(v->w), -1 if v, w not adjacent
};

constexpr CubeTables make_cube_tables() {
    CubeTables c{};
    for (int v = 0; v < 8; ++v) {
        const auto e = vertex_edges(v);
        for (int a = 0; a < 3; ++a) {
            c.vertex_edges[v][a] = e[a];
            const auto ev = edge_vertices(e[a]);
            c.vertex_neighbours[v][a] = ev[0] == v ? ev[1] : ev[0];
        }
        for (int w = 0; w < 8; ++w) c.edge_point[v][w] = edge_number(v, w) >= 0 ? d3_edge_point(v, w) : -1;
    }
    for (int phi = 0; phi < 6; ++phi) {
        const auto f = face_vertices(phi);
        for (int e = 0; e < 4; ++e) {
            c.face_vertices[phi][e] = f[e];
            c.face_edges[phi][e] = edge_number(f[e], f[(e + 1) % 4]);
        }
    }
    for (int n = 0; n < 12; ++n) {
        const auto ev = edge_vertices(n);
        const auto ef = edge_faces(n);
        c.edge_vertices[n][0] = ev[0];
        c.edge_vertices[n][1] = ev[1];
        for (int i = 0; i < 2; ++i) c.edge_triangles[n][i] = face_triangle(ef[i], ev[0], ev[1]);
    }
    return c;
}

inline constexpr CubeTables cube_tables = make_cube_tables();

// ---- Determining set from data (spec §2.1, §3.1) ----------------------------------------------

/// The determining-set values of a cube from its 27-point stencil (Kalbe & Zeilfelder 2008,
/// Sect. 4 and Fig. 4; masks of spec §2.1 / §3.1).
/// Numerics: value k = (Σ_i T(w_i) * f[s_i]) / T(den), a left fold over the mask's terms in
/// increasing stencil index (so cubes sharing a point compute it bit-identically), then one
/// division by den = 8 (D2) or 192 (D3).
template <int Q, class T>
DeterminingSet<T, Q> determining_set_from_stencil(const Stencil<T>& f) {
    static constexpr auto masks = d_masks<Q>();
    const T den = T(static_cast<double>(d_mask_denominator(Q)));
    DeterminingSet<T, Q> d{};
    for (int k = 0; k < d_count(Q); ++k) {
        const DataMask& m = masks[k];
        T acc = T(static_cast<double>(m.weight[0])) * f[m.stencil[0]];
        for (int i = 1; i < m.count; ++i) acc = acc + T(static_cast<double>(m.weight[i])) * f[m.stencil[i]];
        d[k] = acc / den;
    }
    return d;
}

// ---- Repeated averaging, QSS (spec §2.2, paper Fig. 7 top) -------------------------------------

/// QSS rule Q1.1, the R1 point (v_Q+v)/2 of cube vertex v:
/// ½[b((v+w1)/2) + b((v+w2)/2) + b((v+w3)/2) - b(v)].
/// Numerics: T(0.5) * (((m1 + m2) + m3) - b(v)), edges in axis order.
template <class T>
T qss_rule_q11(const DeterminingSet<T, 2>& d, int v) {
    const auto& e = cube_tables.vertex_edges[v];
    return T(0.5) * (((d[8 + e[0]] + d[8 + e[1]]) + d[8 + e[2]]) - d[v]);
}

/// QSS rule Q2.1, the R2 point (F+v)/2 for the vertex at position ε of face φ:
/// ½[b((v+a)/2) + b((v+c)/2)] with a, c the face vertices at ε+1, ε-1.
/// Numerics: T(0.5) * (m(v,a) + m(v,c)).
template <class T>
T qss_rule_q21(const DeterminingSet<T, 2>& d, int phi, int eps) {
    const auto& fe = cube_tables.face_edges[phi];
    return T(0.5) * (d[8 + fe[eps]] + d[8 + fe[(eps + 3) % 4]]);
}

/// QSS rule Q2.2, the face centre F: ¼ Σ of the 4 edge midpoints of the face.
/// Numerics: T(0.25) * (((m0 + m1) + m2) + m3), edges in ε order.
template <class T>
T qss_rule_q22(const DeterminingSet<T, 2>& d, int phi) {
    const auto& fe = cube_tables.face_edges[phi];
    return T(0.25) * (((d[8 + fe[0]] + d[8 + fe[1]]) + d[8 + fe[2]]) + d[8 + fe[3]]);
}

/// The 10 QSS coefficients of T_0 from the determining set expressed in the frame of T_0
/// (d_rot[k] = d[perm_t[k]] gives tetrahedron t; `rotate_determining_set`), ring by ring:
/// R2 from D2 (Q2.1, Q2.2), then R1 (Q1.1 at the 8 vertices, Q1.2 on face +x), then R0 (Q0.1)
/// (Kalbe & Zeilfelder 2008, Sect. 5.2 and Fig. 7; spec §2.2). Same code for all 24 tetrahedra.
/// Numerics: Q1.2 = T(0.25) * (((r0 + r1) + r2) + r3) over the face vertices in ε order;
/// Q0.1 = T(0.125) * (left fold of the 8 Q1.1 values in vertex-number order).
template <class T>
bb::BezierTet<T, 2> qss_tet0_from_d2(const DeterminingSet<T, 2>& d) {
    constexpr int phi = 0;
    const auto& fv = cube_tables.face_vertices[phi];
    const int v2 = fv[0], v3 = fv[1];
    // Ring R1 at the cube vertices (all 8 are needed by the centre).
    T r1[8];
    for (int v = 0; v < 8; ++v) r1[v] = qss_rule_q11(d, v);
    bb::BezierTet<T, 2> c{};
    // Ring R2 (the cube surface).
    c.at(0, 0, 2) = d[v2];
    c.at(0, 0, 1) = d[8 + cube_tables.face_edges[phi][0]];
    c.at(0, 0, 0) = d[v3];
    c.at(0, 1, 1) = qss_rule_q21(d, phi, 0);
    c.at(0, 1, 0) = qss_rule_q21(d, phi, 1);
    c.at(0, 2, 0) = qss_rule_q22(d, phi);
    // Ring R1.
    c.at(1, 0, 1) = r1[v2];
    c.at(1, 0, 0) = r1[v3];
    c.at(1, 1, 0) = T(0.25) * (((r1[fv[0]] + r1[fv[1]]) + r1[fv[2]]) + r1[fv[3]]);
    // Ring R0.
    T sum = r1[0];
    for (int v = 1; v < 8; ++v) sum = sum + r1[v];
    c.at(2, 0, 0) = T(0.125) * sum;
    return c;
}

// ---- Repeated averaging, S31 (spec §3.2, paper Fig. 7 bottom) ----------------------------------

/// S31 rule S2.1, the R2 point (v_Q+2v)/3: ½[b(e(v→w1)) + b(e(v→w2)) + b(e(v→w3)) - b(v)].
/// Numerics: T(0.5) * (((e1 + e2) + e3) - b(v)), edges in axis order.
template <class T>
T s31_rule_s21(const DeterminingSet<T, 3>& d, int v) {
    const auto& w = cube_tables.vertex_neighbours[v];
    const auto& ep = cube_tables.edge_point[v];
    return T(0.5) * (((d[ep[w[0]]] + d[ep[w[1]]]) + d[ep[w[2]]]) - d[v]);
}

/// S31 rule S2.2, the R2 point (v_Q+v+w)/3 of cube edge n = [v,w]:
/// b(t(F1;v,w)) + b(t(F2;v,w)) - ½[b(e(v→w)) + b(e(w→v))].
/// Numerics: (t1 + t2) - T(0.5) * (e_lo + e_hi).
template <class T>
T s31_rule_s22(const DeterminingSet<T, 3>& d, int n) {
    const auto& tr = cube_tables.edge_triangles[n];
    return (d[32 + tr[0]] + d[32 + tr[1]]) - T(0.5) * (d[8 + 2 * n] + d[8 + 2 * n + 1]);
}

/// S31 rule S1.1 from precomputed S2.2 (per edge) and S2.1 (per vertex) values:
/// ½[Σ_{3 edges at v} b((v_Q+v+w)/3) - b((v_Q+2v)/3)].
/// Numerics: T(0.5) * (((s22[e1] + s22[e2]) + s22[e3]) - s21[v]).
template <class T>
T s31_rule_s11(const T (&s22)[12], const T (&s21)[8], int v) {
    const auto& e = cube_tables.vertex_edges[v];
    return T(0.5) * (((s22[e[0]] + s22[e[1]]) + s22[e[2]]) - s21[v]);
}

/// S31 rule S3.1, the R3 point (2v+F)/3 for the vertex at position ε of face φ:
/// ½[b(e(v→a)) + b(e(v→c))].
template <class T>
T s31_rule_s31(const DeterminingSet<T, 3>& d, int phi, int eps) {
    const auto& fv = cube_tables.face_vertices[phi];
    const int v = fv[eps];
    return T(0.5) * (d[cube_tables.edge_point[v][fv[(eps + 1) % 4]]] + d[cube_tables.edge_point[v][fv[(eps + 3) % 4]]]);
}

/// S31 rule S3.2, the R3 point (2F+v)/3: ½[b(t(F;v,a)) + b(t(F;v,c))] (the triangles ε and ε-1).
template <class T>
T s31_rule_s32(const DeterminingSet<T, 3>& d, int phi, int eps) {
    return T(0.5) * (d[32 + 4 * phi + eps] + d[32 + 4 * phi + (eps + 3) % 4]);
}

/// S31 rule S3.3, the face centre F: ¼ Σ of the 4 face-triangle points.
/// Numerics: T(0.25) * (((t0 + t1) + t2) + t3) in ε order.
template <class T>
T s31_rule_s33(const DeterminingSet<T, 3>& d, int phi) {
    const int b = 32 + 4 * phi;
    return T(0.25) * (((d[b] + d[b + 1]) + d[b + 2]) + d[b + 3]);
}

/// The 20 S31 coefficients of T_0 from the determining set in the frame of T_0, ring by ring:
/// R3 from D3 (S3.1-S3.3), R2 (S2.1 at all vertices, S2.2 at all edges, S2.3, S2.4 on face +x),
/// R1 (S1.1 at all vertices, S1.2 on face +x), R0 (S0.1) (Kalbe & Zeilfelder 2008, Fig. 7;
/// spec §3.2). Same code for all 24 tetrahedra.
/// Numerics: S2.3 = T(0.5) * (s22[va] + s22[vc]); S2.4 = T(0.25) * (((s22[e0] + s22[e1]) + s22[e2]) + s22[e3])
/// (face edges in ε order); S1.2 = T(0.25) * (((s11[f0] + s11[f1]) + s11[f2]) + s11[f3]);
/// S0.1 = T(0.125) * (left fold of the 8 S1.1 values in vertex-number order).
template <class T>
bb::BezierTet<T, 3> s31_tet0_from_d3(const DeterminingSet<T, 3>& d) {
    constexpr int phi = 0;
    const auto& fv = cube_tables.face_vertices[phi];
    const auto& fe = cube_tables.face_edges[phi];
    const int v2 = fv[0], v3 = fv[1];
    // Ring R2 at all edges and vertices (the centre needs them all).
    T s22[12], s21[8], s11[8];
    for (int n = 0; n < 12; ++n) s22[n] = s31_rule_s22(d, n);
    for (int v = 0; v < 8; ++v) s21[v] = s31_rule_s21(d, v);
    // Ring R1 at all vertices.
    for (int v = 0; v < 8; ++v) s11[v] = s31_rule_s11(s22, s21, v);
    bb::BezierTet<T, 3> c{};
    // Ring R3 (the cube surface).
    c.at(0, 0, 3) = d[v2];
    c.at(0, 0, 0) = d[v3];
    c.at(0, 0, 2) = d[cube_tables.edge_point[v2][v3]];
    c.at(0, 0, 1) = d[cube_tables.edge_point[v3][v2]];
    c.at(0, 1, 1) = d[32 + 0];
    c.at(0, 1, 2) = s31_rule_s31(d, phi, 0);
    c.at(0, 1, 0) = s31_rule_s31(d, phi, 1);
    c.at(0, 2, 1) = s31_rule_s32(d, phi, 0);
    c.at(0, 2, 0) = s31_rule_s32(d, phi, 1);
    c.at(0, 3, 0) = s31_rule_s33(d, phi);
    // Ring R2.
    c.at(1, 0, 2) = s21[v2];
    c.at(1, 0, 0) = s21[v3];
    c.at(1, 0, 1) = s22[fe[0]];
    c.at(1, 1, 1) = T(0.5) * (s22[fe[0]] + s22[fe[3]]);
    c.at(1, 1, 0) = T(0.5) * (s22[fe[1]] + s22[fe[0]]);
    c.at(1, 2, 0) = T(0.25) * (((s22[fe[0]] + s22[fe[1]]) + s22[fe[2]]) + s22[fe[3]]);
    // Ring R1.
    c.at(2, 0, 1) = s11[v2];
    c.at(2, 0, 0) = s11[v3];
    c.at(2, 1, 0) = T(0.25) * (((s11[fv[0]] + s11[fv[1]]) + s11[fv[2]]) + s11[fv[3]]);
    // Ring R0.
    T sum = s11[0];
    for (int v = 1; v < 8; ++v) sum = sum + s11[v];
    c.at(3, 0, 0) = T(0.125) * sum;
    return c;
}

/// The coefficients of T_0 from the determining set in the frame of T_0 (repeated averaging):
/// `qss_tet0_from_d2` (Q = 2) or `s31_tet0_from_d3` (Q = 3).
template <int Q, class T>
bb::BezierTet<T, Q> tet0_from_determining_set(const DeterminingSet<T, Q>& d_rot) {
    static_assert(Q == 2 || Q == 3, "QSS (2) or S31 (3)");
    if constexpr (Q == 2) return qss_tet0_from_d2(d_rot);
    else return s31_tet0_from_d3(d_rot);
}

/// The determining set seen from tetrahedron t: d_rot[k] = d[perm_t[k]], b[R_t ξ_k]
/// (a permutation; for the GPU an integer table lookup).
template <int Q, class T>
DeterminingSet<T, Q> rotate_determining_set(const DeterminingSet<T, Q>& d, int t) {
    static constexpr auto perm = d_permutations<Q>();
    DeterminingSet<T, Q> r{};
    for (int k = 0; k < d_count(Q); ++k) r[k] = d[perm[t][k]];
    return r;
}

/// The coefficients of tetrahedron t of a cube from its determining set (repeated averaging).
template <int Q, class T>
bb::BezierTet<T, Q> tet_from_determining_set(const DeterminingSet<T, Q>& d, int t) {
    return tet0_from_determining_set<Q>(rotate_determining_set<Q>(d, t));
}

// ---- Direct path: every coefficient from the 27 data (spec §2.3, §3.3) --------------------------

/// The stencil seen from tetrahedron t: f_rot[s] = f[R_t s].
template <class T>
Stencil<T> rotate_stencil(const Stencil<T>& f, int t) {
    static constexpr auto perm = stencil_permutations();
    Stencil<T> r{};
    for (int s = 0; s < stencil_size; ++s) r[s] = f[perm[t][s]];
    return r;
}

/// The coefficients of T_0 directly from the rotated stencil by the masks of spec §2.3 / §3.3
/// (reference path for tests and CPU tools).
/// Numerics: c_n = (Σ_s T(w_ns) * f[s]) / T(den), a left fold over the nonzero weights in flat
/// stencil order, den = 128 (QSS) or 192 (S31).
template <int Q, class T>
bb::BezierTet<T, Q> tet0_from_stencil(const Stencil<T>& f_rot) {
    static_assert(Q == 2 || Q == 3, "QSS (2) or S31 (3)");
    const T den = T(static_cast<double>(coefficient_mask_denominator(Q)));
    bb::BezierTet<T, Q> c{};
    for (int n = 0; n < bb::coefficient_count(Q); ++n) {
        bool first = true;
        T acc = T(0);
        for (int s = 0; s < stencil_size; ++s) {
            const int w = tet0_mask<Q>(n, s);
            if (w == 0) continue;
            const T term = T(static_cast<double>(w)) * f_rot[s];
            acc = first ? term : acc + term;
            first = false;
        }
        c[n] = acc / den;
    }
    return c;
}

/// The coefficients of tetrahedron t directly from the cube's (unrotated) stencil.
template <int Q, class T>
bb::BezierTet<T, Q> tet_from_stencil(const Stencil<T>& f, int t) {
    return tet0_from_stencil<Q>(rotate_stencil(f, t));
}

// ---- All distinct coefficients of a cube (host: ranges for the octree, tests) ------------------

/// Number of distinct domain points per cube: 65 (QSS) and 175 (S31) (spec §1.4).
constexpr int cube_point_count(int q) { return q == 2 ? 65 : 175; }

/// The values of all distinct BB-coefficients of a cube with the scaled domain point q·ξ of
/// each (cube-local). Order: D-set, then the remaining R_q points, then R_{q-1} ... R0.
template <int Q, class T>
struct CubeCoefficients {
    std::array<T, cube_point_count(Q)> value;
    std::array<IVec3, cube_point_count(Q)> point;
};

/// All distinct coefficients of a cube, computed in the cube's own frame by the same rule
/// functions as `tet0_from_determining_set` (host-side: octree ranges, tests). Values agree with
/// the per-tetrahedron path up to the association of the 4- and 8-term sums (exactly in exact
/// arithmetic).
template <int Q, class T>
CubeCoefficients<Q, T> cube_coefficients(const DeterminingSet<T, Q>& d) {
    CubeCoefficients<Q, T> r{};
    int n = 0;
    auto put = [&](const IVec3& p, const T& v) {
        r.point[n] = p;
        r.value[n] = v;
        ++n;
    };
    auto add3 = [](IVec3 a, IVec3 b) { return IVec3{a[0] + b[0], a[1] + b[1], a[2] + b[2]}; };
    auto scale = [](int s, IVec3 a) { return IVec3{s * a[0], s * a[1], s * a[2]}; };
    for (int k = 0; k < d_count(Q); ++k) put(d_point(Q, k), d[k]);
    if constexpr (Q == 2) {
        T r1[8];
        for (int v = 0; v < 8; ++v) r1[v] = qss_rule_q11(d, v);
        for (int phi = 0; phi < 6; ++phi) {
            const IVec3 F = face_normal(phi);
            for (int e = 0; e < 4; ++e) put(add3(F, face_vertex(phi, e)), qss_rule_q21(d, phi, e));
            put(scale(2, F), qss_rule_q22(d, phi));
        }
        for (int v = 0; v < 8; ++v) put(vertex_of(v), r1[v]);
        for (int phi = 0; phi < 6; ++phi) {
            const auto& fv = cube_tables.face_vertices[phi];
            put(face_normal(phi), T(0.25) * (((r1[fv[0]] + r1[fv[1]]) + r1[fv[2]]) + r1[fv[3]]));
        }
        T sum = r1[0];
        for (int v = 1; v < 8; ++v) sum = sum + r1[v];
        put({0, 0, 0}, T(0.125) * sum);
    } else {
        T s22[12], s21[8], s11[8];
        for (int e = 0; e < 12; ++e) s22[e] = s31_rule_s22(d, e);
        for (int v = 0; v < 8; ++v) s21[v] = s31_rule_s21(d, v);
        for (int v = 0; v < 8; ++v) s11[v] = s31_rule_s11(s22, s21, v);
        for (int phi = 0; phi < 6; ++phi) {
            const IVec3 F = face_normal(phi);
            for (int e = 0; e < 4; ++e) {
                const IVec3 v = face_vertex(phi, e);
                put(add3(F, scale(2, v)), s31_rule_s31(d, phi, e));
                put(add3(scale(2, F), v), s31_rule_s32(d, phi, e));
            }
            put(scale(3, F), s31_rule_s33(d, phi));
        }
        for (int v = 0; v < 8; ++v) put(scale(2, vertex_of(v)), s21[v]);
        for (int e = 0; e < 12; ++e)
            put(add3(vertex_of(cube_tables.edge_vertices[e][0]), vertex_of(cube_tables.edge_vertices[e][1])), s22[e]);
        for (int phi = 0; phi < 6; ++phi) {
            const IVec3 F = face_normal(phi);
            const auto& fv = cube_tables.face_vertices[phi];
            const auto& fe = cube_tables.face_edges[phi];
            for (int e = 0; e < 4; ++e)
                put(add3(F, vertex_of(fv[e])), T(0.5) * (s22[fe[e]] + s22[fe[(e + 3) % 4]]));
            put(scale(2, F), T(0.25) * (((s22[fe[0]] + s22[fe[1]]) + s22[fe[2]]) + s22[fe[3]]));
        }
        for (int v = 0; v < 8; ++v) put(vertex_of(v), s11[v]);
        for (int phi = 0; phi < 6; ++phi) {
            const auto& fv = cube_tables.face_vertices[phi];
            put(face_normal(phi), T(0.25) * (((s11[fv[0]] + s11[fv[1]]) + s11[fv[2]]) + s11[fv[3]]));
        }
        T sum = s11[0];
        for (int v = 1; v < 8; ++v) sum = sum + s11[v];
        put({0, 0, 0}, T(0.125) * sum);
    }
    return r;
}

}  // namespace quadcast::spline
