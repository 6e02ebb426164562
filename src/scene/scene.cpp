// src/scene/scene.cpp -- camera validation, quadric matrices, bounding boxes
#include "quadcast/scene/scene.hpp"

#include "quadcast/bilinear.hpp"
#include "quadcast/quadric.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

namespace quadcast::scene {

// Diagnostics ----------------------------------------------------------------------------------

std::string format_location(const Location& where) {
    std::string s;
    if (!where.file.empty()) {
        s += where.file;
        if (where.line > 0) {
            s += ':' + std::to_string(where.line);
            if (where.column > 0) s += ':' + std::to_string(where.column);
        }
        s += ": ";
    }
    if (!where.field.empty()) {
        // A pointer holds keys from the input: keep a long one short like a quoted token.
        if (where.field.size() > 4 * max_token_chars) s += where.field.substr(0, 4 * max_token_chars) + "...: ";
        else s += where.field + ": ";
    }
    return s;
}

ParseError::ParseError(Location where, const std::string& message)
    : std::runtime_error(format_location(where) + message), where_(std::move(where)), message_(message) {}

ParseErrors::ParseErrors(std::vector<ParseError> errors)
    : ParseError(errors.at(0).where(), errors.at(0).message()), errors_(std::move(errors)) {
    for (std::size_t i = 0; i < errors_.size() && i < max_reported; ++i) text_ += (i ? "\n" : "") + std::string(errors_[i].what());
    if (errors_.size() > max_reported)
        text_ += "\n... and " + std::to_string(errors_.size() - max_reported) + " more error" +
                 (errors_.size() - max_reported > 1 ? "s" : "");
}

std::string quote_token(std::string_view text) {
    if (text.size() <= max_token_chars) return "'" + std::string(text) + "'";
    // Cut at a UTF-8 character boundary.
    std::size_t n = max_token_chars;
    while (n > 0 && (static_cast<unsigned char>(text[n]) & 0xC0) == 0x80) --n;
    return "'" + std::string(text.substr(0, n)) + "...' (" + std::to_string(text.size()) + " bytes)";
}

std::vector<std::string> line_tokens(std::string_view line, bool comments) {
    if (comments)
        if (const auto hash = line.find('#'); hash != std::string_view::npos) line = line.substr(0, hash);
    std::vector<std::string> t;
    std::size_t i = 0;
    while (i < line.size()) {
        while (i < line.size() && std::isspace(static_cast<unsigned char>(line[i]))) ++i;
        std::size_t j = i;
        while (j < line.size() && !std::isspace(static_cast<unsigned char>(line[j]))) ++j;
        if (j > i) t.emplace_back(line.substr(i, j - i));
        i = j;
    }
    return t;
}

std::optional<double> parse_decimal(std::string_view token) {
    const char* b = token.data();
    const char* e = token.data() + token.size();
    if (!token.empty() && token[0] == '+') ++b;
    double v = 0.0;
    const auto [p, ec] = std::from_chars(b, e, v);
    if (ec != std::errc() || p != e) return std::nullopt;
    return v;
}

// Camera ---------------------------------------------------------------------------------------

namespace {
bool finite3(const Vec3d& v) { return std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]); }
}  // namespace

Camera::Problem Camera::check() const {
    if (!finite3(eye)) return {"eye", "not finite"};
    if (!finite3(target)) return {"target", "not finite"};
    if (!finite3(up)) return {"up", "not finite"};
    const Vec3d dir = target - eye;
    const double ld = length(dir);
    if (!std::isfinite(ld))
        return {"eye", "is too far from target: |target - eye| overflows a double (not a zero view direction)"};
    if (!(ld > 0.0)) return {"target", "equals eye (no view direction)"};
    const double lu = length(up);
    if (!std::isfinite(lu)) return {"up", "is too long: its length overflows a double"};
    if (!(lu > 0.0)) return {"up", "is the zero vector"};
    // |sin(angle)| between up and the view direction; 1e-3 is about 0.06 degrees.
    const double s = length(cross(dir / ld, up / lu));
    if (!(s > 1e-3)) return {"up", "is parallel to the view direction (target - eye)"};
    if (!std::isfinite(near) || !(near > 0.0)) return {"near", "must be > 0"};
    if (!std::isfinite(far) || !(far > near)) return {"far", "must be > near"};
    if (projection == Projection::perspective) {
        if (!std::isfinite(fov_y_deg) || !(fov_y_deg > 0.0 && fov_y_deg < 180.0))
            return {"fov_y", "must be in (0, 180) degrees"};
    } else {
        if (!std::isfinite(height) || !(height > 0.0)) return {"height", "must be > 0"};
    }
    return {};
}

void Camera::validate() const {
    const Problem p = check();
    if (!p.field.empty()) throw std::invalid_argument("camera " + p.field + ": " + p.message);
}

// Quadrics -------------------------------------------------------------------------------------

Mat4d quadric_matrix_from_coefficients(const std::array<double, 10>& k) {
    // The core's conversion (Stoll et al. 2006, eq. 3-4), so the formula exists once.
    return quadcast::quadric_from_coefficients(
               quadcast::Coefficients10<double>{k[0], k[1], k[2], k[3], k[4], k[5], k[6], k[7], k[8], k[9]})
        .q;
}

// Boxes ----------------------------------------------------------------------------------------

void Aabb::extend(const Vec3d& p) {
    for (int i = 0; i < 3; ++i) {
        lo[i] = std::min(lo[i], p[i]);
        hi[i] = std::max(hi[i], p[i]);
    }
}
void Aabb::extend(const Vec3d& c, const Vec3d& h) {
    extend(c - h);
    extend(c + h);
}
void Aabb::extend(const Aabb& b) {
    if (b.empty()) return;
    extend(b.lo);
    extend(b.hi);
}
// (halves first, and the diagonal scaled by its largest component: no overflow for boxes
// near the double range)
Vec3d Aabb::center() const { return empty() ? Vec3d{{0.0, 0.0, 0.0}} : lo * 0.5 + hi * 0.5; }
double Aabb::radius() const {
    if (empty()) return 0.0;
    const Vec3d h = hi * 0.5 - lo * 0.5;
    const double m = std::max({h[0], h[1], h[2]});
    return m > 0.0 ? m * length(h / m) : 0.0;
}

Aabb bounds(const Sphere& s) {
    Aabb b;
    b.extend(s.center, splat<double, 3>(s.radius));
    return b;
}

Aabb bounds(const Ellipsoid& e) {
    // The support of the ellipsoid along coordinate axis i is |(a_i, b_i, c_i)|.
    Vec3d h{};
    for (int i = 0; i < 3; ++i)
        h[i] = std::sqrt(e.axes[0][i] * e.axes[0][i] + e.axes[1][i] * e.axes[1][i] + e.axes[2][i] * e.axes[2][i]);
    Aabb b;
    b.extend(e.center, h);
    return b;
}

namespace {
/// Half extents of a disc of radius r perpendicular to the unit vector d.
Vec3d disc_extent(const Vec3d& d, double r) {
    Vec3d h{};
    for (int i = 0; i < 3; ++i) h[i] = r * std::sqrt(std::max(0.0, 1.0 - d[i] * d[i]));
    return h;
}
}  // namespace

Aabb bounds(const Cylinder& c) {
    const Vec3d axis = c.p1 - c.p0;
    const double l = length(axis);
    const Vec3d h = l > 0.0 ? disc_extent(axis / l, c.radius) : splat<double, 3>(c.radius);
    Aabb b;
    b.extend(c.p0, h);
    b.extend(c.p1, h);
    return b;
}

Aabb bounds(const Cone& c) {
    const Vec3d axis = c.base - c.apex;
    const double l = length(axis);
    const Vec3d h = l > 0.0 ? disc_extent(axis / l, c.radius) : splat<double, 3>(c.radius);
    Aabb b;
    b.extend(c.base, h);
    b.extend(c.apex);
    return b;
}

Aabb bounds(const Quadric& q) {
    Aabb b;
    if (q.bound == Quadric::Bound::sphere)
        b.extend(q.sphere.center, splat<double, 3>(q.sphere.radius));
    else
        for (const Vec3d& p : q.tetrahedron.p) b.extend(p);
    return b;
}

Aabb bounds(const BilinearQuad& q) {
    // A bilinear patch lies in the convex hull of its corners.
    Aabb b;
    for (const Vec3d& p : q.p) b.extend(p);
    return b;
}

Aabb Scene::bounds() const {
    Aabb b;
    for (const auto& x : spheres) b.extend(scene::bounds(x));
    for (const auto& x : ellipsoids) b.extend(scene::bounds(x));
    for (const auto& x : cylinders) b.extend(scene::bounds(x));
    for (const auto& x : cones) b.extend(scene::bounds(x));
    for (const auto& x : quadrics) b.extend(scene::bounds(x));
    for (const auto& x : quads) {
        // (segments and points are not drawn: they neither move the frame nor the fitted camera)
        const QuadKind k = classify_quad(x.p[0], x.p[1], x.p[2], x.p[3]);
        if (k != QuadKind::segment && k != QuadKind::point && k != QuadKind::non_finite) b.extend(scene::bounds(x));
    }
    for (const auto& x : volumes)
        if (!x.box.empty()) b.extend(x.box);
    for (const auto& x : slims)
        for (const auto& ball : x.balls) b.extend(ball.center, Vec3d{{ball.radius, ball.radius, ball.radius}});
    return b;
}

namespace {
VolumeBoxFunction g_volume_box = nullptr;
}

void set_volume_box_function(VolumeBoxFunction f) { g_volume_box = f; }

namespace {
SlimLoadFunction g_slim_load = nullptr;
}
void set_slim_load_function(SlimLoadFunction f) { g_slim_load = f; }
SlimLoadFunction slim_load_function() { return g_slim_load; }

namespace {
SkinBuildFunction g_skin_build = nullptr;
}
void set_skin_build_function(SkinBuildFunction f) { g_skin_build = f; }
SkinBuildFunction skin_build_function() { return g_skin_build; }
VolumeBoxFunction volume_box_function() { return g_volume_box; }

Location Scene::location(const Origin& o) const {
    return {source.string(), o.line, o.column, "/objects/" + std::to_string(o.object) + "/" + std::string(o.kind)};
}

std::size_t Scene::primitive_count() const {
    return spheres.size() + ellipsoids.size() + cylinders.size() + cones.size() + quadrics.size() + quads.size() + volumes.size() + slims.size();
}

Camera fit_camera(const Aabb& box, double fov_y_deg) {
    Camera cam;
    cam.fov_y_deg = fov_y_deg;
    if (box.empty()) return cam;
    const double r = box.radius() > 0.0 ? box.radius() : 1.0;  // (a single point: a unit view)
    const double half = 0.5 * fov_y_deg * std::numbers::pi / 180.0;
    const double dist = 1.05 * r / std::sin(half);
    cam.target = box.center();
    cam.eye = cam.target + Vec3d{{0.0, 0.0, dist}};
    cam.up = Vec3d{{0.0, 1.0, 0.0}};
    cam.near = std::max(dist - 1.1 * r, 1e-3 * dist);
    cam.far = dist + 1.1 * r;
    return cam;
}

}  // namespace quadcast::scene
