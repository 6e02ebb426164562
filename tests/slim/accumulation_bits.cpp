// tests/slim/accumulation_bits.cpp -- what 8-bit accumulation targets would cost: the SLIM sums
// encoded in UNORM8 and blended with saturation, simulated against the float sums
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "quadcast/camera.hpp"
#include "quadcast/render/slim_cpu_renderer.hpp"
#include "quadcast/render/slim_patch.hpp"
#include "slim/slim_testing.hpp"

using namespace quadcast;

namespace {

/// A fragment output stored in a GL UNORM8 target: clamped to [0, 1], rounded to 1/255.
float unorm8(float v) { return std::nearbyint(std::clamp(v, 0.0f, 1.0f) * 255.0f) / 255.0f; }

/// GL_ONE, GL_ONE blending into a UNORM8 target: the sum saturates at 1.
float blend8(float dst, float src) { return std::min(1.0f, dst + src); }

}  // namespace

TEST_CASE("8-bit accumulation targets, simulated: the error of UNORM8 sums against the float sums") {
    // UNORM8 holds [0, 1], so an 8-bit SLIM renderer would have to encode the signed sums: per
    // fragment w / K, w (n + 1) / (2 K) and w (lambda - lambda0) / ((lambda1 - lambda0) K), with K
    // at least the largest sum of weights of a pixel (else the sums saturate) and [lambda0,
    // lambda1] the frame's range of ray parameters (here the exact range of the hits: the best
    // case). Each output is rounded to 1/255 and the blend saturates at 1, as GL does.
    const std::vector<render::Primitive>& balls = slim::testing::model_balls("bunny_3k.off", 3e-3);
    const slim::OrientedPoints pts = slim::read_points(std::string(QUADCAST_SLIM_TEST_DATA) + "/bunny_3k.off");
    Vec3<double> lo = pts.positions[0], hi = pts.positions[0];
    for (const Vec3<double>& p : pts.positions)
        for (int i = 0; i < 3; ++i) lo[i] = std::min(lo[i], p[i]), hi[i] = std::max(hi[i], p[i]);
    const double E = 3e-3 * length(hi - lo);
    const int w = 240, h = 180;
    const Vec3<double> centre = (lo + hi) * 0.5;
    const Mat4<double> view = look_at(centre + normalize(vec3(0.22, 0.3, 1.0)) * (1.25 * length(hi - lo)), centre, vec3(0.0, 1.0, 0.0));
    const render::Camera cam = camera_from_matrices(view, perspective(40.0, double(w) / h, 0.05 * length(hi - lo), 10.0 * length(hi - lo)));
    render::RenderOptions opt;
    opt.width = w;
    opt.height = h;
    const render::FrameSetup f = render::frame_setup(cam, w, h);
    const std::vector<SlimPatch<float>> patches = render::slim_patches(balls);
    std::vector<render::PixelRect> rects(balls.size());
    for (std::size_t i = 0; i < balls.size(); ++i)
        if (!render::slim_ball_culled(balls[i], &patches[i], f, opt)) rects[i] = render::slim_pixels(balls[i], patches[i], f);
    // Per pixel the fragments the renderers blend (visibility, then every hit at or before it, in ball order)
    struct Term {
        float w, lambda;
        Vec3<float> n;
    };
    std::vector<std::vector<Term>> terms(std::size_t(w) * h);
    std::vector<render::SlimPixel> reference;
    render::render_slim_cpu(balls, cam, render::Light{}, opt, &reference, 0, &patches);
    float lambda_lo = 1e30f, lambda_hi = -1e30f, max_weight = 0.0f;
    long mismatched = 0;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const render::PixelRay ray = render::pixel_ray(f, x, y);
            auto inside = [&](const render::PixelRect& r) { return x >= r.x0 && x <= r.x1 && y >= r.y0 && y <= r.y1; };
            float vis = 1.0f;
            bool any = false;
            for (std::size_t i = 0; i < balls.size(); ++i) {
                if (!inside(rects[i])) continue;
                const SlimFragment<float> s = render::slim_cast(balls[i], ray, f, true);
                any = any || s.hit;
                if (s.hit && s.visibility < vis) vis = s.visibility;
            }
            std::vector<Term>& t = terms[std::size_t(h - 1 - y) * w + x];
            float sum_w = 0.0f;
            if (any)
                for (std::size_t i = 0; i < balls.size(); ++i) {
                    if (!inside(rects[i])) continue;
                    const SlimFragment<float> s = render::slim_cast(balls[i], ray, f, true);
                    if (!s.hit || !(s.depth <= vis)) continue;
                    t.push_back(Term{s.weight, s.lambda, s.normal});
                    sum_w += s.weight;
                    lambda_lo = std::min(lambda_lo, s.lambda);
                    lambda_hi = std::max(lambda_hi, s.lambda);
                }
            max_weight = std::max(max_weight, sum_w);
            const render::SlimPixel& r = reference[std::size_t(h - 1 - y) * w + x];
            mismatched += int(t.size()) != r.blended || sum_w != r.weight;
        }
    // The simulation blends what the CPU reference blends
    CHECK(mismatched == 0);
    std::printf("8-bit accumulation (simulated), reduced bunny, %dx%d: largest sum of weights %.2f, ray parameters %.4f..%.4f\n", w, h, double(max_weight),
                double(lambda_lo), double(lambda_hi));
    for (const float K : {4.0f, 8.0f, 16.0f}) {
        long covered = 0, lost = 0, saturated = 0;
        std::vector<double> angle, position;
        for (std::size_t p = 0; p < terms.size(); ++p) {
            if (terms[p].empty()) continue;
            float sw = 0.0f, sl = 0.0f, sw8 = 0.0f, sl8 = 0.0f;
            Vec3<float> sn{}, sn8{};
            bool sat = false;
            for (const Term& t : terms[p]) {
                sw += t.w;
                sl += t.w * t.lambda;
                sn = sn + t.n * t.w;
                const float ow = unorm8(t.w / K), ol = unorm8(t.w * (t.lambda - lambda_lo) / ((lambda_hi - lambda_lo) * K));
                sat = sat || sw8 + ow > 1.0f || sl8 + ol > 1.0f;
                sw8 = blend8(sw8, ow);
                sl8 = blend8(sl8, ol);
                for (int k = 0; k < 3; ++k) {
                    const float on = unorm8(t.w * (t.n[k] + 1.0f) / (2.0f * K));
                    sat = sat || sn8[k] + on > 1.0f;
                    sn8[k] = blend8(sn8[k], on);
                }
            }
            if (!(sw > 0.0f)) continue;
            ++covered;
            saturated += sat;
            if (!(sw8 > 0.0f)) {
                ++lost;
                continue;
            }
            // Decode: n = 2 S_n / S_w - 1, lambda = lambda0 + (S_l / S_w) (lambda1 - lambda0)
            const Vec3<double> n32 = normalize(cast<double>(sn));
            Vec3<double> n8{};
            for (int k = 0; k < 3; ++k) n8[k] = 2.0 * double(sn8[k]) / double(sw8) - 1.0;
            const double len8 = length(n8);
            angle.push_back(len8 > 0 ? std::acos(std::clamp(dot(n32, n8 / len8), -1.0, 1.0)) * 57.29577951308232 : 180.0);
            const double l32 = double(sl) / double(sw), l8 = double(lambda_lo) + double(sl8) / double(sw8) * double(lambda_hi - lambda_lo);
            const render::PixelRay ray = render::pixel_ray(f, int(p % std::size_t(w)), h - 1 - int(p / std::size_t(w)));
            position.push_back(std::abs(l8 - l32) * length(cast<double>(ray.dir)) / E);
        }
        std::printf("  K = %2.0f: %ld covered pixels, %ld lost (every weight below 1/510 K), %ld saturated; normal error median %.2f, 99%% %.2f, max %.2f deg; "
                    "position error median %.3f, 99%% %.3f, max %.3f E\n",
                    double(K), covered, lost, saturated, slim::testing::percentile(angle, 0.5), slim::testing::percentile(angle, 0.99), slim::testing::percentile(angle, 1.0), slim::testing::percentile(position, 0.5),
                    slim::testing::percentile(position, 0.99), slim::testing::percentile(position, 1.0));
        CHECK(covered > 10000);
    }
}
