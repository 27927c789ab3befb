// Light type "emissive_disc" (unit: core/render/src/lights/emissive_disc.cpp, math there).
#pragma once

#include "facet/render/light_sample.h"

namespace facet::render {

struct EmissiveDisc {
    static constexpr std::string_view kName = "emissive_disc";
    static constexpr bool kHittable = true, kNee = true;
    static constexpr bool kInline = false;
    Vec3 center{0.f}, e1{0.f}, e2{0.f};
    Vec3 normal{0.f};      // unit front normal
    Vec3 sample_err{0.f};  // error box of every sample (Light::area_disc)
    Rgb radiance{0.f};
    float area = 0.f, inv_area = 0.f;

    std::optional<LightLiSample> sample_li(const LightSampleContext& ctx, Vec2 u) const;
    float pdf_li(const LightSampleContext& ctx, const Vec3& wi, const Vec3& p_light,
                 const Vec3& n_light) const {
        if (!(area > 0.f)) return 0.f;
        return area_to_solid_angle_pdf(ctx.p, wi, p_light, n_light, inv_area);
    }
    Rgb le(const Vec3& n_light, const Vec3& w) const {
        return glm::dot(n_light, w) > 0.f ? radiance : Rgb(0.f);
    }
    Rgb power(float) const { return radiance * (kPi * area); }
    std::optional<LightBounds> bounds() const;
    static void note(SceneFeatures& f);
};

}  // namespace facet::render
