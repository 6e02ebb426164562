// quadcast/gl/slim_renderer.hpp -- the GL three-pass SLIM renderer (Stoll et al. 2006, sec. 5.1.1)
#pragma once
// Host-only. A ScenePass of the QuadricRenderer (`QuadricRenderer::add_pass`): in its geometry
// buffer pass it draws
//   1. visibility   every ball's quadric over the quadrilateral of its patch (`slim_patch_quad` of
//                   its `slim_patches` bound, computed in `set_balls`; with tight bounds, else its
//                   bounding sphere's quad), culled per quadric (perspective) and by its patch's
//                   normal cone (`slim_patch_culled`, tight bounds) with culling on, depth only:
//                   the hit's depth pushed away from the eye (`SlimFragment::visibility`), GL_LESS
//                   into the frame's depth target;
//   2. accumulate   the same quads with depth writes off and GL_LEQUAL against that depth,
//                   additive blending (GL_ONE, GL_ONE) of `slim_terms` -- (w n, w), (w lambda,
//                   w specular, w shininess), w colour -- into three float targets (RGBA16F or
//                   RGBA32F, `set_precision`);
//   3. resolve      a full-screen triangle dividing by the weight (`slim_resolve`) into the
//                   geometry buffer and the depth target where the weight is > 0,
// and the quadric renderer's deferred pass shades the result like its own primitives (shadows,
// outlines, environment). In the shadow map's pass (no colour target) only pass 1 runs. A
// renderer with balls asks the quadric renderer for the geometry buffer (`needs_gbuffer`).
// The CPU reference is quadcast/render/slim_cpu_renderer.hpp (same templates, same order).

#include <cstddef>
#include <memory>
#include <vector>

#include "quadcast/gl/scene_pass.hpp"
#include "quadcast/render/types.hpp"
#include "quadcast/slim_blend.hpp"

namespace quadcast::gl {

struct Api;

class SlimRenderer final : public ScenePass {
public:
    /// Makes the renderer's buffers in the current context (`api`: its function table).
    explicit SlimRenderer(const Api& api);
    ~SlimRenderer() override;
    SlimRenderer(const SlimRenderer&) = delete;
    SlimRenderer& operator=(const SlimRenderer&) = delete;

    /// Bits per channel of the accumulation targets: 32 (RGBA32F, default) or 16 (RGBA16F: the
    /// half-float sum of w lambda rounds the blended position along the ray to about 2^-11 of its
    /// distance, at no measured gain in speed on llvmpipe); other values throw
    /// std::invalid_argument (8-bit UNORM targets would need an encoding of the signed sums whose
    /// rounding moves the blended surface by about E: README, "8-bit targets").
    void set_precision(int bits);
    int precision() const;

    /// Uploads the balls (render::validate_slim_balls: `bounded` primitives, clip planes in
    /// shape.planes[0] and shape.planes[1]; throws std::invalid_argument before anything is uploaded) and their patch
    /// bounds (render::slim_patches, on all cores: about 0.1 ms per ball).
    void set_balls(const std::vector<render::Primitive>& balls);
    std::size_t ball_count() const;
    /// The balls' patch bounds computed by `set_balls` (render::slim_patches), in ball order.
    const std::vector<SlimPatch<float>>& patches() const;

    void draw(const render::Camera& cam, const render::Light& light, const render::RenderOptions& opt, bool gbuffer) override;
    void bounds(Vec3<double>& lo, Vec3<double>& hi) const override;
    bool needs_gbuffer() const override;
    /// Changes with every `set_balls` and `set_precision`.
    std::uint64_t revision() const override;

    /// The accumulation targets of the last draw, rows top first like render::Image: per pixel
    /// (sum w n, sum w) and (sum w lambda, sum w specular, sum w shininess, 0), as floats.
    void read_sums(std::vector<float>& normal_weight, std::vector<float>& lambda_material) const;

private:
    class Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace quadcast::gl
