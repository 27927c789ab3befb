// principled: Blender 3.4's Principled BSDF as Cycles evaluates it (facet/principled.h).
#include "model_unit.h"

namespace facet {

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
        .build =
            [](ParamReader& r, Children) {
                PrincipledParams p;
                auto unit = [&](const char* key, float def) {
                    return float(r.number(key, def, 0.0, 1.0));
                };
                p.base_color = r.color("base_color", p.base_color, 0.0, 1.0);
                p.subsurface = unit("subsurface", p.subsurface);
                p.subsurface_color = r.color("subsurface_color", p.subsurface_color, 0.0, 1.0);
                p.metallic = unit("metallic", p.metallic);
                p.specular = unit("specular", p.specular);
                p.specular_tint = unit("specular_tint", p.specular_tint);
                p.roughness = unit("roughness", p.roughness);
                p.anisotropic = unit("anisotropic", p.anisotropic);
                p.anisotropic_rotation = unit("anisotropic_rotation", p.anisotropic_rotation);
                p.sheen = unit("sheen", p.sheen);
                p.sheen_tint = unit("sheen_tint", p.sheen_tint);
                p.clearcoat = unit("clearcoat", p.clearcoat);
                p.clearcoat_roughness = unit("clearcoat_roughness", p.clearcoat_roughness);
                p.ior = float(r.number("ior", p.ior, 1e-3, models::kMaxIor));
                p.transmission = unit("transmission", p.transmission);
                p.transmission_roughness = unit("transmission_roughness", p.transmission_roughness);
                p.multiscatter = r.choice("distribution") == "multi_ggx";
                const SubsurfaceInputs in = read_subsurface_inputs(r, "subsurface_", p.subsurface);
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
                const PrincipledBxDF surface = PrincipledBxDF::subsurface_surface(p);
                if (surface.flags() != BxDFFlags::None) {
                    s.surface = std::make_shared<const Material>(surface);
                    // Cycles' sample weights: the BSSRDF's mean weight times its 3 channels;
                    // the surface closures' sum is taken as 1 here (a selection probability:
                    // any positive choice is unbiased).
                    const float m = s.lobe.weight.r + s.lobe.weight.g + s.lobe.weight.b;
                    s.probability = m / (m + 1.f);
                }
                return Material::with_subsurface(std::move(fallback), std::move(s));
            },
        .diffuse_param = "",
        .staged = StagedFamily::Principled,
        .pov_samples = true};
    return m;
}

}  // namespace facet
