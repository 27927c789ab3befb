// The model table: names, parameters, defaults, ranges and the builders. This table is the
// documentation of the models too (docs/models.md is printed from it by
// `facet brdf models --markdown`).
#include "facet/registry.h"

#include <algorithm>
#include <functional>
#include <set>
#include <sstream>

namespace facet {

namespace {

// ---------------------------------------------------------------------------------------------
// Parameter table

constexpr double kMaxAlpha = 10.0;    // GGX/Beckmann alpha = RMS slope-ish; > 10 is meaningless
constexpr double kMaxExponent = 1e9;  // Blinn kappa; 1e9 is far past the mirror threshold
constexpr double kMaxIor = 100.0;

ParamInfo number(std::string name, std::string def, std::string doc) {
    return {std::move(name), ParamType::Number, std::move(def), std::move(doc)};
}
ParamInfo color(std::string name, std::string def, std::string doc) {
    return {std::move(name), ParamType::Color, std::move(def), std::move(doc)};
}
ParamInfo text(std::string name, std::string def, std::string doc) {
    return {std::move(name), ParamType::String, std::move(def), std::move(doc)};
}
ParamInfo flag(std::string name, std::string def, std::string doc) {
    return {std::move(name), ParamType::Bool, std::move(def), std::move(doc)};
}

std::vector<ParamInfo> fresnel_params(const std::string& default_kind) {
    return {
        text("fresnel", default_kind,
             "Fresnel term: none (F = 1), dielectric (uses ior), conductor (uses eta, k), "
             "schlick (uses f0)"),
        number("ior", "1.5",
               "relative index of refraction n_t/n_i for fresnel = dielectric, "
               "in [0.001, 100]"),
        color("eta", "1.657 0.880 0.521",
              "real part of the complex IOR per channel for fresnel = conductor (default: "
              "aluminium), in (0, 100]"),
        color("k", "9.224 6.270 4.837",
              "imaginary part (extinction) per channel for fresnel = conductor, in [0, 100]"),
        color("f0", "0.04", "reflectance at normal incidence for fresnel = schlick, in [0, 1]"),
    };
}

std::vector<ParamInfo> alpha_params() {
    return {
        number("alpha", "0.2",
               "isotropic roughness alpha (RMS slope scale), in [0, 10]; "
               "below 1e-4 the lobe is the mirror"),
        number("alpha_u", "-", "roughness along the tangent u (anisotropic; give with alpha_v)"),
        number("alpha_v", "-", "roughness along the bitangent v (anisotropic; give with alpha_u)"),
    };
}

std::vector<ParamInfo> exponent_params() {
    return {
        number("exponent", "50", "Blinn exponent kappa in D ~ (n.h)^kappa, in [0, 1e9]"),
        number("exponent_u", "-",
               "exponent along the tangent u (anisotropic; give with "
               "exponent_v)"),
        number("exponent_v", "-", "exponent along the bitangent v (anisotropic)"),
    };
}

std::vector<ParamInfo> concat(std::vector<std::vector<ParamInfo>> parts) {
    std::vector<ParamInfo> all;
    for (auto& p : parts) all.insert(all.end(), p.begin(), p.end());
    return all;
}

const ParamInfo kEnergyCompensation =
    flag("energy_compensation", "false",
         "add Kulla & Conty 2017 multiple-scattering compensation (no energy loss at high "
         "roughness)");

std::vector<ModelInfo> build_table() {
    std::vector<ModelInfo> t;
    t.push_back({"lambert",
                 "ideal diffuse reflection f = rho/pi (Cohen & Wallace eq. 2.33-2.36)",
                 {color("reflectance", "0.5", "diffuse reflectance rho, in [0, 1]")}});
    t.push_back(
        {"mirror", "perfect specular reflection, a delta lobe (eq. 2.27-2.29) times F",
         concat({{color("reflectance", "1", "scale on F, in [0, 1]")}, fresnel_params("none")})});
    for (const char* name : {"ggx", "beckmann"}) {
        bool ggx = std::string(name) == "ggx";
        t.push_back({name,
                     std::string("microfacet f = D G F / (4 cos_i cos_o) (eq. 2.37), ") +
                         (ggx ? "GGX / Trowbridge-Reitz D" : "Beckmann D") +
                         ", exact Smith height-correlated G, visible-normal sampling",
                     concat({{color("reflectance", "1", "scale on F, in [0, 1]")},
                             alpha_params(),
                             fresnel_params("none"),
                             {kEnergyCompensation}})});
    }
    t.push_back({"blinn",
                 "microfacet with Blinn D = (kappa+2)/(2 pi) (n.h)^kappa (eq. 2.38), exact Smith "
                 "G for this D (Student-t slopes)",
                 concat({{color("reflectance", "1", "scale on F, in [0, 1]")},
                         exponent_params(),
                         fresnel_params("none"),
                         {kEnergyCompensation}})});
    t.push_back(
        {"composite",
         "diffuse + glossy + mirror (Cohen & Wallace §2.5.5); diffuse gets what the specular "
         "lobes leave",
         concat({{color("diffuse_reflectance", "0.5", "rho_d of the diffuse lobe, in [0, 1]"),
                  color("glossy_reflectance", "1",
                        "scale on the glossy lobe, in [0, 1]; glossy + mirror <= 1"),
                  color("mirror_reflectance", "0", "scale on the mirror lobe, in [0, 1]"),
                  text("distribution", "ggx", "glossy D: ggx, beckmann or blinn")},
                 alpha_params(),
                 exponent_params(),
                 fresnel_params("dielectric"),
                 {kEnergyCompensation}})});
    // Transmissive models (facet/dielectric.h): inside is the side opposite the shape's normal.
    const ParamInfo ior = number("ior", "1.5",
                                 "relative index of refraction eta = n_inside / n_outside (the "
                                 "outside is the side the shape's normal points to), in "
                                 "[0.001, 100]");
    const ParamInfo transmittance =
        color("transmittance", "1", "scale on the transmitted light (tint), in [0, 1]");
    t.push_back(
        {"dielectric",
         "interface between two media (glass, water): exact Fresnel reflection + refraction, "
         "radiance scaled by 1/eta'^2 across it; smooth (alpha = 0: two delta lobes) or rough "
         "(Walter et al. 2007, Smith G, visible-normal sampling)",
         {ior, transmittance,
          number("alpha", "0",
                 "isotropic roughness alpha, in [0, 10]; below 1e-4 the interface is smooth"),
          number("alpha_u", "-", "roughness along the tangent u (anisotropic; give with alpha_v)"),
          number("alpha_v", "-",
                 "roughness along the bitangent v (anisotropic; give with alpha_u)"),
          text("distribution", "ggx", "microfacet D of a rough interface: ggx or beckmann"),
          flag("energy_compensation", "false",
               "rough, isotropic interfaces: add the multiple-scattering lobe (Kulla & Conty "
               "2017 extended to refraction, facet/dielectric.h): reflection + transmission "
               "conserve energy at transmittance 1")}});
    t.push_back(
        {"principled",
         "Blender 3.4's Principled BSDF as Cycles evaluates it: Disney diffuse with "
         "retro-reflection, sheen, GGX specular (anisotropic), metallic, GTR1 clearcoat, rough "
         "glass transmission (docs/principled.md)",
         {color("base_color", "0.8", "Base Color C, in [0, 1]"),
          number("subsurface", "0",
                 "Subsurface, in [0, 1]: no subsurface transport; C = mix(base_color, "
                 "subsurface_color, subsurface) for every lobe (Cycles' diffuse fallback)"),
          color("subsurface_color", "0.8", "Subsurface Color, in [0, 1]"),
          number("metallic", "0", "Metallic, in [0, 1]"),
          number("specular", "0.5",
                 "Specular, in [0, 1]: F0 = 0.08 specular; with specular = metallic = 0 there "
                 "is no specular lobe"),
          number("specular_tint", "0", "Specular Tint, in [0, 1]"),
          number("roughness", "0.5", "Roughness r, in [0, 1]: GGX alpha = r^2"),
          number("anisotropic", "0",
                 "Anisotropic, in [0, 1]: alpha_u = min(1, r^2 / a), alpha_v = min(1, r^2 a), "
                 "a = sqrt(1 - 0.9 anisotropic)"),
          number("anisotropic_rotation", "0",
                 "Anisotropic Rotation, in [0, 1]: the tangent turned by 2 pi times this"),
          number("sheen", "0", "Sheen, in [0, 1]"),
          number("sheen_tint", "0.5", "Sheen Tint, in [0, 1]"),
          number("clearcoat", "0", "Clearcoat, in [0, 1]: lobe weight 0.25 clearcoat"),
          number("clearcoat_roughness", "0.03",
                 "Clearcoat Roughness, in [0, 1]: GTR1 alpha = clearcoat_roughness^2"),
          number("ior", "1.45", "IOR of the transmission (n_inside / n_outside), in [0.001, 100]"),
          number("transmission", "0", "Transmission, in [0, 1]"),
          number("transmission_roughness", "0",
                 "Transmission Roughness, in [0, 1]: refraction roughness 1 - (1 - r)(1 - this)"),
          text("distribution", "ggx",
               "microfacet distribution: ggx (Cycles' GGX) or multi_ggx (Cycles' Multiscatter "
               "GGX: for roughness > 0.075 the specular lobe takes the height-correlated G and a "
               "Kulla-Conty compensation lobe, so a white metal reflects everything)")}});
    t.push_back({"oren_nayar",
                 "rough diffuse reflection as Cycles' Diffuse BSDF with roughness: f = rho (A + "
                 "B t), A = 1 / (pi + (3 pi - 4) / 6 sigma), B = sigma A, t = s / max(cos_i, "
                 "cos_o) for s = wi.wo - cos_i cos_o > 0, else s (Fujii 2012)",
                 {color("reflectance", "0.5", "diffuse reflectance rho, in [0, 1]"),
                  number("sigma", "0.5",
                         "roughness as Blender's Diffuse BSDF Roughness (not radians), in [0, 1]; "
                         "0 is Lambert")}});
    const ParamInfo materials{"materials", ParamType::Materials, "-",
                              "the two sub-materials [a, b]: names from the scene's materials or "
                              "inline material objects (nesting allowed, no cycles)"};
    t.push_back({"mix",
                 "blend of two materials (Blender's Mix Shader): f = (1 - w) f_a + w f_b, "
                 "sampled by w",
                 {materials, number("weight", "0.5", "the weight w of b, in [0, 1]")},
                 2});
    t.push_back({"add",
                 "sum of two materials (Blender's Add Shader): f = f_a + f_b, each sampled with "
                 "probability 1/2; may reflect more than it receives (the scene builder warns)",
                 {materials},
                 2});
    t.push_back({"thin_dielectric",
                 "thin pane (window glass): both interfaces' reflections summed, R' = R + "
                 "T^2 R / (1 - R^2); transmission straight through with T' = 1 - R'",
                 {ior, transmittance}});
    return t;
}

// ---------------------------------------------------------------------------------------------
// Reading a ParamSet against a model's table

std::string format_value(double v) {
    std::ostringstream s;
    s << v;
    return s.str();
}

class Reader {
  public:
    Reader(const ModelInfo& model, const ParamSet& params) : m_model(model), m_params(params) {
        // Unknown names first: a typo must not be reported as "missing parameter".
        std::vector<std::string> names;
        for (const auto& p : model.params) names.push_back(p.name);
        for (const auto& [name, value] : params.values()) {
            if (std::find(names.begin(), names.end(), name) != names.end()) continue;
            std::string msg = "unknown parameter '" + name + "' for model '" + model.name + "'";
            std::string guess = closest_name(name, names);
            if (!guess.empty()) msg += " (did you mean '" + guess + "'?)";
            throw ParamError(name, msg);
        }
    }

    bool has(const std::string& name) const { return m_params.has(name); }

    double number(const std::string& name, double def, double lo, double hi) {
        const ParamValue* v = find(name);
        if (!v) return def;
        const double* d = std::get_if<double>(v);
        if (!d) throw error(name, "must be a number");
        check_range(name, *d, lo, hi);
        return *d;
    }

    Rgb color(const std::string& name, Rgb def, double lo, double hi) {
        const ParamValue* v = find(name);
        if (!v) return def;
        Rgb c;
        if (const double* d = std::get_if<double>(v))
            c = Rgb(float(*d));
        else if (const Rgb* r = std::get_if<Rgb>(v))
            c = *r;
        else
            throw error(name, "must be a colour (three numbers) or a number");
        for (int i = 0; i < 3; ++i) check_range(name, c[i], lo, hi);
        return c;
    }

    std::string choice(const std::string& name, const std::string& def,
                       const std::vector<std::string>& allowed) {
        const ParamValue* v = find(name);
        if (!v) return def;
        const std::string* s = std::get_if<std::string>(v);
        if (!s) throw error(name, "must be a string");
        if (std::find(allowed.begin(), allowed.end(), *s) != allowed.end()) return *s;
        std::string msg = "unknown value '" + *s + "' (expected one of";
        for (const auto& a : allowed) msg += " " + a;
        msg += ")";
        std::string guess = closest_name(*s, allowed);
        if (!guess.empty()) msg += " (did you mean '" + guess + "'?)";
        throw error(name, msg);
    }

    bool boolean(const std::string& name, bool def) {
        const ParamValue* v = find(name);
        if (!v) return def;
        const bool* b = std::get_if<bool>(v);
        if (!b) throw error(name, "must be true or false");
        return *b;
    }

    // Parameters that were given but that the chosen options make meaningless are errors:
    // silently ignoring "ior" under fresnel = conductor hides a user's mistake.
    void forbid(const std::string& name, const std::string& because) {
        if (has(name)) throw error(name, "has no effect " + because);
    }

    ParamError error(const std::string& name, const std::string& what) const {
        return ParamError(name,
                          "parameter '" + name + "' of model '" + m_model.name + "': " + what);
    }

  private:
    const ParamValue* find(const std::string& name) const {
        auto it = m_params.values().find(name);
        return it == m_params.values().end() ? nullptr : &it->second;
    }
    void check_range(const std::string& name, double v, double lo, double hi) const {
        if (std::isnan(v)) throw error(name, "is NaN");
        if (!(v >= lo && v <= hi))
            throw error(name, "must be in [" + format_value(lo) + ", " + format_value(hi) +
                                  "] (got " + format_value(v) + ")");
    }

    const ModelInfo& m_model;
    const ParamSet& m_params;
};

Fresnel read_fresnel(Reader& r, const std::string& default_kind) {
    std::string kind =
        r.choice("fresnel", default_kind, {"none", "dielectric", "conductor", "schlick"});
    const std::string because = "with fresnel = " + kind;
    if (kind != "dielectric") r.forbid("ior", because);
    if (kind != "conductor") r.forbid("eta", because), r.forbid("k", because);
    if (kind != "schlick") r.forbid("f0", because);
    if (kind == "dielectric")
        return Fresnel::dielectric(float(r.number("ior", 1.5, 1e-3, kMaxIor)));
    if (kind == "conductor") {
        Rgb eta = r.color("eta", Rgb(1.657f, 0.880f, 0.521f), 0.0, kMaxIor);
        for (int c = 0; c < 3; ++c)
            if (!(eta[c] > 0.f)) throw r.error("eta", "must be > 0");
        return Fresnel::conductor(eta, r.color("k", Rgb(9.224f, 6.270f, 4.837f), 0.0, kMaxIor));
    }
    if (kind == "schlick") return Fresnel::schlick(r.color("f0", Rgb(0.04f), 0.0, 1.0));
    return Fresnel::none();
}

// Reads the pair (x, x_u/x_v): either the isotropic value or both anisotropic ones.
std::pair<float, float> read_roughness_pair(Reader& r, const std::string& base, double def,
                                            double hi) {
    const std::string u = base + "_u", v = base + "_v";
    bool aniso = r.has(u) || r.has(v);
    if (aniso) {
        if (r.has(base)) throw r.error(base, "give either " + base + " or " + u + "/" + v);
        if (!r.has(u)) throw r.error(v, "needs " + u + " as well");
        if (!r.has(v)) throw r.error(u, "needs " + v + " as well");
        return {float(r.number(u, def, 0.0, hi)), float(r.number(v, def, 0.0, hi))};
    }
    float x = float(r.number(base, def, 0.0, hi));
    return {x, x};
}

MicrofacetDistribution read_distribution(Reader& r, const std::string& kind) {
    const std::string because = "with distribution " + kind;
    if (kind == "blinn") {
        for (const char* p : {"alpha", "alpha_u", "alpha_v"}) r.forbid(p, because);
        auto [ku, kv] = read_roughness_pair(r, "exponent", 50.0, kMaxExponent);
        return MicrofacetDistribution::blinn(ku, kv);
    }
    for (const char* p : {"exponent", "exponent_u", "exponent_v"}) r.forbid(p, because);
    auto [au, av] = read_roughness_pair(r, "alpha", 0.2, kMaxAlpha);
    return kind == "ggx" ? MicrofacetDistribution::ggx(au, av)
                         : MicrofacetDistribution::beckmann(au, av);
}

Material build(const ModelInfo& info, const ParamSet& params,
               std::span<const std::shared_ptr<const Material>> children) {
    Reader r(info, params);
    const std::string& name = info.name;
    if (r.has("materials"))
        throw r.error("materials",
                      "sub-materials are not a parameter value (give materials [a, b])");
    if (std::ptrdiff_t(children.size()) != info.children) {
        if (info.children == 0) throw r.error("materials", "this model takes no sub-materials");
        throw r.error("materials", "needs exactly " + std::to_string(info.children) +
                                       " sub-materials (got " + std::to_string(children.size()) +
                                       ")");
    }
    for (const auto& c : children)
        if (!c) throw r.error("materials", "a sub-material is missing");
    if (name == "mix")
        return Material::mix(children[0], children[1], float(r.number("weight", 0.5, 0.0, 1.0)));
    if (name == "add") return Material::add(children[0], children[1]);
    if (name == "oren_nayar") {
        const Rgb rho = r.color("reflectance", Rgb(0.5f), 0.0, 1.0);
        return Material(OrenNayarReflection(rho, float(r.number("sigma", 0.5, 0.0, 1.0))));
    }
    if (name == "lambert")
        return Material(LambertReflection(r.color("reflectance", Rgb(0.5f), 0.0, 1.0)),
                        std::nullopt, std::nullopt);
    if (name == "mirror") {
        Rgb scale = r.color("reflectance", Rgb(1.f), 0.0, 1.0);
        return Material(std::nullopt, std::nullopt,
                        MirrorReflection(read_fresnel(r, "none"), scale));
    }
    if (name == "ggx" || name == "beckmann" || name == "blinn") {
        Rgb scale = r.color("reflectance", Rgb(1.f), 0.0, 1.0);
        MicrofacetDistribution d = read_distribution(r, name);
        Fresnel fr = read_fresnel(r, "none");
        bool ec = r.boolean("energy_compensation", false);
        return Material(std::nullopt, MicrofacetReflection(d, fr, scale, ec), std::nullopt);
    }
    if (name == "dielectric" || name == "thin_dielectric") {
        const float eta = float(r.number("ior", 1.5, 1e-3, kMaxIor));
        const Rgb tr = r.color("transmittance", Rgb(1.f), 0.0, 1.0);
        if (name == "thin_dielectric") return Material(ThinDielectricBxDF(eta, tr));
        std::string kind = r.choice("distribution", "ggx", {"ggx", "beckmann"});
        auto [au, av] = read_roughness_pair(r, "alpha", 0.0, kMaxAlpha);
        const bool ec = r.boolean("energy_compensation", false);
        if (ec && au != av)
            throw r.error("energy_compensation",
                          "is not available for anisotropic dielectrics (alpha_u != alpha_v)");
        return Material(DielectricBxDF(eta, tr,
                                       kind == "ggx" ? MicrofacetDistribution::ggx(au, av)
                                                     : MicrofacetDistribution::beckmann(au, av),
                                       ec));
    }
    if (name == "principled") {
        PrincipledParams p;
        auto unit = [&](const char* key, float def) { return float(r.number(key, def, 0.0, 1.0)); };
        p.base_color = r.color("base_color", p.base_color, 0.0, 1.0);
        p.subsurface = unit("subsurface", p.subsurface);
        p.subsurface_color = r.color("subsurface_color", p.subsurface_color, 0.0, 1.0);
        p.metallic = unit("metallic", p.metallic);
        p.specular = unit("specular", p.specular);
        p.specular_tint = unit("specular_tint", p.specular_tint);
        p.roughness = unit("roughness", p.roughness);
        p.anisotropic = unit("anisotropic", p.anisotropic);
        p.anisotropic_rotation = unit("anisotropic_rotation", p.anisotropic_rotation);
        p.sheen = unit("sheen", p.sheen);
        p.sheen_tint = unit("sheen_tint", p.sheen_tint);
        p.clearcoat = unit("clearcoat", p.clearcoat);
        p.clearcoat_roughness = unit("clearcoat_roughness", p.clearcoat_roughness);
        p.ior = float(r.number("ior", p.ior, 1e-3, kMaxIor));
        p.transmission = unit("transmission", p.transmission);
        p.transmission_roughness = unit("transmission_roughness", p.transmission_roughness);
        p.multiscatter = r.choice("distribution", "ggx", {"ggx", "multi_ggx"}) == "multi_ggx";
        return Material(PrincipledBxDF(p));
    }
    // composite
    Rgb kd = r.color("diffuse_reflectance", Rgb(0.5f), 0.0, 1.0);
    Rgb ks = r.color("glossy_reflectance", Rgb(1.f), 0.0, 1.0);
    Rgb km = r.color("mirror_reflectance", Rgb(0.f), 0.0, 1.0);
    for (int c = 0; c < 3; ++c)
        if (ks[c] + km[c] > 1.f + 1e-6f)
            throw r.error("mirror_reflectance",
                          "glossy_reflectance + mirror_reflectance must be <= 1 per channel "
                          "(energy conservation)");
    std::string kind = r.choice("distribution", "ggx", {"ggx", "beckmann", "blinn"});
    MicrofacetDistribution d = read_distribution(r, kind);
    Fresnel fr = read_fresnel(r, "dielectric");
    bool ec = r.boolean("energy_compensation", false);
    return Material::composite(kd, ks, km, d, fr, ec);
}

size_t edit_distance(std::string_view a, std::string_view b) {
    std::vector<size_t> prev(b.size() + 1), cur(b.size() + 1);
    for (size_t j = 0; j <= b.size(); ++j) prev[j] = j;
    for (size_t i = 1; i <= a.size(); ++i) {
        cur[0] = i;
        for (size_t j = 1; j <= b.size(); ++j) {
            size_t sub = prev[j - 1] + (std::tolower(a[i - 1]) == std::tolower(b[j - 1]) ? 0 : 1);
            cur[j] = std::min({prev[j] + 1, cur[j - 1] + 1, sub});
        }
        std::swap(prev, cur);
    }
    return prev[b.size()];
}

}  // namespace

const std::vector<ModelInfo>& model_table() {
    static const std::vector<ModelInfo> table = build_table();
    return table;
}

const ModelInfo* find_model(std::string_view name) {
    for (const auto& m : model_table())
        if (m.name == name) return &m;
    return nullptr;
}

Material make_material(std::string_view model, const ParamSet& params,
                       std::span<const std::shared_ptr<const Material>> children) {
    const ModelInfo* info = find_model(model);
    if (!info) {
        std::vector<std::string> names;
        for (const auto& m : model_table()) names.push_back(m.name);
        std::string msg = "unknown model '" + std::string(model) + "'";
        std::string guess = closest_name(model, names);
        if (!guess.empty()) msg += " (did you mean '" + guess + "'?)";
        msg += "; models:";
        for (const auto& n : names) msg += " " + n;
        throw ParamError("", msg);
    }
    return build(*info, params, children);
}

std::string closest_name(std::string_view name, const std::vector<std::string>& candidates) {
    std::string best;
    size_t best_d = std::numeric_limits<size_t>::max();
    for (const auto& c : candidates) {
        size_t d = edit_distance(name, c);
        if (d < best_d) best_d = d, best = c;
    }
    // Close enough: at most a third of the name's letters wrong (and at least 2 allowed).
    size_t limit = std::max<size_t>(2, name.size() / 3);
    return best_d <= limit ? best : std::string();
}

}  // namespace facet
