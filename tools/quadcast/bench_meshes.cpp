// tools/quadcast/bench_meshes.cpp -- `quadcast bench meshes`: sphere impostors against tessellated spheres of equal geometric error
//
// The scenes of `quadcast bench spheres` (N random spheres in the unit cube, radius 0.3 N^(-1/3),
// 1024x768, 30 degree perspective): once as ray-cast impostors (QuadricRenderer), once as
// geodesic spheres (quadcast/render/sphere_mesh.hpp) drawn by MeshRenderer, in one GL context.
//
// Tessellation: the geodesic sphere of frequency f is inscribed in the sphere and contains the
// concentric sphere of radius r (1 - s_f) (s_f = `sphere_mesh_sagitta`), so its outline lies
// between the outlines of the two spheres. For a sphere whose centre is seen at angle phi from
// the view axis at distance rho, the two outlines are nested conics whose widest gap is radial,
// at the far end of the major axis: F (tan(phi + asin(r / rho)) - tan(phi + asin(r (1 - s_f) / rho)))
// pixels, F = P11 height / 2 the focal length in pixels. The scene gets the smallest f for which
// that bound is <= the target (0.5 px) for every sphere (the worst is the nearest).
//
// Measured, not only bounded:
// - The sphere with the largest bound alone, both ways, 4x4 sub-pixel shifts of the projection:
//   every pixel centre against the analytic cone (as tests/gl/test_gl_sphere_projection.cpp:
//   covered iff its ray lies in the cone from the eye tangent to the sphere, in double); a
//   mismatching pixel centre lies between the drawn and the true outline, so the largest distance
//   of one from the true conic (to first order, |f| / |grad f|) is a sampled lower bound of the
//   outline error. Depth: the view z of the exact front hit of the pixel ray against the view z
//   read back from the depth buffer, where both cover the pixel.
// - The whole scene against the CPU reference renderer (`render_cpu`, exact up to float
//   rounding: tests/render/test_cpu_sphere.cpp), each sphere coloured by its index (ambient-only
//   material, so a pixel's colour is the index of the sphere it shows): pixels that show another
//   sphere (or background) than the reference, and the view-z difference where they show the same.
// Frame times: the median over --frames frames of each, interleaved (impostor, mesh; then mesh,
// impostor; ...) after a warm-up, so that load from other processes hits both alike.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "quadcast/camera.hpp"
#include "commands.hpp"
#include "timing.hpp"
#include "quadcast/image/image_io.hpp"
#include "quadcast/gl/mesh_renderer.hpp"
#include "quadcast/gl/osmesa_context.hpp"
#include "quadcast/gl/quadric_renderer.hpp"
#include "quadcast/render/cpu_renderer.hpp"
#include "quadcast/render/sphere_mesh.hpp"
#include "quadcast/scene/scene_render.hpp"

namespace quadcast::cli {

namespace {

struct MeshesOptions {
    std::vector<int> counts{1000, 10000, 100000};
    int frames = 5, width = 1024, height = 768;
    double max_error = 0.5;  ///< outline error target in pixels
    std::string png;         ///< write <png><N>_impostor.png and <png><N>_mesh.png when not empty
};

/// The spheres of `quadcast bench spheres` (same generator and seed).
std::vector<render::Primitive> random_spheres(int n, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(0.0f, 1.0f), c(0.2f, 1.0f);
    const float r = 0.3f * std::pow(static_cast<float>(n), -1.0f / 3.0f);
    std::vector<render::Primitive> out(static_cast<std::size_t>(n));
    for (auto& p : out) {
        p.shape.q.q = identity<float, 4>();
        p.shape.q.q[3][3] = -r * r;
        p.shape.center = vec3(u(rng), u(rng), u(rng));
        p.shape.radius = r;
        p.shape.axis = vec3(0.0f, 0.0f, 1.0f);
        p.shape.half_length = std::numeric_limits<float>::infinity();
        p.variant = render::Variant::ellipsoid;
        p.color = vec3(c(rng), c(rng), c(rng));
    }
    return out;
}

/// The tessellated sphere of a primitive: the unit mesh scaled by the radius around the centre
/// (in double, rounded to float), normals = the unit vertices.
gl::Mesh sphere_mesh(const render::Primitive& p, const render::SphereMesh& unit) {
    gl::Mesh m;
    m.color = p.color;
    const Vec3<double> c = cast<double>(p.shape.center);
    const double r = static_cast<double>(p.shape.radius);
    m.positions.reserve(unit.vertices.size());
    m.normals.reserve(unit.vertices.size());
    for (const auto& v : unit.vertices) {
        m.positions.push_back(cast<float>(c + v * r));
        m.normals.push_back(cast<float>(v));
    }
    m.indices.reserve(3 * unit.triangles.size());
    for (const auto& t : unit.triangles) m.indices.insert(m.indices.end(), t.begin(), t.end());
    return m;
}

/// A sphere as the camera sees it: distance rho of the centre, angle phi of the centre off the
/// view axis, in double from the float camera.
struct SphereView {
    double rho = 0, phi = 0, r = 0;
};

SphereView sphere_view(const render::Camera& cam, const render::Primitive& p) {
    const Vec4<double> cv = cast<double>(cam.view) * vec4(cast<double>(p.shape.center), 1.0);
    SphereView s;
    s.rho = std::sqrt(cv[0] * cv[0] + cv[1] * cv[1] + cv[2] * cv[2]);
    s.phi = std::acos(std::clamp(-cv[2] / s.rho, -1.0, 1.0));
    s.r = static_cast<double>(p.shape.radius);
    return s;
}

/// The widest gap in pixels between the outlines of the sphere and of the concentric sphere of
/// radius r (1 - sagitta) (see the top of the file); +Inf when the outline reaches the horizon.
double outline_gap(const SphereView& s, double sagitta, double focal_px) {
    if (s.r >= s.rho) return std::numeric_limits<double>::infinity();
    const double a1 = std::asin(s.r / s.rho), a0 = std::asin(s.r * (1.0 - sagitta) / s.rho);
    if (s.phi + a1 >= M_PI / 2) return std::numeric_limits<double>::infinity();
    return focal_px * (std::tan(s.phi + a1) - std::tan(s.phi + a0));
}

/// Half the radial extent of the sphere's outline in pixels (its projected radius).
double projected_radius(const SphereView& s, double focal_px) {
    const double a = std::asin(std::min(1.0, s.r / s.rho));
    return 0.5 * focal_px * (std::tan(s.phi + a) - std::tan(s.phi - a));
}

/// The analytic image of one sphere for a perspective camera whose projection has
/// P10 = P30 = P01 = P31 = 0 (as tests/gl/test_gl_sphere_projection.cpp): pixel rays
/// d = R^T ((x_ndc + P20) / P00, (y_ndc + P21) / P11, -1), cone test against the tangent cone.
struct AnalyticSphere {
    double rt[3][3];
    double p00, p11, p20, p21, p22, p32;
    Vec3<double> w;  // centre - eye
    double r2, w2;
    int width, height;

    AnalyticSphere(const render::Camera& cam, const render::Primitive& p, int w_px, int h_px) : width(w_px), height(h_px) {
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j) rt[i][j] = static_cast<double>(cam.view[i][j]);
        p00 = cam.projection[0][0];
        p11 = cam.projection[1][1];
        p20 = cam.projection[2][0];
        p21 = cam.projection[2][1];
        p22 = cam.projection[2][2];
        p32 = cam.projection[3][2];
        w = cast<double>(p.shape.center) - cast<double>(cam.eye);
        r2 = static_cast<double>(p.shape.radius) * static_cast<double>(p.shape.radius);
        w2 = dot(w, w);
    }
    Vec3<double> ray(double px, double py) const {
        const double v[3] = {(2.0 * px / width - 1.0 + p20) / p00, (2.0 * py / height - 1.0 + p21) / p11, -1.0};
        Vec3<double> d{};
        for (int i = 0; i < 3; ++i) d[i] = rt[i][0] * v[0] + rt[i][1] * v[1] + rt[i][2] * v[2];
        return d;
    }
    double cone(double px, double py) const {
        const Vec3<double> d = ray(px, py);
        const double dw = dot(d, w);
        return dw * dw - (w2 - r2) * dot(d, d);
    }
    bool covered(int x, int y) const { return cone(x + 0.5, y + 0.5) >= 0 && dot(ray(x + 0.5, y + 0.5), w) > 0; }
    double boundary_distance(int x, int y) const {
        const double px = x + 0.5, py = y + 0.5;
        const double gx = cone(px + 0.5, py) - cone(px - 0.5, py), gy = cone(px, py + 0.5) - cone(px, py - 0.5);
        return std::fabs(cone(px, py)) / std::sqrt(gx * gx + gy * gy);
    }
    /// View z of the front hit of pixel (x, y)'s ray (the ray's view z is -1 per unit of t).
    double hit_z(int x, int y) const {
        const Vec3<double> d = ray(x + 0.5, y + 0.5);
        const double a = dot(d, d), b = dot(d, w), disc = b * b - a * (w2 - r2);
        return -(b - std::sqrt(std::max(0.0, disc))) / a;
    }
    /// View z of a window depth (inverse of `window_depth` for P23 = -1, P33 = 0).
    double depth_to_z(double depth) const { return p32 / (-(2.0 * depth - 1.0) - p22); }
};

/// What a renderer drew against the exact image.
struct Accuracy {
    long mismatches = 0;
    double outline_px = 0;  ///< largest distance of a mismatching pixel centre from the true outline
    double depth = 0;       ///< largest |view z - exact view z| where both cover
};

/// Renders `draw_one` at 4x4 sub-pixel shifts and compares with the analytic sphere.
template <class Draw>
Accuracy measure_single(const render::Camera& cam, const render::Primitive& p, int w, int h, Draw&& draw_one) {
    Accuracy acc;
    for (int j = 0; j < 16; ++j) {
        render::Camera c = cam;
        const double sx = ((j % 4) + 0.5) / 4.0 - 0.5, sy = ((j / 4) + 0.5) / 4.0 - 0.5;
        c.projection[2][0] = static_cast<float>(static_cast<double>(cam.projection[2][0]) - 2.0 * sx / w);
        c.projection[2][1] = static_cast<float>(static_cast<double>(cam.projection[2][1]) - 2.0 * sy / h);
        const render::Image img = draw_one(c);
        const AnalyticSphere ex(c, p, w, h);
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                const float d = img.depth[static_cast<std::size_t>(h - 1 - y) * w + x];
                const bool drawn = d < 1.0f, want = ex.covered(x, y);
                if (drawn != want) {
                    ++acc.mismatches;
                    acc.outline_px = std::max(acc.outline_px, ex.boundary_distance(x, y));
                } else if (drawn) {
                    acc.depth = std::max(acc.depth, std::fabs(ex.depth_to_z(d) - ex.hit_z(x, y)));
                }
            }
    }
    return acc;
}

/// Sphere i's index colour: i + 1 in base 256, one digit per channel (byte / 255; 0 = background).
Vec3<float> index_color(std::size_t i) {
    const std::size_t k = i + 1;
    return vec3(static_cast<float>(k & 255u) / 255.0f, static_cast<float>((k >> 8) & 255u) / 255.0f, static_cast<float>((k >> 16) & 255u) / 255.0f);
}

/// Pixels that show another sphere than the reference (both drawn with `index_color` and an
/// ambient-only material), and the largest view-z difference where they show the same one.
Accuracy compare_scene(const render::Image& img, const render::Image& ref, const render::Camera& cam) {
    const double p22 = cam.projection[2][2], p32 = cam.projection[3][2];
    auto z_of = [&](float d) { return p32 / (-(2.0 * static_cast<double>(d) - 1.0) - p22); };
    Accuracy acc;
    for (std::size_t i = 0; i < ref.depth.size(); ++i) {
        const bool same = std::equal(&img.rgba[4 * i], &img.rgba[4 * i + 3], &ref.rgba[4 * i]);
        if (!same) ++acc.mismatches;
        else if (ref.depth[i] < 1.0f) acc.depth = std::max(acc.depth, std::fabs(z_of(img.depth[i]) - z_of(ref.depth[i])));
    }
    return acc;
}

double time_ms(const std::function<void()>& f) {
    const auto t0 = std::chrono::steady_clock::now();
    f();
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

struct Row {
    int n = 0, frequency = 0;
    std::size_t triangles = 0;
    double radius_px = 0, bound_px = 0;
    Accuracy single_imp, single_mesh, scene_imp, scene_mesh;
    double ms_imp = 0, ms_mesh = 0;
};

void run_meshes(const MeshesOptions& o) {
    gl::OsmesaContext ctx;
    std::printf("quadcast bench meshes: %dx%d, 30 degree perspective, random spheres in the unit cube, r = 0.3 N^(-1/3);\n"
                "impostors (QuadricRenderer) vs geodesic spheres (MeshRenderer) with outline error <= %.2f px\n",
                o.width, o.height, o.max_error);
    std::printf("%s\n", ctx.info().summary().c_str());
    render::Camera cam;
    const double aspect = static_cast<double>(o.width) / o.height;
    cam.view = cast<float>(quadcast::look_at(vec3(0.5, 0.5, 3.2), vec3(0.5, 0.5, 0.5), vec3(0.0, 1.0, 0.0)));
    cam.projection = cast<float>(quadcast::perspective(30.0, aspect, 1.0, 5.0));
    cam.eye = vec3(0.5f, 0.5f, 3.2f);
    const double focal_px = static_cast<double>(cam.projection[1][1]) * o.height / 2.0;
    render::Light light;
    light.direction = vec3(-0.4f, -0.6f, -1.0f);
    render::RenderOptions ro;
    ro.width = o.width;
    ro.height = o.height;
    std::vector<Row> rows;
    for (int n : o.counts) {
        Row row;
        row.n = n;
        const std::vector<render::Primitive> spheres = random_spheres(n, 7);
        std::vector<SphereView> views;
        views.reserve(spheres.size());
        for (const auto& p : spheres) views.push_back(sphere_view(cam, p));
        // The coarsest frequency whose outline bound holds for every sphere
        render::SphereMesh unit;
        std::size_t worst = 0;
        for (int f = 1;; ++f) {
            unit = render::geodesic_sphere(f);
            const double s = render::sphere_mesh_sagitta(unit);
            double b = 0;
            for (std::size_t i = 0; i < views.size(); ++i) {
                const double g = outline_gap(views[i], s, focal_px);
                if (g > b) { b = g; worst = i; }
            }
            if (b <= o.max_error || f == 4096) {
                row.frequency = f;
                row.bound_px = b;
                break;
            }
        }
        row.radius_px = projected_radius(views[worst], focal_px);
        std::vector<gl::Mesh> meshes;
        meshes.reserve(spheres.size());
        for (const auto& p : spheres) meshes.push_back(sphere_mesh(p, unit));

        gl::QuadricRenderer qr(ctx.api());
        gl::MeshRenderer mr(ctx.api());
        qr.set_primitives(spheres);
        mr.set_meshes(meshes);
        row.triangles = mr.triangle_count();
        meshes = {};
        // Warm-up (compiles the programs), then interleaved timing
        qr.draw(cam, light, ro);
        mr.draw(cam, light, ro);
        std::vector<double> t_imp, t_mesh;
        for (int i = 0; i < o.frames; ++i) {
            auto imp = [&] { t_imp.push_back(time_ms([&] { qr.draw(cam, light, ro); })); };
            auto mesh = [&] { t_mesh.push_back(time_ms([&] { mr.draw(cam, light, ro); })); };
            if (i % 2 == 0) { imp(); mesh(); } else { mesh(); imp(); }
        }
        row.ms_imp = median(t_imp);
        row.ms_mesh = median(t_mesh);
        if (!o.png.empty()) {
            render::write_png(o.png + std::to_string(n) + "_impostor.png", qr.read());
            render::write_png(o.png + std::to_string(n) + "_mesh.png", mr.read());
        }
        // The whole scene against the CPU reference, every sphere in its index colour
        std::vector<render::Primitive> indexed = spheres;
        for (std::size_t i = 0; i < indexed.size(); ++i) indexed[i].color = index_color(i);
        render::RenderOptions flat = ro;
        flat.material = vec4(1.0f, 0.0f, 0.0f, 1.0f);
        flat.background = vec3(0.0f, 0.0f, 0.0f);
        const render::Image ref = render::render_cpu(indexed, cam, light, flat);
        qr.set_primitives(indexed);
        qr.draw(cam, light, flat);
        row.scene_imp = compare_scene(qr.read(), ref, cam);
        for (const auto& p : indexed) meshes.push_back(sphere_mesh(p, unit));
        mr.set_meshes(meshes);
        meshes = {};
        mr.draw(cam, light, flat);
        row.scene_mesh = compare_scene(mr.read(), ref, cam);
        // The worst sphere alone against the analytic sphere
        const render::Primitive& p = spheres[worst];
        qr.set_primitives({p});
        mr.set_meshes({sphere_mesh(p, unit)});
        row.single_imp = measure_single(cam, p, o.width, o.height, [&](const render::Camera& c) { qr.draw(c, light, ro); return qr.read(); });
        row.single_mesh = measure_single(cam, p, o.width, o.height, [&](const render::Camera& c) { mr.draw(c, light, ro); return mr.read(); });
        rows.push_back(row);
        std::printf("%d spheres: frequency %d (%zu triangles per sphere), nearest sphere %.1f px radius\n", n, row.frequency,
                    unit.triangles.size(), row.radius_px);
        std::fflush(stdout);
    }
    std::printf("\naccuracy. outline: the sphere with the largest outline bound (the nearest) alone, 16 sub-pixel shifts,\n"
                "against the analytic cone: bound, mismatching pixel centres, their largest distance from the true outline\n"
                "(a sampled lower bound of the error), largest |view z error| (world units) where both cover;\n"
                "scene: pixels that show another sphere (or background) than the CPU reference, largest |view z difference|\n"
                "where they show the same sphere\n");
    std::printf("%8s %5s %9s | %8s %11s %9s %9s %9s %9s | %8s %8s %9s %9s\n", "spheres", "freq", "radius px", "bound px",
                "mismatch", "imp px", "mesh px", "imp dz", "mesh dz", "imp px", "mesh px", "imp dz", "mesh dz");
    std::printf("%8s %5s %9s | %8s %11s %9s %9s %9s %9s | %8s %8s %9s %9s\n", "", "", "", "", "imp/mesh", "", "", "", "", "", "", "", "");
    for (const Row& r : rows)
        std::printf("%8d %5d %9.2f | %8.3f %5ld/%-5ld %9.2e %9.3f %9.2e %9.2e | %8ld %8ld %9.2e %9.2e\n", r.n, r.frequency, r.radius_px,
                    r.bound_px, r.single_imp.mismatches, r.single_mesh.mismatches, r.single_imp.outline_px, r.single_mesh.outline_px,
                    r.single_imp.depth, r.single_mesh.depth, r.scene_imp.mismatches, r.scene_mesh.mismatches, r.scene_imp.depth, r.scene_mesh.depth);
    std::printf("\nframe time: median of %d frames each, interleaved, whole frame incl. glFinish\n", o.frames);
    std::printf("%8s %5s %14s %14s %14s %16s\n", "spheres", "freq", "triangles", "impostor ms", "mesh ms", "mesh / impostor");
    for (const Row& r : rows)
        std::printf("%8d %5d %14zu %14.1f %14.1f %15.2fx\n", r.n, r.frequency, r.triangles, r.ms_imp, r.ms_mesh, r.ms_mesh / r.ms_imp);
}

}  // namespace

void add_bench_meshes(CLI::App& bench) {
    auto o = std::make_shared<MeshesOptions>();
    CLI::App* cmd = bench.add_subcommand("meshes", "sphere impostors vs tessellated spheres of equal outline error (<= 0.5 px)");
    cmd->add_option("--counts", o->counts, "sphere counts");
    cmd->add_option("--frames", o->frames, "timed frames per renderer")->check(CLI::Range(1, 1000));
    cmd->add_option("--max-error", o->max_error, "outline error target in pixels")->check(CLI::Range(0.01, 100.0));
    cmd->add_option("--png", o->png, "write <PREFIX><N>_impostor.png and <PREFIX><N>_mesh.png of each scene");
    cmd->callback([o] { run_meshes(*o); });
}

}  // namespace quadcast::cli
