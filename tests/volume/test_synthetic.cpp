// tests/volume/test_synthetic.cpp -- Marschner-Lobb and 3-D Franke volumes sample the stated functions
#include <doctest/doctest.h>

#include <cmath>
#include <numbers>

#include "quadcast/volume/synthetic.hpp"

using namespace quadcast::volume;

TEST_CASE("Marschner-Lobb has its standard values and sampling") {
    // Centre line r = 0: rho_r = cos(2 pi 6) = 1, so f = (1 - sin(pi z/2) + 0.5) / 2.5.
    CHECK(marschner_lobb(0, 0, 0) == doctest::Approx(0.6).epsilon(1e-15));
    CHECK(marschner_lobb(0, 0, 1) == doctest::Approx(0.2).epsilon(1e-15));
    // r = 1: cos(pi/2) = 0, rho_r = 1 as well; r = 2/3: cos(pi/3) = 1/2, rho_r = cos(6 pi) = 1;
    // r such that cos(pi r/2) = 1/12: rho_r = cos(pi) = -1 -> f = (1 - sin(pi z/2)) / 2.5.
    const double r = 2.0 / std::numbers::pi * std::acos(1.0 / 12.0);
    CHECK(marschner_lobb(r, 0, 0) == doctest::Approx(0.4).epsilon(1e-12));
    CHECK(marschner_lobb(0, r, -1) == doctest::Approx(0.8).epsilon(1e-12));
    const VolumeData v = marschner_lobb_volume(41);
    CHECK(v.nx() == 41);
    CHECK(v.spacing[0] == doctest::Approx(0.05));
    CHECK(v.origin[1] == -1.0);
    CHECK(v.grid.at(20, 20, 20) == static_cast<float>(marschner_lobb(0, 0, 0)));
    CHECK(v.grid.at(3, 7, 11) == static_cast<float>(marschner_lobb(-1 + 0.05 * 3, -1 + 0.05 * 7, -1 + 0.05 * 11)));
    CHECK(v.min >= 0.0f);
    CHECK(v.max <= 1.0f);
    CHECK_THROWS_AS((void)marschner_lobb_volume(1), VolumeError);
}

TEST_CASE("the 3-D Franke volume samples Franke's function on the unit cube") {
    // The first peak 3/4 exp(0) at (2/9, 2/9, 2/9) plus the other three terms there.
    const double a = 2.0, b = 2.0, c = 2.0;
    const double f = 0.75 + 0.75 * std::exp(-(a + 1) * (a + 1) / 49 - (b + 1) / 10 - (c + 1) / 10) +
                     0.5 * std::exp(-((a - 7) * (a - 7) + (b - 3) * (b - 3) + (c - 5) * (c - 5)) / 4) -
                     0.2 * std::exp(-(a - 4) * (a - 4) - (b - 7) * (b - 7) - (c - 5) * (c - 5));
    CHECK(franke3(2.0 / 9, 2.0 / 9, 2.0 / 9) == doctest::Approx(f).epsilon(1e-14));
    const VolumeData v = franke_volume(10);
    CHECK(v.grid.at(2, 2, 2) == static_cast<float>(franke3(2.0 / 9, 2.0 / 9, 2.0 / 9)));
    CHECK(v.origin[0] == 0.0);
    CHECK(v.spacing[2] == doctest::Approx(1.0 / 9));
}
