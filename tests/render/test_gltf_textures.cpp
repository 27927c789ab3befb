// glTF textures (core/render/src/io/gltf_import.cpp): TEXCOORD_0 turned bottom-left, base colour
// texels against the image read directly with OpenImageIO, images from files, .glb buffer views
// and data: URIs alike, KHR_texture_transform as Facet's uv transform (the same texel), alpha
// modes as opacity, and the reports. The real assets are Debian's assimp-testmodels (skipped
// when absent); nobody here made them.
#include <gtest/gtest.h>

#include <OpenImageIO/imageio.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include <unistd.h>

#include "facet/render/gltf.h"
#include "facet/render/render.h"
#include "facet/render/scene.h"
#include "facet/render/scene_description.h"
#include "facet/render/texture.h"
#include "facet/testsupport/render_test_util.h"

namespace fr = facet::render;
using facet::Rgb;
using facet::Vec2;

namespace {

const std::string kAssimp = "/usr/share/assimp/models/glTF2/";
const std::string kDir = FACET_GLTF_TEST_DIR;

#define REQUIRE_ASSET(f) \
    if (!std::filesystem::exists(kAssimp + (f))) GTEST_SKIP() << "assimp-testmodels absent"

fr::Scene gltf_scene(const std::string& file, int size = 8) {
    const std::string json =
        R"({"format": "facet-scene", "version": 1,
            "camera": {"position": [2, -3, 2], "look_at": [0, 0, 0], "up": [0, 0, 1],
                       "fov": 40, "width": )" +
        std::to_string(size) + R"(, "height": )" + std::to_string(size) + R"(},
            "lights": [{"type": "environment", "radiance": 1}],
            "shapes": [{"type": "gltf", "file": ")" +
        file + R"("}], "render": {"max_depth": 2}})";
    return fr::build_scene(fr::parse_scene_description(json, "t.json", "/"), "t.json");
}

// The part whose material is the file's material `index`, and its textured material.
const fr::ShapeSurface& part_of(const fr::Scene& s, int index) {
    for (const fr::ShapeSurface& p : s.shapes()[0].parts) {
        const std::string tail = "#/materials/" + std::to_string(index);
        if (p.material_name.size() >= tail.size() &&
            p.material_name.compare(p.material_name.size() - tail.size(), tail.size(), tail) == 0)
            return p;
    }
    throw std::runtime_error("no part with material " + std::to_string(index));
}

const fr::Texture* slot(const fr::Scene& s, const fr::ShapeSurface& p, const std::string& name) {
    if (p.textured < 0) return nullptr;
    for (const auto& sl : s.textured_materials()[std::size_t(p.textured)].slots)
        if (sl.name == name) return sl.texture;
    return nullptr;
}

// 8-bit codes of an image as stored (row 0 at the top), read with OpenImageIO directly.
struct Codes {
    int w = 0, h = 0, c = 0, alpha = -1;
    std::vector<unsigned char> v;
    unsigned char at(int x, int y, int ch) const {
        return v[(std::size_t(y) * std::size_t(w) + std::size_t(x)) * std::size_t(c) +
                 std::size_t(ch)];
    }
};
Codes read_codes(const std::string& path) {
    auto in = OIIO::ImageInput::open(path);
    if (!in) throw std::runtime_error("cannot open " + path);
    Codes r;
    r.w = in->spec().width;
    r.h = in->spec().height;
    r.c = in->spec().nchannels;
    r.alpha = in->spec().alpha_channel;
    r.v.resize(std::size_t(r.w) * std::size_t(r.h) * std::size_t(r.c));
    in->read_image(0, 0, 0, r.c, OIIO::TypeDesc::UINT8, r.v.data());
    return r;
}

float srgb(unsigned char code) {
    const double e = double(code) / 255.0;
    return float(e <= 0.04045 ? e / 12.92 : std::pow((e + 0.055) / 1.055, 2.4));
}

// Facet's uv of the glTF uv (u, v): (u, 1 - v).
Vec2 facet_uv(double u, double v) {
    return Vec2(float(u), float(1.0 - v));
}

// normalTexture (ClearCoatTest's "BaseNorm_Base", via Debian): imported as the material's
// normal map, read linearly, with glTF's scale (default 1) as xy_scale; the file is the one the
// glTF names (RibsNormal.png). Exact: these are copied values.
TEST(GltfTextures, NormalTextureBecomesTheNormalMap) {
    REQUIRE_ASSET("ClearCoat-glTF/ClearCoatTest.gltf");
    const fr::GltfImport g = fr::import_gltf(kAssimp + "ClearCoat-glTF/ClearCoatTest.gltf");
    const fr::GltfMaterial* found = nullptr;
    for (const fr::GltfMaterial& m : g.materials)
        if (m.name == "BaseNorm_Base") found = &m;
    ASSERT_NE(found, nullptr);
    ASSERT_TRUE(found->desc.normal_map.has_value());
    EXPECT_EQ(found->desc.normal_map->texture.colorspace, "linear");
    EXPECT_EQ(found->desc.normal_map->xy_scale, 1.0);
    EXPECT_EQ(found->desc.normal_map->strength, 1.0);
    EXPECT_NE(found->desc.normal_map->texture.file.find("RibsNormal.png"), std::string::npos)
        << found->desc.normal_map->texture.file;
    // Materials without one have none.
    for (const fr::GltfMaterial& m : g.materials)
        if (m.name == "Partial_Coating") EXPECT_FALSE(m.desc.normal_map.has_value());
    // The whole asset builds (tangents computed where the file gives none) and renders finite.
    const fr::Scene s = gltf_scene(kAssimp + "ClearCoat-glTF/ClearCoatTest.gltf");
    EXPECT_GT(s.shapes().size(), 0u);
}

}  // namespace

// KHR_texture_transform: glTF samples T(o) R(r) S(s) uv_glTF (its uv origin top-left); Facet's
// transform of the converted uv must give the same point, F(R S F(uv) + o) with
// F(u, v) = (u, 1 - v), for random transforms and points. Tolerance 1e-5: float coordinates of
// magnitude < 10 after a few operations. Then the same texel of a 7 x 5 image with the closest
// filter (points within 1e-3 texel of an edge skipped: rounding may pick either side).
TEST(GltfTextures, KhrTextureTransformSamplesTheSameTexel) {
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> U(-1.0, 1.0);
    fr::TexelImage img;
    img.width = 7;
    img.height = 5;
    img.channels = 1;
    for (int i = 0; i < 35; ++i) img.texels.push_back(float(i));
    auto image = std::make_shared<fr::TexelImage>(img);
    int compared = 0;
    for (int t = 0; t < 200; ++t) {
        const Vec2 o(float(U(rng)), float(U(rng)));
        const Vec2 s(float(0.5 + 1.5 * (U(rng) + 1.0)), float(0.5 + 1.5 * (U(rng) + 1.0)));
        const double r = 3.0 * U(rng);
        fr::TextureDesc d;
        fr::apply_khr_texture_transform(d, o, r, s);
        const fr::Texture tex =
            fr::Texture::image(image, fr::TextureFilter::Closest, fr::TextureWrap::Repeat, 0, d);
        for (int k = 0; k < 10; ++k) {
            const double u = U(rng), v = U(rng);
            // glTF's matrix (the extension's specification: translation * rotation * scale).
            const double su = s.x * u, sv = s.y * v;
            const double tu = std::cos(r) * su - std::sin(r) * sv + o.x;
            const double tv = std::sin(r) * su + std::cos(r) * sv + o.y;
            glm::mat2 ta;
            Vec2 tb;
            fr::uv_transform(d, ta, tb);
            const Vec2 got = ta * facet_uv(u, v) + tb;
            EXPECT_NEAR(got.x, tu, 1e-5);
            EXPECT_NEAR(got.y, 1.0 - tv, 1e-5);
            // The texel glTF reads: x = floor(tu W), y = floor(tv H) (row 0 at the top), wrapped.
            const double fx = tu * 7.0, fy = tv * 5.0;
            if (std::fabs(fx - std::round(fx)) < 1e-3 || std::fabs(fy - std::round(fy)) < 1e-3)
                continue;
            const int x = fr::wrap_index(int(std::floor(fx)), 7, fr::TextureWrap::Repeat);
            const int y = fr::wrap_index(int(std::floor(fy)), 5, fr::TextureWrap::Repeat);
            EXPECT_EQ(tex.eval(facet_uv(u, v)).r, float(y * 7 + x));
            ++compared;
        }
    }
    EXPECT_GT(compared, 1500);
}

// BoxTextured (Khronos sample, via Debian): TEXCOORD_0 is imported as (u, 1 - v) of the accessor
// read here from the .bin directly, and the base colour texture at texel centres equals the
// PNG's sRGB-decoded codes read with OpenImageIO (baseColorFactor 1). Bilinear filtering at a
// texel centre weighs its neighbours by the float rounding of u W only (~W 2^-24 = 1.3e-5 texel
// for W = 211, times a texel difference <= 1): tolerance 5e-5.
TEST(GltfTextures, BoxTexturedTexelsAndUvsMatchTheFiles) {
    REQUIRE_ASSET("BoxTextured-glTF/BoxTextured.gltf");
    const std::string dir = kAssimp + "BoxTextured-glTF/";
    // UVs from the accessor bytes.
    const nlohmann::json j = nlohmann::json::parse(std::ifstream(dir + "BoxTextured.gltf"));
    const int acc = j["meshes"][0]["primitives"][0]["attributes"]["TEXCOORD_0"];
    const auto& a = j["accessors"][acc];
    const auto& bv = j["bufferViews"][int(a["bufferView"])];
    std::ifstream bin(dir + std::string(j["buffers"][0]["uri"]), std::ios::binary);
    const std::vector<char> bytes(std::istreambuf_iterator<char>(bin), {});
    const std::size_t off = std::size_t(bv.value("byteOffset", 0)) + a.value("byteOffset", 0);
    const std::size_t stride = bv.value("byteStride", 8);
    const fr::GltfImport g = fr::import_gltf(dir + "BoxTextured.gltf");
    ASSERT_EQ(g.parts.size(), 1u);
    const std::vector<Vec2>& uvs = g.parts[0].mesh.uvs;
    ASSERT_EQ(uvs.size(), std::size_t(a["count"]));
    for (std::size_t i = 0; i < uvs.size(); ++i) {
        float raw[2];
        std::memcpy(raw, bytes.data() + off + i * stride, sizeof raw);
        EXPECT_EQ(uvs[i].x, raw[0]);
        EXPECT_EQ(uvs[i].y, 1.f - raw[1]);
    }
    // Texels.
    const fr::Scene s = gltf_scene(dir + "BoxTextured.gltf");
    const fr::Texture* tex = slot(s, part_of(s, 0), "base_color");
    ASSERT_NE(tex, nullptr);
    const Codes c = read_codes(dir + "CesiumLogoFlat.png");
    ASSERT_EQ(tex->texel_image()->width, c.w);
    for (int y = 0; y < c.h; y += 7) {
        for (int x = 0; x < c.w; x += 5) {
            const Rgb v = tex->eval(facet_uv((x + 0.5) / c.w, (y + 0.5) / c.h));
            for (int ch = 0; ch < 3; ++ch)
                ASSERT_NEAR(v[ch], srgb(c.at(x, y, ch)), 5e-5) << x << "," << y << " " << ch;
        }
    }
}

// The same box with its image in a .glb buffer view and as a data: URI (decoded from memory,
// no temporary file) gives the texels of the separate PNG file, exactly; the .glb and the
// data: URI variants render the same image. (Debian's separate-file variant has another
// sampler, mirror/clamp instead of repeat, and UVs up to 6: its render differs.)
TEST(GltfTextures, GlbAndDataUriImagesEqualTheFile) {
    REQUIRE_ASSET("BoxTextured-glTF-Binary/BoxTextured.glb");
    const fr::Scene file = gltf_scene(kAssimp + "BoxTextured-glTF/BoxTextured.gltf", 16);
    const fr::Scene glb = gltf_scene(kAssimp + "BoxTextured-glTF-Binary/BoxTextured.glb", 16);
    const fr::Scene uri = gltf_scene(kAssimp + "BoxTextured-glTF-Embedded/BoxTextured.gltf", 16);
    const fr::TexelImage* a = slot(file, part_of(file, 0), "base_color")->texel_image();
    for (const fr::Scene* other : {&glb, &uri}) {
        const fr::TexelImage* b = slot(*other, part_of(*other, 0), "base_color")->texel_image();
        EXPECT_NE(b->path.find("#/images/0.png"), std::string::npos) << b->path;
        EXPECT_EQ(b->width, a->width);
        EXPECT_EQ(b->height, a->height);
        EXPECT_TRUE(b->texels == a->texels);
    }
    // One sample per pixel: every textured hit builds its composite (with its albedo table).
    const fr::RenderOptions o = fr::testing::test_options("path", 1, 4);
    const fr::Image ib = fr::render(glb, o), ic = fr::render(uri, o);
    EXPECT_TRUE(ib.pixels() == ic.pixels());
    const fr::Image& ia = ib;
    // The texture shows: the box is not one colour.
    float lo = 1e9f, hi = -1e9f;
    for (const Rgb& p : ia.pixels()) {
        if (p.g == 1.f) continue;  // background
        lo = std::min(lo, p.g);
        hi = std::max(hi, p.g);
    }
    EXPECT_GT(hi - lo, 0.1f);
}

// TextureTransformTest (Khronos sample, via Debian): for each of its six transformed materials,
// Facet's texture at the converted uv equals the same image without a transform read at the
// point the extension's formula gives. Tolerance 2e-3: bilinear values of points that agree to
// ~1e-6 in uv (1e-3 texel at 1024 texels) on an 8-bit image.
TEST(GltfTextures, TextureTransformAssetSamplesTheTransformedPoint) {
    REQUIRE_ASSET("textureTransform/TextureTransformTest.gltf");
    const std::string path = kAssimp + "textureTransform/TextureTransformTest.gltf";
    const nlohmann::json j = nlohmann::json::parse(std::ifstream(path));
    const fr::Scene s = gltf_scene(path);
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> U(0.0, 1.0);
    for (int m = 0; m < 6; ++m) {
        const auto& x = j["materials"][m]["pbrMetallicRoughness"]["baseColorTexture"]["extensions"]
                         ["KHR_texture_transform"];
        const double ou = x.contains("offset") ? double(x["offset"][0]) : 0.0;
        const double ov = x.contains("offset") ? double(x["offset"][1]) : 0.0;
        const double r = x.value("rotation", 0.0);
        const double su = x.contains("scale") ? double(x["scale"][0]) : 1.0;
        const double sv = x.contains("scale") ? double(x["scale"][1]) : 1.0;
        const fr::Texture* tex = slot(s, part_of(s, m), "base_color");
        ASSERT_NE(tex, nullptr) << m;
        const fr::Texture plain = fr::Texture::image(
            std::make_shared<fr::TexelImage>(*tex->texel_image()), fr::TextureFilter::Linear,
            fr::TextureWrap::Clamp, fr::Texture::kAllChannels, fr::TextureDesc{});
        for (int k = 0; k < 50; ++k) {
            const double u = U(rng), v = U(rng);
            const double tu = std::cos(r) * su * u - std::sin(r) * sv * v + ou;
            const double tv = std::sin(r) * su * u + std::cos(r) * sv * v + ov;
            const Rgb got = tex->eval(facet_uv(u, v)), want = plain.eval(facet_uv(tu, tv));
            for (int c = 0; c < 3; ++c) EXPECT_NEAR(got[c], want[c], 2e-3) << m << " " << k;
        }
    }
    // Its sampler (clamp, linear) is converted.
    EXPECT_EQ(fr::import_gltf(path).materials[0].desc.textures.at("base_color").wrap, "clamp");
}

// alphaMode BLEND (ClearCoatTest's "Partial_Coating", via Debian): the opacity is the base colour
// texture's alpha (linear, times baseColorFactor's 1) at every texel centre. Exact to 1e-6.
TEST(GltfTextures, BlendAlphaIsTheTexturesAlpha) {
    REQUIRE_ASSET("ClearCoat-glTF/ClearCoatTest.gltf");
    const fr::Scene s = gltf_scene(kAssimp + "ClearCoat-glTF/ClearCoatTest.gltf");
    const fr::ShapeSurface& p = part_of(s, 5);
    const Codes c = read_codes(kAssimp + "ClearCoat-glTF/PartialCoating_Alpha.png");
    ASSERT_GE(c.alpha, 0) << "the asset's image has an alpha channel";
    ASSERT_NE(p.opacity.texture, nullptr);
    EXPECT_EQ(p.opacity.cutoff, 0.f);
    int partial = 0;
    for (int y = 0; y < c.h; y += 3) {
        for (int x = 0; x < c.w; x += 3) {
            const float a = p.opacity.alpha(facet_uv((x + 0.5) / c.w, (y + 0.5) / c.h));
            ASSERT_NEAR(a, float(c.at(x, y, c.alpha)) / 255.f, 1e-6) << x << "," << y;
            partial += a > 0.f && a < 1.f;
        }
    }
    // Opaque materials stay on the fast path.
    EXPECT_FALSE(part_of(s, 0).opacity.active());
}

// An emissive texture is a light source for the scene check: BoxTextured (Debian's
// assimp-testmodels) with its base colour texture as emissiveTexture (factor 1) and no
// "lights" key builds with the box as its one light, and camera rays see the texture's
// emission: the middle 4 x 4 pixels, all on the box, are above 0 (the logo image has no black
// texel; nothing else lights the scene).
TEST(GltfTextures, AnEmissiveTextureAloneIsALightSource) {
    REQUIRE_ASSET("BoxTextured-glTF/BoxTextured.gltf");
    const std::string dir =
        (std::filesystem::temp_directory_path() / ("facet_gltf_emit_" + std::to_string(getpid())))
            .string();
    std::filesystem::create_directories(dir);
    for (const char* f : {"BoxTextured0.bin", "CesiumLogoFlat.png"})
        std::filesystem::copy_file(kAssimp + "BoxTextured-glTF/" + f, dir + "/" + f,
                                   std::filesystem::copy_options::overwrite_existing);
    nlohmann::json j =
        nlohmann::json::parse(std::ifstream(kAssimp + "BoxTextured-glTF/BoxTextured.gltf"));
    nlohmann::json& m = j["materials"][0];
    m["emissiveTexture"] = m["pbrMetallicRoughness"]["baseColorTexture"];
    m["emissiveFactor"] = {1.0, 1.0, 1.0};
    std::ofstream(dir + "/emissive.gltf") << j.dump();
    const std::string json =
        R"({"format": "facet-scene", "version": 1,
            "camera": {"position": [2, -3, 2], "look_at": [0, 0, 0], "up": [0, 0, 1],
                       "fov": 20, "width": 8, "height": 8},
            "shapes": [{"type": "gltf", "file": "emissive.gltf"}]})";
    const fr::Scene s = fr::load_scene_from_string(json, "t.json", dir);
    ASSERT_EQ(s.lights().size(), 1u);
    ASSERT_EQ(s.shapes()[0].parts.size(), 1u);
    EXPECT_EQ(s.shapes()[0].parts[0].light, 0);
    const fr::Image img = fr::render(s, fr::testing::test_options("direct", 4, 1, 1));
    for (int y = 2; y < 6; ++y)
        for (int x = 2; x < 6; ++x) {
            const Rgb px = img.at(x, y);
            EXPECT_GT(px.r + px.g + px.b, 0.f) << x << ", " << y;
        }
}

// alphaMode MASK on a constant base colour alpha: 0.3 below the cutoff 0.5 is a hole (opacity 0,
// camera rays see the environment), 0.7 above it is opaque (not even a cut-out); BLEND keeps
// 0.3. The box.gltf of make_gltf_tests.py, edited here. Also: the occlusion texture is reported
// as not used.
TEST(GltfTextures, MaskCutsAtTheCutoffAndOcclusionIsReported) {
    const std::string dir =
        (std::filesystem::temp_directory_path() / ("facet_gltf_tex_" + std::to_string(getpid())))
            .string();
    std::filesystem::create_directories(dir);
    nlohmann::json j = nlohmann::json::parse(std::ifstream(kDir + "/box.gltf"));
    j["materials"][0].erase("emissiveFactor");
    auto variant = [&](const std::string& mode, double alpha) {
        nlohmann::json v = j;
        v["materials"][0]["alphaMode"] = mode;
        v["materials"][0]["alphaCutoff"] = 0.5;
        v["materials"][0]["pbrMetallicRoughness"]["baseColorFactor"][3] = alpha;
        v["materials"][0]["occlusionTexture"] = {{"index", 0}};
        const std::string f = dir + "/" + mode + std::to_string(int(alpha * 10)) + ".gltf";
        std::ofstream(f) << v.dump();
        return f;
    };
    const fr::Scene hole = gltf_scene(variant("MASK", 0.3));
    EXPECT_TRUE(hole.shapes()[0].parts[0].opacity.active());
    EXPECT_EQ(hole.shapes()[0].parts[0].opacity.value, 0.f);
    const fr::Image img = fr::render(hole, fr::testing::test_options("path", 1, 1));
    for (const Rgb& px : img.pixels()) EXPECT_EQ(px, Rgb(1.f));
    const fr::Scene solid = gltf_scene(variant("MASK", 0.7));
    EXPECT_FALSE(solid.shapes()[0].parts[0].opacity.active());
    const fr::Scene blend = gltf_scene(variant("BLEND", 0.3));
    EXPECT_FLOAT_EQ(blend.shapes()[0].parts[0].opacity.value, 0.3f);
    std::string reports;
    for (const std::string& w : hole.warnings()) reports += w + "\n";
    EXPECT_NE(reports.find("#/materials/0/occlusionTexture: texture 0 (ambient occlusion"),
              std::string::npos)
        << reports;
    std::filesystem::remove_all(dir);
}

// A colour "scale" multiplies a colour texture per channel, and survives the JSON round trip.
TEST(GltfTextures, ColourScaleMultipliesPerChannelAndRoundTrips) {
    fr::TextureDesc d;
    d.kind = "checker";
    d.colors = {Rgb(0.5f), Rgb(1.f)};
    d.color_scale = Rgb(1.f, 0.5f, 0.25f);
    const fr::Texture t = fr::Texture::checker(d);
    EXPECT_EQ(t.eval(Vec2(0.25f, 0.25f)), Rgb(0.5f, 0.25f, 0.125f));
    const std::string json = R"({"format": "facet-scene", "version": 1,
        "camera": {"position": [0, 0, 2], "look_at": [0, 0, 0], "fov": 40, "width": 4,
                   "height": 4},
        "lights": [{"type": "environment", "radiance": 1}],
        "shapes": [{"type": "quad", "vertices": [[-1, -1, 0], [1, -1, 0], [1, 1, 0], [-1, 1, 0]],
                    "material": {"model": "lambert", "reflectance":
                        {"checker": {"colors": [0.5, 1]}, "scale": [1, 0.5, 0.25]}}}]})";
    const fr::SceneDescription a = fr::parse_scene_description(json, "c.json");
    EXPECT_EQ(a.shapes[0].material->textures.at("reflectance").color_scale, Rgb(1.f, 0.5f, 0.25f));
    const fr::SceneDescription b = fr::parse_scene_description(fr::write_scene_json(a), "c2.json");
    EXPECT_TRUE(a == b);
    // A number parameter refuses a non-grey scale, naming it.
    std::string e;
    try {
        fr::load_scene_from_string(
            R"({"format": "facet-scene", "version": 1,
                "camera": {"position": [0, 0, 2], "look_at": [0, 0, 0], "fov": 40, "width": 4,
                   "height": 4},
                "lights": [{"type": "environment", "radiance": 1}],
                "shapes": [{"type": "sphere", "center": [0, 0, 0], "radius": 1,
                            "material": {"model": "lambert", "reflectance": 0.5,
                            "opacity": {"checker": {"colors": [0, 1]}, "scale": [1, 0.5, 1]}}}]})",
            "n.json");
    } catch (const fr::SceneError& x) {
        e = x.what();
    }
    EXPECT_NE(e.find("/shapes/0/material/opacity/scale"), std::string::npos) << e;
}
