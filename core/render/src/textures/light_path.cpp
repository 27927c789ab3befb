// Texture kind "light_path": an output of Blender 3.4's Light Path node for the ray that reached
// the hit, as Cycles 3.4's svm_node_light_path gives it to a surface shader (TexturePoint::ray,
// texture.h RayState):
//  - is_camera_ray, is_diffuse_ray, is_glossy_ray, is_singular_ray, is_reflection_ray,
//    is_transmission_ray: 1 when the ray is of that kind (scene.h LightPathRay), else 0;
//  - ray_length: the distance the ray travelled from its origin to the hit;
//  - ray_depth, diffuse_depth, glossy_depth, transmission_depth: the bounces before the hit.
// Shading never runs for shadow rays here, so Is Shadow Ray is not an output (the shape's Light
// Path switches, scene.h LightPathSwitch, take it). A composite-like kind: it reads no point,
// only the ray (kTextureReadsRay), which the kernel of scenes that read it tracks.
#include <cfloat>

#include "composite.h"
#include "facet/render/scene.h"

namespace facet::render {

namespace {

enum class Output {
    IsCamera,
    IsDiffuse,
    IsGlossy,
    IsSingular,
    IsReflection,
    IsTransmission,
    RayLength,
    RayDepth,
    DiffuseDepth,
    GlossyDepth,
    TransmissionDepth
};

const std::vector<std::string> kOutputs = {
    "is_camera_ray",     "is_diffuse_ray",      "is_glossy_ray",     "is_singular_ray",
    "is_reflection_ray", "is_transmission_ray", "ray_length",        "ray_depth",
    "diffuse_depth",     "glossy_depth",        "transmission_depth"};

// The largest depth a path reaches (render settings' max_depth bound).
constexpr float kMaxRayDepth = 1024.f;

class LightPathSource final : public CompositeSource {
  public:
    Output m_output = Output::IsCamera;
    Rgb value(const TexturePoint& p) const override {
        static constexpr RayState kCamera{};
        const RayState& r = p.ray ? *p.ray : kCamera;
        auto bit = [&](std::uint8_t b) { return Rgb((r.kinds & b) != 0 ? 1.f : 0.f); };
        switch (m_output) {
            case Output::IsCamera:
                return bit(kLpCamera);
            case Output::IsDiffuse:
                return bit(kLpDiffuse);
            case Output::IsGlossy:
                return bit(kLpGlossy);
            case Output::IsSingular:
                return bit(kLpSingular);
            case Output::IsReflection:
                return bit(kLpReflection);
            case Output::IsTransmission:
                return bit(kLpTransmission);
            case Output::RayLength:
                return Rgb(std::min(r.length, FLT_MAX));
            case Output::RayDepth:
                return Rgb(float(r.depth));
            case Output::DiffuseDepth:
                return Rgb(float(r.diffuse));
            case Output::GlossyDepth:
                return Rgb(float(r.glossy));
            case Output::TransmissionDepth:
            default:
                return Rgb(float(r.transmission));
        }
    }
};

Texture build_light_path(TextureBuild& b) {
    check_texture_params(b, kLightPathTexture);
    auto s = std::make_shared<LightPathSource>();
    const CompositeParams p(b, kLightPathTexture);
    s->m_output = Output(p.choice("output"));
    const float hi = s->m_output == Output::RayLength  ? FLT_MAX
                     : s->m_output >= Output::RayDepth ? kMaxRayDepth
                                                       : 1.f;
    return make_composite(b, kLightPathTexture, s, Rgb(0.f), Rgb(hi), kTextureReadsRay,
                          "light_path");
}

}  // namespace

const TextureKindDef kLightPathTexture{
    "light_path",
    "Blender's Light Path node for the ray that reached the hit, as Cycles 3.4 gives it to a "
    "surface: `is_camera_ray`, `is_diffuse_ray`, `is_glossy_ray`, `is_singular_ray`, "
    "`is_reflection_ray`, `is_transmission_ray` (1 or 0), `ray_length` (the distance from the "
    "ray's origin), `ray_depth`, `diffuse_depth`, `glossy_depth`, `transmission_depth` (the "
    "bounces before the hit; [Light Path outputs](#light-path-outputs)). Only in a material's "
    "parameters and combinations' weights (no coordinates)",
    {
        {"output", ParamType::String, 0, "is_camera_ray", 0, 0, false, kOutputs, kOutputDoc},
    },
    true,
    build_light_path,
    true,
};

}  // namespace facet::render
