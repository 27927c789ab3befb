// mix and add: combinations of two materials (facet/material.h, Material::mix / add).
#include "model_unit.h"

namespace facet {

namespace {
// mix's parameters' indices in its table (ParamValues), and its factor's choices.
enum Param : std::size_t { kMaterials, kWeight, kFactor, kIor, kBlend };
enum Factor : int { kConstant, kFresnel, kLayerFresnel, kLayerFacing };
}  // namespace

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
        .read =
            [](ParamReader& r, ParamValues& v) {
                const int factor = r.choice(v, kFactor);
                const std::string because = "with factor = " + r.choice(r.name(kFactor));
                if (factor != kConstant) r.forbid("weight", because);
                if (factor != kFresnel) r.forbid("ior", because);
                if (factor != kLayerFresnel && factor != kLayerFacing) r.forbid("blend", because);
                if (factor == kConstant) r.number(v, kWeight, 0.5, 0.0, 1.0);
                if (factor == kFresnel) r.number(v, kIor, 1.45, 0.0, models::kMaxIor);
                if (factor == kLayerFresnel || factor == kLayerFacing)
                    r.number(v, kBlend, 0.5, 0.0, 1.0);
            },
        .make =
            [](const ParamValues& v, Children c) {
                using W = Material::MixWeight;
                const int factor = v.choice(kFactor);
                if (factor == kConstant) return Material::mix(c[0], c[1], float(v.number(kWeight)));
                if (factor == kFresnel)
                    return Material::mix(c[0], c[1], W::Fresnel, float(v.number(kIor)));
                return Material::mix(c[0], c[1],
                                     factor == kLayerFresnel ? W::LayerFresnel : W::LayerFacing,
                                     float(v.number(kBlend)));
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
        .read = [](ParamReader&, ParamValues&) {},
        .make = [](const ParamValues&, Children c) { return Material::add(c[0], c[1]); },
        .pov_finish = false};
    return m;
}

}  // namespace facet
