// Shape kind "gltf": every triangle primitive of a glTF 2.0 file with its node transforms
// and its metallic-roughness materials, as the importer (io/gltf_import.cpp, conventions
// there and in docs/gltf.md) reads them; meshes several nodes use are placed as instances.
#include <filesystem>
#include <string>

#include "../io/pov_writer.h"
#include "../kind_build.h"
#include "facet/render/gltf.h"

namespace facet::render {

namespace {

// The glTF texture sources of gltf_composite_params: what a texture may replace.
const MaterialConversion kGltfConversion{{{"base_color", ParamType::Color, "1", "baseColor"},
                                          {"metallic", ParamType::Number, "1", "metallic"},
                                          {"roughness", ParamType::Number, "1", "roughness"}},
                                         gltf_composite_params,
                                         {"diffuse_reflectance", "alpha", "f0"},
                                         gltf_composite_values};

// All parts as one mesh (the exporters' `triangles`, and a shape whose "material" replaces the
// file's).
TriangleMesh merged(const GltfImport& g) {
    TriangleMesh out;
    for (const GltfPart& p : g.parts) {
        const std::uint32_t base = std::uint32_t(out.positions.size());
        out.positions.insert(out.positions.end(), p.mesh.positions.begin(), p.mesh.positions.end());
        for (std::uint32_t i : p.mesh.indices) out.indices.push_back(base + i);
    }
    // Normals only when every part has them (a mesh has one normal per position or none).
    bool all = !g.parts.empty();
    for (const GltfPart& p : g.parts) all = all && !p.mesh.normals.empty();
    if (all) {
        for (const GltfPart& p : g.parts) {
            out.normals.insert(out.normals.end(), p.mesh.normals.begin(), p.mesh.normals.end());
        }
    }
    // UVs likewise (a shape "material" with textures needs them everywhere).
    bool uvs = !g.parts.empty();
    for (const GltfPart& p : g.parts) uvs = uvs && !p.mesh.uvs.empty();
    if (uvs)
        for (const GltfPart& p : g.parts)
            out.uvs.insert(out.uvs.end(), p.mesh.uvs.begin(), p.mesh.uvs.end());
    // Tangents likewise.
    bool all_tangents = !g.parts.empty();
    for (const GltfPart& p : g.parts) all_tangents = all_tangents && !p.mesh.tangents.empty();
    for (const GltfPart& p : g.parts) {
        if (all_tangents)
            out.tangents.insert(out.tangents.end(), p.mesh.tangents.begin(), p.mesh.tangents.end());
    }
    return out;
}

TriangleMesh triangles(const ShapeDesc& s, const std::string& base_dir) {
    return merged(import_gltf(resolve_scene_path(s.file, base_dir)));
}

bool replaces_materials(const ShapeDesc& s) {
    return s.material || !s.material_ref.empty();
}

// The base colour times the vertex colour: its texture tinted per hit, or a constant factor as
// the scale of a vertex-colour texture.
MaterialDesc gltf_vertex_colored(const MaterialDesc& desc) {
    MaterialDesc d = desc;
    if (auto t = d.textures.find("base_color"); t != d.textures.end()) {
        t->second.times_vertex_color = true;
    } else {
        TextureDesc v;
        v.kind = "vertex_color";
        v.color_scale = std::get<Rgb>(d.params.values().at("base_color"));
        ParamSet rest;
        for (const auto& [key, value] : d.params.values())
            if (key != "base_color") rest.set(key, value);
        d.params = std::move(rest);
        d.textures["base_color"] = v;
    }
    return d;
}

void build(ShapeBuild& b) {
    const ShapeDesc& s = b.shape;
    const std::string fp = b.ptr + "/file";
    if (!b.files_allowed()) b.fail(fp, "files are disabled here");
    GltfImport g;
    // Meshes that several nodes use are stored once and placed as instances (embree_scene.cpp),
    // unless the shape's own material replaces the file's (then one merged mesh) or the shape
    // is itself in a prototype (one level of instancing).
    const bool share = b.can_instance() && !replaces_materials(s);
    try {
        g = import_gltf(resolve_scene_path(s.file, b.base_dir()), share);
    } catch (const std::exception& e) {
        b.fail(fp, e.what());
    }
    for (const std::string& r : g.reports) b.warn(b.place() + ": " + r);
    if (g.num_cameras > 0) {
        b.warn(b.place() + ": " + std::filesystem::path(s.file).filename().string() +
               "#/cameras: " + std::to_string(g.num_cameras) +
               " camera(s) not used by a gltf shape (`facet render` on the bare file uses the "
               "first perspective one)");
    }
    if (g.parts.empty()) {
        b.fail(fp,
               "the file's scene has no triangle primitives (nothing to render; see the "
               "warnings for what was skipped)");
    }
    std::uint64_t n = 0;
    for (const GltfPart& p : g.parts) n += p.mesh.num_triangles();
    b.reserve_triangles(n, fp);
    if (replaces_materials(s)) {
        // The shape's own material (and emission) for every primitive.
        b.add_triangles(merged(g), Vec3(0.f));
        return;
    }
    if (b.emissive) {
        b.fail(b.ptr + "/emission",
               "a gltf shape emits what its file's materials emit (emissiveFactor); give the "
               "shape a \"material\" to replace the file's materials and emit this instead");
    }
    // Per material, built without and with COLOR_0 (glTF 3.9.2: a primitive's vertex colour
    // multiplies its base colour, factor and texture alike).
    std::vector<std::array<std::optional<ShapeSurface>, 2>> built(g.materials.size());
    std::vector<std::uint32_t> prototypes;
    for (int i = 0; i < g.num_prototypes; ++i) prototypes.push_back(b.add_local_prototype());
    for (GltfPart& p : g.parts) {
        const GltfMaterial& gm = g.materials[std::size_t(p.material)];
        const bool colored = !p.mesh.colors.empty();
        std::optional<ShapeSurface>& mat = built[std::size_t(p.material)][colored ? 1 : 0];
        if (!mat) {
            mat = b.add_material(colored ? gltf_vertex_colored(gm.desc) : gm.desc, fp,
                                 &kGltfConversion);
            if (gm.emission_texture)
                mat->emission_texture = b.add_texture(*gm.emission_texture, fp, true, true);
        }
        if (colored && mat->opacity.active() &&
            std::any_of(p.mesh.colors.begin(), p.mesh.colors.end(),
                        [](const glm::vec4& c) { return c.a != 1.f; }))
            b.warn(s.file + "#" + p.pointer +
                   "/attributes/COLOR_0: the vertex colours' alpha does not multiply the "
                   "material's opacity (" +
                   gm.pointer + " alphaMode); their RGB does multiply the base colour");
        ShapeSurface su = *mat;
        su.material_name = s.file + "#" + gm.pointer;
        su.emission = gm.emission;
        const bool uv_textured = (su.textured >= 0 && b.textured_uses_uv(su.textured)) ||
                                 su.emission_texture || su.opacity.texture;
        if (uv_textured && p.mesh.uvs.empty())
            b.fail(fp, std::filesystem::path(s.file).filename().string() + "#" + p.pointer +
                           "/attributes: the primitive's material " + gm.pointer +
                           " has textures but the primitive has no TEXCOORD_0");
        su.two_sided = gm.double_sided && s.two_sided;
        if (p.prototype >= 0)
            b.add_part_to(prototypes[std::size_t(p.prototype)], std::move(p.mesh), std::move(su));
        else
            b.add_part(std::move(p.mesh), std::move(su));
    }
    for (const GltfPlacement& pl : g.placements)
        b.place_prototype(prototypes[std::size_t(pl.prototype)], pl.to_object);
}

// POV-Ray: one mesh with the shape's material when it replaces the file's; a file's several
// materials have no export yet.
void pov(PovShapeOut& o) {
    if (replaces_materials(o.shape)) return o.triangles(false);
    o.fail(o.pointer + "/file",
           "export-pov cannot write a glTF file's own materials yet; give the shape a "
           "\"material\" to export its triangles with that one");
}

}  // namespace

extern const ShapeKindDef kGltfKind{
    ShapeKind::Gltf,
    "gltf",
    "every triangle primitive of a glTF 2.0 file (`.gltf` or `.glb`, tinygltf) with its node "
    "transforms, turned Z-up ((x, y, z) -> (x, -z, y)) before `transform`, and its "
    "metallic-roughness materials as `composite` with their base colour, metallic-roughness and "
    "emissive textures (TEXCOORD_0, v -> 1 - v; samplers; KHR_texture_transform), its normal "
    "textures as normal maps (TANGENT or MikkTSpace tangents) and alphaMode as opacity "
    "(docs/gltf.md); `material`, when given, replaces the file's materials; what is "
    "not converted is reported",
    {{"file", FieldType::Path, true, &ShapeDesc::file, "-",
      "the glTF file, relative to the scene file; per material, with b = baseColorFactor x "
      "baseColorTexture, m = metallicFactor x texture B, r = roughnessFactor x texture G: "
      "diffuse_reflectance = b (1 - m), ggx alpha = r^2, schlick f0 = 0.04 (1 - m) + b m, "
      "emission = emissiveFactor x emissiveTexture x emissiveStrength, opacity = base alpha "
      "(MASK: cut at alphaCutoff; BLEND), two_sided = doubleSided and `two_sided`"}},
    build,
    triangles,
    pov,
    true};

}  // namespace facet::render
