// The Henyey-Greenstein phase function (Henyey & Greenstein 1941; pbrt-v4 §11.3.1), the phase
// function of every medium kind (facet/render/medium.h).
//
// Conventions (the BxDF ones of facet/bxdf.h, carried over to a point in a medium):
//  - World directions, unit, both pointing AWAY from the scattering point: `wo` toward the
//    viewer (the path's previous vertex), `wi` toward the light (the next vertex). Light
//    travels along -wi, scatters, and leaves along wo.
//  - The scattering angle theta is the angle between the light's propagation directions before
//    and after the event: cos theta = dot(-wi, wo). Anisotropy g = <cos theta> in (-1, 1):
//    g > 0 scatters forward (light keeps going: wi near -wo), g < 0 backward, g = 0 is
//    isotropic. This is Cycles' `anisotropy` (Blender's Volume Scatter and Principled Volume).
//  - p(wo, wi) = (1 - g^2) / (4 pi (1 + g^2 - 2 g cos theta)^(3/2)), per unit solid angle,
//    normalised over the sphere and symmetric in wo and wi (reciprocal). `eval` returns p;
//    `pdf` is p (sampling is exact); `sample` returns wi with value and pdf both p, so the
//    sample weight p / pdf is exactly 1.
//  - Random numbers are arguments (u in [0, 1)^2); no state, no RNG.
#pragma once

#include <cmath>
#include <optional>

#include "facet/frame.h"
#include "facet/types.h"

namespace facet {

struct PhaseSample {
    float p = 0.f;    // phase function value p(wo, wi), 1/sr
    Vec3 wi{0.f};     // sampled direction, unit, pointing away from the point
    float pdf = 0.f;  // per unit solid angle (== p for Henyey-Greenstein)
};

class HenyeyGreenstein {
  public:
    // Below this |g| the distribution is sampled as isotropic: the inverse CDF below divides
    // by 2g, which loses all precision as g -> 0 (at |g| = 1e-3 the two forms differ by ~1e-3
    // of the density, far below any visible effect and consistent with eval, which uses the
    // exact formula: the sampling test allows it).
    static constexpr float kIsotropicG = 1e-3f;
    // Largest |g| accepted by the scene format (scenes/FORMAT.md, "media"): beyond it the lobe
    // is narrower than float directions resolve near the peak.
    static constexpr float kMaxAbsG = 0.999f;

    explicit HenyeyGreenstein(float g = 0.f) : m_g(g) {}
    float g() const { return m_g; }

    // p as a function of cos theta (the scattering angle, see conventions).
    static float p_of_cos(float cos_theta, float g) {
        const float denom = 1.f + g * g - 2.f * g * cos_theta;
        return kInv4Pi * (1.f - g * g) / (denom * std::sqrt(denom));
    }

    // p(wo, wi) in 1/sr.
    float eval(const Vec3& wo, const Vec3& wi) const { return p_of_cos(-glm::dot(wo, wi), m_g); }
    float pdf(const Vec3& wo, const Vec3& wi) const { return eval(wo, wi); }

    // wi drawn with density p(wo, .): cos theta by the inverse of the CDF of
    // p(cos theta) = (1 - g^2) / (2 (1 + g^2 - 2 g cos theta)^(3/2)) on [-1, 1] (pbrt-v4
    // eq. 11.14 with its sign of g turned to Cycles'), phi uniform. Never fails for a unit wo.
    std::optional<PhaseSample> sample(const Vec3& wo, Vec2 u) const {
        float cos_t;
        if (std::fabs(m_g) < kIsotropicG) {
            cos_t = 1.f - 2.f * u.x;
        } else {
            const float s = (1.f - m_g * m_g) / (1.f - m_g + 2.f * m_g * u.x);
            cos_t = (1.f + m_g * m_g - s * s) / (2.f * m_g);
        }
        cos_t = glm::clamp(cos_t, -1.f, 1.f);
        const float sin_t = std::sqrt(std::fmax(0.f, 1.f - cos_t * cos_t));
        const float phi = 2.f * kPi * u.y;
        // The outgoing propagation direction wo makes angle theta with the incoming one, -wi.
        const Frame f = Frame::from_z(wo);
        const Vec3 v = f.from_local(Vec3(sin_t * std::cos(phi), sin_t * std::sin(phi), cos_t));
        const Vec3 wi = -glm::normalize(v);
        const float p = eval(wo, wi);
        return PhaseSample{p, wi, p};
    }

  private:
    float m_g;
};

}  // namespace facet
