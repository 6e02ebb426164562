// quadcast/skin/skin.hpp -- molecular skin surfaces (Edelsbrunner) as quadrics clipped to the
// tetrahedra of CGAL's triangulated mixed complex
#pragma once

// The skin surface of a set of balls with shrink factor s in (0, 1) (Edelsbrunner 1999, "Deformable
// smooth surface design") is a C1 surface made of quadric patches: CGAL's Skin_surface_3 builds the
// mixed complex of the weighted points and triangulates it; each tetrahedron of that triangulation
// carries one quadratic function whose zero set is the skin there (f < 0 inside). This component
// reads each cell's function back as a quadcast quadric (its Hessian and gradient from CGAL's own
// gradient(), its constant from value(), checked against value() at the cell's 10 quadratic nodes)
// and keeps the cells the surface crosses (the BB coefficients of f on the cell change sign).
//
// CGAL (header-only, with -frounding-math) is confined to src/skin/skin.cpp: nothing here includes
// it. Programs that link quadcast_skin and call install_scene_builder() draw the "skin" style of
// PDB objects.

#include <array>
#include <cstddef>
#include <memory>
#include <vector>

#include "quadcast/quadric.hpp"
#include "quadcast/scene/scene.hpp"

namespace quadcast::skin {

using scene::Vec3d;

/// One tetrahedron of the triangulated mixed complex that the surface crosses, with its quadric in
/// world coordinates (double) and the ball nearest to its centroid (power distance of the grown balls).
struct Piece {
    std::array<Vec3d, 4> tet;       ///< the clip tetrahedron: the cell, or a part of it (`refine_levels`)
    std::array<Vec3d, 4> cell_tet;  ///< the cell of the triangulated mixed complex it lies in
    Quadric<double> q;
    std::size_t ball = 0;
    std::size_t cell = 0;  ///< index for SkinSurface::cell_value / cell_gradient
};

/// Figures of a build.
struct Stats {
    std::size_t balls = 0;
    std::size_t cells = 0;         ///< finite tetrahedra of the triangulated mixed complex
    std::size_t cells_crossed = 0; ///< cells the surface crosses
    std::size_t pieces = 0;        ///< their clip tetrahedra (`refine_levels`: the crossed parts of refined cells)
    double seconds_cgal = 0;       ///< CGAL: regular triangulation and mixed complex
    double seconds_pieces = 0;     ///< reading the quadrics back, checking, selecting
    double worst_check = 0;        ///< max |quadric - CGAL value()| at the cells' nodes, relative to the cell's scale
};

/// The skin surface of `balls` (scene::SkinBall: centre and radius; the balls handed to CGAL are
/// grown by 1/sqrt(shrink), so that an isolated ball's skin is the ball's sphere). Throws
/// std::invalid_argument (no balls, a shrink factor outside (0, 1), a radius <= 0 or a
/// non-finite coordinate) and std::runtime_error when a recovered quadric fails its check.
class SkinSurface {
public:
    /// `refine_levels`: how many times a crossed cell may be refined into smaller clip
    /// tetrahedra (`bb::refine_crossing`, at most 4 of 8 children kept per step); 0 keeps the cells.
    SkinSurface(const std::vector<scene::SkinBall>& balls, double shrink, int refine_levels = 2);
    ~SkinSurface();
    SkinSurface(const SkinSurface&) = delete;
    SkinSurface& operator=(const SkinSurface&) = delete;

    const std::vector<Piece>& pieces() const;
    const Stats& stats() const;
    /// CGAL's value() and gradient() of the cell of a piece, at any point.
    double cell_value(std::size_t cell, const Vec3d& x) const;
    Vec3d cell_gradient(std::size_t cell, const Vec3d& x) const;
    /// CGAL's value() at x, in the cell of the mixed complex that contains it (located).
    double value(const Vec3d& x) const;
    Vec3d gradient(const Vec3d& x) const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

/// CGAL's own triangulated skin (make_skin_surface_mesh_3 with `subdivisions` steps of its
/// refinement), for comparisons: triangle count, seconds, and the worst |value()| / |gradient()|
/// (a distance to the skin, first order) over the vertices and the midpoints of the triangles.
struct MeshFigures {
    std::size_t triangles = 0;
    std::size_t vertices = 0;
    double seconds = 0;
    double worst_distance = 0;
};
MeshFigures cgal_mesh(const std::vector<scene::SkinBall>& balls, double shrink, int subdivisions);

/// The pieces as scene quadrics (Bound::tetrahedron, one-sided: f < 0 inside), each with `material`
/// and its ball's colour. This is the scene::SkinBuildFunction.
std::vector<scene::Quadric> build_scene_skin(const std::vector<scene::SkinBall>& balls, double shrink, const scene::Material& material);

/// Installs build_scene_skin as scene::skin_build_function (call once before loading scenes).
void install_scene_builder();

}  // namespace quadcast::skin
