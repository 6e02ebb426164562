// tests/scene/off.cpp -- the OFF reader and its conversion to bilinear quads
#include <doctest/doctest.h>

#include <cmath>
#include <random>
#include <sstream>

#include "helpers.hpp"
#include "quadcast/scene/off.hpp"

using namespace quadcast::scene;
using namespace scene_test;

namespace {

OffMesh parse(const std::string& text) {
    std::istringstream in(text);
    return parse_off(in, "mem.off");
}

std::string what_of(const std::string& text) { return parse_error_of([&] { parse(text); }).what(); }

const char* const kSquare = "OFF\n4 1 0\n0 0 0\n1 0 0\n1 1 1\n0 1 0\n4 0 1 2 3\n";

}  // namespace

TEST_CASE("the twisted cube example reads as six quads in face order") {
    OffMesh m = read_off(example_scenes() / "twisted_cube.off");
    CHECK(m.warnings.empty());
    REQUIRE(m.vertices.size() == 8);
    REQUIRE(m.faces.size() == 6);
    CHECK(m.face_lines[0] == 15);
    Warnings w;
    const std::vector<BilinearQuad> q = off_to_quads(m, {}, Material{}, w);
    REQUIRE(q.size() == 6);
    CHECK(w.empty());
    // Face 2 is "4 0 1 5 4": corners in that order.
    CHECK(q[2].p[0][0] == m.vertices[0][0]);
    CHECK(q[2].p[1][0] == m.vertices[1][0]);
    CHECK(q[2].p[2][1] == m.vertices[5][1]);
    CHECK(q[2].p[3][1] == m.vertices[4][1]);
}

TEST_CASE("the Moebius band example has 64 quads and no triangles") {
    OffMesh m = read_off(example_scenes() / "moebius.off");
    Warnings w;
    CHECK(off_to_quads(m, {TrianglePolicy::error}, Material{}, w).size() == 64);
    CHECK(w.empty());
}

TEST_CASE("comments, counts on the header line and face colours are read") {
    const std::string text = "OFF 4 3 0 # counts beside the keyword\n"
                             "# a comment line\n\n"
                             "0 0 0\n1 0 0 # trailing comment\n1 1 0.5\n0 1 0\n"
                             "4 0 1 2 3 255 0 0\n"
                             "4 0 1 2 3 0.0 0.5 1.0 1.0\n"
                             "4 3 2 1 0 7\n";
    OffMesh m = parse(text);
    REQUIRE(m.faces.size() == 3);
    REQUIRE(m.face_colors[0]);
    CHECK((*m.face_colors[0])[0] == 1.0);
    CHECK((*m.face_colors[1])[1] == 0.5);
    CHECK_FALSE(m.face_colors[2]);
    REQUIRE(m.warnings.size() == 1);
    CHECK(m.warnings[0].to_string() == "mem.off:10: warning: face 2 colour: colour-map index ignored");
    Warnings w;
    Material mat;
    const auto q = off_to_quads(m, {}, mat, w);
    CHECK(q[0].material.color[0] == 1.0);
    CHECK(q[2].material.color[0] == mat.color[0]);
    // The keyword is optional (Geomview).
    CHECK(parse("4 1 0\n0 0 0\n1 0 0\n1 1 1\n0 1 0\n4 0 1 2 3\n").faces.size() == 1);
}

TEST_CASE("triangles become degenerate quads (a, b, c, c), or errors when asked") {
    const std::string text = "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
    OffMesh m = parse(text);
    Warnings w;
    const auto q = off_to_quads(m, {}, Material{}, w);
    REQUIRE(q.size() == 1);
    CHECK(q[0].p[2][1] == 1.0);
    CHECK(q[0].p[3][0] == q[0].p[2][0]);
    CHECK(q[0].p[3][1] == q[0].p[2][1]);
    CHECK(q[0].p[3][2] == q[0].p[2][2]);
    const ParseError e = parse_error_of([&] { off_to_quads(m, {TrianglePolicy::error}, Material{}, w); });
    CHECK(std::string(e.what()) == "mem.off:6: face 0: is a triangle; this mesh is read with \"triangles\": \"error\" (only quads)");
}

TEST_CASE("polygons with more than four vertices are errors; zero-area faces are skipped with a warning") {
    OffMesh m = parse("OFF\n5 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n2 2 0\n5 0 1 2 3 4\n4 0 1 1 0\n");
    Warnings w;
    ParseError e = parse_error_of([&] { off_to_quads(m, {}, Material{}, w); });
    CHECK(std::string(e.what()) == "mem.off:8: face 0: has 5 vertices; only quads (and triangles) can be bilinear patches");
    m = parse("OFF\n4 2 0\n0 0 0\n1 0 0\n1 1 0\n2 2 0\n4 0 1 2 3\n4 0 2 3 0\n");
    const auto q = off_to_quads(m, {}, Material{}, w);
    CHECK(q.size() == 1);
    REQUIRE(w.size() == 1);
    CHECK(w[0].to_string() == "mem.off:8: warning: face 1: zero area (corners collinear or coincident); skipped");
}

TEST_CASE("malformed and truncated OFF files are errors naming line and field") {
    CHECK(what_of("") == "mem.off: header: unexpected end of file (truncated?)");
    CHECK(what_of("COFF\n") == "mem.off:1: header: 'COFF' files are not supported (plain OFF only)");
    CHECK(what_of("OFF BINARY\n") == "mem.off:1: header: binary OFF is not supported");
    CHECK(what_of("ply\nformat ascii 1.0\n") == "mem.off:1: header: expected 'OFF', found 'ply'");
    CHECK(what_of("OFF\n4\n") == "mem.off:2: counts: expected 'vertex_count face_count [edge_count]', found 1 values");
    CHECK(what_of("OFF\n4 x 0\n") == "mem.off:2: face_count: 'x' is not an integer");
    CHECK(what_of("OFF\n-4 1 0\n") == "mem.off:2: vertex_count: is negative");
    CHECK(what_of("OFF\n4 1 0\n0 0 0\n1 0\n") == "mem.off:4: vertex 1: expected 3 coordinates, found 2 values (COFF/NOFF data is not supported)");
    CHECK(what_of("OFF\n4 1 0\n0 0 0\n1 0x 0\n") == "mem.off:4: vertex 1 y: '0x' is not a number");
    CHECK(what_of("OFF\n4 1 0\n0 0 0\n1 0 nan\n") == "mem.off:4: vertex 1 z: 'nan' is not finite");
    CHECK(what_of("OFF\n4 1 0\n0 0 0\n1 0 0\n") == "mem.off:4: vertex 2: file ends after 2 of 4 vertices (truncated?)");
    CHECK(what_of("OFF\n4 2 0\n0 0 0\n1 0 0\n1 1 1\n0 1 0\n4 0 1 2 3\n") ==
          "mem.off:7: face 1: file ends after 1 of 2 faces (truncated?)");
    CHECK(what_of("OFF\n4 1 0\n0 0 0\n1 0 0\n1 1 1\n0 1 0\n4 0 1 2\n") ==
          "mem.off:7: face 0: declares 4 vertices but lists 3 (truncated line?)");
    CHECK(what_of("OFF\n4 1 0\n0 0 0\n1 0 0\n1 1 1\n0 1 0\n4 0 1 9 3\n") ==
          "mem.off:7: face 0 vertex 2: index 9 is out of range 0..3");
    CHECK(what_of("OFF\n4 1 0\n0 0 0\n1 0 0\n1 1 1\n0 1 0\n4 0 1 -1 3\n") ==
          "mem.off:7: face 0 vertex 2: index -1 is out of range 0..3");
    CHECK(what_of("OFF\n4 1 0\n0 0 0\n1 0 0\n1 1 1\n0 1 0\n2 0 1\n") ==
          "mem.off:7: face 0 vertex_count: a face needs at least 3 vertices, found 2");
    CHECK(what_of("OFF\n4 1 0\n0 0 0\n1 0 0\n1 1 1\n0 1 0\n4 0 1 2 3 0 0\n") ==
          "mem.off:7: face 0: 2 values after the vertex indices; expected none, a colour-map index, or an RGB(A) colour");
    CHECK(what_of("OFF\n4 1 0\n0 0 0\n1 0 0\n1 1 1\n0 1 0\n4 0 1 2 3 300 0 0\n") ==
          "mem.off:7: face 0 colour r: '300' is outside 0..255");
    OffMesh extra = parse(std::string(kSquare) + "junk\n");
    REQUIRE(extra.warnings.size() == 1);
    CHECK(extra.warnings[0].where.line == 8);
    CHECK(parse_error_of([] { read_off("/nonexistent/m.off"); }).file() == "/nonexistent/m.off");
}

TEST_CASE("randomly corrupted OFF text never crashes: it reads or throws ParseError") {
    const std::string base = read_text(example_scenes() / "twisted_cube.off");
    const std::string alphabet = "0123456789 .-+eE\n#OFFx";
    int ok = 0, errors = 0;
    for (int iter = 0; iter < 400; ++iter) {
        std::mt19937 rng(2000u + unsigned(iter));
        std::string t = base;
        for (int k = 0, n = 1 + int(rng() % 4); k < n; ++k) {
            const std::size_t at = rng() % t.size();
            switch (rng() % 3) {
            case 0: t[at] = alphabet[rng() % alphabet.size()]; break;
            case 1: t.erase(at, 1 + rng() % 10); break;
            default: t.resize(at); break;
            }
            if (t.empty()) t.push_back('x');
        }
        try {
            OffMesh m = parse(t);
            Warnings w;
            for (const BilinearQuad& q : off_to_quads(m, {}, Material{}, w))
                for (const Vec3d& p : q.p) REQUIRE(std::isfinite(p[0] + p[1] + p[2]));
            ++ok;
        } catch (const ParseError& e) {
            CHECK(e.file() == "mem.off");
            ++errors;
        }
    }
    CHECK(ok > 10);
    CHECK(errors > 10);
}
