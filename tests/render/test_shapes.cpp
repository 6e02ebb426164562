// tests/render/test_shapes.cpp -- the public shapes API drawn by the CPU reference, against
// independent long-double ray tracers (open and capped tubes and cones, twisted bilinear patches)
#include <doctest/doctest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <optional>
#include <string>

#include "quadcast/isosurface.hpp"
#include "quadcast/shapes.hpp"
#include "render/render_testing.hpp"

using namespace qc_render_test;
namespace shapes = quadcast::shapes;

namespace {

V3 ldv(const glm::vec3& v) { return vec3(LD(v[0]), LD(v[1]), LD(v[2])); }
V3 cross_ld(const V3& a, const V3& b) { return vec3(a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]); }

/// Every t > 0 where the ray meets the bilinear patch P(u, v), u, v in [0, 1] (Ramsey et al.'s
/// approach: two planes through the ray give two bilinear equations in u, v), nearest first; -1
/// if none. Independent of quadcast's quadric form of the patch.
LD patch_hit(const V3& o, const V3& d, const std::array<V3, 4>& p) {
    // P(u, v) = p1 + u A + v B + uv C
    const V3 A = p[1] - p[0], B = p[3] - p[0], C = (p[0] - p[1]) + (p[2] - p[3]);
    // Two normals perpendicular to d
    V3 n1 = std::fabs(d[0]) > std::fabs(d[1]) ? vec3(-d[2], LD(0), d[0]) : vec3(LD(0), d[2], -d[1]);
    n1 = n1 / norm_ld(n1);
    V3 n2 = cross_ld(d, n1);
    n2 = n2 / norm_ld(n2);
    // n.(P - o) = a uv + b u + c v + e
    const LD a1 = dot_ld(n1, C), b1 = dot_ld(n1, A), c1 = dot_ld(n1, B), e1 = dot_ld(n1, p[0] - o);
    const LD a2 = dot_ld(n2, C), b2 = dot_ld(n2, A), c2 = dot_ld(n2, B), e2 = dot_ld(n2, p[0] - o);
    // Eliminate u: u (a1 v + b1) = -(c1 v + e1), u (a2 v + b2) = -(c2 v + e2)
    // => (c1 v + e1)(a2 v + b2) - (c2 v + e2)(a1 v + b1) = 0
    const LD qa = c1 * a2 - c2 * a1, qb = c1 * b2 + e1 * a2 - c2 * b1 - e2 * a1, qc = e1 * b2 - e2 * b1;
    LD vs[2];
    int nv = 0;
    if (std::fabs(qa) < 1e-30L) {
        if (qb != 0) vs[nv++] = -qc / qb;
    } else {
        const LD disc = qb * qb - 4 * qa * qc;
        if (disc >= 0) {
            vs[nv++] = (-qb - std::sqrt(disc)) / (2 * qa);
            vs[nv++] = (-qb + std::sqrt(disc)) / (2 * qa);
        }
    }
    LD best = -1;
    for (int i = 0; i < nv; ++i) {
        const LD v = vs[i];
        const LD den1 = a1 * v + b1, den2 = a2 * v + b2;
        const LD u = std::fabs(den1) > std::fabs(den2) ? -(c1 * v + e1) / den1 : -(c2 * v + e2) / den2;
        if (!(u >= 0 && u <= 1 && v >= 0 && v <= 1)) continue;
        const V3 x = p[0] + A * u + B * v + C * (u * v);
        const LD t = dot_ld(x - o, d) / dot_ld(d, d);
        if (t > 0 && (best < 0 || t < best)) best = t;
    }
    return best;
}

struct Comparison {
    long reference = 0;      ///< pixels the reference covers
    long mismatch = 0;       ///< coverage differs
    long interior_miss = 0;  ///< the reference covers the pixel and its 8 neighbours, the render does not
    long depth_bad = 0;      ///< both cover, window depth differs by more than 1e-4
};

/// Renders `prims` with the CPU reference and compares every pixel with `hit(o, d)` (nearest t or
/// -1) traced in long double through the exact pixel rays.
template <class Hit>
Comparison compare_with(const std::vector<Primitive>& prims, const Camera& cam, int w, int h, Hit&& hit, bool culling = true) {
    RenderOptions o;
    o.width = w;
    o.height = h;
    o.culling = culling;
    Light light;
    const Image img = render_cpu(prims, cam, light, o);
    const ExactCamera ex(cam, w, h);
    std::vector<LD> ref(std::size_t(w) * h, LD(2));
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            V3 ro, rd;
            ex.ray(x, y, ro, rd);
            const LD t = hit(ro, rd);
            if (t > 0) {
                const LD z = ex.view_z(ro + rd * t);
                const LD dep = exact_depth(cam.projection, z);
                if (dep >= 0 && dep <= 1) ref[std::size_t(y) * w + x] = dep;
            }
        }
    Comparison c;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const bool r = ref[std::size_t(y) * w + x] < 2;
            const bool g = covered(img, x, y);
            c.reference += r;
            if (r != g) {
                ++c.mismatch;
                bool interior = r;
                for (int dy = -1; dy <= 1 && interior; ++dy)
                    for (int dx = -1; dx <= 1 && interior; ++dx) {
                        const int xx = std::clamp(x + dx, 0, w - 1), yy = std::clamp(y + dy, 0, h - 1);
                        interior = ref[std::size_t(yy) * w + xx] < 2;
                    }
                c.interior_miss += interior && !g;
                continue;
            }
            if (r && std::fabs(double(ref[std::size_t(y) * w + x]) - double(depth_at(img, x, y))) > 1e-4) ++c.depth_bad;
        }
    return c;
}

Camera view_from(const Vec3<double>& eye, bool ortho = false) {
    return ortho ? look_at(eye, vec3(0.0, 0.0, 0.0), vec3(0.0, 1.0, 0.0), orthographic(-2.5, 2.5, -2, 2, 0.5, 30), true)
                 : look_at(eye, vec3(0.0, 0.0, 0.0), vec3(0.0, 1.0, 0.0), perspective(40, 1.25, 0.5, 30));
}

}  // namespace

TEST_CASE("open and capped cylinders: the CPU reference draws what an independent tracer sees") {
    const glm::vec3 p0(-0.3f, -1.0f, 0.2f), p1(0.4f, 1.1f, -0.3f);
    const float r = 0.55f;
    // Seen obliquely from above p1's end: the inside of an open tube shows through its opening.
    for (bool ortho : {false, true})
        for (const auto& [ends, cap0, cap1, name] : {std::tuple{shapes::Ends::both, true, true, "both"}, std::tuple{shapes::Ends::none, false, false, "none"},
                                                     std::tuple{shapes::Ends::first, true, false, "first"}, std::tuple{shapes::Ends::second, false, true, "second"}}) {
            const std::vector<Primitive> prims = {shapes::cylinder(p0, p1, r, ends)};
            const Camera cam = view_from(vec3(1.5, 5.0, 2.5), ortho);
            const bool c0 = cap0, c1 = cap1;  // (Clang 14 cannot capture structured bindings)
            const Comparison c = compare_with(prims, cam, 200, 160, [&](const V3& o, const V3& d) { return tube_hit(o, d, ldv(p0), ldv(p1), r, c0, c1); });
            std::printf("[open slabs] cylinder, ends %s, %s: %ld reference px, %ld coverage mismatches (%ld interior), %ld depth > 1e-4\n", name,
                        ortho ? "orthographic" : "perspective", c.reference, c.mismatch, c.interior_miss, c.depth_bad);
            CHECK(c.reference > 2000);
            CHECK(c.interior_miss == 0);
            CHECK(c.mismatch <= c.reference / 100);
            CHECK(c.depth_bad <= c.reference / 200);
        }
    // Looking down the tube's axis: the open tube shows the background through its hole, a
    // closed one the disc; each drawing against the other's reference differs a lot (so the
    // comparison above would catch an ignored `ends`).
    const Vec3<double> along = cast<double>(quadcast::from_glm(p1)) + 4.0 * normalize(cast<double>(quadcast::from_glm(p1 - p0)));
    const Camera end_on = look_at(along, vec3(0.0, 0.0, 0.0), vec3(1.0, 0.0, 0.0), perspective(40, 1.25, 0.5, 30));
    for (shapes::Ends ends : {shapes::Ends::none, shapes::Ends::both}) {
        const bool open = ends == shapes::Ends::none;
        const Comparison same = compare_with({shapes::cylinder(p0, p1, r, ends)}, end_on, 200, 160,
                                             [&](const V3& o, const V3& d) { return tube_hit(o, d, ldv(p0), ldv(p1), r, !open, !open); });
        const Comparison other = compare_with({shapes::cylinder(p0, p1, r, ends)}, end_on, 200, 160,
                                              [&](const V3& o, const V3& d) { return tube_hit(o, d, ldv(p0), ldv(p1), r, open, open); });
        std::printf("[open slabs] end-on, ends %s: %ld reference px, %ld mismatches, %ld depth > 1e-4; against the other kind's reference %ld mismatches, %ld depth > 1e-4\n",
                    open ? "none" : "both", same.reference, same.mismatch, same.depth_bad, other.mismatch, other.depth_bad);
        CHECK(same.interior_miss == 0);
        CHECK(same.mismatch <= same.reference / 100);
        CHECK(same.depth_bad <= same.reference / 200);
        CHECK(other.mismatch + other.depth_bad > same.reference / 4);
    }
}

TEST_CASE("open and capped cones: the CPU reference draws what an independent tracer sees") {
    const glm::vec3 apex(0.2f, 1.2f, 0.1f), base(-0.2f, -0.9f, -0.1f);
    const float r = 0.8f;
    for (bool cap : {true, false})
        for (const Vec3<double>& eye : {vec3(1.0, -5.0, 2.0), vec3(2.0, 4.0, 3.0)}) {
            const std::vector<Primitive> prims = {shapes::cone(apex, base, r, cap)};
            const Camera cam = view_from(eye);
            const Comparison c = compare_with(prims, cam, 200, 160, [&](const V3& o, const V3& d) { return cone_hit(o, d, ldv(apex), ldv(base), r, cap); });
            std::printf("[open slabs] cone, cap %s, eye (%g, %g, %g): %ld reference px, %ld coverage mismatches (%ld interior), %ld depth > 1e-4\n",
                        cap ? "on" : "off", eye[0], eye[1], eye[2], c.reference, c.mismatch, c.interior_miss, c.depth_bad);
            CHECK(c.reference > 2000);
            CHECK(c.interior_miss == 0);
            CHECK(c.mismatch <= c.reference / 100);
            CHECK(c.depth_bad <= c.reference / 200);
        }
}

TEST_CASE("strongly twisted bilinear quads are drawn whole (independent ray-patch intersection)") {
    // Opposite corner normals about 140 degrees apart: seen along any corner normal the quad's
    // outline is not convex.
    for (float k : {0.3f, 1.0f, 2.0f, 4.0f}) {
        const std::array<glm::vec3, 4> q = {glm::vec3(-1, -1, k), glm::vec3(1, -1, -k), glm::vec3(1, 1, k), glm::vec3(-1, 1, -k)};
        const std::array<V3, 4> ql = {ldv(q[0]), ldv(q[1]), ldv(q[2]), ldv(q[3])};
        const std::vector<Primitive> prims = {shapes::quad(q[0], q[1], q[2], q[3])};
        for (const Vec3<double>& eye : {vec3(0.3, 0.4, 9.0), vec3(6.0, 2.0, 5.0), vec3(-3.0, 7.0, -4.0)}) {
            const Camera cam = look_at(eye, vec3(0.0, 0.0, 0.0), vec3(0.0, 1.0, 0.0), perspective(45, 1.25, 0.5, 40));
            const Comparison c = compare_with(prims, cam, 200, 160, [&](const V3& o, const V3& d) { return patch_hit(o, d, ql); }, false);
            std::printf("[twisted quad] k %g, eye (%g, %g, %g): %ld reference px, %ld coverage mismatches (%ld interior), %ld depth > 1e-4\n", double(k), eye[0], eye[1],
                        eye[2], c.reference, c.mismatch, c.interior_miss, c.depth_bad);
            CHECK(c.reference > 800);
            CHECK(c.interior_miss == 0);
            CHECK(c.mismatch <= c.reference / 100);
            CHECK(c.depth_bad <= c.reference / 200);
        }
    }
    // The clip this replaced, the edges extruded along the largest corner triangle's normal, cuts
    // real parts off the strongly twisted quads (so the comparison above tells the two apart).
    const std::array<glm::vec3, 4> q = {glm::vec3(-1, -1, 4), glm::vec3(1, -1, -4), glm::vec3(1, 1, 4), glm::vec3(-1, 1, -4)};
    const std::array<V3, 4> ql = {ldv(q[0]), ldv(q[1]), ldv(q[2]), ldv(q[3])};
    Primitive cut = shapes::quad(q[0], q[1], q[2], q[3]);
    std::array<Vec3<double>, 4> qd{};
    for (int i = 0; i < 4; ++i) qd[std::size_t(i)] = cast<double>(quadcast::from_glm(q[std::size_t(i)]));
    const shapes::QuadClip old = shapes::detail::extruded_edges(qd, cast<double>(cut.shape.center), shapes::detail::quad_normal(qd), double(cut.shape.radius));
    for (int i = 0; i < 4; ++i) cut.shape.planes[i] = cast<float>(old.planes[i]);
    cut.shape.axis = cast<float>(old.axis);
    cut.shape.half_length = float(old.half_length);
    const Camera cam = look_at(vec3(6.0, 2.0, 5.0), vec3(0.0, 0.0, 0.0), vec3(0.0, 1.0, 0.0), perspective(45, 1.25, 0.5, 40));
    const Comparison c = compare_with({cut}, cam, 200, 160, [&](const V3& o, const V3& d) { return patch_hit(o, d, ql); }, false);
    std::printf("[twisted quad] extruded-edge clip, k 4: %ld reference px, %ld coverage mismatches (%ld interior)\n", c.reference, c.mismatch, c.interior_miss);
    CHECK(c.interior_miss > c.reference / 20);
}

TEST_CASE("a mesh of twisted quads sharing edges has no pinholes") {
    // A 6 x 6 grid over z = 0.8 sin(2x) cos(3y) with every vertex pushed up or down alternately:
    // neighbouring patches twist in opposite senses, and every interior edge is shared.
    const int n = 6;
    auto vertex = [&](int i, int j) {
        const float x = -1.5f + 3.0f * i / n, y = -1.5f + 3.0f * j / n;
        return glm::vec3(x, y, 0.8f * std::sin(2 * x) * std::cos(3 * y) + ((i + j) % 2 ? 0.25f : -0.25f));
    };
    std::vector<Primitive> prims;
    std::vector<std::array<V3, 4>> quads;
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const std::array<glm::vec3, 4> q = {vertex(i, j), vertex(i + 1, j), vertex(i + 1, j + 1), vertex(i, j + 1)};
            prims.push_back(shapes::quad(q[0], q[1], q[2], q[3]));
            quads.push_back({ldv(q[0]), ldv(q[1]), ldv(q[2]), ldv(q[3])});
        }
    for (const Vec3<double>& eye : {vec3(0.2, -1.0, 6.0), vec3(4.0, -3.0, 3.0), vec3(-2.0, 4.0, 1.5)}) {
        const Camera cam = look_at(eye, vec3(0.0, 0.0, 0.0), vec3(0.0, 0.0, 1.0), perspective(50, 1.25, 0.3, 40));
        const Comparison c = compare_with(prims, cam, 240, 192, [&](const V3& o, const V3& d) {
            LD best = -1;
            for (const auto& q : quads) {
                const LD t = patch_hit(o, d, q);
                if (t > 0 && (best < 0 || t < best)) best = t;
            }
            return best;
        }, false);
        std::printf("[quad mesh] eye (%g, %g, %g): %ld reference px, %ld coverage mismatches (%ld interior), %ld depth > 1e-4\n", eye[0], eye[1], eye[2],
                    c.reference, c.mismatch, c.interior_miss, c.depth_bad);
        CHECK(c.reference > 5000);
        CHECK(c.interior_miss == 0);
        CHECK(c.mismatch <= c.reference / 100);
    }
}

TEST_CASE("specular and shininess of each primitive reach the picture") {
    Light light;
    light.direction = vec3(-0.3f, -0.4f, -1.0f);
    RenderOptions o;
    o.width = 160;
    o.height = 120;
    const Camera cam = look_at(vec3(0.0, 0.0, 6.0), vec3(0.0, 0.0, 0.0), vec3(0.0, 1.0, 0.0), perspective(40, 160.0 / 120, 1, 20));
    shapes::Appearance matte{{0.5f, 0.3f, 0.2f}, 0.0f, 2.0f}, shiny{{0.5f, 0.3f, 0.2f}, 1.0f, 200.0f};
    const Image a = render_cpu({shapes::sphere({0, 0, 0}, 1.0f, matte)}, cam, light, o);
    const Image b = render_cpu({shapes::sphere({0, 0, 0}, 1.0f, shiny)}, cam, light, o);
    int brightest_a = 0, brightest_b = 0;
    long differ = 0;
    for (std::size_t i = 0; i < a.depth.size(); ++i) {
        if (a.depth[i] >= 1.0f) continue;
        brightest_a = std::max(brightest_a, int(a.rgba[i * 4]));
        brightest_b = std::max(brightest_b, int(b.rgba[i * 4]));
        differ += a.rgba[i * 4] != b.rgba[i * 4];
    }
    std::printf("[materials] matte sphere brightest red %d, shiny %d, %ld pixels differ\n", brightest_a, brightest_b, differ);
    // Without a highlight the red channel stays at colour * (ambient + diffuse) = 0.5 * 1.0.
    CHECK(brightest_a <= 128);
    CHECK(brightest_b == 255);
    CHECK(differ > 100);
}

TEST_CASE("shapes validate their input and name the field") {
    auto message = [](auto&& fn) -> std::string {
        try {
            fn();
        } catch (const std::invalid_argument& e) {
            return e.what();
        }
        return "";
    };
    CHECK(message([] { shapes::sphere({0, 0, 0}, -1.0f); }).find("sphere: radius must be positive") != std::string::npos);
    CHECK(message([] { shapes::sphere({0, 0, 0}, std::nanf("")); }).find("radius") != std::string::npos);
    CHECK(message([] { shapes::sphere({0, std::nanf(""), 0}, 1.0f); }).find("center must be finite") != std::string::npos);
    CHECK(message([] { shapes::cylinder({0, 0, 0}, {0, 0, 0}, 1.0f); }).find("p0 and p1 coincide") != std::string::npos);
    CHECK(message([] { shapes::cone({0, 0, 0}, {0, 0, 1}, 0.0f); }).find("cone: radius") != std::string::npos);
    CHECK(message([] { shapes::quad({0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {3, 0, 0}); }).find("collinear") != std::string::npos);
    CHECK(message([] { shapes::ellipsoid({0, 0, 0}, glm::mat3(glm::vec3(1, 0, 0), glm::vec3(2, 0, 0), glm::vec3(0, 0, 1))); }).find("linearly dependent") != std::string::npos);
    CHECK(message([] { shapes::tensor_ellipsoid({0, 0, 0}, glm::mat3(glm::vec3(1, 0, 0), glm::vec3(0, -1, 0), glm::vec3(0, 0, 1))); }).find("positive definite") != std::string::npos);
    CHECK(message([] { shapes::tensor_ellipsoid({0, 0, 0}, glm::mat3(glm::vec3(1, 2, 0), glm::vec3(0, 1, 0), glm::vec3(0, 0, 1))); }).find("not symmetric") != std::string::npos);
    CHECK(message([] { shapes::sphere({0, 0, 0}, 1.0f, {{1.5f, 0, 0}}); }).find("color") != std::string::npos);
    CHECK(message([] { shapes::sphere({0, 0, 0}, 1.0f, {{1, 1, 1}, 2.0f}); }).find("specular") != std::string::npos);
    CHECK(message([] { shapes::quadric(glm::mat4(0.0f), shapes::SphereBound{{0, 0, 0}, 1.0f}); }).find("zero") != std::string::npos);
    CHECK(message([] { shapes::quadric(glm::mat4(1.0f), shapes::TetrahedronBound{{glm::vec3(0, 0, 0), glm::vec3(1, 0, 0), glm::vec3(0, 1, 0), glm::vec3(1, 1, 0)}}); })
              .find("flat") != std::string::npos);
    CHECK(message([] { shapes::camera(glm::mat4(2.0f), glm::mat4(1.0f)); }).find("not rigid") != std::string::npos);
}

TEST_CASE("tensor glyphs: semi-axes are the eigenvectors scaled by the eigenvalues") {
    // A tensor with eigenvalues 3, 2, 0.5 along a rotated frame.
    const glm::vec3 e0 = glm::normalize(glm::vec3(1, 1, 0)), e1 = glm::normalize(glm::vec3(-1, 1, 0)), e2(0, 0, 1);
    glm::mat3 t(0.0f);
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) t[j][i] = 3.0f * e0[i] * e0[j] + 2.0f * e1[i] * e1[j] + 0.5f * e2[i] * e2[j];
    const shapes::TensorAxes ax = shapes::tensor_axes(t);
    CHECK(ax.eigenvalues[0] == doctest::Approx(3.0f).epsilon(1e-5));
    CHECK(ax.eigenvalues[1] == doctest::Approx(2.0f).epsilon(1e-5));
    CHECK(ax.eigenvalues[2] == doctest::Approx(0.5f).epsilon(1e-5));
    CHECK(std::fabs(glm::dot(ax.eigenvectors[0], e0)) == doctest::Approx(1.0f).epsilon(1e-5));
    const glm::vec3 c = shapes::principal_direction_color(t);
    CHECK(c[0] == doctest::Approx(std::sqrt(0.5f)).epsilon(1e-4));
    CHECK(c[2] == doctest::Approx(0.0f).epsilon(1e-4));
    const Primitive p = shapes::tensor_ellipsoid({1, 2, 3}, t, 0.5f);
    CHECK(p.shape.radius == doctest::Approx(1.5f).epsilon(1e-5));
    // The point centre + 1.5 e0 lies on the surface (f = 0, local coordinates).
    const Vec3<float> x = vec3(1.5f * e0[0], 1.5f * e0[1], 1.5f * e0[2]);
    CHECK(std::fabs(quadcast::evaluate(p.shape.q, x)) < 1e-5f);
}

TEST_CASE("hand-made primitives are validated by the renderers") {
    Light light;
    RenderOptions o;
    o.width = 64;
    o.height = 48;
    const Camera cam = look_at(vec3(0.0, 0.0, 6.0), vec3(0.0, 0.0, 0.0), vec3(0.0, 1.0, 0.0), perspective(40, 64.0 / 48, 1, 20));
    auto message = [&](const Primitive& p) -> std::string {
        try {
            render_cpu({sphere(vec3(2.0f, 0.0f, 0.0f), 0.5f), p}, cam, light, o);
        } catch (const std::invalid_argument& e) {
            return e.what();
        }
        return "";
    };
    Primitive small = ellipsoid(vec3(0.0f, 0.0f, 0.0f), std::array<Vec3<double>, 3>{vec3(1.0, 0.0, 0.0), vec3(0.0, 1.0, 0.0), vec3(0.0, 0.0, 1.0)}.data(), vec3(2.0, 1.0, 1.0));
    small.shape.radius = 1.5f;  // the ellipsoid reaches 2
    CHECK(message(small).find("primitive 1: the bounding radius 1.5 is smaller than the ellipsoid's extent 2") != std::string::npos);
    Primitive nan_radius = sphere(vec3(0.0f, 0.0f, 0.0f), 1.0f);
    nan_radius.shape.radius = std::nanf("");
    CHECK(message(nan_radius).find("primitive 1: radius must be positive and finite") != std::string::npos);
    Primitive stubby = cylinder(vec3(0.0f, 0.0f, 0.0f), vec3(0.0f, 0.0f, 1.0f), 0.5f, 1.0f);
    stubby.shape.radius = 1.0f;  // needs sqrt(1.25)
    CHECK(message(stubby).find("smaller than the shape's extent") != std::string::npos);
    Primitive bad_spec = sphere(vec3(0.0f, 0.0f, 0.0f), 1.0f);
    bad_spec.material.specular = 3.0f;
    CHECK(message(bad_spec).find("material.specular") != std::string::npos);
    // A closed quadric marked as a slab bulges out between its end sections: the tight screen
    // rectangle (the hull of the end sections) would crop it.
    auto as_slab = [](Primitive p, float h) {
        p.variant = Variant::slab;
        p.shape.half_length = h;
        p.shape.caps[0] = p.shape.caps[1] = 1.0f;
        return p;
    };
    CHECK(message(as_slab(sphere(vec3(0.0f, 0.0f, 0.0f), 1.0f), 0.5f)).find("primitive 1: variant slab: the surface bulges out between its end sections") != std::string::npos);
    CHECK(message(as_slab(small, 0.9f)).find("bulges out") != std::string::npos);
    // A hyperboloid of one sheet narrows between its ends (x^2 + y^2 - z^2 = 0.25), a cone whose
    // apex lies inside the slab is two cones: both lie inside the hull of their end sections.
    Mat3<float> saddle = identity<float, 3>();
    saddle[2][2] = -1.0f;
    Primitive hyperboloid = as_slab(sphere(vec3(0.0f, 0.0f, 0.0f), 1.2f), 0.6f);
    hyperboloid.shape.q = quadric_from_abc(saddle, vec3(0.0f, 0.0f, 0.0f), -0.25f);
    CHECK(message(hyperboloid).empty());
    Primitive double_cone = hyperboloid;
    double_cone.shape.q = quadric_from_abc(saddle, vec3(0.0f, 0.0f, 0.0f), 0.0f);
    CHECK(message(double_cone).empty());
    // Valid ones pass.
    CHECK(message(cylinder(vec3(0.0f, 0.0f, 0.0f), vec3(0.0f, 0.0f, 1.0f), 0.5f, 1.0f)).empty());
    CHECK(message(shapes::cone({0, 0, 0}, {0, 0, 1}, 0.3f, false)).empty());
    CHECK(message(shapes::cylinder({0, 0, 0}, {0.3, -2, 1}, 0.2f, shapes::Ends::first)).empty());
}

namespace {

/// Samples of the distance to `c` on an anisotropic grid around it: nx x ny x nz samples from
/// `origin` with `spacing` (a different spacing per axis, so that a swapped axis shows).
quadcast::spline::Volume<float> distance_volume(const V3& c, const glm::dvec3& origin, const glm::dvec3& spacing, int nx, int ny, int nz) {
    quadcast::spline::Volume<float> v(nx, ny, nz);
    for (int k = 0; k < nz; ++k)
        for (int j = 0; j < ny; ++j)
            for (int i = 0; i < nx; ++i) {
                const V3 x = vec3(LD(origin.x + spacing.x * i), LD(origin.y + spacing.y * j), LD(origin.z + spacing.z * k));
                v.at(i, j, k) = float(norm_ld(x - c));
            }
    return v;
}

/// A 96 x 72 view from `eye` to `target` (35 degrees) with a light from the upper left.
struct IsoView {
    Light light;
    RenderOptions options;
    Camera camera;
    IsoView(const Vec3<double>& eye, const Vec3<double>& target)
        : camera(look_at(eye, target, vec3(0.0, 1.0, 0.0), perspective(35, 96.0 / 72, 1, 20))) {
        light.direction = vec3(-0.3f, -0.4f, -1.0f);
        options.width = 96;
        options.height = 72;
    }
};

}  // namespace

TEST_CASE("volume isosurface: placed by origin and spacing where an independent tracer sees the sphere") {
    // f = |x - c| sampled on an anisotropic grid; f = 1 is the sphere of radius 1 around c.
    const V3 c = vec3(LD(0.2), LD(-0.1), LD(0.15));
    const glm::dvec3 spacing(0.1, 0.125, 0.09), origin(-1.4, -1.6, -1.3);
    const auto vol = distance_volume(c, origin, spacing, 30, 24, 33);
    const IsoView v(vec3(0.5, 0.8, 5.0), vec3(0.1, 0.0, 0.0));
    const Light& light = v.light;
    const RenderOptions& o = v.options;
    const Camera& cam = v.camera;
    const ExactCamera ex(cam, o.width, o.height);
    for (const shapes::Reconstruction scheme : {shapes::Reconstruction::qss, shapes::Reconstruction::s31, shapes::Reconstruction::trilinear}) {
        const quadcast::render::VolumeModel m = shapes::isosurface(vol, origin, spacing, 1.0f, scheme, {}, true);
        const Image img = quadcast::render::render_volumes_cpu({&m}, cam, light, o);
        // Rays that pass the centre closer than 0.9 must hit, farther than 1.1 must miss (the
        // reconstruction of a distance field is within a fraction of a voxel of the sphere).
        long inside = 0, outside = 0, wrong = 0;
        for (int y = 0; y < o.height; ++y)
            for (int x = 0; x < o.width; ++x) {
                V3 ro, rd;
                ex.ray(x, y, ro, rd);
                const LD dist = line_distance(ro, rd, c);
                if (dist < 0.9L) {
                    ++inside;
                    wrong += !covered(img, x, y);
                } else if (dist > 1.1L) {
                    ++outside;
                    wrong += covered(img, x, y);
                }
            }
        std::printf("[isosurface] %s: %ld inside, %ld outside pixels, %ld wrong\n", quadcast::render::volume_scheme_name(scheme), inside, outside, wrong);
        CHECK(inside > 1000);
        CHECK(wrong == 0);
    }
}

TEST_CASE("volume isosurface: specular and shininess reach the picture; invalid input names the field") {
    const V3 c = vec3(LD(0), LD(0), LD(0));
    const glm::dvec3 spacing(0.1, 0.1, 0.1), origin(-1.5, -1.5, -1.5);
    const auto vol = distance_volume(c, origin, spacing, 31, 31, 31);
    const IsoView v(vec3(0.0, 0.0, 5.0), vec3(0.0, 0.0, 0.0));
    const Light& light = v.light;
    const RenderOptions& o = v.options;
    const Camera& cam = v.camera;
    const shapes::Appearance matte{{0.5f, 0.3f, 0.2f}, 0.0f, 2.0f}, shiny{{0.5f, 0.3f, 0.2f}, 1.0f, 200.0f};
    const quadcast::render::VolumeModel a = shapes::isosurface(vol, origin, spacing, 1.0f, shapes::Reconstruction::qss, matte, true);
    const quadcast::render::VolumeModel b = shapes::isosurface(vol, origin, spacing, 1.0f, shapes::Reconstruction::qss, shiny, true);
    const Image ia = quadcast::render::render_volumes_cpu({&a}, cam, light, o), ib = quadcast::render::render_volumes_cpu({&b}, cam, light, o);
    int brightest_a = 0, brightest_b = 0;
    for (std::size_t i = 0; i < ia.depth.size(); ++i) {
        if (ia.depth[i] >= 1.0f) continue;
        brightest_a = std::max(brightest_a, int(ia.rgba[i * 4]));
        brightest_b = std::max(brightest_b, int(ib.rgba[i * 4]));
    }
    std::printf("[isosurface materials] matte brightest red %d, shiny %d\n", brightest_a, brightest_b);
    CHECK(brightest_a <= 128);
    CHECK(brightest_b == 255);

    auto message = [&](auto&& fn) -> std::string {
        try {
            fn();
        } catch (const std::invalid_argument& e) {
            return e.what();
        }
        return "";
    };
    CHECK(message([&] { shapes::isosurface(vol, origin, spacing, 5.0f); }).find("isosurface: iso 5 is outside the range of the samples") != std::string::npos);
    CHECK(message([&] { shapes::isosurface(vol, origin, spacing, std::nanf("")); }).find("iso must be finite") != std::string::npos);
    CHECK(message([&] { shapes::isosurface(vol, origin, glm::dvec3(0.1, 0.0, 0.1), 1.0f); }).find("spacing must be positive") != std::string::npos);
    CHECK(message([&] { shapes::isosurface(vol, glm::dvec3(0, std::nan(""), 0), spacing, 1.0f); }).find("origin must be finite") != std::string::npos);
    CHECK(message([&] { shapes::isosurface(vol, origin, spacing, 1.0f, shapes::Reconstruction::qss, {{1.5f, 0, 0}}); }).find("color") != std::string::npos);
    CHECK(message([&] { shapes::isosurface(quadcast::spline::Volume<float>(1, 4, 4), origin, spacing, 0.0f, shapes::Reconstruction::trilinear); })
              .find("at least 2 samples") != std::string::npos);
}

TEST_CASE("rays just inside a capped cylinder's rims hit its front surface (independent tracer)") {
    // Where a cap meets the wall, a ray entering the solid close to the rim is kept by neither
    // clip test when the float wall hit rounds beyond the cap plane and the cap hit rounds outside
    // the quadric: the back wall shows through (culling off) or nothing (culling on). Rays aimed
    // at points inside the solid by 2^-10 of the radius from a rim, from eyes 3 to 3000 radii
    // away and up to 50 units off the origin, against the long-double tube_hit.
    long trials = 0, missed[2] = {0, 0}, off_front[2] = {0, 0};
    for (int it = 0; it < 40000; ++it) {
        std::mt19937 rng = rng_for(31, static_cast<std::uint32_t>(it));
        const double r = uniform(rng, 0.002, 0.3), len = r * uniform(rng, 1.0, 40.0);
        const Vec3<double> centre = random_dir(rng) * uniform(rng, 0.0, 50.0), ax = random_dir(rng);
        const glm::vec3 p0 = glm::vec3(centre[0], centre[1], centre[2]) - glm::vec3(ax[0], ax[1], ax[2]) * float(0.5 * len);
        const glm::vec3 p1 = glm::vec3(centre[0], centre[1], centre[2]) + glm::vec3(ax[0], ax[1], ax[2]) * float(0.5 * len);
        const Primitive prim = shapes::cylinder(p0, p1, float(r), shapes::Ends::both);
        // A point inside the solid near the rim of one end
        const V3 a = ldv(p0), b = ldv(p1), axis = (b - a) / norm_ld(b - a);
        const V3 t0 = std::fabs(axis[0]) < 0.9L ? vec3(LD(1), LD(0), LD(0)) : vec3(LD(0), LD(1), LD(0));
        V3 e1 = cross_ld(axis, t0);
        e1 = e1 / norm_ld(e1);
        const V3 e2 = cross_ld(axis, e1);
        const LD phi = uniform(rng, 0.0, 6.283185307179586), in = LD(r) / 1024;
        const bool end1 = it % 2 == 1;
        const V3 rim = (end1 ? b : a) + (e1 * std::cos(phi) + e2 * std::sin(phi)) * (LD(r) - in) + axis * (end1 ? -in : in);
        const Vec3<double> dir = random_dir(rng);
        const double dist = r * std::exp(uniform(rng, std::log(3.0), std::log(3000.0)));
        const glm::vec3 eye(float(rim[0] + dir[0] * dist), float(rim[1] + dir[1] * dist), float(rim[2] + dir[2] * dist));
        const V3 o = ldv(eye);
        V3 d = rim - o;
        d = d / norm_ld(d);
        const V3 oa = o - a;
        const LD along = dot_ld(oa, axis), radial = norm_ld(oa - axis * along);
        if (along >= 0 && along <= norm_ld(b - a) && radial <= LD(r)) continue;  // the eye inside the solid
        const LD exact = tube_hit(o, d, a, b, LD(r), true, true);
        if (!(exact > 0)) continue;
        ++trials;
        const glm::vec3 df{float(d[0]), float(d[1]), float(d[2])};
        const quadcast::LocalRay<float> lr = quadcast::local_ray(prim.shape, quadcast::from_glm(eye), quadcast::from_glm(df));
        for (int cull = 0; cull < 2; ++cull) {
            using quadcast::render::cast_options;
            const quadcast::CastHit<float> h = cull ? quadcast::cast_ray<cast_options(Variant::slab, true)>(prim.shape, lr) : quadcast::cast_ray<cast_options(Variant::slab, false)>(prim.shape, lr);
            // The front surface: a hit facing the ray (not the back wall) on the exact surface to
            // 2^-16 of the distances involved (the float ray and the float quadric are not the exact
            // ones, and along a grazing ray that moves the hit far; off the surface it does not).
            if (!h.hit) {
                ++missed[cull];
                continue;
            }
            const V3 x = o + d * LD(h.lambda);
            const V3 xa = x - a;
            const LD l = norm_ld(b - a), al = dot_ld(xa, axis), dr = norm_ld(xa - axis * al) - LD(r), dz = std::fabs(al - l / 2) - l / 2;
            const LD sdf = std::max(dr, dz) < 0 ? std::max(dr, dz) : std::sqrt(std::max(dr, LD(0)) * std::max(dr, LD(0)) + std::max(dz, LD(0)) * std::max(dz, LD(0)));
            const LD tol = (LD(dist) + LD(len) + LD(norm_ld(ldv(glm::vec3(p0 + p1) * 0.5f)))) / 65536;
            const bool facing = quadcast::dot(h.normal, lr.v) < 0.0f;
            if (!facing || std::fabs(sdf) > tol) {
                if (off_front[cull] < 3) std::printf("  iteration %d, culling %d: hit at %.9g, %s, %.3Lg from the surface\n", it, cull, double(h.lambda), facing ? "facing the ray" : "facing away", sdf);
                ++off_front[cull];
            }
        }
    }
    std::printf("[cap rims] %ld rays just inside the rim: culling off %ld missed, %ld hits off the front surface; culling on %ld missed, %ld off the front surface\n", trials,
                missed[0], off_front[0], missed[1], off_front[1]);
    CHECK(trials > 30000);
    CHECK(missed[0] + missed[1] == 0);
    CHECK(off_front[0] + off_front[1] == 0);
}
