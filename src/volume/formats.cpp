// src/volume/formats.cpp -- volume file formats: INR (and .inr.gz), NRRD, raw + dimensions
#include "quadcast/volume/formats.hpp"

#include <algorithm>
#include <bit>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <optional>
#include <sstream>

#include <zlib.h>

namespace quadcast::volume {

namespace {

/// Largest volume accepted (samples), so that sizes cannot overflow and absurd headers fail fast.
constexpr std::uint64_t max_samples = std::uint64_t(1) << 34;
/// Largest size along one axis (sample indices stay exact in float).
constexpr long long max_axis_samples = 1LL << 24;
/// An INR header (with its padding) must end within this many bytes.
constexpr std::uint64_t max_inr_header_bytes = std::uint64_t(1) << 20;

std::string trim(std::string s) {
    const auto ws = [](char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n'; };
    while (!s.empty() && ws(s.back())) s.pop_back();
    std::size_t b = 0;
    while (b < s.size() && ws(s[b])) ++b;
    return s.substr(b);
}

std::string lower(std::string s) {
    for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return s;
}

/// Quotes header text for messages (printable, at most 60 characters).
std::string show(const std::string& s) {
    std::string r = "'";
    for (std::size_t i = 0; i < s.size() && i < 60; ++i) {
        const unsigned char c = static_cast<unsigned char>(s[i]);
        if (c >= 32 && c < 127) r += static_cast<char>(c);
        else {
            char b[8];
            std::snprintf(b, sizeof b, "\\x%02x", c);
            r += b;
        }
    }
    if (s.size() > 60) r += "...";
    return r + "'";
}

std::optional<long long> parse_int(const std::string& s) {
    long long v = 0;
    const char* e = s.data() + s.size();
    const auto [p, ec] = std::from_chars(s.data(), e, v);
    if (ec != std::errc() || p != e) return std::nullopt;
    return v;
}

std::optional<double> parse_double(const std::string& s) {
    if (s.empty()) return std::nullopt;
    char* end = nullptr;
    errno = 0;
    const double v = std::strtod(s.c_str(), &end);
    if (end != s.c_str() + s.size() || errno == ERANGE || !std::isfinite(v)) return std::nullopt;
    return v;
}

/// Finishes a volume read: sample conversion, NaN policy, range.
VolumeData make_volume(const std::string& name, int nx, int ny, int nz, std::span<const std::uint8_t> samples,
                       std::int64_t data_offset, SampleType type, Endian endian, const ReadOptions& options) {
    VolumeData v;
    v.source = name;
    v.grid = spline::Volume<float>(nx, ny, nz);
    v.sample_type = sample_type_name(type);
    convert_samples(samples.data(), v.grid.data.size(), type, endian, v.grid.data.data());
    const int b = sample_bytes(type);
    apply_nan_policy(v, options.nan, [=](std::size_t n) { return data_offset + static_cast<std::int64_t>(n) * b; });
    update_range(v);
    return v;
}

std::uint64_t checked_count(const std::string& name, long long nx, long long ny, long long nz, int line,
                            const std::string& field) {
    const std::uint64_t n = static_cast<std::uint64_t>(nx) * static_cast<std::uint64_t>(ny);
    const std::string dims = std::to_string(nx) + "x" + std::to_string(ny) + "x" + std::to_string(nz);
    if (nx > max_axis_samples || ny > max_axis_samples || nz > max_axis_samples)
        throw VolumeError(name, -1, line, field,
                          "dimensions " + dims + " are too large (more than 2^24 = " + std::to_string(max_axis_samples) +
                              " samples along an axis)");
    if (n > max_samples || n * static_cast<std::uint64_t>(nz) > max_samples)
        throw VolumeError(name, -1, line, field, "dimensions " + dims + " are too large (more than 2^34 samples in all)");
    return n * static_cast<std::uint64_t>(nz);
}

}  // namespace

// ---- INR ------------------------------------------------------------------------------------------

namespace {

/// What an INR header says.
struct InrHeader {
    long long nx = 0, ny = 0, nz = 0;
    std::uint64_t count = 0;
    SampleType type{};
    Endian endian = Endian::little;
    Vec3d spacing{}, origin{};
    std::size_t data_offset = 0;
    std::vector<std::string> warnings;
    std::uint64_t file_bytes() const { return data_offset + count * static_cast<std::uint64_t>(sample_bytes(type)); }
};

InrHeader parse_inr_header(std::span<const std::uint8_t> bytes, const std::string& name) {
    static const char magic[] = "#INRIMAGE-4#{";
    const std::size_t mlen = sizeof magic - 1;
    if (bytes.size() < mlen || std::memcmp(bytes.data(), magic, mlen) != 0) {
        std::string start(reinterpret_cast<const char*>(bytes.data()), std::min<std::size_t>(bytes.size(), 13));
        throw VolumeError(name, 0, 0, "", "not an INR file: expected '#INRIMAGE-4#{', found " + show(start));
    }
    struct Entry {
        std::string value;
        int line;
    };
    std::map<std::string, Entry> fields;
    std::vector<std::string> warnings;
    std::size_t pos = 0, data_offset = 0;
    int line_no = 0;
    bool ended = false;
    while (pos < bytes.size()) {
        const std::size_t start = pos;
        while (pos < bytes.size() && bytes[pos] != '\n') ++pos;
        std::string line(reinterpret_cast<const char*>(bytes.data()) + start, pos - start);
        if (pos < bytes.size()) ++pos;  // the '\n'
        ++line_no;
        if (line_no == 1) continue;  // the magic
        line = trim(line);
        if (line.rfind("##}", 0) == 0) {
            ended = true;
            data_offset = pos;
            break;
        }
        if (line.empty() || line[0] == '#') continue;
        const std::size_t eq = line.find('=');
        if (eq == std::string::npos)
            throw VolumeError(name, -1, line_no, "", "expected KEY=VALUE, found " + show(line));
        const std::string key = trim(line.substr(0, eq)), value = trim(line.substr(eq + 1));
        if (auto it = fields.find(key); it != fields.end())
            throw VolumeError(name, -1, line_no, key, "given twice (first on header line " + std::to_string(it->second.line) + ")");
        fields[key] = {value, line_no};
        if (pos - start > 4096 || line_no > 10000) break;  // binary garbage: stop early
    }
    if (!ended)
        throw VolumeError(name, static_cast<std::int64_t>(std::min(pos, bytes.size())), 0, "",
                          "INR header not terminated by '##}' (file ends or header garbled after header line " +
                              std::to_string(line_no) + ")");

    const int end_line = line_no;
    auto field_int = [&](const std::string& key, std::optional<long long> dflt) -> long long {
        auto it = fields.find(key);
        if (it == fields.end()) {
            if (dflt) return *dflt;
            throw VolumeError(name, -1, end_line, key, "missing from the header (required)");
        }
        const auto v = parse_int(it->second.value);
        if (!v || *v <= 0)
            throw VolumeError(name, -1, it->second.line, key, "expected a positive integer, found " + show(it->second.value));
        return *v;
    };
    auto field_double = [&](const std::string& key, double dflt, bool positive) -> double {
        auto it = fields.find(key);
        if (it == fields.end()) return dflt;
        const auto v = parse_double(it->second.value);
        if (!v || (positive && !(*v > 0.0)))
            throw VolumeError(name, -1, it->second.line, key,
                              std::string("expected a ") + (positive ? "positive " : "") + "finite number, found " +
                                  show(it->second.value));
        return *v;
    };

    const long long nx = field_int("XDIM", std::nullopt), ny = field_int("YDIM", std::nullopt), nz = field_int("ZDIM", std::nullopt);
    const std::uint64_t count = checked_count(name, nx, ny, nz, fields["XDIM"].line, "XDIM");
    const long long vdim = field_int("VDIM", 1);
    if (vdim != 1)
        throw VolumeError(name, -1, fields["VDIM"].line, "VDIM",
                          "vector images (VDIM=" + std::to_string(vdim) + ") are not supported; only scalar images (VDIM=1)");

    // TYPE and PIXSIZE.
    auto tit = fields.find("TYPE");
    if (tit == fields.end()) throw VolumeError(name, -1, end_line, "TYPE", "missing from the header (required)");
    const std::string tname = lower(tit->second.value);
    auto pit = fields.find("PIXSIZE");
    if (pit == fields.end()) throw VolumeError(name, -1, end_line, "PIXSIZE", "missing from the header (required)");
    long long bits = 0;
    {
        std::string p = lower(pit->second.value);
        if (p.size() > 4 && p.compare(p.size() - 4, 4, "bits") == 0) p = trim(p.substr(0, p.size() - 4));
        const auto b = parse_int(p);
        if (!b) throw VolumeError(name, -1, pit->second.line, "PIXSIZE", "expected '<n> bits', found " + show(pit->second.value));
        bits = *b;
    }
    SampleType type{};
    if (tname == "unsigned fixed" || tname == "signed fixed") {
        const bool sgn = tname[0] == 's';
        if (bits == 8) type = sgn ? SampleType::i8 : SampleType::u8;
        else if (bits == 16) type = sgn ? SampleType::i16 : SampleType::u16;
        else if (bits == 32) type = sgn ? SampleType::i32 : SampleType::u32;
        else
            throw VolumeError(name, -1, pit->second.line, "PIXSIZE",
                              std::to_string(bits) + " bits is not supported for TYPE=" + tit->second.value + " (8, 16 or 32)");
    } else if (tname == "float") {
        if (bits == 32) type = SampleType::f32;
        else if (bits == 64) type = SampleType::f64;
        else
            throw VolumeError(name, -1, pit->second.line, "PIXSIZE",
                              std::to_string(bits) + " bits is not supported for TYPE=float (32 or 64)");
    } else {
        throw VolumeError(name, -1, tit->second.line, "TYPE",
                          "expected 'unsigned fixed', 'signed fixed' or 'float', found " + show(tit->second.value));
    }

    // Byte order.
    Endian endian = Endian::little;
    if (auto c = fields.find("CPU"); c != fields.end()) {
        const std::string cpu = lower(c->second.value);
        if (cpu == "decm" || cpu == "alpha" || cpu == "pc") endian = Endian::little;
        else if (cpu == "sun" || cpu == "sgi") endian = Endian::big;
        else
            throw VolumeError(name, -1, c->second.line, "CPU",
                              "unknown byte order " + show(c->second.value) + " (decm, alpha, pc: little endian; sun, sgi: big endian)");
    } else if (sample_bytes(type) > 1) {
        warnings.push_back(name + ": CPU missing from the header: little endian assumed");
    }
    if (auto s = fields.find("SCALE"); s != fields.end() && trim(s->second.value) != "2**0")
        warnings.push_back(name + ": header line " + std::to_string(s->second.line) + ": SCALE=" + s->second.value +
                           " ignored (samples are used as stored)");
    static const char* const known[] = {"XDIM", "YDIM", "ZDIM", "VDIM", "TYPE", "PIXSIZE", "SCALE", "CPU",
                                        "VX", "VY", "VZ", "TX", "TY", "TZ"};
    for (const auto& field : fields) {
        const std::string& k = field.first;  // not a structured binding: Clang 14 cannot capture those
        if (std::find_if(std::begin(known), std::end(known), [&](const char* n) { return k == n; }) == std::end(known))
            warnings.push_back(name + ": header line " + std::to_string(field.second.line) + ": unknown field " + k + " ignored");
    }
    const Vec3d spacing{{field_double("VX", 1.0, true), field_double("VY", 1.0, true), field_double("VZ", 1.0, true)}};
    const Vec3d origin{{field_double("TX", 0.0, false), field_double("TY", 0.0, false), field_double("TZ", 0.0, false)}};
    return {nx, ny, nz, count, type, endian, spacing, origin, data_offset, warnings};
}

}  // namespace

VolumeData parse_inr(std::span<const std::uint8_t> bytes, const std::string& name, const ReadOptions& options) {
    InrHeader h = parse_inr_header(bytes, name);
    const long long nx = h.nx, ny = h.ny, nz = h.nz;
    const std::uint64_t count = h.count;
    const SampleType type = h.type;
    const std::size_t data_offset = h.data_offset;
    std::vector<std::string>& warnings = h.warnings;

    // Samples.
    const std::uint64_t need = count * static_cast<std::uint64_t>(sample_bytes(type));
    const std::uint64_t have = bytes.size() - data_offset;
    if (have < need)
        throw VolumeError(name, static_cast<std::int64_t>(bytes.size()), 0, "",
                          "voxel data truncated: " + dims_string(int(nx), int(ny), int(nz)) + " samples of " +
                              std::to_string(sample_bytes(type)) + " bytes need " + std::to_string(need) + " bytes after the " +
                              std::to_string(data_offset) + "-byte header, the file has " + std::to_string(have));
    if (have > need)
        warnings.push_back(name + ": byte " + std::to_string(data_offset + need) + ": " + std::to_string(have - need) +
                           " bytes after the voxel data ignored");
    VolumeData v = make_volume(name, int(nx), int(ny), int(nz), bytes.subspan(data_offset, need),
                               static_cast<std::int64_t>(data_offset), type, h.endian, options);
    v.spacing = h.spacing;
    v.origin = h.origin;
    v.warnings.insert(v.warnings.begin(), warnings.begin(), warnings.end());
    return v;
}

VolumeData parse_inr_file(std::span<const std::uint8_t> raw, const std::string& path, const ReadOptions& options,
                          std::uint64_t max_bytes) {
    if (raw.size() < 2 || raw[0] != 0x1f || raw[1] != 0x8b) return parse_inr(raw, path, options);
    // .inr.gz: the header says how many bytes to expect; decompress no more than that (plus
    // max_trailing_bytes), so a small file cannot expand without bound.
    const InrHeader h = parse_inr_header(gunzip(raw, path, std::min(max_inr_header_bytes, max_bytes), true), path);
    return parse_inr(gunzip(raw, path, std::min(h.file_bytes() + max_trailing_bytes, max_bytes)), path, options);
}

VolumeData read_inr(const std::string& path, const ReadOptions& options) {
    return parse_inr_file(read_regular_file(path), path, options);
}

namespace {

template <class U>
void store(std::vector<std::uint8_t>& out, U v, Endian e) {
    std::uint8_t b[sizeof(U)];
    std::memcpy(b, &v, sizeof v);
    if ((e == Endian::big) == (std::endian::native == std::endian::little)) std::reverse(b, b + sizeof(U));
    out.insert(out.end(), b, b + sizeof(U));
}

template <class I>
I round_clamp(float x) {
    const double r = std::nearbyint(static_cast<double>(x));
    const double lo = static_cast<double>(std::numeric_limits<I>::min()), hi = static_cast<double>(std::numeric_limits<I>::max());
    return static_cast<I>(std::clamp(std::isnan(r) ? 0.0 : r, lo, hi));
}

}  // namespace

std::vector<std::uint8_t> inr_bytes(const VolumeData& v, SampleType type, Endian endian) {
    std::ostringstream h;
    h << "#INRIMAGE-4#{\nXDIM=" << v.nx() << "\nYDIM=" << v.ny() << "\nZDIM=" << v.nz() << "\nVDIM=1\n";
    const bool is_float = type == SampleType::f32 || type == SampleType::f64;
    const bool is_signed = type == SampleType::i8 || type == SampleType::i16 || type == SampleType::i32;
    h << "TYPE=" << (is_float ? "float" : is_signed ? "signed fixed" : "unsigned fixed") << "\n";
    h << "PIXSIZE=" << 8 * sample_bytes(type) << " bits\n";
    if (!is_float) h << "SCALE=2**0\n";
    h << "CPU=" << (endian == Endian::little ? "decm" : "sun") << "\n";
    h.precision(9);
    h << "VX=" << v.spacing[0] << "\nVY=" << v.spacing[1] << "\nVZ=" << v.spacing[2] << "\n";
    if (v.origin[0] != 0.0 || v.origin[1] != 0.0 || v.origin[2] != 0.0)
        h << "TX=" << v.origin[0] << "\nTY=" << v.origin[1] << "\nTZ=" << v.origin[2] << "\n";
    std::string header = h.str();
    const std::size_t end = std::string("##}\n").size();
    const std::size_t total = (header.size() + end + 255) / 256 * 256;
    header.append(total - header.size() - end, '\n');
    header += "##}\n";
    std::vector<std::uint8_t> out(header.begin(), header.end());
    out.reserve(out.size() + v.voxel_count() * static_cast<std::size_t>(sample_bytes(type)));
    for (float x : v.grid.data) {
        switch (type) {
        case SampleType::u8: out.push_back(round_clamp<std::uint8_t>(x)); break;
        case SampleType::i8: out.push_back(static_cast<std::uint8_t>(round_clamp<std::int8_t>(x))); break;
        case SampleType::u16: store(out, round_clamp<std::uint16_t>(x), endian); break;
        case SampleType::i16: store(out, round_clamp<std::int16_t>(x), endian); break;
        case SampleType::u32: store(out, round_clamp<std::uint32_t>(x), endian); break;
        case SampleType::i32: store(out, round_clamp<std::int32_t>(x), endian); break;
        case SampleType::f32: store(out, std::bit_cast<std::uint32_t>(x), endian); break;
        case SampleType::f64: store(out, std::bit_cast<std::uint64_t>(static_cast<double>(x)), endian); break;
        }
    }
    return out;
}

void write_file_bytes(const std::string& path, std::span<const std::uint8_t> bytes, bool gzip) {
    if (gzip) {
        gzFile f = gzopen(path.c_str(), "wb6");
        if (!f) throw VolumeError(path, -1, 0, "", std::string("cannot create: ") + std::strerror(errno));
        std::size_t done = 0;
        while (done < bytes.size()) {
            const unsigned n = static_cast<unsigned>(std::min<std::size_t>(bytes.size() - done, 1u << 30));
            if (gzwrite(f, bytes.data() + done, n) != static_cast<int>(n)) {
                gzclose(f);
                throw VolumeError(path, static_cast<std::int64_t>(done), 0, "", "write error");
            }
            done += n;
        }
        if (gzclose(f) != Z_OK) throw VolumeError(path, -1, 0, "", "write error");
        return;
    }
    std::ofstream out(path, std::ios::binary);
    if (!out) throw VolumeError(path, -1, 0, "", std::string("cannot create: ") + std::strerror(errno));
    out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
    if (!out) throw VolumeError(path, -1, 0, "", "write error");
}

void write_inr(const std::string& path, const VolumeData& v, SampleType type, Endian endian, bool gzip) {
    write_file_bytes(path, inr_bytes(v, type, endian), gzip);
}

// ---- NRRD ---------------------------------------------------------------------------------------

namespace {

std::vector<std::string> split_ws(const std::string& s) {
    std::vector<std::string> r;
    std::istringstream in(s);
    std::string t;
    while (in >> t) r.push_back(t);
    return r;
}

SampleType nrrd_type(const std::string& name, const std::string& t, int line) {
    static const std::pair<const char*, SampleType> types[] = {
        {"signed char", SampleType::i8}, {"int8", SampleType::i8}, {"int8_t", SampleType::i8},
        {"uchar", SampleType::u8}, {"unsigned char", SampleType::u8}, {"uint8", SampleType::u8}, {"uint8_t", SampleType::u8},
        {"short", SampleType::i16}, {"short int", SampleType::i16}, {"signed short", SampleType::i16},
        {"signed short int", SampleType::i16}, {"int16", SampleType::i16}, {"int16_t", SampleType::i16},
        {"ushort", SampleType::u16}, {"unsigned short", SampleType::u16}, {"unsigned short int", SampleType::u16},
        {"uint16", SampleType::u16}, {"uint16_t", SampleType::u16},
        {"int", SampleType::i32}, {"signed int", SampleType::i32}, {"int32", SampleType::i32}, {"int32_t", SampleType::i32},
        {"uint", SampleType::u32}, {"unsigned int", SampleType::u32}, {"uint32", SampleType::u32}, {"uint32_t", SampleType::u32},
        {"float", SampleType::f32}, {"double", SampleType::f64},
    };
    for (const auto& [n, ty] : types)
        if (t == n) return ty;
    throw VolumeError(name, -1, line, "type", "unsupported sample type " + show(t));
}

}  // namespace

VolumeData parse_nrrd(std::span<const std::uint8_t> bytes, const std::string& path, const ReadOptions& options) {
    const std::string& name = path;
    if (bytes.size() < 8 || std::memcmp(bytes.data(), "NRRD000", 7) != 0) {
        std::string start(reinterpret_cast<const char*>(bytes.data()), std::min<std::size_t>(bytes.size(), 8));
        throw VolumeError(name, 0, 0, "", "not a NRRD file: expected 'NRRD000x', found " + show(start));
    }
    struct Entry {
        std::string value;
        int line;
    };
    std::map<std::string, Entry> fields;
    std::size_t pos = 0;
    int line_no = 0;
    bool ended = false;
    while (pos < bytes.size()) {
        const std::size_t start = pos;
        while (pos < bytes.size() && bytes[pos] != '\n') ++pos;
        std::string line(reinterpret_cast<const char*>(bytes.data()) + start, pos - start);
        const bool had_newline = pos < bytes.size();
        if (had_newline) ++pos;
        ++line_no;
        if (line_no == 1) continue;
        if (!line.empty() && line.back() == '\r') line.pop_back();
        if (line.empty()) {
            ended = true;
            break;
        }
        if (line[0] == '#') continue;
        if (line.find(":=") != std::string::npos) continue;  // key/value pair
        const std::size_t colon = line.find(": ");
        if (colon == std::string::npos) throw VolumeError(name, -1, line_no, "", "expected 'field: value', found " + show(line));
        const std::string key = lower(trim(line.substr(0, colon)));
        if (fields.count(key)) throw VolumeError(name, -1, line_no, key, "given twice");
        fields[key] = {trim(line.substr(colon + 2)), line_no};
        if (!had_newline) break;
    }
    const bool detached = fields.count("data file") || fields.count("datafile");
    if (!ended && !detached)
        throw VolumeError(name, static_cast<std::int64_t>(bytes.size()), 0, "",
                          "NRRD header not terminated by an empty line (file ends after header line " + std::to_string(line_no) + ")");
    const int end_line = line_no;
    auto need = [&](const std::string& key) -> Entry& {
        auto it = fields.find(key);
        if (it == fields.end()) throw VolumeError(name, -1, end_line, key, "missing from the header (required)");
        return it->second;
    };
    const Entry& te = need("type");
    const SampleType type = nrrd_type(name, lower(te.value), te.line);
    const Entry& de = need("dimension");
    const auto dim = parse_int(de.value);
    if (!dim || (*dim != 3 && *dim != 4))
        throw VolumeError(name, -1, de.line, "dimension", "only 3-D scalar volumes are supported, found " + show(de.value));
    const Entry& se = need("sizes");
    const auto sz = split_ws(se.value);
    if (static_cast<long long>(sz.size()) != *dim)
        throw VolumeError(name, -1, se.line, "sizes", "expected " + std::to_string(*dim) + " sizes, found " + show(se.value));
    std::vector<long long> sizes;
    for (const auto& s : sz) {
        const auto v = parse_int(s);
        if (!v || *v <= 0) throw VolumeError(name, -1, se.line, "sizes", "expected positive integers, found " + show(se.value));
        sizes.push_back(*v);
    }
    const int first_axis = *dim == 4 ? 1 : 0;
    if (*dim == 4 && sizes[0] != 1)
        throw VolumeError(name, -1, se.line, "sizes", "vector volumes (first size " + std::to_string(sizes[0]) + ") are not supported");
    const long long nx = sizes[first_axis], ny = sizes[first_axis + 1], nz = sizes[first_axis + 2];
    const std::uint64_t count = checked_count(name, nx, ny, nz, se.line, "sizes");

    Endian endian = Endian::little;
    if (auto e = fields.find("endian"); e != fields.end()) {
        const std::string v = lower(e->second.value);
        if (v == "big") endian = Endian::big;
        else if (v != "little") throw VolumeError(name, -1, e->second.line, "endian", "expected little or big, found " + show(e->second.value));
    } else if (sample_bytes(type) > 1) {
        throw VolumeError(name, -1, end_line, "endian", "missing from the header (required for " + std::string(sample_type_name(type)) + ")");
    }
    const Entry& ee = need("encoding");
    const std::string enc = lower(ee.value);
    if (enc != "raw" && enc != "gzip" && enc != "gz")
        throw VolumeError(name, -1, ee.line, "encoding", "unsupported encoding " + show(ee.value) + " (raw or gzip)");
    for (const char* skip : {"line skip", "lineskip", "byte skip", "byteskip"})
        if (auto s = fields.find(skip); s != fields.end() && s->second.value != "0")
            throw VolumeError(name, -1, s->second.line, skip, "non-zero skips are not supported");

    Vec3d spacing{{1.0, 1.0, 1.0}}, origin{{0.0, 0.0, 0.0}};
    std::vector<std::string> warnings;
    if (auto s = fields.find("spacings"); s != fields.end()) {
        const auto t = split_ws(s->second.value);
        if (static_cast<long long>(t.size()) != *dim)
            throw VolumeError(name, -1, s->second.line, "spacings", "expected " + std::to_string(*dim) + " values, found " + show(s->second.value));
        for (int a = 0; a < 3; ++a) {
            const auto v = parse_double(t[std::size_t(first_axis + a)]);
            if (!v || !(*v > 0.0)) throw VolumeError(name, -1, s->second.line, "spacings", "expected positive numbers, found " + show(s->second.value));
            spacing[a] = *v;
        }
    } else if (auto d = fields.find("space directions"); d != fields.end()) {
        // "(dx,0,0) (0,dy,0) (0,0,dz)" (a leading "none" for a vector axis).
        std::vector<std::array<double, 3>> dirs;
        std::string s = d->second.value;
        std::size_t p = 0;
        while ((p = s.find('(', p)) != std::string::npos) {
            const std::size_t q = s.find(')', p);
            if (q == std::string::npos) break;
            std::string inner = s.substr(p + 1, q - p - 1);
            std::replace(inner.begin(), inner.end(), ',', ' ');
            const auto t = split_ws(inner);
            std::array<double, 3> v{};
            if (t.size() != 3) throw VolumeError(name, -1, d->second.line, "space directions", "expected 3-vectors, found " + show(s));
            for (int a = 0; a < 3; ++a) {
                const auto x = parse_double(t[std::size_t(a)]);
                if (!x) throw VolumeError(name, -1, d->second.line, "space directions", "expected numbers, found " + show(s));
                v[std::size_t(a)] = *x;
            }
            dirs.push_back(v);
            p = q + 1;
        }
        if (dirs.size() != 3) throw VolumeError(name, -1, d->second.line, "space directions", "expected 3 directions, found " + show(s));
        for (int a = 0; a < 3; ++a)
            for (int b = 0; b < 3; ++b)
                if (a != b && dirs[std::size_t(a)][std::size_t(b)] != 0.0)
                    throw VolumeError(name, -1, d->second.line, "space directions", "only axis-aligned (diagonal) directions are supported");
        for (int a = 0; a < 3; ++a) {
            spacing[a] = std::abs(dirs[std::size_t(a)][std::size_t(a)]);
            if (!(spacing[a] > 0.0)) throw VolumeError(name, -1, d->second.line, "space directions", "zero direction");
            if (dirs[std::size_t(a)][std::size_t(a)] < 0.0) warnings.push_back(name + ": header line " + std::to_string(d->second.line) + ": negative space direction: axis not flipped");
        }
    }
    if (auto o = fields.find("space origin"); o != fields.end()) {
        std::string s = o->second.value;
        std::replace(s.begin(), s.end(), '(', ' ');
        std::replace(s.begin(), s.end(), ')', ' ');
        std::replace(s.begin(), s.end(), ',', ' ');
        const auto t = split_ws(s);
        if (t.size() != 3) throw VolumeError(name, -1, o->second.line, "space origin", "expected (x,y,z), found " + show(o->second.value));
        for (int a = 0; a < 3; ++a) {
            const auto x = parse_double(t[std::size_t(a)]);
            if (!x) throw VolumeError(name, -1, o->second.line, "space origin", "expected numbers, found " + show(o->second.value));
            origin[a] = *x;
        }
    }
    static const char* const known[] = {"type", "dimension", "sizes", "endian", "encoding", "spacings", "space directions",
                                        "space origin", "data file", "datafile", "line skip", "lineskip", "byte skip",
                                        "byteskip", "content", "space", "kinds", "centers", "centerings", "space units",
                                        "units", "labels", "min", "max", "old min", "old max", "measurement frame"};
    for (const auto& field : fields) {
        const std::string& k = field.first;  // not a structured binding: Clang 14 cannot capture those
        if (std::find_if(std::begin(known), std::end(known), [&](const char* n) { return k == n; }) == std::end(known))
            warnings.push_back(name + ": header line " + std::to_string(field.second.line) + ": field " + show(k) + " ignored");
    }

    // The samples: after the header, or in a detached file.
    std::vector<std::uint8_t> payload;
    std::string data_name = name;
    std::int64_t data_offset = static_cast<std::int64_t>(pos);
    if (detached) {
        const Entry& f = fields.count("data file") ? fields["data file"] : fields["datafile"];
        if (f.value.rfind("LIST", 0) == 0 || split_ws(f.value).size() != 1)
            throw VolumeError(name, -1, f.line, "data file", "only a single detached data file is supported");
        std::filesystem::path p = f.value;
        if (p.is_relative()) p = std::filesystem::path(path).parent_path() / p;
        data_name = p.string();
        // Only a regular file of at least the announced size (raw) is read: a directory, a
        // device such as /dev/zero or a FIFO would throw, read without end, or block.
        std::error_code ec;
        const auto st = std::filesystem::status(p, ec);
        if (ec || !std::filesystem::exists(st))
            throw VolumeError(name, -1, f.line, "data file", "cannot open " + show(p.string()) + ": no such file");
        if (!std::filesystem::is_regular_file(st))
            throw VolumeError(name, -1, f.line, "data file",
                              show(p.string()) + " is not a regular file (" +
                                  (std::filesystem::is_directory(st) ? "a directory" : "a device, FIFO or socket") + ")");
        const std::uintmax_t size = std::filesystem::file_size(p, ec);
        const std::uint64_t need_bytes = count * static_cast<std::uint64_t>(sample_bytes(type));
        if (!ec && enc == "raw" && size < need_bytes)
            throw VolumeError(name, -1, f.line, "data file",
                              show(p.string()) + " has " + std::to_string(size) + " bytes, the header's " +
                                  dims_string(int(nx), int(ny), int(nz)) + " samples of " + std::to_string(sample_bytes(type)) +
                                  " bytes need " + std::to_string(need_bytes));
        try {
            payload = read_regular_file(p.string());
        } catch (const VolumeError& e) {
            throw VolumeError(name, -1, f.line, "data file", e.what());
        }
        data_offset = 0;
    } else {
        payload.assign(bytes.begin() + static_cast<std::ptrdiff_t>(pos), bytes.end());
    }
    if (enc != "raw") {
        if (payload.size() < 2 || payload[0] != 0x1f || payload[1] != 0x8b)
            throw VolumeError(data_name, data_offset, 0, "", "encoding is gzip but the data do not start with the gzip magic");
        try {
            payload = gunzip(payload, data_name, count * static_cast<std::uint64_t>(sample_bytes(type)) + max_trailing_bytes);
        } catch (const VolumeError& e) {
            throw VolumeError(data_name, e.byte_offset() < 0 ? -1 : data_offset + e.byte_offset(), 0, "", e.message());
        }
        data_offset = 0;
        data_name += " (decompressed)";
    }
    const std::uint64_t need_bytes = count * static_cast<std::uint64_t>(sample_bytes(type));
    if (payload.size() < need_bytes)
        throw VolumeError(data_name, data_offset + static_cast<std::int64_t>(payload.size()), 0, "",
                          "voxel data truncated: " + dims_string(int(nx), int(ny), int(nz)) + " samples of " +
                              std::to_string(sample_bytes(type)) + " bytes need " + std::to_string(need_bytes) +
                              " bytes, found " + std::to_string(payload.size()));
    if (payload.size() > need_bytes)
        warnings.push_back(data_name + ": " + std::to_string(payload.size() - need_bytes) + " bytes after the voxel data ignored");
    VolumeData v = make_volume(name, int(nx), int(ny), int(nz), std::span<const std::uint8_t>(payload).first(need_bytes),
                               data_offset, type, endian, options);
    v.spacing = spacing;
    v.origin = origin;
    v.warnings.insert(v.warnings.begin(), warnings.begin(), warnings.end());
    return v;
}

VolumeData read_nrrd(const std::string& path, const ReadOptions& options) {
    const std::vector<std::uint8_t> bytes = read_regular_file(path);
    return parse_nrrd(bytes, path, options);
}

// ---- Raw ------------------------------------------------------------------------------------------

VolumeData read_raw(const std::string& path, const RawFormat& f, const ReadOptions& options) {
    if (f.nx <= 0 || f.ny <= 0 || f.nz <= 0)
        throw VolumeError(path, -1, 0, "dimensions", "must be positive, found " + dims_string(f.nx, f.ny, f.nz));
    (void)checked_count(path, f.nx, f.ny, f.nz, 0, "dimensions");  // before reading anything
    const std::vector<std::uint8_t> raw = read_regular_file(path);
    return parse_raw(raw, path, f, options);
}

VolumeData parse_raw(std::span<const std::uint8_t> raw, const std::string& path, const RawFormat& f, const ReadOptions& options) {
    if (f.nx <= 0 || f.ny <= 0 || f.nz <= 0)
        throw VolumeError(path, -1, 0, "dimensions", "must be positive, found " + dims_string(f.nx, f.ny, f.nz));
    const std::uint64_t count = checked_count(path, f.nx, f.ny, f.nz, 0, "dimensions");
    const std::uint64_t need = f.header_bytes + count * static_cast<std::uint64_t>(sample_bytes(f.type));
    const bool gz = raw.size() >= 2 && raw[0] == 0x1f && raw[1] == 0x8b;
    std::vector<std::uint8_t> inflated;
    if (gz) inflated = gunzip(raw, path, need + 1);  // decompress no more than needed + 1
    const std::span<const std::uint8_t> bytes = gz ? std::span<const std::uint8_t>(inflated) : raw;
    if (bytes.size() != need)
        throw VolumeError(path, static_cast<std::int64_t>(std::min<std::uint64_t>(bytes.size(), need)), 0, "dimensions",
                          dims_string(f.nx, f.ny, f.nz) + " samples of " + sample_type_name(f.type) +
                              (f.header_bytes ? " after a " + std::to_string(f.header_bytes) + "-byte header" : std::string()) +
                              " need " + std::to_string(need) + " bytes, the " + (gz ? "decompressed " : "") + "file has " +
                              std::to_string(bytes.size()));
    VolumeData v = make_volume(path, f.nx, f.ny, f.nz, std::span<const std::uint8_t>(bytes).subspan(f.header_bytes),
                               static_cast<std::int64_t>(f.header_bytes), f.type, f.endian, options);
    v.spacing = f.spacing;
    return v;
}

}  // namespace quadcast::volume
