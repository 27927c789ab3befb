// ggx, beckmann, blinn: one microfacet lobe f = D G F / (4 cos_i cos_o) (facet/microfacet.h).
#include "model_unit.h"

namespace facet {

namespace {

// The parameters' indices in a lobe's table (ParamValues): reflectance, the roughness group
// (alpha or exponent, with _u and _v), the Fresnel group, energy_compensation.
enum Param : std::size_t { kReflectance, kRoughness, kFresnel = 4, kCompensation = 9 };

void read_lobe(ParamReader& r, ParamValues& v, const std::string& distribution) {
    r.color(v, kReflectance, Rgb(1.f), 0.0, 1.0);
    r.distribution(distribution);  // the checks (the other group's parameters forbidden)
    if (distribution == "blinn")
        read_roughness(r, v, kRoughness, 50.0, models::kMaxExponent);
    else
        read_roughness(r, v, kRoughness, 0.2, models::kMaxAlpha);
    read_fresnel(r, v, kFresnel);
    v[kCompensation] = DVec3(r.boolean(r.name(kCompensation), false) ? 1.0 : 0.0);
}

Material make_lobe(const ParamValues& v, DistributionKind kind) {
    return Material(
        std::nullopt,
        MicrofacetReflection(make_distribution(kind, v, kRoughness), make_fresnel(v, kFresnel),
                             v.color(kReflectance), v.flag(kCompensation)),
        std::nullopt);
}

ModelInfo lobe_model(std::string name, std::string d_doc, std::vector<ParamInfo> roughness,
                     void (*read)(ParamReader&, ParamValues&),
                     Material (*make)(const ParamValues&, Children)) {
    return {.name = std::move(name),
            .summary = std::move(d_doc),
            .params = models::concat({{models::color("reflectance", "1", "scale on F, in [0, 1]")},
                                      std::move(roughness),
                                      models::fresnel_params("none"),
                                      {models::energy_compensation_param()}}),
            .read = read,
            .make = make,
            .staged = StagedFamily::Microfacet,
            .pov_samples = true};
}

}  // namespace

const ModelInfo& ggx_model() {
    static const ModelInfo m = lobe_model(
        "ggx",
        "microfacet f = D G F / (4 cos_i cos_o) (eq. 2.37), GGX / Trowbridge-Reitz D, exact Smith "
        "height-correlated G, visible-normal sampling",
        models::alpha_params(), [](ParamReader& r, ParamValues& v) { read_lobe(r, v, "ggx"); },
        [](const ParamValues& v, Children) { return make_lobe(v, DistributionKind::GGX); });
    return m;
}

const ModelInfo& beckmann_model() {
    static const ModelInfo m = lobe_model(
        "beckmann",
        "microfacet f = D G F / (4 cos_i cos_o) (eq. 2.37), Beckmann D, exact Smith "
        "height-correlated G, visible-normal sampling",
        models::alpha_params(), [](ParamReader& r, ParamValues& v) { read_lobe(r, v, "beckmann"); },
        [](const ParamValues& v, Children) { return make_lobe(v, DistributionKind::Beckmann); });
    return m;
}

const ModelInfo& blinn_model() {
    static const ModelInfo m = lobe_model(
        "blinn",
        "microfacet with Blinn D = (kappa+2)/(2 pi) (n.h)^kappa (eq. 2.38), exact Smith G for this "
        "D (Student-t slopes)",
        models::exponent_params(), [](ParamReader& r, ParamValues& v) { read_lobe(r, v, "blinn"); },
        [](const ParamValues& v, Children) { return make_lobe(v, DistributionKind::Blinn); });
    return m;
}

}  // namespace facet
