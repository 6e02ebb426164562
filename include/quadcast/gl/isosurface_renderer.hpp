// quadcast/gl/isosurface_renderer.hpp -- OpenGL 4.5 isosurfaces of QSS / S31 splines and trilinear volumes (generated shaders)
#pragma once
// Host-only. Kalbe & Zeilfelder 2008, Sect. 5, on generated shaders:
// - GPU data: the determining sets of the active cubes (20 or 56 floats each) in a shader storage
//   buffer, or the samples for trilinear; one record per drawn element (cube index + tetrahedron,
//   or cell index). No vertex is stored: the geometry is implicit.
// - Per frame, the min-max octree (coefficient ranges, the convex hull property) and hierarchical
//   frustum culling select the cubes; every relevant tetrahedron of a selected cube (its own
//   coefficient range contains ρ) is drawn as its 4 back faces (indexed, 4 vertices), every active
//   trilinear cell as its box's back faces (8 vertices).
// - Vertex stage (traced): the tetrahedron's BB-coefficients by repeated averaging from the
//   determining set seen from that tetrahedron (or read from a compute pre-pass that runs the same
//   averaging once per tetrahedron: by default for S31 within a memory budget, CoefficientStage),
//   the vertex's clip position and the ray terms.
// - Occlusion culling (RenderOptions::occlusion_culling, occlusion_phases): the cubes (cells)
//   nearest first, the tetrahedra (cells) in phases; before each later phase a copy of the depth buffer,
//   its max-depth pyramid and per element `spline::tet_occlusion_bound` / `cell_occlusion_bound` (compute): the kept
//   ones are compacted into a list of survivors (compute), which the phase draws; their fragments
//   behind the copied depth are discarded before they cast. The same picture, bit for bit.
// - Fragment stage (traced): the interpolated ray is rotated into T_0, clipped by barycentric
//   coordinates, restricted to a univariate BB-form by blossoming, its first root gives the hit;
//   depth, normal; forward Blinn-Phong or the quadric renderer's geometry buffer (deferred,
//   shadows, silhouettes), so it is drawn as a `ScenePass` of a `QuadricRenderer`.

#include <algorithm>
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "quadcast/gl/depth_pyramid.hpp"
#include "quadcast/gl/generated_programs.hpp"
#include "quadcast/gl/loader.hpp"
#include "quadcast/gl/program.hpp"
#include "quadcast/gl/scene_pass.hpp"
#include "quadcast/render/spline_cpu_renderer.hpp"
#include "quadcast/render/types.hpp"
#include "quadcast/spline/masks.hpp"

namespace quadcast::gl {

/// What the last `draw` of one volume selected.
struct IsoDrawStats {
    std::size_t active = 0;          ///< active cubes / cells of the volume (range contains ρ)
    std::size_t visible = 0;         ///< of these, not outside the view frustum
    std::size_t elements = 0;        ///< tetrahedra / cells drawn
    std::size_t relevant = 0;        ///< relevant tetrahedra / active cells of the whole volume
    std::size_t nodes_visited = 0;   ///< octree nodes tested
    int phases = 0;                  ///< phases drawn (occlusion culling: each later one tested against the earlier ones' depth)
    std::size_t occluded = 0;        ///< elements of the later phases culled behind the earlier ones
    bool reused = false;             ///< the last frame's shown set was drawn first (RenderOptions::occlusion_reuse)
    bool unchanged_view = false;     ///< that set was drawn alone, untested: the view and the depth under the pass are those it was tested under
    std::size_t alone = 0;           ///< with unchanged_view: the set's elements (drawn), of `elements`
    bool pre_pass = false;           ///< the coefficients came from the compute pre-pass (IsosurfaceRenderer::CoefficientStage)
};

/// Draws the isosurfaces of prepared volumes (`render::prepare_volume`, with or without CPU
/// coefficients) into the bound framebuffer. Not thread-safe (GL contexts are not).
class IsosurfaceRenderer final : public ScenePass {
public:
    explicit IsosurfaceRenderer(const Api& api) : api_(&api) { api.GenVertexArrays(1, &vao_); }
    ~IsosurfaceRenderer() override {
        for (Volume& v : volumes_) release(v);
        api_->DeleteVertexArrays(1, &vao_);
        for (DepthCopy& c : copies_) {
            if (c.fbo) api_->DeleteFramebuffers(1, &c.fbo);
            if (c.tex) api_->DeleteTextures(1, &c.tex);
        }
        if (pyramid_) api_->DeleteBuffers(1, &pyramid_);
        if (pyramid_view_) api_->DeleteTextures(1, &pyramid_view_);
    }
    IsosurfaceRenderer(const IsosurfaceRenderer&) = delete;
    IsosurfaceRenderer& operator=(const IsosurfaceRenderer&) = delete;

    /// Frustum culling of the octree nodes (on by default); off draws every relevant element.
    void set_frustum_culling(bool on) {
        frustum_culling_ = on;
        ++revision_;
    }
    /// Skipping the tetrahedra of an active cube whose own coefficient range misses ρ (on by
    /// default); off draws all 24 tetrahedra of every selected cube.
    void set_tetrahedron_culling(bool on) {
        tet_culling_ = on;
        ++revision_;
    }

    /// Where a tetrahedron's BB-coefficients are rebuilt from the determining set: in the vertex
    /// stage, once per vertex (the paper's way), or in a compute pre-pass once per drawn
    /// tetrahedron into a storage buffer the vertex stage reads (same traced averaging, same
    /// numbers; llvmpipe runs vertex shaders on one thread but compute shaders on all), or
    /// `automatic` (the default): the pre-pass for S31 lists whose coefficients fit in the
    /// pre-pass budget (`set_pre_pass_budget`), the vertex stage otherwise. Why (`quadcast bench isosurfaces`
    /// and `render --frames`, 1024x768, frames interleaved): the pre-pass made CGAL's skull S31
    /// frame 1.11x faster (S31 averages 56 values into 20 per vertex), and QSS (10 from 23) gained
    /// nothing measurable; on the liver (S31, several million tetrahedra drawn) it gained 1.07-1.13x
    /// but raised the process's peak memory from 0.97 to 1.7 GB.
    enum class CoefficientStage { vertex, compute, automatic };
    /// `CoefficientStage::automatic` uses the pre-pass where the frame's list needs at most this
    /// many bytes of coefficients, per volume (default 64 MiB: 838,860 S31 tetrahedra of 20
    /// floats; the buffer is allocated with 1/8 headroom and kept for later frames).
    void set_pre_pass_budget(std::size_t bytes) {
        pre_pass_budget_ = bytes;
        ++revision_;
    }
    std::size_t pre_pass_budget() const { return pre_pass_budget_; }
    void set_coefficient_stage(CoefficientStage s) {
        coeff_stage_ = s;
        ++revision_;
    }

    /// Where the frame's element list is built: on the CPU (the default), where the min-max
    /// octree's hierarchical frustum test selects the cubes and their elements are uploaded each
    /// frame; or on the GPU, where compute passes test every active cube's box against the view
    /// frustum (`spline::clip_outside` of its corners as the vertex stage computes them; trilinear:
    /// every active cell), keep the relevant tetrahedra of the kept cubes from the volume's list of
    /// all of them, uploaded once, and copy them in order into the list the vertex stage reads
    /// (IsoDrawStats::visible and nodes_visited are counted on the CPU path only). The same picture;
    /// both draw over a fixed index buffer of at most 65536 elements, in batches. The CPU list is
    /// the default: on llvmpipe the GPU list's frame time is within the noise of the CPU list's
    /// (`quadcast bench isosurfaces`, column 'GPU list', time ratios to the CPU list: skull,
    /// 218k tetrahedra, 1.00-1.01x; liver, 2.9M, 0.98-1.29x whole, 0.86-0.99x close-up), its
    /// per-element compute passes costing about what the octree and the upload cost, and it keeps
    /// 36 B per relevant element on the GPU against 16 B per drawn one.
    enum class ElementList { gpu, cpu };
    void set_element_list(ElementList l) {
        element_list_ = l;
        ++revision_;
    }

    /// Elements per draw call (default and upper limit 65536, the index buffer's size; at least
    /// 1). A test switch: smaller batches give the same picture.
    void set_batch_elements(std::size_t n) {
        batch_elements = std::clamp<std::size_t>(n, 1, 65536);
        ++revision_;
        for (Volume& v : volumes_) v.index_capacity = 0;  // (remade at the new size)
    }

    /// Adds a volume; `m` must outlive the renderer's use of it (its octree is consulted per
    /// frame) and must not change while it is added (its data is uploaded here: `clear` and add
    /// it again). Uploads its determining sets (or samples). Throws std::invalid_argument for an
    /// empty or inconsistent model.
    void add_volume(const render::VolumeModel& m) {
        const Api& gl = *api_;
        const bool tri = m.scheme == render::VolumeScheme::trilinear;
        if (m.nx < 1 || m.ny < 1 || m.nz < 1) throw std::invalid_argument("quadcast::gl::IsosurfaceRenderer: empty volume");
        if (m.octree.level_count() == 0) throw std::invalid_argument("quadcast::gl::IsosurfaceRenderer: the volume has no octree (not from prepare_volume)");
        Volume v;
        v.model = &m;
        gl.GenBuffers(1, &v.data);
        gl.GenBuffers(1, &v.elements);
        gl.GenBuffers(1, &v.indices);
        gl.GenBuffers(1, &v.coeffs);
        gl.BindBuffer(GL_SHADER_STORAGE_BUFFER, v.data);
        if (tri) {
            const std::size_t n = static_cast<std::size_t>(m.nx) * m.ny * m.nz;
            if (m.samples.size() != n) throw std::invalid_argument("quadcast::gl::IsosurfaceRenderer: trilinear volume without its samples");
            upload(GL_SHADER_STORAGE_BUFFER, m.samples);
        } else {
            const std::size_t nd = static_cast<std::size_t>(spline::d_count(m.degree()));
            if (m.dsets.size() != m.cubes.size() * nd || m.tet_mask.size() != m.cubes.size())
                throw std::invalid_argument("quadcast::gl::IsosurfaceRenderer: spline volume without its determining sets");
            upload(GL_SHADER_STORAGE_BUFFER, m.dsets);
            for (std::uint32_t mask : m.tet_mask) v.relevant += static_cast<std::size_t>(__builtin_popcount(mask));
        }
        if (tri) v.relevant = m.active;
        gl.BindBuffer(GL_SHADER_STORAGE_BUFFER, 0);
        volumes_.push_back(v);
        ++revision_;
    }

    /// Removes every volume.
    void clear() {
        for (Volume& v : volumes_) release(v);
        volumes_.clear();
        ++revision_;
    }

    /// Statistics of volume i in the last `draw`.
    const IsoDrawStats& stats(std::size_t i) const { return volumes_.at(i).stats; }
    std::size_t volume_count() const { return volumes_.size(); }

    void draw(const render::Camera& cam, const render::Light& light, const render::RenderOptions& opt, bool gbuffer) override {
        const Api& gl = *api_;
        gl.BindVertexArray(vao_);
        // Back faces only: each covered pixel casts once per element, from the face where the ray
        // leaves it (the ray's part inside the element comes from clipping).
        gl.Enable(GL_CULL_FACE);
        gl.CullFace(GL_FRONT);
        // (the depth under this draw only: a later draw without `frame_before` is unknown)
        const std::optional<std::vector<std::uint64_t>> before = std::exchange(before_, std::nullopt);
        for (std::size_t i = 0; i < volumes_.size(); ++i) {
            // Under volume i: what lay under the pass and the volumes before it (each fixed by
            // the view, the renderer's revision and its own model's isovalue)
            std::optional<std::vector<std::uint64_t>> under = before;
            if (under) under->push_back(i);
            draw_volume(volumes_[i], cam, light, opt, gbuffer, under ? &*under : nullptr);
        }
        gl.Disable(GL_CULL_FACE);
        gl.CullFace(GL_BACK);
        gl.BindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, 0);
        gl.BindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, 0);
    }

    /// Changes with every call that changes what is drawn (the setters above, `add_volume`, `clear`).
    std::uint64_t revision() const override { return revision_; }

    /// The depth under the next `draw` (ScenePass::frame_before). Where it and the view are the
    /// ones a volume's shown set was tested under (RenderOptions::occlusion_reuse, the CPU list),
    /// that draw draws the set alone, untested (IsoDrawStats::unchanged_view): the test kept every
    /// element that can show in front of that depth, and the same depth lies under it now.
    void frame_before(const std::vector<std::uint64_t>* key) override {
        before_ = key ? std::optional<std::vector<std::uint64_t>>(*key) : std::nullopt;
    }
    /// Whether a frame whose view and underlying depth are unchanged since its shown set was tested
    /// draws the set alone (true, the default) or tests every element again.
    void set_skip_unchanged_view_test(bool on) { skip_unchanged_ = on; }

    void bounds(Vec3<double>& lo, Vec3<double>& hi) const override {
        lo = Vec3<double>{{1e300, 1e300, 1e300}};
        hi = Vec3<double>{{-1e300, -1e300, -1e300}};
        for (const Volume& v : volumes_) {
            Vec3<double> a{}, b{};
            v.model->world_box(a, b);
            for (int i = 0; i < 3; ++i) {
                lo[i] = std::min(lo[i], std::min(a[i], b[i]));
                hi[i] = std::max(hi[i], std::max(a[i], b[i]));
            }
        }
    }

private:
    struct Volume {
        const render::VolumeModel* model = nullptr;
        GLuint data = 0, elements = 0, indices = 0, coeffs = 0, floors = 0;
        // Occlusion culling: a later phase's kept elements and their floors (`survivors`,
        // `survivor_floors`, at the phase's slots), the bound pass's flags and workgroup counts,
        // and the kept count the scan writes.
        GLuint survivors = 0, survivor_floors = 0, phase_keep = 0, phase_groups = 0, phase_count = 0;
        GLuint passed = 0;  ///< the bound pass's per-element results (not culled: 1), for the shown set
        /// RenderOptions::occlusion_reuse (the CPU list): per depth target (the bound framebuffer)
        /// whether each element (`element_id`) passed its last test against what was drawn.
        struct ShownSet {
            GLint target = -1;  ///< the framebuffer
            bool valid = false;
            std::vector<std::uint64_t> bits;
            std::uint64_t version = 0;        ///< changes with `bits`
            std::vector<std::uint64_t> view;  ///< `view_key` of the frame that tested it (empty: the depth under the pass was unknown)
        };
        ShownSet shown[2];
        int next_shown = 0;
        /// The CPU list in `elements` (and `ids`): ordered with this set's elements (`ordered_first`
        /// of them) first, at its `version`, for the view `ordered_view`; null: no set.
        const ShownSet* ordered_by = nullptr;
        std::uint64_t ordered_version = 0;
        std::vector<std::uint64_t> ordered_view;
        std::size_t ordered_first = 0, ordered_n = 0;
        std::vector<std::uint32_t> ids;  ///< the frame's elements' `element_id`s, in list order
        /// Host buffers of the CPU list's per-frame work, kept between frames (their pages are
        /// not faulted in and cleared again each frame: tens of MB on the liver)
        std::vector<std::uint32_t> scratch_records, scratch_ordered, scratch_ids, scratch_passed;
        std::size_t floor_capacity = 0;  ///< elements `floors`, `survivors`, ... hold
        std::size_t index_capacity = 0;  ///< elements the index buffer covers
        std::size_t element_capacity = 0, coeff_capacity = 0;  ///< elements `elements` and `coeffs` hold (grown only: a large
                                                               ///< buffer reallocated per frame is faulted in again per frame)
        std::size_t relevant = 0;
        IsoDrawStats stats;
        // The GPU element list: every relevant element (uploaded on first use, again when the
        // tetrahedron culling changes), the frame's list with room for all of them (the CPU list
        // has `elements`), the cull pass's flags and workgroup counts, and the count the scan writes.
        GLuint all = 0, listed = 0, keep = 0, groups = 0, count = 0;
        GLuint cubes = 0, cube_kept = 0;  ///< splines: per slot its cube, and whether the frame keeps it
        std::size_t all_count = 0;
        int all_tet_culling = -1;  ///< the tetrahedron culling `all` was built with (-1: not built)
    };

    /// Elements per batch of a draw: the index buffer covers this many at most.
    std::size_t batch_elements = 65536;

    template <class V>
    void upload(GLenum target, const V& v) {
        api_->BufferData(target, static_cast<GLsizeiptr>(std::max<std::size_t>(1, v.size()) * sizeof(typename V::value_type)),
                         v.empty() ? nullptr : v.data(), GL_STATIC_DRAW);
    }

    void release(Volume& v) {
        v.floor_capacity = v.element_capacity = v.coeff_capacity = 0;
        for (GLuint* b : {&v.data, &v.elements, &v.indices, &v.coeffs, &v.floors, &v.survivors, &v.survivor_floors, &v.phase_keep, &v.phase_groups, &v.phase_count, &v.passed, &v.all, &v.listed, &v.keep, &v.groups, &v.count, &v.cubes, &v.cube_kept}) {
            if (*b) api_->DeleteBuffers(1, b);
            *b = 0;
        }
    }

    /// The world -> clip matrix of the vertex stage (qc_view_proj) and of the element list's cull pass.
    static Mat4<float> view_proj(const render::Camera& cam) { return cam.projection * cam.view; }

    /// The index-space clip matrix view_proj · (origin + spacing ⊙ p), in double.
    static Mat<double, 4, 4> index_clip_matrix(const render::Camera& cam, const render::VolumeModel& m) {
        Mat<double, 4, 4> world{};
        for (int a = 0; a < 3; ++a) {
            world[a][a] = m.spacing[a];
            world[3][a] = m.origin[a];
        }
        world[3][3] = 1.0;
        return cast<double>(cam.projection) * cast<double>(cam.view) * world;
    }

    /// The elements of one frame into `rec`: the octree's active cubes not outside the frustum,
    /// expanded into their relevant tetrahedra (slot << 5 | t), or the active cells.
    void select(Volume& v, const render::Camera& cam, std::vector<std::uint32_t>& rec) const {
        const render::VolumeModel& m = *v.model;
        const spline::Frustum f = spline::frustum_from_clip_matrix(index_clip_matrix(cam, m));
        std::size_t visited = 0;
        std::vector<int> cubes = m.octree.active_cubes(m.iso, frustum_culling_ ? &f : nullptr, &visited);
        order_by_view_depth(cubes, m, cam);
        expand(v, cubes, visited, rec);
    }

    /// Spline cubes (or trilinear cells) ordered by the view depth of their centres, nearest first
    /// (ties by index): the order of the phases of occlusion culling, and of the draw whether it
    /// culls or not (where two elements hit a pixel at exactly the same depth, the first drawn keeps
    /// it). The GPU list keeps the octree's order.
    static void order_by_view_depth(std::vector<int>& cubes, const render::VolumeModel& m, const render::Camera& cam) {
        const int nx = m.octree.level(0).nx, ny = m.octree.level(0).ny;
        const double off = m.scheme == render::VolumeScheme::trilinear ? 0.5 : 0.0;  // (cells: from their lower corners)
        double row[4];
        for (int a = 0; a < 4; ++a) row[a] = double(cam.view[a][2]);
        std::vector<std::pair<double, int>> keyed;
        keyed.reserve(cubes.size());
        for (int c : cubes) {
            const double p[3] = {double(c % nx) + off, double((c / nx) % ny) + off, double(c / (nx * ny)) + off};
            double z = row[3];
            for (int a = 0; a < 3; ++a) z += row[a] * (m.origin[a] + m.spacing[a] * p[a]);
            keyed.emplace_back(-z, c);
        }
        std::sort(keyed.begin(), keyed.end());
        for (std::size_t i = 0; i < cubes.size(); ++i) cubes[i] = keyed[i].second;
    }

    /// The records of the elements of `cubes` (in their order) into `rec`, and the frame's statistics.
    void expand(Volume& v, const std::vector<int>& cubes, std::size_t visited, std::vector<std::uint32_t>& rec) const {
        const render::VolumeModel& m = *v.model;
        const bool tri = m.scheme == render::VolumeScheme::trilinear;
        rec.clear();
        const int nx = m.octree.level(0).nx, ny = m.octree.level(0).ny;
        v.stats = IsoDrawStats{};
        v.stats.active = m.active;
        v.stats.relevant = v.relevant;
        v.stats.nodes_visited = visited;
        for (int c : cubes) {
            const auto i = static_cast<std::uint32_t>(c % nx), j = static_cast<std::uint32_t>((c / nx) % ny),
                       k = static_cast<std::uint32_t>(c / (nx * ny));
            if (tri) {
                if (!m.cell_active[static_cast<std::size_t>(c)]) continue;
                ++v.stats.visible;
                rec.insert(rec.end(), {i, j, k, 0u});
                continue;
            }
            const std::int32_t slot = m.slot[static_cast<std::size_t>(c)];
            if (slot < 0) continue;
            ++v.stats.visible;
            const std::uint32_t mask = tet_culling_ ? m.tet_mask[static_cast<std::size_t>(slot)] : 0xffffffu;
            for (std::uint32_t t = 0; t < spline::tets_per_cube; ++t)
                if (mask & (1u << t)) rec.insert(rec.end(), {i, j, k, static_cast<std::uint32_t>(slot) << 5 | t});
        }
        v.stats.elements = rec.size() / 4;
    }

    /// Index buffer for n <= `batch_elements` elements (grown only): the 4 faces of a tetrahedron over its 4 vertices (vertex
    /// order of positive orientation, faces counter-clockwise seen from outside), or the 12
    /// triangles of a cell box over its 8 corners (corner k = (k & 1, k >> 1 & 1, k >> 2 & 1)).
    void ensure_indices(Volume& v, std::size_t n, bool tri) const {
        if (n <= v.index_capacity) return;
        static constexpr std::uint32_t tet[12] = {0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3};
        static constexpr std::uint32_t box[36] = {0, 2, 1, 1, 2, 3,  4, 5, 6, 5, 7, 6,  0, 1, 4, 1, 5, 4,
                                                  2, 6, 3, 3, 6, 7,  0, 4, 2, 2, 4, 6,  1, 3, 5, 3, 7, 5};
        const std::size_t cap = std::min(batch_elements, std::max<std::size_t>(n, 2 * v.index_capacity));
        const std::uint32_t per = tri ? 8 : 4;
        const std::size_t count = tri ? 36 : 12;
        std::vector<std::uint32_t> idx(cap * count);
        for (std::size_t e = 0; e < cap; ++e)
            for (std::size_t k = 0; k < count; ++k) idx[e * count + k] = static_cast<std::uint32_t>(e) * per + (tri ? box[k] : tet[k]);
        api_->BindBuffer(GL_ELEMENT_ARRAY_BUFFER, v.indices);
        api_->BufferData(GL_ELEMENT_ARRAY_BUFFER, static_cast<GLsizeiptr>(idx.size() * sizeof(std::uint32_t)), idx.data(), GL_STATIC_DRAW);
        v.index_capacity = cap;
    }

    /// The phases of a frame's n elements (RenderOptions::occlusion_phases, as the quadric
    /// renderer's phased drawing): phase k ends at (2^(k+1) - 1) / (2^p - 1) of them, nearest
    /// first (the CPU list is ordered by the cubes' view depth); one phase without occlusion
    /// culling, or for fewer than 4096 elements.
    static std::vector<std::size_t> phase_ends(std::size_t n, int phases) {
        std::vector<std::size_t> ends;
        const int p = n < 4096 ? 1 : std::clamp(phases, 1, 8);
        const double all = double((1u << p) - 1);
        for (int k = 0; k + 1 < p; ++k) ends.push_back(static_cast<std::size_t>(double(n) * double((2u << k) - 1) / all));
        ends.push_back(n);
        return ends;
    }

    /// The occlusion test's copy of the bound framebuffer's depth (viewport region), bound to
    /// texture unit `drawn_unit`; false (no test) when the depth buffer cannot be copied: the
    /// default framebuffer, no depth attachment, a stencil attachment of its own, multisampling,
    /// or a format other than 32-bit float or 24-bit normalised depth. Two copies are kept (the
    /// shadow map's size and the view's), each remade when its size or format changes.
    bool copy_drawn_depth() {
        const Api& gl = *api_;
        GLint fbo = 0, vp[4] = {0, 0, 0, 0}, samples = 0;
        gl.GetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &fbo);
        gl.GetIntegerv(GL_VIEWPORT, vp);
        gl.GetIntegerv(GL_SAMPLES, &samples);
        if (fbo == 0 || samples > 0 || vp[2] <= 0 || vp[3] <= 0) return false;
        GLint type = GL_NONE, name = 0, size = 0, comp = GL_NONE, stencil_type = GL_NONE, stencil_name = 0, stencil = 0;
        gl.GetFramebufferAttachmentParameteriv(GL_DRAW_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_FRAMEBUFFER_ATTACHMENT_OBJECT_TYPE, &type);
        if (type == GL_NONE) return false;
        gl.GetFramebufferAttachmentParameteriv(GL_DRAW_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_FRAMEBUFFER_ATTACHMENT_OBJECT_NAME, &name);
        gl.GetFramebufferAttachmentParameteriv(GL_DRAW_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_FRAMEBUFFER_ATTACHMENT_DEPTH_SIZE, &size);
        gl.GetFramebufferAttachmentParameteriv(GL_DRAW_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_FRAMEBUFFER_ATTACHMENT_COMPONENT_TYPE, &comp);
        gl.GetFramebufferAttachmentParameteriv(GL_DRAW_FRAMEBUFFER, GL_STENCIL_ATTACHMENT, GL_FRAMEBUFFER_ATTACHMENT_OBJECT_TYPE, &stencil_type);
        if (stencil_type != GL_NONE) {
            gl.GetFramebufferAttachmentParameteriv(GL_DRAW_FRAMEBUFFER, GL_STENCIL_ATTACHMENT, GL_FRAMEBUFFER_ATTACHMENT_OBJECT_NAME, &stencil_name);
            if (stencil_type != type || stencil_name != name) return false;  // (a stencil buffer of its own)
            gl.GetFramebufferAttachmentParameteriv(GL_DRAW_FRAMEBUFFER, GL_STENCIL_ATTACHMENT, GL_FRAMEBUFFER_ATTACHMENT_STENCIL_SIZE, &stencil);
        }
        GLenum format = GL_NONE;
        if (size == 32 && comp == GL_FLOAT) format = stencil ? GL_DEPTH32F_STENCIL8 : GL_DEPTH_COMPONENT32F;
        else if (size == 24 && comp == GL_UNSIGNED_NORMALIZED) format = stencil ? GL_DEPTH24_STENCIL8 : GL_DEPTH_COMPONENT24;
        if (format == GL_NONE) return false;
        const GLint w = vp[0] + vp[2], h = vp[1] + vp[3];
        DepthCopy* c = &copies_[0];
        for (DepthCopy& k : copies_)
            if (k.w == w && k.h == h && k.format == format) c = &k;
        if (c->w != w || c->h != h || c->format != format) {
            c = &copies_[next_copy_];  // (replaced in turn)
            next_copy_ = 1 - next_copy_;
            if (c->tex) gl.DeleteTextures(1, &c->tex);
            if (!c->fbo) gl.CreateFramebuffers(1, &c->fbo);
            gl.CreateTextures(GL_TEXTURE_2D, 1, &c->tex);
            gl.TextureStorage2D(c->tex, 1, format, w, h);
            gl.TextureParameteri(c->tex, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
            gl.TextureParameteri(c->tex, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
            gl.NamedFramebufferTexture(c->fbo, stencil ? GL_DEPTH_STENCIL_ATTACHMENT : GL_DEPTH_ATTACHMENT, c->tex, 0);
            gl.NamedFramebufferDrawBuffer(c->fbo, GL_NONE);
            gl.NamedFramebufferReadBuffer(c->fbo, GL_NONE);
            c->w = w;
            c->h = h;
            c->format = format;
        }
        gl.BlitNamedFramebuffer(static_cast<GLuint>(fbo), c->fbo, vp[0], vp[1], w, h, vp[0], vp[1], w, h, GL_DEPTH_BUFFER_BIT, GL_NEAREST);
        gl.BindTextureUnit(drawn_unit, c->tex);
        return true;
    }

    /// Occlusion culling of a later phase (after `copy_drawn_depth`): the max-depth pyramid of the
    /// copy (`pyramid_`), then each of the phase's `count` elements from `first` on culled against
    /// it or given its depth floor (`floors`), its result into `passed`, and the kept ones (from
    /// `draw_from` on: the ones before it are drawn already) with their floors copied in order into
    /// `survivors` and `survivor_floors` from slot `first + draw_from` on; their count into `kept`.
    /// False when the viewport is too large for 16 levels.
    bool cull_phase(Volume& v, const render::Camera& cam, const render::Light& light, const render::RenderOptions& opt, std::size_t first, std::size_t count,
                    std::size_t& kept, std::size_t draw_from = 0) {
        const Api& gl = *api_;
        GLint vp[4] = {0, 0, 0, 0};
        gl.GetIntegerv(GL_VIEWPORT, vp);
        const std::vector<std::array<std::uint32_t, 3>> levels = pyramid_levels(GLuint(vp[2]), GLuint(vp[3]));
        if (levels.size() > 16) return false;
        const std::size_t texels = pyramid_texels(levels);
        if (texels > pyramid_texels_) {
            if (!pyramid_) gl.GenBuffers(1, &pyramid_);
            gl.BindBuffer(GL_SHADER_STORAGE_BUFFER, pyramid_);
            gl.BufferData(GL_SHADER_STORAGE_BUFFER, static_cast<GLsizeiptr>(texels * sizeof(GLuint)), nullptr, GL_DYNAMIC_COPY);
            gl.BindBuffer(GL_SHADER_STORAGE_BUFFER, 0);
            view_depth_texels(gl, pyramid_view_, pyramid_, texels);
            pyramid_texels_ = texels;
        }
        gl.BindBufferBase(GL_SHADER_STORAGE_BUFFER, 3, pyramid_);
        const Program& base = programs_.pyramid_base();
        gl.UseProgram(base.id());
        gl.Uniform1i(base.uniform_location("qc_drawn_depth"), static_cast<GLint>(drawn_unit));
        gl.Uniform4i(base.uniform_location("qc_viewport_rect"), vp[0], vp[1], vp[2], vp[3]);
        gl.DispatchCompute((GLuint(vp[2]) + 7) / 8, (GLuint(vp[3]) + 7) / 8, 1);
        build_pyramid(gl, programs_.get(render::OcclusionKey{render::OcclusionPass::pyramid}), levels);
        const Program& cp = programs_.occlusion_bounds(cam.orthographic, v.model->scheme == render::VolumeScheme::trilinear);
        gl.UseProgram(cp.id());
        set_uniforms(cp, *v.model, cam, light, opt);
        gl.Uniform1ui(cp.uniform_location("qc_first"), static_cast<GLuint>(first));
        gl.Uniform1ui(cp.uniform_location("qc_count"), static_cast<GLuint>(count));
        gl.Uniform1ui(cp.uniform_location("qc_draw_from"), static_cast<GLuint>(draw_from));
        gl.Uniform2f(cp.uniform_location("qc_viewport"), float(vp[2]), float(vp[3]));
        set_pyramid_uniforms(gl, cp, levels);
        gl.BindTextureUnit(depth_texels_unit, pyramid_view_);  // (the pyramid's reads)
        const auto groups = static_cast<std::uint32_t>((count + 63) / 64);
        gl.BindBufferBase(GL_SHADER_STORAGE_BUFFER, 6, v.phase_keep);
        gl.BindBufferBase(GL_SHADER_STORAGE_BUFFER, 7, v.phase_groups);
        gl.BindBufferBase(GL_SHADER_STORAGE_BUFFER, 13, v.passed);
        dispatch_rows(gl, groups);
        gl.MemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
        gl.BindTextureUnit(depth_texels_unit, 0);
        // The kept elements in order into the survivors' list (the quadric renderer's scan)
        const Program& scan = programs_.get(render::OcclusionKey{render::OcclusionPass::scan});
        gl.UseProgram(scan.id());
        gl.Uniform1ui(scan.uniform_location("qc_group_count"), groups);
        gl.Uniform1ui(scan.uniform_location("qc_command_at"), 0u);
        gl.Uniform1ui(scan.uniform_location("qc_per_kept"), 1u);
        gl.BindBufferBase(GL_SHADER_STORAGE_BUFFER, 5, v.phase_count);
        gl.DispatchCompute(1, 1, 1);
        gl.MemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
        const Program& compact = programs_.get(render::OcclusionKey{render::OcclusionPass::phase_compact});
        gl.UseProgram(compact.id());
        gl.Uniform1ui(compact.uniform_location("qc_first"), static_cast<GLuint>(first));
        gl.Uniform1ui(compact.uniform_location("qc_count"), static_cast<GLuint>(count));
        gl.Uniform1ui(compact.uniform_location("qc_to"), static_cast<GLuint>(first + draw_from));
        gl.BindBufferBase(GL_SHADER_STORAGE_BUFFER, 11, v.survivors);
        gl.BindBufferBase(GL_SHADER_STORAGE_BUFFER, 12, v.survivor_floors);
        dispatch_rows(gl, groups);
        gl.MemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
        for (GLuint b : {5u, 6u, 7u, 11u, 12u, 13u}) gl.BindBufferBase(GL_SHADER_STORAGE_BUFFER, b, 0);
        std::uint32_t k = 0;
        gl.GetNamedBufferSubData(v.phase_count, 0, sizeof k, &k);
        kept = k;
        return true;
    }

    /// Whether a list of n elements of `m` gets its coefficients from the compute pre-pass.
    bool uses_pre_pass(const render::VolumeModel& m, std::size_t n) const {
        if (m.scheme == render::VolumeScheme::trilinear || coeff_stage_ == CoefficientStage::vertex) return false;
        if (coeff_stage_ == CoefficientStage::compute) return true;
        return m.degree() == 3 && n * static_cast<std::size_t>(bb::coefficient_count(3)) * sizeof(float) <= pre_pass_budget_;
    }

    /// What decides a volume's shown set (with `under`, the key of the depth under it): the
    /// camera, the viewport, the depth function, the options of the element selection and of
    /// occlusion culling, the renderer's revision, the model and its isovalue, the bound
    /// framebuffer. Empty where `under` is null.
    std::vector<std::uint64_t> view_key(const Volume& v, const render::Camera& cam, const render::RenderOptions& opt, const std::vector<std::uint64_t>* under,
                                        GLint depth_func, GLint fbo) const {
        std::vector<std::uint64_t> key;
        if (!under) return key;
        key = *under;
        push_camera_key(key, cam);
        GLint viewport[4] = {0, 0, 0, 0};
        api_->GetIntegerv(GL_VIEWPORT, viewport);
        for (GLint x : viewport) key.push_back(static_cast<std::uint32_t>(x));
        key.insert(key.end(), {static_cast<std::uint64_t>(depth_func), static_cast<std::uint64_t>(fbo), static_cast<std::uint64_t>(opt.width),
                               static_cast<std::uint64_t>(opt.height), static_cast<std::uint64_t>(opt.occlusion_phases), opt.occlusion_culling,
                               opt.occlusion_reuse, revision_, reinterpret_cast<std::uintptr_t>(v.model)});
        push_float_bits(key, v.model->iso);
        return key;
    }

    void draw_volume(Volume& v, const render::Camera& cam, const render::Light& light, const render::RenderOptions& opt, bool gbuffer,
                     const std::vector<std::uint64_t>* under) {
        const Api& gl = *api_;
        const render::VolumeModel& m = *v.model;
        const bool tri = m.scheme == render::VolumeScheme::trilinear;
        // Occlusion culling (tetrahedra): the elements in phases, nearest first; before each later
        // one, the depth drawn so far is copied for the fragment stage's test of its element's
        // depth floor, which a compute pass computes first.
        // (The tests drop only what the depth test would: only with the depth test on, LESS or LEQUAL.)
        GLint depth_func = GL_NONE;
        gl.GetIntegerv(GL_DEPTH_FUNC, &depth_func);
        const bool depth_tested = gl.IsEnabled(GL_DEPTH_TEST) && (depth_func == GL_LESS || depth_func == GL_LEQUAL);
        const bool cull = opt.occlusion_culling && depth_tested && std::clamp(opt.occlusion_phases, 1, 8) > 1;
        // Reuse of the last frame's shown set (RenderOptions::occlusion_reuse; the CPU list, per
        // bound framebuffer): the set's elements are drawn first, then every element is tested
        // against that depth and the rest that pass are drawn; the results are the next frame's
        // set. A frame without a valid set draws in phases and records the set after them.
        Volume::ShownSet* shown = nullptr;
        std::vector<std::uint64_t> view;
        if (cull && opt.occlusion_reuse && element_list_ == ElementList::cpu) {
            GLint fbo = 0;
            gl.GetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &fbo);
            shown = &shown_set_of(v.shown, v.next_shown, fbo);
            view = view_key(v, cam, opt, under, depth_func, fbo);
        }
        // Drawn alone: the set was tested under this view and the same depth under the pass (so
        // every element left out lies behind what is drawn now), and has not changed since
        const bool alone = shown && shown->valid && skip_unchanged_ && !view.empty() && shown->view == view;
        std::size_t first_shown = 0;  // the shown set's elements lead the list
        std::size_t n = 0;
        if (alone && v.ordered_by == shown && v.ordered_version == shown->version && v.ordered_view == view) {
            n = v.ordered_n;  // (the list is in place, the set's elements first)
            first_shown = v.ordered_first;
        } else {
            n = element_list_ == ElementList::gpu ? gpu_select(v, cam) : cpu_select(v, cam, shown && shown->valid ? shown : nullptr, first_shown);
            if (shown && shown->valid) {
                v.ordered_view = view;
                v.ordered_first = first_shown;
                v.ordered_n = n;
            }
        }
        v.stats.unchanged_view = alone;  // (after the selection, which sets the statistics)
        v.stats.alone = 0;
        if (n == 0) return;
        ensure_indices(v, std::min(n, batch_elements), tri);
        gl.BindBuffer(GL_ELEMENT_ARRAY_BUFFER, v.indices);
        gl.BindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, element_list_ == ElementList::gpu ? v.listed : v.elements);
        gl.BindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, v.data);
        const bool pre = uses_pre_pass(m, n);
        if (pre) {
            if (n > v.coeff_capacity) {
                const std::size_t nc = static_cast<std::size_t>(bb::coefficient_count(m.degree()));
                v.coeff_capacity = n + n / 8;
                gl.BindBuffer(GL_SHADER_STORAGE_BUFFER, v.coeffs);
                gl.BufferData(GL_SHADER_STORAGE_BUFFER, static_cast<GLsizeiptr>(v.coeff_capacity * nc * sizeof(float)), nullptr, GL_DYNAMIC_COPY);
                gl.BindBuffer(GL_SHADER_STORAGE_BUFFER, 0);
            }
            gl.BindBufferBase(GL_SHADER_STORAGE_BUFFER, 2, v.coeffs);
        }
        // The compute pre-pass: the coefficients of elements first .. first + count - 1 of the list
        // bound (a phase's survivors after its occlusion test), then a barrier for the vertex stage
        const auto precompute = [&](std::size_t first, std::size_t count) {
            const Program& cp = programs_.compute(m.scheme);
            gl.UseProgram(cp.id());
            gl.Uniform1ui(cp.uniform_location("qc_first"), static_cast<GLuint>(first));
            gl.Uniform1ui(cp.uniform_location("qc_count"), static_cast<GLuint>(count));
            dispatch_rows(gl, static_cast<std::uint32_t>((count + 63) / 64));
            gl.MemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
        };
        if (alone) v.stats.alone = first_shown;
        const bool reuse = shown && shown->valid && (n >= 4096 || alone);
        const std::vector<std::size_t> ends = alone ? std::vector<std::size_t>{first_shown}
                                              : reuse ? std::vector<std::size_t>{first_shown, n} : phase_ends(n, cull ? opt.occlusion_phases : 1);
        const bool occlusion = ends.size() > 1;
        if (occlusion && n > v.floor_capacity) {
            v.floor_capacity = std::max(n, 2 * v.floor_capacity);
            const std::size_t cap = v.floor_capacity, groups = (cap + 63) / 64;
            for (const auto& [b, bytes] : {std::pair<GLuint*, std::size_t>{&v.floors, cap * sizeof(float)}, {&v.survivors, cap * 4 * sizeof(std::uint32_t)},
                                           {&v.survivor_floors, cap * sizeof(float)}, {&v.phase_keep, cap * sizeof(std::uint32_t)},
                                           {&v.phase_groups, groups * sizeof(std::uint32_t)}, {&v.phase_count, sizeof(std::uint32_t)},
                                           {&v.passed, cap * sizeof(std::uint32_t)}}) {
                if (!*b) gl.GenBuffers(1, b);
                gl.BindBuffer(GL_SHADER_STORAGE_BUFFER, *b);
                gl.BufferData(GL_SHADER_STORAGE_BUFFER, static_cast<GLsizeiptr>(bytes), nullptr, GL_DYNAMIC_COPY);
            }
            gl.BindBuffer(GL_SHADER_STORAGE_BUFFER, 0);
        }
        if (occlusion) gl.BindBufferBase(GL_SHADER_STORAGE_BUFFER, 10, v.floors);
        const Program& prog = programs_.get(render::IsoKey{m.scheme, cam.orthographic, gbuffer, pre});
        gl.UseProgram(prog.id());
        set_uniforms(prog, m, cam, light, opt);
        gl.Uniform1ui(prog.uniform_location("qc_first"), 0u);
        gl.Uniform1i(prog.uniform_location("qc_drawn_depth"), static_cast<GLint>(drawn_unit));
        // In batches over the index buffer of `batch_elements`: the base vertex moves gl_VertexID,
        // and with it the element the vertex stage reads, to the batch's first.
        const std::size_t per = tri ? 8 : 4;
        std::size_t first = 0;
        v.stats.phases = 0;
        v.stats.occluded = 0;
        v.stats.reused = reuse;
        v.stats.pre_pass = pre;
        const GLuint list = element_list_ == ElementList::gpu ? v.listed : v.elements;
        // The bound pass over the whole list, against the depth drawn so far, only recording which
        // elements pass (the shown set) where `draw_from` is n, or keeping those from `draw_from` on.
        bool recorded = false;
        const auto test_all = [&](std::size_t draw_from, std::size_t& kept) {
            gl.BindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, list);
            gl.BindBufferBase(GL_SHADER_STORAGE_BUFFER, 10, v.floors);
            if (!copy_drawn_depth() || !cull_phase(v, cam, light, opt, 0, n, kept, draw_from)) return false;
            read_shown(v, *shown, n);
            shown->view = view;
            recorded = true;
            return true;
        };
        for (std::size_t end : ends) {
            // A later phase tested against the depth drawn so far draws only its kept elements
            // (`survivors`, from slot `first` on), each with its depth floor. Reusing the shown set,
            // the second phase tests every element (the shown ones for the next frame's set) and
            // keeps the rest that pass, into the survivors' list from slot `first` on.
            std::size_t kept = end - first;
            const std::size_t slot = first;
            bool test = false;
            if (occlusion && first > 0) {
                if (reuse) {
                    test = test_all(first, kept);
                } else {
                    gl.BindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, list);
                    gl.BindBufferBase(GL_SHADER_STORAGE_BUFFER, 10, v.floors);
                    test = copy_drawn_depth() && cull_phase(v, cam, light, opt, first, end - first, kept);
                }
                if (test) {
                    v.stats.occluded += end - first - kept;
                    gl.BindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, v.survivors);
                    gl.BindBufferBase(GL_SHADER_STORAGE_BUFFER, 10, v.survivor_floors);
                } else {
                    kept = end - first;
                }
            }
            if (pre) precompute(slot, kept);
            gl.UseProgram(prog.id());
            gl.Uniform1i(prog.uniform_location("qc_occlusion"), test ? 1 : 0);
            for (std::size_t b = slot; b < slot + kept; b += std::min(batch_elements, slot + kept - b))
                gl.DrawElementsBaseVertex(GL_TRIANGLES, static_cast<GLsizei>(std::min(batch_elements, slot + kept - b) * (tri ? 36 : 12)), GL_UNSIGNED_INT, nullptr,
                                          static_cast<GLint>(b * per));
            first = end;
            ++v.stats.phases;
        }
        // A frame without a valid set records it: which elements pass against the whole depth drawn.
        if (shown && !recorded && occlusion) {
            std::size_t none = 0;
            test_all(n, none);
        }
        if (shown) shown->valid = recorded || alone;
        if (occlusion) {
            gl.BindTextureUnit(drawn_unit, 0);
            gl.BindBufferBase(GL_SHADER_STORAGE_BUFFER, 3, 0);
            gl.BindBufferBase(GL_SHADER_STORAGE_BUFFER, 10, 0);
        }
        if (pre) gl.BindBufferBase(GL_SHADER_STORAGE_BUFFER, 2, 0);
    }

    /// The stable id of an element record (cube slot << 5 | tetrahedron, or the cell's index).
    static std::uint32_t element_id(const render::VolumeModel& m, const std::uint32_t* rec) {
        if (m.scheme != render::VolumeScheme::trilinear) return rec[3];
        const auto nx = static_cast<std::uint32_t>(m.octree.level(0).nx), ny = static_cast<std::uint32_t>(m.octree.level(0).ny);
        return rec[0] + nx * (rec[1] + ny * rec[2]);
    }

    /// The bound pass's results over the frame's n elements into the shown set (by `element_id`).
    void read_shown(Volume& v, Volume::ShownSet& set, std::size_t n) const {
        std::vector<std::uint32_t>& passed = v.scratch_passed;
        passed.resize(n);
        api_->GetNamedBufferSubData(v.passed, 0, static_cast<GLsizeiptr>(n * sizeof(std::uint32_t)), passed.data());
        std::fill(set.bits.begin(), set.bits.end(), 0);
        ++set.version;
        for (std::size_t i = 0; i < n; ++i) {
            if (!passed[i]) continue;
            const std::uint32_t id = v.ids[i];
            if (id / 64 >= set.bits.size()) set.bits.resize(id / 64 + 1, 0);
            set.bits[id / 64] |= std::uint64_t(1) << (id % 64);
        }
    }

    /// The CPU element list: the octree's selection, uploaded into `elements`; its count.
    /// With a shown set, the set's elements first (each part in its order); their count into
    /// `first_shown`. The elements' `element_id`s into v.ids.
    std::size_t cpu_select(Volume& v, const render::Camera& cam, const Volume::ShownSet* shown, std::size_t& first_shown) {
        std::vector<std::uint32_t>& rec = v.scratch_records;
        select(v, cam, rec);
        first_shown = 0;
        if (rec.empty()) return 0;
        const std::size_t n = rec.size() / 4;
        v.ids.resize(n);
        for (std::size_t i = 0; i < n; ++i) v.ids[i] = element_id(*v.model, &rec[4 * i]);
        if (shown) {
            const auto is_shown = [&](std::uint32_t id) { return id / 64 < shown->bits.size() && (shown->bits[id / 64] >> (id % 64) & 1u); };
            std::vector<std::uint32_t>& ordered = v.scratch_ordered;
            std::vector<std::uint32_t>& ids = v.scratch_ids;
            ordered.resize(rec.size());
            ids.resize(n);
            for (std::size_t i = 0; i < n; ++i)
                first_shown += is_shown(v.ids[i]);
            std::size_t a = 0, b = first_shown;
            for (std::size_t i = 0; i < n; ++i) {
                std::size_t& to = is_shown(v.ids[i]) ? a : b;
                std::copy(&rec[4 * i], &rec[4 * i] + 4, &ordered[4 * to]);
                ids[to++] = v.ids[i];
            }
            rec.swap(ordered);
            v.ids.swap(ids);
        }
        api_->BindBuffer(GL_SHADER_STORAGE_BUFFER, v.elements);
        if (n > v.element_capacity) {
            v.element_capacity = n + n / 8;
            api_->BufferData(GL_SHADER_STORAGE_BUFFER, static_cast<GLsizeiptr>(v.element_capacity * 4 * sizeof(std::uint32_t)), nullptr, GL_DYNAMIC_DRAW);
        }
        api_->BufferSubData(GL_SHADER_STORAGE_BUFFER, 0, static_cast<GLsizeiptr>(rec.size() * sizeof(std::uint32_t)), rec.data());
        api_->BindBuffer(GL_SHADER_STORAGE_BUFFER, 0);
        v.ordered_by = shown;
        v.ordered_version = shown ? shown->version : 0;
        v.ordered_view.clear();  // (the caller's view, where it keeps the order)
        return n;
    }

    /// The GPU element list (`ElementList::gpu`): every relevant element of the volume (uploaded
    /// once) tested against the frustum by a compute pass, the kept ones copied in order into
    /// `listed` (OcclusionPass::element_cull_*, scan, element_compact); their count, read back.
    std::size_t gpu_select(Volume& v, const render::Camera& cam) {
        const Api& gl = *api_;
        const render::VolumeModel& m = *v.model;
        const bool tri = m.scheme == render::VolumeScheme::trilinear;
        if (v.all_tet_culling != int(tet_culling_)) {
            std::size_t visited = 0;
            std::vector<std::uint32_t> all;
            expand(v, m.octree.active_cubes(m.iso, nullptr, &visited), visited, all);
            v.all_count = all.size() / 4;
            const std::size_t groups = (v.all_count + 63) / 64;
            for (GLuint* b : {&v.all, &v.listed, &v.keep, &v.groups, &v.count, &v.cubes, &v.cube_kept})
                if (!*b) gl.GenBuffers(1, b);
            if (!tri) {
                gl.BindBuffer(GL_SHADER_STORAGE_BUFFER, v.cubes);
                upload(GL_SHADER_STORAGE_BUFFER, m.cubes);
                gl.BindBuffer(GL_SHADER_STORAGE_BUFFER, v.cube_kept);
                gl.BufferData(GL_SHADER_STORAGE_BUFFER, static_cast<GLsizeiptr>(std::max<std::size_t>(1, m.cubes.size()) * sizeof(std::uint32_t)), nullptr, GL_DYNAMIC_COPY);
            }
            gl.BindBuffer(GL_SHADER_STORAGE_BUFFER, v.all);
            upload(GL_SHADER_STORAGE_BUFFER, all);
            gl.BindBuffer(GL_SHADER_STORAGE_BUFFER, v.listed);
            gl.BufferData(GL_SHADER_STORAGE_BUFFER, static_cast<GLsizeiptr>(std::max<std::size_t>(1, v.all_count) * 4 * sizeof(std::uint32_t)), nullptr, GL_DYNAMIC_COPY);
            gl.BindBuffer(GL_SHADER_STORAGE_BUFFER, v.keep);
            gl.BufferData(GL_SHADER_STORAGE_BUFFER, static_cast<GLsizeiptr>(std::max<std::size_t>(1, v.all_count) * sizeof(std::uint32_t)), nullptr, GL_DYNAMIC_COPY);
            gl.BindBuffer(GL_SHADER_STORAGE_BUFFER, v.groups);
            gl.BufferData(GL_SHADER_STORAGE_BUFFER, static_cast<GLsizeiptr>(std::max<std::size_t>(1, groups) * sizeof(std::uint32_t)), nullptr, GL_DYNAMIC_COPY);
            gl.BindBuffer(GL_SHADER_STORAGE_BUFFER, v.count);
            gl.BufferData(GL_SHADER_STORAGE_BUFFER, sizeof(std::uint32_t), nullptr, GL_DYNAMIC_COPY);
            gl.BindBuffer(GL_SHADER_STORAGE_BUFFER, 0);
            v.all_tet_culling = int(tet_culling_);
        }
        v.stats = IsoDrawStats{};
        v.stats.active = m.active;
        v.stats.relevant = v.relevant;
        if (v.all_count == 0) return 0;
        if (!frustum_culling_) {  // every element: the whole list
            gl.CopyNamedBufferSubData(v.all, v.listed, 0, 0, static_cast<GLsizeiptr>(v.all_count * 4 * sizeof(std::uint32_t)));
            gl.MemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
            v.stats.elements = v.all_count;
            return v.all_count;
        }
        const auto n = static_cast<std::uint32_t>(v.all_count);
        const std::uint32_t groups = (n + 63) / 64;
        gl.MemoryBarrier(GL_ALL_BARRIER_BITS);  // (the last frame's reads of these buffers)
        gl.BindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, v.listed);
        gl.BindBufferBase(GL_SHADER_STORAGE_BUFFER, 3, v.all);
        gl.BindBufferBase(GL_SHADER_STORAGE_BUFFER, 5, v.count);
        gl.BindBufferBase(GL_SHADER_STORAGE_BUFFER, 6, v.keep);
        gl.BindBufferBase(GL_SHADER_STORAGE_BUFFER, 7, v.groups);
        const float origin[3] = {float(m.origin[0]), float(m.origin[1]), float(m.origin[2])}, spacing[3] = {float(m.spacing[0]), float(m.spacing[1]), float(m.spacing[2])};
        const Mat4<float> vp = view_proj(cam);
        if (!tri) {
            // Pass 0: the active cubes' boxes; a tetrahedron goes with its cube
            const Program& cc = programs_.get(render::OcclusionKey{render::OcclusionPass::element_cull_cubes});
            gl.UseProgram(cc.id());
            const auto nc = static_cast<std::uint32_t>(m.cubes.size());
            gl.Uniform1ui(cc.uniform_location("qc_count"), nc);
            gl.Uniform3i(cc.uniform_location("qc_dims"), m.nx, m.ny, m.nz);
            gl.Uniform3fv(cc.uniform_location("qc_origin"), 1, origin);
            gl.Uniform3fv(cc.uniform_location("qc_spacing"), 1, spacing);
            gl.UniformMatrix4fv(cc.uniform_location("qc_view_proj"), 1, GL_FALSE, &vp[0][0]);
            gl.BindBufferBase(GL_SHADER_STORAGE_BUFFER, 8, v.cubes);
            gl.BindBufferBase(GL_SHADER_STORAGE_BUFFER, 9, v.cube_kept);
            dispatch_rows(gl, (nc + 63) / 64);
            gl.MemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
        }
        const Program& cull = programs_.get(render::OcclusionKey{tri ? render::OcclusionPass::element_cull_cells : render::OcclusionPass::element_cull_tets});
        gl.UseProgram(cull.id());
        gl.Uniform1ui(cull.uniform_location("qc_count"), n);
        gl.Uniform3fv(cull.uniform_location("qc_origin"), 1, origin);
        gl.Uniform3fv(cull.uniform_location("qc_spacing"), 1, spacing);
        gl.UniformMatrix4fv(cull.uniform_location("qc_view_proj"), 1, GL_FALSE, &vp[0][0]);
        dispatch_rows(gl, groups);
        gl.MemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
        const Program& scan = programs_.get(render::OcclusionKey{render::OcclusionPass::scan});
        gl.UseProgram(scan.id());
        gl.Uniform1ui(scan.uniform_location("qc_group_count"), groups);
        gl.Uniform1ui(scan.uniform_location("qc_command_at"), 0u);
        gl.Uniform1ui(scan.uniform_location("qc_per_kept"), 1u);
        gl.DispatchCompute(1, 1, 1);
        gl.MemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
        const Program& compact = programs_.get(render::OcclusionKey{render::OcclusionPass::element_compact});
        gl.UseProgram(compact.id());
        gl.Uniform1ui(compact.uniform_location("qc_count"), n);
        dispatch_rows(gl, groups);
        gl.MemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
        for (GLuint b : {3u, 5u, 6u, 7u, 8u, 9u}) gl.BindBufferBase(GL_SHADER_STORAGE_BUFFER, b, 0);
        std::uint32_t kept = 0;
        gl.GetNamedBufferSubData(v.count, 0, sizeof kept, &kept);
        v.stats.elements = kept;
        return kept;
    }

    void set_uniforms(const Program& p, const render::VolumeModel& m, const render::Camera& cam, const render::Light& light,
                      const render::RenderOptions& opt) const {
        const Api& gl = *api_;
        const bool tri = m.scheme == render::VolumeScheme::trilinear;
        // The camera in index space (double, rounded once)
        const Vec3<double> eye = cast<double>(cam.eye);
        float eye_index[3], origin[3], spacing[3], grad_scale[3];
        for (int a = 0; a < 3; ++a) {
            eye_index[a] = static_cast<float>((eye[a] - m.origin[a]) / m.spacing[a]);
            origin[a] = static_cast<float>(m.origin[a]);
            spacing[a] = static_cast<float>(m.spacing[a]);
            grad_scale[a] = static_cast<float>((tri ? 1.0 : 2.0) / m.spacing[a]);
        }
        const float vz_row[3] = {cam.view[0][2], cam.view[1][2], cam.view[2][2]};
        const float forward[3] = {-vz_row[0], -vz_row[1], -vz_row[2]};
        const Mat4<float> vp = view_proj(cam);
        const float pz[4] = {cam.projection[2][2], cam.projection[3][2], cam.projection[2][3], cam.projection[3][3]};
        gl.Uniform3fv(p.uniform_location("qc_eye_index"), 1, eye_index);
        gl.Uniform3fv(p.uniform_location("qc_eye_world"), 1, cam.eye.c);
        gl.Uniform3fv(p.uniform_location("qc_forward_world"), 1, forward);
        gl.Uniform3fv(p.uniform_location("qc_origin"), 1, origin);
        gl.Uniform3fv(p.uniform_location("qc_spacing"), 1, spacing);
        gl.UniformMatrix4fv(p.uniform_location("qc_view_proj"), 1, GL_FALSE, &vp[0][0]);
        gl.Uniform3fv(p.uniform_location("qc_vz_row"), 1, vz_row);
        if (tri) gl.Uniform3i(p.uniform_location("qc_dims"), m.nx, m.ny, m.nz);
        gl.Uniform4fv(p.uniform_location("qc_pz"), 1, pz);
        gl.Uniform1f(p.uniform_location("qc_rho"), m.iso);
        gl.Uniform3fv(p.uniform_location("qc_grad_scale"), 1, grad_scale);
        gl.Uniform1f(p.uniform_location("qc_pixel"), 2.0f / (cam.projection[1][1] * static_cast<float>(opt.height)));
        gl.Uniform3fv(p.uniform_location("qc_color"), 1, m.color.c);
        gl.Uniform3fv(p.uniform_location("qc_light_dir"), 1, light.direction.c);
        gl.Uniform3fv(p.uniform_location("qc_light_color"), 1, light.color.c);
        // The frame's ambient and diffuse weights with the isosurface's specular and shininess.
        const float material[4] = {opt.material[0], opt.material[1], m.material.specular, m.material.shininess};
        gl.Uniform4fv(p.uniform_location("qc_material"), 1, material);
    }

    const Api* api_;
    GLuint vao_ = 0;
    std::vector<Volume> volumes_;
    GeneratedPrograms programs_{*api_, "quadcast::gl::IsosurfaceRenderer"};
    bool frustum_culling_ = true, tet_culling_ = true;
    CoefficientStage coeff_stage_ = CoefficientStage::automatic;
    std::size_t pre_pass_budget_ = std::size_t(64) << 20;
    ElementList element_list_ = ElementList::cpu;
    std::uint64_t revision_ = 1;
    std::optional<std::vector<std::uint64_t>> before_;  ///< the key `frame_before` gave for the next draw (none: unknown)
    bool skip_unchanged_ = true;
    /// The occlusion test's copy of the depth buffer, and the texture unit it is read from.
    static constexpr GLuint drawn_unit = 7;
    struct DepthCopy {
        GLuint fbo = 0, tex = 0;
        GLint w = 0, h = 0;
        GLenum format = GL_NONE;
    };
    DepthCopy copies_[2];
    int next_copy_ = 0;
    GLuint pyramid_ = 0;  ///< the max-depth pyramid of occlusion culling (window depth bits, levels packed)
    GLuint pyramid_view_ = 0;  ///< its texture-buffer view (depth_texels_unit), which the cull pass reads
    std::size_t pyramid_texels_ = 0;
};

}  // namespace quadcast::gl
