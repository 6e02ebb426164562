// tests/slim/slim_testing.hpp -- test helpers of the slim tests: ellipsoid samples and the exact distance to an ellipsoid
#pragma once

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <random>

#include <map>
#include <string>
#include <utility>
#include <vector>

#include "quadcast/scene/scene_render.hpp"
#include "quadcast/slim/build.hpp"
#include "quadcast/slim/points.hpp"
#include "quadcast/slim/scene_loader.hpp"

namespace quadcast::slim::testing {

using V3L = Vec<long double, 3>;

/// CGAL's sample data where `make data` (and `make test`) put it: build/data in the source tree.
inline std::filesystem::path cgal_data(const char* name) {
    return std::filesystem::path(__FILE__).parent_path().parent_path().parent_path() / "build" / "data" / name;
}

inline V3L to_long(const Vec3d& v) { return vec3((long double)v[0], (long double)v[1], (long double)v[2]); }

/// Uniform points on the ellipsoid with semi-axes a around c (normals outward), `n` of them.
inline OrientedPoints ellipsoid_points(const Vec3d& c, const Vec3d& a, int n, std::uint64_t seed) {
    OrientedPoints p;
    p.file = "ellipsoid";
    std::mt19937_64 rng(seed);
    std::normal_distribution<double> g;
    for (int i = 0; i < n; ++i) {
        Vec3d d = normalize(vec3(g(rng), g(rng), g(rng)));
        const Vec3d x = vec3(a[0] * d[0], a[1] * d[1], a[2] * d[2]);
        p.positions.push_back(c + x);
        p.normals.push_back(normalize(vec3(x[0] / (a[0] * a[0]), x[1] / (a[1] * a[1]), x[2] / (a[2] * a[2]))));
    }
    return p;
}

/// Euclidean distance from y to the ellipsoid sum (x_i / a_i)^2 = 1 (centred), in long double:
/// the closest point x_i = a_i^2 y_i / (t + a_i^2) with t the root of
/// F(t) = sum (a_i y_i / (t + a_i^2))^2 - 1 on (-a_min^2, inf), found by bisection (Eberly's bracket).
inline long double ellipsoid_distance(const V3L& y0, const Vec3d& a) {
    V3L y;
    for (int i = 0; i < 3; ++i) y[i] = std::fabs(y0[i]) + 1e-30L;
    int m = 0;
    for (int i = 1; i < 3; ++i)
        if (a[i] < a[m]) m = i;
    const long double am2 = (long double)a[m] * a[m];
    long double s = 0;
    for (int i = 0; i < 3; ++i) s += (long double)a[i] * a[i] * y[i] * y[i];
    long double lo = -am2 + (long double)a[m] * y[m], hi = -am2 + std::sqrt(s);
    const auto F = [&](long double t) {
        long double f = -1;
        for (int i = 0; i < 3; ++i) {
            const long double q = (long double)a[i] * y[i] / (t + (long double)a[i] * a[i]);
            f += q * q;
        }
        return f;
    };
    for (int it = 0; it < 200; ++it) {
        const long double mid = 0.5L * (lo + hi);
        (F(mid) > 0 ? lo : hi) = mid;
    }
    const long double t = 0.5L * (lo + hi);
    long double d2 = 0;
    for (int i = 0; i < 3; ++i) {
        const long double x = (long double)a[i] * a[i] * y[i] / (t + (long double)a[i] * a[i]);
        d2 += (x - y[i]) * (x - y[i]);
    }
    return std::sqrt(d2);
}

/// Points on the torus around the z axis (tube radius r around the circle of radius R), uniform
/// in area (rejection on the tube angle), outward normals, `n` of them.
inline OrientedPoints torus_points(double R, double r, int n, std::uint64_t seed) {
    OrientedPoints p;
    p.file = "torus";
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    const double two_pi = 6.283185307179586;
    while (static_cast<int>(p.size()) < n) {
        const double a = two_pi * u(rng), b = two_pi * u(rng);
        if (u(rng) * (R + r) > R + r * std::cos(b)) continue;  // area element (R + r cos b)
        const Vec3d nrm = vec3(std::cos(b) * std::cos(a), std::cos(b) * std::sin(a), std::sin(b));
        p.positions.push_back(vec3(R * std::cos(a), R * std::sin(a), 0.0) + nrm * r);
        p.normals.push_back(nrm);
    }
    return p;
}

/// Distance from y to that torus, and its outward normal at the closest point (long double).
inline long double torus_distance(const V3L& y, long double R, long double r, V3L* normal = nullptr) {
    const long double q = std::sqrt(y[0] * y[0] + y[1] * y[1]);
    const long double dx = q - R, dz = y[2];
    const long double d = std::sqrt(dx * dx + dz * dz);
    if (normal) {
        const long double cx = q > 0 ? y[0] / q : 1.0L, cy = q > 0 ? y[1] / q : 0.0L;
        *normal = vec3(dx / d * cx, dx / d * cy, dz / d);
    }
    return std::fabs(d - r);
}

/// The balls of a SLIM surface built from `file` (tests/slim/data) at `error` (built once per run).
inline const std::vector<render::Primitive>& model_balls(const char* file, double error) {
    static std::map<std::pair<std::string, double>, std::vector<render::Primitive>> built;
    const auto key = std::make_pair(std::string(file), error);
    if (const auto it = built.find(key); it != built.end()) return it->second;
    BuildOptions opt;
    opt.error = error;
    const OrientedPoints pts = read_points(std::string(QUADCAST_SLIM_TEST_DATA) + "/" + file);
    const BuildResult b = build(pts, opt);
    scene::Scene s;
    scene::Slim m;
    m.balls = scene_balls(b.model);
    s.slims.push_back(m);
    s.camera.eye = scene::Vec3d{{0.0, 0.0, 4.0}};
    s.camera.target = scene::Vec3d{{0.0, 0.0, 0.0}};
    s.lights.push_back(scene::Light{});
    return built[key] = render::build_frame(s, 64, 48).slim_balls;
}

/// Points on the faces of the box [-H, H] with their exact outward face normals: every face cut
/// into a grid of cells of side about h, one point per cell, uniform in the central 90% of the
/// cell (seeded): about uniform in area, never on an edge (at least h / 20 from it).
inline OrientedPoints box_points(const Vec3d& H, double h, std::uint64_t seed) {
    OrientedPoints p;
    p.file = "box";
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(0.05, 0.95);
    for (int a = 0; a < 3; ++a)
        for (const int s : {-1, 1}) {
            const int b = (a + 1) % 3, c = (a + 2) % 3;
            const int nb = std::max(1, int(std::lround(2 * H[b] / h))), nc = std::max(1, int(std::lround(2 * H[c] / h)));
            for (int i = 0; i < nb; ++i)
                for (int j = 0; j < nc; ++j) {
                    Vec3d x = vec3(0.0, 0.0, 0.0), n = vec3(0.0, 0.0, 0.0);
                    x[a] = s * H[a];
                    x[b] = -H[b] + (i + u(rng)) * 2 * H[b] / nb;
                    x[c] = -H[c] + (j + u(rng)) * 2 * H[c] / nc;
                    n[a] = s;
                    p.positions.push_back(x);
                    p.normals.push_back(n);
                }
        }
    return p;
}

/// Calls f(x) for points of a record's zero set (long double roots): where the lines parallel to
/// the three axes through an n x n grid over the ball's bounding square cross its quadric, inside
/// the ball and on the kept side of its clip planes (as the renderers draw it).
template <class F>
inline void zero_set_samples(const Ball& b, int n, F&& f) {
    Quadric<long double> q;
    for (int j = 0; j < 4; ++j)
        for (int i = 0; i < 4; ++i) q.q[j][i] = b.q.q[j][i];
    const V3L c = to_long(b.center);
    const long double r = b.radius;
    auto kept = [](bool has, const Vec<double, 4>& p, const V3L& x) -> bool { return !has || p[0] * x[0] + p[1] * x[1] + p[2] * x[2] + p[3] >= 0; };
    for (int a = 0; a < 3; ++a)
        for (int i = 0; i < n; ++i)
            for (int j = 0; j < n; ++j) {
                V3L p = c, e = vec3(0.0L, 0.0L, 0.0L);
                p[(a + 1) % 3] += r * (2.0L * (i + 0.5L) / n - 1);
                p[(a + 2) % 3] += r * (2.0L * (j + 0.5L) / n - 1);
                e[a] = r;
                // q(p + s e) = A s^2 + B s + C, exactly from three values.
                const long double fm = evaluate(q, p - e), f0 = evaluate(q, p), fp = evaluate(q, p + e);
                const long double A = 0.5L * (fp + fm) - f0, B = 0.5L * (fp - fm), C = f0;
                long double s[2];
                int m = 0;
                if (A == 0) {
                    if (B != 0) s[m++] = -C / B;
                } else if (B * B - 4 * A * C >= 0) {
                    const long double h = -0.5L * (B + std::copysign(std::sqrt(B * B - 4 * A * C), B));
                    s[m++] = h / A;
                    if (h != 0) s[m++] = C / h;
                }
                for (int k = 0; k < m; ++k) {
                    const V3L x = p + e * s[k];
                    if (dot(x - c, x - c) > r * r) continue;
                    if (!kept(b.has_plane, b.plane, x) || !kept(b.has_plane && b.has_plane2, b.plane2, x)) continue;
                    f(x);
                }
            }
}

/// The q-quantile of v (the element at index q n of the sorted values, clamped), 0 for none.
inline double percentile(std::vector<double> v, double q) {
    if (v.empty()) return 0;
    std::sort(v.begin(), v.end());
    return v[std::min(v.size() - 1, std::size_t(q * double(v.size())))];
}

}  // namespace quadcast::slim::testing
