// quadcast/slim/points.hpp -- oriented point clouds: .xyz/.pwn, .ply (ASCII and binary), .off meshes sampled
#pragma once

// Readers of the SLIM builder's input (Ohtake, Belyaev & Alexa 2005): points with outward unit
// normals. Every error is a quadcast::scene::ParseError naming the file, the line (text) or the
// byte offset (binary PLY, in the field: "vertex 12 nz (byte 4711)") and the field.
//
//   .xyz, .pwn   ASCII, one point per line "x y z nx ny nz" ('#' starts a comment, blank lines are
//                skipped). A line of 3 numbers is "missing normals"; any other count, a
//                non-number or a non-finite value is an error.
//   .ply         "ply", "format ascii 1.0" | "binary_little_endian 1.0" | "binary_big_endian 1.0",
//                comment/obj_info lines, elements with scalar and list properties (char/int8 ..
//                double/float64), "end_header". The element "vertex" must have x y z nx ny nz
//                (float or double); its other properties and every other element (faces, edges)
//                are read and ignored. Errors: a malformed header (wrong magic or format, unknown
//                type, a property outside an element, no end_header, no vertex element, missing
//                normals), a record with too few / too many values (ASCII), data that ends early
//                (binary: the byte offset where it ends and the record it was in), a non-finite
//                value.
//   .off         a mesh (quadcast::scene::read_off), sampled to oriented points: see sample_mesh.
//
// Every normal is normalised; a zero (or non-finite after normalisation) normal is an error on
// its line / record. Fewer than ReadOptions::min_points points is an error naming the file.

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <istream>
#include <string>
#include <vector>

#include "quadcast/linalg.hpp"
#include "quadcast/scene/diagnostics.hpp"
#include "quadcast/scene/off.hpp"

namespace quadcast::slim {

using Vec3d = Vec<double, 3>;

/// Points with outward unit normals (f < 0 inside, normals point towards f > 0).
struct OrientedPoints {
    std::string file;             ///< for diagnostics
    std::vector<Vec3d> positions;
    std::vector<Vec3d> normals;   ///< unit length, one per position
    scene::Warnings warnings;
    std::size_t size() const { return positions.size(); }
};

/// The fewest points a quadric fit needs (10 coefficients).
inline constexpr std::size_t min_fit_points = 10;

struct ReadOptions {
    /// Fewer points than this is a ParseError naming the file.
    std::size_t min_points = min_fit_points;
    /// .off only: oriented samples drawn from the faces (0: as many as the mesh has vertices,
    /// at least 100000).
    std::size_t mesh_samples = 0;
    /// .off only: seed of the sampler (same seed, same samples on every platform).
    std::uint64_t seed = 1;
};

/// ASCII "x y z nx ny nz" lines. Throws scene::ParseError.
OrientedPoints parse_xyz(std::istream& in, const std::string& file_name, const ReadOptions& options = {});
/// A PLY file (ASCII or binary, either byte order); `in` must be opened in binary mode.
OrientedPoints parse_ply(std::istream& in, const std::string& file_name, const ReadOptions& options = {});

/// Area-weighted random samples of a mesh's faces (polygons are fanned from their first vertex),
/// each with its face's unit normal (right-hand rule over the face's vertex order: a mesh whose
/// faces are counter-clockwise seen from outside gets outward normals, as OFF files are written).
/// The random numbers are a std::mt19937_64 seeded with `options.seed`, mapped to [0, 1) by the
/// top 53 bits (no library distribution, so every platform draws the same samples). Faces of zero
/// area are never drawn; a mesh with no area is a ParseError.
/// Why faces and not vertices: at a crease a vertex normal averages the two sides, so the
/// sharp-feature split (quadcast/slim/build.hpp) would see a third, wrong, normal cluster.
OrientedPoints sample_mesh(const scene::OffMesh& mesh, const ReadOptions& options = {});

/// Reads by extension (case-insensitive): .xyz, .pwn, .ply, .off. Throws scene::ParseError
/// (unknown extension, cannot open, parse errors).
OrientedPoints read_points(const std::filesystem::path& path, const ReadOptions& options = {});

}  // namespace quadcast::slim
