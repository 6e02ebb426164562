// quadcast/volume/volume.hpp -- volume data for the spline renderer: samples, errors, value range, progress
#pragma once

// Host-side input of `quadcast` (nothing here is traced to GLSL). Every reader produces a
// VolumeData: float samples on a regular grid (quadcast::spline::Volume<float>, i fastest), the
// voxel spacing and origin, and where the data came from.
//
// Errors: VolumeError, whose what() names the file, the place (a header line with its field,
// or a byte offset; in a .gz file the offset counts decompressed bytes) and the problem, e.g.
//     skull.inr: header line 3: XDIM: expected a positive integer, found 'x64'
//     skull.inr: byte 1000: voxel data truncated: 262144 voxels of 4 bytes need 1048576 bytes
//       after the 256-byte header, the file has 744
// Handled cases are documented where they occur (NanPolicy for NaN/Inf voxels, warnings for
// ignored header fields).

#include <array>
#include <cstdint>
#include <functional>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "quadcast/spline/grid.hpp"

namespace quadcast::volume {

using Vec3d = Vec<double, 3>;

/// A problem that makes a volume input unusable. `what()` is the full message
/// `file: place: field: message` (parts that do not apply are left out).
class VolumeError : public std::runtime_error {
public:
    /// `byte_offset` < 0 and `line` <= 0 mean "not known / not applicable".
    VolumeError(std::string file, std::int64_t byte_offset, int line, std::string field, const std::string& message);
    const std::string& file() const noexcept { return file_; }
    std::int64_t byte_offset() const noexcept { return offset_; }
    int line() const noexcept { return line_; }
    const std::string& field() const noexcept { return field_; }
    const std::string& message() const noexcept { return message_; }

private:
    std::string file_;
    std::int64_t offset_;
    int line_;
    std::string field_, message_;
};

/// Sample types of the file formats (converted to float on reading).
enum class SampleType : std::uint8_t { u8, i8, u16, i16, u32, i32, f32, f64 };
/// "uint8", "int8", "uint16", "int16", "uint32", "int32", "float32", "float64".
const char* sample_type_name(SampleType t);
/// Bytes per sample.
int sample_bytes(SampleType t);
/// Parses the names of sample_type_name (and "float"/"double"/"uchar"/"short"/"ushort"); throws
/// std::invalid_argument.
SampleType parse_sample_type(const std::string& name);

enum class Endian : std::uint8_t { little, big };

/// What to do with NaN or infinite samples (only float files can have them).
enum class NanPolicy : std::uint8_t {
    error,        ///< VolumeError naming the first bad voxel (i,j,k) and its byte offset (default)
    replace_min,  ///< replace by the minimum finite sample (a warning says how many)
    replace_zero, ///< replace by 0 (a warning says how many)
};

/// A scalar volume on a regular grid.
struct VolumeData {
    spline::Volume<float> grid;        ///< samples f[i,j,k] = grid.at(i,j,k), i fastest
    Vec3d spacing{{1.0, 1.0, 1.0}};    ///< distance of neighbouring samples per axis (INR VX VY VZ)
    Vec3d origin{{0.0, 0.0, 0.0}};     ///< world position of sample (0,0,0)
    std::string source;                ///< file name or generator description
    std::string sample_type = "float32";  ///< type in the file before conversion to float
    float min = 0.0f, max = 0.0f;      ///< range of the samples (all finite after reading)
    std::vector<std::string> warnings; ///< handled problems, "file: place: message"

    int nx() const { return grid.nx; }
    int ny() const { return grid.ny; }
    int nz() const { return grid.nz; }
    std::size_t voxel_count() const { return grid.data.size(); }
};

/// Recomputes min/max (all samples must be finite).
void update_range(VolumeData& v);

/// Applies `policy` to NaN/Inf samples. `byte_offset_of(n)` gives the file offset of sample n
/// for the error message (may be null). Throws VolumeError under NanPolicy::error.
void apply_nan_policy(VolumeData& v, NanPolicy policy, const std::function<std::int64_t(std::size_t)>& byte_offset_of);

/// Throws VolumeError when the isovalue lies outside [min, max] of the samples (the surface would
/// be empty) or is not finite. Documented handling: an isovalue equal to min or max is accepted.
void check_isovalue(const VolumeData& v, double isovalue);

/// Progress of a long computation: called with the fraction done in [0, 1], from any thread
/// (calls may be concurrent); the last call is with 1.
using Progress = std::function<void(double)>;

/// A Progress that prints `label: NN%` on stderr whenever the percentage grows (on a terminal
/// the line is rewritten in place; otherwise one line per 10%), and a final `label: 100% (T s)`.
Progress stderr_progress(std::string label);

/// Largest decompressed size of a gzip input (the README's "Limits"). Readers whose header
/// gives the size (INR, NRRD, raw) stop at that size plus max_trailing_bytes instead.
inline constexpr std::uint64_t max_decompressed_bytes = std::uint64_t(4) << 30;
/// Extra decompressed bytes tolerated after the samples a header announces.
inline constexpr std::uint64_t max_trailing_bytes = std::uint64_t(1) << 20;

/// The whole content of a file. Files starting with the gzip magic (1f 8b) are decompressed
/// (zlib, concatenated members allowed), so readers see the decompressed bytes and byte
/// offsets in their errors count those. Errors (VolumeError): cannot open; corrupt or truncated
/// gzip stream (with the compressed byte offset where zlib failed).
/// Only regular files are read (a directory, device or FIFO is an error before anything is
/// read), and decompression stops with an error beyond `max_bytes`.
std::vector<std::uint8_t> read_file_bytes(const std::string& path, bool* was_gzip = nullptr,
                                          std::uint64_t max_bytes = max_decompressed_bytes);

/// The bytes of a regular file, not decompressed (VolumeError for anything else: a directory,
/// a device, a FIFO, a file that cannot be opened or read).
std::vector<std::uint8_t> read_regular_file(const std::string& path);
/// Throws VolumeError(`path`) unless `path` names an existing regular file.
void require_regular_file(const std::string& path);

/// Decompresses gzip data (concatenated members allowed; trailing zero bytes ignored). Errors
/// name `path` and the compressed byte offset where zlib failed. More than `max_bytes` of output
/// is an error, or, with `prefix`, the first `max_bytes` are returned (to read a header).
std::vector<std::uint8_t> gunzip(std::span<const std::uint8_t> compressed, const std::string& path,
                                 std::uint64_t max_bytes = max_decompressed_bytes, bool prefix = false);

/// Converts `count` samples of type `type` and byte order `endian` starting at `data` to float
/// (integers exactly up to 2^24, float64 rounded to nearest).
void convert_samples(const std::uint8_t* data, std::size_t count, SampleType type, Endian endian, float* out);

/// "64x64x64".
std::string dims_string(int nx, int ny, int nz);

}  // namespace quadcast::volume
