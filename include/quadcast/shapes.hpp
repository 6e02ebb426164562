// quadcast/shapes.hpp -- the public way from shapes and cameras to what both renderers draw
#pragma once

// Host-only (double precision inside, Eigen for eigen-decompositions, exceptions). Every
// function validates its input and throws std::invalid_argument naming the function and the
// field ("quadcast::shapes::cylinder: radius must be positive and finite (got -1)"); what it
// returns is a render::Primitive / render::Camera that quadcast::gl::QuadricRenderer and
// quadcast::render::render_cpu draw alike. GLM types at this boundary (quadcast/glm_interop.hpp).
//
// Each primitive is stored around its bounding sphere: the quadric in local coordinates
// x_local = x - center (coefficients small, the re-origined discriminant accurate), the
// bounding sphere tight around the clipped surface (what the renderers rasterise).

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>

#include <Eigen/Dense>
#include <glm/mat3x3.hpp>
#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include "quadcast/bilinear.hpp"
#include "quadcast/bounds.hpp"
#include "quadcast/camera.hpp"
#include "quadcast/glm_interop.hpp"
#include "quadcast/primitives.hpp"
#include "quadcast/primitives_host.hpp"
#include "quadcast/quadric.hpp"
#include "quadcast/ray.hpp"
#include "quadcast/render/types.hpp"
#include "quadcast/render/validate.hpp"

namespace quadcast::shapes {

/// Colour (linear RGB in [0, 1]) and Blinn-Phong material of a shape.
struct Appearance {
    glm::vec3 color{0.8f, 0.8f, 0.8f};
    float specular = 0.35f;   ///< in [0, 1]
    float shininess = 48.0f;  ///< > 0
};

/// Which ends of a cylinder are closed by discs.
enum class Ends { both, none, first, second };

/// The bounding sphere a general quadric is clipped to.
struct SphereBound {
    glm::vec3 center;
    float radius;
};

/// The tetrahedron a general quadric is clipped to.
struct TetrahedronBound {
    std::array<glm::vec3, 4> corners;
};

namespace detail {

using V3 = Vec3<double>;

inline std::string num(double x) {
    std::ostringstream s;
    s.precision(9);
    s << x;
    return s.str();
}

[[noreturn]] inline void fail(const char* fn, const std::string& what) {
    throw std::invalid_argument(std::string("quadcast::shapes::") + fn + ": " + what);
}

inline V3 point(const char* fn, const char* field, const glm::vec3& p) {
    for (int i = 0; i < 3; ++i)
        if (!std::isfinite(p[i])) fail(fn, std::string(field) + " must be finite (got (" + num(p[0]) + ", " + num(p[1]) + ", " + num(p[2]) + "))");
    return vec3(double(p[0]), double(p[1]), double(p[2]));
}

inline double positive(const char* fn, const char* field, double x) {
    if (!(x > 0) || !std::isfinite(x)) fail(fn, std::string(field) + " must be positive and finite (got " + num(x) + ")");
    return x;
}

inline void appearance(const char* fn, const Appearance& a) {
    for (int i = 0; i < 3; ++i)
        if (!(a.color[i] >= 0.0f && a.color[i] <= 1.0f)) fail(fn, "color components must be in [0, 1] (got " + num(a.color[i]) + ")");
    if (!(a.specular >= 0.0f && a.specular <= 1.0f)) fail(fn, "specular must be in [0, 1] (got " + num(a.specular) + ")");
    positive(fn, "shininess", a.shininess);
}

/// A float value that must stay finite and nonzero-normal (the GPU stores floats).
inline float to_float(const char* fn, const char* field, double x) {
    const float f = static_cast<float>(x);
    if (!std::isfinite(f)) fail(fn, std::string(field) + " " + num(x) + " is outside the float range");
    return f;
}

/// The quadric scaled so that its largest coefficient has magnitude 1 (the zero set and the
/// inside (f < 0) do not change; float over- and underflow of the ray coefficients does not
/// happen for any representable shape).
inline Quadric<double> normalized(const char* fn, const Quadric<double>& q) {
    double m = 0;
    for (int j = 0; j < 4; ++j)
        for (int i = 0; i < 4; ++i) {
            if (!std::isfinite(q.q[j][i])) fail(fn, "the quadric has a coefficient that is not finite");
            m = std::max(m, std::fabs(q.q[j][i]));
        }
    if (!(m > 0)) fail(fn, "the quadric is zero");
    Quadric<double> r = q;
    for (int j = 0; j < 4; ++j)
        for (int i = 0; i < 4; ++i) r.q[j][i] /= m;
    return r;
}

inline render::Primitive make(const char* fn, const Quadric<double>& local, const V3& center, double radius, render::Variant variant,
                              const Appearance& look, const V3& axis = vec3(0.0, 0.0, 1.0),
                              double half_length = std::numeric_limits<double>::infinity()) {
    appearance(fn, look);
    const Quadric<double> q = normalized(fn, local);
    render::Primitive p{};
    p.shape.q.q = cast<float>(q.q);
    for (int i = 0; i < 3; ++i) p.shape.center[i] = to_float(fn, "center", center[i]);
    p.shape.radius = to_float(fn, "bounding radius", radius);
    if (!(p.shape.radius > 0)) fail(fn, "the bounding radius " + num(radius) + " underflows float");
    p.shape.axis = cast<float>(axis);
    p.shape.half_length = std::isinf(half_length) ? std::numeric_limits<float>::infinity() : to_float(fn, "half length", half_length);
    p.variant = variant;
    p.color = vec3(look.color[0], look.color[1], look.color[2]);
    p.material.specular = look.specular;
    p.material.shininess = look.shininess;
    return p;
}

/// Centre (centroid) and radius (farthest point, + 1e-6 relative) of a sphere around the points.
template <std::size_t N>
void bounding_sphere(const std::array<V3, N>& pts, V3& c, double& r) {
    c = vec3(0.0, 0.0, 0.0);
    for (const V3& p : pts) c = c + p;
    c = c / static_cast<double>(N);
    r = 0;
    for (const V3& p : pts) r = std::max(r, length(p - c));
    r *= 1.0 + 1e-6;
}

/// An ellipsoid with semi-axis vectors u, v, w around the local origin: Q = T^-T D T^-1.
inline render::Primitive ellipsoid_from_axes(const char* fn, const V3& center, const V3& u, const V3& v, const V3& w, const Appearance& look) {
    const V3 zero = vec3(0.0, 0.0, 0.0);
    const double vol = std::fabs(dot(u, cross(v, w)));
    const double lu = length(u), lv = length(v), lw = length(w);
    if (!(lu > 0 && lv > 0 && lw > 0) || !std::isfinite(lu * lv * lw)) fail(fn, "every semi-axis must be nonzero and finite");
    if (!(vol > 1e-9 * lu * lv * lw)) fail(fn, "the semi-axes are (nearly) linearly dependent");
    const Quadric<double> q = host::quadric_from_form(quadcast::ellipsoid(zero, u, v, w));
    return make(fn, q, center, std::max({lu, lv, lw}), render::Variant::ellipsoid, look);
}

}  // namespace detail

/// A sphere.
inline render::Primitive sphere(const glm::vec3& center, float radius, const Appearance& look = {}) {
    const char* fn = "sphere";
    const detail::V3 c = detail::point(fn, "center", center);
    const double r = detail::positive(fn, "radius", radius);
    Quadric<double> q{identity<double, 4>()};
    q.q[3][3] = -r * r;
    return detail::make(fn, q, c, r, render::Variant::sphere, look);
}

/// An ellipsoid with three semi-axis vectors (the columns of `axes`; they need not be orthogonal,
/// but must not be linearly dependent).
inline render::Primitive ellipsoid(const glm::vec3& center, const glm::mat3& axes, const Appearance& look = {}) {
    const char* fn = "ellipsoid";
    const detail::V3 c = detail::point(fn, "center", center);
    const detail::V3 u = detail::point(fn, "axes[0]", axes[0]), v = detail::point(fn, "axes[1]", axes[1]), w = detail::point(fn, "axes[2]", axes[2]);
    return detail::ellipsoid_from_axes(fn, c, u, v, w, look);
}

/// An ellipsoid with radii along the columns of the rotation matrix `rotation` (orthonormal,
/// determinant +1, within 1e-4).
inline render::Primitive ellipsoid(const glm::vec3& center, const glm::vec3& radii, const glm::mat3& rotation, const Appearance& look = {}) {
    const char* fn = "ellipsoid";
    const detail::V3 c = detail::point(fn, "center", center);
    detail::V3 col[3];
    for (int j = 0; j < 3; ++j) {
        detail::positive(fn, j == 0 ? "radii.x" : j == 1 ? "radii.y" : "radii.z", radii[j]);
        col[j] = detail::point(fn, "rotation", rotation[j]);
    }
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            if (std::fabs(dot(col[i], col[j]) - (i == j ? 1.0 : 0.0)) > 1e-4) detail::fail(fn, "rotation is not orthonormal");
    if (dot(col[0], cross(col[1], col[2])) < 0) detail::fail(fn, "rotation has determinant -1 (a reflection)");
    return detail::ellipsoid_from_axes(fn, c, col[0] * double(radii[0]), col[1] * double(radii[1]), col[2] * double(radii[2]), look);
}

/// The principal axes of a symmetric positive-definite tensor (Eigen's SelfAdjointEigenSolver):
/// eigenvalues in decreasing order and unit eigenvectors (columns, right-handed).
struct TensorAxes {
    glm::vec3 eigenvalues;
    glm::mat3 eigenvectors;
};

inline TensorAxes tensor_axes(const glm::mat3& tensor) {
    const char* fn = "tensor_axes";
    Eigen::Matrix3d m;
    for (int j = 0; j < 3; ++j)
        for (int i = 0; i < 3; ++i) {
            if (!std::isfinite(tensor[j][i])) detail::fail(fn, "the tensor has an entry that is not finite");
            m(i, j) = tensor[j][i];
        }
    const double scale = m.cwiseAbs().maxCoeff();
    if (!(scale > 0)) detail::fail(fn, "the tensor is zero");
    if ((m - m.transpose()).cwiseAbs().maxCoeff() > 1e-5 * scale) detail::fail(fn, "the tensor is not symmetric");
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(0.5 * (m + m.transpose()));
    if (es.info() != Eigen::Success) detail::fail(fn, "the eigen-decomposition did not converge");
    TensorAxes t{};
    // Eigen sorts ascending; the glyph convention is the major axis first.
    Eigen::Vector3d e[3];
    for (int k = 0; k < 3; ++k) {
        t.eigenvalues[k] = static_cast<float>(es.eigenvalues()[2 - k]);
        e[k] = es.eigenvectors().col(2 - k);
    }
    if (e[0].cross(e[1]).dot(e[2]) < 0) e[2] = -e[2];
    for (int k = 0; k < 3; ++k)
        for (int i = 0; i < 3; ++i) t.eigenvectors[k][i] = static_cast<float>(e[k][i]);
    return t;
}

/// The usual colour of a tensor glyph: the absolute components of its major eigenvector (red =
/// x, green = y, blue = z).
inline glm::vec3 principal_direction_color(const glm::mat3& tensor) {
    const TensorAxes t = tensor_axes(tensor);
    return {std::fabs(t.eigenvectors[0][0]), std::fabs(t.eigenvectors[0][1]), std::fabs(t.eigenvectors[0][2])};
}

/// A tensor glyph: the ellipsoid whose semi-axes are the eigenvectors of a symmetric
/// positive-definite tensor scaled by `scale` times their eigenvalues.
inline render::Primitive tensor_ellipsoid(const glm::vec3& center, const glm::mat3& tensor, float scale = 1.0f, const Appearance& look = {}) {
    const char* fn = "tensor_ellipsoid";
    detail::positive(fn, "scale", scale);
    const TensorAxes t = tensor_axes(tensor);
    if (!(t.eigenvalues[2] > 0)) detail::fail(fn, "the tensor is not positive definite (smallest eigenvalue " + detail::num(t.eigenvalues[2]) + ")");
    glm::mat3 axes;
    for (int k = 0; k < 3; ++k) axes[k] = t.eigenvectors[k] * (t.eigenvalues[k] * scale);
    const detail::V3 c = detail::point(fn, "center", center);
    return detail::ellipsoid_from_axes(fn, c, detail::point(fn, "axes", axes[0]), detail::point(fn, "axes", axes[1]), detail::point(fn, "axes", axes[2]), look);
}

/// A circular cylinder of `radius` from p0 to p1; `ends` says which end discs close it. A
/// cylinder with an open end is two-sided: its inside shows through the opening.
inline render::Primitive cylinder(const glm::vec3& p0, const glm::vec3& p1, float radius, Ends ends = Ends::both, const Appearance& look = {}) {
    const char* fn = "cylinder";
    const detail::V3 a0 = detail::point(fn, "p0", p0), a1 = detail::point(fn, "p1", p1);
    const double r = detail::positive(fn, "radius", radius);
    const detail::V3 d = a1 - a0;
    const double h = 0.5 * length(d);
    if (!(h > 0)) detail::fail(fn, "p0 and p1 coincide");
    if (!std::isfinite(h)) detail::fail(fn, "|p1 - p0| overflows");
    const detail::V3 axis = d / (2.0 * h);
    detail::V3 b1{}, b2{};
    orthonormal_basis(axis, b1, b2);
    const Quadric<double> q = host::quadric_from_form(elliptic_cylinder(vec3(0.0, 0.0, 0.0), b1 * r, b2 * r, axis * h));
    const bool closed = ends == Ends::both;
    render::Primitive p = detail::make(fn, q, 0.5 * (a0 + a1), std::sqrt(r * r + h * h), closed ? render::Variant::slab : render::Variant::open_slab, look, axis, h);
    // caps[0] closes the end +half_length along the axis (p1), caps[1] the end at p0.
    p.shape.caps = vec2(ends == Ends::both || ends == Ends::second ? 1.0f : 0.0f, ends == Ends::both || ends == Ends::first ? 1.0f : 0.0f);
    return p;
}

/// A circular cone from `apex` to the disc of `radius` centred at `base`; `cap` closes the base.
/// An open cone is two-sided.
inline render::Primitive cone(const glm::vec3& apex, const glm::vec3& base, float radius, bool cap = true, const Appearance& look = {}) {
    const char* fn = "cone";
    const detail::V3 ap = detail::point(fn, "apex", apex), bc = detail::point(fn, "base", base);
    const double r = detail::positive(fn, "radius", radius);
    const detail::V3 w = bc - ap;
    const double H = length(w);
    if (!(H > 0)) detail::fail(fn, "apex and base coincide");
    if (!std::isfinite(H)) detail::fail(fn, "|base - apex| overflows");
    const detail::V3 mid = 0.5 * (ap + bc);
    detail::V3 b1{}, b2{};
    orthonormal_basis(w / H, b1, b2);
    const Quadric<double> q = host::quadric_from_form(elliptic_cone(ap - mid, b1 * r, b2 * r, w));
    // The slab axis points from the base to the apex (the apex end +H/2 meets the quadric's inside
    // only at the apex: it needs no cap).
    render::Primitive p = detail::make(fn, q, mid, std::sqrt(r * r + 0.25 * H * H), cap ? render::Variant::slab : render::Variant::open_slab, look, -w / H, 0.5 * H);
    p.shape.caps = vec2(0.0f, cap ? 1.0f : 0.0f);
    return p;
}

/// The homogeneous matrix Q (x~^T Q x~ = 0, x~ = (x, y, z, 1); symmetrised as (Q + Q^T) / 2) of
/// a general quadric, clipped to a sphere. Q is taken in double and moved to the bound's centre
/// before it is rounded to float: give it in double (glm::dmat4) when the bound lies far from the
/// origin compared with its size (a float Q's constant term there has lost the surface).
inline render::Primitive quadric(const glm::dmat4& q_world, const SphereBound& bound, const Appearance& look = {}) {
    const char* fn = "quadric";
    const detail::V3 c = detail::point(fn, "bound.center", bound.center);
    const double r = detail::positive(fn, "bound.radius", bound.radius);
    Quadric<double> q{};
    for (int j = 0; j < 4; ++j)
        for (int i = 0; i < 4; ++i) q.q[j][i] = 0.5 * (q_world[j][i] + q_world[i][j]);
    q = detail::normalized(fn, q);
    return detail::make(fn, translate_to_eye(q, c), c, r, render::Variant::bounded, look);
}
inline render::Primitive quadric(const glm::mat4& q_world, const SphereBound& bound, const Appearance& look = {}) {
    return quadric(glm::dmat4(q_world), bound, look);
}

/// A general quadric clipped to a tetrahedron (whose corners must span a volume); Q in double
/// as above (e.g. the pieces of a finite-element mesh far from the origin).
inline render::Primitive quadric(const glm::dmat4& q_world, const TetrahedronBound& bound, const Appearance& look = {}) {
    const char* fn = "quadric";
    std::array<detail::V3, 4> p{};
    for (int i = 0; i < 4; ++i) p[static_cast<std::size_t>(i)] = detail::point(fn, "bound.corners", bound.corners[static_cast<std::size_t>(i)]);
    Quadric<double> q{};
    for (int j = 0; j < 4; ++j)
        for (int i = 0; i < 4; ++i) q.q[j][i] = 0.5 * (q_world[j][i] + q_world[i][j]);
    q = detail::normalized(fn, q);
    detail::V3 c;
    double r;
    detail::bounding_sphere(p, c, r);
    const TetShape<double> shape = tet_shape(p);
    if (!std::isfinite(shape.vol6) || !std::isfinite(shape.longest)) detail::fail(fn, "the tetrahedron's size overflows");
    if (shape.flatter_than(1e-12)) detail::fail(fn, "the tetrahedron is flat (its corners are coplanar)");
    render::Primitive prim = detail::make(fn, translate_to_eye(q, c), c, r, render::Variant::planes, look);
    BoundingTet<double> t{};
    for (int i = 0; i < 4; ++i) t.p[i] = p[static_cast<std::size_t>(i)] - c;
    // Each face plane scaled to the barycentric coordinate of its opposite corner (1 there).
    const TetPlanes<double> pl = barycentric_planes(t);
    for (int i = 0; i < 4; ++i) prim.shape.planes[i] = cast<float>(pl.plane[i]);
    // The tetrahedron the float planes bound, each moved out by the clip test's slack (what the
    // renderers accept): for a sliver (the triangulated mixed complex of a skin surface has many)
    // its corners lie measurably off the double ones. The bounding sphere must hold them, or the
    // renderers would crop the piece, and occlusion culling, which takes every surface point to
    // lie in the ball, would cull a visible one (quadcast::planes_within_ball).
    // (The extent as render::validate measures it, so that the two agree however thin it is.)
    double e = 0;
    try {
        Vec4<float> slack[4];
        for (int i = 0; i < 4; ++i) slack[i] = prim.shape.planes[i] + vec4(0.0f, 0.0f, 0.0f, float(clip_plane_slack));
        e = render::validate_detail::tet_extent(0, slack);
    } catch (const std::invalid_argument&) {
        detail::fail(fn, "the tetrahedron is too flat for float clip planes");
    }
    if (e > r) prim.shape.radius = detail::to_float(fn, "bounding radius", e * (1 + 1e-6));
    return prim;
}
inline render::Primitive quadric(const glm::mat4& q_world, const TetrahedronBound& bound, const Appearance& look = {}) {
    return quadric(glm::dmat4(q_world), bound, look);
}

/// The four clip planes of a quad (local coordinates around `c`) and the slab half-thickness
/// along `axis` that keep exactly the patch of its quadric. See `quad`.
struct QuadClip {
    Vec4<double> planes[4];
    Vec3<double> axis;
    double half_length;
};

namespace detail {

/// The unit normal of the quad's largest corner triangle (robust for triangles with a repeated
/// corner).
inline V3 quad_normal(const std::array<V3, 4>& q) {
    V3 n = vec3(0.0, 0.0, 0.0);
    for (std::size_t i = 0; i < 4; ++i) {
        const V3 m = cross(q[(i + 1) % 4] - q[i], q[(i + 3) % 4] - q[i]);
        if (length(m) > length(n)) n = m;
    }
    return n / length(n);
}

/// The edges of the quad extruded along its unit normal n, each plane scaled to 1 at the
/// farthest corner, and the slab |n.x| <= half-thickness + 2^-10 r: exact for a (nearly) planar
/// quad whose outline seen along n is convex, well conditioned however flat it is.
inline QuadClip extruded_edges(const std::array<V3, 4>& q, const V3& c, const V3& n, double r) {
    QuadClip k{};
    double thick = 0;
    for (const V3& corner : q) thick = std::max(thick, std::fabs(dot(n, corner - c)));
    k.axis = n;
    k.half_length = thick + r * 0x1.0p-10;
    for (int i = 0; i < 4; ++i) {
        const V3 a = q[static_cast<std::size_t>(i)] - c, b = q[static_cast<std::size_t>((i + 1) % 4)] - c;
        const V3 e = cross(n, b - a);
        const double le = length(e);
        if (!(le > 0)) { k.planes[i] = vec4(0.0, 0.0, 0.0, 1.0); continue; }  // repeated corner: no constraint
        const Vec4<double> pl = vec4(e / le, -dot(e / le, a));
        double far = 0;
        for (const V3& corner : q) far = std::max(far, dot(pl, vec4(corner - c, 1.0)));
        k.planes[i] = far > 0 ? pl / far : pl;
    }
    return k;
}

/// The patch's own parameters as planes: on its hyperbolic paraboloid the bilinear parameters
/// are affine functions of the point, u = n_u.(x - p1) / n_u.(p2 - p1) with n_u = (p4 - p1) x f and
/// v = n_v.(x - p1) / n_v.(p4 - p1) with n_v = (p2 - p1) x f, f = p1 - p2 + p3 - p4 (the rulings of
/// each family are parallel to a director plane; in Stoll's local frame u = x' - (e/g) z',
/// v = y' - (f/g) z'). The planes u >= 0, 1 - u >= 0, v >= 0, 1 - v >= 0 keep exactly the patch
/// (the map (u, v) -> P(u, v) covers the quadric once), for every twist; no slab is needed.
inline QuadClip director_planes(const std::array<V3, 4>& q, const V3& c) {
    const V3 p1 = q[0] - c, p2 = q[1] - c, p3 = q[2] - c, p4 = q[3] - c;
    const V3 f = (p1 - p2) + (p3 - p4);
    const V3 nu = cross(p4 - p1, f), nv = cross(p2 - p1, f);
    const Vec4<double> u = vec4(nu, -dot(nu, p1)) / dot(nu, p2 - p1);
    const Vec4<double> v = vec4(nv, -dot(nv, p1)) / dot(nv, p4 - p1);
    const Vec4<double> one = vec4(0.0, 0.0, 0.0, 1.0);
    QuadClip k{};
    k.planes[0] = v;          // edge p1 p2 (v = 0)
    k.planes[1] = one - u;    // edge p2 p3 (u = 1)
    k.planes[2] = one - v;    // edge p3 p4 (v = 1)
    k.planes[3] = u;          // edge p4 p1 (u = 0)
    k.axis = vec3(0.0, 0.0, 1.0);
    k.half_length = std::numeric_limits<double>::infinity();
    return k;
}

}  // namespace detail

/// How `quad` clips a non-planar quad's quadric to its patch: by the patch's own (u, v) range
/// (`detail::director_planes`, exact for every twist) unless the quad is so flat that those planes
/// are nearly tangent to it, where the extruded edges (`detail::extruded_edges`) are exact and
/// better conditioned. The switch: twist ratio max(|e|, |f|) / |g| of Stoll's local frame
/// (p3 = p1 + (1 + e)(p2 - p1) + (1 + f)(p4 - p1) + g n^ / L) above 8, and the outline seen along
/// the normal convex.
inline QuadClip quad_clip(const std::array<Vec3<double>, 4>& q, const Vec3<double>& c, double r) {
    using detail::V3;
    const V3 n = detail::quad_normal(q);
    // The outline seen along n is convex when every corner turns the same way.
    bool convex = true;
    for (int i = 0; i < 4; ++i) {
        const V3 m = cross(q[static_cast<std::size_t>((i + 1) % 4)] - q[static_cast<std::size_t>(i)], q[static_cast<std::size_t>((i + 3) % 4)] - q[static_cast<std::size_t>(i)]);
        if (length(m) > 0 && !(dot(m, n) > 0)) convex = false;
    }
    // Stoll's frame: p3 - p1 = (1 + e) a + (1 + f) b + g n^ with a = p2 - p1, b = p4 - p1.
    const V3 a = q[1] - q[0], b = q[3] - q[0], nn = cross(a, b);
    const double ln = length(nn);
    if (ln > 0) {
        // (columns a, b and the unit normal: the determinant is |a x b| > 0)
        const Mat3<double> m{{a, b, nn / ln}};
        double det_m = 0;
        const V3 s = inverse(m, det_m) * (q[2] - q[0]);
        const double size = std::max(length(a), length(b));
        const double g = std::fabs(s[2]) / size, twist = std::max(std::fabs(s[0] - 1.0), std::fabs(s[1] - 1.0));
        if (!convex || twist <= 8.0 * g) return detail::director_planes(q, c);
    }
    return detail::extruded_edges(q, c, n, r);
}

/// A bilinear patch P(u, v) = (1-u)(1-v) p1 + u(1-v) p2 + uv p3 + (1-u)v p4 (corners around the
/// perimeter; the front side is the one from which they appear counter-clockwise). Non-planar
/// quads are their quadric (Stoll et al. 2006, eq. 20-29) clipped to the patch (`quad_clip`);
/// planar quads and triangles (a repeated corner) their plane clipped by the extruded edges.
/// Collinear or coincident corners are an error.
inline render::Primitive quad(const glm::vec3& p1, const glm::vec3& p2, const glm::vec3& p3, const glm::vec3& p4, const Appearance& look = {}) {
    const char* fn = "quad";
    const std::array<detail::V3, 4> q = {detail::point(fn, "p1", p1), detail::point(fn, "p2", p2), detail::point(fn, "p3", p3), detail::point(fn, "p4", p4)};
    const QuadConversion<double> conv = quad_to_quadric(q[0], q[1], q[2], q[3]);
    if (conv.kind == QuadKind::segment || conv.kind == QuadKind::point) detail::fail(fn, "the corners are collinear or coincide");
    if (conv.kind == QuadKind::non_finite) detail::fail(fn, "the quad's size over- or underflows");
    detail::V3 c;
    double r;
    detail::bounding_sphere(q, c, r);
    QuadClip clip{};
    Quadric<double> local{};
    if (conv.ok()) {
        local = translate_to_eye(conv.local.quadric, c - conv.local.origin);
        clip = quad_clip(q, c, r);
    } else {
        // Planar quad or triangle: its plane n.x = n.p1.
        const detail::V3 n = detail::quad_normal(q);
        local.q = zero_mat<double, 4, 4>();
        for (int i = 0; i < 3; ++i) local.q[3][i] = local.q[i][3] = 0.5 * n[i];
        local.q[3][3] = -dot(n, q[0] - c);
        clip = detail::extruded_edges(q, c, n, r);
    }
    render::Primitive p = detail::make(fn, local, c, r, render::Variant::planes, look, clip.axis, clip.half_length);
    for (int i = 0; i < 4; ++i) p.shape.planes[i] = cast<float>(clip.planes[i]);
    return p;
}

/// A camera from a host application's own matrices: a rigid world -> view matrix (right-handed,
/// looking along -z) and an OpenGL projection, perspective (glm::perspective, glm::frustum) or
/// orthographic (glm::ortho). The eye is recovered from the view matrix.
inline render::Camera camera(const glm::mat4& view, const glm::mat4& projection) {
    return camera_from_matrices(from_glm(glm::dmat4(view)), from_glm(glm::dmat4(projection)));
}

/// A perspective camera at `eye` looking at `target` (fov_y: full vertical angle in degrees).
inline render::Camera perspective_camera(const glm::vec3& eye, const glm::vec3& target, const glm::vec3& up, double fov_y_deg, double aspect,
                                         double near, double far) {
    const char* fn = "perspective_camera";
    return camera_from_matrices(look_at(detail::point(fn, "eye", eye), detail::point(fn, "target", target), detail::point(fn, "up", up)),
                                perspective(fov_y_deg, aspect, near, far));
}

/// An orthographic camera at `eye` looking at `target`, `height` world units high.
inline render::Camera orthographic_camera(const glm::vec3& eye, const glm::vec3& target, const glm::vec3& up, double height, double aspect,
                                          double near, double far) {
    const char* fn = "orthographic_camera";
    return camera_from_matrices(look_at(detail::point(fn, "eye", eye), detail::point(fn, "target", target), detail::point(fn, "up", up)),
                                orthographic(height, aspect, near, far));
}

}  // namespace quadcast::shapes
