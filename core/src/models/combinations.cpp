// mix and add: combinations of two materials (facet/material.h, Material::mix / add).
#include "model_unit.h"

namespace facet {

const ModelInfo& mix_model() {
    static const ModelInfo m{
        .name = "mix",
        .summary =
            "blend of two materials (Blender's Mix Shader): f = (1 - w) f_a + w f_b, "
            "sampled by w",
        .params = {models::materials_param(),
                   models::number("weight", "0.5",
                                  "the weight w of b, in [0, 1] (factor = constant)"),
                   models::text(
                       "factor", "constant",
                       "where w comes from: constant (weight), or the view as a Mix "
                       "Shader's Fac linked to Blender's Fresnel node (fresnel: w = "
                       "F(abs(cos theta_o), ior)) or Layer Weight node (layer_fresnel: w = "
                       "F(abs(cos theta_o), 1 / (1 - blend)); layer_facing: w = 1 - abs(cos "
                       "theta_o)^b, b = 2 blend below 0.5, 0.5 / (1 - blend) above)",
                       {"constant", "fresnel", "layer_fresnel", "layer_facing"}),
                   models::number("ior", "1.45",
                                  "the Fresnel node's IOR (factor = fresnel), in [0, 100]"),
                   models::number("blend", "0.5",
                                  "the Layer Weight node's Blend (factor = layer_*), in [0, 1]")},
        .children = 2,
        .build =
            [](ParamReader& r, Children c) {
                using W = Material::MixWeight;
                const std::string factor = r.choice("factor");
                const std::string because = "with factor = " + factor;
                if (factor != "constant") r.forbid("weight", because);
                if (factor != "fresnel") r.forbid("ior", because);
                if (factor != "layer_fresnel" && factor != "layer_facing")
                    r.forbid("blend", because);
                if (factor == "constant")
                    return Material::mix(c[0], c[1], float(r.number("weight", 0.5, 0.0, 1.0)));
                if (factor == "fresnel")
                    return Material::mix(c[0], c[1], W::Fresnel,
                                         float(r.number("ior", 1.45, 0.0, models::kMaxIor)));
                return Material::mix(c[0], c[1],
                                     factor == "layer_fresnel" ? W::LayerFresnel : W::LayerFacing,
                                     float(r.number("blend", 0.5, 0.0, 1.0)));
            },
        .pov_finish = false};
    return m;
}

const ModelInfo& add_model() {
    static const ModelInfo m{
        .name = "add",
        .summary =
            "sum of two materials (Blender's Add Shader): f = f_a + f_b, each sampled "
            "with probability 1/2; may reflect more than it receives (the scene builder "
            "warns)",
        .params = {models::materials_param()},
        .children = 2,
        .build = [](ParamReader&, Children c) { return Material::add(c[0], c[1]); },
        .pov_finish = false};
    return m;
}

}  // namespace facet
