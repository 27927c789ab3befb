// Scene loader tests: every kind of bad input gives one SceneError naming the file and the JSON
// pointer, with a suggestion for misspelt names; good inputs give the documented scene.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "facet/render/scene.h"

using namespace facet;
using namespace facet::render;

namespace {

// A minimal valid scene; tests splice their fragment into it.
std::string scene_with(const std::string& shapes, const std::string& lights = "",
                       const std::string& extra = "") {
    std::string l =
        lights.empty() ? R"([{"type": "point", "position": [0, 5, 0], "power": 100}])" : lights;
    return R"({"format": "facet-scene", "version": 1,
      "camera": {"position": [0, 1, 5], "look_at": [0, 0, 0], "fov": 40, "width": 32, "height": 24},
      "materials": {"glossy": {"model": "ggx", "alpha": 0.3}, "white": {"model": "lambert", "reflectance": 0.8}},
      "shapes": )" +
           shapes + R"(, "lights": )" + l + extra + "}";
}

// The error message of loading `json`, or "" when it loads.
std::string error_of(const std::string& json) {
    try {
        load_scene_from_string(json, "t.json");
    } catch (const SceneError& e) {
        return e.what();
    }
    return "";
}

const char* kSphere =
    R"([{"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": "white"}])";

}  // namespace

TEST(SceneLoader, MinimalSceneLoads) {
    Scene s = load_scene_from_string(scene_with(kSphere), "t.json");
    EXPECT_EQ(s.shapes().size(), 1u);
    EXPECT_EQ(s.lights().size(), 1u);
    EXPECT_EQ(s.camera().width, 32);
    EXPECT_EQ(s.settings().width, 32);
    EXPECT_EQ(s.settings().height, 24);
    EXPECT_EQ(s.settings().integrator, "path");
}

TEST(SceneLoader, UnknownMaterialNameSuggestsTheClosest) {
    std::string shapes =
        R"([{"type": "sphere", "center": [0,0,0], "radius": 1, "material": "white"},
            {"type": "sphere", "center": [0,0,0], "radius": 1, "material": "white"},
            {"type": "sphere", "center": [0,0,0], "radius": 1, "material": "white"},
            {"type": "sphere", "center": [0,0,0], "radius": 1, "material": "glosy"}])";
    EXPECT_EQ(error_of(scene_with(shapes)),
              "t.json: /shapes/3/material: unknown material 'glosy' (did you mean 'glossy'?)");
}

TEST(SceneLoader, SyntaxErrorNamesLineAndColumn) {
    std::string e = error_of("{\n  \"format\": \"facet-scene\",\n  \"version\": 1,,\n}");
    EXPECT_NE(e.find("t.json: line 3, column 16: invalid JSON"), std::string::npos) << e;
}

TEST(SceneLoader, WrongTypes) {
    std::string s = scene_with(kSphere);
    std::string bad = s;
    bad.replace(bad.find("\"fov\": 40"), 9, "\"fov\": \"40\"");
    EXPECT_EQ(error_of(bad), "t.json: /camera/fov: expected a number, got a string");
    bad = s;
    bad.replace(bad.find("\"width\": 32"), 11, "\"width\": 32.5");
    EXPECT_EQ(error_of(bad), "t.json: /camera/width: expected an integer, got a fractional number");
    EXPECT_EQ(error_of(scene_with(
                  R"([{"type": "sphere", "center": [0, 0], "radius": 1, "material": "white"}])")),
              "t.json: /shapes/0/center: expected an array of 3 numbers, got an array of 2 "
              "elements");
    EXPECT_EQ(error_of(scene_with(R"({"type": "sphere"})")),
              "t.json: /shapes: expected an array, got an object");
}

TEST(SceneLoader, NegativeAndNonFiniteValues) {
    EXPECT_EQ(
        error_of(scene_with(kSphere, R"([{"type": "point", "position": [0, 5, 0], "power": -1}])")),
        "t.json: /lights/0/power: a power (W) must be >= 0");
    EXPECT_EQ(error_of(scene_with(kSphere, R"([{"type": "point", "position": [0, 5, 0],
                                               "power": [1, -2, 1]}])")),
              "t.json: /lights/0/power: a power (W) must be >= 0");
    // JSON has no NaN/Infinity literals: both are syntax errors, never a silent value.
    std::string e = error_of(scene_with(kSphere, R"([{"type": "point", "position": [0, 5, 0],
                                                     "power": NaN}])"));
    EXPECT_NE(e.find("invalid JSON"), std::string::npos) << e;
    // An overflowing literal is rejected too (by the parser or as "too large for float").
    e = error_of(scene_with(
        R"([{"type": "sphere", "center": [0, 1e39, 0], "radius": 1, "material": "white"}])"));
    EXPECT_NE(e.find("t.json: /shapes/0/center/1"), std::string::npos) << e;
    e = error_of(scene_with(
        R"([{"type": "sphere", "center": [0, 1e999, 0], "radius": 1, "material": "white"}])"));
    EXPECT_NE(e.find("t.json: "), std::string::npos) << e;
    EXPECT_EQ(
        error_of(scene_with(
            R"([{"type": "sphere", "center": [0, 0, 0], "radius": 0, "material": "white"}])")),
        "t.json: /shapes/0/radius: must be > 0");
}

TEST(SceneLoader, UnknownKeysAndNamesAreErrors) {
    EXPECT_EQ(error_of(scene_with(
                  R"([{"type": "sphere", "center": [0, 0, 0], "radus": 1, "material": "white"}])")),
              "t.json: /shapes/0/radus: unknown key 'radus' (did you mean 'radius'?)");
    EXPECT_EQ(
        error_of(scene_with(
            R"([{"type": "shpere", "center": [0, 0, 0], "radius": 1, "material": "white"}])")),
        "t.json: /shapes/0/type: unknown shape type 'shpere' (did you mean 'sphere'?)");
    EXPECT_EQ(
        error_of(scene_with(kSphere, R"([{"type": "pont", "position": [0, 5, 0], "power": 1}])")),
        "t.json: /lights/0/type: unknown light type 'pont' (did you mean 'point'?)");
    EXPECT_EQ(error_of(scene_with(kSphere, "", R"(, "render": {"integrator": "paht"})")),
              "t.json: /render/integrator: unknown integrator 'paht' (did you mean 'path'?)");
    EXPECT_EQ(error_of(scene_with(kSphere, "", R"(, "rendre": {})")),
              "t.json: /rendre: unknown key 'rendre' (did you mean 'render'?)");
}

TEST(SceneLoader, MaterialErrorsNameTheParameter) {
    std::string shapes =
        R"([{"type": "sphere", "center": [0,0,0], "radius": 1,
             "material": {"model": "lambert", "reflectance": 1.5}}])";
    std::string e = error_of(scene_with(shapes));
    EXPECT_EQ(e.rfind("t.json: /shapes/0/material/reflectance: ", 0), 0u) << e;
    shapes = R"([{"type": "sphere", "center": [0,0,0], "radius": 1,
                  "material": {"model": "lamberr"}}])";
    EXPECT_EQ(error_of(scene_with(shapes)),
              "t.json: /shapes/0/material/model: unknown model 'lamberr' (did you mean "
              "'lambert'?)");
    shapes = R"([{"type": "sphere", "center": [0,0,0], "radius": 1,
                  "material": {"model": "ggx", "alpah": 0.1}}])";
    e = error_of(scene_with(shapes));
    EXPECT_EQ(e.rfind("t.json: /shapes/0/material/alpah: ", 0), 0u) << e;
    EXPECT_NE(e.find("did you mean 'alpha'"), std::string::npos) << e;
}

// A shape's `emission` is a light source by itself: a scene without a "lights" key whose only
// light is an emitting sphere, or one with an emission texture, builds with that one light; without
// any, the error names /lights whether the key is there or not.
TEST(SceneLoader, AnEmittingShapeAloneIsALightSource) {
    auto without_lights_key = [](const std::string& shapes) {
        return R"({"format": "facet-scene", "version": 1,
          "camera": {"position": [0, 1, 5], "look_at": [0, 0, 0], "fov": 40, "width": 8, "height": 6},
          "shapes": )" +
               shapes + "}";
    };
    const Scene s = load_scene_from_string(
        without_lights_key(
            R"([{"type": "sphere", "center": [0,0,0], "radius": 1, "emission": 2}])"),
        "t.json");
    ASSERT_EQ(s.lights().size(), 1u);
    EXPECT_EQ(s.shapes()[0].light, 0);
    const Scene t = load_scene_from_string(
        without_lights_key(R"([{"type": "sphere", "center": [0,0,0], "radius": 1,
                                "emission": {"checker": {"colors": [1, 0.5], "scale": 4}}}])"),
        "t.json");
    ASSERT_EQ(t.lights().size(), 1u);
    EXPECT_EQ(t.shapes()[0].light, 0);
    const std::string none =
        "t.json: /lights: the scene has no light source (no entry in \"lights\" and no shape that "
        "emits: \"emission\" or a glTF emissive material)";
    EXPECT_EQ(
        error_of(without_lights_key(
            R"([{"type": "sphere", "center": [0,0,0], "radius": 1, "material": {"model": "lambert"}}])")),
        none);
    EXPECT_EQ(error_of(without_lights_key(R"([{"type": "sphere", "center": [0,0,0], "radius": 1,
                                               "material": {"model": "lambert"}, "emission": 0}])")),
              none);
}

TEST(SceneLoader, StructuralErrors) {
    EXPECT_EQ(error_of(R"({"format": "facet-scene", "version": 2})"),
              "t.json: /version: unsupported version 2 (this build reads version 1)");
    EXPECT_EQ(error_of(R"({"format": "pbrt", "version": 1})"),
              "t.json: /format: expected \"facet-scene\", got \"pbrt\"");
    EXPECT_EQ(error_of(R"([1, 2])"), "t.json: /: expected an object, got an array");
    EXPECT_EQ(error_of(scene_with(kSphere, "[]")),
              "t.json: /lights: the scene has no light source (no entry in \"lights\" and no "
              "shape that emits: \"emission\" or a glTF emissive material)");
    EXPECT_EQ(error_of(scene_with(R"([{"type": "sphere", "center": [0,0,0], "radius": 1}])")),
              "t.json: /shapes/0: missing required key 'material' (only emissive shapes may "
              "omit it)");
    std::string dup = scene_with(
        R"([{"type": "sphere", "center": [0,0,0], "radius": 1, "radius": 2, "material": "white"}])");
    EXPECT_EQ(error_of(dup), "t.json: /shapes/0: duplicate key 'radius'");
    EXPECT_EQ(error_of(scene_with(R"([{"type": "plane", "point": [0,0,0], "normal": [0,1,0],
                                      "emission": 1}])")),
              "t.json: /shapes/0/emission: an infinite plane cannot emit (infinite power); use a "
              "quad or a disc");
    EXPECT_EQ(error_of(scene_with(R"([{"type": "mesh", "positions": [0,0,0, 1,0,0, 0,1,0],
                                      "indices": [0, 1, 3], "material": "white"}])")),
              "t.json: /shapes/0/indices/2: value 3 is out of range: must be in [0, 2]");
    std::string cam = scene_with(kSphere);
    cam.replace(cam.find("\"look_at\": [0, 0, 0]"), 20, "\"look_at\": [0, 1, 5]");
    EXPECT_EQ(error_of(cam), "t.json: /camera/look_at: must differ from the camera position");
    EXPECT_EQ(error_of(scene_with(R"([{"type": "sphere", "center": [0,0,0], "radius": 1,
        "material": "white", "transform": {"scale": 0}}])")),
              "t.json: /shapes/0/transform: the transform is singular (zero scale?) or not "
              "finite");
    EXPECT_EQ(
        error_of(scene_with(R"([{"type": "mesh", "file": "missing.obj", "material": "white"}])"))
            .rfind("t.json: /shapes/0/file: cannot read OBJ file", 0),
        0u);
}

TEST(SceneLoader, MissingFile) {
    try {
        load_scene("/nonexistent/dir/scene.json");
        FAIL() << "no error";
    } catch (const SceneError& e) {
        EXPECT_STREQ(e.what(), "/nonexistent/dir/scene.json: cannot open the scene file");
    }
}

TEST(SceneLoader, LimitsAreEnforced) {
    SceneLimits lim;
    lim.max_triangles = 1000;
    std::string s = scene_with(R"([{"type": "icosphere", "center": [0,0,0], "radius": 1,
                                    "subdivisions": 4, "material": "white"}])");
    try {
        load_scene_from_string(s, "t.json", ".", lim);
        FAIL() << "no error";
    } catch (const SceneError& e) {
        EXPECT_STREQ(e.what(),
                     "t.json: /shapes/0/subdivisions: the scene exceeds the limit of "
                     "1000 triangles");
    }
}

TEST(SceneLoader, EveryShapeKindAndTransform) {
    std::string shapes = R"([
      {"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": "white",
       "transform": [{"scale": [1, 2, 1]}, {"rotate": {"axis": [0, 0, 1], "angle": 30}},
                     {"translate": [5, 0, 0]}]},
      {"type": "plane", "point": [0, -1, 0], "normal": [0, 1, 0], "material": "white"},
      {"type": "box", "min": [-1, -1, -1], "max": [1, 1, 1], "material": "glossy",
       "transform": {"matrix": [1,0,0,10, 0,1,0,0, 0,0,1,0, 0,0,0,1]}},
      {"type": "quad", "vertices": [[0,3,0], [1,3,0], [1,3,1], [0,3,1]], "emission": [1, 2, 3]},
      {"type": "disc", "center": [0, 4, 0], "normal": [0, -1, 0], "radius": 0.5, "emission": 5},
      {"type": "mesh", "positions": [0,0,0, 1,0,0, 0,1,0], "indices": [0,1,2],
       "normals": [0,0,1, 0,0,1, 0,0,1], "material": "white"},
      {"type": "icosphere", "center": [0, 0, -5], "radius": 1, "subdivisions": 2,
       "material": "white", "two_sided": false},
      {"type": "grid", "nx": 4, "ny": 3, "amplitude": 0.1, "frequency": 2, "material": "white"}
    ])";
    Scene s = load_scene_from_string(scene_with(shapes), "t.json");
    ASSERT_EQ(s.shapes().size(), 8u);
    EXPECT_EQ(s.shapes()[2].triangles, 12u);
    EXPECT_EQ(s.shapes()[3].triangles, 2u);
    EXPECT_EQ(s.shapes()[6].triangles, 20u * 16u);
    EXPECT_EQ(s.shapes()[7].triangles, 24u);
    EXPECT_FALSE(s.shapes()[6].two_sided);
    // Area lights in shape order, then the "lights" array: quad, disc, point.
    ASSERT_EQ(s.lights().size(), 3u);
    EXPECT_EQ(s.shapes()[3].light, 0);
    EXPECT_EQ(s.shapes()[4].light, 1);
    EXPECT_EQ(s.lights()[0].type_name(), "emissive_parallelogram");  // the quad
    EXPECT_EQ(s.lights()[0].shape(), 3u);
    EXPECT_EQ(s.lights()[0].emission(), Rgb(1, 2, 3));
    EXPECT_EQ(s.lights()[1].type_name(), "emissive_disc");
    EXPECT_EQ(s.lights()[2].type_name(), "point");
    // quad area 1, disc area pi r^2
    EXPECT_NEAR(s.lights()[0].area(), 1.f, 1e-6f);
    EXPECT_NEAR(s.lights()[1].area(), kPi * 0.25f, 1e-6f);
    const SceneFeatures& f = s.features();
    EXPECT_EQ(f.num_spheres, 1u);
    EXPECT_EQ(f.num_planes, 1u);
    EXPECT_EQ(f.num_discs, 1u);
    EXPECT_TRUE(f.has_area);
    EXPECT_TRUE(f.has_point);
    EXPECT_FALSE(f.all_lights_delta);
    EXPECT_TRUE(f.has_glossy);
    EXPECT_FALSE(f.lambert_only);

    // The transformed ellipsoid: scale y by 2, rotate 30 deg about z, move to x = 5. A ray down
    // the rotated long axis from above hits the top at distance 2 from the centre.
    Vec3 axis(-std::sin(kPi / 6.f), std::cos(kPi / 6.f), 0.f);
    Ray r;
    r.o = Vec3(5, 0, 0) + 10.f * axis;
    r.d = -axis;
    SurfaceHit h;
    ASSERT_TRUE(s.intersect(r, h));
    EXPECT_EQ(h.shape, 0u);
    EXPECT_NEAR(h.t, 8.f, 1e-5f);
    EXPECT_NEAR(glm::dot(h.ng, axis), 1.f, 1e-6f);
}

TEST(SceneLoader, FeaturesOfSimpleScenes) {
    // Lambert only, delta lights only, the point light is not an emitter the camera can see.
    Scene a = load_scene_from_string(scene_with(kSphere), "a.json");
    EXPECT_TRUE(a.features().lambert_only);
    EXPECT_TRUE(a.features().all_lights_delta);
    EXPECT_FALSE(a.features().emitter_visible);
    EXPECT_TRUE(a.features().can_reflect);
    EXPECT_FALSE(a.features().describe().empty());
    // Black material and an emitter behind the camera: nothing reflects, nothing visible.
    std::string shapes = R"([
        {"type": "sphere", "center": [0,0,0], "radius": 1,
         "material": {"model": "lambert", "reflectance": 0}},
        {"type": "sphere", "center": [0,1,20], "radius": 1, "emission": 1}])";
    Scene b = load_scene_from_string(scene_with(shapes, "[]"), "b.json");
    EXPECT_FALSE(b.features().can_reflect);
    EXPECT_FALSE(b.features().emitter_visible);
    EXPECT_TRUE(b.features().has_area);
    // Reflection-only unit BxDFs reflect (they were taken for black: a scene whose only
    // surfaces were velvet or a hair's reflection lobe rendered them black).
    for (const char* m : {R"({"model": "velvet"})", R"({"model": "hair"})"}) {
        const std::string one = R"([{"type": "sphere", "center": [0,0,0], "radius": 1,
                                     "material": )" +
                                std::string(m) + "}]";
        EXPECT_TRUE(load_scene_from_string(scene_with(one), "v.json").features().can_reflect) << m;
    }
    // The same emitter in front of the camera is visible; an environment always is.
    shapes = R"([{"type": "sphere", "center": [0,0,-3], "radius": 1, "emission": 1}])";
    EXPECT_TRUE(
        load_scene_from_string(scene_with(shapes, "[]"), "c.json").features().emitter_visible);
    Scene d = load_scene_from_string(
        scene_with(kSphere, R"([{"type": "environment", "radiance": 1}])"), "d.json");
    EXPECT_TRUE(d.features().emitter_visible);
    EXPECT_TRUE(d.features().has_environment);
    ASSERT_NE(d.environment(), nullptr);
    EXPECT_EQ(d.environment()->le_escape(Vec3(0, 0, 1)), Rgb(1.f));
    // A mirror scene has specular lobes.
    shapes = R"([{"type": "sphere", "center": [0,0,0], "radius": 1,
                  "material": {"model": "mirror"}}])";
    Scene e = load_scene_from_string(scene_with(shapes), "e.json");
    EXPECT_TRUE(e.features().has_specular);
    EXPECT_FALSE(e.features().has_diffuse);
}

TEST(SceneLoader, RenderSettings) {
    Scene s = load_scene_from_string(
        scene_with(kSphere, "",
                   R"(, "render": {"integrator": "direct", "spp": 7, "time_budget": 1.5,
                                   "max_depth": 3, "seed": 18446744073709551615})"),
        "t.json");
    EXPECT_EQ(s.settings().integrator, "direct");
    EXPECT_EQ(s.settings().spp, 7);
    EXPECT_EQ(s.settings().time_budget_s, 1.5);
    EXPECT_EQ(s.settings().max_depth, 3);
    EXPECT_EQ(s.settings().seed, 18446744073709551615ull);
    EXPECT_EQ(error_of(scene_with(kSphere, "", R"(, "render": {"spp": 0})")),
              "t.json: /render/spp: value 0 is out of range: must be in [1, 1048576]");
}

// Every scene shipped in scenes/ loads (FACET_SCENES_DIR is set by CMake).
TEST(SceneLoader, ShippedScenesLoad) {
    namespace fs = std::filesystem;
    int n = 0;
    for (const auto& entry : fs::directory_iterator(FACET_SCENES_DIR)) {
        if (entry.path().extension() != ".json") continue;
        SCOPED_TRACE(entry.path().string());
        EXPECT_NO_THROW({
            Scene s = load_scene(entry.path().string());
            EXPECT_GT(s.lights().size(), 0u);
        });
        ++n;
    }
    EXPECT_GE(n, 7);
}
