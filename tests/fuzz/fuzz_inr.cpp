// tests/fuzz/fuzz_inr.cpp -- libFuzzer harness: the INR reader (uncompressed bytes)
#include <cstddef>
#include <cstdint>
#include <span>

#include "fuzz_volume_common.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace quadcast::volume;
    try {
        ReadOptions o;
        o.nan = size % 3 == 0 ? NanPolicy::error : size % 3 == 1 ? NanPolicy::replace_min : NanPolicy::replace_zero;
        (void)parse_inr(std::span<const std::uint8_t>(data, size), "fuzz.inr", o);
    } catch (const VolumeError&) {
    }
    return 0;
}
