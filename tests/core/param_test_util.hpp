// tests/core/param_test_util.hpp -- long double references and random scenes for the parameter-space tests
#pragma once

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <random>
#include <utility>

#include "quadcast/linalg.hpp"
#include "quadcast/primitives.hpp"

namespace qct {

using LD = long double;
using V3L = quadcast::Vec3<LD>;
using V4L = quadcast::Vec4<LD>;
using M4L = quadcast::Mat4<LD>;

inline LD len3(const V3L& v) { return std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]); }
inline V3L unit3(const V3L& v) { return v / len3(v); }

/// Inverse by Gauss-Jordan elimination with partial pivoting (long double reference).
inline M4L inverse(const M4L& m) {
    LD a[4][8];
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) {
            a[i][j] = m[j][i];
            a[i][j + 4] = i == j ? 1 : 0;
        }
    for (int c = 0; c < 4; ++c) {
        int p = c;
        for (int i = c + 1; i < 4; ++i)
            if (std::fabs(a[i][c]) > std::fabs(a[p][c])) p = i;
        for (int j = 0; j < 8; ++j) std::swap(a[c][j], a[p][j]);
        const LD piv = a[c][c];
        for (int j = 0; j < 8; ++j) a[c][j] /= piv;
        for (int i = 0; i < 4; ++i) {
            if (i == c) continue;
            const LD f = a[i][c];
            for (int j = 0; j < 8; ++j) a[i][j] -= f * a[c][j];
        }
    }
    M4L r{};
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) r[j][i] = a[i][j + 4];
    return r;
}

/// A vector orthogonal to the three 4-vectors a, b, c (signed 3x3 minors).
inline V4L null4(const V4L& a, const V4L& b, const V4L& c) {
    auto det3 = [&](int i, int j, int k) {
        return a[i] * (b[j] * c[k] - b[k] * c[j]) - a[j] * (b[i] * c[k] - b[k] * c[i]) +
               a[k] * (b[i] * c[j] - b[j] * c[i]);
    };
    return {{det3(1, 2, 3), -det3(0, 2, 3), det3(0, 1, 3), -det3(0, 1, 2)}};
}

/// OpenGL view matrix (world -> eye, eye looks down -z).
inline M4L look_at(const V3L& eye, const V3L& target, const V3L& up) {
    const V3L f = unit3(target - eye);
    const V3L s = unit3(quadcast::cross(f, up));
    const V3L u = quadcast::cross(s, f);
    M4L m = quadcast::identity<LD, 4>();
    for (int j = 0; j < 3; ++j) {
        m[j][0] = s[j];
        m[j][1] = u[j];
        m[j][2] = -f[j];
    }
    m[3][0] = -quadcast::dot(s, eye);
    m[3][1] = -quadcast::dot(u, eye);
    m[3][2] = quadcast::dot(f, eye);
    return m;
}

/// glFrustum.
inline M4L frustum(LD l, LD r, LD b, LD t, LD n, LD f) {
    M4L m = quadcast::zero_mat<LD, 4, 4>();
    m[0][0] = 2 * n / (r - l);
    m[1][1] = 2 * n / (t - b);
    m[2][0] = (r + l) / (r - l);
    m[2][1] = (t + b) / (t - b);
    m[2][2] = -(f + n) / (f - n);
    m[2][3] = -1;
    m[3][2] = -2 * f * n / (f - n);
    return m;
}

/// Viewport transform NDC -> window with depth range [0, 1].
inline M4L viewport(LD x0, LD y0, LD w, LD h) {
    M4L m = quadcast::identity<LD, 4>();
    m[0][0] = w / 2;
    m[1][1] = h / 2;
    m[2][2] = LD(0.5);
    m[3][0] = x0 + w / 2;
    m[3][1] = y0 + h / 2;
    m[3][2] = LD(0.5);
    return m;
}

inline LD uniform(std::mt19937& rng, LD a, LD b) {
    return a + (b - a) * LD(std::uniform_real_distribution<double>(0.0, 1.0)(rng));
}
inline LD log_uniform(std::mt19937& rng, LD a, LD b) { return std::exp(uniform(rng, std::log(a), std::log(b))); }

inline V3L unit_vector(std::mt19937& rng) {
    std::normal_distribution<double> g;
    for (;;) {
        const V3L v{{LD(g(rng)), LD(g(rng)), LD(g(rng))}};
        const LD l = len3(v);
        if (l > 1e-3L) return v / l;
    }
}

/// Random rotation (columns orthonormal, det +1).
inline void random_frame(std::mt19937& rng, V3L& a, V3L& b, V3L& c) {
    a = unit_vector(rng);
    V3L t = unit_vector(rng);
    b = unit3(t - a * quadcast::dot(a, t));
    c = quadcast::cross(a, b);
}

/// Maximum of f on [lo, hi] near a sampled maximum: `n` samples then golden-section refinement
/// of the best bracket (f smooth, unimodal near the best sample). `periodic`: f has period
/// hi - lo (the bracket may then cross the ends).
inline LD maximize(const std::function<LD(LD)>& f, LD lo, LD hi, int n = 256, bool periodic = false) {
    LD best = -std::numeric_limits<LD>::infinity(), arg = lo;
    const LD h = (hi - lo) / n;
    for (int i = 0; i <= n; ++i) {
        const LD x = lo + h * i;
        const LD v = f(x);
        if (v > best) best = v, arg = x;
    }
    LD a = periodic ? arg - h : std::max(lo, arg - h), b = periodic ? arg + h : std::min(hi, arg + h);
    const LD g = (std::sqrt(LD(5)) - 1) / 2;
    LD x1 = b - g * (b - a), x2 = a + g * (b - a), f1 = f(x1), f2 = f(x2);
    for (int it = 0; it < 50; ++it) {
        if (f1 < f2) a = x1, x1 = x2, f1 = f2, x2 = a + g * (b - a), f2 = f(x2);
        else b = x2, x2 = x1, f2 = f1, x1 = b - g * (b - a), f1 = f(x1);
    }
    return std::max({best, f1, f2});
}

/// Matrix of doubles/floats to long double.
template <class T>
M4L to_ld(const quadcast::Mat4<T>& m) { return quadcast::cast<LD>(m); }

/// Units in the last place of x in type T.
template <class T>
LD ulp(LD x) {
    const T t = T(x);
    return LD(std::nextafter(t, std::numeric_limits<T>::infinity())) - LD(t);
}

/// A random camera looking roughly at `target` from `eye`: view M, an asymmetric frustum
/// with vertical field of view in [fov_lo, fov_hi] degrees, and its near/far planes.
struct Camera {
    M4L view, proj;
    LD near_z, far_z;
};

inline Camera random_camera(std::mt19937& rng, const V3L& eye, const V3L& look_dir, LD fov_lo = 20, LD fov_hi = 120) {
    Camera cam{};
    V3L up = unit_vector(rng);
    while (len3(quadcast::cross(up, look_dir)) < 0.2L) up = unit_vector(rng);
    cam.view = look_at(eye, eye + look_dir, up);
    const LD pi = LD(3.14159265358979323846264338327950288L);
    const LD fov = uniform(rng, fov_lo, fov_hi) * pi / 180;
    const LD aspect = uniform(rng, 0.5L, 2.0L);
    const LD n = log_uniform(rng, 0.01L, 0.1L), f = log_uniform(rng, 100.0L, 1000.0L);
    const LD ty = n * std::tan(fov / 2), tx = ty * aspect;
    // Shift the window off-axis (asymmetric frustum)
    const LD sx = uniform(rng, -0.8L, 0.8L), sy = uniform(rng, -0.8L, 0.8L);
    cam.proj = frustum(tx * (-1 + sx), tx * (1 + sx), ty * (-1 + sy), ty * (1 + sy), n, f);
    cam.near_z = n;
    cam.far_z = f;
    return cam;
}

/// Rotates unit vector `v` towards a random perpendicular direction by `angle` radians.
inline V3L tilt(std::mt19937& rng, const V3L& v, LD angle) {
    V3L p = unit_vector(rng);
    p = unit3(p - v * quadcast::dot(v, p));
    return v * std::cos(angle) + p * std::sin(angle);
}


/// A random primitive of `kind` (inputs drawn in long double, rounded to T by the constructors'
/// arguments). Centres in [-5, 5]^3, axis lengths in [0.2, 2], some shear for ellipsoids.
template <class T>
quadcast::ParameterForm<T> random_primitive(std::mt19937& rng, quadcast::PrimitiveKind kind, int variant = 0) {
    using quadcast::PrimitiveKind;
    auto t3 = [](const V3L& v) { return quadcast::cast<T>(v); };
    const V3L c{{uniform(rng, -5, 5), uniform(rng, -5, 5), uniform(rng, -5, 5)}};
    V3L a{}, b{}, n{};
    random_frame(rng, a, b, n);
    const LD s0 = log_uniform(rng, 0.2L, 2), s1 = log_uniform(rng, 0.2L, 2), s2 = log_uniform(rng, 0.2L, 2);
    const V3L u = a * s0, v = b * s1, w = n * s2;
    switch (kind) {
    case PrimitiveKind::ellipsoid:
        if (variant % 2 == 0) return quadcast::sphere(t3(c), T(s0));
        return quadcast::ellipsoid(t3(c), t3(u), t3(v + u * uniform(rng, -0.3L, 0.3L)), t3(w + v * uniform(rng, -0.3L, 0.3L)));
    case PrimitiveKind::cylinder:
        if (variant % 2 == 0) return quadcast::cylinder(t3(c - w), t3(c + w), T(s0));
        return quadcast::elliptic_cylinder(t3(c), t3(u), t3(v), t3(w));
    case PrimitiveKind::cone:
        if (variant % 2 == 0) return quadcast::cone(t3(c - w), t3(c + w), T(s0));
        return quadcast::elliptic_cone(t3(c - w), t3(u), t3(v), t3(w * LD(2)));
    case PrimitiveKind::paraboloid:
        if (variant % 2 == 0) return quadcast::paraboloid(t3(c - w), t3(c + w), T(s0));
        return quadcast::paraboloid(t3(c), t3(u), t3(v), t3(w));
    case PrimitiveKind::hyperboloid_one_sheet:
        return quadcast::hyperboloid_one_sheet(t3(c), t3(u), t3(v), t3(w * LD(0.5)), T(uniform(rng, 0.5L, 1.5L)));
    case PrimitiveKind::hyperboloid_two_sheets: {
        const LD h = uniform(rng, 1.5L, 3);
        if (variant % 2 == 0) return quadcast::hyperboloid_two_sheets(t3(c), t3(u), t3(v), t3(w * LD(0.5)), T(1), T(h));
        return quadcast::hyperboloid_two_sheets(t3(c), t3(u), t3(v), t3(w * LD(0.5)), T(-h), T(h));
    }
    }
    return {};
}

/// Parameter-space point (k rho cos(theta), k rho sin(theta), z, 1) at height z of a primitive
/// with D = (1, 1, d2, d3): on the surface for k = 1, on the negative side for k < 1.
inline V4L param_point(const V4L& d, LD theta, LD z, LD k = 1) {
    const LD rho = std::sqrt(std::max(LD(0), -(d[2] * z * z + d[3])));
    return {{k * rho * std::cos(theta), k * rho * std::sin(theta), z, 1}};
}

/// Dehomogenised object point T p.
inline V3L object_point(const M4L& t, const V4L& p) {
    const V4L x = t * p;
    return quadcast::vec3(x[0] / x[3], x[1] / x[3], x[2] / x[3]);
}

/// x^T Q x for x = (p, 1).
inline LD eval_quadric(const M4L& q, const V3L& x) {
    const V4L h = quadcast::vec4(x, LD(1));
    return quadcast::dot(h, q * h);
}

/// Gradient of x^T Q x at x = (p, 1).
inline V3L grad_quadric(const M4L& q, const V3L& x) {
    return quadcast::xyz(q * quadcast::vec4(x, LD(1))) * LD(2);
}

/// Centre and radius of a sphere containing the clipped primitive (from samples; padded 1 %).
template <class T>
void bounding_sphere(const quadcast::ParameterForm<T>& prim, V3L& centre, LD& radius) {
    const M4L t = quadcast::cast<LD>(prim.t);
    const V4L d = quadcast::cast<LD>(prim.d);
    const LD zl = LD(prim.slab[0]), zh = LD(prim.slab[1]);
    V3L pts[64 * 17];
    int n = 0;
    centre = V3L{{0, 0, 0}};
    for (int i = 0; i < 64; ++i)
        for (int j = 0; j <= 16; ++j) {
            pts[n] = object_point(t, param_point(d, LD(6.283185307179586476925L) * i / 64, zl + (zh - zl) * j / 16));
            centre = centre + pts[n++];
        }
    centre = centre / LD(n);
    radius = 0;
    for (int i = 0; i < n; ++i) radius = std::max(radius, len3(pts[i] - centre));
    radius *= LD(1.01);
}

}  // namespace qct
