// src/image/image_io.cpp -- PNG and PFM output, written atomically
#include "quadcast/image/image_io.hpp"

#include <png.h>

#include <fcntl.h>
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <system_error>

namespace quadcast::render {

namespace fs = std::filesystem;

namespace {

// Temporaries that a SIGINT/SIGTERM/SIGHUP must not leave behind. The handler may only read
// these fixed buffers and call unlink (async-signal-safe); a slot is published by setting
// `used` after its path is written, and withdrawn by clearing it before the file is renamed.
constexpr std::size_t kSlots = 16;
constexpr std::size_t kPathMax = 4096;
char g_temp_paths[kSlots][kPathMax];
volatile std::sig_atomic_t g_temp_used[kSlots];
std::mutex g_temp_mutex;

extern "C" void remove_temporaries_and_reraise(int sig) {
    for (std::size_t i = 0; i < kSlots; ++i)
        if (g_temp_used[i]) ::unlink(g_temp_paths[i]);
    ::signal(sig, SIG_DFL);
    ::raise(sig);
}

void install_signal_handlers() {
    static std::once_flag once;
    std::call_once(once, [] {
        for (int s : {SIGINT, SIGTERM, SIGHUP}) {
            struct sigaction old{};
            if (::sigaction(s, nullptr, &old) != 0 || old.sa_handler != SIG_DFL) continue;  // keep a program's own handler
            struct sigaction sa{};
            sa.sa_handler = remove_temporaries_and_reraise;
            sigemptyset(&sa.sa_mask);
            ::sigaction(s, &sa, nullptr);
        }
    });
}

std::string errno_text(int e) { return std::strerror(e); }

/// A uniquely named temporary file beside `target` (mkstemp, so concurrent writers to one
/// target never share it), removed when destroyed unless committed, and on SIGINT/SIGTERM.
class Temporary {
public:
    explicit Temporary(const fs::path& target) : target_(target) {
        install_signal_handlers();
        const fs::path dir = target.parent_path().empty() ? fs::path(".") : target.parent_path();
        std::string name = (dir / ("." + target.filename().string() + ".XXXXXX")).string();
        if (name.size() + 1 > kPathMax) throw std::runtime_error(target.string() + ": cannot open for writing: path too long");
        std::lock_guard<std::mutex> lock(g_temp_mutex);
        for (slot_ = 0; slot_ < kSlots && g_temp_used[slot_]; ++slot_) {}
        if (slot_ == kSlots) throw std::runtime_error(target.string() + ": cannot open for writing: too many files at once");
        std::memcpy(g_temp_paths[slot_], name.c_str(), name.size() + 1);
        // Block the signals while the file exists but is not yet registered.
        sigset_t all, old;
        sigfillset(&all);
        ::pthread_sigmask(SIG_BLOCK, &all, &old);
        fd_ = ::mkstemp(g_temp_paths[slot_]);
        const int err = errno;
        if (fd_ >= 0) g_temp_used[slot_] = 1;
        ::pthread_sigmask(SIG_SETMASK, &old, nullptr);
        if (fd_ < 0) throw std::runtime_error(target.string() + ": cannot open for writing: " + errno_text(err));
        path_ = g_temp_paths[slot_];
        // mkstemp creates the file 0600; give it the mode a plain open would (0666 & ~umask).
        const mode_t mask = ::umask(0);
        ::umask(mask);
        ::fchmod(fd_, 0666 & ~mask);
    }
    Temporary(const Temporary&) = delete;
    Temporary& operator=(const Temporary&) = delete;
    ~Temporary() {
        if (fd_ >= 0) ::close(fd_);
        if (!committed_) {
            withdraw();
            ::unlink(path_.c_str());
        }
    }

    /// Takes over the descriptor as a stdio stream (closing it is then the caller's job).
    std::FILE* stream() {
        std::FILE* f = ::fdopen(fd_, "wb");
        if (!f) throw std::runtime_error(target_.string() + ": cannot open for writing: " + errno_text(errno));
        fd_ = -1;
        return f;
    }

    /// Replaces the target by the temporary (rename: readers see the old or the new file).
    void commit() {
        check_output_path(target_);
        withdraw();
        if (::rename(path_.c_str(), target_.c_str()) != 0) {
            const int err = errno;
            ::unlink(path_.c_str());
            committed_ = true;
            throw std::runtime_error(target_.string() + ": cannot write: " + errno_text(err));
        }
        committed_ = true;
    }
    const fs::path& target() const { return target_; }

private:
    void withdraw() {
        std::lock_guard<std::mutex> lock(g_temp_mutex);
        g_temp_used[slot_] = 0;
    }
    fs::path target_;
    std::string path_;
    std::size_t slot_ = 0;
    int fd_ = -1;
    bool committed_ = false;
};

/// Closes `f`, checking every buffered write reached the file.
void close_checked(std::FILE* f, const fs::path& target) {
    const bool failed = std::fflush(f) != 0 || std::ferror(f);
    const int err = errno;
    if (std::fclose(f) != 0 || failed)
        throw std::runtime_error(target.string() + ": write failed: " + errno_text(failed ? err : errno));
}

void write_png_to(Temporary& t, const Image& img) {
    std::FILE* f = t.stream();
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
    png_infop info = png ? png_create_info_struct(png) : nullptr;
    if (!png || !info || setjmp(png_jmpbuf(png))) {
        const int err = errno;
        png_destroy_write_struct(&png, &info);
        std::fclose(f);
        throw std::runtime_error(t.target().string() + ": libpng failed to write the image (" + errno_text(err) + ")");
    }
    png_init_io(png, f);
    png_set_IHDR(png, info, static_cast<png_uint_32>(img.width), static_cast<png_uint_32>(img.height), 8, PNG_COLOR_TYPE_RGB,
                 PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    png_write_info(png, info);
    std::vector<png_byte> row(static_cast<std::size_t>(img.width) * 3);
    for (int y = 0; y < img.height; ++y) {
        for (int x = 0; x < img.width; ++x)
            for (int c = 0; c < 3; ++c) row[static_cast<std::size_t>(x * 3 + c)] = img.rgba[(static_cast<std::size_t>(y) * img.width + x) * 4 + c];
        png_write_row(png, row.data());
    }
    png_write_end(png, nullptr);
    png_destroy_write_struct(&png, &info);
    close_checked(f, t.target());
}

void write_pfm_to(Temporary& t, const Image& img) {
    std::FILE* f = t.stream();
    bool ok = std::fprintf(f, "Pf\n%d %d\n-1.0\n", img.width, img.height) > 0;
    for (int y = img.height - 1; ok && y >= 0; --y)
        ok = std::fwrite(img.depth.data() + static_cast<std::size_t>(y) * img.width, sizeof(float),
                         static_cast<std::size_t>(img.width), f) == static_cast<std::size_t>(img.width);
    if (!ok) {
        const int err = errno;
        std::fclose(f);
        throw std::runtime_error(t.target().string() + ": write failed: " + errno_text(err));
    }
    close_checked(f, t.target());
}

bool same_file(const fs::path& a, const fs::path& b) {
    std::error_code ec;
    if (fs::exists(a, ec) && fs::exists(b, ec) && fs::equivalent(a, b, ec)) return true;
    const fs::path ca = fs::weakly_canonical(a, ec);
    if (ec) return a.lexically_normal() == b.lexically_normal();
    const fs::path cb = fs::weakly_canonical(b, ec);
    if (ec) return a.lexically_normal() == b.lexically_normal();
    return ca == cb;
}

}  // namespace

void check_output_path(const fs::path& path) {
    std::error_code ec;
    const fs::file_status st = fs::status(path, ec);
    if (!ec && fs::exists(st) && !fs::is_regular_file(st))
        throw std::runtime_error(path.string() + ": exists and is not a regular file (" +
                                 (fs::is_directory(st) ? "a directory" : "a device, FIFO or socket") + "); refusing to replace it");
}

void check_output_paths(const fs::path& png, const fs::path& pfm) {
    check_output_path(png);
    if (pfm.empty()) return;
    check_output_path(pfm);
    if (same_file(png, pfm))
        throw std::runtime_error(png.string() + ": the PNG and the --depth PFM would be the same file (" + pfm.string() + ")");
}

void write_png(const fs::path& path, const Image& img) { write_png_and_pfm(path, {}, img); }

void write_pfm(const fs::path& path, const Image& img) {
    check_output_path(path);
    Temporary t(path);
    write_pfm_to(t, img);
    t.commit();
}

void write_png_and_pfm(const fs::path& png, const fs::path& pfm, const Image& img) {
    check_output_paths(png, pfm);
    Temporary tpng(png);
    std::unique_ptr<Temporary> tpfm = pfm.empty() ? nullptr : std::make_unique<Temporary>(pfm);
    write_png_to(tpng, img);
    if (tpfm) write_pfm_to(*tpfm, img);
    // Both are complete: only now replace the targets.
    tpng.commit();
    if (tpfm) tpfm->commit();
}

Image read_png(const fs::path& path) {
    png_image im{};
    im.version = PNG_IMAGE_VERSION;
    if (!png_image_begin_read_from_file(&im, path.c_str())) throw std::runtime_error(path.string() + ": " + im.message);
    im.format = PNG_FORMAT_RGBA;
    Image img;
    img.width = static_cast<int>(im.width);
    img.height = static_cast<int>(im.height);
    img.rgba.resize(PNG_IMAGE_SIZE(im));
    if (!png_image_finish_read(&im, nullptr, img.rgba.data(), 0, nullptr)) throw std::runtime_error(path.string() + ": " + im.message);
    img.depth.assign(static_cast<std::size_t>(img.width) * img.height, 1.0f);
    return img;
}

}  // namespace quadcast::render
