#include "vtkQuadcastGLContext.h"

#include <dlfcn.h>

#include <cmath>
#include <exception>
#include <stdexcept>

#include "vtkCamera.h"
#include "vtkMatrix4x4.h"
#include "vtkRenderer.h"

#include <quadcast/camera.hpp>

namespace quadcast_paraview {

namespace {

using GetProc = void* (*)(const char*);

/// The current context's getProcAddress: GLX, EGL or OSMesa, whichever has a current context
/// in this process.
GetProc current_context_resolver() {
    struct Pair {
        const char* current;
        const char* resolve;
    };
    for (const Pair& p : {Pair{"glXGetCurrentContext", "glXGetProcAddressARB"}, Pair{"eglGetCurrentContext", "eglGetProcAddress"},
                          Pair{"OSMesaGetCurrentContext", "OSMesaGetProcAddress"}}) {
        auto current = reinterpret_cast<void* (*)()>(dlsym(RTLD_DEFAULT, p.current));
        auto resolve = reinterpret_cast<GetProc>(dlsym(RTLD_DEFAULT, p.resolve));
        if (current && resolve && current() != nullptr) return resolve;
    }
    return nullptr;
}

}  // namespace

std::unique_ptr<quadcast::gl::Api> load_current_api() {
    const GetProc resolve = current_context_resolver();
    if (!resolve) throw std::runtime_error("no current GLX, EGL or OSMesa context");
    return std::make_unique<quadcast::gl::Api>(quadcast::gl::Api::load(resolve));
}

SavedState::SavedState(const quadcast::gl::Api& gl) : gl_(gl) {
    gl.GetIntegerv(GL_CURRENT_PROGRAM, &program_);
    gl.GetIntegerv(GL_VERTEX_ARRAY_BINDING, &vao_);
    gl.GetIntegerv(GL_ARRAY_BUFFER_BINDING, &array_buffer_);
    gl.GetIntegerv(GL_ELEMENT_ARRAY_BUFFER_BINDING, &element_buffer_);  // (of the bound vertex array)
    gl.GetIntegerv(GL_ACTIVE_TEXTURE, &active_texture_);
    gl.GetIntegerv(GL_DEPTH_FUNC, &depth_func_);
    gl.GetIntegerv(GL_CULL_FACE_MODE, &cull_face_);
    GLboolean b[4];
    gl.GetBooleanv(GL_DEPTH_WRITEMASK, b);
    depth_mask_ = b[0];
    gl.GetBooleanv(GL_COLOR_WRITEMASK, color_mask_);
    for (std::size_t i = 0; i < std::size(caps_); ++i) enabled_[i] = gl.IsEnabled(caps_[i]);
    gl.Enable(GL_DEPTH_TEST);
    gl.DepthMask(GL_TRUE);
    gl.DepthFunc(GL_LESS);
    gl.Disable(GL_BLEND);
    gl.Disable(GL_CULL_FACE);
    gl.Disable(GL_POLYGON_OFFSET_FILL);
    gl.Disable(GL_STENCIL_TEST);
}

SavedState::~SavedState() {
    const quadcast::gl::Api& gl = gl_;
    for (std::size_t i = 0; i < std::size(caps_); ++i) (enabled_[i] ? gl.Enable : gl.Disable)(caps_[i]);
    gl.ColorMask(color_mask_[0], color_mask_[1], color_mask_[2], color_mask_[3]);
    gl.DepthMask(depth_mask_);
    gl.DepthFunc(static_cast<GLenum>(depth_func_));
    gl.CullFace(static_cast<GLenum>(cull_face_));
    gl.ActiveTexture(static_cast<GLenum>(active_texture_));
    gl.BindVertexArray(static_cast<GLuint>(vao_));
    gl.BindBuffer(GL_ELEMENT_ARRAY_BUFFER, static_cast<GLuint>(element_buffer_));
    gl.BindBuffer(GL_ARRAY_BUFFER, static_cast<GLuint>(array_buffer_));
    gl.UseProgram(static_cast<GLuint>(program_));
    for (GLuint i = 0; i < 8; ++i) gl.BindBufferBase(GL_SHADER_STORAGE_BUFFER, i, 0);
}

quadcast::Mat4<double> to_quadcast(const vtkMatrix4x4* m) {
    quadcast::Mat4<double> r{};
    for (int row = 0; row < 4; ++row)
        for (int col = 0; col < 4; ++col) r[col][row] = m->GetElement(row, col);
    return r;
}

bool view_camera(vtkRenderer* ren, quadcast::render::Camera& camera, quadcast::render::Light& light,
                 quadcast::render::RenderOptions& options, std::string& error) {
    int width = 0, height = 0, x0 = 0, y0 = 0;
    ren->GetTiledSizeAndOrigin(&width, &height, &x0, &y0);
    error.clear();
    if (width <= 0 || height <= 0) return false;  // (nothing to draw: no error)
    vtkCamera* cam = ren->GetActiveCamera();
    try {
        camera = quadcast::camera_from_matrices(to_quadcast(cam->GetModelViewTransformMatrix()), to_quadcast(cam->GetProjectionTransformMatrix(static_cast<double>(width) / height, -1, 1)));
    } catch (const std::exception& e) {
        error = e.what();
        return false;
    }
    double dop[3];
    cam->GetDirectionOfProjection(dop);
    light.direction = quadcast::Vec3<float>{{static_cast<float>(dop[0]), static_cast<float>(dop[1]), static_cast<float>(dop[2])}};
    options.width = width;
    options.height = height;
    return true;
}

}  // namespace quadcast_paraview
