// Light type of an emissive disc shape (light.h "Structure"): Light::area_disc, a flat ellipse
// c + r (cos(a) e1 + sin(a) e2), r in [0, 1] (a transformed disc).
//
// Sampling (light.h conventions): uniformly by area (concentric mapping), converted to solid
// angle: pdf = r^2 / (A |cos theta_l|). One-sided: the front normal is normalize(e1 x e2).
// Power: pi A L.
#include "sampling.h"

namespace facet::render {

namespace {}  // namespace

std::optional<LightLiSample> EmissiveDisc::sample_li(const LightSampleContext& ctx, Vec2 u) const {
    LightLiSample s;
    Vec2 d = sample_uniform_disk_concentric(u);
    s.p_light = center + d.x * e1 + d.y * e2;
    s.n_light = normal;
    s.p_light_err = sample_err;
    return finish_area_sample(ctx, s, inv_area, radiance);
}

void EmissiveDisc::note(SceneFeatures& f) {
    f.has_area = true;
}

Light Light::area_disc(const Vec3& center, const Vec3& e1, const Vec3& e2, const Rgb& radiance,
                       std::uint32_t shape) {
    EmissiveDisc l;
    l.center = center;
    l.e1 = e1;
    l.e2 = e2;
    // In double: the float cross product's squared length overflows for edges beyond ~4e9.
    const glm::dvec3 c = glm::cross(glm::dvec3(e1), glm::dvec3(e2));
    l.normal = Vec3(glm::normalize(c));
    l.radiance = radiance;
    l.area = float(kPiD * glm::length(c));  // an affine image of the unit disc
    // Every sample c + d.x e1 + d.y e2 (|d| <= 1): centre and axes are roundings of the traced
    // disc's double transform, then two products and two sums.
    l.sample_err = gamma_bound(5) * (glm::abs(center) + glm::abs(e1) + glm::abs(e2));
    l.inv_area = 1.f / l.area;
    const float area = l.area;
    return make(l, {.emission = radiance, .position = center, .area = area, .shape = shape});
}

std::optional<LightBounds> EmissiveDisc::bounds() const {
    return flat_bounds(center, e1, e2, normal, power(0.f));
}

}  // namespace facet::render
