// quadcast/codegen/src/stages.cpp -- complete vertex/fragment shaders of the quadric renderer,
// assembled around traced kernels. The plumbing here only moves data (records, varyings,
// uniforms, picks by index); every number it outputs comes from a traced function.
#include "quadcast/codegen/stages.hpp"

#include <sstream>

#include "quadcast/codegen/emit.hpp"
#include "quadcast/codegen/generate.hpp"

namespace quadcast::codegen {

namespace {

const KernelDef& kernel(const std::string& name) {
    const KernelDef* k = find_kernel(name);
    if (!k) throw std::logic_error("quadcast::codegen: stage shader needs unregistered kernel " + name);
    return *k;
}

/// The record of one primitive (std430): the local quadric's 10 coefficients, radius,
/// half-length, centre, slab axis, colour. quadcast::gl::PrimitiveRecord packs it on the host.
const char* record_glsl =
    "struct qc_Primitive {\n"
    "    vec4 q0;      // A00 A01 A02 A11\n"
    "    vec4 q1;      // A12 A22 b0 b1\n"
    "    vec4 q2;      // b2 c radius half_length\n"
    "    vec4 center;  // xyz\n"
    "    vec4 axis;    // xyz (slab variants)\n"
    "    vec4 color;   // rgb\n"
    "};\n"
    "layout(std430, binding = 0) readonly buffer qc_Primitives { qc_Primitive qc_prims[]; };\n\n"
    "mat4 qc_record_quadric(qc_Primitive p)\n{\n"
    "    return mat4(p.q0.x, p.q0.y, p.q0.z, p.q1.z,\n"
    "                p.q0.y, p.q0.w, p.q1.x, p.q1.w,\n"
    "                p.q0.z, p.q1.x, p.q1.y, p.q2.x,\n"
    "                p.q1.z, p.q1.w, p.q2.x, p.q2.y);\n}\n\n";

struct Stage {
    std::string text;
    std::set<std::string> ops;
    std::string sources;
};

void add_kernel(Stage& s, std::ostringstream& fns, const std::string& name) {
    const KernelDef& k = kernel(name);
    const EmittedKernel e = emit_kernel(k);
    fns << e.function << "\n";
    s.ops.insert(e.ops.begin(), e.ops.end());
    s.sources += (s.sources.empty() ? "" : "; ") + k.source;
}

Stage vertex_shader(bool ortho) {
    Stage s;
    std::ostringstream fns;
    const std::string proj = ortho ? "ortho" : "perspective";
    add_kernel(s, fns, "primitive_bound_" + proj);
    add_kernel(s, fns, "primitive_vertex_" + proj);
    const char* q = ortho ? "" : "flat ";  // constant over the quad for one camera model
    const char* vq = ortho ? "flat " : "";
    std::ostringstream m;
    m << record_glsl;
    m << "uniform mat4 qc_view;\nuniform mat4 qc_projection;\nuniform mat3 qc_view_rot_inv;\nuniform vec3 qc_eye;\n"
         "uniform vec3 qc_near_corners[4];  // view space, used when the eye is inside a bounding sphere\n"
         "uniform bool qc_cull;\nuniform uint qc_first;\n\n"
         "flat out uint qc_prim;\n"
      << q << "out vec3 qc_o;\n" << vq << "out vec3 qc_v;\n" << q << "out vec3 qc_g;\n" << vq << "out vec3 qc_a;\n\n";
    m << fns.str();
    m << "// Indexed draw: vertex 4 i + k is corner k of primitive qc_first + i (two triangles share two).\n"
         "void main()\n{\n"
         "    uint prim = qc_first + uint(gl_VertexID) / 4u;\n"
         "    int k = gl_VertexID % 4;\n"
         "    qc_Primitive p = qc_prims[prim];\n"
         "    mat4 q = qc_record_quadric(p);\n"
         "    vec3 c0, c1, c2, c3;\n    bool valid;\n"
         "    qc_primitive_bound_" << proj << "(qc_view, p.center.xyz, p.q2.z, c0, c1, c2, c3, valid);\n"
         "    vec3 corners[4] = vec3[4](c0, c1, c2, c3);\n"
         "    vec3 corner = valid ? corners[k] : qc_near_corners[k];\n"
         "    bool culled;\n"
         "    qc_primitive_vertex_" << proj << "(q, p.center.xyz, p.q2.z, p.axis.xyz, p.q2.w, corner, qc_view_rot_inv, qc_eye,\n"
         "        qc_o, qc_v, qc_g, qc_a, culled);\n"
         "    qc_prim = prim;\n"
         "    gl_Position = (qc_cull && culled) ? vec4(2.0, 2.0, 2.0, 1.0) : qc_projection * vec4(corner, 1.0);\n"
         "}\n";
    s.text = m.str();
    return s;
}

Stage fragment_shader(const std::string& variant, bool ortho) {
    Stage s;
    const bool planes = variant.rfind("planes", 0) == 0;
    std::ostringstream fns;
    add_kernel(s, fns, "fragment_" + variant);
    add_kernel(s, fns, "shade_blinn_phong");
    const char* q = ortho ? "" : "flat ";
    const char* vq = ortho ? "flat " : "";
    std::ostringstream m;
    m << record_glsl;
    if (planes)
        m << "// Clip planes of the `planes` variant, one set per primitive of the draw (index prim - qc_first).\n"
             "struct qc_Planes { vec4 p[4]; };\n"
             "layout(std430, binding = 1) readonly buffer qc_PlaneSets { qc_Planes qc_planes[]; };\n"
             "uniform uint qc_first;\n\n";
    m << "uniform vec3 qc_vz_row;       // third row of the world->view rotation\n"
         "uniform vec4 qc_pz;           // P22, P32, P23, P33 of the projection\n"
         "uniform vec3 qc_light_dir;    // towards the scene\nuniform vec3 qc_light_color;\n"
         "uniform vec4 qc_material;     // ambient, diffuse, specular, shininess\n\n"
         "flat in uint qc_prim;\n"
      << q << "in vec3 qc_o;\n" << vq << "in vec3 qc_v;\n" << q << "in vec3 qc_g;\n" << vq << "in vec3 qc_a;\n"
         "layout(location = 0) out vec4 qc_color;\n\n";
    m << fns.str();
    m << "void main()\n{\n"
         "    qc_Primitive p = qc_prims[qc_prim];\n"
         "    bool hit;\n    float depth;\n    vec3 n;\n"
         "    qc_fragment_" << variant << "(qc_record_quadric(p), p.center.xyz, p.q2.z, p.axis.xyz, p.q2.w,\n"
      << (planes ? "        qc_planes[qc_prim - qc_first].p[0], qc_planes[qc_prim - qc_first].p[1], qc_planes[qc_prim - qc_first].p[2], qc_planes[qc_prim - qc_first].p[3],\n" : "")
      << "        qc_o, qc_v, qc_g, qc_a, qc_vz_row, qc_pz, hit, depth, n);\n"
         "    if (!hit) discard;\n"
         "    gl_FragDepth = depth;\n"
         "    vec3 rgb;\n"
         "    qc_shade_blinn_phong(n, -qc_light_dir, -qc_v, p.color.rgb, qc_light_color, qc_material, rgb);\n"
         "    qc_color = vec4(rgb, 1.0);\n"
         "}\n";
    s.text = m.str();
    return s;
}

}  // namespace

std::vector<StageShader> render_stage_shaders() {
    std::vector<StageShader> out;
    for (bool ortho : {false, true}) {
        const std::string proj = ortho ? "ortho" : "perspective";
        const Stage v = vertex_shader(ortho);
        const std::string vname = "qc_quadric_" + proj + ".vert";
        out.push_back({vname, "glsl/render/" + vname,
                       "#version 450 core\n" + banner("glsl/render/" + vname, v.sources, v.ops, "quadric renderer: vertex stage, " + proj + " camera") + "\n" + v.text});
        for (const char* variant : {"closed", "closed_nocull", "slab", "slab_nocull", "bounded", "bounded_nocull", "planes", "planes_nocull"}) {
            const Stage f = fragment_shader(variant, ortho);
            const std::string fname = std::string("qc_quadric_") + variant + "_" + proj + ".frag";
            out.push_back({fname, "glsl/render/" + fname,
                           "#version 450 core\n" + banner("glsl/render/" + fname, f.sources, f.ops, std::string("quadric renderer: fragment stage, ") + variant + ", " + proj + " camera") + "\n" + f.text});
        }
    }
    return out;
}

}  // namespace quadcast::codegen
