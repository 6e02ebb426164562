// tests/render/test_scene_frame.cpp -- scene files to primitives: every documented key reaches the picture
#include <doctest/doctest.h>

#include <string>

#include "quadcast/render/cpu_renderer.hpp"
#include "quadcast/scene/scene_json.hpp"
#include "quadcast/scene/scene_render.hpp"

using namespace quadcast;

namespace {

render::Frame frame_of(const std::string& objects) {
    const scene::Scene s = scene::parse_scene(R"({"camera": {"eye": [0, 0, 6], "target": [0, 0, 0]}, "objects": [)" + objects + "]}", "test.json", ".");
    return render::build_frame(s, 160, 120);
}

}  // namespace

TEST_CASE("cylinder caps and cone cap are honoured") {
    const render::Frame f = frame_of(R"({"cylinder": {"p0": [0, 0, 0], "p1": [0, 1, 0], "radius": 0.3, "caps": false}},
                                        {"cylinder": {"p0": [1, 0, 0], "p1": [1, 1, 0], "radius": 0.3}},
                                        {"cone": {"apex": [0, 0, 1], "base": [0, 1, 1], "radius": 0.3, "cap": false}},
                                        {"cone": {"apex": [1, 0, 1], "base": [1, 1, 1], "radius": 0.3}})");
    REQUIRE(f.primitives.size() == 4);
    CHECK(f.primitives[0].variant == render::Variant::open_slab);
    CHECK(f.primitives[0].shape.caps[0] == 0.0f);
    CHECK(f.primitives[0].shape.caps[1] == 0.0f);
    CHECK(f.primitives[1].variant == render::Variant::slab);
    CHECK(f.primitives[1].shape.caps[0] == 1.0f);
    CHECK(f.primitives[1].shape.caps[1] == 1.0f);
    CHECK(f.primitives[2].variant == render::Variant::open_slab);
    CHECK(f.primitives[2].shape.caps[1] == 0.0f);
    CHECK(f.primitives[3].variant == render::Variant::slab);
    CHECK(f.primitives[3].shape.caps[1] == 1.0f);
}

TEST_CASE("material specular and shininess reach the primitives and the picture") {
    const render::Frame f = frame_of(R"({"sphere": {"center": [-1.1, 0, 0], "radius": 1}, "material": {"color": [0.5, 0.3, 0.2], "specular": 0, "shininess": 2}},
                                        {"sphere": {"center": [1.1, 0, 0], "radius": 1}, "material": {"color": [0.5, 0.3, 0.2], "specular": 1, "shininess": 200}})");
    REQUIRE(f.primitives.size() == 2);
    CHECK(f.primitives[0].material.specular == 0.0f);
    CHECK(f.primitives[0].material.shininess == 2.0f);
    CHECK(f.primitives[1].material.specular == 1.0f);
    CHECK(f.primitives[1].material.shininess == 200.0f);
    // The two halves of the picture differ (mirror images but for the material).
    const render::Image img = render::render_cpu(f.primitives, f.camera, f.light, f.options);
    long differ = 0;
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width / 2; ++x) {
            const std::size_t a = (std::size_t(y) * img.width + x) * 4, b = (std::size_t(y) * img.width + (img.width - 1 - x)) * 4;
            differ += img.rgba[a] != img.rgba[b];
        }
    CHECK(differ > 200);
}

TEST_CASE("default material: the renderer's former constants") {
    const render::Frame f = frame_of(R"({"sphere": {"center": [0, 0, 0], "radius": 1}})");
    REQUIRE(f.primitives.size() == 1);
    CHECK(f.primitives[0].material.specular == doctest::Approx(f.options.material[2]));
    CHECK(f.primitives[0].material.shininess == doctest::Approx(f.options.material[3]));
}
