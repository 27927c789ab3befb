// composite: diffuse + glossy + mirror (facet/material.h).
#include "model_unit.h"

namespace facet {

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
        .build =
            [](ParamReader& r, Children) {
                const Rgb kd = r.color("diffuse_reflectance", Rgb(0.5f), 0.0, 1.0);
                const Rgb ks = r.color("glossy_reflectance", Rgb(1.f), 0.0, 1.0);
                const Rgb km = r.color("mirror_reflectance", Rgb(0.f), 0.0, 1.0);
                for (int c = 0; c < 3; ++c)
                    if (ks[c] + km[c] > 1.f + 1e-6f)
                        throw r.error(
                            "mirror_reflectance",
                            "glossy_reflectance + mirror_reflectance must be <= 1 per channel "
                            "(energy conservation)");
                const MicrofacetDistribution d = r.distribution(r.choice("distribution"));
                const Fresnel fr = r.fresnel();
                const bool ec = r.boolean("energy_compensation", false);
                return Material::composite(kd, ks, km, d, fr, ec);
            },
        .diffuse_param = "diffuse_reflectance",
        .diffuse_lobe = true,
        .staged = StagedFamily::Composite,
        .pov_samples = true};
    return m;
}

}  // namespace facet
