// The `gltf` shape kind (core/render/src/shapes/gltf.cpp, io/gltf_import.cpp): geometry, node
// transforms, the Y-up -> Z-up turn, materials, parts with their own materials, reports and errors.
// The files under tests/render/gltf are written by make_gltf_tests.py (an independent writer); the
// real and malformed assets are Debian's assimp-testmodels (skipped when absent).
#include <gtest/gtest.h>

#include <glm/glm.hpp>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string>
#include <vector>

#include "facet/render/gltf.h"
#include "facet/render/pov_export.h"
#include "facet/render/render.h"
#include "facet/render/scene_description.h"
#include "facet/testsupport/render_test_util.h"

using namespace facet;
using namespace facet::render;

namespace {

const std::string kDir = FACET_GLTF_TEST_DIR;
const std::string kAssimp = "/usr/share/assimp/models/glTF2/";

std::string joined(const std::vector<std::string>& v) {
    std::string s;
    for (const std::string& x : v) s += x + "\n";
    return s;
}

Vec3 tri_normal(const TriangleMesh& m, std::size_t t) {
    const Vec3 a = m.positions[m.indices[3 * t]], b = m.positions[m.indices[3 * t + 1]],
               c = m.positions[m.indices[3 * t + 2]];
    return glm::normalize(glm::cross(b - a, c - a));
}

// A scene of one gltf shape (plus `extra` keys) under a constant environment.
std::string scene_json(const std::string& file, const std::string& extra = "", bool light = true) {
    return R"({"format": "facet-scene", "version": 1,
      "camera": {"position": [0, -8, 0], "look_at": [0, 0, 0], "up": [0, 0, 1],
                 "fov": 40, "width": 8, "height": 8},
      "lights": [)" +
           std::string(light ? R"({"type": "environment", "radiance": 1})" : "") +
           R"(], "shapes": [{"type": "gltf", "file": ")" + file + "\"" + extra + "}]}";
}

Scene build(const std::string& json, BuildReport* report = nullptr) {
    return build_scene(parse_scene_description(json, "t.json", kDir), "t.json", {}, report);
}

std::string build_error(const std::string& json) {
    try {
        build(json);
    } catch (const SceneError& e) {
        return e.what();
    }
    return "(no error)";
}

double param(const MaterialDesc& m, const std::string& key, int channel = -1) {
    const ParamValue& v = m.params.values().at(key);
    if (channel < 0) return std::get<double>(v);
    return std::get<Rgb>(v)[channel];
}

}  // namespace

// A box with known corners: every vertex is a corner of [-1, 1] x [-0.25, 0.25] x [-0.5, 0.5]
// after the Z-up turn (x, y, z) -> (x, -z, y) of the glTF box [-1, 1] x [-0.5, 0.5] x
// [-0.25, 0.25]; every triangle faces outward and agrees with its vertex normals. Exact: the
// turn only moves and negates coordinates.
TEST(Gltf, BoxHasItsKnownCornersTurnedZUpAndFacesOutward) {
    const GltfImport g = import_gltf(kDir + "/box.gltf");
    ASSERT_EQ(g.parts.size(), 1u);
    const TriangleMesh& m = g.parts[0].mesh;
    EXPECT_EQ(m.positions.size(), 24u);
    EXPECT_EQ(m.num_triangles(), 12u);
    ASSERT_EQ(m.normals.size(), 24u);
    for (const Vec3& p : m.positions) {
        EXPECT_EQ(std::fabs(p.x), 1.f);
        EXPECT_EQ(std::fabs(p.y), 0.25f);
        EXPECT_EQ(std::fabs(p.z), 0.5f);
    }
    for (std::size_t t = 0; t < m.num_triangles(); ++t) {
        const Vec3 n = tri_normal(m, t);
        const Vec3 centre = (m.positions[m.indices[3 * t]] + m.positions[m.indices[3 * t + 1]] +
                             m.positions[m.indices[3 * t + 2]]) /
                            3.f;
        EXPECT_GT(glm::dot(n, centre), 0.f) << "triangle " << t << " faces inward";
        EXPECT_NEAR(glm::dot(n, m.normals[m.indices[3 * t]]), 1.f, 1e-6f);
    }
}

// Node transforms composed down the tree: parent T(1, 2, 3) R_y(90 deg), child T(0, 0, 1)
// S(2, 3, 4); a second child mirrors x with a "matrix". Expected world positions worked out
// by hand (R_y(90): (x, y, z) -> (z, y, -x); then Z-up). Tolerance 2e-6: the quaternion's
// sqrt(0.5) rounds in double, the results (|coordinate| <= 5) in float (ulp 4.8e-7 at 4..8).
TEST(Gltf, NodeHierarchyComposesTranslationRotationScaleAndMatrix) {
    const GltfImport g = import_gltf(kDir + "/hierarchy.gltf");
    ASSERT_EQ(g.parts.size(), 2u);
    const std::vector<Vec3> trs = {{2, -3, 2}, {2, -1, 2}, {2, -3, 5}};
    const std::vector<Vec3> mirrored = {{1, -3, 2}, {1, -4, 2}, {1, -3, 3}};
    for (int i = 0; i < 3; ++i) {
        for (int c = 0; c < 3; ++c) {
            EXPECT_NEAR(g.parts[0].mesh.positions[i][c], trs[i][c], 2e-6) << i << "," << c;
            EXPECT_NEAR(g.parts[1].mesh.positions[i][c], mirrored[i][c], 2e-6) << i << "," << c;
        }
    }
    // The unmirrored triangle keeps its winding; the mirrored one is reversed back (glTF
    // 3.7.4), so that both front faces are the image of the local +z side.
    EXPECT_EQ(g.parts[0].mesh.indices, (std::vector<std::uint32_t>{0, 1, 2}));
    EXPECT_EQ(g.parts[1].mesh.indices, (std::vector<std::uint32_t>{0, 2, 1}));
}

// baseColor b = (0.8, 0.4, 0.2), metallic 0.25, roughness 0.5, emissive (1, 0.5, 0) x
// strength 3, doubleSided: composite with diffuse b (1 - m), ggx alpha r^2, schlick
// f0 = 0.04 (1 - m) + b m. Tolerance 1e-6: float rounding of the products.
TEST(Gltf, MetallicRoughnessMapsToComposite) {
    const GltfImport g = import_gltf(kDir + "/box.gltf");
    ASSERT_EQ(g.materials.size(), 1u);
    const GltfMaterial& gm = g.materials[0];
    EXPECT_EQ(gm.desc.model, "composite");
    // The sources, then the one conversion (gltf_composite_params).
    EXPECT_NEAR(param(gm.desc, "metallic"), 0.25, 1e-12);
    EXPECT_NEAR(param(gm.desc, "roughness"), 0.5, 1e-12);
    EXPECT_NEAR(param(gm.desc, "base_color", 1), 0.4, 1e-7);
    MaterialDesc m;
    m.params = gltf_composite_params(gm.desc.params);
    EXPECT_EQ(std::get<std::string>(m.params.values().at("distribution")), "ggx");
    EXPECT_EQ(std::get<std::string>(m.params.values().at("fresnel")), "schlick");
    EXPECT_NEAR(param(m, "alpha"), 0.25, 1e-12);
    const double b[3] = {0.8, 0.4, 0.2};
    for (int c = 0; c < 3; ++c) {
        EXPECT_NEAR(param(m, "diffuse_reflectance", c), b[c] * 0.75, 1e-6);
        EXPECT_NEAR(param(m, "f0", c), 0.04 * 0.75 + b[c] * 0.25, 1e-6);
    }
    EXPECT_EQ(gm.emission, Rgb(3.f, 1.5f, 0.f));
    EXPECT_TRUE(gm.double_sided);
}

// Strips and fans become triangle lists of the same winding; lines are skipped and
// reported, as is a primitive without a material (glTF's default material).
TEST(Gltf, StripsFansAndReports) {
    const GltfImport g = import_gltf(kDir + "/modes.gltf");
    ASSERT_EQ(g.parts.size(), 3u);
    EXPECT_EQ(g.parts[0].mesh.num_triangles(), 2u);
    EXPECT_EQ(g.parts[1].mesh.num_triangles(), 3u);
    EXPECT_EQ(g.parts[2].mesh.num_triangles(), 1u);
    // glTF +z is -y after the Z-up turn.
    for (int p = 0; p < 2; ++p) {
        for (std::size_t t = 0; t < g.parts[p].mesh.num_triangles(); ++t) {
            EXPECT_NEAR(tri_normal(g.parts[p].mesh, t).y, -1.f, 1e-6f) << p << "/" << t;
        }
    }
    ASSERT_EQ(g.materials.size(), 3u);  // grey, red, glTF's default
    EXPECT_EQ(g.parts[2].material, 2);
    const std::string r = joined(g.reports);
    EXPECT_NE(r.find("modes.gltf#/meshes/0/primitives/3/mode"), std::string::npos) << r;
    EXPECT_NE(r.find("modes.gltf#/meshes/0/primitives/2/material"), std::string::npos) << r;
}

// Each primitive is a part with its own material: a ray from -y meets the red fan (glTF
// z = 1), one from +y the grey strip (glTF z = 0).
TEST(Gltf, PartsKeepTheirOwnMaterials) {
    const Scene s = build(scene_json("modes.gltf"));
    ASSERT_EQ(s.shapes().size(), 1u);
    const ShapeInfo& info = s.shapes()[0];
    ASSERT_EQ(info.parts.size(), 3u);
    EXPECT_EQ(info.triangles, 6u);
    EXPECT_NE(info.parts[0].material, info.parts[1].material);
    SurfaceHit hit;
    ASSERT_TRUE(s.intersect(Ray{Vec3(0.75f, -5.f, 0.75f), Vec3(0.f, 1.f, 0.f)}, hit));
    EXPECT_EQ(hit.material, info.parts[1].material);
    ASSERT_TRUE(hit.material->diffuse());
    EXPECT_NEAR(hit.material->diffuse()->rho()[0], 0.9f, 1e-6f);
    ASSERT_TRUE(s.intersect(Ray{Vec3(0.75f, 5.f, 0.75f), Vec3(0.f, -1.f, 0.f)}, hit));
    EXPECT_EQ(hit.material, info.parts[0].material);
    EXPECT_NEAR(hit.material->diffuse()->rho()[0], 0.5f, 1e-6f);
}

// An emissive material makes its part an area light (the scene has no other light); a
// shape "material" replaces the file's materials (no parts).
TEST(Gltf, EmissivePartsAreLightsAndMaterialReplacesTheFiles) {
    const Scene s = build(scene_json("box.gltf", "", false));
    ASSERT_EQ(s.lights().size(), 1u);
    ASSERT_EQ(s.shapes()[0].parts.size(), 1u);
    EXPECT_EQ(s.shapes()[0].parts[0].light, 0);
    EXPECT_EQ(s.shapes()[0].parts[0].emission, Rgb(3.f, 1.5f, 0.f));
    EXPECT_TRUE(s.shapes()[0].parts[0].two_sided);

    const Scene o = build(
        scene_json("modes.gltf", R"(, "material": {"model": "lambert", "reflectance": 0.3})"));
    EXPECT_TRUE(o.shapes()[0].parts.empty());
    EXPECT_EQ(o.shapes()[0].triangles, 6u);
    EXPECT_NE(
        build_error(scene_json("modes.gltf", R"(, "emission": 1)")).find("/shapes/0/emission"),
        std::string::npos);
}

// A glTF's emissive material is a light source for the scene check: a scene with no "lights"
// key whose only light is box.gltf's emissive (1, 0.5, 0) x 3 builds, with the box as its one
// light, and renders it: the centre pixel sees the box's emitted radiance (the convex box
// lights nothing of itself, so the direct integrator adds nothing to it; tolerance: float
// sums of one term). A glTF without emission alone is refused at /lights.
TEST(Gltf, AnEmissiveGltfAloneIsALightSource) {
    auto alone = [](const std::string& file) {
        return R"({"format": "facet-scene", "version": 1,
          "camera": {"position": [0, -8, 0], "look_at": [0, 0, 0], "up": [0, 0, 1],
                     "fov": 40, "width": 9, "height": 9},
          "shapes": [{"type": "gltf", "file": ")" +
               file + R"("}]})";
    };
    const Scene s = load_scene_from_string(alone("box.gltf"), "t.json", kDir);
    ASSERT_EQ(s.lights().size(), 1u);
    EXPECT_EQ(s.shapes()[0].parts[0].light, 0);
    const Image img =
        facet::render::render(s, facet::render::testing::test_options("direct", 4, 1, 1));
    const Rgb c = img.at(4, 4);
    EXPECT_NEAR(c.r, 3.f, 1e-5f);
    EXPECT_NEAR(c.g, 1.5f, 1e-5f);
    EXPECT_EQ(c.b, 0.f);
    EXPECT_EQ(build_error(alone("modes.gltf")),
              "t.json: /lights: the scene has no light source (no entry in \"lights\" and no "
              "shape that emits: \"emission\" or a glTF emissive material)");
}

// Bad data: each error names the file and the glTF pointer.
TEST(Gltf, BadFilesNameTheGltfPointer) {
    const std::vector<std::pair<std::string, std::string>> cases = {
        {"bad_index.gltf", "bad_index.gltf#/accessors/1: index 2 is 3, out of range [0, 2]"},
        {"bad_required.gltf", "bad_required.gltf#/extensionsRequired/0: 'EXT_made_up'"},
        {"bad_bounds.gltf", "bad_bounds.gltf#/accessors/0: 4 elements"},
        {"bad_type.gltf", "bad_type.gltf#/accessors/0/type: expected VEC3, got VEC2"},
        {"bad_nan.gltf", "bad_nan.gltf#/accessors/0: position 1 is not finite"},
        {"missing.glb", "missing.glb: cannot open"},
    };
    for (const auto& [file, expected] : cases) {
        const std::string e = build_error(scene_json(file));
        EXPECT_NE(e.find("t.json: /shapes/0/file: " + expected), std::string::npos)
            << file << ": " << e;
    }
}

// Real assets: the right triangle counts, their base colour textures and UVs imported (the
// sampler's differing wrapT and its mipmap minFilter reported, not silently dropped).
TEST(Gltf, RealAssetsLoadWithTheirTextures) {
    for (const char* f :
         {"BoxTextured-glTF/BoxTextured.gltf", "BoxTextured-glTF-Binary/BoxTextured.glb"}) {
        if (!std::filesystem::exists(kAssimp + f)) GTEST_SKIP() << "assimp-testmodels absent";
        const GltfImport g = import_gltf(kAssimp + f);
        std::uint64_t n = 0;
        for (const GltfPart& p : g.parts) n += p.mesh.num_triangles();
        EXPECT_EQ(n, 12u) << f;
        const std::string r = joined(g.reports);
        ASSERT_EQ(g.materials.size(), 1u);
        EXPECT_EQ(g.materials[0].desc.textures.count("base_color"), 1u);
        EXPECT_EQ(g.parts[0].mesh.uvs.size(), g.parts[0].mesh.positions.size());
        EXPECT_EQ(r.find("TEXCOORD_0"), std::string::npos) << r;
        EXPECT_NE(r.find("#/samplers/0/minFilter"), std::string::npos) << r;
        // Debian's .gltf variant has a mirror/clamp sampler, the .glb a repeat one.
        const bool gltf = std::string(f).find(".glb") == std::string::npos;
        EXPECT_EQ(g.materials[0].desc.textures.at("base_color").wrap, gltf ? "mirror" : "repeat");
        EXPECT_EQ(r.find("#/samplers/0/wrapT: wrapT differs") != std::string::npos, gltf) << r;
    }
}

// Debian's malformed glTF files: each gives a clear error naming the file (and a pointer
// where there is one), or imports with a report; never a crash or a hang.
TEST(Gltf, MalformedAssetsGiveClearErrors) {
    if (!std::filesystem::exists(kAssimp)) GTEST_SKIP() << "assimp-testmodels absent";
    const std::vector<std::pair<std::string, std::string>> errors = {
        {"IndexOutOfRange/IndexOutOfRange.gltf", "#/accessors/0: index 0 is 255, out of range"},
        {"IndexOutOfRange/AllIndicesOutOfRange.gltf", "#/accessors/0: index 0 is 65535"},
        {"BoxWithInfinites-glTF-Binary/BoxWithInfinites.glb", "#/accessors/2: position 0 is not"},
        {"IncorrectVertexArrays/Cube.gltf", "#/meshes/1/primitives/0: TRIANGLES with 35"},
        {"SchemaFailures/sceneWrongType.gltf", "sceneWrongType.gltf: not a readable glTF"},
        {"draco/2CylinderEngine.gltf", "#/extensionsRequired/0: 'KHR_draco_mesh_compression'"},
        {"MissingBin/BoxTextured.gltf", "BoxTextured.gltf: not a readable glTF"},
        {"RecursiveNodes/RecursiveNodes.gltf", "#/nodes/1/children/0: node 0 is reached twice"},
        {"TestNoRootNode/NoScene.gltf", "#/scene: scene 0 does not exist"},
    };
    for (const auto& [f, expected] : errors) {
        std::string e = "(no error)";
        try {
            import_gltf(kAssimp + f);
        } catch (const std::runtime_error& x) {
            e = x.what();
        }
        EXPECT_NE(e.find(expected), std::string::npos) << f << ": " << e;
    }
    // Wrong JSON types tinygltf tolerates (it drops the value and keeps glTF's default): a
    // KHR_texture_transform that is a string imports untransformed (docs/gltf.md, Limitation).
    const GltfImport g = import_gltf(kAssimp + "wrongTypes/badExtension.gltf");
    EXPECT_EQ(g.materials.at(0).desc.textures.at("base_color").uv_scale, Vec2(1.f));
}

// `facet render` on a bare glTF file: the file's camera when it has one.
TEST(Gltf, BareFileSceneUsesTheFilesCameraOrFramesTheModel) {
    std::vector<std::string> notes;
    const SceneDescription d = gltf_scene_description(kDir + "/box.gltf", 64, 48, notes);
    ASSERT_EQ(d.shapes.size(), 1u);
    EXPECT_EQ(d.shapes[0].kind, ShapeKind::Gltf);
    ASSERT_EQ(d.lights.size(), 1u);
    EXPECT_EQ(d.lights[0].kind, LightKind::Environment);
    EXPECT_NE(joined(notes).find("no camera"), std::string::npos);
    // The framing camera looks at the box's centre, from outside its bounding sphere.
    EXPECT_EQ(d.camera.look_at, Vec3(0.f));
    EXPECT_GT(glm::length(d.camera.position), 1.2f);
    EXPECT_NO_THROW(build_scene(d, "box.gltf"));
}

// export-pov: a gltf shape with a "material" exports as a mesh; the file's own materials are
// an error naming the shape's file key (never silently dropped).
TEST(Gltf, PovExportWritesAMeshOrNamesTheKey) {
    // POV-Ray has no exact environment light: a point light instead.
    auto pov_scene = [](std::string json) {
        const std::string env = R"({"type": "environment", "radiance": 1})";
        json.replace(json.find(env), env.size(),
                     R"({"type": "point", "position": [0, -5, 0], "power": 100})");
        return parse_scene_description(json, "t.json", kDir);
    };
    const SceneDescription own = pov_scene(scene_json("modes.gltf"));
    try {
        (void)export_pov(own, "t.json");
        ADD_FAILURE() << "no error";
    } catch (const std::exception& e) {
        EXPECT_NE(std::string(e.what()).find("/shapes/0/file"), std::string::npos) << e.what();
    }
    const SceneDescription one = pov_scene(
        scene_json("modes.gltf", R"(, "material": {"model": "lambert", "reflectance": 0.3})"));
    const std::string sdl = export_pov(one, "t.json");
    EXPECT_NE(sdl.find("mesh2"), std::string::npos);
    EXPECT_NE(sdl.find("face_indices { 6,"), std::string::npos) << sdl;
}

// The binary container (.glb) of the same box gives the same triangles, and bytes in memory
// (parse_gltf, the fuzzer's entry) give what the file gives.
TEST(Gltf, GlbAndMemoryGiveTheSameTriangles) {
    const GltfImport a = import_gltf(kDir + "/box.gltf");
    const GltfImport b = import_gltf(kDir + "/box.glb");
    ASSERT_EQ(a.parts.size(), 1u);
    ASSERT_EQ(b.parts.size(), 1u);
    EXPECT_EQ(a.parts[0].mesh.positions, b.parts[0].mesh.positions);
    EXPECT_EQ(a.parts[0].mesh.indices, b.parts[0].mesh.indices);
    std::ifstream in(kDir + "/box.glb", std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(in)), {});
    const GltfImport c = parse_gltf(bytes, "box.glb");
    ASSERT_EQ(c.parts.size(), 1u);
    EXPECT_EQ(c.parts[0].mesh.positions, a.parts[0].mesh.positions);
    // From memory, an external buffer is refused, not read.
    const std::string ext = R"({"asset": {"version": "2.0"}, "buffers": [{"byteLength": 4,
        "uri": "/etc/passwd"}]})";
    EXPECT_THROW(parse_gltf(ext, "ext.gltf"), std::runtime_error);
}
