// Light type "environment", the constant environment (unit:
// core/render/src/lights/environment.cpp, math there).
#pragma once

#include "facet/render/light_sample.h"

namespace facet::render {

struct ConstantEnvironment {
    static constexpr std::string_view kName = "environment";
    static constexpr bool kHittable = true, kNee = false;
    static constexpr bool kInline = false;
    Rgb radiance{0.f};

    std::optional<LightLiSample> sample_li(const LightSampleContext& ctx, Vec2 u) const;
    float pdf_li(const LightSampleContext& ctx, const Vec3& wi, const Vec3&, const Vec3&) const;
    Rgb le_escape(const Vec3&) const { return radiance; }
    Rgb power(float scene_radius) const {
        return radiance * (4.f * kPi * kPi * scene_radius * scene_radius);
    }
    static void note(SceneFeatures& f);
};

}  // namespace facet::render
