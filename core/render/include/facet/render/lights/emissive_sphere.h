// Light type "emissive_sphere" (unit: core/render/src/lights/emissive_sphere.cpp, math there).
#pragma once

#include "facet/render/light_sample.h"

namespace facet::render {

struct EmissiveSphere {
    static constexpr std::string_view kName = "emissive_sphere";
    static constexpr bool kHittable = true, kNee = true;
    static constexpr bool kInline = false;
    Vec3 center{0.f};
    float radius = 0.f;
    bool inward = false;  // turned inside out
    Rgb radiance{0.f};
    float area = 0.f, inv_area = 0.f;

    std::optional<LightLiSample> sample_li(const LightSampleContext& ctx, Vec2 u) const;
    float pdf_li(const LightSampleContext& ctx, const Vec3& wi, const Vec3& p_light,
                 const Vec3& n_light) const;
    Rgb le(const Vec3& n_light, const Vec3& w) const {
        return glm::dot(n_light, w) > 0.f ? radiance : Rgb(0.f);
    }
    Rgb power(float) const { return radiance * (kPi * area); }
    std::optional<LightBounds> bounds() const;
    static void note(SceneFeatures& f);
};

}  // namespace facet::render
