// src/slim/model.cpp -- SLIM model files: writer and reader with file/line errors
#include "quadcast/slim/model.hpp"

#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <stdexcept>

namespace quadcast::slim {

using scene::ParseError;
using scene::quote_token;

namespace {

std::string num(double x) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.17g", x);
    return buf;
}

const char* const kBallFields[14] = {"cx", "cy", "cz", "r", "k000", "k100", "k010", "k001", "k110", "k011", "k101", "k200", "k020", "k002"};
const char* const kPlaneFields[4] = {"plane a", "plane b", "plane c", "plane d"};


}  // namespace

void write_model(std::ostream& out, const Model& model) {
    out << "quadcast-slim " << model_format_version << "\n";
    out << "# ball cx cy cz r k000 k100 k010 k001 k110 k011 k101 k200 k020 k002 [plane a b c d [plane a b c d]]\n";
    out << "balls " << model.balls.size() << "\n";
    for (const Ball& b : model.balls) {
        const Coefficients10<double> k = coefficients(b.q);
        out << "ball " << num(b.center[0]) << ' ' << num(b.center[1]) << ' ' << num(b.center[2]) << ' ' << num(b.radius);
        for (double v : {k.k000, k.k100, k.k010, k.k001, k.k110, k.k011, k.k101, k.k200, k.k020, k.k002}) out << ' ' << num(v);
        if (b.has_plane)
            out << " plane " << num(b.plane[0]) << ' ' << num(b.plane[1]) << ' ' << num(b.plane[2]) << ' ' << num(b.plane[3]);
        if (b.has_plane && b.has_plane2)
            out << " plane " << num(b.plane2[0]) << ' ' << num(b.plane2[1]) << ' ' << num(b.plane2[2]) << ' ' << num(b.plane2[3]);
        out << "\n";
    }
}

void write_model(const std::filesystem::path& path, const Model& model) {
    const std::filesystem::path tmp = path.string() + ".part";
    {
        std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
        if (!out) throw std::runtime_error(path.string() + ": cannot write: " + std::strerror(errno));
        write_model(out, model);
        out.flush();
        if (!out) throw std::runtime_error(path.string() + ": write failed");
    }
    std::error_code ec;
    std::filesystem::rename(tmp, path, ec);
    if (ec) throw std::runtime_error(path.string() + ": cannot write: " + ec.message());
}

Model parse_model(std::istream& in, const std::string& file) {
    Model m;
    int line = 0;
    std::string raw;
    const auto fail = [&](const std::string& field, const std::string& msg) { throw ParseError({file, line, 0, field}, msg); };
    const auto next = [&]() -> std::vector<std::string> {
        while (std::getline(in, raw)) {
            ++line;
            std::vector<std::string> t = scene::line_tokens(raw);
            if (!t.empty()) return t;
        }
        return {};
    };
    const auto number = [&](const std::string& s, const std::string& field) {
        const std::optional<double> v = scene::parse_decimal(s);
        if (!v) fail(field, quote_token(s) + " is not a number");
        if (!std::isfinite(*v)) fail(field, quote_token(s) + " is not finite");
        return *v;
    };
    std::vector<std::string> t = next();
    if (t.empty() || t[0] != "quadcast-slim") fail("header", "not a quadcast SLIM model (expected 'quadcast-slim 1')");
    if (t.size() != 2 || (t[1] != "1" && t[1] != std::to_string(model_format_version)))
        fail("version", "unsupported version " + (t.size() > 1 ? quote_token(t[1]) : std::string("(none)")) + " (this reader reads 1 and 2)");
    const bool two_planes = t[1] != "1";
    t = next();
    if (t.size() != 2 || t[0] != "balls") fail("balls", "expected 'balls <count>'");
    long long n = -1;
    {
        const auto [p, ec] = std::from_chars(t[1].data(), t[1].data() + t[1].size(), n);
        if (ec != std::errc() || p != t[1].data() + t[1].size() || n < 0) fail("balls", quote_token(t[1]) + " is not a non-negative integer");
        if (n > 500'000'000) fail("balls", t[1] + " is implausibly large");
    }
    m.balls.reserve(std::size_t(std::min<long long>(n, 1'000'000)));
    for (long long i = 0; i < n; ++i) {
        const std::string what = "ball " + std::to_string(i);
        t = next();
        if (t.empty()) fail(what, "the file ends after " + std::to_string(i) + " of " + std::to_string(n) + " balls (truncated?)");
        if (t[0] != "ball") fail(what, "expected 'ball', found " + quote_token(t[0]));
        const bool one = t.size() == 20 && t[15] == "plane", two = t.size() == 25 && t[15] == "plane" && t[20] == "plane";
        if (t.size() == 25 && !two_planes) fail(what, "a second plane needs version 2 (the file says 'quadcast-slim 1')");
        if (t.size() != 15 && !one && !two)
            fail(what, std::string("expected 'ball' and 14 numbers, optionally 'plane' and 4 numbers") + (two_planes ? " (twice)" : "") + "; found " +
                           std::to_string(t.size()) + " values");
        double v[14];
        for (int k = 0; k < 14; ++k) v[k] = number(t[std::size_t(1 + k)], what + " " + kBallFields[k]);
        Ball b;
        b.center = vec3(v[0], v[1], v[2]);
        b.radius = v[3];
        if (!(b.radius > 0)) fail(what + " r", "radius must be positive (got " + t[4] + ")");
        b.q = quadric_from_coefficients(Coefficients10<double>{v[4], v[5], v[6], v[7], v[8], v[9], v[10], v[11], v[12], v[13]});
        bool zero = true;
        for (int k = 4; k < 14; ++k) zero = zero && v[k] == 0;
        if (zero) fail(what, "the quadric is zero");
        if (t.size() >= 20) {
            for (int k = 0; k < 4; ++k) b.plane[k] = number(t[std::size_t(16 + k)], what + " " + kPlaneFields[k]);
            if (b.plane[0] == 0 && b.plane[1] == 0 && b.plane[2] == 0) fail(what + " plane", "the plane's normal (a, b, c) is zero");
            b.has_plane = true;
        }
        if (t.size() == 25) {
            for (int k = 0; k < 4; ++k) b.plane2[k] = number(t[std::size_t(21 + k)], what + " second " + kPlaneFields[k]);
            if (b.plane2[0] == 0 && b.plane2[1] == 0 && b.plane2[2] == 0) fail(what + " second plane", "the plane's normal (a, b, c) is zero");
            b.has_plane2 = true;
        }
        m.balls.push_back(b);
    }
    if (!next().empty()) fail("", "more ball lines than the count " + std::to_string(n));
    return m;
}

Model read_model(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw ParseError({path.string(), 0, 0, ""}, std::string("cannot open: ") + std::strerror(errno));
    return parse_model(in, path.string());
}

}  // namespace quadcast::slim
