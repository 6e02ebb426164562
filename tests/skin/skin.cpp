// tests/skin/skin.cpp -- molecular skin surfaces (quadcast::skin over CGAL's Skin_surface_3): the
// pieces against CGAL's own functions, rays on the surface, C1 across cells, no pinholes, the
// "skin" style of PDB objects and its errors, GL against the CPU reference
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <random>
#include <string>
#include <vector>

#include "quadcast/bb/quadric_form.hpp"
#include "quadcast/gl/osmesa_context.hpp"
#include "quadcast/gl/quadric_renderer.hpp"
#include "quadcast/render/cpu_renderer.hpp"
#include "quadcast/scene/pdb.hpp"
#include "quadcast/scene/scene_json.hpp"
#include "quadcast/scene/scene_render.hpp"
#include "quadcast/skin/skin.hpp"
#include "core/exact_tet.hpp"
#include "render/render_testing.hpp"
#include "scene/helpers.hpp"

using namespace quadcast;
using scene::Vec3d;
using scene_test::TempDir;
using scene_test::parse_error_of;

namespace {

Vec3d random_point(std::mt19937& rng, const std::array<Vec3d, 4>& t) {
    std::exponential_distribution<double> e(1.0);
    double w[4], sum = 0;
    for (double& x : w) sum += x = e(rng);
    Vec3d p{{0, 0, 0}};
    for (int k = 0; k < 4; ++k) p = p + t[std::size_t(k)] * (w[k] / sum);
    return p;
}

/// One PDB ATOM record (fixed columns, wwPDB 3.3).
std::string atom(int serial, const char* element, double x, double y, double z) {
    char buf[100];
    std::snprintf(buf, sizeof buf, "ATOM  %5d  %-3s ALA A   1    %8.3f%8.3f%8.3f  1.00  0.00          %2s\n", serial, element, x, y, z, element);
    return buf;
}

std::vector<scene::SkinBall> two_atoms() { return {{Vec3d{{0, 0, 0}}, 1.7, {}}, {Vec3d{{2.6, 0.3, -0.2}}, 1.55, {}}}; }

/// The pixel's hit point on the exact ray of the double camera (eye, target, fov_y 30, up +y), from
/// the window depth (as tests/scene/msh.cpp does).
struct PixelRays {
    Vec3d eye, fwd, right, up;
    double th;
    int w, h;
    PixelRays(const Vec3d& e, const Vec3d& target, int w_, int h_) : eye(e), w(w_), h(h_) {
        fwd = normalize(target - eye);
        right = normalize(cross(fwd, Vec3d{{0, 1, 0}}));
        up = cross(right, fwd);
        th = std::tan(30.0 * M_PI / 360.0);
    }
    Vec3d dir(int x, int y) const {
        const double u = (2 * (x + 0.5) / w - 1) * th * w / h, v = (1 - 2 * (y + 0.5) / h) * th;
        return normalize(fwd + right * u + up * v);
    }
    Vec3d hit(const render::Frame& f, float depth, const Vec3d& d) const {
        const auto& V = f.camera.view;
        const auto& P = f.camera.projection;
        const double ndc = 2.0 * double(depth) - 1.0;
        const double zv = -double(P[3][2]) / (ndc + double(P[2][2]));
        const double v0 = double(V[0][2]), v1 = double(V[1][2]), v2 = double(V[2][2]), v3 = double(V[3][2]);
        const double z0 = v0 * eye[0] + v1 * eye[1] + v2 * eye[2] + v3;
        const double dz = v0 * d[0] + v1 * d[1] + v2 * d[2];
        return eye + d * ((zv - z0) / dz);
    }
};

std::string camera_json(const Vec3d& eye, const Vec3d& target) {
    char buf[300];
    std::snprintf(buf, sizeof buf, R"("camera": {"eye": [%.17g, %.17g, %.17g], "target": [%.17g, %.17g, %.17g], "fov_y": 30})", eye[0], eye[1], eye[2],
                  target[0], target[1], target[2]);
    return buf;
}

/// Uncovered pixels whose 8 neighbours are all covered.
long pinholes(const render::Image& img, int w, int h) {
    long n = 0;
    const auto covered = [&](int x, int y) { return img.depth[std::size_t(y) * std::size_t(w) + std::size_t(x)] < 1.0f; };
    for (int y = 1; y + 1 < h; ++y)
        for (int x = 1; x + 1 < w; ++x) {
            if (covered(x, y)) continue;
            bool all = true;
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx)
                    if ((dx || dy) && !covered(x + dx, y + dy)) all = false;
            n += all;
        }
    return n;
}

}  // namespace

TEST_CASE("an isolated atom's skin is its van der Waals sphere: pieces, rays, no pinholes, culling on and off") {
    const Vec3d c{{10.5, -3.25, 40.0}};
    const double r = 1.7;
    for (const double s : {0.5, 0.2, 0.9}) {
        CAPTURE(s);
        const skin::SkinSurface skin({{c, r, {}}}, s);
        const auto& pieces = skin.pieces();
        double longest = 0;
        for (const auto& p : pieces)
            for (int a = 0; a < 4; ++a)
                for (int b = a + 1; b < 4; ++b) longest = std::max(longest, length(p.tet[std::size_t(a)] - p.tet[std::size_t(b)]));
        std::printf("[skin] one atom, s = %g: %zu cells, %zu pieces (longest edge %.2f A), worst check %.2e\n", s, skin.stats().cells, pieces.size(),
                    longest, skin.stats().worst_check);
        REQUIRE(pieces.size() >= 4);
        std::mt19937 rng(7);
        double worst = 0;
        for (const auto& p : pieces)
            for (int i = 0; i < 20; ++i) {
                const Vec3d x = random_point(rng, p.tet);
                const Vec3d d = x - c;
                // CGAL's function of a ball's cell is (1 - s) (|x - c|^2 - r^2).
                worst = std::max(worst, std::fabs(evaluate(p.q, x) / (1 - s) - (dot(d, d) - r * r)));
            }
        CHECK(worst < 1e-11);  // |x|^2 ~ 1700 here
    }
    // The scene: a one-atom PDB file, drawn by the CPU reference.
    skin::install_scene_builder();
    TempDir dir;
    dir.write("one.pdb", atom(1, "C", c[0], c[1], c[2]) + "END\n");
    const Vec3d eye = c + Vec3d{{2.0, 3.1, 7.4}};
    const int w = 240, h = 180;
    const PixelRays rays(eye, c, w, h);
    for (const bool culling : {true, false}) {
        CAPTURE(culling);
        scene::Scene sc = scene::parse_scene("{" + camera_json(eye, c) + R"(, "objects": [{"pdb": "one.pdb", "style": "skin"}]})", "s.json", dir.path);
        sc.options.culling = culling;
        const render::Frame f = render::build_frame(sc, w, h);
        const render::Image img = render::render_cpu(f.primitives, f.camera, f.light, f.options);
        long inside = 0, holes = 0, outside_hits = 0, far_hits = 0;
        double worst_r = 0;
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                const Vec3d d = rays.dir(x, y);
                const double tc = -dot(eye - c, d);
                const double miss = length(eye - c + d * tc);
                const double px = tc * 2 * rays.th / h;
                const float depth = img.depth[std::size_t(y) * w + std::size_t(x)];
                if (miss < r - 1.5 * px) {
                    ++inside;
                    if (!(depth < 1.0f)) ++holes;
                } else if (miss > r + 1.5 * px && depth < 1.0f) {
                    ++outside_hits;
                }
                if (!(depth < 1.0f) || miss > r - 1.5 * px) continue;
                const Vec3d p = rays.hit(f, depth, d);
                if (-dot(normalize(p - c), d) < 0.2) continue;
                const double err = std::fabs(length(p - c) - r);
                worst_r = std::max(worst_r, err);
                far_hits += err > 1e-3;
            }
        std::printf("[skin] one atom, culling %s: %ld interior pixels, %ld holes, %ld hits outside, worst | |p - c| - r | = %.2e\n",
                    culling ? "on" : "off", inside, holes, outside_hits, worst_r);
        CHECK(inside > 10000);
        CHECK(holes == 0);
        CHECK(outside_hits == 0);
        CHECK(far_hits == 0);
    }
}

TEST_CASE("two overlapping atoms: the pieces are CGAL's functions, hits lie on the skin, normals are continuous (C1)") {
    const std::vector<scene::SkinBall> balls = two_atoms();
    const skin::SkinSurface skin(balls, 0.5);
    const auto& pieces = skin.pieces();
    std::printf("[skin] two atoms: %zu cells, %zu pieces, worst check %.2e, CGAL %.3f s, pieces %.3f s\n", skin.stats().cells, pieces.size(),
                skin.stats().worst_check, skin.stats().seconds_cgal, skin.stats().seconds_pieces);
    REQUIRE(pieces.size() > 8);
    // Each piece equals its cell's value() at random points of the cell (the size is ~1 A, values ~1).
    std::mt19937 rng(3);
    double worst = 0, worst_grad = 0;
    for (const auto& p : pieces)
        for (int i = 0; i < 20; ++i) {
            const Vec3d x = random_point(rng, p.tet);
            worst = std::max(worst, std::fabs(evaluate(p.q, x) - skin.cell_value(p.cell, x)));
            worst_grad = std::max(worst_grad, length(gradient(p.q, x) - skin.cell_gradient(p.cell, x)));
        }
    std::printf("[skin] two atoms: worst |piece - value()| = %.2e, |grad piece - gradient()| = %.2e\n", worst, worst_grad);
    CHECK(worst < 1e-12);
    CHECK(worst_grad < 1e-12);

    // C1: on faces shared by two pieces, at points of the surface (bisection along random chords
    // of the face), the other piece vanishes too and the normals agree.
    std::map<std::array<std::array<double, 3>, 3>, std::vector<std::size_t>> faces;
    for (std::size_t i = 0; i < pieces.size(); ++i)
        for (int skip = 0; skip < 4; ++skip) {
            std::array<std::array<double, 3>, 3> key{};
            int n = 0;
            for (int k = 0; k < 4; ++k)
                if (k != skip) key[std::size_t(n++)] = {pieces[i].tet[std::size_t(k)][0], pieces[i].tet[std::size_t(k)][1], pieces[i].tet[std::size_t(k)][2]};
            std::sort(key.begin(), key.end());
            faces[key].push_back(i);
        }
    long shared = 0, tested = 0;
    double worst_value = 0, worst_angle = 0;
    for (const auto& [key, who] : faces) {
        if (who.size() != 2) continue;
        ++shared;
        const auto& a = pieces[who[0]];
        const auto& b = pieces[who[1]];
        const Vec3d v[3] = {Vec3d{{key[0][0], key[0][1], key[0][2]}}, Vec3d{{key[1][0], key[1][1], key[1][2]}}, Vec3d{{key[2][0], key[2][1], key[2][2]}}};
        std::uniform_real_distribution<double> u(0, 1);
        const auto on_face = [&] {
            double x = u(rng), y = u(rng);
            if (x + y > 1) x = 1 - x, y = 1 - y;
            return v[0] + (v[1] - v[0]) * x + (v[2] - v[0]) * y;
        };
        for (int i = 0; i < 30; ++i) {
            Vec3d p = on_face(), q = on_face();
            double fp = evaluate(a.q, p), fq = evaluate(a.q, q);
            if (fp * fq > 0) continue;
            for (int it = 0; it < 80; ++it) {
                const Vec3d m = (p + q) * 0.5;
                const double fm = evaluate(a.q, m);
                if ((fm < 0) == (fp < 0)) p = m, fp = fm;
                else q = m, fq = fm;
            }
            const Vec3d x = (p + q) * 0.5;
            ++tested;
            const Vec3d ga = gradient(a.q, x), gb = gradient(b.q, x);
            worst_value = std::max(worst_value, std::fabs(evaluate(b.q, x)) / length(gb));
            worst_angle = std::max(worst_angle, length(normalize(ga) - normalize(gb)));
        }
    }
    std::printf("[skin] two atoms: %ld shared faces, %ld surface points on them: worst |f_b| / |grad f_b| = %.2e, worst normal difference %.2e\n",
                shared, tested, worst_value, worst_angle);
    CHECK(tested > 100);
    CHECK(worst_value < 1e-10);
    CHECK(worst_angle < 1e-7);

    // Drawn by the CPU reference (culling on and off, the same pixels): every hit satisfies CGAL's
    // value() = 0 to the window depth's resolution, and no pinholes.
    skin::install_scene_builder();
    TempDir dir;
    dir.write("two.pdb", atom(1, "C", 0, 0, 0) + atom(2, "N", 2.6, 0.3, -0.2) + "END\n");
    const Vec3d target{{1.3, 0.15, -0.1}}, eye = target + Vec3d{{1.5, 4.0, 8.5}};
    const int w = 240, h = 180;
    const PixelRays rays(eye, target, w, h);
    render::Image first;
    for (const bool culling : {true, false}) {
        CAPTURE(culling);
        scene::Scene sc = scene::parse_scene("{" + camera_json(eye, target) + R"(, "objects": [{"pdb": "two.pdb", "style": "skin"}]})", "s.json", dir.path);
        CHECK(sc.quadrics.size() == pieces.size());
        sc.options.culling = culling;
        const render::Frame f = render::build_frame(sc, w, h);
        const render::Image img = render::render_cpu(f.primitives, f.camera, f.light, f.options);
        long covered = 0, off = 0;
        double worst_d = 0;
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                const float depth = img.depth[std::size_t(y) * w + std::size_t(x)];
                if (!(depth < 1.0f)) continue;
                ++covered;
                const Vec3d d = rays.dir(x, y);
                const Vec3d p = rays.hit(f, depth, d);
                const Vec3d g = skin.gradient(p);
                if (-dot(normalize(g), d) < 0.2) continue;  // grazing: the depth resolution dominates
                const double dist = std::fabs(skin.value(p)) / length(g);
                worst_d = std::max(worst_d, dist);
                off += dist > 1e-3;
            }
        const long holes = pinholes(img, w, h);
        std::printf("[skin] two atoms, culling %s: %ld covered pixels, %ld pinholes, worst |value()| / |gradient()| at hits %.2e\n",
                    culling ? "on" : "off", covered, holes, worst_d);
        CHECK(covered > 5000);
        CHECK(holes == 0);
        CHECK(off == 0);
        if (culling) first = img;
        else CHECK(qc_render_test::image_diff(first, img, 0).coverage_diff == 0);
    }
}

TEST_CASE("the \"skin\" style: keys and errors located at the scene key") {
    skin::install_scene_builder();
    TempDir dir;
    dir.write("two.pdb", atom(1, "C", 0, 0, 0) + atom(2, "N", 2.6, 0.3, -0.2) + "END\n");
    const auto scene_with = [&](const std::string& keys) {
        return std::string(R"({"camera": {"eye": [0, 0, 12], "target": [1, 0, 0]}, "objects": [{"pdb": "two.pdb", "style": "skin")") + keys + "}]}";
    };
    const scene::Scene a = scene::parse_scene(scene_with(R"(, "shrink": 0.3, "vdw_scale": 0.9, "material": {"color": [0.2, 0.5, 0.9]})"), "s.json", dir.path);
    REQUIRE(!a.quadrics.empty());
    CHECK(a.spheres.empty());
    CHECK(a.quadrics[0].bound == scene::Quadric::Bound::tetrahedron);
    CHECK_FALSE(a.quadrics[0].two_sided);
    CHECK(a.quadrics[0].material.color[2] == doctest::Approx(0.9));
    const auto error_of = [&](const std::string& keys) {
        return std::string(parse_error_of([&] { scene::parse_scene(scene_with(keys), "s.json", dir.path); }).what());
    };
    for (const char* bad : {R"(, "shrink": 0)", R"(, "shrink": 1)", R"(, "shrink": -0.5)", R"(, "shrink": 1.5)"}) {
        const std::string e = error_of(bad);
        CAPTURE(e);
        CHECK(e.find("s.json:1:") == 0);
        CHECK(e.find("/objects/0/shrink: the shrink factor must lie in (0, 1)") != std::string::npos);
    }
    std::string e = error_of(R"(, "ball_scale": 0.3)");
    CHECK(e.find("/objects/0/ball_scale: only for \"style\": \"balls_and_sticks\"") != std::string::npos);
    e = std::string(parse_error_of([&] {
                        scene::parse_scene(R"({"objects": [{"pdb": "two.pdb", "style": "space_filling", "shrink": 0.5}]})", "s.json", dir.path);
                    }).what());
    CHECK(e.find("/objects/0/shrink: only for \"style\": \"skin\"") != std::string::npos);
    e = std::string(parse_error_of([&] { scene::parse_scene(R"({"objects": [{"pdb": "two.pdb", "shrink": 0.5}]})", "s.json", dir.path); }).what());
    CHECK(e.find("/objects/0/shrink: only for \"style\": \"skin\"") != std::string::npos);
    // Without the skin component the style is an error saying so.
    scene::set_skin_build_function(nullptr);
    e = error_of("");
    CHECK(e.find("/objects/0/style: skin surfaces need the skin component, which is not linked") != std::string::npos);
    skin::install_scene_builder();
    // The library's own checks.
    CHECK_THROWS_AS(skin::SkinSurface({}, 0.5), std::invalid_argument);
    CHECK_THROWS_AS(skin::SkinSurface(two_atoms(), 1.0), std::invalid_argument);
    CHECK_THROWS_AS(skin::SkinSurface({{Vec3d{{0, 0, 0}}, -1.0, {}}}, 0.5), std::invalid_argument);
}

TEST_CASE("a small molecule's skin: GL draws what the CPU reference draws, culling on and off") {
    scene_test::require_pymol_data();
    skin::install_scene_builder();
    // The first residues of 1TII (a few dozen atoms).
    std::ifstream in(scene_test::pymol_demo() / "1tii.pdb");
    std::string line, text;
    int atoms = 0;
    Vec3d centre{{0, 0, 0}};
    while (std::getline(in, line) && atoms < 60)
        if (line.rfind("ATOM", 0) == 0) {
            text += line + "\n";
            centre = centre + Vec3d{{std::stod(line.substr(30, 8)), std::stod(line.substr(38, 8)), std::stod(line.substr(46, 8))}};
            ++atoms;
        }
    centre = centre * (1.0 / atoms);
    TempDir dir;
    dir.write("small.pdb", text + "END\n");
    // The camera on the atoms (the outermost pieces reach a few A beyond them).
    scene::Scene s = scene::parse_scene("{" + camera_json(centre + Vec3d{{12, 9, 30}}, centre) + R"(, "objects": [{"pdb": "small.pdb", "style": "skin"}]})",
                                        "s.json", dir.path);
    REQUIRE(s.quadrics.size() > 100);
    gl::OsmesaContext ctx;
    gl::QuadricRenderer r(ctx.api());
    for (const bool cull : {true, false})
        for (const bool occlusion : {true, false}) {
            s.options.culling = cull;
            const render::Frame f = render::build_frame(s, 240, 180);
            CHECK(f.options.culling == cull);  // one-sided pieces: per-quadric culling stays on
            render::RenderOptions o = f.options;
            o.occlusion_culling = occlusion;
            o.occlusion_min_overlap = 0.0f;  // (the cull pass in every frame, however little the primitives overlap)
            r.set_primitives(f.primitives);
            r.draw(f.camera, f.light, o);
            const render::Image g = r.read();
            const render::Image c = render::render_cpu(f.primitives, f.camera, f.light, o);
            const qc_render_test::ImageDiff d = qc_render_test::image_diff(g, c, 1);
            std::printf("[skin gl vs cpu] %d atoms, %zu pieces, culling %s, occlusion culling %s: %ld covered px, %ld coverage differences, "
                        "%ld colour differences > 1 LSB, max depth difference %.3g, %ld pinholes (GL)\n",
                        atoms, s.quadrics.size(), cull ? "on" : "off", occlusion ? "on" : "off", d.covered, d.coverage_diff, d.color_diff, d.max_depth,
                        pinholes(g, 240, 180));
            CHECK(d.covered > 5000);
            CHECK(d.coverage_diff <= d.covered / 200);
            CHECK(d.color_diff <= d.covered / 100);
            CHECK(d.max_depth < 1e-4);
            CHECK(pinholes(g, 240, 180) == 0);
        }
}

/// The primitives of a skin's pieces (as the scene path makes them), in one colour.
std::vector<render::Primitive> skin_primitives(const skin::SkinSurface& skin) {
    std::vector<render::Primitive> out;
    for (const skin::Piece& p : skin.pieces()) {
        glm::dmat4 q;
        for (int j = 0; j < 4; ++j)
            for (int i = 0; i < 4; ++i) q[j][i] = p.q.q[j][i];
        shapes::TetrahedronBound tb{};
        for (std::size_t k = 0; k < 4; ++k) tb.corners[k] = glm::vec3(float(p.tet[k][0]), float(p.tet[k][1]), float(p.tet[k][2]));
        out.push_back(shapes::quadric(q, tb, {{0.8f, 0.6f, 0.4f}}));
    }
    return out;
}

TEST_CASE("refined clip tetrahedra hold every surface point of their cell and draw the same skin from fewer fragments") {
    scene_test::require_pymol_data();
    std::ifstream in(scene_test::pymol_demo() / "1tii.pdb");
    std::string line;
    std::vector<scene::SkinBall> balls;
    Vec3d centre{{0, 0, 0}};
    while (std::getline(in, line) && balls.size() < 80)
        if (line.rfind("ATOM", 0) == 0) {
            const Vec3d c{{std::stod(line.substr(30, 8)), std::stod(line.substr(38, 8)), std::stod(line.substr(46, 8))}};
            balls.push_back({c, 1.6, {}});
            centre = centre + c;
        }
    centre = centre * (1.0 / double(balls.size()));
    const skin::SkinSurface whole(balls, 0.5, 0), refined(balls, 0.5, 2);
    REQUIRE(whole.stats().cells_crossed == refined.stats().cells_crossed);
    CHECK(whole.pieces().size() == whole.stats().cells_crossed);
    // Every point of the surface in a cell lies in a kept clip tetrahedron of that cell: points
    // pulled onto CGAL's own function of the cell by Newton steps from random points of the cell
    // (kept when they stay inside it), against the kept tetrahedra in long double.
    std::map<std::size_t, std::vector<std::array<Vec3d, 4>>> kept;
    std::map<std::size_t, std::array<Vec3d, 4>> cells;
    for (const skin::Piece& p : refined.pieces()) {
        kept[p.cell].push_back(p.tet);
        cells[p.cell] = p.cell_tet;
    }
    std::mt19937 rng(5);
    long samples = 0, outside = 0;
    double volume_whole = 0, volume_kept = 0;
    const auto vol = [](const std::array<Vec3d, 4>& t) { return std::fabs(dot(t[1] - t[0], cross(t[2] - t[0], t[3] - t[0]))) / 6.0; };
    const auto inside = [](const std::array<Vec3d, 4>& t, const Vec3d& x) { return qc_exact::in_tetrahedron(t, x, 1e-9L); };
    for (const auto& [cell, tet] : cells) {
        volume_whole += vol(tet);
        for (const auto& t : kept[cell]) volume_kept += vol(t);
        for (int n = 0; n < 40; ++n) {
            Vec3d x = random_point(rng, tet);
            for (int it = 0; it < 30; ++it) {
                const Vec3d g = refined.cell_gradient(cell, x);
                const double gg = dot(g, g);
                if (!(gg > 0)) break;
                x = x - g * (refined.cell_value(cell, x) / gg);
            }
            if (!(std::fabs(refined.cell_value(cell, x)) < 1e-9) || !inside(tet, x)) continue;
            ++samples;
            bool found = false;
            for (const auto& t : kept[cell]) found = found || inside(t, x);
            outside += !found;
        }
    }
    // The same picture (the same quadrics, clipped to smaller tetrahedra) from fewer fragments.
    const int w = 240, h = 180;
    const render::Camera cam = qc_render_test::look_at(vec3(centre[0] + 12, centre[1] + 9, centre[2] + 30), vec3(centre[0], centre[1], centre[2]),
                                                       vec3(0.0, 1.0, 0.0), qc_render_test::perspective(30, double(w) / h, 5, 100));
    render::Light light;
    render::RenderOptions o;
    o.width = w;
    o.height = h;
    render::FrameStats sw, sr;
    const render::Image a = render::render_cpu(skin_primitives(whole), cam, light, o, &sw);
    const render::Image b = render::render_cpu(skin_primitives(refined), cam, light, o, &sr);
    const qc_render_test::ImageDiff d = qc_render_test::image_diff(a, b, 1);
    std::printf("[skin refinement] %zu atoms: %zu crossed cells -> %zu clip tetrahedra (%.1f%% of the cells' volume); %ld surface points, %ld outside "
                "every kept tetrahedron; CPU image %ld covered px, %ld coverage / %ld colour (> 1 LSB) differences, max depth difference %.2g; "
                "fragments cast %llu -> %llu (%.2fx fewer)\n",
                balls.size(), whole.stats().cells_crossed, refined.pieces().size(), 100.0 * volume_kept / volume_whole, samples, outside, d.covered,
                d.coverage_diff, d.color_diff, d.max_depth, static_cast<unsigned long long>(sw.fragments), static_cast<unsigned long long>(sr.fragments),
                double(sw.fragments) / double(std::max<std::uint64_t>(1, sr.fragments)));
    CHECK(samples > 20000);
    CHECK(outside == 0);
    CHECK(volume_kept < 0.5 * volume_whole);
    CHECK(d.covered > 5000);
    CHECK(d.coverage_diff <= d.covered / 2000);
    CHECK(d.color_diff <= d.covered / 500);
    // (Depths differ where neighbouring cells' pieces overlap within the clip test's slack, 2^-12
    // of a clip tetrahedron: smaller for the refined ones; as between GL and the CPU above.)
    CHECK(d.max_depth < 1e-4);
    CHECK(sr.fragments < sw.fragments);
}

// Figures, not a check (minutes: CGAL's mesh refinement); run it with
//     build/tests/test_skin -tc="CGAL's own*" --no-skip
TEST_CASE("CGAL's own triangulated skin (make_skin_surface_mesh_3) against the quadric pieces: build time, size, error [figures]" *
          doctest::skip()) {
    scene_test::require_pymol_data();
    // The first 200 atoms of IL2 (their van der Waals balls), s = 0.5: CGAL's mesher and its
    // exact mixed complex take minutes and gigabytes on the whole protein.
    const scene::Molecule m = scene::read_pdb(scene_test::pymol_demo() / "il2.pdb");
    std::vector<scene::SkinBall> balls;
    for (const scene::Atom& a : m.atoms)
        if (balls.size() < 200) balls.push_back({a.position, a.element->vdw, {}});
    const skin::SkinSurface skin(balls, 0.5);
    const skin::Stats& st = skin.stats();
    const double pieces_s = st.seconds_cgal + st.seconds_pieces;
    std::printf("[skin vs mesh] IL2, first %zu atoms, s = 0.5: quadric pieces %zu (of %zu cells), %.2f s (CGAL mixed complex %.2f s + pieces %.2f s), "
                "exact to rounding (worst check %.1e)\n",
                balls.size(), st.pieces, st.cells, pieces_s, st.seconds_cgal, st.seconds_pieces, st.worst_check);
    for (int sub = 0; sub <= 1; ++sub) {
        const skin::MeshFigures f = skin::cgal_mesh(balls, 0.5, sub);
        std::printf("[skin vs mesh] IL2, CGAL mesh with %d subdivision step(s): %zu triangles (%.2f per quadric piece), %.2f s (%.2fx the pieces' "
                    "build), worst distance from the skin %.3g A (vertices and triangle centroids)\n",
                    sub, f.triangles, double(f.triangles) / double(st.pieces), f.seconds, f.seconds / pieces_s, f.worst_distance);
        CHECK(f.triangles > 0);
    }
}
