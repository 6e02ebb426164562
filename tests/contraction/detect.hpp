// tests/contraction/detect.hpp -- does this translation unit fuse a*b+c into one rounding?
#pragma once

/// `x * y + z` as the translation unit's flags compile it (maybe one fused rounding).
__attribute__((noinline)) inline float multiply_add(float x, float y, float z) { return x * y + z; }

/// With a = 1 + 2^-13, b = 1 - 2^-13: a*b = 1 - 2^-26 exactly, which rounds to 1 in float, so
/// the unfused a*b - 1 is 0 while a fused one is -2^-26. `volatile` keeps both from folding.
inline bool contraction_happens_here() {
    volatile float a = 1.0f + 0x1.0p-13f, b = 1.0f - 0x1.0p-13f, c = -1.0f;
    volatile float product = a * b;
    const float unfused = product + c;
    return multiply_add(a, b, c) != unfused;
}
