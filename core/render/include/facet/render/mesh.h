// Triangle meshes for the scene layer: procedural generators and file readers.
//
// Conventions:
//  - Triangles are index triples into `positions`; the front side is the counter-clockwise one,
//    n = cross(p1 - p0, p2 - p0) (scene.h). `normals` is empty or holds one unit vertex normal
//    per position (used for smooth shading only; geometry stays flat). `uvs` is empty or holds
//    one texture coordinate per position: (0, 0) the bottom-left corner of an image, v up
//    (scenes/FORMAT.md, "UV coordinates"); the generators below give each kind's documented UVs.
//    `tangents` is empty or holds one per position: xyz the tangent (the direction of increasing
//    u), w the bitangent sign, bitangent = w cross(normal, tangent) (glTF's TANGENT).
//    `colors` is empty or holds one vertex colour per position: linear RGBA, each channel in
//    [0, 1] (alpha 1 where the source has none); a hit interpolates them barycentrically
//    (scenes/FORMAT.md, "Vertex colours").
//  - Readers throw std::runtime_error with a message naming the line / element at fault (the
//    scene loader prefixes the file and JSON path); they never crash on malformed input.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include <glm/vec4.hpp>

#include "facet/types.h"

namespace facet::render {

struct TriangleMesh {
    std::vector<Vec3> positions;
    std::vector<Vec3> normals;           // empty, or one per position
    std::vector<Vec2> uvs;               // empty, or one per position
    std::vector<glm::vec4> tangents;     // empty, or one per position (xyz, bitangent sign)
    std::vector<glm::vec4> colors;       // empty, or one per position (linear RGBA in [0, 1])
    std::vector<std::uint32_t> indices;  // 3 per triangle
    std::size_t num_triangles() const { return indices.size() / 3; }
};

// Axis-aligned box [lo, hi], outward facing, 12 triangles, flat; 4 vertices per face so that
// each face has its own UVs: [0, 1]^2, v toward +y on the side faces (+-x, +-z), toward -z on
// the top (+y) and toward +z on the bottom (-y), each read unmirrored from outside.
TriangleMesh make_box(const Vec3& lo, const Vec3& hi);
// Quad p0 p1 p2 p3 (counter-clockwise seen from the front) as triangles (p0 p1 p2), (p0 p2 p3);
// UVs p0 (0, 0), p1 (1, 0), p2 (1, 1), p3 (0, 1).
TriangleMesh make_quad(const std::array<Vec3, 4>& p);
// Unit sphere at the origin: an icosahedron subdivided `subdivisions` times (20 * 4^s
// triangles), outward facing; smooth = vertex normals = positions.
TriangleMesh make_icosphere(int subdivisions, bool smooth);
// nx x ny cells over [-1, 1]^2 in the z = 0 plane, 2 nx ny triangles facing +z; optionally
// displaced by z = amplitude * sin(frequency x) * sin(frequency y) (with matching normals);
// UVs ((x + 1) / 2, (y + 1) / 2) of the undisplaced grid.
TriangleMesh make_grid(int nx, int ny, float amplitude, float frequency);

// Wavefront OBJ (tinyobjloader; polygons are triangulated, vertex normals kept when every
// corner has one, texture coordinates `vt` likewise; vertex colours from `v x y z r g b` lines,
// taken as linear RGB as tinyobjloader reads them, when every vertex has them).
TriangleMesh load_obj(const std::string& path);
// PLY, ascii or binary_little_endian: element vertex with float/double x y z (optional nx ny
// nz; optional u v, or s t, or texture_u texture_v; optional red green blue [alpha]: uchar
// values are sRGB-encoded bytes, decoded with the sRGB curve (as Blender's PLY importer reads
// them), alpha linearly as a / 255; float values are linear), element face with a list of vertex
// indices (polygons are fan-triangulated). Other elements and properties are skipped. Written here:
// Debian ships no small PLY library.
TriangleMesh load_ply(const std::string& path);
TriangleMesh parse_ply(std::string_view data);

// Per-corner tangents (3 per triangle, in index order) of a mesh with UVs, as MikkTSpace
// computes them (Mikkelsen 2008; Blender's Mesh.calc_tangents, glTF's assumed tangent space):
//  - corners with bit-identical position, normal and uv are one vertex (the normal is the
//    vertex normal, or the face normal when the mesh has none);
//  - each triangle contributes its unit dp/du (from its UV gradients), projected into the
//    vertex's tangent plane and normalised, weighted by its corner angle in that plane;
//  - a vertex is split by the triangles' UV orientation (sign of the UV area): w = +1 for
//    triangles whose UV map keeps the orientation, -1 for mirrored ones;
//  - a triangle with zero UV area takes the tangent of its vertex's group (orientation
//    preserving first).
// Simplifications against the reference implementation: the triangles of one orientation
// around a vertex form one group even when they are not contiguous around it (the reference
// splits such fans), and its 180-degree angular threshold (the default) is not a parameter.
// A vertex without any UV gradient gets a unit vector perpendicular to its normal. Meshes
// without UVs get zeros.
std::vector<glm::vec4> compute_tangents(const TriangleMesh& mesh);

// "" when the mesh is usable, else a message: index out of range, non-finite position, wrong
// normal, UV, tangent or colour count, non-finite UV or tangent, a colour channel outside
// [0, 1] (or NaN), no triangles.
std::string validate_mesh(const TriangleMesh& mesh);

}  // namespace facet::render
