// tools/quadcast/bench_stability.cpp -- `quadcast bench stability`: root accuracy under bad conditioning
//
// Sweeps the conditioning of ray/quadric intersection -- eye distance over size, grazing rays,
// alpha -> 0, nearly planar bilinear quads -- and prints the float error of each root
// formulation against an MPFR reference computed from the very same float inputs, so the numbers
// are the error of the float computation alone. Cost is measured in the same run.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <random>
#include <string>
#include <vector>

#include <mpreal.h>

#include "commands.hpp"
#include "quadcast/bilinear.hpp"
#include "quadcast/codegen/emit.hpp"
#include "quadcast/codegen/verify.hpp"
#include "quadcast/quadric.hpp"
#include "quadcast/ray.hpp"

namespace quadcast::cli {

namespace {

using mp = mpfr::mpreal;
using V3d = Vec3<double>;

/// One ray, as a renderer stores it: the quadric in local coordinates (origin at its bound's
/// centre or a quad corner), the eye o in those coordinates, the ray direction v; all float.
struct Sample {
    Quadric<float> q;
    Vec3<float> o, v;
};

/// Reference roots of the float inputs, in 256-bit arithmetic.
struct Reference {
    bool front_exists = false, near_exists = false;
    mp front, nearest;
};

Reference reference(const Sample& s) {
    Reference r;
    mp A[3][3], b[3], v[3], o[3];
    for (int i = 0; i < 3; ++i) {
        v[i] = s.v[i];
        o[i] = s.o[i];
        b[i] = s.q.q[3][i];
        for (int j = 0; j < 3; ++j) A[j][i] = s.q.q[j][i];
    }
    // Ray coefficients of eq. 6 (eye o), exact at this precision: g = A o + b,
    // alpha = v.Av, beta = g.v, gamma = f(o) = o.(g + b) + c.
    mp alpha = 0, beta = 0, gamma = s.q.q[3][3];
    for (int i = 0; i < 3; ++i) {
        mp av = 0, g = b[i];
        for (int j = 0; j < 3; ++j) { av += A[j][i] * v[j]; g += A[j][i] * o[j]; }
        alpha += v[i] * av;
        beta += g * v[i];
        gamma += o[i] * (g + b[i]);
    }
    const mp disc = beta * beta - alpha * gamma;
    if (disc < 0) return r;
    const mp sd = mpfr::sqrt(disc);
    if (alpha == 0) {
        if (beta == 0) return r;
        const mp lin = -gamma / (2 * beta);
        r.front_exists = beta < 0 && lin > 0;  // alpha lambda + beta = beta
        r.front = lin;
        r.near_exists = lin > 0;
        r.nearest = lin;
        return r;
    }
    const mp lm = (-beta - sd) / alpha, lp = (-beta + sd) / alpha;
    r.front = lm;
    r.front_exists = lm > 0;
    mp best = 0;
    for (const mp& l : {lm, lp})
        if (l > 0 && (!r.near_exists || l < best)) { best = l; r.near_exists = true; }
    r.nearest = best;
    return r;
}

/// Error statistics of one formulation on one scenario.
struct Stats {
    std::vector<double> ulps;
    std::size_t lost = 0, spurious = 0, rays = 0;
    double percentile(double p) const {
        if (ulps.empty()) return NAN;
        std::vector<double> s = ulps;
        const std::size_t k = std::min(s.size() - 1, static_cast<std::size_t>(p * static_cast<double>(s.size())));
        std::nth_element(s.begin(), s.begin() + static_cast<std::ptrdiff_t>(k), s.end());
        return s[k];
    }
    double max() const { return ulps.empty() ? NAN : *std::max_element(ulps.begin(), ulps.end()); }
};

void record(Stats& st, bool exists, const mp& ref, bool hit, float lambda) {
    ++st.rays;
    if (exists && !hit) { ++st.lost; return; }
    if (!exists && hit) { ++st.spurious; return; }
    if (!exists) return;
    const float rf = static_cast<float>(ref.toDouble());
    const std::uint64_t d = codegen::ulp_distance(std::bit_cast<std::uint32_t>(rf), std::bit_cast<std::uint32_t>(lambda));
    st.ulps.push_back(d == UINT64_MAX ? INFINITY : static_cast<double>(d));
}

constexpr RootFormula formulas[] = {RootFormula::classic, RootFormula::stoll, RootFormula::stable};
constexpr int n_methods = 4;  // the three formulas on eq. 6 coefficients, then ray_quadratic_local
const char* method_name(int m) {
    static const char* names[] = {"classic (eq. 7)", "stoll (eq. 15)", "stable", "local (re-origined)"};
    return names[m];
}

// Scenario geometry (double, then rounded to float) ----------------------------------------------

V3d random_unit(std::mt19937& rng) {
    std::normal_distribution<double> n;
    const V3d v = vec3(n(rng), n(rng), n(rng));
    return v / length(v);
}

/// An orthonormal frame with w as third axis.
void frame(const V3d& w, V3d& u, V3d& v) {
    const V3d t = std::fabs(w[0]) < 0.6 ? vec3(1.0, 0.0, 0.0) : vec3(0.0, 1.0, 0.0);
    u = normalize(cross(t, w));
    v = cross(w, u);
}

Sample to_float(const Quadric<double>& q_local, const V3d& eye, const V3d& dir) {
    Sample s;
    s.q.q = cast<float>(q_local.q);
    s.o = cast<float>(eye);
    s.v = cast<float>(dir / length(dir));
    return s;
}

/// Unit sphere at distance d from the eye; rays through the visible disk at impact parameter p
/// (fraction of the radius; p < 0 means uniform over the disk).
Sample sphere_ray(std::mt19937& rng, double d, double p) {
    const V3d w = random_unit(rng);
    Quadric<double> q{};
    q.q = identity<double, 4>();
    q.q[3][3] = -1.0;
    V3d a, b;
    frame(w, a, b);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    const double ang = 2.0 * M_PI * u(rng);
    const double rho = p < 0 ? std::sqrt(u(rng)) * 0.999 : p;
    // Aim at the point of the tangent cone at angle asin(rho / d) from the centre direction.
    const double s = rho / d, cth = std::sqrt(1.0 - s * s);
    const V3d dir = cth * w + s * (std::cos(ang) * a + std::sin(ang) * b);
    return to_float(q, -d * w, dir);
}

/// Paraboloid z = x^2 + y^2 seen from below (outside) along its axis, tilted by theta:
/// alpha = |v_xy|^2 -> 0, the front-facing root stays finite and the far root goes to infinity.
Sample paraboloid_ray(std::mt19937& rng, double theta) {
    std::uniform_real_distribution<double> u(-0.5, 0.5);
    const V3d eye = vec3(u(rng), u(rng), -4.0);
    Quadric<double> q{};
    q.q = zero_mat<double, 4, 4>();
    q.q[0][0] = q.q[1][1] = 1.0;
    q.q[3][2] = q.q[2][3] = -0.5;
    const double phi = 2.0 * M_PI * (u(rng) + 0.5);
    const V3d dir = vec3(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta));
    return to_float(q, eye, dir);
}

/// A bilinear quad whose fourth corner is lifted by h out of the plane of the other three,
/// randomly placed; the ray goes from an eye 3 units away through a random patch point.
Sample quad_ray(std::mt19937& rng, double h) {
    const V3d w = random_unit(rng);
    V3d a, b;
    frame(w, a, b);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    const V3d o = vec3(u(rng), u(rng), u(rng)) * 2.0;
    const V3d p1 = o, p2 = o + a, p3 = o + a + b + h * w, p4 = o + b;
    const QuadConversion<double> conv = quad_to_quadric(p1, p2, p3, p4);
    const V3d target = bilinear_point(p1, p2, p3, p4, u(rng), u(rng));
    V3d side = random_unit(rng);
    if (dot(side, w) < 0.3) side = normalize(side + w);
    const V3d eye = target + 3.0 * side;
    return to_float(conv.local.quadric, eye - conv.local.origin, target - eye);
}

struct Scenario {
    std::string family, level;
    std::function<Sample(std::mt19937&)> make;
};

std::vector<Scenario> scenarios() {
    std::vector<Scenario> s;
    for (double d : {1.05, 10.0, 1e2, 1e3, 1e4, 1e5, 1e6}) {
        char buf[32];
        std::snprintf(buf, sizeof buf, "d/r = %g", d);
        s.push_back({"distance", buf, [d](std::mt19937& r) { return sphere_ray(r, d, -1.0); }});
    }
    for (int k = 1; k <= 6; ++k) {
        const double p = 1.0 - std::pow(10.0, -k);
        char buf[32];
        std::snprintf(buf, sizeof buf, "1 - p = 1e-%d", k);
        s.push_back({"grazing", buf, [p](std::mt19937& r) { return sphere_ray(r, 10.0, p); }});
    }
    for (int k = 1; k <= 7; ++k) {
        const double th = std::pow(10.0, -k);
        char buf[32];
        std::snprintf(buf, sizeof buf, "theta = 1e-%d", k);
        s.push_back({"alpha->0", buf, [th](std::mt19937& r) { return paraboloid_ray(r, th); }});
    }
    for (int k = 1; k <= 6; ++k) {
        const double h = std::pow(10.0, -k);
        char buf[32];
        std::snprintf(buf, sizeof buf, "h = 1e-%d", k);
        s.push_back({"bilinear", buf, [h](std::mt19937& r) { return quad_ray(r, h); }});
    }
    return s;
}

// The methods ----------------------------------------------------------------------------------

/// Front root and nearest root of one ray by method m (0..2: eq. 6 coefficients and a
/// RootFormula; 3: `ray_quadratic_local` and the stable formulas).
template <class T>
void solve(int m, const Quadric<T>& q, const Vec3<T>& o, const Vec3<T>& v, RayHit<T>& front, RootPair<T>& pair) {
    if (m < 3) {
        const RayCoefficients<T> c = ray_coefficients(q, o, v);
        front = front_root(c, formulas[m]);
        pair = roots_near_first(c, formulas[m]);
    } else {
        const RayQuadratic<T> r = ray_quadratic_local(q, o, v);
        front = front_root(r);
        pair = roots_near_first(r);
    }
}

template <int M, bool Front>
struct MethodKernel {
    static constexpr const char* name = "bench_root";
    static constexpr const char* source = "quadcast/ray.hpp";
    static constexpr const char* summary = "bench";
    template <class IO> static void run(IO& io) {
        using T = typename IO::T;
        const Quadric<T> q{io.template mat<4>("q")};
        const Vec3<T> o = io.template vec<3>("o"), v = io.template vec<3>("v");
        RayHit<T> h{};
        RootPair<T> p{};
        if constexpr (M < 3) {
            const RayCoefficients<T> c = ray_coefficients(q, o, v);
            if constexpr (Front) h = front_root<formulas[M]>(c); else p = roots_near_first<formulas[M]>(c);
        } else {
            const RayQuadratic<T> r = ray_quadratic_local(q, o, v);
            if constexpr (Front) h = front_root(r); else p = roots_near_first(r);
        }
        if constexpr (Front) {
            io.out("lambda", h.lambda);
            io.out("hit", h.hit);
        } else {
            io.out("near", p.lambda_near);
            io.out("far", p.lambda_far);
            io.out("near_ok", p.near_valid);
            io.out("far_ok", p.far_valid);
        }
    }
};

/// Operations in the traced kernel of method m (from the stored quadric to the root).
int traced_ops(int m, bool front) {
    auto ops = []<int M, bool F>() { return codegen::emit_kernel(codegen::make_kernel<MethodKernel<M, F>>()).statements; };
    static const int table[4][2] = {
        {ops.template operator()<0, true>(), ops.template operator()<0, false>()},
        {ops.template operator()<1, true>(), ops.template operator()<1, false>()},
        {ops.template operator()<2, true>(), ops.template operator()<2, false>()},
        {ops.template operator()<3, true>(), ops.template operator()<3, false>()}};
    return table[m][front ? 0 : 1];
}

/// Nanoseconds per ray on the CPU (float, coefficients and root), min over interleaved repetitions.
void cpu_cost(const std::vector<Sample>& rays, double ns[n_methods]) {
    for (int m = 0; m < n_methods; ++m) ns[m] = INFINITY;
    volatile float sink = 0;
    for (int rep = 0; rep < 5; ++rep)
        for (int m = 0; m < n_methods; ++m) {
            const auto t0 = std::chrono::steady_clock::now();
            float acc = 0;
            for (const Sample& r : rays) {
                RayHit<float> h{};
                RootPair<float> p{};
                solve(m, r.q, r.o, r.v, h, p);
                acc += (h.hit ? h.lambda : 0.0f) + (p.near_valid ? p.lambda_near : 0.0f);
            }
            sink = sink + acc;
            const double t = std::chrono::duration<double, std::nano>(std::chrono::steady_clock::now() - t0).count() / static_cast<double>(rays.size());
            ns[m] = std::min(ns[m], t);
        }
}

struct BenchOptions {
    int rays = 20000;
    unsigned seed = 1;
};

void run_stability(const BenchOptions& opt) {
    mp::set_default_prec(256);
    std::printf("quadcast bench stability: float roots against an MPFR (256-bit) reference on the same float inputs\n");
    std::printf("input per ray: the quadric in local coordinates, the eye there, the direction (float); the methods\n");
    std::printf("compute everything from that input. %d rays per row; error in ULPs of lambda (p50 / p99 / max over\n", opt.rays);
    std::printf("rays where both hit); bad = hit/miss disagrees with the reference (%% of rays).\n");
    std::printf("front = front-facing root (culling on, Stoll eq. 7/14); near = nearest positive root (culling off, eq. 15)\n\n");
    std::printf("%-9s %-14s %-5s", "scenario", "level", "mode");
    for (int m = 0; m < n_methods; ++m) std::printf(" | %-30s", method_name(m));
    std::printf("\n%-30s", "");
    for (int m = 0; m < n_methods; ++m) std::printf(" | %6s %7s %7s %7s", "p50", "p99", "max", "bad");
    std::printf("\n");
    std::vector<Sample> cost_sample;
    for (const Scenario& sc : scenarios()) {
        Stats st[n_methods][2];
        for (int i = 0; i < opt.rays; ++i) {
            std::mt19937 rng(opt.seed * 7919u + static_cast<unsigned>(i));
            const Sample s = sc.make(rng);
            const Reference ref = reference(s);
            if (i < 1000) cost_sample.push_back(s);
            for (int m = 0; m < n_methods; ++m) {
                RayHit<float> h{};
                RootPair<float> p{};
                solve(m, s.q, s.o, s.v, h, p);
                record(st[m][0], ref.front_exists, ref.front, h.hit, h.lambda);
                record(st[m][1], ref.near_exists, ref.nearest, p.near_valid || p.far_valid, p.near_valid ? p.lambda_near : p.lambda_far);
            }
        }
        for (int mode = 0; mode < 2; ++mode) {
            std::printf("%-9s %-14s %-5s", sc.family.c_str(), sc.level.c_str(), mode == 0 ? "front" : "near");
            for (int m = 0; m < n_methods; ++m) {
                const Stats& x = st[m][mode];
                const double bad = 100.0 * static_cast<double>(x.lost + x.spurious) / static_cast<double>(x.rays);
                std::printf(" | %6.3g %7.3g %7.3g %6.2f%%", x.percentile(0.5), x.percentile(0.99), x.max(), bad);
            }
            std::printf("\n");
        }
    }
    double ns[n_methods];
    cpu_cost(cost_sample, ns);
    std::printf("\ncost per ray, from the stored quadric to both roots (CPU float ns, ratio to classic, one run;\n");
    std::printf("GPU: operations in the traced kernel, front-root / both-roots kernels)\n");
    std::printf("%-22s %16s %10s %10s\n", "method", "CPU ns", "front ops", "near ops");
    for (int m = 0; m < n_methods; ++m)
        std::printf("%-22s %7.2f (%4.2fx) %10d %10d\n", method_name(m), ns[m], ns[m] / ns[0], traced_ops(m, true), traced_ops(m, false));
}

}  // namespace

void add_bench_stability(CLI::App& bench) {
    auto opt = std::make_shared<BenchOptions>();
    CLI::App* cmd = bench.add_subcommand("stability", "float error of the root formulations against an MPFR reference, and their cost");
    cmd->add_option("--rays", opt->rays, "rays per scenario")->check(CLI::Range(100, 10000000));
    cmd->add_option("--seed", opt->seed, "seed");
    cmd->callback([opt] { run_stability(*opt); });
}

}  // namespace quadcast::cli
