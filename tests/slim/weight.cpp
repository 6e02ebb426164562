// tests/slim/weight.cpp -- the SLIM blending weight (quadcast/slim_blend.hpp) against its analytic form in long double
#include <doctest/doctest.h>

#include <cmath>

#include "quadcast/slim_blend.hpp"

using namespace quadcast;

namespace {

/// The weight's definition, evaluated independently in long double: exp(-4 t^2) on [0, 1/2],
/// 4 e^-1 (1 - t)^2 on [1/2, 1], 0 beyond.
long double weight_exact(long double t) {
    if (t < 0.5L) return std::exp(-4.0L * t * t);
    if (t < 1.0L) return 4.0L * std::exp(-1.0L) * (1.0L - t) * (1.0L - t);
    return 0.0L;
}

}  // namespace

TEST_CASE("the SLIM weight is 1 at the centre and 0 on and beyond the sphere") {
    CHECK(slim_weight(0.0f) == 1.0f);
    CHECK(slim_weight(0.0) == 1.0);
    CHECK(slim_weight(1.0f) == 0.0f);
    CHECK(slim_weight(1.0) == 0.0);
    CHECK(slim_weight(1.5f) == 0.0f);
    CHECK(slim_weight(1e6f) == 0.0f);
    CHECK(slim_weight(std::nextafter(1.0f, 0.0f)) > 0.0f);
}

TEST_CASE("the float and double weights are within a few ULP of the analytic weight") {
    double worst_f = 0, worst_d = 0;
    for (int i = 0; i <= 100000; ++i) {
        const float tf = float(i) / 100000.0f;
        const long double ref = weight_exact(static_cast<long double>(tf));
        const long double ef = std::fabs(static_cast<long double>(slim_weight(tf)) - ref);
        const long double ed = std::fabs(static_cast<long double>(slim_weight(static_cast<double>(tf))) - ref);
        // In units of the float spacing at the reference value (and at least the smallest normal's).
        const long double ulp_f = std::max<long double>(std::ldexp(1.0L, std::ilogb(static_cast<double>(ref)) - 23), 1e-38L);
        worst_f = std::max(worst_f, static_cast<double>(ef / ulp_f));
        worst_d = std::max(worst_d, static_cast<double>(ed));
    }
    MESSAGE("largest float error: " << worst_f << " ULP, double: " << worst_d);
    CHECK(worst_f <= 8.0);
    // The degree-11 Taylor polynomial's truncation (<= 1/12! relative) bounds the double error.
    CHECK(worst_d <= 3e-9);
}

TEST_CASE("the SLIM weight never increases from the centre to the sphere") {
    float prev = slim_weight(0.0f);
    int increases = 0;
    for (int i = 1; i <= 1 << 20; ++i) {
        const float w = slim_weight(float(i) / float(1 << 20));
        if (w > prev) ++increases;
        prev = w;
    }
    CHECK(increases == 0);
    double prev_d = 1.0;
    for (int i = 1; i <= 100000; ++i) {
        const double w = slim_weight(double(i) / 100000.0);
        CHECK(w <= prev_d);
        prev_d = w;
    }
}

TEST_CASE("the weight and its slope are continuous where the Gaussian meets the quadratic, and at the sphere") {
    // Value: both pieces at t = 1/2 give the same number (the tail's factor is 4 E(1)).
    const double below = slim_weight(std::nextafter(0.5, 0.0)), at = slim_weight(0.5);
    CHECK(std::fabs(below - at) < 1e-15);
    CHECK(std::fabs(at - std::exp(-1.0)) < 3e-9);
    // Slope: one-sided difference quotients of the double weight converge to the same value, the
    // analytic -4 / e (long double).
    const double slope = static_cast<double>(-4.0L * std::exp(-1.0L));
    for (double h : {1e-4, 1e-5, 1e-6}) {
        const double left = (slim_weight(0.5) - slim_weight(0.5 - h)) / h;
        const double right = (slim_weight(0.5 + h) - slim_weight(0.5)) / h;
        CHECK(std::fabs(left - right) < 20.0 * h);
        CHECK(std::fabs(left - slope) < 20.0 * h);
        CHECK(std::fabs(right - slope) < 20.0 * h);
    }
    // At the sphere the weight and its slope go to 0 (C1 with the zero outside).
    const double h = 1e-4;
    CHECK(std::fabs((slim_weight(1.0) - slim_weight(1.0 - h)) / h) < 20.0 * h);
}
