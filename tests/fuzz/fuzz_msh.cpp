// tests/fuzz/fuzz_msh.cpp -- libFuzzer harness: the Gmsh MSH reader and the isosurface of its field
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "quadcast/scene/msh.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace quadcast::scene;
    try {
        const MshMesh mesh = parse_msh(std::string_view(reinterpret_cast<const char*>(data), size), "fuzz.msh");
        TetmeshIso what;
        what.iso = size % 2 ? 0.25 : 1.0;
        (void)tetmesh_isosurface(mesh, what, Material{}, {});
    } catch (const ParseError&) {
    }
    return 0;
}
