// A Facet material: the sum of a diffuse, a glossy and a mirror component (Cohen & Wallace
// §2.5.5, f = kd f_d + ks f_s + f_m), energy conserving by construction.
//
// Conventions: facet/bxdf.h (local frame, no cosine in f, pdf per solid angle, delta lobes).
//  - Glossy and mirror are summed as they are: the registry requires their scales to sum to
//    at most 1 per channel, and F <= 1, so together they reflect at most 1.
//  - The diffuse lobe gets what the specular lobes leave, reciprocally:
//      f_d(wo, wi) = rho_d/pi * (1 - Es(wo)) (1 - Es(wi)) / (1 - Es_avg)
//    where Es(mu) is the directional albedo of glossy + mirror and Es_avg = 2 int Es(mu) mu dmu
//    (Kelemen & Szirmay-Kalos 2001 form; Kulla & Conty 2017 §5.3). Then the albedo at wo is
//    Es(wo) + rho_d (1 - Es(wo)) <= 1, and f stays symmetric in wo, wi (eq. 2.24).
//    Es is tabulated per channel at construction by Gauss-Legendre quadrature over mu.
//  - sample_f picks a lobe with probability proportional to its albedo at wo (luminance), and
//    pdf() is the matching mixture density of the non-delta lobes.
//  - A transmissive material (flags() has Transmission) is one dielectric BxDF and nothing else
//    (facet/dielectric.h: `dielectric`, `thin_dielectric`): its frame's z is the shape's
//    outward shading normal, not the viewer's side, and wo may lie on either side. The
//    TransportMode argument matters only to these (radiance by default: camera paths); the
//    reflection lobes are symmetric and ignore it.
//  - A principled material (facet/principled.h) is that one model and nothing else; with
//    transmission it follows the transmissive conventions above.
#pragma once

#include <array>
#include <optional>
#include <string>

#include "facet/bxdf.h"
#include "facet/dielectric.h"
#include "facet/lambert.h"
#include "facet/microfacet.h"
#include "facet/mirror.h"
#include "facet/principled.h"

namespace facet {

class Material {
  public:
    Material(std::optional<LambertReflection> diffuse, std::optional<MicrofacetReflection> glossy,
             std::optional<MirrorReflection> mirror);
    // A transmissive material: the dielectric interface or the thin pane alone.
    explicit Material(const DielectricBxDF& dielectric);
    explicit Material(const ThinDielectricBxDF& thin);
    // Blender's Principled BSDF (facet/principled.h), alone.
    explicit Material(const PrincipledBxDF& principled);

    using Mode = TransportMode;
    Rgb f(const Vec3& wo, const Vec3& wi, Mode mode = Mode::Radiance) const;
    float pdf(const Vec3& wo, const Vec3& wi, Mode mode = Mode::Radiance) const;
    // f and pdf together
    BSDFEval eval(const Vec3& wo, const Vec3& wi, Mode mode = Mode::Radiance) const;
    std::optional<BSDFSample> sample_f(const Vec3& wo, float uc, Vec2 u,
                                       Mode mode = Mode::Radiance) const;
    BxDFFlags flags() const { return m_flags; }
    bool transmissive() const { return is_transmissive(m_flags); }

    const std::optional<DielectricBxDF>& dielectric() const { return m_dielectric; }
    const std::optional<ThinDielectricBxDF>& thin_dielectric() const { return m_thin; }
    const std::optional<PrincipledBxDF>& principled() const { return m_principled; }

    // The same material with the diffuse lobe's reflectance rho replaced (it has a diffuse lobe):
    // bit for bit the material the constructor builds from that lobe and the same glossy and
    // mirror lobes, since rho enters no table. No allocation: for per-hit textured materials.
    Material with_diffuse_reflectance(const Rgb& rho) const {
        Material m = *this;
        m.m_diffuse.emplace(rho);
        return m;
    }

    const std::optional<LambertReflection>& diffuse() const { return m_diffuse; }
    const std::optional<MicrofacetReflection>& glossy() const { return m_glossy; }
    const std::optional<MirrorReflection>& mirror() const { return m_mirror; }

    // Directional albedo of the specular part (glossy + mirror) at cos theta = mu, per channel
    // (0 for a single-lobe material, which needs no table).
    Rgb specular_albedo(float mu) const;
    // Directional albedo of the glossy lobe alone (phi-averaged table), per channel.
    Rgb glossy_albedo(float mu) const;
    // The diffuse lobe's f including its energy-conserving weight (see header comment).
    Rgb diffuse_f(const Vec3& wo, const Vec3& wi) const;

    // Number of mu nodes of the Es table (uniform in mu, linear interpolation).
    static constexpr int kTableSize = 64;

  private:
    // Lobe-selection probabilities at wo: diffuse, glossy, mirror (sum 1 when any is > 0).
    // Multi-lobe materials only (m_has_table): a single-lobe material is its lobe.
    std::array<float, 3> lobe_probabilities(const Vec3& wo) const;
    Rgb diffuse_scale(float mu) const { return Rgb(1.f) - specular_albedo(mu); }

    std::optional<LambertReflection> m_diffuse;
    std::optional<MicrofacetReflection> m_glossy;
    std::optional<MirrorReflection> m_mirror;
    std::optional<DielectricBxDF> m_dielectric;
    std::optional<ThinDielectricBxDF> m_thin;
    std::optional<PrincipledBxDF> m_principled;
    BxDFFlags m_flags = BxDFFlags::None;
    bool m_has_table = false;            // false for single-lobe materials
    std::array<Rgb, kTableSize> m_eg{};  // glossy albedo Eg(mu_k), mu_k = k / (kTableSize - 1)
    Rgb m_inv_one_minus_es_avg{1.f};     // 1 / (1 - Es_avg), per channel
};

}  // namespace facet
