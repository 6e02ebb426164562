// tests/bb/test_scalars.hpp -- scalar types for tests: exact rationals and an op-counting scalar with a non-bool mask
#pragma once

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <numeric>
#include <ostream>
#include <stdexcept>

#include "quadcast/scalar.hpp"

namespace qtest {

// ---- Rational: exact arithmetic for the mask/rule identities ---------------------------------

/// An exact rational with 64-bit numerator and denominator (normalised, d > 0); throws on
/// overflow or on a non-dyadic double.
struct Rational {
    std::int64_t n = 0, d = 1;

    Rational() = default;
    Rational(int v) : n(v), d(1) {}  // NOLINT: implicit, like an integer literal
    explicit Rational(double v) {
        if (!std::isfinite(v)) throw std::domain_error("Rational(double): not finite");
        int e = 0;
        double m = std::frexp(v, &e);  // v = m 2^e, |m| in [0.5, 1)
        std::int64_t num = static_cast<std::int64_t>(std::ldexp(m, 53));
        e -= 53;
        std::int64_t den = 1;
        while (e > 0) { num *= 2; --e; }
        while (e < 0 && num % 2 == 0 && num != 0) { num /= 2; ++e; }
        if (e < -62) throw std::domain_error("Rational(double): exponent");
        if (e < 0) den = std::int64_t(1) << (-e);
        n = num;
        d = num == 0 ? 1 : den;
        norm();
    }
    static Rational make(__int128 a, __int128 b) {
        if (b == 0) throw std::domain_error("Rational: division by zero");
        if (b < 0) { a = -a; b = -b; }
        __int128 g = gcd128(a < 0 ? -a : a, b);
        if (g > 1) { a /= g; b /= g; }
        const __int128 lim = (__int128(1) << 62);
        if (a > lim || a < -lim || b > lim) throw std::overflow_error("Rational overflow");
        Rational r;
        r.n = static_cast<std::int64_t>(a);
        r.d = static_cast<std::int64_t>(b);
        return r;
    }
    static __int128 gcd128(__int128 a, __int128 b) {
        while (b != 0) { __int128 t = a % b; a = b; b = t; }
        return a == 0 ? 1 : a;
    }
    void norm() { *this = make(n, d); }
    double to_double() const { return static_cast<double>(n) / static_cast<double>(d); }
};

inline Rational operator+(const Rational& a, const Rational& b) { return Rational::make(__int128(a.n) * b.d + __int128(b.n) * a.d, __int128(a.d) * b.d); }
inline Rational operator-(const Rational& a, const Rational& b) { return Rational::make(__int128(a.n) * b.d - __int128(b.n) * a.d, __int128(a.d) * b.d); }
inline Rational operator-(const Rational& a) { return Rational::make(-__int128(a.n), a.d); }
inline Rational operator*(const Rational& a, const Rational& b) { return Rational::make(__int128(a.n) * b.n, __int128(a.d) * b.d); }
inline Rational operator/(const Rational& a, const Rational& b) { return Rational::make(__int128(a.n) * b.d, __int128(a.d) * b.n); }
inline bool operator==(const Rational& a, const Rational& b) { return a.n == b.n && a.d == b.d; }
inline bool operator!=(const Rational& a, const Rational& b) { return !(a == b); }
inline bool operator<(const Rational& a, const Rational& b) { return __int128(a.n) * b.d < __int128(b.n) * a.d; }
inline bool operator>(const Rational& a, const Rational& b) { return b < a; }
inline bool operator<=(const Rational& a, const Rational& b) { return !(b < a); }
inline bool operator>=(const Rational& a, const Rational& b) { return !(a < b); }
inline Rational select(bool m, const Rational& a, const Rational& b) { return m ? a : b; }
inline Rational abs(const Rational& a) { return a.n < 0 ? -a : a; }
inline std::ostream& operator<<(std::ostream& o, const Rational& r) { return o << r.n << '/' << r.d; }

// ---- Counted<F>: behaves like the tracer (explicit literals, mask without bool) and counts ----

/// Operation counters (per thread).
struct OpCounts {
    long add = 0, mul = 0, div = 0, sqrt = 0, cmp = 0, sel = 0, logic = 0, abs = 0;
    long arith() const { return add + mul + div + sqrt + abs; }
    long total() const { return arith() + cmp + sel + logic; }
};
inline thread_local OpCounts op_counts;

/// A mask that, like the tracer's, cannot be converted to bool.
struct CMask {
    bool v;
    explicit operator bool() const = delete;
};
inline CMask operator&&(CMask a, CMask b) { ++op_counts.logic; return {a.v && b.v}; }
inline CMask operator||(CMask a, CMask b) { ++op_counts.logic; return {a.v || b.v}; }
inline CMask operator!(CMask a) { ++op_counts.logic; return {!a.v}; }
inline CMask mask_and(CMask a, CMask b) { return a && b; }
inline CMask mask_or(CMask a, CMask b) { return a || b; }
inline CMask mask_not(CMask a) { return !a; }

/// Scalar wrapping an F value; explicit construction only (so `x * 0.5` does not compile),
/// comparisons return CMask, every operation is counted. Results are bit-identical to F.
template <class F>
struct Counted {
    F v{};
    Counted() = default;
    explicit Counted(double x) : v(static_cast<F>(x)) {}
    explicit Counted(int x) : v(static_cast<F>(x)) {}
    static Counted raw(F x) { Counted c; c.v = x; return c; }
};
template <class F> Counted<F> operator+(Counted<F> a, Counted<F> b) { ++op_counts.add; return Counted<F>::raw(a.v + b.v); }
template <class F> Counted<F> operator-(Counted<F> a, Counted<F> b) { ++op_counts.add; return Counted<F>::raw(a.v - b.v); }
template <class F> Counted<F> operator-(Counted<F> a) { ++op_counts.add; return Counted<F>::raw(-a.v); }
template <class F> Counted<F> operator*(Counted<F> a, Counted<F> b) { ++op_counts.mul; return Counted<F>::raw(a.v * b.v); }
template <class F> Counted<F> operator/(Counted<F> a, Counted<F> b) { ++op_counts.div; return Counted<F>::raw(a.v / b.v); }
template <class F> CMask operator<(Counted<F> a, Counted<F> b) { ++op_counts.cmp; return {a.v < b.v}; }
template <class F> CMask operator>(Counted<F> a, Counted<F> b) { ++op_counts.cmp; return {a.v > b.v}; }
template <class F> CMask operator<=(Counted<F> a, Counted<F> b) { ++op_counts.cmp; return {a.v <= b.v}; }
template <class F> CMask operator>=(Counted<F> a, Counted<F> b) { ++op_counts.cmp; return {a.v >= b.v}; }
template <class F> CMask operator==(Counted<F> a, Counted<F> b) { ++op_counts.cmp; return {a.v == b.v}; }
template <class F> CMask operator!=(Counted<F> a, Counted<F> b) { ++op_counts.cmp; return {a.v != b.v}; }
template <class F> Counted<F> select(CMask m, Counted<F> a, Counted<F> b) { ++op_counts.sel; return m.v ? a : b; }
inline CMask select(CMask m, CMask a, CMask b) { ++op_counts.sel; return m.v ? a : b; }
template <class F> Counted<F> sqrt(Counted<F> a) { ++op_counts.sqrt; return Counted<F>::raw(std::sqrt(a.v)); }
template <class F> Counted<F> abs(Counted<F> a) { ++op_counts.abs; return Counted<F>::raw(std::fabs(a.v)); }
template <class F> CMask isfinite(Counted<F> a) { ++op_counts.cmp; return {std::isfinite(a.v)}; }
template <class F> CMask isnan(Counted<F> a) { ++op_counts.cmp; return {std::isnan(a.v)}; }

}  // namespace qtest

template <>
struct quadcast::scalar_traits<qtest::Rational> {
    using mask = bool;
    static constexpr const char* name = "rational";
};
template <class F>
struct quadcast::scalar_traits<qtest::Counted<F>> {
    using mask = qtest::CMask;
    static constexpr const char* name = "counted";
};
