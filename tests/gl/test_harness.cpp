// tests/gl/test_harness.cpp -- offscreen context, program errors, compute runner; GPU float ops vs CPU bits
#include "quadcast/gl/compute.hpp"
#include "quadcast/gl/egl_context.hpp"
#include "quadcast/gl/osmesa_context.hpp"
#include "quadcast/gl/program.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <bit>
#include <cstdio>
#include <functional>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <random>
#include <string>
#include <vector>

namespace {

using quadcast::gl::Api;
using quadcast::gl::ComputeRunner;
using quadcast::gl::OsmesaContext;

/// One OSMesa context for the whole executable, made current for each test.
OsmesaContext& context() {
    static OsmesaContext ctx;
    ctx.make_current();
    return ctx;
}

bool contains(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

float as_float(std::uint32_t u) { return std::bit_cast<float>(u); }
std::uint32_t as_bits(float f) { return std::bit_cast<std::uint32_t>(f); }
bool is_nan_bits(std::uint32_t u) { return (u & 0x7F800000u) == 0x7F800000u && (u & 0x007FFFFFu) != 0; }
/// Equal bits, or both NaN (payload and sign of NaN are not meaningful).
bool same_float(std::uint32_t gpu, std::uint32_t cpu) { return gpu == cpu || (is_nan_bits(gpu) && is_nan_bits(cpu)); }
bool is_subnormal_bits(std::uint32_t u) { return (u & 0x7F800000u) == 0 && (u & 0x007FFFFFu) != 0; }

/// Random float bit patterns that hit the hard cases: uniform bits (incl. NaN), subnormals,
/// specials, near-equal pairs (cancellation), moderate values, pairs whose product, quotient
/// or difference lands in the subnormal range.
void random_pair(std::mt19937& rng, std::uint32_t& a, std::uint32_t& b) {
    std::uniform_int_distribution<std::uint32_t> bits;
    auto sign = [&] { return bits(rng) & 0x80000000u; };
    auto mant = [&] { return bits(rng) & 0x007FFFFFu; };
    auto with_exp = [&](int lo, int hi) {  // biased exponent in [lo, hi]
        std::uniform_int_distribution<int> e(lo, hi);
        return sign() | (static_cast<std::uint32_t>(e(rng)) << 23) | mant();
    };
    static const std::uint32_t specials[] = {0x00000000u, 0x80000000u, 0x7F800000u, 0xFF800000u, 0x7FC00000u,
                                             0xFFC00000u, 0x7F800001u, 0x7FBFFFFFu, 0x7F7FFFFFu, 0xFF7FFFFFu,
                                             0x00800000u, 0x80800000u, 0x00000001u, 0x80000001u, 0x007FFFFFu,
                                             0x3F800000u, 0xBF800000u, 0x40000000u, 0x3F000000u};
    auto special = [&] { return specials[bits(rng) % (sizeof specials / sizeof specials[0])]; };
    switch (bits(rng) % 8) {
    case 0:
    case 1: a = bits(rng); b = bits(rng); break;  // uniform patterns
    case 2: a = sign() | mant(); b = (bits(rng) & 1) ? (sign() | mant()) : with_exp(1, 254); break;  // subnormals
    case 3: a = (bits(rng) & 1) ? special() : with_exp(0, 255); b = (bits(rng) & 1) ? special() : with_exp(0, 255); break;
    case 4: {  // near-equal: cancellation in a - b, a + (-b)
        a = with_exp(1, 254);
        std::int32_t d = static_cast<std::int32_t>(bits(rng) % 64) - 32;
        b = static_cast<std::uint32_t>(static_cast<std::int32_t>(a) + d);
        if (bits(rng) & 1) b ^= 0x80000000u;
        break;
    }
    case 5: a = with_exp(107, 147); b = with_exp(107, 147); break;  // |x| in [2^-20, 2^20]
    case 6: a = with_exp(1, 40); b = with_exp(100, 150); break;     // tiny*moderate, tiny/moderate
    default: a = with_exp(1, 3); b = with_exp(1, 3); break;          // differences of smallest normals
    }
}

/// The op kernel's outputs per invocation, in order.
enum Out : unsigned {
    kAdd, kSub, kMul, kDiv, kSqrt, kAbs, kNeg, kCmp, kTernary, kRecipSqrt, kMulAdd, kInverseSqrt, kMin, kMax,
    kCount
};
const char* const kOutName[kCount] = {"a + b",          "a - b",          "a * b",     "a / b",
                                      "sqrt(a)",        "abs(a)",         "-a",        "comparisons",
                                      "a < b ? a : b",  "1.0 / sqrt(a)",  "a * b + a", "inversesqrt(a)",
                                      "min(a, b)",      "max(a, b)"};

/// Every result is `precise`, as in generated kernels.
std::string op_kernel_source() {
    return ComputeRunner::prologue(64) + R"(
void main() {
    uint i;
    if (!qc_index(i)) return;
    float a = uintBitsToFloat(qc_in[2u * i]);
    float b = uintBitsToFloat(qc_in[2u * i + 1u]);
    uint o = i * 14u;
    precise float add = a + b, sub = a - b, mul = a * b, div = a / b, root = sqrt(a), absolute = abs(a);
    precise float neg = -a, ternary = a < b ? a : b, rsq = 1.0 / sqrt(a), muladd = a * b + a;
    precise float irsq = inversesqrt(a), lo = min(a, b), hi = max(a, b);
    qc_out[o + 0u] = floatBitsToUint(add);
    qc_out[o + 1u] = floatBitsToUint(sub);
    qc_out[o + 2u] = floatBitsToUint(mul);
    qc_out[o + 3u] = floatBitsToUint(div);
    qc_out[o + 4u] = floatBitsToUint(root);
    qc_out[o + 5u] = floatBitsToUint(absolute);
    qc_out[o + 6u] = floatBitsToUint(neg);
    qc_out[o + 7u] = (a < b ? 1u : 0u) | (a <= b ? 2u : 0u) | (a > b ? 4u : 0u) | (a >= b ? 8u : 0u)
                   | (a == b ? 16u : 0u) | (a != b ? 32u : 0u) | (isnan(a) ? 64u : 0u) | (isinf(a) ? 128u : 0u);
    qc_out[o + 8u] = floatBitsToUint(ternary);
    qc_out[o + 9u] = floatBitsToUint(rsq);
    qc_out[o + 10u] = floatBitsToUint(muladd);
    qc_out[o + 11u] = floatBitsToUint(irsq);
    qc_out[o + 12u] = floatBitsToUint(lo);
    qc_out[o + 13u] = floatBitsToUint(hi);
}
)";
}

/// The same operations on the CPU (built with -ffp-contract=off: a * b + a is two roundings).
void cpu_ops(float a, float b, std::uint32_t* out) {
    out[kAdd] = as_bits(a + b);
    out[kSub] = as_bits(a - b);
    out[kMul] = as_bits(a * b);
    out[kDiv] = as_bits(a / b);
    out[kSqrt] = as_bits(std::sqrt(a));
    out[kAbs] = as_bits(std::fabs(a));
    out[kNeg] = as_bits(-a);
    out[kCmp] = (a < b ? 1u : 0u) | (a <= b ? 2u : 0u) | (a > b ? 4u : 0u) | (a >= b ? 8u : 0u) |
                (a == b ? 16u : 0u) | (a != b ? 32u : 0u) | (std::isnan(a) ? 64u : 0u) | (std::isinf(a) ? 128u : 0u);
    out[kTernary] = as_bits(a < b ? a : b);
    out[kRecipSqrt] = as_bits(1.0f / std::sqrt(a));
    const float p = a * b;
    out[kMulAdd] = as_bits(p + a);
    out[kInverseSqrt] = as_bits(1.0f / std::sqrt(a));
    out[kMin] = as_bits(b < a ? b : a);  // GLSL min(x, y) = y < x ? y : x
    out[kMax] = as_bits(a < b ? b : a);  // GLSL max(x, y) = x < y ? y : x
}

}  // namespace

TEST_CASE("the OSMesa context is OpenGL 4.5 core on llvmpipe") {
    OsmesaContext& ctx = context();
    const auto& info = ctx.info();
    MESSAGE("context: ", info.summary(), "; GLSL ", info.glsl);
    CHECK(info.major * 10 + info.minor >= 45);
    CHECK(info.core_profile);
    CHECK(contains(info.renderer, "llvmpipe"));
    CHECK(ctx.is_current());
    CHECK(ctx.api().version() == info.major * 10 + info.minor);
    CHECK(ctx.api().has_gl45());
    CHECK((ctx.api().CreateBuffers != nullptr));
    CHECK((ctx.api().BindTextureUnit != nullptr));
    CHECK(ctx.api().GetError() == GL_NO_ERROR);
}

TEST_CASE("a context request below OpenGL 4.5 is refused before any context is made") {
    OsmesaContext::Options o;
    o.min_minor = 3;
    CHECK_THROWS_WITH_AS(OsmesaContext{o}, doctest::Contains("request OpenGL 4.5 or later"), std::invalid_argument);
    quadcast::gl::EglContext::Options e;
    e.minor = 4;
    CHECK_THROWS_WITH_AS(quadcast::gl::EglContext{e}, doctest::Contains("request OpenGL 4.5 or later"), std::invalid_argument);
}

TEST_CASE("a resolver missing one entry point gives an error naming that function") {
    context();
    quadcast::gl::Resolver without = [](const char* name) -> void* {
        if (std::strcmp(name, "glDispatchCompute") == 0) return nullptr;
        return OsmesaContext::get_proc_address(name);
    };
    try {
        (void)Api::load(without);
        FAIL("load() accepted a resolver without glDispatchCompute");
    } catch (const quadcast::gl::MissingEntryPoints& e) {
        REQUIRE(e.names().size() == 1);
        CHECK(e.names()[0] == "glDispatchCompute");
        CHECK(contains(e.what(), "does not provide glDispatchCompute"));
    }
    // A 4.5 function is required once the context reports 4.5.
    if (context().api().has_gl45()) {
        quadcast::gl::Resolver without45 = [](const char* name) -> void* {
            if (std::strcmp(name, "glCreateBuffers") == 0) return nullptr;
            return OsmesaContext::get_proc_address(name);
        };
        CHECK_THROWS_WITH_AS(Api::load(without45), doctest::Contains("glCreateBuffers"),
                             quadcast::gl::MissingEntryPoints);
    }
    // The full resolver loads.
    CHECK_NOTHROW(Api::load(OsmesaContext::get_proc_address));
}

TEST_CASE("a shader compile error quotes the offending line with its number and the shader's name") {
    const Api& gl = context().api();
    const std::string source =
        "#version 430 core\n"                          // 1
        "layout(local_size_x = 1) in;\n"               // 2
        "layout(std430, binding = 1) buffer O { uint o[]; };\n"  // 3
        "void main() {\n"                              // 4
        "    uint x = 3u +* 4u;\n"                     // 5: syntax error
        "    o[0] = x;\n"                              // 6
        "}\n";
    try {
        (void)quadcast::gl::make_compute_program(gl, source, "broken_kernel");
        FAIL("a shader with a syntax error compiled");
    } catch (const quadcast::gl::ShaderCompileError& e) {
        const std::string what = e.what();
        MESSAGE("compile error message:\n", what);
        CHECK(e.name() == "broken_kernel");
        CHECK(e.stage() == GL_COMPUTE_SHADER);
        CHECK(contains(what, "broken_kernel"));
        CHECK(contains(what, "compute shader"));
        CHECK(contains(what, e.log()));
        CHECK(contains(what, ">     5 |     uint x = 3u +* 4u;"));  // quoted, numbered, marked
        CHECK(contains(what, "      4 | void main() {"));           // with a line of context
        bool names_line5 = false;
        for (const auto& d : e.diagnostics()) names_line5 = names_line5 || (d.error && d.line == 5);
        CHECK(names_line5);
    }
    CHECK(gl.GetError() == GL_NO_ERROR);
}

TEST_CASE("an undeclared identifier is reported on its own line") {
    const Api& gl = context().api();
    const std::string prologue = ComputeRunner::prologue(64);
    const int bad_line = static_cast<int>(std::count(prologue.begin(), prologue.end(), '\n')) + 4;
    const std::string source = prologue +
                               "void main() {\n"
                               "    uint i;\n"
                               "    if (!qc_index(i)) return;\n"
                               "    qc_out[i] = undeclared_thing;\n"  // bad_line
                               "}\n";
    char expected[64];
    std::snprintf(expected, sizeof expected, ">%6d |     qc_out[i] = undeclared_thing;", bad_line);
    CHECK_THROWS_WITH_AS(quadcast::gl::make_compute_program(gl, source, "undeclared"), doctest::Contains(expected),
                         quadcast::gl::ShaderCompileError);
}

TEST_CASE("info logs of Mesa, NVIDIA and glslang name their source lines") {
    using quadcast::gl::parse_info_log;
    auto mesa = parse_info_log("0:7(12): error: syntax error, unexpected '*'\n0:9(1): warning: unused\n");
    REQUIRE(mesa.size() == 2);
    CHECK(mesa[0].line == 7);
    CHECK(mesa[0].column == 12);
    CHECK(mesa[0].error);
    CHECK(mesa[1].line == 9);
    CHECK_FALSE(mesa[1].error);
    auto nv = parse_info_log("0(23) : error C1008: undefined variable \"x\"");
    REQUIRE(nv.size() == 1);
    CHECK(nv[0].line == 23);
    auto gs = parse_info_log("ERROR: 0:4: 'x' : undeclared identifier\nERROR: 1 compilation errors.");
    REQUIRE(gs.size() == 1);
    CHECK(gs[0].line == 4);
    CHECK(parse_info_log("some free text\n").empty());
    CHECK(quadcast::gl::quote_source_lines("a\nb\nc\nd\ne\nf\ng", {2, 6}, 1) ==
          "      1 | a\n>     2 | b\n      3 | c\n        ...\n      5 | e\n>     6 | f\n      7 | g\n");
    CHECK(contains(quadcast::gl::quote_source_lines("a\nb", {9}, 1), "line 9 is past the end"));
}

TEST_CASE("precise float + - * / sqrt, abs, negation, comparisons and ?: in compute shaders match the CPU bit for bit") {
    const Api& gl = context().api();
    ComputeRunner runner(gl, op_kernel_source(), "float_ops");
    constexpr std::size_t n = std::size_t{1} << 20;
    std::vector<std::uint32_t> in(2 * n);
    std::mt19937 rng(20240611u);
    for (std::size_t i = 0; i < n; ++i) random_pair(rng, in[2 * i], in[2 * i + 1]);

    const auto result = runner.run(in, n, n * kCount);
    MESSAGE("float_ops: ", n, " invocations, upload ", result.timing.upload_s, " s, dispatch ", result.timing.dispatch_s,
            " s, readback ", result.timing.readback_s, " s");

    std::size_t mismatch[kCount] = {};
    std::size_t first_bad[kCount];
    std::size_t subnormal_results = 0, subnormal_kept = 0, subnormal_inputs = 0;
    for (std::size_t i = 0; i < n; ++i) {
        std::uint32_t cpu[kCount];
        const float a = as_float(in[2 * i]), b = as_float(in[2 * i + 1]);
        cpu_ops(a, b, cpu);
        subnormal_inputs += is_subnormal_bits(in[2 * i]) ? 1 : 0;
        for (unsigned k = 0; k < kCount; ++k) {
            const std::uint32_t g = result.output[i * kCount + k];
            const bool ok = (k == kCmp) ? g == cpu[k] : same_float(g, cpu[k]);
            if (!ok && mismatch[k]++ == 0) first_bad[k] = i;
            if (k <= kDiv && is_subnormal_bits(cpu[k])) {
                ++subnormal_results;
                subnormal_kept += (g == cpu[k]) ? 1 : 0;
            }
        }
    }
    for (unsigned k = 0; k < kCount; ++k) {
        std::string line = std::string(kOutName[k]) + ": " + std::to_string(mismatch[k]) + " of " + std::to_string(n) +
                           " differ";
        if (mismatch[k] != 0) {
            const std::size_t i = first_bad[k];
            char buf[160];
            std::snprintf(buf, sizeof buf, " (first: a=0x%08X b=0x%08X gpu=0x%08X cpu=0x%08X)", in[2 * i],
                          in[2 * i + 1], result.output[i * kCount + k],
                          [&] {
                              std::uint32_t c[kCount];
                              cpu_ops(as_float(in[2 * i]), as_float(in[2 * i + 1]), c);
                              return c[k];
                          }());
            line += buf;
        }
        MESSAGE(line);
    }
    MESSAGE("subnormal inputs a: ", subnormal_inputs, "; subnormal results of + - * /: ", subnormal_results,
            ", identical on the GPU: ", subnormal_kept);

    // The operations the shared templates may use are exact (correctly rounded) on llvmpipe.
    for (unsigned k : {kAdd, kSub, kMul, kDiv, kSqrt, kAbs, kNeg, kCmp, kTernary, kRecipSqrt, kMulAdd}) {
        INFO(std::string(kOutName[k]));
        CHECK(mismatch[k] == 0);
    }
    // Compute shaders keep subnormals (the inputs hit that range often).
    CHECK(subnormal_inputs > n / 20);
    CHECK(subnormal_results > n / 100);
    CHECK(subnormal_kept == subnormal_results);
}

TEST_CASE("precise stops Mesa's value-changing rewrites; literal zeros are folded regardless") {
    // Without `precise`, Mesa's NIR applies "inexact" algebraic rules: a - a -> 0,
    // (a + b) - b -> a, a*b + a*c -> a*(b + c), 1/(1/a) -> a, a < b ? a : b -> min(a, b) (which
    // differs for NaN and for -0 vs +0), a < 0 ? -a : a -> abs(a). `precise` disables them all.
    // Literal zeros are folded even under `precise` (a * 0.0 -> 0 for inf/NaN/negative a,
    // a + 0.0 -> a for a = -0, 0.0 - a -> -a for a = +0): emitted code must not multiply or add
    // literal zeros (fold them in the tracer, or pass the constant in a buffer).
    struct Pattern {
        const char* glsl;
        std::function<float(float, float, float)> cpu;
        bool exact_when_precise;
    };
    const std::vector<Pattern> patterns = {
        {"a - a", [](float a, float, float) { return a - a; }, true},
        {"(a + b) - b", [](float a, float b, float) { return (a + b) - b; }, true},
        {"a * b + a * c", [](float a, float b, float c) { const float x = a * b, y = a * c; return x + y; }, true},
        {"1.0 / (1.0 / a)", [](float a, float, float) { return 1.0f / (1.0f / a); }, true},
        {"a < b ? a : b", [](float a, float b, float) { return a < b ? a : b; }, true},
        {"a <= b ? b : a", [](float a, float b, float) { return a <= b ? b : a; }, true},
        {"a < 0.0 ? -a : a", [](float a, float, float) { return a < 0.0f ? -a : a; }, true},
        {"sqrt(a >= 0.0 ? a : 0.0)", [](float a, float, float) { return std::sqrt(a >= 0.0f ? a : 0.0f); }, true},
        {"(a + b) + c", [](float a, float b, float c) { return (a + b) + c; }, true},
        {"a * b - c", [](float a, float b, float c) { const float x = a * b; return x - c; }, true},
        {"a * 1.0 - 0.0", [](float a, float, float) { return a * 1.0f - 0.0f; }, true},
        {"a * 0.0", [](float a, float, float) { return a * 0.0f; }, false},
        {"a + 0.0", [](float a, float, float) { return a + 0.0f; }, false},
        {"0.0 - a", [](float a, float, float) { return 0.0f - a; }, false},
    };
    const Api& gl = context().api();
    constexpr std::size_t n = std::size_t{1} << 17;
    std::vector<std::uint32_t> in(3 * n);
    std::mt19937 rng(99u);
    for (std::size_t i = 0; i < n; ++i) {
        random_pair(rng, in[3 * i], in[3 * i + 1]);
        std::uint32_t c, unused;
        random_pair(rng, c, unused);
        in[3 * i + 2] = c;
    }
    for (const Pattern& pat : patterns) {
        std::size_t bad[2] = {0, 0};
        for (int precise = 0; precise < 2; ++precise) {
            const std::string src = ComputeRunner::prologue(64) +
                                    "void main() { uint i; if (!qc_index(i)) return;\n"
                                    "    float a = uintBitsToFloat(qc_in[3u * i]), b = uintBitsToFloat(qc_in[3u * i + 1u]),"
                                    " c = uintBitsToFloat(qc_in[3u * i + 2u]);\n    " +
                                    (precise ? "precise " : "") + "float r = " + pat.glsl +
                                    ";\n    qc_out[i] = floatBitsToUint(r);\n}\n";
            ComputeRunner runner(gl, src, pat.glsl);
            const auto r = runner.run(in, n, n);
            for (std::size_t i = 0; i < n; ++i) {
                const float cpu = pat.cpu(as_float(in[3 * i]), as_float(in[3 * i + 1]), as_float(in[3 * i + 2]));
                bad[precise] += same_float(r.output[i], as_bits(cpu)) ? 0 : 1;
            }
        }
        MESSAGE(std::string(pat.glsl), ": ", bad[0], " plain / ", bad[1], " precise of ", n, " differ from the CPU");
        if (pat.exact_when_precise) {
            INFO(std::string(pat.glsl));
            CHECK(bad[1] == 0);
        }
    }
}

TEST_CASE("4M invocations of a trivial kernel are split over dispatches, computed and read back") {
    const Api& gl = context().api();
    ComputeRunner runner(gl,
                         ComputeRunner::prologue(64) +
                             "void main() { uint i; if (!qc_index(i)) return; qc_out[i] = qc_in[i] * 3u + i; }\n",
                         "trivial");
    constexpr std::size_t n = std::size_t{1} << 22;  // 64 more than 65535 groups of 64
    std::vector<std::uint32_t> in(n);
    std::mt19937 rng(7u);
    for (auto& w : in) w = rng();
    // Ask for one word more than invocations: the runner zeroes the output before the run.
    const auto first = runner.run(in, n, n + 1);  // includes llvmpipe's shader JIT
    for (std::size_t i = 0; i < n; i += 4099) in[i] ^= 0x5u;
    const auto r = runner.run(in, n, n + 1);
    const std::uint64_t groups = (n + runner.local_size_x() - 1) / runner.local_size_x();
    CHECK(r.timing.dispatches ==
          static_cast<int>((groups + runner.max_groups_per_dispatch() - 1) / runner.max_groups_per_dispatch()));
    std::size_t bad = 0;
    for (std::size_t i = 0; i < n; ++i) bad += (r.output[i] != in[i] * 3u + static_cast<std::uint32_t>(i)) ? 1 : 0;
    CHECK(bad == 0);
    MESSAGE("first run (with JIT): dispatch+finish ", first.timing.dispatch_s, " s");
    CHECK(r.output[n] == 0u);
    MESSAGE("trivial kernel, ", n, " invocations in ", r.timing.dispatches, " dispatches (max ",
            runner.max_groups_per_dispatch(), " groups of ", runner.local_size_x(), "): upload ", r.timing.upload_s,
            " s, dispatch+finish ", r.timing.dispatch_s, " s (GL_TIME_ELAPSED ", r.timing.gpu_s, " s), readback ",
            r.timing.readback_s, " s");
}

TEST_CASE("the runner offsets every dispatch and leaves no GL state bound") {
    const Api& gl = context().api();
    ComputeRunner runner(gl,
                         ComputeRunner::prologue(1) +
                             "void main() { uint i; if (!qc_index(i)) return; qc_out[i] = i ^ qc_in[0]; }\n",
                         "offsets");
    const std::uint64_t per = runner.max_groups_per_dispatch();
    const std::size_t n = static_cast<std::size_t>(2 * per + 17);  // three dispatches, the last partial
    const std::uint32_t key[] = {0xA5A5A5A5u};
    const auto r = runner.run(key, n, n + 3);
    CHECK(r.timing.dispatches == 3);
    std::size_t bad = 0;
    for (std::size_t i = 0; i < n; ++i) bad += (r.output[i] != (static_cast<std::uint32_t>(i) ^ key[0])) ? 1 : 0;
    CHECK(bad == 0);
    CHECK(r.output[n] == 0u);
    CHECK(r.output[n + 2] == 0u);
    // Runs reuse (and grow) the buffers; a second, smaller run sees fresh zeros.
    const auto r2 = runner.run(key, 5, 8);
    CHECK(r2.output[4] == (4u ^ key[0]));
    CHECK(r2.output[5] == 0u);

    CHECK(quadcast::gl::get_integer(gl, GL_CURRENT_PROGRAM) == 0);
    CHECK(quadcast::gl::get_integer(gl, GL_SHADER_STORAGE_BUFFER_BINDING) == 0);
    for (GLuint slot : {0u, 1u}) {
        GLint bound = -1;
        gl.GetIntegeri_v(GL_SHADER_STORAGE_BUFFER_BINDING, slot, &bound);
        CHECK(bound == 0);
    }
    CHECK(gl.GetError() == GL_NO_ERROR);
}

TEST_CASE("a kernel without qc_offset is refused when one dispatch is not enough") {
    const Api& gl = context().api();
    ComputeRunner runner(gl,
                         "#version 430 core\nlayout(local_size_x = 1) in;\n"
                         "layout(std430, binding = 1) writeonly buffer O { uint o[]; };\n"
                         "void main() { o[gl_GlobalInvocationID.x] = 1u; }\n",
                         "no_offset");
    const std::uint64_t too_many = std::uint64_t{runner.max_groups_per_dispatch()} + 1;
    CHECK_THROWS_WITH_AS(runner.run({}, too_many, 4), doctest::Contains("qc_offset"), std::runtime_error);
    const auto r = runner.run({}, 3, 4);  // one dispatch is fine
    CHECK(r.output == std::vector<std::uint32_t>{1u, 1u, 1u, 0u});
}

TEST_CASE("an EGL surfaceless context, where available, is also OpenGL 4.5 core and runs compute") {
    if (!quadcast::gl::EglContext::available()) {
        MESSAGE("EGL surfaceless not available here; skipped");
        return;
    }
    {
        quadcast::gl::EglContext egl;
        MESSAGE("EGL context: ", egl.info().summary());
        CHECK(egl.info().major * 10 + egl.info().minor >= 45);
        CHECK(egl.info().core_profile);
        CHECK(egl.is_current());
        ComputeRunner runner(egl.api(),
                             ComputeRunner::prologue(64) +
                                 "void main() { uint i; if (!qc_index(i)) return;"
                                 " qc_out[i] = floatBitsToUint(uintBitsToFloat(qc_in[i]) * 3.0); }\n",
                             "egl_mul");
        std::vector<std::uint32_t> in(1000);
        std::mt19937 rng(3u);
        for (auto& w : in) w = rng();
        const auto r = runner.run(in, in.size(), in.size());
        std::size_t bad = 0;
        for (std::size_t i = 0; i < in.size(); ++i) bad += same_float(r.output[i], as_bits(as_float(in[i]) * 3.0f)) ? 0 : 1;
        CHECK(bad == 0);
    }
    // The OSMesa context still works after the EGL one is gone.
    const Api& gl = context().api();
    CHECK(quadcast::gl::get_integer(gl, GL_MAJOR_VERSION) >= 4);
    CHECK(gl.GetError() == GL_NO_ERROR);
}
