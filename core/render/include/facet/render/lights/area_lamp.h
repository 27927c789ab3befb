// Light type "area_lamp", Blender's area lamp (unit: core/render/src/lights/area.cpp, math
// there).
#pragma once

#include "facet/render/light_sample.h"

namespace facet::render {

struct AreaLamp {
    static constexpr std::string_view kName = "area_lamp";
    static constexpr bool kHittable = false, kNee = true;
    static constexpr bool kInline = false;
    Vec3 center{0.f};
    Vec3 e1{0.f}, e2{0.f};  // perpendicular half-axes
    Vec3 normal{0.f};       // unit front normal
    Vec3 sample_err{0.f};   // error box of every area sample (Light::area_lamp)
    Rgb radiance{0.f};
    float area = 0.f, inv_area = 0.f;
    bool ellipse = false;

    std::optional<LightLiSample> sample_li(const LightSampleContext& ctx, Vec2 u) const;
    float pdf_li(const LightSampleContext& ctx, const Vec3& wi, const Vec3& p_light,
                 const Vec3& n_light) const;
    Rgb le(const Vec3& n_light, const Vec3& w) const {
        return glm::dot(n_light, w) > 0.f ? radiance : Rgb(0.f);
    }
    Rgb power(float) const { return radiance * (kPi * area); }
    std::optional<LightBounds> bounds() const;
    float camera_hit(const Vec3& o, const Vec3& d) const;
    static void note(SceneFeatures& f);
};

}  // namespace facet::render
