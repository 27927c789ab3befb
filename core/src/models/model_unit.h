// What a model unit (core/src/models/<model>.cpp) uses to declare its parameters and read them:
// the ParamInfo helpers, the parameter groups several models share (Fresnel, roughness), and
// ParamReader, a ParamSet read against the model's table. Private to facet::core.
//
// Conventions: facet/registry.h (names, ranges, errors as ParamError naming the parameter).
#pragma once

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "facet/registry.h"

namespace facet {

namespace models {

constexpr double kMaxAlpha = 10.0;    // GGX/Beckmann alpha = RMS slope-ish; > 10 is meaningless
constexpr double kMaxExponent = 1e9;  // Blinn kappa; 1e9 is far past the mirror threshold
constexpr double kMaxIor = 100.0;

inline ParamInfo number(std::string name, std::string def, std::string doc) {
    return {std::move(name), ParamType::Number, std::move(def), std::move(doc)};
}
inline ParamInfo color(std::string name, std::string def, std::string doc) {
    return {std::move(name), ParamType::Color, std::move(def), std::move(doc)};
}
inline ParamInfo text(std::string name, std::string def, std::string doc,
                      std::vector<std::string> choices) {
    return {std::move(name), ParamType::String, std::move(def), std::move(doc), std::move(choices)};
}
inline ParamInfo flag(std::string name, std::string def, std::string doc) {
    return {std::move(name), ParamType::Bool, std::move(def), std::move(doc)};
}
std::vector<ParamInfo> concat(std::vector<std::vector<ParamInfo>> parts);

// fresnel (none | dielectric | conductor | schlick, default `default_kind`), ior, eta, k, f0.
std::vector<ParamInfo> fresnel_params(const std::string& default_kind);
// alpha, alpha_u, alpha_v (default alpha 0.2).
std::vector<ParamInfo> alpha_params();
// exponent, exponent_u, exponent_v (Blinn).
std::vector<ParamInfo> exponent_params();
// distribution (`choices`, default ggx).
ParamInfo distribution_param(std::string doc, std::vector<std::string> choices);
ParamInfo energy_compensation_param();
// The sub-materials [a, b] of a combination.
ParamInfo materials_param();
// A random walk's radius, ior, anisotropy and method, names prefixed (subsurface.cpp).
std::vector<ParamInfo> subsurface_walk_params(const std::string& prefix);

}  // namespace models

class ParamReader {
  public:
    // Throws ParamError for a parameter the model does not have (with a "did you mean").
    ParamReader(const ModelInfo& model, const ParamSet& params);

    bool has(const std::string& name) const { return m_params.has(name); }
    double number(const std::string& name, double def, double lo, double hi);
    Rgb color(const std::string& name, Rgb def, double lo, double hi);
    // A String parameter: one of its ParamInfo::choices, its default when not given.
    std::string choice(const std::string& name);
    bool boolean(const std::string& name, bool def);
    // The two-stage units (ModelInfo::read): parameter i of the model's table (its index in
    // ModelInfo::params) read as above and stored in v[i] (ParamValues' conventions); choice
    // returns the index of the value among the choices.
    const std::string& name(std::size_t i) const { return m_model.params[i].name; }
    double number(ParamValues& v, std::size_t i, double def, double lo, double hi);
    Rgb color(ParamValues& v, std::size_t i, Rgb def, double lo, double hi);
    int choice(ParamValues& v, std::size_t i);
    // Parameters that were given but that the chosen options make meaningless are errors:
    // silently ignoring "ior" under fresnel = conductor hides a user's mistake.
    void forbid(const std::string& name, const std::string& because);
    ParamError error(const std::string& name, const std::string& what) const;

    // The shared groups (models::fresnel_params, alpha_params, exponent_params).
    Fresnel fresnel();
    // The pair (x, x_u/x_v): either the isotropic value or both anisotropic ones.
    std::pair<float, float> roughness_pair(const std::string& base, double def, double hi);
    // The microfacet distribution of kind ggx, beckmann or blinn from its roughness group.
    MicrofacetDistribution distribution(const std::string& kind);

  private:
    const ParamValue* find(const std::string& name) const;
    void check_range(const std::string& name, double v, double lo, double hi) const;

    const ModelInfo& m_model;
    const ParamSet& m_params;
};

// The shared groups for the two-stage units (ModelInfo::read and make), `i` the index of the
// group's first parameter in the model's table. read_* makes the checks of fresnel() and
// roughness_pair() and stores every parameter of the group at its index (given or its default);
// the make_* functions build from those values alone (no strings, no throw).
// Fresnel group (models::fresnel_params) at i: fresnel, ior, eta, k, f0.
void read_fresnel(ParamReader& r, ParamValues& v, std::size_t i);
Fresnel make_fresnel(const ParamValues& v, std::size_t i);
// Roughness group (models::alpha_params, exponent_params) at i: x, x_u, x_v. x_u and x_v hold
// -1 unless given (the lobe is then anisotropic and x is unused).
void read_roughness(ParamReader& r, ParamValues& v, std::size_t i, double def, double hi);
std::pair<float, float> make_roughness(const ParamValues& v, std::size_t i);
// The microfacet distribution of `kind` from the roughness group at i.
MicrofacetDistribution make_distribution(DistributionKind kind, const ParamValues& v,
                                         std::size_t i);

// The walk parameters (models::subsurface_walk_params) read and checked; radius times `scale`.
struct SubsurfaceInputs {
    Rgb radius{0.f};
    float ior = 1.4f, anisotropy = 0.f;
    SubsurfaceMethod method = SubsurfaceMethod::RandomWalk;
    bool walked = false;  // every channel's radius is above Cycles' minimum (else none is)
};
SubsurfaceInputs read_subsurface_inputs(ParamReader& r, const std::string& prefix, float scale);
// The walk's radius, IOR, anisotropy and method into those indices of a unit's block (their
// defaults and ranges as read_subsurface_inputs's).
void read_subsurface_values(ParamReader& r, ParamValues& v, std::size_t radius, std::size_t ior,
                            std::size_t anisotropy, std::size_t method);
// The same from a model's evaluated block (a per-hit build): the radius (already scaled), and
// the IOR, anisotropy and method at those indices of `v`. nullopt when only some channels'
// radius reaches Cycles' minimum, which read_subsurface_inputs rejects (a texture can give that
// between its checked extremes): the model then builds black, as a failed build is.
std::optional<SubsurfaceInputs> make_subsurface_inputs(const ParamValues& v, const Rgb& radius,
                                                       std::size_t ior, std::size_t anisotropy,
                                                       std::size_t method);

}  // namespace facet
