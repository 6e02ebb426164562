// tests/core/test_bounds.cpp -- Sigg's screen-space bounds, window-space ray casting, sphere quads
#include <doctest/doctest.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <random>

#include "core/param_test_util.hpp"
#include "quadcast/bounds.hpp"
#include "quadcast/primitives.hpp"

using namespace qct;
using quadcast::PrimitiveKind;

namespace {

using quadcast::primitive_kind_name;
constexpr auto& all_kinds = quadcast::all_primitive_kinds;

const char* kind_name(PrimitiveKind k) { return primitive_kind_name(k); }

constexpr LD two_pi = LD(6.283185307179586476925286766559L);

/// A primitive seen by a random camera. Matrices are rounded to T (the inputs); the `_l`
/// copies are those rounded values in long double.
template <class T>
struct Scene {
    quadcast::ParameterForm<T> prim;
    M4L view_l, proj_l, t_l;
    quadcast::Mat4<T> pmt;  ///< P M T, computed in long double from the rounded factors, rounded
    V3L centre;             ///< bounding sphere of the clipped primitive (object space)
    LD radius;
};

/// Camera at `dist` times the bounding radius (for ellipsoids: parameter-space distance, so a
/// sphere's eye is at dist * r), looking at the centre tilted by up to `tilt_frac` of the angle
/// that keeps the bounding sphere in front of the eye (negative: see below).
template <class T>
Scene<T> make_scene(std::mt19937& rng, const quadcast::ParameterForm<T>& prim, LD dist, LD tilt_frac) {
    Scene<T> s{};
    s.prim = prim;
    s.t_l = to_ld(prim.t);
    bounding_sphere(prim, s.centre, s.radius);
    V3L eye{};
    if (prim.kind == PrimitiveKind::ellipsoid) {
        const V3L g = unit_vector(rng) * dist;
        eye = object_point(s.t_l, quadcast::vec4(g, LD(1)));
    } else {
        eye = s.centre + unit_vector(rng) * (dist * s.radius);
    }
    const V3L to_c = s.centre - eye;
    const LD l = len3(to_c);
    const LD max_tilt = std::acos(std::min(LD(1), s.radius / l));
    // (tilt_frac < 0: turn by -tilt_frac right angles: -1 puts the centre on the eye plane,
    // -2 the whole primitive behind the eye)
    const LD angle = tilt_frac < 0 ? -tilt_frac * LD(1.5707963267948966192313216916L) : uniform(rng, 0, tilt_frac) * max_tilt;
    const V3L look = tilt(rng, to_c / l, angle);
    const Camera cam = random_camera(rng, eye, look);
    s.view_l = to_ld(quadcast::cast<T>(cam.view));
    s.proj_l = to_ld(quadcast::cast<T>(cam.proj));
    s.pmt = quadcast::cast<T>(s.proj_l * s.view_l * s.t_l);
    return s;
}

/// Exact extremes of F(p) = (a . p) / (r4 . p) over the clipped surface of a primitive with
/// D = (1, 1, d2, d3) (p = (rho cos t, rho sin t, z, 1), rho^2 = -(d2 z^2 + d3)): the maximum
/// is on a cap circle or on the silhouette p^T D e = 0 (e the eye in parameter space), which
/// for each z has the two solutions t = phi +- acos(-(d2 z e_z + d3 e_w) / (rho |e_xy|)).
LD ref_max(const V4L& a, const V4L& r4, const V4L& e, const V4L& d, LD zl, LD zh) {
    auto F = [&](const V4L& p) { return quadcast::dot(a, p) / quadcast::dot(r4, p); };
    LD best = -std::numeric_limits<LD>::infinity();
    for (LD h : {zl, zh}) best = std::max(best, maximize([&](LD t) { return F(param_point(d, t, h)); }, 0, two_pi, 256, true));
    const LD exy = std::hypot(e[0], e[1]), phi = std::atan2(e[1], e[0]);
    for (int branch = -1; branch <= 1; branch += 2) {
        auto G = [&](LD z) {
            const LD rho = std::sqrt(std::max(LD(0), -(d[2] * z * z + d[3])));
            const LD c = -(d[2] * z * e[2] + d[3] * e[3]) / (rho * exy);
            if (!(rho > 0) || !(std::fabs(c) <= 1)) return -std::numeric_limits<LD>::infinity();
            return F(param_point(d, phi + branch * std::acos(c), z));
        };
        best = std::max(best, maximize(G, zl, zh, 256));
    }
    return best;
}

/// Reference box [lo, hi] of the clipped primitive for the compound matrix c (long double).
struct RefBox {
    LD lo[2], hi[2];
};

RefBox ref_box(const M4L& c, const V4L& d, LD zl, LD zh) {
    const V4L r1 = quadcast::row(c, 0), r2 = quadcast::row(c, 1), r4 = quadcast::row(c, 3);
    const V4L e = null4(r1, r2, r4);
    RefBox b{};
    b.hi[0] = ref_max(r1, r4, e, d, zl, zh);
    b.lo[0] = -ref_max(-r1, r4, e, d, zl, zh);
    b.hi[1] = ref_max(r2, r4, e, d, zl, zh);
    b.lo[1] = -ref_max(-r2, r4, e, d, zl, zh);
    return b;
}

/// Minimum and maximum of w_c over a dense sample of the clipped surface (with exact cap minima).
void w_range(const M4L& c, const V4L& d, LD zl, LD zh, LD& wmin, LD& wmax) {
    const V4L r4 = quadcast::row(c, 3);
    wmin = std::numeric_limits<LD>::infinity();
    wmax = -wmin;
    for (int j = 0; j <= 32; ++j)
        for (int i = 0; i < 64; ++i) {
            const LD w = quadcast::dot(r4, param_point(d, two_pi * i / 64, zl + (zh - zl) * j / 32));
            wmin = std::min(wmin, w);
            wmax = std::max(wmax, w);
        }
    for (LD h : {zl, zh}) {
        const LD rho = std::sqrt(std::max(LD(0), -(d[2] * h * h + d[3])));
        wmin = std::min(wmin, h * r4[2] + r4[3] - rho * std::hypot(r4[0], r4[1]));
    }
}

template <class T>
LD eps_of() { return LD(std::numeric_limits<T>::epsilon()); }

}  // namespace

TEST_CASE_TEMPLATE("Sigg's box contains the projected primitive and touches it on every side", T, float, double) {
    const LD eps = eps_of<T>();
    for (PrimitiveKind kind : all_kinds) {
        int tested = 0, invalid_ok = 0, by_silhouette = 0;
        LD worst_tight = 0, worst_out = 0, worst_centre = 0;
        for (int it = 0; it < 48; ++it) {
            std::mt19937 rng(10000u + 1009u * unsigned(kind) + unsigned(it));
            const auto prim = random_primitive<T>(rng, kind, it);
            // Cameras from 1.05 to 30 radii, one in four close to the minimum
            const LD dist = it % 4 == 0 ? uniform(rng, 1.05L, 1.2L) : log_uniform(rng, 1.05L, 30);
            // Mostly in front of the eye; every eighth camera straddles the primitive, every
            // sixteenth looks away from it
            const LD turn = it % 8 == 7 ? -1.0L : (it % 16 == 3 ? -2.0L : 1.0L);
            const Scene<T> s = make_scene(rng, prim, dist, turn);
            const M4L c = to_ld(s.pmt);
            const V4L d = quadcast::cast<LD>(prim.d);
            const LD zl = LD(prim.slab[0]), zh = LD(prim.slab[1]);
            const quadcast::ScreenBox<T> box = quadcast::primitive_bbox(s.pmt, prim);

            // The validity mask says whether the primitive is in front of the eye plane
            LD wmin = 0, wmax = 0;
            w_range(c, d, zl, zh, wmin, wmax);
            if (wmin < -1e-6L * wmax) {
                CHECK_MESSAGE(!box.valid, kind_name(kind), " it ", it);
                CHECK(box.lo[0] == T(-1));
                CHECK(box.hi[1] == T(1));
                ++invalid_ok;
                continue;
            }
            if (wmin < 0.02L * wmax) continue;  // too close to the eye plane to call
            REQUIRE_MESSAGE(box.valid, kind_name(kind), " it ", it);
            ++tested;

            // Count the boxes that the silhouette (not the caps) decides
            if (quadcast::is_clipped(kind)) {
                const auto caps = quadcast::box_union(quadcast::cap_bbox(s.pmt, prim.slab[0], quadcast::section_radius2(prim.d, prim.slab[0])),
                                                      quadcast::cap_bbox(s.pmt, prim.slab[1], quadcast::section_radius2(prim.d, prim.slab[1])));
                bool differs = false;
                for (int ax = 0; ax < 2; ++ax) differs = differs || caps.lo[ax] != box.lo[ax] || caps.hi[ax] != box.hi[ax];
                by_silhouette += differs;
            }

            // Every side touches the exact extreme of the projection
            const RefBox ref = ref_box(c, d, zl, zh);
            for (int ax = 0; ax < 2; ++ax) {
                const LD mag = std::max({std::fabs(ref.lo[ax]), std::fabs(ref.hi[ax]), (ref.hi[ax] - ref.lo[ax]) / 2});
                const LD e_lo = std::fabs(LD(box.lo[ax]) - ref.lo[ax]) / (eps * mag);
                const LD e_hi = std::fabs(LD(box.hi[ax]) - ref.hi[ax]) / (eps * mag);
                worst_tight = std::max({worst_tight, e_lo, e_hi});
                CHECK_MESSAGE(e_lo < 64, kind_name(kind), " it ", it, " axis ", ax, " lo ", double(box.lo[ax]), " ref ", double(ref.lo[ax]));
                CHECK_MESSAGE(e_hi < 64, kind_name(kind), " it ", it, " axis ", ax, " hi ", double(box.hi[ax]), " ref ", double(ref.hi[ax]));
            }
            // Every sampled surface point projects into the box
            for (int j = 0; j <= 16; ++j)
                for (int i = 0; i < 48; ++i) {
                    const V4L p = param_point(d, two_pi * i / 48, zl + (zh - zl) * j / 16);
                    const V4L x = c * p;
                    const LD q[2] = {x[0] / x[3], x[1] / x[3]};
                    for (int ax = 0; ax < 2; ++ax) {
                        const LD mag = std::max(std::fabs(LD(box.lo[ax])), std::fabs(LD(box.hi[ax])));
                        const LD out = std::max(LD(box.lo[ax]) - q[ax], q[ax] - LD(box.hi[ax])) / (eps * mag);
                        worst_out = std::max(worst_out, out);
                        CHECK(out < 8);
                    }
                }
            // Sigg's centre is the midpoint of an ellipsoid's box
            if (kind == PrimitiveKind::ellipsoid) {
                const quadcast::Vec4<T> vc = quadcast::sigg_center(s.pmt, prim.d);
                for (int ax = 0; ax < 2; ++ax) {
                    const LD mid = (ref.lo[ax] + ref.hi[ax]) / 2;
                    const LD mag = std::max(std::fabs(ref.lo[ax]), std::fabs(ref.hi[ax]));
                    const LD err = std::fabs(LD(vc[ax]) / LD(vc[3]) - mid) / (eps * mag);
                    worst_centre = std::max(worst_centre, err);
                    CHECK(err < 64);
                }
            }
        }
        std::printf("[bounds %s] %s: %d boxes (%d widened by the silhouette), %d invalid detected; side vs exact "
                    "extreme max %.1Lf eps, samples outside max %.1Lf eps, centre %.1Lf eps (of max |side|)\n",
                    quadcast::scalar_traits<T>::name, kind_name(kind), tested, by_silhouette, invalid_ok, worst_tight,
                    std::max(LD(0), worst_out), worst_centre);
        CHECK(tested >= 30);
        CHECK(invalid_ok >= 9);
        if (kind == PrimitiveKind::paraboloid || kind == PrimitiveKind::hyperboloid_two_sheets) CHECK(by_silhouette >= 5);
    }
}

TEST_CASE_TEMPLATE("the window-space hit is the world-space ray hit, with the eye-space normal", T, float, double) {
    const LD eps = eps_of<T>();
    for (PrimitiveKind kind : all_kinds) {
        int hits = 0, misses = 0, mask_checked = 0;
        LD worst_depth_ulp = 0, worst_same = 0, worst_world = 0, worst_rel = 0, worst_normal = 0;
        for (int it = 0; it < 40; ++it) {
            std::mt19937 rng(20000u + 1013u * unsigned(kind) + unsigned(it));
            const auto prim = random_primitive<T>(rng, kind, it);
            const Scene<T> s = make_scene(rng, prim, log_uniform(rng, 1.1L, 20), 0.8L);
            const V4L d = quadcast::cast<LD>(prim.d);
            const LD zl = LD(prim.slab[0]), zh = LD(prim.slab[1]);
            const M4L vp_l = to_ld(quadcast::cast<T>(viewport(10, 20, 800, 600))) * s.proj_l;
            const M4L mt_l = s.view_l * s.t_l;
            const M4L vpmt_l = vp_l * mt_l;
            // Inputs of the window-space kernel, rounded to T
            const quadcast::Mat4<T> vpmt_inv = quadcast::cast<T>(inverse(vpmt_l));
            const quadcast::Mat4<T> vp_inv = quadcast::cast<T>(inverse(vp_l));
            const quadcast::Mat4<T> mt_inv_t = quadcast::cast<T>(quadcast::transpose(inverse(mt_l)));
            const M4L vp_inv_l = inverse(vp_l), mt_inv_l = inverse(mt_l), same_l = to_ld(vpmt_inv);
            auto eye_point = [&](LD xw, LD yw, LD zw) {
                const V4L h = vp_inv_l * V4L{{xw, yw, zw, 1}};
                return quadcast::vec3(h[0] / h[3], h[1] / h[3], h[2] / h[3]);
            };
            auto in_slab = [&](const V4L& p, LD margin) {
                const LD z = p[2] / p[3];
                return z >= zl + margin && z <= zh - margin;
            };
            for (int k = 0; k < 24; ++k) {
                // Pick a pixel: the projection of a surface point, or anywhere near the primitive
                V4L xw4{};
                if (k < 18) {
                    xw4 = vpmt_l * param_point(d, uniform(rng, 0, two_pi), uniform(rng, zl, zh));
                } else {
                    xw4 = vpmt_l * param_point(d, uniform(rng, 0, two_pi), uniform(rng, zl, zh), uniform(rng, 0.5L, 1.5L));
                }
                if (!(xw4[3] > 0)) continue;
                const T xw = T(xw4[0] / xw4[3]), yw = T(xw4[1] / xw4[3]);

                // Reference: the eye-space ray through the pixel against the object quadric
                const V3L q = eye_point(LD(xw), LD(yw), 0);
                const V4L a = mt_inv_l * quadcast::vec4(q, LD(0)), b = mt_inv_l * V4L{{0, 0, 0, 1}};
                const LD A = quadcast::dot(quadcast::cmul(d, a), a), B = quadcast::dot(quadcast::cmul(d, a), b),
                         C = quadcast::dot(quadcast::cmul(d, b), b);
                const LD disc = B * B - A * C;
                LD t_ref = -1;
                bool borderline = false;
                if (disc >= 0 && A != 0) {
                    const LD sq = std::sqrt(disc);
                    LD t1 = (-B - sq) / A, t2 = (-B + sq) / A;
                    if (t1 > t2) std::swap(t1, t2);
                    for (LD t : {t1, t2}) {
                        if (t > 0 && in_slab(a * t + b, 0)) { t_ref = t; break; }
                    }
                }
                // Grazing rays and hits on a cap rim are ill-conditioned: check no mask there.
                // Judge it on the kernel's inputs x0 + z c3 and their rounding error eps * |terms|.
                {
                    const V4L c3 = same_l[2];
                    V4L x0{};
                    for (int i = 0; i < 4; ++i) x0[i] = same_l[0][i] * LD(xw) + same_l[1][i] * LD(yw) + same_l[3][i];
                    // First-order bound of the discriminant's error: the minors m_ij have errors
                    // of eps (|x0_i c3_j| + |x0_j c3_i|), x0 measured by the terms it is summed from
                    LD xa[4];
                    for (int i = 0; i < 4; ++i)
                        xa[i] = std::fabs(same_l[0][i] * LD(xw)) + std::fabs(same_l[1][i] * LD(yw)) + std::fabs(same_l[3][i]);
                    LD disc_s = 0, disc_err = 0;
                    for (int i = 0; i < 4; ++i)
                        for (int j = i + 1; j < 4; ++j) {
                            const LD m = x0[i] * c3[j] - x0[j] * c3[i];
                            const LD dm = eps * (xa[i] * std::fabs(c3[j]) + xa[j] * std::fabs(c3[i]));
                            disc_s -= d[i] * d[j] * m * m;
                            disc_err += std::fabs(d[i] * d[j]) * (2 * std::fabs(m) * dm + dm * dm);
                        }
                    borderline = std::fabs(disc_s) < 16 * disc_err;
                    if (disc_s > 0) {
                        const LD A2 = quadcast::dot(quadcast::cmul(d, c3), c3), B2 = quadcast::dot(quadcast::cmul(d, c3), x0);
                        for (int r = -1; r <= 1; r += 2) {
                            const LD z = (-B2 + r * std::sqrt(disc_s)) / A2;
                            const V4L p = x0 + c3 * z;
                            LD kappa = 0;
                            for (int i = 0; i < 4; ++i) kappa = std::max(kappa, std::fabs(x0[i]) + std::fabs(z * c3[i]));
                            kappa /= std::max(std::fabs(p[2]), std::fabs(p[3]));
                            const LD margin = 1e-4L + 256 * eps * kappa;
                            borderline = borderline || (in_slab(p, -margin) && !in_slab(p, margin));
                        }
                    }
                }
                const quadcast::WindowHit<T> wh = quadcast::intersect_window(vpmt_inv, prim.d, xw, yw);
                const quadcast::SurfaceHit<T> sh = quadcast::nearest_in_slab(wh, prim.slab);
                if (borderline) continue;
                ++mask_checked;
                CHECK_MESSAGE(bool(sh.hit) == (t_ref > 0), kind_name(kind), " it ", it, " k ", k);
                if (!(t_ref > 0) || !sh.hit) {
                    misses += !(t_ref > 0);
                    continue;
                }
                ++hits;

                // Condition of the root: |z error| ~ eps S / |f'(z)|, S the size of the terms of
                // f(z) = (x0 + z c3)^T D (x0 + z c3), |f'(z)| = 2 sqrt(disc), on the kernel's inputs
                const V4L c3 = same_l[2];
                V4L x0{};
                for (int i = 0; i < 4; ++i) x0[i] = same_l[0][i] * LD(xw) + same_l[1][i] * LD(yw) + same_l[3][i];
                LD disc_s = 0, size_s = 0, p_size = 0, p_abs = 0, dp_abs = 0;
                for (int i = 0; i < 4; ++i) {
                    for (int j = i + 1; j < 4; ++j) {
                        const LD m = x0[i] * c3[j] - x0[j] * c3[i];
                        disc_s -= d[i] * d[j] * m * m;
                    }
                    const LD term = std::fabs(x0[i]) + std::fabs(LD(sh.z) * c3[i]);
                    size_s += std::fabs(d[i]) * term * term;
                    p_size = std::max(p_size, term);
                    p_abs = std::max(p_abs, std::fabs(x0[i] + LD(sh.z) * c3[i]));
                    dp_abs = std::max(dp_abs, std::fabs(d[i] * (x0[i] + LD(sh.z) * c3[i])));
                }
                const LD z_cond = eps * size_s / (2 * std::sqrt(std::max(disc_s, LD(0))));
                // The kernel's rounding alone: the same quadratic in long double
                {
                    const LD A2 = quadcast::dot(quadcast::cmul(d, c3), c3), B2 = quadcast::dot(quadcast::cmul(d, c3), x0),
                             C2 = quadcast::dot(quadcast::cmul(d, x0), x0);
                    const LD sq2 = std::sqrt(std::max(LD(0), disc_s));
                    const LD qq = -(B2 + (B2 < 0 ? -sq2 : sq2));
                    LD z1 = qq / A2, z2 = C2 / qq;
                    if (z1 > z2) std::swap(z1, z2);
                    const LD z_same = LD(sh.z) == LD(wh.z_near) ? z1 : z2;
                    worst_same = std::max(worst_same, std::fabs(LD(sh.z) - z_same) / z_cond);
                    CHECK(std::fabs(LD(sh.z) - z_same) < 8 * z_cond);
                }
                // The hit point against the world-space reference
                const V3L h_ref = q * t_ref;
                const V4L zr4 = vp_l * quadcast::vec4(h_ref, LD(1));
                const LD z_ref = zr4[2] / zr4[3];
                const LD e_z = std::fabs(LD(sh.z) - z_ref) / z_cond;
                worst_world = std::max(worst_world, e_z);
                CHECK_MESSAGE(e_z < 16, kind_name(kind), " it ", it, " k ", k);
                const LD err = len3(eye_point(LD(xw), LD(yw), LD(sh.z)) - h_ref);
                worst_rel = std::max(worst_rel, err / s.radius);
                worst_depth_ulp = std::max(worst_depth_ulp, std::fabs(LD(sh.z) - z_ref) / ulp<T>(z_ref));

                // The eye-space normal (eq. 9) points outwards along the reference gradient; its
                // error follows the relative error of the parameter-space point x0 + z c3
                const T w_e = quadcast::window_to_eye(vp_inv, xw, yw, sh.z)[3];
                const V3L n_c = quadcast::cast<LD>(quadcast::eye_normal(mt_inv_t, prim.d, sh.p, w_e));
                const V4L pr = mt_inv_l * quadcast::vec4(h_ref, LD(1));
                const V3L n_ref = quadcast::xyz(quadcast::transpose(mt_inv_l) * quadcast::cmul(d, pr));  // grad f / 2
                const LD cosang = quadcast::dot(n_c, n_ref) / (len3(n_c) * len3(n_ref));
                const LD ang = len3(quadcast::cross(n_c, n_ref)) / (len3(n_c) * len3(n_ref));  // sin
                // (relative to |D p|: the normal of a cone degrades towards its apex)
                const LD n_cond = (eps * p_size + err / s.radius * p_abs) / dp_abs;
                worst_normal = std::max(worst_normal, ang / n_cond);
                CHECK(cosang > 0);
                CHECK(ang < 64 * n_cond);
            }
        }
        std::printf("[window %s] %s: %d hits, %d misses (%d masks checked); z_w error vs world-space ray %.2Lf x cond "
                    "(%.0Lf ulp(z_w), %.2Le of the radius in eye space), kernel rounding %.2Lf x cond, normal angle "
                    "%.2Lf x cond\n",
                    quadcast::scalar_traits<T>::name, kind_name(kind), hits, misses, mask_checked, worst_world,
                    worst_depth_ulp, worst_rel, worst_same, worst_normal);
        CHECK(hits >= 300);
    }
}

TEST_CASE_TEMPLATE("the sphere quad encloses the projected sphere and touches it on all four sides", T, float, double) {
    const LD eps = eps_of<T>();
    LD worst_in = 0, worst_touch = 0, worst_r = 0;
    int tested = 0;
    for (int it = 0; it < 1000; ++it) {
        std::mt19937 rng(30000u + unsigned(it));
        const LD r_l = log_uniform(rng, 0.01L, 100);
        // Eye from 1 + 1e-4 to 1000 radii away, the centre in any direction (also behind the eye)
        const LD ratio = it % 3 == 0 ? 1 + log_uniform(rng, 1e-4L, 1e-1L) : log_uniform(rng, 1.1L, 1000);
        const quadcast::Vec3<T> c = quadcast::cast<T>(unit_vector(rng) * (ratio * r_l));
        const T r = T(r_l);
        const V3L cl = quadcast::cast<LD>(c);
        const LD rl = LD(r), L = len3(cl);
        if (!(L > rl)) continue;
        ++tested;
        const quadcast::SphereQuad<T> sq = quadcast::sphere_quad(c, r);
        REQUIRE(sq.valid);
        // Half size R = r L / sqrt(L^2 - r^2): relative condition L / (L - r); the corners are
        // positions, rounded relative to L + R, so shapes measured in R carry eps (L + R) / R
        const LD r_ref = rl * L / std::sqrt((L - rl) * (L + rl));
        const LD cond = L / (L - rl) + (L + r_ref) / r_ref;
        const LD tol = 16 * eps * cond;
        worst_r = std::max(worst_r, std::fabs(LD(sq.half_size) - r_ref) / r_ref / (eps * L / (L - rl)));
        CHECK(std::fabs(LD(sq.half_size) - r_ref) <= 16 * eps * L / (L - rl) * r_ref);
        V3L k[4];
        for (int i = 0; i < 4; ++i) k[i] = quadcast::cast<LD>(sq.corner[i]);
        const V3L dir = cl / L;
        const V3L ctr = (((k[0] + k[1]) + k[2]) + k[3]) / LD(4);
        const V3L e1 = unit3(k[1] - k[0]), e2 = unit3(k[3] - k[0]);
        // A square in the plane through the centre perpendicular to the view direction,
        // counter-clockwise seen from the eye
        CHECK(len3(ctr - cl) <= tol * r_ref);
        for (int i = 0; i < 4; ++i) {
            CHECK(std::fabs(quadcast::dot(k[i] - cl, dir)) <= tol * r_ref);
            CHECK(std::fabs(len3(k[i] - ctr) - std::sqrt(LD(2)) * r_ref) <= tol * r_ref);
        }
        CHECK(std::fabs(quadcast::dot(e1, e2)) <= tol);
        CHECK(quadcast::dot(quadcast::cross(e1, e2), dir) < 0);
        // Rays along the silhouette cone cross the quad's plane inside the square, touching each side
        const V3L nrm = unit3(quadcast::cross(k[1] - k[0], k[3] - k[0]));
        V3L a{}, b{};
        a = unit3(quadcast::cross(dir, std::fabs(dir[0]) < 0.5L ? V3L{{1, 0, 0}} : V3L{{0, 1, 0}}));
        b = quadcast::cross(dir, a);
        const LD sin_a = rl / L, cos_a = std::sqrt((L - rl) * (L + rl)) / L;
        const LD half = LD(sq.half_size);
        LD ext[4] = {-1e9L, -1e9L, -1e9L, -1e9L};
        for (int i = 0; i < 360; ++i) {
            const LD phi = two_pi * i / 360;
            const V3L v = dir * cos_a + (a * std::cos(phi) + b * std::sin(phi)) * sin_a;
            const V3L q = v * (quadcast::dot(nrm, ctr) / quadcast::dot(nrm, v));
            const LD s1 = quadcast::dot(q - ctr, e1) / half, s2 = quadcast::dot(q - ctr, e2) / half;
            ext[0] = std::max(ext[0], s1);
            ext[1] = std::max(ext[1], -s1);
            ext[2] = std::max(ext[2], s2);
            ext[3] = std::max(ext[3], -s2);
        }
        for (LD e : ext) {
            worst_in = std::max(worst_in, (e - 1) / (eps * cond));
            // 360 samples: the extreme is within 1 - cos(pi / 360) < 4e-5 of the true one
            worst_touch = std::max(worst_touch, (1 - e - 4e-5L) / (eps * cond));
            CHECK(e <= 1 + tol);
            CHECK(e >= 1 - 4e-5L - tol);
        }
    }
    std::printf("[sphere quad %s] %d spheres: half size error %.2Lf eps L/(L-r); silhouette outside the square %.2Lf, "
                "gap to the sides %.2Lf (eps (L/(L-r) + (L+R)/R))\n",
                quadcast::scalar_traits<T>::name, tested, worst_r, worst_in, std::max(LD(0), worst_touch));
    CHECK(tested > 950);
}

TEST_CASE_TEMPLATE("the sphere quad reports an eye inside or on the sphere and is screen-aligned on the axis", T, float, double) {
    for (int it = 0; it < 200; ++it) {
        std::mt19937 rng(31000u + unsigned(it));
        const T r = T(log_uniform(rng, 0.01L, 100));
        const quadcast::Vec3<T> c = quadcast::cast<T>(unit_vector(rng) * (LD(r) * uniform(rng, 0, 0.999L)));
        CHECK_FALSE(quadcast::sphere_quad(c, r).valid);
    }
    CHECK_FALSE(quadcast::sphere_quad(quadcast::vec3(T(0), T(0), T(-2)), T(2)).valid);
    CHECK_FALSE(quadcast::sphere_quad(quadcast::vec3(T(0), T(0), T(0)), T(1)).valid);
    const auto sq = quadcast::sphere_quad(quadcast::vec3(T(0), T(0), T(-5)), T(3));
    CHECK(sq.valid);
    CHECK(sq.half_size == T(3.75));  // 3 * 5 / 4
    CHECK(sq.corner[0][0] == T(-3.75));
    CHECK(sq.corner[0][1] == T(-3.75));
    CHECK(sq.corner[2][0] == T(3.75));
    CHECK(sq.corner[2][1] == T(3.75));
    CHECK(sq.corner[2][2] == T(-5));
    // Straight up or down (d = +-y) still gives a valid square
    const auto up = quadcast::sphere_quad(quadcast::vec3(T(0), T(4), T(0)), T(1));
    CHECK(up.valid);
    CHECK(up.corner[1][0] - up.corner[0][0] > T(0));
}

TEST_CASE_TEMPLATE("the validity mask sees a bowl that crosses the eye plane between its caps", T, float, double) {
    // Eye planes r4 . p = 0 in parameter space against the paraboloid's hemisphere and a
    // two-sheet hyperboloid's bowl: the caps can be in front while the side of the bowl is not
    const PrimitiveKind kinds[] = {PrimitiveKind::paraboloid, PrimitiveKind::hyperboloid_two_sheets};
    for (PrimitiveKind kind : kinds) {
        const V4L d = kind == PrimitiveKind::paraboloid ? V4L{{1, 1, 1, -1}} : V4L{{1, 1, -1, 1}};
        const LD zl = kind == PrimitiveKind::paraboloid ? -1 : 1, zh = kind == PrimitiveKind::paraboloid ? 0 : 3;
        int side_only = 0, valid = 0, invalid = 0;
        for (int it = 0; it < 200; ++it) {
            std::mt19937 rng(32000u + 97u * unsigned(kind) + unsigned(it));
            M4L m{};
            for (int j = 0; j < 4; ++j)
                for (int i = 0; i < 4; ++i) m[j][i] = uniform(rng, -1, 1);
            V3L n = unit_vector(rng);
            LD off = uniform(rng, -1, 4);
            if (it % 2 == 0) {
                // Cut a small cap off the side of the bowl at p*, below its supporting plane
                // n . p = n . p* (n the outward normal; the bowl is convex)
                const V4L ps = param_point(d, uniform(rng, 0, two_pi), uniform(rng, zl + (zh - zl) * 0.2L, zh - (zh - zl) * 0.2L));
                const V3L g = unit3(V3L{{ps[0], ps[1], d[2] * ps[2]}});
                LD cap_max = -std::numeric_limits<LD>::infinity();
                for (LD h : {zl, zh}) {
                    const LD rho = std::sqrt(std::max(LD(0), -(d[2] * h * h + d[3])));
                    cap_max = std::max(cap_max, g[2] * h + rho * std::hypot(g[0], g[1]));
                }
                const LD top = quadcast::dot(g, quadcast::xyz(ps));
                n = -g;
                off = top - uniform(rng, 0.05L, 1.5L) * (top - cap_max);
            }
            for (int j = 0; j < 3; ++j) m[j][3] = n[j];
            m[3][3] = off;
            const quadcast::Mat4<T> pmt = quadcast::cast<T>(m);
            const M4L c = to_ld(pmt);
            LD wmin = 0, wmax = 0;
            w_range(c, d, zl, zh, wmin, wmax);
            // Exact minimum on the caps
            const V4L r4 = quadcast::row(c, 3);
            LD cap_min = std::numeric_limits<LD>::infinity();
            for (LD h : {zl, zh}) {
                const LD rho = std::sqrt(std::max(LD(0), -(d[2] * h * h + d[3])));
                cap_min = std::min(cap_min, h * r4[2] + r4[3] - rho * std::hypot(r4[0], r4[1]));
            }
            if (std::fabs(wmin) < 0.01L * std::fabs(wmax)) continue;
            const auto box = quadcast::slab_bbox(pmt, quadcast::cast<T>(d), quadcast::vec2(T(zl), T(zh)), true);
            CHECK_MESSAGE(bool(box.valid) == (wmin > 0), kind_name(kind), " it ", it);
            valid += wmin > 0;
            invalid += wmin < 0;
            side_only += wmin < 0 && cap_min > 0.01L * std::fabs(wmax);
        }
        std::printf("[bounds %s] %s eye planes: %d valid, %d invalid, %d of them with both caps in front\n",
                    quadcast::scalar_traits<T>::name, kind_name(kind), valid, invalid, side_only);
        CHECK(side_only >= 10);
        CHECK(valid >= 20);
    }
}
