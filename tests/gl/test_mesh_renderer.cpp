// tests/gl/test_mesh_renderer.cpp -- the GL triangle-mesh renderer: coverage, plane depth, shading, several meshes, bad input
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>

#include "quadcast/gl/mesh_renderer.hpp"
#include "quadcast/gl/osmesa_context.hpp"
#include "quadcast/gl/quadric_renderer.hpp"
#include "quadcast/render/cpu_renderer.hpp"
#include "quadcast/render/sphere_mesh.hpp"
#include "quadcast/shading.hpp"
#include "render/render_testing.hpp"

using namespace quadcast;
using namespace quadcast::render;
using qc_render_test::LD;
using qc_render_test::V3;

namespace {

/// A box with centre c, half-size h and orthonormal axes e[0..2]: 6 faces of 4 vertices with the
/// face normal (outward, or inward when `inward`), 12 triangles.
gl::Mesh box_mesh(const Vec3<double>& c, double h, const Vec3<double> e[3], Vec3<float> color, bool inward = false) {
    gl::Mesh m;
    m.color = color;
    for (int axis = 0; axis < 3; ++axis)
        for (int side : {-1, 1}) {
            const Vec3<double> n = e[axis] * double(side);
            const Vec3<double> u = e[(axis + 1) % 3], v = e[(axis + 2) % 3];
            const auto base = static_cast<std::uint32_t>(m.positions.size());
            const double su[4] = {-1, 1, 1, -1}, sv[4] = {-1, -1, 1, 1};
            for (int k = 0; k < 4; ++k) {
                m.positions.push_back(cast<float>(c + n * h + u * (su[k] * h) + v * (sv[k] * h)));
                m.normals.push_back(cast<float>(inward ? -n : n));
            }
            for (std::uint32_t k : {0u, 1u, 2u, 0u, 2u, 3u}) m.indices.push_back(base + k);
        }
    return m;
}

/// The exact ray o + t d against the box (centre c, half-size h, axes e) grown by g (absolute):
/// the entry t and the axis of the entry face, or t = -1 when the ray misses or starts inside.
struct BoxHit {
    LD t = -1;
    int axis = -1, side = 0;
};
BoxHit box_hit(const V3& o, const V3& d, const V3& c, LD h, const V3 e[3], LD g) {
    LD t_in = -1e300L, t_out = 1e300L;
    BoxHit hit;
    for (int a = 0; a < 3; ++a) {
        const LD od = qc_render_test::dot_ld(o - c, e[a]), dd = qc_render_test::dot_ld(d, e[a]);
        if (dd == 0) {
            if (std::fabs(od) > h + g) return {};
            continue;
        }
        LD t0 = (-(h + g) - od) / dd, t1 = ((h + g) - od) / dd;
        int side = -1;
        if (t0 > t1) {
            std::swap(t0, t1);
            side = 1;
        }
        if (t0 > t_in) {
            t_in = t0;
            hit.axis = a;
            hit.side = side;
        }
        t_out = std::min(t_out, t1);
    }
    if (t_in > t_out || t_in <= 0) return {};
    hit.t = t_in;
    return hit;
}

/// An Api whose every entry point is null: a renderer that made a GL call would crash.
const gl::Api& null_api() {
    static const gl::Api api{};
    return api;
}

}  // namespace

TEST_CASE("MeshRenderer rejects bad meshes with a clear error before any GL call") {
    gl::MeshRenderer r(null_api());
    const Vec3<double> e[3] = {vec3(1.0, 0.0, 0.0), vec3(0.0, 1.0, 0.0), vec3(0.0, 0.0, 1.0)};
    const gl::Mesh good = box_mesh(vec3(0.0, 0.0, 0.0), 1.0, e, vec3(0.5f, 0.5f, 0.5f));
    auto rejects = [&](const gl::Mesh& bad, const char* text) {
        CHECK_THROWS_WITH_AS(r.set_meshes({good, bad}), doctest::Contains(text), std::invalid_argument);
    };
    gl::Mesh m = good;
    m.indices[7] = 24;
    rejects(m, "mesh 1: index 7 (triangle 2) is 24, but the mesh has 24 vertices");
    m = good;
    m.indices.back() = 0xffffffffu;
    rejects(m, "mesh 1: index 35 (triangle 11) is 4294967295, but the mesh has 24 vertices");
    m = good;
    m.indices.pop_back();
    rejects(m, "mesh 1: 35 indices is not a multiple of 3");
    m = good;
    m.normals.pop_back();
    rejects(m, "mesh 1: 24 positions but 23 normals");
    m = good;
    m.positions[5][1] = std::nanf("");
    rejects(m, "mesh 1: position 5 is not finite");
    m = good;
    m.normals[3] = vec3(0.0f, 0.0f, 0.0f);
    rejects(m, "mesh 1: normal 3 is zero");
    m = good;
    m.normals[2][0] = std::numeric_limits<float>::infinity();
    rejects(m, "mesh 1: normal 2 is not finite");
    m = good;
    m.color[2] = std::nanf("");
    rejects(m, "mesh 1: colour is not finite");
    // Drawing with effects meshes do not have is refused before any GL call, too.
    RenderOptions o;
    o.shadows = true;
    CHECK_THROWS_AS(r.draw(Camera{}, Light{}, o), std::invalid_argument);
    CHECK(r.mesh_count() == 0);
}

TEST_CASE("a box covers the pixels its exact rays hit, at the depth of its face planes, shaded like the impostors") {
    // Exact: the pixel ray (long double, from the float camera) against the box. A pixel may
    // disagree only where the ray passes within 1e-4 h of an edge (the box grown and shrunk by
    // that much disagree; 1e-4 h is < 0.01 px here). Depth: the window depth of the entry point
    // on its face plane; rasterised depth is interpolated in float, so a few ulp of 1.
    // Colour: shade_blinn_phong of the face normal (either orientation: two-sided), the light and
    // the direction to the eye at the exact hit (orthographic: the view axis), within 1 LSB.
    gl::OsmesaContext ctx;
    gl::MeshRenderer r(ctx.api());
    const int w = 240, h = 180;
    Light light;
    light.direction = vec3(-0.3f, -0.5f, -1.0f);
    long total_cover = 0, total_mismatch = 0, color_off = 0, edge_px = 0;
    double worst_depth = 0;
    int worst_color = 0;
    for (std::uint32_t it = 0; it < 6; ++it) {
        std::mt19937 rng = qc_render_test::rng_for(301, it);
        const bool ortho = it % 2 == 1;
        const Vec3<double> c = vec3(0.3, -0.2, 0.1);
        const double hs = 0.7;
        Vec3<double> e[3];
        e[0] = qc_render_test::random_dir(rng);
        e[1] = normalize(cross(e[0], qc_render_test::random_dir(rng)));
        e[2] = cross(e[0], e[1]);
        const Vec3<double> eye = c + qc_render_test::random_dir(rng) * qc_render_test::uniform(rng, 2.5, 5.0);
        const Camera cam = ortho ? qc_render_test::look_at(eye, c, qc_render_test::random_dir(rng), qc_render_test::orthographic(-1.6, 1.6, -1.2, 1.2, 0.5, 10.0), true)
                                 : qc_render_test::look_at(eye, c, qc_render_test::random_dir(rng), qc_render_test::perspective(50, double(w) / h, 0.5, 10.0));
        const Vec3<float> color = vec3(0.9f, 0.5f, 0.2f);
        RenderOptions opt;
        opt.width = w;
        opt.height = h;
        r.set_meshes({box_mesh(c, hs, e, color)});
        r.draw(cam, light, opt);
        const Image img = r.read();
        CHECK(r.triangle_count() == 12);
        // The same box with inward normals draws the same image (two-sided shading).
        r.set_meshes({box_mesh(c, hs, e, color, true)});
        r.draw(cam, light, opt);
        const Image inward = r.read();
        CHECK(inward.rgba == img.rgba);
        CHECK(inward.depth == img.depth);

        const qc_render_test::ExactCamera ex(cam, w, h);
        const V3 cl = qc_render_test::ld(c);
        const V3 el[3] = {qc_render_test::ld(e[0]), qc_render_test::ld(e[1]), qc_render_test::ld(e[2])};
        const Vec3<float> vz_row = vec3(cam.view[0][2], cam.view[1][2], cam.view[2][2]);
        long cover = 0, mismatch = 0;
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                V3 o, d;
                ex.ray(x, y, o, d);
                const BoxHit hit = box_hit(o, d, cl, hs, el, 0);
                const LD depth = hit.t > 0 ? qc_render_test::exact_depth(cam.projection, ex.view_z(o + d * hit.t)) : 2;
                const bool exact = hit.t > 0 && depth >= 0 && depth <= 1;
                const bool boundary = (box_hit(o, d, cl, hs, el, 1e-4L * hs).t > 0) != (box_hit(o, d, cl, hs, el, -1e-4L * hs).t > 0);
                cover += exact;
                const bool drawn = qc_render_test::covered(img, x, y);
                if (exact != drawn) {
                    ++mismatch;
                    CHECK_MESSAGE(boundary, "view " << it << " pixel (" << x << ", " << y << ") exact=" << exact);
                }
                if (!exact || !drawn || boundary) continue;
                // Pixels within 1e-4 h of an edge between two visible faces may show either face.
                const V3 xl = o + d * hit.t - cl;
                bool on_edge = false;
                for (int a = 0; a < 3; ++a)
                    on_edge |= a != hit.axis && std::fabs(qc_render_test::dot_ld(xl, el[a])) >= (1 - 1e-4L) * hs;
                if (on_edge) {
                    ++edge_px;
                    continue;
                }
                const double de = double(std::fabs(LD(qc_render_test::depth_at(img, x, y)) - depth));
                worst_depth = std::max(worst_depth, de);
                CHECK_MESSAGE(de <= 6e-7, "view " << it << " pixel (" << x << ", " << y << ")");
                // Shading of the entry face
                const Vec3<float> n = cast<float>(e[hit.axis] * double(hit.side));
                const V3 xh = o + d * hit.t;
                const Vec3<float> to_eye = ortho ? vz_row : vec3(float(ex.eye[0] - xh[0]), float(ex.eye[1] - xh[1]), float(ex.eye[2] - xh[2]));
                const Vec3<float> rgb = shade_blinn_phong(n, -light.direction, to_eye, color, light.color, opt.material);
                const std::uint8_t* px = &img.rgba[(std::size_t(h - 1 - y) * w + x) * 4];
                int diff = 0;
                for (int k = 0; k < 3; ++k) diff = std::max(diff, std::abs(int(px[k]) - int(cpu_detail::to_unorm8(rgb[k]))));
                worst_color = std::max(worst_color, diff);
                color_off += diff > 0;
                CHECK_MESSAGE(diff <= 1, "view " << it << " pixel (" << x << ", " << y << ")");
            }
        total_cover += cover;
        total_mismatch += mismatch;
    }
    std::printf("[mesh] boxes: %ld covered pixels, %ld coverage mismatches (all within 1e-4 h of an edge), max depth error %.2e, "
                "colour: %ld pixels off by %d LSB at most (%ld pixels on inner edges not compared)\n",
                total_cover, total_mismatch, worst_depth, color_off, worst_color, edge_px);
    CHECK(total_cover > 20000);
    CHECK(total_mismatch <= 10);
}

TEST_CASE("several meshes: each drawn in its own colour, the nearer one in front") {
    // Two overlapping squares facing an orthographic camera (one world unit per pixel), the
    // nearer drawn first and second; ambient-only material, so a pixel's colour is its mesh's
    // colour exactly.
    gl::OsmesaContext ctx;
    gl::MeshRenderer r(ctx.api());
    const int w = 128, h = 96;
    auto square = [](double x0, double y0, double x1, double y1, double z, Vec3<float> color) {
        gl::Mesh m;
        m.color = color;
        m.positions = {vec3(float(x0), float(y0), float(z)), vec3(float(x1), float(y0), float(z)), vec3(float(x1), float(y1), float(z)),
                       vec3(float(x0), float(y1), float(z))};
        m.normals.assign(4, vec3(0.0f, 0.0f, 1.0f));
        m.indices = {0, 1, 2, 0, 2, 3};
        return m;
    };
    // Window x = world x + 64, window y = world y + 48 (edges at .25 and .75: no pixel centre on them)
    const gl::Mesh near = square(-40.25, -30.25, 10.25, 20.75, -2.0, vec3(1.0f, 0.0f, 0.0f));
    const gl::Mesh far = square(-10.75, -20.75, 40.75, 30.25, -6.0, vec3(0.0f, 0.0f, 1.0f));
    const Camera cam = qc_render_test::look_at(vec3(0.0, 0.0, 0.0), vec3(0.0, 0.0, -1.0), vec3(0.0, 1.0, 0.0),
                                               qc_render_test::orthographic(-64, 64, -48, 48, 1, 11), true);
    RenderOptions opt;
    opt.width = w;
    opt.height = h;
    opt.material = vec4(1.0f, 0.0f, 0.0f, 1.0f);
    opt.background = vec3(0.0f, 1.0f, 0.0f);
    Light light;
    light.direction = vec3(0.0f, 0.0f, -1.0f);
    auto inside = [](int px, double lo, double hi) { return px + 0.5 > lo && px + 0.5 < hi; };
    for (bool near_first : {true, false}) {
        r.set_meshes(near_first ? std::vector<gl::Mesh>{near, far} : std::vector<gl::Mesh>{far, near});
        CHECK(r.mesh_count() == 2);
        CHECK(r.triangle_count() == 4);
        CHECK(r.vertex_count() == 8);
        r.draw(cam, light, opt);
        const Image img = r.read();
        long wrong = 0, visible = 0;
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                const bool in_near = inside(x, -40.25 + 64, 10.25 + 64) && inside(y, -30.25 + 48, 20.75 + 48);
                const bool in_far = inside(x, -10.75 + 64, 40.75 + 64) && inside(y, -20.75 + 48, 30.25 + 48);
                const std::uint8_t want[3] = {std::uint8_t(in_near ? 255 : 0), std::uint8_t(!in_near && !in_far ? 255 : 0),
                                              std::uint8_t(!in_near && in_far ? 255 : 0)};
                // Depth of the plane z = -2 or -6 (exact_depth of the view z)
                const LD want_depth = in_near ? qc_render_test::exact_depth(cam.projection, -2.0L)
                                      : in_far ? qc_render_test::exact_depth(cam.projection, -6.0L)
                                               : 1.0L;
                const std::uint8_t* px = &img.rgba[(std::size_t(h - 1 - y) * w + x) * 4];
                const bool ok = px[0] == want[0] && px[1] == want[1] && px[2] == want[2] &&
                                std::fabs(LD(qc_render_test::depth_at(img, x, y)) - want_depth) <= 1e-6L;
                wrong += !ok;
                visible += in_near || in_far;
            }
        CHECK_MESSAGE(wrong == 0, (near_first ? "near first" : "far first"));
        // Every visible pixel passed the depth test once, the overlap twice when far came first.
        CHECK(r.samples_passed() >= std::uint64_t(visible));
    }
    // No meshes: the background alone.
    r.set_meshes({});
    r.draw(cam, light, opt);
    const Image empty = r.read();
    CHECK(std::all_of(empty.depth.begin(), empty.depth.end(), [](float d) { return d == 1.0f; }));
    CHECK(r.triangle_count() == 0);
}

TEST_CASE("a finely tessellated sphere draws like the impostor sphere") {
    // A frequency-48 geodesic sphere (46080 triangles; sagitta ~1e-4 r, ~0.005 px here) against
    // the GL quadric renderer's sphere (~55 px radius): the outlines differ only at pixel centres
    // within that gap (plus the rasteriser's 1/256 px vertex snapping) of a ~350 px long outline,
    // a few pixels; the colours agree within 2 LSB (the interpolated vertex normal is within
    // ~1e-3 rad of the true one).
    gl::OsmesaContext ctx;
    gl::MeshRenderer mr(ctx.api());
    gl::QuadricRenderer qr(ctx.api());
    const int w = 256, h = 192;
    const Vec3<double> c = vec3(0.2, 0.1, -0.3);
    const double radius = 0.9;
    const SphereMesh unit = geodesic_sphere(48);
    gl::Mesh m;
    m.color = vec3(0.8f, 0.3f, 0.2f);
    for (const auto& v : unit.vertices) {
        m.positions.push_back(cast<float>(c + v * radius));
        m.normals.push_back(cast<float>(v));
    }
    for (const auto& t : unit.triangles) m.indices.insert(m.indices.end(), t.begin(), t.end());
    mr.set_meshes({m});
    qr.set_primitives({qc_render_test::sphere(cast<float>(c), float(radius), m.color)});
    const Camera cam = qc_render_test::look_at(vec3(1.0, 1.5, 4.0), c, vec3(0.0, 1.0, 0.0), qc_render_test::perspective(40, double(w) / h, 0.5, 10.0));
    Light light;
    light.direction = vec3(-0.4f, -0.6f, -1.0f);
    RenderOptions opt;
    opt.width = w;
    opt.height = h;
    mr.draw(cam, light, opt);
    qr.draw(cam, light, opt);
    const Image a = mr.read(), b = qr.read();
    long both = 0, cover_diff = 0, color_big = 0;
    int worst = 0;
    for (std::size_t i = 0; i < a.depth.size(); ++i) {
        const bool ca = a.depth[i] < 1.0f, cb = b.depth[i] < 1.0f;
        if (ca != cb) { ++cover_diff; continue; }
        if (!ca) continue;
        ++both;
        int d = 0;
        for (int k = 0; k < 3; ++k) d = std::max(d, std::abs(int(a.rgba[i * 4 + k]) - int(b.rgba[i * 4 + k])));
        worst = std::max(worst, d);
        color_big += d > 2;
    }
    std::printf("[mesh] f=48 sphere vs impostor: %ld pixels covered by both, %ld coverage differences, %ld colour differences > 2 LSB (max %d)\n",
                both, cover_diff, color_big, worst);
    CHECK(both > 8000);
    CHECK(cover_diff <= 20);
    CHECK(color_big <= both / 1000);
}
