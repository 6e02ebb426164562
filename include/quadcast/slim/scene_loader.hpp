// quadcast/slim/scene_loader.hpp -- SLIM objects of JSON scenes ("slim": MODEL or point file)
#pragma once

#include <filesystem>
#include <vector>

#include "quadcast/scene/scene.hpp"
#include "quadcast/slim/model.hpp"

namespace quadcast::slim {

/// The scene's balls of a model (world quadric, sphere, clip plane), unchanged.
std::vector<scene::SlimBall> scene_balls(const Model& m);

/// What the scene reader calls for a "slim" object: `read_model(input)` when `error` is 0, else
/// `build(read_points(input), error)` (default build options, one seed: the same model every
/// time). Throws scene::ParseError (file and line of the model or points) or std::invalid_argument.
std::vector<scene::SlimBall> load_scene_slim(const std::filesystem::path& input, double error);

/// Installs `load_scene_slim` as scene::slim_load_function (programs linking the slim component
/// call it once before loading scenes).
void install_scene_loader();

}  // namespace quadcast::slim
