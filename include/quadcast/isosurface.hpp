// quadcast/isosurface.hpp -- the volume isosurface of the public shape API (quadcast::shapes)
#pragma once

// Host-only, beside quadcast/shapes.hpp (kept apart so that an app drawing only quadrics does not
// compile the spline preparation): a sampled volume and an isovalue become the input of both
// isosurface renderers (quadcast::gl::IsosurfaceRenderer and render::render_volumes_cpu).

#include <cmath>
#include <string>

#include <glm/vec3.hpp>

#include "quadcast/render/spline_cpu_renderer.hpp"
#include "quadcast/shapes.hpp"
#include "quadcast/spline/grid.hpp"

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

}  // namespace quadcast::shapes
