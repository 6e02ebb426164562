// quadcast/volume/load.hpp -- one entry point for every volume source of `quadcast` (files, synthetic, meshes)
#pragma once

#include <array>
#include <cstdint>
#include <string>

#include "quadcast/volume/formats.hpp"
#include "quadcast/volume/sdf.hpp"
#include "quadcast/volume/synthetic.hpp"
#include "quadcast/volume/volume.hpp"

namespace quadcast::volume {

/// What to load. `input` is a file or the name of a synthetic volume:
///   marschner-lobb   Marschner-Lobb, `size`^3 samples on [-1,1]^3 (default 41)
///   franke           3-D Franke function, `size`^3 samples on [0,1]^3 (default 64)
///   *.inr, *.inr.gz  INR image (also recognised by its magic "#INRIMAGE-4#{")
///   *.nrrd, *.nhdr   NRRD (magic "NRRD000x")
///   *.off            triangle mesh -> signed distance volume, `size` samples along the longest
///                    side (default 64), negative inside
///   anything else    raw samples: `raw.nx/ny/nz` and `raw.type` must be given
struct VolumeRequest {
    std::string input;
    int size = 0;        ///< synthetic: samples per axis; mesh: samples along the longest side; 0 = default
    RawFormat raw{};     ///< for raw files
    ReadOptions read{};  ///< NaN policy of file readers
    int sdf_padding = 3; ///< mesh: extra samples outside the bounding box on each side
};

/// Loads the volume; long computations (signed distance) report to `progress`.
/// Throws VolumeError (or scene::ParseError for a malformed OFF file, whose message names
/// file:line and field).
VolumeData load_volume(const VolumeRequest& request, const Progress& progress = {});

/// One line: source, dimensions, sample type, spacing, range.
std::string describe(const VolumeData& v);

}  // namespace quadcast::volume
