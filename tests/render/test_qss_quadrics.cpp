// tests/render/test_qss_quadrics.cpp -- QSS pieces as quadrics clipped to their tetrahedra
// (shapes::isosurface_quadrics, Stoll's path) against the BB form, the spline's own evaluation,
// an exact sphere and the Bézier ray caster (Kalbe's path) on the CPU
#include <doctest/doctest.h>

#include <cmath>
#include <cstdio>
#include <random>

#include "quadcast/bb/bezier.hpp"
#include "quadcast/isosurface.hpp"
#include "quadcast/render/spline_cpu_renderer.hpp"
#include "quadcast/spline/quadric_pieces.hpp"
#include "quadcast/spline/spline.hpp"
#include "render/render_testing.hpp"

using namespace qc_render_test;
namespace spl = quadcast::spline;
namespace bb = quadcast::bb;
using quadcast::render::VolumeScheme;
using quadcast::BoundingTet;
using quadcast::Mat;
using quadcast::Vec;

namespace {

template <class T>
T eval_quadric(const Quadric<T>& q, const Vec3<T>& x) {
    const T v[4] = {x[0], x[1], x[2], T(1)};
    T s = 0;
    for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 4; ++c) s += v[r] * q.q[c][r] * v[c];
    return s;
}

Vec<double, 4> random_lambda(std::mt19937& rng) {
    std::exponential_distribution<double> e;
    Vec<double, 4> l{};
    double sum = 0;
    for (int k = 0; k < 4; ++k) sum += l[k] = e(rng);
    for (int k = 0; k < 4; ++k) l[k] /= sum;
    return l;
}

template <class F>
spl::Volume<float> sample(int n, double h, F f) {
    spl::Volume<float> v(n, n, n);
    for (int k = 0; k < n; ++k)
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i) v.at(i, j, k) = float(f(h * i, h * j, h * k));
    return v;
}

/// View-space z (negative) of a window depth under a perspective projection, in long double.
long double view_z_of_depth(const Mat4<float>& p, float depth) {
    const long double ndc = 2.0L * depth - 1.0L;
    return -static_cast<long double>(p[3][2]) / (static_cast<long double>(p[2][2]) + ndc);
}

/// The world point of NDC (x, y, z) of a camera (double).
Vec3<double> unproject(const Camera& cam, double x, double y, double z) {
    const Mat4<float> vp = cam.projection * cam.view;
    Mat<double, 4, 4> m{};
    for (int a = 0; a < 4; ++a)
        for (int b = 0; b < 4; ++b) m[a][b] = vp[a][b];
    const Vec<double, 4> v = quadcast::host_inverse(m) * Vec<double, 4>{{x, y, z, 1.0}};
    return vec3(v[0] / v[3], v[1] / v[3], v[2] / v[3]);
}

double marschner_lobb(double x, double y, double z) {
    const double a = 0.25, fm = 6.0, r = std::sqrt(x * x + y * y);
    return (1.0 - std::sin(M_PI * z / 2.0) + a * (1.0 + std::cos(2.0 * M_PI * fm * std::cos(M_PI * r / 2.0)))) / (2.0 * (1.0 + a));
}

}  // namespace

TEST_CASE("each QSS piece's quadric equals its BB polynomial at random points of its tetrahedron") {
    // Reference: de Casteljau in long double on the coefficients of `tet_from_determining_set`.
    std::mt19937 rng(71);
    std::uniform_real_distribution<double> u(-3, 3);
    double worst = 0;
    for (int cube = 0; cube < 40; ++cube) {
        spl::DeterminingSet<double, 2> d{};
        for (int n = 0; n < spl::d_count(2); ++n) d[n] = u(rng);
        const double rho = u(rng) * 0.3;
        for (int t = 0; t < spl::tets_per_cube; ++t) {
            const bb::BezierTet<double, 2> b = spl::tet_from_determining_set<2>(d, t);
            bb::BezierTet<long double, 2> bl{};
            double size = 0;
            for (int n = 0; n < b.size; ++n) {
                bl[n] = static_cast<long double>(b[n]) - rho;
                size = std::max(size, std::fabs(b[n] - rho));
            }
            const Quadric<double> q = spl::qss_piece_quadric(d, t, rho);
            const BoundingTet<double> tet = spl::local_tet<double>(t);
            for (int s = 0; s < 25; ++s) {
                const Vec<double, 4> l = random_lambda(rng);
                Vec3<double> x{};
                for (int k = 0; k < 4; ++k) x = x + tet.p[k] * l[k];
                Vec<long double, 4> ll{};
                for (int k = 0; k < 4; ++k) ll[k] = l[k];
                const long double want = bb::evaluate(bl, ll);
                worst = std::max(worst, double(std::fabs(static_cast<long double>(eval_quadric(q, x)) - want)) / size);
            }
        }
    }
    std::printf("[qss quadrics] piece quadric against de Casteljau (long double): max error %.2e of the largest |c - rho|\n", worst);
    CHECK(worst < 1e-14);
}

TEST_CASE("cube_local_to_world moves a quadric to x = centre + spacing u / 2") {
    std::mt19937 rng(72);
    std::uniform_real_distribution<double> u(-1, 1);
    double worst = 0;
    for (int i = 0; i < 200; ++i) {
        Quadric<double> q{};
        for (int c = 0; c < 4; ++c)
            for (int r = c; r < 4; ++r) q.q[c][r] = q.q[r][c] = u(rng);
        const Vec3<double> centre = vec3(100 * u(rng), 100 * u(rng), 100 * u(rng));
        const Vec3<double> spacing = vec3(0.5 + std::fabs(u(rng)), 0.5 + std::fabs(u(rng)), 0.5 + std::fabs(u(rng)));
        const Quadric<double> w = spl::cube_local_to_world(q, centre, spacing);
        const Vec3<double> p = vec3(u(rng), u(rng), u(rng));
        Vec3<double> x{};
        for (int a = 0; a < 3; ++a) x[a] = centre[a] + spacing[a] * p[a] / 2;
        worst = std::max(worst, std::fabs(eval_quadric(w, x) - eval_quadric(q, p)));
    }
    CHECK(worst < 1e-8);  // world entries ~1e4 (centre up to 100)
}

TEST_CASE("isosurface_quadrics: the pieces equal the spline (its own evaluation) minus the isovalue") {
    const int n = 20;
    const double h = 0.1;
    const spl::Volume<float> vol = sample(n, h, [](double x, double y, double z) { return marschner_lobb(2 * x - 1, 2 * y - 1, 2 * z - 1); });
    const float iso = 0.5f;
    const quadcast::render::VolumeModel m = quadcast::shapes::isosurface(vol, {0, 0, 0}, {h, h, h}, iso, VolumeScheme::qss);
    const std::vector<Primitive> pieces = quadcast::shapes::isosurface_quadrics(m);
    std::size_t relevant = 0;
    for (const auto mask : m.tet_mask) relevant += std::size_t(__builtin_popcount(mask));
    std::printf("[qss quadrics] Marschner-Lobb %d^3: %zu active cubes, %zu pieces\n", n, m.active, pieces.size());
    REQUIRE(pieces.size() > 1000);
    CHECK(pieces.size() <= relevant);
    // The spline in index coordinates (the reference path: spline::build_spline + evaluate).
    const spl::SplineGrid<2, float> g = spl::build_spline<2>(vol, {{0.0, 0.0, 0.0}}, 1.0, 2);
    // A primitive's quadric is normalised (scaled), so compare scale-free: f / |grad f| (the
    // first-order distance to the zero set) of the piece and of the spline, at random points of
    // the piece's tetrahedron, found from its barycentric planes (`shape.planes`).
    std::mt19937 rng(73);
    double worst = 0;
    long compared = 0;
    for (std::size_t i = 0; i < pieces.size(); i += 7) {
        const Primitive& p = pieces[i];
        Mat<double, 4, 4> pl{};
        for (int k = 0; k < 4; ++k)
            for (int a = 0; a < 4; ++a) pl[a][k] = double(p.shape.planes[k][a]);
        const Mat<double, 4, 4> inv = quadcast::host_inverse(pl);
        const Quadric<double> q{cast<double>(p.shape.q.q)};
        const Vec3<double> c = cast<double>(p.shape.center);
        for (int s = 0; s < 4; ++s) {
            const Vec<double, 4> xl = inv * random_lambda(rng);
            const Vec3<double> local = vec3(xl[0] / xl[3], xl[1] / xl[3], xl[2] / xl[3]);
            const Vec3<double> gq = quadcast::gradient(q, local);
            const auto r = spl::evaluate(g, quadcast::Vec<double, 3>{{(local[0] + c[0]) / h, (local[1] + c[1]) / h, (local[2] + c[2]) / h}});
            const double gs = std::sqrt(double(r.gradient[0] * r.gradient[0] + r.gradient[1] * r.gradient[1] + r.gradient[2] * r.gradient[2])) / h;
            if (gs < 0.05) continue;  // flat spots: the ratio says nothing
            const double dq = eval_quadric(q, local) / length(gq), ds = (double(r.value) - double(iso)) / gs;
            worst = std::max(worst, std::fabs(dq - ds) / (h * (1 + std::fabs(ds) / h)));
            ++compared;
        }
    }
    std::printf("[qss quadrics] %ld points: |f / |grad f| of the piece - the same of spline::evaluate| <= %.2e h (1 + |d| / h)\n", compared, worst);
    CHECK(compared > 1000);
    CHECK(worst < 1e-4);
}

TEST_CASE("a sampled |x - c|^2 gives pieces on the exact sphere of radius sqrt(iso - 3 h^2 / 4), with no pinholes") {
    // QSS reproduces a quadratic p up to the constant (h^2 / 8) Δp (spec; tests/spline), here
    // 6 h^2 / 8: the isosurface is a sphere, and every piece must lie on it.
    const int n = 24;
    const double h = 0.1, cc = 1.15;
    const spl::Volume<float> vol = sample(n, h, [&](double x, double y, double z) { return (x - cc) * (x - cc) + (y - cc) * (y - cc) + (z - cc) * (z - cc); });
    const float iso = 0.49f;
    const double r = std::sqrt(double(iso) - 0.75 * h * h);
    const quadcast::render::VolumeModel m = quadcast::shapes::isosurface(vol, {0, 0, 0}, {h, h, h}, iso, VolumeScheme::qss);
    const std::vector<Primitive> pieces = quadcast::shapes::isosurface_quadrics(m);
    const int w = 240, hh = 180;
    const Vec3<double> centre = vec3(cc, cc, cc), eye = centre + vec3(0.9, 1.3, 3.1);
    const double fov = 30;
    const Camera cam = look_at(eye, centre, vec3(0.0, 1.0, 0.0), perspective(fov, double(w) / hh, 0.5, 10));
    RenderOptions o;
    o.width = w;
    o.height = hh;
    const Image img = render_cpu(pieces, cam, Light{vec3(-0.3f, -0.5f, -1.0f)}, o);
    const Vec3<double> fwd = normalize(centre - eye);
    const Vec3<double> right = normalize(cross(fwd, vec3(0.0, 1.0, 0.0)));
    const Vec3<double> up = cross(right, fwd);
    const double th = std::tan(fov * M_PI / 360.0);
    long inside = 0, holes = 0, outside = 0, far = 0;
    double worst = 0;
    for (int y = 0; y < hh; ++y)
        for (int x = 0; x < w; ++x) {
            const double su = (2 * (x + 0.5) / w - 1) * th * w / hh, sv = (2 * (y + 0.5) / hh - 1) * th;  // y: window rows, bottom up
            const Vec3<double> d = normalize(fwd + right * su + up * sv);
            const double tc = -dot(eye - centre, d), miss = length(eye - centre + d * tc), px = tc * 2 * th / hh;
            const float depth = depth_at(img, x, y);
            if (miss < r - 1.5 * px) {
                ++inside;
                holes += !(depth < 1.0f);
            } else if (miss > r + 1.5 * px) {
                outside += depth < 1.0f;
            }
            if (!(depth < 1.0f) || miss > r - 1.5 * px) continue;
            // The hit on the exact ray from the window depth (the view's z axis is -fwd).
            const long double zv = view_z_of_depth(cam.projection, depth);
            const Vec3<double> p = eye + d * double(-zv / dot(d, fwd));
            if (-dot(normalize(p - centre), d) < 0.2) continue;
            const double e = std::fabs(length(p - centre) - r);
            worst = std::max(worst, e);
            far += e > 2e-4;
        }
    std::printf("[qss quadrics] sphere data: %zu pieces, %ld interior pixels, %ld holes, %ld hits outside, worst | |p - c| - r | = %.2e\n",
                pieces.size(), inside, holes, outside, worst);
    CHECK(inside > 10000);
    CHECK(holes == 0);
    CHECK(outside == 0);
    CHECK(far == 0);
}

TEST_CASE("Stoll's quadrics and Kalbe's Bézier ray casting draw the same QSS isosurface (Marschner-Lobb, CPU)") {
    const int n = 32;
    const double h = 2.0 / (n - 1);
    const spl::Volume<float> vol = sample(n, h, [](double x, double y, double z) { return marschner_lobb(x - 1, y - 1, z - 1); });
    quadcast::render::VolumeModel m = quadcast::shapes::isosurface(vol, {-1, -1, -1}, {h, h, h}, 0.5f, VolumeScheme::qss, {}, true);
    const std::vector<Primitive> pieces = quadcast::shapes::isosurface_quadrics(m);
    const int w = 240, hh = 180;
    const Camera cam = look_at(vec3(2.6, -2.2, 2.4), vec3(0.0, 0.0, -0.1), vec3(0.0, 0.0, 1.0), perspective(40, double(w) / hh, 0.5, 10));
    RenderOptions o;
    o.width = w;
    o.height = hh;
    o.culling = false;  // a level set has no outside (render::isosurface_culling_note)
    const Light light{vec3(-0.4f, 0.6f, -1.0f)};
    const Image a = render_cpu(pieces, cam, light, o);
    const Image b = quadcast::render::render_volumes_cpu({&m}, cam, light, o);
    const ImageDiff d = image_diff(a, b, 2);
    // Coverage may differ only where a neighbour pixel differs in coverage too (a silhouette).
    long isolated = 0;
    for (int y = 1; y + 1 < hh; ++y)
        for (int x = 1; x + 1 < w; ++x) {
            const auto cov = [&](const Image& im, int xx, int yy) { return depth_at(im, xx, yy) < 1.0f; };
            if (cov(a, x, y) == cov(b, x, y)) continue;
            bool edge = false;
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) edge = edge || cov(b, x + dx, y + dy) != cov(b, x, y);
            isolated += !edge;
        }
    std::printf("[qss quadrics] Marschner-Lobb %d^3, quadrics (%zu) against Bezier ray casting: %ld covered px, %ld coverage differences "
                "(%ld away from silhouettes), %ld colour differences > 2 LSB, max depth difference %.3g\n",
                n, pieces.size(), d.covered, d.coverage_diff, isolated, d.color_diff, d.max_depth);
    CHECK(d.covered > 5000);
    CHECK(isolated == 0);
    CHECK(d.coverage_diff <= d.covered / 100);
    CHECK(d.max_depth < 1e-4);
}

TEST_CASE("seen from hundreds of piece sizes away, the quadrics keep every hit the Bézier ray caster finds (CPU)") {
    // Small pieces far from the eye: the cast starts at the pieces' bounding spheres
    // (quadcast::cast_ray), not at the eye, whose distance made f(eye) and the discriminant lose
    // the root by up to 1e-4 of a piece, so that hits near a face the surface does not continue
    // across fell outside the clip and the ray went on to a farther sheet (pinholes).
    const int n = 32;
    const double h = 2.0 / (n - 1);
    const spl::Volume<float> vol = sample(n, h, [](double x, double y, double z) { return marschner_lobb(x - 1, y - 1, z - 1); });
    quadcast::render::VolumeModel m = quadcast::shapes::isosurface(vol, {-1, -1, -1}, {h, h, h}, 0.5f, VolumeScheme::qss, {}, true);
    const std::vector<Primitive> pieces = quadcast::shapes::isosurface_quadrics(m);
    const int w = 240, hh = 180;
    RenderOptions o;
    o.width = w;
    o.height = hh;
    o.culling = false;
    const Light light{vec3(-0.4f, 0.6f, -1.0f)};
    // (At 200 the cast from the eye lost 6 hits; at 600, 10^4 piece radii, the float pixel ray
    // itself is off by more than the clip's slack and 3 are lost even so: the Bezier path's hits
    // there are the spline's first crossings, the quadrics' up to 0.26 off.)
    const spl::SplineGrid<2, float> g = spl::build_spline<2>(vol, {{0.0, 0.0, 0.0}}, 1.0, 2);
    for (const double dist : {40.0, 200.0}) {
        const Vec3<double> dir = normalize(vec3(2.6, -2.2, 2.4));
        const Camera cam = look_at(vec3(dist * dir[0], dist * dir[1], dist * dir[2]), vec3(0.0, 0.0, -0.1), vec3(0.0, 0.0, 1.0),
                                   perspective(2 * std::atan(1.6 / dist) * 180 / 3.14159265358979, double(w) / hh, dist - 3, dist + 3));
        const Image a = render_cpu(pieces, cam, light, o);
        const Image b = quadcast::render::render_volumes_cpu({&m}, cam, light, o);
        const ImageDiff d = image_diff(a, b, 2);
        // Where the depths differ, the quadrics' hit must be a point of the spline's isosurface
        // (evaluated independently, in double: spline::evaluate) on the boundary of the volume's
        // domain [-1 - h/2, 1 + h/2]^3, where the surface leaves it: there the quadrics' clip slack
        // keeps the crossing and the Bezier path's exact clip does not, and the ray goes on.
        long deep = 0, unexplained = 0;
        for (std::size_t i = 0; i < a.depth.size(); ++i) {
            if (!(a.depth[i] < 1.0f && b.depth[i] < 1.0f && std::fabs(a.depth[i] - b.depth[i]) > 1e-3f)) continue;
            ++deep;
            const int px = int(i % std::size_t(w)), row = int(i / std::size_t(w));
            const Vec3<double> x = unproject(cam, (px + 0.5) / w * 2 - 1, ((hh - 1 - row) + 0.5) / hh * 2 - 1, 2.0 * double(a.depth[i]) - 1);
            const double f = double(spl::evaluate(g, quadcast::Vec<double, 3>{{(x[0] + 1) / h, (x[1] + 1) / h, (x[2] + 1) / h}}).value) - 0.5;
            const double out = std::max({std::fabs(x[0]), std::fabs(x[1]), std::fabs(x[2])}) - (1 + h / 2);
            std::printf("[qss quadrics]   pixel (%d, %d): depth %.6f (quadrics) / %.6f (Bezier); the quadrics' hit (%.6f, %.6f, %.6f): spline - iso %.2g, %.2g h off the "
                        "domain's boundary\n", px, row, double(a.depth[i]), double(b.depth[i]), x[0], x[1], x[2], f, out / h);
            unexplained += !(std::fabs(f) < 1e-4 && std::fabs(out) < 1e-3 * h);
        }
        std::printf("[qss quadrics] eye %.0f away (%.0f piece radii): %ld covered px, %ld coverage / %ld colour differences, %ld depths differ by more "
                    "than 1e-3, max depth difference %.3g\n",
                    dist, dist / (h * 0.87), d.covered, d.coverage_diff, d.color_diff, deep, d.max_depth);
        CAPTURE(dist);
        CHECK(d.covered > 6000);
        CHECK(deep <= 2);
        CHECK(unexplained == 0);
        CHECK(d.coverage_diff <= d.covered / 100);
    }
}
