// quadcast/codegen/interpret.hpp -- evaluates a traced kernel's DAG on the CPU, node by node
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "quadcast/codegen/kernel.hpp"

namespace quadcast::codegen {

/// A kernel traced once and kept for repeated evaluation.
class TracedKernel {
public:
    explicit TracedKernel(const KernelDef& k);
    const Signature& signature() const { return io_.signature(); }
    /// Evaluates the recorded DAG in float for one flat input; returns flat output words
    /// (float bits, 0/1 for masks). Every node is one IEEE operation, so this equals what the
    /// GLSL computes where the driver rounds like the CPU.
    void run(std::span<const std::uint32_t> in, std::span<std::uint32_t> out);
    std::size_t nodes() const { return rec_.size(); }

private:
    Recorder rec_;
    TraceIO io_;
    std::vector<std::uint32_t> values_;
};

}  // namespace quadcast::codegen
