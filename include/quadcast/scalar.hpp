// quadcast/scalar.hpp -- scalar traits and branch-free helpers shared by float, double and the tracer
#pragma once

#include <cmath>
#include <type_traits>

namespace quadcast {

/// Traits of a scalar type used by the shared templates.
/// `mask` is the type a comparison returns: `bool` for float/double, a traced mask for the
/// code generator's `Expr`. A scalar type opts in by specialising this template.
template <class T>
struct scalar_traits;

template <>
struct scalar_traits<float> {
    using mask = bool;
    static constexpr const char* name = "float";
};

template <>
struct scalar_traits<double> {
    using mask = bool;
    static constexpr const char* name = "double";
};

/// The mask type of scalar `T` (what `a < b` returns).
template <class T>
using mask_t = typename scalar_traits<T>::mask;

// Primitive operations for the CPU scalars. The tracer provides the same names for its own
// type in its namespace (found by ADL); shared templates call them unqualified from inside
// namespace quadcast. Each one is exactly rounded (IEEE 754) on the CPU and maps to a GLSL
// operation measured to be bit-identical on Mesa llvmpipe.

/// `m ? a : b`, written as data so the tracer can record it.
inline float select(bool m, float a, float b) { return m ? a : b; }
inline double select(bool m, double a, double b) { return m ? a : b; }
inline bool select(bool m, bool a, bool b) { return m ? a : b; }

inline float sqrt(float x) { return std::sqrt(x); }
inline double sqrt(double x) { return std::sqrt(x); }
inline float abs(float x) { return std::fabs(x); }
inline double abs(double x) { return std::fabs(x); }
/// Round towards -infinity (exact in IEEE 754 and in GLSL).
inline float floor(float x) { return std::floor(x); }
inline double floor(double x) { return std::floor(x); }

/// True where x is neither infinite nor NaN.
inline bool isfinite(float x) { return std::isfinite(x); }
inline bool isfinite(double x) { return std::isfinite(x); }
inline bool isnan(float x) { return std::isnan(x); }
inline bool isnan(double x) { return std::isnan(x); }

/// Mask combinators that work for `bool` and for traced masks alike.
inline bool mask_and(bool a, bool b) { return a && b; }
inline bool mask_or(bool a, bool b) { return a || b; }
inline bool mask_not(bool a) { return !a; }

// Derived helpers, defined once in terms of the primitives above so every scalar type gets
// the same semantics (including NaN handling).

/// `b < a ? b : a`: returns `a` when either operand is NaN and `b` is not smaller.
template <class T>
T min(const T& a, const T& b) { return select(b < a, b, a); }

/// `a < b ? b : a`.
template <class T>
T max(const T& a, const T& b) { return select(a < b, b, a); }

/// `min(max(x, lo), hi)`.
template <class T>
T clamp(const T& x, const T& lo, const T& hi) { return min(max(x, lo), hi); }

/// +1 for x >= 0 (including +0 and -0), -1 otherwise. Not GLSL's `sign` (which returns 0 at 0).
template <class T>
T sign_nonzero(const T& x) { return select(x < T(0), T(-1), T(1)); }

/// `x * x`.
template <class T>
T sq(const T& x) { return x * x; }

}  // namespace quadcast
