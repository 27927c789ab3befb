// Image files read as data for rendering: textures and environment maps. One reader for all of
// them (OpenImageIO: EXR, HDR, PNG, JPEG, TGA, TIFF and the other formats it reads), and one
// cache so that an image used twice is read once.
//
// Conventions:
//  - Texels are float, row-major, interleaved by channel, row 0 at the TOP of the picture as
//    stored in the file, x to the right: texel (x, y) channel c is
//    texels[(y * width + x) * channels + c]. Every channel the file has is kept (1 grey,
//    2 grey + alpha, 3 RGB, 4 RGBA, or more).
//  - Colour space: Srgb decodes the colour channels with the piecewise sRGB transfer function of
//    IEC 61966-2-1 (evaluated in double and rounded once to float); alpha is never decoded. Linear
//    keeps the stored values (integer formats normalised to [0, 1]). Auto is Srgb for integer
//    formats (8- and 16-bit PNG, JPEG, TGA, TIFF) and Linear for float formats (EXR, HDR, float
//    TIFF): the scene format's default for colour parameters and environment maps.
//  - Validation: a missing, unreadable or corrupt file, a size of zero, and NaN or Inf texels
//    throw TexelImageError naming `where` (a JSON pointer or an object name) and the file.
//    Negative texels are rejected only when asked (environment maps and emission: radiance
//    cannot be negative), as float files can legitimately hold signed data (normal maps).
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <span>
#include <stdexcept>
#include <string>
#include <tuple>
#include <vector>

namespace facet::render {

enum class ColorSpace : std::uint8_t { Auto, Srgb, Linear };

struct TexelImageError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

struct TexelImage {
    std::string path;  // as opened
    int width = 0, height = 0, channels = 0;
    int alpha_channel = -1;                       // index of the alpha channel, or -1
    bool float_format = false;                    // the file stores floats (EXR, HDR, float TIFF)
    ColorSpace color_space = ColorSpace::Linear;  // as decoded (never Auto)
    std::vector<float> texels;

    float at(int x, int y, int c) const {
        return texels[(std::size_t(y) * std::size_t(width) + std::size_t(x)) *
                          std::size_t(channels) +
                      std::size_t(c)];
    }
};

struct TexelImageOptions {
    ColorSpace color_space = ColorSpace::Auto;
    bool reject_negative = false;
};

// Reads `path` (see conventions). `where` names the place in the scene for error messages
// ("/lights/0/file", "material 'wood'"); messages read "<where>: <path>: <what>".
TexelImage load_texel_image(const std::string& path, const TexelImageOptions& options,
                            const std::string& where);
// The same from an encoded image file held in memory (e.g. inside a .glb, or a data: URI),
// through OpenImageIO's IOMemReader, without a temporary file. `name` names it in messages and
// its extension (".png", ".jpg") picks the format.
TexelImage load_texel_image_memory(const std::string& name, std::span<const unsigned char> bytes,
                                   const TexelImageOptions& options, const std::string& where);

// Loaded images by (path, options): the same image used twice is read once. Thread-safe.
// Paths are compared after std::filesystem::weakly_canonical, so "a/../b.png" and "b.png" are
// one image.
class TexelImageCache {
  public:
    std::shared_ptr<const TexelImage> get(const std::string& path, const TexelImageOptions& options,
                                          const std::string& where);
    // An image in memory (load_texel_image_memory), cached under `name` (which must then name
    // these bytes only, e.g. "/abs/model.glb#/images/0").
    std::shared_ptr<const TexelImage> get_memory(const std::string& name,
                                                 std::span<const unsigned char> bytes,
                                                 const TexelImageOptions& options,
                                                 const std::string& where);
    std::size_t size() const;
    std::size_t bytes() const;  // texel memory held

  private:
    mutable std::mutex m_mutex;
    std::map<std::tuple<std::string, int, bool>, std::shared_ptr<const TexelImage>> m_images;
};

}  // namespace facet::render
