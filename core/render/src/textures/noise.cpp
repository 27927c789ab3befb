// Texture kind "noise": Blender 3.4's Noise Texture node (Cycles' node_noise_texture): fBm of
// Perlin noise (cycles_noise.h) in 1-4 dimensions with Detail, Roughness and Distortion.
//
// At the point x (procedural.h) scaled by Scale, with w = W x Scale the 4th (or, in 1D, the
// only) coordinate: with Distortion d != 0 the point moves by d times signed noise at the point
// plus seeded offsets o_0..o_{n-1} (one per dimension n); Fac = fBm(point, Detail, Roughness);
// Color = (Fac, fBm(point + o_n), fBm(point + o_{n+1})). The offsets are Cycles'
// random_float*_offset: 100 + 100 hash(seed, component).
#include "cycles_noise.h"
#include "procedural.h"

namespace facet::render {

namespace {

using cycles::vec2;
using cycles::vec3;
using cycles::vec4;

float offset1(float seed) {
    return 100.f + cycles::hash_float(seed) * 100.f;
}
float offset_c(float seed, float c) {
    return 100.f + cycles::hash_float(vec2(seed, c)) * 100.f;
}
vec2 offset2(float seed) {
    return {offset_c(seed, 0.f), offset_c(seed, 1.f)};
}
vec3 offset3(float seed) {
    return {offset_c(seed, 0.f), offset_c(seed, 1.f), offset_c(seed, 2.f)};
}
vec4 offset4(float seed) {
    return {offset_c(seed, 0.f), offset_c(seed, 1.f), offset_c(seed, 2.f), offset_c(seed, 3.f)};
}

class NoiseSource final : public ProceduralSource {
  public:
    int m_dimensions = 3;
    float m_scale_in = 5.f, m_detail = 2.f, m_roughness = 0.5f, m_distortion = 0.f, m_w = 0.f;
    bool m_color = false;

    template <class P>
    Rgb texture(P p, P (*offset)(float), int n) const {
        if (m_distortion != 0.f) {
            P r;
            for (int i = 0; i < n; ++i) r[i] = cycles::snoise(p + offset(float(i))) * m_distortion;
            p += r;
        }
        const float fac = cycles::fractal_noise(p, m_detail, m_roughness);
        if (!m_color) return Rgb(fac);
        return {fac, cycles::fractal_noise(p + offset(float(n)), m_detail, m_roughness),
                cycles::fractal_noise(p + offset(float(n + 1)), m_detail, m_roughness)};
    }

    Rgb pattern(const Vec3& x) const override {
        const Vec3 v = x * m_scale_in;
        const float w = m_w * m_scale_in;
        switch (m_dimensions) {
            case 1: {
                float p = w;
                if (m_distortion != 0.f) p += cycles::snoise(p + offset1(0.f)) * m_distortion;
                const float fac = cycles::fractal_noise(p, m_detail, m_roughness);
                if (!m_color) return Rgb(fac);
                return {fac, cycles::fractal_noise(p + offset1(1.f), m_detail, m_roughness),
                        cycles::fractal_noise(p + offset1(2.f), m_detail, m_roughness)};
            }
            case 2:
                return texture(vec2(v.x, v.y), offset2, 2);
            case 4:
                return texture(vec4(v.x, v.y, v.z, w), offset4, 4);
            default:
                return texture(vec3(v), offset3, 3);
        }
    }
};

Texture build_noise(TextureBuild& b) {
    auto s = std::make_shared<NoiseSource>();
    const ProceduralParams p(b, kNoiseTexture);
    Texture t = make_procedural(b, kNoiseTexture, s, Rgb(0.f), Rgb(1.f));
    s->m_dimensions = int(p.number("dimensions"));
    s->m_scale_in = float(p.number("scale"));
    s->m_detail = float(p.number("detail"));
    s->m_roughness = float(p.number("roughness"));
    s->m_distortion = float(p.number("distortion"));
    s->m_w = float(p.number("w"));
    s->m_color = p.choice("output") == 1;
    return t;
}

}  // namespace

// Fac and the colour's channels are fBm values, each in [0, 1] up to the few percent by which
// Perlin noise's scaled extremes exceed +-1 (the range validation reads [0, 1]).
const TextureKindDef kNoiseTexture{
    "noise",
    "Blender's Noise Texture: fBm of Perlin noise (Cycles 3.4)",
    {
        {"dimensions", ParamType::Number, 3, {}, 1, 4, true, {}, "1, 2, 3 or 4 (W the 4th)"},
        {"scale", ParamType::Number, 5, {}, -1e30, 1e30, false, {}, "Scale"},
        {"detail", ParamType::Number, 2, {}, 0, 15, false, {}, "Detail (octaves - 1)"},
        {"roughness", ParamType::Number, 0.5, {}, 0, 1, false, {}, "Roughness"},
        {"distortion", ParamType::Number, 0, {}, -1e30, 1e30, false, {}, "Distortion"},
        {"w", ParamType::Number, 0, {}, -1e30, 1e30, false, {}, "W (1D and 4D)"},
        {"output", ParamType::String, 0, "fac", 0, 0, false, {"fac", "color"}, kOutputDoc},
    },
    true,
    build_noise,
};

}  // namespace facet::render
