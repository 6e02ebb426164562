// tests/contraction/contract_off.cpp -- built like a user of quadcast::quadcast: no contraction
#include <cstdio>
#include "detect.hpp"

int main() {
    if (!__builtin_cpu_supports("fma")) { std::puts("contraction: this CPU has no FMA; nothing can contract"); return 0; }
    const bool c = contraction_happens_here();
    std::printf("contraction with the quadcast target's flags (-mfma): %s\n", c ? "DETECTED" : "none");
    return c ? 1 : 0;
}
