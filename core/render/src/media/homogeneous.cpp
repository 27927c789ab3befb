// Medium kind "homogeneous": constant absorption, scattering and emission inside the volume
// a shape bounds (a material's "interior") or everywhere (the scene's "world_medium"), with a
// Henyey-Greenstein phase function (facet/render/medium.h). Given as sigma_a and sigma_s, or
// in Cycles' Principled Volume terms (density, color, absorption_color: cycles_volume()).
#include "../kind_build.h"
#include "facet/render/medium.h"

namespace facet::render {

namespace {

Medium build(const MediumDesc& m, const std::string& ptr, const MediumBuild& b) {
    const MediumBuild::Coefficients c = b.coefficients(m, ptr, true, ">= 0 (per scene unit)");
    const Rgb emission = b.check_color(m.emission, ptr + "/emission", "an emission");
    return Medium::homogeneous(c.sigma_a, c.sigma_s, c.g, emission);
}

}  // namespace

extern const MediumKindDef kHomogeneousMediumKind{
    MediumKind::Homogeneous,
    "homogeneous",
    "Constant coefficients: sigma_t = sigma_a + sigma_s per scene unit; transmittance "
    "exp(-sigma_t d) (Beer-Lambert). Give `sigma_a` and `sigma_s`, or Cycles' Principled Volume "
    "`density`, `color`, `absorption_color` (sigma_s = density color, sigma_a = density "
    "max(1 - color, 0) max(1 - sqrt(absorption_color), 0)), not both.",
    {
        {"sigma_a", FieldType::Color, false, &MediumDesc::sigma_a, "0",
         "absorption coefficient per scene unit, >= 0"},
        {"sigma_s", FieldType::Color, false, &MediumDesc::sigma_s, "0",
         "scattering coefficient per scene unit, >= 0"},
        {"g", FieldType::Number, false, &MediumDesc::g, "0",
         "Henyey-Greenstein anisotropy in [-0.999, 0.999]; > 0 forward (Cycles' Anisotropy)"},
        {"emission", FieldType::Color, false, &MediumDesc::emission, "0",
         "emitted radiance per scene unit of length, >= 0 (Cycles: Emission Strength x "
         "Emission Color)"},
        {"density", FieldType::Number, false, &MediumDesc::density, "-",
         "Cycles' Density, >= 0 (instead of sigma_a, sigma_s)"},
        {"color", FieldType::Color, false, &MediumDesc::color, "0.5",
         "Cycles' Color (scattering colour), with density"},
        {"absorption_color", FieldType::Color, false, &MediumDesc::absorption_color, "0",
         "Cycles' Absorption Color, with density"},
    },
    &build};

}  // namespace facet::render
