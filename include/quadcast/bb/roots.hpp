// quadcast/bb/roots.hpp -- roots in [0,1] of univariate quadratics and cubics in BB-form, branch-free
#pragma once

#include "quadcast/bb/restrict.hpp"
#include "quadcast/linalg.hpp"
#include "quadcast/scalar.hpp"

namespace quadcast::bb {

/// A root in [0,1] (`t`) and whether there is one (`hit`). `t` is finite even when !hit.
template <class T>
struct UnitRoot {
    T t;
    mask_t<T> hit;
};

/// Up to two roots in [0,1], ascending; the valid ones come first (hit[1] implies hit[0]).
template <class T>
struct UnitRoots2 {
    T t[2];
    mask_t<T> hit[2];
};

/// a != b for masks, spelled with the combinators (a traced mask has no operator!=).
template <class M>
M detail_mask_xor(const M& a, const M& b) {
    return mask_or(mask_and(a, mask_not(b)), mask_and(mask_not(a), b));
}

/// Roots in [0,1] of the quadratic Σ c_i B_i^2(t) = c0 (1-t)^2 + 2 c1 t(1-t) + c2 t^2 (subtract
/// the isovalue ρ from the coefficients first). Stable analytic formula (the "well known
/// formulae [HE95]" of Kalbe & Zeilfelder 2008, Sect. 5.3; cancellation-free form as in
/// Numerical Recipes §5.6): with A = c0 - 2c1 + c2, B' = c0 - c1 and the discriminant
/// D = c1² - c0 c2 (= B'² - A c0, computed from the coefficients directly), the roots are
/// s/A and c0/s with s = B' + sgn(B')·sqrt(D). A = 0 (linear) needs no special case: c0/s is its
/// root. D < 0 (also a grazing double root pushed below zero by rounding) gives no root.
/// Numerics: A = (c0 - c1) - (c1 - c2); D = (c1*c1) - (c0*c2); s = B' + sign_nonzero(B') * sqrt(D);
/// two divisions guarded by select so no NaN is produced; about 14 operations.
template <class T>
UnitRoots2<T> quadratic_roots(const Vec<T, 3>& c) {
    // Form the Bernstein differences and the discriminant.
    const T bp = c[0] - c[1];
    const T a = bp - (c[1] - c[2]);
    const T disc = c[1] * c[1] - c[0] * c[2];
    const mask_t<T> real = disc >= T(0);
    const T s = bp + sign_nonzero(bp) * sqrt(select(real, disc, T(0)));
    // Divide, keeping the unselected side finite.
    const mask_t<T> a_ok = a != T(0);
    const mask_t<T> s_ok = s != T(0);
    const T r1 = select(a_ok, s / select(a_ok, a, T(1)), T(-1));
    const T r2 = select(s_ok, c[0] / select(s_ok, s, T(1)), T(-1));
    // Keep the roots in [0,1] and sort them, valid ones first.
    const mask_t<T> v1 = real && a_ok && r1 >= T(0) && r1 <= T(1);
    const mask_t<T> v2 = real && s_ok && r2 >= T(0) && r2 <= T(1);
    const mask_t<T> first1 = v1 && (mask_not(v2) || r1 <= r2);
    UnitRoots2<T> r{};
    r.t[0] = select(first1, r1, r2);
    r.t[1] = select(first1, r2, r1);
    r.hit[0] = v1 || v2;
    r.hit[1] = v1 && v2;
    return r;
}

/// The smallest root in [0,1] of Σ b_i B_i^2(t) - rho (`quadratic_roots`).
/// Numerics: c_i = b_i - rho, then as `quadratic_roots`.
template <class T>
UnitRoot<T> quadratic_first_root(const Vec<T, 3>& b, const T& rho) {
    const UnitRoots2<T> r = quadratic_roots(Vec<T, 3>{{b[0] - rho, b[1] - rho, b[2] - rho}});
    return {r.t[0], r.hit[0]};
}

/// The smallest root in [0,1] of the cubic Σ c_i B_i^3(t) by Newton's method as in
/// Kalbe & Zeilfelder 2008, Sect. 5.3: three starts t = 0, the inflection point if it lies in
/// [0,1] (else 1/2), and t = 1, a fixed number `Iterations` of steps t <- t - p(t)/p'(t) each
/// (the paper prints "+", a typo; I = 5 in the paper), then the smallest start that ended in
/// [0,1] wins. Not in the paper (which only clips by λ >= 0 afterwards): a start is accepted
/// only if |p(t)| <= residual_tol * max_i |c_i| at its final t, a step with p'(t) = 0 is skipped,
/// and every iterate is clamped to [-1, 2] so that no overflow/NaN can arise.
/// Newton can miss a root (all three starts converge elsewhere or too slowly) — see the
/// comparison in tests/bb; `cubic_first_root_isolated` does not.
/// Numerics: inflection at e0/(e0 - e1), e0 = (c0 - c1) - (c1 - c2), e1 = (c1 - c2) - (c2 - c3);
/// p and p' by `evaluate_univariate`; per start Iterations + 1 evaluations.
template <int Iterations = 5, class T>
UnitRoot<T> cubic_first_root_newton(const Vec<T, 4>& c, const T& residual_tol) {
    // Compute the inflection point (second differences change sign) or take 1/2.
    const T e0 = (c[0] - c[1]) - (c[1] - c[2]);
    const T e1 = (c[1] - c[2]) - (c[2] - c[3]);
    const mask_t<T> infl = detail_mask_xor(e0 < T(0), e1 < T(0));
    const T den = select(infl, e0 - e1, T(1));
    const T t_mid = select(infl, e0 / den, T(0.5));
    const T scale = max(max(abs(c[0]), abs(c[1])), max(abs(c[2]), abs(c[3])));
    const T tol = residual_tol * scale;
    const T starts[3] = {T(0), t_mid, T(1)};
    T best = T(2);
    mask_t<T> found = T(1) < T(0);
    for (int s = 0; s < 3; ++s) {
        // Iterate Newton a fixed number of times.
        T t = starts[s];
        for (int it = 0; it < Iterations; ++it) {
            const ValueAndSlope<T> v = evaluate_univariate(c, t);
            const mask_t<T> d_ok = v.slope != T(0);
            const T step = select(d_ok, v.value / select(d_ok, v.slope, T(1)), T(0));
            t = clamp(t - step, T(-1), T(2));
        }
        // Accept a converged start in [0,1]; keep the smallest.
        const T f = evaluate_univariate(c, t).value;
        const mask_t<T> ok = t >= T(0) && t <= T(1) && abs(f) <= tol;
        const mask_t<T> take = ok && (mask_not(found) || t < best);
        best = select(take, t, best);
        found = found || ok;
    }
    return {select(found, best, T(0)), found};
}

/// Start point for `cubic_first_root_isolated`: the root nearest to the bracket end e of the
/// quadratic Taylor model f + fp·s + half_fpp·s² (s = dir·(t - e) >= 0, dir = +1 at the lower
/// end, -1 at the upper end); `hit` if it exists and lies in [lo, hi].
/// Numerics: stable quadratic formula q = -(B + sgn(B) sqrt(B² - 4AC))/2, roots q/A and C/q.
template <class T>
UnitRoot<T> detail_taylor_start(const T& e, const T& f, const T& fp, const T& half_fpp, const T& dir, const T& lo,
                                const T& hi) {
    const T a = half_fpp, b = dir * fp, c = f;
    const T disc = b * b - T(4) * (a * c);
    const mask_t<T> real = disc >= T(0);
    const T q = T(-0.5) * (b + sign_nonzero(b) * sqrt(select(real, disc, T(0))));
    const mask_t<T> a_ok = a != T(0), q_ok = q != T(0);
    const T s1 = select(a_ok, q / select(a_ok, a, T(1)), T(-1));
    const T s2 = select(q_ok, c / select(q_ok, q, T(1)), T(-1));
    const mask_t<T> v1 = a_ok && s1 >= T(0), v2 = q_ok && s2 >= T(0);
    const T s = select(v1 && (mask_not(v2) || s1 <= s2), s1, s2);
    const T t = e + dir * s;
    return {t, real && (v1 || v2) && t >= lo && t <= hi};
}

/// A point of [0,1] with p and p' there (for sorting break points with selects).
template <class T>
struct detail_Knot {
    T t, f, d;
};

template <class M, class T>
detail_Knot<T> detail_select(const M& m, const detail_Knot<T>& a, const detail_Knot<T>& b) {
    return {select(m, a.t, b.t), select(m, a.f, b.f), select(m, a.d, b.d)};
}

/// The smallest root in [0,1] of the cubic Σ c_i B_i^3(t), robust alternative to
/// `cubic_first_root_newton`: isolate, then bracket.
/// 1. The critical points (roots of p' = 3 Σ (c_{i+1} - c_i) B_i^2, by the stable
///    `quadratic_roots`) and the inflection point (root of p'') split [0,1] into at most four
///    pieces on which p is monotone and convex or concave (missing points are replaced by 1,
///    giving empty pieces).
/// 2. The first piece whose end values have opposite signs (or a zero) holds the first root;
///    |p| <= touch_tol at a critical point counts as a zero there (grazing rays; 0 = off).
/// 3. Start at whichever has the smallest |p|: the regula-falsi point of the piece or the root
///    of the quadratic Taylor model of p at either end (near a critical end p' -> 0, where
///    Newton alone converges only linearly).
/// 4. `Iterations` safeguarded Newton steps: Newton if the step stays inside the (closed)
///    current bracket and p' != 0, bisection otherwise; the bracket shrinks by the sign of p; an
///    exact zero stops. The evaluated point (piece ends included) with the smallest |p| is
///    returned.
/// A sign change is never missed, so no root is lost except a tangential one whose extremum
/// value rounds to the wrong side (see tests/bb). Not from Kalbe & Zeilfelder 2008 (they mention
/// Cardano / [HE95] and Newton).
/// Numerics: one `quadratic_roots`; inflection e0 / (e0 - e1) with e0 = (c0 - c1) - (c1 - c2),
/// e1 = (c1 - c2) - (c2 - c3); p and p' by `evaluate_univariate` at the 3 break points, the 3
/// start candidates and after every step (6 + Iterations evaluations);
/// p''(x)/2 = T(3) * ((1-x) e0 + x e1); all branches are selects.
template <int Iterations = 6, class T>
UnitRoot<T> cubic_first_root_isolated(const Vec<T, 4>& c, const T& touch_tol = T(0)) {
    using K = detail_Knot<T>;
    // Locate the critical points and the inflection point, with p and p' there.
    const UnitRoots2<T> cr = quadratic_roots(Vec<T, 3>{{c[1] - c[0], c[2] - c[1], c[3] - c[2]}});
    const T e0 = (c[0] - c[1]) - (c[1] - c[2]);
    const T e1 = (c[1] - c[2]) - (c[2] - c[3]);
    const mask_t<T> infl = detail_mask_xor(e0 < T(0), e1 < T(0));
    const T ta = select(cr.hit[0], cr.t[0], T(1));
    const T tb = select(cr.hit[1], cr.t[1], T(1));
    const T ti = select(infl, e0 / select(infl, e0 - e1, T(1)), T(1));
    const ValueAndSlope<T> va = evaluate_univariate(c, ta), vb = evaluate_univariate(c, tb),
                           vi = evaluate_univariate(c, ti);
    const K ka = {ta, select(abs(va.value) <= touch_tol, T(0), va.value), va.slope};
    const K kb = {tb, select(abs(vb.value) <= touch_tol, T(0), vb.value), vb.slope};
    const K ki = {ti, vi.value, vi.slope};
    // Sort the break points: insert ti into ta <= tb.
    const mask_t<T> i_lt_a = ti < ka.t, i_lt_b = ti < kb.t;
    const K k1 = detail_select(i_lt_a, ki, ka);
    const K k2 = detail_select(i_lt_a, ka, detail_select(i_lt_b, ki, kb));
    const K k3 = detail_select(i_lt_b, kb, ki);
    const K k0 = {T(0), c[0], T(3) * (c[1] - c[0])};
    const K k4 = {T(1), c[3], T(3) * (c[3] - c[2])};
    // Pick the first piece that brackets a root.
    auto brackets = [](const K& l, const K& r) { return min(l.f, r.f) <= T(0) && max(l.f, r.f) >= T(0); };
    const mask_t<T> in0 = brackets(k0, k1), in1 = brackets(k1, k2), in2 = brackets(k2, k3), in3 = brackets(k3, k4);
    const mask_t<T> hit = (in0 || in1) || (in2 || in3);
    K kl = detail_select(in2, k2, k3), kh = detail_select(in2, k3, k4);
    kl = detail_select(in1, k1, kl);
    kh = detail_select(in1, k2, kh);
    kl = detail_select(in0, k0, kl);
    kh = detail_select(in0, k1, kh);
    T lo = kl.t, hi = kh.t, flo = kl.f;
    // Start candidates: regula falsi (|flo - fhi| = |flo| + |fhi|: no cancellation) and the
    // quadratic Taylor models at both ends; keep the one with the smallest |p|.
    const T span = kl.f - kh.f;
    const mask_t<T> span_ok = span != T(0);
    const T t_rf = select(span_ok, lo + (hi - lo) * (kl.f / select(span_ok, span, T(1))), (lo + hi) * T(0.5));
    const UnitRoot<T> s_lo = detail_taylor_start(lo, kl.f, kl.d, T(3) * ((T(1) - lo) * e0 + lo * e1), T(1), lo, hi);
    const UnitRoot<T> s_hi = detail_taylor_start(hi, kh.f, kh.d, T(3) * ((T(1) - hi) * e0 + hi * e1), T(-1), lo, hi);
    const T t_lo = select(s_lo.hit, s_lo.t, t_rf), t_hi = select(s_hi.hit, s_hi.t, t_rf);
    const ValueAndSlope<T> v_rf = evaluate_univariate(c, t_rf), v_lo = evaluate_univariate(c, t_lo),
                           v_hi = evaluate_univariate(c, t_hi);
    const mask_t<T> take_lo = abs(v_lo.value) < abs(v_rf.value);
    T t = select(take_lo, t_lo, t_rf);
    ValueAndSlope<T> v = {select(take_lo, v_lo.value, v_rf.value), select(take_lo, v_lo.slope, v_rf.slope)};
    const mask_t<T> take_hi = abs(v_hi.value) < abs(v.value);
    t = select(take_hi, t_hi, t);
    v = {select(take_hi, v_hi.value, v.value), select(take_hi, v_hi.slope, v.slope)};
    // The best point so far: a piece end or the start.
    const mask_t<T> lo_best = abs(kl.f) <= abs(kh.f);
    T best = select(lo_best, lo, hi), f_best = min(abs(kl.f), abs(kh.f));
    const mask_t<T> start_better = abs(v.value) < f_best;
    best = select(start_better, t, best);
    f_best = select(start_better, abs(v.value), f_best);
    // Refine by safeguarded Newton steps.
    for (int it = 0; it < Iterations; ++it) {
        const mask_t<T> exact = v.value == T(0);
        const mask_t<T> same_as_lo = mask_not(detail_mask_xor(v.value < T(0), flo < T(0)));
        lo = select(same_as_lo, t, lo);
        flo = select(same_as_lo, v.value, flo);
        hi = select(same_as_lo, hi, t);
        const mask_t<T> d_ok = v.slope != T(0);
        const T newton = t - select(d_ok, v.value / select(d_ok, v.slope, T(1)), T(0));
        const mask_t<T> inside = d_ok && newton >= lo && newton <= hi;
        t = select(exact, t, select(inside, newton, (lo + hi) * T(0.5)));
        v = evaluate_univariate(c, t);
        const mask_t<T> better = abs(v.value) < f_best;
        best = select(better, t, best);
        f_best = select(better, abs(v.value), f_best);
    }
    return {select(hit, best, T(0)), hit};
}

/// The smallest root in [0,1] of Σ b_i B_i^3(t) - rho by `cubic_first_root_isolated`.
template <int Iterations = 6, class T>
UnitRoot<T> cubic_first_root(const Vec<T, 4>& b, const T& rho, const T& touch_tol = T(0)) {
    return cubic_first_root_isolated<Iterations>(Vec<T, 4>{{b[0] - rho, b[1] - rho, b[2] - rho, b[3] - rho}},
                                                 touch_tol);
}

}  // namespace quadcast::bb
