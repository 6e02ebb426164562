// quadcast/occlusion.hpp -- conservative occluders and the per-primitive occlusion test
#pragma once

// Traced (scalar or SIMD T). Occlusion culling of a frame (the GL renderer's cull pass): every
// closed convex primitive whose occluder ball (c, r_in) -- a ball inside the solid, see
// quadcast/render/occluder.hpp -- lies between the near and far planes writes, at each pixel whose
// centre ray crosses the ball's central disk perpendicular to the viewing axis, the view distance
// of that disk. With the eye outside the solid and all of it beyond the near plane
// (`occluder_usable`), the ray enters the solid before it reaches the disk and the fragment stage
// keeps that hit, so the primitive's own surface there is nearer than the value written: the
// occluder depth of a pixel is never nearer than what the pixel shows, whichever occluder wrote it
// last (so the writes need no atomics).
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

/// Window depth of the view distance `s` for the projection entries pz = (P22, P32, P23, P33).
/// Numerics: z = -s; ((P22 z + P32) / (P23 z + P33)) * 0.5 + 0.5.
template <class T>
T window_depth_of(const T& s, const Vec4<T>& pz) {
    const T z = -s;
    return ((pz[0] * z + pz[1]) / (pz[2] * z + pz[3])) * T(0.5) + T(0.5);
}

/// A view distance no nearer than the surface a depth buffer holds at window depth `w` (the
/// inverse of `window_depth_of`, from w + 2^-22, which outweighs the rounding of the inversion
/// for both camera models): z = (P32 - ndc P33) / (ndc P23 - P22) for ndc = 2 (w + 2^-22) - 1,
/// s = -z. Not usable (`far`: the background, or nothing nearer than the far plane) for
/// w + 2^-22 >= 1; the caller then leaves the pixel's value as it is.
/// Numerics: as written, one rounding per operation.
template <class T>
T distance_of_window_depth(const T& w, const Vec4<T>& pz, mask_t<T>& far) {
    const T wu = w + T(1.0 / 4194304.0);
    far = !(wu < T(1));
    const T ndc = wu * T(2) - T(1);
    return -((pz[1] - ndc * pz[3]) / (ndc * pz[2] - pz[0]));
}

/// The nearest view distance a primitive can show at: its bounding sphere's, s - radius, with
/// the radius grown by 2^-10 (validation accepts shapes reaching 1e-4 beyond their bounding radius).
/// Numerics: s - radius * (1 + 2^-10).
template <class T>
T nearest_distance(const T& s, const T& radius) {
    return s - radius * T(1.0 + 1.0 / 1024.0);
}

/// Whether an occluder may write its disk (view distance `s`, radius `r_in`, centre `c`):
/// - the whole primitive, its bounding sphere of radius `radius` (`nearest_distance`), lies beyond the near distance
///   (so the eye is outside it and the near plane cuts none of its surface: every pixel ray
///   through the disk meets the surface in front of the disk and the fragment stage keeps that
///   hit) and the disk before the far distance;
/// - the surface lies in front of the disk by gap * r_in at least along every pixel ray (`gap`:
///   quadcast::render::occlusion_range), and that is more than 2^-16 in window depth, far above
///   the rounding of the fragment stage's depths;
/// - r_in > 2^-12 (|c|_1 + |vz_t|): the rounding of view distances and projections, which grows
///   with the coordinates, stays far below the disk's margins.
/// Numerics: nearest_distance(s, radius) > near, s < far, window_depth_of(s) - window_depth_of(s - gap * r_in) > 2^-16,
/// r_in > (|c.x| + |c.y| + |c.z| + |vz_t|) * 2^-12.
template <class T>
mask_t<T> occluder_usable(const T& s, const T& r_in, const T& radius, const Vec3<T>& c, const T& vz_t, const T& near, const T& far, const T& gap,
                          const Vec4<T>& pz) {
    const T mag = ((abs(c[0]) + abs(c[1])) + abs(c[2])) + abs(vz_t);
    const mask_t<T> range = (nearest_distance(s, radius) > near) && (s < far);
    const mask_t<T> resolved = window_depth_of(s, pz) - window_depth_of(s - gap * r_in, pz) > T(1.0 / 65536.0);
    return (range && resolved) && (r_in > mag * T(1.0 / 4096.0));
}

/// The projection of an occluder's central disk (centre c, radius r_in, perpendicular to the
/// viewing axis): all of the disk lies at one view depth, where both camera models map view x and
/// y affinely and without rotation to NDC, so the disk projects exactly to the axis-aligned
/// ellipse around the projection of c whose semi-axes are the offsets of the projections of
/// c + r_in right and c + r_in up (`right` and `up`: the first two rows of the world -> view
/// rotation). The caller passes r_in with a margin (the ball's radius times 15/16): rounding
/// cannot carry a pixel centre out of the disk, and near its rim the surface still lies in front
/// of it by the `gap` of `occluder_usable`.
/// Also the ellipse's box [lo, hi] = centre -+ axes.
/// Numerics: clip = VP (p, 1) (left folds) for p = c, c + right r_in, c + up r_in; ndc = clip.xy / clip.w;
/// axes = |ndc(c + right r_in).x - ndc(c).x|, |ndc(c + up r_in).y - ndc(c).y|; lo, hi per component.
template <class T>
void occluder_ellipse(const Mat4<T>& view_projection, const Vec3<T>& c, const Vec3<T>& right, const Vec3<T>& up, const T& r_in,
                      Vec2<T>& centre, Vec2<T>& axes, Vec2<T>& lo, Vec2<T>& hi) {
    const Vec4<T> m = view_projection * vec4(c, T(1));
    const Vec4<T> a = view_projection * vec4(c + right * r_in, T(1)), b = view_projection * vec4(c + up * r_in, T(1));
    centre = vec2(m[0] / m[3], m[1] / m[3]);
    axes = vec2(abs(a[0] / a[3] - centre[0]), abs(b[1] / b[3] - centre[1]));
    lo = centre - axes;
    hi = centre + axes;
}

/// The number of disks of an occluder chain (quadcast::render::occluder_half_axis) of half axis
/// `half_axis` and disk radius `r_in`: 1 + ceil(2 |half_axis| / r_in), so that neighbouring
/// disks lie at most r_in apart, at most 64 (then farther apart: fewer pixels occluded, none
/// wrongly); 1 for a zero half axis.
/// Numerics: length, one division, ceil as -floor(-x), min.
template <class T>
T occluder_chain_count(const Vec3<T>& half_axis, const T& r_in) {
    const T l = length(half_axis);
    return min(T(1) - floor(-((l + l) / r_in)), T(64));  // ceil(x) = -floor(-x)
}

/// Disk k (0 <= k < n) of an occluder chain around centre c: its centre c + half_axis t_k with
/// t_k = 2 k / (n - 1) - 1 (t = 0 for n = 1), and the radius of a ball around it that holds the
/// primitive, radius + |half_axis| |t_k| (for `occluder_usable`: the primitive's bounding sphere
/// of radius `radius` around c lies in it).
/// Numerics: t = (k + k) / max(n - 1, 1) - 1, exact for n = 1; c + half_axis * t; the radius grown
/// by 2^-20 of itself against the rounding of the centre.
template <class T>
void occluder_chain_disk(const Vec3<T>& c, const Vec3<T>& half_axis, const T& radius, const T& k, const T& n, Vec3<T>& ck, T& radius_k) {
    const T t = select(n > T(1), (k + k) / max(n - T(1), T(1)) - T(1), T(0));
    ck = c + half_axis * t;
    radius_k = (radius + length(half_axis) * abs(t)) * T(1.0 + 1.0 / 1048576.0);
}

/// Corner k (0 <= k < 4, in the order -L-W, +L-W, +L+W, -L+W) of the occluder quadrilateral of a
/// record, drawn by the rasteriser into a depth buffer without a depth write of its own (so early
/// depth testing holds): its occluder ball (centre c = ball.xyz, radius r_in = ball.w) and chain
/// (bounding radius more.x, half axis more.yzw; `occluder_chain_disk`).
/// - A chain (half axis ha != 0): the rectangle c +- ha +- r_in u with u = cross(vz_row, ha) / |.|
///   (`right` where that is shorter than |ha| / 16: any u perpendicular to the viewing axis will do).
///   Each of its points c + t ha + s r_in u (|t|, |s| <= 1) lies on the disk perpendicular to the
///   viewing axis of radius r_in around c + t ha, an occluder of the chain's continuum, so the
///   rectangle's (planar) depth is never nearer than the surface in front of it.
/// - A single ball: the square c +- q right +- q up, q = r_in 0.7071 (inside the disk of radius r_in).
/// Usable when both end disks of the chain are (`occluder_usable`; every condition there is
/// weakest at an end: the nearest distance s_t - radius_t is concave in t, s_t linear, the
/// window-depth gap falls with s, |c_t|_1 is convex) and the half width |W| spans at least one
/// pixel at the far end (|W| p11 height / 2 >= w_clip there): the rasteriser's snapping of the
/// corners (1/256 pixel on llvmpipe) then stays far inside the margin r_in / 15 of the balls.
/// `range`: near, far, gap (quadcast::render::occlusion_range); p11: the projection's P11.
/// Numerics: the ends by `occluder_chain_disk` (k = 0, 1 of n = 2) and `view_distance`; u by
/// `cross` and `length`; corner c + L sl + W sw (sl, sw = -1 or 1); clip = VP (corner, 1), left folds;
/// w_clip(s) = P23 (-s) + P33.
template <class T>
void occluder_corner(const Mat4<T>& view_projection, const Vec3<T>& vz_row, const T& vz_t, const Vec3<T>& right, const Vec3<T>& up, const Vec4<T>& ball,
                     const Vec4<T>& more, const Vec3<T>& range, const Vec4<T>& pz, const T& p11, const T& height, const T& k, Vec4<T>& clip,
                     mask_t<T>& usable) {
    const Vec3<T> c = vec3(ball[0], ball[1], ball[2]), ha = vec3(more[1], more[2], more[3]);
    const T r_in = ball[3];
    Vec3<T> e0{}, e1{};
    T radius0{}, radius1{};
    occluder_chain_disk(c, ha, more[0], T(0), T(2), e0, radius0);
    occluder_chain_disk(c, ha, more[0], T(1), T(2), e1, radius1);
    const T s0 = view_distance(vz_row, vz_t, e0), s1 = view_distance(vz_row, vz_t, e1);
    const T l = length(ha);
    const mask_t<T> chain = l > T(0);
    const Vec3<T> u_raw = cross(vz_row, ha);
    const T lu = length(u_raw);
    const Vec3<T> u = select(lu > l * T(0.0625), u_raw / max(lu, T(1e-30)), right);
    const T q = r_in * T(0.7071);
    const Vec3<T> w = select(chain, u * r_in, right * q);
    const Vec3<T> a = select(chain, ha, up * q);
    const T half_width = select(chain, r_in, q);
    const T w_far = max(pz[2] * -s0 + pz[3], pz[2] * -s1 + pz[3]);
    const mask_t<T> wide = half_width * abs(p11) * (height * T(0.5)) >= w_far;
    usable = (occluder_usable(s0, r_in, radius0, e0, vz_t, range[0], range[1], range[2], pz) &&
              occluder_usable(s1, r_in, radius1, e1, vz_t, range[0], range[1], range[2], pz)) &&
             (wide && r_in > T(0));
    const T sl = select((k > T(0.5)) && (k < T(2.5)), T(1), T(-1));
    const T sw = select(k > T(1.5), T(1), T(-1));
    clip = view_projection * vec4((c + a * sl) + w * sw, T(1));
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

/// The texels of the level below that texel `t` of a max-depth pyramid level takes the largest
/// of: columns 2 t.x and min(2 t.x + 1, w - 1), rows likewise, as (x0, y0, x1, y1), where
/// `below` = (w, h) is the size of the level below. Each level halves the one below, rounding up,
/// so 2 t lies in it and an odd last column or row is read twice. Texel t of level l then holds
/// the largest depth over the pixels [2^l t, 2^l (t + 1) - 1] of level 0 (clamped to it).
/// Numerics: exact integers (below 2^24).
template <class T>
Vec4<T> pyramid_children(const Vec2<T>& t, const Vec2<T>& below) {
    const T x0 = T(2) * t[0], y0 = T(2) * t[1];
    return vec4(x0, y0, min(x0 + T(1), below[0] - T(1)), min(y0 + T(1), below[1] - T(1)));
}

}  // namespace quadcast
