// Texture kind "brick": Blender 3.4's Brick Texture node (Cycles' svm_brick), at the point p
// (procedural.h) times Scale. Rows of height row_height: row r = floor(p.y / row_height); in
// rows with r mod squash_frequency = 0 the bricks are squash times as wide, and rows with
// r mod offset_frequency = 0 are shifted by offset times the (squashed) brick width (mod as
// C's %, so negative rows count from -1). Brick k = floor((p.x + shift) / width); (x, y) the
// point inside its brick. Each brick's tint is Cycles' integer hash of (r << 16) + (k & 0xffff)
// in [0, 1), plus bias, clamped to [0, 1]. d = the distance to the nearest brick edge; mortar
// f = 0 for d >= mortar_size, else 1 when mortar_smooth = 0, else smoothstep(s / mortar_smooth)
// (s = 1 - d / mortar_size; 1 once s >= mortar_smooth). Color = mix(mix(color1, color2, tint),
// mortar, f); Fac = f. Color1, Color2 and Mortar are constants or textures evaluated at the same
// hit (composite.h's inputs; Cycles evaluates the linked nodes at the shading point).
#include <cmath>
#include <cstdint>

#include "composite.h"

namespace facet::render {

namespace {

// Cycles' brick_noise: a fast integer hash in [0, 1).
float brick_noise(std::uint32_t n) {
    n = (n + 1013u) & 0x7fffffffu;
    n = (n >> 13) ^ n;
    const std::uint32_t nn = (n * (n * n * 60493u + 19990303u) + 1376312589u) & 0x7fffffffu;
    return 0.5f * (float(nn) / 1073741824.f);
}

class BrickSource final : public ProceduralSource {
  public:
    float m_scale_in = 5.f, m_mortar_size = 0.02f, m_mortar_smooth = 0.1f, m_bias = 0.f;
    float m_width = 0.5f, m_row_height = 0.25f, m_offset = 0.5f, m_squash = 1.f;
    int m_offset_frequency = 2, m_squash_frequency = 2;
    Rgb m_color1{0.8f}, m_color2{0.2f}, m_mortar{0.f};
    bool m_color = false;
    // Textured colours (any: the colours are read per hit by eval).
    std::optional<CompositeInput> m_in1, m_in2, m_in_mortar;

    Rgb eval(const TexturePoint& p) const override {
        if (!m_in1) return pattern(point(p)) * m_scale;
        return colored(point(p), m_in1->eval(p), m_in2->eval(p), m_in_mortar->eval(p)) * m_scale;
    }
    Rgb pattern(const Vec3& xin) const override {
        return colored(xin, m_color1, m_color2, m_mortar);
    }
    Rgb colored(const Vec3& xin, const Rgb& color1, const Rgb& color2, const Rgb& mortar) const {
        const Vec3 p = xin * m_scale_in;
        const int row = int(std::floor(p.y / m_row_height));
        float width = m_width, shift = 0.f;
        if (m_offset_frequency && m_squash_frequency) {
            width *= (row % m_squash_frequency) ? 1.f : m_squash;
            shift = (row % m_offset_frequency) ? 0.f : width * m_offset;
        }
        const int brick = int(std::floor((p.x + shift) / width));
        const float x = (p.x + shift) - width * float(brick);
        const float y = p.y - m_row_height * float(row);
        const float tint = std::clamp(
            brick_noise((std::uint32_t(row) << 16) + std::uint32_t(brick & 0xffff)) + m_bias, 0.f,
            1.f);
        float d = std::fmin(std::fmin(x, y), std::fmin(width - x, m_row_height - y));
        float f;
        if (d >= m_mortar_size) {
            f = 0.f;
        } else if (m_mortar_smooth == 0.f) {
            f = 1.f;
        } else {
            d = 1.f - d / m_mortar_size;
            if (d < m_mortar_smooth) {
                const float s = d / m_mortar_smooth, s2 = s * s;
                f = 3.f * s2 - 2.f * s2 * s;
            } else {
                f = 1.f;
            }
        }
        if (!m_color) return Rgb(f);
        Rgb c = color1;
        if (f != 1.f) c = (1.f - tint) * color1 + tint * color2;
        return c * (1.f - f) + mortar * f;
    }
};

Texture build_brick(TextureBuild& b) {
    auto s = std::make_shared<BrickSource>();
    const ProceduralParams p(b, kBrickTexture);
    check_texture_params(b, kBrickTexture);
    s->m_scale_in = float(p.number("scale"));
    s->m_mortar_size = float(p.number("mortar_size"));
    s->m_mortar_smooth = float(p.number("mortar_smooth"));
    s->m_bias = float(p.number("bias"));
    s->m_width = float(p.number("brick_width"));
    s->m_row_height = float(p.number("row_height"));
    s->m_offset = float(p.number("offset"));
    s->m_squash = float(p.number("squash"));
    s->m_offset_frequency = int(p.number("offset_frequency"));
    s->m_squash_frequency = int(p.number("squash_frequency"));
    s->m_color = p.choice("output") == 1;
    if (!s->m_color) {
        if (!b.desc.inputs.empty())
            b.fail(p.pointer(b.desc.inputs.front().name),
                   "the Fac output reads no colour: a texture here is unused");
        return make_procedural(b, kBrickTexture, s, Rgb(0.f), Rgb(1.f));
    }
    const CompositeParams in(b, kBrickTexture);
    CompositeInput c1 = in.input("color1", true), c2 = in.input("color2", true),
                   cm = in.input("mortar", true);
    s->m_color1 = c1.m_constant;
    s->m_color2 = c2.m_constant;
    s->m_mortar = cm.m_constant;
    // Convex combinations of the three colours.
    const Rgb lo = glm::min(glm::min(c1.m_lo, c2.m_lo), cm.m_lo);
    const Rgb hi = glm::max(glm::max(c1.m_hi, c2.m_hi), cm.m_hi);
    if (c1.is_constant() && c2.is_constant() && cm.is_constant())
        return make_procedural(b, kBrickTexture, s, lo, hi);
    s->m_in1 = std::move(c1);
    s->m_in2 = std::move(c2);
    s->m_in_mortar = std::move(cm);
    return make_procedural(b, kBrickTexture, s, lo, hi, in.reads());
}

}  // namespace

const TextureKindDef kBrickTexture{
    "brick",
    "Blender's Brick Texture (Cycles 3.4): offset rows of bricks with a tint per brick and "
    "mortar between",
    {
        {"scale", ParamType::Number, 5, {}, -1e30, 1e30, false, {}, "Scale"},
        {"offset", ParamType::Number, 0.5, {}, 0, 1, false, {}, "Offset (of every n-th row)"},
        {"offset_frequency", ParamType::Number, 2, {}, 1, 99, true, {}, "Offset's Frequency"},
        {"squash", ParamType::Number, 1, {}, 0, 99, false, {}, "Squash (of every n-th row)"},
        {"squash_frequency", ParamType::Number, 2, {}, 1, 99, true, {}, "Squash's Frequency"},
        {"mortar_size", ParamType::Number, 0.02, {}, 0, 0.125, false, {}, "Mortar Size"},
        {"mortar_smooth", ParamType::Number, 0.1, {}, 0, 1, false, {}, "Mortar Smooth"},
        {"bias", ParamType::Number, 0, {}, -1, 1, false, {}, "Bias (of the tint)"},
        {"brick_width", ParamType::Number, 0.5, {}, 0.01, 100, false, {}, "Brick Width"},
        {"row_height", ParamType::Number, 0.25, {}, 0.01, 100, false, {}, "Row Height"},
        {"color1",
         ParamType::Color,
         0,
         {},
         0,
         0,
         false,
         {},
         "Color1 (default grey 0.8; a texture: Color output only)",
         TextureParamForm::Input,
         Rgb(0.8f)},
        {"color2",
         ParamType::Color,
         0,
         {},
         0,
         0,
         false,
         {},
         "Color2 (default grey 0.2; a texture: Color output only)",
         TextureParamForm::Input,
         Rgb(0.2f)},
        {"mortar",
         ParamType::Color,
         0,
         {},
         0,
         0,
         false,
         {},
         "Mortar colour (default black; a texture: Color output only)",
         TextureParamForm::Input,
         Rgb(0.f)},
        {"output", ParamType::String, 0, "fac", 0, 0, false, {"fac", "color"}, kOutputDoc},
    },
    true,
    build_brick,
};

}  // namespace facet::render
