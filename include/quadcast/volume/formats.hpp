// quadcast/volume/formats.hpp -- volume file formats: INR (and .inr.gz), NRRD, raw + dimensions
#pragma once

// INR (Inrimage, as written by CGAL; CGAL's ImageIO reads it the same way):
//     #INRIMAGE-4#{             magic line
//     XDIM=64                   positive integers (leading zeros allowed)
//     YDIM=64
//     ZDIM=64
//     VDIM=1                    optional, default 1; only 1 (scalar images) is supported
//     TYPE=float                "unsigned fixed", "signed fixed" or "float"
//     PIXSIZE=32 bits           8/16/32 bits for fixed, 32/64 bits for float
//     SCALE=2**0                optional; any other value is ignored with a warning
//     CPU=decm                  decm, alpha, pc: little endian; sun, sgi: big endian; missing:
//                               little endian (a warning when samples have more than one byte)
//     VX=3.94  VY=  VZ=         optional voxel size, default 1
//     TX=  TY=  TZ=             optional origin, default 0
//     #GEOMETRY=CARTESIAN       lines starting with '#' are comments; blank lines are padding
//     ##}                       end of the header
// followed by XDIM*YDIM*ZDIM samples, x fastest. The header is normally padded to a multiple of
// 256 bytes; the data start right after the "##}" line in any case (CGAL's small-scalar.inr
// has a 240-byte header). Unknown keys: warning. A key given twice: error.
// Errors (VolumeError): not an INR file, header not terminated, a line without '=', a value
// that does not parse (with the header line and the key), a missing dimension/TYPE/PIXSIZE,
// unsupported TYPE/PIXSIZE/VDIM/CPU, fewer data bytes than the header says (with the byte
// offset where the file ends), NaN/Inf samples (NanPolicy). Extra bytes after the data: warning.
// Gzip-compressed files (.inr.gz, detected by content) are decompressed first; offsets then
// count decompressed bytes.
//
// NRRD (teem's format, the common subset): magic "NRRD000x", then "field: value" lines up to
// an empty line. Supported: type (all 8 scalar types and their aliases), dimension 3 (or 4 with
// a first axis of size 1), sizes, endian, encoding raw / gzip, spacings or a diagonal
// "space directions", "space origin", "data file" (one detached file, relative to the header),
// comments (#) and key:=value lines (ignored). Other fields are ignored with a warning; other
// encodings (ascii, hex, bzip2), "line skip"/"byte skip" != 0 and non-diagonal space directions
// are errors.
//
// Raw: samples only, dimensions and type given by the caller; the file size must be exactly
// header_bytes + nx*ny*nz*size (error otherwise, naming both sizes).

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "quadcast/volume/volume.hpp"

namespace quadcast::volume {

struct ReadOptions {
    NanPolicy nan = NanPolicy::error;
};

/// Parses an INR image from its (decompressed) bytes; `name` is used in messages.
VolumeData parse_inr(std::span<const std::uint8_t> bytes, const std::string& name, const ReadOptions& options = {});
/// Parses the bytes of an .inr or .inr.gz file (gzip detected by content), decompressing no
/// more than the header announces (+ max_trailing_bytes) and never more than `max_bytes`.
VolumeData parse_inr_file(std::span<const std::uint8_t> file_bytes, const std::string& name, const ReadOptions& options = {},
                          std::uint64_t max_bytes = max_decompressed_bytes);
/// Reads an .inr or .inr.gz file.
VolumeData read_inr(const std::string& path, const ReadOptions& options = {});

/// The bytes of an INR file holding `v` with samples of type `type` (values are converted by
/// rounding to nearest and clamping to the type's range), header padded to 256 bytes.
std::vector<std::uint8_t> inr_bytes(const VolumeData& v, SampleType type = SampleType::f32, Endian endian = Endian::little);
/// Writes an INR file (gzip-compressed when `gzip`).
void write_inr(const std::string& path, const VolumeData& v, SampleType type = SampleType::f32,
               Endian endian = Endian::little, bool gzip = false);

/// Parses a NRRD file from its bytes; `path` locates detached data files.
VolumeData parse_nrrd(std::span<const std::uint8_t> bytes, const std::string& path, const ReadOptions& options = {});
/// Reads a .nrrd (attached data) or .nhdr (detached) file.
VolumeData read_nrrd(const std::string& path, const ReadOptions& options = {});

/// Layout of a raw file.
struct RawFormat {
    int nx = 0, ny = 0, nz = 0;
    SampleType type = SampleType::u8;
    Endian endian = Endian::little;
    std::uint64_t header_bytes = 0;  ///< bytes to skip before the samples
    Vec3d spacing{{1.0, 1.0, 1.0}};
};

/// Parses the bytes of a raw file (gzip-compressed ones are decompressed first, no further than
/// the size the format needs).
VolumeData parse_raw(std::span<const std::uint8_t> file_bytes, const std::string& path, const RawFormat& format,
                     const ReadOptions& options = {});
/// Reads raw samples (gzip-compressed raw files are decompressed first).
VolumeData read_raw(const std::string& path, const RawFormat& format, const ReadOptions& options = {});

/// Writes bytes to a file (gzip-compressed when `gzip`); throws VolumeError.
void write_file_bytes(const std::string& path, std::span<const std::uint8_t> bytes, bool gzip = false);

}  // namespace quadcast::volume
