// tests/core/test_primitives.cpp -- parameter-space primitives (Sigg et al. 2006, sec. 3.1) and Q <-> (D, T)
#include <doctest/doctest.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <string>

#include "core/param_test_util.hpp"
#include "quadcast/primitives.hpp"
#include "quadcast/primitives_host.hpp"

using namespace qct;
using quadcast::PrimitiveKind;

namespace {

using quadcast::primitive_kind_name;
constexpr auto& all_kinds = quadcast::all_primitive_kinds;

const char* kind_name(PrimitiveKind k) { return primitive_kind_name(k); }

/// Expected D of each kind.
V4L canonical_d(PrimitiveKind k) {
    switch (k) {
    case PrimitiveKind::ellipsoid: return {{1, 1, 1, -1}};
    case PrimitiveKind::cylinder: return {{1, 1, 0, -1}};
    case PrimitiveKind::cone: return {{1, 1, -1, 0}};
    case PrimitiveKind::paraboloid: return {{1, 1, 1, -1}};
    case PrimitiveKind::hyperboloid_one_sheet: return {{1, 1, -1, -1}};
    case PrimitiveKind::hyperboloid_two_sheets: return {{1, 1, -1, 1}};
    }
    return {};
}

LD max_abs(const M4L& m) {
    LD r = 0;
    for (int j = 0; j < 4; ++j)
        for (int i = 0; i < 4; ++i) r = std::max(r, std::fabs(m[j][i]));
    return r;
}

LD max_abs_diff(const M4L& a, const M4L& b) {
    LD r = 0;
    for (int j = 0; j < 4; ++j)
        for (int i = 0; i < 4; ++i) r = std::max(r, std::fabs(a[j][i] - b[j][i]));
    return r;
}

}  // namespace

TEST_CASE_TEMPLATE("points on each primitive lie on its conic matrix, with the centre side negative", T, float, double) {
    const LD eps = std::numeric_limits<T>::epsilon();
    for (PrimitiveKind kind : all_kinds) {
        LD worst = 0;
        for (int it = 0; it < 200; ++it) {
            std::mt19937 rng(1000u + 7919u * unsigned(kind) + unsigned(it));
            const quadcast::ParameterForm<T> prim = random_primitive<T>(rng, kind, it);
            const M4L q = to_ld(quadcast::to_quadric(prim).q);  // computed in T
            const M4L t = to_ld(prim.t);
            const V4L d = quadcast::cast<LD>(prim.d);
            const M4L ti = inverse(t);
            // Size of the terms of f = sum_k d_k (T^-1 x)_k^2: the scale of its rounding errors
            auto term_size = [&](const V3L& x) {
                LD n = 0;
                for (int k = 0; k < 4; ++k) {
                    LD r = std::fabs(ti[3][k]);
                    for (int i = 0; i < 3; ++i) r += std::fabs(ti[i][k] * x[i]);
                    n += r * r;
                }
                return n;
            };
            // Keep away from the apex of cones and the vertex of one-sheet bowls (rho = 0)
            LD zl = LD(prim.slab[0]), zh = LD(prim.slab[1]);
            if (kind == PrimitiveKind::cone) zl = 0.2L;
            if (kind == PrimitiveKind::hyperboloid_two_sheets) zl = std::max(zl, LD(1.2));
            if (kind == PrimitiveKind::paraboloid) zl = -0.9L;
            for (int s = 0; s < 16; ++s) {
                const LD theta = uniform(rng, 0, 6.2831853L), z = uniform(rng, zl, zh);
                // On the surface: f relative to the size of its terms (backward error of Q)
                const V3L x = object_point(t, param_point(d, theta, z));
                worst = std::max(worst, std::fabs(eval_quadric(q, x)) / term_size(x) / eps);
                // Inside and outside
                CHECK(eval_quadric(q, object_point(t, param_point(d, theta, z, 0.5L))) < 0);
                CHECK(eval_quadric(q, object_point(t, param_point(d, theta, z, 1.5L))) > 0);
            }
        }
        std::printf("[primitives %s] %s: max |f| on the surface %.2Lf eps of the size of its terms\n",
                    quadcast::scalar_traits<T>::name, kind_name(kind), worst);
        CHECK(worst < 8);
    }
}

TEST_CASE_TEMPLATE("a cylinder's clipped length and caps match p0, p1 and the radius", T, float, double) {
    const LD eps = std::numeric_limits<T>::epsilon();
    for (int it = 0; it < 200; ++it) {
        std::mt19937 rng(2000u + unsigned(it));
        const V3L p0l{{uniform(rng, -5, 5), uniform(rng, -5, 5), uniform(rng, -5, 5)}};
        const V3L p1l = p0l + unit_vector(rng) * log_uniform(rng, 0.1L, 10);
        const quadcast::Vec3<T> p0 = quadcast::cast<T>(p0l), p1 = quadcast::cast<T>(p1l);
        const T r = T(log_uniform(rng, 0.05L, 3));
        const auto prim = quadcast::cylinder(p0, p1, r);
        REQUIRE(prim.kind == PrimitiveKind::cylinder);
        const M4L t = to_ld(prim.t);
        const V3L a0 = quadcast::cast<LD>(p0), a1 = quadcast::cast<LD>(p1);
        const LD scale = std::max(len3(a0), len3(a1)) + LD(r);
        // The slab ends map to the segment's end points
        const V3L e0 = object_point(t, V4L{{0, 0, LD(prim.slab[0]), 1}});
        const V3L e1 = object_point(t, V4L{{0, 0, LD(prim.slab[1]), 1}});
        CHECK(len3(e0 - a0) <= 8 * eps * scale);
        CHECK(len3(e1 - a1) <= 8 * eps * scale);
        CHECK(std::fabs(len3(e1 - e0) - len3(a1 - a0)) <= 8 * eps * scale);
        // Cap boundary points are at distance r from the end point, perpendicular to the axis
        const V3L axis = unit3(a1 - a0);
        for (int s = 0; s < 8; ++s) {
            const LD theta = uniform(rng, 0, 6.2831853L);
            const V3L x = object_point(t, param_point(quadcast::cast<LD>(prim.d), theta, LD(prim.slab[1])));
            CHECK(std::fabs(len3(x - a1) - LD(r)) <= 8 * eps * scale);
            CHECK(std::fabs(quadcast::dot(x - a1, axis)) <= 8 * eps * scale);
        }
    }
}

TEST_CASE_TEMPLATE("cones and paraboloids have their apex, base and rim where they were asked", T, float, double) {
    const LD eps = std::numeric_limits<T>::epsilon();
    for (int it = 0; it < 200; ++it) {
        std::mt19937 rng(3000u + unsigned(it));
        const V3L apex_l{{uniform(rng, -5, 5), uniform(rng, -5, 5), uniform(rng, -5, 5)}};
        const V3L base_l = apex_l + unit_vector(rng) * log_uniform(rng, 0.1L, 10);
        const auto apex = quadcast::cast<T>(apex_l), base = quadcast::cast<T>(base_l);
        const V3L a = quadcast::cast<LD>(apex), b = quadcast::cast<LD>(base);
        const T r = T(log_uniform(rng, 0.05L, 3));
        const LD scale = std::max(len3(a), len3(b)) + LD(r);
        for (const auto& prim : {quadcast::cone(apex, base, r), quadcast::paraboloid(apex, base, r)}) {
            const M4L t = to_ld(prim.t);
            const V4L d = quadcast::cast<LD>(prim.d);
            CHECK(len3(object_point(t, param_point(d, 0, LD(prim.slab[0]))) - a) <= 16 * eps * scale);
            for (int s = 0; s < 8; ++s) {
                const V3L x = object_point(t, param_point(d, uniform(rng, 0, 6.2831853L), LD(prim.slab[1])));
                CHECK(std::fabs(len3(x - b) - LD(r)) <= 16 * eps * scale);
                CHECK(std::fabs(quadcast::dot(x - b, unit3(b - a))) <= 16 * eps * scale);
            }
        }
    }
}

TEST_CASE_TEMPLATE("inverse_variance inverts T, also the projective T of paraboloids", T, float, double) {
    const LD eps = std::numeric_limits<T>::epsilon();
    LD worst = 0;
    for (PrimitiveKind kind : all_kinds) {
        for (int it = 0; it < 100; ++it) {
            std::mt19937 rng(4000u + 131u * unsigned(kind) + unsigned(it));
            const auto prim = random_primitive<T>(rng, kind, it);
            const M4L t = to_ld(prim.t), ti = to_ld(quadcast::inverse_variance(prim));
            const M4L ref = inverse(t);
            worst = std::max(worst, max_abs_diff(ti, ref) / max_abs(ref) / eps);
        }
    }
    std::printf("[primitives %s] inverse_variance: max error %.2Lf eps of max|T^-1|\n", quadcast::scalar_traits<T>::name,
                worst);
    CHECK(worst < 256);
}

TEST_CASE("the shared and the host conversion to Q agree") {
    for (PrimitiveKind kind : all_kinds) {
        for (int it = 0; it < 50; ++it) {
            std::mt19937 rng(5000u + 17u * unsigned(kind) + unsigned(it));
            const auto prim = random_primitive<double>(rng, kind, it);
            const M4L a = to_ld(quadcast::to_quadric(prim).q), b = to_ld(quadcast::host::quadric_from_form(prim).q);
            CHECK(max_abs_diff(a, b) <= 1e-12L * max_abs(b));
        }
    }
}

TEST_CASE("decomposing Q recovers the class and reproduces Q") {
    LD worst = 0;
    for (PrimitiveKind kind : all_kinds) {
        for (int it = 0; it < 200; ++it) {
            std::mt19937 rng(6000u + 37u * unsigned(kind) + unsigned(it));
            const auto prim = random_primitive<double>(rng, kind, it);
            const double scale = double((rng() % 2 ? 1 : -1) * log_uniform(rng, 0.01L, 100));
            quadcast::Quadric<double> q = quadcast::host::quadric_from_form(prim);
            for (int j = 0; j < 4; ++j) q.q[j] = q.q[j] * scale;
            const auto res = quadcast::host::decompose_quadric(q);
            REQUIRE_MESSAGE(res, kind_name(kind), ": ", res.error);
            const auto& dec = *res.value;
            CHECK(dec.prim.kind == kind);
            for (int i = 0; i < 4; ++i) CHECK(LD(dec.prim.d[i]) == canonical_d(kind)[i]);
            // Q / scale = T^-T D T^-1
            quadcast::Quadric<double> back = quadcast::host::quadric_from_form(dec.prim);
            for (int j = 0; j < 4; ++j) back.q[j] = back.q[j] * dec.scale;
            const LD err = max_abs_diff(to_ld(back.q), to_ld(q.q)) / max_abs(to_ld(q.q));
            worst = std::max(worst, err);
            CHECK(err < 1e-9L);
            // The affine frame [u v w] is right-handed
            M4L a = to_ld(dec.prim.t);
            if (quadcast::is_projective(kind)) a[2] = (a[2] + a[3]) * LD(0.5);
            CHECK(quadcast::dot(quadcast::cross(quadcast::xyz(a[0]), quadcast::xyz(a[1])), quadcast::xyz(a[2])) > 0);
        }
    }
    std::printf("[primitives] Q -> (D, T) round trip: max relative error %.3Le\n", worst);
}

TEST_CASE("decomposing degenerate or unsupported Q gives a clear error") {
    struct Case {
        const char* what;
        V4L diag;       // Q = diag for the quadratic part and the constant
        V3L b;          // linear part
        const char* expect;
    };
    const Case cases[] = {
        {"imaginary ellipsoid", {{1, 2, 3, 1}}, {{0, 0, 0}}, "empty"},
        {"single point", {{1, 2, 3, 0}}, {{0, 0, 0}}, "point"},
        {"plane", {{0, 0, 0, 0}}, {{1, 0, 0}}, "plane"},
        {"intersecting planes", {{1, -1, 0, 0}}, {{0, 0, 0}}, "intersecting planes"},
        {"parallel planes", {{1, 0, 0, -1}}, {{0, 0, 0}}, "rank"},
        {"parabolic cylinder", {{1, 0, 0, 0}}, {{0, 0, -0.5}}, "rank"},
        {"hyperbolic paraboloid", {{1, -1, 0, 0}}, {{0, 0, -0.5}}, "hyperbolic paraboloid"},
        {"hyperbolic cylinder", {{1, -1, 0, -1}}, {{0, 0, 0}}, "hyperbolic cylinder"},
        {"imaginary cylinder", {{1, 1, 0, 1}}, {{0, 0, 0}}, "empty"},
        {"line", {{1, 1, 0, 0}}, {{0, 0, 0}}, "line"},
        {"zero", {{0, 0, 0, 0}}, {{0, 0, 0}}, "zero"},
    };
    for (const Case& c : cases) {
        for (int it = 0; it < 10; ++it) {
            // Put the canonical form into a random affine frame
            std::mt19937 rng(7000u + unsigned(it));
            M4L q = quadcast::zero_mat<LD, 4, 4>();
            for (int i = 0; i < 4; ++i) q[i][i] = c.diag[i];
            for (int i = 0; i < 3; ++i) q[3][i] = q[i][3] = c.b[i];
            V3L a{}, b{}, n{};
            random_frame(rng, a, b, n);
            M4L f = quadcast::identity<LD, 4>();
            f[0] = quadcast::vec4(a * log_uniform(rng, 0.5L, 2), LD(0));
            f[1] = quadcast::vec4(b * log_uniform(rng, 0.5L, 2), LD(0));
            f[2] = quadcast::vec4(n * log_uniform(rng, 0.5L, 2), LD(0));
            f[3] = V4L{{uniform(rng, -3, 3), uniform(rng, -3, 3), uniform(rng, -3, 3), 1}};
            const M4L fi = inverse(f);
            const M4L qo = quadcast::transpose(fi) * q * fi;
            const auto res = quadcast::host::decompose_quadric({quadcast::cast<double>(qo)});
            CHECK_MESSAGE(!res, c.what);
            CHECK_MESSAGE(res.error.find(c.expect) != std::string::npos, c.what, ": ", res.error);
        }
    }
    // Non-finite and non-symmetric input
    quadcast::Quadric<double> q{quadcast::identity<double, 4>()};
    q.q[2][1] = std::numeric_limits<double>::quiet_NaN();
    CHECK(quadcast::host::decompose_quadric(q).error.find("NaN") != std::string::npos);
    q.q = quadcast::identity<double, 4>();
    q.q[3][3] = -1;
    q.q[2][1] = 0.5;
    CHECK(quadcast::host::decompose_quadric(q).error.find("symmetric") != std::string::npos);
    // A singular T is refused by the host conversion
    CHECK_THROWS_AS(quadcast::host::quadric_from_form(quadcast::Vec4<double>{{1, 1, 1, -1}}, quadcast::zero_mat<double, 4, 4>()),
                    std::invalid_argument);
}
