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

#include <algorithm>
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

namespace sdf_detail {

template <class T>
T dot3(const Vec<T, 3>& a, const Vec<T, 3>& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

/// The squared distance from p to the segment (a, b).
template <class T>
T segment_distance2(const Vec<T, 3>& p, const Vec<T, 3>& a, const Vec<T, 3>& b) {
    const Vec<T, 3> ab = b - a;
    const T l2 = dot3(ab, ab);
    const T t = l2 > T(0) ? std::clamp(dot3(p - a, ab) / l2, T(0), T(1)) : T(0);
    const Vec<T, 3> d = p - (a + ab * t);
    return dot3(d, d);
}

}  // namespace sdf_detail

/// The squared distance from p to the triangle (a, b, c) (Ericson, Real-Time Collision
/// Detection, 5.1.5), exact up to the rounding of T (double for the volumes; the slim tests take
/// long double). Degenerate and needle-like triangles (the sine of the angle at a below 1e-6) are
/// measured by their edges (error below 1e-6 of their size).
template <class T>
T point_triangle_distance2(const Vec<T, 3>& p, const Vec<T, 3>& a, const Vec<T, 3>& b, const Vec<T, 3>& c) {
    using sdf_detail::dot3;
    using sdf_detail::segment_distance2;
    const Vec<T, 3> ab = b - a, ac = c - a, ap = p - a;
    // Degenerate or needle-like triangles (sin of the angle at a below 1e-6; |ab x ac|^2 by
    // Lagrange's identity): the nearest of the edges, which lie within 1e-6 of the size of the
    // triangle from every point of it. Ericson's region tests are unreliable there.
    const T ab2 = dot3(ab, ab), ac2 = dot3(ac, ac), abac = dot3(ab, ac);
    if (!(ab2 * ac2 - abac * abac > T(1e-12) * (ab2 * ac2)))
        return std::min({segment_distance2(p, a, b), segment_distance2(p, b, c), segment_distance2(p, c, a)});
    auto d2 = [&](const Vec<T, 3>& q) { const Vec<T, 3> d = p - q; return dot3(d, d); };
    const T d1 = dot3(ab, ap), d2v = dot3(ac, ap);
    if (d1 <= T(0) && d2v <= T(0)) return d2(a);
    const Vec<T, 3> bp = p - b;
    const T d3 = dot3(ab, bp), d4 = dot3(ac, bp);
    if (d3 >= T(0) && d4 <= d3) return d2(b);
    const T vc = d1 * d4 - d3 * d2v;
    if (vc <= T(0) && d1 >= T(0) && d3 <= T(0)) return d2(a + ab * (d1 / (d1 - d3)));
    const Vec<T, 3> cp = p - c;
    const T d5 = dot3(ab, cp), d6 = dot3(ac, cp);
    if (d6 >= T(0) && d5 <= d6) return d2(c);
    const T vb = d5 * d2v - d1 * d6;
    if (vb <= T(0) && d2v >= T(0) && d6 <= T(0)) return d2(a + ac * (d2v / (d2v - d6)));
    const T va = d3 * d6 - d5 * d4;
    if (va <= T(0) && (d4 - d3) >= T(0) && (d5 - d6) >= T(0)) return d2(b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6))));
    const T den = va + vb + vc;
    const T v = vb / den, w = vc / den;
    return d2(a + ab * v + ac * w);
}

/// The signed distance volume of `mesh` (see above). Throws VolumeError for an empty mesh, a
/// mesh without extent, or bad options.
VolumeData signed_distance_volume(const TriangleMesh& mesh, const SdfOptions& options = {}, const Progress& progress = {});

}  // namespace quadcast::volume
