// Textures evaluated at UV coordinates (conventions in facet/render/texture.h).
#include "facet/render/texture.h"

#include "facet/render/scene.h"
#include "facet/render/texel_pages.h"

#include <algorithm>
#include <cmath>

namespace facet::render {

namespace {

constexpr float kPi = 3.14159265358979323846f;

// Rec. 709 / sRGB primaries: luminance of linear RGB.
float luminance(const Rgb& c) {
    return 0.2126f * c.r + 0.7152f * c.g + 0.0722f * c.b;
}

void set_transform(const TextureDesc& d, glm::mat2& a, Vec2& b) {
    const double th = d.uv_rotation * double(kPi) / 180.0;
    const float c = float(std::cos(th)), s = float(std::sin(th));
    // R diag(su, sv); glm matrices are column-major: a[col][row].
    a = glm::mat2(c * d.uv_scale.x, s * d.uv_scale.x, -s * d.uv_scale.y, c * d.uv_scale.y);
    b = d.uv_offset;
}

}  // namespace

int wrap_index(int i, int n, TextureWrap wrap) {
    switch (wrap) {
        case TextureWrap::Clamp:
            return std::clamp(i, 0, n - 1);
        case TextureWrap::Mirror: {
            const int m = ((i % (2 * n)) + 2 * n) % (2 * n);
            return m < n ? m : 2 * n - 1 - m;
        }
        case TextureWrap::Repeat:
        default:
            return ((i % n) + n) % n;
    }
}

Texture Texture::image(std::shared_ptr<const TexelImage> img, TextureFilter filter,
                       TextureWrap wrap, int channel, const TextureDesc& d,
                       std::shared_ptr<const std::vector<TexelImage>> mips) {
    Texture t;
    t.m_image = std::move(img);
    t.m_mips = std::move(mips);
    if (filter == TextureFilter::Mipmap && !t.m_mips) filter = TextureFilter::Linear;
    t.m_filter = filter;
    t.m_wrap = wrap;
    if (d.times_vertex_color) t.m_vertex = Vertex::Tint;
    t.m_channel = channel;
    t.m_scale = float(d.scale) * d.color_scale;
    set_transform(d, t.m_a, t.m_b);
    const TexelImage& im = *t.m_image;
    t.m_paged = im.paged.get();
    t.m_min = Rgb(INFINITY);
    t.m_max = Rgb(-INFINITY);
    auto extend = [&](const float* row) {
        for (int x = 0; x < im.width; ++x) {
            const Rgb v = t.value(row + std::size_t(x) * std::size_t(im.channels), im.channels);
            t.m_min = glm::min(t.m_min, v);
            t.m_max = glm::max(t.m_max, v);
        }
    };
    if (t.m_paged) {
        t.m_paged->for_each_row(extend);
    } else {
        for (int y = 0; y < im.height; ++y)
            extend(im.texels.data() +
                   std::size_t(y) * std::size_t(im.width) * std::size_t(im.channels));
    }
    if (t.m_vertex == Vertex::Tint) t.m_min = Rgb(0.f);  // a vertex colour may be black
    return t;
}

Texture Texture::checker(const TextureDesc& d) {
    Texture t;
    t.m_scale = float(d.scale) * d.color_scale;
    t.m_colors = {d.colors[0] * t.m_scale, d.colors[1] * t.m_scale};
    t.m_cells = float(d.checker_scale);
    set_transform(d, t.m_a, t.m_b);
    t.m_min = glm::min(t.m_colors[0], t.m_colors[1]);
    t.m_max = glm::max(t.m_colors[0], t.m_colors[1]);
    if (d.times_vertex_color) t.m_vertex = Vertex::Tint, t.m_min = Rgb(0.f);
    return t;
}

Texture Texture::vertex_color(const TextureDesc& d, int channel) {
    Texture t;
    t.m_vertex = Vertex::Value;
    t.m_channel = channel;
    t.m_scale = float(d.scale) * d.color_scale;
    t.m_min = Rgb(0.f);
    t.m_max = channel == kAllChannels ? t.m_scale : Rgb(t.m_scale.r);
    return t;
}

Rgb Texture::vertex_eval(Vec2 uv, const UvFootprint& fp, const glm::vec4& color) const {
    if (m_vertex == Vertex::Tint) return eval(uv, fp) * Rgb(color);
    const Rgb rgb(color);
    const float v = m_channel == kAllChannels ? 0.f
                    : m_channel == kLuminance ? luminance(rgb)
                                              : color[m_channel];
    return (m_channel == kAllChannels ? rgb : Rgb(v)) * m_scale;
}

Vec2 Texture::transform(Vec2 uv) const {
    return m_a * uv + m_b;
}

// One texel's channels p as the texture's value, times scale.
Rgb Texture::value(const float* p, int channels) const {
    Rgb c;
    if (m_channel == kAllChannels) {
        c = channels >= 3 ? Rgb(p[0], p[1], p[2]) : Rgb(p[0]);
    } else if (m_channel == kLuminance) {
        c = Rgb(channels >= 3 ? luminance(Rgb(p[0], p[1], p[2])) : p[0]);
    } else {
        c = Rgb(p[m_channel]);
    }
    return c * m_scale;
}

namespace {

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

}  // namespace

// Bilinear between the texel centres of `level` around the transformed coordinates t.
template <class Levels>
Rgb Texture::bilinear(const Levels& levels, int level, Vec2 t) const {
    const int w = levels.width(level), h = levels.height(level);
    const int c = m_image->channels;
    // Continuous texel coordinates: x right from the left edge, y down from the top edge.
    const float gx = t.x * float(w) - 0.5f, gy = (1.f - t.y) * float(h) - 0.5f;
    const int x0 = texel_index(gx), y0 = texel_index(gy);
    const float ax = gx - float(x0), ay = gy - float(y0);
    const int xa = wrap_index(x0, w, m_wrap), xb = wrap_index(x0 + 1, w, m_wrap);
    const int ya = wrap_index(y0, h, m_wrap), yb = wrap_index(y0 + 1, h, m_wrap);
    float scratch[kMaxPagedChannels];
    auto texel = [&](int x, int y) { return value(levels.texel(level, x, y, scratch), c); };
    return (1.f - ay) * ((1.f - ax) * texel(xa, ya) + ax * texel(xb, ya)) +
           ay * ((1.f - ax) * texel(xa, yb) + ax * texel(xb, yb));
}

template <class Levels>
Rgb Texture::lookup(const Levels& levels, Vec2 uv, const UvFootprint* fp) const {
    const Vec2 t = transform(uv);
    if (m_filter == TextureFilter::Closest) {
        const int w = levels.width(0), h = levels.height(0);
        float scratch[kMaxPagedChannels];
        return value(
            levels.texel(0, wrap_index(texel_index(t.x * float(w)), w, m_wrap),
                         wrap_index(texel_index((1.f - t.y) * float(h)), h, m_wrap), scratch),
            m_image->channels);
    }
    // Mipmap with a footprint: the level (conventions); otherwise (and when magnified) level
    // 0, exactly "linear".
    const float lambda = fp && m_filter == TextureFilter::Mipmap ? mip_level(*fp) : 0.f;
    if (!(lambda > 0.f)) return bilinear(levels, 0, t);
    const int last = levels.count() - 1;  // index of the 1 x 1 level
    if (lambda >= float(last)) return bilinear(levels, last, t);
    const int l = int(std::floor(lambda));
    const float a = lambda - float(l);
    return (1.f - a) * bilinear(levels, l, t) + a * bilinear(levels, l + 1, t);
}

Rgb Texture::eval_image(Vec2 uv, const UvFootprint* fp) const {
    if (m_paged) return lookup(PagedLevels{*m_paged}, uv, fp);
    return lookup(WholeLevels{*m_image, m_mips.get()}, uv, fp);
}

Rgb Texture::eval(Vec2 uv) const {
    if (!m_image) {
        const Vec2 t = transform(uv);
        const float i = std::floor(m_cells * t.x), j = std::floor(m_cells * t.y);
        // (i + j) mod 2 without overflow for huge cells: parity of each floor.
        const bool odd =
            (std::fmod(std::fabs(i), 2.f) == 1.f) != (std::fmod(std::fabs(j), 2.f) == 1.f);
        return m_colors[odd ? 1 : 0];
    }
    return eval_image(uv, nullptr);
}

float Texture::mip_level(const UvFootprint& fp) const {
    if (!m_image) return 0.f;
    const Vec2 size(float(m_image->width), float(m_image->height));
    const Vec2 gx = size * (m_a * fp.duvdx), gy = size * (m_a * fp.duvdy);
    const float width = std::max(glm::dot(gx, gx), glm::dot(gy, gy));
    // log2 of the longer length; a zero or non-finite footprint reads level 0.
    return width > 0.f && std::isfinite(width) ? 0.5f * std::log2(width) : 0.f;
}

Rgb Texture::eval(Vec2 uv, const UvFootprint& fp) const {
    if (!m_image) return eval(uv);
    return eval_image(uv, &fp);
}

UvFootprint uv_footprint(const PixelFootprint& fp, const Vec3& dpdu, const Vec3& dpdv) {
    // Normal equations of the 3 x 2 system [dpdu dpdv] (du, dv) = dp, solved in double (the
    // determinant of nearly parallel derivatives cancels badly in float).
    const glm::dvec3 a(dpdu), b(dpdv);
    const double aa = glm::dot(a, a), ab = glm::dot(a, b), bb = glm::dot(b, b);
    const double det = aa * bb - ab * ab;
    if (!(det > 0.0) || !std::isfinite(det)) return {};
    auto solve = [&](const Vec3& dp) {
        const glm::dvec3 d(dp);
        const double ra = glm::dot(a, d), rb = glm::dot(b, d);
        const glm::dvec2 r((bb * ra - ab * rb) / det, (aa * rb - ab * ra) / det);
        // A huge (grazing) footprint is clamped far past any pyramid's last level.
        constexpr double kMaxDuv = 1e8;
        return std::isfinite(r.x) && std::isfinite(r.y)
                   ? Vec2(glm::clamp(r, glm::dvec2(-kMaxDuv), glm::dvec2(kMaxDuv)))
                   : Vec2(float(kMaxDuv));
    };
    return {solve(fp.dpdx), solve(fp.dpdy)};
}

UvFootprint Scene::texture_footprint(const SurfaceHit& hit, const Ray* camera_ray) const {
    const PixelFootprint fp = camera_ray
                                  ? m_camera.footprint(camera_ray->o, camera_ray->d, hit.p, hit.ng)
                                  : m_camera.footprint_at(hit.p, hit.ng);
    return uv_footprint(fp, hit.dpdu_uv, hit.dpdv_uv);
}

// Per-hit instantiation of a textured material (scene.h). The values are clamped into the
// textures' [min, max] ranges, which build_scene validated through the registry: bilinear
// weights can round a value one ulp past its neighbours.
Material Scene::material_at(const SurfaceHit& hit, const UvFootprint& fp) const {
    return textured_material(std::size_t(hit.textured), hit.uv, fp, hit.color);
}

Material Scene::textured_material(std::size_t index, Vec2 uv, const UvFootprint& fp,
                                  const glm::vec4& color) const {
    const TexturedMaterial& tm = m_textured[index];
    if (tm.diffuse_base) {
        // A textured diffuse reflectance alone: the base material with its diffuse lobe
        // replaced, the same bits as make_material gives. Composite leaves out a zero diffuse
        // lobe, so a black value takes the general path below.
        const TexturedMaterial::Slot& s = tm.slots[0];
        const Rgb v = glm::clamp(s.texture->eval(uv, fp, color), s.texture->min_value(),
                                 s.texture->max_value());
        if (tm.diffuse_black_ok || max_component(v) > 0.f)
            return tm.diffuse_base->with_diffuse_reflectance(v);
    }
    if (tm.staged) {
        // The staged build: the slots' values (through the conversion's sources) set the lobes.
        std::array<DVec3, TexturedMaterial::kMaxStaged> in, out;
        if (tm.convert_values) std::copy(tm.sources.begin(), tm.sources.end(), in.begin());
        for (std::size_t i = 0; i < tm.slots.size(); ++i) {
            const TexturedMaterial::Slot& s = tm.slots[i];
            const Rgb v = glm::clamp(s.texture->eval(uv, fp, color), s.texture->min_value(),
                                     s.texture->max_value());
            (tm.convert_values ? in[tm.slot_source[i]] : out[i]) =
                s.color ? DVec3(v) : DVec3(double(v.r));
        }
        if (tm.convert_values) tm.convert_values(in.data(), out.data());
        return tm.staged->at(std::span(out.data(), tm.num_staged));
    }
    return textured_material_rebuilt(index, uv, fp, color);
}

Material Scene::textured_material_rebuilt(std::size_t index, Vec2 uv, const UvFootprint& fp,
                                          const glm::vec4& color) const {
    const TexturedMaterial& tm = m_textured[index];
    ParamSet params = tm.params;
    for (const TexturedMaterial::Slot& s : tm.slots) {
        const Rgb v = glm::clamp(s.texture->eval(uv, fp, color), s.texture->min_value(),
                                 s.texture->max_value());
        params.set(s.name, s.color ? ParamValue(v) : ParamValue(double(v.r)));
    }
    // A combination's textured children are built at the same uv (one allocation each).
    std::array<std::shared_ptr<const Material>, 2> children;
    for (std::size_t k = 0; k < tm.children.size() && k < children.size(); ++k) {
        const TexturedMaterial::Child& c = tm.children[k];
        children[k] = c.textured >= 0 ? std::make_shared<const Material>(textured_material(
                                            std::size_t(c.textured), uv, fp, color))
                                      : c.constant;
    }
    try {
        return make_material(
            tm.model, tm.convert ? tm.convert(params) : params,
            std::span(children.data(), std::min(tm.children.size(), children.size())));
    } catch (const ParamError&) {
        // Unreachable after build_scene's checks; the render loop never throws.
        return Material(std::nullopt, std::nullopt, std::nullopt);
    }
}

}  // namespace facet::render
