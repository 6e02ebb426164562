// quadcast/codegen/src/registry.cpp -- the list of every kernel the project emits
#include "quadcast/codegen/generate.hpp"

#include "kernels/quadric_kernels.hpp"

namespace quadcast::codegen {

const std::vector<KernelDef>& registry() {
    using namespace kernels;
    static const std::vector<KernelDef> all = {
        make_kernel<QuadricEvaluate>(),
        make_kernel<QuadricHalfGradient>(),
        make_kernel<QuadricTransform>(),
        make_kernel<QuadricToEye>(),
    };
    return all;
}

}  // namespace quadcast::codegen
