// tests/spline/spline_test_util.hpp -- helpers shared by the spline tests
#pragma once

#include <array>
#include <random>

#include "quadcast/spline/spline.hpp"

namespace stest {

using namespace quadcast;
using namespace quadcast::spline;

/// Random data in [lo, hi], seeded.
template <class T>
Volume<T> random_volume(int nx, int ny, int nz, unsigned seed, double lo = -1.0, double hi = 1.0) {
    Volume<T> v(nx, ny, nz);
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(lo, hi);
    for (auto& x : v.data) x = T(u(rng));
    return v;
}

/// Value and world gradient of piece t of cube c at the cube-local point u (λ from u).
template <int Q, class T>
ValueAndGradient<T> eval_piece(const SplineGrid<Q, T>& g, int c, int t, const Vec<double, 3>& u) {
    const bb::BezierTet<T, Q> coef = tet_from_determining_set<Q>(g.cube_d(c), t);
    const bb::ValueAndPartials<T> vp = bb::value_and_partials(coef, barycentric(t, cast<T>(u)));
    const Vec<T, 3> gu = bb::gradient(vp, barycentric_directions<T>(t));
    return {vp.value, gu * T(2.0 / g.h)};
}

}  // namespace stest
