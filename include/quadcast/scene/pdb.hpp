// quadcast/scene/pdb.hpp -- PDB reader, bonds, and the balls-and-sticks / space-filling styles
#pragma once

// Reads the fixed-column ATOM/HETATM/CONECT records of the PDB format v3.3 (wwPDB, "Atomic
// Coordinate Entry Format Description" 3.3, 2012). What is read, and how odd input is handled
// (every warning and error names file:line and the field with its columns):
//
// - ATOM/HETATM: serial (7-11), name (13-16), altLoc (17), resName (18-20), chainID (22),
//   resSeq+iCode (23-27), x y z (31-38, 39-46, 47-54), element (77-78). Other columns
//   (occupancy, B-factor, segment, charge) are ignored. A record shorter than 54 columns, or a
//   coordinate that is blank, not a number or not finite, is an ERROR (truncated or corrupt).
//   A serial that is not a decimal or hybrid-36 number is a warning (the atom is kept but
//   CONECT cannot refer to it); a repeated serial is a warning (CONECT uses the first atom).
// - Element: columns 77-78 when they hold an element symbol (any case). Otherwise (blank, or
//   not a symbol, e.g. "18" in old files whose columns 73-80 are an ID; a warning then) it is
//   inferred from the atom name: ATOM records (standard residues) take the first letter of the
//   name (column 14 when column 13 is blank or a digit); HETATM records follow the PDB
//   alignment rule: a name starting in column 13 is a two-letter element ("CA  " = calcium,
//   " CA " = carbon) unless it is a 4-character hydrogen name ("HG11", "Hh22") or the two
//   letters are not a tabulated element ("CH3 " = carbon).
// - Unknown element (no symbol found, or a symbol without tabulated radii, e.g. "Ac"): a
//   warning, and the atom is drawn with unknown_element() (covalent 0.77 A, vdW 1.80 A, deep
//   pink). Rationale: wild PDB files carry many non-standard element columns; one odd atom
//   should not stop a picture of thousands, and the pink atom plus the warning make the
//   problem visible. PdbOptions::strict turns every warning into an error.
// - altLoc: the first alternate location of an atom (same chain, residue, name) is kept, the
//   others are dropped silently.
// - MODEL/ENDMDL: only the first model is read; a warning says how many were ignored.
// - END stops reading. TER, ANISOU, REMARK and every other record are ignored.
// - CONECT: columns 7-11 (atom) and 12-16, 17-21, 22-26, 27-31 (bonded atoms); repeated pairs
//   (bond orders written as repeats) count once; a field that is not a number is an ERROR; a
//   serial that names no atom is a warning (unless the atom was dropped as an altLoc or in a
//   later model); an atom bonded to itself is a warning.
// - No ATOM/HETATM record at all is an ERROR.
//
// Bonds (compute_bonds): every CONECT bond, plus the distance rule
//     0.4 A < d(i, j) < 1.15 * (r_cov(i) + r_cov(j))
// for every pair except two HETATM atoms that both appear in CONECT records (their bonds are
// taken from CONECT alone, so ligands keep their given topology). Disulfides between ATOM
// records are found by both. Neighbours are searched in a uniform hash grid of cell size
// 2 * 1.15 * max r_cov, so the cost is O(n) for molecules. Limits (ParseError naming the atom's
// line): more than max_bonds_per_atom atoms within bonding distance of one atom (closer than
// 0.4 A included), or more than max_atoms_per_cell atoms in one grid cell -- no molecule comes
// near either, and both keep absurd inputs (thousands of atoms at one point) linear.

#include <cstdint>
#include <filesystem>
#include <istream>
#include <string>
#include <vector>

#include "quadcast/scene/diagnostics.hpp"
#include "quadcast/scene/elements.hpp"
#include "quadcast/scene/scene.hpp"

namespace quadcast::scene {

struct Atom {
    int serial = -1;           ///< -1 when the serial field was unusable
    std::string name;          ///< columns 13-16, trimmed
    char alt_loc = ' ';
    std::string res_name;      ///< trimmed
    char chain = ' ';
    std::string res_seq;       ///< columns 23-27 (number and insertion code), raw
    Vec3d position{};
    bool hetatm = false;
    const ElementInfo* element = nullptr;  ///< never null after reading (unknown_element())
    int line = 0;              ///< line in the file, for diagnostics
};

struct Bond {
    int a, b;  ///< atom indices, a < b
};

struct Molecule {
    std::string file;
    std::vector<Atom> atoms;
    std::vector<Bond> bonds;  ///< filled by CONECT while reading, completed by compute_bonds
    /// Atom indices named in CONECT records (used by the distance rule).
    std::vector<bool> in_conect;
    Warnings warnings;
};

struct PdbOptions {
    bool strict = false;  ///< every warning is a ParseError
};

/// Parses PDB text; `file_name` is used in diagnostics. Throws ParseError.
Molecule parse_pdb(std::istream& in, const std::string& file_name, const PdbOptions& options = {});
/// Opens and parses a file (ParseError if it cannot be opened).
Molecule read_pdb(const std::filesystem::path& path, const PdbOptions& options = {});

/// Most atoms within bonding distance of one atom (a covalent atom has at most 6-8 bonds).
inline constexpr int max_bonds_per_atom = 16;
/// Most atoms in one cell of the neighbour grid (a cube of two bond lengths).
inline constexpr std::size_t max_atoms_per_cell = 256;

/// Adds distance-rule bonds to the CONECT bonds (see above); sorts and deduplicates `bonds`.
void compute_bonds(Molecule& m);

/// Decodes a PDB serial (decimal, or hybrid-36 for serials > 99999); false if not a number.
bool decode_hybrid36(std::string_view field, int& value);

enum class MoleculeStyle { balls_and_sticks, space_filling, skin };

struct MoleculeLook {
    MoleculeStyle style = MoleculeStyle::balls_and_sticks;
    double ball_scale = 0.25;   ///< balls_and_sticks: atom radius = ball_scale * vdW radius
    double bond_radius = 0.15;  ///< balls_and_sticks: stick radius, A
    double vdw_scale = 1.0;     ///< space_filling and skin: atom radius = vdw_scale * vdW radius
    double shrink = 0.5;        ///< skin: the shrink factor s in (0, 1)
};

/// Appends the molecule to the scene: balls_and_sticks = one sphere per atom (ball_scale * vdW,
/// CPK colour) and per bond two uncapped cylinders meeting at the bond's midpoint, each
/// coloured like its atom; space_filling = one vdW sphere per atom, no bonds (compute_bonds is
/// not needed). `uniform_color` (if not null) replaces the CPK colours; `material` gives
/// specular and shininess. The skin style is not drawn here (it needs the skin component: the
/// scene loader hands the balls to scene::skin_build_function()); append_molecule draws it as
/// space filling.
void append_molecule(Scene& scene, const Molecule& m, const MoleculeLook& look, const Material& material,
                     const Vec3d* uniform_color = nullptr);

}  // namespace quadcast::scene
