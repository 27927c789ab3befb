// The environment map's lookup and importance sampling (conventions in environment_map.h).
#include "facet/render/environment_map.h"

#include <algorithm>
#include <cmath>

#include "facet/render/texel_image.h"

namespace facet::render {

namespace {

// Mean over a texel's cell of the bilinear (tent) weight of the texel one step before, the
// texel itself and the one after, per axis: the tent of texel i, centred at i + 0.5, covers
// [i, i + 1] with 1 - |t| and half of each neighbour's cell, which gives 1/8, 3/4, 1/8.
constexpr double kCellTent[3] = {0.125, 0.75, 0.125};

// Index of the interval of u in a cdf (the first i with u < cdf[i], the last one at most),
// and u's position within it, in [0, 1).
std::size_t sample_cdf(const float* cdf, std::size_t n, float u, float& offset) {
    const std::size_t i = std::min(std::size_t(std::upper_bound(cdf, cdf + n, u) - cdf), n - 1);
    const float lo = i == 0 ? 0.f : cdf[i - 1];
    const float w = cdf[i] - lo;
    offset = w > 0.f ? std::clamp((u - lo) / w, 0.f, kOneMinusEpsilon) : 0.5f;
    return i;
}

}  // namespace

EnvironmentMap::EnvironmentMap(const TexelImage& image, const Rgb& multiplier,
                               const glm::mat3& frame)
    : m_width(image.width),
      m_height(image.height),
      m_frame(frame),
      m_inverse(glm::transpose(frame)) {
    const int W = m_width, H = m_height;
    const std::size_t n = std::size_t(W) * std::size_t(H);
    // RGB per texel: 1 channel (grey) and 2 (grey + alpha) are grey; alpha is ignored.
    m_texels.resize(n);
    const int colour_channels = image.channels >= 3 ? 3 : 1;
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            Rgb c;
            for (int k = 0; k < 3; ++k) c[k] = image.at(x, y, colour_channels == 3 ? k : 0);
            m_texels[std::size_t(y) * W + x] = c * multiplier;
        }

    // Cell weights (conventions): cell mean of the bilinear luminance times sin(theta) at the
    // row's centre; the mean radiance by the rows' exact solid angles.
    std::vector<double> w(n);
    std::vector<double> row_sum(std::size_t(H), 0.0);
    glm::dvec3 radiant(0.0);
    for (int y = 0; y < H; ++y) {
        const double theta0 = kPiD * y / H, theta1 = kPiD * (y + 1) / H;
        const double sin_c = std::sin(kPiD * (y + 0.5) / H);
        const double cell_solid_angle = 2.0 * kPiD / W * (std::cos(theta0) - std::cos(theta1));
        for (int x = 0; x < W; ++x) {
            glm::dvec3 mean(0.0);
            for (int j = -1; j <= 1; ++j) {
                const int yy = std::clamp(y + j, 0, H - 1);
                for (int i = -1; i <= 1; ++i) {
                    const int xx = ((x + i) % W + W) % W;
                    mean += kCellTent[j + 1] * kCellTent[i + 1] * glm::dvec3(texel(xx, yy));
                }
            }
            radiant += mean * cell_solid_angle;
            const double lum = 0.2126 * mean.x + 0.7152 * mean.y + 0.0722 * mean.z;
            w[std::size_t(y) * W + x] = lum * sin_c;
            row_sum[std::size_t(y)] += lum * sin_c;
        }
    }
    m_mean = Rgb(radiant / (4.0 * kPiD));

    double total = 0.0;
    for (double r : row_sum) total += r;
    m_black = !(total > 0.0) || !std::isfinite(total);
    if (m_black) return;
    m_row_cdf.resize(std::size_t(H));
    m_col_cdf.resize(n);
    m_cell_pdf.resize(n);
    double run_rows = 0.0;
    for (int y = 0; y < H; ++y) {
        run_rows += row_sum[std::size_t(y)];
        m_row_cdf[std::size_t(y)] = float(run_rows / total);
        const double rs = row_sum[std::size_t(y)];
        double run = 0.0;
        for (int x = 0; x < W; ++x) {
            const std::size_t i = std::size_t(y) * W + x;
            run += w[i];
            // A row of zero weight is never chosen; its cdf is uniform only to stay monotone.
            m_col_cdf[i] = rs > 0.0 ? float(run / rs) : float(x + 1) / float(W);
            m_cell_pdf[i] = float(double(W) * double(H) * w[i] / total);
        }
        m_col_cdf[std::size_t(y) * W + W - 1] = 1.f;
    }
    // Exactly 1 at the end so that every u < 1 selects a row (trailing zero rows keep width 0).
    const float last = m_row_cdf[std::size_t(H - 1)];
    for (int y = H; y-- > 0 && m_row_cdf[std::size_t(y)] == last;) m_row_cdf[std::size_t(y)] = 1.f;
}

Vec2 EnvironmentMap::direction_to_uv(const Vec3& d) const {
    const Vec3 l = m_inverse * d;
    // atan2 for theta too: acos(z) loses half its digits near the poles.
    const float theta = std::atan2(std::sqrt(l.x * l.x + l.y * l.y), l.z);
    const float u = 0.5f - std::atan2(l.y, l.x) * kInv2Pi, v = theta * kInvPi;
    // Clamped into [0, 1] with NaN (a NaN direction) to 0: the lookups convert to int.
    auto unit = [](float t) { return t > 0.f ? (t < 1.f ? t : 1.f) : 0.f; };
    return {unit(u), unit(v)};
}

Vec3 EnvironmentMap::uv_to_direction(Vec2 uv) const {
    const float phi = kPi - 2.f * kPi * uv.x;
    const float theta = kPi * uv.y;
    const float s = std::sin(theta);
    return m_frame * Vec3(s * std::cos(phi), s * std::sin(phi), std::cos(theta));
}

Rgb EnvironmentMap::lookup(Vec2 uv) const {
    const float fx = uv.x * float(m_width) - 0.5f, fy = uv.y * float(m_height) - 0.5f;
    const float x0f = std::floor(fx), y0f = std::floor(fy);
    const float tx = fx - x0f, ty = fy - y0f;
    int x0 = int(x0f) % m_width;
    if (x0 < 0) x0 += m_width;
    const int x1 = x0 + 1 == m_width ? 0 : x0 + 1;
    const int y0 = std::clamp(int(y0f), 0, m_height - 1);
    const int y1 = std::clamp(int(y0f) + 1, 0, m_height - 1);
    return (1.f - ty) * ((1.f - tx) * texel(x0, y0) + tx * texel(x1, y0)) +
           ty * ((1.f - tx) * texel(x0, y1) + tx * texel(x1, y1));
}

Rgb EnvironmentMap::eval(const Vec3& d) const {
    return lookup(direction_to_uv(d));
}

float EnvironmentMap::cell_pdf(int x, int y) const {
    return m_cell_pdf[std::size_t(y) * m_width + x];
}

float EnvironmentMap::pdf(const Vec3& d) const {
    if (m_black) return 0.f;
    const Vec2 uv = direction_to_uv(d);
    const float sin_theta = std::sin(kPi * uv.y);
    if (!(sin_theta > 0.f)) return 0.f;
    const int x = std::min(int(uv.x * float(m_width)), m_width - 1);
    const int y = std::min(int(uv.y * float(m_height)), m_height - 1);
    return cell_pdf(x, y) / (2.f * kPi * kPi * sin_theta);
}

EnvironmentMap::Sample EnvironmentMap::sample(Vec2 u) const {
    Sample s;
    if (m_black) return s;
    float dv = 0.f, du = 0.f;
    const std::size_t W = std::size_t(m_width);
    const int y = int(sample_cdf(m_row_cdf.data(), m_row_cdf.size(), u.y, dv));
    const int x = int(sample_cdf(&m_col_cdf[std::size_t(y) * W], W, u.x, du));
    const Vec2 uv((float(x) + du) / float(m_width), (float(y) + dv) / float(m_height));
    const float sin_theta = std::sin(kPi * uv.y);
    if (!(sin_theta > 0.f)) return s;
    s.wi = uv_to_direction(uv);
    s.pdf = cell_pdf(x, y) / (2.f * kPi * kPi * sin_theta);
    s.radiance = lookup(uv);
    return s;
}

}  // namespace facet::render
