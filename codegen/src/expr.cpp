// quadcast/codegen/src/expr.cpp -- node arena, hash-consing and constant folding of the tracer
#include "quadcast/codegen/expr.hpp"

#include <bit>
#include <cmath>
#include <functional>
#include <stdexcept>
#include <unordered_map>
#include <utility>

namespace quadcast::codegen {

namespace {

thread_local Recorder* g_current = nullptr;

struct Key {
    Op op;
    Type type;
    std::uint32_t a, b, c, lit;
    bool operator==(const Key&) const = default;
};

struct KeyHash {
    std::size_t operator()(const Key& k) const noexcept {
        std::uint64_t h = 1469598103934665603ull;
        auto mix = [&h](std::uint64_t v) { h ^= v; h *= 1099511628211ull; };
        mix(static_cast<std::uint64_t>(k.op));
        mix(static_cast<std::uint64_t>(k.type));
        mix(k.a); mix(k.b); mix(k.c); mix(k.lit);
        return static_cast<std::size_t>(h);
    }
};

std::uint64_t mix64(std::uint64_t h, std::uint64_t v) {
    // SplitMix64-style mixing: deterministic on every platform.
    h ^= v + 0x9E3779B97F4A7C15ull + (h << 6) + (h >> 2);
    h ^= h >> 30; h *= 0xBF58476D1CE4E5B9ull;
    h ^= h >> 27; h *= 0x94D049BB133111EBull;
    h ^= h >> 31;
    return h;
}

std::uint64_t string_hash(const std::string& s) {
    std::uint64_t h = 1469598103934665603ull;
    for (unsigned char ch : s) { h ^= ch; h *= 1099511628211ull; }
    return h;
}

bool commutative(Op op) { return op == Op::add || op == Op::mul || op == Op::eq || op == Op::ne; }

int arity(Op op) {
    switch (op) {
    case Op::input: case Op::literal: return 0;
    case Op::neg: case Op::sqrt: case Op::abs: case Op::lnot: case Op::isnan: case Op::isinf: case Op::floor: return 1;
    case Op::select: return 3;
    default: return 2;
    }
}

}  // namespace

const char* op_symbol(Op op) {
    switch (op) {
    case Op::input: return "input";
    case Op::literal: return "literal";
    case Op::add: return "+";
    case Op::sub: return "-";
    case Op::mul: return "*";
    case Op::div: return "/";
    case Op::neg: return "neg";
    case Op::sqrt: return "sqrt";
    case Op::abs: return "abs";
    case Op::lt: return "<";
    case Op::le: return "<=";
    case Op::gt: return ">";
    case Op::ge: return ">=";
    case Op::eq: return "==";
    case Op::ne: return "!=";
    case Op::land: return "&&";
    case Op::lor: return "||";
    case Op::lnot: return "!";
    case Op::select: return "?:";
    case Op::isnan: return "isnan";
    case Op::isinf: return "isinf";
    case Op::floor: return "floor";
    }
    return "?";
}

struct Recorder::Impl {
    std::unordered_map<Key, std::uint32_t, KeyHash> cse;
};

Recorder::Recorder() : impl_(new Impl) {
    nodes_.push_back(Node{Op::literal, Type::f32});  // id 0: "unset", rejected by make()
}

Recorder::~Recorder() { delete impl_; }

Recording::Recording(Recorder& r) : previous_(g_current) { g_current = &r; }
Recording::~Recording() { g_current = previous_; }

Recorder& Recorder::current() {
    if (!g_current) throw std::logic_error("quadcast::codegen: traced value used with no live Recorder");
    return *g_current;
}

const Node& Recorder::node(std::uint32_t id) const {
    if (id == 0 || id >= nodes_.size()) throw std::logic_error("quadcast::codegen: use of an unset traced value");
    return nodes_[id];
}

std::uint32_t Recorder::input(Type type, std::string access) {
    for (std::size_t i = 0; i < inputs_.size(); ++i)
        if (inputs_[i] == access) throw std::logic_error("quadcast::codegen: input declared twice: " + access);
    const std::uint32_t index = static_cast<std::uint32_t>(inputs_.size());
    const std::uint64_t h = mix64(mix64(static_cast<std::uint64_t>(Op::input), static_cast<std::uint64_t>(type)), string_hash(access));
    inputs_.push_back(std::move(access));
    nodes_.push_back(Node{Op::input, type, 0, 0, 0, index, h});
    return static_cast<std::uint32_t>(nodes_.size() - 1);
}

std::uint32_t Recorder::literal_f32(float v) {
    const std::uint32_t bits = std::bit_cast<std::uint32_t>(v);
    Key k{Op::literal, Type::f32, 0, 0, 0, bits};
    if (auto it = impl_->cse.find(k); it != impl_->cse.end()) return it->second;
    const std::uint64_t h = mix64(mix64(static_cast<std::uint64_t>(Op::literal), 0), bits);
    nodes_.push_back(Node{Op::literal, Type::f32, 0, 0, 0, bits, h});
    const auto id = static_cast<std::uint32_t>(nodes_.size() - 1);
    impl_->cse.emplace(k, id);
    return id;
}

std::uint32_t Recorder::literal_bool(bool v) {
    Key k{Op::literal, Type::boolean, 0, 0, 0, v ? 1u : 0u};
    if (auto it = impl_->cse.find(k); it != impl_->cse.end()) return it->second;
    const std::uint64_t h = mix64(mix64(static_cast<std::uint64_t>(Op::literal), 1), v ? 1u : 0u);
    nodes_.push_back(Node{Op::literal, Type::boolean, 0, 0, 0, v ? 1u : 0u, h});
    const auto id = static_cast<std::uint32_t>(nodes_.size() - 1);
    impl_->cse.emplace(k, id);
    return id;
}

std::uint32_t Recorder::make(Op op, Type type, std::uint32_t a, std::uint32_t b, std::uint32_t c) {
    const int n = arity(op);
    const std::uint32_t ops[3] = {a, b, c};
    for (int i = 0; i < n; ++i) (void)node(ops[i]);  // validates ids

    // Fold constants in the kernel's precision (float), exactly as the CPU float build would.
    auto is_lit = [&](std::uint32_t id) { return nodes_[id].op == Op::literal; };
    auto f = [&](std::uint32_t id) { return std::bit_cast<float>(nodes_[id].lit); };
    auto bl = [&](std::uint32_t id) { return nodes_[id].lit != 0; };
    if (op == Op::select && is_lit(a)) return bl(a) ? b : c;
    bool all_lit = n > 0;
    for (int i = 0; i < n; ++i) all_lit = all_lit && is_lit(ops[i]);
    if (all_lit) {
        switch (op) {
        case Op::add: return literal_f32(f(a) + f(b));
        case Op::sub: return literal_f32(f(a) - f(b));
        case Op::mul: return literal_f32(f(a) * f(b));
        case Op::div: return literal_f32(f(a) / f(b));
        case Op::neg: return literal_f32(-f(a));
        case Op::sqrt: return literal_f32(std::sqrt(f(a)));
        case Op::abs: return literal_f32(std::fabs(f(a)));
        case Op::lt: return literal_bool(f(a) < f(b));
        case Op::le: return literal_bool(f(a) <= f(b));
        case Op::gt: return literal_bool(f(a) > f(b));
        case Op::ge: return literal_bool(f(a) >= f(b));
        case Op::eq: return type == Type::boolean && nodes_[a].type == Type::boolean ? literal_bool(bl(a) == bl(b)) : literal_bool(f(a) == f(b));
        case Op::ne: return nodes_[a].type == Type::boolean ? literal_bool(bl(a) != bl(b)) : literal_bool(f(a) != f(b));
        case Op::land: return literal_bool(bl(a) && bl(b));
        case Op::lor: return literal_bool(bl(a) || bl(b));
        case Op::lnot: return literal_bool(!bl(a));
        case Op::isnan: return literal_bool(std::isnan(f(a)));
        case Op::isinf: return literal_bool(std::isinf(f(a)));
        case Op::floor: return literal_f32(std::floor(f(a)));
        default: break;
        }
    }

    // Canonical operand order for exactly commutative operations.
    if (commutative(op)) {
        const Node& na = nodes_[a];
        const Node& nb = nodes_[b];
        if (nb.hash < na.hash || (nb.hash == na.hash && b < a)) std::swap(a, b);
    }

    Key k{op, type, a, b, c, 0};
    if (auto it = impl_->cse.find(k); it != impl_->cse.end()) return it->second;
    std::uint64_t h = mix64(static_cast<std::uint64_t>(op), static_cast<std::uint64_t>(type));
    const std::uint32_t cops[3] = {a, b, c};
    for (int i = 0; i < n; ++i) h = mix64(h, nodes_[cops[i]].hash);
    nodes_.push_back(Node{op, type, a, b, c, 0, h});
    const auto id = static_cast<std::uint32_t>(nodes_.size() - 1);
    impl_->cse.emplace(k, id);
    return id;
}

// Operators ----------------------------------------------------------------------------------

namespace {
Recorder& rec() { return Recorder::current(); }
Expr bin(Op op, const Expr& a, const Expr& b) { return Expr::from_id(rec().make(op, Type::f32, a.id, b.id)); }
Mask cmp(Op op, const Expr& a, const Expr& b) { return Mask::from_id(rec().make(op, Type::boolean, a.id, b.id)); }
}  // namespace

Expr& Expr::operator+=(const Expr& o) { return *this = *this + o; }
Expr& Expr::operator-=(const Expr& o) { return *this = *this - o; }
Expr& Expr::operator*=(const Expr& o) { return *this = *this * o; }
Expr& Expr::operator/=(const Expr& o) { return *this = *this / o; }

// Literal zeros. GLSL compilers fold `x * 0.0`, `x + 0.0` and `0.0 - x` even in `precise`
// statements (measured on Mesa llvmpipe), which is wrong for x = -0, Inf or NaN. So an
// arithmetic operation never gets a literal +-0 operand in the emitted text: the exact IEEE
// identities are applied here (x + -0 = x, x - +0 = x, -0 - x = -x), and the other cases are
// rewritten into selects and comparisons that compute the same bits for every x.

namespace {

bool is_zero_literal(const Expr& e, bool& negative) {
    const Node& n = rec().node(e.id);
    if (n.op != Op::literal || n.type != Type::f32 || (n.lit & 0x7FFFFFFFu) != 0) return false;
    negative = (n.lit & 0x80000000u) != 0;
    return true;
}

bool is_literal(const Expr& e) { return rec().node(e.id).op == Op::literal; }

Expr lit(float v) { return Expr(v); }
Expr nan_lit() { return Expr::from_id(rec().literal_f32(std::bit_cast<float>(0x7FC00000u))); }

/// True where x has its sign bit set (including -0): x < 0, or x == 0 and 1/x < 0.
Mask sign_bit(const Expr& x) {
    const Mask is_zero = cmp(Op::eq, x, lit(0.0f));
    const Expr inv = bin(Op::div, lit(1.0f), x);
    return Mask::from_id(rec().make(Op::lor, Type::boolean, cmp(Op::lt, x, lit(0.0f)).id,
                                    rec().make(Op::land, Type::boolean, is_zero.id, cmp(Op::lt, inv, lit(0.0f)).id)));
}

/// A zero whose sign bit is `negative`.
Expr signed_zero(const Mask& negative) { return select(negative, lit(-0.0f), lit(0.0f)); }

/// x + (+0): x, except -0 + +0 = +0.
Expr plus_zero(const Expr& x) { return select(cmp(Op::eq, x, lit(0.0f)), lit(0.0f), x); }

/// x * (+-0): a zero with the product's sign for finite x, NaN for Inf and NaN.
Expr times_zero(const Expr& x, bool zero_negative) {
    const Mask neg = zero_negative ? !sign_bit(x) : sign_bit(x);
    return select(isfinite(x), signed_zero(neg), nan_lit());
}

}  // namespace

Expr operator+(const Expr& a, const Expr& b) {
    bool na = false, nb = false;
    const bool za = is_zero_literal(a, na), zb = is_zero_literal(b, nb);
    if (za && zb) return bin(Op::add, a, b);  // folds
    if (zb) return nb ? a : plus_zero(a);
    if (za) return na ? b : plus_zero(b);
    return bin(Op::add, a, b);
}

Expr operator-(const Expr& a, const Expr& b) {
    bool na = false, nb = false;
    const bool za = is_zero_literal(a, na), zb = is_zero_literal(b, nb);
    if (za && zb) return bin(Op::sub, a, b);  // folds
    if (zb) return nb ? plus_zero(a) : a;                 // x - (-0) = x + 0; x - (+0) = x
    if (za) return na ? -b : select(cmp(Op::eq, b, lit(0.0f)), lit(0.0f), -b);  // -0 - x = -x; +0 - x
    return bin(Op::sub, a, b);
}

Expr operator*(const Expr& a, const Expr& b) {
    bool na = false, nb = false;
    const bool za = is_zero_literal(a, na), zb = is_zero_literal(b, nb);
    if (za && zb) return bin(Op::mul, a, b);  // folds
    if (zb) return times_zero(a, nb);
    if (za) return times_zero(b, na);
    return bin(Op::mul, a, b);
}

Expr operator/(const Expr& a, const Expr& b) {
    bool na = false, nb = false;
    const bool za = is_zero_literal(a, na), zb = is_zero_literal(b, nb);
    if (!is_literal(a) || !is_literal(b)) {
        if (zb) throw std::logic_error("quadcast::codegen: division by a literal zero in a traced kernel");
        if (za) {
            // +-0 / x: NaN for x = +-0 or NaN, otherwise a zero with the quotient's sign.
            const Mask undefined = cmp(Op::eq, b, lit(0.0f)) || isnan(b);
            const Mask neg = na ? !sign_bit(b) : sign_bit(b);
            return select(undefined, nan_lit(), signed_zero(neg));
        }
    }
    return bin(Op::div, a, b);
}
Expr operator-(const Expr& a) { return Expr::from_id(rec().make(Op::neg, Type::f32, a.id)); }
Mask operator<(const Expr& a, const Expr& b) { return cmp(Op::lt, a, b); }
Mask operator<=(const Expr& a, const Expr& b) { return cmp(Op::le, a, b); }
Mask operator>(const Expr& a, const Expr& b) { return cmp(Op::gt, a, b); }
Mask operator>=(const Expr& a, const Expr& b) { return cmp(Op::ge, a, b); }
Mask operator==(const Expr& a, const Expr& b) { return cmp(Op::eq, a, b); }
Mask operator!=(const Expr& a, const Expr& b) { return cmp(Op::ne, a, b); }
Mask operator&&(const Mask& a, const Mask& b) { return Mask::from_id(rec().make(Op::land, Type::boolean, a.id, b.id)); }
Mask operator||(const Mask& a, const Mask& b) { return Mask::from_id(rec().make(Op::lor, Type::boolean, a.id, b.id)); }
Mask operator!(const Mask& a) { return Mask::from_id(rec().make(Op::lnot, Type::boolean, a.id)); }

Expr select(const Mask& m, const Expr& a, const Expr& b) {
    if (a.id == b.id) { (void)rec().node(m.id); return a; }
    return Expr::from_id(rec().make(Op::select, Type::f32, m.id, a.id, b.id));
}
Mask select(const Mask& m, const Mask& a, const Mask& b) {
    if (a.id == b.id) { (void)rec().node(m.id); return a; }
    return Mask::from_id(rec().make(Op::select, Type::boolean, m.id, a.id, b.id));
}
Expr sqrt(const Expr& x) { return Expr::from_id(rec().make(Op::sqrt, Type::f32, x.id)); }
Expr abs(const Expr& x) { return Expr::from_id(rec().make(Op::abs, Type::f32, x.id)); }
Expr floor(const Expr& x) { return Expr::from_id(rec().make(Op::floor, Type::f32, x.id)); }
Mask isnan(const Expr& x) { return Mask::from_id(rec().make(Op::isnan, Type::boolean, x.id)); }
Mask isinf(const Expr& x) { return Mask::from_id(rec().make(Op::isinf, Type::boolean, x.id)); }
Mask isfinite(const Expr& x) { return !(isnan(x) || isinf(x)); }

}  // namespace quadcast::codegen
