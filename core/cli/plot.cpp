#include "plot.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <stb/stb_easy_font.h>
#include <stb/stb_image_write.h>

namespace facet::cli {

Canvas::Canvas(int width, int height, Color8 bg)
    : m_width(width), m_height(height), m_rgb(size_t(width) * height * 3) {
    for (size_t i = 0; i < m_rgb.size(); i += 3)
        m_rgb[i] = bg.r, m_rgb[i + 1] = bg.g, m_rgb[i + 2] = bg.b;
}

void Canvas::blend(int x, int y, Color8 c, float a) {
    if (x < 0 || y < 0 || x >= m_width || y >= m_height || !(a > 0.f)) return;
    a = std::min(a, 1.f);
    std::uint8_t* p = &m_rgb[(size_t(y) * m_width + x) * 3];
    p[0] = std::uint8_t(std::lround(p[0] * (1.f - a) + c.r * a));
    p[1] = std::uint8_t(std::lround(p[1] * (1.f - a) + c.g * a));
    p[2] = std::uint8_t(std::lround(p[2] * (1.f - a) + c.b * a));
}

void Canvas::line(float x0, float y0, float x1, float y1, Color8 c, float thickness) {
    if (!std::isfinite(x0 + y0 + x1 + y1)) return;
    float half = thickness / 2.f;
    int xmin = int(std::floor(std::min(x0, x1) - half - 1)),
        xmax = int(std::ceil(std::max(x0, x1) + half + 1));
    int ymin = int(std::floor(std::min(y0, y1) - half - 1)),
        ymax = int(std::ceil(std::max(y0, y1) + half + 1));
    xmin = std::max(xmin, 0), ymin = std::max(ymin, 0);
    xmax = std::min(xmax, m_width - 1), ymax = std::min(ymax, m_height - 1);
    float dx = x1 - x0, dy = y1 - y0, len2 = dx * dx + dy * dy;
    for (int y = ymin; y <= ymax; ++y)
        for (int x = xmin; x <= xmax; ++x) {
            float px = x + 0.5f - x0, py = y + 0.5f - y0;
            float t = len2 > 0.f ? std::clamp((px * dx + py * dy) / len2, 0.f, 1.f) : 0.f;
            float d = std::hypot(px - t * dx, py - t * dy);
            blend(x, y, c, half + 0.5f - d);  // coverage ramp over one pixel at the edge
        }
}

void Canvas::dashed_line(float x0, float y0, float x1, float y1, Color8 c, float dash) {
    float len = std::hypot(x1 - x0, y1 - y0);
    int n = std::max(1, int(len / dash));
    for (int i = 0; i < n; i += 2) {
        float a = float(i) / n, b = float(std::min(i + 1, n)) / n;
        line(x0 + (x1 - x0) * a, y0 + (y1 - y0) * a, x0 + (x1 - x0) * b, y0 + (y1 - y0) * b, c,
             1.f);
    }
}

void Canvas::text(float x, float y, const std::string& s, Color8 c, float scale) {
    // stb_easy_font emits quads of 4 vertices (x, y, z, rgba) = 16 bytes each, in font units.
    static thread_local std::vector<char> buffer(64 * 1024);
    std::string copy = s;
    int quads =
        stb_easy_font_print(0.f, 0.f, copy.data(), nullptr, buffer.data(), int(buffer.size()));
    for (int q = 0; q < quads; ++q) {
        const float* v = reinterpret_cast<const float*>(buffer.data() + q * 64);
        float qx0 = v[0], qy0 = v[1], qx1 = v[8], qy1 = v[9];  // vertices 0 and 2
        for (int py = int(y + qy0 * scale); py < int(y + qy1 * scale); ++py)
            for (int px = int(x + qx0 * scale); px < int(x + qx1 * scale); ++px)
                blend(px, py, c, 1.f);
    }
}

void Canvas::write_png(const std::string& path) const {
    if (!stbi_write_png(path.c_str(), m_width, m_height, 3, m_rgb.data(), m_width * 3))
        throw std::runtime_error(path + ": cannot write PNG");
}

}  // namespace facet::cli
