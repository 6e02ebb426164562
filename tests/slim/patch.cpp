// tests/slim/patch.cpp -- the patch bound of a SLIM ball (slab, normal cone, screen quadrilateral) against
// long-double samples of the patch, and the renderers' images with and without it
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <random>
#include <string>
#include <vector>

#include "quadcast/camera.hpp"
#include "quadcast/render/slim_cpu_renderer.hpp"
#include "quadcast/render/slim_patch.hpp"
#include "quadcast/render/window_ray.hpp"
#include "quadcast/scene/scene_render.hpp"
#include "quadcast/slim/build.hpp"
#include "quadcast/slim/points.hpp"
#include "quadcast/slim/scene_loader.hpp"
#include "slim/slim_testing.hpp"

using namespace quadcast;

namespace {

using L = long double;
using V3L = Vec<L, 3>;

/// A ball as the renderers hold it: the quadric x^T A x + 2 b.x + c in local coordinates, its
/// radius and centre, and its clip plane.
render::Primitive ball(const Mat3<double>& A, const Vec3<double>& b, double c, const Vec3<double>& center, double r, const Vec4<double>& plane) {
    render::Primitive p{};
    p.variant = render::Variant::bounded;
    for (int j = 0; j < 3; ++j) {
        for (int i = 0; i < 3; ++i) p.shape.q.q[j][i] = float(A[j][i]);
        p.shape.q.q[3][j] = p.shape.q.q[j][3] = float(b[j]);
    }
    p.shape.q.q[3][3] = float(c);
    p.shape.center = cast<float>(center);
    p.shape.radius = float(r);
    p.shape.planes[0] = cast<float>(plane);
    return p;
}

/// Points of a ball's patch: where lines parallel to the axes (n x n per axis, across the ball)
/// cross the quadric (the float coefficients, in long double) inside the ball and on the kept side
/// of both planes; local coordinates.
std::vector<V3L> patch_samples(const render::Primitive& p, int n) {
    const ClippedQuadric<float>& s = p.shape;
    L A[3][3], b[3];
    for (int j = 0; j < 3; ++j) {
        for (int i = 0; i < 3; ++i) A[j][i] = s.q.q[j][i];
        b[j] = s.q.q[3][j];
    }
    const L c = s.q.q[3][3], r = s.radius;
    std::vector<V3L> out;
    for (int axis = 0; axis < 3; ++axis) {
        const int i1 = (axis + 1) % 3, i2 = (axis + 2) % 3;
        for (int u = 0; u < n; ++u)
            for (int v = 0; v < n; ++v) {
                V3L o{};
                o[i1] = r * (L(2 * u + 1) / n - 1);
                o[i2] = r * (L(2 * v + 1) / n - 1);
                // f(o + t e_axis) = qa t^2 + 2 qb t + qc
                const L qa = A[axis][axis];
                L qb = b[axis], qc = c;
                for (int k = 0; k < 3; ++k) {
                    qb += A[axis][k] * o[k];
                    qc += 2 * b[k] * o[k];
                    for (int l = 0; l < 3; ++l) qc += o[k] * A[k][l] * o[l];
                }
                L ts[2];
                int m = 0;
                if (std::abs(qa) < 1e-30L) {
                    if (qb != 0) ts[m++] = -qc / (2 * qb);
                } else {
                    const L disc = qb * qb - qa * qc;
                    if (disc >= 0) {
                        ts[m++] = (-qb - std::sqrt(disc)) / qa;
                        ts[m++] = (-qb + std::sqrt(disc)) / qa;
                    }
                }
                for (int k = 0; k < m; ++k) {
                    V3L x = o;
                    x[axis] = ts[k];
                    if (dot(x, x) > r * r) continue;
                    bool kept = true;
                    for (int q = 0; q < 2; ++q)
                        kept = kept && L(s.planes[q][0]) * x[0] + L(s.planes[q][1]) * x[1] + L(s.planes[q][2]) * x[2] + L(s.planes[q][3]) >= 0;
                    if (!kept) continue;
                    out.push_back(x);
                }
            }
    }
    return out;
}

/// The gradient 2 (A x + b) of the ball's quadric at local x.
V3L gradient(const render::Primitive& p, const V3L& x) {
    V3L g{};
    for (int j = 0; j < 3; ++j) {
        g[j] = L(p.shape.q.q[3][j]);
        for (int i = 0; i < 3; ++i) g[j] += L(p.shape.q.q[j][i]) * x[i];
        g[j] *= 2;
    }
    return g;
}

Mat3<double> random_rotation(std::mt19937_64& rng) {
    std::normal_distribution<double> g;
    const Vec3<double> a = normalize(vec3(g(rng), g(rng), g(rng)));
    Vec3<double> t = normalize(vec3(g(rng), g(rng), g(rng)));
    const Vec3<double> b = normalize(cross(a, t));
    Mat3<double> m{};
    m[0] = a;
    m[1] = b;
    m[2] = cross(a, b);
    return m;
}

/// Random balls of every kind of sheet a fit gives: planes, spheres, cylinders, cones, plane
/// pairs, paraboloids, hyperboloids, random quadrics; with and without clip planes; some empty.
std::vector<render::Primitive> random_balls(int count, std::uint64_t seed) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    std::vector<render::Primitive> out;
    for (int i = 0; i < count; ++i) {
        const double r = 0.05 + 2.0 * u(rng);
        const Vec3<double> center = vec3(u(rng) - 0.5, u(rng) - 0.5, u(rng) - 0.5) * 20.0;
        const Mat3<double> R = random_rotation(rng);
        // The kind in its own frame (x' = R^T x): diagonal A', b', c
        Vec3<double> d{}, e{};
        double c = 0;
        const double k = 1.0 / r;  // curvatures of the order of the ball's
        switch (i % 8) {
        case 0: e = vec3(0.0, 0.0, 0.5); c = (u(rng) - 0.5) * r; break;                                    // plane z = offset
        case 1: d = vec3(1.0, 1.0, 1.0) * (0.5 * k * u(rng)); e = vec3(0.0, 0.0, 0.5); break;              // sphere through the centre
        case 2: d = vec3(1.0, 1.0, 0.0) * (0.5 * k * u(rng)); e = vec3(0.0, 0.5, 0.0); break;              // cylinder
        case 3: d = vec3(1.0, 1.0, -0.3) * k; c = -0.01 * r * k; break;                                    // cone near its apex
        case 4: d = vec3(0.0, 0.0, 0.0); c = 0; break;                                                     // plane pair (below)
        case 5: d = vec3(k * u(rng), k * u(rng), 0.0); e = vec3(0.0, 0.0, -0.5); break;                    // paraboloid
        case 6: d = vec3(k, -k * u(rng), k * u(rng)); c = -0.2 * r * r * k * k; break;                     // hyperboloid
        default: d = vec3(u(rng) - 0.5, u(rng) - 0.5, u(rng) - 0.5) * (2 * k); e = vec3(u(rng) - 0.5, u(rng) - 0.5, u(rng) - 0.5); c = (u(rng) - 0.5) * r; break;
        }
        Mat3<double> Ap{};
        for (int j = 0; j < 3; ++j) Ap[j][j] = d[j];
        if (i % 8 == 4) Ap[0][1] = Ap[1][0] = k;  // x y = 0
        // A = R A' R^T, b = R e
        Mat3<double> A{};
        for (int j = 0; j < 3; ++j)
            for (int l = 0; l < 3; ++l) {
                double s = 0;
                for (int m = 0; m < 3; ++m)
                    for (int n = 0; n < 3; ++n) s += R[m][j] * Ap[m][n] * R[n][l];
                A[j][l] = s;
            }
        const Vec3<double> b = R * e;
        Vec4<double> plane = vec4(0.0, 0.0, 0.0, 1.0);
        if (u(rng) < 0.4) plane = vec4(R[0] * (u(rng) < 0.5 ? 1.0 : -1.0) + R[1] * (u(rng) - 0.5), (u(rng) - 0.5) * r);
        if (i % 23 == 22) c = 10.0 * r;  // a plane far outside the ball: empty
        out.push_back(ball(A, b, c, center, r, plane));
        // Half of the clipped balls get a second plane (a corner's record), across the first.
        if (plane[0] != 0.0 || plane[1] != 0.0 || plane[2] != 0.0) {
            if (u(rng) < 0.5)
                out.back().shape.planes[1] = cast<float>(vec4(R[2] * (u(rng) < 0.5 ? 1.0 : -1.0) + R[0] * (u(rng) - 0.5), (u(rng) - 0.5) * r));
            else
                out.back().shape.planes[1] = vec4(0.0f, 0.0f, 0.0f, 1.0f);
        }
    }
    return out;
}

struct PatchCheck {
    long samples = 0, outside_slab = 0, outside_cone = 0, empty_with_samples = 0;
    long culled = 0, culled_front = 0, quads = 0, outside_quad = 0;
    double slab_width = 0, sampled_width = 0;  ///< sums over balls of hi - lo and of the samples' a.x range, over the ball's diameter
    int balls = 0;
};

/// Every sample of every ball against its `slim_patch`: a . x in [lo, hi], the gradient within the
/// cone; for random cameras, a culled ball has no front-facing sample (perspective: (x - eye) . g
/// < 0 is front-facing; orthographic: dir . g < 0) and every sample projects into the quadrilateral.
PatchCheck check_patches(const std::vector<render::Primitive>& balls, std::uint64_t seed, int lines, int cameras) {
    PatchCheck pc;
    std::mt19937_64 rng(seed);
    std::normal_distribution<double> g;
    std::uniform_real_distribution<double> u(0.0, 1.0);
    const std::vector<SlimPatch<float>> patches = render::slim_patches(balls);
    for (std::size_t i = 0; i < balls.size(); ++i) {
        const render::Primitive& b = balls[i];
        const SlimPatch<float>& p = patches[i];
        const std::vector<V3L> xs = patch_samples(b, lines);
        const V3L a = vec3(L(p.axis_rho[0]), L(p.axis_rho[1]), L(p.axis_rho[2]));
        const L lo = p.slab_cone[0], hi = p.slab_cone[1], cos_t = p.slab_cone[2];
        ++pc.balls;
        if (lo > hi) {
            pc.empty_with_samples += xs.empty() ? 0 : 1;
            continue;
        }
        L zmin = 1e30L, zmax = -1e30L;
        for (const V3L& x : xs) {
            ++pc.samples;
            const L z = dot(a, x);
            zmin = std::min(zmin, z);
            zmax = std::max(zmax, z);
            if (z < lo || z > hi) ++pc.outside_slab;
            const V3L gx = gradient(b, x);
            const L len = std::sqrt(dot(gx, gx));
            if (cos_t > 0 && len > 0 && dot(a, gx) < cos_t * len * (1 - 1e-6L)) ++pc.outside_cone;
        }
        pc.slab_width += double((hi - lo) / (2 * L(b.shape.radius)));
        if (!xs.empty()) pc.sampled_width += double((zmax - zmin) / (2 * L(b.shape.radius)));
        // Cameras around the ball
        for (int k = 0; k < cameras; ++k) {
            const bool ortho = k % 2 == 1;
            const double r = b.shape.radius;
            const Vec3<double> dirn = normalize(vec3(g(rng), g(rng), g(rng)));
            const Vec3<double> c = cast<double>(b.shape.center);
            const Vec3<double> eye = c + dirn * (r * (1.2 + 30.0 * u(rng) * u(rng)));
            const Mat4<double> view = look_at(eye, c + vec3(g(rng), g(rng), g(rng)) * (0.3 * r), vec3(0.0, 1.0, 0.0));
            const double dist = length(eye - c);
            const Mat4<double> proj = ortho ? orthographic(3.0 * r, 4.0 / 3.0, 0.01 * r, dist + 10 * r)
                                            : perspective(40.0 + 60.0 * u(rng), 4.0 / 3.0, 0.01 * r, dist + 10 * r);
            const render::Camera cam = camera_from_matrices(view, proj);
            const render::FrameSetup f = render::frame_setup(cam, 320, 240);
            // The cone: culled balls show no front-facing sample
            if (render::slim_patch_cull(b, p, f)) {
                ++pc.culled;
                const V3L view_dir = vec3(L(f.rays.fixed[0]), L(f.rays.fixed[1]), L(f.rays.fixed[2]));
                for (const V3L& x : xs) {
                    const V3L ray = ortho ? view_dir : (x + vec3(L(c[0]), L(c[1]), L(c[2]))) - vec3(L(cam.eye[0]), L(cam.eye[1]), L(cam.eye[2]));
                    if (dot(ray, gradient(b, x)) <= 0) ++pc.culled_front;
                }
            }
            // The quadrilateral holds every sample's projection
            const ScreenQuad<float> q = slim_patch_quad(f.view_projection, b.shape.center, p.axis_rho, p.slab_cone, vec2(320.0f, 240.0f));
            if (!q.tight || !q.visible) continue;
            ++pc.quads;
            const Mat4<double> vp = proj * view;
            for (const V3L& x : xs) {
                const Vec4<double> h = vp * vec4(double(x[0] + L(c[0])), double(x[1] + L(c[1])), double(x[2] + L(c[2])), 1.0);
                if (!(h[3] > 0)) continue;
                const Vec2<double> ndc = vec2(h[0] / h[3], h[1] / h[3]);
                bool inside = true;
                for (int e = 0; e < 4; ++e) {
                    const Vec2<double> p0 = cast<double>(q.corner[e]), p1 = cast<double>(q.corner[(e + 1) % 4]);
                    // Counter-clockwise corners: inside is left of every edge (1/64 pixel of slack for the double projection)
                    const double side = (p1[0] - p0[0]) * (ndc[1] - p0[1]) - (p1[1] - p0[1]) * (ndc[0] - p0[0]);
                    const double len = std::hypot(p1[0] - p0[0], p1[1] - p0[1]);
                    if (side < -len * (2.0 / 240.0) / 64.0) inside = false;
                }
                if (!inside) ++pc.outside_quad;
            }
        }
    }
    return pc;
}

void print(const char* name, const PatchCheck& pc) {
    std::printf("slim patches, %s: %d balls, %ld samples: %ld outside the slab, %ld outside the cone, %ld empty patches with samples; "
                "%ld culled views (%ld front-facing samples in them); %ld quads, %ld samples outside; mean slab width %.3f of the "
                "diameter (the samples' range %.3f)\n",
                name, pc.balls, pc.samples, pc.outside_slab, pc.outside_cone, pc.empty_with_samples, pc.culled, pc.culled_front, pc.quads,
                pc.outside_quad, pc.slab_width / std::max(1, pc.balls), pc.sampled_width / std::max(1, pc.balls));
}

}  // namespace

TEST_CASE("slim_patch: every long-double sample of random patches lies in its slab, cone and screen quadrilateral") {
    const std::vector<render::Primitive> balls = random_balls(400, 17);
    const PatchCheck pc = check_patches(balls, 5, 48, 8);
    print("random quadrics", pc);
    CHECK(pc.samples > 100000);
    CHECK(pc.outside_slab == 0);
    CHECK(pc.outside_cone == 0);
    CHECK(pc.empty_with_samples == 0);
    CHECK(pc.culled > 200);  // the cone test culls
    CHECK(pc.culled_front == 0);
    CHECK(pc.quads > 1000);
    CHECK(pc.outside_quad == 0);
}

TEST_CASE("slim_patch: the balls of built models (torus, reduced bunny)") {
    for (const char* file : {"torus_1024.off", "bunny_3k.off"}) {
        const std::vector<render::Primitive>& balls = slim::testing::model_balls(file, 3e-3);
        const PatchCheck pc = check_patches(balls, 9, 20, 3);
        print(file, pc);
        CHECK(pc.samples > 100000);
        CHECK(pc.outside_slab == 0);
        CHECK(pc.outside_cone == 0);
        CHECK(pc.empty_with_samples == 0);
        CHECK(pc.culled > long(balls.size()) / 2);  // about a quarter of the views
        CHECK(pc.culled_front == 0);
        CHECK(pc.outside_quad == 0);
        // The slab is not the ball: the sheets are nearly flat, and the slab within 0.1 diameters of their range
        CHECK(pc.slab_width < pc.sampled_width + 0.1 * pc.balls);
    }
}

TEST_CASE("slim_patch: a plane's patch is a thin slab with a closed cone; a sphere's cone opens to 90 degrees") {
    const Mat3<double> zero{};
    // The plane z = 0.1 r through a ball of radius 1: f = z - 0.1 (b = (0, 0, 0.5))
    const render::Primitive plane = ball(zero, vec3(0.0, 0.0, 0.5), -0.1, vec3(3.0, 1.0, -2.0), 1.0, vec4(0.0, 0.0, 0.0, 1.0));
    const SlimPatch<float> p = render::slim_patch(plane.shape);
    std::printf("plane z = 0.1 in the unit ball: axis (%g, %g, %g), slab [%.4f, %.4f], rho %.4f, cone cos %.6f\n", double(p.axis_rho[0]),
                double(p.axis_rho[1]), double(p.axis_rho[2]), double(p.slab_cone[0]), double(p.slab_cone[1]), double(p.axis_rho[3]),
                double(p.slab_cone[2]));
    CHECK(std::abs(p.axis_rho[2] - 1.0f) < 1e-6f);
    CHECK(p.slab_cone[0] <= 0.1f);
    CHECK(p.slab_cone[1] >= 0.1f);
    CHECK(p.slab_cone[1] - p.slab_cone[0] < 0.06f);  // boxes of 1/64 of the diameter, and the 2^-8 margins
    CHECK(p.slab_cone[2] > 0.9999f);
    // The unit sphere |x|^2 = 0.25 inside a ball of radius 1: its whole surface, every normal
    Mat3<double> id{};
    for (int i = 0; i < 3; ++i) id[i][i] = 1.0;
    const render::Primitive sphere = ball(id, vec3(0.0, 0.0, 0.0), -0.25, vec3(0.0, 0.0, 0.0), 1.0, vec4(0.0, 0.0, 0.0, 1.0));
    const SlimPatch<float> s = render::slim_patch(sphere.shape);
    CHECK(s.slab_cone[2] == 0.0f);
    CHECK(s.slab_cone[0] <= -0.5f);
    CHECK(s.slab_cone[1] >= 0.5f);
    // Cut by the plane z >= 0.3: the cap's normals lie within acos(0.6) of +z
    const render::Primitive cap = ball(id, vec3(0.0, 0.0, 0.0), -0.25, vec3(0.0, 0.0, 0.0), 1.0, vec4(0.0, 0.0, 1.0, -0.3));
    const SlimPatch<float> c = render::slim_patch(cap.shape);
    std::printf("sphere of radius 0.5 cut at z >= 0.3: axis (%g, %g, %g), slab [%.4f, %.4f], cone cos %.4f (exact 0.6)\n", double(c.axis_rho[0]),
                double(c.axis_rho[1]), double(c.axis_rho[2]), double(c.slab_cone[0]), double(c.slab_cone[1]), double(c.slab_cone[2]));
    CHECK(c.axis_rho[2] > 0.999f);
    CHECK(c.slab_cone[2] > 0.45f);
    CHECK(c.slab_cone[2] <= 0.6f);
    CHECK(c.slab_cone[0] <= 0.3f);
    CHECK(c.slab_cone[0] > 0.2f);
}

TEST_CASE("slim CPU reference: tight patch bounds and the patch cone change no pixel") {
    const std::vector<render::Primitive>& balls = slim::testing::model_balls("bunny_3k.off", 3e-3);
    const std::vector<SlimPatch<float>> patches = render::slim_patches(balls);
    int compared = 0, identical = 0;
    long culled_balls = 0;
    for (int view = 0; view < 3; ++view)
        for (bool ortho : {false, true})
            for (bool culling : {true, false}) {
                const Vec3<double> eyes[3] = {vec3(0.8, 1.1, 3.6), vec3(-2.5, -0.4, -1.0), vec3(0.2, 0.35, 0.6)};
                const Mat4<double> view_m = look_at(eyes[view], vec3(0.0, 0.0, 0.0), vec3(0.0, 1.0, 0.0));
                const Mat4<double> proj = ortho ? orthographic(2.5, 4.0 / 3.0, 0.1, 20.0) : perspective(40.0, 4.0 / 3.0, 0.1, 20.0);
                const render::Camera cam = camera_from_matrices(view_m, proj);
                render::RenderOptions opt;
                opt.width = 160;
                opt.height = 120;
                opt.culling = culling;
                render::Light light{};
                light.direction = normalize(vec3(-0.5f, -0.6f, -0.7f));
                light.color = vec3(1.0f, 1.0f, 1.0f);
                std::vector<render::SlimPixel> a, b;
                opt.tight_bounds = true;
                const render::Image tight = render::render_slim_cpu(balls, cam, light, opt, &a, 0, &patches);
                opt.tight_bounds = false;
                const render::Image loose = render::render_slim_cpu(balls, cam, light, opt, &b);
                CHECK(tight.rgba == loose.rgba);
                CHECK(tight.depth == loose.depth);
                int blended_diff = 0;
                for (std::size_t i = 0; i < a.size(); ++i) blended_diff += a[i].blended != b[i].blended || a[i].weight != b[i].weight;
                CHECK(blended_diff == 0);
                identical += tight.rgba == loose.rgba && tight.depth == loose.depth && blended_diff == 0;
                const render::FrameSetup f = render::frame_setup(cam, opt.width, opt.height);
                if (culling)
                    for (std::size_t i = 0; i < balls.size(); ++i) culled_balls += render::slim_patch_cull(balls[i], patches[i], f);
                ++compared;
            }
    std::printf("slim CPU reference, reduced bunny (%zu balls): %d of %d frames identical with tight patch bounds on and off; %ld balls culled by "
                "their patch cones over the 6 culled frames\n",
                balls.size(), identical, compared, culled_balls);
    CHECK(culled_balls > 0);
}
