// composite: diffuse + glossy + mirror (facet/material.h).
#include "model_unit.h"

namespace facet {

namespace {
// The parameters' indices in the table (ParamValues), and the distribution's choices.
enum Param : std::size_t {
    kDiffuse,
    kGlossy,
    kMirror,
    kDistribution,
    kAlpha,
    kExponent = 7,
    kFresnel = 10,
    kCompensation = 15
};
enum Kind : int { kGgx, kBeckmann, kBlinn };
}  // namespace

const ModelInfo& composite_model() {
    static const ModelInfo m{
        .name = "composite",
        .summary =
            "diffuse + glossy + mirror (Cohen & Wallace §2.5.5); diffuse gets what the "
            "specular lobes leave",
        .params = models::concat(
            {{models::color("diffuse_reflectance", "0.5", "rho_d of the diffuse lobe, in [0, 1]"),
              models::color("glossy_reflectance", "1",
                            "scale on the glossy lobe, in [0, 1]; glossy + mirror <= 1"),
              models::color("mirror_reflectance", "0", "scale on the mirror lobe, in [0, 1]"),
              models::distribution_param("glossy D: ggx, beckmann or blinn",
                                         {"ggx", "beckmann", "blinn"})},
             models::alpha_params(),
             models::exponent_params(),
             models::fresnel_params("dielectric"),
             {models::energy_compensation_param()}}),
        .read =
            [](ParamReader& r, ParamValues& v) {
                r.color(v, kDiffuse, Rgb(0.5f), 0.0, 1.0);
                const Rgb ks = r.color(v, kGlossy, Rgb(1.f), 0.0, 1.0);
                const Rgb km = r.color(v, kMirror, Rgb(0.f), 0.0, 1.0);
                for (int c = 0; c < 3; ++c)
                    if (ks[c] + km[c] > 1.f + 1e-6f)
                        throw r.error(
                            "mirror_reflectance",
                            "glossy_reflectance + mirror_reflectance must be <= 1 per channel "
                            "(energy conservation)");
                const int kind = r.choice(v, kDistribution);
                r.distribution(r.choice(r.name(kDistribution)));  // the checks
                if (kind == kBlinn)
                    read_roughness(r, v, kExponent, 50.0, models::kMaxExponent);
                else
                    read_roughness(r, v, kAlpha, 0.2, models::kMaxAlpha);
                read_fresnel(r, v, kFresnel);
                v[kCompensation] = DVec3(r.boolean(r.name(kCompensation), false) ? 1.0 : 0.0);
            },
        .make =
            [](const ParamValues& v, Children) {
                const int kind = v.choice(kDistribution);
                const MicrofacetDistribution d =
                    kind == kBlinn      ? make_distribution(DistributionKind::Blinn, v, kExponent)
                    : kind == kBeckmann ? make_distribution(DistributionKind::Beckmann, v, kAlpha)
                                        : make_distribution(DistributionKind::GGX, v, kAlpha);
                return Material::composite(v.color(kDiffuse), v.color(kGlossy), v.color(kMirror), d,
                                           make_fresnel(v, kFresnel), v.flag(kCompensation));
            },
        .diffuse_param = "diffuse_reflectance",
        .diffuse_lobe = true,
        .staged = StagedFamily::Composite,
        .pov_samples = true};
    return m;
}

}  // namespace facet
