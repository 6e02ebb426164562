// quadcast/scene/scene.hpp -- the scene the `quadcast render` command draws (host-only, double)
#pragma once

// Plain data: the JSON loader (scene_json.hpp), the PDB reader (pdb.hpp) and the OFF reader
// (off.hpp) fill it; the renderers read it. Everything is in double precision and in world
// units (Angstrom for molecules). Nothing here is traced to GLSL.

#include <array>
#include <cmath>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "quadcast/scene/diagnostics.hpp"
#include "quadcast/linalg.hpp"
#include "quadcast/render/types.hpp"

namespace quadcast::scene {

using Vec3d = quadcast::Vec<double, 3>;
using Mat4d = quadcast::Mat<double, 4, 4>;

/// Surface appearance. `color` is linear RGB in [0,1]; `specular` in [0,1] scales the
/// highlight; `shininess` > 0 is the Phong exponent.
struct Material {
    Vec3d color{{0.8, 0.8, 0.8}};
    double specular = 0.35;
    double shininess = 48.0;
};

enum class Projection { perspective, orthographic };

/// A look-at camera. Perspective cameras use `fov_y_deg` (full vertical angle, degrees),
/// orthographic ones `height` (full vertical extent of the view volume, world units).
struct Camera {
    Projection projection = Projection::perspective;
    Vec3d eye{{0.0, 0.0, 5.0}};
    Vec3d target{{0.0, 0.0, 0.0}};
    Vec3d up{{0.0, 1.0, 0.0}};
    double fov_y_deg = 45.0;
    double height = 2.0;
    double near = 0.1;
    double far = 100.0;

    /// The first problem found, as {field, message} with field one of "eye", "target", "up",
    /// "fov_y", "height", "near", "far"; empty field = valid. Valid means: every number finite,
    /// eye != target, up not parallel to the view direction (angle > ~0.06 degrees), 0 < near <
    /// far, and 0 < fov_y_deg < 180 (perspective) or height > 0 (orthographic).
    struct Problem {
        std::string field, message;
    };
    Problem check() const;
    /// Throws std::invalid_argument("camera field: message") when check() finds a problem.
    void validate() const;
};

/// A directional light shines along `direction` (from the light towards the scene); a point
/// light sits at `position`. `color` in [0,1], `intensity` >= 0.
struct Light {
    enum class Kind { directional, point };
    Kind kind = Kind::directional;
    Vec3d direction{{-1.0, -1.0, -1.0}};
    Vec3d position{{0.0, 0.0, 0.0}};
    Vec3d color{{1.0, 1.0, 1.0}};
    double intensity = 1.0;
};

struct Sphere {
    Vec3d center;
    double radius;
    Material material;
};

/// Ellipsoid {center + a*x + b*y + c*z : x^2 + y^2 + z^2 <= 1}; `axes` are the three mutually
/// orthogonal semi-axis vectors (their lengths are the radii).
struct Ellipsoid {
    Vec3d center;
    std::array<Vec3d, 3> axes;
    Material material;
};

/// Circular cylinder around the segment p0-p1; `caps` closes both ends with discs.
struct Cylinder {
    Vec3d p0, p1;
    double radius;
    bool caps = true;
    Material material;
};

/// Circular cone from `apex` to the disc of `radius` centred at `base` (perpendicular to the
/// axis); `cap` closes the base with a disc.
struct Cone {
    Vec3d apex, base;
    double radius;
    bool cap = true;
    Material material;
};

/// Bounding volume a general quadric is clipped to.
struct BoundingSphere {
    Vec3d center;
    double radius;
};
struct BoundingTetrahedron {
    std::array<Vec3d, 4> p;
};

/// General quadric x~^T Q x~ = 0 with the symmetric homogeneous 4x4 matrix Q
/// (Stoll et al. 2006, eq. 4: Q = [A b; b^T c], x~ = (x, y, z, 1)), clipped to a bounding
/// sphere or tetrahedron. Column-major like every Mat: `q[col][row]`; the same layout as
/// `quadcast::Quadric<double>::q` (quadcast/quadric.hpp).
struct Quadric {
    enum class Bound { sphere, tetrahedron };
    Mat4d q;
    Bound bound = Bound::sphere;
    BoundingSphere sphere{};            ///< used when bound == sphere
    BoundingTetrahedron tetrahedron{};  ///< used when bound == tetrahedron
    Material material;
    /// A piece of an isosurface (the "tetmesh" object): a field's level set has no outside, so
    /// either side may face the eye; a frame with such pieces draws without per-quadric culling.
    bool two_sided = false;
};

/// Bilinear patch P(u,v) = (1-u)(1-v) p[0] + u(1-v) p[1] + uv p[2] + (1-u)v p[3], u,v in [0,1]:
/// the corners go around the perimeter (Stoll et al. 2006, sec. 4.5, p1..p4). A triangle
/// (a, b, c) may appear as the degenerate quad (a, b, c, c), which is exactly the flat triangle.
struct BilinearQuad {
    std::array<Vec3d, 4> p;
    Material material;
};

/// The 10 coefficients k of Stoll et al. 2006, eq. 1, in the order
/// k000, k100, k010, k001, k110, k011, k101, k200, k020, k002 (quadcast::Coefficients10), as
/// the matrix of eq. 3/4 (by quadcast::quadric_from_coefficients).
Mat4d quadric_matrix_from_coefficients(const std::array<double, 10>& k);

/// Rendering switches (see the paper references in the README): per-quadric back-face
/// culling, deferred shading, shadows, silhouette edges; background colour in [0,1].
struct Options {
    bool culling = true;
    /// "tight_bounds": draw each primitive over its tight screen rectangle (RenderOptions::tight_bounds).
    bool tight_bounds = true;
    /// "occlusion_culling": the GL renderer's cull pass (RenderOptions::occlusion_culling).
    bool occlusion_culling = true;
    /// "occlusion_phases": phased drawing of tetrahedral pieces (RenderOptions::occlusion_phases), 1-8.
    int occlusion_phases = 3;
    /// "occlusion_min_overlap": the cull pass runs only in frames whose expected overlap reaches
    /// this (RenderOptions::occlusion_min_overlap); 0: always.
    float occlusion_min_overlap = render::RenderOptions{}.occlusion_min_overlap;
    /// "occlusion_reuse": draw the last frame's shown set first where frames repeat
    /// (RenderOptions::occlusion_reuse).
    bool occlusion_reuse = render::RenderOptions{}.occlusion_reuse;
    bool deferred = false;
    bool shadows = false;
    bool silhouettes = false;
    /// "outline": {"depth": relative depth-gradient threshold, "crease": normal-gradient
    /// threshold, "strength": in [0, 1]} (quadcast::silhouette_weight); absent: the renderer's
    /// defaults.
    std::optional<double> outline_depth, outline_crease, outline_strength;
    /// "shadow": {"map_size": texels per side, "pcf_step": texels between PCF samples, "bias":
    /// in shadow-map texels, "reuse": keep the map across frames (RenderOptions::shadow_map_reuse)};
    /// absent: the renderer's defaults.
    std::optional<int> shadow_map_size, pcf_step;
    std::optional<double> shadow_bias;
    bool shadow_map_reuse = render::RenderOptions{}.shadow_map_reuse;
    Vec3d background{{1.0, 1.0, 1.0}};
    /// Environment reflection ("environment": {"file" | "procedural", "reflectivity"}): a
    /// latitude-longitude PNG (resolved path) or the built-in sky (colours, defaults of
    /// quadcast::render::ProceduralSky when absent), mixed in by `reflectivity`.
    enum class Environment { none, file, procedural };
    Environment environment = Environment::none;
    std::filesystem::path environment_file;
    /// The environment image, decoded when the scene was loaded (so that a corrupt PNG is an error
    /// at its scene location, and the file is read once).
    std::shared_ptr<const render::Image> environment_image;
    std::optional<Vec3d> sky_zenith, sky_horizon, sky_ground;
    double reflectivity = 0.3;
};

/// Axis-aligned box; empty while lo > hi.
struct Aabb {
    // (empty: +inf / -inf, so that any finite coordinate extends it, even beyond 1e300)
    Vec3d lo{{HUGE_VAL, HUGE_VAL, HUGE_VAL}};
    Vec3d hi{{-HUGE_VAL, -HUGE_VAL, -HUGE_VAL}};
    bool empty() const { return lo[0] > hi[0] || lo[1] > hi[1] || lo[2] > hi[2]; }
    void extend(const Vec3d& p);
    /// Extends by the box [c - h, c + h].
    void extend(const Vec3d& c, const Vec3d& half_extent);
    void extend(const Aabb& b);
    Vec3d center() const;
    /// Half the length of the diagonal (radius of a sphere around the box).
    double radius() const;
};

/// Tight boxes of each primitive (the clip region for quadrics).
Aabb bounds(const Sphere& s);
Aabb bounds(const Ellipsoid& e);
Aabb bounds(const Cylinder& c);
Aabb bounds(const Cone& c);
Aabb bounds(const Quadric& q);
Aabb bounds(const BilinearQuad& q);

/// An isosurface of a volume (the "volume" object kind). The scene records only what to load;
/// the volume component (quadcast::volume, `quadcast::volume::load_volume`) reads the samples and
/// the CPU spline renderer draws them. `box` is the world box of the samples: known for the
/// synthetic volumes, for files filled by the installed `volume_box_function` (empty if none).
struct Volume {
    enum class Scheme { qss, s31, trilinear };
    std::string input;       ///< resolved file path, or the synthetic name "marschner-lobb" / "franke"
    bool synthetic = false;
    int size = 0;            ///< synthetic: samples per axis (0 = the generator's default)
    double iso = 0.0;
    Location iso_where;      ///< where "iso" was written (for a range error found when the data are read)
    Scheme scheme = Scheme::qss;
    /// How a QSS isosurface is drawn: per cube by the isosurface renderers (Kalbe & Zeilfelder,
    /// `bezier`), or each relevant tetrahedron's piece as a quadric clipped to it by the quadric
    /// renderers (Stoll et al. 2006, sec. 5.1.2, `quadric`; shapes::isosurface_quadrics).
    enum class Method { bezier, quadric };
    Method method = Method::bezier;
    Material material;
    Aabb box;
};

/// Computes the world box of a file volume (installed by programs that link the volume library;
/// may throw, the loader reports the message at the "volume" value).
using VolumeBoxFunction = Aabb (*)(const Volume&);
void set_volume_box_function(VolumeBoxFunction f);
VolumeBoxFunction volume_box_function();

/// One ball of a SLIM surface (quadcast::slim::Ball without the slim component's types): the
/// world quadric x~^T q x~ clipped to the sphere (center, radius) and, with `has_plane`, to
/// plane[0] x + plane[1] y + plane[2] z + plane[3] >= 0, with `has_plane2` (a corner's) to plane2
/// the same way too.
struct SlimBall {
    Vec3d center;
    double radius = 0;
    Mat4d q;
    bool has_plane = false;
    std::array<double, 4> plane{};
    bool has_plane2 = false;
    std::array<double, 4> plane2{};
};

/// A SLIM surface (the "slim" object kind): a model file, or a point file built at relative
/// error `error` (> 0; 0 for a model file) when the scene was loaded, by the installed
/// `slim_load_function` (quadcast::slim::install_scene_loader).
struct Slim {
    std::string input;  ///< resolved file path
    double error = 0;
    Material material;
    std::vector<SlimBall> balls;
};

/// Loads the balls of a SLIM object: a model file when `error` is 0, else builds one from the
/// points at that relative error. Throws ParseError (naming the model or point file's line) or
/// std::exception. Installed by programs that link the slim component.
using SlimLoadFunction = std::vector<SlimBall> (*)(const std::filesystem::path& input, double error);
void set_slim_load_function(SlimLoadFunction f);
SlimLoadFunction slim_load_function();

/// A ball of a molecular skin surface ("style": "skin" of a "pdb" object): the atom's centre, its
/// van der Waals radius times "vdw_scale" (the skin of an isolated atom is this sphere), its colour.
struct SkinBall {
    Vec3d center;
    double radius = 0;
    Vec3d color{{0.8, 0.8, 0.8}};
};

/// Builds the skin surface of `balls` (Edelsbrunner; shrink factor `shrink` in (0, 1)) as quadrics
/// clipped to the tetrahedra of its mixed complex, each with `material` and the colour of the ball
/// nearest to it (power distance). Throws std::exception. Installed by programs that link the skin
/// component (quadcast::skin::install_scene_builder); none is installed by default, so that CGAL
/// stays out of the scene component.
using SkinBuildFunction = std::vector<Quadric> (*)(const std::vector<SkinBall>& balls, double shrink, const Material& material);
void set_skin_build_function(SkinBuildFunction f);
SkinBuildFunction skin_build_function();

/// Everything the renderer draws: one vector per primitive kind.
struct Scene {
    std::filesystem::path source;  ///< the scene file ("" when built in code)
    Camera camera;
    std::vector<Light> lights;
    Options options;

    std::vector<Sphere> spheres;
    std::vector<Ellipsoid> ellipsoids;
    std::vector<Cylinder> cylinders;
    std::vector<Cone> cones;
    std::vector<Quadric> quadrics;
    std::vector<BilinearQuad> quads;
    std::vector<Volume> volumes;  ///< isosurfaces, drawn by the CPU spline renderer
    std::vector<Slim> slims;      ///< SLIM surfaces, drawn by the SLIM renderers

    /// Problems that were handled in a documented way while loading (print them).
    Warnings warnings;

    /// Where the primitives came from: one entry per scene object, with the sizes of the
    /// primitive vectors before it was loaded, so that primitive i of a kind belongs to the last
    /// entry whose start for that kind is <= i. Empty for scenes built in code.
    /// The object is entry `object` of "objects" in `source`; line and column are those of its
    /// kind key's value, `kind` that key ("sphere"; static storage). (No strings per object: a
    /// scene of a million objects keeps 80 bytes each.)
    struct Origin {
        std::size_t spheres = 0, ellipsoids = 0, cylinders = 0, cones = 0, quadrics = 0, quads = 0, slims = 0;
        int line = 0, column = 0;
        std::size_t object = 0;
        std::string_view kind;
    };
    std::vector<Origin> origins;
    /// `source:line:column` and the pointer /objects/<object>/<kind> of an origin.
    Location location(const Origin& o) const;

    /// Box around every primitive and volume; empty when there are none.
    Aabb bounds() const;
    std::size_t primitive_count() const;
};

/// A perspective camera (fov_y 45 degrees) looking at the centre of `box` along -z from far
/// enough that the box's bounding sphere fits the view, with near/far around that sphere.
Camera fit_camera(const Aabb& box, double fov_y_deg = 45.0);

}  // namespace quadcast::scene
