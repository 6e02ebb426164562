// tests/fuzz/fuzz_raw.cpp -- libFuzzer harness: raw samples; the first 4 bytes choose the layout
#include <cstddef>
#include <cstdint>
#include <span>

#include "fuzz_volume_common.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace quadcast::volume;
    if (size < 4) return 0;
    RawFormat f;
    f.nx = 1 + data[0] % 16;
    f.ny = 1 + data[1] % 16;
    f.nz = 1 + data[2] % 16;
    f.type = static_cast<SampleType>(data[3] % 8);
    f.endian = data[3] & 8 ? Endian::big : Endian::little;
    f.header_bytes = (data[3] >> 4) % 4;
    try {
        ReadOptions o;
        o.nan = data[3] & 64 ? NanPolicy::replace_zero : NanPolicy::error;
        (void)parse_raw(std::span<const std::uint8_t>(data + 4, size - 4), "fuzz.raw", f, o);
    } catch (const VolumeError&) {
    }
    return 0;
}
