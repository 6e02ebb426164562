// tests/package/consumer.cpp -- uses the installed headers as a user's program would
#include <quadcast/linalg.hpp>
#include <quadcast/generated/shaders.hpp>

#include <cstdio>

int main() {
    const quadcast::Vec3<float> a{{1.0f, 2.0f, 3.0f}};
    const float d = quadcast::dot(a, a);
#ifndef QUADCAST_FP_CONTRACT_OFF
    std::puts("consumer: quadcast target did not carry QUADCAST_FP_CONTRACT_OFF");
    return 1;
#endif
    std::printf("consumer: dot = %g, %zu generated shaders\n", static_cast<double>(d), std::size(quadcast::generated::shaders));
    return d == 14.0f ? 0 : 1;
}
