// tests/fuzz/fuzz_nrrd.cpp -- libFuzzer harness: the NRRD reader (attached raw or gzip data)
#include <cstddef>
#include <cstdint>
#include <span>

#include "fuzz_volume_common.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace quadcast::volume;
    try {
        (void)parse_nrrd(std::span<const std::uint8_t>(data, size), "/nonexistent-quadcast-fuzz-dir/fuzz.nrrd");
    } catch (const VolumeError&) {
    }
    return 0;
}
