// Lambertian (ideal diffuse) reflection: f = rho / pi (Cohen & Wallace eq. 2.33-2.36).
//
// Conventions: facet/bxdf.h. Sampling is cosine-weighted, pdf = cos(theta_i) / pi, so
// f * cos / pdf = rho exactly.
#pragma once

#include <optional>

#include "facet/bxdf.h"
#include "facet/sampling.h"

namespace facet {

class LambertReflection {
  public:
    // rho: directional-hemispherical reflectance per channel, in [0, 1] (validated by the
    // registry, not here).
    explicit LambertReflection(const Rgb& rho) : m_rho(rho) {}

    Rgb f(const Vec3& wo, const Vec3& wi) const {
        return same_hemisphere(wo, wi) && wo.z > 0.f ? m_rho * kInvPi : Rgb(0.f);
    }
    float pdf(const Vec3& wo, const Vec3& wi) const {
        return same_hemisphere(wo, wi) && wo.z > 0.f ? cosine_hemisphere_pdf(wi.z) : 0.f;
    }
    std::optional<BSDFSample> sample_f(const Vec3& wo, float /*uc*/, Vec2 u) const {
        if (!(wo.z > 0.f)) return std::nullopt;
        Vec3 wi = sample_cosine_hemisphere(u);
        float p = cosine_hemisphere_pdf(wi.z);
        if (!(p > 0.f)) return std::nullopt;  // sampled exactly on the horizon
        return BSDFSample{m_rho * kInvPi, wi, p, BxDFFlags::Diffuse};
    }
    BxDFFlags flags() const { return BxDFFlags::Diffuse; }
    const Rgb& rho() const { return m_rho; }

  private:
    Rgb m_rho;
};

}  // namespace facet
