// The POV-Ray bridge's sky sampling (see facet_pov_sky.h). The table and the lat-long mapping
// are the core's (facet/latlong.h); this file only evaluates the sky on the grid.
#include "facet_pov_sky.h"

#include <atomic>
#include <cmath>
#include <cstdint>
#include <memory>
#include <mutex>
#include <vector>

#include "facet/latlong.h"
#include "facet/render/sampler.h"  // header-only part: the renderer's Owen-scrambled Sobol
#include "facet/types.h"

namespace facet_pov {

class Sky {
  public:
    explicit Sky(int samples) : m_samples(samples) {}
    int samples() const { return m_samples; }

    bool prepare(int width, int height, const double frame[9], SkyRadianceFn fn, void* ctx) {
        std::call_once(m_once, [&] {
            build(width, height, frame, fn, ctx);
            m_built.store(true, std::memory_order_release);
        });
        return !m_table.black();
    }
    int state() const {
        if (!m_built.load(std::memory_order_acquire)) return -1;
        return m_table.black() ? 0 : 1;
    }
    bool sample(const double u[2], double wi[3], double& pdf) const {
        const facet::LatLongDistribution::Sample s =
            m_table.sample(facet::Vec2(float(u[0]), float(u[1])));
        if (!(s.pdf > 0.f)) return false;
        const glm::dvec3 d = m_frame * glm::dvec3(facet::latlong_direction(s.uv));
        wi[0] = d.x;
        wi[1] = d.y;
        wi[2] = d.z;
        pdf = s.pdf;
        return true;
    }
    double pdf(const double wi[3]) const {
        const glm::dvec3 l = glm::transpose(m_frame) * glm::dvec3(wi[0], wi[1], wi[2]);
        return m_table.pdf(facet::latlong_uv(facet::Vec3(l)));
    }

  private:
    void build(int W, int H, const double frame[9], SkyRadianceFn fn, void* ctx) {
        if (W < 1 || H < 1) return;
        for (int c = 0; c < 3; ++c)
            m_frame[c] = glm::dvec3(frame[3 * c], frame[3 * c + 1], frame[3 * c + 2]);
        // The sky's luminance on the (2W + 1) x (2H + 1) grid of corners, edge midpoints and
        // centres (conventions).
        const int GW = 2 * W + 1, GH = 2 * H + 1;
        std::vector<double> g(std::size_t(GW) * std::size_t(GH));
        for (int j = 0; j < GH; ++j)
            for (int i = 0; i < GW; ++i) {
                const facet::Vec2 uv(float(i) / float(2 * W), float(j) / float(2 * H));
                const glm::dvec3 d = m_frame * glm::dvec3(facet::latlong_direction(uv));
                const double dd[3] = {d.x, d.y, d.z};
                float rgb[3] = {0.f, 0.f, 0.f};
                fn(ctx, dd, rgb);
                const double y = 0.2126 * rgb[0] + 0.7152 * rgb[1] + 0.0722 * rgb[2];
                g[std::size_t(j) * GW + i] = std::isfinite(y) && y > 0.0 ? y : 0.0;
            }
        constexpr double kTrap[3] = {0.25, 0.5, 0.25};
        std::vector<double> lum(std::size_t(W) * std::size_t(H), 0.0);
        double sum = 0.0;
        for (int y = 0; y < H; ++y)
            for (int x = 0; x < W; ++x) {
                double m = 0.0;
                for (int b = 0; b < 3; ++b)
                    for (int a = 0; a < 3; ++a)
                        m += kTrap[b] * kTrap[a] * g[std::size_t(2 * y + b) * GW + 2 * x + a];
                lum[std::size_t(y) * W + x] = m;
                sum += m;
            }
        const double floor = 1e-4 * sum / double(lum.size());
        for (double& v : lum) v = std::max(v, floor);
        m_table = facet::LatLongDistribution(W, H, lum);
    }

    int m_samples;
    std::once_flag m_once;
    std::atomic<bool> m_built{false};
    glm::dmat3 m_frame{1.0};
    facet::LatLongDistribution m_table;
};

namespace {
std::mutex g_sky_mutex;
std::vector<std::unique_ptr<Sky>>& all_skies() {
    static std::vector<std::unique_ptr<Sky>> skies;
    return skies;
}
}  // namespace

Sky* sky_create(int samples) {
    std::lock_guard<std::mutex> lock(g_sky_mutex);
    all_skies().push_back(std::make_unique<Sky>(samples));
    return all_skies().back().get();
}

int sky_sample_count(const Sky* sky, unsigned trace_level) {
    if (!sky || sky->samples() <= 0) return 0;
    return trace_level <= 1 ? sky->samples() : 1;
}

int sky_state(const Sky* sky) {
    return sky ? sky->state() : 0;
}

bool sky_prepare(Sky* sky, int width, int height, const double frame[9], SkyRadianceFn fn,
                 void* context) {
    return sky && sky->prepare(width, height, frame, fn, context);
}

void sky_sample_u(unsigned seed, unsigned trace_level, int index, double u[2]) {
    // Another sequence than glossy_sample's (seed, trace level): the same seed hashed once more.
    facet::render::Sampler sampler(
        facet::render::hash_combine(facet::render::hash_combine(seed, trace_level), 0x736b79u),
        std::uint32_t(index));
    const facet::Vec2 uv = sampler.get_2d();
    u[0] = uv.x;
    u[1] = uv.y;
}

bool sky_sample(const Sky* sky, const double u[2], double wi[3], double& pdf) {
    return sky && sky->sample(u, wi, pdf);
}

double sky_pdf(const Sky* sky, const double wi[3]) {
    return sky ? sky->pdf(wi) : 0.0;
}

double power_heuristic(int n_a, double pdf_a, int n_b, double pdf_b) {
    const double a = n_a * pdf_a, b = n_b * pdf_b;
    if (!(a > 0.0)) return 0.0;
    return std::isinf(a) ? 1.0 : a * a / (a * a + b * b);
}

}  // namespace facet_pov
