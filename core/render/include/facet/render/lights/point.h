// Light type "point" (unit: core/render/src/lights/point.cpp, math there).
#pragma once

#include <cstdint>

#include "facet/render/light_sample.h"

namespace facet::render {

// What a point or spot light with a radius r is (the kinds' "radius_model", lights/point.cpp).
// Both have the radiance L = I0 / (pi r^2) and the light's far field.
enum class RadiusModel : std::uint8_t {
    Sphere,        // "sphere": a sphere of radius r (Cycles 4; the default)
    Cycles34Disc,  // "cycles34_disc": Cycles 3.4's disc of radius r centred on the light,
                   // facing the lit point (on-axis irradiance I0 / (d^2 + r^2))
};

// A point, or with a radius the sphere (or Cycles 3.4's facing disc) of the same intensity and
// radiance (point and spot).
struct PointEmitter {
    Vec3 position{0.f};
    Rgb intensity{0.f};      // I0, on the axis
    Rgb power{0.f};          // Phi
    float radius = 0.f;      // > 0: the sphere, or the disc
    Rgb size_radiance{0.f};  // the sphere's (disc's) L
    bool disc = false;       // RadiusModel::Cycles34Disc
};

struct PointLight {
    static constexpr std::string_view kName = "point";
    static constexpr bool kHittable = false, kNee = true;
    static constexpr bool kInline = false;
    PointEmitter e;

    std::optional<LightLiSample> sample_li(const LightSampleContext& ctx, Vec2 u) const;
    float pdf_li(const LightSampleContext&, const Vec3&, const Vec3&, const Vec3&) const {
        return 0.f;
    }
    Rgb power(float) const { return e.power; }
    std::optional<LightBounds> bounds() const;
    static void note(SceneFeatures& f);
};

}  // namespace facet::render
