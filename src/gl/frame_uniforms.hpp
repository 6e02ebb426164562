// src/gl/frame_uniforms.hpp -- host-side camera terms shared by the GL renderers (internal to quadcast::gl)
#pragma once

#include <array>

#include "quadcast/render/types.hpp"

namespace quadcast::gl::detail {

/// View-space corners of the near-plane rectangle (qc_near_corners: the bounding quad of a
/// primitive whose bounding sphere contains the eye), slightly inside the near plane
/// (src/gl/quadric_renderer.cpp).
std::array<float, 12> near_corners(const render::Camera& cam);

}  // namespace quadcast::gl::detail
