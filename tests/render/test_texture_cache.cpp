// The texture memory bound (texel_image.h, "Memory bound"; texel_pages.h): images past the
// bound are paged through a tile cache, give the same texels and the same rendered image bit
// for bit, and the resident texels never pass the bound.
#include <gtest/gtest.h>

#include <OpenImageIO/imageio.h>

#include <cstdint>
#include <cstring>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "facet/render/render.h"
#include "facet/render/scene.h"
#include "facet/render/texel_image.h"
#include "facet/render/texel_pages.h"
#include "facet/testsupport/render_test_util.h"
#include "oiio_test_image.h"

namespace fr = facet::render;

namespace {

constexpr std::uint64_t kMiB = std::uint64_t(1) << 20;

template <typename T>
std::vector<T> noise(std::size_t n, std::uint32_t seed, double scale) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(0.0, scale);
    std::vector<T> v(n);
    for (T& x : v) x = T(u(rng));
    return v;
}

// Every texel of every level of `paged` equals the whole image's (build_mip_levels).
void expect_same_levels(const fr::TexelImage& whole, const fr::TexelImage& paged) {
    ASSERT_TRUE(paged.paged);
    ASSERT_FALSE(whole.paged);
    EXPECT_TRUE(paged.texels.empty());
    const auto mips = fr::build_mip_levels(whole);
    const fr::PagedImage& p = *paged.paged;
    ASSERT_EQ(p.levels(), int(mips.size()) + 1);
    const int c = whole.channels;
    std::vector<float> t(static_cast<std::size_t>(c));
    std::size_t differ = 0;
    for (int l = 0; l < p.levels(); ++l) {
        const fr::TexelImage& w = l == 0 ? whole : mips[std::size_t(l - 1)];
        ASSERT_EQ(p.level(l).width, w.width);
        ASSERT_EQ(p.level(l).height, w.height);
        for (int y = 0; y < w.height; ++y)
            for (int x = 0; x < w.width; ++x) {
                p.texel(l, x, y, t.data());
                const float* e =
                    &w.texels[(std::size_t(y) * std::size_t(w.width) + std::size_t(x)) *
                              std::size_t(c)];
                differ += std::memcmp(t.data(), e, std::size_t(c) * sizeof(float)) != 0;
            }
    }
    EXPECT_EQ(differ, 0u);
}

}  // namespace

// Paged texels are the whole image's bit for bit at every MIP level: odd sizes (fractional box
// weights, narrow edge tiles), a float EXR and an 8-bit sRGB PNG with alpha (both decoders).
// The 1 MiB bound keeps 768 KiB for whole images; each of these needs more, so both are paged.
TEST(TextureCache, PagedLevelsAreTheWholeLevels) {
    const std::string dir = fr::testing::test_temp_dir("facet_texcache");
    fr::testing::write_test_image(dir + "/f.exr", 301, 173, 3, noise<float>(301 * 173 * 3, 1, 4.0),
                                  OIIO::TypeDesc::FLOAT);
    fr::testing::write_test_image(dir + "/b.png", 517, 263, 4,
                                  noise<std::uint8_t>(517 * 263 * 4, 2, 255.99),
                                  OIIO::TypeDesc::UINT8);
    fr::TexelImageCache whole, bounded(kMiB);
    for (const char* f : {"/f.exr", "/b.png"}) {
        const auto w = whole.get(dir + f, {}, "/x");
        const auto p = bounded.get(dir + f, {}, "/x");
        expect_same_levels(*w, *p);
        EXPECT_EQ(p->width, w->width);
        EXPECT_EQ(p->alpha_channel, w->alpha_channel);
    }
    const fr::TextureMemoryStats s = bounded.stats();
    EXPECT_EQ(s.paged_images, 2u);
    EXPECT_EQ(s.whole_bytes, 0u);
    EXPECT_EQ(s.tile_capacity, kMiB);
    EXPECT_LE(s.peak_bytes(), kMiB);
    EXPECT_GT(s.evictions, 0u);  // the levels need more than 1 MiB: tiles were evicted
    std::filesystem::remove_all(dir);
}

// A scene whose textures are six times the bound renders the same image bit for bit as with
// the default bound, at 1 and 2 threads, with the resident texels (whole + the tile cache's
// peak) within the bound. Six 512^2 RGB PNGs (4 MiB of float texels each with their MIP levels)
// on a floor seen at a grazing angle (every MIP level used) and on a wall, mipmap, linear and
// closest filters, one texture in mirror wrap.
TEST(TextureCache, RenderIsBitIdenticalWithinTheBound) {
    const std::string dir = fr::testing::test_temp_dir("facet_texcache");
    for (int i = 0; i < 6; ++i)
        fr::testing::write_test_image(dir + "/t" + std::to_string(i) + ".png", 512, 512, 3,
                                      noise<std::uint8_t>(512 * 512 * 3, 10 + i, 255.99),
                                      OIIO::TypeDesc::UINT8);
    std::string shapes;
    const char* filters[] = {"mipmap", "mipmap", "linear", "closest", "mipmap", "mipmap"};
    for (int i = 0; i < 6; ++i) {
        const double x0 = -3.0 + i;
        shapes += std::string(i ? "," : "") + R"({"type": "quad", "vertices": [[)" +
                  std::to_string(x0) + R"(, 0, 4], [)" + std::to_string(x0 + 1) + R"(, 0, 4], [)" +
                  std::to_string(x0 + 1) + R"(, 0, -30], [)" + std::to_string(x0) + R"(, 0, -30]],
                     "material": {"model": "lambert", "reflectance": {"texture": "t)" +
                  std::to_string(i) + R"(.png", "filter": ")" + filters[i] +
                  R"(", "uv_scale": [2, 8])" + (i == 5 ? R"(, "wrap": "mirror")" : "") + R"(}}})";
    }
    shapes += R"(, {"type": "quad", "vertices": [[-3, 0, -6], [3, 0, -6], [3, 3, -6], [-3, 3, -6]],
                    "material": {"model": "lambert", "reflectance": {"texture": "t4.png"}}})";
    const std::string json =
        R"({"format": "facet-scene", "version": 1,
            "camera": {"position": [0, 0.6, 4], "look_at": [0, 0.3, 0], "fov": 60,
                       "width": 96, "height": 64},
            "shapes": [)" +
        shapes + R"(], "lights": [{"type": "environment", "radiance": 1}],
            "render": {"max_depth": 2}})";
    auto render = [&](std::uint64_t limit, int threads, fr::TextureMemoryStats* stats) {
        fr::SceneLimits limits;
        limits.texture_memory = limit;
        const fr::Scene scene = fr::load_scene_from_string(json, "cache.json", dir, limits);
        fr::Image im = fr::render(scene, fr::testing::test_options("path", 2, 7, threads));
        if (stats) *stats = scene.texture_memory();
        return im;
    };
    fr::TextureMemoryStats whole, s1, s2;
    const fr::Image ref = render(fr::kDefaultTextureMemory, 1, &whole);
    EXPECT_EQ(whole.paged_images, 0u);
    EXPECT_EQ(whole.whole_bytes, 6 * fr::pyramid_bytes(512, 512, 3));
    const std::uint64_t limit = 4 * kMiB;
    ASSERT_GT(whole.whole_bytes, 5 * limit);
    const fr::Image one = render(limit, 1, &s1), two = render(limit, 2, &s2);
    ASSERT_EQ(one.pixels().size(), ref.pixels().size());
    EXPECT_EQ(std::memcmp(one.pixels().data(), ref.pixels().data(),
                          ref.pixels().size() * sizeof(facet::Rgb)),
              0);
    EXPECT_EQ(std::memcmp(two.pixels().data(), ref.pixels().data(),
                          ref.pixels().size() * sizeof(facet::Rgb)),
              0);
    for (const fr::TextureMemoryStats& s : {s1, s2}) {
        EXPECT_GE(s.paged_images, 5u);
        EXPECT_LE(s.peak_bytes(), limit);
        EXPECT_GT(s.evictions, 0u);
        EXPECT_GT(s.hits, s.misses);  // filtering reads neighbouring texels of one tile
    }
    std::filesystem::remove_all(dir);
}

// Four threads read random texels of two paged images through one small cache at once:
// every value is the whole image's, and the resident tiles never pass the capacity (run under
// ASan + UBSan too, where a use of an evicted tile would be reported).
TEST(TextureCache, ConcurrentLookupsAreExactAndBounded) {
    const std::string dir = fr::testing::test_temp_dir("facet_texcache");
    fr::testing::write_test_image(dir + "/a.exr", 700, 300, 1, noise<float>(700 * 300, 3, 1.0),
                                  OIIO::TypeDesc::FLOAT);
    fr::testing::write_test_image(dir + "/b.exr", 300, 700, 4, noise<float>(300 * 700 * 4, 4, 1.0),
                                  OIIO::TypeDesc::FLOAT);
    fr::TexelImageCache whole, bounded(kMiB);
    const std::vector<std::string> files{dir + "/a.exr", dir + "/b.exr"};
    std::vector<std::shared_ptr<const fr::TexelImage>> w, p;
    for (const auto& f : files) {
        w.push_back(whole.get(f, {}, "/x"));
        p.push_back(bounded.get(f, {}, "/x"));
        ASSERT_TRUE(p.back()->paged);
    }
    std::vector<std::size_t> wrong(4, 0);
    std::vector<std::thread> threads;
    const int n = 20000 / (std::getenv("FACET_STRESS_SCALE") ? 4 : 1);
    for (int k = 0; k < 4; ++k)
        threads.emplace_back([&, k] {
            std::mt19937 rng(std::uint32_t(100 + k));
            float t[4];
            for (int i = 0; i < n; ++i) {
                const std::size_t im = rng() % 2;
                const fr::TexelImage& whole_im = *w[im];
                const int x = int(rng() % std::uint32_t(whole_im.width));
                const int y = int(rng() % std::uint32_t(whole_im.height));
                p[im]->paged->texel(0, x, y, t);
                const int c = whole_im.channels;
                for (int ch = 0; ch < c; ++ch)
                    wrong[std::size_t(k)] += t[ch] != whole_im.at(x, y, ch);
            }
        });
    for (auto& t : threads) t.join();
    for (std::size_t k = 0; k < wrong.size(); ++k) EXPECT_EQ(wrong[k], 0u) << "thread " << k;
    const fr::TextureMemoryStats s = bounded.stats();
    EXPECT_LE(s.tile_peak, s.tile_capacity);
    EXPECT_LE(s.peak_bytes(), kMiB);
    EXPECT_GT(s.evictions, 0u);
    EXPECT_EQ(s.hits + s.misses, 4u * std::uint64_t(n));  // every look-up counted once
    std::filesystem::remove_all(dir);
}

// Images are whole while they fit limit - reserve (reserve = min(limit / 4, 64 MiB)), in load
// order; the first that does not, and every later one, is paged.
TEST(TextureCache, WholeUntilTheFirstImageThatDoesNotFit) {
    const std::string dir = fr::testing::test_temp_dir("facet_texcache");
    // 256^2 grey float: 256 KiB + its levels (341.3 KiB); three fit 1 MiB - 256 KiB = 768 KiB
    // twice only.
    for (const char* f : {"/a.exr", "/b.exr", "/c.exr", "/d.exr"})
        fr::testing::write_test_image(dir + f, 256, 256, 1, noise<float>(256 * 256, 5, 1.0),
                                      OIIO::TypeDesc::FLOAT);
    fr::TexelImageCache cache(kMiB);
    EXPECT_FALSE(cache.get(dir + "/a.exr", {}, "/x")->paged);
    EXPECT_FALSE(cache.get(dir + "/b.exr", {}, "/x")->paged);
    EXPECT_TRUE(cache.get(dir + "/c.exr", {}, "/x")->paged);
    EXPECT_TRUE(cache.get(dir + "/d.exr", {}, "/x")->paged);
    const fr::TextureMemoryStats s = cache.stats();
    EXPECT_EQ(s.whole_bytes, 2 * fr::pyramid_bytes(256, 256, 1));
    EXPECT_EQ(s.tile_capacity, kMiB - s.whole_bytes);
    std::filesystem::remove_all(dir);
}

// A bound below 1 MiB is an error naming the bound (the CLI's checks are in test_render_cli).
TEST(TextureCache, BoundBelowOneMebibyteIsAnError) {
    fr::SceneLimits limits;
    limits.texture_memory = kMiB - 1;
    try {
        fr::load_scene_from_string(
            R"({"format": "facet-scene", "version": 1,
                "camera": {"position": [0, 0, 3], "look_at": [0, 0, 0], "fov": 40, "width": 4, "height": 4},
                "shapes": [{"type": "sphere", "center": [0, 0, 0], "radius": 1}],
                "lights": [{"type": "environment", "radiance": 1}]})",
            "mem.json", ".", limits);
        ADD_FAILURE() << "no error";
    } catch (const fr::SceneError& e) {
        EXPECT_NE(std::string(e.what()).find("below the smallest, 1 MiB"), std::string::npos)
            << e.what();
    }
}
