// src/volume/sdf.cpp -- signed distance volumes from triangle meshes (OFF)
#include "quadcast/volume/sdf.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <numeric>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "quadcast/scene/off.hpp"

namespace quadcast::volume {

TriangleMesh read_off_mesh(const std::string& path, std::vector<std::string>* warnings) {
    const scene::OffMesh off = scene::read_off(path);  // throws scene::ParseError (file:line: field: message)
    if (warnings)
        for (const auto& w : off.warnings) warnings->push_back(w.to_string());
    TriangleMesh m;
    m.source = path;
    m.vertices = off.vertices;
    for (const auto& f : off.faces)
        for (std::size_t k = 1; k + 1 < f.size(); ++k) m.triangles.push_back({f[0], f[k], f[k + 1]});
    return m;
}

namespace {

struct Box {
    Vec3d lo{{std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity()}};
    Vec3d hi{{-std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()}};
    void add(const Vec3d& p) {
        for (int a = 0; a < 3; ++a) {
            lo[a] = std::min(lo[a], p[a]);
            hi[a] = std::max(hi[a], p[a]);
        }
    }
    void add(const Box& b) { add(b.lo); add(b.hi); }
    double distance2(const Vec3d& p) const {
        double s = 0.0;
        for (int a = 0; a < 3; ++a) {
            const double d = std::max({lo[a] - p[a], 0.0, p[a] - hi[a]});
            s += d * d;
        }
        return s;
    }
};

/// Bounding volume hierarchy over the triangles (median split on the longest centroid axis).
class Bvh {
public:
    explicit Bvh(const TriangleMesh& m) {
        const std::size_t n = m.triangles.size();
        tri_.resize(n);
        std::vector<int> order(n);
        std::iota(order.begin(), order.end(), 0);
        std::vector<Vec3d> centroid(n);
        for (std::size_t t = 0; t < n; ++t) {
            const auto& f = m.triangles[t];
            centroid[t] = (m.vertices[std::size_t(f[0])] + m.vertices[std::size_t(f[1])] + m.vertices[std::size_t(f[2])]) * (1.0 / 3.0);
        }
        nodes_.reserve(2 * n / leaf_size + 2);
        build(m, order, centroid, 0, n);
        for (std::size_t i = 0; i < n; ++i) {
            const auto& f = m.triangles[std::size_t(order[i])];
            tri_[i] = {m.vertices[std::size_t(f[0])], m.vertices[std::size_t(f[1])], m.vertices[std::size_t(f[2])]};
        }
    }

    /// Squared distance to the nearest triangle, searching only below `bound2` (returns bound2
    /// when nothing is closer).
    double nearest2(const Vec3d& p, double bound2) const {
        double best = bound2;
        int stack[128];
        int top = 0;
        stack[top++] = 0;
        while (top > 0) {
            const Node& nd = nodes_[std::size_t(stack[--top])];
            if (nd.box.distance2(p) >= best) continue;
            if (nd.count > 0) {
                for (int i = nd.first; i < nd.first + nd.count; ++i) {
                    const auto& t = tri_[std::size_t(i)];
                    best = std::min(best, point_triangle_distance2(p, t[0], t[1], t[2]));
                }
                continue;
            }
            const double dl = nodes_[std::size_t(nd.left)].box.distance2(p), dr = nodes_[std::size_t(nd.right)].box.distance2(p);
            // Push the farther child first so that the nearer one is searched first.
            if (dl < dr) {
                if (dr < best) stack[top++] = nd.right;
                if (dl < best) stack[top++] = nd.left;
            } else {
                if (dl < best) stack[top++] = nd.left;
                if (dr < best) stack[top++] = nd.right;
            }
        }
        return best;
    }

private:
    static constexpr std::size_t leaf_size = 4;
    struct Node {
        Box box;
        int left = -1, right = -1;
        int first = 0, count = 0;
    };

    int build(const TriangleMesh& m, std::vector<int>& order, const std::vector<Vec3d>& centroid, std::size_t first,
              std::size_t count) {
        const int id = static_cast<int>(nodes_.size());
        nodes_.push_back({});
        Box box, cbox;
        for (std::size_t i = first; i < first + count; ++i) {
            const auto& f = m.triangles[std::size_t(order[i])];
            for (int k = 0; k < 3; ++k) box.add(m.vertices[std::size_t(f[std::size_t(k)])]);
            cbox.add(centroid[std::size_t(order[i])]);
        }
        nodes_[std::size_t(id)].box = box;
        if (count <= leaf_size) {
            nodes_[std::size_t(id)].first = static_cast<int>(first);
            nodes_[std::size_t(id)].count = static_cast<int>(count);
            return id;
        }
        int axis = 0;
        for (int a = 1; a < 3; ++a)
            if (cbox.hi[a] - cbox.lo[a] > cbox.hi[axis] - cbox.lo[axis]) axis = a;
        const std::size_t half = count / 2;
        std::nth_element(order.begin() + std::ptrdiff_t(first), order.begin() + std::ptrdiff_t(first + half),
                         order.begin() + std::ptrdiff_t(first + count),
                         [&](int x, int y) { return centroid[std::size_t(x)][axis] < centroid[std::size_t(y)][axis]; });
        const int l = build(m, order, centroid, first, half);
        const int r = build(m, order, centroid, first + half, count - half);
        nodes_[std::size_t(id)].left = l;
        nodes_[std::size_t(id)].right = r;
        return id;
    }

    std::vector<Node> nodes_;
    std::vector<std::array<Vec3d, 3>> tri_;
};

/// orient2d of (a, b, q): > 0 when q lies left of the directed line a -> b.
double orient(double ax, double ay, double bx, double by, double qx, double qy) {
    return (bx - ax) * (qy - ay) - (by - ay) * (qx - ax);
}

/// Adds, for rows parallel to axis `a`, one vote per sample that lies inside by ray parity.
void parity_votes(const TriangleMesh& m, int a, const int n[3], const Vec3d& origin, double h, std::vector<std::uint8_t>& votes) {
    const int b = (a + 1) % 3, c = (a + 2) % 3;
    const int nb = n[b], nc = n[c];
    std::vector<std::vector<double>> rows(static_cast<std::size_t>(nb) * static_cast<std::size_t>(nc));
    for (const auto& f : m.triangles) {
        double pb[3], pc[3], pa[3];
        for (int k = 0; k < 3; ++k) {
            const Vec3d& v = m.vertices[std::size_t(f[std::size_t(k)])];
            pa[k] = v[a];
            pb[k] = v[b];
            pc[k] = v[c];
        }
        const double area = orient(pb[0], pc[0], pb[1], pc[1], pb[2], pc[2]);
        if (area == 0.0 || !std::isfinite(area)) continue;  // parallel to the rows (or degenerate)
        const double sgn = area > 0.0 ? 1.0 : -1.0;
        const double minb = std::min({pb[0], pb[1], pb[2]}), maxb = std::max({pb[0], pb[1], pb[2]});
        const double minc = std::min({pc[0], pc[1], pc[2]}), maxc = std::max({pc[0], pc[1], pc[2]});
        const int jb0 = std::max(0, static_cast<int>(std::ceil((minb - origin[b]) / h)));
        const int jb1 = std::min(nb - 1, static_cast<int>(std::floor((maxb - origin[b]) / h)));
        const int jc0 = std::max(0, static_cast<int>(std::ceil((minc - origin[c]) / h)));
        const int jc1 = std::min(nc - 1, static_cast<int>(std::floor((maxc - origin[c]) / h)));
        for (int jc = jc0; jc <= jc1; ++jc) {
            for (int jb = jb0; jb <= jb1; ++jb) {
                const double qb = origin[b] + h * jb, qc = origin[c] + h * jc;
                double e[3];
                bool inside = true;
                for (int k = 0; k < 3 && inside; ++k) {
                    const int u = k, w = (k + 1) % 3;
                    // Canonical evaluation: endpoints in vertex-index order, so that the two
                    // triangles sharing the edge compute the same number.
                    const bool fwd = f[std::size_t(u)] < f[std::size_t(w)];
                    const int lo = fwd ? u : w, hi = fwd ? w : u;
                    double ev = orient(pb[lo], pc[lo], pb[hi], pc[hi], qb, qc);
                    if (!fwd) ev = -ev;
                    ev *= sgn;  // > 0: on the inner side of the counter-clockwise edge
                    if (ev == 0.0) {
                        // Top-left rule on the counter-clockwise direction of the edge.
                        const double db = (pb[w] - pb[u]) * sgn, dc = (pc[w] - pc[u]) * sgn;
                        inside = dc < 0.0 || (dc == 0.0 && db < 0.0);
                    } else {
                        inside = ev > 0.0;
                    }
                    e[k] = ev;
                }
                if (!inside) continue;
                // e[k] belongs to the edge opposite vertex k+2: barycentric weights.
                const double s = e[0] + e[1] + e[2];
                const double x = s != 0.0 ? (e[0] * pa[2] + e[1] * pa[0] + e[2] * pa[1]) / s : (pa[0] + pa[1] + pa[2]) / 3.0;
                rows[static_cast<std::size_t>(jc) * static_cast<std::size_t>(nb) + static_cast<std::size_t>(jb)].push_back(x);
            }
        }
    }
    for (int jc = 0; jc < nc; ++jc) {
        for (int jb = 0; jb < nb; ++jb) {
            auto& r = rows[static_cast<std::size_t>(jc) * static_cast<std::size_t>(nb) + static_cast<std::size_t>(jb)];
            if (r.empty()) continue;
            std::sort(r.begin(), r.end());
            std::size_t crossed = 0;
            for (int i = 0; i < n[a]; ++i) {
                const double x = origin[a] + h * i;
                while (crossed < r.size() && r[crossed] < x) ++crossed;
                if (crossed % 2 == 1) {
                    int idx[3];
                    idx[a] = i;
                    idx[b] = jb;
                    idx[c] = jc;
                    ++votes[static_cast<std::size_t>(idx[0]) +
                            static_cast<std::size_t>(n[0]) * (static_cast<std::size_t>(idx[1]) + static_cast<std::size_t>(n[1]) * static_cast<std::size_t>(idx[2]))];
                }
            }
        }
    }
}

}  // namespace

VolumeData signed_distance_volume(const TriangleMesh& mesh, const SdfOptions& options, const Progress& progress) {
    const std::string name = mesh.source.empty() ? std::string("mesh") : mesh.source;
    if (mesh.triangles.empty()) throw VolumeError(name, -1, 0, "", "the mesh has no faces");
    if (options.resolution < 8 || options.resolution > 2048)
        throw VolumeError(name, -1, 0, "resolution", "must lie in 8..2048, found " + std::to_string(options.resolution));
    if (options.padding < 0 || 2 * options.padding + 2 > options.resolution)
        throw VolumeError(name, -1, 0, "padding", "must lie in 0.." + std::to_string(options.resolution / 2 - 1) +
                                                      ", found " + std::to_string(options.padding));
    Box box;
    for (const auto& f : mesh.triangles)
        for (int k = 0; k < 3; ++k) {
            const int vi = f[std::size_t(k)];
            if (vi < 0 || static_cast<std::size_t>(vi) >= mesh.vertices.size())
                throw VolumeError(name, -1, 0, "", "triangle vertex index " + std::to_string(vi) + " out of range");
            const Vec3d& v = mesh.vertices[std::size_t(vi)];
            if (!std::isfinite(v[0]) || !std::isfinite(v[1]) || !std::isfinite(v[2]))
                throw VolumeError(name, -1, 0, "", "vertex " + std::to_string(vi) + " is not finite");
            box.add(v);
        }
    const double extent = std::max({box.hi[0] - box.lo[0], box.hi[1] - box.lo[1], box.hi[2] - box.lo[2]});
    if (!(extent > 0.0)) throw VolumeError(name, -1, 0, "", "the mesh has no extent (all vertices coincide)");

    const int pad = options.padding;
    const double h = extent / (options.resolution - 1 - 2 * pad);
    int n[3];
    Vec3d origin{};
    for (int a = 0; a < 3; ++a) {
        const double e = box.hi[a] - box.lo[a];
        n[a] = std::min(options.resolution, static_cast<int>(std::ceil(e / h - 1e-9)) + 1 + 2 * pad);
        origin[a] = 0.5 * (box.lo[a] + box.hi[a]) - 0.5 * h * (n[a] - 1);
    }

    VolumeData v;
    v.source = "signed distance of " + name + " (" + dims_string(n[0], n[1], n[2]) + ")";
    v.grid = spline::Volume<float>(n[0], n[1], n[2]);
    v.spacing = Vec3d{{h, h, h}};
    v.origin = origin;

    // Sign: three parity votes per sample.
    std::vector<std::uint8_t> votes(v.voxel_count(), 0);
    for (int a = 0; a < 3; ++a) parity_votes(mesh, a, n, origin, h, votes);

    // Distance: nearest triangle by the BVH, slices in parallel.
    const Bvh bvh(mesh);
    std::atomic<int> done{0};
    tbb::parallel_for(tbb::blocked_range<int>(0, n[2]), [&](const tbb::blocked_range<int>& range) {
        for (int k = range.begin(); k < range.end(); ++k) {
            for (int j = 0; j < n[1]; ++j) {
                double prev = -1.0;
                for (int i = 0; i < n[0]; ++i) {
                    const Vec3d p{{origin[0] + h * i, origin[1] + h * j, origin[2] + h * k}};
                    double bound = std::numeric_limits<double>::infinity();
                    if (prev >= 0.0) {
                        const double r = (prev + h) * (1.0 + 1e-9) + 1e-12 * extent;
                        bound = r * r;
                    }
                    double d2 = bvh.nearest2(p, bound);
                    if (!(d2 < bound)) d2 = bvh.nearest2(p, std::numeric_limits<double>::infinity());
                    const double d = std::sqrt(d2);
                    prev = d;
                    const std::size_t idx = v.grid.index(i, j, k);
                    v.grid.data[idx] = static_cast<float>(votes[idx] >= 2 ? -d : d);
                }
            }
            const int finished = ++done;
            if (progress) progress(static_cast<double>(finished) / n[2]);
        }
    });
    update_range(v);
    return v;
}

}  // namespace quadcast::volume
