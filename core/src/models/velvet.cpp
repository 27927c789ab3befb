// velvet: Blender's Velvet BSDF as Cycles 3.4 evaluates it (bsdf_ashikhmin_velvet, after
// Ashikhmin et al. 2000's cloth distribution), a microfacet form without Fresnel:
//   f(wo, wi) = D G / (4 cos_o cos_i),
//   D = exp(-cot^2 theta_h / sigma^2) / (pi sigma^2 sin^4 theta_h),   sigma = max(Sigma, 0.01),
//   G = min(1, 2 cos theta_h cos_o / |wo.h|, 2 cos theta_h cos_i / |wo.h|),
// with h the half vector, times the colour. Reflection only; zero where |cos theta_h| >= 1 - 1e-5
// or |wo.h| <= 1e-5, as Cycles. Symmetric in wo and wi (|wo.h| = |wi.h|): reciprocal. Sampled
// as Cycles does, uniformly over the hemisphere (pdf 1 / (2 pi)). Not energy conserving by
// construction: the albedo is whatever Cycles' closure reflects (tests/core/test_new_models.cpp
// prints it).
// Conventions: facet/inline_bxdf.h.
#include "facet/sampling.h"
#include "model_unit.h"

namespace facet {

namespace {

class VelvetReflection {
  public:
    VelvetReflection(const Rgb& color, float sigma) : m_color(color) {
        const float s = std::max(sigma, 0.01f);
        m_inv_sigma2 = 1.f / (s * s);
    }
    Rgb f(const Vec3& wo, const Vec3& wi) const {
        if (!(wo.z > 0.f && wi.z > 0.f)) return Rgb(0.f);
        const Vec3 h = glm::normalize(wo + wi);
        const float cos_h = h.z, cos_ho = std::fabs(glm::dot(wo, h));
        if (!(std::fabs(cos_h) < 1.f - 1e-5f && cos_ho > 1e-5f)) return Rgb(0.f);
        const float ratio = std::max(cos_h / cos_ho, 1e-5f);
        const float g = std::min(1.f, std::min(2.f * ratio * wo.z, 2.f * ratio * wi.z));
        // sin^2 theta_h from h's tangent components, not 1 - cos^2 (which cancels near the
        // normal, and exp(-cot^2 / sigma^2) multiplies that error by cot^2 / sigma^2).
        const float sin2 = h.x * h.x + h.y * h.y;
        const float cot2 = cos_h * cos_h / sin2;
        const float d = std::exp(-cot2 * m_inv_sigma2) * m_inv_sigma2 * kInvPi / (sin2 * sin2);
        return m_color * (0.25f * d * g / (wo.z * wi.z));
    }
    BSDFEval eval(const Vec3& wo, const Vec3& wi) const {
        if (!(wo.z > 0.f && wi.z > 0.f)) return {};
        return {f(wo, wi), uniform_hemisphere_pdf()};
    }
    std::optional<BSDFSample> sample_f(const Vec3& wo, float /*uc*/, Vec2 u) const {
        if (!(wo.z > 0.f)) return std::nullopt;
        const Vec3 wi = sample_uniform_hemisphere(u);
        if (!(wi.z > 0.f)) return std::nullopt;
        return BSDFSample{f(wo, wi), wi, uniform_hemisphere_pdf(), flags()};
    }
    BxDFFlags flags() const { return BxDFFlags::Diffuse; }

  private:
    Rgb m_color;
    float m_inv_sigma2;
};

}  // namespace

const ModelInfo& velvet_model() {
    static const ModelInfo m{
        .name = "velvet",
        .summary =
            "cloth sheen as Blender's Velvet BSDF (Cycles' Ashikhmin velvet): f = D G / "
            "(4 cos_i cos_o) with D = exp(-cot^2 theta_h / sigma^2) / (pi sigma^2 sin^4 "
            "theta_h), no Fresnel",
        .params = {models::color("reflectance", "0.8", "the colour (Blender's Color), in [0, 1]"),
                   models::number("sigma", "1",
                                  "Blender's Sigma, the spread of the sheen, in [0, 1] (below "
                                  "0.01 it is 0.01)")},
        .read =
            [](ParamReader& r, ParamValues& v) {
                r.color(v, 0, Rgb(0.8f), 0.0, 1.0);  // reflectance
                r.number(v, 1, 1.0, 0.0, 1.0);       // sigma
            },
        .make =
            [](const ParamValues& v, Children) {
                return Material(InlineBxDF(VelvetReflection(v.color(0), float(v.number(1)))));
            },
        .diffuse_param = "reflectance"};
    return m;
}

}  // namespace facet
