// tests/render/bounds_scenes.hpp -- scenes for the tight-bounds tests (CPU and GL): every variant,
// eye inside bounds, primitives across the near plane, perspective and orthographic cameras
#pragma once

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "quadcast/shapes.hpp"
#include "render/render_testing.hpp"

namespace qc_bounds_test {

using namespace quadcast;
using namespace quadcast::render;
namespace shapes = quadcast::shapes;

/// A scene and the camera it is seen from.
struct BoundsScene {
    std::string name;
    std::vector<Primitive> prims;
    Camera camera;
};

inline glm::vec3 gv(std::mt19937& rng, float lo, float hi) {
    std::uniform_real_distribution<float> u(lo, hi);
    return {u(rng), u(rng), u(rng)};
}

inline shapes::Appearance look(std::mt19937& rng) {
    std::uniform_real_distribution<float> c(0.1f, 1.0f);
    return {{c(rng), c(rng), c(rng)}, 0.35f, 48.0f};
}

/// Random primitives of every kind in [-s, s]^3: spheres, rotated ellipsoids, capped, open and
/// half-open cylinders, capped and open cones, a one-sheet hyperboloid in a sphere, quadrics in
/// tetrahedra, twisted and planar quads and a triangle.
inline std::vector<Primitive> every_kind(unsigned seed, float s, int per_kind) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> r(0.05f, 0.4f), ang(0.0f, 6.2831853f);
    std::vector<Primitive> out;
    for (int i = 0; i < per_kind; ++i) {
        out.push_back(shapes::sphere(gv(rng, -s, s), r(rng), look(rng)));
        const glm::mat4 rot = glm::rotate(glm::mat4(1.0f), ang(rng), glm::normalize(gv(rng, -1, 1) + glm::vec3(0.01f)));
        out.push_back(shapes::ellipsoid(gv(rng, -s, s), glm::vec3(r(rng), 0.3f * r(rng), 0.6f * r(rng)), glm::mat3(rot), look(rng)));
        const glm::vec3 p0 = gv(rng, -s, s), d = glm::normalize(gv(rng, -1, 1) + glm::vec3(0.01f)) * (3.0f * r(rng));
        const shapes::Ends ends[4] = {shapes::Ends::both, shapes::Ends::none, shapes::Ends::first, shapes::Ends::second};
        out.push_back(shapes::cylinder(p0, p0 + d, 0.25f * r(rng), ends[i % 4], look(rng)));
        const glm::vec3 a = gv(rng, -s, s), b = a + glm::normalize(gv(rng, -1, 1) + glm::vec3(0.01f)) * (2.0f * r(rng));
        out.push_back(shapes::cone(a, b, 0.6f * r(rng), i % 2 == 0, look(rng)));
        // A one-sheet hyperboloid x^2 - y^2 + z^2 = k in a sphere (bounded variant).
        const glm::vec3 c = gv(rng, -s, s);
        const float k = 0.01f;
        glm::mat4 q(0.0f);
        q[0][0] = 1.0f; q[1][1] = -1.0f; q[2][2] = 1.0f;
        q[3][0] = q[0][3] = -c.x; q[3][1] = q[1][3] = c.y; q[3][2] = q[2][3] = -c.z;
        q[3][3] = c.x * c.x - c.y * c.y + c.z * c.z - k;
        out.push_back(shapes::quadric(q, shapes::SphereBound{c, r(rng)}, look(rng)));
        // A sphere-like quadric in a tetrahedron (planes variant).
        const glm::vec3 t0 = gv(rng, -s, s);
        const float e = 2.0f * r(rng);
        shapes::TetrahedronBound tet{{t0, t0 + glm::vec3(e, 0, 0), t0 + glm::vec3(0, e, 0), t0 + glm::vec3(0, 0, e)}};
        const glm::vec3 m = t0 + glm::vec3(0.25f * e);
        glm::mat4 qs(0.0f);
        qs[0][0] = qs[1][1] = qs[2][2] = 1.0f;
        qs[3][0] = qs[0][3] = -m.x; qs[3][1] = qs[1][3] = -m.y; qs[3][2] = qs[2][3] = -m.z;
        qs[3][3] = glm::dot(m, m) - 0.2f * e * e;
        out.push_back(shapes::quadric(qs, tet, look(rng)));
        // A twisted and a planar quad, a triangle.
        const glm::vec3 o = gv(rng, -s, s);
        const float w = 2.0f * r(rng);
        out.push_back(shapes::quad(o, o + glm::vec3(w, 0, 0.3f * w), o + glm::vec3(w, w, -0.2f * w), o + glm::vec3(0, w, 0.4f * w), look(rng)));
        const glm::vec3 o2 = gv(rng, -s, s);
        out.push_back(shapes::quad(o2, o2 + glm::vec3(w, 0.1f * w, 0), o2 + glm::vec3(w, w, 0.2f * w), o2 + glm::vec3(0, w, 0.1f * w), look(rng)));
        const glm::vec3 o3 = gv(rng, -s, s);
        out.push_back(shapes::quad(o3, o3 + glm::vec3(w, 0, 0), o3 + glm::vec3(0, w, 0), o3 + glm::vec3(0, w, 0), look(rng)));
    }
    return out;
}

/// The quadric x^T diag(a) x + k = 0 (a field of finite elements, say) cut into the Kuhn
/// tetrahedra of an n^3 grid of cubes over [-s, s]^3: one `planes` primitive per tetrahedron the
/// surface can cross (the field's range over the tetrahedron, bounded by its corners' values
/// widened by its diameter's share of the gradient bound, holds 0).
inline std::vector<Primitive> tetrahedral_pieces(const glm::dvec3& a, double k, int n, double s, const glm::vec3& color) {
    std::vector<Primitive> out;
    glm::dmat4 q(0.0);
    for (int i = 0; i < 3; ++i) q[i][i] = a[i];
    q[3][3] = k;
    const double h = 2.0 * s / n;
    const double grad = 2.0 * s * std::max({std::fabs(a.x), std::fabs(a.y), std::fabs(a.z)}) * std::sqrt(3.0);
    auto f = [&](const glm::dvec3& x) { return a.x * x.x * x.x + a.y * x.y * x.y + a.z * x.z * x.z + k; };
    const int perms[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
    for (int z = 0; z < n; ++z)
        for (int y = 0; y < n; ++y)
            for (int x = 0; x < n; ++x)
                for (const auto& pm : perms) {
                    glm::dvec3 p[4];
                    p[0] = glm::dvec3(-s + x * h, -s + y * h, -s + z * h);
                    for (int j = 0; j < 3; ++j) {
                        p[j + 1] = p[j];
                        p[j + 1][pm[j]] += h;
                    }
                    double lo = 1e300, hi = -1e300;
                    for (const auto& c : p) {
                        lo = std::min(lo, f(c));
                        hi = std::max(hi, f(c));
                    }
                    const double slack = grad * h * std::sqrt(3.0);
                    if (lo - slack > 0 || hi + slack < 0) continue;
                    out.push_back(shapes::quadric(q, shapes::TetrahedronBound{{glm::vec3(p[0]), glm::vec3(p[1]), glm::vec3(p[2]), glm::vec3(p[3])}},
                                                  {color, 0.35f, 48.0f}));
                }
    return out;
}

/// The scenes: every kind seen in perspective from outside; from an eye inside an ellipsoid, a
/// cylinder's and a sphere's bounds with primitives across the near plane; a near plane cutting
/// through the scene; the same orthographic; long sticks seen along and across their axes.
inline std::vector<BoundsScene> bounds_scenes(int width, int height) {
    using qc_render_test::look_at;
    const double aspect = double(width) / height;
    std::vector<BoundsScene> out;
    {
        BoundsScene b{"every kind, perspective", every_kind(11, 2.0f, 6), {}};
        b.camera = look_at(vec3(0.7, 1.1, 8.0), vec3(0.0, 0.0, 0.0), vec3(0.0, 1.0, 0.0), qc_render_test::perspective(45, aspect, 1, 30));
        out.push_back(b);
    }
    {
        // The eye at the origin inside a big ellipsoid's bound (seen from inside: its far side),
        // inside a long open tube's bound and a sphere's bound, the near plane cutting a cone.
        BoundsScene b{"eye inside bounds, near plane crossing", every_kind(12, 1.5f, 4), {}};
        b.prims.push_back(shapes::ellipsoid({0.2f, 0.0f, 0.3f}, glm::vec3(2.5f, 1.5f, 4.0f), glm::mat3(1.0f), {{0.7f, 0.7f, 0.9f}}));
        b.prims.push_back(shapes::cylinder({-1.0f, 0.3f, 0.5f}, {1.0f, 0.2f, -0.6f}, 0.15f, shapes::Ends::none, {{0.9f, 0.5f, 0.2f}}));
        b.prims.push_back(shapes::sphere({0.0f, 0.0f, 0.4f}, 0.6f, {{0.3f, 0.9f, 0.3f}}));
        b.prims.push_back(shapes::cone({0.1f, -0.05f, 0.2f}, {0.3f, -0.2f, -1.5f}, 0.5f, true, {{0.9f, 0.9f, 0.3f}}));
        b.camera = look_at(vec3(0.0, 0.0, 0.0), vec3(0.1, 0.05, -1.0), vec3(0.0, 1.0, 0.0), qc_render_test::perspective(70, aspect, 0.25, 30));
        out.push_back(b);
    }
    {
        BoundsScene b{"near plane through the scene", every_kind(13, 2.0f, 6), {}};
        b.camera = look_at(vec3(0.3, -0.4, 4.0), vec3(0.0, 0.0, 0.0), vec3(0.0, 1.0, 0.0), qc_render_test::perspective(60, aspect, 3.5, 30));
        out.push_back(b);
    }
    {
        BoundsScene b{"every kind, orthographic, near plane through the scene", every_kind(14, 2.0f, 6), {}};
        b.camera = look_at(vec3(0.5, 0.8, 3.0), vec3(0.0, 0.0, 0.0), vec3(0.0, 1.0, 0.0),
                           qc_render_test::orthographic(-3.0 * aspect, 3.0 * aspect, -3, 3, 1.5, 30), true);
        out.push_back(b);
    }
    {
        // Tetrahedral pieces of a sphere and of a one-sheet hyperboloid, seen orthographically
        // straight along z (faces parallel to the view: flat hulls) and in perspective from
        // inside the mesh, close to the sphere (pieces across the near and eye planes).
        BoundsScene b{"tetrahedral pieces, orthographic along z", tetrahedral_pieces({1, 1, 1}, -0.64, 6, 1.0, {0.8f, 0.4f, 0.3f}), {}};
        const std::vector<Primitive> hyp = tetrahedral_pieces({1, -1, 1}, -0.1, 5, 0.7, {0.3f, 0.6f, 0.9f});
        for (Primitive p : hyp) {
            p.shape.center[0] += 1.8f;  // (moved beside the sphere: the field moves with its pieces' centres)
            b.prims.push_back(p);
        }
        b.camera = look_at(vec3(0.9, 0.0, 5.0), vec3(0.9, 0.0, 0.0), vec3(0.0, 1.0, 0.0),
                           qc_render_test::orthographic(-1.6 * aspect, 1.6 * aspect, -1.6, 1.6, 1, 10), true);
        out.push_back(b);
        BoundsScene c{"tetrahedral pieces, perspective from inside the mesh", b.prims, {}};
        c.camera = look_at(vec3(0.2, 0.3, 0.95), vec3(0.0, 0.0, 0.0), vec3(0.0, 1.0, 0.0), qc_render_test::perspective(75, aspect, 0.25, 30));
        out.push_back(c);
    }
    {
        // Sticks (capped cylinders of length 0.05, radius 0.005) seen at an angle and along z.
        std::mt19937 rng(15);
        BoundsScene b{"sticks", {}, {}};
        for (int i = 0; i < 2000; ++i) {
            const glm::vec3 p = gv(rng, 0.0f, 1.0f), d = glm::normalize(gv(rng, -1, 1) + glm::vec3(0.001f)) * 0.05f;
            b.prims.push_back(shapes::cylinder(p, p + d, 0.005f, i % 5 == 0 ? shapes::Ends::none : shapes::Ends::both, look(rng)));
        }
        for (int i = 0; i < 50; ++i) {
            const glm::vec3 p = gv(rng, 0.0f, 1.0f);
            b.prims.push_back(shapes::cylinder(p, p + glm::vec3(0.0f, 0.0f, 0.05f), 0.005f, shapes::Ends::both, look(rng)));
        }
        b.camera = look_at(vec3(0.5, 0.5, 2.2), vec3(0.5, 0.5, 0.5), vec3(0.0, 1.0, 0.0), qc_render_test::perspective(30, aspect, 1, 5));
        out.push_back(b);
    }
    return out;
}

using qc_render_test::ImageDiff;
using qc_render_test::image_diff;

}  // namespace qc_bounds_test
