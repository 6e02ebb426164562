// quadcast/slim/fit.hpp -- one SLIM ball's quadric: weighted least squares on points and normals
#pragma once

// Host-only (double, Eigen inside). The fit of one ball of a SLIM surface (Ohtake, Belyaev &
// Alexa 2005, sec. 3): the quadric f that best passes through the ball's points with its
// gradient parallel to their normals, in coordinates local to the ball, u = (x - c) / r, so that
// the points lie in the unit ball whatever the model's size and position.
//
// The problem (Hermite least squares with one normalisation constraint):
//     minimise  sum_i w_i [ f(u_i)^2 + lambda^2 |n_i x grad f(u_i)|^2 ] + mu sum_{quadratic k} k^2
//     subject to  sum_i w_i n_i . grad f(u_i) = sum_i w_i
// Every term is linear in the 10 coefficients, so this is one 11x11 KKT system (solved by a
// full-pivoting LU). A quadric's own samples (normals = grad f / |grad f|) give zero residual
// for the true f, so the fit recovers it up to scale whatever the gradient's magnitude varies
// like (fitting grad f = n instead would bend an ellipsoid); mu (1e-8 of the mean weight) only
// decides the coefficients the data leave free, e.g. the z^2 of a plane z = 0, which it keeps 0.
// The constraint fixes the orientation: grad f points along the normals, i.e. f < 0 inside
// (normals point outward, to f > 0). Afterwards f is divided by the weighted mean of |grad f|
// over the points, so |grad f| ~ 1 near the surface and f is close to a signed distance.
// Weights are uniform (w_i = 1): the acceptance test below is a maximum over all the ball's
// points, so the boundary points count as much as the centre's.

#include <cstddef>
#include <cstdint>
#include <vector>

#include "quadcast/linalg.hpp"
#include "quadcast/quadric.hpp"

namespace quadcast::slim {

using Vec3d = Vec<double, 3>;
using Vec4d = Vec<double, 4>;

struct FitOptions {
    /// lambda: weight of the normal residual |n x grad f| (unitless) against the value residual f
    /// (local length units, ~ distance / r).
    double normal_weight = 0.25;
    /// mu: Tikhonov weight on the 6 quadratic coefficients, relative to the mean weight.
    double regularization = 1e-8;
};

/// One fit. `local` is f in the ball's coordinates u = (x - c) / r (|grad f| ~ 1 in u).
struct LocalFit {
    bool solved = false;           ///< false: the system was singular or the result not finite
    Quadric<double> local{};
    double max_distance = 0;       ///< over the fitted points, in world units (r times local)
    double rms_distance = 0;       ///< world units
    bool oriented = false;         ///< grad f . n_i > 0 at every fitted point
    double min_normal_cos = -1;    ///< the smallest cosine of the angle between grad f and n_i over the fitted points
};

/// Fits the points `idx` (indices into `positions` / `normals`, unit normals) in the ball
/// (c, r). The distances are `gradient_line_distance` of each point. Needs idx.size() >= 10
/// (fewer: solved = false).
LocalFit fit_ball(const std::vector<Vec3d>& positions, const std::vector<Vec3d>& normals,
                  const std::vector<std::uint32_t>& idx, const Vec3d& c, double r, const FitOptions& options = {});

/// Distance from x to the zero set of q along the line through x in the direction of grad f(x):
/// the smallest |t| with f(x + t g^) = 0, g^ = grad f / |grad f|, a root of
/// a t^2 + |g| t + f = 0, a = g^T A g / |g|^2 (f(x + s) = f + grad f . s + s^T A s). An upper
/// bound of the Euclidean distance, exact for planes and spheres, and |f| / |grad f| to first
/// order. +inf when that line misses the surface (a negative discriminant) or grad f = 0 with
/// f != 0.
/// Numerics: t = -2 f / (|g| + sqrt(|g|^2 - 4 a f)) (no cancellation: both terms >= 0).
double gradient_line_distance(const Quadric<double>& q, const Vec3d& x);

/// The world quadric F(x) = r f((x - c) / r) of a ball-local one (|grad F| = |grad f|):
/// A / r, b, r c in coordinates y = x - c, then moved to the world origin (translate_to_eye by -c).
Quadric<double> local_to_world(const Quadric<double>& local, const Vec3d& c, double r);
/// Inverse of `local_to_world` (up to rounding).
Quadric<double> world_to_local(const Quadric<double>& world, const Vec3d& c, double r);

}  // namespace quadcast::slim
