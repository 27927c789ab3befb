// Medium kind "grid": absorption and scattering that scale with a density read from a float
// grid of an OpenVDB file (media/openvdb_grid.cpp), over the grid's active voxels in world
// space; 0 outside them. Tracked against a majorant grid (facet/render/density_grid.h,
// facet/render/medium.h).
#include <optional>

#include "../kind_build.h"
#include "facet/blackbody.h"
#include "facet/render/medium.h"
#include "openvdb_grid.h"

namespace facet::render {

Rgb GridEmission::at(const Vec3& p) const {
    Rgb e = grid ? color * grid->density(p) : color;
    if (blackbody > 0.f) {
        const float t = temperature_grid
                            ? temperature * std::fmax(temperature_grid->density(p), 0.f)
                            : temperature;
        e += principled_volume_blackbody(blackbody, t, tint);
    }
    return e;
}

namespace {

// The world placement of a grid read from the file: the scene's transform after the file's
// own map from the grid's index space.
void place(VdbDensity& vdb, const std::optional<glm::dmat4>& transform) {
    glm::dmat4 world_from_index = vdb.file_from_index;
    if (transform) world_from_index = *transform * world_from_index;
    const glm::dmat3 inv = glm::inverse(glm::dmat3(world_from_index));
    vdb.grid.set_world_to_grid(glm::mat3(inv), Vec3(-(inv * glm::dvec3(world_from_index[3]))));
}

Medium build(const MediumDesc& m, const std::string& ptr, const MediumBuild& b) {
    const MediumBuild::Coefficients c =
        b.coefficients(m, ptr, false, ">= 0 (a factor on the grid's values)");
    const Rgb emission = b.check_color(m.emission, ptr + "/emission", "an emission");
    const float blackbody =
        float(b.check_range(m.blackbody_intensity, ptr + "/blackbody_intensity", 0.0, 1.0,
                            "in [0, 1] (Cycles' Blackbody Intensity)"));
    const float temperature =
        float(b.check_range(m.temperature, ptr + "/temperature", 0.0, 1e6, "in [0, 1e6] (kelvin)"));
    const Rgb tint = b.check_color(m.blackbody_tint, ptr + "/blackbody_tint", "a colour");
    if (m.file.empty()) b.fail(ptr + "/file", "is required: an OpenVDB file (.vdb)");
    if (!b.files_allowed()) b.fail(ptr + "/file", "files are disabled here");
    if (m.transform) {
        const glm::dmat4& x = *m.transform;
        bool finite = true;
        for (int col = 0; col < 4; ++col)
            for (int r = 0; r < 4; ++r) finite = finite && std::isfinite(x[col][r]);
        if (!finite || !(std::fabs(glm::determinant(glm::dmat3(x))) > 1e-12))
            b.fail(ptr + "/transform", "must be a finite, invertible affine transform");
    }
    const std::string path = resolve_scene_path(m.file, b.base_dir());
    // A grid of the file, placed in the world; errors name `key` for the grid's faults.
    auto read = [&](const std::string& name, const std::string& key, bool allow_negative) {
        std::optional<VdbDensity> vdb;
        try {
            vdb.emplace(read_openvdb_density(path, name, allow_negative));
        } catch (const GridFileError& e) {
            b.fail(ptr + (e.names_grid ? key : "/file"), e.what());
        }
        place(*vdb, m.transform);
        return std::make_shared<const DensityGrid>(std::move(vdb->grid));
    };
    std::shared_ptr<const DensityGrid> density = read(m.grid, "/grid", false);
    std::shared_ptr<const GridEmission> emits;
    const bool has_emission = emission != Rgb(0.f), has_blackbody = blackbody > 0.f;
    if (!m.emission_grid.empty() && !has_emission)
        b.fail(ptr + "/emission_grid", "needs \"emission\" > 0 (the grid scales it)");
    if (!m.temperature_grid.empty() && !has_blackbody)
        b.fail(ptr + "/temperature_grid", "needs \"blackbody_intensity\" > 0");
    if (has_emission || has_blackbody) {
        auto e = std::make_shared<GridEmission>();
        e->color = emission;
        if (!m.emission_grid.empty())
            e->grid = m.emission_grid == m.grid ? density
                                                : read(m.emission_grid, "/emission_grid", false);
        e->blackbody = blackbody;
        e->temperature = temperature;
        e->tint = tint;
        if (has_blackbody && !m.temperature_grid.empty())
            e->temperature_grid = read(m.temperature_grid, "/temperature_grid", true);
        emits = std::move(e);
    }
    return Medium::grid(std::move(density), c.sigma_a, c.sigma_s, c.g, std::move(emits));
}

}  // namespace

extern const MediumKindDef kGridMediumKind{
    MediumKind::Grid,
    "grid",
    "Heterogeneous: a float grid of an OpenVDB file (`file`, `grid`) scales the coefficients, "
    "sigma(x) = value(x) sigma per unit, with the values trilinearly interpolated between "
    "voxel centres over the grid's active voxels in the file's world space (0 outside). "
    "Coefficients per unit value as `sigma_a`, `sigma_s`, or Cycles' `density` (a factor), "
    "`color`, `absorption_color` as for `homogeneous`. At most 512^3 voxels (4 bytes each). "
    "An optional `transform` (as a shape's) places the file's space in the world. Emission "
    "(radiance per unit length, not scaled by the density: Cycles' Principled Volume) over the "
    "density grid's box: `emission` times the grid `emission_grid` (constant without one), "
    "plus blackbody emission blackbody_tint (5.670373e-14 / pi) mix(1, T^4, "
    "blackbody_intensity) rgb(T) at T = `temperature` times the grid `temperature_grid` (clamped "
    "to >= 0; constant without "
    "one), rgb(T) Cycles' blackbody colour (docs/media.md).",
    {
        {"file", FieldType::Path, true, &MediumDesc::file, "-",
         "an OpenVDB file (.vdb), relative to the scene file"},
        {"grid", FieldType::Text, false, &MediumDesc::grid, "density",
         "the name of a float grid in `file` (Blender: density, or a Mesh to Volume's grid)"},
        {"sigma_a", FieldType::Color, false, &MediumDesc::sigma_a, "0",
         "absorption coefficient per unit grid value per scene unit, >= 0"},
        {"sigma_s", FieldType::Color, false, &MediumDesc::sigma_s, "0",
         "scattering coefficient per unit grid value per scene unit, >= 0"},
        {"g", FieldType::Number, false, &MediumDesc::g, "0",
         "Henyey-Greenstein anisotropy in [-0.999, 0.999]; > 0 forward (Cycles' Anisotropy)"},
        {"density", FieldType::Number, false, &MediumDesc::density, "1",
         "Cycles' Density, >= 0: a factor on the grid's values (instead of sigma_a, sigma_s)"},
        {"color", FieldType::Color, false, &MediumDesc::color, "0.5",
         "Cycles' Color (scattering colour), with density"},
        {"absorption_color", FieldType::Color, false, &MediumDesc::absorption_color, "0",
         "Cycles' Absorption Color, with density"},
        {"emission", FieldType::Color, false, &MediumDesc::emission, "0",
         "emitted radiance per scene unit of length, >= 0 (Cycles: Emission Strength x Emission "
         "Color)"},
        {"emission_grid", FieldType::Text, false, &MediumDesc::emission_grid, "-",
         "a float grid of `file` (>= 0) that scales `emission` (Cycles: an Attribute node on "
         "Emission Strength); without it the emission is constant over the box"},
        {"blackbody_intensity", FieldType::Number, false, &MediumDesc::blackbody_intensity, "0",
         "Cycles' Blackbody Intensity, in [0, 1] (1: the Stefan-Boltzmann radiance)"},
        {"blackbody_tint", FieldType::Color, false, &MediumDesc::blackbody_tint, "1",
         "Cycles' Blackbody Tint"},
        {"temperature", FieldType::Number, false, &MediumDesc::temperature, "1000",
         "Cycles' Temperature in kelvin, in [0, 1e6]; a factor on `temperature_grid` when given"},
        {"temperature_grid", FieldType::Text, false, &MediumDesc::temperature_grid, "-",
         "a float grid of `file` for the temperature (Cycles' Temperature Attribute; negative "
         "values count as 0), with blackbody_intensity > 0"},
    },
    &build};

}  // namespace facet::render
