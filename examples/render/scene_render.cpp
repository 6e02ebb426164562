// examples/render/scene_render.cpp -- from a loaded scene to what the renderers draw
#include "scene_render.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>

#include "image_io.hpp"
#include "quadcast/bilinear.hpp"
#include "quadcast/quadric.hpp"
#include "quadcast/ray.hpp"
#include "quadcast/render/environment.hpp"

namespace quadcast::render {

namespace {

using V3 = Vec3<double>;

Vec3<float> to_f(const V3& v) { return cast<float>(v); }

Primitive make(const Quadric<double>& q_local, const V3& center, double radius, Variant variant, const V3& color,
               const V3& axis = V3{{0.0, 0.0, 1.0}}, double half_length = std::numeric_limits<double>::infinity()) {
    Primitive p{};
    p.shape.q.q = cast<float>(q_local.q);
    p.shape.center = to_f(center);
    p.shape.radius = static_cast<float>(radius);
    p.shape.axis = to_f(axis);
    p.shape.half_length = static_cast<float>(half_length);
    p.variant = variant;
    p.color = to_f(color);
    return p;
}

Quadric<double> sphere_local(double r) {
    Quadric<double> q{identity<double, 4>()};
    q.q[3][3] = -r * r;
    return q;
}

/// A = M^-T M^-1 for the semi-axis matrix M = (u v w): x^T A x - 1 = 0.
Quadric<double> ellipsoid_local(const std::array<V3, 3>& axes) {
    Mat3<double> m{};
    for (int j = 0; j < 3; ++j) m[j] = axes[static_cast<std::size_t>(j)];
    double d = 0;
    const Mat3<double> n = inverse(m, d);
    if (!(std::fabs(d) > 0)) throw std::invalid_argument("ellipsoid with degenerate axes");
    const Mat3<double> a = transpose(n) * n;
    Quadric<double> q{zero_mat<double, 4, 4>()};
    for (int j = 0; j < 3; ++j) for (int i = 0; i < 3; ++i) q.q[j][i] = a[j][i];
    q.q[3][3] = -1.0;
    return q;
}

/// |x|^2 - (1 + k^2)(a.x)^2 + k^2 H (a.x) - k^2 H^2 / 4 with a from base to apex, origin at the
/// midpoint: the cone of slope k = r / H through the apex, f <= 0 inside.
Quadric<double> cone_local(const V3& a, double k2, double H) {
    Quadric<double> q{identity<double, 4>()};
    for (int j = 0; j < 3; ++j) for (int i = 0; i < 3; ++i) q.q[j][i] -= (1.0 + k2) * a[i] * a[j];
    for (int i = 0; i < 3; ++i) q.q[3][i] = q.q[i][3] = 0.5 * k2 * H * a[i];
    q.q[3][3] = -0.25 * k2 * H * H;
    return q;
}

/// Centre and radius of a sphere around the points (centroid, farthest point).
template <std::size_t N>
void bounding_sphere(const std::array<V3, N>& pts, V3& c, double& r) {
    c = V3{{0.0, 0.0, 0.0}};
    for (const V3& p : pts) c = c + p;
    c = c / static_cast<double>(N);
    r = 0;
    for (const V3& p : pts) r = std::max(r, length(p - c));
    r *= 1.0 + 1e-6;
}

/// A quadric given relative to `origin`, clipped to the tetrahedron of `corners`: stored relative
/// to the tetrahedron's bounding sphere with its inward face planes there, scaled as barycentric
/// coordinates (no normal slab: half_length = +Inf).
Primitive planes_primitive(const Quadric<double>& q_rel, const V3& origin, const std::array<V3, 4>& corners, const V3& color) {
    V3 c;
    double r;
    bounding_sphere(corners, c, r);
    const Quadric<double> local = translate_to_eye(q_rel, c - origin);
    Primitive p = make(local, c, r, Variant::planes, color);
    BoundingTet<double> t{};
    for (int i = 0; i < 4; ++i) t.p[i] = corners[static_cast<std::size_t>(i)] - c;
    const TetPlanes<double> pl = tet_planes(t);
    // Scale each face plane to the barycentric coordinate of its opposite corner (1 there).
    for (int i = 0; i < 4; ++i) p.shape.planes[i] = cast<float>(pl.plane[i] / dot(pl.plane[i], vec4(t.p[i], 1.0)));
    return p;
}

/// A quad: its quadric (given relative to `origin`; nullptr for a planar quad or a triangle,
/// which is its plane), clipped by its four edges extruded along the quad's normal n (each plane
/// scaled to 1 at the farthest corner) and by the slab |n.x| <= half-thickness (+2^-10 of its
/// size) that keeps the quadric's far sheet out (see `inside_planes`).
Primitive quad_primitive(const Quadric<double>* q_rel, const V3& origin, const std::array<V3, 4>& q, const V3& color) {
    V3 c;
    double r;
    bounding_sphere(q, c, r);
    // The normal of the largest corner triangle (robust for triangles with a repeated corner).
    V3 n{{0.0, 0.0, 0.0}};
    for (int i = 0; i < 4; ++i) {
        const V3 m = cross(q[static_cast<std::size_t>((i + 1) % 4)] - q[static_cast<std::size_t>(i)], q[static_cast<std::size_t>((i + 3) % 4)] - q[static_cast<std::size_t>(i)]);
        if (length(m) > length(n)) n = m;
    }
    n = n / length(n);
    Quadric<double> local{};
    if (q_rel) {
        local = translate_to_eye(*q_rel, c - origin);
    } else {
        local.q = zero_mat<double, 4, 4>();
        for (int i = 0; i < 3; ++i) local.q[3][i] = local.q[i][3] = 0.5 * n[i];
        local.q[3][3] = -dot(n, q[0] - c);
    }
    double thick = 0;
    for (const V3& corner : q) thick = std::max(thick, std::fabs(dot(n, corner - c)));
    Primitive p = make(local, c, r, Variant::planes, color, n, thick + r * 0x1.0p-10);
    for (int i = 0; i < 4; ++i) {
        const V3 a = q[static_cast<std::size_t>(i)] - c, b = q[static_cast<std::size_t>((i + 1) % 4)] - c;
        V3 e = cross(n, b - a);
        const double le = length(e);
        if (!(le > 0)) { p.shape.planes[i] = vec4(0.0f, 0.0f, 0.0f, 1.0f); continue; }  // repeated corner: no constraint
        // Scale to 1 at the farthest corner (a barycentric-like coordinate across the quad).
        const Vec4<double> pl = vec4(e / le, -dot(e / le, a));
        double far = 0;
        for (const V3& corner : q) far = std::max(far, dot(pl, vec4(corner - c, 1.0)));
        p.shape.planes[i] = cast<float>(far > 0 ? pl / far : pl);
    }
    return p;
}

}  // namespace

Mat4<double> look_at(const V3& eye, const V3& target, const V3& up) {
    const V3 f = normalize(target - eye);
    const V3 s = normalize(cross(f, up));
    const V3 u = cross(s, f);
    Mat4<double> m = identity<double, 4>();
    for (int j = 0; j < 3; ++j) { m[j][0] = s[j]; m[j][1] = u[j]; m[j][2] = -f[j]; }
    m[3][0] = -dot(s, eye);
    m[3][1] = -dot(u, eye);
    m[3][2] = dot(f, eye);
    return m;
}

Mat4<double> perspective(double fov_y_deg, double aspect, double n, double f) {
    const double t = 1.0 / std::tan(fov_y_deg * M_PI / 360.0);
    Mat4<double> p = zero_mat<double, 4, 4>();
    p[0][0] = t / aspect;
    p[1][1] = t;
    p[2][2] = -(f + n) / (f - n);
    p[2][3] = -1.0;
    p[3][2] = -2.0 * f * n / (f - n);
    return p;
}

Mat4<double> orthographic(double height, double aspect, double n, double f) {
    Mat4<double> p = identity<double, 4>();
    p[0][0] = 2.0 / (height * aspect);
    p[1][1] = 2.0 / height;
    p[2][2] = -2.0 / (f - n);
    p[3][2] = -(f + n) / (f - n);
    return p;
}

Frame build_frame(const scene::Scene& s, int width, int height) {
    Frame fr;
    // Spheres use the sphere-specialised variant (closed form, no quadric coefficients read per
    // fragment; the same image as the closed variant, faster: quadcast bench spheres --compare).
    for (const auto& x : s.spheres) fr.primitives.push_back(make(sphere_local(x.radius), x.center, x.radius, Variant::sphere, x.material.color));
    for (const auto& x : s.ellipsoids) {
        double r = 0;
        for (const V3& a : x.axes) r = std::max(r, length(a));
        fr.primitives.push_back(make(ellipsoid_local(x.axes), x.center, r, Variant::closed, x.material.color));
    }
    for (const auto& x : s.cylinders) {
        const V3 d = x.p1 - x.p0;
        const double h = 0.5 * length(d);
        const V3 a = d / (2.0 * h);
        Quadric<double> q{identity<double, 4>()};
        for (int j = 0; j < 3; ++j) for (int i = 0; i < 3; ++i) q.q[j][i] -= a[i] * a[j];
        q.q[3][3] = -x.radius * x.radius;
        fr.primitives.push_back(make(q, 0.5 * (x.p0 + x.p1), std::sqrt(x.radius * x.radius + h * h), Variant::slab, x.material.color, a, h));
    }
    for (const auto& x : s.cones) {
        const V3 d = x.apex - x.base;
        const double H = length(d);
        const V3 a = d / H;
        const double k2 = (x.radius / H) * (x.radius / H);
        fr.primitives.push_back(make(cone_local(a, k2, H), 0.5 * (x.apex + x.base), std::sqrt(x.radius * x.radius + 0.25 * H * H), Variant::slab,
                                     x.material.color, a, 0.5 * H));
    }
    for (const auto& x : s.quadrics) {
        if (x.bound == scene::Quadric::Bound::sphere) {
            const Quadric<double> local = translate_to_eye(Quadric<double>{x.q}, x.sphere.center);
            fr.primitives.push_back(make(local, x.sphere.center, x.sphere.radius, Variant::bounded, x.material.color));
        } else {
            fr.primitives.push_back(planes_primitive(Quadric<double>{x.q}, V3{{0.0, 0.0, 0.0}}, x.tetrahedron.p, x.material.color));
        }
    }
    std::size_t skipped = 0;
    for (const auto& x : s.quads) {
        const auto& p = x.p;
        const QuadConversion<double> conv = quad_to_quadric(p[0], p[1], p[2], p[3]);
        if (conv.ok()) {
            fr.primitives.push_back(quad_primitive(&conv.local.quadric, conv.local.origin, p, x.material.color));
        } else if (conv.kind == QuadKind::planar || conv.kind == QuadKind::triangle) {
            fr.primitives.push_back(quad_primitive(nullptr, V3{{0.0, 0.0, 0.0}}, p, x.material.color));
        } else {
            ++skipped;
        }
    }
    if (skipped) fr.notes.push_back(std::to_string(skipped) + " degenerate quad(s) (segments, points, non-finite) are not drawn");

    const scene::Camera& c = s.camera;
    const double aspect = static_cast<double>(width) / static_cast<double>(height);
    fr.camera.view = cast<float>(look_at(c.eye, c.target, c.up));
    fr.camera.orthographic = c.projection == scene::Projection::orthographic;
    fr.camera.projection = cast<float>(fr.camera.orthographic ? orthographic(c.height, aspect, c.near, c.far) : perspective(c.fov_y_deg, aspect, c.near, c.far));
    fr.camera.eye = cast<float>(c.eye);
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
        if (s.options.sky_zenith) sky.zenith = to_f(*s.options.sky_zenith);
        if (s.options.sky_horizon) sky.horizon = to_f(*s.options.sky_horizon);
        if (s.options.sky_ground) sky.ground = to_f(*s.options.sky_ground);
        fr.options.environment = std::make_shared<const EnvironmentMap>(procedural_environment(sky));
    }
    fr.options.reflectivity = static_cast<float>(s.options.reflectivity);
    return fr;
}

}  // namespace quadcast::render
