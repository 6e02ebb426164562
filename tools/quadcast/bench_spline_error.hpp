// tools/quadcast/bench_spline_error.hpp -- the reconstruction methods `quadcast bench spline-error` compares
#pragma once

// A method turns sampled data into a picture of one isosurface: `prepare` is the preprocessing
// (timed once) and returns the frame function, which owns the prepared data and renders the
// λ image of a camera (timed per frame). The bench compares λ with the analytic isosurface along
// the same pixel rays, so any renderer that can report, per pixel, the ray parameter of its first
// hit on the ray of `render::pixel_ray` can be measured. A GL renderer reads back its window
// depth d and converts it: the bench's camera is orthographic (rays start in the plane
// z_view = 0 and run along -z_view with unit speed), so λ = -z_view with z_view from
// `view_z_from_depth` (quadcast/shading.hpp). Such a
// method is appended to `spline_error_methods`.

#include <functional>
#include <string>
#include <vector>

#include "quadcast/render/types.hpp"
#include "quadcast/volume/volume.hpp"

namespace quadcast::cli {

/// Per pixel (x, y) (window coordinates, y = 0 the bottom row; index x + width * y) the ray
/// parameter λ of the first isosurface hit on the pixel's ray (`render::pixel_ray`, hit point
/// origin + λ dir), NaN where the ray hits nothing.
struct LambdaImage {
    int width = 0, height = 0;
    std::vector<float> lambda;
};

/// λ per pixel from a GL window-depth image (`render::Image::depth`, rows top first, 1 = no hit) of
/// an orthographic camera: λ = -z_view (`view_z_from_depth`), NaN where nothing was hit; rows
/// flipped to window order (y = 0 the bottom row). `quadcast bench slim` uses it too.
LambdaImage lambda_from_depth(const render::Image& img, const render::Camera& cam);

/// Renders the λ image of the prepared data for a camera and image size.
using LambdaFrame = std::function<LambdaImage(const render::Camera& camera, int width, int height)>;

/// A reconstruction method of the bench.
struct ErrorMethod {
    std::string name;
    /// Preprocessing for the volume (world = origin + spacing * index) and isovalue, on up to
    /// `threads` threads (0: all cores); returns the frame function owning the prepared data.
    std::function<LambdaFrame(const volume::VolumeData& v, float iso, unsigned threads)> prepare;
};

/// The methods measured by default, in table order: "qss", "s31", "trilinear" (the CPU spline
/// renderer's `cast_volume_ray`), "mc" (the marching-cubes mesh, ray cast on the CPU by a DDA
/// over its cells), then the same on OpenGL: "qss-gl", "s31-gl", "trilinear-gl" (the GL
/// isosurface renderer) and "mc-gl" (the mesh drawn by gl::MeshRenderer).
std::vector<ErrorMethod> spline_error_methods();

}  // namespace quadcast::cli
