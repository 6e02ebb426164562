// quadcast/codegen/kernel.hpp -- one kernel definition drives tracing, CPU evaluation and verification
#pragma once

#include <bit>
#include <cstdint>
#include <random>
#include <span>
#include <string>
#include <vector>

#include "quadcast/codegen/expr.hpp"
#include "quadcast/linalg.hpp"

namespace quadcast::codegen {

/// GLSL type of a kernel parameter.
enum class Kind : std::uint8_t { f32, vec2, vec3, vec4, mat3, mat4, boolean };

/// Number of scalar components of a kind.
int components(Kind k);
/// GLSL spelling (`float`, `vec3`, `mat4`, `bool`).
const char* glsl_type(Kind k);

/// A named parameter; emitted as `qc_<name>`.
struct Param {
    std::string name;
    Kind kind;
};

/// Declared inputs and outputs of a kernel, in declaration order. Flat order of the scalar
/// components: vectors x, y, z, w; matrices column by column (`m[0][0], m[0][1], ...`).
struct Signature {
    std::vector<Param> inputs, outputs;
    int input_words() const;
    int output_words() const;
};

/// Kernel I/O for tracing: inputs become named parameter nodes, outputs are recorded.
class TraceIO {
public:
    using T = Expr;
    explicit TraceIO(Recorder& r) : rec_(r) {}

    Expr scalar(const std::string& name);
    template <int N> Vec<Expr, N> vec(const std::string& name);
    template <int N> Mat<Expr, N, N> mat(const std::string& name);

    void out(const std::string& name, const Expr& v) { add_out(name, Kind::f32, {v.id}); }
    void out(const std::string& name, const Mask& m) { add_out(name, Kind::boolean, {m.id}); }
    template <int N> void out(const std::string& name, const Vec<Expr, N>& v);
    template <int N> void out(const std::string& name, const Mat<Expr, N, N>& m);

    const Signature& signature() const { return sig_; }
    /// Node ids of every output component, flat, in declaration order.
    const std::vector<std::uint32_t>& output_nodes() const { return out_nodes_; }
    Recorder& recorder() { return rec_; }

private:
    void add_out(const std::string& name, Kind k, std::initializer_list<std::uint32_t> ids);
    void add_out_v(const std::string& name, Kind k, const std::vector<std::uint32_t>& ids);
    Recorder& rec_;
    Signature sig_;
    std::vector<std::uint32_t> out_nodes_;
};

/// Kernel I/O on the CPU in float: reads flat input words, writes flat output words
/// (float bits, or 0/1 for masks), exactly as the verification compute shader does.
class CpuIO {
public:
    using T = float;
    CpuIO(std::span<const std::uint32_t> in, std::span<std::uint32_t> out) : in_(in), out_(out) {}

    float scalar(const std::string&) { return next(); }
    template <int N> Vec<float, N> vec(const std::string&) { Vec<float, N> v{}; for (int i = 0; i < N; ++i) v[i] = next(); return v; }
    template <int N> Mat<float, N, N> mat(const std::string&) { Mat<float, N, N> m{}; for (int j = 0; j < N; ++j) m[j] = vec<N>(""); return m; }

    void out(const std::string&, float v) { put(std::bit_cast<std::uint32_t>(v)); }
    void out(const std::string&, bool m) { put(m ? 1u : 0u); }
    template <int N> void out(const std::string&, const Vec<float, N>& v) { for (int i = 0; i < N; ++i) out("", v[i]); }
    template <int N> void out(const std::string&, const Mat<float, N, N>& m) { for (int j = 0; j < N; ++j) out("", m[j]); }

private:
    float next() { return std::bit_cast<float>(in_[pos_in_++]); }
    void put(std::uint32_t w) { out_[pos_out_++] = w; }
    std::span<const std::uint32_t> in_;
    std::span<std::uint32_t> out_;
    std::size_t pos_in_ = 0, pos_out_ = 0;
};

/// Draws one structured input (flat float words) for a kernel: configurations that exercise
/// its meaningful regime (rays that hit, grazing rays, near-degenerate quads ...).
using Generator = void (*)(std::mt19937& rng, std::span<float> inputs);

/// A registered kernel: the GLSL function `qc_<name>` traced from `source`, and its CPU twin.
struct KernelDef {
    std::string name;       ///< GLSL function name without the `qc_` prefix
    std::string source;     ///< the template it instantiates, e.g. `quadcast::ray_coefficients (quadcast/ray.hpp)`
    std::string summary;    ///< one line for banners and reports
    void (*trace)(TraceIO&);
    void (*cpu)(CpuIO&);
    Generator generate = nullptr;
};

/// Builds a KernelDef from a functor with `name`, `source`, `summary` and
/// `template <class IO> static void run(IO&)` (and optionally `static void generate(...)`).
template <class K>
KernelDef make_kernel() {
    KernelDef d{K::name, K::source, K::summary, &K::template run<TraceIO>, &K::template run<CpuIO>, nullptr};
    if constexpr (requires { &K::generate; }) d.generate = &K::generate;
    return d;
}

// Template definitions --------------------------------------------------------------------------

template <int N>
Vec<Expr, N> TraceIO::vec(const std::string& name) {
    static const char* comp = "xyzw";
    const Kind k = N == 2 ? Kind::vec2 : N == 3 ? Kind::vec3 : Kind::vec4;
    sig_.inputs.push_back({name, k});
    Vec<Expr, N> v{};
    for (int i = 0; i < N; ++i) v[i] = Expr::from_id(rec_.input(Type::f32, "qc_" + name + "." + comp[i]));
    return v;
}

template <int N>
Mat<Expr, N, N> TraceIO::mat(const std::string& name) {
    static_assert(N == 3 || N == 4);
    sig_.inputs.push_back({name, N == 3 ? Kind::mat3 : Kind::mat4});
    Mat<Expr, N, N> m{};
    for (int j = 0; j < N; ++j)
        for (int i = 0; i < N; ++i)
            m[j][i] = Expr::from_id(rec_.input(Type::f32, "qc_" + name + "[" + std::to_string(j) + "][" + std::to_string(i) + "]"));
    return m;
}

template <int N>
void TraceIO::out(const std::string& name, const Vec<Expr, N>& v) {
    std::vector<std::uint32_t> ids;
    for (int i = 0; i < N; ++i) ids.push_back(v[i].id);
    add_out_v(name, N == 2 ? Kind::vec2 : N == 3 ? Kind::vec3 : Kind::vec4, ids);
}

template <int N>
void TraceIO::out(const std::string& name, const Mat<Expr, N, N>& m) {
    std::vector<std::uint32_t> ids;
    for (int j = 0; j < N; ++j) for (int i = 0; i < N; ++i) ids.push_back(m[j][i].id);
    add_out_v(name, N == 3 ? Kind::mat3 : Kind::mat4, ids);
}

}  // namespace quadcast::codegen
