// Textures as parameter values and UVs on hits (texture.h, scene.h): rendered texels, the
// filters, wrap modes and UV transform at analytic points, each shape's UV convention, and the
// errors for bad input. Test images are written with OpenImageIO directly, so the expected
// texels are known independently of the reader.
#include <gtest/gtest.h>

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include <unistd.h>

#include "facet/render/pov_export.h"
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
    return fr::testing::test_temp_dir("facet_textures");
}

using fr::testing::write_test_image;

// IEC 61966-2-1 decoding in double, rounded once (the reader's documented exact decoding).
float srgb(std::uint8_t code) {
    const double e = double(code) / 255.0;
    return float(e <= 0.04045 ? e / 12.92 : std::pow((e + 0.055) / 1.055, 2.4));
}

fr::Scene scene_in(const std::string& dir, const std::string& body) {
    return fr::testing::scene_in_dir(dir, body, "tex.json");
}

std::string error_of(const std::string& dir, const std::string& body) {
    return fr::testing::scene_error(dir, body, "tex.json");
}

// A 4 x 3 camera whose pixel centres hit the texel centres of the 4 x 3 quad [-2, 2] x
// [-1.5, 1.5] at z = 0 (facing +z): from (0, 0, 1.5) the full vertical fov is 90 degrees, so
// the film's edges meet the quad's (tan 45 = 1.5 / 1.5; horizontally (4/3) * 1.5 = 2), and a
// plane parallel to the film maps film positions linearly: pixel (x, y)'s centre lands on
// (x - 1.5, 1 - y) = the centre of texel (x, y) (row 0 at the top, as v grows upward).
const char* const kTexelCamera =
    R"("camera": {"position": [0, 0, 1.5], "look_at": [0, 0, 0], "up": [0, 1, 0], "fov": 90,
                  "width": 4, "height": 3},)";
const char* const kTexelQuadVertices =
    R"([[-2, -1.5, 0], [2, -1.5, 0], [2, 1.5, 0], [-2, 1.5, 0]])";

fr::Image render_once(const fr::Scene& scene, const std::string& integrator) {
    fr::RenderOptions o = fr::testing::test_options(integrator, 1, 3, 1);
    return fr::render(scene, o);
}

// 4 x 3 RGB 8-bit texels, all codes different.
std::vector<std::uint8_t> test_codes() {
    std::vector<std::uint8_t> c(4 * 3 * 3);
    for (std::size_t i = 0; i < c.size(); ++i) c[i] = std::uint8_t(20 + 6 * i);
    return c;
}

fr::TexelImage one_row(std::vector<float> values) {
    fr::TexelImage img;
    img.width = int(values.size());
    img.height = 1;
    img.channels = 1;
    img.texels = std::move(values);
    return img;
}

fr::Texture image_texture(const fr::TexelImage& img, fr::TextureFilter f, fr::TextureWrap w,
                          const fr::TextureDesc& d = {}) {
    return fr::Texture::image(std::make_shared<fr::TexelImage>(img), f, w,
                              fr::Texture::kAllChannels, d);
}

}  // namespace

// A Lambertian quad textured with reflectance rho(x, y) under a constant environment of
// radiance 1, max_depth 1: L = rho E / pi with E = pi, so each pixel is its texel's linear
// reflectance. The path integrator's cosine-sampled estimate f cos / pdf * 1 = rho holds for
// every sample, so the only error is float rounding: tolerance 2e-7 relative (a few ulps). A
// wrong row order, sRGB decoding or texel offset changes values by > 1e-2.
TEST(Textures, LambertQuadRendersEachTexelsLinearReflectance) {
    const std::string dir = temp_dir();
    const std::vector<std::uint8_t> codes = test_codes();
    write_test_image(dir + "/rho.png", 4, 3, 3, codes, OIIO::TypeDesc::UINT8);
    const fr::Scene scene = scene_in(dir, std::string(kTexelCamera) + R"(
        "shapes": [{"type": "quad", "vertices": )" +
                                              kTexelQuadVertices + R"(,
                    "material": {"model": "lambert",
                                 "reflectance": {"texture": "rho.png", "filter": "closest"}}}],
        "lights": [{"type": "environment", "radiance": 1}],
        "render": {"max_depth": 1})");
    const fr::Image img = render_once(scene, "path");
    for (int y = 0; y < 3; ++y)
        for (int x = 0; x < 4; ++x)
            for (int c = 0; c < 3; ++c) {
                const float want = srgb(codes[std::size_t((y * 4 + x) * 3 + c)]);
                EXPECT_NEAR(img.at(x, y)[c], want, 2e-7f * want) << x << "," << y << " c" << c;
            }
}

// An emission texture seen directly: each pixel is its texel (float EXR, linear by default).
// The camera ray adds the emitted radiance with weight 1, so the match is exact.
TEST(Textures, EmissionTextureSeenDirectlyEqualsItsTexels) {
    const std::string dir = temp_dir();
    std::vector<float> le(4 * 3 * 3);
    for (std::size_t i = 0; i < le.size(); ++i) le[i] = 0.25f + 0.5f * float(i);
    write_test_image(dir + "/le.exr", 4, 3, 3, le, OIIO::TypeDesc::FLOAT);
    const fr::Scene scene = scene_in(dir, std::string(kTexelCamera) + R"(
        "shapes": [{"type": "quad", "vertices": )" +
                                              kTexelQuadVertices + R"(,
                    "emission": {"texture": "le.exr", "filter": "closest"}}],
        "lights": [])");
    ASSERT_EQ(scene.lights().size(), 1u);
    EXPECT_TRUE(scene.lights()[0].textured_emission());
    for (const char* integrator : {"path", "direct"}) {
        const fr::Image img = render_once(scene, integrator);
        for (int y = 0; y < 3; ++y)
            for (int x = 0; x < 4; ++x)
                for (int c = 0; c < 3; ++c)
                    EXPECT_EQ(img.at(x, y)[c], le[std::size_t((y * 4 + x) * 3 + c)])
                        << integrator << " " << x << "," << y << " c" << c;
    }
}

// Textured emission is found by BSDF sampling alone (not light-sampled): a Lambertian floor
// under a textured emitter of uniform radiance matches the same floor under a constant emitter
// (light-sampled with MIS), within 4 standard errors of the difference of two independent means.
TEST(Textures, TexturedEmitterLightsTheSceneUnbiased) {
    const std::string dir = temp_dir();
    write_test_image(dir + "/two.exr", 1, 1, 3, std::vector<float>{2.f, 2.f, 2.f},
                     OIIO::TypeDesc::FLOAT);
    auto scene_with = [&](const std::string& emission) {
        return scene_in(dir, R"("camera": {"position": [0, 2, 3], "look_at": [0, 0, 0],
                                          "fov": 40, "width": 16, "height": 16},
            "materials": {"white": {"model": "lambert", "reflectance": 0.7}},
            "shapes": [{"type": "plane", "point": [0, 0, 0], "normal": [0, 1, 0], "material": "white"},
                       {"type": "quad", "emission": )" +
                                 emission + R"(,
                        "vertices": [[-1, 0.6, -1], [1, 0.6, -1], [1, 0.6, 1], [-1, 0.6, 1]]}],
            "render": {"max_depth": 2})");
    };
    // FACET_STRESS_SCALE scales the sample count (as the other Monte Carlo tests do).
    const char* scale_env = std::getenv("FACET_STRESS_SCALE");
    const double scale = scale_env ? std::max(0.05, std::atof(scale_env)) : 1.0;
    const int spp = std::max(16, int(64 * scale));
    auto mean = [&](const fr::Scene& s, double& se) {
        const fr::Image img = fr::render(s, fr::testing::test_options("path", spp, 11, 2));
        double sum = 0, sum2 = 0;
        const double n = double(img.pixels().size());
        for (const Rgb& p : img.pixels()) sum += p.g, sum2 += double(p.g) * p.g;
        const double m = sum / n;
        se = std::sqrt(std::max(0.0, sum2 / n - m * m) / (n - 1));
        return m;
    };
    double se_t = 0, se_c = 0;
    const double mt = mean(scene_with(R"({"texture": "two.exr"})"), se_t);
    const double mc = mean(scene_with("2"), se_c);
    EXPECT_GT(mc, 0.1);
    EXPECT_NEAR(mt, mc, 4 * std::sqrt(se_t * se_t + se_c * se_c));
}

// Checker: colors[(floor(n u') + floor(n v')) mod 2], colors[0] at the origin's cell.
TEST(Textures, CheckerValuesAtAnalyticPoints) {
    fr::TextureDesc d;
    d.kind = "checker";
    d.colors = {Rgb(0.1f, 0.2f, 0.3f), Rgb(0.9f, 0.8f, 0.7f)};
    d.checker_scale = 2.0;
    const fr::Texture t = fr::Texture::checker(d);
    EXPECT_EQ(t.eval({0.1f, 0.1f}), d.colors[0]);    // cell (0, 0)
    EXPECT_EQ(t.eval({0.6f, 0.1f}), d.colors[1]);    // cell (1, 0)
    EXPECT_EQ(t.eval({0.6f, 0.6f}), d.colors[0]);    // cell (1, 1)
    EXPECT_EQ(t.eval({-0.1f, 0.1f}), d.colors[1]);   // cell (-1, 0)
    EXPECT_EQ(t.eval({-0.1f, -0.3f}), d.colors[0]);  // cell (-1, -1)
    EXPECT_EQ(t.min_value(), d.colors[0]);
    EXPECT_EQ(t.max_value(), d.colors[1]);
}

// Wrap modes on texel indices of a 4-texel row (closest filter): u = 1.1 -> x = 4.4 (index 4),
// u = -0.1 -> x = -0.4 (index -1).
TEST(Textures, WrapModesAtAnalyticPoints) {
    const fr::TexelImage img = one_row({10.f, 11.f, 12.f, 13.f});
    using W = fr::TextureWrap;
    auto at = [&](W w, float u) {
        return image_texture(img, fr::TextureFilter::Closest, w).eval({u, 0.5f}).r;
    };
    EXPECT_EQ(at(W::Repeat, 1.1f), 10.f);
    EXPECT_EQ(at(W::Clamp, 1.1f), 13.f);
    EXPECT_EQ(at(W::Mirror, 1.1f), 13.f);  // index 4 reflects to 3
    EXPECT_EQ(at(W::Repeat, -0.1f), 13.f);
    EXPECT_EQ(at(W::Clamp, -0.1f), 10.f);
    EXPECT_EQ(at(W::Mirror, -0.1f), 10.f);  // index -1 reflects to 0
    EXPECT_EQ(at(W::Mirror, 1.6f), 11.f);   // x = 6.4: index 6 reflects to 1
    EXPECT_EQ(fr::wrap_index(-5, 4, W::Repeat), 3);
    EXPECT_EQ(fr::wrap_index(9, 4, W::Mirror), 1);  // 9 mod 8 = 1
}

// uv' = R(rotation) (uv_scale * uv) + uv_offset, evaluated on the 4-texel row.
TEST(Textures, UvTransformAtAnalyticPoints) {
    const fr::TexelImage img = one_row({10.f, 11.f, 12.f, 13.f});
    auto at = [&](const fr::TextureDesc& d, Vec2 uv) {
        return image_texture(img, fr::TextureFilter::Closest, fr::TextureWrap::Repeat, d)
            .eval(uv)
            .r;
    };
    fr::TextureDesc scale;
    scale.uv_scale = {2.f, 1.f};
    EXPECT_EQ(at(scale, {0.3f, 0.5f}), 12.f);  // u' = 0.6 -> x = 2.4
    fr::TextureDesc offset;
    offset.uv_offset = {0.25f, 0.f};
    EXPECT_EQ(at(offset, {0.1f, 0.5f}), 11.f);  // u' = 0.35 -> x = 1.4
    fr::TextureDesc rot;
    rot.uv_rotation = 90.0;  // (u, v) -> (-v, u)
    glm::mat2 ra;
    Vec2 rb;
    fr::uv_transform(rot, ra, rb);
    const Vec2 t = ra * Vec2(0.2f, 0.6f) + rb;
    EXPECT_NEAR(t.x, -0.6f, 1e-6f);
    EXPECT_NEAR(t.y, 0.2f, 1e-6f);
    EXPECT_EQ(at(rot, {0.2f, 0.6f}), 11.f);  // u' = -0.6 -> x = -2.4: index -3 repeats to 1
}

// Bilinear filtering between the centres of two texels a, b (u = 0.25 and 0.75): exactly a at
// a's centre, the mean half way, 3/4 a + 1/4 b a quarter of the way (tolerance 1 ulp of the
// values: the weights are exact binary fractions).
TEST(Textures, BilinearBetweenTwoTexels) {
    const float a = 2.f, b = 6.f;
    const fr::TexelImage img = one_row({a, b});
    const fr::Texture t = image_texture(img, fr::TextureFilter::Linear, fr::TextureWrap::Clamp);
    EXPECT_EQ(t.eval({0.25f, 0.5f}).r, a);
    EXPECT_EQ(t.eval({0.75f, 0.5f}).r, b);
    EXPECT_EQ(t.eval({0.5f, 0.5f}).r, 0.5f * (a + b));
    EXPECT_EQ(t.eval({0.375f, 0.5f}).r, 0.75f * a + 0.25f * b);
    EXPECT_EQ(t.eval({0.1f, 0.5f}).r, a);  // clamp: beyond a's centre only a
    // Repeat blends across the edge: u = 0 is half way between b (x = -1) and a (x = 0).
    const fr::Texture r = image_texture(img, fr::TextureFilter::Linear, fr::TextureWrap::Repeat);
    EXPECT_EQ(r.eval({0.f, 0.5f}).r, 0.5f * (a + b));
}

// Textures sharing one image's lookup at a point (TexturePoint::memo, as a textured
// material's slots share it): every channel choice, scale, filter and UV transform gives the
// bits of its own lookup, and a texture with another transform or image does not take the
// shared texels. Exact equality: the shared texels are the same computation.
TEST(Textures, SharedImageLookupsGiveEachTexturesOwnBits) {
    fr::TexelImage img;
    img.width = 5, img.height = 3, img.channels = 4, img.alpha_channel = 3;
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> u01(0.f, 1.f);
    for (int i = 0; i < 5 * 3 * 4; ++i) img.texels.push_back(u01(rng));
    auto shared = std::make_shared<fr::TexelImage>(img);
    auto mips = std::make_shared<const std::vector<fr::TexelImage>>(fr::build_mip_levels(img));
    auto other = std::make_shared<fr::TexelImage>(img);
    for (float& t : other->texels) t = 1.f - t;
    fr::TextureDesc plain, scaled, moved;
    scaled.scale = 0.7;
    moved.uv_offset = {0.3f, 0.1f};
    std::vector<fr::Texture> ts;
    for (int ch : {fr::Texture::kAllChannels, 0, 1, 2, 3, int(fr::Texture::kLuminance)}) {
        for (auto f :
             {fr::TextureFilter::Linear, fr::TextureFilter::Mipmap, fr::TextureFilter::Closest}) {
            ts.push_back(fr::Texture::image(shared, f, fr::TextureWrap::Repeat, ch, plain, mips));
            ts.push_back(fr::Texture::image(shared, f, fr::TextureWrap::Mirror, ch, scaled, mips));
            ts.push_back(fr::Texture::image(shared, f, fr::TextureWrap::Repeat, ch, moved, mips));
            ts.push_back(fr::Texture::image(other, f, fr::TextureWrap::Repeat, ch, plain, mips));
        }
    }
    for (int i = 0; i < 200; ++i) {
        const Vec2 uv(3.f * u01(rng) - 1.f, 3.f * u01(rng) - 1.f);
        const fr::UvFootprint fp{Vec2(u01(rng), 0.f), Vec2(0.f, 2.f * u01(rng))};
        fr::ImageLookupMemo memo;
        fr::TexturePoint p{uv, &fp};
        p.memo = &memo;
        std::shuffle(ts.begin(), ts.end(), rng);
        for (const fr::Texture& t : ts) ASSERT_EQ(t.eval(p), t.eval(uv, fp)) << i;
    }
}

namespace {

// The uv of the closest hit along a ray, in a scene whose shape has a checker material (so
// that hits compute UVs).
Vec2 uv_at(const std::string& shape, const Vec3& o, const Vec3& d) {
    return fr::testing::checker_scene_hit(shape, o, d).uv;
}

void expect_uv(const Vec2& got, float u, float v, const char* what) {
    // 1e-5: the hit point carries float rounding of the unit-sized geometry (~1e-7), the
    // conversions to uv a few more ulps; a wrong axis or origin is off by > 0.1.
    EXPECT_NEAR(got.x, u, 1e-5f) << what;
    EXPECT_NEAR(got.y, v, 1e-5f) << what;
}

}  // namespace

TEST(TextureUvs, EachShapeFollowsItsConvention) {
    const Vec3 down(0, 0, -1);
    // quad: p0 (0,0), p1 (1,0), p2 (1,1), p3 (0,1); a skewed quad, hit at p0 + 0.25 e1 + 0.5 e2.
    expect_uv(uv_at(R"({"type": "quad", "material": "c",
                        "vertices": [[0, 0, 0], [4, 0, 0], [4, 2, 0], [0, 2, 0]]})",
                    Vec3(1, 1, 5), down),
              0.25f, 0.5f, "quad");
    // box [-1, 1]^3: +z face, u along +x, v along +y.
    const char* box = R"({"type": "box", "material": "c", "min": [-1, -1, -1], "max": [1, 1, 1]})";
    expect_uv(uv_at(box, Vec3(0.5f, -0.5f, 5), down), 0.75f, 0.25f, "box +z");
    // -z face (seen from -z): u along -x, v along +y.
    expect_uv(uv_at(box, Vec3(0.5f, -0.5f, -5), Vec3(0, 0, 1)), 0.25f, 0.25f, "box -z");
    // +x face: u along -z, v along +y.
    expect_uv(uv_at(box, Vec3(5, 0.5f, 0.5f), Vec3(-1, 0, 0)), 0.25f, 0.75f, "box +x");
    // +y face (top): u along +x, v along -z.
    expect_uv(uv_at(box, Vec3(0.5f, 5, 0.5f), Vec3(0, -1, 0)), 0.75f, 0.25f, "box +y");
    // -y face (bottom): u along +x, v along +z.
    expect_uv(uv_at(box, Vec3(0.5f, -5, 0.5f), Vec3(0, 1, 0)), 0.75f, 0.75f, "box -y");
    // -x face: u along +z, v along +y.
    expect_uv(uv_at(box, Vec3(-5, 0.5f, 0.5f), Vec3(1, 0, 0)), 0.75f, 0.75f, "box -x");
    // grid over [-1, 1]^2: ((x + 1) / 2, (y + 1) / 2).
    expect_uv(
        uv_at(R"({"type": "grid", "material": "c", "nx": 3, "ny": 2})", Vec3(0.5f, -0.2f, 5), down),
        0.75f, 0.4f, "grid");
    // sphere at (1, 2, 3), radius 2: hit at longitude 90 degrees on the equator -> (0.25, 0.5);
    // at the top of the +z pole -> v = 1; straight below -> v = 0.
    const char* sphere = R"({"type": "sphere", "material": "c", "center": [1, 2, 3], "radius": 2})";
    expect_uv(uv_at(sphere, Vec3(1, 12, 3), Vec3(0, -1, 0)), 0.25f, 0.5f, "sphere +y");
    expect_uv(uv_at(sphere, Vec3(-9, 2, 3), Vec3(1, 0, 0)), 0.5f, 0.5f, "sphere -x");
    EXPECT_NEAR(uv_at(sphere, Vec3(1, 2, 13), down).y, 1.f, 1e-5f);
    EXPECT_NEAR(uv_at(sphere, Vec3(1, 2, -7), Vec3(0, 0, 1)).y, 0.f, 1e-5f);
    // icosphere: the same convention from the hit point's direction (the ray through the
    // centre at longitude 45 degrees, latitude 0).
    const Vec2 ico = uv_at(
        R"({"type": "icosphere", "material": "c", "center": [0, 0, 0], "radius": 1,
            "subdivisions": 2})",
        Vec3(5, 5, 0), Vec3(-1, -1, 0));
    expect_uv(ico, 0.125f, 0.5f, "icosphere");
    // disc (normal +z: local x = +x, y = +y): its bounding square [-r, r]^2 onto [0, 1]^2.
    expect_uv(uv_at(R"({"type": "disc", "material": "c", "center": [0, 0, 0], "radius": 2,
                        "normal": [0, 0, 1]})",
                    Vec3(1, -1, 5), down),
              0.75f, 0.25f, "disc");
    // plane (normal +z: local x = +x, y = +y) through (1, 1, 0): scene units from the point.
    expect_uv(uv_at(R"({"type": "plane", "material": "c", "point": [1, 1, 0],
                        "normal": [0, 0, 1]})",
                    Vec3(3.5f, -2, 5), down),
              2.5f, -3.f, "plane");
    // mesh with uvs: barycentric interpolation.
    expect_uv(uv_at(R"({"type": "mesh", "material": "c", "positions": [0, 0, 0, 2, 0, 0, 0, 2, 0],
                        "indices": [0, 1, 2], "uvs": [0.1, 0.2, 0.9, 0.2, 0.1, 0.6]})",
                    Vec3(0.5f, 0.5f, 5), down),
              0.1f + 0.8f * 0.25f, 0.2f + 0.4f * 0.25f, "mesh");
}

// An untextured scene never computes UVs and its hits say so (the fast path).
TEST(TextureUvs, UntexturedHitsAreNotTextured) {
    const fr::Scene scene = fr::testing::scene_from(
        R"("camera": {"position": [0, 0, 10], "look_at": [0, 0, 0], "fov": 40, "width": 4, "height": 4},
           "materials": {"w": {"model": "lambert", "reflectance": 0.5}},
           "shapes": [{"type": "sphere", "material": "w", "center": [0, 0, 0], "radius": 1}],
           "lights": [{"type": "environment", "radiance": 1}])");
    fr::SurfaceHit hit;
    hit.uv = Vec2(-7.f);
    ASSERT_TRUE(scene.intersect({Vec3(0, 0, 5), Vec3(0, 0, -1), facet::kInfinity}, hit));
    EXPECT_EQ(hit.textured, -1);
    EXPECT_EQ(hit.uv, Vec2(-7.f));  // not computed
}

TEST(Textures, OneImageUsedTwiceIsLoadedOnce) {
    const std::string dir = temp_dir();
    write_test_image(dir + "/g.png", 2, 2, 1, std::vector<std::uint8_t>{10, 20, 30, 40},
                     OIIO::TypeDesc::UINT8);
    fr::SceneDescription d = fr::parse_scene_description(
        R"({"format": "facet-scene", "version": 1,
            "camera": {"position": [0, 0, 10], "look_at": [0, 0, 0], "fov": 40, "width": 4, "height": 4},
            "materials": {"a": {"model": "lambert", "reflectance": {"texture": "g.png"}},
                          "b": {"model": "composite", "diffuse_reflectance": {"texture": "g.png"},
                                "alpha": {"texture": "g.png", "colorspace": "linear"}}},
            "shapes": [{"type": "sphere", "material": "a", "center": [0, 0, 0], "radius": 1}, {"type": "sphere", "material": "b", "radius": 1,
                        "center": [3, 0, 0]}],
            "lights": [{"type": "environment", "radiance": 1}]})",
        "tex.json", dir);
    // Round trip: the writer gives back the same description.
    EXPECT_EQ(fr::parse_scene_description(fr::write_scene_json(d), "again.json", dir), d);
    const fr::Scene s = fr::build_scene(d, "tex.json");
    // Three texture values over two decodings (sRGB for the colours, linear for alpha): the
    // two sRGB uses share one decoded image.
    ASSERT_EQ(s.shapes()[0].textured, 0);
    ASSERT_EQ(s.shapes()[1].textured, 1);
    const auto tm = s.textured_materials();
    ASSERT_EQ(tm[0].slots.size(), 1u);
    ASSERT_EQ(tm[1].slots.size(), 2u);
    const fr::TexelImage* a = tm[0].slots[0].texture->texel_image();
    const fr::TexelImage* alpha = tm[1].slots[0].texture->texel_image();  // "alpha" sorts first
    const fr::TexelImage* diffuse = tm[1].slots[1].texture->texel_image();
    EXPECT_EQ(tm[1].slots[1].name, "diffuse_reflectance");
    EXPECT_EQ(a, diffuse);
    EXPECT_NE(a, alpha);
    EXPECT_EQ(alpha->color_space, fr::ColorSpace::Linear);
    EXPECT_EQ(a->color_space, fr::ColorSpace::Srgb);
}

TEST(Textures, BadInputNamesThePointerAndTheFile) {
    const std::string dir = temp_dir();
    write_test_image(dir + "/grey.png", 2, 1, 1, std::vector<std::uint8_t>{10, 200},
                     OIIO::TypeDesc::UINT8);
    write_test_image(dir + "/rgb.png", 1, 1, 3, std::vector<std::uint8_t>{10, 20, 30},
                     OIIO::TypeDesc::UINT8);
    write_test_image(dir + "/nan.exr", 2, 1, 1, std::vector<float>{0.5f, std::nanf("")},
                     OIIO::TypeDesc::FLOAT);
    std::ofstream(dir + "/corrupt.png") << "not a png at all";
    auto with_reflectance = [&](const std::string& value, const std::string& extra = "") {
        return error_of(dir, R"("camera": {"position": [0, 0, 10], "look_at": [0, 0, 0], "fov": 40,
                                           "width": 4, "height": 4},
            "materials": {"m": {"model": "lambert", "reflectance": )" +
                                 value + R"(}},
            "shapes": [{"type": "quad", "material": "m",
                        "vertices": [[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]]})" +
                                 extra + R"(],
            "lights": [{"type": "environment", "radiance": 1}])");
    };
    const std::string ptr = "/materials/m/reflectance";
    struct Case {
        std::string value, pointer, words;
    };
    const Case cases[] = {
        {R"({"texture": "missing.png"})", ptr + "/texture", "missing.png"},
        {R"({"texture": "corrupt.png"})", ptr + "/texture", "corrupt.png"},
        {R"({"texture": "nan.exr"})", ptr + "/texture", "nan.exr"},
        {R"({"texture": "grey.png", "filtr": "closest"})", ptr + "/filtr", "did you mean 'filter'"},
        {R"({"texture": "grey.png", "channel": "g"})", ptr + "/channel", "grey.png"},
        {R"({"texture": "grey.png", "channel": "a"})", ptr + "/channel", "no channel 'a'"},
        {R"({"texture": "grey.png", "wrap": "tile"})", ptr + "/wrap", "unknown value 'tile'"},
        {R"({"texture": "grey.png", "scale": 2})", ptr, "largest value"},
        {R"({"checker": {"colors": [0.1]}})", ptr + "/checker/colors", "two colours"},
        {R"({"checker": {"colors": [0.1, 0.2], "scale": 0}})", ptr + "/checker/scale", ""},
    };
    for (const Case& c : cases) {
        const std::string e = with_reflectance(c.value);
        EXPECT_NE(e.find("tex.json: " + c.pointer + ":"), std::string::npos) << c.value << "\n"
                                                                             << e;
        EXPECT_NE(e.find(c.words), std::string::npos) << c.value << "\n" << e;
    }
    // A number parameter needs one channel of a colour image.
    const std::string num =
        error_of(dir, R"("camera": {"position": [0, 0, 10], "look_at": [0, 0, 0], "fov": 40,
                                                       "width": 4, "height": 4},
        "materials": {"m": {"model": "ggx", "alpha": {"texture": "rgb.png"}}},
        "shapes": [{"type": "sphere", "material": "m", "center": [0, 0, 0], "radius": 1}],
        "lights": [{"type": "environment", "radiance": 1}])");
    EXPECT_NE(num.find("/materials/m/alpha/channel"), std::string::npos) << num;
    // A UV array of the wrong length, and a textured mesh without UVs.
    const std::string mesh = R"("camera": {"position": [0, 0, 10], "look_at": [0, 0, 0], "fov": 40,
                                           "width": 4, "height": 4},
        "materials": {"m": {"model": "lambert", "reflectance": {"checker": {"colors": [0, 1]}}}},
        "lights": [{"type": "environment", "radiance": 1}],
        "shapes": [{"type": "mesh", "material": "m", "positions": [0, 0, 0, 1, 0, 0, 0, 1, 0],
                    "indices": [0, 1, 2])";
    const std::string wrong_len = error_of(dir, mesh + R"(, "uvs": [0, 0, 1, 0, 0]}])");
    EXPECT_NE(wrong_len.find("/shapes/0/uvs"), std::string::npos) << wrong_len;
    const std::string none = error_of(dir, mesh + "}]");
    EXPECT_NE(none.find("/shapes/0/uvs"), std::string::npos) << none;
    EXPECT_NE(none.find("no UVs"), std::string::npos) << none;
    // A negative emission texel (float image) is an error: radiance cannot be negative.
    write_test_image(dir + "/neg.exr", 1, 1, 1, std::vector<float>{-1.f}, OIIO::TypeDesc::FLOAT);
    const std::string neg =
        error_of(dir, R"("camera": {"position": [0, 0, 10], "look_at": [0, 0, 0], "fov": 40,
                                                       "width": 4, "height": 4},
        "shapes": [{"type": "quad", "emission": {"texture": "neg.exr"},
                    "vertices": [[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]]}],
        "lights": [])");
    EXPECT_NE(neg.find("/shapes/0/emission/texture"), std::string::npos) << neg;
}

// export-pov writes a textured diffuse colour or emission as a uv_mapping pigment on objects
// whose POV-Ray UVs are the core's (docs/povray.md, "Textures"; the pictures are compared by the
// povray test povray_export_textures) and names what it cannot write: any other textured
// parameter, a textured shape without POV-Ray UVs.
TEST(Textures, PovExportWritesUvPigmentsOrNamesThePointer) {
    const std::string head = R"({"format": "facet-scene", "version": 1,
        "camera": {"position": [0, 0, 10], "look_at": [0, 0, 0], "fov": 40, "width": 4,
                   "height": 4},
        "lights": [{"type": "point", "position": [0, 0, 5], "power": 10}],)";
    std::string sdl;
    auto error_of_export = [&](const std::string& rest) {
        try {
            sdl =
                fr::export_pov(fr::parse_scene_description(head + rest + "}", "p.json"), "p.json");
        } catch (const fr::SceneError& e) {
            return std::string(e.what());
        }
        return std::string();
    };
    // A checker diffuse colour on a sphere: a uv_mapping checker scaled to the cells, on a
    // unit sphere with y and z exchanged (POV-Ray's sphere UVs are the core's in that frame).
    EXPECT_EQ(error_of_export(R"(
        "materials": {"m": {"model": "lambert",
                            "reflectance": {"checker": {"colors": [0, 1], "scale": 4}}}},
        "shapes": [{"type": "sphere", "material": "m", "center": [1, 2, 3], "radius": 2}])"),
              "");
    EXPECT_NE(sdl.find("pigment { uv_mapping checker rgb <0, 0, 0>, rgb <1, 1, 1> matrix <0.25, "
                       "0, 0, 0, 0.25, 0, 0, 0, 1, 0, 0, 0> }"),
              std::string::npos)
        << sdl;
    EXPECT_NE(sdl.find("sphere { 0, 1\n  matrix <2, 0, 0, 0, 0, 2, 0, 2, 0, 1, 2, 3>"),
              std::string::npos)
        << sdl;
    // A textured emission (no material): the texture as the pigment, glowing.
    EXPECT_EQ(error_of_export(R"(
        "shapes": [{"type": "sphere", "center": [0, 0, 0], "radius": 1,
                    "emission": {"checker": {"colors": [0, 1]}, "scale": 2}}])"),
              "");
    EXPECT_NE(sdl.find("finish { ambient 0 diffuse 0 emission rgb <2, 2, 2> }"), std::string::npos)
        << sdl;
    // A textured roughness: povray-facet's brdf block takes constants.
    const std::string named = error_of_export(R"(
        "materials": {"m": {"model": "ggx", "alpha": {"checker": {"colors": [0.1, 0.5]}}}},
        "shapes": [{"type": "sphere", "material": "m", "center": [0, 0, 0], "radius": 1}])");
    EXPECT_NE(named.find("p.json: /materials/m/alpha: a textured 'alpha'"), std::string::npos)
        << named;
    // A textured disc: POV-Ray's disc has no UVs.
    const std::string emission = error_of_export(R"(
        "shapes": [{"type": "disc", "center": [0, 0, 0], "normal": [0, 0, 1], "radius": 1,
                    "emission": {"checker": {"colors": [0, 1]}}}])");
    EXPECT_NE(emission.find("p.json: /shapes/0/emission: a texture read through UVs"),
              std::string::npos)
        << emission;
    // The same scene without the texture exports.
    EXPECT_EQ(error_of_export(R"(
        "materials": {"m": {"model": "lambert", "reflectance": 0.5}},
        "shapes": [{"type": "sphere", "material": "m", "center": [0, 0, 0], "radius": 1}])"),
              "");
}
