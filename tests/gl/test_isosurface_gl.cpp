// tests/gl/test_isosurface_gl.cpp -- the GL isosurface renderer (QSS, S31, trilinear) draws the CPU reference's image
#include <doctest/doctest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <functional>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "quadcast/gl/framebuffer.hpp"
#include "quadcast/gl/isosurface_renderer.hpp"
#include "quadcast/gl/osmesa_context.hpp"
#include "quadcast/gl/quadric_renderer.hpp"
#include "quadcast/render/spline_cpu_renderer.hpp"
#include "quadcast/spline/render.hpp"
#include "gl/host_frame.hpp"
#include "render/render_testing.hpp"

using namespace quadcast;
using namespace quadcast::render;

namespace {

/// n^3 samples of the Marschner-Lobb function on [-1,1]^3.
spline::Volume<float> marschner_lobb_volume(int n) {
    spline::Volume<float> v(n, n, n);
    const double h = 2.0 / (n - 1), a = 0.25, fm = 6.0;
    for (int k = 0; k < n; ++k)
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i) {
                const double x = -1 + h * i, y = -1 + h * j, z = -1 + h * k, r = std::sqrt(x * x + y * y);
                v.at(i, j, k) = float((1.0 - std::sin(M_PI * z / 2.0) + a * (1.0 + std::cos(2.0 * M_PI * fm * std::cos(M_PI * r / 2.0)))) / (2.0 * (1.0 + a)));
            }
    return v;
}

Camera camera(bool ortho, double distance = 4.0) {
    const Vec3<double> eye = vec3(1.2, -2.1, 2.4) * (distance / 3.4);
    return ortho ? qc_render_test::look_at(eye, vec3(0.0, 0.0, 0.0), vec3(0.0, 0.0, 1.0), qc_render_test::orthographic(-1.4, 1.4, -1.1, 1.1, 0.5, 10), true)
                 : qc_render_test::look_at(eye, vec3(0.0, 0.0, 0.0), vec3(0.0, 0.0, 1.0), qc_render_test::perspective(40, 200.0 / 160.0, 0.5, 10));
}

/// GL (the quadric renderer's passes with the isosurfaces as a ScenePass) and CPU images.
struct Pair {
    Image gl, cpu;
};

struct Compare {
    long covered = 0, mismatch = 0, mismatch_inside = 0, depth_far = 0, color_far = 0;
    double max_depth_inside = 0;
    int max_color_inside = 0;
};

/// A pixel is on a silhouette when its 3x3 neighbourhood in `img` has both covered and
/// uncovered pixels, or depths more than `jump` apart.
bool at_edge(const Image& img, int x, int y, float jump) {
    const float d0 = img.depth[std::size_t(y) * img.width + x];
    for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
            const int u = std::clamp(x + dx, 0, img.width - 1), v = std::clamp(y + dy, 0, img.height - 1);
            const float d = img.depth[std::size_t(v) * img.width + u];
            if ((d < 1.0f) != (d0 < 1.0f) || std::abs(d - d0) > jump) return true;
        }
    return false;
}

Compare compare(const Pair& p, float depth_tol, int color_tol) {
    Compare c;
    for (int y = 0; y < p.cpu.height; ++y)
        for (int x = 0; x < p.cpu.width; ++x) {
            const std::size_t i = std::size_t(y) * p.cpu.width + x;
            const bool a = p.gl.depth[i] < 1.0f, b = p.cpu.depth[i] < 1.0f;
            c.covered += b;
            const bool edge = at_edge(p.cpu, x, y, 1e-3f) || at_edge(p.gl, x, y, 1e-3f);
            if (a != b) {
                ++c.mismatch;
                c.mismatch_inside += !edge;
                continue;
            }
            if (!a) continue;
            const double dd = std::abs(double(p.gl.depth[i]) - double(p.cpu.depth[i]));
            int dc = 0;
            for (int k = 0; k < 3; ++k) dc = std::max(dc, std::abs(int(p.gl.rgba[i * 4 + k]) - int(p.cpu.rgba[i * 4 + k])));
            if (edge) continue;
            c.max_depth_inside = std::max(c.max_depth_inside, dd);
            c.max_color_inside = std::max(c.max_color_inside, dc);
            c.depth_far += dd > double(depth_tol);
            c.color_far += dc > color_tol;
        }
    return c;
}

}  // namespace

TEST_CASE("the GL isosurface renderer draws the CPU reference's image (QSS, S31, trilinear; perspective and orthographic)") {
    gl::OsmesaContext ctx;
    const spline::Volume<float> vol = marschner_lobb_volume(20);
    const double h = 2.0 / 19;
    Light light;
    light.direction = vec3(-0.3f, 0.5f, -1.0f);
    for (VolumeScheme s : {VolumeScheme::qss, VolumeScheme::s31, VolumeScheme::trilinear}) {
        const VolumeModel m = prepare_volume(vol, vec3(-1.0, -1.0, -1.0), vec3(h, h, h), s, 0.5f, vec3(0.9f, 0.7f, 0.4f), 2);
        gl::QuadricRenderer qr(ctx.api());
        gl::IsosurfaceRenderer iso(ctx.api());
        qr.set_primitives({});
        iso.add_volume(m);
        qr.add_pass(iso);
        for (bool ortho : {false, true}) {
            RenderOptions o;
            o.occlusion_min_overlap = 0.0f;  // (the quadric cull pass too, however sparse the primitives)
            o.width = 200;
            o.height = 160;
            const Camera cam = camera(ortho);
            qr.draw(cam, light, o);
            Pair p{qr.read(), render_volumes_cpu({&m}, cam, light, o, nullptr, 2)};
            const Compare c = compare(p, 2e-5f, 3);
            std::printf("[iso gl] %-9s %-12s: %ld covered, %ld coverage mismatches (%ld away from silhouettes), %zu of %zu elements drawn;"
                        " inside: max depth diff %.2e (%ld > 2e-5), max colour diff %d (%ld > 3 LSB)\n",
                        volume_scheme_name(s), ortho ? "orthographic" : "perspective", c.covered, c.mismatch, c.mismatch_inside,
                        iso.stats(0).elements, iso.stats(0).relevant, c.max_depth_inside, c.depth_far, c.max_color_inside, c.color_far);
            CHECK(c.covered > 8000);
            CHECK(c.mismatch_inside == 0);
            CHECK(c.mismatch <= c.covered / 100);
            CHECK(c.depth_far <= c.covered / 1000);
            // Trilinear normals jump across cell faces (C0): a hit within the clip pad of a face
            // (quadcast::spline::min_clip_pad) may take either cell's gradient.
            CHECK(c.color_far <= c.covered / (s == VolumeScheme::trilinear ? 100 : 500));
        }
    }
}

TEST_CASE("frustum culling skips cubes outside the view and leaves the image unchanged, with the element list from the CPU or the GPU") {
    gl::OsmesaContext ctx;
    const spline::Volume<float> vol = marschner_lobb_volume(24);
    const double h = 2.0 / 23;
    for (VolumeScheme scheme : {VolumeScheme::qss, VolumeScheme::trilinear}) {
        const VolumeModel m = prepare_volume(vol, vec3(-1.0, -1.0, -1.0), vec3(h, h, h), scheme, 0.5f, vec3(0.9f, 0.7f, 0.4f), 2, false);
        CHECK(m.coeffs.empty());
        gl::QuadricRenderer qr(ctx.api());
        gl::IsosurfaceRenderer iso(ctx.api());
        qr.set_primitives({});
        iso.add_volume(m);
        qr.add_pass(iso);
        Light light;
        RenderOptions o;
        o.occlusion_min_overlap = 0.0f;  // (the quadric cull pass too, however sparse the primitives)
        o.width = 160;
        o.height = 120;
        struct View {
            const char* name;
            Camera cam;
        };
        const View views[] = {
            // Close up: a part of the volume fills the view
            {"close up", qc_render_test::look_at(vec3(0.5, -0.9, 0.9), vec3(0.3, 0.0, 0.2), vec3(0.0, 0.0, 1.0), qc_render_test::perspective(35, 160.0 / 120.0, 0.05, 10))},
            // The eye inside the volume, the near plane through it
            {"eye inside", qc_render_test::look_at(vec3(0.1, -0.2, 0.3), vec3(0.8, 0.5, -0.2), vec3(0.0, 0.0, 1.0), qc_render_test::perspective(60, 160.0 / 120.0, 0.2, 10))},
            // Orthographic, the far plane through the volume
            {"orthographic", qc_render_test::look_at(vec3(1.5, -2.0, 1.2), vec3(0.2, 0.1, 0.0), vec3(0.0, 0.0, 1.0),
                                                     qc_render_test::orthographic(-0.6 * 4 / 3, 0.6 * 4 / 3, -0.6, 0.6, 0.5, 3.2), true)},
        };
        for (const View& view : views) {
            auto frame = [&](gl::IsosurfaceRenderer::ElementList list, bool culling, std::size_t batch) {
                iso.set_element_list(list);
                iso.set_frustum_culling(culling);
                iso.set_batch_elements(batch);
                qr.draw(view.cam, light, o);
                return std::make_pair(qr.read(), iso.stats(0));
            };
            using L = gl::IsosurfaceRenderer::ElementList;
            const auto [all, off] = frame(L::cpu, false, 65536);
            const auto [cpu, on] = frame(L::cpu, true, 65536);
            const auto [gpu, on_gpu] = frame(L::gpu, true, 65536);
            const auto [gpu_small, on_small] = frame(L::gpu, true, 100);  // many batches
            const auto [gpu_all, off_gpu] = frame(L::gpu, false, 65536);
            long covered = 0, differ[4] = {0, 0, 0, 0}, depth_differ[4] = {0, 0, 0, 0};
            const Image* imgs[4] = {&cpu, &gpu, &gpu_small, &gpu_all};
            for (std::size_t i = 0; i < all.depth.size(); ++i) {
                covered += all.depth[i] < 1.0f;
                for (int k = 0; k < 4; ++k) {
                    differ[k] += all.depth[i] != imgs[k]->depth[i] || all.rgba[4 * i] != imgs[k]->rgba[4 * i] || all.rgba[4 * i + 1] != imgs[k]->rgba[4 * i + 1] ||
                                 all.rgba[4 * i + 2] != imgs[k]->rgba[4 * i + 2];
                    depth_differ[k] += all.depth[i] != imgs[k]->depth[i];
                }
            }
            std::printf("[iso gl] %s, %s: CPU list %zu of %zu active cubes visible, %zu of %zu elements drawn, %zu octree nodes tested; GPU list %zu elements drawn "
                        "(%zu in batches of 100); %ld covered px, %ld / %ld / %ld / %ld differ (CPU list / GPU list / its batches / GPU list unculled)\n",
                        render::volume_scheme_name(scheme), view.name, on.visible, on.active, on.elements, off.elements, on.nodes_visited, on_gpu.elements,
                        on_small.elements, covered, differ[0], differ[1], differ[2], differ[3]);
            CAPTURE(view.name);
            CHECK(covered > 3000);
            CHECK(on.visible < on.active);
            CHECK(off.visible == off.active);
            CHECK(on.elements < off.elements);
            CHECK(on_gpu.elements < off.elements);
            CHECK(on_gpu.elements <= on.elements + on.elements / 100);  // (each element tested, not its cube; cells: the same boxes, with a margin)
            CHECK(on_small.elements == on_gpu.elements);
            CHECK(off_gpu.elements == off.elements);
            // The CPU list draws cubes (cells) nearest first, the GPU list in the octree's order: where
            // two elements hit a pixel at exactly the same depth (a root on their shared face), the
            // one drawn first keeps it, so the colours of such pixels may differ; no depth may.
            CHECK(differ[0] == 0);
            for (int k = 1; k < 4; ++k) {
                CHECK(depth_differ[k] == 0);
                CHECK(differ[k] <= covered / 500);
            }
        }
    }
}

TEST_CASE("clip_outside culls only boxes whose every point lies outside the clip volume (long double)") {
    // Random boxes and perspective cameras: where the float test says outside, 300 random points
    // of the box, mapped in long double by the same matrix, all lie beyond one clip plane; where a
    // point of the box lies inside the clip volume, it never says outside.
    std::mt19937 rng(17);
    std::uniform_real_distribution<double> u(-1.0, 1.0), u01(0.0, 1.0);
    int outside = 0, inside = 0;
    for (int it = 0; it < 20000; ++it) {
        const Camera cam = qc_render_test::look_at(vec3(u(rng), u(rng), u(rng)) * 3.0, vec3(u(rng), u(rng), u(rng)) * 0.3, vec3(0.0, 0.0, 1.0),
                                                   qc_render_test::perspective(20 + 80 * u01(rng), 4.0 / 3.0, 0.05 + u01(rng), 3 + 5 * u01(rng)));
        const Mat4<float> vp = cam.projection * cam.view;
        const Vec3<double> lo = vec3(u(rng), u(rng), u(rng)) * 4.0, size = vec3(u01(rng), u01(rng), u01(rng)) * (u01(rng) < 0.5 ? 0.05 : 1.5);
        std::array<Vec4<float>, 8> c{};
        std::array<Vec3<double>, 8> corner{};
        for (int k = 0; k < 8; ++k) {
            corner[k] = lo + vec3(k & 1 ? size[0] : 0.0, k & 2 ? size[1] : 0.0, k & 4 ? size[2] : 0.0);
            c[static_cast<std::size_t>(k)] = vp * vec4(float(corner[k][0]), float(corner[k][1]), float(corner[k][2]), 1.0f);
        }
        const bool out = spline::clip_outside(c);
        bool any_inside = false;
        for (int j = 0; j < 300 && !any_inside; ++j) {
            const long double a = j == 0 ? 0.5L : u01(rng), b = j == 0 ? 0.5L : u01(rng), e = j == 0 ? 0.5L : u01(rng);
            const long double x[4] = {static_cast<long double>(float(lo[0])) + a * static_cast<long double>(float(lo[0] + size[0]) - float(lo[0])),
                                      static_cast<long double>(float(lo[1])) + b * static_cast<long double>(float(lo[1] + size[1]) - float(lo[1])),
                                      static_cast<long double>(float(lo[2])) + e * static_cast<long double>(float(lo[2] + size[2]) - float(lo[2])), 1.0L};
            long double q[4] = {0, 0, 0, 0};
            for (int r = 0; r < 4; ++r)
                for (int col = 0; col < 4; ++col) q[r] += static_cast<long double>(vp[col][r]) * x[col];
            any_inside = std::fabs(q[0]) <= q[3] && std::fabs(q[1]) <= q[3] && std::fabs(q[2]) <= q[3];
        }
        CAPTURE(it);
        if (out) {
            ++outside;
            CHECK_FALSE(any_inside);
        } else if (any_inside) {
            ++inside;
        }
    }
    std::printf("[iso gl] clip_outside: %d boxes outside, %d with a point inside, none of those culled\n", outside, inside);
    CHECK(outside > 2000);
    CHECK(inside > 2000);
}

TEST_CASE("isosurfaces and quadrics share the depth buffer; deferred shading draws the forward image") {
    gl::OsmesaContext ctx;
    const spline::Volume<float> vol = marschner_lobb_volume(16);
    const double h = 2.0 / 15;
    const VolumeModel m = prepare_volume(vol, vec3(-1.0, -1.0, -1.0), vec3(h, h, h), VolumeScheme::s31, 0.5f, vec3(0.9f, 0.7f, 0.4f), 2, false);
    gl::QuadricRenderer qr(ctx.api());
    gl::IsosurfaceRenderer iso(ctx.api());
    // A sphere outside the volume, in front of a part of the surface
    qr.set_primitives({qc_render_test::sphere(vec3(0.55f, -1.05f, 1.15f), 0.3f, vec3(0.2f, 0.4f, 0.9f))});
    iso.add_volume(m);
    qr.add_pass(iso);
    Light light;
    light.direction = vec3(-0.3f, 0.5f, -1.0f);
    RenderOptions o;
    o.occlusion_min_overlap = 0.0f;  // (the quadric cull pass too, however sparse the primitives)
    o.width = 160;
    o.height = 128;
    const Camera cam = camera(false);
    qr.draw(cam, light, o);
    const Image fwd = qr.read();
    o.deferred = true;
    qr.draw(cam, light, o);
    const Image def = qr.read();
    long blue = 0, warm = 0, depth_diff = 0, color_diff = 0;
    for (std::size_t i = 0; i < fwd.depth.size(); ++i) {
        const std::uint8_t* c = &fwd.rgba[i * 4];
        if (fwd.depth[i] < 1.0f) (c[2] > c[0] ? blue : warm) += 1;
        depth_diff += fwd.depth[i] != def.depth[i];
        for (int k = 0; k < 3; ++k) color_diff += std::abs(int(c[k]) - int(def.rgba[i * 4 + k])) > 1;
    }
    std::printf("[iso gl] mixed scene: %ld sphere px, %ld isosurface px; deferred vs forward: %ld depth, %ld colour differences\n", blue, warm, depth_diff, color_diff);
    CHECK(blue > 500);
    CHECK(warm > 3000);
    CHECK(depth_diff == 0);
    CHECK(color_diff == 0);
}

namespace {

/// A pass that draws nothing and counts its draws, with a revision the test sets.
struct CountingPass final : gl::ScenePass {
    std::uint64_t rev = 0;
    int draws = 0;
    void draw(const Camera&, const Light&, const RenderOptions&, bool) override { ++draws; }
    void bounds(Vec3<double>& lo, Vec3<double>& hi) const override {
        lo = vec3(-1.0, -1.0, -1.0);
        hi = vec3(1.0, 1.0, 1.0);
    }
    std::uint64_t revision() const override { return rev; }
};

}  // namespace

TEST_CASE("the shadow map kept across frames gives the images of a map drawn in every frame, and is drawn again when what it shows changes") {
    // One renderer keeps its shadow map (RenderOptions::shadow_map_reuse, the default), the
    // other draws it in every frame; both draw the same quadrics and isosurface pass, deferred
    // with shadows and outlines, through a sequence of frames that move the camera and change
    // the light, the primitives, the options and the passes. Every frame: the same pixels, and
    // the map kept exactly where nothing it depends on changed.
    gl::OsmesaContext ctx;
    const spline::Volume<float> vol = marschner_lobb_volume(16);
    const double h = 2.0 / 15;
    const VolumeModel m05 = prepare_volume(vol, vec3(-1.0, -1.0, -1.0), vec3(h, h, h), VolumeScheme::qss, 0.5f, vec3(0.9f, 0.7f, 0.4f), 2, false);
    const VolumeModel m04 = prepare_volume(vol, vec3(-1.0, -1.0, -1.0), vec3(h, h, h), VolumeScheme::qss, 0.4f, vec3(0.5f, 0.8f, 0.4f), 2, false);
    gl::QuadricRenderer keep(ctx.api()), every(ctx.api());
    gl::IsosurfaceRenderer iso_keep(ctx.api()), iso_every(ctx.api());
    // Spheres over the surface (their shadows fall on it) and beside it
    std::vector<Primitive> prims;
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> u(-1.1f, 1.1f);
    for (int i = 0; i < 40; ++i) prims.push_back(qc_render_test::sphere(vec3(u(rng), u(rng), 1.0f + 0.4f * u(rng)), 0.12f, vec3(0.2f, 0.4f, 0.9f)));
    std::vector<Primitive> moved = prims;
    moved[0] = qc_render_test::sphere(vec3(0.0f, 0.0f, 1.3f), 0.35f, vec3(0.9f, 0.2f, 0.2f));
    for (gl::QuadricRenderer* r : {&keep, &every}) r->set_primitives(prims);
    iso_keep.add_volume(m05);
    iso_every.add_volume(m05);
    keep.add_pass(iso_keep);
    every.add_pass(iso_every);
    Light light;
    light.direction = vec3(-0.3f, 0.5f, -1.0f);
    RenderOptions o;
    o.width = 200;
    o.height = 160;
    o.deferred = o.shadows = o.silhouettes = true;
    Camera cam = camera(false);
    const Camera near_cam = camera(false, 3.2), ortho_cam = camera(true);
    CountingPass counting;
    struct Step {
        const char* what;
        std::function<void()> change;
        bool kept;
    };
    const std::vector<Step> steps = {
        {"first frame", [] {}, false},
        {"the same frame", [] {}, true},
        {"the camera moved", [&] { cam = near_cam; }, true},
        {"an orthographic camera", [&] { cam = ortho_cam; }, true},
        {"the light turned", [&] { light.direction = vec3(0.4f, 0.3f, -1.0f); }, false},
        {"the same frame", [] {}, true},
        {"a sphere moved and grown", [&] { keep.set_primitives(moved); every.set_primitives(moved); }, false},
        {"the same frame", [] {}, true},
        {"the map's size", [&] { o.shadow_map_size = 1024; }, false},
        {"back-face culling off", [&] { o.culling = false; }, false},
        {"the same frame", [] {}, true},
        {"the isovalue (the volume added again)", [&] {
             for (gl::IsosurfaceRenderer* i : {&iso_keep, &iso_every}) {
                 i->clear();
                 i->add_volume(m04);
             }
         }, false},
        {"the same frame", [] {}, true},
        {"a pass setting", [&] { iso_keep.set_tetrahedron_culling(false); iso_every.set_tetrahedron_culling(false); }, false},
        {"the same frame", [] {}, true},
        {"a pass without a revision", [&] { keep.add_pass(counting); }, false},
        {"the same frame", [] {}, false},
        {"that pass's revision set", [&] { counting.rev = 7; }, false},
        {"the same frame", [] {}, true},
        {"that pass's revision changed", [&] { counting.rev = 8; }, false},
        {"the passes cleared and added again", [&] { keep.clear_passes(); keep.add_pass(iso_keep); keep.add_pass(counting); }, false},
        {"the same frame", [] {}, true},
        {"a renderer setting", [&] { keep.set_slab_quads(false); every.set_slab_quads(false); }, false},
        {"the same frame", [] {}, true},
    };
    RenderOptions off = o;
    int reused = 0;
    for (std::size_t k = 0; k < steps.size(); ++k) {
        steps[k].change();
        off = o;
        off.shadow_map_reuse = false;
        const int draws_before = counting.draws;
        keep.draw(cam, light, o);
        every.draw(cam, light, off);
        const qc_render_test::ImageDiff d = qc_render_test::image_diff(keep.read(), every.read());
        CAPTURE(k);
        const std::string what = steps[k].what;
        CAPTURE(what);
        CHECK(d.covered > 3000);
        CHECK(d.coverage_diff == 0);
        CHECK(d.color_diff == 0);
        CHECK(d.depth_diff == 0);
        CHECK(keep.reused_shadow_map() == steps[k].kept);
        CHECK_FALSE(every.reused_shadow_map());
        // A pass draws in the shadow map's pass only where the map is drawn
        if (counting.draws > 0) CHECK(counting.draws - draws_before == (steps[k].kept ? 1 : 2));
        reused += keep.reused_shadow_map();
    }
    std::printf("[shadow map reuse] %d of %zu frames kept the map; every frame's pixels equal a map drawn in every frame\n", reused, steps.size());
}

TEST_CASE("the compute pre-pass of the coefficients draws the vertex stage's image bit for bit") {
    gl::OsmesaContext ctx;
    const spline::Volume<float> vol = marschner_lobb_volume(16);
    const double h = 2.0 / 15;
    Light light;
    light.direction = vec3(-0.3f, 0.5f, -1.0f);
    for (VolumeScheme s : {VolumeScheme::qss, VolumeScheme::s31}) {
        const VolumeModel m = prepare_volume(vol, vec3(-1.0, -1.0, -1.0), vec3(h, h, h), s, 0.5f, vec3(0.9f, 0.7f, 0.4f), 2, false);
        gl::QuadricRenderer qr(ctx.api());
        gl::IsosurfaceRenderer iso(ctx.api());
        qr.set_primitives({});
        iso.add_volume(m);
        qr.add_pass(iso);
        for (bool ortho : {false, true}) {
            RenderOptions o;
            o.occlusion_min_overlap = 0.0f;  // (the quadric cull pass too, however sparse the primitives)
            o.width = 160;
            o.height = 128;
            const Camera cam = camera(ortho);
            using Stage = gl::IsosurfaceRenderer::CoefficientStage;
            iso.set_pre_pass_budget(std::size_t(64) << 20);
            iso.set_coefficient_stage(Stage::vertex);
            qr.draw(cam, light, o);
            CHECK_FALSE(iso.stats(0).pre_pass);
            const Image a = qr.read();
            iso.set_coefficient_stage(Stage::compute);
            qr.draw(cam, light, o);
            CHECK(iso.stats(0).pre_pass);
            const Image b = qr.read();
            // The default: the pre-pass for S31 (its list is far below the budget), the vertex stage for QSS
            iso.set_coefficient_stage(Stage::automatic);
            qr.draw(cam, light, o);
            CHECK(iso.stats(0).pre_pass == (s == VolumeScheme::s31));
            const std::size_t bytes = iso.stats(0).elements * 20 * sizeof(float);
            CHECK(bytes <= iso.pre_pass_budget());
            const Image c = qr.read();
            // Above the budget, the vertex stage
            iso.set_pre_pass_budget(bytes - 1);
            qr.draw(cam, light, o);
            CHECK_FALSE(iso.stats(0).pre_pass);
            iso.set_pre_pass_budget(bytes);
            qr.draw(cam, light, o);
            CHECK(iso.stats(0).pre_pass == (s == VolumeScheme::s31));
            const Image d = qr.read();
            CHECK(d.rgba == a.rgba);
            CHECK(d.depth == a.depth);
            long covered = 0;
            for (float d : a.depth) covered += d < 1.0f;
            std::printf("[iso gl] compute pre-pass, %s %s: %ld covered px, images %s\n", volume_scheme_name(s), ortho ? "orthographic" : "perspective",
                        covered, a.rgba == b.rgba && a.depth == b.depth && a.rgba == c.rgba && a.depth == c.depth ? "identical" : "DIFFER");
            CHECK(covered > 3000);
            CHECK(a.rgba == b.rgba);
            CHECK(a.depth == b.depth);
            CHECK(a.rgba == c.rgba);
            CHECK(a.depth == c.depth);
        }
    }
}

TEST_CASE("occlusion culling of isosurface tetrahedra leaves every image unchanged and culls the hidden ones") {
    // Marschner-Lobb's rings stack several sheets along most rays. Every image with occlusion
    // culling on (3 and 8 phases; element lists from the CPU, nearest first, and from the GPU, in
    // the octree's order) equals the one with it off, bit for bit (colour and depth): forward,
    // deferred with shadows and silhouettes, a sphere in front, the eye inside the volume,
    // orthographic; QSS and S31 (coefficients in the vertex stage and in the pre-pass), trilinear.
    gl::OsmesaContext ctx;
    const spline::Volume<float> vol = marschner_lobb_volume(28);
    const double h = 2.0 / 27;
    Light light;
    light.direction = vec3(-0.3f, 0.5f, -1.0f);
    struct View {
        const char* name;
        Camera cam;
    };
    const View views[] = {
        {"whole", camera(false)},
        {"close up", qc_render_test::look_at(vec3(0.5, -0.9, 0.9), vec3(0.3, 0.0, 0.2), vec3(0.0, 0.0, 1.0), qc_render_test::perspective(35, 200.0 / 160.0, 0.05, 10))},
        {"eye inside", qc_render_test::look_at(vec3(0.1, -0.2, 0.3), vec3(0.8, 0.5, -0.2), vec3(0.0, 0.0, 1.0), qc_render_test::perspective(60, 200.0 / 160.0, 0.2, 10))},
        {"orthographic", camera(true)},
    };
    for (VolumeScheme s : {VolumeScheme::qss, VolumeScheme::s31, VolumeScheme::trilinear}) {
        // (trilinear: a finer grid, for as many elements as the splines' tetrahedra)
        const spline::Volume<float> vs = s == VolumeScheme::trilinear ? marschner_lobb_volume(64) : vol;
        const double hs = s == VolumeScheme::trilinear ? 2.0 / 63 : h;
        const VolumeModel m = prepare_volume(vs, vec3(-1.0, -1.0, -1.0), vec3(hs, hs, hs), s, 0.5f, vec3(0.9f, 0.7f, 0.4f), 2, false);
        gl::QuadricRenderer qr(ctx.api());
        gl::IsosurfaceRenderer iso(ctx.api());
        qr.set_primitives({qc_render_test::sphere(vec3(0.3f, -0.6f, 0.7f), 0.25f, vec3(0.2f, 0.4f, 0.9f))});
        iso.add_volume(m);
        qr.add_pass(iso);
        for (const View& view : views)
            for (bool deferred : {false, true})
                for (auto list : {gl::IsosurfaceRenderer::ElementList::cpu, gl::IsosurfaceRenderer::ElementList::gpu}) {
                    RenderOptions o;
                    o.occlusion_min_overlap = 0.0f;  // (the quadric cull pass too, however sparse the primitives)
                    o.occlusion_reuse = false;       // (the phases themselves; reuse: the next test)
                    o.width = 200;
                    o.height = 160;
                    o.deferred = deferred;
                    o.shadows = deferred;
                    o.silhouettes = deferred;
                    iso.set_element_list(list);
                    iso.set_coefficient_stage(deferred ? gl::IsosurfaceRenderer::CoefficientStage::compute : gl::IsosurfaceRenderer::CoefficientStage::vertex);
                    o.occlusion_culling = false;
                    qr.draw(view.cam, light, o);
                    const Image off = qr.read();
                    const gl::IsoDrawStats st_off = iso.stats(0);
                    o.occlusion_culling = true;
                    for (int phases : {3, 8}) {
                        o.occlusion_phases = phases;
                        qr.draw(view.cam, light, o);
                        const Image on = qr.read();
                        const gl::IsoDrawStats st = iso.stats(0);
                        long covered = 0, differ = 0;
                        for (std::size_t i = 0; i < off.depth.size(); ++i) {
                            covered += off.depth[i] < 1.0f;
                            differ += off.depth[i] != on.depth[i] || off.rgba[4 * i] != on.rgba[4 * i] || off.rgba[4 * i + 1] != on.rgba[4 * i + 1] ||
                                      off.rgba[4 * i + 2] != on.rgba[4 * i + 2];
                        }
                        const std::size_t later = st.elements - st.elements * 1 / ((1u << phases) - 1);
                        std::printf("[iso gl] occlusion, %s %s%s, %s list, %d phases: %zu elements, %d phases drawn, %zu culled behind earlier phases (of about %zu "
                                    "in later phases); %ld covered px, %ld differ\n",
                                    render::volume_scheme_name(s), view.name, deferred ? " deferred+shadows" : "",
                                    list == gl::IsosurfaceRenderer::ElementList::cpu ? "CPU" : "GPU", phases, st.elements, st.phases, st.occluded, later, covered, differ);
                        CAPTURE(view.name);
                        CAPTURE(deferred);
                        CAPTURE(phases);
                        CHECK(covered > 5000);
                        CHECK(differ == 0);
                        CHECK(st_off.phases == 1);
                        CHECK(st.phases == phases);
                        // Culling works where large elements stack: close up, most of the later phases' are hidden
                        if (std::string(view.name) == "close up") CHECK(st.occluded * (s == VolumeScheme::trilinear ? 2 : 4) > later * (s == VolumeScheme::trilinear ? 1 : 3));
                    }
                }
    }
}

TEST_CASE("reusing the last frame's shown set of isosurface elements changes no pixel as the camera moves, and draws fewer elements") {
    // Frames repeat in one renderer (RenderOptions::occlusion_reuse, the default, CPU list): each
    // draws the elements that passed the last frame's test first, then tests every element
    // against that depth and draws the rest that pass. Every frame, while the camera jumps
    // between views and back, against a renderer without occlusion culling, bit for bit; forward
    // and deferred with shadows and silhouettes (the shadow map's set is its own, by framebuffer),
    // coefficients in the vertex stage and in the pre-pass; QSS, S31, trilinear.
    gl::OsmesaContext ctx;
    const spline::Volume<float> vol = marschner_lobb_volume(28);
    const double h = 2.0 / 27;
    Light light;
    light.direction = vec3(-0.3f, 0.5f, -1.0f);
    const Camera whole = camera(false), ortho = camera(true);
    const Camera close = qc_render_test::look_at(vec3(0.5, -0.9, 0.9), vec3(0.3, 0.0, 0.2), vec3(0.0, 0.0, 1.0), qc_render_test::perspective(35, 200.0 / 160.0, 0.05, 10));
    const Camera inside = qc_render_test::look_at(vec3(0.1, -0.2, 0.3), vec3(0.8, 0.5, -0.2), vec3(0.0, 0.0, 1.0), qc_render_test::perspective(60, 200.0 / 160.0, 0.2, 10));
    const Camera turned = qc_render_test::look_at(vec3(1.6, -1.5, 2.6), vec3(0.0, 0.0, 0.0), vec3(0.0, 0.0, 1.0), qc_render_test::perspective(40, 200.0 / 160.0, 0.5, 10));
    const Camera* frames[] = {&whole, &whole, &whole, &turned, &close, &close, &inside, &ortho, &ortho, &whole};
    for (VolumeScheme s : {VolumeScheme::qss, VolumeScheme::s31, VolumeScheme::trilinear}) {
        const spline::Volume<float> vs = s == VolumeScheme::trilinear ? marschner_lobb_volume(64) : vol;
        const double hs = s == VolumeScheme::trilinear ? 2.0 / 63 : h;
        const VolumeModel m = prepare_volume(vs, vec3(-1.0, -1.0, -1.0), vec3(hs, hs, hs), s, 0.5f, vec3(0.9f, 0.7f, 0.4f), 2, false);
        gl::QuadricRenderer qr(ctx.api()), plain(ctx.api());
        gl::IsosurfaceRenderer iso(ctx.api()), iso_plain(ctx.api());
        for (gl::QuadricRenderer* r : {&qr, &plain}) r->set_primitives({qc_render_test::sphere(vec3(0.3f, -0.6f, 0.7f), 0.25f, vec3(0.2f, 0.4f, 0.9f))});
        iso.add_volume(m);
        iso_plain.add_volume(m);
        qr.add_pass(iso);
        plain.add_pass(iso_plain);
        for (bool deferred : {false, true}) {
            iso.set_coefficient_stage(deferred ? gl::IsosurfaceRenderer::CoefficientStage::compute : gl::IsosurfaceRenderer::CoefficientStage::vertex);
            RenderOptions o;
            o.width = 200;
            o.height = 160;
            o.deferred = o.shadows = o.silhouettes = deferred;
            RenderOptions off = o;
            off.occlusion_culling = false;
            int reused = 0, alone = 0;
            std::size_t drawn_reuse = 0, drawn_phases = 0;
            for (std::size_t f = 0; f < std::size(frames); ++f) {
                qr.draw(*frames[f], light, o);
                const Image on = qr.read();
                const gl::IsoDrawStats st = iso.stats(0);
                plain.draw(*frames[f], light, off);
                const qc_render_test::ImageDiff d = qc_render_test::image_diff(on, plain.read());
                CAPTURE(render::volume_scheme_name(s));
                CAPTURE(deferred);
                CAPTURE(f);
                CHECK(d.covered > 5000);
                CHECK(d.coverage_diff == 0);
                CHECK(d.color_diff == 0);
                CHECK(d.depth_diff == 0);
                // A frame whose view (and the sphere's depth under the pass) is the last frame's
                // draws the set that frame's test chose, alone, untested (the first frame of all
                // records a set after its phases); any other frame after the first reuses the set
                // and tests every element.
                const bool same_view = f > 0 && frames[f] == frames[f - 1];
                CHECK(st.unchanged_view == same_view);
                CHECK(st.phases == (st.unchanged_view ? 1 : st.reused ? 2 : 3));
                if (f > 0) CHECK(st.reused);
                reused += st.reused;
                alone += st.unchanged_view;
                if (f == 0) drawn_phases = st.elements - st.occluded;
                if (f == 1) drawn_reuse = st.alone;
            }
            std::printf("[iso gl] reuse, %s%s: %d of %zu frames reused the shown set, %d of them drew it alone; the first view drew %zu elements in 3 phases, "
                        "%zu as the set alone\n",
                        render::volume_scheme_name(s), deferred ? " deferred+shadows" : "", reused, std::size(frames), alone, drawn_phases, drawn_reuse);
            CHECK(drawn_reuse < drawn_phases);
            CHECK(alone == 4);
        }
        // Switched off, or with the GPU list: phases only
        RenderOptions o;
        o.width = 200;
        o.height = 160;
        o.occlusion_reuse = false;
        qr.draw(whole, light, o);
        qr.draw(whole, light, o);
        CHECK_FALSE(iso.stats(0).reused);
        o.occlusion_reuse = true;
        iso.set_element_list(gl::IsosurfaceRenderer::ElementList::gpu);
        qr.draw(whole, light, o);
        qr.draw(whole, light, o);
        CHECK_FALSE(iso.stats(0).reused);
    }
}

TEST_CASE("a volume's shown set is drawn alone only while its view and the depth under it stay the same, and every picture stays exact") {
    // The quadric renderer tells its passes what lies under them (ScenePass::frame_before): its
    // view, primitives and options, the target, the earlier passes' revisions. The isosurface
    // renderer draws a set alone where that and its own view are the ones the set was tested
    // under. Frames where the sphere in front of the surface moves, the isosurface renderer's
    // settings or the back-face option change, and draws into a host's framebuffer (nothing
    // known under them) in between, against renderers without occlusion culling, bit for bit.
    gl::OsmesaContext ctx;
    const spline::Volume<float> vol = marschner_lobb_volume(28);
    const double h = 2.0 / 27;
    const VolumeModel m = prepare_volume(vol, vec3(-1.0, -1.0, -1.0), vec3(h, h, h), VolumeScheme::s31, 0.5f, vec3(0.9f, 0.7f, 0.4f), 2, false);
    Light light;
    light.direction = vec3(-0.3f, 0.5f, -1.0f);
    const Camera cam = camera(false);
    gl::QuadricRenderer qr(ctx.api()), plain(ctx.api());
    gl::IsosurfaceRenderer iso(ctx.api()), iso_plain(ctx.api());
    iso.add_volume(m);
    iso_plain.add_volume(m);
    qr.add_pass(iso);
    plain.add_pass(iso_plain);
    const std::vector<render::Primitive> near_sphere{qc_render_test::sphere(vec3(0.3f, -0.6f, 0.7f), 0.25f, vec3(0.2f, 0.4f, 0.9f))};
    const std::vector<render::Primitive> moved_sphere{qc_render_test::sphere(vec3(-0.2f, -0.7f, 0.6f), 0.35f, vec3(0.2f, 0.4f, 0.9f))};
    RenderOptions o;
    o.width = 200;
    o.height = 160;
    int host_draws = 0;
    const auto frame = [&](const char* what, bool alone_expected) {
        RenderOptions off = o;
        off.occlusion_culling = false;
        qr.draw(cam, light, o);
        plain.draw(cam, light, off);
        const qc_render_test::ImageDiff d = qc_render_test::image_diff(qr.read(), plain.read());
        const std::string label = what;
        CAPTURE(label);
        CHECK(d.covered > 5000);
        CHECK(d.coverage_diff == 0);
        CHECK(d.color_diff == 0);
        CHECK(d.depth_diff == 0);
        CHECK(iso.stats(0).unchanged_view == alone_expected);
        if (alone_expected) CHECK(iso.stats(0).alone < iso.stats(0).elements);
    };
    for (gl::QuadricRenderer* r : {&qr, &plain}) r->set_primitives(near_sphere);
    frame("first", false);
    frame("same view", true);
    frame("same view again", true);
    for (gl::QuadricRenderer* r : {&qr, &plain}) r->set_primitives(moved_sphere);
    frame("the sphere moved", false);
    frame("after the sphere moved", true);
    iso.set_tetrahedron_culling(true);  // (the same setting: still a new revision)
    frame("isosurface setting", false);
    frame("after the isosurface setting", true);
    o.culling = !o.culling;
    frame("back-face culling switched", false);
    frame("after the switch", true);
    // A host's framebuffer: nothing is known under the pass, so every draw tests
    GLuint tex[2] = {0, 0};
    const GLuint fbo = gl::make_framebuffer(ctx.api(), o.width, o.height, tex, "test");
    const gl::Api& api = ctx.api();
    for (int k = 0; k < 2; ++k) {
        const float black[4] = {0.0f, 0.0f, 0.0f, 1.0f};
        qc_gl_test::begin_host_frame(api, fbo, o.width, o.height, black);
        iso.draw(cam, light, o, false);
        api.BindFramebuffer(GL_FRAMEBUFFER, 0);
        CHECK_FALSE(iso.stats(0).unchanged_view);
        CHECK(iso.stats(0).reused == (k > 0));
        ++host_draws;
    }
    api.DeleteFramebuffers(1, &fbo);
    api.DeleteTextures(2, tex);
    // The renderer's own target keeps its set (the host's draws listed the elements in their own order)
    frame("after the host's draws", true);
    {
        // A quadric renderer made anew, as many setter calls, other primitives (its GL names may
        // be the old one's): the depth under the pass is not the old renderer's
        std::optional<gl::QuadricRenderer> a, b;
        a.emplace(ctx.api());
        a->set_primitives(near_sphere);
        a->add_pass(iso);
        a->draw(cam, light, o);
        a->draw(cam, light, o);
        CHECK(iso.stats(0).unchanged_view);
        a.reset();
        b.emplace(ctx.api());
        b->set_primitives(moved_sphere);
        b->add_pass(iso);
        b->draw(cam, light, o);
        CHECK_FALSE(iso.stats(0).unchanged_view);
        RenderOptions off = o;
        off.occlusion_culling = false;
        plain.draw(cam, light, off);
        const qc_render_test::ImageDiff d = qc_render_test::image_diff(b->read(), plain.read());
        CHECK(d.coverage_diff == 0);
        CHECK(d.color_diff == 0);
        CHECK(d.depth_diff == 0);
    }
    iso.set_skip_unchanged_view_test(false);
    frame("skip turned off", false);
    CHECK(host_draws == 2);
}

TEST_CASE("tet_occlusion_bound, cell_occlusion_bound: every hit the fragment stage can find lies behind the floor and inside the rectangle (long double)") {
    // Random cubes, tetrahedra and cameras (perspective and orthographic, the eye near and far,
    // anisotropic spacing); points of the tetrahedron grown by the fragment stage's pad at that
    // point (barycentric coordinates down to -pad, pad = clip_pad of the point's own ray), mapped
    // in long double: their window depth is never below the float floor, their NDC position
    // never outside the float rectangle.
    std::mt19937 rng(23);
    std::uniform_real_distribution<double> u(-1.0, 1.0), u01(0.0, 1.0);
    long points = 0, bounded = 0;
    long double least_gap = 1e9L;
    for (int it = 0; it < 4000; ++it) {
        const bool ortho = it % 4 == 3;
        // (every other volume far from the world origin, as scanner coordinates are)
        const Vec3<double> spacing = vec3(0.3 + u01(rng), 0.3 + u01(rng), 0.3 + u01(rng)), origin = vec3(u(rng), u(rng), u(rng)) * (it % 2 ? 3000.0 : 20.0);
        const Vec3<float> c = vec3(float(std::floor(40 * u01(rng))), float(std::floor(40 * u01(rng))), float(std::floor(40 * u01(rng))));
        const Vec3<double> centre = origin + cmul(spacing, cast<double>(c));
        const double dist = it % 3 == 0 ? 1.0 + 3 * u01(rng) : 5 + 400 * u01(rng);
        const Vec3<double> eye = centre + normalize(vec3(u(rng), u(rng), u(rng))) * dist;
        const Vec3<double> target = centre + vec3(u(rng), u(rng), u(rng)) * 2.0;
        const double near = ortho ? -5.0 : 0.05 + 0.5 * u01(rng), far = dist * 3 + 50;
        const double half = dist * 0.4;
        const Camera cam = ortho ? qc_render_test::look_at(eye, target, vec3(0.0, 0.0, 1.0), qc_render_test::orthographic(-half, half, -half * 0.75, half * 0.75, near, far), true)
                                 : qc_render_test::look_at(eye, target, vec3(0.0, 0.0, 1.0), qc_render_test::perspective(20 + 60 * u01(rng), 4.0 / 3.0, near, far));
        const int t = std::uniform_int_distribution<int>(0, spline::tets_per_cube - 1)(rng);
        const auto tv = spline::tet_vertices(t);
        std::array<Vec3<float>, 4> corners{};
        for (int k = 0; k < 4; ++k) corners[k] = vec3(float(tv[k][0]), float(tv[k][1]), float(tv[k][2]));
        Vec3<float> eye_index{}, origin_f = vec3(float(origin[0]), float(origin[1]), float(origin[2])), spacing_f = vec3(float(spacing[0]), float(spacing[1]), float(spacing[2]));
        for (int a = 0; a < 3; ++a) eye_index[a] = float((eye[a] - origin[a]) / spacing[a]);
        const Vec3<float> vz_row = vec3(cam.view[0][2], cam.view[1][2], cam.view[2][2]);
        const Vec4<float> pz = vec4(cam.projection[2][2], cam.projection[3][2], cam.projection[2][3], cam.projection[3][3]);
        const float pixel = 2.0f / (cam.projection[1][1] * 600.0f);
        const Mat4<float> vp = cam.projection * cam.view;
        // (every third case a trilinear cell: lower corner c, s = 1, grown by 1 + 2 pad)
        const bool cell = it % 3 == 1;
        const spline::OcclusionBound<float> b = cell ? spline::cell_occlusion_bound(c, eye_index, cam.eye, -vz_row, origin_f, spacing_f, vp, vz_row, pz, pixel, ortho)
                                                     : spline::tet_occlusion_bound(c, corners, eye_index, cam.eye, -vz_row, origin_f, spacing_f, vp, vz_row, pz, pixel, ortho);
        const long double s_el = cell ? 1.0L : 0.5L, k_pad = cell ? 2.0L : 4.0L;
        // The camera as the renderer's rounded uniforms define it, in long double
        const long double ex = cam.eye[0], ey = cam.eye[1], ez = cam.eye[2];
        for (int j = 0; j < 60; ++j) {
            // A point of the tetrahedron, then pushed out to barycentric -pad on random faces
            long double w[4], sum = 0;
            for (long double& x : w) sum += (x = static_cast<long double>(u01(rng)) + (j % 3 == 0 ? 0.0L : 1e-9L));
            for (long double& x : w) x /= sum;
            long double p[3] = {0, 0, 0};
            if (cell)  // a point of the cell [0, 1]^3 (some on its faces)
                for (int a = 0; a < 3; ++a) p[a] = static_cast<long double>(c[a]) + (j % 4 == 0 && a == j % 3 ? static_cast<long double>(j % 2) : static_cast<long double>(u01(rng)));
            else
                for (int k = 0; k < 4; ++k)
                    for (int a = 0; a < 3; ++a) p[a] += w[k] * (static_cast<long double>(c[a]) + 0.5L * corners[k][a]);
            // the pad at this point (the fragment stage's, from the ray through it)
            long double vlen = 0;
            for (int a = 0; a < 3; ++a) {
                const long double va = (ortho ? static_cast<long double>(-vz_row[a]) / static_cast<long double>(spacing_f[a]) : p[a] - eye_index[a]) / s_el;
                vlen += va * va;
            }
            const long double pad = std::max(1.0L / 65536, static_cast<long double>(pixel) / 32 * std::sqrt(vlen));
            // grow: barycentric λ' = (1 + 4 pad) λ - pad, the scaled tetrahedron about its centroid;
            // a cell [-pad, 1 + pad]^3, the box scaled by 1 + 2 pad about its centre
            long double cen[3] = {0, 0, 0};
            for (int a = 0; a < 3; ++a)
                if (cell) cen[a] = static_cast<long double>(c[a]) + 0.5L;
                else
                    for (int k = 0; k < 4; ++k) cen[a] += 0.25L * (static_cast<long double>(c[a]) + 0.5L * corners[k][a]);
            long double xi[3], x[3];
            for (int a = 0; a < 3; ++a) {
                xi[a] = cen[a] + (1 + k_pad * pad) * (p[a] - cen[a]);
                x[a] = static_cast<long double>(origin_f[a]) + static_cast<long double>(spacing_f[a]) * xi[a];
            }
            // view z as the fragment stage has it (perspective: λ vz from the eye in index space;
            // orthographic: from the camera plane through the world eye), window depth; clip position
            long double z = 0;
            for (int a = 0; a < 3; ++a)
                z += static_cast<long double>(vz_row[a]) * (ortho ? x[a] - (a == 0 ? ex : a == 1 ? ey : ez) : static_cast<long double>(spacing_f[a]) * (xi[a] - eye_index[a]));
            long double q[4] = {0, 0, 0, 0};
            const long double xh[4] = {x[0], x[1], x[2], 1.0L};
            for (int r = 0; r < 4; ++r)
                for (int col = 0; col < 4; ++col) q[r] += static_cast<long double>(vp[col][r]) * xh[col];
            if (!ortho && !(z < -near)) continue;  // (not between the near and far planes: no fragment)
            const long double depth = window_depth(z, 1.0L, Vec4<long double>{{pz[0], pz[1], pz[2], pz[3]}});
            if (depth < 0 || depth > 1) continue;
            ++points;
            CAPTURE(it);
            CHECK(depth >= static_cast<long double>(b.floor));
            if (b.floor > 0) least_gap = std::min(least_gap, depth - static_cast<long double>(b.floor));
            if (b.visible) {
                ++bounded;
                const long double nx = q[0] / q[3], ny = q[1] / q[3];
                CHECK(nx >= static_cast<long double>(b.lo[0]));
                CHECK(nx <= static_cast<long double>(b.hi[0]));
                CHECK(ny >= static_cast<long double>(b.lo[1]));
                CHECK(ny <= static_cast<long double>(b.hi[1]));
            }
        }
    }
    std::printf("[iso gl] tet_occlusion_bound, cell_occlusion_bound: %ld points between the near and far planes, %ld in visible rectangles; smallest depth above the floor %.3Lg\n",
                points, bounded, least_gap);
    CHECK(points > 100000);
    CHECK(bounded > 100000);
}
