// Reading a density grid from an OpenVDB file: the one file that includes OpenVDB's headers.
#pragma once

#include <cstddef>
#include <stdexcept>
#include <string>

#include "facet/render/density_grid.h"

namespace facet::render {

// The largest grid read: 512^3 voxels, 512 MiB of floats (DensityGrid::memory_bytes()).
constexpr std::size_t kMaxGridVoxels = std::size_t(512) * 512 * 512;

// A file that cannot be read, or a grid that is missing or unusable; `names_grid` when the
// fault is the grid's (its name, type or values), not the file's.
struct GridFileError : std::runtime_error {
    GridFileError(const std::string& what, bool grid)
        : std::runtime_error(what), names_grid(grid) {}
    bool names_grid;
};

// A grid read from a file: its values in index space (the box of its active voxels, voxel
// centres at integer coordinates) and the file's affine map from index space to its world.
struct VdbDensity {
    DensityGrid grid;
    glm::dmat4 file_from_index;
};

// The float grid `name` of the OpenVDB file `path`, densely over its active voxels' bounding
// box. Requires an affine transform, values finite and >= 0 (finite only with
// `allow_negative`: a temperature grid, clamped where it is used), at most kMaxGridVoxels
// voxels; otherwise GridFileError, whose message names the file (and the grid and voxel where
// it is the grid's fault).
VdbDensity read_openvdb_density(const std::string& path, const std::string& name,
                                bool allow_negative = false);

}  // namespace facet::render
