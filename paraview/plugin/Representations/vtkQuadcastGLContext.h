// vtkQuadcastGLContext -- what the plugin's mappers share to draw with quadcast inside a VTK render window
#ifndef vtkQuadcastGLContext_h
#define vtkQuadcastGLContext_h

#include <exception>
#include <memory>
#include <string>

// quadcast after VTK's headers; none of VTK's OpenGL headers is included with these, so
// quadcast's loader brings <GL/glcorearb.h> and the renderers draw through its own function table.
#include <quadcast/gl/loader.hpp>
#include <quadcast/render/types.hpp>

class vtkMatrix4x4;
class vtkRenderer;
class vtkWindow;

namespace quadcast_paraview {

/// The current GLX, EGL or OSMesa context's function table (its getProcAddress looked up at run
/// time: the plugin links none of them). Throws std::runtime_error when no context is current.
std::unique_ptr<quadcast::gl::Api> load_current_api();

/// A quadcast renderer (QuadricRenderer, IsosurfaceRenderer) made in the render window a mapper
/// last drew in, with its function table. For another window it is made anew; the old window's
/// GL objects are then left to that window's context (not current) instead of being deleted in
/// this one, whose names they might share.
template <class Renderer>
class WindowRenderer {
public:
    WindowRenderer() = default;
    WindowRenderer(const WindowRenderer&) = delete;
    WindowRenderer& operator=(const WindowRenderer&) = delete;
    /// GL objects are freed by `release` while their context is current; what is left here
    /// belongs to a window already gone, and its names die with that context.
    ~WindowRenderer() { drop(); }

    /// The renderer for `win`, whose context is current: `fresh` when made by this call; null
    /// when it cannot be made there (`error` says why the first time, and is empty after).
    Renderer* get(vtkWindow* win, bool& fresh, std::string& error) {
        fresh = false;
        error.clear();
        if (win == window_) return renderer_.get();
        drop();
        window_ = win;
        try {
            api_ = load_current_api();
            renderer_ = std::make_unique<Renderer>(*api_);
            fresh = true;
        } catch (const std::exception& e) {
            renderer_.reset();
            error = e.what();
        }
        return renderer_.get();
    }
    const quadcast::gl::Api& api() const { return *api_; }
    /// Frees the GL objects when `win` is the window they were made in (its context current:
    /// vtkMapper::ReleaseGraphicsResources).
    void release(vtkWindow* win) {
        if (!win || win != window_) return;
        renderer_.reset();
        api_.reset();
        window_ = nullptr;
    }

private:
    void drop() {
        (void)renderer_.release();
        (void)api_.release();
        window_ = nullptr;
    }
    vtkWindow* window_ = nullptr;
    std::unique_ptr<quadcast::gl::Api> api_;
    std::unique_ptr<Renderer> renderer_;
};

/// The GL state VTK's state cache relies on, saved before quadcast draws and put back after; the
/// constructor then sets what quadcast draws with (depth test LESS with writes; no blending, face
/// culling, polygon offset or stencil test).
class SavedState {
public:
    explicit SavedState(const quadcast::gl::Api& gl);
    ~SavedState();
    SavedState(const SavedState&) = delete;
    SavedState& operator=(const SavedState&) = delete;

private:
    const quadcast::gl::Api& gl_;
    static constexpr GLenum caps_[] = {GL_DEPTH_TEST, GL_BLEND, GL_CULL_FACE, GL_DEPTH_CLAMP, GL_SCISSOR_TEST, GL_POLYGON_OFFSET_FILL, GL_STENCIL_TEST};
    GLboolean enabled_[std::size(caps_)] = {};
    GLint program_ = 0, vao_ = 0, array_buffer_ = 0, element_buffer_ = 0, active_texture_ = GL_TEXTURE0, depth_func_ = GL_LESS, cull_face_ = GL_BACK;
    GLboolean depth_mask_ = GL_TRUE;
    GLboolean color_mask_[4] = {GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE};
};

/// A VTK matrix (row-major) as quadcast's (columns first).
quadcast::Mat4<double> to_quadcast(const vtkMatrix4x4* m);

/// The camera of `ren`'s active vtkCamera for this viewport's aspect (VTK's view and projection
/// matrices), a white headlight along the direction of projection, and the viewport's size in
/// `options`. False for an empty viewport (`error` empty) and for matrices that are not a
/// camera's (`error` says why).
bool view_camera(vtkRenderer* ren, quadcast::render::Camera& camera, quadcast::render::Light& light,
                 quadcast::render::RenderOptions& options, std::string& error);

}  // namespace quadcast_paraview

#endif
