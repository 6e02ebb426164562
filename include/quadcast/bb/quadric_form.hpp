// quadcast/bb/quadric_form.hpp -- a quadratic BB piece on a tetrahedron as a quadric, and the
// BB form of the quadratic (and linear) Lagrange element
#pragma once

// A degree-2 polynomial on a tetrahedron is p(λ) = Σ_{|α|=2} c_α 2!/α! λ^α = λ^T B λ with the
// symmetric 4x4 B_ii = c_{2e_i}, B_ij = c_{e_i+e_j} (Kalbe & Zeilfelder 2008, eq. 1), and the
// barycentric coordinates are affine, λ = L (x, 1), so p is the quadric
// Q = L^T B L (Stoll et al. 2006, sec. 5.1.2: each piece of a tetrahedral quadratic spline is a
// quadric clipped to its tetrahedron).
//
// The 10-node Lagrange tetrahedron interpolates its corner values f_i and its edge-midpoint
// values f_ij; p(m_ij) = (c_{2e_i} + c_{2e_j}) / 4 + c_{e_i+e_j} / 2 gives
// c_{2e_i} = f_i, c_{e_i+e_j} = 2 f_ij - (f_i + f_j) / 2.

#include "quadcast/bb/bezier.hpp"
#include "quadcast/quadric.hpp"
#include "quadcast/ray.hpp"

namespace quadcast::bb {

/// The edges (i, j), i < j, in the storage order of the mixed degree-2 multi-indices
/// e_i + e_j (1100 1010 1001 0110 0101 0011).
inline constexpr int quadratic_edges[6][2] = {{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}};

/// The BB form of the quadratic Lagrange interpolant of corner values `corner[i]` and edge
/// midpoint values `mid[e]` (edges in `quadratic_edges` order).
/// Numerics: c_{e_i+e_j} = 2 mid - (corner_i + corner_j) 0.5 (2 mul, 1 add, 1 sub).
template <class T>
BezierTet<T, 2> bezier_from_quadratic_nodes(const T (&corner)[4], const T (&mid)[6]) {
    BezierTet<T, 2> b{};
    for (int i = 0; i < 4; ++i) {
        const int e[4] = {2 * (i == 0), 2 * (i == 1), 2 * (i == 2), 2 * (i == 3)};
        b[index_of(2, MultiIndex{e[0], e[1], e[2], e[3]})] = corner[i];
    }
    for (int n = 0; n < 6; ++n) {
        const int i = quadratic_edges[n][0], j = quadratic_edges[n][1];
        const int e[4] = {(i == 0) + (j == 0), (i == 1) + (j == 1), (i == 2) + (j == 2), (i == 3) + (j == 3)};
        b[index_of(2, MultiIndex{e[0], e[1], e[2], e[3]})] = T(2) * mid[n] - (corner[i] + corner[j]) * T(0.5);
    }
    return b;
}

/// A linear piece (4-node element) in degree-2 BB form (degree elevation: c_{e_i+e_j} =
/// (f_i + f_j) / 2).
template <class T>
BezierTet<T, 2> bezier_from_linear_nodes(const T (&corner)[4]) {
    T mid[6];
    for (int n = 0; n < 6; ++n) mid[n] = (corner[quadratic_edges[n][0]] + corner[quadratic_edges[n][1]]) * T(0.5);
    return bezier_from_quadratic_nodes(corner, mid);
}

/// The quadric x~^T Q x~ equal to the degree-2 piece `b` on the tetrahedron `t` (in t's
/// coordinates): Q = L^T B L with L's rows the `barycentric_planes` of t.
/// Numerics: Q_rc = Σ_i Σ_j B_ij L_ir L_jc, summed over i, then j, in that order (16 products
/// per entry); exactly symmetric (entry (c, r) is set from (r, c)).
template <class T>
Quadric<T> quadric_from_bezier(const BezierTet<T, 2>& b, const BoundingTet<T>& t) {
    const TetPlanes<T> l = barycentric_planes(t);
    T B[4][4];
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) {
            const int e[4] = {(i == 0) + (j == 0), (i == 1) + (j == 1), (i == 2) + (j == 2), (i == 3) + (j == 3)};
            B[i][j] = b[index_of(2, MultiIndex{e[0], e[1], e[2], e[3]})];
        }
    Quadric<T> q{};
    for (int r = 0; r < 4; ++r)
        for (int c = r; c < 4; ++c) {
            T s = T(0);
            for (int i = 0; i < 4; ++i)
                for (int j = 0; j < 4; ++j) s = s + B[i][j] * l.plane[i][r] * l.plane[j][c];
            q.q[c][r] = s;
            q.q[r][c] = s;
        }
    return q;
}

}  // namespace quadcast::bb
