// tests/render/test_spline_render.cpp -- the CPU isosurface renderer (QSS, S31, trilinear) hits the isosurface, draws discs of the right size, leaves no holes
#include <doctest/doctest.h>

#include <cmath>
#include <cstdio>

#include "quadcast/render/spline_cpu_renderer.hpp"
#include "quadcast/spline/grid.hpp"
#include "render/render_testing.hpp"

using namespace qc_render_test;
using quadcast::render::VolumeModel;
using quadcast::render::VolumeScheme;
namespace spl = quadcast::spline;

namespace {

/// n^3 samples of f on [-1,1]^3 (spacing 2/(n-1), origin -1).
template <class F>
spl::Volume<float> sample(int n, F f) {
    spl::Volume<float> v(n, n, n);
    const double h = 2.0 / (n - 1);
    for (int k = 0; k < n; ++k)
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i) v.at(i, j, k) = float(f(-1 + h * i, -1 + h * j, -1 + h * k));
    return v;
}

double marschner_lobb(double x, double y, double z) {
    const double a = 0.25, fm = 6.0, r = std::sqrt(x * x + y * y);
    return (1.0 - std::sin(M_PI * z / 2.0) + a * (1.0 + std::cos(2.0 * M_PI * fm * std::cos(M_PI * r / 2.0)))) / (2.0 * (1.0 + a));
}

/// The reconstruction's value and index-space gradient at a world point (reference evaluation,
/// independent of the renderer's walk): spline::evaluate on a grid built the same way, or the
/// trilinear formula in double.
struct Reference {
    VolumeScheme scheme;
    spl::Volume<float> vol;
    spl::SplineGrid<2, float> g2;
    spl::SplineGrid<3, float> g3;
    Vec3<double> origin, spacing;

    Reference(VolumeScheme s, const spl::Volume<float>& v, Vec3<double> o, Vec3<double> h) : scheme(s), vol(v), origin(o), spacing(h) {
        if (s == VolumeScheme::qss) g2 = spl::build_spline<2>(v, {{0.0, 0.0, 0.0}}, 1.0, 2);
        if (s == VolumeScheme::s31) g3 = spl::build_spline<3>(v, {{0.0, 0.0, 0.0}}, 1.0, 2);
    }
    void eval(const Vec3<float>& world, double& value, double& grad_norm) const {
        quadcast::Vec<double, 3> x{};
        for (int a = 0; a < 3; ++a) x[a] = (double(world[a]) - origin[a]) / spacing[a];
        quadcast::Vec<double, 3> g{};
        if (scheme == VolumeScheme::qss || scheme == VolumeScheme::s31) {
            const auto r = scheme == VolumeScheme::qss ? spl::evaluate(g2, x) : spl::evaluate(g3, x);
            value = r.value;
            for (int a = 0; a < 3; ++a) g[a] = r.gradient[a];
        } else {
            int c[3];
            double w[3];
            const int n[3] = {vol.nx, vol.ny, vol.nz};
            for (int a = 0; a < 3; ++a) {
                c[a] = std::clamp(int(std::floor(x[a])), 0, n[a] - 2);
                w[a] = x[a] - c[a];
            }
            value = 0;
            for (int k = 0; k < 8; ++k) {
                const int di = k & 1, dj = (k >> 1) & 1, dk = (k >> 2) & 1;
                const double f = vol.at(c[0] + di, c[1] + dj, c[2] + dk);
                const double wx = di ? w[0] : 1 - w[0], wy = dj ? w[1] : 1 - w[1], wz = dk ? w[2] : 1 - w[2];
                value += f * wx * wy * wz;
                g[0] += f * (di ? 1 : -1) * wy * wz;
                g[1] += f * wx * (dj ? 1 : -1) * wz;
                g[2] += f * wx * wy * (dk ? 1 : -1);
            }
        }
        grad_norm = std::sqrt(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]);
    }
};

Camera top_ortho(double half, int w, int h) {
    const double aspect = double(w) / h;
    return look_at(vec3(0.0, 0.0, 4.0), vec3(0.0, 0.0, 0.0), vec3(0.0, 1.0, 0.0),
                   orthographic(-half * aspect, half * aspect, -half, half, 0.5, 8.0), true);
}

constexpr VolumeScheme kSchemes[] = {VolumeScheme::qss, VolumeScheme::s31, VolumeScheme::trilinear};

}  // namespace

TEST_CASE("the first hit of a random ray lies on the reconstructed isosurface, and no crossing comes before it") {
    const int n = 24;
    const spl::Volume<float> vol = sample(n, marschner_lobb);
    const Vec3<double> origin{{-1.0, -1.0, -1.0}}, spacing{{2.0 / (n - 1), 2.0 / (n - 1), 2.0 / (n - 1)}};
    const float rho = 0.5f;
    for (VolumeScheme s : kSchemes) {
        const VolumeModel m = quadcast::render::prepare_volume(vol, origin, spacing, s, rho, {{0.8f, 0.8f, 0.8f}}, 2);
        const Reference ref(s, vol, origin, {{1.0, 1.0, 1.0}});
        const Reference ref_world(s, vol, origin, spacing);
        int hits = 0;
        double worst = 0;
        for (std::uint32_t it = 0; it < 3000; ++it) {
            std::mt19937 rng = rng_for(301, it);
            const Vec3<double> target = vec3(uniform(rng, -0.9, 0.9), uniform(rng, -0.9, 0.9), uniform(rng, -0.9, 0.9));
            const Vec3<double> dir = random_dir(rng);
            const Vec3<float> o = cast<float>(target - dir * 3.0), d = cast<float>(dir);
            const auto h = quadcast::render::cast_volume_ray(m, o, d, 0.0, 10.0);
            if (it < 400) {
                // No earlier (or, for a miss, no) crossing: sample the reconstruction densely along
                // the ray inside the data box up to the hit; a clear sign change is a missed root.
                const double l_end = h.hit ? double(h.lambda) - 2e-3 : 6.0;
                double prev = 0;
                bool have_prev = false;
                for (int k = 0; k <= 600; ++k) {
                    const double l = l_end * k / 600.0;
                    Vec3<double> x{};
                    bool inside = true;
                    for (int a = 0; a < 3; ++a) {
                        x[a] = double(o[a]) + l * double(d[a]);
                        inside = inside && std::abs(x[a]) <= 0.99;
                    }
                    if (!inside) {
                        have_prev = false;
                        continue;
                    }
                    double v = 0, gn = 0;
                    ref_world.eval(cast<float>(x), v, gn);
                    v -= double(rho);
                    if (have_prev && ((prev < -1e-4 && v > 1e-4) || (prev > 1e-4 && v < -1e-4)))
                        FAIL_CHECK(std::string(volume_scheme_name(s)), " ray ", it, ": a crossing at lambda ~ ", l, " before the reported ",
                                   std::string(h.hit ? "hit" : "miss"));
                    prev = v;
                    have_prev = true;
                }
            }
            if (!h.hit) continue;
            ++hits;
            double v = 0, gn = 0;
            ref_world.eval(h.point, v, gn);
            // Index-space distance to the surface ~ |v - rho| / |grad_index|; allow 1e-3 voxel
            // (the hit point is rounded to float in world units, ~1e-7) plus the roots' tolerance.
            const double dist = std::abs(v - double(rho)) / std::max(gn, 1e-6);
            worst = std::max(worst, dist);
            CHECK_MESSAGE(dist < 1e-3, std::string(volume_scheme_name(s)), " ray ", it, ": |s - rho| = ", std::abs(v - double(rho)), ", |grad| = ", gn);
        }
        std::printf("on-surface: %s %d hits of 3000 rays, worst distance %.3g voxels\n", volume_scheme_name(s), hits, worst);
        CHECK(hits > 1500);
        (void)ref;
    }
}

TEST_CASE("the sphere-distance volume |x| - R renders a disc of radius R (orthographic, seen from +z)") {
    // Sampled signed distance of a sphere of radius R = 0.6 on [-1,1]^3 with 33^3 samples. A pixel
    // whose ray passes at distance r from the centre must hit for r < R - h/2 and miss for
    // r > R + h/2, h = 1/16 the spacing (the reconstructions of |x| differ from it by O(h^2)
    // away from the centre; QSS's silhouette reaches 0.34 h outside), and the covered area is
    // within 2% of pi R^2.
    const int n = 33;
    const double R = 0.6;
    const spl::Volume<float> vol = sample(n, [&](double x, double y, double z) { return std::sqrt(x * x + y * y + z * z) - R; });
    const Vec3<double> origin{{-1.0, -1.0, -1.0}}, spacing{{2.0 / (n - 1), 2.0 / (n - 1), 2.0 / (n - 1)}};
    const int w = 160, hgt = 160;
    const double tol = 0.5 * spacing[0];
    const Camera cam = top_ortho(1.0, w, hgt);
    RenderOptions opt;
    opt.width = w;
    opt.height = hgt;
    for (VolumeScheme s : kSchemes) {
        const VolumeModel m = quadcast::render::prepare_volume(vol, origin, spacing, s, 0.0f, {{0.8f, 0.8f, 0.8f}}, 2);
        quadcast::render::VolumeFrameStats st;
        const Image img = quadcast::render::render_volumes_cpu({&m}, cam, Light{vec3(-0.3f, -0.5f, -1.0f)}, opt, &st, 2);
        int wrong = 0;
        long covered = 0;
        for (int y = 0; y < hgt; ++y)
            for (int x = 0; x < w; ++x) {
                const double px = -1.0 + (x + 0.5) * (2.0 / w), py = -1.0 + (y + 0.5) * (2.0 / hgt);
                const double r = std::sqrt(px * px + py * py);
                const bool hit = img.depth[std::size_t(hgt - 1 - y) * w + x] < 1.0f;
                covered += hit;
                if ((r < R - tol && !hit) || (r > R + tol && hit)) {
                    ++wrong;
                    if (wrong <= 5) std::printf("  wrong pixel (%d,%d) r = %.4f hit = %d\n", x, y, r, int(hit));
                }
            }
        const double area = covered * (2.0 / w) * (2.0 / hgt), expect = M_PI * R * R;
        std::printf("disc: %s covered area %.4f (pi R^2 = %.4f), %d wrong pixels, %llu pieces cast\n", volume_scheme_name(s), area,
                    expect, wrong, static_cast<unsigned long long>(st.pieces));
        CHECK_MESSAGE(wrong == 0, std::string(volume_scheme_name(s)));
        CHECK(std::abs(area - expect) < 0.02 * expect);
    }
}

TEST_CASE("Marschner-Lobb at rho = 0.5 renders without holes and with depth of the surface below every pixel") {
    // Seen from +z the ML isosurface rho = 0.5 is a height field over the whole square, so every
    // pixel whose ray passes inside [-1,1]^2 (minus a margin) must hit.
    const int n = 41;
    const spl::Volume<float> vol = sample(n, marschner_lobb);
    const Vec3<double> origin{{-1.0, -1.0, -1.0}}, spacing{{2.0 / (n - 1), 2.0 / (n - 1), 2.0 / (n - 1)}};
    const int w = 128, hgt = 128;
    const Camera cam = top_ortho(1.0, w, hgt);
    RenderOptions opt;
    opt.width = w;
    opt.height = hgt;
    for (VolumeScheme s : kSchemes) {
        const VolumeModel m = quadcast::render::prepare_volume(vol, origin, spacing, s, 0.5f, {{0.8f, 0.8f, 0.8f}}, 2);
        const Image img = quadcast::render::render_volumes_cpu({&m}, cam, Light{vec3(-0.3f, -0.5f, -1.0f)}, opt, nullptr, 2);
        int holes = 0;
        for (int y = 0; y < hgt; ++y)
            for (int x = 0; x < w; ++x) {
                const double px = -1.0 + (x + 0.5) * (2.0 / w), py = -1.0 + (y + 0.5) * (2.0 / hgt);
                if (std::abs(px) > 0.95 || std::abs(py) > 0.95) continue;
                holes += !(img.depth[std::size_t(hgt - 1 - y) * w + x] < 1.0f);
            }
        CHECK_MESSAGE(holes == 0, std::string(volume_scheme_name(s)), ": ", holes, " holes");
    }
}

TEST_CASE("the data bound of a stencil contains every BB-coefficient of the cube (the preparation's cheap skip test)") {
    namespace det = quadcast::render::spline_cpu_detail;
    CHECK(det::negative_weight<2>() == doctest::Approx(1.0 / 16.0));
    CHECK(det::negative_weight<3>() == 0.0);
    std::mt19937 rng(7);
    int tight2 = 0;
    for (int it = 0; it < 2000; ++it) {
        spl::Stencil<float> f{};
        const int kind = it % 3;
        for (int s = 0; s < spl::stencil_size; ++s)
            f[s] = kind == 0 ? float(std::uniform_real_distribution<double>(-1, 1)(rng))
                 : kind == 1 ? float(std::uniform_int_distribution<int>(0, 1)(rng) * 255)
                             : float(1e4 + std::uniform_real_distribution<double>(0, 1)(rng));
        const spl::Range<float> b2 = det::data_bound<2>(f), b3 = det::data_bound<3>(f);
        spl::DeterminingSet<float, 2> d2{};
        spl::DeterminingSet<float, 3> d3{};
        const auto e2 = spl::determining_set_from_stencil<2>(quadcast::cast<double>(f));
        const auto e3 = spl::determining_set_from_stencil<3>(quadcast::cast<double>(f));
        for (int n = 0; n < spl::d_count(2); ++n) d2[n] = float(e2[n]);
        for (int n = 0; n < spl::d_count(3); ++n) d3[n] = float(e3[n]);
        for (float v : spl::cube_coefficients<2>(d2).value) {
            REQUIRE(b2.contains(v));
            tight2 += v < *std::min_element(f.c, f.c + spl::stencil_size);
        }
        for (float v : spl::cube_coefficients<3>(d3).value) REQUIRE(b3.contains(v));
    }
    std::printf("[spline render] data bound: QSS coefficients below the data minimum in %d cases (the bound's widening is needed)\n", tight2);
    CHECK(tight2 > 0);
}

namespace {

/// Samples [first, last] along x of `vol` (all of y and z).
spl::Volume<float> x_slab(const spl::Volume<float>& vol, int first, int last) {
    spl::Volume<float> v(last - first + 1, vol.ny, vol.nz);
    for (int k = 0; k < vol.nz; ++k)
        for (int j = 0; j < vol.ny; ++j)
            for (int i = first; i <= last; ++i) v.at(i - first, j, k) = vol.at(i, j, k);
    return v;
}

}  // namespace

TEST_CASE("a volume split in two pieces with a ghost layer of one sample renders as the whole volume; without it a seam shows") {
    // The split of a distributed volume (VTK's pieces share their boundary samples; one ghost
    // level adds a sample beyond): piece A holds samples 0..s+1 and draws cubes 0..s-1 (cells
    // 0..s-1), piece B holds samples s-1..n-1 and draws cubes s..n-1 (cells s..n-2). The pieces'
    // surfaces together must be the whole volume's (same coverage, depth within rounding: the
    // pieces' origins differ), seen obliquely so that the seam plane x = s is crossed by the rays.
    const int n = 33, s = 16;
    const spl::Volume<float> vol = sample(n, marschner_lobb);
    const double h = 2.0 / (n - 1);
    const Vec3<double> origin{{-1.0, -1.0, -1.0}}, spacing{{h, h, h}};
    const Vec3<double> origin_b{{-1.0 + (s - 1) * h, -1.0, -1.0}};
    const int w = 160, hgt = 120;
    const Camera cam = look_at(Vec3<double>{{1.5, -1.8, 1.4}}, Vec3<double>{{0.0, 0.0, 0.0}}, Vec3<double>{{0.0, 0.0, 1.0}},
                               perspective(40.0, double(w) / hgt, 0.5, 10.0));
    RenderOptions opt;
    opt.width = w;
    opt.height = hgt;
    const Light light{vec3(-0.3f, -0.5f, -1.0f)};
    for (VolumeScheme sc : kSchemes) {
        const bool tri = sc == VolumeScheme::trilinear;
        const std::string name = volume_scheme_name(sc);
        INFO(name);
        const VolumeModel whole = quadcast::render::prepare_volume(vol, origin, spacing, sc, 0.5f, {{0.8f, 0.8f, 0.8f}}, 2);
        quadcast::render::IndexBox own_a, own_b;
        own_a.hi[0] = s - 1;  // (cubes / cells 0..s-1 of A)
        own_b.lo[0] = 1;      // (B's sample 0 is the whole volume's s-1: cubes s.. are its 1..)
        const VolumeModel a = quadcast::render::prepare_volume_piece(x_slab(vol, 0, s + 1), origin, spacing, sc, 0.5f, own_a, {{0.8f, 0.8f, 0.8f}}, 2);
        const VolumeModel b = quadcast::render::prepare_volume_piece(x_slab(vol, s - 1, n - 1), origin_b, spacing, sc, 0.5f, own_b, {{0.8f, 0.8f, 0.8f}}, 2);
        const Image ref = quadcast::render::render_volumes_cpu({&whole}, cam, light, opt, nullptr, 2);
        const Image split = quadcast::render::render_volumes_cpu({&a, &b}, cam, light, opt, nullptr, 2);
        const ImageDiff d = image_diff(ref, split, 1);
        MESSAGE(name, ": ", d.covered, " px covered, coverage differences ", d.coverage_diff, ", max depth difference ", d.max_depth);
        CHECK(d.covered > w * hgt / 4);
        CHECK(d.coverage_diff <= 2);
        CHECK(d.max_depth < 2e-6);
        CHECK(a.active + b.active == whole.active);
        // The drawn pieces' boxes meet at the seam.
        Vec3<double> alo{}, ahi{}, blo{}, bhi{};
        a.world_box(alo, ahi);
        b.world_box(blo, bhi);
        CHECK(ahi[0] == doctest::Approx(blo[0]).epsilon(1e-12));
        CHECK(ahi[0] == doctest::Approx(-1.0 + (tri ? s : s - 0.5) * h).epsilon(1e-12));

        // Without the ghost layer (A: samples 0..s, B: s..n-1, each drawing all it can): the
        // splines' cubes next to the seam see clamped samples, and the surface there moves.
        if (tri) continue;  // (trilinear cells need no ghost layer: the shared samples suffice)
        quadcast::render::IndexBox own_a0;
        own_a0.hi[0] = s - 1;
        const VolumeModel a0 = quadcast::render::prepare_volume_piece(x_slab(vol, 0, s), origin, spacing, sc, 0.5f, own_a0, {{0.8f, 0.8f, 0.8f}}, 2);
        const VolumeModel b0 = quadcast::render::prepare_volume(x_slab(vol, s, n - 1), Vec3<double>{{-1.0 + s * h, -1.0, -1.0}}, spacing, sc, 0.5f, {{0.8f, 0.8f, 0.8f}}, 2);
        const ImageDiff d0 = image_diff(ref, quadcast::render::render_volumes_cpu({&a0, &b0}, cam, light, opt, nullptr, 2), 1);
        MESSAGE("  without ghosts: coverage differences ", d0.coverage_diff, ", max depth difference ", d0.max_depth);
        CHECK(d0.coverage_diff + d0.depth_diff > 50);
        CHECK(d0.max_depth > 1e-4);
    }
}
