// quadcast/bb/multi_index.hpp -- multi-indices and domain points of the BB-form on a tetrahedron
#pragma once

#include <array>

namespace quadcast::bb {

/// Number of trivariate Bernstein polynomials of degree q: (q+1)(q+2)(q+3)/6 (10 for q = 2,
/// 20 for q = 3).
constexpr int coefficient_count(int q) { return (q + 1) * (q + 2) * (q + 3) / 6; }

/// A multi-index (i, j, k, l), i + j + k + l = q; entry m is the power of λm.
struct MultiIndex {
    int i, j, k, l;
    constexpr int operator[](int m) const { return m == 0 ? i : m == 1 ? j : m == 2 ? k : l; }
    constexpr int degree() const { return i + j + k + l; }
    constexpr bool operator==(const MultiIndex&) const = default;
};

/// Storage position of c_ijkl among the degree-q coefficients. The order is i descending, then
/// j descending, then k descending (spec §1.3): for q = 2
/// 2000 1100 1010 1001 0200 0110 0101 0020 0011 0002.
/// Closed form: C(q-i+2, 3) entries have a larger i, (q-i-j)(q-i-j+1)/2 a larger j, q-i-j-k a
/// larger k.
constexpr int index_of(int q, int i, int j, int k) {
    const int a = q - i, b = q - i - j;
    return a * (a + 1) * (a + 2) / 6 + b * (b + 1) / 2 + (b - k);
}
constexpr int index_of(int q, const MultiIndex& m) { return index_of(q, m.i, m.j, m.k); }

/// All degree-Q multi-indices in storage order.
template <int Q>
constexpr std::array<MultiIndex, coefficient_count(Q)> multi_indices() {
    std::array<MultiIndex, coefficient_count(Q)> r{};
    int n = 0;
    for (int i = Q; i >= 0; --i)
        for (int j = Q - i; j >= 0; --j)
            for (int k = Q - i - j; k >= 0; --k) r[n++] = MultiIndex{i, j, k, Q - i - j - k};
    return r;
}

/// Ring of c_ijkl in the type-6 cube (Kalbe & Zeilfelder 2008, Fig. 3): ν = q - i, since λ0
/// belongs to the cube centre v_Q.
constexpr int ring(int q, const MultiIndex& m) { return q - m.i; }

/// The domain point ξ_ijkl scaled by q: i·v0 + j·v1 + k·v2 + l·v3 for integer vertices
/// (Kalbe & Zeilfelder 2008, Sect. 3). Two coefficients are shared iff these coincide.
constexpr std::array<int, 3> scaled_domain_point(const MultiIndex& m, const std::array<std::array<int, 3>, 4>& v) {
    std::array<int, 3> p{};
    for (int a = 0; a < 3; ++a) p[a] = m.i * v[0][a] + m.j * v[1][a] + m.k * v[2][a] + m.l * v[3][a];
    return p;
}

/// `table[n][m]` = storage index (degree Q) of α_n + e_m, where α_n is the n-th multi-index of
/// degree Q-1: the four coefficients one de Casteljau step combines into b^[1]_{α_n}.
template <int Q>
constexpr std::array<std::array<int, 4>, coefficient_count(Q - 1)> step_table() {
    static_assert(Q >= 1, "a de Casteljau step needs degree >= 1");
    std::array<std::array<int, 4>, coefficient_count(Q - 1)> r{};
    const auto lower = multi_indices<Q - 1>();
    for (int n = 0; n < coefficient_count(Q - 1); ++n) {
        const MultiIndex a = lower[n];
        r[n] = {index_of(Q, a.i + 1, a.j, a.k), index_of(Q, a.i, a.j + 1, a.k),
                index_of(Q, a.i, a.j, a.k + 1), index_of(Q, a.i, a.j, a.k)};
    }
    return r;
}

}  // namespace quadcast::bb
