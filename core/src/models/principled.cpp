// principled: Blender 3.4's Principled BSDF as Cycles evaluates it (facet/principled.h).
#include "model_unit.h"

namespace facet {

namespace {
// The parameters' indices in the table (ParamValues): principled's own, then the walk's
// (models::subsurface_walk_params).
enum Param : std::size_t {
    kBaseColor,
    kSubsurface,
    kSubsurfaceColor,
    kMetallic,
    kIor = 13,
    kTransmissionRoughness = 15,
    kDistribution,
    kRadius,
    kWalkIor,
    kAnisotropy,
    kMethod
};
using P = PrincipledParams;
// The number fields from metallic to transmission_roughness, in the table's order.
constexpr float P::*kNumbers[] = {&P::metallic,
                                  &P::specular,
                                  &P::specular_tint,
                                  &P::roughness,
                                  &P::anisotropic,
                                  &P::anisotropic_rotation,
                                  &P::sheen,
                                  &P::sheen_tint,
                                  &P::clearcoat,
                                  &P::clearcoat_roughness,
                                  &P::ior,
                                  &P::transmission,
                                  &P::transmission_roughness};
static_assert(std::size(kNumbers) == kTransmissionRoughness - kMetallic + 1);
}  // namespace

const ModelInfo& principled_model() {
    static const ModelInfo m{
        .name = "principled",
        .summary =
            "Blender 3.4's Principled BSDF as Cycles evaluates it: Disney diffuse with "
            "retro-reflection, sheen, GGX specular (anisotropic), metallic, GTR1 clearcoat, rough "
            "glass transmission (docs/principled.md)",
        .params = models::concat(
            {{models::color("base_color", "0.8", "Base Color C, in [0, 1]"),
              models::number(
                  "subsurface", "0",
                  "Subsurface, in [0, 1]: the diffuse lobe becomes a random walk of albedo "
                  "C = mix(base_color, subsurface_color, subsurface) and radius subsurface_radius "
                  "times this (docs/subsurface.md); after a diffuse bounce, and for integrators "
                  "without walks, C for every lobe with the diffuse lobe (Cycles' fallback)"),
              models::color("subsurface_color", "0.8", "Subsurface Color, in [0, 1]"),
              models::number("metallic", "0", "Metallic, in [0, 1]"),
              models::number(
                  "specular", "0.5",
                  "Specular, in [0, 1]: F0 = 0.08 specular; with specular = metallic = 0 there "
                  "is no specular lobe"),
              models::number("specular_tint", "0", "Specular Tint, in [0, 1]"),
              models::number("roughness", "0.5", "Roughness r, in [0, 1]: GGX alpha = r^2"),
              models::number(
                  "anisotropic", "0",
                  "Anisotropic, in [0, 1]: alpha_u = min(1, r^2 / a), alpha_v = min(1, r^2 a), "
                  "a = sqrt(1 - 0.9 anisotropic)"),
              models::number(
                  "anisotropic_rotation", "0",
                  "Anisotropic Rotation, in [0, 1]: the tangent turned by 2 pi times this"),
              models::number("sheen", "0", "Sheen, in [0, 1]"),
              models::number("sheen_tint", "0.5", "Sheen Tint, in [0, 1]"),
              models::number("clearcoat", "0", "Clearcoat, in [0, 1]: lobe weight 0.25 clearcoat"),
              models::number("clearcoat_roughness", "0.03",
                             "Clearcoat Roughness, in [0, 1]: GTR1 alpha = clearcoat_roughness^2"),
              models::number("ior", "1.45",
                             "IOR of the transmission (n_inside / n_outside), in [0.001, 100]"),
              models::number("transmission", "0", "Transmission, in [0, 1]"),
              models::number(
                  "transmission_roughness", "0",
                  "Transmission Roughness, in [0, 1]: refraction roughness 1 - (1 - r)(1 - this)"),
              models::text(
                  "distribution", "ggx",
                  "microfacet distribution: ggx (Cycles' GGX) or multi_ggx (Cycles' Multiscatter "
                  "GGX: for roughness > 0.075 the specular lobe takes the height-correlated G and "
                  "a "
                  "Kulla-Conty compensation lobe, so a white metal reflects everything)",
                  {"ggx", "multi_ggx"})},
             models::subsurface_walk_params("subsurface_")}),
        .read =
            [](ParamReader& r, ParamValues& v) {
                const PrincipledParams d;
                r.color(v, kBaseColor, d.base_color, 0.0, 1.0);
                const float subsurface = float(r.number(v, kSubsurface, d.subsurface, 0.0, 1.0));
                r.color(v, kSubsurfaceColor, d.subsurface_color, 0.0, 1.0);
                for (std::size_t i = kMetallic; i <= kTransmissionRoughness; ++i) {
                    if (i == kIor) continue;
                    r.number(v, i, double(d.*kNumbers[i - kMetallic]), 0.0, 1.0);
                }
                r.number(v, kIor, d.ior, 1e-3, models::kMaxIor);
                r.choice(v, kDistribution);
                read_subsurface_inputs(r, "subsurface_", subsurface);  // the checks
                read_subsurface_values(r, v, kRadius, kWalkIor, kAnisotropy, kMethod);
            },
        .make =
            [](const ParamValues& v, Children) {
                PrincipledParams p;
                p.base_color = v.color(kBaseColor);
                p.subsurface = float(v.number(kSubsurface));
                p.subsurface_color = v.color(kSubsurfaceColor);
                for (std::size_t i = kMetallic; i <= kTransmissionRoughness; ++i)
                    p.*kNumbers[i - kMetallic] = float(v.number(i));
                p.multiscatter = v.choice(kDistribution) == 1;
                const std::optional<SubsurfaceInputs> walk = make_subsurface_inputs(
                    v, v.color(kRadius) * p.subsurface, kWalkIor, kAnisotropy, kMethod);
                if (!walk) return Material(std::nullopt, std::nullopt, std::nullopt);
                const SubsurfaceInputs& in = *walk;
                Material fallback{PrincipledBxDF(p)};
                // Cycles' switch between its diffuse closure and the BSSRDF.
                const Rgb mixed = glm::mix(p.base_color, p.subsurface_color, p.subsurface);
                const float w_d = PrincipledBxDF::diffuse_weight(p);
                constexpr float kCut = PrincipledBxDF::kWeightCutoff;
                if (!(p.subsurface > kCut && w_d > kCut &&
                      (mixed.r + mixed.g + mixed.b) / 3.f > kCut && in.walked))
                    return fallback;
                Material::Subsurface s;
                s.lobe.weight = mixed * w_d;
                s.lobe.walk = SubsurfaceWalk::make(
                    mixed, subsurface_effective_radius(in.radius, mixed, in.ior, in.method),
                    in.anisotropy);
                s.lobe.fresnel = true;
                s.weight = (s.lobe.weight.r + s.lobe.weight.g + s.lobe.weight.b) / 3.f;
                const PrincipledBxDF surface = PrincipledBxDF::subsurface_surface(p);
                if (surface.flags() != BxDFFlags::None)
                    s.surface = pooled_material(Material(surface));
                return Material::with_subsurface(std::move(fallback), std::move(s));
            },
        .diffuse_param = "",
        .staged = StagedFamily::Principled,
        .pov_samples = true};
    return m;
}

}  // namespace facet
