// subsurface: Blender's Subsurface Scattering node with Cycles 3.4's random walks
// (facet/subsurface.h, docs/subsurface.md).
#include "model_unit.h"

namespace facet {

namespace {

SubsurfaceMethod method_of(const std::string& s) {
    return s == "random_walk_fixed_radius" ? SubsurfaceMethod::RandomWalkFixedRadius
                                           : SubsurfaceMethod::RandomWalk;
}

}  // namespace

namespace models {

std::vector<ParamInfo> subsurface_walk_params(const std::string& prefix) {
    return {
        color(prefix + "radius", "1 0.2 0.1",
              "scattering radius per channel (mean free path, scene units), each >= 0; all "
              "zero (or a zero scale) gives the diffuse surface instead of the walk"),
        number(prefix + "ior", "1.4",
               "index of refraction of the medium, in [1.01, 3.8] (Cycles' clamp); Random Walk "
               "rescales the radius with it (docs/subsurface.md)"),
        number(prefix + "anisotropy", "0",
               "Henyey-Greenstein anisotropy g of the walk's phase function, in [0, 0.9] "
               "(Cycles' clamp)"),
        text(prefix + "method", "random_walk",
             "random_walk (radius rescaled by the albedo and IOR to match the dipole's "
             "look) or random_walk_fixed_radius (radius / (4 pi), Cycles' Random Walk (Fixed "
             "Radius))",
             {"random_walk", "random_walk_fixed_radius"}),
    };
}

}  // namespace models

SubsurfaceInputs read_subsurface_inputs(ParamReader& r, const std::string& prefix, float scale) {
    SubsurfaceInputs in;
    const Rgb radius = r.color(prefix + "radius", Rgb(1.f, 0.2f, 0.1f), 0.0, 1e30);
    // The ranges in double: the float constants (0.9f < 0.9) would reject the values written.
    in.ior = float(r.number(prefix + "ior", 1.4, 1.01, 3.8));
    in.anisotropy = float(r.number(prefix + "anisotropy", 0.0, 0.0, 0.9));
    in.method = method_of(r.choice(prefix + "method"));
    in.radius = radius * scale;
    int walked = 0;
    for (int c = 0; c < 3; ++c) walked += in.radius[c] >= SubsurfaceLimits::kMinRadius;
    if (walked != 0 && walked != 3)
        throw r.error(prefix + "radius",
                      "every channel times the scale must be > 0, or all of them 0 (a channel "
                      "of radius 0 beside walked ones is not supported)");
    in.walked = walked == 3;
    return in;
}

void read_subsurface_values(ParamReader& r, ParamValues& v, std::size_t radius, std::size_t ior,
                            std::size_t anisotropy, std::size_t method) {
    r.color(v, radius, Rgb(1.f, 0.2f, 0.1f), 0.0, 1e30);
    r.number(v, ior, 1.4, 1.01, 3.8);
    r.number(v, anisotropy, 0.0, 0.0, 0.9);
    r.choice(v, method);
}

namespace {
// The parameters' indices in subsurface's table (ParamValues); method 1 is the fixed radius.
enum Param : std::size_t { kColor, kScale, kRadius, kIor, kAnisotropy, kMethod };
}  // namespace

const ModelInfo& subsurface_model() {
    static const ModelInfo m{
        .name = "subsurface",
        .summary =
            "Blender's Subsurface Scattering node: a random walk inside the closed object as "
            "Cycles 3.4 does it (Random Walk, Random Walk (Fixed Radius)); diffuse after a "
            "diffuse bounce (docs/subsurface.md)",
        .params = models::concat(
            {{models::color("color", "0.8",
                            "Color: the surface albedo the walk reproduces, in [0, 1]"),
              models::number("scale", "1", "Scale: multiplies the radius, >= 0")},
             models::subsurface_walk_params("")}),
        .read =
            [](ParamReader& r, ParamValues& v) {
                r.color(v, kColor, Rgb(0.8f), 0.0, 1.0);
                const float scale = float(r.number(v, kScale, 1.0, 0.0, 1e30));
                read_subsurface_inputs(r, "", scale);  // the checks
                read_subsurface_values(r, v, kRadius, kIor, kAnisotropy, kMethod);
            },
        .make =
            [](const ParamValues& v, Children) {
                const Rgb color = v.color(kColor);
                const std::optional<SubsurfaceInputs> walk = make_subsurface_inputs(
                    v, v.color(kRadius) * float(v.number(kScale)), kIor, kAnisotropy, kMethod);
                if (!walk) return Material(std::nullopt, std::nullopt, std::nullopt);
                const SubsurfaceInputs& in = *walk;
                // Cycles after a diffuse bounce (and at radius 0): a Lambertian surface.
                Material fallback(LambertReflection(color), std::nullopt, std::nullopt);
                if (!in.walked || max_component(color) <= 0.f) return fallback;
                Material::Subsurface s;
                s.lobe.weight = color;
                s.lobe.walk = SubsurfaceWalk::make(
                    color, subsurface_effective_radius(in.radius, color, in.ior, in.method),
                    in.anisotropy);
                s.lobe.fresnel = false;
                s.weight = (color.r + color.g + color.b) / 3.f;
                return Material::with_subsurface(std::move(fallback), std::move(s));
            },
        .diffuse_param = "",
        .pov_finish = false};
    return m;
}

}  // namespace facet
