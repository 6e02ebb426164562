// quadcast/render/environment.hpp -- environment maps for reflections: the built-in procedural sky, 8-bit images, the CPU lookup
#pragma once

// Host-only. The lookup is the plumbing of the GL stages' `qc_reflect_environment`
// (src/gl/stages.cpp) around the same templates: `reflect_view` and `latlong_texel` give the
// position, `latlong_texels` the four texels around it (columns wrap, rows clamp), which are
// fetched, and `environment_mix` blends them into the colour. The GL renderer stores the texels as RGBA32F
// and reads them with texelFetch (no sampler filtering), so for equal normal and view vectors
// the two renderers compute the same bits.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>

#include "quadcast/linalg.hpp"
#include "quadcast/render/types.hpp"
#include "quadcast/shading.hpp"

namespace quadcast::render {

/// Colours of the procedural environment.
struct ProceduralSky {
    Vec3<float> zenith{{0.16f, 0.36f, 0.78f}};
    Vec3<float> horizon{{0.86f, 0.91f, 0.97f}};
    Vec3<float> ground{{0.42f, 0.38f, 0.33f}};  ///< the light squares of the ground's checkerboard
};

/// The built-in environment: a sky from `horizon` (elevation 0) to `zenith` (straight up),
/// blended by sqrt(sin elevation), over a ground plane one unit below the viewer with a
/// checkerboard of unit squares (`ground` and 0.55 `ground`) that fades into `horizon` with
/// distance (weight exp(-distance / 8)), so reflections show both the horizon and the ground.
/// Each texel of the width x height latitude-longitude image (the mapping of `latlong_texel`)
/// is the mean of 4 x 4 samples over its area (the checkerboard shrinks towards the horizon and
/// would alias), evaluated in double and rounded to float. Image data, not a traced formula.
inline EnvironmentMap procedural_environment(const ProceduralSky& sky = {}, int width = 1024, int height = 512) {
    if (width < 2 || height < 2) throw std::invalid_argument("quadcast::render::procedural_environment: image size must be at least 2 x 2");
    constexpr double pi = 3.14159265358979323846;
    constexpr int sub = 4;
    EnvironmentMap env;
    env.width = width;
    env.height = height;
    env.rgb.resize(std::size_t(width) * height * 3);
    const Vec3<double> horizon = cast<double>(sky.horizon), zenith = cast<double>(sky.zenith), ground = cast<double>(sky.ground);
    // The colour in the direction of azimuth az (atan2(x, -z)) and elevation el.
    auto colour = [&](double az, double el) {
        const double x = std::cos(el) * std::sin(az), y = std::sin(el), z = -std::cos(el) * std::cos(az);
        if (y >= 0.0) return horizon + (zenith - horizon) * std::sqrt(y);
        // The ray meets the plane y = -1 at distance 1 / -y.
        const double d = 1.0 / -y;
        const bool light = (static_cast<long long>(std::floor(x * d)) + static_cast<long long>(std::floor(z * d))) % 2 == 0;
        return horizon + (ground * (light ? 1.0 : 0.55) - horizon) * std::exp(-d / 8.0);
    };
    for (int j = 0; j < height; ++j)
        for (int i = 0; i < width; ++i) {
            Vec3<double> c{{0.0, 0.0, 0.0}};
            for (int sj = 0; sj < sub; ++sj)
                for (int si = 0; si < sub; ++si) {
                    const double u = (i + (si + 0.5) / sub) / width, v = (j + (sj + 0.5) / sub) / height;
                    c = c + colour(2.0 * pi * (u - 0.5), pi * (0.5 - v));  // u = 1/2 + az / (2 pi), v = 1/2 - el / pi
                }
            float* px = &env.rgb[(std::size_t(j) * width + i) * 3];
            for (int k = 0; k < 3; ++k) px[k] = static_cast<float>(c[k] / (sub * sub));
        }
    return env;
}

/// An environment from 8-bit RGBA pixels (rows top first, alpha ignored): each channel c / 255
/// in float. `what` names the source in errors.
inline EnvironmentMap environment_from_rgba8(int width, int height, const std::uint8_t* rgba, const std::string& what) {
    if (width < 2 || height < 1)
        throw std::invalid_argument(what + ": an environment image needs at least 2 x 1 pixels, got " + std::to_string(width) + " x " +
                                    std::to_string(height));
    EnvironmentMap env;
    env.width = width;
    env.height = height;
    env.rgb.resize(std::size_t(width) * height * 3);
    for (std::size_t p = 0; p < std::size_t(width) * height; ++p)
        for (int k = 0; k < 3; ++k) env.rgb[p * 3 + k] = static_cast<float>(rgba[p * 4 + k]) / 255.0f;
    return env;
}

/// Mixes the environment's reflection into a shaded colour, as the GL stages do
/// (`qc_reflect_environment`): t = `latlong_texel(reflect_view(n, e), size)`, the texels
/// (x0, y0), (x1, y0), (x0, y1), (x1, y1) of `latlong_texels(t, size)`, then
/// `environment_mix(rgb, t, base, ...)`. e points towards the eye; neither need be unit.
inline Vec3<float> reflect_environment(const EnvironmentMap& env, const Vec3<float>& rgb, const Vec3<float>& n, const Vec3<float>& e,
                                       float reflectivity) {
    const Vec2<float> size = vec2(static_cast<float>(env.width), static_cast<float>(env.height));
    const Vec2<float> t = latlong_texel(reflect_view(n, e), size);
    const LatlongTexels<float> l = latlong_texels(t, size);
    const int x0 = static_cast<int>(l.index[0]), x1 = static_cast<int>(l.index[1]);
    const int y0 = static_cast<int>(l.index[2]), y1 = static_cast<int>(l.index[3]);
    const auto texel = [&](int x, int y) {
        const float* p = &env.rgb[(std::size_t(y) * env.width + x) * 3];
        return vec3(p[0], p[1], p[2]);
    };
    return environment_mix(rgb, t, l.base, texel(x0, y0), texel(x1, y0), texel(x0, y1), texel(x1, y1), reflectivity);
}

}  // namespace quadcast::render
