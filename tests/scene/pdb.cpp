// tests/scene/pdb.cpp -- the PDB reader, bonds and molecule styles
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <random>
#include <set>
#include <sstream>

#include "helpers.hpp"
#include "quadcast/scene/pdb.hpp"

using namespace quadcast::scene;
using namespace scene_test;

namespace {

std::vector<int> degrees(const Molecule& m) {
    std::vector<int> d(m.atoms.size(), 0);
    for (const Bond& b : m.bonds) ++d[std::size_t(b.a)], ++d[std::size_t(b.b)];
    return d;
}

bool has_bond(const Molecule& m, int serial_a, int serial_b) {
    int a = -1, b = -1;
    for (std::size_t i = 0; i < m.atoms.size(); ++i) {
        if (m.atoms[i].serial == serial_a && a < 0) a = int(i);
        if (m.atoms[i].serial == serial_b && b < 0) b = int(i);
    }
    const int lo = std::min(a, b), hi = std::max(a, b);  // (Clang 14 cannot capture structured bindings)
    return std::any_of(m.bonds.begin(), m.bonds.end(), [&](const Bond& x) { return x.a == lo && x.b == hi; });
}

const Atom& atom_on_line(const Molecule& m, int line) {
    for (const Atom& a : m.atoms)
        if (a.line == line) return a;
    FAIL("no atom from line " << line);
    return m.atoms.front();
}

std::string symbol(const Atom& a) { return std::string(a.element->symbol); }

Molecule parse(const std::string& text, const PdbOptions& opt = {}) {
    std::istringstream in(text);
    return parse_pdb(in, "mem.pdb", opt);
}

/// An ATOM/HETATM record in the fixed columns of PDB v3.3.
std::string atom_line(const char* rec, int serial, const char* name, char alt, const char* res, char chain, int seq, double x,
                      double y, double z, const char* element) {
    char buf[100];
    std::snprintf(buf, sizeof buf, "%-6s%5d %-4s%c%3s %c%4d    %8.3f%8.3f%8.3f%6.2f%6.2f          %2s", rec, serial, name, alt,
                  res, chain, seq, x, y, z, 1.0, 20.0, element);
    return buf;
}

/// Every pair within the distance rule, by brute force (the oracle for the grid search).
std::set<std::pair<int, int>> brute_force_bonds(const Molecule& m) {
    std::set<std::pair<int, int>> r;
    for (const Bond& b : m.bonds)  // CONECT bonds (compute_bonds not yet run)
        r.insert({b.a, b.b});
    for (std::size_t i = 0; i < m.atoms.size(); ++i)
        for (std::size_t j = i + 1; j < m.atoms.size(); ++j) {
            const Atom &a = m.atoms[i], &b = m.atoms[j];
            if (a.hetatm && b.hetatm && m.in_conect[i] && m.in_conect[j]) continue;
            const double d = length(b.position - a.position);
            if (d > 0.4 && d < 1.15 * (a.element->covalent + b.element->covalent)) r.insert({int(i), int(j)});
        }
    return r;
}

}  // namespace

TEST_CASE("1tii.pdb reads 5684 atoms and every non-water atom has 1 to 4 bonds") {
    require_pymol_data();
    Molecule m = read_pdb(pymol_demo() / "1tii.pdb");
    CHECK(m.warnings.empty());
    REQUIRE(m.atoms.size() == 5684);  // 5469 ATOM + 215 HETATM (water)
    std::map<std::string, int> count;
    for (const Atom& a : m.atoms) ++count[symbol(a)];
    CHECK(count == std::map<std::string, int>{{"C", 3405}, {"N", 956}, {"O", 1278}, {"S", 45}});

    const auto oracle = brute_force_bonds(m);
    compute_bonds(m);
    const std::set<std::pair<int, int>> got = [&] {
        std::set<std::pair<int, int>> s;
        for (const Bond& b : m.bonds) s.insert({b.a, b.b});
        return s;
    }();
    CHECK(got.size() == m.bonds.size());  // no duplicates
    CHECK(got == oracle);                 // the hash grid finds exactly the brute-force pairs

    const std::vector<int> deg = degrees(m);
    int waters = 0;
    for (std::size_t i = 0; i < m.atoms.size(); ++i) {
        if (m.atoms[i].res_name == "HOH") {
            ++waters;
            CHECK(deg[i] == 0);
        } else {
            INFO("atom " << m.atoms[i].serial << " " << m.atoms[i].name << " " << m.atoms[i].res_name);
            CHECK(deg[i] >= 1);
            CHECK(deg[i] <= 4);
        }
    }
    CHECK(waters == 215);
    // About one bond per heavy atom in a protein (chains plus rings, minus chain ends).
    CHECK(m.bonds.size() > std::size_t(5469 * 0.95));
    CHECK(m.bonds.size() < std::size_t(5469 * 1.10));
    // The disulfides given in CONECT (e.g. 77-617) are bonds.
    CHECK(has_bond(m, 77, 617));
    CHECK(has_bond(m, 5169, 5205));
}

TEST_CASE("il2.pdb reads 2084 atoms with hydrogens, each hydrogen bonded once") {
    require_pymol_data();
    Molecule m = read_pdb(pymol_demo() / "il2.pdb");
    CHECK(m.warnings.empty());
    REQUIRE(m.atoms.size() == 2084);
    compute_bonds(m);
    const std::vector<int> deg = degrees(m);
    int hydrogens = 0;
    for (std::size_t i = 0; i < m.atoms.size(); ++i) {
        INFO("atom " << m.atoms[i].serial << " " << m.atoms[i].name);
        if (symbol(m.atoms[i]) == "H") {
            ++hydrogens;
            CHECK(deg[i] == 1);
        } else {
            CHECK(deg[i] >= 1);
            CHECK(deg[i] <= 4);
        }
    }
    CHECK(hydrogens == 1059);
    CHECK(m.bonds.size() > 2084 - 10);
    CHECK(m.bonds.size() < std::size_t(2084 * 1.05));
}

TEST_CASE("odd01.pdb: old ID columns give warnings, element from the name's alignment, CONECT repeats count once") {
    require_pymol_data();
    Molecule m = read_pdb(pymol_test_dat() / "odd01.pdb");
    compute_bonds(m);
    REQUIRE(m.atoms.size() == 18);
    // Lines 16-18 carry "1AKE18xx" in columns 73-80: element "18" is no symbol.
    REQUIRE(m.warnings.size() == 3);
    for (int i = 0; i < 3; ++i) {
        CHECK(m.warnings[std::size_t(i)].where.line == 16 + i);
        CHECK(m.warnings[std::size_t(i)].where.field == "element (columns 77-78)");
        CHECK(m.warnings[std::size_t(i)].message.find("'18' is not an element symbol") != std::string::npos);
    }
    CHECK(symbol(atom_on_line(m, 16)) == "P");   // " PE " -> P
    CHECK(symbol(atom_on_line(m, 17)) == "O");   // " O1B" -> O
    CHECK(symbol(atom_on_line(m, 18)) == "X");   // "AC5 " -> nothing tabulated: unknown
    CHECK(symbol(atom_on_line(m, 9)) == "C");    // HETATM " CA " (column 14): carbon
    CHECK(symbol(atom_on_line(m, 10)) == "Ca");  // HETATM "CA  " (column 13): calcium
    // Blank occupancy, no chain, odd names "ABCD"/"XYZ": the element column decides.
    for (int line = 11; line <= 15; ++line) CHECK(symbol(atom_on_line(m, line)) == "O");
    // CONECT 1316-1317 is written four times, the last line has no newline.
    CHECK(has_bond(m, 1313, 1314));
    CHECK(has_bond(m, 1316, 1317));
    CHECK(std::count_if(m.bonds.begin(), m.bonds.end(), [&](const Bond& b) {
              return m.atoms[std::size_t(b.a)].serial + m.atoms[std::size_t(b.b)].serial == 1316 + 1317 &&
                     m.atoms[std::size_t(b.a)].serial * m.atoms[std::size_t(b.b)].serial == 1316 * 1317;
          }) == 1);
    // Strict mode makes the first of those warnings an error.
    const ParseError e = parse_error_of([] { read_pdb(pymol_test_dat() / "odd01.pdb", {true}); });
    CHECK(e.line() == 16);
    CHECK(e.field() == "element (columns 77-78)");
}

TEST_CASE("odd02.pdb: no element column and mixed-case hydrogen names read as hydrogens") {
    require_pymol_data();
    Molecule m = read_pdb(pymol_test_dat() / "odd02.pdb");
    compute_bonds(m);
    CHECK(m.warnings.empty());
    REQUIRE(m.atoms.size() == 36);
    const std::vector<int> deg = degrees(m);
    int h = 0;
    for (std::size_t i = 0; i < m.atoms.size(); ++i) {
        const std::string s = symbol(m.atoms[i]);
        CHECK((s == "C" || s == "H" || s == "N" || s == "O"));
        if (s == "H") {
            ++h;
            CHECK(deg[i] == 1);
        }
    }
    CHECK(h == 19);
    CHECK(symbol(atom_on_line(m, 15)) == "H");  // "Hh22"
    CHECK(symbol(atom_on_line(m, 27)) == "H");  // "Hg13", not mercury
}

TEST_CASE("the other PDB files of the PyMOL test data read as documented") {
    require_pymol_data();
    struct Expect {
        const char* file;
        std::size_t atoms;
        std::size_t bonds;  // 0 = not checked
    };
    // names.pdb: '*' and "'" names, "Na+"/"Cl-" names with element O; tiny.pdb: "2HB" names and
    // repeated CONECT; water.pdb: 54-column records; small02.pdb: ligand, bonds from CONECT only;
    // helix_amber.pdb: 65-column records without elements; 3al1.pdb: altLocs A/B/C and ANISOU.
    const Expect expect[] = {{"names.pdb", 86, 0},       {"tiny.pdb", 37, 36},   {"water.pdb", 648, 432},
                             {"small02.pdb", 36, 40},    {"helix_amber.pdb", 392, 0}, {"pept.pdb", 107, 0},
                             {"3al1.pdb", 491, 0},       {"odd01.pdb", 18, 0},   {"odd02.pdb", 36, 0},
                             {"1tii.pdb", 5684, 0},      {"il2.pdb", 2084, 0}};
    for (const Expect& x : expect) {
        INFO(x.file);
        Molecule m = read_pdb(pymol_test_dat() / x.file);
        compute_bonds(m);
        CHECK(m.atoms.size() == x.atoms);
        if (x.bonds) CHECK(m.bonds.size() == x.bonds);
        if (std::string(x.file) != "odd01.pdb") CHECK(m.warnings.empty());
        for (const Atom& a : m.atoms) {
            CHECK(a.element != nullptr);
            CHECK(std::string(a.element->symbol) != "Hg");
        }
    }
    // Every .pdb there (also ones added later) reads without an exception.
    for (const auto& f : fs::directory_iterator(pymol_test_dat())) {
        if (f.path().extension() != ".pdb") continue;
        INFO(f.path());
        CHECK_NOTHROW(read_pdb(f.path()));
    }
    // names.pdb: the ions are named Na+/Cl- but their element column says O.
    Molecule names = read_pdb(pymol_test_dat() / "names.pdb");
    CHECK(symbol(atom_on_line(names, 85)) == "O");
    // small02.pdb: "CL16"/"BR37" with element columns Cl/Br.
    Molecule small = read_pdb(pymol_test_dat() / "small02.pdb");
    CHECK(symbol(small.atoms[0]) == "Cl");
    CHECK(symbol(small.atoms[34]) == "Br");
    // water.pdb: every oxygen has its two hydrogens and nothing else.
    Molecule water = read_pdb(pymol_test_dat() / "water.pdb");
    compute_bonds(water);
    const std::vector<int> deg = degrees(water);
    for (std::size_t i = 0; i < water.atoms.size(); ++i) CHECK(deg[i] == (symbol(water.atoms[i]) == "O" ? 2 : 1));
    // 3al1.pdb: one atom per (chain, residue, name) after dropping later altLocs.
    Molecule alt = read_pdb(pymol_test_dat() / "3al1.pdb");
    std::set<std::tuple<char, std::string, std::string>> ids;
    for (const Atom& a : alt.atoms) ids.insert({a.chain, a.res_seq, a.name});
    CHECK(ids.size() == alt.atoms.size());
}

TEST_CASE("a truncated PDB record is an error naming the line and the missing field") {
    require_pymol_data();
    // The first 500 lines of 1tii.pdb and half of the next one.
    const fs::path src = pymol_demo() / "1tii.pdb";
    std::string text = head_lines(src, 500);
    const std::string next = head_lines(src, 501).substr(text.size());
    REQUIRE(next.rfind("ATOM", 0) == 0);
    text += next.substr(0, 42);  // ends inside y (columns 39-46)
    TempDir dir;
    const fs::path p = dir.write("cut.pdb", text);
    const ParseError e = parse_error_of([&] { read_pdb(p); });
    CHECK(e.file() == p.string());
    CHECK(e.line() == 501);
    CHECK(e.field() == "y (columns 39-46)");
    CHECK(std::string(e.what()) == p.string() + ":501: y (columns 39-46): record ends at column 42 (truncated line?)");
}

TEST_CASE("bad PDB coordinates are errors with file, line and field") {
    const std::string good = atom_line("ATOM", 1, " CA ", ' ', "ALA", 'A', 1, 1, 2, 3, "C");
    REQUIRE(good.size() == 78);
    std::string bad = good;
    bad.replace(30, 8, "     abc");
    ParseError e = parse_error_of([&] { parse(good + "\n" + bad + "\n"); });
    CHECK(std::string(e.what()) == "mem.pdb:2: x (columns 31-38): 'abc' is not a number");

    bad = good;
    bad.replace(38, 8, "     nan");
    e = parse_error_of([&] { parse(bad + "\n"); });
    CHECK(std::string(e.what()) == "mem.pdb:1: y (columns 39-46): 'nan' is not finite");

    bad = good;
    bad.replace(46, 8, "        ");
    e = parse_error_of([&] { parse(bad + "\n"); });
    CHECK(std::string(e.what()) == "mem.pdb:1: z (columns 47-54): is blank");

    bad = good;
    bad.replace(30, 8, "  1.5e99");  // finite: accepted
    CHECK(parse(bad).atoms[0].position[0] == 1.5e99);
}

TEST_CASE("unknown elements are drawn as unknown with a warning, or rejected in strict mode") {
    const std::string xx = atom_line("HETATM", 1, "XX1", ' ', "LIG", 'A', 1, 0, 0, 0, "Xx");
    const std::string ac = atom_line("HETATM", 2, "AC1", ' ', "LIG", 'A', 1, 6, 0, 0, "AC");
    const std::string c = atom_line("HETATM", 3, "C1", ' ', "LIG", 'A', 1, 1.5, 0, 0, "C");
    const std::string text = xx + "\n" + ac + "\n" + c + "\n";
    Molecule m = parse(text);
    REQUIRE(m.atoms.size() == 3);
    CHECK(m.atoms[0].element == &unknown_element());
    CHECK(m.atoms[1].element == &unknown_element());
    REQUIRE(m.warnings.size() == 2);
    CHECK(m.warnings[0].to_string() ==
          "mem.pdb:1: warning: element (columns 77-78): 'Xx' is not an element symbol; atom name 'XX1' does not tell "
          "either; drawn as unknown");
    CHECK(m.warnings[1].to_string() ==
          "mem.pdb:2: warning: element (columns 77-78): element 'Ac' has no tabulated radii; drawn as unknown");
    // The unknown atom still bonds like an organic atom (covalent radius 0.77).
    compute_bonds(m);
    CHECK(m.bonds.size() == 1);
    const ParseError e = parse_error_of([&] { parse(text, {true}); });
    CHECK(e.line() == 1);
}

TEST_CASE("MODEL: only the first model is read, with a warning") {
    std::string text = "MODEL        1\n";
    text += atom_line("ATOM", 1, " N  ", ' ', "GLY", 'A', 1, 0, 0, 0, "N") + "\n";
    text += atom_line("ATOM", 2, " CA ", ' ', "GLY", 'A', 1, 1.45, 0, 0, "C") + "\n";
    text += "ENDMDL\nMODEL        2\n";
    text += atom_line("ATOM", 1, " N  ", ' ', "GLY", 'A', 1, 9, 0, 0, "N") + "\n";
    text += atom_line("ATOM", 2, " CA ", ' ', "GLY", 'A', 1, 9, 1.45, 0, "C") + "\n";
    text += "ENDMDL\nCONECT    1    2\nEND\n";
    Molecule m = parse(text);
    REQUIRE(m.atoms.size() == 2);
    CHECK(m.atoms[0].position[0] == 0.0);
    REQUIRE(m.warnings.size() == 1);
    CHECK(m.warnings[0].message == "only the first model is read; 1 more ignored");
    CHECK(m.bonds.size() == 1);
}

TEST_CASE("altLoc: the first alternate location is kept") {
    std::string text;
    text += atom_line("ATOM", 1, " CB ", 'A', "SER", 'A', 5, 0, 0, 0, "C") + "\n";
    text += atom_line("ATOM", 2, " CB ", 'B', "SER", 'A', 5, 0.3, 0, 0, "C") + "\n";
    text += atom_line("ATOM", 3, " OG ", 'A', "SER", 'A', 5, 1.4, 0, 0, "O") + "\n";
    text += atom_line("ATOM", 4, " OG ", 'B', "SER", 'A', 5, 1.7, 0, 0, "O") + "\n";
    text += "CONECT    2    4\n";  // bonds between dropped atoms: silently ignored
    Molecule m = parse(text);
    REQUIRE(m.atoms.size() == 2);
    CHECK(m.atoms[0].serial == 1);
    CHECK(m.atoms[1].serial == 3);
    CHECK(m.warnings.empty());
    CHECK(m.bonds.empty());
}

TEST_CASE("CONECT: garbage is an error, unknown serials and self bonds are warnings") {
    const std::string atoms = atom_line("HETATM", 1, " C1 ", ' ', "LIG", 'A', 1, 0, 0, 0, "C") + "\n" +
                              atom_line("HETATM", 2, " C2 ", ' ', "LIG", 'A', 1, 1.5, 0, 0, "C") + "\n";
    ParseError e = parse_error_of([&] { parse(atoms + "CONECT    1  abc\n"); });
    CHECK(std::string(e.what()) == "mem.pdb:3: bonded atom 1 (columns 12-16): 'abc' is not a serial number");
    Molecule m = parse(atoms + "CONECT    1    2    7\nCONECT    2    2\n");
    REQUIRE(m.warnings.size() == 2);
    CHECK(m.warnings[0].to_string() == "mem.pdb:3: warning: bonded atom 2 (columns 17-21): serial 7 names no atom; bond ignored");
    CHECK(m.warnings[1].where.line == 4);
    CHECK(m.bonds.size() == 1);
}

TEST_CASE("files without atoms, and files that are not PDB, are errors") {
    ParseError e = parse_error_of([] { parse(""); });
    CHECK(std::string(e.what()) == "mem.pdb: no ATOM/HETATM records (not a PDB file, or empty)");
    e = parse_error_of([] { parse("{\"objects\": []}\n"); });
    CHECK(e.message().find("no ATOM/HETATM") != std::string::npos);
    e = parse_error_of([] { read_pdb("/nonexistent/x.pdb"); });
    CHECK(std::string(e.what()) == "/nonexistent/x.pdb: cannot open: No such file or directory");
}

TEST_CASE("randomly corrupted PDB text never crashes: it reads or throws ParseError") {
    require_pymol_data();
    const std::string base = head_lines(pymol_test_dat() / "tiny.pdb", 60);
    const std::string alphabet = "0123456789 .-+eEnaNxX\n#ATOMHETCONECT";
    int errors = 0, ok = 0;
    for (int iter = 0; iter < 300; ++iter) {
        std::mt19937 rng(1000u + unsigned(iter));
        std::string t = base;
        const int edits = 1 + int(rng() % 8);
        for (int k = 0; k < edits; ++k) {
            const std::size_t at = rng() % t.size();
            switch (rng() % 3) {
            case 0: t[at] = alphabet[rng() % alphabet.size()]; break;
            case 1: t.erase(at, 1 + rng() % 20); break;
            default: t.resize(at); break;
            }
            if (t.empty()) t.push_back('x');
        }
        try {
            Molecule m = parse(t);
            compute_bonds(m);
            for (const Atom& a : m.atoms) REQUIRE(std::isfinite(a.position[0] + a.position[1] + a.position[2]));
            ++ok;
        } catch (const ParseError& e) {
            CHECK(e.file() == "mem.pdb");
            ++errors;
        }
    }
    // Both outcomes occur, so the test exercises both paths.
    CHECK(ok > 10);
    CHECK(errors > 10);
}

TEST_CASE("hybrid-36 serial numbers decode as in the PDB convention") {
    int v = 0;
    CHECK((decode_hybrid36("99999", v) && v == 99999));
    CHECK((decode_hybrid36("    7", v) && v == 7));
    CHECK((decode_hybrid36("A0000", v) && v == 100000));
    CHECK((decode_hybrid36("A0001", v) && v == 100001));
    CHECK((decode_hybrid36("ZZZZZ", v) && v == 100000 + 26 * 36 * 36 * 36 * 36 - 1));
    CHECK((decode_hybrid36("a0000", v) && v == 100000 + 26 * 36 * 36 * 36 * 36));
    CHECK_FALSE(decode_hybrid36("A000", v));
    CHECK_FALSE(decode_hybrid36("aB000", v));
    CHECK_FALSE(decode_hybrid36("*****", v));
    CHECK_FALSE(decode_hybrid36("     ", v));
}

TEST_CASE("balls_and_sticks: a ball per atom and two half sticks per bond; space_filling: vdW spheres") {
    std::string text;
    text += atom_line("HETATM", 1, " C1 ", ' ', "LIG", 'A', 1, 0, 0, 0, "C") + "\n";
    text += atom_line("HETATM", 2, " O1 ", ' ', "LIG", 'A', 1, 1.2, 0, 0, "O") + "\n";
    Molecule m = parse(text);
    compute_bonds(m);
    REQUIRE(m.bonds.size() == 1);
    Scene s;
    Material mat;
    mat.specular = 0.7;
    append_molecule(s, m, {}, mat);
    REQUIRE(s.spheres.size() == 2);
    REQUIRE(s.cylinders.size() == 2);
    CHECK(s.spheres[0].radius == doctest::Approx(0.25 * 1.70));
    CHECK(s.spheres[1].radius == doctest::Approx(0.25 * 1.52));
    CHECK(s.spheres[1].material.color[0] == doctest::Approx(1.0));  // oxygen red
    CHECK(s.spheres[1].material.specular == 0.7);
    CHECK(s.cylinders[0].p1[0] == doctest::Approx(0.6));
    CHECK(s.cylinders[1].p0[0] == doctest::Approx(0.6));
    CHECK(s.cylinders[0].radius == 0.15);
    CHECK(s.cylinders[0].caps);  // capped: closed surfaces keep per-quadric culling
    CHECK(s.cylinders[0].material.color[0] == s.spheres[0].material.color[0]);
    CHECK(s.cylinders[1].material.color[0] == s.spheres[1].material.color[0]);

    Scene f;
    const Vec3d grey{{0.5, 0.5, 0.5}};
    append_molecule(f, m, {MoleculeStyle::space_filling}, mat, &grey);
    REQUIRE(f.spheres.size() == 2);
    CHECK(f.cylinders.empty());
    CHECK(f.spheres[0].radius == 1.70);
    CHECK(f.spheres[1].material.color[0] == 0.5);
}

TEST_CASE("absurd but finite coordinates do not break the neighbour grid") {
    std::string text;
    text += atom_line("HETATM", 1, " C1 ", ' ', "LIG", 'A', 1, 0, 0, 0, "C") + "\n";
    text += atom_line("HETATM", 2, " C2 ", ' ', "LIG", 'A', 1, 0, 0, 0, "C") + "\n";
    text += atom_line("HETATM", 3, " C3 ", ' ', "LIG", 'A', 1, 1.5, 0, 0, "C") + "\n";
    Molecule m = parse(text);
    m.atoms[0].position = Vec3d{{1e300, -1e300, 0}};
    m.atoms[1].position = Vec3d{{-1e300, 1e300, 1e300}};
    m.atoms[2].position = Vec3d{{1e12, 0, 0}};
    m.atoms.push_back(m.atoms[2]);
    m.atoms[3].position = Vec3d{{1e12 + 1.5, 0, 0}};
    compute_bonds(m);
    REQUIRE(m.bonds.size() == 1);
    CHECK(m.bonds[0].a == 2);
    CHECK(m.bonds[0].b == 3);
}
