// Light type "point" (unit: core/render/src/lights/point.cpp, math there).
#pragma once

#include "facet/render/light_sample.h"

namespace facet::render {

// A point, or with a radius the sphere of the same intensity and power (point and spot).
struct PointEmitter {
    Vec3 position{0.f};
    Rgb intensity{0.f};      // I0, on the axis
    Rgb power{0.f};          // Phi
    float radius = 0.f;      // > 0: the sphere
    Rgb size_radiance{0.f};  // the sphere's L
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
    static void note(SceneFeatures& f);
};

}  // namespace facet::render
