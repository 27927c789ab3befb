// lambert: ideal diffuse reflection (facet/lambert.h).
#include "model_unit.h"

namespace facet {

const ModelInfo& lambert_model() {
    static const ModelInfo m{
        .name = "lambert",
        .summary = "ideal diffuse reflection f = rho/pi (Cohen & Wallace eq. 2.33-2.36)",
        .params = {models::color("reflectance", "0.5", "diffuse reflectance rho, in [0, 1]")},
        .read = [](ParamReader& r,
                   ParamValues& v) { r.color(v, 0, Rgb(0.5f), 0.0, 1.0); },  // reflectance
        .make =
            [](const ParamValues& v, Children) {
                return Material(LambertReflection(v.color(0)), std::nullopt, std::nullopt);
            },
        .diffuse_param = "reflectance",
        .diffuse_lobe = true,
        .diffuse_black_ok = true,
        .staged = StagedFamily::Lambert};
    return m;
}

}  // namespace facet
