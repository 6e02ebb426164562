// tests/core/test_umbrella.cpp -- every public header compiles together (no name clashes)
#include <doctest/doctest.h>

#include "quadcast/quadcast.hpp"
#include "quadcast/bb/bb.hpp"
#include "quadcast/spline/spline.hpp"
#include "quadcast/primitives_host.hpp"

TEST_CASE("the umbrella headers compile together and name the documented vocabulary") {
    const quadcast::Quadric<float> q{quadcast::identity<float, 4>()};
    CHECK(quadcast::evaluate(q, quadcast::vec3(1.0f, 0.0f, 0.0f)) == 2.0f);
}
