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

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

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

/// How far a 10-node tetrahedron's edge nodes lie from their edges' midpoints (`edge_node_offset`).
template <class T>
struct EdgeNodeOffset {
    T distance = T(0);  ///< the largest distance
    int edge = 0;       ///< the edge (quadratic_edges order) where it is
};

/// Edge nodes farther than this times the longest edge from their midpoints make an element
/// curved: its isosurface is not a quadric, and `element_isosurface` does not apply.
inline constexpr double straight_edge_tolerance = 1e-6;

/// The largest distance of the edge nodes `x` (quadratic_edges order) of the tetrahedron with
/// corners `p` from their edges' midpoints (the first edge where it is).
/// Numerics: about the corners' centroid c (as `element_isosurface`): |(x_e - c) - ((p_i - c) +
/// (p_j - c)) * 0.5|, c as there.
template <class T>
EdgeNodeOffset<T> edge_node_offset(const Vec3<T> (&p)[4], const Vec3<T> (&x)[6]) {
    Vec3<T> c{{T(0), T(0), T(0)}};
    for (int k = 0; k < 4; ++k) c = c + p[k] * T(0.25);
    EdgeNodeOffset<T> r{};
    for (int e = 0; e < 6; ++e) {
        const int i = quadratic_edges[e][0], j = quadratic_edges[e][1];
        const T d = length((x[e] - c) - ((p[i] - c) + (p[j] - c)) * T(0.5));
        if (e == 0 || d > r.distance) r = {d, e};
    }
    return r;
}

/// The isosurface f = iso of one straight-sided Lagrange tetrahedron (`element_isosurface`).
template <class T>
struct ElementIsosurface {
    Quadric<T> q;           ///< f - iso as a quadric in world coordinates (meaningful when `crosses`)
    T lo = T(0), hi = T(0);  ///< the range of f's BB coefficients (it contains f on the element)
    bool crosses = false;   ///< the coefficients of f - iso are not all of one sign, nor all 0
};

/// The isosurface f = iso of the 4-node (`mid` null: linear) or 10-node (`mid`: the six edge
/// midpoint values in `quadratic_edges` order) Lagrange tetrahedron with corners `p` and corner
/// values `corner`, as a quadric to clip to the tetrahedron: the BB form of f
/// (`bezier_from_quadratic_nodes` / `bezier_from_linear_nodes`) minus iso, as a quadric
/// (`quadric_from_bezier`) in coordinates about the corners' centroid c, moved back to world
/// coordinates (`translate_to_eye` by -c). `crosses` is false when the BB coefficients of
/// f - iso all have one sign (by the convex hull property, no surface) or are all 0. The
/// element's edge nodes must lie at the midpoints (the caller checks: curved elements are not
/// quadrics).
/// Numerics: c = (p0 + p1 + p2 + p3) * 0.25 (left fold of p_k * 0.25); the rest as the named functions.
template <class T>
ElementIsosurface<T> element_isosurface(const Vec3<T> (&p)[4], const T (&corner)[4], const T* mid, const T& iso) {
    BoundingTet<T> local{};
    Vec3<T> c{{T(0), T(0), T(0)}};
    for (int k = 0; k < 4; ++k) c = c + p[k] * T(0.25);
    for (int k = 0; k < 4; ++k) local.p[k] = p[k] - c;
    BezierTet<T, 2> b{};
    if (mid) {
        const T m[6] = {mid[0], mid[1], mid[2], mid[3], mid[4], mid[5]};
        b = bezier_from_quadratic_nodes(corner, m);
    } else {
        b = bezier_from_linear_nodes(corner);
    }
    ElementIsosurface<T> r{};
    r.lo = b[0];
    r.hi = b[0];
    T bmin = b[0] - iso, bmax = bmin;
    for (int n = 0; n < b.size; ++n) {
        r.lo = std::min(r.lo, b[n]);
        r.hi = std::max(r.hi, b[n]);
        b[n] = b[n] - iso;
        bmin = std::min(bmin, b[n]);
        bmax = std::max(bmax, b[n]);
    }
    r.crosses = !(bmin > T(0) || bmax < T(0) || (bmin == T(0) && bmax == T(0)));
    if (r.crosses) r.q = translate_to_eye(quadric_from_bezier(b, local), Vec3<T>{{-c[0], -c[1], -c[2]}});
    return r;
}

/// The BB coefficient c_{e_i+e_j} of a quadric restricted to a tetrahedron with corners p_i, p_j:
/// its blossom (p_i, 1)^T Q (p_j, 1) (c_{2e_i} = f(p_i)).
/// Numerics: dot((a, 1), Q (b, 1)) with linalg's left folds.
template <class T>
T quadric_blossom(const Quadric<T>& q, const Vec3<T>& a, const Vec3<T>& b) {
    return dot(vec4(a, T(1)), q.q * vec4(b, T(1)));
}

/// Whether the quadric's zero set can meet the tetrahedron: false only when its ten BB
/// coefficients (`quadric_blossom`) all exceed 2^-40 of their largest magnitude with one sign
/// (then, by the convex hull property, f keeps that sign on the whole tetrahedron; the margin
/// covers the rounding of the coefficients).
template <class T>
bool quadric_may_cross(const Quadric<T>& q, const BoundingTet<T>& t) {
    T lo = T(0), hi = T(0), big = T(0);
    for (int i = 0; i < 4; ++i)
        for (int j = i; j < 4; ++j) {
            const T c = quadric_blossom(q, t.p[i], t.p[j]);
            if (!(c == c)) return true;  // NaN: keep
            lo = (i == 0 && j == 0) ? c : std::min(lo, c);
            hi = (i == 0 && j == 0) ? c : std::max(hi, c);
            big = std::max(big, std::fabs(c));
        }
    const T margin = big * T(9.094947017729282379150390625e-13);
    return !(lo > margin || hi < -margin);
}

/// The eight children of Bey's red refinement of a tetrahedron (corners x_i, edge midpoints
/// x_ij): the four corner tetrahedra (x_0, x_01, x_02, x_03), (x_01, x_1, x_12, x_13),
/// (x_02, x_12, x_2, x_23), (x_03, x_13, x_23, x_3) and the inner octahedron cut along x_02 x_13
/// into (x_01, x_02, x_03, x_13), (x_01, x_02, x_12, x_13), (x_02, x_03, x_13, x_23),
/// (x_02, x_12, x_13, x_23). Together they tile the parent.
template <class T>
std::array<BoundingTet<T>, 8> red_refinement(const BoundingTet<T>& t) {
    const Vec3<T>* x = t.p;
    auto mid = [&](int i, int j) { return (x[i] + x[j]) * T(0.5); };
    const Vec3<T> m01 = mid(0, 1), m02 = mid(0, 2), m03 = mid(0, 3), m12 = mid(1, 2), m13 = mid(1, 3), m23 = mid(2, 3);
    return {BoundingTet<T>{{x[0], m01, m02, m03}}, BoundingTet<T>{{m01, x[1], m12, m13}}, BoundingTet<T>{{m02, m12, x[2], m23}},
            BoundingTet<T>{{m03, m13, m23, x[3]}}, BoundingTet<T>{{m01, m02, m03, m13}}, BoundingTet<T>{{m01, m02, m12, m13}},
            BoundingTet<T>{{m02, m03, m13, m23}}, BoundingTet<T>{{m02, m12, m13, m23}}};
}

/// Smaller clip tetrahedra for a quadric clipped to a tetrahedron whose zero set fills little
/// of it (e.g. the cells of a skin's mixed complex): the parent is refined (`red_refinement`) and
/// only the children the surface can cross (`quadric_may_cross`) are kept, as long as at most
/// `max_kept` of the eight are and `levels` allows; then each kept child likewise. The kept
/// tetrahedra hold every point of the zero set in the parent (each dropped child has none), so
/// drawing the quadric clipped to each of them draws the same surface over a smaller screen area.
/// Appends to `out`; the parent itself when refining does not pay or would keep a flat child
/// (six times its volume at most 10^-3 of its longest edge cubed: the float corners of a primitive
/// could make it flatter still) or one whose longest edge is
/// shorter than `min_edge` (e.g. what the float coordinates of a primitive can still resolve).
template <class T>
void refine_crossing(const Quadric<T>& q, const BoundingTet<T>& t, int levels, int max_kept, const T& min_edge, std::vector<BoundingTet<T>>& out) {
    if (levels > 0) {
        const std::array<BoundingTet<T>, 8> kids = red_refinement(t);
        BoundingTet<T> kept[8];
        int n = 0;
        bool flat = false;
        for (const BoundingTet<T>& k : kids)
            if (quadric_may_cross(q, k)) {
                kept[n++] = k;
                // (A flat child, from a sliver parent, would be refused as a clip tetrahedron.)
                const TetShape<T> shape = tet_shape(k.p);
                flat = (flat || shape.flatter_than(T(0.001))) || !(shape.longest >= min_edge);
            }
        if (n > 0 && n <= max_kept && !flat) {
            for (int i = 0; i < n; ++i) refine_crossing(q, kept[i], levels - 1, max_kept, min_edge, out);
            return;
        }
    }
    out.push_back(t);
}

}  // namespace quadcast::bb
