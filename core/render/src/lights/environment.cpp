// Light kind "environment": radiance arriving from every direction that escapes the scene (at
// most one per scene): a constant, or an equirectangular image (environment_map.h) oriented by
// "up" and "rotate". The constant environment's light type is here; the map's is in
// environment_map.cpp.
//
// Sampling (light.h conventions): the constant environment samples the cosine-weighted
// hemisphere about ctx.n (the whole sphere uniformly when n = 0); li = L. Next-event estimation
// does not sample it (nee = false, light.h nee_samples: BSDF sampling finds it). Its power for
// the light choice is L from every direction through a disc of the scene's cross-section,
// 4 pi^2 R^2 L (R the scene's bounding radius).
#include <glm/gtc/matrix_transform.hpp>

#include <cctype>
#include <cmath>
#include <filesystem>
#include <functional>

#include "../io/pov_writer.h"
#include "../kind_build.h"
#include "facet/render/environment_map.h"
#include "facet/render/texel_image.h"
#include "sampling.h"

namespace facet::render {

namespace {

// R_up (environment_map.h): the smallest rotation taking +Z to the unit vector `up`.
glm::dmat3 up_rotation(const glm::dvec3& up) {
    const glm::dvec3 z(0.0, 0.0, 1.0);
    const double c = glm::dot(z, up);
    const glm::dvec3 axis = glm::cross(z, up);
    const double s = glm::length(axis);
    if (!(s > 1e-12)) {
        // +Z: the identity; -Z: a half turn about X (keeps +X, flips Y and Z).
        return c > 0.0
                   ? glm::dmat3(1.0)
                   : glm::dmat3(glm::dvec3(1, 0, 0), glm::dvec3(0, -1, 0), glm::dvec3(0, 0, -1));
    }
    return glm::dmat3(glm::rotate(glm::dmat4(1.0), std::atan2(s, c), axis / s));
}

// M (environment_map.h) of the light at `ptr`; `fail` (which does not return) names the pointer
// of a zero or non-finite up or axis, or a non-finite angle. One function for the builder and
// the exporter.
using Fail = std::function<void(const std::string&, const std::string&)>;
Vec3 checked_unit(const Vec3& v, const std::string& ptr, const Fail& fail) {
    const float len = glm::length(v);
    if (!is_finite(v) || !(len > 0.f) || !std::isfinite(len))
        fail(ptr, "must be a finite, non-zero direction");
    return v / len;
}
glm::dmat3 map_frame(const LightDesc& l, const std::string& ptr, const Fail& fail) {
    glm::dmat3 frame(1.0);
    if (l.up) frame = up_rotation(glm::dvec3(checked_unit(*l.up, ptr + "/up", fail)));
    if (l.rotate) {
        const Vec3 axis = checked_unit(l.rotate->axis, ptr + "/rotate/axis", fail);
        if (!std::isfinite(l.rotate->angle)) fail(ptr + "/rotate/angle", "must be a finite number");
        frame = glm::dmat3(
                    glm::rotate(glm::dmat4(1.0), glm::radians(l.rotate->angle), glm::dvec3(axis))) *
                frame;
    }
    return frame;
}

// Negative texels: lossy EXR codecs (DWAA, B44, PXR24) undershoot near black, and Blender's own
// studio-light HDRIs hold such values: down to -0.0039 (sunrise.exr, mean 0.47) and -0.0033
// (night.exr, mean 0.13, i.e. 2.5% of it), measured with `oiiotool --stats` on Blender 3.4.1's
// eight maps. A texel channel v < 0 with v >= -kNoise * m, m the mean of all colour texel values
// and kNoise = 0.05 (twice the worst of those maps), is that noise: it is set to 0 and reported
// once (how many, the most negative). Anything more negative is an error naming the file and the
// texel, as before. (Test: EnvironmentMap.BlenderStudioHdrisLoad.)
void clamp_compression_noise(TexelImage& image, const std::string& path, const std::string& where,
                             LightBuild& b) {
    double sum = 0.0;
    for (float v : image.texels) sum += v;
    const double mean = image.texels.empty() ? 0.0 : sum / double(image.texels.size());
    constexpr double kNoise = 0.05;
    const double tolerance = kNoise * std::max(mean, 0.0);
    std::size_t clamped = 0;
    float lowest = 0.f;
    const std::size_t channels = std::size_t(image.channels);
    for (std::size_t i = 0; i < image.texels.size(); ++i) {
        float& v = image.texels[i];
        if (!(v < 0.f)) continue;
        if (double(v) < -tolerance) {
            const std::size_t t = i / channels;
            b.fail(where, path + ": texel (" + std::to_string(t % std::size_t(image.width)) + ", " +
                              std::to_string(t / std::size_t(image.width)) + ") channel " +
                              std::to_string(i % channels) + " is negative: " + std::to_string(v) +
                              ", below the compression-noise tolerance -" +
                              std::to_string(tolerance) + " (5% of the mean; row 0 at the top)");
        }
        lowest = std::min(lowest, v);
        v = 0.f;
        ++clamped;
    }
    if (clamped > 0)
        b.warn(where + ": " + path + ": " + std::to_string(clamped) +
               " slightly negative texel values (compression noise, the lowest " +
               std::to_string(lowest) + ") read as 0");
}

void build(LightBuild& b) {
    const LightDesc& l = b.light;
    const std::string& ptr = b.ptr;
    if (l.file.empty()) {
        for (const auto& [given, key] :
             {std::pair{l.rotate.has_value(), "rotate"}, std::pair{l.up.has_value(), "up"}}) {
            if (given)
                b.fail(ptr + "/" + key,
                       "orients an environment map: give \"file\" (a constant environment "
                       "looks the same from every direction)");
        }
        if (!l.radiance) b.fail(ptr + "/radiance", "is required (or give a map as \"file\")");
        b.add_environment(
            Light::environment(b.check_color(*l.radiance, ptr + "/radiance", "a radiance")));
        return;
    }
    const Rgb multiplier =
        l.radiance ? b.check_color(*l.radiance, ptr + "/radiance", "a radiance multiplier")
                   : Rgb(1.f);
    const glm::dmat3 frame =
        map_frame(l, ptr, [&](const std::string& p, const std::string& m) { b.fail(p, m); });
    if (!b.files_allowed()) b.fail(ptr + "/file", "image files are disabled here");
    const std::string path = resolve_scene_path(l.file, b.base_dir());
    TexelImage image;
    const std::string where = ptr + "/file";
    try {
        // Auto colour space: float files linear, 8/16-bit files sRGB-decoded (texel_image.h).
        // NaN and Inf are errors there; negative texels are judged below.
        image = load_texel_image(path, {ColorSpace::Auto, false}, where);
    } catch (const TexelImageError& e) {
        // "<where>: <file>: <what>"; fail() names the pointer itself.
        std::string m = e.what();
        if (m.rfind(where + ": ", 0) == 0) m.erase(0, where.size() + 2);
        b.fail(where, m);
    }
    clamp_compression_noise(image, path, where, b);
    b.add_environment(Light::environment_map(
        std::make_shared<const EnvironmentMap>(image, multiplier, glm::mat3(frame))));
}

// The map as POV-Ray's sky_sphere (--environment background only, as the constant: seen by
// camera and mirror rays, lighting no surface). POV-Ray's spherical image map (map_type 1)
// looks the pattern point q up at u = atan2(q.z, q.x) / 2pi (mod 1) from the left edge and
// at the polar angle from +y over pi from the top row, and the exporter keeps Facet's world
// coordinates (the camera's right/up vectors carry the handedness). With l = M^T d the map's
// frame (environment_map.h), q = F l, F = [[-1, 0, 0], [0, 0, 1], [0, 1, 0]], gives Blender's
// u = 0.5 - atan2(l.y, l.x) / 2pi and v = theta / pi: the pigment's transform (pattern ->
// world) is T = M F (F = F^-1). Its bilinear lookup (interpolate 2) puts texel centres where
// Facet does; it wraps around vertically where Facet clamps (stated in the comment).
void write_map(PovLightOut& o, bool light) {
    const LightDesc& l = o.light;
    if (l.radiance && *l.radiance != Rgb(1.f))
        o.fail(o.pointer + "/radiance",
               "POV-Ray's sky_sphere cannot scale an image map's colours: only a multiplier of 1 "
               "is exported exactly");
    const std::filesystem::path path(resolve_scene_path(l.file, o.base_dir));
    std::string ext = path.extension().string();
    for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
    const char* type = ext == ".exr" ? "exr" : ext == ".hdr" ? "hdr" : nullptr;
    if (!type)
        o.fail(o.pointer + "/file",
               "only .exr and .hdr maps are exported (POV-Ray's decoding of 8-bit files differs "
               "from Facet's sRGB decoding)");
    const glm::dmat3 m =
        map_frame(l, o.pointer, [&](const std::string& p, const std::string& e) { o.fail(p, e); });
    const glm::dmat3 f(glm::dvec3(-1, 0, 0), glm::dvec3(0, 0, 1), glm::dvec3(0, 1, 0));
    const glm::dmat3 t = m * f;
    std::string file = std::filesystem::absolute(path).lexically_normal().string();
    if (file.find('"') != std::string::npos || file.find('\n') != std::string::npos)
        o.fail(o.pointer + "/file", "the path cannot be written as a POV-Ray string");
    o.out() << "sky_sphere {  // " << o.pointer
            << (light ? ": environment map, lighting brdf finishes by brdf_sky_sampling "
                        "(approximation: "
                      : ": environment map, seen by camera and mirror rays only (approximation: "
                        "it lights no surface; ")
            << "within half a texel row of the poles POV-Ray's lookup wraps to the opposite row "
               "where Facet's clamps)\n  pigment { image_map { "
            << type << " \"" << file << "\" map_type 1 interpolate 2 }\n    matrix <"
            << pov_num(t[0].x) << ", " << pov_num(t[0].y) << ", " << pov_num(t[0].z) << ", "
            << pov_num(t[1].x) << ", " << pov_num(t[1].y) << ", " << pov_num(t[1].z) << ", "
            << pov_num(t[2].x) << ", " << pov_num(t[2].y) << ", " << pov_num(t[2].z)
            << ", 0, 0, 0> }\n}\n";
}

void pov(PovLightOut& o) {
    if (o.options.environment == "light") {
        // povray-facet's brdf_sky_sampling (global_settings) makes brdf finishes sample it.
        if (!o.light.file.empty()) return write_map(o, true);
        if (!o.light.radiance)
            o.fail(o.pointer + "/radiance", "is required (or give a map as \"file\")");
        o.out() << "sky_sphere { pigment { " << pov_rgb(glm::dvec3(*o.light.radiance))
                << " } }  // " << o.pointer
                << ": constant environment, lighting brdf finishes by brdf_sky_sampling\n";
        return;
    }
    if (o.options.environment == "background") {
        if (!o.light.file.empty()) return write_map(o, false);
        if (!o.light.radiance)
            o.fail(o.pointer + "/radiance", "is required (or give a map as \"file\")");
        o.out() << "background { " << pov_rgb(glm::dvec3(*o.light.radiance)) << " }  // "
                << o.pointer
                << ": environment, seen by camera and mirror rays only (approximation: it lights "
                   "no surface)\n";
        return;
    }
    o.fail(o.pointer,
           "an environment light lights every surface from every unoccluded direction, which "
           "POV-Ray cannot express exactly (radiosity only approximates it); --environment "
           "light exports it as a sky_sphere that povray-facet's brdf finishes sample "
           "(brdf_sky_sampling), --environment background as the background only");
}

}  // namespace

std::optional<LightLiSample> ConstantEnvironment::sample_li(const LightSampleContext& ctx,
                                                            Vec2 u) const {
    LightLiSample s;
    if (ctx.n != Vec3(0.f)) {
        Vec3 local = sample_cosine_hemisphere(u);
        s.pdf = cosine_hemisphere_pdf(local.z);
        s.wi = Frame::from_z(ctx.n).from_local(local);
    } else {
        s.wi = sample_uniform_sphere(u);
        s.pdf = uniform_sphere_pdf();
    }
    if (!(s.pdf > 0.f)) return std::nullopt;
    s.li = radiance;
    s.dist = kInfinity;
    return s;
}

float ConstantEnvironment::pdf_li(const LightSampleContext& ctx, const Vec3& wi, const Vec3&,
                                  const Vec3&) const {
    if (ctx.n != Vec3(0.f)) return cosine_hemisphere_pdf(glm::dot(ctx.n, wi));
    return uniform_sphere_pdf();
}

void ConstantEnvironment::note(SceneFeatures& f) {
    f.has_environment = true;
}

Light Light::environment(const Rgb& radiance) {
    return make(ConstantEnvironment{radiance}, {.emission = radiance});
}

extern const LightKindDef kEnvironmentLightKind{
    LightKind::Environment,
    "environment",
    "radiance arriving from every direction that escapes the scene (at most one): a constant, "
    "or an equirectangular map (see [Environment maps](#environment-maps))",
    {{"radiance", FieldType::Color, false, &LightDesc::radiance,
      "required without `file`; 1 with `file`",
      "a radiance L (W sr^-1 m^-2), or with `file` the multiplier of the map's texels"},
     {"file", FieldType::Path, false, &LightDesc::file, "-",
      "an equirectangular image (EXR, HDR, PNG sRGB-decoded, ... relative to the scene file); "
      "direction d looks up u = 0.5 - atan2(d.y, d.x) / 2pi from the left edge, v = theta / pi "
      "from the top row (Blender's Environment Texture, Z up)"},
     {"up", FieldType::Direction, false, &LightDesc::up, "[0, 0, 1]",
      "the world direction of the map's top row (smallest rotation from +Z); `file` only"},
     {"rotate", FieldType::Rotation, false, &LightDesc::rotate, "none",
      "rotates the map (after `up`) by `angle` degrees about `axis`, right-handed, in world "
      "space; `file` only"}},
    {},
    build,
    pov};

}  // namespace facet::render
