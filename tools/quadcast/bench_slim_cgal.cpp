// tools/quadcast/bench_slim_cgal.cpp -- CGAL's edge-collapse simplification and AABB-tree distances for `quadcast bench slim`
#include "bench_slim_cgal.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <unordered_set>

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Simple_cartesian.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/Surface_mesh_simplification/Policies/Edge_collapse/Count_stop_predicate.h>
#include <CGAL/Surface_mesh_simplification/edge_collapse.h>

namespace quadcast::cli {

namespace {

using Kernel = CGAL::Simple_cartesian<double>;
using Point = Kernel::Point_3;
using SurfaceMesh = CGAL::Surface_mesh<Point>;

}  // namespace

std::size_t TriangleMesh::edge_count() const {
    std::unordered_set<std::uint64_t> edges;
    edges.reserve(triangles.size() * 2);
    for (const auto& t : triangles)
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t a = t[std::size_t(k)], b = t[std::size_t((k + 1) % 3)];
            edges.insert((std::uint64_t(std::min(a, b)) << 32) | std::max(a, b));
        }
    return edges.size();
}

TriangleMesh simplify_triangles(const TriangleMesh& mesh, std::size_t edges, std::size_t* dropped) {
    // Build the Surface_mesh (CGAL refuses faces that would make it non-manifold)
    SurfaceMesh sm;
    std::vector<SurfaceMesh::Vertex_index> v;
    v.reserve(mesh.positions.size());
    for (const Vec3<double>& p : mesh.positions) v.push_back(sm.add_vertex(Point(p[0], p[1], p[2])));
    std::size_t refused = 0;
    for (const auto& t : mesh.triangles)
        if (sm.add_face(v[t[0]], v[t[1]], v[t[2]]) == SurfaceMesh::null_face()) ++refused;
    if (dropped) *dropped = refused;

    // Collapse edges (Lindstrom-Turk cost and placement, CGAL's defaults)
    namespace SMS = CGAL::Surface_mesh_simplification;
    SMS::Count_stop_predicate<SurfaceMesh> stop(edges);
    SMS::edge_collapse(sm, stop);
    sm.collect_garbage();

    // Back to an indexed mesh (indices are contiguous after collect_garbage)
    TriangleMesh out;
    out.positions.reserve(sm.number_of_vertices());
    for (const SurfaceMesh::Vertex_index vi : sm.vertices()) {
        const Point& p = sm.point(vi);
        out.positions.push_back(Vec3<double>{{p.x(), p.y(), p.z()}});
    }
    out.triangles.reserve(sm.number_of_faces());
    for (const SurfaceMesh::Face_index f : sm.faces()) {
        std::array<std::uint32_t, 3> tri{};
        int k = 0;
        for (const SurfaceMesh::Vertex_index vi : CGAL::vertices_around_face(sm.halfedge(f), sm)) {
            if (k == 3) throw std::runtime_error("CGAL edge_collapse left a face with more than 3 vertices");
            tri[std::size_t(k++)] = std::uint32_t(vi.idx());
        }
        if (k != 3) throw std::runtime_error("CGAL edge_collapse left a face with fewer than 3 vertices");
        out.triangles.push_back(tri);
    }
    return out;
}

struct MeshDistance::Impl {
    using Triangles = std::vector<Kernel::Triangle_3>;
    using Primitive = CGAL::AABB_triangle_primitive<Kernel, Triangles::const_iterator>;
    using Tree = CGAL::AABB_tree<CGAL::AABB_traits<Kernel, Primitive>>;
    Triangles triangles;
    Tree tree;
};

MeshDistance::MeshDistance(const TriangleMesh& mesh) : impl_(std::make_unique<Impl>()) {
    if (mesh.triangles.empty()) throw std::invalid_argument("MeshDistance: the mesh has no triangles");
    auto P = [&](std::uint32_t i) { return Point(mesh.positions[i][0], mesh.positions[i][1], mesh.positions[i][2]); };
    impl_->triangles.reserve(mesh.triangles.size());
    for (const auto& t : mesh.triangles) impl_->triangles.emplace_back(P(t[0]), P(t[1]), P(t[2]));
    impl_->tree.insert(impl_->triangles.begin(), impl_->triangles.end());
    impl_->tree.build();
    impl_->tree.accelerate_distance_queries();
    // (one query here, so that the lazily built search structure exists before threads query)
    (void)impl_->tree.squared_distance(P(mesh.triangles[0][0]));
}

MeshDistance::~MeshDistance() = default;

double MeshDistance::distance(const Vec3<double>& p) const {
    return std::sqrt(impl_->tree.squared_distance(Point(p[0], p[1], p[2])));
}

}  // namespace quadcast::cli
