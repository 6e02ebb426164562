// Tensor glyphs: N random symmetric positive-definite tensors drawn as ellipsoids, offscreen to a PNG.
#include <cstdlib>
#include <random>
#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include <quadcast/gl/osmesa_context.hpp>
#include <quadcast/gl/quadric_renderer.hpp>
#include <quadcast/render/cpu_renderer.hpp>
#include <quadcast/image/image_io.hpp>
#include <quadcast/shapes.hpp>

int main(int argc, char** argv) {
    const int n = argc > 1 ? std::atoi(argv[1]) : 2000;
    const std::string out = argc > 2 ? argv[2] : "glyphs.png";
    const bool cpu = argc > 3 && std::string(argv[3]) == "cpu";  // the CPU reference instead of OpenGL
    namespace qs = quadcast::shapes;
    std::mt19937 rng(1);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f), ev(0.3f, 1.0f);
    std::vector<quadcast::render::Primitive> glyphs;
    for (int i = 0; i < n; ++i) {
        // T = R diag(l) R^T with a random rotation R and eigenvalues l.
        const glm::vec3 axis = glm::normalize(glm::vec3(u(rng), u(rng), u(rng)) + glm::vec3(0.0f, 0.0f, 1.5f));
        const glm::mat3 r(glm::rotate(glm::mat4(1.0f), 3.14159f * u(rng), axis));
        const glm::mat3 t = r * glm::mat3(glm::vec3(ev(rng), 0, 0), glm::vec3(0, 0.5f * ev(rng), 0), glm::vec3(0, 0, 0.25f * ev(rng))) * glm::transpose(r);
        qs::Appearance look;
        look.color = qs::principal_direction_color(t);
        glyphs.push_back(qs::tensor_ellipsoid({u(rng), u(rng), 0.5f * u(rng)}, t, 0.08f, look));
    }
    quadcast::render::RenderOptions options;  // 1024 x 768
    options.shadows = true;
    const glm::mat4 view = glm::lookAt(glm::vec3(0.3f, -0.8f, 3.2f), glm::vec3(0.0f), glm::vec3(0.0f, 1.0f, 0.0f));
    const glm::mat4 proj = glm::perspective(glm::radians(45.0f), 1024.0f / 768.0f, 1.0f, 10.0f);
    const quadcast::render::Camera camera = qs::camera(view, proj);
    quadcast::render::Light light;  // directional, along (-1, -1, -1)
    quadcast::render::Image image;
    if (cpu) {
        image = quadcast::render::render_cpu(glyphs, camera, light, options);
    } else {
        quadcast::gl::OsmesaContext context;  // offscreen OpenGL 4.5 (Mesa)
        quadcast::gl::QuadricRenderer renderer(context.api());
        renderer.set_primitives(glyphs);
        renderer.draw(camera, light, options);
        image = renderer.read();
    }
    quadcast::render::write_png(out, image);
}
