// quadcast/spline/partition.hpp -- the type-6 partition: 24 tetrahedra per cube, rotations R_t, barycentrics
#pragma once

#include <array>

#include "quadcast/linalg.hpp"
#include "quadcast/scalar.hpp"

namespace quadcast::spline {

/// Integer 3-vector (cube-local lattice points, stencil offsets).
using IVec3 = std::array<int, 3>;
/// Integer 3x3 matrix, row-major: m[row][col].
using IMat3 = std::array<IVec3, 3>;

/// Number of tetrahedra per cube of the type-6 partition.
inline constexpr int tets_per_cube = 24;

// Cube-local coordinates (spec §1.1): the cube is [-1,1]^3 with centre v_Q = 0, face centres
// ±e_a and vertices (±1,±1,±1); u = (x - v_Q) / (h/2).

/// Outer normal of face φ = 0..5: +x, -x, +y, -y, +z, -z (axis φ/2, sign + for even φ).
constexpr IVec3 face_normal(int phi) {
    IVec3 n{0, 0, 0};
    n[phi / 2] = (phi % 2 == 0) ? 1 : -1;
    return n;
}

/// Vertex ε = 0..3 of face φ, counter-clockwise seen from outside (spec §1.2): in-plane axes
/// (b, c) = ((a+1)%3, (a+2)%3) for s = +1, ((a+2)%3, (a+1)%3) for s = -1; (u_b, u_c) =
/// (-1,-1), (+1,-1), (+1,+1), (-1,+1).
constexpr IVec3 face_vertex(int phi, int eps) {
    const int a = phi / 2, s = (phi % 2 == 0) ? 1 : -1;
    const int b = s > 0 ? (a + 1) % 3 : (a + 2) % 3;
    const int c = s > 0 ? (a + 2) % 3 : (a + 1) % 3;
    constexpr int ub[4] = {-1, 1, 1, -1}, uc[4] = {-1, -1, 1, 1};
    IVec3 v{0, 0, 0};
    v[a] = s;
    v[b] = ub[eps & 3];
    v[c] = uc[eps & 3];
    return v;
}

/// Vertices of tetrahedron t = 4φ + ε: [v_Q, F_φ, vertex ε, vertex ε+1 mod 4] (spec §1.2).
constexpr std::array<IVec3, 4> tet_vertices(int t) {
    return {IVec3{0, 0, 0}, face_normal(t / 4), face_vertex(t / 4, t % 4), face_vertex(t / 4, (t % 4 + 1) % 4)};
}

/// R_t, the rotation (signed permutation) with R_t(T_0 vertex m) = T_t vertex m (spec §1.2).
/// T_0 = [0, e_x, (1,-1,-1), (1,1,-1)], so column 0 = F_t, column 1 = (v3 - v2)/2 and
/// column 2 = F_t - (v2 + v3)/2.
constexpr IMat3 rotation(int t) {
    const auto v = tet_vertices(t);
    IMat3 r{};
    for (int i = 0; i < 3; ++i) {
        r[i][0] = v[1][i];
        r[i][1] = (v[3][i] - v[2][i]) / 2;
        r[i][2] = v[1][i] - (v[2][i] + v[3][i]) / 2;
    }
    return r;
}

/// m · p for an integer matrix and vector.
constexpr IVec3 mat_apply(const IMat3& m, const IVec3& p) {
    IVec3 r{};
    for (int i = 0; i < 3; ++i) r[i] = m[i][0] * p[0] + m[i][1] * p[1] + m[i][2] * p[2];
    return r;
}

/// mᵀ · p.
constexpr IVec3 mat_apply_transpose(const IMat3& m, const IVec3& p) {
    IVec3 r{};
    for (int i = 0; i < 3; ++i) r[i] = m[0][i] * p[0] + m[1][i] * p[1] + m[2][i] * p[2];
    return r;
}

/// Barycentric coordinates w.r.t. T_0 of a point given in the frame of T_0 (u' = R_tᵀ u):
/// λ0 = 1 - u'x, λ1 = u'x + u'z, λ2 = -(u'y + u'z)/2, λ3 = (u'y - u'z)/2 (spec §1.5).
/// Numerics: λ2 = T(-0.5) * (u'y + u'z), λ3 = T(0.5) * (u'y - u'z) (exact scalings).
template <class T>
Vec<T, 4> barycentric_tet0(const Vec<T, 3>& up) {
    return {{T(1) - up[0], up[0] + up[2], T(-0.5) * (up[1] + up[2]), T(0.5) * (up[1] - up[2])}};
}

/// R_tᵀ u (cube-local point -> frame of T_0). Entries of R_t are 0/±1, so this is exact
/// (negations and copies; written as a signed selection, no multiplications).
template <class T>
Vec<T, 3> to_tet0_frame(int t, const Vec<T, 3>& u) {
    const IMat3 r = rotation(t);
    Vec<T, 3> up{};
    for (int j = 0; j < 3; ++j) {
        for (int i = 0; i < 3; ++i) {
            if (r[i][j] == 1) up[j] = u[i];
            if (r[i][j] == -1) up[j] = -u[i];
        }
    }
    return up;
}

/// R_t v' (frame of T_0 -> cube-local), exact like `to_tet0_frame`.
template <class T>
Vec<T, 3> from_tet0_frame(int t, const Vec<T, 3>& vp) {
    const IMat3 r = rotation(t);
    Vec<T, 3> v{};
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
            if (r[i][j] == 1) v[i] = vp[j];
            if (r[i][j] == -1) v[i] = -vp[j];
        }
    }
    return v;
}

/// Barycentric coordinates w.r.t. T_t of the cube-local point u.
template <class T>
Vec<T, 4> barycentric(int t, const Vec<T, 3>& u) {
    return barycentric_tet0(to_tet0_frame(t, u));
}

/// Barycentric directions of the cube-local axes for tetrahedron t: column a holds
/// λ(e_a) = (∇λm · R_tᵀ e_a)_m (the "λ(x), λ(y), λ(z)" of Kalbe & Zeilfelder 2008, Sect. 5.3),
/// with ∇λ0 = (-1,0,0), ∇λ1 = (1,0,1), ∇λ2 = (0,-1/2,-1/2), ∇λ3 = (0,1/2,-1/2) in the frame of T_0.
/// Entries are 0, ±1/2, ±1 (exact). The world gradient is (2/h) · bb::gradient(vp, dirs).
template <class T>
Mat<T, 4, 3> barycentric_directions(int t) {
    constexpr int grad2[4][3] = {{-2, 0, 0}, {2, 0, 2}, {0, -1, -1}, {0, 1, -1}};  // 2·∇λm
    const IMat3 r = rotation(t);
    Mat<T, 4, 3> d{};
    for (int a = 0; a < 3; ++a) {
        for (int m = 0; m < 4; ++m) {
            // ∇λm · (row a of R_t)
            const int twice = grad2[m][0] * r[a][0] + grad2[m][1] * r[a][1] + grad2[m][2] * r[a][2];
            d[a][m] = T(0.5 * static_cast<double>(twice));
        }
    }
    return d;
}

/// The tetrahedron of the cube containing the cube-local point u (host-side point location,
/// spec §1.5): face axis a = argmax |u_m| (first on ties), s = sgn u_a, then ε from the
/// in-plane coordinates: 0 if u_c <= -|u_b|, else 1 if u_b >= |u_c|, else 2 if u_c >= |u_b|,
/// else 3. Not traced (integer result by branches).
template <class T>
int locate_tet(const Vec<T, 3>& u) {
    const T ax = abs(u[0]), ay = abs(u[1]), az = abs(u[2]);
    int a = 0;
    if (ay > ax && ay >= az) a = 1;
    else if (az > ax && az > ay) a = 2;
    const int s = u[a] < T(0) ? -1 : 1;
    const int phi = 2 * a + (s < 0 ? 1 : 0);
    const int b = s > 0 ? (a + 1) % 3 : (a + 2) % 3;
    const int c = s > 0 ? (a + 2) % 3 : (a + 1) % 3;
    const T ub = u[b], uc = u[c];
    int eps = 3;
    if (uc <= -abs(ub)) eps = 0;
    else if (ub >= abs(uc)) eps = 1;
    else if (uc >= abs(ub)) eps = 2;
    return 4 * phi + eps;
}

}  // namespace quadcast::spline
