// tests/package/consumer.cpp -- the header-only core alone, as a user's program would use it
#include <quadcast/linalg.hpp>
#include <quadcast/render/cpu_renderer.hpp>
#include <quadcast/shapes.hpp>

#include <cstdio>

int main() {
    const quadcast::Vec3<float> a{{1.0f, 2.0f, 3.0f}};
    const float d = quadcast::dot(a, a);
#ifndef QUADCAST_FP_CONTRACT_OFF
    std::puts("consumer: quadcast target did not carry QUADCAST_FP_CONTRACT_OFF");
    return 1;
#endif
    // A sphere through the public API, drawn by the CPU reference.
    quadcast::render::RenderOptions o;
    o.width = 64;
    o.height = 48;
    const auto cam = quadcast::shapes::perspective_camera({0, 0, 5}, {0, 0, 0}, {0, 1, 0}, 40.0, 64.0 / 48.0, 1.0, 10.0);
    const auto img = quadcast::render::render_cpu({quadcast::shapes::sphere({0, 0, 0}, 1.0f)}, cam, quadcast::render::Light{}, o);
    long covered = 0;
    for (float z : img.depth) covered += z < 1.0f;
    std::printf("consumer: dot = %g, a unit sphere covers %ld of %d pixels\n", static_cast<double>(d), covered, o.width * o.height);
    return d == 14.0f && covered > 300 ? 0 : 1;
}
