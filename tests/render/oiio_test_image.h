// Test images written with OpenImageIO directly (test_texel_image.cpp, test_textures.cpp,
// test_mipmap.cpp), so that the texels a test expects are known independently of the reader
// under test; and the texture tests' other shared helpers.
#pragma once

#include <gtest/gtest.h>

#include <OpenImageIO/imageio.h>

#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include <unistd.h>

#include "facet/render/scene.h"
#include "facet/testsupport/render_test_util.h"

namespace facet::render::testing {

// Writes w x h pixels of c interleaved channels (row 0 first: the top of the picture); a
// 4-channel image marks channel 3 as alpha.
template <typename T>
void write_test_image(const std::string& path, int w, int h, int c, const std::vector<T>& data,
                      OIIO::TypeDesc type) {
    auto out = OIIO::ImageOutput::create(path);
    ASSERT_TRUE(out) << OIIO::geterror();
    OIIO::ImageSpec spec(w, h, c, type);
    if (c == 4) spec.alpha_channel = 3;
    ASSERT_TRUE(out->open(path, spec));
    ASSERT_TRUE(out->write_image(type, data.data()));
    out->close();
}

// A per-process temporary directory for test images, "<tmp>/<prefix>_<pid>".
inline std::string test_temp_dir(const std::string& prefix) {
    const auto d =
        std::filesystem::temp_directory_path() / (prefix + "_" + std::to_string(::getpid()));
    std::filesystem::create_directories(d);
    return d.string();
}

// An 8 x 8 float image of c channels, texels uniform in [lo, 1] (seeded: reproducible),
// written as <dir>/<name>.exr; returns its path.
inline std::string random_test_image(const std::string& dir, const std::string& name, int c,
                                     float lo, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(lo, 1.f);
    std::vector<float> px(std::size_t(8 * 8 * c));
    for (float& x : px) x = u(rng);
    const std::string path = dir + "/" + name + ".exr";
    write_test_image(path, 8, 8, c, px, OIIO::TypeDesc::FLOAT);
    return path;
}

// The closest hit along ray (o, d) in a scene whose only shape is `shape` with the checker
// material "c" (so that hits compute uv and its derivatives).
inline SurfaceHit checker_scene_hit(const std::string& shape, const Vec3& o, const Vec3& d) {
    const Scene scene = scene_from(
        R"("camera": {"position": [0, 0, 10], "look_at": [0, 0, 0], "fov": 40, "width": 4, "height": 4},
           "materials": {"c": {"model": "lambert",
                               "reflectance": {"checker": {"colors": [0.2, 0.8]}}}},
           "shapes": [)" +
        shape + R"(], "lights": [{"type": "environment", "radiance": 1}])");
    SurfaceHit hit;
    EXPECT_TRUE(scene.intersect(Ray{o, glm::normalize(d), kInfinity}, hit)) << shape;
    EXPECT_GE(hit.textured, 0);
    return hit;
}

}  // namespace facet::render::testing
