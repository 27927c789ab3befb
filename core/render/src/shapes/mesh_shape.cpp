// Shape kind "mesh": a triangle mesh from arrays (positions, indices, optional normals) or
// from a file (.obj, .ply; load_mesh_file).
#include <cstring>
#include <filesystem>

#include "../io/pov_writer.h"
#include "../kind_build.h"
#include "../scene_checks.h"

namespace facet::render {

namespace {

// The mesh as given (arrays copied; normals as given, not normalised).
TriangleMesh triangles(const ShapeDesc& s, const std::string& base_dir) {
    if (!s.file.empty()) return load_mesh_file(resolve_scene_path(s.file, base_dir));
    const MeshData& md = s.mesh;
    TriangleMesh m;
    const std::size_t n = md.num_vertices();
    m.positions.resize(n);
    std::memcpy(m.positions.data(), md.positions.data(), n * sizeof(Vec3));
    m.indices.assign(md.indices.begin(), md.indices.end());
    if (md.normals.size() == md.positions.size() && !md.normals.empty()) {
        m.normals.resize(n);
        std::memcpy(m.normals.data(), md.normals.data(), n * sizeof(Vec3));
    }
    if (md.uvs.size() == 2 * n && n > 0) {
        m.uvs.resize(n);
        std::memcpy(m.uvs.data(), md.uvs.data(), n * sizeof(Vec2));
    }
    if (md.tangents.size() == 4 * n && n > 0) {
        m.tangents.resize(n);
        std::memcpy(m.tangents.data(), md.tangents.data(), n * sizeof(glm::vec4));
    }
    if (n > 0 && (md.colors.size() == 3 * n || md.colors.size() == 4 * n)) {
        // RGB gets alpha 1 (mesh.h).
        const std::size_t k = md.colors.size() / n;
        m.colors.resize(n);
        for (std::size_t i = 0; i < n; ++i)
            m.colors[i] = glm::vec4(md.colors[k * i], md.colors[k * i + 1], md.colors[k * i + 2],
                                    k == 4 ? md.colors[k * i + 3] : 1.f);
    }
    return m;
}

TriangleMesh checked_mesh(ShapeBuild& b) {
    const ShapeDesc& s = b.shape;
    const std::string& ptr = b.ptr;
    const MeshData& md = s.mesh;
    if (!s.file.empty()) {
        if (!md.positions.empty() || !md.indices.empty() || !md.normals.empty() ||
            !md.uvs.empty() || !md.tangents.empty() || !md.colors.empty()) {
            b.fail(ptr + "/file", "cannot be combined with mesh arrays (give one or the other)");
        }
        if (!b.files_allowed()) b.fail(ptr + "/file", "mesh files are disabled here");
        try {
            return triangles(s, b.base_dir());
        } catch (const std::exception& e) {
            b.fail(ptr + "/file", e.what());
        }
    }
    const std::string place = b.place();
    if (md.positions.empty() || md.positions.size() % 3 != 0) {
        b.fail(ptr + "/positions", "expected a flat array of 3n numbers (x0, y0, z0, x1, ...)");
    }
    if (md.indices.empty() || md.indices.size() % 3 != 0) {
        b.fail(ptr + "/indices", "expected a flat array of 3n vertex indices");
    }
    const std::size_t n = md.num_vertices();
    TriangleMesh m = triangles(s, b.base_dir());
    for (std::size_t i = 0; i < n; ++i) {
        if (!is_finite(m.positions[i])) {
            b.fail(place, "position " + std::to_string(i) + " is not finite");
        }
    }
    for (std::size_t i = 0; i < m.indices.size(); ++i) {
        if (m.indices[i] >= n) {
            b.fail(ptr + "/indices/" + std::to_string(i),
                   detail::int_range_message(m.indices[i], 0, std::int64_t(n) - 1));
        }
    }
    if (!md.normals.empty() && md.normals.size() != md.positions.size()) {
        b.fail(ptr + "/normals", "expected one normal per position (" + std::to_string(n) +
                                     "), got " + std::to_string(md.normals.size() / 3));
    }
    if (!md.uvs.empty() && md.uvs.size() != 2 * n) {
        b.fail(ptr + "/uvs", "expected one (u, v) pair per position (" + std::to_string(2 * n) +
                                 " numbers), got " + std::to_string(md.uvs.size()));
    }
    for (std::size_t i = 0; i < md.uvs.size(); ++i) {
        if (!std::isfinite(md.uvs[i]))
            b.fail(ptr + "/uvs/" + std::to_string(i), "must be a finite number");
    }
    if (!md.tangents.empty() && md.tangents.size() != 4 * n) {
        b.fail(ptr + "/tangents", "expected 4 numbers (x, y, z, bitangent sign) per position (" +
                                      std::to_string(4 * n) + " numbers), got " +
                                      std::to_string(md.tangents.size()));
    }
    for (std::size_t i = 0; i < md.tangents.size(); ++i) {
        if (!std::isfinite(md.tangents[i]))
            b.fail(ptr + "/tangents/" + std::to_string(i), "must be a finite number");
    }
    if (!md.colors.empty() && md.colors.size() != 3 * n && md.colors.size() != 4 * n) {
        b.fail(ptr + "/colors", "expected 3 (r, g, b) or 4 (r, g, b, a) numbers per position (" +
                                    std::to_string(3 * n) + " or " + std::to_string(4 * n) +
                                    " numbers), got " + std::to_string(md.colors.size()));
    }
    for (std::size_t i = 0; i < md.colors.size(); ++i) {
        if (!(md.colors[i] >= 0.f && md.colors[i] <= 1.f))
            b.fail(ptr + "/colors/" + std::to_string(i),
                   "must be a finite number in [0, 1] (a linear colour channel)");
    }
    for (std::size_t i = 0; i < m.tangents.size(); ++i) {
        if (!(glm::length(Vec3(m.tangents[i])) > 0.f))
            b.fail(ptr + "/tangents/" + std::to_string(4 * i),
                   "tangent " + std::to_string(i) + " is zero");
        if (m.tangents[i].w == 0.f)
            b.fail(ptr + "/tangents/" + std::to_string(4 * i + 3),
                   "the bitangent sign must be +1 or -1 (non-zero)");
    }
    for (std::size_t i = 0; i < m.normals.size(); ++i) {
        Vec3& v = m.normals[i];
        if (!is_finite(v)) b.fail(place, "normal " + std::to_string(i) + " is not finite");
        const float l = glm::length(v);
        if (!(l > 0.f)) b.fail(ptr + "/normals", "contains a zero normal");
        v /= l;
    }
    return m;
}

void build(ShapeBuild& b) {
    TriangleMesh m = checked_mesh(b);
    b.reserve_triangles(m.num_triangles(), b.ptr);
    b.add_triangles(std::move(m), Vec3(0.f));
}

}  // namespace

extern const ShapeKindDef kMeshKind{
    ShapeKind::Mesh,
    "mesh",
    "triangle mesh from flat arrays (`positions`, `indices`, optional `normals`, optional "
    "`uvs`) or from a `file`: `.obj` (tinyobjloader; polygons triangulated, vertex normals and "
    "texture coordinates `vt` kept when every corner has one, vertex colours `v x y z r g b` "
    "when every vertex has one, read as sRGB) or `.ply` (ascii or binary_little_endian; vertex "
    "x y z [nx ny nz] [u v | s t | texture_u texture_v] [red green blue [alpha]: uchar/ushort "
    "sRGB-encoded, float linear], face vertex_indices lists, fan-triangulated)",
    {{"positions", FieldType::MeshArrays, false, &ShapeDesc::mesh, "-",
      "flat arrays: `positions` [x0, y0, z0, x1, ...], `indices` (3 per triangle), optional "
      "`normals` (one per position: smooth shading), optional `uvs` [u0, v0, u1, ...] (one pair "
      "per position; needed when the material or emission is textured), optional `tangents` "
      "[x0, y0, z0, w0, x1, ...] (4 per position: the tangent along increasing u and the "
      "bitangent sign w, bitangent = w normal x tangent, glTF's TANGENT; computed as MikkTSpace "
      "does when a normal map or bump needs them and none are given), optional `colors` "
      "[r0, g0, b0, r1, ...] or [r0, g0, b0, a0, r1, ...] (3 or 4 per position: linear vertex "
      "colours, each in [0, 1], alpha 1 when 3; read by `{\"vertex_color\": true}` textures)"},
     {"file", FieldType::Path, false, &ShapeDesc::file, "-",
      "a mesh file (instead of the arrays), relative to the scene file"}},
    build,
    triangles,
    nullptr};

}  // namespace facet::render
