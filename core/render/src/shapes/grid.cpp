// Shape kind "grid": nx x ny cells over [-1, 1]^2 (z = 0, facing +z), optionally displaced.
#include "../io/pov_writer.h"
#include "../kind_build.h"
#include "../scene_checks.h"

namespace facet::render {

namespace {

TriangleMesh triangles(const ShapeDesc& s, const std::string&) {
    return make_grid(s.nx, s.ny, float(s.amplitude), float(s.frequency));
}

void build(ShapeBuild& b) {
    const ShapeDesc& s = b.shape;
    const std::int64_t nx = b.check_int(s.nx, b.ptr + "/nx", 1, detail::kMaxGridSide);
    const std::int64_t ny = b.check_int(s.ny, b.ptr + "/ny", 1, detail::kMaxGridSide);
    if (nx * ny > detail::kMaxGridCells) {
        b.fail(b.ptr,
               "grid too large: nx * ny must be <= " + std::to_string(detail::kMaxGridCells));
    }
    (void)b.check_range(s.amplitude, b.ptr + "/amplitude", -1e6, 1e6, "in [-1e6, 1e6]");
    (void)b.check_range(s.frequency, b.ptr + "/frequency", 0.0, 1e6, "in [0, 1e6]");
    b.reserve_triangles(2ull * std::uint64_t(nx) * std::uint64_t(ny), b.ptr);
    b.add_triangles(triangles(s, b.base_dir()), Vec3(1.f, 0.f, 0.f));
}

}  // namespace

extern const ShapeKindDef kGridKind{
    ShapeKind::Grid,
    "grid",
    "`nx × ny` cells over [−1, 1]² in the z = 0 plane facing +z (2·nx·ny triangles), "
    "displaced by `amplitude · sin(frequency·x) · sin(frequency·y)`; place it with `transform`",
    {{"nx", FieldType::Integer, true, &ShapeDesc::nx, "-", "cells along x", 1,
      detail::kMaxGridSide},
     {"ny", FieldType::Integer, true, &ShapeDesc::ny, "-", "cells along y", 1,
      detail::kMaxGridSide},
     {"amplitude", FieldType::Number, false, &ShapeDesc::amplitude, "0",
      "displacement, in [-1e6, 1e6]"},
     {"frequency", FieldType::Number, false, &ShapeDesc::frequency, "0", "f, in [0, 1e6]"}},
    build,
    triangles,
    nullptr};

}  // namespace facet::render
