// tests/slim/render_cpu.cpp -- the CPU reference SLIM renderer: blended hits on the exact surface, no seams, scene objects
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "quadcast/camera.hpp"
#include "quadcast/image/image_io.hpp"
#include "quadcast/render/slim_cpu_renderer.hpp"
#include "quadcast/scene/scene_json.hpp"
#include "quadcast/scene/scene_render.hpp"
#include "quadcast/slim/build.hpp"
#include "quadcast/slim/scene_loader.hpp"
#include "slim/slim_testing.hpp"

using namespace quadcast;
using namespace quadcast::slim;
using namespace quadcast::slim::testing;

namespace {

/// A scene of one SLIM surface built from `pts` at relative error `error`, seen from `eye`.
scene::Scene slim_scene(const OrientedPoints& pts, double error, const Vec3d& eye, double* threshold) {
    BuildOptions opt;
    opt.error = error;
    const BuildResult r = build(pts, opt);
    if (threshold) *threshold = r.stats.threshold;
    scene::Scene s;
    scene::Slim m;
    m.balls = scene_balls(r.model);
    s.slims.push_back(m);
    s.camera.eye = eye;
    s.camera.target = Vec3d{{0.0, 0.0, 0.0}};
    s.camera.near = 0.5;
    s.camera.far = 20.0;
    s.camera.fov_y_deg = 40.0;
    return s;
}

struct Measured {
    long double max_distance = 0;   ///< of the blended positions to the exact surface
    double max_normal_deg = 0;      ///< blended normal vs the exact normal at the blended position (interior pixels)
    double max_normal_silhouette_deg = 0;  ///< the same at silhouette and grazing pixels
    double max_seam_deg = 0;        ///< neighbours' normal angle minus the exact normals' angle
    int covered = 0;
    int seam_at = -1;   ///< pixel index of the largest seam
};

double angle_deg(const Vec<long double, 3>& a, const Vec<long double, 3>& b) {
    const long double c = dot(a, b) / std::sqrt(dot(a, a) * dot(b, b));
    return static_cast<double>(std::acos(std::clamp(c, -1.0L, 1.0L)) * 180.0L / 3.14159265358979323846L);
}

/// Every covered pixel's blended position against the exact surface (long double): distance and
/// normal angle (`exact(x, &normal)` returns the distance), and the seams between 4-neighbours.
template <class Exact>
Measured measure(const std::vector<render::SlimPixel>& px, int w, int h, Exact&& exact) {
    Measured m;
    using L = long double;
    std::vector<Vec<L, 3>> exact_n(px.size()), blended_n(px.size());
    // Interior pixels: every 8-neighbour covered too (at the silhouette the ray grazes the surface,
    // and the normal of a position error there is not a seam).
    auto interior = [&](std::size_t i) {
        const int x = int(i % std::size_t(w)), y = int(i / std::size_t(w));
        for (int dy = -1; dy <= 1; ++dy)
            for (int dx = -1; dx <= 1; ++dx) {
                const int xx = x + dx, yy = y + dy;
                if (xx < 0 || yy < 0 || xx >= w || yy >= h || !px[std::size_t(yy) * w + xx].covered) return false;
            }
        return true;
    };
    // ... and not seen at a grazing angle: |cos| between the ray and the exact normal >= 1/2.
    std::vector<char> facing(px.size(), 0);
    for (std::size_t i = 0; i < px.size(); ++i) {
        const render::SlimPixel& p = px[i];
        if (!p.covered) continue;
        ++m.covered;
        Vec<L, 3> x;
        for (int k = 0; k < 3; ++k) x[k] = L(p.origin[k]) + L(p.lambda) * L(p.dir[k]);
        m.max_distance = std::max(m.max_distance, exact(x, &exact_n[i]));
        for (int k = 0; k < 3; ++k) blended_n[i][k] = L(p.normal[k]);
        {
            Vec<L, 3> dl;
            for (int k = 0; k < 3; ++k) dl[k] = L(p.dir[k]);
            facing[i] = std::fabs(dot(dl, exact_n[i])) >= 0.5L * std::sqrt(dot(dl, dl) * dot(exact_n[i], exact_n[i]));
        }
        if (interior(i) && facing[i]) m.max_normal_deg = std::max(m.max_normal_deg, angle_deg(exact_n[i], blended_n[i]));
        else m.max_normal_silhouette_deg = std::max(m.max_normal_silhouette_deg, angle_deg(exact_n[i], blended_n[i]));
    }
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            for (int d = 0; d < 2; ++d) {
                if ((d == 0 && x + 1 >= w) || (d == 1 && y + 1 >= h)) continue;
                const std::size_t i = std::size_t(y) * w + x, j = d == 0 ? i + 1 : i + std::size_t(w);
                if (!interior(i) || !interior(j) || !facing[i] || !facing[j]) continue;
                // Only neighbours whose blended positions are at most 3 pixel footprints apart (a
                // steeper step is a surface seen nearly edge-on, where the fit's normal error of two
                // far apart points is compared, not a seam).
                Vec<L, 3> xi, xj, di;
                for (int k = 0; k < 3; ++k) {
                    xi[k] = L(px[i].origin[k]) + L(px[i].lambda) * L(px[i].dir[k]);
                    xj[k] = L(px[j].origin[k]) + L(px[j].lambda) * L(px[j].dir[k]);
                    di[k] = L(px[i].lambda) * (L(px[j].dir[k]) - L(px[i].dir[k])) + (L(px[j].origin[k]) - L(px[i].origin[k]));
                }
                if (dot(xi - xj, xi - xj) > 9.0L * dot(di, di)) continue;
                const double seam = angle_deg(blended_n[i], blended_n[j]) - angle_deg(exact_n[i], exact_n[j]);
                if (seam > m.max_seam_deg) {
                    m.max_seam_deg = seam;
                    m.seam_at = static_cast<int>(i);
                }
            }
    return m;
}

/// The exact ellipsoid with semi-axes a (centred): distance and outward normal at x (first order:
/// the gradient at x, whose angle to the closest point's normal is O(distance)).
auto ellipsoid_exact(const Vec3d& a) {
    return [a](const Vec<long double, 3>& x, Vec<long double, 3>* n) {
        for (int k = 0; k < 3; ++k) (*n)[k] = x[k] / ((long double)a[k] * (long double)a[k]);
        return ellipsoid_distance(x, a);
    };
}

}  // namespace

TEST_CASE("a SLIM sphere, ellipsoid and torus render with every blended hit on the exact surface, without seams") {
    // Documented bounds (README, "SLIM surfaces"), over the pixels whose 3x3 neighbourhood is covered
    // and whose ray meets the exact surface at |cos| >= 1/2 (at grazing angles a ball's own quadric
    // can have its silhouette inside the ball, where its hit ends with a weight > 0): the blended
    // normal's angle to the exact normal, and the seam measure -- per pair of 4-neighbours (at most 3
    // pixel footprints apart) the angle between their blended normals minus the exact normals'. The
    // distance bound holds for every covered pixel. The sphere and the ellipsoid are quadrics (each
    // ball fits them exactly); the torus is not, so its balls' quadrics differ and the blend matters.
    struct Bound {
        double distance_e, normal_deg, seam_deg;
    };
    const int w = 160, h = 120;
    for (const std::string name : {"sphere", "ellipsoid", "torus"}) {
        CAPTURE(name);
        const Vec3d axes = name == "sphere" ? Vec3d{{1.0, 1.0, 1.0}} : Vec3d{{1.2, 0.8, 0.6}};
        const OrientedPoints pts = name == "torus" ? torus_points(1.0, 0.4, 8000, 5) : ellipsoid_points(Vec3d{{0.0, 0.0, 0.0}}, axes, 4000, 7);
        double E = 0;
        const scene::Scene s = slim_scene(pts, name == "torus" ? 2e-3 : 1e-3, Vec3d{{0.8, 1.9, 3.2}}, &E);
        const render::Frame fr = render::build_frame(s, w, h);
        REQUIRE(!fr.slim_balls.empty());
        std::vector<render::SlimPixel> px;
        const render::Image img = render::render_slim_cpu(fr.slim_balls, fr.camera, fr.light, fr.options, &px);
        const Measured m = name == "torus" ? measure(px, w, h, [](const Vec<long double, 3>& x, Vec<long double, 3>* n) { return torus_distance(x, 1.0L, 0.4L, n); })
                                           : measure(px, w, h, ellipsoid_exact(axes));
        MESSAGE(name << ": " << fr.slim_balls.size() << " balls, " << m.covered << " covered pixels, E = " << E << ", max distance "
                     << double(m.max_distance) << " (" << double(m.max_distance / E) << " E), max normal error " << m.max_normal_deg
                     << " deg (silhouette and grazing pixels " << m.max_normal_silhouette_deg << " deg), max seam " << m.max_seam_deg << " deg at pixel " << m.seam_at % w << ", " << m.seam_at / w
                     << " (" << px[std::size_t(m.seam_at)].blended << " fragments blended)");
        if (std::getenv("QUADCAST_SLIM_TEST_PNG")) render::write_png(std::string(std::getenv("QUADCAST_SLIM_TEST_PNG")) + name + ".png", img);
        CHECK(m.covered > w * h / 8);
        const Bound b = name == "torus" ? Bound{1.0, 3.5, 1.0} : Bound{0.01, 0.01, 0.01};
        CHECK(m.max_distance <= b.distance_e * E);
        CHECK(m.max_normal_deg < b.normal_deg);
        CHECK(m.max_seam_deg < b.seam_deg);
        // Coverage: the blended depth is written where the surface is, the background elsewhere.
        int bg = 0;
        for (std::size_t i = 0; i < px.size(); ++i) bg += img.depth[i] == 1.0f;
        CHECK(bg == w * h - m.covered);
    }
}

TEST_CASE("the visibility window blends only the front sheet: a SLIM sphere seen from outside never blends its back") {
    const OrientedPoints pts = ellipsoid_points(Vec3d{{0.0, 0.0, 0.0}}, Vec3d{{1.0, 1.0, 1.0}}, 3000, 3);
    double E = 0;
    for (bool culling : {true, false}) {
        CAPTURE(culling);
        scene::Scene s = slim_scene(pts, 2e-3, Vec3d{{0.0, 0.0, 4.0}}, &E);
        s.options.culling = culling;
        const render::Frame fr = render::build_frame(s, 64, 64);
        std::vector<render::SlimPixel> px;
        render::render_slim_cpu(fr.slim_balls, fr.camera, fr.light, fr.options, &px);
        int covered = 0, back = 0;
        for (const auto& p : px) {
            if (!p.covered) continue;
            ++covered;
            // The front sheet faces the eye: its blended normal points against the ray.
            back += p.normal[0] * p.dir[0] + p.normal[1] * p.dir[1] + p.normal[2] * p.dir[2] > 0.0f;
        }
        CHECK(covered > 500);
        CHECK(back == 0);
    }
}

TEST_CASE("SLIM objects in scene files: models and point files load, bad input names the file and field") {
    const std::filesystem::path dir = std::filesystem::temp_directory_path() / "quadcast_slim_scene_test";
    std::filesystem::create_directories(dir);
    install_scene_loader();
    const std::string points = std::string(QUADCAST_SLIM_TEST_DATA) + "/sphere_500.xyz";
    auto scene_file = [&](const std::string& name, const std::string& object) {
        const std::filesystem::path p = dir / name;
        std::ofstream(p) << "{\"objects\": [\n  " << object << "\n]}\n";
        return p;
    };
    auto error_of = [&](const std::filesystem::path& p) -> std::string {
        try {
            scene::load_scene(p);
        } catch (const scene::ParseError& e) {
            return e.what();
        }
        return "";
    };
    SUBCASE("a point file builds at the given error; its model file loads the same balls") {
        const scene::Scene s = scene::load_scene(scene_file("points.json", "{\"slim\": \"" + points + "\", \"error\": 5e-3, \"color\": [0.2, 0.6, 0.9]}"));
        REQUIRE(s.slims.size() == 1);
        CHECK(s.slims[0].balls.size() > 10);
        CHECK(s.slims[0].material.color[2] == 0.9);
        CHECK(!s.bounds().empty());
        Model m;
        BuildOptions opt;
        opt.error = 5e-3;
        m = build(read_points(points), opt).model;
        write_model(dir / "sphere.slim", m);
        const scene::Scene s2 = scene::load_scene(scene_file("model.json", "{\"slim\": \"sphere.slim\"}"));
        REQUIRE(s2.slims.size() == 1);
        CHECK(s2.slims[0].balls.size() == s.slims[0].balls.size());
        const render::Frame fr = render::build_frame(s2, 32, 32);
        CHECK(fr.slim_balls.size() == m.balls.size());
    }
    SUBCASE("a missing file") {
        const std::string e = error_of(scene_file("missing.json", "{\"slim\": \"nowhere.slim\"}"));
        CHECK(e.find("missing.json:2:") != std::string::npos);
        CHECK(e.find("/objects/0/slim") != std::string::npos);
        CHECK(e.find("no such file") != std::string::npos);
    }
    SUBCASE("a point file without an error, or an error <= 0") {
        std::string e = error_of(scene_file("noerror.json", "{\"slim\": \"" + points + "\"}"));
        CHECK(e.find("noerror.json:2:") != std::string::npos);
        CHECK(e.find("/objects/0/slim") != std::string::npos);
        CHECK(e.find("needs \"error\"") != std::string::npos);
        for (const char* bad : {"0", "-1e-3"}) {
            e = error_of(scene_file("zero.json", "{\"slim\": \"" + points + "\", \"error\": " + bad + "}"));
            CHECK(e.find("zero.json:2:") != std::string::npos);
            CHECK(e.find("/objects/0/error") != std::string::npos);
        }
    }
    SUBCASE("an error for a model file is not ignored") {
        std::ofstream(dir / "one.slim") << "quadcast-slim 1\nballs 0\n";
        const std::string e = error_of(scene_file("modelerror.json", "{\"slim\": \"one.slim\", \"error\": 1e-3}"));
        CHECK(e.find("/objects/0/error") != std::string::npos);
        CHECK(e.find("only for point files") != std::string::npos);
    }
    SUBCASE("a bad model line names the model file and line, and the scene entry") {
        std::ofstream(dir / "bad.slim") << "quadcast-slim 1\nballs 1\nball 0 0 0 -1 0 0 0 0 0 0 0 1 1 1\n";
        const std::string e = error_of(scene_file("badmodel.json", "{\"slim\": \"bad.slim\"}"));
        CHECK(e.find("bad.slim:3") != std::string::npos);
        CHECK(e.find("badmodel.json:2:") != std::string::npos);
        CHECK(e.find("/objects/0/slim") != std::string::npos);
    }
    SUBCASE("an unknown key next to slim") {
        const std::string e = error_of(scene_file("key.json", "{\"slim\": \"one.slim\", \"eror\": 1e-3}"));
        CHECK(e.find("eror") != std::string::npos);
    }
}
