// Smooth, rough and thin dielectrics (facet/dielectric.h).
#include "facet/dielectric.h"

#include "facet/fresnel.h"

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

DielectricBxDF::DielectricBxDF(float eta, const Rgb& transmittance, const MicrofacetDistribution& d)
    : m_eta(eta),
      m_transmittance(transmittance),
      m_distribution(d),
      m_smooth(d.effectively_smooth()) {}

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

BSDFEval DielectricBxDF::eval(const Vec3& wo, const Vec3& wi, TransportMode mode) const {
    if (m_smooth) return {};
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
