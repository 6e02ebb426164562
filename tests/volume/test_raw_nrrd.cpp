// tests/volume/test_raw_nrrd.cpp -- raw files with given dimensions, NRRD (attached, detached, gzip), the common loader
#include <doctest/doctest.h>

#include <cstring>
#include <fstream>
#include <string>

#include "quadcast/volume/formats.hpp"
#include "helpers.hpp"
#include "quadcast/volume/load.hpp"

using namespace quadcast::volume;

namespace {

std::vector<std::uint8_t> u8_ramp(std::size_t n) {
    std::vector<std::uint8_t> b(n);
    for (std::size_t i = 0; i < n; ++i) b[i] = static_cast<std::uint8_t>(i * 7 % 251);
    return b;
}

std::vector<std::uint8_t> text(const std::string& s) { return {s.begin(), s.end()}; }

}  // namespace

TEST_CASE("raw files are read with the given dimensions, type and byte order") {
    vtest::TempDir dir;
    const auto data = u8_ramp(4 * 3 * 2 * 2);
    write_file_bytes(dir.file("v.raw"), data);
    RawFormat f;
    f.nx = 4;
    f.ny = 3;
    f.nz = 2;
    f.type = SampleType::u16;
    f.endian = Endian::big;
    const VolumeData v = read_raw(dir.file("v.raw"), f);
    CHECK(v.voxel_count() == 24);
    CHECK(v.grid.at(1, 0, 0) == static_cast<float>(data[2] * 256 + data[3]));
    CHECK(v.grid.at(3, 2, 1) == static_cast<float>(data[46] * 256 + data[47]));
    // The same bytes as uint8 with a 24-byte header.
    f.type = SampleType::u8;
    f.nz = 2;
    f.header_bytes = 24;
    const VolumeData w = read_raw(dir.file("v.raw"), f);
    CHECK(w.grid.at(0, 0, 0) == static_cast<float>(data[24]));
    // Compressed raw files are decompressed first.
    write_file_bytes(dir.file("v.raw.gz"), data, true);
    f.header_bytes = 0;
    f.type = SampleType::i16;
    f.endian = Endian::little;
    const VolumeData g = read_raw(dir.file("v.raw.gz"), f);
    CHECK(g.grid.at(0, 0, 0) == static_cast<float>(static_cast<std::int16_t>(data[0] | data[1] << 8)));
}

TEST_CASE("raw dimensions that disagree with the file size name both sizes") {
    vtest::TempDir dir;
    write_file_bytes(dir.file("v.raw"), u8_ramp(1000));
    RawFormat f;
    f.nx = f.ny = f.nz = 10;
    f.type = SampleType::u16;
    try {
        (void)read_raw(dir.file("v.raw"), f);
        FAIL("accepted a raw file of the wrong size");
    } catch (const VolumeError& e) {
        CHECK(e.field() == "dimensions");
        CHECK(e.message() == "10x10x10 samples of uint16 need 2000 bytes, the file has 1000");
        CHECK(e.byte_offset() == 1000);
    }
    f.nx = 0;
    CHECK_THROWS_AS((void)read_raw(dir.file("v.raw"), f), VolumeError);
}

TEST_CASE("NRRD files with attached, gzip and detached data are read") {
    vtest::TempDir dir;
    const auto data = u8_ramp(5 * 4 * 3 * 4);
    const std::string header = "NRRD0004\n# a comment\ntype: float\ndimension: 3\nsizes: 5 4 3\nendian: little\n"
                               "spacings: 0.5 1 2\ncontent:=ignored\n";
    auto raw = text(header + "encoding: raw\n\n");
    raw.insert(raw.end(), data.begin(), data.end());
    const VolumeData a = parse_nrrd(raw, dir.file("a.nrrd"));
    float first;
    std::memcpy(&first, data.data(), 4);
    CHECK(a.grid.at(0, 0, 0) == first);
    CHECK(a.spacing[2] == 2.0);
    CHECK(a.warnings.empty());

    // gzip encoding
    write_file_bytes(dir.file("payload.gz"), data, true);
    std::ifstream in(dir.file("payload.gz"), std::ios::binary);
    std::vector<std::uint8_t> gz((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    auto g = text(header + "encoding: gzip\n\n");
    g.insert(g.end(), gz.begin(), gz.end());
    CHECK(parse_nrrd(g, dir.file("g.nrrd")).grid.data == a.grid.data);

    // detached data file, relative to the header; diagonal space directions
    write_file_bytes(dir.file("d.raw"), data);
    write_file_bytes(dir.file("d.nhdr"), text("NRRD0005\ntype: float\ndimension: 3\nsizes: 5 4 3\nendian: little\nencoding: raw\n"
                                               "space directions: (0.5,0,0) (0,1,0) (0,0,2)\nspace origin: (1,2,3)\ndata file: d.raw\n"));
    const VolumeData d = read_nrrd(dir.file("d.nhdr"));
    CHECK(d.grid.data == a.grid.data);
    CHECK(d.spacing[0] == 0.5);
    CHECK(d.origin[2] == 3.0);
}

TEST_CASE("bad NRRD headers name the line and the field") {
    auto err = [](const std::string& h) -> VolumeError {
        auto b = text(h);
        b.resize(b.size() + 64, 0);
        try {
            (void)parse_nrrd(b, "/tmp/x.nrrd");
        } catch (const VolumeError& e) {
            return e;
        }
        FAIL("accepted " << h);
        return VolumeError("", -1, 0, "", "");
    };
    VolumeError e = err("NRRD0004\ntype: complex\ndimension: 3\nsizes: 4 4 4\nencoding: raw\n\n");
    CHECK(e.line() == 2);
    CHECK(e.field() == "type");
    e = err("NRRD0004\ntype: uchar\ndimension: 3\nsizes: 4 4\nencoding: raw\n\n");
    CHECK(e.field() == "sizes");
    CHECK(e.message() == "expected 3 sizes, found '4 4'");
    e = err("NRRD0004\ntype: uchar\ndimension: 3\nsizes: 4 4 5\nencoding: raw\n\n");
    CHECK(e.message() == "voxel data truncated: 4x4x5 samples of 1 bytes need 80 bytes, found 64");
    e = err("NRRD0004\ntype: short\ndimension: 3\nsizes: 2 2 2\nencoding: raw\n\n");
    CHECK(e.field() == "endian");
    e = err("NRRD0004\ntype: uchar\ndimension: 3\nsizes: 2 2 2\nencoding: bzip2\n\n");
    CHECK(e.message() == "unsupported encoding 'bzip2' (raw or gzip)");
    e = err("P5\n");
    CHECK(e.byte_offset() == 0);
}

TEST_CASE("load_volume recognises formats by content and name, and synthetic names") {
    vtest::TempDir dir;
    const VolumeData v = vtest::small_volume(3, 3, 3, 1, true);
    write_file_bytes(dir.file("no_extension"), inr_bytes(v, SampleType::u8));
    VolumeRequest r;
    r.input = dir.file("no_extension");
    CHECK(load_volume(r).grid.data == v.grid.data);
    r.input = "marschner-lobb";
    r.size = 9;
    CHECK(load_volume(r).nx() == 9);
    r.input = "franke";
    r.size = 0;
    CHECK(load_volume(r).nx() == 64);
    // Unknown content without raw dimensions: a clear error.
    write_file_bytes(dir.file("mystery.dat"), u8_ramp(27));
    r.input = dir.file("mystery.dat");
    CHECK_THROWS_WITH_AS((void)load_volume(r), doctest::Contains("raw samples need dimensions"), VolumeError);
    r.raw.nx = r.raw.ny = r.raw.nz = 3;
    CHECK(load_volume(r).voxel_count() == 27);
    r.input = dir.file("does-not-exist.inr");
    CHECK_THROWS_WITH_AS((void)load_volume(r), doctest::Contains("cannot open"), VolumeError);
}

TEST_CASE("an isovalue outside the data range is a clear error") {
    const VolumeData v = vtest::small_volume(4, 4, 4, 2, true);
    CHECK_NOTHROW(check_isovalue(v, static_cast<double>(v.min)));
    CHECK_NOTHROW(check_isovalue(v, 0.5 * (static_cast<double>(v.min) + static_cast<double>(v.max))));
    CHECK_THROWS_WITH_AS(check_isovalue(v, static_cast<double>(v.max) + 1.0), doctest::Contains("outside the data range"), VolumeError);
    CHECK_THROWS_WITH_AS(check_isovalue(v, std::nan("")), doctest::Contains("isovalue: is not a finite number"), VolumeError);
}
