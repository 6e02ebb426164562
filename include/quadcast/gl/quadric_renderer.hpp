// quadcast/gl/quadric_renderer.hpp -- OpenGL 4.5 renderer of quadric primitives (generated shaders)
#pragma once
// Host-only. One record per primitive in a shader storage buffer, pulled by gl_VertexID (no
// vertex attributes, no display lists): 4 indexed vertices = one bounding quad per primitive. The
// vertex stage does the per-primitive work once per corner (the tight screen rectangle or the
// bounding-sphere quad, culling; an index buffer shares the two corners of the quad's diagonal),
// the fragment stage casts the pixel's ray (`window_ray`: affine in the window position, so the
// image does not depend on the bounding geometry) and finishes the quadratic. Shaders come from
// the generated kernels, assembled per variant key (quadcast/render/variant_key.hpp: primitive
// shape, culling, camera model, forward or geometry buffer ...); a scene compiles only the
// variants it uses.

#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include "quadcast/gl/scene_pass.hpp"
#include "quadcast/render/types.hpp"
#include "quadcast/render/variant_key.hpp"

namespace quadcast::gl {

struct Api;

/// Renders primitives into an offscreen framebuffer (RGBA8 colour, 32-bit float depth) of the
/// context current when it is constructed, which must outlive it and be current whenever it is
/// used. Not thread-safe (GL contexts are not). Compiled in quadcast::gl (src/gl/quadric_renderer.cpp).
/// The fragments of a primitive pass (QuadricRenderer::set_count_fragments).
struct FragmentCounts {
    /// Fragment-shader invocations (GL_ARB_pipeline_statistics_query,
    /// GL_FRAGMENT_SHADER_INVOCATIONS): what the driver counts; llvmpipe counts all 16 of each 4x4
    /// block that has a fragment (and shades them, masked), a GPU its 2x2 quads.
    std::uint64_t invocations = 0;
    /// Counted fragment by fragment by the stages: the fragments rasterised for the drawn
    /// primitives (the stage started), those of them not behind the occluder depth image (the
    /// early discard: they cast their ray), and those whose ray hit the primitive (they reach
    /// the depth test).
    std::uint64_t started = 0, cast = 0, hit = 0;
};

class QuadricRenderer {
public:
    /// Makes the renderer's vertex array and buffers in the current context (`api`: its function
    /// table, e.g. `OsmesaContext::api()`).
    explicit QuadricRenderer(const Api& api);
    ~QuadricRenderer();
    QuadricRenderer(const QuadricRenderer&) = delete;
    QuadricRenderer& operator=(const QuadricRenderer&) = delete;

    /// Which fragment stage the forward pass uses (`quadcast bench fragments`): the pixel's ray
    /// from the frame's affine terms (`window_ray`, default); brute force, which rebuilds the
    /// pixel's world ray from gl_FragCoord (`pixel_ray`) and runs `local_ray` and `cast_ray` per
    /// fragment (same image, perspective camera and forward shading only); or a pass-through
    /// stage writing a constant colour and the rasterised depth over the same bounding quads
    /// (the fill-rate ceiling).
    using FragmentStage = render::FragmentStage;
    void set_fragment_stage(FragmentStage s);
    FragmentStage fragment_stage() const;
    /// Depth test of the primitive pass (on by default); off makes every rasterised fragment
    /// count in `samples_passed`. (A benchmark switch: with RenderOptions::occlusion_culling the
    /// primitives the cull pass leaves out are not rasterised either, so the picture differs.)
    void set_depth_test(bool on);
    /// Slab-bounded primitives (cylinders, cones, one-sheet hyperboloids) with tight bounds are
    /// drawn over the quadrilateral turned to their projected axis (`quadcast::slab_quad`, on by
    /// default) or, off, over their axis-aligned rectangle (`primitive_rect`). The same picture;
    /// a benchmark switch.
    void set_slab_quads(bool on);
    /// In frames that run the cull pass (RenderOptions::occlusion_culling, `cull_pass_ran`), the fragment stage first compares the primitive's
    /// nearest view distance with the cull pass's occluder depth at the pixel and discards the
    /// fragment before casting its ray when the primitive lies behind (on by default; not for the
    /// sphere variant, whose cast is about as cheap as the test, nor the planes variant). The same
    /// picture; a benchmark switch.
    void set_early_discard(bool on);
    /// In frames that run the cull pass (`cull_pass_ran`), a compute pass after the compaction computes, for the
    /// kept primitives only and on all threads, the clip positions of each one's four corners and
    /// its nearest view distance (the vertex stage's per-primitive work, from the same traced
    /// kernels), and the vertex stage only fetches them; off (the default), the vertex stage
    /// computes them, once per corner. The same picture; a benchmark switch. Off by default
    /// because it did not pay on llvmpipe: `quadcast bench spheres` / `bench sticks`, column 'comp'.
    void set_compute_bounds(bool on);
    /// Deferred shading with outlines (RenderOptions::silhouettes) and the depth test: the
    /// background's pixels get their outlines only in the 8 x 8 tiles where one may show, listed by
    /// a compute pass (a tile of which a pixel, or a neighbour of one, holds geometry) and drawn as
    /// one point each (the default); off, over the whole image. The same picture; a test switch.
    void set_outline_tiles(bool on);
    /// Soft shadows (RenderOptions::shadows) with the shadow map kept from an earlier frame
    /// (RenderOptions::shadow_map_reuse): the penumbra's 64 PCF samples read four at a time
    /// (textureGather) from the map in phases of the PCF step (an R32F image of step x step tiles,
    /// together a little larger than the map, made by a compute pass once per kept map), the
    /// default; off, one by one. The same picture; a test switch.
    void set_shadow_phases(bool on);
    /// Whether the last `draw`'s deferred pass read the shadow map in phases (set_shadow_phases).
    bool used_shadow_phases() const;
    /// A shown set drawn alone (`unchanged_view`) in the renderer's own target is the records the
    /// picture shows (the default): a frame whose camera has not moved since the last one also
    /// writes each pixel's record into an ids target (QuadricKey::ids), compute passes list the
    /// records left in it, and the next frame with the view unchanged draws those alone: a subset
    /// of the test's set (which keeps records whose bounds reach a pixel farther than their
    /// nearest distance), the same picture. A moving camera pays nothing for it (its views do not
    /// repeat); the first frame after it moves draws the smaller set first. Off, the test's set
    /// is drawn alone. The same picture either way; a switch for benchmarks and tests.
    void set_shown_from_picture(bool on);
    /// Whether the last `draw` drew alone the records an earlier frame's picture showed, its view
    /// unchanged (set_shown_from_picture; `unchanged_view` is then true too).
    bool shown_set_from_picture() const;
    /// In a frame that draws the records the picture shows (`shown_set_from_picture`), the sphere
    /// variant's are not drawn as sprites: a full-screen pass reads at each pixel the record the
    /// ids target holds (written by the frame that listed them, the view unchanged since) and casts
    /// and shades it with the sprites' code (QuadricKey::reshade): the same picture and depth, one
    /// fragment per pixel, no vertex per sphere; the light and the material may change between the
    /// frames (the ids say which record shows, not its colour). On by default; off, the sprites are
    /// drawn. A switch for benchmarks and tests.
    void set_reshade(bool on);
    /// Whether the last `draw` shaded the sphere variant from the ids target (set_reshade).
    bool reshaded() const;
    /// A frame reusing the last one's shown set (RenderOptions::occlusion_reuse) whose view -- the
    /// camera's matrices, the viewport, back-face culling, the primitives and settings -- is the one
    /// that set was tested under draws the set alone (the default): that test kept every primitive
    /// that can show in this view, so the picture is complete, and testing again could only keep a
    /// subset. Off, it tests every primitive against what the set drew, as a frame after the camera
    /// moved does. The same picture either way; a switch for benchmarks and tests.
    void set_skip_unchanged_view_test(bool on);
    /// In frames that run the cull pass (`cull_pass_ran`), the occluders reach its depth image by a
    /// compute pass that writes each occluder's disks pixel by pixel (the default), or, on, drawn by
    /// the rasteriser into the depth buffer first (one quadrilateral per record,
    /// `quadcast::occluder_corner`: a square inside a sphere's disk, a rectangle along a stick's
    /// axis), whose depths the cull pass then reads. The same picture; fewer pixels occluded (the
    /// quadrilaterals cover less than the disks). Off by default because it did not pay on
    /// llvmpipe, whose rasteriser spent as long on the quadrilaterals as the compute pass on the
    /// disks: `quadcast bench spheres` / `bench sticks`, column 'rast'.
    void set_raster_occluders(bool on);
    /// The sphere variant drawn as point sprites, one vertex per sphere (`quadcast::point_sprite`:
    /// the square around the bounding quad's corners), in frames where every sphere fits
    /// (`quadcast::render::sphere_points_fit`: inside the view's side planes, beyond the near plane,
    /// sprites within GL_POINT_SIZE_RANGE), else quads of four vertices. On by default: llvmpipe
    /// runs the vertex stage on one thread (`quadcast bench spheres`, column 'quads'). The same
    /// picture. Not with `set_compute_bounds`, whose corners the quads' vertex stage fetches.
    void set_point_sprites(bool on);
    /// Whether the last frame's (or `draw_primitives`') sphere variant was drawn as point sprites.
    bool drew_points() const;
    /// The compute passes over records dispatch their workgroups (64 records each) in rows of at
    /// most this many (default and upper limit 65535, GL's guaranteed limit per dimension), so
    /// that a variant with more than 4M primitives can be culled. A test switch: smaller rows
    /// give the same picture.
    void set_dispatch_row_limit(std::uint32_t groups);
    /// Samples that passed (GL_SAMPLES_PASSED) in the primitive pass of the last `draw`.
    std::uint64_t samples_passed() const;
    /// Count the fragments of the primitive pass (the quadric primitives, not the added passes) in
    /// the next draws (`fragment_counts`); off by default: the pass then uses counting variants of
    /// its fragment stages (an atomic add per fragment at three points; the same picture, slower:
    /// not for timed frames). Throws std::runtime_error when the context does not have
    /// GL_ARB_pipeline_statistics_query.
    void set_count_fragments(bool on);
    /// The fragment counts of the primitive pass of the last `draw` with `set_count_fragments`.
    const FragmentCounts& fragment_counts() const;
    /// fragment_counts().invocations.
    std::uint64_t fragment_invocations() const;
    /// Other geometry (e.g. isosurfaces) drawn in every pass after the primitives; `p` must
    /// outlive its use here. `clear_passes` removes them.
    void add_pass(ScenePass& p);
    void clear_passes();

    /// Uploads the primitives (grouped by variant). Call again when they change. Throws
    /// std::invalid_argument (quadcast::render::validate) for a primitive that cannot be drawn
    /// as it says, before anything is uploaded.
    void set_primitives(const std::vector<render::Primitive>& prims);

    /// Draws one frame into the offscreen framebuffer and waits for it (glFinish).
    void draw(const render::Camera& cam, const render::Light& light, const render::RenderOptions& opt);

    /// Draws every variant's primitives with the forward or geometry-buffer programs into the
    /// bound framebuffer (a host application's own: its viewport and depth test, the caller's
    /// clears; the depth written is each surface's own window depth under `cam`), then the other
    /// passes (`add_pass`). With opt.occlusion_culling the cull pass runs first where it pays, as
    /// in `draw` (frustum culling and occlusion by these primitives' own occluders, in one phase,
    /// where the viewport's expected overlap reaches opt.occlusion_min_overlap: no phased drawing
    /// here, so tetrahedral pieces fall under that rule too; the same picture), and
    /// `cull_pass_ran`, `drawn_primitives`, `frustum_culled`, `occluded` count its outcome. Shadows,
    /// outlines and the full-screen deferred shading are `draw`'s only. Leaves the GL state it
    /// sets (program, vertex array, storage-buffer bindings, depth clamp off) for the caller to restore.
    void draw_primitives(const render::Camera& cam, const render::Light& light, const render::RenderOptions& opt, bool deferred);

    /// Reads back the last frame (rows top first, like the CPU renderer).
    render::Image read() const;

    std::size_t primitive_count() const;
    /// The primitives the last `draw` drew: where its cull pass ran, those it kept (in the
    /// frustum and not hidden by occluders), else all of them.
    std::size_t drawn_primitives() const;
    /// Whether the last `draw`'s (or `draw_primitives`') camera pass ran the cull pass:
    /// RenderOptions::occlusion_culling and an expected overlap of at least
    /// RenderOptions::occlusion_min_overlap (or phased drawing).
    bool cull_pass_ran() const;
    /// The phases the last `draw`'s camera pass drew in (RenderOptions::occlusion_phases where it
    /// drew a phased variant: tetrahedral pieces, or sticks and other primitives without a single
    /// occluder disk; 2 where it reused the last frame's shown set, 1 where its view was the one the
    /// set was tested under; else 1).
    int phases() const;
    /// Whether the last `draw`'s camera pass drew the last frame's shown set first
    /// (RenderOptions::occlusion_reuse).
    bool reused_shown_set() const;
    /// Whether it drew that set alone, its view unchanged since the set's test
    /// (`set_skip_unchanged_view_test`; `phases` is then 1).
    bool unchanged_view() const;
    /// Whether the last `draw` kept the shadow map of an earlier frame instead of drawing it
    /// (RenderOptions::shadow_map_reuse).
    bool reused_shadow_map() const;
    /// The expected overlap (render::expected_overlap) the last camera pass decided on; 0 where
    /// it did not estimate one (occlusion culling off, occlusion_min_overlap 0, phased drawing).
    double expected_overlap() const;
    /// Of the last `draw`'s primitives, those its cull pass left out because they cannot reach a
    /// pixel of the viewport (behind the eye or off screen), and those hidden behind occluders
    /// or, in phased drawing, behind what the earlier phases drew (0 where the cull pass did not run).
    /// Where it drew the shown set alone (`unchanged_view`: no compute pass ran, `cull_pass_ms` is
    /// 0), the first is 0 and the second every primitive not in the set (off screen ones too).
    std::size_t frustum_culled() const;
    std::size_t occluded() const;
    /// GPU time (GL_TIME_ELAPSED) of the last `draw`'s cull passes (the camera's and the shadow
    /// map's), in milliseconds; 0 where none ran.
    double cull_pass_ms() const;

private:
    class Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace quadcast::gl
