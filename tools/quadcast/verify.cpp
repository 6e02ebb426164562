// tools/quadcast/verify.cpp -- `quadcast verify`: the generated kernels on this GL against the CPU
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <iostream>
#include <stdexcept>
#include <string>

#include "commands.hpp"
#include "quadcast/codegen/emit.hpp"
#include "quadcast/codegen/generate.hpp"
#include "quadcast/codegen/verify.hpp"
#include "quadcast/generated/shaders.hpp"
#include "quadcast/gl/compute.hpp"
#include "quadcast/gl/osmesa_context.hpp"

namespace quadcast::cli {

namespace {

struct VerifyOptions {
    std::size_t count = 1u << 20;
    std::uint64_t seed = 1;
    std::string kernel;
};

int run_verify(const VerifyOptions& opt) {
    std::unique_ptr<gl::OsmesaContext> ctx;
    try {
        ctx = std::make_unique<gl::OsmesaContext>();
    } catch (const std::exception& e) {
        std::cerr << "quadcast verify: " << e.what() << "\n";
        return 2;
    }
    std::cout << "quadcast verify: " << ctx->info().summary() << "\n";
    std::cout << "inputs per kernel: " << opt.count << " (seed " << opt.seed
              << "): structured, scaled 2^-40..2^40, adversarial (0, -0, Inf, NaN, subnormals), raw bits\n\n";
    std::printf("%-28s %9s %14s %9s %7s  %s\n", "kernel", "inputs", "bit-identical", "max ULP", "time s", "operations");
    int failures = 0, ran = 0;
    for (const codegen::KernelDef& k : codegen::registry()) {
        if (!opt.kernel.empty() && k.name != opt.kernel) continue;
        ++ran;
        const auto t0 = std::chrono::steady_clock::now();
        const std::string name = "qc_" + k.name;
        // The kernel text the renderers embed (quadcast::gl), checked against the templates, in
        // this command's own harness (no verification shaders in the renderers' library).
        const std::string_view embedded = generated::find(name);
        const codegen::EmittedKernel emitted = codegen::emit_kernel(k);
        if (embedded.empty() || embedded != emitted.function) {
            std::printf("%-28s  %s the generated shaders: run `make regenerate`\n", name.c_str(), embedded.empty() ? "not in" : "differs from");
            ++failures;
            continue;
        }
        const std::string source = codegen::verify_compute_shader(emitted, k, embedded);
        const auto inputs = codegen::make_inputs(k, opt.count, opt.seed);
        const auto expected = codegen::run_cpu(k, inputs, opt.count);
        gl::ComputeRunner runner(ctx->api(), source, name + ".verify.comp");
        // Runs in chunks when the buffers would exceed GL_MAX_SHADER_STORAGE_BLOCK_SIZE (kernels
        // with many inputs, e.g. the 56 values of an S31 determining set).
        const std::size_t nin = static_cast<std::size_t>(emitted.signature.input_words());
        const std::size_t nout = static_cast<std::size_t>(emitted.signature.output_words());
        const std::size_t per_sample = 4 * std::max<std::size_t>({nin, nout, 1});
        const std::size_t chunk = std::max<std::size_t>(1, std::min<std::size_t>(opt.count, runner.max_buffer_bytes() / per_sample));
        std::vector<std::uint32_t> gpu(expected.size());
        for (std::size_t first = 0; first < opt.count; first += chunk) {
            const std::size_t n = std::min(chunk, opt.count - first);
            runner.run_into(std::span<const std::uint32_t>(inputs).subspan(first * nin, n * nin), n,
                            std::span<std::uint32_t>(gpu).subspan(first * nout, n * nout));
        }
        const codegen::Comparison c = codegen::compare(emitted.signature, inputs, expected, gpu, opt.count);
        const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        std::string ops;
        for (const auto& o : emitted.ops) ops += (ops.empty() ? "" : " ") + o;
        char ulp[32];
        if (c.max_ulp == UINT64_MAX) std::snprintf(ulp, sizeof ulp, "NaN");
        else std::snprintf(ulp, sizeof ulp, "%llu", static_cast<unsigned long long>(c.max_ulp));
        std::printf("%-28s %9zu %13.4f%% %9s %7.2f  %s\n", name.c_str(), c.samples,
                    100.0 * static_cast<double>(c.identical) / static_cast<double>(c.samples), ulp, secs, ops.c_str());
        if (c.identical != c.samples) {
            ++failures;
            std::printf("  %zu samples differ (%zu mask differences); first: %s\n", c.samples - c.identical, c.mask_differences,
                        c.first_report.c_str());
        }
    }
    if (ran == 0 && !opt.kernel.empty()) {
        std::cerr << "quadcast verify: no kernel named \"" << opt.kernel << "\"\n";
        return 2;
    }
    std::printf("\n%d passed, %d failed\n", ran - failures, failures);
    return failures ? 1 : 0;
}

}  // namespace

void add_verify(CLI::App& app) {
    auto opt = std::make_shared<VerifyOptions>();
    CLI::App* cmd = app.add_subcommand("verify", "run every generated kernel on this machine's OpenGL and compare with the CPU bit by bit");
    cmd->add_option("--count", opt->count, "inputs per kernel")->check(CLI::Range(std::size_t{1}, std::size_t{1} << 26));
    cmd->add_option("--seed", opt->seed, "seed of the inputs");
    cmd->add_option("--kernel", opt->kernel, "only this kernel (name without qc_)");
    cmd->callback([opt] {
        const int rc = run_verify(*opt);
        if (rc) throw CLI::RuntimeError(rc);
    });
}

}  // namespace quadcast::cli
