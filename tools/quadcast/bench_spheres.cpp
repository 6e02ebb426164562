// tools/quadcast/bench_spheres.cpp -- `quadcast bench spheres` and `quadcast bench sticks`: frame
// time and fragments per covered pixel with tight screen bounds off and on
//
// spheres: N random spheres in the unit cube, radius 0.3 N^(-1/3); sticks: N capped cylinders of
// length 0.05 and radius 0.005 at random positions in the unit cube and random directions. Both
// seen at 1024x768 with a 30 degree perspective camera from (0.5, 0.5, 3), rendered by the GL
// quadric renderer (Mesa llvmpipe here): spheres with the sphere-specialised variant, sticks with
// the slab variant. Each scene is drawn over the bounding-sphere quads (tight bounds off) and over
// the tight rectangles (on), frame by frame interleaved in one run (the machine's load changes
// both alike); the medians and their ratio are printed, and per covered pixel: the fragments
// rasterised (one extra frame each with the pass-through fragment stage and the depth test off:
// GL_SAMPLES_PASSED counts every fragment of every bounding quad) and the fragment-shader
// invocations of the real frame (GL_ARB_pipeline_statistics_query; llvmpipe counts 16 per 4x4
// block it shades, so this is the work its fragment stage does). With
// --compare (spheres) the general closed-quadric variant (Variant::ellipsoid, tight bounds on)
// draws the same spheres too, interleaved, and its ratio to the sphere variant is printed. The
// cull pass is also timed with the kept primitives' corners computed by a compute pass instead of
// the vertex stage ('comp', QuadricRenderer::set_compute_bounds), and with the occluders drawn by the
// rasteriser instead of written by a compute pass ('rast', QuadricRenderer::set_raster_occluders),
// and those frames checked equal.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <random>
#include <vector>

#include "quadcast/camera.hpp"
#include "commands.hpp"
#include "timing.hpp"
#include "quadcast/gl/osmesa_context.hpp"
#include "quadcast/gl/quadric_renderer.hpp"
#include "quadcast/scene/scene_render.hpp"
#include "quadcast/shapes.hpp"

namespace quadcast::cli {

namespace {

struct BoundsBenchOptions {
    std::vector<int> counts;
    int frames = 5, width = 1024, height = 768;
    bool culling = true;
    bool compare = false;
    bool sticks = false;
    bool deferred = false;
};

std::vector<render::Primitive> random_spheres(int n, unsigned seed, render::Variant variant) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(0.0f, 1.0f), c(0.2f, 1.0f);
    const float r = 0.3f * std::pow(static_cast<float>(n), -1.0f / 3.0f);
    std::vector<render::Primitive> out(static_cast<std::size_t>(n));
    for (auto& p : out) {
        p.shape.q.q = identity<float, 4>();
        p.shape.q.q[3][3] = -r * r;
        p.shape.center = vec3(u(rng), u(rng), u(rng));
        p.shape.radius = r;
        p.shape.axis = vec3(0.0f, 0.0f, 1.0f);
        p.shape.half_length = std::numeric_limits<float>::infinity();
        p.variant = variant;
        p.color = vec3(c(rng), c(rng), c(rng));
    }
    return out;
}

/// N capped sticks (length 0.05, radius 0.005) in the unit cube, through the public shapes API.
std::vector<render::Primitive> random_sticks(int n, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(0.0f, 1.0f), s(-1.0f, 1.0f), c(0.2f, 1.0f);
    std::vector<render::Primitive> out;
    out.reserve(static_cast<std::size_t>(n));
    while (static_cast<int>(out.size()) < n) {
        const glm::vec3 d(s(rng), s(rng), s(rng));
        const float l = glm::length(d);
        if (!(l > 0.05f && l <= 1.0f)) continue;  // uniform directions
        const glm::vec3 p(u(rng), u(rng), u(rng));
        out.push_back(shapes::cylinder(p - d * (0.025f / l), p + d * (0.025f / l), 0.005f, shapes::Ends::both, {{c(rng), c(rng), c(rng)}}));
    }
    return out;
}

/// Pixels with a hit (depth < 1) in the last frame.
long covered_pixels(const gl::QuadricRenderer& r) {
    const render::Image img = r.read();
    return static_cast<long>(std::count_if(img.depth.begin(), img.depth.end(), [](float d) { return d < 1.0f; }));
}

void run_bounds_bench(const BoundsBenchOptions& o) {
    gl::OsmesaContext ctx;
    const char* what = o.sticks ? "random capped sticks (length 0.05, radius 0.005) in the unit cube" : "random spheres in the unit cube, r = 0.3 N^(-1/3)";
    std::printf("quadcast bench %s: %dx%d, 30 degree perspective from (0.5, 0.5, 3), %s\n", o.sticks ? "sticks" : "spheres", o.width, o.height, what);
    std::printf("%s\n", ctx.info().summary().c_str());
    std::printf("medians of %d interleaved frames; 'quad': bounding-sphere quads, no cull pass; 'tight': tight bounds (sticks: quadrilaterals along the axis), no cull pass;\n"
                "'cull': tight rectangles and the occlusion cull pass ('of it cp': the cull pass's GPU time); 'drawn': primitives the cull pass keeps;\nper covered pixel: fragments "
                "rasterised ('rast'; '-' for a cull pass in phases) and fragment-shader invocations ('fs', llvmpipe: 16 per 4x4 block shaded)%s\n", o.frames,
                o.sticks ? ";\n'rect': tight axis-aligned rectangles instead of the quadrilaterals, no cull pass" : "");
    std::printf("'late': the cull pass without the fragment stage's early discard against the occluder depth image;\n"
                "'comp': the cull pass with the kept primitives' corners computed by a compute pass on all threads, the vertex stage fetching them\n"
                "(QuadricRenderer::set_compute_bounds; 'c of cp': its cull passes' GPU time; 'cull/comp' > 1: the compute pass pays);\n"
                "'rast': the cull pass with the occluders drawn into the depth buffer by the rasteriser instead of written pixel by pixel by a compute pass\n"
                "(QuadricRenderer::set_raster_occluders; 'r of cp': its GPU time of the occluders and cull passes, 'r drawn': the primitives it keeps,\n"
                "'r fs': its fragment-shader invocations per covered pixel; 'cull/rast' > 1: the rasteriser pays);\n"
                "'overlap': the renderer's expected overlap of the frame (render::expected_overlap, from a sample of at most 4096 primitives),\n"
                "'t layers': the tight bounds' rasterised fragments per viewport pixel (measured); 'auto': the renderer's default\n"
                "(the cull pass only where the expected overlap reaches RenderOptions::occlusion_min_overlap = %.1f; 'cull' and 'quad' above always and never run it),\n"
                "'best/auto': the faster of 'tight' and 'cull' over 'auto' (1.00x: the default chose right);\n"
                "'1ph': the cull pass in one phase (RenderOptions::occlusion_phases = 1: sticks occlude with their chains of disks; 'cull' draws\n"
                "sticks in phases, nearest first, each later one culled against what the earlier drew, and writes no chains), '1ph drawn' its kept primitives;\n"
                "'reuse': the default options with the last frame's shown set drawn first (RenderOptions::occlusion_reuse; the other columns' frames\n"
                "interleave options in one renderer and reuse nothing), its own renderer's third and later frames; 'reuse drawn' the primitives\n"
                "it drew ('*': the frame did not reuse the set: drawn in phases, or too little overlap), 'reuse fs' its\n"
                "fragment-shader invocations per covered pixel, and counted fragment by fragment by the stages (QuadricRenderer::fragment_counts)\n"
                "'started' (rasterised for the drawn primitives), 'shaded' (passed the early discard: cast their ray) and 'hit',\n"
                "'auto/reuse' > 1: the reuse pays; the camera stays, so from the third frame on the set is drawn alone, its view unchanged since the\n"
                "test that chose it (QuadricRenderer::set_skip_unchanged_view_test); 'tested ms': the same frames testing every primitive\n"
                "again and drawing what passes (as after the camera moved), in a renderer of its own, 'tested/reuse' > 1: not testing pays;\n"
                "spheres: every column draws the sphere variant as point sprites, one vertex per sphere, where they fit (QuadricRenderer::set_point_sprites,\n"
                "render::sphere_points_fit); from the fourth 'reuse' frame on (the view unchanged) the spheres the picture shows are shaded once per pixel\n"
                "from the ids target (QuadricRenderer::set_reshade); 'sprites ms': those frames drawing them as sprites instead, in a renderer of its own,\n"
                "'sprites/reuse' > 1: shading from the ids target pays; 'quads ms': the sprites' frames with quads of four vertices instead, in a\n"
                "renderer of its own, 'pts' whether the 'reuse' frame drew sprites, 'quads/sprites' > 1: the sprites pay\n",
                double(render::RenderOptions{}.occlusion_min_overlap));
    std::printf("%10s %9s %8s %8s %8s %8s %10s %10s %7s %6s %6s %6s %7s %7s %7s", o.sticks ? "sticks" : "spheres", "covered", "quad ms", "tight ms", "cull ms", "of it cp",
                "quad/cull", "tight/cull", "drawn", "q rast", "t rast", "c rast", "q fs", "t fs", "c fs");
    std::printf(" %9s %11s %9s %9s %11s %8s %8s %8s %7s %9s", "late ms", "late/cull", "comp ms", "c of cp", "cull/comp", "rast ms", "r of cp", "r drawn", "r fs", "cull/rast");
    if (o.sticks) std::printf(" %8s %10s %7s", "rect ms", "rect/tight", "r rast");
    std::printf(" %8s %8s %8s %6s %10s %8s %9s %9s", "overlap", "t layers", "auto ms", "auto", "best/auto", "1ph ms", "1ph drawn", "1ph/cull");
    std::printf(" %8s %10s %8s %8s %7s %7s %11s %9s %12s", "reuse ms", "reuse drawn", "reuse fs", "started", "shaded", "hit", "auto/reuse", "tested ms", "tested/reuse");
    if (!o.sticks) std::printf(" %10s %13s %8s %4s %13s", "sprites ms", "sprites/reuse", "quads ms", "pts", "quads/sprites");
    if (o.compare) std::printf(" %16s %14s %14s %15s", "closed cull ms", "sphere/closed", "closed comp ms", "cl. cull/comp");
    std::printf("\n");
    gl::QuadricRenderer r(ctx.api());
    gl::QuadricRenderer reuse_r(ctx.api());  // the default options' frames, each reusing the last one's shown set
    gl::QuadricRenderer tested_r(ctx.api());  // the same, testing every primitive again in every frame
    tested_r.set_skip_unchanged_view_test(false);
    gl::QuadricRenderer sprites_r(ctx.api());  // the same drawing the picture's spheres as sprites, not shading them from the ids target
    sprites_r.set_reshade(false);
    gl::QuadricRenderer quads_r(ctx.api());  // the same with the sphere variant as quads, not point sprites
    quads_r.set_point_sprites(false);
    quads_r.set_reshade(false);
    std::unique_ptr<gl::QuadricRenderer> general;  // --compare: the closed-quadric variant
    if (o.compare) general = std::make_unique<gl::QuadricRenderer>(ctx.api());
    render::Camera cam;
    const double aspect = static_cast<double>(o.width) / o.height;
    cam.view = cast<float>(quadcast::look_at(vec3(0.5, 0.5, 3.0), vec3(0.5, 0.5, 0.5), vec3(0.0, 1.0, 0.0)));
    cam.projection = cast<float>(quadcast::perspective(30.0, aspect, 1.0, 5.0));
    cam.eye = vec3(0.5f, 0.5f, 3.0f);
    render::Light light;
    light.direction = vec3(-0.4f, -0.6f, -1.0f);
    render::RenderOptions modes[3];  // quad, tight, cull
    for (render::RenderOptions& m : modes) {
        m.width = o.width;
        m.height = o.height;
        m.culling = o.culling;
        m.deferred = o.deferred;
        m.occlusion_culling = false;
        m.occlusion_reuse = false;  // (the modes interleave in one renderer; the reuse of shown sets has its own, below)
    }
    modes[0].tight_bounds = false;
    modes[2].occlusion_culling = true;
    modes[2].occlusion_min_overlap = 0.0f;  // the cull pass in every frame
    render::RenderOptions one_phase = modes[2];  // the cull pass in one phase (sticks: their occluder chains)
    one_phase.occlusion_phases = 1;
    render::RenderOptions automatic = modes[2];  // the renderer's default: the cull pass where the expected overlap reaches the threshold
    automatic.occlusion_min_overlap = render::RenderOptions{}.occlusion_min_overlap;
    render::RenderOptions reuse = automatic;  // the renderer's default, with the shown set reused where frames repeat
    reuse.occlusion_reuse = true;
    auto time_frame = [&](gl::QuadricRenderer& renderer, const render::RenderOptions& ro) {
        const auto t0 = std::chrono::steady_clock::now();
        renderer.draw(cam, light, ro);
        return ms_since(t0);
    };
    for (int n : o.counts) {
        const auto prims = o.sticks ? random_sticks(n, 7) : random_spheres(n, 7, render::Variant::sphere);  // (made once for every renderer)
        r.set_primitives(prims);
        reuse_r.set_primitives(prims);
        tested_r.set_primitives(prims);
        if (!o.sticks) {
            sprites_r.set_primitives(prims);
            quads_r.set_primitives(prims);
        }
        if (general) general->set_primitives(random_spheres(n, 7, render::Variant::ellipsoid));
        // Count the fragments of one frame each (the queries are not in the timed frames)
        double frag[3], rast[3];
        r.set_count_fragments(true);
        for (int m = 0; m < 3; ++m) {
            r.draw(cam, light, modes[m]);
            frag[m] = static_cast<double>(r.fragment_invocations());
        }
        const std::size_t drawn = r.drawn_primitives();
        const int cull_phases = r.phases();  // (phased: the pass-through count below, without depth writes, culls nothing in the later phases)
        const long covered = std::max(1L, covered_pixels(r));
        // Culling must not change the picture: the cull frame against the tight frame
        const render::Image culled_img = r.read();
        r.draw(cam, light, modes[1]);
        const render::Image tight_img = r.read();
        auto differing = [](const render::Image& a, const render::Image& b) {  // pixels whose depth or colour differ
            long n = 0;
            for (std::size_t i = 0; i < a.depth.size(); ++i)
                n += a.depth[i] != b.depth[i] || a.rgba[4 * i] != b.rgba[4 * i] || a.rgba[4 * i + 1] != b.rgba[4 * i + 1] || a.rgba[4 * i + 2] != b.rgba[4 * i + 2];
            return n;
        };
        const long img_diff = differing(culled_img, tight_img);
        if (img_diff) std::printf("WARNING: %ld pixels differ between the culled and the unculled frame\n", img_diff);
        // Nor where the corners are computed: a compute pass's against the vertex stage's
        r.set_compute_bounds(true);
        r.draw(cam, light, modes[2]);
        const render::Image comp_img = r.read();
        r.set_compute_bounds(false);
        const long comp_diff = differing(culled_img, comp_img);
        if (comp_diff) std::printf("WARNING: %ld pixels differ between corners from the compute pass and from the vertex stage\n", comp_diff);
        // Nor how the occluders reach the depth image: the rasteriser's quadrilaterals against the compute pass's disks
        r.set_raster_occluders(true);
        r.draw(cam, light, modes[2]);
        const render::Image occ_img = r.read();
        const std::size_t occ_drawn = r.drawn_primitives();
        const double occ_frag = static_cast<double>(r.fragment_invocations());
        r.set_raster_occluders(false);
        const long occ_diff = differing(culled_img, occ_img);
        if (occ_diff) std::printf("WARNING: %ld pixels differ between occluders from the rasteriser and from the compute pass\n", occ_diff);
        // Nor drawing in phases: one phase against the default
        r.draw(cam, light, one_phase);
        const render::Image one_phase_img = r.read();
        const std::size_t one_phase_drawn = r.drawn_primitives();
        const long phase_diff = differing(culled_img, one_phase_img);
        if (phase_diff) std::printf("WARNING: %ld pixels differ between the cull pass in one phase and in phases\n", phase_diff);
        r.set_count_fragments(false);
        r.set_fragment_stage(gl::QuadricRenderer::FragmentStage::passthrough);
        r.set_depth_test(false);
        auto forward = [](render::RenderOptions ro) { ro.deferred = false; return ro; };  // pass-through shades forward only
        for (int m = 0; m < 3; ++m) {
            r.draw(cam, light, forward(modes[m]));
            rast[m] = static_cast<double>(r.samples_passed());
        }
        double rast_rect = 0.0;  // sticks: tight rectangles instead of the quadrilaterals
        if (o.sticks) {
            r.set_slab_quads(false);
            r.draw(cam, light, forward(modes[1]));
            rast_rect = static_cast<double>(r.samples_passed());
            r.set_slab_quads(true);
        }
        r.set_depth_test(true);
        r.set_fragment_stage(gl::QuadricRenderer::FragmentStage::incremental);
        // The reused shown set: its third frame (the first records every primitive as shown, the
        // second tests them against what they drew), its fragments, and its picture against the tight frame
        reuse_r.draw(cam, light, reuse);
        reuse_r.draw(cam, light, reuse);
        reuse_r.set_count_fragments(true);
        reuse_r.draw(cam, light, reuse);
        reuse_r.set_count_fragments(false);
        const double reuse_frag = static_cast<double>(reuse_r.fragment_invocations());
        const gl::FragmentCounts reuse_counts = reuse_r.fragment_counts();
        const std::size_t reuse_drawn = reuse_r.drawn_primitives();
        const bool reused = reuse_r.reused_shown_set();
        const long reuse_diff = differing(tight_img, reuse_r.read());
        if (reuse_diff) std::printf("WARNING: %ld pixels differ between the frame reusing the shown set and the unculled frame\n", reuse_diff);
        for (int i = 0; i < 3; ++i) tested_r.draw(cam, light, reuse);
        const long tested_diff = differing(tight_img, tested_r.read());
        if (tested_diff) std::printf("WARNING: %ld pixels differ between the frame testing the reused shown set again and the unculled frame\n", tested_diff);
        const bool drew_points = reuse_r.drew_points();
        if (!o.sticks) {  // sprites against shading from the ids target, quads against sprites: the same pictures
            for (int i = 0; i < 4; ++i) sprites_r.draw(cam, light, reuse);
            for (int i = 0; i < 4; ++i) quads_r.draw(cam, light, reuse);
            const long sprites_diff = differing(reuse_r.read(), sprites_r.read());
            if (sprites_diff) std::printf("WARNING: %ld pixels differ between the spheres drawn as sprites and shaded from the ids target\n", sprites_diff);
            const long quads_diff = differing(sprites_r.read(), quads_r.read());
            if (quads_diff) std::printf("WARNING: %ld pixels differ between the sphere variant as quads and as point sprites\n", quads_diff);
        }
        r.draw(cam, light, modes[2]);  // warm-up
        if (general) general->draw(cam, light, modes[2]);  // warm-up
        // Time the frames, interleaved
        std::vector<double> ms_auto, ms_one_phase, ms_reuse, ms_tested, ms_sprites, ms_quads;
        std::vector<double> ms[3], ms_general, ms_general_comp, ms_cull, ms_rect, ms_late, ms_comp, ms_cull_comp, ms_occ, ms_cull_occ;
        for (int i = 0; i < o.frames; ++i) {
            for (int m = 0; m < 3; ++m) ms[m].push_back(time_frame(r, modes[m]));
            ms_cull.push_back(r.cull_pass_ms());
            ms_auto.push_back(time_frame(r, automatic));
            ms_reuse.push_back(time_frame(reuse_r, reuse));
            ms_tested.push_back(time_frame(tested_r, reuse));
            if (!o.sticks) {
                ms_sprites.push_back(time_frame(sprites_r, reuse));
                ms_quads.push_back(time_frame(quads_r, reuse));
            }
            ms_one_phase.push_back(time_frame(r, one_phase));
            r.set_early_discard(false);
            ms_late.push_back(time_frame(r, modes[2]));
            r.set_early_discard(true);
            r.set_compute_bounds(true);
            ms_comp.push_back(time_frame(r, modes[2]));
            ms_cull_comp.push_back(r.cull_pass_ms());
            r.set_compute_bounds(false);
            r.set_raster_occluders(true);
            ms_occ.push_back(time_frame(r, modes[2]));
            ms_cull_occ.push_back(r.cull_pass_ms());
            r.set_raster_occluders(false);
            if (o.sticks) {
                r.set_slab_quads(false);
                ms_rect.push_back(time_frame(r, modes[1]));
                r.set_slab_quads(true);
            }
            if (general) {
                ms_general.push_back(time_frame(*general, modes[2]));
                general->set_compute_bounds(true);
                ms_general_comp.push_back(time_frame(*general, modes[2]));
                general->set_compute_bounds(false);
            }
        }
        const double t[3] = {median(ms[0]), median(ms[1]), median(ms[2])};
        char c_rast[16] = "     -";
        if (cull_phases == 1) std::snprintf(c_rast, sizeof c_rast, "%6.2f", rast[2] / covered);
        std::printf("%10d %9ld %8.1f %8.1f %8.1f %8.1f %9.2fx %9.2fx %6.1f%% %6.2f %6.2f %s %7.2f %7.2f %7.2f", n, covered, t[0], t[1], t[2], median(ms_cull), t[0] / t[2], t[1] / t[2],
                    100.0 * static_cast<double>(drawn) / std::max(1, n), rast[0] / covered, rast[1] / covered, c_rast, frag[0] / covered,
                    frag[1] / covered, frag[2] / covered);
        const double t_late = median(ms_late);
        const double t_comp = median(ms_comp);
        std::printf(" %9.1f %10.2fx %9.1f %9.1f %10.2fx", t_late, t_late / t[2], t_comp, median(ms_cull_comp), t[2] / t_comp);
        const double t_occ = median(ms_occ);
        std::printf(" %8.1f %8.1f %7.1f%% %7.2f %8.2fx", t_occ, median(ms_cull_occ), 100.0 * static_cast<double>(occ_drawn) / std::max(1, n), occ_frag / covered, t[2] / t_occ);
        if (o.sticks) {
            const double t_rect = median(ms_rect);
            std::printf(" %8.1f %9.2fx %7.2f", t_rect, t_rect / t[1], rast_rect / covered);
        }
        r.draw(cam, light, automatic);
        const double t_auto = median(ms_auto);
        std::printf(" %8.2f %8.2f %8.1f %6s %9.2fx", r.expected_overlap(), rast[1] / (double(o.width) * o.height), t_auto, r.cull_pass_ran() ? "cull" : "skip",
                    std::min(t[1], t[2]) / t_auto);
        const double t_one_phase = median(ms_one_phase);
        std::printf(" %8.1f %8.1f%% %8.2fx", t_one_phase, 100.0 * static_cast<double>(one_phase_drawn) / std::max(1, n), t_one_phase / t[2]);
        const double t_reuse = median(ms_reuse);
        std::printf(" %8.1f %9.1f%%%s %8.2f %8.2f %7.2f %7.2f %10.2fx %9.1f %11.2fx", t_reuse, 100.0 * static_cast<double>(reuse_drawn) / std::max(1, n), reused ? "" : "*",
                    reuse_frag / covered, double(reuse_counts.started) / covered, double(reuse_counts.cast) / covered, double(reuse_counts.hit) / covered,
                    t_auto / t_reuse, median(ms_tested), median(ms_tested) / t_reuse);
        if (!o.sticks)
            std::printf(" %10.1f %12.2fx %8.1f %4s %12.2fx", median(ms_sprites), median(ms_sprites) / t_reuse, median(ms_quads), drew_points ? "yes" : "no",
                        median(ms_quads) / median(ms_sprites));
        if (general) {
            const double m_general = median(ms_general);
            const double m_general_comp = median(ms_general_comp);
            std::printf(" %16.1f %13.2fx %14.1f %14.2fx", m_general, m_general / t[2], m_general_comp, m_general / m_general_comp);
        }
        std::printf("\n");
    }
}

}  // namespace

void add_bench_spheres(CLI::App& bench) {
    auto o = std::make_shared<BoundsBenchOptions>();
    o->counts = {10000, 100000, 1000000};
    CLI::App* cmd = bench.add_subcommand("spheres", "frame time and fragments per covered pixel of N random spheres (10k / 100k / 1M): bounding quads, tight rectangles, occlusion cull pass");
    cmd->add_option("--counts", o->counts, "sphere counts");
    cmd->add_option("--frames", o->frames, "timed frames per count and mode")->check(CLI::Range(1, 1000));
    cmd->add_flag("--compare", o->compare, "also time the general closed-quadric variant, interleaved, and print the ratio");
    cmd->add_option("--width", o->width, "image width")->check(CLI::Range(16, 8192));
    cmd->add_option("--height", o->height, "image height")->check(CLI::Range(16, 8192));
    cmd->add_flag("--deferred", o->deferred, "shade in the deferred pass (geometry buffer) instead of in the primitive pass");
    cmd->callback([o] { run_bounds_bench(*o); });

    auto s = std::make_shared<BoundsBenchOptions>();
    s->counts = {50000};
    s->sticks = true;
    CLI::App* sticks = bench.add_subcommand("sticks", "frame time and fragments per covered pixel of N random capped sticks (50k): bounding quads, tight rectangles, occlusion cull pass");
    sticks->add_option("--counts", s->counts, "stick counts");
    sticks->add_option("--frames", s->frames, "timed frames per count and mode")->check(CLI::Range(1, 1000));
    sticks->add_option("--width", s->width, "image width")->check(CLI::Range(16, 8192));
    sticks->add_option("--height", s->height, "image height")->check(CLI::Range(16, 8192));
    sticks->add_flag("--deferred", s->deferred, "shade in the deferred pass (geometry buffer) instead of in the primitive pass");
    sticks->callback([s] { run_bounds_bench(*s); });
}

}  // namespace quadcast::cli
