// quadcast/codegen/expr.hpp -- the tracer scalar: every operation records a node of a DAG
#pragma once

#include <cstdint>
#include <string>
#include <type_traits>
#include <vector>

#include "quadcast/scalar.hpp"

namespace quadcast::codegen {

/// Node types. Kernels compute in 32-bit float; comparisons give booleans.
enum class Type : std::uint8_t { f32, boolean };

/// Node operations. Leaves are `input` (a named kernel parameter component) and `literal`.
enum class Op : std::uint8_t {
    input, literal,
    add, sub, mul, div, neg, sqrt, abs,
    lt, le, gt, ge, eq, ne,
    land, lor, lnot,
    select, isnan, isinf,
    floor,  // appended: the enumerators take part in the structural hashes
};

/// Spelling of an operation in reports and banners (`+`, `sqrt`, `?:` ...).
const char* op_symbol(Op op);

/// One recorded operation. Operands are node ids; `lit` holds a literal's bits (float bits, or
/// 0/1 for a boolean) or, for an input, the index of its access expression.
struct Node {
    Op op;
    Type type;
    std::uint32_t a = 0, b = 0, c = 0;
    std::uint32_t lit = 0;
    std::uint64_t hash = 0;  ///< structural hash: independent of creation order
};

/// The arena of one recording. Identical (op, type, operands, literal) return the same node;
/// operands of exactly commutative operations (+ * == !=) are put in a canonical order by
/// structural hash, so `a*b` and `b*a` are one node whatever the C++ evaluation order was.
/// Constant operands are folded in float on the CPU; nothing is reassociated and `x + 0` is
/// never simplified (it differs from `x` at -0).
class Recorder {
public:
    Recorder();
    ~Recorder();
    Recorder(const Recorder&) = delete;
    Recorder& operator=(const Recorder&) = delete;

    /// The recorder that traced operations of this thread go to: the one of the innermost
    /// live `Recording`. Throws when there is none.
    static Recorder& current();

    std::uint32_t input(Type type, std::string access);
    std::uint32_t literal_f32(float v);
    std::uint32_t literal_bool(bool v);
    std::uint32_t make(Op op, Type type, std::uint32_t a, std::uint32_t b = 0, std::uint32_t c = 0);

    const Node& node(std::uint32_t id) const;
    const std::string& input_access(std::uint32_t id) const { return inputs_[node(id).lit]; }
    std::size_t size() const { return nodes_.size(); }

private:
    struct Impl;
    Impl* impl_;
    std::vector<Node> nodes_;
    std::vector<std::string> inputs_;
};

/// Makes `r` the current recorder of this thread for the guard's lifetime (guards nest).
class Recording {
public:
    explicit Recording(Recorder& r);
    ~Recording();
    Recording(const Recording&) = delete;
    Recording& operator=(const Recording&) = delete;

private:
    Recorder* previous_;
};

class Mask;

/// A traced 32-bit float. A 4-byte trivially copyable handle (node id in the current recorder;
/// 0 = unset), so it fits into `Vec<Expr, N>` and `std::array`. Only explicit construction from
/// a number: `Expr(0.1)` is the float nearest to 0.1, as `float(0.1)` would be on the CPU, and
/// `x * 2.0` (mixed precision) does not compile.
class Expr {
public:
    Expr() = default;
    explicit Expr(float v) : id(Recorder::current().literal_f32(v)) {}
    explicit Expr(double v) : id(Recorder::current().literal_f32(static_cast<float>(v))) {}
    explicit Expr(int v) : id(Recorder::current().literal_f32(static_cast<float>(v))) {}
    static Expr from_id(std::uint32_t i) { Expr e; e.id = i; return e; }

    Expr& operator+=(const Expr& o);
    Expr& operator-=(const Expr& o);
    Expr& operator*=(const Expr& o);
    Expr& operator/=(const Expr& o);

    std::uint32_t id;
};

/// A traced boolean. It does not convert to `bool`: a branch on traced data must be written
/// with `select`, so the GLSL and the CPU take the same path for every input.
class Mask {
public:
    Mask() = default;
    explicit Mask(bool v) : id(Recorder::current().literal_bool(v)) {}
    static Mask from_id(std::uint32_t i) { Mask m; m.id = i; return m; }
    explicit operator bool() const = delete;
    std::uint32_t id;
};

static_assert(std::is_trivially_copyable_v<Expr> && sizeof(Expr) == 4);
static_assert(std::is_trivially_copyable_v<Mask> && sizeof(Mask) == 4);
static_assert(!std::is_convertible_v<Mask, bool> && !std::is_constructible_v<bool, Mask>);

Expr operator+(const Expr& a, const Expr& b);
Expr operator-(const Expr& a, const Expr& b);
Expr operator*(const Expr& a, const Expr& b);
Expr operator/(const Expr& a, const Expr& b);
Expr operator-(const Expr& a);
Mask operator<(const Expr& a, const Expr& b);
Mask operator<=(const Expr& a, const Expr& b);
Mask operator>(const Expr& a, const Expr& b);
Mask operator>=(const Expr& a, const Expr& b);
Mask operator==(const Expr& a, const Expr& b);
Mask operator!=(const Expr& a, const Expr& b);
Mask operator&&(const Mask& a, const Mask& b);
Mask operator||(const Mask& a, const Mask& b);
Mask operator!(const Mask& a);

Expr select(const Mask& m, const Expr& a, const Expr& b);
Mask select(const Mask& m, const Mask& a, const Mask& b);
Expr sqrt(const Expr& x);
Expr abs(const Expr& x);
Expr floor(const Expr& x);
Mask isnan(const Expr& x);
Mask isinf(const Expr& x);
/// Neither infinite nor NaN.
Mask isfinite(const Expr& x);
inline Mask mask_and(const Mask& a, const Mask& b) { return a && b; }
inline Mask mask_or(const Mask& a, const Mask& b) { return a || b; }
inline Mask mask_not(const Mask& a) { return !a; }

}  // namespace quadcast::codegen

namespace quadcast {
template <>
struct scalar_traits<codegen::Expr> {
    using mask = codegen::Mask;
    static constexpr const char* name = "traced float";
};
}  // namespace quadcast
