// quadcast/codegen/verify.hpp -- inputs and comparison for "the GPU computes the CPU's bits"
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "quadcast/codegen/kernel.hpp"

namespace quadcast::codegen {

/// `count` flat inputs for kernel `k`, reproducible from `seed`. A mix per sample: the kernel's
/// own structured generator (its meaningful regime: hits, grazing rays, near-degenerate data),
/// uniformly scaled data over 2^-40..2^40, per-component adversarial values (0, -0, ±1, ±Inf,
/// NaN, subnormals, FLT_MAX, FLT_MIN) and raw bit patterns.
std::vector<std::uint32_t> make_inputs(const KernelDef& k, std::size_t count, std::uint64_t seed);

/// Flat outputs of the CPU float instantiation for every input.
std::vector<std::uint32_t> run_cpu(const KernelDef& k, std::span<const std::uint32_t> inputs, std::size_t count);

/// Distance in units in the last place between two floats given as bits; 0 when both are NaN,
/// UINT64_MAX when exactly one is NaN.
std::uint64_t ulp_distance(std::uint32_t a, std::uint32_t b);

/// How two runs of one kernel compare.
struct Comparison {
    std::size_t samples = 0;
    std::size_t identical = 0;       ///< samples whose every output word matches (NaN == NaN)
    std::uint64_t max_ulp = 0;       ///< over float outputs; UINT64_MAX when a NaN met a number
    std::size_t mask_differences = 0;
    std::size_t first_difference = SIZE_MAX;  ///< index of the first differing sample
    std::string first_report;        ///< inputs and both outputs of that sample
};

Comparison compare(const Signature& sig, std::span<const std::uint32_t> inputs, std::span<const std::uint32_t> expected,
                   std::span<const std::uint32_t> actual, std::size_t count);

}  // namespace quadcast::codegen
