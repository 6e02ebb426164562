// quadcast/gl/mesh_renderer.hpp -- OpenGL 4.5 renderer of indexed triangle meshes, shaded like the quadric impostors
#pragma once
// Host-only. The counterpart of QuadricRenderer for tessellated geometry (the baseline the
// impostors are measured against, and marching-cubes output): same Camera / Light /
// RenderOptions / Image types, same offscreen framebuffer (RGBA8 colour, 32-bit float depth;
// window depth in [0, 1], 1 = background), same read-back (rows top first), and the same
// two-sided Blinn-Phong: the fragment stage calls the traced kernel `qc_shade_blinn_phong`
// (quadcast/generated/shaders.hpp) with the arguments the impostors' fragment stage gives it:
// the interpolated vertex normal, -light.direction, the direction towards the eye (eye - point;
// orthographic: the third row of the view rotation, -(ray direction)), the mesh colour, the light
// colour and options.material. The rest of the two stages is hand-written below: it is the
// fixed-function transform (P (V x)) and attribute interpolation, no traced formula.
//
// All meshes of a frame go into one vertex buffer (position, normal, mesh index; 28 bytes per
// vertex) and one index buffer (indices rebased to the shared vertex buffer), and are drawn with
// one glDrawElements; the mesh colours are a storage buffer indexed by the vertex's mesh index.
// No face culling (shading is two-sided, marching-cubes windings need not be consistent).

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "quadcast/generated/shaders.hpp"
#include "quadcast/gl/framebuffer.hpp"
#include "quadcast/gl/loader.hpp"
#include "quadcast/gl/program.hpp"
#include "quadcast/linalg.hpp"
#include "quadcast/render/types.hpp"

namespace quadcast::gl {

/// One indexed triangle mesh in world coordinates: triangle t is the vertices
/// indices[3t], indices[3t + 1], indices[3t + 2]; normals are per vertex (any non-zero length,
/// the shading normalises the interpolated normal; either orientation, the shading is two-sided);
/// one colour for the whole mesh.
struct Mesh {
    std::vector<Vec3<float>> positions;
    std::vector<Vec3<float>> normals;
    std::vector<std::uint32_t> indices;
    Vec3<float> color{{0.8f, 0.8f, 0.8f}};
};

/// Checks one mesh; throws std::invalid_argument "quadcast::gl::MeshRenderer: mesh <index>: ..."
/// naming the first problem: positions and normals of different counts, an index count that is
/// not a multiple of 3, an index out of range (with its triangle), a non-finite position, a
/// non-finite or zero normal, a non-finite colour.
inline void validate_mesh(const Mesh& m, std::size_t index) {
    const std::string where = "quadcast::gl::MeshRenderer: mesh " + std::to_string(index) + ": ";
    auto finite = [](const Vec3<float>& v) { return std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]); };
    if (m.positions.size() != m.normals.size())
        throw std::invalid_argument(where + std::to_string(m.positions.size()) + " positions but " + std::to_string(m.normals.size()) +
                                    " normals (one normal per vertex)");
    if (m.indices.size() % 3 != 0)
        throw std::invalid_argument(where + std::to_string(m.indices.size()) + " indices is not a multiple of 3 (triangles)");
    for (std::size_t i = 0; i < m.indices.size(); ++i)
        if (m.indices[i] >= m.positions.size())
            throw std::invalid_argument(where + "index " + std::to_string(i) + " (triangle " + std::to_string(i / 3) + ") is " +
                                        std::to_string(m.indices[i]) + ", but the mesh has " + std::to_string(m.positions.size()) +
                                        " vertices");
    for (std::size_t i = 0; i < m.positions.size(); ++i) {
        if (!finite(m.positions[i])) throw std::invalid_argument(where + "position " + std::to_string(i) + " is not finite");
        const Vec3<float>& n = m.normals[i];
        if (!finite(n)) throw std::invalid_argument(where + "normal " + std::to_string(i) + " is not finite");
        if (n[0] == 0.0f && n[1] == 0.0f && n[2] == 0.0f) throw std::invalid_argument(where + "normal " + std::to_string(i) + " is zero");
    }
    if (!finite(m.color)) throw std::invalid_argument(where + "colour is not finite");
}

namespace mesh_detail {

/// The vertex stage: world position through the view and projection matrices (two products, as
/// the impostors project their corners), world position and normal to the fragment stage, the
/// mesh colour fetched once per vertex.
inline constexpr const char* vertex_shader = R"glsl(#version 450 core
// quadcast/gl/mesh_renderer.hpp: mesh vertex stage (hand-written; no traced formula)
layout(location = 0) in vec3 qc_position;  // world
layout(location = 1) in vec3 qc_normal;    // world, any length
layout(location = 2) in uint qc_mesh;      // index into qc_mesh_colors
layout(std430, binding = 0) readonly buffer qc_MeshColors { vec4 qc_mesh_colors[]; };
uniform mat4 qc_view;
uniform mat4 qc_projection;
out vec3 qc_world;
out vec3 qc_n;
flat out vec3 qc_albedo;

void main()
{
    qc_world = qc_position;
    qc_n = qc_normal;
    qc_albedo = qc_mesh_colors[qc_mesh].rgb;
    gl_Position = qc_projection * (qc_view * vec4(qc_position, 1.0));
}
)glsl";

/// The fragment stage's declarations; the traced kernel and main() follow (fragment_shader()).
inline constexpr const char* fragment_head = R"glsl(#version 450 core
// quadcast/gl/mesh_renderer.hpp: mesh fragment stage; shading = the traced qc_shade_blinn_phong
in vec3 qc_world;
in vec3 qc_n;
flat in vec3 qc_albedo;
uniform vec3 qc_eye;          // world eye (perspective)
uniform vec3 qc_vz_row;       // third row of the world->view rotation (orthographic: towards the eye)
uniform int qc_ortho;
uniform vec3 qc_light_dir;    // towards the scene
uniform vec3 qc_light_color;
uniform vec4 qc_material;     // ambient, diffuse, specular, shininess
layout(location = 0) out vec4 qc_color;

)glsl";

inline constexpr const char* fragment_main = R"glsl(
void main()
{
    vec3 e = qc_ortho != 0 ? qc_vz_row : qc_eye - qc_world;
    vec3 rgb;
    qc_shade_blinn_phong(qc_n, -qc_light_dir, e, qc_albedo, qc_light_color, qc_material, rgb);
    qc_color = vec4(rgb, 1.0);
}
)glsl";

/// The fragment stage: declarations, the generated kernel, main().
inline std::string fragment_shader() {
    const std::string_view kernel = generated::find("qc_shade_blinn_phong");
    if (kernel.empty()) throw std::runtime_error("quadcast::gl::MeshRenderer: no generated kernel qc_shade_blinn_phong");
    return std::string(fragment_head) + std::string(kernel) + fragment_main;
}

/// One vertex of the shared vertex buffer.
struct Vertex {
    float position[3];
    float normal[3];
    std::uint32_t mesh;
};
static_assert(sizeof(Vertex) == 28);

}  // namespace mesh_detail

/// Renders triangle meshes into an offscreen framebuffer (RGBA8 colour, 32-bit float depth) of
/// the context current when its first GL object is made. GL objects are made on first use, so a
/// MeshRenderer whose meshes are rejected has made no GL call. Not thread-safe.
class MeshRenderer {
public:
    explicit MeshRenderer(const Api& api) : api_(&api) {}
    ~MeshRenderer() {
        release_fbo();
        if (vao_ == 0) return;
        const GLuint buffers[3] = {vertices_, indices_, colors_};
        api_->DeleteBuffers(3, buffers);
        api_->DeleteVertexArrays(1, &vao_);
        if (query_) api_->DeleteQueries(1, &query_);
    }
    MeshRenderer(const MeshRenderer&) = delete;
    MeshRenderer& operator=(const MeshRenderer&) = delete;

    /// Validates every mesh (`validate_mesh`; on error nothing is uploaded, no GL call is made and
    /// the previous meshes stay), then uploads them. Throws std::invalid_argument also when the
    /// meshes together exceed 2^32 - 1 vertices or 2^31 - 1 indices (one 32-bit index buffer,
    /// one draw).
    void set_meshes(const std::vector<Mesh>& meshes) {
        std::size_t n_vertices = 0, n_indices = 0;
        for (std::size_t i = 0; i < meshes.size(); ++i) {
            validate_mesh(meshes[i], i);
            n_vertices += meshes[i].positions.size();
            n_indices += meshes[i].indices.size();
        }
        if (n_vertices > std::numeric_limits<std::uint32_t>::max())
            throw std::invalid_argument("quadcast::gl::MeshRenderer: " + std::to_string(n_vertices) + " vertices in all meshes (at most 2^32 - 1)");
        if (n_indices > static_cast<std::size_t>(std::numeric_limits<GLsizei>::max()))
            throw std::invalid_argument("quadcast::gl::MeshRenderer: " + std::to_string(n_indices) + " indices in all meshes (at most 2^31 - 1)");
        if (meshes.size() > std::numeric_limits<std::uint32_t>::max())
            throw std::invalid_argument("quadcast::gl::MeshRenderer: too many meshes");
        std::vector<mesh_detail::Vertex> verts;
        std::vector<std::uint32_t> idx;
        std::vector<float> colors;
        verts.reserve(n_vertices);
        idx.reserve(n_indices);
        colors.reserve(4 * std::max<std::size_t>(1, meshes.size()));
        for (std::size_t i = 0; i < meshes.size(); ++i) {
            const Mesh& m = meshes[i];
            const auto base = static_cast<std::uint32_t>(verts.size());
            for (std::size_t v = 0; v < m.positions.size(); ++v) {
                mesh_detail::Vertex x{};
                std::memcpy(x.position, m.positions[v].c, sizeof x.position);
                std::memcpy(x.normal, m.normals[v].c, sizeof x.normal);
                x.mesh = static_cast<std::uint32_t>(i);
                verts.push_back(x);
            }
            for (std::uint32_t k : m.indices) idx.push_back(base + k);
            colors.insert(colors.end(), {m.color[0], m.color[1], m.color[2], 1.0f});
        }
        if (colors.empty()) colors.assign(4, 0.0f);
        const Api& gl = *api_;
        ensure_objects();
        gl.BindVertexArray(vao_);
        gl.BindBuffer(GL_ARRAY_BUFFER, vertices_);
        gl.BufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(std::max<std::size_t>(1, verts.size()) * sizeof(mesh_detail::Vertex)),
                      verts.empty() ? nullptr : verts.data(), GL_STATIC_DRAW);
        const auto stride = static_cast<GLsizei>(sizeof(mesh_detail::Vertex));
        gl.EnableVertexAttribArray(0);
        gl.VertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, stride, reinterpret_cast<const void*>(offsetof(mesh_detail::Vertex, position)));
        gl.EnableVertexAttribArray(1);
        gl.VertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, stride, reinterpret_cast<const void*>(offsetof(mesh_detail::Vertex, normal)));
        gl.EnableVertexAttribArray(2);
        gl.VertexAttribIPointer(2, 1, GL_UNSIGNED_INT, stride, reinterpret_cast<const void*>(offsetof(mesh_detail::Vertex, mesh)));
        gl.BindBuffer(GL_ELEMENT_ARRAY_BUFFER, indices_);
        gl.BufferData(GL_ELEMENT_ARRAY_BUFFER, static_cast<GLsizeiptr>(std::max<std::size_t>(1, idx.size()) * sizeof(std::uint32_t)),
                      idx.empty() ? nullptr : idx.data(), GL_STATIC_DRAW);
        gl.BindVertexArray(0);
        gl.BindBuffer(GL_ARRAY_BUFFER, 0);
        gl.BindBuffer(GL_SHADER_STORAGE_BUFFER, colors_);
        gl.BufferData(GL_SHADER_STORAGE_BUFFER, static_cast<GLsizeiptr>(colors.size() * sizeof(float)), colors.data(), GL_STATIC_DRAW);
        gl.BindBuffer(GL_SHADER_STORAGE_BUFFER, 0);
        check_errors(gl, "MeshRenderer::set_meshes");
        index_count_ = idx.size();
        vertex_count_ = verts.size();
        mesh_count_ = meshes.size();
    }

    /// Draws one frame into the offscreen framebuffer and waits for it (glFinish): clears to
    /// options.background and depth 1, draws every triangle with GL_LESS. Of the options only
    /// width, height, background and material apply (`culling` is per quadric, `deferred` gives
    /// the same image as forward shading); shadows and silhouettes are not drawn for meshes and
    /// throw std::invalid_argument.
    void draw(const render::Camera& cam, const render::Light& light, const render::RenderOptions& opt) {
        if (opt.shadows || opt.silhouettes)
            throw std::invalid_argument("quadcast::gl::MeshRenderer: shadows and silhouettes are not implemented for meshes");
        if (opt.width <= 0 || opt.height <= 0) throw std::invalid_argument("quadcast::gl::MeshRenderer: image size must be positive");
        const Api& gl = *api_;
        ensure_objects();
        ensure_fbo(opt.width, opt.height);
        if (!program_) program_ = std::make_unique<Program>(make_program(gl, "quadcast mesh renderer",
                                                                         {{GL_VERTEX_SHADER, mesh_detail::vertex_shader},
                                                                          {GL_FRAGMENT_SHADER, mesh_detail::fragment_shader()}}));
        gl.BindFramebuffer(GL_FRAMEBUFFER, fbo_);
        gl.Viewport(0, 0, opt.width, opt.height);
        const float bg[4] = {opt.background[0], opt.background[1], opt.background[2], 1.0f};
        const float one = 1.0f;
        gl.ClearBufferfv(GL_COLOR, 0, bg);
        gl.ClearBufferfv(GL_DEPTH, 0, &one);
        gl.Enable(GL_DEPTH_TEST);
        gl.DepthFunc(GL_LESS);
        gl.Disable(GL_CULL_FACE);
        gl.UseProgram(program_->id());
        set_uniforms(cam, light, opt);
        gl.BindVertexArray(vao_);
        gl.BindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, colors_);
        if (!query_) gl.GenQueries(1, &query_);
        gl.BeginQuery(GL_SAMPLES_PASSED, query_);
        if (index_count_ > 0) gl.DrawElements(GL_TRIANGLES, static_cast<GLsizei>(index_count_), GL_UNSIGNED_INT, nullptr);
        gl.EndQuery(GL_SAMPLES_PASSED);
        GLuint64 passed = 0;
        gl.GetQueryObjectui64v(query_, GL_QUERY_RESULT, &passed);
        samples_passed_ = static_cast<std::uint64_t>(passed);
        gl.BindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, 0);
        gl.BindVertexArray(0);
        gl.UseProgram(0);
        gl.Finish();
        check_errors(gl, "MeshRenderer::draw");
    }

    /// Reads back the last frame (rows top first, like the CPU renderer and QuadricRenderer).
    render::Image read() const {
        if (fbo_ == 0) throw std::logic_error("quadcast::gl::MeshRenderer::read: nothing drawn yet");
        return read_framebuffer(*api_, fbo_, width_, height_);
    }

    std::size_t mesh_count() const { return mesh_count_; }
    std::size_t vertex_count() const { return vertex_count_; }
    /// Triangles drawn per frame (all meshes).
    std::size_t triangle_count() const { return index_count_ / 3; }
    /// Samples that passed the depth test (GL_SAMPLES_PASSED) in the last `draw`.
    std::uint64_t samples_passed() const { return samples_passed_; }

private:
    void ensure_objects() {
        if (vao_ != 0) return;
        const Api& gl = *api_;
        gl.GenVertexArrays(1, &vao_);
        GLuint b[3] = {0, 0, 0};
        gl.GenBuffers(3, b);
        vertices_ = b[0];
        indices_ = b[1];
        colors_ = b[2];
    }

    void set_uniforms(const render::Camera& cam, const render::Light& light, const render::RenderOptions& opt) const {
        const Api& gl = *api_;
        const Program& p = *program_;
        float view[16], proj[16];
        for (int j = 0; j < 4; ++j)
            for (int i = 0; i < 4; ++i) { view[j * 4 + i] = cam.view[j][i]; proj[j * 4 + i] = cam.projection[j][i]; }
        const float vz_row[3] = {cam.view[0][2], cam.view[1][2], cam.view[2][2]};
        gl.UniformMatrix4fv(p.uniform_location("qc_view"), 1, GL_FALSE, view);
        gl.UniformMatrix4fv(p.uniform_location("qc_projection"), 1, GL_FALSE, proj);
        gl.Uniform3fv(p.uniform_location("qc_eye"), 1, cam.eye.c);
        gl.Uniform3fv(p.uniform_location("qc_vz_row"), 1, vz_row);
        gl.Uniform1i(p.uniform_location("qc_ortho"), cam.orthographic ? 1 : 0);
        gl.Uniform3fv(p.uniform_location("qc_light_dir"), 1, light.direction.c);
        gl.Uniform3fv(p.uniform_location("qc_light_color"), 1, light.color.c);
        gl.Uniform4fv(p.uniform_location("qc_material"), 1, opt.material.c);
    }

    void ensure_fbo(int w, int h) {
        if (fbo_ != 0 && w == width_ && h == height_) return;
        release_fbo();
        const Api& gl = *api_;
        width_ = w;
        height_ = h;
        fbo_ = make_framebuffer(gl, w, h, tex_, "quadcast::gl::MeshRenderer");
    }

    void release_fbo() {
        if (fbo_ == 0) return;
        api_->DeleteFramebuffers(1, &fbo_);
        api_->DeleteTextures(2, tex_);
        fbo_ = 0;
    }

    const Api* api_;
    GLuint vao_ = 0, vertices_ = 0, indices_ = 0, colors_ = 0, fbo_ = 0, tex_[2] = {0, 0};
    GLuint query_ = 0;
    std::unique_ptr<Program> program_;
    int width_ = 0, height_ = 0;
    std::size_t index_count_ = 0, vertex_count_ = 0, mesh_count_ = 0;
    std::uint64_t samples_passed_ = 0;
};

}  // namespace quadcast::gl
