// quadcast/slim/model.hpp -- SLIM models: balls holding a world quadric and an optional clip plane; the file format
#pragma once

// One record per ball, in what the quadric renderer draws as a general quadric clipped to a
// sphere (quadcast::shapes::quadric(q_world, SphereBound{center, radius}), variant `bounded`):
// the quadric in WORLD coordinates, f(x) = x~^T Q x~ (x~ = (x, 1)), f < 0 inside, |grad f| ~ 1
// near the surface, and the ball (centre, radius). The SLIM blending weight of a point x is
// w(|x - c| / r), 1 at the centre and 0 on the sphere (Ohtake et al. 2005; not stored).
// A sharp-feature record also holds a clip plane p: the surface is the part of the quadric in
// the ball with p.x * x + p.y * y + p.z * z + p.w >= 0 (|p.xyz| = 1; Stoll et al. 2006, fig. 8).
// A corner's record holds two, and keeps the part on the kept side of both.
//
// File (text, UTF-8/ASCII, '#' starts a comment to the end of the line, blank lines skipped):
//     quadcast-slim 2                      magic and version (this reader also reads 1, which
//                                          has no second plane)
//     balls N                              record count
//     ball cx cy cz r k000 k100 k010 k001 k110 k011 k101 k200 k020 k002 [plane a b c d [plane a b c d]]
//                                          N lines; k.. are quadcast::Coefficients10 (world):
//     f = k000 + k100 x + k010 y + k001 z + k110 xy + k011 yz + k101 zx + k200 x^2 + k020 y^2 + k002 z^2
// Numbers are written with 17 significant digits (doubles round-trip). Reader errors
// (scene::ParseError, file:line and field): wrong magic or version, a missing/garbled count,
// a wrong number of values, a non-number or non-finite value, r <= 0, a zero quadric, a plane
// with a zero normal, a second plane in a version 1 file, fewer or more ball lines than the count.

#include <filesystem>
#include <istream>
#include <ostream>
#include <string>
#include <vector>

#include "quadcast/linalg.hpp"
#include "quadcast/quadric.hpp"
#include "quadcast/scene/diagnostics.hpp"

namespace quadcast::slim {

struct Ball {
    Vec<double, 3> center{};
    double radius = 0;
    Quadric<double> q{};              ///< world coordinates
    bool has_plane = false;
    Vec<double, 4> plane{};           ///< world; keep dot(plane.xyz, x) + plane.w >= 0
    bool has_plane2 = false;          ///< a corner's second clip plane (only with has_plane)
    Vec<double, 4> plane2{};          ///< world; keep dot(plane2.xyz, x) + plane2.w >= 0 too
};

struct Model {
    std::vector<Ball> balls;
};

inline constexpr int model_format_version = 2;

void write_model(std::ostream& out, const Model& model);
/// Writes to `path` (through a temporary file renamed into place). Throws std::runtime_error.
void write_model(const std::filesystem::path& path, const Model& model);
/// Throws scene::ParseError.
Model parse_model(std::istream& in, const std::string& file_name);
Model read_model(const std::filesystem::path& path);

}  // namespace quadcast::slim
