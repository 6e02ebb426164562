// tools/quadcast/bench_spline_error.cpp -- `quadcast bench spline-error`: isosurface position error
// against frame time for QSS, S31, trilinear and marching cubes on analytic functions
//
// The functions: Marschner-Lobb (f_M = 6, alpha = 1/4, on [-1,1]^3, ρ = 0.5) and the 3-D Franke
// function (on [0,1]^3, ρ = 0.5 by default: the surface around the main peak near (2/9,2/9,2/9)
// and the second one near (7/9,1/3,5/9)), sampled on n^3 grids (src/volume/synthetic.cpp).
//
// The view: orthographic, looking at the domain's centre from the direction (0.42, 0.31, 0.85)
// (oblique to every grid axis), the image square and just enclosing the sphere around the
// evaluation box. Orthographic keeps the pixel rays parallel, so every grid size sees the same
// rays and the error along a ray is a distance in the domain. The evaluation box is the domain
// shrunk by 15% of its side on every side: it keeps the clamp-to-edge boundary cubes of the
// splines (which reach 1.5 voxels inward at n = 16) out of the statistics.
//
// The metric, per pixel whose reconstructed first hit λ_r lies in the evaluation box: the
// analytic g(λ) = f(o + λ d) - ρ on the same float ray (o, d of `render::pixel_ray`; |d| = 1,
// so λ is a domain distance) is sampled in long double on [λ_r - w, λ_r + w] (w = `--window`
// voxels, default 3) in steps of w/24; each sign change is refined by 40 bisection steps and the
// root nearest λ_r is the true hit. The error is |λ_r - λ_true|, reported in voxel units h
// (the grid spacing) and in domain units: median, mean, RMS, max. A hit without any sign change in
// the window is an outlier (counted, not in the statistics). Along the ray the error is the
// surface's normal offset divided by the cosine of the incidence angle, so near-silhouette
// pixels dominate mean, RMS and max (max is close to the window); the median is robust to them.
//
// Times, one run, on the CPU: preprocessing (the method's `prepare`), and the median of
// `--frames` frames after one untimed frame (whose λ image is the one measured); a frame is the
// λ image of all pixels, no shading. Ratios are relative to trilinear at the same n.
#include "quadcast/camera.hpp"
#include "bench_spline_error.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <memory>
#include <numbers>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "commands.hpp"
#include "timing.hpp"
#include "quadcast/image/image_io.hpp"
#include "plot.hpp"
#include "quadcast/gl/isosurface_renderer.hpp"
#include "quadcast/gl/mesh_renderer.hpp"
#include "quadcast/gl/osmesa_context.hpp"
#include "quadcast/gl/quadric_renderer.hpp"
#include "quadcast/render/cpu_renderer.hpp"
#include "quadcast/render/spline_cpu_renderer.hpp"
#include "quadcast/shading.hpp"
#include "quadcast/spline/marching_cubes.hpp"
#include "quadcast/scene/scene_render.hpp"
#include "quadcast/volume/synthetic.hpp"

namespace quadcast::cli {

namespace {

using Clock = std::chrono::steady_clock;

constexpr float no_hit = std::numeric_limits<float>::quiet_NaN();

/// The λ image of a camera: per pixel `pixel_ray`, its λ range of window depth [0, 1]
/// (`depth_range_lambda`), and cast(origin, dir, λ_min, λ_max) -> λ or NaN; rows in parallel.
template <class Cast>
LambdaImage cast_image(const render::Camera& camera, int width, int height, unsigned threads, Cast&& cast) {
    const render::FrameSetup f = render::frame_setup(camera, width, height);
    LambdaImage img;
    img.width = width;
    img.height = height;
    img.lambda.assign(std::size_t(width) * height, no_hit);
    const int n_threads = threads ? int(threads) : int(std::max(1u, std::thread::hardware_concurrency()));
    render::cpu_detail::parallel_for(height, n_threads, [&](int y, int) {
        for (int x = 0; x < width; ++x) {
            const render::PixelRay ray = render::pixel_ray(f, x, y);
            double lmin = 0, lmax = 0;
            render::depth_range_lambda(f, dot(f.vz_row, ray.dir), lmin, lmax);
            img.lambda[std::size_t(y) * width + x] = cast(ray.origin, ray.dir, lmin, lmax);
        }
    });
    return img;
}

// ---- Marching cubes, ray cast over its cells -----------------------------------------------------

/// The MC mesh of a volume with its triangles bucketed by cell (CSR: cell c owns triangles
/// first[c] .. first[c+1]-1), everything in index space.
struct McModel {
    spline::McMesh mesh;
    std::vector<std::uint32_t> first;
    int cx = 0, cy = 0, cz = 0;  ///< cells per axis
    Vec3<double> origin, spacing;
};

McModel prepare_mc(const volume::VolumeData& v, float iso) {
    McModel m;
    m.mesh = spline::marching_cubes(v.grid, iso);
    m.cx = v.nx() - 1;
    m.cy = v.ny() - 1;
    m.cz = v.nz() - 1;
    m.origin = v.origin;
    m.spacing = v.spacing;
    const std::size_t cells = std::size_t(m.cx) * m.cy * m.cz;
    m.first.assign(cells + 1, 0);
    for (const std::int32_t c : m.mesh.triangle_cell) ++m.first[std::size_t(c) + 1];
    for (std::size_t c = 0; c < cells; ++c) m.first[c + 1] += m.first[c];
    return m;
}

/// Ray/triangle (Möller & Trumbore 1997) in double, two-sided; the barycentric tests allow
/// 1e-12 so that a ray through a shared edge hits one of its triangles. Returns t or +Inf.
double ray_triangle(const Vec3<double>& o, const Vec3<double>& d, const Vec3<double>& a, const Vec3<double>& b, const Vec3<double>& c) {
    constexpr double inf = std::numeric_limits<double>::infinity(), eps = 1e-12;
    const Vec3<double> e1 = b - a, e2 = c - a, p = cross(d, e2);
    const double det = dot(e1, p);
    if (det == 0.0 || !std::isfinite(det)) return inf;
    const double inv = 1.0 / det;
    const Vec3<double> s = o - a;
    const double u = dot(s, p) * inv;
    if (u < -eps || u > 1.0 + eps) return inf;
    const Vec3<double> q = cross(s, e1);
    const double w = dot(d, q) * inv;
    if (w < -eps || u + w > 1.0 + eps) return inf;
    return dot(e2, q) * inv;
}

/// The first mesh hit on the world ray o + λ d, λ in [lmin, lmax]: the ray in index space walks
/// the cells it crosses in order (3-D DDA, Amanatides & Woo 1987, as `cast_volume_ray`); in a
/// cell with triangles the nearest hit in [lmin, lmax] wins and ends the walk (each triangle
/// lies in its cell, so no later cell has a nearer hit).
float cast_mc(const McModel& m, const Vec3<float>& o, const Vec3<float>& d, double lmin, double lmax) {
    const int n[3] = {m.cx, m.cy, m.cz};
    Vec3<double> oi{}, di{};
    double t0 = lmin, t1 = lmax;
    for (int a = 0; a < 3; ++a) {
        oi[a] = (double(o[a]) - m.origin[a]) / m.spacing[a];
        di[a] = double(d[a]) / m.spacing[a];
        if (di[a] == 0.0) {
            if (oi[a] < 0 || oi[a] > n[a]) return no_hit;
            continue;
        }
        double ta = (0.0 - oi[a]) / di[a], tb = (n[a] - oi[a]) / di[a];
        if (ta > tb) std::swap(ta, tb);
        t0 = std::max(t0, ta);
        t1 = std::min(t1, tb);
    }
    if (!(t0 <= t1)) return no_hit;
    int cell[3], step[3];
    double t_next[3], t_delta[3];
    for (int a = 0; a < 3; ++a) {
        cell[a] = std::clamp(int(std::floor(oi[a] + t0 * di[a])), 0, n[a] - 1);
        step[a] = di[a] > 0 ? 1 : di[a] < 0 ? -1 : 0;
        t_next[a] = step[a] > 0 ? (cell[a] + 1 - oi[a]) / di[a] : step[a] < 0 ? (cell[a] - oi[a]) / di[a] : HUGE_VAL;
        t_delta[a] = step[a] ? 1.0 / std::abs(di[a]) : HUGE_VAL;
    }
    while (true) {
        const std::size_t c = std::size_t(cell[0]) + std::size_t(n[0]) * (std::size_t(cell[1]) + std::size_t(n[1]) * cell[2]);
        double best = HUGE_VAL;
        for (std::uint32_t t = m.first[c]; t < m.first[c + 1]; ++t) {
            const auto& tri = m.mesh.triangles[t];
            const double s = ray_triangle(oi, di, cast<double>(m.mesh.positions[tri[0]]), cast<double>(m.mesh.positions[tri[1]]),
                                          cast<double>(m.mesh.positions[tri[2]]));
            if (s >= lmin && s <= lmax && s < best) best = s;
        }
        if (best < HUGE_VAL) return float(best);
        const int a = t_next[0] <= t_next[1] ? (t_next[0] <= t_next[2] ? 0 : 2) : (t_next[1] <= t_next[2] ? 1 : 2);
        if (t_next[a] >= t1) return no_hit;
        cell[a] += step[a];
        if (cell[a] < 0 || cell[a] >= n[a]) return no_hit;
        t_next[a] += t_delta[a];
    }
}

ErrorMethod volume_method(render::VolumeScheme scheme) {
    return {render::volume_scheme_name(scheme), [scheme](const volume::VolumeData& v, float iso, unsigned threads) -> LambdaFrame {
                auto m = std::make_shared<render::VolumeModel>(
                    render::prepare_volume(v.grid, v.origin, v.spacing, scheme, iso, {{0.8f, 0.8f, 0.8f}}, threads));
                return [m, threads](const render::Camera& cam, int w, int h) {
                    return cast_image(cam, w, h, threads, [&](const Vec3<float>& o, const Vec3<float>& d, double l0, double l1) {
                        const render::VolumeHit hit = render::cast_volume_ray(*m, o, d, l0, l1);
                        return hit.hit ? hit.lambda : no_hit;
                    });
                };
            }};
}

// ---- GL methods: the isosurface renderer and the marching-cubes mesh on llvmpipe ----------------

/// The one GL context of the GL methods (made on first use, current on this thread).
gl::OsmesaContext& gl_context() {
    static gl::OsmesaContext ctx;
    return ctx;
}

ErrorMethod gl_volume_method(render::VolumeScheme scheme) {
    return {std::string(render::volume_scheme_name(scheme)) + "-gl", [scheme](const volume::VolumeData& v, float iso, unsigned threads) -> LambdaFrame {
                struct State {
                    render::VolumeModel model;
                    gl::QuadricRenderer quadrics{gl_context().api()};
                    gl::IsosurfaceRenderer iso{gl_context().api()};
                };
                auto st = std::make_shared<State>();
                st->model = render::prepare_volume(v.grid, v.origin, v.spacing, scheme, iso, {{0.8f, 0.8f, 0.8f}}, threads, false);
                st->quadrics.set_primitives({});
                st->iso.add_volume(st->model);
                st->quadrics.add_pass(st->iso);
                return [st](const render::Camera& cam, int w, int h) {
                    render::RenderOptions o;
                    o.width = w;
                    o.height = h;
                    st->quadrics.draw(cam, render::Light{}, o);
                    return lambda_from_depth(st->quadrics.read(), cam);
                };
            }};
}

ErrorMethod gl_mc_method() {
    return {"mc-gl", [](const volume::VolumeData& v, float iso, unsigned) -> LambdaFrame {
                // The marching-cubes mesh in world coordinates (normals: index-space gradients / spacing)
                const spline::McMesh mc = spline::marching_cubes(v.grid, iso);
                gl::Mesh mesh;
                mesh.positions.reserve(mc.positions.size());
                for (std::size_t i = 0; i < mc.positions.size(); ++i) {
                    Vec3<float> p{}, n{};
                    for (int a = 0; a < 3; ++a) {
                        p[a] = float(v.origin[a] + v.spacing[a] * double(mc.positions[i][a]));
                        n[a] = float(double(mc.normals[i][a]) / v.spacing[a]);
                    }
                    mesh.positions.push_back(p);
                    mesh.normals.push_back(length(n) > 0.0f ? n : vec3(0.0f, 0.0f, 1.0f));
                }
                for (const auto& t : mc.triangles)
                    for (int k = 0; k < 3; ++k) mesh.indices.push_back(static_cast<std::uint32_t>(t[static_cast<std::size_t>(k)]));
                auto r = std::make_shared<gl::MeshRenderer>(gl_context().api());
                r->set_meshes({mesh});
                return [r](const render::Camera& cam, int w, int h) {
                    render::RenderOptions o;
                    o.width = w;
                    o.height = h;
                    r->draw(cam, render::Light{}, o);
                    return lambda_from_depth(r->read(), cam);
                };
            }};
}

// ---- The analytic functions -------------------------------------------------------------------

/// Marschner-Lobb in T (the formula of volume::marschner_lobb).
template <class T>
T marschner_lobb_t(T x, T y, T z) {
    const T pi = std::numbers::pi_v<T>, fm = 6, alpha = T(0.25);
    const T r = std::sqrt(x * x + y * y);
    return (T(1) - std::sin(pi * z / T(2)) + alpha * (T(1) + std::cos(T(2) * pi * fm * std::cos(pi * r / T(2))))) / (T(2) * (T(1) + alpha));
}

/// The 3-D Franke function in T (the formula of volume::franke3).
template <class T>
T franke_t(T x, T y, T z) {
    const T a = 9 * x, b = 9 * y, c = 9 * z;
    return T(0.75) * std::exp(-((a - 2) * (a - 2) + (b - 2) * (b - 2) + (c - 2) * (c - 2)) / T(4)) +
           T(0.75) * std::exp(-(a + 1) * (a + 1) / T(49) - (b + 1) / T(10) - (c + 1) / T(10)) +
           T(0.5) * std::exp(-((a - 7) * (a - 7) + (b - 3) * (b - 3) + (c - 5) * (c - 5)) / T(4)) -
           T(0.2) * std::exp(-(a - 4) * (a - 4) - (b - 7) * (b - 7) - (c - 5) * (c - 5));
}

struct TestFunction {
    std::string name;
    long double (*f)(long double, long double, long double);
    volume::VolumeData (*sample)(int);
    double lo, hi;  ///< the domain [lo, hi]^3
    double iso;
};

/// Checks that the long double formula is the one the volumes are sampled from.
void check_formula(const TestFunction& tf, double (*reference)(double, double, double)) {
    for (int i = 0; i < 64; ++i) {
        const double t = (i + 0.37) / 64.0, x = tf.lo + (tf.hi - tf.lo) * t, y = tf.lo + (tf.hi - tf.lo) * (1 - t * t),
                     z = tf.lo + (tf.hi - tf.lo) * std::fmod(7 * t, 1.0);
        if (std::abs(double(tf.f(x, y, z)) - reference(x, y, z)) > 1e-12)
            throw std::logic_error("the long double " + tf.name + " differs from the sampled function");
    }
}

// ---- Error statistics ---------------------------------------------------------------------------

struct ErrorStats {
    long hits = 0;       ///< pixels with a reconstructed hit
    long evaluated = 0;  ///< ... whose hit lies in the evaluation box
    long outliers = 0;   ///< ... without a true root within the window
    double sum = 0, sum2 = 0, max = 0;  ///< of |λ_r - λ_true| in domain units, over evaluated - outliers
    std::vector<double> errors;          ///< the errors themselves (for the median)
    void add(const ErrorStats& o) {
        hits += o.hits;
        evaluated += o.evaluated;
        outliers += o.outliers;
        sum += o.sum;
        sum2 += o.sum2;
        max = std::max(max, o.max);
        errors.insert(errors.end(), o.errors.begin(), o.errors.end());
    }
    long measured() const { return evaluated - outliers; }
    double mean() const { return measured() ? sum / double(measured()) : std::numeric_limits<double>::quiet_NaN(); }
    double rms() const { return measured() ? std::sqrt(sum2 / double(measured())) : std::numeric_limits<double>::quiet_NaN(); }
    /// The median error (sorts `errors`).
    double median() {
        if (errors.empty()) return std::numeric_limits<double>::quiet_NaN();
        const auto mid = errors.begin() + std::ptrdiff_t(errors.size() / 2);
        std::nth_element(errors.begin(), mid, errors.end());
        return *mid;
    }
};

/// The true root of g(λ) = f(o + λ d) - ρ nearest λ_r within [λ_r - w, λ_r + w] (see the top of
/// this file); NaN if g has no sign change there.
long double true_root(const TestFunction& tf, const Vec3<float>& o, const Vec3<float>& d, long double lr, long double w) {
    const long double O[3] = {o[0], o[1], o[2]}, D[3] = {d[0], d[1], d[2]}, rho = tf.iso;
    auto g = [&](long double s) { return tf.f(O[0] + s * D[0], O[1] + s * D[1], O[2] + s * D[2]) - rho; };
    constexpr int steps = 48;
    long double best = NAN, prev_s = lr - w, prev_g = g(prev_s);
    for (int i = 1; i <= steps; ++i) {
        const long double s = lr - w + 2 * w * i / steps, gs = g(s);
        if ((prev_g <= 0) != (gs <= 0) || prev_g == 0) {
            long double a = prev_s, b = s, ga = prev_g;
            if (ga != 0)
                for (int k = 0; k < 40; ++k) {
                    const long double m = (a + b) / 2, gm = g(m);
                    if ((gm <= 0) == (ga <= 0)) a = m, ga = gm;
                    else b = m;
                }
            const long double r = ga == 0 ? a : (a + b) / 2;
            if (std::isnan(best) || std::abs(r - lr) < std::abs(best - lr)) best = r;
        }
        prev_s = s;
        prev_g = gs;
    }
    return best;
}

ErrorStats measure(const LambdaImage& img, const render::Camera& camera, const TestFunction& tf, const double box_lo[3],
                   const double box_hi[3], double window, unsigned threads) {
    const render::FrameSetup f = render::frame_setup(camera, img.width, img.height);
    const int n_threads = threads ? int(threads) : int(std::max(1u, std::thread::hardware_concurrency()));
    std::vector<ErrorStats> per(static_cast<std::size_t>(n_threads));
    render::cpu_detail::parallel_for(img.height, n_threads, [&](int y, int th) {
        ErrorStats& st = per[static_cast<std::size_t>(th)];
        for (int x = 0; x < img.width; ++x) {
            const float lr = img.lambda[std::size_t(y) * img.width + x];
            if (std::isnan(lr)) continue;
            ++st.hits;
            const render::PixelRay ray = render::pixel_ray(f, x, y);
            bool inside = true;
            for (int a = 0; a < 3; ++a) {
                const double p = double(ray.origin[a]) + double(lr) * double(ray.dir[a]);
                inside = inside && p >= box_lo[a] && p <= box_hi[a];
            }
            if (!inside) continue;
            ++st.evaluated;
            const long double t = true_root(tf, ray.origin, ray.dir, lr, window);
            if (std::isnan(t)) {
                ++st.outliers;
                continue;
            }
            const double e = double(std::abs(t - (long double)lr));
            st.sum += e;
            st.sum2 += e * e;
            st.max = std::max(st.max, e);
            st.errors.push_back(e);
        }
    });
    ErrorStats all;
    for (const ErrorStats& s : per) all.add(s);
    return all;
}

// ---- The bench ----------------------------------------------------------------------------------

struct SplineErrorOptions {
    std::vector<int> sizes{16, 32, 64, 128};
    std::vector<std::string> functions{"marschner-lobb", "franke"};
    std::vector<std::string> methods;  ///< empty: all
    int frames = 3, width = 512;
    unsigned threads = 0;
    double franke_iso = 0.5, window = 3.0;
    std::string plot = "spline_error";
};

struct Row {
    int n = 0;
    double h = 0;
    std::string method;
    double prep_ms = 0, frame_ms = 0;
    ErrorStats err;
    double median = 0;
};

/// The camera of the bench for a domain [lo, hi]^3: orthographic along -dir (see the top).
render::Camera bench_camera(double lo, double hi, double box_radius) {
    const double c = 0.5 * (lo + hi), R = std::sqrt(3.0) * 0.5 * (hi - lo);
    const Vec3<double> dir = normalize(Vec3<double>{{0.42, 0.31, 0.85}});
    const Vec3<double> centre{{c, c, c}};
    const Vec3<double> eye = centre + dir * (3.0 * R);
    render::Camera cam;
    cam.view = cast<float>(quadcast::look_at(eye, centre, Vec3<double>{{0.0, 0.0, 1.0}}));
    cam.projection = cast<float>(quadcast::orthographic(2.0 * box_radius, 1.0, R, 5.0 * R));
    cam.eye = cast<float>(eye);
    cam.orthographic = true;
    return cam;
}

std::string fmt(const char* f, double v) {
    char buf[64];
    std::snprintf(buf, sizeof buf, f, v);
    return buf;
}

void run_spline_error(const SplineErrorOptions& opt) {
    std::vector<TestFunction> functions;
    for (const std::string& name : opt.functions) {
        if (name == "marschner-lobb") {
            functions.push_back({name, marschner_lobb_t<long double>, volume::marschner_lobb_volume, -1.0, 1.0, 0.5});
            check_formula(functions.back(), volume::marschner_lobb);
        } else if (name == "franke") {
            functions.push_back({name, franke_t<long double>, volume::franke_volume, 0.0, 1.0, opt.franke_iso});
            check_formula(functions.back(), volume::franke3);
        } else {
            throw std::invalid_argument("--functions: unknown function '" + name + "' (expected marschner-lobb or franke)");
        }
    }
    std::vector<ErrorMethod> methods;
    for (ErrorMethod& m : spline_error_methods())
        if (opt.methods.empty() || std::find(opt.methods.begin(), opt.methods.end(), m.name) != opt.methods.end()) methods.push_back(std::move(m));
    for (const std::string& name : opt.methods)
        if (std::none_of(methods.begin(), methods.end(), [&](const ErrorMethod& m) { return m.name == name; }))
            throw std::invalid_argument("--methods: unknown method '" + name + "'");
    if (!opt.plot.empty()) {
        const std::filesystem::path dir = std::filesystem::path(opt.plot).parent_path();
        if (!dir.empty() && !std::filesystem::is_directory(dir))
            throw std::invalid_argument("--plot " + opt.plot + ": directory '" + dir.string() + "' does not exist");
    }
    const unsigned hw = std::max(1u, std::thread::hardware_concurrency());
    std::printf("quadcast bench spline-error: %dx%d orthographic, view direction (0.42, 0.31, 0.85), %d timed frames (median), %u threads\n",
                opt.width, opt.width, opt.frames, opt.threads ? opt.threads : hw);
    std::printf("error = |lambda_reconstructed - lambda_true| along the pixel ray; true root in long double within +-%.3g voxels;"
                " evaluation box = domain shrunk by 15%% per side\n",
                opt.window);
    for (const TestFunction& tf : functions) {
        const double inset = 0.15 * (tf.hi - tf.lo);
        const double box_lo[3] = {tf.lo + inset, tf.lo + inset, tf.lo + inset}, box_hi[3] = {tf.hi - inset, tf.hi - inset, tf.hi - inset};
        const render::Camera cam = bench_camera(tf.lo, tf.hi, std::sqrt(3.0) * 0.5 * (box_hi[0] - box_lo[0]));
        std::printf("\n%s on [%g, %g]^3, isovalue %g, evaluation box [%g, %g]^3\n", tf.name.c_str(), tf.lo, tf.hi, tf.iso, box_lo[0], box_hi[0]);
        std::printf("%5s %-12s %9s %9s %8s %7s %6s %9s %9s %9s %9s %10s %10s %10s %10s\n", "n", "method", "prep ms", "frame ms", "x trilin",
                    "pixels", "outl.", "median/h", "mean/h", "rms/h", "max/h", "median", "mean", "rms", "max");
        std::vector<Row> rows;
        for (const int n : opt.sizes) {
            const volume::VolumeData v = tf.sample(n);
            const double h = v.spacing[0];
            std::vector<Row> at_n;
            for (const ErrorMethod& m : methods) {
                Row r;
                r.n = n;
                r.h = h;
                r.method = m.name;
                auto t0 = Clock::now();
                const LambdaFrame frame = m.prepare(v, float(tf.iso), opt.threads);
                r.prep_ms = ms_since(t0);
                const LambdaImage img = frame(cam, opt.width, opt.width);
                std::vector<double> times;
                for (int i = 0; i < opt.frames; ++i) {
                    t0 = Clock::now();
                    (void)frame(cam, opt.width, opt.width);
                    times.push_back(ms_since(t0));
                }
                std::sort(times.begin(), times.end());
                r.frame_ms = times[times.size() / 2];
                r.err = measure(img, cam, tf, box_lo, box_hi, opt.window * h, opt.threads);
                r.median = r.err.median();
                r.err.errors = {};
                at_n.push_back(r);
            }
            double tri_ms = std::numeric_limits<double>::quiet_NaN();
            for (const Row& r : at_n)
                if (r.method == "trilinear") tri_ms = r.frame_ms;
            for (const Row& r : at_n) {
                std::printf("%5d %-12s %9.1f %9.1f %8s %7ld %6ld %9.3e %9.3e %9.3e %9.3e %10.3e %10.3e %10.3e %10.3e\n", r.n, r.method.c_str(),
                            r.prep_ms, r.frame_ms, std::isnan(tri_ms) ? "-" : fmt("%.2f", r.frame_ms / tri_ms).c_str(), r.err.evaluated,
                            r.err.outliers, r.median / h, r.err.mean() / h, r.err.rms() / h, r.err.max / h, r.median, r.err.mean(), r.err.rms(),
                            r.err.max);
                rows.push_back(r);
            }
            std::fflush(stdout);
        }
        if (!opt.plot.empty()) {
            LogLogPlot p;
            p.title = tf.name + " (iso " + fmt("%g", tf.iso) + "): RMS error vs frame time";
            p.x_label = "frame time (ms; CPU methods on 2 threads, -gl on llvmpipe), " + std::to_string(opt.width) + "x" + std::to_string(opt.width);
            p.y_label = "RMS isosurface position error (domain units)";
            for (const ErrorMethod& m : methods) {
                PlotSeries s;
                s.name = m.name;
                for (const Row& r : rows)
                    if (r.method == m.name) {
                        s.x.push_back(r.frame_ms);
                        s.y.push_back(r.err.rms());
                        s.labels.push_back(std::to_string(r.n));
                    }
                p.series.push_back(std::move(s));
            }
            const std::string path = opt.plot + "_" + tf.name + ".png";
            render::write_png(path, draw_loglog(p, 800, 600));
            std::printf("wrote %s (points labelled with n)\n", path.c_str());
        }
    }
}

}  // namespace

LambdaImage lambda_from_depth(const render::Image& img, const render::Camera& cam) {
    LambdaImage out;
    out.width = img.width;
    out.height = img.height;
    out.lambda.assign(img.depth.size(), no_hit);
    const Vec4<double> pz = cast<double>(vec4(cam.projection[2][2], cam.projection[3][2], cam.projection[2][3], cam.projection[3][3]));
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x) {
            const float d = img.depth[std::size_t(img.height - 1 - y) * img.width + x];
            if (d >= 1.0f) continue;
            out.lambda[std::size_t(y) * img.width + x] = float(-view_z_from_depth(double(d), pz));
        }
    return out;
}

std::vector<ErrorMethod> spline_error_methods() {
    std::vector<ErrorMethod> m{volume_method(render::VolumeScheme::qss), volume_method(render::VolumeScheme::s31),
                               volume_method(render::VolumeScheme::trilinear)};
    m.push_back({"mc", [](const volume::VolumeData& v, float iso, unsigned threads) -> LambdaFrame {
                     auto model = std::make_shared<McModel>(prepare_mc(v, iso));
                     return [model, threads](const render::Camera& cam, int w, int h) {
                         return cast_image(cam, w, h, threads, [&](const Vec3<float>& o, const Vec3<float>& d, double l0, double l1) {
                             return cast_mc(*model, o, d, l0, l1);
                         });
                     };
                 }});
    for (render::VolumeScheme s : {render::VolumeScheme::qss, render::VolumeScheme::s31, render::VolumeScheme::trilinear}) m.push_back(gl_volume_method(s));
    m.push_back(gl_mc_method());
    return m;
}

void add_bench_spline_error(CLI::App& bench) {
    auto o = std::make_shared<SplineErrorOptions>();
    CLI::App* cmd = bench.add_subcommand("spline-error",
                                         "isosurface position error vs frame time: QSS, S31, trilinear, marching cubes on Marschner-Lobb and Franke");
    cmd->add_option("--sizes", o->sizes, "samples per axis of the grids (default 16,32,64,128)")->delimiter(',')->check(CLI::Range(4, 256));
    cmd->add_option("--functions", o->functions, "marschner-lobb and/or franke (default both)")->delimiter(',');
    cmd->add_option("--methods", o->methods, "subset of qss,s31,trilinear,mc (CPU) and qss-gl,s31-gl,trilinear-gl,mc-gl (OpenGL) (default all)")->delimiter(',');
    cmd->add_option("--frames", o->frames, "timed frames per method and grid (median)")->check(CLI::Range(1, 1000));
    cmd->add_option("--width", o->width, "image width = height in pixels")->check(CLI::Range(16, 8192));
    cmd->add_option("--threads", o->threads, "render threads (0: all cores)");
    cmd->add_option("--franke-iso", o->franke_iso, "isovalue of the Franke function")->check(CLI::Range(0.0, 1.0));
    cmd->add_option("--window", o->window, "half-width of the true-root search around a hit, in voxels")->check(CLI::Range(0.5, 50.0));
    cmd->add_option("--plot", o->plot, "write PREFIX_<function>.png: log-log RMS error vs frame time (\"\": no plot)");
    cmd->callback([o] {
        try {
            run_spline_error(*o);
        } catch (const std::exception& e) {
            std::fprintf(stderr, "quadcast bench spline-error: %s\n", e.what());
            throw CLI::RuntimeError(2);
        }
    });
}

}  // namespace quadcast::cli
