// quadcast/codegen/src/emit.cpp -- GLSL emission of traced kernels
#include "quadcast/codegen/emit.hpp"

#include <bit>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <stdexcept>
#include <unordered_map>

namespace quadcast::codegen {

// Signatures and kernel I/O --------------------------------------------------------------------

int components(Kind k) {
    switch (k) {
    case Kind::f32: case Kind::boolean: return 1;
    case Kind::vec2: return 2;
    case Kind::vec3: return 3;
    case Kind::vec4: return 4;
    case Kind::mat3: return 9;
    case Kind::mat4: return 16;
    }
    return 0;
}

const char* glsl_type(Kind k) {
    switch (k) {
    case Kind::f32: return "float";
    case Kind::boolean: return "bool";
    case Kind::vec2: return "vec2";
    case Kind::vec3: return "vec3";
    case Kind::vec4: return "vec4";
    case Kind::mat3: return "mat3";
    case Kind::mat4: return "mat4";
    }
    return "?";
}

int Signature::input_words() const { int n = 0; for (auto& p : inputs) n += components(p.kind); return n; }
int Signature::output_words() const { int n = 0; for (auto& p : outputs) n += components(p.kind); return n; }

Expr TraceIO::scalar(const std::string& name) {
    sig_.inputs.push_back({name, Kind::f32});
    return Expr::from_id(rec_.input(Type::f32, "qc_" + name));
}

void TraceIO::add_out(const std::string& name, Kind k, std::initializer_list<std::uint32_t> ids) {
    add_out_v(name, k, std::vector<std::uint32_t>(ids));
}

void TraceIO::add_out_v(const std::string& name, Kind k, const std::vector<std::uint32_t>& ids) {
    for (auto& p : sig_.outputs)
        if (p.name == name) throw std::logic_error("quadcast::codegen: output declared twice: " + name);
    const Type want = k == Kind::boolean ? Type::boolean : Type::f32;
    for (auto id : ids)
        if (rec_.node(id).type != want) throw std::logic_error("quadcast::codegen: output " + name + " has the wrong type");
    sig_.outputs.push_back({name, k});
    out_nodes_.insert(out_nodes_.end(), ids.begin(), ids.end());
}

// Literals ---------------------------------------------------------------------------------------

std::string glsl_float(float v) {
    const std::uint32_t bits = std::bit_cast<std::uint32_t>(v);
    char buf[96];
    if (std::isfinite(v) && !(v == 0.0f && std::signbit(v))) {
        // A decimal whose exact value is v: no rounding anywhere between the text and the bits.
        for (int p = 1; p <= 9; ++p) {
            std::snprintf(buf, sizeof buf, "%.*g", p, static_cast<double>(v));
            if (std::strtod(buf, nullptr) == static_cast<double>(v)) {
                std::string s = buf;
                if (s.find_first_of(".e") == std::string::npos) s += ".0";
                if (v < 0.0f) s = "(" + s + ")";
                return s;
            }
        }
    }
    char cmt[32];
    if (std::isnan(v)) std::snprintf(cmt, sizeof cmt, "NaN");
    else std::snprintf(cmt, sizeof cmt, "%.9g", static_cast<double>(v));
    std::snprintf(buf, sizeof buf, "uintBitsToFloat(0x%08Xu) /* %s */", bits, cmt);
    return buf;
}

// Kernel functions -------------------------------------------------------------------------------

namespace {

struct Printer {
    const Recorder& rec;
    std::ostringstream body;
    std::unordered_map<std::uint32_t, std::string> names;
    std::set<std::string> ops;
    int next = 0;

    std::string ref(std::uint32_t id) {
        const Node& n = rec.node(id);
        if (n.op == Op::input) return rec.input_access(id);
        if (n.op == Op::literal) return n.type == Type::boolean ? (n.lit ? "true" : "false") : glsl_float(std::bit_cast<float>(n.lit));
        return names.at(id);
    }

    void visit(std::uint32_t root) {
        // Iterative post-order walk (kernels unroll into deep DAGs).
        struct Frame { std::uint32_t id; int stage; };
        std::vector<Frame> stack{{root, 0}};
        while (!stack.empty()) {
            Frame& f = stack.back();
            const Node& n = rec.node(f.id);
            if (n.op == Op::input || n.op == Op::literal || names.count(f.id)) { stack.pop_back(); continue; }
            const std::uint32_t operands[3] = {n.a, n.b, n.c};
            const int arity = n.op == Op::select ? 3 : (n.op == Op::neg || n.op == Op::sqrt || n.op == Op::abs || n.op == Op::lnot || n.op == Op::isnan || n.op == Op::isinf || n.op == Op::floor) ? 1 : 2;
            if (f.stage < arity) { const std::uint32_t child = operands[f.stage++]; stack.push_back({child, 0}); continue; }
            print(f.id, n);
            stack.pop_back();
        }
    }

    void print(std::uint32_t id, const Node& n) {
        const std::string name = "qc_t" + std::to_string(next++);
        ops.insert(op_symbol(n.op));
        std::string e;
        switch (n.op) {
        case Op::add: e = ref(n.a) + " + " + ref(n.b); break;
        case Op::sub: e = ref(n.a) + " - " + ref(n.b); break;
        case Op::mul: e = ref(n.a) + " * " + ref(n.b); break;
        case Op::div: e = ref(n.a) + " / " + ref(n.b); break;
        case Op::neg: e = "-" + ref(n.a); break;
        case Op::sqrt: e = "sqrt(" + ref(n.a) + ")"; break;
        case Op::abs: e = "abs(" + ref(n.a) + ")"; break;
        case Op::floor: e = "floor(" + ref(n.a) + ")"; break;
        case Op::lt: e = ref(n.a) + " < " + ref(n.b); break;
        case Op::le: e = ref(n.a) + " <= " + ref(n.b); break;
        case Op::gt: e = ref(n.a) + " > " + ref(n.b); break;
        case Op::ge: e = ref(n.a) + " >= " + ref(n.b); break;
        case Op::eq: e = ref(n.a) + " == " + ref(n.b); break;
        case Op::ne: e = ref(n.a) + " != " + ref(n.b); break;
        case Op::land: e = ref(n.a) + " && " + ref(n.b); break;
        case Op::lor: e = ref(n.a) + " || " + ref(n.b); break;
        case Op::lnot: e = "!" + ref(n.a); break;
        case Op::select: e = ref(n.a) + " ? " + ref(n.b) + " : " + ref(n.c); break;
        case Op::isnan: e = "isnan(" + ref(n.a) + ")"; break;
        case Op::isinf: e = "isinf(" + ref(n.a) + ")"; break;
        default: throw std::logic_error("quadcast::codegen: cannot print a leaf");
        }
        if (n.type == Type::boolean) body << "    precise bool " << name << " = " << e << ";\n";
        else body << "    precise float " << name << " = " << e << ";\n";
        names.emplace(id, name);
    }
};

}  // namespace

EmittedKernel emit_kernel(const KernelDef& k) {
    Recorder rec;
    Recording scope(rec);
    TraceIO io(rec);
    k.trace(io);

    Printer p{rec, {}, {}, {}, 0};
    const Signature& sig = io.signature();
    const auto& outs = io.output_nodes();
    std::size_t pos = 0;
    for (const Param& o : sig.outputs) {
        const int n = components(o.kind);
        for (int c = 0; c < n; ++c, ++pos) {
            p.visit(outs[pos]);
            std::string lhs = "qc_" + o.name;
            if (o.kind == Kind::vec2 || o.kind == Kind::vec3 || o.kind == Kind::vec4) lhs += std::string(".") + "xyzw"[c];
            if (o.kind == Kind::mat3 || o.kind == Kind::mat4) {
                const int rows = o.kind == Kind::mat3 ? 3 : 4;
                lhs += "[" + std::to_string(c / rows) + "][" + std::to_string(c % rows) + "]";
            }
            p.body << "    " << lhs << " = " << p.ref(outs[pos]) << ";\n";
        }
    }

    std::ostringstream f;
    f << "void qc_" << k.name << "(";
    bool first = true;
    for (const Param& in : sig.inputs) { f << (first ? "" : ", ") << "in " << glsl_type(in.kind) << " qc_" << in.name; first = false; }
    for (const Param& o : sig.outputs) { f << (first ? "" : ", ") << "out " << glsl_type(o.kind) << " qc_" << o.name; first = false; }
    f << ")\n{\n" << p.body.str() << "}\n";

    EmittedKernel e;
    e.name = "qc_" + k.name;
    e.function = f.str();
    e.ops = p.ops;
    e.signature = sig;
    e.statements = p.next;
    return e;
}

std::string banner(const std::string& file, const std::string& source, const std::set<std::string>& ops, const std::string& summary) {
    std::ostringstream b;
    b << "// " << file << " -- generated by quadcast-codegen; do not edit.\n";
    b << "// " << summary << "\n";
    b << "// Traced from: " << source << "\n";
    b << "// Operations: ";
    bool first = true;
    for (auto& o : ops) { b << (first ? "" : " ") << o; first = false; }
    b << "\n// Numerics: float; every operation is its own `precise` statement (no contraction, no\n"
         "// reassociation); literals are exact; no built-in whose rounding differs from the CPU.\n";
    return b.str();
}

std::string verify_compute_shader(const EmittedKernel& k, const KernelDef& def) { return verify_compute_shader(k, def, k.function); }

std::string verify_compute_shader(const EmittedKernel& k, const KernelDef& def, std::string_view function) {
    const Signature& s = k.signature;
    std::ostringstream c;
    c << "#version 430 core\n";
    c << banner(k.name + ".verify.comp", def.source, k.ops, "verification harness: runs " + k.name + " once per invocation");
    c << "layout(local_size_x = 64) in;\n"
         "layout(std430, binding = 0) readonly buffer qc_Inputs { uint qc_in[]; };\n"
         "layout(std430, binding = 1) writeonly buffer qc_Outputs { uint qc_out[]; };\n"
         "uniform uint qc_count;\n"
         "uniform uint qc_offset;\n\n";
    c << function << "\n";
    c << "float qc_verify_word(uint i) { return uintBitsToFloat(qc_in[i]); }\n\n";
    c << "void main()\n{\n";
    c << "    uint qc_verify_i = qc_offset + gl_GlobalInvocationID.x;\n";
    c << "    if (qc_verify_i >= qc_count) return;\n";
    c << "    uint qc_verify_b = qc_verify_i * " << s.input_words() << "u;\n";
    int w = 0;
    for (const Param& in : s.inputs) {
        const int n = components(in.kind);
        c << "    " << glsl_type(in.kind) << " qc_" << in.name << " = " << glsl_type(in.kind) << "(";
        for (int i = 0; i < n; ++i) c << (i ? ", " : "") << "qc_verify_word(qc_verify_b + " << w++ << "u)";
        c << ");\n";
    }
    for (const Param& o : s.outputs) c << "    " << glsl_type(o.kind) << " qc_" << o.name << ";\n";
    c << "    " << k.name << "(";
    bool first = true;
    for (const Param& in : s.inputs) { c << (first ? "" : ", ") << "qc_" << in.name; first = false; }
    for (const Param& o : s.outputs) { c << (first ? "" : ", ") << "qc_" << o.name; first = false; }
    c << ");\n";
    c << "    uint qc_verify_o = qc_verify_i * " << s.output_words() << "u;\n";
    w = 0;
    for (const Param& o : s.outputs) {
        const int n = components(o.kind);
        for (int i = 0; i < n; ++i) {
            std::string v = "qc_" + o.name;
            if (o.kind == Kind::vec2 || o.kind == Kind::vec3 || o.kind == Kind::vec4) v += std::string(".") + "xyzw"[i];
            if (o.kind == Kind::mat3 || o.kind == Kind::mat4) {
                const int rows = o.kind == Kind::mat3 ? 3 : 4;
                v += "[" + std::to_string(i / rows) + "][" + std::to_string(i % rows) + "]";
            }
            if (o.kind == Kind::boolean) c << "    qc_out[qc_verify_o + " << w++ << "u] = " << v << " ? 1u : 0u;\n";
            else c << "    qc_out[qc_verify_o + " << w++ << "u] = floatBitsToUint(" << v << ");\n";
        }
    }
    c << "}\n";
    return c.str();
}

}  // namespace quadcast::codegen
