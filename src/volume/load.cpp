// src/volume/load.cpp -- one entry point for every volume source of `quadcast` (files, synthetic, meshes)
#include "quadcast/volume/load.hpp"

#include <cstdio>
#include <cstring>
#include <fstream>

namespace quadcast::volume {

namespace {

bool ends_with(const std::string& s, const char* suffix) {
    const std::size_t n = std::strlen(suffix);
    return s.size() >= n && s.compare(s.size() - n, n, suffix) == 0;
}

/// The first bytes of a file (decompressed if it is gzip), to recognise the format.
std::string file_start(const std::string& path) {
    require_regular_file(path);  // a FIFO would block here, a directory read as empty
    std::ifstream in(path, std::ios::binary);
    if (!in) throw VolumeError(path, -1, 0, "", std::string("cannot open: ") + std::strerror(errno));
    char buf[16] = {};
    in.read(buf, sizeof buf);
    return std::string(buf, static_cast<std::size_t>(in.gcount()));
}

}  // namespace

VolumeData load_volume(const VolumeRequest& r, const Progress& progress) {
    if (r.input == "marschner-lobb") return marschner_lobb_volume(r.size > 0 ? r.size : 41);
    if (r.input == "franke") return franke_volume(r.size > 0 ? r.size : 64);
    const std::string start = file_start(r.input);
    const bool gz = start.size() >= 2 && static_cast<unsigned char>(start[0]) == 0x1f && static_cast<unsigned char>(start[1]) == 0x8b;
    if (start.rfind("#INRIMAGE-4#{", 0) == 0 || ends_with(r.input, ".inr") || (gz && ends_with(r.input, ".inr.gz")))
        return read_inr(r.input, r.read);
    if (start.rfind("NRRD000", 0) == 0 || ends_with(r.input, ".nrrd") || ends_with(r.input, ".nhdr"))
        return read_nrrd(r.input, r.read);
    if (start.rfind("OFF", 0) == 0 || ends_with(r.input, ".off")) {
        std::vector<std::string> warnings;
        const TriangleMesh m = read_off_mesh(r.input, &warnings);
        SdfOptions o;
        o.resolution = r.size > 0 ? r.size : 64;
        o.padding = r.sdf_padding;
        VolumeData v = signed_distance_volume(m, o, progress);
        v.warnings.insert(v.warnings.begin(), warnings.begin(), warnings.end());
        return v;
    }
    if (r.raw.nx <= 0 || r.raw.ny <= 0 || r.raw.nz <= 0)
        throw VolumeError(r.input, -1, 0, "", "unknown format (not INR, NRRD or OFF): raw samples need dimensions and a sample type");
    return read_raw(r.input, r.raw, r.read);
}

std::string describe(const VolumeData& v) {
    char buf[512];
    std::snprintf(buf, sizeof buf, "%s: %s %s samples, spacing (%g, %g, %g), origin (%g, %g, %g), range [%.9g, %.9g]",
                  v.source.c_str(), dims_string(v.nx(), v.ny(), v.nz()).c_str(), v.sample_type.c_str(), v.spacing[0],
                  v.spacing[1], v.spacing[2], v.origin[0], v.origin[1], v.origin[2], static_cast<double>(v.min),
                  static_cast<double>(v.max));
    return buf;
}

}  // namespace quadcast::volume
