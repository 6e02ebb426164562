// tests/render/render_testing.hpp -- cameras, primitives and long-double pixel rays for the renderer tests
#pragma once

#include <limits>

#include <cmath>
#include <cstdint>
#include <random>

#include "quadcast/linalg.hpp"
#include "quadcast/quadric.hpp"
#include "quadcast/render/cpu_renderer.hpp"
#include "quadcast/render/types.hpp"
#include "quadcast/shapes.hpp"

namespace qc_render_test {

// quadcast::render's names, and the core's vocabulary by name (quadcast::ParameterForm, the
// parameter-space primitive, would clash with render::Primitive).
using namespace quadcast::render;
using quadcast::cast;
using quadcast::cross;
using quadcast::dot;
using quadcast::identity;
using quadcast::Mat3;
using quadcast::Mat4;
using quadcast::normalize;
using quadcast::Quadric;
using quadcast::quadric_from_abc;
using quadcast::vec3;
using quadcast::Vec3;
using quadcast::vec4;
using quadcast::Vec4;
using quadcast::zero_mat;
using LD = long double;
using V3 = Vec3<LD>;

inline std::mt19937 rng_for(std::uint32_t test_id, std::uint32_t iteration) {
    std::seed_seq seq{test_id, iteration};
    return std::mt19937(seq);
}
inline double uniform(std::mt19937& rng, double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(rng); }
inline Vec3<double> random_dir(std::mt19937& rng) {
    std::normal_distribution<double> n;
    Vec3<double> v{};
    double l = 0;
    do {
        v = vec3(n(rng), n(rng), n(rng));
        l = std::sqrt(dot(v, v));
    } while (l < 1e-3);
    return v / l;
}

inline LD dot_ld(const V3& a, const V3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
inline LD norm_ld(const V3& a) { return std::sqrt(dot_ld(a, a)); }
template <class T>
V3 ld(const Vec3<T>& v) { return vec3(LD(v[0]), LD(v[1]), LD(v[2])); }

// Cameras (built in double, stored in float as both renderers take them) -------------------------

/// OpenGL gluPerspective.
inline Mat4<float> perspective(double fovy_deg, double aspect, double n, double f) {
    const double t = 1.0 / std::tan(fovy_deg * M_PI / 360.0);
    Mat4<double> p = zero_mat<double, 4, 4>();
    p[0][0] = t / aspect;
    p[1][1] = t;
    p[2][2] = -(f + n) / (f - n);
    p[3][2] = -2.0 * f * n / (f - n);
    p[2][3] = -1.0;
    return cast<float>(p);
}

/// OpenGL glOrtho.
inline Mat4<float> orthographic(double l, double r, double b, double t, double n, double f) {
    Mat4<double> p = identity<double, 4>();
    p[0][0] = 2.0 / (r - l);
    p[1][1] = 2.0 / (t - b);
    p[2][2] = -2.0 / (f - n);
    p[3][0] = -(r + l) / (r - l);
    p[3][1] = -(t + b) / (t - b);
    p[3][2] = -(f + n) / (f - n);
    return cast<float>(p);
}

/// gluLookAt; the eye is rounded to float first so that view and eye agree.
inline Camera look_at(const Vec3<double>& eye_d, const Vec3<double>& target, const Vec3<double>& up, const Mat4<float>& proj,
                      bool ortho = false) {
    const Vec3<float> eye_f = cast<float>(eye_d);
    const Vec3<double> eye = cast<double>(eye_f);
    const Vec3<double> zf = normalize(eye - target);
    const Vec3<double> x = normalize(cross(up, zf));
    const Vec3<double> y = cross(zf, x);
    Mat4<double> v = identity<double, 4>();
    for (int j = 0; j < 3; ++j) {
        v[j][0] = x[j];
        v[j][1] = y[j];
        v[j][2] = zf[j];
    }
    v[3][0] = -dot(x, eye);
    v[3][1] = -dot(y, eye);
    v[3][2] = -dot(zf, eye);
    return Camera{cast<float>(v), proj, eye_f, ortho};
}

// Primitives ------------------------------------------------------------------------------------

// Every primitive of the tests is built by the core's shapes (quadcast/shapes.hpp), the one
// construction path of the CLI and host apps; tests that need a hand-made primitive change the
// fields of one afterwards.

inline glm::vec3 gv(const Vec3<float>& v) { return {v[0], v[1], v[2]}; }
inline quadcast::shapes::Appearance look(const Vec3<float>& color) {
    quadcast::shapes::Appearance a;
    a.color = gv(color);
    return a;
}

/// A sphere (the sphere variant).
inline Primitive sphere(const Vec3<float>& c, float r, Vec3<float> color = vec3(0.8f, 0.3f, 0.2f)) {
    return quadcast::shapes::sphere(gv(c), r, look(color));
}

/// Capped circular cylinder around centre c along the unit axis: radius r, half-length h.
inline Primitive cylinder(const Vec3<float>& c, const Vec3<float>& axis, float r, float h,
                          Vec3<float> color = vec3(0.2f, 0.6f, 0.9f)) {
    const glm::vec3 gc = gv(c), ga = gv(axis);
    return quadcast::shapes::cylinder(gc - h * ga, gc + h * ga, r, quadcast::shapes::Ends::both, look(color));
}

/// Ellipsoid with orthonormal axes e0, e1, e2 and semi-axes s (the ellipsoid variant).
inline Primitive ellipsoid(const Vec3<float>& c, const Vec3<double> e[3], const Vec3<double>& s,
                           Vec3<float> color = vec3(0.4f, 0.8f, 0.3f)) {
    glm::mat3 axes(0.0f);
    for (int k = 0; k < 3; ++k)
        for (int i = 0; i < 3; ++i) axes[k][i] = static_cast<float>(e[k][i] * s[k]);
    return quadcast::shapes::ellipsoid(gv(c), axes, look(color));
}

/// A general quadric given in coordinates around c (q_local(x - c)), clipped to the sphere (c, radius).
inline Primitive bounded(const Vec3<float>& c, const Quadric<float>& q, float radius, Vec3<float> color = vec3(0.9f, 0.9f, 0.2f)) {
    const Quadric<double> world = quadcast::translate_to_eye(Quadric<double>{cast<double>(q.q)}, -cast<double>(c));
    glm::mat4 qw;
    for (int j = 0; j < 4; ++j)
        for (int i = 0; i < 4; ++i) qw[j][i] = static_cast<float>(world.q[j][i]);
    return quadcast::shapes::quadric(qw, quadcast::shapes::SphereBound{gv(c), radius}, look(color));
}

// Exact pixel rays -------------------------------------------------------------------------------

/// The exact ray of window pixel (x, y) for the float camera, in long double: the pixel centre
/// unprojected through P^-1 (Gauss-Jordan in long double) and rotated by R^T.
struct ExactCamera {
    LD pinv[4][4];
    LD rot[3][3];  // R (world -> view)
    V3 eye;
    int w, h;
    bool ortho;

    ExactCamera(const Camera& cam, int width, int height) : w(width), h(height), ortho(cam.orthographic) {
        LD a[4][8];
        for (int i = 0; i < 4; ++i)
            for (int j = 0; j < 4; ++j) {
                a[i][j] = LD(cam.projection[j][i]);
                a[i][j + 4] = i == j;
            }
        for (int c = 0; c < 4; ++c) {
            int p = c;
            for (int i = c + 1; i < 4; ++i)
                if (std::fabs(a[i][c]) > std::fabs(a[p][c])) p = i;
            for (int j = 0; j < 8; ++j) std::swap(a[p][j], a[c][j]);
            const LD d = a[c][c];
            for (int j = 0; j < 8; ++j) a[c][j] /= d;
            for (int i = 0; i < 4; ++i)
                if (i != c) {
                    const LD f = a[i][c];
                    for (int j = 0; j < 8; ++j) a[i][j] -= f * a[c][j];
                }
        }
        for (int i = 0; i < 4; ++i)
            for (int j = 0; j < 4; ++j) pinv[i][j] = a[i][j + 4];
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j) rot[i][j] = LD(cam.view[j][i]);
        eye = ld(cam.eye);
    }
    /// View-space point on the near plane through the pixel centre.
    V3 near_point(int x, int y) const {
        const LD nd[4] = {(2 * (x + 0.5L)) / w - 1, (2 * (y + 0.5L)) / h - 1, -1, 1};
        LD hv[4] = {0, 0, 0, 0};
        for (int i = 0; i < 4; ++i)
            for (int j = 0; j < 4; ++j) hv[i] += pinv[i][j] * nd[j];
        return vec3(hv[0] / hv[3], hv[1] / hv[3], hv[2] / hv[3]);
    }
    V3 rot_t(const V3& p) const {  // R^T p
        V3 r{};
        for (int j = 0; j < 3; ++j) r[j] = rot[0][j] * p[0] + rot[1][j] * p[1] + rot[2][j] * p[2];
        return r;
    }
    void ray(int x, int y, V3& origin, V3& dir) const {
        const V3 p = near_point(x, y);
        if (ortho) {
            origin = eye + rot_t(vec3(p[0], p[1], LD(0)));
            dir = rot_t(vec3(LD(0), LD(0), LD(-1)));
        } else {
            origin = eye;
            dir = rot_t(p);
        }
    }
    /// View-space z of a world point relative to the eye.
    LD view_z(const V3& x) const { return rot[2][0] * (x[0] - eye[0]) + rot[2][1] * (x[1] - eye[1]) + rot[2][2] * (x[2] - eye[2]); }
};

/// Window depth of view z for the float projection, in long double.
inline LD exact_depth(const Mat4<float>& p, LD z) {
    return 0.5L * ((LD(p[2][2]) * z + LD(p[3][2])) / (LD(p[2][3]) * z + LD(p[3][3]))) + 0.5L;
}

/// Nearest hit t > 0 of the ray o + t d with the sphere (c, r) grown by `grow` (absolute), or
/// -1 if none.
inline LD sphere_hit(const V3& o, const V3& d, const V3& c, LD r) {
    const V3 oc = o - c;
    const LD a = dot_ld(d, d), b = dot_ld(oc, d), cc = dot_ld(oc, oc) - r * r;
    const LD disc = b * b - a * cc;
    if (disc < 0) return -1;
    const LD s = std::sqrt(disc);
    const LD t0 = (-b - s) / a, t1 = (-b + s) / a;
    if (t0 > 0) return t0;
    if (t1 > 0) return t1;
    return -1;
}

/// Distance from c to the ray's line.
inline LD line_distance(const V3& o, const V3& d, const V3& c) {
    const V3 oc = c - o;
    const LD t = dot_ld(oc, d) / dot_ld(d, d);
    return norm_ld(oc - d * t);
}

/// Nearest hit t > 0 of the ray with the capped cylinder (centre c, unit axis a, radius r,
/// half-length h), or -1. The solid is the intersection of the slab and the infinite cylinder.
inline LD cylinder_hit(const V3& o, const V3& d, const V3& c, const V3& a, LD r, LD h) {
    const V3 oc = o - c;
    LD t_in = -1e300L, t_out = 1e300L;
    // Slab
    const LD ad = dot_ld(a, d), ao = dot_ld(a, oc);
    if (ad == 0) {
        if (std::fabs(ao) > h) return -1;
    } else {
        LD t0 = (-h - ao) / ad, t1 = (h - ao) / ad;
        if (t0 > t1) std::swap(t0, t1);
        t_in = std::max(t_in, t0);
        t_out = std::min(t_out, t1);
    }
    // Infinite cylinder
    const V3 dp = d - a * ad, op = oc - a * ao;
    const LD qa = dot_ld(dp, dp), qb = dot_ld(op, dp), qc = dot_ld(op, op) - r * r;
    if (qa == 0) {
        if (qc > 0) return -1;
    } else {
        const LD disc = qb * qb - qa * qc;
        if (disc < 0) return -1;
        const LD s = std::sqrt(disc);
        t_in = std::max(t_in, (-qb - s) / qa);
        t_out = std::min(t_out, (-qb + s) / qa);
    }
    if (t_in > t_out || t_out <= 0) return -1;
    return t_in > 0 ? t_in : t_out;
}

/// Nearest t > 0 where the ray meets a circular cylinder p0-p1 of radius r whose ends are
/// closed where cap0 / cap1 say (the wall between the end planes, each closed end's disc).
inline LD tube_hit(const V3& o, const V3& d, const V3& p0, const V3& p1, LD r, bool cap0, bool cap1) {
    const V3 ax = (p1 - p0) / norm_ld(p1 - p0);
    const LD len = norm_ld(p1 - p0);
    LD best = -1;
    auto take = [&](LD t) { if (t > 0 && (best < 0 || t < best)) best = t; };
    const V3 op = o - p0;
    const V3 dp = d - ax * dot_ld(d, ax), opp = op - ax * dot_ld(op, ax);
    const LD qa = dot_ld(dp, dp), qb = dot_ld(opp, dp), qc = dot_ld(opp, opp) - r * r;
    const LD disc = qb * qb - qa * qc;
    if (qa > 0 && disc >= 0) {
        for (LD t : {(-qb - std::sqrt(disc)) / qa, (-qb + std::sqrt(disc)) / qa}) {
            const LD s = dot_ld(op + d * t, ax);
            if (s >= 0 && s <= len) take(t);
        }
    }
    for (int e = 0; e < 2; ++e) {
        if (!(e == 0 ? cap0 : cap1)) continue;
        const V3 c = e == 0 ? p0 : p1;
        const LD den = dot_ld(d, ax);
        if (den == 0) continue;
        const LD t = dot_ld(c - o, ax) / den;
        const V3 x = o + d * t - c;
        if (dot_ld(x, x) <= r * r) take(t);
    }
    return best;
}

/// Nearest t > 0 on the cone from `apex` to the disc of radius r at `base` (the disc if capped).
inline LD cone_hit(const V3& o, const V3& d, const V3& apex, const V3& base, LD r, bool cap) {
    const LD H = norm_ld(base - apex);
    const V3 ax = (base - apex) / H;
    const LD k = r / H;
    LD best = -1;
    auto take = [&](LD t) { if (t > 0 && (best < 0 || t < best)) best = t; };
    // |x_perp|^2 = k^2 s^2 with s = (x - apex).ax in [0, H]
    const V3 oa = o - apex;
    const LD ds = dot_ld(d, ax), os = dot_ld(oa, ax);
    const V3 dp = d - ax * ds, opp = oa - ax * os;
    const LD qa = dot_ld(dp, dp) - k * k * ds * ds, qb = dot_ld(opp, dp) - k * k * os * ds, qc = dot_ld(opp, opp) - k * k * os * os;
    if (qa != 0) {
        const LD disc = qb * qb - qa * qc;
        if (disc >= 0)
            for (LD t : {(-qb - std::sqrt(disc)) / qa, (-qb + std::sqrt(disc)) / qa}) {
                const LD s = os + ds * t;
                if (s >= 0 && s <= H) take(t);
            }
    }
    if (cap && ds != 0) {
        const LD t = (H - os) / ds;
        const V3 x = o + d * t - base;
        if (dot_ld(x, x) <= r * r) take(t);
    }
    return best;
}

inline bool covered(const Image& img, int x, int y_window) {
    return img.depth[std::size_t(img.height - 1 - y_window) * img.width + x] < 1.0f;
}
inline float depth_at(const Image& img, int x, int y_window) {
    return img.depth[std::size_t(img.height - 1 - y_window) * img.width + x];
}

/// Two images of the same view compared pixel by pixel: `covered` counts a's covered pixels;
/// pixels covered in one only are coverage differences; where both are covered, a pixel whose
/// RGBA differs by more than `lsb` in some channel is a colour difference, one whose depth
/// differs at all a depth difference; max_lsb and max_depth are the largest differences there.
struct ImageDiff {
    long covered = 0, coverage_diff = 0, color_diff = 0, depth_diff = 0;
    int max_lsb = 0;
    double max_depth = 0;
};

inline ImageDiff image_diff(const Image& a, const Image& b, int lsb = 0) {
    ImageDiff d;
    for (std::size_t i = 0; i < a.depth.size(); ++i) {
        const bool ca = a.depth[i] < 1.0f, cb = b.depth[i] < 1.0f;
        d.covered += ca;
        if (ca != cb) { ++d.coverage_diff; continue; }
        if (!ca) continue;
        d.depth_diff += a.depth[i] != b.depth[i];
        d.max_depth = std::max(d.max_depth, static_cast<double>(std::fabs(a.depth[i] - b.depth[i])));
        int m = 0;
        for (int c = 0; c < 4; ++c) m = std::max(m, std::abs(int(a.rgba[i * 4 + c]) - int(b.rgba[i * 4 + c])));
        d.max_lsb = std::max(d.max_lsb, m);
        d.color_diff += m > lsb;
    }
    return d;
}

/// What `mixed_scene` puts in: random spheres and ellipsoids (half each), capped cylinders and
/// sphere-bounded one-sheet hyperboloids (sphere, ellipsoid, slab and bounded variants) in [-2, 2]^3.
struct MixedScene {
    int spheres = 60, cylinders = 30, hyperboloids = 10;
    bool colored = false;          ///< a random colour per object (else each helper's default)
    bool end_on_cylinder = false;  ///< add a cylinder along z at the origin (seen end-on)
};

inline std::vector<Primitive> mixed_scene(unsigned seed, const MixedScene& m = {}) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(-2.0f, 2.0f), s(0.15f, 0.5f), c(0.1f, 1.0f);
    auto color = [&](Vec3<float> fallback) { return m.colored ? vec3(c(rng), c(rng), c(rng)) : fallback; };
    std::vector<Primitive> out;
    for (int i = 0; i < m.spheres; ++i) {
        const Vec3<float> p = vec3(u(rng), u(rng), u(rng));
        const float r = s(rng);
        if (i % 2 == 0) {
            out.push_back(sphere(p, r, color(vec3(0.8f, 0.3f, 0.2f))));
            continue;
        }
        // Every other one an ellipsoid (the ellipsoid variant) of random orientation.
        const Vec3<double> e0 = random_dir(rng);
        const Vec3<double> t = std::fabs(e0[0]) < 0.9 ? vec3(1.0, 0.0, 0.0) : vec3(0.0, 1.0, 0.0);
        const Vec3<double> e1 = normalize(cross(e0, t)), e2 = cross(e0, e1);
        const Vec3<double> axes[3] = {e0, e1, e2};
        out.push_back(ellipsoid(p, axes, vec3(double(r), 0.6 * double(r), 1.1 * double(r)), color(vec3(0.4f, 0.8f, 0.3f))));
    }
    for (int i = 0; i < m.cylinders; ++i) {
        const Vec3<double> a = random_dir(rng);
        const Vec3<float> p = vec3(u(rng), u(rng), u(rng));
        const float r = s(rng) * 0.5f, h = s(rng);
        out.push_back(cylinder(p, cast<float>(a), r, h, color(vec3(0.2f, 0.6f, 0.9f))));
    }
    if (m.end_on_cylinder) out.push_back(cylinder(vec3(0.0f, 0.0f, 0.0f), vec3(0.0f, 0.0f, 1.0f), 0.4f, 0.6f));
    for (int i = 0; i < m.hyperboloids; ++i) {
        Quadric<float> hq = quadric_from_abc(identity<float, 3>(), vec3(0.0f, 0.0f, 0.0f), -0.04f);
        hq.q[1][1] = -1.0f;  // x^2 - y^2 + z^2 = 0.04: a one-sheet hyperboloid
        const Vec3<float> p = vec3(u(rng), u(rng), u(rng));
        out.push_back(bounded(p, hq, s(rng)));
    }
    return out;
}

}  // namespace qc_render_test
