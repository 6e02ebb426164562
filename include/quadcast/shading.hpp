// quadcast/shading.hpp -- screen-space effects of the deferred pass: silhouette and crease outlines
#pragma once

#include "quadcast/linalg.hpp"
#include "quadcast/raycast.hpp"
#include "quadcast/scalar.hpp"

namespace quadcast {

/// View-space z of a window depth d (glDepthRange 0..1) for a projection with depth terms
/// pz = (P22, P32, P23, P33) (as `window_depth`): the inverse of z_ndc = (P22 z + P32) / (P23 z + P33).
/// Numerics: ndc = 2 d - 1; z = (P32 - P33 ndc) / (P23 ndc - P22). The denominator is nonzero for
/// d in [0, 1] with 0 < near < far (perspective and orthographic).
template <class T>
T view_z_from_depth(const T& d, const Vec4<T>& pz) {
    const T ndc = T(2) * d - T(1);
    return (pz[1] - pz[3] * ndc) / (pz[2] * ndc - pz[0]);
}

/// Silhouette and crease strength at the centre of a 3x3 pixel neighbourhood of the geometry
/// buffer (Sigg et al. 2006, sec. 4, "Silhouette and Crease Lines": a Sobel edge detector on
/// depth and on surface normals). depth[3 r + c] are window depths (1 = background), normal[...]
/// the unnormalised normals (zero for background), row r = 0 at the top, column c = 0 at the left.
/// params = (depth threshold, normal threshold, strength, unused).
/// - Silhouettes: the Sobel gradient of the linearised (view-space) depth, relative to the centre
///   pixel's |z|, so the threshold does not depend on the distance: s_d = |grad z| / |z_centre|.
/// - Creases: the Sobel gradient of the unit normals (per component), s_n = sqrt(|gx|^2 + |gy|^2).
/// Returns w = clamp(max(s_d / t_d, s_n / t_n) - 1, 0, 1): zero below the thresholds, saturated at
/// twice a threshold.
/// Numerics: Sobel sums as (a + 2 b) + c per column/row, differences of those; unit normals as
/// n / sqrt(n.n) (zero when n.n = 0); magnitudes as sqrt of left-folded sums of squares.
template <class T>
T silhouette_weight(const T (&depth)[9], const Vec3<T> (&normal)[9], const Vec4<T>& pz, const Vec4<T>& params) {
    T z[9];
    Vec3<T> n[9];
    for (int i = 0; i < 9; ++i) {
        z[i] = view_z_from_depth(depth[i], pz);
        const T l2 = dot(normal[i], normal[i]);
        const mask_t<T> ok = l2 > T(0);
        n[i] = select(ok, normal[i] / sqrt(select(ok, l2, T(1))), vec3(T(0), T(0), T(0)));
    }
    // Sobel: gx = right column - left column, gy = top row - bottom row, weights (1, 2, 1).
    auto sobel_x = [](const auto* a) { return ((a[2] + T(2) * a[5]) + a[8]) - ((a[0] + T(2) * a[3]) + a[6]); };
    auto sobel_y = [](const auto* a) { return ((a[0] + T(2) * a[1]) + a[2]) - ((a[6] + T(2) * a[7]) + a[8]); };
    const T zx = sobel_x(z), zy = sobel_y(z);
    const T zc = abs(z[4]);
    const T s_d = sqrt(zx * zx + zy * zy) / select(zc > T(0), zc, T(1));
    const Vec3<T> nx = sobel_x(n), ny = sobel_y(n);
    const T s_n = sqrt(dot(nx, nx) + dot(ny, ny));
    return clamp(max(s_d / params[0], s_n / params[1]) - T(1), T(0), T(1));
}

/// Blends the outline colour black over a shaded colour: rgb (1 - strength w) (Sigg et al. 2006,
/// sec. 4: "the gradient length ... is used to blend the outline color with the Phong lighting").
/// Numerics: k = 1 - strength * w, then rgb * k per component.
template <class T>
Vec3<T> apply_outline(const Vec3<T>& rgb, const T& w, const T& strength) {
    const T k = T(1) - strength * w;
    return rgb * k;
}


/// One step of a PCF count: `count` + 1 where shadow-map depth s does not occlude a receiver at
/// light-space window depth z (z - bias <= s), else `count`.
/// Numerics: zb = z - bias; a sum of 0/1 (exact).
template <class T>
T pcf_count_step(const T& count, const T& z, const T& bias, const T& s) {
    return count + select(z - bias <= s, T(1), T(0));
}

/// Percentage-closer filtering (Reeves, Salesin and Cook 1987, as used by Sigg et al. 2006, sec. 4,
/// "Soft Shadows"): the fraction of N shadow-map depths s[i] that do not occlude a receiver at
/// light-space window depth z, i.e. with z - bias <= s[i].
/// Numerics: the count is a left fold of `pcf_count_step` from 0 (exact, in any order); lit =
/// count / N (exact for N a power of two).
template <int N, class T>
T pcf_lit_fraction(const T& z, const T& bias, const T (&s)[N]) {
    T count = T(0);
    for (int i = 0; i < N; ++i) count = pcf_count_step(count, z, bias, s[i]);
    return count / T(N);
}

/// The 64-sample fraction from the first 8 samples' fraction `lit8` (`pcf_first8_from_count`) and the count
/// of the other 56 samples that are lit (`pcf_count_step` from 0): equal to
/// `pcf_lit_fraction<64>` of all 64, so a renderer can fetch the 56 one at a time (and stop
/// fetching where every pixel's first 8 agree).
/// Numerics: (lit8 * 8 + count56) / 64; every step exact.
template <class T>
T pcf_fraction64(const T& lit8, const T& count56) {
    return (lit8 * T(8) + count56) / T(64);
}

/// The first 8 of the 64 PCF samples (Sigg et al. 2006, sec. 4: "the first 8 samples are used to
/// adaptively determine whether the full 64 samples are required"): their lit fraction, and
/// `decided` when they agree (all lit or all shadowed), in which case the 64-sample filter is skipped.
template <class T>
struct PcfFirst {
    T lit;
    mask_t<T> decided;
};

/// The first 8 samples' lit fraction and whether they agree, from the count of those lit
/// (`pcf_count_step` over the 8 from 0), so a renderer can fetch them one at a time.
/// Numerics: lit = count8 / 8 (exact); decided = lit == 0 || lit == 1 (exact).
template <class T>
PcfFirst<T> pcf_first8_from_count(const T& count8) {
    const T lit = count8 / T(8);
    return {lit, lit == T(0) || lit == T(1)};
}

/// Soft-shadow visibility with the early-out: the 8-sample fraction where the first 8 samples agree,
/// else the 64-sample fraction (s[0..7] are the first 8). A renderer may skip fetching s[8..63] when
/// the first 8 are decided; the result is the same.
/// Numerics: the GPU's composition: the first 8 counted by `pcf_count_step` from 0,
/// `pcf_first8_from_count`, the other 56 counted from 0, `pcf_fraction64`; equal to
/// `pcf_lit_fraction<64>` of all 64 (exact).
template <class T>
T pcf_soft_shadow(const T& z, const T& bias, const T (&s)[64]) {
    T count8 = T(0), count56 = T(0);
    for (int i = 0; i < 8; ++i) count8 = pcf_count_step(count8, z, bias, s[i]);
    for (int i = 8; i < 64; ++i) count56 = pcf_count_step(count56, z, bias, s[i]);
    const PcfFirst<T> f = pcf_first8_from_count(count8);
    return select(f.decided, f.lit, pcf_fraction64(f.lit, count56));
}

/// Texel offsets of the 64 PCF samples: an 8x8 grid of offsets -7, -5, ..., 7 (in half texels of
/// the grid step), ordered so that the first 8 spread over the whole footprint (corners, then edge
/// midpoints). Data: the stages index it by sample and pass the cell to `pcf_sample_texel`.
inline constexpr int pcf_grid_order[64] = {
    0, 7, 56, 63, 3, 24, 39, 60,   // first 8: corners and edge samples
    1, 2, 4, 5, 6, 8, 9, 10, 11, 12, 13, 14, 15, 16, 17, 18, 19, 20, 21, 22, 23, 25, 26, 27, 28,
    29, 30, 31, 32, 33, 34, 35, 36, 37, 38, 40, 41, 42, 43, 44, 45, 46, 47, 48, 49, 50, 51, 52, 53,
    54, 55, 57, 58, 59, 61, 62};

/// A texel index clamped to [0, last]: the index itself inside, 0 below (and for NaN), `last`
/// above. Indices are integers held in float (exact below 2^24).
/// Numerics: select(i >= 0, min(i, last), 0) (exact).
template <class T>
T clamp_texel(const T& i, const T& last) {
    return select(i >= T(0), min(i, last), T(0));
}

/// The texel of PCF sample grid cell g (pcf_grid_order[k], 0..63) around the shadow-map position
/// `texel` (`shadow_coord`), for a grid step of `step` texels, clamped to [0, last] (last = map
/// size - 1): floor(texel) + (g mod 8, g div 8) step - floor(7 step / 2), so a step of 2 gives
/// offsets -7, -5, ..., 7. A NaN or huge position gives a texel of the map's border.
/// Numerics: gy = floor(g * 0.125), gx = g - 8 gy; every term an integer
/// below 2^24 in float (exact); `clamp_texel` per component.
template <class T>
Vec2<T> pcf_sample_texel(const Vec2<T>& texel, const T& g, const T& step, const T& last) {
    // (products with 1/8 and 1/2, exact by construction; GLSL's `/` need not be)
    const T gy = floor(g * T(0.125));
    const T gx = g - T(8) * gy;
    const T centre = floor(T(7) * step * T(0.5));
    return vec2(clamp_texel(floor(texel[0]) + gx * step - centre, last), clamp_texel(floor(texel[1]) + gy * step - centre, last));
}

/// An integer x split by a step of `step`: (q, r) with x = q step + r and 0 <= r < step, from
/// `inv_step` = 1 / step (rounded: the quotient may be one off, and is corrected).
/// Numerics: exact for integers |x| < 2^22 and 1 <= step < 2^22 held in float: q0 = floor(x inv_step)
/// is within one of the quotient; the corrections are exact integer arithmetic.
template <class T>
Vec2<T> split_by_step(const T& x, const T& step, const T& inv_step) {
    const T q0 = floor(x * inv_step);
    const T r0 = x - q0 * step;
    const T q = select(r0 < T(0), q0 - T(1), select(r0 >= step, q0 + T(1), q0));
    return vec2(q, x - q * step);
}

/// Margin, in texels, on each side of a tile of the shadow map in phases (`phase_source_texel`).
inline constexpr int pcf_phase_margin = 8;

/// Texels per side of a tile of the shadow map in phases (`phase_source_texel`) for a map of
/// `map_size` texels per side and a PCF step of `step` texels: ceil(map_size / step) + 2 margins.
constexpr int pcf_phase_tile(int map_size, int step) { return (map_size + step - 1) / step + 2 * pcf_phase_margin; }

/// The shadow map in phases of the PCF step, so that a receiver's 64 PCF samples, `step` texels
/// apart in the map, are 8 x 8 consecutive texels there and a renderer can read them four at a
/// time (textureGather; `pcf_phase`, `pcf_gather_coord`). Per axis the image is `step` tiles of
/// `tile` = ceil(map size / step) + 2 `pcf_phase_margin` texels; texel X = r tile + i of it holds
/// map texel (i - margin) step + r, clamped to the map as `pcf_sample_texel` clamps (the
/// margins hold the clamped samples of footprints that reach past the map's edges). This is
/// that map texel of X (per axis), given `inv_tile` = 1 / tile and the map's last texel `last`.
/// Numerics: `split_by_step` of X by the tile, then exact integers and `clamp_texel`.
template <class T>
T phase_source_texel(const T& x, const T& step, const T& tile, const T& inv_tile, const T& last) {
    const Vec2<T> ri = split_by_step(x, tile, inv_tile);
    return clamp_texel((ri[1] - T(pcf_phase_margin)) * step + ri[0], last);
}

/// The texel of the shadow map in phases (`phase_source_texel`) that holds the first PCF sample
/// around shadow-map position `texel` (`shadow_coord`), for a grid step of `step` texels
/// (`inv_step` = 1 / step), a map of last texel `last` and tiles of `tile` texels: sample (gx, gy)
/// (grid cell 8 gy + gx of `pcf_sample_texel`) is then at cell + (gx, gy), for every position.
/// Numerics: per axis o = floor(texel) - floor(7 step / 2), the first sample's texel as in
/// `pcf_sample_texel`, limited to [-7 step, last] (a NaN gives -7 step): beyond those bounds every
/// sample clamps to the same texel as at them; (q, r) = `split_by_step` of o; r tile + q + margin.
/// Exact integers.
template <class T>
Vec2<T> pcf_phase(const Vec2<T>& texel, const T& step, const T& inv_step, const T& last, const T& tile) {
    const T centre = floor(T(7) * step * T(0.5));
    const T low = -(T(7) * step);
    const auto axis = [&](const T& p) {
        const T o = floor(p) - centre;
        const Vec2<T> qr = split_by_step(select(o >= low, min(o, last), low), step, inv_step);
        return qr[1] * tile + qr[0] + T(pcf_phase_margin);
    };
    return vec2(axis(texel[0]), axis(texel[1]));
}

/// The normalised coordinate at which textureGather reads the 2 x 2 texels (cell + (gx, gy)) ..
/// (cell + (gx + 1, gy + 1)) of the map in phases, `inv_size` = 1 / its texels per side: their shared
/// corner, (cell + (gx, gy) + 1) inv_size (a gather reads the texels floor(u size - 0.5) and the
/// next, and u size is within far less than 0.5 of the corner).
/// Numerics: exact integer sums, one rounded product per component.
template <class T>
Vec2<T> pcf_gather_coord(const Vec2<T>& cell, const T& gx, const T& gy, const T& inv_size) {
    return vec2((cell[0] + gx + T(1)) * inv_size, (cell[1] + gy + T(1)) * inv_size);
}

/// The 64-sample lit fraction from the count of all 64 samples that are lit: equal to
/// `pcf_fraction64` of the first 8's fraction and the other 56's count.
/// Numerics: count64 / 64 (exact).
template <class T>
T pcf_fraction_of64(const T& count64) {
    return count64 / T(64);
}

/// The texel at offset (dx, dy) from the pixel at window position `frag` (a pixel centre, i + 0.5),
/// clamped to the image [0, last.x] x [0, last.y]: the 3x3 neighbourhood of the silhouette pass.
/// Numerics: floor(frag) + d (exact integers), `clamp_texel` per component.
template <class T>
Vec2<T> neighbour_texel(const Vec2<T>& frag, const T& dx, const T& dy, const Vec2<T>& last) {
    return vec2(clamp_texel(floor(frag[0]) + dx, last[0]), clamp_texel(floor(frag[1]) + dy, last[1]));
}

/// The geometry buffer's normal target (unnormalised normal, window depth) where nothing is drawn:
/// a zero normal at the far plane. Its nine texels give `silhouette_weight` zero.
template <class T>
Vec4<T> cleared_gnormal() {
    return vec4(T(0), T(0), T(0), T(1));
}

/// Whether a texel of the geometry buffer's normal target holds `cleared_gnormal` (-0 counts as 0).
/// Numerics: four comparisons.
template <class T>
mask_t<T> is_cleared_gnormal(const Vec4<T>& g) {
    return ((g[0] == T(0) && g[1] == T(0)) && g[2] == T(0)) && g[3] == T(1);
}

/// Outline tiles of the deferred background pass: the pixels (x0, y0, x1, y1), inclusive, whose
/// texels the outline of a pixel in tile `tile` (the 8 x 8 pixels from 8 tile) reads -- its
/// 3 x 3 neighbourhood (`neighbour_texel`) -- so the tile grown by one pixel, clamped to the
/// viewport. Where all of them hold `cleared_gnormal`, the tile's outlines are zero.
/// Numerics: exact integers.
template <class T>
Vec4<T> outline_tile_reach(const Vec2<T>& tile, const Vec2<T>& viewport) {
    return vec4(max(T(8) * tile[0] - T(1), T(0)), max(T(8) * tile[1] - T(1), T(0)),
                min(T(8) * tile[0] + T(8), viewport[0] - T(1)), min(T(8) * tile[1] + T(8), viewport[1] - T(1)));
}

/// The window position of the 8-pixel point drawn over outline tile `tile`: the tile's centre
/// 8 tile + 4, moved inwards for a partial tile at the right or top edge (to size - 4, or to the
/// middle of a viewport narrower than 8 pixels), since GL clips a point whose centre leaves the
/// view. The point then still covers every pixel of the tile, and maybe some of the tile beside it.
/// Numerics: exact (multiples of 1/2).
template <class T>
Vec2<T> outline_tile_centre(const Vec2<T>& tile, const Vec2<T>& viewport) {
    return vec2(min(T(8) * tile[0] + T(4), max(viewport[0] - T(4), viewport[0] * T(0.5))),
                min(T(8) * tile[1] + T(4), max(viewport[1] - T(4), viewport[1] * T(0.5))));
}

/// Where a pixel's surface point falls in the shadow map: the camera's window position
/// (frag = pixel centre, window depth d, viewport size) is taken to the camera's NDC, mapped by
/// M = P_light V_light (P_camera V_camera)^-1 to the light's clip space and to the light's window
/// (texel coordinates in [0, size] and window depth in [0, 1]).
/// Numerics: ndc = (2 frag / viewport - 1, 2 d - 1, 1); h = M ndc (left folds); texel =
/// ((h.xy / h.w) * 0.5 + 0.5) * size; z = (h.z / h.w) * 0.5 + 0.5.
template <class T>
struct ShadowCoord {
    Vec2<T> texel;
    T z;
};

template <class T>
ShadowCoord<T> shadow_coord(const Vec2<T>& frag, const T& d, const Vec2<T>& viewport, const Mat4<T>& m, const T& size) {
    const Vec4<T> ndc = vec4(T(2) * frag[0] / viewport[0] - T(1), T(2) * frag[1] / viewport[1] - T(1), T(2) * d - T(1), T(1));
    const Vec4<T> h = m * ndc;
    const T tx = (h[0] / h[3] * T(0.5) + T(0.5)) * size;
    const T ty = (h[1] / h[3] * T(0.5) + T(0.5)) * size;
    return {vec2(tx, ty), h[2] / h[3] * T(0.5) + T(0.5)};
}

/// Blinn-Phong (`shade_blinn_phong`) with the light attenuated by a shadow visibility vis in
/// [0, 1]: diffuse and specular scale by vis, ambient does not. vis = 1 gives exactly
/// `shade_blinn_phong`.
/// Numerics: material' = (ambient, diffuse * vis, specular * vis, shininess), then `shade_blinn_phong`.
template <class T>
Vec3<T> shade_blinn_phong_shadowed(const Vec3<T>& n, const Vec3<T>& l, const Vec3<T>& e, const Vec3<T>& color, const Vec3<T>& light,
                                   const Vec4<T>& material, const T& vis) {
    return shade_blinn_phong(n, l, e, color, light, vec4(material[0], material[1] * vis, material[2] * vis, material[3]));
}


/// Mirror reflection of the view direction about a surface normal, two-sided like
/// `shade_blinn_phong` (a normal facing away from the eye is flipped). n and e need not be unit
/// vectors; e points towards the eye. Returns r = 2 (n.e) n - e with n, e normalised: a unit
/// vector (up to rounding) with the angle of reflection equal to the angle of incidence.
/// Numerics: e = e / sqrt(e.e), n = n / sqrt(n.n) (`normalize`), then n (2 (n.e)) - e.
template <class T>
Vec3<T> reflect_view(const Vec3<T>& n_in, const Vec3<T>& e_in) {
    const Vec3<T> e = normalize(e_in);
    const Vec3<T> n0 = normalize(n_in);
    const Vec3<T> n = select(dot(n0, e) < T(0), -n0, n0);
    return n * (T(2) * dot(n, e)) - e;
}

/// atan2(y, x) in (-pi, pi] without the GLSL built-in (whose rounding is not specified): the
/// octant reduction t = min(|x|, |y|) / max(|x|, |y|) in [0, 1], the polynomial of Abramowitz and
/// Stegun 4.4.47 (|error| <= 1e-5 rad on [0, 1]), then pi/2 - a where |y| > |x|, pi - a where
/// x < 0, -a where y < 0. atan2(0, 0) = 0.
/// Numerics: one division, Horner in t^2 (left to right as written), exact float constants.
template <class T>
T atan2_poly(const T& y, const T& x) {
    const T ax = abs(x), ay = abs(y);
    const T hi = max(ax, ay), lo = min(ax, ay);
    const T t = lo / select(hi > T(0), hi, T(1));
    const T s = t * t;
    const T p = (((T(0.0208351) * s - T(0.0851330)) * s + T(0.1801410)) * s - T(0.3302995)) * s + T(0.9998660);
    const T a0 = t * p;
    const T a1 = select(ay > ax, T(1.57079632679489662) - a0, a0);
    const T a2 = select(x < T(0), T(3.14159265358979324) - a1, a1);
    return select(y < T(0), -a2, a2);
}

/// Where a direction r falls in a latitude-longitude (equirectangular) environment image of
/// size (width, height) texels, in texel units with texel (i, j) centred at (i + 0.5, j + 0.5)
/// (the centre convention of GL textures): u = 1/2 + atan2(r.x, -r.z) / (2 pi) (the view
/// direction -z at the middle column, +x to the right), v = 1/2 - atan2(r.y, sqrt(r.x^2 + r.z^2))
/// / pi (row 0 = straight up), returned as (u width - 1/2, v height - 1/2). r need not be unit.
/// Numerics: `atan2_poly` twice (the elevation from atan2 rather than acos: well conditioned at
/// the poles), products with the float-rounded 1/(2 pi) and 1/pi.
template <class T>
Vec2<T> latlong_texel(const Vec3<T>& r, const Vec2<T>& size) {
    const T az = atan2_poly(r[0], -r[2]);
    const T el = atan2_poly(r[1], sqrt(r[0] * r[0] + r[2] * r[2]));
    const T u = az * T(0.159154943091895336) + T(0.5);
    const T v = T(0.5) - el * T(0.318309886183790672);
    return vec2(u * size[0] - T(0.5), v * size[1] - T(0.5));
}

/// The four texels around a latitude-longitude lookup position `texel` (`latlong_texel`) of an
/// image of `size` texels: base = floor(texel) clamped to [-1, size - 1] (NaN to -1), and the
/// indices (x0, x1, y0, y1) of the columns base.x and base.x + 1, wrapped around (-1 is the last
/// column, size.x the first), and of the rows base.y and base.y + 1, clamped to the image.
template <class T>
struct LatlongTexels {
    Vec2<T> base;
    Vec4<T> index;  ///< x0, x1, y0, y1
};

/// Numerics: integers in float (exact below 2^24): b = select(f >= -1, min(f, size - 1), -1) with
/// f = floor(texel); x0 = select(b.x < 0, size.x - 1, b.x), x1 = select(b.x + 1 < size.x,
/// b.x + 1, 0), y0 = max(b.y, 0), y1 = min(b.y + 1, size.y - 1).
template <class T>
LatlongTexels<T> latlong_texels(const Vec2<T>& texel, const Vec2<T>& size) {
    const auto base = [](const T& v, const T& hi) {
        const T f = floor(v);
        return select(f >= T(-1), min(f, hi), T(-1));
    };
    const T bx = base(texel[0], size[0] - T(1)), by = base(texel[1], size[1] - T(1));
    const T x0 = select(bx < T(0), size[0] - T(1), bx);
    const T x1 = select(bx + T(1) < size[0], bx + T(1), T(0));
    return {vec2(bx, by), vec4(x0, x1, max(by, T(0)), min(by + T(1), size[1] - T(1)))};
}

/// Environment-map reflection mixed into a shaded colour: the bilinear interpolation of the four
/// texels around the lookup position `texel` (`latlong_texel`), c00 at base (`latlong_texels`),
/// c10 one column right, c01 one row down, c11 both (the caller fetches them at the indices of
/// `latlong_texels`), mixed as rgb (1 - k) + env k with the reflectivity k in [0, 1].
/// Numerics: f = texel - base (exact for |texel| < 2^23); top = c00 + (c10 - c00) f.x, bottom
/// likewise, env = top + (bottom - top) f.y; then rgb * (1 - k) + env * k per component.
template <class T>
Vec3<T> environment_mix(const Vec3<T>& rgb, const Vec2<T>& texel, const Vec2<T>& base, const Vec3<T>& c00, const Vec3<T>& c10,
                        const Vec3<T>& c01, const Vec3<T>& c11, const T& k) {
    const T fx = texel[0] - base[0], fy = texel[1] - base[1];
    const Vec3<T> top = c00 + (c10 - c00) * fx;
    const Vec3<T> bottom = c01 + (c11 - c01) * fx;
    const Vec3<T> env = top + (bottom - top) * fy;
    return rgb * (T(1) - k) + env * k;
}

}  // namespace quadcast
