// tests/core/core_testing.hpp -- shared helpers of the core tests: seeded sampling, references, ULP statistics
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include <mpreal.h>

#include "quadcast/linalg.hpp"
#include "quadcast/quadric.hpp"

namespace qc_test {

using quadcast::Mat3;
using quadcast::Mat4;
using quadcast::Quadric;
using quadcast::Vec3;
using quadcast::Vec4;
using LD = long double;

/// One generator per iteration: the seed identifies a failing case.
inline std::mt19937 rng_for(std::uint32_t test_id, std::uint32_t iteration) {
    std::seed_seq seq{test_id, iteration};
    return std::mt19937(seq);
}

inline double uniform(std::mt19937& rng, double lo, double hi) {
    return std::uniform_real_distribution<double>(lo, hi)(rng);
}

/// 10^U(lo, hi).
inline double log_uniform(std::mt19937& rng, double lo_exp10, double hi_exp10) {
    return std::pow(10.0, uniform(rng, lo_exp10, hi_exp10));
}

template <class T>
Vec3<T> random_vec(std::mt19937& rng, double lo, double hi) {
    const double x = uniform(rng, lo, hi), y = uniform(rng, lo, hi), z = uniform(rng, lo, hi);
    return quadcast::vec3(T(x), T(y), T(z));
}

/// A uniformly distributed unit vector, rounded to T.
template <class T>
Vec3<T> random_dir(std::mt19937& rng) {
    std::normal_distribution<double> n;
    double v[3], l = 0;
    do {
        for (double& c : v) c = n(rng);
        l = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    } while (l < 1e-3);
    return quadcast::vec3(T(v[0] / l), T(v[1] / l), T(v[2] / l));
}

/// A quadric with A, b, c entries uniform in [-a_scale, a_scale], [-b_scale, ...], [-c_scale, ...].
template <class T>
Quadric<T> random_quadric(std::mt19937& rng, double a_scale = 1, double b_scale = 1, double c_scale = 1) {
    Mat3<T> A{};
    for (int j = 0; j < 3; ++j)
        for (int i = 0; i <= j; ++i) A[j][i] = A[i][j] = T(uniform(rng, -a_scale, a_scale));
    const Vec3<T> b = random_vec<T>(rng, -b_scale, b_scale);
    return quadcast::quadric_from_abc(A, b, T(uniform(rng, -c_scale, c_scale)));
}

// Long double references (exact for float inputs products; 11 extra bits for double) --------

template <class T>
Mat4<LD> to_ld(const Quadric<T>& q) { return quadcast::cast<LD>(q.q); }

inline Vec4<LD> hom(const Vec3<LD>& x, LD w = 1) { return {{x[0], x[1], x[2], w}}; }

/// x~^T Q x~ in long double.
inline LD eval_ld(const Mat4<LD>& q, const Vec3<LD>& x) {
    const Vec4<LD> xh = hom(x);
    LD s = 0;
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) s += xh[i] * q[j][i] * xh[j];
    return s;
}

/// |x~|^T |Q| |x~|: the magnitude of the terms of f(x).
inline LD eval_mag_ld(const Mat4<LD>& q, const Vec4<LD>& xh) {
    LD s = 0;
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) s += std::fabs(xh[i]) * std::fabs(q[j][i]) * std::fabs(xh[j]);
    return s;
}

/// 2 (A x + b) in long double.
inline Vec3<LD> grad_ld(const Mat4<LD>& q, const Vec3<LD>& x) {
    Vec3<LD> g{};
    for (int i = 0; i < 3; ++i) g[i] = 2 * (q[0][i] * x[0] + q[1][i] * x[1] + q[2][i] * x[2] + q[3][i]);
    return g;
}

inline LD norm_ld(const Vec3<LD>& v) { return std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]); }
inline LD dot_ld(const Vec3<LD>& a, const Vec3<LD>& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

// ULPs ---------------------------------------------------------------------------------------

/// ulp of T at the magnitude of x (x rounded to T first).
template <class T>
mpfr::mpreal ulp_of(const mpfr::mpreal& x) {
    const T r = std::fabs(static_cast<T>(x));
    const T up = std::nextafter(r, std::numeric_limits<T>::infinity());
    return mpfr::mpreal(static_cast<LD>(up)) - mpfr::mpreal(static_cast<LD>(r));
}

/// |x - ref| in ulps of T at ref.
template <class T>
double ulp_error(T x, const mpfr::mpreal& ref) {
    const mpfr::mpreal d = mpfr::abs(mpfr::mpreal(static_cast<LD>(x)) - ref);
    return (d / ulp_of<T>(ref)).toDouble();
}

/// median / p99 / max of a sample.
struct Stats {
    double median = 0, p99 = 0, max = 0;
    std::size_t n = 0;
};

inline Stats stats_of(std::vector<double> v) {
    Stats s;
    s.n = v.size();
    if (v.empty()) return s;
    std::sort(v.begin(), v.end());
    auto at = [&](double q) { return v[std::min(v.size() - 1, static_cast<std::size_t>(q * double(v.size() - 1) + 0.5))]; };
    s.median = at(0.5);
    s.p99 = at(0.99);
    s.max = v.back();
    return s;
}

inline std::string fmt(double x) {
    char buf[32];
    if (x != 0 && (std::fabs(x) >= 1e5 || std::fabs(x) < 1e-2))
        std::snprintf(buf, sizeof buf, "%.2e", x);
    else
        std::snprintf(buf, sizeof buf, "%.2f", x);
    return buf;
}

inline std::string fmt(const Stats& s) { return fmt(s.median) + " / " + fmt(s.p99) + " / " + fmt(s.max); }

}  // namespace qc_test
