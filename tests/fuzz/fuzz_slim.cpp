// tests/fuzz/fuzz_slim.cpp -- libFuzzer harness: the SLIM inputs (oriented .xyz points, ASCII and
// binary PLY, model files), the reader chosen by the input's first line as read_points does by extension
#include <cstddef>
#include <cstdint>
#include <sstream>
#include <string>

#include "quadcast/slim/model.hpp"
#include "quadcast/slim/points.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace quadcast;
    const std::string text(reinterpret_cast<const char*>(data), size);
    std::istringstream in(text);
    try {
        if (text.rfind("ply", 0) == 0) (void)slim::parse_ply(in, "fuzz.ply");
        else if (text.rfind("quadcast-slim", 0) == 0) (void)slim::parse_model(in, "fuzz.slim");
        else (void)slim::parse_xyz(in, "fuzz.xyz");
    } catch (const scene::ParseError&) {
    }
    return 0;
}
