// Perfect specular (mirror) reflection: a true Dirac delta lobe (Cohen & Wallace eq. 2.27-2.29)
// weighted by a Fresnel term.
//
// Conventions: facet/bxdf.h. f() and pdf() return 0 (a delta has no finite value); sample_f
// returns wi = reflect(wo, n) with pdf = 1 and f = scale * F(cos theta) / cos theta_i, flagged
// Specular, so f * cos / pdf = scale * F is the reflected fraction.
#pragma once

#include <optional>

#include "facet/bxdf.h"
#include "facet/fresnel.h"

namespace facet {

class MirrorReflection {
  public:
    MirrorReflection(const Fresnel& fresnel, const Rgb& scale)
        : m_fresnel(fresnel), m_scale(scale) {}

    Rgb f(const Vec3&, const Vec3&) const { return Rgb(0.f); }
    float pdf(const Vec3&, const Vec3&) const { return 0.f; }
    std::optional<BSDFSample> sample_f(const Vec3& wo, float /*uc*/, Vec2 /*u*/) const {
        if (!(wo.z > 0.f)) return std::nullopt;
        Vec3 wi(-wo.x, -wo.y, wo.z);
        return BSDFSample{reflectance(wo.z) / wo.z, wi, 1.f, BxDFFlags::Specular};
    }
    // The reflected fraction scale * F(cos theta) at cos theta = cos_o.
    Rgb reflectance(float cos_o) const { return m_scale * m_fresnel.eval(cos_o); }
    BxDFFlags flags() const { return BxDFFlags::Specular; }
    const Fresnel& fresnel() const { return m_fresnel; }
    const Rgb& scale() const { return m_scale; }

  private:
    Fresnel m_fresnel;
    Rgb m_scale;
};

}  // namespace facet
