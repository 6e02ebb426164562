// tests/gl/host_frame.hpp -- what a host application does before drawing into its own framebuffer
#pragma once

#include "quadcast/gl/loader.hpp"

namespace qc_gl_test {

/// Binds the host's framebuffer `fbo`, sets a width x height viewport, clears the colour to `bg`
/// and the depth to 1, and turns the LESS depth test on, as a host does before its geometry and
/// quadcast's draws.
inline void begin_host_frame(const quadcast::gl::Api& api, GLuint fbo, int width, int height, const float (&bg)[4]) {
    api.BindFramebuffer(GL_FRAMEBUFFER, fbo);
    api.Viewport(0, 0, width, height);
    const float one = 1.0f;
    api.ClearBufferfv(GL_COLOR, 0, bg);
    api.ClearBufferfv(GL_DEPTH, 0, &one);
    api.Enable(GL_DEPTH_TEST);
    api.DepthFunc(GL_LESS);
}

}  // namespace qc_gl_test
