// tests/core/test_ray.cpp -- ray coefficients, error-free transformations, root formulations against MPFR
#include <doctest/doctest.h>

#include <cfenv>
#include <cmath>
#include <sstream>

#include "core/core_testing.hpp"
#include "quadcast/ray.hpp"

using namespace quadcast;
using namespace qc_test;
using mpfr::mpreal;

namespace {

struct MpfrPrecision {
    MpfrPrecision() { mpreal::set_default_prec(200); }
};

/// Exact (200-bit) roots of the quadratic with the given T coefficients.
struct RefRoots {
    bool real = false;       // disc >= 0
    bool has_front = false;  // the front-facing root (alpha l + beta = -sqrt(disc)) is > 0
    mpreal front;
    int npos = 0;            // positive roots, ascending
    mpreal pos[2];
    mpreal disc;
};

RefRoots ref_roots(const mpreal& a, const mpreal& b, const mpreal& g) {
    RefRoots r;
    r.disc = b * b - a * g;
    if (r.disc < 0) return r;
    r.real = true;
    const mpreal s = mpfr::sqrt(r.disc);
    const mpreal q = -(b + (b < 0 ? -s : s));
    if (q == 0) return r;  // alpha gamma = beta = 0: no isolated roots
    // Front root: beta < 0 ? gamma / q : q / alpha.
    if (b < 0) { r.front = g / q; r.has_front = r.front > 0; }
    else if (a != 0) { r.front = q / a; r.has_front = r.front > 0; }
    mpreal roots[2];
    int n = 0;
    if (a != 0) roots[n++] = q / a;
    roots[n++] = g / q;
    if (n == 2 && roots[1] < roots[0]) std::swap(roots[0], roots[1]);
    for (int i = 0; i < n; ++i)
        if (roots[i] > 0) r.pos[r.npos++] = roots[i];
    return r;
}

template <class T>
RefRoots ref_roots(const RayCoefficients<T>& c) {
    return ref_roots(mpreal(LD(c.alpha)), mpreal(LD(c.beta)), mpreal(LD(c.gamma)));
}

/// alpha, beta, gamma of the T-valued quadric and ray, computed exactly (eq. 6 in 200 bits).
struct ExactCoefficients {
    mpreal a, b, g;
};

template <class T>
ExactCoefficients exact_coefficients(const Quadric<T>& q, const Vec3<T>& e, const Vec3<T>& v) {
    mpreal eh[4] = {LD(e[0]), LD(e[1]), LD(e[2]), 1}, vh[4] = {LD(v[0]), LD(v[1]), LD(v[2]), 0};
    ExactCoefficients c{0, 0, 0};
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) {
            const mpreal qij = LD(q.q[j][i]);
            c.a += vh[i] * qij * vh[j];
            c.b += eh[i] * qij * vh[j];
            c.g += eh[i] * qij * eh[j];
        }
    return c;
}

enum class Category { random, grazing, far_eye, near_linear };
constexpr Category categories[] = {Category::random, Category::grazing, Category::far_eye, Category::near_linear};
const char* name_of(Category c) {
    switch (c) {
        case Category::random: return "random";
        case Category::grazing: return "grazing";
        case Category::far_eye: return "far eye";
        case Category::near_linear: return "near-linear";
    }
    return "?";
}
constexpr RootFormula formulas[] = {RootFormula::classic, RootFormula::stoll, RootFormula::stable};
const char* name_of(RootFormula f) {
    switch (f) {
        case RootFormula::classic: return "classic";
        case RootFormula::stoll: return "stoll";
        case RootFormula::stable: return "stable";
    }
    return "?";
}

template <class T>
struct RayCase {
    Quadric<T> q;
    Vec3<T> e, v;
};

/// Sets c so that p lies on the quadric (to the rounding of c).
template <class T>
void put_on_surface(Quadric<T>& q, const Vec3<LD>& p) {
    Mat4<LD> ql = to_ld(q);
    ql[3][3] = 0;
    q.q[3][3] = T(-eval_ld(ql, p));
}

template <class T>
Vec3<T> round_dir(const Vec3<LD>& d) {
    const LD l = norm_ld(d);
    return vec3(T(d[0] / l), T(d[1] / l), T(d[2] / l));
}

/// random: random quadric, eye in [-3,3]^3, random direction.
/// grazing: a ray tangent at a surface point p, its eye moved off the tangent by 10^U(-9,-1).
/// far eye: an eye 10^U(1,4) away from a surface point p near the origin, aimed at p.
/// near-linear: A scaled by 10^U(-9,-1), so alpha gamma << beta^2 (the linear case threshold
/// of the classic formulation lies inside that range for float and double).
template <class T>
RayCase<T> make_case(Category cat, std::mt19937& rng) {
    RayCase<T> r{random_quadric<T>(rng), random_vec<T>(rng, -3, 3), random_dir<T>(rng)};
    switch (cat) {
        case Category::random: break;
        case Category::grazing: {
            const Vec3<LD> p = cast<LD>(random_vec<T>(rng, -1, 1));
            put_on_surface(r.q, p);
            const Vec3<LD> g = grad_ld(to_ld(r.q), p);
            const Vec3<LD> n = g / norm_ld(g);
            Vec3<LD> t = cast<LD>(random_dir<double>(rng));
            t = t - dot_ld(t, n) * n;
            t = t / norm_ld(t);
            const LD off = (uniform(rng, 0, 1) < 0.5 ? -1 : 1) * LD(log_uniform(rng, -9, -1));
            const LD dist = uniform(rng, 1, 3);
            const Vec3<LD> e = p - dist * t + off * n;
            r.e = vec3(T(e[0]), T(e[1]), T(e[2]));
            r.v = round_dir<T>(t);
            break;
        }
        case Category::far_eye: {
            const Vec3<LD> p = cast<LD>(random_vec<T>(rng, -1, 1));
            put_on_surface(r.q, p);
            const Vec3<LD> w = cast<LD>(random_dir<double>(rng));
            const Vec3<LD> e = p + LD(log_uniform(rng, 1, 4)) * w;
            r.e = vec3(T(e[0]), T(e[1]), T(e[2]));
            r.v = round_dir<T>(p - cast<LD>(r.e));
            break;
        }
        case Category::near_linear: {
            const T s = T(log_uniform(rng, -9, -1));
            for (int j = 0; j < 3; ++j)
                for (int i = 0; i < 3; ++i) r.q.q[j][i] = r.q.q[j][i] * s;
            break;
        }
    }
    return r;
}

constexpr int samples_per_category = 3000;

}  // namespace

TEST_CASE_TEMPLATE("eye-origin alpha, beta, gamma (eq. 10) equal the general ones (eq. 6) to rounding", T, float, double) {
    const LD eps = std::numeric_limits<T>::epsilon();
    LD worst = 0;
    for (std::uint32_t it = 0; it < 2000; ++it) {
        auto rng = rng_for(201, it);
        const Quadric<T> q = random_quadric<T>(rng);
        const Vec3<T> e = random_vec<T>(rng, -20, 20), v = random_dir<T>(rng);
        const RayCoefficients<T> g = ray_coefficients(q, e, v);
        const RayCoefficients<T> o = ray_coefficients_eye(translate_to_eye(q, e), v);
        CHECK(g.alpha == o.alpha);  // same operations
        CHECK(g.beta == o.beta);    // b_i + (A e)_i == (A e)_i + b_i * 1
        CHECK(g.gamma == evaluate(q, e));
        Vec4<LD> ae{};
        for (int i = 0; i < 3; ++i) ae[i] = std::fabs(LD(e[i]));
        ae[3] = 1;
        const LD err = std::fabs(LD(g.gamma) - LD(o.gamma)) / (eps * eval_mag_ld(to_ld(q), ae));
        worst = std::max(worst, err);
        REQUIRE(err <= 8);
    }
    MESSAGE(std::string(scalar_traits<T>::name) << ": max |gamma - c'| / (eps |e~|^T|Q||e~|) = " << double(worst));
    CHECK(worst > 0);
}

TEST_CASE_TEMPLATE("two_sum and two_product are error-free", T, float, double) {
    MpfrPrecision prec;
    for (std::uint32_t it = 0; it < 5000; ++it) {
        auto rng = rng_for(202, it);
        const T a = T(uniform(rng, -1, 1) * log_uniform(rng, -10, 10));
        const T b = T(uniform(rng, -1, 1) * log_uniform(rng, -10, 10));
        const TwoTerm<T> s = two_sum(a, b);
        const TwoTerm<T> p = two_product(a, b);
        CHECK(s.hi == a + b);
        CHECK(p.hi == a * b);
        CHECK(mpreal(LD(s.hi)) + mpreal(LD(s.lo)) == mpreal(LD(a)) + mpreal(LD(b)));
        CHECK(mpreal(LD(p.hi)) + mpreal(LD(p.lo)) == mpreal(LD(a)) * mpreal(LD(b)));
        const TwoTerm<T> sp = veltkamp_split(a);
        CHECK(sp.hi + sp.lo == a);
    }
    CHECK(veltkamp_constant<T>() == (std::is_same_v<T, float> ? T(4097) : T(134217729)));
}

TEST_CASE_TEMPLATE("the accurate discriminant is within a few ulp of the exact one, the naive one is not", T, float, double) {
    MpfrPrecision prec;
    std::vector<double> acc, naive;
    for (std::uint32_t it = 0; it < 5000; ++it) {
        auto rng = rng_for(203, it);
        // beta^2 and alpha gamma agree to 10^U(-12, 0) relative: cancellation.
        const double a = uniform(rng, 0.1, 10), g = uniform(rng, 0.1, 10);
        const double b = std::sqrt(a * g) * (1 + uniform(rng, -1, 1) * log_uniform(rng, -12, 0));
        const RayCoefficients<T> c{T(a), T(b), T(g)};
        const mpreal exact = mpreal(LD(c.beta)) * mpreal(LD(c.beta)) - mpreal(LD(c.alpha)) * mpreal(LD(c.gamma));
        if (exact == 0) continue;
        acc.push_back(ulp_error(discriminant_accurate(c), exact));
        naive.push_back(ulp_error(discriminant_naive(c), exact));
    }
    const Stats sa = stats_of(acc), sn = stats_of(naive);
    MESSAGE(std::string(scalar_traits<T>::name) << ": discriminant error in ulps (median / p99 / max): accurate " << fmt(sa)
                                                << ", naive " << fmt(sn));
    CHECK(sa.max <= 2);
    CHECK(sn.p99 > 1000);  // the comparison is meaningful: the naive form does cancel here
}

TEST_CASE_TEMPLATE("root formulations compared against an MPFR reference root", T, float, double) {
    MpfrPrecision prec;
    std::ostringstream report;
    report << scalar_traits<T>::name << ": |lambda - lambda_exact| in ulps (median / p99 / max) for the exact roots of the"
           << " rounded alpha, beta, gamma; [n] compared cases, {m} hit/miss disagreements\n";
    for (Category cat : categories) {
        std::vector<double> err_front[3], err_near[3];
        int mismatch_front[3] = {0, 0, 0}, mismatch_near[3] = {0, 0, 0};
        for (int it = 0; it < samples_per_category; ++it) {
            auto rng = rng_for(204 + 10 * static_cast<std::uint32_t>(cat), static_cast<std::uint32_t>(it));
            const RayCase<T> rc = make_case<T>(cat, rng);
            const RayCoefficients<T> c = ray_coefficients(rc.q, rc.e, rc.v);
            const RefRoots ref = ref_roots(c);
            for (int f = 0; f < 3; ++f) {
                // Culling on: the front-facing root.
                const RayHit<T> h = front_root(c, formulas[f]);
                if (h.hit && ref.has_front) err_front[f].push_back(ulp_error(h.lambda, ref.front));
                else if (h.hit != ref.has_front) ++mismatch_front[f];
                // Culling off: the first valid root of the near-first pair (no bound).
                const RayHit<T> n = pick_first(roots_near_first(c, formulas[f]), true, true);
                if (n.hit && ref.npos > 0) err_near[f].push_back(ulp_error(n.lambda, ref.pos[0]));
                else if (n.hit != (ref.npos > 0)) ++mismatch_near[f];
            }
        }
        Stats sf[3], sn[3];
        for (int f = 0; f < 3; ++f) {
            sf[f] = stats_of(err_front[f]);
            sn[f] = stats_of(err_near[f]);
            report << "  " << name_of(cat) << ", " << name_of(formulas[f]) << ": front " << fmt(sf[f]) << " [" << sf[f].n
                   << "] {" << mismatch_front[f] << "}, near-first " << fmt(sn[f]) << " [" << sn[f].n << "] {"
                   << mismatch_near[f] << "}\n";
        }
        // The default (stable) is within a few ulp everywhere, misses nothing, and is the most
        // accurate formulation by the maximum error in every category and mode.
        const int s = 2;
        CHECK(formulas[s] == default_root_formula);
        CHECK(sf[s].max <= 3);
        CHECK(sn[s].max <= 3);
        CHECK(mismatch_front[s] == 0);
        CHECK(mismatch_near[s] == 0);
        for (int f = 0; f < 2; ++f) {
            CHECK(sf[s].max <= sf[f].max);
            CHECK(sn[s].max <= sn[f].max);
        }
    }
    MESSAGE(report.str());
}

TEST_CASE_TEMPLATE("the default roots lie on the quadric (backward error) and the front root faces the viewer", T, float, double) {
    MpfrPrecision prec;
    const LD eps = std::numeric_limits<T>::epsilon();
    std::ostringstream report;
    report << scalar_traits<T>::name << ": front root, in eps: backward error |f(x)| / (|e~|+|l v~|)^T|Q|(...) and"
           << " |f(x)| / (|grad f| |x|) (median / p99 / max), the latter also for the exact root of the exact"
           << " coefficients rounded to T\n";
    for (Category cat : categories) {
        std::vector<double> backward, rel, rel_ref;
        int facing_checked = 0;
        for (int it = 0; it < samples_per_category; ++it) {
            auto rng = rng_for(205 + 10 * static_cast<std::uint32_t>(cat), static_cast<std::uint32_t>(it));
            const RayCase<T> rc = make_case<T>(cat, rng);
            const RayHit<T> h = front_root(ray_coefficients(rc.q, rc.e, rc.v));
            if (!h.hit) continue;
            const Mat4<LD> ql = to_ld(rc.q);
            const Vec3<LD> el = cast<LD>(rc.e), vl = cast<LD>(rc.v);
            const auto residuals = [&](LD lambda, double* rel_out) {
                const Vec3<LD> x = el + lambda * vl;
                const LD f = eval_ld(ql, x);
                const Vec3<LD> g = grad_ld(ql, x);
                *rel_out = double(std::fabs(f) / (norm_ld(g) * norm_ld(x)) / eps);
                Vec4<LD> m{};
                for (int i = 0; i < 3; ++i) m[i] = std::fabs(el[i]) + std::fabs(lambda * vl[i]);
                m[3] = 1;
                return std::fabs(f) / (eval_mag_ld(ql, m) * eps);
            };
            double r = 0, r_ref = 0;
            const LD bw = residuals(LD(h.lambda), &r);
            backward.push_back(double(bw));
            rel.push_back(r);
            const ExactCoefficients ex = exact_coefficients(rc.q, rc.e, rc.v);
            const RefRoots exact = ref_roots(ex.a, ex.b, ex.g);
            if (exact.has_front) {
                residuals(LD(static_cast<T>(exact.front)), &r_ref);
                rel_ref.push_back(r_ref);
            }
            REQUIRE(bw <= 8);
            // Where the coefficients are well conditioned, the relative distance to the surface is
            // within a few eps of that of the exact root rounded to T (grazing rays and far eyes are
            // dominated by the rounding of alpha, beta, gamma: covered by the backward error).
            if (exact.has_front && (cat == Category::random || cat == Category::near_linear)) CHECK(r <= r_ref + 12);
            // Front-facing: v . grad f(x) < 0 where the ray is not grazing (|v.n| > 1e-3 |n|).
            const Vec3<LD> g = grad_ld(ql, el + LD(h.lambda) * vl);
            const LD vn = dot_ld(vl, g);
            if (std::fabs(vn) > 1e-3L * norm_ld(g)) {
                ++facing_checked;
                CHECK(vn < 0);
            }
        }
        report << "  " << name_of(cat) << ": backward " << fmt(stats_of(backward)) << ", |f|/(|grad f||x|) "
               << fmt(stats_of(rel)) << ", exact root rounded " << fmt(stats_of(rel_ref)) << " [" << backward.size()
               << " hits, facing checked on " << facing_checked << "]\n";
        CHECK(facing_checked > 100);
    }
    MESSAGE(report.str());
}

TEST_CASE_TEMPLATE("near-first returns the nearest root inside the bound", T, float, double) {
    MpfrPrecision prec;
    int compared = 0, far_chosen = 0, skipped = 0;
    for (std::uint32_t it = 0; it < 4000; ++it) {
        auto rng = rng_for(206, it);
        const RayCase<T> rc = make_case<T>(Category::random, rng);
        const RayCoefficients<T> c = ray_coefficients(rc.q, rc.e, rc.v);
        const RefRoots ref = ref_roots(c);
        // A sphere around a point of the ray, sometimes containing both roots, one or none.
        const Vec3<T> center = ray_point(rc.e, rc.v, T(uniform(rng, 0, 6))) + random_vec<T>(rng, -0.5, 0.5);
        const T radius = T(uniform(rng, 0.2, 3));
        // Reference: the nearest positive exact root whose point is inside (skip borderline points).
        bool borderline = false;
        int want = -1;
        for (int i = 0; i < ref.npos && want < 0; ++i) {
            const Vec3<LD> x = cast<LD>(rc.e) + LD(static_cast<LD>(ref.pos[i])) * cast<LD>(rc.v);
            const Vec3<LD> d = x - cast<LD>(center);
            const LD s = dot_ld(d, d) - LD(radius) * LD(radius);
            if (std::fabs(s) < 1e-3L * LD(radius) * LD(radius)) borderline = true;
            if (s <= 0) want = i;
        }
        if (borderline) { ++skipped; continue; }
        for (RootFormula f : formulas) {
            const RootPair<T> pr = roots_near_first(c, f);
            if (pr.near_valid && pr.far_valid) CHECK(pr.lambda_near <= pr.lambda_far);
            const RayHit<T> h = pick_first(pr, inside_sphere(ray_point(rc.e, rc.v, pr.lambda_near), center, radius),
                                           inside_sphere(ray_point(rc.e, rc.v, pr.lambda_far), center, radius));
            REQUIRE(h.hit == (want >= 0));
            if (want < 0) continue;
            // Within 1e-3 relative for every formulation (their errors differ, the choice must not).
            CHECK(std::fabs(LD(h.lambda) - static_cast<LD>(ref.pos[want])) <= 1e-3L * static_cast<LD>(ref.pos[want]));
            if (f == default_root_formula) {
                CHECK(ulp_error(h.lambda, ref.pos[want]) <= 3);
                ++compared;
                far_chosen += want == 1;
            }
        }
    }
    MESSAGE(std::string(scalar_traits<T>::name) << ": near-first with a sphere bound: " << compared << " hits compared, "
                                                << far_chosen << " of them the far root, " << skipped << " borderline skipped");
    CHECK(far_chosen > 50);
}

TEST_CASE_TEMPLATE("near-first with a tetrahedron bound and the tetrahedron inside test", T, float, double) {
    MpfrPrecision prec;
    int compared = 0;
    for (std::uint32_t it = 0; it < 2000; ++it) {
        auto rng = rng_for(207, it);
        const RayCase<T> rc = make_case<T>(Category::random, rng);
        const RayCoefficients<T> c = ray_coefficients(rc.q, rc.e, rc.v);
        const RefRoots ref = ref_roots(c);
        // A tetrahedron (not too flat) around a root or a random point of the ray.
        const T at = ref.npos > 0 ? static_cast<T>(ref.pos[it % ref.npos]) : T(uniform(rng, 0, 6));
        const Vec3<T> mid = ray_point(rc.e, rc.v, at);
        BoundingTet<T> tet{};
        LD shape = 0;
        do {
            // Random corners, shifted so that mid has barycentric weights w (mid is inside when
            // it > 0, i.e. 3 times out of 4).
            double w[4], wsum = 0;
            for (double& x : w) wsum += (x = uniform(rng, 0.05, 1));
            if (it % 4 == 3) w[0] = -0.3 * wsum;
            wsum = w[0] + w[1] + w[2] + w[3];
            Vec3<double> off[4], wc{{0, 0, 0}};
            for (int i = 0; i < 4; ++i) {
                off[i] = random_vec<double>(rng, -1.5, 1.5);
                wc = wc + (w[i] / wsum) * off[i];
            }
            for (int i = 0; i < 4; ++i) tet.p[i] = mid + cast<T>(off[i] - wc);
            const Vec3<LD> a = cast<LD>(tet.p[1]) - cast<LD>(tet.p[0]), b = cast<LD>(tet.p[2]) - cast<LD>(tet.p[0]),
                           d = cast<LD>(tet.p[3]) - cast<LD>(tet.p[0]);
            shape = std::fabs(dot_ld(a, cross(b, d))) / (norm_ld(a) * norm_ld(b) * norm_ld(d));
        } while (shape < 0.05L);
        const TetPlanes<T> planes = tet_planes(tet);
        // Barycentric reference for the inside test.
        const auto bary_inside = [&](const Vec3<LD>& x, bool* border) {
            const Vec3<LD> p0 = cast<LD>(tet.p[0]);
            const Vec3<LD> a = cast<LD>(tet.p[1]) - p0, b = cast<LD>(tet.p[2]) - p0, d = cast<LD>(tet.p[3]) - p0, r = x - p0;
            const LD det = dot_ld(a, cross(b, d));
            const LD l1 = dot_ld(r, cross(b, d)) / det, l2 = dot_ld(a, cross(r, d)) / det, l3 = dot_ld(a, cross(b, r)) / det;
            const LD l0 = 1 - l1 - l2 - l3;
            const LD m = std::min(std::min(l0, l1), std::min(l2, l3));
            *border = std::fabs(m) < 1e-4L;
            return m >= 0;
        };
        bool border = false;
        int want = -1;
        for (int i = 0; i < ref.npos && want < 0; ++i) {
            bool b = false;
            if (bary_inside(cast<LD>(rc.e) + static_cast<LD>(ref.pos[i]) * cast<LD>(rc.v), &b)) want = i;
            border = border || b;
        }
        if (border) continue;
        const RootPair<T> pr = roots_near_first(c);
        const RayHit<T> h = pick_first(pr, inside_tet(planes, ray_point(rc.e, rc.v, pr.lambda_near)),
                                       inside_tet(planes, ray_point(rc.e, rc.v, pr.lambda_far)));
        REQUIRE(h.hit == (want >= 0));
        if (want >= 0) {
            CHECK(ulp_error(h.lambda, ref.pos[want]) <= 3);
            ++compared;
        }
        // Points near the corners (inside) and the centroid are inside, points beyond a face or a
        // corner are not. (Points ON a face are borderline under rounding: not tested.)
        const Vec3<T> cen = (T(0.25) * ((tet.p[0] + tet.p[1]) + (tet.p[2] + tet.p[3])));
        CHECK(inside_tet(planes, cen));
        for (const Vec3<T>& p : tet.p) {
            CHECK(inside_tet(planes, cen + T(0.95) * (p - cen)));
            CHECK_FALSE(inside_tet(planes, cen + T(1.05) * (p - cen)));
        }
        for (int i = 0; i < 4; ++i) {
            // Beyond the face opposite corner i.
            const Vec3<T> fc = T(1) / T(3) * ((tet.p[(i + 1) % 4] + tet.p[(i + 2) % 4]) + tet.p[(i + 3) % 4]);
            CHECK_FALSE(inside_tet(planes, fc + T(0.05) * (fc - tet.p[i])));
        }
    }
    MESSAGE(std::string(scalar_traits<T>::name) << ": near-first with a tetrahedron bound: " << compared << " hits compared");
    CHECK(compared > 200);
}

TEST_CASE_TEMPLATE("the linear case: alpha = 0 gives -gamma / (2 beta), front-facing only for beta < 0", T, float, double) {
    for (RootFormula f : formulas) {
        // 2 beta lambda + gamma = 0 with beta < 0: lambda = 3.
        const RayCoefficients<T> c{T(0), T(-2), T(12)};
        const RayHit<T> h = front_root(c, f);
        CHECK(h.hit);
        CHECK(h.lambda == T(3));
        const RootPair<T> p = roots_near_first(c, f);
        CHECK(p.near_valid);
        CHECK(p.lambda_near == T(3));
        CHECK_FALSE(p.far_valid);
        // beta > 0: the root -3 is behind the eye, and there is no front-facing root at all.
        const RayCoefficients<T> b{T(0), T(2), T(12)};
        CHECK_FALSE(front_root(b, f).hit);
        CHECK_FALSE(pick_first(roots_near_first(b, f), true, true).hit);
        // beta > 0 with the root ahead: back-facing, so culled, but found without culling.
        const RayCoefficients<T> d{T(0), T(2), T(-12)};
        CHECK_FALSE(front_root(d, f).hit);
        const RayHit<T> dn = pick_first(roots_near_first(d, f), true, true);
        CHECK(dn.hit);
        CHECK(dn.lambda == T(3));
    }
    // The classic formulation switches at the documented threshold; its error there is bounded
    // by about sqrt(eps / 2) relative (the best eq. 7 can do; the other formulations need no switch).
    MpfrPrecision prec;
    const double tau = double(linear_case_threshold<T>());
    CHECK(tau == doctest::Approx(std::sqrt(8.0 * double(std::numeric_limits<T>::epsilon()))).epsilon(1e-6));
    double worst = 0;
    for (std::uint32_t it = 0; it < 2000; ++it) {
        auto rng = rng_for(208, it);
        const double ratio = log_uniform(rng, std::log10(tau) - 2, std::log10(tau) + 2);  // alpha gamma / beta^2
        const RayCoefficients<T> c{T(ratio * uniform(rng, 0.5, 2)), T(-1), T(1)};
        const RefRoots ref = ref_roots(c);
        const RayHit<T> h = front_root<RootFormula::classic>(c);
        REQUIRE(h.hit);
        worst = std::max(worst, std::fabs(double(h.lambda) - ref.front.toDouble()) / ref.front.toDouble());
    }
    MESSAGE(std::string(scalar_traits<T>::name) << ": classic formulation near the linear-case switch: max relative error "
                                                << worst << " (sqrt(eps/2) = " << std::sqrt(double(std::numeric_limits<T>::epsilon()) / 2) << ")");
    CHECK(worst <= 2 * std::sqrt(double(std::numeric_limits<T>::epsilon()) / 2));
}

TEST_CASE_TEMPLATE("a negative discriminant or non-finite coefficients never hit, and nothing divides by zero", T, float, double) {
    const T nan = std::numeric_limits<T>::quiet_NaN(), inf = std::numeric_limits<T>::infinity();
    const RayCoefficients<T> cases[] = {
        {T(1), T(1), T(2)},    // disc = -1
        {T(-1), T(0), T(-1)},  // disc = -1
        {nan, T(-1), T(1)},  {T(1), nan, T(1)},  {T(1), T(-1), nan},
        {inf, T(-1), T(1)},  {T(1), -inf, T(1)}, {T(1), T(-1), inf},
        {T(0), T(0), T(1)},    // constant: no root
        {T(0), T(0), T(0)},    // identically zero along the ray
    };
    for (RootFormula f : formulas) {
        for (const RayCoefficients<T>& c : cases) {
            CHECK_FALSE(front_root(c, f).hit);
            const RootPair<T> p = roots_near_first(c, f);
            CHECK_FALSE(p.near_valid);
            CHECK_FALSE(p.far_valid);
        }
    }
    // With finite inputs, no formulation raises the divide-by-zero flag (divisions are guarded).
    const RayCoefficients<T> finite[] = {{T(0), T(0), T(1)}, {T(0), T(0), T(0)}, {T(0), T(2), T(0)}, {T(1), T(0), T(0)},
                                         {T(0), T(-2), T(12)}, {T(0), T(2), T(12)}};
    std::feclearexcept(FE_ALL_EXCEPT);
    for (RootFormula f : formulas)
        for (const RayCoefficients<T>& c : finite) {
            volatile T sink = front_root(c, f).lambda + roots_near_first(c, f).lambda_near + roots_near_first(c, f).lambda_far;
            (void)sink;
        }
    CHECK_FALSE(std::fetestexcept(FE_DIVBYZERO));
}

TEST_CASE_TEMPLATE("the eye on the surface (gamma = 0): the root 0 is not a hit, the other one is", T, float, double) {
    // alpha = 1, beta = -2, gamma = 0: roots 0 and 4; v . n at 4: alpha 4 + beta = 2 > 0 (back-facing).
    for (RootFormula f : {RootFormula::classic, RootFormula::stable}) {
        const RayCoefficients<T> c{T(1), T(-2), T(0)};
        const RayHit<T> n = pick_first(roots_near_first(c, f), true, true);
        CHECK(n.hit);
        CHECK(n.lambda == T(4));
        CHECK_FALSE(front_root(c, f).hit);
        // alpha = -1, beta = 2: roots 0 and 4, front-facing at 4 (alpha 4 + beta = -2).
        const RayCoefficients<T> d{T(-1), T(2), T(0)};
        CHECK(front_root(d, f).hit);
        CHECK(front_root(d, f).lambda == T(4));
    }
}
