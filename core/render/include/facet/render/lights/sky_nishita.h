// Light type "sky_nishita", Blender 3.4's Nishita Sky Texture as the environment (unit:
// core/render/src/lights/sky_nishita.cpp, math there; the model: facet/render/sky_nishita.h).
#pragma once

#include <memory>

#include "facet/render/light_sample.h"
#include "facet/render/sky_nishita.h"

namespace facet::render {

struct SkyNishitaLight {
    static constexpr std::string_view kName = "sky_nishita";
    static constexpr bool kHittable = true, kNee = true;
    static constexpr bool kInline = false;
    std::shared_ptr<const SkyNishita> sky;

    std::optional<LightLiSample> sample_li(const LightSampleContext& ctx, Vec2 u) const;
    float pdf_li(const LightSampleContext&, const Vec3& wi, const Vec3&, const Vec3&) const {
        return sky->pdf(wi);
    }
    Rgb le_escape(const Vec3& d) const { return sky->eval(d); }
    Rgb power(float scene_radius) const {
        return sky->mean_radiance() * (4.f * kPi * kPi * scene_radius * scene_radius);
    }
    static void note(SceneFeatures& f);
};

}  // namespace facet::render
