// quadcast/image/image_io.hpp -- PNG and PFM output, written atomically (no half-written files)
#pragma once

#include <filesystem>

#include "quadcast/render/types.hpp"

namespace quadcast::render {

/// Writes the colour as an 8-bit RGB PNG (libpng). Writes to a temporary file in the same
/// directory and renames it, so an error leaves no output behind. Throws std::runtime_error.
void write_png(const std::filesystem::path& path, const Image& img);

/// Writes the window depth as a greyscale PFM ("Pf", little endian, rows bottom first as the
/// format requires); 1.0 = background. Atomic like write_png.
void write_pfm(const std::filesystem::path& path, const Image& img);

/// Reads an 8-bit PNG (RGB or RGBA) written by write_png (for tests and comparisons).
Image read_png(const std::filesystem::path& path);

}  // namespace quadcast::render
