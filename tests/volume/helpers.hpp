// tests/volume/helpers.hpp -- temporary files and small volumes for the volume tests
#pragma once

#include <filesystem>
#include <random>
#include <string>
#include <unistd.h>

#include "quadcast/volume/volume.hpp"

namespace vtest {

/// A fresh directory under the system temp dir, removed with the object.
struct TempDir {
    std::filesystem::path path;
    TempDir() {
        path = std::filesystem::temp_directory_path() / ("quadcast-test-volume-" + std::to_string(::getpid()) + "-" +
                                                         std::to_string(counter()++));
        std::filesystem::remove_all(path);
        std::filesystem::create_directories(path);
    }
    ~TempDir() { std::filesystem::remove_all(path); }
    std::string file(const std::string& name) const { return (path / name).string(); }
    static int& counter() { static int c = 0; return c; }
};

/// A small volume with distinct values (exact in every sample type when `integers`).
inline quadcast::volume::VolumeData small_volume(int nx, int ny, int nz, unsigned seed, bool integers) {
    quadcast::volume::VolumeData v;
    v.source = "test";
    v.grid = quadcast::spline::Volume<float>(nx, ny, nz);
    std::mt19937 rng(seed);
    std::uniform_int_distribution<int> ui(0, 120);
    std::uniform_real_distribution<float> uf(-1000.0f, 1000.0f);
    for (float& x : v.grid.data) x = integers ? static_cast<float>(ui(rng)) : uf(rng);
    v.spacing = quadcast::volume::Vec3d{{0.5, 0.25, 2.0}};
    quadcast::volume::update_range(v);
    return v;
}

}  // namespace vtest
