// Private to facet_render: what a texture kind's builder (texture_kinds.h) gets from
// build_scene. The builder (build_materials.cpp: TextureContext) implements it; the kind units
// (textures/*.cpp) call it. Every check fails with a SceneError naming the JSON pointer
// (`ptr` + "/key").
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "../kind_build.h"
#include "facet/render/texel_image.h"
#include "facet/render/texture.h"
#include "facet/render/texture_kinds.h"

namespace facet::render {

// The kinds (one unit each; the table: texture_kinds.cpp).
extern const TextureKindDef kImageTexture;        // textures/image.cpp
extern const TextureKindDef kCheckerTexture;      // textures/checker.cpp
extern const TextureKindDef kVertexColorTexture;  // textures/vertex_color.cpp
extern const TextureKindDef kNoiseTexture;        // textures/noise.cpp
extern const TextureKindDef kWhiteNoiseTexture;   // textures/white_noise.cpp
extern const TextureKindDef kGradientTexture;     // textures/gradient.cpp
extern const TextureKindDef kVoronoiTexture;      // textures/voronoi.cpp
extern const TextureKindDef kMusgraveTexture;     // textures/musgrave.cpp
extern const TextureKindDef kWaveTexture;         // textures/wave.cpp
extern const TextureKindDef kMagicTexture;        // textures/magic.cpp
extern const TextureKindDef kBrickTexture;        // textures/brick.cpp
extern const TextureKindDef kMathTexture;         // textures/math.cpp
extern const TextureKindDef kMixRgbTexture;       // textures/mix_rgb.cpp
extern const TextureKindDef kColorRampTexture;    // textures/color_ramp.cpp
extern const TextureKindDef kHairInfoTexture;     // textures/hair_info.cpp
extern const TextureKindDef kLightPathTexture;    // textures/light_path.cpp
extern const TextureKindDef kVectorMathTexture;   // textures/vector_math.cpp

class TextureBuild : public BuildChecks {
  public:
    TextureBuild(const TextureDesc& d, std::string p, bool c, bool r)
        : desc(d), ptr(std::move(p)), color(c), radiance(r) {}
    const TextureDesc& desc;
    const std::string ptr;  // the texture's JSON pointer
    // The parameter is a colour (else a number: one channel); negative values are errors
    // (an emitted radiance).
    const bool color, radiance;

    // Image files may be read (not for in-memory scenes that forbid it).
    virtual bool files_allowed() const = 0;
    // The texture's image (desc.file, bytes or image), decoded with `opt`, shared per file.
    virtual std::shared_ptr<const TexelImage> load_image(const TexelImageOptions& opt) = 0;
    // Its MIP levels 1, 2, ... (shared per image).
    virtual std::shared_ptr<const std::vector<TexelImage>> mip_levels(
        const std::shared_ptr<const TexelImage>& img) = 0;
    // A composite kind's input texture `d` at pointer `p`, built and validated as any texture
    // (`color`: it feeds a colour input, else a number one).
    virtual Texture build_input(const TextureDesc& d, const std::string& p, bool color) = 0;

    // The index of `value` in `allowed`, else an error at ptr/key listing them.
    int choose(const std::string& key, const std::string& value,
               const std::vector<std::string>& allowed) const {
        const auto it = std::find(allowed.begin(), allowed.end(), value);
        if (it != allowed.end()) return int(it - allowed.begin());
        std::string msg = "unknown value '" + value + "' (expected one of";
        for (const auto& a : allowed) msg += " " + a;
        msg += ")";
        const std::string g = closest_name(value, allowed);
        if (!g.empty()) msg += " (did you mean '" + g + "'?)";
        fail(ptr + "/" + key, msg);
    }
};

}  // namespace facet::render
