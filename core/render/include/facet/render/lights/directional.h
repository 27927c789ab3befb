// Light type "directional" (unit: core/render/src/lights/directional.cpp, math there).
#pragma once

#include <cstdint>

#include "facet/render/light_sample.h"

namespace facet::render {

// What a directional light with an angle is (the kind's "angle_model", lights/directional.cpp).
enum class SunAngleModel : std::uint8_t {
    Uniform,   // "uniform": a cone of uniform radiance, E on a facing surface (the default)
    Cycles34,  // "cycles34": Cycles 3.4's sun, darker on a facing surface as the angle grows
};

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
    // Cycles 3.4's sun ("angle_model": "cycles34", lights/directional.cpp): directions through
    // the disc of radius tan delta at distance 1, radiance E / (pi tan^2 delta cos^3 theta).
    bool cycles34 = false;
    double tan_delta = 0.0;

    std::optional<LightLiSample> sample_li(const LightSampleContext& ctx, Vec2 u) const;
    float pdf_li(const LightSampleContext&, const Vec3&, const Vec3&, const Vec3&) const {
        return 0.f;
    }
    Rgb power(float scene_radius) const { return irradiance * (kPi * scene_radius * scene_radius); }
    static void note(SceneFeatures& f);
};

}  // namespace facet::render
