// Light types "emissive_triangles" and "emissive_parallelogram" (unit:
// core/render/src/lights/emissive_triangles.cpp, math there).
#pragma once

#include <cstdint>
#include <vector>

#include "facet/render/light_sample.h"

namespace facet::render {

struct EmissiveTriangles {
    static constexpr std::string_view kName = "emissive_triangles";
    static constexpr bool kHittable = true, kNee = true;
    static constexpr bool kInline = false;
    std::vector<Vec3> tri;                 // 3 vertices per triangle
    std::vector<Vec3> tri_n;               // unit front normal per triangle
    std::vector<float> tri_cdf;            // running area fraction, last = 1
    std::vector<std::uint32_t> tri_guide;  // tri_cdf's cutpoint table (facet/cdf_search.h)
    Rgb radiance{0.f};
    float area = 0.f, inv_area = 0.f;

    std::optional<LightLiSample> sample_li(const LightSampleContext& ctx, Vec2 u) const;
    float pdf_li(const LightSampleContext& ctx, const Vec3& wi, const Vec3& p_light,
                 const Vec3& n_light) const {
        if (!(area > 0.f)) return 0.f;
        return area_to_solid_angle_pdf(ctx.p, wi, p_light, n_light, inv_area);
    }
    Rgb le(const Vec3& n_light, const Vec3& w) const {
        return glm::dot(n_light, w) > 0.f ? radiance : Rgb(0.f);
    }
    Rgb power(float) const { return radiance * (kPi * area); }  // one-sided Lambertian: pi A L
    std::optional<LightBounds> bounds() const;
    static void note(SceneFeatures& f);
};

// Inline: the usual area light (the Cornell box's), sampled at every path vertex.
struct EmissiveParallelogram {
    static constexpr std::string_view kName = "emissive_parallelogram";
    static constexpr bool kHittable = true, kNee = true;
    static constexpr bool kInline = true;
    Vec3 corner{0.f}, e1{0.f}, e2{0.f};  // p = corner + u.x e1 + u.y e2
    Vec3 normal{0.f};                    // unit front normal
    Vec3 sample_err{0.f};                // error box of every sample
    Rgb radiance{0.f};
    float area = 0.f, inv_area = 0.f;

    [[gnu::always_inline]] std::optional<LightLiSample> sample_li(const LightSampleContext& ctx,
                                                                  Vec2 u) const {
        LightLiSample s;
        s.p_light = corner + u.x * e1 + u.y * e2;
        s.n_light = normal;
        s.p_light_err = sample_err;
        return finish_area_sample(ctx, s, inv_area, radiance);
    }
    float pdf_li(const LightSampleContext& ctx, const Vec3& wi, const Vec3& p_light,
                 const Vec3& n_light) const {
        if (!(area > 0.f)) return 0.f;
        return area_to_solid_angle_pdf(ctx.p, wi, p_light, n_light, inv_area);
    }
    Rgb le(const Vec3& n_light, const Vec3& w) const {
        return glm::dot(n_light, w) > 0.f ? radiance : Rgb(0.f);
    }
    Rgb power(float) const { return radiance * (kPi * area); }
    std::optional<LightBounds> bounds() const;
    static void note(SceneFeatures& f);
};

}  // namespace facet::render
