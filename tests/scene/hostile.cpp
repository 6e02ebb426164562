// tests/scene/hostile.cpp -- hostile scene, PDB and OFF input: limits, located errors, error order
#include <doctest/doctest.h>

#include <chrono>
#include <sstream>

#include "helpers.hpp"
#include "quadcast/scene/off.hpp"
#include "quadcast/scene/pdb.hpp"
#include "quadcast/scene/scene_json.hpp"

using namespace quadcast::scene;
using namespace scene_test;

namespace {

Scene parse(const std::string& text, const fs::path& base = ".") { return parse_scene(text, "s.json", base); }

ParseError error_of(const std::string& text, const fs::path& base = ".") {
    return parse_error_of([&] { parse(text, base); });
}

std::string with_object(const std::string& object) { return "{\"objects\": [" + object + "]}"; }

/// A PDB ATOM record (80 columns) for a carbon at (x, y, z).
std::string atom(int serial, double x, double y, double z) {
    char buf[96];
    std::snprintf(buf, sizeof buf, "ATOM  %5d  CA  ALA A   1    %8.3f%8.3f%8.3f  1.00  0.00           C  \n", serial, x, y, z);
    return buf;
}

}  // namespace

TEST_CASE("a scene nested deeper than the limit is a located error, not a stack overflow") {
    const std::string deep = "{\"objects\": [" + std::string(8000, '[') + std::string(8000, ']') + "]}";
    const ParseError e = error_of(deep);
    CHECK(e.line() == 1);
    CHECK(e.column() == 12 + max_json_depth);  // the bracket that opens level max_json_depth + 1
    CHECK(e.message().find("nested deeper than 256") != std::string::npos);
    // At the limit the text parses (and then fails for what it is, an array in "objects").
    const std::string ok = "{\"objects\": [" + std::string(max_json_depth - 2, '[') + std::string(max_json_depth - 2, ']') + "]}";
    CHECK(error_of(ok).message().find("expected an object") != std::string::npos);
    // Brackets inside strings do not count.
    CHECK_NOTHROW(parse("{\"objects\": [], \"comment\": \"" + std::string(1000, '[') + "\"}"));
}

TEST_CASE("every error of a scene is reported, in file order") {
    const std::string text = "{\"camera\": {\"eye\": [0, 0, 5], \"target\": [0, 0, 5]},\n"
                             " \"objects\": [\n"
                             "  {\"sphere\": {\"center\": [0, 0, 0], \"radius\": -1}},\n"
                             "  {\"sphere\": {\"center\": [0, 0, 0], \"radius\": 1}},\n"
                             "  {\"cone\": {\"apex\": [0, 0, 0], \"base\": [0, 0, 0], \"radius\": 1}}\n"
                             " ],\n"
                             " \"lights\": [{\"direction\": [0, 0, 0]}]}";
    try {
        parse(text);
        FAIL("no error");
    } catch (const ParseErrors& e) {
        REQUIRE(e.errors().size() == 4);
        CHECK(e.errors()[0].field() == "/camera/target");  // line 1, though found after the objects
        CHECK(e.errors()[1].field() == "/objects/0/sphere/radius");
        CHECK(e.errors()[2].field() == "/objects/2/cone/base");
        CHECK(e.errors()[3].field() == "/lights/0/direction");
        CHECK(e.line() == 1);  // as a ParseError: the first in the file
        const std::string w = e.what();
        CHECK(w.find("s.json:1:") == 0);
        CHECK(std::count(w.begin(), w.end(), '\n') == 3);
    }
}

TEST_CASE("more than 20 errors: the first 20 and a count") {
    std::string objs;
    for (int i = 0; i < 25; ++i) objs += std::string(i ? "," : "") + "{\"sphere\": {\"center\": [0, 0, 0], \"radius\": 0}}";
    try {
        parse(with_object(objs));
        FAIL("no error");
    } catch (const ParseErrors& e) {
        CHECK(e.errors().size() == 25);
        CHECK(std::string(e.what()).find("... and 5 more errors") != std::string::npos);
    }
}

TEST_CASE("with up omitted, a vertical view says the default up is parallel and must be given") {
    const ParseError e = error_of(R"({"objects": [], "camera": {"eye": [0, 5, 0], "target": [0, 0, 0]}})");
    CHECK(e.field() == "/camera");
    CHECK(e.message() == "the default up [0, 1, 0] is parallel to the view direction (target - eye); give \"up\"");
}

TEST_CASE("overflow is diagnosed as overflow, not as a zero quantity") {
    ParseError e = error_of(R"({"objects": [], "camera": {"eye": [1e300, 1e300, 0], "target": [-1e300, 0, 0]}})");
    CHECK(e.field() == "/camera/eye");
    CHECK(e.message().find("overflows") != std::string::npos);
    e = error_of(with_object(R"({"quadric": {"coefficients": [-1, 0, 0, 0, 0, 0, 0, 1, 1, 1],
        "bound": {"tetrahedron": [[0, 0, 0], [1e200, 0, 0], [0, 1e200, 0], [0, 0, 1e200]]}}})"));
    CHECK(e.field() == "/objects/0/quadric/bound/tetrahedron");
    CHECK(e.message().find("overflows") != std::string::npos);
}

TEST_CASE("ellipsoid axes too small for the renderer's matrix are a located loader error") {
    ParseError e = error_of(with_object(R"({"ellipsoid": {"center": [0, 0, 0], "axes": [[1e-200, 0, 0], [0, 1e-200, 0], [0, 0, 1e-200]]}})"));
    CHECK(e.field() == "/objects/0/ellipsoid/axes");
    e = error_of(with_object(R"({"ellipsoid": {"center": [0, 0, 0], "radii": [1, 1e-200, 1]}})"));
    CHECK(e.field() == "/objects/0/ellipsoid/radii");
    CHECK_NOTHROW(parse(with_object(R"({"ellipsoid": {"center": [0, 0, 0], "radii": [1e-3, 1, 1e3]}})")));
}

TEST_CASE("an environment file that is not a PNG is an error at /options/environment/file") {
    TempDir d;
    d.write("sky.png", "not a png at all");
    const ParseError e = error_of(R"({"objects": [], "options": {"environment": {"file": "sky.png"}}})", d.path);
    CHECK(e.field() == "/options/environment/file");
    CHECK(e.message().find("not a PNG") != std::string::npos);
}

TEST_CASE("quoted tokens in messages are cut to a bounded length") {
    const std::string big(1 << 20, 'x');
    ParseError e = error_of(with_object("{\"sphere\": {\"center\": [0, 0, 0], \"radius\": 1, \"" + big + "\": 1}}"));
    CHECK(std::string(e.what()).size() < 600);
    std::istringstream off("OFF\n1 0 0\n" + big + " 0 0\n");
    e = parse_error_of([&] { parse_off(off, "m.off"); });
    CHECK(std::string(e.what()).size() < 200);
    CHECK(e.message().find("...' (1048576 bytes)") != std::string::npos);
}

TEST_CASE("OFF counts larger than the file can hold are found where the file ends, without allocating for them") {
    std::istringstream off("OFF\n100000000 100000000 0\n0 0 0\n");
    const ParseError e = parse_error_of([&] { parse_off(off, "m.off"); });
    CHECK(e.line() == 3);
    CHECK(e.message() == "file ends after 1 of 100000000 vertices (truncated?)");
    std::istringstream ok("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
    CHECK(parse_off(ok, "m.off").faces.size() == 1);
}

TEST_CASE("atoms packed denser than any molecule are an error naming the atom's line, found fast") {
    const auto t0 = std::chrono::steady_clock::now();
    {
        // 5,000 atoms inside one cubic Angstrom: nearly every pair would be a bond.
        std::string text;
        std::mt19937 rng(5);
        std::uniform_real_distribution<double> u(0.0, 1.0);
        for (int i = 1; i <= 5000; ++i) text += atom(i, u(rng), u(rng), u(rng));
        std::istringstream in(text);
        Molecule m = parse_pdb(in, "dense.pdb");
        const ParseError e = parse_error_of([&] { compute_bonds(m); });
        CHECK(e.file() == "dense.pdb");
        CHECK(e.line() >= 1);
        CHECK(e.message().find("at most 16 bonds per atom") != std::string::npos);
    }
    {
        // 40,000 atoms at one point: no bond (closer than 0.4 A), but a quadratic search.
        std::string text;
        for (int i = 1; i <= 40000; ++i) text += atom(i % 99999, 1.0, 2.0, 3.0);
        std::istringstream in(text);
        Molecule m = parse_pdb(in, "point.pdb");
        const ParseError e = parse_error_of([&] { compute_bonds(m); });
        CHECK(e.file() == "point.pdb");
    }
    CHECK(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() < 10.0);
}

TEST_CASE("a real protein stays within the bond limits") {
    require_pymol_data();
    Molecule m = read_pdb(pymol_demo() / "1tii.pdb");
    CHECK_NOTHROW(compute_bonds(m));
    CHECK(m.bonds.size() > m.atoms.size() / 2);
}
