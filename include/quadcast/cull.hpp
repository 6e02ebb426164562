// quadcast/cull.hpp -- conservative per-quadric back-face culling against sphere and tetrahedron bounds
#pragma once

#include "quadcast/linalg.hpp"
#include "quadcast/quadric.hpp"
#include "quadcast/ray.hpp"
#include "quadcast/scalar.hpp"

namespace quadcast {

// The test (Stoll et al. 2006, sec. 4.4.4). In eye-origin coordinates (eq. 9) a hit y = lambda v,
// lambda > 0, on the quadric y^T A' y + 2 b'^T y + c' = 0 is front-facing when v . (A' y + b') < 0,
// i.e. (times lambda) y^T A' y + b'^T y < 0, i.e. (using the surface equation) c' + b'^T y > 0
// (eq. 16-17). So if c' + max_{y in bound} b'^T y < 0, no ray has a front-facing hit inside the
// bound and the quadric can be skipped: eq. 18 (sphere: max = c_sph'^T b' + r |b'|) and eq. 19
// (tetrahedron: max over the corners). This holds for every y != 0 in the bound, so also when
// the eye is inside it.
//
// Rounding. The test D = c' + max(...) < 0 is computed in T, from a rounded eye-origin quadric.
// We cull only when D < -margin, margin = 16 eps S, where S bounds the magnitudes of everything
// that was summed (eps = machine_epsilon<T>(); componentwise |.|):
//     m_b = |b| + |A| |e|                      (bounds b' = b + A e and its partial sums)
//     m_c = |c| + |e| . (m_b + |b|)            (bounds c' = c + e . (b' + b))
//     S   = m_c + |y0| . m_b + r |m_b|         (sphere, y0 = center - e)
//     S   = m_c + max_i |p_i - e| . m_b        (tetrahedron)
// A standard forward error analysis (gamma_n = n u / (1 - n u), u = eps / 2) bounds the error of
// c' by gamma_9 m_c, of b' by gamma_4 m_b, of each dot product term by gamma_8 (.) and of the
// final sums by 2u S, in total below gamma_12 S < 6.1 eps S; S itself is computed from
// nonnegative terms with relative error < gamma_10. 16 eps S covers all of it with a factor 2.5
// to spare, so whenever `cull_*` says true, the EXACT D of the given T inputs is negative, and no
// ray has an exactly computed front-facing hit inside the bound. The margin is relative
// (~2e-6 in float): it costs almost no culling. Measured (tests/core/test_cull.cpp, 3000
// near-threshold configurations, float and double): |D - D_exact| <= 0.92 eps S, and the same
// test without the margin culls ~150 of them whose exact D is >= 0.
// NaN or infinite inputs never cull (every comparison with NaN is false).

namespace cull_detail {

/// Magnitude bounds m_b, m_c of the eye-origin transform (see above).
/// Numerics: the same association as `translate_to_eye`, on absolute values.
template <class T>
struct EyeMagnitudes {
    Vec3<T> mb;
    T mc;
};

template <class T>
Vec3<T> abs3(const Vec3<T>& v) { return vec3(abs(v[0]), abs(v[1]), abs(v[2])); }

template <class T>
EyeMagnitudes<T> eye_magnitudes(const Quadric<T>& q, const Vec3<T>& e) {
    Mat3<T> abs_a{};
    for (int j = 0; j < 3; ++j) abs_a[j] = abs3(Vec3<T>{{q.q[j][0], q.q[j][1], q.q[j][2]}});
    const Vec3<T> abs_b = abs3(xyz(q.q[3]));
    const Vec3<T> abs_e = abs3(e);
    const Vec3<T> mb = abs_b + abs_a * abs_e;
    return {mb, abs(q.q[3][3]) + dot(abs_e, mb + abs_b)};
}

/// 16 eps, the margin factor (see the comment above).
template <class T>
T margin_factor() { return T(16) * machine_epsilon<T>(); }

}  // namespace cull_detail

/// Per-quadric back-face culling with a bounding sphere, inputs in world coordinates
/// (Stoll et al. 2006, eq. 18 ff.): translate to the eye (eq. 9), then cull when
/// c' + c_sph'^T b' + r |b'| < -margin (c_sph' = center - eye). True means: no ray from the eye
/// has a front-facing hit inside the sphere, also under rounding (see above).
/// Numerics: `translate_to_eye`; D = (c' + dot(c_sph', b')) + r * sqrt(dot(b', b'));
/// margin = 16 eps S with S as described above.
template <class T>
mask_t<T> cull_sphere(const Quadric<T>& q, const Vec3<T>& eye, const Vec3<T>& center, const T& radius) {
    using namespace cull_detail;
    // Move to eye-origin coordinates.
    const Quadric<T> qe = translate_to_eye(q, eye);
    const Vec3<T> bp = xyz(qe.q[3]);
    const Vec3<T> y0 = center - eye;
    // Evaluate eq. 18 and its rounding margin.
    const T d = (qe.q[3][3] + dot(y0, bp)) + radius * length(bp);
    const EyeMagnitudes<T> m = eye_magnitudes(q, eye);
    const T s = (m.mc + dot(abs3(y0), m.mb)) + abs(radius) * length(m.mb);
    return d < -(margin_factor<T>() * s);
}

/// `cull_sphere` for a BoundingSphere.
template <class T>
mask_t<T> cull_sphere(const Quadric<T>& q, const Vec3<T>& eye, const BoundingSphere<T>& s) {
    return cull_sphere(q, eye, s.center, s.radius);
}

/// Per-quadric back-face culling with a bounding tetrahedron, inputs in world coordinates
/// (Stoll et al. 2006, eq. 19): cull when c' + max_i (p_i - eye)^T b' < -margin.
/// Numerics: `translate_to_eye`; the max is a left fold of `max` over i = 0..3 (plus a sum of
/// the four dots that makes NaN/inf corners refuse to cull);
/// margin = 16 eps S with S as described above.
template <class T>
mask_t<T> cull_tet(const Quadric<T>& q, const Vec3<T>& eye, const BoundingTet<T>& t) {
    using namespace cull_detail;
    const Quadric<T> qe = translate_to_eye(q, eye);
    const Vec3<T> bp = xyz(qe.q[3]);
    const EyeMagnitudes<T> m = eye_magnitudes(q, eye);
    // Maximise b'^T y and its magnitude bound over the corners.
    // (`max` drops a NaN operand, so the sum `probe` carries any NaN/inf into the result.)
    Vec3<T> y = t.p[0] - eye;
    T best = dot(y, bp);
    T best_mag = dot(abs3(y), m.mb);
    T probe = best;
    for (int i = 1; i < 4; ++i) {
        y = t.p[i] - eye;
        const T di = dot(y, bp);
        best = max(best, di);
        best_mag = max(best_mag, dot(abs3(y), m.mb));
        probe = probe + di;
    }
    const T d = qe.q[3][3] + best;
    return (d < -(margin_factor<T>() * (m.mc + best_mag))) && isfinite(probe);
}

/// The same tests for a quadric that is ALREADY in eye-origin coordinates (the paper's form, for
/// a vertex stage that has Q' at hand). The margin only covers the rounding of this test, so it
/// is conservative with respect to the given Q', not to a world quadric it was rounded from;
/// prefer the world-coordinate versions above.
/// Numerics: m_b = |b'|, m_c = |c'| in the formulas above.
template <class T>
mask_t<T> cull_sphere_eye(const Quadric<T>& q_eye, const Vec3<T>& center_eye, const T& radius) {
    using namespace cull_detail;
    const Vec3<T> bp = xyz(q_eye.q[3]);
    const T d = (q_eye.q[3][3] + dot(center_eye, bp)) + radius * length(bp);
    const Vec3<T> mb = abs3(bp);
    const T s = (abs(q_eye.q[3][3]) + dot(abs3(center_eye), mb)) + abs(radius) * length(mb);
    return d < -(margin_factor<T>() * s);
}

/// Tetrahedron version of `cull_sphere_eye`; corners in eye-origin coordinates.
template <class T>
mask_t<T> cull_tet_eye(const Quadric<T>& q_eye, const BoundingTet<T>& t_eye) {
    using namespace cull_detail;
    const Vec3<T> bp = xyz(q_eye.q[3]);
    const Vec3<T> mb = abs3(bp);
    T best = dot(t_eye.p[0], bp);
    T best_mag = dot(abs3(t_eye.p[0]), mb);
    T probe = best;
    for (int i = 1; i < 4; ++i) {
        const T di = dot(t_eye.p[i], bp);
        best = max(best, di);
        best_mag = max(best_mag, dot(abs3(t_eye.p[i]), mb));
        probe = probe + di;
    }
    return (q_eye.q[3][3] + best < -(margin_factor<T>() * (abs(q_eye.q[3][3]) + best_mag))) && isfinite(probe);
}

}  // namespace quadcast
