// Image files as texture data (texel_image.h): decoding, orientation, validation, the cache.
// The files are written here with OpenImageIO itself, byte for byte, so the expected texels are
// known independently of the reader under test.
#include <gtest/gtest.h>

#include <OpenImageIO/imageio.h>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <unistd.h>

#include "facet/render/texel_image.h"
#include "oiio_test_image.h"

namespace fr = facet::render;

namespace {

std::string temp_path(const std::string& name) {
    return (std::filesystem::temp_directory_path() /
            ("facet_texel_" + std::to_string(::getpid()) + "_" + name))
        .string();
}

using facet::render::testing::write_test_image;

// IEC 61966-2-1 decoding in double: the reference the float decoder must meet.
double srgb_reference(double e) {
    return e <= 0.04045 ? e / 12.92 : std::pow((e + 0.055) / 1.055, 2.4);
}

std::string error_of(const std::string& path, const fr::TexelImageOptions& o = {}) {
    try {
        fr::load_texel_image(path, o, "/materials/wood/reflectance");
    } catch (const fr::TexelImageError& e) {
        return e.what();
    }
    return "";
}

}  // namespace

TEST(TexelImage, EightBitPngDecodesEveryCodeWithTheSrgbCurve) {
    // 256 x 1 grey ramp: code k at column k.
    const std::string path = temp_path("ramp.png");
    std::vector<std::uint8_t> ramp(256);
    for (int k = 0; k < 256; ++k) ramp[k] = std::uint8_t(k);
    write_test_image(path, 256, 1, 1, ramp, OIIO::TypeDesc::UINT8);
    const fr::TexelImage img = fr::load_texel_image(path, {}, "test");
    ASSERT_EQ(img.width, 256);
    ASSERT_EQ(img.channels, 1);
    EXPECT_FALSE(img.float_format);
    EXPECT_EQ(img.color_space, fr::ColorSpace::Srgb);  // Auto -> sRGB for 8-bit
    for (int k = 0; k < 256; ++k) {
        // Exact: the float nearest to the curve evaluated in double (the decoder works in
        // double and rounds once; a float evaluation misses by up to ~3 ulps, gamma 2.2 by 1e-2).
        EXPECT_EQ(img.at(k, 0, 0), float(srgb_reference(double(k) / 255.0))) << "code " << k;
    }
    // Linear keeps the normalised codes.
    const fr::TexelImage lin = fr::load_texel_image(path, {fr::ColorSpace::Linear}, "test");
    for (int k = 0; k < 256; ++k) EXPECT_FLOAT_EQ(lin.at(k, 0, 0), float(k) / 255.f);
    std::filesystem::remove(path);
}

TEST(TexelImage, RowZeroIsTheTopAndAlphaIsNotDecoded) {
    // 1 x 2 RGBA: top row red with alpha 128, bottom row green with alpha 255.
    const std::string path = temp_path("rows.png");
    std::vector<std::uint8_t> px = {255, 0, 0, 128, 0, 255, 0, 255};
    write_test_image(path, 1, 2, 4, px, OIIO::TypeDesc::UINT8);
    const fr::TexelImage img = fr::load_texel_image(path, {}, "test");
    ASSERT_EQ(img.channels, 4);
    EXPECT_EQ(img.alpha_channel, 3);
    EXPECT_FLOAT_EQ(img.at(0, 0, 0), 1.f);
    EXPECT_FLOAT_EQ(img.at(0, 0, 1), 0.f);
    EXPECT_FLOAT_EQ(img.at(0, 1, 1), 1.f);
    EXPECT_FLOAT_EQ(img.at(0, 0, 3), 128.f / 255.f);  // alpha stays linear
    std::filesystem::remove(path);
}

TEST(TexelImage, FloatFilesAreLinearAndKeepTheirValues) {
    const std::string path = temp_path("hdr.exr");
    std::vector<float> px = {0.f, 0.5f, 1.f, 1000.f, 1e-6f, 3.25f};
    write_test_image(path, 2, 1, 3, px, OIIO::TypeDesc::FLOAT);
    const fr::TexelImage img = fr::load_texel_image(path, {}, "test");
    EXPECT_TRUE(img.float_format);
    EXPECT_EQ(img.color_space, fr::ColorSpace::Linear);
    for (std::size_t i = 0; i < px.size(); ++i) EXPECT_EQ(img.texels[i], px[i]);
    std::filesystem::remove(path);
}

TEST(TexelImage, BadFilesAreErrorsNamingThePlaceAndTheFile) {
    const std::string missing = temp_path("missing.png");
    std::string e = error_of(missing);
    EXPECT_NE(e.find("/materials/wood/reflectance: " + missing), std::string::npos) << e;
    EXPECT_NE(e.find("no such image file"), std::string::npos) << e;

    const std::string corrupt = temp_path("corrupt.png");
    std::ofstream(corrupt) << "this is not a PNG file";
    e = error_of(corrupt);
    EXPECT_NE(e.find(corrupt), std::string::npos) << e;
    EXPECT_NE(e.find("cannot read image"), std::string::npos) << e;
    std::filesystem::remove(corrupt);

    const std::string nan = temp_path("nan.exr");
    write_test_image(nan, 2, 2, 3,
                     std::vector<float>{0, 0, 0, 0, 0, 0, 0, 0, 0, 1, std::nanf(""), 1},
                     OIIO::TypeDesc::FLOAT);
    e = error_of(nan);
    EXPECT_NE(e.find("texel (1, 1) channel 1 is nan"), std::string::npos) << e;
    std::filesystem::remove(nan);

    const std::string neg = temp_path("neg.exr");
    write_test_image(neg, 1, 1, 3, std::vector<float>{1.f, -0.5f, 1.f}, OIIO::TypeDesc::FLOAT);
    EXPECT_EQ(error_of(neg), "");  // signed data is allowed unless asked
    e = error_of(neg, {fr::ColorSpace::Auto, true});
    EXPECT_NE(e.find("texel (0, 0) channel 1 is negative: -0.5"), std::string::npos) << e;
    std::filesystem::remove(neg);
}

TEST(TexelImageCache, TheSameImageIsReadOnce) {
    const std::string dir = temp_path("cache");
    std::filesystem::create_directories(dir + "/sub");
    const std::string path = dir + "/a.png";
    write_test_image(path, 2, 2, 3, std::vector<std::uint8_t>(12, 200), OIIO::TypeDesc::UINT8);
    fr::TexelImageCache cache;
    auto a = cache.get(path, {}, "x");
    auto b = cache.get(dir + "/sub/../a.png", {}, "y");
    EXPECT_EQ(a.get(), b.get());
    EXPECT_EQ(cache.size(), 1u);
    auto c = cache.get(path, {fr::ColorSpace::Linear}, "z");  // other decoding: another entry
    EXPECT_NE(a.get(), c.get());
    EXPECT_EQ(cache.size(), 2u);
    EXPECT_EQ(cache.bytes(), 2u * (12u + 3u) * sizeof(float));  // 2x2 RGB and its 1x1 level
    std::filesystem::remove_all(dir);
}
