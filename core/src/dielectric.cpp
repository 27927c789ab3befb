// Smooth, rough and thin dielectrics (facet/dielectric.h).
#include "facet/dielectric.h"

#include "albedo_table.h"
#include "facet/fresnel.h"
#include "facet/quadrature.h"
#include "facet/sampling.h"

namespace facet {

bool refract(const Vec3& w, Vec3 n, float eta, float& etap, Vec3& wt) {
    float cos_i = glm::dot(n, w);
    // From the inside (w on the side opposite to n): the relative index inverts, n turns over.
    if (cos_i < 0.f) {
        eta = 1.f / eta;
        cos_i = -cos_i;
        n = -n;
    }
    const float sin2_i = std::max(0.f, 1.f - cos_i * cos_i);
    const float sin2_t = sin2_i / (eta * eta);
    if (sin2_t >= 1.f) return false;  // total internal reflection
    const float cos_t = safe_sqrt(1.f - sin2_t);
    // Snell's law in vector form: tangential part scaled by 1 / eta, normal part -cos_t n.
    wt = glm::normalize(-w / eta + (cos_i / eta - cos_t) * n);
    etap = eta;
    return true;
}

float fresnel_dielectric_signed(float cos_i, float eta) {
    return cos_i >= 0.f ? fresnel_dielectric(cos_i, eta) : fresnel_dielectric(-cos_i, 1.f / eta);
}

// ---- DielectricBxDF ----

namespace {
constexpr int kTableOrder = 48;       // Gauss-Legendre nodes per dimension of the table
constexpr double kTableMinMu = 1e-4;  // mu where the first node (mu = 0) is evaluated
}  // namespace

DielectricBxDF::DielectricBxDF(float eta, const Rgb& transmittance, const MicrofacetDistribution& d,
                               bool energy_compensation)
    : m_eta(eta),
      m_transmittance(transmittance),
      m_distribution(d),
      m_smooth(d.effectively_smooth()),
      m_energy_compensation(energy_compensation) {
    m_e.fill(1.f);
    if (!m_energy_compensation || m_smooth) return;
    // E_out and E_in at the nodes mu_k = (k / (n - 1))^2 (albedo_table.h), by quadrature.
    for (int side = 0; side < 2; ++side) {
        for (int k = 0; k < kTableSize; ++k) {
            const double s_k = double(k) / (kTableSize - 1);
            const double mu = std::fmax(s_k * s_k, kTableMinMu);
            const Vec3 wo(float(std::sqrt(1.0 - mu * mu)), 0.f, float(side == 0 ? mu : -mu));
            m_e[size_t(side * kTableSize + k)] =
                float(std::fmin(single_scattering_albedo(wo, kTableOrder), 1.0));
        }
        m_e_avg[side] = sqrt_mu_table_average(&m_e[size_t(side * kTableSize)], kTableSize);
    }
    finish_compensation();
}

DielectricBxDF::DielectricBxDF(float eta, const Rgb& transmittance, const MicrofacetDistribution& d,
                               const Compensation& c)
    : m_eta(eta),
      m_transmittance(transmittance),
      m_distribution(d),
      m_smooth(d.effectively_smooth()),
      m_energy_compensation(true) {
    m_e.fill(1.f);
    if (m_smooth) return;
    m_e = c.e;
    m_e_avg[0] = c.e_avg[0], m_e_avg[1] = c.e_avg[1];
    finish_compensation();
}

DielectricBxDF::Compensation DielectricBxDF::compensation() const {
    Compensation c;
    c.e = m_e;
    c.e_avg[0] = m_e_avg[0], c.e_avg[1] = m_e_avg[1];
    return c;
}

void DielectricBxDF::finish_compensation() {
    for (int side = 0; side < 2; ++side) m_m[side] = kPi * (1.f - m_e_avg[side]);
    if (1.f - m_e_avg[0] < kMinMissingEnergy || 1.f - m_e_avg[1] < kMinMissingEnergy) return;
    // The split of the multiply scattered energy (header comment): x = 1 - F_avg(eta), at most
    // eta^2 m_in / m_out.
    const float eta2 = m_eta * m_eta;
    const float x_smooth = 1.f - Fresnel::dielectric(m_eta).average().r;
    m_x = std::clamp(x_smooth, 0.f, std::fmin(1.f, eta2 * m_m[1] / m_m[0]));
    m_k[0][0] = (1.f - m_x) / m_m[0];
    m_k[0][1] = m_x / m_m[1];
    m_k[1][0] = m_x / (eta2 * m_m[1]);
    m_k[1][1] = std::fmax(0.f, 1.f - m_k[1][0] * m_m[0]) / m_m[1];
    m_has_ms = std::isfinite(m_k[0][0] + m_k[0][1] + m_k[1][0] + m_k[1][1]);
}

// E(wo) = int D_wo(wm) [F G(wo, wr) / G1(wo) + (1 - F) G(wo, wt) / G1(wo)] dwm over the visible
// normals, written as an integral of the visible-normal sampler's weight over its unit square
// (its pdf is D_wo exactly), by an order x order Gauss-Legendre product rule. A reflected
// direction below the horizon, a refracted one on wo's side or total internal reflection of
// the refracted part contribute 0, as in sample_f.
double DielectricBxDF::single_scattering_albedo(const Vec3& wo, int order) const {
    if (m_smooth) return 1.0;
    const QuadratureRule& q = gauss_legendre(order);
    const Vec3 wo_up = wo.z > 0.f ? wo : -wo;
    const double lam_o = m_distribution.lambda(wo), g1 = 1.0 / (1.0 + lam_o);
    // G(wo, w) = 1 / (1 + Lambda(wo) + Lambda(w)), as MicrofacetDistribution::G.
    auto g = [&](const Vec3& w) { return 1.0 / (1.0 + lam_o + double(m_distribution.lambda(w))); };
    double e = 0.0;
    for (size_t i = 0; i < q.nodes.size(); ++i) {
        for (size_t j = 0; j < q.nodes.size(); ++j) {
            const Vec3 wm =
                m_distribution.sample_wm(wo_up, Vec2(float(q.nodes[i]), float(q.nodes[j])));
            const float c = glm::dot(wo, wm);
            const double fr = fresnel_dielectric_signed(c, m_eta);
            double w = 0.0;
            const Vec3 wr = reflect(wo, wm);
            if (same_hemisphere(wo, wr)) w += fr * g(wr);
            float etap;
            Vec3 wt;
            if (fr < 1.0 && refract(wo, wm, m_eta, etap, wt) && !same_hemisphere(wo, wt) &&
                wt.z != 0.f)
                w += (1.0 - fr) * g(wt);
            e += q.weights[i] * q.weights[j] * w;
        }
    }
    return g1 > 0.0 ? e / g1 : 0.0;
}

float DielectricBxDF::albedo_table(bool inside, float mu) const {
    return sqrt_mu_table_lookup(&m_e[inside ? size_t(kTableSize) : 0], kTableSize, std::fabs(mu));
}

float DielectricBxDF::ms_probability(const Vec3& wo) const {
    return m_has_ms ? clamp_unit(1.f - albedo_table(wo.z < 0.f, wo.z)) : 0.f;
}

std::optional<BSDFSample> DielectricBxDF::sample_smooth(const Vec3& wo, float uc,
                                                        TransportMode mode) const {
    const float r = fresnel_dielectric_signed(cos_theta(wo), m_eta);
    const float t = 1.f - r;
    // Lobe choice in proportion to R and T: the sample weights f |cos| / pdf are then 1 and
    // transmittance / etap^2.
    if (uc < r || !(t > 0.f)) {
        const Vec3 wi(-wo.x, -wo.y, wo.z);
        return BSDFSample{Rgb(r / abs_cos_theta(wi)), wi, r, BxDFFlags::Specular};
    }
    float etap;
    Vec3 wi;
    // Round-off may put a direction the double-precision Fresnel just lets through at the
    // float critical angle: no sample then (probability ~1e-7).
    if (!refract(wo, Vec3(0.f, 0.f, 1.f), m_eta, etap, wi) || wi.z == 0.f) return std::nullopt;
    Rgb ft = m_transmittance * (t / abs_cos_theta(wi));
    if (mode == TransportMode::Radiance) ft /= etap * etap;
    return BSDFSample{ft, wi, t, BxDFFlags::Specular | BxDFFlags::Transmission};
}

namespace {
// The generalised half vector of (wo, wi) turned to z > 0, the cosines wo.wm and wi.wm, and etap
// (1 for reflection); false for degenerate configurations and for microfacets that face away
// from wo or wi (f = pdf = 0). In double: the transmission Jacobian's wi.wm + wo.wm / etap adds
// terms of opposite signs, and in float the two orders (wo, wi) and (wi, wo) differed by up to
// 1e-3 relative (generalised reciprocity, tests/core/test_dielectric.cpp).
struct HalfVector {
    Vec3 wm;
    double dot_o, dot_i, etap;
};
bool half_vector(const Vec3& wo, const Vec3& wi, float eta, HalfVector& h) {
    const double cos_o = cos_theta(wo), cos_i = cos_theta(wi);
    if (cos_o == 0.0 || cos_i == 0.0) return false;
    const bool reflect = cos_o * cos_i > 0.0;
    h.etap = reflect ? 1.0 : (cos_o > 0.0 ? double(eta) : 1.0 / double(eta));
    DVec3 wm = DVec3(wi) * h.etap + DVec3(wo);
    const double len2 = glm::dot(wm, wm);
    if (!(len2 > 0.0)) return false;
    wm /= std::sqrt(len2);
    if (wm.z < 0.0) wm = -wm;
    if (!(float(wm.z) > 0.f)) return false;
    h.dot_o = glm::dot(DVec3(wo), wm);
    h.dot_i = glm::dot(DVec3(wi), wm);
    h.wm = Vec3(wm);
    return h.dot_i * cos_i > 0.0 && h.dot_o * cos_o > 0.0;
}
}  // namespace

BSDFEval DielectricBxDF::eval_single(const Vec3& wo, const Vec3& wi, TransportMode mode) const {
    HalfVector h;
    if (!half_vector(wo, wi, m_eta, h)) return {};
    // F from the outside direction's side for transmission (equal to F(wo.wm) by Stokes'
    // relations, and the same in both orders: F near the inside's critical angle is
    // ill-conditioned in the cosine).
    const double cos_fresnel = h.etap == 1.0 || wo.z > 0.f ? h.dot_o : h.dot_i;
    const float fr = fresnel_dielectric_signed(float(cos_fresnel), m_eta);
    const float d = m_distribution.D(h.wm);
    const float g = m_distribution.G(wo, wi);
    // Visible normals are sampled from wo turned to z > 0 (the distribution's convention).
    const Vec3 wo_up = wo.z > 0.f ? wo : -wo;
    const float pdf_wm = m_distribution.pdf(wo_up, h.wm);
    const double cos_io = std::fabs(double(cos_theta(wi)) * double(cos_theta(wo)));
    BSDFEval e;
    if (h.etap == 1.0) {  // reflection (Walter eq. 20; the Jacobian 1 / (4 |wo.wm|), eq. 14)
        e.f = Rgb(float(d * g * fr / (4.0 * cos_io)));
        e.pdf = float(pdf_wm / (4.0 * std::fabs(h.dot_o)) * fr);
    } else {  // transmission (Walter eq. 21; the Jacobian |wi.wm| / (wi.wm + wo.wm / etap)^2)
        const double denom = sqr(h.dot_i + h.dot_o / h.etap);
        double ft = d * g * (1.0 - fr) * std::fabs(h.dot_i * h.dot_o / (cos_io * denom));
        if (mode == TransportMode::Radiance) ft /= h.etap * h.etap;
        e.f = m_transmittance * float(ft);
        e.pdf = float(pdf_wm * std::fabs(h.dot_i) / denom * (1.0 - fr));
    }
    if (!std::isfinite(e.pdf) || !is_finite(e.f)) return {};
    return e;
}

BSDFEval DielectricBxDF::eval(const Vec3& wo, const Vec3& wi, TransportMode mode) const {
    if (m_smooth) return {};
    if (!m_has_ms) return eval_single(wo, wi, mode);
    if (wo.z == 0.f || wi.z == 0.f) return {};
    // Single lobe with probability 1 - p_ms, plus f_ms (header comment).
    BSDFEval e = eval_single(wo, wi, mode);
    const bool in_o = wo.z < 0.f, in_i = wi.z < 0.f;
    const float p_ms = ms_probability(wo);
    const float p_t = ms_transmit_probability(in_o);
    // Radiance mode divides the transmitted lobe by etap^2, which swaps k(out, in), k(in, out).
    const bool swap = in_o != in_i && mode == TransportMode::Radiance;
    const float k = swap ? m_k[in_i][in_o] : m_k[in_o][in_i];
    Rgb f_ms((1.f - albedo_table(in_o, wo.z)) * (1.f - albedo_table(in_i, wi.z)) * k);
    if (in_o != in_i) f_ms *= m_transmittance;
    e.f += f_ms;
    e.pdf = (1.f - p_ms) * e.pdf +
            p_ms * (in_o != in_i ? p_t : 1.f - p_t) * cosine_hemisphere_pdf(std::fabs(wi.z));
    return e;
}

Rgb DielectricBxDF::f(const Vec3& wo, const Vec3& wi, TransportMode mode) const {
    return eval(wo, wi, mode).f;
}

float DielectricBxDF::pdf(const Vec3& wo, const Vec3& wi, TransportMode mode) const {
    return eval(wo, wi, mode).pdf;
}

std::optional<BSDFSample> DielectricBxDF::sample_f(const Vec3& wo, float uc, Vec2 u,
                                                   TransportMode mode) const {
    if (wo.z == 0.f) return std::nullopt;
    if (m_smooth) return sample_smooth(wo, uc, mode);
    if (m_has_ms) {
        // f_ms with probability p_ms (uc reused, rescaled), on the side chosen by its share.
        const float p_ms = ms_probability(wo);
        if (uc < p_ms) {
            const float v = uc / p_ms;
            const bool transmit = v < ms_transmit_probability(wo.z < 0.f);
            Vec3 wi = sample_cosine_hemisphere(u);
            if ((wo.z < 0.f) != transmit) wi.z = -wi.z;
            if (wi.z == 0.f) return std::nullopt;
            const BSDFEval e = eval(wo, wi, mode);
            if (!(e.pdf > 0.f)) return std::nullopt;
            BxDFFlags flags = BxDFFlags::Glossy;
            if (transmit) flags = flags | BxDFFlags::Transmission;
            return BSDFSample{e.f, wi, e.pdf, flags};
        }
        uc = (uc - p_ms) / (1.f - p_ms);
    }
    const Vec3 wo_up = wo.z > 0.f ? wo : -wo;
    const Vec3 wm = m_distribution.sample_wm(wo_up, u);
    const float fr = fresnel_dielectric_signed(glm::dot(wo, wm), m_eta);
    Vec3 wi;
    BxDFFlags flags = BxDFFlags::Glossy;
    if (uc < fr) {
        wi = reflect(wo, wm);
        if (!same_hemisphere(wo, wi)) return std::nullopt;
    } else {
        float etap;
        if (!refract(wo, wm, m_eta, etap, wi)) return std::nullopt;
        if (same_hemisphere(wo, wi) || wi.z == 0.f) return std::nullopt;
        flags = flags | BxDFFlags::Transmission;
    }
    // f and pdf from the pair, as f() and pdf() compute them (one-sample consistency).
    const BSDFEval e = eval(wo, wi, mode);
    if (!(e.pdf > 0.f)) return std::nullopt;
    return BSDFSample{e.f, wi, e.pdf, flags};
}

// ---- ThinDielectricBxDF ----

float ThinDielectricBxDF::reflectance(float cos_o) const {
    float r = fresnel_dielectric(std::fabs(cos_o), m_eta);
    // Inter-reflections between the two interfaces (geometric series; pbrt-v4 §9.5.2).
    if (r < 1.f) r += sqr(1.f - r) * r / (1.f - r * r);
    return r;
}

std::optional<BSDFSample> ThinDielectricBxDF::sample_f(const Vec3& wo, float uc, Vec2 /*u*/,
                                                       TransportMode /*mode*/) const {
    if (wo.z == 0.f) return std::nullopt;
    const float r = reflectance(wo.z);
    const float t = 1.f - r;
    const float cos = std::fabs(wo.z);
    if (uc < r || !(t > 0.f))
        return BSDFSample{Rgb(r / cos), Vec3(-wo.x, -wo.y, wo.z), r, BxDFFlags::Specular};
    return BSDFSample{m_transmittance * (t / cos), -wo, t,
                      BxDFFlags::Specular | BxDFFlags::Transmission};
}

}  // namespace facet
