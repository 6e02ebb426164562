// src/scene/scene_json.cpp -- the JSON scene format of `quadcast render` (see the README)
#include "quadcast/scene/scene_json.hpp"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <numbers>
#include <tuple>

#include "quadcast/image/image_io.hpp"
#include "quadcast/scene/msh.hpp"
#include "quadcast/scene/off.hpp"
#include "quadcast/scene/pdb.hpp"

namespace quadcast::scene {

namespace {

const std::vector<std::string_view> kCommonKeys = {"color", "material", "comment"};

/// A number for a message: "%g" (1e-200, not std::to_string's 0.000000).
std::string shortest(double x) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%g", x);
    return buf;
}

/// The errors found so far, each with its position in the scene file (the position of the entry
/// that loaded another file, for errors inside that file), for sorting into file order.
struct ErrorList {
    struct Item {
        TextPosition at;
        std::size_t found;  // order of discovery, to keep equal positions stable
        ParseError error;
    };
    std::vector<Item> items;
    std::string file;  ///< the scene file's name in messages

    void add(const ParseError& e, const JsonNode* from = nullptr) {
        TextPosition at{e.line(), e.column()};
        if (e.file() != file && from) at = from->position();
        items.push_back({at, items.size(), e});
    }
    /// Runs `f`, recording a ParseError (or running out of memory) instead of propagating it.
    template <class F>
    bool attempt(const JsonNode& at, F&& f) {
        try {
            f();
            return true;
        } catch (const ParseError& e) {
            add(e, &at);
        } catch (const std::bad_alloc&) {
            add(ParseError(at.location(), "out of memory while loading this entry"), &at);
        }
        return false;
    }
    [[noreturn]] void raise() {
        std::stable_sort(items.begin(), items.end(), [](const Item& a, const Item& b) {
            return std::tie(a.at.line, a.at.column, a.found) < std::tie(b.at.line, b.at.column, b.found);
        });
        std::vector<ParseError> sorted;
        for (const Item& i : items) sorted.push_back(i.error);
        throw ParseErrors(std::move(sorted));
    }
};

/// Re-throws a reader's error with a note of which scene entry loaded the file.
[[noreturn]] void rethrow_from(const ParseError& e, const JsonNode& from) {
    const Location l = from.location();
    throw ParseError(e.where(), e.message() + " (loaded by " + format_location({l.file, l.line, l.column, ""}) +
                                    from.pointer() + ")");
}

// Primitive kinds --------------------------------------------------------------------------------

void load_sphere(ObjectContext& ctx) {
    const JsonNode& v = ctx.value;
    v.expect_keys({"center", "radius", "comment"});
    ctx.scene.spheres.push_back({v.at("center").vec3(), v.at("radius").number(Range::positive), ctx.material});
}

/// Rodrigues' rotation matrix (columns are the images of the coordinate axes).
std::array<Vec3d, 3> rotation(const Vec3d& axis, double angle_deg) {
    const Vec3d k = normalize(axis);
    const double a = angle_deg * std::numbers::pi / 180.0, c = std::cos(a), s = std::sin(a);
    std::array<Vec3d, 3> cols{};
    for (int j = 0; j < 3; ++j) {
        Vec3d e{{0.0, 0.0, 0.0}};
        e[j] = 1.0;
        // v cos + (k x v) sin + k (k.v)(1 - cos)
        cols[std::size_t(j)] = (e * c + cross(k, e) * s) + k * (dot(k, e) * (1.0 - c));
    }
    return cols;
}

void load_ellipsoid(ObjectContext& ctx) {
    const JsonNode& v = ctx.value;
    v.expect_keys({"center", "axes", "radii", "rotation", "comment"});
    Ellipsoid e{v.at("center").vec3(), {}, ctx.material};
    if (v.has("axes") == v.has("radii")) v.fail("give either \"axes\" (3 orthogonal semi-axis vectors) or \"radii\"");
    if (v.has("axes")) {
        if (v.has("rotation")) v.at("rotation").fail("\"rotation\" goes with \"radii\"; \"axes\" are already rotated");
        const std::vector<JsonNode> axes = v.at("axes").array(3, "semi-axis vectors");
        for (std::size_t i = 0; i < 3; ++i) e.axes[i] = axes[i].direction();
        for (std::size_t i = 0; i < 3; ++i)
            for (std::size_t j = i + 1; j < 3; ++j) {
                const double c = std::abs(dot(e.axes[i], e.axes[j])) / (length(e.axes[i]) * length(e.axes[j]));
                if (c > 1e-6)
                    axes[j].fail("not orthogonal to axis " + std::to_string(i) + " (|cos| = " + std::to_string(c) + ")");
            }
    } else {
        const std::vector<JsonNode> r = v.at("radii").array(3, "numbers");
        std::array<Vec3d, 3> rot = {Vec3d{{1, 0, 0}}, Vec3d{{0, 1, 0}}, Vec3d{{0, 0, 1}}};
        if (const auto rn = v.get("rotation")) {
            rn->expect_keys({"axis", "angle", "comment"});
            rot = rotation(rn->at("axis").direction(), rn->at("angle").number());
        }
        for (std::size_t i = 0; i < 3; ++i) e.axes[i] = rot[i] * r[i].number(Range::positive);
    }
    // The renderer inverts the axis matrix and squares the inverse: lengths outside
    // [1e-150, 1e150] under- or overflow there, so they are rejected here, with the location.
    const JsonNode where = v.has("axes") ? v.at("axes") : v.at("radii");
    for (std::size_t i = 0; i < 3; ++i) {
        double big = 0.0;
        for (int k = 0; k < 3; ++k) big = std::max(big, std::abs(e.axes[i][k]));
        if (!(big >= 1e-150 && big <= 1e150))
            where.fail("semi-axis " + std::to_string(i) + " has length " + shortest(big) +
                       ", outside [1e-150, 1e150] (the ellipsoid's matrix would under- or overflow a double)");
    }
    ctx.scene.ellipsoids.push_back(e);
}

void load_cylinder(ObjectContext& ctx) {
    const JsonNode& v = ctx.value;
    v.expect_keys({"p0", "p1", "radius", "caps", "comment"});
    Cylinder c{v.at("p0").vec3(), v.at("p1").vec3(), v.at("radius").number(Range::positive), true, ctx.material};
    if (const auto caps = v.get("caps")) c.caps = caps->boolean();
    if (!(length2(c.p1 - c.p0) > 0.0)) v.at("p1").fail("equals p0 (zero-length axis)");
    ctx.scene.cylinders.push_back(c);
}

void load_cone(ObjectContext& ctx) {
    const JsonNode& v = ctx.value;
    v.expect_keys({"apex", "base", "radius", "cap", "comment"});
    Cone c{v.at("apex").vec3(), v.at("base").vec3(), v.at("radius").number(Range::positive), true, ctx.material};
    if (const auto cap = v.get("cap")) c.cap = cap->boolean();
    if (!(length2(c.base - c.apex) > 0.0)) v.at("base").fail("equals apex (zero-length axis)");
    ctx.scene.cones.push_back(c);
}

void load_quadric(ObjectContext& ctx) {
    const JsonNode& v = ctx.value;
    v.expect_keys({"coefficients", "matrix", "bound", "comment"});
    Quadric q{};
    q.material = ctx.material;
    if (v.has("coefficients") == v.has("matrix"))
        v.fail("give either \"coefficients\" (10 numbers k000 k100 k010 k001 k110 k011 k101 k200 k020 k002) or \"matrix\" (4x4)");
    if (v.has("coefficients")) {
        const std::vector<JsonNode> k = v.at("coefficients").array(10, "numbers");
        std::array<double, 10> c{};
        for (std::size_t i = 0; i < 10; ++i) c[i] = k[i].number();
        q.q = quadric_matrix_from_coefficients(c);
    } else {
        const JsonNode m = v.at("matrix");
        const std::vector<JsonNode> rows = m.array(4, "rows");
        double max_abs = 0.0;
        for (int i = 0; i < 4; ++i) {
            const std::vector<JsonNode> r = rows[std::size_t(i)].array(4, "numbers");
            for (int j = 0; j < 4; ++j) {
                q.q[j][i] = r[std::size_t(j)].number();
                max_abs = std::max(max_abs, std::abs(q.q[j][i]));
            }
        }
        double asym = 0.0;
        for (int i = 0; i < 4; ++i)
            for (int j = i + 1; j < 4; ++j) {
                asym = std::max(asym, std::abs(q.q[j][i] - q.q[i][j]));
                q.q[j][i] = q.q[i][j] = 0.5 * (q.q[j][i] + q.q[i][j]);
            }
        if (asym > 1e-12 * max_abs)
            ctx.scene.warnings.push_back(m.warning("matrix is not symmetric; using (Q + Q^T)/2, which has the same quadric"));
    }
    bool all_zero = true;
    for (int j = 0; j < 4; ++j)
        for (int i = 0; i < 4; ++i) all_zero = all_zero && q.q[j][i] == 0.0;
    if (all_zero) v.fail("every coefficient is zero (no surface)");

    const JsonNode b = v.at("bound");
    b.expect_keys({"sphere", "tetrahedron", "comment"});
    if (b.has("sphere") == b.has("tetrahedron")) b.fail("give either \"sphere\" or \"tetrahedron\"");
    if (const auto s = b.get("sphere")) {
        s->expect_keys({"center", "radius", "comment"});
        q.bound = Quadric::Bound::sphere;
        q.sphere = {s->at("center").vec3(), s->at("radius").number(Range::positive)};
    } else {
        const JsonNode t = b.at("tetrahedron");
        const std::vector<JsonNode> p = t.array(4, "points");
        q.bound = Quadric::Bound::tetrahedron;
        for (std::size_t i = 0; i < 4; ++i) q.tetrahedron.p[i] = p[i].vec3();
        const auto& P = q.tetrahedron.p;
        const Vec3d e1 = P[1] - P[0], e2 = P[2] - P[0], e3 = P[3] - P[0];
        const double vol6 = std::abs(dot(e1, cross(e2, e3)));
        const double l = std::max({length(e1), length(e2), length(e3), length(P[2] - P[1]), length(P[3] - P[1]), length(P[3] - P[2])});
        if (!std::isfinite(l) || !std::isfinite(vol6) || !std::isfinite(l * l * l))
            t.fail("tetrahedron too large: its volume (edge length " + shortest(l) + " cubed) overflows a double");
        if (!(vol6 > 1e-12 * l * l * l)) t.fail("degenerate tetrahedron (zero volume)");
    }
    ctx.scene.quadrics.push_back(q);
}

void load_quad(ObjectContext& ctx) {
    const JsonNode& v = ctx.value;
    v.expect_keys({"corners", "comment"});
    const JsonNode c = v.at("corners");
    const std::vector<JsonNode> p = c.array(4, "corner points (around the perimeter)");
    BilinearQuad q{};
    q.material = ctx.material;
    for (std::size_t i = 0; i < 4; ++i) q.p[i] = p[i].vec3();
    if (quad_has_zero_area(q.p)) c.fail("degenerate quad: the corners are collinear or coincident (zero area)");
    ctx.scene.quads.push_back(q);
}

// File kinds -----------------------------------------------------------------------------------

void load_pdb(ObjectContext& ctx) {
    const std::filesystem::path path = ctx.file_path();
    const JsonNode& e = ctx.entry;
    MoleculeLook look;
    if (const auto s = e.get("style")) {
        const std::string k = s->choice({"balls_and_sticks", "space_filling", "skin"});
        look.style = k == "space_filling" ? MoleculeStyle::space_filling : k == "skin" ? MoleculeStyle::skin : MoleculeStyle::balls_and_sticks;
    }
    const bool sticks = look.style == MoleculeStyle::balls_and_sticks;
    const bool skin = look.style == MoleculeStyle::skin;
    for (std::string_view k : {"ball_scale", "bond_radius"})
        if (!sticks && e.has(k)) e.at(k).fail("only for \"style\": \"balls_and_sticks\"");
    if (sticks && e.has("vdw_scale")) e.at("vdw_scale").fail("only for \"style\": \"space_filling\" or \"skin\"");
    if (!skin && e.has("shrink")) e.at("shrink").fail("only for \"style\": \"skin\"");
    if (const auto n = e.get("ball_scale")) look.ball_scale = n->number(Range::positive);
    if (const auto n = e.get("bond_radius")) look.bond_radius = n->number(Range::positive);
    if (const auto n = e.get("vdw_scale")) look.vdw_scale = n->number(Range::positive);
    if (const auto n = e.get("shrink")) {
        look.shrink = n->number();
        if (!(look.shrink > 0 && look.shrink < 1)) n->fail("the shrink factor must lie in (0, 1), got " + shortest(look.shrink));
    }
    const SkinBuildFunction build_skin = skin ? skin_build_function() : nullptr;
    if (skin && !build_skin)
        e.at("style").fail("skin surfaces need the skin component, which is not linked into this program "
                           "(link quadcast_skin and call quadcast::skin::install_scene_builder)");
    PdbOptions opt;
    if (const auto n = e.get("strict")) opt.strict = n->boolean();

    Molecule m;
    try {
        m = read_pdb(path, opt);
        if (sticks) compute_bonds(m);
    } catch (const ParseError& err) {
        rethrow_from(err, ctx.value);
    }
    ctx.scene.warnings.insert(ctx.scene.warnings.end(), m.warnings.begin(), m.warnings.end());
    if (!skin) {
        append_molecule(ctx.scene, m, look, ctx.material, ctx.color_given ? &ctx.material.color : nullptr);
        return;
    }
    // The skin: the atoms' van der Waals balls (times vdw_scale) handed to the installed builder.
    std::vector<SkinBall> balls;
    balls.reserve(m.atoms.size());
    for (const Atom& a : m.atoms) balls.push_back({a.position, look.vdw_scale * a.element->vdw, ctx.color_given ? ctx.material.color : a.element->cpk});
    std::vector<Quadric> pieces;
    try {
        pieces = build_skin(balls, look.shrink, ctx.material);
    } catch (const ParseError&) {
        throw;
    } catch (const std::bad_alloc&) {
        ctx.value.fail("out of memory while building the skin surface of '" + path.string() + "'");
    } catch (const std::exception& err) {
        ctx.value.fail(std::string("the skin surface of '") + path.string() + "': " + err.what());
    }
    ctx.scene.quadrics.insert(ctx.scene.quadrics.end(), pieces.begin(), pieces.end());
}

void load_off(ObjectContext& ctx) {
    const std::filesystem::path path = ctx.file_path();
    OffOptions opt;
    if (const auto t = ctx.entry.get("triangles"))
        opt.triangles = t->choice({"degenerate", "error"}) == "error" ? TrianglePolicy::error : TrianglePolicy::degenerate_quad;
    std::vector<BilinearQuad> quads;
    try {
        OffMesh mesh = read_off(path);
        ctx.scene.warnings.insert(ctx.scene.warnings.end(), mesh.warnings.begin(), mesh.warnings.end());
        quads = off_to_quads(mesh, opt, ctx.material, ctx.scene.warnings);
    } catch (const ParseError& err) {
        rethrow_from(err, ctx.value);
    }
    if (quads.empty()) ctx.scene.warnings.push_back(ctx.value.warning("the mesh has no usable faces"));
    ctx.scene.quads.insert(ctx.scene.quads.end(), quads.begin(), quads.end());
}

/// "volume": "path" or "synthetic:marschner_lobb[:N]" / "synthetic:franke[:N]"; "iso" (required),
/// "scheme": "qss" (default) | "s31" | "trilinear". Synthetic boxes are known ([-1,1]^3 and
/// [0,1]^3); a file's box comes from `volume_box_function()` when one is installed.
void load_volume(ObjectContext& ctx) {
    Volume v;
    v.material = ctx.material;
    v.iso = ctx.entry.at("iso").number();
    v.iso_where = ctx.entry.at("iso").location();
    if (const auto s = ctx.entry.get("scheme")) {
        const std::string k = s->choice({"qss", "s31", "trilinear"});
        v.scheme = k == "s31" ? Volume::Scheme::s31 : k == "trilinear" ? Volume::Scheme::trilinear : Volume::Scheme::qss;
    }
    if (const auto m = ctx.entry.get("method")) {
        v.method = m->choice({"bezier", "quadric"}) == "quadric" ? Volume::Method::quadric : Volume::Method::bezier;
        if (v.method == Volume::Method::quadric && v.scheme != Volume::Scheme::qss)
            m->fail("\"quadric\" draws the pieces of a QSS spline (\"scheme\": \"qss\"); S31 pieces are cubic and trilinear cells are not quadrics");
    }
    const std::string text = ctx.value.string();
    if (text.rfind("synthetic:", 0) == 0) {
        std::string rest = text.substr(10), name = rest;
        const std::size_t colon = rest.find(':');
        if (colon != std::string::npos) {
            name = rest.substr(0, colon);
            const std::string num = rest.substr(colon + 1);
            char* end = nullptr;
            const long n = std::strtol(num.c_str(), &end, 10);
            if (num.empty() || *end != '\0' || n < 2 || n > 1024)
                ctx.value.fail("the sample count after " + quote_token(name + ":") + " must be an integer in [2, 1024], got " + quote_token(num));
            v.size = static_cast<int>(n);
        }
        std::replace(name.begin(), name.end(), '_', '-');
        if (name != "marschner-lobb" && name != "franke")
            ctx.value.fail("unknown synthetic volume " + quote_token(name) + " (expected marschner_lobb or franke)");
        v.input = name;
        v.synthetic = true;
        const double lo = name == "franke" ? 0.0 : -1.0;
        v.box.extend(Vec3d{{lo, lo, lo}});
        v.box.extend(Vec3d{{1.0, 1.0, 1.0}});
    } else {
        v.input = ctx.file_path().string();
        if (const VolumeBoxFunction f = volume_box_function()) {
            try {
                v.box = f(v);
            } catch (const ParseError&) {
                throw;  // located by the box function (e.g. at "iso")
            } catch (const std::bad_alloc&) {
                ctx.value.fail("out of memory while reading '" + v.input + "'");
            } catch (const std::exception& e) {
                ctx.value.fail(e.what());
            }
        }
    }
    ctx.scene.volumes.push_back(v);
}

/// "slim": a SLIM model file (`quadcast-slim 1`), or a point file (.xyz, .pwn, .ply, .off) built
/// into one at "error" (required for point files, > 0; an error for model files), by the
/// installed `slim_load_function()`.
void load_slim(ObjectContext& ctx) {
    Slim m;
    m.material = ctx.material;
    const std::filesystem::path path = ctx.file_path();
    m.input = path.string();
    std::string ext = path.extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    const bool points = ext == ".xyz" || ext == ".pwn" || ext == ".ply" || ext == ".off";
    if (points) {
        if (!ctx.entry.has("error"))
            ctx.value.fail("a point file needs \"error\": the fit threshold relative to the bounding-box diagonal (> 0)");
        m.error = ctx.entry.at("error").number(Range::positive);
    } else if (ctx.entry.has("error")) {
        ctx.entry.at("error").fail("only for point files (.xyz, .pwn, .ply, .off); '" + path.filename().string() + "' is read as a SLIM model");
    }
    const SlimLoadFunction f = slim_load_function();
    if (!f) ctx.value.fail("SLIM surfaces need the slim component (quadcast::slim::install_scene_loader)");
    try {
        m.balls = f(path, m.error);
    } catch (const ParseError& err) {
        rethrow_from(err, ctx.value);
    } catch (const std::bad_alloc&) {
        ctx.value.fail("out of memory while reading '" + m.input + "'");
    } catch (const std::exception& e) {
        ctx.value.fail(e.what());
    }
    if (m.balls.empty()) ctx.scene.warnings.push_back(ctx.value.warning("the SLIM model has no balls"));
    ctx.scene.slims.push_back(std::move(m));
}

/// "tetmesh": a Gmsh .msh file (4.1) of 4- or 10-node tetrahedra; "iso" (required) of the nodal
/// field "field" (optional when the file has one field) at time step "step" (optional when the
/// field has one). Each element the isosurface crosses becomes a quadric clipped to it.
void load_tetmesh(ObjectContext& ctx) {
    const std::filesystem::path path = ctx.file_path();
    TetmeshIso what;
    const JsonNode iso = ctx.entry.at("iso");
    what.iso = iso.number();
    if (const auto f = ctx.entry.get("field")) {
        what.field = f->string();
        if (what.field.empty()) f->fail("empty field name");
    }
    if (const auto st = ctx.entry.get("step")) {
        const double k = st->number(Range::nonnegative);
        if (k != std::floor(k) || k > 2147483647.0) st->fail("a time step is a non-negative integer", true);
        what.step = static_cast<int>(k);
    }
    std::vector<Quadric> pieces;
    try {
        const MshMesh mesh = read_msh(path);
        ctx.scene.warnings.insert(ctx.scene.warnings.end(), mesh.warnings.begin(), mesh.warnings.end());
        pieces = tetmesh_isosurface(mesh, what, ctx.material, ctx.value.location());
    } catch (const ParseError& err) {
        if (err.file() != path.string()) {  // the choice's error: its field names the scene key
            if (const auto key = ctx.entry.get(err.field())) key->fail(err.message());
            ctx.value.fail(err.message());
        }
        rethrow_from(err, ctx.value);
    }
    if (pieces.empty()) ctx.scene.warnings.push_back(iso.warning("the isosurface crosses no element (nothing to draw)"));
    ctx.scene.quadrics.insert(ctx.scene.quadrics.end(), pieces.begin(), pieces.end());
}

// Scene sections -------------------------------------------------------------------------------

Material load_material(const JsonNode& entry, bool& color_given) {
    Material m;
    color_given = false;
    if (const auto mn = entry.get("material")) {
        mn->expect_keys({"color", "specular", "shininess", "comment"});
        if (const auto c = mn->get("color")) m.color = c->color(), color_given = true;
        if (const auto s = mn->get("specular")) m.specular = s->number(Range::unit);
        if (const auto s = mn->get("shininess")) m.shininess = s->number(Range::positive);
    }
    if (const auto c = entry.get("color")) {
        if (color_given) c->fail("the colour is given twice (also in \"material\")", true);
        m.color = c->color();
        color_given = true;
    }
    return m;
}

/// Entry `index` of "objects".
void load_object(Scene& scene, const JsonNode& entry, std::size_t index, const std::filesystem::path& base_dir) {
    if (!entry.json().is_object()) entry.fail("expected an object such as {\"sphere\": {...}}, got " + entry.describe());
    const ObjectKind* kind = nullptr;
    for (const ObjectKind& k : object_kinds()) {
        if (!entry.has(k.key)) continue;
        if (kind) entry.at(k.key).fail("an object has one kind; this one has both '" + std::string(kind->key) + "' and '" +
                                            std::string(k.key) + "'", true);
        kind = &k;
    }
    if (!kind) {
        // Name a misspelt kind key if there is one, else say which kinds exist.
        std::vector<std::string_view> all = kCommonKeys;
        for (const ObjectKind& k : object_kinds()) all.push_back(k.key);
        entry.expect_keys(all);
        std::string kinds;
        for (const ObjectKind& k : object_kinds()) kinds += (kinds.empty() ? "" : ", ") + std::string(k.key);
        entry.fail("no object kind; an object needs one of the keys: " + kinds);
    }
    std::vector<std::string_view> allowed = kCommonKeys;
    allowed.push_back(kind->key);
    allowed.insert(allowed.end(), kind->options.begin(), kind->options.end());
    entry.expect_keys(allowed);

    bool color_given = false;
    const Material material = load_material(entry, color_given);
    ObjectContext ctx{scene, entry, entry.at(kind->key), material, color_given, base_dir};
    const TextPosition at = ctx.value.position();
    scene.origins.push_back({scene.spheres.size(), scene.ellipsoids.size(), scene.cylinders.size(), scene.cones.size(),
                             scene.quadrics.size(), scene.quads.size(), scene.slims.size(), at.line, at.column, index, kind->key});
    kind->load(ctx);
}

/// "environment": exactly one of "file" (a latitude-longitude PNG, relative to the scene file) or
/// "procedural" (an object of optional colours "zenith", "horizon", "ground"), and "reflectivity"
/// in [0, 1].
void load_environment(const JsonNode& n, Options& o, const std::filesystem::path& base_dir) {
    n.expect_keys({"file", "procedural", "reflectivity", "comment"});
    if (n.has("file") == n.has("procedural")) n.fail("an environment has either \"file\" or \"procedural\"");
    if (const auto f = n.get("file")) {
        const std::string s = f->string();
        if (s.empty()) f->fail("empty file name");
        std::filesystem::path p(s);
        if (p.is_relative()) p = base_dir / p;
        p = p.lexically_normal();
        std::error_code ec;
        if (!std::filesystem::is_regular_file(p, ec)) f->fail("cannot open '" + p.string() + "': no such file");
        // Decoded here, so that a file that is no PNG, or a corrupt one, is an error at this
        // location (and not at render time).
        std::ifstream in(p, std::ios::binary);
        char sig[8] = {};
        in.read(sig, sizeof sig);
        if (!in || std::memcmp(sig, "\x89PNG\r\n\x1a\n", 8) != 0)
            f->fail("'" + p.string() + "' is not a PNG file (no PNG signature)");
        try {
            o.environment_image = std::make_shared<const render::Image>(render::read_png(p));
        } catch (const std::bad_alloc&) {
            throw;
        } catch (const std::exception& e) {
            f->fail(std::string("cannot decode the environment image: ") + e.what());
        }
        o.environment = Options::Environment::file;
        o.environment_file = p;
    } else {
        const JsonNode sky = n.at("procedural");
        sky.expect_keys({"zenith", "horizon", "ground", "comment"});
        o.environment = Options::Environment::procedural;
        if (const auto c = sky.get("zenith")) o.sky_zenith = c->color();
        if (const auto c = sky.get("horizon")) o.sky_horizon = c->color();
        if (const auto c = sky.get("ground")) o.sky_ground = c->color();
    }
    if (const auto r = n.get("reflectivity")) o.reflectivity = r->number(Range::unit);
}

Options load_options(const JsonNode& n, const std::filesystem::path& base_dir) {
    n.expect_keys({"culling", "tight_bounds", "occlusion_culling", "occlusion_phases", "occlusion_min_overlap", "occlusion_reuse", "deferred", "shadows", "silhouettes", "outline", "shadow", "background", "environment", "comment"});
    Options o;
    if (const auto ol = n.get("outline")) {
        ol->expect_keys({"depth", "crease", "strength", "comment"});
        if (const auto v = ol->get("depth")) o.outline_depth = v->number(Range::positive);
        if (const auto v = ol->get("crease")) o.outline_crease = v->number(Range::positive);
        if (const auto v = ol->get("strength")) o.outline_strength = v->number(Range::unit);
    }
    if (const auto sh = n.get("shadow")) {
        sh->expect_keys({"map_size", "pcf_step", "bias", "reuse", "comment"});
        if (const auto v = sh->get("map_size")) {
            const double m = v->number(Range::positive);
            if (m != std::floor(m) || m < 64 || m > 8192) v->fail("the shadow map size must be an integer in [64, 8192]", true);
            o.shadow_map_size = static_cast<int>(m);
        }
        if (const auto v = sh->get("pcf_step")) {
            const double m = v->number(Range::positive);
            if (m != std::floor(m) || m > 64) v->fail("the PCF step must be an integer in [1, 64] (texels)", true);
            o.pcf_step = static_cast<int>(m);
        }
        if (const auto v = sh->get("bias")) o.shadow_bias = v->number(Range::nonnegative);
        if (const auto v = sh->get("reuse")) o.shadow_map_reuse = v->boolean();
    }
    if (const auto v = n.get("culling")) o.culling = v->boolean();
    if (const auto v = n.get("tight_bounds")) o.tight_bounds = v->boolean();
    if (const auto v = n.get("occlusion_culling")) o.occlusion_culling = v->boolean();
    if (const auto v = n.get("occlusion_phases")) {
        const double m = v->number(Range::positive);
        if (m != std::floor(m) || m > 8) v->fail("the number of occlusion phases must be an integer in [1, 8]", true);
        o.occlusion_phases = static_cast<int>(m);
    }
    if (const auto v = n.get("occlusion_min_overlap")) {
        const double m = v->number(Range::nonnegative);
        if (m > 1e6) v->fail("the minimum expected overlap for the cull pass must be in [0, 1e6] (0: always)", true);
        o.occlusion_min_overlap = static_cast<float>(m);
    }
    if (const auto v = n.get("occlusion_reuse")) o.occlusion_reuse = v->boolean();
    if (const auto v = n.get("deferred")) o.deferred = v->boolean();
    if (const auto v = n.get("shadows")) o.shadows = v->boolean();
    if (const auto v = n.get("silhouettes")) o.silhouettes = v->boolean();
    if (const auto v = n.get("background")) o.background = v->color();
    if (const auto v = n.get("environment")) load_environment(*v, o, base_dir);
    return o;
}

Camera load_camera(const JsonNode& n, const Aabb& box) {
    n.expect_keys({"type", "eye", "target", "up", "fov_y", "height", "near", "far", "comment"});
    Camera c;
    if (const auto t = n.get("type"))
        c.projection = t->choice({"perspective", "orthographic"}) == "orthographic" ? Projection::orthographic
                                                                                   : Projection::perspective;
    const bool persp = c.projection == Projection::perspective;
    if (persp && n.has("height")) n.at("height").fail("only for orthographic cameras (perspective cameras take \"fov_y\")", true);
    if (!persp && n.has("fov_y")) n.at("fov_y").fail("only for perspective cameras (orthographic cameras take \"height\")", true);
    c.eye = n.at("eye").vec3();
    c.target = n.at("target").vec3();
    if (const auto u = n.get("up")) c.up = u->vec3();
    if (const auto f = n.get("fov_y")) c.fov_y_deg = f->number();

    // near/far/height not given: fit the scene's bounding sphere (see the README).
    const double r = box.empty() ? 0.0 : 1.05 * box.radius();
    const double d = box.empty() ? 0.0 : length(c.eye - box.center());
    c.far = box.empty() ? 100.0 : std::max(d + r, 1e-6);
    c.near = box.empty() ? 0.1 : std::max(d - r, 1e-4 * c.far);
    c.height = box.empty() ? 2.0 : std::max(2.0 * r, 1e-6);
    if (const auto v = n.get("near")) c.near = v->number();
    if (const auto v = n.get("far")) c.far = v->number();
    if (const auto v = n.get("height")) c.height = v->number();

    const Camera::Problem p = c.check();
    if (!p.field.empty()) {
        if (const auto f = n.get(p.field)) f->fail(p.message);
        if (p.field == "up")
            n.fail("the default up [0, 1, 0] " + p.message + "; give \"up\"");
        n.fail(p.field + " (computed from the scene bounds) " + p.message);
    }
    return c;
}

Light load_light(const JsonNode& l) {
    {
        l.expect_keys({"direction", "position", "color", "intensity", "comment"});
        if (l.has("direction") == l.has("position")) l.fail("a light has either \"direction\" or \"position\"");
        Light light;
        if (const auto d = l.get("direction")) {
            light.kind = Light::Kind::directional;
            light.direction = d->direction();
        } else {
            light.kind = Light::Kind::point;
            light.position = l.at("position").vec3();
        }
        if (const auto c = l.get("color")) light.color = c->color();
        if (const auto i = l.get("intensity")) light.intensity = i->number(Range::nonnegative);
        return light;
    }
}

}  // namespace

std::filesystem::path ObjectContext::file_path() const {
    const std::string s = value.string();
    if (s.empty()) value.fail("empty file name");
    std::filesystem::path p(s);
    if (p.is_relative()) p = base_dir / p;
    p = p.lexically_normal();
    std::error_code ec;
    const auto st = std::filesystem::status(p, ec);
    if (ec || !std::filesystem::exists(st)) value.fail("cannot open '" + p.string() + "': no such file");
    if (!std::filesystem::is_regular_file(st)) value.fail("'" + p.string() + "' is not a regular file");
    return p;
}

const std::vector<ObjectKind>& object_kinds() {
    static const std::vector<ObjectKind> kinds = {
        {"sphere", {}, load_sphere},
        {"ellipsoid", {}, load_ellipsoid},
        {"cylinder", {}, load_cylinder},
        {"cone", {}, load_cone},
        {"quadric", {}, load_quadric},
        {"quad", {}, load_quad},
        {"pdb", {"style", "ball_scale", "bond_radius", "vdw_scale", "shrink", "strict"}, load_pdb},
        {"off", {"triangles"}, load_off},
        {"volume", {"iso", "scheme", "method"}, load_volume},
        {"slim", {"error"}, load_slim},
        {"tetmesh", {"field", "step", "iso"}, load_tetmesh},
    };
    return kinds;
}

Scene parse_scene(std::string text, const std::string& file_name, const std::filesystem::path& base_dir) {
    // Every section and every object is checked even after an error (errors are collected and
    // reported in file order); the scene is returned only when there is none. The entries of
    // "objects" are loaded one by one while the text is parsed, each dropped once loaded, so a
    // large scene is never held as JSON; a syntax error or duplicate key anywhere (found by the
    // parse) discards what they gave.
    ErrorList errors;
    errors.file = file_name;
    Scene scene;
    scene.source = file_name;
    std::size_t entry_index = 0;
    const JsonDocument doc(std::move(text), file_name, "objects", [&](const JsonNode& entry) {
        const std::size_t i = entry_index++;
        errors.attempt(entry, [&] { load_object(scene, entry, i, base_dir); });
    });
    const JsonNode root = doc.root();
    if (!root.json().is_object()) root.fail("a scene is a JSON object with \"objects\", \"camera\", ..., got " + root.describe());
    const bool keys_ok = errors.attempt(root, [&] { root.expect_keys({"camera", "lights", "objects", "options", "comment"}); });

    if (const auto o = root.get("options")) errors.attempt(*o, [&] { scene.options = load_options(*o, base_dir); });
    std::optional<JsonNode> objects;
    if (keys_ok || root.has("objects")) errors.attempt(root, [&] { objects = root.at("objects"); });  // a misspelt key says enough
    if (objects) {
        // (an array was streamed above and is empty here; anything else is an error here)
        std::vector<JsonNode> entries;
        errors.attempt(*objects, [&] { entries = objects->array(); });
        for (const JsonNode& entry : entries) errors.attempt(entry, [&] { load_object(scene, entry, entry_index++, base_dir); });
        if (scene.primitive_count() == 0 && errors.items.empty())
            scene.warnings.push_back(objects->warning("the scene has nothing to draw"));
    }

    const Aabb box = scene.bounds();
    scene.camera = fit_camera(box);
    if (root.has("camera")) errors.attempt(root.at("camera"), [&] { scene.camera = load_camera(root.at("camera"), box); });
    if (const auto l = root.get("lights")) {
        if (l->json().is_array()) {
            for (const JsonNode& light : l->array())
                errors.attempt(light, [&] { scene.lights.push_back(load_light(light)); });
        } else {
            errors.attempt(*l, [&] { l->array(); });
        }
    } else {
        Light head;  // a headlight: shines along the view direction
        head.direction = scene.camera.target - scene.camera.eye;
        scene.lights.push_back(head);
    }
    if (!errors.items.empty()) errors.raise();
    return scene;
}

Scene load_scene(const std::filesystem::path& path) {
    const Location file{path.string(), 0, 0, ""};
    std::error_code ec;
    const auto st = std::filesystem::status(path, ec);
    if (!ec && std::filesystem::exists(st) && !std::filesystem::is_regular_file(st))
        throw ParseError(file, "not a regular file");
    if (!ec && std::filesystem::is_regular_file(st)) {
        const std::uintmax_t size = std::filesystem::file_size(path, ec);
        if (!ec && size > max_scene_file_bytes)
            throw ParseError(file, "the file has " + std::to_string(size) + " bytes, more than the limit of " +
                                       std::to_string(max_scene_file_bytes >> 20) +
                                       " MiB for a scene file (put large geometry in PDB, OFF or volume files)");
    }
    std::ifstream in(path, std::ios::binary);
    if (!in) throw ParseError(file, std::string("cannot open: ") + std::strerror(errno));
    try {
        // Read in blocks into one string (no second copy of the text).
        std::string text;
        constexpr std::size_t block = std::size_t(1) << 20;
        if (!ec && std::filesystem::is_regular_file(st)) {
            const std::uintmax_t size = std::filesystem::file_size(path, ec);
            if (!ec) text.reserve(static_cast<std::size_t>(size) + block);
        }
        while (in) {
            const std::size_t n = text.size();
            text.resize(n + block);
            in.read(text.data() + n, static_cast<std::streamsize>(block));
            text.resize(n + static_cast<std::size_t>(in.gcount()));
            if (text.size() > max_scene_file_bytes)
                throw ParseError(file, "the file has more than the limit of " + std::to_string(max_scene_file_bytes >> 20) +
                                           " MiB for a scene file (put large geometry in PDB, OFF or volume files)");
        }
        if (in.bad()) throw ParseError(file, "read error");
        std::filesystem::path base = path.parent_path();
        if (base.empty()) base = ".";
        return parse_scene(std::move(text), path.string(), base);
    } catch (const std::bad_alloc&) {
        throw ParseError(file, "out of memory while loading the scene");
    }
}

}  // namespace quadcast::scene
