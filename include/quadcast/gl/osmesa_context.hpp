// quadcast/gl/osmesa_context.hpp -- RAII offscreen OpenGL 4.5 core context through Mesa's OSMesa (llvmpipe)
#pragma once
// Host-only. Link: pkg-config osmesa (the CMake target quadcast::gl does it).
// Include order: this header includes loader.hpp (<GL/glcorearb.h>) before <GL/osmesa.h>.

#include "quadcast/gl/loader.hpp"

#include <GL/osmesa.h>

#include <string>
#include <utility>
#include <vector>

namespace quadcast::gl {

/// An offscreen OpenGL core context from OSMesa (Mesa's llvmpipe on a machine without GPU),
/// current on the constructing thread, with a small RGBA8 default framebuffer (render to your
/// own framebuffer objects for real work) and the loaded function table. Objects that keep a
/// pointer to api() (ComputeRunner, Program ...) need the context at a stable address: move it
/// before creating them, and destroy them first.
class OsmesaContext {
public:
    struct Options {
        int width = 16;   ///< default framebuffer size; RGBA8, owned by the context
        int height = 16;
        int major = 4;  ///< requested core version; lower minor versions down to min_minor are tried
        int minor = 5;
        int min_minor = 5;  ///< lowest acceptable 4.x: 5 (every stage is `#version 450`; the renderers use direct state access)
        int depth_bits = 24;
        int stencil_bits = 8;
    };

    OsmesaContext() : OsmesaContext(Options{}) {}

    /// Creates the context (trying core 4.minor, 4.(minor-1) ... 4.min_minor), makes it current
    /// and loads the Api. Throws std::runtime_error "no OpenGL 4.5 core context: OSMesa ..." on
    /// failure.
    explicit OsmesaContext(const Options& opt) : width_(opt.width), height_(opt.height) {
        if (opt.width <= 0 || opt.height <= 0)
            throw std::invalid_argument("quadcast::gl::OsmesaContext: framebuffer size must be positive");
        if (opt.major != 4 || opt.min_minor < 5 || opt.minor < opt.min_minor)
            throw std::invalid_argument("quadcast::gl::OsmesaContext: request OpenGL 4.5 or later (major 4, min_minor >= 5)");
        std::string tried;
        for (int minor = opt.minor; minor >= opt.min_minor && ctx_ == nullptr; --minor) {
            const int attribs[] = {OSMESA_FORMAT,
                                   OSMESA_RGBA,
                                   OSMESA_DEPTH_BITS,
                                   opt.depth_bits,
                                   OSMESA_STENCIL_BITS,
                                   opt.stencil_bits,
                                   OSMESA_ACCUM_BITS,
                                   0,
                                   OSMESA_PROFILE,
                                   OSMESA_CORE_PROFILE,
                                   OSMESA_CONTEXT_MAJOR_VERSION,
                                   opt.major,
                                   OSMESA_CONTEXT_MINOR_VERSION,
                                   minor,
                                   0};
            ctx_ = OSMesaCreateContextAttribs(attribs, nullptr);
            tried += (tried.empty() ? "" : ", ") + std::to_string(opt.major) + "." + std::to_string(minor);
        }
        if (ctx_ == nullptr)
            throw std::runtime_error("no OpenGL 4.5 core context: OSMesaCreateContextAttribs returned null for core " +
                                     tried + highest_core_version(opt) +
                                     " (is Mesa's libOSMesa built with a gallium driver such as llvmpipe? "
                                     "GALLIUM_DRIVER / LIBGL_ALWAYS_SOFTWARE may select another one)");
        pixels_.assign(static_cast<std::size_t>(width_) * static_cast<std::size_t>(height_) * 4u, 0);
        try {
            make_current();
            api_ = Api::load(&OsmesaContext::get_proc_address);
        } catch (const std::exception& e) {
            release();
            throw std::runtime_error(std::string("no OpenGL 4.5 core context: OSMesa context created but ") +
                                     e.what());
        }
        info_ = describe_context(api_, "OSMesa");
        if (api_.version() < 10 * opt.major + opt.minor)
            info_.fallback = "requested " + std::to_string(opt.major) + "." + std::to_string(opt.minor) + ", got " +
                             std::to_string(api_.major) + "." + std::to_string(api_.minor);
    }

    ~OsmesaContext() { release(); }

    /// ", the highest core version it creates is 4.3" (or that it creates none from 4.4 down to
    /// 3.2): names the version found when 4.5 is refused.
    static std::string highest_core_version(const Options& opt) {
        for (int v = 44; v >= 32; v = v % 10 == 0 ? v - 7 : v - 1) {  // 4.4 ... 4.0, 3.3 ... 3.2
            const int attribs[] = {OSMESA_FORMAT, OSMESA_RGBA, OSMESA_DEPTH_BITS, opt.depth_bits, OSMESA_PROFILE, OSMESA_CORE_PROFILE,
                                   OSMESA_CONTEXT_MAJOR_VERSION, v / 10, OSMESA_CONTEXT_MINOR_VERSION, v % 10, 0};
            if (::OSMesaContext c = OSMesaCreateContextAttribs(attribs, nullptr)) {
                OSMesaDestroyContext(c);
                return "; the highest core version it creates is " + std::to_string(v / 10) + "." + std::to_string(v % 10);
            }
        }
        return "; it creates no core context from 4.4 down to 3.2";
    }

    OsmesaContext(const OsmesaContext&) = delete;
    OsmesaContext& operator=(const OsmesaContext&) = delete;
    OsmesaContext(OsmesaContext&& o) noexcept
        : ctx_(std::exchange(o.ctx_, nullptr)), width_(o.width_), height_(o.height_), pixels_(std::move(o.pixels_)),
          api_(o.api_), info_(std::move(o.info_)) {}
    OsmesaContext& operator=(OsmesaContext&& o) noexcept {
        if (this != &o) {
            release();
            ctx_ = std::exchange(o.ctx_, nullptr);
            width_ = o.width_;
            height_ = o.height_;
            pixels_ = std::move(o.pixels_);
            api_ = o.api_;
            info_ = std::move(o.info_);
        }
        return *this;
    }

    /// Makes this context current on the calling thread (with its own default framebuffer).
    void make_current() {
        if (ctx_ == nullptr) throw std::logic_error("quadcast::gl::OsmesaContext: moved-from context");
        if (!OSMesaMakeCurrent(ctx_, pixels_.data(), GL_UNSIGNED_BYTE, width_, height_))
            throw std::runtime_error("quadcast::gl::OsmesaContext: OSMesaMakeCurrent failed");
    }
    bool is_current() const noexcept { return ctx_ != nullptr && OSMesaGetCurrentContext() == ctx_; }

    /// OSMesaGetProcAddress, usable as a Resolver.
    static void* get_proc_address(const char* name) {
        return reinterpret_cast<void*>(OSMesaGetProcAddress(name));
    }
    Resolver resolver() const { return &OsmesaContext::get_proc_address; }

    /// The function table of this context.
    const Api& api() const noexcept { return api_; }
    const ContextInfo& info() const noexcept { return info_; }
    int width() const noexcept { return width_; }
    int height() const noexcept { return height_; }
    /// The default framebuffer's RGBA8 pixels (bottom row first), valid after glFinish.
    const std::vector<unsigned char>& pixels() const noexcept { return pixels_; }
    ::OSMesaContext osmesa() const noexcept { return ctx_; }

private:
    void release() noexcept {
        if (ctx_ == nullptr) return;
        if (OSMesaGetCurrentContext() == ctx_) OSMesaMakeCurrent(nullptr, nullptr, 0, 0, 0);
        OSMesaDestroyContext(ctx_);
        ctx_ = nullptr;
    }

    ::OSMesaContext ctx_ = nullptr;
    int width_ = 0, height_ = 0;
    std::vector<unsigned char> pixels_;
    Api api_{};
    ContextInfo info_;
};

}  // namespace quadcast::gl
