// Light kind "spot": a point light restricted to a cone, with a linear fall-off between the
// inner and the outer half-angle.
#include "../io/pov_writer.h"
#include "../kind_build.h"
#include "facet/render/light_units.h"

namespace facet::render {

namespace {

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
        b.add_light(Light::spot_blend(p, dir, phi, float(outer), float(blend), b.light_radius()));
        return;
    }
    const double inner = l.inner_angle ? b.check_range(*l.inner_angle, ptr + "/inner_angle", 0.0,
                                                       outer, "in [0, outer_angle] degrees")
                                       : outer;
    b.add_light(Light::spot(p, dir, phi, float(inner), float(outer), b.light_radius()));
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
            << pov_num(outer) << " tightness 0 physical_falloff }  // " << o.pointer << "\n";
}

}  // namespace

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
     kLightRadiusField},
    {{"direction", "look_at"}},
    build,
    pov};

}  // namespace facet::render
