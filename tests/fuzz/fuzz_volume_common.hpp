// tests/fuzz/fuzz_volume_common.hpp -- what the volume harnesses share: the memory bound and the error type
#pragma once

#include <cstdint>

#include "quadcast/volume/formats.hpp"

namespace quadcast_fuzz {
/// Decompressed bytes a harness may produce (below libFuzzer's -rss_limit_mb=2048).
inline constexpr std::uint64_t max_bytes = std::uint64_t(64) << 20;
}  // namespace quadcast_fuzz
