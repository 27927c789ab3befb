#include "facet/material.h"

#include "facet/reflectance.h"

#include <algorithm>
#include <vector>

namespace facet {

namespace {
// Below this, 1 - Es_avg means the specular layers reflect (almost) everything: the diffuse
// lobe then receives nothing, instead of a 0/0 normalisation.
constexpr float kMinDiffuseShare = 1e-6f;

// Exact integral 2 * int_0^1 e(mu) mu dmu of the piecewise-linear interpolant through
// table[k] at mu_k = k/(n-1): the same function f() uses, so the diffuse normalisation is
// consistent to round-off, not only to the table's resolution.
template <size_t N>
Rgb hemispherical_average(const std::array<Rgb, N>& table) {
    DVec3 sum(0.0);
    const double h = 1.0 / double(N - 1);
    for (size_t k = 0; k + 1 < N; ++k) {
        double a = k * h, b = (k + 1) * h;
        DVec3 ea(table[k]), eb(table[k + 1]);
        // int_a^b (ea + (eb - ea)(mu - a)/h) mu dmu
        double i0 = (b * b - a * a) / 2.0;                   // int mu
        double i1 = (b * b * b - a * a * a) / 3.0 - a * i0;  // int (mu - a) mu
        sum += ea * i0 + (eb - ea) * (i1 / h);
    }
    return Rgb(2.0 * sum);
}
}  // namespace

Material::Material(std::optional<LambertReflection> diffuse,
                   std::optional<MicrofacetReflection> glossy,
                   std::optional<MirrorReflection> mirror)
    : m_diffuse(std::move(diffuse)), m_glossy(std::move(glossy)), m_mirror(std::move(mirror)) {
    init();
}

Rgb Material::table_average(const AlbedoTable& table) {
    return hemispherical_average(table);
}

Rgb Material::specular_average(const AlbedoTable& eg, const MirrorReflection* mirror) {
    AlbedoTable es;
    for (int k = 0; k < kTableSize; ++k) {
        float mu = float(k) / float(kTableSize - 1);
        es[k] =
            glm::clamp(eg[k] + (mirror ? mirror->reflectance(mu) : Rgb(0.f)), Rgb(0.f), Rgb(1.f));
    }
    return hemispherical_average(es);
}

void Material::init(const Rgb* es_avg, const AlbedoRef* eg_ref) {
    if (m_diffuse) m_flags = m_flags | BxDFFlags::Diffuse;
    if (m_glossy) m_flags = m_flags | m_glossy->flags();
    if (m_mirror) m_flags = m_flags | BxDFFlags::Specular;
    m_anisotropic =
        m_glossy && m_glossy->distribution().alpha_x() != m_glossy->distribution().alpha_y();

    // The glossy albedo table is needed to weight the diffuse lobe and to choose between lobes;
    // a single-lobe material needs neither.
    int lobes = int(m_diffuse.has_value()) + int(m_glossy.has_value()) + int(m_mirror.has_value());
    if (lobes < 2) return;
    m_has_table = true;
    if (eg_ref && m_glossy && (es_avg || !m_diffuse)) {
        m_eg_ref = *eg_ref;
    } else if (eg_ref && m_glossy) {
        AlbedoTable& eg_own = m_eg.emplace();
        for (int k = 0; k < kTableSize; ++k) eg_own[k] = eg_ref->node(k);
    } else {
        AlbedoTable& eg_own = m_eg.emplace();
        for (int k = 0; k < kTableSize; ++k) {
            float mu = float(k) / float(kTableSize - 1);
            eg_own[k] = m_glossy ? phi_averaged_albedo(*m_glossy, mu) : Rgb(0.f);
        }
    }
    if (m_diffuse) {
        // Given (the staged build's table) or computed from the lobes.
        Rgb one_minus_avg =
            Rgb(1.f) -
            (es_avg ? *es_avg : specular_average(*m_eg, m_mirror ? &*m_mirror : nullptr));
        for (int c = 0; c < 3; ++c)
            m_inv_one_minus_es_avg[c] =
                one_minus_avg[c] > kMinDiffuseShare ? 1.f / one_minus_avg[c] : 0.f;
    }
}

Material Material::composite(const Rgb& kd, const Rgb& ks, const Rgb& km,
                             const MicrofacetDistribution& d, const Fresnel& fr, bool ec,
                             const CompositeTables& t) {
    // One named result (returned without a move: the staged build calls this per hit).
    Material m;
    // Zero-weight lobes are left out, so a material never pays for what it does not show.
    if (max_component(kd) > 0.f) m.m_diffuse.emplace(kd);
    if (max_component(ks) > 0.f) {
        if (ec && t.compensation)
            m.m_glossy.emplace(d, fr, ks, *t.compensation, t.f_avg);
        else
            m.m_glossy.emplace(d, fr, ks, ec);
    }
    if (max_component(km) > 0.f) m.m_mirror.emplace(fr, km);
    if (!m.m_diffuse && !m.m_glossy && !m.m_mirror)
        m.m_diffuse.emplace(Rgb(0.f));  // black: keep a valid lobe
    m.init(t.eg_ref ? t.es_avg : nullptr, t.eg_ref);
    return m;
}

Material Material::composite(const Rgb& kd, const Rgb& ks, const Rgb& km,
                             const MicrofacetDistribution& d, const Fresnel& fr, bool ec) {
    return composite(kd, ks, km, d, fr, ec, CompositeTables{});
}

Material::Material(const DielectricBxDF& dielectric)
    : m_dielectric(dielectric),
      m_flags(dielectric.flags()),
      m_special(true),
      m_anisotropic(dielectric.distribution().alpha_x() != dielectric.distribution().alpha_y()) {}

Material::Material(const ThinDielectricBxDF& thin)
    : m_thin(thin), m_flags(thin.flags()), m_special(true) {}

Material::Material(const InlineBxDF& unit)
    : m_unit(unit), m_flags(unit.flags()), m_special(true), m_anisotropic(unit.reads_tangent()) {}

float Material::Subsurface::probability(const Vec3& wo) const {
    if (!surface) return 1.f;
    const std::optional<PrincipledBxDF>& p = surface->principled();
    const float s = p ? p->sample_weight(wo) : 1.f;
    return weight / (weight + s);
}

Material Material::with_subsurface(Material fallback, Subsurface s) {
    fallback.m_subsurface.emplace(std::move(s));
    return fallback;
}

Material Material::mix(std::shared_ptr<const Material> a, std::shared_ptr<const Material> b,
                       float weight) {
    // The end points are the children themselves: w = 0 renders a exactly, w = 1 b.
    if (weight <= 0.f) return *a;
    if (weight >= 1.f) return *b;
    Material m(std::nullopt, std::nullopt, std::nullopt);
    m.m_combination.emplace(Combination{Combine::Mix, a, b, 1.f - weight, weight, 1.f - weight});
    m.m_flags = a->flags() | b->flags();
    m.m_special = true;
    m.m_anisotropic = a->anisotropic() || b->anisotropic();
    m.m_holdout = std::max(a->m_holdout, b->m_holdout);
    return m;
}

Material Material::mix(std::shared_ptr<const Material> a, std::shared_ptr<const Material> b,
                       MixWeight weight, float param) {
    if (weight == MixWeight::Constant) return mix(std::move(a), std::move(b), param);
    Material m = mix(a, b, 0.5f);
    m.m_combination.emplace(Combination{Combine::Mix, a, b, 0.5f, 0.5f, 0.5f, weight, param});
    return m;
}

float mix_weight(Material::MixWeight kind, float param, const Vec3& wo) {
    using W = Material::MixWeight;
    // Cycles 3.4 (svm_node_fresnel, svm_node_layer_weight): |cos| of the view with the
    // shading normal; the relative IOR inverted on the back side.
    const float c = std::min(std::abs(wo.z), 1.f);
    const bool back = wo.z < 0.f;
    float w = param;
    switch (kind) {
        case W::Constant:
            break;
        case W::Fresnel: {
            const float eta = std::max(param, 1e-5f);
            w = fresnel_dielectric(c, back ? 1.f / eta : eta);
            break;
        }
        case W::LayerFresnel: {
            const float eta = std::max(1.f - param, 1e-5f);
            w = fresnel_dielectric(c, back ? eta : 1.f / eta);
            break;
        }
        case W::LayerFacing: {
            float f = c;
            if (param != 0.5f) {
                const float b = std::clamp(param, 0.f, 1.f - 1e-5f);
                f = std::pow(f, b < 0.5f ? 2.f * b : 0.5f / (1.f - b));
            }
            w = 1.f - f;
            break;
        }
    }
    return std::clamp(w, 0.f, 1.f);
}

Material::Combination::At Material::Combination::at(const Vec3& wo) const {
    if (weight == MixWeight::Constant) return {coef_a, coef_b, prob_a};
    const float w = mix_weight(weight, weight_param, wo);
    return {1.f - w, w, 1.f - w};
}

Material Material::add(std::shared_ptr<const Material> a, std::shared_ptr<const Material> b) {
    Material m(std::nullopt, std::nullopt, std::nullopt);
    // Sampling 50/50: a per-direction albedo estimate of arbitrary children would cost a
    // table per child at every (textured) construction; the pdf stays exact either way.
    m.m_combination.emplace(Combination{Combine::Add, a, b, 1.f, 1.f, 0.5f});
    m.m_flags = a->flags() | b->flags();
    m.m_special = true;
    m.m_anisotropic = a->anisotropic() || b->anisotropic();
    m.m_holdout = a->m_holdout + b->m_holdout;
    return m;
}

Material Material::holdout() {
    Material m(LambertReflection(Rgb(0.f)), std::nullopt, std::nullopt);
    m.m_holdout = 1.f;
    return m;
}

float Material::holdout_weight(const Vec3& wo) const {
    if (!(m_holdout > 0.f)) return 0.f;
    if (!m_combination) return m_holdout;
    const Combination& c = *m_combination;
    const Combination::At at = c.at(wo);
    // (Cycles clamps nothing here either; an `add` of two holdouts is 2, which the film's
    // alpha, clamped to [0, 1], absorbs.)
    return at.coef_a * c.a->holdout_weight(wo) + at.coef_b * c.b->holdout_weight(wo);
}

Material::Material(const PrincipledBxDF& principled)
    : m_principled(principled),
      m_flags(principled.flags()),
      m_special(true),
      m_anisotropic(principled.anisotropic()) {}

Material::Material(std::in_place_type_t<PrincipledBxDF>, const PrincipledParams& params)
    : m_principled(std::in_place, params), m_special(true) {
    m_flags = m_principled->flags();
    m_anisotropic = m_principled->anisotropic();
}

Rgb Material::glossy_albedo(float mu) const {
    if (!m_has_table) return Rgb(0.f);
    float x = clamp_unit(mu) * float(kTableSize - 1);
    int k = std::min(int(x), kTableSize - 2);
    float t = x - float(k);
    if (m_eg_ref.b0) return m_eg_ref.node(k) * (1.f - t) + m_eg_ref.node(k + 1) * t;
    return (*m_eg)[k] * (1.f - t) + (*m_eg)[k + 1] * t;
}

Rgb Material::specular_albedo(float mu) const {
    Rgb e = glossy_albedo(mu);
    if (m_mirror) e += m_mirror->reflectance(glm::clamp(mu, 0.f, 1.f));
    return glm::clamp(e, Rgb(0.f), Rgb(1.f));
}

Rgb Material::diffuse_f(const Vec3& wo, const Vec3& wi) const {
    Rgb f = m_diffuse->f(wo, wi);
    if (!m_has_table) return f;
    return f * diffuse_scale(wo.z) * diffuse_scale(wi.z) * m_inv_one_minus_es_avg;
}

std::array<float, 3> Material::lobe_probabilities(const Vec3& wo) const {
    float mu = glm::clamp(wo.z, 0.f, 1.f);
    std::array<float, 3> w{0.f, 0.f, 0.f};
    // Albedo of each lobe at wo (luminance): diffuse gets rho_d (1 - Es) (see header).
    // Eg(mu) once for both lobes (diffuse_scale reads it too; the same bits).
    const Rgb eg = m_diffuse || m_glossy ? glossy_albedo(mu) : Rgb(0.f);
    if (m_diffuse) {
        Rgb es = eg;  // specular_albedo(mu)
        if (m_mirror) es += m_mirror->reflectance(mu);
        w[0] = luminance(m_diffuse->rho() * (Rgb(1.f) - glm::clamp(es, Rgb(0.f), Rgb(1.f))));
    }
    if (m_glossy) w[1] = luminance(eg);
    if (m_mirror) w[2] = luminance(m_mirror->reflectance(mu));
    float sum = w[0] + w[1] + w[2];
    if (!(sum > 0.f)) {
        // Black at this angle: fall back to uniform over the present lobes so pdf stays
        // defined (the samples then carry f = 0 and are discarded by the caller).
        float n = float(m_diffuse.has_value() + m_glossy.has_value() + m_mirror.has_value());
        return {m_diffuse ? 1.f / n : 0.f, m_glossy ? 1.f / n : 0.f, m_mirror ? 1.f / n : 0.f};
    }
    return {w[0] / sum, w[1] / sum, w[2] / sum};
}

// ---- the rare kinds ----

namespace {
// A reflection-only child of a transmissive combination sees wo from its own side: z mirrored
// when wo is below the shape's frame (header comment).
inline Vec3 flip_z(const Vec3& w) {
    return {w.x, w.y, -w.z};
}
inline bool child_flipped(const Material& parent, const Material& child, const Vec3& wo) {
    return wo.z < 0.f && parent.transmissive() && !child.transmissive();
}
}  // namespace

BSDFEval Material::special_eval(const Vec3& wo, const Vec3& wi, Mode mode) const {
    if (m_dielectric) return m_dielectric->eval(wo, wi, mode);
    if (m_principled) return m_principled->eval(wo, wi, mode);
    if (m_unit) return m_unit->eval(wo, wi);
    if (!m_combination) return {};  // the thin pane: deltas only
    const Combination& cm = *m_combination;
    const Combination::At c = cm.at(wo);
    BSDFEval e;
    for (int k = 0; k < 2; ++k) {
        const Material& child = k == 0 ? *cm.a : *cm.b;
        const bool flip = child_flipped(*this, child, wo);
        const BSDFEval ce =
            flip ? child.eval(flip_z(wo), flip_z(wi), mode) : child.eval(wo, wi, mode);
        e.f += (k == 0 ? c.coef_a : c.coef_b) * ce.f;
        e.pdf += (k == 0 ? c.prob_a : 1.f - c.prob_a) * ce.pdf;
    }
    return e;
}

std::optional<BSDFSample> Material::special_sample_f(const Vec3& wo, float uc, Vec2 u,
                                                     Mode mode) const {
    if (m_dielectric) return m_dielectric->sample_f(wo, uc, u, mode);
    if (m_principled) return m_principled->sample_f(wo, uc, u, mode);
    if (m_thin) return m_thin->sample_f(wo, uc, u, mode);
    if (m_unit) return m_unit->sample_f(wo, uc, u);
    const Combination& cm = *m_combination;
    const Combination::At c = cm.at(wo);
    // Choose a child with uc, then stretch the used part of uc back to [0, 1) for it.
    const bool first = uc < c.prob_a;
    const float p = first ? c.prob_a : 1.f - c.prob_a;
    if (!(p > 0.f)) return std::nullopt;
    const float uc_child =
        std::max(std::min((first ? uc : uc - c.prob_a) / p, kOneMinusEpsilon), 0.f);
    const Material& child = first ? *cm.a : *cm.b;
    const bool flip = child_flipped(*this, child, wo);
    std::optional<BSDFSample> s = child.sample_f(flip ? flip_z(wo) : wo, uc_child, u, mode);
    if (!s) return std::nullopt;
    if (flip) s->wi = flip_z(s->wi);
    if (s->is_specular()) {
        // A delta lobe of the child: its discrete probability times the choice of the child.
        s->f *= first ? c.coef_a : c.coef_b;
        s->pdf *= p;
        return s;
    }
    // One-sample MIS over both children's non-delta lobes.
    const BSDFEval e = special_eval(wo, s->wi, mode);
    if (!(e.pdf > 0.f)) return std::nullopt;
    s->f = e.f;
    s->pdf = e.pdf;
    return s;
}

Rgb Material::f(const Vec3& wo, const Vec3& wi, Mode mode) const {
    // Dielectrics, Oren-Nayar and combinations (the thin pane has only deltas: f = 0).
    if (m_special) [[unlikely]]
        return special_eval(wo, wi, mode).f;
    Rgb result(0.f);
    if (m_diffuse) result += diffuse_f(wo, wi);
    if (m_glossy) result += m_glossy->f(wo, wi);
    return result;  // the mirror is a delta: f = 0 (facet/bxdf.h)
}

float Material::pdf(const Vec3& wo, const Vec3& wi, Mode mode) const {
    if (m_special) [[unlikely]]
        return special_eval(wo, wi, mode).pdf;
    // A single-lobe material is that lobe (probability 1: the same bits as the sum below).
    if (!m_has_table) {
        if (m_diffuse) return m_diffuse->pdf(wo, wi);
        if (m_glossy) return m_glossy->pdf(wo, wi);
        return 0.f;
    }
    auto p = lobe_probabilities(wo);
    float result = 0.f;
    if (m_diffuse && p[0] > 0.f) result += p[0] * m_diffuse->pdf(wo, wi);
    if (m_glossy && p[1] > 0.f) result += p[1] * m_glossy->pdf(wo, wi);
    return result;
}

BSDFEval Material::eval(const Vec3& wo, const Vec3& wi, Mode mode) const {
    if (m_special) [[unlikely]]
        return special_eval(wo, wi, mode);
    // f() and pdf() in one pass: the glossy lobe's D and Lambda and the lobe probabilities are
    // computed once (same arithmetic, so the results equal f() and pdf() bit for bit).
    if (!m_has_table) {  // single lobe, as in pdf()
        if (m_diffuse) return {m_diffuse->f(wo, wi), m_diffuse->pdf(wo, wi)};
        if (m_glossy) return m_glossy->eval(wo, wi);
        return {};
    }
    BSDFEval e;
    auto p = lobe_probabilities(wo);
    if (m_diffuse) {
        e.f += diffuse_f(wo, wi);
        if (p[0] > 0.f) e.pdf += p[0] * m_diffuse->pdf(wo, wi);
    }
    if (m_glossy) {
        BSDFEval g = m_glossy->eval(wo, wi);
        e.f += g.f;
        if (p[1] > 0.f) e.pdf += p[1] * g.pdf;
    }
    return e;
}

std::optional<BSDFSample> Material::sample_f(const Vec3& wo, float uc, Vec2 u, Mode mode) const {
    if (m_special) [[unlikely]]
        return special_sample_f(wo, uc, u, mode);
    if (!(wo.z > 0.f)) return std::nullopt;
    if (!m_has_table) {
        // A single-lobe material is that lobe: it gets uc as the general path below would
        // stretch it (probability 1, offset 0), and its sample as it is.
        const float uc_lobe = std::max(std::min(uc, kOneMinusEpsilon), 0.f);
        if (m_diffuse) return m_diffuse->sample_f(wo, uc_lobe, u);
        if (m_glossy) return m_glossy->sample_f(wo, uc_lobe, u);
        if (m_mirror) return m_mirror->sample_f(wo, uc_lobe, u);
        return std::nullopt;
    }
    auto p = lobe_probabilities(wo);
    // Choose a lobe with uc, then stretch the used part of uc back to [0, 1) for the lobe.
    int lobe = 0;
    float lo = 0.f;
    if (uc >= p[0]) {
        lobe = 1, lo = p[0];
        if (uc >= p[0] + p[1]) lobe = 2, lo = p[0] + p[1];
    }
    while (!(p[lobe] > 0.f)) {  // round-off put uc on an empty lobe: take the previous one
        if (--lobe < 0) return std::nullopt;
        lo = 0.f;
        for (int k = 0; k < lobe; ++k) lo += p[k];
    }
    float uc_lobe = std::min((uc - lo) / p[lobe], kOneMinusEpsilon);
    uc_lobe = std::max(uc_lobe, 0.f);

    std::optional<BSDFSample> s;
    if (lobe == 0)
        s = m_diffuse->sample_f(wo, uc_lobe, u);
    else if (lobe == 1)
        s = m_glossy->sample_f(wo, uc_lobe, u);
    else
        s = m_mirror->sample_f(wo, uc_lobe, u);
    if (!s) return std::nullopt;

    if (s->is_specular()) {
        // Discrete choice of a delta lobe: pdf is its selection probability.
        s->pdf *= p[lobe];
        return s;
    }
    // One-sample MIS over the non-delta lobes: full f and the mixture pdf.
    const BSDFEval e = eval(wo, s->wi);
    s->f = e.f;
    s->pdf = e.pdf;
    if (!(s->pdf > 0.f)) return std::nullopt;
    return s;
}

std::shared_ptr<const Material> pooled_material(Material m) {
    // Searched from the back, a few entries deep: the entries a long-lived material keeps (a
    // constant material built at scene load on this thread) stay behind the ones per-hit
    // builds release.
    constexpr std::size_t kSearch = 16;
    thread_local std::vector<std::shared_ptr<Material>> pool;
    for (std::size_t k = 0; k < std::min(pool.size(), kSearch); ++k) {
        std::shared_ptr<Material>& slot = pool[pool.size() - 1 - k];
        if (slot.use_count() != 1) continue;
        *slot = std::move(m);
        return slot;
    }
    pool.push_back(std::make_shared<Material>(std::move(m)));
    return pool.back();
}

}  // namespace facet
