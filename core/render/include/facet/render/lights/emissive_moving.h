// Light type "emissive_moving_triangles" (unit: core/render/src/lights/emissive_moving.cpp,
// math there): an emitting triangle shape that moves over the shutter (its "motion", its
// "motion_positions" or both; scenes/FORMAT.md "Motion blur"). Its samples and pdfs are taken
// at the path's shutter time (Light::sample_li_at, pdf_li_at), on the triangles as the scene
// traces them then.
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "facet/render/light_sample.h"
#include "facet/render/motion.h"

namespace facet::render {

struct EmissiveMovingTriangles {
    static constexpr std::string_view kName = "emissive_moving_triangles";
    static constexpr bool kHittable = true, kNee = true;
    static constexpr bool kInline = false;
    // Object-space corners, 3 per triangle, for each deformation step (one step: the shape does
    // not deform); triangle i is the traced mesh's primitive i (SurfaceHit::emitter_prim).
    std::vector<std::vector<Vec3>> corners;
    std::vector<DecomposedTransform> motion;  // the placement's steps; empty: `place`
    glm::dmat4 place{1.0};                    // the still placement (no "motion")
    std::vector<float> tri_pmf;               // probability of choosing triangle i
    std::vector<float> tri_cdf;               // running sum of tri_pmf, last = 1
    std::vector<std::uint32_t> tri_guide;     // tri_cdf's cutpoint table (facet/cdf_search.h)
    Rgb radiance{0.f};
    float max_area = 0.f;            // the largest total area over the shutter
    std::optional<LightBounds> box;  // bounds() (computed once, by the factory)

    std::uint32_t num_triangles() const { return std::uint32_t(tri_pmf.size()); }
    // Triangle i's world-space corners at shutter time tau (motion.h), in double.
    void corners_at(std::uint32_t i, float tau, glm::dvec3 out[3]) const;

    // At shutter time `time` (light.h "Time"); without it, at time 0.
    std::optional<LightLiSample> sample_li(const LightSampleContext& ctx, Vec2 u, float time) const;
    std::optional<LightLiSample> sample_li(const LightSampleContext& ctx, Vec2 u) const {
        return sample_li(ctx, u, 0.f);
    }
    // The pdf needs the triangle that was hit (its area at `time`): `prim` is the hit's
    // SurfaceHit::emitter_prim.
    float pdf_li(const LightSampleContext& ctx, const Vec3& wi, const Vec3& p_light,
                 const Vec3& n_light, std::uint32_t prim, float time) const;
    Rgb le(const Vec3& n_light, const Vec3& w) const {
        return glm::dot(n_light, w) > 0.f ? radiance : Rgb(0.f);
    }
    Rgb power(float) const { return radiance * (kPi * max_area); }
    std::optional<LightBounds> bounds() const { return box; }
    static void note(SceneFeatures& f);
};

}  // namespace facet::render
