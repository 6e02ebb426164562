// tests/fuzz/fuzz_off.cpp -- libFuzzer harness: the OFF reader and the conversion to bilinear quads
#include <cstddef>
#include <cstdint>
#include <sstream>
#include <string>

#include "quadcast/scene/off.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace quadcast::scene;
    std::istringstream in(std::string(reinterpret_cast<const char*>(data), size));
    try {
        const OffMesh mesh = parse_off(in, "fuzz.off");
        Warnings w;
        OffOptions o;
        o.triangles = size % 2 ? TrianglePolicy::error : TrianglePolicy::degenerate_quad;
        (void)off_to_quads(mesh, o, Material{}, w);
    } catch (const ParseError&) {
    }
    return 0;
}
