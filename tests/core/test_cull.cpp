// tests/core/test_cull.cpp -- per-quadric back-face culling is conservative (also under rounding) and effective
#include <doctest/doctest.h>

#include <cmath>

#include "core/core_testing.hpp"
#include "quadcast/cull.hpp"

using namespace quadcast;
using namespace qc_test;
using mpfr::mpreal;

namespace {

/// A SLIM-like configuration: a random quadric through a random point p, a small bound around p,
/// an eye 1..10 units away.
template <class T>
struct CullCase {
    Quadric<T> q;
    Vec3<T> eye;
    BoundingSphere<T> sphere;
    BoundingTet<T> tet;
};

template <class T>
CullCase<T> make_cull_case(std::mt19937& rng) {
    CullCase<T> c{random_quadric<T>(rng), {}, {}, {}};
    const Vec3<LD> p = cast<LD>(random_vec<T>(rng, -1, 1));
    Mat4<LD> ql = to_ld(c.q);
    ql[3][3] = 0;
    c.q.q[3][3] = T(-eval_ld(ql, p));
    const double r = uniform(rng, 0.05, 0.5);
    c.sphere.radius = T(r);
    c.sphere.center = cast<T>(p) + random_vec<T>(rng, -0.3 * r, 0.3 * r);
    LD shape = 0;
    do {
        for (Vec3<T>& x : c.tet.p) x = cast<T>(p) + random_vec<T>(rng, -r, r);
        const Vec3<LD> a = cast<LD>(c.tet.p[1]) - cast<LD>(c.tet.p[0]), b = cast<LD>(c.tet.p[2]) - cast<LD>(c.tet.p[0]),
                       d = cast<LD>(c.tet.p[3]) - cast<LD>(c.tet.p[0]);
        shape = std::fabs(dot_ld(a, cross(b, d))) / (norm_ld(a) * norm_ld(b) * norm_ld(d));
    } while (shape < 0.05L);
    c.eye = cast<T>(p) + T(uniform(rng, 1, 10)) * random_dir<T>(rng);
    return c;
}

/// Brute force in long double: shoots `n` rays from the eye through random points of the bound
/// (uniform inside, and just inside its boundary) and returns the number of front-facing hits
/// (v . grad f < 0) that lie inside the bound.
template <class T, class Inside, class Sample>
int front_hits_in_bound(const Quadric<T>& q, const Vec3<T>& eye, Inside inside, Sample sample, int n, std::mt19937& rng) {
    const Mat4<LD> ql = to_ld(q);
    const Vec3<LD> e = cast<LD>(eye);
    int hits = 0;
    for (int k = 0; k < n; ++k) {
        const Vec3<LD> v = sample(rng, k) - e;
        LD a = 0, b = 0, g = eval_ld(ql, e);
        const Vec3<LD> h = grad_ld(ql, e);  // 2 (A e + b)
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j) a += v[i] * ql[j][i] * v[j];
        b = dot_ld(h, v) / 2;
        const LD disc = b * b - a * g;
        if (disc < 0) continue;
        const LD s = std::sqrt(disc);
        const LD qq = -(b + (b < 0 ? -s : s));
        LD roots[2];
        int nr = 0;
        if (a != 0) roots[nr++] = qq / a;
        if (qq != 0) roots[nr++] = g / qq;
        for (int i = 0; i < nr; ++i) {
            if (!(roots[i] > 0) || !std::isfinite(roots[i])) continue;
            const Vec3<LD> x = e + roots[i] * v;
            if (!inside(x)) continue;
            if (dot_ld(v, grad_ld(ql, x)) < 0) ++hits;
        }
    }
    return hits;
}

template <class T>
auto sphere_sampler(const BoundingSphere<T>& s) {
    return [s](std::mt19937& rng, int k) {
        const Vec3<LD> d = cast<LD>(random_dir<double>(rng));
        // Half the samples uniform in the ball, half just inside the boundary sphere.
        const LD rad = LD(s.radius) * (k % 2 ? LD(1) - 1e-9L : std::cbrt(LD(uniform(rng, 0, 1))));
        return cast<LD>(s.center) + rad * d;
    };
}

template <class T>
auto sphere_inside(const BoundingSphere<T>& s) {
    return [s](const Vec3<LD>& x) {
        const Vec3<LD> d = x - cast<LD>(s.center);
        return dot_ld(d, d) <= LD(s.radius) * LD(s.radius);
    };
}

template <class T>
auto tet_sampler(const BoundingTet<T>& t) {
    return [t](std::mt19937& rng, int k) {
        // Uniform barycentric weights; every other sample with one weight ~0 (near a face).
        LD w[4], sum = 0;
        for (LD& x : w) sum += (x = -std::log(LD(uniform(rng, 1e-12, 1))));
        if (k % 2) { sum -= w[k % 4]; w[k % 4] = 1e-9L * sum; sum += w[k % 4]; }
        Vec3<LD> y{{0, 0, 0}};
        for (int i = 0; i < 4; ++i) y = y + (w[i] / sum) * cast<LD>(t.p[i]);
        return y;
    };
}

template <class T>
auto tet_inside(const BoundingTet<T>& t) {
    return [t](const Vec3<LD>& x) {
        const Vec3<LD> p0 = cast<LD>(t.p[0]);
        const Vec3<LD> a = cast<LD>(t.p[1]) - p0, b = cast<LD>(t.p[2]) - p0, d = cast<LD>(t.p[3]) - p0, r = x - p0;
        const LD det = dot_ld(a, cross(b, d));
        const LD l1 = dot_ld(r, cross(b, d)) / det, l2 = dot_ld(a, cross(r, d)) / det, l3 = dot_ld(a, cross(b, r)) / det;
        return l1 >= 0 && l2 >= 0 && l3 >= 0 && 1 - l1 - l2 - l3 >= 0;
    };
}

/// D = c' + max_{y in bound} b'^T y computed exactly (200-bit MPFR) from the T inputs.
template <class T>
mpreal exact_d_sphere(const Quadric<T>& q, const Vec3<T>& eye, const BoundingSphere<T>& s) {
    mpreal bp[3], cp = LD(q.q[3][3]), y0[3];
    for (int i = 0; i < 3; ++i) {
        bp[i] = LD(q.q[3][i]);
        for (int j = 0; j < 3; ++j) bp[i] += mpreal(LD(q.q[j][i])) * mpreal(LD(eye[j]));
        y0[i] = mpreal(LD(s.center[i])) - mpreal(LD(eye[i]));
    }
    for (int i = 0; i < 3; ++i) cp += mpreal(LD(eye[i])) * (bp[i] + mpreal(LD(q.q[3][i])));
    mpreal d = cp + mpfr::sqrt(bp[0] * bp[0] + bp[1] * bp[1] + bp[2] * bp[2]) * mpreal(LD(s.radius));
    for (int i = 0; i < 3; ++i) d += y0[i] * bp[i];
    return d;
}

template <class T>
mpreal exact_d_tet(const Quadric<T>& q, const Vec3<T>& eye, const BoundingTet<T>& t) {
    mpreal bp[3], cp = LD(q.q[3][3]);
    for (int i = 0; i < 3; ++i) {
        bp[i] = LD(q.q[3][i]);
        for (int j = 0; j < 3; ++j) bp[i] += mpreal(LD(q.q[j][i])) * mpreal(LD(eye[j]));
    }
    for (int i = 0; i < 3; ++i) cp += mpreal(LD(eye[i])) * (bp[i] + mpreal(LD(q.q[3][i])));
    mpreal best;
    for (int k = 0; k < 4; ++k) {
        mpreal s = 0;
        for (int i = 0; i < 3; ++i) s += (mpreal(LD(t.p[k][i])) - mpreal(LD(eye[i]))) * bp[i];
        if (k == 0 || s > best) best = s;
    }
    return cp + best;
}

/// The same test in T without the rounding margin (what eq. 18 / 19 give when typed in directly).
template <class T>
bool unguarded_cull_sphere(const Quadric<T>& q, const Vec3<T>& eye, const BoundingSphere<T>& s) {
    const Quadric<T> qe = translate_to_eye(q, eye);
    const Vec3<T> bp = xyz(qe.q[3]);
    return (qe.q[3][3] + dot(s.center - eye, bp)) + s.radius * length(bp) < T(0);
}

template <class T>
bool unguarded_cull_tet(const Quadric<T>& q, const Vec3<T>& eye, const BoundingTet<T>& t) {
    const Quadric<T> qe = translate_to_eye(q, eye);
    const Vec3<T> bp = xyz(qe.q[3]);
    T best = dot(t.p[0] - eye, bp);
    for (int i = 1; i < 4; ++i) best = std::max(best, dot(t.p[i] - eye, bp));
    return qe.q[3][3] + best < T(0);
}

/// Magnitude S of the margin (see cull.hpp), in long double.
template <class T>
LD magnitude_s(const Quadric<T>& q, const Vec3<T>& eye, const Vec3<LD>* pts, int npts, LD radius) {
    Vec3<LD> mb{};
    LD mc = std::fabs(LD(q.q[3][3]));
    for (int i = 0; i < 3; ++i) {
        mb[i] = std::fabs(LD(q.q[3][i]));
        for (int j = 0; j < 3; ++j) mb[i] += std::fabs(LD(q.q[j][i])) * std::fabs(LD(eye[j]));
    }
    for (int i = 0; i < 3; ++i) mc += std::fabs(LD(eye[i])) * (mb[i] + std::fabs(LD(q.q[3][i])));
    LD best = 0;
    for (int k = 0; k < npts; ++k) {
        LD s = 0;
        for (int i = 0; i < 3; ++i) s += std::fabs(pts[k][i] - LD(eye[i])) * mb[i];
        best = std::max(best, s);
    }
    return mc + best + radius * norm_ld(mb);
}

}  // namespace

TEST_CASE_TEMPLATE("culling with a bounding sphere is conservative: no front-facing hit inside (brute force)", T, float, double) {
    int culled = 0, total = 0, rays_checked = 0;
    for (std::uint32_t it = 0; it < 1500; ++it) {
        auto rng = rng_for(301, it);
        const CullCase<T> c = make_cull_case<T>(rng);
        ++total;
        if (!cull_sphere(c.q, c.eye, c.sphere)) continue;
        ++culled;
        REQUIRE(front_hits_in_bound(c.q, c.eye, sphere_inside(c.sphere), sphere_sampler(c.sphere), 200, rng) == 0);
        rays_checked += 200;
    }
    MESSAGE(std::string(scalar_traits<T>::name) << ": sphere bound: culled " << culled << " of " << total << " random SLIM-like configurations ("
                                                << 100.0 * culled / total << "%), " << rays_checked << " brute-force rays found no front-facing hit");
    CHECK(culled > total / 5);
}

TEST_CASE_TEMPLATE("culling with a bounding tetrahedron is conservative: no front-facing hit inside (brute force)", T, float, double) {
    int culled = 0, total = 0;
    for (std::uint32_t it = 0; it < 1500; ++it) {
        auto rng = rng_for(302, it);
        const CullCase<T> c = make_cull_case<T>(rng);
        ++total;
        if (!cull_tet(c.q, c.eye, c.tet)) continue;
        ++culled;
        REQUIRE(front_hits_in_bound(c.q, c.eye, tet_inside(c.tet), tet_sampler(c.tet), 200, rng) == 0);
    }
    MESSAGE(std::string(scalar_traits<T>::name) << ": tetrahedron bound: culled " << culled << " of " << total << " ("
                                                << 100.0 * culled / total << "%)");
    CHECK(culled > total / 5);
}

TEST_CASE_TEMPLATE("how much culling the paper's test leaves on the table (brute force estimate)", T, float, double) {
    // Configurations without any front-facing hit in the bound that are not culled: eq. 18 bounds
    // max b'^T y over the whole sphere, not over the surface inside it, so it is not tight.
    int no_front = 0, culled = 0;
    for (std::uint32_t it = 0; it < 400; ++it) {
        auto rng = rng_for(303, it);
        const CullCase<T> c = make_cull_case<T>(rng);
        const bool cull = cull_sphere(c.q, c.eye, c.sphere);
        const int hits = front_hits_in_bound(c.q, c.eye, sphere_inside(c.sphere), sphere_sampler(c.sphere), 400, rng);
        no_front += hits == 0;
        culled += cull;
        if (cull) REQUIRE(hits == 0);
    }
    MESSAGE(std::string(scalar_traits<T>::name) << ": sphere bound: " << culled << " culled of " << no_front
                                                << " configurations where 400 rays found no front-facing hit (of 400)");
    CHECK(culled <= no_front);
    CHECK(culled > no_front / 2);
}

TEST_CASE_TEMPLATE("culling is conservative under rounding: near the threshold, culled implies exact D < 0", T, float, double) {
    mpreal::set_default_prec(200);
    const LD eps = std::numeric_limits<T>::epsilon();
    int culled_s = 0, culled_t = 0, unsafe_s = 0, unsafe_t = 0, n = 0;
    LD worst_err = 0;
    for (std::uint32_t it = 0; it < 3000; ++it) {
        auto rng = rng_for(304, it);
        CullCase<T> c = make_cull_case<T>(rng);
        if (it % 2) c.eye = c.eye * T(uniform(rng, 5, 50));  // far eyes: large, cancelling c'
        // Move c so that the exact D is within +-100 eps S of zero (both bound types).
        const Vec3<LD> sc[1] = {cast<LD>(c.sphere.center)};
        const LD s_sphere = magnitude_s(c.q, c.eye, sc, 1, LD(c.sphere.radius));
        Vec3<LD> tp[4];
        for (int i = 0; i < 4; ++i) tp[i] = cast<LD>(c.tet.p[i]);
        const LD s_tet = magnitude_s(c.q, c.eye, tp, 4, 0);
        const bool sphere_round = it % 3 != 0;
        const LD target = LD(uniform(rng, -1, 1) * log_uniform(rng, -2, 2)) * eps * (sphere_round ? s_sphere : s_tet);
        const mpreal d0 = sphere_round ? exact_d_sphere(c.q, c.eye, c.sphere) : exact_d_tet(c.q, c.eye, c.tet);
        c.q.q[3][3] = T(LD(c.q.q[3][3]) - static_cast<LD>(d0) + target);  // D depends on c with slope 1
        ++n;
        // The guarded tests: culled => exact D < 0.
        if (cull_sphere(c.q, c.eye, c.sphere)) {
            ++culled_s;
            CHECK(exact_d_sphere(c.q, c.eye, c.sphere) < 0);
        }
        if (cull_tet(c.q, c.eye, c.tet)) {
            ++culled_t;
            CHECK(exact_d_tet(c.q, c.eye, c.tet) < 0);
        }
        // The rounding error of D in units of eps S (the margin is 16).
        {
            const Quadric<T> qe = translate_to_eye(c.q, c.eye);
            const Vec3<T> bp = xyz(qe.q[3]);
            const T ds = (qe.q[3][3] + dot(c.sphere.center - c.eye, bp)) + c.sphere.radius * length(bp);
            worst_err = std::max(worst_err, std::fabs(static_cast<LD>(mpreal(LD(ds)) - exact_d_sphere(c.q, c.eye, c.sphere))) / (eps * s_sphere));
        }
        // Without the margin, rounding alone culls quadrics whose exact D is >= 0.
        unsafe_s += unguarded_cull_sphere(c.q, c.eye, c.sphere) && exact_d_sphere(c.q, c.eye, c.sphere) >= 0;
        unsafe_t += unguarded_cull_tet(c.q, c.eye, c.tet) && exact_d_tet(c.q, c.eye, c.tet) >= 0;
    }
    MESSAGE(std::string(scalar_traits<T>::name) << ": near-threshold configurations: " << n << "; culled (all with exact D < 0): sphere "
                                                << culled_s << ", tet " << culled_t << "; without the margin, wrongly culled: sphere "
                                                << unsafe_s << ", tet " << unsafe_t << "; max |D - D_exact| / (eps S) = " << double(worst_err));
    CHECK(worst_err < 16);
    CHECK(culled_s > 100);
    CHECK(culled_t > 100);
    CHECK(unsafe_s + unsafe_t > 0);  // the margin is needed
}

TEST_CASE_TEMPLATE("NaN or infinite inputs never cull", T, float, double) {
    const T nan = std::numeric_limits<T>::quiet_NaN(), inf = std::numeric_limits<T>::infinity();
    // Start from a configuration that culls with both bounds, then poison one input.
    CullCase<T> base{};
    bool found = false;
    for (std::uint32_t it = 0; it < 100 && !found; ++it) {
        auto r = rng_for(305, it);
        base = make_cull_case<T>(r);
        found = cull_sphere(base.q, base.eye, base.sphere) && cull_tet(base.q, base.eye, base.tet);
    }
    REQUIRE(found);
    for (T bad : {nan, inf, -inf}) {
        for (int k = 0; k < 16; ++k) {
            CullCase<T> c = base;
            c.q.q[k / 4][k % 4] = bad;
            c.q.q[k % 4][k / 4] = bad;
            CHECK_FALSE(cull_sphere(c.q, c.eye, c.sphere));
            CHECK_FALSE(cull_tet(c.q, c.eye, c.tet));
        }
        for (int k = 0; k < 3; ++k) {
            CullCase<T> c = base;
            c.eye[k] = bad;
            CHECK_FALSE(cull_sphere(c.q, c.eye, c.sphere));
            CHECK_FALSE(cull_tet(c.q, c.eye, c.tet));
            c = base;
            c.sphere.center[k] = bad;
            CHECK_FALSE(cull_sphere(c.q, c.eye, c.sphere));
            for (int corner = 0; corner < 4; ++corner) {
                c = base;
                c.tet.p[corner][k] = bad;
                CHECK_FALSE(cull_tet(c.q, c.eye, c.tet));
            }
        }
        CullCase<T> c = base;
        c.sphere.radius = bad;
        CHECK_FALSE(cull_sphere(c.q, c.eye, c.sphere));
    }
}

TEST_CASE_TEMPLATE("the eye-origin forms agree with the world forms away from the threshold", T, float, double) {
    int agree = 0, total = 0;
    for (std::uint32_t it = 0; it < 2000; ++it) {
        auto rng = rng_for(306, it);
        const CullCase<T> c = make_cull_case<T>(rng);
        const Quadric<T> qe = translate_to_eye(c.q, c.eye);
        BoundingTet<T> te{};
        for (int i = 0; i < 4; ++i) te.p[i] = c.tet.p[i] - c.eye;
        const bool s_world = cull_sphere(c.q, c.eye, c.sphere), s_eye = cull_sphere_eye(qe, c.sphere.center - c.eye, c.sphere.radius);
        const bool t_world = cull_tet(c.q, c.eye, c.tet), t_eye = cull_tet_eye(qe, te);
        // The world forms have the larger margin, so they never cull where the eye forms do not.
        CHECK((!s_world || s_eye));
        CHECK((!t_world || t_eye));
        agree += (s_world == s_eye) + (t_world == t_eye);
        total += 2;
    }
    CHECK(agree >= total * 99 / 100);
}
