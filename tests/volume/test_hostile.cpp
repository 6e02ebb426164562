// tests/volume/test_hostile.cpp -- hostile volume input: special files, gzip bombs, limits in messages
#include <doctest/doctest.h>

#include <sys/stat.h>

#include <cstring>
#include <string>

#include "quadcast/volume/formats.hpp"
#include "helpers.hpp"
#include "quadcast/volume/load.hpp"

using namespace quadcast::volume;

namespace {

std::vector<std::uint8_t> text(const std::string& s) { return {s.begin(), s.end()}; }

template <class F>
VolumeError volume_error_of(F&& f) {
    try {
        f();
    } catch (const VolumeError& e) {
        return e;
    } catch (const std::exception& e) {
        FAIL("threw something else than VolumeError: " << e.what());
    }
    FAIL("no error");
    return VolumeError("", -1, 0, "", "");
}

const std::string kHeader = "NRRD0004\ntype: uchar\ndimension: 3\nsizes: 2 2 2\nencoding: raw\n";

}  // namespace

TEST_CASE("a NRRD data file that is a directory, a device or a FIFO is an error naming the header line") {
    vtest::TempDir dir;
    write_file_bytes(dir.file("dir.nhdr"), text(kHeader + "data file: .\n"));
    VolumeError e = volume_error_of([&] { (void)read_nrrd(dir.file("dir.nhdr")); });
    CHECK(e.file() == dir.file("dir.nhdr"));
    CHECK(e.line() == 6);
    CHECK(e.field() == "data file");
    CHECK(e.message().find("is not a regular file (a directory)") != std::string::npos);

    write_file_bytes(dir.file("zero.nhdr"), text(kHeader + "data file: /dev/zero\n"));
    e = volume_error_of([&] { (void)read_nrrd(dir.file("zero.nhdr")); });
    CHECK(e.line() == 6);
    CHECK(e.message().find("not a regular file") != std::string::npos);

    REQUIRE(::mkfifo(dir.file("fifo").c_str(), 0600) == 0);
    write_file_bytes(dir.file("fifo.nhdr"), text(kHeader + "data file: fifo\n"));
    e = volume_error_of([&] { (void)read_nrrd(dir.file("fifo.nhdr")); });  // would block forever
    CHECK(e.line() == 6);

    // Too small for the header's sizes: an error before reading it.
    write_file_bytes(dir.file("small.raw"), text("abc"));
    write_file_bytes(dir.file("small.nhdr"), text(kHeader + "data file: small.raw\n"));
    e = volume_error_of([&] { (void)read_nrrd(dir.file("small.nhdr")); });
    CHECK(e.line() == 6);
    CHECK(e.message().find("has 3 bytes") != std::string::npos);

    // The loader itself refuses special files (a FIFO would block while sniffing the format).
    VolumeRequest r;
    r.input = dir.file("fifo");
    e = volume_error_of([&] { (void)load_volume(r); });
    CHECK(e.message().find("not a regular file") != std::string::npos);
}

TEST_CASE("a gzip bomb stops at the size the header announces") {
    vtest::TempDir dir;
    // An INR header for 2x2x2 bytes followed by 8 MiB of zeros, compressed to a few KiB.
    std::string h = "#INRIMAGE-4#{\nXDIM=2\nYDIM=2\nZDIM=2\nTYPE=unsigned fixed\nPIXSIZE=8 bits\nCPU=decm\n";
    h.append(252 - h.size(), '\n');
    h += "##}\n";
    std::vector<std::uint8_t> bytes = text(h);
    bytes.resize(bytes.size() + (std::size_t(8) << 20), 0);
    write_file_bytes(dir.file("bomb.inr.gz"), bytes, true);
    VolumeError e = volume_error_of([&] { (void)read_inr(dir.file("bomb.inr.gz")); });
    CHECK(e.message().find("decompresses to more than") != std::string::npos);
    // The same with only a little trailing data reads, with a warning.
    bytes.resize(h.size() + 8 + 100);
    write_file_bytes(dir.file("ok.inr.gz"), bytes, true);
    const VolumeData v = read_inr(dir.file("ok.inr.gz"));
    CHECK(v.nx() == 2);
    CHECK(v.warnings.size() == 1);

    // NRRD gzip and raw gzip: the same bound.
    write_file_bytes(dir.file("payload.gz"), std::vector<std::uint8_t>(std::size_t(8) << 20, 0), true);
    write_file_bytes(dir.file("g.nhdr"), text("NRRD0004\ntype: uchar\ndimension: 3\nsizes: 2 2 2\nencoding: gzip\ndata file: payload.gz\n"));
    e = volume_error_of([&] { (void)read_nrrd(dir.file("g.nhdr")); });
    CHECK(e.message().find("decompresses to more than") != std::string::npos);
    RawFormat f;
    f.nx = f.ny = f.nz = 2;
    e = volume_error_of([&] { (void)read_raw(dir.file("payload.gz"), f); });
    CHECK(e.message().find("decompresses to more than 9 bytes") != std::string::npos);
}

TEST_CASE("a dimension over 2^24 names the per-axis limit") {
    std::string h = "#INRIMAGE-4#{\nXDIM=16777217\nYDIM=1\nZDIM=1\nTYPE=unsigned fixed\nPIXSIZE=8 bits\n##}\n";
    const VolumeError e = volume_error_of([&] { (void)parse_inr(text(h), "big.inr"); });
    CHECK(e.field() == "XDIM");
    CHECK(e.message().find("more than 2^24 = 16777216 samples along an axis") != std::string::npos);
}
