// The texture kind table (facet/render/texture_kinds.h): one line per kind unit.
#include "facet/render/texture_kinds.h"
#include "texture_build.h"

#include <sstream>

namespace facet::render {

std::span<const TextureKindDef* const> texture_kinds() {
    static const TextureKindDef* const kinds[] = {
        &kImageTexture,      &kCheckerTexture,    &kVertexColorTexture, &kNoiseTexture,
        &kVoronoiTexture,    &kMusgraveTexture,   &kWaveTexture,        &kMagicTexture,
        &kGradientTexture,   &kWhiteNoiseTexture, &kBrickTexture,       &kMathTexture,
        &kVectorMathTexture, &kMixRgbTexture,     &kColorRampTexture,   &kHairInfoTexture,
        &kLightPathTexture,
    };
    return kinds;
}

const TextureKindDef* find_texture_kind(std::string_view name) {
    for (const TextureKindDef* k : texture_kinds())
        if (k->name == name) return k;
    return nullptr;
}

std::vector<std::string> texture_kind_names() {
    std::vector<std::string> out;
    for (const TextureKindDef* k : texture_kinds()) out.emplace_back(k->name);
    return out;
}

std::string texture_kinds_markdown() {
    std::ostringstream s;
    for (const TextureKindDef* k : texture_kinds()) {
        if (!k->procedural) continue;
        s << "\n#### `" << k->name << "`\n\n" << k->summary << ".\n\n";
        s << "| key | default | values | meaning |\n|---|---|---|---|\n";
        for (const TextureParamDef& p : k->params) {
            s << "| `" << p.name << "` | ";
            const char* texture = p.form == TextureParamForm::Input ? ", or a texture" : "";
            if (p.form == TextureParamForm::Stops) {
                s << "(none) | a list of stops";
            } else if (p.type == ParamType::Bool) {
                s << (p.default_number != 0.0 ? "`true`" : "`false`") << " | `true`, `false`";
            } else if (p.type == ParamType::Color) {
                const Rgb& c = p.default_color;
                s << "[" << c.r << ", " << c.g << ", " << c.b << "] | a colour or a number"
                  << texture;
            } else if (p.type == ParamType::String) {
                s << "`\"" << p.default_text << "\"` | ";
                for (std::size_t i = 0; i < p.choices.size(); ++i)
                    s << (i ? ", " : "") << "`" << p.choices[i] << "`";
            } else {
                s << p.default_number << " | ";
                if (p.lo <= -1e30 && p.hi >= 1e30)
                    s << "any";
                else if (p.hi >= 1e30)
                    s << ">= " << p.lo;
                else
                    s << p.lo << " to " << p.hi;
                if (p.integer) s << ", integer";
                s << texture;
            }
            s << " | " << p.doc << " |\n";
        }
    }
    return s.str();
}

}  // namespace facet::render
