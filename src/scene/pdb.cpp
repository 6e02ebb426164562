// src/scene/pdb.cpp -- PDB reader, bonds, and the balls-and-sticks / space-filling styles
#include "quadcast/scene/pdb.hpp"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <map>
#include <set>
#include <tuple>
#include <unordered_map>

namespace quadcast::scene {

namespace {

std::string_view trim(std::string_view s) {
    while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front()))) s.remove_prefix(1);
    while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.remove_suffix(1);
    return s;
}

/// Columns [first, last] (1-based, inclusive) of `line`, cut short where the line ends.
std::string_view columns(std::string_view line, int first, int last) {
    const std::size_t b = std::size_t(first - 1);
    if (b >= line.size()) return {};
    return line.substr(b, std::min<std::size_t>(std::size_t(last - first + 1), line.size() - b));
}

std::string field_name(const char* name, int first, int last) {
    return std::string(name) + " (columns " + std::to_string(first) + "-" + std::to_string(last) + ")";
}

std::string in_quotes(std::string_view s) { return quote_token(s); }

/// Reads a line-oriented file, keeping track of where we are for diagnostics.
class PdbParser {
public:
    PdbParser(const std::string& file, const PdbOptions& opt) : opt_(opt) { mol_.file = file; }

    Molecule run(std::istream& in) {
        std::string raw;
        while (std::getline(in, raw)) {
            ++line_no_;
            if (!raw.empty() && raw.back() == '\r') raw.pop_back();
            line_ = raw;
            const std::string_view name = trim(columns(line_, 1, 6));
            if (name == "ATOM" || name == "HETATM") {
                if (ignoring_models_) continue;
                read_atom(name == "HETATM");
            } else if (name == "CONECT") {
                conect_lines_.emplace_back(line_no_, line_);
            } else if (name == "MODEL") {
                ++models_;
            } else if (name == "ENDMDL") {
                ignoring_models_ = true;
            } else if (name == "END") {
                break;
            }
        }
        if (in.bad()) error(0, "", "read error");
        if (mol_.atoms.empty()) error(0, "", "no ATOM/HETATM records (not a PDB file, or empty)");
        if (models_ > 1)
            warn(0, "MODEL", "only the first model is read; " + std::to_string(models_ - 1) + " more ignored");
        resolve_conect();
        return std::move(mol_);
    }

private:
    [[noreturn]] void error(int line, const std::string& field, const std::string& msg) const {
        throw ParseError({mol_.file, line, 0, field}, msg);
    }
    void warn(int line, const std::string& field, const std::string& msg) {
        if (opt_.strict) error(line, field, msg + " (strict mode)");
        mol_.warnings.push_back({{mol_.file, line, 0, field}, msg});
    }

    /// Checks that the line reaches column `last` for the field `name`.
    void need(const char* name, int first, int last) const {
        if (int(line_.size()) < last)
            error(line_no_, field_name(name, first, last),
                  "record ends at column " + std::to_string(line_.size()) + " (truncated line?)");
    }

    double coordinate(const char* name, int first, int last) const {
        need(name, first, last);
        const std::string_view f = trim(columns(line_, first, last));
        double v = 0.0;
        const auto [p, ec] = std::from_chars(f.data(), f.data() + f.size(), v);
        if (f.empty()) error(line_no_, field_name(name, first, last), "is blank");
        if (ec != std::errc() || p != f.data() + f.size())
            error(line_no_, field_name(name, first, last), in_quotes(f) + " is not a number");
        if (!std::isfinite(v)) error(line_no_, field_name(name, first, last), in_quotes(f) + " is not finite");
        return v;
    }

    /// Element from columns 77-78 or the atom name (see pdb.hpp).
    const ElementInfo* element_of(std::string_view name4, bool hetatm) {
        const std::string col = canonical_symbol(columns(line_, 77, 78));
        if (!col.empty()) {
            if (is_element_symbol(col)) {
                if (const ElementInfo* e = find_element(col)) return e;
                warn(line_no_, field_name("element", 77, 78),
                     "element " + in_quotes(col) + " has no tabulated radii; drawn as unknown");
                return &unknown_element();
            }
            const std::string inferred = infer_from_name(name4, hetatm);
            warn(line_no_, field_name("element", 77, 78),
                 in_quotes(col) + " is not an element symbol; " +
                     (inferred.empty() ? "atom name " + in_quotes(trim(name4)) + " does not tell either; drawn as unknown"
                                       : "inferred " + in_quotes(inferred) + " from the atom name"));
            if (const ElementInfo* e = find_element(inferred)) return e;
            return &unknown_element();
        }
        const std::string inferred = infer_from_name(name4, hetatm);
        if (const ElementInfo* e = inferred.empty() ? nullptr : find_element(inferred)) return e;
        warn(line_no_, field_name("name", 13, 16),
             "cannot infer an element from atom name " + in_quotes(trim(name4)) + " (columns 77-78 blank); drawn as unknown");
        return &unknown_element();
    }

    static std::string infer_from_name(std::string_view name4, bool hetatm) {
        std::string n(name4);
        n.resize(4, ' ');
        auto letter = [](char c) { return std::isalpha(static_cast<unsigned char>(c)) != 0; };
        auto single = [&](char c) -> std::string {
            if (!letter(c)) return {};
            const std::string s(1, char(std::toupper(static_cast<unsigned char>(c))));
            return find_element(s) ? s : std::string{};
        };
        // Column 13 blank or a digit ("1HB "): one-letter element in column 14.
        if (n[0] == ' ' || std::isdigit(static_cast<unsigned char>(n[0]))) return single(n[1]);
        // Standard residues hold only one-letter elements (H C N O S P).
        if (!hetatm) return single(n[0]);
        // Four-character hydrogen names start in column 13 ("HG11", "Hh22").
        if (std::toupper(static_cast<unsigned char>(n[0])) == 'H' && n[3] != ' ') return "H";
        // PDB alignment rule: a name starting in column 13 is a two-letter element.
        if (letter(n[1])) {
            const std::string two = canonical_symbol(n.substr(0, 2));
            if (find_element(two)) return two;
        }
        return single(n[0]);
    }

    void read_atom(bool hetatm) {
        // Coordinates first: a truncated record is an error before anything else is reported.
        const double x = coordinate("x", 31, 38);
        const double y = coordinate("y", 39, 46);
        const double z = coordinate("z", 47, 54);

        Atom a;
        a.hetatm = hetatm;
        a.line = line_no_;
        a.position = Vec3d{{x, y, z}};
        const std::string_view name4 = columns(line_, 13, 16);
        a.name = std::string(trim(name4));
        a.alt_loc = columns(line_, 17, 17).empty() ? ' ' : columns(line_, 17, 17)[0];
        a.res_name = std::string(trim(columns(line_, 18, 20)));
        a.chain = columns(line_, 22, 22).empty() ? ' ' : columns(line_, 22, 22)[0];
        a.res_seq = std::string(columns(line_, 23, 27));

        // altLoc: keep the first alternate location of each atom.
        if (a.alt_loc != ' ') {
            const auto key = std::make_tuple(a.chain, a.res_seq, a.name);
            if (!alt_seen_.insert(key).second) {
                int s = 0;
                if (decode_hybrid36(columns(line_, 7, 11), s)) dropped_serials_.insert(s);
                return;
            }
        }

        const std::string_view serial = columns(line_, 7, 11);
        int s = 0;
        if (decode_hybrid36(serial, s)) {
            a.serial = s;
            if (!serial_index_.emplace(s, int(mol_.atoms.size())).second)
                warn(line_no_, field_name("serial", 7, 11),
                     "serial " + std::to_string(s) + " repeats the atom of line " +
                         std::to_string(mol_.atoms[std::size_t(serial_index_[s])].line) + "; CONECT uses that one");
        } else {
            warn(line_no_, field_name("serial", 7, 11),
                 in_quotes(trim(serial)) + " is not a serial number; CONECT cannot refer to this atom");
        }
        a.element = element_of(name4, hetatm);
        mol_.atoms.push_back(std::move(a));
    }

    void resolve_conect() {
        mol_.in_conect.assign(mol_.atoms.size(), false);
        std::set<std::pair<int, int>> seen;
        static const char* const names[5] = {"atom", "bonded atom 1", "bonded atom 2", "bonded atom 3", "bonded atom 4"};
        for (const auto& [ln, text] : conect_lines_) {
            line_ = text;
            if (trim(columns(text, 7, 11)).empty()) error(ln, field_name("atom", 7, 11), "is blank");
            int idx[5] = {-1, -1, -1, -1, -1};
            int ser[5] = {0, 0, 0, 0, 0};
            for (int k = 0; k < 5; ++k) {
                const int first = 7 + 5 * k, last = first + 4;
                const std::string_view f = columns(text, first, last);
                if (trim(f).empty()) continue;
                if (!decode_hybrid36(f, ser[k]))
                    error(ln, field_name(names[k], first, last), in_quotes(trim(f)) + " is not a serial number");
                const auto it = serial_index_.find(ser[k]);
                if (it != serial_index_.end()) {
                    idx[k] = it->second;
                } else if (!dropped_serials_.count(ser[k]) && !ignoring_models_) {
                    warn(ln, field_name(names[k], first, last),
                         "serial " + std::to_string(ser[k]) + " names no atom; bond ignored");
                }
            }
            for (int k = 1; k < 5; ++k) {
                if (idx[0] < 0 || idx[k] < 0) continue;
                if (idx[0] == idx[k]) {
                    warn(ln, field_name(names[k], 7 + 5 * k, 11 + 5 * k), "atom bonded to itself; ignored");
                    continue;
                }
                const auto key = std::minmax(idx[0], idx[k]);
                mol_.in_conect[std::size_t(idx[0])] = mol_.in_conect[std::size_t(idx[k])] = true;
                if (seen.insert(key).second) mol_.bonds.push_back({key.first, key.second});
            }
        }
    }

    PdbOptions opt_;
    Molecule mol_;
    std::string line_;
    int line_no_ = 0;
    int models_ = 0;
    bool ignoring_models_ = false;
    std::map<int, int> serial_index_;
    std::set<int> dropped_serials_;
    std::set<std::tuple<char, std::string, std::string>> alt_seen_;
    std::vector<std::pair<int, std::string>> conect_lines_;
};

}  // namespace

bool decode_hybrid36(std::string_view field, int& value) {
    const std::string_view f = trim(field);
    if (f.empty() || f.size() > 5) return false;
    const bool digit0 = std::isdigit(static_cast<unsigned char>(f[0])) || f[0] == '-';
    if (digit0) {
        const auto [p, ec] = std::from_chars(f.data(), f.data() + f.size(), value);
        return ec == std::errc() && p == f.data() + f.size();
    }
    // Hybrid-36 (R. W. Grosse-Kunstleve, 2007): A0000..ZZZZZ then a0000..zzzzz after 99999.
    if (f.size() != 5) return false;
    const bool upper = std::isupper(static_cast<unsigned char>(f[0])) != 0;
    long v = 0;
    for (char c : f) {
        int d;
        if (std::isdigit(static_cast<unsigned char>(c))) d = c - '0';
        else if (upper && c >= 'A' && c <= 'Z') d = c - 'A' + 10;
        else if (!upper && c >= 'a' && c <= 'z') d = c - 'a' + 10;
        else return false;
        v = v * 36 + d;
    }
    const long p4 = 36L * 36 * 36 * 36;
    value = int(upper ? v - 10 * p4 + 100000 : v + 16 * p4 + 100000);
    return true;
}

Molecule parse_pdb(std::istream& in, const std::string& file_name, const PdbOptions& options) {
    PdbParser parser(file_name, options);
    return parser.run(in);
}

Molecule read_pdb(const std::filesystem::path& path, const PdbOptions& options) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw ParseError({path.string(), 0, 0, ""}, std::string("cannot open: ") + std::strerror(errno));
    return parse_pdb(in, path.string(), options);
}

void compute_bonds(Molecule& m) {
    const std::size_t n = m.atoms.size();
    if (m.in_conect.size() != n) m.in_conect.assign(n, false);
    double max_rc = 0.0;
    for (const Atom& a : m.atoms) max_rc = std::max(max_rc, a.element->covalent);
    constexpr double tolerance = 1.15, min_distance = 0.4;
    const double cell = 2.0 * tolerance * max_rc;

    // Hash grid: cell index triple -> atoms in it.
    // Cell indices are clamped (absurd coordinates share the outermost cells; the distance test
    // stays exact) so that the +-1 neighbour offsets cannot overflow.
    auto cell_of = [&](const Vec3d& p) {
        std::array<std::int64_t, 3> c{};
        for (int k = 0; k < 3; ++k) c[std::size_t(k)] = std::int64_t(std::clamp(std::floor(p[k] / cell), -1e15, 1e15));
        return c;
    };
    auto key = [](std::int64_t i, std::int64_t j, std::int64_t k) {
        return (std::uint64_t(i) * 73856093u) ^ (std::uint64_t(j) * 19349663u) ^ (std::uint64_t(k) * 83492791u);
    };
    struct Entry {
        std::array<std::int64_t, 3> c;
        int atom;
    };
    std::unordered_map<std::uint64_t, std::vector<Entry>> grid;
    grid.reserve(n);
    const auto crowded = [&](std::size_t i, const std::string& what) {
        throw ParseError({m.file, m.atoms[i].line, 0, "atom " + quote_token(m.atoms[i].name)},
                         what + " (not a molecular structure: at most " + std::to_string(max_bonds_per_atom) +
                             " bonds per atom are allowed)");
    };
    for (std::size_t i = 0; i < n; ++i) {
        const auto c = cell_of(m.atoms[i].position);
        std::vector<Entry>& in_cell = grid[key(c[0], c[1], c[2])];
        in_cell.push_back({c, int(i)});
        // A grid cell is a cube of two bond lengths: real matter puts a few dozen atoms in it.
        // Absurd densities (thousands of atoms at one point) would make the search quadratic.
        if (in_cell.size() > max_atoms_per_cell) {
            char side[32];
            std::snprintf(side, sizeof side, "%.3g", cell);
            crowded(i, "more than " + std::to_string(max_atoms_per_cell) + " atoms within a cube of " + side + " A side");
        }
    }
    // Atoms within bonding distance of each atom (closer than 0.4 A included): more than
    // max_bonds_per_atom is an error, found before the bond list grows quadratically.
    std::vector<std::uint16_t> near(n, 0);

    std::vector<Bond> bonds = m.bonds;
    for (std::size_t i = 0; i < n; ++i) {
        const Atom& a = m.atoms[i];
        const auto c = cell_of(a.position);
        for (int dx = -1; dx <= 1; ++dx)
            for (int dy = -1; dy <= 1; ++dy)
                for (int dz = -1; dz <= 1; ++dz) {
                    const std::array<std::int64_t, 3> nc{c[0] + dx, c[1] + dy, c[2] + dz};
                    const auto it = grid.find(key(nc[0], nc[1], nc[2]));
                    if (it == grid.end()) continue;
                    for (const Entry& e : it->second) {
                        if (e.c != nc || std::size_t(e.atom) <= i) continue;  // other cell (hash clash), or pair seen
                        const Atom& b = m.atoms[std::size_t(e.atom)];
                        if (a.hetatm && b.hetatm && m.in_conect[i] && m.in_conect[std::size_t(e.atom)]) continue;
                        const double d2 = length2(b.position - a.position);
                        const double cut = tolerance * (a.element->covalent + b.element->covalent);
                        if (!(d2 < cut * cut)) continue;
                        for (const std::size_t k : {i, std::size_t(e.atom)})
                            if (++near[k] > max_bonds_per_atom)
                                crowded(k, "more than " + std::to_string(max_bonds_per_atom) + " atoms within bonding distance");
                        if (d2 > min_distance * min_distance) bonds.push_back({int(i), e.atom});
                    }
                }
    }
    std::sort(bonds.begin(), bonds.end(), [](const Bond& x, const Bond& y) { return std::tie(x.a, x.b) < std::tie(y.a, y.b); });
    bonds.erase(std::unique(bonds.begin(), bonds.end(), [](const Bond& x, const Bond& y) { return x.a == y.a && x.b == y.b; }),
                bonds.end());
    m.bonds = std::move(bonds);
}

void append_molecule(Scene& scene, const Molecule& m, const MoleculeLook& look, const Material& material,
                     const Vec3d* uniform_color) {
    auto material_of = [&](const Atom& a) {
        Material mat = material;
        mat.color = uniform_color ? *uniform_color : a.element->cpk;
        return mat;
    };
    const double scale = look.style == MoleculeStyle::balls_and_sticks ? look.ball_scale : look.vdw_scale;
    scene.spheres.reserve(scene.spheres.size() + m.atoms.size());
    for (const Atom& a : m.atoms) scene.spheres.push_back({a.position, scale * a.element->vdw, material_of(a)});
    if (look.style != MoleculeStyle::balls_and_sticks) return;
    scene.cylinders.reserve(scene.cylinders.size() + 2 * m.bonds.size());
    for (const Bond& b : m.bonds) {
        const Atom& x = m.atoms[std::size_t(b.a)];
        const Atom& y = m.atoms[std::size_t(b.b)];
        const Vec3d mid = (x.position + y.position) * 0.5;
        scene.cylinders.push_back({x.position, mid, look.bond_radius, true, material_of(x)});
        scene.cylinders.push_back({mid, y.position, look.bond_radius, true, material_of(y)});
    }
}

}  // namespace quadcast::scene
