// Dielectric interfaces that reflect and transmit: the smooth or rough boundary between two
// media (DielectricBxDF: Fresnel reflection and refraction, Walter et al. 2007 when rough) and
// the thin pane (ThinDielectricBxDF: two parallel interfaces, light leaves on the far side
// undeflected).
//
// Conventions (facet/bxdf.h holds, with these additions for transmission):
//  - Local frame z = the shading normal as the SHAPE defines it, not flipped toward the viewer:
//    the side z > 0 points to is OUTSIDE (relative IOR 1), the side z < 0 is INSIDE (the
//    medium of index `eta` relative to the outside). `wo` may lie on either side; `wi` on the
//    same side is reflection, on the other side transmission. Both point away from the surface.
//  - eta = n_inside / n_outside. For a direction pair, etap = n(wi's side) / n(wo's side) when
//    transmitting, i.e. eta when wo is outside and 1 / eta when wo is inside.
//  - `f` is the BSDF without the cosine. Transmission across the boundary compresses or expands
//    solid angle, so the transmitted f is not symmetric. With TransportMode::Radiance (paths
//    traced from the camera: f weighs incident radiance, as in the renderer's integrators) the
//    transmitted f is divided by etap^2 (Veach 1997, §5.2: radiance entering a medium of index
//    n_t from n_i is multiplied by (n_t / n_i)^2); with TransportMode::Importance (paths traced
//    from the lights) it is not. Then, in radiance mode, the generalised reciprocity
//        f(wo, wi) / n(wo)^2 = f(wi, wo) / n(wi)^2                    (Veach eq. 5.14)
//    holds, and f_radiance(wo, wi) = f_importance(wi, wo) (the adjoint BSDF).
//  - Fresnel: exact unpolarised dielectric reflectance F (facet/fresnel.h,
//    fresnel_dielectric) at the angle to the (micro) normal; total internal reflection when
//    the inside direction is past the critical angle (F = 1).
//  - `transmittance` (per channel, in [0, 1]) scales the transmitted lobe only; reflection is
//    untinted. With transmittance 1, reflection + transmission = 1 (smooth) before the etap^2
//    factor of radiance mode.
//  - Smooth (alpha below kSmoothAlpha, facet/microfacet.h): two delta lobes. f = pdf = 0;
//    sample_f chooses reflection with probability R = F(|cos theta_o|) and refraction with
//    T = 1 - R, pdf = that probability, f = R / |cos theta_i| resp.
//    transmittance T / |cos theta_i| / etap^2 (radiance), flagged Specular (| Transmission).
//  - Rough (Walter, Marschner, Li & Torrance 2007, eqs. 15-21, with the height-correlated Smith
//    G of facet/microfacet.h): the generalised half vector wm = normalize(etap wi + wo) turned
//    to z > 0 (etap = 1 for reflection); microfacets that face away from either direction are
//    discarded (f = 0);
//        f_r = D(wm) G(wo, wi) F / (4 |cos_i cos_o|),
//        f_t = transmittance D(wm) G(wo, wi) (1 - F) |wi.wm| |wo.wm|
//              / (|cos_i cos_o| (wi.wm + wo.wm / etap)^2)   [/ etap^2 in radiance mode],
//    F = F(wo.wm). Sampling draws wm from the visible normals seen from wo turned to z > 0
//    (the distribution's exact VNDF sampler), then reflects with probability F, refracts
//    otherwise; pdf = D_wo(wm) / (4 |wo.wm|) F  resp.  D_wo(wm) |wi.wm| / (wi.wm + wo.wm /
//    etap)^2 (1 - F). Without energy compensation the rough lobe loses the energy of light
//    scattered more than once between microfacets (measured in tests/core/test_dielectric.cpp).
//  - Energy compensation (optional, rough only; the Kulla & Conty 2017 construction extended to
//    refraction, with our own reciprocal split): E_s(mu) is the single-scattering albedo
//    R + T of the interface above with transmittance 1, in importance mode, for wo on side s
//    (s = out: relative index eta; s = in: 1 / eta), tabulated per material on kTableSize
//    nodes uniform in sqrt(mu) by Gauss-Legendre quadrature over the visible-normal sampler's
//    unit square (the sample weight F G / G1 resp. (1 - F) G / G1); E_avg_s = 2 int E_s mu dmu
//    of the interpolant, exactly; m_s = pi (1 - E_avg_s). The added lobe, in importance mode,
//        f_ms(wo, wi) = k(s_o, s_i) (1 - E_so(mu_o)) (1 - E_si(mu_i))  [* transmittance when
//                       s_o != s_i],
//        k(out, out) = (1 - x) / m_out,   k(out, in) = x / m_in,
//        k(in, out) = x / (eta^2 m_in),   k(in, in) = (1 - k(in, out) m_out) / m_in;
//    in radiance mode the transmitted f_ms is divided by etap^2 as the single lobe is, which
//    swaps k(out, in) and k(in, out). Then f_ms(wo, wi) / n(wi)^2 (n_out = 1, n_in = eta) is
//    symmetric, so generalised reciprocity holds as for the single lobe, and
//    int f_ms |cos_i| dwi = 1 - E_so(mu_o) on both sides: a rough interface with transmittance
//    1 conserves energy up to the table's error (white furnace). x, the share of the
//    multiply scattered energy from outside that is transmitted, is the free parameter: we take
//    the smooth interface's hemispherical transmittance 1 - F_avg(eta), clamped to
//    eta^2 m_in / m_out so that k(in, in) >= 0. Sampling picks f_ms with probability
//    1 - E_so(mu_o), then transmission with probability x (outside) resp. k(in, out) m_out
//    (inside), then a cosine-distributed direction on that side. Off when either side misses
//    less than kMinMissingEnergy (albedo_table.h) on average (the table error would dominate).
//    Anisotropic interfaces are not compensated (the registry rejects the combination).
//  - ThinDielectricBxDF (pbrt-v4's ThinDielectricBxDF): two parallel interfaces with the
//    inter-reflections inside the pane summed, R' = R + T^2 R / (1 - R^2), T' = 1 - R'
//    (R = F(|cos theta_o|) of one interface); reflection about the normal and transmission
//    straight through (wi = -wo), both delta lobes chosen with probabilities R' and T'. The
//    medium is the same on both sides: no etap^2 factor, and no inside or outside.
#pragma once

#include <array>
#include <optional>

#include "facet/bxdf.h"
#include "facet/microfacet.h"

namespace facet {

// Which quantity a path carries (Veach 1997, §5.2): radiance (camera paths; the renderer's
// integrators) or importance (light paths, adjoint transport).
enum class TransportMode : std::uint8_t { Radiance, Importance };

// Refraction of w (pointing away from the surface, on either side) through the interface with
// normal n (any orientation) and relative IOR eta = n_inside / n_outside, where the inside is
// the side opposite to n. On success writes the refracted direction (unit, pointing away on the
// other side) and etap = n(wt's side) / n(w's side); false on total internal reflection.
bool refract(const Vec3& w, Vec3 n, float eta, float& etap, Vec3& wt);

// Fresnel reflectance F of a dielectric interface of relative IOR eta (n_inside / n_outside,
// inside opposite to the normal) for the cosine cos_i between the incident direction and the
// normal: cos_i > 0 from outside, cos_i < 0 from inside (then 1 / eta).
float fresnel_dielectric_signed(float cos_i, float eta);

class DielectricBxDF {
  public:
    // eta: n_inside / n_outside, > 0 (validated by the registry). A distribution with
    // effectively_smooth() makes the delta (smooth) interface; only GGX and Beckmann (exact
    // visible-normal samplers) are accepted by the registry. energy_compensation builds the
    // tables (isotropic rough interfaces only; ignored when smooth).
    DielectricBxDF(float eta, const Rgb& transmittance, const MicrofacetDistribution& d,
                   bool energy_compensation = false);

    static constexpr int kTableSize = 64;  // nodes in sqrt(mu), per side

    // The compensation tables (E_out, E_in at the nodes, and their averages). They depend on
    // eta and the distribution only, so the staged build of a textured roughness at a constant
    // IOR (facet/staged_material.h) tabulates them over alpha once and interpolates.
    struct Compensation {
        std::array<float, 2 * kTableSize> e{};
        float e_avg[2] = {1.f, 1.f};
    };
    // The compensated interface with its tables given instead of computed (ignored when d is
    // effectively smooth): bit for bit the first constructor's when `c` is its compensation().
    DielectricBxDF(float eta, const Rgb& transmittance, const MicrofacetDistribution& d,
                   const Compensation& c);
    // This interface's tables (with energy compensation; otherwise E = 1).
    Compensation compensation() const;

    Rgb f(const Vec3& wo, const Vec3& wi, TransportMode mode) const;
    float pdf(const Vec3& wo, const Vec3& wi, TransportMode mode) const;
    BSDFEval eval(const Vec3& wo, const Vec3& wi, TransportMode mode) const;
    std::optional<BSDFSample> sample_f(const Vec3& wo, float uc, Vec2 u, TransportMode mode) const;
    BxDFFlags flags() const {
        return (m_smooth ? BxDFFlags::Specular : BxDFFlags::Glossy) | BxDFFlags::Transmission;
    }

    float eta() const { return m_eta; }
    const Rgb& transmittance() const { return m_transmittance; }
    bool smooth() const { return m_smooth; }
    const MicrofacetDistribution& distribution() const { return m_distribution; }
    bool energy_compensation() const { return m_energy_compensation; }
    bool has_multiple_scattering() const { return m_has_ms; }
    // This interface with another transmittance: the compensation tables do not depend on it
    // (they are built with transmittance 1), so the copy keeps them (staged materials).
    DielectricBxDF with_transmittance(const Rgb& transmittance) const {
        DielectricBxDF d = *this;
        d.m_transmittance = transmittance;
        return d;
    }

    // The tabulated single-scattering albedo E_s(mu) (header comment) for wo outside
    // (inside = false) or inside, and its average; 1 when no table is built.
    float albedo_table(bool inside, float mu) const;
    float albedo_average(bool inside) const { return m_e_avg[inside ? 1 : 0]; }
    // The single-scattering albedo R + T at wo (transmittance 1, importance mode) by the
    // table's quadrature (Gauss-Legendre of `order` nodes per dimension of the visible-normal
    // sampler's unit square); what the table stores at its nodes, exposed for the tests.
    double single_scattering_albedo(const Vec3& wo, int order) const;

  private:
    // The constructors' last step: the split of the multiply scattered energy from the tables.
    void finish_compensation();
    std::optional<BSDFSample> sample_smooth(const Vec3& wo, float uc, TransportMode mode) const;
    BSDFEval eval_single(const Vec3& wo, const Vec3& wi, TransportMode mode) const;
    // Probability of choosing the f_ms lobe at wo, and of transmission within it.
    float ms_probability(const Vec3& wo) const;
    float ms_transmit_probability(bool wo_inside) const {
        return wo_inside ? m_k[1][0] * m_m[0] : m_x;
    }

    float m_eta;
    Rgb m_transmittance;
    MicrofacetDistribution m_distribution;
    bool m_smooth;
    bool m_energy_compensation = false;
    bool m_has_ms = false;
    // E_out at [0, kTableSize), E_in at [kTableSize, 2 kTableSize) (nodes of albedo_table.h).
    std::array<float, 2 * kTableSize> m_e{};
    float m_e_avg[2] = {1.f, 1.f};
    float m_m[2] = {0.f, 0.f};  // pi (1 - E_avg) per side
    float m_x = 0.f;            // transmitted share of the outside f_ms
    float m_k[2][2] = {};       // importance-mode k(s_o, s_i), index 0 = out, 1 = in
};

class ThinDielectricBxDF {
  public:
    ThinDielectricBxDF(float eta, const Rgb& transmittance)
        : m_eta(eta), m_transmittance(transmittance) {}

    // Delta lobes only: f = pdf = 0 (the mode does not matter: same medium on both sides).
    Rgb f(const Vec3&, const Vec3&, TransportMode) const { return Rgb(0.f); }
    float pdf(const Vec3&, const Vec3&, TransportMode) const { return 0.f; }
    std::optional<BSDFSample> sample_f(const Vec3& wo, float uc, Vec2 u, TransportMode mode) const;
    BxDFFlags flags() const { return BxDFFlags::Specular | BxDFFlags::Transmission; }
    // R' of the pane at |cos theta| = cos_o (header comment); T' = 1 - R'.
    float reflectance(float cos_o) const;

    float eta() const { return m_eta; }
    const Rgb& transmittance() const { return m_transmittance; }

  private:
    float m_eta;
    Rgb m_transmittance;
};

}  // namespace facet
