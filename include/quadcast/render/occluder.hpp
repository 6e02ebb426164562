// quadcast/render/occluder.hpp -- the occluder ball of a primitive (occlusion culling, quadcast/occlusion.hpp)
#pragma once

// Host-only (double). A closed convex primitive occludes with a ball around its centre that lies
// inside its solid: then the disk of that ball perpendicular to the viewing axis is inside the
// solid too, and every ray crossing the disk has met the surface before.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <vector>

#include "quadcast/render/types.hpp"
#include "quadcast/render/validate.hpp"

namespace quadcast::render {

/// What a primitive occludes with (`occluder_radius`, `occluder_half_axis`).
struct OccluderShape {
    float r_in = 0.0f;     ///< `occluder_radius`
    Vec3<float> half_axis{{0.0f, 0.0f, 0.0f}};  ///< `occluder_half_axis`
};
inline OccluderShape occluder_shape(const Primitive& p);

/// The radius of a ball around `p.shape.center` inside the primitive's solid (f < 0 as stored:
/// the side the fragment stage's front-root selection treats as inside), times 15/16 (the margin
/// `occluder_ellipse` and `occluder_usable` rely on); 0 when the primitive does not occlude this way:
/// - sphere variant: the sphere itself (its bounding radius is its radius);
/// - ellipsoid variant, centred (the shapes' case): the shortest semi-axis sqrt(-k / lambda_max);
/// - slab variant closed at both ends whose quadric is a centred cylinder along the slab axis
///   (A axis = 0, b = 0: every section the same ellipse): min(shortest semi-axis,
///   half_length / |axis|) (the slab is |axis . x| <= half_length);
/// - anything else (open slabs, cones, bounded and planes variants): 0.
/// `p` must have passed `validate`.
inline float occluder_radius(const Primitive& p) { return occluder_shape(p).r_in; }

/// A chain of occluder balls along a closed centred cylinder (the slab case of
/// `occluder_radius`) whose half length h = half_length / |axis| exceeds its shortest semi-axis
/// rho: the balls of radius rho centred on the axis within h - rho of the centre lie inside the
/// solid, so each disk of radius `occluder_radius` (rho 15/16) around c + t half_axis, |t| <= 1,
/// with half_axis = axis / |axis| (h - rho), is an occluder (quadcast::occluder_chain_disk).
/// A capped stick of length 10 radii occludes with the sausage of 10 disks instead of one disk.
/// Zero for every other primitive.
inline Vec3<float> occluder_half_axis(const Primitive& p) { return occluder_shape(p).half_axis; }

/// Whether `o` is a chain of several disks (a non-zero `occluder_half_axis`) rather than one disk.
inline bool occluder_is_chain(const OccluderShape& o) { return o.half_axis[0] != 0.0f || o.half_axis[1] != 0.0f || o.half_axis[2] != 0.0f; }

/// Both at once (one eigen-decomposition).
inline OccluderShape occluder_shape(const Primitive& p) {
    using namespace validate_detail;
    constexpr double margin = 15.0 / 16.0;
    if (p.variant == Variant::sphere) return {static_cast<float>(static_cast<double>(p.shape.radius) * margin), {}};
    if (p.variant != Variant::ellipsoid && p.variant != Variant::slab) return {};
    M3 a{};
    V3 b{};
    double c = 0;
    split(p.shape.q.q, a, b, c);
    // As stored: with f > 0 inside, front-root selection shows the far wall (not an occluder).
    const V3 lam = symmetric_eigenvalues(a);
    const double scale = lam[2];
    if (!(scale > 0) || !(c < 0)) return {};
    // Centred: |b| small against the size of the form (b = 0 for the shapes' quadrics, up to rounding).
    if (length(b) > 1e-6 * std::sqrt(scale * -c)) return {};
    double r = std::sqrt(-c / scale);
    OccluderShape out;
    if (p.variant == Variant::ellipsoid) {
        if (!(lam[0] > 0)) return {};
    } else {
        if (!(p.shape.caps[0] == 1.0f && p.shape.caps[1] == 1.0f)) return {};
        const V3 axis = cast<double>(p.shape.axis), ax = normalize(axis);
        if (length(a * ax) > 1e-6 * scale || !(lam[0] > -1e-6 * scale) || !(lam[1] > 1e-6 * scale)) return {};
        const double h = static_cast<double>(p.shape.half_length) / length(axis);
        // (1 - 2^-20: the float rounding of the half axis stays inside h - r)
        if (h > r) out.half_axis = cast<float>(ax * ((h - r) * (1.0 - 1.0 / 1048576.0)));
        r = std::min(r, h);
    }
    out.r_in = static_cast<float>(r * margin);
    return out;
}

/// The view distances an occluder ball must lie strictly between (`occluder_usable`): the near
/// and far planes of the camera's projection, 1e-5 of themselves inside (and the near distance
/// not below 0, so that every depth written is a positive float). Perspective: z_ndc =
/// (P22 z + P32) / -z gives near = P32 / (P22 - 1), far = P32 / (P22 + 1); orthographic: z_ndc =
/// P22 z + P32 gives near = (P32 + 1) / P22, far = (P32 - 1) / P22 (in double).
///
/// `gap`: the shortest distance along the viewing axis, in units of the disk's radius rho, by
/// which a ball of radius rho 16/15 lies in front of its central disk of radius rho along any
/// pixel ray: for a ray at angle theta to the axis crossing the disk at its rim, the smallest
/// t >= 0 with (rho + t tan theta)^2 + t^2 = (16/15 rho)^2, at the largest tan theta of the view
/// (its corners; 0 for orthographic cameras), times 0.99.
/// A projection of another form than glm's perspective, frustum and ortho matrices (x and y
/// unmixed, z and w free of them, w = -z or 1) gets an empty range: no occluders.
struct OcclusionRange {
    float near, far, gap;
};

inline OcclusionRange occlusion_range(const Camera& cam) {
    const OcclusionRange none{1.0f, 0.0f, 0.0f};
    const Mat4<float>& p = cam.projection;
    if (p[1][0] != 0.0f || p[0][1] != 0.0f || p[0][2] != 0.0f || p[1][2] != 0.0f || p[0][3] != 0.0f || p[1][3] != 0.0f) return none;
    if (cam.orthographic ? !(p[2][3] == 0.0f && p[3][3] == 1.0f) : !(p[2][3] == -1.0f && p[3][3] == 0.0f)) return none;
    const double p22 = p[2][2], p32 = p[3][2];
    const double n = cam.orthographic ? (p32 + 1.0) / p22 : p32 / (p22 - 1.0);
    const double f = cam.orthographic ? (p32 - 1.0) / p22 : p32 / (p22 + 1.0);
    if (!(f > n) || !std::isfinite(n) || !std::isfinite(f)) return none;
    double tan2 = 0.0;
    if (!cam.orthographic) {
        const double tx = (1.0 + std::fabs(double(p[2][0]))) / std::fabs(double(p[0][0])), ty = (1.0 + std::fabs(double(p[2][1]))) / std::fabs(double(p[1][1]));
        tan2 = tx * tx + ty * ty;
    }
    const double t = std::sqrt(tan2), R2 = (16.0 / 15.0) * (16.0 / 15.0);
    const double gap = (-t + std::sqrt(tan2 + (1.0 + tan2) * (R2 - 1.0))) / (1.0 + tan2) * 0.99;
    if (!(gap > 1e-3)) return none;
    return {static_cast<float>(std::max(n, 0.0) * (1.0 + 1e-5)), static_cast<float>(f * (1.0 - 1e-5)), static_cast<float>(gap)};
}

/// Whether the cull pass pays (RenderOptions::occlusion_min_overlap): it costs a roughly fixed
/// few milliseconds plus work per primitive and per occluder pixel, and saves only the fragments
/// of hidden primitives, of which there are few where primitives rarely overlap on screen. The
/// renderer decides per frame from the frame's expected overlap: the pixels the primitives cover,
/// summed and divided by the viewport's pixels (how many primitive layers an average pixel has).
/// An estimate from a sample, to decide with, not a bound; the picture is the same either way.

/// A primitive as a capsule for `expected_overlap`: the segment centre +- half_axis swept by a
/// ball of radius rho (centre x, y, z, half axis x, y, z, rho). Slabs (cylinders, cones): the
/// segment of the axis inside the slab, rho = sqrt(R^2 - h^2) with R the bounding radius and h
/// the slab's half length along the unit axis (a cylinder's radius; a cone's larger end's for
/// the shapes' cones); every other variant: its bounding ball.
inline std::array<float, 7> overlap_capsule(const Primitive& p) {
    const ClippedQuadric<float>& s = p.shape;
    std::array<float, 7> out{{s.center[0], s.center[1], s.center[2], 0.0f, 0.0f, 0.0f, s.radius}};
    if (p.variant != Variant::slab && p.variant != Variant::open_slab) return out;
    const Vec3<double> axis = cast<double>(s.axis);
    const double a = length(axis);
    if (!(a > 0.0)) return out;
    const double h = std::min(double(s.half_length) / a, double(s.radius)), R = s.radius;
    for (int i = 0; i < 3; ++i) out[static_cast<std::size_t>(3 + i)] = static_cast<float>(axis[i] / a * h);
    out[6] = static_cast<float>(std::sqrt(std::max(R * R - h * h, 0.0)));
    return out;
}

/// The primitives `expected_overlap` looks at: at most `max_capsules` of them, evenly strided,
/// as capsules (`overlap_capsule`), each standing for `weight` primitives.
struct OverlapSample {
    std::vector<std::array<float, 7>> capsules;
    double weight = 0.0;
};

inline OverlapSample overlap_sample(const std::vector<Primitive>& prims, std::size_t max_capsules = 4096) {
    OverlapSample s;
    if (prims.empty() || max_capsules == 0) return s;
    const std::size_t stride = (prims.size() + max_capsules - 1) / max_capsules;
    for (std::size_t i = 0; i < prims.size(); i += stride) s.capsules.push_back(overlap_capsule(prims[i]));
    s.weight = double(prims.size()) / double(s.capsules.size());
    return s;
}

/// The pixels of a width x height view a capsule (`overlap_capsule`) covers, estimated: its
/// centre projected with the camera's matrices; at the centre's clip w, a ball of radius rho
/// covers pi rho_x rho_y pixels and the segment adds 2 rho L, L the projected length of the axis
/// (rho_x = rho P00 width / (2 w), rho_y likewise with P11 and height; perspective
/// foreshortening across the capsule is left out). That area times the share of the capsule's
/// screen box inside the viewport. A capsule behind the eye plane covers nothing; one reaching
/// to it (a perspective camera inside or beside it) counts as the whole viewport.
/// `view` and `proj` are the camera's matrices in double (`expected_overlap` casts them once).
inline double capsule_pixels(const Mat4<double>& view, const Mat4<double>& proj, bool orthographic, int width, int height, const std::array<float, 7>& c) {
    const Vec4<double> vc = view * Vec4<double>{{c[0], c[1], c[2], 1.0}};
    const Vec4<double> va = view * Vec4<double>{{c[3], c[4], c[5], 0.0}};
    const double rho = c[6], half = std::sqrt(va[0] * va[0] + va[1] * va[1] + va[2] * va[2]);
    const double W = width, H = height;
    if (!orthographic) {
        const double s = -vc[2], reach = rho + half;
        if (s < -reach) return 0.0;
        if (s <= reach) return W * H;
    }
    const Vec4<double> clip = proj * vc;
    if (!(clip[3] > 0.0)) return 0.0;
    const double kx = std::fabs(proj[0][0]) * 0.5 * W / clip[3], ky = std::fabs(proj[1][1]) * 0.5 * H / clip[3];
    const double cx = (clip[0] / clip[3] + 1.0) * 0.5 * W, cy = (clip[1] / clip[3] + 1.0) * 0.5 * H;
    const double lx = 2.0 * va[0] * kx, ly = 2.0 * va[1] * ky;
    const double rx = rho * kx, ry = rho * ky, r = std::sqrt(rx * ry);
    const double area = 3.14159265358979323846 * rx * ry + 2.0 * r * std::sqrt(lx * lx + ly * ly);
    const double ex = rx + 0.5 * std::fabs(lx), ey = ry + 0.5 * std::fabs(ly);  // half extents of its box
    auto inside = [](double centre, double e, double size) {
        if (!(e > 0.0)) return centre >= 0.0 && centre <= size ? 1.0 : 0.0;
        return std::clamp((std::min(centre + e, size) - std::max(centre - e, 0.0)) / (2.0 * e), 0.0, 1.0);
    };
    return std::min(area * inside(cx, ex, W) * inside(cy, ey, H), W * H);
}
inline double capsule_pixels(const Camera& cam, int width, int height, const std::array<float, 7>& c) {
    return capsule_pixels(cast<double>(cam.view), cast<double>(cam.projection), cam.orthographic, width, height, c);
}

/// The expected overlap of a frame: the sample's covered pixels (`capsule_pixels`) times its
/// weight, over the viewport's pixels. 0 for an empty sample or viewport.
inline double expected_overlap(const OverlapSample& s, const Camera& cam, int width, int height) {
    if (s.capsules.empty() || width <= 0 || height <= 0) return 0.0;
    const Mat4<double> view = cast<double>(cam.view), proj = cast<double>(cam.projection);
    double sum = 0.0;
    for (const auto& c : s.capsules) sum += capsule_pixels(view, proj, cam.orthographic, width, height, c);
    return sum * s.weight / (double(width) * double(height));
}

}  // namespace quadcast::render
