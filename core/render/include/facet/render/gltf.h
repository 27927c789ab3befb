// glTF 2.0 import (core/render/src/io/gltf_import.cpp, for the `gltf` shape kind of
// shapes/gltf.cpp and a bare file's scene, io/gltf_scene.cpp; docs/gltf.md).
//
// Conventions:
//  - Everything is in the shape's object space: glTF's right-handed Y-up metres turned Z-up,
//    (x, y, z)_glTF -> (x, -z, y), with every node transform applied (parent * child; a node's
//    "matrix" or T * R * S). The `gltf` shape's "transform" applies after.
//  - Errors are std::runtime_error "<file>#<glTF JSON pointer>: <message>" (e.g.
//    "box.gltf#/accessors/2: index 7 is 9, out of range [0, 7] (used by
//    /meshes/0/primitives/0/indices)"); what is read but not converted is listed in `reports`
//    in the same form, once per material slot, attribute kind or extension.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <glm/mat4x4.hpp>

#include "facet/render/mesh.h"
#include "facet/render/scene_description.h"

namespace facet::render {

// One triangle primitive of the file.
struct GltfPart {
    TriangleMesh mesh;    // object space (see conventions); normals unit or absent; uvs from
                          // TEXCOORD_0 turned bottom-left: (u, v) -> (u, 1 - v), or absent
    int material = -1;    // index into GltfImport::materials
    std::string pointer;  // "/meshes/<m>/primitives/<p>"
    // With share_meshes: the shared mesh this part belongs to (its mesh in that mesh's own
    // space, placed by GltfImport::placements), or -1 (in object space as above).
    int prototype = -1;
};

// One node's use of a shared mesh: the mesh's frame to the shape's object space.
struct GltfPlacement {
    int prototype = 0;
    glm::dmat4 to_object{1.0};
};

// A metallic-roughness material as a core model (docs/gltf.md gives the mapping). `desc` holds
// the sources "base_color" (colour), "metallic" and "roughness" (numbers), each a constant or a
// texture (times its factor: TextureDesc::scale / color_scale), which gltf_composite_params
// maps onto `composite`, and "opacity" / "alpha_cutoff" from alphaMode.
struct GltfMaterial {
    MaterialDesc desc;
    Rgb emission{0.f};  // emissiveFactor x KHR_materials_emissive_strength, radiance
    std::optional<TextureDesc> emission_texture;  // emissiveTexture x the above, or none
    bool double_sided = false;
    std::string pointer;  // "/materials/<i>"
    std::string name;
};

// The first perspective camera met in the node traversal, in object space.
struct GltfCamera {
    glm::dvec3 position{0.0}, forward{0.0, 0.0, -1.0}, up{0.0, 1.0, 0.0};
    double yfov_deg = 40.0;        // full vertical field of view
    std::optional<double> aspect;  // width / height, when the file gives it
    std::string pointer;           // "/cameras/<i>"
};

struct GltfImport {
    std::vector<GltfPart> parts;
    // The file's materials in file order, then glTF's default material if a primitive has none.
    std::vector<GltfMaterial> materials;
    std::vector<std::string> reports;  // "<file>#<pointer>: <what is not converted>"
    std::optional<GltfCamera> camera;
    std::size_t num_cameras = 0;  // in the file's "cameras"
    // With share_meshes: meshes that several nodes use, none of whose materials emit, are
    // imported once (GltfPart::prototype) and placed by these (instancing, kind `gltf`).
    std::vector<GltfPlacement> placements;
    int num_prototypes = 0;
};

// glTF's metallic-roughness sources (base_color b, metallic m, roughness r) -> `composite`:
// diffuse_reflectance = b (1 - m), ggx alpha = r^2, schlick f0 = 0.04 (1 - m) + b m.
ParamSet gltf_composite_params(const ParamSet& sources);
// The same on values (TexturedMaterial::convert_values): sources (b, m, r) as DVec3 (numbers in
// x) -> (diffuse_reflectance, alpha, f0).
void gltf_composite_values(const DVec3* sources, DVec3* outputs);

// KHR_texture_transform (offset o, rotation r radians, scale s; glTF's uv origin top-left)
// as Facet's uv transform (texture.h; origin bottom-left, the mesh's v = 1 - v_glTF): the same
// texel for every uv. With F(u, v) = (u, 1 - v), glTF samples R(r) S F(uv) + o at glTF
// coordinates, i.e. Facet's F(R(r) S F(uv) + o) = R(-r) S uv + (o_u - s_v sin r,
// 1 - o_v - s_v cos r), since F R(r) F = R(-r) on the linear part. Sets uv_scale = s,
// uv_rotation = -r in degrees, uv_offset as given.
void apply_khr_texture_transform(TextureDesc& d, Vec2 offset, double rotation, Vec2 scale);

// Reads a .gltf or .glb file (tinygltf; images are kept encoded, decoded by the texture layer).
// share_meshes: see GltfImport::placements (otherwise every node's mesh is a copy of its own).
GltfImport import_gltf(const std::string& path, bool share_meshes = false);
// The same from bytes in memory (a .glb when they start with "glTF", else .gltf JSON), named
// `name` in messages; external buffers and images are refused (data: URIs work). For fuzzing.
GltfImport parse_gltf(std::string_view bytes, const std::string& name);

// The scene `facet render model.glb` renders: the file as one `gltf` shape, its first
// perspective camera (the image width then follows the camera's aspect ratio when it has one)
// or else a camera framing the model's bounding box, lit by a constant environment of radiance
// 1. `notes` receives one line per such choice, for the user.
SceneDescription gltf_scene_description(const std::string& path, int width, int height,
                                        std::vector<std::string>& notes);

}  // namespace facet::render
