// quadcast/scene/scene_render.hpp -- from a loaded scene to what the renderers draw
#pragma once

#include <string>
#include <vector>

#include "quadcast/render/types.hpp"
#include "quadcast/scene/scene.hpp"

namespace quadcast::render {

/// The similarity a scene is drawn in: frame = (world - offset) / scale, with scale a power of
/// two (exact in binary). The picture does not depend on it (the camera, near and far are
/// transformed alike); it brings scenes of any size into the range where float holds them.
struct FrameTransform {
    Vec3<double> offset{{0.0, 0.0, 0.0}};
    double scale = 1.0;
    Vec3<double> point(const Vec3<double>& w) const { return (w - offset) / scale; }
    double length(double l) const { return l / scale; }
};

/// The frame of a scene with bounds `box` (README "Numeric range"): the identity when the box's
/// half extent h (largest over the axes) is in [2^-16, 2^16] and every coordinate of the box within
/// 2^10 h (float then places every point to 2^-14 h or better), which holds the scenes of everyday
/// units; otherwise offset = the box centre and scale = the power of two nearest h, so that the
/// scene spans about [-1, 1]. An empty box: the identity.
FrameTransform frame_transform(const scene::Aabb& box);

/// Everything a renderer needs for one scene.
/// The note of a frame whose per-quadric culling is turned off because it draws isosurface
/// pieces (scene::Quadric::two_sided, or a volume drawn with "method": "quadric").
inline constexpr const char* isosurface_culling_note =
    "per-quadric culling is off for this frame: isosurface pieces (\"tetmesh\", \"method\": \"quadric\") have no outside, "
    "either side may face the eye";

struct Frame {
    FrameTransform transform;  ///< world -> frame; the primitives and the camera are in the frame
    std::vector<Primitive> primitives;
    /// The balls of the scene's SLIM surfaces (quadcast/render/slim_cpu_renderer.hpp): `bounded`
    /// primitives (shapes::quadric with a SphereBound) whose shape.planes[0] is the clip plane in
    /// local coordinates ((0, 0, 0, 1) when the ball has none).
    std::vector<Primitive> slim_balls;
    Camera camera;
    Light light;
    RenderOptions options;
    std::vector<std::string> notes;  ///< what was skipped or approximated, for the user
};

/// Converts a scene with the public shapes API (quadcast/shapes.hpp) and the camera of
/// quadcast/camera.hpp for width x height, in the frame of `frame_transform(s.bounds())`. General
/// quadrics are normalised in double (largest coefficient 1) before they become float, so their
/// scale never matters. Throws std::invalid_argument for a shape the API rejects, prefixed by the
/// scene location of the object it came from (`Scene::origins`) when there is one. SLIM balls go
/// into `slim_balls`, their quadrics normalised like general quadrics.
Frame build_frame(const scene::Scene& s, int width, int height);

/// The frame's camera (`Frame::camera`) of scene camera `c` for width x height in the frame of
/// `t`: eye and target through the transform, near, far and the orthographic height scaled by it.
Camera frame_camera(const scene::Camera& c, const FrameTransform& t, int width, int height);

/// Scene camera `c` orbited by `degrees` about its target, around its up vector (right-handed):
/// the eye moves on the circle about the up axis through the target; target, up, distance and
/// projection stay.
scene::Camera orbit_camera(const scene::Camera& c, double degrees);

}  // namespace quadcast::render
