// codegen/kernels/common.hpp -- helpers shared by the kernel definitions (structured inputs)
#pragma once

#include <random>
#include <span>

#include "quadcast/linalg.hpp"

namespace quadcast::codegen::kernels {

/// Writes the components of `v` into `out` starting at `pos`.
template <int N>
void put(std::span<float> out, std::size_t& pos, const Vec<float, N>& v) { for (int i = 0; i < N; ++i) out[pos++] = v[i]; }
inline void put(std::span<float> out, std::size_t& pos, float v) { out[pos++] = v; }
template <int N>
void put(std::span<float> out, std::size_t& pos, const Mat<float, N, N>& m) { for (int j = 0; j < N; ++j) put(out, pos, m[j]); }

inline float uniform(std::mt19937& rng, float lo, float hi) { return std::uniform_real_distribution<float>(lo, hi)(rng); }

/// A random point in [-s, s]^3.
inline Vec3<float> random_point(std::mt19937& rng, float s) { return vec3(uniform(rng, -s, s), uniform(rng, -s, s), uniform(rng, -s, s)); }

/// A random unit vector.
inline Vec3<float> random_direction(std::mt19937& rng) {
    std::normal_distribution<float> n(0.0f, 1.0f);
    const Vec3<float> v = vec3(n(rng), n(rng), n(rng));
    return normalize(v);
}

/// A random rotation: rows x, y, z of an orthonormal right-handed frame (column-major Mat3:
/// m[j][i] = axis_i[j], i.e. the world -> frame rotation).
inline Mat3<float> random_rotation(std::mt19937& rng) {
    const Vec3<float> z = random_direction(rng), t = random_direction(rng);
    const Vec3<float> x = normalize(cross(t, z)), y = cross(z, x);
    Mat3<float> r{};
    for (int j = 0; j < 3; ++j) { r[j][0] = x[j]; r[j][1] = y[j]; r[j][2] = z[j]; }
    return r;
}

/// A random symmetric 4x4 conic matrix: an ellipsoid, a hyperboloid, a cylinder, or plain noise,
/// at a random scale and position (the regimes the kernels meet in scenes).
inline Mat4<float> random_quadric(std::mt19937& rng) {
    const int kind = std::uniform_int_distribution<int>(0, 3)(rng);
    Mat4<float> q = zero_mat<float, 4, 4>();
    const float scale = std::ldexp(1.0f, std::uniform_int_distribution<int>(-8, 8)(rng));
    if (kind == 3) {
        for (int j = 0; j < 4; ++j)
            for (int i = 0; i <= j; ++i) q[j][i] = q[i][j] = uniform(rng, -1.0f, 1.0f) * scale;
        return q;
    }
    // Axis-aligned (diagonal) form, then rotated about a random axis and moved.
    Vec3<float> d = vec3(uniform(rng, 0.2f, 2.0f), uniform(rng, 0.2f, 2.0f), uniform(rng, 0.2f, 2.0f));
    if (kind == 1) d[2] = -d[2];     // hyperboloid
    if (kind == 2) d[2] = 0.0f;      // cylinder
    const Vec3<float> u = random_direction(rng);
    const Vec3<float> t = random_direction(rng);
    const Vec3<float> v = normalize(cross(u, t));
    const Vec3<float> w = cross(u, v);
    const Vec3<float> c = random_point(rng, 4.0f * scale);
    const Vec3<float> axes[3] = {u, v, w};
    Mat3<float> A = zero_mat<float, 3, 3>();
    for (int k = 0; k < 3; ++k)
        for (int j = 0; j < 3; ++j)
            for (int i = 0; i < 3; ++i) A[j][i] = A[j][i] + d[k] * axes[k][i] * axes[k][j] / (scale * scale);
    const Vec3<float> b = -(A * c);
    const float cc = dot(c, A * c) - 1.0f;
    for (int j = 0; j < 3; ++j) { for (int i = 0; i < 3; ++i) q[j][i] = A[j][i]; q[3][j] = q[j][3] = b[j]; }
    q[3][3] = cc;
    return q;
}

}  // namespace quadcast::codegen::kernels
