// tests/core/test_bilinear.cpp -- bilinear quads as quadrics: zero set, clipping, orientation, degenerate input
#include <doctest/doctest.h>

#include <cmath>

#include "core/core_testing.hpp"
#include "quadcast/bilinear.hpp"
#include "quadcast/ray.hpp"

using namespace quadcast;
using namespace qc_test;

namespace {

template <class T>
struct Quad {
    Vec3<T> p[4];
};

/// Four random corners in [-1,1]^3, moved by up to `offset`, scaled by `scale`.
template <class T>
Quad<T> random_quad(std::mt19937& rng, double scale = 1, double offset = 0) {
    const Vec3<double> o = random_vec<double>(rng, -offset, offset);
    Quad<T> q{};
    for (Vec3<T>& p : q.p) p = cast<T>(o + scale * random_vec<double>(rng, -1, 1));
    return q;
}

template <class T>
Vec3<LD> s_ld(const Quad<T>& q, LD u, LD v) {
    const Vec3<LD> p1 = cast<LD>(q.p[0]), p2 = cast<LD>(q.p[1]), p3 = cast<LD>(q.p[2]), p4 = cast<LD>(q.p[3]);
    return (1 - v) * ((1 - u) * p1 + u * p2) + v * ((1 - u) * p4 + u * p3);
}

template <class T>
LD size_of(const Quad<T>& q) {
    LD s = 0;
    for (int i = 0; i < 4; ++i)
        for (int j = i + 1; j < 4; ++j) s = std::max(s, norm_ld(cast<LD>(q.p[j]) - cast<LD>(q.p[i])));
    return s;
}

/// Smallest height of a corner over the plane of the other three, relative to the size.
template <class T>
LD twist_of(const Quad<T>& q) {
    Vec3<LD> p[4];
    for (int i = 0; i < 4; ++i) p[i] = cast<LD>(q.p[i]);
    const LD vol6 = std::fabs(dot_ld(p[1] - p[0], cross(p[2] - p[0], p[3] - p[0])));
    LD face = 0;
    for (int i = 0; i < 4; ++i) face = std::max(face, norm_ld(cross(p[(i + 2) % 4] - p[(i + 1) % 4], p[(i + 3) % 4] - p[(i + 1) % 4])));
    return vol6 / face / size_of(q);
}

/// Distance from x to the patch s([0,1]^2) (grid search, then projected Gauss-Newton on (u, v)),
/// and the parameters of the closest point.
template <class T>
LD distance_to_patch(const Quad<T>& q, const Vec3<LD>& x, LD* u_out, LD* v_out) {
    LD best = std::numeric_limits<LD>::infinity(), bu = 0, bv = 0;
    for (int i = 0; i <= 16; ++i)
        for (int j = 0; j <= 16; ++j) {
            const LD u = i / LD(16), v = j / LD(16);
            const LD d = norm_ld(s_ld(q, u, v) - x);
            if (d < best) { best = d; bu = u; bv = v; }
        }
    const Vec3<LD> p1 = cast<LD>(q.p[0]), p2 = cast<LD>(q.p[1]), p3 = cast<LD>(q.p[2]), p4 = cast<LD>(q.p[3]);
    for (int k = 0; k < 40; ++k) {
        const Vec3<LD> r = s_ld(q, bu, bv) - x;
        const Vec3<LD> su = (1 - bv) * (p2 - p1) + bv * (p3 - p4), sv = ((1 - bu) * p4 + bu * p3) - ((1 - bu) * p1 + bu * p2);
        const LD a = dot_ld(su, su), b = dot_ld(su, sv), c = dot_ld(sv, sv), gu = dot_ld(su, r), gv = dot_ld(sv, r);
        const LD det = a * c - b * b;
        if (!(det > 0)) break;
        bu = std::clamp(bu - (c * gu - b * gv) / det, LD(0), LD(1));
        bv = std::clamp(bv - (a * gv - b * gu) / det, LD(0), LD(1));
    }
    *u_out = bu;
    *v_out = bv;
    return norm_ld(s_ld(q, bu, bv) - x);
}

template <class T>
bool all_finite(const Quadric<T>& q) {
    for (int j = 0; j < 4; ++j)
        for (int i = 0; i < 4; ++i)
            if (!std::isfinite(q.q[j][i])) return false;
    return true;
}

template <class T>
bool is_zero(const Quadric<T>& q) {
    for (int j = 0; j < 4; ++j)
        for (int i = 0; i < 4; ++i)
            if (q.q[j][i] != T(0)) return false;
    return true;
}

}  // namespace

TEST_CASE_TEMPLATE("s(u, v) of a random bilinear quad lies on its quadric, with the normal along s_u x s_v", T, float, double) {
    const LD eps = std::numeric_limits<T>::epsilon();
    std::vector<double> dist_local, dist_world;
    int converted = 0;
    for (std::uint32_t it = 0; it < 1000; ++it) {
        auto rng = rng_for(401, it);
        const double scale = log_uniform(rng, -2, 2);
        const Quad<T> quad = random_quad<T>(rng, scale, it % 2 ? 10 * scale : 0);
        const QuadConversion<T> qc = quad_to_quadric(quad.p[0], quad.p[1], quad.p[2], quad.p[3]);
        if (!qc.ok()) continue;
        REQUIRE(all_finite(qc.quadric));
        REQUIRE(all_finite(qc.local.quadric));
        REQUIRE(qc.local.origin[0] == quad.p[0][0]);
        ++converted;
        const Mat4<LD> qw = to_ld(qc.quadric), ql = to_ld(qc.local.quadric);
        const Vec3<LD> origin = cast<LD>(qc.local.origin);
        LD mag = 0;
        for (const Vec3<T>& p : quad.p) mag = std::max({mag, std::fabs(LD(p[0])), std::fabs(LD(p[1])), std::fabs(LD(p[2]))});
        const LD size = size_of(quad), twist = twist_of(quad);
        for (int k = 0; k < 20; ++k) {
            const LD u = uniform(rng, 0, 1), v = uniform(rng, 0, 1);
            const Vec3<LD> x = s_ld(quad, u, v);
            // Distance of s(u, v) from the zero set. The computed quadric is the exact one of
            // corners moved by O(eps (|p|max + L)) (the rounding of p_i - p1), which moves the zero
            // set near the patch by O(eps (|p|max + L) / twist), twist = height / L. The world
            // form adds the cancellation of its constant term, O(eps (|p|max + L)^2 / (L twist)).
            const LD dl = std::fabs(eval_ld(ql, x - origin)) / norm_ld(grad_ld(ql, x - origin));
            const LD dw = std::fabs(eval_ld(qw, x)) / norm_ld(grad_ld(qw, x));
            const LD unit_l = eps * (mag + size) / twist, unit_w = unit_l * (mag + size) / size;
            dist_local.push_back(double(dl / unit_l));
            dist_world.push_back(double(dw / unit_w));
            CHECK(dl <= 8 * unit_l);
            CHECK(dw <= 64 * unit_w);
            // Orientation: grad f . (s_u x s_v) > 0.
            const Vec3<LD> p1 = cast<LD>(quad.p[0]), p2 = cast<LD>(quad.p[1]), p3 = cast<LD>(quad.p[2]), p4 = cast<LD>(quad.p[3]);
            const Vec3<LD> su = (1 - v) * (p2 - p1) + v * (p3 - p4), sv = ((1 - u) * p4 + u * p3) - ((1 - u) * p1 + u * p2);
            const Vec3<LD> n = cross(su, sv);
            if (norm_ld(n) > 1e-3L * size * size) CHECK(dot_ld(grad_ld(ql, x - origin), n) > 0);
        }
    }
    MESSAGE(std::string(scalar_traits<T>::name) << ": " << converted << " of 1000 random quads bilinear; distance of s(u,v) from the"
                                                << " zero set in units of eps (|p|max + L) / twist (median / p99 / max): local form "
                                                << fmt(stats_of(dist_local)) << "; world form, in units of that times (|p|max + L) / L: "
                                                << fmt(stats_of(dist_world)));
    CHECK(converted > 900);
}

TEST_CASE_TEMPLATE("inside its tetrahedron the quadric's zero set is the patch (rays at random patch points)", T, float, double) {
    const LD eps = std::numeric_limits<T>::epsilon();
    int shot = 0, other_point = 0, grazing = 0;
    std::vector<double> err_local, err_world;
    for (std::uint32_t it = 0; it < 1500; ++it) {
        auto rng = rng_for(402, it);
        const Quad<T> quad = random_quad<T>(rng, 1, it % 2 ? 5 : 0);
        if (twist_of(quad) < 0.05L) continue;  // near-planar quads: see the classification test
        const QuadConversion<T> qc = quad_to_quadric(quad.p[0], quad.p[1], quad.p[2], quad.p[3]);
        REQUIRE(qc.ok());
        const TetPlanes<T> planes = tet_planes(qc.bound);
        const LD size = size_of(quad), twist = twist_of(quad);
        const Vec3<LD> p1 = cast<LD>(quad.p[0]), p2 = cast<LD>(quad.p[1]), p3 = cast<LD>(quad.p[2]), p4 = cast<LD>(quad.p[3]);
        for (int k = 0; k < 10; ++k) {
            const LD u0 = uniform(rng, 0.05, 0.95), v0 = uniform(rng, 0.05, 0.95);
            const Vec3<LD> target = s_ld(quad, u0, v0);
            const Vec3<LD> center = (p1 + p2 + p3 + p4) / LD(4);
            const Vec3<T> eye = cast<T>(center + LD(uniform(rng, 2, 5)) * size * cast<LD>(random_dir<double>(rng)));
            const Vec3<LD> dir = target - cast<LD>(eye);
            // Skip rays within ~6 degrees of tangent at the target: there the hit is a near-double
            // root and rounding may legitimately turn it into a miss (a silhouette pixel).
            const Vec3<LD> n = cross((1 - v0) * (p2 - p1) + v0 * (p3 - p4), ((1 - u0) * p4 + u0 * p3) - ((1 - u0) * p1 + u0 * p2));
            if (std::fabs(dot_ld(dir, n)) < 0.1L * norm_ld(dir) * norm_ld(n)) { ++grazing; continue; }
            const Vec3<T> v = cast<T>(dir / norm_ld(dir));
            const LD lambda_target = norm_ld(dir) / norm_ld(cast<LD>(v));
            // Cast without culling, nearest root inside the tetrahedron, from the local quadric
            // (the accurate path) and from the world quadric.
            RayHit<T> hits[2];
            const RayCoefficients<T> coef[2] = {
                ray_coefficients_eye(translate_to_eye(qc.local.quadric, eye - qc.local.origin), v),
                ray_coefficients(qc.quadric, eye, v)};
            for (int path = 0; path < 2; ++path) {
                const RootPair<T> pr = roots_near_first(coef[path]);
                hits[path] = pick_first(pr, inside_tet(planes, ray_point(eye, v, pr.lambda_near)),
                                        inside_tet(planes, ray_point(eye, v, pr.lambda_far)));
                REQUIRE(hits[path].hit);
                const Vec3<LD> x = cast<LD>(eye) + LD(hits[path].lambda) * cast<LD>(v);
                // The hit is on the patch ...
                LD u = 0, w = 0;
                const LD d = distance_to_patch(quad, x, &u, &w);
                const LD unit = eps * (norm_ld(cast<LD>(eye) - p1) + size) / twist;
                (path == 0 ? err_local : err_world).push_back(double(d / unit));
                if (path == 0) CHECK(d <= 64 * unit);
                // ... and it is the target or a crossing of the patch before it.
                if (norm_ld(x - target) > 1e-3L * size) {
                    CHECK(LD(hits[path].lambda) < lambda_target);
                    other_point += path == 0;
                }
            }
            ++shot;
        }
    }
    MESSAGE(std::string(scalar_traits<T>::name) << ": " << shot << " rays at patch points all hit the patch (" << grazing
                                                << " near-tangent rays skipped); " << other_point << " hit it first elsewhere"
                                                << " (the ray crosses the patch twice); distance of the hit from the patch /"
                                                << " (eps (|eye - p1| + L) / twist) (median / p99 / max): local quadric + translate_to_eye "
                                                << fmt(stats_of(err_local)) << ", world quadric " << fmt(stats_of(err_world)));
    CHECK(shot > 5000);
}

TEST_CASE_TEMPLATE("degenerate quads classify correctly and never produce NaN quadrics", T, float, double) {
    const T nan = std::numeric_limits<T>::quiet_NaN(), inf = std::numeric_limits<T>::infinity();
    const auto check = [](const Quad<T>& q, QuadKind want) {
        const QuadConversion<T> c = quad_to_quadric(q.p[0], q.p[1], q.p[2], q.p[3]);
        CHECK(classify_quad(q.p[0], q.p[1], q.p[2], q.p[3]) == want);
        CHECK(c.kind == want);
        CHECK(all_finite(c.quadric));
        if (want != QuadKind::bilinear) CHECK(is_zero(c.quadric));
    };
    for (std::uint32_t it = 0; it < 300; ++it) {
        auto rng = rng_for(403, it);
        const double scale = log_uniform(rng, -3, 3), offset = it % 2 ? 10 * scale : 0;
        const Vec3<double> o = random_vec<double>(rng, -offset, offset);
        const Vec3<double> a = scale * random_vec<double>(rng, -1, 1), b = scale * random_vec<double>(rng, -1, 1);
        auto in_plane = [&](double s, double t) { return cast<T>(o + s * a + t * b); };
        // Planar: four points of a plane, rounded to T.
        check({{in_plane(0, 0), in_plane(1, 0.1), in_plane(1.2, 0.9), in_plane(-0.1, 1)}}, QuadKind::planar);
        // Triangle: an adjacent or a diagonal corner repeated.
        const Vec3<T> t0 = in_plane(0, 0), t1 = in_plane(1, 0), t2 = in_plane(0.3, 1);
        check({{t0, t0, t1, t2}}, QuadKind::triangle);
        check({{t0, t1, t1, t2}}, QuadKind::triangle);
        check({{t0, t1, t0, t2}}, QuadKind::triangle);
        // Segment: four points of a line, also with repeats.
        auto on_line = [&](double s) { return cast<T>(o + s * a); };
        check({{on_line(0), on_line(1), on_line(0.3), on_line(-0.5)}}, QuadKind::segment);
        check({{on_line(0), on_line(0), on_line(1), on_line(1)}}, QuadKind::segment);
        // Point.
        check({{on_line(0), on_line(0), on_line(0), on_line(0)}}, QuadKind::point);
        // Non-finite coordinates.
        for (T bad : {nan, inf, -inf}) {
            Quad<T> q{{in_plane(0, 0), in_plane(1, 0), cast<T>(o + a + b + scale * Vec3<double>{{0, 0, 1}}), in_plane(0, 1)}};
            q.p[it % 4][it % 3] = bad;
            check(q, QuadKind::non_finite);
        }
        // Out of plane by twice / half the planar tolerance (relative to the size).
        const double tau = std::sqrt(double(std::numeric_limits<T>::epsilon()));
        const Vec3<double> nrm = cross(a, b) / std::sqrt(length2(cross(a, b)));
        const Quad<T> base{{in_plane(0, 0), in_plane(1, 0), in_plane(1, 1), in_plane(0, 1)}};
        const double size = std::sqrt(double(size_of(base)) * double(size_of(base)));
        for (double factor : {4.0, 0.25}) {
            Quad<T> q = base;
            q.p[2] = cast<T>(cast<double>(q.p[2]) + factor * tau * size * nrm);
            if (std::sqrt(length2(cross(a, b))) < 0.3 * std::sqrt(length2(a) * length2(b))) continue;  // skip slivers
            check(q, factor > 1 ? QuadKind::bilinear : QuadKind::planar);
        }
    }
}

TEST_CASE("tiny and huge float quads stay representable thanks to the unit normal in M") {
    // With the paper's unnormalised third column the quadric scales like L^-4 and beta^2 like
    // L^-8, which overflows float for L ~ 1e-5; with the unit normal it scales like L^0.
    for (const float scale : {1e-5f, 1e-3f, 1e3f, 1e5f}) {
        const Vec3<float> p1 = vec3(0.f, 0.f, 0.f) * scale, p2 = vec3(1.f, 0.f, 0.f) * scale,
                          p3 = vec3(1.f, 1.f, 0.6f) * scale, p4 = vec3(0.f, 1.f, 0.f) * scale;
        const QuadConversion<float> qc = quad_to_quadric(p1, p2, p3, p4);
        REQUIRE(qc.ok());
        // A ray from 3 L above at s(0.5, 0.5) = (0.5, 0.5, 0.15) L hits it there.
        const Vec3<float> target = bilinear_point(p1, p2, p3, p4, 0.5f, 0.5f);
        const Vec3<float> eye = target + vec3(0.2f, 0.1f, 3.f) * scale;
        const Vec3<float> v = target - eye;
        const RayCoefficients<float> c = ray_coefficients(qc.quadric, eye, v);
        CHECK(std::isfinite(c.alpha));
        CHECK(std::isfinite(c.beta * c.beta));
        CHECK(std::isfinite(c.alpha * c.gamma));
        const RayHit<float> h = pick_first(roots_near_first(c), true, true);
        REQUIRE(h.hit);
        CHECK(h.lambda == doctest::Approx(1.0).epsilon(1e-5));
    }
    // Far too small for float: reported as non_finite (the unit normal cannot be computed), not NaN.
    const float t = 1e-22f;
    const QuadConversion<float> qc = quad_to_quadric(vec3(0.f, 0.f, 0.f), vec3(t, 0.f, 0.f), vec3(t, t, 0.6f * t), vec3(0.f, t, 0.f));
    CHECK(qc.kind == QuadKind::non_finite);
    CHECK(all_finite(qc.quadric));
}

TEST_CASE_TEMPLATE("the unit square with a lifted corner gives the expected hyperbolic paraboloid", T, float, double) {
    // p3 = (1, 1, h): s(u, v) = (u, v, h u v), so the surface is z = h x y; oriented along +z.
    const T h = T(0.5);
    const QuadConversion<T> qc = quad_to_quadric(vec3(T(0), T(0), T(0)), vec3(T(1), T(0), T(0)), vec3(T(1), T(1), h), vec3(T(0), T(1), T(0)));
    REQUIRE(qc.ok());
    // f is a positive multiple of z - h x y: check ratios at a few points.
    const T ref = evaluate(qc.quadric, vec3(T(0), T(0), T(1)));  // = k (1)
    REQUIRE(ref > T(0));
    for (const Vec3<T>& x : {vec3(T(0.3), T(0.7), T(0.2)), vec3(T(2), T(-1), T(0.5)), vec3(T(-1), T(-1), T(-1))}) {
        const T want = ref * (x[2] - h * x[0] * x[1]);
        CHECK(evaluate(qc.quadric, x) == doctest::Approx(want).epsilon(1e-5));
    }
}
