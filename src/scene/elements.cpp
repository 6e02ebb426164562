// src/scene/elements.cpp -- element radii and CPK colours for molecule rendering
//
// Sources of the numbers (all radii in Angstrom):
// - Covalent radii: B. Cordero, V. Gomez, A. E. Platero-Prats, M. Reves, J. Echeverria,
//   E. Cremades, F. Barragan, S. Alvarez, "Covalent radii revisited", Dalton Trans. (2008)
//   2832-2838, table 2 (C: sp3 value 0.76; Mn, Fe, Co: low-spin values).
// - van der Waals radii: A. Bondi, "van der Waals volumes and radii", J. Phys. Chem. 68 (1964)
//   441-451, table I; main-group elements Bondi lacks from M. Mantina, A. C. Chamberlin,
//   R. Valero, C. J. Cramer, D. G. Truhlar, "Consistent van der Waals radii for the whole main
//   group", J. Phys. Chem. A 113 (2009) 5806-5812, table 12. Transition metals in neither table
//   (Cr, Mn, Fe, Co, Mo) get the fallback 2.00 A (marked VdwSource::fallback).
// - Colours: Jmol's element colours (the CPK variant used by Jmol/PyMOL-like viewers), as the
//   hex triplets listed at jmol.sourceforge.net/jscolors.
#include "quadcast/scene/elements.hpp"

#include <array>
#include <cctype>

namespace quadcast::scene {

namespace {

constexpr Vec3d rgb(unsigned hex) {
    return {{double((hex >> 16) & 0xFF) / 255.0, double((hex >> 8) & 0xFF) / 255.0, double(hex & 0xFF) / 255.0}};
}

using S = VdwSource;
constexpr S B = S::bondi1964, M = S::mantina2009, F = S::fallback;

// clang-format off
const ElementInfo kElements[] = {
    // sym   Z   covalent vdW   source colour
    {"H",    1,  0.31,    1.20, B, rgb(0xFFFFFF)},
    {"D",    1,  0.31,    1.20, B, rgb(0xFFFFC0)},  // deuterium: hydrogen's radii
    {"He",   2,  0.28,    1.40, B, rgb(0xD9FFFF)},
    {"Li",   3,  1.28,    1.82, B, rgb(0xCC80FF)},
    {"Be",   4,  0.96,    1.53, M, rgb(0xC2FF00)},
    {"B",    5,  0.84,    1.92, M, rgb(0xFFB5B5)},
    {"C",    6,  0.76,    1.70, B, rgb(0x909090)},
    {"N",    7,  0.71,    1.55, B, rgb(0x3050F8)},
    {"O",    8,  0.66,    1.52, B, rgb(0xFF0D0D)},
    {"F",    9,  0.57,    1.47, B, rgb(0x90E050)},
    {"Ne",  10,  0.58,    1.54, B, rgb(0xB3E3F5)},
    {"Na",  11,  1.66,    2.27, B, rgb(0xAB5CF2)},
    {"Mg",  12,  1.41,    1.73, B, rgb(0x8AFF00)},
    {"Al",  13,  1.21,    1.84, M, rgb(0xBFA6A6)},
    {"Si",  14,  1.11,    2.10, B, rgb(0xF0C8A0)},
    {"P",   15,  1.07,    1.80, B, rgb(0xFF8000)},
    {"S",   16,  1.05,    1.80, B, rgb(0xFFFF30)},
    {"Cl",  17,  1.02,    1.75, B, rgb(0x1FF01F)},
    {"Ar",  18,  1.06,    1.88, B, rgb(0x80D1E3)},
    {"K",   19,  2.03,    2.75, B, rgb(0x8F40D4)},
    {"Ca",  20,  1.76,    2.31, M, rgb(0x3DFF00)},
    {"Cr",  24,  1.39,    2.00, F, rgb(0x8A99C7)},
    {"Mn",  25,  1.39,    2.00, F, rgb(0x9C7AC7)},
    {"Fe",  26,  1.32,    2.00, F, rgb(0xE06633)},
    {"Co",  27,  1.26,    2.00, F, rgb(0xF090A0)},
    {"Ni",  28,  1.24,    1.63, B, rgb(0x50D050)},
    {"Cu",  29,  1.32,    1.40, B, rgb(0xC88033)},
    {"Zn",  30,  1.22,    1.39, B, rgb(0x7D80B0)},
    {"Ga",  31,  1.22,    1.87, B, rgb(0xC28F8F)},
    {"Ge",  32,  1.20,    2.11, M, rgb(0x668F8F)},
    {"As",  33,  1.19,    1.85, B, rgb(0xBD80E3)},
    {"Se",  34,  1.20,    1.90, B, rgb(0xFFA100)},
    {"Br",  35,  1.20,    1.85, B, rgb(0xA62929)},
    {"Kr",  36,  1.16,    2.02, B, rgb(0x5CB8D1)},
    {"Rb",  37,  2.20,    3.03, M, rgb(0x702EB0)},
    {"Sr",  38,  1.95,    2.49, M, rgb(0x00FF00)},
    {"Mo",  42,  1.54,    2.00, F, rgb(0x54B5B5)},
    {"Pd",  46,  1.39,    1.63, B, rgb(0x006985)},
    {"Ag",  47,  1.45,    1.72, B, rgb(0xC0C0C0)},
    {"Cd",  48,  1.44,    1.58, B, rgb(0xFFD98F)},
    {"In",  49,  1.42,    1.93, B, rgb(0xA67573)},
    {"Sn",  50,  1.39,    2.17, B, rgb(0x668080)},
    {"Sb",  51,  1.39,    2.06, M, rgb(0x9E63B5)},
    {"Te",  52,  1.38,    2.06, B, rgb(0xD47A00)},
    {"I",   53,  1.39,    1.98, B, rgb(0x940094)},
    {"Xe",  54,  1.40,    2.16, B, rgb(0x429EB0)},
    {"Cs",  55,  2.44,    3.43, M, rgb(0x57178F)},
    {"Ba",  56,  2.15,    2.68, M, rgb(0x00C900)},
    {"Pt",  78,  1.36,    1.72, B, rgb(0xD0D0E0)},
    {"Au",  79,  1.36,    1.66, B, rgb(0xFFD123)},
    {"Hg",  80,  1.32,    1.55, B, rgb(0xB8B8D0)},
    {"Tl",  81,  1.45,    1.96, B, rgb(0xA6544D)},
    {"Pb",  82,  1.46,    2.02, B, rgb(0x575961)},
    {"Bi",  83,  1.48,    2.07, M, rgb(0x9E4FB5)},
    {"U",   92,  1.96,    1.86, B, rgb(0x008FFF)},
};
// clang-format on

const ElementInfo kUnknown{"X", 0, 0.77, 1.80, F, rgb(0xFF1493)};

constexpr std::array<std::string_view, 119> kPeriodic = {
    "H",  "He", "Li", "Be", "B",  "C",  "N",  "O",  "F",  "Ne", "Na", "Mg", "Al", "Si", "P",  "S",
    "Cl", "Ar", "K",  "Ca", "Sc", "Ti", "V",  "Cr", "Mn", "Fe", "Co", "Ni", "Cu", "Zn", "Ga", "Ge",
    "As", "Se", "Br", "Kr", "Rb", "Sr", "Y",  "Zr", "Nb", "Mo", "Tc", "Ru", "Rh", "Pd", "Ag", "Cd",
    "In", "Sn", "Sb", "Te", "I",  "Xe", "Cs", "Ba", "La", "Ce", "Pr", "Nd", "Pm", "Sm", "Eu", "Gd",
    "Tb", "Dy", "Ho", "Er", "Tm", "Yb", "Lu", "Hf", "Ta", "W",  "Re", "Os", "Ir", "Pt", "Au", "Hg",
    "Tl", "Pb", "Bi", "Po", "At", "Rn", "Fr", "Ra", "Ac", "Th", "Pa", "U",  "Np", "Pu", "Am", "Cm",
    "Bk", "Cf", "Es", "Fm", "Md", "No", "Lr", "Rf", "Db", "Sg", "Bh", "Hs", "Mt", "Ds", "Rg", "Cn",
    "Nh", "Fl", "Mc", "Lv", "Ts", "Og", "D"};

}  // namespace

std::string canonical_symbol(std::string_view s) {
    while (!s.empty() && s.front() == ' ') s.remove_prefix(1);
    while (!s.empty() && s.back() == ' ') s.remove_suffix(1);
    std::string r(s);
    for (std::size_t i = 0; i < r.size(); ++i) {
        const unsigned char c = static_cast<unsigned char>(r[i]);
        r[i] = static_cast<char>(i == 0 ? std::toupper(c) : std::tolower(c));
    }
    return r;
}

const ElementInfo* find_element(std::string_view symbol) {
    const std::string c = canonical_symbol(symbol);
    for (const ElementInfo& e : kElements)
        if (e.symbol == c) return &e;
    return nullptr;
}

const ElementInfo& unknown_element() { return kUnknown; }

bool is_element_symbol(std::string_view symbol) {
    const std::string c = canonical_symbol(symbol);
    for (std::string_view e : kPeriodic)
        if (e == c) return true;
    return false;
}

}  // namespace quadcast::scene
