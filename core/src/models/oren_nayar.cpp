// oren_nayar: rough diffuse reflection as Cycles' Diffuse BSDF (facet/oren_nayar.h).
#include "model_unit.h"

namespace facet {

const ModelInfo& oren_nayar_model() {
    static const ModelInfo m{
        .name = "oren_nayar",
        .summary =
            "rough diffuse reflection as Cycles' Diffuse BSDF with roughness: f = rho (A "
            "+ B t), A = 1 / (pi + (3 pi - 4) / 6 sigma), B = sigma A, t = s / "
            "max(cos_i, cos_o) for s = wi.wo - cos_i cos_o > 0, else s (Fujii 2012)",
        .params = {models::color("reflectance", "0.5", "diffuse reflectance rho, in [0, 1]"),
                   models::number("sigma", "0.5",
                                  "roughness as Blender's Diffuse BSDF Roughness (not radians), "
                                  "in [0, 1]; 0 is Lambert")},
        .read =
            [](ParamReader& r, ParamValues& v) {
                r.color(v, 0, Rgb(0.5f), 0.0, 1.0);  // reflectance
                r.number(v, 1, 0.5, 0.0, 1.0);       // sigma
            },
        .make =
            [](const ParamValues& v, Children) {
                return Material(InlineBxDF(OrenNayarReflection(v.color(0), float(v.number(1)))));
            },
        .diffuse_param = "reflectance",
        .staged = StagedFamily::OrenNayar};
    return m;
}

}  // namespace facet
