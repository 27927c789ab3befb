// Mipmap filtering (texture.h, texel_image.h) and the pixel footprints it reads (camera.h,
// scene.h): the MIP levels' values, the level chosen for a known footprint with each camera,
// the footprint against the real neighbouring camera rays, magnification equal to "linear"
// bit for bit, the far checker that mipmap averages and closest aliases, and the texture
// memory bound.
#include <gtest/gtest.h>

#include <OpenImageIO/imageio.h>

#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include <unistd.h>

#include "facet/frame.h"
#include "facet/render/camera.h"
#include "facet/render/render.h"
#include "facet/render/scene.h"
#include "facet/render/texel_image.h"
#include "facet/render/texture.h"
#include "facet/testsupport/render_test_util.h"
#include "oiio_test_image.h"

namespace fr = facet::render;
using facet::Vec2;
using facet::Vec3;

namespace {

fr::TexelImage grey_image(int w, int h, const std::vector<float>& v) {
    fr::TexelImage im;
    im.width = w;
    im.height = h;
    im.channels = 1;
    im.texels = v;
    return im;
}

// A w x h one-channel checker with 1-texel checks: texel (x, y) = (x + y) mod 2.
std::vector<float> checker_texels(int w, int h) {
    std::vector<float> v(std::size_t(w) * std::size_t(h));
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            v[std::size_t(y) * std::size_t(w) + std::size_t(x)] = float((x + y) % 2);
    return v;
}

fr::Texture mip_texture(const fr::TexelImage& im, fr::TextureFilter filter,
                        const fr::TextureDesc& d = {}) {
    auto img = std::make_shared<const fr::TexelImage>(im);
    return fr::Texture::image(
        img, filter, fr::TextureWrap::Repeat, fr::Texture::kAllChannels, d,
        std::make_shared<const std::vector<fr::TexelImage>>(fr::build_mip_levels(*img)));
}

}  // namespace

// Levels of a 4 x 2 image: 2 x 1 (means of 2 x 2 blocks), then 1 x 1 (the mean). Odd sizes
// weigh each texel by its overlap: 3 x 1 -> 1 x 1 is the plain mean; 5 x 3 keeps the mean of
// the image at every level. Tolerance: float sums of at most 15 values, 1e-6 relative.
TEST(MipLevels, BoxFilterKeepsTheMean) {
    const auto l = fr::build_mip_levels(grey_image(4, 2, {1, 2, 3, 4, 5, 6, 7, 8}));
    ASSERT_EQ(l.size(), 2u);
    EXPECT_EQ(l[0].width, 2);
    EXPECT_EQ(l[0].height, 1);
    EXPECT_FLOAT_EQ(l[0].at(0, 0, 0), (1 + 2 + 5 + 6) / 4.f);
    EXPECT_FLOAT_EQ(l[0].at(1, 0, 0), (3 + 4 + 7 + 8) / 4.f);
    EXPECT_FLOAT_EQ(l[1].at(0, 0, 0), 4.5f);
    const auto odd = fr::build_mip_levels(grey_image(3, 1, {1, 2, 6}));
    ASSERT_EQ(odd.size(), 1u);
    EXPECT_NEAR(odd[0].at(0, 0, 0), 3.f, 3e-6f);
    std::vector<float> v(15);
    double sum = 0;
    for (std::size_t i = 0; i < v.size(); ++i) sum += v[i] = float((i * 7) % 11);
    const auto l53 = fr::build_mip_levels(grey_image(5, 3, v));
    ASSERT_EQ(l53.size(), 2u);  // 2 x 1, 1 x 1
    EXPECT_NEAR(0.5 * (l53[0].at(0, 0, 0) + l53[0].at(1, 0, 0)), sum / 15, 1e-6 * sum);
    EXPECT_NEAR(l53[1].at(0, 0, 0), sum / 15, 1e-6 * sum);
}

// A plane facing the camera at distance D, textured with a 1024^2 image over S x S scene units,
// where one pixel covers exactly 2^k texels, selects level k, for the pinhole, a thin lens (any
// lens sample, plane off the plane of focus) and orthographic. Tolerance 1e-4 levels: float
// footprints and log2.
TEST(MipLevels, OnePixelOverTwoToTheKTexelsSelectsLevelK) {
    const int n = 1024, film = 64;
    const float S = 2.f;  // uv [0, 1]^2 spans S scene units: dp/du = S x, dp/dv = S y
    const fr::Texture tex =
        mip_texture(grey_image(n, n, checker_texels(n, n)), fr::TextureFilter::Mipmap);
    const Vec3 dpdu(S, 0, 0), dpdv(0, S, 0), normal(0, 0, 1);
    for (int k = 0; k <= 6; ++k) {
        // Pixel footprint 2^k texels = 2^k S / n scene units. Perspective: D 2 tan(fov/2) / film.
        const float w = std::ldexp(S / float(n), k);
        const float tan_half = 0.25f;
        const float D = w * float(film) / (2.f * tan_half);
        const float fov = 2.f * std::atan(tan_half) * 180.f / 3.14159265f;
        for (float aperture : {0.f, 0.3f}) {
            fr::CameraOptions o;
            o.aperture_radius = aperture;
            o.focus_distance = 0.5f * D;  // off the plane of focus
            const fr::Camera cam =
                fr::Camera::make(Vec3(0, 0, D), Vec3(0), Vec3(0, 1, 0), fov, film, film, o);
            for (Vec2 lens : {Vec2(0.5f), Vec2(0.1f, 0.9f)}) {
                const fr::Ray r = cam.generate_ray(Vec2(film / 2.f + 0.5f), lens);
                const Vec3 p = r.o + (-r.o.z / r.d.z) * r.d;
                const fr::UvFootprint fp =
                    fr::uv_footprint(cam.footprint(r.o, r.d, p, normal), dpdu, dpdv);
                EXPECT_NEAR(tex.mip_level(fp), float(k), 1e-4f)
                    << "k " << k << " aperture " << aperture;
            }
        }
        fr::CameraOptions ortho;
        ortho.projection = fr::Projection::Orthographic;
        ortho.ortho_scale = w * float(film);
        const fr::Camera oc =
            fr::Camera::make(Vec3(0, 0, 7), Vec3(0), Vec3(0, 1, 0), 40.f, film, film, ortho);
        const fr::Ray r = oc.generate_ray(Vec2(3.5f, 40.5f));
        const Vec3 p = r.o + (-r.o.z / r.d.z) * r.d;
        EXPECT_NEAR(tex.mip_level(fr::uv_footprint(oc.footprint(r.o, r.d, p, normal), dpdu, dpdv)),
                    float(k), 1e-4f)
            << "orthographic k " << k;
        // Later vertices' approximation is the same for points the camera sees.
        EXPECT_NEAR(tex.mip_level(fr::uv_footprint(oc.footprint_at(p, normal), dpdu, dpdv)),
                    float(k), 1e-4f);
    }
}

// The closed-form footprint equals the offsets to where the real camera rays of film positions
// x + 1 and y + 1 (same lens sample) meet the tangent plane, on a tilted plane, off-centre, for
// every camera kind. Tolerance 2e-3 relative to the footprint: the real rays are normalised and
// re-intersected in float at distance ~5.
TEST(MipLevels, FootprintMatchesTheNeighbouringCameraRays) {
    const Vec3 n = glm::normalize(Vec3(0.3f, -0.4f, 1.f));
    const Vec3 q(0.2f, -0.1f, 0.f);  // a point of the plane
    auto meet = [&](const fr::Ray& r) {
        return r.o + (glm::dot(q - r.o, n) / glm::dot(r.d, n)) * r.d;
    };
    for (int kind = 0; kind < 4; ++kind) {
        fr::CameraOptions o;
        if (kind == 1 || kind == 3) {
            o.aperture_radius = 0.4f;
            o.focus_distance = 3.f;
        }
        if (kind >= 2) {
            o.projection = fr::Projection::Orthographic;
            o.ortho_scale = 3.f;
        }
        const fr::Camera cam =
            fr::Camera::make(Vec3(0.5f, 0.2f, 5), Vec3(0), Vec3(0, 1, 0), 50.f, 80, 60, o);
        const Vec2 film(17.3f, 41.8f), lens(0.8f, 0.3f);
        const fr::Ray r = cam.generate_ray(film, lens);
        const Vec3 p = meet(r);
        const fr::PixelFootprint fp = cam.footprint(r.o, r.d, p, n);
        const Vec3 px = meet(cam.generate_ray(film + Vec2(1, 0), lens)) - p;
        const Vec3 py = meet(cam.generate_ray(film + Vec2(0, 1), lens)) - p;
        EXPECT_LT(glm::length(fp.dpdx - px), 2e-3f * glm::length(px)) << "kind " << kind;
        EXPECT_LT(glm::length(fp.dpdy - py), 2e-3f * glm::length(py)) << "kind " << kind;
    }
}

// Magnification (lambda <= 0: a footprint under one texel, or none) reads level 0 exactly as
// the "linear" filter does: compared bit for bit at many uv.
TEST(MipLevels, MagnificationIsLinearBitForBit) {
    std::vector<float> v(16 * 8);
    for (std::size_t i = 0; i < v.size(); ++i) v[i] = std::sin(float(i) * 0.37f) * 0.5f + 0.5f;
    fr::TextureDesc d;
    d.uv_scale = Vec2(1.3f, 0.7f);
    d.uv_rotation = 20.0;
    const fr::Texture mip = mip_texture(grey_image(16, 8, v), fr::TextureFilter::Mipmap, d);
    const fr::Texture lin = mip_texture(grey_image(16, 8, v), fr::TextureFilter::Linear, d);
    for (int i = 0; i < 500; ++i) {
        const Vec2 uv(std::fmod(float(i) * 0.6180339f, 1.f) * 3.f - 1.f,
                      std::fmod(float(i) * 0.4142135f, 1.f) * 3.f - 1.f);
        const fr::UvFootprint small{Vec2(0.02f, 0.f), Vec2(0.f, 0.05f)};  // < 1 texel
        ASSERT_LE(mip.mip_level(small), 0.f);
        EXPECT_EQ(mip.eval(uv, small), lin.eval(uv)) << i;
        EXPECT_EQ(mip.eval(uv, fr::UvFootprint{}), lin.eval(uv)) << i;
    }
    // Past the last level: the 1 x 1 mean.
    const fr::UvFootprint huge{Vec2(100.f, 0.f), Vec2(0.f, 100.f)};
    double mean = 0;
    for (float x : v) mean += x;
    EXPECT_NEAR(mip.eval(Vec2(0.3f), huge).r, mean / double(v.size()), 1e-6);
}

namespace {

// A 1024^2 checker of 1-texel checks (float EXR, 0 and 1) as the emission of a 1 x 1 quad seen
// from far away: 32 x 32 pixels over the quad, 32 texels per pixel (level 5).
fr::Image far_checker(const std::string& dir, const std::string& filter,
                      const std::string& camera) {
    const fr::Scene scene =
        fr::load_scene_from_string(R"({"format": "facet-scene", "version": 1, )" + camera + R"(
            "shapes": [{"type": "quad", "vertices": [[-0.5, -0.5, 0], [0.5, -0.5, 0],
                                                     [0.5, 0.5, 0], [-0.5, 0.5, 0]],
                        "material": {"model": "lambert", "reflectance": 0},
                        "emission": {"texture": "checker.exr", "filter": ")" +
                                       filter + R"("}}],
            "render": {"max_depth": 0}})",
                                   "far.json", dir);
    return fr::render(scene, fr::testing::test_options("path", 1, 3, 1));
}

}  // namespace

// The far checker at 1 spp: mipmap gives the average 0.5 in every pixel (level 5 of a 1-texel
// checker is exactly 0.5 in float: every level >= 1 averages equal numbers of 0s and 1s, so
// the tolerance 1e-6 only allows for the blend weights' rounding), while closest reads single
// texels, 0 or 1 (aliasing: its RMSE from 0.5 is 0.5, far over the 0.25 the test allows).
// Pinhole, thin lens and orthographic cameras alike.
TEST(MipLevels, FarCheckerAveragesWithMipmapAndAliasesWithClosest) {
    const std::string dir = fr::testing::test_temp_dir("facet_mipmap");
    fr::testing::write_test_image(dir + "/checker.exr", 1024, 1024, 1, checker_texels(1024, 1024),
                                  OIIO::TypeDesc::FLOAT);
    // fov: the 1-unit quad spans 32 of 64 pixels at distance 20 (tan(fov/2) = 1 / 20).
    const std::string fov = std::to_string(2.0 * std::atan(1.0 / 20.0) * 180.0 / M_PI);
    const std::vector<std::string> cameras = {
        R"("camera": {"position": [0, 0, 20], "look_at": [0, 0, 0], "fov": )" + fov +
            R"(, "width": 64, "height": 64},)",
        R"("camera": {"position": [0, 0, 20], "look_at": [0, 0, 0], "fov": )" + fov +
            R"(, "width": 64, "height": 64, "aperture_radius": 0.2, "focus_distance": 20},)",
        R"("camera": {"type": "orthographic", "position": [0, 0, 20], "look_at": [0, 0, 0],
                      "scale": 2, "width": 64, "height": 64},)"};
    for (const std::string& cam : cameras) {
        const fr::Image mip = far_checker(dir, "mipmap", cam);
        const fr::Image closest = far_checker(dir, "closest", cam);
        double se_mip = 0, se_closest = 0;
        int n = 0;
        for (int y = 20; y < 44; ++y)  // well inside the quad (pixels 16..47)
            for (int x = 20; x < 44; ++x) {
                EXPECT_NEAR(mip.at(x, y)[0], 0.5f, 1e-6f) << cam << " " << x << "," << y;
                se_mip += std::pow(mip.at(x, y)[0] - 0.5, 2);
                se_closest += std::pow(closest.at(x, y)[0] - 0.5, 2);
                ++n;
            }
        EXPECT_LT(std::sqrt(se_mip / n), 1e-6);
        EXPECT_GT(std::sqrt(se_closest / n), 0.25) << cam;
    }
}

// "mipmap" is the default filter of image textures.
TEST(MipLevels, MipmapIsTheDefaultFilter) {
    const std::string dir = fr::testing::test_temp_dir("facet_mipmap");
    fr::testing::write_test_image(dir + "/g.exr", 4, 4, 1, std::vector<float>(16, 0.5f),
                                  OIIO::TypeDesc::FLOAT);
    const fr::Scene scene = fr::load_scene_from_string(
        R"({"format": "facet-scene", "version": 1,
            "camera": {"position": [0, 0, 3], "look_at": [0, 0, 0], "fov": 40, "width": 4, "height": 4},
            "shapes": [{"type": "sphere", "center": [0, 0, 0], "radius": 1,
                        "material": {"model": "lambert", "reflectance": {"texture": "g.exr"}}}],
            "lights": [{"type": "environment", "radiance": 1}]})",
        "d.json", dir);
    ASSERT_EQ(scene.textured_materials().size(), 1u);
    EXPECT_EQ(scene.textured_materials()[0].slots[0].texture->filter(), fr::TextureFilter::Mipmap);
}

// Texture memory is bounded: past the bound an image is paged, not an error (the paging
// itself: test_texture_cache.cpp). A 512^2 grey float image is 1 MiB, 1.33 MiB with its
// levels: a 1 MiB bound pages it, "linear" and "mipmap" alike, with the same value range.
TEST(MipLevels, TextureMemoryBoundPagesInsteadOfFailing) {
    const std::string dir = fr::testing::test_temp_dir("facet_mipmap");
    std::vector<float> texels(512 * 512);
    for (std::size_t i = 0; i < texels.size(); ++i) texels[i] = float(i % 1000) / 1000.f;
    fr::testing::write_test_image(dir + "/m.exr", 512, 512, 1, texels, OIIO::TypeDesc::FLOAT);
    for (const std::string filter : {"linear", "mipmap"}) {
        fr::SceneLimits limits;
        limits.texture_memory = 1 << 20;
        const fr::Scene scene = fr::load_scene_from_string(
            R"({"format": "facet-scene", "version": 1,
                "camera": {"position": [0, 0, 3], "look_at": [0, 0, 0], "fov": 40, "width": 4, "height": 4},
                "shapes": [{"type": "sphere", "center": [0, 0, 0], "radius": 1,
                            "material": {"model": "lambert",
                                         "reflectance": {"texture": "m.exr", "filter": ")" +
                filter + R"("}}}],
                "lights": [{"type": "environment", "radiance": 1}]})",
            "mem.json", dir, limits);
        EXPECT_EQ(scene.texture_memory().paged_images, 1u) << filter;
        const fr::Texture& t = *scene.textured_materials()[0].slots[0].texture;
        EXPECT_EQ(t.min_value().r, 0.f);
        EXPECT_EQ(t.max_value().r, 0.999f);
    }
}

// dp/du and dp/dv on every shape kind agree with the surface: two hits delta = 1e-3 apart
// satisfy p1 - p0 = dpdu (u1 - u0) + dpdv (v1 - v0) to first order. Tolerance 1e-2 of |p1 - p0|:
// the sphere's curvature contributes O(delta) relative, float uv rounding ~1e-4 relative at
// this delta; a wrong scale (2 pi, 2 r) or axis is off by > 0.3.
TEST(MipLevels, SurfaceDerivativesMatchTheUvMap) {
    struct Case {
        const char* shape;
        Vec3 o, d;
    };
    const Vec3 down(0, 0, -1);
    const std::vector<Case> cases = {
        {R"({"type": "quad", "material": "c", "vertices": [[0, 0, 0], [4, 0, 0], [5, 2, 0], [0, 3, 0]]})",
         Vec3(1, 1, 5), down},
        {R"({"type": "box", "material": "c", "min": [-1, -2, -1], "max": [1, 1, 3]})",
         Vec3(0.3f, -0.5f, 9), down},
        {R"({"type": "box", "material": "c", "min": [-1, -2, -1], "max": [1, 1, 3]})",
         Vec3(9, -0.5f, 0.4f), Vec3(-1, 0, 0)},
        {R"({"type": "grid", "material": "c", "nx": 3, "ny": 2, "transform": {"scale": [2, 1, 1]}})",
         Vec3(0.5f, -0.2f, 5), down},
        {R"({"type": "sphere", "material": "c", "center": [0, 0, 0], "radius": 2})",
         Vec3(0.4f, 9, 0.7f), Vec3(0, -1, 0)},
        {R"({"type": "icosphere", "material": "c", "center": [0, 0, 0], "radius": 2,
             "subdivisions": 5})",
         Vec3(0.4f, 9, 0.7f), Vec3(0, -1, 0)},
        {R"({"type": "disc", "material": "c", "center": [0, 0, 0], "radius": 2, "normal": [0, 0, 1]})",
         Vec3(0.5f, -0.5f, 5), down},
        {R"({"type": "plane", "material": "c", "point": [1, 1, 0], "normal": [0, 0, 1]})",
         Vec3(3.5f, -2, 5), down},
    };
    const float delta = 1e-3f;
    for (const Case& c : cases) {
        const fr::SurfaceHit h0 = fr::testing::checker_scene_hit(c.shape, c.o, c.d);
        ASSERT_GT(glm::length(h0.dpdu_uv), 0.f) << c.shape;
        // Two directions across the ray.
        const facet::Frame f = facet::Frame::from_z(glm::normalize(c.d));
        for (const Vec3& t : {f.x, f.y}) {
            const fr::SurfaceHit h1 = fr::testing::checker_scene_hit(c.shape, c.o + delta * t, c.d);
            const Vec3 dp = h1.p - h0.p;
            const Vec2 duv = h1.uv - h0.uv;
            const Vec3 lin = h0.dpdu_uv * duv.x + h0.dpdv_uv * duv.y;
            EXPECT_LT(glm::length(dp - lin), 1e-2f * glm::length(dp)) << c.shape;
        }
    }
}
