// Light type "environment_map" (unit: core/render/src/lights/environment_map.cpp, math there).
#pragma once

#include <memory>

#include "facet/render/environment_map.h"
#include "facet/render/light_sample.h"

namespace facet::render {

struct EnvironmentMapLight {
    static constexpr std::string_view kName = "environment_map";
    static constexpr bool kHittable = true, kNee = true;
    static constexpr bool kInline = false;
    std::shared_ptr<const EnvironmentMap> m;

    std::optional<LightLiSample> sample_li(const LightSampleContext& ctx, Vec2 u) const;
    float pdf_li(const LightSampleContext&, const Vec3& wi, const Vec3&, const Vec3&) const {
        return m->pdf(wi);
    }
    Rgb le_escape(const Vec3& d) const { return m->eval(d); }
    Rgb le_escape(const Vec3& d, float& pdf) const { return m->eval_pdf(d, pdf); }
    Rgb power(float scene_radius) const {
        return m->mean_radiance() * (4.f * kPi * kPi * scene_radius * scene_radius);
    }
    const EnvironmentMap* map() const { return m.get(); }
    static void note(SceneFeatures& f);
};

}  // namespace facet::render
