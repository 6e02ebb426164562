// quadcast/bb/restrict.hpp -- univariate BB-form of a trivariate piece along a segment, by blossoming
#pragma once

#include <array>

#include "quadcast/bb/bezier.hpp"

namespace quadcast::bb {

/// Value and derivative d/dt of a univariate polynomial.
template <class T>
struct ValueAndSlope {
    T value;
    T slope;
};

/// Univariate de Casteljau on [0,1]: p(t) = Σ_i b_i B_i^{N-1}(t), and p'(t).
/// Numerics: s = 1 - t once; every step is (s * b_i) + (t * b_{i+1}); the slope is
/// T(N-1) * (b^[N-2]_1 - b^[N-2]_0) (before the last step).
template <class T, int N>
ValueAndSlope<T> evaluate_univariate(const Vec<T, N>& b, const T& t) {
    static_assert(N >= 1, "at least one coefficient");
    const T s = T(1) - t;
    Vec<T, N> w = b;
    T slope = T(0);
    for (int level = N - 1; level >= 1; --level) {
        if (level == 1) slope = T(static_cast<double>(N - 1)) * (w[1] - w[0]);
        for (int i = 0; i < level; ++i) w[i] = s * w[i] + t * w[i + 1];
    }
    return {w[0], slope};
}

/// Implementation of the blossoming scheme: `level[j]` is the blossom of the piece with
/// (K-1-j) arguments `la` and j arguments `lb` already applied (degree D left); one more
/// level applies `la` to level[0] and `lb` to every level[j].
template <class T, int D, int K>
Vec<T, D + K> detail_blossom_levels(const std::array<BezierTet<T, D>, K>& level, const Vec<T, 4>& la,
                                    const Vec<T, 4>& lb) {
    if constexpr (D == 0) {
        Vec<T, K> r{};
        for (int j = 0; j < K; ++j) r[j] = level[j][0];
        return r;
    } else {
        std::array<BezierTet<T, D - 1>, K + 1> next{};
        next[0] = de_casteljau_step(level[0], la);
        for (int j = 0; j < K; ++j) next[j + 1] = de_casteljau_step(level[j], lb);
        return detail_blossom_levels<T, D - 1, K + 1>(next, la, lb);
    }
}

/// Univariate BB-form of p restricted to the segment from the barycentric point `la` (t = 0)
/// to `lb` (t = 1), given the first de Casteljau step at both ends, ba = b^[1](la) and
/// bb = b^[1](lb) (degree D = Q-1). Coefficient i is the blossom p[la^(Q-i), lb^i]
/// (Kalbe & Zeilfelder 2008, Sect. 5.2-5.3 and Fig. 10: the vertex stage provides b^[1] at v
/// and its companion v̄, linear interpolation gives them at w and w̄, and the fragment stage
/// finishes the blossom: 3 steps for q = 2, 12 + 4 for q = 3).
/// Because a step is linear in its argument, interpolating b^[1] is exact.
/// Numerics: every step is `de_casteljau_step` (left-fold dot of 4); level k+1 applies la to
/// the all-la set and lb to every set of level k.
template <class T, int D>
Vec<T, D + 2> restrict_from_first_step(const BezierTet<T, D>& ba, const BezierTet<T, D>& bb, const Vec<T, 4>& la,
                                       const Vec<T, 4>& lb) {
    const std::array<BezierTet<T, D>, 2> level = {ba, bb};
    return detail_blossom_levels<T, D, 2>(level, la, lb);
}

/// Univariate BB-form (Q+1 coefficients on t ∈ [0,1]) of p along the segment from the
/// barycentric point `la` to `lb`: p((1-t) la + t lb) = Σ_i r_i B_i^Q(t), r_i = p[la^(Q-i), lb^i]
/// (Kalbe & Zeilfelder 2008, Sect. 5.3). The points may lie outside the tetrahedron.
/// Numerics: one step at each end, then `restrict_from_first_step`.
template <class T, int Q>
Vec<T, Q + 1> restrict_to_segment(const BezierTet<T, Q>& b, const Vec<T, 4>& la, const Vec<T, 4>& lb) {
    if constexpr (Q == 0) {
        return {{b[0]}};
    } else {
        return restrict_from_first_step(de_casteljau_step(b, la), de_casteljau_step(b, lb), la, lb);
    }
}

}  // namespace quadcast::bb
