// The latitude-longitude mapping and its piecewise-constant density (conventions in latlong.h).
#include "facet/latlong.h"

#include "facet/cdf_search.h"

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace facet {

namespace {

// Index of the interval of u in a cdf with its cutpoint guide (facet/cdf_search.h), and u's
// position within it, in [0, 1).
std::size_t sample_cdf(const float* cdf, const std::uint32_t* guide, std::size_t n, float u,
                       float& offset) {
    const std::size_t i = find_cdf_interval(cdf, guide, n, u);
    const float lo = i == 0 ? 0.f : cdf[i - 1];
    const float w = cdf[i] - lo;
    offset = w > 0.f ? std::clamp((u - lo) / w, 0.f, kOneMinusEpsilon) : 0.5f;
    return i;
}

}  // namespace

float atan2_approx(float y, float x) {
    // atan on [0, 1] by Abramowitz & Stegun 4.4.49 (|error| <= 2e-8 rad), then the octant:
    // atan2 = pi/2 - atan(1/a) above the diagonal, pi - . for x < 0, the sign of y (so that
    // atan2(-0, x < 0) = -pi as std::atan2 gives). One division and no branch the compiler
    // cannot turn into selects; std::atan2 costs about three times as many instructions.
    const float ax = std::abs(x), ay = std::abs(y);
    const float mx = std::max(ax, ay), mn = std::min(ax, ay);
    const float a = mx > 0.f ? mn / mx : 0.f;  // atan2(0, 0) = 0, as std::atan2
    const float s = a * a;
    float p = 0.0028662257f;
    p = p * s - 0.0161657367f;
    p = p * s + 0.0429096138f;
    p = p * s - 0.0752896400f;
    p = p * s + 0.1065626393f;
    p = p * s - 0.1420889944f;
    p = p * s + 0.1999355085f;
    p = p * s - 0.3333314528f;
    float r = a + a * s * p;
    if (ay > ax) r = 0.5f * kPi - r;
    if (x < 0.f) r = kPi - r;
    return std::isnan(x) || std::isnan(y) ? x + y : std::copysign(r, y);
}

Vec2 latlong_uv(const Vec3& l, float& sin_theta) {
    // atan2 for theta too: acos(z) loses half its digits near the poles.
    sin_theta = std::sqrt(l.x * l.x + l.y * l.y);
    const float theta = atan2_approx(sin_theta, l.z);
    const float u = 0.5f - atan2_approx(l.y, l.x) * kInv2Pi, v = theta * kInvPi;
    // Clamped into [0, 1] with NaN (a NaN direction) to 0: the lookups convert to int.
    auto unit = [](float t) { return t > 0.f ? (t < 1.f ? t : 1.f) : 0.f; };
    return {unit(u), unit(v)};
}

Vec2 latlong_uv(const Vec3& l) {
    float sin_theta;
    return latlong_uv(l, sin_theta);
}

Vec3 latlong_direction(Vec2 uv, float& sin_theta) {
    const float phi = kPi - 2.f * kPi * uv.x;
    const float theta = kPi * uv.y;
    sin_theta = std::sin(theta);
    return Vec3(sin_theta * std::cos(phi), sin_theta * std::sin(phi), std::cos(theta));
}

Vec3 latlong_direction(Vec2 uv) {
    float sin_theta;
    return latlong_direction(uv, sin_theta);
}

LatLongDistribution::LatLongDistribution(int width, int height,
                                         const std::vector<double>& luminance)
    : m_width(width), m_height(height) {
    const int W = width, H = height;
    const std::size_t n = std::size_t(W) * std::size_t(H);
    if (W <= 0 || H <= 0 || luminance.size() != n) return;
    std::vector<double> w(n);
    std::vector<double> row_sum(std::size_t(H), 0.0);
    for (int y = 0; y < H; ++y) {
        const double sin_c = std::sin(kPiD * (y + 0.5) / H);
        for (int x = 0; x < W; ++x) {
            const std::size_t i = std::size_t(y) * W + x;
            w[i] = luminance[i] * sin_c;
            row_sum[std::size_t(y)] += w[i];
        }
    }
    double total = 0.0;
    for (double r : row_sum) total += r;
    m_black = !(total > 0.0) || !std::isfinite(total);
    if (m_black) return;
    m_scale = double(W) * double(H) / total;
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
    m_row_guide.resize(std::size_t(H));
    m_col_guide.resize(n);
    build_cdf_guide(m_row_cdf.data(), std::size_t(H), m_row_guide.data());
    for (int y = 0; y < H; ++y)
        build_cdf_guide(&m_col_cdf[std::size_t(y) * W], std::size_t(W),
                        &m_col_guide[std::size_t(y) * W]);
}

float LatLongDistribution::pdf(Vec2 uv) const {
    if (m_black) return 0.f;
    const float sin_theta = std::sin(kPi * uv.y);
    if (!(sin_theta > 0.f)) return 0.f;
    const int x = std::min(int(uv.x * float(m_width)), m_width - 1);
    const int y = std::min(int(uv.y * float(m_height)), m_height - 1);
    return cell_pdf(x, y) / (2.f * kPi * kPi * sin_theta);
}

LatLongDistribution::Cell LatLongDistribution::sample_cell(Vec2 u) const {
    Cell c;
    const std::size_t W = std::size_t(m_width);
    c.y = int(sample_cdf(m_row_cdf.data(), m_row_guide.data(), m_row_cdf.size(), u.y, c.offset.y));
    const std::size_t row = std::size_t(c.y) * W;
    c.x = int(sample_cdf(&m_col_cdf[row], &m_col_guide[row], W, u.x, c.offset.x));
    return c;
}

LatLongDistribution::Sample LatLongDistribution::sample(Vec2 u) const {
    Sample s;
    if (m_black) return s;
    const Cell c = sample_cell(u);
    s.uv = Vec2((float(c.x) + c.offset.x) / float(m_width),
                (float(c.y) + c.offset.y) / float(m_height));
    const float sin_theta = std::sin(kPi * s.uv.y);
    if (!(sin_theta > 0.f)) return s;
    s.pdf = cell_pdf(c.x, c.y) / (2.f * kPi * kPi * sin_theta);
    return s;
}

}  // namespace facet
