// tests/gl/test_traced_kernels.cpp -- traced test kernels compute the CPU's bits on the GL
#include <doctest/doctest.h>

#include "codegen/test_kernels.hpp"
#include "quadcast/codegen/emit.hpp"
#include "quadcast/codegen/verify.hpp"
#include "quadcast/gl/compute.hpp"
#include "quadcast/gl/osmesa_context.hpp"

using namespace quadcast;

namespace {

codegen::Comparison run_on_gl(const codegen::KernelDef& k, std::size_t count) {
    gl::OsmesaContext ctx;
    const codegen::EmittedKernel e = codegen::emit_kernel(k);
    const std::string source = codegen::verify_compute_shader(e, k);
    const auto in = codegen::make_inputs(k, count, 42);
    const auto cpu = codegen::run_cpu(k, in, count);
    gl::ComputeRunner runner(ctx.api(), source, e.name);
    const auto gpu = runner.run(in, count, cpu.size());
    const codegen::Comparison c = codegen::compare(e.signature, in, cpu, gpu.output, count);
    INFO(c.first_report);
    return c;
}

}  // namespace

TEST_CASE("a traced kernel with selects, loops and sqrt is bit-identical on the GL") {
    const auto c = run_on_gl(codegen::make_kernel<test::MixedKernel>(), 200000);
    INFO(c.first_report);
    CHECK(c.identical == c.samples);
}

TEST_CASE("literal zeros rewritten by the tracer keep IEEE semantics on the GL") {
    const auto c = run_on_gl(codegen::make_kernel<test::ZeroLiteralKernel>(), 200000);
    INFO(c.first_report);
    CHECK(c.identical == c.samples);
}
