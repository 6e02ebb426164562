// quadcast/spline/quadric_pieces.hpp -- the pieces of a QSS spline as quadrics clipped to their
// tetrahedra (Stoll et al. 2006, sec. 5.1.2)
#pragma once

// A QSS spline is quadratic on each tetrahedron of the type-6 partition, so piece t of a cube,
// minus the isovalue, is a quadric, exactly (bb::quadric_from_bezier). Host-side preparation
// (double), not traced: the quadric renderers then draw each piece clipped to its tetrahedron.

#include "quadcast/bb/quadric_form.hpp"
#include "quadcast/quadric.hpp"
#include "quadcast/spline/partition.hpp"
#include "quadcast/spline/quasi_interpolation.hpp"

namespace quadcast::spline {

/// Tetrahedron t of the type-6 partition in cube-local coordinates u (the cube [-1, 1]^3,
/// `tet_vertices`).
template <class T>
BoundingTet<T> local_tet(int t) {
    const std::array<IVec3, 4> v = tet_vertices(t);
    BoundingTet<T> r{};
    for (int k = 0; k < 4; ++k) r.p[k] = vec3(T(v[k][0]), T(v[k][1]), T(v[k][2]));
    return r;
}

/// Piece t of a QSS cube with determining set `d`, minus `rho`, as the quadric u~^T Q u~ in
/// cube-local coordinates: the coefficients of `tet_from_determining_set`, each less rho, then
/// `bb::quadric_from_bezier` on `local_tet(t)`.
/// Numerics: as those two; the coefficients c - rho rounded once each.
template <class T>
Quadric<T> qss_piece_quadric(const DeterminingSet<T, 2>& d, int t, T rho) {
    bb::BezierTet<T, 2> b = tet_from_determining_set<2>(d, t);
    for (int n = 0; n < b.size; ++n) b[n] = b[n] - rho;
    return bb::quadric_from_bezier(b, local_tet<T>(t));
}

/// A quadric in the cube-local coordinates u = 2 (x - centre) / spacing (per axis) of a cube
/// centred at `centre` with sample spacing `spacing`, given in x: Q_x = A^T Q_u A with A the
/// affine map x~ -> u~ (`transform_with_inverse`).
/// Numerics: A's entries 2 / s and -2 c / s rounded once each, then as transform_with_inverse.
template <class T>
Quadric<T> cube_local_to_world(const Quadric<T>& q_u, const Vec3<T>& centre, const Vec3<T>& spacing) {
    Mat4<T> a = zero_mat<T, 4, 4>();
    for (int i = 0; i < 3; ++i) {
        a[i][i] = T(2) / spacing[i];
        a[3][i] = T(-2) * centre[i] / spacing[i];
    }
    a[3][3] = T(1);
    return transform_with_inverse(q_u, a);
}

}  // namespace quadcast::spline
