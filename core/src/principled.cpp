// The principled model (facet/principled.h; formulas and differences from Cycles:
// docs/principled.md).
#include "facet/principled.h"

#include <algorithm>
#include <cmath>

#include "albedo_table.h"
#include "facet/fresnel.h"
#include "facet/sampling.h"

namespace facet {

namespace {

// Cycles' CLOSURE_WEIGHT_CUTOFF: a closure whose weight is at most this is not allocated.
constexpr float kCutoff = 1e-5f;
// Cycles treats a GGX / GTR1 lobe with alpha_x alpha_y <= 1e-7 as singular (a delta lobe).
constexpr float kSingular = 1e-7f;
// Cycles' floor on the glass refraction weight (keeps MNEE from a null BSDF).
constexpr float kMinRefraction = 1e-4f;
// The clearcoat lobe's fixed masking-shadowing alpha (Cycles: "alpha2 = 0.25 * 0.25").
constexpr float kClearcoatGAlpha = 0.25f;
constexpr float kClearcoatIor = 1.5f;
constexpr float kIorOne = 1e-3f;  // |ior - 1| below this: refraction straight through
// Cycles 3.4 takes single-scattering GGX for a Multiscatter GGX specular with roughness <= this.
constexpr float kMultiscatterMinRoughness = 0.075f;
// ... and single-scattering glass lobes for a Multiscatter GGX glass with roughness <= this.
constexpr float kMultiscatterMinGlassRoughness = 0.05f;

// The F = 1 single-scattering albedo E(mu; alpha) of isotropic GGX with the height-correlated
// G, at alpha_j = r_j^2, r_j = j / (kAlphaNodes - 1) (uniform in roughness), on the mu nodes of
// albedo_table.h, and E_avg per node. Built once (about 0.1 s) by the quadrature of the ggx
// model's own energy compensation (MicrofacetReflection), shared by every multiscatter
// principled material so that building one per hit (textured parameters) costs no table.
// Linear interpolation between alpha nodes keeps E_avg exact: the average of the blend is the
// blend of the averages. Measured: the blend between nodes differs from a table built at the
// exact alpha by at most 1.5e-3 (test Principled.MultiscatterAlbedoTableInterpolates).
struct GgxAlbedoTable {
    static constexpr int kAlphaNodes = 33;
    static constexpr int kMu = MicrofacetReflection::kTableSize;
    std::array<std::array<float, kMu>, kAlphaNodes> e{};
    std::array<float, kAlphaNodes> avg{};
};
const GgxAlbedoTable& ggx_albedo_table() {
    static const GgxAlbedoTable table = [] {
        GgxAlbedoTable t;
        for (int j = 0; j < GgxAlbedoTable::kAlphaNodes; ++j) {
            const float r = float(j) / float(GgxAlbedoTable::kAlphaNodes - 1), a = r * r;
            const MicrofacetReflection lobe(MicrofacetDistribution::ggx(a, a), Fresnel::none(),
                                            Rgb(1.f), true);
            for (int k = 0; k < GgxAlbedoTable::kMu; ++k) {
                const float s = float(k) / float(GgxAlbedoTable::kMu - 1);
                t.e[j][k] = lobe.albedo_table(s * s);
            }
            t.avg[j] = sqrt_mu_table_average(t.e[j].data(), GgxAlbedoTable::kMu);
        }
        return t;
    }();
    return table;
}

float schlick_weight(float cos_theta) {
    const float m = std::clamp(1.f - cos_theta, 0.f, 1.f);
    return (m * m) * (m * m) * m;
}
float average(const Rgb& c) {
    return (c.r + c.g + c.b) / 3.f;
}
Rgb mix(const Rgb& a, const Rgb& b, float t) {
    return a * (1.f - t) + b * t;
}
Vec3 mirror_z(const Vec3& w) {
    return {w.x, w.y, -w.z};
}
// Colour with its luminance divided out ("hue and saturation"), white for black; `lum` is the
// weighting Cycles uses at that place.
Rgb tint_of(const Rgb& c, float lum) {
    return lum > 0.f ? c / lum : Rgb(1.f);
}

// Cycles' interpolate_fresnel_color: blends cspec0 toward white by the dielectric Fresnel term
// at ior renormalised to [0, 1] (FH = (F - F0) / (1 - F0), F0 = F(normal incidence)).
Rgb interpolate_fresnel(float cos_ih, float eta, float f0, const Rgb& cspec0) {
    const float fh = f0 < 1.f ? (fresnel_dielectric(cos_ih, eta) - f0) / (1.f - f0) : 1.f;
    return cspec0 * (1.f - fh) + Rgb(fh);
}

// Generalised Trowbridge-Reitz with gamma = 1 (Burley 2012, eq. 4), normalised so that
// int D cos dw = 1; a2 = alpha^2; Cycles returns 1 / pi for a2 >= 1. The denominator
// 1 + (a2 - 1) cos^2 is written a2 cos^2 + sin^2 with sin^2 from the vector's x, y: near the
// peak of a sharp lobe (a2 ~ 1e-6) the first form loses all digits to cancellation.
constexpr float kGtr1Uniform = 0.9999f;  // above this, the a2 -> 1 limit 1 / pi (see sampling)
float gtr1_d(const Vec3& h, float a2) {
    if (h.z <= 0.f) return 0.f;
    if (a2 >= kGtr1Uniform) return kInvPi;
    const float t = a2 * h.z * h.z + (h.x * h.x + h.y * h.y);
    return (a2 - 1.f) / (kPi * std::log(a2) * t);
}
// Draws a GTR1 normal with density D(h) cos(theta_h): sin^2 = (a2^(1 - u) - a2) / (1 - a2)
// (cos^2 = (1 - a2^(1 - u)) / (1 - a2), Burley 2012 appendix B), in double.
Vec3 sample_gtr1(float a2, Vec2 u) {
    double sin2;
    if (a2 >= kGtr1Uniform)
        sin2 = double(u[0]);  // D = 1 / pi: cosine-distributed normals
    else
        sin2 = (std::pow(double(a2), 1.0 - double(u[0])) - double(a2)) / (1.0 - double(a2));
    sin2 = std::clamp(sin2, 0.0, 1.0);
    const double s = std::sqrt(sin2), c = std::sqrt(1.0 - sin2);
    const double phi = 2.0 * kPiD * double(u[1]);
    return Vec3(glm::normalize(DVec3(s * std::cos(phi), s * std::sin(phi), c)));
}

// Cycles 3.4's masking-shadowing: the separable Smith form G1(wo) G1(wi), not the
// height-correlated 1 / (1 + Lambda(wo) + Lambda(wi)) of Facet's other microfacet models (Cycles
// switched in 3.5). Measured: a GGX sphere at alpha 0.81 renders 0.4573 in Cycles 3.4, the
// separable form predicts 0.4570, the height-correlated one 0.4689 (docs/principled.md).
float separable_g(const MicrofacetDistribution& d, const Vec3& wo, const Vec3& wi) {
    return d.G1(wo) * d.G1(wi);
}

}  // namespace

PrincipledBxDF::PrincipledBxDF(const PrincipledParams& p) : m_params(p) {
    // Subsurface: Cycles' fallback after a diffuse bounce (the base colour mixed toward the
    // subsurface colour, the diffuse lobe instead of the BSSRDF) for every path.
    const Rgb c =
        p.subsurface > 0.f ? mix(p.base_color, p.subsurface_color, p.subsurface) : p.base_color;
    const float metallic = p.metallic, transmission = p.transmission;
    const float w_d = (1.f - metallic) * (1.f - transmission);
    const float w_t = transmission * (1.f - metallic);
    const float w_s = 1.f - w_t;

    if (w_d > kCutoff && std::fabs(average(c)) > kCutoff) m_diffuse = c * w_d;
    if (w_d > kCutoff && p.sheen > kCutoff) {
        const float lum = 0.2126f * c.r + 0.7152f * c.g + 0.0722f * c.b;  // Rec. 709
        m_sheen = p.sheen * w_d * mix(Rgb(1.f), tint_of(c, lum), p.sheen_tint);
    }
    m_cosine = max_component(m_diffuse) > 0.f || max_component(m_sheen) > 0.f;

    // Specular: none at all when specular and metallic are both (almost) 0.
    if (w_s > kCutoff && (p.specular > kCutoff || metallic > kCutoff)) {
        m_spec = true;
        m_spec_weight = w_s;
        m_spec_eta = 2.f / (1.f - safe_sqrt(0.08f * p.specular)) - 1.f;
        m_spec_f0 = fresnel_dielectric(1.f, m_spec_eta);
        const float lum = 0.3f * c.r + 0.6f * c.g + 0.1f * c.b;  // Cycles' approximation
        const Rgb tint = mix(Rgb(1.f), tint_of(c, lum), p.specular_tint);
        m_cspec0 = glm::clamp(p.specular * 0.08f * tint * (1.f - metallic) + c * metallic, Rgb(0.f),
                              Rgb(1.f));
        const float aspect = safe_sqrt(1.f - 0.9f * p.anisotropic);
        const float r2 = p.roughness * p.roughness;
        const float ax = std::min(1.f, r2 / aspect), ay = std::min(1.f, r2 * aspect);
        m_spec_dist = MicrofacetDistribution::ggx(ax, ay);
        if (ax * ay <= kSingular) m_delta_mask |= 1u << kSpecular;
        if (p.multiscatter && p.roughness > kMultiscatterMinRoughness) setup_multiscatter();
        const float angle = 2.f * kPi * p.anisotropic_rotation;
        m_rot_c = std::cos(angle), m_rot_s = std::sin(angle);
    }

    if (p.clearcoat > kCutoff) {
        m_clearcoat = true;
        m_cc_weight = 0.25f * p.clearcoat;
        const float a = p.clearcoat_roughness * p.clearcoat_roughness;
        m_cc_a2 = a * a;
        m_cc_g = MicrofacetDistribution::ggx(kClearcoatGAlpha, kClearcoatGAlpha);
        if (m_cc_a2 <= kSingular) m_delta_mask |= 1u << kClearcoat;
    }

    if (w_t > kCutoff) {
        m_glass = true;
        m_glass_weight = w_t;
        m_glass_color = c;
        m_cspec_glass =
            glm::clamp(c * p.specular_tint + Rgb(1.f - p.specular_tint), Rgb(0.f), Rgb(1.f));
        const float ar = std::min(1.f, p.roughness * p.roughness);
        // Cycles' Multiscatter GGX ignores Transmission Roughness (its glass branches both
        // refract at the roughness).
        const float rt = p.multiscatter
                             ? p.roughness
                             : 1.f - (1.f - p.roughness) * (1.f - p.transmission_roughness);
        const float at = std::min(1.f, rt * rt);
        m_glass_r_dist = MicrofacetDistribution::ggx(ar, ar);
        m_glass_t_dist = MicrofacetDistribution::ggx(at, at);
        if (ar * ar <= kSingular) m_delta_mask |= 1u << kGlassReflect;
        // Cycles samples a refraction at |ior - 1| < 1e-4 as singular; Facet widens this to
        // 1e-3, where the half-vector Jacobian (etap wi.wm + wo.wm)^-2 of the rough lobe
        // degenerates in float while the lobe is narrower than 1e-3 rad.
        if (at * at <= kSingular || std::fabs(p.ior - 1.f) < kIorOne)
            m_delta_mask |= 1u << kGlassRefract;
        if (p.multiscatter && p.roughness > kMultiscatterMinGlassRoughness &&
            !(m_delta_mask & (1u << kGlassRefract))) {
            m_glass_ms.emplace(p.ior, c, MicrofacetDistribution::ggx(ar, ar), true);
            m_delta_mask &= ~((1u << kGlassReflect) | (1u << kGlassRefract));
        }
    }

    set_flags();
}

void PrincipledBxDF::set_flags() {
    m_flags = BxDFFlags::None;
    if (m_cosine) m_flags = m_flags | BxDFFlags::Diffuse;
    for (int k = kSpecular; k < kLobes; ++k)
        if (has_lobe(Lobe(k)))
            m_flags = m_flags | (is_delta(k) ? BxDFFlags::Specular : BxDFFlags::Glossy);
    if (m_glass) m_flags = m_flags | BxDFFlags::Transmission;
}

void PrincipledBxDF::setup_multiscatter() {
    m_spec_hc = true;
    // The shared table's blend at the lobe's equivalent isotropic roughness sqrt(sqrt(ax ay)).
    const GgxAlbedoTable& t = ggx_albedo_table();
    const float r = std::sqrt(std::sqrt(m_spec_dist.alpha_x() * m_spec_dist.alpha_y()));
    const float x = std::clamp(r, 0.f, 1.f) * float(GgxAlbedoTable::kAlphaNodes - 1);
    m_ms_node = std::min(int(x), GgxAlbedoTable::kAlphaNodes - 2);
    m_ms_t = x - float(m_ms_node);
    const float e_avg = t.avg[m_ms_node] + m_ms_t * (t.avg[m_ms_node + 1] - t.avg[m_ms_node]);
    // As the ggx model: no compensation when the lobe misses less than the table's error.
    if (1.f - e_avg < kMinMissingEnergy) return;
    // F_avg of Cycles' interpolated Fresnel, which is linear in F_d: the average of F_H is
    // (avg F_d - F0) / (1 - F0).
    const float fd_avg = Fresnel::dielectric(m_spec_eta).average().r;
    const float fh_avg = m_spec_f0 < 1.f ? (fd_avg - m_spec_f0) / (1.f - m_spec_f0) : 1.f;
    const Rgb f_avg = m_cspec0 * (1.f - fh_avg) + Rgb(fh_avg);
    const Rgb f_ms = f_avg * f_avg * e_avg / (Rgb(1.f) - f_avg * (1.f - e_avg));
    m_ms_color = m_spec_weight * f_ms / (kPi * (1.f - e_avg));
    if (!is_finite(m_ms_color) || !(max_component(m_ms_color) > 0.f)) return;
    m_spec_ms = true;
    m_ms_e_avg = e_avg;
}

float PrincipledBxDF::multiscatter_albedo(float mu) const {
    if (!m_spec_ms) return 1.f;
    const GgxAlbedoTable& t = ggx_albedo_table();
    const int n = GgxAlbedoTable::kMu;
    const float e0 = sqrt_mu_table_lookup(t.e[m_ms_node].data(), n, mu);
    const float e1 = sqrt_mu_table_lookup(t.e[m_ms_node + 1].data(), n, mu);
    return e0 + m_ms_t * (e1 - e0);
}

bool PrincipledBxDF::has_lobe(Lobe lobe) const {
    switch (lobe) {
        case kCosine:
            return m_cosine;
        case kSpecular:
            return m_spec;
        case kClearcoat:
            return m_clearcoat;
        case kGlassReflect:
        case kGlassRefract:
            return m_glass;
        case kSpecularMs:
            return m_spec_ms;
        default:
            return false;
    }
}

PrincipledBxDF PrincipledBxDF::only(unsigned lobes) const {
    PrincipledBxDF b = *this;
    auto keep = [&](int k) { return ((lobes >> k) & 1u) != 0u; };
    if (!keep(kCosine)) {
        b.m_cosine = false;
        b.m_diffuse = b.m_sheen = Rgb(0.f);
    }
    // The multiscatter compensation goes with the specular lobe it completes.
    if (!keep(kSpecular)) b.m_spec = b.m_spec_ms = false;
    if (!keep(kClearcoat)) b.m_clearcoat = false;
    if (!keep(kGlassReflect) && !keep(kGlassRefract)) {
        b.m_glass = false;
        b.m_glass_ms.reset();
    }
    b.set_flags();
    return b;
}

Rgb PrincipledBxDF::spec_fresnel(float cos_ih) const {
    return interpolate_fresnel(cos_ih, m_spec_eta, m_spec_f0, m_cspec0);
}

Rgb PrincipledBxDF::glass_fresnel(float cos_ih, float etap) const {
    return interpolate_fresnel(cos_ih, etap, fresnel_dielectric(1.f, etap), m_cspec_glass);
}

PrincipledBxDF PrincipledBxDF::subsurface_surface(const PrincipledParams& p) {
    PrincipledParams q = p;
    q.subsurface = 0.f;  // every lobe takes the unmixed base colour
    PrincipledBxDF b(q);
    const Rgb mixed = mix(p.base_color, p.subsurface_color, p.subsurface);
    const float w_d = diffuse_weight(p);
    b.m_diffuse = p.roughness > 0.f ? mixed * w_d : Rgb(0.f);
    b.m_retro_only = true;
    b.m_cosine = max_component(b.m_diffuse) > 0.f || max_component(b.m_sheen) > 0.f;
    b.set_flags();
    return b;
}

PrincipledBxDF::AtWo PrincipledBxDF::at_wo(const Vec3& wo, float etap) const {
    // wo is above the (mirrored) surface here; etap is the glass's n(other side) / n(wo side).
    AtWo a;
    a.etap = etap;
    const float c = wo.z;
    float w[kLobes] = {0.f, 0.f, 0.f, 0.f, 0.f, 0.f};
    // Sheen's sample weight is Cycles' avg_value schlick(cos_o) cos_o, floored so that the
    // cosine lobe keeps a positive probability wherever sheen reflects.
    if (m_cosine)
        w[kCosine] =
            average(m_diffuse) *
                (m_retro_only ? std::max(m_params.roughness * schlick_weight(c), 1e-3f) : 1.f) +
            average(m_sheen) * std::max(schlick_weight(c) * c, 1e-3f);
    if (m_spec) w[kSpecular] = m_spec_weight * average(spec_fresnel(c));
    if (m_clearcoat) w[kClearcoat] = m_cc_weight * fresnel_dielectric(c, kClearcoatIor);
    if (m_glass) {
        a.fm = fresnel_dielectric(c, a.etap);
        if (m_glass_ms) {
            // The compensated dielectric: reflects ~Fm, transmits ~(1 - Fm) C.
            w[kGlassReflect] = m_glass_weight * (a.fm + (1.f - a.fm) * average(m_glass_color));
        } else {
            w[kGlassReflect] = m_glass_weight * a.fm * average(glass_fresnel(c, a.etap));
            w[kGlassRefract] =
                m_glass_weight * std::max(kMinRefraction, 1.f - a.fm) * average(m_glass_color);
        }
    }
    if (m_spec_ms) {
        // The compensation lobe's albedo at wo: (1 - E(mu_o)) w_s mean(F_ms).
        a.ms_o = std::max(0.f, 1.f - multiscatter_albedo(c));
        w[kSpecularMs] = a.ms_o * average(m_ms_color) * kPi * (1.f - m_ms_e_avg);
    }
    const bool present[kLobes] = {m_cosine, m_spec, m_clearcoat, m_glass, m_glass && !m_glass_ms,
                                  m_spec_ms};
    float sum = 0.f;
    int n = 0;
    for (int k = 0; k < kLobes; ++k) sum += w[k], n += present[k];
    a.weight = sum;
    for (int k = 0; k < kLobes; ++k)
        a.p[k] = sum > 0.f ? w[k] / sum : (present[k] ? 1.f / float(n) : 0.f);
    return a;
}

void PrincipledBxDF::evaluate(const Vec3& wo, const Vec3& wi, const AtWo& a, TransportMode mode,
                              Rgb* f_out, float* pdf_out) const {
    Rgb f(0.f);
    float pdf = 0.f;
    const float cos_o = wo.z, cos_i = wi.z;
    if (cos_i > 0.f) {
        const Vec3 h = glm::normalize(wo + wi);
        const float cos_ih = glm::dot(wi, h), cos_oh = glm::dot(wo, h);
        const float inv4 = 1.f / (4.f * cos_o * cos_i);
        if (m_cosine) {
            // Disney diffuse with retro-reflection (Burley 2015; Cycles' PRINCIPLED_DIFFUSE_FULL)
            const float fl = schlick_weight(cos_i), fv = schlick_weight(cos_o);
            const float rr = m_params.roughness * (1.f + glm::dot(wi, wo));
            const float lambert = m_retro_only ? 0.f : (1.f - 0.5f * fv) * (1.f - 0.5f * fl);
            const float d = lambert + rr * (fl + fv + fl * fv * (rr - 1.f));
            f += m_diffuse * (d * kInvPi) + m_sheen * schlick_weight(cos_ih);
            pdf += a.p[kCosine] * cosine_hemisphere_pdf(cos_i);
        }
        if (m_spec && !is_delta(kSpecular)) {
            const Vec3 so = to_spec(wo), si = to_spec(wi), sh = to_spec(h);
            const float d = m_spec_dist.D(sh);
            // Multiscatter GGX's first bounce has the height-correlated G (Cycles' mf_eval).
            const float g = m_spec_hc ? m_spec_dist.G(so, si) : separable_g(m_spec_dist, so, si);
            f += m_spec_weight * spec_fresnel(cos_ih) * (d * g * inv4);
            if (cos_oh > 0.f) pdf += a.p[kSpecular] * m_spec_dist.pdf(so, sh) / (4.f * cos_oh);
        }
        if (m_spec_ms) {
            // Kulla & Conty 2017's compensation lobe (header comment).
            f += m_ms_color * (a.ms_o * std::max(0.f, 1.f - multiscatter_albedo(cos_i)));
            pdf += a.p[kSpecularMs] * cosine_hemisphere_pdf(cos_i);
        }
        if (m_clearcoat && !is_delta(kClearcoat)) {
            const float d = gtr1_d(h, m_cc_a2);
            f += Rgb(m_cc_weight * fresnel_dielectric(cos_ih, kClearcoatIor) * d *
                     separable_g(m_cc_g, wo, wi) * inv4);
            if (cos_oh > 0.f) pdf += a.p[kClearcoat] * d * h.z / (4.f * cos_oh);
        }
        if (m_glass && !m_glass_ms && !is_delta(kGlassReflect)) {
            const float d = m_glass_r_dist.D(h);
            f += (m_glass_weight * a.fm) * glass_fresnel(cos_ih, a.etap) *
                 (d * separable_g(m_glass_r_dist, wo, wi) * inv4);
            if (cos_oh > 0.f)
                pdf += a.p[kGlassReflect] * m_glass_r_dist.pdf(wo, h) / (4.f * cos_oh);
        }
    } else if (cos_i < 0.f && m_glass && !m_glass_ms && !is_delta(kGlassRefract)) {
        // Walter et al. 2007 refraction without a Fresnel factor (Cycles'
        // CLOSURE_BSDF_MICROFACET_GGX_REFRACTION_ID); microfacets facing away from either
        // direction reflect nothing (as facet/dielectric.h).
        const float etap = a.etap;
        Vec3 wm = etap * wi + wo;
        const float len2 = glm::dot(wm, wm);
        if (len2 > 0.f) {
            wm /= std::sqrt(len2);
            if (wm.z < 0.f) wm = -wm;
            const float d_i = glm::dot(wi, wm), d_o = glm::dot(wo, wm);
            if (d_o > 0.f && d_i < 0.f) {
                const float denom = sqr(etap * d_i + d_o);
                const float d = m_glass_t_dist.D(wm);
                float ft = d * separable_g(m_glass_t_dist, wo, wi) * std::fabs(d_i) * d_o /
                           (cos_o * std::fabs(cos_i) * denom);
                if (mode == TransportMode::Importance) ft *= etap * etap;
                f += (m_glass_weight * std::max(kMinRefraction, 1.f - a.fm) * ft) * m_glass_color;
                pdf += a.p[kGlassRefract] * m_glass_t_dist.pdf(wo, wm) * etap * etap *
                       std::fabs(d_i) / denom;
            }
        }
    }
    if (f_out) *f_out = f;
    if (pdf_out) *pdf_out = pdf;
}

bool PrincipledBxDF::mirrored(const Vec3& wo, Vec3& o, AtWo& a) const {
    const bool inside = wo.z < 0.f;
    if (wo.z == 0.f || (inside && !m_glass)) return false;
    o = inside ? mirror_z(wo) : wo;
    a = at_wo(o, inside ? 1.f / m_params.ior : m_params.ior);
    return true;
}

float PrincipledBxDF::sample_weight(const Vec3& wo) const {
    Vec3 o;
    AtWo a;
    return mirrored(wo, o, a) ? a.weight : 0.f;
}

std::array<float, PrincipledBxDF::kLobes> PrincipledBxDF::lobe_probabilities(const Vec3& wo) const {
    Vec3 o;
    AtWo a;
    if (!mirrored(wo, o, a)) return {};
    return a.p;
}

BSDFEval PrincipledBxDF::eval(const Vec3& wo, const Vec3& wi, TransportMode mode) const {
    BSDFEval e;
    Vec3 o;
    AtWo a;
    if (!mirrored(wo, o, a)) return e;
    evaluate(o, wo.z < 0.f ? mirror_z(wi) : wi, a, mode, &e.f, &e.pdf);
    if (m_glass_ms) {
        // The compensated dielectric takes the shape's frame itself (no mirroring).
        const BSDFEval g = m_glass_ms->eval(wo, wi, mode);
        e.f += m_glass_weight * g.f;
        e.pdf += a.p[kGlassReflect] * g.pdf;
    }
    return e;
}

Rgb PrincipledBxDF::f(const Vec3& wo, const Vec3& wi, TransportMode mode) const {
    return eval(wo, wi, mode).f;
}

float PrincipledBxDF::pdf(const Vec3& wo, const Vec3& wi, TransportMode mode) const {
    return eval(wo, wi, mode).pdf;
}

std::optional<BSDFSample> PrincipledBxDF::sample_f(const Vec3& wo, float uc, Vec2 u,
                                                   TransportMode mode) const {
    Vec3 o;
    AtWo a;
    if (!mirrored(wo, o, a)) return std::nullopt;
    const bool inside = wo.z < 0.f;
    // Choose a lobe with uc (the last present lobe absorbs round-off).
    int lobe = -1;
    float acc = 0.f, below = 0.f;
    for (int k = 0; k < kLobes; ++k) {
        if (!(a.p[k] > 0.f)) continue;
        lobe = k;
        below = acc;
        acc += a.p[k];
        if (uc < acc) break;
    }
    if (lobe < 0) return std::nullopt;

    if (m_glass_ms && lobe == kGlassReflect) {
        // The compensated dielectric samples in the shape's frame with uc rescaled to its
        // interval; f and pdf are the whole mixture's at the sampled direction.
        const float ug = std::clamp((uc - below) / a.p[lobe], 0.f, 0x1.fffffep-1f);
        const auto g = m_glass_ms->sample_f(wo, ug, u, mode);
        if (!g) return std::nullopt;
        const BSDFEval e = eval(wo, g->wi, mode);
        if (!(e.pdf > 0.f)) return std::nullopt;
        BSDFSample s;
        s.wi = g->wi;
        s.f = e.f;
        s.pdf = e.pdf;
        s.flags = g->flags;
        return s;
    }

    BSDFSample s;
    const Vec3 n(0.f, 0.f, 1.f);
    if (is_delta(lobe)) {
        // A delta lobe: f |cos_i| / pdf is its weight; pdf is the discrete choice.
        Rgb weight(0.f);
        if (lobe == kGlassRefract) {
            float etap = 1.f;
            if (!refract(o, n, a.etap, etap, s.wi)) return std::nullopt;
            float t = m_glass_weight * std::max(kMinRefraction, 1.f - a.fm);
            if (mode == TransportMode::Radiance) t /= etap * etap;
            weight = t * m_glass_color;
            s.flags = BxDFFlags::Specular | BxDFFlags::Transmission;
        } else {
            s.wi = reflect(o, n);
            const float c = o.z;
            if (lobe == kSpecular) weight = m_spec_weight * spec_fresnel(c);
            if (lobe == kClearcoat)
                weight = Rgb(m_cc_weight * fresnel_dielectric(c, kClearcoatIor));
            if (lobe == kGlassReflect) weight = (m_glass_weight * a.fm) * glass_fresnel(c, a.etap);
            s.flags = BxDFFlags::Specular;
        }
        if (!(std::fabs(s.wi.z) > 0.f)) return std::nullopt;
        s.f = weight / std::fabs(s.wi.z);
        s.pdf = a.p[lobe];
        if (inside) s.wi = mirror_z(s.wi);
        return s;
    }

    Vec3 wi;
    switch (lobe) {
        case kCosine:
        case kSpecularMs:
            wi = sample_cosine_hemisphere(u);
            break;
        case kSpecular:
            wi = reflect(o, from_spec(m_spec_dist.sample_wm(to_spec(o), u)));
            break;
        case kClearcoat:
            wi = reflect(o, sample_gtr1(m_cc_a2, u));
            break;
        case kGlassReflect:
            wi = reflect(o, m_glass_r_dist.sample_wm(o, u));
            break;
        default: {  // kGlassRefract
            const Vec3 wm = m_glass_t_dist.sample_wm(o, u);
            float etap = 1.f;
            if (!refract(o, wm, a.etap, etap, wi)) return std::nullopt;
            if (!(wi.z < 0.f)) return std::nullopt;
            break;
        }
    }
    if (lobe != kGlassRefract && !(wi.z > 0.f)) return std::nullopt;
    if (m_glass_ms) {
        // The mixture includes the dielectric, which eval() adds in the shape's frame.
        const BSDFEval e = eval(wo, inside ? mirror_z(wi) : wi, mode);
        s.f = e.f, s.pdf = e.pdf;
    } else {
        evaluate(o, wi, a, mode, &s.f, &s.pdf);
    }
    if (!(s.pdf > 0.f)) return std::nullopt;
    s.flags = wi.z < 0.f ? BxDFFlags::Glossy | BxDFFlags::Transmission
                         : (lobe == kCosine ? BxDFFlags::Diffuse : BxDFFlags::Glossy);
    s.wi = inside ? mirror_z(wi) : wi;
    return s;
}

}  // namespace facet
