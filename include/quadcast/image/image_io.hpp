// quadcast/image/image_io.hpp -- PNG and PFM output, written atomically (no half-written files)
#pragma once

#include <filesystem>

#include "quadcast/render/types.hpp"

namespace quadcast::render {

// Output is whole or absent: each file is written to a uniquely named temporary in the target's
// directory (mkstemp, so concurrent writers to one name do not share it), every write and the
// close are checked, and the temporary is renamed over the target only when complete. A failure
// (or SIGINT/SIGTERM/SIGHUP, whose handler unlinks the registered temporaries and re-raises)
// leaves the old file untouched and no temporary behind. An existing target that is not a
// regular file (a device such as /dev/null, a directory, a FIFO) is never replaced.

/// Writes the colour as an 8-bit RGB PNG (libpng), atomically (see above). Throws std::runtime_error.
void write_png(const std::filesystem::path& path, const Image& img);

/// Writes the window depth as a greyscale PFM ("Pf", little endian, rows bottom first as the
/// format requires); 1.0 = background. Atomic like write_png.
void write_pfm(const std::filesystem::path& path, const Image& img);

/// The PNG and (unless `pfm` is empty) the PFM: both are written to temporaries first and
/// renamed only when both are complete, so an error leaves neither.
void write_png_and_pfm(const std::filesystem::path& png, const std::filesystem::path& pfm, const Image& img);

/// Throws std::runtime_error when `path` exists and is not a regular file.
void check_output_path(const std::filesystem::path& path);
/// check_output_path for both, and an error when they name the same file (compared as
/// canonical paths and as existing files). `pfm` may be empty.
void check_output_paths(const std::filesystem::path& png, const std::filesystem::path& pfm);

/// Reads an 8-bit PNG (RGB or RGBA) written by write_png (for tests and comparisons).
Image read_png(const std::filesystem::path& path);

}  // namespace quadcast::render
