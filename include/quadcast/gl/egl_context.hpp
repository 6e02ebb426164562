// quadcast/gl/egl_context.hpp -- RAII offscreen OpenGL 4.5 core context through EGL surfaceless (Mesa)
#pragma once
// Host-only. libEGL.so.1 is opened at run time (dlopen), so neither EGL headers nor -lEGL are
// needed to build; link -ldl on glibc < 2.34. Mesa's EGL_MESA_platform_surfaceless falls back
// to llvmpipe where there is no GPU render node, like OSMesa.
// Caveat: the surfaceless EGLDisplay is process-wide and not reference counted, so contexts
// never eglTerminate it (the display stays initialised until exit).

#include "quadcast/gl/loader.hpp"

#include <dlfcn.h>

#include <cstdint>
#include <cstring>
#include <string>
#include <utility>

namespace quadcast::gl {

namespace egl_detail {

// The few EGL types and constants used (values from the Khronos <EGL/egl.h>, <EGL/eglext.h>).
using EGLDisplay = void*;
using EGLContext = void*;
using EGLSurface = void*;
using EGLConfig = void*;
using EGLint = std::int32_t;
using EGLBoolean = unsigned int;
using EGLenum = unsigned int;
inline constexpr EGLint kNone = 0x3038;
inline constexpr EGLint kSuccess = 0x3000;
inline constexpr EGLint kExtensions = 0x3055;
inline constexpr EGLint kSurfaceType = 0x3033;
inline constexpr EGLint kPbufferBit = 0x0001;
inline constexpr EGLint kRenderableType = 0x3040;
inline constexpr EGLint kOpenglBit = 0x0008;
inline constexpr EGLenum kOpenglApi = 0x30A2;
inline constexpr EGLint kContextMajorVersion = 0x3098;
inline constexpr EGLint kContextMinorVersion = 0x30FB;
inline constexpr EGLint kContextOpenglProfileMask = 0x30FD;
inline constexpr EGLint kContextOpenglCoreProfileBit = 0x0001;
inline constexpr EGLenum kPlatformSurfacelessMesa = 0x31DD;

struct Lib {
    void* handle = nullptr;
    std::string error;  // why loading failed
    void* (*GetProcAddress)(const char*) = nullptr;
    EGLDisplay (*GetPlatformDisplayEXT)(EGLenum, void*, const EGLint*) = nullptr;
    EGLBoolean (*Initialize)(EGLDisplay, EGLint*, EGLint*) = nullptr;
    EGLBoolean (*BindAPI)(EGLenum) = nullptr;
    EGLBoolean (*ChooseConfig)(EGLDisplay, const EGLint*, EGLConfig*, EGLint, EGLint*) = nullptr;
    EGLContext (*CreateContext)(EGLDisplay, EGLConfig, EGLContext, const EGLint*) = nullptr;
    EGLBoolean (*DestroyContext)(EGLDisplay, EGLContext) = nullptr;
    EGLBoolean (*MakeCurrent)(EGLDisplay, EGLSurface, EGLSurface, EGLContext) = nullptr;
    EGLContext (*GetCurrentContext)() = nullptr;
    EGLint (*GetError)() = nullptr;
    const char* (*QueryString)(EGLDisplay, EGLint) = nullptr;
};

/// libEGL.so.1, opened once per process and never closed.
inline const Lib& lib() {
    static const Lib l = [] {
        Lib r;
        r.handle = dlopen("libEGL.so.1", RTLD_NOW | RTLD_LOCAL);
        if (r.handle == nullptr) {
            const char* e = dlerror();
            r.error = std::string("cannot open libEGL.so.1 (") + (e ? e : "?") + ")";
            return r;
        }
        auto sym = [&](auto& slot, const char* name) {
            slot = reinterpret_cast<std::remove_reference_t<decltype(slot)>>(dlsym(r.handle, name));
            if (slot == nullptr && r.error.empty()) r.error = std::string("libEGL.so.1 lacks ") + name;
        };
        sym(r.GetProcAddress, "eglGetProcAddress");
        sym(r.Initialize, "eglInitialize");
        sym(r.BindAPI, "eglBindAPI");
        sym(r.ChooseConfig, "eglChooseConfig");
        sym(r.CreateContext, "eglCreateContext");
        sym(r.DestroyContext, "eglDestroyContext");
        sym(r.MakeCurrent, "eglMakeCurrent");
        sym(r.GetCurrentContext, "eglGetCurrentContext");
        sym(r.GetError, "eglGetError");
        sym(r.QueryString, "eglQueryString");
        if (r.error.empty())
            r.GetPlatformDisplayEXT = reinterpret_cast<decltype(r.GetPlatformDisplayEXT)>(
                r.GetProcAddress("eglGetPlatformDisplayEXT"));
        if (r.error.empty() && r.GetPlatformDisplayEXT == nullptr) r.error = "no eglGetPlatformDisplayEXT";
        return r;
    }();
    return l;
}

inline bool has_extension(const char* list, const char* name) {
    if (list == nullptr) return false;
    const std::size_t n = std::strlen(name);
    for (const char* p = list; (p = std::strstr(p, name)) != nullptr; p += n)
        if ((p == list || p[-1] == ' ') && (p[n] == ' ' || p[n] == '\0')) return true;
    return false;
}

inline std::string hex(EGLint v) {
    char buf[16];
    std::snprintf(buf, sizeof buf, "0x%04X", static_cast<unsigned>(v));
    return buf;
}

}  // namespace egl_detail

/// An offscreen OpenGL core context on Mesa's EGL surfaceless platform, current on the
/// constructing thread with no default framebuffer (render to framebuffer objects). As with
/// OsmesaContext, objects holding a pointer to api() need the context at a stable address.
class EglContext {
public:
    struct Options {
        int major = 4;
        int minor = 5;
        int min_minor = 5;  ///< lowest acceptable 4.x: 5 (every stage is `#version 450`; the renderers use direct state access)
    };

    EglContext() : EglContext(Options{}) {}

    /// Throws std::runtime_error "no OpenGL 4.5 core context: EGL ..." on failure.
    explicit EglContext(const Options& opt) {
        namespace d = egl_detail;
        if (opt.major != 4 || opt.min_minor < 5 || opt.minor < opt.min_minor)
            throw std::invalid_argument("quadcast::gl::EglContext: request OpenGL 4.5 or later (major 4, min_minor >= 5)");
        const d::Lib& egl = d::lib();
        const std::string fail = "no OpenGL 4.5 core context: EGL surfaceless: ";
        if (!egl.error.empty()) throw std::runtime_error(fail + egl.error);
        if (!d::has_extension(egl.QueryString(nullptr, d::kExtensions), "EGL_MESA_platform_surfaceless"))
            throw std::runtime_error(fail + "the EGL client lacks EGL_MESA_platform_surfaceless");
        display_ = egl.GetPlatformDisplayEXT(d::kPlatformSurfacelessMesa, nullptr, nullptr);
        d::EGLint emajor = 0, eminor = 0;
        if (display_ == nullptr || !egl.Initialize(display_, &emajor, &eminor))
            throw std::runtime_error(fail + "eglInitialize failed (" + d::hex(egl.GetError()) + ")");
        if (!egl.BindAPI(d::kOpenglApi))
            throw std::runtime_error(fail + "eglBindAPI(EGL_OPENGL_API) failed (" + d::hex(egl.GetError()) + ")");
        d::EGLConfig config = nullptr;  // EGL_NO_CONFIG_KHR
        if (!d::has_extension(egl.QueryString(display_, d::kExtensions), "EGL_KHR_no_config_context")) {
            const d::EGLint cattr[] = {d::kRenderableType, d::kOpenglBit, d::kSurfaceType, d::kPbufferBit, d::kNone};
            d::EGLint n = 0;
            if (!egl.ChooseConfig(display_, cattr, &config, 1, &n) || n < 1)
                throw std::runtime_error(fail + "no EGLConfig with EGL_OPENGL_BIT");
        }
        std::string tried;
        for (int minor = opt.minor; minor >= opt.min_minor && ctx_ == nullptr; --minor) {
            const d::EGLint attr[] = {d::kContextMajorVersion,      opt.major, d::kContextMinorVersion,
                                      minor,                        d::kContextOpenglProfileMask,
                                      d::kContextOpenglCoreProfileBit, d::kNone};
            ctx_ = egl.CreateContext(display_, config, nullptr, attr);
            tried += (tried.empty() ? "" : ", ") + std::to_string(opt.major) + "." + std::to_string(minor);
        }
        if (ctx_ == nullptr) {
            const std::string error = d::hex(egl.GetError());
            throw std::runtime_error(fail + "eglCreateContext failed for core " + tried + " (" + error + ")" + highest_core_version(config));
        }
        try {
            make_current();
            api_ = Api::load(&EglContext::get_proc_address);
        } catch (const std::exception& e) {
            release();
            throw std::runtime_error(fail + "context created but " + e.what());
        }
        info_ = describe_context(api_, "EGL surfaceless");
        if (api_.version() < 10 * opt.major + opt.minor)
            info_.fallback = "requested " + std::to_string(opt.major) + "." + std::to_string(opt.minor) + ", got " +
                             std::to_string(api_.major) + "." + std::to_string(api_.minor);
    }

    ~EglContext() { release(); }

    /// "; the highest core version it creates is 4.3" (or that it creates none from 4.4 down to
    /// 3.2): names the version found when 4.5 is refused.
    std::string highest_core_version(void* config) const {
        namespace d = egl_detail;
        const d::Lib& egl = d::lib();
        for (int v = 44; v >= 32; v = v % 10 == 0 ? v - 7 : v - 1) {  // 4.4 ... 4.0, 3.3 ... 3.2
            const d::EGLint attr[] = {d::kContextMajorVersion, v / 10, d::kContextMinorVersion, v % 10,
                                      d::kContextOpenglProfileMask, d::kContextOpenglCoreProfileBit, d::kNone};
            if (d::EGLContext c = egl.CreateContext(display_, config, nullptr, attr)) {
                egl.DestroyContext(display_, c);
                return "; the highest core version it creates is " + std::to_string(v / 10) + "." + std::to_string(v % 10);
            }
        }
        return "; it creates no core context from 4.4 down to 3.2";
    }
    EglContext(const EglContext&) = delete;
    EglContext& operator=(const EglContext&) = delete;
    EglContext(EglContext&& o) noexcept
        : display_(o.display_), ctx_(std::exchange(o.ctx_, nullptr)), api_(o.api_), info_(std::move(o.info_)) {}
    EglContext& operator=(EglContext&& o) noexcept {
        if (this != &o) {
            release();
            display_ = o.display_;
            ctx_ = std::exchange(o.ctx_, nullptr);
            api_ = o.api_;
            info_ = std::move(o.info_);
        }
        return *this;
    }

    /// True when libEGL.so.1 opens and offers EGL_MESA_platform_surfaceless (no context made).
    static bool available() {
        const egl_detail::Lib& egl = egl_detail::lib();
        return egl.error.empty() &&
               egl_detail::has_extension(egl.QueryString(nullptr, egl_detail::kExtensions),
                                         "EGL_MESA_platform_surfaceless");
    }

    void make_current() {
        if (ctx_ == nullptr) throw std::logic_error("quadcast::gl::EglContext: moved-from context");
        const auto& egl = egl_detail::lib();
        if (!egl.MakeCurrent(display_, nullptr, nullptr, ctx_))
            throw std::runtime_error("quadcast::gl::EglContext: eglMakeCurrent failed (" +
                                     egl_detail::hex(egl.GetError()) + ")");
    }
    bool is_current() const noexcept { return ctx_ != nullptr && egl_detail::lib().GetCurrentContext() == ctx_; }

    /// eglGetProcAddress, usable as a Resolver.
    static void* get_proc_address(const char* name) {
        const auto& egl = egl_detail::lib();
        return egl.GetProcAddress ? egl.GetProcAddress(name) : nullptr;
    }
    Resolver resolver() const { return &EglContext::get_proc_address; }

    const Api& api() const noexcept { return api_; }
    const ContextInfo& info() const noexcept { return info_; }

private:
    void release() noexcept {
        if (ctx_ == nullptr) return;
        const auto& egl = egl_detail::lib();
        if (egl.GetCurrentContext() == ctx_) egl.MakeCurrent(display_, nullptr, nullptr, nullptr);
        egl.DestroyContext(display_, ctx_);
        ctx_ = nullptr;
    }

    egl_detail::EGLDisplay display_ = nullptr;
    egl_detail::EGLContext ctx_ = nullptr;
    Api api_{};
    ContextInfo info_;
};

}  // namespace quadcast::gl
