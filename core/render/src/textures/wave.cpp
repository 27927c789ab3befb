// Texture kind "wave": Blender 3.4's Wave Texture node (Cycles' svm_wave). At the point p
// (procedural.h) times Scale, nudged as Cycles does against integer coordinates,
// p <- (p + 1e-6) 0.999999:
//  - bands: n = 20 p.x (or p.y, p.z), diagonal 10 (p.x + p.y + p.z);
//  - rings: n = 20 |p| with the direction's axis zeroed (x, y, z), spherical 20 |p|;
// n += Phase Offset, plus Distortion (2 fBm(Detail Scale p, Detail, Detail Roughness) - 1)
// (cycles_noise.h) when Distortion != 0; profile sin: 1/2 + 1/2 sin(n - pi/2), saw:
// frac(n / 2 pi), tri: 2 |n / 2 pi - floor(n / 2 pi + 1/2)|. Fac and Color are that value
// (grey), in [0, 1].
#include "cycles_noise.h"
#include "procedural.h"

#include <cmath>

namespace facet::render {

namespace {

class WaveSource final : public ProceduralSource {
  public:
    int m_type = 0, m_direction = 0, m_profile = 0;  // bands/rings; x y z diagonal|spherical
    float m_scale_in = 5.f, m_distortion = 0.f, m_detail = 2.f, m_detail_scale = 1.f,
          m_detail_roughness = 0.5f, m_phase = 0.f;

    Rgb pattern(const Vec3& x) const override {
        const cycles::vec3 p = (cycles::vec3(x * m_scale_in) + 0.000001f) * 0.999999f;
        float n;
        if (m_type == 0) {
            n = m_direction == 0   ? p.x * 20.f
                : m_direction == 1 ? p.y * 20.f
                : m_direction == 2 ? p.z * 20.f
                                   : (p.x + p.y + p.z) * 10.f;
        } else {
            cycles::vec3 r = p;
            if (m_direction < 3) r[m_direction] = 0.f;
            n = std::sqrt(r.x * r.x + r.y * r.y + r.z * r.z) * 20.f;
        }
        n += m_phase;
        if (m_distortion != 0.f)
            n += m_distortion *
                 (cycles::fractal_noise(p * m_detail_scale, m_detail, m_detail_roughness) * 2.f -
                  1.f);
        constexpr float k2Pi = 6.28318530717958647692f, kHalfPi = 1.57079632679489661923f;
        float v;
        if (m_profile == 0) {
            v = 0.5f + 0.5f * std::sin(n - kHalfPi);
        } else if (m_profile == 1) {
            n /= k2Pi;
            v = n - std::floor(n);
        } else {
            n /= k2Pi;
            v = std::fabs(n - std::floor(n + 0.5f)) * 2.f;
        }
        return Rgb(v);
    }
};

Texture build_wave(TextureBuild& b) {
    auto s = std::make_shared<WaveSource>();
    Texture t = make_procedural(b, kWaveTexture, s, Rgb(0.f), Rgb(1.f));
    const ProceduralParams p(b, kWaveTexture);
    s->m_type = p.choice("type");
    s->m_direction = p.choice(s->m_type == 0 ? "bands_direction" : "rings_direction");
    s->m_profile = p.choice("profile");
    s->m_scale_in = float(p.number("scale"));
    s->m_distortion = float(p.number("distortion"));
    s->m_detail = float(p.number("detail"));
    s->m_detail_scale = float(p.number("detail_scale"));
    s->m_detail_roughness = float(p.number("detail_roughness"));
    s->m_phase = float(p.number("phase"));
    return t;
}

}  // namespace

const TextureKindDef kWaveTexture{
    "wave",
    "Blender's Wave Texture: bands or rings, in [0, 1] (Cycles 3.4)",
    {
        {"type", ParamType::String, 0, "bands", 0, 0, false, {"bands", "rings"}, "Type"},
        {"bands_direction",
         ParamType::String,
         0,
         "x",
         0,
         0,
         false,
         {"x", "y", "z", "diagonal"},
         "bands' direction"},
        {"rings_direction",
         ParamType::String,
         0,
         "x",
         0,
         0,
         false,
         {"x", "y", "z", "spherical"},
         "rings' direction"},
        {"profile", ParamType::String, 0, "sin", 0, 0, false, {"sin", "saw", "tri"}, "Profile"},
        {"scale", ParamType::Number, 5, {}, -1e30, 1e30, false, {}, "Scale"},
        {"distortion", ParamType::Number, 0, {}, -1e30, 1e30, false, {}, "Distortion"},
        {"detail", ParamType::Number, 2, {}, 0, 15, false, {}, "Detail"},
        {"detail_scale", ParamType::Number, 1, {}, -1e30, 1e30, false, {}, "Detail Scale"},
        {"detail_roughness", ParamType::Number, 0.5, {}, 0, 1, false, {}, "Detail Roughness"},
        {"phase", ParamType::Number, 0, {}, -1e30, 1e30, false, {}, "Phase Offset"},
        {"output", ParamType::String, 0, "fac", 0, 0, false, {"fac", "color"}, kOutputDoc},
    },
    true,
    build_wave,
    false,
    true,
};

}  // namespace facet::render
