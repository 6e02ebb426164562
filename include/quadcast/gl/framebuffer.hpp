// quadcast/gl/framebuffer.hpp -- the renderers' offscreen framebuffer (RGBA8 + float depth): making it, reading it back
#pragma once

#include <algorithm>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "quadcast/gl/loader.hpp"
#include "quadcast/render/types.hpp"

namespace quadcast::gl {

/// Makes a width x height framebuffer with an RGBA8 colour texture tex[0] and a 32-bit float
/// depth texture tex[1]; returns it. Throws std::runtime_error naming `owner` when incomplete.
inline GLuint make_framebuffer(const Api& gl, int width, int height, GLuint (&tex)[2], const std::string& owner) {
    gl.GenTextures(2, tex);
    gl.BindTexture(GL_TEXTURE_2D, tex[0]);
    gl.TexStorage2D(GL_TEXTURE_2D, 1, GL_RGBA8, width, height);
    gl.BindTexture(GL_TEXTURE_2D, tex[1]);
    gl.TexStorage2D(GL_TEXTURE_2D, 1, GL_DEPTH_COMPONENT32F, width, height);
    gl.BindTexture(GL_TEXTURE_2D, 0);
    GLuint fbo = 0;
    gl.GenFramebuffers(1, &fbo);
    gl.BindFramebuffer(GL_FRAMEBUFFER, fbo);
    gl.FramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, tex[0], 0);
    gl.FramebufferTexture2D(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_TEXTURE_2D, tex[1], 0);
    const GLenum status = gl.CheckFramebufferStatus(GL_FRAMEBUFFER);
    gl.BindFramebuffer(GL_FRAMEBUFFER, 0);
    if (status != GL_FRAMEBUFFER_COMPLETE) {
        gl.DeleteFramebuffers(1, &fbo);
        gl.DeleteTextures(2, tex);
        throw std::runtime_error(owner + ": incomplete framebuffer");
    }
    return fbo;
}

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
