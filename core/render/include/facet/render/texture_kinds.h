// Texture kinds: the one table that says what each kind of texture of the scene format is
// (texture.h). One unit per kind (core/render/src/textures/<kind>.cpp) defines a
// TextureKindDef: its name (TextureDesc::kind and its JSON key), its parameters with their
// types, defaults, ranges and documentation, and its builder (description -> Texture). The
// JSON reader and writer, build_scene, the Python module and the docs read this table.
//
// Conventions: image, checker and vertex_color have keys of their own (scenes/FORMAT.md,
// "Textures"), read by scene_json.cpp; a procedural kind's parameters are the keys of the
// object under its name, {"noise": {"scale": 5, "detail": 2}, "coordinates": "object", ...},
// each a number or a name from `choices`, absent ones taking `default_number` /
// `default_text`. A composite kind (composite = true: math, vector_math, mix_rgb, color_ramp)
// reads no point: its Input parameters are a constant (a number, or a colour [r, g, b] for a
// Color one) or a texture object, {"math": {"operation": "add", "a": {"noise": {...}}, "b":
// 0.5}}, and it has no "coordinates" or "mapping".
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "facet/registry.h"
#include "facet/render/texture.h"

namespace facet::render {

class TextureBuild;  // what a kind's builder gets (core/render/src/textures/texture_build.h)

// How a parameter is given (TextureParamDef::form).
enum class TextureParamForm : std::uint8_t {
    Value,  // a constant of its type
    Input,  // a Number or Color constant, or a texture of that type (composite kinds)
    Stops,  // a colour ramp's stops: [{"position": p, "color": [r, g, b(, a)]}, ...]
};

// One parameter of a procedural kind.
struct TextureParamDef {
    std::string_view name;
    ParamType type = ParamType::Number;  // Number, String, Bool, or Color (an Input)
    double default_number = 0.0;
    std::string_view default_text = {};
    double lo = 0.0, hi = 0.0;              // a Number's range, inclusive
    bool integer = false;                   // a Number that must be an integer
    std::vector<std::string> choices = {};  // a String's values
    std::string_view doc = {};
    TextureParamForm form = TextureParamForm::Value;
    // A Color Input's default (a Number Input's is default_number).
    Rgb default_color{0.f};
};

struct TextureKindDef {
    std::string_view name;
    std::string_view summary;  // one line for the docs
    std::vector<TextureParamDef> params;
    // A procedural kind: reads a point (TextureDesc::coordinates, mapping) and `params`.
    bool procedural = false;
    // Validates the description (errors name the JSON pointer) and builds the texture.
    Texture (*build)(TextureBuild&) = nullptr;
    // A composite kind: its inputs are textures or constants, it reads no point.
    bool composite = false;
    // Its "color" output is grey (Gradient, Wave): a number parameter may read it.
    bool grey_color = false;
};

// The table, in the scene format's documented order.
std::span<const TextureKindDef* const> texture_kinds();
// nullptr when no kind has that name.
const TextureKindDef* find_texture_kind(std::string_view name);
std::vector<std::string> texture_kind_names();
// A procedural kind's parameter by name (nullptr: none).
const TextureParamDef* find_texture_param(const TextureKindDef& kind, std::string_view name);
// A procedural texture alone, outside a scene (tests, previews): validated as build_scene
// validates it (errors throw std::invalid_argument "<ptr>/...: message"); `color`: it feeds a
// colour (else a number). Throws std::invalid_argument for a kind that is not procedural.
Texture build_procedural_texture(const TextureDesc& desc, bool color, const std::string& ptr = "");
// Markdown tables of the procedural kinds (scenes/FORMAT.md holds this text between the
// markers `<!-- texture-kinds:begin -->` and `<!-- texture-kinds:end -->`).
std::string texture_kinds_markdown();

}  // namespace facet::render
