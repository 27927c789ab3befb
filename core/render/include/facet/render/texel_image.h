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
//  - MIP levels (build_mip_levels): level l + 1 has max(1, floor(W_l / 2)) x
//    max(1, floor(H_l / 2)) texels, each the area-weighted mean of the level-l texels it
//    covers (a box filter with fractional weights at odd sizes, so every level keeps the mean
//    of the image exactly up to float rounding); the last level is 1 x 1. Built once, on load,
//    from the decoded (linear) texels, so sRGB images are averaged in linear light.
//  - Memory bound (docs/textures.md, "Texture memory"): a TexelImageCache holds at most
//    `limit` bytes of texels (4 bytes per channel, MIP levels counted). Images are held whole,
//    in load order, while the whole images with their MIP pyramids stay within
//    limit - reserve (reserve = min(limit / 4, 64 MiB)). The first image that would pass it,
//    and every image after it, is paged (texel_pages.h): its pyramid is built once, streaming
//    the file's rows, into a tiled spill file, and read through a shared tile cache of
//    limit - (whole bytes) with LRU eviction. Paged or whole, a lookup returns the same bits.
//    In-memory images (numpy: adopt) are never paged; one that passes the limit is an error.
#pragma once

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <span>
#include <stdexcept>
#include <string>
#include <tuple>
#include <vector>

namespace facet::render {

class PagedImage;

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
    std::vector<float> texels;                    // empty when paged
    // The image's pyramid in the tile cache instead of `texels` (conventions); null when whole.
    std::shared_ptr<const PagedImage> paged;

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

// The MIP levels 1, 2, ... of `image` down to 1 x 1 (level 0 is the image itself; see
// conventions). Empty for a 1 x 1 image.
std::vector<TexelImage> build_mip_levels(const TexelImage& image);

// The MIP levels of a w x h image of c channels as a stream: push level 0's rows in order
// (top first) and `emit(level, y, row)` receives every row of levels 1, 2, ... in order of y
// within each level, computed with the same float operations in the same order as
// build_mip_levels (which uses it), so a streamed pyramid is bit-identical to a whole one.
// Holds a few rows per level only.
class MipChain {
  public:
    using Emit = std::function<void(int level, int y, const float* row)>;
    MipChain(int width, int height, int channels, Emit emit);
    ~MipChain();
    void push_row(const float* row);  // the next row of level 0 (width * channels floats)
    // Levels 0, 1, ... down to 1 x 1: (width, height) of each.
    static std::vector<std::pair<int, int>> level_sizes(int width, int height);

  private:
    struct Stage;
    void push(std::size_t stage, const float* row);
    std::vector<std::unique_ptr<Stage>> m_stages;
    int m_channels;
    Emit m_emit;
};

// Bytes of float texels of a w x h x c image with every MIP level.
std::uint64_t pyramid_bytes(int width, int height, int channels);

// The default bound of a TexelImageCache: 4 GiB of float texels (an 8-bit RGBA 16K x 16K
// image with its MIP levels takes 5.3 GiB; a 4K RGB image 0.27 GiB).
constexpr std::uint64_t kDefaultTextureMemory = std::uint64_t(4) << 30;

// IEC 61966-2-1 decoding in double, rounded once to float (conventions).
inline float srgb_decode_exact(double e) {
    return float(e <= 0.04045 ? e / 12.92 : std::pow((e + 0.055) / 1.055, 2.4));
}

// Checks the texels of `image` (NaN, Inf; negative values when reject_negative) and decodes
// its colour channels in place when cs is Srgb; throws TexelImageError "<where>: <path>:
// texel (x, y) channel c is ..." for the first bad texel. Shared by the file reader and
// in-memory images.
// `first_row`: the image row of image.texels' row 0 (a band of rows read by a streaming
// reader), for the message.
inline void check_and_decode_texels(TexelImage& image, ColorSpace cs, bool reject_negative,
                                    const std::string& where, int first_row = 0) {
    const std::size_t nc = std::size_t(image.channels);
    for (std::size_t i = 0; i < image.texels.size(); ++i) {
        float& v = image.texels[i];
        const int c = int(i % nc);
        if (!std::isfinite(v) || (reject_negative && v < 0.f)) {
            const std::size_t p = i / nc;
            char value[32];
            if (std::isnan(v))
                std::snprintf(value, sizeof value, "nan");
            else
                std::snprintf(value, sizeof value, "%g", double(v));
            throw TexelImageError(
                where + ": " + image.path + ": texel (" +
                std::to_string(p % std::size_t(image.width)) + ", " +
                std::to_string(p / std::size_t(image.width) + std::size_t(first_row)) +
                ") channel " + std::to_string(c) + " is " + (std::isfinite(v) ? "negative: " : "") +
                value + " (row 0 at the top)");
        }
        if (cs == ColorSpace::Srgb && c != image.alpha_channel) v = srgb_decode_exact(v);
    }
    image.color_space = cs == ColorSpace::Srgb ? ColorSpace::Srgb : ColorSpace::Linear;
}

// An image from memory (the Python module's numpy arrays): w x h texels of c channels
// (1 grey, 2 grey + alpha, 3 RGB, 4 RGBA), row 0 at the top, interleaved; `codes` 8-bit (value
// code / 255) or else `floats`. Colour space Auto is Srgb for 8-bit codes and Linear for floats,
// as for files. Validated as files are (conventions); `name` stands for the path in messages.
TexelImage texel_image_from_memory(const std::uint8_t* codes, const float* floats, int w, int h,
                                   int c, const TexelImageOptions& options, const std::string& name,
                                   const std::string& where);

// Streaming hooks of load_texel_image_rows: `stream` sees the header (texels empty; size,
// channels, formats) first and returns true to get the decoded rows through `rows` (bands of
// rows in order, each checked and decoded as the whole image would be) instead of the whole
// image in `texels`. Either may throw TexelImageError (e.g. the spill file cannot be written).
struct TexelRowSink {
    std::function<bool(const TexelImage& header)> stream;
    std::function<void(int first_row, int rows, const float* texels)> rows;
};

// load_texel_image / load_texel_image_memory (bytes non-null) with streaming (TexelRowSink).
TexelImage load_texel_image_rows(const std::string& path, std::span<const unsigned char>* bytes,
                                 const TexelImageOptions& options, const std::string& where,
                                 const TexelRowSink& sink);

// Reads `path` (see conventions). `where` names the place in the scene for error messages
// ("/lights/0/file", "material 'wood'"); messages read "<where>: <path>: <what>".
TexelImage load_texel_image(const std::string& path, const TexelImageOptions& options,
                            const std::string& where);
// The same from an encoded image file held in memory (e.g. inside a .glb, or a data: URI),
// through OpenImageIO's IOMemReader, without a temporary file. `name` names it in messages and
// its extension (".png", ".jpg") picks the format.
TexelImage load_texel_image_memory(const std::string& name, std::span<const unsigned char> bytes,
                                   const TexelImageOptions& options, const std::string& where);

// Texture memory in use and the tile cache's counters (TexelImageCache::stats, Scene).
struct TextureMemoryStats {
    std::uint64_t limit = 0;
    std::uint64_t whole_bytes = 0;       // whole images with their MIP pyramids
    std::uint64_t tile_capacity = 0;     // the tile cache's bound (0: nothing paged)
    std::uint64_t tile_bytes = 0;        // tiles resident now
    std::uint64_t tile_peak = 0;         // most tiles resident at once
    std::uint64_t hits = 0, misses = 0;  // tile look-ups
    std::uint64_t evictions = 0;         // tiles dropped to make room
    std::size_t paged_images = 0;
    // Peak resident texel memory: whole_bytes + tile_peak <= limit (conventions).
    std::uint64_t peak_bytes() const { return whole_bytes + tile_peak; }
};

class TileCache;

// The smallest texture memory bound: 1 MiB (SceneLimits::texture_memory, --texture-memory).
constexpr std::uint64_t kMinTextureMemory = std::uint64_t(1) << 20;

// Loaded images by (path, options): the same image used twice is read once. Thread-safe.
// Paths are compared after std::filesystem::weakly_canonical, so "a/../b.png" and "b.png" are
// one image. Whole or paged by the memory bound (conventions).
class TexelImageCache {
  public:
    explicit TexelImageCache(std::uint64_t limit = kDefaultTextureMemory) : m_limit(limit) {}
    std::shared_ptr<const TexelImage> get(const std::string& path, const TexelImageOptions& options,
                                          const std::string& where);
    // An image in memory (load_texel_image_memory), cached under `name` (which must then name
    // these bytes only, e.g. "/abs/model.glb#/images/0").
    std::shared_ptr<const TexelImage> get_memory(const std::string& name,
                                                 std::span<const unsigned char> bytes,
                                                 const TexelImageOptions& options,
                                                 const std::string& where);
    // An image made elsewhere (texel_image_from_memory), counted against the limit once with
    // its MIP pyramid; never paged, so passing the limit throws TexelImageError.
    std::shared_ptr<const TexelImage> adopt(std::shared_ptr<const TexelImage> image,
                                            const std::string& where);
    // The MIP levels of a whole image returned by get() (build_mip_levels), built on first
    // request and shared by every texture of that image (counted by get() already). A paged
    // image holds its levels itself: an empty list.
    std::shared_ptr<const std::vector<TexelImage>> mip_levels(
        const std::shared_ptr<const TexelImage>& image, const std::string& where);
    std::size_t size() const;
    std::size_t bytes() const;  // texel memory of whole images, MIP pyramids counted
    std::uint64_t limit() const { return m_limit; }
    TextureMemoryStats stats() const;
    // The tile cache of paged images (null while nothing is paged).
    std::shared_ptr<const TileCache> tile_cache() const;

  private:
    std::shared_ptr<const TexelImage> load(const std::string& path,
                                           std::span<const unsigned char>* bytes,
                                           const TexelImageOptions& options,
                                           const std::string& where);
    // Adds `add` bytes to m_bytes or throws (adopt); call with m_mutex held.
    void reserve(std::uint64_t add, const std::string& where, const std::string& path);
    mutable std::mutex m_mutex;
    std::uint64_t m_limit;
    std::uint64_t m_bytes = 0;
    bool m_paging = false;  // an image was paged: every later one is too
    std::size_t m_paged = 0;
    std::shared_ptr<TileCache> m_tiles;
    std::map<std::tuple<std::string, int, bool>, std::shared_ptr<const TexelImage>> m_images;
    std::map<const TexelImage*, std::shared_ptr<const std::vector<TexelImage>>> m_mips;
    std::map<const TexelImage*, std::shared_ptr<const TexelImage>> m_adopted;
};

}  // namespace facet::render
