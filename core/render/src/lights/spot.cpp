// Light kind "spot": a point light restricted to a cone, with a linear fall-off between the
// inner and the outer half-angle (or Blender's), and its light type.
//
// Sampling (light.h conventions): the delta spot gives li = I(theta) / r^2 with I(theta) = I0
// falloff(cos theta), where falloff is 1 inside the inner cone, 0 outside the outer cone and
// LINEAR IN cos theta between them, so Phi = 2 pi I0 [(1 - cos_in) + (cos_in - cos_out) / 2]
// holds exactly (light_units.h, spot_intensity); Blender's form uses Cycles' fall-off instead
// (cycles_spot_attenuation, cycles_spot_intensity). With a radius it is the point light's
// sphere (lights/point.cpp) of on-axis radiance L = I0 / (pi r^2), whose radiance along w (from
// the sphere toward the receiver) is L falloff(w . axis). With "radius_model": "cycles34_disc" it
// is the point light's Cycles 3.4 disc facing the lit point instead (lights/point.cpp), whose
// radiance toward the lit point along w is likewise L falloff(w . axis) (Cycles 3.4 attenuates
// each disc sample by the spot's fall-off along its own direction).
#include <algorithm>

#include "../io/pov_writer.h"
#include "../kind_build.h"
#include "facet/render/light_units.h"
#include "sampling.h"

namespace facet::render {

namespace {

Light make_spot(SpotLight& l, const Vec3& position, float radius, RadiusModel model) {
    const bool sphere = set_emitter_radius(l.e, radius, model);
    return Light::make(l, {.emission = l.e.power, .position = position, .delta = !sphere});
}

void build(LightBuild& b) {
    const LightDesc& l = b.light;
    const std::string& ptr = b.ptr;
    b.check_finite(l.position, ptr + "/position");
    const Vec3 p = l.position;
    const Vec3 dir = b.aim(p);
    const Rgb phi = b.check_color(l.power, ptr + "/power", "a power (W)");
    const double outer = b.check_range(l.outer_angle, ptr + "/outer_angle", 0.0, 180.0,
                                       "in (0, 180) degrees (half-angle)");
    if (!(outer > 0.0 && outer < 180.0)) {
        b.fail(ptr + "/outer_angle", "must be in (0, 180) degrees (half-angle)");
    }
    if (l.spot_blend) {
        // Blender's form (Cycles 3.4's fall-off): instead of inner_angle, a cone of at most 90
        // degrees (Blender's spot_size <= 180).
        const std::string bp = ptr + "/spot_blend";
        if (l.inner_angle) b.fail(bp, "give inner_angle or spot_blend, not both");
        const double blend = b.check_range(*l.spot_blend, bp, 0.0, 1.0, "in [0, 1]");
        if (outer > 90.0)
            b.fail(ptr + "/outer_angle",
                   "must be <= 90 degrees with spot_blend (Blender's "
                   "spot_size <= 180)");
        b.add_light(Light::spot_blend(p, dir, phi, float(outer), float(blend), b.light_radius(),
                                      b.radius_model()));
        return;
    }
    const double inner = l.inner_angle ? b.check_range(*l.inner_angle, ptr + "/inner_angle", 0.0,
                                                       outer, "in [0, outer_angle] degrees")
                                       : outer;
    b.add_light(
        Light::spot(p, dir, phi, float(inner), float(outer), b.light_radius(), b.radius_model()));
}

void pov(PovLightOut& o) {
    const LightDesc& l = o.light;
    o.check_no_radius();
    if (l.spot_blend)
        o.fail(o.pointer + "/spot_blend",
               "Blender's spot fall-off (Cycles' mu * smoothstep) has no POV-Ray equivalent");
    const double outer = l.outer_angle;
    const double inner = l.inner_angle.value_or(outer);
    if (inner != outer)
        o.fail(o.pointer + "/inner_angle",
               "POV-Ray's spotlight fades with a smoothstep in cos(theta), Facet's linearly: only "
               "inner_angle = outer_angle (a hard edge) is exported exactly");
    if (outer > 90.0)
        o.fail(o.pointer + "/outer_angle",
               "POV-Ray's spotlight lights only the front hemisphere: outer_angle must be <= 90");
    const glm::dvec3 pos(l.position);
    const glm::dvec3 dir = l.direction ? glm::dvec3(*l.direction) : glm::dvec3(*l.look_at) - pos;
    const glm::dvec3 c = pov_light_colour(spot_intensity(glm::dvec3(l.power), inner, outer));
    o.out() << "light_source { " << pov_vec(pos) << " " << pov_rgb(c) << " spotlight point_at "
            << pov_vec(pos + glm::normalize(dir)) << " radius " << pov_num(outer) << " falloff "
            << pov_num(outer) << " tightness 0 physical_falloff" << o.media_keywords() << " }  // "
            << o.pointer << "\n";
}

}  // namespace

float SpotLight::falloff(float cos_theta) const {
    if (smooth < 0.f) {
        if (cos_theta >= cos_inner) return 1.f;
        if (cos_theta <= cos_outer) return 0.f;
        return (cos_theta - cos_outer) / (cos_inner - cos_outer);
    }
    return float(cycles_spot_attenuation(double(cos_theta), double(cos_outer), double(smooth)));
}

std::optional<LightLiSample> SpotLight::sample_li(const LightSampleContext& ctx, Vec2 u) const {
    const auto f = [this](const Vec3& wi) { return falloff(-glm::dot(wi, direction)); };
    if (e.radius > 0.f) {
        if (e.disc) return sample_emitter_disc(e, ctx, u, f);
        return sample_emitter_sphere(e, ctx, u, f);
    }
    return sample_emitter_point(e, ctx, f);
}

void SpotLight::note(SceneFeatures& f) {
    f.has_spot = true;
}

Light Light::spot(const Vec3& position, const Vec3& direction, const Rgb& power,
                  float inner_half_angle_deg, float outer_half_angle_deg, float radius,
                  RadiusModel model) {
    SpotLight l;
    l.e.position = position;
    l.e.power = power;
    l.direction = glm::normalize(direction);
    l.cos_inner = float(std::cos(double(inner_half_angle_deg) * kPiD / 180.0));
    l.cos_outer = float(std::cos(double(outer_half_angle_deg) * kPiD / 180.0));
    // Phi = 2 pi I0 int_{cos_out}^{1} falloff(mu) dmu (light_units.h, shared with the exporters).
    l.e.intensity = Rgb(spot_intensity(glm::dvec3(power), double(inner_half_angle_deg),
                                       double(outer_half_angle_deg)));
    return make_spot(l, position, radius, model);
}

Light Light::spot_blend(const Vec3& position, const Vec3& direction, const Rgb& power,
                        float outer_half_angle_deg, float blend, float radius, RadiusModel model) {
    SpotLight l;
    l.e.position = position;
    l.e.power = power;
    l.direction = glm::normalize(direction);
    const double c = std::cos(double(outer_half_angle_deg) * kPiD / 180.0);
    l.cos_inner = l.cos_outer = float(c);
    l.smooth = float((1.0 - c) * double(blend));
    l.e.intensity =
        Rgb(cycles_spot_intensity(glm::dvec3(power), double(outer_half_angle_deg), double(blend)));
    return make_spot(l, position, radius, model);
}

extern const LightKindDef kSpotLightKind{
    LightKind::Spot,
    "spot",
    "half-angles from the axis in degrees, 0 ≤ inner ≤ outer < 180. Intensity I(θ) = I₀ inside "
    "the inner cone, 0 outside the outer cone, **linear in cos θ** in between; I₀ is set so "
    "that the total power is exactly Φ: Φ = 2π I₀ [(1 − cos inner) + (cos inner − cos outer)/2]. "
    "With `radius` R > 0 it is a sphere of radiance L(ω) = I₀ falloff(ω) / (π R²) toward ω "
    "(the intensity and power of the point spot; the cone fall-off is evaluated per sampled "
    "direction from the sphere to the lit point, as Cycles does); otherwise as `point`'s radius. "
    "**Blender's form**: `outer_angle` = spot_size/2 (≤ 90) and `spot_blend` b instead of "
    "`inner_angle`: I(θ) = K g(cos θ) with Cycles 3.4's fall-off g(μ) = 0 for μ ≤ c, "
    "μ·smoothstep((μ − c)/s) for c < μ < c + s, μ beyond (c = cos outer, s = (1 − c) b, "
    "smoothstep(x) = 3x² − 2x³); K is set so that the power is Φ: "
    "Φ = 2π K [(1 − (c + s)²)/2 + s (c/2 + 0.35 s)]. A Blender spot of power P has K = P/(4π)",
    {{"position", FieldType::Point, true, &LightDesc::position, "-", "position"},
     {"direction", FieldType::Direction, false, &LightDesc::direction, "-",
      "cone axis (give this or look_at)"},
     {"look_at", FieldType::Point, false, &LightDesc::look_at, "-",
      "a point on the cone axis (give this or direction)"},
     {"power", FieldType::Color, true, &LightDesc::power, "-", "a power (W)"},
     {"inner_angle", FieldType::Number, false, &LightDesc::inner_angle, "outer_angle",
      "half-angle of full intensity, degrees, in [0, outer_angle]"},
     {"outer_angle", FieldType::Number, true, &LightDesc::outer_angle, "-",
      "half-angle of the cone, degrees, in (0, 180)"},
     {"spot_blend", FieldType::Number, false, &LightDesc::spot_blend, "-",
      "Blender's spot_blend in [0, 1], instead of inner_angle (Blender's form, see above)"},
     kLightRadiusField,
     kLightRadiusModelField},
    {{"direction", "look_at"}},
    build,
    pov};

// Full intensity inside the inner cone and none beyond the outer one (linear fall-off), or
// Cycles' smooth fall-off from the axis to the outer cone.
std::optional<LightBounds> SpotLight::bounds() const {
    LightBounds b = point_bounds(e);
    b.w = direction;
    const float outer = std::acos(std::clamp(cos_outer, -1.f, 1.f));
    const float inner = smooth < 0.f ? std::acos(std::clamp(cos_inner, -1.f, 1.f)) : 0.f;
    b.cos_theta_o = std::cos(inner);
    // (1e-3 rad wider: the fall-off's own float test of the cone's edge may round the other way)
    b.cos_theta_e = std::cos(std::max(0.f, outer - inner) + 1e-3f);
    return b;
}

}  // namespace facet::render
