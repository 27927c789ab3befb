// Adaptive sampling (render.h, "Adaptive sampling"): tiles stop at their own checkpoints once
// every pixel's Cycles-style error is below the threshold, deterministically.
#include <gtest/gtest.h>

#include <stdexcept>
#include <string>
#include <vector>

#include "facet/render/render.h"
#include "facet/render/scene.h"
#include "facet/testsupport/render_test_util.h"

namespace fr = facet::render;
using fr::testing::scene_from;

namespace {

// 64 x 32: the left half sees the lit plane (noisy: a quad light sampled per path), the right
// half only the constant environment above the horizon (no noise at all).
const char* const kHalfSky = R"(
    "camera": {"position": [0, 1, 3], "look_at": [0, 0.5, 0], "up": [0, 1, 0], "fov": 60,
               "width": 64, "height": 32},
    "materials": {"white": {"model": "lambert", "reflectance": 0.7}},
    "shapes": [
      {"type": "quad", "material": "white",
       "vertices": [[-20, 0, -20], [-20, 0, 3], [-0.3, 0, 3], [-0.3, 0, -20]]},
      {"type": "quad", "emission": 5,
       "vertices": [[-3, 3, -1], [-1, 3, -1], [-1, 3, 1], [-3, 3, 1]]}
    ],
    "lights": [{"type": "environment", "radiance": 0.5}])";

fr::RenderOptions adaptive_options(double threshold, int spp, int threads) {
    fr::RenderOptions o = fr::testing::test_options("path", spp, 3, threads);
    o.adaptive_threshold = threshold;
    o.adaptive_min_samples = 8;
    o.tile_size = 8;
    return o;
}

int differing(const fr::Image& a, const fr::Image& b) {
    int n = 0;
    for (std::size_t i = 0; i < a.pixels().size(); ++i) n += a.pixels()[i] != b.pixels()[i];
    return n;
}

}  // namespace

// The sky tiles have zero variance: they stop at the second checkpoint (8 + 4 samples); the lit
// tiles keep sampling. The image is the same on 1 thread in one pass as on 2 threads in many
// small passes (decisions at fixed sample counts of each tile).
TEST(AdaptiveSampling, FlatTilesStopEarlyAndTheImageIsDeterministic) {
    const fr::Scene scene = scene_from(kHalfSky);
    fr::RenderSession one(scene, adaptive_options(0.02, 256, 1));
    one.render();
    fr::RenderOptions watched = adaptive_options(0.02, 256, 2);
    watched.pass_seconds = 1e-4;
    fr::RenderSession two(scene, watched);
    int passes = 0;
    two.render([&](const fr::PassInfo&) { return ++passes, true; });
    EXPECT_GT(passes, 3);
    EXPECT_EQ(differing(one.image(), two.image()), 0);
    const fr::Film& film = one.film();
    const int w = film.width();
    // Pixel (60, 4): sky; pixel (4, 28): the lit plane.
    EXPECT_EQ(film.count_values()[std::size_t(4 * w + 60)], 12u);
    EXPECT_GT(film.count_values()[std::size_t(28 * w + 4)], 12u);
    EXPECT_LT(one.stats().mean_spp, 256.0);
    EXPECT_EQ(one.stats().spp, 12);
    std::printf("adaptive 0.02: mean %.1f spp of 256\n", one.stats().mean_spp);
}

// Ability to fail: at a threshold only noise-free pixels meet (the sky: both halves exactly
// equal), the noisy tiles take every sample and the image is the plain render's bit for bit
// (a constant pixel's mean is exact at any count); a loose one takes fewer and differs.
TEST(AdaptiveSampling, TinyThresholdIsThePlainRender) {
    const fr::Scene scene = scene_from(kHalfSky);
    fr::RenderOptions plain = fr::testing::test_options("path", 64, 3, 2);
    plain.tile_size = 8;
    fr::RenderStats st;
    const fr::Image a = fr::render(scene, plain);
    fr::RenderSession s(scene, adaptive_options(1e-12, 64, 2));
    s.render();
    const fr::Image b = s.image();
    EXPECT_EQ(differing(a, b), 0);
    EXPECT_EQ(s.film().count_values()[std::size_t(28 * s.film().width() + 4)], 64u);
    const fr::Image c = fr::render(scene, adaptive_options(0.5, 64, 2), &st);
    EXPECT_GT(differing(a, c), 0);
    EXPECT_LT(st.mean_spp, 64.0);
}

// A region render on the tile grid gives the whole adaptive render's pixels there, bit for bit
// (tiles decide alone; a tile the region cuts decides on its pixels inside, so it may differ);
// parts refuse adaptive renders (no per-pixel counts in them).
TEST(AdaptiveSampling, RegionRenderHasTheWholeRendersPixels) {
    const fr::Scene scene = scene_from(kHalfSky);
    const fr::Image whole = fr::render(scene, adaptive_options(0.05, 64, 2));
    fr::RenderOptions o = adaptive_options(0.05, 64, 2);
    o.region = fr::Region{24, 8, 56, 32};
    fr::RenderSession s(scene, o);
    s.render();
    const fr::Image crop = s.image();
    int differ = 0;
    for (int y = 8; y < 32; ++y)
        for (int x = 24; x < 56; ++x) differ += crop.at(x - 24, y - 8) != whole.at(x, y);
    EXPECT_EQ(differ, 0);
    EXPECT_THROW(s.part(), std::invalid_argument);
}

// Bad options name the option; sample ranges and the denoiser's halves are refused.
TEST(AdaptiveSampling, BadOptionsNameTheOption) {
    const fr::Scene scene = scene_from(kHalfSky);
    auto error_of = [&](fr::RenderOptions o) {
        try {
            fr::RenderSession s(scene, o);
        } catch (const std::invalid_argument& e) {
            return std::string(e.what());
        }
        return std::string("<no error>");
    };
    EXPECT_NE(error_of(adaptive_options(-0.1, 16, 1)).find("--adaptive-threshold"),
              std::string::npos);
    fr::RenderOptions o = adaptive_options(0.01, 16, 1);
    o.adaptive_min_samples = -2;
    EXPECT_NE(error_of(o).find("--adaptive-min-samples"), std::string::npos);
    o = adaptive_options(0.01, 16, 1);
    o.sample_begin = 0;
    o.sample_end = 8;
    EXPECT_NE(error_of(o).find("--region"), std::string::npos);
}
