// src/slim/build.cpp -- the greedy ball cover of a SLIM surface, with sharp features
#include "quadcast/slim/build.hpp"

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <numbers>
#include <random>
#include <span>
#include <stdexcept>
#include <string>

namespace quadcast::slim {

namespace {

/// A uniform grid over the points' bounding box: cells in x-fastest order, each cell's points
/// in index order (so every query returns its points in the same order).
class PointGrid {
public:
    PointGrid(const std::vector<Vec3d>& p, const Vec3d& lo, const Vec3d& hi) : p_(p), lo_(lo) {
        const Vec3d ext = hi - lo;
        const double vol_side = std::max({ext[0], ext[1], ext[2], 1e-300});
        // About 8 points per occupied cell on a surface: N / 8 cells on the largest face.
        const double cells_on_face = std::max(1.0, double(p.size()) / 8.0);
        h_ = vol_side / std::max(1.0, std::sqrt(cells_on_face));
        for (int k = 0; k < 3; ++k) n_[k] = std::max(1, std::min(1024, int(std::ceil(ext[k] / h_)) + 1));
        start_.assign(std::size_t(n_[0]) * std::size_t(n_[1]) * std::size_t(n_[2]) + 1, 0);
        std::vector<std::uint32_t> cell(p.size());
        for (std::size_t i = 0; i < p.size(); ++i) {
            cell[i] = std::uint32_t(index(p[i]));
            ++start_[cell[i] + 1];
        }
        for (std::size_t c = 1; c < start_.size(); ++c) start_[c] += start_[c - 1];
        items_.resize(p.size());
        std::vector<std::uint32_t> fill(start_.begin(), start_.end() - 1);
        for (std::size_t i = 0; i < p.size(); ++i) items_[fill[cell[i]]++] = std::uint32_t(i);
    }

    /// The points within distance r of c (|p - c| <= r), appended to `out` (cleared first).
    void query(const Vec3d& c, double r, std::vector<std::uint32_t>& out) const {
        out.clear();
        int a[3], b[3];
        for (int k = 0; k < 3; ++k) {
            a[k] = std::clamp(int(std::floor((c[k] - r - lo_[k]) / h_)), 0, n_[k] - 1);
            b[k] = std::clamp(int(std::floor((c[k] + r - lo_[k]) / h_)), 0, n_[k] - 1);
        }
        const double r2 = r * r;
        for (int z = a[2]; z <= b[2]; ++z)
            for (int y = a[1]; y <= b[1]; ++y)
                for (int x = a[0]; x <= b[0]; ++x) {
                    const std::size_t cell = (std::size_t(z) * std::size_t(n_[1]) + std::size_t(y)) * std::size_t(n_[0]) + std::size_t(x);
                    for (std::uint32_t k = start_[cell]; k < start_[cell + 1]; ++k) {
                        const std::uint32_t i = items_[k];
                        const Vec3d d = p_[i] - c;
                        if (dot(d, d) <= r2) out.push_back(i);
                    }
                }
    }

private:
    std::size_t index(const Vec3d& x) const {
        int c[3];
        for (int k = 0; k < 3; ++k) c[k] = std::clamp(int(std::floor((x[k] - lo_[k]) / h_)), 0, n_[k] - 1);
        return (std::size_t(c[2]) * std::size_t(n_[1]) + std::size_t(c[1])) * std::size_t(n_[0]) + std::size_t(c[0]);
    }

    const std::vector<Vec3d>& p_;
    Vec3d lo_;
    double h_ = 1;
    int n_[3] = {1, 1, 1};
    std::vector<std::uint32_t> start_, items_;
};

/// FitOptions::regularization of the plane fit (`attempt`): the 6 quadratic coefficients cost 1e6
/// times the mean residual, so they stay below ~1e-6 of the linear ones.
constexpr double planar_regularization = 1e6;

/// The fewest points of a corner cluster's sharp split-off part that reject the corner
/// (`attempt_corner`): more than one stray normal.
constexpr std::size_t corner_min_split = 3;

/// How far a crease's face normals may spread about their mean (`rounds_crease`): CGAL's bunny and
/// the coarse bunny_3k have pairs of facets more than 60 degrees apart whose normals spread 10-30
/// degrees; counting those as creases cut their smooth sheets into planes (seams).
constexpr double crease_face_spread_degrees = 5;

/// The largest ball, in E, that `rounds_crease` examines: the flakes were balls of 2-3 E; in
/// larger balls a quadric within E of both faces of a crease bends little.
constexpr double crease_max_radius = 3;

/// The fewest points of a face of `attempt_small_pair`.
constexpr std::size_t small_pair_min_face = 4;

/// A record being built: the world ball and the local fit (kept for the statistics).
struct Record {
    Ball ball;
    Quadric<double> local;
};

/// What one seed produces: 1 record, 2 for a sharp pair, 3 for a corner, 4 for a saddle corner;
/// `side[i]` = the record of each ball point (for the covering); `forced` when the fit exceeded E.
struct SeedResult {
    std::vector<Record> records;
    std::vector<std::uint32_t> points;   ///< the ball's points
    std::vector<unsigned char> side;
    double radius = 0;
    bool forced = false;
    std::size_t fits = 0;
};

struct Context {
    const OrientedPoints& pts;
    const BuildOptions& opt;
    const PointGrid& grid;
    double diagonal, threshold;
};

/// The record of a fit in the ball (c, r), drawn in the ball (c, t r) (t: its support fraction).
Record make_record(const LocalFit& f, const Vec3d& c, double r, double t = 1) {
    Record rec;
    rec.ball.center = c;
    rec.ball.radius = t * r;
    rec.ball.q = local_to_world(f.local, c, r);
    rec.local = t == 1 ? f.local : world_to_local(rec.ball.q, c, t * r);
    return rec;
}

/// 2-means of the normals of `idx`: labels 0/1 and the unit cluster means.
void two_means(const std::vector<Vec3d>& n, const std::vector<std::uint32_t>& idx, std::vector<unsigned char>& label, Vec3d& m0,
               Vec3d& m1) {
    Vec3d mean = vec3(0.0, 0.0, 0.0);
    for (const std::uint32_t i : idx) mean = mean + n[i];
    // Seeds: the normal farthest from the mean, then the one farthest from it.
    std::size_t a = 0, b = 0;
    for (std::size_t k = 1; k < idx.size(); ++k)
        if (dot(n[idx[k]], mean) < dot(n[idx[a]], mean)) a = k;
    for (std::size_t k = 1; k < idx.size(); ++k)
        if (dot(n[idx[k]], n[idx[a]]) < dot(n[idx[b]], n[idx[a]])) b = k;
    m0 = n[idx[a]];
    m1 = n[idx[b]];
    label.assign(idx.size(), 0);
    for (int round = 0; round < 10; ++round) {
        Vec3d s0 = vec3(0.0, 0.0, 0.0), s1 = s0;
        for (std::size_t k = 0; k < idx.size(); ++k) {
            label[k] = dot(n[idx[k]], m1) > dot(n[idx[k]], m0) ? 1 : 0;
            if (label[k]) s1 = s1 + n[idx[k]];
            else s0 = s0 + n[idx[k]];
        }
        if (!(length(s0) > 0) || !(length(s1) > 0)) return;
        m0 = normalize(s0);
        m1 = normalize(s1);
    }
}

/// Whether a fit rounds a crease (BuildOptions::crease_normal_degrees): its gradient at one of
/// its points is more than crease_normal_degrees from the point's normal, and the ball's normals
/// split (2-means) into two parts more than sharp_angle apart, the smaller of at least 3 points,
/// each part's normals within crease_face_spread_degrees of its mean.
bool rounds_crease(const Context& cx, const std::vector<std::uint32_t>& idx, double r, const LocalFit& f) {
    if (r > crease_max_radius * cx.threshold) return false;
    if (f.min_normal_cos >= std::cos(cx.opt.crease_normal_degrees * std::numbers::pi / 180)) return false;
    std::vector<unsigned char> label;
    Vec3d s0{}, s1{};
    two_means(cx.pts.normals, idx, label, s0, s1);
    std::size_t n1 = 0;
    for (const unsigned char l : label) n1 += l;
    if (!(dot(s0, s1) < std::cos(cx.opt.sharp_angle_degrees * std::numbers::pi / 180) && std::min(n1, idx.size() - n1) >= 3)) return false;
    // Two faces, each nearly flat: every normal within crease_face_spread_degrees of its part's
    // mean (a coarse mesh's curved region, its faces' normals spread, is no crease).
    const double cos_tight = std::cos(crease_face_spread_degrees * std::numbers::pi / 180);
    for (std::size_t k = 0; k < idx.size(); ++k)
        if (dot(cx.pts.normals[idx[k]], label[k] ? s1 : s0) < cos_tight) return false;
    return true;
}

/// The boundary part of the support check (BuildOptions::support_max_gap_degrees): the input
/// points of `near` whose normals lie within 60 degrees (or the sharp angle, if smaller) of the gradient g at the zero-set sample
/// x (the sheet's own points), projected onto the tangent plane at x, surround x: seen from x,
/// no angle between consecutive ones exceeds the maximum gap. Inside a sheet they surround it; on
/// the sheet's edge (a face's crease, a point cloud's border) they fill half the circle; past it
/// (a plane continued beyond its face: a fin) less. Fewer than three such points never surround.
bool surrounded(const Context& cx, const Vec3d& x, const Vec3d& g, const std::vector<std::uint32_t>& near, std::vector<double>& angles) {
    const double gl = length(g);
    if (!(gl > 0)) return false;
    const Vec3d n = g * (1 / gl);
    // A tangent basis (t1, t2) of the plane normal to n.
    const Vec3d a = std::fabs(n[0]) < 0.6 ? vec3(1.0, 0.0, 0.0) : vec3(0.0, 1.0, 0.0);
    const Vec3d t1 = normalize(cross(n, a)), t2 = cross(n, t1);
    // A sheet's own points: normals within 60 degrees of g, or within the sharp angle where that
    // is smaller (else the other face of a sharper crease would count as the same sheet).
    const double own_sheet_cos = std::max(0.5, std::cos(cx.opt.sharp_angle_degrees * std::numbers::pi / 180));
    angles.clear();
    for (const std::uint32_t i : near) {
        if (!(dot(cx.pts.normals[i], n) > own_sheet_cos)) continue;
        const Vec3d d = cx.pts.positions[i] - x;
        const double p = dot(d, t1), q = dot(d, t2);
        if (p == 0 && q == 0) continue;  // on the normal line: no direction
        angles.push_back(std::atan2(q, p));
    }
    if (angles.size() < 3) return false;
    std::sort(angles.begin(), angles.end());
    double gap = 2 * std::numbers::pi + angles.front() - angles.back();
    for (std::size_t k = 1; k < angles.size(); ++k) gap = std::max(gap, angles[k] - angles[k - 1]);
    return gap <= cx.opt.support_max_gap_degrees * std::numbers::pi / 180;
}

/// The support check (BuildOptions::support_check): how far from the centre the zero set of the
/// local quadric inside the ball (and on the kept side of each of `planes`, world coordinates)
/// lies near the input points. Sampled where the lines parallel to the three axes through an n x n
/// grid of [-1, 1]^2 (local coordinates; n from 13 to support_max_lines) cross it. A sample x passes when
///  - an input point within 2 h of it (h = r sqrt(pi / m), the spacing of m points on a disc of
///    radius r; at least 2 E) has a normal n with n . g > support_normal_cos |g| (g the gradient
///    at x): a second sheet, or a sheet folded back through the points, fails;
///  - and (`surrounded`) the points within 3 h whose normals are within 60 degrees of g leave no
///    angular gap wider than support_max_gap_degrees around x: a quadric continued past a crease
///    or a border (a fin) fails. Within 2 h of where the sheet crosses the clip plane, its
///    intended edge, this test is skipped.
/// Returns the smallest |u| of a failing sample (1 when none fails): the ball of that radius
/// (relative to r) holds only supported samples. Returns early, with a value below `floor`, once a
/// failing sample nearer than `floor` is found.
double support_fraction(const Context& cx, const Quadric<double>& local, const Vec3d& c, double r, std::span<const Vec4d> planes, std::size_t m,
                        double floor, int min_lines = 13, double density = 3) {
    const double support = std::max(2.0 * r * std::sqrt(std::numbers::pi / double(std::max<std::size_t>(m, 1))), 2.0 * cx.threshold);
    const double gap_radius = 1.5 * support;
    const bool gap_test = cx.opt.support_max_gap_degrees < 360;
    std::vector<std::uint32_t> near;
    std::vector<double> angles;
    double t = 1;
    // Lines two thirds of the support distance apart (13 to support_max_lines per side): a fin
    // narrower than their spacing can lie between them.
    const int lines = std::clamp(int(std::ceil(density * r / support)) + 1, min_lines, std::max(min_lines, cx.opt.support_max_lines));
    const double half = 0.5 * (lines - 1), spacing = 1.0 / (0.5 * lines);
    for (int a = 0; a < 3; ++a)
        for (int i = 0; i < lines; ++i)
            for (int j = 0; j < lines; ++j) {
                Vec3d p = vec3(0.0, 0.0, 0.0), e = vec3(0.0, 0.0, 0.0);
                p[(a + 1) % 3] = (i - half) * spacing;
                p[(a + 2) % 3] = (j - half) * spacing;
                e[a] = 1.0;
                // f(p + s e) = A s^2 + B s + C from three values
                const double fm = evaluate(local, p - e), f0 = evaluate(local, p), fp = evaluate(local, p + e);
                const double A = 0.5 * (fp + fm) - f0, B = 0.5 * (fp - fm), C = f0;
                double roots[2];
                int n = 0;
                const double scale = std::fabs(A) + std::fabs(B) + std::fabs(C);
                if (std::fabs(A) <= 1e-12 * scale) {
                    if (std::fabs(B) > 1e-12 * scale) roots[n++] = -C / B;
                } else {
                    const double disc = B * B - 4 * A * C;
                    if (disc >= 0) {
                        const double q = -0.5 * (B + std::copysign(std::sqrt(disc), B));
                        roots[n++] = q / A;
                        if (q != 0) roots[n++] = C / q;
                    }
                }
                for (int k = 0; k < n; ++k) {
                    const Vec3d u = p + e * roots[k];
                    const double uu = dot(u, u);
                    if (!(uu < t * t)) continue;  // outside the ball, or no nearer than a failure found
                    const Vec3d x = c + u * r;
                    bool outside = false;
                    for (const Vec4d& pl : planes) outside = outside || dot(xyz(pl), x) + pl[3] < 0;
                    if (outside) continue;
                    cx.grid.query(x, gap_test ? gap_radius : support, near);
                    // ... and one of them with a normal on the sample's side: a sheet folded back
                    // or a second sheet near other points has the opposite orientation.
                    const Vec3d g = gradient(local, u);
                    const double gl = length(g);
                    bool agrees = false;
                    for (const std::uint32_t i : near) {
                        const Vec3d d = cx.pts.positions[i] - x;
                        if (dot(d, d) <= support * support && dot(cx.pts.normals[i], g) > cx.opt.support_normal_cos * gl) {
                            agrees = true;
                            break;
                        }
                    }
                    // The clip plane ends the sheet: within 2 h of their crossing, measured in the
                    // sheet (side / sin of the angle between the sheet and the plane), the sheet's
                    // points fill only half of the circle. (A sheet parallel to its plane, as in
                    // a thin shell's pair, never comes near the crossing.)
                    bool at_plane = false;
                    for (const Vec4d& pl : planes) {
                        const double side = dot(xyz(pl), x) + pl[3];
                        const double cos_gm = gl > 0 ? dot(g, xyz(pl)) / gl : 1.0;
                        const double sin2 = std::max(0.0, 1 - cos_gm * cos_gm);
                        at_plane = at_plane || side * side < support * support * sin2;
                    }
                    const bool ok = agrees && (!gap_test || at_plane || surrounded(cx, x, g, near, angles));
                    if (ok) continue;
                    t = std::sqrt(uu);
                    if (t < floor) return t;
                }
            }
    return t;
}

/// The radius fraction a record keeps of its fitting ball, from its support fraction: all of it
/// when every sample passed, else 0.9 of the distance to the nearest failing one (the sampled
/// lines are up to 0.15 r apart: a fin starts a little nearer than where a line finds it).
double kept_fraction(double support) { return support >= 1 ? 1.0 : 0.9 * support; }

bool attempt_pair(const Context& cx, const Vec3d& c, double r, const std::vector<std::uint32_t>& idx, SeedResult& out);
bool attempt_corner(const Context& cx, const Vec3d& c, double r, const std::vector<std::uint32_t>& idx, SeedResult& out);

/// Tries the ball (c, r) of `points`: a single quadric, else a sharp pair. `ok` when accepted.
bool attempt_quadrics(const Context& cx, const Vec3d& c, double r, const std::vector<std::uint32_t>& idx, SeedResult& out) {
    const auto& P = cx.pts.positions;
    const auto& N = cx.pts.normals;
    out.records.clear();
    out.points = idx;
    out.side.assign(idx.size(), 0);
    out.radius = r;
    ++out.fits;
    const LocalFit single = fit_ball(P, N, idx, c, r, cx.opt.fit);
    bool single_ok = single.solved && single.oriented && single.max_distance <= cx.threshold && !rounds_crease(cx, idx, r, single);
    double t = 1;
    if (single_ok && cx.opt.support_check) {
        t = support_fraction(cx, single.local, c, r, {}, idx.size(), cx.opt.min_support_fraction);
        single_ok = t >= cx.opt.min_support_fraction;
    }
    // (Rejected: the whole ball's record, which grow_ball's forced case checks again.)
    if (single.solved) out.records.push_back(make_record(single, c, r, single_ok ? kept_fraction(t) : 1.0));
    if (single_ok || !cx.opt.sharp_features) return single_ok;
    return attempt_pair(cx, c, r, idx, out) || (cx.opt.corners && attempt_corner(cx, c, r, idx, out));
}

/// Whether the normals of cluster `sd` split (2-means) into two parts whose means are more than
/// the sharp angle apart (cosine below cos_max), the smaller holding at least `min_part` points.
bool splits_again(const std::vector<Vec3d>& N, const std::vector<std::uint32_t>& sd, double cos_max, std::size_t min_part) {
    std::vector<unsigned char> sub_label;
    Vec3d s0{}, s1{};
    two_means(N, sd, sub_label, s0, s1);
    std::size_t n1 = 0;
    for (const unsigned char l : sub_label) n1 += l;
    return dot(s0, s1) < cos_max && std::min(n1, sd.size() - n1) >= min_part;
}

/// The clip plane between two clusters of a ball's points (world; positive on cluster a's side):
/// along m = (ma - mb) / |ma - mb| (the clusters' unit mean normals: it bisects their dihedral
/// angle), the threshold with the fewest points of a below it and of b above it, or the reverse
/// orientation, whichever is better; `misclassified` that count.
Vec4d separating_plane(const std::vector<Vec3d>& P, const std::vector<std::uint32_t>& a, const std::vector<std::uint32_t>& b, const Vec3d& ma,
                       const Vec3d& mb, const Vec3d& c, double r, std::size_t& misclassified) {
    const Vec3d m = normalize(ma - mb);
    std::vector<std::pair<double, unsigned char>> proj;
    proj.reserve(a.size() + b.size());
    for (const std::uint32_t i : a) proj.push_back({dot(m, P[i] - c), 0});
    for (const std::uint32_t i : b) proj.push_back({dot(m, P[i] - c), 1});
    std::sort(proj.begin(), proj.end());
    // Errors for "a on the positive side" at split j (points [0, j) negative).
    std::size_t na_below = 0, nb_below = 0;
    const std::size_t na = a.size(), nb = b.size();
    std::size_t best_err = std::numeric_limits<std::size_t>::max(), best_j = 0;
    bool best_flip = false;
    for (std::size_t j = 0; j <= proj.size(); ++j) {
        if (j > 0) (proj[j - 1].second ? nb_below : na_below)++;
        if (j > 0 && j < proj.size() && proj[j].first == proj[j - 1].first) continue;
        const std::size_t e_pos = na_below + (nb - nb_below);   // a above
        const std::size_t e_neg = nb_below + (na - na_below);   // a below
        if (e_pos < best_err) { best_err = e_pos; best_j = j; best_flip = false; }
        if (e_neg < best_err) { best_err = e_neg; best_j = j; best_flip = true; }
    }
    misclassified = best_err;
    double t;
    if (best_j == 0) t = proj.front().first - 1e-9 * r;
    else if (best_j == proj.size()) t = proj.back().first + 1e-9 * r;
    else t = 0.5 * (proj[best_j - 1].first + proj[best_j].first);
    // Plane of a: s (m . (x - c) - t) >= 0, s = +1 unless flipped.
    const double s = best_flip ? -1.0 : 1.0;
    return vec4(m * s, -s * (dot(m, c) + t));
}

/// The normal of the face a cluster `sd` of a ball's normals belongs to, from its unit mean m: the
/// mean of its normals within the sharp angle of m (cosine at least cos_max), twice. A few points of
/// another face in the cluster (where the ball reaches a third face, too few points to be a cluster
/// of their own) tilt the plain mean, and with it the plane between the clusters: on a box, a face
/// continued past its edge by up to 5 E (tests/slim/corner.cpp).
Vec3d face_normal(const std::vector<Vec3d>& N, const std::vector<std::uint32_t>& sd, Vec3d m, double cos_max) {
    for (int round = 0; round < 2; ++round) {
        Vec3d s = vec3(0.0, 0.0, 0.0);
        for (const std::uint32_t i : sd)
            if (dot(N[i], m) >= cos_max) s = s + N[i];
        if (!(length(s) > 0)) break;
        m = normalize(s);
    }
    return m;
}

/// The plane's value at x (a record keeps the part of its quadric where it is >= 0: `kept`).
double plane_value(const Vec4d& plane, const Vec3d& x) { return dot(xyz(plane), x) + plane[3]; }
bool kept(const Vec4d& plane, const Vec3d& x) { return plane_value(plane, x) >= 0; }

/// The points of a on the negative side of `plane` and of b on its positive side.
std::size_t misclassified(const std::vector<Vec3d>& P, const std::vector<std::uint32_t>& a, const std::vector<std::uint32_t>& b, const Vec4d& plane) {
    std::size_t n = 0;
    for (const std::uint32_t i : a) n += plane_value(plane, P[i]) < 0;
    for (const std::uint32_t i : b) n += plane_value(plane, P[i]) > 0;
    return n;
}

/// The mean signed distance of the points `pts` to the plane through x0 with unit normal n: the
/// convexity of an edge (negative where a face's points lie behind the other face's plane on both
/// sides: convex; positive on both: concave).
double mean_signed_distance(const std::vector<Vec3d>& P, const std::vector<std::uint32_t>& pts, const Vec3d& n, const Vec3d& x0) {
    double sum = 0;
    for (const std::uint32_t i : pts) sum += dot(n, P[i] - x0);
    return sum / double(pts.size());
}

Vec3d centroid_of(const std::vector<Vec3d>& P, const std::vector<std::uint32_t>& pts) {
    Vec3d s = vec3(0.0, 0.0, 0.0);
    for (const std::uint32_t i : pts) s = s + P[i];
    return s * (1.0 / double(pts.size()));
}

/// The clip plane `plane` between the faces of fits fa and fb (unit face normals na, nb) in the
/// ball (c, r), moved along its normal to pass through the fits' crossing in the ball (the edge
/// they draw): `separating_plane` puts it midway between the two clusters' nearest points, which
/// may lie up to a point spacing from the edge, and where the plane misses the crossing one face
/// ends short of it and the other runs past it (a crack along a convex edge, a ledge along a
/// concave one, the faces' normals blended across it). The crossing is sampled at 9 points along
/// the edge direction na x nb (Newton's method on fa = fb = 0 in the plane across it); its offset is
/// the samples' mean. Unchanged when the faces are within 30 degrees of parallel or opposite (no
/// edge: a thin shell's two sides) or fewer than 3 samples converge inside the ball.
Vec4d plane_through_crossing(const Vec4d& plane, const LocalFit& fa, const LocalFit& fb, const Vec3d& na, const Vec3d& nb, const Vec3d& c, double r,
                             std::vector<Vec3d>* crossing = nullptr) {
    const Vec3d e = cross(na, nb);
    if (!(length(e) >= 0.5)) return plane;
    const Vec3d d = normalize(e);
    const Vec3d n = xyz(plane);  // unit
    // Two directions across the edge, and the plane's point nearest the centre (ball coordinates).
    const Vec3d e1 = normalize(cross(d, n)), e2 = cross(d, e1);
    const Vec3d base = n * (-(dot(n, c) + plane[3]) / r);
    double sum = 0;
    int count = 0;
    for (int k = -4; k <= 4; ++k) {
        Vec3d u = base + d * (0.2 * k);
        bool converged = false;
        for (int it = 0; it < 12 && !converged; ++it) {
            const double f0 = evaluate(fa.local, u), f1 = evaluate(fb.local, u);
            const Vec3d g0 = gradient(fa.local, u), g1 = gradient(fb.local, u);
            const double a = dot(g0, e1), b = dot(g0, e2), cc = dot(g1, e1), dd = dot(g1, e2);
            const double det = a * dd - b * cc;
            if (!(std::fabs(det) > 1e-12 * length(g0) * length(g1))) break;
            const double s = (-f0 * dd + b * f1) / det, t = (-a * f1 + cc * f0) / det;
            u = u + e1 * s + e2 * t;
            converged = std::fabs(s) + std::fabs(t) < 1e-12;  // ball units (r = 1); near tangency it may not: the sample is dropped
        }
        if (!converged || !(dot(u, u) < 0.9 * 0.9) || length(u - base - d * (0.2 * k)) > 0.5) continue;
        sum += dot(n, c + u * r);
        if (crossing) crossing->push_back(c + u * r);
        ++count;
    }
    if (count < 3) return plane;
    return vec4(n, -sum / count);
}

/// The clip plane between clusters a and b of a ball's points (positive on a's side; unit face
/// normals na, nb; their fits fa, fb): `separating_plane`, then moved through the fits' crossing
/// (`plane_through_crossing`) where that puts no more points on the wrong side; `misclassified`
/// the points it does.
Vec4d edge_plane(const std::vector<Vec3d>& P, const std::vector<std::uint32_t>& a, const std::vector<std::uint32_t>& b, const Vec3d& na, const Vec3d& nb,
                 const LocalFit& fa, const LocalFit& fb, const Vec3d& c, double r, std::size_t& misclassified_points, std::vector<Vec3d>* crossing = nullptr) {
    const Vec4d plane = separating_plane(P, a, b, na, nb, c, r, misclassified_points);
    const Vec4d moved = plane_through_crossing(plane, fa, fb, na, nb, c, r, crossing);
    const std::size_t err = misclassified(P, a, b, moved);
    if (err > misclassified_points) return plane;  // (the crossing itself still serves `crossing_planes`, which checks its planes' points)
    misclassified_points = err;
    return moved;
}

/// 2-means of the normals of `idx` (labels, unit means) and the points of each side; false when
/// the means are not more than the sharp angle apart (cosine not below cos_max).
bool sharp_split(const std::vector<Vec3d>& N, const std::vector<std::uint32_t>& idx, double cos_max, std::vector<unsigned char>& label, Vec3d& m0,
                 Vec3d& m1, std::vector<std::uint32_t> (&side)[2]) {
    two_means(N, idx, label, m0, m1);
    if (!(dot(m0, m1) < cos_max)) return false;
    for (std::size_t k = 0; k < idx.size(); ++k) side[label[k]].push_back(idx[k]);
    return true;
}

/// The two records of a sharp pair of the ball (c, r) with the points `idx`: the fits f0 and f1
/// clipped by plane0 and its opposite (or `own_plane1`), each drawn as far as the support check accepts it (false,
/// `out` unchanged, below min_support_fraction).
bool commit_pair(const Context& cx, const Vec3d& c, double r, const std::vector<std::uint32_t>& idx, const LocalFit& f0, const LocalFit& f1,
                 const Vec4d& plane0, const std::vector<unsigned char>& label, SeedResult& out, const Vec4d* own_plane1 = nullptr) {
    const Vec4d plane1 = own_plane1 ? *own_plane1 : -plane0;
    double t0 = 1, t1 = 1;
    if (cx.opt.support_check) {
        t0 = support_fraction(cx, f0.local, c, r, std::span<const Vec4d>(&plane0, 1), idx.size(), cx.opt.min_support_fraction);
        if (t0 < cx.opt.min_support_fraction) return false;
        t1 = support_fraction(cx, f1.local, c, r, std::span<const Vec4d>(&plane1, 1), idx.size(), cx.opt.min_support_fraction);
        if (t1 < cx.opt.min_support_fraction) return false;
    }
    out.records.clear();
    out.records.push_back(make_record(f0, c, r, kept_fraction(t0)));
    out.records.push_back(make_record(f1, c, r, kept_fraction(t1)));
    out.records[0].ball.has_plane = out.records[1].ball.has_plane = true;
    out.records[0].ball.plane = plane0;
    out.records[1].ball.plane = plane1;
    out.points = idx;
    out.side = label;
    out.radius = r;
    return true;
}

/// The clip planes of a sharp pair's two faces (fits f0, f1 in the ball (c, r); their clusters
/// `side`; samples of the fits' crossing, `plane_through_crossing`): each face ended by the OTHER
/// face's tangent plane at the crossing's centroid, the face kept behind it at a convex edge and in
/// front of it at a concave one (each face's points on average behind, or in front of, the other's
/// tangent plane; false when they disagree). A plane between the faces ends both along a straight
/// line, a chord of a curved crease: where a curved face meets a flat one (fandisk's top and its
/// rounded column) the curved face ran up past the flat one between the chord and the crease, a
/// fin up to the chord's sagitta high, and the flat face past the curved one at the chord's ends.
/// Ended by the flat face's own plane, the curved face stops exactly at it; the flat face, ended by
/// the curved face's tangent plane, still runs past the crease by the curved face's sagitta along
/// it. Between two planar faces both planes are the faces themselves: the edge, as before. False
/// too where fewer than 3 crossing samples converged or more than sharp_max_misclassified of the
/// points lie on their plane's wrong side.
bool crossing_planes(const Context& cx, const std::vector<Vec3d>& P, const std::vector<std::uint32_t> (&side)[2], const LocalFit& f0, const LocalFit& f1,
                     const Vec3d& c, double r, const std::vector<Vec3d>& crossing, Vec4d (&own)[2]) {
    if (crossing.size() < 3) return false;
    Vec3d xm = vec3(0.0, 0.0, 0.0);
    for (const Vec3d& x : crossing) xm = xm + x;
    xm = xm * (1.0 / double(crossing.size()));
    const Vec3d g[2] = {normalize(gradient(f0.local, (xm - c) * (1 / r))), normalize(gradient(f1.local, (xm - c) * (1 / r)))};
    const double s01 = mean_signed_distance(P, side[1], g[0], xm), s10 = mean_signed_distance(P, side[0], g[1], xm);
    if (!((s01 < 0 && s10 < 0) || (s01 > 0 && s10 > 0))) return false;
    const double sign = s01 < 0 ? -1.0 : 1.0;  // convex: behind the other's tangent plane
    std::size_t wrong = 0;
    for (int k = 0; k < 2; ++k) {
        const Vec3d& n = g[1 - k];
        own[k] = vec4(n * sign, -sign * dot(n, xm));
        for (const std::uint32_t i : side[k]) wrong += !kept(own[k], P[i]);
    }
    return double(wrong) <= cx.opt.sharp_max_misclassified * double(side[0].size() + side[1].size());
}

/// The sharp pair of the ball (c, r) (build.hpp, step 4). On success `out` holds the two records
/// and the points' sides; otherwise `out` is unchanged.
bool attempt_pair(const Context& cx, const Vec3d& c, double r, const std::vector<std::uint32_t>& idx, SeedResult& out) {
    const auto& P = cx.pts.positions;
    const auto& N = cx.pts.normals;
    // Split the normals; a pair needs two distinct, large enough clusters.
    std::vector<unsigned char> label;
    Vec3d m0{}, m1{};
    std::vector<std::uint32_t> side[2];
    const double cos_max = std::cos(cx.opt.sharp_angle_degrees * std::numbers::pi / 180);
    if (!sharp_split(N, idx, cos_max, label, m0, m1, side)) return false;
    const std::size_t need = std::max(cx.opt.min_points, std::size_t(std::ceil(cx.opt.sharp_min_fraction * double(idx.size()))));
    if (side[0].size() < need || side[1].size() < need) return false;
    // Neither side may split again (a corner: three faces in two clusters, one of them two faces
    // whose quadric draws both planes past their crease, where the clip plane, tilted between the
    // clusters' means, does not cut them off; `attempt_corner` then).
    for (const std::vector<std::uint32_t>& sd : side)
        if (splits_again(N, sd, cos_max, need)) return false;
    out.fits += 2;
    const LocalFit f0 = fit_ball(P, N, side[0], c, r, cx.opt.fit), f1 = fit_ball(P, N, side[1], c, r, cx.opt.fit);
    const auto good = [&](const LocalFit& f) { return f.solved && f.oriented && f.max_distance <= cx.threshold; };
    if (!good(f0) || !good(f1)) return false;
    // The clip plane between the clusters (`edge_plane`); a split the plane cannot make
    // (e.g. a corner's three faces in two clusters) is no pair.
    std::size_t best_err = 0;
    m0 = face_normal(N, side[0], m0, cos_max);
    m1 = face_normal(N, side[1], m1, cos_max);
    std::vector<Vec3d> crossing;
    const Vec4d plane0 = edge_plane(P, side[0], side[1], m0, m1, f0, f1, c, r, best_err, &crossing);
    if (double(best_err) > cx.opt.sharp_max_misclassified * double(idx.size())) return false;
    // Each face ended by the other's tangent plane where that keeps its points (`crossing_planes`),
    // else both by plane0.
    Vec4d own[2];
    if (cx.opt.pair_tangent_planes && crossing_planes(cx, P, side, f0, f1, c, r, crossing, own) && commit_pair(cx, c, r, idx, f0, f1, own[0], label, out, &own[1])) return true;
    return commit_pair(cx, c, r, idx, f0, f1, plane0, label, out);
}

/// 3-means of the normals of `idx`: labels 0/1/2 and the unit cluster means. Seeds: the normal
/// farthest from the mean, the one farthest from it, and the one farthest from both.
void three_means(const std::vector<Vec3d>& n, const std::vector<std::uint32_t>& idx, std::vector<unsigned char>& label, Vec3d (&m)[3]) {
    Vec3d mean = vec3(0.0, 0.0, 0.0);
    for (const std::uint32_t i : idx) mean = mean + n[i];
    std::size_t a = 0, b = 0, c = 0;
    for (std::size_t k = 1; k < idx.size(); ++k)
        if (dot(n[idx[k]], mean) < dot(n[idx[a]], mean)) a = k;
    for (std::size_t k = 1; k < idx.size(); ++k)
        if (dot(n[idx[k]], n[idx[a]]) < dot(n[idx[b]], n[idx[a]])) b = k;
    const auto nearest = [&](std::size_t k) { return std::max(dot(n[idx[k]], n[idx[a]]), dot(n[idx[k]], n[idx[b]])); };
    for (std::size_t k = 1; k < idx.size(); ++k)
        if (nearest(k) < nearest(c)) c = k;
    m[0] = n[idx[a]];
    m[1] = n[idx[b]];
    m[2] = n[idx[c]];
    label.assign(idx.size(), 0);
    for (int round = 0; round < 10; ++round) {
        Vec3d sum[3] = {vec3(0.0, 0.0, 0.0), vec3(0.0, 0.0, 0.0), vec3(0.0, 0.0, 0.0)};
        for (std::size_t k = 0; k < idx.size(); ++k) {
            const Vec3d& v = n[idx[k]];
            unsigned char l = 0;
            for (unsigned char j = 1; j < 3; ++j)
                if (dot(v, m[j]) > dot(v, m[l])) l = j;
            label[k] = l;
            sum[l] = sum[l] + v;
        }
        for (int j = 0; j < 3; ++j)
            if (!(length(sum[j]) > 0)) return;
        for (int j = 0; j < 3; ++j) m[j] = normalize(sum[j]);
    }
}

/// The face of a saddle corner whose part of the surface is not convex, from the three faces'
/// clusters `side` and their unit face normals `m` (`face_normal`): each face approximated by the plane
/// through its points' centroid along its face normal, the edge of faces i and j is convex where the points of
/// each lie behind the other's plane on average, concave where in front. A saddle has one edge
/// unlike the other two; the face opposite it (on neither of its faces) is the one drawn where it is
/// inside (or outside) EITHER of the other two: a wedge of more than 180 degrees about the corner,
/// which no pair of clip planes keeps. -1 when the corner is no saddle (all three edges alike, or an
/// edge whose two faces disagree).
int saddle_face(const std::vector<Vec3d>& P, const std::vector<std::uint32_t> (&side)[3], const Vec3d (&m)[3]) {
    const Vec3d centroid[3] = {centroid_of(P, side[0]), centroid_of(P, side[1]), centroid_of(P, side[2])};
    const auto behind = [&](int i, int j) { return mean_signed_distance(P, side[j], m[i], centroid[i]); };
    int convex[3];  // edge k: faces (k + 1) % 3 and (k + 2) % 3
    for (int k = 0; k < 3; ++k) {
        const int i = (k + 1) % 3, j = (k + 2) % 3;
        const double a = behind(i, j), b = behind(j, i);
        if (a < 0 && b < 0) convex[k] = 1;
        else if (a > 0 && b > 0) convex[k] = 0;
        else return -1;
    }
    for (int k = 0; k < 3; ++k)
        if (convex[k] != convex[(k + 1) % 3] && convex[k] != convex[(k + 2) % 3]) return k;
    return -1;
}

/// Whether every record of `recs` passes the support check with its planes over its whole ball.
bool corner_supported(const Context& cx, const Vec3d& c, double r, std::size_t m, std::span<const Record> recs) {
    if (!cx.opt.support_check) return true;
    for (const Record& rec : recs) {
        const Vec4d planes[2] = {rec.ball.plane, rec.ball.plane2};
        if (support_fraction(cx, rec.local, c, r, std::span<const Vec4d>(planes, 2), m, cx.opt.min_support_fraction) < 1.0) return false;
    }
    return true;
}

/// The record of fit f in the ball (c, r) clipped by planes a and b.
Record corner_record(const LocalFit& f, const Vec3d& c, double r, const Vec4d& a, const Vec4d& b) {
    Record rec = make_record(f, c, r);
    rec.ball.has_plane = rec.ball.has_plane2 = true;
    rec.ball.plane = a;
    rec.ball.plane2 = b;
    return rec;
}

/// The points of idx outside their record: point q belongs to recs[rec_of[q]] and lies on the
/// wrong side of one of its two planes.
std::size_t misplaced(const std::vector<Vec3d>& P, const std::vector<std::uint32_t>& idx, std::span<const Record> recs, const std::vector<unsigned char>& rec_of) {
    std::size_t n = 0;
    for (std::size_t q = 0; q < idx.size(); ++q) {
        const Ball& b = recs[rec_of[q]].ball;
        n += kept(b.plane, P[idx[q]]) && kept(b.plane2, P[idx[q]]) ? 0 : 1;
    }
    return n;
}

/// A saddle corner of the ball (c, r) (build.hpp, step 4) with the three faces `side` (unit face
/// normals m, fits f, labels `label` 0/1/2 of idx), whose face o (`saddle_face`) covers more than
/// half the turn about the corner. With j, k the other faces, the plane between
/// them (p_jk, positive on j's side) also splits o into its part beside j and its part beside k;
/// the planes p_oj and p_ok between those parts and j and k end o at its edges. FOUR records:
/// o on (p_oj, p_jk), o on (p_ok, -p_jk), j on (-p_oj, p_jk), k on (-p_ok, -p_jk). (On the saddle
/// y <= 0 and (x <= 0 or z <= 0), o is y = 0; its two records are its parts x <= 0 and z <= 0
/// either side of the bisector x = z.) Accepted as the triple is (misclassified points, support).
bool attempt_saddle(const Context& cx, const Vec3d& c, double r, const std::vector<std::uint32_t>& idx, const std::vector<std::uint32_t> (&side)[3],
                    const Vec3d (&m)[3], const LocalFit (&f)[3], const std::vector<unsigned char>& label, int o, SeedResult& out) {
    const auto& P = cx.pts.positions;
    const int j = (o + 1) % 3, k = (o + 2) % 3;
    std::size_t err = 0;
    const Vec4d p_jk = edge_plane(P, side[j], side[k], m[j], m[k], f[j], f[k], c, r, err);
    std::vector<std::uint32_t> oj, ok;
    for (const std::uint32_t p : side[o]) (kept(p_jk, P[p]) ? oj : ok).push_back(p);
    if (oj.size() < small_pair_min_face || ok.size() < small_pair_min_face) return false;
    const Vec4d p_oj = edge_plane(P, oj, side[j], m[o], m[j], f[o], f[j], c, r, err);
    const Vec4d p_ok = edge_plane(P, ok, side[k], m[o], m[k], f[o], f[k], c, r, err);
    const Record recs[4] = {corner_record(f[o], c, r, p_oj, p_jk), corner_record(f[o], c, r, p_ok, -p_jk), corner_record(f[j], c, r, -p_oj, p_jk),
                            corner_record(f[k], c, r, -p_ok, -p_jk)};
    // Each point's record.
    std::vector<unsigned char> rec_of(idx.size());
    for (std::size_t q = 0; q < idx.size(); ++q)
        rec_of[q] = label[q] == o ? (kept(p_jk, P[idx[q]]) ? 0 : 1) : (label[q] == j ? 2 : 3);
    if (double(misplaced(P, idx, recs, rec_of)) > cx.opt.sharp_max_misclassified * double(idx.size())) return false;
    if (!corner_supported(cx, c, r, idx.size(), recs)) return false;
    out.records.assign(std::begin(recs), std::end(recs));
    out.side = std::move(rec_of);
    return true;
}

/// The corner of the ball (c, r) (build.hpp, step 4): three faces, each its own record clipped by
/// the two planes that separate its cluster from the other two, or at a saddle (`saddle_face`)
/// four records (`attempt_saddle`). On success `out` holds the records and the points' sides;
/// otherwise `out` is unchanged.
bool attempt_corner(const Context& cx, const Vec3d& c, double r, const std::vector<std::uint32_t>& idx, SeedResult& out) {
    const auto& P = cx.pts.positions;
    const auto& N = cx.pts.normals;
    std::vector<unsigned char> label;
    Vec3d m[3];
    three_means(N, idx, label, m);
    // Three clusters, each pair of means farther apart than the sharp angle, each large enough.
    const double cos_max = std::cos(cx.opt.sharp_angle_degrees * std::numbers::pi / 180);
    for (int i = 0; i < 3; ++i)
        if (!(dot(m[i], m[(i + 1) % 3]) < cos_max)) return false;
    std::vector<std::uint32_t> side[3];
    for (std::size_t k = 0; k < idx.size(); ++k) side[label[k]].push_back(idx[k]);
    const std::size_t need = std::max(cx.opt.min_points, std::size_t(std::ceil(cx.opt.sharp_min_fraction * double(idx.size()))));
    for (const std::vector<std::uint32_t>& sd : side)
        if (sd.size() < need) return false;
    // No cluster may split again, however few points the split-off part holds (four faces in three
    // clusters: one quadric would draw two of them, as the plane pair x y = 0, or bend to reach a
    // fourth face's few points, and the planes, tilted by the merged cluster's mean, would not end
    // the faces at their edges; a smaller ball is tried instead).
    for (const std::vector<std::uint32_t>& sd : side)
        if (splits_again(N, sd, cos_max, corner_min_split)) return false;
    for (int i = 0; i < 3; ++i) m[i] = face_normal(N, side[i], m[i], cos_max);
    out.fits += 3;
    LocalFit f[3];
    for (int i = 0; i < 3; ++i) {
        f[i] = fit_ball(P, N, side[i], c, r, cx.opt.fit);
        if (!(f[i].solved && f[i].oriented && f[i].max_distance <= cx.threshold)) return false;
    }
    // A saddle: four records (`attempt_saddle`; its 270-degree face would lose a quadrant to a
    // wedge, which the misplaced-points test below may not see where few points lie there).
    if (cx.opt.saddle_corners) {
        const int o = saddle_face(P, side, m);
        if (o >= 0) return attempt_saddle(cx, c, r, idx, side, m, f, label, o, out);
    }
    // One plane per two clusters (positive on the first's side); cluster i keeps the side of its
    // own of both of its planes. So no two records draw the same point; they leave no gap where
    // the three planes meet in a line (as the bisectors of three planar faces do).
    Vec4d planes[3][2];
    for (int i = 0; i < 3; ++i) {
        const int j = (i + 1) % 3;
        std::size_t err = 0;
        const Vec4d pl = edge_plane(P, side[i], side[j], m[i], m[j], f[i], f[j], c, r, err);
        planes[i][0] = pl;
        planes[j][1] = -pl;
    }
    const Record recs[3] = {corner_record(f[0], c, r, planes[0][0], planes[0][1]), corner_record(f[1], c, r, planes[1][0], planes[1][1]),
                            corner_record(f[2], c, r, planes[2][0], planes[2][1])};
    // Points outside their own cluster's wedge.
    if (double(misplaced(P, idx, recs, label)) > cx.opt.sharp_max_misclassified * double(idx.size())) return false;
    if (!corner_supported(cx, c, r, idx.size(), recs)) return false;
    out.records.assign(std::begin(recs), std::end(recs));
    out.side = label;
    return true;
}

/// Tries the ball (c, r) of `points`: a single quadric, else a sharp pair, else (support check on)
/// a plane: the fit with its quadratic coefficients held near 0 (planar_regularization). In a ball of
/// few points the quadratic coefficients are barely determined and the quadric often turns back
/// into the ball as a second sheet crossing the points with the opposite orientation, which the
/// support check rejects; the plane has no second sheet and is accepted where it is within E.
bool attempt(const Context& cx, const Vec3d& c, double r, const std::vector<std::uint32_t>& idx, SeedResult& out) {
    if (attempt_quadrics(cx, c, r, idx, out)) return true;
    if (!cx.opt.support_check) return false;
    FitOptions planar = cx.opt.fit;
    planar.regularization = planar_regularization;
    ++out.fits;
    const LocalFit plane = fit_ball(cx.pts.positions, cx.pts.normals, idx, c, r, planar);
    if (!(plane.solved && plane.oriented && plane.max_distance <= cx.threshold) || rounds_crease(cx, idx, r, plane)) return false;
    const double t = support_fraction(cx, plane.local, c, r, {}, idx.size(), cx.opt.min_support_fraction);
    if (t < cx.opt.min_support_fraction) return false;
    out.records.assign(1, make_record(plane, c, r, kept_fraction(t)));
    out.side.assign(idx.size(), 0);
    return true;
}

/// The plane of a few points (too few for `fit_ball`): through their centroid, normal to their
/// mean normal, in local coordinates of the ball (c, r) (f(u) = m . u + m . (c - centroid) / r);
/// its distances (to the plane) and orientation as `fit_ball` measures them.
LocalFit small_plane(const Context& cx, const std::vector<std::uint32_t>& pts, const Vec3d& c, double r) {
    LocalFit f;
    Vec3d mean = vec3(0.0, 0.0, 0.0), centroid = mean;
    for (const std::uint32_t i : pts) {
        mean = mean + cx.pts.normals[i];
        centroid = centroid + cx.pts.positions[i];
    }
    if (pts.empty() || !(length(mean) > 0)) return f;
    const Vec3d m = normalize(mean);
    centroid = centroid * (1.0 / double(pts.size()));
    f.solved = true;
    f.oriented = true;
    f.min_normal_cos = 1;
    for (const std::uint32_t i : pts) {
        f.max_distance = std::max(f.max_distance, std::fabs(dot(m, cx.pts.positions[i] - centroid)));
        f.oriented = f.oriented && dot(m, cx.pts.normals[i]) > 0;
        f.min_normal_cos = std::min(f.min_normal_cos, dot(m, cx.pts.normals[i]));
    }
    Coefficients10<double> k{};
    k.k000 = dot(m, c - centroid) / r;
    k.k100 = m[0];
    k.k010 = m[1];
    k.k001 = m[2];
    f.local = quadric_from_coefficients(k);
    return f;
}

/// The sharp pair of a ball too small for `attempt_pair` (the min_points ball of a seed on a
/// crease, whose two faces hold a few points each; build.hpp, step 5): two planes (`small_plane`,
/// or the fit with its quadratic coefficients held near 0 where a face has enough points for it),
/// each within E of its points and its normal within crease_normal_degrees of theirs, the plane
/// between them (`edge_plane`) putting no point on the wrong side.
bool attempt_small_pair(const Context& cx, const Vec3d& c, double r, const std::vector<std::uint32_t>& idx, SeedResult& out) {
    const auto& P = cx.pts.positions;
    const auto& N = cx.pts.normals;
    std::vector<unsigned char> label;
    Vec3d m0{}, m1{};
    std::vector<std::uint32_t> side[2];
    const double cos_max = std::cos(cx.opt.sharp_angle_degrees * std::numbers::pi / 180);
    if (!sharp_split(N, idx, cos_max, label, m0, m1, side)) return false;
    LocalFit f[2];
    for (int i = 0; i < 2; ++i) {
        if (side[i].size() < small_pair_min_face || splits_again(N, side[i], cos_max, corner_min_split)) return false;
        if (side[i].size() >= min_fit_points) {
            FitOptions planar = cx.opt.fit;
            planar.regularization = planar_regularization;
            f[i] = fit_ball(P, N, side[i], c, r, planar);
        } else {
            f[i] = small_plane(cx, side[i], c, r);
        }
        ++out.fits;
        if (!(f[i].solved && f[i].oriented && f[i].max_distance <= cx.threshold &&
              f[i].min_normal_cos >= std::cos(cx.opt.crease_normal_degrees * std::numbers::pi / 180)))
            return false;
    }
    std::size_t err = 0;
    const Vec4d plane0 = edge_plane(P, side[0], side[1], m0, m1, f[0], f[1], c, r, err);
    if (err > 0) return false;
    return commit_pair(cx, c, r, idx, f[0], f[1], plane0, label, out);
}

/// The ball of one seed (see build.hpp, step 3).
SeedResult grow_ball(const Context& cx, std::uint32_t seed) {
    const Vec3d c = cx.pts.positions[seed];
    std::vector<std::uint32_t> idx;
    // The radius holding min_points points.
    double r = cx.opt.initial_radius * cx.diagonal;
    cx.grid.query(c, r, idx);
    while (idx.size() < cx.opt.min_points) {
        // (Terminates: at the diagonal the ball holds every point, and there are >= min_points.)
        r = std::min(r * 2, 2 * cx.diagonal);
        cx.grid.query(c, r, idx);
    }
    std::vector<double> d2(idx.size());
    for (std::size_t k = 0; k < idx.size(); ++k) d2[k] = dot(cx.pts.positions[idx[k]] - c, cx.pts.positions[idx[k]] - c);
    std::nth_element(d2.begin(), d2.begin() + long(cx.opt.min_points - 1), d2.end());
    // (At least 1e-9 diagonals: min_points copies of the seed would make it 0.)
    const double r_min = std::max(std::sqrt(d2[cx.opt.min_points - 1]) * (1 + 1e-12), 1e-9 * cx.diagonal);
    const double r_max = std::max(r_min, cx.opt.max_radius * cx.diagonal);
    // Start at most 8 times the min_points radius: a far outlier makes the diagonal (and so the
    // initial radius) huge, and shrinking from there would take hundreds of fits per seed.
    r = std::clamp(std::min(cx.opt.initial_radius * cx.diagonal, 8 * r_min), r_min, r_max);

    SeedResult best, cur;
    std::size_t fits = 0;
    const auto run = [&](double radius) {
        cx.grid.query(c, radius, idx);
        const bool ok = attempt(cx, c, radius, idx, cur);
        fits += cur.fits;
        cur.fits = 0;
        return ok;
    };
    // (The largest accepted fitting ball wins, even where the support check trims it to draw less
    // than a smaller one would: choosing by the drawn radius measured worse, with pinholes at
    // fandisk's corners and wider seams on the bunny, tests/slim/against_mesh.cpp.)
    double lo = 0, hi = 0;  // largest accepted, smallest rejected radius
    if (run(r)) {
        best = cur;
        lo = r;
        while (lo < r_max) {
            const double next = std::min(lo * 1.5, r_max);
            if (run(next)) { best = cur; lo = next; }
            else { hi = next; break; }
        }
    } else {
        hi = r;
        SeedResult first = cur;
        while (hi > r_min) {
            const double next = std::max(hi * 0.6, r_min);
            if (run(next)) { best = cur; lo = next; break; }
            hi = next;
            if (next == r_min) first = cur;
        }
        if (lo == 0 && cx.opt.sharp_features && attempt_small_pair(cx, c, first.radius, first.points, first)) {
            first.fits += fits;
            return first;
        }
        if (lo == 0) {
            // Even the smallest ball is rejected: keep its single quadric (forced) where the
            // support check accepts it, else the seed's tangent plane (f = n . u in the ball),
            // drawn only as far as the check accepts it: a quadric fitted to the fewest points
            // often has a second sheet or a fold in its ball, and the tangent plane of a seed
            // near a crease runs past it; the renderers would draw either as a flake.
            best = first;
            if (best.records.size() > 1) best.records.resize(1);
            if (cx.opt.support_check) {
                const std::size_t m = best.points.size();
                double t = best.records.empty() ? 0.0 : support_fraction(cx, best.records[0].local, c, best.radius, {}, m, cx.opt.min_support_fraction);
                if (t >= cx.opt.min_support_fraction) {
                    const LocalFit fit{true, best.records[0].local};
                    best.records.assign(1, make_record(fit, c, best.radius, kept_fraction(t)));
                } else {
                    const Vec3d n = cx.pts.normals[seed];
                    Coefficients10<double> k{};
                    k.k100 = n[0];
                    k.k010 = n[1];
                    k.k001 = n[2];
                    LocalFit plane;
                    plane.local = quadric_from_coefficients(k);
                    // At least a quarter of the ball: the plane passes through the seed, with its
                    // normal, and a seed on a crease fails the boundary test at the centre.
                    t = support_fraction(cx, plane.local, c, best.radius, {}, m, 0.0);
                    best.records.assign(1, make_record(plane, c, best.radius, std::max(kept_fraction(t), 0.25)));
                }
            }
            best.side.assign(best.points.size(), 0);
            best.forced = true;
            best.fits = fits;
            return best;
        }
    }
    // Two bisection steps between lo (accepted) and hi (rejected).
    for (int step = 0; step < 2 && hi > 0; ++step) {
        const double mid = std::sqrt(lo * hi);
        if (run(mid)) { best = cur; lo = mid; }
        else hi = mid;
    }
    best.fits = fits;
    return best;
}

std::vector<std::uint32_t> seed_order(std::size_t n, std::uint64_t seed) {
    std::vector<std::uint32_t> p(n);
    for (std::size_t i = 0; i < n; ++i) p[i] = std::uint32_t(i);
    std::mt19937_64 rng(seed);
    for (std::size_t i = n; i > 1; --i) {
        const std::size_t j = std::size_t(double(rng() >> 11) * 0x1.0p-53 * double(i));
        std::swap(p[i - 1], p[std::min(j, i - 1)]);
    }
    return p;
}

[[noreturn]] void bad_option(const std::string& what) { throw std::invalid_argument("quadcast::slim::build: " + what); }

}  // namespace

BuildResult build(const OrientedPoints& points, const BuildOptions& options) {
    const auto t0 = std::chrono::steady_clock::now();
    const auto num = [](double x) { return std::to_string(x); };
    if (!(options.error > 0) || !std::isfinite(options.error)) bad_option("error must be positive and finite (got " + num(options.error) + ")");
    if (!(options.cover_fraction > 0 && options.cover_fraction <= 1)) bad_option("cover_fraction must be in (0, 1]");
    if (!(options.initial_radius > 0) || !(options.max_radius >= options.initial_radius)) bad_option("need 0 < initial_radius <= max_radius");
    if (!(options.support_normal_cos >= -1 && options.support_normal_cos < 1))
        bad_option("support_normal_cos must be in [-1, 1) (got " + num(options.support_normal_cos) + ")");
    if (!(options.min_support_fraction > 0 && options.min_support_fraction <= 1))
        bad_option("min_support_fraction must be in (0, 1] (got " + num(options.min_support_fraction) + ")");
    if (options.support_max_lines < 13 || options.support_max_lines > 201)
        bad_option("support_max_lines must be in [13, 201] (got " + std::to_string(options.support_max_lines) + ")");
    if (!(options.support_max_gap_degrees > 0 && options.support_max_gap_degrees <= 360))
        bad_option("support_max_gap_degrees must be in (0, 360] (got " + num(options.support_max_gap_degrees) + ")");
    if (options.min_points < min_fit_points) bad_option("min_points must be at least " + std::to_string(min_fit_points));
    if (points.size() < options.min_points)
        bad_option(points.file + ": " + std::to_string(points.size()) + " points; a ball needs at least " + std::to_string(options.min_points));
    if (points.size() > std::numeric_limits<std::uint32_t>::max() / 2) bad_option("too many points");

    // Bounding box, E, grid.
    Vec3d lo = points.positions[0], hi = lo;
    for (const Vec3d& p : points.positions)
        for (int k = 0; k < 3; ++k) { lo[k] = std::min(lo[k], p[k]); hi[k] = std::max(hi[k], p[k]); }
    BuildResult res;
    BuildStats& st = res.stats;
    st.points = points.size();
    st.diagonal = length(hi - lo);
    if (!(st.diagonal > 0)) bad_option(points.file + ": all points coincide");
    if (!std::isfinite(st.diagonal)) bad_option(points.file + ": the bounding box's diagonal overflows (coordinates too large)");
    st.threshold = options.error * st.diagonal;
    const PointGrid grid(points.positions, lo, hi);
    const Context cx{points, options, grid, st.diagonal, st.threshold};

    const std::uint32_t none = std::numeric_limits<std::uint32_t>::max();
    res.covered_by.assign(points.size(), none);
    std::vector<Quadric<double>> locals;
    const std::vector<std::uint32_t> order = seed_order(points.size(), options.seed);
    std::size_t cursor = 0, covered = 0;
    tbb::task_arena arena(options.threads > 0 ? options.threads : tbb::task_arena::automatic);
    const std::size_t batch_size = std::size_t(std::max(1, arena.max_concurrency())) * 4;
    std::vector<std::uint32_t> batch;
    std::vector<SeedResult> results;
    while (covered < points.size()) {
        // The next uncovered seeds, in order.
        batch.clear();
        while (cursor < order.size() && batch.size() < batch_size) {
            if (res.covered_by[order[cursor]] == none) batch.push_back(order[cursor]);
            ++cursor;
        }
        if (batch.empty()) break;
        results.assign(batch.size(), SeedResult{});
        arena.execute([&] {
            tbb::parallel_for(std::size_t(0), batch.size(), [&](std::size_t k) { results[k] = grow_ball(cx, batch[k]); });
        });
        // Commit in seed order.
        for (std::size_t k = 0; k < batch.size(); ++k) {
            SeedResult& r = results[k];
            st.fits += r.fits;
            if (res.covered_by[batch[k]] != none) { ++st.dropped_seeds; continue; }
            const std::uint32_t first = std::uint32_t(res.model.balls.size());
            if (r.records.empty()) {
                // No fit at all (degenerate points): the seed alone is marked, by no record.
                res.covered_by[batch[k]] = none - 1;
                ++covered;
                continue;
            }
            for (Record& rec : r.records) {
                res.model.balls.push_back(rec.ball);
                res.forced.push_back(r.forced ? 1 : 0);
                locals.push_back(rec.local);
            }
            if (r.records.size() == 2) ++st.sharp_pairs;
            if (r.records.size() >= 3) ++st.corners;
            if (r.records.size() == 4) ++st.saddles;
            if (r.forced) ++st.forced;
            const Vec3d c = points.positions[batch[k]];
            for (std::size_t j = 0; j < r.points.size(); ++j) {
                const std::uint32_t i = r.points[j];
                const std::uint32_t side = r.side[j] < r.records.size() ? r.side[j] : 0;
                // Within cover_fraction of the record's drawn radius (less than the fitting ball's
                // where the support check trimmed it).
                const double rc = options.cover_fraction * r.records[side].ball.radius;
                const Vec3d d = points.positions[i] - c;
                if ((dot(d, d) <= rc * rc || i == batch[k]) && res.covered_by[i] == none) {
                    res.covered_by[i] = first + side;
                    ++covered;
                }
            }
        }
        if (options.progress) options.progress(BuildProgress{covered, points.size(), res.model.balls.size()});
    }
    st.balls = res.model.balls.size();

    // Every record checked once more on lines twice as dense (at least 31 per side): a sliver of
    // zero set narrower than the fits' lines (a piece of a second sheet at a ball's rim, drawn as a
    // speck off the surface) is cut off the same way, but never below half the drawn radius.
    if (options.support_check) {
        arena.execute([&] {
            tbb::parallel_for(std::size_t(0), res.model.balls.size(), [&](std::size_t i) {
                Ball& ball = res.model.balls[i];
                std::vector<std::uint32_t> in;
                grid.query(ball.center, ball.radius, in);
                const Vec4d planes[2] = {ball.plane, ball.plane2};
                const std::size_t n_planes = ball.has_plane ? (ball.has_plane2 ? 2 : 1) : 0;
                const double t = support_fraction(cx, locals[i], ball.center, ball.radius, std::span<const Vec4d>(planes, n_planes), in.size(), 0.0, 31, 6);
                if (t >= 1) return;
                ball.radius *= std::max(kept_fraction(t), 0.5);
                locals[i] = world_to_local(ball.q, ball.center, ball.radius);
            });
        });
    }

    // Distances of the input points to their covering record's surface.
    double sum2 = 0;
    for (std::size_t i = 0; i < points.size(); ++i) {
        const std::uint32_t b = res.covered_by[i];
        double d = std::numeric_limits<double>::infinity();
        if (b < locals.size()) {
            const Ball& ball = res.model.balls[b];
            const Vec3d u = (points.positions[i] - ball.center) * (1 / ball.radius);
            d = gradient_line_distance(locals[b], u) * ball.radius;
            // A forced ball's gradient line may miss its surface: then the first-order distance.
            if (std::isinf(d)) d = std::fabs(evaluate(locals[b], u)) / length(gradient(locals[b], u)) * ball.radius;
        }
        if (d > st.threshold) ++st.over_threshold;
        st.max_distance = std::max(st.max_distance, d);
        sum2 += d * d;
    }
    st.rms_distance = std::sqrt(sum2 / double(points.size()));
    st.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return res;
}

}  // namespace quadcast::slim
