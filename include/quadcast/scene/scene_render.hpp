// quadcast/scene/scene_render.hpp -- from a loaded scene to what the renderers draw
#pragma once

#include <string>
#include <vector>

#include "quadcast/render/types.hpp"
#include "quadcast/scene/scene.hpp"

namespace quadcast::render {

/// Everything a renderer needs for one scene.
struct Frame {
    std::vector<Primitive> primitives;
    Camera camera;
    Light light;
    RenderOptions options;
    std::vector<std::string> notes;  ///< what was skipped or approximated, for the user
};

/// Converts a scene with the public shapes API (quadcast/shapes.hpp) and the camera of
/// quadcast/camera.hpp for width x height. Throws std::invalid_argument for a shape the API rejects.
Frame build_frame(const scene::Scene& s, int width, int height);

}  // namespace quadcast::render
