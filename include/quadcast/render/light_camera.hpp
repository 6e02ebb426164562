// quadcast/render/light_camera.hpp -- the shadow map's light camera, shared by the GL renderer and the CPU reference
#pragma once

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "quadcast/linalg.hpp"
#include "quadcast/quadric.hpp"
#include "quadcast/render/types.hpp"

namespace quadcast::render {

namespace detail {

/// `host_inverse` with the renderers' message.
inline Mat4<double> inverse4(const Mat4<double>& m) {
    try {
        return host_inverse(m);
    } catch (const std::invalid_argument& e) {
        throw std::invalid_argument(std::string("quadcast::render: projection matrix: ") + e.what());
    }
}

}  // namespace detail

/// An orthographic camera looking along light.direction that sees every primitive's bounding
/// sphere: the sphere around their bounding box (centre c, radius R) seen from c - 2 R dir, a
/// 2R x 2R window, near R, far 3R. A scene without primitives gets the unit sphere. The box
/// [lo, hi] of other geometry (volumes) is included; empty (lo > hi) by default.
/// Grows the box [lo, hi] by every primitive's bounding sphere (lo > hi: empty).
inline void grow_by_bounds(const std::vector<Primitive>& prims, Vec3<double>& lo, Vec3<double>& hi) {
    for (const Primitive& p : prims) {
        const double r = static_cast<double>(p.shape.radius);
        if (!std::isfinite(r)) continue;
        for (int i = 0; i < 3; ++i) {
            lo[i] = std::min(lo[i], static_cast<double>(p.shape.center[i]) - r);
            hi[i] = std::max(hi[i], static_cast<double>(p.shape.center[i]) + r);
        }
    }
}

inline Camera light_camera(const std::vector<Primitive>& prims, const Light& light,
                           Vec3<double> lo = {{1e300, 1e300, 1e300}}, Vec3<double> hi = {{-1e300, -1e300, -1e300}}) {
    grow_by_bounds(prims, lo, hi);
    Vec3<double> c{{0.0, 0.0, 0.0}};
    double R = 1.0;
    if (lo[0] <= hi[0]) {
        c = 0.5 * (lo + hi);
        R = std::max(1e-6, 0.5 * length(hi - lo));
    }
    Vec3<double> d = cast<double>(light.direction);
    d = length(d) > 0 ? normalize(d) : Vec3<double>{{0.0, 0.0, -1.0}};
    const Vec3<double> eye = c - (2.0 * R) * d;
    const Vec3<double> up0 = std::fabs(d[1]) < 0.9 ? Vec3<double>{{0.0, 1.0, 0.0}} : Vec3<double>{{1.0, 0.0, 0.0}};
    const Vec3<double> s = normalize(cross(d, up0)), u = cross(s, d);
    Mat4<double> view = identity<double, 4>();
    for (int j = 0; j < 3; ++j) { view[j][0] = s[j]; view[j][1] = u[j]; view[j][2] = -d[j]; }
    view[3][0] = -dot(s, eye);
    view[3][1] = -dot(u, eye);
    view[3][2] = dot(d, eye);
    const double n = R, f = 3.0 * R;
    Mat4<double> proj = identity<double, 4>();
    proj[0][0] = 1.0 / R;
    proj[1][1] = 1.0 / R;
    proj[2][2] = -2.0 / (f - n);
    proj[3][2] = -(f + n) / (f - n);
    Camera cam;
    cam.view = cast<float>(view);
    cam.projection = cast<float>(proj);
    cam.eye = cast<float>(eye);
    cam.orthographic = true;
    return cam;
}

/// M = P_light V_light (P_camera V_camera)^-1: the camera's NDC (homogeneous) to the light's clip
/// space (`shadow_coord`), in double, rounded to float.
inline Mat4<float> camera_to_light(const Camera& cam, const Camera& lc) {
    const Mat4<double> c = cast<double>(cam.projection) * cast<double>(cam.view);
    const Mat4<double> l = cast<double>(lc.projection) * cast<double>(lc.view);
    return cast<float>(l * detail::inverse4(c));
}

}  // namespace quadcast::render
