// quadcast/render/point_sprites.hpp -- whether a frame may draw its spheres as point sprites
#pragma once

// The GL renderer draws the sphere variant as one point sprite per sphere (`quadcast::point_sprite`:
// the square around the bounding quad's corners) instead of a quad of four vertices: llvmpipe runs
// the vertex stage on one thread, so a quarter of the vertices is most of the per-sphere cost. A
// point is clipped by its centre alone (GL, and llvmpipe does so), so a sprite whose centre leaves
// the view loses the part that reaches into it; a sprite is at most the implementation's largest
// point size; and the vertex stage's quad needs the eye outside the sphere (else it is the
// near-plane rectangle). `sphere_points_fit` decides per frame, conservatively, for all the spheres
// at once; where it does not hold, the frame draws quads.

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <vector>

#include "quadcast/linalg.hpp"
#include "quadcast/render/types.hpp"

namespace quadcast::render {

/// Whether every sphere whose centre lies in the box [lo, hi] and whose radius is at most `radius`
/// can be drawn as a point sprite in a width x height view of `cam` with sprites of at most
/// `max_size` pixels. Each sphere's bounding quad (`sphere_quad` or `ortho_sphere_square`, grown by
/// `rasterised_sphere_quad`, view-space centre c) lies in the ball of radius 1.5 (r + |c| 2^-15)
/// around its centre where the eye is at least 4 r from the centre (the quad's half size is
/// r L / sqrt(L^2 - r^2) <= 1.033 r, grown to at most 1.033 (1 + 1/128) r + |c| 2^-15, its corners
/// sqrt(2) times that away; orthographic: r for 1.033 r), so in the box grown by
/// rho = 1.5 (radius + max |c| 2^-15).
/// It holds where:
/// - perspective: every corner of the grown box lies beyond the near plane (view distance above
///   near (1 + 1e-3)) and 4 radius away from the eye plane at least (so is the eye from every centre);
/// - the corners' projections (the box is convex and in front of the eye, so its projection is
///   the hull of theirs) lie inside NDC [-1 + 1e-3, 1 - 1e-3] in x and y: every quad corner, so
///   every sprite centre, is inside the view;
/// - the largest sprite is at most max_size: a ball of radius rho at view distance s and lateral
///   offset |x| spans P00 2 rho (|x| + s) / (s^2 - rho^2) in NDC x (P11 and y alike; orthographic:
///   P00 2 rho), taken with the box's largest |x| + s over its smallest s^2 - rho^2, times half
///   the viewport, plus the sprite's 1/4 pixel.
/// In double. False for an empty box (lo > hi), a non-positive size or a degenerate projection.
inline bool sphere_points_fit(const Camera& cam, int width, int height, const Vec3<float>& lo, const Vec3<float>& hi, float radius, float max_size) {
    if (!(lo[0] <= hi[0] && lo[1] <= hi[1] && lo[2] <= hi[2]) || !(radius >= 0.0f) || width <= 0 || height <= 0 || !(max_size > 1.0f)) return false;
    const Mat4<double> view = cast<double>(cam.view), proj = cast<double>(cam.projection);
    double far_centre = 0.0;  // the largest view-space distance of a centre (the quad's |c| 2^-15 pad)
    for (int k = 0; k < 8; ++k) {
        const Vec4<double> v = view * Vec4<double>{{double(k & 1 ? hi[0] : lo[0]), double(k & 2 ? hi[1] : lo[1]), double(k & 4 ? hi[2] : lo[2]), 1.0}};
        far_centre = std::max(far_centre, std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]));
    }
    const double rho = 1.5 * (double(radius) + far_centre / 32768.0), margin = 1.0 - 1e-3;
    double near = 0.0;
    if (!cam.orthographic) {
        if (!(proj[2][3] == -1.0 && proj[3][3] == 0.0)) return false;
        near = proj[3][2] / (proj[2][2] - 1.0);
        if (!(near > 0.0) || !std::isfinite(near)) return false;
    }
    double sum_x = 0.0, sum_y = 0.0, s_min = std::numeric_limits<double>::infinity();
    for (int k = 0; k < 8; ++k) {
        const Vec4<double> w{{(k & 1 ? double(hi[0]) + rho : double(lo[0]) - rho), (k & 2 ? double(hi[1]) + rho : double(lo[1]) - rho),
                              (k & 4 ? double(hi[2]) + rho : double(lo[2]) - rho), 1.0}};
        const Vec4<double> v = view * w;
        const double s = -v[2];
        if (!cam.orthographic && !(s > near * (1.0 + 1e-3) && s >= 4.0 * double(radius))) return false;
        const Vec4<double> c = proj * v;
        if (!(c[3] > 0.0)) return false;
        const double nx = c[0] / c[3], ny = c[1] / c[3];
        if (!(std::fabs(nx) <= margin && std::fabs(ny) <= margin)) return false;
        sum_x = std::max(sum_x, std::fabs(v[0]) + s);
        sum_y = std::max(sum_y, std::fabs(v[1]) + s);
        s_min = std::min(s_min, s);
    }
    double ex = std::fabs(proj[0][0]) * 2.0 * rho, ey = std::fabs(proj[1][1]) * 2.0 * rho;
    if (!cam.orthographic) {
        const double d = s_min * s_min - rho * rho;
        if (!(d > 0.0)) return false;
        ex *= sum_x / d;
        ey *= sum_y / d;
    }
    const double size = std::max(ex * 0.5 * width, ey * 0.5 * height) + 0.25;
    return size <= double(max_size);
}

/// `sphere_points_fit` for each sphere (centre x, y, z, radius) on its own: all must fit. For
/// scenes whose box of centres does not fit while every sphere does (a molecule framed by the
/// camera: the box's corners lie outside the view); linear in the spheres, so the renderer runs it
/// on small sets only, once per camera.
inline bool each_sphere_points_fit(const Camera& cam, int width, int height, const std::vector<std::array<float, 4>>& spheres, float max_size) {
    for (const auto& s : spheres) {
        const Vec3<float> c{{s[0], s[1], s[2]}};
        if (!sphere_points_fit(cam, width, height, c, c, s[3], max_size)) return false;
    }
    return !spheres.empty();
}

}  // namespace quadcast::render
