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
//  - A model unit's BxDF (facet/inline_bxdf.h: `oren_nayar`, `translucent`, `velvet`, ...) is
//    that one BxDF alone; with Transmission it follows the transmissive conventions above.
//  - Combinations (`mix`, `add`; Material::mix, Material::add) hold two child materials:
//        mix:  f = (1 - w) f_a + w f_b,   add:  f = f_a + f_b,
//    chosen for sampling with probabilities p_a = 1 - w, p_b = w (mix) and 1/2, 1/2 (add);
//    pdf = p_a pdf_a + p_b pdf_b (the mixture density of the non-delta lobes). A child's delta
//    sample keeps its direction, with f scaled by the child's coefficient ((1 - w), w or 1)
//    and pdf by its probability, so f |cos| / pdf is the child's weight over p. A non-delta
//    sample gets the whole combination's f and pdf (one-sample MIS, as the composite does).
//    Flags are the union of the children's. A combination with a transmissive child is
//    transmissive: its frame is the shape's (facet/dielectric.h) and wo may lie below it; its
//    reflection-only children are then evaluated from wo's side (z mirrored when wo.z < 0),
//    i.e. they reflect on both sides of the interface, as Cycles' closures do. `add` may
//    reflect more than it receives (albedo sum > 1, as Cycles allows); the scene builder warns.
#pragma once

#include <array>
#include <memory>
#include <optional>
#include <string>

#include "facet/bxdf.h"
#include "facet/dielectric.h"
#include "facet/inline_bxdf.h"
#include "facet/lambert.h"
#include "facet/microfacet.h"
#include "facet/mirror.h"
#include "facet/oren_nayar.h"
#include "facet/principled.h"
#include "facet/subsurface.h"

namespace facet {

class Material {
  public:
    Material(std::optional<LambertReflection> diffuse, std::optional<MicrofacetReflection> glossy,
             std::optional<MirrorReflection> mirror);
    // Number of mu nodes of the Es table (uniform in mu, linear interpolation).
    static constexpr int kTableSize = 64;
    using AlbedoTable = std::array<Rgb, kTableSize>;  // Eg(mu_k), mu_k = k / (kTableSize - 1)
    // The glossy albedo Eg read from tables held elsewhere instead of a table of its own: the
    // staged build's tables over alpha nodes (facet/staged_material.h), which outlive every
    // per-hit material built from them. At node k,
    //   Eg_k = ks (f0 (a0_k + t (a1_k - a0_k)) + (b0_k + t (b1_k - b0_k)))   (a0 non-null),
    //   Eg_k = ks (b0_k + t (b1_k - b0_k))                                    (a0 null),
    //   Eg_k = b0_k                                                           (direct),
    // and Eg(mu) interpolates the nodes linearly in mu as an own table would: the per-hit
    // material reads 2 nodes per lookup instead of filling 64 (bit for bit the material built
    // with the table of those Eg_k).
    struct AlbedoRef {
        const AlbedoTable *a0 = nullptr, *a1 = nullptr, *b0 = nullptr, *b1 = nullptr;
        float t = 0.f;
        Rgb ks{1.f}, f0{0.f};
        bool direct = false;
        Rgb node(int k) const {
            if (direct) return (*b0)[k];
            const Rgb b = (*b0)[k] + t * ((*b1)[k] - (*b0)[k]);
            if (a0) return ks * (f0 * ((*a0)[k] + t * ((*a1)[k] - (*a0)[k])) + b);
            return ks * b;
        }
    };
    // What the staged build (facet/staged_material.h) gives the composite instead of computing
    // it: the glossy albedo to read (`eg_ref`), Es_avg (header comment; read only with eg_ref:
    // the same material bit for bit when it is that value), the glossy lobe's compensation
    // table (used when ec is on) and its Fresnel average. Null: computed.
    struct CompositeTables {
        const AlbedoRef* eg_ref = nullptr;
        const Rgb* es_avg = nullptr;
        const MicrofacetReflection::Compensation* compensation = nullptr;
        const Rgb* f_avg = nullptr;
    };
    // The registry's "composite" model: the lobes of non-zero weight (diffuse kd, glossy ks with
    // distribution d, Fresnel fr and compensation ec, mirror km with fr), a black diffuse lobe
    // when all are zero; the tables `t` given or computed (CompositeTables).
    static Material composite(const Rgb& kd, const Rgb& ks, const Rgb& km,
                              const MicrofacetDistribution& d, const Fresnel& fr, bool ec,
                              const CompositeTables& t);
    static Material composite(const Rgb& kd, const Rgb& ks, const Rgb& km,
                              const MicrofacetDistribution& d, const Fresnel& fr, bool ec);
    // Es_avg = 2 int Es(mu) mu dmu of the piecewise-linear interpolant of Es = clamp(eg + the
    // mirror lobe's reflectance, 0, 1) at the table's nodes (exactly, in double): the diffuse
    // lobe's normalisation (header comment). No mirror: `mirror` null.
    static Rgb specular_average(const AlbedoTable& eg, const MirrorReflection* mirror);
    // 2 int e(mu) mu dmu of the piecewise-linear interpolant of a table, exactly (in double):
    // linear in the table, so the staged build interpolates it with the table.
    static Rgb table_average(const AlbedoTable& table);
    // A transmissive material: the dielectric interface or the thin pane alone.
    explicit Material(const DielectricBxDF& dielectric);
    explicit Material(const ThinDielectricBxDF& thin);
    // Blender's Principled BSDF (facet/principled.h), alone; the second form builds it in place
    // from its parameters (the per-hit build: no copy of the BxDF).
    explicit Material(const PrincipledBxDF& principled);
    Material(std::in_place_type_t<PrincipledBxDF>, const PrincipledParams& params);
    // A model unit's BxDF (facet/inline_bxdf.h), alone.
    explicit Material(const InlineBxDF& unit);

    // Subsurface scattering (facet/subsurface.h): a material whose BSDF is Cycles' fallback
    // (what Cycles renders after a diffuse bounce: the node's Lambert, Principled's diffuse
    // with the mixed colour) and which, on paths without a diffuse bounce, is instead the
    // subsurface lobe beside the `surface` closures. Only the path integrators with random
    // walks read it (facet/render/integrator.h, "Subsurface"); every other consumer (AOVs,
    // reflectance, POV-Ray, `direct`) sees the fallback.
    struct Subsurface {
        SubsurfaceLobe lobe;
        // The BSDF closures beside the lobe (Principled's specular, sheen, retro-reflection,
        // ...); null when there are none (the Subsurface Scattering node).
        std::shared_ptr<const Material> surface;
        // The lobe's sample weight (the average of lobe.weight: about what the walk returns).
        float weight = 1.f;
        // The probability of choosing the lobe at a vertex seen from wo (local frame), else
        // `surface`: 1 without surface closures; else in proportion to the sample weights, the
        // lobe's against the surface's at wo (PrincipledBxDF::sample_weight; 1 for a surface
        // of another kind), as Cycles picks among its closures.
        float probability(const Vec3& wo) const;
    };
    static Material with_subsurface(Material fallback, Subsurface s);
    const Subsurface* subsurface() const { return m_subsurface ? &*m_subsurface : nullptr; }

    // Combinations (header comment). mix() with weight 0 or 1 returns a copy of a or b itself.
    enum class Combine : std::uint8_t { Mix, Add };
    // A mix's weight w of b: constant, or from the view as Cycles' Fresnel and Layer Weight
    // nodes give a Mix Shader's Fac (mix_weight()): w depends on wo alone, so f is not
    // reciprocal, as in Cycles.
    enum class MixWeight : std::uint8_t { Constant, Fresnel, LayerFresnel, LayerFacing };
    struct Combination {
        Combine kind;
        std::shared_ptr<const Material> a, b;
        float coef_a, coef_b;  // f = coef_a f_a + coef_b f_b (MixWeight::Constant)
        float prob_a;          // probability of sampling a (b: 1 - prob_a)
        MixWeight weight = MixWeight::Constant;
        float weight_param = 0.f;  // Fresnel: the IOR; Layer*: the blend
        struct At {
            float coef_a, coef_b, prob_a;
        };
        // The coefficients at wo (the constant ones, or those of the view-dependent weight).
        At at(const Vec3& wo) const;
    };
    static Material mix(std::shared_ptr<const Material> a, std::shared_ptr<const Material> b,
                        float weight);
    static Material mix(std::shared_ptr<const Material> a, std::shared_ptr<const Material> b,
                        MixWeight weight, float param);
    static Material add(std::shared_ptr<const Material> a, std::shared_ptr<const Material> b);

    using Mode = TransportMode;
    Rgb f(const Vec3& wo, const Vec3& wi, Mode mode = Mode::Radiance) const;
    float pdf(const Vec3& wo, const Vec3& wi, Mode mode = Mode::Radiance) const;
    // f and pdf together
    BSDFEval eval(const Vec3& wo, const Vec3& wi, Mode mode = Mode::Radiance) const;
    std::optional<BSDFSample> sample_f(const Vec3& wo, float uc, Vec2 u,
                                       Mode mode = Mode::Radiance) const;
    BxDFFlags flags() const { return m_flags; }
    bool transmissive() const { return is_transmissive(m_flags); }
    // Holdout (the `holdout` model, Blender's Holdout shader): the fraction of the surface that
    // is a hole in the image where camera rays reach it (facet/render/integrator.h). The model
    // is a black surface of holdout weight 1; a combination's weight is its children's,
    // weighted by their coefficients at wo (local frame), as Cycles sums its holdout closures.
    // Its BSDF is unchanged by this: the holdout part reflects nothing.
    bool has_holdout() const { return m_holdout > 0.f; }
    float holdout_weight(const Vec3& wo) const;
    // The `holdout` model: black, holdout weight 1.
    static Material holdout();
    // Some lobe reads the tangent direction (an anisotropic microfacet lobe or a unit BxDF that
    // reads it, facet/inline_bxdf.h, here or in a child).
    bool anisotropic() const { return m_anisotropic; }
    const Combination* combination() const { return m_combination ? &*m_combination : nullptr; }
    // The model unit's BxDF (facet/inline_bxdf.h), if the material is one.
    const std::optional<InlineBxDF>& unit() const { return m_unit; }
    const OrenNayarReflection* oren_nayar() const {
        return m_unit ? m_unit->get<OrenNayarReflection>() : nullptr;
    }

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

  private:
    // composite() with an AlbedoRef fills the lobes, then init(). User-provided: a defaulted
    // constructor lets GCC 12 zero the whole object (kilobytes of disengaged optionals) at each
    // per-hit build.
    Material() noexcept {}
    // The constructors' common part: flags and, for two or more lobes, the tables (eg_ref to
    // read, with es_avg given or computed, or computed).
    void init(const Rgb* es_avg = nullptr, const AlbedoRef* eg_ref = nullptr);

    // Lobe-selection probabilities at wo: diffuse, glossy, mirror (sum 1 when any is > 0).
    // Multi-lobe materials only (m_has_table): a single-lobe material is its lobe.
    std::array<float, 3> lobe_probabilities(const Vec3& wo) const;
    Rgb diffuse_scale(float mu) const { return Rgb(1.f) - specular_albedo(mu); }
    // The rare kinds (dielectric, thin pane, unit BxDFs, combinations), out of the fast path.
    BSDFEval special_eval(const Vec3& wo, const Vec3& wi, Mode mode) const;
    std::optional<BSDFSample> special_sample_f(const Vec3& wo, float uc, Vec2 u, Mode mode) const;

    std::optional<LambertReflection> m_diffuse;
    std::optional<MicrofacetReflection> m_glossy;
    std::optional<MirrorReflection> m_mirror;
    std::optional<DielectricBxDF> m_dielectric;
    std::optional<ThinDielectricBxDF> m_thin;
    std::optional<PrincipledBxDF> m_principled;
    std::optional<InlineBxDF> m_unit;
    // Held in place: a per-hit combination or walk allocates nothing of its own.
    std::optional<Combination> m_combination;
    std::optional<Subsurface> m_subsurface;
    BxDFFlags m_flags = BxDFFlags::None;
    bool m_special = false;  // one of the rare kinds: f, pdf and sample_f go to special_*
    bool m_anisotropic = false;
    // Holdout weight: the model's 1; for a combination an upper bound (0: none in it), its
    // weight at wo comes from the children (holdout_weight).
    float m_holdout = 0.f;
    bool m_has_table = false;  // false for single-lobe materials
    // The glossy albedo Eg(mu_k), mu_k = k / (kTableSize - 1): an own table, or (m_eg_ref.b0
    // set) read from elsewhere. Optional so that a per-hit material with a reference neither
    // fills nor copies 64 entries.
    std::optional<AlbedoTable> m_eg;
    AlbedoRef m_eg_ref;
    Rgb m_inv_one_minus_es_avg{1.f};  // 1 / (1 - Es_avg), per channel
};

// The weight w of b of a view-dependent mix at wo (Material::MixWeight; Constant: param).
float mix_weight(Material::MixWeight kind, float param, const Vec3& wo);

// A shared copy of `m` for a material built per hit (a combination's child, a subsurface
// material's surface closures): `m` moved into a material of this thread's pool that nothing
// else holds any more (use count 1), so that once the pool has grown to the depth of the
// nesting a per-hit build allocates nothing.
std::shared_ptr<const Material> pooled_material(Material m);

}  // namespace facet
