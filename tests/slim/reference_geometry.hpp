// tests/slim/reference_geometry.hpp -- independent references of the slim tests: ray casting of a triangle mesh, nearest input point
#pragma once

// Neither uses the SLIM code: a bounding volume hierarchy of the mesh's triangles with the
// Moeller-Trumbore ray-triangle test (double), and a uniform grid of the input points for the
// distance to the nearest one.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "quadcast/linalg.hpp"

namespace quadcast::slim::testing {

using V3 = Vec<double, 3>;

/// First hits of rays with a triangle mesh (double; a BVH of median splits, leaves of <= 4 triangles).
class MeshRaycaster {
public:
    MeshRaycaster(std::vector<V3> positions, std::vector<std::array<std::uint32_t, 3>> triangles)
        : p_(std::move(positions)), t_(std::move(triangles)) {
        order_.resize(t_.size());
        for (std::size_t i = 0; i < t_.size(); ++i) order_[i] = std::uint32_t(i);
        centroid_.resize(t_.size());
        for (std::size_t i = 0; i < t_.size(); ++i) centroid_[i] = (p_[t_[i][0]] + p_[t_[i][1]] + p_[t_[i][2]]) * (1.0 / 3.0);
        if (!t_.empty()) build(0, t_.size());
    }

    /// The ray parameter of the first hit of origin + s dir with s > 0, or +inf. An edge shared by
    /// two triangles counts as hit (barycentric tolerance 1e-12), so a closed mesh has no pinholes.
    double first_hit(const V3& o, const V3& d) const { return first_hit(o, d, nullptr, nullptr, nullptr); }

    /// The same, with the triangle hit and the barycentric coordinates (u, v) of the hit on it
    /// (the point is (1 - u - v) p0 + u p1 + v p2).
    double first_hit(const V3& o, const V3& d, std::uint32_t* tri, double* bu, double* bv) const {
        double best = std::numeric_limits<double>::infinity();
        if (nodes_.empty()) return best;
        V3 inv;
        for (int k = 0; k < 3; ++k) inv[k] = 1.0 / d[k];
        std::uint32_t stack[128];
        int top = 0;
        stack[top++] = 0;
        while (top > 0) {
            const Node& n = nodes_[stack[--top]];
            if (!slab(n, o, inv, best)) continue;
            if (n.count > 0) {
                for (std::uint32_t k = n.first; k < n.first + n.count; ++k) {
                    double u = 0, v = 0;
                    const double s = triangle(order_[k], o, d, u, v);
                    if (s < best) {
                        best = s;
                        if (tri) *tri = order_[k], *bu = u, *bv = v;
                    }
                }
            } else {
                stack[top++] = n.first;
                stack[top++] = n.first + 1;
            }
        }
        return best;
    }

private:
    struct Node {
        V3 lo, hi;
        std::uint32_t first = 0, count = 0;  ///< leaf: triangles [first, first + count); inner: children first, first + 1
    };

    void build(std::size_t root_begin, std::size_t root_end) {
        struct Job {
            std::uint32_t node;
            std::size_t b, e;
        };
        nodes_.push_back({});
        std::vector<Job> jobs{{0, root_begin, root_end}};
        while (!jobs.empty()) {
            const Job j = jobs.back();
            jobs.pop_back();
            Node n;
            n.lo = n.hi = p_[t_[order_[j.b]][0]];
            V3 clo = centroid_[order_[j.b]], chi = clo;
            for (std::size_t k = j.b; k < j.e; ++k) {
                for (const std::uint32_t v : t_[order_[k]])
                    for (int a = 0; a < 3; ++a) n.lo[a] = std::min(n.lo[a], p_[v][a]), n.hi[a] = std::max(n.hi[a], p_[v][a]);
                for (int a = 0; a < 3; ++a) clo[a] = std::min(clo[a], centroid_[order_[k]][a]), chi[a] = std::max(chi[a], centroid_[order_[k]][a]);
            }
            if (j.e - j.b <= 4) {
                n.first = std::uint32_t(j.b);
                n.count = std::uint32_t(j.e - j.b);
                nodes_[j.node] = n;
                continue;
            }
            int axis = 0;
            for (int a = 1; a < 3; ++a)
                if (chi[a] - clo[a] > chi[axis] - clo[axis]) axis = a;
            const std::size_t mid = (j.b + j.e) / 2;
            std::nth_element(order_.begin() + long(j.b), order_.begin() + long(mid), order_.begin() + long(j.e),
                             [&](std::uint32_t x, std::uint32_t y) { return centroid_[x][axis] < centroid_[y][axis]; });
            n.first = std::uint32_t(nodes_.size());
            n.count = 0;
            nodes_[j.node] = n;
            nodes_.push_back({});
            nodes_.push_back({});
            jobs.push_back({n.first, j.b, mid});
            jobs.push_back({n.first + 1, mid, j.e});
        }
    }

    static bool slab(const Node& n, const V3& o, const V3& inv, double tmax) {
        double t0 = 0, t1 = tmax;
        for (int a = 0; a < 3; ++a) {
            double ta = (n.lo[a] - o[a]) * inv[a], tb = (n.hi[a] - o[a]) * inv[a];
            if (ta > tb) std::swap(ta, tb);
            t0 = std::max(t0, ta);
            t1 = std::min(t1, tb);
            if (!(t0 <= t1 * (1 + 1e-12) + 1e-300)) return false;
        }
        return true;
    }

    double triangle(std::uint32_t i, const V3& o, const V3& d, double& u, double& v) const {
        const V3 a = p_[t_[i][0]], e1 = p_[t_[i][1]] - a, e2 = p_[t_[i][2]] - a;
        const V3 pv = cross(d, e2);
        const double det = dot(e1, pv);
        if (det == 0) return std::numeric_limits<double>::infinity();
        const double inv = 1.0 / det;
        const V3 tv = o - a;
        u = dot(tv, pv) * inv;
        const double tol = 1e-12;
        if (u < -tol || u > 1 + tol) return std::numeric_limits<double>::infinity();
        const V3 qv = cross(tv, e1);
        v = dot(d, qv) * inv;
        if (v < -tol || u + v > 1 + tol) return std::numeric_limits<double>::infinity();
        const double s = dot(e2, qv) * inv;
        return s > 0 ? s : std::numeric_limits<double>::infinity();
    }

    std::vector<V3> p_;
    std::vector<std::array<std::uint32_t, 3>> t_;
    std::vector<std::uint32_t> order_;
    std::vector<V3> centroid_;
    std::vector<Node> nodes_;
};

/// The distance from a query to the nearest of a set of points (a uniform grid, rings of cells).
class NearestPoint {
public:
    NearestPoint(const std::vector<V3>& points, double cell) : p_(points), h_(cell) {
        lo_ = hi_ = points.front();
        for (const V3& q : points)
            for (int a = 0; a < 3; ++a) lo_[a] = std::min(lo_[a], q[a]), hi_[a] = std::max(hi_[a], q[a]);
        for (int a = 0; a < 3; ++a) n_[a] = std::max(1, int(std::ceil((hi_[a] - lo_[a]) / h_)) + 1);
        start_.assign(std::size_t(n_[0]) * n_[1] * n_[2] + 1, 0);
        std::vector<std::size_t> c(points.size());
        for (std::size_t i = 0; i < points.size(); ++i) ++start_[(c[i] = cell_of(points[i])) + 1];
        for (std::size_t k = 1; k < start_.size(); ++k) start_[k] += start_[k - 1];
        items_.resize(points.size());
        std::vector<std::size_t> fill(start_.begin(), start_.end() - 1);
        for (std::size_t i = 0; i < points.size(); ++i) items_[fill[c[i]]++] = std::uint32_t(i);
    }

    /// The distance of x to the nearest point (exact: rings of cells until the ring is farther).
    double distance(const V3& x) const {
        int c[3];
        for (int a = 0; a < 3; ++a) c[a] = int(std::floor((x[a] - lo_[a]) / h_));
        double best2 = std::numeric_limits<double>::infinity();
        const int max_ring = std::max({n_[0], n_[1], n_[2]}) + std::max({std::abs(c[0]), std::abs(c[1]), std::abs(c[2])}) + 1;
        for (int ring = 0; ring <= max_ring; ++ring) {
            // Every point outside the cube of rings < ring is farther than (ring - 1) h.
            if (ring > 0 && double(ring - 1) * h_ * double(ring - 1) * h_ > best2) break;
            for (int z = c[2] - ring; z <= c[2] + ring; ++z)
                for (int y = c[1] - ring; y <= c[1] + ring; ++y)
                    for (int xx = c[0] - ring; xx <= c[0] + ring; ++xx) {
                        if (std::max({std::abs(z - c[2]), std::abs(y - c[1]), std::abs(xx - c[0])}) != ring) continue;
                        if (xx < 0 || y < 0 || z < 0 || xx >= n_[0] || y >= n_[1] || z >= n_[2]) continue;
                        const std::size_t cell = (std::size_t(z) * n_[1] + std::size_t(y)) * n_[0] + std::size_t(xx);
                        for (std::size_t k = start_[cell]; k < start_[cell + 1]; ++k) {
                            const V3 d = p_[items_[k]] - x;
                            best2 = std::min(best2, dot(d, d));
                        }
                    }
        }
        return std::sqrt(best2);
    }

private:
    std::size_t cell_of(const V3& x) const {
        int c[3];
        for (int a = 0; a < 3; ++a) c[a] = std::clamp(int(std::floor((x[a] - lo_[a]) / h_)), 0, n_[a] - 1);
        return (std::size_t(c[2]) * n_[1] + std::size_t(c[1])) * n_[0] + std::size_t(c[0]);
    }

    const std::vector<V3>& p_;
    double h_;
    V3 lo_, hi_;
    int n_[3] = {1, 1, 1};
    std::vector<std::size_t> start_;
    std::vector<std::uint32_t> items_;
};

}  // namespace quadcast::slim::testing
