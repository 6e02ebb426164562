// quadcast/gl/scene_pass.hpp -- geometry drawn by another renderer in the quadric renderer's passes
#pragma once

#include <cstdint>
#include <cstring>
#include <vector>

#include "quadcast/linalg.hpp"
#include "quadcast/render/types.hpp"

namespace quadcast::gl {

/// Appends the bits of `f` to a frame key.
inline void push_float_bits(std::vector<std::uint64_t>& key, float f) {
    std::uint32_t u = 0;
    std::memcpy(&u, &f, sizeof u);
    key.push_back(u);
}

/// Appends what a camera contributes to a frame key (the quadric renderer's view and shadow keys,
/// the isosurface renderer's view key): the view and projection matrices' and the eye's float
/// bits, and whether it is orthographic.
inline void push_camera_key(std::vector<std::uint64_t>& key, const render::Camera& cam) {
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r) {
            push_float_bits(key, cam.view[c][r]);
            push_float_bits(key, cam.projection[c][r]);
        }
    for (int i = 0; i < 3; ++i) push_float_bits(key, cam.eye[i]);
    key.push_back(cam.orthographic);
}

/// Geometry that a `QuadricRenderer` draws in each of its passes after its own primitives: the
/// shadow map, the forward pass and the geometry buffer of deferred shading share one depth
/// buffer, so the two kinds of geometry occlude each other and the deferred pass shades,
/// shadows and outlines both.
class ScenePass {
public:
    virtual ~ScenePass() = default;
    /// Draws into the bound framebuffer (viewport, depth test and clears are the caller's) with
    /// forward shading or, with `gbuffer`, the geometry-buffer outputs (normal + window depth, ray
    /// direction + 1, colour + 1). Leaves its own vertex array and buffers bound.
    virtual void draw(const render::Camera& cam, const render::Light& light, const render::RenderOptions& opt, bool gbuffer) = 0;
    /// World bounding box of the geometry (for fitting the shadow map); lo > hi when empty.
    virtual void bounds(Vec3<double>& lo, Vec3<double>& hi) const = 0;
    /// True when the pass draws only into the geometry buffer (the SLIM renderer's blending): the
    /// quadric renderer then shades the frame deferred (the same image as forward shading).
    virtual bool needs_gbuffer() const { return false; }
    /// A number that changes whenever what `draw` draws for a given camera and options may
    /// change (the pass's geometry or settings). The quadric renderer keeps its shadow map across
    /// frames while the light, its own primitives and every pass's revision stay the same
    /// (RenderOptions::shadow_map_reuse). 0, the default: not tracked, and the shadow map is
    /// drawn again in every frame.
    virtual std::uint64_t revision() const { return 0; }
    /// Called by the quadric renderer just before `draw`, about the depth already in the target:
    /// `key` identifies everything drawn there before this pass in this frame (the renderer, its
    /// view, primitives and options, the target, the light, the revisions of the passes before
    /// this one), equal keys meaning equal depth; nullptr where it cannot say (a host's
    /// framebuffer, a pass before this one without a revision). So a pass's revision must change
    /// with whatever changes the depth it draws besides the camera, the viewport, the light and
    /// RenderOptions::culling, tight_bounds and deferred. A pass may use it for the next `draw` only: the isosurface
    /// renderer draws the last frame's shown set alone where its own view and this key are the
    /// ones its set was tested under. The default ignores it.
    virtual void frame_before(const std::vector<std::uint64_t>* key) { (void)key; }
};

}  // namespace quadcast::gl
