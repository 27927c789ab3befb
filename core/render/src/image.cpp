// Image file I/O: OpenEXR 3 (linear float RGB) and PNG through stb (8-bit sRGB).
//
// The stb implementations are compiled here with static linkage (STB_*_STATIC), so no other
// target sees their symbols and Debian's libstb.so is not needed.
#include "facet/render/image.h"

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputFile.h>
#include <OpenEXR/ImfOutputFile.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wall"
#pragma GCC diagnostic ignored "-Wextra"
#pragma GCC diagnostic ignored "-Wpedantic"
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#pragma GCC diagnostic ignored "-Wsign-compare"
#pragma GCC diagnostic ignored "-Wunused-function"
#define STB_IMAGE_STATIC
#define STB_IMAGE_IMPLEMENTATION
#define STBI_ONLY_PNG
#include <stb/stb_image.h>
#define STB_IMAGE_WRITE_STATIC
#define STB_IMAGE_WRITE_IMPLEMENTATION
#include <stb/stb_image_write.h>
#pragma GCC diagnostic pop

namespace facet::render {

namespace {

std::string lower_extension(const std::string& path) {
    auto dot = path.find_last_of('.');
    auto slash = path.find_last_of('/');
    if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return "";
    std::string ext = path.substr(dot);
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return char(std::tolower(c)); });
    return ext;
}

void write_exr(const Image& image, const std::string& path) {
    try {
        Imf::Header header(image.width(), image.height());
        header.compression() = Imf::ZIP_COMPRESSION;
        for (const char* c : {"R", "G", "B"}) header.channels().insert(c, Imf::Channel(Imf::FLOAT));
        if (image.has_alpha()) header.channels().insert("A", Imf::Channel(Imf::FLOAT));
        Imf::OutputFile file(path.c_str(), header);
        Imf::FrameBuffer fb;
        // Rgb is three packed floats: x stride = sizeof(Rgb), y stride = one row.
        char* base = const_cast<char*>(reinterpret_cast<const char*>(image.pixels().data()));
        const size_t xs = sizeof(Rgb), ys = sizeof(Rgb) * size_t(image.width());
        fb.insert("R", Imf::Slice(Imf::FLOAT, base + 0 * sizeof(float), xs, ys));
        fb.insert("G", Imf::Slice(Imf::FLOAT, base + 1 * sizeof(float), xs, ys));
        fb.insert("B", Imf::Slice(Imf::FLOAT, base + 2 * sizeof(float), xs, ys));
        if (image.has_alpha()) {
            char* a = const_cast<char*>(reinterpret_cast<const char*>(image.alpha().data()));
            fb.insert("A", Imf::Slice(Imf::FLOAT, a, sizeof(float),
                                      sizeof(float) * size_t(image.width())));
        }
        file.setFrameBuffer(fb);
        file.writePixels(image.height());
    } catch (const std::exception& e) {
        throw std::runtime_error(path + ": cannot write EXR: " + e.what());
    }
}

Image read_exr(const std::string& path) {
    try {
        Imf::InputFile file(path.c_str());
        const Imath::Box2i dw = file.header().dataWindow();
        const int w = dw.max.x - dw.min.x + 1, h = dw.max.y - dw.min.y + 1;
        if (w <= 0 || h <= 0) throw std::runtime_error("empty data window");
        const Imf::ChannelList& ch = file.header().channels();
        // A luminance-only file ("Y") is read as grey; missing colour channels are an error.
        const bool has_rgb = ch.findChannel("R") && ch.findChannel("G") && ch.findChannel("B");
        const bool has_y = ch.findChannel("Y") != nullptr;
        if (!has_rgb && !has_y) throw std::runtime_error("no R,G,B (or Y) channels");
        Image image(w, h);
        char* base = reinterpret_cast<char*>(image.pixels().data());
        const size_t xs = sizeof(Rgb), ys = sizeof(Rgb) * size_t(w);
        // OpenEXR addresses slices by absolute data-window coordinates: shift the base pointer.
        base -= (ptrdiff_t(dw.min.x) * ptrdiff_t(xs) + ptrdiff_t(dw.min.y) * ptrdiff_t(ys));
        Imf::FrameBuffer fb;
        if (has_rgb) {
            fb.insert("R", Imf::Slice(Imf::FLOAT, base + 0 * sizeof(float), xs, ys));
            fb.insert("G", Imf::Slice(Imf::FLOAT, base + 1 * sizeof(float), xs, ys));
            fb.insert("B", Imf::Slice(Imf::FLOAT, base + 2 * sizeof(float), xs, ys));
        } else {
            fb.insert("Y", Imf::Slice(Imf::FLOAT, base, xs, ys));
        }
        if (ch.findChannel("A")) {
            image.add_alpha();
            char* a = reinterpret_cast<char*>(image.alpha().data());
            const size_t as = sizeof(float), ays = sizeof(float) * size_t(w);
            a -= (ptrdiff_t(dw.min.x) * ptrdiff_t(as) + ptrdiff_t(dw.min.y) * ptrdiff_t(ays));
            fb.insert("A", Imf::Slice(Imf::FLOAT, a, as, ays));
        }
        file.setFrameBuffer(fb);
        file.readPixels(dw.min.y, dw.max.y);
        if (!has_rgb)
            for (Rgb& p : image.pixels()) p = Rgb(p.r);
        return image;
    } catch (const std::exception& e) {
        throw std::runtime_error(path + ": cannot read EXR: " + e.what());
    }
}

void write_png(const Image& image, const std::string& path) {
    const int w = image.width(), h = image.height();
    if (w <= 0 || h <= 0) throw std::runtime_error(path + ": cannot write PNG: empty image");
    const int n = image.has_alpha() ? 4 : 3;
    std::vector<std::uint8_t> bytes(size_t(w) * size_t(h) * size_t(n));
    for (size_t i = 0; i < image.pixels().size(); ++i) {
        Rgb p = image.pixels()[i];
        if (n == 4) {
            // PNG's alpha is straight: un-premultiply (a pixel of alpha 0 is black).
            const float a = std::fmin(std::fmax(image.alpha()[i], 0.f), 1.f);
            p = a > 0.f ? p / a : Rgb(0.f);
            bytes[4 * i + 3] = std::uint8_t(std::lround(a * 255.f));
        }
        for (int c = 0; c < 3; ++c) {
            // NaN maps to 0 (fmax drops it); round to nearest 8-bit code.
            float v = std::fmin(std::fmax(p[c], 0.f), 1.f);
            bytes[size_t(n) * i + size_t(c)] = std::uint8_t(std::lround(srgb_encode(v) * 255.f));
        }
    }
    if (!stbi_write_png(path.c_str(), w, h, n, bytes.data(), w * n))
        throw std::runtime_error(path + ": cannot write PNG");
}

Image read_png(const std::string& path) {
    int w = 0, h = 0, n = 0;
    // 16-bit PNGs are read at full precision; stbi converts 8-bit files as well.
    stbi_us* data = stbi_load_16(path.c_str(), &w, &h, &n, 3);
    if (!data) throw std::runtime_error(path + ": cannot read PNG: " + stbi_failure_reason());
    Image image(w, h);
    for (size_t i = 0; i < image.pixels().size(); ++i)
        for (int c = 0; c < 3; ++c)
            image.pixels()[i][c] = srgb_decode(float(data[3 * i + c]) / 65535.f);
    stbi_image_free(data);
    return image;
}

}  // namespace

void write_image(const Image& image, const std::string& path) {
    const std::string ext = lower_extension(path);
    if (ext == ".exr") return write_exr(image, path);
    if (ext == ".png") return write_png(image, path);
    throw std::runtime_error(path + ": unknown image extension '" + ext + "' (use .exr or .png)");
}

Image read_image(const std::string& path) {
    const std::string ext = lower_extension(path);
    if (ext == ".exr") return read_exr(path);
    if (ext == ".png") return read_png(path);
    throw std::runtime_error(path + ": unknown image extension '" + ext + "' (use .exr or .png)");
}

// sRGB transfer function, IEC 61966-2-1: linear segment below 0.0031308, 2.4 power above.
float srgb_encode(float linear) {
    if (linear <= 0.0031308f) return 12.92f * linear;
    return 1.055f * std::pow(linear, 1.f / 2.4f) - 0.055f;
}

float srgb_decode(float encoded) {
    if (encoded <= 0.04045f) return encoded / 12.92f;
    return std::pow((encoded + 0.055f) / 1.055f, 2.4f);
}

}  // namespace facet::render
