// Medium kind "grid": absorption and scattering that scale with a density read from a float
// grid of an OpenVDB file (media/openvdb_grid.cpp), over the grid's active voxels in world
// space; 0 outside them. Tracked against a majorant grid (facet/render/density_grid.h,
// facet/render/medium.h).
#include <optional>

#include "../kind_build.h"
#include "facet/render/medium.h"
#include "openvdb_grid.h"

namespace facet::render {

namespace {

Medium build(const MediumDesc& m, const std::string& ptr, const MediumBuild& b) {
    const MediumBuild::Coefficients c =
        b.coefficients(m, ptr, false, ">= 0 (a factor on the grid's values)");
    if (m.emission != Vec3(0.f))
        b.fail(ptr + "/emission", "a grid medium does not emit (not supported by this kind)");
    if (m.file.empty()) b.fail(ptr + "/file", "is required: an OpenVDB file (.vdb)");
    if (!b.files_allowed()) b.fail(ptr + "/file", "files are disabled here");
    const std::string path = resolve_scene_path(m.file, b.base_dir());
    std::optional<VdbDensity> vdb;
    try {
        vdb.emplace(read_openvdb_density(path, m.grid));
    } catch (const GridFileError& e) {
        b.fail(ptr + (e.names_grid ? "/grid" : "/file"), e.what());
    }
    // World from the grid's index space: the scene's placement after the file's own map.
    glm::dmat4 world_from_index = vdb->file_from_index;
    if (m.transform) {
        const glm::dmat4& x = *m.transform;
        bool finite = true;
        for (int c = 0; c < 4; ++c)
            for (int r = 0; r < 4; ++r) finite = finite && std::isfinite(x[c][r]);
        if (!finite || !(std::fabs(glm::determinant(glm::dmat3(x))) > 1e-12))
            b.fail(ptr + "/transform", "must be a finite, invertible affine transform");
        world_from_index = x * world_from_index;
    }
    const glm::dmat3 inv = glm::inverse(glm::dmat3(world_from_index));
    vdb->grid.set_world_to_grid(glm::mat3(inv), Vec3(-(inv * glm::dvec3(world_from_index[3]))));
    return Medium::grid(std::make_shared<const DensityGrid>(std::move(vdb->grid)), c.sigma_a,
                        c.sigma_s, c.g);
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
    "An optional `transform` (as a shape's) places the file's space in the world.",
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
    },
    &build};

}  // namespace facet::render
