// Light type "spot" (unit: core/render/src/lights/spot.cpp, math there).
#pragma once

#include "facet/render/lights/point.h"

namespace facet::render {

struct SpotLight {
    static constexpr std::string_view kName = "spot";
    static constexpr bool kHittable = false, kNee = true;
    static constexpr bool kInline = false;
    PointEmitter e;
    Vec3 direction{0.f, 0.f, -1.f};  // unit cone axis
    float cos_inner = 1.f, cos_outer = 1.f;
    // Blender's fall-off: (1 - cos outer) blend; < 0: the linear form.
    float smooth = -1.f;

    // The intensity relative to I0 at cos theta from the axis.
    float falloff(float cos_theta) const;
    std::optional<LightLiSample> sample_li(const LightSampleContext& ctx, Vec2 u) const;
    float pdf_li(const LightSampleContext&, const Vec3&, const Vec3&, const Vec3&) const {
        return 0.f;
    }
    Rgb power(float) const { return e.power; }
    std::optional<LightBounds> bounds() const;
    static void note(SceneFeatures& f);
};

}  // namespace facet::render
