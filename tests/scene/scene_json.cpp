// tests/scene/scene_json.cpp -- the JSON scene loader: examples, errors with pointers and positions
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>

#include "helpers.hpp"
#include "quadcast/image/image_io.hpp"
#include "quadcast/scene/scene_json.hpp"
#include "quadcast/scene/scene_render.hpp"

using namespace quadcast::scene;
using namespace scene_test;

namespace {

Scene parse(const std::string& text, const fs::path& base = ".") { return parse_scene(text, "s.json", base); }

ParseError error_of(const std::string& text, const fs::path& base = ".") {
    return parse_error_of([&] { parse(text, base); });
}

/// A scene with one object entry written as `object`.
std::string with_object(const std::string& object) { return "{\"objects\": [" + object + "]}"; }

const char* const kSphere = R"({"sphere": {"center": [0, 0, 0], "radius": 1}})";

}  // namespace

TEST_CASE("the example scenes load") {
    require_pymol_data();
    Scene s = load_scene(example_scenes() / "spheres.json");
    CHECK(s.warnings.empty());
    CHECK(s.spheres.size() == 2);
    CHECK(s.ellipsoids.size() == 2);
    CHECK(s.cylinders.size() == 1);
    CHECK(s.cones.size() == 1);
    CHECK(s.quadrics.size() == 2);
    CHECK(s.quads.size() == 1);
    CHECK(s.lights.size() == 2);
    CHECK(s.lights[1].kind == Light::Kind::point);
    CHECK(s.options.shadows);
    CHECK(s.camera.fov_y_deg == 40);
    CHECK(s.quadrics[1].bound == Quadric::Bound::tetrahedron);
    CHECK(s.spheres[1].material.shininess == 64);

    Scene q = load_scene(example_scenes() / "quads_cube.json");
    CHECK(q.warnings.empty());
    CHECK(q.quads.size() == 6 + 64 + 1);
    CHECK(q.camera.projection == Projection::orthographic);
    CHECK(q.camera.height == 7);
    CHECK_FALSE(q.options.culling);
    CHECK(q.options.silhouettes);

    Scene m = load_scene(example_scenes() / "molecule_1tii.json");
    CHECK(m.warnings.empty());
    CHECK(m.spheres.size() == 5684);
    CHECK(m.cylinders.size() % 2 == 0);
    CHECK(m.cylinders.size() > 2 * 5000);
    CHECK(m.options.deferred);
    // No camera in the file: the fitted one sees every atom inside near..far and the fov cone.
    const Camera& c = m.camera;
    CHECK_NOTHROW(c.validate());
    const Vec3d view = normalize(c.target - c.eye);
    const double half = 0.5 * c.fov_y_deg * std::numbers::pi / 180.0;
    for (const Sphere& a : m.spheres) {
        const Vec3d d = a.center - c.eye;
        const double depth = dot(d, view);
        CHECK(depth > c.near);
        CHECK(depth < c.far);
        CHECK(length(d - view * depth) < depth * std::tan(half));
    }
}

TEST_CASE("JSON syntax errors name line and column") {
    const std::string text = "{\n  \"objects\": [\n    {\"sphere\": {\"center\": [0, 0, 0], \"radius\": 1},,\n  ]\n}\n";
    ParseError e = error_of(text);
    CHECK(e.line() == 3);
    CHECK(e.column() == 51);  // the second comma
    CHECK(std::string(e.what()).rfind("s.json:3:51: syntax error while parsing object key - unexpected ','", 0) == 0);

    // A truncated file: the error is at its end.
    const std::string full = read_text(example_scenes() / "spheres.json");
    const std::string cut = full.substr(0, full.size() / 2);
    e = error_of(cut);
    CHECK(e.message().rfind("syntax error", 0) == 0);
    CHECK(e.line() == 1 + std::count(cut.begin(), cut.end(), '\n'));
    e = error_of(R"({"objects": [{"sphere": {"center": [0, 0, 0], "radius": 1}})");
    CHECK(e.message() == "syntax error while parsing array - unexpected end of input; expected ']'");
    CHECK(e.column() == 60);  // just past the last character

    e = error_of("");
    CHECK(std::string(e.what()).rfind("s.json:1:1: syntax error", 0) == 0);
    e = error_of("[1, 2] x");
    CHECK(e.line() == 1);
    CHECK(e.column() == 8);
}

TEST_CASE("NaN and overflowing numbers are errors at their line and column") {
    ParseError e = error_of("{\"objects\": [\n {\"sphere\": {\"center\": [0, 0, 0], \"radius\": NaN}}]}");
    CHECK(e.line() == 2);
    CHECK(e.column() == 45);
    CHECK(e.message().find("JSON has no NaN or Infinity") != std::string::npos);
    e = error_of("{\"objects\": [\n {\"sphere\": {\"center\": [0, -Infinity, 0], \"radius\": 1}}]}");
    CHECK(e.line() == 2);
    CHECK(e.message().find("JSON has no NaN or Infinity") != std::string::npos);
    e = error_of("{\"objects\": [\n {\"sphere\": {\"center\": [0, 0, 0], \"radius\": 1e999}}]}");
    CHECK(e.line() == 2);
    CHECK(e.column() == 45);
    CHECK(e.message() == "number overflow parsing '1e999' (not representable as a finite double)");
    e = error_of("{\"objects\": [\n {\"sphere\": {\"center\": [0, 0, 0], \"radius\": \"NaN\"}}]}");
    CHECK(std::string(e.what()) == "s.json:2:45: /objects/0/sphere/radius: expected a number, got string \"NaN\"");
}

TEST_CASE("unknown keys are errors naming the pointer, the position and a close key") {
    const std::string text = "{\"objects\": [\n  " + std::string(kSphere) +
                             ",\n  {\"sphere\": {\"center\": [0, 0, 0], \"radus\": 1}}\n]}";
    ParseError e = error_of(text);
    CHECK(e.field() == "/objects/1/sphere/radus");
    CHECK(e.line() == 3);
    CHECK(e.column() == 36);
    CHECK(e.message() == "unknown key 'radus' (did you mean 'radius'?); allowed: center, radius, comment");

    e = error_of(R"({"obejcts": []})");
    CHECK(e.field() == "/obejcts");
    CHECK(e.message().find("did you mean 'objects'") != std::string::npos);
    e = error_of(with_object(R"({"sphre": {"center": [0, 0, 0], "radius": 1}})"));
    CHECK(e.field() == "/objects/0/sphre");
    CHECK(e.message().find("did you mean 'sphere'") != std::string::npos);
    e = error_of(with_object(R"({"sphere": {"center": [0, 0, 0], "radius": 1}, "colour": [1, 0, 0]})"));
    CHECK(e.field() == "/objects/0/colour");
    e = error_of(R"({"objects": [], "options": {"shadow": true}})");
    CHECK(e.field() == "/options/shadow");
    e = error_of(R"({"objects": [], "camera": {"eye": [0, 0, 5], "target": [0, 0, 0], "fov": 45}})");
    CHECK(e.message().find("did you mean 'fov_y'") != std::string::npos);
    // Keys with '/' and '~' are escaped in the pointer (RFC 6901).
    e = error_of(R"({"objects": [], "a/b~c": 1})");
    CHECK(e.field() == "/a~1b~0c");
}

TEST_CASE("wrong types, array lengths, ranges and missing keys are errors naming the pointer") {
    auto what = [](const std::string& object) { return std::string(error_of(with_object(object)).what()); };
    CHECK(what(R"({"sphere": {"center": [0, 0], "radius": 1}})") ==
          "s.json:1:36: /objects/0/sphere/center: expected an array of 3 numbers, got 2 elements");
    CHECK(what(R"({"sphere": {"center": [0, 0, "0"], "radius": 1}})") ==
          "s.json:1:43: /objects/0/sphere/center/2: expected a number, got string \"0\"");
    CHECK(what(R"({"sphere": {"center": [0, 0, 0], "radius": -1}})") ==
          "s.json:1:57: /objects/0/sphere/radius: expected a number > 0, got -1");
    CHECK(what(R"({"sphere": {"center": [0, 0, 0]}})") ==
          "s.json:1:25: /objects/0/sphere: missing required key 'radius'");
    CHECK(what(R"({"sphere": {"center": [0, 0, 0], "radius": 1}, "color": [1, 2, 0]})") ==
          "s.json:1:74: /objects/0/color/1: expected a number in [0, 1], got 2");
    CHECK(what(R"({"sphere": [0, 0, 0, 1]})") == "s.json:1:25: /objects/0/sphere: expected an object, got an array of 4");
    CHECK(what(R"({"cylinder": {"p0": [0, 0, 0], "p1": [0, 0, 1], "radius": 1, "caps": "yes"}})") ==
          "s.json:1:83: /objects/0/cylinder/caps: expected true or false, got string \"yes\"");
    CHECK(what(R"({"cylinder": {"p0": [0, 0, 0], "p1": [0, 0, 0], "radius": 1}})") ==
          "s.json:1:51: /objects/0/cylinder/p1: equals p0 (zero-length axis)");
    CHECK(what(R"({"color": [1, 0, 0]})") ==
          "s.json:1:14: /objects/0: no object kind; an object needs one of the keys: sphere, ellipsoid, cylinder, cone, "
          "quadric, quad, pdb, off, volume, slim, tetmesh");
    CHECK(what(R"({"sphere": {"center": [0, 0, 0], "radius": 1}, "quad": {}})").find("/objects/0/quad: an object has one kind") !=
          std::string::npos);
    CHECK(what("42") == "s.json:1:14: /objects/0: expected an object such as {\"sphere\": {...}}, got number 42");
    CHECK(std::string(error_of("[]").what()) == "s.json:1:1: /: a scene is a JSON object with \"objects\", \"camera\", ..., got an array of 0");
    CHECK(std::string(error_of("{}").what()) == "s.json:1:1: /: missing required key 'objects'");
    CHECK(what(R"({"sphere": {"center": [0, 0, 0], "radius": 1}, "color": [1, 0, 0], "material": {"color": [0, 1, 0]}})")
              .find("/objects/0/color: the colour is given twice") != std::string::npos);
}

TEST_CASE("duplicate keys are errors at the second occurrence") {
    const ParseError e = error_of(with_object(R"({"sphere": {"center": [0, 0, 0], "radius": 1, "radius": 2}})"));
    CHECK(std::string(e.what()) == "s.json:1:60: /objects/0/sphere/radius: duplicate key");
}

TEST_CASE("columns count characters, not bytes") {
    const ParseError e = error_of("{\"comment\": \"\xC3\xA9\xC3\xA9\", \"objects\": [], \"x\": 1}");
    CHECK(e.field() == "/x");
    CHECK(e.column() == 34);
}

TEST_CASE("cameras are validated and name the offending key") {
    auto cam = [](const std::string& c) { return error_of(R"({"objects": [], "camera": )" + c + "}"); };
    CHECK(cam(R"({"eye": [0, 0, 5], "target": [0, 0, 0], "up": [0, 0, 1]})").field() == "/camera/up");
    CHECK(cam(R"({"eye": [0, 0, 5], "target": [0, 0, 5]})").field() == "/camera/target");
    CHECK(cam(R"({"eye": [0, 0, 5], "target": [0, 0, 0], "near": 0})").field() == "/camera/near");
    CHECK(cam(R"({"eye": [0, 0, 5], "target": [0, 0, 0], "near": 2, "far": 1})").field() == "/camera/far");
    CHECK(cam(R"({"eye": [0, 0, 5], "target": [0, 0, 0], "fov_y": 180})").field() == "/camera/fov_y");
    CHECK(cam(R"({"type": "orthographic", "eye": [0, 0, 5], "target": [0, 0, 0], "height": -2})").field() == "/camera/height");
    ParseError e = cam(R"({"type": "orthographic", "eye": [0, 0, 5], "target": [0, 0, 0], "fov_y": 30})");
    CHECK(e.field() == "/camera/fov_y");
    CHECK(e.message() == "only for perspective cameras (orthographic cameras take \"height\")");
    e = cam(R"({"type": "fisheye", "eye": [0, 0, 5], "target": [0, 0, 0]})");
    CHECK(e.message() == "'fisheye' is not one of: perspective, orthographic");
    CHECK(cam(R"({"target": [0, 0, 0]})").message() == "missing required key 'eye'");
    // Camera::validate for code that builds cameras itself.
    Camera c;
    c.up = Vec3d{{0, 0, 1}};
    CHECK_THROWS_AS(c.validate(), std::invalid_argument);
    // near/far left out: they enclose the scene.
    Scene s = parse(R"({"objects": [{"sphere": {"center": [0, 0, -50], "radius": 10}}],
                        "camera": {"eye": [0, 0, 100], "target": [0, 0, 0]}})");
    CHECK(s.camera.near < 140);
    CHECK(s.camera.far > 160);
    CHECK(s.camera.near > 0);
}

TEST_CASE("lights: direction or position, defaults to a headlight") {
    Scene s = parse(with_object(kSphere));
    REQUIRE(s.lights.size() == 1);
    CHECK(s.lights[0].kind == Light::Kind::directional);
    const Vec3d view = s.camera.target - s.camera.eye;
    CHECK(length(cross(view, s.lights[0].direction)) == doctest::Approx(0.0));
    CHECK(parse(R"({"objects": [], "lights": []})").lights.empty());
    auto light = [](const std::string& l) { return error_of(R"({"objects": [], "lights": [)" + l + "]}"); };
    CHECK(light(R"({"direction": [0, 0, -1], "position": [0, 0, 1]})").field() == "/lights/0");
    CHECK(light(R"({"color": [1, 1, 1]})").message() == "a light has either \"direction\" or \"position\"");
    CHECK(light(R"({"direction": [0, 0, 0]})").field() == "/lights/0/direction");
    CHECK(light(R"({"direction": [0, 0, -1], "intensity": -1})").field() == "/lights/0/intensity");
}

TEST_CASE("quadrics: coefficients match the 4x4 matrix of Stoll et al. 2006, eq. 3-4") {
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(-2.0, 2.0);
    for (int iter = 0; iter < 100; ++iter) {
        rng.seed(100u + unsigned(iter));
        std::array<double, 10> k{};
        for (double& x : k) x = u(rng);
        const Mat4d q = quadric_matrix_from_coefficients(k);
        const double x = u(rng), y = u(rng), z = u(rng);
        const quadcast::Vec<double, 4> h{{x, y, z, 1.0}};
        const double via_matrix = quadcast::dot(h, q * h);
        const double poly = k[0] + k[1] * x + k[2] * y + k[3] * z + k[4] * x * y + k[5] * y * z + k[6] * z * x + k[7] * x * x +
                            k[8] * y * y + k[9] * z * z;
        CHECK(via_matrix == doctest::Approx(poly).epsilon(1e-12).scale(10.0));
        for (int i = 0; i < 4; ++i)
            for (int j = 0; j < 4; ++j) CHECK(q[i][j] == q[j][i]);
    }
}

TEST_CASE("quadric input errors: zero, both forms, degenerate tetrahedron; an asymmetric matrix is symmetrized") {
    auto quadric = [](const std::string& q) { return with_object(R"({"quadric": )" + q + "}"); };
    const std::string sphere_bound = R"("bound": {"sphere": {"center": [0, 0, 0], "radius": 2}})";
    ParseError e = error_of(quadric(R"({"coefficients": [0, 0, 0, 0, 0, 0, 0, 0, 0, 0], )" + sphere_bound + "}"));
    CHECK(e.field() == "/objects/0/quadric");
    CHECK(e.message() == "every coefficient is zero (no surface)");
    e = error_of(quadric(R"({"coefficients": [1, 0, 0, 0, 0, 0, 0, 0, 0], )" + sphere_bound + "}"));
    CHECK(e.message() == "expected an array of 10 numbers, got 9 elements");
    e = error_of(quadric(R"({"coefficients": [-1, 0, 0, 0, 0, 0, 0, 1, 1, 1], "matrix": [], )" + sphere_bound + "}"));
    CHECK(e.field() == "/objects/0/quadric");
    e = error_of(quadric(R"({"matrix": [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1], [0, 0, 0, -1]], )" + sphere_bound + "}"));
    CHECK(e.field() == "/objects/0/quadric/matrix/2");
    e = error_of(quadric(R"({"coefficients": [-1, 0, 0, 0, 0, 0, 0, 1, 1, 1],
                            "bound": {"tetrahedron": [[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]]}})"));
    CHECK(e.field() == "/objects/0/quadric/bound/tetrahedron");
    CHECK(e.message() == "degenerate tetrahedron (zero volume)");
    e = error_of(quadric(R"({"coefficients": [-1, 0, 0, 0, 0, 0, 0, 1, 1, 1], "bound": {}})"));
    CHECK(e.message() == "give either \"sphere\" or \"tetrahedron\"");
    Scene s = parse(quadric(R"({"matrix": [[1, 2, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, -1]], )" + sphere_bound + "}"));
    REQUIRE(s.quadrics.size() == 1);
    CHECK(s.quadrics[0].q[1][0] == 1.0);
    CHECK(s.quadrics[0].q[0][1] == 1.0);
    REQUIRE(s.warnings.size() == 1);
    CHECK(s.warnings[0].where.field == "/objects/0/quadric/matrix");
}

TEST_CASE("ellipsoids from orthogonal axes or radii and a rotation") {
    Scene s = parse(with_object(R"({"ellipsoid": {"center": [1, 2, 3], "radii": [1, 2, 3], "rotation": {"axis": [0, 0, 1], "angle": 90}}})"));
    REQUIRE(s.ellipsoids.size() == 1);
    const Ellipsoid& e = s.ellipsoids[0];
    CHECK(e.axes[0][1] == doctest::Approx(1.0));  // x axis turned onto y
    CHECK(e.axes[1][0] == doctest::Approx(-2.0));
    CHECK(e.axes[2][2] == doctest::Approx(3.0));
    const Aabb b = bounds(e);
    CHECK(b.hi[0] == doctest::Approx(3.0));
    CHECK(b.hi[1] == doctest::Approx(3.0));
    CHECK(b.hi[2] == doctest::Approx(6.0));
    ParseError err = error_of(with_object(R"({"ellipsoid": {"center": [0, 0, 0], "axes": [[1, 0, 0], [1, 1, 0], [0, 0, 1]]}})"));
    CHECK(err.field() == "/objects/0/ellipsoid/axes/1");
    CHECK(err.message().rfind("not orthogonal to axis 0", 0) == 0);
    err = error_of(with_object(R"({"ellipsoid": {"center": [0, 0, 0], "radii": [1, 1, 1], "axes": [[1, 0, 0], [0, 1, 0], [0, 0, 1]]}})"));
    CHECK(err.field() == "/objects/0/ellipsoid");
}

TEST_CASE("a degenerate quad is an error") {
    const ParseError e = error_of(with_object(R"({"quad": {"corners": [[0, 0, 0], [1, 1, 1], [2, 2, 2], [3, 3, 3]]}})"));
    CHECK(e.field() == "/objects/0/quad/corners");
    CHECK(e.message() == "degenerate quad: the corners are collinear or coincident (zero area)");
}

TEST_CASE("file paths resolve against the scene's directory; reader errors keep their file and line") {
    require_pymol_data();
    TempDir dir;
    fs::create_directories(dir.path / "data");
    fs::copy_file(pymol_test_dat() / "tiny.pdb", dir.path / "data" / "tiny.pdb");
    fs::copy_file(example_scenes() / "twisted_cube.off", dir.path / "cube.off");
    const fs::path scene = dir.write("scene.json", R"({"objects": [
        {"pdb": "data/tiny.pdb", "style": "space_filling", "color": [0.5, 0.5, 0.5]},
        {"off": "cube.off", "triangles": "error"}]})");
    Scene s = load_scene(scene);
    CHECK(s.spheres.size() == 37);
    CHECK(s.cylinders.empty());
    CHECK(s.spheres[0].material.color[0] == 0.5);
    CHECK(s.quads.size() == 6);

    // Loading from another working directory changes nothing: paths are relative to the file.
    const fs::path cwd = fs::current_path();
    fs::current_path(fs::temp_directory_path());
    CHECK(load_scene(scene).spheres.size() == 37);
    fs::current_path(cwd);

    // A missing file names the pointer.
    ParseError e = parse_error_of([&] { load_scene(dir.write("missing.json", R"({"objects": [{"pdb": "nope.pdb"}]})")); });
    CHECK(e.field() == "/objects/0/pdb");
    CHECK(e.line() == 1);
    CHECK(e.column() == 22);
    CHECK(e.message() == "cannot open '" + (dir.path / "nope.pdb").string() + "': no such file");
    e = parse_error_of([&] { load_scene(dir.write("dir.json", R"({"objects": [{"off": "data"}]})")); });
    CHECK(e.message().find("is not a regular file") != std::string::npos);

    // An error inside the PDB file names that file and line, and the scene entry.
    dir.write("bad.pdb", head_lines(pymol_test_dat() / "tiny.pdb", 4) + "ATOM      5  CB  PRO C   8      25.419  25.3");
    e = parse_error_of([&] { load_scene(dir.write("bad.json", "{\"objects\": [\n  {\"pdb\": \"bad.pdb\"}]}")); });
    CHECK(e.file() == (dir.path / "bad.pdb").string());
    CHECK(e.line() == 5);
    CHECK(e.field() == "y (columns 39-46)");
    CHECK(e.message().find("(loaded by " + (dir.path / "bad.json").string() + ":2:11: /objects/0/pdb)") != std::string::npos);

    // So does an error inside an OFF file.
    dir.write("bad.off", "OFF\n4 1 0\n0 0 0\n1 0 0\n1 1 1\n");
    e = parse_error_of([&] { load_scene(dir.write("badoff.json", R"({"objects": [{"off": "bad.off"}]})")); });
    CHECK(e.file() == (dir.path / "bad.off").string());
    CHECK(e.field() == "vertex 3");

    // PDB warnings reach the scene.
    fs::copy_file(pymol_test_dat() / "odd01.pdb", dir.path / "odd01.pdb");
    Scene odd = load_scene(dir.write("odd.json", R"({"objects": [{"pdb": "odd01.pdb"}]})"));
    CHECK(odd.warnings.size() == 3);
    CHECK(odd.spheres.size() == 18);
    e = parse_error_of([&] { load_scene(dir.write("strict.json", R"({"objects": [{"pdb": "odd01.pdb", "strict": true}]})")); });
    CHECK(e.line() == 16);

    // Style options are checked against the style.
    e = parse_error_of([&] {
        load_scene(dir.write("style.json", R"({"objects": [{"pdb": "odd01.pdb", "style": "space_filling", "bond_radius": 0.2}]})"));
    });
    CHECK(e.field() == "/objects/0/bond_radius");
    e = parse_error_of([&] { load_scene(dir.write("style2.json", R"({"objects": [{"pdb": "odd01.pdb", "style": "cartoon"}]})")); });
    CHECK(e.message() == "'cartoon' is not one of: balls_and_sticks, space_filling, skin");
}

TEST_CASE("a missing scene file is an error naming it") {
    const ParseError e = parse_error_of([] { load_scene("/nonexistent/scene.json"); });
    CHECK(std::string(e.what()) == "/nonexistent/scene.json: cannot open: No such file or directory");
}

TEST_CASE("an empty scene loads with a warning") {
    Scene s = parse(R"({"objects": []})");
    CHECK(s.primitive_count() == 0);
    REQUIRE(s.warnings.size() == 1);
    CHECK(s.warnings[0].to_string() == "s.json:1:13: warning: /objects: the scene has nothing to draw");
    CHECK(s.bounds().empty());
}

TEST_CASE("bounding boxes enclose sampled surface points and are tight") {
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    const Cylinder cyl{{{1, 2, 3}}, {{2, -1, 4}}, 0.5, true, {}};
    const Cone cone{{{0, 0, 0}}, {{1, 1, 1}}, 0.7, true, {}};
    const Aabb bc = bounds(cyl), bk = bounds(cone);
    Aabb sc, sk;  // boxes of the samples
    for (int i = 0; i < 20000; ++i) {
        rng.seed(500u + unsigned(i));
        const double t = i % 3 == 0 ? 0.0 : i % 3 == 1 ? 1.0 : u(rng), phi = 2 * std::numbers::pi * u(rng);
        auto rim = [&](const Vec3d& a, const Vec3d& b, double r) {
            const Vec3d d = normalize(b - a);
            const Vec3d e1 = normalize(cross(d, std::abs(d[0]) < 0.9 ? Vec3d{{1, 0, 0}} : Vec3d{{0, 1, 0}}));
            const Vec3d e2 = cross(d, e1);
            return (e1 * std::cos(phi) + e2 * std::sin(phi)) * r;
        };
        const Vec3d pc = (cyl.p0 + (cyl.p1 - cyl.p0) * t) + rim(cyl.p0, cyl.p1, cyl.radius);
        const Vec3d pk = (cone.apex + (cone.base - cone.apex) * t) + rim(cone.apex, cone.base, cone.radius * t);
        sc.extend(pc);
        sk.extend(pk);
    }
    for (int k = 0; k < 3; ++k) {
        CHECK(sc.lo[k] >= bc.lo[k] - 1e-12);
        CHECK(sc.hi[k] <= bc.hi[k] + 1e-12);
        CHECK(sc.lo[k] == doctest::Approx(bc.lo[k]).epsilon(1e-3).scale(1.0));
        CHECK(sc.hi[k] == doctest::Approx(bc.hi[k]).epsilon(1e-3).scale(1.0));
        CHECK(sk.lo[k] >= bk.lo[k] - 1e-12);
        CHECK(sk.hi[k] <= bk.hi[k] + 1e-12);
        CHECK(sk.hi[k] == doctest::Approx(bk.hi[k]).epsilon(1e-3).scale(1.0));
    }
}

TEST_CASE("randomly corrupted scene text never crashes: it loads or throws ParseError") {
    const std::string base = read_text(example_scenes() / "spheres.json");
    const std::string alphabet = "0123456789 .-+eE{}[],:\"NaI\nxyz";
    int ok = 0, errors = 0;
    for (int iter = 0; iter < 300; ++iter) {
        std::mt19937 rng(3000u + unsigned(iter));
        std::string t = base;
        for (int k = 0, n = 1 + int(rng() % 3); k < n; ++k) {
            const std::size_t at = rng() % t.size();
            switch (rng() % 4) {
            case 0: t[at] = alphabet[rng() % alphabet.size()]; break;
            case 1: t.erase(at, 1 + rng() % 5); break;
            case 2: t.insert(at, 1, alphabet[rng() % alphabet.size()]); break;
            default: if (rng() % 4 == 0) t.resize(at); break;
            }
        }
        try {
            parse(t);
            ++ok;
        } catch (const ParseError& e) {
            CHECK(e.file() == "s.json");
            CHECK(e.line() >= 1);
            ++errors;
        }
    }
    CHECK(ok > 10);
    CHECK(errors > 10);
}

TEST_CASE("options.environment: a file relative to the scene or the procedural sky, a reflectivity in [0, 1]") {
    TempDir dir;
    quadcast::render::Image sky;
    sky.width = 4;
    sky.height = 2;
    sky.rgba.assign(4 * 2 * 4, 200);
    quadcast::render::write_png(dir.path / "sky.png", sky);
    Scene s = parse(R"({"objects": [], "options": {"environment": {"file": "sky.png", "reflectivity": 0.5}}})", dir.path);
    CHECK(s.options.environment == Options::Environment::file);
    CHECK(s.options.environment_file == (dir.path / "sky.png").lexically_normal());
    REQUIRE(s.options.environment_image != nullptr);  // decoded when loaded
    CHECK(s.options.environment_image->width == 4);
    CHECK(s.options.environment_image->rgba[0] == 200);
    // A PNG signature followed by garbage: an error at the scene location, not at render time.
    dir.write("broken.png", std::string("\x89PNG\r\n\x1a\n", 8) + "not a PNG stream");
    const ParseError broken = error_of(R"({"objects": [], "options": {"environment": {"file": "broken.png"}}})", dir.path);
    CHECK(broken.field() == "/options/environment/file");
    CHECK(broken.message().find("cannot decode the environment image") != std::string::npos);
    CHECK(s.options.reflectivity == 0.5);
    s = parse(R"({"objects": [], "options": {"environment": {"procedural": {"zenith": [0, 0, 1]}}}})");
    CHECK(s.options.environment == Options::Environment::procedural);
    REQUIRE(s.options.sky_zenith.has_value());
    CHECK((*s.options.sky_zenith)[2] == 1.0);
    CHECK_FALSE(s.options.sky_ground.has_value());
    CHECK(s.options.reflectivity == 0.3);
    CHECK(parse(R"({"objects": []})").options.environment == Options::Environment::none);

    ParseError e = error_of(R"({"objects": [], "options": {"environment": {"reflectivity": 0.5}}})");
    CHECK(e.field() == "/options/environment");
    CHECK(e.message().find("either \"file\" or \"procedural\"") != std::string::npos);
    e = error_of(R"({"objects": [], "options": {"environment": {"file": "nope.png"}}})", dir.path);
    CHECK(e.field() == "/options/environment/file");
    CHECK(e.message().find("no such file") != std::string::npos);
    e = error_of(R"({"objects": [], "options": {"environment": {"procedural": {}, "reflectivity": 1.5}}})");
    CHECK(e.field() == "/options/environment/reflectivity");
    e = error_of(R"({"objects": [], "options": {"environment": {"procedural": {"sky": [0, 0, 1]}}}})");
    CHECK(e.field() == "/options/environment/procedural/sky");
}

TEST_CASE("options.outline and options.shadow set the outline and shadow parameters, checked") {
    Scene s = parse(R"({"objects": [], "options": {"outline": {"depth": 0.1, "strength": 0.4}, "shadow": {"map_size": 1024, "pcf_step": 1, "bias": 4}}})");
    REQUIRE(s.options.outline_depth.has_value());
    CHECK(*s.options.outline_depth == 0.1);
    CHECK_FALSE(s.options.outline_crease.has_value());
    CHECK(*s.options.outline_strength == 0.4);
    CHECK(*s.options.shadow_map_size == 1024);
    CHECK(*s.options.pcf_step == 1);
    CHECK(*s.options.shadow_bias == 4.0);
    CHECK_FALSE(parse(R"({"objects": []})").options.shadow_map_size.has_value());
    CHECK(s.options.shadow_map_reuse);
    CHECK_FALSE(parse(R"({"objects": [], "options": {"shadow": {"reuse": false}}})").options.shadow_map_reuse);
    CHECK_FALSE(quadcast::render::build_frame(parse(R"({"objects": [{"sphere": {"center": [0, 0, 0], "radius": 1}}], "options": {"shadow": {"reuse": false}}})"), 8, 8)
                    .options.shadow_map_reuse);
    CHECK(quadcast::render::build_frame(parse(R"({"objects": [{"sphere": {"center": [0, 0, 0], "radius": 1}}]})"), 8, 8).options.shadow_map_reuse);

    ParseError e = error_of(R"({"objects": [], "options": {"outline": {"strength": 2}}})");
    CHECK(e.field() == "/options/outline/strength");
    e = error_of(R"({"objects": [], "options": {"outline": {"width": 2}}})");
    CHECK(e.field() == "/options/outline/width");
    e = error_of(R"({"objects": [], "options": {"shadow": {"map_size": 100.5}}})");
    CHECK(e.field() == "/options/shadow/map_size");
    CHECK(e.message().find("integer in [64, 8192]") != std::string::npos);
    e = error_of(R"({"objects": [], "options": {"shadow": {"bias": -1}}})");
    CHECK(e.field() == "/options/shadow/bias");
    e = error_of(R"({"objects": [], "options": {"shadow": {"reuse": "yes"}}})");
    CHECK(e.field() == "/options/shadow/reuse");
}

TEST_CASE("options.tight_bounds switches the tight screen rectangles and must be a boolean") {
    CHECK(parse(R"({"objects": []})").options.tight_bounds);
    CHECK_FALSE(parse(R"({"objects": [], "options": {"tight_bounds": false}})").options.tight_bounds);
    const ParseError e = error_of(R"({"objects": [], "options": {"tight_bounds": 1}})");
    CHECK(std::string(e.what()) == "s.json:1:45: /options/tight_bounds: expected true or false, got number 1");
}

namespace {

/// `n` spheres, one per line after the line `{"objects": [`; sphere `bad` (if any) has radius -1.
std::string many_spheres(std::size_t n, std::size_t bad, const std::string& tail = "") {
    std::string t = "{\"objects\": [\n";
    for (std::size_t i = 0; i < n; ++i)
        t += std::string(i ? ",\n" : "") + "{\"sphere\": {\"center\": [" + std::to_string(i % 97) + ", 0, 0], \"radius\": " + (i == bad ? "-1" : "0.5") + "}}";
    return t + "]" + tail + "}\n";
}

}  // namespace

TEST_CASE("a scene of many objects names the line and column of an error late in the file, and keeps them in file order") {
    const std::size_t n = 60000, bad = n - 3;
    // Sphere i is on line i + 2; its radius value starts after `{"sphere": {"center": [X, 0, 0], "radius": `.
    const std::string x = std::to_string(bad % 97);
    const int column = static_cast<int>(std::string("{\"sphere\": {\"center\": [" + x + ", 0, 0], \"radius\": ").size()) + 1;
    {
        const ParseError e = error_of(many_spheres(n, bad));
        CHECK(std::string(e.what()) == "s.json:" + std::to_string(bad + 2) + ":" + std::to_string(column) + ": /objects/" +
                                           std::to_string(bad) + "/sphere/radius: expected a number > 0, got -1");
    }
    {
        // Errors before and after the objects in the text (found after them) sort around it.
        std::string text = many_spheres(n, bad, ", \"options\": {\"culling\": 3}");
        text.insert(1, "\"camera\": {\"eye\": [0, 0, 0], \"target\": [0, 0, 0]},");
        try {
            parse(text);
            FAIL("no error");
        } catch (const ParseErrors& e) {
            REQUIRE(e.errors().size() == 3);
            CHECK(e.errors()[0].field() == "/camera/target");
            CHECK(e.errors()[1].field() == "/objects/" + std::to_string(bad) + "/sphere/radius");
            CHECK(e.errors()[1].line() == static_cast<int>(bad) + 2);
            CHECK(e.errors()[2].field() == "/options/culling");
            CHECK(e.errors()[2].line() == static_cast<int>(n) + 1);
        }
    }
    {
        // All on one line: the column counts from the start of the file.
        std::string text = many_spheres(n, bad);
        std::replace(text.begin(), text.end(), '\n', ' ');
        const std::size_t at = text.find("-1");
        const ParseError e = error_of(text);
        CHECK(e.line() == 1);
        CHECK(e.column() == static_cast<int>(at) + 1);
    }
    {
        // No error: every sphere, each object's origin at its kind value.
        const Scene s = parse(many_spheres(n, n));
        REQUIRE(s.spheres.size() == n);
        REQUIRE(s.origins.size() == n);
        CHECK(s.spheres[bad].center[0] == double(bad % 97));
        const Location l = s.location(s.origins[bad]);
        CHECK(format_location(l) == "s.json:" + std::to_string(bad + 2) + ":12: /objects/" + std::to_string(bad) + "/sphere: ");
    }
}

TEST_CASE("a syntax error or a duplicate key after bad objects is the only error, and nothing is loaded") {
    const std::size_t n = 2000;
    std::string text = many_spheres(n, 10);
    text.insert(text.rfind(']'), ", {\"sphere\": {\"center\": [0, 0, 0], \"radius\": 1,}}");
    const ParseError syntax = error_of(text);
    CHECK(syntax.field().empty());
    CHECK(syntax.line() == static_cast<int>(n) + 1);
    CHECK(std::string(syntax.what()).find("/objects/10") == std::string::npos);

    text = many_spheres(n, 10);
    text.insert(text.rfind(']'), ", {\"sphere\": {\"center\": [0, 0, 0], \"center\": [1, 0, 0], \"radius\": 1}}");
    const ParseError dup = error_of(text);
    CHECK(dup.field() == "/objects/" + std::to_string(n) + "/sphere/center");
    CHECK(dup.message() == "duplicate key");
    CHECK(dup.line() == static_cast<int>(n) + 1);

    // A top-level key written twice, the second time after the objects.
    const ParseError top = error_of(many_spheres(5, 1, ", \"objects\": []"));
    CHECK(top.field() == "/objects");
    CHECK(top.message() == "duplicate key");
}

TEST_CASE("JsonDocument hands the elements of the streamed array over one by one and keeps none") {
    const std::string text = "{\"a\": {\"objects\": [1, 2]},\n \"objects\": [{\"x\": [1, 2]}, 7, [true, {\"y/z\": null}]],\n \"b\": 3}";
    std::vector<std::string> seen;
    const JsonDocument doc(text, "d.json", "objects", [&](const JsonNode& e) {
        // The element's tree is its own: positions and pointers as in the whole document.
        seen.push_back(e.pointer() + " " + e.json().dump() + " @" + std::to_string(e.position().line) + ":" + std::to_string(e.position().column));
        if (e.json().is_object()) {
            const JsonNode x1 = e.at("x").array(2)[1];
            CHECK(format_location(x1.location()) == "d.json:2:24: /objects/0/x/1: ");
            CHECK(e.at("x").position(true).column == 15);  // (its key)
        }
        if (e.json().is_array()) {
            const JsonNode y = e.array(2)[1].at("y/z");
            CHECK(y.pointer() == "/objects/2/1/y~1z");
            CHECK(y.position().column == 47);
        }
    });
    REQUIRE(seen.size() == 3);
    CHECK(seen[0] == "/objects/0 {\"x\":[1,2]} @2:14");
    CHECK(seen[1] == "/objects/1 7 @2:29");
    CHECK(seen[2] == "/objects/2 [true,{\"y/z\":null}] @2:32");
    const JsonNode root = doc.root();
    CHECK(root.at("objects").json() == Json::array());  // streamed, not kept
    CHECK(root.at("objects").position().column == 13);
    CHECK(root.at("a").at("objects").json().size() == 2);  // not at the top: kept
    CHECK(root.at("b").position().line == 3);

    // Not an array: kept in the document, nothing streamed.
    std::size_t calls = 0;
    const JsonDocument other("{\"objects\": {\"sphere\": 1}}", "d.json", "objects", [&](const JsonNode&) { ++calls; });
    CHECK(calls == 0);
    CHECK(other.root().at("objects").json().is_object());
}

TEST_CASE("options.occlusion_phases takes an integer from 1 to 8") {
    CHECK(parse(R"({"objects": []})").options.occlusion_phases == 3);
    CHECK(parse(R"({"objects": [], "options": {"occlusion_phases": 1}})").options.occlusion_phases == 1);
    CHECK(parse(R"({"objects": [], "options": {"occlusion_phases": 8}})").options.occlusion_phases == 8);
    for (const char* bad : {R"({"objects": [], "options": {"occlusion_phases": 0}})", R"({"objects": [], "options": {"occlusion_phases": 9}})",
                            R"({"objects": [], "options": {"occlusion_phases": 2.5}})", R"({"objects": [], "options": {"occlusion_phases": "3"}})"}) {
        const ParseError e = error_of(bad);
        CAPTURE(bad);
        CHECK(std::string(e.what()).find("/options/occlusion_phases") != std::string::npos);
    }
}
