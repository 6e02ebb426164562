// quadcast/linalg.hpp -- tiny vector and matrix types whose sums have a stated association
#pragma once

#include <cstddef>

#include "quadcast/scalar.hpp"

namespace quadcast {

/// A small fixed-size vector. Trivially copyable when `T` is, so it can hold tracer handles.
/// Every reduction is a left fold: `dot(a, b) = ((a0*b0 + a1*b1) + a2*b2) + a3*b3`.
template <class T, int N>
struct Vec {
    T c[N];
    constexpr T& operator[](int i) { return c[i]; }
    constexpr const T& operator[](int i) const { return c[i]; }
    static constexpr int size = N;
};

template <class T> using Vec2 = Vec<T, 2>;
template <class T> using Vec3 = Vec<T, 3>;
template <class T> using Vec4 = Vec<T, 4>;

/// Column-major matrix with R rows and C columns: `m[j]` is column j, `m[j][i]` is row i.
/// This matches GLSL's `mat4 m; m[col][row]` and GLM's layout.
template <class T, int R, int C>
struct Mat {
    Vec<T, R> col[C];
    constexpr Vec<T, R>& operator[](int j) { return col[j]; }
    constexpr const Vec<T, R>& operator[](int j) const { return col[j]; }
    static constexpr int rows = R;
    static constexpr int cols = C;
};

template <class T> using Mat3 = Mat<T, 3, 3>;
template <class T> using Mat4 = Mat<T, 4, 4>;

// Construction -----------------------------------------------------------------------------

template <class T> constexpr Vec<T, 2> vec2(T x, T y) { return {{x, y}}; }
template <class T> constexpr Vec<T, 3> vec3(T x, T y, T z) { return {{x, y, z}}; }
template <class T> constexpr Vec<T, 4> vec4(T x, T y, T z, T w) { return {{x, y, z, w}}; }
/// (v, w) as a homogeneous 4-vector.
template <class T> constexpr Vec<T, 4> vec4(const Vec<T, 3>& v, T w) { return {{v[0], v[1], v[2], w}}; }
/// First three components.
template <class T> constexpr Vec<T, 3> xyz(const Vec<T, 4>& v) { return {{v[0], v[1], v[2]}}; }

/// Every component equal to `s`.
template <class T, int N>
constexpr Vec<T, N> splat(T s) { Vec<T, N> r{}; for (int i = 0; i < N; ++i) r[i] = s; return r; }

/// Converts every component with `T(x)` (e.g. double -> float, float -> long double).
template <class U, class T, int N>
constexpr Vec<U, N> cast(const Vec<T, N>& a) { Vec<U, N> r{}; for (int i = 0; i < N; ++i) r[i] = U(a[i]); return r; }
template <class U, class T, int R, int C>
constexpr Mat<U, R, C> cast(const Mat<T, R, C>& m) { Mat<U, R, C> r{}; for (int j = 0; j < C; ++j) r[j] = cast<U>(m[j]); return r; }

template <class T, int R, int C>
constexpr Mat<T, R, C> zero_mat() { Mat<T, R, C> m{}; for (int j = 0; j < C; ++j) for (int i = 0; i < R; ++i) m[j][i] = T(0); return m; }

template <class T, int N>
constexpr Mat<T, N, N> identity() { auto m = zero_mat<T, N, N>(); for (int i = 0; i < N; ++i) m[i][i] = T(1); return m; }

/// Matrix from rows given row by row (reads like the paper's notation).
template <class T, int R, int C>
constexpr Mat<T, R, C> from_rows(const Vec<T, C> (&rows)[R]) {
    Mat<T, R, C> m{};
    for (int j = 0; j < C; ++j) for (int i = 0; i < R; ++i) m[j][i] = rows[i][j];
    return m;
}

// Component-wise arithmetic --------------------------------------------------------------------

template <class T, int N> constexpr Vec<T, N> operator+(const Vec<T, N>& a, const Vec<T, N>& b) { Vec<T, N> r{}; for (int i = 0; i < N; ++i) r[i] = a[i] + b[i]; return r; }
template <class T, int N> constexpr Vec<T, N> operator-(const Vec<T, N>& a, const Vec<T, N>& b) { Vec<T, N> r{}; for (int i = 0; i < N; ++i) r[i] = a[i] - b[i]; return r; }
template <class T, int N> constexpr Vec<T, N> operator-(const Vec<T, N>& a)                     { Vec<T, N> r{}; for (int i = 0; i < N; ++i) r[i] = -a[i]; return r; }
template <class T, int N> constexpr Vec<T, N> operator*(const Vec<T, N>& a, const T& s)          { Vec<T, N> r{}; for (int i = 0; i < N; ++i) r[i] = a[i] * s; return r; }
template <class T, int N> constexpr Vec<T, N> operator*(const T& s, const Vec<T, N>& a)          { Vec<T, N> r{}; for (int i = 0; i < N; ++i) r[i] = s * a[i]; return r; }
template <class T, int N> constexpr Vec<T, N> operator/(const Vec<T, N>& a, const T& s)          { Vec<T, N> r{}; for (int i = 0; i < N; ++i) r[i] = a[i] / s; return r; }
/// Component-wise product (GLSL `a * b` on vectors).
template <class T, int N> constexpr Vec<T, N> cmul(const Vec<T, N>& a, const Vec<T, N>& b)      { Vec<T, N> r{}; for (int i = 0; i < N; ++i) r[i] = a[i] * b[i]; return r; }

/// Component-wise `select`.
template <class M, class T, int N>
Vec<T, N> select(const M& m, const Vec<T, N>& a, const Vec<T, N>& b) { Vec<T, N> r{}; for (int i = 0; i < N; ++i) r[i] = select(m, a[i], b[i]); return r; }

// Reductions -----------------------------------------------------------------------------------

/// Left fold: `((a0*b0 + a1*b1) + a2*b2) + ...`.
/// Numerics: N multiplications and N-1 additions, associated from the left; no FMA.
template <class T, int N>
constexpr T dot(const Vec<T, N>& a, const Vec<T, N>& b) {
    T s = a[0] * b[0];
    for (int i = 1; i < N; ++i) s = s + a[i] * b[i];
    return s;
}

/// `dot(a, a)`.
template <class T, int N>
constexpr T length2(const Vec<T, N>& a) { return dot(a, a); }

/// `sqrt(dot(a, a))`. Numerics: like `dot`, then one correctly rounded `sqrt`.
template <class T, int N>
T length(const Vec<T, N>& a) { return sqrt(dot(a, a)); }

/// `a / length(a)` as N divisions (not a multiplication by a reciprocal).
template <class T, int N>
Vec<T, N> normalize(const Vec<T, N>& a) { return a / length(a); }

/// Numerics: each component is one `a*b - c*d`.
template <class T>
constexpr Vec<T, 3> cross(const Vec<T, 3>& a, const Vec<T, 3>& b) {
    return {{a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]}};
}

/// Row i of `m`.
template <class T, int R, int C>
constexpr Vec<T, C> row(const Mat<T, R, C>& m, int i) { Vec<T, C> r{}; for (int j = 0; j < C; ++j) r[j] = m[j][i]; return r; }

/// `m * v`; component i is `dot(row(m, i), v)` (left fold over the columns).
template <class T, int R, int C>
constexpr Vec<T, R> operator*(const Mat<T, R, C>& m, const Vec<T, C>& v) {
    Vec<T, R> r{};
    for (int i = 0; i < R; ++i) r[i] = dot(row(m, i), v);
    return r;
}

/// `v^T m`, i.e. `m^T v`; component j is `dot(v, m[j])`.
template <class T, int R, int C>
constexpr Vec<T, C> operator*(const Vec<T, R>& v, const Mat<T, R, C>& m) {
    Vec<T, C> r{};
    for (int j = 0; j < C; ++j) r[j] = dot(v, m[j]);
    return r;
}

/// `a * b`; entry (i, j) is `dot(row(a, i), b[j])`.
template <class T, int R, int K, int C>
constexpr Mat<T, R, C> operator*(const Mat<T, R, K>& a, const Mat<T, K, C>& b) {
    Mat<T, R, C> r{};
    for (int j = 0; j < C; ++j) r[j] = a * b[j];
    return r;
}

template <class T, int R, int C>
constexpr Mat<T, C, R> transpose(const Mat<T, R, C>& m) {
    Mat<T, C, R> r{};
    for (int j = 0; j < C; ++j) for (int i = 0; i < R; ++i) r[i][j] = m[j][i];
    return r;
}

/// `a^T M b` as `dot(a, M * b)`.
template <class T, int N>
constexpr T bilinear(const Vec<T, N>& a, const Mat<T, N, N>& m, const Vec<T, N>& b) { return dot(a, m * b); }

/// Upper-left 3x3 block.
template <class T>
constexpr Mat<T, 3, 3> upper3(const Mat<T, 4, 4>& m) {
    Mat<T, 3, 3> r{};
    for (int j = 0; j < 3; ++j) for (int i = 0; i < 3; ++i) r[j][i] = m[j][i];
    return r;
}

/// Determinant of a 3x3 matrix as `dot(c0, cross(c1, c2))`.
template <class T>
constexpr T det(const Mat<T, 3, 3>& m) { return dot(m[0], cross(m[1], m[2])); }

/// Inverse of a 3x3 matrix by the adjugate: rows of the inverse are `cross` products of the
/// columns divided by the determinant. Returns the determinant through `d` (the caller
/// decides what "singular" means for its data).
template <class T>
Mat<T, 3, 3> inverse(const Mat<T, 3, 3>& m, T& d) {
    d = det(m);
    const Vec<T, 3> r0 = cross(m[1], m[2]), r1 = cross(m[2], m[0]), r2 = cross(m[0], m[1]);
    const Vec<T, 3> rows[3] = {r0 / d, r1 / d, r2 / d};
    return from_rows<T, 3, 3>(rows);
}

}  // namespace quadcast
