// Texture kind "vertex_color": the hit's interpolated vertex colour (conventions in
// facet/render/texture.h).
#include "facet/render/texture.h"
#include "texture_build.h"

namespace facet::render {

namespace {

class VertexColorSource final : public TextureSource {
  public:
    int m_channel = Texture::kAllChannels;
    Rgb m_scale{1.f};

    Rgb eval(const TexturePoint& p) const override {
        const Rgb rgb(p.color);
        if (m_channel == Texture::kAllChannels) return rgb * m_scale;
        const float v = m_channel == Texture::kLuminance
                            ? 0.2126f * rgb.r + 0.7152f * rgb.g + 0.0722f * rgb.b
                            : p.color[m_channel];
        return Rgb(v) * m_scale;
    }
};

Texture build_vertex_color(TextureBuild& b) {
    // No image, no UVs; `channel` as for images.
    int channel = Texture::kAllChannels;
    if (!b.desc.channel.empty()) {
        channel = b.choose("channel", b.desc.channel, {"r", "g", "b", "a", "luminance"});
    } else if (!b.color) {
        b.fail(b.ptr + "/channel",
               "a number parameter reads one channel: give \"channel\" (r, g, b, a or "
               "luminance) for the vertex colour");
    }
    return Texture::vertex_color(b.desc, channel);
}

}  // namespace

Texture Texture::vertex_color(const TextureDesc& d, int channel) {
    auto s = std::make_shared<VertexColorSource>();
    s->m_channel = channel;
    s->m_scale = float(d.scale) * d.color_scale;
    const Rgb hi = channel == kAllChannels ? s->m_scale : Rgb(s->m_scale.r);
    return Texture(std::move(s), Rgb(0.f), hi, kTextureReadsColor);
}

const TextureKindDef kVertexColorTexture{
    "vertex_color",
    "the mesh's interpolated vertex colour: `{\"vertex_color\": true, \"channel\": ...}`",
    {},
    false,
    build_vertex_color,
};

}  // namespace facet::render
