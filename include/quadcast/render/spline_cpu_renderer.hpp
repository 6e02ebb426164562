// quadcast/render/spline_cpu_renderer.hpp -- multi-threaded CPU reference renderer of isosurfaces of QSS / S31 splines and trilinear volumes
#pragma once

// Host-only. The per-piece numbers come from the shared templates of quadcast/spline/raycast.hpp
// (`intersect_piece` for a tetrahedron of a spline cube, `intersect_trilinear_cell` for a cell
// of the trilinear interpolant), depth from `window_depth`, colour from `shade_blinn_phong`,
// pixel rays from `pixel_ray` (the quadric CPU renderer's). What is here is the plumbing:
//
// - Everything is done in the volume's INDEX space: sample (i,j,k) sits at index point (i,j,k),
//   world = origin + spacing * index (per axis). A world ray o + λ d is the index ray
//   (o - origin)/spacing + λ d/spacing with the same λ, so depths need no conversion; gradients
//   are converted back by dividing by the spacing per axis (anisotropic voxels work).
// - Splines: cube (i,j,k) is [i-1/2, i+1/2] x ... (data at cube centres, spec §1.1; h = 1 in
//   index space); trilinear: cell (i,j,k) is [i, i+1] x ... between 8 samples.
// - Empty-space skipping: a cube is active iff its coefficient range (`cube_coefficient_ranges`,
//   convex hull property) contains ρ; only active cubes are stored, with the BB-coefficients of
//   their 24 tetrahedra (repeated averaging, `tet_from_determining_set`, computed once at
//   preparation) and a mask of the tetrahedra whose own coefficient range contains ρ. A
//   trilinear cell is active iff ρ lies in the range of its 8 samples.
// - Per pixel, a 3-D DDA (Amanatides & Woo 1987) walks the cubes/cells the ray crosses in
//   order, clipped to the depth range [0, 1]; in an active cube every relevant tetrahedron the
//   ray passes through (`clip_ray_to_tet` first, as a host shortcut) is cast on the cube's ray interval (widened by 1e-5 of a cube so that no root on a shared face
//   is lost to rounding) and the nearest hit wins; the first cube with a hit ends the walk.

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <mutex>
#include <stdexcept>
#include <string>
#include <vector>

#include "quadcast/linalg.hpp"
#include "quadcast/raycast.hpp"
#include "quadcast/render/cpu_renderer.hpp"
#include "quadcast/render/types.hpp"
#include "quadcast/render/variant_key.hpp"
#include "quadcast/spline/grid.hpp"
#include "quadcast/spline/octree.hpp"
#include "quadcast/spline/raycast.hpp"

namespace quadcast::render {

/// The cubes (splines: cube (i,j,k) is centred on sample (i,j,k)) or cells (trilinear: cell
/// (i,j,k) spans samples (i,j,k) to (i+1,j+1,k+1)) of a volume that are drawn: lo <= index <= hi
/// per axis; by default all. A piece of a volume split over processes is prepared with a ghost
/// layer (one sample around its own: the rest of its boundary cubes' stencils) and draws only the
/// cubes it owns, so that the pieces' surfaces join exactly as the whole volume's surface does.
struct IndexBox {
    std::array<int, 3> lo{{0, 0, 0}};
    std::array<int, 3> hi{{std::numeric_limits<int>::max(), std::numeric_limits<int>::max(), std::numeric_limits<int>::max()}};
    bool contains(int i, int j, int k) const {
        return lo[0] <= i && i <= hi[0] && lo[1] <= j && j <= hi[1] && lo[2] <= k && k <= hi[2];
    }
};

/// A volume prepared for rendering one isosurface (host-only; build with `prepare_volume`).
struct VolumeModel {
    VolumeScheme scheme = VolumeScheme::qss;
    float iso = 0.0f;
    Vec3<float> color{{0.8f, 0.8f, 0.8f}};
    Material material;                       ///< specular and shininess of the isosurface
    Vec3<double> origin{{0.0, 0.0, 0.0}};   ///< world position of sample (0,0,0)
    Vec3<double> spacing{{1.0, 1.0, 1.0}};  ///< world distance of neighbouring samples per axis
    int nx = 0, ny = 0, nz = 0;              ///< sample counts
    /// Splines: per cube (cube-major, i fastest) the slot of its coefficients or -1 (inactive).
    std::vector<std::int32_t> slot;
    /// Splines: per active cube 24 tetrahedra x coefficient_count(q) floats (storage order of
    /// bb::multi_indices); empty when prepared for the GPU renderer only.
    std::vector<float> coeffs;
    /// Splines: per active cube the mask of tetrahedra whose coefficient range contains ρ.
    std::vector<std::uint32_t> tet_mask;
    /// Splines: per active cube its index (i + nx (j + ny k)) and its determining set
    /// (`spline::d_count(q)` floats, the order of spline::d_point): what the GPU renderer keeps.
    std::vector<std::int32_t> cubes;
    std::vector<float> dsets;
    /// Min-max octree over the cubes (splines: coefficient ranges, boxes [i-1/2, i+1/2] in index
    /// space) or the cells (trilinear: sample ranges, boxes [i, i+1]): what the renderers skip.
    spline::MinMaxOctree<float> octree;
    /// Trilinear: the samples (i fastest) and per cell (i fastest over (nx-1)x(ny-1)x(nz-1))
    /// whether ρ lies in the range of its 8 samples.
    std::vector<float> samples;
    std::vector<std::uint8_t> cell_active;
    std::size_t active = 0;  ///< active cubes / cells
    IndexBox drawn;          ///< the cubes / cells drawn (`prepare_volume_piece`); the others are inactive

    int degree() const { return scheme == VolumeScheme::qss ? 2 : scheme == VolumeScheme::s31 ? 3 : 1; }
    /// The index range [first, last] along axis a of the drawn cubes (cells): `drawn` clamped to
    /// the volume's cubes (cells); first > last when none.
    void drawn_range(int a, int& first, int& last) const {
        const int n[3] = {nx, ny, nz};
        first = std::max(0, drawn.lo[a]);
        last = std::min(n[a] - (scheme == VolumeScheme::trilinear ? 2 : 1), drawn.hi[a]);
    }
    /// True when no cube (cell) is drawn (`drawn` misses the volume, or a trilinear volume is flat).
    bool draws_nothing() const {
        for (int a = 0; a < 3; ++a) {
            int first = 0, last = 0;
            drawn_range(a, first, last);
            if (first > last) return true;
        }
        return false;
    }
    /// World bounding box of the drawn reconstruction (splines reach half a voxel beyond the
    /// samples; `drawn` limits it).
    void world_box(Vec3<double>& lo, Vec3<double>& hi) const {
        const bool tri = scheme == VolumeScheme::trilinear;
        for (int a = 0; a < 3; ++a) {
            int first = 0, last = 0;
            drawn_range(a, first, last);
            lo[a] = origin[a] + spacing[a] * (tri ? first : first - 0.5);
            hi[a] = origin[a] + spacing[a] * (tri ? last + 1 : last + 0.5);
        }
    }
};

/// Progress of a long preparation: called with the fraction done (0..1], from any thread, one
/// call at a time.
using ProgressFn = std::function<void(double)>;

namespace spline_cpu_detail {

/// The largest total negative weight of a coefficient mask (spec §2.3 / §3.3): 1/16 for QSS
/// (e.g. c1010 = (... - 8 f ...)/128), 0 for S31 (all weights are non-negative).
template <int Q>
constexpr double negative_weight() {
    int worst = 0;
    for (int n = 0; n < bb::coefficient_count(Q); ++n) {
        int neg = 0;
        for (int s = 0; s < spline::stencil_size; ++s) neg += std::max(0, -spline::tet0_mask<Q>(n, s));
        worst = std::max(worst, neg);
    }
    return double(worst) / spline::coefficient_mask_denominator(Q);
}

/// A range containing every BB-coefficient of the cube with stencil f: the coefficients are
/// affine combinations of f (weights summing to 1), so they lie in [min f - N w, max f + N w]
/// with w = max f - min f and N = `negative_weight<Q>()`; widened like the coefficient ranges
/// (16 ε max(|lo|, |hi|)) for rounding.
template <int Q>
spline::Range<float> data_bound(const spline::Stencil<float>& f) {
    float lo = f[0], hi = f[0];
    for (int s = 1; s < spline::stencil_size; ++s) {
        lo = std::min(lo, f[s]);
        hi = std::max(hi, f[s]);
    }
    const double w = double(hi) - double(lo), n = negative_weight<Q>();
    const double a = double(lo) - n * w, b = double(hi) + n * w;
    const double widen = 16.0 * double(std::numeric_limits<float>::epsilon()) * std::max(std::abs(a), std::abs(b));
    return {float(a - widen), float(b + widen)};
}

/// Streams over the cubes (no whole-volume spline is kept): per cube the determining set from
/// its stencil (`determining_set_from_stencil` in double, rounded to float once, as
/// `build_spline`) and its coefficient range (as `cube_coefficient_ranges`, widened alike) --
/// unless the cheaper `data_bound` already excludes ρ, which then stands for the range -- and for
/// an active cube (range contains ρ) its determining set, the mask of relevant tetrahedra and,
/// with `cpu`, the coefficients of its 24 tetrahedra.
template <int Q>
void prepare_spline(VolumeModel& m, const spline::Volume<float>& vol, bool cpu, unsigned threads, const ProgressFn& progress) {
    constexpr int nc = bb::coefficient_count(Q), nd = spline::d_count(Q);
    struct Slice {
        std::vector<std::int32_t> cubes;
        std::vector<float> dsets, coeffs;
        std::vector<std::uint32_t> mask;
    };
    std::vector<Slice> slices(static_cast<std::size_t>(vol.nz));
    std::vector<spline::Range<float>> ranges(static_cast<std::size_t>(vol.nx) * vol.ny * vol.nz);
    std::atomic<int> done{0};
    std::mutex report;
    spline::parallel_for(vol.nz, [&](int k) {
        Slice& sl = slices[static_cast<std::size_t>(k)];
        for (int j = 0; j < vol.ny; ++j)
            for (int i = 0; i < vol.nx; ++i) {
                const int c = i + vol.nx * (j + vol.ny * k);
                if (!m.drawn.contains(i, j, k)) {  // (not drawn: an empty range, inactive)
                    ranges[static_cast<std::size_t>(c)] = {std::numeric_limits<float>::infinity(), -std::numeric_limits<float>::infinity()};
                    continue;
                }
                const spline::Stencil<float> f = spline::stencil(vol, i, j, k);
                // Cheap test first: every coefficient lies within the stencil's data range widened
                // by `negative_weight<Q>()` of its width (`data_bound`); most cubes end here.
                const spline::Range<float> bound = data_bound<Q>(f);
                if (!bound.contains(m.iso)) {
                    ranges[static_cast<std::size_t>(c)] = bound;
                    continue;
                }
                const spline::DeterminingSet<double, Q> dv = spline::determining_set_from_stencil<Q>(cast<double>(f));
                spline::DeterminingSet<float, Q> d{};
                for (int n = 0; n < nd; ++n) d[n] = float(dv[n]);
                const spline::CubeCoefficients<Q, float> cc = spline::cube_coefficients<Q>(d);
                float lo = cc.value[0], hi = cc.value[0];
                for (const float& v : cc.value) {
                    lo = std::min(lo, v);
                    hi = std::max(hi, v);
                }
                const float widen = 16.0f * std::numeric_limits<float>::epsilon() * std::max(std::abs(lo), std::abs(hi));
                ranges[static_cast<std::size_t>(c)] = {lo - widen, hi + widen};
                if (!ranges[static_cast<std::size_t>(c)].contains(m.iso)) continue;
                sl.cubes.push_back(c);
                sl.dsets.insert(sl.dsets.end(), d.c, d.c + nd);
                std::uint32_t mask = 0;
                for (int t = 0; t < spline::tets_per_cube; ++t) {
                    const bb::BezierTet<float, Q> b = spline::tet_from_determining_set<Q>(d, t);
                    float blo = b[0], bhi = b[0];
                    for (int n = 0; n < nc; ++n) {
                        blo = std::min(blo, b[n]);
                        bhi = std::max(bhi, b[n]);
                    }
                    if (cpu) sl.coeffs.insert(sl.coeffs.end(), b.c, b.c + nc);
                    if (blo <= m.iso && m.iso <= bhi) mask |= 1u << t;
                }
                sl.mask.push_back(mask);
            }
        const int n = ++done;
        if (progress) {
            const std::lock_guard<std::mutex> lock(report);
            progress(double(n) / vol.nz);
        }
    }, threads);
    m.slot.assign(ranges.size(), -1);
    for (Slice& sl : slices) {
        for (std::size_t n = 0; n < sl.cubes.size(); ++n) m.slot[static_cast<std::size_t>(sl.cubes[n])] = static_cast<std::int32_t>(m.cubes.size() + n);
        m.cubes.insert(m.cubes.end(), sl.cubes.begin(), sl.cubes.end());
        m.dsets.insert(m.dsets.end(), sl.dsets.begin(), sl.dsets.end());
        m.coeffs.insert(m.coeffs.end(), sl.coeffs.begin(), sl.coeffs.end());
        m.tet_mask.insert(m.tet_mask.end(), sl.mask.begin(), sl.mask.end());
        sl = Slice{};
    }
    m.active = m.cubes.size();
    m.octree = spline::MinMaxOctree<float>(vol.nx, vol.ny, vol.nz, std::move(ranges), Vec<double, 3>{{0.0, 0.0, 0.0}}, 1.0);
}

inline void prepare_trilinear(VolumeModel& m, const spline::Volume<float>& vol) {
    m.samples = vol.data;
    const int cx = std::max(0, m.nx - 1), cy = std::max(0, m.ny - 1), cz = std::max(0, m.nz - 1);
    m.cell_active.assign(static_cast<std::size_t>(cx) * cy * cz, 0);
    std::vector<spline::Range<float>> ranges(m.cell_active.size());
    std::size_t n = 0;
    for (int k = 0; k < cz; ++k)
        for (int j = 0; j < cy; ++j)
            for (int i = 0; i < cx; ++i) {
                const std::size_t c = static_cast<std::size_t>(i) + static_cast<std::size_t>(cx) * (static_cast<std::size_t>(j) + static_cast<std::size_t>(cy) * k);
                if (!m.drawn.contains(i, j, k)) {  // (not drawn: an empty range, inactive)
                    ranges[c] = {std::numeric_limits<float>::infinity(), -std::numeric_limits<float>::infinity()};
                    continue;
                }
                float lo = vol.at(i, j, k), hi = lo;
                for (int corner = 1; corner < 8; ++corner) {
                    const float v = vol.at(i + (corner & 1), j + ((corner >> 1) & 1), k + ((corner >> 2) & 1));
                    lo = std::min(lo, v);
                    hi = std::max(hi, v);
                }
                const bool a = lo <= m.iso && m.iso <= hi;
                m.cell_active[c] = a;
                ranges[c] = {lo, hi};
                n += a;
            }
    m.active = n;
    m.octree = spline::MinMaxOctree<float>(cx, cy, cz, std::move(ranges), Vec<double, 3>{{0.5, 0.5, 0.5}}, 1.0);
}

/// The barycentric axis directions of the 24 tetrahedra (cube-local frame).
inline const std::array<Mat<float, 4, 3>, spline::tets_per_cube>& tet_dirs() {
    static const auto d = [] {
        std::array<Mat<float, 4, 3>, spline::tets_per_cube> r{};
        for (int t = 0; t < spline::tets_per_cube; ++t) r[t] = spline::barycentric_directions<float>(t);
        return r;
    }();
    return d;
}

}  // namespace spline_cpu_detail

/// Prepares `vol` (samples f[i,j,k], world = origin + spacing * (i,j,k)) for rendering the
/// isosurface `iso` with `scheme`: splines by the determining sets of `build_spline`
/// (clamp-to-edge padding), kept for the active cubes with, if `cpu_coefficients` (needed by
/// `render_volumes_cpu`), their per-tetrahedron coefficients; trilinear by the active-cell
/// flags. Both with the min-max octree. `progress` (optional) reports the fraction of the
/// spline preparation done. Only the cubes (cells) in `drawn` can be active: the others are
/// left out of the octree and never drawn (their samples still serve their neighbours' stencils).
/// Throws std::invalid_argument for a non-finite iso or non-positive spacing, or a trilinear
/// volume with fewer than 2 samples along an axis.
inline VolumeModel prepare_volume_piece(const spline::Volume<float>& vol, const Vec3<double>& origin, const Vec3<double>& spacing,
                                        VolumeScheme scheme, float iso, const IndexBox& drawn, const Vec3<float>& color = {{0.8f, 0.8f, 0.8f}},
                                        unsigned threads = 0, bool cpu_coefficients = true, const ProgressFn& progress = {}) {
    if (!std::isfinite(iso)) throw std::invalid_argument("quadcast::render::prepare_volume: isovalue is not finite");
    for (int a = 0; a < 3; ++a)
        if (!(spacing[a] > 0) || !std::isfinite(spacing[a]) || !std::isfinite(origin[a]))
            throw std::invalid_argument("quadcast::render::prepare_volume: spacing must be positive and finite");
    VolumeModel m;
    m.scheme = scheme;
    m.iso = iso;
    m.color = color;
    m.origin = origin;
    m.spacing = spacing;
    m.nx = vol.nx;
    m.ny = vol.ny;
    m.nz = vol.nz;
    m.drawn = drawn;
    if (scheme == VolumeScheme::qss) spline_cpu_detail::prepare_spline<2>(m, vol, cpu_coefficients, threads, progress);
    else if (scheme == VolumeScheme::s31) spline_cpu_detail::prepare_spline<3>(m, vol, cpu_coefficients, threads, progress);
    else {
        if (vol.nx < 2 || vol.ny < 2 || vol.nz < 2)
            throw std::invalid_argument("quadcast::render::prepare_volume: trilinear needs at least 2 samples per axis");
        spline_cpu_detail::prepare_trilinear(m, vol);
    }
    return m;
}

/// `prepare_volume_piece` drawing every cube (cell) of `vol`.
inline VolumeModel prepare_volume(const spline::Volume<float>& vol, const Vec3<double>& origin, const Vec3<double>& spacing,
                                  VolumeScheme scheme, float iso, const Vec3<float>& color = {{0.8f, 0.8f, 0.8f}},
                                  unsigned threads = 0, bool cpu_coefficients = true, const ProgressFn& progress = {}) {
    return prepare_volume_piece(vol, origin, spacing, scheme, iso, IndexBox{}, color, threads, cpu_coefficients, progress);
}

/// The first isosurface hit of a world ray.
struct VolumeHit {
    bool hit = false;
    float lambda = 0.0f;    ///< ray parameter: hit point = origin + lambda * dir
    Vec3<float> point;      ///< world hit point (float)
    Vec3<float> gradient;   ///< world gradient of the reconstruction at the hit (unnormalised)
};

/// Counters of a cast.
struct VolumeCastStats {
    std::uint64_t cells = 0;   ///< cubes/cells visited by the DDA
    std::uint64_t pieces = 0;  ///< tetrahedra/cells cast (intersect_piece / intersect_trilinear_cell calls; relevant tetrahedra the ray crosses)
};

/// The first hit of the isosurface on the world ray o + λ d with λ in [lambda_min, lambda_max]
/// (see the top of this file for the walk).
inline VolumeHit cast_volume_ray(const VolumeModel& m, const Vec3<float>& o, const Vec3<float>& d, double lambda_min,
                                 double lambda_max, VolumeCastStats* stats = nullptr) {
    VolumeHit none;
    const bool tri = m.scheme == VolumeScheme::trilinear;
    if (!tri && m.active > 0 && m.coeffs.empty())
        throw std::invalid_argument("quadcast::render::cast_volume_ray: the volume was prepared without CPU coefficients");
    const int n[3] = {tri ? m.nx - 1 : m.nx, tri ? m.ny - 1 : m.ny, tri ? m.nz - 1 : m.nz};
    const double lo = tri ? 0.0 : -0.5;
    // The ray in index space (double), clipped to the grid box
    double oi[3], di[3];
    double t0 = lambda_min, t1 = lambda_max;
    for (int a = 0; a < 3; ++a) {
        oi[a] = (double(o[a]) - m.origin[a]) / m.spacing[a];
        di[a] = double(d[a]) / m.spacing[a];
        const double b0 = lo, b1 = lo + n[a];
        if (di[a] == 0.0) {
            if (oi[a] < b0 || oi[a] > b1) return none;
            continue;
        }
        double ta = (b0 - oi[a]) / di[a], tb = (b1 - oi[a]) / di[a];
        if (ta > tb) std::swap(ta, tb);
        t0 = std::max(t0, ta);
        t1 = std::min(t1, tb);
    }
    if (!(t0 <= t1)) return none;
    // DDA set-up: the cell of the entry point and the λ of the next boundary per axis
    int cell[3], step[3];
    double t_next[3], t_delta[3];
    for (int a = 0; a < 3; ++a) {
        const double p = oi[a] + t0 * di[a] - lo;
        cell[a] = std::clamp(static_cast<int>(std::floor(p)), 0, n[a] - 1);
        if (di[a] > 0) {
            step[a] = 1;
            t_next[a] = (lo + cell[a] + 1 - oi[a]) / di[a];
            t_delta[a] = 1.0 / di[a];
        } else if (di[a] < 0) {
            step[a] = -1;
            t_next[a] = (lo + cell[a] - oi[a]) / di[a];
            t_delta[a] = -1.0 / di[a];
        } else {
            step[a] = 0;
            t_next[a] = std::numeric_limits<double>::infinity();
            t_delta[a] = std::numeric_limits<double>::infinity();
        }
    }
    const auto& dirs = spline_cpu_detail::tet_dirs();
    const int nc = tri ? 0 : bb::coefficient_count(m.degree());
    double t_enter = t0;
    std::uint64_t cells = 0, pieces = 0;
    VolumeHit result;
    while (true) {
        const int a_min = t_next[0] <= t_next[1] ? (t_next[0] <= t_next[2] ? 0 : 2) : (t_next[1] <= t_next[2] ? 1 : 2);
        const double t_exit = std::min(t_next[a_min], t1);
        ++cells;
        bool found = false;
        float best_s = std::numeric_limits<float>::infinity();
        Vec3<float> best_g{};
        if (tri) {
            const std::size_t ci = static_cast<std::size_t>(cell[0]) +
                                   static_cast<std::size_t>(n[0]) * (static_cast<std::size_t>(cell[1]) + static_cast<std::size_t>(n[1]) * cell[2]);
            if (m.cell_active[ci]) {
                ++pieces;
                spline::CellCorners<float> v{};
                for (int c = 0; c < 8; ++c) {
                    const std::size_t i = static_cast<std::size_t>(cell[0] + (c & 1)) +
                                          static_cast<std::size_t>(m.nx) * (static_cast<std::size_t>(cell[1] + ((c >> 1) & 1)) +
                                                                            static_cast<std::size_t>(m.ny) * (cell[2] + ((c >> 2) & 1)));
                    v[c] = m.samples[i];
                }
                Vec3<float> w0{}, wd{};
                for (int a = 0; a < 3; ++a) {
                    w0[a] = float((oi[a] + t_enter * di[a]) - double(cell[a]));
                    wd[a] = float(di[a]);
                }
                const float len = float(t_exit - t_enter);
                const float pad = 1e-5f * (len + 1.0f);
                const spline::PieceHit<float> h = spline::intersect_trilinear_cell(v, w0, wd, -pad, len + pad, m.iso);
                if (h.hit) {
                    found = true;
                    best_s = h.s;
                    best_g = h.gradient;
                }
            }
        } else {
            const std::size_t ci = static_cast<std::size_t>(cell[0]) +
                                   static_cast<std::size_t>(n[0]) * (static_cast<std::size_t>(cell[1]) + static_cast<std::size_t>(n[1]) * cell[2]);
            const std::int32_t s = m.slot[ci];
            if (s >= 0) {
                // Cube-local ray u(s) = u_e + s ud, u = 2 (index - centre), s = λ - t_enter
                Vec3<float> ue{}, ud{};
                for (int a = 0; a < 3; ++a) {
                    ue[a] = float(2.0 * ((oi[a] + t_enter * di[a]) - double(cell[a])));
                    ud[a] = float(2.0 * di[a]);
                }
                const float len = float(t_exit - t_enter);
                const float pad = 1e-5f * (len + 1.0f);
                const std::uint32_t mask = m.tet_mask[static_cast<std::size_t>(s)];
                const float* base = &m.coeffs[static_cast<std::size_t>(s) * spline::tets_per_cube * nc];
                for (int t = 0; t < spline::tets_per_cube; ++t) {
                    if (!(mask & (1u << t))) continue;
                    const Vec<float, 4> beta0 = spline::barycentric(t, ue);
                    const Vec<float, 4> delta = dirs[t] * ud;
                    // Host shortcut: the ray misses most of the 24 tetrahedra (same clip as inside intersect_piece)
                    if (!spline::clip_ray_to_tet(beta0, delta, -pad, len + pad).valid) continue;
                    ++pieces;
                    spline::PieceHit<float> h;
                    if (m.scheme == VolumeScheme::qss) {
                        bb::BezierTet<float, 2> c;
                        std::copy(base + t * nc, base + (t + 1) * nc, c.c);
                        h = spline::intersect_piece<2>(c, beta0, delta, -pad, len + pad, m.iso, dirs[t]);
                    } else {
                        bb::BezierTet<float, 3> c;
                        std::copy(base + t * nc, base + (t + 1) * nc, c.c);
                        h = spline::intersect_piece<3>(c, beta0, delta, -pad, len + pad, m.iso, dirs[t]);
                    }
                    if (h.hit && h.s < best_s) {
                        found = true;
                        best_s = h.s;
                        best_g = h.gradient * 2.0f;  // d/d(index) = 2 d/du
                    }
                }
            }
        }
        if (found) {
            result.hit = true;
            const double lam = t_enter + double(best_s);
            result.lambda = float(lam);
            for (int a = 0; a < 3; ++a) {
                result.point[a] = float(double(o[a]) + lam * double(d[a]));
                result.gradient[a] = float(double(best_g[a]) / m.spacing[a]);
            }
            break;
        }
        if (t_next[a_min] >= t1) break;
        // Step to the next cell
        t_enter = t_next[a_min];
        cell[a_min] += step[a_min];
        if (cell[a_min] < 0 || cell[a_min] >= n[a_min]) break;
        t_next[a_min] += t_delta[a_min];
    }
    if (stats) {
        stats->cells += cells;
        stats->pieces += pieces;
    }
    return result;
}

/// Statistics of a volume frame.
struct VolumeFrameStats {
    std::uint64_t pixels = 0, hits = 0, cells = 0, pieces = 0;
};

/// The λ range of a pixel ray (`pixel_ray`) whose window depth lies in [0, 1] (the near and far
/// planes), from the projection's depth terms; vz = view-space z of the ray direction.
inline void depth_range_lambda(const FrameSetup& f, float vz, double& lmin, double& lmax) {
    const double p22 = f.projection[2][2], p32 = f.projection[3][2], p23 = f.projection[2][3], p33 = f.projection[3][3];
    const double z_near = -(p32 + p33) / (p22 + p23), z_far = (p33 - p32) / (p22 - p23);
    double a = z_near / double(vz), b = z_far / double(vz);
    if (a > b) std::swap(a, b);
    lmin = std::max(0.0, a);
    lmax = b;
}

/// Renders the isosurface of each model (nearest hit over all models wins) with the CPU:
/// per pixel centre the ray of `pixel_ray`, `cast_volume_ray` over the λ range of depth [0, 1],
/// depth by `window_depth`, colour by `shade_blinn_phong(gradient, -light.direction, -dir,
/// model.color, light.color, (options.material[0..1], model.material))` (two-sided); elsewhere the background and
/// depth 1. Rows top first. `threads` = 0: hardware concurrency.
inline Image render_volumes_cpu(const std::vector<const VolumeModel*>& models, const Camera& camera, const Light& light,
                                const RenderOptions& options, VolumeFrameStats* stats = nullptr, int threads = 0) {
    using namespace cpu_detail;
    const FrameSetup f = frame_setup(camera, options.width, options.height);
    if (threads <= 0) threads = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
    Image img;
    img.width = f.width;
    img.height = f.height;
    img.rgba.assign(std::size_t(f.width) * f.height * 4, 0);
    img.depth.assign(std::size_t(f.width) * f.height, 1.0f);
    const std::uint8_t bg[4] = {to_unorm8(options.background[0]), to_unorm8(options.background[1]), to_unorm8(options.background[2]), 255};
    std::vector<VolumeFrameStats> per(static_cast<std::size_t>(threads));
    constexpr int rows = 4;
    const int n_bands = (f.height + rows - 1) / rows;
    parallel_for(n_bands, threads, [&](int band, int th) {
        VolumeFrameStats& st = per[static_cast<std::size_t>(th)];
        for (int y = band * rows; y < std::min(f.height, (band + 1) * rows); ++y)
            for (int x = 0; x < f.width; ++x) {
                const PixelRay ray = pixel_ray(f, x, y);
                const float vz = dot(f.vz_row, ray.dir);
                const std::size_t o = std::size_t(f.height - 1 - y) * f.width + x;
                std::uint8_t* px = &img.rgba[o * 4];
                ++st.pixels;
                double lmin = 0, lmax = 0;
                depth_range_lambda(f, vz, lmin, lmax);
                float best_depth = 1.0f;
                Vec3<float> normal{}, color{};
                Vec4<float> material = options.material;
                bool any = false;
                for (const VolumeModel* m : models) {
                    VolumeCastStats cs;
                    const VolumeHit h = cast_volume_ray(*m, ray.origin, ray.dir, lmin, lmax, &cs);
                    st.cells += cs.cells;
                    st.pieces += cs.pieces;
                    if (!h.hit) continue;
                    const float depth = window_depth(h.lambda, vz, f.pz);
                    if (!(depth >= 0.0f && depth < best_depth)) continue;
                    best_depth = depth;
                    normal = h.gradient;
                    color = m->color;
                    material = vec4(options.material[0], options.material[1], m->material.specular, m->material.shininess);
                    any = true;
                }
                img.depth[o] = best_depth;
                if (!any) {
                    std::copy(bg, bg + 4, px);
                    continue;
                }
                ++st.hits;
                const Vec3<float> c = shade_blinn_phong(normal, -light.direction, -ray.dir, color, light.color, material);
                for (int i = 0; i < 3; ++i) px[i] = to_unorm8(c[i]);
                px[3] = 255;
            }
    });
    if (stats) {
        *stats = VolumeFrameStats{};
        for (const auto& s : per) {
            stats->pixels += s.pixels;
            stats->hits += s.hits;
            stats->cells += s.cells;
            stats->pieces += s.pieces;
        }
    }
    return img;
}

/// Composites `over` onto `base` by depth (per pixel the smaller depth wins; ties keep `base`).
/// Both must have the same size; throws std::invalid_argument otherwise.
inline void composite_by_depth(Image& base, const Image& over) {
    if (base.width != over.width || base.height != over.height)
        throw std::invalid_argument("quadcast::render::composite_by_depth: image sizes differ");
    for (std::size_t i = 0; i < base.depth.size(); ++i)
        if (over.depth[i] < base.depth[i]) {
            base.depth[i] = over.depth[i];
            std::copy(&over.rgba[i * 4], &over.rgba[i * 4] + 4, &base.rgba[i * 4]);
        }
}

}  // namespace quadcast::render
