// Texture kind "gradient": Blender 3.4's Gradient Texture node (Cycles' svm_gradient), of the
// point p: linear p.x; quadratic max(p.x, 0)^2; easing 3 t^2 - 2 t^3 of t = clamp(p.x, 0, 1);
// diagonal (p.x + p.y) / 2; radial atan2(p.y, p.x) / 2 pi + 1/2; quadratic_sphere
// max(1 - |p|, 0)^2; spherical max(1 - |p|, 0). Fac and Color are the value clamped to [0, 1]
// (grey).
#include "procedural.h"

#include <algorithm>
#include <cmath>

namespace facet::render {

namespace {

enum class GradientType { Linear, Quadratic, Easing, Diagonal, Radial, QuadraticSphere, Spherical };

class GradientSource final : public ProceduralSource {
  public:
    GradientType m_type = GradientType::Linear;

    Rgb pattern(const Vec3& p) const override {
        float f = 0.f;
        switch (m_type) {
            case GradientType::Linear:
                f = p.x;
                break;
            case GradientType::Quadratic: {
                const float r = std::fmax(p.x, 0.f);
                f = r * r;
                break;
            }
            case GradientType::Easing: {
                const float r = std::fmin(std::fmax(p.x, 0.f), 1.f);
                const float t = r * r;
                f = 3.f * t - 2.f * t * r;
                break;
            }
            case GradientType::Diagonal:
                f = (p.x + p.y) * 0.5f;
                break;
            case GradientType::Radial:
                f = std::atan2(p.y, p.x) / (2.f * 3.14159265358979323846f) + 0.5f;
                break;
            case GradientType::QuadraticSphere: {
                const float r = std::fmax(0.f, 1.f - std::sqrt(p.x * p.x + p.y * p.y + p.z * p.z));
                f = r * r;
                break;
            }
            case GradientType::Spherical:
                f = std::fmax(0.f, 1.f - std::sqrt(p.x * p.x + p.y * p.y + p.z * p.z));
                break;
        }
        return Rgb(std::clamp(f, 0.f, 1.f));
    }
};

Texture build_gradient(TextureBuild& b) {
    auto s = std::make_shared<GradientSource>();
    Texture t = make_procedural(b, kGradientTexture, s, Rgb(0.f), Rgb(1.f));
    s->m_type = GradientType(ProceduralParams(b, kGradientTexture).choice("type"));
    return t;
}

}  // namespace

const TextureKindDef kGradientTexture{
    "gradient",
    "Blender's Gradient Texture, in [0, 1]",
    {
        {"type",
         ParamType::String,
         0,
         "linear",
         0,
         0,
         false,
         {"linear", "quadratic", "easing", "diagonal", "radial", "quadratic_sphere", "spherical"},
         "the gradient's type"},
        {"output", ParamType::String, 0, "fac", 0, 0, false, {"fac", "color"}, kOutputDoc},
    },
    true,
    build_gradient,
    false,
    true,
};

}  // namespace facet::render
