// quadcast/spline/render.hpp -- the per-vertex and per-fragment numbers of the GPU isosurface renderer (traceable)
#pragma once

// Shared templates (traceable): no branches on T values, fixed trip counts, explicit association.
// The GL spline renderer draws the back faces of every relevant tetrahedron (of a QSS or S31
// cube) or of every active trilinear cell; nothing about the geometry is stored: the vertex stage
// takes a cube index and a vertex of the cell's implicit geometry (Kalbe & Zeilfelder 2008,
// Sect. 5.1-5.3). All positions are in the volume's INDEX space (sample (i,j,k) at (i,j,k),
// world = origin + spacing * index), as in the CPU reference renderer:
//
// - A spline cube c has centre c (an integer point) and cube-local coordinates u = (p - c) / s
//   with s = 1/2, so the cube is [-1,1]^3 (spec §1.1); a trilinear cell with lower corner c is
//   [0,1]^3 in w = (p - c) / s with s = 1.
// - The ray of a fragment is o + s v in cube-local coordinates, re-origined at the fragment's own
//   point on the drawn (back) face: o = the interpolated cube-local vertex position (|o| <= 1, so
//   the barycentric coordinates carry rounding errors ~eps, not ~eps times the eye's distance in
//   cubes), v = the interpolated direction (perspective: vertex - eye; orthographic: the viewing
//   direction). λ = w + s is the world ray parameter of the CPU renderer's pixel rays (origin in
//   the camera plane), w = the λ of the face point (perspective: 1, as v = vertex - eye;
//   orthographic: its distance from the camera plane), so `window_depth(λ, vz, pz)` applies, vz =
//   view-space z of the world direction.

#include <array>

#include "quadcast/bb/bezier.hpp"
#include "quadcast/bb/restrict.hpp"
#include "quadcast/linalg.hpp"
#include "quadcast/raycast.hpp"
#include "quadcast/scalar.hpp"
#include "quadcast/spline/partition.hpp"
#include "quadcast/spline/raycast.hpp"

namespace quadcast::spline {

/// What the vertex stage hands to the rasteriser for one vertex of a cell's implicit geometry.
template <class T>
struct CellVertex {
    Vec4<T> clip;  ///< clip-space position
    Vec3<T> o;     ///< cube-local ray origin: the vertex itself
    T w;           ///< the ray parameter λ of the vertex
    Vec3<T> v;     ///< cube-local ray direction
    Vec3<T> dir;   ///< world ray direction (the shading's eye vector is -dir)
    T vz;          ///< view-space z of the world ray direction
};

/// One vertex of the implicit bounding geometry of the cell with index-space anchor `c` (a cube
/// centre or a cell's lower corner; integers, so exact in float up to 2^24) at cube-local
/// offset `u` (entries 0, ±1: exact), s = the cell's half (spline) or full (trilinear) size:
/// index point p = c + s u (exact), world point x = origin + spacing ⊙ p, clip = view_proj (x, 1).
/// Shared vertices of neighbouring tetrahedra and cubes have the same p, hence bit-identical clip
/// positions (no cracks between the drawn faces).
/// o = u. Perspective (`ortho` false): v = (p - eye) / s, w = 1, dir = spacing ⊙ (p - eye).
/// Orthographic: v = forward / s with forward = the viewing direction in index space
/// (forward_world / spacing), w = -vz_row · (x - eye_world), the vertex's distance from the camera
/// plane; dir = forward_world. vz = vz_row · dir.
/// Numerics: 1/s is 2 or 1 (exact scaling); d = p - eye rounded once per component; dot products
/// are left folds; clip = view_proj * (x, 1) column by column.
template <class T>
CellVertex<T> cell_vertex(const Vec3<T>& c, const Vec3<T>& u, const T& s, const T& inv_s, const Vec3<T>& eye_index,
                          const Vec3<T>& eye_world, const Vec3<T>& forward_world, const Vec3<T>& origin, const Vec3<T>& spacing,
                          const Mat4<T>& view_proj, const Vec3<T>& vz_row, bool ortho) {
    const Vec3<T> p = c + u * s;
    const Vec3<T> x = origin + cmul(spacing, p);
    CellVertex<T> r{};
    r.clip = view_proj * vec4(x[0], x[1], x[2], T(1));
    r.o = u;
    if (!ortho) {
        const Vec3<T> d = p - eye_index;
        r.w = T(1);
        r.v = d * inv_s;
        r.dir = cmul(spacing, d);
    } else {
        Vec3<T> fwd_index{};
        for (int a = 0; a < 3; ++a) fwd_index[a] = forward_world[a] / spacing[a];
        r.v = fwd_index * inv_s;
        r.w = -dot(vz_row, x - eye_world);
        r.dir = forward_world;
    }
    r.vz = dot(vz_row, r.dir);
    return r;
}

/// Whether a convex element (a tetrahedron or a cell box) whose corners have the clip positions
/// c[0..7] (`cell_vertex`; a tetrahedron repeats a corner) lies wholly beyond one plane of the
/// clip volume -w <= x, y, z <= w, every corner beyond it by more than 2^-10 (|coordinate| + |w|).
/// In homogeneous coordinates, so it holds for corners behind the eye too: the element's points
/// are convex combinations of its corners in clip space as well. Then no pixel of the view sees
/// it, and no hit in it lies between the near and far planes (`depth_range_lambda`): the GPU
/// element list leaves it out (quadcast::gl::IsosurfaceRenderer).
/// Numerics: per plane and corner s c[i] - c.w > (|c[i]| + |c.w|) 2^-10 (s = -1, 1), each side
/// rounded once.
template <class T>
mask_t<T> clip_outside(const std::array<Vec4<T>, 8>& c) {
    mask_t<T> out = mask_t<T>(false);
    for (int i = 0; i < 3; ++i)
        for (int s = -1; s <= 1; s += 2) {
            mask_t<T> all = mask_t<T>(true);
            for (const Vec4<T>& k : c) {
                const T d = (s < 0 ? -k[i] : k[i]) - k[3];
                all = all && (d > (abs(k[i]) + abs(k[3])) * T(1.0 / 1024.0));
            }
            out = out || all;
        }
    return out;
}

/// The λ range of the visible depth range [0, 1] on a ray whose direction has view-space z `vz`
/// (< 0 in front of the camera) and whose origin lies in the camera plane: λ = z / vz for the
/// near and far planes' view z from the projection terms pz = (P22, P32, P23, P33), clamped to
/// λ >= 0. Numerics: z_near = -(P32 + P33) / (P22 + P23), z_far = (P33 - P32) / (P22 - P23).
template <class T>
Vec2<T> depth_range_lambda(const T& vz, const Vec4<T>& pz) {
    const T z_near = -(pz[1] + pz[3]) / (pz[0] + pz[2]);
    const T z_far = (pz[3] - pz[1]) / (pz[0] - pz[2]);
    return vec2(max(z_near / vz, T(0)), z_far / vz);
}

/// R^T x for a signed permutation R given as a matrix (entries 0, ±1): exact (products by ±1 and
/// 0, sums with zeros), the same values as `to_tet0_frame` up to the sign of zero.
template <class T>
Vec3<T> apply_transpose(const Mat3<T>& r, const Vec3<T>& x) {
    return vec3(dot(r[0], x), dot(r[1], x), dot(r[2], x));
}

/// The barycentric direction of a cube-local direction d' given in the frame of T_0 (the linear
/// part of `barycentric_tet0`): (-d'x, d'x + d'z, -(d'y + d'z)/2, (d'y - d'z)/2); Σ = 0.
template <class T>
Vec4<T> barycentric_tet0_direction(const Vec3<T>& dp) {
    return {{-dp[0], dp[0] + dp[2], T(-0.5) * (dp[1] + dp[2]), T(0.5) * (dp[1] - dp[2])}};
}

/// A fragment's cast: hit (between the near and far planes), window depth, world-space normal
/// (the unnormalised gradient of the reconstruction).
template <class T>
struct IsoFragment {
    mask_t<T> hit;
    T depth;
    Vec3<T> normal;
};

/// How far (in barycentric coordinates) the fragment stage grows each tetrahedron
/// (`clip_ray_to_tet`) or cell, so that no root near a shared face is lost between two elements
/// cast separately: the rasteriser decides which elements a pixel's ray gets fragments from on
/// vertex positions snapped to its sub-pixel grid (llvmpipe: 1/256 pixel), so a ray may pass
/// through an element that received no fragment for it, within 1/256 of a pixel's footprint of
/// that element. The pad is therefore `clip_pad_per_footprint` = 1/32 of the pixel's footprint in
/// cube-local units (perspective: the pixel's angle times the cube-local length of v, the ray from
/// the eye to the fragment; orthographic: the pixel's width times the cube-local length of the unit
/// view direction; barycentric coordinates change by at most 2 per cube-local unit: a factor 4 to
/// spare), and at least `min_clip_pad` = 2^-16 (some 500 times the rounding error of the
/// re-origined ray's barycentric coordinates). A root found in the grown part is the piece's
/// continuation less than 1/32 pixel beyond its face.
inline constexpr double min_clip_pad = 1.0 / 65536.0;
inline constexpr double clip_pad_per_footprint = 1.0 / 32.0;

/// The clip pad of a fragment (see `min_clip_pad`): pixel = a pixel's angle (perspective) or world
/// width (orthographic), 2 / (P11 height); v = the fragment's cube-local ray direction.
/// Numerics: max(2^-16, (pixel / 32) * |v|), |v| = sqrt(v.v).
template <class T>
T clip_pad(const T& pixel, const Vec3<T>& v) {
    return max(T(min_clip_pad), (T(clip_pad_per_footprint) * pixel) * length(v));
}

/// What the isosurface renderer's occlusion culling knows of an element (a tetrahedron of a spline
/// cube, or a trilinear cell; quadcast::gl::IsosurfaceRenderer): a lower bound `floor` of the window
/// depth of every hit its fragment stage can find there, and the NDC rectangle [lo, hi] of its
/// pixels, which holds when `visible` (every corner of the grown element in front of the eye
/// plane, clip w > 0). An element whose floor lies behind the depth already drawn over its
/// rectangle is not drawn; a fragment whose floor lies behind the depth drawn at its pixel is
/// discarded before it casts.
template <class T>
struct OcclusionBound {
    T floor;
    Vec2<T> lo, hi;
    mask_t<T> visible;
};

/// `OcclusionBound` of the convex element with the N corners c + s u_k (index space; u_k =
/// `corners`, entries 0, ±1) that the fragment stage clips to after growing it about its centroid
/// by the factor 1 + k pad (k = 4 for a tetrahedron: barycentric coordinates >= -pad; k = 2 for a
/// cell: [-pad, 1 + pad]^3); other arguments as `cell_vertex`. pad = `clip_pad` is largest where
/// |v| is, and |v| (the local ray direction, perspective: (p - eye) / s) is convex in p, so its
/// largest value over the element is at a corner. So both bounds take the corners scaled about
/// their centroid by g = 1 + k pad_max + 2^-12 (rounding of the element's coordinates). floor:
/// their view-space z (affine: the centroid's plus g times the offsets), the largest (nearest)
/// moved nearer by 2^-16 of (|z| + the offsets), its window depth (as `window_depth` computes it)
/// less 2^-20; perspective (pz[2] != 0): 0 (no bound) unless that z is in front of the eye (< 0).
/// Rectangle: the scaled corners through view_proj, x / w and y / w.
/// Numerics: p = c + u s, x = origin + spacing ⊙ p; z = vz_row · (spacing ⊙ (p - eye_index))
/// (perspective, as `cell_vertex`'s vz of dir) or vz_row · (x - eye_world) (orthographic, as its
/// w), left folds; |v| = sqrt(v · v) with v as in `cell_vertex`; centroids (sum of the N, left
/// fold) * 1/N; scaled corner = xc + g (x - xc); the rest as written.
template <std::size_t N, class T>
OcclusionBound<T> element_occlusion_bound(const Vec3<T>& c, const std::array<Vec3<T>, N>& corners, const T& s, const T& inv_s, const T& k_pad,
                                          const Vec3<T>& eye_index, const Vec3<T>& eye_world, const Vec3<T>& forward_world, const Vec3<T>& origin,
                                          const Vec3<T>& spacing, const Mat4<T>& view_proj, const Vec3<T>& vz_row, const Vec4<T>& pz, const T& pixel,
                                          bool ortho) {
    std::array<Vec3<T>, N> x{};
    std::array<T, N> z{};
    T vmax = T(0);
    for (std::size_t k = 0; k < N; ++k) {
        const Vec3<T> p = c + corners[k] * s;
        x[k] = origin + cmul(spacing, p);
        Vec3<T> v{};
        if (!ortho) {
            // as the fragment stage's z = λ vz: from the eye in index space, so that its rounding
            // scales with the distance from the eye, not with the coordinates' magnitude
            const Vec3<T> d = p - eye_index;
            z[k] = dot(vz_row, cmul(spacing, d));
            v = d * inv_s;
        } else {
            z[k] = dot(vz_row, x[k] - eye_world);
            for (int a = 0; a < 3; ++a) v[a] = (forward_world[a] / spacing[a]) * inv_s;
        }
        vmax = max(vmax, length(v));
    }
    const T pad = max(T(min_clip_pad), (T(clip_pad_per_footprint) * pixel) * vmax);
    const T g = (T(1) + k_pad * pad) + T(1.0 / 4096.0);
    const T inv_n = T(1.0 / double(N));
    // The floor
    T zsum = z[0];
    for (std::size_t k = 1; k < N; ++k) zsum = zsum + z[k];
    const T zc = zsum * inv_n;
    T off = (z[0] - zc) * g, extent = abs(z[0] - zc);
    for (std::size_t k = 1; k < N; ++k) {
        off = max(off, (z[k] - zc) * g);
        extent = max(extent, abs(z[k] - zc));
    }
    const T zn = zc + off;
    const T zf = zn + (abs(zn) + extent * g) * T(1.0 / 65536.0);
    const T depth = T(0.5) * ((pz[0] * zf + pz[1]) / (pz[2] * zf + pz[3])) + T(0.5) - T(1.0 / 1048576.0);
    OcclusionBound<T> b{};
    b.floor = select(pz[2] != T(0) && zf >= T(0), T(0), depth);
    // The rectangle
    Vec3<T> xsum = x[0];
    for (std::size_t k = 1; k < N; ++k) xsum = xsum + x[k];
    const Vec3<T> xc = xsum * inv_n;
    b.visible = mask_t<T>(true);
    for (std::size_t k = 0; k < N; ++k) {
        const Vec3<T> xg = xc + (x[k] - xc) * g;
        const Vec4<T> q = view_proj * vec4(xg[0], xg[1], xg[2], T(1));
        b.visible = b.visible && q[3] > T(0);
        const T inv_w = T(1) / select(q[3] > T(0), q[3], T(1));
        const Vec2<T> n = vec2(q[0] * inv_w, q[1] * inv_w);
        b.lo = k == 0 ? n : vec2(min(b.lo[0], n[0]), min(b.lo[1], n[1]));
        b.hi = k == 0 ? n : vec2(max(b.hi[0], n[0]), max(b.hi[1], n[1]));
    }
    return b;
}

/// `element_occlusion_bound` of tetrahedron t of the spline cube with centre `c` (s = 1/2, the
/// cube [-1, 1]^3 in its local coordinates); `corners` = the tetrahedron's cube-local vertices.
template <class T>
OcclusionBound<T> tet_occlusion_bound(const Vec3<T>& c, const std::array<Vec3<T>, 4>& corners, const Vec3<T>& eye_index, const Vec3<T>& eye_world,
                                      const Vec3<T>& forward_world, const Vec3<T>& origin, const Vec3<T>& spacing, const Mat4<T>& view_proj,
                                      const Vec3<T>& vz_row, const Vec4<T>& pz, const T& pixel, bool ortho) {
    return element_occlusion_bound<4>(c, corners, T(0.5), T(2), T(4), eye_index, eye_world, forward_world, origin, spacing, view_proj, vz_row, pz, pixel, ortho);
}

/// `element_occlusion_bound` of the trilinear cell with lower corner `c` (s = 1, the cell [0, 1]^3
/// in its local coordinates; corner k at (k & 1, k >> 1 & 1, k >> 2 & 1)).
template <class T>
OcclusionBound<T> cell_occlusion_bound(const Vec3<T>& c, const Vec3<T>& eye_index, const Vec3<T>& eye_world, const Vec3<T>& forward_world,
                                       const Vec3<T>& origin, const Vec3<T>& spacing, const Mat4<T>& view_proj, const Vec3<T>& vz_row, const Vec4<T>& pz,
                                       const T& pixel, bool ortho) {
    std::array<Vec3<T>, 8> corners{};
    for (std::size_t k = 0; k < 8; ++k) corners[k] = vec3(T(double(k & 1)), T(double(k >> 1 & 1)), T(double(k >> 2 & 1)));
    return element_occlusion_bound<8>(c, corners, T(1), T(1), T(2), eye_index, eye_world, forward_world, origin, spacing, view_proj, vz_row, pz, pixel, ortho);
}

/// The fragment stage of a spline tetrahedron (Kalbe & Zeilfelder 2008, Sect. 5.3): the ray
/// o + s v (cube-local, λ = w + s) is rotated into the frame of T_0 by R_t^T (`apply_transpose`,
/// exact), clipped to the tetrahedron grown by `clip_pad(pixel, v)` and to the visible λ range
/// (`depth_range_lambda`), the first root of the restricted BB-form minus ρ is found
/// (`intersect_piece`), the T_0-frame gradient is rotated back (R_t g') and scaled to world units
/// by grad_scale = (1/s) / spacing per axis.
/// Numerics: s range = λ range - w; depth = `window_depth(w + s, vz, pz)`; normal = grad_scale ⊙
/// (R_t g') (left folds).
template <int Q, class T>
IsoFragment<T> spline_fragment(const bb::BezierTet<T, Q>& c, const Mat3<T>& rot, const Vec3<T>& o, const T& w, const Vec3<T>& v,
                               const T& vz, const Vec4<T>& pz, const T& rho, const Vec3<T>& grad_scale, const T& pixel) {
    const Vec3<T> op = apply_transpose(rot, o), vp = apply_transpose(rot, v);
    const Vec2<T> range = depth_range_lambda(vz, pz);
    const T pad = clip_pad(pixel, v);
    const PieceHit<T> h = intersect_piece<Q>(c, barycentric_tet0(op), barycentric_tet0_direction(vp), range[0] - w, range[1] - w, rho,
                                             barycentric_directions<T>(0), &pad);
    IsoFragment<T> f{};
    f.depth = window_depth(w + h.s, vz, pz);
    f.hit = (h.hit && f.depth >= T(0)) && f.depth <= T(1);
    f.normal = cmul(grad_scale, rot * h.gradient);
    return f;
}

/// The part [s_in, s_out] of [s_min, s_max] where w0 + s d lies in the cell [-pad, 1 + pad]^3
/// (slab test; for d_a = 0 the ray must have -pad <= w0_a <= 1 + pad), and whether it is
/// non-empty. Numerics: per axis s = (-pad - w0_a) / d_a and ((1 + pad) - w0_a) / d_a, the
/// smaller bounds s_in, the larger bounds s_out (divisions guarded by select).
template <class T>
struct CellSegment {
    T s_in, s_out;
    mask_t<T> valid;
};

template <class T>
CellSegment<T> clip_ray_to_cell(const Vec3<T>& w0, const Vec3<T>& d, const T& s_min, const T& s_max, const T& pad) {
    T s_in = s_min, s_out = s_max;
    mask_t<T> ok = s_min <= s_max;
    const T lo = -pad, hi = T(1) + pad;
    for (int a = 0; a < 3; ++a) {
        const mask_t<T> nz = d[a] != T(0);
        const T inv = T(1) / select(nz, d[a], T(1));
        const T t0 = (lo - w0[a]) * inv, t1 = (hi - w0[a]) * inv;
        s_in = select(nz, max(s_in, min(t0, t1)), s_in);
        s_out = select(nz, min(s_out, max(t0, t1)), s_out);
        ok = ok && (nz || (w0[a] >= lo && w0[a] <= hi));
    }
    return {s_in, s_out, ok && s_in <= s_out};
}

/// The fragment stage of a trilinear cell: the ray o + s v (cell-local, re-origined on the drawn
/// face, λ = w + s) clipped to the cell grown by `clip_pad(pixel, v)` and to the visible λ range, the first hit of the trilinear
/// isosurface (`intersect_trilinear_cell`), gradient scaled to world units by grad_scale =
/// 1 / spacing. Numerics: as `spline_fragment`.
template <class T>
IsoFragment<T> trilinear_fragment(const CellCorners<T>& corners, const Vec3<T>& o, const T& w, const Vec3<T>& v, const T& vz,
                                  const Vec4<T>& pz, const T& rho, const Vec3<T>& grad_scale, const T& pixel) {
    const Vec2<T> range = depth_range_lambda(vz, pz);
    const CellSegment<T> seg = clip_ray_to_cell(o, v, range[0] - w, range[1] - w, clip_pad(pixel, v));
    const PieceHit<T> h = intersect_trilinear_cell(corners, o, v, seg.s_in, seg.s_out, rho);
    IsoFragment<T> f{};
    f.depth = window_depth(w + h.s, vz, pz);
    f.hit = ((seg.valid && h.hit) && f.depth >= T(0)) && f.depth <= T(1);
    f.normal = cmul(grad_scale, h.gradient);
    return f;
}

}  // namespace quadcast::spline
