// tools/msh_example.cpp -- `quadcast-msh-example`: a 10-node tetrahedral Gmsh mesh of a box with
// a scalar field at its nodes, written by Gmsh itself (its C++ API, Debian's libgmsh-dev).
//
// The demo data of the "tetmesh" scene object and the test meshes come from here, so that the
// files the reader is tested on are written by Gmsh, not by us:
//     quadcast-msh-example -o box.msh [--field sphere|tangle|linear] [--size 0.25] [--box -1,1]
//                          [--order 1|2] [--binary] [--steps 1]
// Fields (named after themselves in the file's $NodeData): "sphere" x^2 + y^2 + z^2 (exactly
// quadratic, so its isosurfaces are spheres), "tangle" the tangle cube x^4 - 5x^2 + y^4 - 5y^2 +
// z^4 - 5z^2 + 11.8 (quartic; a quadratic element approximates it), "linear" x + 2y + 3z.
// The mesh is straight-sided (Mesh.SecondOrderLinear): the edge nodes are the edges' midpoints.
// With --steps N the field is written N times (steps 0..N-1, the values of step k scaled by k+1).
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <string>
#include <vector>

#include <gmsh.h>

namespace {

double field_value(const std::string& name, double x, double y, double z) {
    if (name == "sphere") return x * x + y * y + z * z;
    if (name == "linear") return x + 2 * y + 3 * z;
    if (name == "tangle") {
        const auto t = [](double u) { return u * u * u * u - 5 * u * u; };
        return t(x) + t(y) + t(z) + 11.8;
    }
    throw std::invalid_argument("unknown field '" + name + "' (sphere, tangle, linear)");
}

[[noreturn]] void usage(const std::string& why) {
    std::fprintf(stderr,
                 "quadcast-msh-example: %s\nusage: quadcast-msh-example -o FILE.msh [--field sphere|tangle|linear] "
                 "[--size H] [--box LO,HI] [--order 1|2] [--binary] [--steps N]\n",
                 why.c_str());
    std::exit(2);
}

double number(const char* s, const char* what) {
    char* end = nullptr;
    const double v = std::strtod(s, &end);
    if (end == s || *end != '\0' || !std::isfinite(v)) usage(std::string("bad ") + what + " '" + s + "'");
    return v;
}

}  // namespace

int main(int argc, char** argv) {
    std::string out, field = "sphere";
    double size = 0.25, lo = -1, hi = 1;
    int order = 2, steps = 1;
    bool binary = false;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        const auto value = [&]() -> const char* {
            if (i + 1 >= argc) usage(a + " needs a value");
            return argv[++i];
        };
        if (a == "-o") out = value();
        else if (a == "--field") field = value();
        else if (a == "--size") size = number(value(), "size");
        else if (a == "--order") order = static_cast<int>(number(value(), "order"));
        else if (a == "--steps") steps = static_cast<int>(number(value(), "steps"));
        else if (a == "--binary") binary = true;
        else if (a == "--box") {
            const std::string b = value();
            const std::size_t comma = b.find(',');
            if (comma == std::string::npos) usage("--box takes LO,HI");
            lo = number(b.substr(0, comma).c_str(), "box");
            hi = number(b.substr(comma + 1).c_str(), "box");
        } else usage("unknown argument '" + a + "'");
    }
    if (out.empty()) usage("no output file (-o)");
    if (!(size > 0) || !(hi > lo) || (order != 1 && order != 2) || steps < 1) usage("bad --size, --box, --order or --steps");
    try {
        (void)field_value(field, 0, 0, 0);
        gmsh::initialize(0, nullptr, false);
        gmsh::option::setNumber("General.Terminal", 0);
        gmsh::model::add("box");
        gmsh::model::occ::addBox(lo, lo, lo, hi - lo, hi - lo, hi - lo);
        gmsh::model::occ::synchronize();
        gmsh::option::setNumber("Mesh.MeshSizeMax", size);
        gmsh::option::setNumber("Mesh.SecondOrderLinear", 1);
        gmsh::model::mesh::generate(3);
        if (order == 2) gmsh::model::mesh::setOrder(2);
        std::vector<std::size_t> tags;
        std::vector<double> xyz, param;
        gmsh::model::mesh::getNodes(tags, xyz, param);
        gmsh::option::setNumber("Mesh.MshFileVersion", 4.1);
        gmsh::option::setNumber("Mesh.Binary", binary ? 1 : 0);
        gmsh::option::setNumber("PostProcessing.SaveMesh", 0);
        gmsh::write(out);
        const int view = gmsh::view::add(field);
        for (int s = 0; s < steps; ++s) {
            std::vector<double> values(tags.size());
            for (std::size_t n = 0; n < tags.size(); ++n)
                values[n] = (s + 1) * field_value(field, xyz[3 * n], xyz[3 * n + 1], xyz[3 * n + 2]);
            gmsh::view::addHomogeneousModelData(view, s, "box", "NodeData", tags, values, double(s), 1);
        }
        gmsh::view::write(view, out, true);
        std::vector<int> types;
        std::vector<std::vector<std::size_t>> element_tags, node_tags;
        gmsh::model::mesh::getElements(types, element_tags, node_tags, 3);
        std::size_t tets = 0;
        for (const auto& e : element_tags) tets += e.size();
        std::printf("%s: %zu nodes, %zu tetrahedra of order %d, field '%s' (%d step%s), %s\n", out.c_str(), tags.size(), tets,
                    order, field.c_str(), steps, steps == 1 ? "" : "s", binary ? "binary" : "ASCII");
        gmsh::finalize();
    } catch (const std::string& e) {  // (Gmsh's API throws its error message as a string)
        std::fprintf(stderr, "quadcast-msh-example: Gmsh: %s\n", e.c_str());
        return 1;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "quadcast-msh-example: %s\n", e.what());
        return 1;
    }
    return 0;
}
