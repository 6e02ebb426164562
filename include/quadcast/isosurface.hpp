// quadcast/isosurface.hpp -- the volume isosurface of the public shape API (quadcast::shapes)
#pragma once

// Host-only, beside quadcast/shapes.hpp (kept apart so that an app drawing only quadrics does not
// compile the spline preparation): a sampled volume and an isovalue become the input of both
// isosurface renderers (quadcast::gl::IsosurfaceRenderer and render::render_volumes_cpu).

#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "quadcast/render/spline_cpu_renderer.hpp"
#include "quadcast/render/variant_key.hpp"
#include "quadcast/shapes.hpp"
#include "quadcast/spline/grid.hpp"
#include "quadcast/spline/quadric_pieces.hpp"

namespace quadcast::shapes {

/// The reconstruction of the isosurface (render::VolumeScheme): Kalbe & Zeilfelder's quadratic
/// super splines (qss), Sorokina & Zeilfelder's cubic S31 splines (s31), or trilinear
/// interpolation of the samples.
using Reconstruction = render::VolumeScheme;

/// The isosurface f = iso of `samples` (f[i,j,k] at world origin + spacing * (i, j, k)),
/// reconstructed by `scheme`, drawn with `look` (colour, specular, shininess). With
/// `cpu_coefficients` the model also keeps every active tetrahedron's spline coefficients, which
/// the CPU reference renderer needs (the GL renderer does not). `threads` 0: all cores;
/// `progress` (optional) reports the fraction of the spline preparation done.
/// Throws std::invalid_argument naming the field: a non-finite origin, a spacing that is not
/// positive and finite, an isovalue that is not finite or lies outside the range of the finite
/// samples (no surface to draw), a volume with no finite sample, an invalid appearance.
inline render::VolumeModel isosurface(const spline::Volume<float>& samples, const glm::dvec3& origin, const glm::dvec3& spacing, float iso,
                                      Reconstruction scheme = Reconstruction::qss, const Appearance& look = {}, bool cpu_coefficients = false,
                                      unsigned threads = 0, const render::ProgressFn& progress = {}) {
    constexpr const char* fn = "isosurface";
    detail::appearance(fn, look);
    Vec3<double> o, s;
    for (int a = 0; a < 3; ++a) {
        if (!std::isfinite(origin[a]))
            detail::fail(fn, "origin must be finite (got (" + detail::num(origin[0]) + ", " + detail::num(origin[1]) + ", " + detail::num(origin[2]) + "))");
        o[a] = origin[a];
        s[a] = detail::positive(fn, "spacing", spacing[a]);
    }
    if (samples.nx < 1 || samples.ny < 1 || samples.nz < 1 || samples.data.size() != std::size_t(samples.nx) * samples.ny * samples.nz)
        detail::fail(fn, "the volume's sample count does not match its dimensions");
    if (scheme == Reconstruction::trilinear && (samples.nx < 2 || samples.ny < 2 || samples.nz < 2))
        detail::fail(fn, "trilinear interpolation needs at least 2 samples along each axis (got " + std::to_string(samples.nx) + " x " +
                             std::to_string(samples.ny) + " x " + std::to_string(samples.nz) + ")");
    if (!std::isfinite(iso)) detail::fail(fn, "iso must be finite (got " + detail::num(iso) + ")");
    float lo = INFINITY, hi = -INFINITY;
    for (const float v : samples.data)
        if (std::isfinite(v)) {
            lo = std::min(lo, v);
            hi = std::max(hi, v);
        }
    if (!(lo <= hi)) detail::fail(fn, "the volume has no finite sample");
    if (!(iso >= lo && iso <= hi))
        detail::fail(fn, "iso " + detail::num(iso) + " is outside the range of the samples [" + detail::num(lo) + ", " + detail::num(hi) + "]: there is no surface");
    render::VolumeModel m = render::prepare_volume(samples, o, s, scheme, iso, vec3(look.color[0], look.color[1], look.color[2]), threads, cpu_coefficients, progress);
    m.material.specular = look.specular;
    m.material.shininess = look.shininess;
    return m;
}

/// The QSS isosurface of a prepared model (`isosurface(..., Reconstruction::qss, ...)`) as
/// quadrics for the quadric renderers (Stoll et al. 2006, sec. 5.1.2), instead of the model for
/// the isosurface renderers (Kalbe & Zeilfelder): one primitive per tetrahedron of an active cube
/// whose coefficient range contains the isovalue (`VolumeModel::tet_mask`), the piece's
/// polynomial minus the isovalue as a quadric (`spline::qss_piece_quadric` in the cube's local
/// coordinates from the model's float determining set, in double, then in the model's
/// coordinates) clipped to the tetrahedron, with the model's colour and material. A piece equal
/// to the isovalue on its whole tetrahedron (no surface, all coefficients zero) is left out.
/// Throws std::invalid_argument for a model of another scheme.
inline std::vector<render::Primitive> isosurface_quadrics(const render::VolumeModel& m) {
    constexpr const char* fn = "isosurface_quadrics";
    if (m.scheme != Reconstruction::qss) detail::fail(fn, "only a QSS isosurface is piecewise quadratic (the model's scheme is " + std::string(render::volume_scheme_name(m.scheme)) + ")");
    constexpr int nd = spline::d_count(2);
    Appearance look;
    look.color = glm::vec3(m.color[0], m.color[1], m.color[2]);
    look.specular = m.material.specular;
    look.shininess = m.material.shininess;
    std::vector<render::Primitive> out;
    std::size_t relevant = 0;
    for (const std::uint32_t mask : m.tet_mask) relevant += static_cast<std::size_t>(__builtin_popcount(mask));
    out.reserve(relevant);
    for (std::size_t s = 0; s < m.cubes.size(); ++s) {
        const std::int32_t c = m.cubes[s];
        const int idx[3] = {c % m.nx, (c / m.nx) % m.ny, c / (m.nx * m.ny)};
        Vec3<double> centre;
        for (int a = 0; a < 3; ++a) centre[a] = m.origin[a] + m.spacing[a] * idx[a];
        spline::DeterminingSet<double, 2> d{};
        for (int n = 0; n < nd; ++n) d[n] = double(m.dsets[s * nd + static_cast<std::size_t>(n)]);
        for (int t = 0; t < spline::tets_per_cube; ++t) {
            if (!(m.tet_mask[s] >> t & 1u)) continue;
            const Quadric<double> q = spline::cube_local_to_world(spline::qss_piece_quadric(d, t, double(m.iso)), centre, m.spacing);
            bool zero = true;
            for (int j = 0; j < 4; ++j)
                for (int i = 0; i < 4; ++i) zero = zero && q.q[j][i] == 0.0;
            if (zero) continue;
            glm::dmat4 g;
            for (int j = 0; j < 4; ++j)
                for (int i = 0; i < 4; ++i) g[j][i] = q.q[j][i];
            const BoundingTet<double> u = spline::local_tet<double>(t);
            TetrahedronBound b{};
            for (int k = 0; k < 4; ++k)
                for (int a = 0; a < 3; ++a) b.corners[static_cast<std::size_t>(k)][a] = float(m.origin[a] + m.spacing[a] * (idx[a] + 0.5 * u.p[k][a]));  // shared corners alike
            out.push_back(quadric(g, b, look));
        }
    }
    return out;
}

}  // namespace quadcast::shapes
