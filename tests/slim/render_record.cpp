// tests/slim/render_record.cpp -- a model ball is what the renderer's sphere-clipped quadric takes
#include <doctest/doctest.h>

#include <cmath>

#include "quadcast/shapes.hpp"
#include "quadcast/slim/fit.hpp"
#include "quadcast/slim/model.hpp"

using namespace quadcast;
using namespace quadcast::slim;

TEST_CASE("a ball's world quadric and sphere go into shapes::quadric unchanged and keep the surface") {
    // The north cap of the sphere |x - (1, 2, 3)| = 0.5, as the fit stores it.
    const Vec3d c0 = vec3(1.0, 2.0, 3.0);
    Ball b;
    b.center = c0 + vec3(0.0, 0.0, 0.5);
    b.radius = 0.2;
    const Quadric<double> world = quadric_from_abc(identity<double, 3>(), -c0, dot(c0, c0) - 0.25);
    b.q = local_to_world(world_to_local(world, b.center, b.radius), b.center, b.radius);
    glm::mat4 m{};
    for (int j = 0; j < 4; ++j)
        for (int i = 0; i < 4; ++i) m[j][i] = float(b.q.q[j][i]);
    const render::Primitive p = shapes::quadric(m, shapes::SphereBound{glm::vec3(float(b.center[0]), float(b.center[1]), float(b.center[2])), float(b.radius)});
    CHECK(p.variant == render::Variant::bounded);
    CHECK(p.shape.radius == float(b.radius));
    // The stored local quadric vanishes on the surface point at the ball's centre and is negative inside.
    Quadric<double> local{};
    for (int j = 0; j < 4; ++j)
        for (int i = 0; i < 4; ++i) local.q[j][i] = double(p.shape.q.q[j][i]);
    const double g = length(gradient(local, vec3(0.0, 0.0, 0.0)));
    CHECK(std::fabs(evaluate(local, vec3(0.0, 0.0, 0.0))) < 1e-5 * g);
    CHECK(evaluate(local, vec3(0.0, 0.0, -0.1)) < 0);
    CHECK(evaluate(local, vec3(0.0, 0.0, 0.1)) > 0);
}
