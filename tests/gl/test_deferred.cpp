// tests/gl/test_deferred.cpp -- deferred shading (geometry buffer + full-screen pass) and silhouette outlines
#include <doctest/doctest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <cstdio>
#include <random>

#include "quadcast/gl/osmesa_context.hpp"
#include "quadcast/gl/quadric_renderer.hpp"
#include "quadcast/render/cpu_renderer.hpp"
#include "render/render_testing.hpp"

using namespace quadcast;
using namespace quadcast::render;

namespace {

Camera test_camera(bool ortho) {
    return ortho ? qc_render_test::look_at(vec3(0.5, 1.0, 8.0), vec3(0.0, 0.0, 0.0), vec3(0.0, 1.0, 0.0), qc_render_test::orthographic(-4, 4, -3, 3, 1, 20), true)
                 : qc_render_test::look_at(vec3(0.5, 1.0, 8.0), vec3(0.0, 0.0, 0.0), vec3(0.0, 1.0, 0.0), qc_render_test::perspective(50, 240.0 / 180.0, 1, 20));
}

/// Largest per-channel difference of two RGBA8 images and the number of pixels that differ.
struct ColorDiff {
    int max = 0;
    long pixels = 0;
};
ColorDiff color_diff(const Image& a, const Image& b) {
    ColorDiff d;
    for (std::size_t i = 0; i < a.depth.size(); ++i) {
        int m = 0;
        for (int c = 0; c < 4; ++c) m = std::max(m, std::abs(int(a.rgba[i * 4 + c]) - int(b.rgba[i * 4 + c])));
        d.max = std::max(d.max, m);
        d.pixels += m > 0;
    }
    return d;
}

}  // namespace

TEST_CASE("deferred shading draws the image forward shading draws") {
    gl::OsmesaContext ctx;
    gl::QuadricRenderer r(ctx.api());
    const std::vector<render::Primitive> prims = qc_render_test::mixed_scene(11, {50, 25, 8, true, false});
    r.set_primitives(prims);
    Light light;
    light.direction = vec3(-0.4f, -0.6f, -1.0f);
    for (bool ortho : {false, true})
        for (bool cull : {true, false}) {
            RenderOptions o;
            o.width = 240;
            o.height = 180;
            o.culling = cull;
            o.background = vec3(0.2f, 0.3f, 0.4f);
            const Camera cam = test_camera(ortho);
            r.draw(cam, light, o);
            const Image fwd = r.read();
            o.deferred = true;
            r.draw(cam, light, o);
            const Image def = r.read();
            long covered = 0, depth_diff = 0;
            for (std::size_t i = 0; i < fwd.depth.size(); ++i) {
                covered += fwd.depth[i] < 1.0f;
                depth_diff += fwd.depth[i] != def.depth[i];
            }
            const ColorDiff d = color_diff(fwd, def);
            std::printf("[deferred] %s, culling %s: %ld covered px, %ld px differ (max %d LSB), %ld depth differences\n",
                        ortho ? "orthographic" : "perspective", cull ? "on" : "off", covered, d.pixels, d.max, depth_diff);
            CHECK(covered > 5000);
            CHECK(d.max <= 1);
            CHECK(depth_diff == 0);
        }
}

TEST_CASE("the deferred pass writes every pixel: the background's and the covered ones, in two draws") {
    // The pass draws the covered pixels (depth < 1) and the background (depth 1) apart, selected by
    // the depth test. A frame with another background colour must leave no pixel of the last one,
    // and give the covered pixels the same colours; with shadows and outlines on and off.
    gl::OsmesaContext ctx;
    gl::QuadricRenderer r(ctx.api());
    r.set_primitives(qc_render_test::mixed_scene(11, {50, 25, 8, true, false}));
    Light light;
    light.direction = vec3(-0.4f, -0.6f, -1.0f);
    for (bool effects : {false, true}) {
        RenderOptions o;
        o.width = 240;
        o.height = 180;
        o.deferred = true;
        o.shadows = effects;
        o.silhouettes = effects;
        const Camera cam = test_camera(false);
        o.background = vec3(1.0f, 1.0f, 1.0f);
        r.draw(cam, light, o);
        const Image white = r.read();
        o.background = vec3(0.0f, 0.5f, 0.0f);
        r.draw(cam, light, o);
        const Image green = r.read();
        long background = 0, stale = 0, wrong = 0, covered_differ = 0;
        for (std::size_t i = 0; i < green.depth.size(); ++i) {
            const std::uint8_t* g = &green.rgba[i * 4];
            if (green.depth[i] < 1.0f) {
                // (an outline may reach a covered pixel from the background; without outlines none differs)
                covered_differ += !effects && std::memcmp(g, &white.rgba[i * 4], 4) != 0;
                continue;
            }
            ++background;
            stale += g[0] == 255 && g[2] == 255;
            // the background colour, or with outlines darkened towards black: red and blue 0, green at most 128
            wrong += g[0] != 0 || g[2] != 0 || g[1] > 128 || g[3] != 255 || (!effects && g[1] != 128);
        }
        std::printf("[deferred] two draws, %s: %ld background px, %ld keep the last frame's colour, %ld not the background colour; %ld covered px differ\n",
                    effects ? "shadows and outlines" : "plain", background, stale, wrong, covered_differ);
        CHECK(background > 10000);
        CHECK(stale == 0);
        CHECK(wrong == 0);
        CHECK(covered_differ == 0);
    }
}

TEST_CASE("silhouette outlines darken edges only, and the GL and CPU renderers agree on them") {
    gl::OsmesaContext ctx;
    gl::QuadricRenderer r(ctx.api());
    const std::vector<render::Primitive> prims = qc_render_test::mixed_scene(12, {50, 25, 8, true, false});
    r.set_primitives(prims);
    Light light;
    light.direction = vec3(-0.4f, -0.6f, -1.0f);
    for (bool ortho : {false, true}) {
        RenderOptions o;
        o.width = 480;  // twice the other tests' resolution: outlines are a few pixels wide at any size
        o.height = 360;
        const Camera cam = test_camera(ortho);
        r.draw(cam, light, o);
        const Image plain = r.read();
        o.silhouettes = true;
        r.draw(cam, light, o);
        const Image gl_sil = r.read();
        const Image cpu_sil = render_cpu(prims, cam, light, o);
        // Outlines only darken, and only near depth or normal discontinuities: a pixel whose 3x3
        // neighbourhood is all background keeps its colour.
        long darker = 0, brighter = 0, changed_in_background = 0;
        const int w = o.width, h = o.height;
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                const std::size_t i = std::size_t(y) * w + x;
                bool all_bg = true;
                for (int dy = -1; dy <= 1; ++dy)
                    for (int dx = -1; dx <= 1; ++dx) {
                        const int yy = std::clamp(y + dy, 0, h - 1), xx = std::clamp(x + dx, 0, w - 1);
                        all_bg = all_bg && plain.depth[std::size_t(yy) * w + xx] >= 1.0f;
                    }
                bool is_darker = false, is_brighter = false, changed = false;
                for (int c = 0; c < 3; ++c) {
                    const int a = plain.rgba[i * 4 + c], b = gl_sil.rgba[i * 4 + c];
                    is_darker = is_darker || b < a - 1;
                    is_brighter = is_brighter || b > a + 1;
                    changed = changed || a != b;
                }
                darker += is_darker;
                brighter += is_brighter;
                changed_in_background += all_bg && changed;
            }
        // GL vs CPU: the rays differ by rounding (see test_render_gl_vs_cpu), so a few edge pixels may differ.
        long differ = 0, covered = 0;
        for (std::size_t i = 0; i < gl_sil.depth.size(); ++i) {
            covered += gl_sil.depth[i] < 1.0f;
            for (int c = 0; c < 3; ++c)
                if (std::abs(int(gl_sil.rgba[i * 4 + c]) - int(cpu_sil.rgba[i * 4 + c])) > 1) { ++differ; break; }
        }
        std::printf("[silhouettes] %s: %ld covered px, %ld darkened, %ld brightened, %ld changed away from surfaces, %ld px GL vs CPU > 1 LSB\n",
                    ortho ? "orthographic" : "perspective", covered, darker, brighter, changed_in_background, differ);
        CHECK(darker > covered / 50);
        CHECK(darker < covered * 3 / 4);
        CHECK(brighter == 0);
        CHECK(changed_in_background == 0);
        CHECK(differ <= covered / 50);
    }
}

TEST_CASE("soft shadows only darken, and the GL and CPU renderers agree on them") {
    gl::OsmesaContext ctx;
    gl::QuadricRenderer r(ctx.api());
    const std::vector<render::Primitive> prims = qc_render_test::mixed_scene(13, {50, 25, 8, true, false});
    r.set_primitives(prims);
    Light light;
    light.direction = vec3(-0.4f, -0.6f, -1.0f);
    for (bool ortho : {false, true}) {
        RenderOptions o;
        o.width = 240;
        o.height = 180;
        o.shadow_map_size = 512;
        const Camera cam = test_camera(ortho);
        r.draw(cam, light, o);
        const Image lit = r.read();
        o.shadows = true;
        r.draw(cam, light, o);
        const Image gl_sh = r.read();
        const Image cpu_sh = render_cpu(prims, cam, light, o);
        long covered = 0, darker = 0, brighter = 0, differ = 0, depth_diff = 0;
        for (std::size_t i = 0; i < lit.depth.size(); ++i) {
            covered += lit.depth[i] < 1.0f;
            depth_diff += lit.depth[i] != gl_sh.depth[i];
            bool d = false, b = false, x = false;
            for (int c = 0; c < 3; ++c) {
                const int a = lit.rgba[i * 4 + c], g = gl_sh.rgba[i * 4 + c], p = cpu_sh.rgba[i * 4 + c];
                d = d || g < a - 1;
                b = b || g > a + 1;
                x = x || std::abs(g - p) > 1;
            }
            darker += d;
            brighter += b;
            differ += x;
        }
        std::printf("[shadows] %s: %ld covered px, %ld in (partial) shadow, %ld brightened, %ld px GL vs CPU > 1 LSB\n",
                    ortho ? "orthographic" : "perspective", covered, darker, brighter, differ);
        CHECK(depth_diff == 0);
        CHECK(darker > covered / 20);
        CHECK(darker < covered * 3 / 4);
        CHECK(brighter == 0);
        CHECK(differ <= covered / 50);
    }
}

TEST_CASE("the background's outlines drawn over the listed tiles only: the picture of the full-screen draw") {
    // QuadricRenderer::set_outline_tiles: the compute pass lists the 8x8 tiles where a pixel or a
    // neighbour holds geometry, and only they run the background program; the rest keep the
    // cleared background colour. Image sizes that are not multiples of 8 (partial tiles at the
    // right and top edges) and below one tile, primitives across the image's edges, shadows on and
    // off, perspective and orthographic: the same bytes and depths as the full-screen draw.
    gl::OsmesaContext ctx;
    gl::QuadricRenderer r(ctx.api());
    r.set_primitives(qc_render_test::mixed_scene(13, {60, 30, 10, true, false}));
    Light light;
    light.direction = vec3(-0.4f, -0.6f, -1.0f);
    struct Size { int w, h; };
    long outlined_total = 0;
    for (const Size size : {Size{240, 180}, Size{237, 173}, Size{5, 3}, Size{1021, 9}})
        for (bool ortho : {false, true})
            for (bool close : {false, true})
                for (bool shadows : {false, true}) {
                    RenderOptions o;
                    o.width = size.w;
                    o.height = size.h;
                    o.deferred = true;
                    o.silhouettes = true;
                    o.shadows = shadows;
                    o.background = vec3(0.9f, 0.95f, 1.0f);
                    const Camera cam = close ? qc_render_test::look_at(vec3(0.3, 0.6, 4.0), vec3(0.0, 0.0, 0.0), vec3(0.0, 1.0, 0.0),
                                                                       ortho ? qc_render_test::orthographic(-2, 2, -1.5, 1.5, 1, 20)
                                                                             : qc_render_test::perspective(40, double(size.w) / size.h, 1, 20),
                                                                       ortho)
                                             : test_camera(ortho);
                    r.set_outline_tiles(true);
                    r.draw(cam, light, o);
                    const Image tiles = r.read();
                    r.set_outline_tiles(false);
                    r.draw(cam, light, o);
                    const Image full = r.read();
                    r.set_outline_tiles(true);
                    long differ = 0, depth_differ = 0, outlined = 0, covered = 0;
                    for (std::size_t i = 0; i < full.depth.size(); ++i) {
                        differ += std::memcmp(&tiles.rgba[i * 4], &full.rgba[i * 4], 4) != 0;
                        depth_differ += tiles.depth[i] != full.depth[i];
                        covered += full.depth[i] < 1.0f;
                        // a background pixel darkened by an outline (the background colour is (230, 242, 255))
                        outlined += full.depth[i] >= 1.0f && full.rgba[i * 4 + 2] < 250;
                    }
                    outlined_total += outlined;
                    CAPTURE(size.w);
                    CAPTURE(size.h);
                    CAPTURE(ortho);
                    CAPTURE(close);
                    CAPTURE(shadows);
                    CHECK(differ == 0);
                    CHECK(depth_differ == 0);
                    if (size.w * size.h > 1000) CHECK(covered > 0);
                    if (size.w == 240 || size.w == 237) CHECK(outlined > 100);
                }
    std::printf("[deferred] outline tiles: %ld background px outlined over all frames, each frame the same as the full-screen draw\n", outlined_total);
}

TEST_CASE("PCF samples gathered from the shadow map in phases: the picture of the samples read one by one") {
    // QuadricRenderer::set_shadow_phases: with the shadow map kept from an earlier frame, the
    // penumbra's 64 samples are read four at a time from the map in phases of the PCF step. The
    // same count, so the same bytes and depths as reading them one by one, for PCF steps from 1 to
    // 8, map sizes that are not multiples of the step, and footprints reaching past the map's
    // edges (a 64-texel map with a step of 8: a footprint 56 texels wide).
    gl::OsmesaContext ctx;
    gl::QuadricRenderer r(ctx.api());
    r.set_primitives(qc_render_test::mixed_scene(13, {50, 25, 8, true, false}));
    Light light;
    light.direction = vec3(-0.4f, -0.6f, -1.0f);
    struct Case { int map, step; };
    long shadowed_total = 0;
    for (const Case c : {Case{512, 2}, Case{512, 1}, Case{300, 3}, Case{257, 5}, Case{64, 8}, Case{200, 7}})
        for (bool ortho : {false, true}) {
            RenderOptions o;
            o.width = 240;
            o.height = 180;
            const Camera cam = test_camera(ortho);
            r.draw(cam, light, o);
            const Image lit = r.read();
            o.shadows = true;
            o.shadow_map_size = c.map;
            o.pcf_step = c.step;
            r.set_shadow_phases(true);
            r.draw(cam, light, o);  // the map drawn (no phases yet), or kept from the other camera's frames
            CHECK(r.used_shadow_phases() == r.reused_shadow_map());
            const Image first = r.read();
            r.draw(cam, light, o);  // the map kept: its phases made and read
            CHECK(r.reused_shadow_map());
            CHECK(r.used_shadow_phases());
            const Image gathered = r.read();
            r.set_shadow_phases(false);
            r.draw(cam, light, o);
            CHECK_FALSE(r.used_shadow_phases());
            const Image single = r.read();
            r.set_shadow_phases(true);
            long differ = 0, depth_differ = 0, shadowed = 0;
            for (std::size_t i = 0; i < single.depth.size(); ++i) {
                differ += std::memcmp(&gathered.rgba[i * 4], &single.rgba[i * 4], 4) != 0 || std::memcmp(&first.rgba[i * 4], &single.rgba[i * 4], 4) != 0;
                depth_differ += gathered.depth[i] != single.depth[i];
                shadowed += std::memcmp(&lit.rgba[i * 4], &single.rgba[i * 4], 4) != 0;
            }
            shadowed_total += shadowed;
            CAPTURE(c.map);
            CAPTURE(c.step);
            CAPTURE(ortho);
            CHECK(differ == 0);
            CHECK(depth_differ == 0);
            CHECK(shadowed > 200);
        }
    std::printf("[deferred] shadow map in phases: %ld shadowed px over all frames, each the same as with the samples read one by one\n", shadowed_total);
}
