// quadcast/ray.hpp -- ray/quadric intersection: coefficients, root selection, bound tests
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>
#include <type_traits>

#include "quadcast/linalg.hpp"
#include "quadcast/quadric.hpp"
#include "quadcast/scalar.hpp"

namespace quadcast {

// Coefficients ---------------------------------------------------------------------------------

/// The quadratic alpha lambda^2 + 2 beta lambda + gamma = 0 along a ray x(lambda) = e + lambda v
/// (Stoll et al. 2006, eq. 6). Note the factor 2 on beta.
template <class T>
struct RayCoefficients {
    T alpha, beta, gamma;
};

/// Ray coefficients for a general eye e and direction v (Stoll et al. 2006, eq. 6):
/// alpha = v^T A v, beta = e~^T Q~ v~ = (A e + b) . v, gamma = e~^T Q~ e~ = f(e).
/// Numerics: r = Q~ e~ (left folds, r_i = ((A_i0 e0 + A_i1 e1) + A_i2 e2) + b_i);
/// alpha = dot(v, A v), beta = dot(r.xyz, v), gamma = dot(e~, r) (bitwise `evaluate(q, e)`).
/// beta and alpha are bitwise equal to `ray_coefficients_eye(translate_to_eye(q, e), v)`;
/// gamma agrees with it to rounding (the two associate f(e) differently).
template <class T>
RayCoefficients<T> ray_coefficients(const Quadric<T>& q, const Vec3<T>& eye, const Vec3<T>& dir) {
    const Vec4<T> eh = vec4(eye, T(1));
    const Vec4<T> r = q.q * eh;
    return {dot(dir, upper3(q.q) * dir), dot(xyz(r), dir), dot(eh, r)};
}

/// Ray coefficients in eye-origin coordinates (Stoll et al. 2006, eq. 10), for a quadric from
/// `translate_to_eye`: alpha = v^T A' v, beta = b'^T v, gamma = c'.
/// Numerics: alpha = dot(v, A' v), beta = dot(b', v) (left folds).
template <class T>
RayCoefficients<T> ray_coefficients_eye(const Quadric<T>& q_eye, const Vec3<T>& dir) {
    return {dot(dir, upper3(q_eye.q) * dir), dot(xyz(q_eye.q[3]), dir), q_eye.q[3][3]};
}

/// The point e + lambda v. Numerics: per component e_i + lambda v_i.
template <class T>
Vec3<T> ray_point(const Vec3<T>& eye, const Vec3<T>& dir, const T& lambda) {
    return eye + lambda * dir;
}

// Error-free transformations -------------------------------------------------------------------

/// hi + lo, exactly equal to the value it represents (|lo| <= ulp(hi) / 2 where produced below).
template <class T>
struct TwoTerm {
    T hi, lo;
};

/// Veltkamp's splitting constant 2^ceil(p/2) + 1 of T's format (p = significand bits):
/// 4097 for float and the traced scalar, 134217729 for double.
template <class T>
T veltkamp_constant() {
    using F = float_format_t<T>;
    constexpr int s = (std::numeric_limits<F>::digits + 1) / 2;
    return T(static_cast<F>((1LL << s) + 1));
}

/// Veltkamp split a = hi + lo, each half fitting in ceil(p/2) bits (Dekker 1971).
/// Numerics: c = K a; hi = c - (c - a); lo = a - hi. Exact when every operation rounds to
/// nearest without contraction (-ffp-contract=off, GLSL `precise`) and K a does not overflow
/// (|a| < max/K, about 8e34 in float).
template <class T>
TwoTerm<T> veltkamp_split(const T& a) {
    const T c = veltkamp_constant<T>() * a;
    const T hi = c - (c - a);
    return {hi, a - hi};
}

/// a + b = s + e exactly, s = fl(a + b) (Knuth's TwoSum; no ordering of |a|, |b| needed).
/// Numerics: s = a + b; bb = s - a; e = (a - (s - bb)) + (b - bb).
template <class T>
TwoTerm<T> two_sum(const T& a, const T& b) {
    const T s = a + b;
    const T bb = s - a;
    return {s, (a - (s - bb)) + (b - bb)};
}

/// a * b = p + e exactly, p = fl(a b), without FMA (Dekker's TwoProduct with Veltkamp splits).
/// Numerics: e = (((ah bh - p) + ah bl) + al bh) + al bl. Exact unless a product underflows
/// (e loses bits below the subnormal range; GPU fragment stages that flush subnormals lose
/// them too) or a split overflows.
template <class T>
TwoTerm<T> two_product(const T& a, const T& b) {
    const T p = a * b;
    const TwoTerm<T> as = veltkamp_split(a), bs = veltkamp_split(b);
    const T e = (((as.hi * bs.hi - p) + as.hi * bs.lo) + as.lo * bs.hi) + as.lo * bs.lo;
    return {p, e};
}

// Discriminant ---------------------------------------------------------------------------------

/// beta^2 - alpha gamma as written in Stoll et al. 2006, eq. 7.
/// Numerics: beta*beta - alpha*gamma; loses all accuracy when the two products nearly cancel
/// (grazing rays).
template <class T>
T discriminant_naive(const RayCoefficients<T>& c) {
    return c.beta * c.beta - c.alpha * c.gamma;
}

/// beta^2 - alpha gamma with the products and their difference computed error-free:
/// beta^2 = p1 + e1 and alpha gamma = p2 + e2 exactly (`two_product`), p1 - p2 = s + t exactly
/// (`two_sum`), result s + ((t + e1) - e2). Only the last three roundings remain, so the
/// result is within a few ulp of the exact discriminant of the given (rounded) alpha, beta,
/// gamma even when beta^2 and alpha gamma cancel; its sign is right whenever it is not tiny
/// compared with ulp(ulp(beta^2)).
/// Numerics: 2 x (1 + 2 splits + 4 products + 3 sums), 1 TwoSum (6 ops), 3 more sums; no FMA.
template <class T>
T discriminant_accurate(const RayCoefficients<T>& c) {
    const TwoTerm<T> bb = two_product(c.beta, c.beta);
    const TwoTerm<T> ag = two_product(c.alpha, c.gamma);
    const TwoTerm<T> d = two_sum(bb.hi, -ag.hi);
    return d.hi + ((d.lo + bb.lo) - ag.lo);
}

// Root selection -------------------------------------------------------------------------------

/// How the roots of alpha lambda^2 + 2 beta lambda + gamma are computed. A plain C++ value
/// (template argument or runtime argument), never traced.
enum class RootFormula {
    /// Stoll et al. 2006, eq. 7: (-beta -+ sqrt(disc)) / alpha, naive discriminant, and the
    /// paper's separate linear case -gamma / (2 beta) when alpha is small (see
    /// `linear_case_threshold`). Cancels when |alpha gamma| << beta^2.
    classic,
    /// Stoll et al. 2006, eq. 15 (reciprocal form): gamma / (-beta +- sqrt(disc)), naive
    /// discriminant. No division by alpha (alpha -> 0 is handled by the formula itself), but
    /// the root whose denominator cancels (the far one when beta and gamma have equal signs) is
    /// inaccurate.
    stoll,
    /// Cancellation-free: q = -(beta + sign(beta) sqrt(disc)), roots q / alpha and gamma / q,
    /// with `discriminant_accurate`. Needs no linear case either (gamma / q -> -gamma / (2 beta)
    /// as alpha -> 0, q / alpha -> infinity).
    stable,
};

/// The default formulation, the most accurate one in tests/core/test_ray.cpp for both modes.
inline constexpr RootFormula default_root_formula = RootFormula::stable;

/// A ray parameter and whether it is a hit.
template <class T>
struct RayHit {
    T lambda;
    mask_t<T> hit;
};

/// Both candidate roots, nearer positive root first, with validity masks.
/// `near_valid`: the discriminant is >= 0, the root is finite and lambda > 0 (same for far).
/// Whenever a positive root exists, `lambda_near` is the smallest one; `lambda_far` is the other
/// root (possibly invalid: behind the eye, at infinity, or no real roots at all).
template <class T>
struct RootPair {
    T lambda_near, lambda_far;
    mask_t<T> near_valid, far_valid;
};

/// The threshold tau of the classic formulation's linear case: the quadratic is treated as
/// linear, lambda = -gamma / (2 beta), when |alpha gamma| <= tau beta^2.
/// Why relative to beta^2 / |gamma|: the ratio alpha gamma / beta^2 is invariant under scaling of
/// the quadric and of v, and it is what both errors depend on: the linear root differs from the
/// true (cancelling) root -gamma / (beta + sign(beta) sqrt(disc)) by a relative
/// |alpha gamma| / (4 beta^2) <= tau / 4, while eq. 7's cancelling root (-beta + sign(beta)
/// sqrt(disc)) / alpha has a relative rounding error of about 2 eps beta^2 / |alpha gamma|.
/// tau = sqrt(8 eps) makes both equal at the switch (sqrt(eps / 2), ~2.4e-4 in float): the best
/// the classic formulation can do. (2^-10 for float, 2^-24.5 for double.)
template <class T>
T linear_case_threshold() {
    using F = float_format_t<T>;
    return T(static_cast<F>(std::sqrt(8.0L * static_cast<long double>(std::numeric_limits<F>::epsilon()))));
}

/// |alpha gamma| <= tau beta^2 (`linear_case_threshold`): eq. 7 degenerates to a linear
/// equation (Stoll et al. 2006, sec. 5). Numerics: two products, one comparison (no division;
/// NaN gives false).
template <class T>
mask_t<T> is_linear_case(const RayCoefficients<T>& c) {
    return abs(c.alpha * c.gamma) <= linear_case_threshold<T>() * (c.beta * c.beta);
}

namespace ray_detail {

template <class T>
struct Ratio {
    T value;
    mask_t<T> ok;
};

/// num / den with a zero den replaced by 1 (no division by zero on the CPU); ok = den != 0.
template <class T>
Ratio<T> guarded_div(const T& num, const T& den) {
    const mask_t<T> ok = den != T(0);
    return {num / select(ok, den, T(1)), ok};
}

/// A candidate root is a hit when the discriminant is >= 0, the division was defined, and
/// lambda is finite and positive.
template <class T>
mask_t<T> valid_root(const mask_t<T>& disc_ok, const Ratio<T>& r) {
    return ((disc_ok && r.ok) && isfinite(r.value)) && (r.value > T(0));
}

template <class T>
struct SqrtDisc {
    T s;
    mask_t<T> ok;
};

template <RootFormula F, class T>
SqrtDisc<T> sqrt_discriminant(const RayCoefficients<T>& c) {
    const T disc = (F == RootFormula::stable) ? discriminant_accurate(c) : discriminant_naive(c);
    const mask_t<T> ok = disc >= T(0);
    return {sqrt(select(ok, disc, T(0))), ok};
}


/// The stable front root from a given sqrt(discriminant): q = -(beta + sign(beta) sqrt(disc)),
/// lambda = beta < 0 ? gamma / q : q / alpha (nothing cancels).
template <class T>
RayHit<T> stable_front_root(const RayCoefficients<T>& c, const SqrtDisc<T>& sd) {
    // Form the non-cancelling q, then divide so that nothing cancels.
    const T q = -(c.beta + sign_nonzero(c.beta) * sd.s);
    const mask_t<T> by_q = c.beta < T(0);
    const Ratio<T> r = guarded_div(select(by_q, c.gamma, q), select(by_q, q, c.alpha));
    return {r.value, valid_root(sd.ok, r)};
}

/// Both stable roots from a given sqrt(discriminant), the nearer positive one first.
template <class T>
RootPair<T> stable_roots_near_first(const RayCoefficients<T>& c, const SqrtDisc<T>& sd) {
    const T sg = sign_nonzero(c.gamma);
    const T sb = sign_nonzero(c.beta);
    // Pick which of q / alpha and gamma / q is nearer from the signs alone.
    const T q = -(c.beta + sb * sd.s);
    const mask_t<T> g_near = sg * sb < T(0);
    const Ratio<T> nr = guarded_div(select(g_near, c.gamma, q), select(g_near, q, c.alpha));
    const Ratio<T> fr = guarded_div(select(g_near, q, c.gamma), select(g_near, c.alpha, q));
    return {nr.value, fr.value, valid_root(sd.ok, nr), valid_root(sd.ok, fr)};
}

}  // namespace ray_detail

/// The front-facing root only (back-face culling on): the root with alpha lambda + beta < 0,
/// i.e. v . n < 0 (Stoll et al. 2006, eq. 13-14: alpha lambda_- + beta = -sqrt(disc), so it is
/// lambda_- = (-beta - sqrt(disc)) / alpha of eq. 7).
/// - classic: (-beta - sqrt(disc)) / alpha; in the linear case with beta < 0 (where this
///   cancels) -gamma / (2 beta) instead. With beta >= 0 the expression does not cancel and
///   is kept (it tends to infinity, a miss, as alpha -> 0: then the finite root is back-facing).
/// - stoll: gamma / (-beta + sqrt(disc)) (eq. 15, lambda'_-).
/// - stable: beta < 0 ? gamma / q : q / alpha with q = -(beta + sign(beta) sqrt(disc)).
/// hit: disc >= 0, the root is finite and lambda > 0 (the caller adds its bound test).
/// Numerics: one sqrt, one division (two for classic); see RootFormula for the discriminant.
template <RootFormula F = default_root_formula, class T>
RayHit<T> front_root(const RayCoefficients<T>& c) {
    using namespace ray_detail;
    const SqrtDisc<T> sd = sqrt_discriminant<F>(c);
    if constexpr (F == RootFormula::classic) {
        // Take eq. 7's minus root, or the linear root where that cancels.
        const Ratio<T> quad = guarded_div(-c.beta - sd.s, c.alpha);
        const Ratio<T> lin = guarded_div(-c.gamma, T(2) * c.beta);
        const mask_t<T> use_lin = is_linear_case(c) && (c.beta < T(0));
        return {select(use_lin, lin.value, quad.value),
                select(use_lin, valid_root(sd.ok, lin), valid_root(sd.ok, quad))};
    } else if constexpr (F == RootFormula::stoll) {
        const Ratio<T> r = guarded_div(c.gamma, -c.beta + sd.s);
        return {r.value, valid_root(sd.ok, r)};
    } else {
        return stable_front_root(c, sd);
    }
}

/// Both roots, the nearer positive one first (back-face culling off; the idea of Stoll et al.
/// 2006, eq. 15: test the near root against the bound first, the far one only if that fails).
/// The nearer positive root is gamma / (-beta + sign(gamma) sqrt(disc)) = (-beta - sign(gamma)
/// sqrt(disc)) / alpha. Erratum: the paper says lambda'_+ (= gamma / (-beta - sqrt(disc))) is
/// always the nearer one; that is wrong when gamma > 0 (eye outside, e.g. roots 1 and 5 of
/// lambda^2 - 6 lambda + 5: lambda'_+ = 5). In the paper's last form
/// 1 / (-beta/gamma -+ sqrt((beta/gamma)^2 - alpha/gamma)) the square root silently carries
/// sign(gamma), and there the nearer root is the one with "+ sqrt" (labelled lambda'_-).
/// - classic: (-beta -+ sign(gamma) sqrt(disc)) / alpha; in the linear case the one of the two
///   that cancels, (-beta + sign(beta) sqrt(disc)) / alpha, is replaced by -gamma / (2 beta).
/// - stoll: gamma / (-beta +- sign(gamma) sqrt(disc)).
/// - stable: gamma / q is the near root when sign(beta) sign(gamma) < 0, else q / alpha.
/// Numerics: one sqrt, two divisions (three for classic); sign products are exact.
template <RootFormula F = default_root_formula, class T>
RootPair<T> roots_near_first(const RayCoefficients<T>& c) {
    using namespace ray_detail;
    const SqrtDisc<T> sd = sqrt_discriminant<F>(c);
    const T sg = sign_nonzero(c.gamma);
    const T sb = sign_nonzero(c.beta);
    Ratio<T> nr{}, fr{};
    if constexpr (F == RootFormula::classic) {
        // Eq. 7 for both roots, then the linear root in place of the cancelling one.
        const Ratio<T> near_q = guarded_div(-c.beta - sg * sd.s, c.alpha);
        const Ratio<T> far_q = guarded_div(-c.beta + sg * sd.s, c.alpha);
        const Ratio<T> lin = guarded_div(-c.gamma, T(2) * c.beta);
        const mask_t<T> lin_case = is_linear_case(c);
        const mask_t<T> near_cancels = sg * sb < T(0);
        const mask_t<T> lin_near = lin_case && near_cancels;
        const mask_t<T> lin_far = lin_case && !near_cancels;
        return {select(lin_near, lin.value, near_q.value), select(lin_far, lin.value, far_q.value),
                select(lin_near, valid_root(sd.ok, lin), valid_root(sd.ok, near_q)),
                select(lin_far, valid_root(sd.ok, lin), valid_root(sd.ok, far_q))};
    } else if constexpr (F == RootFormula::stoll) {
        nr = guarded_div(c.gamma, -c.beta + sg * sd.s);
        fr = guarded_div(c.gamma, -c.beta - sg * sd.s);
    } else {
        return stable_roots_near_first(c, sd);
    }
    return {nr.value, fr.value, valid_root(sd.ok, nr), valid_root(sd.ok, fr)};
}

/// Runtime choice of the formulation (a plain C++ value; each case is a separate instantiation).
template <class T>
RayHit<T> front_root(const RayCoefficients<T>& c, RootFormula f) {
    switch (f) {
        case RootFormula::classic: return front_root<RootFormula::classic>(c);
        case RootFormula::stoll: return front_root<RootFormula::stoll>(c);
        case RootFormula::stable: break;
    }
    return front_root<RootFormula::stable>(c);
}

/// Runtime choice of the formulation (a plain C++ value).
template <class T>
RootPair<T> roots_near_first(const RayCoefficients<T>& c, RootFormula f) {
    switch (f) {
        case RootFormula::classic: return roots_near_first<RootFormula::classic>(c);
        case RootFormula::stoll: return roots_near_first<RootFormula::stoll>(c);
        case RootFormula::stable: break;
    }
    return roots_near_first<RootFormula::stable>(c);
}

/// The first valid root that passes the caller's bound test: the near root if it is valid and
/// `near_inside`, else the far root if it is valid and `far_inside`, else a miss
/// (Stoll et al. 2006, sec. 4.4.3). `near_inside` / `far_inside` are the bound tests evaluated at
/// the two candidate points (e.g. `inside_sphere(ray_point(e, v, r.lambda_near), ...)`).
/// Numerics: selects only.
template <class T>
RayHit<T> pick_first(const RootPair<T>& r, const mask_t<T>& near_inside, const mask_t<T>& far_inside) {
    const mask_t<T> use_near = r.near_valid && near_inside;
    const mask_t<T> use_far = r.far_valid && far_inside;
    return {select(use_near, r.lambda_near, r.lambda_far), use_near || use_far};
}

// Re-origined rays -------------------------------------------------------------------------------

/// A ray quadratic alpha lambda^2 + 2 beta lambda + gamma with its discriminant
/// beta^2 - alpha gamma computed separately (see `ray_quadratic_local`).
template <class T>
struct RayQuadratic {
    RayCoefficients<T> c;
    T disc;
};

/// Ray coefficients and discriminant for a quadric stored in LOCAL coordinates (origin at its
/// bound's centre, or at a corner of a quad) and the eye at o = e - origin there.
///
/// Why: in eye-origin form (Stoll et al. 2006, eq. 9-10) gamma = f(e) ~ d^2 for a quadric of
/// size 1 at distance d, and beta^2 - alpha gamma cancels down to ~1: rounding beta and gamma
/// alone costs eps d^2 in the discriminant, whatever formula solves the quadratic afterwards
/// (quadcast bench stability: half the rays of a sphere at d = 1e4 are lost in float). Here the
/// discriminant is evaluated where it is small and accurate instead: the quadratic is extremal
/// at lambda0 = -beta / alpha, q(lambda) = alpha (lambda - lambda0)^2 + q(lambda0), so
///     beta^2 - alpha gamma = -alpha q(lambda0) = -alpha f(x0),   x0 = o + lambda0 v,
/// and f(x0) is evaluated in local coordinates, near the quadric when the ray passes near it
/// (the idea of re-origining the ray close to the primitive, Haines et al., Ray Tracing Gems,
/// ch. 7, applied to general quadrics). The error is then ~eps d instead of ~eps d^2.
/// Where the quadratic is nearly linear (`is_linear_case`: |alpha gamma| <= tau beta^2, x0 is
/// far away) and where alpha = 0, the plain beta^2 - alpha gamma is used instead: there it
/// cannot cancel (|alpha gamma| <= tau beta^2 with tau ~ 2^-10), so its relative error stays
/// ~2 eps, and the error-free `discriminant_accurate` (which a traced select would evaluate
/// for every fragment) is not needed.
/// Numerics: g = A o + b, a = A v (left folds), then `ray_quadratic_incremental`.
/// One division more than eq. 10.
template <class T>
RayQuadratic<T> ray_quadratic_local(const Quadric<T>& q_local, const Vec3<T>& o, const Vec3<T>& v) {
    const Mat3<T> A = upper3(q_local.q);
    return ray_quadratic_incremental(q_local, o, v, A * o + xyz(q_local.q[3]), A * v);
}

/// `ray_quadratic_local` from terms that are linear in the ray, g = A o + b and a = A v: the
/// form of incremental ray casting (Stoll et al. 2006, sec. 5), where the per-primitive stage
/// computes o, v, g, a at the corners of the bounding geometry, the rasteriser interpolates them
/// and the per-fragment stage finishes here. With g and a computed exactly as in
/// `ray_quadratic_local` the result is the same bits.
/// Numerics: alpha = dot(v, a); beta = dot(g, v); gamma = dot(o, g + b) + c; lambda0 =
/// -beta / alpha; x0 = o + lambda0 v; A x0 + b = g + lambda0 a; f(x0) = dot(x0, (g + lambda0 a)
/// + b) + c; disc = -(alpha f(x0)), or `discriminant_naive` in the linear case.
template <class T>
RayQuadratic<T> ray_quadratic_incremental(const Quadric<T>& q_local, const Vec3<T>& o, const Vec3<T>& v,
                                          const Vec3<T>& g, const Vec3<T>& a) {
    const Vec3<T> b = xyz(q_local.q[3]);
    const T c0 = q_local.q[3][3];
    // Coefficients of eq. 6 with the eye at o.
    const RayCoefficients<T> c{dot(v, a), dot(g, v), dot(o, g + b) + c0};
    // The discriminant at the extremum of the quadratic along the ray.
    const mask_t<T> geometric = (c.alpha != T(0)) && !is_linear_case(c);
    const T lambda0 = -c.beta / select(geometric, c.alpha, T(1));
    const Vec3<T> x0 = o + lambda0 * v;
    const T f0 = dot(x0, (g + lambda0 * a) + b) + c0;
    const T disc = select(geometric, -(c.alpha * f0), discriminant_naive(c));
    return {c, disc};
}

/// `ray_quadratic_incremental` for the sphere x.x = r2 in local coordinates (A = I, b = 0,
/// c = -r2, so g = o and a = v): the same formulas without the quadric's coefficients, the
/// closed form of the sphere-specialised fragment stage. Same bits as the general form for a
/// quadric diag(1, 1, 1, -r2) up to the sign of zero terms.
/// Numerics: alpha = dot(v, v); beta = dot(o, v); gamma = dot(o, o) - r2; lambda0 = -beta /
/// alpha; x0 = o + lambda0 v; disc = -(alpha (dot(x0, x0) - r2)), or `discriminant_naive` in
/// the linear case.
template <class T>
RayQuadratic<T> ray_quadratic_sphere(const T& r2, const Vec3<T>& o, const Vec3<T>& v) {
    const RayCoefficients<T> c{dot(v, v), dot(o, v), dot(o, o) - r2};
    const mask_t<T> geometric = (c.alpha != T(0)) && !is_linear_case(c);
    const T lambda0 = -c.beta / select(geometric, c.alpha, T(1));
    const Vec3<T> x0 = o + lambda0 * v;
    const T disc = select(geometric, -(c.alpha * (dot(x0, x0) - r2)), discriminant_naive(c));
    return {c, disc};
}

/// The front-facing root of a `RayQuadratic` (back-face culling on), with the stable formulas.
template <class T>
RayHit<T> front_root(const RayQuadratic<T>& r) {
    using namespace ray_detail;
    const mask_t<T> ok = r.disc >= T(0);
    return stable_front_root(r.c, SqrtDisc<T>{sqrt(select(ok, r.disc, T(0))), ok});
}

/// Both roots of a `RayQuadratic`, the nearer positive one first (culling off).
template <class T>
RootPair<T> roots_near_first(const RayQuadratic<T>& r) {
    using namespace ray_detail;
    const mask_t<T> ok = r.disc >= T(0);
    return stable_roots_near_first(r.c, SqrtDisc<T>{sqrt(select(ok, r.disc, T(0))), ok});
}

// Bounds ---------------------------------------------------------------------------------------

/// A bounding sphere (Stoll et al. 2006, sec. 4.4.4 and 5.1.1).
template <class T>
struct BoundingSphere {
    Vec3<T> center;
    T radius;
};

/// A bounding tetrahedron given by its corners (Stoll et al. 2006, sec. 4.4.4 and 5.1.2).
template <class T>
struct BoundingTet {
    Vec3<T> p[4];
};

/// Six times the volume of a tetrahedron and its longest edge: vol6 / longest^3 tells how flat it
/// is (a regular tetrahedron's 0.71, 0 for coplanar corners). Host-side.
template <class T>
struct TetShape {
    T vol6 = T(0), longest = T(0);
    /// vol6 <= ratio longest^3, or either is NaN.
    bool flatter_than(const T& ratio) const { return !(vol6 > ratio * longest * longest * longest); }
};

/// `TetShape` of the corners p[0..3] (a C array, std::array or BoundingTet::p).
/// Numerics: vol6 = |dot(p1 - p0, cross(p2 - p0, p3 - p0))|; longest = max |p[j] - p[i]| over i < j.
template <class P>
auto tet_shape(const P& p) {
    using T = std::decay_t<decltype(p[0][0])>;
    TetShape<T> s;
    s.vol6 = std::fabs(dot(p[1] - p[0], cross(p[2] - p[0], p[3] - p[0])));
    for (int i = 0; i < 4; ++i)
        for (int j = i + 1; j < 4; ++j) s.longest = std::max(s.longest, length(p[j] - p[i]));
    return s;
}

/// The four face planes of a tetrahedron, oriented inwards: x is inside when
/// dot(plane[i], (x, 1)) >= 0 for all i (the paper's M_clip, sec. 5.1.2, with the sign flipped).
/// plane[i] is the face opposite corner i.
template <class T>
struct TetPlanes {
    Vec4<T> plane[4];
};

/// |x - center|^2 <= radius^2. Numerics: d = x - center; ((d0 d0 + d1 d1) + d2 d2) <= r r.
template <class T>
mask_t<T> inside_sphere(const Vec3<T>& x, const Vec3<T>& center, const T& radius) {
    const Vec3<T> d = x - center;
    return dot(d, d) <= radius * radius;
}

/// `inside_sphere` for a BoundingSphere.
template <class T>
mask_t<T> inside(const BoundingSphere<T>& s, const Vec3<T>& x) {
    return inside_sphere(x, s.center, s.radius);
}

/// Inward face planes of a tetrahedron (works in the vertex stage; a flat tetrahedron gives
/// planes that only accept points on its plane).
/// Numerics: face opposite corner i through corners (a, b, c) in cyclic order after i:
/// n = cross(b - a, c - a), d = -dot(n, a); negated when dot(n, p_i) + d < 0.
template <class T>
TetPlanes<T> tet_planes(const BoundingTet<T>& t) {
    TetPlanes<T> r{};
    for (int i = 0; i < 4; ++i) {
        const Vec3<T>& a = t.p[(i + 1) % 4];
        const Vec3<T>& b = t.p[(i + 2) % 4];
        const Vec3<T>& c = t.p[(i + 3) % 4];
        const Vec3<T> n = cross(b - a, c - a);
        const Vec4<T> pl = vec4(n, -dot(n, a));
        r.plane[i] = select(dot(pl, vec4(t.p[i], T(1))) < T(0), -pl, pl);
    }
    return r;
}

/// The barycentric coordinates of a tetrahedron as affine functions: lambda_i(x) =
/// dot(r.plane[i], (x, 1)), 1 at corner i and 0 on the opposite face (`tet_planes` scaled).
/// Numerics: plane[i] / dot(plane[i], (p_i, 1)).
template <class T>
TetPlanes<T> barycentric_planes(const BoundingTet<T>& t) {
    TetPlanes<T> r = tet_planes(t);
    for (int i = 0; i < 4; ++i) r.plane[i] = r.plane[i] / dot(r.plane[i], vec4(t.p[i], T(1)));
    return r;
}

/// x is inside or on the tetrahedron: all four plane tests >= 0.
/// Numerics: each test ((n0 x + n1 y) + n2 z) + d.
template <class T>
mask_t<T> inside_tet(const TetPlanes<T>& t, const Vec3<T>& x) {
    const Vec4<T> xh = vec4(x, T(1));
    return ((dot(t.plane[0], xh) >= T(0) && dot(t.plane[1], xh) >= T(0)) && dot(t.plane[2], xh) >= T(0)) &&
           dot(t.plane[3], xh) >= T(0);
}

}  // namespace quadcast
