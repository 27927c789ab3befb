// dielectric and thin_dielectric: transmissive interfaces (facet/dielectric.h). Inside is the
// side opposite the shape's normal.
#include "model_unit.h"

namespace facet {

namespace {

ParamInfo ior_param() {
    return models::number("ior", "1.5",
                          "relative index of refraction eta = n_inside / n_outside (the outside "
                          "is the side the shape's normal points to), in [0.001, 100]");
}
ParamInfo transmittance_param() {
    return models::color("transmittance", "1", "scale on the transmitted light (tint), in [0, 1]");
}

// dielectric's parameters' indices in its table (ParamValues).
enum Param : std::size_t { kIor, kTransmittance, kAlpha, kDistribution = 5, kCompensation };

}  // namespace

const ModelInfo& dielectric_model() {
    static const ModelInfo m{
        .name = "dielectric",
        .summary =
            "interface between two media (glass, water): exact Fresnel reflection + "
            "refraction, radiance scaled by 1/eta'^2 across it; smooth (alpha = 0: two "
            "delta lobes) or rough (Walter et al. 2007, Smith G, visible-normal sampling)",
        .params = {ior_param(), transmittance_param(),
                   models::number("alpha", "0",
                                  "isotropic roughness alpha, in [0, 10]; below 1e-4 the "
                                  "interface is smooth"),
                   models::number("alpha_u", "-",
                                  "roughness along the tangent u (anisotropic; give with "
                                  "alpha_v)"),
                   models::number("alpha_v", "-",
                                  "roughness along the bitangent v (anisotropic; give with "
                                  "alpha_u)"),
                   models::distribution_param("microfacet D of a rough interface: ggx or "
                                              "beckmann",
                                              {"ggx", "beckmann"}),
                   models::flag("energy_compensation", "false",
                                "rough, isotropic interfaces: add the multiple-scattering lobe "
                                "(Kulla & Conty 2017 extended to refraction, "
                                "facet/dielectric.h): reflection + transmission conserve energy "
                                "at transmittance 1")},
        .read =
            [](ParamReader& r, ParamValues& v) {
                r.number(v, kIor, 1.5, 1e-3, models::kMaxIor);
                r.color(v, kTransmittance, Rgb(1.f), 0.0, 1.0);
                r.choice(v, kDistribution);
                auto [au, av] = r.roughness_pair("alpha", 0.0, models::kMaxAlpha);
                read_roughness(r, v, kAlpha, 0.0, models::kMaxAlpha);
                const bool ec = r.boolean(r.name(kCompensation), false);
                v[kCompensation] = DVec3(ec ? 1.0 : 0.0);
                if (ec && au != av)
                    throw r.error(
                        "energy_compensation",
                        "is not available for anisotropic dielectrics (alpha_u != alpha_v)");
            },
        .make =
            [](const ParamValues& v, Children) {
                const MicrofacetDistribution d =
                    make_distribution(v.choice(kDistribution) == 0 ? DistributionKind::GGX
                                                                   : DistributionKind::Beckmann,
                                      v, kAlpha);
                // Compensation is isotropic only: textured alpha_u and alpha_v that differ at
                // a hit (build_scene checked the extremes) leave it out there.
                const auto [au, av] = make_roughness(v, kAlpha);
                return Material(DielectricBxDF(float(v.number(kIor)), v.color(kTransmittance), d,
                                               v.flag(kCompensation) && au == av));
            },
        .staged = StagedFamily::Dielectric,
        .pov_finish = false};
    return m;
}

const ModelInfo& thin_dielectric_model() {
    static const ModelInfo m{
        .name = "thin_dielectric",
        .summary =
            "thin pane (window glass): both interfaces' reflections summed, R' = R + "
            "T^2 R / (1 - R^2); transmission straight through with T' = 1 - R'",
        .params = {ior_param(), transmittance_param()},
        .read =
            [](ParamReader& r, ParamValues& v) {
                r.number(v, 0, 1.5, 1e-3, models::kMaxIor);  // ior
                r.color(v, 1, Rgb(1.f), 0.0, 1.0);           // transmittance
            },
        .make =
            [](const ParamValues& v, Children) {
                return Material(ThinDielectricBxDF(float(v.number(0)), v.color(1)));
            },
        .staged = StagedFamily::ThinDielectric,
        .pov_finish = false};
    return m;
}

}  // namespace facet
