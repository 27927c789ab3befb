// The shared parameter groups and ParamReader (model_unit.h).
#include "model_unit.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace facet {

namespace models {

std::vector<ParamInfo> concat(std::vector<std::vector<ParamInfo>> parts) {
    std::vector<ParamInfo> all;
    for (auto& p : parts) all.insert(all.end(), p.begin(), p.end());
    return all;
}

std::vector<ParamInfo> fresnel_params(const std::string& default_kind) {
    return {
        text("fresnel", default_kind,
             "Fresnel term: none (F = 1), dielectric (uses ior), conductor (uses eta, k), "
             "schlick (uses f0)",
             {"none", "dielectric", "conductor", "schlick"}),
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

ParamInfo distribution_param(std::string doc, std::vector<std::string> choices) {
    return text("distribution", "ggx", std::move(doc), std::move(choices));
}

ParamInfo energy_compensation_param() {
    return flag("energy_compensation", "false",
                "add Kulla & Conty 2017 multiple-scattering compensation (no energy loss at "
                "high roughness)");
}

ParamInfo materials_param() {
    return {"materials", ParamType::Materials, "-",
            "the two sub-materials [a, b]: names from the scene's materials or inline material "
            "objects (nesting allowed, no cycles)"};
}

}  // namespace models

namespace {

std::string format_value(double v) {
    std::ostringstream s;
    s << v;
    return s.str();
}

}  // namespace

ParamReader::ParamReader(const ModelInfo& model, const ParamSet& params)
    : m_model(model), m_params(params) {
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

double ParamReader::number(const std::string& name, double def, double lo, double hi) {
    const ParamValue* v = find(name);
    if (!v) return def;
    const double* d = std::get_if<double>(v);
    if (!d) throw error(name, "must be a number");
    check_range(name, *d, lo, hi);
    return *d;
}

Rgb ParamReader::color(const std::string& name, Rgb def, double lo, double hi) {
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

std::string ParamReader::choice(const std::string& name) {
    const ParamInfo* info = m_model.param(name);
    const std::vector<std::string>& allowed = info->choices;
    const ParamValue* v = find(name);
    if (!v) return info->default_value;
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

bool ParamReader::boolean(const std::string& name, bool def) {
    const ParamValue* v = find(name);
    if (!v) return def;
    const bool* b = std::get_if<bool>(v);
    if (!b) throw error(name, "must be true or false");
    return *b;
}

double ParamReader::number(ParamValues& v, std::size_t i, double def, double lo, double hi) {
    const double x = number(name(i), def, lo, hi);
    v[i] = DVec3(x);
    return x;
}

Rgb ParamReader::color(ParamValues& v, std::size_t i, Rgb def, double lo, double hi) {
    const Rgb c = color(name(i), def, lo, hi);
    v[i] = DVec3(c);
    return c;
}

int ParamReader::choice(ParamValues& v, std::size_t i) {
    const std::vector<std::string>& choices = m_model.params[i].choices;
    const int k = int(std::find(choices.begin(), choices.end(), choice(name(i))) - choices.begin());
    v[i] = DVec3(double(k));
    return k;
}

void ParamReader::forbid(const std::string& name, const std::string& because) {
    if (has(name)) throw error(name, "has no effect " + because);
}

ParamError ParamReader::error(const std::string& name, const std::string& what) const {
    return ParamError(name, "parameter '" + name + "' of model '" + m_model.name + "': " + what);
}

const ParamValue* ParamReader::find(const std::string& name) const {
    auto it = m_params.values().find(name);
    return it == m_params.values().end() ? nullptr : &it->second;
}

void ParamReader::check_range(const std::string& name, double v, double lo, double hi) const {
    if (std::isnan(v)) throw error(name, "is NaN");
    if (!(v >= lo && v <= hi))
        throw error(name, "must be in [" + format_value(lo) + ", " + format_value(hi) + "] (got " +
                              format_value(v) + ")");
}

Fresnel ParamReader::fresnel() {
    const std::string kind = choice("fresnel");
    const std::string because = "with fresnel = " + kind;
    if (kind != "dielectric") forbid("ior", because);
    if (kind != "conductor") forbid("eta", because), forbid("k", because);
    if (kind != "schlick") forbid("f0", because);
    if (kind == "dielectric")
        return Fresnel::dielectric(float(number("ior", 1.5, 1e-3, models::kMaxIor)));
    if (kind == "conductor") {
        Rgb eta = color("eta", Rgb(1.657f, 0.880f, 0.521f), 0.0, models::kMaxIor);
        for (int c = 0; c < 3; ++c)
            if (!(eta[c] > 0.f)) throw error("eta", "must be > 0");
        return Fresnel::conductor(eta,
                                  color("k", Rgb(9.224f, 6.270f, 4.837f), 0.0, models::kMaxIor));
    }
    if (kind == "schlick") return Fresnel::schlick(color("f0", Rgb(0.04f), 0.0, 1.0));
    return Fresnel::none();
}

std::pair<float, float> ParamReader::roughness_pair(const std::string& base, double def,
                                                    double hi) {
    const std::string u = base + "_u", v = base + "_v";
    bool aniso = has(u) || has(v);
    if (aniso) {
        if (has(base)) throw error(base, "give either " + base + " or " + u + "/" + v);
        if (!has(u)) throw error(v, "needs " + u + " as well");
        if (!has(v)) throw error(u, "needs " + v + " as well");
        return {float(number(u, def, 0.0, hi)), float(number(v, def, 0.0, hi))};
    }
    float x = float(number(base, def, 0.0, hi));
    return {x, x};
}

MicrofacetDistribution ParamReader::distribution(const std::string& kind) {
    const std::string because = "with distribution " + kind;
    if (kind == "blinn") {
        for (const char* p : {"alpha", "alpha_u", "alpha_v"}) forbid(p, because);
        auto [ku, kv] = roughness_pair("exponent", 50.0, models::kMaxExponent);
        return MicrofacetDistribution::blinn(ku, kv);
    }
    for (const char* p : {"exponent", "exponent_u", "exponent_v"}) forbid(p, because);
    auto [au, av] = roughness_pair("alpha", 0.2, models::kMaxAlpha);
    return kind == "ggx" ? MicrofacetDistribution::ggx(au, av)
                         : MicrofacetDistribution::beckmann(au, av);
}

namespace {
// The parameter at index i of a group is the one the group's layout says (a unit's table out
// of step with its indices is a programming error, caught when any material is read).
void expect_name(const ParamReader& r, std::size_t i, const std::string& name) {
    if (r.name(i) != name)
        throw std::logic_error("model table: parameter " + std::to_string(i) + " is '" + r.name(i) +
                               "', expected '" + name + "'");
}
}  // namespace

void read_fresnel(ParamReader& r, ParamValues& v, std::size_t i) {
    expect_name(r, i, "fresnel"), expect_name(r, i + 4, "f0");
    r.fresnel();  // the checks (forbidden members, eta > 0)
    r.choice(v, i);
    r.number(v, i + 1, 1.5, 1e-3, models::kMaxIor);
    r.color(v, i + 2, Rgb(1.657f, 0.880f, 0.521f), 0.0, models::kMaxIor);
    r.color(v, i + 3, Rgb(9.224f, 6.270f, 4.837f), 0.0, models::kMaxIor);
    r.color(v, i + 4, Rgb(0.04f), 0.0, 1.0);
}

Fresnel make_fresnel(const ParamValues& v, std::size_t i) {
    // The order of models::fresnel_params' choices: none, dielectric, conductor, schlick.
    switch (v.choice(i)) {
        case 1:
            return Fresnel::dielectric(float(v.number(i + 1)));
        case 2:
            return Fresnel::conductor(v.color(i + 2), v.color(i + 3));
        case 3:
            return Fresnel::schlick(v.color(i + 4));
        default:
            return Fresnel::none();
    }
}

void read_roughness(ParamReader& r, ParamValues& v, std::size_t i, double def, double hi) {
    const std::string& base = r.name(i);
    expect_name(r, i + 1, base + "_u"), expect_name(r, i + 2, base + "_v");
    r.roughness_pair(base, def, hi);  // the checks
    if (r.has(base + "_u")) {
        v[i] = DVec3(-1.0);
        r.number(v, i + 1, def, 0.0, hi), r.number(v, i + 2, def, 0.0, hi);
    } else {
        r.number(v, i, def, 0.0, hi);
        v[i + 1] = v[i + 2] = DVec3(-1.0);
    }
}

std::pair<float, float> make_roughness(const ParamValues& v, std::size_t i) {
    if (v.number(i + 1) >= 0.0) return {float(v.number(i + 1)), float(v.number(i + 2))};
    const float x = float(v.number(i));
    return {x, x};
}

MicrofacetDistribution make_distribution(DistributionKind kind, const ParamValues& v,
                                         std::size_t i) {
    const auto [u, w] = make_roughness(v, i);
    switch (kind) {
        case DistributionKind::Blinn:
            return MicrofacetDistribution::blinn(u, w);
        case DistributionKind::Beckmann:
            return MicrofacetDistribution::beckmann(u, w);
        default:
            return MicrofacetDistribution::ggx(u, w);
    }
}

std::optional<SubsurfaceInputs> make_subsurface_inputs(const ParamValues& v, const Rgb& radius,
                                                       std::size_t ior, std::size_t anisotropy,
                                                       std::size_t method) {
    SubsurfaceInputs in;
    in.radius = radius;
    in.ior = float(v.number(ior));
    in.anisotropy = float(v.number(anisotropy));
    in.method = v.choice(method) == 1 ? SubsurfaceMethod::RandomWalkFixedRadius
                                      : SubsurfaceMethod::RandomWalk;
    int walked = 0;
    for (int c = 0; c < 3; ++c) walked += in.radius[c] >= SubsurfaceLimits::kMinRadius;
    if (walked != 0 && walked != 3) return std::nullopt;
    in.walked = walked == 3;
    return in;
}

}  // namespace facet
