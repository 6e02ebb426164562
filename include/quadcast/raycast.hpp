// quadcast/raycast.hpp -- the per-primitive and per-fragment stages of quadric ray casting
#pragma once

#include "quadcast/bounds.hpp"
#include "quadcast/cull.hpp"
#include "quadcast/linalg.hpp"
#include "quadcast/quadric.hpp"
#include "quadcast/ray.hpp"
#include "quadcast/scalar.hpp"

namespace quadcast {

/// A quadric primitive as a renderer stores it: the quadric in LOCAL coordinates
/// (x_local = x_world - center, which keeps its coefficients small and the re-origined
/// discriminant accurate), clipped to the bounding sphere (center, radius) and, for cylinders
/// and cones, to the slab |dot(axis, x_local)| <= half_length, each end closed by a flat cap or
/// left open.
template <class T>
struct ClippedQuadric {
    Quadric<T> q;
    Vec3<T> center;
    T radius;
    Vec3<T> axis;     ///< unit slab axis (used by the `slab` variants only)
    T half_length;
    /// Caps of the slab variants: caps[0] closes the end dot(axis, x) = +half_length, caps[1]
    /// the end -half_length; 1 = closed by a disc, 0 = open.
    Vec2<T> caps{{T(1), T(1)}};
    /// Inward planes (local coordinates) of a convex clip volume, for the `planes` variants: the
    /// faces of a bounding tetrahedron (bilinear quads, tetrahedral quadric patches), or the edge
    /// planes of a planar quad, scaled as barycentric coordinates (see `inside_planes`).
    Vec4<T> planes[4];
};

/// What a ray needs at a fragment, in local coordinates: origin o, direction v and the terms
/// g = A o + b and a = A v (Stoll et al. 2006, sec. 5). All four are affine in the ray's origin
/// and direction; the renderers build them per fragment from the pixel's ray (`window_ray`,
/// `local_ray`) rather than let the rasteriser interpolate them over the bounding geometry, whose
/// rounding would then depend on that geometry.
template <class T>
struct LocalRay {
    Vec3<T> o, v, g, a;
};

/// A world-space ray (origin, direction; not normalised).
template <class T>
struct WorldRay {
    Vec3<T> origin, dir;
};

/// The world-space ray through the view-space point p (a corner of a bounding quad, or a pixel
/// centre on the near plane) of a camera at `eye` with inverse view rotation R^T
/// (`view_rot_inv`, view -> world): perspective, origin = eye and dir = R^T p; orthographic,
/// origin = eye + (R^T_0 p_x + R^T_1 p_y) and dir = -R^T_2 (the viewing direction).
/// Numerics: R^T p is linalg's matrix-vector product (a left fold over the columns); the
/// orthographic origin is eye + (c0 p_x + c1 p_y).
template <bool Ortho, class T>
WorldRay<T> view_point_ray(const Mat3<T>& view_rot_inv, const Vec3<T>& eye, const Vec3<T>& p) {
    if constexpr (Ortho) return {eye + (view_rot_inv[0] * p[0] + view_rot_inv[1] * p[1]), -view_rot_inv[2]};
    else return {eye, view_rot_inv * p};
}

/// The world-space ray through the window position `frag` (a pixel centre: gl_FragCoord.xy in
/// the fragment stage, (x + 0.5, y + 0.5) in the CPU reference). The camera's rays are affine in
/// the window position: with the frame's terms (base, dx, dy) (`render::window_ray_terms`),
/// perspective, origin = `fixed` (the eye) and dir = base + x dx + y dy (R^T of the view-space
/// near-plane point); orthographic, origin = base + x dx + y dy (in the camera plane through the
/// eye) and dir = `fixed` (the viewing direction). The ray depends on the pixel only, not on the
/// bounding geometry a primitive is drawn over, so every bound gives the same image.
/// Numerics: (base + dx * x) + dy * y per component.
template <bool Ortho, class T>
WorldRay<T> window_ray(const Vec3<T>& base, const Vec3<T>& dx, const Vec3<T>& dy, const Vec3<T>& fixed, const Vec2<T>& frag) {
    const Vec3<T> affine = (base + dx * frag[0]) + dy * frag[1];
    if constexpr (Ortho) return {affine, fixed};
    else return {fixed, affine};
}

/// The local ray for a world-space ray (origin, dir).
/// Numerics: o = origin - center; g = A o + b, a = A v (left folds).
template <class T>
LocalRay<T> local_ray(const ClippedQuadric<T>& p, const Vec3<T>& origin, const Vec3<T>& dir) {
    const Mat3<T> A = upper3(p.q.q);
    const Vec3<T> o = origin - p.center;
    return {o, dir, A * o + xyz(p.q.q[3]), A * dir};
}

/// Per-quadric back-face culling of a primitive for an eye at local position o (Stoll et al.
/// 2006, sec. 4.4.4, `cull_sphere` against the bounding sphere): true when no ray from the eye
/// can meet a front-facing point of the quadric in its bound.
/// Numerics: `cull_sphere` (conservative under rounding).
template <class T>
mask_t<T> cull_primitive(const ClippedQuadric<T>& p, const Vec3<T>& o) {
    return cull_sphere(p.q, o, vec3(T(0), T(0), T(0)), p.radius);
}

/// `cull_primitive` for the capped `slab` variants: the caps are planes whose outward normals
/// face away from an eye strictly between them, so the primitive is culled only when the
/// quadric is culled AND |dot(axis, o)| < half_length.
template <class T>
mask_t<T> cull_primitive_with_caps(const ClippedQuadric<T>& p, const Vec3<T>& o) {
    return cull_primitive(p, o) && (abs(dot(p.axis, o)) < p.half_length);
}

/// Options of a fragment-stage variant (plain C++ values: each combination is one kernel).
struct CastOptions {
    bool cull = true;   ///< front-facing surface only (per-fragment back-face culling, Stoll eq. 14)
    bool slab = false;  ///< clip to the slab and close it with caps (cylinders, cones)
    bool bound = true;  ///< clip to the bounding sphere (general quadrics; spheres/ellipsoids need not)
    bool planes = false;  ///< clip to the four planes (tetrahedra, planar quads)
    /// The sphere x.x = radius^2 (local coordinates) in closed form (`ray_quadratic_sphere`): the
    /// quadric's coefficients and the ray terms g, a are not read. No clipping.
    bool sphere = false;
    /// Clip to the half-spaces dot(planes[0], (x, 1)) >= 0 and dot(planes[1], (x, 1)) >= 0 too (the
    /// optional clip planes of a SLIM ball: one at a sharp edge, Stoll et al. 2006, fig. 8, two at a
    /// corner; local coordinates; (0, 0, 0, 1) keeps everything).
    bool clip_plane = false;
};

/// A fragment's hit: ray parameter, local position and (unnormalised) outward normal.
template <class T>
struct CastHit {
    mask_t<T> hit;
    T lambda;
    Vec3<T> x;
    Vec3<T> normal;
};

/// The clip test of the `planes` variants: dot(plane[i], (x, 1)) >= -clip_plane_slack (2^-12)
/// for all four planes.
/// The planes are stored scaled to 1 at the farthest corner (barycentric coordinates of a
/// tetrahedron; for a quad, its four edges extruded along the quad's normal), so the slack is
/// relative to the element's size. Neighbouring patches share edges, on which a hit lies on a
/// plane of both; without slack rounding can reject it from both (pinholes along shared edges).
/// Quads are clipped by their extruded edges, not by their tetrahedron: a nearly planar quad has
/// a thin tetrahedron whose faces are almost tangent to the patch, so tiny normal errors of a
/// hit become large barycentric errors there, and any slack admits a strip of the quadric
/// beyond the patch; the extruded edge planes are perpendicular to the patch instead.
/// Numerics: four left-fold dot products and comparisons.
template <class T>
mask_t<T> inside_planes(const ClippedQuadric<T>& p, const Vec3<T>& x) {
    const Vec4<T> xh = vec4(x, T(1));
    const T slack = T(-clip_plane_slack);
    return ((dot(p.planes[0], xh) >= slack && dot(p.planes[1], xh) >= slack) && dot(p.planes[2], xh) >= slack) &&
           dot(p.planes[3], xh) >= slack;
}

namespace raycast_detail {

template <class T>
struct Candidate {
    mask_t<T> ok;
    T lambda;
    Vec3<T> normal;
};

/// The nearer of two candidates (a wins ties); a candidate that is not ok never wins.
template <class T>
Candidate<T> nearer(const Candidate<T>& a, const Candidate<T>& b) {
    const mask_t<T> take_b = b.ok && (!a.ok || b.lambda < a.lambda);
    return {a.ok || b.ok, select(take_b, b.lambda, a.lambda), select(take_b, b.normal, a.normal)};
}

}  // namespace raycast_detail

/// Casts a fragment's ray at a primitive (Stoll et al. 2006, sec. 4.2-4.4 and 5, with the
/// re-origined discriminant of `ray_quadratic_incremental` and the stable root formulas).
/// - cull: only the front-facing root (eq. 14); otherwise the nearer valid root first, the
///   farther one where the nearer fails the clip (eq. 15, corrected: `roots_near_first`).
/// - bound: the hit must lie in the bounding sphere, |x|^2 <= radius^2.
/// - planes: the hit must lie inside the four planes (`inside_tet`).
/// - clip_plane: the hit must lie on the kept side of planes[0] and of planes[1]
///   (dot(planes[i], (x, 1)) >= 0).
/// - slab: the hit must lie in the slab; the caps dot(axis, x) = +-half_length that are closed
///   (caps[0], caps[1] > 0) are hit where the quadric's inside (f <= 0) is, or where the cap
///   crossing's ray parameter equals the quadric's entry root to 2^-18 of itself (the rim: there
///   float rounding can reject both the wall hit, just beyond the cap plane, and the cap point,
///   just outside the quadric, leaving a pinhole), with normal +-axis; with cull only the caps
///   facing the ray.
/// - sphere: the quadric is the sphere |x| = radius (`ray_quadratic_sphere`), normal o + lambda v.
/// The nearest candidate wins. Normal of a quadric hit: A x + b = g + lambda a (eq. 11).
/// Numerics: see the functions named; the cap parameter is (s h - dot(axis, o)) / dot(axis, v).
template <CastOptions Opt, class T>
CastHit<T> cast_ray(const ClippedQuadric<T>& p, const LocalRay<T>& r_eye) {
    using namespace raycast_detail;
    const T r2 = p.radius * p.radius;
    // planes: the ray starts where it enters the sphere of twice the bounding radius, at ray
    // parameter t0, with g = A o + b taken afresh there. From the eye, hundreds of radii away
    // for a small piece, f(o) and the re-origined discriminant carry errors of order eps |o|^2
    // that move the root by up to 1e-4 of the piece's size, and a hit near a face it does not
    // continue across falls outside the clip test's slack (pinholes through finite-element and
    // isosurface pieces seen from afar). What the clip accepts lies in the bounding sphere
    // (tetrahedra: `planes_within_ball`; a bilinear patch in its corners' hull); the doubled
    // radius leaves room for rounding and costs nothing in accuracy.
    // Numerics: vv = v.v; t0 = (-(o.v) - (2 radius) sqrt(vv)) / vv where vv > 0 and that is
    // positive, else 0; o' = o + t0 v; g' = A o' + b (left folds).
    LocalRay<T> r = r_eye;
    T t0{};
    if constexpr (Opt.planes) {
        const T vv = dot(r_eye.v, r_eye.v);
        const mask_t<T> moving = vv > T(0);
        const T entry = (-dot(r_eye.o, r_eye.v) - (p.radius * T(2)) * sqrt(vv)) / select(moving, vv, T(1));
        t0 = select(moving && (entry > T(0)), entry, T(0));
        r.o = r_eye.o + t0 * r_eye.v;
        r.g = upper3(p.q.q) * r.o + xyz(p.q.q[3]);
    }
    const RayQuadratic<T> rq = [&] {
        if constexpr (Opt.sphere) return ray_quadratic_sphere(r2, r.o, r.v);
        else return ray_quadratic_incremental(p.q, r.o, r.v, r.g, r.a);
    }();
    // The clip of a point at ray parameter lambda.
    auto clip = [&](const T& lambda) {
        const Vec3<T> x = r.o + lambda * r.v;
        mask_t<T> in = mask_t<T>(true);
        if constexpr (Opt.bound) in = dot(x, x) <= r2;
        if constexpr (Opt.slab) in = in && (abs(dot(p.axis, x)) <= p.half_length);
        if constexpr (Opt.planes) in = (in && inside_planes(p, x)) && (abs(dot(p.axis, x)) <= p.half_length);
        if constexpr (Opt.clip_plane) {
            const Vec4<T> xh = vec4(x, T(1));
            in = (in && (dot(p.planes[0], xh) >= T(0))) && (dot(p.planes[1], xh) >= T(0));
        }
        return in;
    };
    auto quadric_candidate = [&](const T& lambda, const mask_t<T>& valid) {
        if constexpr (Opt.sphere) return Candidate<T>{valid && clip(lambda), lambda, r.o + lambda * r.v};
        else return Candidate<T>{valid && clip(lambda), lambda, r.g + lambda * r.a};
    };
    // Roots of the quadric, clipped.
    Candidate<T> best{};
    T entry{};            // the quadric root where the ray enters (clipped or not)
    mask_t<T> entry_ok{};
    if constexpr (Opt.cull) {
        const RayHit<T> h = front_root(rq);
        best = quadric_candidate(h.lambda, h.hit);
        entry = h.lambda;
        entry_ok = h.hit;
    } else {
        const RootPair<T> pr = roots_near_first(rq);
        best = nearer(quadric_candidate(pr.lambda_near, pr.near_valid), quadric_candidate(pr.lambda_far, pr.far_valid));
        entry = pr.lambda_near;
        entry_ok = pr.near_valid;
    }
    // Caps of the slab.
    if constexpr (Opt.slab) {
        const T av = dot(p.axis, r.v);
        const T ao = dot(p.axis, r.o);
        const mask_t<T> ok_den = av != T(0);
        const T den = select(ok_den, av, T(1));
        for (int s = 0; s < 2; ++s) {
            const T sign = s == 0 ? T(1) : T(-1);
            const T lambda = (sign * p.half_length - ao) / den;
            const Vec3<T> x = r.o + lambda * r.v;
            // At the rim the wall's entry and the cap crossing coincide, and rounding can put the
            // first beyond the cap plane and the second outside the quadric: the cap is kept too
            // where the two ray parameters agree to 2^-18.
            const mask_t<T> rim = entry_ok && (abs(lambda - entry) <= lambda * T(0.000003814697265625));
            mask_t<T> ok = ((ok_den && lambda > T(0)) && ((evaluate(p.q, x) <= T(0)) || rim)) && (p.caps[s] > T(0));
            if constexpr (Opt.bound) ok = ok && dot(x, x) <= r2;
            if constexpr (Opt.cull) ok = ok && (sign * av < T(0));
            best = nearer(best, Candidate<T>{ok, lambda, sign * p.axis});
        }
    }
    if constexpr (Opt.planes) return {best.ok, t0 + best.lambda, r.o + best.lambda * r.v, best.normal};
    else return {best.ok, best.lambda, r.o + best.lambda * r.v, best.normal};
}

/// Window depth of the point at ray parameter lambda, for a ray whose origin lies in the
/// camera plane (view-space z = 0: the eye of a perspective camera, or a point of the image
/// plane of an orthographic one). vz = view-space z of the ray direction; pz = (P22, P32, P23,
/// P33) of the projection matrix (column-major P[col][row]): z_clip = P22 z + P32,
/// w_clip = P23 z + P33, depth = 0.5 z_clip / w_clip + 0.5 (glDepthRange 0..1).
template <class T>
T window_depth(const T& lambda, const T& vz, const Vec4<T>& pz) {
    const T z = lambda * vz;
    return T(0.5) * ((pz[0] * z + pz[1]) / (pz[2] * z + pz[3])) + T(0.5);
}

/// What the fragment stage keeps of a cast: the hit (only between the near and far planes,
/// window depth in [0, 1]), its window depth and the unnormalised normal.
template <class T>
struct FragmentHit {
    mask_t<T> hit;
    T depth;
    Vec3<T> normal;
};

/// `cast_ray` then `window_depth` for a ray whose origin lies in the camera plane; vz_row is the
/// third row of the world -> view rotation. The one definition of a fragment's hit for the GL
/// fragment stages (incremental and brute force) and the CPU reference renderer.
template <CastOptions Opt, class T>
FragmentHit<T> cast_and_depth(const ClippedQuadric<T>& p, const LocalRay<T>& r, const Vec3<T>& vz_row, const Vec4<T>& pz) {
    const CastHit<T> h = cast_ray<Opt>(p, r);
    const T depth = window_depth(h.lambda, dot(vz_row, r.v), pz);
    return {(h.hit && depth >= T(0)) && depth <= T(1), depth, h.normal};
}

/// Blinn-Phong shading with one directional light, two-sided (a normal facing away from the eye
/// is flipped: back faces are lit like front faces when culling is off). n, l, e need not be
/// unit vectors (normalised here); l points towards the light, e towards the eye. The specular lobe
/// cos^s is Schlick's rational approximation t / (s - s t + t) (Schlick 1994), so no `pow`.
/// Returns colour * (ambient + diffuse max(n.l, 0)) + specular * lobe * light.
template <class T>
Vec3<T> shade_blinn_phong(const Vec3<T>& n_in, const Vec3<T>& l_in, const Vec3<T>& e_in, const Vec3<T>& color,
                          const Vec3<T>& light, const Vec4<T>& material /* ambient, diffuse, specular, shininess */) {
    const Vec3<T> e = normalize(e_in), l = normalize(l_in);
    const Vec3<T> n0 = normalize(n_in);
    const Vec3<T> n = select(dot(n0, e) < T(0), -n0, n0);
    const T ndl = max(dot(n, l), T(0));
    const Vec3<T> h = normalize(l + e);
    const T t = max(dot(n, h), T(0));
    const T s = material[3];
    const T lobe = select(ndl > T(0), t / ((s - s * t) + t), T(0));
    const T k = material[0] + material[1] * ndl;
    return cmul(color, light) * k + light * (material[2] * lobe);
}

}  // namespace quadcast

namespace quadcast {

/// The world-space ray of a pixel of a perspective camera, reconstructed from its window position
/// (the brute-force fragment stage): origin the eye, direction towards the pixel's point on the
/// near plane, unprojected with the inverse view-projection (NDC z = -1). Its view-space z is the
/// near-plane z, so `window_depth(lambda, dot(vz_row, dir), pz)` applies as for the interpolated ray.
/// Numerics: ndc = (2 frag) / viewport - 1 per component; p = inv_view_proj * (ndc, -1, 1) (left
/// folds); dir = xyz(p) * (1 / p.w) - eye.
template <class T>
WorldRay<T> pixel_ray(const Mat4<T>& inv_view_proj, const Vec3<T>& eye, const Vec2<T>& frag, const Vec2<T>& viewport) {
    const T x = (T(2) * frag[0]) / viewport[0] - T(1);
    const T y = (T(2) * frag[1]) / viewport[1] - T(1);
    const Vec4<T> p = inv_view_proj * vec4(x, y, T(-1), T(1));
    const T w = T(1) / p[3];
    return {eye, vec3(p[0] * w, p[1] * w, p[2] * w) - eye};
}

}  // namespace quadcast
