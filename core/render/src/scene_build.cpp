// build_scene: SceneDescription -> Scene (facet/render/scene_description.h), with every value
// validated, and the scene analysis (SceneFeatures). Every error is a SceneError
// "<name>: <path>: <message>" with the JSON pointer the value would have in a scene file.
#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <chrono>
#include <cstring>
#include <filesystem>
#include <limits>
#include <map>
#include <set>
#include <sstream>

#include "facet/frame.h"
#include "facet/reflectance.h"
#include "facet/render/kinds.h"
#include "facet/render/scene_description.h"
#include "facet/render/texel_pages.h"
#include "kind_build.h"
#include "scene_checks.h"
#include "scene_impl.h"
#include "scene_precision.h"
#include "shapes/analytic.h"
#include "textures/texture_build.h"

namespace facet::render {

using detail::escape_pointer_token;

MeshData MeshData::copy_of(std::vector<float> positions, std::vector<std::uint32_t> indices,
                           std::vector<float> normals, std::vector<float> uvs,
                           std::vector<float> tangents, std::vector<float> colors) {
    struct Arrays {
        std::vector<float> p;
        std::vector<std::uint32_t> i;
        std::vector<float> n, uv, t, c;
    };
    auto a = std::make_shared<Arrays>(Arrays{std::move(positions), std::move(indices),
                                             std::move(normals), std::move(uvs),
                                             std::move(tangents), std::move(colors)});
    MeshData m;
    m.positions = a->p;
    m.indices = a->i;
    m.normals = a->n;
    m.uvs = a->uv;
    m.tangents = a->t;
    m.colors = a->c;
    m.owner = a;
    return m;
}

bool MeshData::operator==(const MeshData& o) const {
    auto same = [](auto a, auto b) {
        return a.size() == b.size() &&
               (a.empty() || std::memcmp(a.data(), b.data(), a.size_bytes()) == 0);
    };
    return same(positions, o.positions) && same(indices, o.indices) && same(normals, o.normals) &&
           same(uvs, o.uvs) && same(tangents, o.tangents) && same(colors, o.colors);
}

bool SceneDescription::operator==(const SceneDescription& o) const {
    return description == o.description && camera == o.camera && materials == o.materials &&
           shapes == o.shapes && prototypes == o.prototypes && lights == o.lights &&
           media == o.media && world_medium == o.world_medium &&
           render.integrator == o.render.integrator && render.spp == o.render.spp &&
           render.time_budget_s == o.render.time_budget_s &&
           render.max_depth == o.render.max_depth && render.seed == o.render.seed &&
           render.adaptive_threshold == o.render.adaptive_threshold &&
           render.adaptive_min_samples == o.render.adaptive_min_samples &&
           render.motion_blur == o.render.motion_blur &&
           render.film_transparent == o.render.film_transparent;
}

namespace {

// Largest |component| of a vector, in double.
double max_abs(const glm::dvec3& v) {
    return std::max({std::fabs(v.x), std::fabs(v.y), std::fabs(v.z)});
}

class Builder final : public BuildChecks {
  public:
    Builder(const SceneDescription& desc, std::string name, const SceneLimits& limits,
            BuildReport* report)
        : m_desc(desc),
          m_name(std::move(name)),
          m_limits(limits),
          m_report(report),
          m_images(limits.texture_memory) {}

    Scene build() {
        const auto t0 = std::chrono::steady_clock::now();
        m_builder.name() = m_name;
        m_builder.fingerprint() = fingerprint(m_desc);
        if (m_limits.texture_memory < kMinTextureMemory)
            throw SceneError(m_name + ": the texture memory bound of " +
                             std::to_string(m_limits.texture_memory) +
                             " bytes is below the smallest, 1 MiB (SceneLimits::texture_memory)");
        build_motion();
        build_camera();
        build_media();
        build_materials();
        for (std::size_t i = 0; i < m_desc.shapes.size(); ++i) {
            build_shape(m_desc.shapes[i], std::uint32_t(i), "/shapes/" + std::to_string(i), -1);
        }
        build_prototypes();
        for (std::size_t i = 0; i < m_desc.lights.size(); ++i) {
            build_light(m_desc.lights[i], i);
        }
        if (m_builder.lights().empty()) {
            fail("/lights",
                 "the scene has no light source (no entry in \"lights\" and no shape that "
                 "emits: \"emission\" or a glTF emissive material)");
        }
        check_precision(m_builder, m_desc, m_name);  // scene_precision.h
        build_render();
        const auto t1 = std::chrono::steady_clock::now();
        m_builder.impl().build(m_name);
        const auto t2 = std::chrono::steady_clock::now();
        analyse();
        m_builder.light_distribution() =
            LightDistribution(m_builder.scene.lights(), m_builder.scene.radius());
        for (std::size_t i = 0; i < m_builder.lights().size(); ++i)
            if (m_builder.lights()[i].camera_visible())
                m_builder.camera_lamps().push_back(std::uint32_t(i));
        if (m_report) {
            m_report->degenerate_triangles = m_degenerate;
            m_report->warnings = m_builder.warnings();
            m_report->seconds_before_bvh = std::chrono::duration<double>(t1 - t0).count();
            m_report->seconds_bvh = std::chrono::duration<double>(t2 - t1).count();
        }
        m_builder.texture_memory() = m_images.stats();
        m_builder.tile_cache() = m_images.tile_cache();
        // Last: its pilot traces rays through the finished scene (textures, tile cache).
        m_builder.view_light_distribution() = LightDistribution::view(m_builder.scene);
        return std::move(m_builder.scene);
    }

    [[noreturn]] void fail(const std::string& pointer, const std::string& message) const override {
        throw SceneError(m_name + ": " + (pointer.empty() ? std::string("/") : pointer) + ": " +
                         message);
    }

  private:
    // "/shapes/3" or "/shapes/3 ('Suzanne')" (or "/prototypes/tree/0 ...") for messages about a
    // shape as a whole (index: in Scene::shapes()).
    std::string shape_place(std::uint32_t index) const { return m_places[index]; }

    // --- camera, render ------------------------------------------------------------------------

    void build_camera() {
        const CameraDesc& c = m_desc.camera;
        const std::string ptr = "/camera";
        check_finite(c.position, ptr + "/position");
        check_finite(c.look_at, ptr + "/look_at");
        check_finite(c.up, ptr + "/up");
        const std::vector<std::string> types = {"perspective", "orthographic"};
        if (std::find(types.begin(), types.end(), c.type) == types.end()) {
            std::string msg = "unknown camera type '" + c.type + "'";
            std::string g = closest_name(c.type, types);
            msg += g.empty() ? " (expected perspective or orthographic)"
                             : " (did you mean '" + g + "'?)";
            fail(ptr + "/type", msg);
        }
        CameraOptions o;
        double fov = 40.0;
        if (c.type == "perspective") {
            fov = check_range(c.fov, ptr + "/fov", 1e-3, 179.0,
                              "in [0.001, 179] degrees (full vertical angle)");
            if (c.scale) fail(ptr + "/scale", "'scale' is for orthographic cameras");
        } else {
            o.projection = Projection::Orthographic;
            if (!c.scale) fail(ptr + "/scale", "required for an orthographic camera");
            o.ortho_scale = float(positive_length(*c.scale, ptr + "/scale"));
        }
        o.shift_x = float(check_range(c.shift_x, ptr + "/shift_x", -1e3, 1e3, "in [-1000, 1000]"));
        o.shift_y = float(check_range(c.shift_y, ptr + "/shift_y", -1e3, 1e3, "in [-1000, 1000]"));
        o.aperture_radius = float(checked_aperture_radius(c, ptr, o.projection));
        if (c.focus_distance || o.aperture_radius > 0.f) {
            if (!c.focus_distance)
                fail(ptr + "/focus_distance",
                     "required with an aperture (aperture_radius or fstop)");
            o.focus_distance = float(positive_length(*c.focus_distance, ptr + "/focus_distance"));
        }
        if (c.blades == 1 || c.blades == 2)
            fail(ptr + "/blades",
                 "must be 0 (round aperture) or at least 3, got " + std::to_string(c.blades));
        o.blades = int(check_int(c.blades, ptr + "/blades", 0, 1024));
        o.rotation_deg = float(
            check_range(c.rotation, ptr + "/rotation", -1e6, 1e6, "a finite angle in degrees"));
        int w = int(check_int(c.width, ptr + "/width", 1, detail::kMaxImageSide));
        int h = int(check_int(c.height, ptr + "/height", 1, detail::kMaxImageSide));
        for (const char* key : {"position", "look_at"}) {
            const Vec3& v = key[0] == 'p' ? c.position : c.look_at;
            if (max_abs(glm::dvec3(v)) > Scene::kMaxCoordinate) {
                std::ostringstream msg;
                msg << "beyond the renderer's coordinate range of +-" << Scene::kMaxCoordinate;
                fail(ptr + "/" + key, msg.str());
            }
        }
        if (std::int64_t(w) * h > m_limits.max_pixels) {
            fail(ptr, "the image has too many pixels (limit " +
                          std::to_string(m_limits.max_pixels) + ")");
        }
        // A frame (position, look_at, up) at `p`: look_at away from position, up not parallel.
        auto check_frame = [&](const Vec3& position, const Vec3& look_at, const Vec3& up,
                               const std::string& p) {
            glm::dvec3 f = glm::dvec3(look_at) - glm::dvec3(position);
            double flen = glm::length(f);
            if (!(flen > 0.0)) fail(p + "/look_at", "must differ from the camera position");
            glm::dvec3 cr = glm::cross(f / flen, glm::dvec3(up));
            if (!(glm::length(cr) > 1e-6 * glm::length(glm::dvec3(up)))) {
                fail(p + "/up", "must not be zero or parallel to the view direction");
            }
        };
        check_frame(c.position, c.look_at, c.up, ptr);
        m_builder.camera() = Camera::make(c.position, c.look_at, c.up, float(fov), w, h, o);
        if (c.motion.empty()) return;
        if (c.motion.size() < 2)
            fail(ptr + "/motion",
                 "needs at least 2 steps (the camera at shutter open and close), got " +
                     std::to_string(c.motion.size()));
        if (c.motion.size() > kMaxMotionSteps)
            fail(ptr + "/motion", "at most " + std::to_string(kMaxMotionSteps) + " steps");
        std::vector<Camera> steps;
        for (std::size_t i = 0; i < c.motion.size(); ++i) {
            const CameraDesc::Step& st = c.motion[i];
            const std::string sp = ptr + "/motion/" + std::to_string(i);
            check_finite(st.position, sp + "/position");
            check_finite(st.look_at, sp + "/look_at");
            check_finite(st.up, sp + "/up");
            for (const Vec3* v : {&st.position, &st.look_at})
                if (max_abs(glm::dvec3(*v)) > Scene::kMaxCoordinate)
                    fail(sp + (v == &st.position ? "/position" : "/look_at"),
                         "beyond the renderer's coordinate range");
            check_frame(st.position, st.look_at, st.up, sp);
            steps.push_back(Camera::make(st.position, st.look_at, st.up, float(fov), w, h, o));
        }
        // Without motion blur the still camera renders (position, look_at, up).
        if (!m_motion_on) return;
        m_builder.camera_motion().steps = std::move(steps);
        m_camera_moves = true;
    }

    // "render"/"motion_blur" (scenes/FORMAT.md, "Motion blur"): checked whether on or off;
    // the shutter curve when on.
    void build_motion() {
        const std::optional<RenderSettings::MotionBlur>& mb = m_desc.render.motion_blur;
        if (!mb) return;
        const std::string ptr = "/render/motion_blur";
        check_finite(mb->shutter, ptr + "/shutter");
        if (!(mb->shutter > 0.0))
            fail(ptr + "/shutter", "must be > 0 (the time the shutter is open, in frames)");
        const std::vector<std::string> positions = {"start", "center", "end"};
        if (std::find(positions.begin(), positions.end(), mb->position) == positions.end()) {
            std::string msg = "unknown shutter position '" + mb->position + "'";
            const std::string g = closest_name(mb->position, positions);
            msg += g.empty() ? " (expected start, center or end)" : " (did you mean '" + g + "'?)";
            fail(ptr + "/position", msg);
        }
        if (mb->curve.size() > kMaxShutterCurve)
            fail(ptr + "/curve", "at most " + std::to_string(kMaxShutterCurve) + " values");
        double total = 0.0;
        for (std::size_t i = 0; i < mb->curve.size(); ++i) {
            const std::string cp = ptr + "/curve/" + std::to_string(i);
            check_finite(mb->curve[i], cp);
            if (!(mb->curve[i] >= 0.0)) fail(cp, "must be >= 0 (a weight of the shutter curve)");
            total += mb->curve[i];
        }
        if (!mb->curve.empty() && !(total > 0.0 && std::isfinite(total)))
            fail(ptr + "/curve", "the shutter curve is zero everywhere (no time to sample)");
        m_motion_on = mb->enabled;
        if (m_motion_on) m_builder.shutter() = ShutterCurve(mb->curve);
    }

    // Motion steps beyond this are an error (Blender's Steps 1..7 give 2^Steps + 1 <= 129).
    static constexpr std::size_t kMaxMotionSteps = 1024;
    static constexpr std::size_t kMaxShutterCurve = 65536;

    // The thin lens's radius (scene units) from aperture_radius, or fstop and focal_length
    // (mm) as Cycles computes it (blender/camera.cpp): focal_length 1e-3 / (2 fstop), i.e.
    // scene units taken as metres. 0 = pinhole.
    double checked_aperture_radius(const CameraDesc& c, const std::string& ptr,
                                   Projection proj) const {
        if (c.aperture_radius && c.fstop)
            fail(ptr + "/fstop", "give aperture_radius or fstop (with focal_length), not both");
        if (c.focal_length && !c.fstop)
            fail(ptr + "/focal_length", "only used with fstop (the aperture from an f-number)");
        if (c.aperture_radius) {
            return check_range(*c.aperture_radius, ptr + "/aperture_radius", 0.0,
                               Scene::kMaxCoordinate, ">= 0 (scene units)");
        }
        if (!c.fstop) return 0.0;
        if (proj == Projection::Orthographic) {
            fail(ptr + "/fstop",
                 "an orthographic camera has no focal length: give "
                 "aperture_radius (Cycles uses 1 / (2 fstop))");
        }
        positive_length(*c.fstop, ptr + "/fstop");
        if (!c.focal_length) fail(ptr + "/focal_length", "required with fstop (millimetres)");
        positive_length(*c.focal_length, ptr + "/focal_length");
        const double radius = aperture_radius(c);
        if (!(radius <= Scene::kMaxCoordinate))
            fail(ptr + "/fstop", "the aperture focal_length / 1000 / (2 fstop) is too large");
        return radius;
    }

    void build_render() {
        const RenderSettings& r = m_desc.render;
        const std::string ptr = "/render";
        RenderSettings& s = m_builder.settings();
        const std::vector<std::string> known = {"direct", "path"};
        if (std::find(known.begin(), known.end(), r.integrator) == known.end()) {
            std::string msg = "unknown integrator '" + r.integrator + "'";
            std::string g = closest_name(r.integrator, known);
            msg += g.empty() ? " (expected direct or path)" : " (did you mean '" + g + "'?)";
            fail(ptr + "/integrator", msg);
        }
        s.integrator = r.integrator;
        s.spp = int(check_int(r.spp, ptr + "/spp", 1, detail::kMaxSpp));
        s.time_budget_s =
            check_range(r.time_budget_s, ptr + "/time_budget", 0.0, 1e7, "in [0, 1e7] seconds");
        s.max_depth = int(check_int(r.max_depth, ptr + "/max_depth", 0, detail::kMaxDepth));
        s.seed = r.seed;
        s.adaptive_threshold = check_range(r.adaptive_threshold, ptr + "/adaptive_threshold", 0.0,
                                           1.0, "in [0, 1] (0 = off)");
        s.adaptive_min_samples = int(
            check_int(r.adaptive_min_samples, ptr + "/adaptive_min_samples", 0, detail::kMaxSpp));
        s.width = m_builder.camera().width;
        s.height = m_builder.camera().height;
        s.motion_blur = r.motion_blur;
        s.film_transparent = r.film_transparent;
    }

    // --- materials -----------------------------------------------------------------------------

    // A built material: the Material (for textured ones, built from every texture's largest
    // value: the scene analysis reads its lobes) and the index of its TexturedMaterial or -1.
    struct BuiltMaterial {
        const Material* material = nullptr;
        std::int32_t textured = -1;
        std::shared_ptr<const Material> shared = {};  // the same material, for combinations
        Opacity opacity = {};                         // the material's "opacity" and "alpha_cutoff"
        std::int32_t interior = -1;                   // its "interior" medium (Scene::media())
    };

    // --- media ---------------------------------------------------------------------------------

    // "unknown medium 'x'" with a did-you-mean among the scene's medium names.
    std::string unknown_medium(const std::string& name) const {
        std::vector<std::string> names;
        for (const auto& [n, _] : m_desc.media) names.push_back(n);
        std::string msg = "unknown medium '" + name + "'";
        const std::string g = closest_name(name, names);
        if (!g.empty()) {
            msg += " (did you mean '" + g + "'?)";
        } else if (names.empty()) {
            msg += " (the scene defines no \"media\")";
        }
        return msg;
    }

    // The named media (their kinds validate them) and the world medium.
    void build_media() {
        for (const auto& [name, m] : m_desc.media) {
            const std::string ptr = "/media/" + escape_pointer_token(name);
            if (m_medium_index.count(name)) fail(ptr, "duplicate medium name '" + name + "'");
            const MediumKindDef* k = find_medium_kind(m.kind);
            if (!k) fail(ptr + "/kind", "unknown medium kind");
            m_medium_index[name] = std::int32_t(m_builder.media().size());
            m_builder.media().push_back(k->build(m, ptr, MediumContext(*this)));
        }
        if (!m_desc.world_medium.empty()) {
            const auto it = m_medium_index.find(m_desc.world_medium);
            if (it == m_medium_index.end())
                fail("/world_medium", unknown_medium(m_desc.world_medium));
            m_builder.world_medium() = it->second;
            // An escaping ray crosses the world medium over an infinite length: its emission
            // would be infinite where nothing attenuates it.
            const Medium& w = m_builder.media()[std::size_t(it->second)];
            for (int c = 0; c < 3; ++c)
                if (w.emission()[c] > 0.f && !(w.sigma_t()[c] > 0.f))
                    fail("/world_medium",
                         "the world medium '" + m_desc.world_medium +
                             "' emits where it neither absorbs nor scatters: rays that escape "
                             "would gather infinite emission");
        }
    }

    // The key "interior" of a material (scenes/FORMAT.md, "Media"): the name of the medium its
    // shapes bound, taken out of `m` (it belongs to no reflection model).
    std::int32_t take_interior(MaterialDesc& m, const std::string& ptr) {
        const auto it = m.params.values().find("interior");
        if (it == m.params.values().end()) return -1;
        const std::string p = ptr + "/interior";
        const std::string* name = std::get_if<std::string>(&it->second);
        if (!name) fail(p, "expected the name of a medium of \"media\"");
        const auto found = m_medium_index.find(*name);
        if (found == m_medium_index.end()) fail(p, unknown_medium(*name));
        ParamSet rest;
        for (const auto& [key, v] : m.params.values())
            if (key != "interior") rest.set(key, v);
        m.params = std::move(rest);
        return found->second;
    }

    // The keys "opacity" (a number or a texture) and "alpha_cutoff" of a material, which belong
    // to no reflection model (scenes/FORMAT.md, "Opacity"): validated, and taken out of `m`.
    Opacity build_opacity(MaterialDesc& m, const std::string& ptr) {
        Opacity o;
        auto number = [&](const char* key, double lo, const char* range) -> std::optional<double> {
            const auto it = m.params.values().find(key);
            if (it == m.params.values().end()) return std::nullopt;
            const std::string p = ptr + "/" + key;
            const double* d = std::get_if<double>(&it->second);
            if (!d) fail(p, std::string("expected a number ") + range);
            return check_range(*d, p, lo, 1.0, range);
        };
        const std::optional<double> value = number("opacity", 0.0, "in [0, 1]");
        const std::optional<double> cutoff = number("alpha_cutoff", 1e-30, "in (0, 1]");
        if (value) o.value = float(*value);
        if (auto it = m.textures.find("opacity"); it != m.textures.end()) {
            const std::string op = ptr + "/opacity";
            const TextureDesc& td = it->second;
            if (td.kind == "vertex_color" || td.times_vertex_color)
                fail(op,
                     "a vertex colour cannot be an opacity (cut-outs are decided during "
                     "traversal, before the hit's colour is known)");
            TexelImageOptions linear;
            linear.color_space = ColorSpace::Linear;
            if (td.kind == "image" && td.channel == "a" && !td.file.empty() &&
                (m_limits.allow_files || td.bytes || td.image) &&
                load_image(td, linear, op)->alpha_channel < 0) {
                // The alpha of an image without one is 1 (opaque), as glTF and Blender read it:
                // the opacity is the texture's scale alone.
                o.value = float(check_range(td.scale * double(td.color_scale.r), op + "/scale", 0.0,
                                            1.0, "in [0, 1]"));
                m.textures.erase(it);
            } else {
                o.texture = build_texture(td, op, false, false);
                if (o.texture->uses_position() || o.texture->uses_view())
                    fail(op,
                         "an opacity reads UVs only (cut-outs are decided during traversal): "
                         "give the procedural texture \"coordinates\": \"uv\"");
                if (!(o.texture->min_value().r >= 0.f) || !(o.texture->max_value().r <= 1.f))
                    fail(op, "the texture's values must lie in [0, 1]");
                m.textures.erase(it);
            }
        }
        if (cutoff) {
            o.cutoff = float(*cutoff);
            if (!o.texture) o.value = o.value >= o.cutoff ? 1.f : 0.f;
        }
        if (value || cutoff) {
            ParamSet rest;
            for (const auto& [key, v] : m.params.values())
                if (key != "opacity" && key != "alpha_cutoff") rest.set(key, v);
            m.params = std::move(rest);
        }
        return o;
    }

    // The image of texture `d` (a file, or encoded bytes in memory), through the scene's cache.
    std::shared_ptr<const TexelImage> load_image(const TextureDesc& d, const TexelImageOptions& opt,
                                                 const std::string& ptr) {
        try {
            if (d.image) {
                // In memory (numpy): decoded when it was made; counted against the bound, and
                // checked here for what a file is checked on load.
                auto img = m_images.adopt(d.image, ptr + "/texture");
                for (std::size_t i = 0; opt.reject_negative && i < img->texels.size(); ++i)
                    if (img->texels[i] < 0.f &&
                        int(i % std::size_t(img->channels)) != img->alpha_channel)
                        fail(ptr + "/texture", d.file + ": texel " +
                                                   std::to_string(i / std::size_t(img->channels)) +
                                                   " is negative (an emitted radiance)");
                return img;
            }
            return d.bytes ? m_images.get_memory(d.file, *d.bytes, opt, ptr + "/texture")
                           : m_images.get(resolve_scene_path(d.file, m_desc.base_dir), opt,
                                          ptr + "/texture");
        } catch (const TexelImageError& e) {
            throw SceneError(m_name + ": " + e.what());
        }
    }

    // "unknown material 'x'" with a did-you-mean among the scene's material names.
    std::string unknown_material(const std::string& name) const {
        std::vector<std::string> names;
        for (const auto& [n, _] : m_desc.materials) names.push_back(n);
        std::string msg = "unknown material '" + name + "'";
        std::string g = closest_name(name, names);
        if (!g.empty()) {
            msg += " (did you mean '" + g + "'?)";
        } else if (names.empty()) {
            msg += " (the scene defines no \"materials\")";
        }
        return msg;
    }

    // The named material `name`, built on first use (a combination may name a material that
    // the file lists after it); `ref_ptr` is the pointer of the reference, for errors. A chain
    // of references that comes back to a material being built is a cycle: an error.
    BuiltMaterial named_material(const std::string& name, const std::string& ref_ptr) {
        if (auto it = m_named.find(name); it != m_named.end()) return it->second;
        const auto d = m_named_desc.find(name);
        if (d == m_named_desc.end()) fail(ref_ptr, unknown_material(name));
        if (std::find(m_building.begin(), m_building.end(), name) != m_building.end()) {
            std::string chain;
            for (auto it = std::find(m_building.begin(), m_building.end(), name);
                 it != m_building.end(); ++it)
                chain += "'" + *it + "' -> ";
            fail(ref_ptr, "material '" + name + "' refers to itself (" + chain + "'" + name + "')");
        }
        m_building.push_back(name);
        const BuiltMaterial bm =
            build_material(*d->second, "/materials/" + escape_pointer_token(name));
        m_building.pop_back();
        m_named[name] = bm;
        return bm;
    }

    // The children of a combination (ModelInfo::children of them, under ptr/materials).
    std::vector<BuiltMaterial> build_children(const MaterialDesc& m, const ModelInfo& info,
                                              const std::string& ptr) {
        if (int(m.materials.size()) != info.children) {
            fail(ptr + "/materials",
                 info.children == 0
                     ? "model '" + m.model + "' takes no sub-materials"
                     : "model '" + m.model + "' needs exactly " + std::to_string(info.children) +
                           " materials [a, b] (got " + std::to_string(m.materials.size()) + ")");
        }
        std::vector<BuiltMaterial> children;
        for (std::size_t k = 0; k < m.materials.size(); ++k) {
            const MaterialDesc& c = m.materials[k];
            const std::string cp = ptr + "/materials/" + std::to_string(k);
            if (!c.ref.empty()) {
                if (!c.model.empty() || !c.params.values().empty() || !c.materials.empty())
                    fail(cp, "give either a material name or an inline material, not both");
                children.push_back(named_material(c.ref, cp));
            } else {
                children.push_back(build_material(c, cp));
            }
        }
        return children;
    }

    // Warns when an `add` reflects more than it receives (allowed, as in Cycles): its
    // directional albedo at a few angles (Gauss-Legendre order 16, reflection only).
    void check_energy_gain(const MaterialDesc& m, const Material& mat, const std::string& ptr) {
        if (m.model != "add") return;
        float worst = 0.f, worst_mu = 1.f;
        for (float mu : {1.f, 0.7f, 0.4f, 0.1f}) {
            const Vec3 w(std::sqrt(1.f - mu * mu), 0.f, mu);
            const DVec3 r = hemispherical_directional(mat, w, 16).value;
            const float rmax = float(std::max({r.x, r.y, r.z}));
            if (rmax > worst) worst = rmax, worst_mu = mu;
        }
        if (worst > 1.001f) {
            m_builder.warnings().push_back(
                m_name + ": " + ptr + ": add reflects " + fmt_number(worst) +
                " of the light at cos theta = " + fmt_number(worst_mu) +
                " (> 1: an energy gain, allowed as in Cycles' Add Shader)");
        }
    }
    // Warns for each child of a combination that has a subsurface walk: the walk runs only for
    // a material a shape uses directly; inside mix or add the child is its diffuse fallback
    // (docs/subsurface.md).
    void check_nested_subsurface(const MaterialDesc& m, const std::vector<BuiltMaterial>& children,
                                 const std::string& ptr) {
        for (std::size_t k = 0; k < children.size(); ++k) {
            const Material* c = children[k].material;
            if (c == nullptr || c->subsurface() == nullptr) continue;
            m_builder.warnings().push_back(
                m_name + ": " + ptr + "/materials/" + std::to_string(k) +
                ": a subsurface material inside '" + m.model +
                "' renders its diffuse fallback (the random walk runs only for a material a "
                "shape uses directly)");
        }
    }
    static std::string fmt_number(double v) {
        std::ostringstream s;
        s.precision(3);
        s << v;
        return s.str();
    }

    // A texture parameter value (texture.h), validated with JSON pointers under `ptr`. `color`:
    // the parameter is a colour (sRGB decoding by default for integer images) or a number
    // (linear by default, one channel). `radiance`: negative texels are errors.
    const Texture* build_texture(const TextureDesc& d, const std::string& ptr, bool color,
                                 bool radiance) {
        check_finite(d.scale, ptr + "/scale");
        check_finite(double(d.uv_rotation), ptr + "/uv_rotation");
        for (int i = 0; i < 2; ++i) {
            check_finite(double(d.uv_scale[i]), ptr + "/uv_scale/" + std::to_string(i));
            check_finite(double(d.uv_offset[i]), ptr + "/uv_offset/" + std::to_string(i));
        }
        if (d.scale < 0.0) fail(ptr + "/scale", "must be >= 0");
        check_color(d.color_scale, ptr + "/scale", "a colour multiplier");
        if (!color && (d.color_scale.r != d.color_scale.g || d.color_scale.r != d.color_scale.b))
            fail(ptr + "/scale", "a number parameter needs a number (or grey) scale");
        const TextureKindDef* kind = find_texture_kind(d.kind);
        if (!kind) {
            std::string msg = "unknown texture kind '" + d.kind + "'";
            const std::string g = closest_name(d.kind, texture_kind_names());
            if (!g.empty()) msg += " (did you mean '" + g + "'?)";
            fail(ptr, msg);
        }
        if (!kind->procedural &&
            (!d.params.values().empty() || !d.coordinates.empty() || d.mapping != glm::dmat4(1.0) ||
             !d.inputs.empty() || !d.stops.empty()))
            fail(ptr,
                 "a " + d.kind + " texture has no procedural parameters, coordinates or mapping");
        TextureContext ctx(*this, d, ptr, color, radiance);
        m_builder.textures().push_back(std::make_unique<Texture>(kind->build(ctx)));
        return m_builder.textures().back().get();
    }

    // What a texture kind's builder gets (textures/texture_build.h).
    class TextureContext final : public TextureBuild {
      public:
        TextureContext(Builder& b, const TextureDesc& d, const std::string& p, bool c, bool r)
            : TextureBuild(d, p, c, r), m_b(b) {}
        [[noreturn]] void fail(const std::string& p, const std::string& m) const override {
            m_b.fail(p, m);
        }
        bool files_allowed() const override { return m_b.m_limits.allow_files; }
        std::shared_ptr<const TexelImage> load_image(const TexelImageOptions& opt) override {
            return m_b.load_image(desc, opt, ptr);
        }
        std::shared_ptr<const std::vector<TexelImage>> mip_levels(
            const std::shared_ptr<const TexelImage>& img) override {
            try {
                return m_b.m_images.mip_levels(img, ptr + "/texture");
            } catch (const TexelImageError& e) {
                throw SceneError(m_b.m_name + ": " + e.what());
            }
        }
        Texture build_input(const TextureDesc& d, const std::string& p, bool c) override {
            return *m_b.build_texture(d, p, c, false);
        }

      private:
        Builder& m_b;
    };

    // Builds a material; parameter errors from the registry name the parameter, which becomes
    // part of the pointer. A material with textured parameters also gets its TexturedMaterial:
    // the registry validates it with every texture at its smallest and at its largest value
    // (a value between them, as bilinear filtering gives, is then valid too).
    BuiltMaterial build_material(const MaterialDesc& desc, const std::string& ptr,
                                 const MaterialConversion* conversion = nullptr) {
        MaterialDesc m = desc;
        const Opacity opacity = build_opacity(m, ptr);
        const std::int32_t interior = take_interior(m, ptr);
        BuiltMaterial built = build_model(m, ptr, conversion);
        built.opacity = opacity;
        built.interior = interior;
        // A medium's boundary must let rays in: a transmissive model, or `null`.
        const ModelInfo* info = find_model(m.model);
        const bool pass_through = info && info->pass_through;
        if (interior >= 0 && !pass_through && !built.material->transmissive())
            fail(ptr + "/interior",
                 "model '" + m.model +
                     "' cannot bound a medium: rays never cross it (use a transmissive model "
                     "such as dielectric, or \"null\" for an invisible boundary)");
        if (interior >= 0 && opacity.active())
            fail(ptr + "/interior",
                 "a medium's boundary cannot be a cut-out (opacity < 1): rays passing through "
                 "the holes would not know they entered");
        if (interior >= 0 || pass_through)
            m_builder.interfaces().push_back({built.material, interior, pass_through});
        return built;
    }

    // The reflection model of a material (build_material without its opacity).
    // With a conversion, the parameters and textures are its sources (kind_build.h).
    BuiltMaterial build_model(const MaterialDesc& m, const std::string& ptr,
                              const MaterialConversion* conversion) {
        auto to_model = [&](const ParamSet& ps) {
            return conversion ? conversion->convert(ps) : ps;
        };
        if (!find_model(m.model)) {
            std::vector<std::string> names;
            for (const auto& mi : model_table()) names.push_back(mi.name);
            std::string msg = "unknown model '" + m.model + "'";
            std::string g = closest_name(m.model, names);
            if (!g.empty()) {
                msg += " (did you mean '" + g + "'?)";
            } else {
                msg += " (expected one of:";
                for (const auto& n : names) msg += " " + n;
                msg += ")";
            }
            fail(ptr + "/model", msg);
        }
        for (const auto& [key, v] : m.params.values()) {
            const std::string p = ptr + "/" + escape_pointer_token(key);
            if (const double* d = std::get_if<double>(&v)) check_finite(*d, p);
            if (const Rgb* c = std::get_if<Rgb>(&v)) check_finite(*c, p);
        }
        // A normal map of strength 0 is no map (exactly: the material stays constant).
        const bool normal_map = m.normal_map && m.normal_map->strength != 0.0;
        if (m.normal_map) {
            check_range(m.normal_map->strength, ptr + "/normal_map/strength", 0.0, 1e6,
                        "in [0, 1e6] (Blender's Normal Map strength; 0 = no map)");
            check_range(m.normal_map->xy_scale, ptr + "/normal_map/xy_scale", -1e6, 1e6,
                        "a finite number (glTF's normalTexture.scale)");
            if (m.normal_map->texture.scale != 1.0)
                fail(ptr + "/normal_map/scale",
                     "a normal map's texels are not scaled: use \"strength\" (Blender) or "
                     "\"xy_scale\" (glTF)");
        }
        if (m.bump) {
            check_range(m.bump->distance, ptr + "/bump/distance", -1e30, 1e30,
                        "a finite number (scene units per unit of height)");
            check_range(m.bump->strength, ptr + "/bump/strength", 0.0, 1e6,
                        "in [0, 1e6] (Blender's Bump strength; 0 = no bump)");
        }
        // A bump of distance 0 or strength 0 is no bump (the material stays constant).
        const bool bump = m.bump && m.bump->distance != 0.0 && m.bump->strength != 0.0;
        const ModelInfo& info = *find_model(m.model);
        const std::vector<BuiltMaterial> children = build_children(m, info, ptr);
        check_nested_subsurface(m, children, ptr);
        std::vector<std::shared_ptr<const Material>> kids;
        bool textured_child = false;
        for (const BuiltMaterial& c : children) {
            kids.push_back(c.shared);
            textured_child = textured_child || c.textured >= 0;
        }
        if (m.textures.empty() && !normal_map && !bump && !textured_child) {
            try {
                m_builder.materials().push_back(
                    std::make_shared<Material>(make_material(m.model, to_model(m.params), kids)));
            } catch (const ParamError& e) {
                fail(e.param().empty() ? ptr + "/model"
                                       : ptr + "/" + escape_pointer_token(e.param()),
                     e.what());
            }
            check_energy_gain(m, *m_builder.materials().back(), ptr);
            return {m_builder.materials().back().get(), -1, m_builder.materials().back()};
        }
        const std::vector<ParamInfo>& table =
            conversion ? conversion->sources : find_model(m.model)->params;
        TexturedMaterial tm;
        tm.model = m.model;
        tm.params = m.params;
        if (conversion) tm.convert = conversion->convert;
        for (const BuiltMaterial& c : children)
            tm.children.push_back({c.textured >= 0 ? nullptr : c.shared, c.textured});
        for (const auto& [name, td] : m.textures) {
            const std::string& key = name;  // (clang 14 cannot capture a structured binding)
            const std::string p = ptr + "/" + escape_pointer_token(key);
            if (m.params.has(key)) fail(p, "given both as a constant and as a texture");
            const auto pi = std::find_if(table.begin(), table.end(),
                                         [&](const ParamInfo& x) { return x.name == key; });
            if (pi == table.end()) {
                std::vector<std::string> names;
                for (const auto& x : table) names.push_back(x.name);
                std::string msg = "unknown parameter '" + key + "' for model '" + m.model + "'";
                const std::string g = closest_name(key, names);
                if (!g.empty()) msg += " (did you mean '" + g + "'?)";
                fail(p, msg);
            }
            if (pi->type != ParamType::Color && pi->type != ParamType::Number)
                fail(p, "only colour and number parameters can be textures");
            const bool color = pi->type == ParamType::Color;
            tm.slots.push_back({key, build_texture(td, p, color, false), color});
            tm.uses_uv = tm.uses_uv || tm.slots.back().texture->uses_uv();
            tm.uses_color = tm.uses_color || tm.slots.back().texture->uses_vertex_color();
            tm.uses_position = tm.uses_position || tm.slots.back().texture->uses_position();
            tm.uses_view = tm.uses_view || tm.slots.back().texture->uses_view();
        }
        for (const BuiltMaterial& c : children) {
            if (c.textured < 0) continue;
            const TexturedMaterial& ct = m_builder.textured()[std::size_t(c.textured)];
            tm.uses_uv = tm.uses_uv || ct.uses_uv;
            tm.uses_color = tm.uses_color || ct.uses_color;
            tm.uses_position = tm.uses_position || ct.uses_position;
            tm.uses_view = tm.uses_view || ct.uses_view;
        }
        // Validate at the extremes: slot i at its largest value when bit i of `corner` is set.
        // The model's own parameters are checked per value (both ends); a conversion mixes its
        // sources, monotonically in each (glTF: b (1 - m), r^2, ...), so every corner of the
        // box. Keep the material of the largest values for the analysis, and every corner's
        // lobes (TexturedMaterial::flags).
        auto with = [&](std::uint32_t corner) {
            ParamSet ps = tm.params;
            for (std::size_t i = 0; i < tm.slots.size(); ++i) {
                const auto& s = tm.slots[i];
                const Rgb v = (corner >> i) & 1u ? s.texture->max_value() : s.texture->min_value();
                ps.set(s.name, s.color ? ParamValue(v) : ParamValue(double(v.r)));
            }
            return ps;
        };
        const std::uint32_t all = (1u << std::min<std::size_t>(tm.slots.size(), 8)) - 1u;
        std::vector<std::uint32_t> corners{0u, all};
        if (conversion) {
            if (tm.slots.size() > 8) fail(ptr, "more than 8 textured sources");
            corners.clear();
            for (std::uint32_t c = 0; c <= all; ++c) corners.push_back(c);
        }
        for (std::uint32_t corner : corners) {
            const bool largest = corner == all;
            try {
                // Children: their largest-value materials (the analysis' view of them).
                Material mat = make_material(m.model, to_model(with(corner)), kids);
                tm.flags = tm.flags | mat.flags();
                if (largest) m_builder.materials().push_back(std::make_shared<Material>(mat));
            } catch (const ParamError& e) {
                fail(e.param().empty() ? ptr + "/model"
                                       : ptr + "/" + escape_pointer_token(e.param()),
                     std::string(e.what()) + " (a texture's " +
                         (largest       ? "largest"
                          : corner == 0 ? "smallest"
                                        : "extreme") +
                         " value)");
            }
        }
        stage(tm, *m_builder.materials().back(), conversion);
        for (const auto& s : tm.slots)
            tm.params.set(s.name, s.color ? ParamValue(Rgb(0.f)) : ParamValue(0.0));
        for (const auto* map : {m.normal_map ? &m.normal_map->texture : nullptr,
                                m.bump ? &m.bump->texture : nullptr}) {
            if (map && (map->kind == "vertex_color" || map->times_vertex_color))
                fail(ptr + (map == &m.bump->texture ? "/bump" : "/normal_map"),
                     "a vertex colour cannot be a normal or bump map (they need texture "
                     "coordinates)");
        }
        tm.uses_uv = tm.uses_uv || normal_map || bump;
        if (normal_map) {
            // Read linearly unless the scene says otherwise (the texture's colour space key).
            TextureDesc td = m.normal_map->texture;
            if (td.colorspace.empty()) td.colorspace = "linear";
            tm.normal_map = build_texture(td, ptr + "/normal_map", true, false);
            if (tm.normal_map->uses_position() || tm.normal_map->uses_view())
                fail(ptr + "/normal_map",
                     "a normal map reads UVs only: give the procedural texture "
                     "\"coordinates\": \"uv\"");
            tm.normal_strength = float(m.normal_map->strength);
            tm.normal_xy_scale = float(m.normal_map->xy_scale);
        }
        if (bump) {
            tm.bump = build_texture(m.bump->texture, ptr + "/bump", false, false);
            if (tm.bump->uses_position() || tm.bump->uses_view())
                fail(ptr + "/bump",
                     "a bump map reads UVs only: give the procedural texture \"coordinates\": "
                     "\"uv\"");
            tm.bump_distance = float(m.bump->distance);
            tm.bump_strength = float(m.bump->strength);
            // Forward-difference step in uv: half a texel of the image (or a thousandth of a
            // checker cell), through the texture's UV scale.
            const TextureDesc& td = m.bump->texture;
            const double per_uv = std::max(
                {std::fabs(double(td.uv_scale.x)), std::fabs(double(td.uv_scale.y)), 1e-12});
            const TexelImage* im = tm.bump->texel_image();
            const double cells =
                im ? double(std::max(im->width, im->height)) : 1000.0 * td.checker_scale;
            tm.bump_step = float(0.5 / (cells * per_uv));
        }
        // A texture on the diffuse reflectance alone of a model with that Lambert lobe
        // (ModelInfo::diffuse_lobe): only the lobe's rho changes per hit.
        if (!tm.convert && tm.slots.size() == 1 && info.diffuse_lobe &&
            tm.slots[0].name == info.diffuse_param && m_builder.materials().back()->diffuse()) {
            tm.diffuse_base = m_builder.materials().back().get();
            tm.diffuse_black_ok = info.diffuse_black_ok;
        }
        m_builder.textured().push_back(std::move(tm));
        return {m_builder.materials().back().get(), std::int32_t(m_builder.textured().size() - 1),
                m_builder.materials().back()};
    }

    // The staged per-hit build of a textured material (facet/staged_material.h), where the model
    // and its textured parameters allow it. `base` is the material at the textures' largest
    // values (with a conversion: its sources' largest), validated by build_model.
    static void stage(TexturedMaterial& tm, const Material& base,
                      const MaterialConversion* conversion) {
        // A subsurface walk is built by the model itself (the staged lobes have none).
        if (base.subsurface()) return;
        using Range = StagedMaterial::Range;
        constexpr std::size_t kMax = TexturedMaterial::kMaxStaged;
        auto value = [](const TexturedMaterial::Slot& s, const Rgb& v) {
            return s.color ? DVec3(v) : DVec3(double(v.r));
        };
        std::vector<std::string> names;
        std::vector<Range> ranges;
        if (tm.slots.size() > kMax) return;
        if (!conversion) {
            for (const TexturedMaterial::Slot& s : tm.slots) {
                names.push_back(s.name);
                ranges.push_back(
                    {value(s, s.texture->min_value()), value(s, s.texture->max_value())});
            }
        } else {
            if (!conversion->convert_values || conversion->sources.size() > kMax ||
                conversion->outputs.size() > kMax)
                return;
            // The sources' constants, and the source of each slot.
            tm.sources.assign(conversion->sources.size(), DVec3(0.0));
            tm.slot_source.assign(tm.slots.size(), 0);
            for (std::size_t i = 0; i < conversion->sources.size(); ++i) {
                const std::string& name = conversion->sources[i].name;
                const auto slot = std::find_if(tm.slots.begin(), tm.slots.end(),
                                               [&](const auto& s) { return s.name == name; });
                if (slot != tm.slots.end()) {
                    tm.slot_source[std::size_t(slot - tm.slots.begin())] = std::uint8_t(i);
                    continue;
                }
                if (!tm.params.has(name)) return;  // a default: not staged
                const ParamValue& v = tm.params.values().at(name);
                if (const double* d = std::get_if<double>(&v))
                    tm.sources[i] = DVec3(*d);
                else if (const Rgb* c = std::get_if<Rgb>(&v))
                    tm.sources[i] = DVec3(*c);
                else
                    return;
            }
            // The outputs' ranges: over every corner of the sources' box (the conversion is
            // monotonic in each source, as build_model's validation assumes).
            names = conversion->outputs;
            ranges.assign(names.size(), {DVec3(INFINITY), DVec3(-INFINITY)});
            std::vector<DVec3> src(tm.sources), out(names.size());
            for (std::uint32_t c = 0; c < (1u << tm.slots.size()); ++c) {
                for (std::size_t i = 0; i < tm.slots.size(); ++i) {
                    const auto& s = tm.slots[i];
                    src[tm.slot_source[i]] =
                        value(s, (c >> i) & 1u ? s.texture->max_value() : s.texture->min_value());
                }
                conversion->convert_values(src.data(), out.data());
                for (std::size_t k = 0; k < out.size(); ++k) {
                    ranges[k].lo = glm::min(ranges[k].lo, out[k]);
                    ranges[k].hi = glm::max(ranges[k].hi, out[k]);
                }
            }
            tm.convert_values = conversion->convert_values;
        }
        std::optional<StagedMaterial> st = StagedMaterial::make(tm.model, base, names, ranges);
        if (!st) {
            tm.sources.clear(), tm.slot_source.clear(), tm.convert_values = nullptr;
            return;
        }
        tm.staged = std::make_shared<const StagedMaterial>(std::move(*st));
        tm.num_staged = names.size();
    }

    void build_materials() {
        for (const auto& [name, m] : m_desc.materials) {
            const std::string ptr = "/materials/" + escape_pointer_token(name);
            if (m_named_desc.count(name)) fail(ptr, "duplicate material name '" + name + "'");
            m_named_desc[name] = &m;
        }
        for (const auto& [name, m] : m_desc.materials)
            named_material(name, "/materials/" + escape_pointer_token(name));
    }

    // Whether hits on a surface compute uv: its material, emission or opacity reads a texture
    // over UVs (an image or checker; not a vertex colour alone).
    bool needs_uv(const ShapeSurface& s) {
        return (s.textured >= 0 && m_builder.textured()[std::size_t(s.textured)].uses_uv) ||
               (s.emission_texture && s.emission_texture->uses_uv()) ||
               s.opacity.texture != nullptr;
    }
    // The texture space of shape `s` (ShapeDesc::texture_space; default its object-space box
    // `bounds`, as Blender's automatic texture space: centre and half size, a zero half size
    // counting as 1 and one below 1e-5 as 1e-5): generated = (po - (centre - half)) / (2 half).
    void set_texture_space(ShapeInfo& info, const ShapeDesc& s, const Bounds3& bounds,
                           const std::string& ptr) {
        Vec3 loc(0.f), size(1.f);
        if (s.texture_space) {
            const std::string tp = ptr + "/texture_space";
            check_finite(s.texture_space->location, tp + "/location");
            check_finite(s.texture_space->size, tp + "/size");
            loc = s.texture_space->location;
            size = s.texture_space->size;
            for (int i = 0; i < 3; ++i)
                if (size[i] == 0.f) fail(tp + "/size/" + std::to_string(i), "must be non-zero");
        } else if (!bounds.empty()) {
            loc = 0.5f * (bounds.lo + bounds.hi);
            size = 0.5f * (bounds.hi - bounds.lo);
            for (int i = 0; i < 3; ++i) {
                if (size[i] == 0.f)
                    size[i] = 1.f;
                else if (size[i] > 0.f && size[i] < 1e-5f)
                    size[i] = 1e-5f;
            }
        }
        info.texture_lo = loc - size;
        info.texture_inv = 0.5f / size;
    }

    // Whether hits on a surface compute the object-space point: a procedural texture of its
    // material or emission reads object or generated coordinates.
    bool needs_position(const ShapeSurface& s) {
        return (s.textured >= 0 && m_builder.textured()[std::size_t(s.textured)].uses_position) ||
               (s.emission_texture && s.emission_texture->uses_position());
    }
    // Whether hits on a surface compute the view-dependent coordinates: a procedural texture of
    // its material or emission reads normal, reflection, camera or window coordinates.
    bool needs_view(const ShapeSurface& s) {
        return (s.textured >= 0 && m_builder.textured()[std::size_t(s.textured)].uses_view) ||
               (s.emission_texture && s.emission_texture->uses_view());
    }
    // Whether hits on a surface interpolate vertex colours: its material or emission reads them.
    bool needs_color(const ShapeSurface& s) {
        return (s.textured >= 0 && m_builder.textured()[std::size_t(s.textured)].uses_color) ||
               (s.emission_texture && s.emission_texture->uses_vertex_color());
    }

    const Material* black_material() {
        if (!m_black) {
            m_builder.materials().push_back(
                std::make_unique<Material>(std::nullopt, std::nullopt, std::nullopt));
            m_black = m_builder.materials().back().get();
        }
        return m_black;
    }

    // --- shapes --------------------------------------------------------------------------------

    // Shape `s` as Scene::shapes()[index], at JSON pointer `ptr`: a description shape
    // (proto -1) or a shape of prototype `proto` (its geometry then goes to the prototype).
    void build_shape(const ShapeDesc& s, std::uint32_t index, const std::string& ptr,
                     std::int32_t proto) {
        m_places.push_back(ptr + (s.name.empty() ? "" : " ('" + s.name + "')"));
        if (!find_shape_kind(s.kind)) fail(ptr + "/type", "unknown shape type");
        if (proto >= 0 && (s.emission != Rgb(0.f) || s.emission_texture))
            fail(ptr + "/emission",
                 "a prototype's shapes cannot emit (light sampling would need each instance as "
                 "a light of its own; place an emitter as a shape instead)");
        if (shape_kind(s.kind).places_prototype) {
            // No surface of its own: hits report the prototype's shapes.
            if (s.material || !s.material_ref.empty())
                fail(ptr + "/material",
                     "an instance takes its prototype's materials (give them in the prototype)");
            if (s.emission != Rgb(0.f) || s.emission_texture)
                fail(ptr + "/emission", "an instance cannot emit (its prototype's shapes do not)");
            if (!s.two_sided) fail(ptr + "/two_sided", "give it on the prototype's shapes");
            if (s.flip_normals) fail(ptr + "/flip_normals", "give it on the prototype's shapes");
            if (s.holdout) fail(ptr + "/holdout", "give it on the prototype's shapes");
        }

        ShapeInfo info;
        info.kind = s.kind;
        info.two_sided = s.two_sided;
        info.holdout = s.holdout;
        info.emission = check_color(s.emission, ptr + "/emission", "an emitted radiance");
        if (s.emission_texture) {
            if (info.emission != Rgb(0.f))
                fail(ptr + "/emission", "give either a constant or a texture, not both");
            info.emission_texture =
                build_texture(*s.emission_texture, ptr + "/emission", true, true);
            // The largest value makes the shape an emitter and sets its light's power (light.h).
            info.emission = info.emission_texture->max_value();
        }
        const bool emissive = max_component(info.emission) > 0.f;
        if (s.material) {
            if (!s.material_ref.empty()) {
                fail(ptr + "/material",
                     "give either a material name or an inline material, not both");
            }
            const BuiltMaterial bm = build_material(*s.material, ptr + "/material");
            info.material = bm.material;
            info.textured = bm.textured;
            info.opacity = bm.opacity;
            info.material_name = "<inline>";
        } else if (!s.material_ref.empty()) {
            const std::string& name = s.material_ref;
            auto found = m_named.find(name);
            if (found == m_named.end()) fail(ptr + "/material", unknown_material(name));
            info.material = found->second.material;
            info.textured = found->second.textured;
            info.opacity = found->second.opacity;
            info.material_name = name;
        } else if (emissive || shape_kind(s.kind).own_materials ||
                   shape_kind(s.kind).places_prototype) {
            // Emitters reflect nothing; kinds with their own materials add them as parts.
            info.material = black_material();
            info.material_name = "<black>";
        } else {
            fail(ptr, "missing required key 'material' (only emissive shapes may omit it)");
        }

        info.needs_uv = needs_uv(info);
        info.needs_color = needs_color(info);
        info.needs_position = needs_position(info);
        info.needs_view = needs_view(info);
        // An invisible boundary cannot emit: rays cross it without a vertex.
        if (emissive) {
            if (const MediumInterface* mi = m_builder.scene.medium_interface(info.material);
                mi && mi->pass_through)
                fail(ptr + "/material", "an emitting shape cannot have a null material");
        }
        // Light sampling would count a cut-out emitter's light in full where rays see it with
        // probability alpha: not supported rather than biased.
        if (emissive && info.opacity.active())
            fail(ptr + "/material", "an emitting shape cannot have a material with opacity < 1");
        if (info.textured >= 0) {
            const TexturedMaterial& tm = m_builder.textured()[std::size_t(info.textured)];
            info.needs_tangent = tm.normal_map != nullptr;
        }
        glm::dmat4 xf(1.0);
        if (s.transform) {
            xf = *s.transform;
            const std::string tp = ptr + "/transform";
            for (int c = 0; c < 4; ++c)
                for (int r = 0; r < 4; ++r)
                    if (!std::isfinite(xf[c][r]))
                        fail(tp, "the transform is singular (zero scale?) or not finite");
            if (xf[0][3] != 0.0 || xf[1][3] != 0.0 || xf[2][3] != 0.0 || xf[3][3] != 1.0) {
                fail(tp, "the last row must be [0, 0, 0, 1] (affine transforms only)");
            }
            double det = glm::determinant(glm::dmat3(xf));
            if (!(std::fabs(det) > 1e-300) || !std::isfinite(det)) {
                fail(tp, "the transform is singular (zero scale?) or not finite");
            }
        }
        const std::vector<DecomposedTransform> motion = shape_motion(s, ptr, proto, emissive);
        const bool deforms = shape_deformation(s, ptr, proto, emissive);
        ShapeContext ctx(*this, s, index, ptr, info, proto);
        ctx.emission = info.emission;
        ctx.emissive = emissive;
        ctx.xf = xf;
        ctx.deform_steps = !s.motion_positions.empty();  // checked by add_mesh, on or off
        const bool places = shape_kind(s.kind).places_prototype;
        if (!motion.empty() || deforms) {
            // A moving shape: an instance moves its placement; a triangle shape goes into a
            // prototype of its own (object space), placed by its motion. A deforming mesh
            // likewise (its steps in object space), placed by its motion or its transform.
            ctx.xf = places ? motion[0].matrix() : glm::dmat4(1.0);
            if (!places) ctx.build_into(ctx.add_local_prototype());
            ctx.deform = deforms;
        }
        const std::size_t pending = m_pending.size();
        shape_kind(s.kind).build(ctx);
        if (!motion.empty()) {
            if (places) {
                if (m_pending.size() == pending + 1) m_pending.back().motion = motion;
            } else {
                m_pending.push_back({index, std::uint32_t(ctx.local_prototype()),
                                     motion[0].matrix(), false, motion});
            }
        } else if (deforms) {
            m_pending.push_back({index, std::uint32_t(ctx.local_prototype()), xf, false});
        }
        for (const ShapeSurface& part : info.parts) {
            info.needs_position = info.needs_position || needs_position(part);
            info.needs_view = info.needs_view || needs_view(part);
        }
        if (info.needs_position || info.needs_view) {
            info.to_object = glm::inverse(xf);
            info.normal_to_object = glm::mat3(glm::transpose(glm::dmat3(xf)));
            m_builder.impl().position_extras = true;
        }
        if (info.needs_view && proto >= 0) {
            // Instanced hits keep the object-space normal in SurfaceHit::po (scene.h).
            if (info.needs_position)
                fail(ptr,
                     "a prototype's shape cannot read normal, reflection, camera or window "
                     "coordinates and object or generated coordinates together");
            info.normal_in_po = true;
            auto& flags = m_builder.impl().normal_in_po;
            flags.resize(m_builder.shapes().size() + 1, 0);
            flags.back() = 1;
        }
        set_texture_space(info, s, ctx.object_bounds, ptr);
        if (proto >= 0) {
            // Object-space extent of the prototype; the scene's grows by its instances.
            Bounds3& pb = m_builder.impl().prototypes[std::size_t(proto)].bounds;
            pb.lo = glm::min(pb.lo, ctx.bounds.lo);
            pb.hi = glm::max(pb.hi, ctx.bounds.hi);
        } else if (!ctx.bounds.empty()) {
            check_coordinate_range(std::max(max_abs(ctx.bounds.lo), max_abs(ctx.bounds.hi)), index);
            m_builder.bounds().lo = glm::min(m_builder.bounds().lo, ctx.bounds.lo);
            m_builder.bounds().hi = glm::max(m_builder.bounds().hi, ctx.bounds.hi);
        }
        m_shape_bounds.push_back(ctx.bounds);
        m_builder.shapes().push_back(info);
    }

    // A shape's `motion` (scenes/FORMAT.md, "Motion blur"), checked, decomposed (motion.h);
    // empty when it has none or motion blur is off (the still `transform` then renders).
    std::vector<DecomposedTransform> shape_motion(const ShapeDesc& s, const std::string& ptr,
                                                  std::int32_t proto, bool emissive) {
        if (s.motion.empty()) return {};
        const std::string mp = ptr + "/motion";
        if (proto >= 0) fail(mp, "a prototype's shapes cannot move (give the instance a motion)");
        if (s.motion.size() < 2)
            fail(mp, "needs at least 2 steps (the transforms at shutter open and close), got " +
                         std::to_string(s.motion.size()));
        if (s.motion.size() > kMaxMotionSteps)
            fail(mp, "at most " + std::to_string(kMaxMotionSteps) + " steps");
        switch (s.kind) {
            case ShapeKind::Box:
            case ShapeKind::Quad:
            case ShapeKind::Mesh:
            case ShapeKind::Icosphere:
            case ShapeKind::Grid:
            case ShapeKind::Instance:
                break;
            default:
                fail(mp,
                     "only triangle shapes (box, quad, mesh, icosphere, grid) and instances "
                     "can move, not a '" +
                         std::string(shape_kind(s.kind).name) + "'");
        }
        if (emissive)
            fail(mp, "an emitting shape cannot move (light sampling places emitters at one time)");
        std::vector<DecomposedTransform> out;
        for (std::size_t i = 0; i < s.motion.size(); ++i) {
            const glm::dmat4& m = s.motion[i];
            const std::string tp = mp + "/" + std::to_string(i);
            for (int c = 0; c < 4; ++c)
                for (int r = 0; r < 4; ++r)
                    if (!std::isfinite(m[c][r])) fail(tp, "the transform is not finite");
            if (m[0][3] != 0.0 || m[1][3] != 0.0 || m[2][3] != 0.0 || m[3][3] != 1.0)
                fail(tp, "the last row must be [0, 0, 0, 1] (affine transforms only)");
            const double det = glm::determinant(glm::dmat3(m));
            if (!(std::fabs(det) > 1e-300) || !std::isfinite(det))
                fail(tp, "the transform is singular (zero scale?) or not finite");
            out.push_back(DecomposedTransform::decompose(m));
        }
        if (!m_motion_on) return {};
        m_shapes_move = true;
        return out;
    }

    // A shape's deformation motion (`motion_positions`, `motion_normals`; scenes/FORMAT.md,
    // "Motion blur"): its structure checked here (the kind, the step count), its values by
    // add_mesh against the mesh. True when it renders (motion blur on).
    bool shape_deformation(const ShapeDesc& s, const std::string& ptr, std::int32_t proto,
                           bool emissive) {
        const std::string mp = ptr + "/motion_positions";
        if (s.motion_positions.empty()) {
            if (!s.motion_normals.empty())
                fail(ptr + "/motion_normals", "given without \"motion_positions\"");
            return false;
        }
        if (s.kind != ShapeKind::Mesh)
            fail(mp,
                 "only a 'mesh' can deform, not a '" + std::string(shape_kind(s.kind).name) + "'");
        if (proto >= 0) fail(mp, "a prototype's shapes cannot deform");
        if (s.motion_positions.size() < 2)
            fail(mp, "needs at least 2 steps (the positions at shutter open and close), got " +
                         std::to_string(s.motion_positions.size()));
        if (s.motion_positions.size() > kMaxDeformSteps)
            fail(mp, "at most " + std::to_string(kMaxDeformSteps) + " steps");
        if (!s.motion.empty() && s.motion.size() != s.motion_positions.size())
            fail(mp, "has " + std::to_string(s.motion_positions.size()) +
                         " steps but the shape's \"motion\" has " +
                         std::to_string(s.motion.size()) + " (give both the same steps)");
        if (!s.motion_normals.empty() && s.motion_normals.size() != s.motion_positions.size())
            fail(ptr + "/motion_normals", "has " + std::to_string(s.motion_normals.size()) +
                                              " steps but \"motion_positions\" has " +
                                              std::to_string(s.motion_positions.size()));
        if (emissive)
            fail(mp,
                 "an emitting shape cannot deform (light sampling places emitters at one time)");
        if (!m_motion_on) return false;
        m_shapes_move = true;
        return true;
    }
    // Embree's limit on a geometry's time steps (RTC_MAX_TIME_STEP_COUNT).
    static constexpr std::size_t kMaxDeformSteps = 129;

    // What a shape kind's builder adds to the scene (kind_build.h).
    class ShapeContext final : public ShapeBuild {
      public:
        ShapeContext(Builder& b, const ShapeDesc& s, std::uint32_t i, const std::string& p,
                     ShapeInfo& info, std::int32_t proto)
            : ShapeBuild(s, i, p), m_b(b), m_info(info), m_proto(proto) {}
        Bounds3 bounds;         // world extent of what was added
        Bounds3 object_bounds;  // object-space extent of what was added (meshes, spheres, discs)

        [[noreturn]] void fail(const std::string& p, const std::string& m) const override {
            m_b.fail(p, m);
        }
        std::string place() const override { return m_b.shape_place(index); }
        void reserve_triangles(std::uint64_t n, const std::string& p) override {
            m_b.reserve_triangles(n, p);
        }
        bool files_allowed() const override { return m_b.m_limits.allow_files; }
        const std::string& base_dir() const override { return m_b.m_desc.base_dir; }

        const AnalyticPrim& add_prim(AnalyticPrim::Kind k, const glm::dmat4& local) override {
            analytic_in_prototype();
            if (m_info.needs_color) fail_no_colors(m_info.material_name, false);
            AnalyticPrim prim;
            prim.kind = k;
            prim.shape = index;
            prim.flip = shape.flip_normals;
            prim.to_world = xf * local;
            prim.to_object = glm::inverse(prim.to_world);
            prim.normal_to_world = glm::transpose(glm::inverse(glm::dmat3(prim.to_world)));
            prim.uv = m_info.needs_uv;
            prim.opacity = m_info.opacity;
            if (m_info.needs_tangent) prim.tangent_sign = handedness(prim.to_world);
            const double zr = analytic::half_depth(k);
            for (int i = 0; i < 8; ++i) {
                glm::dvec3 c(i & 1 ? 1.0 : -1.0, i & 2 ? 1.0 : -1.0, i & 4 ? zr : -zr);
                grow(glm::dvec3(prim.to_world * glm::dvec4(c, 1.0)));
                const Vec3 o(glm::dvec3(local * glm::dvec4(c, 1.0)));
                object_bounds.lo = glm::min(object_bounds.lo, o);
                object_bounds.hi = glm::max(object_bounds.hi, o);
            }
            std::vector<AnalyticPrim>& prims = m_b.m_builder.impl().prims;
            prims.push_back(prim);
            return prims.back();
        }

        void add_plane(const glm::dvec3& point, const Vec3& n) override {
            analytic_in_prototype();
            if (m_info.needs_color) fail_no_colors(m_info.material_name, false);
            const glm::dmat3 lin(xf);
            PlaneGeom pl;
            pl.shape = index;
            pl.point = glm::dvec3(xf * glm::dvec4(point, 1.0));
            pl.normal = glm::normalize(glm::transpose(glm::inverse(lin)) * glm::dvec3(n));
            if (shape.flip_normals) pl.normal = -pl.normal;
            const Frame local = Frame::from_z(n);
            pl.tangent = Vec3(glm::normalize(lin * glm::dvec3(local.x)));
            // UV axes: the local frame's x and y through the transform, in world units; y is
            // made orthogonal to x in the plane (the unflipped normal, so flip_normals does not
            // mirror the texture).
            pl.uv = m_info.needs_uv;
            pl.opacity = m_info.opacity;
            pl.tangent_sign = shape.flip_normals ? -1.f : 1.f;
            pl.ex = glm::normalize(lin * glm::dvec3(local.x));
            pl.ey = glm::cross(glm::normalize(glm::transpose(glm::inverse(lin)) * glm::dvec3(n)),
                               pl.ex);
            if (!is_finite(Vec3(pl.point)) || !is_finite(Vec3(pl.normal))) {
                fail(ptr, "the transformed plane is not finite");
            }
            m_b.check_coordinate_range(max_abs(pl.point), index);
            m_b.m_builder.impl().planes.push_back(pl);
        }

        void add_triangles(TriangleMesh mesh, const Vec3& tangent,
                           const glm::dmat4* sphere) override {
            add_mesh(std::move(mesh), tangent, -1, emissive, emission, sphere);
        }

        ShapeSurface add_material(const MaterialDesc& m, const std::string& p,
                                  const MaterialConversion* conversion) override {
            const BuiltMaterial bm = m_b.build_material(m, p, conversion);
            ShapeSurface surface;
            surface.material = bm.material;
            surface.textured = bm.textured;
            surface.opacity = bm.opacity;
            return surface;
        }

        const Texture* add_texture(const TextureDesc& t, const std::string& p, bool color,
                                   bool radiance) override {
            return m_b.build_texture(t, p, color, radiance);
        }

        bool textured_uses_uv(std::int32_t textured) const override {
            return m_b.m_builder.textured()[std::size_t(textured)].uses_uv;
        }

        void add_part(TriangleMesh mesh, ShapeSurface surface) override {
            if (surface.emission_texture) surface.emission = surface.emission_texture->max_value();
            const bool emits = max_component(surface.emission) > 0.f;
            if (emits && m_proto >= 0)
                fail(ptr, "a prototype's shapes cannot emit (" + surface.material_name +
                              " emits; place the emitter as a shape instead)");
            if (emits && surface.opacity.active())
                fail(ptr,
                     "an emitting part cannot have opacity < 1 (" + surface.material_name + ")");
            const Rgb radiance = surface.emission;
            m_info.parts.push_back(std::move(surface));
            add_mesh(std::move(mesh), Vec3(0.f), std::int32_t(m_info.parts.size() - 1), emits,
                     radiance, nullptr);
        }

        void warn(std::string message) override {
            m_b.m_builder.warnings().push_back(std::move(message));
        }

        void add_curves(CurveGeom g, const Bounds3& extent, const Bounds3& object_extent) override {
            if (m_info.needs_color) fail_no_colors(m_info.material_name, false);
            if (m_info.needs_tangent)
                fail(ptr + "/material",
                     "the material has a normal map, which needs a surface's tangent space: "
                     "curves have none");
            if (m_info.opacity.active())
                fail(ptr + "/material", "curves cannot have a material with opacity < 1");
            if (m_info.needs_uv && g.root_uvs.empty())
                fail(ptr + "/root_uvs",
                     "the shape's material or emission is textured but the curves have no "
                     "root_uvs");
            if (!m_info.needs_uv) g.root_uvs = {};
            object_bounds.lo = glm::min(object_bounds.lo, object_extent.lo);
            object_bounds.hi = glm::max(object_bounds.hi, object_extent.hi);
            grow(glm::dvec3(extent.lo));
            grow(glm::dvec3(extent.hi));
            check_finite_bounds();
            if (m_proto >= 0)
                m_b.m_builder.impl().prototypes[std::size_t(m_proto)].curves.push_back(
                    std::move(g));
            else
                m_b.m_builder.impl().curves.push_back(std::move(g));
        }

        void add_instance(const std::string& of, const std::string& of_ptr) override {
            if (m_proto >= 0)
                fail(of_ptr,
                     "a prototype cannot hold instances (one level of instancing: a prototype "
                     "may not place itself or another prototype)");
            const auto& protos = m_b.m_desc.prototypes;
            for (std::size_t p = 0; p < protos.size(); ++p) {
                if (protos[p].first != of) continue;
                m_b.m_pending.push_back({index, std::uint32_t(p), xf, true});
                return;
            }
            std::string msg = "unknown prototype '" + of + "' (";
            if (protos.empty()) msg += "the scene has no \"prototypes\"";
            for (std::size_t p = 0; p < protos.size(); ++p)
                msg += (p ? ", '" : "known: '") + protos[p].first + "'";
            fail(of_ptr, msg + ")");
        }

        bool can_instance() const override { return m_proto < 0; }
        std::uint32_t add_local_prototype() override {
            std::vector<PrototypeGeom>& protos = m_b.m_builder.impl().prototypes;
            protos.emplace_back();
            return std::uint32_t(protos.size() - 1);
        }
        void add_part_to(std::uint32_t prototype, TriangleMesh mesh,
                         ShapeSurface surface) override {
            // As add_part, with the prototype as destination and no transform (the
            // placements carry it).
            const glm::dmat4 shape_xf = xf;
            xf = glm::dmat4(1.0);
            m_proto = std::int32_t(prototype);
            m_local = true;
            add_part(std::move(mesh), std::move(surface));
            m_local = false;
            m_proto = -1;
            xf = shape_xf;
        }
        void place_prototype(std::uint32_t prototype, const glm::dmat4& local) override {
            m_b.m_pending.push_back({index, prototype, xf * local, false});
        }
        // A moving shape (shape_motion): everything it adds goes to its own prototype, in
        // object space.
        void build_into(std::uint32_t prototype) {
            m_proto = std::int32_t(prototype);
            m_local = true;
        }
        std::int32_t local_prototype() const { return m_proto; }
        // The shape has `motion_positions` (checked against its mesh by add_mesh); `deform`:
        // they render (motion blur on; the mesh then goes to its own prototype).
        bool deform_steps = false;
        bool deform = false;

      private:
        // The shape's own triangles (part -1) or one of its parts: transformed, validated,
        // degenerate triangles dropped, an area light when it emits; UVs as add_triangles says.
        void add_mesh(TriangleMesh mesh, const Vec3& tangent, std::int32_t part, bool emits,
                      const Rgb& radiance, const glm::dmat4* sphere) {
            for (const Vec3& p : mesh.positions) {
                object_bounds.lo = glm::min(object_bounds.lo, p);
                object_bounds.hi = glm::max(object_bounds.hi, p);
            }
            const glm::dmat3 lin(xf);
            const glm::dmat3 normal_mat = glm::transpose(glm::inverse(lin));
            // A mirroring transform reverses the winding: undo it so the authored front stays
            // the front; "flip_normals" reverses it on purpose.
            const bool flip = (glm::determinant(lin) < 0.0) != shape.flip_normals;
            // Object-space copies for MikkTSpace (only when a normal map needs tangents).
            std::vector<Vec3> object_positions, object_normals;
            std::vector<std::array<glm::vec4, 3>> tri_tangents;
            if (m_info.needs_tangent && !sphere && mesh.tangents.empty()) {
                object_positions = mesh.positions;
                object_normals = mesh.normals;
            }
            // Also without a transform: the identity leaves positions exact, and normals get
            // their double-precision renormalisation either way.
            for (Vec3& p : mesh.positions) {
                p = Vec3(glm::dvec3(xf * glm::dvec4(glm::dvec3(p), 1.0)));
                grow(glm::dvec3(p));
            }
            for (Vec3& n : mesh.normals) {
                const glm::dvec3 w = normal_mat * glm::dvec3(n);
                const double l = glm::length(w);
                n = l > 0.0 ? Vec3(w / l) : Vec3(0.f, 0.f, 1.f);
            }
            if (flip) {
                for (std::size_t i = 0; i + 2 < mesh.indices.size(); i += 3) {
                    std::swap(mesh.indices[i + 1], mesh.indices[i + 2]);
                }
            }
            std::vector<std::vector<Vec3>> step_positions, step_normals;
            if (deform_steps && part < 0)
                deformation_steps(mesh, normal_mat, step_positions, step_normals);
            check_finite_bounds();
            if (std::string err = validate_mesh(mesh); !err.empty()) fail(place(), err);
            // A deforming mesh keeps every triangle: one of zero area at the still time may not
            // be at another (Embree's test misses it while it is degenerate).
            if (step_positions.empty()) m_b.drop_degenerate(mesh, index);
            if (m_info.needs_tangent && !sphere) {
                if (mesh.uvs.empty())
                    fail(ptr + (shape.file.empty() ? "/uvs" : "/file"),
                         "the material has a normal map but the mesh has no UVs (its tangent "
                         "space needs them)");
                // MikkTSpace in object space, as Blender computes it: the kept triangles
                // over the untransformed positions and normals.
                TriangleMesh obj;
                if (mesh.tangents.empty()) {
                    obj.positions = std::move(object_positions);
                    obj.normals = std::move(object_normals);
                    obj.uvs = mesh.uvs;
                    obj.indices = mesh.indices;
                }
                tri_tangents = corner_tangents(mesh, obj, lin);
            }
            m_info.triangles += mesh.num_triangles();
            if (emits) {
                std::vector<Vec3> tri;
                tri.reserve(mesh.indices.size());
                for (std::uint32_t i : mesh.indices) tri.push_back(mesh.positions[i]);
                Light l = Light::area_triangles(std::move(tri), radiance, index);
                if (!(l.area() > 0.f)) fail(ptr + "/emission", "the emitting shape has no area");
                if (part < 0) {
                    add_light(std::move(l));
                } else {
                    std::vector<Light>& lights = m_b.m_builder.lights();
                    if (m_info.parts[std::size_t(part)].emission_texture) l.set_textured_emission();
                    m_info.parts[std::size_t(part)].light = std::int32_t(lights.size());
                    lights.push_back(std::move(l));
                }
            }
            MeshGeom g;
            g.shape = index;
            g.part = part;
            g.opacity = part < 0 ? m_info.opacity : m_info.parts[std::size_t(part)].opacity;
            const bool uv =
                part < 0 ? m_info.needs_uv : m_b.needs_uv(m_info.parts[std::size_t(part)]);
            if (uv) {
                if (sphere) {
                    g.spherical = true;
                    g.to_object = glm::inverse(xf * *sphere);
                } else if (mesh.uvs.empty()) {
                    fail(ptr + (shape.file.empty() ? "/uvs" : "/file"),
                         "the shape's material or emission is textured but the mesh has no UVs");
                } else {
                    g.tri_uvs.resize(mesh.num_triangles());
                    g.tri_dpduv.resize(mesh.num_triangles());
                    for (std::size_t t = 0; t < g.tri_uvs.size(); ++t) {
                        std::array<glm::dvec3, 3> p;
                        for (std::size_t j = 0; j < 3; ++j) {
                            g.tri_uvs[t][j] = mesh.uvs[mesh.indices[3 * t + j]];
                            p[j] = glm::dvec3(mesh.positions[mesh.indices[3 * t + j]]);
                        }
                        g.tri_dpduv[t] = triangle_uv_derivatives(p, g.tri_uvs[t]);
                    }
                }
            }
            const ShapeSurface& surface = part < 0 ? m_info : m_info.parts[std::size_t(part)];
            if (part < 0 ? m_info.needs_color : m_b.needs_color(surface)) {
                if (mesh.colors.empty()) fail_no_colors(surface.material_name, true);
                g.tri_colors.resize(mesh.num_triangles());
                for (std::size_t t = 0; t < g.tri_colors.size(); ++t)
                    for (std::size_t j = 0; j < 3; ++j)
                        g.tri_colors[t][j] = mesh.colors[mesh.indices[3 * t + j]];
            }
            mesh.colors = {};
            if (m_info.needs_tangent && sphere) g.tangent_sign = handedness(xf * *sphere);
            if (m_info.needs_tangent && sphere) g.sphere_to_world = glm::dmat3(xf * *sphere);
            g.tri_tangents = std::move(tri_tangents);
            mesh.uvs = {};
            mesh.tangents = {};
            g.mesh = std::move(mesh);
            g.step_positions = std::move(step_positions);
            g.step_normals = std::move(step_normals);
            if (tangent != Vec3(0.f)) g.tangent = Vec3(lin * glm::dvec3(tangent));
            if (m_proto >= 0) {
                m_b.m_builder.impl().prototypes[std::size_t(m_proto)].meshes.push_back(
                    std::move(g));
            } else {
                m_b.m_builder.impl().meshes.push_back(std::move(g));
            }
        }

        // The shape's `motion_positions` and `motion_normals` against `mesh` (as given: n
        // vertices, normals or none): every step 3n finite numbers, normals per step exactly
        // when the mesh has normals, none zero. With `deform`, the steps through the shape's
        // transform (positions) and its inverse transpose (normals, normalised), and the
        // shape's extent grown by them; otherwise checked only.
        void deformation_steps(const TriangleMesh& mesh, const glm::dmat3& normal_mat,
                               std::vector<std::vector<Vec3>>& positions,
                               std::vector<std::vector<Vec3>>& normals) {
            const std::size_t n = mesh.positions.size();
            const std::string mp = ptr + "/motion_positions";
            const std::string np = ptr + "/motion_normals";
            auto steps = [&](const std::vector<std::vector<float>>& in, const std::string& p,
                             const char* what, bool unit) {
                std::vector<std::vector<Vec3>> out;
                for (std::size_t k = 0; k < in.size(); ++k) {
                    const std::string sp = p + "/" + std::to_string(k);
                    if (in[k].size() != 3 * n)
                        fail(sp, "expected " + std::to_string(3 * n) + " numbers (3 per vertex: " +
                                     "the mesh has " + std::to_string(n) + " vertices), got " +
                                     std::to_string(in[k].size()));
                    for (std::size_t i = 0; i < in[k].size(); ++i)
                        if (!std::isfinite(in[k][i]))
                            fail(sp + "/" + std::to_string(i), "must be a finite number");
                    std::vector<Vec3> v(n);
                    for (std::size_t i = 0; i < n; ++i) {
                        v[i] = Vec3(in[k][3 * i], in[k][3 * i + 1], in[k][3 * i + 2]);
                        if (unit && !(glm::length(v[i]) > 0.f))
                            fail(sp + "/" + std::to_string(3 * i),
                                 std::string(what) + " " + std::to_string(i) + " is zero");
                    }
                    out.push_back(std::move(v));
                }
                return out;
            };
            std::vector<std::vector<Vec3>> p = steps(shape.motion_positions, mp, "position", false);
            if (mesh.normals.empty() && !shape.motion_normals.empty())
                fail(np, "the mesh has no normals (give \"normals\" too, or no motion_normals)");
            if (!mesh.normals.empty() && shape.motion_normals.empty())
                fail(mp,
                     "the mesh has normals: give its \"motion_normals\" too (one per vertex "
                     "per step)");
            std::vector<std::vector<Vec3>> nn = steps(shape.motion_normals, np, "normal", true);
            if (!deform) return;
            for (std::vector<Vec3>& step : p)
                for (Vec3& q : step) {
                    q = Vec3(glm::dvec3(xf * glm::dvec4(glm::dvec3(q), 1.0)));
                    grow(glm::dvec3(q));
                }
            for (std::vector<Vec3>& step : nn)
                for (Vec3& q : step) {
                    const glm::dvec3 w = normal_mat * glm::dvec3(q);
                    q = Vec3(w / glm::length(w));
                }
            positions = std::move(p);
            normals = std::move(nn);
        }

        // Prototypes hold triangles only: their hits are filled as meshes' are.
        void analytic_in_prototype() const {
            if (m_proto >= 0)
                fail(ptr + "/type",
                     "a prototype holds triangle shapes and curves only (box, quad, mesh, "
                     "icosphere, grid, gltf, curves), not the analytic sphere, disc or plane");
        }

        // A material or emission reads vertex colours the shape does not have: a mesh
        // without "colors" (`mesh`), or a kind that has none.
        [[noreturn]] void fail_no_colors(const std::string& material, bool mesh) const {
            const std::string what = "the material '" + material +
                                     "' or the emission reads vertex colours "
                                     "({\"vertex_color\": true}) but ";
            if (!mesh)
                fail(ptr + "/type", what + "a '" + std::string(shape_kind(shape.kind).name) +
                                        "' has none (only meshes with \"colors\" do)");
            fail(ptr + (shape.kind != ShapeKind::Mesh ? "/type"
                        : shape.file.empty()          ? "/colors"
                                                      : "/file"),
                 what + "the mesh has no colours" +
                     (shape.kind == ShapeKind::Mesh ? " (give \"colors\")" : ""));
        }

        // The bitangent sign factor of a placement: -1 when it mirrors (cross(n, t) then
        // points against dp/dv) or when flip_normals reverses n, +1 otherwise (both: +1).
        float handedness(const glm::dmat4& to_world) const {
            const bool mirrored = glm::determinant(glm::dmat3(to_world)) < 0.0;
            return mirrored != shape.flip_normals ? -1.f : 1.f;
        }

        // World tangents per corner of `mesh` (already transformed, degenerate triangles
        // dropped): its own per-position tangents, or MikkTSpace's over `obj` (the same
        // triangles in object space); xyz through the linear part `lin`, w times the
        // handedness.
        std::vector<std::array<glm::vec4, 3>> corner_tangents(const TriangleMesh& mesh,
                                                              const TriangleMesh& obj,
                                                              const glm::dmat3& lin) const {
            const std::size_t nt = mesh.num_triangles();
            std::vector<glm::vec4> c;
            if (mesh.tangents.empty()) {
                c = compute_tangents(obj);
            } else {
                c.resize(3 * nt);
                for (std::size_t i = 0; i < 3 * nt; ++i) c[i] = mesh.tangents[mesh.indices[i]];
            }
            const float hand = handedness(glm::dmat4(lin));
            std::vector<std::array<glm::vec4, 3>> out(nt);
            for (std::size_t t = 0; t < nt; ++t) {
                for (std::size_t j = 0; j < 3; ++j) {
                    const glm::vec4& v = c[3 * t + j];
                    const glm::dvec3 w = lin * glm::dvec3(Vec3(v));
                    const double l = glm::length(w);
                    out[t][j] = glm::vec4(l > 0.0 ? Vec3(w / l) : Vec3(0.f), v.w * hand);
                }
            }
            return out;
        }

      public:
        void add_light(Light light) override {
            if (m_info.emission_texture) light.set_textured_emission();
            std::vector<Light>& lights = m_b.m_builder.lights();
            m_info.light = std::int32_t(lights.size());
            lights.push_back(std::move(light));
        }

        void check_finite_bounds() override {
            const Bounds3& b = m_local ? local_bounds() : bounds;
            if (!is_finite(b.lo) || !is_finite(b.hi)) {
                fail(ptr, "the shape's extent overflows float (transform or size too large)");
            }
        }

      private:
        // The shape's extent, or (add_part_to) its local prototype's.
        void grow(const glm::dvec3& p) {
            Bounds3& b = m_local ? local_bounds() : bounds;
            b.lo = glm::min(b.lo, Vec3(p));
            b.hi = glm::max(b.hi, Vec3(p));
        }
        Bounds3& local_bounds() {
            return m_b.m_builder.impl().prototypes[std::size_t(m_proto)].bounds;
        }
        Builder& m_b;
        ShapeInfo& m_info;
        std::int32_t m_proto;  // the prototype being built, or -1
        bool m_local = false;  // building one of the shape's own prototypes (add_part_to)
    };

    // --- instancing (scenes/FORMAT.md, "Instances") -------------------------------------------

    // Every prototype's shapes after the description's (Scene::shapes() order), then the
    // instances that place them.
    void build_prototypes() {
        std::set<std::string> names;
        // After the shapes' own prototypes (add_local_prototype).
        m_prototype_base = m_builder.impl().prototypes.size();
        for (std::size_t p = 0; p < m_desc.prototypes.size(); ++p) {
            const auto& [pname, shapes] = m_desc.prototypes[p];
            const std::string pp = "/prototypes/" + escape_pointer_token(pname);
            if (!names.insert(pname).second) fail(pp, "duplicate prototype name '" + pname + "'");
            if (shapes.empty()) fail(pp, "a prototype needs at least one shape");
            m_builder.impl().prototypes.emplace_back();
            for (std::size_t k = 0; k < shapes.size(); ++k) {
                build_shape(shapes[k], std::uint32_t(m_builder.shapes().size()),
                            pp + "/" + std::to_string(k), std::int32_t(m_prototype_base + p));
            }
        }
        for (const PendingInstance& pi : m_pending) place_instance(pi);
    }

    struct PendingInstance {
        std::uint32_t shape, prototype;
        glm::dmat4 xf;
        bool described;  // prototype indexes the description's prototypes (else Impl's)
        std::vector<DecomposedTransform> motion = {};  // a moving placement (InstanceGeom)
    };

    // Instance `pi` (its transforms checked by build_shape: finite, affine, not singular).
    void place_instance(const PendingInstance& pi) {
        InstanceGeom in;
        in.prototype = std::uint32_t(pi.described ? m_prototype_base + pi.prototype : pi.prototype);
        in.place(pi.xf);
        in.motion = pi.motion;
        const PrototypeGeom& proto = m_builder.impl().prototypes[in.prototype];
        in.deforms = std::any_of(proto.meshes.begin(), proto.meshes.end(),
                                 [](const MeshGeom& g) { return !g.step_positions.empty(); });
        const Bounds3& pb = proto.bounds;
        if (pb.empty()) return;  // a glTF mesh without triangles: nothing to place
        // The world extent of every step's placement; a moving instance's also of its
        // interpolated placements, sampled finely (rotations swing corners outside the steps'
        // boxes). The scene's bounds serve light sampling and precision checks, not tracing
        // (Embree bounds the motion itself).
        Bounds3 wb;
        auto add_corners = [&](const glm::dmat4& m) {
            for (int i = 0; i < 8; ++i) {
                const glm::dvec3 c(i & 1 ? pb.hi.x : pb.lo.x, i & 2 ? pb.hi.y : pb.lo.y,
                                   i & 4 ? pb.hi.z : pb.lo.z);
                const Vec3 w(glm::dvec3(m * glm::dvec4(c, 1.0)));
                wb.lo = glm::min(wb.lo, w);
                wb.hi = glm::max(wb.hi, w);
            }
        };
        add_corners(pi.xf);
        if (!in.motion.empty()) {
            constexpr int kBoundSamples = 64;  // per motion segment
            const int n = kBoundSamples * int(in.motion.size() - 1);
            for (int i = 0; i <= n; ++i)
                add_corners(interpolate_motion(in.motion, double(i) / double(n)));
        }
        if (!is_finite(wb.lo) || !is_finite(wb.hi))
            fail(shape_place(pi.shape), "the instance's extent overflows float");
        check_coordinate_range(std::max(max_abs(wb.lo), max_abs(wb.hi)), pi.shape);
        m_builder.bounds().lo = glm::min(m_builder.bounds().lo, wb.lo);
        m_builder.bounds().hi = glm::max(m_builder.bounds().hi, wb.hi);
        Bounds3& sb = m_shape_bounds[pi.shape];
        sb.lo = glm::min(sb.lo, wb.lo);
        sb.hi = glm::max(sb.hi, wb.hi);
        m_builder.impl().instances.push_back(in);
    }

    // Coordinates beyond Scene::kMaxCoordinate break Embree's float triangle test (scene.h).
    void check_coordinate_range(double m, std::uint32_t index) {
        if (m > Scene::kMaxCoordinate) {
            std::ostringstream msg;
            msg << "the shape reaches coordinate " << m << ", beyond the renderer's range of +-"
                << Scene::kMaxCoordinate
                << " (float ray-triangle tests overflow there); scale the scene down or move it "
                   "nearer the origin";
            fail(shape_place(index), msg.str());
        }
    }

    // Removes triangles whose world-space edge cross product is exactly zero (repeated or
    // collinear vertices): they have no area, Embree never hits them, and their normal would be
    // NaN. Every other triangle, slivers included, stays.
    void drop_degenerate(TriangleMesh& mesh, std::uint32_t index) {
        std::vector<std::uint32_t>& ix = mesh.indices;
        std::size_t kept = 0;
        for (std::size_t t = 0; t + 2 < ix.size(); t += 3) {
            const Vec3 &a = mesh.positions[ix[t]], &b = mesh.positions[ix[t + 1]],
                       &c = mesh.positions[ix[t + 2]];
            if (glm::cross(b - a, c - a) == Vec3(0.f)) continue;
            ix[kept] = ix[t];
            ix[kept + 1] = ix[t + 1];
            ix[kept + 2] = ix[t + 2];
            kept += 3;
        }
        const std::size_t dropped = (ix.size() - kept) / 3;
        if (dropped == 0) return;
        ix.resize(kept);
        m_degenerate += dropped;
        std::string w = shape_place(index) + ": dropped " + std::to_string(dropped) +
                        " zero-area triangle" + (dropped == 1 ? "" : "s");
        if (kept == 0) fail(shape_place(index), "mesh has no triangles with non-zero area");
        m_builder.warnings().push_back(std::move(w));
    }

    // --- lights --------------------------------------------------------------------------------

    void build_light(const LightDesc& l, std::size_t index) {
        LightContext ctx(*this, l, "/lights/" + std::to_string(index));
        const LightKindDef* k = find_light_kind(l.kind);
        if (!k) fail(ctx.ptr + "/type", "unknown light type");
        k->build(ctx);
    }

    // What a medium kind's builder gets (kind_build.h).
    class MediumContext final : public MediumBuild {
      public:
        explicit MediumContext(Builder& b) : m_b(b) {}
        [[noreturn]] void fail(const std::string& p, const std::string& m) const override {
            m_b.fail(p, m);
        }
        bool files_allowed() const override { return m_b.m_limits.allow_files; }
        const std::string& base_dir() const override { return m_b.m_desc.base_dir; }

      private:
        Builder& m_b;
    };

    // What a light kind's builder adds to the scene (kind_build.h).
    class LightContext final : public LightBuild {
      public:
        LightContext(Builder& b, const LightDesc& l, std::string p)
            : LightBuild(l, std::move(p)), m_b(b) {}
        [[noreturn]] void fail(const std::string& p, const std::string& m) const override {
            m_b.fail(p, m);
        }
        bool files_allowed() const override { return m_b.m_limits.allow_files; }
        const std::string& base_dir() const override { return m_b.m_desc.base_dir; }
        void add_light(Light light) override { m_b.m_builder.lights().push_back(std::move(light)); }
        void add_environment(Light light) override {
            if (m_b.m_builder.environment() >= 0)
                fail(ptr, "only one environment light is allowed");
            m_b.m_builder.environment() = std::int32_t(m_b.m_builder.lights().size());
            add_light(std::move(light));
        }
        void warn(std::string message) override {
            m_b.m_builder.warnings().push_back(std::move(message));
        }

      private:
        Builder& m_b;
    };

    // --- analysis ------------------------------------------------------------------------------

    static bool reflects(const Material& m) {
        if (m.transmissive()) return true;  // a dielectric reflects at least its Fresnel part
        if (const Material::Combination* c = m.combination())
            return reflects(*c->a) || reflects(*c->b);
        if (m.oren_nayar()) return max_component(m.oren_nayar()->rho()) > 0.f;
        if (m.diffuse() && max_component(m.diffuse()->rho()) > 0.f) return true;
        if (m.glossy()) return true;
        if (m.principled()) return m.principled()->flags() != BxDFFlags::None;
        if (m.mirror() && max_component(m.mirror()->scale()) > 0.f) return true;
        return false;
    }

    // Conservative frustum test: false only when the box lies entirely outside one side of the
    // camera's view frustum (with a 1% margin).
    bool maybe_visible(const Bounds3& b) const {
        if (b.empty()) return false;
        const Camera& c = m_builder.scene.camera();
        bool all_behind = true, all_left = true, all_right = true, all_below = true,
             all_above = true;
        float tx = 1.01f * c.tan_half_x, ty = 1.01f * c.tan_half_y;
        const bool persp = c.projection == Projection::Perspective;
        for (int i = 0; i < 8; ++i) {
            Vec3 p(i & 1 ? b.hi.x : b.lo.x, i & 2 ? b.hi.y : b.lo.y, i & 4 ? b.hi.z : b.lo.z);
            Vec3 v = p - c.position;
            float z = glm::dot(v, c.forward), x = glm::dot(v, c.right), y = glm::dot(v, c.true_up);
            // The window at depth z: k (centre +- half-extent), k = z (perspective) or 1
            // (orthographic), widened by a lens of radius R: a lens ray's offset from its
            // lens-centre ray is l (1 - z / focus_distance), at most R (1 + z / focus_distance).
            const float k = persp ? z : 1.f;
            const float m = c.has_lens() ? c.lens_radius * (1.f + z / c.focus_distance) : 0.f;
            all_behind &= z <= 0.f;
            all_left &= x < k * (c.center_x - tx) - m;
            all_right &= x > k * (c.center_x + tx) + m;
            all_below &= y < k * (c.center_y - ty) - m;
            all_above &= y > k * (c.center_y + ty) + m;
        }
        return !(all_behind || all_left || all_right || all_below || all_above);
    }

    void analyse() {
        SceneFeatures& f = m_builder.features();
        const Scene& scene = m_builder.scene;
        f = SceneFeatures{};
        f.num_shapes = scene.shapes().size();
        f.num_materials = m_builder.materials().size();
        f.num_lights = scene.lights().size();
        f.lambert_only = !scene.shapes().empty();
        for (std::size_t i = 0; i < scene.shapes().size(); ++i) {
            const ShapeInfo& s = scene.shapes()[i];
            // The shape's own surface, then its parts' (a glTF file's materials).
            auto surface = [&](const ShapeSurface& su) {
                BxDFFlags fl = su.material->flags();
                if (su.textured >= 0)
                    fl = fl | m_builder.textured()[std::size_t(su.textured)].flags;
                f.lobes = f.lobes | fl;
                // The Lambert-only kernel reads the Lambertian lobe itself: Oren-Nayar and
                // combinations of Lambertians are Diffuse too but have no such lobe.
                if (fl != BxDFFlags::None && !(fl == BxDFFlags::Diffuse && su.material->diffuse()))
                    f.lambert_only = false;
                if (reflects(*su.material)) f.can_reflect = true;
                if (su.textured >= 0) f.has_textured = true;
                // A surface that bounds a medium or lets rays through (an unused one is not).
                if (scene.medium_interface(su.material)) f.has_media = true;
                if (su.material->subsurface()) f.has_subsurface = true;
                if (su.material->has_holdout()) f.has_holdout = true;
                if (su.light >= 0 && maybe_visible(m_shape_bounds[i])) f.emitter_visible = true;
            };
            if (s.parts.empty()) surface(s);
            for (const ShapeSurface& p : s.parts) surface(p);
            if (s.holdout) f.has_holdout = true;
            f.num_triangles += s.triangles;
            if (s.kind == ShapeKind::Sphere) ++f.num_spheres;
            if (s.kind == ShapeKind::Plane) ++f.num_planes;
            if (s.kind == ShapeKind::Disc) ++f.num_discs;
        }
        f.has_diffuse = any(f.lobes & BxDFFlags::Diffuse);
        f.has_glossy = any(f.lobes & BxDFFlags::Glossy);
        f.has_specular = any(f.lobes & BxDFFlags::Specular);
        f.has_transmission = is_transmissive(f.lobes);
        for (const Light& l : scene.lights()) {
            l.note(f);
            if (!l.is_delta()) f.any_non_delta_light = true;
            if (l.hittable()) f.any_hittable_light = true;
        }
        f.all_lights_delta = !f.any_non_delta_light;
        if (scene.world_medium() >= 0) f.has_media = true;
        if (scene.environment()) f.emitter_visible = true;  // escaping camera rays see it
        f.has_motion = m_camera_moves || m_shapes_move;
        f.needs_alpha = m_desc.render.film_transparent || f.has_holdout;
        if (m_camera_moves) f.emitter_visible = true;  // the frustum test is the still camera's
    }

    // Counts triangles against the limit before they are generated.
    void reserve_triangles(std::uint64_t n, const std::string& ptr) {
        m_triangles += n;
        if (n > m_limits.max_triangles || m_triangles > m_limits.max_triangles) {
            fail(ptr, "the scene exceeds the limit of " + std::to_string(m_limits.max_triangles) +
                          " triangles");
        }
    }

    const SceneDescription& m_desc;
    std::string m_name;
    SceneLimits m_limits;
    BuildReport* m_report;
    std::uint64_t m_triangles = 0, m_degenerate = 0;
    Scene::Builder m_builder;
    std::map<std::string, BuiltMaterial> m_named;
    std::map<std::string, const MaterialDesc*> m_named_desc;  // every named material
    std::map<std::string, std::int32_t> m_medium_index;       // medium name -> Scene::media()
    std::vector<std::string> m_building;  // named materials being built (cycle detection)
    TexelImageCache m_images;             // an image used twice is read once
    const Material* m_black = nullptr;
    std::vector<Bounds3> m_shape_bounds;
    std::vector<std::string> m_places;       // shape_place() per Scene::shapes() index
    std::vector<PendingInstance> m_pending;  // instances, placed once their prototypes are built
    bool m_motion_on = false;                // "motion_blur" given and enabled
    bool m_camera_moves = false;             // with motion blur on: the camera has a motion
    bool m_shapes_move = false;              // with motion blur on: some shape has a motion
    std::size_t m_prototype_base = 0;        // Impl::prototypes index of the first described
};

}  // namespace

std::string SceneFeatures::describe() const {
    std::ostringstream s;
    auto yn = [](bool b) { return b ? "yes" : "no"; };
    s << "geometry: " << num_shapes << " shapes (" << num_triangles << " triangles, " << num_spheres
      << " exact spheres, " << num_discs << " discs, " << num_planes << " infinite planes), "
      << num_materials << " materials\n";
    s << "lobes: diffuse " << yn(has_diffuse) << ", glossy " << yn(has_glossy) << ", specular "
      << yn(has_specular) << ", transmission " << yn(has_transmission)
      << (lambert_only ? " (Lambert only)" : "") << "; textured materials " << yn(has_textured)
      << "\n";
    s << "lights: " << num_lights << " (point " << yn(has_point) << ", spot " << yn(has_spot)
      << ", directional " << yn(has_directional) << ", area " << yn(has_area) << ", environment "
      << yn(has_environment) << "); all delta: " << yn(all_lights_delta) << "\n";
    s << "emitter visible to the camera: " << yn(emitter_visible)
      << "; surfaces reflect (indirect light possible): " << yn(can_reflect) << "\n";
    if (has_media) s << "media: yes (a world medium or medium boundaries)\n";
    if (has_subsurface) s << "subsurface: yes (random walks inside objects)\n";
    if (has_motion) s << "motion blur: yes (a moving camera, moving or deforming shapes)\n";
    if (needs_alpha)
        s << "alpha: yes (" << (has_holdout ? "a holdout" : "film transparent") << ")\n";
    return s.str();
}

double aperture_radius(const CameraDesc& c) {
    if (c.aperture_radius) return *c.aperture_radius;
    if (c.fstop && c.focal_length) return *c.focal_length * 1e-3 / (2.0 * *c.fstop);
    return 0.0;
}

TextureMemoryStats Scene::texture_memory() const {
    TextureMemoryStats s = m_texture_memory;
    if (m_tile_cache) {
        s.hits = s.misses = s.evictions = 0;
        m_tile_cache->stats(s);
    }
    return s;
}

Scene build_scene(const SceneDescription& desc, const std::string& name, const SceneLimits& limits,
                  BuildReport* report) {
    return Builder(desc, name, limits, report).build();
}

}  // namespace facet::render
