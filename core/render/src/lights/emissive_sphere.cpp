// Light type of an emissive sphere shape (light.h "Structure"): Light::area_sphere.
//
// Sampling (light.h conventions): outward-emitting spheres are sampled uniformly in the cone
// of directions they subtend (pdf per solid angle 1 / (2 pi (1 - cos theta_max)), sin
// theta_max = r / d; pbrt-v4's SampleSphere), in double precision; a point on (or inside) the
// sphere sees none of it. A sphere turned inside out ("flip_normals") lights only its interior
// and is sampled uniformly by area from inside (pdf = r^2 / (A |cos theta_l|)). Power: pi A L.
#include "sampling.h"

namespace facet::render {

namespace {

bool sphere_inside(const EmissiveSphere& l, const Vec3& p) {
    Vec3 v = p - l.center;
    return glm::dot(v, v) <= l.radius * l.radius * 1.001f;
}

}  // namespace

std::optional<LightLiSample> EmissiveSphere::sample_li(const LightSampleContext& ctx,
                                                       Vec2 u) const {
    LightLiSample s;
    if (inward) {
        // Inside-out sphere: only its interior is lit; uniform by area from inside.
        if (!sphere_inside(*this, ctx.p)) return std::nullopt;
        Vec3 n = sample_uniform_sphere(u);
        s.p_light = center + radius * n;
        s.n_light = -n;
        s.p_light_err = sphere_sample_error(s.p_light, center, radius);
        return finish_area_sample(ctx, s, inv_area, radiance);
    }
    // Sample the cone of directions the sphere subtends (uniform in solid angle).
    glm::dvec3 c(center), p(ctx.p);
    glm::dvec3 to_c = c - p;
    double dc2 = glm::dot(to_c, to_c);
    double r2 = double(radius) * double(radius);
    if (!(dc2 > r2 * kSphereOutside2)) return std::nullopt;  // inside or on it: unseen
    double dc = std::sqrt(dc2);
    double omc = sphere_cone_one_minus_cos(dc2, r2);
    glm::dvec3 wi = sample_cone(Vec3(to_c / dc), omc, u);
    double t = sphere_hit_distance(to_c, wi, r2, false);
    glm::dvec3 n = glm::normalize(p + t * wi - c);
    glm::dvec3 pl = c + double(radius) * n;
    s.p_light = Vec3(pl);
    s.n_light = Vec3(n);
    s.p_light_err = sphere_sample_error(s.p_light, center, radius);
    s.wi = Vec3(wi);
    s.dist = float(glm::length(pl - p));
    s.pdf = float(1.0 / (2.0 * kPiD * omc));
    s.li = radiance;
    if (!(s.pdf > 0.f) || !std::isfinite(s.pdf) || !(s.dist > 0.f)) return std::nullopt;
    return s;
}
float EmissiveSphere::pdf_li(const LightSampleContext& ctx, const Vec3& wi, const Vec3& p_light,
                             const Vec3& n_light) const {
    if (inward) {
        if (!sphere_inside(*this, ctx.p)) return 0.f;  // see sample_li
        return area_to_solid_angle_pdf(ctx.p, wi, p_light, n_light, inv_area);
    }
    if (!(-glm::dot(n_light, wi) > 0.f)) return 0.f;
    glm::dvec3 to_c = glm::dvec3(center) - glm::dvec3(ctx.p);
    double dc2 = glm::dot(to_c, to_c);
    double r2 = double(radius) * double(radius);
    if (!(dc2 > r2 * kSphereOutside2)) return 0.f;
    return float(1.0 / (2.0 * kPiD * sphere_cone_one_minus_cos(dc2, r2)));
}

void EmissiveSphere::note(SceneFeatures& f) {
    f.has_area = true;
}

Light Light::area_sphere(const Vec3& center, float radius, const Rgb& radiance, std::uint32_t shape,
                         bool inward) {
    EmissiveSphere l;
    l.center = center;
    l.radius = radius;
    l.inward = inward;
    l.radiance = radiance;
    l.area = 4.f * kPi * radius * radius;
    l.inv_area = 1.f / l.area;
    const float area = l.area;
    return make(l, {.emission = radiance, .position = center, .area = area, .shape = shape});
}

// Every direction (its normals cover the sphere; turned inward, too).
std::optional<LightBounds> EmissiveSphere::bounds() const {
    const Vec3 r(radius);
    return light_bounds(center - r, center + r, power(0.f), Vec3(0.f, 0.f, 1.f), -1.f, 0.f);
}

}  // namespace facet::render
