// Texture kind "white_noise": Blender 3.4's White Noise Texture node: the hash of the point's
// float bits (cycles_noise.h) in 1-4 dimensions, W the 4th (or in 1D the only) coordinate.
// Value: hash_floatN_to_float; Color: hash_floatN_to_float3. No scale: the point is used as is.
#include "cycles_noise.h"
#include "procedural.h"

namespace facet::render {

namespace {

using cycles::vec2;
using cycles::vec3;
using cycles::vec4;

class WhiteNoiseSource final : public ProceduralSource {
  public:
    int m_dimensions = 3;
    float m_w = 0.f;
    bool m_color = false;

    template <class P>
    Rgb at(P p) const {
        if (!m_color) return Rgb(cycles::hash_float(p));
        return Rgb(cycles::hash_vec3(p));
    }
    Rgb pattern(const Vec3& x) const override {
        switch (m_dimensions) {
            case 1:
                return at(m_w);
            case 2:
                return at(vec2(x.x, x.y));
            case 4:
                return at(vec4(x.x, x.y, x.z, m_w));
            default:
                return at(vec3(x));
        }
    }
};

Texture build_white_noise(TextureBuild& b) {
    auto s = std::make_shared<WhiteNoiseSource>();
    Texture t = make_procedural(b, kWhiteNoiseTexture, s, Rgb(0.f), Rgb(1.f));
    const ProceduralParams p(b, kWhiteNoiseTexture);
    s->m_dimensions = int(p.number("dimensions"));
    s->m_w = float(p.number("w"));
    s->m_color = p.choice("output") == 1;
    return t;
}

}  // namespace

const TextureKindDef kWhiteNoiseTexture{
    "white_noise",
    "Blender's White Noise Texture: a hash of the point, in [0, 1]",
    {
        {"dimensions", ParamType::Number, 3, {}, 1, 4, true, {}, "1, 2, 3 or 4 (W the 4th)"},
        {"w", ParamType::Number, 0, {}, -1e30, 1e30, false, {}, "W (1D and 4D)"},
        {"output", ParamType::String, 0, "value", 0, 0, false, {"value", "color"}, kOutputDoc},
    },
    true,
    build_white_noise,
};

}  // namespace facet::render
