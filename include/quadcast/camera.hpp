// quadcast/camera.hpp -- view and projection matrices (double) and the renderers' Camera
#pragma once

// Host-only. The matrices follow OpenGL (gluLookAt, gluPerspective, glOrtho): right-handed
// view space looking along -z, clip space z in [-w, w]. Both renderers take render::Camera:
// the matrices rounded to float plus the eye.

#include <cmath>
#include <stdexcept>
#include <string>

#include "quadcast/linalg.hpp"
#include "quadcast/quadric.hpp"
#include "quadcast/render/types.hpp"

namespace quadcast {

namespace camera_detail {
[[noreturn]] inline void fail(const char* fn, const std::string& what) {
    throw std::invalid_argument(std::string("quadcast::") + fn + ": " + what);
}
inline bool finite(const Vec3<double>& v) { return std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]); }
}  // namespace camera_detail

/// World -> view matrix of a camera at `eye` looking at `target` (right-handed, -z forward).
/// Throws std::invalid_argument when a point is not finite, eye == target, `up` is parallel
/// to the view direction, or the distance overflows.
inline Mat4<double> look_at(const Vec3<double>& eye, const Vec3<double>& target, const Vec3<double>& up) {
    using camera_detail::fail;
    if (!camera_detail::finite(eye) || !camera_detail::finite(target) || !camera_detail::finite(up)) fail("look_at", "eye, target and up must be finite");
    const Vec3<double> d = target - eye;
    const double l = length(d);
    if (!std::isfinite(l)) fail("look_at", "the distance from eye to target overflows");
    if (!(l > 0)) fail("look_at", "target equals eye");
    const Vec3<double> f = d / l;
    const double lu = length(up);
    if (!(lu > 0) || !std::isfinite(lu)) fail("look_at", "up must be nonzero and finite");
    const Vec3<double> side = cross(f, up / lu);
    if (!(length(side) > 1e-6)) fail("look_at", "up is parallel to the view direction");
    const Vec3<double> s = normalize(side);
    const Vec3<double> u = cross(s, f);
    Mat4<double> m = identity<double, 4>();
    for (int j = 0; j < 3; ++j) { m[j][0] = s[j]; m[j][1] = u[j]; m[j][2] = -f[j]; }
    m[3][0] = -dot(s, eye);
    m[3][1] = -dot(u, eye);
    m[3][2] = dot(f, eye);
    return m;
}

/// OpenGL perspective projection with vertical field of view fov_y (degrees, in (0, 180)).
inline Mat4<double> perspective(double fov_y_deg, double aspect, double n, double f) {
    using camera_detail::fail;
    if (!(fov_y_deg > 0 && fov_y_deg < 180)) fail("perspective", "fov_y must be in (0, 180) degrees");
    if (!(aspect > 0) || !std::isfinite(aspect)) fail("perspective", "aspect must be positive and finite");
    if (!(n > 0) || !(f > n) || !std::isfinite(f)) fail("perspective", "need 0 < near < far < inf");
    const double t = 1.0 / std::tan(fov_y_deg * M_PI / 360.0);
    Mat4<double> p = zero_mat<double, 4, 4>();
    p[0][0] = t / aspect;
    p[1][1] = t;
    p[2][2] = -(f + n) / (f - n);
    p[2][3] = -1.0;
    p[3][2] = -2.0 * f * n / (f - n);
    return p;
}

/// OpenGL orthographic projection of a view `height` high (and height * aspect wide).
inline Mat4<double> orthographic(double height, double aspect, double n, double f) {
    using camera_detail::fail;
    if (!(height > 0) || !std::isfinite(height)) fail("orthographic", "height must be positive and finite");
    if (!(aspect > 0) || !std::isfinite(aspect)) fail("orthographic", "aspect must be positive and finite");
    if (!(f > n) || !std::isfinite(f) || !std::isfinite(n)) fail("orthographic", "need near < far, both finite");
    Mat4<double> p = identity<double, 4>();
    p[0][0] = 2.0 / (height * aspect);
    p[1][1] = 2.0 / height;
    p[2][2] = -2.0 / (f - n);
    p[3][2] = -(f + n) / (f - n);
    return p;
}

/// The renderers' camera of a rigid view matrix (rotation + translation, checked to 1e-4) and an
/// OpenGL perspective (last row (0, 0, -1, 0)) or orthographic (last row (0, 0, 0, 1)) projection.
/// The eye is -R^T t. Throws std::invalid_argument when a matrix is not finite, not rigid, not
/// one of the two projection kinds, singular, or does not fit in float.
inline render::Camera camera_from_matrices(const Mat4<double>& view, const Mat4<double>& projection) {
    using camera_detail::fail;
    for (int j = 0; j < 4; ++j)
        for (int i = 0; i < 4; ++i)
            if (!std::isfinite(view[j][i]) || !std::isfinite(projection[j][i])) fail("camera", "a matrix entry is not finite");
    const Mat3<double> r = upper3(view);
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
            const double d = r[0][i] * r[0][j] + r[1][i] * r[1][j] + r[2][i] * r[2][j];
            if (std::fabs(d - (i == j ? 1.0 : 0.0)) > 1e-4) fail("camera", "the view matrix is not rigid (its 3x3 part is not a rotation)");
        }
    if (std::fabs(view[0][3]) + std::fabs(view[1][3]) + std::fabs(view[2][3]) + std::fabs(view[3][3] - 1.0) > 1e-9)
        fail("camera", "the view matrix has a projective last row");
    const bool ortho = projection[0][3] == 0 && projection[1][3] == 0 && projection[2][3] == 0 && projection[3][3] == 1;
    const bool persp = projection[0][3] == 0 && projection[1][3] == 0 && projection[2][3] == -1 && projection[3][3] == 0;
    if (!ortho && !persp) fail("camera", "the projection is neither perspective (last row 0 0 -1 0) nor orthographic (last row 0 0 0 1)");
    host_inverse(projection);  // throws when singular
    const Vec3<double> t = xyz(view[3]);
    const Vec3<double> eye = -(transpose(r) * t);
    render::Camera c;
    c.view = cast<float>(view);
    c.projection = cast<float>(projection);
    c.eye = cast<float>(eye);
    c.orthographic = ortho;
    for (int j = 0; j < 4; ++j)
        for (int i = 0; i < 4; ++i)
            if (!std::isfinite(c.view[j][i]) || !std::isfinite(c.projection[j][i])) fail("camera", "a matrix entry is outside the float range");
    if (!std::isfinite(c.eye[0]) || !std::isfinite(c.eye[1]) || !std::isfinite(c.eye[2])) fail("camera", "the eye is outside the float range");
    return c;
}

}  // namespace quadcast
