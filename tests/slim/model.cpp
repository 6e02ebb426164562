// tests/slim/model.cpp -- the SLIM model file: round trip and located errors
#include <doctest/doctest.h>

#include <sstream>

#include "quadcast/slim/model.hpp"
#include "scene/helpers.hpp"

using namespace quadcast;
using namespace quadcast::slim;
using scene_test::parse_error_of;

namespace {

Model parse(const std::string& text) {
    std::istringstream in(text);
    return parse_model(in, "mem.slim");
}

const std::string kBall = "ball 1 2 3 0.5 -1 0 0 0 0 0 0 1 1 1";

}  // namespace

TEST_CASE("a model written and read back has the same doubles, planes included") {
    Model m;
    Ball a;
    a.center = vec3(0.1, -2.0 / 3.0, 1e-300);
    a.radius = 0.3;
    a.q = quadric_from_coefficients(Coefficients10<double>{-1.0 / 7, 0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 1.0 / 3, 2, 0.5});
    Ball b = a;
    b.has_plane = true;
    b.plane = vec4(0.6, 0.0, 0.8, -1.0 / 9);
    Ball c = b;
    c.has_plane2 = true;
    c.plane2 = vec4(0.0, -1.0, 0.0, 1.0 / 3);
    m.balls = {a, b, c};
    std::ostringstream out;
    write_model(out, m);
    const Model r = parse(out.str());
    CHECK(out.str().rfind("quadcast-slim 2\n", 0) == 0);
    REQUIRE(r.balls.size() == 3);
    for (int j = 0; j < 4; ++j)
        for (int i = 0; i < 4; ++i) CHECK(r.balls[1].q.q[j][i] == a.q.q[j][i]);
    CHECK(r.balls[0].center[1] == a.center[1]);
    CHECK(r.balls[0].center[2] == a.center[2]);
    CHECK_FALSE(r.balls[0].has_plane);
    CHECK(r.balls[1].has_plane);
    CHECK(r.balls[1].plane[3] == b.plane[3]);
    CHECK_FALSE(r.balls[1].has_plane2);
    REQUIRE(r.balls[2].has_plane2);
    for (int k = 0; k < 4; ++k) {
        CHECK(r.balls[2].plane[k] == b.plane[k]);
        CHECK(r.balls[2].plane2[k] == c.plane2[k]);
    }
}

TEST_CASE("a version 1 model (one plane per ball at most) still reads") {
    const Model r = parse("quadcast-slim 1\nballs 2\n" + kBall + "\n" + kBall + " plane 0 0 1 0.5\n");
    REQUIRE(r.balls.size() == 2);
    CHECK_FALSE(r.balls[0].has_plane);
    CHECK(r.balls[1].has_plane);
    CHECK_FALSE(r.balls[1].has_plane2);
    CHECK(r.balls[1].plane[3] == 0.5);
}

TEST_CASE("bad model files are errors naming the line and the field") {
    struct Case { std::string text; int line; std::string field, needle; };
    const Case cases[] = {
        {"quadcast-slam 1\n", 1, "header", "not a quadcast SLIM model"},
        {"quadcast-slim 3\n", 1, "version", "unsupported version '3'"},
        {"quadcast-slim 1\nballs 1\n" + kBall + " plane 0 0 1 0 plane 1 0 0 0\n", 3, "ball 0", "a second plane needs version 2"},
        {"quadcast-slim 2\nballs 1\n" + kBall + " plane 0 0 1 0 plane 1 0 0\n", 3, "ball 0", "found 24 values"},
        {"quadcast-slim 2\nballs 1\n" + kBall + " plane 0 0 1 0 plane 0 0 0 1\n", 3, "ball 0 second plane", "normal (a, b, c) is zero"},
        {"quadcast-slim 2\nballs 1\n" + kBall + " plane 0 0 1 0 plane 1 0 0 inf\n", 3, "ball 0 second plane d", "not finite"},
        {"quadcast-slim 2\nballs 1\n" + kBall + " plane 0 0 1 0 wall 1 0 0 1\n", 3, "ball 0", "found 25 values"},
        {"quadcast-slim 1\nballs x\n", 2, "balls", "not a non-negative integer"},
        {"quadcast-slim 1\nballs 2\n" + kBall + "\n", 3, "ball 1", "ends after 1 of 2 balls"},
        {"quadcast-slim 1\nballs 1\n" + kBall + " 7\n", 3, "ball 0", "found 16 values"},
        {"quadcast-slim 1\nballs 1\nball 1 2 3 0.5 -1 0 0 0 0 nan 0 1 1 1\n", 3, "ball 0 k011", "not finite"},
        {"quadcast-slim 1\nballs 1\nball 1 2 3 0 -1 0 0 0 0 0 0 1 1 1\n", 3, "ball 0 r", "radius must be positive"},
        {"quadcast-slim 1\nballs 1\nball 1 2 3 1 0 0 0 0 0 0 0 0 0 0\n", 3, "ball 0", "the quadric is zero"},
        {"quadcast-slim 1\nballs 1\n" + kBall + " plane 0 0 0 1\n", 3, "ball 0 plane", "normal (a, b, c) is zero"},
        {"quadcast-slim 1\nballs 1\n" + kBall + " plane 0 1 0 x\n", 3, "ball 0 plane d", "not a number"},
        {"quadcast-slim 1\nballs 1\n" + kBall + "\n# fine\n" + kBall + "\n", 5, "", "more ball lines than the count 1"},
    };
    for (const Case& c : cases) {
        CAPTURE(c.text);
        const auto e = parse_error_of([&] { parse(c.text); });
        CHECK(e.file() == "mem.slim");
        CHECK(e.line() == c.line);
        CHECK(e.field() == c.field);
        CHECK(e.message().find(c.needle) != std::string::npos);
    }
}
