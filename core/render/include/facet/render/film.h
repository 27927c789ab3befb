// The film: per-pixel sums of radiance samples, resolved to an Image by a box filter.
//
// Conventions: one double-precision RGB sum per pixel, row-major like Image. Each pixel is
// written only by the tile that owns it, so no synchronisation is needed and the sums do not
// depend on the thread count or the tile order. The image is sum / samples per pixel.
#pragma once

#include <vector>

#include "facet/render/image.h"
#include "facet/types.h"

namespace facet::render {

class Film {
  public:
    Film(int width, int height)
        : m_width(width), m_height(height), m_sums(std::size_t(width) * std::size_t(height)) {}

    int width() const { return m_width; }
    int height() const { return m_height; }
    DVec3* sums() { return m_sums.data(); }
    const std::vector<DVec3>& sum_values() const { return m_sums; }

    // Mean radiance per pixel after `samples_per_pixel` samples (black when 0).
    Image resolve(int samples_per_pixel) const {
        Image img(m_width, m_height);
        const double inv = samples_per_pixel > 0 ? 1.0 / double(samples_per_pixel) : 0.0;
        for (std::size_t i = 0; i < m_sums.size(); ++i) img.pixels()[i] = Rgb(m_sums[i] * inv);
        return img;
    }

  private:
    int m_width, m_height;
    std::vector<DVec3> m_sums;
};

}  // namespace facet::render
