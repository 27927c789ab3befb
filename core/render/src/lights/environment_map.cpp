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

namespace facet::render {

namespace {

// Mean over a texel's cell of the bilinear (tent) weight of the texel one step before, the
// texel itself and the one after, per axis: the tent of texel i, centred at i + 0.5, covers
// [i, i + 1] with 1 - |t| and half of each neighbour's cell, which gives 1/8, 3/4, 1/8.
constexpr double kCellTent[3] = {0.125, 0.75, 0.125};

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
                    const int xx = ((x + i) % W + W) % W;
                    mean += kCellTent[j + 1] * kCellTent[i + 1] * glm::dvec3(texel(xx, yy));
                }
            }
            radiant += mean * cell_solid_angle;
            lum[std::size_t(y) * W + x] = 0.2126 * mean.x + 0.7152 * mean.y + 0.0722 * mean.z;
        }
    }
    m_mean = Rgb(radiant / (4.0 * kPiD));
    m_distribution = LatLongDistribution(W, H, lum);
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

float EnvironmentMap::pdf(const Vec3& d) const {
    return m_distribution.pdf(direction_to_uv(d));
}

EnvironmentMap::Sample EnvironmentMap::sample(Vec2 u) const {
    Sample s;
    const LatLongDistribution::Sample t = m_distribution.sample(u);
    if (!(t.pdf > 0.f)) return s;
    s.wi = uv_to_direction(t.uv);
    s.pdf = t.pdf;
    s.radiance = lookup(t.uv);
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
