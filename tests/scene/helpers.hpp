// tests/scene/helpers.hpp -- temporary files and paths for the scene tests
#pragma once

#include <doctest/doctest.h>

#include <atomic>
#include <filesystem>
#include <fstream>
#include <functional>
#include <random>
#include <string>
#include <unistd.h>

#include "quadcast/scene/diagnostics.hpp"

namespace scene_test {

namespace fs = std::filesystem;

/// The examples/scenes directory of this source tree.
inline fs::path example_scenes() { return fs::path(__FILE__).parent_path().parent_path().parent_path() / "examples" / "scenes"; }

/// PyMOL's data (Debian package pymol-data); the tests need it and say so.
inline fs::path pymol_test_dat() { return "/usr/share/pymol/test/dat"; }
inline fs::path pymol_demo() { return "/usr/share/pymol/data/demo"; }
inline void require_pymol_data() {
    INFO("install the Debian package pymol-data (apt-get install pymol-data)");
    REQUIRE(fs::is_regular_file(pymol_demo() / "1tii.pdb"));
    REQUIRE(fs::is_regular_file(pymol_test_dat() / "odd01.pdb"));
}

/// A fresh directory removed at scope exit.
struct TempDir {
    fs::path path;
    TempDir() {
        static std::atomic<int> counter{0};
        path = fs::temp_directory_path() /
               ("quadcast_scene_test_" + std::to_string(::getpid()) + "_" + std::to_string(counter++));
        fs::create_directories(path);
    }
    ~TempDir() {
        std::error_code ec;
        fs::remove_all(path, ec);
    }
    fs::path write(const std::string& name, const std::string& text) const {
        const fs::path p = path / name;
        std::ofstream(p, std::ios::binary) << text;
        return p;
    }
};

/// Runs `f`, which must throw ParseError; returns it.
inline quadcast::scene::ParseError parse_error_of(const std::function<void()>& f) {
    try {
        f();
    } catch (const quadcast::scene::ParseError& e) {
        return e;
    } catch (const std::exception& e) {
        FAIL("threw something else than ParseError: " << e.what());
    }
    FAIL("did not throw");
    return quadcast::scene::ParseError({}, "");
}

/// The first `n` lines of a file.
inline std::string head_lines(const fs::path& p, int n) {
    std::ifstream in(p);
    std::string line, out;
    for (int i = 0; i < n && std::getline(in, line); ++i) out += line + "\n";
    return out;
}

inline std::string read_text(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
}

}  // namespace scene_test
