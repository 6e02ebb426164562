// quadcast/scene/elements.hpp -- element radii and CPK colours for molecule rendering
#pragma once

#include <string>
#include <string_view>

#include "quadcast/scene/scene.hpp"

namespace quadcast::scene {

/// Where a van der Waals radius comes from.
enum class VdwSource {
    bondi1964,    ///< A. Bondi, J. Phys. Chem. 68 (1964) 441-451, table I
    mantina2009,  ///< M. Mantina et al., J. Phys. Chem. A 113 (2009) 5806-5812 (main group, not in Bondi)
    fallback      ///< neither table has the element (transition metals): 2.00 A, documented
};

struct ElementInfo {
    std::string_view symbol;  ///< "C", "Cl" (canonical case)
    int z;                    ///< atomic number (D, deuterium, has z = 1)
    double covalent;          ///< single-bond covalent radius, A (Cordero et al. 2008)
    double vdw;               ///< van der Waals radius, A
    VdwSource vdw_source;
    Vec3d cpk;                ///< colour in [0,1] (Jmol's CPK variant)
};

/// The tabulated element with this symbol (any case: "CL", "cl", "Cl"), or nullptr.
const ElementInfo* find_element(std::string_view symbol);

/// The entry used for atoms whose element is unknown or not tabulated: symbol "X",
/// covalent 0.77 A (carbon-like, so it bonds like an organic atom), vdW 1.80 A, deep pink.
const ElementInfo& unknown_element();

/// True when `symbol` (any case) is one of the 118 element symbols of the periodic table
/// (or D, deuterium), tabulated or not.
bool is_element_symbol(std::string_view symbol);

/// "CL" -> "Cl", " c" -> "C"; trims blanks. Does not check that the result is an element.
std::string canonical_symbol(std::string_view symbol);

}  // namespace quadcast::scene
