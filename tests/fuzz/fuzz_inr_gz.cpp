// tests/fuzz/fuzz_inr_gz.cpp -- libFuzzer harness: .inr.gz (gzip, the header-derived decompression bound, INR)
#include <cstddef>
#include <cstdint>
#include <span>

#include "fuzz_volume_common.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace quadcast::volume;
    try {
        (void)parse_inr_file(std::span<const std::uint8_t>(data, size), "fuzz.inr.gz", {}, quadcast_fuzz::max_bytes);
    } catch (const VolumeError&) {
    }
    return 0;
}
