// Image I/O round trips and diff metrics on images with known answers.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <stdexcept>
#include <string>

#include <unistd.h>

#include "facet/render/diff.h"
#include "facet/render/image.h"

namespace fr = facet::render;
using facet::Rgb;

namespace {

std::string temp_path(const std::string& name) {
    return (std::filesystem::temp_directory_path() /
            ("facet_test_" + std::to_string(::getpid()) + "_" + name))
        .string();
}

fr::Image gradient(int w, int h) {
    fr::Image img(w, h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            img.at(x, y) = Rgb(float(x) / float(w - 1), float(y) / float(h - 1), 0.25f);
    return img;
}

}  // namespace

TEST(Image, SrgbRoundTripAndKnownValues) {
    // The transfer function's published anchor points: 0 -> 0, 1 -> 1, 0.0031308 -> 0.04045
    // (both sides of the linear segment agree there to ~1e-6 by construction of the standard).
    EXPECT_FLOAT_EQ(fr::srgb_encode(0.f), 0.f);
    EXPECT_NEAR(fr::srgb_encode(1.f), 1.f, 1e-6f);
    EXPECT_NEAR(fr::srgb_encode(0.0031308f), 0.04045f, 1e-5f);
    EXPECT_NEAR(fr::srgb_encode(0.18f), 0.46135f, 1e-4f);  // middle grey, tabulated value
    // Round trip to 1e-5: float pow in both directions loses a few ulps, nothing more.
    for (int i = 0; i <= 1000; ++i) {
        float v = float(i) / 1000.f;
        EXPECT_NEAR(fr::srgb_decode(fr::srgb_encode(v)), v, 1e-5f) << v;
    }
}

TEST(Image, ExrRoundTripIsBitExact) {
    fr::Image img = gradient(37, 21);
    img.at(3, 4) = Rgb(1e-20f, 65504.f * 4.f, 1e30f);  // values outside half range survive
    const std::string path = temp_path("rt.exr");
    fr::write_image(img, path);
    fr::Image back = fr::read_image(path);
    ASSERT_EQ(back.width(), img.width());
    ASSERT_EQ(back.height(), img.height());
    for (size_t i = 0; i < img.pixels().size(); ++i) EXPECT_EQ(back.pixels()[i], img.pixels()[i]);
    std::filesystem::remove(path);
}

TEST(Image, PngRoundTripWithinQuantisation) {
    fr::Image img = gradient(32, 16);
    img.at(0, 0) = Rgb(-1.f, 2.f, 0.5f);  // clamped to [0, 1]
    const std::string path = temp_path("rt.png");
    fr::write_image(img, path);
    fr::Image back = fr::read_image(path);
    ASSERT_EQ(back.width(), 32);
    ASSERT_EQ(back.height(), 16);
    EXPECT_EQ(back.at(0, 0),
              Rgb(0.f, 1.f, fr::srgb_decode(std::round(fr::srgb_encode(0.5f) * 255.f) / 255.f)));
    for (int y = 0; y < 16; ++y) {
        for (int x = 1; x < 32; ++x) {
            for (int c = 0; c < 3; ++c) {
                // 8-bit sRGB: rounding moves the encoded value by at most half a code,
                // 0.5/255 = 1.96e-3; the decode slope is at most 2.4/1.055 = 2.27 (at 1), so the
                // linear error is at most 4.46e-3.
                const float want = std::clamp(img.at(x, y)[c], 0.f, 1.f);
                EXPECT_NEAR(back.at(x, y)[c], want, 4.5e-3f);
                // And in the encoded domain it is exact to half a code.
                EXPECT_NEAR(fr::srgb_encode(back.at(x, y)[c]), fr::srgb_encode(want),
                            0.5f / 255.f + 1e-5f);
            }
        }
    }
    std::filesystem::remove(path);
}

TEST(Image, ErrorsNameTheFile) {
    try {
        fr::read_image("/nonexistent/dir/x.exr");
        FAIL() << "expected a throw";
    } catch (const std::runtime_error& e) {
        EXPECT_NE(std::string(e.what()).find("/nonexistent/dir/x.exr"), std::string::npos);
    }
    EXPECT_THROW(fr::read_image("/nonexistent/x.png"), std::runtime_error);
    EXPECT_THROW(fr::write_image(gradient(2, 2), temp_path("x.bmp")), std::runtime_error);
    // A text file with an .exr name is malformed, not a crash.
    const std::string bad = temp_path("bad.exr");
    if (std::FILE* f = std::fopen(bad.c_str(), "w")) {
        std::fputs("not an exr", f);
        std::fclose(f);
    }
    EXPECT_THROW(fr::read_image(bad), std::runtime_error);
    std::filesystem::remove(bad);
}

TEST(Diff, KnownMetrics) {
    // Reference all 1; test image 1 everywhere except one pixel at 1.5 (all channels).
    fr::Image b(4, 5), a(4, 5);
    for (auto& p : b.pixels()) p = Rgb(1.f);
    a = b;
    a.at(2, 3) = Rgb(1.5f);
    fr::DiffStats s = fr::diff_images(a, b, {0.1, 0.0});
    // 20 pixels x 3 channels, 3 of them with error 0.5: mse = 3 * 0.25 / 60 = 0.0125.
    // Tolerance 1e-12: the sums are exact in double except for the final sqrt/divide.
    EXPECT_NEAR(s.rmse, std::sqrt(0.0125), 1e-12);
    EXPECT_NEAR(s.rel_mse, 3 * 0.25 / (1.0 + fr::kRelMseEpsilon) / 60.0, 1e-12);
    EXPECT_DOUBLE_EQ(s.max_abs, 0.5);
    EXPECT_DOUBLE_EQ(s.max_rel, 0.5);
    EXPECT_EQ(s.max_abs_x, 2);
    EXPECT_EQ(s.max_abs_y, 3);
    EXPECT_EQ(s.pixels_within, 19u);
    EXPECT_DOUBLE_EQ(s.fraction_within, 19.0 / 20.0);
    EXPECT_EQ(s.nonfinite_pixels, 0u);
    // With a 60% tolerance every pixel passes.
    EXPECT_DOUBLE_EQ(fr::diff_images(a, b, {0.6, 0.0}).fraction_within, 1.0);
    // Identical images: zero error.
    fr::DiffStats z = fr::diff_images(b, b, {0.0, 0.0});
    EXPECT_EQ(z.rmse, 0.0);
    EXPECT_EQ(z.fraction_within, 1.0);
}

TEST(Diff, NonFiniteAndSizeMismatch) {
    fr::Image a(3, 3), b(3, 3);
    a.at(1, 1) = Rgb(NAN, 0.f, 0.f);
    fr::DiffStats s = fr::diff_images(a, b, {0.01, 0.0});
    EXPECT_EQ(s.nonfinite_pixels, 1u);
    EXPECT_EQ(s.pixels_within, 8u);
    EXPECT_EQ(s.rmse, 0.0);
    try {
        fr::diff_images(fr::Image(3, 3), fr::Image(4, 3), {});
        FAIL() << "expected a throw";
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("3x3 vs 4x3"), std::string::npos) << e.what();
    }
}

TEST(Diff, HeatmapMarksErrors) {
    fr::Image b(2, 1), a(2, 1);
    b.at(0, 0) = b.at(1, 0) = Rgb(1.f);
    a = b;
    a.at(1, 0) = Rgb(10.f);  // far beyond tolerance: the hot end of the ramp (white)
    fr::Image h = fr::error_heatmap(a, b, {0.01, 0.0});
    EXPECT_EQ(h.at(0, 0), Rgb(0.f));
    EXPECT_NEAR(h.at(1, 0).r, 1.f, 1e-6f);
    EXPECT_NEAR(h.at(1, 0).g, 1.f, 1e-6f);
}
