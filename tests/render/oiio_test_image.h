// Test images written with OpenImageIO directly (test_texel_image.cpp, test_textures.cpp), so
// that the texels a test expects are known independently of the reader under test.
#pragma once

#include <gtest/gtest.h>

#include <OpenImageIO/imageio.h>

#include <string>
#include <vector>

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

}  // namespace facet::render::testing
