// tests/gl/test_occlusion_gl.cpp -- the occlusion cull pass changes no pixel (forward, deferred,
// shadows and outlines, culling on and off, tight bounds off, slab rectangles, perspective and
// orthographic, eye inside bounds, near and far planes through occluders; the survivors' corners
// from the vertex stage or from a compute pass; occluders from a compute pass or drawn by the
// rasteriser), and it culls what is hidden or off screen; occluder quadrilaterals lie behind the
// surfaces in front of them (long double rays)
#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <memory>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "quadcast/gl/framebuffer.hpp"
#include "quadcast/gl/osmesa_context.hpp"
#include "quadcast/gl/quadric_renderer.hpp"
#include "quadcast/render/cpu_renderer.hpp"
#include "quadcast/render/environment.hpp"
#include "quadcast/occlusion.hpp"
#include "quadcast/render/occluder.hpp"
#include "core/param_test_util.hpp"
#include "gl/host_frame.hpp"
#include "render/bounds_scenes.hpp"

using namespace qc_bounds_test;

namespace {

/// A dense block of spheres, ellipsoids and capped cylinders in [0, 1]^3 (most of them hidden
/// from outside), with a few open cylinders and cones, which do not occlude.
std::vector<Primitive> dense_block(unsigned seed, int n) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(0.0f, 1.0f), c(0.2f, 1.0f), ang(0.0f, 6.2831853f);
    const float r = 0.6f * std::cbrt(1.0f / float(n));
    std::vector<Primitive> out;
    for (int i = 0; i < n; ++i) {
        const glm::vec3 p(u(rng), u(rng), u(rng));
        const shapes::Appearance look{{c(rng), c(rng), c(rng)}, 0.35f, 48.0f};
        const glm::vec3 d = glm::normalize(glm::vec3(u(rng) - 0.5f, u(rng) - 0.5f, u(rng) - 0.5f) + glm::vec3(0.01f));
        switch (i % 8) {
        case 0: case 1: case 2: case 3: out.push_back(shapes::sphere(p, r * (0.6f + u(rng)), look)); break;
        case 4: {
            const glm::mat4 rot = glm::rotate(glm::mat4(1.0f), ang(rng), d);
            out.push_back(shapes::ellipsoid(p, glm::vec3(1.2f * r, 0.7f * r, r), glm::mat3(rot), look));
            break;
        }
        case 5: out.push_back(shapes::cylinder(p - d * r, p + d * r, 0.6f * r, shapes::Ends::both, look)); break;
        case 6: out.push_back(shapes::cylinder(p - d * r, p + d * r, 0.5f * r, shapes::Ends::none, look)); break;
        default: out.push_back(shapes::cone(p - d * r, p + d * r, 0.7f * r, true, look)); break;
        }
    }
    return out;
}

struct Case {
    std::string name;
    std::vector<Primitive> prims;
    Camera camera;
};

std::vector<Case> occlusion_cases(int w, int h) {
    using qc_render_test::look_at;
    const double aspect = double(w) / h;
    std::vector<Case> out;
    for (const BoundsScene& b : bounds_scenes(w, h)) out.push_back({b.name, b.prims, b.camera});
    const std::vector<Primitive> block = dense_block(5, 3000);
    out.push_back({"dense block, perspective", block, look_at(vec3(0.4, 0.7, 2.6), vec3(0.5, 0.5, 0.5), vec3(0.0, 1.0, 0.0), qc_render_test::perspective(35, aspect, 1, 5))});
    out.push_back({"dense block, orthographic", block,
                   look_at(vec3(1.9, 1.2, 2.3), vec3(0.5, 0.5, 0.5), vec3(0.0, 1.0, 0.0), qc_render_test::orthographic(-0.9 * aspect, 0.9 * aspect, -0.9, 0.9, 0.5, 5), true)});
    // The near plane through the block (occluders cut open show what lies behind them) and the
    // far plane through it (occluders beyond it are not drawn).
    out.push_back({"dense block, near plane through it", block, look_at(vec3(0.5, 0.5, 1.6), vec3(0.5, 0.5, 0.5), vec3(0.0, 1.0, 0.0), qc_render_test::perspective(40, aspect, 0.9, 5))});
    out.push_back({"dense block, far plane through it", block, look_at(vec3(0.5, 0.5, 2.4), vec3(0.5, 0.5, 0.5), vec3(0.0, 1.0, 0.0), qc_render_test::perspective(40, aspect, 1, 2.0))});
    // A large sphere whose front the near plane cuts away (its centre plane beyond the near
    // plane): the small spheres behind it show through the cut.
    {
        std::vector<Primitive> p{shapes::sphere({0, 0, 0}, 1.0f, {{0.9f, 0.9f, 0.9f}})};
        std::mt19937 rng(4);
        std::uniform_real_distribution<float> u(-0.4f, 0.4f);
        for (int i = 0; i < 40; ++i) p.push_back(shapes::sphere({u(rng), u(rng), -2.0f + u(rng)}, 0.15f));
        out.push_back({"large sphere cut by the near plane", p, look_at(vec3(0.0, 0.0, 1.0995), vec3(0.0, 0.0, 0.0), vec3(0.0, 1.0, 0.0), qc_render_test::perspective(60, aspect, 0.1, 10))});
    }
    // The eye inside a long ellipsoid, small spheres inside it ahead; and an ellipsoid whose quadric
    // has the other sign (f > 0 inside: with culling on it shows its far wall), spheres inside.
    {
        std::vector<Primitive> p{shapes::ellipsoid({0, 0, 0}, {1.0f, 1.0f, 10.0f}, glm::mat3(1.0f), {{0.8f, 0.8f, 0.3f}})};
        for (int i = 0; i < 12; ++i) p.push_back(shapes::sphere({0.3f * float(i % 3) - 0.3f, 0.3f * float(i / 3 % 2), -2.0f - 0.5f * float(i)}, 0.25f));
        out.push_back({"eye inside a long ellipsoid", p, look_at(vec3(0.0, 0.0, 5.0), vec3(0.0, 0.0, 0.0), vec3(0.0, 1.0, 0.0), qc_render_test::perspective(50, aspect, 0.5, 30))});
        Primitive flipped = shapes::sphere({0, 0, 0}, 1.0f, {{0.3f, 0.8f, 0.8f}});
        flipped.variant = Variant::ellipsoid;
        for (int j = 0; j < 4; ++j)
            for (int i = 0; i < 4; ++i) flipped.shape.q.q[j][i] = -flipped.shape.q.q[j][i];
        std::vector<Primitive> q{flipped};
        for (int i = 0; i < 8; ++i) q.push_back(shapes::sphere({0.4f * float(i % 3) - 0.4f, 0.4f * float(i / 3) - 0.4f, 0.3f}, 0.1f));
        out.push_back({"an ellipsoid of the other sign", q, look_at(vec3(0.0, 0.0, 5.0), vec3(0.0, 0.0, 0.0), vec3(0.0, 1.0, 0.0), qc_render_test::perspective(40, aspect, 1, 20))});
    }
    // Equal depths: pairs of identical spheres of different colours far apart in the records
    // (more than a workgroup): the first of each pair wins the depth test, with or without the pass.
    {
        std::vector<Primitive> p;
        std::mt19937 rng(6);
        std::uniform_real_distribution<float> u(-1.5f, 1.5f);
        std::vector<glm::vec3> at;
        for (int i = 0; i < 150; ++i) at.push_back({u(rng), u(rng), u(rng)});
        for (int i = 0; i < 150; ++i) p.push_back(shapes::sphere(at[i], 0.3f, {{1.0f, 0.2f, 0.2f}}));
        for (int i = 0; i < 150; ++i) p.push_back(shapes::sphere(at[i], 0.3f, {{0.2f, 0.2f, 1.0f}}));
        out.push_back({"identical spheres of two colours", p, look_at(vec3(0.0, 0.0, 6.0), vec3(0.0, 0.0, 0.0), vec3(0.0, 1.0, 0.0), qc_render_test::perspective(45, aspect, 1, 20))});
    }
    // The eye inside the block, among the spheres.
    out.push_back({"dense block, eye inside", block, look_at(vec3(0.5, 0.52, 0.5), vec3(0.9, 0.4, 0.1), vec3(0.0, 1.0, 0.0), qc_render_test::perspective(70, aspect, 0.005, 3))});
    return out;
}

/// `cam` with its view turned by `angle` radians about `axis` (world space, through the origin)
/// and then moved by `move` (view space); its eye follows.
Camera turned(const Camera& cam, float angle, glm::vec3 axis, glm::vec3 move) {
    Camera out = cam;
    glm::mat4 view;
    for (int j = 0; j < 4; ++j)
        for (int i = 0; i < 4; ++i) view[j][i] = cam.view[j][i];
    view = glm::translate(glm::mat4(1.0f), move) * view * glm::rotate(glm::mat4(1.0f), angle, axis);
    for (int j = 0; j < 4; ++j)
        for (int i = 0; i < 4; ++i) out.view[j][i] = view[j][i];
    const glm::mat4 inv = glm::inverse(view);
    out.eye = vec3(inv[3][0], inv[3][1], inv[3][2]);
    return out;
}

}  // namespace

TEST_CASE("the occlusion cull pass changes no pixel of the GL renderer") {
    gl::OsmesaContext ctx;
    gl::QuadricRenderer r(ctx.api());
    const int w = 320, h = 240;
    Light light;
    light.direction = vec3(-0.4f, -0.6f, -1.0f);
    for (const Case& s : occlusion_cases(w, h)) {
        r.set_primitives(s.prims);
        for (int mode = 0; mode < 6; ++mode) {
            RenderOptions o;
            o.occlusion_min_overlap = 0.0f;  // (the cull pass in every frame: these scenes test it)
            o.width = w;
            o.height = h;
            o.culling = mode != 1;
            o.deferred = mode == 2;
            o.shadows = o.silhouettes = mode == 3;
            o.tight_bounds = mode != 4;
            r.set_slab_quads(mode != 5);
            o.occlusion_culling = true;
            r.draw(s.camera, light, o);
            const Image culled = r.read();
            const std::size_t drawn = r.drawn_primitives();
            // The survivors' corners computed by a compute pass instead of their vertex stage
            r.set_compute_bounds(true);
            r.draw(s.camera, light, o);
            const Image culled_compute = r.read();  // (its count of kept primitives may differ: occluder stores race)
            r.set_compute_bounds(false);
            // The occluders drawn by the rasteriser into the depth buffer instead of the compute pass's disks
            r.set_raster_occluders(true);
            r.draw(s.camera, light, o);
            const Image culled_raster = r.read();
            const std::size_t drawn_raster = r.drawn_primitives();
            r.set_raster_occluders(false);
            o.occlusion_culling = false;
            r.draw(s.camera, light, o);
            const Image all = r.read();
            r.set_slab_quads(true);
            CHECK(r.drawn_primitives() == s.prims.size());
            const ImageDiff d = image_diff(culled, all);
            const ImageDiff dv = image_diff(culled_compute, all);
            const ImageDiff dr = image_diff(culled_raster, all);
            const char* what = mode == 0 ? "forward" : mode == 1 ? "culling off" : mode == 2 ? "deferred" : mode == 3 ? "shadows + outlines"
                             : mode == 4 ? "tight bounds off" : "slab rectangles";
            std::printf("[occlusion] %s, %s: %ld covered px, %ld coverage / %ld colour / %ld depth differences (corners from a compute pass: %ld / %ld / %ld; rasterised occluders: %ld / %ld / %ld); %zu (rasterised occluders: %zu) of %zu primitives drawn\n",
                        s.name.c_str(), what, d.covered, d.coverage_diff, d.color_diff, d.depth_diff, dv.coverage_diff, dv.color_diff, dv.depth_diff, dr.coverage_diff,
                        dr.color_diff, dr.depth_diff, drawn, drawn_raster, s.prims.size());
            CAPTURE(s.name);
            CAPTURE(what);
            CHECK(d.covered > 300);
            CHECK(d.coverage_diff == 0);
            CHECK(d.color_diff == 0);
            CHECK(d.depth_diff == 0);
            CHECK(dv.coverage_diff == 0);
            CHECK(dv.color_diff == 0);
            CHECK(dv.depth_diff == 0);
            CHECK(dr.coverage_diff == 0);
            CHECK(dr.color_diff == 0);
            CHECK(dr.depth_diff == 0);
            CHECK(drawn <= s.prims.size());
            if (s.name == "dense block, perspective" || s.name == "dense block, orthographic") {
                CHECK(drawn < s.prims.size() * 6 / 10);
                CHECK(drawn_raster < s.prims.size() * 8 / 10);  // (the quadrilaterals cover less than the disks)
            }
        }
    }
}

TEST_CASE("the passes over records dispatched in many rows of workgroups give the same picture") {
    // A variant of more than 4M primitives needs more than 65535 workgroups of 64: the passes
    // dispatch them in rows (QuadricRenderer::set_dispatch_row_limit). Rows of 1 and 3 workgroups
    // here stand for that, with the cull pass, its compaction, the occluders and the bounds pass.
    gl::OsmesaContext ctx;
    gl::QuadricRenderer r(ctx.api());
    const int w = 320, h = 240;
    Light light;
    for (const Case& s : occlusion_cases(w, h)) {
        r.set_primitives(s.prims);
        RenderOptions o;
        o.occlusion_min_overlap = 0.0f;  // (the cull pass in every frame: these scenes test it)
        o.width = w;
        o.height = h;
        r.draw(s.camera, light, o);
        const Image one_row = r.read();
        for (const std::uint32_t rows : {1u, 3u})
            for (const bool compute : {false, true}) {
                r.set_dispatch_row_limit(rows);
                r.set_compute_bounds(compute);
                r.draw(s.camera, light, o);
                const ImageDiff d = image_diff(r.read(), one_row);
                std::printf("[dispatch rows] %s, rows of %u workgroups%s: %ld covered px, %ld coverage / %ld colour / %ld depth differences; %zu of %zu primitives drawn\n",
                            s.name.c_str(), rows, compute ? ", bounds pass" : "", d.covered, d.coverage_diff, d.color_diff, d.depth_diff, r.drawn_primitives(), s.prims.size());
                CAPTURE(s.name);
                CHECK(d.covered > 300);
                CHECK(d.coverage_diff == 0);
                CHECK(d.color_diff == 0);
                CHECK(d.depth_diff == 0);
                CHECK(r.drawn_primitives() < s.prims.size() + 1);
            }
        r.set_dispatch_row_limit(65535);
        r.set_compute_bounds(false);
    }
}

TEST_CASE("the occlusion cull pass keeps exactly what shows in front of a large sphere and nothing off screen") {
    gl::OsmesaContext ctx;
    gl::QuadricRenderer r(ctx.api());
    const int w = 200, h = 150;
    const Camera cam = qc_render_test::look_at(vec3(0.0, 0.0, 6.0), vec3(0.0, 0.0, 0.0), vec3(0.0, 1.0, 0.0), qc_render_test::perspective(40, double(w) / h, 1, 20));
    std::vector<Primitive> prims{shapes::sphere({0, 0, 0}, 1.5f)};
    // 50 small spheres behind the large one (hidden: culled), 10 in front of it (kept), 40 beside
    // the view (off screen: culled).
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> u(-0.5f, 0.5f);
    for (int i = 0; i < 50; ++i) prims.push_back(shapes::sphere({u(rng), u(rng), -2.0f + u(rng)}, 0.1f));
    for (int i = 0; i < 10; ++i) prims.push_back(shapes::sphere({u(rng), u(rng), 2.5f + u(rng)}, 0.1f));
    for (int i = 0; i < 40; ++i) prims.push_back(shapes::sphere({12.0f + u(rng), u(rng), u(rng)}, 0.1f));
    r.set_primitives(prims);
    Light light;
    RenderOptions o;
    o.occlusion_min_overlap = 0.0f;  // (the cull pass in every frame: these scenes test it)
    o.width = w;
    o.height = h;
    r.draw(cam, light, o);
    CHECK(r.drawn_primitives() == 11);
    const Image culled = r.read();
    o.occlusion_culling = false;
    r.draw(cam, light, o);
    const ImageDiff d = image_diff(culled, r.read());
    CHECK(d.coverage_diff == 0);
    CHECK(d.color_diff == 0);
    CHECK(d.depth_diff == 0);
    // No primitives: nothing drawn, the background everywhere.
    {
        gl::QuadricRenderer empty(ctx.api());
        empty.set_primitives({});
        RenderOptions e = o;
        e.occlusion_culling = true;
        empty.draw(cam, light, e);
        CHECK(empty.drawn_primitives() == 0);
        const Image img = empty.read();
        CHECK(std::count_if(img.depth.begin(), img.depth.end(), [](float d) { return d < 1.0f; }) == 0);
    }
    // A skewed projection (view x mixed into NDC y) gets no occluders: only frustum culling.
    Camera skew = cam;
    skew.projection[0][1] = 0.05f;
    o.occlusion_culling = true;
    r.draw(skew, light, o);
    CHECK(r.drawn_primitives() == 61);
}

TEST_CASE("occluder balls lie inside their solids") {
    // Independent check: points of the ball (centre + r_in u, u on a sphere grid) are inside the
    // primitive's quadric (f < 0 in its local coordinates) for every occluding shape.
    std::vector<Primitive> prims = dense_block(9, 64);
    int occluders = 0;
    for (const Primitive& p : prims) {
        const double r_in = quadcast::render::occluder_radius(p);
        if (r_in == 0) continue;
        ++occluders;
        for (int i = 0; i <= 16; ++i)
            for (int j = 0; j < 32; ++j) {
                const long double th = 3.14159265358979L * i / 16, ph = 6.28318530717959L * j / 32;
                const long double x[4] = {r_in * std::sin(th) * std::cos(ph), r_in * std::sin(th) * std::sin(ph), r_in * std::cos(th), 1.0L};
                long double f = 0;
                for (int a = 0; a < 4; ++a)
                    for (int b = 0; b < 4; ++b) f += x[a] * static_cast<long double>(p.shape.q.q[b][a]) * x[b];
                // slab caps: the ball must stay within the slab too
                long double along = 0;
                for (int a = 0; a < 3; ++a) along += x[a] * p.shape.axis[a];
                CHECK(f < 0);  // inside as stored (the side front-root selection treats as inside)
                if (p.variant == Variant::slab) CHECK(std::fabs(along) < p.shape.half_length);
            }
    }
    CHECK(occluders == 48);  // spheres, ellipsoids and capped cylinders: 6 of every 8
    // Chains along capped sticks: every disk's ball of radius 16/15 r_in (what the gap of
    // occluder_usable assumes) inside the solid, 1 to 40 radii long.
    long chain_disks = 0;
    for (int i = 0; i < 200; ++i) {
        std::mt19937 rng(static_cast<unsigned>(100 + i));
        std::uniform_real_distribution<float> u(-1.0f, 1.0f), len(0.5f, 40.0f);
        const glm::vec3 a(u(rng), u(rng), u(rng)), d = glm::normalize(glm::vec3(u(rng), u(rng), u(rng)) + glm::vec3(1e-3f));
        const float r = 0.01f + 0.2f * (u(rng) + 1.0f);
        const Primitive p = shapes::cylinder(a, a + d * (r * len(rng)), r, shapes::Ends::both);
        const quadcast::render::OccluderShape o = quadcast::render::occluder_shape(p);
        REQUIRE(o.r_in > 0.0f);
        const float n = quadcast::occluder_chain_count(o.half_axis, o.r_in);
        CHECK(n >= 1.0f);
        for (float k = 0; k < n; k += 1.0f) {
            quadcast::Vec3<float> ck{};
            float radius_k = 0;
            quadcast::occluder_chain_disk(p.shape.center, o.half_axis, p.shape.radius, k, n, ck, radius_k);
            ++chain_disks;
            // (less 2^-12: the slab axis and the float quadric's own axis agree to ~1e-7, which
            // over a chain 40 radii long moves a ball ~4e-6 radii; the gap's 1% slack covers it)
            const long double rho = static_cast<long double>(o.r_in) * 16 / 15 * (1 - 1.0L / 4096);
            for (int ti = 0; ti <= 8; ++ti)
                for (int j = 0; j < 16; ++j) {
                    const long double th = 3.14159265358979L * ti / 8, ph = 6.28318530717959L * j / 16;
                    long double x[4] = {rho * std::sin(th) * std::cos(ph), rho * std::sin(th) * std::sin(ph), rho * std::cos(th), 1.0L};
                    for (int c = 0; c < 3; ++c) x[c] += static_cast<long double>(ck[c]) - static_cast<long double>(p.shape.center[c]);
                    long double f = 0, along = 0;
                    for (int aa = 0; aa < 4; ++aa)
                        for (int bb = 0; bb < 4; ++bb) f += x[aa] * static_cast<long double>(p.shape.q.q[bb][aa]) * x[bb];
                    for (int c = 0; c < 3; ++c) along += x[c] * p.shape.axis[c];
                    CHECK(f < 0);
                    CHECK(std::fabs(along) < p.shape.half_length);
                }
            // The ball around the disk holding the primitive: its bounding sphere inside it, with
            // the 2^-10 that nearest_distance adds
            const long double off = std::sqrt(std::pow(static_cast<long double>(ck[0]) - p.shape.center[0], 2) + std::pow(static_cast<long double>(ck[1]) - p.shape.center[1], 2) +
                                              std::pow(static_cast<long double>(ck[2]) - p.shape.center[2], 2));
            CHECK(off + p.shape.radius <= radius_k * (1 + 1.0L / 1024));
        }
    }
    CHECK(chain_disks > 2000);
    // An ellipsoid of the other sign (f > 0 inside) does not occlude.
    Primitive flipped = shapes::sphere({0, 0, 0}, 1.0f);
    flipped.variant = Variant::ellipsoid;
    for (int j = 0; j < 4; ++j)
        for (int i = 0; i < 4; ++i) flipped.shape.q.q[j][i] = -flipped.shape.q.q[j][i];
    CHECK(quadcast::render::occluder_radius(flipped) == 0.0f);
}

namespace {

using qct::LD;
using M4 = qct::M4L;  // [column][row]

std::array<LD, 3> unproject(const M4& inv, LD x, LD y, LD z) {
    const LD v[4] = {x, y, z, 1.0L};
    LD o[4] = {0, 0, 0, 0};
    for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 4; ++c) o[r] += inv[c][r] * v[c];
    return {o[0] / o[3], o[1] / o[3], o[2] / o[3]};
}

LD dot3(const std::array<LD, 3>& a, const std::array<LD, 3>& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
std::array<LD, 3> sub3(const std::array<LD, 3>& a, const std::array<LD, 3>& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
std::array<LD, 3> cross3(const std::array<LD, 3>& a, const std::array<LD, 3>& b) {
    return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}

/// The ray parameter where o + t d enters the solid capped cylinder from a to b of radius r (or
/// the ball of radius r around a when a == b); NaN when it misses.
LD enter_capsule_free(const std::array<LD, 3>& o, const std::array<LD, 3>& d, const std::array<LD, 3>& a, const std::array<LD, 3>& b, LD r) {
    const std::array<LD, 3> ab = sub3(b, a), oa = sub3(o, a);
    const LD len = std::sqrt(dot3(ab, ab));
    if (len == 0) {  // ball
        const LD B = dot3(oa, d), C = dot3(oa, oa) - r * r, A = dot3(d, d), disc = B * B - A * C;
        return disc < 0 ? NAN : (-B - std::sqrt(disc)) / A;
    }
    const std::array<LD, 3> ax = {ab[0] / len, ab[1] / len, ab[2] / len};
    const LD da = dot3(d, ax), oaa = dot3(oa, ax);
    const std::array<LD, 3> dp = {d[0] - da * ax[0], d[1] - da * ax[1], d[2] - da * ax[2]}, op = {oa[0] - oaa * ax[0], oa[1] - oaa * ax[1], oa[2] - oaa * ax[2]};
    LD t0 = -INFINITY, t1 = INFINITY;
    const LD A = dot3(dp, dp), B = dot3(op, dp), C = dot3(op, op) - r * r;
    if (A > 0) {
        const LD disc = B * B - A * C;
        if (disc < 0) return NAN;
        t0 = (-B - std::sqrt(disc)) / A;
        t1 = (-B + std::sqrt(disc)) / A;
    } else if (C > 0) {
        return NAN;
    }
    LD s0 = -INFINITY, s1 = INFINITY;
    if (da != 0) {
        s0 = (0 - oaa) / da;
        s1 = (len - oaa) / da;
        if (s0 > s1) std::swap(s0, s1);
    } else if (oaa < 0 || oaa > len) {
        return NAN;
    }
    const LD enter = std::max(t0, s0), leave = std::min(t1, s1);
    return enter <= leave ? enter : NAN;
}

}  // namespace

TEST_CASE("occluder quadrilaterals lie behind the surfaces in front of them") {
    // Independent check in long double of what the rasterised occluders rely on: through every
    // point of the quadrilateral `occluder_corner` gives (the square of a sphere, the rectangle
    // along a capped stick), the pixel ray enters the primitive's solid (its exact geometry, not its
    // quadric) nearer than the quadrilateral's plane, by more than 2^-20 in window depth.
    std::mt19937 rng(31);
    std::uniform_real_distribution<double> u(-1.0, 1.0), u01(0.0, 1.0);
    int usable_count = 0, points = 0, sticks = 0;
    LD worst_gap = 1;
    for (int i = 0; i < 3000; ++i) {
        const bool ortho = i % 4 == 3;
        const double fov = 20.0 + 70.0 * u01(rng), dist = 2.0 + 18.0 * u01(rng);
        const Vec3<double> dir = normalize(vec3(u(rng), u(rng), u(rng)) + vec3(1e-3, 0.0, 0.0));
        const Vec3<double> target = vec3(u(rng), u(rng), u(rng)) * 0.3;
        const double n = 0.05 + 0.5 * u01(rng), f = dist + 3.0 + 20.0 * u01(rng);
        const double half = dist * std::tan(fov * 3.14159265358979 / 360.0);
        const Camera cam = qc_render_test::look_at(target + dir * dist, target, vec3(0.0, 1.0, 0.0),
                                                   ortho ? qc_render_test::orthographic(-half * 4 / 3, half * 4 / 3, -half, half, n, f)
                                                         : qc_render_test::perspective(fov, 4.0 / 3.0, n, f),
                                                   ortho);
        // A sphere or a capped stick of 1 to 30 radii near the target
        const double r = 0.02 + 0.4 * u01(rng);
        const glm::vec3 c(float(u(rng) * 0.5), float(u(rng) * 0.5), float(u(rng) * 0.5));
        const glm::vec3 ad = glm::normalize(glm::vec3(float(u(rng)), float(u(rng)), float(u(rng))) + glm::vec3(1e-3f));
        const bool stick = i % 2 == 1;
        const float half_len = stick ? float(r * (0.5 + 15.0 * u01(rng))) : 0.0f;
        const Primitive p = stick ? shapes::cylinder(c - ad * half_len, c + ad * half_len, float(r), shapes::Ends::both) : shapes::sphere(c, float(r));
        const quadcast::render::OccluderShape o = quadcast::render::occluder_shape(p);
        REQUIRE(o.r_in > 0.0f);
        const quadcast::render::OcclusionRange range = quadcast::render::occlusion_range(cam);
        const Mat4<float> vpf = quadcast::render::view_projection(cam);
        Mat4<double> vp{};
        M4 vpl{};
        for (int a = 0; a < 4; ++a)
            for (int b = 0; b < 4; ++b) {
                vp[a][b] = vpf[a][b];
                vpl[a][b] = vpf[a][b];
            }
        const M4 inv = qct::inverse(vpl);
        const Vec3<double> vz_row = vec3<double>(cam.view[0][2], cam.view[1][2], cam.view[2][2]), right = vec3<double>(cam.view[0][0], cam.view[1][0], cam.view[2][0]),
                           up = vec3<double>(cam.view[0][1], cam.view[1][1], cam.view[2][1]);
        const Vec4<double> pz = vec4<double>(cam.projection[2][2], cam.projection[3][2], cam.projection[2][3], cam.projection[3][3]);
        const Vec4<double> ball = vec4<double>(p.shape.center[0], p.shape.center[1], p.shape.center[2], o.r_in);
        const Vec4<double> more = vec4<double>(p.shape.radius, o.half_axis[0], o.half_axis[1], o.half_axis[2]);
        Vec4<double> clip[4]{};
        bool usable[4] = {};
        for (int k = 0; k < 4; ++k)
            quadcast::occluder_corner(vp, vz_row, double(cam.view[3][2]), right, up, ball, more, vec3<double>(range.near, range.far, range.gap), pz, double(cam.projection[1][1]),
                                      768.0, double(k), clip[k], usable[k]);
        CHECK((usable[0] == usable[1] && usable[1] == usable[2] && usable[2] == usable[3]));
        if (!usable[0]) continue;
        ++usable_count;
        sticks += stick;
        std::array<LD, 3> world[4];
        LD ndc[4][2];
        for (int k = 0; k < 4; ++k) {
            ndc[k][0] = LD(clip[k][0]) / LD(clip[k][3]);
            ndc[k][1] = LD(clip[k][1]) / LD(clip[k][3]);
            world[k] = unproject(inv, ndc[k][0], ndc[k][1], LD(clip[k][2]) / LD(clip[k][3]));
        }
        const std::array<LD, 3> normal = cross3(sub3(world[1], world[0]), sub3(world[3], world[0]));
        const std::array<LD, 3> a = {LD(c.x) - LD(ad.x) * half_len, LD(c.y) - LD(ad.y) * half_len, LD(c.z) - LD(ad.z) * half_len},
                                b = {LD(c.x) + LD(ad.x) * half_len, LD(c.y) + LD(ad.y) * half_len, LD(c.z) + LD(ad.z) * half_len};
        auto window_depth = [&](const std::array<LD, 3>& x) {
            LD zc = 0, wc = 0;
            const LD v[4] = {x[0], x[1], x[2], 1.0L};
            for (int k = 0; k < 4; ++k) {
                zc += vpl[k][2] * v[k];
                wc += vpl[k][3] * v[k];
            }
            return zc / wc * 0.5L + 0.5L;
        };
        for (int j = 0; j < 40; ++j) {
            // A point of the quadrilateral on screen: a corner, or a convex combination of the corners
            LD w[4] = {0, 0, 0, 0}, sum = 0;
            if (j < 4) w[j] = 1;
            else
                for (LD& x : w) sum += (x = LD(u01(rng)) + 1e-6L);
            if (j >= 4)
                for (LD& x : w) x /= sum;
            const LD mx = w[0] * ndc[0][0] + w[1] * ndc[1][0] + w[2] * ndc[2][0] + w[3] * ndc[3][0];
            const LD my = w[0] * ndc[0][1] + w[1] * ndc[1][1] + w[2] * ndc[2][1] + w[3] * ndc[3][1];
            const std::array<LD, 3> o0 = unproject(inv, mx, my, -1.0L), o1 = unproject(inv, mx, my, 1.0L);
            const std::array<LD, 3> d = sub3(o1, o0);
            const LD tq = dot3(normal, sub3(world[0], o0)) / dot3(normal, d);
            const std::array<LD, 3> q = {o0[0] + tq * d[0], o0[1] + tq * d[1], o0[2] + tq * d[2]};
            const LD th = enter_capsule_free(o0, d, a, b, LD(r));
            CAPTURE(i);
            CAPTURE(j);
            REQUIRE(!std::isnan(th));
            const std::array<LD, 3> hit = {o0[0] + th * d[0], o0[1] + th * d[1], o0[2] + th * d[2]};
            const LD gap = window_depth(q) - window_depth(hit);
            worst_gap = std::min(worst_gap, gap);
            CHECK(gap > 1.0L / 1048576.0L);
            ++points;
        }
    }
    std::printf("[occlusion] occluder quadrilaterals: %d usable of 3000 (%d sticks), %d points, smallest window-depth gap %.3Le\n", usable_count, sticks, points, worst_gap);
    CHECK(usable_count > 1000);
    CHECK(sticks > 400);
}

TEST_CASE("tetrahedral pieces lie in their bounding balls; bilinear quads need not") {
    // Every piece of a tetrahedral mesh (shapes::quadric clipped to a tetrahedron, any shape of
    // tetrahedron): the region its clip test accepts lies in its ball, so occlusion culling and
    // phased drawing may use the ball's nearest distance.
    std::mt19937 rng(21);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    int pieces = 0;
    for (int i = 0; i < 2000; ++i) {
        glm::dvec3 p[4];
        for (auto& c : p) c = glm::dvec3(u(rng), u(rng), u(rng)) * (i % 3 == 0 ? 50.0 : 1.0) + glm::dvec3(i % 5 == 0 ? 300.0 : 0.0);
        std::array<Vec3<double>, 4> corners{};
        for (int k = 0; k < 4; ++k) corners[static_cast<std::size_t>(k)] = vec3(p[k].x, p[k].y, p[k].z);
        if (quadcast::tet_shape(corners).flatter_than(1e-3)) continue;
        glm::dmat4 q(0.0);
        q[0][0] = q[1][1] = q[2][2] = 1.0;
        q[3][3] = -1.0;
        const Primitive prim = shapes::quadric(q, shapes::TetrahedronBound{{glm::vec3(p[0]), glm::vec3(p[1]), glm::vec3(p[2]), glm::vec3(p[3])}});
        Vec4<double> pl[4];
        for (int k = 0; k < 4; ++k) pl[k] = cast<double>(prim.shape.planes[k]);
        CAPTURE(i);
        CHECK(quadcast::planes_within_ball(pl, double(prim.shape.radius)));
        ++pieces;
    }
    CHECK(pieces > 500);
    // A twisted quad's planes (its director planes in parallel pairs) bound no tetrahedron.
    const Primitive quad = shapes::quad(glm::vec3(0, 0, 0), glm::vec3(1, 0, 0.3f), glm::vec3(1, 1, 0), glm::vec3(0, 1, 0.4f));
    Vec4<double> pl[4];
    for (int k = 0; k < 4; ++k) pl[k] = cast<double>(quad.shape.planes[k]);
    CHECK_FALSE(quadcast::planes_within_ball(pl, double(quad.shape.radius)));
}

TEST_CASE("phased drawing of tetrahedral pieces culls what earlier phases hide and changes no depth") {
    // Three nested spheres made of tetrahedral pieces (over 4096 of them): the inner two are
    // hidden from outside. Drawn in 1 and in 3 phases (RenderOptions::occlusion_phases) from
    // outside in perspective, from between the shells, orthographically, and with shadows and
    // outlines: the same coverage and depths; colours may differ only where two pieces meet at
    // exactly the same depth (which one wins a tie depends on the order they are drawn in).
    gl::OsmesaContext ctx;
    gl::QuadricRenderer r(ctx.api());
    const int w = 320, h = 240;
    const double aspect = double(w) / h;
    std::vector<Primitive> prims;
    const double radii[3] = {0.45, 0.7, 0.95};
    const glm::vec3 colors[3] = {{0.9f, 0.3f, 0.2f}, {0.2f, 0.8f, 0.3f}, {0.3f, 0.4f, 0.9f}};
    for (int s = 0; s < 3; ++s) {
        const std::vector<Primitive> shell = tetrahedral_pieces({1, 1, 1}, -radii[s] * radii[s], 12, 1.0, colors[s]);
        prims.insert(prims.end(), shell.begin(), shell.end());
    }
    REQUIRE(prims.size() >= 4096);
    r.set_primitives(prims);
    Light light;
    light.direction = vec3(-0.4f, -0.6f, -1.0f);
    using qc_render_test::look_at;
    const std::vector<std::pair<std::string, Camera>> cams = {
        {"outside", look_at(vec3(0.6, 0.9, 3.2), vec3(0.0, 0.0, 0.0), vec3(0.0, 1.0, 0.0), qc_render_test::perspective(40, aspect, 0.5, 10))},
        {"between the shells", look_at(vec3(0.1, 0.2, 0.82), vec3(0.0, 0.0, 0.0), vec3(0.0, 1.0, 0.0), qc_render_test::perspective(80, aspect, 0.02, 10))},
        {"orthographic", look_at(vec3(0.3, 0.2, 4.0), vec3(0.0, 0.0, 0.0), vec3(0.0, 1.0, 0.0),
                                 qc_render_test::orthographic(-1.3 * aspect, 1.3 * aspect, -1.3, 1.3, 1, 8), true)},
    };
    for (const auto& [name, cam] : cams)
        for (int mode = 0; mode < 2; ++mode) {
            RenderOptions o;
            o.occlusion_min_overlap = 0.0f;  // (the cull pass in every frame: these scenes test it)
            o.width = w;
            o.height = h;
            o.culling = false;  // (isosurface pieces: render::isosurface_culling_note)
            o.shadows = o.silhouettes = mode == 1;
            o.occlusion_phases = 1;
            r.draw(cam, light, o);
            const Image one = r.read();
            const std::size_t drawn_one = r.drawn_primitives();
            o.occlusion_phases = 3;
            r.draw(cam, light, o);
            const Image three = r.read();
            const std::size_t drawn_three = r.drawn_primitives();
            o.occlusion_culling = false;
            r.draw(cam, light, o);
            const Image all = r.read();
            const ImageDiff d = image_diff(three, one), d_all = image_diff(three, all);
            std::printf("[phases] %s%s: %ld covered px, %ld coverage / %ld colour / %ld depth differences (against no culling: %ld / %ld / %ld); "
                        "%zu of %zu pieces drawn in 1 phase, %zu in 3\n",
                        name.c_str(), mode ? ", shadows + outlines" : "", d.covered, d.coverage_diff, d.color_diff, d.depth_diff, d_all.coverage_diff,
                        d_all.color_diff, d_all.depth_diff, drawn_one, prims.size(), drawn_three);
            CAPTURE(name);
            CAPTURE(mode);
            CHECK(d.covered > 5000);
            CHECK(d.coverage_diff == 0);
            CHECK(d.depth_diff == 0);
            CHECK(d_all.coverage_diff == 0);
            CHECK(d_all.depth_diff == 0);
            CHECK(d.color_diff * 1000 <= d.covered);  // ties only
            CHECK(d_all.color_diff * 1000 <= d_all.covered);
            if (name == "outside") CHECK(drawn_three * 10 < drawn_one * 7);  // the inner shells culled
            if (name == "orthographic") CHECK(drawn_three * 10 < drawn_one * 9);
        }
}

namespace {

/// n capped sticks (length 0.1, radius 0.01) at random points of the unit cube, random directions.
std::vector<Primitive> random_sticks(unsigned seed, int n) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(0.0f, 1.0f), s(-1.0f, 1.0f), c(0.2f, 1.0f);
    std::vector<Primitive> out;
    while (static_cast<int>(out.size()) < n) {
        const glm::vec3 d(s(rng), s(rng), s(rng));
        const float l = glm::length(d);
        if (!(l > 0.05f && l <= 1.0f)) continue;
        const glm::vec3 p(u(rng), u(rng), u(rng));
        out.push_back(shapes::cylinder(p - d * (0.05f / l), p + d * (0.05f / l), 0.01f, shapes::Ends::both, {{c(rng), c(rng), c(rng)}}));
    }
    return out;
}

/// Balls and sticks: atoms on a jittered 14^3 grid in the unit cube, each bonded to its
/// neighbours along +x, +y and +z by a capped stick that ends inside both atoms (the stick's
/// cap and the atom's sphere meet, as in a molecule).
std::vector<Primitive> balls_and_sticks(unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> j(-0.012f, 0.012f), c(0.2f, 1.0f);
    const int g = 14;
    std::vector<glm::vec3> at;
    for (int z = 0; z < g; ++z)
        for (int y = 0; y < g; ++y)
            for (int x = 0; x < g; ++x) at.push_back(glm::vec3(x, y, z) / float(g - 1) + glm::vec3(j(rng), j(rng), j(rng)));
    std::vector<Primitive> out;
    for (const glm::vec3& p : at) out.push_back(shapes::sphere(p, 0.018f, {{c(rng), c(rng), c(rng)}}));
    auto index = [g](int x, int y, int z) { return static_cast<std::size_t>((z * g + y) * g + x); };
    for (int z = 0; z < g; ++z)
        for (int y = 0; y < g; ++y)
            for (int x = 0; x < g; ++x) {
                const glm::vec3 p = at[index(x, y, z)];
                if (x + 1 < g) out.push_back(shapes::cylinder(p, at[index(x + 1, y, z)], 0.007f, shapes::Ends::both, {{0.6f, 0.6f, 0.6f}}));
                if (y + 1 < g) out.push_back(shapes::cylinder(p, at[index(x, y + 1, z)], 0.007f, shapes::Ends::both, {{0.6f, 0.6f, 0.6f}}));
                if (z + 1 < g) out.push_back(shapes::cylinder(p, at[index(x, y, z + 1)], 0.007f, shapes::Ends::both, {{0.6f, 0.6f, 0.6f}}));
            }
    return out;
}

}  // namespace

TEST_CASE("phased drawing of sticks: the picture of one phase and of no culling, fewer primitives drawn") {
    // Scenes of at least 4096 primitives of which at least half are sticks (chains of occluder
    // disks) are drawn in RenderOptions::occlusion_phases phases, nearest first, without the
    // chains; spheres alone are not (one disk each). 8000 random sticks and a grid of balls and
    // sticks (2744 atoms, 7644 bonds), from outside in perspective, orthographically, and with the
    // eye inside (the near plane through sticks); forward, back-face culling off, deferred with
    // shadows and outlines: the same coverage, colours and depths as one phase and as no culling.
    gl::OsmesaContext ctx;
    gl::QuadricRenderer r(ctx.api());
    const int w = 320, h = 240;
    const double aspect = double(w) / h;
    Light light;
    light.direction = vec3(-0.4f, -0.6f, -1.0f);
    using qc_render_test::look_at;
    const std::vector<std::pair<std::string, Camera>> cams = {
        {"outside", look_at(vec3(0.5, 0.5, 3.0), vec3(0.5, 0.5, 0.5), vec3(0.0, 1.0, 0.0), qc_render_test::perspective(30, aspect, 1, 5))},
        {"orthographic", look_at(vec3(1.9, 1.2, 2.3), vec3(0.5, 0.5, 0.5), vec3(0.0, 1.0, 0.0),
                                 qc_render_test::orthographic(-0.9 * aspect, 0.9 * aspect, -0.9, 0.9, 0.5, 5), true)},
        {"eye inside", look_at(vec3(0.5, 0.52, 0.55), vec3(0.9, 0.4, 0.1), vec3(0.0, 1.0, 0.0), qc_render_test::perspective(70, aspect, 0.005, 3))},
    };
    const std::vector<std::pair<std::string, std::vector<Primitive>>> scenes = {{"random sticks", random_sticks(3, 8000)}, {"balls and sticks", balls_and_sticks(4)}};
    for (const auto& [scene, prims] : scenes) {
        REQUIRE(prims.size() >= 4096);
        r.set_primitives(prims);
        for (const auto& [name, cam] : cams)
            for (int mode = 0; mode < 3; ++mode) {
                RenderOptions o;
                o.occlusion_min_overlap = 0.0f;  // (the cull pass in every frame)
                o.width = w;
                o.height = h;
                o.culling = mode != 1;
                o.deferred = o.shadows = o.silhouettes = mode == 2;
                o.occlusion_phases = 3;
                r.draw(cam, light, o);
                const Image three = r.read();
                const std::size_t drawn_three = r.drawn_primitives();
                CHECK(r.phases() == 3);
                o.occlusion_phases = 1;
                r.draw(cam, light, o);
                const Image one = r.read();
                const std::size_t drawn_one = r.drawn_primitives();
                CHECK(r.phases() == 1);
                o.occlusion_culling = false;
                r.draw(cam, light, o);
                const Image all = r.read();
                const ImageDiff d = image_diff(three, one), d_all = image_diff(three, all), d_one = image_diff(one, all);
                const char* what = mode == 0 ? "forward" : mode == 1 ? "culling off" : "deferred, shadows + outlines";
                std::printf("[phased sticks] %s, %s, %s: %ld covered px, 3 phases against 1: %ld coverage / %ld colour / %ld depth differences, "
                            "against no culling: %ld / %ld / %ld (1 phase: %ld / %ld / %ld); %zu of %zu drawn in 3 phases, %zu in 1\n",
                            scene.c_str(), name.c_str(), what, d.covered, d.coverage_diff, d.color_diff, d.depth_diff, d_all.coverage_diff, d_all.color_diff,
                            d_all.depth_diff, d_one.coverage_diff, d_one.color_diff, d_one.depth_diff, drawn_three, prims.size(), drawn_one);
                CAPTURE(scene);
                CAPTURE(name);
                CAPTURE(what);
                CHECK(d.covered > 5000);
                CHECK(d_all.coverage_diff == 0);
                CHECK(d_all.color_diff == 0);
                CHECK(d_all.depth_diff == 0);
                CHECK(d_one.coverage_diff == 0);
                CHECK(d_one.color_diff == 0);
                CHECK(d_one.depth_diff == 0);
                // What lies behind the first phases is culled (the grid is porous: it hides less).
                if (name == "outside") CHECK(drawn_three * 100 < prims.size() * (scene == "random sticks" ? 55 : 75));
            }
    }
    // Spheres alone occlude with one disk each: one phase.
    std::vector<Primitive> spheres;
    for (const Primitive& p : balls_and_sticks(4))
        if (p.variant == Variant::sphere) spheres.push_back(p);
    for (int copy = 0; copy < 2; ++copy)
        for (std::size_t i = 0; i < 2744; ++i) {
            Primitive p = spheres[i];
            p.shape.center[2] += 0.02f * float(copy + 1);
            spheres.push_back(p);
        }
    REQUIRE(spheres.size() >= 4096);
    r.set_primitives(spheres);
    RenderOptions o;
    o.occlusion_min_overlap = 0.0f;
    o.width = w;
    o.height = h;
    r.draw(cams[0].second, light, o);
    CHECK(r.cull_pass_ran());
    CHECK(r.phases() == 1);
}

TEST_CASE("draw_primitives into a host application's framebuffer: the cull pass changes no pixel, and the picture is draw's") {
    gl::OsmesaContext ctx;
    const gl::Api& api = ctx.api();
    gl::QuadricRenderer r(api);
    const int w = 320, h = 240;
    // The host's framebuffer: RGBA8 colour and a 32-bit float depth buffer of its own.
    GLuint fbo = 0, color = 0, depth = 0;
    api.CreateFramebuffers(1, &fbo);
    api.CreateRenderbuffers(1, &color);
    api.CreateRenderbuffers(1, &depth);
    api.NamedRenderbufferStorage(color, GL_RGBA8, w, h);
    api.NamedRenderbufferStorage(depth, GL_DEPTH_COMPONENT32F, w, h);
    api.NamedFramebufferRenderbuffer(fbo, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, color);
    api.NamedFramebufferRenderbuffer(fbo, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, depth);
    REQUIRE(api.CheckNamedFramebufferStatus(fbo, GL_FRAMEBUFFER) == GL_FRAMEBUFFER_COMPLETE);
    Light light;
    light.direction = vec3(-0.4f, -0.6f, -1.0f);
    // The host draws: its clears, viewport and depth test, then quadcast's primitives; read back
    // top row first, as QuadricRenderer::read.
    auto host_frame = [&](const Camera& cam, const RenderOptions& o) {
        const float bg[4] = {o.background[0], o.background[1], o.background[2], 1.0f};
        qc_gl_test::begin_host_frame(api, fbo, w, h, bg);
        r.draw_primitives(cam, light, o, false);
        api.BindFramebuffer(GL_FRAMEBUFFER, 0);
        return gl::read_framebuffer(api, fbo, w, h);
    };
    for (const Case& s : occlusion_cases(w, h)) {
        r.set_primitives(s.prims);
        for (int mode = 0; mode < 2; ++mode) {
            RenderOptions o;
            o.occlusion_min_overlap = 0.0f;  // (the cull pass in every frame: these scenes test it)
            o.width = w;
            o.height = h;
            o.culling = mode == 0;
            o.occlusion_culling = true;
            const Image culled = host_frame(s.camera, o);
            const std::size_t drawn = r.drawn_primitives();
            o.occlusion_culling = false;
            const Image all = host_frame(s.camera, o);
            CHECK(r.drawn_primitives() == s.prims.size());
            r.draw(s.camera, light, o);  // (the renderer's own framebuffer)
            const Image own = r.read();
            const ImageDiff d = image_diff(culled, all), e = image_diff(all, own);
            std::printf("[occlusion, host framebuffer] %s, culling %s: %ld covered px, %ld coverage / %ld colour / %ld depth differences with the pass off; "
                        "against draw: %ld / %ld / %ld; %zu of %zu primitives drawn\n",
                        s.name.c_str(), o.culling ? "on" : "off", d.covered, d.coverage_diff, d.color_diff, d.depth_diff, e.coverage_diff, e.color_diff,
                        e.depth_diff, drawn, s.prims.size());
            CAPTURE(s.name);
            CHECK(d.covered > 300);
            CHECK(d.coverage_diff == 0);
            CHECK(d.color_diff == 0);
            CHECK(d.depth_diff == 0);
            CHECK(e.coverage_diff == 0);
            CHECK(e.color_diff == 0);
            CHECK(e.depth_diff == 0);
            if (s.name == "dense block, perspective" || s.name == "dense block, orthographic") CHECK(drawn < s.prims.size() * 6 / 10);
        }
    }
    api.DeleteFramebuffers(1, &fbo);
    api.DeleteRenderbuffers(1, &color);
    api.DeleteRenderbuffers(1, &depth);
}

TEST_CASE("the cull pass runs only where the primitives overlap enough to pay for it, and the picture is the same") {
    // RenderOptions::occlusion_min_overlap: 300 small spheres hardly overlap (expected overlap
    // far below 3): no cull pass, every primitive drawn; 60000 spheres of the benchmark's size
    // overlap about 5 deep: the cull pass runs and hides most of them. Either way the picture
    // is the one with the cull pass forced (min overlap 0) and without culling.
    gl::OsmesaContext ctx;
    gl::QuadricRenderer r(ctx.api());
    const int w = 320, h = 240;
    using qc_render_test::look_at;
    const Camera cam = look_at(vec3(0.5, 0.5, 3.0), vec3(0.5, 0.5, 0.5), vec3(0.0, 1.0, 0.0), qc_render_test::perspective(30, double(w) / h, 1.0, 5.0));
    Light light;
    for (const int n : {300, 60000}) {
        std::mt19937 rng(5);
        std::uniform_real_distribution<float> u(0.0f, 1.0f);
        const float radius = n == 300 ? 0.01f : 0.3f * std::pow(float(n), -1.0f / 3.0f);
        std::vector<Primitive> prims;
        for (int i = 0; i < n; ++i) prims.push_back(shapes::sphere({u(rng), u(rng), u(rng)}, radius));
        r.set_primitives(prims);
        RenderOptions o;  // the default: occlusion culling, min overlap 3
        o.width = w;
        o.height = h;
        r.draw(cam, light, o);
        const Image automatic = r.read();
        const bool ran = r.cull_pass_ran();
        const double overlap = r.expected_overlap();
        const std::size_t drawn = r.drawn_primitives();
        o.occlusion_min_overlap = 0.0f;
        r.draw(cam, light, o);
        const Image forced = r.read();
        CHECK(r.cull_pass_ran());
        CHECK(r.expected_overlap() == 0.0);  // (not estimated)
        o.occlusion_culling = false;
        r.draw(cam, light, o);
        const Image off = r.read();
        CHECK_FALSE(r.cull_pass_ran());
        std::printf("[occlusion] %d spheres: expected overlap %.2f, cull pass %s, %zu drawn\n", n, overlap, ran ? "ran" : "skipped", drawn);
        const ImageDiff da = image_diff(automatic, off), df = image_diff(forced, off);
        CHECK(da.coverage_diff == 0);
        CHECK(da.color_diff == 0);
        CHECK(da.depth_diff == 0);
        CHECK(df.coverage_diff == 0);
        CHECK(df.color_diff == 0);
        CHECK(df.depth_diff == 0);
        if (n == 300) {
            CHECK(overlap < 0.5);
            CHECK_FALSE(ran);
            CHECK(drawn == prims.size());
        } else {
            CHECK(overlap > double(RenderOptions{}.occlusion_min_overlap));
            CHECK(ran);
            CHECK(drawn < prims.size() / 2);
        }
    }
}

TEST_CASE("reusing the last frame's shown set changes no pixel, as the camera moves or stays, and draws fewer primitives") {
    // Frames repeat in one renderer with RenderOptions::occlusion_reuse (the default): the first
    // records its shown set, each later one draws that set first and tests every primitive
    // against its depth. Every frame against a renderer without occlusion culling, for each
    // case's camera, the camera turned and moved, and back; forward, back-face culling off,
    // deferred with shadows and outlines (the shadow map's set is its own).
    gl::OsmesaContext ctx;
    gl::QuadricRenderer r(ctx.api()), plain(ctx.api());
    const int w = 320, h = 240;
    Light light;
    light.direction = vec3(-0.4f, -0.6f, -1.0f);
    for (const Case& s : occlusion_cases(w, h)) {
        r.set_primitives(s.prims);
        plain.set_primitives(s.prims);
        // The case's camera, and the same camera turned about the target and moved in
        const Camera moved = turned(s.camera, 0.15f, glm::vec3(0.3f, 1.0f, 0.1f), glm::vec3(0.02f, -0.03f, 0.05f));
        const Camera* cams[] = {&s.camera, &s.camera, &s.camera, &moved, &moved, &s.camera};
        for (int mode = 0; mode < 3; ++mode) {
            RenderOptions o;
            o.occlusion_min_overlap = 0.0f;  // (reuse in every frame, however sparse the scene)
            o.width = w;
            o.height = h;
            o.culling = mode != 1;
            o.deferred = o.shadows = o.silhouettes = mode == 2;
            o.shadow_map_reuse = false;  // (the shadow map drawn in every frame, from its own shown set, which reaches the set alone too)
            RenderOptions off = o;
            off.occlusion_culling = false;
            std::size_t first_drawn = 0, last_drawn = 0;
            int reused = 0, unchanged = 0;
            for (int f = 0; f < 6; ++f) {
                r.draw(*cams[f], light, o);
                const Image got = r.read();
                plain.draw(*cams[f], light, off);
                const ImageDiff d = image_diff(got, plain.read());
                reused += r.reused_shown_set();
                unchanged += r.unchanged_view();
                // The set alone where the view is the one its set was tested under against what
                // the set before it drew: the third frame of each camera (the first records a set
                // against occluder disks, the second tests it against what it drew).
                if (f == 2 || f == 4) CHECK(r.unchanged_view());
                if (f == 3 || f == 5) CHECK_FALSE(r.unchanged_view());
                if (f == 0) first_drawn = r.drawn_primitives();
                if (f == 2) last_drawn = r.drawn_primitives();
                CAPTURE(s.name);
                CAPTURE(mode);
                CAPTURE(f);
                CHECK(d.covered > 300);
                CHECK(d.coverage_diff == 0);
                CHECK(d.color_diff == 0);
                CHECK(d.depth_diff == 0);
                CHECK(r.drawn_primitives() <= s.prims.size());
            }
            std::printf("[occlusion reuse] %s, mode %d: %d of 5 later frames reused the shown set, %d of them drew it alone (view unchanged); %zu primitives drawn in the first frame, %zu in the third, of %zu\n",
                        s.name.c_str(), mode, reused, unchanged, first_drawn, last_drawn, s.prims.size());
            CAPTURE(s.name);
            CHECK(reused >= 5);  // (none of these cases is drawn in phases; after the first mode the first frame reuses the last mode's set too)
            if (s.name.rfind("dense block", 0) == 0 && s.name != "dense block, eye inside") CHECK(last_drawn < first_drawn);
        }
    }
    // By default only where the primitives overlap enough (a sparse scene does not, the dense
    // block does); switched off, never.
    const std::vector<Case> cases = occlusion_cases(w, h);
    RenderOptions o;
    o.width = w;
    o.height = h;
    for (const Case& c : cases) {
        if (c.name != "every kind, perspective" && c.name != "dense block, perspective") continue;
        r.set_primitives(c.prims);
        o.occlusion_reuse = true;
        r.draw(c.camera, light, o);
        r.draw(c.camera, light, o);
        CAPTURE(c.name);
        CHECK(r.reused_shown_set() == (c.name == "dense block, perspective"));
        o.occlusion_reuse = false;
        r.draw(c.camera, light, o);
        r.draw(c.camera, light, o);
        CHECK_FALSE(r.reused_shown_set());
    }
    // With set_skip_unchanged_view_test(false) every reusing frame tests again, drawing the set
    // and then what passes: the same picture as the set alone (the records the picture shows,
    // set_shown_from_picture), which stays the same set. (The two
    // renderers' sets may differ by a few primitives: the first frame's occluder disks are written
    // with plain stores, so which of two overlapping disks a pixel keeps varies from run to run;
    // either is conservative.)
    for (const Case& c : cases) {
        if (c.name != "dense block, perspective") continue;
        o.occlusion_reuse = true;
        gl::QuadricRenderer retest(ctx.api());
        retest.set_skip_unchanged_view_test(false);
        retest.set_primitives(c.prims);
        r.set_primitives(c.prims);
        std::size_t set_drawn = 0;
        for (int f = 0; f < 4; ++f) {
            r.draw(c.camera, light, o);
            retest.draw(c.camera, light, o);
            CAPTURE(f);
            CHECK_FALSE(retest.unchanged_view());
            CHECK(r.unchanged_view() == (f >= 2));
            if (f == 2) set_drawn = r.drawn_primitives();
            if (f >= 2) {
                // (drawn alone: the records the second frame's picture showed, fewer than the
                // test's set that the renderer testing again draws)
                CHECK(r.shown_set_from_picture());
                CHECK(r.drawn_primitives() == set_drawn);
                CHECK(r.drawn_primitives() < retest.drawn_primitives());
                CHECK(r.drawn_primitives() + r.occluded() == c.prims.size());
            }
            const ImageDiff d = image_diff(r.read(), retest.read());
            CHECK(d.coverage_diff == 0);
            CHECK(d.color_diff == 0);
            CHECK(d.depth_diff == 0);
        }
    }
}

/// The options of the shown-set tests' modes: 0 forward, 1 back-face culling off, 2 deferred with
/// shadows and outlines (3 and up: forward; the caller adds to it); the cull pass whatever the overlap.
RenderOptions mode_options(int mode, int w, int h) {
    RenderOptions o;
    o.occlusion_min_overlap = 0.0f;
    o.width = w;
    o.height = h;
    o.culling = mode != 1;
    o.deferred = o.shadows = o.silhouettes = mode == 2;
    return o;
}

TEST_CASE("a shown set drawn alone becomes the records its picture shows: what the CPU reference's picture shows, the same picture") {
    // The same camera frame after frame: a frame whose camera has not moved since the last one
    // lists the records its picture shows, and the frames after it with the view unchanged draw
    // those alone. Then the camera moves (the set is tested again, drawing the smaller set
    // first) and comes back. Every frame against a renderer without occlusion
    // culling, and one with the test's set only (set_shown_from_picture(false)); the records
    // drawn alone against the primitives the CPU reference's picture shows
    // (render::FrameStats::shown: an independent visibility, with its own bounds, binning and
    // casts, the nearest hit per pixel). Forward, back-face culling off, deferred with shadows
    // and outlines.
    gl::OsmesaContext ctx;
    gl::QuadricRenderer r(ctx.api()), plain(ctx.api()), tested(ctx.api());
    tested.set_shown_from_picture(false);
    const int w = 320, h = 240;
    Light light;
    light.direction = vec3(-0.4f, -0.6f, -1.0f);
    std::size_t fewer = 0, cases = 0;
    int reshaded = 0;
    for (const Case& s : occlusion_cases(w, h)) {
        r.set_primitives(s.prims);
        plain.set_primitives(s.prims);
        tested.set_primitives(s.prims);
        const bool has_spheres = std::any_of(s.prims.begin(), s.prims.end(), [](const Primitive& p) { return p.variant == render::Variant::sphere; });
        const Camera moved = turned(s.camera, 0.1f, glm::vec3(0.1f, 1.0f, 0.2f), glm::vec3(0.0f));
        const Camera* cams[] = {&s.camera, &s.camera, &s.camera, &s.camera, &s.camera, &moved, &s.camera, &s.camera, &s.camera, &s.camera};
        for (int mode = 0; mode < 3; ++mode) {
            const RenderOptions o = mode_options(mode, w, h);
            RenderOptions off = o;
            off.occlusion_culling = false;
            render::FrameStats cpu;
            (void)render::render_cpu(s.prims, s.camera, light, o, &cpu);
            std::size_t before = s.prims.size();
            for (int f = 0; f < 10; ++f) {
                r.draw(*cams[f], light, o);
                tested.draw(*cams[f], light, o);
                plain.draw(*cams[f], light, off);
                CAPTURE(s.name);
                CAPTURE(mode);
                CAPTURE(f);
                const Image want = plain.read();
                for (const Image& got : {r.read(), tested.read()}) {
                    const ImageDiff d = image_diff(got, want);
                    CHECK(d.coverage_diff == 0);
                    CHECK(d.color_diff == 0);
                    CHECK(d.depth_diff == 0);
                }
                CHECK_FALSE(tested.shown_set_from_picture());
                if (r.shown_set_from_picture()) {
                    // The records the picture shows: no more than the frame before drew alone,
                    // and those the CPU reference's picture shows, but for the few pixels where
                    // the two pictures' nearest hits may differ (the rays' set-up rounds apart).
                    CHECK(r.unchanged_view());
                    CHECK(r.drawn_primitives() <= before);
                    CHECK(r.drawn_primitives() + r.occluded() == s.prims.size());
                    CHECK(std::abs(static_cast<double>(r.drawn_primitives()) - static_cast<double>(cpu.shown)) <= 2.0 + 0.01 * static_cast<double>(cpu.shown));
                }
                // The fourth frame of a still camera draws the picture's records alone, and so do
                // the frames after it; the renderer without them, the test's set. The spheres among
                // them are shaded from the ids target (set_reshade), the others drawn.
                if (r.reshaded()) CHECK((r.shown_set_from_picture() && has_spheres));
                reshaded += r.reshaded();
                CHECK_FALSE(tested.reshaded());
                if (f == 4 || f == 9) {
                    CHECK(r.shown_set_from_picture());
                    CHECK(tested.unchanged_view());
                    CHECK(r.drawn_primitives() <= tested.drawn_primitives());
                }
                if (f == 5) CHECK_FALSE(r.unchanged_view());
                before = r.unchanged_view() ? r.drawn_primitives() : s.prims.size();
            }
            std::printf("[shown set from the picture] %s, mode %d: %zu drawn alone from the picture, %zu of the test's set; the CPU reference's picture shows %llu of %zu\n",
                        s.name.c_str(), mode, r.drawn_primitives(), tested.drawn_primitives(), static_cast<unsigned long long>(cpu.shown), s.prims.size());
            fewer += r.drawn_primitives() < tested.drawn_primitives();
            ++cases;
        }
    }
    CHECK(fewer * 2 > cases);  // (the test's set is larger in most)
    std::printf("[shown set from the picture] %d frames shaded the spheres from the ids target\n", reshaded);
    CHECK(reshaded > 100);
}

TEST_CASE("the spheres shaded from the ids target: the sprites' picture and depth, the light and material of the frame, one fragment per pixel") {
    // A still camera: from the fourth frame the records the picture shows are drawn alone and the
    // sphere variant's are shaded from the ids target (QuadricRenderer::set_reshade). Against a
    // renderer without occlusion culling, frame by frame: the same colour, depth and coverage,
    // also after the light and the material change with the view kept (the ids say which record
    // shows, not how it is lit), forward, culling off, deferred with shadows and outlines, with
    // environment reflections, perspective and orthographic. The counted fragments of a reshaded frame of spheres alone:
    // one started per pixel of the view, and as many hit as the picture covers (its pixels of
    // depth below 1, read back independently), each once.
    gl::OsmesaContext ctx;
    gl::QuadricRenderer r(ctx.api()), plain(ctx.api());
    const int w = 256, h = 192;
    const double aspect = double(w) / h;
    std::mt19937 rng(77);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    std::vector<Primitive> balls, mixed;
    for (int i = 0; i < 3000; ++i) balls.push_back(shapes::sphere({u(rng), u(rng), u(rng)}, 0.04f, {{u(rng), u(rng), u(rng)}}));
    mixed = balls;
    for (int i = 0; i < 300; ++i) mixed.push_back(shapes::ellipsoid({u(rng), u(rng), u(rng)}, glm::vec3(0.08f, 0.03f, 0.05f), glm::mat3(1.0f), {{0.9f, 0.4f, 0.2f}}));
    const Camera persp = qc_render_test::look_at(vec3(0.4, 0.7, 2.6), vec3(0.5, 0.5, 0.5), vec3(0.0, 1.0, 0.0), qc_render_test::perspective(35, aspect, 1, 5));
    const Camera ortho = qc_render_test::look_at(vec3(0.4, 0.7, 2.6), vec3(0.5, 0.5, 0.5), vec3(0.0, 1.0, 0.0),
                                                 qc_render_test::orthographic(-0.9 * aspect, 0.9 * aspect, -0.9, 0.9, 1, 5), true);
    const auto env = std::make_shared<const render::EnvironmentMap>(render::procedural_environment({}, 256, 128));
    int reshaded = 0;
    for (const std::vector<Primitive>* prims : {&balls, &mixed}) {
        r.set_primitives(*prims);
        plain.set_primitives(*prims);
        for (const Camera* cam : {&persp, &ortho}) {
            for (int mode = 0; mode < 4; ++mode) {
                RenderOptions o = mode_options(mode, w, h);
                if (mode == 3) o.environment = env;
                Light light;
                light.direction = vec3(-0.4f, -0.6f, -1.0f);
                for (int f = 0; f < 8; ++f) {
                    if (f == 6) {
                        light.direction = vec3(0.7f, -0.2f, -0.5f);
                        light.color = vec3(1.0f, 0.8f, 0.6f);
                        o.material = vec4(0.2f, 0.6f, 0.9f, 40.0f);
                    }
                    RenderOptions off = o;
                    off.occlusion_culling = false;
                    r.draw(*cam, light, o);
                    plain.draw(*cam, light, off);
                    CAPTURE(prims->size());
                    CAPTURE(cam->orthographic);
                    CAPTURE(mode);
                    CAPTURE(f);
                    const ImageDiff d = image_diff(r.read(), plain.read());
                    CHECK(d.covered > 1000);
                    CHECK(d.coverage_diff == 0);
                    CHECK(d.color_diff == 0);
                    CHECK(d.depth_diff == 0);
                    if (f >= 4) CHECK(r.reshaded());
                    reshaded += r.reshaded();
                }
                // Counted, spheres alone, forward: one fragment started per pixel, hits exactly the covered pixels
                if (prims == &balls && mode == 0) {
                    r.set_count_fragments(true);
                    r.draw(*cam, light, o);
                    r.set_count_fragments(false);
                    REQUIRE(r.reshaded());
                    const Image img = r.read();
                    const auto covered = static_cast<std::uint64_t>(std::count_if(img.depth.begin(), img.depth.end(), [](float z) { return z < 1.0f; }));
                    const gl::FragmentCounts& c = r.fragment_counts();
                    CHECK(c.started == static_cast<std::uint64_t>(w) * static_cast<std::uint64_t>(h));
                    CHECK(c.hit == covered);
                    CHECK(c.cast >= c.hit);
                    CHECK(c.cast <= covered);
                }
            }
        }
    }
    // Switched off, the sprites are drawn: the same picture
    r.set_primitives(mixed);
    plain.set_primitives(mixed);
    RenderOptions o;
    o.occlusion_min_overlap = 0.0f;
    o.width = w;
    o.height = h;
    RenderOptions off = o;
    off.occlusion_culling = false;
    Light light;
    for (int f = 0; f < 6; ++f) {
        r.set_reshade(f % 2 == 0);
        r.draw(persp, light, o);
        plain.draw(persp, light, off);
        CAPTURE(f);
        if (f >= 4) CHECK(r.shown_set_from_picture());
        if (f % 2 == 1) CHECK_FALSE(r.reshaded());
        if (f == 4) CHECK(r.reshaded());
        const ImageDiff d = image_diff(r.read(), plain.read());
        CHECK(d.coverage_diff == 0);
        CHECK(d.color_diff == 0);
        CHECK(d.depth_diff == 0);
    }
    // The ids target is the renderer's own: a resize between the listing frame and the next drops
    // the set (the next frames test and list anew), and forward and deferred frames share it.
    r.set_reshade(true);
    const int sizes[][2] = {{w, h}, {w, h}, {w, h}, {w, h}, {w, h}, {w / 2, h / 2}, {w / 2, h / 2}, {w, h}, {w, h}, {w, h}, {w, h}, {w, h}, {w, h}, {w, h}};
    for (int f = 0; f < 14; ++f) {
        o.width = sizes[f][0];
        o.height = sizes[f][1];
        o.deferred = o.shadows = f >= 11;  // (forward, then deferred with the view kept)
        RenderOptions plain_o = o;
        plain_o.occlusion_culling = false;
        r.draw(persp, light, o);
        plain.draw(persp, light, plain_o);
        CAPTURE(f);
        if (f == 4 || f == 10 || f == 13) CHECK(r.reshaded());
        if (f == 5 || f == 7) CHECK_FALSE(r.reshaded());
        const ImageDiff d = image_diff(r.read(), plain.read());
        CHECK(d.covered > 100);
        CHECK(d.coverage_diff == 0);
        CHECK(d.color_diff == 0);
        CHECK(d.depth_diff == 0);
    }
    std::printf("[reshade] %d frames shaded the spheres from the ids target\n", reshaded);
}
