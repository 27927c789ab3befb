// The principled model: Blender 3.4's Principled BSDF as Cycles 3.4 evaluates it
// (intern/cycles/kernel/svm/closure.h, CLOSURE_BSDF_PRINCIPLED_ID, and the closures it allocates:
// bsdf_principled_diffuse.h, bsdf_principled_sheen.h, bsdf_microfacet.h). docs/principled.md
// derives every formula below and lists each deliberate difference from Cycles with its reason.
//
// Conventions: facet/bxdf.h, and facet/dielectric.h when the model transmits:
//  - Local frame z = shading normal. A model with transmission > 0 is flagged Transmission and
//    then takes the dielectric convention: z is the shape's outward normal, wo may lie below
//    (inside); the model then evaluates in the frame mirrored to wo's side (z -> -z) with the
//    relative IOR 1 / ior, as Cycles flips N on back faces and uses 1 / ior. Without
//    transmission, wo and wi must both lie above (f = 0 otherwise).
//  - f carries no cosine; pdf is per solid angle of wi; delta lobes (smooth specular, smooth
//    glass, a clearcoat sharper than Cycles' singular threshold) follow facet/bxdf.h.
//  - Transmitted f follows facet/dielectric.h's TransportMode: divided by etap^2 in radiance
//    mode (Cycles never divides; for a closed object the two crossings cancel, see the doc).
//
// The lobes, with w_d = (1 - metallic)(1 - transmission), w_t = transmission (1 - metallic),
// w_s = 1 - w_t, C = base colour (mixed with the subsurface colour, see below), FL =
// (1 - cos_i)^5, FV = (1 - cos_o)^5 (Schlick weights), h = normalize(wi + wo):
//  - Disney diffuse (Burley 2015, with retro-reflection):
//      f_d = C w_d / pi [(1 - FV/2)(1 - FL/2) + RR (FL + FV + FL FV (RR - 1))],
//      RR = roughness (1 + wi.wo)  (= 2 roughness (wi.h)^2).
//  - Sheen: f_sh = sheen w_d C_sheen (1 - wi.h)^5, C_sheen = mix(1, C / lum(C), sheen_tint)
//    (lum: Rec. 709 luminance); only when w_d and sheen exceed Cycles' cut-off 1e-5.
//  - G in every microfacet lobe below is Cycles 3.4's separable Smith form G1(wo) G1(wi)
//    (not the height-correlated G of facet/microfacet.h; Cycles switched in 3.5).
//  - Specular (GGX, anisotropic): present only when w_s > 1e-5 and
//    (specular > 1e-5 or metallic > 1e-5) -- with both 0 there is no specular lobe at all.
//      f_s = w_s F_s D G / (4 cos_i cos_o),  alpha_x = min(1, r^2 / a), alpha_y = min(1, r^2 a),
//      a = sqrt(1 - 0.9 anisotropic), tangent rotated by 2 pi anisotropic_rotation;
//      F_s = cspec0 (1 - FH) + FH, FH = (F_diel(wi.h, eta_s) - F0) / (1 - F0), eta_s =
//      2 / (1 - sqrt(0.08 specular)) - 1, F0 = F_diel(1, eta_s) = 0.08 specular,
//      cspec0 = clamp01(0.08 specular mix(1, C / lum'(C), specular_tint) (1 - metallic)
//               + C metallic), lum' = 0.3 r + 0.6 g + 0.1 b (Cycles' "luminance approx.").
//  - Glass (w_t > 1e-5), split by the Fresnel term of the macro normal Fm = F_diel(cos_o, etap):
//      reflection  w_t Fm F_g D G / (4 cos_i cos_o)            (GGX alpha = r^2, isotropic),
//      F_g = cspec_g (1 - FH) + FH at etap, cspec_g = clamp01(mix(1, C, specular_tint));
//      refraction  w_t max(1e-4, 1 - Fm) C f_walter(wo, wi)    (GGX alpha = rt^2, no Fresnel),
//      rt = 1 - (1 - roughness)(1 - transmission_roughness) (Cycles' GGX branch).
//  - Clearcoat (clearcoat > 1e-5): 0.25 clearcoat F_diel(wi.h, 1.5) D_GTR1 G / (4 cos_i cos_o),
//      D_GTR1 = (a2 - 1) / (pi ln(a2) (1 + (a2 - 1) cos_h^2)), a2 = clearcoat_roughness^4
//      (1 / pi when a2 >= 1), G the GGX G at the fixed alpha 0.25.
//  - Subsurface: this model is Cycles' fallback (the one Cycles takes after a diffuse bounce):
//    C = mix(base_color, subsurface_color, subsurface) for every lobe, and the diffuse lobe
//    instead of the BSSRDF. The random walk itself is Material::subsurface() (facet/
//    subsurface.h): its surface closures are subsurface_surface(), the model with the unmixed
//    base colour for every lobe and, in place of the diffuse lobe, only its retro-reflection
//    term C_mixed w_d / pi RR (FL + FV + FL FV (RR - 1)) (Cycles' PRINCIPLED_DIFFUSE_RETRO_
//    REFLECTION, sampled with weight mean(C_mixed w_d) max(roughness FV, 1e-3)).
//  - Multiscatter GGX (distribution "multi_ggx", Cycles' Multiscatter GGX; docs/principled.md):
//    for roughness > 0.075 (Cycles' own switch to single scattering below), the specular lobe
//    takes the height-correlated G (what Cycles' random walk evaluates for its first bounce)
//    and gains the Kulla & Conty 2017 compensation lobe instead of Cycles' stochastic walk:
//      f_ms = w_s F_ms (1 - E(mu_o)) (1 - E(mu_i)) / (pi (1 - E_avg)),
//      F_ms = F_avg^2 E_avg / (1 - F_avg (1 - E_avg)), F_avg = 2 int F_s(mu) mu dmu,
//    E the F = 1 single-scattering albedo of isotropic GGX at alpha = sqrt(alpha_x alpha_y)
//    (one table over (alpha, mu) shared by every material; an anisotropic lobe is compensated
//    with its equivalent isotropic alpha). A white metal then reflects everything (furnace).
//    Glass (w_t > 1e-5) with roughness > 0.05 (Cycles' switch for its glass): Cycles 3.4 makes
//    one random-walk glass closure with microfacet Fresnel at alpha = r^2 (Transmission
//    Roughness ignored), refraction tinted by C; Facet takes its rough `dielectric` (Walter et
//    al. 2007, height-correlated G, microfacet Fresnel) with energy compensation, transmittance
//    C, weight w_t, in place of the two glass lobes. Its reflection is not tinted by
//    specular_tint (Cycles tints it by mix(1, C, specular_tint)); at roughness <= 0.05 the two
//    single-scattering glass lobes stay, with the refraction at r (no Transmission Roughness).
//  - Sampling: one lobe is chosen with probability proportional to its Cycles-style sample
//    weight at wo (average colour times its Fresnel at the normal), cosine-weighted for
//    diffuse + sheen, visible normals for GGX, D cos for GTR1; pdf() is the mixture.
#pragma once

#include <array>
#include <optional>

#include "facet/bxdf.h"
#include "facet/dielectric.h"
#include "facet/microfacet.h"

namespace facet {

// Blender 3.4's Principled BSDF inputs (their defaults), with Facet's ranges validated by the
// registry. Colours are linear RGB.
struct PrincipledParams {
    Rgb base_color{0.8f};
    float subsurface = 0.f;
    Rgb subsurface_color{0.8f};
    float metallic = 0.f;
    float specular = 0.5f;
    float specular_tint = 0.f;
    float roughness = 0.5f;
    float anisotropic = 0.f;
    float anisotropic_rotation = 0.f;
    float sheen = 0.f;
    float sheen_tint = 0.5f;
    float clearcoat = 0.f;
    float clearcoat_roughness = 0.03f;
    float ior = 1.45f;
    float transmission = 0.f;
    float transmission_roughness = 0.f;
    bool multiscatter = false;  // distribution "multi_ggx" (header comment)
};

class PrincipledBxDF {
  public:
    explicit PrincipledBxDF(const PrincipledParams& p);
    // The closures beside the subsurface lobe when the walk is taken (header comment).
    static PrincipledBxDF subsurface_surface(const PrincipledParams& p);
    // The diffuse weight w_d = (1 - metallic)(1 - transmission) and the cut-off below which a
    // lobe weight is dropped (Cycles' CLOSURE_WEIGHT_CUTOFF).
    static float diffuse_weight(const PrincipledParams& p) {
        return (1.f - p.metallic) * (1.f - p.transmission);
    }
    static constexpr float kWeightCutoff = 1e-5f;

    Rgb f(const Vec3& wo, const Vec3& wi, TransportMode mode) const;
    float pdf(const Vec3& wo, const Vec3& wi, TransportMode mode) const;
    BSDFEval eval(const Vec3& wo, const Vec3& wi, TransportMode mode) const;
    std::optional<BSDFSample> sample_f(const Vec3& wo, float uc, Vec2 u, TransportMode mode) const;
    BxDFFlags flags() const { return m_flags; }

    const PrincipledParams& params() const { return m_params; }
    // Whether the specular lobe is anisotropic (the renderer then needs the surface tangent).
    bool anisotropic() const { return m_spec && m_spec_dist.alpha_x() != m_spec_dist.alpha_y(); }

    // Lobe indices: diffuse + sheen (cosine-sampled), specular, clearcoat, glass reflection,
    // glass refraction, the specular's multiple-scattering compensation (cosine-sampled).
    enum Lobe {
        kCosine = 0,
        kSpecular,
        kClearcoat,
        kGlassReflect,
        kGlassRefract,
        kSpecularMs,
        kLobes
    };

    // The lobe selection probabilities of sample_f at wo (indexed by Lobe; all 0 when the model
    // sends nothing toward wo's side). sample_f chooses lobe k for uc in [sum_{j<k} p_j,
    // sum_{j<=k} p_j); the reflectance quadrature integrates each lobe's samples apart.
    std::array<float, kLobes> lobe_probabilities(const Vec3& wo) const;
    // The sum of the lobes' sample weights at wo (what lobe_probabilities normalises: each
    // lobe's average colour times its Fresnel at wo, Cycles' closure sample weights); 0 when the
    // model sends nothing toward wo's side. A caller weighs the model against other closures
    // with it (the subsurface lobe beside subsurface_surface()).
    float sample_weight(const Vec3& wo) const;
    // The compensated dielectric that stands for the glass lobes with multiscatter (or null).
    const DielectricBxDF* multiscatter_glass() const { return m_glass_ms ? &*m_glass_ms : nullptr; }
    // Whether the specular lobe has the multiscatter compensation (multiscatter and roughness
    // above Cycles' single-scattering threshold), and its table: the F = 1 single-scattering
    // albedo E(mu) and its average E_avg (1 without compensation).
    bool multiscatter_compensated() const { return m_spec_ms; }
    float multiscatter_albedo(float mu) const;
    float multiscatter_albedo_average() const { return m_ms_e_avg; }

    // Whether the model has the lobe (of non-zero weight), and whether it is a delta lobe.
    bool has_lobe(Lobe lobe) const;
    bool lobe_is_delta(Lobe lobe) const { return has_lobe(lobe) && is_delta(lobe); }
    // The same model with only the lobes whose bit (1 << Lobe) is set in `lobes`; the two
    // glass lobes stay or go together (they share the macro-normal Fresnel split). f of the
    // whole model is the sum of f over a partition of its lobes (each lobe's f does not depend
    // on the others); sampling renormalises the selection over the lobes kept. For front ends
    // that estimate lobes separately (povray-facet: the cosine lobe by lights and radiosity,
    // the glossy lobes by rays, the delta lobes by mirror rays).
    PrincipledBxDF only(unsigned lobes) const;

  private:
    // What depends on wo (in the frame mirrored to wo's side): the glass split and the lobe
    // selection probabilities.
    struct AtWo {
        float etap = 1.f;               // n(other side) / n(wo's side) for the glass lobes
        float fm = 0.f;                 // Fresnel of the macro normal at wo (glass split)
        float ms_o = 0.f;               // 1 - E(mu_o) of the multiscatter compensation
        std::array<float, kLobes> p{};  // selection probabilities (sum 1 when any lobe)
        float weight = 0.f;             // the sum of the lobes' sample weights
    };
    AtWo at_wo(const Vec3& wo, float etap) const;
    // wo mirrored to the upper side (o) and its AtWo; false when the model sends nothing
    // (wo on the surface, or below it without transmission).
    bool mirrored(const Vec3& wo, Vec3& o, AtWo& a) const;
    // f and pdf for wo above the (mirrored) surface; either pointer may be null.
    void evaluate(const Vec3& wo, const Vec3& wi, const AtWo& a, TransportMode mode, Rgb* f_out,
                  float* pdf_out) const;
    bool is_delta(int lobe) const { return (m_delta_mask >> lobe) & 1u; }
    // The multiscatter shape and compensation of the specular lobe (after m_spec_dist).
    void setup_multiscatter();
    // m_flags from the lobes present.
    void set_flags();
    // Rotation of the anisotropic specular's tangent (into its rotated frame).
    Vec3 to_spec(const Vec3& w) const {
        return {m_rot_c * w.x + m_rot_s * w.y, -m_rot_s * w.x + m_rot_c * w.y, w.z};
    }
    Vec3 from_spec(const Vec3& w) const {
        return {m_rot_c * w.x - m_rot_s * w.y, m_rot_s * w.x + m_rot_c * w.y, w.z};
    }
    Rgb spec_fresnel(float cos_ih) const;
    Rgb glass_fresnel(float cos_ih, float etap) const;

    PrincipledParams m_params;
    BxDFFlags m_flags = BxDFFlags::None;
    unsigned m_delta_mask = 0;  // bit per Lobe: the lobe is a delta

    Rgb m_diffuse{0.f};         // C w_d
    bool m_retro_only = false;  // subsurface_surface(): the retro-reflection term alone
    Rgb m_sheen{0.f};           // sheen w_d C_sheen
    bool m_cosine = false;

    bool m_spec = false;
    float m_spec_weight = 0.f;  // w_s
    float m_spec_eta = 1.5f, m_spec_f0 = 0.04f;
    Rgb m_cspec0{0.f};
    MicrofacetDistribution m_spec_dist = MicrofacetDistribution::ggx(0.25f, 0.25f);
    float m_rot_c = 1.f, m_rot_s = 0.f;

    bool m_spec_hc = false;  // multiscatter shape: the height-correlated G on the specular
    bool m_spec_ms = false;  // multiscatter compensation on the specular lobe
    int m_ms_node = 0;       // the shared table's alpha node below alpha ...
    float m_ms_t = 0.f;      // ... and the linear weight of the node above
    float m_ms_e_avg = 1.f;
    Rgb m_ms_color{0.f};  // w_s F_ms / (pi (1 - E_avg))

    bool m_clearcoat = false;
    float m_cc_weight = 0.f;  // 0.25 clearcoat
    float m_cc_a2 = 0.f;      // clearcoat_roughness^4
    MicrofacetDistribution m_cc_g = MicrofacetDistribution::ggx(0.25f, 0.25f);  // G only

    bool m_glass = false;
    float m_glass_weight = 0.f;  // w_t
    Rgb m_cspec_glass{1.f};
    Rgb m_glass_color{1.f};  // C (refraction tint)
    MicrofacetDistribution m_glass_r_dist = MicrofacetDistribution::ggx(0.25f, 0.25f);
    MicrofacetDistribution m_glass_t_dist = MicrofacetDistribution::ggx(0.25f, 0.25f);
    // Multiscatter glass (header comment): replaces the two glass lobes; sampled in the
    // kGlassReflect slot.
    std::optional<DielectricBxDF> m_glass_ms;
};

}  // namespace facet
