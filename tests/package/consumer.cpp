// tests/package/consumer.cpp -- the header-only core alone, as a user's program would use it
#include <quadcast/isosurface.hpp>
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
    // A sampled field's QSS isosurface as quadrics clipped to tetrahedra (Stoll's path): |x|^2 on
    // 8^3 samples, iso 4, is the sphere of radius sqrt(4 - 3/4) = 1.8.
    quadcast::spline::Volume<float> vol(8, 8, 8);
    for (int k = 0; k < 8; ++k)
        for (int j = 0; j < 8; ++j)
            for (int i = 0; i < 8; ++i) vol.at(i, j, k) = float((i - 3.5) * (i - 3.5) + (j - 3.5) * (j - 3.5) + (k - 3.5) * (k - 3.5));
    const auto model = quadcast::shapes::isosurface(vol, {-3.5, -3.5, -3.5}, {1.0, 1.0, 1.0}, 4.0f);
    const std::vector<quadcast::render::Primitive> pieces = quadcast::shapes::isosurface_quadrics(model);
    o.culling = false;  // isosurface pieces are two-sided
    const auto iso_img = quadcast::render::render_cpu(pieces, cam, quadcast::render::Light{}, o);
    long iso_covered = 0;
    for (float z : iso_img.depth) iso_covered += z < 1.0f;
    std::printf("consumer: %zu QSS pieces of a sampled sphere cover %ld of %d pixels\n", pieces.size(), iso_covered, o.width * o.height);
    return d == 14.0f && covered > 300 && iso_covered > 2 * covered ? 0 : 1;
}
