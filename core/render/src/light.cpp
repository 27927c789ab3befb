// Light selection for next-event estimation (LightDistribution, light.h). The light types'
// sampling lives in their units (lights/*.cpp, light.h "Structure").
#include "facet/render/light.h"
#include "facet/render/scene.h"

#include <algorithm>

#include "facet/frame.h"
#include "facet/sampling.h"

namespace facet::render {

// --- Light: the dispatch to the light's type (light.h "Structure") ------------------------

std::string_view Light::type_name() const {
    return visit([](const auto& t) { return std::decay_t<decltype(t)>::kName; });
}

std::optional<LightLiSample> Light::sample_li_out_of_line(const LightSampleContext& ctx,
                                                          Vec2 u) const {
    return visit([&](const auto& t) { return t.sample_li(ctx, u); });
}

float Light::pdf_li(const LightSampleContext& ctx, const Vec3& wi, const Vec3& p_light,
                    const Vec3& n_light) const {
    return visit([&](const auto& t) {
        if constexpr (requires { t.pdf_li(ctx, wi, p_light, n_light); })
            return t.pdf_li(ctx, wi, p_light, n_light);
        else
            return 0.f;  // a moving emitter: pdf_li_at
    });
}

std::optional<LightLiSample> Light::sample_li_at_out_of_line(const LightSampleContext& ctx, Vec2 u,
                                                             float time) const {
    return visit([&](const auto& t) {
        if constexpr (requires { t.sample_li(ctx, u, time); })
            return t.sample_li(ctx, u, time);
        else
            return t.sample_li(ctx, u);
    });
}

float Light::pdf_li_at(const LightSampleContext& ctx, const Vec3& wi, const Vec3& p_light,
                       const Vec3& n_light, std::uint32_t prim, float time) const {
    return visit([&](const auto& t) {
        if constexpr (requires { t.pdf_li(ctx, wi, p_light, n_light, prim, time); })
            return t.pdf_li(ctx, wi, p_light, n_light, prim, time);
        else
            return t.pdf_li(ctx, wi, p_light, n_light);
    });
}

Rgb Light::le(const Vec3& n_light, const Vec3& w) const {
    return visit([&](const auto& t) {
        if constexpr (requires { t.le(n_light, w); })
            return t.le(n_light, w);
        else
            return Rgb(0.f);
    });
}

Rgb Light::le_escape(const Vec3& d) const {
    return visit([&](const auto& t) {
        if constexpr (requires { t.le_escape(d); })
            return t.le_escape(d);
        else
            return Rgb(0.f);
    });
}

Rgb Light::le_escape(const Vec3& d, const LightSampleContext& ctx, float& pdf) const {
    return visit([&](const auto& t) {
        if constexpr (requires { t.le_escape(d, pdf); }) {
            return t.le_escape(d, pdf);
        } else {
            pdf = pdf_li(ctx, d, Vec3(0.f), Vec3(0.f));
            return le_escape(d);
        }
    });
}

Rgb Light::power(float scene_radius) const {
    return visit([&](const auto& t) { return t.power(scene_radius); });
}

void Light::note(SceneFeatures& f) const {
    visit([&](const auto& t) { t.note(f); });
}

const EnvironmentMap* Light::map() const {
    return visit([](const auto& t) -> const EnvironmentMap* {
        if constexpr (requires { t.map(); })
            return t.map();
        else
            return nullptr;
    });
}

std::optional<LightBounds> Light::bounds() const {
    return visit([&](const auto& t) -> std::optional<LightBounds> {
        if constexpr (requires { t.bounds(); })
            return t.bounds();
        else
            return std::nullopt;
    });
}

float Light::camera_hit(const Vec3& o, const Vec3& d) const {
    if (!m_common.camera_visible) return kInfinity;
    return visit([&](const auto& t) {
        if constexpr (requires { t.camera_hit(o, d); })
            return t.camera_hit(o, d);
        else
            return kInfinity;
    });
}

// --- LightDistribution --------------------------------------------------------------------

LightDistribution::LightDistribution(std::span<const Light> lights, float scene_radius) {
    std::vector<double> w(lights.size());
    for (std::size_t i = 0; i < lights.size(); ++i) {
        if (!nee_samples(lights[i])) {
            w[i] = -1.0;
            continue;
        }
        const Rgb phi = lights[i].power(scene_radius);
        const double avg = (double(phi.r) + double(phi.g) + double(phi.b)) / 3.0;
        w[i] = std::isfinite(avg) && avg > 0.0 ? avg : 0.0;
    }
    build(w);
}

LightDistribution LightDistribution::uniform(std::span<const Light> lights) {
    LightDistribution d;
    std::vector<double> w(lights.size());
    for (std::size_t i = 0; i < lights.size(); ++i) w[i] = nee_samples(lights[i]) ? 1.0 : -1.0;
    d.build(w);
    return d;
}

// The view pilot (light.h). Why not the power estimate alone: the environment's and the
// directional lights' power is pi r^2 times their irradiance over the scene's bounding sphere of
// radius r (pbrt-v4), so a large ground (a 40 m plane around a 2 m asset) makes them r^2 times
// more likely than the lamps beside the asset, whatever the camera sees; and a strong lamp that
// is mostly occluded from the view still takes its power's share. The pilot measures both.
LightDistribution LightDistribution::view(const Scene& scene) {
    const std::span<const Light> lights = scene.lights();
    LightDistribution power(lights, scene.radius());
    std::vector<std::size_t> cand;
    for (std::size_t i = 0; i < lights.size(); ++i)
        if (!power.m_empty && power.pmf(i) > 0.f) cand.push_back(i);
    if (cand.size() < 2) return power;
    // Primary receivers: a gx x gy grid (the film's aspect), each with one bounce.
    const std::size_t receivers = kViewBudget / cand.size() / 2;
    if (receivers < 96) return power;
    const Camera& cam = scene.camera();
    const double aspect = double(cam.width) / double(cam.height);
    const int gy = std::clamp(
        int(std::sqrt(double(std::min<std::size_t>(receivers, 768)) / aspect)), 1, cam.height);
    const int gx =
        std::clamp(int(double(std::min<std::size_t>(receivers, 768)) / gy), 1, cam.width);
    std::vector<double> sum(lights.size(), 0.0);
    std::uint32_t n = 0;  // R2 sequence index (Roberts 2018): well spread, deterministic
    const auto next_u = [&n]() {
        ++n;
        const double a = 0.5 + n * 0.7548776662466927, b = 0.5 + n * 0.5698402909980532;
        return Vec2(float(a - std::floor(a)), float(b - std::floor(b)));
    };
    const auto receive = [&](const SurfaceHit& hit, const Vec3& wo, double weight) {
        const Vec3 nrm = glm::dot(hit.ng, wo) < 0.f ? -hit.ng : hit.ng;
        const LightSampleContext ctx{hit.p, nrm};
        for (std::size_t i : cand) {
            const std::optional<LightLiSample> ls = lights[i].sample_li(ctx, next_u());
            if (!ls || !(ls->pdf > 0.f)) continue;
            const double lum = (double(ls->li.r) + double(ls->li.g) + double(ls->li.b)) / 3.0;
            const double c = lum * std::max(0.0, double(glm::dot(nrm, ls->wi))) / double(ls->pdf);
            if (!(c > 0.0) || !std::isfinite(c) || scene.occluded(hit, *ls)) continue;
            sum[i] += (weight * c) * (weight * c);  // second moment: see the weights below
        }
    };
    for (int y = 0; y < gy; ++y) {
        for (int x = 0; x < gx; ++x) {
            const Vec2 film((float(x) + 0.5f) * float(cam.width) / float(gx),
                            (float(y) + 0.5f) * float(cam.height) / float(gy));
            const Ray ray = cam.generate_ray(film);
            SurfaceHit hit;
            if (!scene.intersect(ray, hit)) continue;
            const Vec3 wo = -ray.d;
            receive(hit, wo, 1.0);
            const Vec3 nrm = glm::dot(hit.ng, wo) < 0.f ? -hit.ng : hit.ng;
            const Vec3 d = Frame::from_z(nrm).from_local(sample_cosine_hemisphere(next_u()));
            SurfaceHit bounce;
            if (scene.intersect(Scene::spawn_ray(hit, d), bounce)) receive(bounce, -d, 0.5);
        }
    }
    // The one-sample estimator f_i / p_i of choosing light i with probability p_i has second
    // moment sum_i E[f_i^2] / p_i, least for p_i proportional to sqrt(E[f_i^2]) (Lagrange):
    // a light whose samples vary (an HDRI) gets more than its mean's share, a steady one (a
    // sun) less. Measured against the mean: bench/light_selection_bench.py.
    double total = 0.0;
    for (std::size_t i : cand) total += (sum[i] = std::sqrt(sum[i]));
    if (!(total > 0.0) || !std::isfinite(total)) return power;
    std::vector<double> w(lights.size(), -1.0);
    for (std::size_t i = 0; i < lights.size(); ++i) {
        if (!nee_samples(lights[i])) continue;
        w[i] = (1.0 - kViewPowerShare) * sum[i] / total + kViewPowerShare * double(power.pmf(i));
    }
    LightDistribution d;
    d.build(w);
    return d;
}

LightDistribution LightDistribution::tree(std::span<const Light> lights, float scene_radius) {
    LightDistribution d(lights, scene_radius);
    std::size_t candidates = 0;
    for (std::size_t i = 0; i < lights.size(); ++i) candidates += d.pmf(i) > 0.f ? 1 : 0;
    if (candidates < 2) return d;
    d.m_tree = std::make_shared<const LightTree>(lights,
                                                 [&](std::uint32_t i) { return d.m_pmf[i] > 0.f; });
    return d;
}

void LightDistribution::build(const std::vector<double>& weights) {
    const std::size_t n = weights.size();
    m_cdf.assign(n, 0.f);
    m_pmf.assign(n, 0.f);
    std::size_t candidates = 0;
    double total = 0.0;
    for (double w : weights) {
        if (w < 0.0) continue;
        ++candidates;
        total += w;
    }
    m_empty = candidates == 0;
    if (m_empty) return;
    const bool uniform = !(total > 0.0) || !std::isfinite(total);
    double run = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
        if (weights[i] >= 0.0) run += uniform ? 1.0 : weights[i];
        m_cdf[i] = float(run / (uniform ? double(candidates) : total));
    }
    // The last entry is exactly 1 so that every u in [0,1) selects some light; the trailing
    // zero-weight lights keep their zero probability.
    const float last = m_cdf[n - 1];
    for (std::size_t i = n; i-- > 0 && m_cdf[i] == last;) m_cdf[i] = 1.f;
    // pmf as the selection actually happens: the width of each light's interval of u.
    for (std::size_t i = 0; i < n; ++i) m_pmf[i] = m_cdf[i] - (i > 0 ? m_cdf[i - 1] : 0.f);
    m_guide.resize(n);
    build_cdf_guide(m_cdf.data(), n, m_guide.data());
}

}  // namespace facet::render
