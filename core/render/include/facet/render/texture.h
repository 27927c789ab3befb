// Textures as parameter values: an image (read through TexelImageCache) or a procedural
// checker, evaluated at a hit's UV coordinates. A material parameter or a shape's emission holds
// either a constant (the ParamSet / ShapeDesc value) or one of these (scenes/FORMAT.md,
// "Textures").
//
// Conventions:
//  - UV: (0, 0) is the bottom-left corner of the image, v grows upward, [0, 1]^2 covers the
//    image once (the convention of OBJ and Blender). Texel (x, y) of a TexelImage (row 0 at the
//    top) covers u in [x / W, (x + 1) / W] and v in [1 - (y + 1) / H, 1 - y / H]; its centre is
//    ((x + 0.5) / W, 1 - (y + 0.5) / H).
//  - The UV transform maps the hit's uv to the texture's:
//      uv' = R(uv_rotation) (uv_scale * uv) + uv_offset,
//    R rotating counter-clockwise by uv_rotation degrees about (0, 0), `*` per component.
//  - Filters: closest (the texel containing uv'), linear (bilinear between the 4 texel centres
//    around uv'), mipmap (trilinear over the image's MIP levels, texel_image.h; the default).
//    Wrap modes act on texel indices of every level: repeat (period W_l), clamp (edge texels),
//    mirror (period 2 W_l, reflected).
//  - Mipmap level (Williams 1983; pbrt-v4 section 10.4.3, isotropic trilinear): the pixel's
//    footprint in uv (UvFootprint: duv/dx, duv/dy per pixel step, from ray differentials,
//    camera.h) is mapped into level-0 texel units, g = diag(W, H) A duv (A the UV transform's
//    linear part), and the level is lambda = log2(max(|g_x|, |g_y|)), the longer of the two
//    footprint vectors (isotropic: blurrier than anisotropic filtering at grazing angles, never
//    aliased). One pixel spanning exactly 2^k texels gives lambda = k. lambda <= 0
//    (magnification, or a zero footprint) is exactly the bilinear lookup of level 0 (bit for
//    bit the "linear" filter); otherwise the bilinear lookups of levels floor(lambda) and
//    floor(lambda) + 1 are blended linearly in lambda, and lambda past the last (1 x 1) level
//    reads that level.
//  - Values: a colour texture of a 1- or 2-channel image is grey (channel 0 in r, g, b); of a
//    3+ channel image, its first three channels; `channel` picks one channel (or the Rec. 709
//    luminance 0.2126 R + 0.7152 G + 0.0722 B of linear values) as grey. A number texture
//    reads channel 0 of a 1- or 2-channel image and needs `channel` otherwise. Every value is
//    multiplied by `scale` last; a colour `scale` ([r, g, b], `color_scale`) multiplies per
//    channel (a colour parameter's tint, e.g. glTF's baseColorFactor times its texture).
//  - Paged images (texel_pages.h) are looked up through the tile cache with the same
//    arithmetic as whole ones: a texture's values do not depend on the memory bound.
//  - Checker: cell (i, j) = (floor(n u'), floor(n v')), colour colors[(i + j) mod 2]; so the
//    cell at the UV origin has colors[0].
//  - Vertex colour ({"vertex_color": true}): the hit's vertex colour c = (1 - b1 - b2) c0 +
//    b1 c1 + b2 c2 (linear RGBA, barycentric b1, b2; mesh.h), read as an image texel is: its
//    RGB as a colour, or `channel` r, g, b, a or luminance as grey; times `scale`. No UVs, no
//    filtering. Its range is [0, scale] per channel (mesh colours lie in [0, 1]).
//  - Vertex tint (TextureDesc::times_vertex_color, an importer's: glTF's COLOR_0 times its
//    base colour texture): an image or checker value multiplied per channel by c's RGB.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <glm/vec4.hpp>

#include "facet/render/texel_image.h"
#include "facet/types.h"

namespace facet::render {

// A texture as the scene format writes it (plain data, validated by build_scene).
struct TextureDesc {
    bool checker = false;       // a procedural checker instead of an image
    bool vertex_color = false;  // the mesh's vertex colour instead of an image (`channel`, `scale`)
    // An image or checker multiplied by the vertex colour (glTF's COLOR_0 times its base colour
    // texture; an importer's, never read from or written to JSON).
    bool times_vertex_color = false;
    // Image
    std::string file;  // relative to the scene file's directory (a name for `image`)
    // In-memory texels instead of a file (the Python module's numpy arrays, already decoded:
    // texel_image_from_memory); the scene writer cannot write it (an error).
    std::shared_ptr<const TexelImage> image;
    std::string colorspace;  // "" (default: image's), "srgb", "linear"
    std::string filter;      // "" (default: mipmap), "closest", "linear", "mipmap"
    std::string wrap;        // "" (default: repeat), "repeat", "clamp", "mirror"
    std::string channel;     // "" (all), "r", "g", "b", "a", "luminance"
    // An encoded image held in memory instead of a file (an importer's: a .glb's buffer view or
    // a data: URI); `file` then names it ("/path/model.glb#/images/0", with the format's
    // extension appended) for messages and the image cache. Never written to JSON.
    std::shared_ptr<const std::vector<unsigned char>> bytes;
    // Checker
    std::array<Rgb, 2> colors{Rgb(0.f), Rgb(1.f)};
    double checker_scale = 1.0;  // cells per unit of uv'
    // Both
    Vec2 uv_scale{1.f}, uv_offset{0.f};
    double uv_rotation = 0.0;  // degrees, counter-clockwise
    double scale = 1.0;        // multiplier on the value
    Rgb color_scale{1.f};      // per-channel multiplier (JSON "scale": [r, g, b]), times `scale`
    bool operator==(const TextureDesc&) const = default;
};

enum class TextureFilter : std::uint8_t { Closest, Linear, Mipmap };

// A pixel's footprint in texture coordinates: the change of uv per pixel step along film x
// and along film y (zero: a point, sampled at level 0). From uv_footprint (scene.h).
struct UvFootprint {
    Vec2 duvdx{0.f}, duvdy{0.f};
};

enum class TextureWrap : std::uint8_t { Repeat, Clamp, Mirror };

// A texture ready to evaluate (immutable, thread-safe). Never throws once built.
class Texture {
  public:
    // `channel`: -1 all (colour) channels, 0..3 one channel, 4 luminance.
    static constexpr int kAllChannels = -1, kLuminance = 4;
    // `mips`: the image's MIP levels 1, 2, ... (TexelImageCache::mip_levels), needed by the
    // Mipmap filter only (null otherwise).
    static Texture image(std::shared_ptr<const TexelImage> img, TextureFilter filter,
                         TextureWrap wrap, int channel, const TextureDesc& transform,
                         std::shared_ptr<const std::vector<TexelImage>> mips = nullptr);
    static Texture checker(const TextureDesc& desc);
    // The vertex colour (conventions); `channel` as for images.
    static Texture vertex_color(const TextureDesc& desc, int channel);

    // The value at uv (see conventions): a colour (grey for one channel). Without a footprint
    // the Mipmap filter reads level 0 (bilinear).
    Rgb eval(Vec2 uv) const;
    // The value at uv filtered over the pixel footprint `fp` (Mipmap; the other filters and the
    // checker ignore fp).
    Rgb eval(Vec2 uv, const UvFootprint& fp) const;
    // The value at a hit with uv, footprint fp and interpolated vertex colour `color` (linear
    // RGBA; (1, 1, 1, 1) on surfaces without colours): the only evaluation that serves
    // vertex-colour textures (the others read them as white).
    Rgb eval(Vec2 uv, const UvFootprint& fp, const glm::vec4& color) const {
        if (m_vertex == Vertex::None) [[likely]]
            return eval(uv, fp);
        return vertex_eval(uv, fp, color);
    }
    // Whether the value depends on the hit's uv (images, checkers) / its vertex colour.
    bool uses_uv() const { return m_vertex != Vertex::Value; }
    bool uses_vertex_color() const { return m_vertex != Vertex::None; }
    // The (continuous) MIP level of footprint fp (conventions), before clamping to the levels.
    float mip_level(const UvFootprint& fp) const;
    TextureFilter filter() const { return m_filter; }
    // The transformed coordinates uv' (conventions).
    Vec2 transform(Vec2 uv) const;
    // Smallest and largest value per channel over the whole texture (every texel, times scale;
    // bilinear values lie between them), for validation against a parameter's range.
    Rgb min_value() const { return m_min; }
    Rgb max_value() const { return m_max; }
    // The image (null for a checker).
    const TexelImage* texel_image() const { return m_image.get(); }

  private:
    // The texture's value of one texel's channels p (channel choice, times scale).
    Rgb value(const float* p, int channels) const;
    // The image's filtered value at uv over footprint fp (null: level 0) through `levels`, the
    // whole image's or the paged image's (texture.cpp): one code for both, so the same bits.
    template <class Levels>
    Rgb lookup(const Levels& levels, Vec2 uv, const UvFootprint* fp) const;
    template <class Levels>
    Rgb bilinear(const Levels& levels, int level, Vec2 t) const;
    Rgb eval_image(Vec2 uv, const UvFootprint* fp) const;
    enum class Vertex : std::uint8_t { None, Value, Tint };
    Rgb vertex_eval(Vec2 uv, const UvFootprint& fp, const glm::vec4& color) const;
    std::shared_ptr<const TexelImage> m_image;              // null for a checker
    std::shared_ptr<const std::vector<TexelImage>> m_mips;  // levels 1.. (Mipmap only)
    const PagedImage* m_paged = nullptr;                    // m_image->paged
    TextureFilter m_filter = TextureFilter::Linear;
    TextureWrap m_wrap = TextureWrap::Repeat;
    int m_channel = kAllChannels;
    Rgb m_scale{1.f};  // scale * color_scale
    // uv' = m_a * uv + m_b (m_a = R(rotation) diag(uv_scale))
    glm::mat2 m_a{1.f};
    Vec2 m_b{0.f};
    std::array<Rgb, 2> m_colors{};
    float m_cells = 1.f;
    Rgb m_min{0.f}, m_max{0.f};
    Vertex m_vertex = Vertex::None;
};

// Wraps texel index i into [0, n) by `wrap` (conventions).
int wrap_index(int i, int n, TextureWrap wrap);

}  // namespace facet::render
