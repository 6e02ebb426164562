// tests/codegen/test_kernels.hpp -- small kernels that exercise the tracer (CPU and GPU tests)
#pragma once

#include "quadcast/codegen/kernel.hpp"
#include "quadcast/linalg.hpp"

namespace quadcast::test {

// A small kernel with every kind of operation: selects, comparisons, sqrt, division, a loop.
struct MixedKernel {
    static constexpr const char* name = "test_mixed";
    static constexpr const char* source = "tests/codegen/test_tracer.cpp";
    static constexpr const char* summary = "tracer test kernel";
    template <class IO>
    static void run(IO& io) {
        using T = typename IO::T;
        const Vec3<T> a = io.template vec<3>("a");
        const Vec3<T> b = io.template vec<3>("b");
        const T s = io.scalar("s");
        const T d = dot(a, b);
        const auto pos = d > T(0);
        T acc = s;
        for (int i = 0; i < 4; ++i) acc = acc * T(0.5) + select(pos, d, -d);  // unrolls
        const T r = sqrt(select(pos, d, T(0))) / (abs(s) + T(0.1));
        io.out("acc", acc);
        io.out("r", r);
        io.out("c", cross(a, b));
        io.out("hit", pos && isfinite(r));
        io.out("m", min(d, s));
    }
};

// Arithmetic with literal +-0 in every position (GLSL compilers fold these even when precise).
struct ZeroLiteralKernel {
    static constexpr const char* name = "test_zero_literals";
    static constexpr const char* source = "tests/codegen/test_tracer.cpp";
    static constexpr const char* summary = "tracer test kernel: literal zeros";
    template <class IO>
    static void run(IO& io) {
        using T = typename IO::T;
        const T x = io.scalar("x");
        io.out("a", x * T(0));
        io.out("b", T(-0.0) * x);
        io.out("c", x + T(0));
        io.out("d", T(0) - x);
        io.out("e", x - T(-0.0));
        io.out("f", T(0) / x);
        io.out("g", T(-0.0) / x);
        io.out("h", x + T(-0.0));
        io.out("i", x - T(0));
        io.out("j", T(-0.0) - x);
        io.out("k", dot(vec4(x, x, x, T(0)), vec4(x, T(1), x, x)));  // a homogeneous direction
    }
};


}  // namespace quadcast::test
