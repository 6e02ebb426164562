// codegen/src/stage_builder.hpp -- assembling a stage shader around traced kernels (internal to the generator)
#pragma once

#include <set>
#include <sstream>
#include <stdexcept>
#include <string>

#include "quadcast/codegen/emit.hpp"
#include "quadcast/codegen/generate.hpp"
#include "quadcast/codegen/stages.hpp"

namespace quadcast::codegen::detail {

/// A stage shader under construction: the traced functions it calls, the operations they use and
/// the C++ templates they come from (for the banner).
struct Stage {
    std::string text;
    std::set<std::string> ops;
    std::string sources;
};

/// The registered kernel `name`; a stage needing an unregistered kernel is a generator bug.
inline const KernelDef& stage_kernel(const std::string& name) {
    const KernelDef* k = find_kernel(name);
    if (!k) throw std::logic_error("quadcast::codegen: stage shader needs unregistered kernel " + name);
    return *k;
}

/// Emits kernel `name` into `fns` and records its operations and source in `s`.
inline void add_kernel(Stage& s, std::ostringstream& fns, const std::string& name) {
    const KernelDef& k = stage_kernel(name);
    const EmittedKernel e = emit_kernel(k);
    fns << e.function << "\n";
    s.ops.insert(e.ops.begin(), e.ops.end());
    s.sources += (s.sources.empty() ? "" : "; ") + k.source;
}

/// The complete file of stage `s` under glsl/render/: version line, banner, text.
inline StageShader stage_file(const std::string& name, const Stage& s, const std::string& summary) {
    const std::string path = "glsl/render/" + name;
    return {name, path, "#version 450 core\n" + banner(path, s.sources, s.ops, summary) + "\n" + s.text};
}

}  // namespace quadcast::codegen::detail
