// tests/slim/points.cpp -- the oriented point readers: .xyz/.pwn, .ply (ASCII, binary), .off sampled
#include <doctest/doctest.h>

#include <bit>
#include <cmath>
#include <cstring>
#include <sstream>

#include "quadcast/slim/points.hpp"
#include "scene/helpers.hpp"

using namespace quadcast::slim;
using quadcast::scene::ParseError;
using scene_test::parse_error_of;
using scene_test::TempDir;

namespace {

/// `n` points "i 0 0 0 0 2" as xyz lines.
std::string xyz_lines(int n) {
    std::string s;
    for (int i = 0; i < n; ++i) s += std::to_string(i) + " 0 0 0 0 2\n";
    return s;
}

OrientedPoints xyz(const std::string& text) {
    std::istringstream in(text);
    return parse_xyz(in, "mem.xyz");
}

OrientedPoints ply(const std::string& bytes) {
    std::istringstream in(bytes, std::ios::binary);
    return parse_ply(in, "mem.ply");
}

/// A binary PLY header for `n` vertices with double x y z nx ny nz and a uchar before them.
std::string binary_header(int n, const char* order = "binary_little_endian") {
    return std::string("ply\nformat ") + order + " 1.0\ncomment made by the test\nelement vertex " + std::to_string(n) +
           "\nproperty uchar flag\nproperty double x\nproperty double y\nproperty double z\n"
           "property double nx\nproperty double ny\nproperty double nz\nelement face 0\n"
           "property list uchar int vertex_indices\nend_header\n";
}

template <class V>
void put(std::string& out, V v, bool big) {
    unsigned char b[sizeof(V)];
    std::memcpy(b, &v, sizeof(V));
    const bool swap = big == (std::endian::native == std::endian::little);
    for (std::size_t i = 0; i < sizeof(V); ++i) out.push_back(char(b[swap ? sizeof(V) - 1 - i : i]));
}

std::string binary_records(int n, bool big) {
    std::string s;
    for (int i = 0; i < n; ++i) {
        put<unsigned char>(s, 7, big);
        for (double v : {double(i), 1.0, 2.0, 0.0, 3.0, 0.0}) put(s, v, big);
    }
    return s;
}

}  // namespace

TEST_CASE("xyz lines read as points with unit normals") {
    const OrientedPoints p = xyz("# a comment\n\n" + xyz_lines(12));
    REQUIRE(p.size() == 12);
    CHECK(p.positions[3][0] == 3.0);
    CHECK(p.normals[3][2] == 1.0);
    CHECK(p.normals[3][0] == 0.0);
}

TEST_CASE("an xyz file without normals names the line and says normals are missing") {
    const ParseError e = parse_error_of([] { xyz("0 0 0 0 0 1\n1 2 3\n"); });
    CHECK(e.file() == "mem.xyz");
    CHECK(e.line() == 2);
    CHECK(std::string(e.what()).find("missing normals") != std::string::npos);
}

TEST_CASE("NaN and infinite values in xyz files are errors naming the field") {
    ParseError e = parse_error_of([] { xyz(xyz_lines(3) + "0 nan 0 0 0 1\n"); });
    CHECK(e.line() == 4);
    CHECK(e.field() == "y");
    CHECK(e.message().find("not finite") != std::string::npos);
    e = parse_error_of([] { xyz(xyz_lines(3) + "0 0 0 0 0 -inf\n"); });
    CHECK(e.field() == "nz");
    e = parse_error_of([] { xyz("0 0 0 0 0 x1\n"); });
    CHECK(e.message().find("not a number") != std::string::npos);
}

TEST_CASE("a zero normal is an error on its line") {
    const ParseError e = parse_error_of([] { xyz(xyz_lines(2) + "0 0 0 0 0 0\n"); });
    CHECK(e.line() == 3);
    CHECK(e.message().find("zero length") != std::string::npos);
}

TEST_CASE("fewer points than a quadric fit needs is an error naming the file") {
    const ParseError e = parse_error_of([] { xyz(xyz_lines(9)); });
    CHECK(e.file() == "mem.xyz");
    CHECK(e.message().find("9 points; a quadric fit needs at least 10") != std::string::npos);
    CHECK(xyz(xyz_lines(10)).size() == 10);
}

TEST_CASE("ASCII PLY: other properties and elements are skipped") {
    std::string s = "ply\r\nformat ascii 1.0\r\nelement edge 1\r\nproperty list uchar int v\r\n"
                    "element vertex 10\r\nproperty float x\r\nproperty float y\r\nproperty float z\r\n"
                    "property uchar red\r\nproperty float nx\r\nproperty float ny\r\nproperty float nz\r\n"
                    "end_header\r\n3 0 1 2\r\n";
    for (int i = 0; i < 10; ++i) s += std::to_string(i) + " 1 2 255 0 0 -4\r\n";
    const OrientedPoints p = ply(s);
    REQUIRE(p.size() == 10);
    CHECK(p.positions[9][0] == 9.0);
    CHECK(p.positions[9][2] == 2.0);
    CHECK(p.normals[9][2] == -1.0);
}

TEST_CASE("binary PLY in both byte orders reads the same points") {
    for (bool big : {false, true}) {
        CAPTURE(big);
        const OrientedPoints p = ply(binary_header(11, big ? "binary_big_endian" : "binary_little_endian") + binary_records(11, big));
        REQUIRE(p.size() == 11);
        CHECK(p.positions[10][0] == 10.0);
        CHECK(p.positions[10][1] == 1.0);
        CHECK(p.normals[10][1] == 1.0);
    }
}

TEST_CASE("truncated binary PLY names the record and the byte offset where it ends") {
    const std::string header = binary_header(11);
    std::string data = binary_records(11, false);
    data.resize(data.size() - 5);  // inside vertex 10's nz
    const ParseError e = parse_error_of([&] { ply(header + data); });
    CHECK(e.line() == 0);
    const std::size_t nz_byte = header.size() + 10 * 49 + 1 + 5 * 8;
    CHECK(e.field() == "vertex 10 nz (byte " + std::to_string(nz_byte) + ")");
    CHECK(e.message().find("truncated") != std::string::npos);
}

TEST_CASE("malformed PLY headers are errors naming the line") {
    struct Case { std::string text; int line; std::string needle; };
    const Case cases[] = {
        {"plx\nformat ascii 1.0\n", 1, "not a PLY file"},
        {"ply\nformat ebcdic 1.0\nend_header\n", 2, "unknown format"},
        {"ply\nformat ascii 2.0\nend_header\n", 2, "unsupported version"},
        {"ply\nelement vertex 3\n", 2, "format"},
        {"ply\nformat ascii 1.0\nproperty float x\nend_header\n", 3, "before any 'element'"},
        {"ply\nformat ascii 1.0\nelement vertex 3\nproperty quad x\nend_header\n", 4, "unknown type"},
        {"ply\nformat ascii 1.0\nelement vertex -3\nend_header\n", 3, "not a non-negative integer"},
        {"ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n", 4, "before 'end_header'"},
        {"ply\nformat ascii 1.0\nelement face 0\nend_header\n", 4, "no 'vertex' element"},
        {"ply\nformat ascii 1.0\nbanana\nend_header\n", 3, "unknown header keyword"},
        {"ply\nformat ascii 1.0\nelement vertex 10\nproperty float x\nproperty float y\nproperty float z\nend_header\n", 3,
         "missing normals"},
    };
    for (const Case& c : cases) {
        CAPTURE(c.text);
        const ParseError e = parse_error_of([&] { ply(c.text); });
        CHECK(e.line() == c.line);
        CHECK(std::string(e.what()).find(c.needle) != std::string::npos);
    }
}

TEST_CASE("ASCII PLY records with the wrong number of values or NaN are errors on their line") {
    const std::string h = "ply\nformat ascii 1.0\nelement vertex 10\nproperty float x\nproperty float y\nproperty float z\n"
                          "property float nx\nproperty float ny\nproperty float nz\nend_header\n";
    ParseError e = parse_error_of([&] { ply(h + "0 0 0 0 0 1\n0 0 0 0 1\n"); });
    CHECK(e.line() == 12);
    CHECK(e.field() == "vertex 1 nz");
    e = parse_error_of([&] { ply(h + "0 0 0 0 0 1 5\n"); });
    CHECK(e.message().find("7 values; the header declares 6") != std::string::npos);
    e = parse_error_of([&] { ply(h + "0 0 0 0 0 1\n0 NaN 0 0 0 1\n"); });
    CHECK(e.line() == 12);
    CHECK(e.field() == "vertex 1 y");
    e = parse_error_of([&] { ply(h + "0 0 0 0 0 1\n"); });
    CHECK(e.message().find("ends after 1 of 10 vertex records") != std::string::npos);
}

TEST_CASE("NaN in binary PLY names the record's field and byte offset") {
    std::string data = binary_records(11, false);
    const double nan = std::nan("");
    std::memcpy(&data[3 * 49 + 1 + 8], &nan, 8);  // vertex 3 y
    const ParseError e = parse_error_of([&] { ply(binary_header(11) + data); });
    CHECK(e.field().rfind("vertex 3 y (byte ", 0) == 0);
    CHECK(e.message().find("not finite") != std::string::npos);
}

TEST_CASE("an OFF mesh is sampled by area with its faces' outward normals, the same for the same seed") {
    TempDir dir;
    // A unit cube, faces counter-clockwise seen from outside.
    const auto path = dir.write("cube.off",
                                "OFF\n8 6 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n0 0 1\n1 0 1\n1 1 1\n0 1 1\n"
                                "4 0 3 2 1\n4 4 5 6 7\n4 0 1 5 4\n4 2 3 7 6\n4 1 2 6 5\n4 0 4 7 3\n");
    ReadOptions o;
    o.mesh_samples = 600;
    const OrientedPoints a = read_points(path, o), b = read_points(path, o);
    REQUIRE(a.size() == 600);
    int per_face[6] = {};
    for (std::size_t i = 0; i < a.size(); ++i) {
        CHECK(a.positions[i][0] == b.positions[i][0]);
        // Outward: the normal points away from the centre.
        const auto c = a.positions[i] - quadcast::vec3(0.5, 0.5, 0.5);
        CHECK(dot(c, a.normals[i]) == doctest::Approx(0.5));
        for (int k = 0; k < 3; ++k)
            if (std::fabs(a.normals[i][k]) == 1.0) ++per_face[2 * k + (a.normals[i][k] > 0)];
    }
    for (int f : per_face) CHECK(f > 60);  // 100 expected per face
}

TEST_CASE("read_points names unknown extensions and unopenable files") {
    CHECK(parse_error_of([] { read_points("cloud.las"); }).message().find("unknown point cloud format") != std::string::npos);
    CHECK(parse_error_of([] { read_points("/no/such/cloud.xyz"); }).message().find("cannot open") != std::string::npos);
}
