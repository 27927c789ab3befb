// Texture kind "checker": two colours in alternating cells of the transformed UVs
// (conventions in facet/render/texture.h).
#include "facet/render/texture.h"
#include "texture_build.h"

#include <cmath>

namespace facet::render {

namespace {

class CheckerSource final : public TextureSource {
  public:
    std::array<Rgb, 2> m_colors{};  // times the texture's scale
    float m_cells = 1.f;
    glm::mat2 m_a{1.f};
    Vec2 m_b{0.f};

    Rgb eval(const TexturePoint& p) const override {
        const Vec2 t = m_a * p.uv + m_b;
        const float i = std::floor(m_cells * t.x), j = std::floor(m_cells * t.y);
        // (i + j) mod 2 without overflow for huge cells: parity of each floor.
        const bool odd =
            (std::fmod(std::fabs(i), 2.f) == 1.f) != (std::fmod(std::fabs(j), 2.f) == 1.f);
        return m_colors[odd ? 1 : 0];
    }
};

Texture build_checker(TextureBuild& b) {
    const TextureDesc& d = b.desc;
    const std::string cp = b.ptr + "/checker";
    for (int i = 0; i < 2; ++i)
        b.check_color(d.colors[std::size_t(i)], cp + "/colors/" + std::to_string(i),
                      "a checker colour");
    if (!b.color && (d.colors[0].r != d.colors[0].g || d.colors[0].r != d.colors[0].b ||
                     d.colors[1].r != d.colors[1].g || d.colors[1].r != d.colors[1].b))
        b.fail(cp + "/colors", "a number parameter needs grey (single-number) colours");
    b.check_range(d.checker_scale, cp + "/scale", 1e-30, 1e30, "> 0");
    return Texture::checker(d);
}

}  // namespace

Texture Texture::checker(const TextureDesc& d) {
    auto s = std::make_shared<CheckerSource>();
    const Rgb scale = float(d.scale) * d.color_scale;
    s->m_colors = {d.colors[0] * scale, d.colors[1] * scale};
    s->m_cells = float(d.checker_scale);
    uv_transform(d, s->m_a, s->m_b);
    Rgb lo = glm::min(s->m_colors[0], s->m_colors[1]);
    const Rgb hi = glm::max(s->m_colors[0], s->m_colors[1]);
    if (d.times_vertex_color) lo = Rgb(0.f);
    return Texture(std::move(s), lo, hi, kTextureReadsUv, d.times_vertex_color);
}

const TextureKindDef kCheckerTexture{
    "checker",
    "two colours in alternating cells of the UVs: `{\"checker\": {\"colors\": [c0, c1], "
    "\"scale\": n}}`",
    {},
    false,
    build_checker,
};

}  // namespace facet::render
