// src/gl/quadric_renderer.cpp -- quadcast::gl::QuadricRenderer, compiled once in the quadcast::gl library
// (the header declares the interface only, so an includer parses no GL function table, program
// cache or record packing).

#include "quadcast/gl/quadric_renderer.hpp"
#include "quadcast/gl/depth_pyramid.hpp"

#include <algorithm>
#include <atomic>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <iterator>
#include <limits>
#include <map>
#include <memory>
#include <stdexcept>
#include <span>
#include <string>
#include <vector>

#include "quadcast/bounds.hpp"
#include "quadcast/gl/framebuffer.hpp"
#include "quadcast/gl/generated_programs.hpp"
#include "quadcast/gl/loader.hpp"
#include "quadcast/gl/program.hpp"
#include "quadcast/gl/validate.hpp"
#include "frame_uniforms.hpp"
#include "quadcast/occlusion.hpp"
#include "quadcast/render/light_camera.hpp"
#include "quadcast/render/occluder.hpp"
#include "quadcast/render/point_sprites.hpp"
#include "quadcast/render/record.hpp"
#include "quadcast/render/window_ray.hpp"
#include "quadcast/shading.hpp"

namespace quadcast::gl {

/// The std430 record of one primitive (quadcast::render::record_layout; `qc_Primitive` in the
/// generated shaders is declared from the same layout).
using PrimitiveRecord = std::array<float, render::record_slots * 4>;
static_assert(sizeof(PrimitiveRecord) == 16 * render::record_slots);

namespace detail {

/// View-space corners of the near-plane rectangle (for primitives whose bounding sphere contains
/// the eye), slightly inside the near plane so they are not clipped.
std::array<float, 12> near_corners(const render::Camera& cam) {
    Mat4<double> P{};
    for (int j = 0; j < 4; ++j) for (int i = 0; i < 4; ++i) P[j][i] = static_cast<double>(cam.projection[j][i]);
    std::array<float, 12> r{};
    const double ndc[4][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
    for (int k = 0; k < 4; ++k) {
        if (cam.orthographic) {
            // x_ndc = P00 x + P30, y_ndc = P11 y + P31; z just in front of the near plane.
            const double x = (ndc[k][0] - P[3][0]) / P[0][0], y = (ndc[k][1] - P[3][1]) / P[1][1];
            const double zn = (-1.0 - P[3][2]) / P[2][2];
            r[static_cast<std::size_t>(3 * k)] = static_cast<float>(x);
            r[static_cast<std::size_t>(3 * k + 1)] = static_cast<float>(y);
            r[static_cast<std::size_t>(3 * k + 2)] = static_cast<float>(zn * 0.999);
        } else {
            // Perspective: z_ndc = -1 at z = -n with n = P32 / (P22 - 1); x_ndc = (P00 x + P20 z) / -z.
            const double n = P[3][2] / (P[2][2] - 1.0) * 1.001;
            const double z = -n;
            const double x = (ndc[k][0] * n - P[2][0] * z) / P[0][0], y = (ndc[k][1] * n - P[2][1] * z) / P[1][1];
            r[static_cast<std::size_t>(3 * k)] = static_cast<float>(x);
            r[static_cast<std::size_t>(3 * k + 1)] = static_cast<float>(y);
            r[static_cast<std::size_t>(3 * k + 2)] = static_cast<float>(z);
        }
    }
    return r;
}

/// P22, P32, P23, P33 of the camera's projection (uniform qc_pz: view z -> window depth).
std::array<float, 4> projection_pz(const render::Camera& cam) {
    return {cam.projection[2][2], cam.projection[3][2], cam.projection[2][3], cam.projection[3][3]};
}

void set_camera_uniforms(const Api& gl, const Program& p, const render::Camera& cam, int width, int height) {
    float view[16], proj[16], rot_inv[9];
    for (int j = 0; j < 4; ++j)
        for (int i = 0; i < 4; ++i) { view[j * 4 + i] = cam.view[j][i]; proj[j * 4 + i] = cam.projection[j][i]; }
    // The inverse of a rotation is its transpose: column j of R^T is row j of R.
    for (int j = 0; j < 3; ++j)
        for (int i = 0; i < 3; ++i) rot_inv[j * 3 + i] = cam.view[i][j];
    const float vz_row[3] = {cam.view[0][2], cam.view[1][2], cam.view[2][2]};
    const std::array<float, 4> pz = projection_pz(cam);
    const auto near = near_corners(cam);
    gl.UniformMatrix4fv(p.uniform_location("qc_view"), 1, GL_FALSE, view);
    gl.UniformMatrix4fv(p.uniform_location("qc_projection"), 1, GL_FALSE, proj);
    gl.UniformMatrix3fv(p.uniform_location("qc_view_rot_inv"), 1, GL_FALSE, rot_inv);
    gl.Uniform3fv(p.uniform_location("qc_eye"), 1, cam.eye.c);
    const Mat4<float> vp = render::view_projection(cam);
    gl.UniformMatrix4fv(p.uniform_location("qc_view_projection"), 1, GL_FALSE, &vp[0][0]);
    const render::WindowRayTerms rays = render::window_ray_terms(cam, width, height);
    gl.Uniform3fv(p.uniform_location("qc_ray_base"), 1, rays.base.c);
    gl.Uniform3fv(p.uniform_location("qc_ray_dx"), 1, rays.dx.c);
    gl.Uniform3fv(p.uniform_location("qc_ray_dy"), 1, rays.dy.c);
    gl.Uniform3fv(p.uniform_location("qc_ray_fixed"), 1, rays.fixed.c);
    gl.Uniform2f(p.uniform_location("qc_viewport"), static_cast<float>(width), static_cast<float>(height));
    gl.Uniform3fv(p.uniform_location("qc_near_corners"), 4, near.data());
    gl.Uniform3fv(p.uniform_location("qc_vz_row"), 1, vz_row);
    gl.Uniform1f(p.uniform_location("qc_vz_t"), cam.view[3][2]);
    gl.Uniform4fv(p.uniform_location("qc_pz"), 1, pz.data());
}

}  // namespace detail

class QuadricRenderer::Impl {
public:
    explicit Impl(const Api& api) : api_(&api) {
        api.GenVertexArrays(1, &vao_);
        api.GenBuffers(1, &ssbo_);
        api.GenBuffers(1, &planes_);
        api.GenBuffers(1, &indices_);
        api.GenBuffers(1, &occluders_);
        api.GenBuffers(1, &depths_);
        api.GenBuffers(1, &visible_);
        api.GenBuffers(1, &commands_);
        api.GenBuffers(1, &keep_);
        api.GenBuffers(1, &groups_);
        api.GenBuffers(1, &corners_);
        api.GenBuffers(1, &nearests_);
        api.GenBuffers(1, &keep2_);
        api.GenBuffers(1, &groups2_);
        api.GenBuffers(1, &commands2_);
        api.GenBuffers(1, &tiles_);
        api.GenBuffers(1, &tile_command_);
        api.GenBuffers(1, &owner_bits_);
        api.GenBuffers(1, &owner_groups_);
        GLfloat sizes[2] = {1.0f, 1.0f};
        api.GetFloatv(GL_POINT_SIZE_RANGE, sizes);
        max_point_size_ = sizes[1];
    }
    ~Impl() {
        if (etex_) api_->DeleteTextures(1, &etex_);
        if (depth_view_) api_->DeleteTextures(1, &depth_view_);
        release_shadow_map();
        release_fbo();
        api_->DeleteBuffers(1, &ssbo_);
        api_->DeleteBuffers(1, &tiles_);
        api_->DeleteBuffers(1, &tile_command_);
        api_->DeleteBuffers(1, &planes_);
        api_->DeleteBuffers(1, &indices_);
        api_->DeleteBuffers(1, &occluders_);
        api_->DeleteBuffers(1, &depths_);
        api_->DeleteBuffers(1, &visible_);
        api_->DeleteBuffers(1, &commands_);
        api_->DeleteBuffers(1, &keep_);
        api_->DeleteBuffers(1, &groups_);
        api_->DeleteBuffers(1, &corners_);
        api_->DeleteBuffers(1, &nearests_);
        api_->DeleteBuffers(1, &keep2_);
        api_->DeleteBuffers(1, &groups2_);
        api_->DeleteBuffers(1, &commands2_);
        api_->DeleteBuffers(1, &owner_bits_);
        api_->DeleteBuffers(1, &owner_groups_);
        for (ShownSet& s : shown_)
            for (GLuint b : {s.list, s.owners.buffer, s.owners.list})
                if (b) api_->DeleteBuffers(1, &b);
        api_->DeleteVertexArrays(1, &vao_);
        if (query_) api_->DeleteQueries(1, &query_);
        if (fs_query_) api_->DeleteQueries(1, &fs_query_);
        if (count_buffer_) api_->DeleteBuffers(1, &count_buffer_);
        for (GLuint q : cull_queries_)
            if (q) api_->DeleteQueries(1, &q);
    }
    Impl(const Impl&) = delete;
    Impl& operator=(const Impl&) = delete;

    /// Which fragment stage the forward pass uses (`quadcast bench fragments`): the pixel's ray
    /// from the frame's affine terms (`window_ray`, default); brute force, which rebuilds the pixel's world ray
    /// from gl_FragCoord (`pixel_ray`) and runs `local_ray` and `cast_ray` per fragment (same image,
    /// perspective camera and forward shading only); or a pass-through stage writing a constant
    /// colour and the rasterised depth over the same bounding quads (the fill-rate ceiling).
    using FragmentStage = render::FragmentStage;
    void set_fragment_stage(FragmentStage s) {
        stage_ = s;
        ++revision_;
    }
    FragmentStage fragment_stage() const { return stage_; }
    /// Depth test of the primitive pass (on by default); off makes every rasterised fragment
    /// count in `samples_passed`.
    void set_depth_test(bool on) {
        depth_test_ = on;
        ++revision_;
    }
    void set_slab_quads(bool on) {
        slab_quads_ = on;
        ++revision_;
    }
    void set_early_discard(bool on) {
        early_discard_ = on;
        ++revision_;
    }
    void set_compute_bounds(bool on) {
        compute_bounds_ = on;
        ++revision_;
    }
    void set_raster_occluders(bool on) {
        raster_occluders_ = on;
        ++revision_;
    }
    void set_point_sprites(bool on) {
        point_sprites_ = on;
        ++revision_;
    }
    void set_outline_tiles(bool on) { outline_tiles_ = on; }
    void set_shadow_phases(bool on) { shadow_phases_ = on; }
    void set_shown_from_picture(bool on) {
        shown_from_picture_ = on;
        ++revision_;
    }
    bool shown_set_from_picture() const { return picture_set_drawn_; }
    void set_reshade(bool on) { reshade_ = on; }
    bool reshaded() const { return reshaded_; }
    bool used_shadow_phases() const { return phases_used_; }

    /// Whether the deferred pass may read the shadow map in phases (set_shadow_phases); it does where
    /// they are made, for a map kept from an earlier frame.
    bool phases_for(const render::RenderOptions& opt) const { return opt.shadows && shadow_phases_ && opt.pcf_step >= 1; }
    /// Whether the shadow map in phases holds the current map (the same key, so the same depths
    /// even where the map was drawn again) for this PCF step.
    bool phases_ready(const render::RenderOptions& opt) const { return ptex_ != 0 && shadow_valid_ && phases_step_ == opt.pcf_step && phases_key_ == shadow_key_; }
    void set_skip_unchanged_view_test(bool on) {
        keep_unchanged_sets_ = on;
        ++revision_;
    }
    /// Whether the last `draw_primitives` drew the sphere variant as point sprites.
    bool drew_points() const { return points_; }
    void set_dispatch_row_limit(std::uint32_t groups) {
        row_limit_ = std::clamp<std::uint32_t>(groups, 1u, 65535u);
        ++revision_;
    }
    /// Samples that passed (GL_SAMPLES_PASSED) in the primitive pass of the last `draw`.
    std::uint64_t samples_passed() const { return samples_passed_; }
    /// Count the fragments of the primitive pass in the next draws (see QuadricRenderer); off by
    /// default. Throws std::runtime_error when the context does not have the extension.
    void set_count_fragments(bool on) {
        if (on && !has_extension(*api_, "GL_ARB_pipeline_statistics_query"))
            throw std::runtime_error("quadcast::gl::QuadricRenderer: the context has no GL_ARB_pipeline_statistics_query (fragment shader invocations)");
        count_fragments_ = on;
    }
    std::uint64_t fragment_invocations() const { return counts_.invocations; }
    const FragmentCounts& fragment_counts() const { return counts_; }
    /// Other geometry (e.g. isosurfaces) drawn in every pass after the primitives; `p` must
    /// outlive its use here. `clear_passes` removes them.
    void add_pass(ScenePass& p) {
        passes_.push_back(&p);
        ++revision_;
    }
    void clear_passes() {
        passes_.clear();
        ++revision_;
    }

    /// Uploads the primitives (grouped by variant). Call again when they change. Throws
    /// std::invalid_argument (quadcast::render::validate) for a primitive that cannot be drawn
    /// as it says, before anything is uploaded.
    void set_primitives(const std::vector<render::Primitive>& prims) {
        gl::validate_primitives(prims);
        ++revision_;
        std::vector<PrimitiveRecord> records;
        std::vector<float> planes;  // 16 floats per primitive of the planes variant, in record order
        std::vector<float> occluders;  // per record its centre, render::occluder_radius, its bounding radius, render::occluder_half_axis
        records.reserve(prims.size());
        occluders.reserve(8 * prims.size());
        bounds_lo_ = {{1e300, 1e300, 1e300}};
        bounds_hi_ = {{-1e300, -1e300, -1e300}};
        render::grow_by_bounds(prims, bounds_lo_, bounds_hi_);
        std::size_t n_without_disk = 0;  // non-planes primitives that do not occlude with one disk (`phased_variant`)
        sphere_lo_ = {{std::numeric_limits<float>::infinity(), std::numeric_limits<float>::infinity(), std::numeric_limits<float>::infinity()}};
        sphere_hi_ = {{-std::numeric_limits<float>::infinity(), -std::numeric_limits<float>::infinity(), -std::numeric_limits<float>::infinity()}};
        sphere_radius_ = 0.0f;
        each_sphere_.clear();
        each_sphere_key_.clear();
        for (int v = 0; v < render::variant_count; ++v) {
            ranges_[v] = {static_cast<std::uint32_t>(records.size()), 0};
            for (const auto& p : prims) {
                if (static_cast<int>(p.variant) != v) continue;
                records.push_back(render::pack_record(p));
                if (p.variant == render::Variant::sphere) {
                    for (int i = 0; i < 3; ++i) {
                        sphere_lo_[i] = std::min(sphere_lo_[i], p.shape.center[i]);
                        sphere_hi_[i] = std::max(sphere_hi_[i], p.shape.center[i]);
                    }
                    sphere_radius_ = std::max(sphere_radius_, p.shape.radius);
                    if (each_sphere_.size() <= each_sphere_limit) each_sphere_.push_back({p.shape.center[0], p.shape.center[1], p.shape.center[2], p.shape.radius});
                }
                const render::OccluderShape o = render::occluder_shape(p);
                occluders.insert(occluders.end(), {p.shape.center[0], p.shape.center[1], p.shape.center[2], o.r_in, p.shape.radius, o.half_axis[0], o.half_axis[1], o.half_axis[2]});
                n_without_disk += p.variant != render::Variant::planes && (!(o.r_in > 0.0f) || render::occluder_is_chain(o));
                if (p.variant == render::Variant::planes)
                    for (const auto& pl : p.shape.planes) planes.insert(planes.end(), pl.c, pl.c + 4);
            }
            ranges_[v].second = static_cast<std::uint32_t>(records.size()) - ranges_[v].first;
        }
        api_->BindBuffer(GL_SHADER_STORAGE_BUFFER, planes_);
        api_->BufferData(GL_SHADER_STORAGE_BUFFER, static_cast<GLsizeiptr>(std::max<std::size_t>(1, planes.size()) * sizeof(float)),
                         planes.empty() ? nullptr : planes.data(), GL_STATIC_DRAW);
        api_->BindBuffer(GL_SHADER_STORAGE_BUFFER, ssbo_);
        api_->BufferData(GL_SHADER_STORAGE_BUFFER, static_cast<GLsizeiptr>(std::max<std::size_t>(1, records.size()) * sizeof(PrimitiveRecord)),
                         records.empty() ? nullptr : records.data(), GL_STATIC_DRAW);
        upload(occluders_, occluders);
        // Phased drawing (RenderOptions::occlusion_phases): whether every planes primitive shows
        // only inside its bounding ball; whether the other variants are phased (`phases_others_`);
        // a sample of the phased records for the phases' cuts.
        planes_in_ball_ = true;
        phase_sample_.clear();
        {
            const std::size_t n_planes = ranges_[static_cast<int>(render::Variant::planes)].second, n_others = prims.size() - n_planes;
            for (const auto& p : prims) {
                if (p.variant != render::Variant::planes) continue;
                Vec4<double> pl[4];
                for (int k = 0; k < 4; ++k) pl[k] = cast<double>(p.shape.planes[static_cast<std::size_t>(k)]);
                planes_in_ball_ = planes_in_ball_ && planes_within_ball(pl, double(p.shape.radius));
            }
            phases_others_ = n_others >= phase_min_count && 2 * n_without_disk >= n_others;
            phases_planes_ = planes_in_ball_ && n_planes >= phase_min_count;
            const std::size_t phased = (phases_planes_ ? n_planes : 0) + (phases_others_ ? n_others : 0);
            const std::size_t stride = std::max<std::size_t>(1, phased / 4096);
            std::size_t i = 0;
            for (const auto& p : prims) {
                if (!(p.variant == render::Variant::planes ? phases_planes_ : phases_others_)) continue;
                if (i++ % stride == 0) phase_sample_.push_back({p.shape.center[0], p.shape.center[1], p.shape.center[2], p.shape.radius});
            }
        }
        overlap_sample_ = render::overlap_sample(prims);
        for (ShownSet& s : shown_) {
            if (!s.buffer) api_->GenBuffers(1, &s.buffer);
            upload(s.buffer, std::vector<std::uint32_t>(std::max<std::size_t>(1, records.size())));
            if (!s.list) api_->GenBuffers(1, &s.list);
            upload(s.list, std::vector<std::uint32_t>(std::max<std::size_t>(1, records.size())));
            s.owners.capacity = 0;  // (allocated by the first make_owner_set)
            s.valid = s.all = s.listed = s.owners.valid = s.of_picture = false;
            s.target = 0;
        }
        reused_ = view_unchanged_ = picture_set_drawn_ = false;
        cull_pass_ran_ = false;
        phase_count_ = 1;
        expected_overlap_ = 0.0;
        upload(visible_, std::vector<std::uint32_t>(std::max<std::size_t>(1, records.size())));
        upload(keep_, std::vector<std::uint32_t>(std::max<std::size_t>(1, records.size())));
        upload(keep2_, std::vector<std::uint32_t>(std::max<std::size_t>(1, records.size())));
        upload(commands2_, std::vector<std::uint32_t>(5 * render::variant_count));
        api_->BindBuffer(GL_SHADER_STORAGE_BUFFER, 0);
        count_ = records.size();
        drawn_ = count_;
        // Two triangles per bounding quad over its 4 corners, so the vertex stage runs 4 times
        // per primitive (the post-transform cache reuses the shared corners).
        std::vector<std::uint32_t> idx(6 * std::max<std::size_t>(1, count_));
        for (std::size_t i = 0; i < idx.size() / 6; ++i) {
            const auto b = static_cast<std::uint32_t>(4 * i);
            const std::uint32_t quad[6] = {b, b + 1, b + 2, b, b + 2, b + 3};
            std::copy_n(quad, 6, idx.begin() + static_cast<std::ptrdiff_t>(6 * i));
        }
        api_->BindVertexArray(vao_);
        api_->BindBuffer(GL_ELEMENT_ARRAY_BUFFER, indices_);
        api_->BufferData(GL_ELEMENT_ARRAY_BUFFER, static_cast<GLsizeiptr>(idx.size() * sizeof(std::uint32_t)), idx.data(), GL_STATIC_DRAW);
        api_->BindVertexArray(0);
    }

    /// Draws one frame into the offscreen framebuffer and waits for it (glFinish).
    void draw(const render::Camera& cam, const render::Light& light, const render::RenderOptions& opt) {
        const Api& gl = *api_;
        cull_queries_used_ = 0;
        cull_ms_ = 0.0;
        phases_used_ = false;
        ensure_fbo(opt.width, opt.height);
        // Other passes shade forward without environment reflection: with an environment they
        // go through the geometry buffer (the same image for the primitives).
        const bool deferred = opt.deferred || opt.silhouettes || opt.shadows || (opt.environment && !passes_.empty()) ||
                              std::any_of(passes_.begin(), passes_.end(), [](const ScenePass* p) { return p->needs_gbuffer(); });
        if (opt.environment) ensure_environment(opt.environment);
        gl.BindVertexArray(vao_);
        gl.BindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, ssbo_);
        gl.BindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, planes_);
        if (opt.shadows) {
            // Shadow map: the geometry-buffer programs from the light camera, depth only.
            Vec3<double> lo = bounds_lo_, hi = bounds_hi_;
            for (const ScenePass* p : passes_) {
                Vec3<double> plo{}, phi{};
                p->bounds(plo, phi);
                for (int i = 0; i < 3; ++i) {
                    lo[i] = std::min(lo[i], plo[i]);
                    hi[i] = std::max(hi[i], phi[i]);
                }
            }
            light_cam_ = render::light_camera({}, light, lo, hi);
            ensure_shadow_map(opt.shadow_map_size);
            std::vector<std::uint64_t> key = shadow_key(opt);
            shadow_reused_ = opt.shadow_map_reuse && shadow_valid_ && key == shadow_key_;
            if (!shadow_reused_) {
                gl.BindFramebuffer(GL_FRAMEBUFFER, sfbo_);
                gl.Viewport(0, 0, shadow_size_, shadow_size_);
                const float clear_one = 1.0f;
                gl.ClearBufferfv(GL_DEPTH, 0, &clear_one);
                gl.Enable(GL_DEPTH_TEST);
                gl.DepthFunc(GL_LESS);
                if (opt.occlusion_culling) rasterise_occluders(light_cam_, opt, shadow_size_, shadow_size_);
                draw_primitives(light_cam_, light, opt, true, opt.occlusion_culling, stex_);  // culled from the light: what it cannot see casts no shadow
                // Kept for the next frames where every pass tracks its revision.
                shadow_valid_ = std::all_of(passes_.begin(), passes_.end(), [](const ScenePass* p) { return p->revision() != 0; });
                shadow_key_ = std::move(key);
            } else if (phases_for(opt) && !phases_ready(opt)) {
                // Made for a map kept from an earlier frame: where the map changes every frame,
                // making them (about 15 ms at 2048^2 on llvmpipe) costs more than they save.
                make_shadow_phases(opt.pcf_step);
            }
        } else {
            shadow_reused_ = false;
        }
        const float bg[4] = {opt.background[0], opt.background[1], opt.background[2], 1.0f};
        const float one = 1.0f;
        if (deferred) {
            // Geometry buffer: normal + depth (background: depth 1), ray direction + covered, colour.
            ensure_gbuffer();
            gl.BindFramebuffer(GL_FRAMEBUFFER, gfbo_);
            const Vec4<float> cleared = cleared_gnormal<float>();
            const float gn_clear[4] = {cleared[0], cleared[1], cleared[2], cleared[3]}, zero[4] = {0.0f, 0.0f, 0.0f, 0.0f};
            gl.ClearBufferfv(GL_COLOR, 0, gn_clear);
            gl.ClearBufferfv(GL_COLOR, 1, zero);
            gl.ClearBufferfv(GL_COLOR, 2, zero);
        } else {
            gl.BindFramebuffer(GL_FRAMEBUFFER, fbo_);
            gl.ClearBufferfv(GL_COLOR, 0, bg);
        }
        gl.Viewport(0, 0, opt.width, opt.height);
        gl.ClearBufferfv(GL_DEPTH, 0, &one);
        if (depth_test_) gl.Enable(GL_DEPTH_TEST); else gl.Disable(GL_DEPTH_TEST);
        gl.DepthFunc(GL_LESS);
        if (opt.occlusion_culling && depth_test_) rasterise_occluders(cam, opt, opt.width, opt.height);  // (before the primitive pass's queries)
        if (!query_) gl.GenQueries(1, &query_);
        gl.BeginQuery(GL_SAMPLES_PASSED, query_);
        if (count_fragments_) {
            if (!fs_query_) gl.GenQueries(1, &fs_query_);
            gl.BeginQuery(0x82F4 /* GL_FRAGMENT_SHADER_INVOCATIONS */, fs_query_);
            // (the counting stages add into binding 14, zeroed here: this pass's fragments only)
            const std::uint32_t zero[3] = {0, 0, 0};
            if (!count_buffer_) gl.GenBuffers(1, &count_buffer_);
            gl.BindBuffer(GL_SHADER_STORAGE_BUFFER, count_buffer_);
            gl.BufferData(GL_SHADER_STORAGE_BUFFER, sizeof zero, zero, GL_DYNAMIC_READ);
            gl.BindBufferBase(GL_SHADER_STORAGE_BUFFER, 14, count_buffer_);
            counting_ = true;
        }
        draw_primitives(cam, light, opt, deferred, opt.occlusion_culling, tex_[1]);
        counting_ = false;
        gl.EndQuery(GL_SAMPLES_PASSED);
        if (count_fragments_) gl.EndQuery(0x82F4);
        GLuint64 passed = 0;
        gl.GetQueryObjectui64v(query_, GL_QUERY_RESULT, &passed);
        samples_passed_ = static_cast<std::uint64_t>(passed);
        if (count_fragments_) {
            GLuint64 invocations = 0;
            gl.GetQueryObjectui64v(fs_query_, GL_QUERY_RESULT, &invocations);
            std::uint32_t c[3] = {0, 0, 0};
            gl.MemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
            gl.BindBuffer(GL_SHADER_STORAGE_BUFFER, count_buffer_);
            gl.GetBufferSubData(GL_SHADER_STORAGE_BUFFER, 0, sizeof c, c);
            gl.BindBufferBase(GL_SHADER_STORAGE_BUFFER, 14, 0);
            counts_ = {static_cast<std::uint64_t>(invocations), c[0], c[1], c[2]};
        }
        gl.BindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, 0);
        gl.BindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, 0);
        if (deferred) shade_deferred(cam, light, opt);
        gl.UseProgram(0);
        gl.BindVertexArray(0);
        gl.Finish();
        check_errors(gl, "QuadricRenderer::draw");
        count_culled();
    }

    /// What the shadow map depends on (RenderOptions::shadow_map_reuse): the light camera (the
    /// light's direction and the bounds of the primitives and passes), the map's size, the
    /// options that change its depths, the renderer's revision (its primitives, setters and
    /// passes) and every pass's revision.
    std::vector<std::uint64_t> shadow_key(const render::RenderOptions& opt) const {
        std::vector<std::uint64_t> key;
        push_camera_key(key, light_cam_);
        key.push_back(static_cast<std::uint64_t>(shadow_size_));
        key.push_back(opt.culling);
        key.push_back(opt.tight_bounds);
        key.push_back(opt.occlusion_culling);
        key.push_back(revision_);
        for (const ScenePass* p : passes_) {
            key.push_back(reinterpret_cast<std::uintptr_t>(p));
            key.push_back(p->revision());
        }
        return key;
    }

    /// Whether the last `draw` kept the shadow map of an earlier frame.
    bool reused_shadow_map() const { return shadow_reused_; }

    /// `drawn_`, `frustum_culled_` and `occluded_` of the frame just drawn.
    void count_culled() {
        if (view_unchanged_) {  // (the set alone: the others, left out by its test, count as hidden)
            drawn_ = unchanged_drawn_;
            frustum_culled_ = 0;
            occluded_ = count_ - std::min(count_, unchanged_drawn_);
        } else if (cull_pass_ran_) {
            const auto cmds = read_commands();
            drawn_ = earlier_phases_drawn_ + cmds[5 * render::variant_count];  // (phased drawing: and the phases before the last)
            frustum_culled_ = cmds[5 * render::variant_count + 1];
            occluded_ = cmds[5 * render::variant_count + 2];
        } else {
            drawn_ = count_;
            frustum_culled_ = occluded_ = 0;
        }
    }

    /// The public `draw_primitives`: into the host's bound framebuffer, with the cull pass when
    /// opt.occlusion_culling and it pays (`runs_cull_pass`; its occluders are these primitives
    /// only; one phase).
    void draw_into_bound(const render::Camera& cam, const render::Light& light, const render::RenderOptions& opt, bool deferred) {
        const Api& gl = *api_;
        cull_queries_used_ = 0;
        cull_ms_ = 0.0;
        gl.BindVertexArray(vao_);
        gl.BindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, ssbo_);  // (the cull pass reads the records before the draws bind them)
        gl.BindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, planes_);
        draw_primitives(cam, light, opt, deferred, opt.occlusion_culling);
        gl.BindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, 0);
        gl.BindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, 0);
        count_culled();
    }

    std::size_t drawn_primitives() const { return drawn_; }
    bool cull_pass_ran() const { return cull_pass_ran_; }
    int phases() const { return phase_count_; }
    bool reused_shown_set() const { return reused_; }
    bool unchanged_view() const { return view_unchanged_; }
    double expected_overlap() const { return expected_overlap_; }
    std::size_t frustum_culled() const { return frustum_culled_; }
    double cull_pass_ms() const { return cull_ms_; }
    std::size_t occluded() const { return occluded_; }

    /// The cull pass's indirect commands as read back (waits for it), then the primitives they
    /// draw (6 indices each), then the counts of primitives culled outside the view and behind
    /// occluders.
    std::array<std::uint32_t, 5 * render::variant_count + 3> read_commands() const {
        std::array<std::uint32_t, 5 * render::variant_count + 3> out{};
        api_->BindBuffer(GL_DRAW_INDIRECT_BUFFER, commands_);
        api_->GetBufferSubData(GL_DRAW_INDIRECT_BUFFER, 0, 5 * render::variant_count * sizeof(std::uint32_t), out.data());
        api_->GetBufferSubData(GL_DRAW_INDIRECT_BUFFER, 5 * render::variant_count * sizeof(std::uint32_t), 2 * sizeof(std::uint32_t),
                               out.data() + 5 * render::variant_count + 1);
        api_->BindBuffer(GL_DRAW_INDIRECT_BUFFER, 0);
        for (int v = 0; v < render::variant_count; ++v) out[5 * render::variant_count] += out[static_cast<std::size_t>(5 * v)] / per_kept(static_cast<render::Variant>(v));
        return out;
    }

    /// Whether every sphere of the sphere variant fits a point sprite in this view: the box of their
    /// centres (`render::sphere_points_fit`), or else, for at most `each_sphere_limit` spheres, each
    /// on its own (`render::each_sphere_points_fit`; its answer kept for the camera and viewport).
    bool sprites_fit(const render::Camera& cam, int width, int height) {
        if (render::sphere_points_fit(cam, width, height, sphere_lo_, sphere_hi_, sphere_radius_, max_point_size_)) return true;
        if (each_sphere_.empty() || each_sphere_.size() > each_sphere_limit) return false;
        std::vector<float> key;
        for (int j = 0; j < 4; ++j)
            for (int i = 0; i < 4; ++i) key.insert(key.end(), {cam.view[j][i], cam.projection[j][i]});
        key.insert(key.end(), {float(cam.orthographic), float(width), float(height)});
        if (key != each_sphere_key_) {
            each_sphere_key_ = std::move(key);
            each_sphere_fit_ = render::each_sphere_points_fit(cam, width, height, each_sphere_, max_point_size_);
        }
        return each_sphere_fit_;
    }

    /// What a variant's indirect command counts per drawn primitive: 6 indices of a quad, or 1 point sprite.
    std::uint32_t per_kept(render::Variant v) const { return points_ && v == render::Variant::sphere ? 1u : 6u; }

    /// The cuts between the phases of phased drawing: quantiles of the sampled phased primitives'
    /// nearest view distances (`nearest_distance`). Planes primitives alone: phase k ending at
    /// (2^(k+1) - 1) / (2^n - 1) of them (a small first phase of the nearest, then ever larger
    /// ones); with the other variants phased, by their expected overlap (below).
    std::vector<float> phase_cuts(const render::Camera& cam, int n, int width, int height) const {
        const Vec3<float> vz_row = vec3(cam.view[0][2], cam.view[1][2], cam.view[2][2]);
        const float vz_t = cam.view[3][2];
        std::vector<float> keys;
        keys.reserve(phase_sample_.size());
        for (const auto& b : phase_sample_) {
            const float k = nearest_distance(view_distance(vz_row, vz_t, vec3(b[0], b[1], b[2])), b[3]);
            if (std::isfinite(k)) keys.push_back(k);
        }
        std::sort(keys.begin(), keys.end());
        std::vector<float> cuts;
        const double total = double((1u << n) - 1u);
        // With the other variants phased: the first phase ends where the primitives' expected
        // overlap reaches 2.5 layers, each later one where 1.8 times the layers before it (bench
        // sticks, 50k sticks of overlap 10.3: cuts at 1/7 and 3/7 left 42% of them drawn, at 0.25
        // and 0.45 36%, 1.2x faster), no later than the even split k / n.
        const double layers = frame_phases_others_ ? render::expected_overlap(overlap_sample_, cam, width, height) : 0.0;
        for (int k = 0; k + 1 < n; ++k) {
            const double f = frame_phases_others_ ? std::min(double(k + 1) / n, layers > 0.0 ? 2.5 * std::pow(1.8, k) / layers : 1.0)
                                            : double((2u << k) - 1u) / total;
            cuts.push_back(keys.empty() ? 0.0f : keys[std::min(keys.size() - 1, static_cast<std::size_t>(f * double(keys.size())))]);
        }
        return cuts;
    }

    /// A depth target's shown set (RenderOptions::occlusion_reuse): per record whether it passed
    /// the last test against what was drawn, and those records as a list.
    struct ShownSet {
        GLuint buffer = 0, target = 0;
        bool valid = false;
        bool all = false;  ///< every record marked shown (frames without a cull pass need not mark them again)
        GLuint list = 0;   ///< the shown records in record order, each variant's from its first record (the visible list's layout)
        std::array<std::uint32_t, render::variant_count> counts{};  ///< per variant the shown records in `list`
        bool listed = false;  ///< `list` and `counts` hold the set (compacted by the frame that tested it)
        std::vector<std::uint64_t> view;  ///< with `listed`: `view_key` of the frame that tested it
        bool against_drawn = false;  ///< that test ran against what the set before it drew (not only occluder disks)
        /// The records that frame's picture shows (set_shown_from_picture; `valid`: made by it),
        /// flags and list as above: the set a frame whose view is unchanged draws instead.
        struct Owners {
            GLuint buffer = 0, list = 0;
            std::array<std::uint32_t, render::variant_count> counts{};
            bool valid = false;
            std::size_t capacity = 0;  ///< records `buffer` and `list` hold
        } owners;
        bool of_picture = false;  ///< `list` holds the records of the picture (swapped in from `owners`)
    };
    /// The phase of a cull pass: its index of `count`, and the window [lo, hi) of nearest view
    /// distances of the planes primitives it keeps (the first phase from -infinity, the last to
    /// +infinity); a single phase keeps all. `depth_target`: the depth texture the draws write.
    struct Phase {
        int index = 0, count = 1;
        float lo = 0.0f, hi = 0.0f;
        GLuint depth_target = 0;
        int reuse = 0;  ///< the cull shader's qc_reuse (1, 2: the phases of a frame reusing the shown set; 3: a frame recording it)
        GLuint shown = 0;  ///< the shown set's buffer (with `reuse`)
        GLuint list = 0;   ///< with `reuse` 2 or 3: the shown set's list, compacted from the test's results for the next frame
        const ShownSet* listed = nullptr;  ///< reuse 1 drawn from this set's list without a cull pass
        bool fresh = false;  ///< the frame's first cull pass (it clears the depth image and the counts)
        bool first() const { return index == 0; }
        bool last() const { return index + 1 == count; }
    };

    /// Whether a frame with a cull pass may draw in phases: with a depth target and more than one
    /// phase asked for.
    static bool phases_allowed(const render::RenderOptions& opt, bool depth_target) { return depth_target && std::clamp(opt.occlusion_phases, 1, 8) > 1; }

    /// Whether variant v is drawn in phases in this frame (set by `draw_primitives`, in frames
    /// with a cull pass and `phases_allowed`): the planes variant when it has at least
    /// `phase_min_count` primitives, each inside its bounding ball; the others together when they
    /// have at least `phase_min_count` and at least half of them do not occlude with one disk
    /// (chains of disks along sticks, or no occluder: open slabs, cones, general quadrics). The
    /// disk chains of phased sticks are not written: what the earlier phases draw hides more, for
    /// less (bench sticks, 50k sticks: the chains' pass took 77 ms of a 224 ms frame; without
    /// them, in 3 phases, the cull passes took 28-40 ms and the frame 1.2x less).
    bool phased_variant(render::Variant v) const { return v == render::Variant::planes ? frame_phases_planes_ : frame_phases_others_; }

    /// Whether a frame with occlusion culling runs the cull pass: phased drawing of the planes
    /// variant always does; otherwise where its expected overlap (`render::expected_overlap`, into `overlap`; 0 when
    /// not estimated) reaches RenderOptions::occlusion_min_overlap, or that is 0. Where the
    /// primitives rarely overlap on screen the pass costs more than it saves.
    bool runs_cull_pass(const render::Camera& cam, const render::RenderOptions& opt, bool depth_target, int width, int height, double& overlap) const {
        overlap = 0.0;
        if (count_ == 0) return false;
        if ((phases_planes_ && phases_allowed(opt, depth_target)) || !(opt.occlusion_min_overlap > 0.0f)) return true;
        overlap = render::expected_overlap(overlap_sample_, cam, width, height);
        return overlap >= double(opt.occlusion_min_overlap);
    }

    /// What decides which primitives a view shows, besides the primitives themselves (`revision_`):
    /// the camera's matrices, the viewport, per-quadric back-face culling, the depth test and the
    /// fragment stage.
    std::vector<std::uint64_t> view_key(const render::Camera& cam, const GLint (&viewport)[4], const render::RenderOptions& opt) const {
        std::vector<std::uint64_t> key;
        push_camera_key(key, cam);
        for (GLint v : viewport) key.push_back(static_cast<std::uint32_t>(v));
        key.push_back(opt.culling);
        key.push_back(depth_test_);
        key.push_back(static_cast<std::uint64_t>(stage_));
        key.push_back(revision_);
        return key;
    }

    /// Draws every variant's primitives with the forward or geometry-buffer programs into the
    /// bound framebuffer, then the other passes (`add_pass`).
    /// With `cull_pass` and a depth target, the phased variants (`phased_variant`) are drawn in
    /// RenderOptions::occlusion_phases phases by nearest view distance (`phase_cuts`); after
    /// each, the cull pass of the next takes the depth buffer into its depth image
    /// (OcclusionPass::depth_image), so what the earlier phases drew hides what lies behind it.
    /// The other variants draw in the first phase.
    void draw_primitives(const render::Camera& cam, const render::Light& light, const render::RenderOptions& opt, bool deferred, bool cull_pass = false,
                         GLuint depth_target = 0) {
        const Api& gl = *api_;
        GLint viewport[4] = {0, 0, 1, 1};
        gl.GetIntegerv(GL_VIEWPORT, viewport);
        const int phases = std::clamp(opt.occlusion_phases, 1, 8);
        expected_overlap_ = 0.0;
        // The sphere variant as point sprites where all of it fits (render::sphere_points_fit);
        // not with the compute pass's corners (set_compute_bounds), which the quads' vertex stage fetches.
        points_ = point_sprites_ && !compute_bounds_ && ranges_[static_cast<int>(render::Variant::sphere)].second > 0 && sprites_fit(cam, viewport[2], viewport[3]);
        const bool asked = cull_pass;
        cull_pass = cull_pass && runs_cull_pass(cam, opt, depth_target != 0, viewport[2], viewport[3], expected_overlap_);  // (none without primitives)
        const bool may_phase = cull_pass && phases_allowed(opt, depth_target != 0);
        frame_phases_planes_ = may_phase && phases_planes_;
        frame_phases_others_ = may_phase && phases_others_;
        const bool phased = frame_phases_planes_ || frame_phases_others_;
        // Reuse of the last frame's shown set (RenderOptions::occlusion_reuse): per depth target,
        // not with phased drawing nor with rasterised occluders. A frame with a valid set draws
        // it first (no occluders), then tests every record against that depth and draws the
        // rest that pass; the test's results are the next frame's set. A frame without one
        // records the cull pass's kept records, or, without a cull pass, all.
        ShownSet* shown = nullptr;
        if (opt.occlusion_culling && opt.occlusion_reuse && depth_target != 0 && count_ > 0 && !phased && !occluders_in_depth_) {
            shown = &shown_set_of(shown_, next_shown_, depth_target);
        } else {
            forget_shown_sets(depth_target);
        }
        // (reuse needs no occluders, so it pays from a lower overlap than the cull pass: from
        // `reuse_overlap_share` of occlusion_min_overlap)
        reused_ = shown && shown->valid && asked && (cull_pass || expected_overlap_ >= reuse_overlap_share * double(opt.occlusion_min_overlap));
        if (reused_) cull_pass = true;
        cull_pass_ran_ = cull_pass;
        const std::vector<float> cuts = phased ? phase_cuts(cam, phases, viewport[2], viewport[3]) : std::vector<float>{};
        earlier_phases_drawn_ = 0;
        bool culled_before = false, listed_now = false;  // (a cull pass ran in an earlier phase; a list was compacted)
        // A reusing frame whose view is the one its set was tested under (`view_key`), against what
        // the set before it drew, draws the set alone: that test passed every primitive that can
        // show in this view (it is conservative, and what it tested against lay no nearer than
        // this view's picture), so the picture is complete, and a new test would keep a subset of
        // the set. The set stays.
        const std::vector<std::uint64_t> view = shown ? view_key(cam, viewport, opt) : std::vector<std::uint64_t>{};
        // (the set's view is this one: the camera has not moved since the frame that tested it)
        const bool same_view = reused_ && shown->listed && !compute_bounds_ && keep_unchanged_sets_ && shown->view == view;
        view_unchanged_ = same_view && shown->against_drawn;
        // The records the picture shows (set_shown_from_picture), made where the camera has not
        // moved since the last frame (the set's view is this one: a reusing frame that tests the
        // set again, or one that draws the test's set alone), in the renderer's own target with
        // the depth test: the primitives' pass writes each pixel's record into the ids target,
        // and compute passes list the records left in it (make_owner_set). The next frame with
        // the view unchanged draws those alone instead, a subset of the test's set with the same
        // picture (the whole picture: at each pixel the record left was the nearest of all). A
        // moving camera pays nothing for them: its views never repeat.
        if (view_unchanged_ && shown->owners.valid) {
            std::swap(shown->buffer, shown->owners.buffer);
            std::swap(shown->list, shown->owners.list);
            std::swap(shown->counts, shown->owners.counts);
            shown->owners.valid = false;
            shown->owners.capacity = count_;  // (the set's buffers, sized to the records)
            shown->of_picture = true;
        }
        picture_set_drawn_ = view_unchanged_ && shown->of_picture;
        // (the ids target still holds the picture's records: only an ids frame writes it, and the
        // set is the picture's only while its view is this one, in this target)
        reshade_frame_ = picture_set_drawn_ && reshade_ && depth_target == tex_[1] && stage_ == render::FragmentStage::incremental;
        reshaded_ = false;
        // (the pictures whose records can be listed: with the depth test, in the renderer's own target)
        const bool listable = shown_from_picture_ && depth_target == tex_[1] && depth_test_ && stage_ != render::FragmentStage::passthrough;
        ids_frame_ = same_view && !picture_set_drawn_ && listable;
        // Where a still camera's frames would list the picture's records, their programs are compiled
        // in the first frame (a first use costs a frame tens of milliseconds on llvmpipe).
        prefetch_ = shown && listable && !compute_bounds_;
        if (prefetch_)
            for (render::OcclusionPass pass : {render::OcclusionPass::owners, render::OcclusionPass::owner_count, render::OcclusionPass::scan, render::OcclusionPass::owner_compact})
                programs_.get(render::OcclusionKey{pass});
        if (ids_frame_) {
            const GLenum bufs[4] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1, GL_COLOR_ATTACHMENT2, GL_COLOR_ATTACHMENT3};
            gl.DrawBuffers(deferred ? 4 : 2, bufs);
            const GLuint none[4] = {0, 0, 0, 0};
            gl.ClearBufferuiv(GL_COLOR, deferred ? 3 : 1, none);
        }
        const int phase_count = phased ? phases : reused_ ? (view_unchanged_ ? 1 : 2) : 1;
        phase_count_ = phase_count;
        for (int k = 0; k < phase_count; ++k) {
            Phase ph;
            ph.index = k;
            ph.count = phase_count;
            ph.lo = phased && k > 0 ? cuts[static_cast<std::size_t>(k - 1)] : 0.0f;
            ph.hi = phased && k + 1 < phase_count ? cuts[static_cast<std::size_t>(k)] : 0.0f;
            ph.depth_target = depth_target;
            ph.reuse = reused_ ? k + 1 : shown && cull_pass ? 3 : 0;
            ph.shown = shown ? shown->buffer : 0;
            ph.list = ph.reuse >= 2 && !compute_bounds_ ? shown->list : 0;
            // (a reusing frame draws the set's list, compacted by the frame that tested it, without a cull pass)
            ph.listed = ph.reuse == 1 && shown->listed && !compute_bounds_ ? shown : nullptr;
            ph.fresh = !culled_before;
            culled_before = culled_before || (cull_pass && !ph.listed);
            draw_phase(cam, light, opt, deferred, cull_pass, ph, viewport);
            if (!ph.last()) {
                if (ph.listed)
                    for (std::uint32_t n : ph.listed->counts) earlier_phases_drawn_ += n;
                else
                    earlier_phases_drawn_ += read_commands()[5 * render::variant_count];  // (the last phase's: `draw`)
            }
            listed_now = listed_now || ph.list != 0;
        }
        if (shown && view_unchanged_) {
            unchanged_drawn_ = 0;
            for (std::uint32_t n : shown->counts) unchanged_drawn_ += n;
        } else if (shown) {
            // The list the test's results were compacted into: its counts, for the next frame
            shown->listed = listed_now;
            shown->owners.valid = shown->of_picture = false;
            if (listed_now) {
                shown->view = view;
                shown->against_drawn = reused_;  // (a frame recording its first set tested against occluder disks: tested once more, it keeps fewer)
                shown->counts = listed_counts();
            }
        }
        if (ids_frame_) {  // (after the test's counts were read from commands2_, which make_owner_set reuses)
            const GLenum bufs[3] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1, GL_COLOR_ATTACHMENT2};
            gl.DrawBuffers(deferred ? 3 : 1, bufs);
            ids_frame_ = false;
            timed_cull([&] { make_owner_set(shown->owners, viewport[2], viewport[3]); });
            shown->owners.valid = true;
        }
        if (shown && !cull_pass && !(shown->valid && shown->all)) {  // (no cull pass: every record is drawn, so all count as shown)
            gl.BindBuffer(GL_SHADER_STORAGE_BUFFER, shown->buffer);
            const std::uint32_t one = 1u;
            gl.ClearBufferData(GL_SHADER_STORAGE_BUFFER, GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, &one);
            gl.BindBuffer(GL_SHADER_STORAGE_BUFFER, 0);
        }
        if (shown) {
            shown->all = !cull_pass;
            shown->valid = true;
        }
        occluders_in_depth_ = false;
        gl.Enable(GL_DEPTH_CLAMP);  // (as for the primitives)
        // What lies in the depth target under each pass (ScenePass::frame_before): in the
        // renderer's own targets (cleared), its primitives' picture, exact whatever culling
        // drew it, so fixed by `view_key`, this renderer and the target; then each earlier
        // pass's revision, under the light and the options a pass's geometry may depend on.
        // Unknown in a host's framebuffer, after a pass without a revision, and with the
        // pass-through stage (a benchmark's: its depth is the drawn bounds').
        std::vector<std::uint64_t> before;
        bool known = depth_target != 0 && stage_ != render::FragmentStage::passthrough;
        if (known) {
            before = view_key(cam, viewport, opt);
            before.insert(before.end(), {instance_, depth_target, static_cast<std::uint64_t>(deferred), opt.tight_bounds});
            for (int i = 0; i < 3; ++i) push_float_bits(before, light.direction[i]);
        }
        for (ScenePass* p : passes_) {
            p->frame_before(known ? &before : nullptr);
            p->draw(cam, light, opt, deferred);
            known = known && p->revision() != 0;
            before.push_back(p->revision());
        }
        gl.Disable(GL_DEPTH_CLAMP);
    }

    /// Occlusion pass 1 by the rasteriser (`set_raster_occluders`): into the bound framebuffer's
    /// cleared depth buffer (colour writes off), per variant with occluders its records'
    /// quadrilaterals (`occluder_corner`), whose rasterised depth is never nearer than the
    /// primitive's own surface at any pixel they cover. So the depth buffer stays conservative for
    /// the primitive pass (whose own surfaces lie in front and are drawn: the picture does not
    /// change), and the first cull pass takes it into its depth image (OcclusionPass::depth_image).
    /// The depth test runs before the (empty) fragment stage.
    /// Not in a frame whose cull pass `draw_primitives` will skip (`runs_cull_pass`, with a depth target).
    void rasterise_occluders(const render::Camera& cam, const render::RenderOptions& opt, int width, int height) {
        occluders_in_depth_ = false;
        if (!raster_occluders_ || count_ == 0) return;
        double overlap = 0.0;
        if (!runs_cull_pass(cam, opt, true, width, height, overlap)) return;
        const render::OcclusionRange range = render::occlusion_range(cam);
        if (!(range.far > range.near)) return;
        // (glFinish inside the timed range: llvmpipe rasterises a draw when it flushes, after
        // GL_TIME_ELAPSED has ended, so without it the time left out the rasterisation, 50-60 ms
        // of 50k sticks' occluders, and printed 14 ms)
        timed_cull([&] {
            draw_occluders(cam, range, width, height);
            api_->Finish();
        });
        occluders_in_depth_ = true;
    }

    /// The occluders' quadrilaterals of `rasterise_occluders`.
    void draw_occluders(const render::Camera& cam, const render::OcclusionRange& range, int width, int height) {
        const Api& gl = *api_;
        const Program& prog = programs_.get(render::OcclusionKey{render::OcclusionPass::occluder_raster});
        gl.UseProgram(prog.id());
        detail::set_camera_uniforms(gl, prog, cam, width, height);
        gl.Uniform3f(prog.uniform_location("qc_occluder_range"), range.near, range.far, range.gap);
        const float right[3] = {cam.view[0][0], cam.view[1][0], cam.view[2][0]}, up[3] = {cam.view[0][1], cam.view[1][1], cam.view[2][1]};
        gl.Uniform3fv(prog.uniform_location("qc_right"), 1, right);
        gl.Uniform3fv(prog.uniform_location("qc_up"), 1, up);
        gl.Uniform1f(prog.uniform_location("qc_p11"), cam.projection[1][1]);
        gl.BindVertexArray(vao_);
        gl.BindBufferBase(GL_SHADER_STORAGE_BUFFER, 2, occluders_);
        gl.Disable(GL_DEPTH_CLAMP);
        gl.ColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
        gl.DepthMask(GL_TRUE);
        for (render::Variant v : {render::Variant::sphere, render::Variant::ellipsoid, render::Variant::slab}) {
            const auto& r = ranges_[static_cast<int>(v)];
            if (r.second == 0) continue;
            gl.Uniform1ui(prog.uniform_location("qc_first"), r.first);
            gl.DrawElements(GL_TRIANGLES, static_cast<GLsizei>(6 * r.second), GL_UNSIGNED_INT, nullptr);
        }
        gl.ColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
        gl.BindBufferBase(GL_SHADER_STORAGE_BUFFER, 2, 0);
    }

    /// Runs `pass` (culling work) and adds its GPU time (GL_TIME_ELAPSED, one of `cull_queries_`
    /// while they last: the shadow map's passes and the camera's) to `cull_pass_ms`. Read at
    /// once: the draws after it wait for it anyway, and llvmpipe's elapsed time read after the
    /// frame also counted the draws queued behind it.
    template <class F>
    void timed_cull(F&& pass) {
        const Api& gl = *api_;
        GLuint* q = nullptr;
        if (cull_queries_used_ < static_cast<int>(std::size(cull_queries_))) {
            q = &cull_queries_[cull_queries_used_++];
            if (!*q) gl.GenQueries(1, q);
            gl.BeginQuery(GL_TIME_ELAPSED, *q);
        }
        pass();
        if (!q) return;
        gl.EndQuery(GL_TIME_ELAPSED);
        GLuint64 ns = 0;
        gl.GetQueryObjectui64v(*q, GL_QUERY_RESULT, &ns);
        cull_ms_ += static_cast<double>(ns) * 1e-6;
    }

    /// One phase of `draw_primitives`: its cull pass, then its primitives.
    void draw_phase(const render::Camera& cam, const render::Light& light, const render::RenderOptions& opt, bool deferred, bool cull_pass,
                    const Phase& ph, const GLint (&viewport)[4]) {
        const Api& gl = *api_;
        gl.BindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, planes_);  // (the bounds pass reads them too; a scene pass may have unbound them)
        if (cull_pass && !ph.listed) timed_cull([&] { run_cull_pass(cam, opt, viewport[2], viewport[3], ph); });
        const bool indirect = cull_pass && !ph.listed;
        // The bounding geometry (quads, tetrahedron faces) is a stand-in: the fragment stage
        // computes the depth and keeps only hits in [0, 1]. Without depth clamping GL would clip
        // the stand-in itself at the near and far planes, losing the visible part of a primitive
        // whose quad lies beyond the far plane or in front of the near plane.
        gl.Enable(GL_DEPTH_CLAMP);
        gl.BindVertexArray(vao_);
        gl.BindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, ssbo_);
        gl.BindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, planes_);
        gl.BindBufferBase(GL_SHADER_STORAGE_BUFFER, 4, ph.listed ? ph.listed->list : visible_);
        if (indirect) {
            gl.BindTextureUnit(depth_texels_unit, depth_view_);  // (the early discard's reads)
            if (compute_bounds_) {
                gl.BindBufferBase(GL_SHADER_STORAGE_BUFFER, 8, corners_);
                gl.BindBufferBase(GL_SHADER_STORAGE_BUFFER, 9, nearests_);
            }
            gl.BindBuffer(GL_DRAW_INDIRECT_BUFFER, commands_);
        }
        for (int v = 0; v < render::variant_count; ++v) {
            if (ranges_[v].second == 0) continue;
            const auto variant = static_cast<render::Variant>(v);
            if (!ph.first() && !phased_variant(variant) && ph.reuse != 2) continue;  // (drawn in the first phase)
            const auto listed = static_cast<GLsizei>(ph.listed ? ph.listed->counts[static_cast<std::size_t>(v)] : 0u);
            if (ph.listed && listed == 0) continue;
            const bool points = points_ && variant == render::Variant::sphere;
            // The variant's program for this frame's camera and options: forward (with the environment
            // reflection) or into the geometry buffer, for the fragment stage set by `set_fragment_stage`,
            // counting in `draw`'s counted pass (compiled on first use).
            auto key_of = [&](bool sprites, bool early, bool ids, bool reshade) {
                return render::quadric_key(variant, opt.culling, cam.orthographic, deferred, opt.environment != nullptr, stage_, sprites, counting_, early, ids, reshade);
            };
            if (reshade_frame_ && variant == render::Variant::sphere) {
                // The records the picture shows, each pixel's shaded once from the ids target (QuadricKey::reshade)
                const Program& prog = programs_.get(key_of(false, false, false, true));
                gl.UseProgram(prog.id());
                set_uniforms(prog, cam, light, opt, viewport[2], viewport[3]);
                gl.Uniform1ui(prog.require_uniform("qc_reshade_first"), ranges_[v].first);
                gl.Uniform1ui(prog.require_uniform("qc_reshade_count"), ranges_[v].second);
                gl.BindTextureUnit(reshade_ids_unit, idtex_);
                gl.TextureBarrier();  // (an earlier draw wrote the ids target, still attached, not drawn to)
                gl.DrawArrays(GL_TRIANGLES, 0, 3);
                gl.BindTextureUnit(reshade_ids_unit, 0);
                reshaded_ = true;
                continue;
            }
            // The early discard (QuadricKey::early): not the planes variant unless all its patches
            // show only inside their bounding balls (a bilinear patch may reach out of its ball
            // inside its quad), nor the sphere variant, whose cast costs about what the test does
            // (bench spheres: 0.85-0.99x).
            const bool early = indirect && early_discard_ && (variant != render::Variant::planes || planes_in_ball_) && variant != render::Variant::sphere;
            // (only the incremental stage has the early discard: key.early)
            const render::QuadricKey key = key_of(points, early, ids_frame_, false);
            const Program& prog = programs_.get(key);
            if (prefetch_) {
                // (compiled with this frame's: the programs of a still camera's next frames, the set
                // drawn alone without the early discard, with the ids output, the spheres shaded from
                // the ids target, so that none of those frames pays a compile)
                for (bool ids : {false, true}) programs_.get(key_of(points, false, ids, false));
                if (variant == render::Variant::sphere && reshade_) programs_.get(key_of(false, false, false, true));
            }
            gl.UseProgram(prog.id());
            set_uniforms(prog, cam, light, opt, viewport[2], viewport[3]);
            set_bound_uniforms(prog, variant, cam, opt);
            gl.Uniform1i(prog.uniform_location("qc_indirect"), cull_pass ? 1 : 0);  // (the visible list, or the shown set's)
            gl.Uniform1i(prog.uniform_location("qc_fetch"), indirect && compute_bounds_ ? 1 : 0);
            if (key.early) gl.Uniform1i(prog.require_uniform("qc_depth_width"), viewport[2]);
            if (points) {
                // (the cull pass wrote a DrawArraysIndirectCommand: count, 1, first = qc_first, 0)
                gl.Enable(GL_PROGRAM_POINT_SIZE);
                if (ph.listed)
                    gl.DrawArrays(GL_POINTS, static_cast<GLint>(ranges_[v].first), listed);
                else if (cull_pass)
                    gl.DrawArraysIndirect(GL_POINTS, reinterpret_cast<const void*>(static_cast<std::uintptr_t>(20 * v)));
                else
                    gl.DrawArrays(GL_POINTS, 0, static_cast<GLsizei>(ranges_[v].second));
                gl.Disable(GL_PROGRAM_POINT_SIZE);
            } else if (ph.listed) {
                gl.DrawElementsBaseVertex(GL_TRIANGLES, 6 * listed, GL_UNSIGNED_INT, nullptr, static_cast<GLint>(4 * ranges_[v].first));
            } else if (cull_pass) {
                gl.DrawElementsIndirect(GL_TRIANGLES, GL_UNSIGNED_INT, reinterpret_cast<const void*>(static_cast<std::uintptr_t>(20 * v)));
            } else {
                gl.DrawElements(GL_TRIANGLES, static_cast<GLsizei>(6 * ranges_[v].second), GL_UNSIGNED_INT, nullptr);
            }
        }
        if (indirect) gl.BindBuffer(GL_DRAW_INDIRECT_BUFFER, 0);
        gl.BindBufferBase(GL_SHADER_STORAGE_BUFFER, 4, 0);
        gl.BindBufferBase(GL_SHADER_STORAGE_BUFFER, 8, 0);
        gl.BindBufferBase(GL_SHADER_STORAGE_BUFFER, 9, 0);
        gl.BindTextureUnit(depth_texels_unit, 0);
        gl.BindTextureUnit(4, 0);
        gl.Disable(GL_DEPTH_CLAMP);
    }

    /// Reads back the last frame (rows top first, like the CPU renderer).
    render::Image read() const {
        return read_framebuffer(*api_, fbo_, width_, height_);
    }

    std::size_t primitive_count() const { return count_; }

private:
    template <class V>
    void upload(GLuint buffer, const V& data) {
        api_->BindBuffer(GL_SHADER_STORAGE_BUFFER, buffer);
        api_->BufferData(GL_SHADER_STORAGE_BUFFER, static_cast<GLsizeiptr>(std::max<std::size_t>(1, data.size()) * sizeof(data[0])),
                         data.empty() ? nullptr : data.data(), GL_DYNAMIC_DRAW);
    }

    /// The compute passes of occlusion culling (quadcast/occlusion.hpp) for a width x height
    /// viewport: the occluders' disks into the depth image, the max-depth pyramid over it, then
    /// per variant the test of every record, then the kept ones in record order into the visible
    /// list and the variant's indirect draw command {6 n, 1, 0, 4 first, 0} (the vertex stage
    /// reads slot first + i); with `set_compute_bounds`, then each slot's corners and nearest
    /// distance (the variant's vertex stage's uniforms from `opt`).
    /// Dispatches `n` workgroups of a pass over records in rows of at most `row_limit_` (65535,
    /// GL's guaranteed limit per dimension; the shaders number them by `qc_linear_group`, and a
    /// cull pass workgroup past the records returns).
    void dispatch_rows(const Api& gl, std::uint32_t n) const { gl::dispatch_rows(gl, n, row_limit_); }

    /// The shown set from the picture in the ids target (OcclusionPass::owners, owner_count, scan,
    /// owner_compact): its flags, its list and per variant its count (read back into `set`).
    void make_owner_set(ShownSet::Owners& set, int width, int height) {
        const Api& gl = *api_;
        if (set.capacity < count_) {
            for (GLuint* b : {&set.buffer, &set.list}) {
                if (!*b) gl.GenBuffers(1, b);
                upload(*b, std::vector<std::uint32_t>(count_));
            }
            set.capacity = count_;
        }
        const auto words = static_cast<std::uint32_t>((count_ + 31) / 32);
        if (words > owner_words_) {
            upload(owner_bits_, std::vector<std::uint32_t>(words));
            upload(owner_groups_, std::vector<std::uint32_t>(words + 1));
            owner_words_ = words;
        }
        const std::uint32_t zero = 0u;
        for (GLuint b : {owner_bits_, set.buffer}) {
            gl.BindBuffer(GL_SHADER_STORAGE_BUFFER, b);
            gl.ClearBufferData(GL_SHADER_STORAGE_BUFFER, GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, &zero);
        }
        std::uint32_t cmds[5 * render::variant_count] = {};
        gl.BindBuffer(GL_SHADER_STORAGE_BUFFER, commands2_);
        gl.BufferSubData(GL_SHADER_STORAGE_BUFFER, 0, sizeof cmds, cmds);
        gl.BindBuffer(GL_SHADER_STORAGE_BUFFER, 0);
        gl.MemoryBarrier(GL_ALL_BARRIER_BITS);  // (the primitives' pass wrote the ids target)
        const Program& owners = programs_.get(render::OcclusionKey{render::OcclusionPass::owners});
        gl.UseProgram(owners.id());
        gl.BindTextureUnit(0, idtex_);
        gl.BindBufferBase(GL_SHADER_STORAGE_BUFFER, 10, set.buffer);
        gl.BindBufferBase(GL_SHADER_STORAGE_BUFFER, 13, owner_bits_);
        gl.Uniform2ui(owners.uniform_location("qc_size"), static_cast<GLuint>(width), static_cast<GLuint>(height));
        gl.Uniform1ui(owners.uniform_location("qc_records"), static_cast<GLuint>(count_));
        gl.DispatchCompute(static_cast<GLuint>((width + 7) / 8), static_cast<GLuint>((height + 7) / 8), 1);
        gl.MemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
        gl.BindTextureUnit(0, 0);
        const Program& count = programs_.get(render::OcclusionKey{render::OcclusionPass::owner_count});
        const Program& scan = programs_.get(render::OcclusionKey{render::OcclusionPass::scan});
        const Program& compact = programs_.get(render::OcclusionKey{render::OcclusionPass::owner_compact});
        gl.BindBufferBase(GL_SHADER_STORAGE_BUFFER, 4, set.list);
        gl.BindBufferBase(GL_SHADER_STORAGE_BUFFER, 5, commands2_);
        gl.BindBufferBase(GL_SHADER_STORAGE_BUFFER, 7, owner_groups_);
        for (int v = 0; v < render::variant_count; ++v) {
            const auto [first, n] = ranges_[v];
            if (n == 0) continue;
            const std::uint32_t variant_words = (first + n - 1) / 32 - first / 32 + 1;
            for (const Program* p : {&count, &compact}) {
                gl.UseProgram(p->id());
                gl.Uniform1ui(p->uniform_location("qc_first"), first);
                gl.Uniform1ui(p->uniform_location("qc_count"), n);
                gl.Uniform1ui(p->uniform_location("qc_words"), variant_words);
            }
            gl.UseProgram(count.id());
            dispatch_rows(gl, (variant_words + 63) / 64);
            gl.MemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
            gl.UseProgram(scan.id());
            gl.Uniform1ui(scan.uniform_location("qc_group_count"), variant_words);
            gl.Uniform1ui(scan.uniform_location("qc_per_kept"), 1u);
            gl.Uniform1ui(scan.uniform_location("qc_command_at"), static_cast<GLuint>(5 * v));
            gl.DispatchCompute(1, 1, 1);
            gl.MemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
            gl.UseProgram(compact.id());
            dispatch_rows(gl, (variant_words + 63) / 64);
            gl.MemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
        }
        for (GLuint b : {4u, 5u, 7u, 10u, 13u}) gl.BindBufferBase(GL_SHADER_STORAGE_BUFFER, b, 0);
        gl.MemoryBarrier(GL_ALL_BARRIER_BITS);
        set.counts = listed_counts();
    }

    /// Per variant the records the last compaction into a shown set's list wrote (the scan pass's
    /// count in each variant's command of commands2_; waits for it).
    std::array<std::uint32_t, render::variant_count> listed_counts() const {
        const Api& gl = *api_;
        std::uint32_t cmds[5 * render::variant_count] = {};
        gl.BindBuffer(GL_SHADER_STORAGE_BUFFER, commands2_);
        gl.GetBufferSubData(GL_SHADER_STORAGE_BUFFER, 0, sizeof cmds, cmds);
        gl.BindBuffer(GL_SHADER_STORAGE_BUFFER, 0);
        std::array<std::uint32_t, render::variant_count> counts{};
        for (int v = 0; v < render::variant_count; ++v) counts[static_cast<std::size_t>(v)] = ranges_[v].second ? cmds[5 * v] : 0u;
        return counts;
    }

    void run_cull_pass(const render::Camera& cam, const render::RenderOptions& opt, int width, int height, const Phase& ph) {
        const Api& gl = *api_;
        const auto w = static_cast<std::uint32_t>(width), h = static_cast<std::uint32_t>(height);
        // Pyramid levels down to 1 x 1, level 0 the viewport.
        const std::vector<std::array<std::uint32_t, 3>> levels = pyramid_levels(w, h);
        // Earlier frames', the shadow pass's and the earlier phases' reads and writes of these
        // buffers (and of the depth target) are done.
        gl.MemoryBarrier(GL_ALL_BARRIER_BITS);
        const std::size_t texels = pyramid_texels(levels);
        if (texels > depth_texels_) {  // grown only (the shadow map's pass and the camera's share it)
            upload(depths_, std::vector<std::uint32_t>(texels));
            view_depth_texels(gl, depth_view_, depths_, texels);
            depth_texels_ = texels;
        }
        if (ph.fresh) {
            gl.BindBuffer(GL_SHADER_STORAGE_BUFFER, depths_);
            const std::uint32_t none = 0xffffffffu;
            gl.ClearBufferData(GL_SHADER_STORAGE_BUFFER, GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, &none);
            gl.BindBuffer(GL_SHADER_STORAGE_BUFFER, 0);
        }
        gl.BindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, ssbo_);
        gl.BindBufferBase(GL_SHADER_STORAGE_BUFFER, 2, occluders_);
        gl.BindBufferBase(GL_SHADER_STORAGE_BUFFER, 3, depths_);
        gl.BindBufferBase(GL_SHADER_STORAGE_BUFFER, 4, visible_);
        gl.BindBufferBase(GL_SHADER_STORAGE_BUFFER, 5, commands_);
        gl.BindBufferBase(GL_SHADER_STORAGE_BUFFER, 6, keep_);
        gl.BindTextureUnit(depth_texels_unit, depth_view_);  // (the cull pass's pyramid reads)
        const render::OcclusionRange range = render::occlusion_range(cam);
        auto common = [&](const Program& p) {
            gl.UseProgram(p.id());
            set_uniforms(p, cam, render::Light{}, render::RenderOptions{}, width, height);
        };
        auto groups = [](std::uint32_t n, std::uint32_t size) { return (n + size - 1) / size; };
        const auto runs = [&](int v) { return ranges_[v].second != 0 && (ph.first() || phased_variant(static_cast<render::Variant>(v)) || ph.reuse == 2); };
        const bool from_depth = !ph.first() || (occluders_in_depth_ && ph.depth_target != 0);
        gl.BindBufferBase(GL_SHADER_STORAGE_BUFFER, 10, ph.shown);
        if (from_depth) {
            // 1'. A later phase: what the earlier phases drew, from the depth target, into level 0
            // (over the occluders' disks and the earlier phases' values); or the first, after
            // `rasterise_occluders`: the occluders' depths.
            const Program& dp = programs_.get(render::OcclusionKey{render::OcclusionPass::depth_image});
            gl.UseProgram(dp.id());
            detail::set_camera_uniforms(gl, dp, cam, width, height);  // (qc_pz)
            gl.BindTextureUnit(5, ph.depth_target);
            gl.Uniform1i(dp.uniform_location("qc_depth_buffer"), 5);
            gl.Uniform2ui(dp.uniform_location("qc_size"), w, h);
            const auto& l1 = levels[std::min<std::size_t>(1, levels.size() - 1)];
            gl.Uniform3ui(dp.uniform_location("qc_level1"), l1[0], l1[1], l1[2]);
            gl.DispatchCompute(groups(l1[1], 8), groups(l1[2], 8), 1);
            gl.MemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
            gl.BindTextureUnit(5, 0);
        }
        // 1. Occluders (the variants that have them), in the first phase, unless rasterised or
        // the shown set is drawn first (no occlusion test in that phase).
        if (ph.first() && !from_depth && ph.reuse != 1) {
            const Program& occ = programs_.get(render::OcclusionKey{render::OcclusionPass::occluders});
            common(occ);
            gl.Uniform3f(occ.uniform_location("qc_occluder_range"), range.near, range.far, range.gap);
            const float right[3] = {cam.view[0][0], cam.view[1][0], cam.view[2][0]}, up[3] = {cam.view[0][1], cam.view[1][1], cam.view[2][1]};
            gl.Uniform3fv(occ.uniform_location("qc_right"), 1, right);
            gl.Uniform3fv(occ.uniform_location("qc_up"), 1, up);
            gl.Uniform1ui(occ.uniform_location("qc_max_pixels"), 1u << 18);
            gl.Uniform1i(occ.uniform_location("qc_chains"), frame_phases_others_ ? 0 : 1);
            for (render::Variant v : {render::Variant::sphere, render::Variant::ellipsoid, render::Variant::slab}) {
                const auto& r = ranges_[static_cast<int>(v)];
                if (r.second == 0) continue;
                gl.Uniform1ui(occ.uniform_location("qc_first"), r.first);
                gl.Uniform1ui(occ.uniform_location("qc_count"), r.second);
                dispatch_rows(gl, groups(r.second, 64));
            }
        }
        gl.MemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
        // 2. The max-depth pyramid.
        // (from level 2 after the depth image, which wrote level 1)
        if (ph.reuse != 1) build_pyramid(gl, programs_.get(render::OcclusionKey{render::OcclusionPass::pyramid}), levels, from_depth ? 1 : 0);
        // 3. The cull pass, from zeroed commands (and, in the first phase, zeroed counts).
        std::uint32_t cmds[5 * render::variant_count + 2] = {};  // the commands, then the counts of culled primitives
        for (int v = 0; v < render::variant_count; ++v) {
            cmds[5 * v + 1] = 1;
            if (points_ && static_cast<render::Variant>(v) == render::Variant::sphere)
                cmds[5 * v + 2] = ranges_[v].first;  // DrawArraysIndirectCommand: count, instances, first vertex, base instance
            else
                cmds[5 * v + 3] = 4 * ranges_[v].first;  // DrawElementsIndirectCommand: count, instances, first index, base vertex, base instance
        }
        gl.BindBuffer(GL_SHADER_STORAGE_BUFFER, commands_);
        if (ph.fresh)
            gl.BufferData(GL_SHADER_STORAGE_BUFFER, sizeof cmds, cmds, GL_DYNAMIC_DRAW);
        else
            gl.BufferSubData(GL_SHADER_STORAGE_BUFFER, 0, 5 * render::variant_count * sizeof(std::uint32_t), cmds);
        gl.BindBuffer(GL_SHADER_STORAGE_BUFFER, 0);
        // Each variant's workgroup counts at its own offset (16-uint aligned for BindBufferRange).
        std::uint32_t group_base[render::variant_count] = {};
        std::uint32_t group_total = 0;
        for (int v = 0; v < render::variant_count; ++v) {
            group_base[v] = group_total;
            group_total += (groups(ranges_[v].second, 64) + 63) / 64 * 64;
        }
        if (group_total > group_capacity_) {
            upload(groups_, std::vector<std::uint32_t>(group_total));
            upload(groups2_, std::vector<std::uint32_t>(group_total));
            group_capacity_ = group_total;
        }
        // (a program for the bounding-sphere rectangle, which reads no record, and one for the others)
        const Program* used = nullptr;
        for (int v = 0; v < render::variant_count; ++v) {
            if (!runs(v)) continue;
            const bool planes = static_cast<render::Variant>(v) == render::Variant::planes;
            // (the cull pass tests the bounding sphere's rectangle for every bound but the ellipsoid and slab ones)
            const RectBound bound = render::rect_bound(static_cast<render::Variant>(v));
            const bool sphere_rect = bound != RectBound::ellipsoid && bound != RectBound::slab;
            const Program& cull = programs_.get(render::OcclusionKey{render::OcclusionPass::cull, sphere_rect});
            if (&cull != used) {
                common(cull);
                gl.Uniform1ui(cull.uniform_location("qc_stats_at"), static_cast<GLuint>(5 * render::variant_count));
                gl.Uniform1i(cull.uniform_location("qc_reuse"), ph.reuse);
                gl.Uniform1i(cull.uniform_location("qc_list"), ph.list != 0 ? 1 : 0);
                set_pyramid_uniforms(gl, cull, levels);
                used = &cull;
            }
            gl.Uniform1ui(cull.uniform_location("qc_first"), ranges_[v].first);
            gl.Uniform1ui(cull.uniform_location("qc_count"), ranges_[v].second);
            if (!sphere_rect) gl.Uniform1i(cull.uniform_location("qc_bound"), static_cast<int>(bound));
            // The planes variant may not lie in its bounding sphere (a bilinear patch may reach out
            // of it inside its quad): no nearest distance, frustum culling only, unless all its
            // primitives show only inside their balls.
            gl.Uniform1i(cull.uniform_location("qc_occlusion"), (planes && !planes_in_ball_) || ph.reuse == 1 ? 0 : 1);
            gl.Uniform1i(cull.uniform_location("qc_windowed"), phased_variant(static_cast<render::Variant>(v)) && ph.count > 1 ? 1 : 0);
            gl.Uniform2f(cull.uniform_location("qc_window"), ph.lo, ph.hi);
            gl.Uniform1i(cull.uniform_location("qc_window_first"), ph.first() ? 1 : 0);
            gl.Uniform1i(cull.uniform_location("qc_window_last"), ph.last() ? 1 : 0);
            gl.BindBufferRange(GL_SHADER_STORAGE_BUFFER, 7, groups_, static_cast<GLintptr>(group_base[v] * sizeof(std::uint32_t)),
                               static_cast<GLsizeiptr>(groups(ranges_[v].second, 64) * sizeof(std::uint32_t)));
            gl.BindBufferBase(GL_SHADER_STORAGE_BUFFER, 11, keep2_);
            gl.BindBufferRange(GL_SHADER_STORAGE_BUFFER, 12, groups2_, static_cast<GLintptr>(group_base[v] * sizeof(std::uint32_t)),
                               static_cast<GLsizeiptr>(groups(ranges_[v].second, 64) * sizeof(std::uint32_t)));
            dispatch_rows(gl, groups(ranges_[v].second, 64));
        }
        gl.MemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
        // 4. Per variant the workgroups' first slots and the command, 5. the kept records in
        // order into the visible list (each variant's workgroup counts from its own offset).
        const Program& scan = programs_.get(render::OcclusionKey{render::OcclusionPass::scan});
        const Program& compact = programs_.get(render::OcclusionKey{render::OcclusionPass::compact});
        if (compute_bounds_) {
            if (count_ > bounds_capacity_) {  // grown only; 4 clip positions and 1 distance per slot
                api_->BindBuffer(GL_SHADER_STORAGE_BUFFER, corners_);
                api_->BufferData(GL_SHADER_STORAGE_BUFFER, static_cast<GLsizeiptr>(count_ * 16 * sizeof(float)), nullptr, GL_DYNAMIC_DRAW);
                api_->BindBuffer(GL_SHADER_STORAGE_BUFFER, nearests_);
                api_->BufferData(GL_SHADER_STORAGE_BUFFER, static_cast<GLsizeiptr>(count_ * sizeof(float)), nullptr, GL_DYNAMIC_DRAW);
                api_->BindBuffer(GL_SHADER_STORAGE_BUFFER, 0);
                bounds_capacity_ = count_;
            }
            gl.BindBufferBase(GL_SHADER_STORAGE_BUFFER, 8, corners_);
            gl.BindBufferBase(GL_SHADER_STORAGE_BUFFER, 9, nearests_);
        }
        // (the workgroup counts in `groups_of`, the flags bound at 6, the list at 4, the commands at 5)
        auto scan_and_compact = [&](GLuint groups_of, bool records) {
            for (int v = 0; v < render::variant_count; ++v) {
                if (!runs(v)) continue;
                gl.BindBufferRange(GL_SHADER_STORAGE_BUFFER, 7, groups_of, static_cast<GLintptr>(group_base[v] * sizeof(std::uint32_t)),
                                   static_cast<GLsizeiptr>(groups(ranges_[v].second, 64) * sizeof(std::uint32_t)));
                gl.UseProgram(scan.id());
                gl.Uniform1ui(scan.uniform_location("qc_group_count"), groups(ranges_[v].second, 64));
                gl.Uniform1ui(scan.uniform_location("qc_per_kept"), records ? 1u : per_kept(static_cast<render::Variant>(v)));
                gl.Uniform1ui(scan.uniform_location("qc_command_at"), static_cast<GLuint>(5 * v));
                gl.DispatchCompute(1, 1, 1);
                gl.MemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
                gl.UseProgram(compact.id());
                gl.Uniform1ui(compact.uniform_location("qc_first"), ranges_[v].first);
                gl.Uniform1ui(compact.uniform_location("qc_count"), ranges_[v].second);
                dispatch_rows(gl, groups(ranges_[v].second, 64));
            }
        };
        scan_and_compact(groups_, false);
        // 5'. With ph.list: the new shown set's records, the same way, into its list (their counts
        // per variant into commands2_, which `draw_primitives` reads back for the next frame).
        if (ph.list) {
            gl.MemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
            gl.BindBufferBase(GL_SHADER_STORAGE_BUFFER, 4, ph.list);
            gl.BindBufferBase(GL_SHADER_STORAGE_BUFFER, 5, commands2_);
            gl.BindBufferBase(GL_SHADER_STORAGE_BUFFER, 6, keep2_);
            scan_and_compact(groups2_, true);
            gl.BindBufferBase(GL_SHADER_STORAGE_BUFFER, 4, visible_);
            gl.BindBufferBase(GL_SHADER_STORAGE_BUFFER, 5, commands_);
            gl.BindBufferBase(GL_SHADER_STORAGE_BUFFER, 6, keep_);
        }
        // 6. With compute bounds, per variant one invocation per slot of its visible list (those
        // beyond its count return at once).
        if (compute_bounds_) {
            gl.MemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
            for (int v = 0; v < render::variant_count; ++v) {
                if (!runs(v)) continue;
                const auto variant = static_cast<render::Variant>(v);
                const Program& bounds = programs_.get(
                    render::OcclusionKey{render::OcclusionPass::bounds, render::fragment_shape(variant) == render::FragmentShape::sphere, cam.orthographic});
                gl.UseProgram(bounds.id());
                detail::set_camera_uniforms(gl, bounds, cam, width, height);
                set_bound_uniforms(bounds, variant, cam, opt);
                gl.Uniform1ui(bounds.uniform_location("qc_command_at"), static_cast<GLuint>(5 * v));
                dispatch_rows(gl, groups(ranges_[v].second, 64));
            }
        }
        gl.MemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_COMMAND_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT);
        for (int b = 2; b <= 12; ++b) gl.BindBufferBase(GL_SHADER_STORAGE_BUFFER, static_cast<GLuint>(b), 0);
        gl.BindTextureUnit(depth_texels_unit, 0);
    }

    /// The uniforms of a variant's bounding geometry and per-quadric culling, the same for its
    /// vertex stage and for the cull pass that computes them for it (`set_compute_bounds`).
    void set_bound_uniforms(const Program& prog, render::Variant variant, const render::Camera& cam, const render::RenderOptions& opt) const {
        const Api& gl = *api_;
        const bool cull = render::cast_options(variant, opt.culling).cull;
        gl.Uniform1i(prog.uniform_location("qc_bound"), opt.tight_bounds ? static_cast<int>(render::rect_bound(variant)) : 0);
        gl.Uniform1i(prog.uniform_location("qc_slab_quad"), slab_quads_ ? 1 : 0);
        gl.Uniform1i(prog.uniform_location("qc_cull"), cull && !cam.orthographic ? 1 : 0);
        gl.Uniform1ui(prog.uniform_location("qc_first"), ranges_[static_cast<int>(variant)].first);
        gl.Uniform1i(prog.uniform_location("qc_caps"), variant == render::Variant::slab ? 1 : 0);
    }

    /// The deferred pass: full-screen triangles into the colour target (no depth writes; the depth
    /// target keeps the quadric pass's depth) shading each pixel from the geometry buffer.
    void shade_deferred(const render::Camera& cam, const render::Light& light, const render::RenderOptions& opt) {
        const Api& gl = *api_;
        gl.BindFramebuffer(GL_FRAMEBUFFER, fbo_);
        for (int i = 0; i < 3; ++i) gl.BindTextureUnit(static_cast<GLuint>(i), gtex_[i]);
        const std::array<float, 4> pz = detail::projection_pz(cam);
        // With the depth test on, the covered pixels (window depth below 1) and the background
        // (depth 1: nothing passed the test there) are drawn apart: the full-screen triangle at
        // depth 1 (depth range [1, 1]), GREATER for the shading program, EQUAL for the background
        // one (background colour and outlines). The early depth test then skips every 4x4 block of
        // background for the shading, which llvmpipe would otherwise run masked, shadow-map
        // samples included. The same picture: the shading program draws its background colour
        // wherever nothing was hit, too.
        // (A pixel whose depth fails both tests, which only a pass writing gl_FragDepth at or beyond
        // the far plane can leave, keeps the background colour the target is cleared to.)
        // Without outlines the background program draws only the background colour, which the
        // target is cleared to: no background draw. With them, only the tiles where an outline
        // may show (OcclusionPass::outline_tiles), unless `set_outline_tiles(false)`.
        const bool split = depth_test_;
        const bool tiles = split && opt.silhouettes && outline_tiles_;
        const render::DeferredKey shading{opt.shadows, opt.silhouettes, opt.environment != nullptr, false, false, phases_for(opt) && phases_ready(opt)};
        phases_used_ = shading.phases;
        const render::DeferredKey background{false, opt.silhouettes, false, true, tiles};
        const std::pair<render::DeferredKey, const Program*> passes[2] = {{shading, &programs_.get(shading)},  // (compiled before any state changes)
                                                                          {background, split && opt.silhouettes ? &programs_.get(background) : nullptr}};
        if (tiles) {
            // The tiles' list and its draw command (the count zeroed), from the normal target (unit 0)
            const Program& list = programs_.get(render::OcclusionKey{render::OcclusionPass::outline_tiles});
            const auto tw = static_cast<std::uint32_t>((opt.width + 7) / 8), th = static_cast<std::uint32_t>((opt.height + 7) / 8);
            if (tw * th > tile_capacity_) {
                upload(tiles_, std::vector<std::uint32_t>(tw * th));
                tile_capacity_ = tw * th;
            }
            const std::uint32_t command[4] = {0, 1, 0, 0};
            upload(tile_command_, std::vector<std::uint32_t>(std::begin(command), std::end(command)));
            gl.UseProgram(list.id());
            gl.Uniform2ui(list.uniform_location("qc_size"), static_cast<GLuint>(opt.width), static_cast<GLuint>(opt.height));
            gl.BindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, tiles_);
            gl.BindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, tile_command_);
            gl.DispatchCompute((tw + 7) / 8, (th + 7) / 8, 1);
            gl.MemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_COMMAND_BARRIER_BIT);
            gl.BindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, 0);
        }
        if (split) {
            const float bg[4] = {opt.background[0], opt.background[1], opt.background[2], 1.0f};
            gl.ClearBufferfv(GL_COLOR, 0, bg);
            gl.Enable(GL_DEPTH_TEST);
            gl.DepthMask(GL_FALSE);
            gl.DepthRangef(1.0f, 1.0f);
        } else {
            gl.Disable(GL_DEPTH_TEST);
        }
        for (const auto& [key, program] : std::span(passes, passes[1].second ? 2 : 1)) {
            const Program& prog = *program;
            gl.UseProgram(prog.id());
            gl.Uniform3fv(prog.uniform_location("qc_background"), 1, opt.background.c);
            gl.Uniform4fv(prog.uniform_location("qc_pz"), 1, pz.data());
            gl.Uniform4fv(prog.uniform_location("qc_silhouette_params"), 1, opt.silhouette.c);
            if (!key.background) {
                gl.Uniform3fv(prog.uniform_location("qc_light_dir"), 1, light.direction.c);
                gl.Uniform3fv(prog.uniform_location("qc_light_color"), 1, light.color.c);
                gl.Uniform4fv(prog.uniform_location("qc_material"), 1, opt.material.c);
            }
            if (key.environment) {
                gl.BindTextureUnit(4, etex_);
                gl.Uniform1f(prog.uniform_location("qc_reflectivity"), opt.reflectivity);
            }
            if (key.shadows) {
                gl.BindTextureUnit(3, stex_);
                if (key.phases) {
                    gl.BindTextureUnit(5, ptex_);
                    gl.Uniform1f(prog.uniform_location("qc_pcf_inv_step"), 1.0f / static_cast<float>(opt.pcf_step));
                    gl.Uniform1f(prog.uniform_location("qc_phase_tile"), static_cast<float>(phase_tile_));
                    gl.Uniform1f(prog.uniform_location("qc_phase_inv_size"), 1.0f / static_cast<float>(phase_tile_ * opt.pcf_step));
                }
                const Mat4<float> m = render::camera_to_light(cam, light_cam_);
                float to_light[16];
                for (int j = 0; j < 4; ++j)
                    for (int i = 0; i < 4; ++i) to_light[j * 4 + i] = m[j][i];
                gl.UniformMatrix4fv(prog.uniform_location("qc_to_light"), 1, GL_FALSE, to_light);
                gl.Uniform2f(prog.uniform_location("qc_viewport"), static_cast<float>(opt.width), static_cast<float>(opt.height));
                gl.Uniform1f(prog.uniform_location("qc_shadow_size"), static_cast<float>(shadow_size_));
                gl.Uniform1f(prog.uniform_location("qc_shadow_bias"), opt.shadow_bias / static_cast<float>(shadow_size_));
                gl.Uniform1f(prog.uniform_location("qc_pcf_step"), static_cast<float>(opt.pcf_step));
                gl.Uniform1i(prog.require_uniform("qc_pcf_samples"), static_cast<GLint>(std::size(pcf_grid_order)));
            }
            if (split) gl.DepthFunc(key.background ? GL_EQUAL : GL_GREATER);
            if (key.tiles) {
                gl.Uniform2f(prog.uniform_location("qc_viewport"), static_cast<float>(opt.width), static_cast<float>(opt.height));
                gl.Enable(GL_PROGRAM_POINT_SIZE);
                gl.BindBuffer(GL_DRAW_INDIRECT_BUFFER, tile_command_);
                gl.DrawArraysIndirect(GL_POINTS, nullptr);
                gl.BindBuffer(GL_DRAW_INDIRECT_BUFFER, 0);
                gl.BindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, 0);
            } else {
                gl.DrawArrays(GL_TRIANGLES, 0, 3);
            }
        }
        if (split) {
            gl.DepthRangef(0.0f, 1.0f);
            gl.DepthMask(GL_TRUE);
            gl.DepthFunc(GL_LESS);
            gl.Disable(GL_DEPTH_TEST);
        }
        for (int i = 0; i < 6; ++i) gl.BindTextureUnit(static_cast<GLuint>(i), 0);
    }

    /// The shadow map in phases of the PCF step for the deferred pass's gathered samples
    /// (DeferredKey::phases, OcclusionPass::shadow_phases, `phase_source_texel`): an R32F image of
    /// step x step tiles of `pcf_phase_tile` texels per side, made once per
    /// map drawn and step (kept with a kept map).
    void make_shadow_phases(int step) {
        const Api& gl = *api_;
        const int tile = pcf_phase_tile(shadow_size_, step);
        if (ptex_ == 0 || phase_tile_ != tile || phases_step_ != step) {
            if (ptex_ != 0) gl.DeleteTextures(1, &ptex_);
            gl.GenTextures(1, &ptex_);
            gl.BindTexture(GL_TEXTURE_2D, ptex_);
            gl.TexStorage2D(GL_TEXTURE_2D, 1, GL_R32F, tile * step, tile * step);
            gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
            gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
            gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
            gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
            gl.BindTexture(GL_TEXTURE_2D, 0);
            phase_tile_ = tile;
        }
        const Program& prog = programs_.get(render::OcclusionKey{render::OcclusionPass::shadow_phases});
        gl.UseProgram(prog.id());
        gl.Uniform1i(prog.uniform_location("qc_size"), tile * step);
        gl.Uniform1f(prog.uniform_location("qc_last"), static_cast<float>(shadow_size_ - 1));
        gl.Uniform1f(prog.uniform_location("qc_pcf_step"), static_cast<float>(step));
        gl.Uniform1f(prog.uniform_location("qc_phase_tile"), static_cast<float>(tile));
        gl.Uniform1f(prog.uniform_location("qc_phase_inv_tile"), 1.0f / static_cast<float>(tile));
        gl.BindTextureUnit(0, stex_);
        gl.BindImageTexture(0, ptex_, 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_R32F);
        const auto groups = static_cast<GLuint>((tile * step + 7) / 8);
        gl.DispatchCompute(groups, groups, 1);
        gl.MemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT);
        gl.BindImageTexture(0, 0, 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_R32F);
        gl.BindTextureUnit(0, 0);
        phases_step_ = step;
        phases_key_ = shadow_key_;
    }

    /// The environment image as an RGB32F texture (the floats of the map, read with texelFetch:
    /// no filtering or format conversion), uploaded when the map changes.
    void ensure_environment(const std::shared_ptr<const render::EnvironmentMap>& env) {
        if (env == env_) return;
        const Api& gl = *api_;
        if (env->width < 1 || env->height < 1 || env->rgb.size() != std::size_t(env->width) * env->height * 3)
            throw std::invalid_argument("quadcast::gl::QuadricRenderer: environment map size does not match its texels");
        if (etex_) gl.DeleteTextures(1, &etex_);
        gl.GenTextures(1, &etex_);
        gl.BindTexture(GL_TEXTURE_2D, etex_);
        gl.TexStorage2D(GL_TEXTURE_2D, 1, GL_RGB32F, env->width, env->height);
        gl.PixelStorei(GL_UNPACK_ALIGNMENT, 4);
        gl.TexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, env->width, env->height, GL_RGB, GL_FLOAT, env->rgb.data());
        gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
        gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
        gl.BindTexture(GL_TEXTURE_2D, 0);
        env_ = env;
    }

    /// The shadow map (DEPTH32F, size x size, no colour), remade when the size changes.
    void ensure_shadow_map(int size) {
        if (sfbo_ != 0 && size == shadow_size_) return;
        const Api& gl = *api_;
        release_shadow_map();
        shadow_size_ = size;
        shadow_valid_ = false;
        stex_ = nearest_texture(gl, GL_DEPTH_COMPONENT32F, size, size);
        gl.GenFramebuffers(1, &sfbo_);
        gl.BindFramebuffer(GL_FRAMEBUFFER, sfbo_);
        gl.FramebufferTexture2D(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_TEXTURE_2D, stex_, 0);
        gl.DrawBuffer(GL_NONE);
        gl.ReadBuffer(GL_NONE);
        const GLenum status = gl.CheckFramebufferStatus(GL_FRAMEBUFFER);
        gl.BindFramebuffer(GL_FRAMEBUFFER, 0);
        if (status != GL_FRAMEBUFFER_COMPLETE) throw std::runtime_error("quadcast::gl::QuadricRenderer: incomplete shadow map");
    }

    void release_shadow_map() {
        if (ptex_ != 0) api_->DeleteTextures(1, &ptex_);
        ptex_ = 0;
        phases_step_ = 0;
        if (sfbo_ == 0) return;
        api_->DeleteFramebuffers(1, &sfbo_);
        api_->DeleteTextures(1, &stex_);
        sfbo_ = 0;
    }

    /// A width x height texture of `format`, one level, nearest filtering.
    static GLuint nearest_texture(const Api& gl, GLenum format, int width, int height) {
        GLuint t = 0;
        gl.GenTextures(1, &t);
        gl.BindTexture(GL_TEXTURE_2D, t);
        gl.TexStorage2D(GL_TEXTURE_2D, 1, format, width, height);
        gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
        gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
        gl.BindTexture(GL_TEXTURE_2D, 0);
        return t;
    }

    /// The geometry buffer (three RGBA32F targets sharing the depth target), made on first use.
    void ensure_gbuffer() {
        if (gfbo_ != 0) return;
        const Api& gl = *api_;
        for (GLuint& t : gtex_) t = nearest_texture(gl, GL_RGBA32F, width_, height_);
        gl.GenFramebuffers(1, &gfbo_);
        gl.BindFramebuffer(GL_FRAMEBUFFER, gfbo_);
        for (int i = 0; i < 3; ++i) gl.FramebufferTexture2D(GL_FRAMEBUFFER, static_cast<GLenum>(GL_COLOR_ATTACHMENT0 + i), GL_TEXTURE_2D, gtex_[i], 0);
        gl.FramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT3, GL_TEXTURE_2D, idtex_, 0);
        gl.FramebufferTexture2D(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_TEXTURE_2D, tex_[1], 0);
        const GLenum bufs[3] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1, GL_COLOR_ATTACHMENT2};
        gl.DrawBuffers(3, bufs);
        const GLenum status = gl.CheckFramebufferStatus(GL_FRAMEBUFFER);
        gl.BindFramebuffer(GL_FRAMEBUFFER, 0);
        if (status != GL_FRAMEBUFFER_COMPLETE) throw std::runtime_error("quadcast::gl::QuadricRenderer: incomplete geometry buffer");
    }

    void set_uniforms(const Program& p, const render::Camera& cam, const render::Light& light, const render::RenderOptions& opt, int width,
                      int height) const {
        const Api& gl = *api_;
        detail::set_camera_uniforms(gl, p, cam, width, height);
        gl.Uniform3fv(p.uniform_location("qc_light_dir"), 1, light.direction.c);
        gl.Uniform3fv(p.uniform_location("qc_light_color"), 1, light.color.c);
        gl.Uniform4fv(p.uniform_location("qc_material"), 1, opt.material.c);
        if (opt.environment) {
            gl.BindTextureUnit(4, etex_);
            gl.Uniform1f(p.uniform_location("qc_reflectivity"), opt.reflectivity);
        }
        if (stage_ == FragmentStage::brute_force) {
            const Mat4<float> ivp = inverse_view_projection(cam);
            gl.UniformMatrix4fv(p.uniform_location("qc_inv_view_proj"), 1, GL_FALSE, &ivp[0][0]);
        }
    }

    /// (projection view)^-1 in double (`host_inverse`), rounded to float.
    static Mat4<float> inverse_view_projection(const render::Camera& cam) {
        return cast<float>(host_inverse(cast<double>(cam.projection) * cast<double>(cam.view)));
    }


    void ensure_fbo(int w, int h) {
        if (fbo_ != 0 && w == width_ && h == height_) return;
        release_fbo();
        const Api& gl = *api_;
        width_ = w;
        height_ = h;
        fbo_ = make_framebuffer(gl, w, h, tex_, "quadcast::gl::QuadricRenderer");
        // The ids target (QuadricKey::ids), colour attachment 1 here and 3 of the geometry buffer;
        // drawn into only by the frames that make the shown set from the picture.
        idtex_ = nearest_texture(gl, GL_R32UI, w, h);
        gl.BindFramebuffer(GL_FRAMEBUFFER, fbo_);
        gl.FramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT1, GL_TEXTURE_2D, idtex_, 0);
        const GLenum first[1] = {GL_COLOR_ATTACHMENT0};
        gl.DrawBuffers(1, first);
        const GLenum status = gl.CheckFramebufferStatus(GL_FRAMEBUFFER);
        gl.BindFramebuffer(GL_FRAMEBUFFER, 0);
        if (status != GL_FRAMEBUFFER_COMPLETE) throw std::runtime_error("quadcast::gl::QuadricRenderer: incomplete framebuffer with the ids target");
    }

    /// Drops the shown sets of a depth target (its texture is gone, or its frames do not reuse one):
    /// a texture name GL hands out again later names other depths and other ids.
    void forget_shown_sets(GLuint depth_target) {
        for (ShownSet& s : shown_)
            if (s.target == depth_target) s.valid = s.listed = s.owners.valid = s.of_picture = false;
    }

    void release_fbo() {
        if (fbo_ != 0) forget_shown_sets(tex_[1]);
        if (gfbo_ != 0) {
            api_->DeleteFramebuffers(1, &gfbo_);
            api_->DeleteTextures(3, gtex_);
            gfbo_ = 0;
        }
        if (fbo_ == 0) return;
        api_->DeleteFramebuffers(1, &fbo_);
        api_->DeleteTextures(2, tex_);
        api_->DeleteTextures(1, &idtex_);
        idtex_ = 0;
        fbo_ = 0;
    }

    const Api* api_;
    GLuint vao_ = 0, ssbo_ = 0, planes_ = 0, indices_ = 0, fbo_ = 0, tex_[2] = {0, 0};
    GLuint gfbo_ = 0, gtex_[3] = {0, 0, 0};  ///< geometry buffer of deferred shading
    GLuint tiles_ = 0, tile_command_ = 0;     ///< the deferred pass's outline tiles and their draw command
    std::uint32_t tile_capacity_ = 0;
    bool outline_tiles_ = true;
    bool shadow_phases_ = true;     ///< set_shadow_phases
    bool shown_from_picture_ = true;  ///< set_shown_from_picture
    bool ids_frame_ = false;        ///< this frame's primitives write the ids target (draw_primitives)
    bool reshade_ = true;           ///< set_reshade
    bool prefetch_ = false;         ///< this frame also compiles a still camera's later programs (draw_primitives)
    bool reshade_frame_ = false;    ///< this frame shades the sphere variant from the ids target (draw_primitives)
    bool reshaded_ = false;         ///< it did (reshaded)
    bool picture_set_drawn_ = false;  ///< the last `draw_primitives` drew a picture's records alone (shown_set_from_picture)
    GLuint idtex_ = 0;              ///< the ids target (R32UI: per pixel the record it shows + 1)
    GLuint owner_bits_ = 0, owner_groups_ = 0;  ///< the shown records' bits, their words' counts (make_owner_set)
    std::uint32_t owner_words_ = 0;  ///< words allocated in owner_bits_
    GLuint ptex_ = 0;               ///< the shadow map in phases (make_shadow_phases)
    int phase_tile_ = 0;            ///< texels per side of a tile of ptex_
    int phases_step_ = 0;           ///< the PCF step of ptex_'s phases (its tiles per side)
    std::vector<std::uint64_t> phases_key_;  ///< `shadow_key` of the map ptex_ holds in phases
    bool phases_used_ = false;      ///< the last deferred pass read ptex_
    GLuint sfbo_ = 0, stex_ = 0;             ///< shadow map
    GLuint etex_ = 0;                        ///< environment map
    GLuint occluders_ = 0, depths_ = 0, visible_ = 0, commands_ = 0, keep_ = 0, groups_ = 0;  ///< occlusion culling
    GLuint depth_view_ = 0;  ///< texture-buffer view of depths_ (depth_texels_unit): the cull pass's and the early discard's reads
    GLuint keep2_ = 0, groups2_ = 0, commands2_ = 0;  ///< the shown set's flags, workgroup counts and per-variant counts for its list
    GLuint corners_ = 0, nearests_ = 0;  ///< per slot of the visible list: 4 clip positions, the nearest distance
    std::size_t bounds_capacity_ = 0;    ///< slots corners_ and nearests_ hold
    std::uint32_t group_capacity_ = 0;
    GLuint cull_queries_[16] = {};     ///< GL_TIME_ELAPSED of the cull passes of a frame (the shadow map's and the camera's phases)
    int cull_queries_used_ = 0;
    bool planes_in_ball_ = false;      ///< every planes primitive shows only inside its bounding ball (`planes_within_ball`)
    bool phases_planes_ = false, phases_others_ = false;  ///< which variants `phased_variant` may phase
    bool frame_phases_planes_ = false, frame_phases_others_ = false;  ///< `phased_variant` in this frame
    int phase_count_ = 1;  ///< the phases of the last `draw_primitives`
    /// RenderOptions::occlusion_reuse: per depth target (the camera's, the shadow map's) whether
    /// each record passed its last test against what was drawn (`shown_`), and whether that is
    /// valid for the current records and that target.
    ShownSet shown_[2];
    int next_shown_ = 0;
    bool reused_ = false;  ///< the last `draw_primitives` drew the last frame's shown set first
    bool view_unchanged_ = false;  ///< ... and only it: the view it was tested under (`draw_primitives`)
    bool keep_unchanged_sets_ = true;  ///< off: `set_skip_unchanged_view_test(false)`
    std::size_t unchanged_drawn_ = 0;  ///< the set it drew then
    /// Reuse runs in frames whose expected overlap reaches this share of
    /// RenderOptions::occlusion_min_overlap (or whose cull pass runs anyway): at 1024x768 10k
    /// random spheres (overlap 2.63) drew 1.08-1.13x faster with it, the 1TII balls-and-sticks
    /// demo (0.64; shadows: a 2048^2 depth image and pyramid more) 1.4x slower.
    static constexpr double reuse_overlap_share = 2.0 / 3.0;
    static constexpr std::size_t phase_min_count = 4096;
    render::OverlapSample overlap_sample_;  ///< what `expected_overlap` estimates a frame's overlap from
    bool cull_pass_ran_ = false;            ///< the last `draw_primitives` ran the cull pass
    double expected_overlap_ = 0.0;         ///< the overlap it decided on (0: not estimated)
    std::vector<std::array<float, 4>> phase_sample_;  ///< centres and radii of at most ~4096 phased primitives (`phase_cuts`)
    std::size_t earlier_phases_drawn_ = 0;  ///< primitives drawn by the phases before the last of the last `draw_primitives`
    double cull_ms_ = 0.0;  ///< GPU time of the last draw's cull passes (GL_TIME_ELAPSED)
    std::size_t depth_texels_ = 0, drawn_ = 0, frustum_culled_ = 0, occluded_ = 0;
    std::shared_ptr<const render::EnvironmentMap> env_;  ///< the map in etex_
    int shadow_size_ = 0;
    render::Camera light_cam_;
    std::uint64_t revision_ = 0;  ///< changed by every setter, `set_primitives` and the passes' list (the shadow map's key)
    /// This renderer among all of the process's (the key under its passes: a renderer made anew,
    /// with the same revision count and GL names handed out again, is not the old one)
    const std::uint64_t instance_ = next_instance();
    static std::uint64_t next_instance() {
        static std::atomic<std::uint64_t> count{0};
        return ++count;
    }
    std::vector<std::uint64_t> shadow_key_;  ///< `shadow_key` of the shadow map drawn last
    bool shadow_valid_ = false;   ///< that map may be kept (every pass tracks its revision)
    bool shadow_reused_ = false;  ///< the last `draw` kept it
    Vec3<double> bounds_lo_{{1e300, 1e300, 1e300}}, bounds_hi_{{-1e300, -1e300, -1e300}};  ///< of the primitives' bounding spheres (the light camera)
    std::vector<ScenePass*> passes_;
    int width_ = 0, height_ = 0;
    std::size_t count_ = 0;
    std::pair<std::uint32_t, std::uint32_t> ranges_[render::variant_count] = {};
    GeneratedPrograms programs_{*api_, "quadcast::gl::QuadricRenderer"};
    FragmentStage stage_ = FragmentStage::incremental;
    bool depth_test_ = true;
    bool slab_quads_ = true;
    std::uint32_t row_limit_ = 65535u;
    bool early_discard_ = true;
    bool compute_bounds_ = false;  ///< off by default: it did not pay on llvmpipe (bench spheres, 'comp')
    bool raster_occluders_ = false;  ///< off by default: it did not pay on llvmpipe (bench spheres, 'rast')
    bool point_sprites_ = true;  ///< the sphere variant as point sprites where they fit (`set_point_sprites`)
    bool points_ = false;        ///< the frame being drawn does (`draw_primitives`)
    float max_point_size_ = 1.0f;  ///< GL_POINT_SIZE_RANGE's upper end
    Vec3<float> sphere_lo_{}, sphere_hi_{};  ///< the box of the sphere variant's centres (empty: lo > hi)
    float sphere_radius_ = 0.0f;             ///< its largest radius
    static constexpr std::size_t each_sphere_limit = 32768;  ///< spheres tested one by one where their box does not fit (`sprites_fit`)
    std::vector<std::array<float, 4>> each_sphere_;  ///< their centres and radii (collected up to one more than the limit: more are not tested)
    std::vector<float> each_sphere_key_;             ///< the camera and viewport of `each_sphere_fit_`
    bool each_sphere_fit_ = false;
    bool occluders_in_depth_ = false;  ///< `rasterise_occluders` drew into the depth target of the next `draw_primitives`
    GLuint query_ = 0, fs_query_ = 0;
    std::uint64_t samples_passed_ = 0;
    FragmentCounts counts_;
    bool count_fragments_ = false;
    bool counting_ = false;  ///< the primitive pass of a `draw` with count_fragments_: the counting stages
    GLuint count_buffer_ = 0;
};

QuadricRenderer::QuadricRenderer(const Api& api) : impl_(std::make_unique<Impl>(api)) {}
QuadricRenderer::~QuadricRenderer() = default;
void QuadricRenderer::set_fragment_stage(FragmentStage s) { impl_->set_fragment_stage(s); }
QuadricRenderer::FragmentStage QuadricRenderer::fragment_stage() const { return impl_->fragment_stage(); }
void QuadricRenderer::set_depth_test(bool on) { impl_->set_depth_test(on); }
void QuadricRenderer::set_slab_quads(bool on) { impl_->set_slab_quads(on); }
void QuadricRenderer::set_early_discard(bool on) { impl_->set_early_discard(on); }
void QuadricRenderer::set_compute_bounds(bool on) { impl_->set_compute_bounds(on); }
void QuadricRenderer::set_outline_tiles(bool on) { impl_->set_outline_tiles(on); }
void QuadricRenderer::set_shadow_phases(bool on) { impl_->set_shadow_phases(on); }
void QuadricRenderer::set_shown_from_picture(bool on) { impl_->set_shown_from_picture(on); }
bool QuadricRenderer::shown_set_from_picture() const { return impl_->shown_set_from_picture(); }
void QuadricRenderer::set_reshade(bool on) { impl_->set_reshade(on); }
bool QuadricRenderer::reshaded() const { return impl_->reshaded(); }
bool QuadricRenderer::used_shadow_phases() const { return impl_->used_shadow_phases(); }
void QuadricRenderer::set_skip_unchanged_view_test(bool on) { impl_->set_skip_unchanged_view_test(on); }
void QuadricRenderer::set_raster_occluders(bool on) { impl_->set_raster_occluders(on); }
void QuadricRenderer::set_point_sprites(bool on) { impl_->set_point_sprites(on); }
bool QuadricRenderer::drew_points() const { return impl_->drew_points(); }
void QuadricRenderer::set_dispatch_row_limit(std::uint32_t groups) { impl_->set_dispatch_row_limit(groups); }
std::uint64_t QuadricRenderer::samples_passed() const { return impl_->samples_passed(); }
void QuadricRenderer::set_count_fragments(bool on) { impl_->set_count_fragments(on); }
std::uint64_t QuadricRenderer::fragment_invocations() const { return impl_->fragment_invocations(); }
const FragmentCounts& QuadricRenderer::fragment_counts() const { return impl_->fragment_counts(); }
void QuadricRenderer::add_pass(ScenePass& p) { impl_->add_pass(p); }
void QuadricRenderer::clear_passes() { impl_->clear_passes(); }
void QuadricRenderer::set_primitives(const std::vector<render::Primitive>& prims) { impl_->set_primitives(prims); }
void QuadricRenderer::draw(const render::Camera& cam, const render::Light& light, const render::RenderOptions& opt) {
    impl_->draw(cam, light, opt);
}
void QuadricRenderer::draw_primitives(const render::Camera& cam, const render::Light& light, const render::RenderOptions& opt, bool deferred) {
    impl_->draw_into_bound(cam, light, opt, deferred);
}
render::Image QuadricRenderer::read() const { return impl_->read(); }
std::size_t QuadricRenderer::primitive_count() const { return impl_->primitive_count(); }
std::size_t QuadricRenderer::drawn_primitives() const { return impl_->drawn_primitives(); }
bool QuadricRenderer::cull_pass_ran() const { return impl_->cull_pass_ran(); }
int QuadricRenderer::phases() const { return impl_->phases(); }
bool QuadricRenderer::reused_shown_set() const { return impl_->reused_shown_set(); }
bool QuadricRenderer::unchanged_view() const { return impl_->unchanged_view(); }
bool QuadricRenderer::reused_shadow_map() const { return impl_->reused_shadow_map(); }
double QuadricRenderer::expected_overlap() const { return impl_->expected_overlap(); }
std::size_t QuadricRenderer::frustum_culled() const { return impl_->frustum_culled(); }
std::size_t QuadricRenderer::occluded() const { return impl_->occluded(); }
double QuadricRenderer::cull_pass_ms() const { return impl_->cull_pass_ms(); }

}  // namespace quadcast::gl
