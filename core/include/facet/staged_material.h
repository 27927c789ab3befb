// Staged material build (issue 25): a material some of whose parameters vary from hit to hit
// (textures) is built in two stages instead of through the registry at every hit.
//  - Once, at scene build (StagedMaterial::make): everything that does not depend on the
//    varying values — the model's parsed constants (Fresnel kind, distribution, compensation),
//    the lobe structure, and the tables (the composite's glossy albedo Eg(mu), over the varying
//    roughness's range).
//  - Per hit (StagedMaterial::at): only the lobe parameters are set, from the values; no heap
//    allocation and no string handling.
//
// Conventions:
//  - A value is a DVec3: a colour parameter's channels, or a number in x (all three equal), as
//    a ParamSet holds them (the models read float(x) for numbers, as the registry does).
//  - `base` is the model built by the registry (make_material) at some valid values of the
//    varying parameters (the scene builder uses their largest): its constants are read from it.
//    The caller guarantees that every value passed to at() lies in the ranges given to make()
//    and is valid for the model (the scene builder validates the extremes of each texture).
//  - Every model unit builds in two stages (ModelInfo::read and make), so any model is staged
//    whatever its varying parameters: make() reads the constants once (ModelInfo::read of
//    `params`, the parameters `base` was built from), and at() sets the varying values and calls
//    ModelInfo::make with the children given. It is the same code on the same values as the
//    registry's build: bit for bit. make() returns nullopt only for a varying parameter that is
//    not a number or a colour.
//  - A model with a family (ModelInfo::staged) takes the family's build below instead where it
//    covers the varying parameters (not: Blinn exponents, anisotropic alpha_u/alpha_v,
//    conductor eta/k, a composite's ior with a glossy lobe or its f0 with energy compensation,
//    a principled with a subsurface weight), with its tables built once.
//
// Exactness against make_material at the same values:
//  - bit for bit for lambert, oren_nayar, principled, mirror, ggx/beckmann/blinn (the same
//    constructors with the same arguments), dielectric, thin_dielectric, and for a composite
//    whose glossy lobe does not vary (only diffuse_reflectance and/or mirror_reflectance do:
//    its Eg table is computed once, as the constructor would);
//  - a composite whose glossy lobe varies (alpha, f0 under fresnel = schlick,
//    glossy_reflectance) reads Eg from tables built once: Eg(mu) = ks (f0 A(mu, alpha) +
//    B(mu, alpha)), exact in ks and f0 (the lobe is linear in its scale, and Schlick's
//    F = f0 (1 - (1 - c)^5) + (1 - c)^5 is linear in f0), with A, B tabulated on kAlphaNodes
//    nodes uniform in sqrt(alpha) over the texture's range and interpolated linearly. Eg only
//    weights the diffuse lobe and picks lobes (facet/material.h); the glossy lobe itself is
//    exact. The diffuse lobe's normalisation 1 / (1 - Es_avg) is linear in the same tables
//    (Es_avg = ks (f0 H(A) + H(B)) + km H(F_mirror), H the table average), so it is tabulated
//    with them instead of being integrated at every hit;
//  - energy compensation (ggx/beckmann/blinn, a composite's glossy lobe, dielectric): the lobe's
//    own compensation tables depend on alpha (and a dielectric's IOR) only. With a constant
//    alpha they are the base's, read at each hit (bit for bit); with a textured alpha they are
//    tabulated on kAlphaNodes nodes in sqrt(alpha) and interpolated by Catmull-Rom (E(mu) and
//    E_avg with the same weights, so f_ms still integrates to 1 - E(mu_o)). An anisotropic lobe, or
//    a dielectric with a textured IOR or alpha, still builds them per hit.
// Tested against the model built from constants (tests/render/test_staged_material.cpp).
#pragma once

#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "facet/material.h"
#include "facet/registry.h"

namespace facet {

class StagedMaterial {
  public:
    struct Range {
        DVec3 lo, hi;  // per channel; numbers in x
    };
    // Nodes of the composite's Eg tables over sqrt(alpha) (when alpha varies).
    static constexpr int kAlphaNodes = 48;

    // `varying[i]` is the registry's name of value i of at(); ranges[i] its range. `params`:
    // the parameters `base` was built from (read by the two-stage units).
    static std::optional<StagedMaterial> make(std::string_view model, const Material& base,
                                              const ParamSet& params,
                                              std::span<const std::string> varying,
                                              std::span<const Range> ranges);

    // The material at these values (one per varying name, in make()'s order), with these
    // sub-materials (a combination's, built at the same hit; empty for the others).
    Material at(std::span<const DVec3> values, Children children = {}) const;

  private:
    using Family = StagedFamily;
    enum class Param : std::uint8_t {
        Reflectance,  // lambert, oren_nayar, mirror, ggx/beckmann/blinn: the lobe's scale/rho
        Sigma,
        Alpha,
        F0,
        Ior,
        Transmittance,
        Diffuse,  // composite's diffuse_reflectance
        Glossy,   // composite's glossy_reflectance
        Mirror,   // composite's mirror_reflectance
        PrincipledColor,
        PrincipledNumber
    };
    struct Slot {
        Param param;
        Rgb PrincipledParams::*color = nullptr;
        float PrincipledParams::*number = nullptr;
    };
    // The values of the reflection models' parameters at one hit.
    struct Values {
        Rgb rho{0.f}, kd{0.f}, ks{0.f}, km{0.f}, tr{1.f};
        float sigma = 0.f, eta = 1.f, alpha = 0.f;
        bool alpha_set = false, ec = false;
        Fresnel fr = Fresnel::none();
        MicrofacetDistribution dist = MicrofacetDistribution::ggx(1.f, 1.f);
    };

    explicit StagedMaterial(const Material& base) : m_base(base) {}
    Values constants() const;
    Material composite_at(const Values& v) const;
    // The alpha node below `alpha` and the weight of the one above (linear in sqrt(alpha));
    // node 0 and weight 0 when alpha does not vary.
    void alpha_node(float alpha, std::size_t& i, float& t) const;
    // The compensation tables at alpha (node i, weight t of node i + 1): m_comp / m_dcomp
    // interpolated by Catmull-Rom over the nodes (E and E_avg with the same weights).
    MicrofacetReflection::Compensation glossy_compensation(std::size_t i, float t) const;
    DielectricBxDF::Compensation dielectric_compensation(std::size_t i, float t) const;

    Family m_family = Family::Lambert;
    // A two-stage unit (ModelInfo::make; then m_family is unused): its constants and the index
    // of each varying value's parameter.
    const ModelInfo* m_unit = nullptr;
    ParamValues m_unit_values;
    std::vector<std::uint8_t> m_unit_slots;
    std::vector<Slot> m_slots;
    Material m_base;  // the constants' source (see the header comment)
    // Composite: Eg per alpha node, A (the f0 slope; zero unless f0 varies) and B; one node
    // when alpha is constant. m_glossy_varies false: m_eg_const is the exact table.
    bool m_glossy_varies = false, m_f0_varies = false, m_alpha_varies = false;
    std::vector<Material::AlbedoTable> m_eg_a, m_eg_b;
    Material::AlbedoTable m_eg_const{};
    // Node i at sqrt(alpha) = m_s_lo + i m_s_step (m_alpha_varies), for the Eg tables and the
    // compensation tables below.
    float m_s_lo = 0.f, m_s_step = 0.f;
    // Composite: Es_avg (facet/material.h), linear in the tables: ks (f0 m_ha + m_hb) per alpha
    // node plus km (f0 m_hm_a + m_hm_b) for the mirror lobe. m_es_avg_const: one value for
    // every hit (m_es_const, computed as the per-hit build would, bit for bit).
    std::vector<Rgb> m_ha, m_hb;
    Rgb m_hm_a{0.f}, m_hm_b{0.f};
    bool m_es_avg_const = false;
    Rgb m_es_const{0.f};
    // Energy compensation of a ggx/beckmann/blinn or composite glossy lobe (m_comp) or of a
    // dielectric (m_dcomp): the lobe's own tables per alpha node (one node when alpha is
    // constant: the base's, exact), interpolated per hit like Eg. Empty: the lobe computes
    // them (no compensation; an anisotropic lobe; a dielectric's textured IOR).
    std::vector<MicrofacetReflection::Compensation> m_comp;
    std::vector<DielectricBxDF::Compensation> m_dcomp;
    // The base's values (constants()), read once at make().
    Values m_constants;
    // The glossy lobe's Fresnel average F_avg when no texture changes its Fresnel (no f0 or
    // ior slot): computed once, as every per-hit lobe with compensation would.
    bool m_f_avg_const = false;
    Rgb m_f_avg{0.f};
};

}  // namespace facet
