// quadcast/scene/msh.hpp -- Gmsh MSH 4.1 reader (tetrahedral meshes with nodal fields) and the
// isosurface of a nodal field as quadrics clipped to the tetrahedra
#pragma once

// The subset of MSH 4.1 (https://gmsh.info/doc/texinfo/gmsh.html#MSH-file-format) a finite
// element user's tetrahedral mesh with scalar results needs, ASCII and binary (little-endian,
// data size 8):
//     $MeshFormat      version 4.1 (2.x and 4.0 are rejected: convert with
//                      `gmsh in.msh -0 -format msh41 -o out.msh`)
//     $Nodes           every entity block; parametric coordinates are read and dropped
//     $Elements        4-node (type 4) and 10-node (type 11) tetrahedra are kept; elements of
//                      dimension 0-2 (boundary points, lines, triangles) are skipped; other
//                      volume elements (hexahedra, prisms, pyramids, higher-order tetrahedra)
//                      are an error
//     $NodeData        one field per block (its first string tag is the name, its integer tags
//                      the time step, the number of components and the number of entries)
//     $Entities, $PhysicalNames and every other section are skipped; $PartitionedEntities
//     (a partitioned mesh) is an error.
// Errors (ParseError) name the file, the line (in binary sections the line the binary data
// start on, and the byte offset in the field) and the field ("$Nodes block 2 node 17 z"): a
// missing or garbled number, a count that the file is too short for (a truncated file), a node
// tag given twice, an element whose node is not in $Nodes, an unterminated section.
//
// This is a reader of our own: libgmsh reads these files too, but it interprets any file that is
// not a mesh as a Gmsh script (a scene pointing at a hostile file would run it), and its errors
// name neither the line nor the field. The tests compare this reader with libgmsh on files Gmsh
// writes.

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "quadcast/scene/diagnostics.hpp"
#include "quadcast/scene/scene.hpp"

namespace quadcast::scene {

/// A 4- or 10-node tetrahedron: `node` are indices into MshMesh::nodes in Gmsh's order (corners
/// 0-3, then for 10 nodes the edge nodes of edges 01, 12, 20, 30, 32, 31).
struct MshTet {
    std::uint32_t node[10];
    int nodes = 10;  ///< 4 or 10
    std::size_t tag = 0;
    int line = 0;  ///< line of the element (binary: of the element block's data)
};

/// One $NodeData block: `value[c + components * n]` is component c at node index n, NaN for nodes
/// the block does not list.
struct MshField {
    std::string name;
    int step = 0;
    double time = 0;
    int components = 1;
    int line = 0;  ///< line of its $NodeData
    std::vector<double> value;
};

struct MshMesh {
    std::string file;
    bool binary = false;
    std::vector<Vec3d> nodes;
    std::vector<std::size_t> node_tags;  ///< the tag of each node
    std::vector<MshTet> tets;
    std::size_t skipped_lower_dimensional = 0;  ///< boundary points, lines and triangles
    std::vector<MshField> fields;
    Warnings warnings;
};

/// Parses the bytes of a .msh file; `file_name` is used in messages. Throws ParseError.
MshMesh parse_msh(std::string_view bytes, const std::string& file_name);
/// Reads and parses a file (ParseError if it cannot be read).
MshMesh read_msh(const std::filesystem::path& path);

/// What to draw of a mesh: the isosurface field = iso of the scalar field `field` (empty: the
/// file's only field) at time step `step` (nullopt: the field's only step).
struct TetmeshIso {
    std::string field;
    std::optional<int> step;
    double iso = 0;
};

/// The isosurface as one quadric per tetrahedron whose field range contains `iso`, clipped to it
/// (Quadric::Bound::tetrahedron): the element's Lagrange polynomial (linear for 4 nodes,
/// quadratic for 10) minus `iso`, converted to BB form and then to a quadric
/// (quadcast/bb/quadric_form.hpp), in double. The gradient of the field is the normal.
/// Errors (ParseError at `where` with the field "field", "step", "iso" or "tetmesh" naming the
/// choice that failed, or at the element's line in the mesh file): no such field,
/// several fields or steps and none chosen, a vector field, an isovalue outside the field's
/// range over the elements, a node without a value, a curved 10-node element (an edge node
/// farther than 1e-6 of the element's size from its edge's midpoint: only straight-sided
/// elements are drawn exactly; Gmsh writes them with Mesh.SecondOrderLinear = 1), a flat
/// element.
std::vector<Quadric> tetmesh_isosurface(const MshMesh& mesh, const TetmeshIso& what, const Material& material,
                                        const Location& where);

}  // namespace quadcast::scene
