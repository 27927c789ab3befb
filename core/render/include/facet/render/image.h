// Float RGB images and their file formats, shared by the renderer, `facet diff` and the
// cross-checks.
//
// Conventions: pixels are linear RGB (radiance, W sr^-1 m^-2 per channel), row-major, row 0 at
// the top of the picture, x to the right. EXR files are written and read as linear float (RGB,
// 32-bit). PNG files are 8-bit sRGB: linear values are clamped to [0, 1] and encoded with the
// sRGB transfer function (IEC 61966-2-1); reading a PNG decodes sRGB back to linear.
// An image may carry an alpha channel (film transparency and holdouts, render.h): coverage in
// [0, 1], with the colour premultiplied by it (as Cycles writes it). It is then written as an
// RGBA EXR (channel "A") and an RGBA PNG (alpha 8-bit, linear; colour un-premultiplied before
// the sRGB encoding, as PNG stores straight alpha); reading an EXR with "A" keeps it.
// All I/O errors throw std::runtime_error naming the file.
#pragma once

#include <string>
#include <vector>

#include "facet/types.h"

namespace facet::render {

class Image {
  public:
    Image() = default;
    Image(int width, int height)
        : m_width(width), m_height(height), m_pixels(size_t(width) * height) {}

    int width() const { return m_width; }
    int height() const { return m_height; }
    Rgb& at(int x, int y) { return m_pixels[size_t(y) * m_width + x]; }
    const Rgb& at(int x, int y) const { return m_pixels[size_t(y) * m_width + x]; }
    std::vector<Rgb>& pixels() { return m_pixels; }
    const std::vector<Rgb>& pixels() const { return m_pixels; }

    // The alpha channel: empty when the image has none (see conventions).
    bool has_alpha() const { return !m_alpha.empty(); }
    void add_alpha(float value = 1.f) { m_alpha.assign(m_pixels.size(), value); }
    std::vector<float>& alpha() { return m_alpha; }
    const std::vector<float>& alpha() const { return m_alpha; }

  private:
    int m_width = 0, m_height = 0;
    std::vector<Rgb> m_pixels;
    std::vector<float> m_alpha;
};

// Writes by extension: ".exr" (linear float) or ".png" (sRGB 8-bit). Other extensions throw.
void write_image(const Image& image, const std::string& path);
// Reads ".exr" or ".png" (see conventions). Throws on a missing or malformed file.
Image read_image(const std::string& path);

float srgb_encode(float linear);   // linear [0,1] -> sRGB-encoded [0,1]
float srgb_decode(float encoded);  // sRGB-encoded [0,1] -> linear

}  // namespace facet::render
