// examples/render/scene_render.hpp -- from a loaded scene to what the renderers draw
#pragma once

#include <string>
#include <vector>

#include "quadcast/render/types.hpp"
#include "scene.hpp"

namespace quadcast::render {

/// Everything a renderer needs for one scene.
struct Frame {
    std::vector<Primitive> primitives;
    Camera camera;
    Light light;
    RenderOptions options;
    std::vector<std::string> notes;  ///< what was skipped or approximated, for the user
};

/// Converts a scene: every primitive becomes a local quadric on its bounding sphere (spheres and
/// ellipsoids: closed; cylinders and cones: slab with caps; general quadrics with a sphere bound:
/// bounded). Camera matrices for width x height.
Frame build_frame(const scene::Scene& s, int width, int height);

/// World -> view matrix of a camera at eye looking at target (right-handed, -z forward).
Mat4<double> look_at(const Vec3<double>& eye, const Vec3<double>& target, const Vec3<double>& up);

/// OpenGL perspective projection with vertical field of view fov_y (degrees).
Mat4<double> perspective(double fov_y_deg, double aspect, double near, double far);

/// OpenGL orthographic projection of a view `height` high.
Mat4<double> orthographic(double height, double aspect, double near, double far);

}  // namespace quadcast::render
