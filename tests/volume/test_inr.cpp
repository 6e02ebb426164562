// tests/volume/test_inr.cpp -- INR reading: round trips in every type and byte order, gzip, and clear errors on bad files
#include <doctest/doctest.h>

#include <bit>
#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>
#include <limits>
#include <random>
#include <string>

#include "quadcast/volume/formats.hpp"
#include "helpers.hpp"

using namespace quadcast::volume;

namespace {

std::vector<std::uint8_t> bytes_of(const std::string& s) { return {s.begin(), s.end()}; }

/// A header (padded to 256 bytes) followed by `data`.
std::vector<std::uint8_t> inr_file(const std::string& fields, const std::vector<std::uint8_t>& data, bool pad = true) {
    std::string h = "#INRIMAGE-4#{\n" + fields;
    if (pad) h.append(256 - 4 - h.size(), '\n');
    h += "##}\n";
    std::vector<std::uint8_t> b = bytes_of(h);
    b.insert(b.end(), data.begin(), data.end());
    return b;
}

const std::string float_2x2x2 = "XDIM=2\nYDIM=2\nZDIM=2\nVDIM=1\nTYPE=float\nPIXSIZE=32 bits\nCPU=decm\n";

std::vector<std::uint8_t> float_data(std::initializer_list<float> v) {
    std::vector<std::uint8_t> b;
    for (float x : v) {
        std::uint8_t w[4];
        std::memcpy(w, &x, 4);
        b.insert(b.end(), w, w + 4);
    }
    return b;
}

/// The exception a parse throws (fails the test when none).
VolumeError parse_error(const std::vector<std::uint8_t>& b, const ReadOptions& o = {}) {
    try {
        (void)parse_inr(b, "bad.inr", o);
    } catch (const VolumeError& e) {
        return e;
    }
    FAIL("parse_inr accepted a bad file");
    return VolumeError("", -1, 0, "", "");
}

}  // namespace

TEST_CASE("INR files round-trip in every sample type and byte order") {
    const SampleType types[] = {SampleType::u8, SampleType::i8, SampleType::u16, SampleType::i16,
                                SampleType::u32, SampleType::i32, SampleType::f32, SampleType::f64};
    for (SampleType t : types) {
        for (Endian e : {Endian::little, Endian::big}) {
            CAPTURE(sample_type_name(t));
            CAPTURE(static_cast<int>(e));
            const VolumeData v = vtest::small_volume(5, 4, 3, 7, t != SampleType::f32 && t != SampleType::f64);
            const auto b = inr_bytes(v, t, e);
            CHECK((b.size() - v.voxel_count() * std::size_t(sample_bytes(t))) % 256 == 0);
            const VolumeData r = parse_inr(b, "x.inr");
            REQUIRE(r.nx() == 5);
            REQUIRE(r.ny() == 4);
            REQUIRE(r.nz() == 3);
            CHECK(r.sample_type == sample_type_name(t));
            CHECK(r.grid.data == v.grid.data);
            CHECK(r.spacing[0] == 0.5);
            CHECK(r.spacing[1] == 0.25);
            CHECK(r.spacing[2] == 2.0);
            CHECK(r.min == v.min);
            CHECK(r.max == v.max);
            CHECK(r.warnings.empty());
        }
    }
}

TEST_CASE("big-endian INR data (CPU=sun) are byte-swapped") {
    const std::vector<std::uint8_t> data = {0x3f, 0x80, 0, 0, 0xc0, 0, 0, 0};  // 1.0f, -2.0f big endian
    const VolumeData v = parse_inr(inr_file("XDIM=2\nYDIM=1\nZDIM=1\nTYPE=float\nPIXSIZE=32 bits\nCPU=sun\n", data), "be.inr");
    CHECK(v.grid.data[0] == 1.0f);
    CHECK(v.grid.data[1] == -2.0f);
    const std::vector<std::uint8_t> d16 = {0x01, 0x02};  // 0x0102 = 258 big endian
    const VolumeData w = parse_inr(inr_file("XDIM=1\nYDIM=1\nZDIM=1\nTYPE=unsigned fixed\nPIXSIZE=16 bits\nCPU=sgi\n", d16), "be.inr");
    CHECK(w.grid.data[0] == 258.0f);
}

TEST_CASE("an INR header that is not padded to 256 bytes is read like CGAL reads it") {
    // CGAL's data/images/small-scalar.inr: a 240-byte header, samples right after "##}".
    const auto data = float_data({3, -2, -1, 3, -3, 1, -1, -1.4f});
    const VolumeData v = parse_inr(inr_file(float_2x2x2 + "SCALE=2**0\nVX=100\nVY=100\nVZ=100\n#GEOMETRY=CARTESIAN\n", data, false), "s.inr");
    CHECK(v.grid.data[7] == -1.4f);
    CHECK(v.min == -3.0f);
    CHECK(v.max == 3.0f);
    CHECK(v.spacing[2] == 100.0);
}

TEST_CASE("gzip-compressed INR files are read by content, and so are plain ones named .gz") {
    vtest::TempDir dir;
    const VolumeData v = vtest::small_volume(7, 6, 5, 3, true);
    write_inr(dir.file("a.inr.gz"), v, SampleType::u8, Endian::little, true);
    const VolumeData r = read_inr(dir.file("a.inr.gz"));
    CHECK(r.grid.data == v.grid.data);
    CHECK(r.sample_type == "uint8");
    write_inr(dir.file("b.inr.gz"), v, SampleType::i16, Endian::big, false);  // not compressed despite the name
    CHECK(read_inr(dir.file("b.inr.gz")).grid.data == v.grid.data);
    // Two concatenated gzip members are one stream.
    const auto whole = inr_bytes(v, SampleType::f32);
    const std::size_t cut = 300;
    write_file_bytes(dir.file("p1.gz"), std::span(whole).first(cut), true);
    write_file_bytes(dir.file("p2.gz"), std::span(whole).subspan(cut), true);
    auto b1 = read_file_bytes(dir.file("p1.gz")), b2 = read_file_bytes(dir.file("p2.gz"));
    CHECK(b1.size() + b2.size() == whole.size());
    std::ifstream f1(dir.file("p1.gz"), std::ios::binary), f2(dir.file("p2.gz"), std::ios::binary);
    std::vector<std::uint8_t> cat((std::istreambuf_iterator<char>(f1)), std::istreambuf_iterator<char>());
    cat.insert(cat.end(), std::istreambuf_iterator<char>(f2), std::istreambuf_iterator<char>());
    write_file_bytes(dir.file("c.inr.gz"), cat, false);
    CHECK(read_inr(dir.file("c.inr.gz")).grid.data == v.grid.data);
}

TEST_CASE("a truncated INR file names the byte offset where the data end") {
    auto b = inr_file(float_2x2x2, float_data({1, 2, 3, 4, 5, 6, 7, 8}));
    b.resize(b.size() - 5);
    const VolumeError e = parse_error(b);
    CHECK(e.byte_offset() == static_cast<std::int64_t>(b.size()));
    CHECK(std::string(e.what()).find("bad.inr: byte 283: voxel data truncated") == 0);
    CHECK(e.message().find("need 32 bytes after the 256-byte header, the file has 27") != std::string::npos);
}

TEST_CASE("dimensions that disagree with the data size are an error; extra bytes a warning") {
    // The header claims 3x2x2 floats, the file holds 8.
    const VolumeError e = parse_error(inr_file("XDIM=3\nYDIM=2\nZDIM=2\nTYPE=float\nPIXSIZE=32 bits\nCPU=decm\n", float_data({1, 2, 3, 4, 5, 6, 7, 8})));
    CHECK(e.message().find("3x2x2 samples of 4 bytes need 48 bytes") != std::string::npos);
    // The header claims 1x2x2, the file holds 8: accepted, the rest reported.
    const VolumeData v = parse_inr(inr_file("XDIM=1\nYDIM=2\nZDIM=2\nTYPE=float\nPIXSIZE=32 bits\nCPU=decm\n", float_data({1, 2, 3, 4, 5, 6, 7, 8})), "x.inr");
    REQUIRE(v.warnings.size() == 1);
    CHECK(v.warnings[0] == "x.inr: byte 272: 16 bytes after the voxel data ignored");
}

TEST_CASE("corrupt INR headers name the header line and the field") {
    struct Case {
        std::string fields;
        int line;
        std::string field, message;
    };
    const Case cases[] = {
        {"XDIM=2\nYDIM=x2\nZDIM=2\nTYPE=float\nPIXSIZE=32 bits\n", 3, "YDIM", "expected a positive integer, found 'x2'"},
        {"XDIM=2\nYDIM=0\nZDIM=2\nTYPE=float\nPIXSIZE=32 bits\n", 3, "YDIM", "expected a positive integer, found '0'"},
        {"XDIM=2\nYDIM=2\nZDIM=2\nTYPE=float\nPIXSIZE=24 bits\n", 6, "PIXSIZE", "24 bits is not supported for TYPE=float (32 or 64)"},
        {"XDIM=2\nYDIM=2\nZDIM=2\nTYPE=complex\nPIXSIZE=32 bits\n", 5, "TYPE", "expected 'unsigned fixed', 'signed fixed' or 'float', found 'complex'"},
        {"XDIM=2\nYDIM=2\nZDIM=2\nVDIM=3\nTYPE=float\nPIXSIZE=32 bits\n", 5, "VDIM", "vector images (VDIM=3) are not supported; only scalar images (VDIM=1)"},
        {"XDIM=2\nYDIM=2\nZDIM=2\nTYPE=float\nPIXSIZE=32 bits\nCPU=vax\n", 7, "CPU", "unknown byte order 'vax' (decm, alpha, pc: little endian; sun, sgi: big endian)"},
        {"XDIM=2\nYDIM=2\nZDIM=2\nXDIM=3\nTYPE=float\nPIXSIZE=32 bits\n", 5, "XDIM", "given twice (first on header line 2)"},
        {"XDIM=2\nYDIM=2\nZDIM=2\nTYPE=float\nPIXSIZE=32 bits\nVX=-1\n", 7, "VX", "expected a positive finite number, found '-1'"},
        {"XDIM=2\nYDIM=2\nZDIM 2\nTYPE=float\nPIXSIZE=32 bits\n", 4, "", "expected KEY=VALUE, found 'ZDIM 2'"},
        {"XDIM=99999999\nYDIM=99999999\nZDIM=99999999\nTYPE=float\nPIXSIZE=32 bits\n", 2, "XDIM", "dimensions 99999999x99999999x99999999 are too large (more than 2^24 = 16777216 samples along an axis)"},
        {"XDIM=16777216\nYDIM=16777216\nZDIM=2\nTYPE=float\nPIXSIZE=32 bits\n", 2, "XDIM", "dimensions 16777216x16777216x2 are too large (more than 2^34 samples in all)"},
    };
    for (const Case& c : cases) {
        CAPTURE(c.fields);
        const VolumeError e = parse_error(inr_file(c.fields, float_data({1, 2, 3, 4, 5, 6, 7, 8})));
        CHECK(e.line() == c.line);
        CHECK(e.field() == c.field);
        CHECK(e.message() == c.message);
        CHECK(std::string(e.what()).find("bad.inr: header line " + std::to_string(c.line)) == 0);
    }
    // A missing dimension: the field and the line of the end of the header.
    const VolumeError m = parse_error(inr_file("XDIM=2\nZDIM=2\nTYPE=float\nPIXSIZE=32 bits\n", float_data({1, 2})));
    CHECK(m.field() == "YDIM");
    CHECK(m.message() == "missing from the header (required)");
}

TEST_CASE("a file that is not INR, or whose header never ends, is rejected at a byte offset") {
    const VolumeError a = parse_error(bytes_of("P5\n2 2\n255\n...."));
    CHECK(a.byte_offset() == 0);
    CHECK(a.message() == "not an INR file: expected '#INRIMAGE-4#{', found 'P5\\x0a2 2\\x0a255\\x0a..'");
    const VolumeError b = parse_error(bytes_of("#INRIMAGE-4#{\nXDIM=2\nYDIM=2\n"));
    CHECK(b.byte_offset() == 28);
    CHECK(b.message().find("INR header not terminated by '##}'") == 0);
    CHECK(parse_error({}).byte_offset() == 0);
}

TEST_CASE("NaN samples are an error naming the voxel and its byte offset, or replaced on request") {
    const float nan = std::numeric_limits<float>::quiet_NaN();
    const auto b = inr_file(float_2x2x2, float_data({1, 2, 3, 4, 5, nan, 7, -std::numeric_limits<float>::infinity()}));
    const VolumeError e = parse_error(b);
    CHECK(e.byte_offset() == 256 + 5 * 4);
    CHECK(e.message().find("NaN sample at voxel (1,0,1); 2 non-finite samples in total") == 0);
    const VolumeData r = parse_inr(b, "n.inr", ReadOptions{NanPolicy::replace_min});
    CHECK(r.grid.data[5] == 1.0f);
    CHECK(r.grid.data[7] == 1.0f);
    CHECK(r.min == 1.0f);
    REQUIRE(r.warnings.size() == 1);
    CHECK(r.warnings[0] == "n.inr: byte 276: 2 non-finite samples (first: NaN sample at voxel (1,0,1)) replaced by 1");
    const VolumeData z = parse_inr(b, "n.inr", ReadOptions{NanPolicy::replace_zero});
    CHECK(z.grid.data[5] == 0.0f);
    CHECK(z.max == 7.0f);
}

TEST_CASE("corrupt and truncated gzip streams are clear errors") {
    vtest::TempDir dir;
    const VolumeData v = vtest::small_volume(16, 16, 16, 11, false);
    write_inr(dir.file("ok.inr.gz"), v, SampleType::f32, Endian::little, true);
    std::ifstream in(dir.file("ok.inr.gz"), std::ios::binary);
    const std::vector<std::uint8_t> gz((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    // Truncated: the compressed file ends early.
    write_file_bytes(dir.file("short.inr.gz"), std::span(gz).first(gz.size() / 2));
    try {
        (void)read_inr(dir.file("short.inr.gz"));
        FAIL("accepted a truncated gzip file");
    } catch (const VolumeError& e) {
        CHECK(e.message().find("gzip stream truncated") == 0);
        CHECK(e.byte_offset() == static_cast<std::int64_t>(gz.size() / 2));
    }
    // Corrupt: bytes in the middle of the deflate data replaced (zlib's own error or the CRC).
    auto bad = gz;
    for (std::size_t i = gz.size() / 3; i < gz.size() / 3 + 16; ++i) bad[i] ^= 0x5a;
    write_file_bytes(dir.file("bad.inr.gz"), bad);
    try {
        (void)read_inr(dir.file("bad.inr.gz"));
        FAIL("accepted a corrupt gzip file");
    } catch (const VolumeError& e) {
        CHECK(e.message().find("corrupt gzip stream") == 0);
        CHECK(e.byte_offset() > 0);
        CHECK(e.byte_offset() <= static_cast<std::int64_t>(gz.size()));
    }
    // A file that does not exist.
    try {
        (void)read_inr(dir.file("missing.inr"));
        FAIL("opened a missing file");
    } catch (const VolumeError& e) {
        CHECK(e.message().find("cannot open") == 0);
    }
}

TEST_CASE("randomly damaged INR files give a VolumeError or a valid volume, never a crash") {
    const VolumeData v = vtest::small_volume(6, 5, 4, 5, false);
    const auto good = inr_bytes(v, SampleType::f32);
    std::mt19937 rng(2024);
    int errors = 0, accepted = 0;
    for (int it = 0; it < 400; ++it) {
        auto b = good;
        const int kind = it % 3;
        if (kind == 0) {
            b.resize(std::uniform_int_distribution<std::size_t>(0, b.size() - 1)(rng));
        } else {
            const int n = std::uniform_int_distribution<int>(1, 8)(rng);
            for (int k = 0; k < n; ++k) {
                // Mostly in the header, where the structure is.
                const std::size_t at = std::uniform_int_distribution<std::size_t>(0, kind == 1 ? 120 : b.size() - 1)(rng);
                b[at] = static_cast<std::uint8_t>(std::uniform_int_distribution<int>(0, 255)(rng));
            }
        }
        try {
            const VolumeData r = parse_inr(b, "fuzz.inr");
            ++accepted;
            CHECK(r.voxel_count() == std::size_t(r.nx()) * std::size_t(r.ny()) * std::size_t(r.nz()));
            for (float x : r.grid.data) REQUIRE(std::isfinite(x));
        } catch (const VolumeError& e) {
            ++errors;
            CHECK(std::string(e.what()).rfind("fuzz.inr: ", 0) == 0);
        }
    }
    CHECK(errors > 100);
    CHECK(accepted > 20);
}
