// quadcast/quadric.hpp -- quadrics as symmetric homogeneous 4x4 matrices: conversions, evaluation, transforms
#pragma once

#include <algorithm>
#include <cmath>
#include <concepts>
#include <limits>
#include <stdexcept>
#include <type_traits>
#include <utility>

#include "quadcast/linalg.hpp"
#include "quadcast/scalar.hpp"

namespace quadcast {

// Precision of a scalar type -----------------------------------------------------------------

/// The IEEE format a scalar type computes in: `T` itself for `float`/`double`; a non-builtin
/// scalar (the code generator's tracer) records GLSL `float`, i.e. binary32. A future traced
/// type of another precision specialises this template.
template <class T, class = void>
struct float_format { using type = float; };
template <class T>
struct float_format<T, std::enable_if_t<std::is_floating_point_v<T>>> { using type = T; };
template <class T>
using float_format_t = typename float_format<T>::type;

/// Machine epsilon (distance from 1 to the next number) of T's format, as a T literal:
/// 2^-23 for float and the traced scalar, 2^-52 for double. The unit roundoff is half of it.
template <class T>
T machine_epsilon() { return T(std::numeric_limits<float_format_t<T>>::epsilon()); }

// Representation -------------------------------------------------------------------------------

/// A quadric as the symmetric homogeneous 4x4 matrix Q~ of Stoll et al. 2006, eq. 4:
///
///     Q~ = | A   b |      f(x) = x~^T Q~ x~ = x^T A x + 2 b^T x + c,   x~ = (x, 1)
///          | b^T c |
///
/// `q[j][i]` is column j, row i (linalg's column-major layout, like GLSL `mat4`): A is the
/// upper-left 3x3 block, b is column 3 (`q[3][0..2]`) and row 3 (`q[0..2][3]`), c is `q[3][3]`.
/// Every function here keeps Q exactly symmetric (entries (i,j) and (j,i) are the same value).
/// The interior is f < 0, the exterior f > 0 and the normal is the direction of grad f.
template <class T>
struct Quadric {
    Mat4<T> q;
};

/// The 10 monomial coefficients of Stoll et al. 2006, sec. 4.1, in this (documented) order:
///     f = k000 + k100 x + k010 y + k001 z + k110 xy + k011 yz + k101 zx + k200 x^2 + k020 y^2 + k002 z^2.
template <class T>
struct Coefficients10 {
    T k000, k100, k010, k001, k110, k011, k101, k200, k020, k002;
};

/// The (A, b, c) form of Stoll et al. 2006, eq. 2-3: f(x) = (x^T A + 2 b^T) x + c, A symmetric.
template <class T>
struct QuadricABC {
    Mat3<T> A;
    Vec3<T> b;
    T c;
};

/// A quadratic graph function z = k00 + k10 x + k01 y + k11 xy + k20 x^2 + k02 y^2
/// (Stoll et al. 2006, sec. 4).
template <class T>
struct GraphCoefficients {
    T k00, k10, k01, k11, k20, k02;
};

/// The zero matrix (not a surface; used as the "no quadric" value of host conversions).
template <class T>
Quadric<T> zero_quadric() { return {zero_mat<T, 4, 4>()}; }

/// Q~ from (A, b, c) (Stoll et al. 2006, eq. 4). Only the upper triangle of `A` is read
/// (A is symmetric by definition), so the result is exactly symmetric whatever the caller passes.
/// Numerics: copies only.
template <class T>
Quadric<T> quadric_from_abc(const Mat3<T>& A, const Vec3<T>& b, const T& c) {
    Quadric<T> r{};
    for (int j = 0; j < 3; ++j)
        for (int i = 0; i <= j; ++i) { r.q[j][i] = A[j][i]; r.q[i][j] = A[j][i]; }
    for (int i = 0; i < 3; ++i) { r.q[3][i] = b[i]; r.q[i][3] = b[i]; }
    r.q[3][3] = c;
    return r;
}

/// (A, b, c) of a quadric (Stoll et al. 2006, eq. 4). Numerics: copies only.
template <class T>
QuadricABC<T> to_abc(const Quadric<T>& q) {
    return {upper3(q.q), xyz(q.q[3]), q.q[3][3]};
}

/// Q~ from the 10 coefficients (Stoll et al. 2006, eq. 3): c = k000, b = k100/2 ..., the
/// mixed terms are halved off the diagonal. Numerics: 6 multiplications by 0.5 (exact unless
/// the result is subnormal).
template <class T>
Quadric<T> quadric_from_coefficients(const Coefficients10<T>& k) {
    const T h = T(0.5);
    Mat3<T> A{};
    A[0][0] = k.k200;  A[1][1] = k.k020;  A[2][2] = k.k002;
    A[1][0] = A[0][1] = h * k.k110;   // xy
    A[2][1] = A[1][2] = h * k.k011;   // yz
    A[2][0] = A[0][2] = h * k.k101;   // zx
    return quadric_from_abc(A, vec3(h * k.k100, h * k.k010, h * k.k001), k.k000);
}

/// The 10 coefficients of a quadric (inverse of `quadric_from_coefficients`).
/// Numerics: 6 multiplications by 2 (exact unless they overflow); reads the upper triangle.
template <class T>
Coefficients10<T> coefficients(const Quadric<T>& q) {
    const T two = T(2);
    const Mat4<T>& m = q.q;
    return {m[3][3],
            two * m[3][0], two * m[3][1], two * m[3][2],
            two * m[1][0], two * m[2][1], two * m[2][0],
            m[0][0], m[1][1], m[2][2]};
}

/// The implicit form f_I(x, y, z) = z - f_G(x, y) of a graph function (Stoll et al. 2006, sec. 4):
/// positive above the graph, so the normal points towards +z.
/// Numerics: negations, the halving of `quadric_from_coefficients`.
template <class T>
Quadric<T> quadric_from_graph(const GraphCoefficients<T>& g) {
    const T zero = T(0);
    return quadric_from_coefficients(Coefficients10<T>{-g.k00, -g.k10, -g.k01, T(1), -g.k11, zero, zero,
                                                       -g.k20, -g.k02, zero});
}

// Evaluation -----------------------------------------------------------------------------------

/// f(x) = x~^T Q~ x~ (Stoll et al. 2006, eq. 4).
/// Numerics: `dot(x~, Q~ * x~)`: r_i = ((Q_i0 x + Q_i1 y) + Q_i2 z) + Q_i3, then
/// f = ((x r_0 + y r_1) + z r_2) + r_3 (left folds, no FMA; the products by 1 are exact).
template <class T>
T evaluate(const Quadric<T>& q, const Vec3<T>& x) {
    const Vec4<T> xh = vec4(x, T(1));
    return dot(xh, q.q * xh);
}

/// A x + b = (Q~ x~)|xyz, the surface normal direction of Stoll et al. 2006, eq. 11.
/// This is HALF the gradient of f (f = x^T A x + 2 b^T x + c has grad f = 2 (A x + b)).
/// Numerics: component i is ((A_i0 x + A_i1 y) + A_i2 z) + b_i.
template <class T>
Vec3<T> half_gradient(const Quadric<T>& q, const Vec3<T>& x) {
    return xyz(q.q * vec4(x, T(1)));
}

/// grad f = 2 (A x + b). Numerics: `half_gradient` times 2 (exact).
template <class T>
Vec3<T> gradient(const Quadric<T>& q, const Vec3<T>& x) {
    return T(2) * half_gradient(q, x);
}

// Transforms -----------------------------------------------------------------------------------

/// The quadric in new coordinates y~ = M x~, given N = M^-1 directly:
/// Q' = N^T Q N = M^-T Q M^-1, so that f'(M x) = f(x) (Sigg et al. 2006, sec. 3; Stoll et al.
/// 2006, eq. 23-25 for the affine case). This is the version to trace: it never inverts.
/// Numerics: w_j = Q * N[j] (left folds over Q's columns), then Q'_ij = dot(N[i], w_j) for
/// i <= j (left fold) and mirrored, so Q' is exactly symmetric.
template <class T>
Quadric<T> transform_with_inverse(const Quadric<T>& q, const Mat4<T>& m_inv) {
    Vec4<T> w[4];
    for (int j = 0; j < 4; ++j) w[j] = q.q * m_inv[j];
    Quadric<T> r{};
    for (int j = 0; j < 4; ++j)
        for (int i = 0; i <= j; ++i) {
            const T v = dot(m_inv[i], w[j]);
            r.q[j][i] = v;
            r.q[i][j] = v;
        }
    return r;
}

/// Host-only: the inverse of a 4x4 matrix by Gauss-Jordan elimination with partial pivoting in
/// long double, rounded to T; the one host 4x4 inverse of the library. Throws
/// std::invalid_argument if M has a non-finite entry, is zero, or is singular (a pivot at most
/// 1e-12 times the largest entry). Not for tracing.
template <std::floating_point T>
Mat4<T> host_inverse(const Mat4<T>& m) {
    long double a[4][8];
    long double scale = 0;
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) {
            if (!std::isfinite(m[j][i])) throw std::invalid_argument("quadcast::host_inverse: non-finite matrix entry");
            a[i][j] = static_cast<long double>(m[j][i]);
            a[i][4 + j] = (i == j) ? 1.0L : 0.0L;
            scale = std::max(scale, std::fabs(a[i][j]));
        }
    if (scale == 0) throw std::invalid_argument("quadcast::host_inverse: zero matrix");
    for (int k = 0; k < 4; ++k) {
        // Pick the largest pivot in column k.
        int p = k;
        for (int i = k + 1; i < 4; ++i)
            if (std::fabs(a[i][k]) > std::fabs(a[p][k])) p = i;
        if (std::fabs(a[p][k]) <= 1e-12L * scale) throw std::invalid_argument("quadcast::host_inverse: singular matrix");
        if (p != k)
            for (int j = 0; j < 8; ++j) std::swap(a[p][j], a[k][j]);
        // Normalise row k and eliminate column k from the other rows.
        const long double piv = a[k][k];
        for (int j = 0; j < 8; ++j) a[k][j] /= piv;
        for (int i = 0; i < 4; ++i) {
            if (i == k) continue;
            const long double f = a[i][k];
            for (int j = 0; j < 8; ++j) a[i][j] -= f * a[k][j];
        }
    }
    Mat4<T> r{};
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) r[j][i] = static_cast<T>(a[i][4 + j]);
    return r;
}

/// Host-only: the quadric in coordinates y~ = M x~ (Q' = M^-T Q M^-1), inverting M on the host
/// with `host_inverse` and then calling `transform_with_inverse`. Throws like `host_inverse`.
template <std::floating_point T>
Quadric<T> transform(const Quadric<T>& q, const Mat4<T>& m) {
    return transform_with_inverse(q, host_inverse(m));
}

/// The quadric in coordinates whose origin is the eye point e, y = x - e (Stoll et al. 2006,
/// eq. 9): A' = A, b' = b + A e, c' = c + e^T (A e + 2 b) = f(e). Written to run in the vertex
/// stage (it is a template over T like everything else here).
/// Numerics: (A e)_i = ((A_i0 e0 + A_i1 e1) + A_i2 e2); b'_i = b_i + (A e)_i;
/// c' = c + dot(e, b' + b) with dot a left fold (b' + b = A e + 2b, reusing b').
/// 9 + 3 + 3 + 3 multiplications/additions; c' is the cancellation-prone part (it is f(e)).
template <class T>
Quadric<T> translate_to_eye(const Quadric<T>& q, const Vec3<T>& e) {
    const Mat3<T> A = upper3(q.q);
    const Vec3<T> b = xyz(q.q[3]);
    // Shift the linear term, then the constant term.
    const Vec3<T> bp = b + A * e;
    const T cp = q.q[3][3] + dot(e, bp + b);
    Quadric<T> r = q;
    for (int i = 0; i < 3; ++i) { r.q[3][i] = bp[i]; r.q[i][3] = bp[i]; }
    r.q[3][3] = cp;
    return r;
}

}  // namespace quadcast
