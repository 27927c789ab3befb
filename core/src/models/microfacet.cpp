// ggx, beckmann, blinn: one microfacet lobe f = D G F / (4 cos_i cos_o) (facet/microfacet.h).
#include "model_unit.h"

namespace facet {

namespace {

Material build_lobe(ParamReader& r, const std::string& distribution) {
    const Rgb scale = r.color("reflectance", Rgb(1.f), 0.0, 1.0);
    const MicrofacetDistribution d = r.distribution(distribution);
    const Fresnel fr = r.fresnel();
    const bool ec = r.boolean("energy_compensation", false);
    return Material(std::nullopt, MicrofacetReflection(d, fr, scale, ec), std::nullopt);
}

ModelInfo lobe_model(std::string name, std::string d_doc, std::vector<ParamInfo> roughness,
                     Material (*build)(ParamReader&, Children)) {
    return {.name = std::move(name),
            .summary = std::move(d_doc),
            .params = models::concat({{models::color("reflectance", "1", "scale on F, in [0, 1]")},
                                      std::move(roughness),
                                      models::fresnel_params("none"),
                                      {models::energy_compensation_param()}}),
            .build = build,
            .staged = StagedFamily::Microfacet,
            .pov_samples = true};
}

}  // namespace

const ModelInfo& ggx_model() {
    static const ModelInfo m = lobe_model(
        "ggx",
        "microfacet f = D G F / (4 cos_i cos_o) (eq. 2.37), GGX / Trowbridge-Reitz D, exact Smith "
        "height-correlated G, visible-normal sampling",
        models::alpha_params(), [](ParamReader& r, Children) { return build_lobe(r, "ggx"); });
    return m;
}

const ModelInfo& beckmann_model() {
    static const ModelInfo m = lobe_model(
        "beckmann",
        "microfacet f = D G F / (4 cos_i cos_o) (eq. 2.37), Beckmann D, exact Smith "
        "height-correlated G, visible-normal sampling",
        models::alpha_params(), [](ParamReader& r, Children) { return build_lobe(r, "beckmann"); });
    return m;
}

const ModelInfo& blinn_model() {
    static const ModelInfo m = lobe_model(
        "blinn",
        "microfacet with Blinn D = (kappa+2)/(2 pi) (n.h)^kappa (eq. 2.38), exact Smith G for this "
        "D (Student-t slopes)",
        models::exponent_params(), [](ParamReader& r, Children) { return build_lobe(r, "blinn"); });
    return m;
}

}  // namespace facet
