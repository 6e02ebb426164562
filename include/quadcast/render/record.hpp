// quadcast/render/record.hpp -- the GPU record of one primitive: one layout for the C++ packing and the GLSL declaration
#pragma once

// Host-only, no GL. `record_layout` says which value each float of the std430 record holds;
// `pack_record` (the GL renderer's upload) and `record_glsl` (the struct and its accessors in
// every generated stage that reads records) are both written from it, so the two cannot drift.

#include <array>
#include <cstdint>
#include <string>

#include "quadcast/render/types.hpp"

namespace quadcast::render {

/// What one float of a primitive's record holds: the local quadric's upper triangle (A, b, c
/// of Q = [A b; b^T c]), the bound, the slab, the material and the colour.
enum class RecordValue : std::uint8_t {
    a00, a01, a02, a11, a12, a22, b0, b1, b2, c,
    radius, half_length,
    center_x, center_y, center_z,
    axis_x, axis_y, axis_z,
    red, green, blue,
    specular, shininess,
    cap_hi, cap_lo,
    zero,
};

/// vec4 slots per record (std430: 16 bytes each).
inline constexpr int record_slots = 7;

/// The record, slot by slot.
inline constexpr RecordValue record_layout[record_slots * 4] = {
    RecordValue::a00,      RecordValue::a01,      RecordValue::a02,      RecordValue::a11,
    RecordValue::a12,      RecordValue::a22,      RecordValue::b0,       RecordValue::b1,
    RecordValue::b2,       RecordValue::c,        RecordValue::radius,   RecordValue::half_length,
    RecordValue::center_x, RecordValue::center_y, RecordValue::center_z, RecordValue::specular,
    RecordValue::axis_x,   RecordValue::axis_y,   RecordValue::axis_z,   RecordValue::shininess,
    RecordValue::red,      RecordValue::green,    RecordValue::blue,     RecordValue::zero,
    RecordValue::cap_hi,   RecordValue::cap_lo,   RecordValue::zero,     RecordValue::zero,
};

/// The value `v` of primitive `p`.
inline float record_value(const Primitive& p, RecordValue v) {
    const Mat4<float>& q = p.shape.q.q;
    switch (v) {
    case RecordValue::a00: return q[0][0];
    case RecordValue::a01: return q[1][0];
    case RecordValue::a02: return q[2][0];
    case RecordValue::a11: return q[1][1];
    case RecordValue::a12: return q[2][1];
    case RecordValue::a22: return q[2][2];
    case RecordValue::b0: return q[3][0];
    case RecordValue::b1: return q[3][1];
    case RecordValue::b2: return q[3][2];
    case RecordValue::c: return q[3][3];
    case RecordValue::radius: return p.shape.radius;
    case RecordValue::half_length: return p.shape.half_length;
    case RecordValue::center_x: return p.shape.center[0];
    case RecordValue::center_y: return p.shape.center[1];
    case RecordValue::center_z: return p.shape.center[2];
    case RecordValue::axis_x: return p.shape.axis[0];
    case RecordValue::axis_y: return p.shape.axis[1];
    case RecordValue::axis_z: return p.shape.axis[2];
    case RecordValue::red: return p.color[0];
    case RecordValue::green: return p.color[1];
    case RecordValue::blue: return p.color[2];
    case RecordValue::specular: return p.material.specular;
    case RecordValue::shininess: return p.material.shininess;
    case RecordValue::cap_hi: return p.shape.caps[0];
    case RecordValue::cap_lo: return p.shape.caps[1];
    case RecordValue::zero: return 0.0f;
    }
    return 0.0f;
}

/// The record of a primitive as the GPU reads it.
inline std::array<float, record_slots * 4> pack_record(const Primitive& p) {
    std::array<float, record_slots * 4> r{};
    for (int i = 0; i < record_slots * 4; ++i) r[static_cast<std::size_t>(i)] = record_value(p, record_layout[i]);
    return r;
}

namespace record_detail {

/// GLSL expression of value v of the record variable `var` (e.g. "p.s2.z").
inline std::string field(const char* var, RecordValue v) {
    for (int i = 0; i < record_slots * 4; ++i)
        if (record_layout[i] == v) return std::string(var) + ".s" + std::to_string(i / 4) + "." + "xyzw"[i % 4];
    return "0.0";
}

inline const char* value_name(RecordValue v) {
    static const char* names[] = {"A00", "A01", "A02", "A11", "A12", "A22", "b0", "b1", "b2", "c", "radius", "half_length",
                                  "center.x", "center.y", "center.z", "axis.x", "axis.y", "axis.z", "red", "green", "blue",
                                  "specular", "shininess", "cap+", "cap-", "0"};
    return names[static_cast<int>(v)];
}

}  // namespace record_detail

/// The GLSL declaration of the record array (std430, binding 0) and its accessors: the local
/// quadric as a symmetric mat4 (`qc_record_quadric`), centre, radius, slab axis and half-length,
/// caps (vec2: + end, - end), colour, and (specular, shininess) (`qc_record_material`).
inline std::string record_glsl() {
    using record_detail::field;
    using V = RecordValue;
    std::string s = "struct qc_Primitive {  // quadcast::render::record_layout\n";
    for (int k = 0; k < record_slots; ++k) {
        s += "    vec4 s" + std::to_string(k) + ";  //";
        for (int i = 0; i < 4; ++i) s += std::string(" ") + record_detail::value_name(record_layout[4 * k + i]);
        s += "\n";
    }
    s += "};\nlayout(std430, binding = 0) readonly buffer qc_Primitives { qc_Primitive qc_prims[]; };\n\n";
    auto f = [](V v) { return field("p", v); };
    s += "mat4 qc_record_quadric(qc_Primitive p)\n{\n    return mat4(" + f(V::a00) + ", " + f(V::a01) + ", " + f(V::a02) + ", " + f(V::b0) + ",\n" +
         "                " + f(V::a01) + ", " + f(V::a11) + ", " + f(V::a12) + ", " + f(V::b1) + ",\n" +
         "                " + f(V::a02) + ", " + f(V::a12) + ", " + f(V::a22) + ", " + f(V::b2) + ",\n" +
         "                " + f(V::b0) + ", " + f(V::b1) + ", " + f(V::b2) + ", " + f(V::c) + ");\n}\n";
    s += "vec3 qc_record_center(qc_Primitive p) { return vec3(" + f(V::center_x) + ", " + f(V::center_y) + ", " + f(V::center_z) + "); }\n";
    s += "float qc_record_radius(qc_Primitive p) { return " + f(V::radius) + "; }\n";
    s += "vec3 qc_record_axis(qc_Primitive p) { return vec3(" + f(V::axis_x) + ", " + f(V::axis_y) + ", " + f(V::axis_z) + "); }\n";
    s += "float qc_record_half_length(qc_Primitive p) { return " + f(V::half_length) + "; }\n";
    s += "vec2 qc_record_caps(qc_Primitive p) { return vec2(" + f(V::cap_hi) + ", " + f(V::cap_lo) + "); }\n";
    s += "vec3 qc_record_color(qc_Primitive p) { return vec3(" + f(V::red) + ", " + f(V::green) + ", " + f(V::blue) + "); }\n";
    s += "vec2 qc_record_material(qc_Primitive p) { return vec2(" + f(V::specular) + ", " + f(V::shininess) + "); }\n\n";
    return s;
}

}  // namespace quadcast::render
