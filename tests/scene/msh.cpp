// tests/scene/msh.cpp -- the Gmsh MSH 4.1 reader (against Gmsh's own model of the files it
// writes) and the isosurface of a nodal field as quadrics clipped to tetrahedra
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <random>
#include <string>
#include <vector>

#include "helpers.hpp"
#include "quadcast/render/cpu_renderer.hpp"
#include "quadcast/scene/msh.hpp"
#include "quadcast/scene/scene_json.hpp"
#include "quadcast/scene/scene_render.hpp"

#ifdef QUADCAST_TEST_HAVE_GMSH
#include <gmsh.h>
#endif

using namespace quadcast::scene;
using namespace scene_test;

namespace {

MshMesh parse(const std::string& text) { return parse_msh(text, "mem.msh"); }
std::string what_of(const std::string& text) { return parse_error_of([&] { parse(text); }).what(); }

// One straight 10-node tetrahedron (corners (0,0,0), (1,0,0), (0,1,0), (0,0,1); Gmsh's edge
// order 01, 12, 20, 30, 32, 31) with the field "f" = x^2 + y^2 + z^2 at its nodes, and a 2-node
// line and a 3-node triangle on its boundary (skipped).
const double kNodes[10][3] = {{0, 0, 0},     {1, 0, 0},     {0, 1, 0},   {0, 0, 1},   {0.5, 0, 0},
                              {0.5, 0.5, 0}, {0, 0.5, 0},   {0, 0, 0.5}, {0, 0.5, 0.5}, {0.5, 0, 0.5}};

std::string nodes_section() {
    std::string s = "$Nodes\n1 10 1 10\n3 1 0 10\n";
    for (int i = 1; i <= 10; ++i) s += std::to_string(i) + "\n";
    for (const auto& p : kNodes) {
        char buf[96];
        std::snprintf(buf, sizeof buf, "%.17g %.17g %.17g\n", p[0], p[1], p[2]);
        s += buf;
    }
    return s + "$EndNodes\n";
}

std::string node_data(const std::string& name, int step, int components = 1) {
    std::string s = "$NodeData\n1\n\"" + name + "\"\n1\n" + std::to_string(step) + "\n3\n" + std::to_string(step) + "\n" +
                    std::to_string(components) + "\n10\n";
    for (int i = 0; i < 10; ++i) {
        const double v = (step + 1) * (kNodes[i][0] * kNodes[i][0] + kNodes[i][1] * kNodes[i][1] + kNodes[i][2] * kNodes[i][2]);
        s += std::to_string(i + 1);
        for (int c = 0; c < components; ++c) s += " " + std::to_string(v);
        s += "\n";
    }
    return s + "$EndNodeData\n";
}

const std::string kElements =
    "$Elements\n3 3 1 3\n1 1 1 1\n1 1 2\n2 1 2 1\n2 1 2 3\n3 1 11 1\n3 1 2 3 4 5 6 7 8 9 10\n$EndElements\n";

std::string one_tet(const std::string& data = node_data("f", 0)) {
    return "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$PhysicalNames\n1\n3 1 \"volume\"\n$EndPhysicalNames\n" + nodes_section() +
           kElements + data;
}

double eval(const Mat4d& q, double x, double y, double z) {
    const double v[4] = {x, y, z, 1};
    double s = 0;
    for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 4; ++c) s += v[r] * q[c][r] * v[c];
    return s;
}

/// A random point of the tetrahedron (uniform barycentric coordinates).
Vec3d random_point(std::mt19937& rng, const BoundingTetrahedron& t) {
    std::exponential_distribution<double> e;
    double l[4], sum = 0;
    for (double& x : l) sum += x = e(rng);
    Vec3d p{{0, 0, 0}};
    for (int k = 0; k < 4; ++k) p = p + t.p[static_cast<std::size_t>(k)] * (l[k] / sum);
    return p;
}

}  // namespace

TEST_CASE("a hand-written 10-node tetrahedron: nodes, elements, fields, skipped boundary elements") {
    const MshMesh m = parse(one_tet(node_data("f", 0) + node_data("f", 1)));
    CHECK_FALSE(m.binary);
    REQUIRE(m.nodes.size() == 10);
    CHECK(m.nodes[5][0] == 0.5);
    CHECK(m.node_tags[9] == 10);
    REQUIRE(m.tets.size() == 1);
    CHECK(m.tets[0].nodes == 10);
    CHECK(m.tets[0].tag == 3);
    CHECK(m.tets[0].line == 39);
    CHECK(m.skipped_lower_dimensional == 2);
    REQUIRE(m.fields.size() == 2);
    CHECK(m.fields[0].name == "f");
    CHECK(m.fields[1].step == 1);
    CHECK(m.fields[1].value[1] == 2.0);
}

TEST_CASE("the quadric of a 10-node element is its quadratic: x^2 + y^2 + z^2 - iso exactly") {
    const MshMesh m = parse(one_tet());
    TetmeshIso what;
    what.iso = 0.25;
    const std::vector<Quadric> q = tetmesh_isosurface(m, what, Material{}, {"scene.json", 1, 1, "/objects/0"});
    REQUIRE(q.size() == 1);
    CHECK(q[0].bound == Quadric::Bound::tetrahedron);
    std::mt19937 rng(5);
    double worst = 0;
    for (int i = 0; i < 1000; ++i) {
        const Vec3d p = random_point(rng, q[0].tetrahedron);
        worst = std::max(worst, std::fabs(eval(q[0].q, p[0], p[1], p[2]) - (p[0] * p[0] + p[1] * p[1] + p[2] * p[2] - 0.25)));
    }
    CHECK(worst < 1e-14);
}

TEST_CASE("a 4-node element is its linear interpolant") {
    // The same corners as 4-node elements with the field x + 2y + 3z.
    std::string s = "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n" + nodes_section() + "$Elements\n1 1 1 1\n3 1 4 1\n1 1 2 3 4\n$EndElements\n";
    s += "$NodeData\n1\n\"lin\"\n0\n3\n0\n1\n4\n1 0\n2 1\n3 2\n4 3\n$EndNodeData\n";
    const MshMesh m = parse(s);
    TetmeshIso what;
    what.iso = 1.5;
    const std::vector<Quadric> q = tetmesh_isosurface(m, what, Material{}, {});
    REQUIRE(q.size() == 1);
    for (double x : {0.0, 0.1, 0.3})
        for (double y : {0.0, 0.2})
            for (double z : {0.0, 0.4}) CHECK(eval(q[0].q, x, y, z) == doctest::Approx(x + 2 * y + 3 * z - 1.5).epsilon(1e-14));
}

TEST_CASE("choosing the field and the step; errors name the scene key") {
    const MshMesh m = parse(one_tet(node_data("f", 0) + node_data("f", 1) + node_data("g", 0)));
    const Location at{"scene.json", 4, 7, "/objects/0/tetmesh"};
    TetmeshIso what;
    what.iso = 0.5;
    ParseError e = parse_error_of([&] { tetmesh_isosurface(m, what, Material{}, at); });
    CHECK(std::string(e.what()) == "scene.json:4:7: field: 'mem.msh' has several fields (\"f\", \"g\"): choose one with \"field\"");
    what.field = "h";
    e = parse_error_of([&] { tetmesh_isosurface(m, what, Material{}, at); });
    CHECK(e.field() == "field");
    CHECK(std::string(e.what()).find("has no field \"h\" (its fields: \"f\", \"g\")") != std::string::npos);
    what.field = "f";
    e = parse_error_of([&] { tetmesh_isosurface(m, what, Material{}, at); });
    CHECK(std::string(e.what()) == "scene.json:4:7: step: field \"f\" has several time steps (0, 1): choose one with \"step\"");
    what.step = 3;
    e = parse_error_of([&] { tetmesh_isosurface(m, what, Material{}, at); });
    CHECK(std::string(e.what()).find("has no time step 3 (its steps: 0, 1)") != std::string::npos);
    what.step = 1;
    CHECK(tetmesh_isosurface(m, what, Material{}, at).size() == 1);  // values doubled: 0.5 inside
    what.iso = 3;
    e = parse_error_of([&] { tetmesh_isosurface(m, what, Material{}, at); });
    CHECK(e.field() == "iso");
    CHECK(std::string(e.what()).find("the isovalue 3 is outside the range [0, 2]") != std::string::npos);
    what.field = "g";
    what.step.reset();
    what.iso = 0.5;
    CHECK(tetmesh_isosurface(m, what, Material{}, at).size() == 1);
}

TEST_CASE("vector fields, missing values, curved and flat elements are errors naming the line") {
    TetmeshIso what;
    what.iso = 0.25;
    ParseError e = parse_error_of([&] { tetmesh_isosurface(parse(one_tet(node_data("v", 0, 3))), what, Material{}, {}); });
    CHECK(std::string(e.what()).find("mem.msh:41: $NodeData \"v\": a field of 3 components") == 0);
    // A field that leaves out node 7.
    std::string partial = node_data("f", 0);
    const std::size_t at7 = partial.find("\n7 ");
    partial.erase(at7 + 1, partial.find('\n', at7 + 1) - at7);
    partial.replace(partial.find("\n10\n"), 4, "\n9\n");
    e = parse_error_of([&] { tetmesh_isosurface(parse(one_tet(partial)), what, Material{}, {}); });
    CHECK(std::string(e.what()) == "mem.msh:39: $Elements element 3: node 7 has no value in field \"f\"");
    // Node 5 (edge 01) moved off its edge's midpoint: a curved element.
    std::string curved = one_tet();
    curved.replace(curved.find("0.5 0 0\n"), 8, "0.5 0.1 0\n");
    e = parse_error_of([&] { tetmesh_isosurface(parse(curved), what, Material{}, {}); });
    CHECK(std::string(e.what()).find("mem.msh:39: $Elements element 3: a curved element: node 5 is 0.1 from the midpoint of its edge") == 0);
    // All four corners in the plane z = 0.
    std::string flat = one_tet();
    flat.replace(flat.find("0 0 1\n"), 6, "0 0 0\n");
    e = parse_error_of([&] { tetmesh_isosurface(parse(flat), what, Material{}, {}); });
    CHECK(std::string(e.what()).find("a flat tetrahedron") != std::string::npos);
}

TEST_CASE("malformed and truncated MSH files are errors naming line and field") {
    const std::string head = "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n";
    CHECK(what_of("") == "mem.msh:1: $MeshFormat: an empty file (not a Gmsh .msh file)");
    CHECK(what_of("OFF\n4 1 0\n") == "mem.msh:1: section: expected a section such as $Nodes, got 'OFF'");
    CHECK(what_of("$Nodes\n") == "mem.msh:1: $MeshFormat: the file does not start with $MeshFormat (not a Gmsh .msh file?)");
    CHECK(what_of("$MeshFormat\n2.2 0 8\n$EndMeshFormat\n").find("mem.msh:2: $MeshFormat version: MSH 2.2 is not read, only 4.1") == 0);
    CHECK(what_of("$MeshFormat\n4.1 2 8\n$EndMeshFormat\n") == "mem.msh:2: $MeshFormat file-type: '2' is outside [0, 1]");
    CHECK(what_of(head) == "mem.msh:4: $Nodes: the file has no $Nodes section");  // the line: the end of the file
    CHECK(what_of(head + nodes_section()) == "mem.msh:28: $Elements: the file has no $Elements section");
    // Truncated inside $Nodes.
    const std::string nodes = nodes_section();
    CHECK(what_of(head + nodes.substr(0, nodes.find("0.5 0.5 0"))).find("unexpected end of the file (truncated?)") != std::string::npos);
    // A coordinate that is not a number, one that is not finite.
    std::string bad = one_tet();
    bad.replace(bad.find("0 1 0\n"), 6, "0 1x 0\n");
    CHECK(what_of(bad) == "mem.msh:23: $Nodes block 1 node 3 y: expected a number, got '1x'");
    bad = one_tet();
    bad.replace(bad.find("0 1 0\n"), 6, "0 inf 0\n");
    CHECK(what_of(bad) == "mem.msh:23: $Nodes block 1 node 3 y: not a finite number: 'inf'");
    // An element naming a node that does not exist; a hexahedron; an unknown type.
    bad = one_tet();
    bad.replace(bad.find("3 1 2 3 4 5 6 7 8 9 10"), 22, "3 1 2 3 4 5 6 7 8 9 11");
    CHECK(what_of(bad) == "mem.msh:39: $Elements block 3 element 1 node 10: node 11 is not in $Nodes");
    bad = one_tet();
    bad.replace(bad.find("3 1 11 1\n3 1 2 3 4 5 6 7 8 9 10"), 31, "3 1 5 1\n3 1 2 3 4 5 6 7 8");
    CHECK(what_of(bad).find("mem.msh:38: $Elements block 3 elementType: unsupported volume element: type 5 (8-node hexahedron)") == 0);
    bad = one_tet();
    bad.replace(bad.find("3 1 11 1"), 8, "3 1 77 1");
    CHECK(what_of(bad) == "mem.msh:38: $Elements block 3 elementType: unknown element type 77");
    // A node given twice; a count the blocks do not hold; a missing end marker.
    bad = one_tet();
    bad.replace(bad.find("\n2\n3\n"), 5, "\n2\n2\n");
    CHECK(what_of(bad).find("node 2 is given twice") != std::string::npos);
    bad = one_tet();
    bad.replace(bad.find("$Elements\n3 3 1 3"), 17, "$Elements\n3 4 1 3");
    CHECK(what_of(bad).find("$Elements numElements: the header says 4 elements, the blocks hold 3") != std::string::npos);
    bad = one_tet();
    bad.erase(bad.find("$EndPhysicalNames"), 18);
    CHECK(what_of(bad).find("$PhysicalNames: the section has no $EndPhysicalNames") != std::string::npos);
    CHECK(what_of(head + "$PartitionedEntities\n$EndPartitionedEntities\n").find("partitioned meshes are not read") != std::string::npos);
    CHECK(parse_error_of([] { read_msh("/nonexistent/m.msh"); }).file() == "/nonexistent/m.msh");
}

TEST_CASE("randomly corrupted MSH text never crashes: it reads or throws ParseError") {
    const std::string base = one_tet(node_data("f", 0) + node_data("f", 1));
    const std::string alphabet = "0123456789 .-+eE\n$\"xNodesEnd";
    int ok = 0, errors = 0;
    for (int iter = 0; iter < 600; ++iter) {
        std::mt19937 rng(4000u + unsigned(iter));
        std::string t = base;
        for (int k = 0, n = 1 + int(rng() % 3); k < n; ++k) {
            const std::size_t at = rng() % t.size();
            switch (rng() % 3) {
            case 0: t[at] = alphabet[rng() % alphabet.size()]; break;
            case 1: t.erase(at, 1 + rng() % 6); break;
            default: t.resize(at); break;
            }
            if (t.empty()) t.push_back('x');
        }
        try {
            const MshMesh m = parse(t);
            TetmeshIso what;
            what.field = "f";
            what.step = 0;
            what.iso = 0.25;
            for (const Quadric& q : tetmesh_isosurface(m, what, Material{}, {}))
                for (int r = 0; r < 4; ++r)
                    for (int c = 0; c < 4; ++c) REQUIRE(std::isfinite(q.q[c][r]));
            ++ok;
        } catch (const ParseError& e) {
            CHECK(e.file() == "mem.msh");
            ++errors;
        }
    }
    CHECK(ok > 10);
    CHECK(errors > 10);
}

TEST_CASE("scene object \"tetmesh\": keys, errors located in the scene and in the mesh file") {
    TempDir dir;
    dir.write("one.msh", one_tet(node_data("f", 0) + node_data("f", 1)));
    const auto scene_with = [&](const std::string& object) {
        return R"({"camera": {"eye": [2, 1.5, 3], "target": [0.2, 0.2, 0.2]}, "objects": [)" + object + "]}";
    };
    const Scene s = parse_scene(scene_with(R"({"tetmesh": "one.msh", "field": "f", "step": 1, "iso": 0.5, "material": {"color": [0.2, 0.6, 0.9]}})"),
                                "s.json", dir.path);
    REQUIRE(s.quadrics.size() == 1);
    CHECK(s.quadrics[0].material.color[0] == doctest::Approx(0.2));
    // The CPU reference draws it.
    const quadcast::render::Frame f = quadcast::render::build_frame(s, 96, 72);
    const quadcast::render::Image img = quadcast::render::render_cpu(f.primitives, f.camera, f.light, f.options);
    long covered = 0;
    for (float d : img.depth) covered += d < 1.0f;
    CHECK(covered > 100);

    ParseError e = parse_error_of([&] { parse_scene(scene_with(R"({"tetmesh": "one.msh", "iso": 0.5})"), "s.json", dir.path); });
    CHECK(std::string(e.what()).find("s.json:1:") == 0);
    CHECK(std::string(e.what()).find("/objects/0/field: 'one.msh' has several fields") == std::string::npos);  // one field, two steps
    // A choice the scene did not make is located at the object's kind key.
    CHECK(std::string(e.what()).find("/objects/0/tetmesh: field \"f\" has several time steps (0, 1): choose one with \"step\"") != std::string::npos);
    e = parse_error_of([&] { parse_scene(scene_with(R"({"tetmesh": "one.msh", "step": 0})"), "s.json", dir.path); });
    CHECK(std::string(e.what()).find("iso") != std::string::npos);
    e = parse_error_of([&] { parse_scene(scene_with(R"({"tetmesh": "one.msh", "step": 0, "iso": 0.5, "isovalue": 1})"), "s.json", dir.path); });
    CHECK(std::string(e.what()).find("unknown key 'isovalue'") != std::string::npos);
    e = parse_error_of([&] { parse_scene(scene_with(R"({"tetmesh": "one.msh", "step": 0.5, "iso": 0.5})"), "s.json", dir.path); });
    CHECK(std::string(e.what()).find("/objects/0/step: a time step is a non-negative integer") != std::string::npos);
    e = parse_error_of([&] { parse_scene(scene_with(R"({"tetmesh": "one.msh", "step": 0, "iso": 7})"), "s.json", dir.path); });
    CHECK(std::string(e.what()).find("/objects/0/iso: the isovalue 7 is outside the range [0, 1]") != std::string::npos);
    e = parse_error_of([&] { parse_scene(scene_with(R"({"tetmesh": "missing.msh", "iso": 0.5})"), "s.json", dir.path); });
    CHECK(std::string(e.what()).find("/objects/0/tetmesh: cannot open") != std::string::npos);
    std::string bad = one_tet();
    bad.replace(bad.find("0 1 0\n"), 6, "0 1x 0\n");
    dir.write("bad.msh", bad);
    e = parse_error_of([&] { parse_scene(scene_with(R"({"tetmesh": "bad.msh", "iso": 0.5})"), "s.json", dir.path); });
    CHECK(std::string(e.what()).find("bad.msh:23: $Nodes block 1 node 3 y: expected a number, got '1x' (loaded by s.json:1:") != std::string::npos);
}

#ifdef QUADCAST_TEST_HAVE_GMSH
namespace {

/// What Gmsh itself holds of a box mesh it made and wrote to `file`: node tags and
/// coordinates, the tetrahedra's element tags and node tags.
struct GmshModel {
    std::vector<std::size_t> node_tags;
    std::vector<double> xyz;
    int tet_type = 0;
    std::vector<std::size_t> tet_tags, tet_nodes;
};

double sphere_field(double x, double y, double z) { return x * x + y * y + z * z; }

/// A straight-sided tetrahedral mesh of the box [-1, 1]^3 (Gmsh's OpenCASCADE kernel) of order
/// 1 or 2, written by Gmsh as MSH 4.1 with the field "r2" = x^2 + y^2 + z^2 at its nodes (and
/// step 1 with twice the values). `view_with_mesh`: the file is the view saved with its mesh
/// (Gmsh's default for a view: one file); otherwise the mesh is written and the view appended
/// without it (PostProcessing.SaveMesh = 0).
GmshModel gmsh_box(const fs::path& file, double size, int order, bool binary, bool view_with_mesh = false, double offset = 0) {
    GmshModel m;
    gmsh::initialize(0, nullptr, false);
    gmsh::option::setNumber("General.Terminal", 0);
    gmsh::model::add("box");
    gmsh::model::occ::addBox(offset - 1, offset - 1, offset - 1, 2, 2, 2);
    gmsh::model::occ::synchronize();
    gmsh::option::setNumber("Mesh.MeshSizeMax", size);
    gmsh::option::setNumber("Mesh.SecondOrderLinear", 1);
    gmsh::model::mesh::generate(3);
    if (order == 2) gmsh::model::mesh::setOrder(2);
    std::vector<double> param;
    gmsh::model::mesh::getNodes(m.node_tags, m.xyz, param);
    gmsh::option::setNumber("Mesh.MshFileVersion", 4.1);
    gmsh::option::setNumber("Mesh.Binary", binary ? 1 : 0);
    gmsh::option::setNumber("PostProcessing.SaveMesh", view_with_mesh ? 1 : 0);
    if (!view_with_mesh) gmsh::write(file.string());
    const int view = gmsh::view::add("r2");
    for (int step = 0; step < 2; ++step) {
        std::vector<double> v(m.node_tags.size());
        for (std::size_t n = 0; n < v.size(); ++n)
            v[n] = (step + 1) * sphere_field(m.xyz[3 * n] - offset, m.xyz[3 * n + 1] - offset, m.xyz[3 * n + 2] - offset);
        gmsh::view::addHomogeneousModelData(view, step, "box", "NodeData", m.node_tags, v, double(step), 1);
    }
    gmsh::view::write(view, file.string(), !view_with_mesh);
    m.tet_type = order == 2 ? 11 : 4;
    gmsh::model::mesh::getElementsByType(m.tet_type, m.tet_tags, m.tet_nodes);
    gmsh::finalize();
    return m;
}

}  // namespace

TEST_CASE("files Gmsh writes (ASCII and binary, order 1 and 2) read as Gmsh's own model") {
    TempDir dir;
    for (const int order : {1, 2})
        for (const bool binary : {false, true}) {
            CAPTURE(order);
            CAPTURE(binary);
            const fs::path file = dir.path / ("box" + std::to_string(order) + (binary ? "b" : "a") + ".msh");
            const bool view_with_mesh = order == 1 ? binary : !binary;
            CAPTURE(view_with_mesh);
            const GmshModel g = gmsh_box(file, 0.5, order, binary, view_with_mesh);
            const MshMesh m = read_msh(file);
            CHECK(m.binary == binary);
            REQUIRE(m.nodes.size() == g.node_tags.size());
            std::map<std::size_t, std::size_t> index;
            for (std::size_t i = 0; i < m.node_tags.size(); ++i) index[m.node_tags[i]] = i;
            REQUIRE(index.size() == g.node_tags.size());
            long coordinate_mismatches = 0;
            for (std::size_t n = 0; n < g.node_tags.size(); ++n) {
                const Vec3d& p = m.nodes[index.at(g.node_tags[n])];
                for (int k = 0; k < 3; ++k) {
                    const double want = g.xyz[3 * n + static_cast<std::size_t>(k)];
                    // Binary files hold the doubles; ASCII ones 16 significant digits (%.16g).
                    coordinate_mismatches += binary ? p[k] != want : std::fabs(p[k] - want) > 1e-15 * std::max(1.0, std::fabs(want));
                }
            }
            CHECK(coordinate_mismatches == 0);
            REQUIRE(m.tets.size() == g.tet_tags.size());
            const std::size_t per = order == 2 ? 10 : 4;
            long node_mismatches = 0;
            for (std::size_t e = 0; e < m.tets.size(); ++e) {
                CHECK(m.tets[e].tag == g.tet_tags[e]);
                CHECK(m.tets[e].nodes == int(per));
                for (std::size_t k = 0; k < per; ++k) node_mismatches += m.node_tags[m.tets[e].node[k]] != g.tet_nodes[e * per + k];
            }
            CHECK(node_mismatches == 0);
            CHECK(m.skipped_lower_dimensional > 0);  // Gmsh writes the boundary triangles, lines and points too
            REQUIRE(m.fields.size() == 2);
            CHECK(m.fields[1].step == 1);
            double worst = 0;
            for (std::size_t n = 0; n < g.node_tags.size(); ++n) {
                const double want = sphere_field(g.xyz[3 * n], g.xyz[3 * n + 1], g.xyz[3 * n + 2]);
                worst = std::max(worst, std::fabs(m.fields[0].value[index.at(g.node_tags[n])] - want));
                worst = std::max(worst, std::fabs(m.fields[1].value[index.at(g.node_tags[n])] - 2 * want));
            }
            CHECK(worst < 1e-15 * 3 * 2);  // ASCII values are written to 16 digits
        }
}

TEST_CASE("the isosurface of x^2 + y^2 + z^2 on a meshed box is the sphere: pieces, rays, no pinholes") {
    // The box [-1, 1]^3, and the box [49, 51]^3 with the field |x - (50, 50, 50)|^2: there a
    // quadric rounded to float before it is moved to its element would have lost the surface (its
    // constant term ~7500 against a variation of ~0.2 over an element).
    for (const double o : {0.0, 50.0}) {
        CAPTURE(o);
        TempDir dir;
        const fs::path file = dir.path / "box.msh";
        (void)gmsh_box(file, 0.3, 2, true, false, o);
        const double r = 0.7;
        const Vec3d centre{{o, o, o}};
        // Each piece is |x|^2 - r^2 at random points of its tetrahedron (relative to the coefficients' size 1).
        const MshMesh mesh = read_msh(file);
        TetmeshIso what;
        what.field = "r2";
        what.step = 0;
        what.iso = r * r;
        const std::vector<Quadric> pieces = tetmesh_isosurface(mesh, what, Material{}, {});
        std::printf("[msh] sphere r = 0.7 on %zu 10-node tetrahedra: %zu pieces\n", mesh.tets.size(), pieces.size());
        REQUIRE(pieces.size() > 100);
        std::mt19937 rng(11);
        double worst = 0;
        for (const Quadric& q : pieces)
            for (int i = 0; i < 20; ++i) {
                const Vec3d p = random_point(rng, q.tetrahedron);
                worst = std::max(worst, std::fabs(eval(q.q, p[0], p[1], p[2]) - (sphere_field(p[0] - o, p[1] - o, p[2] - o) - r * r)));
            }
        CHECK(worst < (o == 0 ? 1e-13 : 1e-9));  // relative to |x|^2 ~ 7500 there

        // Drawn by the CPU reference, the pieces cover the pixels whose exact ray meets the sphere, but
        // for those within 1.5 pixels of its silhouette, and every hit lies on it.
        const int w = 240, h = 180;
        const Vec3d eye = centre + Vec3d{{0.9, 1.3, 3.1}};
        char camera[400];
        std::snprintf(camera, sizeof camera, R"("camera": {"eye": [%.17g, %.17g, %.17g], "target": [%g, %g, %g], "fov_y": 30})", eye[0], eye[1],
                      eye[2], o, o, o);
        const std::string scene = std::string("{") + camera + R"(, "objects": [{"tetmesh": "box.msh", "field": "r2", "step": 0, "iso": 0.49}]})";
        for (const bool culling : {true, false}) {
            CAPTURE(culling);
            Scene s = parse_scene(scene, "s.json", dir.path);
            s.options.culling = culling;
            const quadcast::render::Frame f = quadcast::render::build_frame(s, w, h);
            const quadcast::render::Image img = quadcast::render::render_cpu(f.primitives, f.camera, f.light, f.options);
            // Exact pixel rays from the double camera: eye, and the view directions through pixel centres.
            const Vec3d fwd = normalize(centre - eye);
            const Vec3d right = normalize(cross(fwd, Vec3d{{0, 1, 0}}));
            const Vec3d up = cross(right, fwd);
            const double th = std::tan(30.0 * M_PI / 360.0);
            const auto& V = f.camera.view;
            const auto& P = f.camera.projection;
            long inside = 0, holes = 0, outside_hits = 0, far_hits = 0;
            double worst_r = 0;
            for (int y = 0; y < h; ++y)
                for (int x = 0; x < w; ++x) {
                    const double u = (2 * (x + 0.5) / w - 1) * th * w / h, v = (1 - 2 * (y + 0.5) / h) * th;
                    const Vec3d d = normalize(fwd + right * u + up * v);
                    // Distance of the ray's line from the centre, in pixels at the closest point.
                    const double tc = -dot(eye - centre, d);
                    const double miss = length(eye - centre + d * tc);
                    const double px = tc * 2 * th / h;  // one pixel at that distance
                    const float depth = img.depth[static_cast<std::size_t>(y) * w + static_cast<std::size_t>(x)];  // row 0 at the top, as y here
                    if (miss < r - 1.5 * px) {
                        ++inside;
                        if (!(depth < 1.0f)) ++holes;
                    } else if (miss > r + 1.5 * px) {
                        if (depth < 1.0f) ++outside_hits;
                    }
                    if (!(depth < 1.0f) || miss > r - 1.5 * px) continue;
                    // The hit: view z from the window depth, then the point on the exact ray.
                    const double ndc = 2.0 * double(depth) - 1.0;
                    const double A = double(P[2][2]), B = double(P[3][2]);
                    const double zv = -B / (ndc + A);  // view-space z (negative)
                    // view z of eye + t d is dot(V's third row, (p, 1)): solve for t.
                    const double v0 = double(V[0][2]), v1 = double(V[1][2]), v2 = double(V[2][2]), v3 = double(V[3][2]);
                    const double z0 = v0 * eye[0] + v1 * eye[1] + v2 * eye[2] + v3;
                    const double dz = v0 * d[0] + v1 * d[1] + v2 * d[2];
                    const Vec3d p = eye + d * ((zv - z0) / dz);
                    const double cos_theta = -dot(normalize(p - centre), d);
                    if (cos_theta < 0.2) continue;
                    const double err = std::fabs(length(p - centre) - r);
                    worst_r = std::max(worst_r, err);
                    if (err > 1e-4) ++far_hits;
                }
            std::printf("[msh] box centred at %g, culling %s: %ld interior pixels, %ld holes, %ld hits outside the silhouette, worst | |p - c| - r | = "
                        "%.2e (window depth resolution included)\n",
                        o, culling ? "on" : "off", inside, holes, outside_hits, worst_r);
            CHECK(inside > 10000);
            CHECK(holes == 0);
            CHECK(outside_hits == 0);
            CHECK(far_hits == 0);
        }
    }
}
#else
TEST_CASE("files Gmsh writes read as Gmsh's own model [libgmsh not found: skipped]") {
    MESSAGE("install libgmsh-dev (apt-get install libgmsh-dev) to compare the MSH reader with Gmsh");
}
#endif
