// tools/quadcast/bench_slim_cgal.hpp -- what `quadcast bench slim` takes from CGAL: edge-collapse simplification and point-to-mesh distance
#pragma once

// The only translation unit that includes CGAL's headers is bench_slim_cgal.cpp (they are slow to
// compile); this interface speaks quadcast's vector types.
//  - simplify_triangles: CGAL's Surface_mesh_simplification::edge_collapse with its default
//    policies (Lindstrom-Turk cost and placement) until fewer than `edges` edges remain.
//  - MeshDistance: the Euclidean distance of a point to the nearest triangle of a mesh, CGAL's
//    AABB tree with accelerated distance queries (thread-safe once made).

#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include "quadcast/linalg.hpp"

namespace quadcast::cli {

/// An indexed triangle mesh in double.
struct TriangleMesh {
    std::vector<Vec3<double>> positions;
    std::vector<std::array<std::uint32_t, 3>> triangles;
    /// Edges of the triangles (each shared edge once): V + F - 2 for a closed genus-0 mesh; counted.
    std::size_t edge_count() const;
};

/// The mesh as CGAL Surface_mesh (faces CGAL refuses as non-manifold are dropped and counted in
/// `dropped`), collapsed until fewer than `edges` edges remain, garbage collected. Throws
/// std::runtime_error when CGAL reports an error.
TriangleMesh simplify_triangles(const TriangleMesh& mesh, std::size_t edges, std::size_t* dropped = nullptr);

/// The distance of points to a triangle mesh (CGAL AABB tree of its triangles).
class MeshDistance {
public:
    explicit MeshDistance(const TriangleMesh& mesh);
    ~MeshDistance();
    MeshDistance(const MeshDistance&) = delete;
    MeshDistance& operator=(const MeshDistance&) = delete;
    /// The distance of p to the nearest point of the mesh (safe to call from several threads).
    double distance(const Vec3<double>& p) const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace quadcast::cli
