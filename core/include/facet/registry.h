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
    std::string default_value;  // as text, for docs and --help
    std::string doc;            // one line, with the valid range
};

struct ModelInfo {
    std::string name;
    std::string summary;
    std::vector<ParamInfo> params;
    int children = 0;  // number of sub-materials (mix, add: 2), passed to make_material()
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
