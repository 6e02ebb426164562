// src/gl/slim_renderer.cpp -- quadcast::gl::SlimRenderer, the three SLIM passes (visibility, accumulation, resolve)
#include "quadcast/gl/slim_renderer.hpp"

#include <algorithm>
#include <array>
#include <stdexcept>
#include <string>
#include <vector>

#include "frame_uniforms.hpp"
#include "quadcast/gl/generated_programs.hpp"
#include "quadcast/gl/loader.hpp"
#include "quadcast/render/record.hpp"
#include "quadcast/render/slim_cpu_renderer.hpp"
#include "quadcast/render/slim_patch.hpp"
#include "quadcast/render/window_ray.hpp"

namespace quadcast::gl {

class SlimRenderer::Impl {
public:
    explicit Impl(const Api& api) : api_(&api) {
        api.GenVertexArrays(1, &vao_);
        api.GenBuffers(1, &records_);
        api.GenBuffers(1, &planes_);
        api.GenBuffers(1, &patches_);
        api.GenBuffers(1, &indices_);
    }
    ~Impl() {
        release_targets();
        api_->DeleteBuffers(1, &records_);
        api_->DeleteBuffers(1, &planes_);
        api_->DeleteBuffers(1, &patches_);
        api_->DeleteBuffers(1, &indices_);
        api_->DeleteVertexArrays(1, &vao_);
    }
    Impl(const Impl&) = delete;
    Impl& operator=(const Impl&) = delete;

    void set_precision(int bits) {
        if (bits != 16 && bits != 32)
            throw std::invalid_argument("quadcast::gl::SlimRenderer: accumulation precision must be 16 or 32 bits (got " + std::to_string(bits) + ")");
        if (bits != bits_) release_targets();
        bits_ = bits;
        ++revision_;
    }
    int precision() const { return bits_; }
    std::uint64_t revision() const { return revision_; }

    void set_balls(const std::vector<render::Primitive>& balls) {
        render::validate_slim_balls(balls);
        ++revision_;
        const Api& gl = *api_;
        std::vector<std::array<float, render::record_slots * 4>> records;
        std::vector<float> planes;
        lo_ = {{1e300, 1e300, 1e300}};
        hi_ = {{-1e300, -1e300, -1e300}};
        for (const render::Primitive& b : balls) {
            records.push_back(render::pack_record(b));
            planes.insert(planes.end(), b.shape.planes[0].c, b.shape.planes[0].c + 4);
            planes.insert(planes.end(), b.shape.planes[1].c, b.shape.planes[1].c + 4);
            for (int i = 0; i < 3; ++i) {
                lo_[i] = std::min(lo_[i], double(b.shape.center[i]) - double(b.shape.radius));
                hi_[i] = std::max(hi_[i], double(b.shape.center[i]) + double(b.shape.radius));
            }
        }
        count_ = balls.size();
        patches_host_ = render::slim_patches(balls);
        auto upload = [&](GLenum target, GLuint buf, std::size_t bytes, const void* data) {
            gl.BindBuffer(target, buf);
            gl.BufferData(target, static_cast<GLsizeiptr>(std::max<std::size_t>(bytes, 16)), bytes ? data : nullptr, GL_STATIC_DRAW);
            gl.BindBuffer(target, 0);
        };
        upload(GL_SHADER_STORAGE_BUFFER, records_, records.size() * sizeof(records[0]), records.data());
        upload(GL_SHADER_STORAGE_BUFFER, planes_, planes.size() * sizeof(float), planes.data());
        upload(GL_SHADER_STORAGE_BUFFER, patches_, patches_host_.size() * sizeof(patches_host_[0]), patches_host_.data());
        // Two triangles per bounding quad over its 4 corners (as the quadric renderer draws them).
        std::vector<std::uint32_t> idx;
        idx.reserve(6 * count_);
        for (std::uint32_t i = 0; i < count_; ++i) {
            const std::uint32_t b = 4 * i;
            idx.insert(idx.end(), {b, b + 1, b + 2, b, b + 2, b + 3});
        }
        gl.BindVertexArray(vao_);
        gl.BindBuffer(GL_ELEMENT_ARRAY_BUFFER, indices_);
        gl.BufferData(GL_ELEMENT_ARRAY_BUFFER, static_cast<GLsizeiptr>(std::max<std::size_t>(idx.size(), 4) * sizeof(std::uint32_t)),
                      idx.empty() ? nullptr : idx.data(), GL_STATIC_DRAW);
        gl.BindVertexArray(0);
    }
    std::size_t ball_count() const { return count_; }
    const std::vector<SlimPatch<float>>& patches() const { return patches_host_; }

    void bounds(Vec3<double>& lo, Vec3<double>& hi) const {
        lo = lo_;
        hi = hi_;
    }

    void draw(const render::Camera& cam, const render::RenderOptions& opt, bool gbuffer) {
        if (count_ == 0) return;
        const Api& gl = *api_;
        GLint fb = 0, viewport[4] = {0, 0, 1, 1};
        gl.GetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &fb);
        gl.GetIntegerv(GL_VIEWPORT, viewport);
        const bool cull = opt.culling;
        // 1. Visibility: the pushed depth of every ball, no colour.
        gl.BindVertexArray(vao_);
        gl.BindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, records_);
        gl.BindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, planes_);
        gl.BindBufferBase(GL_SHADER_STORAGE_BUFFER, 2, patches_);
        gl.Enable(GL_DEPTH_TEST);
        gl.DepthFunc(GL_LESS);
        gl.DepthMask(GL_TRUE);
        gl.ColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
        draw_balls(programs_.get(render::SlimKey{render::SlimPass::visibility, cull, cam.orthographic}), cam, viewport, opt);
        gl.ColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
        // The shadow map's pass (a framebuffer without colour) needs the depth only.
        GLint color_type = GL_NONE;
        if (fb != 0) gl.GetFramebufferAttachmentParameteriv(GL_DRAW_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_FRAMEBUFFER_ATTACHMENT_OBJECT_TYPE, &color_type);
        if (!gbuffer || color_type == GL_NONE) {
            unbind();
            return;
        }
        GLint depth_type = GL_NONE, depth_tex = 0;
        gl.GetFramebufferAttachmentParameteriv(GL_DRAW_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_FRAMEBUFFER_ATTACHMENT_OBJECT_TYPE, &depth_type);
        if (depth_type != GL_TEXTURE) throw std::runtime_error("quadcast::gl::SlimRenderer: the geometry buffer's depth is not a texture");
        gl.GetFramebufferAttachmentParameteriv(GL_DRAW_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_FRAMEBUFFER_ATTACHMENT_OBJECT_NAME, &depth_tex);
        ensure_targets(viewport[2], viewport[3], static_cast<GLuint>(depth_tex));
        // 2. Accumulation: additive blending of the weighted terms where depth <= the visibility depth.
        gl.BindFramebuffer(GL_FRAMEBUFFER, afbo_);
        const float zero[4] = {0.0f, 0.0f, 0.0f, 0.0f};
        for (int i = 0; i < 3; ++i) gl.ClearBufferfv(GL_COLOR, i, zero);
        gl.DepthMask(GL_FALSE);
        gl.DepthFunc(GL_LEQUAL);
        gl.Enable(GL_BLEND);
        gl.BlendEquation(GL_FUNC_ADD);
        gl.BlendFunc(GL_ONE, GL_ONE);
        draw_balls(programs_.get(render::SlimKey{render::SlimPass::accumulate, cull, cam.orthographic}), cam, viewport, opt);
        gl.Disable(GL_BLEND);
        gl.DepthMask(GL_TRUE);
        // 3. Resolve into the caller's geometry buffer and depth, where the weight is > 0.
        gl.BindFramebuffer(GL_FRAMEBUFFER, static_cast<GLuint>(fb));
        gl.DepthFunc(GL_ALWAYS);
        const Program& res = programs_.get(render::SlimKey{render::SlimPass::resolve, true, cam.orthographic});
        gl.UseProgram(res.id());
        detail::set_camera_uniforms(gl, res, cam, viewport[2], viewport[3]);
        for (int i = 0; i < 3; ++i) gl.BindTextureUnit(static_cast<GLuint>(i), atex_[i]);
        gl.DrawArrays(GL_TRIANGLES, 0, 3);
        for (int i = 0; i < 3; ++i) gl.BindTextureUnit(static_cast<GLuint>(i), 0);
        gl.DepthFunc(GL_LESS);
        unbind();
    }

    void read_sums(std::vector<float>& nw, std::vector<float>& lm) const {
        const Api& gl = *api_;
        nw.assign(std::size_t(width_) * height_ * 4, 0.0f);
        lm.assign(nw.size(), 0.0f);
        if (!afbo_) return;
        std::vector<float> rows(nw.size());
        gl.BindFramebuffer(GL_READ_FRAMEBUFFER, afbo_);
        for (int t = 0; t < 2; ++t) {
            gl.ReadBuffer(static_cast<GLenum>(GL_COLOR_ATTACHMENT0 + t));
            gl.PixelStorei(GL_PACK_ALIGNMENT, 4);
            gl.ReadPixels(0, 0, width_, height_, GL_RGBA, GL_FLOAT, rows.data());
            std::vector<float>& out = t == 0 ? nw : lm;
            for (int y = 0; y < height_; ++y)  // (rows top first)
                std::copy_n(rows.begin() + std::ptrdiff_t(y) * width_ * 4, width_ * 4, out.begin() + std::ptrdiff_t(height_ - 1 - y) * width_ * 4);
        }
        gl.BindFramebuffer(GL_READ_FRAMEBUFFER, 0);
    }

private:
    void unbind() {
        const Api& gl = *api_;
        gl.BindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, 0);
        gl.BindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, 0);
        gl.BindBufferBase(GL_SHADER_STORAGE_BUFFER, 2, 0);
        gl.UseProgram(0);
    }

    /// Every ball with program `p`: over its patch's quadrilateral (`RenderOptions::tight_bounds`) or its
    /// bounding sphere's quad; with `RenderOptions::culling`, per-quadric culling (perspective
    /// cameras) and, with tight bounds, the patch's normal cone.
    void draw_balls(const Program& p, const render::Camera& cam, const GLint* viewport, const render::RenderOptions& opt) {
        const Api& gl = *api_;
        gl.UseProgram(p.id());
        detail::set_camera_uniforms(gl, p, cam, viewport[2], viewport[3]);
        gl.Uniform1i(p.uniform_location("qc_cull"), opt.culling && !cam.orthographic ? 1 : 0);
        gl.Uniform1i(p.uniform_location("qc_patch"), opt.tight_bounds ? 1 : 0);
        gl.Uniform1i(p.uniform_location("qc_patch_cull"), opt.culling && opt.tight_bounds ? 1 : 0);
        gl.DrawElements(GL_TRIANGLES, static_cast<GLsizei>(6 * count_), GL_UNSIGNED_INT, nullptr);
    }

    /// The three accumulation targets (RGBA16F or RGBA32F) sharing the caller's depth texture.
    void ensure_targets(int w, int h, GLuint depth) {
        const Api& gl = *api_;
        if (afbo_ && (w != width_ || h != height_)) release_targets();
        if (!afbo_) {
            width_ = w;
            height_ = h;
            gl.GenTextures(3, atex_);
            for (GLuint t : atex_) {
                gl.BindTexture(GL_TEXTURE_2D, t);
                gl.TexStorage2D(GL_TEXTURE_2D, 1, bits_ == 32 ? GL_RGBA32F : GL_RGBA16F, w, h);
                gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
                gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
            }
            gl.BindTexture(GL_TEXTURE_2D, 0);
            gl.GenFramebuffers(1, &afbo_);
            gl.BindFramebuffer(GL_FRAMEBUFFER, afbo_);
            for (int i = 0; i < 3; ++i) gl.FramebufferTexture2D(GL_FRAMEBUFFER, static_cast<GLenum>(GL_COLOR_ATTACHMENT0 + i), GL_TEXTURE_2D, atex_[i], 0);
            const GLenum bufs[3] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1, GL_COLOR_ATTACHMENT2};
            gl.DrawBuffers(3, bufs);
            depth_ = 0;
        }
        if (depth != depth_) {
            gl.BindFramebuffer(GL_FRAMEBUFFER, afbo_);
            gl.FramebufferTexture2D(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_TEXTURE_2D, depth, 0);
            const GLenum status = gl.CheckFramebufferStatus(GL_FRAMEBUFFER);
            if (status != GL_FRAMEBUFFER_COMPLETE) throw std::runtime_error("quadcast::gl::SlimRenderer: incomplete accumulation framebuffer");
            depth_ = depth;
        }
    }

    void release_targets() {
        if (!afbo_) return;
        api_->DeleteFramebuffers(1, &afbo_);
        api_->DeleteTextures(3, atex_);
        afbo_ = 0;
        depth_ = 0;
    }

    const Api* api_;
    GLuint vao_ = 0, records_ = 0, planes_ = 0, patches_ = 0, indices_ = 0;
    GLuint afbo_ = 0, atex_[3] = {0, 0, 0}, depth_ = 0;
    int width_ = 0, height_ = 0, bits_ = 32;
    std::size_t count_ = 0;
    std::uint64_t revision_ = 1;  ///< changed by every setter (ScenePass::revision)
    std::vector<SlimPatch<float>> patches_host_;
    Vec3<double> lo_{{1e300, 1e300, 1e300}}, hi_{{-1e300, -1e300, -1e300}};
    GeneratedPrograms programs_{*api_, "quadcast::gl::SlimRenderer"};
};

SlimRenderer::SlimRenderer(const Api& api) : impl_(std::make_unique<Impl>(api)) {}
SlimRenderer::~SlimRenderer() = default;
void SlimRenderer::set_precision(int bits) { impl_->set_precision(bits); }
int SlimRenderer::precision() const { return impl_->precision(); }
void SlimRenderer::set_balls(const std::vector<render::Primitive>& balls) { impl_->set_balls(balls); }
std::size_t SlimRenderer::ball_count() const { return impl_->ball_count(); }
const std::vector<SlimPatch<float>>& SlimRenderer::patches() const { return impl_->patches(); }
void SlimRenderer::draw(const render::Camera& cam, const render::Light&, const render::RenderOptions& opt, bool gbuffer) {
    impl_->draw(cam, opt, gbuffer);
}
void SlimRenderer::bounds(Vec3<double>& lo, Vec3<double>& hi) const { impl_->bounds(lo, hi); }
bool SlimRenderer::needs_gbuffer() const { return impl_->ball_count() > 0; }
std::uint64_t SlimRenderer::revision() const { return impl_->revision(); }
void SlimRenderer::read_sums(std::vector<float>& nw, std::vector<float>& lm) const { impl_->read_sums(nw, lm); }

}  // namespace quadcast::gl
