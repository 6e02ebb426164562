// src/slim/points.cpp -- oriented point clouds: .xyz/.pwn, .ply (ASCII and binary), .off meshes sampled
#include "quadcast/slim/points.hpp"

#include <algorithm>
#include <bit>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>
#include <optional>
#include <random>

namespace quadcast::slim {

using scene::Location;
using scene::ParseError;
using scene::quote_token;

namespace {

[[noreturn]] void fail(const std::string& file, int line, const std::string& field, const std::string& msg) {
    throw ParseError({file, line, 0, field}, msg);
}

const char* const kFieldNames[6] = {"x", "y", "z", "nx", "ny", "nz"};

/// Appends a point after checking that its six values are finite and its normal is not zero;
/// `where(k)` names value k (0..5) or the whole record (k = -1) for a message.
template <class Where>
void add_point(OrientedPoints& pts, const double (&v)[6], const Where& where) {
    for (int k = 0; k < 6; ++k)
        if (!std::isfinite(v[k])) where(k, "value " + std::to_string(v[k]) + " is not finite");
    // Scale before squaring so that tiny or huge normals do not under/overflow.
    const double m = std::max({std::fabs(v[3]), std::fabs(v[4]), std::fabs(v[5])});
    if (!(m > 0)) where(-1, "the normal (0, 0, 0) has zero length");
    const Vec3d s = vec3(v[3] / m, v[4] / m, v[5] / m);
    const Vec3d n = s / std::sqrt(dot(s, s));
    pts.positions.push_back(vec3(v[0], v[1], v[2]));
    pts.normals.push_back(n);
}

void check_count(const OrientedPoints& pts, const ReadOptions& options, int line) {
    if (pts.size() < options.min_points)
        fail(pts.file, line, "", std::to_string(pts.size()) + (pts.size() == 1 ? " point" : " points") +
                                     "; a quadric fit needs at least " + std::to_string(options.min_points));
}

// PLY ------------------------------------------------------------------------------------------

enum class PlyFormat { ascii, binary_le, binary_be };

enum class PlyType { i8, u8, i16, u16, i32, u32, f32, f64 };

std::optional<PlyType> ply_type(const std::string& s) {
    if (s == "char" || s == "int8") return PlyType::i8;
    if (s == "uchar" || s == "uint8") return PlyType::u8;
    if (s == "short" || s == "int16") return PlyType::i16;
    if (s == "ushort" || s == "uint16") return PlyType::u16;
    if (s == "int" || s == "int32") return PlyType::i32;
    if (s == "uint" || s == "uint32") return PlyType::u32;
    if (s == "float" || s == "float32") return PlyType::f32;
    if (s == "double" || s == "float64") return PlyType::f64;
    return std::nullopt;
}

std::size_t type_size(PlyType t) {
    switch (t) {
    case PlyType::i8: case PlyType::u8: return 1;
    case PlyType::i16: case PlyType::u16: return 2;
    case PlyType::i32: case PlyType::u32: case PlyType::f32: return 4;
    case PlyType::f64: return 8;
    }
    return 1;
}

bool is_integer(PlyType t) { return t != PlyType::f32 && t != PlyType::f64; }

struct PlyProperty {
    std::string name;
    PlyType type;               ///< the value type (of the items, for a list)
    bool list = false;
    PlyType count_type = PlyType::u8;
};

struct PlyElement {
    std::string name;
    std::uint64_t count = 0;
    int line = 0;               ///< header line of the element
    std::vector<PlyProperty> properties;
};

/// Reads one binary value of type `t` at `p` (the bytes are there) in the file's byte order.
double read_binary(const unsigned char* p, PlyType t, bool swap) {
    unsigned char b[8];
    const std::size_t n = type_size(t);
    for (std::size_t i = 0; i < n; ++i) b[i] = swap ? p[n - 1 - i] : p[i];
    switch (t) {
    case PlyType::i8: { std::int8_t v; std::memcpy(&v, b, 1); return v; }
    case PlyType::u8: { std::uint8_t v; std::memcpy(&v, b, 1); return v; }
    case PlyType::i16: { std::int16_t v; std::memcpy(&v, b, 2); return v; }
    case PlyType::u16: { std::uint16_t v; std::memcpy(&v, b, 2); return v; }
    case PlyType::i32: { std::int32_t v; std::memcpy(&v, b, 4); return v; }
    case PlyType::u32: { std::uint32_t v; std::memcpy(&v, b, 4); return v; }
    case PlyType::f32: { float v; std::memcpy(&v, b, 4); return static_cast<double>(v); }
    case PlyType::f64: { double v; std::memcpy(&v, b, 8); return v; }
    }
    return 0;
}

class PlyParser {
public:
    PlyParser(std::istream& in, const std::string& file, const ReadOptions& options) : in_(in), options_(options) { pts_.file = file; }

    OrientedPoints run() {
        header();
        // Find the vertex element and its six properties.
        const auto v = std::find_if(elements_.begin(), elements_.end(), [](const PlyElement& e) { return e.name == "vertex"; });
        if (v == elements_.end()) fail(pts_.file, line_, "header", "no 'vertex' element");
        for (int k = 0; k < 6; ++k) {
            int found = -1;
            for (std::size_t i = 0; i < v->properties.size(); ++i)
                if (v->properties[i].name == kFieldNames[k]) found = int(i);
            if (found < 0) {
                if (k >= 3)
                    fail(pts_.file, v->line, "element vertex",
                         "missing normals: no 'nx', 'ny', 'nz' properties (the fit needs oriented points)");
                fail(pts_.file, v->line, "element vertex", std::string("no '") + kFieldNames[k] + "' property");
            }
            if (v->properties[std::size_t(found)].list)
                fail(pts_.file, v->line, std::string("property ") + kFieldNames[k], "is a list; expected a number");
            slot_[k] = found;
        }
        // Read the elements up to and including the vertex element; what follows is ignored.
        for (auto e = elements_.begin(); e != elements_.end(); ++e) {
            const bool is_vertex = e == v;
            if (format_ == PlyFormat::ascii) read_ascii(*e, is_vertex);
            else read_binary_element(*e, is_vertex);
            if (is_vertex) break;
        }
        check_count(pts_, options_, format_ == PlyFormat::ascii ? line_ : 0);
        return std::move(pts_);
    }

private:
    bool getline(std::string& s) {
        if (!std::getline(in_, s)) return false;
        ++line_;
        bytes_ += s.size() + 1;
        if (!s.empty() && s.back() == '\r') s.pop_back();
        return true;
    }

    void header() {
        std::string s;
        if (!getline(s) || s != "ply")
            fail(pts_.file, 1, "header", "not a PLY file (the first line must be 'ply', found " + quote_token(s) + ")");
        bool have_format = false;
        while (true) {
            if (!getline(s)) fail(pts_.file, line_, "header", "the file ends before 'end_header' (truncated header?)");
            const std::vector<std::string> t = scene::line_tokens(s, false);
            if (t.empty()) continue;
            const std::string& key = t[0];
            if (key == "end_header") break;
            if (key == "comment" || key == "obj_info") continue;
            if (key == "format") {
                if (have_format) fail(pts_.file, line_, "format", "a second format line");
                if (t.size() != 3) fail(pts_.file, line_, "format", "expected 'format <ascii|binary_little_endian|binary_big_endian> 1.0'");
                if (t[1] == "ascii") format_ = PlyFormat::ascii;
                else if (t[1] == "binary_little_endian") format_ = PlyFormat::binary_le;
                else if (t[1] == "binary_big_endian") format_ = PlyFormat::binary_be;
                else fail(pts_.file, line_, "format", "unknown format " + quote_token(t[1]));
                if (t[2] != "1.0") fail(pts_.file, line_, "format", "unsupported version " + quote_token(t[2]) + " (expected 1.0)");
                have_format = true;
                continue;
            }
            if (!have_format) fail(pts_.file, line_, "header", "expected the 'format' line before " + quote_token(key));
            if (key == "element") {
                if (t.size() != 3) fail(pts_.file, line_, "element", "expected 'element <name> <count>'");
                std::uint64_t n = 0;
                const auto [p, ec] = std::from_chars(t[2].data(), t[2].data() + t[2].size(), n);
                if (ec != std::errc() || p != t[2].data() + t[2].size())
                    fail(pts_.file, line_, "element " + t[1], "count " + quote_token(t[2]) + " is not a non-negative integer");
                if (n > 2'000'000'000ull) fail(pts_.file, line_, "element " + t[1], "count " + t[2] + " is implausibly large");
                elements_.push_back({t[1], n, line_, {}});
                continue;
            }
            if (key == "property") {
                if (elements_.empty()) fail(pts_.file, line_, "property", "a property before any 'element' line");
                PlyProperty prop;
                if (t.size() >= 2 && t[1] == "list") {
                    if (t.size() != 5) fail(pts_.file, line_, "property", "expected 'property list <count type> <item type> <name>'");
                    const auto ct = ply_type(t[2]);
                    const auto it = ply_type(t[3]);
                    if (!ct || !is_integer(*ct)) fail(pts_.file, line_, "property " + t[4], "list count type " + quote_token(t[2]) + " is not an integer type");
                    if (!it) fail(pts_.file, line_, "property " + t[4], "unknown type " + quote_token(t[3]));
                    prop = {t[4], *it, true, *ct};
                } else {
                    if (t.size() != 3) fail(pts_.file, line_, "property", "expected 'property <type> <name>'");
                    const auto ty = ply_type(t[1]);
                    if (!ty) fail(pts_.file, line_, "property " + t[2], "unknown type " + quote_token(t[1]));
                    prop = {t[2], *ty, false, PlyType::u8};
                }
                elements_.back().properties.push_back(prop);
                continue;
            }
            fail(pts_.file, line_, "header", "unknown header keyword " + quote_token(key));
        }
        if (!have_format) fail(pts_.file, line_, "header", "no 'format' line");
    }

    void read_ascii(const PlyElement& e, bool is_vertex) {
        if (is_vertex && e.count <= 100'000'000) pts_.positions.reserve(std::size_t(std::min<std::uint64_t>(e.count, 1'000'000)));
        std::string s;
        for (std::uint64_t i = 0; i < e.count; ++i) {
            const std::string what = e.name + " " + std::to_string(i);
            std::vector<std::string> t;
            while (t.empty()) {
                if (!getline(s))
                    fail(pts_.file, line_, what, "the file ends after " + std::to_string(i) + " of " + std::to_string(e.count) +
                                                     " " + e.name + " records (truncated?)");
                t = scene::line_tokens(s, false);
            }
            // Walk the properties, lists included.
            std::size_t k = 0;
            double v[6] = {};
            for (std::size_t pi = 0; pi < e.properties.size(); ++pi) {
                const PlyProperty& p = e.properties[pi];
                std::size_t items = 1;
                if (p.list) {
                    if (k >= t.size()) fail(pts_.file, line_, what + " " + p.name, "missing (the record has " + std::to_string(t.size()) + " values)");
                    const auto c = scene::parse_decimal(t[k]);
                    if (!c || !(*c >= 0) || *c != std::floor(*c) || *c > 1e6)
                        fail(pts_.file, line_, what + " " + p.name, "list count " + quote_token(t[k]) + " is not a non-negative integer");
                    items = std::size_t(*c);
                    ++k;
                }
                for (std::size_t j = 0; j < items; ++j, ++k) {
                    if (k >= t.size()) fail(pts_.file, line_, what + " " + p.name, "missing (the record has " + std::to_string(t.size()) + " values)");
                    if (!is_vertex) continue;
                    const auto x = scene::parse_decimal(t[k]);
                    if (!x) fail(pts_.file, line_, what + " " + p.name, quote_token(t[k]) + " is not a number");
                    for (int q = 0; q < 6; ++q)
                        if (slot_[q] == int(pi)) v[q] = *x;
                }
            }
            if (k != t.size())
                fail(pts_.file, line_, what, std::to_string(t.size()) + " values; the header declares " + std::to_string(k));
            if (is_vertex) {
                const int line = line_;
                add_point(pts_, v, [&](int q, const std::string& msg) {
                    fail(pts_.file, line, q < 0 ? what + " normal" : what + " " + kFieldNames[q], msg);
                });
            }
        }
    }

    /// Makes sure `n` more bytes of binary data are buffered; false at the end of the file.
    bool have(std::size_t n) {
        while (data_.size() - pos_ < n) {
            if (eof_) return false;
            // Drop what was consumed and read the next chunk.
            data_.erase(0, pos_);
            base_ += pos_;
            pos_ = 0;
            char chunk[1 << 16];
            in_.read(chunk, sizeof chunk);
            const std::streamsize got = in_.gcount();
            if (got <= 0) { eof_ = true; if (in_.bad()) fail(pts_.file, 0, "", "read error"); continue; }
            data_.append(chunk, std::size_t(got));
            if (got < std::streamsize(sizeof chunk)) eof_ = true;
        }
        return true;
    }

    void read_binary_element(const PlyElement& e, bool is_vertex) {
        const bool swap = (format_ == PlyFormat::binary_le) != (std::endian::native == std::endian::little);
        if (is_vertex) pts_.positions.reserve(std::size_t(std::min<std::uint64_t>(e.count, 1'000'000)));
        for (std::uint64_t i = 0; i < e.count; ++i) {
            double v[6] = {};
            const std::uint64_t record_byte = bytes_ + base_ + pos_;
            for (std::size_t pi = 0; pi < e.properties.size(); ++pi) {
                const PlyProperty& p = e.properties[pi];
                const auto field = [&](const std::string& name) {
                    return e.name + " " + std::to_string(i) + " " + name + " (byte " + std::to_string(bytes_ + base_ + pos_) + ")";
                };
                const auto ends = [&](const std::string& name) {
                    fail(pts_.file, 0, field(name), "the file ends inside " + e.name + " record " + std::to_string(i) + " of " +
                                                       std::to_string(e.count) + " (truncated binary data)");
                };
                std::size_t items = 1;
                if (p.list) {
                    if (!have(type_size(p.count_type))) ends(p.name);
                    const double c = read_binary(reinterpret_cast<const unsigned char*>(data_.data() + pos_), p.count_type, swap);
                    if (!(c >= 0)) fail(pts_.file, 0, field(p.name), "negative list count " + std::to_string(c));
                    items = std::size_t(c);
                    pos_ += type_size(p.count_type);
                }
                const std::size_t n = type_size(p.type);
                for (std::size_t j = 0; j < items; ++j) {
                    if (!have(n)) ends(p.name);
                    if (is_vertex) {
                        const double x = read_binary(reinterpret_cast<const unsigned char*>(data_.data() + pos_), p.type, swap);
                        for (int q = 0; q < 6; ++q)
                            if (slot_[q] == int(pi)) {
                                if (!std::isfinite(x)) fail(pts_.file, 0, field(p.name), "value " + std::to_string(x) + " is not finite");
                                v[q] = x;
                            }
                    }
                    pos_ += n;
                }
            }
            if (is_vertex)
                add_point(pts_, v, [&](int q, const std::string& msg) {
                    fail(pts_.file, 0, e.name + " " + std::to_string(i) + (q < 0 ? " normal" : std::string(" ") + kFieldNames[q]) +
                                           " (record at byte " + std::to_string(record_byte) + ")", msg);
                });
        }
    }

    std::istream& in_;
    ReadOptions options_;
    OrientedPoints pts_;
    PlyFormat format_ = PlyFormat::ascii;
    std::vector<PlyElement> elements_;
    int slot_[6] = {-1, -1, -1, -1, -1, -1};
    int line_ = 0;
    std::uint64_t bytes_ = 0;  ///< bytes of the header (the binary data's offset in the file)
    std::string data_;         ///< buffered binary data
    std::size_t pos_ = 0;      ///< read position in data_
    std::uint64_t base_ = 0;   ///< offset of data_[0] in the binary data
    bool eof_ = false;
};

double unit_random(std::mt19937_64& rng) { return double(rng() >> 11) * 0x1.0p-53; }

}  // namespace

OrientedPoints parse_xyz(std::istream& in, const std::string& file_name, const ReadOptions& options) {
    OrientedPoints pts;
    pts.file = file_name;
    std::string raw;
    int line = 0;
    while (std::getline(in, raw)) {
        ++line;
        const std::vector<std::string> t = scene::line_tokens(raw, true);
        if (t.empty()) continue;
        if (t.size() == 3)
            fail(file_name, line, "point " + std::to_string(pts.size()),
                 "missing normals: expected 'x y z nx ny nz', found 3 values (the fit needs oriented points)");
        if (t.size() != 6)
            fail(file_name, line, "point " + std::to_string(pts.size()),
                 "expected 6 values 'x y z nx ny nz', found " + std::to_string(t.size()));
        double v[6];
        for (int k = 0; k < 6; ++k) {
            const auto x = scene::parse_decimal(t[std::size_t(k)]);
            if (!x) fail(file_name, line, kFieldNames[k], quote_token(t[std::size_t(k)]) + " is not a number");
            if (!std::isfinite(*x)) fail(file_name, line, kFieldNames[k], quote_token(t[std::size_t(k)]) + " is not finite");
            v[k] = *x;
        }
        add_point(pts, v, [&](int k, const std::string& msg) { fail(file_name, line, k < 0 ? "normal" : kFieldNames[k], msg); });
    }
    if (in.bad()) fail(file_name, line, "", "read error");
    check_count(pts, options, line);
    return pts;
}

OrientedPoints parse_ply(std::istream& in, const std::string& file_name, const ReadOptions& options) {
    return PlyParser(in, file_name, options).run();
}

OrientedPoints sample_mesh(const scene::OffMesh& mesh, const ReadOptions& options) {
    OrientedPoints pts;
    pts.file = mesh.file;
    pts.warnings = mesh.warnings;
    // Fan every face into triangles; keep those with area, with their unit normals.
    struct Tri { Vec3d a, b, c, n; };
    std::vector<Tri> tris;
    std::vector<double> cumulative;
    double total = 0;
    for (const std::vector<int>& f : mesh.faces)
        for (std::size_t k = 1; k + 1 < f.size(); ++k) {
            const Vec3d a = mesh.vertices[std::size_t(f[0])], b = mesh.vertices[std::size_t(f[k])], c = mesh.vertices[std::size_t(f[k + 1])];
            const Vec3d x = cross(b - a, c - a);
            const double len = length(x);
            if (!(len > 0) || !std::isfinite(len)) continue;
            tris.push_back({a, b, c, x / len});
            total += 0.5 * len;
            cumulative.push_back(total);
        }
    if (tris.empty()) fail(mesh.file, 0, "", "the mesh has no face with a nonzero area to sample");
    const std::size_t n = options.mesh_samples ? options.mesh_samples : std::max<std::size_t>(mesh.vertices.size(), 100000);
    // Draw a triangle by area, then a uniform point in it (Osada et al. 2002, eq. 1).
    std::mt19937_64 rng(options.seed);
    pts.positions.reserve(n);
    pts.normals.reserve(n);
    for (std::size_t i = 0; i < n; ++i) {
        const double u = unit_random(rng) * total;
        const std::size_t t = std::min<std::size_t>(std::size_t(std::upper_bound(cumulative.begin(), cumulative.end(), u) - cumulative.begin()), tris.size() - 1);
        const double s = std::sqrt(unit_random(rng));
        const double w = unit_random(rng);
        const Tri& tr = tris[t];
        pts.positions.push_back(tr.a * (1 - s) + tr.b * (s * (1 - w)) + tr.c * (s * w));
        pts.normals.push_back(tr.n);
    }
    check_count(pts, options, 0);
    return pts;
}

OrientedPoints read_points(const std::filesystem::path& path, const ReadOptions& options) {
    std::string ext = path.extension().string();
    for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
    if (ext != ".xyz" && ext != ".pwn" && ext != ".ply" && ext != ".off")
        fail(path.string(), 0, "", "unknown point cloud format " + quote_token(ext) + " (expected .xyz, .pwn, .ply or .off)");
    if (ext == ".off") return sample_mesh(scene::read_off(path), options);
    std::ifstream in(path, std::ios::binary);
    if (!in) fail(path.string(), 0, "", std::string("cannot open: ") + std::strerror(errno));
    return ext == ".ply" ? parse_ply(in, path.string(), options) : parse_xyz(in, path.string(), options);
}

}  // namespace quadcast::slim
