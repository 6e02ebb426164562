// src/scene/msh.cpp -- Gmsh MSH 4.1 reader and the isosurface of a nodal field as quadrics
#include "quadcast/scene/msh.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <limits>
#include <unordered_map>

#include "quadcast/bb/quadric_form.hpp"

namespace quadcast::scene {

namespace {

std::string shortest(double x) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%g", x);
    return buf;
}

/// Nodes per element type, for the types of Gmsh's documentation (0: unknown) and the dimension.
struct ElementType {
    int nodes, dim;
    const char* name;
};
ElementType element_type(int t) {
    switch (t) {
        case 1: return {2, 1, "2-node line"};
        case 2: return {3, 2, "3-node triangle"};
        case 3: return {4, 2, "4-node quadrangle"};
        case 4: return {4, 3, "4-node tetrahedron"};
        case 5: return {8, 3, "8-node hexahedron"};
        case 6: return {6, 3, "6-node prism"};
        case 7: return {5, 3, "5-node pyramid"};
        case 8: return {3, 1, "3-node line"};
        case 9: return {6, 2, "6-node triangle"};
        case 10: return {9, 2, "9-node quadrangle"};
        case 11: return {10, 3, "10-node tetrahedron"};
        case 12: return {27, 3, "27-node hexahedron"};
        case 13: return {18, 3, "18-node prism"};
        case 14: return {14, 3, "14-node pyramid"};
        case 15: return {1, 0, "1-node point"};
        case 16: return {8, 2, "8-node quadrangle"};
        case 17: return {20, 3, "20-node hexahedron"};
        case 18: return {15, 3, "15-node prism"};
        case 19: return {13, 3, "13-node pyramid"};
        case 20: return {9, 2, "9-node triangle"};
        case 21: return {10, 2, "10-node triangle"};
        case 22: return {12, 2, "12-node triangle"};
        case 23: return {15, 2, "15-node triangle"};
        case 24: return {15, 2, "15-node triangle"};
        case 25: return {21, 2, "21-node triangle"};
        case 26: return {4, 1, "4-node line"};
        case 27: return {5, 1, "5-node line"};
        case 28: return {6, 1, "6-node line"};
        case 29: return {20, 3, "20-node tetrahedron"};
        case 30: return {35, 3, "35-node tetrahedron"};
        case 31: return {56, 3, "56-node tetrahedron"};
        case 92: return {64, 3, "64-node hexahedron"};
        case 93: return {125, 3, "125-node hexahedron"};
        default: return {0, -1, nullptr};
    }
}

/// A cursor over the file's bytes that knows its line, for text and for binary sections.
class Cursor {
public:
    Cursor(std::string_view bytes, const std::string& file) : s_(bytes), file_(file) {}

    [[noreturn]] void fail(const std::string& field, const std::string& message, int line = 0) const {
        throw ParseError({file_, line ? line : line_, 0, field}, message);
    }
    int line() const { return line_; }
    std::size_t offset() const { return pos_; }
    bool at_end() const { return pos_ >= s_.size(); }

    /// The rest of the current line (without '\r\n'), moving to the next one.
    std::string_view text_line() {
        const std::size_t end = s_.find('\n', pos_);
        std::string_view l = s_.substr(pos_, end == std::string_view::npos ? std::string_view::npos : end - pos_);
        pos_ = end == std::string_view::npos ? s_.size() : end + 1;
        if (!l.empty() && l.back() == '\r') l.remove_suffix(1);
        ++line_;
        return l;
    }
    /// The next line that is not blank, trimmed; empty at the end of the file.
    std::string_view next_nonblank_line() {
        while (!at_end()) {
            std::string_view l = text_line();
            while (!l.empty() && (l.front() == ' ' || l.front() == '\t')) l.remove_prefix(1);
            while (!l.empty() && (l.back() == ' ' || l.back() == '\t')) l.remove_suffix(1);
            if (!l.empty()) return l;
        }
        return {};
    }
    /// The next whitespace-separated token; an error naming `field` at the end of the file.
    std::string_view token(const std::string& field) {
        while (pos_ < s_.size() && std::isspace(static_cast<unsigned char>(s_[pos_]))) {
            if (s_[pos_] == '\n') ++line_;
            ++pos_;
        }
        if (pos_ >= s_.size()) fail(field, "unexpected end of the file (truncated?)");
        const std::size_t b = pos_;
        while (pos_ < s_.size() && !std::isspace(static_cast<unsigned char>(s_[pos_]))) ++pos_;
        return s_.substr(b, pos_ - b);
    }
    double real(const std::string& field) {
        const std::string_view t = token(field);
        const std::optional<double> v = parse_decimal(t);
        if (!v) fail(field, "expected a number, got " + quote_token(t));
        if (!std::isfinite(*v)) fail(field, "not a finite number: " + quote_token(t));
        return *v;
    }
    /// An integer token in [lo, hi].
    long long integer(const std::string& field, long long lo, long long hi) {
        const std::string_view t = token(field);
        long long v = 0;
        std::size_t i = t[0] == '-' || t[0] == '+' ? 1 : 0;
        bool ok = i < t.size() && t.size() - i <= 18;
        for (; ok && i < t.size(); ++i) {
            if (t[i] < '0' || t[i] > '9') ok = false;
            else v = v * 10 + (t[i] - '0');
        }
        if (!ok) fail(field, "expected an integer, got " + quote_token(t));
        if (t[0] == '-') v = -v;
        if (v < lo || v > hi) fail(field, quote_token(t) + " is outside [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
        return v;
    }
    /// The end of the current text line after the last token (only blanks may follow).
    void end_of_line(const std::string& field) {
        while (pos_ < s_.size() && (s_[pos_] == ' ' || s_[pos_] == '\t' || s_[pos_] == '\r')) ++pos_;
        if (pos_ < s_.size() && s_[pos_] != '\n') fail(field, "unexpected text " + quote_token(text_line()) + " at the end of the line");
        if (pos_ < s_.size()) {
            ++pos_;
            ++line_;
        }
    }

    /// `n` raw bytes (binary sections); counts the newlines in them so that later lines stay right.
    const char* raw(std::size_t n, const std::string& field) {
        if (n > s_.size() - pos_)
            fail(field + " (byte offset " + std::to_string(pos_) + ")", "the file ends inside binary data (truncated?)");
        const char* p = s_.data() + pos_;
        line_ += static_cast<int>(std::count(p, p + n, '\n'));
        pos_ += n;
        return p;
    }
    template <class X>
    X binary(const std::string& field) {
        X x;
        std::memcpy(&x, raw(sizeof x, field), sizeof x);
        return x;
    }
    std::size_t bytes_left() const { return s_.size() - pos_; }

    /// Skips to the line after "$End<name>".
    void skip_section(std::string_view name, int start_line) {
        const std::string end = "\n$End" + std::string(name);
        std::size_t at = s_.find(end, pos_ == 0 ? 0 : pos_ - 1);
        while (at != std::string_view::npos) {
            const std::size_t after = at + end.size();
            if (after == s_.size() || s_[after] == '\n' || s_[after] == '\r' || s_[after] == ' ') break;
            at = s_.find(end, after);
        }
        if (at == std::string_view::npos) fail("$" + std::string(name), "the section has no $End" + std::string(name), start_line);
        raw(at + 1 - pos_, "$" + std::string(name));
        text_line();
    }

private:
    std::string_view s_;
    const std::string& file_;
    std::size_t pos_ = 0;
    int line_ = 1;
};

class MshParser {
public:
    MshParser(std::string_view bytes, const std::string& file) : c_(bytes, file) { mesh_.file = file; }

    MshMesh run() {
        bool format_seen = false, nodes_seen = false, elements_seen = false;
        while (true) {
            const int line = c_.line();
            const std::string_view header = c_.next_nonblank_line();
            if (header.empty()) break;
            if (header[0] != '$') c_.fail("section", "expected a section such as $Nodes, got " + quote_token(header), line);
            const std::string name(header.substr(1));
            if (!format_seen && name != "MeshFormat") c_.fail("$MeshFormat", "the file does not start with $MeshFormat (not a Gmsh .msh file?)", line);
            if (name == "MeshFormat") {
                if (format_seen) c_.fail("$MeshFormat", "a second $MeshFormat", line);
                mesh_format(line);
                format_seen = true;
            } else if (name == "Nodes") {
                if (nodes_seen) c_.fail("$Nodes", "a second $Nodes section", line);
                nodes(line);
                nodes_seen = true;
            } else if (name == "Elements") {
                if (elements_seen) c_.fail("$Elements", "a second $Elements section", line);
                if (!nodes_seen) c_.fail("$Elements", "$Elements before $Nodes", line);
                elements(line);
                elements_seen = true;
            } else if (name == "NodeData") {
                if (!nodes_seen) c_.fail("$NodeData", "$NodeData before $Nodes", line);
                node_data(line);
            } else if (name == "PartitionedEntities") {
                c_.fail("$PartitionedEntities", "partitioned meshes are not read (join the partitions: gmsh in.msh -0 -part_merge)", line);
            } else if (name == "Entities" && mesh_.binary) {
                entities(line);
            } else {
                if (name.rfind("End", 0) == 0) c_.fail("section", "$" + name + " without its section", line);
                c_.skip_section(name, line);
            }
        }
        if (!format_seen) c_.fail("$MeshFormat", "an empty file (not a Gmsh .msh file)");
        if (!nodes_seen) c_.fail("$Nodes", "the file has no $Nodes section");
        if (!elements_seen) c_.fail("$Elements", "the file has no $Elements section");
        return std::move(mesh_);
    }

private:
    void expect_end(std::string_view name) {
        const int line = c_.line();
        const std::string_view l = c_.next_nonblank_line();
        if (l != "$End" + std::string(name))
            c_.fail("$" + std::string(name), "expected $End" + std::string(name) + ", got " + (l.empty() ? "the end of the file" : quote_token(l)), line);
    }

    void mesh_format(int line) {
        const std::string f = "$MeshFormat";
        const std::string_view version = c_.token(f + " version");
        if (version != "4.1") {
            if (version.size() >= 2 && (version.substr(0, 2) == "2." || version.substr(0, 2) == "3." || version == "4" || version == "4.0"))
                c_.fail(f + " version", "MSH " + std::string(version) + " is not read, only 4.1 (convert: gmsh in.msh -0 -format msh41 -o out.msh)", line + 1);
            c_.fail(f + " version", "expected 4.1, got " + quote_token(version), line + 1);
        }
        const long long type = c_.integer(f + " file-type", 0, 1);
        const long long size = c_.integer(f + " data-size", 0, 64);
        c_.end_of_line(f);
        mesh_.binary = type == 1;
        if (mesh_.binary) {
            if (size != 8) c_.fail(f + " data-size", "binary files with data-size " + std::to_string(size) + " are not read (only 8)", line + 1);
            const int one = c_.binary<int>(f + " endianness marker");
            if (one != 1) c_.fail(f + " endianness marker", "the file is not little-endian (marker " + std::to_string(one) + ", expected 1)");
        }
        expect_end("MeshFormat");
    }

    /// A size_t count: text or 8 binary bytes.
    std::uint64_t count(const std::string& field, std::uint64_t max) {
        if (!mesh_.binary) return static_cast<std::uint64_t>(c_.integer(field, 0, static_cast<long long>(std::min<std::uint64_t>(max, std::numeric_limits<long long>::max()))));
        const std::uint64_t v = c_.binary<std::uint64_t>(field);
        if (v > max) c_.fail(field, std::to_string(v) + " is more than the file can hold (" + std::to_string(max) + ")");
        return v;
    }
    int small_int(const std::string& field, int lo, int hi) {
        if (!mesh_.binary) return static_cast<int>(c_.integer(field, lo, hi));
        const int v = c_.binary<int>(field);
        if (v < lo || v > hi) c_.fail(field, std::to_string(v) + " is outside [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
        return v;
    }
    double real(const std::string& field) {
        if (!mesh_.binary) return c_.real(field);
        const double v = c_.binary<double>(field);
        if (!std::isfinite(v)) c_.fail(field, "not a finite number");
        return v;
    }

    // $Entities of a binary file (a text one is skipped by its end marker; binary data may hold
    // any bytes, so these are parsed).
    void entities(int) {
        const std::string f = "$Entities";
        std::uint64_t n[4];
        for (int d = 0; d < 4; ++d) n[d] = count(f + " count", c_.bytes_left() / 4);
        for (int d = 0; d < 4; ++d)
            for (std::uint64_t i = 0; i < n[d]; ++i) {
                const std::string e = f + " entity of dimension " + std::to_string(d);
                c_.raw(4 + (d == 0 ? 24 : 48), e);
                const std::uint64_t phys = count(e + " physical tags", c_.bytes_left() / 4);
                c_.raw(4 * phys, e);
                if (d > 0) {
                    const std::uint64_t bnd = count(e + " bounding entities", c_.bytes_left() / 4);
                    c_.raw(4 * bnd, e);
                }
            }
        expect_end("Entities");
    }

    std::uint32_t node_index(std::size_t tag, const std::string& field, int line) const {
        if (!dense_.empty()) {
            if (tag < dense_.size() && dense_[tag] != kNone) return dense_[tag];
        } else if (const auto it = sparse_.find(tag); it != sparse_.end()) {
            return it->second;
        }
        c_.fail(field, "node " + std::to_string(tag) + " is not in $Nodes", line);
    }

    void nodes(int line) {
        const std::string f = "$Nodes";
        const std::uint64_t blocks = count(f + " numEntityBlocks", c_.bytes_left() / 4);
        const std::uint64_t total = count(f + " numNodes", std::min<std::uint64_t>(c_.bytes_left() / 4, 0xffffffffu - 1));
        const std::uint64_t min_tag = count(f + " minNodeTag", std::numeric_limits<std::uint64_t>::max());
        const std::uint64_t max_tag = count(f + " maxNodeTag", std::numeric_limits<std::uint64_t>::max());
        if (total > 0 && min_tag > max_tag) c_.fail(f + " minNodeTag", "minNodeTag > maxNodeTag", line + 1);
        if (!mesh_.binary) c_.end_of_line(f);
        // Dense tag table when the tags are compact (Gmsh's usual 1..N), else a hash map.
        const bool dense = max_tag <= 4 * total + 1024;
        if (dense) dense_.assign(static_cast<std::size_t>(max_tag) + 1, kNone);
        mesh_.nodes.reserve(static_cast<std::size_t>(std::min<std::uint64_t>(total, c_.bytes_left() / 8)));
        mesh_.node_tags.reserve(static_cast<std::size_t>(std::min<std::uint64_t>(total, c_.bytes_left() / 8)));
        for (std::uint64_t b = 0; b < blocks; ++b) {
            const std::string bf = f + " block " + std::to_string(b + 1);
            const int dim = small_int(bf + " entityDim", 0, 3);
            (void)small_int(bf + " entityTag", std::numeric_limits<int>::min(), std::numeric_limits<int>::max());
            const int parametric = small_int(bf + " parametric", 0, 1);
            const std::uint64_t n = count(bf + " numNodesInBlock", total - mesh_.nodes.size());
            if (!mesh_.binary) c_.end_of_line(bf);
            const std::size_t first = mesh_.nodes.size();
            for (std::uint64_t i = 0; i < n; ++i) {
                const std::string nf = bf + " node " + std::to_string(i + 1) + " tag";
                const int at = 0;
                const std::uint64_t tag = count(nf, std::numeric_limits<std::uint64_t>::max());
                if (tag == 0) c_.fail(nf, "node tags start at 1", at);
                if (dense && (tag < min_tag || tag > max_tag))
                    c_.fail(nf, "tag " + std::to_string(tag) + " outside [minNodeTag, maxNodeTag] = [" + std::to_string(min_tag) + ", " + std::to_string(max_tag) + "]", at);
                const auto index = static_cast<std::uint32_t>(mesh_.node_tags.size());
                bool fresh = true;
                if (dense) {
                    fresh = dense_[static_cast<std::size_t>(tag)] == kNone;
                    dense_[static_cast<std::size_t>(tag)] = index;
                } else {
                    fresh = sparse_.emplace(static_cast<std::size_t>(tag), index).second;
                }
                if (!fresh) c_.fail(nf, "node " + std::to_string(tag) + " is given twice", at);
                mesh_.node_tags.push_back(static_cast<std::size_t>(tag));
            }
            for (std::uint64_t i = 0; i < n; ++i) {
                const std::string nf = bf + " node " + std::to_string(mesh_.node_tags[first + i]);
                Vec3d p;
                p[0] = real(nf + " x");
                p[1] = real(nf + " y");
                p[2] = real(nf + " z");
                for (int k = 0; k < dim * parametric; ++k) (void)real(nf + " parametric coordinate");
                mesh_.nodes.push_back(p);
            }
        }
        if (mesh_.nodes.size() != total)
            c_.fail(f + " numNodes", "the header says " + std::to_string(total) + " nodes, the blocks hold " + std::to_string(mesh_.nodes.size()), line + 1);
        expect_end("Nodes");
    }

    void elements(int line) {
        const std::string f = "$Elements";
        const std::uint64_t blocks = count(f + " numEntityBlocks", c_.bytes_left() / 4);
        const std::uint64_t total = count(f + " numElements", c_.bytes_left() / 2);
        (void)count(f + " minElementTag", std::numeric_limits<std::uint64_t>::max());
        (void)count(f + " maxElementTag", std::numeric_limits<std::uint64_t>::max());
        if (!mesh_.binary) c_.end_of_line(f);
        std::uint64_t seen = 0;
        for (std::uint64_t b = 0; b < blocks; ++b) {
            const std::string bf = f + " block " + std::to_string(b + 1);
            (void)small_int(bf + " entityDim", 0, 3);
            (void)small_int(bf + " entityTag", std::numeric_limits<int>::min(), std::numeric_limits<int>::max());
            const int type = small_int(bf + " elementType", std::numeric_limits<int>::min(), std::numeric_limits<int>::max());
            const int block_line = c_.line();
            const ElementType et = element_type(type);
            if (!et.name) c_.fail(bf + " elementType", "unknown element type " + std::to_string(type), block_line);
            if (et.dim == 3 && type != 4 && type != 11)
                c_.fail(bf + " elementType", std::string("unsupported volume element: type ") + std::to_string(type) + " (" + et.name +
                                                  "); only 4-node (type 4) and 10-node (type 11) tetrahedra are drawn",
                        block_line);
            const std::uint64_t n = count(bf + " numElementsInBlock", total - seen);
            seen += n;
            const bool keep = et.dim == 3;
            if (!keep) mesh_.skipped_lower_dimensional += static_cast<std::size_t>(n);
            if (!mesh_.binary) c_.end_of_line(bf);
            if (keep) mesh_.tets.reserve(mesh_.tets.size() + static_cast<std::size_t>(std::min<std::uint64_t>(n, c_.bytes_left() / 16)));
            const int data_line = c_.line();
            for (std::uint64_t i = 0; i < n; ++i) {
                const std::string ef = bf + " element " + std::to_string(i + 1);
                MshTet t{};
                t.tag = static_cast<std::size_t>(count(ef + " tag", std::numeric_limits<std::uint64_t>::max()));
                t.nodes = et.nodes;
                t.line = mesh_.binary ? data_line : c_.line();
                for (int k = 0; k < et.nodes; ++k) {
                    const std::string nf = ef + " node " + std::to_string(k + 1);
                    const std::uint64_t tag = count(nf, std::numeric_limits<std::uint64_t>::max());
                    if (keep) t.node[k] = node_index(static_cast<std::size_t>(tag), nf, mesh_.binary ? data_line : 0);
                }
                if (!mesh_.binary) c_.end_of_line(ef);
                if (keep) mesh_.tets.push_back(t);
            }
        }
        if (seen != total)
            c_.fail(f + " numElements", "the header says " + std::to_string(total) + " elements, the blocks hold " + std::to_string(seen), line + 1);
        expect_end("Elements");
    }

    void node_data(int line) {
        const std::string f = "$NodeData";
        MshField field;
        field.line = line;
        const long long strings = c_.integer(f + " numStringTags", 0, 1000);
        c_.end_of_line(f);
        for (long long i = 0; i < strings; ++i) {
            std::string_view s = c_.next_nonblank_line();
            if (s.size() >= 2 && s.front() == '"' && s.back() == '"') s = s.substr(1, s.size() - 2);
            if (i == 0) field.name = std::string(s);
        }
        const long long reals = c_.integer(f + " numRealTags", 0, 1000);
        for (long long i = 0; i < reals; ++i) {
            const double r = c_.real(f + " real tag");
            if (i == 0) field.time = r;
        }
        const long long ints = c_.integer(f + " numIntegerTags", 3, 1000);
        field.step = static_cast<int>(c_.integer(f + " time step", 0, std::numeric_limits<int>::max()));
        field.components = static_cast<int>(c_.integer(f + " number of components", 1, 9));
        const std::uint64_t n = static_cast<std::uint64_t>(c_.integer(f + " number of entries", 0, static_cast<long long>(mesh_.nodes.size())));
        for (long long i = 3; i < ints; ++i) (void)c_.integer(f + " integer tag", std::numeric_limits<int>::min(), std::numeric_limits<int>::max());
        c_.end_of_line(f);
        const std::string fld = f + " \"" + field.name + "\" step " + std::to_string(field.step);
        field.value.assign(mesh_.nodes.size() * static_cast<std::size_t>(field.components), std::numeric_limits<double>::quiet_NaN());
        std::vector<bool> given(mesh_.nodes.size(), false);
        const int data_line = c_.line();
        for (std::uint64_t i = 0; i < n; ++i) {
            const std::string ef = fld + " entry " + std::to_string(i + 1);
            const int at = mesh_.binary ? data_line : 0;
            std::size_t tag = 0;
            if (mesh_.binary) {
                const int t = c_.binary<int>(ef + " node tag");
                if (t <= 0) c_.fail(ef + " node tag", "node tag " + std::to_string(t) + " (tags start at 1)", at);
                tag = static_cast<std::size_t>(t);
            } else {
                tag = static_cast<std::size_t>(c_.integer(ef + " node tag", 1, std::numeric_limits<long long>::max()));
            }
            const std::uint32_t index = node_index(tag, ef + " node tag", at);
            if (given[index]) c_.fail(ef, "node " + std::to_string(tag) + " has a second value", at);
            given[index] = true;
            for (int k = 0; k < field.components; ++k)
                field.value[static_cast<std::size_t>(index) * static_cast<std::size_t>(field.components) + static_cast<std::size_t>(k)] =
                    real(ef + " value");
            if (!mesh_.binary) c_.end_of_line(ef);
        }
        expect_end("NodeData");
        mesh_.fields.push_back(std::move(field));
    }

    static constexpr std::uint32_t kNone = 0xffffffffu;
    Cursor c_;
    MshMesh mesh_;
    std::vector<std::uint32_t> dense_;
    std::unordered_map<std::size_t, std::uint32_t> sparse_;
};

}  // namespace

MshMesh parse_msh(std::string_view bytes, const std::string& file_name) {
    try {
        return MshParser(bytes, file_name).run();
    } catch (const std::bad_alloc&) {
        throw ParseError({file_name, 0, 0, ""}, "out of memory while reading the mesh");
    }
}

MshMesh read_msh(const std::filesystem::path& path) {
    const Location file{path.string(), 0, 0, ""};
    std::ifstream in(path, std::ios::binary);
    if (!in) throw ParseError(file, std::string("cannot open: ") + std::strerror(errno));
    std::string bytes;
    try {
        in.seekg(0, std::ios::end);
        const std::streamoff size = in.tellg();
        in.seekg(0);
        if (size > 0) bytes.resize(static_cast<std::size_t>(size));
        in.read(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    } catch (const std::bad_alloc&) {
        throw ParseError(file, "out of memory while reading the file");
    }
    if (in.bad() || static_cast<std::size_t>(in.gcount()) != bytes.size()) throw ParseError(file, "read error");
    return parse_msh(bytes, path.string());
}

std::vector<Quadric> tetmesh_isosurface(const MshMesh& mesh, const TetmeshIso& what, const Material& material, const Location& where) {
    const auto fail_at = [&](const std::string& field, const std::string& message) -> ParseError {
        Location l = where;
        if (!field.empty()) l.field = field;
        return ParseError(l, message);
    };
    // The field: by name (every step of it), then the step.
    std::vector<const MshField*> named;
    std::string names;
    for (const MshField& f : mesh.fields) {
        if (names.find("\"" + f.name + "\"") == std::string::npos) names += (names.empty() ? "" : ", ") + ("\"" + f.name + "\"");
        if (what.field.empty() || f.name == what.field) named.push_back(&f);
    }
    if (mesh.fields.empty()) throw fail_at("field", "'" + mesh.file + "' has no $NodeData (no field to draw)");
    if (named.empty()) throw fail_at("field", "'" + mesh.file + "' has no field \"" + what.field + "\" (its fields: " + names + ")");
    if (what.field.empty())
        for (const MshField* f : named)
            if (f->name != named.front()->name)
                throw fail_at("field", "'" + mesh.file + "' has several fields (" + names + "): choose one with \"field\"");
    const MshField* field = nullptr;
    std::string steps;
    for (const MshField* f : named) {
        steps += (steps.empty() ? "" : ", ") + std::to_string(f->step);
        if (what.step && f->step == *what.step) field = f;
    }
    if (!what.step) {
        if (named.size() > 1) throw fail_at("step", "field \"" + named.front()->name + "\" has several time steps (" + steps + "): choose one with \"step\"");
        field = named.front();
    }
    if (!field) throw fail_at("step", "field \"" + named.front()->name + "\" has no time step " + std::to_string(*what.step) + " (its steps: " + steps + ")");
    const Location at_field{mesh.file, field->line, 0, "$NodeData \"" + field->name + "\""};
    if (field->components != 1)
        throw ParseError(at_field, "a field of " + std::to_string(field->components) + " components; an isosurface needs a scalar field");
    if (mesh.tets.empty()) throw fail_at("tetmesh", "'" + mesh.file + "' has no tetrahedra");

    std::vector<Quadric> out;
    double lo = HUGE_VAL, hi = -HUGE_VAL;
    // Gmsh's edge nodes 4..9 lie on edges 01, 12, 20, 30, 32, 31; quadratic_edges order is
    // 01, 02, 03, 12, 13, 23.
    static constexpr int gmsh_edge_node[6] = {4, 6, 7, 5, 9, 8};
    for (const MshTet& t : mesh.tets) {
        // The element's location, built only when it fails (no string per element on the way).
        const auto at_elem = [&] { return Location{mesh.file, t.line, 0, "$Elements element " + std::to_string(t.tag)}; };
        double v[10];
        for (int k = 0; k < t.nodes; ++k) {
            v[k] = field->value[t.node[k]];
            if (std::isnan(v[k]))
                throw ParseError(at_elem(), "node " + std::to_string(mesh.node_tags[t.node[k]]) + " has no value in field \"" + field->name + "\"");
        }
        Vec3d p[4];
        for (int k = 0; k < 4; ++k) p[k] = mesh.nodes[t.node[k]];
        const TetShape<double> shape = tet_shape(p);
        if (shape.flatter_than(1e-12)) throw ParseError(at_elem(), "a flat tetrahedron (its corners are coplanar)");
        const double corner[4] = {v[0], v[1], v[2], v[3]};
        double mid[6];
        if (t.nodes == 10) {
            Vec3d x[6];
            for (int e = 0; e < 6; ++e) {
                x[e] = mesh.nodes[t.node[gmsh_edge_node[e]]];
                mid[e] = v[gmsh_edge_node[e]];
            }
            const bb::EdgeNodeOffset<double> off = bb::edge_node_offset(p, x);
            if (!(off.distance <= bb::straight_edge_tolerance * shape.longest))
                throw ParseError(at_elem(), "a curved element: node " + std::to_string(mesh.node_tags[t.node[gmsh_edge_node[off.edge]]]) + " is " +
                                              shortest(off.distance) + " from the midpoint of its edge (" + shortest(off.distance / shape.longest) +
                                              " of the element's size); only straight-sided 10-node tetrahedra are drawn exactly "
                                              "(mesh with Gmsh's Mesh.SecondOrderLinear = 1)");
        }
        const bb::ElementIsosurface<double> e = bb::element_isosurface(p, corner, t.nodes == 10 ? mid : nullptr, what.iso);
        lo = std::min(lo, e.lo);
        hi = std::max(hi, e.hi);
        if (!e.crosses) continue;
        const quadcast::Quadric<double>& q = e.q;
        Quadric s{};
        s.q = q.q;
        s.bound = Quadric::Bound::tetrahedron;
        for (int k = 0; k < 4; ++k) s.tetrahedron.p[static_cast<std::size_t>(k)] = mesh.nodes[t.node[k]];
        s.material = material;
        s.two_sided = true;
        out.push_back(s);
    }
    if (!(what.iso >= lo && what.iso <= hi))
        throw fail_at("iso", "the isovalue " + shortest(what.iso) + " is outside the range [" + shortest(lo) + ", " + shortest(hi) +
                                 "] of field \"" + field->name + "\" over the elements (the bounds of their BB coefficients)");
    return out;
}

}  // namespace quadcast::scene
