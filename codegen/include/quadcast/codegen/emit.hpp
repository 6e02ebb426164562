// quadcast/codegen/emit.hpp -- prints a traced kernel as a GLSL function and shader files
#pragma once

#include <set>
#include <string>
#include <string_view>

#include "quadcast/codegen/kernel.hpp"

namespace quadcast::codegen {

/// A traced kernel printed as GLSL.
struct EmittedKernel {
    std::string name;            ///< `qc_<name>`
    std::string function;        ///< the GLSL function definition
    std::set<std::string> ops;   ///< operations used (`+`, `sqrt`, `?:` ...), for banners and reports
    Signature signature;
    int statements = 0;          ///< number of temporaries (one operation each)
};

/// Traces `k` and prints it. Temporaries are numbered in the order a depth-first walk meets
/// them (outputs in declaration order, operands left to right), so the text does not depend on
/// the order in which the C++ compiler evaluated the kernel's sub-expressions.
EmittedKernel emit_kernel(const KernelDef& k);

/// GLSL spelling of a float literal that reads back to exactly `v`: a short decimal when that
/// decimal is the exact value, otherwise `uintBitsToFloat(0x...u) /* approx */`.
std::string glsl_float(float v);

/// The banner that heads every generated file.
std::string banner(const std::string& file, const std::string& source, const std::set<std::string>& ops, const std::string& summary);

/// A complete compute shader that runs `k` once per invocation over flat input words
/// (binding 0) and writes flat output words (binding 1): the verification harness.
std::string verify_compute_shader(const EmittedKernel& k, const KernelDef& def);

/// The same harness around `function`, the kernel's GLSL as the renderers embed it
/// (quadcast::generated::find), so that `quadcast verify` checks the text the stages use.
std::string verify_compute_shader(const EmittedKernel& k, const KernelDef& def, std::string_view function);

}  // namespace quadcast::codegen
