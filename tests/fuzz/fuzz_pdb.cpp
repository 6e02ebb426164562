// tests/fuzz/fuzz_pdb.cpp -- libFuzzer harness: the PDB reader, bonds and the balls-and-sticks scene
#include <cstddef>
#include <cstdint>
#include <sstream>
#include <string>

#include "quadcast/scene/pdb.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace quadcast::scene;
    std::istringstream in(std::string(reinterpret_cast<const char*>(data), size));
    try {
        Molecule m = parse_pdb(in, "fuzz.pdb", PdbOptions{size % 2 == 0});
        compute_bonds(m);
        Scene s;
        append_molecule(s, m, MoleculeLook{}, Material{});
    } catch (const ParseError&) {
    }
    return 0;
}
