// Instancing (scenes/FORMAT.md, "Instances"): an instanced scene against the same scene
// flattened (every prototype shape written out with the composed transform), normals through a
// non-uniform scale against the analytic irradiance, determinism across thread counts and
// splits, the JSON round trip, and the errors for bad input.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include "facet/render/pov_export.h"
#include "facet/render/render.h"
#include "facet/render/scene.h"
#include "facet/render/scene_description.h"
#include "facet/testsupport/render_test_util.h"

namespace fr = facet::render;
using facet::Rgb;
using facet::Vec3;

namespace {

const char* const kHead = R"({"format": "facet-scene", "version": 1, )";

fr::SceneDescription describe(const std::string& body) {
    return fr::parse_scene_description(std::string(kHead) + body + "}", "inst.json");
}

std::string error_of(const std::string& body) {
    try {
        fr::build_scene(describe(body), "inst.json");
    } catch (const fr::SceneError& e) {
        return e.what();
    }
    return "";
}

// The prototype "tree": a smooth mesh (a tent of 4 triangles with vertex normals and UVs, its
// own transform) and a box, each with its own material.
const char* const kPrototype = R"(
  "materials": {"bark": {"model": "lambert", "reflectance": [0.5, 0.3, 0.2]},
                "leaf": {"model": "ggx", "alpha": 0.3, "fresnel": "conductor"}},
  "prototypes": {"tree": [
    {"type": "mesh", "material": "leaf", "name": "crown",
     "positions": [-1, -1, 0,  1, -1, 0,  1, 1, 0,  -1, 1, 0,  0, 0, 1],
     "indices": [0, 1, 4,  1, 2, 4,  2, 3, 4,  3, 0, 4],
     "normals": [-0.5, -0.5, 0.7,  0.5, -0.5, 0.7,  0.5, 0.5, 0.7,  -0.5, 0.5, 0.7,  0, 0, 1],
     "uvs": [0, 0,  1, 0,  1, 1,  0, 1,  0.5, 0.5],
     "transform": {"translate": [0, 0, 0.6]}},
    {"type": "box", "material": "bark", "min": [-0.2, -0.2, 0], "max": [0.2, 0.2, 0.6]}
  ]},)";

// Three placements: a rotation and uniform scale, a mirror, a translation only.
const char* const kPlacements[3] = {
    R"({"rotate": {"axis": [1, 2, 0.5], "angle": 30}, "scale": 0.8, "translate": [-1.6, 0, 0]})",
    R"({"scale": [-1, 1, 1], "translate": [0, 0.2, 0]})", R"({"translate": [1.7, -0.3, 0.1]})"};

const char* const kRest = R"(
  "camera": {"position": [0, -6, 4], "look_at": [0, 0, 0.5], "up": [0, 0, 1], "fov": 45,
             "width": 32, "height": 24},
  "lights": [{"type": "directional", "direction": [-0.3, 0.4, -1], "irradiance": 3},
             {"type": "environment", "radiance": 0.2}],
  "render": {"max_depth": 3})";

// The instanced scene, plus a ground quad.
std::string instanced_scene() {
    std::string s = std::string(kPrototype) + R"("shapes": [
    {"type": "quad", "material": "bark",
     "vertices": [[-4, -4, 0], [4, -4, 0], [4, 4, 0], [-4, 4, 0]]})";
    for (const char* p : kPlacements)
        s += std::string(R"(, {"type": "instance", "of": "tree", "transform": )") + p + "}";
    return s + "]," + kRest;
}

// The same scene flattened: each instance's shapes with the transform list "shape's, then the
// instance's" (the FORMAT's transform arrays apply in order).
std::string flattened_scene() {
    std::string s = std::string(R"(
  "materials": {"bark": {"model": "lambert", "reflectance": [0.5, 0.3, 0.2]},
                "leaf": {"model": "ggx", "alpha": 0.3, "fresnel": "conductor"}},
  "shapes": [
    {"type": "quad", "material": "bark",
     "vertices": [[-4, -4, 0], [4, -4, 0], [4, 4, 0], [-4, 4, 0]]})");
    for (const char* p : kPlacements) {
        s += std::string(R"(,
    {"type": "mesh", "material": "leaf",
     "positions": [-1, -1, 0,  1, -1, 0,  1, 1, 0,  -1, 1, 0,  0, 0, 1],
     "indices": [0, 1, 4,  1, 2, 4,  2, 3, 4,  3, 0, 4],
     "normals": [-0.5, -0.5, 0.7,  0.5, -0.5, 0.7,  0.5, 0.5, 0.7,  -0.5, 0.5, 0.7,  0, 0, 1],
     "uvs": [0, 0,  1, 0,  1, 1,  0, 1,  0.5, 0.5],
     "transform": [{"translate": [0, 0, 0.6]}, )") +
             p + R"(]},
    {"type": "box", "material": "bark", "min": [-0.2, -0.2, 0], "max": [0.2, 0.2, 0.6],
     "transform": )" +
             p + "}";
    }
    return s + "]," + kRest;
}

double max_abs_diff(const fr::Image& a, const fr::Image& b) {
    double m = 0.0;
    for (std::size_t i = 0; i < a.pixels().size(); ++i)
        for (int c = 0; c < 3; ++c)
            m = std::max(m, double(std::fabs(a.pixels()[i][c] - b.pixels()[i][c])));
    return m;
}

// Traces the camera ray through each pixel (at `offset` in it) in both scenes: both must find
// the same surface (the same material) at the same point with the same normals, to float
// round-off. The instance hit is computed in object space from a ray moved there in float and
// taken back in double, the flattened one in world space from world-space float vertices: both
// are within a few float spacings of the exact hit. Tolerances: points 2e-5 (scenes of size
// ~5: ~40 spacings at 4, the float vertices' own rounding and Embree's t included), unit
// vectors 2e-5, t 2e-5 relative. A wrong transform (normals by M instead of M^-T, a missed
// mirror) moves them by O(1). Returns the hits, and those on shapes other than shape 0.
std::pair<int, int> compare_hits(const fr::Scene& a_scene, const fr::Scene& b_scene,
                                 facet::Vec2 offset) {
    int hits = 0, others = 0;
    const fr::Camera& cam = a_scene.camera();
    for (int y = 0; y < cam.height; ++y) {
        for (int x = 0; x < cam.width; ++x) {
            const fr::Ray ray = cam.generate_ray({float(x) + offset.x, float(y) + offset.y});
            fr::SurfaceHit a, b;
            const bool fa = a_scene.intersect(ray, a), fb = b_scene.intersect(ray, b);
            EXPECT_EQ(fa, fb) << x << "," << y;
            if (!fa || !fb) continue;
            ++hits;
            others += a.shape != 0;
            EXPECT_EQ(a_scene.shapes()[a.shape].material_name,
                      b_scene.shapes()[b.shape].material_name);
            for (int c = 0; c < 3; ++c) {
                EXPECT_NEAR(a.p[c], b.p[c], 2e-5) << x << "," << y;
                EXPECT_NEAR(a.ng[c], b.ng[c], 2e-5) << x << "," << y;
                EXPECT_NEAR(a.ns[c], b.ns[c], 2e-5) << x << "," << y;
            }
            EXPECT_NEAR(a.t, b.t, 2e-5 * b.t);
        }
    }
    return {hits, others};
}

}  // namespace

TEST(Instancing, HitsMatchTheFlattenedScene) {
    const fr::Scene inst = fr::build_scene(describe(instanced_scene()), "inst.json");
    const fr::Scene flat = fr::build_scene(describe(flattened_scene()), "flat.json");
    const auto [hits, on_instances] = compare_hits(inst, flat, {0.37f, 0.61f});
    EXPECT_GT(on_instances, 50);  // the instances are in view
    EXPECT_GT(hits, on_instances);
}

// The images of the two scenes agree: the same sample sequences meet the same surfaces, and
// their points differ by float round-off only (above), which moves each path's next origin by
// ulps. They are not bit-identical (the instance's hit is computed in its object space), and a
// path that grazes an edge could take another branch, so the bounds are: the means within
// 1e-5 relative, and 99% of the pixels within 1e-4 (measured: means 3e-8 apart, every pixel
// within 1e-6). A wrong material, normal or placement changes the mean by percents.
TEST(Instancing, ImageMatchesTheFlattenedScene) {
    const fr::Scene inst = fr::build_scene(describe(instanced_scene()), "inst.json");
    const fr::Scene flat = fr::build_scene(describe(flattened_scene()), "flat.json");
    const fr::Image a = fr::render(inst, fr::testing::test_options("path", 8, 3));
    const fr::Image b = fr::render(flat, fr::testing::test_options("path", 8, 3));
    double sa = 0.0, sb = 0.0;
    int close = 0;
    for (std::size_t i = 0; i < a.pixels().size(); ++i) {
        double d = 0.0;
        for (int c = 0; c < 3; ++c) {
            sa += a.pixels()[i][c];
            sb += b.pixels()[i][c];
            d = std::max(d, double(std::fabs(a.pixels()[i][c] - b.pixels()[i][c])));
        }
        close += d <= 1e-4;
    }
    EXPECT_NEAR(sa / sb, 1.0, 1e-5);
    EXPECT_GE(close, int(0.99 * double(a.pixels().size())));
}

// The same image for 1 and 2 threads, for other tile sizes, for a region rendered alone, and
// when rendered as two sample ranges merged (the render farm's splits): bit for bit.
TEST(Instancing, ImagesAreBitIdenticalAcrossThreadsAndSplits) {
    const fr::Scene inst = fr::build_scene(describe(instanced_scene()), "inst.json");
    const fr::Image one = fr::render(inst, fr::testing::test_options("path", 4, 9, 1));
    const fr::Image two = fr::render(inst, fr::testing::test_options("path", 4, 9, 2));
    fr::RenderOptions small_tiles = fr::testing::test_options("path", 4, 9, 2);
    small_tiles.tile_size = 8;
    const fr::Image tiled = fr::render(inst, small_tiles);
    ASSERT_EQ(one.pixels().size(), two.pixels().size());
    EXPECT_EQ(max_abs_diff(one, two), 0.0);
    EXPECT_EQ(
        std::memcmp(one.pixels().data(), two.pixels().data(), one.pixels().size() * sizeof(Rgb)),
        0);
    EXPECT_EQ(
        std::memcmp(one.pixels().data(), tiled.pixels().data(), one.pixels().size() * sizeof(Rgb)),
        0);
    fr::RenderOptions crop = fr::testing::test_options("path", 4, 9, 2);
    crop.region = fr::Region{5, 3, 27, 19};
    const fr::Image part = fr::render(inst, crop);
    for (int y = 3; y < 19; ++y)
        for (int x = 5; x < 27; ++x)
            ASSERT_EQ(part.at(x - 5, y - 3), one.at(x, y)) << x << "," << y;
    std::vector<fr::RenderPart> halves;
    for (int h = 0; h < 2; ++h) {
        fr::RenderOptions o = fr::testing::test_options("path", 4, 9, 2);
        o.sample_begin = 2 * h;
        o.sample_end = 2 * h + 2;
        fr::RenderSession session(inst, o);
        session.render();
        halves.push_back(session.part());
    }
    const fr::Image merged = fr::merge_parts(halves, {"s0", "s1"}).resolve();
    EXPECT_EQ(
        std::memcmp(one.pixels().data(), merged.pixels().data(), one.pixels().size() * sizeof(Rgb)),
        0);
}

// A unit quad (z = 0, facing +z) placed by M = diag(1, 1, 3) R_x(40 deg) translated: a
// non-uniform scale after a rotation, so the world normal is M^-T n normalised, not M n. Under a
// directional light of irradiance E from direction -l and no environment, a Lambertian of
// reflectance rho has radiance rho/pi E max(0, n . l) everywhere on it (direct integrator,
// exact: one deterministic light sample). Checked at the hit (ng to 1e-6: double math rounded
// to float) and in the image (1e-5 relative: float shading). The wrong normal M n gives a
// cosine 0.29 different, which fails both.
TEST(Instancing, NonUniformScaleNormalsAreInverseTranspose) {
    const std::string body = R"(
      "materials": {"w": {"model": "lambert", "reflectance": 0.6}},
      "prototypes": {"card": [{"type": "quad", "material": "w",
          "vertices": [[-1, -1, 0], [1, -1, 0], [1, 1, 0], [-1, 1, 0]]}]},
      "shapes": [{"type": "instance", "of": "card", "transform": [
          {"rotate": {"axis": [1, 0, 0], "angle": 40}}, {"scale": [1, 1, 3]},
          {"translate": [0, 0, 1]}]}],
      "camera": {"position": [0, -0.2, 8], "look_at": [0, 0, 1], "up": [0, 1, 0], "fov": 4,
                 "width": 8, "height": 8},
      "lights": [{"type": "directional", "direction": [0, 0.5, -1], "irradiance": 2}],
      "render": {"max_depth": 1})";
    const fr::Scene scene = fr::build_scene(describe(body), "inst.json");
    const double a = 40.0 * 3.14159265358979323846 / 180.0;
    // M^-T (0, 0, 1): R_x(a) takes z to (0, -sin a, cos a); the scale's inverse transpose
    // divides z by 3.
    glm::dvec3 n(0.0, -std::sin(a), std::cos(a) / 3.0);
    n = glm::normalize(n);
    glm::dvec3 wrong = glm::normalize(glm::dvec3(0.0, -std::sin(a), 3.0 * std::cos(a)));
    const glm::dvec3 l = glm::normalize(glm::dvec3(0.0, -0.5, 1.0));  // toward the light
    const double expected = 0.6 / 3.14159265358979323846 * 2.0 * std::max(0.0, glm::dot(n, l));
    ASSERT_GT(std::fabs(glm::dot(n, l) - glm::dot(wrong, l)), 0.2);

    fr::SurfaceHit hit;
    const fr::Ray ray = scene.camera().generate_ray({4.f, 4.f});
    ASSERT_TRUE(scene.intersect(ray, hit));
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(hit.ng[c], n[c], 1e-6);
    const fr::Image img = fr::render(scene, fr::testing::test_options("direct", 1, 1));
    for (const Rgb& p : img.pixels()) EXPECT_NEAR(p.r, expected, 1e-5 * expected);
}

// The description round-trips through JSON (prototypes and instances written and read back).
TEST(Instancing, JsonRoundTrip) {
    const fr::SceneDescription d = describe(instanced_scene());
    ASSERT_EQ(d.prototypes.size(), 1u);
    EXPECT_EQ(d.prototypes[0].second.size(), 2u);
    const std::string text = fr::write_scene_json(d);
    fr::SceneDescription back = fr::parse_scene_description(text, "back.json");
    EXPECT_TRUE(back == d);
    EXPECT_EQ(fr::fingerprint(back), fr::fingerprint(d));
}

// Bad input: errors name the JSON pointer.
TEST(Instancing, ErrorsNameThePointer) {
    const std::string cam = R"("camera": {"position": [0, 0, 5], "look_at": [0, 0, 0],
        "fov": 40, "width": 4, "height": 4}, "lights": [{"type": "environment", "radiance": 1}],
        "materials": {"w": {"model": "lambert", "reflectance": 0.5}},)";
    const std::string quad =
        R"({"type": "quad", "material": "w", "vertices": [[0,0,0],[1,0,0],[1,1,0],[0,1,0]]})";
    auto with = [&](const std::string& protos, const std::string& shapes) {
        return cam + R"("prototypes": )" + protos + R"(, "shapes": )" + shapes;
    };
    const std::string ok = R"({"a": [)" + quad + "]}";
    EXPECT_NE(error_of(with(ok, R"([{"type": "instance", "of": "b"}])"))
                  .find("/shapes/0/of: unknown prototype 'b' (known: 'a')"),
              std::string::npos);
    EXPECT_NE(error_of(with(R"({"a": [{"type": "instance", "of": "a"}]})", "[]"))
                  .find("/prototypes/a/0/of: a prototype cannot hold instances"),
              std::string::npos);
    EXPECT_NE(error_of(with(ok, R"([{"type": "instance", "of": "a",
                                     "transform": {"scale": [1, 0, 1]}}])"))
                  .find("/shapes/0/transform: the transform is singular"),
              std::string::npos);
    EXPECT_NE(error_of(with(R"({"a": [{"type": "quad", "emission": 1,
                                       "vertices": [[0,0,0],[1,0,0],[1,1,0],[0,1,0]]}]})",
                            "[]"))
                  .find("/prototypes/a/0/emission: a prototype's shapes cannot emit"),
              std::string::npos);
    EXPECT_NE(error_of(with(R"({"a": [{"type": "sphere", "material": "w", "center": [0,0,0],
                                       "radius": 1}]})",
                            "[]"))
                  .find("/prototypes/a/0/type: a prototype holds triangle shapes and curves only"),
              std::string::npos);
    EXPECT_NE(error_of(with(ok, R"([{"type": "instance", "of": "a", "material": "w"}])"))
                  .find("/shapes/0/material: an instance takes its prototype's materials"),
              std::string::npos);
    EXPECT_NE(error_of(with(R"({"a": []})", "[]")).find("/prototypes/a: a prototype needs"),
              std::string::npos);
    EXPECT_NE(error_of(with(ok, R"([{"type": "instance"}])"))
                  .find("/shapes/0: missing required key 'of'"),
              std::string::npos);
    EXPECT_NE(error_of(with(R"({"a": [{"type": "quad", "material": "nope",
                                       "vertices": [[0,0,0],[1,0,0],[1,1,0],[0,1,0]]}]})",
                            "[]"))
                  .find("/prototypes/a/0/material"),
              std::string::npos);
    EXPECT_EQ(error_of(with(ok, R"([{"type": "instance", "of": "a"}])")), "");
}

// export-pov declares the prototype once and places it per instance with its matrix.
TEST(Instancing, PovExportDeclaresThePrototypeOnce) {
    fr::PovExportOptions options;
    options.environment = "background";  // the scene's constant environment
    const std::string pov = fr::export_pov(describe(instanced_scene()), "inst.json", options);
    const std::string decl = "#declare FacetPrototype0 = union {";
    ASSERT_NE(pov.find(decl), std::string::npos);
    EXPECT_EQ(pov.find(decl, pov.find(decl) + 1), std::string::npos);
    std::size_t n = 0;
    for (std::size_t at = pov.find("object { FacetPrototype0\n  matrix <"); at != std::string::npos;
         at = pov.find("object { FacetPrototype0\n  matrix <", at + 1))
        ++n;
    EXPECT_EQ(n, 3u);
}

// glTF: a mesh that three nodes use is stored once and placed as instances; the same file with
// a copy of the mesh per node is flattened. Both give the same hits (compare_hits; the box's face
// normals interpolate alike under the non-uniform node scale) and the same image to float
// round-off; the shared file counts its 12 triangles once.
TEST(Instancing, GltfSharedMeshesMatchCopies) {
    auto scene_of = [](const std::string& file) {
        return fr::build_scene(describe(R"(
          "shapes": [{"type": "gltf", "file": ")" FACET_GLTF_TEST_DIR "/" +
                                        file + R"(",
                      "transform": {"rotate": {"axis": [0, 0, 1], "angle": 20}}},
                     {"type": "quad", "material": {"model": "lambert", "reflectance": 0.5},
                      "vertices": [[-6, -6, -1], [6, -6, -1], [6, 6, -1], [-6, 6, -1]]}],
          "camera": {"position": [1, -7, 4], "look_at": [0, 0, 0], "up": [0, 0, 1], "fov": 50,
                     "width": 32, "height": 24},
          "lights": [{"type": "directional", "direction": [-0.3, 0.4, -1], "irradiance": 3},
                     {"type": "environment", "radiance": 0.2}],
          "render": {"max_depth": 3})"),
                               file);
    };
    const fr::Scene shared = scene_of("shared_mesh.gltf");
    const fr::Scene copies = scene_of("shared_mesh_copies.gltf");
    EXPECT_EQ(shared.features().num_triangles, 12u + 2u);
    EXPECT_EQ(copies.features().num_triangles, 36u + 2u);
    const auto [hits, on_boxes] = compare_hits(shared, copies, {0.5f, 0.5f});
    EXPECT_GT(hits, on_boxes);
    EXPECT_GT(on_boxes, 40);
    const fr::Image ia = fr::render(shared, fr::testing::test_options("path", 4, 3));
    const fr::Image ib = fr::render(copies, fr::testing::test_options("path", 4, 3));
    EXPECT_LE(max_abs_diff(ia, ib), 1e-4);
}
