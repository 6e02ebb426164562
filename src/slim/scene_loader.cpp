// src/slim/scene_loader.cpp -- "slim" objects of JSON scenes: model files, or point files built on load
#include "quadcast/slim/scene_loader.hpp"

#include "quadcast/slim/build.hpp"
#include "quadcast/slim/points.hpp"

namespace quadcast::slim {

std::vector<scene::SlimBall> scene_balls(const Model& m) {
    std::vector<scene::SlimBall> out;
    out.reserve(m.balls.size());
    for (const Ball& b : m.balls) {
        scene::SlimBall s;
        s.center = b.center;
        s.radius = b.radius;
        s.q = b.q.q;
        s.has_plane = b.has_plane;
        s.has_plane2 = b.has_plane && b.has_plane2;
        for (int i = 0; i < 4; ++i) {
            s.plane[static_cast<std::size_t>(i)] = b.plane[i];
            s.plane2[static_cast<std::size_t>(i)] = b.plane2[i];
        }
        out.push_back(s);
    }
    return out;
}

std::vector<scene::SlimBall> load_scene_slim(const std::filesystem::path& input, double error) {
    if (error == 0.0) return scene_balls(read_model(input));
    BuildOptions opt;
    opt.error = error;
    return scene_balls(build(read_points(input), opt).model);
}

void install_scene_loader() { scene::set_slim_load_function(load_scene_slim); }

}  // namespace quadcast::slim
