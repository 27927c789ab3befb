// mirror: perfect specular reflection times a Fresnel term (facet/mirror.h).
#include "model_unit.h"

namespace facet {

const ModelInfo& mirror_model() {
    static const ModelInfo m{
        .name = "mirror",
        .summary = "perfect specular reflection, a delta lobe (eq. 2.27-2.29) times F",
        .params = models::concat({{models::color("reflectance", "1", "scale on F, in [0, 1]")},
                                  models::fresnel_params("none")}),
        .read =
            [](ParamReader& r, ParamValues& v) {
                r.color(v, 0, Rgb(1.f), 0.0, 1.0);  // reflectance
                read_fresnel(r, v, 1);
            },
        .make =
            [](const ParamValues& v, Children) {
                return Material(std::nullopt, std::nullopt,
                                MirrorReflection(make_fresnel(v, 1), v.color(0)));
            },
        .staged = StagedFamily::Mirror};
    return m;
}

}  // namespace facet
