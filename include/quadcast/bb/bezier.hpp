// quadcast/bb/bezier.hpp -- trivariate BB-form on a tetrahedron: de Casteljau, blossoms, derivatives
#pragma once

#include "quadcast/bb/multi_index.hpp"
#include "quadcast/linalg.hpp"
#include "quadcast/scalar.hpp"

namespace quadcast::bb {

/// The BB-coefficients of one polynomial piece of degree Q on a tetrahedron
/// T = [v0, v1, v2, v3], p = Σ c_ijkl B_ijkl (Kalbe & Zeilfelder 2008, eq. 1), stored in the
/// order of `multi_indices<Q>()`. Trivially copyable when T is.
template <class T, int Q>
struct BezierTet {
    static constexpr int degree = Q;
    static constexpr int size = coefficient_count(Q);
    T c[size];
    constexpr T& operator[](int n) { return c[n]; }
    constexpr const T& operator[](int n) const { return c[n]; }
    /// c_ijkl by multi-index (plain integer indexing, no traced values involved).
    constexpr T& at(int i, int j, int k) { return c[index_of(Q, i, j, k)]; }
    constexpr const T& at(int i, int j, int k) const { return c[index_of(Q, i, j, k)]; }
};

/// One de Casteljau step at the barycentric point (or blossom argument) `lambda`:
/// b^[1]_α = λ0 b_{α+e0} + λ1 b_{α+e1} + λ2 b_{α+e2} + λ3 b_{α+e3}, |α| = Q-1
/// (Kalbe & Zeilfelder 2008, Sect. 3). `lambda` need not sum to 1 (a direction gives a
/// directional derivative up to the factor Q).
/// Numerics: each output is `dot(lambda, (b_{α+e0}, ..., b_{α+e3}))`, a left fold:
/// ((λ0 b0 + λ1 b1) + λ2 b2) + λ3 b3; 4 mul + 3 add per output.
template <class T, int Q>
BezierTet<T, Q - 1> de_casteljau_step(const BezierTet<T, Q>& b, const Vec<T, 4>& lambda) {
    static constexpr auto table = step_table<Q>();
    BezierTet<T, Q - 1> r{};
    for (int n = 0; n < BezierTet<T, Q - 1>::size; ++n) {
        const Vec<T, 4> four = {{b[table[n][0]], b[table[n][1]], b[table[n][2]], b[table[n][3]]}};
        r[n] = dot(lambda, four);
    }
    return r;
}

/// Value p(λ) by Q de Casteljau steps (Kalbe & Zeilfelder 2008, Sect. 3: s(z) = b^[q]_0000).
/// Numerics: as `de_casteljau_step`, Q times; coefficient_count(Q-1) + ... + 1 dot products.
template <class T, int Q>
T evaluate(const BezierTet<T, Q>& b, const Vec<T, 4>& lambda) {
    if constexpr (Q == 0) {
        return b[0];
    } else {
        return evaluate(de_casteljau_step(b, lambda), lambda);
    }
}

/// Implementation of `blossom`: step with args[S], recurse.
template <class T, int Q, int S, int N>
T detail_blossom(const BezierTet<T, Q>& b, const Vec<T, 4> (&args)[N]) {
    if constexpr (Q == 0) {
        return b[0];
    } else {
        return detail_blossom<T, Q - 1, S + 1>(de_casteljau_step(b, args[S]), args);
    }
}

/// The blossom (polar form) p[a_0, ..., a_{Q-1}]: de Casteljau step s uses argument a_s
/// (Seidel 1993; Kalbe & Zeilfelder 2008, Sect. 5.3: "the arguments may vary on the different
/// levels"). Symmetric and multi-affine in its arguments; p[λ, ..., λ] = p(λ); with a_s the
/// vertices v0^i v1^j v2^k v3^l it returns c_ijkl.
/// Numerics: as `de_casteljau_step` applied with a_0 first.
template <class T, int Q>
T blossom(const BezierTet<T, Q>& b, const Vec<T, 4> (&args)[Q]) {
    static_assert(Q >= 1, "the blossom of a constant has no arguments");
    return detail_blossom<T, Q, 0>(b, args);
}

/// Q-1 de Casteljau steps at λ: the degree-1 coefficients b^[Q-1]_{e_m}, m = 0..3
/// (storage order of degree 1 is 1000 0100 0010 0001, i.e. m).
template <class T, int Q>
BezierTet<T, 1> reduce_to_linear(const BezierTet<T, Q>& b, const Vec<T, 4>& lambda) {
    if constexpr (Q == 1) {
        return b;
    } else {
        return reduce_to_linear(de_casteljau_step(b, lambda), lambda);
    }
}

/// Value and the partial derivatives ∂p/∂λm (m = 0..3, the λm treated as independent
/// variables) at λ.
template <class T>
struct ValueAndPartials {
    T value;
    /// partials[m] = ∂p/∂λm = Q · b^[Q-1]_{e_m}.
    Vec<T, 4> partials;
};

/// Value and ∂p/∂λm from the (Q-1)-th de Casteljau step (Kalbe & Zeilfelder 2008, Sect. 3:
/// "after the (q-1)th step three (independent) directional derivatives are immediately
/// available"). A derivative in a barycentric direction δ (Σδ = 0) is dot(partials, δ).
/// Numerics: Q-1 steps as `de_casteljau_step`; value = dot(λ, b^[Q-1]) (left fold, so it is
/// bit-identical to `evaluate`); partials[m] = T(Q) * b^[Q-1]_{e_m} (one multiplication).
template <class T, int Q>
ValueAndPartials<T> value_and_partials(const BezierTet<T, Q>& b, const Vec<T, 4>& lambda) {
    static_assert(Q >= 1, "derivatives need degree >= 1");
    const BezierTet<T, 1> last = reduce_to_linear(b, lambda);
    const Vec<T, 4> lin = {{last[0], last[1], last[2], last[3]}};
    const T q = T(static_cast<double>(Q));
    return {dot(lambda, lin), {{q * lin[0], q * lin[1], q * lin[2], q * lin[3]}}};
}

/// Directional derivative in the barycentric direction `dir` (the barycentric coordinates of a
/// vector, Σ dir_m = 0): dot(partials, dir).
/// Numerics: one left-fold dot product.
template <class T>
T directional_derivative(const ValueAndPartials<T>& vp, const Vec<T, 4>& dir) {
    return dot(vp.partials, dir);
}

/// Gradient with respect to the Cartesian frame whose axis directions have barycentric
/// coordinates dirs[0] = λ(x), dirs[1] = λ(y), dirs[2] = λ(z) (columns of a 4x3 matrix;
/// Kalbe & Zeilfelder 2008, Sect. 5.3: ∂s/∂x = <b^[q-1], λ(x)>).
/// Numerics: component a is dot(partials, dirs[a]), a left fold.
template <class T>
Vec<T, 3> gradient(const ValueAndPartials<T>& vp, const Mat<T, 4, 3>& dirs) {
    return vp.partials * dirs;
}

}  // namespace quadcast::bb
