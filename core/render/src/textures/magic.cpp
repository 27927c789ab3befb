// Texture kind "magic": Blender 3.4's Magic Texture node (Cycles' svm_magic): at the point p
// (procedural.h) times Scale, x = sin(5 (p.x + p.y + p.z)), y = cos(5 (-p.x + p.y - p.z)),
// z = -cos(5 (-p.x - p.y + p.z)), then for Depth > 0 up to 10 nested turbulence steps, each
// a sine or cosine of a signed sum of x, y, z times Distortion (Cycles' sequence); the colour
// is 1/2 - (x, y, z) / (2 Distortion) (Distortion != 0), Fac its mean.
#include "procedural.h"

#include <cmath>

namespace facet::render {

namespace {

class MagicSource final : public ProceduralSource {
  public:
    int m_depth = 2;
    float m_scale_in = 5.f, m_distortion = 1.f;
    bool m_color = false;

    Rgb pattern(const Vec3& xin) const override {
        const Vec3 p = xin * m_scale_in;
        const int n = m_depth;
        const float d = m_distortion;
        float x = std::sin((p.x + p.y + p.z) * 5.f);
        float y = std::cos((-p.x + p.y - p.z) * 5.f);
        float z = -std::cos((-p.x - p.y + p.z) * 5.f);
        if (n > 0) {
            x *= d, y *= d, z *= d;
            y = -std::cos(x - y + z) * d;
            if (n > 1) {
                x = std::cos(x - y - z) * d;
                if (n > 2) {
                    z = std::sin(-x - y - z) * d;
                    if (n > 3) {
                        x = -std::cos(-x + y - z) * d;
                        if (n > 4) {
                            y = -std::sin(-x + y + z) * d;
                            if (n > 5) {
                                y = -std::cos(-x + y + z) * d;
                                if (n > 6) {
                                    x = std::cos(x + y + z) * d;
                                    if (n > 7) {
                                        z = std::sin(x + y - z) * d;
                                        if (n > 8) {
                                            x = -std::cos(-x - y + z) * d;
                                            if (n > 9) y = -std::sin(x - y + z) * d;
                                        }
                                    }
                                }
                            }
                        }
                    }
                }
            }
        }
        if (d != 0.f) {
            const float d2 = d * 2.f;
            x /= d2, y /= d2, z /= d2;
        }
        const Rgb c(0.5f - x, 0.5f - y, 0.5f - z);
        return m_color ? c : Rgb((c.r + c.g + c.b) * (1.f / 3.f));
    }
};

Texture build_magic(TextureBuild& b) {
    auto s = std::make_shared<MagicSource>();
    const ProceduralParams p(b, kMagicTexture);
    make_procedural(b, kMagicTexture, s, Rgb(0.f), Rgb(1.f));  // validates
    s->m_depth = int(p.number("depth"));
    s->m_scale_in = float(p.number("scale"));
    s->m_distortion = float(p.number("distortion"));
    s->m_color = p.choice("output") == 1;
    // |x|, |y|, |z| <= |Distortion| after a turbulence step (or 1 before): the colour lies in
    // 1/2 -+ max(1, |d|) / (2 |d|) (d != 0; 1/2 -+ 1 when d = 0).
    const double d = std::fabs(double(s->m_distortion));
    const double half = d > 0.0 ? std::max(1.0, d) / (2.0 * d) : 1.0;
    return make_procedural(b, kMagicTexture, s, Rgb(float(0.5 - half)), Rgb(float(0.5 + half)));
}

}  // namespace

const TextureKindDef kMagicTexture{
    "magic",
    "Blender's Magic Texture: nested sines and cosines (Cycles 3.4)",
    {
        {"depth", ParamType::Number, 2, {}, 0, 10, true, {}, "Depth"},
        {"scale", ParamType::Number, 5, {}, -1e30, 1e30, false, {}, "Scale"},
        {"distortion", ParamType::Number, 1, {}, -1e30, 1e30, false, {}, "Distortion"},
        {"output", ParamType::String, 0, "fac", 0, 0, false, {"fac", "color"}, kOutputDoc},
    },
    true,
    build_magic,
};

}  // namespace facet::render
