// src/scene/scene_render.cpp -- from a loaded scene to what the renderers draw
#include "quadcast/scene/scene_render.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>

#include "quadcast/image/image_io.hpp"
#include "quadcast/bilinear.hpp"
#include "quadcast/camera.hpp"
#include "quadcast/shapes.hpp"
#include "quadcast/render/environment.hpp"

namespace quadcast::render {

namespace {

using V3 = Vec3<double>;

glm::vec3 g(const V3& v) { return {static_cast<float>(v[0]), static_cast<float>(v[1]), static_cast<float>(v[2])}; }

shapes::Appearance look(const scene::Material& m) {
    return {g(m.color), static_cast<float>(m.specular), static_cast<float>(m.shininess)};
}

}  // namespace

Frame build_frame(const scene::Scene& s, int width, int height) {
    Frame fr;
    // Every shape is built by the public API (quadcast/shapes.hpp), which validates it.
    for (const auto& x : s.spheres) fr.primitives.push_back(shapes::sphere(g(x.center), static_cast<float>(x.radius), look(x.material)));
    for (const auto& x : s.ellipsoids) {
        glm::mat3 axes;
        for (int j = 0; j < 3; ++j) axes[j] = g(x.axes[static_cast<std::size_t>(j)]);
        fr.primitives.push_back(shapes::ellipsoid(g(x.center), axes, look(x.material)));
    }
    for (const auto& x : s.cylinders)
        fr.primitives.push_back(shapes::cylinder(g(x.p0), g(x.p1), static_cast<float>(x.radius), x.caps ? shapes::Ends::both : shapes::Ends::none, look(x.material)));
    for (const auto& x : s.cones) fr.primitives.push_back(shapes::cone(g(x.apex), g(x.base), static_cast<float>(x.radius), x.cap, look(x.material)));
    for (const auto& x : s.quadrics) {
        glm::mat4 q;
        for (int j = 0; j < 4; ++j)
            for (int i = 0; i < 4; ++i) q[j][i] = static_cast<float>(x.q[j][i]);
        if (x.bound == scene::Quadric::Bound::sphere) {
            fr.primitives.push_back(shapes::quadric(q, shapes::SphereBound{g(x.sphere.center), static_cast<float>(x.sphere.radius)}, look(x.material)));
        } else {
            shapes::TetrahedronBound t{};
            for (int i = 0; i < 4; ++i) t.corners[static_cast<std::size_t>(i)] = g(x.tetrahedron.p[static_cast<std::size_t>(i)]);
            fr.primitives.push_back(shapes::quadric(q, t, look(x.material)));
        }
    }
    std::size_t skipped = 0;
    for (const auto& x : s.quads) {
        const auto& p = x.p;
        const QuadKind kind = classify_quad(p[0], p[1], p[2], p[3]);
        if (kind == QuadKind::segment || kind == QuadKind::point || kind == QuadKind::non_finite) {
            ++skipped;
            continue;
        }
        fr.primitives.push_back(shapes::quad(g(p[0]), g(p[1]), g(p[2]), g(p[3]), look(x.material)));
    }
    if (skipped) fr.notes.push_back(std::to_string(skipped) + " degenerate quad(s) (segments, points, non-finite) are not drawn");

    const scene::Camera& c = s.camera;
    const double aspect = static_cast<double>(width) / static_cast<double>(height);
    fr.camera = camera_from_matrices(look_at(c.eye, c.target, c.up), c.projection == scene::Projection::orthographic
                                                                       ? orthographic(c.height, aspect, c.near, c.far)
                                                                       : perspective(c.fov_y_deg, aspect, c.near, c.far));
    if (!s.lights.empty()) {
        const scene::Light& l = s.lights.front();
        fr.light.direction = cast<float>(l.kind == scene::Light::Kind::directional ? l.direction : s.bounds().center() - l.position);
        fr.light.color = cast<float>(l.color * l.intensity);
        if (s.lights.size() > 1) fr.notes.push_back("only the first light is used");
    } else {
        fr.light.direction = vec3(-1.0f, -1.0f, -1.0f);
    }
    fr.options.width = width;
    fr.options.height = height;
    fr.options.culling = s.options.culling;
    fr.options.tight_bounds = s.options.tight_bounds;
    fr.options.background = cast<float>(s.options.background);
    fr.options.deferred = s.options.deferred;
    fr.options.silhouettes = s.options.silhouettes;
    fr.options.shadows = s.options.shadows;
    if (s.options.outline_depth) fr.options.silhouette[0] = static_cast<float>(*s.options.outline_depth);
    if (s.options.outline_crease) fr.options.silhouette[1] = static_cast<float>(*s.options.outline_crease);
    if (s.options.outline_strength) fr.options.silhouette[2] = static_cast<float>(*s.options.outline_strength);
    if (s.options.shadow_map_size) fr.options.shadow_map_size = *s.options.shadow_map_size;
    if (s.options.pcf_step) fr.options.pcf_step = *s.options.pcf_step;
    if (s.options.shadow_bias) fr.options.shadow_bias = static_cast<float>(*s.options.shadow_bias);
    if (s.options.environment == scene::Options::Environment::file) {
        const Image img = read_png(s.options.environment_file);
        fr.options.environment = std::make_shared<const EnvironmentMap>(
            environment_from_rgba8(img.width, img.height, img.rgba.data(), s.options.environment_file.string()));
    } else if (s.options.environment == scene::Options::Environment::procedural) {
        ProceduralSky sky;
        if (s.options.sky_zenith) sky.zenith = cast<float>(*s.options.sky_zenith);
        if (s.options.sky_horizon) sky.horizon = cast<float>(*s.options.sky_horizon);
        if (s.options.sky_ground) sky.ground = cast<float>(*s.options.sky_ground);
        fr.options.environment = std::make_shared<const EnvironmentMap>(procedural_environment(sky));
    }
    fr.options.reflectivity = static_cast<float>(s.options.reflectivity);
    return fr;
}

}  // namespace quadcast::render
