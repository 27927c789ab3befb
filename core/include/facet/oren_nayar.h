// Oren-Nayar rough diffuse reflection in the form Cycles evaluates it (Blender's Diffuse BSDF
// with Roughness > 0; Cycles 3.4, kernel/closure/bsdf_oren_nayar.h), which is Fujii's
// "qualitative" Oren-Nayar (Y. Fujii, "A tiny improvement of Oren-Nayar reflectance model",
// 2012) rather than Oren & Nayar's own 1994 approximation in radians.
//
// Conventions: facet/bxdf.h. With sigma = the roughness, clamped to [0, 1] as Cycles does,
//     A = 1 / (pi + (3 pi - 4) / 6 sigma),   B = sigma A,
//     s = wi.wo - cos_i cos_o          (= sin_i sin_o cos(phi_i - phi_o)),
//     t = s / max(cos_i, cos_o)  when s > 0,   t = s  otherwise,
//     f = rho (A + B t).
// sigma = 0 is Lambert (A = 1/pi, B = 0). f is symmetric in (wo, wi) (reciprocal) and >= 0.
// Sampling is cosine-weighted (pdf = cos_i / pi); Cycles samples the uniform hemisphere,
// which gives the same expectation with more variance.
#pragma once

#include <algorithm>
#include <optional>

#include "facet/bxdf.h"
#include "facet/sampling.h"

namespace facet {

class OrenNayarReflection {
  public:
    // rho in [0, 1] per channel; sigma is clamped to [0, 1] (the registry validates both).
    OrenNayarReflection(const Rgb& rho, float sigma) : m_rho(rho) {
        const float s = std::clamp(sigma, 0.f, 1.f);
        m_sigma = s;
        m_a = 1.f / (kPi + (3.f * kPi - 4.f) / 6.f * s);
        m_b = s * m_a;
    }

    Rgb f(const Vec3& wo, const Vec3& wi) const {
        if (!(wo.z > 0.f && wi.z > 0.f)) return Rgb(0.f);
        float t = glm::dot(wi, wo) - wi.z * wo.z;
        if (t > 0.f) t /= std::max(wi.z, wo.z);
        return m_rho * std::max(0.f, m_a + m_b * t);
    }
    float pdf(const Vec3& wo, const Vec3& wi) const {
        return wo.z > 0.f && wi.z > 0.f ? cosine_hemisphere_pdf(wi.z) : 0.f;
    }
    std::optional<BSDFSample> sample_f(const Vec3& wo, float /*uc*/, Vec2 u) const {
        if (!(wo.z > 0.f)) return std::nullopt;
        const Vec3 wi = sample_cosine_hemisphere(u);
        const float p = cosine_hemisphere_pdf(wi.z);
        if (!(p > 0.f)) return std::nullopt;
        return BSDFSample{f(wo, wi), wi, p, BxDFFlags::Diffuse};
    }
    BSDFEval eval(const Vec3& wo, const Vec3& wi) const { return {f(wo, wi), pdf(wo, wi)}; }
    BxDFFlags flags() const { return BxDFFlags::Diffuse; }
    const Rgb& rho() const { return m_rho; }
    float a() const { return m_a; }
    float b() const { return m_b; }
    float sigma() const { return m_sigma; }  // clamped to [0, 1]

  private:
    Rgb m_rho;
    float m_a, m_b;
    float m_sigma;
};

}  // namespace facet
