// src/scene/scene_render.cpp -- from a loaded scene to what the renderers draw
#include "quadcast/scene/scene_render.hpp"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <limits>
#include <stdexcept>

#include "quadcast/image/image_io.hpp"
#include "quadcast/bilinear.hpp"
#include "quadcast/camera.hpp"
#include "quadcast/shapes.hpp"
#include "quadcast/render/environment.hpp"
#include "quadcast/scene/diagnostics.hpp"

namespace quadcast::render {

namespace {

using V3 = Vec3<double>;

glm::vec3 g(const V3& v) { return {static_cast<float>(v[0]), static_cast<float>(v[1]), static_cast<float>(v[2])}; }

shapes::Appearance look(const scene::Material& m) {
    return {g(m.color), static_cast<float>(m.specular), static_cast<float>(m.shininess)};
}

/// Q' = M^T Q M for the frame's x = scale x' + offset, normalised in double (shapes' own
/// normalisation); it stays double until shapes::quadric has moved it to its bound's centre.
glm::dmat4 frame_quadric(const Mat4<double>& q, const FrameTransform& t) {
    Mat4<double> m = zero_mat<double, 4, 4>();
    for (int i = 0; i < 3; ++i) {
        m[i][i] = t.scale;
        m[3][i] = t.offset[i];
    }
    m[3][3] = 1.0;
    const Quadric<double> r = shapes::detail::normalized("quadric", Quadric<double>{transpose(m) * q * m});
    glm::dmat4 out;
    for (int j = 0; j < 4; ++j)
        for (int i = 0; i < 4; ++i) out[j][i] = r.q[j][i];
    return out;
}

/// "file:line:column: pointer: " of the scene object that primitive i of a kind came from
/// (`field` selects the kind in Scene::Origin); empty when the scene records none.
std::string origin_of(const scene::Scene& s, std::size_t scene::Scene::Origin::*field, std::size_t i) {
    const auto it = std::upper_bound(s.origins.begin(), s.origins.end(), i,
                                     [field](std::size_t v, const scene::Scene::Origin& o) { return v < o.*field; });
    if (it == s.origins.begin()) return "";
    return scene::format_location(s.location(*std::prev(it)));
}

}  // namespace

FrameTransform frame_transform(const scene::Aabb& box) {
    FrameTransform t;
    if (box.empty()) return t;
    double h = 0.0, far = 0.0;
    for (int a = 0; a < 3; ++a) {
        h = std::max(h, 0.5 * box.hi[a] - 0.5 * box.lo[a]);  // (halves first: no overflow)
        far = std::max({far, std::fabs(box.lo[a]), std::fabs(box.hi[a])});
    }
    if (!(h > 0.0) || !std::isfinite(h)) return t;
    if (h >= 0x1p-16 && h <= 0x1p16 && far <= 0x1p10 * h) return t;
    int e = 0;
    const double mant = std::frexp(h, &e);  // h = mant 2^e, mant in [0.5, 1)
    t.scale = std::ldexp(1.0, mant < std::sqrt(0.5) ? e - 1 : e);
    const V3 c = box.center();
    t.offset = c;
    return t;
}

Frame build_frame(const scene::Scene& s, int width, int height) {
    Frame fr;
    const scene::Aabb bounds = s.bounds();
    const FrameTransform t = frame_transform(bounds);
    fr.transform = t;
    const auto P = [&](const V3& w) { return g(t.point(w)); };
    const auto L = [&](double l) { return static_cast<float>(t.length(l)); };
    using O = scene::Scene::Origin;
    // Every shape is built by the public API (quadcast/shapes.hpp), which validates it; its
    // error is prefixed with where the object is in the scene.
    const auto add = [&](std::size_t O::*field, std::size_t i, auto&& make) {
        try {
            fr.primitives.push_back(make());
        } catch (const std::invalid_argument& e) {
            throw std::invalid_argument(origin_of(s, field, i) + e.what());
        }
    };
    fr.primitives.reserve(s.spheres.size() + s.ellipsoids.size() + s.cylinders.size() + s.cones.size() + s.quadrics.size() + s.quads.size());
    for (std::size_t i = 0; i < s.spheres.size(); ++i) {
        const auto& x = s.spheres[i];
        add(&O::spheres, i, [&] { return shapes::sphere(P(x.center), L(x.radius), look(x.material)); });
    }
    for (std::size_t i = 0; i < s.ellipsoids.size(); ++i) {
        const auto& x = s.ellipsoids[i];
        add(&O::ellipsoids, i, [&] {
            glm::mat3 axes;
            for (int j = 0; j < 3; ++j) axes[j] = g(x.axes[static_cast<std::size_t>(j)] / t.scale);
            return shapes::ellipsoid(P(x.center), axes, look(x.material));
        });
    }
    for (std::size_t i = 0; i < s.cylinders.size(); ++i) {
        const auto& x = s.cylinders[i];
        add(&O::cylinders, i, [&] {
            return shapes::cylinder(P(x.p0), P(x.p1), L(x.radius), x.caps ? shapes::Ends::both : shapes::Ends::none, look(x.material));
        });
    }
    for (std::size_t i = 0; i < s.cones.size(); ++i) {
        const auto& x = s.cones[i];
        add(&O::cones, i, [&] { return shapes::cone(P(x.apex), P(x.base), L(x.radius), x.cap, look(x.material)); });
    }
    for (std::size_t i = 0; i < s.quadrics.size(); ++i) {
        const auto& x = s.quadrics[i];
        add(&O::quadrics, i, [&] {
            const glm::dmat4 q = frame_quadric(x.q, t);
            if (x.bound == scene::Quadric::Bound::sphere)
                return shapes::quadric(q, shapes::SphereBound{P(x.sphere.center), L(x.sphere.radius)}, look(x.material));
            shapes::TetrahedronBound tb{};
            for (std::size_t k = 0; k < 4; ++k) tb.corners[k] = P(x.tetrahedron.p[k]);
            return shapes::quadric(q, tb, look(x.material));
        });
    }
    for (std::size_t i = 0; i < s.slims.size(); ++i) {
        const scene::Slim& m = s.slims[i];
        for (std::size_t j = 0; j < m.balls.size(); ++j) {
            const scene::SlimBall& b = m.balls[j];
            try {
                Primitive p = shapes::quadric(frame_quadric(b.q, t), shapes::SphereBound{P(b.center), L(b.radius)}, look(m.material));
                // The clip planes a.x + d >= 0 in the frame (x = scale x' + offset: a.x' + (a.offset + d) / scale >= 0),
                // then local to the ball (x' = centre + u), in double; none: (0, 0, 0, 1).
                const auto local_plane = [&](bool has, const std::array<double, 4>& pl) {
                    if (!has) return vec4(0.0f, 0.0f, 0.0f, 1.0f);
                    const V3 a{{pl[0], pl[1], pl[2]}};
                    const double d_frame = (dot(a, t.offset) + pl[3]) / t.scale;
                    const V3 c = cast<double>(p.shape.center);
                    return vec4(float(a[0]), float(a[1]), float(a[2]), float(dot(a, c) + d_frame));
                };
                p.shape.planes[0] = local_plane(b.has_plane, b.plane);
                p.shape.planes[1] = local_plane(b.has_plane && b.has_plane2, b.plane2);
                fr.slim_balls.push_back(p);
            } catch (const std::invalid_argument& e) {
                throw std::invalid_argument(origin_of(s, &O::slims, i) + "ball " + std::to_string(j) + ": " + e.what());
            }
        }
    }
    std::size_t skipped = 0;
    for (std::size_t i = 0; i < s.quads.size(); ++i) {
        const auto& p = s.quads[i].p;
        const QuadKind kind = classify_quad(p[0], p[1], p[2], p[3]);
        if (kind == QuadKind::segment || kind == QuadKind::point || kind == QuadKind::non_finite) {
            ++skipped;
            continue;
        }
        add(&O::quads, i, [&] { return shapes::quad(P(p[0]), P(p[1]), P(p[2]), P(p[3]), look(s.quads[i].material)); });
    }
    if (skipped) fr.notes.push_back(std::to_string(skipped) + " degenerate quad(s) (segments, points, non-finite) are not drawn");

    // The camera in the frame: eye and target move with the scene, near, far and the
    // orthographic height scale with it, so the projection (and every window depth) is unchanged.
    fr.camera = frame_camera(s.camera, t, width, height);
    if (!s.lights.empty()) {
        const scene::Light& l = s.lights.front();
        // (a direction: normalised in double, so that a light 1e300 away stays finite in float)
        V3 d = l.kind == scene::Light::Kind::directional ? l.direction : t.point(bounds.center()) - t.point(l.position);
        double big = 0.0;
        for (int a = 0; a < 3; ++a) big = std::max(big, std::fabs(d[a]));
        if (big > 0.0 && std::isfinite(big)) d = d / big;
        fr.light.direction = cast<float>(d);
        fr.light.color = cast<float>(l.color * l.intensity);
        if (s.lights.size() > 1) fr.notes.push_back("only the first light is used");
    } else {
        fr.light.direction = vec3(-1.0f, -1.0f, -1.0f);
    }
    fr.options.width = width;
    fr.options.height = height;
    fr.options.culling = s.options.culling;
    if (fr.options.culling && std::any_of(s.quadrics.begin(), s.quadrics.end(), [](const scene::Quadric& q) { return q.two_sided; })) {
        fr.options.culling = false;
        fr.notes.push_back(isosurface_culling_note);
    }
    fr.options.tight_bounds = s.options.tight_bounds;
    fr.options.occlusion_culling = s.options.occlusion_culling;
    fr.options.occlusion_phases = s.options.occlusion_phases;
    fr.options.occlusion_min_overlap = s.options.occlusion_min_overlap;
    fr.options.occlusion_reuse = s.options.occlusion_reuse;
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
    fr.options.shadow_map_reuse = s.options.shadow_map_reuse;
    if (s.options.environment == scene::Options::Environment::file) {
        const Image img = s.options.environment_image ? *s.options.environment_image : read_png(s.options.environment_file);
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

Camera frame_camera(const scene::Camera& c, const FrameTransform& t, int width, int height) {
    const double aspect = static_cast<double>(width) / static_cast<double>(height);
    return camera_from_matrices(look_at(t.point(c.eye), t.point(c.target), c.up),
                                c.projection == scene::Projection::orthographic ? orthographic(t.length(c.height), aspect, t.length(c.near), t.length(c.far))
                                                                                : perspective(c.fov_y_deg, aspect, t.length(c.near), t.length(c.far)));
}

scene::Camera orbit_camera(const scene::Camera& c, double degrees) {
    // Rodrigues' rotation of eye - target about the unit up vector
    const double pi = 3.14159265358979323846;
    const double a = degrees * pi / 180.0, ca = std::cos(a), sa = std::sin(a);
    const V3 k = c.up / length(c.up), v = c.eye - c.target;
    scene::Camera out = c;
    out.eye = c.target + v * ca + cross(k, v) * sa + k * (dot(k, v) * (1.0 - ca));
    return out;
}

}  // namespace quadcast::render
