// Medium kind "homogeneous": constant absorption, scattering and emission inside the volume
// a shape bounds (a material's "interior") or everywhere (the scene's "world_medium"), with a
// Henyey-Greenstein phase function (facet/render/medium.h). Given as sigma_a and sigma_s, or
// in Cycles' Principled Volume terms (density, color, absorption_color: cycles_volume()).
#include "../kind_build.h"
#include "facet/render/medium.h"

namespace facet::render {

namespace {

Medium build(const MediumDesc& m, const std::string& ptr, const MediumBuild& b) {
    const float g = float(b.check_range(m.g, ptr + "/g", -HenyeyGreenstein::kMaxAbsG,
                                        HenyeyGreenstein::kMaxAbsG,
                                        "in [-0.999, 0.999] (Henyey-Greenstein anisotropy)"));
    const Rgb emission = b.check_color(m.emission, ptr + "/emission", "an emission");
    if (!m.density) {
        const char* cycles_only = "is a Cycles key: give it with \"density\"";
        if (m.color) b.fail(ptr + "/color", cycles_only);
        if (m.absorption_color) b.fail(ptr + "/absorption_color", cycles_only);
        const Rgb sa = b.check_color(m.sigma_a, ptr + "/sigma_a", "an absorption coefficient");
        const Rgb ss = b.check_color(m.sigma_s, ptr + "/sigma_s", "a scattering coefficient");
        return Medium::homogeneous(sa, ss, g, emission);
    }
    if (m.sigma_a != Vec3(0.f) || m.sigma_s != Vec3(0.f))
        b.fail(ptr + (m.sigma_a != Vec3(0.f) ? "/sigma_a" : "/sigma_s"),
               "give either sigma_a and sigma_s or Cycles' density and colours, not both");
    const double density =
        b.check_range(*m.density, ptr + "/density", 0.0, 1e30, ">= 0 (per scene unit)");
    const Rgb color = b.check_color(m.color.value_or(Vec3(0.5f)), ptr + "/color", "a colour");
    const Rgb absorption = b.check_color(m.absorption_color.value_or(Vec3(0.f)),
                                         ptr + "/absorption_color", "a colour");
    const MediumCoefficients c = cycles_volume(density, color, absorption);
    return Medium::homogeneous(c.sigma_a, c.sigma_s, g, emission);
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
