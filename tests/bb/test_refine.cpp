// tests/bb/test_refine.cpp -- smaller clip tetrahedra for a quadric clipped to a tetrahedron
// (bb::refine_crossing): every point of the zero set in the parent lies in a kept child, the
// children tile the parent, and the BB sign test against values sampled in long double
#include <doctest/doctest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include "core/exact_tet.hpp"
#include "quadcast/bb/quadric_form.hpp"

using namespace quadcast;
using LD = long double;

namespace {

bool inside(const BoundingTet<double>& t, const Vec3<double>& x, LD slack) { return qc_exact::in_tetrahedron(t.p, x, slack); }

/// Six times the volume of t, in long double.
LD volume6(const BoundingTet<double>& t) { return std::fabs(qc_exact::volume6(t.p[0], t.p[1], t.p[2], t.p[3])); }

/// f(x) = x^T A x + 2 b.x + c in long double.
LD value(const Quadric<double>& q, const Vec3<double>& x) {
    LD s = 0;
    const LD h[4] = {x[0], x[1], x[2], 1};
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) s += h[i] * LD(q.q[j][i]) * h[j];
    return s;
}

/// A random point of the tetrahedron (barycentric weights from exponential variates).
Vec3<double> random_in(const BoundingTet<double>& t, std::mt19937& rng) {
    std::exponential_distribution<double> e(1.0);
    double w[4], sum = 0;
    for (double& x : w) sum += x = e(rng);
    Vec3<double> x{};
    for (int k = 0; k < 4; ++k) x = x + t.p[k] * (w[k] / sum);
    return x;
}

Vec3<double> gradient(const Quadric<double>& q, const Vec3<double>& x) {
    Vec3<double> g{};
    for (int i = 0; i < 3; ++i) {
        LD s = 0;
        const LD h[4] = {x[0], x[1], x[2], 1};
        for (int j = 0; j < 4; ++j) s += 2 * LD(q.q[j][i]) * h[j];
        g[i] = double(s);
    }
    return g;
}

}  // namespace

TEST_CASE("refined clip tetrahedra hold the whole zero set of their parent and tile it") {
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    long parents = 0, refined = 0, children = 0, samples = 0, missed = 0;
    double volume_parent = 0, volume_kept = 0;
    for (int it = 0; it < 300; ++it) {
        // A random tetrahedron and a sphere, cylinder or hyperboloid through a small part of it.
        BoundingTet<double> t{};
        for (auto& p : t.p) p = vec3(u(rng), u(rng), u(rng));
        const LD v6 = volume6(t);
        if (v6 < 0.05) continue;
        Quadric<double> q{};
        const Vec3<double> c = t.p[it % 4] + vec3(u(rng), u(rng), u(rng)) * 0.3;
        const double a[3] = {1.0, it % 3 == 1 ? 0.0 : 1.0, it % 3 == 2 ? -1.0 : 1.0};
        for (int i = 0; i < 3; ++i) {
            q.q[i][i] = a[i];
            q.q[3][i] = q.q[i][3] = -a[i] * c[i];
        }
        q.q[3][3] = a[0] * c[0] * c[0] + a[1] * c[1] * c[1] + a[2] * c[2] * c[2] - 0.04 - 0.2 * (u(rng) + 1.0);
        if (!bb::quadric_may_cross(q, t)) continue;
        ++parents;
        std::vector<BoundingTet<double>> kept;
        bb::refine_crossing(q, t, 3, 4, 0.0, kept);
        refined += kept.size() > 1;
        children += static_cast<long>(kept.size());
        volume_parent += double(v6);
        for (const auto& k : kept) volume_kept += double(volume6(k));
        // The zero set: random points of the parent pulled onto it by Newton steps (long double
        // values), kept when they stay in the parent.
        for (int n = 0; n < 400; ++n) {
            Vec3<double> x = random_in(t, rng);
            for (int s = 0; s < 40; ++s) {
                const Vec3<double> g = gradient(q, x);
                const double gg = dot(g, g);
                if (!(gg > 0)) break;
                x = x - g * double(value(q, x) / gg);
            }
            if (!(std::fabs(double(value(q, x))) < 1e-12) || !inside(t, x, 0)) continue;
            ++samples;
            bool found = false;
            for (const auto& k : kept) found = found || inside(k, x, 1e-12L);
            missed += !found;
        }
    }
    std::printf("[refine crossing] %ld crossed parents (%ld refined) -> %ld clip tetrahedra, %.1f%% of the parents' volume; %ld zero-set points, "
                "%ld outside every kept child\n",
                parents, refined, children, 100.0 * volume_kept / volume_parent, samples, missed);
    CHECK(parents > 100);
    CHECK(refined > parents / 5);
    CHECK(samples > 20000);
    CHECK(missed == 0);
    CHECK(volume_kept < 0.6 * volume_parent);
}

TEST_CASE("red refinement tiles its parent and the BB sign test bounds sampled values") {
    std::mt19937 rng(12);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    for (int it = 0; it < 200; ++it) {
        BoundingTet<double> t{};
        for (auto& p : t.p) p = vec3(u(rng), u(rng), u(rng));
        const LD v6 = volume6(t);
        if (v6 < 0.01) continue;
        // Eight children of an eighth of the volume each; a random point lies in one (or on shared faces).
        LD sum = 0;
        const auto kids = bb::red_refinement(t);
        for (const auto& k : kids) {
            const LD kv = volume6(k);
            CHECK(std::fabs(double(kv / v6 - 0.125L)) < 1e-12);
            sum += kv;
        }
        CHECK(std::fabs(double(sum / v6 - 1)) < 1e-12);
        for (int n = 0; n < 50; ++n) {
            const Vec3<double> x = random_in(t, rng);
            int in = 0;
            for (const auto& k : kids) in += inside(k, x, 1e-12L);
            CHECK(in >= 1);
        }
        // A quadric whose BB coefficients keep one sign keeps that sign at sampled points.
        Quadric<double> q{};
        for (int j = 0; j < 4; ++j)
            for (int i = j; i < 4; ++i) q.q[j][i] = q.q[i][j] = u(rng);
        if (bb::quadric_may_cross(q, t)) continue;
        const LD sign = value(q, t.p[0]) > 0 ? 1 : -1;
        for (int n = 0; n < 50; ++n) {
            const Vec3<double> x = random_in(t, rng);
            CHECK(sign * value(q, x) > 0);
        }
    }
}
