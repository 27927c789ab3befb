// The one name -> model table of Facet. JSON scenes, POV-Ray keywords, Blender enum items and
// CLI flags all use these model and parameter names.
//
// Conventions:
//  - A model is built from a ParamSet (name -> value); every parameter is validated when the
//    model is built. A bad value throws ParamError naming the parameter; the caller prefixes
//    its own place (file:line, JSON path, Blender object) to the message.
//  - Unknown model or parameter names are errors (with a "did you mean" suggestion), never
//    silently ignored. Missing parameters take the documented default.
//  - Colours are linear RGB; a number given where a colour is expected means grey.
#pragma once

#include <array>
#include <cstdint>
#include <initializer_list>
#include <map>
#include <memory>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <variant>
#include <vector>

#include "facet/material.h"

namespace facet {

using ParamValue = std::variant<double, Rgb, std::string, bool>;

class ParamError : public std::runtime_error {
  public:
    ParamError(std::string param, const std::string& message)
        : std::runtime_error(message), m_param(std::move(param)) {}
    // The offending parameter's name ("" for the model name itself).
    const std::string& param() const { return m_param; }

  private:
    std::string m_param;
};

class ParamSet {
  public:
    ParamSet() = default;
    // ParamSet{{"alpha", 0.3f}, {"fresnel", std::string("dielectric")}}: set() per entry.
    ParamSet(std::initializer_list<std::pair<std::string, ParamValue>> list) {
        for (const auto& [name, value] : list) set(name, value);
    }
    void set(const std::string& name, ParamValue value) { m_values[name] = std::move(value); }
    bool has(const std::string& name) const { return m_values.count(name) != 0; }
    const std::map<std::string, ParamValue>& values() const { return m_values; }
    bool operator==(const ParamSet&) const = default;

  private:
    std::map<std::string, ParamValue> m_values;
};

// Materials: the sub-materials of a combination (mix, add), which a ParamSet does not hold:
// they are built first and passed to make_material() (scenes name them or give them inline).
enum class ParamType { Number, Color, String, Bool, Materials };

struct ParamInfo {
    std::string name;
    ParamType type;
    std::string default_value;              // as text, for docs and --help
    std::string doc;                        // one line, with the valid range
    std::vector<std::string> choices = {};  // a String parameter's values (the reader checks)
};

// The family whose staged build (facet/staged_material.h) sets a textured model's lobes per hit
// with tables built once, or None (the unit's own two-stage builder, ModelInfo::make).
enum class StagedFamily : std::uint8_t {
    None,
    Lambert,
    OrenNayar,
    Principled,
    Mirror,
    Microfacet,
    Dielectric,
    ThinDielectric,
    Composite
};

class ParamReader;  // a ParamSet read against a model's table (core/src/models/model_unit.h)
using Children = std::span<const std::shared_ptr<const Material>>;

// A model's parameter values by their index in ModelInfo::params, for the two-stage builders
// (ModelInfo::read, make): a number in x (as a ParamSet holds it: all three channels equal),
// a colour's channels (a float colour is exact in double), a choice's index among its
// ParamInfo::choices in x, a flag 0 or 1 in x; a Materials entry is unused. Fixed-size, so a
// per-hit build neither allocates nor looks up names.
class ParamValues {
  public:
    static constexpr std::size_t kMax = 24;  // parameters of a two-stage model, at most
    DVec3& operator[](std::size_t i) { return m_values[i]; }
    const DVec3& operator[](std::size_t i) const { return m_values[i]; }
    double number(std::size_t i) const { return m_values[i].x; }
    Rgb color(std::size_t i) const { return Rgb(m_values[i]); }
    int choice(std::size_t i) const { return int(m_values[i].x); }
    bool flag(std::size_t i) const { return m_values[i].x != 0.0; }

  private:
    std::array<DVec3, kMax> m_values{};
};

// One model: a unit core/src/models/<model>.cpp defines its ModelInfo, and registry.cpp lists
// it. Everything that deals in models reads these fields instead of comparing names: the JSON
// reader and writer and build_scene (parameters, children), `facet brdf models` and
// docs/models.md (the table), the staged build (`staged`), export-pov and the POV-Ray bridge
// (`diffuse_param`, `pov_finish`, `pov_samples`).
struct ModelInfo {
    std::string name;
    std::string summary;
    std::vector<ParamInfo> params;
    int children = 0;  // number of sub-materials (mix, add: 2), passed to make_material()
    // The unit's builder: the material from its parameters (read and range-checked through
    // `r`, which throws ParamError) and its `children` (already counted).
    Material (*build)(ParamReader& r, Children children) = nullptr;
    // Or the builder in two stages (both set, `build` null; at most ParamValues::kMax
    // parameters): `read` checks the parameters through `r` (throwing ParamError) and stores
    // each in `v` at its index, unchanged; `make` builds the material from those values and the
    // children, with no string handling and no throw, and computes everything derived from them.
    // The staged build (facet/staged_material.h) reads a textured material's constants once and
    // at each hit sets its textured parameters' values and calls `make` alone: a unit with
    // `make` is staged whatever its textured (number or colour) parameters are.
    void (*read)(ParamReader& r, ParamValues& v) = nullptr;
    Material (*make)(const ParamValues& v, Children children) = nullptr;
    // The parameter that is the model's diffuse reflectance, or "": the one a POV-Ray pigment
    // carries (the brdf finish multiplies the pigment into it; 1 when not given).
    std::string diffuse_param = {};
    // The model's material has a Lambert lobe whose rho is `diffuse_param`'s value exactly:
    // a texture on that parameter alone only replaces the lobe's rho per hit
    // (Material::with_diffuse_reflectance). diffuse_black_ok: also at rho = 0 (a composite
    // leaves out a black diffuse lobe, so it is rebuilt there).
    bool diffuse_lobe = false, diffuse_black_ok = false;
    StagedFamily staged = StagedFamily::None;
    // POV-Ray's brdf finish takes the model (reflection only: a transmissive material built
    // from it is an error there), and its `samples` (the glossy lobe's sample count) applies.
    bool pov_finish = true, pov_samples = false;
    // The surface is invisible, only a medium's boundary (`null`): the media kernel crosses it
    // without a vertex and lets shadow rays through (facet/render/medium.h).
    bool pass_through = false;

    const ParamInfo* param(std::string_view n) const {
        for (const ParamInfo& p : params)
            if (p.name == n) return &p;
        return nullptr;
    }
};

// Every model the core knows, in documentation order.
const std::vector<ModelInfo>& model_table();
const ModelInfo* find_model(std::string_view name);

// Builds a material from a model name, its parameters and, for combinations (ModelInfo::
// children > 0), its sub-materials in order. Throws ParamError ("materials" for a wrong number
// of sub-materials).
Material make_material(std::string_view model, const ParamSet& params,
                       std::span<const std::shared_ptr<const Material>> children = {});

// The candidate closest to `name` by edit distance, or "" when nothing is close enough;
// for "did you mean" messages.
std::string closest_name(std::string_view name, const std::vector<std::string>& candidates);

}  // namespace facet
