// tests/fuzz/fuzz_scene_json.cpp -- libFuzzer harness: the JSON scene loader (text only; files it names are not read)
#include <cstddef>
#include <cstdint>
#include <string>

#include "quadcast/scene/scene_json.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    try {
        (void)quadcast::scene::parse_scene(std::string(reinterpret_cast<const char*>(data), size), "fuzz.json",
                                           "/nonexistent-quadcast-fuzz-dir");
    } catch (const quadcast::scene::ParseError&) {
    }
    return 0;
}
