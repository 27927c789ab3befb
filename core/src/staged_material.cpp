// Staged material build: see facet/staged_material.h.
#include "facet/staged_material.h"

#include "facet/registry.h"

#include <algorithm>
#include <cmath>

#include "facet/reflectance.h"
#include "models/model_unit.h"

namespace facet {

namespace {
// Nodes of a compensated dielectric's tables over sqrt(alpha) when alpha varies: its
// transmission tables change faster with alpha than a reflection lobe's (48 nodes, as
// kAlphaNodes, left 3.2e-3 relative in f).
constexpr int kDielectricAlphaNodes = 144;

using P = PrincipledParams;
struct PrincipledField {
    const char* name;
    Rgb P::*color;
    float P::*number;
};
// Principled's colour and number parameters (the registry's names) and their fields.
constexpr PrincipledField kPrincipledFields[] = {
    {"base_color", &P::base_color, nullptr},
    {"subsurface_color", &P::subsurface_color, nullptr},
    {"subsurface", nullptr, &P::subsurface},
    {"metallic", nullptr, &P::metallic},
    {"specular", nullptr, &P::specular},
    {"specular_tint", nullptr, &P::specular_tint},
    {"roughness", nullptr, &P::roughness},
    {"anisotropic", nullptr, &P::anisotropic},
    {"anisotropic_rotation", nullptr, &P::anisotropic_rotation},
    {"sheen", nullptr, &P::sheen},
    {"sheen_tint", nullptr, &P::sheen_tint},
    {"clearcoat", nullptr, &P::clearcoat},
    {"clearcoat_roughness", nullptr, &P::clearcoat_roughness},
    {"ior", nullptr, &P::ior},
    {"transmission", nullptr, &P::transmission},
    {"transmission_roughness", nullptr, &P::transmission_roughness},
};

MicrofacetDistribution isotropic(DistributionKind kind, float alpha) {
    return kind == DistributionKind::Beckmann ? MicrofacetDistribution::beckmann(alpha, alpha)
                                              : MicrofacetDistribution::ggx(alpha, alpha);
}

float mu_node(int k) {
    return float(k) / float(Material::kTableSize - 1);
}

}  // namespace

std::optional<StagedMaterial> StagedMaterial::make(std::string_view model, const Material& base,
                                                   const ParamSet& params,
                                                   std::span<const std::string> varying,
                                                   std::span<const Range> ranges) {
    const ModelInfo* info = find_model(model);
    // A two-stage unit: its own reader, once, and its builder per hit.
    auto unit = [&]() -> std::optional<StagedMaterial> {
        StagedMaterial s(base);
        for (const std::string& name : varying) {
            const ParamInfo* p = info->param(name);
            if (!p || (p->type != ParamType::Number && p->type != ParamType::Color))
                return std::nullopt;
            s.m_unit_slots.push_back(std::uint8_t(p - info->params.data()));
        }
        try {
            ParamReader r(*info, params);
            info->read(r, s.m_unit_values);
        } catch (const ParamError&) {
            return std::nullopt;  // the caller validated `params`: not reached
        }
        s.m_unit = info;
        return s;
    };
    // A family's lobes with their tables built once (the header comment).
    auto by_family = [&]() -> std::optional<StagedMaterial> {
        StagedMaterial s(base);
        using F = Family;
        // The model's unit names its family (facet/registry.h); the base must be that model.
        const StagedFamily family = info ? info->staged : StagedFamily::None;
        bool matches = false;
        switch (family) {
            case StagedFamily::Lambert:
                matches = bool(base.diffuse());
                break;
            case StagedFamily::OrenNayar:
                matches = base.oren_nayar() != nullptr;
                break;
            case StagedFamily::Principled:
                // Not with a subsurface weight: the walk (on where its conditions hold) is the
                // unit's.
                matches = base.principled() && base.principled()->params().subsurface == 0.f &&
                          std::find(varying.begin(), varying.end(), "subsurface") == varying.end();
                break;
            case StagedFamily::Mirror:
                matches = bool(base.mirror());
                break;
            case StagedFamily::Microfacet:
                matches = bool(base.glossy());
                break;
            case StagedFamily::Dielectric:
                matches = bool(base.dielectric());
                break;
            case StagedFamily::ThinDielectric:
                matches = bool(base.thin_dielectric());
                break;
            case StagedFamily::Composite:
                matches = !base.combination() && !base.transmissive();
                break;
            case StagedFamily::None:
                break;
        }
        if (!matches) return std::nullopt;
        s.m_family = family;
        const F f = s.m_family;
        const Fresnel::Kind fresnel_kind = f == F::Mirror       ? base.mirror()->fresnel().kind()
                                           : f == F::Microfacet ? base.glossy()->fresnel().kind()
                                           : base.glossy()      ? base.glossy()->fresnel().kind()
                                           : base.mirror()      ? base.mirror()->fresnel().kind()
                                                                : Fresnel::Kind::Constant;
        const bool reflectance =
            f == F::Lambert || f == F::OrenNayar || f == F::Mirror || f == F::Microfacet;
        const bool fresnel = f == F::Mirror || f == F::Microfacet || f == F::Composite;
        const bool blinn =
            base.glossy() && base.glossy()->distribution().kind() == DistributionKind::Blinn;
        for (const std::string& name : varying) {
            Slot slot{Param::Reflectance};
            if (f == F::Principled) {
                const auto* it =
                    std::find_if(std::begin(kPrincipledFields), std::end(kPrincipledFields),
                                 [&](const PrincipledField& p) { return name == p.name; });
                if (it == std::end(kPrincipledFields)) return std::nullopt;
                slot = {it->color ? Param::PrincipledColor : Param::PrincipledNumber, it->color,
                        it->number};
            } else if (name == "reflectance" && reflectance) {
                slot.param = Param::Reflectance;
            } else if (name == "sigma" && f == F::OrenNayar) {
                slot.param = Param::Sigma;
            } else if (name == "alpha" && !blinn &&
                       (f == F::Microfacet || f == F::Dielectric || f == F::Composite)) {
                slot.param = Param::Alpha;
            } else if (name == "f0" && fresnel && fresnel_kind == Fresnel::Kind::Schlick) {
                slot.param = Param::F0;
            } else if (name == "ior" && ((fresnel && fresnel_kind == Fresnel::Kind::Dielectric) ||
                                         f == F::Dielectric || f == F::ThinDielectric)) {
                // A composite's glossy albedo is not linear in the IOR: not tabulated.
                if (f == F::Composite && base.glossy()) return std::nullopt;
                slot.param = Param::Ior;
            } else if (name == "transmittance" && (f == F::Dielectric || f == F::ThinDielectric)) {
                slot.param = Param::Transmittance;
            } else if (name == "diffuse_reflectance" && f == F::Composite) {
                slot.param = Param::Diffuse;
            } else if (name == "glossy_reflectance" && f == F::Composite) {
                slot.param = Param::Glossy;
            } else if (name == "mirror_reflectance" && f == F::Composite) {
                slot.param = Param::Mirror;
            } else {
                return std::nullopt;
            }
            s.m_slots.push_back(slot);
        }
        s.m_constants = s.constants();
        const bool fresnel_varies = std::any_of(
            s.m_slots.begin(), s.m_slots.end(),
            [](const Slot& sl) { return sl.param == Param::F0 || sl.param == Param::Ior; });
        if (!fresnel_varies && base.glossy() && base.glossy()->energy_compensation()) {
            s.m_f_avg_const = true;
            s.m_f_avg = base.glossy()->fresnel().average();
        }
        // The textured roughness's range: the nodes of every table over alpha (uniform in
        // sqrt(alpha); one node at its value when the texture is constant).
        bool alpha_given = false;
        double alpha_lo = 0.0, alpha_hi = 0.0;
        for (std::size_t i = 0; i < s.m_slots.size(); ++i) {
            if (s.m_slots[i].param != Param::Alpha) continue;
            alpha_given = true;
            if (ranges[i].hi.x > ranges[i].lo.x) {
                s.m_alpha_varies = true;
                alpha_lo = std::max(ranges[i].lo.x, 0.0), alpha_hi = ranges[i].hi.x;
            } else {
                alpha_lo = alpha_hi = ranges[i].lo.x;
            }
        }
        const int nodes = s.m_alpha_varies ? kAlphaNodes : 1;
        s.m_s_lo = float(std::sqrt(alpha_lo));
        s.m_s_step = s.m_alpha_varies
                         ? float((std::sqrt(alpha_hi) - std::sqrt(alpha_lo)) / (nodes - 1))
                         : 0.f;
        // The distribution at node i (d0 itself when alpha is not textured).
        auto node_distribution = [&](int i, const MicrofacetDistribution& d0) {
            const float sq = s.m_s_lo + float(i) * s.m_s_step;
            return alpha_given ? isotropic(d0.kind(), s.m_alpha_varies ? sq * sq : float(alpha_lo))
                               : d0;
        };
        // A compensated isotropic glossy lobe's own tables, once (MicrofacetReflection::
        // Compensation): from the base when alpha is not textured (exact), else per node.
        auto glossy_tables = [&](const MicrofacetReflection& g) {
            if (!g.energy_compensation() || !g.multiple_scattering_is_isotropic()) return;
            if (!alpha_given) {
                s.m_comp.push_back(g.compensation());
                return;
            }
            for (int i = 0; i < nodes; ++i)
                s.m_comp.push_back(MicrofacetReflection(node_distribution(i, g.distribution()),
                                                        Fresnel::none(), Rgb(1.f), true)
                                       .compensation());
        };
        if (f == F::Microfacet) glossy_tables(*base.glossy());
        if (f == F::Dielectric && base.dielectric()->energy_compensation()) {
            // The tables depend on the IOR too: a textured one keeps the per-hit build.
            const bool ior_varies =
                std::any_of(s.m_slots.begin(), s.m_slots.end(),
                            [](const Slot& sl) { return sl.param == Param::Ior; });
            const DielectricBxDF& d = *base.dielectric();
            if (!ior_varies && !alpha_given) s.m_dcomp.push_back(d.compensation());
            // A textured alpha: the lobe's tables on kDielectricAlphaNodes nodes in sqrt(alpha)
            // over the texture's range, interpolated by Catmull-Rom (dielectric_compensation).
            if (!ior_varies && alpha_given && !s.m_alpha_varies)
                s.m_dcomp.push_back(
                    DielectricBxDF(d.eta(), Rgb(1.f), node_distribution(0, d.distribution()), true)
                        .compensation());
            if (!ior_varies && s.m_alpha_varies) {
                const int dn = kDielectricAlphaNodes;
                for (int k = 0; k < dn; ++k) {
                    const float sq =
                        s.m_s_lo + float(k) * s.m_s_step * float(kAlphaNodes - 1) / float(dn - 1);
                    s.m_dcomp.push_back(DielectricBxDF(d.eta(), Rgb(1.f),
                                                       isotropic(d.distribution().kind(), sq * sq),
                                                       true)
                                            .compensation());
                }
            }
        }
        if (f != F::Composite || !base.glossy()) return s;

        // The composite's glossy albedo table Eg(mu) (facet/material.h), once.
        const MicrofacetReflection& g = *base.glossy();
        for (std::size_t i = 0; i < s.m_slots.size(); ++i) {
            const Param p = s.m_slots[i].param;
            s.m_f0_varies = s.m_f0_varies || p == Param::F0;
            s.m_glossy_varies =
                s.m_glossy_varies || p == Param::F0 || p == Param::Glossy || p == Param::Alpha;
        }
        // With compensation, the lobe's albedo is not linear in F0 (F_ms, Kulla & Conty eq. 16).
        if (s.m_f0_varies && g.energy_compensation()) return std::nullopt;
        glossy_tables(g);
        const bool mirror_varies =
            std::any_of(s.m_slots.begin(), s.m_slots.end(),
                        [](const Slot& sl) { return sl.param == Param::Mirror; });
        if (!s.m_glossy_varies) {
            for (int k = 0; k < Material::kTableSize; ++k)
                s.m_eg_const[k] = phi_averaged_albedo(g, mu_node(k));
            // Only the diffuse (and perhaps mirror) reflectance varies: with a constant mirror,
            // Es_avg is the same at every hit, computed as Material's constructor would.
            if (!mirror_varies) {
                s.m_es_avg_const = true;
                s.m_es_const = Material::specular_average(
                    s.m_eg_const, base.mirror() ? &*base.mirror() : nullptr);
            }
            return s;
        }
        s.m_eg_a.assign(std::size_t(s.m_f0_varies ? nodes : 0), {});
        s.m_eg_b.assign(std::size_t(nodes), {});
        for (int i = 0; i < nodes; ++i) {
            const MicrofacetDistribution d = node_distribution(i, g.distribution());
            const Fresnel f_b = s.m_f0_varies ? Fresnel::schlick(Rgb(0.f)) : g.fresnel();
            const MicrofacetReflection lobe_b(d, f_b, Rgb(1.f), g.energy_compensation());
            for (int k = 0; k < Material::kTableSize; ++k)
                s.m_eg_b[std::size_t(i)][k] = phi_averaged_albedo(lobe_b, mu_node(k));
            if (!s.m_f0_varies) continue;
            const MicrofacetReflection lobe_1(d, Fresnel::schlick(Rgb(1.f)), Rgb(1.f), false);
            for (int k = 0; k < Material::kTableSize; ++k)
                s.m_eg_a[std::size_t(i)][k] =
                    phi_averaged_albedo(lobe_1, mu_node(k)) - s.m_eg_b[std::size_t(i)][k];
        }
        // Es_avg per node: the average is linear in the table, so it is interpolated with Eg
        // (without the clamp of Es to [0, 1], which the registry's ks + km <= 1 makes inactive).
        for (const Material::AlbedoTable& t : s.m_eg_b)
            s.m_hb.push_back(Material::table_average(t));
        for (const Material::AlbedoTable& t : s.m_eg_a)
            s.m_ha.push_back(Material::table_average(t));
        // The mirror lobe's part per unit km: Schlick's F is linear in f0 (F(f0) = f0 (F(1) -
        // F(0)) + F(0)); another Fresnel is constant here (a textured IOR is not staged with a
        // glossy lobe).
        Material::AlbedoTable m0, m1;
        const Fresnel fr0 = s.m_f0_varies ? Fresnel::schlick(Rgb(0.f)) : g.fresnel();
        for (int k = 0; k < Material::kTableSize; ++k) {
            m0[k] = MirrorReflection(fr0, Rgb(1.f)).reflectance(mu_node(k));
            m1[k] =
                s.m_f0_varies
                    ? MirrorReflection(Fresnel::schlick(Rgb(1.f)), Rgb(1.f)).reflectance(mu_node(k))
                    : m0[k];
        }
        s.m_hm_b = Material::table_average(m0);
        s.m_hm_a = Material::table_average(m1) - s.m_hm_b;
        return s;
    };
    // A unit with a family takes the family's build where it stages these parameters (its
    // tables over the textured range), else its own two-stage builder (everything derived from
    // the values, such as compensation tables, computed per hit).
    if (info && info->make && info->staged == StagedFamily::None) return unit();
    if (std::optional<StagedMaterial> f = by_family()) return f;
    if (info && info->make) return unit();
    return std::nullopt;
}

void StagedMaterial::alpha_node(float alpha, std::size_t& i, float& t) const {
    i = 0, t = 0.f;
    if (!m_alpha_varies) return;
    const int last = kAlphaNodes - 1;
    const float x =
        std::clamp((std::sqrt(std::max(alpha, 0.f)) - m_s_lo) / m_s_step, 0.f, float(last));
    i = std::size_t(std::min(int(x), last - 1));
    t = x - float(i);
}

namespace {
// Catmull-Rom weights of nodes i - 1 .. i + 2 at t in [0, 1] between nodes i and i + 1, with
// the indices clamped to [0, last] (the end nodes repeated). The weights sum to 1 and reproduce
// the node at t = 0, so any table that is linear in the node tables (a table's average) is
// interpolated consistently with it; the error is O(h^4) against linear's O(h^2).
struct CubicNodes {
    std::size_t i[4];
    float w[4];
};
CubicNodes cubic_nodes(std::size_t i, float t, std::size_t last) {
    const float t2 = t * t, t3 = t2 * t;
    CubicNodes c;
    c.i[0] = i == 0 ? 0 : i - 1, c.i[1] = i, c.i[2] = std::min(i + 1, last);
    c.i[3] = std::min(i + 2, last);
    c.w[0] = 0.5f * (-t3 + 2.f * t2 - t);
    c.w[1] = 0.5f * (3.f * t3 - 5.f * t2 + 2.f);
    c.w[2] = 0.5f * (-3.f * t3 + 4.f * t2 + t);
    c.w[3] = 0.5f * (t3 - t2);
    return c;
}
}  // namespace

MicrofacetReflection::Compensation StagedMaterial::glossy_compensation(std::size_t i,
                                                                       float t) const {
    if (!m_alpha_varies) return m_comp[0];
    const CubicNodes n = cubic_nodes(i, t, m_comp.size() - 1);
    MicrofacetReflection::Compensation c;
    c.e.fill(0.f);
    c.e_avg = 0.f;
    for (int j = 0; j < 4; ++j) {
        const MicrofacetReflection::Compensation& cj = m_comp[n.i[j]];
        for (std::size_t k = 0; k < c.e.size(); ++k) c.e[k] += n.w[j] * cj.e[k];
        c.e_avg += n.w[j] * cj.e_avg;
    }
    return c;
}

DielectricBxDF::Compensation StagedMaterial::dielectric_compensation(std::size_t i, float t) const {
    if (!m_alpha_varies) return m_dcomp[0];
    // (i, t) on the kAlphaNodes grid, mapped onto the dielectric's finer one.
    const std::size_t last = m_dcomp.size() - 1;
    const float x =
        std::clamp((float(i) + t) * float(last) / float(kAlphaNodes - 1), 0.f, float(last));
    const std::size_t j = std::min(std::size_t(x), last - 1);
    const CubicNodes n = cubic_nodes(j, x - float(j), last);
    DielectricBxDF::Compensation c;
    c.e.fill(0.f);
    c.e_avg[0] = c.e_avg[1] = 0.f;
    for (int j = 0; j < 4; ++j) {
        const DielectricBxDF::Compensation& cj = m_dcomp[n.i[j]];
        for (std::size_t k = 0; k < c.e.size(); ++k) c.e[k] += n.w[j] * cj.e[k];
        for (int side = 0; side < 2; ++side) c.e_avg[side] += n.w[j] * cj.e_avg[side];
    }
    return c;
}

StagedMaterial::Values StagedMaterial::constants() const {
    Values v;
    const Material& b = m_base;
    switch (m_family) {
        case Family::Lambert:
            v.rho = b.diffuse()->rho();
            break;
        case Family::OrenNayar:
            v.rho = b.oren_nayar()->rho(), v.sigma = b.oren_nayar()->sigma();
            break;
        case Family::Mirror:
            v.rho = b.mirror()->scale(), v.fr = b.mirror()->fresnel();
            break;
        case Family::Microfacet:
            v.rho = b.glossy()->scale(), v.fr = b.glossy()->fresnel();
            v.dist = b.glossy()->distribution(), v.ec = b.glossy()->energy_compensation();
            break;
        case Family::Dielectric:
            v.eta = b.dielectric()->eta(), v.tr = b.dielectric()->transmittance();
            v.dist = b.dielectric()->distribution(), v.ec = b.dielectric()->energy_compensation();
            break;
        case Family::ThinDielectric:
            v.eta = b.thin_dielectric()->eta(), v.tr = b.thin_dielectric()->transmittance();
            break;
        case Family::Composite:
            if (b.diffuse()) v.kd = b.diffuse()->rho();
            if (b.mirror()) v.km = b.mirror()->scale(), v.fr = b.mirror()->fresnel();
            if (b.glossy()) {
                v.ks = b.glossy()->scale(), v.fr = b.glossy()->fresnel();
                v.dist = b.glossy()->distribution(), v.ec = b.glossy()->energy_compensation();
            }
            break;
        case Family::Principled:
            break;
    }
    return v;
}

Material StagedMaterial::at(std::span<const DVec3> values, Children children) const {
    if (m_unit) {
        ParamValues v = m_unit_values;
        for (std::size_t i = 0; i < m_unit_slots.size(); ++i) v[m_unit_slots[i]] = values[i];
        return m_unit->make(v, children);
    }
    if (m_family == Family::Principled) {
        PrincipledParams p = m_base.principled()->params();
        for (std::size_t i = 0; i < m_slots.size(); ++i) {
            if (m_slots[i].color)
                p.*m_slots[i].color = Rgb(values[i]);
            else
                p.*m_slots[i].number = float(values[i].x);
        }
        return Material(std::in_place_type<PrincipledBxDF>, p);
    }
    Values v = m_constants;
    for (std::size_t i = 0; i < m_slots.size(); ++i) {
        const DVec3& x = values[i];
        switch (m_slots[i].param) {
            case Param::Reflectance:
                v.rho = Rgb(x);
                break;
            case Param::Sigma:
                v.sigma = float(x.x);
                break;
            case Param::Alpha:
                v.alpha = float(x.x), v.alpha_set = true;
                break;
            case Param::F0:
                v.fr = Fresnel::schlick(Rgb(x));
                break;
            case Param::Ior:
                v.eta = float(x.x);
                v.fr = Fresnel::dielectric(v.eta);
                break;
            case Param::Transmittance:
                v.tr = Rgb(x);
                break;
            case Param::Diffuse:
                v.kd = Rgb(x);
                break;
            case Param::Glossy:
                v.ks = Rgb(x);
                break;
            case Param::Mirror:
                v.km = Rgb(x);
                break;
            case Param::PrincipledColor:
            case Param::PrincipledNumber:
                break;
        }
    }
    if (v.alpha_set) v.dist = isotropic(v.dist.kind(), v.alpha);
    switch (m_family) {
        case Family::Lambert:
            return Material(LambertReflection(v.rho), std::nullopt, std::nullopt);
        case Family::OrenNayar:
            return Material(InlineBxDF(OrenNayarReflection(v.rho, v.sigma)));
        case Family::Mirror:
            return Material(std::nullopt, std::nullopt, MirrorReflection(v.fr, v.rho));
        case Family::Microfacet: {
            if (m_comp.empty())
                return Material(std::nullopt, MicrofacetReflection(v.dist, v.fr, v.rho, v.ec),
                                std::nullopt);
            std::size_t i;
            float t;
            alpha_node(v.alpha, i, t);
            return Material(std::nullopt,
                            MicrofacetReflection(v.dist, v.fr, v.rho, glossy_compensation(i, t),
                                                 m_f_avg_const ? &m_f_avg : nullptr),
                            std::nullopt);
        }
        case Family::Dielectric: {
            if (m_dcomp.empty()) return Material(DielectricBxDF(v.eta, v.tr, v.dist, v.ec));
            std::size_t i;
            float t;
            alpha_node(v.alpha, i, t);
            return Material(DielectricBxDF(v.eta, v.tr, v.dist, dielectric_compensation(i, t)));
        }
        case Family::ThinDielectric:
            return Material(ThinDielectricBxDF(v.eta, v.tr));
        case Family::Composite:
            return composite_at(v);
        case Family::Principled:
            break;
    }
    return m_base;
}

Material StagedMaterial::composite_at(const Values& v) const {
    std::size_t i = 0;
    float t = 0.f;
    alpha_node(v.alpha, i, t);
    MicrofacetReflection::Compensation comp;
    Material::CompositeTables tables;
    if (!m_comp.empty()) {
        comp = glossy_compensation(i, t);
        tables.compensation = &comp;
        if (m_f_avg_const) tables.f_avg = &m_f_avg;
    }
    Material::AlbedoRef eg;
    tables.eg_ref = &eg;
    if (!m_glossy_varies) {
        eg.b0 = &m_eg_const, eg.direct = true;
        if (m_es_avg_const) tables.es_avg = &m_es_const;
        return Material::composite(v.kd, v.ks, v.km, v.dist, v.fr, v.ec, tables);
    }
    // Eg = ks (f0 A + B), A and B interpolated linearly in sqrt(alpha) (header comment), read
    // from the tables at the nodes a lookup needs (Material::AlbedoRef), and Es_avg from the
    // tables' averages the same way.
    const std::size_t j = m_alpha_varies ? i + 1 : i;
    eg.b0 = &m_eg_b[i], eg.b1 = &m_eg_b[j], eg.t = t, eg.ks = v.ks;
    const Rgb f0 = m_f0_varies ? v.fr.f0() : Rgb(0.f);
    Rgb es_avg = v.ks * (m_hb[i] + t * (m_hb[j] - m_hb[i])) + v.km * (f0 * m_hm_a + m_hm_b);
    if (m_f0_varies) {
        eg.a0 = &m_eg_a[i], eg.a1 = &m_eg_a[j], eg.f0 = f0;
        es_avg += v.ks * f0 * (m_ha[i] + t * (m_ha[j] - m_ha[i]));
    }
    tables.es_avg = &es_avg;
    return Material::composite(v.kd, v.ks, v.km, v.dist, v.fr, v.ec, tables);
}

}  // namespace facet
