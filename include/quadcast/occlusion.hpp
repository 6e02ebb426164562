// quadcast/occlusion.hpp -- conservative occluders and the per-primitive occlusion test
#pragma once

// Traced (scalar or SIMD T). Occlusion culling of a frame (the GL renderer's cull pass): every
// closed convex primitive whose occluder ball (c, r_in) -- a ball inside the solid, see
// quadcast/render/occluder.hpp -- lies between the near and far planes writes, at each pixel whose
// centre ray crosses the ball's central disk perpendicular to the viewing axis, the view distance
// of that disk. The ray enters the solid before it reaches the disk, so the primitive's own
// surface there is nearer than the value written: the occluder depth of a pixel is never nearer
// than what the pixel shows, whichever occluder wrote it last (so the writes need no atomics).
// A primitive whose nearest possible view distance (its bounding sphere's) lies beyond the
// farthest occluder depth over every pixel of its screen rectangle cannot show anywhere and need
// not be drawn; the picture does not change.

#include "quadcast/linalg.hpp"
#include "quadcast/scalar.hpp"

namespace quadcast {

/// View distance -(R x + t_z) of the world point `c` in front of the camera: `vz_row` is the
/// third row of the world -> view rotation R, `vz_t` the view matrix's z translation (positive
/// in front of the eye plane, along the viewing axis).
/// Numerics: -(dot(vz_row, c) + vz_t), dot a left fold.
template <class T>
T view_distance(const Vec3<T>& vz_row, const T& vz_t, const Vec3<T>& c) {
    return -(dot(vz_row, c) + vz_t);
}

/// Whether an occluder ball at view distance `s` with radius `r_in` may write its disk: the ball
/// lies strictly between the near and far distances (so the fragment stage keeps the surface in
/// front of the disk: nothing nearer than the near plane or beyond the far plane is drawn), and
/// is not so small against its distance (r_in > s 2^-14) that the surface's float depth could
/// reach the disk's.
/// Numerics: s - r_in > near, s + r_in < far, r_in > s * 2^-14.
template <class T>
mask_t<T> occluder_usable(const T& s, const T& r_in, const T& near, const T& far) {
    return ((s - r_in > near) && (s + r_in < far)) && (r_in > s * T(1.0 / 16384.0));
}

/// The nearest view distance a primitive can show at: its bounding sphere's, s - radius.
/// Numerics: one subtraction.
template <class T>
T nearest_distance(const T& s, const T& radius) {
    return s - radius;
}

/// The projection of an occluder's central disk (centre c, radius r_in, perpendicular to the
/// viewing axis): all of the disk lies at one view depth, where both camera models map view x and
/// y affinely and without rotation to NDC, so the disk projects exactly to the axis-aligned
/// ellipse around the projection of c whose semi-axes are the offsets of the projections of
/// c + r_in right and c + r_in up (`right` and `up`: the first two rows of the world -> view
/// rotation). The caller passes r_in with a margin (the ball's radius times 1 - 2^-10): rounding
/// cannot carry a pixel centre out of the disk, and near its rim the surface lies at least
/// 0.04 r_in in front of it.
/// Numerics: clip = VP (p, 1) (left folds) for p = c, c + right r_in, c + up r_in; ndc = clip.xy / clip.w;
/// axes = |ndc(c + right r_in).x - ndc(c).x|, |ndc(c + up r_in).y - ndc(c).y|.
template <class T>
void occluder_ellipse(const Mat4<T>& view_projection, const Vec3<T>& c, const Vec3<T>& right, const Vec3<T>& up, const T& r_in,
                      Vec2<T>& centre, Vec2<T>& axes) {
    const Vec4<T> m = view_projection * vec4(c, T(1));
    const Vec4<T> a = view_projection * vec4(c + right * r_in, T(1)), b = view_projection * vec4(c + up * r_in, T(1));
    centre = vec2(m[0] / m[3], m[1] / m[3]);
    axes = vec2(abs(a[0] / a[3] - centre[0]), abs(b[1] / b[3] - centre[1]));
}

/// Whether the centre `frag` (window coordinates) of a pixel of a viewport falls in the NDC
/// ellipse (centre, axes) of `occluder_ellipse`.
/// Numerics: ndc = frag * (2 / size) - 1 (exact scaling by a power of two for power-of-two sizes,
/// else one rounding); d = (ndc - centre) / axes per component; d.d <= 1.
template <class T>
mask_t<T> ellipse_covers(const Vec2<T>& frag, const Vec2<T>& viewport, const Vec2<T>& centre, const Vec2<T>& axes) {
    const T dx = ((frag[0] * (T(2) / viewport[0]) - T(1)) - centre[0]) / axes[0];
    const T dy = ((frag[1] * (T(2) / viewport[1]) - T(1)) - centre[1]) / axes[1];
    return dx * dx + dy * dy <= T(1);
}

/// The pixels (x0, y0, x1, y1), inclusive, whose centres x + 0.5 can fall in the NDC rectangle
/// [lo, hi] (a superset by at most one pixel on the low side), clamped to the viewport
/// [0, width - 1] x [0, height - 1]; empty (x0 > x1 or y0 > y1) when it misses the viewport.
/// Numerics: floor((v + 1) * (size * 0.5) - 0.5) per bound, exact integers after.
template <class T>
Vec4<T> pixel_span(const Vec2<T>& lo, const Vec2<T>& hi, const Vec2<T>& viewport) {
    Vec4<T> s{};
    for (int k = 0; k < 2; ++k) {
        const T half = viewport[k] * T(0.5);
        const T last = viewport[k] - T(1);
        s[k] = max(floor((lo[k] + T(1)) * half - T(0.5)), T(0));
        s[k + 2] = min(floor((hi[k] + T(1)) * half - T(0.5)), last);
    }
    return s;
}

}  // namespace quadcast
