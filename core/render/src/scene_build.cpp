// build_scene: SceneDescription -> Scene (facet/render/scene_description.h), with every value
// validated, and the scene analysis (SceneFeatures). Every error is a SceneError
// "<name>: <path>: <message>" with the JSON pointer the value would have in a scene file.
// This file holds the Builder's driver (build(): the order of the steps), the camera, motion
// blur and render settings, and the description's comparisons. The other steps, one topic a
// file (the Builder's declaration: scene_builder.h):
//  - build_materials.cpp: media, materials, textures, opacity, textured-material staging;
//  - build_shapes.cpp: shapes, prototypes and instances;
//  - build_lights.cpp: lights;
//  - scene_analysis.cpp: the scene analysis.

#include <algorithm>
#include <chrono>
#include <cstring>
#include <sstream>

#include "facet/render/scene_description.h"
#include "scene_builder.h"
#include "scene_checks.h"
#include "scene_precision.h"

namespace facet::render {

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

namespace detail {

Builder::Builder(const SceneDescription& desc, std::string name, const SceneLimits& limits,
                 BuildReport* report)
    : m_desc(desc),
      m_name(std::move(name)),
      m_limits(limits),
      m_report(report),
      m_images(limits.texture_memory) {}

Scene Builder::build() {
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

void Builder::fail(const std::string& pointer, const std::string& message) const {
    throw SceneError(m_name + ": " + (pointer.empty() ? std::string("/") : pointer) + ": " +
                     message);
}

void Builder::build_camera() {
    const CameraDesc& c = m_desc.camera;
    const std::string ptr = "/camera";
    check_finite(c.position, ptr + "/position");
    check_finite(c.look_at, ptr + "/look_at");
    check_finite(c.up, ptr + "/up");
    const std::vector<std::string> types = {"perspective", "orthographic"};
    if (std::find(types.begin(), types.end(), c.type) == types.end()) {
        std::string msg = "unknown camera type '" + c.type + "'";
        std::string g = closest_name(c.type, types);
        msg +=
            g.empty() ? " (expected perspective or orthographic)" : " (did you mean '" + g + "'?)";
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
            fail(ptr + "/focus_distance", "required with an aperture (aperture_radius or fstop)");
        o.focus_distance = float(positive_length(*c.focus_distance, ptr + "/focus_distance"));
    }
    if (c.blades == 1 || c.blades == 2)
        fail(ptr + "/blades",
             "must be 0 (round aperture) or at least 3, got " + std::to_string(c.blades));
    o.blades = int(check_int(c.blades, ptr + "/blades", 0, 1024));
    o.rotation_deg =
        float(check_range(c.rotation, ptr + "/rotation", -1e6, 1e6, "a finite angle in degrees"));
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
        fail(ptr,
             "the image has too many pixels (limit " + std::to_string(m_limits.max_pixels) + ")");
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
void Builder::build_motion() {
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

// The thin lens's radius (scene units) from aperture_radius, or fstop and focal_length
// (mm) as Cycles computes it (blender/camera.cpp): focal_length 1e-3 / (2 fstop), i.e.
// scene units taken as metres. 0 = pinhole.
double Builder::checked_aperture_radius(const CameraDesc& c, const std::string& ptr,
                                        Projection proj) const {
    if (c.aperture_radius && c.fstop)
        fail(ptr + "/fstop", "give aperture_radius or fstop (with focal_length), not both");
    if (c.focal_length && !c.fstop)
        fail(ptr + "/focal_length", "only used with fstop (the aperture from an f-number)");
    if (c.aperture_radius) {
        return check_range(*c.aperture_radius, ptr + "/aperture_radius", 0.0, Scene::kMaxCoordinate,
                           ">= 0 (scene units)");
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

void Builder::build_render() {
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
    s.adaptive_threshold = check_range(r.adaptive_threshold, ptr + "/adaptive_threshold", 0.0, 1.0,
                                       "in [0, 1] (0 = off)");
    s.adaptive_min_samples =
        int(check_int(r.adaptive_min_samples, ptr + "/adaptive_min_samples", 0, detail::kMaxSpp));
    s.width = m_builder.camera().width;
    s.height = m_builder.camera().height;
    s.motion_blur = r.motion_blur;
    s.film_transparent = r.film_transparent;
}

}  // namespace detail

double aperture_radius(const CameraDesc& c) {
    if (c.aperture_radius) return *c.aperture_radius;
    if (c.fstop && c.focal_length) return *c.focal_length * 1e-3 / (2.0 * *c.fstop);
    return 0.0;
}

Scene build_scene(const SceneDescription& desc, const std::string& name, const SceneLimits& limits,
                  BuildReport* report) {
    return detail::Builder(desc, name, limits, report).build();
}

}  // namespace facet::render
