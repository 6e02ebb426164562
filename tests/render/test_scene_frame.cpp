// tests/render/test_scene_frame.cpp -- scene files to primitives: every documented key reaches the picture
#include <doctest/doctest.h>

#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

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

// Numeric range (README "Numeric range"): a scene and its camera scaled by k and moved by an
// offset draw the unit-scale picture, for every primitive kind, k from 1e-30 to 1e30.
namespace {

/// `text` with every `@x` (a number) replaced by k x + offset and every `#x` by k x (lengths).
std::string scaled(const std::string& text, double k, double offset) {
    std::string out;
    for (std::size_t i = 0; i < text.size(); ++i) {
        const char c = text[i];
        if (c != '@' && c != '#') {
            out += c;
            continue;
        }
        std::size_t used = 0;
        const double x = std::stod(text.substr(i + 1), &used);
        char buf[64];
        std::snprintf(buf, sizeof buf, "%.17g", c == '@' ? k * x + offset : k * x);
        out += buf;
        i += used;
    }
    return out;
}

render::Image render_scaled(const std::string& objects, bool ortho, double k, double offset) {
    const std::string camera = ortho ? R"("camera": {"type": "orthographic", "eye": [@0.3, @0.4, @5], "target": [@0, @0, @0], "height": #3.2, "near": #1, "far": #12})"
                                     : R"("camera": {"eye": [@0.3, @0.4, @5], "target": [@0, @0, @0], "fov_y": 36, "near": #1, "far": #12})";
    const std::string text = scaled("{" + camera + R"(, "lights": [{"direction": [-1, -1.5, -2]}], "objects": [)" + objects + "]}", k, offset);
    const scene::Scene s = scene::parse_scene(text, "scaled.json", ".");
    const render::Frame f = render::build_frame(s, 64, 48);
    return render::render_cpu(f.primitives, f.camera, f.light, f.options);
}

}  // namespace

TEST_CASE("numeric range: every primitive kind draws the unit-scale picture at scales 1e-30 to 1e30") {
    // (a general quadric at scale k: the coefficients of order n scale by k^-n; a one-sheet
    // hyperboloid x^2 + y^2 - z^2 = 0.09 in a sphere)
    const auto hyperboloid = [](double k) {
        char q[512];
        std::snprintf(q, sizeof q, R"({"quadric": {"coefficients": [-0.09, 0, 0, 0, 0, 0, 0, %.17g, %.17g, %.17g], "bound": {"sphere": {"center": [@0, @0, @0], "radius": #0.9}}}})",
                      1 / (k * k), 1 / (k * k), -1 / (k * k));
        return std::string(q);
    };
    struct Kind {
        const char* name;
        std::string objects;  // with k = 1
    };
    const std::vector<Kind> kinds = {
        {"sphere", R"({"sphere": {"center": [@0.2, @-0.1, @0.1], "radius": #0.8}})"},
        {"ellipsoid", R"({"ellipsoid": {"center": [@0, @0, @0], "axes": [[#1.1, #0, #0], [#0, #0.5, #0.5], [#0, #-0.3, #0.3]]}})"},
        {"cylinder", R"({"cylinder": {"p0": [@-0.6, @-0.5, @0], "p1": [@0.7, @0.6, @0.2], "radius": #0.3}})"},
        {"open cylinder", R"({"cylinder": {"p0": [@-0.2, @-0.2, @-0.6], "p1": [@0.2, @0.2, @0.8], "radius": #0.4, "caps": false}})"},
        {"cone", R"({"cone": {"apex": [@0, @0.9, @0], "base": [@0.1, @-0.6, @0.2], "radius": #0.5}})"},
        {"quad", R"({"quad": {"corners": [[@-0.8, @-0.7, @0], [@0.8, @-0.6, @0.6], [@0.7, @0.8, @0], [@-0.7, @0.6, @0.7]]}})"},
        {"quadric", ""},
    };
    for (const bool ortho : {false, true})
        for (std::size_t n = 0; n < kinds.size(); ++n) {
            const bool quadric = kinds[n].objects.empty();
            const render::Image ref = render_scaled(quadric ? hyperboloid(1.0) : kinds[n].objects, ortho, 1.0, 0.0);
            // (the offset moves the scene beyond 2^20, where the frame takes it back to the
            // origin; a general quadric's coefficients at such an offset are ill-conditioned in
            // any precision, so it is only scaled)
            for (const double offset : quadric ? std::vector<double>{0.0} : std::vector<double>{0.0, 1e7})
                for (const double k : {1e-30, 1e-20, 1e-10, 1e-3, 1.0, 1e3, 1e10, 1e20, 1e30}) {
                    const render::Image img = render_scaled(quadric ? hyperboloid(k) : kinds[n].objects, ortho, k, k * offset);
                    long coverage = 0, colour = 0, covered = 0;
                    for (std::size_t p = 0; p < ref.depth.size(); ++p) {
                        const bool a = ref.depth[p] < 1.0f, b = img.depth[p] < 1.0f;
                        covered += a;
                        if (a != b) {
                            ++coverage;
                            continue;
                        }
                        for (int c = 0; c < 3; ++c)
                            if (std::abs(int(ref.rgba[p * 4 + c]) - int(img.rgba[p * 4 + c])) > 2) {
                                ++colour;
                                break;
                            }
                    }
                    INFO(std::string(kinds[n].name) << (ortho ? " orthographic" : " perspective") << " k " << k << " offset " << offset << ": " << covered
                                       << " covered, " << coverage << " coverage and " << colour << " colour differences");
                    CHECK(covered > 100);
                    CHECK(coverage <= 2);
                    CHECK(colour <= 2);
                }
        }
}

TEST_CASE("numeric range: a scene beyond 1e300 is framed; a degenerate quad far away does not move the frame") {
    // (no camera: it is fitted to the scene)
    scene::Scene s = scene::parse_scene(R"({"objects": [{"sphere": {"center": [2e300, 0, 0], "radius": 1e299}}]})", "far.json", ".");
    render::Frame f = render::build_frame(s, 64, 48);
    CHECK(f.transform.offset[0] == doctest::Approx(2e300));
    render::Image img = render::render_cpu(f.primitives, f.camera, f.light, f.options);
    long covered = 0;
    for (const float d : img.depth) covered += d < 1.0f;
    CHECK(covered > 300);
    // (the loader rejects such quads; a scene built in code may hold one, and it is not drawn)
    s = scene::parse_scene(R"({"objects": [{"sphere": {"center": [0, 0, 0], "radius": 1}}]})", "point_quad.json", ".");
    scene::BilinearQuad point{};
    for (auto& p : point.p) p = scene::Vec3d{{1e6, 0.0, 0.0}};
    s.quads.push_back(point);
    f = render::build_frame(s, 64, 48);
    CHECK(f.primitives.size() == 1);
    CHECK(f.transform.scale == 1.0);
    CHECK(f.transform.offset[0] == 0.0);
}
