// read_openvdb_density (openvdb_grid.h), through Debian's libopenvdb.
#include "openvdb_grid.h"

#include <mutex>
#include <sstream>

#include <openvdb/io/File.h>
#include <openvdb/openvdb.h>

namespace facet::render {

VdbDensity read_openvdb_density(const std::string& path, const std::string& name,
                                bool allow_negative) {
    static std::once_flag init;
    std::call_once(init, [] { openvdb::initialize(); });
    openvdb::GridBase::Ptr base;
    std::vector<std::string> names;
    try {
        openvdb::io::File file(path);
        file.open(false);  // no delayed loading: the file is read once, here
        for (auto it = file.beginName(); it != file.endName(); ++it) names.push_back(it.gridName());
        if (file.hasGrid(name)) base = file.readGrid(name);
        file.close();
    } catch (const openvdb::Exception& e) {
        throw GridFileError("'" + path + "': cannot read as an OpenVDB file (" + e.what() + ")",
                            false);
    }
    if (!base) {
        std::string list;
        for (const std::string& n : names) list += (list.empty() ? "" : ", ") + n;
        throw GridFileError("'" + path + "' has no grid '" + name +
                                "' (it has: " + (list.empty() ? "none" : list) + ")",
                            true);
    }
    const openvdb::FloatGrid::Ptr grid = openvdb::gridPtrCast<openvdb::FloatGrid>(base);
    const std::string where = "'" + path + "' grid '" + name + "'";
    if (!grid) throw GridFileError(where + " is a " + base->valueType() + " grid, not float", true);
    const openvdb::math::Transform& xf = grid->transform();
    if (!xf.isLinear())
        throw GridFileError(where + ": its transform is not affine (a frustum grid)", true);
    const openvdb::CoordBBox box = grid->evalActiveVoxelBoundingBox();
    if (box.empty()) throw GridFileError(where + " has no active voxels", true);
    const openvdb::Coord dim = box.dim();
    const std::size_t count = std::size_t(dim.x()) * std::size_t(dim.y()) * std::size_t(dim.z());
    if (count > kMaxGridVoxels)
        throw GridFileError(where + " has " + std::to_string(dim.x()) + "x" +
                                std::to_string(dim.y()) + "x" + std::to_string(dim.z()) +
                                " voxels in its active bounding box, more than 512^3",
                            true);
    // The grid's box in index space (voxel centres at integer coordinates), and the file's
    // affine map from index space to its world, read off by mapping the origin and the axes.
    const Vec3 lo(float(box.min().x()) - 0.5f, float(box.min().y()) - 0.5f,
                  float(box.min().z()) - 0.5f);
    const Vec3 hi(float(box.max().x()) + 0.5f, float(box.max().y()) + 0.5f,
                  float(box.max().z()) + 0.5f);
    glm::dmat4 file_from_index(1.0);
    const openvdb::Vec3d origin = xf.indexToWorld(openvdb::Vec3d(0.0));
    for (int a = 0; a < 3; ++a) {
        openvdb::Vec3d e(0.0);
        e[a] = 1.0;
        const openvdb::Vec3d col = xf.indexToWorld(e) - origin;
        file_from_index[a] = glm::dvec4(col.x(), col.y(), col.z(), 0.0);
    }
    file_from_index[3] = glm::dvec4(origin.x(), origin.y(), origin.z(), 1.0);
    if (!(std::fabs(glm::determinant(glm::dmat3(file_from_index))) > 0.0))
        throw GridFileError(where + ": its transform is singular", true);
    std::vector<float> values;
    values.reserve(count);
    const auto acc = grid->getConstAccessor();
    for (int k = box.min().z(); k <= box.max().z(); ++k)
        for (int j = box.min().y(); j <= box.max().y(); ++j)
            for (int i = box.min().x(); i <= box.max().x(); ++i) {
                const float v = acc.getValue(openvdb::Coord(i, j, k));
                if (!(v >= 0.f || allow_negative) || !std::isfinite(v)) {
                    std::ostringstream s;
                    s << where << ": voxel (" << i << ", " << j << ", " << k << ") is " << v
                      << (allow_negative ? " (values are finite)"
                                         : " (values are finite and >= 0)");
                    throw GridFileError(s.str(), true);
                }
                values.push_back(v);
            }
    return {DensityGrid({dim.x(), dim.y(), dim.z()}, lo, hi, std::move(values)), file_from_index};
}

}  // namespace facet::render
