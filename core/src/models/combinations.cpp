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
                   models::number("weight", "0.5", "the weight w of b, in [0, 1]")},
        .children = 2,
        .build =
            [](ParamReader& r, Children c) {
                return Material::mix(c[0], c[1], float(r.number("weight", 0.5, 0.0, 1.0)));
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
