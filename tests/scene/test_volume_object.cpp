// tests/scene/test_volume_object.cpp -- the "volume" object kind: synthetic names, schemes, boxes, errors
#include <doctest/doctest.h>

#include "helpers.hpp"
#include "quadcast/scene/scene_json.hpp"

using namespace quadcast::scene;
using namespace scene_test;

namespace {

Scene parse_volume(const std::string& object) { return parse_scene("{\"objects\": [" + object + "]}", "s.json", "."); }

std::string volume_error(const std::string& object) {
    return parse_error_of([&] { parse_volume(object); }).what();
}

}  // namespace

TEST_CASE("a synthetic volume object records the generator, size, isovalue, scheme and its box") {
    const Scene s = parse_volume(R"({"volume": "synthetic:marschner_lobb:64", "iso": 0.5, "scheme": "s31", "color": [1, 0, 0]})");
    REQUIRE(s.volumes.size() == 1);
    const Volume& v = s.volumes[0];
    CHECK(v.synthetic);
    CHECK(v.input == "marschner-lobb");
    CHECK(v.size == 64);
    CHECK(v.iso == 0.5);
    CHECK(v.scheme == Volume::Scheme::s31);
    CHECK(v.material.color[0] == 1.0);
    CHECK(v.box.lo[0] == -1.0);
    CHECK(v.box.hi[2] == 1.0);
    CHECK(s.primitive_count() == 1);
    CHECK(s.warnings.empty());
    // The camera is fitted to the volume's box.
    CHECK(s.camera.target[0] == doctest::Approx(0.0));
    const Scene f = parse_volume(R"({"volume": "synthetic:franke", "iso": 0.3})");
    CHECK(f.volumes[0].input == "franke");
    CHECK(f.volumes[0].size == 0);
    CHECK(f.volumes[0].scheme == Volume::Scheme::qss);
    CHECK(f.volumes[0].box.lo[1] == 0.0);
    CHECK(parse_volume(R"({"volume": "synthetic:franke:8", "iso": 0.3, "scheme": "trilinear"})").volumes[0].scheme ==
          Volume::Scheme::trilinear);
}

TEST_CASE("bad volume objects are errors naming the pointer") {
    CHECK(volume_error(R"({"volume": "synthetic:marschner_lobb:64"})").find("/objects/0: missing required key 'iso'") != std::string::npos);
    CHECK(volume_error(R"({"volume": "synthetic:sphere", "iso": 0})").find("unknown synthetic volume 'sphere'") != std::string::npos);
    CHECK(volume_error(R"({"volume": "synthetic:franke:x", "iso": 0})").find("must be an integer in [2, 1024], got 'x'") != std::string::npos);
    CHECK(volume_error(R"({"volume": "synthetic:franke", "iso": 0, "scheme": "cubic"})").find("/objects/0/scheme") != std::string::npos);
    CHECK(volume_error(R"({"volume": "no_such_file.inr", "iso": 0})").find("no such file") != std::string::npos);
}

TEST_CASE("\"method\": bezier (default) or quadric, the latter for QSS only") {
    CHECK(parse_volume(R"({"volume": "synthetic:franke", "iso": 0.3})").volumes[0].method == Volume::Method::bezier);
    CHECK(parse_volume(R"({"volume": "synthetic:franke", "iso": 0.3, "method": "bezier", "scheme": "s31"})").volumes[0].method == Volume::Method::bezier);
    CHECK(parse_volume(R"({"method": "quadric", "volume": "synthetic:franke", "iso": 0.3})").volumes[0].method == Volume::Method::quadric);
    CHECK(volume_error(R"({"volume": "synthetic:franke", "iso": 0.3, "scheme": "s31", "method": "quadric"})")
              .find("/objects/0/method: \"quadric\" draws the pieces of a QSS spline") != std::string::npos);
    CHECK(volume_error(R"({"volume": "synthetic:franke", "iso": 0.3, "method": "stoll"})").find("/objects/0/method:") != std::string::npos);
}
