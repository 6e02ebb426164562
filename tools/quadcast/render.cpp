// tools/quadcast/render.cpp -- `quadcast render SCENE.json -o out.png`
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "commands.hpp"
#include "timing.hpp"
#include "quadcast/scene/diagnostics.hpp"
#include "quadcast/image/image_io.hpp"
#include "quadcast/gl/isosurface_renderer.hpp"
#include "quadcast/gl/osmesa_context.hpp"
#include "quadcast/gl/quadric_renderer.hpp"
#include "quadcast/gl/slim_renderer.hpp"
#include "quadcast/render/cpu_renderer.hpp"
#include "quadcast/render/slim_cpu_renderer.hpp"
#include "quadcast/render/spline_cpu_renderer.hpp"
#include "quadcast/isosurface.hpp"
#include "quadcast/volume/load.hpp"
#include "quadcast/scene/scene_json.hpp"
#include "quadcast/scene/scene_render.hpp"
#include "quadcast/skin/skin.hpp"
#include "quadcast/slim/scene_loader.hpp"

namespace quadcast::cli {

namespace {

struct RenderArgs {
    std::string scene, output, depth;
    int width = 1024, height = 768, frames = 0, slim_bits = 32;
    double orbit = 0.0;  ///< degrees the camera orbits per timed frame (--orbit)
    bool cpu = false, timing = false, allow_empty = false;
};

/// An expected overlap (gl::QuadricRenderer::expected_overlap) as printed.
std::string fmt_overlap(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.2f", v);
    return buf;
}

/// The camera of timed frame i (0-based): the frame's own, or with --orbit the scene's camera
/// orbited by (i + 1) times the angle about its target (render::orbit_camera).
render::Camera frame_camera_at(const RenderArgs& a, const scene::Scene& sc, const render::Frame& fr, int i) {
    if (a.orbit == 0.0) return fr.camera;
    return render::frame_camera(render::orbit_camera(sc.camera, a.orbit * (i + 1)), fr.transform, a.width, a.height);
}

std::string orbit_note(const RenderArgs& a) {
    if (a.orbit == 0.0) return {};
    char buf[96];
    std::snprintf(buf, sizeof buf, ", the camera orbiting its target by %g degrees a frame", a.orbit);
    return buf;
}

/// Frees a vector's memory.
template <class T>
void release(std::vector<T>& v) {
    std::vector<T>().swap(v);
}

/// Writes the picture (and the depth with --depth), unless nothing was drawn (every window depth
/// 1): a blank picture is an error that names the likely causes, and nothing is written (without
/// --allow-empty).
int write_outputs(const RenderArgs& a, const render::Image& img) {
    if (!a.allow_empty && std::none_of(img.depth.begin(), img.depth.end(), [](float d) { return d < 1.0f; })) {
        std::cerr << "quadcast render: " << a.scene
                  << ": the picture is empty: nothing of the scene lies in the camera's view (check the camera's eye, target, near and far "
                     "against the objects); nothing written (--allow-empty writes the empty picture)\n";
        return 1;
    }
    try {
        render::write_png_and_pfm(a.output, a.depth, img);
    } catch (const std::exception& e) {
        std::cerr << "quadcast render: " << e.what() << "\n";
        return 1;
    }
    return 0;
}

/// The world box of a volume's samples (loads it; installed as the scene's volume box function).
scene::Aabb volume_box(const scene::Volume& v) {
    volume::VolumeRequest req;
    req.input = v.input;
    req.size = v.size;
    const volume::VolumeData d = volume::load_volume(req);
    try {
        volume::check_isovalue(d, v.iso);
    } catch (const volume::VolumeError& e) {
        throw scene::ParseError(v.iso_where, e.message() + " of '" + d.source + "'");
    }
    scene::Aabb b;
    b.extend(d.origin);
    b.extend(d.origin + cmul(d.spacing, scene::Vec3d{{double(d.nx() - 1), double(d.ny() - 1), double(d.nz() - 1)}}));
    return b;
}

/// The scene's volumes, loaded and prepared for the GL isosurface renderer or, with `cpu`, the
/// CPU reference renderer (which also keeps every active tetrahedron's coefficients), placed in
/// the frame `t` of the primitives and the camera. Long preparations report progress on stderr.
std::vector<render::VolumeModel> prepare_volumes(const scene::Scene& sc, bool cpu, const render::FrameTransform& t) {
    std::vector<render::VolumeModel> out;
    for (const scene::Volume& v : sc.volumes) {
        volume::VolumeRequest req;
        req.input = v.input;
        req.size = v.size;
        const volume::VolumeData d = volume::load_volume(req);
        for (const auto& w : d.warnings) std::cerr << w << "\n";
        try {
            volume::check_isovalue(d, v.iso);
        } catch (const volume::VolumeError& e) {
            throw std::runtime_error(scene::format_location(v.iso_where) + e.message() + " of '" + d.source + "'");
        }
        const render::VolumeScheme scheme = v.scheme == scene::Volume::Scheme::s31         ? render::VolumeScheme::s31
                                            : v.scheme == scene::Volume::Scheme::trilinear ? render::VolumeScheme::trilinear
                                                                                           : render::VolumeScheme::qss;
        // Progress in steps of 10% for volumes of more than 4M samples
        const bool big = double(d.nx()) * d.ny() * d.nz() > 4e6;
        int shown = 0;
        const render::ProgressFn progress = [&](double f) {
            const int step = int(f * 10.0);
            if (!big || step <= shown) return;
            shown = step;
            std::fprintf(stderr, "%s: preparing %s (%dx%dx%d, %s): %d%%\n", sc.source.string().c_str(), v.input.c_str(), d.nx(), d.ny(), d.nz(),
                         render::volume_scheme_name(scheme), 10 * step);
        };
        shapes::Appearance look;
        look.color = glm::vec3(float(v.material.color[0]), float(v.material.color[1]), float(v.material.color[2]));
        look.specular = float(v.material.specular);
        look.shininess = float(v.material.shininess);
        const Vec3<double> o = t.point(d.origin);
        try {
            out.push_back(shapes::isosurface(d.grid, glm::dvec3(o[0], o[1], o[2]),
                                             glm::dvec3(t.length(d.spacing[0]), t.length(d.spacing[1]), t.length(d.spacing[2])), float(v.iso),
                                             scheme, look, cpu, 0, progress));
        } catch (const std::invalid_argument& e) {
            scene::Location where = v.iso_where;
            where.field = where.field.substr(0, where.field.rfind('/'));  // the volume entry, not its "iso"
            throw std::runtime_error(scene::format_location(where) + e.what() + " ('" + d.source + "')");
        }
    }
    return out;
}

std::size_t active_cubes(const std::vector<render::VolumeModel>& volumes) {
    std::size_t n = 0;
    for (const auto& m : volumes) n += m.active;
    return n;
}

/// The CPU reference: primitives (if any), then the SLIM surfaces (bound by `patches`, the balls'
/// `slim_patches`, computed once per scene) and the volumes composited by depth.
render::Image render_scene_cpu(const render::Frame& fr, const std::vector<SlimPatch<float>>& patches, const std::vector<render::VolumeModel>& volumes,
                               render::FrameStats* st) {
    render::Image img;
    if (!fr.primitives.empty() || volumes.empty()) img = render::render_cpu(fr.primitives, fr.camera, fr.light, fr.options, st);
    if (!fr.slim_balls.empty()) {
        const render::Image s = render::render_slim_cpu(fr.slim_balls, fr.camera, fr.light, fr.options, nullptr, 0, &patches);
        if (img.rgba.empty()) img = s;
        else render::composite_by_depth(img, s);
    }
    if (volumes.empty()) return img;
    std::vector<const render::VolumeModel*> ptrs;
    for (const auto& m : volumes) ptrs.push_back(&m);
    render::Image v = render::render_volumes_cpu(ptrs, fr.camera, fr.light, fr.options);
    if (img.rgba.empty()) return v;
    render::composite_by_depth(img, v);
    return img;
}

int run_render(const RenderArgs& a) {
    // Output paths first: a render that cannot be written is not started.
    try {
        render::check_output_paths(a.output, a.depth);
    } catch (const std::exception& e) {
        std::cerr << "quadcast render: " << e.what() << "\n";
        return 1;
    }
    PhaseTimer timer(a.timing);
    scene::Scene sc;
    scene::set_volume_box_function(volume_box);
    slim::install_scene_loader();
    skin::install_scene_builder();
    try {
        sc = scene::load_scene(a.scene);
    } catch (const scene::ParseError& e) {
        std::cerr << e.what() << "\n";
        return 1;
    } catch (const std::bad_alloc&) {
        std::cerr << a.scene << ": out of memory while loading the scene\n";
        return 1;
    }
    timer.phase("load");
    for (const auto& w : sc.warnings) std::cerr << w.to_string() << "\n";
    render::Frame fr;
    try {
        fr = render::build_frame(sc, a.width, a.height);
    } catch (const std::bad_alloc&) {
        std::cerr << "quadcast render: " << a.scene << ": out of memory while building the frame\n";
        return 1;
    } catch (const std::exception& e) {
        std::cerr << "quadcast render: " << a.scene << ": " << e.what() << "\n";
        return 1;
    }
    // The frame holds the primitives now: the scene's own copies (and their origins) are dropped
    // before the renderers make theirs.
    release(sc.spheres);
    release(sc.ellipsoids);
    release(sc.cylinders);
    release(sc.cones);
    release(sc.quadrics);
    release(sc.quads);
    release(sc.slims);
    release(sc.origins);
    timer.phase("frame");
    for (const auto& n : fr.notes) std::cerr << a.scene << ": note: " << n << "\n";
    std::vector<render::VolumeModel> volumes;
    try {
        const auto t0 = std::chrono::steady_clock::now();
        volumes = prepare_volumes(sc, a.cpu, fr.transform);
        if (!volumes.empty())
            std::fprintf(stderr, "%s: %zu volume(s) prepared in %.1f ms, %zu active cubes\n", a.scene.c_str(), volumes.size(),
                         std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count(), active_cubes(volumes));
        // "method": "quadric": the QSS pieces join the primitives (Stoll's path) instead of the
        // isosurface renderers' cubes.
        std::vector<render::VolumeModel> kept;
        for (std::size_t i = 0; i < volumes.size(); ++i) {
            if (sc.volumes[i].method != scene::Volume::Method::quadric) {
                kept.push_back(std::move(volumes[i]));
                continue;
            }
            const auto t1 = std::chrono::steady_clock::now();
            const std::vector<render::Primitive> pieces = shapes::isosurface_quadrics(volumes[i]);
            fr.primitives.insert(fr.primitives.end(), pieces.begin(), pieces.end());
            if (fr.options.culling) {
                fr.options.culling = false;
                std::cerr << a.scene << ": note: " << render::isosurface_culling_note << "\n";
            }
            std::fprintf(stderr, "%s: %s: %zu QSS pieces as quadrics clipped to their tetrahedra (%.1f ms)\n", a.scene.c_str(),
                         sc.volumes[i].input.c_str(), pieces.size(),
                         std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t1).count());
        }
        volumes = std::move(kept);
    } catch (const std::bad_alloc&) {
        std::cerr << "quadcast render: " << a.scene << ": out of memory while preparing the volumes\n";
        return 1;
    } catch (const std::exception& e) {
        std::cerr << "quadcast render: " << e.what() << "\n";
        return 1;
    }
    if (!volumes.empty()) timer.phase("volumes");
    render::Image img;
    if (a.cpu) {
        render::FrameStats st;
        const std::vector<SlimPatch<float>> patches = render::slim_patches(fr.slim_balls);
        img = render_scene_cpu(fr, patches, volumes, &st);
        timer.phase("draw");
        if (a.frames > 0) {
            std::vector<double> ms;
            const render::Camera still = fr.camera;
            for (int i = 0; i < a.frames; ++i) {
                fr.camera = frame_camera_at(a, sc, fr, i);
                const auto t0 = std::chrono::steady_clock::now();
                img = render_scene_cpu(fr, patches, volumes, nullptr);
                ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
            }
            fr.camera = still;
            if (a.orbit != 0.0) img = render_scene_cpu(fr, patches, volumes, nullptr);  // (the picture of the scene's camera)
            std::printf("%s: %zu primitives, %zu volume(s) (%zu active cubes), %dx%d, median frame %.2f ms over %d frames%s (CPU reference), %llu casts, %llu culled\n",
                        a.scene.c_str(), fr.primitives.size(), volumes.size(), active_cubes(volumes), a.width, a.height, median(ms), a.frames,
                        orbit_note(a).c_str(), static_cast<unsigned long long>(st.fragments), static_cast<unsigned long long>(st.culled));
            if (!fr.slim_balls.empty()) std::printf("%s: %zu SLIM balls (CPU reference, per-ray blending)\n", a.scene.c_str(), fr.slim_balls.size());
        }
        const int rc = write_outputs(a, img);
        timer.phase("write");
        return rc;
    }
    std::unique_ptr<gl::OsmesaContext> ctx;
    try {
        ctx = std::make_unique<gl::OsmesaContext>();
    } catch (const std::exception& e) {
        std::cerr << "quadcast render: " << e.what() << " (use --cpu to render without OpenGL)\n";
        return 2;
    }
    timer.phase("context");
    try {
        gl::QuadricRenderer r(ctx->api());
        gl::IsosurfaceRenderer iso(ctx->api());
        gl::SlimRenderer slim(ctx->api());
        slim.set_precision(a.slim_bits);
        r.set_primitives(fr.primitives);
        slim.set_balls(fr.slim_balls);
        if (!fr.slim_balls.empty()) r.add_pass(slim);
        // (the renderer keeps its own copy)
        const std::size_t primitive_count = fr.primitives.size();
        const bool has_spheres = std::any_of(fr.primitives.begin(), fr.primitives.end(), [](const render::Primitive& p) { return p.variant == render::Variant::sphere; });
        release(fr.primitives);
        for (const auto& m : volumes) iso.add_volume(m);
        if (!volumes.empty()) r.add_pass(iso);
        timer.phase("upload");
        r.draw(fr.camera, fr.light, fr.options);  // warm-up: compiles the variants the scene uses
        timer.phase("draw");
        if (a.frames > 0) {
            std::vector<double> ms;
            for (int i = 0; i < a.frames; ++i) {
                const render::Camera cam = frame_camera_at(a, sc, fr, i);
                const auto t0 = std::chrono::steady_clock::now();
                r.draw(cam, fr.light, fr.options);
                ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
            }
            // (with --orbit, what follows is of the scene's camera again)
            if (a.orbit != 0.0) r.draw(fr.camera, fr.light, fr.options);
            std::printf("%s: %zu primitives, %dx%d, median frame %.2f ms over %d frames%s (%s)\n", a.scene.c_str(), primitive_count, a.width,
                        a.height, median(ms), a.frames, orbit_note(a).c_str(), ctx->info().renderer.c_str());
            if (fr.options.shadows && fr.options.shadow_map_reuse) {
                // The shadow map kept from earlier frames against drawn in every frame, interleaved
                // (the kept frames last, so that what is printed below is theirs).
                render::RenderOptions redraw = fr.options;
                redraw.shadow_map_reuse = false;
                bool every_kept = true;
                const auto [drawn, kept] = interleaved_medians(a.frames, [&](bool keep) {
                    r.draw(fr.camera, fr.light, keep ? fr.options : redraw);
                    if (keep) every_kept = every_kept && r.reused_shadow_map();
                });
                std::printf("%s: shadow map %s: median frame %.2f ms; drawn in every frame (\"shadow\": {\"reuse\": false}) %.2f ms; %.2fx, %d pairs interleaved\n",
                            a.scene.c_str(), every_kept ? "kept from the first frame" : "drawn again in some frames", kept, drawn, drawn / kept, a.frames);
            }
            if (fr.options.shadows) {
                // The penumbra's PCF samples gathered four at a time from the shadow map in phases
                // (the default) against read one by one, interleaved (the default last).
                const auto [single, gathered] = interleaved_medians(a.frames, [&](bool phases) {
                    r.set_shadow_phases(phases);
                    r.draw(fr.camera, fr.light, fr.options);
                });
                std::printf("%s: PCF samples gathered from the shadow map in phases: median frame %.2f ms; read one by one %.2f ms; %.2fx, %d pairs interleaved\n",
                            a.scene.c_str(), gathered, single, single / gathered, a.frames);
            }
            if (fr.options.occlusion_culling && r.unchanged_view()) {  // (a frame with its view unchanged reused a set)
                // The view unchanged: the records the picture shows drawn alone (the default)
                // against the occlusion test's set drawn alone, in alternating blocks (a switch
                // makes the renderer test again: each block draws until its set is drawn alone,
                // then times one frame; the default last).
                std::vector<double> picture, tested;
                std::size_t picture_drawn = 0, tested_drawn = 0;
                for (int i = 0; i < a.frames; ++i)
                    for (bool from_picture : {false, true}) {
                        r.set_shown_from_picture(from_picture);
                        for (int k = 0; k < 8; ++k) {  // (at least once: the switch is a change the renderer tests again)
                            r.draw(fr.camera, fr.light, fr.options);
                            if (from_picture ? r.shown_set_from_picture() : r.unchanged_view()) break;
                        }
                        const auto t0 = std::chrono::steady_clock::now();
                        r.draw(fr.camera, fr.light, fr.options);
                        (from_picture ? picture : tested).push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
                        (from_picture ? picture_drawn : tested_drawn) = r.drawn_primitives();
                    }
                std::printf("%s: view unchanged: the records the picture shows drawn alone, %zu primitives, median frame %.2f ms; the occlusion test's set "
                            "drawn alone, %zu primitives, %.2f ms; %.2fx, %d pairs in alternating blocks\n",
                            a.scene.c_str(), picture_drawn, median(picture), tested_drawn, median(tested), median(tested) / median(picture), a.frames);
            }
            if (r.reshaded()) {
                // The view unchanged: the spheres the picture shows shaded from the ids target (the
                // default) against drawn as sprites, interleaved (the default last).
                const auto [sprites, shaded] = interleaved_medians(a.frames, [&](bool reshade) {
                    r.set_reshade(reshade);
                    r.draw(fr.camera, fr.light, fr.options);
                });
                std::printf("%s: view unchanged: the spheres the picture shows shaded once per pixel from the ids target, median frame %.2f ms; "
                            "drawn as sprites %.2f ms; %.2fx, %d pairs interleaved\n",
                            a.scene.c_str(), shaded, sprites, sprites / shaded, a.frames);
            }
            if (slim.ball_count() > 0) {
                std::printf("%s: %zu SLIM balls, three passes, %d-bit float accumulation targets", a.scene.c_str(), slim.ball_count(), slim.precision());
                if (fr.options.culling) {
                    // What the vertex stage culls (the same tests on the host): per quadric, and by the patches' normal cones
                    const render::FrameSetup f = render::frame_setup(fr.camera, a.width, a.height);
                    std::size_t quadric = 0, either = 0;
                    for (std::size_t i = 0; i < fr.slim_balls.size(); ++i) {
                        quadric += render::culled(fr.slim_balls[i], f);
                        either += render::slim_ball_culled(fr.slim_balls[i], &slim.patches()[i], f, fr.options);
                    }
                    std::printf("; %zu culled per quadric (Stoll's eq. 18, perspective)", quadric);
                    if (fr.options.tight_bounds) std::printf(", %zu with the patches' normal cones", either);
                }
                std::printf("\n");
            }
            if (fr.options.occlusion_culling && r.unchanged_view() && r.shown_set_from_picture())
                std::printf("%s: the records an earlier frame's picture showed drawn alone, the view unchanged: %zu primitives drawn%s, %zu left out "
                            "(outside the view or hidden); no cull pass\n",
                            a.scene.c_str(), r.drawn_primitives(), r.reshaded() ? " (the spheres shaded from the ids target, a full-screen pass)" : "", r.occluded());
            else if (fr.options.occlusion_culling && r.unchanged_view())
                std::printf("%s: the last frame's shown set drawn alone, its view unchanged since the test that chose it: %zu primitives drawn, %zu left out by that test "
                            "(outside the view or hidden); no cull pass\n",
                            a.scene.c_str(), r.drawn_primitives(), r.occluded());
            else if (fr.options.occlusion_culling && r.cull_pass_ran())
                std::printf("%s: cull pass%s: %zu primitives drawn, %zu culled outside the view, %zu hidden behind %s%s; its compute passes %.1f ms (GL_TIME_ELAPSED)\n", a.scene.c_str(),
                            r.reused_shown_set() ? " reusing the last frame's shown set (2 phases)"
                            : r.phases() > 1 ? (" in " + std::to_string(r.phases()) + " phases").c_str() : "", r.drawn_primitives(), r.frustum_culled(), r.occluded(),
                            r.reused_shown_set() ? "what the shown set drew" : r.phases() > 1 ? "occluders or earlier phases" : "occluders",
                            r.expected_overlap() > 0.0 ? (" (expected overlap " + fmt_overlap(r.expected_overlap()) + ")").c_str() : "", r.cull_pass_ms());
            else if (fr.options.occlusion_culling && primitive_count > 0)
                std::printf("%s: no cull pass: expected overlap %s below occlusion_min_overlap %g (the primitives rarely hide one another); all %zu drawn\n",
                            a.scene.c_str(), fmt_overlap(r.expected_overlap()).c_str(), double(fr.options.occlusion_min_overlap), r.drawn_primitives());
            if (has_spheres)
                std::printf("%s: spheres %sdrawn as %s\n", a.scene.c_str(), r.reshaded() ? "shaded from the ids target in this frame; where " : "",
                            r.drew_points() ? "point sprites (one vertex each)"
                                            : "quads (not every sphere lies inside the view's side planes and beyond the near plane with a sprite small enough: render::sphere_points_fit)");
            if (gl::has_extension(ctx->api(), "GL_ARB_pipeline_statistics_query")) {
                // One more frame with the fragment count (not timed).
                r.set_count_fragments(true);
                r.draw(fr.camera, fr.light, fr.options);
                r.set_count_fragments(false);
                const render::Image shown = r.read();
                const auto visible = std::count_if(shown.depth.begin(), shown.depth.end(), [](float d) { return d < 1.0f; });
                const gl::FragmentCounts& c = r.fragment_counts();
                const double per = 1.0 / static_cast<double>(std::max<long long>(1, visible));
                std::printf("%s: %lld visible pixels; per visible pixel %.2f fragment-shader invocations (%llu; llvmpipe counts and shades all 16 of a "
                            "4x4 block), and counted fragment by fragment %.2f started (rasterised for the drawn primitives), %.2f shaded "
                            "(not behind the occluder depth image: cast their ray), %.2f hit\n",
                            a.scene.c_str(), static_cast<long long>(visible), static_cast<double>(c.invocations) * per,
                            static_cast<unsigned long long>(c.invocations), static_cast<double>(c.started) * per, static_cast<double>(c.cast) * per,
                            static_cast<double>(c.hit) * per);
            }
            for (std::size_t i = 0; i < iso.volume_count(); ++i) {
                const gl::IsoDrawStats& s = iso.stats(i);
                const char* what = volumes[i].scheme == render::VolumeScheme::trilinear ? "cells" : "relevant tetrahedra";
                std::printf("%s: volume %zu (%s): %zu active cubes, %zu in the view frustum, ", a.scene.c_str(), i, render::volume_scheme_name(volumes[i].scheme), s.active, s.visible);
                if (s.unchanged_view)
                    std::printf("%zu of %zu %s in view, %zu of them drawn: the last frame's shown set alone (its view and the depth under it unchanged since the "
                                "test that chose it; no test)", s.elements, s.relevant, what, s.alone);
                else
                    std::printf("%zu of %zu %s drawn in %d phase(s)", s.elements, s.relevant, what, s.phases);
                if (s.phases > 1) std::printf(", %zu of them culled behind the earlier phases%s", s.occluded, s.reused ? " (the first: the last frame's shown set)" : "");
                if (volumes[i].scheme != render::VolumeScheme::trilinear)
                    std::printf(", coefficients %s", s.pre_pass ? "from the compute pre-pass" : "averaged in the vertex stage");
                std::printf("\n");
            }
        }
        if (a.frames > 0) timer.phase("frames");
        img = r.read();
        timer.phase("read");
    } catch (const std::exception& e) {
        std::cerr << "quadcast render: " << e.what() << "\n";
        return 1;
    }
    const int rc = write_outputs(a, img);
    timer.phase("write");
    return rc;
}

}  // namespace

void add_render(CLI::App& app) {
    auto a = std::make_shared<RenderArgs>();
    CLI::App* cmd = app.add_subcommand("render", "render a JSON scene to a PNG");
    cmd->add_option("scene", a->scene, "scene file (JSON)")->required();
    cmd->add_option("-o,--output", a->output, "output PNG")->required();
    cmd->add_option("--width", a->width, "image width")->check(CLI::Range(1, 16384));
    cmd->add_option("--height", a->height, "image height")->check(CLI::Range(1, 16384));
    cmd->add_flag("--cpu", a->cpu, "render with the CPU reference renderer");
    cmd->add_flag("--allow-empty", a->allow_empty, "write the picture even when nothing of the scene is in view (otherwise an error)");
    cmd->add_option("--slim-bits", a->slim_bits, "bits per channel of the GL SLIM accumulation targets (16 or 32)")->check(CLI::IsMember({16, 32}));
    cmd->add_option("--depth", a->depth, "also write window depth as PFM (1.0 = background)");
    cmd->add_flag("--timing", a->timing, "print each phase's time and the resident memory after it to stderr (load, frame, context, upload, draw, read, write)");
    cmd->add_option("--frames", a->frames, "time this many frames after a warm-up; print the median")->check(CLI::Range(0, 100000));
    cmd->add_option("--orbit", a->orbit, "with --frames: each timed frame's camera orbits the target by this many degrees more, around the camera's up vector (a moving camera); the picture is the scene camera's")
        ->check(CLI::Range(-360.0, 360.0));
    cmd->callback([a] {
        if (a->orbit != 0.0 && a->frames == 0) throw CLI::ValidationError("--orbit", "needs --frames N with N > 0 (it moves the camera between timed frames)");
        const int rc = run_render(*a);
        if (rc) throw CLI::RuntimeError(rc);
    });
}

}  // namespace quadcast::cli
