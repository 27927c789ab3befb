// Light type "directional" (unit: core/render/src/lights/directional.cpp, math there).
#pragma once

#include "facet/render/light_sample.h"

namespace facet::render {

struct DirectionalLight {
    static constexpr std::string_view kName = "directional";
    static constexpr bool kHittable = false, kNee = true;
    static constexpr bool kInline = false;
    Vec3 direction{0.f, 0.f, -1.f};  // the way the light travels (unit)
    Rgb irradiance{0.f};
    // The sun's disc (sized): its radiance L, and 1 - cos delta (delta its half-angle), in
    // double for narrow cones.
    bool sized = false;
    Rgb size_radiance{0.f};
    double one_minus_cos = 0.0;

    std::optional<LightLiSample> sample_li(const LightSampleContext& ctx, Vec2 u) const;
    float pdf_li(const LightSampleContext&, const Vec3&, const Vec3&, const Vec3&) const {
        return 0.f;
    }
    Rgb power(float scene_radius) const { return irradiance * (kPi * scene_radius * scene_radius); }
    static void note(SceneFeatures& f);
};

}  // namespace facet::render
