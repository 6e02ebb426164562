// src/scene/off.cpp -- OFF (Geomview Object File Format) reader for bilinear quad meshes
#include "quadcast/scene/off.hpp"

#include "quadcast/bilinear.hpp"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <fstream>

namespace quadcast::scene {

namespace {

struct Line {
    int number;
    std::vector<std::string> tokens;
};

class OffParser {
public:
    OffParser(std::istream& in, const std::string& file) : in_(in) { mesh_.file = file; }
    /// Bytes of the input left after the current line (-1: unknown, e.g. a pipe).
    long long remaining() {
        const auto here = in_.tellg();
        if (here < 0) return -1;
        in_.seekg(0, std::ios::end);
        const auto end = in_.tellg();
        in_.seekg(here);
        if (end < 0 || !in_) {
            in_.clear();
            return -1;
        }
        return static_cast<long long>(end - here);
    }

    OffMesh run() {
        // Header and counts.
        Line first = next_line("header");
        std::size_t t = 0;
        const std::string& h = first.tokens[0];
        if (h == "OFF") {
            if (first.tokens.size() > 1 && first.tokens[1] == "BINARY")
                error(first.number, "header", "binary OFF is not supported");
            t = 1;
        } else if (h.size() > 3 && h.compare(h.size() - 3, 3, "OFF") == 0) {
            error(first.number, "header", quote_token(h) + " files are not supported (plain OFF only)");
        } else if (!std::isdigit(static_cast<unsigned char>(h[0]))) {
            error(first.number, "header", "expected 'OFF', found " + quote_token(h));
        }
        Line counts = t < first.tokens.size() ? Line{first.number, {first.tokens.begin() + long(t), first.tokens.end()}}
                                              : next_line("counts");
        remaining_ = remaining();
        if (counts.tokens.size() < 2 || counts.tokens.size() > 3)
            error(counts.number, "counts", "expected 'vertex_count face_count [edge_count]', found " +
                                               std::to_string(counts.tokens.size()) + " values");
        const long nv = count(counts, 0, "vertex_count");
        const long nf = count(counts, 1, "face_count");
        if (counts.tokens.size() == 3) (void)count(counts, 2, "edge_count");

        // Reserve only what the rest of the file can hold (a vertex line takes at least 6 bytes,
        // "0 0 0\n"): counts larger than the file are found where it ends, without allocating for
        // them first.
        const auto fits = [&](long n, long long bytes_each) { return remaining_ < 0 ? n <= 1'000'000 : bytes_each * n <= remaining_; };
        if (fits(nv, 6)) mesh_.vertices.reserve(std::size_t(nv));
        if (fits(nf, 8)) {
            mesh_.faces.reserve(std::size_t(nf));
            mesh_.face_lines.reserve(std::size_t(nf));
            mesh_.face_colors.reserve(std::size_t(nf));
        }

        // Vertices.
        for (long i = 0; i < nv; ++i) {
            const std::string what = "vertex " + std::to_string(i);
            Line l = next_line(what, "file ends after " + std::to_string(i) + " of " + std::to_string(nv) + " vertices");
            if (l.tokens.size() != 3)
                error(l.number, what, "expected 3 coordinates, found " + std::to_string(l.tokens.size()) +
                                          " values (COFF/NOFF data is not supported)");
            Vec3d p{};
            static const char* const axis[3] = {" x", " y", " z"};
            for (int k = 0; k < 3; ++k) p[k] = number(l, std::size_t(k), what + axis[k]);
            mesh_.vertices.push_back(p);
        }

        // Faces.
        for (long f = 0; f < nf; ++f) {
            const std::string what = "face " + std::to_string(f);
            Line l = next_line(what, "file ends after " + std::to_string(f) + " of " + std::to_string(nf) + " faces");
            const long n = integer(l, 0, what + " vertex_count");
            if (n < 3) error(l.number, what + " vertex_count", "a face needs at least 3 vertices, found " + std::to_string(n));
            if (long(l.tokens.size()) < 1 + n)
                error(l.number, what, "declares " + std::to_string(n) + " vertices but lists " +
                                          std::to_string(l.tokens.size() - 1) + " (truncated line?)");
            std::vector<int> face;
            for (long k = 0; k < n; ++k) {
                const std::string fk = what + " vertex " + std::to_string(k);
                const long idx = integer(l, std::size_t(1 + k), fk);
                if (idx < 0 || idx >= nv)
                    error(l.number, fk, "index " + std::to_string(idx) + " is out of range 0.." + std::to_string(nv - 1));
                face.push_back(int(idx));
            }
            const std::size_t extra = l.tokens.size() - std::size_t(1 + n);
            std::optional<Vec3d> colour;
            if (extra == 3 || extra == 4) {
                colour = face_colour(l, std::size_t(1 + n), extra, what);
            } else if (extra == 1) {
                warn(l.number, what + " colour", "colour-map index ignored");
            } else if (extra != 0) {
                error(l.number, what, std::to_string(extra) + " values after the vertex indices; expected none, "
                                      "a colour-map index, or an RGB(A) colour");
            }
            mesh_.faces.push_back(std::move(face));
            mesh_.face_lines.push_back(l.number);
            mesh_.face_colors.push_back(colour);
        }
        if (std::optional<Line> rest = try_next_line())
            warn(rest->number, "", "text after the last face ignored");
        return std::move(mesh_);
    }

private:
    [[noreturn]] void error(int line, const std::string& field, const std::string& msg) const {
        throw ParseError({mesh_.file, line, 0, field}, msg);
    }
    void warn(int line, const std::string& field, const std::string& msg) {
        mesh_.warnings.push_back({{mesh_.file, line, 0, field}, msg});
    }

    /// The next line with tokens (comments and blank lines skipped), if any.
    std::optional<Line> try_next_line() {
        std::string raw;
        while (std::getline(in_, raw)) {
            ++line_no_;
            Line l{line_no_, line_tokens(raw)};
            if (!l.tokens.empty()) return l;
        }
        if (in_.bad()) error(line_no_, "", "read error");
        return std::nullopt;
    }
    Line next_line(const std::string& field, const std::string& at_eof = "") {
        if (std::optional<Line> l = try_next_line()) return std::move(*l);
        error(line_no_, field, at_eof.empty() ? "unexpected end of file (truncated?)" : at_eof + " (truncated?)");
    }

    double number(const Line& l, std::size_t k, const std::string& field) const {
        const std::string& s = l.tokens[k];
        const std::optional<double> v = parse_decimal(s);
        if (!v) error(l.number, field, quote_token(s) + " is not a number");
        if (!std::isfinite(*v)) error(l.number, field, quote_token(s) + " is not finite");
        return *v;
    }
    long integer(const Line& l, std::size_t k, const std::string& field) const {
        const std::string& s = l.tokens[k];
        long v = 0;
        const auto [p, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
        if (ec != std::errc() || p != s.data() + s.size()) error(l.number, field, quote_token(s) + " is not an integer");
        return v;
    }
    long count(const Line& l, std::size_t k, const std::string& field) const {
        const long v = integer(l, k, field);
        if (v < 0) error(l.number, field, "is negative");
        if (v > 100'000'000) error(l.number, field, std::to_string(v) + " is implausibly large");
        return v;
    }
    Vec3d face_colour(const Line& l, std::size_t first, std::size_t n, const std::string& what) const {
        // Geomview: integers are 0..255, anything with a decimal point or exponent is 0..1.
        bool integers = true;
        for (std::size_t k = 0; k < n; ++k)
            if (l.tokens[first + k].find_first_of(".eE") != std::string::npos) integers = false;
        Vec3d c{};
        for (std::size_t k = 0; k < 3; ++k) {
            const std::string field = what + " colour " + "rgb"[k];
            double v = number(l, first + k, field);
            if (integers) v /= 255.0;
            if (v < 0.0 || v > 1.0)
                error(l.number, field, quote_token(l.tokens[first + k]) + " is outside " + (integers ? "0..255" : "0..1"));
            c[int(k)] = v;
        }
        return c;
    }

    std::istream& in_;
    long long remaining_ = -1;
    OffMesh mesh_;
    int line_no_ = 0;
};

}  // namespace

OffMesh parse_off(std::istream& in, const std::string& file_name) {
    OffParser parser(in, file_name);
    return parser.run();
}

OffMesh read_off(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw ParseError({path.string(), 0, 0, ""}, std::string("cannot open: ") + std::strerror(errno));
    return parse_off(in, path.string());
}

bool quad_has_zero_area(const std::array<Vec3d, 4>& p) {
    // The core's host-side classification, so "degenerate" means the same everywhere.
    const quadcast::QuadKind k = quadcast::classify_quad<double>(p[0], p[1], p[2], p[3]);
    return k == quadcast::QuadKind::segment || k == quadcast::QuadKind::point || k == quadcast::QuadKind::non_finite;
}

std::vector<BilinearQuad> off_to_quads(const OffMesh& mesh, const OffOptions& options, const Material& material,
                                       Warnings& warnings) {
    std::vector<BilinearQuad> quads;
    quads.reserve(mesh.faces.size());
    for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
        const std::vector<int>& face = mesh.faces[f];
        const Location where{mesh.file, mesh.face_lines[f], 0, "face " + std::to_string(f)};
        BilinearQuad q;
        q.material = material;
        if (mesh.face_colors[f]) q.material.color = *mesh.face_colors[f];
        auto v = [&](std::size_t k) { return mesh.vertices[std::size_t(face[k])]; };
        if (face.size() == 4) {
            q.p = {v(0), v(1), v(2), v(3)};
        } else if (face.size() == 3) {
            if (options.triangles == TrianglePolicy::error)
                throw ParseError(where, "is a triangle; this mesh is read with \"triangles\": \"error\" (only quads)");
            q.p = {v(0), v(1), v(2), v(2)};
        } else {
            throw ParseError(where, "has " + std::to_string(face.size()) +
                                        " vertices; only quads (and triangles) can be bilinear patches");
        }
        if (quad_has_zero_area(q.p)) {
            warnings.push_back({where, "zero area (corners collinear or coincident); skipped"});
            continue;
        }
        quads.push_back(q);
    }
    return quads;
}

}  // namespace quadcast::scene
