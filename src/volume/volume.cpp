// src/volume/volume.cpp -- volume data for the spline renderer: samples, errors, value range, progress
#include "quadcast/volume/volume.hpp"

#include <algorithm>
#include <atomic>
#include <bit>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <memory>
#include <mutex>
#include <sstream>

#include <unistd.h>
#include <zlib.h>

namespace quadcast::volume {

namespace {

std::string format_message(const std::string& file, std::int64_t offset, int line, const std::string& field,
                           const std::string& message) {
    std::string s = file;
    if (line > 0) s += (s.empty() ? "" : ": ") + std::string("header line ") + std::to_string(line);
    else if (offset >= 0) s += (s.empty() ? "" : ": ") + std::string("byte ") + std::to_string(offset);
    if (!field.empty()) s += (s.empty() ? "" : ": ") + field;
    return s + (s.empty() ? "" : ": ") + message;
}

}  // namespace

VolumeError::VolumeError(std::string file, std::int64_t byte_offset, int line, std::string field, const std::string& message)
    : std::runtime_error(format_message(file, byte_offset, line, field, message)),
      file_(std::move(file)), offset_(byte_offset), line_(line), field_(std::move(field)), message_(message) {}

const char* sample_type_name(SampleType t) {
    switch (t) {
    case SampleType::u8: return "uint8";
    case SampleType::i8: return "int8";
    case SampleType::u16: return "uint16";
    case SampleType::i16: return "int16";
    case SampleType::u32: return "uint32";
    case SampleType::i32: return "int32";
    case SampleType::f32: return "float32";
    case SampleType::f64: return "float64";
    }
    return "?";
}

int sample_bytes(SampleType t) {
    switch (t) {
    case SampleType::u8: case SampleType::i8: return 1;
    case SampleType::u16: case SampleType::i16: return 2;
    case SampleType::u32: case SampleType::i32: case SampleType::f32: return 4;
    case SampleType::f64: return 8;
    }
    return 0;
}

SampleType parse_sample_type(const std::string& name) {
    static const std::pair<const char*, SampleType> names[] = {
        {"uint8", SampleType::u8},   {"uchar", SampleType::u8},    {"int8", SampleType::i8},
        {"uint16", SampleType::u16}, {"ushort", SampleType::u16},  {"int16", SampleType::i16},
        {"short", SampleType::i16},  {"uint32", SampleType::u32},  {"int32", SampleType::i32},
        {"float32", SampleType::f32}, {"float", SampleType::f32},  {"float64", SampleType::f64},
        {"double", SampleType::f64},
    };
    for (const auto& [n, t] : names)
        if (name == n) return t;
    throw std::invalid_argument("unknown sample type '" + name +
                                "' (expected uint8, int8, uint16, int16, uint32, int32, float32 or float64)");
}

void update_range(VolumeData& v) {
    if (v.grid.data.empty()) { v.min = v.max = 0.0f; return; }
    const auto [lo, hi] = std::minmax_element(v.grid.data.begin(), v.grid.data.end());
    v.min = *lo;
    v.max = *hi;
}

void apply_nan_policy(VolumeData& v, NanPolicy policy, const std::function<std::int64_t(std::size_t)>& byte_offset_of) {
    std::size_t bad = 0, first = 0;
    float lo = std::numeric_limits<float>::infinity();
    for (std::size_t n = 0; n < v.grid.data.size(); ++n) {
        const float x = v.grid.data[n];
        if (!std::isfinite(x)) {
            if (bad++ == 0) first = n;
        } else {
            lo = std::min(lo, x);
        }
    }
    if (bad == 0) return;
    const int i = static_cast<int>(first % static_cast<std::size_t>(v.grid.nx));
    const int j = static_cast<int>((first / static_cast<std::size_t>(v.grid.nx)) % static_cast<std::size_t>(v.grid.ny));
    const int k = static_cast<int>(first / (static_cast<std::size_t>(v.grid.nx) * static_cast<std::size_t>(v.grid.ny)));
    const std::string what = std::string(std::isnan(v.grid.data[first]) ? "NaN" : "infinite") + " sample at voxel (" +
                             std::to_string(i) + "," + std::to_string(j) + "," + std::to_string(k) + ")";
    const std::int64_t off = byte_offset_of ? byte_offset_of(first) : -1;
    if (policy == NanPolicy::error)
        throw VolumeError(v.source, off, 0, "",
                          what + "; " + std::to_string(bad) + " non-finite samples in total (choose a NaN policy: replace by min or 0)");
    if (bad == v.grid.data.size()) lo = 0.0f;
    const float repl = policy == NanPolicy::replace_min ? lo : 0.0f;
    for (float& x : v.grid.data)
        if (!std::isfinite(x)) x = repl;
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.9g", static_cast<double>(repl));
    v.warnings.push_back(format_message(v.source, off, 0, "", std::to_string(bad) + " non-finite samples (first: " + what +
                                                                  ") replaced by " + buf));
}

void check_isovalue(const VolumeData& v, double isovalue) {
    if (!std::isfinite(isovalue)) throw VolumeError(v.source, -1, 0, "isovalue", "is not a finite number");
    if (isovalue < static_cast<double>(v.min) || isovalue > static_cast<double>(v.max)) {
        char buf[160];
        std::snprintf(buf, sizeof buf, "%.9g is outside the data range [%.9g, %.9g]: the isosurface would be empty",
                      isovalue, static_cast<double>(v.min), static_cast<double>(v.max));
        throw VolumeError(v.source, -1, 0, "isovalue", buf);
    }
}

Progress stderr_progress(std::string label) {
    struct State {
        std::mutex m;
        int shown = -1;
        bool tty = ::isatty(2) != 0;
        std::chrono::steady_clock::time_point t0 = std::chrono::steady_clock::now();
        std::string label;
    };
    auto s = std::make_shared<State>();
    s->label = std::move(label);
    return [s](double f) {
        const int pct = static_cast<int>(std::clamp(f, 0.0, 1.0) * 100.0);
        std::lock_guard<std::mutex> lock(s->m);
        if (pct <= s->shown) return;
        const int step = s->tty ? 1 : 10;
        if (pct < 100 && s->shown >= 0 && pct / step == s->shown / step) return;
        s->shown = pct;
        if (pct == 100) {
            const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - s->t0).count();
            std::fprintf(stderr, "%s%s: 100%% (%.2f s)\n", s->tty ? "\r" : "", s->label.c_str(), secs);
        } else if (s->tty) {
            std::fprintf(stderr, "\r%s: %3d%%", s->label.c_str(), pct);
        } else {
            std::fprintf(stderr, "%s: %d%%\n", s->label.c_str(), pct);
        }
        std::fflush(stderr);
    };
}

void require_regular_file(const std::string& path) {
    std::error_code ec;
    const auto st = std::filesystem::status(path, ec);
    if (ec || !std::filesystem::exists(st))
        throw VolumeError(path, -1, 0, "", "cannot open: " + (ec ? ec.message() : std::string("no such file")));
    if (!std::filesystem::is_regular_file(st))
        throw VolumeError(path, -1, 0, "",
                          std::string("not a regular file (") +
                              (std::filesystem::is_directory(st) ? "a directory" : "a device, FIFO or socket") + ")");
}

std::vector<std::uint8_t> read_regular_file(const std::string& path) {
    require_regular_file(path);
    std::ifstream in(path, std::ios::binary);
    if (!in) throw VolumeError(path, -1, 0, "", std::string("cannot open: ") + std::strerror(errno));
    std::error_code ec;
    const std::uintmax_t size = std::filesystem::file_size(path, ec);
    std::vector<std::uint8_t> raw;
    if (!ec) raw.reserve(static_cast<std::size_t>(size));
    char buf[1 << 16];
    while (in.read(buf, sizeof buf) || in.gcount() > 0) raw.insert(raw.end(), buf, buf + in.gcount());
    if (in.bad()) throw VolumeError(path, -1, 0, "", "read error");
    return raw;
}

std::vector<std::uint8_t> read_file_bytes(const std::string& path, bool* was_gzip, std::uint64_t max_bytes) {
    std::vector<std::uint8_t> raw = read_regular_file(path);
    const bool gz = raw.size() >= 2 && raw[0] == 0x1f && raw[1] == 0x8b;
    if (was_gzip) *was_gzip = gz;
    return gz ? gunzip(raw, path, max_bytes) : raw;
}

std::vector<std::uint8_t> gunzip(std::span<const std::uint8_t> raw, const std::string& path, std::uint64_t max_bytes, bool prefix) {
    std::vector<std::uint8_t> out;
    out.reserve(static_cast<std::size_t>(std::min<std::uint64_t>(raw.size() * 4, max_bytes)));
    z_stream zs{};
    if (inflateInit2(&zs, 15 + 16) != Z_OK) throw VolumeError(path, -1, 0, "", "zlib initialisation failed");
    std::unique_ptr<z_stream, void (*)(z_stream*)> guard(&zs, [](z_stream* z) { inflateEnd(z); });
    std::uint8_t buf[1 << 16];
    std::size_t pos = 0;  // compressed bytes consumed
    bool member_done = false;
    while (pos < raw.size()) {
        if (member_done) {
            // Another member follows (concatenated gzip files), or trailing zero padding.
            while (pos < raw.size() && raw[pos] == 0) ++pos;
            if (pos >= raw.size()) break;
            inflateReset(&zs);
            member_done = false;
        }
        zs.next_in = const_cast<Bytef*>(raw.data() + pos);
        zs.avail_in = static_cast<uInt>(std::min<std::size_t>(raw.size() - pos, 1u << 30));
        int rc = Z_OK;
        do {
            zs.next_out = buf;
            zs.avail_out = sizeof buf;
            rc = inflate(&zs, Z_NO_FLUSH);
            if (rc != Z_OK && rc != Z_STREAM_END && rc != Z_BUF_ERROR) {
                const std::int64_t at = zs.next_in - raw.data();
                throw VolumeError(path, at, 0, "",
                                  std::string("corrupt gzip stream (") + (zs.msg ? zs.msg : "zlib error") +
                                      "; compressed offset, " + std::to_string(out.size()) + " bytes decompressed)");
            }
            const std::size_t got = sizeof buf - zs.avail_out;
            if (out.size() + got > max_bytes) {
                if (prefix) {
                    out.insert(out.end(), buf, buf + (max_bytes - out.size()));
                    return out;
                }
                throw VolumeError(path, -1, 0, "",
                                  "decompresses to more than " + std::to_string(max_bytes) +
                                      " bytes, the most this file may hold (a gzip bomb, or data that do not match the header)");
            }
            out.insert(out.end(), buf, buf + got);
        } while (rc == Z_OK && (zs.avail_in > 0 || zs.avail_out == 0));
        pos = static_cast<std::size_t>(zs.next_in - raw.data());
        member_done = rc == Z_STREAM_END;
        if (!member_done && pos >= raw.size()) break;
    }
    if (!member_done && !prefix)
        throw VolumeError(path, static_cast<std::int64_t>(raw.size()), 0, "",
                          "gzip stream truncated (the compressed file ends after " + std::to_string(out.size()) +
                              " decompressed bytes)");
    return out;
}

namespace {

template <class U>
U load(const std::uint8_t* p, Endian e) {
    U v;
    std::memcpy(&v, p, sizeof v);
    if ((e == Endian::big) == (std::endian::native == std::endian::little)) {
        if constexpr (sizeof(U) == 2) v = static_cast<U>(__builtin_bswap16(static_cast<std::uint16_t>(v)));
        if constexpr (sizeof(U) == 4) v = static_cast<U>(__builtin_bswap32(static_cast<std::uint32_t>(v)));
        if constexpr (sizeof(U) == 8) v = static_cast<U>(__builtin_bswap64(static_cast<std::uint64_t>(v)));
    }
    return v;
}

}  // namespace

void convert_samples(const std::uint8_t* data, std::size_t count, SampleType type, Endian endian, float* out) {
    const std::size_t b = static_cast<std::size_t>(sample_bytes(type));
    for (std::size_t n = 0; n < count; ++n) {
        const std::uint8_t* p = data + n * b;
        switch (type) {
        case SampleType::u8: out[n] = static_cast<float>(p[0]); break;
        case SampleType::i8: out[n] = static_cast<float>(static_cast<std::int8_t>(p[0])); break;
        case SampleType::u16: out[n] = static_cast<float>(load<std::uint16_t>(p, endian)); break;
        case SampleType::i16: out[n] = static_cast<float>(static_cast<std::int16_t>(load<std::uint16_t>(p, endian))); break;
        case SampleType::u32: out[n] = static_cast<float>(load<std::uint32_t>(p, endian)); break;
        case SampleType::i32: out[n] = static_cast<float>(static_cast<std::int32_t>(load<std::uint32_t>(p, endian))); break;
        case SampleType::f32: out[n] = std::bit_cast<float>(load<std::uint32_t>(p, endian)); break;
        case SampleType::f64: out[n] = static_cast<float>(std::bit_cast<double>(load<std::uint64_t>(p, endian))); break;
        }
    }
}

std::string dims_string(int nx, int ny, int nz) {
    return std::to_string(nx) + "x" + std::to_string(ny) + "x" + std::to_string(nz);
}

}  // namespace quadcast::volume
