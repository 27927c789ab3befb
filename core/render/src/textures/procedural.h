// Private to facet_render: what the procedural texture kinds share (texture.h conventions,
// "Procedural kinds"): the point they read and their parameters.
//
// The point: TexturePoint::generated, ::object or (u, v, 0) by TextureDesc::coordinates, then
// the affine TextureDesc::mapping, in float as Cycles' Mapping node evaluates it. The value:
// the kind's pattern at that point, times the texture's scale.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "facet/render/texture.h"
#include "facet/render/texture_kinds.h"
#include "texture_build.h"

namespace facet::render {

class ProceduralSource : public TextureSource {
  public:
    // In the order of TextureDesc::coordinates' names (kCoordinateNames).
    enum class Coordinates : std::uint8_t {
        Generated,
        Object,
        Uv,
        Normal,
        Reflection,
        Camera,
        Window
    };
    // (A kind with texture inputs, brick's colours, evaluates them at p itself.)
    Rgb eval(const TexturePoint& p) const override { return pattern(point(p)) * m_scale; }
    // The kind's value at texture-space point x (before the scale).
    virtual Rgb pattern(const Vec3& x) const = 0;
    Vec3 point(const TexturePoint& p) const { return m_linear * coordinates(p) + m_offset; }
    Vec3 coordinates(const TexturePoint& p) const {
        switch (m_coordinates) {
            case Coordinates::Generated:
                return p.generated;
            case Coordinates::Object:
                return p.object;
            case Coordinates::Uv:
                return Vec3(p.uv, 0.f);
            case Coordinates::Normal:
                return p.normal;
            case Coordinates::Reflection:
                return p.reflection;
            case Coordinates::Camera:
                return p.camera;
            case Coordinates::Window:
                return p.window;
        }
        return p.generated;
    }

    Coordinates m_coordinates = Coordinates::Generated;
    glm::mat3 m_linear{1.f};
    Vec3 m_offset{0.f};
    Rgb m_scale{1.f};
};

// A procedural kind's parameters from TextureDesc::params, checked against the kind's table
// (errors name ptr/<kind>/<key>).
class ProceduralParams {
  public:
    ProceduralParams(TextureBuild& b, const TextureKindDef& kind) : m_b(b), m_kind(kind) {}
    // A Number parameter's value (the default when absent).
    double number(std::string_view name) const;
    // A String parameter's index in its choices.
    int choice(std::string_view name) const;
    // A Bool parameter's value (default: default_number != 0).
    bool flag(std::string_view name) const;
    // A Color parameter's constant (a number is grey; default: default_color).
    Rgb color(std::string_view name) const;
    std::string pointer(std::string_view name) const;

  private:
    TextureBuild& m_b;
    const TextureKindDef& m_kind;
};

// Checks the description's parameters, inputs and stops against the kind's table (unknown
// names, types, ranges, choices, stop order); errors name ptr/<kind>/<key>.
void check_texture_params(TextureBuild& b, const TextureKindDef& kind);

// Checks every parameter of the description against the kind's table (unknown names, types,
// ranges, choices), fills the shared parts of `source` (coordinates, mapping, scale) and makes
// the texture, its values in [lo, hi] per channel before the scale. `reads`: what its input
// textures read (TextureInput bits), besides its point.
Texture make_procedural(TextureBuild& b, const TextureKindDef& kind,
                        std::shared_ptr<ProceduralSource> source, Rgb lo, Rgb hi,
                        unsigned reads = 0);

// The texture itself, or, when the description has a "channel" (r, g, b or luminance: Rec. 709
// weights 0.2126, 0.7152, 0.0722, as for images), that channel of its value as grey.
Texture with_channel(TextureBuild& b, Texture t);

// TextureDesc::coordinates' names, in the order of ProceduralSource::Coordinates.
inline const std::vector<std::string> kCoordinateNames = {"generated",  "object", "uv",    "normal",
                                                          "reflection", "camera", "window"};

// The parameters every procedural kind's "output" choice shares.
inline constexpr std::string_view kOutputDoc = "which output of the node is the value";

}  // namespace facet::render
