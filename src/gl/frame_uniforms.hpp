// src/gl/frame_uniforms.hpp -- host-side camera terms shared by the GL renderers (internal to quadcast::gl)
#pragma once

#include <array>

#include "quadcast/gl/loader.hpp"
#include "quadcast/gl/program.hpp"
#include "quadcast/render/types.hpp"

namespace quadcast::gl::detail {

/// View-space corners of the near-plane rectangle (qc_near_corners: the bounding quad of a
/// primitive whose bounding sphere contains the eye), slightly inside the near plane
/// (src/gl/quadric_renderer.cpp).
std::array<float, 12> near_corners(const render::Camera& cam);

/// The camera's uniforms of the quadric stages for a width x height viewport, each set where `p`
/// has it: qc_view, qc_projection, qc_view_projection, qc_view_rot_inv, qc_eye, qc_near_corners,
/// qc_viewport, the pixel-ray terms (`window_ray_terms`), qc_vz_row, qc_vz_t and qc_pz
/// (src/gl/quadric_renderer.cpp). The quadric and SLIM renderers both call it.
void set_camera_uniforms(const Api& gl, const Program& p, const render::Camera& cam, int width, int height);

}  // namespace quadcast::gl::detail
