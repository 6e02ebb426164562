// quadcast/render/occluder.hpp -- the occluder ball of a primitive (occlusion culling, quadcast/occlusion.hpp)
#pragma once

// Host-only (double). A closed convex primitive occludes with a ball around its centre that lies
// inside its solid: then the disk of that ball perpendicular to the viewing axis is inside the
// solid too, and every ray crossing the disk has met the surface before.

#include <algorithm>
#include <cmath>

#include "quadcast/render/types.hpp"
#include "quadcast/render/validate.hpp"

namespace quadcast::render {

/// The radius of a ball around `p.shape.center` inside the primitive's solid, times 1 - 2^-10
/// (the margin `occluder_covers` relies on); 0 when the primitive does not occlude this way:
/// - sphere variant: the sphere itself (its bounding radius is its radius);
/// - ellipsoid variant, centred (the shapes' case): the shortest semi-axis sqrt(-k / lambda_max);
/// - slab variant closed at both ends whose quadric is a centred cylinder along the slab axis
///   (A axis = 0, b = 0: every section the same ellipse): min(shortest semi-axis, half_length);
/// - anything else (open slabs, cones, bounded and planes variants): 0.
/// `p` must have passed `validate`.
inline float occluder_radius(const Primitive& p) {
    using namespace validate_detail;
    constexpr double margin = 1.0 - 1.0 / 1024.0;
    if (p.variant == Variant::sphere) return static_cast<float>(static_cast<double>(p.shape.radius) * margin);
    if (p.variant != Variant::ellipsoid && p.variant != Variant::slab) return 0.0f;
    M3 a{};
    V3 b{};
    double c = 0;
    split(p.shape.q.q, a, b, c);
    V3 lam = symmetric_eigenvalues(a);
    if (lam[2] <= 0) {  // -f: the same surface with the inside f < 0
        for (int j = 0; j < 3; ++j)
            for (int i = 0; i < 3; ++i) a[j][i] = -a[j][i];
        b = -b;
        c = -c;
        lam = vec3(-lam[2], -lam[1], -lam[0]);
    }
    const double scale = lam[2];
    if (!(scale > 0) || !(c < 0)) return 0.0f;
    // Centred: |b| small against the size of the form (b = 0 for the shapes' quadrics, up to rounding).
    if (length(b) > 1e-6 * std::sqrt(scale * -c)) return 0.0f;
    double r = std::sqrt(-c / scale);
    if (p.variant == Variant::ellipsoid) {
        if (!(lam[0] > 0)) return 0.0f;
    } else {
        if (!(p.shape.caps[0] == 1.0f && p.shape.caps[1] == 1.0f)) return 0.0f;
        const V3 ax = normalize(cast<double>(p.shape.axis));
        if (length(a * ax) > 1e-6 * scale || !(lam[1] > 1e-6 * scale)) return 0.0f;
        r = std::min(r, static_cast<double>(p.shape.half_length));
    }
    return static_cast<float>(r * margin);
}

/// The view distances an occluder ball must lie strictly between (`occluder_usable`): the near
/// and far planes of the camera's projection, 1e-5 of themselves inside (and the near distance
/// not below 0, so that every depth written is a positive float). Perspective: z_ndc =
/// (P22 z + P32) / -z gives near = P32 / (P22 - 1), far = P32 / (P22 + 1); orthographic: z_ndc =
/// P22 z + P32 gives near = (P32 + 1) / P22, far = (P32 - 1) / P22 (in double).
struct OcclusionRange {
    float near, far;
};

inline OcclusionRange occlusion_range(const Camera& cam) {
    // `occluder_ellipse` needs view x and y mapped to NDC x and y without mixing and w free of
    // them (every perspective and orthographic projection, off-axis ones included); another
    // projection gets an empty range: no occluders.
    const Mat4<float>& p = cam.projection;
    if (p[1][0] != 0.0f || p[0][1] != 0.0f || p[0][3] != 0.0f || p[1][3] != 0.0f) return {1.0f, 0.0f};
    const double p22 = cam.projection[2][2], p32 = cam.projection[3][2];
    const double n = cam.orthographic ? (p32 + 1.0) / p22 : p32 / (p22 - 1.0);
    const double f = cam.orthographic ? (p32 - 1.0) / p22 : p32 / (p22 + 1.0);
    return {static_cast<float>(std::max(n, 0.0) * (1.0 + 1e-5)), static_cast<float>(f * (1.0 - 1e-5))};
}

}  // namespace quadcast::render
