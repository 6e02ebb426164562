// tests/slim/corner.cpp -- corner triples against the exact geometry of a box, saddle corners against an L-shaped solid: their planes on the edges, blended normals and hits, coverage
#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <string>
#include <tuple>
#include <vector>

#include "quadcast/render/slim_cpu_renderer.hpp"
#include "quadcast/scene/scene_render.hpp"
#include "quadcast/slim/build.hpp"
#include "quadcast/slim/scene_loader.hpp"
#include "slim/against_mesh.hpp"
#include "slim/slim_testing.hpp"

using namespace quadcast;
using namespace quadcast::slim;
using namespace quadcast::slim::testing;

// The reference is the box [-H, H] itself, not SLIM code: its faces, edges and corners in closed
// form, and the first hit of a ray by the slab method in long double. Two boxes: the cube [-1, 1]^3,
// and [-1, 1] x [-0.7, 0.7] x [-0.5, 0.5] (no two faces alike, and thinner than the builder's
// largest balls: max_radius = 0.25 diagonals = 0.66, so a ball can hold four faces).

namespace {

using L = long double;

double seconds_since(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

/// The first hit of o + t d (t > 0) with the box (slab method): the face's axis, the point and
/// the outward face normal; false when the ray misses it.
struct BoxHit {
    bool hit = false;
    int axis = -1;
    V3L x, n;
};

BoxHit box_hit(const V3L& o, const V3L& d, const Vec3d& H) {
    BoxHit r;
    L t0 = -std::numeric_limits<L>::infinity(), t1 = std::numeric_limits<L>::infinity();
    int axis = -1;
    for (int a = 0; a < 3; ++a) {
        if (d[a] == 0) {
            if (std::fabs(o[a]) > L(H[a])) return r;
            continue;
        }
        L ta = (-L(H[a]) - o[a]) / d[a], tb = (L(H[a]) - o[a]) / d[a];
        if (ta > tb) std::swap(ta, tb);
        if (ta > t0) t0 = ta, axis = a;
        t1 = std::min(t1, tb);
    }
    if (axis < 0 || !(t0 <= t1) || !(t0 > 0)) return r;
    r.hit = true;
    r.axis = axis;
    r.x = o + d * t0;
    r.n = vec3(0.0L, 0.0L, 0.0L);
    r.n[axis] = r.x[axis] > 0 ? 1 : -1;
    return r;
}

/// Distance from a point x of the face with normal axis `axis` to the nearest edge of the box.
L edge_distance(const V3L& x, int axis, const Vec3d& H) {
    L d = std::numeric_limits<L>::infinity();
    for (int b = 0; b < 3; ++b)
        if (b != axis) d = std::min(d, L(H[b]) - std::fabs(x[b]));
    return d;
}

/// Distance from a point of the box's surface to the nearest corner.
L corner_distance(const V3L& x, const Vec3d& H) {
    L s = 0;
    for (int a = 0; a < 3; ++a) s += (L(H[a]) - std::fabs(x[a])) * (L(H[a]) - std::fabs(x[a]));
    return std::sqrt(s);
}

/// Distance from any point to the box's surface.
L box_surface_distance(const V3L& x, const Vec3d& H) {
    L out = 0, in = -std::numeric_limits<L>::infinity();
    for (int a = 0; a < 3; ++a) {
        const L q = std::fabs(x[a]) - L(H[a]);
        out += std::max(q, L(0)) * std::max(q, L(0));
        in = std::max(in, q);
    }
    return in > 0 ? std::sqrt(out) : -in;
}

double angle_deg(const V3L& a, const V3L& b) {
    const L c = dot(a, b) / std::sqrt(dot(a, a) * dot(b, b));
    return double(std::acos(std::clamp(c, -1.0L, 1.0L)) * 180.0L / 3.14159265358979323846L);
}

/// A box and its SLIM surface: about 45000 samples (point spacing h about 2.2 E) built at error
/// 3e-3 with default options otherwise; built once per run.
struct BoxModel {
    std::string name;
    Vec3d half;
    OrientedPoints points;
    BuildResult result;
    double seconds = 0;
};

/// `which` 0: the cube, 1: the thin box; `corners` false: built as before corner triples and the
/// crease test (BuildOptions::corners off, crease_normal_degrees 180).
const BoxModel& box_model(int which, bool corners = true) {
    static const auto make = [](const char* name, const Vec3d& H, double h, bool with_corners) {
        BoxModel b;
        b.name = name;
        b.half = H;
        b.points = box_points(H, h, 11);
        BuildOptions o;
        o.error = 3e-3;
        o.threads = 0;
        o.corners = with_corners;
        if (!with_corners) o.crease_normal_degrees = 180;  // the builder before corner triples
        const auto t0 = std::chrono::steady_clock::now();
        b.result = build(b.points, o);
        b.seconds = seconds_since(t0);
        return b;
    };
    if (which == 0 && !corners) {
        static const BoxModel cube = make("cube [-1, 1]^3 without corner triples and the crease test", vec3(1.0, 1.0, 1.0), 0.023, false);
        return cube;
    }
    if (which == 0) {
        static const BoxModel cube = make("cube [-1, 1]^3", vec3(1.0, 1.0, 1.0), 0.023, true);
        return cube;
    }
    static const BoxModel box = make("box [-1, 1] x [-0.7, 0.7] x [-0.5, 0.5]", vec3(1.0, 0.7, 0.5), 0.0176, true);
    return box;
}

/// The outward normal of face f (0..5: -x, +x, -y, +y, -z, +z).
V3L face_normal(int f) {
    V3L n = vec3(0.0L, 0.0L, 0.0L);
    n[f / 2] = f % 2 ? 1 : -1;
    return n;
}

/// The face of a sample by its exact normal.
int face_of(const Vec3d& n) {
    for (int a = 0; a < 3; ++a)
        if (n[a] != 0) return 2 * a + (n[a] > 0);
    return -1;
}

/// The largest |plane(x)| over the box edge of faces f and g (adjacent) where it lies in the ball
/// (c, r), or at its point nearest to c when the ball misses it (a linear function: its largest
/// value on a segment is at an end).
L offset_on_edge(const Vec<double, 4>& p, int f, int g, const Vec3d& H, const Vec3d& c, double r) {
    const int a = f / 2, b = g / 2, e = 3 - a - b;
    V3L x0 = vec3(0.0L, 0.0L, 0.0L), dir = vec3(0.0L, 0.0L, 0.0L);
    x0[a] = f % 2 ? L(H[a]) : -L(H[a]);
    x0[b] = g % 2 ? L(H[b]) : -L(H[b]);
    dir[e] = 1;
    const V3L cl = to_long(c);
    const L along = cl[e], d2 = dot(cl - x0, cl - x0) - along * along, rr = L(r) * L(r) - d2;
    const L half = rr > 0 ? std::sqrt(rr) : 0;
    const L t0 = std::clamp(along - half, -L(H[e]), L(H[e])), t1 = std::clamp(along + half, -L(H[e]), L(H[e]));
    L worst = 0;
    for (const L t : {t0, t1}) {
        const V3L x = x0 + dir * t;
        worst = std::max(worst, std::fabs(L(p[0]) * x[0] + L(p[1]) * x[1] + L(p[2]) * x[2] + L(p[3])));
    }
    return worst;
}

}  // namespace

TEST_CASE("corner triples of boxes: every corner gets one, each record's two planes bisect its faces on their true edges, every point within E") {
    for (int which = 0; which < 2; ++which) {
        const BoxModel& m = box_model(which);
        CAPTURE(m.name);
        const BuildResult& r = m.result;
        const BuildStats& st = r.stats;
        const Vec3d& H = m.half;
        const double E = st.threshold;
        MESSAGE(m.name << ": " << m.points.size() << " points, E = " << E << ", built in " << m.seconds << " s: " << st.balls << " records, " << st.sharp_pairs
                       << " sharp pairs, " << st.corners << " corner triples, " << st.forced << " forced; max distance " << st.max_distance / E << " E, "
                       << st.over_threshold << " points over E");
        // As the build tests (tests/slim/build.cpp, check_surface): every input point within E of
        // its covering record. No forced balls (before the clusters' face normals, `face_normal`
        // in src/slim/build.cpp, the thin box had 1, 2.4 E wide, beside a corner).
        CHECK(st.over_threshold == 0);
        CHECK(st.max_distance <= E);
        CHECK(st.forced == 0);
        for (std::size_t i = 0; i < r.forced.size(); ++i)
            if (r.forced[i]) {
                const Ball& b = r.model.balls[i];
                MESSAGE("forced record at (" << b.center[0] << ", " << b.center[1] << ", " << b.center[2] << "), radius " << b.radius / E << " E");
            }
        // Every corner of the box has a triple.
        CHECK(st.corners >= 8);

        // The faces of the points each record covers (its own face: all of them one face).
        std::vector<std::array<int, 6>> covered_faces(r.model.balls.size());
        for (std::size_t i = 0; i < m.points.size(); ++i) ++covered_faces[r.covered_by[i]][std::size_t(face_of(m.points.normals[i]))];
        // The triples: three consecutive records with two planes and one centre (build.cpp commits
        // a seed's records together). Per triple, the faces with points in its ball (the largest of
        // the three drawn radii): a corner's three, or (the thin box) two opposite faces and one
        // between them, or four.
        std::array<int, 8> per_corner{};
        std::size_t triples = 0, corner_kind = 0, opposite_kind = 0, four_kind = 0;
        double worst_norm = 0, worst_angle = 0;
        L worst_offset = 0, worst_mid = 0;
        bool consistent = true;
        for (std::size_t i = 0; i < r.model.balls.size(); ++i) {
            if (!r.model.balls[i].has_plane2) continue;
            REQUIRE(i + 2 < r.model.balls.size());
            const Ball* t[3] = {&r.model.balls[i], &r.model.balls[i + 1], &r.model.balls[i + 2]};
            CHECK(t[1]->has_plane2);
            CHECK(t[2]->has_plane2);
            CHECK(length(t[1]->center - t[0]->center) == 0.0);
            CHECK(length(t[2]->center - t[0]->center) == 0.0);
            ++triples;
            const Vec3d c = t[0]->center;
            const double radius = std::max({t[0]->radius, t[1]->radius, t[2]->radius});
            std::array<int, 6> in{};
            for (std::size_t k = 0; k < m.points.size(); ++k)
                if (length(m.points.positions[k] - c) <= radius) ++in[std::size_t(face_of(m.points.normals[k]))];
            int present = 0;
            bool opposite = false;
            for (int f = 0; f < 6; ++f) {
                present += in[std::size_t(f)] > 0;
                opposite = opposite || (f % 2 == 0 && in[std::size_t(f)] > 0 && in[std::size_t(f + 1)] > 0);
            }
            if (present > 3) ++four_kind;
            else if (opposite) ++opposite_kind;
            else {
                ++corner_kind;
                int ci = 0;
                Vec3d K;
                for (int a = 0; a < 3; ++a) {
                    K[a] = in[std::size_t(2 * a + 1)] > 0 ? H[a] : -H[a];
                    ci |= in[std::size_t(2 * a + 1)] > 0 ? 1 << a : 0;
                }
                if (length(K - c) < radius) ++per_corner[std::size_t(ci)];
            }
            // Each record: its own face (that of the points it covers); each plane bisects the
            // dihedral angle of the own face and another face in the ball (normal (n_own -
            // n_other) / |n_own - n_other|, the best matching other face), different for the two
            // planes; and passes through their edge (adjacent faces: within the ball) or, between
            // opposite faces, is their mid-plane (through the box's centre).
            for (int k = 0; k < 3; ++k) {
                const Ball& b = *t[k];
                const std::array<int, 6>& cf = covered_faces[i + std::size_t(k)];
                const int own = int(std::max_element(cf.begin(), cf.end()) - cf.begin());
                if (cf[std::size_t(own)] == 0) continue;
                int n_faces = 0;
                for (const int n : cf) n_faces += n > 0;
                consistent = consistent && n_faces == 1;
                int other[2] = {-1, -1};
                const Vec<double, 4> planes[2] = {b.plane, b.plane2};
                for (int j = 0; j < 2; ++j) {
                    const Vec<double, 4>& p = planes[j];
                    const V3L pn = vec3(L(p[0]), L(p[1]), L(p[2]));
                    worst_norm = std::max(worst_norm, std::fabs(double(std::sqrt(dot(pn, pn))) - 1.0));
                    double best = 180;
                    for (int f = 0; f < 6; ++f) {
                        if (f == own || in[std::size_t(f)] == 0) continue;
                        const double a = angle_deg(pn, face_normal(own) - face_normal(f));
                        if (a < best) best = a, other[j] = f;
                    }
                    worst_angle = std::max(worst_angle, best);
                    if (other[j] < 0) continue;
                    if (other[j] / 2 != own / 2) worst_offset = std::max(worst_offset, offset_on_edge(p, own, other[j], H, c, b.radius));
                    else worst_mid = std::max(worst_mid, std::fabs(L(p[3])));
                }
                CHECK(other[0] != other[1]);
            }
            i += 2;
        }
        MESSAGE(triples << " triples: " << corner_kind << " at a corner (per corner " << per_corner[0] << " " << per_corner[1] << " " << per_corner[2] << " "
                        << per_corner[3] << " " << per_corner[4] << " " << per_corner[5] << " " << per_corner[6] << " " << per_corner[7] << "), " << opposite_kind
                        << " holding two opposite faces and one between, " << four_kind << " holding four faces; planes: |1 - |n|| at most " << worst_norm
                        << ", angle to the bisector at most " << worst_angle << " deg, at most " << double(worst_offset / E)
                        << " E from the edges in the ball (mid-planes " << double(worst_mid / E) << " E)");
        CHECK(triples == st.corners);
        for (int k = 0; k < 8; ++k) {
            CAPTURE(k);
            CHECK(per_corner[std::size_t(k)] >= 1);
        }
        CHECK(consistent);  // every record covers points of one face only
        CHECK(worst_norm < 1e-9);
        // The builder's planes bisect the clusters' mean normals: exact normals give the exact
        // bisector where every cluster is one face (measured on the cube: 0 deg). On the thin box a
        // ball holding four faces puts two of them in one cluster (fitted by one quadric, a plane
        // pair) and its planes tilt (measured 5.8 deg, 6.6 E off the edges).
        CHECK(worst_angle < 0.5);
        // Their offsets: the midpoint between the two clusters' nearest points along the normal,
        // within about h / (2 sqrt 2) = 0.8 E of the edge with these samples (h = 2.2 E; measured
        // on the cube 0.08 E).
        CHECK(worst_offset <= 1.0L * L(E));
        CHECK(worst_mid <= 1.0L * L(E));

        // What the renderers draw of a corner triple's records: their zero sets in their balls on
        // the kept side of both planes (`zero_set_samples`: long double roots on 31 x 31 x 3 lines
        // per ball), against the box's surface. Measured on the cube: 5e-12 E (planes).
        L worst_corner = 0;
        long corner_samples = 0;
        for (const Ball& b : r.model.balls)
            if (b.has_plane2)
                zero_set_samples(b, 31, [&](const V3L& x) {
                    worst_corner = std::max(worst_corner, box_surface_distance(x, H));
                    ++corner_samples;
                });
        MESSAGE("zero sets of the corner triples' records: " << corner_samples << " samples, the farthest " << double(worst_corner / E) << " E from the box");
        CHECK(corner_samples > 100 * long(3 * triples));
        CHECK(worst_corner <= 1.0L * L(E));
    }
}

TEST_CASE("no fins at a box's edges and corners: every record's zero set lies within E of the box") {
    // As the l_prism test (tests/slim/against_mesh.cpp, its bound 3 E), against the exact box: the
    // zero set of every record (single, sharp pair, corner triple) in its ball on the kept side of
    // its planes, by long double roots on 31 x 31 x 3 lines per ball.
    for (int which = 0; which < 2; ++which) {
        const BoxModel& m = box_model(which);
        CAPTURE(m.name);
        const BuildResult& r = m.result;
        const double E = r.stats.threshold;
        L worst = 0;
        long samples = 0, beyond_3e = 0;
        V3L worst_at{};
        const Ball* worst_ball = nullptr;
        for (const Ball& b : r.model.balls)
            zero_set_samples(b, 31, [&](const V3L& x) {
                const L d = box_surface_distance(x, m.half);
                if (d > worst) worst = d, worst_at = x, worst_ball = &b;
                ++samples;
                beyond_3e += d > 3 * L(E);
            });
        REQUIRE(worst_ball);
        MESSAGE(m.name << ": " << r.model.balls.size() << " records, " << samples << " zero-set samples, " << beyond_3e
                                    << " farther than 3 E from the box, the farthest " << double(worst / E) << " E (at (" << double(worst_at[0]) << ", "
                                    << double(worst_at[1]) << ", " << double(worst_at[2]) << "), of a record with "
                                    << int(worst_ball->has_plane) + int(worst_ball->has_plane2) << " planes, centre (" << worst_ball->center[0] << ", "
                                    << worst_ball->center[1] << ", " << worst_ball->center[2] << "), radius " << worst_ball->radius << ")");
        CHECK(samples > 100 * long(r.model.balls.size()));
        // Measured: the farthest sample 0.001 E from the cube, 0.08 E from the thin box. Before the
        // clusters' face normals (`face_normal` in src/slim/build.cpp) 1 sample lay beyond 3 E on
        // the cube (the farthest 5.1 E) and 4 on the thin box (5.4 E), all of sharp pairs: a pair's
        // ball reaching a third face with too few points to be a cluster of their own got them in
        // one of its clusters, whose mean normal, and so the plane between the clusters, tilted.
        CHECK(worst <= L(E));
    }
}

TEST_CASE("boxes' corner triples rendered (CPU reference): blended normals and hits match the exact box away from its edges and near its corners, coverage too") {
    const int w = 200, h = 150;
    double render_seconds = 0;
    // The cube, the thin box, and the cube built as before corner triples and the crease test
    // (which must fail the corner measures: the test is not vacuous).
    for (int k = 0; k < 3; ++k) {
        const bool corners = k < 2;
        const BoxModel& m = box_model(k % 2 == 1 ? 1 : 0, corners);
        CAPTURE(m.name);
        const Vec3d& H = m.half;
        const double E = m.result.stats.threshold;
        scene::Slim so;
        so.balls = scene_balls(m.result.model);
        // Three corners seen along about their diagonals, each whole (45 degrees, looking at the
        // centre: the corner near the image's centre) and close up (6 degrees, looking at the
        // corner: about 0.27 E per pixel).
        struct View {
            Vec3d eye, target;
            double fov_deg;
        };
        std::vector<View> views;
        const double eye_scale = length(H) / length(vec3(1.0, 0.7, 0.5));
        for (const Vec3d& s : {vec3(1.0, 1.0, 1.0), vec3(-1.0, 1.0, -1.0), vec3(1.0, -1.0, -1.0)}) {
            const Vec3d eye = vec3(3.0 * s[0], 2.5 * s[1], 2.2 * s[2]) * eye_scale;
            views.push_back({eye, vec3(0.0, 0.0, 0.0), 45});
            views.push_back({eye, vec3(H[0] * s[0], H[1] * s[1], H[2] * s[2]), 6});
        }
        const L margin = 4 * L(E);
        std::vector<double> away_deg, away_pos, near_deg, near_pos;
        std::vector<double> edge_deg[3];  // hits within 4 E of an edge: closer than 1 E, 1..2 E, 2..4 E
        long away_total = 0;
        for (const View& v : views) {
            CAPTURE(v.eye[0]);
            CAPTURE(v.eye[1]);
            CAPTURE(v.eye[2]);
            CAPTURE(v.fov_deg);
            scene::Scene s;
            s.slims.push_back(so);
            s.camera.eye = v.eye;
            s.camera.target = v.target;
            s.camera.fov_y_deg = v.fov_deg;
            s.camera.near = 0.5;
            s.camera.far = 20.0;
            s.lights.push_back(scene::Light{});
            const render::Frame fr = render::build_frame(s, w, h);
            REQUIRE(fr.slim_balls.size() == m.result.model.balls.size());
            std::vector<render::SlimPixel> px;
            const auto t0 = std::chrono::steady_clock::now();
            render::render_slim_cpu(fr.slim_balls, fr.camera, fr.light, fr.options, &px);
            render_seconds += seconds_since(t0);
            // Back to world coordinates (world = offset + scale frame).
            const V3L offset = to_long(fr.transform.offset);
            const L scale = fr.transform.scale;
            std::vector<char> box_cov(px.size()), slim_cov(px.size());
            long away = 0, near = 0, covered = 0;
            double view_away_deg = 0, view_near_deg = 0;
            for (std::size_t i = 0; i < px.size(); ++i) {
                const render::SlimPixel& p = px[i];
                V3L ro, rd;
                for (int k = 0; k < 3; ++k) ro[k] = offset[k] + scale * L(p.origin[k]), rd[k] = scale * L(p.dir[k]);
                const BoxHit bh = box_hit(ro, rd, H);
                box_cov[i] = bh.hit;
                slim_cov[i] = p.covered;
                covered += p.covered;
                if (!bh.hit || !p.covered) continue;
                V3L n, x;
                for (int k = 0; k < 3; ++k) n[k] = L(p.normal[k]), x[k] = ro[k] + L(p.lambda) * rd[k];
                const double a = angle_deg(n, bh.n);
                const double pos = double(std::sqrt(dot(x - bh.x, x - bh.x)) / L(E));
                const L de = edge_distance(bh.x, bh.axis, H), dc = corner_distance(bh.x, H);
                if (de > margin) {
                    away_deg.push_back(a);
                    away_pos.push_back(pos);
                    view_away_deg = std::max(view_away_deg, a);
                    ++away;
                } else {
                    edge_deg[de < L(E) ? 0 : de < 2 * L(E) ? 1 : 2].push_back(a);
                }
                if (dc >= 3 * L(E) && dc <= 6 * L(E) && de > L(E)) {
                    near_deg.push_back(a);
                    near_pos.push_back(pos);
                    view_near_deg = std::max(view_near_deg, a);
                    ++near;
                }
            }
            away_total += away;
            // Pixels covered by only one of SLIM and the box, more than 2 pixels from the box's silhouette.
            const Coverage cov = compare_coverage(slim_cov, box_cov, w, h, 2);
            MESSAGE(m.name << ", eye (" << v.eye[0] << ", " << v.eye[1] << ", " << v.eye[2] << "), fov " << v.fov_deg << ": " << covered << " covered pixels, "
                           << away << " farther than 4 E from the edges (max normal error " << view_away_deg << " deg), " << near
                           << " 3..6 E from a corner (max " << view_near_deg << " deg); box " << cov.reference << " px, only SLIM " << cov.only_tested
                           << ", only the box " << cov.only_reference << ", farthest ring " << cov.worst_ring << ", beyond 2 px " << cov.beyond_band);
            CHECK(cov.reference > w * h / 8);
            if (corners) CHECK(cov.beyond_band == 0);
            if (v.fov_deg < 10) CHECK(near > 100);
        }
        MESSAGE(m.name << ": blended normal vs the exact face normal: farther than 4 E from every edge (" << away_deg.size() << " px) max "
                       << percentile(away_deg, 1.0) << " deg, 99.9% " << percentile(away_deg, 0.999) << " deg; 3..6 E from a corner and > 1 E from the edges ("
                       << near_deg.size() << " px) max " << percentile(near_deg, 1.0) << " deg, 99.9% " << percentile(near_deg, 0.999)
                       << " deg. Blended hit vs the exact hit: away from the edges max " << percentile(away_pos, 1.0) << " E, 99.9% " << percentile(away_pos, 0.999)
                       << " E; near the corners max " << percentile(near_pos, 1.0) << " E. Not checked, within 4 E of an edge: closer than 1 E ("
                       << edge_deg[0].size() << " px) max " << percentile(edge_deg[0], 1.0) << " deg, 99.9% " << percentile(edge_deg[0], 0.999) << " deg; 1..2 E ("
                       << edge_deg[1].size() << " px) max " << percentile(edge_deg[1], 1.0) << ", 99.9% " << percentile(edge_deg[1], 0.999) << "; 2..4 E ("
                       << edge_deg[2].size() << " px) max " << percentile(edge_deg[2], 1.0) << ", 99.9% " << percentile(edge_deg[2], 0.999));
        CHECK(away_total > 6 * w * h / 8);
        if (!corners) {
            // Measured without the triples: near the corners max 90 deg (99.9%: 90), away from the
            // edges max 52 deg (99.9%: 0.75), hits up to 3.3 E off; with them 0.01 and 0.25 deg.
            CHECK(percentile(near_deg, 1.0) > 5.0);
            continue;
        }
        // Away from the edges the blend is of planes fitted to exact planar samples: measured max
        // 0.25 deg (cube) and 1.02 deg (thin box; both just beyond 4 E of an edge, where a neighbouring
        // record's plane is slightly tilted), 99.9% 4e-5 deg; hits within 0.19 E of the exact ones.
        CHECK(percentile(away_deg, 1.0) < 2.0);
        CHECK(percentile(away_deg, 0.999) < 0.01);
        CHECK(percentile(away_pos, 1.0) < 0.5);
        // Not vacuous: with sharp_features off (no pairs, no triples: every edge and corner rounded)
        // the same measures gave (once, both boxes) up to 60 deg away from the edges and 90 deg
        // near the corners, hits up to 5.9 E off and coverage holes beyond the silhouette band.
        // Near the corner vertex, where the rounded corners (one quadric, or blended normals, in the
        // balls holding the three faces) tilted the normal towards the diagonal: measured max 0.01
        // deg (cube), 0.13 deg (thin box); hits within 0.02 E.
        CHECK(percentile(near_deg, 1.0) < 0.5);
        CHECK(percentile(near_pos, 1.0) < 0.5);
    }
    MESSAGE("rendering: " << render_seconds << " s");
}

namespace {

// Saddle corners, against the exact geometry of an L-shaped solid: the union of the boxes
// A = [0, 2] x [0, 1] x [0, 1] and B = [0, 1] x [0, 2] x [0, 1] (the shape of
// tests/slim/data/l_prism.off). Its concave edge x = y = 1 meets the top and the bottom at the two
// saddle corners (1, 1, 0) and (1, 1, 1), where the top (bottom) face turns 270 degrees about the
// corner.

/// A face of the L: the axis-aligned rectangle [lo, hi] (lo[a] = hi[a] on its axis a), its outward
/// normal and its plane's group (the two rectangles of a cap share one).
struct LFace {
    V3L lo, hi, n;
    int group;
};

std::vector<LFace> l_faces() {
    const auto v = [](L x, L y, L z) { return vec3(x, y, z); };
    return {{v(0, 0, 0), v(2, 1, 0), v(0, 0, -1), 0}, {v(0, 1, 0), v(1, 2, 0), v(0, 0, -1), 0}, {v(0, 0, 1), v(2, 1, 1), v(0, 0, 1), 1},
            {v(0, 1, 1), v(1, 2, 1), v(0, 0, 1), 1},  {v(0, 0, 0), v(2, 0, 1), v(0, -1, 0), 2}, {v(2, 0, 0), v(2, 1, 1), v(1, 0, 0), 3},
            {v(1, 1, 0), v(2, 1, 1), v(0, 1, 0), 4},  {v(1, 1, 0), v(1, 2, 1), v(1, 0, 0), 5},  {v(0, 2, 0), v(1, 2, 1), v(0, 1, 0), 6},
            {v(0, 0, 0), v(0, 2, 1), v(-1, 0, 0), 7}};
}

L dist(const V3L& a, const V3L& b) { return std::sqrt(dot(a - b, a - b)); }

L rect_distance(const V3L& x, const LFace& f) {
    L s = 0;
    for (int a = 0; a < 3; ++a) {
        const L d = x[a] - std::clamp(x[a], f.lo[a], f.hi[a]);
        s += d * d;
    }
    return std::sqrt(s);
}

/// Jittered samples of every face, about h apart, with the exact outward normals.
OrientedPoints l_points(double h, std::uint64_t seed) {
    OrientedPoints p;
    p.file = "L";
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(0.05, 0.95);
    for (const LFace& f : l_faces()) {
        int a = 0;
        while (f.lo[a] != f.hi[a]) ++a;
        const int b = (a + 1) % 3, c = (a + 2) % 3;
        const double wb = double(f.hi[b] - f.lo[b]), wc = double(f.hi[c] - f.lo[c]);
        const int nb = std::max(1, int(std::lround(wb / h))), nc = std::max(1, int(std::lround(wc / h)));
        for (int i = 0; i < nb; ++i)
            for (int j = 0; j < nc; ++j) {
                Vec3d x, n;
                x[a] = double(f.lo[a]);
                x[b] = double(f.lo[b]) + (i + u(rng)) * wb / nb;
                x[c] = double(f.lo[c]) + (j + u(rng)) * wc / nc;
                for (int k = 0; k < 3; ++k) n[k] = double(f.n[k]);
                p.positions.push_back(x);
                p.normals.push_back(n);
            }
    }
    return p;
}

/// The first hit of a ray from outside the L: the nearer of the two boxes' first hits.
BoxHit l_hit(const V3L& o, const V3L& d) {
    BoxHit best;
    L best_t = std::numeric_limits<L>::infinity();
    for (const Vec3d& centre : {vec3(1.0, 0.5, 0.5), vec3(0.5, 1.0, 0.5)}) {
        const BoxHit b = box_hit(o - to_long(centre), d, centre);  // (each box's centre is its half size: it starts at 0)
        if (!b.hit) continue;
        const V3L x = b.x + to_long(centre);
        const L t = dot(x - o, d) / dot(d, d);
        if (t < best_t) best_t = t, best = b, best.x = x;
    }
    return best;
}

/// The records of the saddle corners: runs of four consecutive two-plane records with one centre.
std::vector<std::size_t> saddle_groups(const Model& m) {
    std::vector<std::size_t> first;
    for (std::size_t i = 0; i < m.balls.size();) {
        std::size_t j = i;
        while (j < m.balls.size() && m.balls[j].has_plane2 && length(m.balls[j].center - m.balls[i].center) == 0.0) ++j;
        if (j - i == 4) first.push_back(i);
        i = std::max(j, i + 1);
    }
    return first;
}

}  // namespace

TEST_CASE("saddle corners of an L-shaped solid: four records each, on the exact faces; rendered (CPU reference), the normals near them are the faces'") {
    const double spacing = 0.02;  // about 2.2 E
    const std::vector<LFace> faces = l_faces();
    const auto surface_distance = [&](const V3L& x) {
        L d = std::numeric_limits<L>::infinity();
        for (const LFace& f : faces) d = std::min(d, rect_distance(x, f));
        return d;
    };
    const V3L saddle[2] = {vec3(1.0L, 1.0L, 0.0L), vec3(1.0L, 1.0L, 1.0L)};
    for (const bool saddles : {true, false}) {
        CAPTURE(saddles);
        const OrientedPoints pts = l_points(spacing, 5);
        BuildOptions o;
        o.error = 3e-3;
        o.threads = 0;
        o.saddle_corners = saddles;
        const BuildResult r = build(pts, o);
        const BuildStats& st = r.stats;
        const double E = st.threshold;
        MESSAGE("L, saddle corners " << (saddles ? "on" : "off") << ": " << pts.size() << " points, E = " << E << ": " << st.balls << " records, "
                                     << st.sharp_pairs << " sharp pairs, " << st.corners << " corners (" << st.saddles << " saddles), " << st.forced
                                     << " forced; max distance " << st.max_distance / E << " E");
        CHECK(st.over_threshold == 0);
        const std::vector<std::size_t> groups = saddle_groups(r.model);
        CHECK(groups.size() == st.saddles);
        if (saddles) {
            // Each saddle corner inside a saddle group's ball, and those records' zero sets on the L.
            int per_saddle[2] = {0, 0};
            L worst = 0;
            long samples = 0;
            for (const std::size_t g : groups) {
                for (int s = 0; s < 2; ++s) per_saddle[s] += dist(to_long(r.model.balls[g].center), saddle[s]) < L(r.model.balls[g].radius);
                for (std::size_t k = 0; k < 4; ++k)
                    zero_set_samples(r.model.balls[g + k], 31, [&](const V3L& x) {
                        worst = std::max(worst, surface_distance(x));
                        ++samples;
                    });
            }
            MESSAGE(groups.size() << " saddle groups (" << per_saddle[0] << " at (1, 1, 0), " << per_saddle[1] << " at (1, 1, 1)); their zero sets: " << samples
                                  << " samples, the farthest " << double(worst / L(E)) << " E from the L");
            CHECK(per_saddle[0] >= 1);
            CHECK(per_saddle[1] >= 1);
            CHECK(samples > 100 * 4 * long(groups.size()));
            CHECK(worst <= L(E));
        } else {
            CHECK(st.saddles == 0);
        }
        // Every record's zero set (as the box test: no fins anywhere on the L).
        L worst_all = 0;
        V3L worst_at{};
        const Ball* worst_ball = nullptr;
        for (const Ball& b : r.model.balls)
            zero_set_samples(b, 31, [&](const V3L& x) {
                const L d = surface_distance(x);
                if (d > worst_all) worst_all = d, worst_at = x, worst_ball = &b;
            });
        REQUIRE(worst_ball);
        MESSAGE("every record's zero set: the farthest " << double(worst_all / L(E)) << " E from the L (at (" << double(worst_at[0]) << ", " << double(worst_at[1])
                                                         << ", " << double(worst_at[2]) << "), of a record with " << int(worst_ball->has_plane) + int(worst_ball->has_plane2)
                                                         << " planes, centre (" << worst_ball->center[0] << ", " << worst_ball->center[1] << ", " << worst_ball->center[2]
                                                         << "), radius " << worst_ball->radius / E << " E)");
        // Measured 3.5 E (3.9 E with the builder before saddle corners, face normals and tangent
        // planes): the x = 0 face continued past y = 2 beside the convex corner (0, 2, 0), a sharp
        // pair whose ball also holds a few points of the third face. Known, left open; the bound
        // keeps it from growing.
        CHECK(worst_all <= 4 * L(E));

        // Each saddle corner from outside the notch, whole (45 degrees) and close up (6 degrees:
        // about 0.3 E per pixel).
        const int w = 200, h = 150;
        scene::Slim so;
        so.balls = scene_balls(r.model);
        std::vector<double> near_deg, away_deg;
        long beyond_band = 0;
        for (const auto& [eye, target, fov] : {std::tuple{vec3(3.6, 3.2, 3.1), vec3(1.0, 1.0, 0.5), 45.0}, std::tuple{vec3(3.6, 3.2, 3.1), vec3(1.0, 1.0, 1.0), 6.0},
                                               std::tuple{vec3(3.3, 3.7, -2.4), vec3(1.0, 1.0, 0.5), 45.0}, std::tuple{vec3(3.3, 3.7, -2.4), vec3(1.0, 1.0, 0.0), 6.0}}) {
            scene::Scene s;
            s.slims.push_back(so);
            s.camera.eye = eye;
            s.camera.target = target;
            s.camera.fov_y_deg = fov;
            s.camera.near = 0.5;
            s.camera.far = 20.0;
            s.lights.push_back(scene::Light{});
            const render::Frame fr = render::build_frame(s, w, h);
            std::vector<render::SlimPixel> px;
            render::render_slim_cpu(fr.slim_balls, fr.camera, fr.light, fr.options, &px);
            const V3L offset = to_long(fr.transform.offset);
            const L scale = fr.transform.scale;
            std::vector<char> l_cov(px.size()), slim_cov(px.size());
            double view_near = 0;
            long near = 0;
            for (std::size_t i = 0; i < px.size(); ++i) {
                const render::SlimPixel& p = px[i];
                V3L ro, rd;
                for (int k = 0; k < 3; ++k) ro[k] = offset[k] + scale * L(p.origin[k]), rd[k] = scale * L(p.dir[k]);
                const BoxHit lh = l_hit(ro, rd);
                l_cov[i] = lh.hit;
                slim_cov[i] = p.covered;
                if (!lh.hit || !p.covered) continue;
                V3L n;
                for (int k = 0; k < 3; ++k) n[k] = L(p.normal[k]);
                // Distance to the edges: to the faces of the other planes.
                int own = -1;
                for (const LFace& f : faces)
                    if (rect_distance(lh.x, f) < 1e-9L && dot(f.n, lh.n) > 0.5L) own = f.group;
                L de = std::numeric_limits<L>::infinity();
                for (const LFace& f : faces)
                    if (f.group != own) de = std::min(de, rect_distance(lh.x, f));
                const L dc = std::min(dist(lh.x, saddle[0]), dist(lh.x, saddle[1]));
                const double a = angle_deg(n, lh.n);
                if (de > 4 * L(E)) away_deg.push_back(a);
                if (dc >= 3 * L(E) && dc <= 6 * L(E) && de > L(E)) {
                    near_deg.push_back(a);
                    view_near = std::max(view_near, a);
                    ++near;
                }
            }
            const Coverage cov = compare_coverage(slim_cov, l_cov, w, h, 2);
            MESSAGE("eye (" << eye[0] << ", " << eye[1] << ", " << eye[2] << "), fov " << fov << ": " << near << " px 3..6 E from a saddle corner (max normal error "
                            << view_near << " deg); the L " << cov.reference << " px, only SLIM " << cov.only_tested << ", only the L " << cov.only_reference
                            << ", beyond 2 px " << cov.beyond_band);
            CHECK(cov.reference > w * h / 8);
            if (fov < 10) CHECK(near > 100);
            beyond_band += cov.beyond_band;
        }
        MESSAGE("blended normal vs the exact face normal: 3..6 E from a saddle corner and > 1 E from the edges (" << near_deg.size() << " px) max "
                                                                                                               << percentile(near_deg, 1.0) << " deg, 99.9% "
                                                                                                               << percentile(near_deg, 0.999)
                                                                                                               << " deg; farther than 4 E from the edges ("
                                                                                                               << away_deg.size() << " px) max "
                                                                                                               << percentile(away_deg, 1.0) << " deg");
        if (saddles) {
            CHECK(beyond_band == 0);
            CHECK(percentile(near_deg, 1.0) < 0.5);
            CHECK(percentile(away_deg, 1.0) < 2.0);
        } else {
            CHECK(percentile(near_deg, 1.0) > 5.0);  // not vacuous: without saddle records the corners are rounded
        }
    }
}
