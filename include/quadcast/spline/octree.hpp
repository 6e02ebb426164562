// quadcast/spline/octree.hpp -- host side: min-max octree over cubes (coefficient ranges) and frustum culling
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>
#include <vector>

#include "quadcast/linalg.hpp"
#include "quadcast/spline/grid.hpp"
#include "quadcast/spline/quasi_interpolation.hpp"

namespace quadcast::spline {

/// A closed interval [lo, hi].
template <class T>
struct Range {
    T lo, hi;
    bool contains(T x) const { return lo <= x && x <= hi; }
};

/// Per-cube range of ALL BB-coefficients of the cube's 24 pieces (65 / 175 distinct values,
/// `cube_coefficients`). By the convex hull property of the BB-form (Kalbe & Zeilfelder 2008,
/// Sect. 4) the spline on the cube lies in this range, so a cube whose range misses ρ cannot
/// contain the isosurface. This is tighter than and, unlike the data range, also valid for QSS,
/// whose masks have negative weights (spec §2.5). The range is widened by
/// 16·ε(T)·max(|lo|, |hi|) to cover the different association of the per-tetrahedron path.
/// Host-only; `threads` as in `parallel_for`.
template <int Q, class T>
std::vector<Range<T>> cube_coefficient_ranges(const SplineGrid<Q, T>& g, unsigned threads = 0) {
    std::vector<Range<T>> r(static_cast<std::size_t>(g.cube_count()));
    const int per_slice = g.nx * g.ny;
    parallel_for(g.nz, [&](int k) {
        for (int c = k * per_slice; c < (k + 1) * per_slice; ++c) {
            const CubeCoefficients<Q, T> cc = cube_coefficients<Q>(g.cube_d(c));
            T lo = cc.value[0], hi = cc.value[0];
            for (const T& v : cc.value) {
                lo = std::min(lo, v);
                hi = std::max(hi, v);
            }
            const T widen = T(16) * std::numeric_limits<T>::epsilon() * std::max(std::abs(lo), std::abs(hi));
            r[static_cast<std::size_t>(c)] = {lo - widen, hi + widen};
        }
    }, threads);
    return r;
}

/// Per-tetrahedron coefficient ranges of one cube (by the per-tetrahedron averaging path, i.e.
/// exactly the coefficients a renderer uses): a tetrahedron is relevant for ρ iff its range
/// contains ρ (Kalbe & Zeilfelder 2008, Sect. 4: "convex hull property to indicate relevant
/// tetrahedra"). Host-only.
template <int Q, class T>
std::array<Range<T>, tets_per_cube> tet_coefficient_ranges(const DeterminingSet<T, Q>& d) {
    std::array<Range<T>, tets_per_cube> r{};
    for (int t = 0; t < tets_per_cube; ++t) {
        const bb::BezierTet<T, Q> c = tet_from_determining_set<Q>(d, t);
        T lo = c[0], hi = c[0];
        for (int n = 1; n < c.size; ++n) {
            lo = std::min(lo, c[n]);
            hi = std::max(hi, c[n]);
        }
        r[t] = {lo, hi};
    }
    return r;
}

/// Bit t set iff tetrahedron t of the cube may meet the isosurface ρ (`tet_coefficient_ranges`).
template <int Q, class T>
unsigned relevant_tets(const DeterminingSet<T, Q>& d, T rho) {
    const auto r = tet_coefficient_ranges<Q>(d);
    unsigned m = 0;
    for (int t = 0; t < tets_per_cube; ++t)
        if (r[t].contains(rho)) m |= 1u << t;
    return m;
}

/// A plane a x + b y + c z + d = 0; the inside half-space is a x + b y + c z + d >= 0.
struct Plane {
    double a = 0, b = 0, c = 0, d = 0;
    double eval(const Vec<double, 3>& p) const { return ((a * p[0] + b * p[1]) + c * p[2]) + d; }
};

/// Six planes, all with the inside of the frustum on their positive side.
struct Frustum {
    std::array<Plane, 6> planes{};
};

/// The frustum of a clip matrix M = projection · view (OpenGL convention -w <= x, y, z <= w)
/// by the Gribb-Hartmann extraction: left r3 + r0, right r3 - r0, bottom r3 + r1, top r3 - r1,
/// near r3 + r2, far r3 - r2 (r_i = row i of M). Planes are not normalised (the test only
/// needs signs).
inline Frustum frustum_from_clip_matrix(const Mat<double, 4, 4>& m) {
    Frustum f;
    const Vec<double, 4> r3 = row(m, 3);
    for (int i = 0; i < 3; ++i) {
        const Vec<double, 4> ri = row(m, i);
        const Vec<double, 4> lo = r3 + ri, hi = r3 - ri;
        f.planes[2 * i] = {lo[0], lo[1], lo[2], lo[3]};
        f.planes[2 * i + 1] = {hi[0], hi[1], hi[2], hi[3]};
    }
    return f;
}

/// Result of testing an axis-aligned box against a frustum.
enum class Containment { outside, intersecting, inside };

/// Classifies the box [lo, hi] (Akenine-Möller & Haines 2002, p. 363; the paper's reference for
/// hierarchical view frustum culling): outside if, for some plane, the box corner farthest
/// along the plane normal (the "p-vertex") is outside; inside if the nearest corner is inside
/// for every plane. Conservative: a box reported outside is disjoint from the frustum.
inline Containment classify_box(const Frustum& f, const Vec<double, 3>& lo, const Vec<double, 3>& hi) {
    bool all_inside = true;
    for (const Plane& p : f.planes) {
        const Vec<double, 3> pv = {{p.a >= 0 ? hi[0] : lo[0], p.b >= 0 ? hi[1] : lo[1], p.c >= 0 ? hi[2] : lo[2]}};
        const Vec<double, 3> nv = {{p.a >= 0 ? lo[0] : hi[0], p.b >= 0 ? lo[1] : hi[1], p.c >= 0 ? lo[2] : hi[2]}};
        if (p.eval(pv) < 0) return Containment::outside;
        if (p.eval(nv) < 0) all_inside = false;
    }
    return all_inside ? Containment::inside : Containment::intersecting;
}

/// Min-max octree over the cubes of a spline grid (Kalbe & Zeilfelder 2008, Sect. 4 and 5.1):
/// level 0 holds one range per cube, level L+1 the union of 2x2x2 children of level L (the last
/// level has a single node). Ranges are COEFFICIENT ranges (`cube_coefficient_ranges`), so
/// "ρ outside a node's range" proves that no cube below it meets the isosurface ρ.
/// Host-only.
template <class T>
class MinMaxOctree {
public:
    struct Level {
        int nx, ny, nz;
        std::vector<Range<T>> range;
    };

    MinMaxOctree() = default;

    /// Builds the pyramid from per-cube ranges (cube-major, i fastest) of an nx × ny × nz grid
    /// whose cube (i,j,k) is the box origin + h·(i,j,k) ± h/2.
    MinMaxOctree(int nx, int ny, int nz, std::vector<Range<T>> cube_ranges, const Vec<double, 3>& origin, double h)
        : origin_(origin), h_(h) {
        levels_.push_back({nx, ny, nz, std::move(cube_ranges)});
        while (levels_.back().nx > 1 || levels_.back().ny > 1 || levels_.back().nz > 1) {
            const Level& c = levels_.back();
            Level p{(c.nx + 1) / 2, (c.ny + 1) / 2, (c.nz + 1) / 2, {}};
            p.range.assign(static_cast<std::size_t>(p.nx) * p.ny * p.nz,
                           {std::numeric_limits<T>::infinity(), -std::numeric_limits<T>::infinity()});
            for (int k = 0; k < c.nz; ++k)
                for (int j = 0; j < c.ny; ++j)
                    for (int i = 0; i < c.nx; ++i) {
                        const Range<T>& r = c.range[idx(c, i, j, k)];
                        Range<T>& q = p.range[idx(p, i / 2, j / 2, k / 2)];
                        q.lo = std::min(q.lo, r.lo);
                        q.hi = std::max(q.hi, r.hi);
                    }
            levels_.push_back(std::move(p));
        }
    }

    /// Octree over the cubes of a spline grid with its coefficient ranges.
    template <int Q>
    static MinMaxOctree from_spline(const SplineGrid<Q, T>& g, unsigned threads = 0) {
        return MinMaxOctree(g.nx, g.ny, g.nz, cube_coefficient_ranges<Q>(g, threads), g.origin, g.h);
    }

    int level_count() const { return static_cast<int>(levels_.size()); }
    const Level& level(int l) const { return levels_[static_cast<std::size_t>(l)]; }

    /// Can cube c contain the isovalue ρ (ρ within its coefficient range)?
    bool cube_may_contain(int c, T rho) const { return levels_[0].range[static_cast<std::size_t>(c)].contains(rho); }

    /// World box of node (i,j,k) of level l (clipped to the grid).
    void node_box(int l, int i, int j, int k, Vec<double, 3>& lo, Vec<double, 3>& hi) const {
        const Level& c = levels_[0];
        const int s = 1 << l, n[3] = {c.nx, c.ny, c.nz}, ijk[3] = {i, j, k};
        for (int a = 0; a < 3; ++a) {
            const int first = ijk[a] * s, last = std::min(n[a], (ijk[a] + 1) * s) - 1;
            lo[a] = origin_[a] + h_ * (first - 0.5);
            hi[a] = origin_[a] + h_ * (last + 0.5);
        }
    }

    /// Cubes (indices, ascending) whose range contains ρ and, if a frustum is given, whose box
    /// is not outside it; nodes are pruned top-down by range and by `classify_box` (a node found
    /// inside the frustum is not tested again below). `visited` (optional) counts tested nodes.
    std::vector<int> active_cubes(T rho, const Frustum* frustum = nullptr, std::size_t* visited = nullptr) const {
        std::vector<int> out;
        std::size_t count = 0;
        const int top = level_count() - 1;
        collect(top, 0, 0, 0, rho, frustum, frustum == nullptr, 0, out, count);
        std::sort(out.begin(), out.end());
        if (visited) *visited = count;
        return out;
    }

    /// Nodes of level `l` (indices into level(l).range) that are active for ρ and not culled:
    /// the unit of a draw batch ("a set of display lists each corresponding to a non-empty node
    /// on a fixed octree level θ", Kalbe & Zeilfelder 2008, Sect. 5.1).
    std::vector<int> active_nodes(int l, T rho, const Frustum* frustum = nullptr) const {
        std::vector<int> out;
        std::size_t count = 0;
        collect(level_count() - 1, 0, 0, 0, rho, frustum, frustum == nullptr, l, out, count);
        std::sort(out.begin(), out.end());
        return out;
    }

private:
    static std::size_t idx(const Level& L, int i, int j, int k) {
        return static_cast<std::size_t>(i) + static_cast<std::size_t>(L.nx) * (static_cast<std::size_t>(j) + static_cast<std::size_t>(L.ny) * k);
    }

    void collect(int l, int i, int j, int k, T rho, const Frustum* f, bool inside, int stop, std::vector<int>& out,
                 std::size_t& count) const {
        const Level& L = levels_[static_cast<std::size_t>(l)];
        if (i >= L.nx || j >= L.ny || k >= L.nz) return;
        ++count;
        const std::size_t n = idx(L, i, j, k);
        if (!L.range[n].contains(rho)) return;
        if (!inside) {
            Vec<double, 3> lo{}, hi{};
            node_box(l, i, j, k, lo, hi);
            const Containment c = classify_box(*f, lo, hi);
            if (c == Containment::outside) return;
            inside = c == Containment::inside;
        }
        if (l == stop) {
            out.push_back(static_cast<int>(n));
            return;
        }
        for (int dz = 0; dz < 2; ++dz)
            for (int dy = 0; dy < 2; ++dy)
                for (int dx = 0; dx < 2; ++dx) collect(l - 1, 2 * i + dx, 2 * j + dy, 2 * k + dz, rho, f, inside, stop, out, count);
    }

    std::vector<Level> levels_;
    Vec<double, 3> origin_{{0.0, 0.0, 0.0}};
    double h_ = 1.0;
};

}  // namespace quadcast::spline
