// src/skin/skin.cpp -- molecular skin surfaces through CGAL's Skin_surface_3: the one translation
// unit that includes CGAL (its -frounding-math stays here)
#include "quadcast/skin/skin.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <stdexcept>
#include <string>
#include <unordered_map>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polyhedron_3.h>
#include <CGAL/Skin_surface_3.h>
#include <CGAL/Skin_surface_traits_3.h>
#include <CGAL/make_skin_surface_mesh_3.h>

#include "quadcast/bb/quadric_form.hpp"

namespace quadcast::skin {

namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Traits = CGAL::Skin_surface_traits_3<K>;
using Cgal_skin = CGAL::Skin_surface_3<Traits>;
using Weighted_point = K::Weighted_point_3;
using Tmc = Cgal_skin::TMC;
using Surface = Cgal_skin::Quadratic_surface;
using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

K::Point_3 point(const Vec3d& x) { return {x[0], x[1], x[2]}; }

void validate(const std::vector<scene::SkinBall>& balls, double shrink) {
    if (balls.empty()) throw std::invalid_argument("a skin surface needs at least one ball");
    if (!(shrink > 0 && shrink < 1)) throw std::invalid_argument("the shrink factor must lie in (0, 1), got " + std::to_string(shrink));
    for (std::size_t i = 0; i < balls.size(); ++i) {
        const scene::SkinBall& b = balls[i];
        if (!std::isfinite(b.center[0]) || !std::isfinite(b.center[1]) || !std::isfinite(b.center[2]) || !(b.radius > 0) || !std::isfinite(b.radius))
            throw std::invalid_argument("skin ball " + std::to_string(i) + ": a non-finite centre or a radius that is not positive");
    }
}

std::vector<Weighted_point> weighted_points(const std::vector<scene::SkinBall>& balls, double shrink) {
    // The weights are the squared radii; CGAL grows them by 1/s (grow_balls = true).
    std::vector<Weighted_point> wp;
    wp.reserve(balls.size() + 6);
    Vec3d lo = balls[0].center, hi = lo;
    double rmax = 0;
    for (const scene::SkinBall& b : balls) {
        wp.emplace_back(point(b.center), b.radius * b.radius);
        for (int k = 0; k < 3; ++k) lo[k] = std::min(lo[k], b.center[k]), hi[k] = std::max(hi[k], b.center[k]);
        rmax = std::max(rmax, b.radius);
    }
    // Six points of negative weight (no surface of their own) far around the balls. CGAL encloses
    // the balls in an octahedron of such points at (dx + dy + dz + sqrt(max weight)) / s from the
    // centre, which for a small molecule is close enough to bend its skin (one atom at s = 0.5: its
    // sphere leaves the atom's mixed cell, and the skin is off the sphere by 1.5e-2 A). An atom's
    // cells reach no farther than r / s when no other point is nearer than 2 r / s, so these are
    // placed 2.5 max(r) / s + 1 A beyond every centre (CGAL's own octahedron lands farther out
    // still). Nearer is better: the cells between the balls and these points are the largest
    // pieces, and they set the depth range of the scene.
    const Vec3d mid = (lo + hi) * 0.5;
    const double d = 0.5 * length(hi - lo) + 2.5 * rmax / shrink + 1;
    for (int k = 0; k < 3; ++k)
        for (const double sign : {-1.0, 1.0}) {
            Vec3d x = mid;
            x[k] += sign * d;
            wp.emplace_back(point(x), -1.0);
        }
    return wp;
}

/// The ball of least power distance |x - c|^2 - r^2 / s to a point (the grown balls), through a
/// uniform grid of cell size 2 max(r) / sqrt(s).
class NearestBall {
public:
    NearestBall(const std::vector<scene::SkinBall>& balls, double shrink) : balls_(balls), shrink_(shrink) {
        double rmax = 0;
        for (const auto& b : balls) rmax = std::max(rmax, b.radius);
        cell_ = 2 * rmax / std::sqrt(shrink);
        for (std::size_t i = 0; i < balls.size(); ++i) grid_[key(cell_of(balls[i].center))].push_back(i);
    }
    std::size_t operator()(const Vec3d& x) const {
        const std::array<long, 3> c = cell_of(x);
        std::size_t best = 0;
        double best_d = HUGE_VAL;
        bool found = false;
        for (long dx = -1; dx <= 1; ++dx)
            for (long dy = -1; dy <= 1; ++dy)
                for (long dz = -1; dz <= 1; ++dz) {
                    const auto it = grid_.find(key({c[0] + dx, c[1] + dy, c[2] + dz}));
                    if (it == grid_.end()) continue;
                    for (std::size_t i : it->second) consider(i, x, best, best_d, found);
                }
        if (!found)
            for (std::size_t i = 0; i < balls_.size(); ++i) consider(i, x, best, best_d, found);
        return best;
    }

private:
    void consider(std::size_t i, const Vec3d& x, std::size_t& best, double& best_d, bool& found) const {
        const Vec3d d = x - balls_[i].center;
        const double p = dot(d, d) - balls_[i].radius * balls_[i].radius / shrink_;
        if (p < best_d) {
            best_d = p;
            best = i;
            found = true;
        }
    }
    std::array<long, 3> cell_of(const Vec3d& x) const {
        return {static_cast<long>(std::floor(x[0] / cell_)), static_cast<long>(std::floor(x[1] / cell_)), static_cast<long>(std::floor(x[2] / cell_))};
    }
    static std::uint64_t key(const std::array<long, 3>& c) {
        return (static_cast<std::uint64_t>(c[0] & 0x1fffff) << 42) | (static_cast<std::uint64_t>(c[1] & 0x1fffff) << 21) |
               static_cast<std::uint64_t>(c[2] & 0x1fffff);
    }
    const std::vector<scene::SkinBall>& balls_;
    double shrink_, cell_ = 1;
    std::unordered_map<std::uint64_t, std::vector<std::size_t>> grid_;
};

}  // namespace

struct SkinSurface::Impl {
    std::vector<Weighted_point> points;
    std::unique_ptr<Cgal_skin> skin;
    std::vector<std::shared_ptr<Surface>> surfaces;  ///< per piece
    std::vector<Piece> pieces;
    Stats stats;
};

SkinSurface::SkinSurface(const std::vector<scene::SkinBall>& balls, double shrink, int refine_levels) : impl_(std::make_unique<Impl>()) {
    validate(balls, shrink);
    Impl& m = *impl_;
    m.stats.balls = balls.size();
    m.points = weighted_points(balls, shrink);

    // Build the regular triangulation and the triangulated mixed complex (CGAL).
    const Clock::time_point t0 = Clock::now();
    m.skin = std::make_unique<Cgal_skin>(m.points.begin(), m.points.end(), shrink, true);
    m.stats.seconds_cgal = seconds_since(t0);

    // Read each cell's quadratic back: f(x) = y^T A y + 2 b^T y + c with y = x - centroid, A from
    // gradient differences (the gradient is linear: grad(m + e_i) - grad(m) = 2 A e_i), b = grad(m)/2,
    // c = value(m); then check it against value() at the cell's 10 quadratic nodes and keep the
    // cells whose BB coefficients change sign.
    const Clock::time_point t1 = Clock::now();
    const NearestBall nearest(balls, shrink);
    // The balls of the regular triangulation's vertices (the far points of negative weight have none).
    std::map<std::array<double, 3>, std::size_t> ball_at;
    for (std::size_t i = balls.size(); i-- > 0;) ball_at[{balls[i].center[0], balls[i].center[1], balls[i].center[2]}] = i;
    // The colour of a cell: the ball of its anchor simplex (the Delaunay simplex of its mixed cell)
    // nearest in power distance to the cell's centroid, so that colours change along mixed cells.
    const auto anchor_ball = [&](const Cgal_skin::Simplex& sim, const Vec3d& x) {
        std::vector<Cgal_skin::Vertex_handle> v;
        switch (sim.dimension()) {
            case 0: v.push_back(Cgal_skin::Vertex_handle(sim)); break;
            case 1: {
                const Cgal_skin::Edge e(sim);
                v = {e.first->vertex(e.second), e.first->vertex(e.third)};
                break;
            }
            case 2: {
                const Cgal_skin::Facet f(sim);
                for (int k = 1; k < 4; ++k) v.push_back(f.first->vertex((f.second + k) % 4));
                break;
            }
            default: {
                const Cgal_skin::Cell_handle c(sim);
                for (int k = 0; k < 4; ++k) v.push_back(c->vertex(k));
            }
        }
        std::size_t best = balls.size();
        double best_d = HUGE_VAL;
        for (const auto& h : v) {
            const auto& wp = h->point();
            const auto it = ball_at.find({CGAL::to_double(wp.x()), CGAL::to_double(wp.y()), CGAL::to_double(wp.z())});
            if (it == ball_at.end()) continue;
            const Vec3d d = x - balls[it->second].center;
            const double pd = dot(d, d) - balls[it->second].radius * balls[it->second].radius / shrink;
            if (pd < best_d) best_d = pd, best = it->second;
        }
        return best < balls.size() ? best : nearest(x);
    };
    Tmc& tmc = m.skin->triangulated_mixed_complex();
    for (auto c = tmc.finite_cells_begin(); c != tmc.finite_cells_end(); ++c) {
        ++m.stats.cells;
        std::array<Vec3d, 4> p;
        for (int k = 0; k < 4; ++k) {
            const auto& v = c->vertex(k)->point();
            p[static_cast<std::size_t>(k)] = Vec3d{{CGAL::to_double(v.x()), CGAL::to_double(v.y()), CGAL::to_double(v.z())}};
        }
        Vec3d mid{{0, 0, 0}};
        for (const Vec3d& x : p) mid = mid + x * 0.25;
        const TetShape<double> shape = tet_shape(p);
        const double longest = shape.longest;
        const std::shared_ptr<Surface>& s = c->info().second;
        const auto grad = [&](const Vec3d& x) {
            const K::Vector_3 g = s->gradient(point(x));
            return Vec3d{{g.x(), g.y(), g.z()}};
        };
        const Vec3d g0 = grad(mid);
        Mat3<double> A{};
        for (int i = 0; i < 3; ++i) {
            Vec3d e{{0, 0, 0}};
            e[i] = 1;
            const Vec3d gi = grad(mid + e) - g0;
            for (int j = 0; j < 3; ++j) A[i][j] = gi[j] * 0.5;  // column i
        }
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < i; ++j) A[i][j] = A[j][i] = (A[i][j] + A[j][i]) * 0.5;
        const double c0 = s->value(point(mid));
        const Quadric<double> local = quadric_from_abc(A, g0 * 0.5, c0);

        // The values at the 10 nodes (corners, edge midpoints), local quadric against CGAL.
        double corner[4], edge[6], scale = std::fabs(c0) + length(g0) * longest;
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j) scale = std::max(scale, std::fabs(c0) + length(g0) * longest + std::fabs(A[i][j]) * longest * longest);
        double worst = 0;
        const auto node = [&](const Vec3d& x) {
            const double v = evaluate(local, x - mid);
            worst = std::max(worst, std::fabs(v - s->value(point(x))));
            return v;
        };
        for (int k = 0; k < 4; ++k) corner[k] = node(p[std::size_t(k)]);
        for (int n = 0; n < 6; ++n)
            edge[n] = node((p[std::size_t(bb::quadratic_edges[n][0])] + p[std::size_t(bb::quadratic_edges[n][1])]) * 0.5);
        const double rel = scale > 0 ? worst / scale : worst;
        m.stats.worst_check = std::max(m.stats.worst_check, rel);
        if (!(rel <= 1e-9))
            throw std::runtime_error("skin: the quadric read back from CGAL's cell disagrees with its value() by " + std::to_string(rel) +
                                     " of the cell's scale");
        const bb::BezierTet<double, 2> bt = bb::bezier_from_quadratic_nodes(corner, edge);
        double bmin = HUGE_VAL, bmax = -HUGE_VAL;
        for (int n = 0; n < bt.size; ++n) {
            bmin = std::min(bmin, bt[n]);
            bmax = std::max(bmax, bt[n]);
        }
        if (bmin > 0 || bmax < 0 || (bmin == 0 && bmax == 0)) continue;
        // A flat cell (CGAL's triangulation may hold slivers) covers nothing.
        if (shape.flatter_than(1e-12)) continue;
        // Smaller clip tetrahedra where the surface fills little of the cell (same quadric).
        ++m.stats.cells_crossed;
        BoundingTet<double> cell_tet{};
        for (int k = 0; k < 4; ++k) cell_tet.p[k] = p[std::size_t(k)] - mid;
        std::vector<BoundingTet<double>> parts;
        // (Parts stay 2^-12 of the coordinates' magnitude or larger: the primitives hold float corners.)
        const double magnitude = std::max({std::fabs(mid[0]), std::fabs(mid[1]), std::fabs(mid[2]), 1.0});
        bb::refine_crossing(local, cell_tet, refine_levels, 4, magnitude * 0.000244140625, parts);
        Piece piece;
        piece.q = translate_to_eye(local, mid * -1.0);
        piece.ball = anchor_ball(c->info().first, mid);
        piece.cell = m.surfaces.size();
        piece.cell_tet = p;
        m.surfaces.push_back(s);
        for (const BoundingTet<double>& t : parts) {
            for (int k = 0; k < 4; ++k) piece.tet[std::size_t(k)] = t.p[k] + mid;
            m.pieces.push_back(piece);
        }
    }
    m.stats.pieces = m.pieces.size();
    m.stats.seconds_pieces = seconds_since(t1);
}

SkinSurface::~SkinSurface() = default;

const std::vector<Piece>& SkinSurface::pieces() const { return impl_->pieces; }
const Stats& SkinSurface::stats() const { return impl_->stats; }

double SkinSurface::cell_value(std::size_t cell, const Vec3d& x) const { return impl_->surfaces.at(cell)->value(point(x)); }

Vec3d SkinSurface::cell_gradient(std::size_t cell, const Vec3d& x) const {
    const K::Vector_3 g = impl_->surfaces.at(cell)->gradient(point(x));
    return Vec3d{{g.x(), g.y(), g.z()}};
}

double SkinSurface::value(const Vec3d& x) const {
    Tmc& tmc = impl_->skin->triangulated_mixed_complex();
    const Tmc::Cell_handle c = tmc.locate(Tmc::Point(x[0], x[1], x[2]));
    if (c == Tmc::Cell_handle() || tmc.is_infinite(c)) return std::numeric_limits<double>::quiet_NaN();
    return c->info().second->value(point(x));
}

Vec3d SkinSurface::gradient(const Vec3d& x) const {
    Tmc& tmc = impl_->skin->triangulated_mixed_complex();
    const Tmc::Cell_handle c = tmc.locate(Tmc::Point(x[0], x[1], x[2]));
    const double nan = std::numeric_limits<double>::quiet_NaN();
    if (c == Tmc::Cell_handle() || tmc.is_infinite(c)) return Vec3d{{nan, nan, nan}};
    const K::Vector_3 g = c->info().second->gradient(point(x));
    return Vec3d{{g.x(), g.y(), g.z()}};
}

MeshFigures cgal_mesh(const std::vector<scene::SkinBall>& balls, double shrink, int subdivisions) {
    validate(balls, shrink);
    const std::vector<Weighted_point> wp = weighted_points(balls, shrink);
    CGAL::Polyhedron_3<K> poly;
    MeshFigures f;
    const Clock::time_point t0 = Clock::now();
    CGAL::make_skin_surface_mesh_3(poly, wp.begin(), wp.end(), shrink, subdivisions, true);
    f.seconds = seconds_since(t0);
    f.vertices = poly.size_of_vertices();
    f.triangles = poly.size_of_facets();
    // The distance of the mesh from the skin, to first order |f| / |grad f|: at vertices and at
    // the centroids of the triangles (where a flat triangle strays farthest), in the located cell.
    const SkinSurface exact(balls, shrink);
    const auto distance = [&](const K::Point_3& x) {
        const Vec3d y{{x.x(), x.y(), x.z()}};
        const double v = exact.value(y);
        const double g = length(exact.gradient(y));
        return g > 0 ? std::fabs(v) / g : std::fabs(v);
    };
    for (auto v = poly.vertices_begin(); v != poly.vertices_end(); ++v) f.worst_distance = std::max(f.worst_distance, distance(v->point()));
    for (auto fc = poly.facets_begin(); fc != poly.facets_end(); ++fc) {
        auto h = fc->facet_begin();
        const K::Point_3 a = h->vertex()->point(), b = (++h)->vertex()->point(), c = (++h)->vertex()->point();
        f.worst_distance = std::max(f.worst_distance, distance(CGAL::centroid(a, b, c)));
    }
    return f;
}

std::vector<scene::Quadric> build_scene_skin(const std::vector<scene::SkinBall>& balls, double shrink, const scene::Material& material) {
    const SkinSurface s(balls, shrink);
    std::vector<scene::Quadric> out;
    out.reserve(s.pieces().size());
    for (const Piece& p : s.pieces()) {
        scene::Quadric q{};
        q.q = p.q.q;
        q.bound = scene::Quadric::Bound::tetrahedron;
        for (std::size_t k = 0; k < 4; ++k) q.tetrahedron.p[k] = p.tet[k];
        q.material = material;
        q.material.color = balls[p.ball].color;
        q.two_sided = false;  // a closed, consistently oriented surface: f < 0 inside
        out.push_back(q);
    }
    return out;
}

void install_scene_builder() { scene::set_skin_build_function(build_scene_skin); }

}  // namespace quadcast::skin
