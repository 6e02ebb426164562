// tests/contraction/contract_fast.cpp -- the control: -ffp-contract=fast -mfma must be detected,
// which shows the detector can fail.
#include <cstdio>
#include "detect.hpp"

int main() {
    if (!__builtin_cpu_supports("fma")) { std::puts("contraction: this CPU has no FMA; control skipped"); return 0; }
    const bool c = contraction_happens_here();
    std::printf("contraction with -ffp-contract=fast -mfma: %s\n", c ? "detected (expected)" : "NOT detected");
    return c ? 0 : 1;
}
