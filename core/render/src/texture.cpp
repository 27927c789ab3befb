// Textures evaluated at UV coordinates (conventions in facet/render/texture.h).
#include "facet/render/texture.h"

#include "facet/render/scene.h"

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
                       TextureWrap wrap, int channel, const TextureDesc& d) {
    Texture t;
    t.m_image = std::move(img);
    t.m_filter = filter;
    t.m_wrap = wrap;
    t.m_channel = channel;
    t.m_scale = float(d.scale);
    set_transform(d, t.m_a, t.m_b);
    const TexelImage& im = *t.m_image;
    t.m_min = Rgb(INFINITY);
    t.m_max = Rgb(-INFINITY);
    for (int y = 0; y < im.height; ++y) {
        for (int x = 0; x < im.width; ++x) {
            const Rgb v = t.texel(x, y);
            t.m_min = glm::min(t.m_min, v);
            t.m_max = glm::max(t.m_max, v);
        }
    }
    return t;
}

Texture Texture::checker(const TextureDesc& d) {
    Texture t;
    t.m_colors = {d.colors[0] * float(d.scale), d.colors[1] * float(d.scale)};
    t.m_cells = float(d.checker_scale);
    t.m_scale = float(d.scale);
    set_transform(d, t.m_a, t.m_b);
    t.m_min = glm::min(t.m_colors[0], t.m_colors[1]);
    t.m_max = glm::max(t.m_colors[0], t.m_colors[1]);
    return t;
}

Vec2 Texture::transform(Vec2 uv) const {
    return m_a * uv + m_b;
}

// Texel (x, y) (indices already wrapped) as the texture's value, times scale.
Rgb Texture::texel(int x, int y) const {
    const TexelImage& im = *m_image;
    const float* p = &im.texels[(std::size_t(y) * std::size_t(im.width) + std::size_t(x)) *
                                std::size_t(im.channels)];
    Rgb c;
    if (m_channel == kAllChannels) {
        c = im.channels >= 3 ? Rgb(p[0], p[1], p[2]) : Rgb(p[0]);
    } else if (m_channel == kLuminance) {
        c = Rgb(im.channels >= 3 ? luminance(Rgb(p[0], p[1], p[2])) : p[0]);
    } else {
        c = Rgb(p[m_channel]);
    }
    return c * m_scale;
}

Rgb Texture::eval(Vec2 uv) const {
    const Vec2 t = transform(uv);
    if (!m_image) {
        const float i = std::floor(m_cells * t.x), j = std::floor(m_cells * t.y);
        // (i + j) mod 2 without overflow for huge cells: parity of each floor.
        const bool odd =
            (std::fmod(std::fabs(i), 2.f) == 1.f) != (std::fmod(std::fabs(j), 2.f) == 1.f);
        return m_colors[odd ? 1 : 0];
    }
    const TexelImage& im = *m_image;
    // Continuous texel coordinates: x right from the left edge, y down from the top edge.
    const float fx = t.x * float(im.width), fy = (1.f - t.y) * float(im.height);
    auto index = [](float f) {
        // Clamp before converting: uv far outside any image must not overflow int.
        return int(std::floor(std::clamp(f, -1e9f, 1e9f)));
    };
    if (m_filter == TextureFilter::Closest) {
        return texel(wrap_index(index(fx), im.width, m_wrap),
                     wrap_index(index(fy), im.height, m_wrap));
    }
    // Bilinear between the texel centres around (fx, fy).
    const float gx = fx - 0.5f, gy = fy - 0.5f;
    const int x0 = index(gx), y0 = index(gy);
    const float ax = gx - float(x0), ay = gy - float(y0);
    const int xa = wrap_index(x0, im.width, m_wrap), xb = wrap_index(x0 + 1, im.width, m_wrap);
    const int ya = wrap_index(y0, im.height, m_wrap), yb = wrap_index(y0 + 1, im.height, m_wrap);
    return (1.f - ay) * ((1.f - ax) * texel(xa, ya) + ax * texel(xb, ya)) +
           ay * ((1.f - ax) * texel(xa, yb) + ax * texel(xb, yb));
}

// Per-hit instantiation of a textured material (scene.h). The values are clamped into the
// textures' [min, max] ranges, which build_scene validated through the registry: bilinear
// weights can round a value one ulp past its neighbours.
Material Scene::material_at(const SurfaceHit& hit) const {
    return textured_material(std::size_t(hit.textured), hit.uv);
}

Material Scene::textured_material(std::size_t index, Vec2 uv) const {
    const TexturedMaterial& tm = m_textured[index];
    ParamSet params = tm.params;
    for (const TexturedMaterial::Slot& s : tm.slots) {
        const Rgb v =
            glm::clamp(s.texture->eval(uv), s.texture->min_value(), s.texture->max_value());
        params.set(s.name, s.color ? ParamValue(v) : ParamValue(double(v.r)));
    }
    // A combination's textured children are built at the same uv (one allocation each).
    std::array<std::shared_ptr<const Material>, 2> children;
    for (std::size_t k = 0; k < tm.children.size() && k < children.size(); ++k) {
        const TexturedMaterial::Child& c = tm.children[k];
        children[k] =
            c.textured >= 0
                ? std::make_shared<const Material>(textured_material(std::size_t(c.textured), uv))
                : c.constant;
    }
    try {
        return make_material(
            tm.model, params,
            std::span(children.data(), std::min(tm.children.size(), children.size())));
    } catch (const ParamError&) {
        // Unreachable after build_scene's checks; the render loop never throws.
        return Material(std::nullopt, std::nullopt, std::nullopt);
    }
}

}  // namespace facet::render
