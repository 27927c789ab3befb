// The environment map's lookup and importance sampling (conventions in environment_map.h), and
// its light type: sample_li and pdf_li use the map's importance density over the whole sphere
// (ctx is ignored), le_escape looks the map up, emission() is its mean radiance. Its power for
// the light choice is the mean radiance's, 4 pi^2 R^2 L (lights/environment.cpp).
#include "facet/render/environment_map.h"

#include <algorithm>
#include <cmath>

#include "facet/render/light.h"
#include "facet/render/scene.h"
#include "facet/render/texel_image.h"
#include "facet/sampling.h"

namespace facet::render {

namespace {

// Mean over a texel's cell of the bilinear (tent) weight of the texel one step before, the
// texel itself and the one after, per axis: the tent of texel i, centred at i + 0.5, covers
// [i, i + 1] with 1 - |t| and half of each neighbour's cell, which gives 1/8, 3/4, 1/8.
constexpr double kCellTent[3] = {0.125, 0.75, 0.125};

// Rec. 709 luminance, the importance density's measure of a colour (environment_map.h).
inline float luminance(const Rgb& c) {
    return 0.2126f * c.r + 0.7152f * c.g + 0.0722f * c.b;
}

// x in [0, 1) with density proportional to (1 - x) a + x b (a, b >= 0) from u in [0, 1): the
// inverse of its cdf, written so that it neither cancels nor divides by a - b (pbrt-v4's
// SampleLinear); u itself when both ends are 0.
inline float sample_linear(float u, float a, float b) {
    if (!(a + b > 0.f)) return u;
    if (u == 0.f && a == 0.f) return 0.f;
    const float x = u * (a + b) / (a + std::sqrt((1.f - u) * a * a + u * b * b));
    return std::min(x, kOneMinusEpsilon);
}

// Which of two parts of weights w0, w1 (not both 0) u in [0, 1) chooses, u rescaled to [0, 1)
// within the chosen part (so that it stays uniform and stratified).
inline int choose_half(float& u, float w0, float w1) {
    const float p0 = w0 / (w0 + w1);
    if (u < p0) {
        u = std::min(u / p0, kOneMinusEpsilon);
        return 0;
    }
    u = std::min((u - p0) / (1.f - p0), kOneMinusEpsilon);
    return 1;
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
    m_luminance.resize(n);
    for (std::size_t i = 0; i < n; ++i) m_luminance[i] = luminance(m_texels[i]);

    // Cell weights (conventions): cell mean of the bilinear luminance (the sin(theta) Jacobian
    // is the distribution's, latlong.h); the mean radiance by the rows' exact solid angles.
    std::vector<double> lum(n);
    glm::dvec3 radiant(0.0);
    for (int y = 0; y < H; ++y) {
        const double theta0 = kPiD * y / H, theta1 = kPiD * (y + 1) / H;
        const double cell_solid_angle = 2.0 * kPiD / W * (std::cos(theta0) - std::cos(theta1));
        for (int x = 0; x < W; ++x) {
            glm::dvec3 mean(0.0);
            for (int j = -1; j <= 1; ++j) {
                const int yy = std::clamp(y + j, 0, H - 1);
                for (int i = -1; i <= 1; ++i) {
                    const int xx = x + i < 0 ? x + i + W : x + i >= W ? x + i - W : x + i;
                    mean += kCellTent[j + 1] * kCellTent[i + 1] * glm::dvec3(texel(xx, yy));
                }
            }
            radiant += mean * cell_solid_angle;
            lum[std::size_t(y) * W + x] = 0.2126 * mean.x + 0.7152 * mean.y + 0.0722 * mean.z;
        }
    }
    m_mean = Rgb(radiant / (4.0 * kPiD));
    m_distribution = LatLongDistribution(W, H, lum);
    // p(u, v) = Y(u, v) sin(theta_y) W H / sum w (conventions): the factor of each row.
    m_row_factor.resize(std::size_t(H));
    for (int y = 0; y < H; ++y)
        m_row_factor[std::size_t(y)] =
            float(std::sin(kPiD * (y + 0.5) / H) * m_distribution.scale());
}

float EnvironmentMap::pdf_at(Vec2 uv, const Rgb& radiance, float sin_theta) const {
    if (m_distribution.black()) return 0.f;
    if (!(sin_theta > 0.f)) return 0.f;
    const int y = std::min(int(uv.y * float(m_height)), m_height - 1);
    return luminance(radiance) * m_row_factor[std::size_t(y)] / (2.f * kPi * kPi * sin_theta);
}

Vec2 EnvironmentMap::direction_to_uv(const Vec3& d) const {
    return latlong_uv(m_inverse * d);
}

Vec3 EnvironmentMap::uv_to_direction(Vec2 uv) const {
    return m_frame * latlong_direction(uv);
}

Rgb EnvironmentMap::lookup(Vec2 uv) const {
    const float fx = uv.x * float(m_width) - 0.5f, fy = uv.y * float(m_height) - 0.5f;
    const float x0f = std::floor(fx), y0f = std::floor(fy);
    const float tx = fx - x0f, ty = fy - y0f;
    // uv.x in [0, 1] puts x0 in [-1, W - 1]: one step wraps it (no integer division).
    int x0 = std::min(int(x0f), m_width - 1);
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

float EnvironmentMap::pdf(const Vec3& d) const {
    float pdf;
    eval_pdf(d, pdf);
    return pdf;
}

Rgb EnvironmentMap::eval_pdf(const Vec3& d, float& pdf) const {
    float sin_theta;
    const Vec2 uv = latlong_uv(m_inverse * d, sin_theta);
    const Rgb radiance = lookup(uv);
    pdf = pdf_at(uv, radiance, sin_theta);
    return radiance;
}

EnvironmentMap::Sample EnvironmentMap::sample(Vec2 u) const {
    Sample s;
    if (m_distribution.black()) return s;
    // The cell by its mean luminance, then the point within it by the bilinear lookup's
    // luminance (conventions): the cell's 2 x 2 quadrants are each bilinear between the
    // luminances g at the cell's corners, edge midpoints and centre (the texel's own value
    // there; half-way between two texels on the cell's edges).
    const LatLongDistribution::Cell c = m_distribution.sample_cell(u);
    const int W = m_width, H = m_height;
    float t[3][3];  // texel luminances: rows y - 1 .. y + 1 (clamped), columns x - 1 .. x + 1
    for (int j = 0; j < 3; ++j) {
        const int yy = std::clamp(c.y + j - 1, 0, H - 1);
        for (int i = 0; i < 3; ++i) {
            int xx = c.x + i - 1;
            xx = xx < 0 ? xx + W : xx >= W ? xx - W : xx;
            t[j][i] = m_luminance[std::size_t(yy) * std::size_t(W) + std::size_t(xx)];
        }
    }
    float r[3][3], g[3][3];  // along x, then along y: edge, centre, edge
    for (int j = 0; j < 3; ++j) {
        r[j][0] = 0.5f * (t[j][0] + t[j][1]);
        r[j][1] = t[j][1];
        r[j][2] = 0.5f * (t[j][1] + t[j][2]);
    }
    for (int i = 0; i < 3; ++i) {
        g[0][i] = 0.5f * (r[0][i] + r[1][i]);
        g[1][i] = r[1][i];
        g[2][i] = 0.5f * (r[1][i] + r[2][i]);
    }
    // Quadrant weights (a bilinear patch's mean is its corners' mean; the 1/4 cancels).
    float q[2][2];
    for (int j = 0; j < 2; ++j)
        for (int i = 0; i < 2; ++i) q[j][i] = g[j][i] + g[j][i + 1] + g[j + 1][i] + g[j + 1][i + 1];
    // (A chosen cell has a positive mean; its float quadrant sums could underflow to 0 only
    // for texels near the smallest floats: no sample then.)
    if (!(q[0][0] + q[0][1] + q[1][0] + q[1][1] > 0.f)) return s;
    Vec2 o = c.offset;
    const int jv = choose_half(o.y, q[0][0] + q[0][1], q[1][0] + q[1][1]);
    const int iu = choose_half(o.x, q[jv][0], q[jv][1]);
    // Within the quadrant: v by the marginal (linear), then u given v (linear).
    const float f00 = g[jv][iu], f10 = g[jv][iu + 1], f01 = g[jv + 1][iu], f11 = g[jv + 1][iu + 1];
    const float fy = sample_linear(o.y, f00 + f10, f01 + f11);
    const float fx = sample_linear(o.x, f00 + fy * (f01 - f00), f10 + fy * (f11 - f10));
    const Vec2 uv(std::min((float(c.x) + 0.5f * (float(iu) + fx)) / float(W), 1.f),
                  std::min((float(c.y) + 0.5f * (float(jv) + fy)) / float(H), 1.f));
    float sin_theta;
    const Vec3 local = latlong_direction(uv, sin_theta);
    s.radiance = lookup(uv);
    s.pdf = pdf_at(uv, s.radiance, sin_theta);
    if (!(s.pdf > 0.f)) return s;
    s.wi = m_frame * local;
    return s;
}

std::optional<LightLiSample> EnvironmentMapLight::sample_li(const LightSampleContext&,
                                                            Vec2 u) const {
    const EnvironmentMap::Sample e = m->sample(u);
    if (!(e.pdf > 0.f)) return std::nullopt;
    LightLiSample s;
    s.wi = e.wi;
    s.pdf = e.pdf;
    s.li = e.radiance;
    s.dist = kInfinity;
    return s;
}

void EnvironmentMapLight::note(SceneFeatures& f) {
    f.has_environment = true;
}

Light Light::environment_map(std::shared_ptr<const EnvironmentMap> map) {
    const Rgb mean = map->mean_radiance();
    return make(EnvironmentMapLight{std::move(map)}, {.emission = mean});
}

}  // namespace facet::render
