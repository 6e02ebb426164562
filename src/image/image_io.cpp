// src/image/image_io.cpp -- PNG and PFM output, written atomically
#include "quadcast/image/image_io.hpp"

#include <png.h>

#include <cstdio>
#include <fstream>
#include <memory>
#include <stdexcept>
#include <system_error>

namespace quadcast::render {

namespace {

std::filesystem::path temp_beside(const std::filesystem::path& p) {
    return p.parent_path() / ("." + p.filename().string() + ".partial");
}

void commit(const std::filesystem::path& tmp, const std::filesystem::path& path) {
    std::error_code ec;
    std::filesystem::rename(tmp, path, ec);
    if (ec) {
        std::filesystem::remove(tmp);
        throw std::runtime_error(path.string() + ": cannot write: " + ec.message());
    }
}

}  // namespace

void write_png(const std::filesystem::path& path, const Image& img) {
    const auto tmp = temp_beside(path);
    std::FILE* f = std::fopen(tmp.c_str(), "wb");
    if (!f) throw std::runtime_error(path.string() + ": cannot open for writing");
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
    png_infop info = png ? png_create_info_struct(png) : nullptr;
    if (!png || !info || setjmp(png_jmpbuf(png))) {
        png_destroy_write_struct(&png, &info);
        std::fclose(f);
        std::filesystem::remove(tmp);
        throw std::runtime_error(path.string() + ": libpng failed to write the image");
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
    if (std::fclose(f) != 0) { std::filesystem::remove(tmp); throw std::runtime_error(path.string() + ": write failed"); }
    commit(tmp, path);
}

void write_pfm(const std::filesystem::path& path, const Image& img) {
    const auto tmp = temp_beside(path);
    {
        std::ofstream out(tmp, std::ios::binary);
        out << "Pf\n" << img.width << " " << img.height << "\n-1.0\n";
        for (int y = img.height - 1; y >= 0; --y)
            out.write(reinterpret_cast<const char*>(img.depth.data() + static_cast<std::size_t>(y) * img.width),
                      static_cast<std::streamsize>(sizeof(float) * static_cast<std::size_t>(img.width)));
        if (!out) { std::filesystem::remove(tmp); throw std::runtime_error(path.string() + ": write failed"); }
    }
    commit(tmp, path);
}

Image read_png(const std::filesystem::path& path) {
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
