// quadcast/codegen/generate.hpp -- the set of generated files, and their registry of kernels
#pragma once

#include <map>
#include <string>
#include <vector>

#include "quadcast/codegen/kernel.hpp"

namespace quadcast::codegen {

/// Every kernel the project emits, in a fixed order.
const std::vector<KernelDef>& registry();

/// Finds a kernel by name (without `qc_`); nullptr when unknown.
const KernelDef* find_kernel(const std::string& name);

/// Every generated file: path relative to generated/ -> exact contents.
/// Deterministic: no timestamps, no absolute paths, sorted by path.
std::map<std::string, std::string> generate_all();

}  // namespace quadcast::codegen
