// quadcast/render/window_ray.hpp -- a frame's pixel-ray terms and view-projection: the same floats for the GL stages and the CPU reference
#pragma once

// Host-only. The GL renderer passes these as uniforms and the CPU reference calls the same
// templates with them (`window_ray`, `primitive_rect`), so both cast the same rays and bound the
// same rectangles.

#include "quadcast/linalg.hpp"
#include "quadcast/render/light_camera.hpp"
#include "quadcast/render/types.hpp"

namespace quadcast::render {

/// The affine terms of `window_ray` for a camera and a width x height viewport (see there).
struct WindowRayTerms {
    Vec3<float> base, dx, dy, fixed;
};

/// `WindowRayTerms` in double, rounded to float: the view-space near-plane point of NDC (x, y) is
/// P^-1 (x, y, -1, 1) dehomogenised (affine in x, y for perspective and orthographic projections,
/// whose w depends on z only), so with x_ndc = 2 x_w / width - 1 the point at window position
/// (x_w, y_w) is p0 + x_w px + y_w py. Perspective: base, dx, dy = R^T p0, R^T px, R^T py (R the
/// view rotation), fixed = eye. Orthographic: base = eye + R^T (p0_x, p0_y, 0), dx, dy = R^T
/// (px_x, px_y, 0) ..., fixed = -(row 2 of R) in float (the viewing direction, as
/// `view_point_ray`). Throws std::invalid_argument for a singular projection.
inline WindowRayTerms window_ray_terms(const Camera& cam, int width, int height) {
    const Mat4<double> pinv = detail::inverse4(cast<double>(cam.projection));
    auto near_point = [&](double x, double y) {
        const Vec4<double> h = pinv * vec4(x, y, -1.0, 1.0);
        return vec3(h[0] / h[3], h[1] / h[3], h[2] / h[3]);
    };
    const Vec3<double> p0 = near_point(-1.0, -1.0);
    const Vec3<double> px = (near_point(1.0, -1.0) - p0) / double(width);
    const Vec3<double> py = (near_point(-1.0, 1.0) - p0) / double(height);
    const Mat3<double> rt = transpose(upper3(cast<double>(cam.view)));
    WindowRayTerms t;
    if (cam.orthographic) {
        auto flat = [](const Vec3<double>& v) { return vec3(v[0], v[1], 0.0); };
        t.base = cast<float>(cast<double>(cam.eye) + rt * flat(p0));
        t.dx = cast<float>(rt * flat(px));
        t.dy = cast<float>(rt * flat(py));
        const Mat3<float> rt_f = transpose(upper3(cam.view));
        t.fixed = -rt_f[2];
    } else {
        t.base = cast<float>(rt * p0);
        t.dx = cast<float>(rt * px);
        t.dy = cast<float>(rt * py);
        t.fixed = cam.eye;
    }
    return t;
}

/// projection * view in double, rounded to float (`primitive_rect`'s world -> clip matrix).
inline Mat4<float> view_projection(const Camera& cam) {
    return cast<float>(cast<double>(cam.projection) * cast<double>(cam.view));
}

/// The tight bound of a variant: the ellipsoid for ellipsoids, the hull of the slab sections for
/// (open) slabs, the projected tetrahedron of the clip planes for the planes variant, the
/// bounding sphere otherwise.
constexpr RectBound rect_bound(Variant v) {
    return v == Variant::ellipsoid                             ? RectBound::ellipsoid
           : (v == Variant::slab || v == Variant::open_slab) ? RectBound::slab
           : v == Variant::planes                              ? RectBound::tetrahedron
                                                               : RectBound::sphere;
}

}  // namespace quadcast::render
