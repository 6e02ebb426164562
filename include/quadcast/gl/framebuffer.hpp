// quadcast/gl/framebuffer.hpp -- reading a rendered frame back from an RGBA8 + float-depth framebuffer
#pragma once

#include <algorithm>
#include <cstdint>
#include <vector>

#include "quadcast/gl/loader.hpp"
#include "quadcast/render/types.hpp"

namespace quadcast::gl {

/// The colour (RGBA8) and depth (float window depth) of framebuffer `fbo`, width x height, as a
/// render::Image with rows top first (like the CPU renderers).
inline render::Image read_framebuffer(const Api& gl, GLuint fbo, int width, int height) {
    render::Image img;
    img.width = width;
    img.height = height;
    std::vector<std::uint8_t> rgba(static_cast<std::size_t>(width) * height * 4);
    std::vector<float> depth(static_cast<std::size_t>(width) * height);
    gl.BindFramebuffer(GL_READ_FRAMEBUFFER, fbo);
    gl.PixelStorei(GL_PACK_ALIGNMENT, 1);
    gl.ReadPixels(0, 0, width, height, GL_RGBA, GL_UNSIGNED_BYTE, rgba.data());
    gl.ReadPixels(0, 0, width, height, GL_DEPTH_COMPONENT, GL_FLOAT, depth.data());
    gl.BindFramebuffer(GL_READ_FRAMEBUFFER, 0);
    img.rgba.resize(rgba.size());
    img.depth.resize(depth.size());
    const std::size_t row = static_cast<std::size_t>(width);
    for (int y = 0; y < height; ++y) {
        const std::size_t src = static_cast<std::size_t>(height - 1 - y) * row, dst = static_cast<std::size_t>(y) * row;
        std::copy_n(rgba.begin() + static_cast<std::ptrdiff_t>(src * 4), row * 4, img.rgba.begin() + static_cast<std::ptrdiff_t>(dst * 4));
        std::copy_n(depth.begin() + static_cast<std::ptrdiff_t>(src), row, img.depth.begin() + static_cast<std::ptrdiff_t>(dst));
    }
    return img;
}

}  // namespace quadcast::gl
