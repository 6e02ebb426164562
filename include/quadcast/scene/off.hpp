// quadcast/scene/off.hpp -- OFF (Geomview Object File Format) reader for bilinear quad meshes
#pragma once

// Plain ASCII OFF, read line by line ('#' starts a comment to the end of the line; blank lines
// are skipped):
//     OFF                      header keyword (optional, as in Geomview; COFF/NOFF/4OFF/
//                              STOFF/nOFF and "OFF BINARY" are rejected)
//     nv nf [ne]               counts (may follow OFF on the same line); ne is ignored
//     x y z                    nv vertex lines, exactly 3 finite numbers each
//     n i0 ... i(n-1) [colour] nf face lines; colour = 3 or 4 numbers, integers 0..255 or
//                              decimals 0..1 (Geomview's rule); 1 number (colour-map index) is
//                              ignored with a warning
// Errors (ParseError, file:line and the field, e.g. "face 3 vertex 2"): missing/garbled
// counts, a vertex or face line missing (truncated file), a wrong number of values, a
// non-number or non-finite value, a face with fewer than 3 vertices, an index out of range.
// Non-comment text after the last face is a warning.
//
// Conversion to bilinear quads (off_to_quads): a 4-vertex face (a, b, c, d) becomes the patch
// with corners p = (a, b, c, d) in face order (see BilinearQuad). A triangle (a, b, c) becomes
// the degenerate quad (a, b, c, c), which is exactly the flat triangle, unless
// OffOptions::triangles == TrianglePolicy::error (then it is a ParseError). Faces with more
// than 4 vertices are a ParseError. A face whose corners are all collinear or coincident (zero
// area) is skipped with a warning.

#include <filesystem>
#include <istream>
#include <optional>
#include <string>
#include <vector>

#include "quadcast/scene/diagnostics.hpp"
#include "quadcast/scene/scene.hpp"

namespace quadcast::scene {

struct OffMesh {
    std::string file;
    std::vector<Vec3d> vertices;
    std::vector<std::vector<int>> faces;
    std::vector<int> face_lines;                    ///< line of each face, for diagnostics
    std::vector<std::optional<Vec3d>> face_colors;  ///< colour in [0,1] when the face has one
    Warnings warnings;
};

/// Parses OFF text; `file_name` is used in diagnostics. Throws ParseError.
OffMesh parse_off(std::istream& in, const std::string& file_name);
/// Opens and parses a file (ParseError if it cannot be opened).
OffMesh read_off(const std::filesystem::path& path);

enum class TrianglePolicy { degenerate_quad, error };

struct OffOptions {
    TrianglePolicy triangles = TrianglePolicy::degenerate_quad;
};

/// The faces as bilinear quads (see above); `material.color` is used for faces without a
/// colour. Warnings (skipped zero-area faces) are appended to `warnings`.
std::vector<BilinearQuad> off_to_quads(const OffMesh& mesh, const OffOptions& options, const Material& material,
                                       Warnings& warnings);

/// True when the four corners are all collinear or coincident (up to rounding): what
/// quadcast::classify_quad<double> (quadcast/bilinear.hpp) calls a segment or a point.
/// Triangles (one corner repeated) and planar quads are not degenerate in this sense.
bool quad_has_zero_area(const std::array<Vec3d, 4>& p);

}  // namespace quadcast::scene
