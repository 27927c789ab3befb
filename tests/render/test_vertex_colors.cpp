// Vertex colours (mesh.h, texture.h, scenes/FORMAT.md "Vertex colours"): the mesh key
// "colors", the texture {"vertex_color": true} on material parameters and emission,
// barycentric interpolation at hits, glTF COLOR_0 times the base colour, OBJ and PLY colours,
// and the errors for bad input.
#include <gtest/gtest.h>

#include <OpenImageIO/imageio.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "facet/render/mesh.h"
#include "facet/render/render.h"
#include "facet/render/scene.h"
#include "facet/render/scene_description.h"
#include "facet/render/texture.h"
#include "facet/testsupport/render_test_util.h"
#include "oiio_test_image.h"

namespace fr = facet::render;
using facet::Rgb;
using facet::Vec2;
using facet::Vec3;

namespace {

std::string temp_dir() {
    return fr::testing::test_temp_dir("facet_vertex_colors");
}

fr::Scene scene_in(const std::string& dir, const std::string& body) {
    return fr::testing::scene_in_dir(dir, body, "vc.json");
}

std::string error_of_in(const std::string& dir, const std::string& body) {
    return fr::testing::scene_error(dir, body, "vc.json");
}

std::string error_of(const std::string& body) {
    return error_of_in(temp_dir(), body);
}

// IEC 61966-2-1 decoding in double (the documented decoding of byte colours).
float srgb(double e) {
    return float(e <= 0.04045 ? e / 12.92 : std::pow((e + 0.055) / 1.055, 2.4));
}

// The 4 x 3 camera of test_textures.cpp: pixel (x, y)'s centre ray meets z = 0 at
// (x - 1.5, 1 - y).
const char* const kCamera =
    R"("camera": {"position": [0, 0, 1.5], "look_at": [0, 0, 0], "up": [0, 1, 0], "fov": 90,
                  "width": 4, "height": 3},)";

// The triangle P0 (-2, -1.5), P1 (2, -1.5), P2 (-2, 1.5) in z = 0, facing +z, with corner
// colours c0, c1, c2 (RGBA): at (px, py) its barycentrics are b1 = (px + 2) / 4,
// b2 = (py + 1.5) / 3, b0 = 1 - b1 - b2.
const float kCorner[3][4] = {
    {0.9f, 0.1f, 0.2f, 1.0f}, {0.1f, 0.8f, 0.3f, 0.5f}, {0.2f, 0.3f, 0.7f, 0.25f}};

std::string triangle_mesh(const std::string& material_or_emission) {
    std::string colors;
    for (const auto& c : kCorner)
        for (float v : c) colors += (colors.empty() ? "" : ", ") + std::to_string(v);
    return R"({"type": "mesh", "positions": [-2, -1.5, 0, 2, -1.5, 0, -2, 1.5, 0],
               "indices": [0, 1, 2], "colors": [)" +
           colors + "], " + material_or_emission + "}";
}

// The interpolated colour (channel c) at pixel (x, y)'s centre, or -1 outside the triangle.
float expected_at(int x, int y, int c) {
    const double px = x - 1.5, py = 1.0 - y;
    const double b1 = (px + 2.0) / 4.0, b2 = (py + 1.5) / 3.0, b0 = 1.0 - b1 - b2;
    if (b0 < 0.0) return -1.f;
    return float(b0 * kCorner[0][c] + b1 * kCorner[1][c] + b2 * kCorner[2][c]);
}

fr::Image render_once(const fr::Scene& scene, const std::string& integrator) {
    return fr::render(scene, fr::testing::test_options(integrator, 1, 3, 1));
}

}  // namespace

// A vertex-colour emission seen directly: each pixel centre inside the triangle gets the
// barycentric interpolation of the corner colours. The camera ray adds the emission with
// weight 1, so the only error is Embree's float barycentrics (~1e-7 relative) and the float
// interpolation: tolerance 2e-6 absolute. Taking the corners in the wrong order, or the
// colours as sRGB, moves values by > 1e-2.
TEST(VertexColors, EmissionInterpolatesCornerColoursBarycentrically) {
    const fr::Scene scene =
        scene_in(temp_dir(), std::string(kCamera) + R"("shapes": [)" + triangle_mesh(R"("emission":
                                                         {"vertex_color": true})") +
                                 R"(], "lights": [])");
    ASSERT_EQ(scene.lights().size(), 1u);
    EXPECT_TRUE(scene.shapes()[0].needs_color);
    EXPECT_FALSE(scene.shapes()[0].needs_uv);  // a vertex colour needs no UVs
    const fr::Image img = render_once(scene, "path");
    int inside = 0;
    for (int y = 0; y < 3; ++y)
        for (int x = 0; x < 4; ++x) {
            if (expected_at(x, y, 0) < 0.f) continue;
            ++inside;
            for (int c = 0; c < 3; ++c)
                EXPECT_NEAR(img.at(x, y)[c], expected_at(x, y, c), 2e-6f)
                    << x << "," << y << " c" << c;
        }
    EXPECT_GE(inside, 6);
}

// A Lambertian reflectance from the vertex colour's alpha (channel "a", scale 0.8) under a
// constant environment of radiance 1, max_depth 1: L = rho (test_textures.cpp's argument:
// every cosine-weighted sample gives rho exactly), rho = 0.8 alpha(b). Tolerance 2e-6 as above.
TEST(VertexColors, ReflectanceFromOneChannelUnderConstantEnvironment) {
    const fr::Scene scene = scene_in(temp_dir(), std::string(kCamera) + R"("shapes": [)" +
                                                     triangle_mesh(R"("material": {
                                                         "model": "lambert", "reflectance":
                                                         {"vertex_color": true, "channel": "a",
                                                          "scale": 0.8}})") +
                                                     R"(], "lights": [{"type": "environment",
                                                         "radiance": 1}],
                                                         "render": {"max_depth": 1})");
    const fr::Image img = render_once(scene, "path");
    for (int y = 0; y < 3; ++y)
        for (int x = 0; x < 4; ++x) {
            if (expected_at(x, y, 3) < 0.f) continue;
            for (int c = 0; c < 3; ++c)
                EXPECT_NEAR(img.at(x, y)[c], 0.8f * expected_at(x, y, 3), 2e-6f)
                    << x << "," << y << " c" << c;
        }
}

// A hit at a known barycentric point: SurfaceHit::color is (1 - u - v) c0 + u c1 + v c2.
// The point (0.5, -0.75) has b1 = 0.625, b2 = 0.25: tolerance 1e-6 (float barycentrics).
TEST(VertexColors, HitColourAtAKnownBarycentricPoint) {
    const fr::Scene scene =
        scene_in(temp_dir(), std::string(kCamera) + R"("shapes": [)" + triangle_mesh(R"("emission":
                                                         {"vertex_color": true})") +
                                 "], \"lights\": []");
    fr::SurfaceHit hit;
    ASSERT_TRUE(scene.intersect(fr::Ray{Vec3(0.5f, -0.75f, 1.f), Vec3(0.f, 0.f, -1.f)}, hit));
    const double b1 = 0.625, b2 = 0.25, b0 = 1.0 - b1 - b2;
    for (int c = 0; c < 4; ++c)
        EXPECT_NEAR(hit.color[c], b0 * kCorner[0][c] + b1 * kCorner[1][c] + b2 * kCorner[2][c],
                    1e-6)
            << c;
}

// An untextured scene never computes a colour: the hit keeps the default white, and the
// shape asks for none (skip what a scene does not need).
TEST(VertexColors, UnusedColoursAreNotInterpolated) {
    const fr::Scene scene =
        scene_in(temp_dir(), std::string(kCamera) + R"("shapes": [)" +
                                 triangle_mesh(R"("material": {"model": "lambert",
                                                   "reflectance": 0.5})") +
                                 "], \"lights\": [{\"type\": \"environment\", \"radiance\": 1}]");
    EXPECT_FALSE(scene.shapes()[0].needs_color);
    fr::SurfaceHit hit;
    ASSERT_TRUE(scene.intersect(fr::Ray{Vec3(0.5f, -0.75f, 1.f), Vec3(0.f, 0.f, -1.f)}, hit));
    EXPECT_EQ(hit.color, glm::vec4(1.f));
}

TEST(VertexColors, JsonRoundTripKeepsColoursAndTheTexture) {
    const std::string text = R"({"format": "facet-scene", "version": 1, )" + std::string(kCamera) +
                             R"("shapes": [)" +
                             triangle_mesh(R"("material": {"model": "lambert", "reflectance":
                                 {"vertex_color": true, "scale": 0.5}})") +
                             "], \"lights\": []}";
    const fr::SceneDescription d = fr::parse_scene_description(text, "vc.json", temp_dir());
    ASSERT_EQ(d.shapes[0].mesh.colors.size(), 12u);
    const fr::TextureDesc& t = d.shapes[0].material->textures.at("reflectance");
    EXPECT_EQ(t.kind, "vertex_color");
    EXPECT_EQ(t.scale, 0.5);
    const fr::SceneDescription back =
        fr::parse_scene_description(fr::write_scene_json(d), "vc.json", temp_dir());
    EXPECT_EQ(back, d);
}

// Bad input: each error names the JSON pointer (and the material for a missing attribute).
TEST(VertexColors, BadInputNamesThePointer) {
    const std::string head = std::string(kCamera) + R"("lights": [], "shapes": [)";
    const std::string tri = R"({"type": "mesh", "positions": [0, 0, 0, 1, 0, 0, 0, 1, 0],
                                "indices": [0, 1, 2], )";
    const std::string lam = R"("material": {"model": "lambert", "reflectance":
                                   {"vertex_color": true}})";
    // Wrong length (neither 3 nor 4 per position).
    EXPECT_NE(error_of(head + tri + R"("colors": [1, 1, 1, 1, 1], )" + lam + "}]")
                  .find("/shapes/0/colors: expected a flat array of 3 (r, g, b) or 4"),
              std::string::npos);
    // Out of [0, 1].
    EXPECT_NE(error_of(head + tri + R"("colors": [1, 1, 1, 1, 1.5, 1, 1, 1, 1], )" + lam + "}]")
                  .find("/shapes/0/colors/4: must be a finite number in [0, 1]"),
              std::string::npos);
    // A mesh without colours.
    const std::string no_colors = error_of(head + tri + lam + "}]");
    EXPECT_NE(no_colors.find("/shapes/0/colors: the material '<inline>'"), std::string::npos)
        << no_colors;
    EXPECT_NE(no_colors.find("the mesh has no colours"), std::string::npos) << no_colors;
    // A named material on an analytic sphere.
    const std::string sphere =
        error_of(std::string(kCamera) +
                 R"("lights": [], "materials": {"painted": {"model": "lambert", "reflectance":
              {"vertex_color": true}}},
           "shapes": [{"type": "sphere", "center": [0, 0, 0], "radius": 1,
                       "material": "painted"}])");
    EXPECT_NE(sphere.find("/shapes/0/type: the material 'painted'"), std::string::npos) << sphere;
    EXPECT_NE(sphere.find("a 'sphere' has none"), std::string::npos) << sphere;
    // A number parameter needs a channel.
    EXPECT_NE(error_of(head + tri + R"("colors": [1, 1, 1, 1, 1, 1, 1, 1, 1],
                  "material": {"model": "oren_nayar", "reflectance": 0.5,
                               "sigma": {"vertex_color": true}}}])")
                  .find("/shapes/0/material/sigma/channel: a number parameter reads one channel"),
              std::string::npos);
    // Not an opacity, not a bump map.
    EXPECT_NE(error_of(head + tri + R"("colors": [1, 1, 1, 1, 1, 1, 1, 1, 1],
                  "material": {"model": "lambert", "reflectance": 0.5,
                               "opacity": {"vertex_color": true, "channel": "a"}}}])")
                  .find("/shapes/0/material/opacity: a vertex colour cannot be an opacity"),
              std::string::npos);
    EXPECT_NE(error_of(head + tri + R"("colors": [1, 1, 1, 1, 1, 1, 1, 1, 1],
                  "material": {"model": "lambert", "reflectance": 0.5,
                               "bump": {"vertex_color": true, "channel": "r"}}}])")
                  .find("/shapes/0/material/bump: a vertex colour cannot be"),
              std::string::npos);
    // "vertex_color": false, and keys that belong to images.
    EXPECT_NE(error_of(head + tri + R"("colors": [1, 1, 1, 1, 1, 1, 1, 1, 1],
                  "material": {"model": "lambert", "reflectance": {"vertex_color": false}}}])")
                  .find("/shapes/0/material/reflectance/vertex_color: must be true"),
              std::string::npos);
    EXPECT_NE(error_of(head + tri + R"("colors": [1, 1, 1, 1, 1, 1, 1, 1, 1],
                  "material": {"model": "lambert", "reflectance":
                      {"vertex_color": true, "uv_scale": [2, 2]}}}])")
                  .find("/shapes/0/material/reflectance"),
              std::string::npos);
    // A reflectance above 1 through the scale: the registry's range check at the largest value.
    EXPECT_NE(error_of(head + tri + R"("colors": [1, 1, 1, 1, 1, 1, 1, 1, 1],
                  "material": {"model": "lambert", "reflectance":
                      {"vertex_color": true, "scale": 1.5}}}])")
                  .find("/shapes/0/material/reflectance"),
              std::string::npos);
}

// OBJ: `v x y z r g b` colours, sRGB-decoded (as Blender writes them); a file where only some
// vertices have colours has none (tinyobjloader's rule). Exact: the same double decoding.
TEST(VertexColors, ObjColoursAreReadAsSrgb) {
    const std::string dir = temp_dir();
    {
        std::ofstream f(dir + "/c.obj");
        f << "v 0 0 0 1 0.5 0\nv 1 0 0 0 0.2 1\nv 0 1 0 0.04 0.25 0.75\nf 1 2 3\n";
    }
    const fr::TriangleMesh m = fr::load_obj(dir + "/c.obj");
    ASSERT_EQ(m.colors.size(), 3u);
    EXPECT_EQ(m.colors[0], glm::vec4(1.f, srgb(0.5), 0.f, 1.f));
    EXPECT_EQ(m.colors[1], glm::vec4(0.f, srgb(0.2), 1.f, 1.f));
    EXPECT_EQ(m.colors[2], glm::vec4(srgb(0.04), srgb(0.25), srgb(0.75), 1.f));
    {
        std::ofstream f(dir + "/partial.obj");
        f << "v 0 0 0 1 0.5 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
    }
    EXPECT_TRUE(fr::load_obj(dir + "/partial.obj").colors.empty());
}

// PLY: uchar red green blue alpha are sRGB bytes (alpha linear, a / 255); float colours are
// linear; other integer types are errors naming the property.
TEST(VertexColors, PlyColoursByType) {
    const std::string head =
        "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
        "property float z\n";
    const fr::TriangleMesh bytes = fr::parse_ply(
        head +
        "property uchar red\nproperty uchar green\nproperty uchar blue\nproperty uchar alpha\n"
        "element face 1\nproperty list uchar int vertex_indices\nend_header\n"
        "0 0 0 255 128 0 255\n1 0 0 10 20 30 51\n0 1 0 0 0 255 0\n3 0 1 2\n");
    ASSERT_EQ(bytes.colors.size(), 3u);
    EXPECT_EQ(bytes.colors[0], glm::vec4(1.f, srgb(128.0 / 255.0), 0.f, 1.f));
    EXPECT_EQ(bytes.colors[1],
              glm::vec4(srgb(10.0 / 255.0), srgb(20.0 / 255.0), srgb(30.0 / 255.0), 0.2f));
    EXPECT_EQ(bytes.colors[2], glm::vec4(0.f, 0.f, 1.f, 0.f));
    const fr::TriangleMesh floats =
        fr::parse_ply(head +
                      "property float red\nproperty float green\nproperty float blue\n"
                      "element face 1\nproperty list uchar int vertex_indices\nend_header\n"
                      "0 0 0 0.5 0.25 0\n1 0 0 1 1 1\n0 1 0 0 0 0.125\n3 0 1 2\n");
    ASSERT_EQ(floats.colors.size(), 3u);
    EXPECT_EQ(floats.colors[0], glm::vec4(0.5f, 0.25f, 0.f, 1.f));
    try {
        fr::parse_ply(head +
                      "property int red\nproperty int green\nproperty int blue\n"
                      "element face 0\nproperty list uchar int vertex_indices\n"
                      "end_header\n0 0 0 1 1 1\n1 0 0 1 1 1\n0 1 0 1 1 1\n");
        ADD_FAILURE() << "int colours accepted";
    } catch (const std::runtime_error& e) {
        EXPECT_NE(std::string(e.what()).find("'red' must be uchar, ushort, float or double"),
                  std::string::npos)
            << e.what();
    }
    // Out of range float colours are reported by the mesh validation.
    fr::TriangleMesh bad = floats;
    bad.colors[1].g = 2.f;
    EXPECT_NE(fr::validate_mesh(bad).find("colour 1 has a channel outside [0, 1]"),
              std::string::npos);
}

namespace {

// A hand-made glTF: the triangle above as three primitives sharing material 0 (baseColorFactor
// f = (0.5, 0.25, 1)): primitive 0 with COLOR_0 as normalised unsigned bytes VEC4, primitive 1
// (moved to z = -1) with COLOR_0 as float VEC3, primitive 2 (z = -2) without colours; material
// 1 has a base colour texture (a 1 x 1 PNG) and is used by primitive 3 (z = -3) with float
// colours.
void write_gltf(const std::string& dir) {
    std::vector<unsigned char> bin;
    auto put = [&](const void* p, std::size_t n) {
        const auto* b = static_cast<const unsigned char*>(p);
        bin.insert(bin.end(), b, b + n);
    };
    for (float z : {0.f, -1.f, -2.f, -3.f}) {
        const float pos[9] = {-2, -1.5f, z, 2, -1.5f, z, -2, 1.5f, z};
        put(pos, sizeof pos);  // 36 bytes each, offsets 0, 36, 72, 108
    }
    const unsigned char ub[12] = {255, 0, 0, 255, 0, 255, 0, 128, 0, 0, 255, 0};
    put(ub, sizeof ub);  // offset 144
    const float fl[9] = {0.25f, 0.5f, 1.f, 1.f, 0.f, 0.5f, 0.f, 1.f, 0.75f};
    put(fl, sizeof fl);  // offset 156, 36 bytes
    const float uv[6] = {0, 0, 1, 0, 0, 1};
    put(uv, sizeof uv);  // offset 192, 24 bytes
    std::ofstream(dir + "/tri.bin", std::ios::binary)
        .write(reinterpret_cast<const char*>(bin.data()), std::streamsize(bin.size()));
    fr::testing::write_test_image(dir + "/base.png", 1, 1, 3,
                                  std::vector<std::uint8_t>{255, 255, 255}, OIIO::TypeDesc::UINT8);
    std::string accessors, views;
    for (int k = 0; k < 4; ++k) {
        views +=
            R"({"buffer": 0, "byteOffset": )" + std::to_string(36 * k) + R"(, "byteLength": 36},)";
        accessors += R"({"bufferView": )" + std::to_string(k) +
                     R"(, "componentType": 5126, "count": 3, "type": "VEC3",
                        "min": [-2, -1.5, -3], "max": [2, 1.5, 0]},)";
    }
    std::ofstream(dir + "/tri.gltf") << R"({"asset": {"version": "2.0"},
        "buffers": [{"uri": "tri.bin", "byteLength": 216}],
        "bufferViews": [)" + views + R"(
            {"buffer": 0, "byteOffset": 144, "byteLength": 12},
            {"buffer": 0, "byteOffset": 156, "byteLength": 36},
            {"buffer": 0, "byteOffset": 192, "byteLength": 24}],
        "accessors": [)" + accessors + R"(
            {"bufferView": 4, "componentType": 5121, "normalized": true, "count": 3,
             "type": "VEC4"},
            {"bufferView": 5, "componentType": 5126, "count": 3, "type": "VEC3"},
            {"bufferView": 6, "componentType": 5126, "count": 3, "type": "VEC2"}],
        "images": [{"uri": "base.png"}], "textures": [{"source": 0}],
        "materials": [
            {"pbrMetallicRoughness": {"baseColorFactor": [0.5, 0.25, 1, 1],
                                      "metallicFactor": 0, "roughnessFactor": 1}},
            {"pbrMetallicRoughness": {"baseColorFactor": [0.5, 0.25, 1, 1],
                                      "baseColorTexture": {"index": 0},
                                      "metallicFactor": 0, "roughnessFactor": 1}}],
        "meshes": [{"primitives": [
            {"attributes": {"POSITION": 0, "COLOR_0": 4}, "material": 0},
            {"attributes": {"POSITION": 1, "COLOR_0": 5}, "material": 0},
            {"attributes": {"POSITION": 2}, "material": 0},
            {"attributes": {"POSITION": 3, "COLOR_0": 5, "TEXCOORD_0": 6}, "material": 1}]}],
        "nodes": [{"mesh": 0}], "scenes": [{"nodes": [0]}], "scene": 0})";
}

}  // namespace

// glTF COLOR_0 multiplies the base colour (glTF 2.0 section 3.9.2): at a hit, the part's
// base_color source is f * c (factor times colour) or texel * f * c; a primitive without
// COLOR_0 keeps the constant factor. Colours: bytes / 255 (normalised), floats as given.
// Tolerance 1e-6 (float barycentrics at (0.5, -0.75): b = (0.125, 0.625, 0.25)).
TEST(VertexColors, GltfColor0MultipliesTheBaseColour) {
    const std::string dir = temp_dir();
    write_gltf(dir);
    const fr::Scene scene = scene_in(dir, std::string(kCamera) +
                                              R"("shapes": [{"type": "gltf", "file": "tri.gltf"}],
                    "lights": [{"type": "environment", "radiance": 1}])");
    const Rgb f(0.5f, 0.25f, 1.f);
    const double b[3] = {0.125, 0.625, 0.25};
    const glm::vec4 ub[3] = {{1, 0, 0, 1}, {0, 1, 0, 128 / 255.f}, {0, 0, 1, 0}};
    const glm::vec4 fl[3] = {{0.25f, 0.5f, 1, 1}, {1, 0, 0.5f, 1}, {0, 1, 0.75f, 1}};
    // The base colour source of the hit's textured material (slot "base_color").
    auto base_at = [&](float z, glm::vec4& color) -> std::optional<Rgb> {
        fr::SurfaceHit hit;
        // glTF (x, y, z) is Facet's (x, -z, y) (Z up, as Blender imports it).
        EXPECT_TRUE(scene.intersect(fr::Ray{Vec3(0.5f, -z - 0.5f, -0.75f), Vec3(0, 1, 0)}, hit));
        color = hit.color;
        if (hit.textured < 0) return std::nullopt;
        for (const auto& s : scene.textured_materials()[std::size_t(hit.textured)].slots)
            if (s.name == "base_color") return s.texture->eval(hit.uv, {}, hit.color);
        return std::nullopt;
    };
    auto mix = [&](const glm::vec4* c) {
        glm::dvec4 v(0.0);
        for (int k = 0; k < 3; ++k) v += b[k] * glm::dvec4(c[k]);
        return glm::vec4(v);
    };
    glm::vec4 color;
    for (const auto& [z, corners] :
         {std::pair<float, const glm::vec4*>{0.f, ub}, {-1.f, fl}, {-3.f, fl}}) {
        const std::optional<Rgb> base = base_at(z, color);
        ASSERT_TRUE(base.has_value()) << z;
        const glm::vec4 want = mix(corners);
        for (int c = 0; c < 4; ++c) EXPECT_NEAR(color[c], want[c], 1e-6) << z << " c" << c;
        for (int c = 0; c < 3; ++c) EXPECT_NEAR((*base)[c], f[c] * want[c], 1e-6) << z << " c" << c;
    }
    // Without COLOR_0: the constant factor (an untextured material).
    EXPECT_FALSE(base_at(-2.f, color).has_value());
}

// Bad COLOR_0 data: a float channel outside [0, 1] is an error naming the accessor.
TEST(VertexColors, GltfColourOutOfRangeIsAnError) {
    const std::string dir = temp_dir();
    write_gltf(dir);
    std::fstream f(dir + "/tri.bin", std::ios::in | std::ios::out | std::ios::binary);
    const float bad = 1.5f;
    f.seekp(156);
    f.write(reinterpret_cast<const char*>(&bad), sizeof bad);
    f.close();
    const std::string err = error_of_in(dir, std::string(kCamera) +
                                                 R"("shapes": [{"type": "gltf", "file":
                                                     "tri.gltf"}], "lights": [])");
    EXPECT_NE(err.find("/accessors/5: colour 0 has a channel outside [0, 1]"), std::string::npos)
        << err;
}
