// tests/gl/test_tetmesh_gl.cpp -- isosurfaces of quadratic tetrahedral elements (the "tetmesh"
// scene object) drawn by the GL quadric renderer against the CPU reference
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "quadcast/gl/osmesa_context.hpp"
#include "quadcast/gl/quadric_renderer.hpp"
#include "quadcast/render/cpu_renderer.hpp"
#include "quadcast/scene/msh.hpp"
#include "quadcast/scene/scene_render.hpp"
#include "render/render_testing.hpp"

using namespace quadcast;

namespace {

/// A 10-node tetrahedral mesh of [-1, 1]^3 made here, independently of Gmsh: n^3 cubes, each cut
/// into the 6 tetrahedra around its main diagonal (Freudenthal; conforming across cubes), nodes
/// at the corners and the edge midpoints (a grid of 2n + 1 points per side), the field
/// f(x, y, z) at every node.
template <class F>
scene::MshMesh freudenthal_mesh(int n, F f) {
    scene::MshMesh m;
    m.file = "freudenthal";
    const int g = 2 * n + 1;
    const auto id = [&](int i, int j, int k) { return static_cast<std::uint32_t>((k * g + j) * g + i); };
    scene::MshField field;
    field.name = "f";
    for (int k = 0; k < g; ++k)
        for (int j = 0; j < g; ++j)
            for (int i = 0; i < g; ++i) {
                const scene::Vec3d p{{-1.0 + 2.0 * i / (g - 1), -1.0 + 2.0 * j / (g - 1), -1.0 + 2.0 * k / (g - 1)}};
                m.nodes.push_back(p);
                m.node_tags.push_back(m.nodes.size());
                field.value.push_back(f(p[0], p[1], p[2]));
            }
    m.fields.push_back(field);
    const int perm[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
    // Gmsh's edge-node order: 01, 12, 20, 30, 32, 31.
    const int edge[6][2] = {{0, 1}, {1, 2}, {2, 0}, {3, 0}, {3, 2}, {3, 1}};
    for (int k = 0; k < n; ++k)
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i)
                for (const auto& p : perm) {
                    int c[4][3] = {{2 * i, 2 * j, 2 * k}};
                    for (int s = 0; s < 3; ++s) {
                        for (int a = 0; a < 3; ++a) c[s + 1][a] = c[s][a];
                        c[s + 1][p[s]] += 2;
                    }
                    scene::MshTet t{};
                    t.nodes = 10;
                    t.tag = m.tets.size() + 1;
                    for (int v = 0; v < 4; ++v) t.node[v] = id(c[v][0], c[v][1], c[v][2]);
                    for (int e = 0; e < 6; ++e) {
                        const int* a = c[edge[e][0]];
                        const int* b = c[edge[e][1]];
                        t.node[4 + e] = id((a[0] + b[0]) / 2, (a[1] + b[1]) / 2, (a[2] + b[2]) / 2);
                    }
                    m.tets.push_back(t);
                }
    return m;
}

}  // namespace

TEST_CASE("a quadratic tetrahedral field's isosurface: GL draws what the CPU reference draws, culling on and off") {
    // A quadric that is not a sphere (an ellipsoid moved off-centre), and a hyperboloid of one
    // sheet cut open by the box: its inside shows through the openings.
    const auto ellipsoid = [](double x, double y, double z) { return x * x + 2 * (y - 0.1) * (y - 0.1) + 0.7 * z * z + 0.3 * x * y; };
    const auto hyperboloid = [](double x, double y, double z) { return x * x + y * y - 1.5 * z * z; };
    gl::OsmesaContext ctx;
    gl::QuadricRenderer r(ctx.api());
    int which = 0;
    for (const double iso : {0.6, 0.3}) {
        const scene::MshMesh mesh = which++ == 0 ? freudenthal_mesh(6, ellipsoid) : freudenthal_mesh(6, hyperboloid);
        scene::TetmeshIso what;
        what.iso = iso;
        scene::Scene s;
        s.quadrics = scene::tetmesh_isosurface(mesh, what, scene::Material{}, {});
        s.camera.eye = {{1.9, 1.4, 2.6}};
        s.camera.target = {{0, 0, 0}};
        for (const bool cull : {true, false})
            for (const bool occlusion : {true, false}) {
                s.options.culling = cull;
                const render::Frame f = render::build_frame(s, 240, 180);
                // Either side of a level set may face the eye: the frame draws without culling, and says so.
                CHECK_FALSE(f.options.culling);
                CHECK((std::find(f.notes.begin(), f.notes.end(), render::isosurface_culling_note) != f.notes.end()) == cull);
                render::RenderOptions o = f.options;
                o.occlusion_culling = occlusion;
                o.occlusion_min_overlap = 0.0f;  // (the cull pass in every frame, however little the primitives overlap)
                r.set_primitives(f.primitives);
                r.draw(f.camera, f.light, o);
                const render::Image g = r.read();
                const render::Image c = render::render_cpu(f.primitives, f.camera, f.light, o);
                const qc_render_test::ImageDiff d = qc_render_test::image_diff(g, c, 1);
                std::printf("[tetmesh gl vs cpu] %s iso %g, %zu pieces, culling %s, occlusion culling %s: %ld covered px, %ld coverage "
                            "differences, %ld colour differences > 1 LSB, max depth difference %.3g\n",
                            which == 1 ? "ellipsoid" : "hyperboloid", iso, s.quadrics.size(), cull ? "on" : "off", occlusion ? "on" : "off",
                            d.covered, d.coverage_diff, d.color_diff, d.max_depth);
                CHECK(d.covered > 5000);
                CHECK(d.coverage_diff <= d.covered / 200);
                CHECK(d.color_diff <= d.covered / 100);
                CHECK(d.max_depth < 1e-4);
            }
    }
}
