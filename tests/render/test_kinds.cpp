// The shape and light kind table (facet/render/kinds.h): every enum value has one kind, names
// and keys are unique, the docs hold the generated tables, and the builder and the POV-Ray
// exporter read mesh files through the same loader.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <string>

#include "facet/render/kinds.h"
#include "facet/render/pov_export.h"
#include "facet/render/scene_description.h"
#include "facet/render/texture_kinds.h"

using namespace facet;
using namespace facet::render;

namespace {

std::string read_text(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

// A scene with one shape or light spliced in (and `extra` top-level members, e.g.
// "prototypes").
SceneDescription scene_with(const std::string& shape, const std::string& light,
                            const std::string& base_dir = ".", const std::string& extra = "") {
    const std::string text = R"({"format": "facet-scene", "version": 1,
      "camera": {"position": [0, 1, 5], "look_at": [0, 0, 0], "fov": 40, "width": 16, "height": 12},
      "materials": {"white": {"model": "lambert", "reflectance": 0.8}},
      )" + extra + R"("shapes": [)" +
                             shape + R"(], "lights": [)" + light + "]}";
    return parse_scene_description(text, "t.json", base_dir);
}

}  // namespace

TEST(Kinds, EveryEnumValueHasExactlyOneKindWithUniqueKeys) {
    std::set<std::string> names;
    for (const ShapeKindDef* k : shape_kinds()) {
        EXPECT_TRUE(names.insert(std::string(k->name)).second) << k->name;
        EXPECT_EQ(&shape_kind(k->kind), k) << k->name;
        EXPECT_EQ(find_shape_kind(k->name), k);
        ASSERT_NE(k->build, nullptr) << k->name;
        std::set<std::string_view> keys(common_shape_keys().begin(), common_shape_keys().end());
        for (const auto& f : k->fields)
            EXPECT_TRUE(keys.insert(f.key).second) << k->name << " " << f.key;
    }
    EXPECT_EQ(names.size(), 11u);  // ShapeKind has 11 values: each one is in the table
    for (int e = 0; e < 11; ++e) EXPECT_NE(find_shape_kind(ShapeKind(e)), nullptr) << e;
    EXPECT_EQ(find_shape_kind(ShapeKind(200)), nullptr);
    EXPECT_THROW(shape_kind(ShapeKind(200)), std::logic_error);

    names.clear();
    for (const LightKindDef* k : light_kinds()) {
        EXPECT_TRUE(names.insert(std::string(k->name)).second) << k->name;
        EXPECT_EQ(&light_kind(k->kind), k);
        ASSERT_NE(k->build, nullptr);
        ASSERT_NE(k->pov, nullptr);
        std::set<std::string_view> keys{"type"};
        for (const auto& f : k->fields)
            EXPECT_TRUE(keys.insert(f.key).second) << k->name << " " << f.key;
    }
    EXPECT_EQ(names.size(), 6u);  // LightKind has 6 values
    for (int e = 0; e < 6; ++e) EXPECT_NE(find_light_kind(LightKind(e)), nullptr) << e;
}

// The docs read the table: scenes/FORMAT.md holds exactly what `facet scene-format --markdown`
// prints, between its markers.
TEST(Kinds, FormatDocHoldsTheGeneratedTables) {
    const std::string doc = read_text(std::string(FACET_SCENES_DIR) + "/FORMAT.md");
    const std::string begin = "<!-- kinds:begin -->\n", end = "<!-- kinds:end -->";
    const auto a = doc.find(begin), b = doc.find(end);
    ASSERT_NE(a, std::string::npos);
    ASSERT_NE(b, std::string::npos);
    EXPECT_EQ(doc.substr(a + begin.size(), b - a - begin.size()), kinds_markdown())
        << "regenerate: facet scene-format --markdown";
}

// Likewise the procedural texture kinds' tables (texture_kinds.h), `facet scene-format
// --textures`.
TEST(Kinds, FormatDocHoldsTheTextureKindTables) {
    const std::string doc = read_text(std::string(FACET_SCENES_DIR) + "/FORMAT.md");
    const std::string begin = "<!-- texture-kinds:begin -->\n", end = "<!-- texture-kinds:end -->";
    const auto a = doc.find(begin), b = doc.find(end);
    ASSERT_NE(a, std::string::npos);
    ASSERT_NE(b, std::string::npos);
    EXPECT_EQ(doc.substr(a + begin.size(), b - a - begin.size()),
              facet::render::texture_kinds_markdown())
        << "regenerate: facet scene-format --textures";
}

// Each kind's fields are what the JSON reader accepts and the writer writes: a scene with one
// shape of every kind reads, writes and reads back equal.
TEST(Kinds, JsonRoundTripOfEveryKind) {
    const std::string shapes = R"(
      {"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": "white"},
      {"type": "plane", "point": [0, -1, 0], "normal": [0, 1, 0], "material": "white"},
      {"type": "box", "min": [0, 0, 0], "max": [1, 1, 1], "material": "white"},
      {"type": "quad", "vertices": [[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], "emission": 2},
      {"type": "disc", "center": [0, 2, 0], "normal": [0, -1, 0], "radius": 0.5, "emission": 1},
      {"type": "mesh", "positions": [0, 0, 0, 1, 0, 0, 0, 1, 0], "indices": [0, 1, 2], "material": "white"},
      {"type": "icosphere", "center": [2, 0, 0], "radius": 0.5, "subdivisions": 1, "material": "white"},
      {"type": "grid", "nx": 2, "ny": 3, "amplitude": 0.1, "frequency": 2, "material": "white"},
      {"type": "gltf", "file": ")" FACET_GLTF_TEST_DIR R"(/modes.gltf"},
      {"type": "instance", "of": "card", "transform": {"translate": [0, 3, 0]}},
      {"type": "curves", "basis": "catmull_rom", "profile": "flat", "material": "white",
       "points": [0, 0, 0, 0, 0, 1, 0, 0, 2, 0, 0, 3], "radius": [0.1, 0.2, 0.3, 0.4],
       "counts": [4], "root_uvs": [0.5, 0.25]})";
    const std::string lights = R"(
      {"type": "point", "position": [0, 5, 0], "power": 100},
      {"type": "spot", "position": [0, 5, 0], "look_at": [0, 0, 0], "power": 10, "outer_angle": 30, "inner_angle": 20},
      {"type": "directional", "direction": [0, -1, 0], "irradiance": [1, 2, 3]},
      {"type": "area", "position": [0, 2, 0], "direction": [0, -1, 0], "size": 1, "power": 5},
      {"type": "environment", "radiance": 0.1},
      {"type": "sky_nishita", "sun_elevation": 20, "sun_disc": false, "radiance": 0.5})";
    const SceneDescription d =
        scene_with(shapes, lights, ".", R"("prototypes": {"card": [{"type": "quad",
          "material": "white", "vertices": [[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]]}]},)");
    ASSERT_EQ(d.shapes.size(), shape_kinds().size());
    ASSERT_EQ(d.lights.size(), light_kinds().size());
    const SceneDescription back = parse_scene_description(write_scene_json(d), "back.json");
    EXPECT_EQ(back, d);
    EXPECT_EQ(d.lights[1].inner_angle, 20.0);
    EXPECT_FALSE(d.lights[1].direction.has_value());
    SceneDescription one_environment = d;  // a scene has at most one environment
    one_environment.lights.pop_back();
    EXPECT_NO_THROW(build_scene(one_environment, "t.json"));
}

// A key of another kind is an unknown key, with the kind's own keys as the suggestion pool.
TEST(Kinds, AnotherKindsKeyIsUnknown) {
    try {
        scene_with(
            R"({"type": "sphere", "center": [0, 0, 0], "radius": 1, "nx": 2, "material": "white"})",
            R"({"type": "point", "position": [0, 5, 0], "power": 1})");
        FAIL() << "no error";
    } catch (const SceneError& e) {
        EXPECT_NE(std::string(e.what()).find("t.json: /shapes/0/nx: unknown key 'nx'"),
                  std::string::npos)
            << e.what();
    }
    try {
        scene_with(R"({"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": "white"})",
                   R"({"type": "spot", "position": [0, 5, 0], "power": 1, "outer_angle": 30})");
        FAIL() << "no error";
    } catch (const SceneError& e) {
        EXPECT_NE(std::string(e.what()).find(
                      "/lights/0: give exactly one of \"direction\" and \"look_at\""),
                  std::string::npos)
            << e.what();
    }
}

// One mesh-file loader for the builder and the exporter: an unknown extension is the same
// error in both (the exporter used to read it as OBJ), and a .PLY file (upper case) gives the
// exporter the triangles the builder renders.
TEST(Kinds, BuilderAndExporterLoadMeshFilesAlike) {
    const auto dir = std::filesystem::temp_directory_path() / "facet_kinds_test";
    std::filesystem::create_directories(dir);
    {
        std::ofstream ply(dir / "tri.PLY");
        ply << "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
               "property float z\nelement face 2\nproperty list uchar int vertex_indices\n"
               "end_header\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n3 0 1 2\n3 0 2 3\n";
        std::ofstream txt(dir / "tri.txt");
        txt << "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
    }
    const std::string light = R"({"type": "point", "position": [0, 5, 0], "power": 1})";
    const SceneDescription ply = scene_with(
        R"({"type": "mesh", "file": "tri.PLY", "material": "white"})", light, dir.string());
    const Scene scene = build_scene(ply, "t.json");
    EXPECT_EQ(scene.features().num_triangles, 2u);
    const std::string sdl = export_pov(ply, "t.json");
    EXPECT_NE(sdl.find("face_indices { 2, <0, 2, 1>, <0, 3, 2> }"), std::string::npos) << sdl;

    const SceneDescription txt = scene_with(
        R"({"type": "mesh", "file": "tri.txt", "material": "white"})", light, dir.string());
    for (int exporter = 0; exporter < 2; ++exporter) {
        try {
            if (exporter)
                (void)export_pov(txt, "t.json");
            else
                (void)build_scene(txt, "t.json");
            FAIL() << "no error";
        } catch (const SceneError& e) {
            EXPECT_NE(std::string(e.what()).find(
                          "t.json: /shapes/0/file: unsupported mesh file extension '.txt'"),
                      std::string::npos)
                << e.what();
        }
    }
    EXPECT_THROW(load_mesh_file((dir / "tri.txt").string()), std::runtime_error);
    std::filesystem::remove_all(dir);
}

// The exporter as a library call: options are checked and named.
TEST(Kinds, PovExportOptionsAreChecked) {
    PovExportOptions o;
    o.radiosity = "medum";
    EXPECT_THROW(check_pov_options(o), std::invalid_argument);
    o = {};
    o.area_grid = 0;
    try {
        check_pov_options(o);
        FAIL() << "no error";
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("--area-grid"), std::string::npos);
    }
}

// The fibre models (principled_hair, hair: no POV-Ray finish, they need the surface's tangent)
// are an export error naming the material, not a brdf block povray-facet would refuse.
TEST(Kinds, PovExportRefusesTheFibreModels) {
    const std::string light = R"({"type": "point", "position": [0, 5, 0], "power": 1})";
    for (const char* model : {"principled_hair", "hair"}) {
        const std::string shape = std::string(R"({"type": "sphere", "center": [0, 0, 0],
            "radius": 1, "material": {"model": ")") +
                                  model + R"("}})";
        try {
            (void)export_pov(scene_with(shape, light), "t.json");
            FAIL() << model << ": no error";
        } catch (const SceneError& e) {
            EXPECT_NE(std::string(e.what()).find("t.json: /shapes/0/material/model: '" +
                                                 std::string(model) + "' scatters about the"),
                      std::string::npos)
                << e.what();
        }
    }
    // Control: the same scene with a lambert exports.
    EXPECT_NO_THROW((void)export_pov(scene_with(R"({"type": "sphere", "center": [0, 0, 0],
        "radius": 1, "material": "white"})",
                                                light),
                                     "t.json"));
}
