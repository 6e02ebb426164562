// quadcast/volume/sdf.hpp -- signed distance volumes from triangle meshes (OFF)
#pragma once

// signed_distance_volume samples the signed Euclidean distance to a triangle mesh on a regular
// grid: negative inside, positive outside, so the isosurface 0 is the mesh.
//   * Distance: exact point-triangle distance (closest point by Voronoi regions, in double) to
//     the nearest triangle, found with a bounding volume hierarchy (median split, 4 triangles
//     per leaf); the distance of the previous sample in the row + h bounds the search (the
//     distance is 1-Lipschitz), which prunes almost every node.
//   * Sign: ray parity along grid rows, for each of the three axes, and the majority of the
//     three votes (robust against a row grazing an edge and against small holes). A row's
//     crossings are found by a 2-D point-in-triangle test in the projection with a consistent
//     tie rule (edge functions are evaluated with the endpoints in vertex-index order, points on
//     an edge belong to the triangle for which the edge is a "top-left" edge), so a row
//     through an edge or vertex shared by two triangles counts one crossing, not zero or two.
//     For a closed, consistently oriented mesh (armadillo.off, bunny00.off) every vote agrees.
//   * Grid: `resolution` samples along the longest side of the mesh's bounding box, the same
//     spacing h on the other axes, `padding` extra samples on each side, centred on the box.
//   * Threads: TBB parallel_for over z slices; Progress is reported per slice.

#include <array>
#include <string>
#include <vector>

#include "quadcast/volume/volume.hpp"

namespace quadcast::volume {

struct TriangleMesh {
    std::vector<Vec3d> vertices;
    std::vector<std::array<int, 3>> triangles;
    std::string source;
};

/// Reads a plain ASCII OFF file (the scene component's parser: errors name file:line and field) and
/// fan-triangulates its faces (v0, vk, vk+1). Faces with repeated vertices give degenerate
/// triangles, which are kept (they have a distance but never count as a crossing).
TriangleMesh read_off_mesh(const std::string& path, std::vector<std::string>* warnings = nullptr);

struct SdfOptions {
    int resolution = 64;  ///< samples along the longest side of the bounding box (>= 8)
    int padding = 3;      ///< samples added outside the bounding box on each side (>= 0)
};

/// The squared distance from p to the triangle (a, b, c) (Ericson, Real-Time Collision
/// Detection, 5.1.5), exact up to double rounding. Degenerate and needle-like triangles (the
/// sine of the angle at a below 1e-6) are measured by their edges (error below 1e-6 of their size).
double point_triangle_distance2(const Vec3d& p, const Vec3d& a, const Vec3d& b, const Vec3d& c);

/// The signed distance volume of `mesh` (see above). Throws VolumeError for an empty mesh, a
/// mesh without extent, or bad options.
VolumeData signed_distance_volume(const TriangleMesh& mesh, const SdfOptions& options = {}, const Progress& progress = {});

}  // namespace quadcast::volume
