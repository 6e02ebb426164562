// quadcast/spline/grid.hpp -- host side: volume data -> per-cube determining sets; CPU evaluation of the spline
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "quadcast/bb/bezier.hpp"
#include "quadcast/linalg.hpp"
#include "quadcast/spline/partition.hpp"
#include "quadcast/spline/quasi_interpolation.hpp"

namespace quadcast::spline {

/// Scalar volume data f[i,j,k], i fastest: data[i + nx*(j + ny*k)] (host-only).
template <class T>
struct Volume {
    int nx = 0, ny = 0, nz = 0;
    std::vector<T> data;

    Volume() = default;
    Volume(int x, int y, int z) : nx(x), ny(y), nz(z), data(static_cast<std::size_t>(x) * y * z, T(0)) {
        if (x < 1 || y < 1 || z < 1) throw std::invalid_argument("quadcast::spline::Volume: empty dimensions");
    }
    std::size_t index(int i, int j, int k) const {
        return static_cast<std::size_t>(i) + static_cast<std::size_t>(nx) * (static_cast<std::size_t>(j) + static_cast<std::size_t>(ny) * k);
    }
    T& at(int i, int j, int k) { return data[index(i, j, k)]; }
    const T& at(int i, int j, int k) const { return data[index(i, j, k)]; }
    /// Padding by clamp to edge: indices outside the data take the value of the nearest sample.
    const T& clamped(int i, int j, int k) const {
        return at(std::clamp(i, 0, nx - 1), std::clamp(j, 0, ny - 1), std::clamp(k, 0, nz - 1));
    }
};

/// The 27-point stencil of cube (i,j,k) (spec §1.1), clamped to edge outside the data.
template <class T>
Stencil<T> stencil(const Volume<T>& vol, int i, int j, int k) {
    Stencil<T> f{};
    for (int s = 0; s < stencil_size; ++s) {
        const IVec3 o = stencil_offset(s);
        f[s] = vol.clamped(i + o[0], j + o[1], k + o[2]);
    }
    return f;
}

/// Runs body(k) for k in [0, n) on up to `threads` std::threads (0: hardware concurrency),
/// in contiguous chunks. Host-only helper.
template <class F>
void parallel_for(int n, F&& body, unsigned threads = 0) {
    if (threads == 0) threads = std::max(1u, std::thread::hardware_concurrency());
    threads = std::min<unsigned>(threads, static_cast<unsigned>(std::max(n, 1)));
    if (threads <= 1) {
        for (int k = 0; k < n; ++k) body(k);
        return;
    }
    std::vector<std::thread> pool;
    const int chunk = (n + static_cast<int>(threads) - 1) / static_cast<int>(threads);
    for (unsigned w = 0; w < threads; ++w) {
        const int lo = static_cast<int>(w) * chunk, hi = std::min(n, lo + chunk);
        if (lo >= hi) break;
        pool.emplace_back([lo, hi, &body] {
            for (int k = lo; k < hi; ++k) body(k);
        });
    }
    for (auto& t : pool) t.join();
}

/// A spline on a grid of cubes: one cube per data sample, cube (i,j,k) centred at
/// origin + h·(i,j,k) with side h (data at cube centres, spec §1.1), and its determining-set
/// values, cube-major: d[(i + nx*(j + ny*k)) * d_count(Q) + m]. The spline is defined on
/// [origin - h/2, origin + (n - 1/2) h] per axis; the stencils of boundary cubes are padded by
/// clamp to edge (so the boundary layer of cubes sees a locally constant extension).
template <int Q, class T>
struct SplineGrid {
    int nx = 0, ny = 0, nz = 0;
    Vec<double, 3> origin{{0.0, 0.0, 0.0}};
    double h = 1.0;
    std::vector<T> d;

    static constexpr int degree = Q;
    int cube_count() const { return nx * ny * nz; }
    int cube_index(int i, int j, int k) const { return i + nx * (j + ny * k); }
    IVec3 cube_ijk(int c) const { return {c % nx, (c / nx) % ny, c / (nx * ny)}; }
    /// The determining set of cube c.
    DeterminingSet<T, Q> cube_d(int c) const {
        DeterminingSet<T, Q> r{};
        const std::size_t base = static_cast<std::size_t>(c) * d_count(Q);
        for (int m = 0; m < d_count(Q); ++m) r[m] = d[base + m];
        return r;
    }
    /// World-space centre v_Q of cube (i,j,k).
    Vec<double, 3> cube_centre(int i, int j, int k) const {
        return {{origin[0] + h * i, origin[1] + h * j, origin[2] + h * k}};
    }
};

/// Per-cube determining sets of a whole volume (Kalbe & Zeilfelder 2008, Sect. 4 and 5.1: the
/// CPU preprocessing; D2 = 20 and D3 = 56 values per cube). Each value is computed by
/// `determining_set_from_stencil` in the accumulator type Acc (double by default) and rounded
/// to T once, so shared points of neighbouring cubes get bit-identical values. Boundary padding:
/// clamp to edge. Runs on `threads` std::threads (0 = all cores), split over z slices.
template <int Q, class Acc = double, class T>
SplineGrid<Q, T> build_spline(const Volume<T>& vol, const Vec<double, 3>& origin, double h, unsigned threads = 0) {
    static_assert(Q == 2 || Q == 3, "QSS (2) or S31 (3)");
    if (!(h > 0.0)) throw std::invalid_argument("quadcast::spline::build_spline: spacing h must be > 0");
    SplineGrid<Q, T> g;
    g.nx = vol.nx;
    g.ny = vol.ny;
    g.nz = vol.nz;
    g.origin = origin;
    g.h = h;
    g.d.resize(static_cast<std::size_t>(vol.nx) * vol.ny * vol.nz * d_count(Q));
    parallel_for(vol.nz, [&](int k) {
        for (int j = 0; j < vol.ny; ++j)
            for (int i = 0; i < vol.nx; ++i) {
                const Stencil<T> f = stencil(vol, i, j, k);
                const DeterminingSet<Acc, Q> dv = determining_set_from_stencil<Q>(cast<Acc>(f));
                const std::size_t base = static_cast<std::size_t>(g.cube_index(i, j, k)) * d_count(Q);
                for (int m = 0; m < d_count(Q); ++m) g.d[base + m] = T(dv[m]);
            }
    }, threads);
    return g;
}

/// Where a world point lies: cube, tetrahedron, cube-local coordinates u.
struct PointLocation {
    int cube = 0;
    IVec3 ijk{};
    int tet = 0;
    Vec<double, 3> u{};
};

/// Locates a world point (spec §1.5): cube = round((x - origin)/h) clamped to the grid,
/// u = (x - v_Q)/(h/2), tetrahedron by `locate_tet`. Host-only.
template <int Q, class T>
PointLocation locate(const SplineGrid<Q, T>& g, const Vec<double, 3>& x) {
    PointLocation p;
    const int n[3] = {g.nx, g.ny, g.nz};
    for (int a = 0; a < 3; ++a) {
        const double r = std::nearbyint((x[a] - g.origin[a]) / g.h);
        p.ijk[a] = static_cast<int>(std::clamp(r, 0.0, static_cast<double>(n[a] - 1)));
        p.u[a] = (x[a] - (g.origin[a] + g.h * p.ijk[a])) / (0.5 * g.h);
    }
    p.cube = g.cube_index(p.ijk[0], p.ijk[1], p.ijk[2]);
    p.tet = locate_tet(p.u);
    return p;
}

/// Value and world-space gradient.
template <class T>
struct ValueAndGradient {
    T value;
    Vec<T, 3> gradient;
};

/// Evaluates the spline and its gradient at a world point on the CPU: locate, coefficients by
/// repeated averaging from the cube's determining set, de Casteljau at the barycentric
/// coordinates (computed in T from u), gradient from the (q-1)-th step with the barycentric
/// directions of the axes, scaled by 2/h (spec §1.5). Host-only (point location branches).
template <int Q, class T>
ValueAndGradient<T> evaluate(const SplineGrid<Q, T>& g, const Vec<double, 3>& x) {
    const PointLocation p = locate(g, x);
    const bb::BezierTet<T, Q> c = tet_from_determining_set<Q>(g.cube_d(p.cube), p.tet);
    const Vec<T, 4> lambda = barycentric(p.tet, cast<T>(p.u));
    const bb::ValueAndPartials<T> vp = bb::value_and_partials(c, lambda);
    const Vec<T, 3> gu = bb::gradient(vp, barycentric_directions<T>(p.tet));
    const T s = T(2.0 / g.h);
    return {vp.value, gu * s};
}

}  // namespace quadcast::spline
