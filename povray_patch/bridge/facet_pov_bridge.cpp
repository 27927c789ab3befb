// The bridge between POV-Ray and the Facet core (see facet_pov_bridge.h). This file includes
// Facet core headers and no POV-Ray header. The BRDF math is the core's; this file only
// translates parameters and frames.
#include "facet_pov_bridge.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <set>
#include <vector>

#include "facet/frame.h"
#include "facet/material.h"
#include "facet/pov_classic.h"
#include "facet/quadrature.h"
#include "facet/registry.h"
#include "facet/render/sampler.h"  // header-only part: the renderer's Owen-scrambled Sobol
#include "facet/types.h"

namespace facet_pov {

// A brdf finish's core material, as POV-Ray's three estimators see it: a "diffuse" part that
// lights, the sky and radiosity shade (tinted by the pigment), a "glossy" part that lights and
// the sky shade and importance-sampled rays trace, and "mirror" (delta) parts that POV-Ray's
// reflection rays trace with their weight at wo.
//  - lambert, the microfacet models, mirror, composite: the Material's own lobes (its diffuse
//    lobe with the energy-sharing weight of facet/material.h).
//  - principled (reflection part): the core's PrincipledBxDF split by PrincipledBxDF::only
//    into the cosine lobe (Disney diffuse + sheen), the non-delta specular + clearcoat, and
//    each delta lobe alone (f of the model is the sum of the parts). Its colours are its own
//    parameters (base_color, ...): the pigment does not tint it.
//  - a model unit's lobe (facet/inline_bxdf.h: oren_nayar, velvet): the diffuse part alone,
//    tinted by the pigment (f is linear in its colour, ModelInfo::diffuse_param).
class Brdf {
  public:
    explicit Brdf(facet::Material m, int samples) : m_material(std::move(m)), m_samples(samples) {
        if (const auto& p = m_material.principled()) {
            init_principled(*p);
            return;
        }
        if (m_material.unit()) {
            // A model unit's one reflection lobe (oren_nayar, velvet): the diffuse part.
            m_split = true;
            m_tinted = true;
            m_diffuse_part.emplace(m_material);
            init_albedo_table();
            m_diffuse = false;
            for (const facet::Rgb& a : m_albedo) m_diffuse |= facet::max_component(a) > 0.f;
            return;
        }
        const auto& g = m_material.glossy();
        // Lobes of zero weight are left out (no light calls, no rays for them).
        const bool g_on = g && facet::max_component(g->scale()) > 0.f;
        m_glossy = g_on && !facet::is_specular(g->flags());
        const auto& mi = m_material.mirror();
        m_mirror = (mi && facet::max_component(mi->scale()) > 0.f) || (g_on && !m_glossy);
        const auto& d = m_material.diffuse();
        m_diffuse = d && facet::max_component(d->rho()) > 0.f;
    }
    // A converted classic finish (facet/pov_classic.h): the split parts of its lobes.
    Brdf(facet::pov::ClassicConversion c, facet::pov::ClassicLobes lobes)
        : m_material(lobes.diffuse), m_samples(c.glossy_samples), m_classic(std::move(c)) {
        m_split = true;
        m_tinted = true;
        if (m_classic->diffuse > 0.0) m_diffuse_part.emplace(std::move(lobes.diffuse));
        if (lobes.glossy) m_glossy_part.emplace(std::move(*lobes.glossy));
        m_mirror_parts = std::move(lobes.mirrors);
        m_diffuse = m_diffuse_part.has_value();
        m_glossy = m_glossy_part.has_value();
        m_mirror = !m_mirror_parts.empty();
        m_albedo.fill(facet::Rgb(1.f));  // Lambert rho = 1: albedo 1 at every angle
    }
    const facet::Material& material() const { return m_material; }
    // The conversion of a classic finish, or none for a brdf block.
    const std::optional<facet::pov::ClassicConversion>& classic() const { return m_classic; }
    // The diffuse part's factor at cos theta_o = mu beyond the pigment (classic: diffuse_at).
    float diffuse_scale(float mu) const {
        return m_classic ? float(m_classic->diffuse_at(mu)) : 1.f;
    }
    // The mirror part k's colour (classic: its reflection colour; else 1).
    facet::Rgb mirror_colour(std::size_t k) const {
        if (!m_classic) return facet::Rgb(1.f);
        const auto& c = m_classic->mirrors[k].colour;
        return facet::Rgb(float(c[0]), float(c[1]), float(c[2]));
    }
    // POV-Ray's metallic tint of the glossy lobe lit from cos theta_i (1 for a brdf block).
    facet::Rgb glossy_tint(const float pigment[3], float cos_i) const {
        if (!m_classic || m_classic->metallic <= 0.0) return facet::Rgb(1.f);
        facet::Rgb t;
        for (int c = 0; c < 3; ++c)
            t[c] = float(facet::pov::metallic_tint(m_classic->metallic, pigment[c], cos_i));
        return t;
    }
    bool glossy() const { return m_glossy; }  // a non-delta glossy lobe
    bool mirror() const { return m_mirror; }  // a mirror lobe or a smooth glossy lobe
    bool diffuse() const { return m_diffuse; }
    int samples() const { return m_samples; }

    // The split parts (split() true: principled, a model unit's lobe).
    bool split() const { return m_split; }
    bool tinted() const { return m_tinted; }
    const std::optional<facet::Material>& diffuse_part() const { return m_diffuse_part; }
    const std::optional<facet::Material>& glossy_part() const { return m_glossy_part; }
    const std::vector<facet::Material>& mirror_parts() const { return m_mirror_parts; }
    // Directional albedo of the diffuse part at cos theta_o = mu (linear in mu_k = k / (n - 1)).
    facet::Rgb diffuse_part_albedo(float mu) const {
        const float x = std::clamp(mu, 0.f, 1.f) * float(kAlbedoNodes - 1);
        const int k = std::min(int(x), kAlbedoNodes - 2);
        const float t = x - float(k);
        return m_albedo[k] * (1.f - t) + m_albedo[k + 1] * t;
    }

  private:
    static constexpr int kAlbedoNodes = 33;

    void init_principled(const facet::PrincipledBxDF& p) {
        using P = facet::PrincipledBxDF;
        m_split = true;
        if (p.has_lobe(P::kCosine)) m_diffuse_part.emplace(p.only(1u << P::kCosine));
        unsigned glossy = 0;
        for (P::Lobe k : {P::kSpecular, P::kClearcoat}) {
            if (!p.has_lobe(k)) continue;
            if (p.lobe_is_delta(k))
                m_mirror_parts.emplace_back(p.only(1u << k));
            else
                glossy |= 1u << k;
        }
        if (glossy) m_glossy_part.emplace(p.only(glossy));
        m_diffuse = m_diffuse_part.has_value();
        m_glossy = m_glossy_part.has_value();
        m_mirror = !m_mirror_parts.empty();
        init_albedo_table();
    }

    // The diffuse part's albedo int f cos dwi at mu_k: Gauss-Legendre over cos theta_i in
    // [0, 1] and over phi_i in [0, pi] (the lobes are isotropic, so f is even in phi_i - phi_o)
    // of the core's f (facet/quadrature.h; the reflectance module has no principled maps):
    // radiosity's reflectance. The lobes are smooth (Disney diffuse, sheen's (1 - cos)^5,
    // Oren-Nayar), so 24 x 24 nodes are well within the radiosity cache's own error.
    void init_albedo_table() {
        if (!m_diffuse_part) return;
        const facet::QuadratureRule& q = facet::gauss_legendre(24);
        for (int k = 0; k < kAlbedoNodes; ++k) {
            const float mu = std::max(1e-3f, float(k) / float(kAlbedoNodes - 1));
            const facet::Vec3 wo(std::sqrt(std::max(0.f, 1.f - mu * mu)), 0.f, mu);
            facet::DVec3 sum(0.0);
            for (std::size_t a = 0; a < q.nodes.size(); ++a) {
                const double c = q.nodes[a], s = std::sqrt(std::max(0.0, 1.0 - c * c));
                for (std::size_t b = 0; b < q.nodes.size(); ++b) {
                    const double phi = facet::kPiD * q.nodes[b];
                    const facet::Vec3 wi(float(s * std::cos(phi)), float(s * std::sin(phi)),
                                         float(c));
                    const facet::Rgb f = m_diffuse_part->f(wo, wi);
                    // dwi = dcos dphi over [0, 1] x [0, 2 pi]: 2 pi, halved by the symmetry
                    sum += (q.weights[a] * q.weights[b] * c * 2.0 * facet::kPiD) *
                           facet::DVec3(f.x, f.y, f.z);
                }
            }
            m_albedo[k] = facet::Rgb(float(sum.x), float(sum.y), float(sum.z));
        }
    }

    facet::Material m_material;
    int m_samples;
    bool m_glossy = false;
    bool m_mirror = false;
    bool m_diffuse = false;
    bool m_split = false;
    bool m_tinted = false;
    std::optional<facet::Material> m_diffuse_part, m_glossy_part;
    std::vector<facet::Material> m_mirror_parts;
    std::array<facet::Rgb, kAlbedoNodes> m_albedo{};
    std::optional<facet::pov::ClassicConversion> m_classic;
};

namespace {

// Every Brdf lives until the process ends: FINISH structs (malloc'ed, struct-copied, freed by a
// macro) hold plain pointers to them. A scene builds a handful, so nothing is reclaimed.
std::mutex g_mutex;
std::vector<std::unique_ptr<Brdf>>& all_brdfs() {
    static std::vector<std::unique_ptr<Brdf>> brdfs;
    return brdfs;
}

constexpr int kDefaultGlossySamples = 8;

const Brdf* keep(std::unique_ptr<Brdf> b) {
    std::lock_guard<std::mutex> lock(g_mutex);
    all_brdfs().push_back(std::move(b));
    return all_brdfs().back().get();
}

facet::Vec3 to_vec(const double v[3]) {
    return {float(v[0]), float(v[1]), float(v[2])};
}

const facet::ParamInfo* find_param(const facet::ModelInfo& m, const char* name) {
    for (const auto& p : m.params)
        if (p.name == name) return &p;
    return nullptr;
}

std::string quoted_list(const std::vector<std::string>& names) {
    std::string s;
    for (std::size_t i = 0; i < names.size(); ++i) {
        if (i) s += ", ";
        s += "'" + names[i] + "'";
    }
    return s;
}

// The models a brdf finish takes: the core's reflection models, and principled (its reflection
// part: transmission > 0 is an error naming that parameter, see build()). A transmissive model
// (dielectric, thin_dielectric) would need POV-Ray's interior and refraction (docs/povray.md),
// so it is not offered, and naming one reads like any other unknown model.
bool reflection_model(const std::string& name) {
    // Combinations (mix, add) need sub-materials, which the finish syntax does not give.
    const facet::ModelInfo* m = facet::find_model(name);
    return m && m->pov_finish;
}

}  // namespace

std::string model_list() {
    std::vector<std::string> names;
    for (const auto& m : facet::model_table())
        if (reflection_model(m.name)) names.push_back(m.name);
    return quoted_list(names);
}

bool is_model(const char* name) {
    return facet::find_model(name) != nullptr && reflection_model(name);
}

ParamKind param_kind(const char* model, const char* param, std::string& message) {
    const facet::ModelInfo* m = facet::find_model(model);
    if (!m) {
        message = "unknown model '" + std::string(model) + "'";
        return ParamKind::Unknown;
    }
    if (const facet::ParamInfo* p = find_param(*m, param)) {
        switch (p->type) {
            case facet::ParamType::Number:
                return ParamKind::Number;
            case facet::ParamType::Color:
                return ParamKind::Colour;
            case facet::ParamType::String:
                return ParamKind::Word;
            case facet::ParamType::Bool:
                return ParamKind::Bool;
            case facet::ParamType::Materials:
                break;  // combinations are not finish models (reflection_model)
        }
    }
    std::vector<std::string> names;
    for (const auto& p : m->params) names.push_back(p.name);
    message = "unknown parameter '" + std::string(param) + "' for model '" + m->name + "'";
    std::string guess = facet::closest_name(param, names);
    if (!guess.empty()) message += " (did you mean '" + guess + "'?)";
    message += "; its parameters are " + quoted_list(names);
    return ParamKind::Unknown;
}

std::string word_choices(const char* model, const char* param) {
    const facet::ModelInfo* m = facet::find_model(model);
    const facet::ParamInfo* p = m ? m->param(param) : nullptr;
    return p ? quoted_list(p->choices) : std::string();
}

struct BrdfBuilder::Impl {
    std::string model;
    facet::ParamSet params;
    int samples = kDefaultGlossySamples;
};

BrdfBuilder::BrdfBuilder(const char* model) : m_impl(new Impl{model, {}, kDefaultGlossySamples}) {}
BrdfBuilder::~BrdfBuilder() {
    delete m_impl;
}

bool BrdfBuilder::set_number(const char* name, double v) {
    if (m_impl->params.has(name)) return false;
    m_impl->params.set(name, v);
    return true;
}
bool BrdfBuilder::set_colour(const char* name, double r, double g, double b) {
    if (m_impl->params.has(name)) return false;
    m_impl->params.set(name, facet::Rgb(float(r), float(g), float(b)));
    return true;
}
bool BrdfBuilder::set_word(const char* name, const char* word) {
    if (m_impl->params.has(name)) return false;
    m_impl->params.set(name, std::string(word));
    return true;
}
bool BrdfBuilder::set_bool(const char* name, bool v) {
    if (m_impl->params.has(name)) return false;
    m_impl->params.set(name, v);
    return true;
}
void BrdfBuilder::set_glossy_samples(int n) {
    m_impl->samples = n;
}

const Brdf* BrdfBuilder::build(std::string& message, std::string& param) {
    try {
        facet::ParamSet params = m_impl->params;
        // In POV-Ray the pigment is the diffuse reflectance (as with classic `diffuse`): the
        // diffuse reflectance parameter is a factor on it, 1 unless given.
        const facet::ModelInfo* info = facet::find_model(m_impl->model);
        if (info && !info->diffuse_param.empty() && !params.has(info->diffuse_param))
            params.set(info->diffuse_param, 1.0);
        facet::Material m = facet::make_material(m_impl->model, params);
        // The brdf finish is reflection only; transmission in POV-Ray stays with its own
        // interior (docs/povray.md).
        if (m.principled() && m.transmissive())
            throw facet::ParamError("transmission",
                                    "parameter 'transmission' of model 'principled': the brdf "
                                    "finish is reflection only; transmission is POV-Ray's "
                                    "interior (ior) with refraction (docs/povray.md)");
        if (m.transmissive())
            throw facet::ParamError("", "model '" + m_impl->model +
                                            "' transmits light: the brdf finish is reflection "
                                            "only (use POV-Ray's interior and refraction)");
        return keep(std::make_unique<Brdf>(std::move(m), m_impl->samples));
    } catch (const facet::ParamError& e) {
        message = e.what();
        param = e.param();
    } catch (const std::exception& e) {
        message = e.what();
        param.clear();
    }
    return nullptr;
}

const Brdf* convert_classic(const ClassicFinish& f, std::vector<ClassicNote>& notes) {
    facet::pov::ClassicFinish in;
    in.diffuse = f.diffuse;
    in.diffuse_back = f.diffuse_back;
    in.brilliance = f.brilliance;
    in.phong = f.phong;
    in.phong_size = f.phong_size;
    in.specular = f.specular;
    in.specular_exponent = f.specular_exponent;
    in.metallic = f.metallic;
    for (int c = 0; c < 3; ++c) {
        in.reflection_min[c] = f.reflection_min[c];
        in.reflection_max[c] = f.reflection_max[c];
    }
    in.reflection_fresnel = f.reflection_fresnel;
    in.reflection_falloff = f.reflection_falloff;
    in.reflection_exponent = f.reflection_exponent;
    in.ior = f.ior;
    in.irid = f.irid;
    in.crand = f.crand;
    in.subsurface = f.subsurface;
    // Scenes copy a few finishes many times (a macro's texture per object): equal inputs share
    // one conversion.
    static std::map<facet::pov::ClassicFinish, std::pair<const Brdf*, std::vector<ClassicNote>>>
        done;
    {
        std::lock_guard<std::mutex> lock(g_mutex);
        if (auto it = done.find(in); it != done.end()) {
            notes = it->second.second;
            return it->second.first;
        }
    }
    facet::pov::ClassicConversion c = facet::pov::convert_classic(in);
    notes.clear();
    for (const facet::pov::ClassicNote& n : c.notes)
        notes.push_back({n.level == facet::pov::ClassicNote::Level::Approximated, n.kind});
    const Brdf* b = nullptr;
    if (c.converted) {
        facet::pov::ClassicLobes lobes = facet::pov::classic_lobes(c);
        b = keep(std::make_unique<Brdf>(std::move(c), std::move(lobes)));
    }
    std::lock_guard<std::mutex> lock(g_mutex);
    done.emplace(in, std::make_pair(b, notes));
    return b;
}

void folded_glossy_weight(const Brdf* b, const double n[3], const double wo[3],
                          const float pigment[3], float out[3]) {
    out[0] = out[1] = out[2] = 0.f;
    const auto& c = b->classic();
    if (!c || !c->glossy_folded) return;
    const float mu = glm::dot(to_vec(n), to_vec(wo));
    if (!(mu > 0.f)) return;
    const facet::Rgb w = float(c->glossy_albedo_at(mu)) * b->glossy_tint(pigment, mu);
    out[0] = w.x;
    out[1] = w.y;
    out[2] = w.z;
}

const char* intern(const char* text) {
    static std::set<std::string> texts;
    std::lock_guard<std::mutex> lock(g_mutex);
    return texts.insert(text).first->c_str();
}

bool is_converted(const Brdf* b) {
    return b->classic().has_value();
}

void glossy_tint(const Brdf* b, const double n[3], const double wi[3], const float pigment[3],
                 float out[3]) {
    const float cos_i = glm::dot(to_vec(n), to_vec(wi));
    const facet::Rgb t = b->glossy_tint(pigment, cos_i);
    out[0] = t.x;
    out[1] = t.y;
    out[2] = t.z;
}

bool lit_by_lights(const Brdf* b) {
    return b->diffuse() || b->glossy();
}
bool has_glossy(const Brdf* b) {
    return b->glossy();
}
bool has_mirror(const Brdf* b) {
    return b->mirror();
}

void shade(const Brdf* b, const double n[3], const double wo[3], const double wi[3],
           const float tint[3], bool glossy, float out[3]) {
    out[0] = out[1] = out[2] = 0.f;
    const facet::Frame frame = facet::Frame::from_z(to_vec(n));
    const facet::Vec3 o = frame.to_local(to_vec(wo)), i = frame.to_local(to_vec(wi));
    if (!(o.z > 0.f) || !(i.z > 0.f)) return;
    const facet::Material& m = b->material();
    facet::Rgb r(0.f);
    if (b->split()) {
        if (const auto& d = b->diffuse_part())
            r += d->f(o, i) * b->diffuse_scale(o.z) *
                 (b->tinted() ? facet::Rgb(tint[0], tint[1], tint[2]) : facet::Rgb(1.f));
        if (glossy && b->glossy()) r += b->glossy_part()->f(o, i) * b->glossy_tint(tint, i.z);
    } else {
        if (m.diffuse()) r += m.diffuse_f(o, i) * facet::Rgb(tint[0], tint[1], tint[2]);
        if (glossy && b->glossy()) r += m.glossy()->f(o, i);
    }
    r *= facet::kPi * i.z;
    if (!facet::is_finite(r)) return;
    out[0] = r.x;
    out[1] = r.y;
    out[2] = r.z;
}

void diffuse_albedo(const Brdf* b, const double n[3], const double wo[3], const float tint[3],
                    float out[3]) {
    out[0] = out[1] = out[2] = 0.f;
    const facet::Material& m = b->material();
    facet::Vec3 nn = to_vec(n), o = to_vec(wo);
    float mu = std::clamp(glm::dot(nn, o), 0.f, 1.f);
    if (b->split()) {
        if (!b->diffuse_part()) return;
        const facet::Rgb a = b->diffuse_part_albedo(mu) * b->diffuse_scale(mu);
        for (int c = 0; c < 3; ++c) out[c] = std::max(0.f, a[c] * (b->tinted() ? tint[c] : 1.f));
        return;
    }
    if (!m.diffuse()) return;
    // int f_d cos dwi = rho_d (1 - Es(wo)) (facet/material.h: 2 int (1 - Es) mu dmu = 1 - Es_avg).
    facet::Rgb a = m.diffuse()->rho() * (facet::Rgb(1.f) - m.specular_albedo(mu));
    for (int c = 0; c < 3; ++c) out[c] = std::max(0.f, a[c] * tint[c]);
}

void mirror_weight(const Brdf* b, const double n[3], const double wo[3], float out[3]) {
    out[0] = out[1] = out[2] = 0.f;
    const facet::Material& m = b->material();
    float mu = std::clamp(glm::dot(to_vec(n), to_vec(wo)), 0.f, 1.f);
    facet::Rgb w(0.f);
    if (b->split()) {
        // Each delta part alone: its one sample is the mirror direction with weight f cos / pdf
        // (pdf 1, the only lobe), i.e. the lobe's reflectance at wo.
        const facet::Frame frame = facet::Frame::from_z(to_vec(n));
        const facet::Vec3 o = frame.to_local(to_vec(wo));
        if (o.z > 0.f)
            for (std::size_t k = 0; k < b->mirror_parts().size(); ++k)
                if (auto s = b->mirror_parts()[k].sample_f(o, 0.5f, facet::Vec2(0.5f));
                    s && s->pdf > 0.f && s->wi.z > 0.f) {
                    const facet::Rgb r = s->f * (s->wi.z / s->pdf) * b->mirror_colour(k);
                    if (facet::is_finite(r)) w += r;
                }
        out[0] = w.x;
        out[1] = w.y;
        out[2] = w.z;
        return;
    }
    if (m.mirror()) w += m.mirror()->reflectance(mu);
    if (m.glossy() && !b->glossy())  // a smooth glossy lobe is the mirror (facet/microfacet.h)
        w += m.glossy()->scale() * m.glossy()->fresnel().eval(mu);
    out[0] = w.x;
    out[1] = w.y;
    out[2] = w.z;
}

bool sample_glossy(const Brdf* b, const double n[3], const double wo[3], const double u[3],
                   double wi[3], float weight[3]) {
    if (!b->glossy()) return false;
    const facet::Frame frame = facet::Frame::from_z(to_vec(n));
    const facet::Vec3 o = frame.to_local(to_vec(wo));
    if (!(o.z > 0.f)) return false;
    const facet::Vec2 u12{float(u[1]), float(u[2])};
    auto s = b->split() ? b->glossy_part()->sample_f(o, float(u[0]), u12)
                        : b->material().glossy()->sample_f(o, float(u[0]), u12);
    if (!s || !(s->pdf > 0.f) || !(s->wi.z > 0.f)) return false;
    facet::Rgb w = s->f * (s->wi.z / s->pdf);
    if (!facet::is_finite(w) || !(facet::max_component(w) > 0.f)) return false;
    facet::Vec3 d = frame.from_local(s->wi);
    wi[0] = d.x;
    wi[1] = d.y;
    wi[2] = d.z;
    weight[0] = w.x;
    weight[1] = w.y;
    weight[2] = w.z;
    return true;
}

double glossy_pdf(const Brdf* b, const double n[3], const double wo[3], const double wi[3]) {
    if (!b->glossy()) return 0.0;
    const facet::Frame frame = facet::Frame::from_z(to_vec(n));
    const facet::Vec3 o = frame.to_local(to_vec(wo)), i = frame.to_local(to_vec(wi));
    if (!(o.z > 0.f) || !(i.z > 0.f)) return 0.0;
    const float p = b->split() ? b->glossy_part()->pdf(o, i) : b->material().glossy()->pdf(o, i);
    return std::isfinite(p) && p > 0.f ? double(p) : 0.0;
}

int glossy_ray_count(const Brdf* b, unsigned trace_level) {
    if (!b->glossy()) return 0;
    if (b->samples() == 0) return 0;
    // A converted classic finish traces its glossy rays at camera hits only (classic scenes are
    // tuned for mirror rays alone; a glossy ray per deeper hit doubles their tree per level).
    if (b->classic()) return trace_level <= 1 ? b->samples() : 0;
    return trace_level <= 1 ? b->samples() : 1;
}

void glossy_sample(unsigned seed, unsigned trace_level, int index, int count, double u[3]) {
    // The renderer's sampler (facet/render/sampler.h): a pure function of (seed, index,
    // dimension); the hit's sequence is seeded by the pixel seed and the trace level.
    (void)count;  // any prefix of the sequence is well stratified
    facet::render::Sampler sampler(facet::render::hash_combine(seed, trace_level),
                                   std::uint32_t(index));
    u[0] = sampler.get_1d();
    const facet::Vec2 uv = sampler.get_2d();
    u[1] = uv.x;
    u[2] = uv.y;
}

unsigned pixel_seed(double x, double y, unsigned sample) {
    std::uint64_t bx, by;
    std::memcpy(&bx, &x, 8);
    std::memcpy(&by, &y, 8);
    std::uint32_t h = facet::render::hash_combine(std::uint32_t(bx), std::uint32_t(bx >> 32));
    h = facet::render::hash_combine(h, std::uint32_t(by));
    h = facet::render::hash_combine(h, std::uint32_t(by >> 32));
    return facet::render::hash_combine(h, sample);
}

}  // namespace facet_pov
