// A minimal raster canvas for `facet brdf plot`: lines, dots and text (stb_easy_font) into an
// 8-bit RGB buffer, written as PNG with stb_image_write.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace facet::cli {

struct Color8 {
    std::uint8_t r, g, b;
};

class Canvas {
  public:
    Canvas(int width, int height, Color8 background);
    // Anti-aliased-by-coverage thick line (distance-to-segment test over the bounding box).
    void line(float x0, float y0, float x1, float y1, Color8 c, float thickness = 1.5f);
    void dashed_line(float x0, float y0, float x1, float y1, Color8 c, float dash = 6.f);
    // Text with its top-left corner at (x, y); scale 2 gives ~14 px tall letters.
    void text(float x, float y, const std::string& s, Color8 c, float scale = 2.f);
    void write_png(const std::string& path) const;  // throws std::runtime_error
    int width() const { return m_width; }
    int height() const { return m_height; }

  private:
    void blend(int x, int y, Color8 c, float alpha);
    int m_width, m_height;
    std::vector<std::uint8_t> m_rgb;
};

}  // namespace facet::cli
