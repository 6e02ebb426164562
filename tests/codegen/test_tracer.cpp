// tests/codegen/test_tracer.cpp -- the tracer records faithfully, shares subexpressions and prints deterministically
#include <doctest/doctest.h>

#include <bit>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <array>
#include <random>
#include <stdexcept>
#include <string>

#include "quadcast/codegen/emit.hpp"
#include "quadcast/codegen/interpret.hpp"
#include "quadcast/linalg.hpp"
#include "codegen/test_kernels.hpp"

using namespace quadcast;
using namespace quadcast::codegen;
using quadcast::test::MixedKernel;
using quadcast::test::ZeroLiteralKernel;

namespace {

std::uint32_t random_word(std::mt19937& rng) {
    std::uniform_int_distribution<int> pick(0, 9);
    std::uniform_real_distribution<float> u(-2.0f, 2.0f);
    switch (pick(rng)) {
    case 0: return std::uniform_int_distribution<std::uint32_t>()(rng);  // any bit pattern
    case 1: return std::bit_cast<std::uint32_t>(std::numeric_limits<float>::denorm_min() * 7.0f);
    case 2: return std::bit_cast<std::uint32_t>(-0.0f);
    default: return std::bit_cast<std::uint32_t>(u(rng));
    }
}

bool same_word(std::uint32_t a, std::uint32_t b) {
    const float fa = std::bit_cast<float>(a), fb = std::bit_cast<float>(b);
    return a == b || (std::isnan(fa) && std::isnan(fb));
}

}  // namespace

TEST_CASE("commutative operands share one node whatever the evaluation order") {
    Recorder rec;
    Recording scope(rec);
    const Expr x = Expr::from_id(rec.input(Type::f32, "qc_x"));
    const Expr y = Expr::from_id(rec.input(Type::f32, "qc_y"));
    CHECK((x * y).id == (y * x).id);
    CHECK((x + y).id == (y + x).id);
    CHECK((x - y).id != (y - x).id);
    CHECK((x / y).id != (y / x).id);
    const std::size_t before = rec.size();
    (void)(x * y);
    CHECK(rec.size() == before);
}

TEST_CASE("constants fold in float and x + 0 is kept") {
    Recorder rec;
    Recording scope(rec);
    const Expr c = Expr(0.1) * Expr(3);
    CHECK(rec.node(c.id).op == Op::literal);
    CHECK(std::bit_cast<float>(rec.node(c.id).lit) == 0.1f * 3.0f);
    const Expr x = Expr::from_id(rec.input(Type::f32, "qc_x"));
    const Expr y = x + Expr(0);
    CHECK(y.id != x.id);  // -0 + 0 = +0, so x + 0 is not x
    CHECK(select(Mask(true), x, y).id == x.id);
}

TEST_CASE("a traced value used without a recorder is a clear error") {
    CHECK_THROWS_WITH_AS(Expr(1.0f), doctest::Contains("no live Recorder"), std::logic_error);
    Recorder rec;
    Recording scope(rec);
    Expr unset{};
    unset.id = 0;
    CHECK_THROWS_WITH_AS(unset + unset, doctest::Contains("unset"), std::logic_error);
}

TEST_CASE("the interpreted trace equals the float instantiation bit for bit") {
    const KernelDef k = make_kernel<MixedKernel>();
    TracedKernel traced(k);
    const int nin = traced.signature().input_words();
    const int nout = traced.signature().output_words();
    CHECK(nin == 7);
    CHECK(nout == 7);
    std::vector<std::uint32_t> in(nin), a(nout), b(nout);
    int mismatches = 0;
    for (int iter = 0; iter < 20000; ++iter) {
        std::mt19937 rng(1000u + iter);
        for (auto& w : in) w = random_word(rng);
        CpuIO io(in, a);
        k.cpu(io);
        traced.run(in, b);
        for (int i = 0; i < nout; ++i) mismatches += !same_word(a[i], b[i]);
    }
    CHECK(mismatches == 0);
}

TEST_CASE("emission does not depend on the order sub-expressions were created") {
    // Build the same function with opposite creation orders.
    auto build = [](bool flip) {
        Recorder rec;
        Recording scope(rec);
        TraceIO io(rec);
        const Expr x = io.scalar("x"), y = io.scalar("y");
        Expr p, q;
        if (flip) { q = y * y; p = x * x; } else { p = x * x; q = y * y; }
        io.out("r", (p + q) * (x * x));
        return io.output_nodes().size();
    };
    CHECK(build(false) == build(true));
    const KernelDef k = make_kernel<MixedKernel>();
    const EmittedKernel e1 = emit_kernel(k), e2 = emit_kernel(k);
    CHECK(e1.function == e2.function);
    CHECK(e1.function.find("precise float qc_t0 = ") != std::string::npos);
    CHECK(e1.ops.count("sqrt") == 1);
    // No GLSL built-in with CPU-different rounding appears.
    for (const char* banned : {"dot(", "length(", "normalize(", "inversesqrt(", "fma(", "pow(", "exp(", "log(", "sin(", "cos(", "mix(", "min(", "max(", "clamp("})
        CHECK_MESSAGE(e1.function.find(banned) == std::string::npos, banned);
}

TEST_CASE("float literals read back to exactly the same bits") {
    std::mt19937 rng(7);
    std::uniform_int_distribution<std::uint32_t> bits;
    for (int i = 0; i < 100000; ++i) {
        const std::uint32_t w = i < 8 ? std::bit_cast<std::uint32_t>(std::array<float, 8>{0.5f, 1.0f, -2.0f, 0.1f, 4097.0f, -0.0f, 1e-30f, 3.0e38f}[i]) : bits(rng);
        const float v = std::bit_cast<float>(w);
        const std::string s = glsl_float(v);
        std::uint32_t back = 0;
        if (s.rfind("uintBitsToFloat(0x", 0) == 0) {
            back = static_cast<std::uint32_t>(std::strtoul(s.c_str() + 18, nullptr, 16));
        } else {
            std::string t = s;
            if (t.front() == '(') t = t.substr(1, t.size() - 2);
            const double d = std::strtod(t.c_str(), nullptr);
            CHECK(d == static_cast<double>(v));  // the decimal is the exact value: no double rounding
            back = std::bit_cast<std::uint32_t>(static_cast<float>(d));
        }
        REQUIRE(back == w);
    }
    CHECK(glsl_float(0.5f) == "0.5");
    CHECK(glsl_float(2.0f) == "2.0");
    CHECK(glsl_float(-2.0f) == "(-2.0)");
    CHECK(glsl_float(0.1f) == "uintBitsToFloat(0x3DCCCCCDu) /* 0.100000001 */");
}

TEST_CASE("literal zeros never reach the GLSL text and keep IEEE semantics") {
    const KernelDef k = make_kernel<ZeroLiteralKernel>();
    const EmittedKernel e = emit_kernel(k);
    for (const char* bad : {"* 0.0", "+ 0.0", "- 0.0", "0.0 *", "0.0 +", "0.0 -", "0.0 /", "/ 0.0", "/* -0 */ *", "/* -0 */ -", "/* -0 */ +", "/* -0 */ /"})
        CHECK_MESSAGE(e.function.find(bad) == std::string::npos, bad);
    TracedKernel traced(k);
    const float special[] = {0.0f, -0.0f, 1.0f, -1.0f, std::numeric_limits<float>::infinity(), -std::numeric_limits<float>::infinity(),
                             std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::denorm_min(), -3.5e38f, 2.5f};
    std::vector<std::uint32_t> a(11), b(11);
    for (float v : special) {
        const std::uint32_t in[1] = {std::bit_cast<std::uint32_t>(v)};
        CpuIO io(in, a);
        k.cpu(io);
        traced.run(in, b);
        for (int i = 0; i < 11; ++i) CHECK_MESSAGE(same_word(a[i], b[i]), "x = " << v << ", output " << i);
    }
}
