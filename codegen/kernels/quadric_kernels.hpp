// codegen/kernels/quadric_kernels.hpp -- kernels traced from quadcast/quadric.hpp
#pragma once

#include "kernels/common.hpp"
#include "quadcast/quadric.hpp"

namespace quadcast::codegen::kernels {

struct QuadricEvaluate {
    static constexpr const char* name = "quadric_evaluate";
    static constexpr const char* source = "quadcast::evaluate (quadcast/quadric.hpp)";
    static constexpr const char* summary = "f(x) = x~^T Q x~ (Stoll et al. 2006, eq. 4)";
    template <class IO> static void run(IO& io) {
        using T = typename IO::T;
        const Quadric<T> q{io.template mat<4>("q")};
        const Vec3<T> x = io.template vec<3>("x");
        io.out("f", evaluate(q, x));
    }
    static void generate(std::mt19937& rng, std::span<float> in) {
        std::size_t p = 0;
        put(in, p, random_quadric(rng));
        put(in, p, random_point(rng, 4.0f));
    }
};

struct QuadricHalfGradient {
    static constexpr const char* name = "quadric_half_gradient";
    static constexpr const char* source = "quadcast::half_gradient (quadcast/quadric.hpp)";
    static constexpr const char* summary = "A x + b, the normal direction (Stoll et al. 2006, eq. 11)";
    template <class IO> static void run(IO& io) {
        using T = typename IO::T;
        const Quadric<T> q{io.template mat<4>("q")};
        const Vec3<T> x = io.template vec<3>("x");
        io.out("n", half_gradient(q, x));
    }
    static void generate(std::mt19937& rng, std::span<float> in) { QuadricEvaluate::generate(rng, in); }
};

struct QuadricTransform {
    static constexpr const char* name = "quadric_transform";
    static constexpr const char* source = "quadcast::transform_with_inverse (quadcast/quadric.hpp)";
    static constexpr const char* summary = "Q' = M^-T Q M^-1 given M^-1 (Sigg et al. 2006, sec. 3.1)";
    template <class IO> static void run(IO& io) {
        using T = typename IO::T;
        const Quadric<T> q{io.template mat<4>("q")};
        const Mat4<T> m_inv = io.template mat<4>("m_inv");
        io.out("q_new", transform_with_inverse(q, m_inv).q);
    }
    static void generate(std::mt19937& rng, std::span<float> in) {
        std::size_t p = 0;
        put(in, p, random_quadric(rng));
        Mat4<float> m = identity<float, 4>();
        for (int j = 0; j < 3; ++j) for (int i = 0; i < 3; ++i) m[j][i] = uniform(rng, -2.0f, 2.0f);
        m[3] = vec4(random_point(rng, 10.0f), 1.0f);
        put(in, p, m);
    }
};

struct QuadricToEye {
    static constexpr const char* name = "quadric_to_eye";
    static constexpr const char* source = "quadcast::translate_to_eye (quadcast/quadric.hpp)";
    static constexpr const char* summary = "the quadric with the eye at the origin (Stoll et al. 2006, eq. 9)";
    template <class IO> static void run(IO& io) {
        using T = typename IO::T;
        const Quadric<T> q{io.template mat<4>("q")};
        const Vec3<T> e = io.template vec<3>("eye");
        io.out("q_eye", translate_to_eye(q, e).q);
    }
    static void generate(std::mt19937& rng, std::span<float> in) {
        std::size_t p = 0;
        put(in, p, random_quadric(rng));
        put(in, p, random_point(rng, std::ldexp(1.0f, std::uniform_int_distribution<int>(0, 20)(rng))));
    }
};

}  // namespace quadcast::codegen::kernels
