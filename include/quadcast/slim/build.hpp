// quadcast/slim/build.hpp -- the greedy ball cover of a SLIM surface, with sharp features
#pragma once

// Ohtake, Belyaev & Alexa 2005, sec. 3, as built here:
//  1. E = error * (bounding-box diagonal). Points go into a uniform grid (cells of about 8
//     points; Debian ships no kd-tree we link already, nanoflann is not a dependency).
//  2. Seeds are visited in a seeded random permutation (std::mt19937_64 + Fisher-Yates on the
//     top 53 bits: the same order on every platform); a seed already covered is skipped.
//  3. Per seed p: the ball (p, r). r starts at initial_radius * diagonal, clamped to [r_min,
//     8 r_min] (r_min: the distance of the min_points-th nearest point), grows by 1.5 while the fit is accepted (at most
//     max_radius * diagonal), shrinks by 0.6 while it is not (down to the min_points radius),
//     then two bisection steps (geometric mean) between the largest accepted and the smallest
//     rejected radius. Accepted: the fit (quadcast/slim/fit.hpp) solved, oriented along every
//     normal, every point of the ball within E (gradient-line distance), and (support_check) its
//     zero set near the points out to at least min_support_fraction of the radius: sampled on
//     lines parallel to the axes (13 to 51 per side, about 4/3 point spacings apart), every sample
//     within 2 point spacings of an input point whose normal is less than 120 degrees from the
//     quadric's gradient there (no second sheet in the ball, no sheet folded back through the
//     points), and surrounded by the points of its own sheet (no angular gap over
//     support_max_gap_degrees: no plane continued past a crease or a border, a fin). Where a
//     sample fails, the record is drawn only in the ball of 0.9 times that sample's distance (and
//     step 6 covers points within cover_fraction of that radius). With the support check, a ball whose quadric
//     and sharp pair are rejected is tried once more with a plane (the fit with its quadratic
//     coefficients held at ~0): in balls of few points the quadratic terms are barely determined
//     and often turn a sheet back into the ball.
//  4. Sharp features: when the single quadric is rejected, the normals are split by 2-means
//     (seeded by the normal farthest from the mean and the one farthest from that, 10 rounds).
//     If the cluster means are more than sharp_angle apart, each cluster holds at least
//     max(min_points, sharp_min_fraction * n) points and neither splits again so (a corner's
//     three faces in two clusters), each cluster gets its own quadric, and
//     the ball becomes TWO records with the same centre and radius, each with a clip plane
//     (Stoll et al. 2006, fig. 8: the surface is the quadric's part on the plane's positive
//     side). The planes are one plane with opposite signs (but see pair_tangent_planes below):
//     normal m = (n1 - n2) / |n1 - n2|
//     (n1, n2 the clusters' face normals: the mean of each cluster's normals within sharp_angle
//     of its mean, twice, so that a third face's few points in a cluster do not tilt it; m
//     bisects the dihedral angle), offset the 1-D threshold along m that misclassifies the
//     fewest points of the two clusters, then moved through the two fits' crossing in the ball
//     (the edge they draw, sampled by Newton's method) where that misclassifies no more points.
//     With pair_tangent_planes, each record is then clipped by the OTHER face's tangent plane at
//     the crossing's centroid instead (kept behind it at a convex edge, in front at a concave
//     one), where that keeps all but sharp_max_misclassified of the points: a plane between the
//     faces ends both along a chord of a curved crease, and the curved face ran up past a flat
//     one (a fin); a flat face's own plane ends the curved face exactly. Where the records with
//     the tangent planes fail the support check, the one plane is tried.
//     Accepted when both fits are
//     and the plane puts at most sharp_max_misclassified of the points on the wrong side (a
//     corner's three faces split into two clusters are not separable by one plane). Note that an
//     edge of two planar faces is often ONE quadric already: the plane pair x y = 0.
//     Corners (`corners`): when the pair is rejected too, 3-means (seeded by the normal farthest
//     from the mean, the one farthest from it, and the one farthest from both). Three clusters
//     pairwise more than sharp_angle apart, each of at least max(min_points, sharp_min_fraction *
//     n) points, none of which splits again (2-means, more than sharp_angle apart) with 3 or more
//     points in its smaller part, get a quadric each, and the ball becomes THREE records with the
//     same centre and radius, each with two clip planes: one plane per two clusters, found as for
//     a pair, each record keeping its own side of its two. Accepted when all three fits are, at
//     most sharp_max_misclassified of the points lie outside their cluster's wedge, and each
//     record passes the support check with both planes over its whole ball (none trimmed).
//     Saddle corners (`saddle_corners`): before the wedges, the corner is tested for a saddle:
//     each face taken as the plane through its points' centroid along its face normal (as for a
//     pair), an edge is convex where each face's points lie behind the other's plane,
//     concave where in front; one edge unlike the other two makes the face opposite it cover more
//     than half the turn about the corner (the top of an L-shaped prism at its notch), which two
//     clip planes cannot keep. The plane between the other two faces j and k splits it into its
//     part beside j and its part beside k, each ended at its edge by a plane found as for a pair
//     from that part's points (each part at least 4 points): the ball becomes FOUR records (the
//     face twice, j, k), accepted as a triple is; a saddle is never drawn as a triple (its
//     270-degree face would lose a quadrant).
//     Creases (crease_normal_degrees): in a ball of radius at most 3 E whose normals split into two
//     flat parts (every normal within 5 degrees of its part's mean) more than sharp_angle apart, a
//     single quadric or plane whose gradient strays more than crease_normal_degrees from a point's
//     normal is rejected (it rounds the crease).
//  5. When even the min_points ball is rejected: a pair of planes where its normals split into two
//     faces of at least 4 points each (each face's plane through its centroid along its mean normal,
//     or its planar fit, within E and crease_normal_degrees of its normals; the plane between them
//     misclassifying none; the support check). Else it is kept anyway ("forced"; counted): its
//     quadric where the support check accepts it, else the seed's tangent plane, drawn as far as
//     the support check accepts it (at least a quarter of the ball).
//  6. The points within cover_fraction * (drawn radius) of the centre are marked covered by that record
//     (by their cluster's record in a sharp pair); repeat until every point is covered.
//  7. (After the cover.) Every record's zero set is checked once more on lines twice as dense (at
//     least 31 per side) and its drawn radius cut the same way where a sample fails, but never
//     below half: a sliver narrower than the fits' lines (a piece of a second sheet at a ball's
//     rim) would be drawn as a speck off the surface.
// Threads (TBB): batches of the next uncovered seeds are fitted in parallel and committed in
// seed order; a seed covered by an earlier ball of its batch is dropped. A seed's ball depends
// only on the seed and the points, so the result is the sequential algorithm's, bit for bit,
// for any thread count.

#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

#include "quadcast/slim/fit.hpp"
#include "quadcast/slim/model.hpp"
#include "quadcast/slim/points.hpp"

namespace quadcast::slim {

struct BuildProgress {
    std::size_t covered = 0, total = 0, balls = 0;
};

struct BuildOptions {
    double error = 1e-3;               ///< E relative to the bounding-box diagonal; > 0
    double cover_fraction = 0.5;       ///< points within this fraction of a record's drawn radius are covered
    double initial_radius = 0.02;      ///< relative to the diagonal
    double max_radius = 0.25;          ///< relative to the diagonal
    std::size_t min_points = 12;       ///< fewest points in a ball (>= 10)
    bool sharp_features = true;
    /// With sharp_features: corner triples (step 4), else a corner's faces are left to smaller balls.
    bool corners = true;
    /// With corners: saddle corners (four records, step 4), else a saddle is left to smaller balls.
    bool saddle_corners = true;
    /// With sharp_features: each face of a sharp pair ended by the other face's tangent plane at
    /// their crossing (step 4), else both by one plane between the faces.
    bool pair_tangent_planes = true;
    /// Accept a fit only where its zero set in the ball (on its plane's side) stays within 2 point
    /// spacings of the input points and inside their edges (src/slim/build.cpp `support_fraction`;
    /// step 3 above): a quadric continued past an edge or a second sheet would be drawn by the
    /// renderers.
    bool support_check = true;
    /// The support check's normal test: a zero-set sample needs an input point within the support
    /// distance whose normal n has n . g > support_normal_cos |g| (g the quadric's gradient there).
    double support_normal_cos = -0.5;
    /// The support check's boundary test: seen from a zero-set sample, the input points within 1.5
    /// support distances (3 point spacings, at least 3 E) whose normals are within 60 degrees (or
    /// sharp_angle_degrees, if smaller) of the quadric's gradient (projected on the tangent plane)
    /// leave no angular gap wider than this. A sheet's edge leaves 180 degrees;
    /// a quadric continued past a crease or a point cloud's border (a fin) more. 360: off.
    double support_max_gap_degrees = 240;
    /// A fit whose support check fails at a sample is still accepted when every sample nearer to
    /// the centre than this fraction of the radius passes; its record is then drawn in the ball
    /// of 0.9 times the distance to that sample (the rest of the fitting ball is cut off).
    double min_support_fraction = 0.5;
    /// The support check samples the zero set on lines about 4/3 point spacings apart, at least 13
    /// and at most this many per side of the ball's square ([13, 201]).
    int support_max_lines = 51;
    /// In a small ball across a crease (radius at most 3 E, its normals split into two flat parts
    /// more than sharp_angle apart),
    /// a single quadric or the plane fallback is accepted only where its gradient at each point is
    /// within this angle of the point's normal: in a small ball a quadric rounding the crease, or a
    /// plane tilted between its faces, is within E of the points but would shade them with a
    /// normal between the faces' (a flake). Such a ball ends as a pair of planes (step 5) or a
    /// smaller ball. 180: off.
    double crease_normal_degrees = 30;
    double sharp_angle_degrees = 60;
    double sharp_min_fraction = 0.1;
    double sharp_max_misclassified = 0.02;  ///< fraction of the ball's points the plane may put on the wrong side
    std::uint64_t seed = 1;
    int threads = 0;                   ///< 0: TBB's default
    FitOptions fit;
    std::function<void(const BuildProgress&)> progress;  ///< after each batch, from the calling thread
};

struct BuildStats {
    std::size_t points = 0;
    std::size_t balls = 0;             ///< records (a sharp pair is two)
    std::size_t sharp_pairs = 0;
    std::size_t corners = 0;           ///< corners (three records each, four at a saddle)
    std::size_t saddles = 0;           ///< of them saddle corners (four records)
    std::size_t forced = 0;            ///< records kept although their fit exceeds E
    std::size_t fits = 0;              ///< quadric fits computed (dropped seeds included: depends on the threads)
    std::size_t dropped_seeds = 0;     ///< computed in a batch, then covered by an earlier ball (depends on the threads)
    double diagonal = 0;               ///< of the points' bounding box
    double threshold = 0;              ///< E in world units
    double seconds = 0;
    double rms_distance = 0;           ///< over the input points, to the surface of the record that covers them
    double max_distance = 0;
    std::size_t over_threshold = 0;    ///< input points farther than E from their covering record's surface
};

struct BuildResult {
    Model model;
    BuildStats stats;
    std::vector<std::uint32_t> covered_by;  ///< per input point, the index of its record
    std::vector<unsigned char> forced;      ///< per record: 1 when it is a forced ball's
};

/// Builds the SLIM model of oriented points. Throws std::invalid_argument naming the option
/// ("quadcast::slim::build: error must be positive and finite (got 0)") or when there are fewer
/// than min_points points.
BuildResult build(const OrientedPoints& points, const BuildOptions& options);

}  // namespace quadcast::slim
