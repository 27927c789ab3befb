// Texture kind "image": an image read through its UV transform, filtered and wrapped
// (conventions in facet/render/texture.h).
#include "facet/render/texel_pages.h"
#include "facet/render/texture.h"
#include "texture_build.h"

#include <algorithm>
#include <cmath>

namespace facet::render {

namespace {

// Rec. 709 / sRGB primaries: luminance of linear RGB.
float luminance(const Rgb& c) {
    return 0.2126f * c.r + 0.7152f * c.g + 0.0722f * c.b;
}

// Clamp before converting: uv far outside any image must not overflow int.
int texel_index(float f) {
    return int(std::floor(std::clamp(f, -1e9f, 1e9f)));
}

// The levels of a whole image: level 0 is the image, level l >= 1 its MIP level l.
struct WholeLevels {
    const TexelImage& image;
    const std::vector<TexelImage>* mips;  // null without MIP levels
    const TexelImage& at(int l) const { return l == 0 ? image : (*mips)[std::size_t(l - 1)]; }
    int count() const { return 1 + (mips ? int(mips->size()) : 0); }
    int width(int l) const { return at(l).width; }
    int height(int l) const { return at(l).height; }
    const float* texel(int l, int x, int y, float*) const {
        const TexelImage& im = at(l);
        return &im.texels[(std::size_t(y) * std::size_t(im.width) + std::size_t(x)) *
                          std::size_t(im.channels)];
    }
};

// The levels of a paged image, through the tile cache (a copy of the texel into `scratch`).
struct PagedLevels {
    const PagedImage& image;
    int count() const { return image.levels(); }
    int width(int l) const { return image.level(l).width; }
    int height(int l) const { return image.level(l).height; }
    const float* texel(int l, int x, int y, float* scratch) const {
        image.texel(l, x, y, scratch);
        return scratch;
    }
};

class ImageSource final : public TextureSource {
  public:
    std::shared_ptr<const TexelImage> m_image;
    std::shared_ptr<const std::vector<TexelImage>> m_mips;  // levels 1.. (Mipmap only)
    const PagedImage* m_paged = nullptr;                    // m_image->paged
    TextureFilter m_filter = TextureFilter::Linear;
    TextureWrap m_wrap = TextureWrap::Repeat;
    int m_channel = Texture::kAllChannels;
    Rgb m_scale{1.f};  // scale * color_scale
    // uv' = m_a * uv + m_b (m_a = R(rotation) diag(uv_scale))
    glm::mat2 m_a{1.f};
    Vec2 m_b{0.f};

    Rgb eval(const TexturePoint& p) const override {
        // Channels first .. first + count - 1 of the texels, filtered (channel choice and scale
        // come after filtering, as a Blender Image Texture node's outputs do).
        const bool beyond = m_channel > 3 && m_channel != Texture::kLuminance;
        const int first = beyond ? m_channel : 0;
        const int count = beyond ? 1 : std::min(m_image->channels, 4);
        const Vec2 t = m_a * p.uv + m_b;
        const float lambda =
            p.footprint && m_filter == TextureFilter::Mipmap ? mip_level(*p.footprint) : 0.f;
        ImageLookupMemo local;
        ImageLookupMemo& memo = p.memo ? *p.memo : local;
        // Every input of the filtered texels is in the key, so a shared value is the one this
        // lookup would compute (textures that read one image at one point share it).
        if (!(p.memo && memo.image == m_image.get() && memo.mips == m_mips.get() &&
              memo.first == first && memo.filter == std::uint8_t(m_filter) &&
              memo.wrap == std::uint8_t(m_wrap) && memo.t == t && memo.lambda == lambda)) {
            if (m_paged)
                lookup(PagedLevels{*m_paged}, t, lambda, first, count, memo.raw);
            else
                lookup(WholeLevels{*m_image, m_mips.get()}, t, lambda, first, count, memo.raw);
            memo.image = m_image.get(), memo.mips = m_mips.get(), memo.first = first;
            memo.t = t, memo.lambda = lambda;
            memo.filter = std::uint8_t(m_filter), memo.wrap = std::uint8_t(m_wrap);
        }
        return value(memo.raw, first);
    }
    float mip_level(const UvFootprint& fp) const override {
        const Vec2 size(float(m_image->width), float(m_image->height));
        const Vec2 gx = size * (m_a * fp.duvdx), gy = size * (m_a * fp.duvdy);
        const float width = std::max(glm::dot(gx, gx), glm::dot(gy, gy));
        // log2 of the longer length; a zero or non-finite footprint reads level 0.
        return width > 0.f && std::isfinite(width) ? 0.5f * std::log2(width) : 0.f;
    }
    const TexelImage* texel_image() const override { return m_image.get(); }
    TextureFilter filter() const override { return m_filter; }

    // The texture's value from channels `first`.. of a texel (or of filtered texels) p, times
    // scale.
    Rgb value(const float* p, int first) const {
        const int channels = m_image->channels;
        Rgb c;
        if (m_channel == Texture::kAllChannels) {
            c = channels >= 3 ? Rgb(p[0], p[1], p[2]) : Rgb(p[0]);
        } else if (m_channel == Texture::kLuminance) {
            c = Rgb(channels >= 3 ? luminance(Rgb(p[0], p[1], p[2])) : p[0]);
        } else {
            c = Rgb(p[m_channel - first]);
        }
        return c * m_scale;
    }

    // Channels first .. first + N - 1 of one texel into out.
    template <int N, class Levels>
    static void texel_channels(const Levels& levels, int level, int x, int y, int first,
                               float* out) {
        float scratch[kMaxPagedChannels];
        const float* p = levels.texel(level, x, y, scratch) + first;
        for (int k = 0; k < N; ++k) out[k] = p[k];
    }

    // Bilinear between the texel centres of `level` around the transformed coordinates t:
    // channels first .. first + N - 1 into out.
    template <int N, class Levels>
    void bilinear(const Levels& levels, int level, Vec2 t, int first, float* out) const {
        const int w = levels.width(level), h = levels.height(level);
        // Continuous texel coordinates: x right from the left edge, y down from the top edge.
        const float gx = t.x * float(w) - 0.5f, gy = (1.f - t.y) * float(h) - 0.5f;
        const int x0 = texel_index(gx), y0 = texel_index(gy);
        const float ax = gx - float(x0), ay = gy - float(y0);
        const int xa = wrap_index(x0, w, m_wrap), xb = wrap_index(x0 + 1, w, m_wrap);
        const int ya = wrap_index(y0, h, m_wrap), yb = wrap_index(y0 + 1, h, m_wrap);
        float a[N], b[N], c[N], d[N];
        texel_channels<N>(levels, level, xa, ya, first, a);
        texel_channels<N>(levels, level, xb, ya, first, b);
        texel_channels<N>(levels, level, xa, yb, first, c);
        texel_channels<N>(levels, level, xb, yb, first, d);
        for (int k = 0; k < N; ++k)
            out[k] =
                (1.f - ay) * ((1.f - ax) * a[k] + ax * b[k]) + ay * ((1.f - ax) * c[k] + ax * d[k]);
    }

    // The filtered channels at the transformed coordinates t, MIP level lambda (0: level 0),
    // through `levels`, the whole image's or the paged image's: one code for both, so the
    // same bits.
    template <int N, class Levels>
    void filtered(const Levels& levels, Vec2 t, float lambda, int first, float* out) const {
        if (m_filter == TextureFilter::Closest) {
            const int w = levels.width(0), h = levels.height(0);
            texel_channels<N>(levels, 0, wrap_index(texel_index(t.x * float(w)), w, m_wrap),
                              wrap_index(texel_index((1.f - t.y) * float(h)), h, m_wrap), first,
                              out);
            return;
        }
        // Mipmap with a footprint: the level (conventions); otherwise (and when magnified)
        // level 0, exactly "linear".
        if (!(lambda > 0.f)) return bilinear<N>(levels, 0, t, first, out);
        const int last = levels.count() - 1;  // index of the 1 x 1 level
        if (lambda >= float(last)) return bilinear<N>(levels, last, t, first, out);
        const int l = int(std::floor(lambda));
        const float s = lambda - float(l);
        float lo[N], hi[N];
        bilinear<N>(levels, l, t, first, lo);
        bilinear<N>(levels, l + 1, t, first, hi);
        for (int k = 0; k < N; ++k) out[k] = (1.f - s) * lo[k] + s * hi[k];
    }

    template <class Levels>
    void lookup(const Levels& levels, Vec2 t, float lambda, int first, int count,
                float* out) const {
        switch (count) {
            case 1:
                return filtered<1>(levels, t, lambda, first, out);
            case 2:
                return filtered<2>(levels, t, lambda, first, out);
            case 3:
                return filtered<3>(levels, t, lambda, first, out);
            default:
                return filtered<4>(levels, t, lambda, first, out);
        }
    }
};

Texture build_image(TextureBuild& b) {
    const TextureDesc& d = b.desc;
    const std::string& ptr = b.ptr;
    if (d.file.empty()) b.fail(ptr + "/texture", "must name an image file");
    if (!b.files_allowed() && !d.bytes && !d.image)
        b.fail(ptr + "/texture", "image files are disabled here");
    const int filter =
        d.filter.empty() ? 2 : b.choose("filter", d.filter, {"closest", "linear", "mipmap"});
    const int wrap = d.wrap.empty() ? 0 : b.choose("wrap", d.wrap, {"repeat", "clamp", "mirror"});
    TexelImageOptions opt;
    opt.reject_negative = b.radiance;
    if (!d.colorspace.empty())
        opt.color_space = b.choose("colorspace", d.colorspace, {"srgb", "linear"}) == 0
                              ? ColorSpace::Srgb
                              : ColorSpace::Linear;
    else if (!b.color)
        opt.color_space = ColorSpace::Linear;
    std::shared_ptr<const TexelImage> img = b.load_image(opt);
    int channel = Texture::kAllChannels;
    if (!d.channel.empty()) {
        channel = b.choose("channel", d.channel, {"r", "g", "b", "a", "luminance"});
        const bool has = channel == 4 ? true
                         : channel == 3
                             ? img->alpha_channel >= 0
                             : channel < img->channels && !(channel == img->alpha_channel);
        if (!has) {
            b.fail(ptr + "/channel", "the image '" + d.file + "' has no channel '" + d.channel +
                                         "' (" + std::to_string(img->channels) + " channel" +
                                         (img->channels == 1 ? "" : "s") + ")");
        }
        if (channel == 3) channel = img->alpha_channel;
    } else if (!b.color && img->channels - (img->alpha_channel >= 0 ? 1 : 0) > 1) {
        b.fail(ptr + "/channel",
               "a number parameter reads one channel: give \"channel\" (r, g, b, a or "
               "luminance) for the colour image '" +
                   d.file + "'");
    }
    std::shared_ptr<const std::vector<TexelImage>> mips;
    if (filter == 2) mips = b.mip_levels(img);
    return Texture::image(std::move(img),
                          filter == 0   ? TextureFilter::Closest
                          : filter == 1 ? TextureFilter::Linear
                                        : TextureFilter::Mipmap,
                          wrap == 0   ? TextureWrap::Repeat
                          : wrap == 1 ? TextureWrap::Clamp
                                      : TextureWrap::Mirror,
                          channel, d, std::move(mips));
}

}  // namespace

Texture Texture::image(std::shared_ptr<const TexelImage> img, TextureFilter filter,
                       TextureWrap wrap, int channel, const TextureDesc& d,
                       std::shared_ptr<const std::vector<TexelImage>> mips) {
    auto s = std::make_shared<ImageSource>();
    s->m_image = std::move(img);
    s->m_mips = std::move(mips);
    if (filter == TextureFilter::Mipmap && !s->m_mips) filter = TextureFilter::Linear;
    s->m_filter = filter;
    s->m_wrap = wrap;
    s->m_channel = channel;
    s->m_scale = float(d.scale) * d.color_scale;
    uv_transform(d, s->m_a, s->m_b);
    const TexelImage& im = *s->m_image;
    s->m_paged = im.paged.get();
    Rgb lo(INFINITY), hi(-INFINITY);
    auto extend = [&](const float* row) {
        for (int x = 0; x < im.width; ++x) {
            const Rgb v = s->value(row + std::size_t(x) * std::size_t(im.channels), 0);
            lo = glm::min(lo, v);
            hi = glm::max(hi, v);
        }
    };
    if (s->m_paged) {
        s->m_paged->for_each_row(extend);
    } else {
        for (int y = 0; y < im.height; ++y)
            extend(im.texels.data() +
                   std::size_t(y) * std::size_t(im.width) * std::size_t(im.channels));
    }
    if (d.times_vertex_color) lo = Rgb(0.f);  // a vertex colour may be black
    return Texture(std::move(s), lo, hi, kTextureReadsUv, d.times_vertex_color);
}

const TextureKindDef kImageTexture{
    "image",     "an image file through the shape's UVs: `{\"texture\": file, ...}` (keys below)",
    {},          false,
    build_image,
};

}  // namespace facet::render
