// The JSON scene format, "facet-scene" version 1 (scenes/FORMAT.md): reader (JSON ->
// SceneDescription), writer (SceneDescription -> JSON), the description's fingerprint, and
// load_scene (reader + build_scene). The reader checks what JSON can get wrong — syntax,
// duplicate keys, types, unknown keys and names, required keys — and reports it as a SceneError
// "<file>: <JSON pointer>: <message>"; value checks are build_scene's (scene_builder.h), which
// names the same pointers.
#include <nlohmann/json.hpp>

#include <array>
#include <bit>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include "facet/render/kinds.h"
#include "facet/render/scene_description.h"
#include "facet/render/texture_kinds.h"
#include "scene_checks.h"

namespace facet::render {

namespace {

using json = nlohmann::json;
using detail::escape_pointer_token;

// The keys of a mesh kind's MeshArrays field (ShapeDesc::mesh).
constexpr std::array<const char*, 6> kMeshArrayKeys = {"positions", "indices",  "normals",
                                                       "uvs",       "tangents", "colors"};
// The keys of a curves kind's CurveArrays field (ShapeDesc::curves).
constexpr std::array<const char*, 5> kCurveArrayKeys = {"points", "radius", "counts", "root_uvs",
                                                        "strand_random"};
// A mesh kind's deformation motion (ShapeDesc::motion_positions, motion_normals), with the
// arrays or a "file"; a curves kind's is motion_positions alone.
constexpr std::array<const char*, 2> kMeshMotionKeys = {"motion_positions", "motion_normals"};

std::string type_name(const json& v) {
    switch (v.type()) {
        case json::value_t::null:
            return "null";
        case json::value_t::boolean:
            return "a boolean";
        case json::value_t::number_integer:
        case json::value_t::number_unsigned:
        case json::value_t::number_float:
            return "a number";
        case json::value_t::string:
            return "a string";
        case json::value_t::array:
            return "an array";
        case json::value_t::object:
            return "an object";
        default:
            return "an unsupported value";
    }
}

// Rejects duplicate object keys (nlohmann keeps the last one silently), naming the object.
class DuplicateKeyGuard {
  public:
    struct Duplicate {
        std::string pointer, key;
    };
    bool operator()(int /*depth*/, json::parse_event_t event, json& parsed) {
        switch (event) {
            case json::parse_event_t::object_start:
                m_frames.push_back({false, {}, {}, 0});
                break;
            case json::parse_event_t::array_start:
                m_frames.push_back({true, {}, {}, 0});
                break;
            case json::parse_event_t::key: {
                Frame& f = m_frames.back();
                f.key = parsed.get<std::string>();
                if (!f.keys.insert(f.key).second) throw Duplicate{pointer(), f.key};
                break;
            }
            case json::parse_event_t::object_end:
            case json::parse_event_t::array_end:
                m_frames.pop_back();
                if (!m_frames.empty() && m_frames.back().is_array) ++m_frames.back().index;
                break;
            case json::parse_event_t::value:
                if (!m_frames.empty() && m_frames.back().is_array) ++m_frames.back().index;
                break;
        }
        return true;
    }

  private:
    struct Frame {
        bool is_array;
        std::set<std::string> keys;
        std::string key;
        std::size_t index;
    };
    // Pointer of the innermost open object (the one that received the duplicate key).
    std::string pointer() const {
        std::string p;
        for (std::size_t i = 0; i + 1 < m_frames.size(); ++i) {
            const Frame& f = m_frames[i];
            p += "/" + (f.is_array ? std::to_string(f.index) : escape_pointer_token(f.key));
        }
        return p;
    }
    std::vector<Frame> m_frames;
};

class Reader {
  public:
    Reader(std::string name, std::string base_dir)
        : m_name(std::move(name)), m_base(std::move(base_dir)) {}

    SceneDescription read(const std::string& text) {
        json root = parse(text);
        expect_object(root, "");
        check_keys(root, "",
                   {"format", "version", "description", "camera", "materials", "shapes",
                    "prototypes", "lights", "media", "world_medium", "render"});
        std::string fmt = get_string(require(root, "", "format"), "/format");
        if (fmt != "facet-scene") fail("/format", "expected \"facet-scene\", got \"" + fmt + "\"");
        std::int64_t version = get_int(require(root, "", "version"), "/version", 0, 1 << 30);
        if (version != 1) {
            fail("/version", "unsupported version " + std::to_string(version) +
                                 " (this build reads version 1)");
        }
        SceneDescription d;
        d.base_dir = m_base;
        if (root.contains("description")) {
            d.description = get_string(root["description"], "/description");
        }
        d.camera = read_camera(require(root, "", "camera"), "/camera");
        if (root.contains("materials")) {
            const json& mats = root["materials"];
            expect_object(mats, "/materials");
            for (const auto& [name, m] : mats.items()) {
                d.materials.emplace_back(
                    name, read_material(m, "/materials/" + escape_pointer_token(name)));
            }
        }
        if (root.contains("shapes")) {
            const json& shapes = root["shapes"];
            expect_array(shapes, "/shapes");
            for (std::size_t i = 0; i < shapes.size(); ++i) {
                d.shapes.push_back(read_shape(shapes[i], "/shapes/" + std::to_string(i)));
            }
        }
        if (root.contains("prototypes")) {
            const json& protos = root["prototypes"];
            expect_object(protos, "/prototypes");
            for (const auto& [pname, shapes] : protos.items()) {
                const std::string pp = "/prototypes/" + escape_pointer_token(pname);
                expect_array(shapes, pp);
                std::vector<ShapeDesc> list;
                for (std::size_t i = 0; i < shapes.size(); ++i)
                    list.push_back(read_shape(shapes[i], pp + "/" + std::to_string(i)));
                d.prototypes.emplace_back(pname, std::move(list));
            }
        }
        if (root.contains("lights")) {
            const json& lights = root["lights"];
            expect_array(lights, "/lights");
            for (std::size_t i = 0; i < lights.size(); ++i) {
                d.lights.push_back(read_light(lights[i], "/lights/" + std::to_string(i)));
            }
        }
        if (root.contains("media")) {
            const json& media = root["media"];
            expect_object(media, "/media");
            for (const auto& [mname, m] : media.items())
                d.media.emplace_back(mname,
                                     read_medium(m, "/media/" + escape_pointer_token(mname)));
        }
        if (root.contains("world_medium")) {
            d.world_medium = get_string(root["world_medium"], "/world_medium");
            if (d.world_medium.empty()) fail("/world_medium", "must name a medium of \"media\"");
        }
        // Whether anything emits is build_scene's question: a glTF shape's materials are read
        // there (a scene lit only by an emissive glTF has no "lights" and no "emission").
        if (root.contains("render")) read_render(root["render"], "/render", d.render);
        return d;
    }

  private:
    // --- errors and JSON access ---------------------------------------------------------------

    [[noreturn]] void fail(const std::string& pointer, const std::string& message) const {
        throw SceneError(m_name + ": " + (pointer.empty() ? std::string("/") : pointer) + ": " +
                         message);
    }

    json parse(const std::string& text) const {
        DuplicateKeyGuard guard;
        try {
            return json::parse(text, std::ref(guard), true, false);
        } catch (const DuplicateKeyGuard::Duplicate& d) {
            fail(d.pointer, "duplicate key '" + d.key + "'");
        } catch (const json::parse_error& e) {
            // Line and column from the byte offset; the library's text minus its prefix.
            std::size_t line = 1, col = 1;
            for (std::size_t i = 0; i + 1 < e.byte && i < text.size(); ++i) {
                if (text[i] == '\n') {
                    ++line;
                    col = 1;
                } else {
                    ++col;
                }
            }
            // what() is "[json.exception.parse_error.N] parse error at line L, column C: why".
            std::string detail = e.what();
            if (std::size_t p = detail.find(": "); p != std::string::npos) {
                detail = detail.substr(p + 2);
            }
            throw SceneError(m_name + ": line " + std::to_string(line) + ", column " +
                             std::to_string(col) + ": invalid JSON: " + detail);
        } catch (const json::exception& e) {
            throw SceneError(m_name + ": invalid JSON: " + std::string(e.what()));
        }
    }

    void expect_object(const json& v, const std::string& ptr) const {
        if (!v.is_object()) fail(ptr, "expected an object, got " + type_name(v));
    }
    void expect_array(const json& v, const std::string& ptr) const {
        if (!v.is_array()) fail(ptr, "expected an array, got " + type_name(v));
    }

    void check_keys(const json& obj, const std::string& ptr,
                    std::initializer_list<const char*> allowed) const {
        check_keys_v(obj, ptr, std::vector<const char*>(allowed));
    }
    void check_keys_v(const json& obj, const std::string& ptr,
                      const std::vector<const char*>& allowed) const {
        // Unknown keys are errors, with the closest allowed key as a suggestion.
        std::vector<std::string> names(allowed.begin(), allowed.end());
        for (const auto& [key, value] : obj.items()) {
            if (std::find(names.begin(), names.end(), key) != names.end()) continue;
            std::string msg = "unknown key '" + key + "'";
            std::string guess = closest_name(key, names);
            if (!guess.empty()) {
                msg += " (did you mean '" + guess + "'?)";
            } else {
                msg += " (expected one of:";
                for (const auto& n : names) msg += " " + n;
                msg += ")";
            }
            fail(ptr + "/" + escape_pointer_token(key), msg);
        }
    }

    const json& require(const json& obj, const std::string& ptr, const char* key) const {
        auto it = obj.find(key);
        if (it == obj.end()) fail(ptr, std::string("missing required key '") + key + "'");
        return *it;
    }

    double get_number(const json& v, const std::string& ptr) const {
        if (!v.is_number()) fail(ptr, "expected a number, got " + type_name(v));
        double d = v.get<double>();
        if (!std::isfinite(d)) fail(ptr, "must be a finite number");
        return d;
    }
    std::int64_t get_int(const json& v, const std::string& ptr, std::int64_t lo,
                         std::int64_t hi) const {
        if (!v.is_number_integer()) {
            fail(ptr, "expected an integer, got " +
                          (v.is_number() ? std::string("a fractional number") : type_name(v)));
        }
        if (v.is_number_unsigned() && v.get<std::uint64_t>() > std::uint64_t(hi)) {
            fail(ptr, "value " + std::to_string(v.get<std::uint64_t>()) +
                          " is out of range: must be in [" + std::to_string(lo) + ", " +
                          std::to_string(hi) + "]");
        }
        std::int64_t i = v.get<std::int64_t>();
        if (i < lo || i > hi) fail(ptr, detail::int_range_message(i, lo, hi));
        return i;
    }
    bool get_bool(const json& v, const std::string& ptr) const {
        if (!v.is_boolean()) fail(ptr, "expected true or false, got " + type_name(v));
        return v.get<bool>();
    }
    std::string get_string(const json& v, const std::string& ptr) const {
        if (!v.is_string()) fail(ptr, "expected a string, got " + type_name(v));
        return v.get<std::string>();
    }
    Vec3 get_vec3(const json& v, const std::string& ptr) const {
        if (!v.is_array() || v.size() != 3) {
            fail(ptr, "expected an array of 3 numbers, got " +
                          (v.is_array() ? "an array of " + std::to_string(v.size()) + " elements"
                                        : type_name(v)));
        }
        Vec3 r;
        for (int i = 0; i < 3; ++i) {
            double d = get_number(v[std::size_t(i)], ptr + "/" + std::to_string(i));
            if (!std::isfinite(float(d)))
                fail(ptr + "/" + std::to_string(i), "too large for float");
            r[i] = float(d);
        }
        return r;
    }
    Vec3 get_direction(const json& v, const std::string& ptr) const {
        Vec3 d = get_vec3(v, ptr);
        float len = glm::length(d);
        if (!(len > 0.f) || !std::isfinite(len)) fail(ptr, "must be a non-zero direction");
        return d / len;
    }
    // A radiometric colour: a number (grey) or [r, g, b] (its sign is build_scene's check).
    Rgb get_color(const json& v, const std::string& ptr, const char* what) const {
        Rgb c;
        if (v.is_number()) {
            c = Rgb(float(get_number(v, ptr)));
        } else if (v.is_array() && v.size() == 3) {
            c = get_vec3(v, ptr);
        } else {
            fail(ptr,
                 std::string("expected ") + what + ": a number or [r, g, b], got " + type_name(v));
        }
        if (!is_finite(c)) fail(ptr, "too large for float");
        return c;
    }

    // --- camera, render, materials -------------------------------------------------------------

    CameraDesc read_camera(const json& c, const std::string& ptr) const {
        expect_object(c, ptr);
        check_keys(c, ptr,
                   {"position", "look_at", "up", "fov", "width", "height", "type", "scale",
                    "shift_x", "shift_y", "aperture_radius", "fstop", "focal_length",
                    "focus_distance", "blades", "rotation", "motion"});
        CameraDesc d;
        d.position = get_vec3(require(c, ptr, "position"), ptr + "/position");
        d.look_at = get_vec3(require(c, ptr, "look_at"), ptr + "/look_at");
        if (c.contains("up")) d.up = get_vec3(c["up"], ptr + "/up");
        if (c.contains("type")) d.type = get_string(c["type"], ptr + "/type");
        // fov frames a perspective camera, scale an orthographic one: each is required by its
        // type and an error with the other (an unknown type is build_scene's error).
        if (d.type != "perspective" && d.type != "orthographic") {
            if (c.contains("fov")) d.fov = get_number(c["fov"], ptr + "/fov");
            if (c.contains("scale")) d.scale = get_number(c["scale"], ptr + "/scale");
        } else if (d.type == "orthographic") {
            if (c.contains("fov"))
                fail(ptr + "/fov", "an orthographic camera has no fov (its framing is 'scale')");
            d.scale = get_number(require(c, ptr, "scale"), ptr + "/scale");
        } else {
            if (c.contains("scale"))
                fail(ptr + "/scale",
                     "'scale' is for orthographic cameras (\"type\": "
                     "\"orthographic\")");
            d.fov = get_number(require(c, ptr, "fov"), ptr + "/fov");
        }
        auto opt_number = [&](const char* key, std::optional<double>& out) {
            if (c.contains(key)) out = get_number(c[key], ptr + "/" + key);
        };
        if (c.contains("shift_x")) d.shift_x = get_number(c["shift_x"], ptr + "/shift_x");
        if (c.contains("shift_y")) d.shift_y = get_number(c["shift_y"], ptr + "/shift_y");
        opt_number("aperture_radius", d.aperture_radius);
        opt_number("fstop", d.fstop);
        opt_number("focal_length", d.focal_length);
        opt_number("focus_distance", d.focus_distance);
        if (c.contains("blades")) d.blades = int(get_int(c["blades"], ptr + "/blades", 0, 1024));
        if (c.contains("rotation")) d.rotation = get_number(c["rotation"], ptr + "/rotation");
        if (c.contains("motion")) {
            const json& m = c["motion"];
            const std::string mp = ptr + "/motion";
            if (!m.is_array()) fail(mp, "expected an array of camera steps, got " + type_name(m));
            for (std::size_t i = 0; i < m.size(); ++i) {
                const json& st = m[i];
                const std::string sp = mp + "/" + std::to_string(i);
                expect_object(st, sp);
                check_keys(st, sp, {"position", "look_at", "up"});
                CameraDesc::Step step;
                step.position = get_vec3(require(st, sp, "position"), sp + "/position");
                step.look_at = get_vec3(require(st, sp, "look_at"), sp + "/look_at");
                step.up = st.contains("up") ? get_vec3(st["up"], sp + "/up") : d.up;
                d.motion.push_back(step);
            }
        }
        d.width = int(get_int(require(c, ptr, "width"), ptr + "/width", 1, detail::kMaxImageSide));
        d.height =
            int(get_int(require(c, ptr, "height"), ptr + "/height", 1, detail::kMaxImageSide));
        return d;
    }

    void read_render(const json& r, const std::string& ptr, RenderSettings& s) const {
        expect_object(r, ptr);
        check_keys(r, ptr,
                   {"integrator", "spp", "time_budget", "max_depth", "seed", "adaptive_threshold",
                    "adaptive_min_samples", "motion_blur", "film_transparent"});
        if (r.contains("film_transparent"))
            s.film_transparent = get_bool(r["film_transparent"], ptr + "/film_transparent");
        if (r.contains("motion_blur")) {
            const json& m = r["motion_blur"];
            const std::string mp = ptr + "/motion_blur";
            RenderSettings::MotionBlur mb;
            if (m.is_boolean()) {
                mb.enabled = m.get<bool>();
            } else {
                expect_object(m, mp);
                check_keys(m, mp, {"enabled", "shutter", "position", "curve"});
                if (m.contains("enabled")) mb.enabled = get_bool(m["enabled"], mp + "/enabled");
                if (m.contains("shutter")) mb.shutter = get_number(m["shutter"], mp + "/shutter");
                if (m.contains("position"))
                    mb.position = get_string(m["position"], mp + "/position");
                if (m.contains("curve")) {
                    const json& c = m["curve"];
                    if (!c.is_array())
                        fail(mp + "/curve", "expected an array of numbers, got " + type_name(c));
                    for (std::size_t i = 0; i < c.size(); ++i)
                        mb.curve.push_back(get_number(c[i], mp + "/curve/" + std::to_string(i)));
                }
            }
            s.motion_blur = mb;
        }
        if (r.contains("adaptive_threshold"))
            s.adaptive_threshold = get_number(r["adaptive_threshold"], ptr + "/adaptive_threshold");
        if (r.contains("adaptive_min_samples"))
            s.adaptive_min_samples = int(get_int(
                r["adaptive_min_samples"], ptr + "/adaptive_min_samples", 0, detail::kMaxSpp));
        if (r.contains("integrator"))
            s.integrator = get_string(r["integrator"], ptr + "/integrator");
        if (r.contains("spp")) s.spp = int(get_int(r["spp"], ptr + "/spp", 1, detail::kMaxSpp));
        if (r.contains("time_budget")) {
            s.time_budget_s = get_number(r["time_budget"], ptr + "/time_budget");
        }
        if (r.contains("max_depth")) {
            s.max_depth = int(get_int(r["max_depth"], ptr + "/max_depth", 0, detail::kMaxDepth));
        }
        if (r.contains("seed")) {
            const json& v = r["seed"];
            if (v.is_number_unsigned()) {
                s.seed = v.get<std::uint64_t>();
            } else {
                s.seed = std::uint64_t(get_int(v, ptr + "/seed", 0, INT64_MAX));
            }
        }
    }

    // The procedural kind a texture object names by its key (texture_kinds.h), or null.
    static const TextureKindDef* procedural_kind_of(const json& t) {
        for (const TextureKindDef* k : texture_kinds())
            if (k->procedural && t.contains(std::string(k->name))) return k;
        return nullptr;
    }

    // A procedural texture's "mapping" (texture.h): Blender's Mapping node of type Point,
    // {"location": [x, y, z], "rotation": [x, y, z] (degrees, Euler XYZ), "scale": [x, y, z]}:
    // p' = T(location) Rz Ry Rx diag(scale) p; or {"matrix": [[4 numbers] x 3]}, the rows of
    // an affine map.
    glm::dmat4 read_mapping(const json& m, const std::string& ptr) const {
        expect_object(m, ptr);
        if (m.contains("matrix")) {
            check_keys(m, ptr, {"matrix"});
            const json& rows = m["matrix"];
            const std::string mp = ptr + "/matrix";
            if (!rows.is_array() || rows.size() != 3)
                fail(mp, "expected 3 rows of 4 numbers, got " + type_name(rows));
            glm::dmat4 x(1.0);
            for (int r = 0; r < 3; ++r) {
                const json& row = rows[std::size_t(r)];
                const std::string rp = mp + "/" + std::to_string(r);
                if (!row.is_array() || row.size() != 4)
                    fail(rp, "expected a row of 4 numbers, got " + type_name(row));
                for (int c = 0; c < 4; ++c)
                    x[c][r] = get_number(row[std::size_t(c)], rp + "/" + std::to_string(c));
            }
            return x;
        }
        check_keys(m, ptr, {"location", "rotation", "scale"});
        glm::dvec3 loc(0.0), rot(0.0), scl(1.0);
        if (m.contains("location")) loc = glm::dvec3(get_vec3(m["location"], ptr + "/location"));
        if (m.contains("rotation")) rot = glm::dvec3(get_vec3(m["rotation"], ptr + "/rotation"));
        if (m.contains("scale")) scl = glm::dvec3(get_vec3(m["scale"], ptr + "/scale"));
        return mapping_point_matrix(loc, glm::radians(rot), scl);
    }

    // A texture value (texture.h): {"texture": file, ...options} or {"checker": {...}}. Value
    // checks (ranges, names of filters...) are build_scene's; here types and keys.
    TextureDesc read_texture(const json& t, const std::string& ptr,
                             std::vector<const char*> extra_keys = {}) const {
        TextureDesc d;
        auto vec2 = [&](const json& v, const std::string& p) {
            if (!v.is_array() || v.size() != 2) fail(p, "expected [x, y], got " + type_name(v));
            return Vec2(float(get_number(v[0], p + "/0")), float(get_number(v[1], p + "/1")));
        };
        if (t.contains("vertex_color")) {
            // The mesh's vertex colour (texture.h): no image, no UV keys.
            std::vector<const char*> keys = {"vertex_color", "channel", "scale"};
            keys.insert(keys.end(), extra_keys.begin(), extra_keys.end());
            check_keys_v(t, ptr, keys);
            if (!get_bool(t["vertex_color"], ptr + "/vertex_color"))
                fail(ptr + "/vertex_color",
                     "must be true (omit the key for an image or checker texture)");
            d.kind = "vertex_color";
            if (t.contains("channel")) d.channel = get_string(t["channel"], ptr + "/channel");
        } else if (t.contains("checker")) {
            std::vector<const char*> keys = {"checker", "uv_scale", "uv_offset", "uv_rotation",
                                             "scale"};
            keys.insert(keys.end(), extra_keys.begin(), extra_keys.end());
            check_keys_v(t, ptr, keys);
            const json& c = t["checker"];
            const std::string cp = ptr + "/checker";
            expect_object(c, cp);
            check_keys(c, cp, {"colors", "scale"});
            d.kind = "checker";
            const json& cols = require(c, cp, "colors");
            if (!cols.is_array() || cols.size() != 2)
                fail(cp + "/colors", "expected two colours [c0, c1], got " + type_name(cols));
            for (std::size_t i = 0; i < 2; ++i)
                d.colors[i] =
                    get_color(cols[i], cp + "/colors/" + std::to_string(i), "a checker colour");
            if (c.contains("scale")) d.checker_scale = get_number(c["scale"], cp + "/scale");
        } else if (const TextureKindDef* kind = procedural_kind_of(t)) {
            // A procedural kind (texture_kinds.h): {"<kind>": {params}, "coordinates": ...,
            // "mapping": ...}. Parameter names and ranges are build_scene's (the kind's table).
            std::vector<const char*> keys = {kind->name.data(), "coordinates", "mapping", "scale",
                                             "channel"};
            keys.insert(keys.end(), extra_keys.begin(), extra_keys.end());
            check_keys_v(t, ptr, keys);
            d.kind = std::string(kind->name);
            const std::string kp = ptr + "/" + d.kind;
            const json& params = t[d.kind];
            expect_object(params, kp);
            for (const auto& [key, v] : params.items()) {
                const std::string p = kp + "/" + escape_pointer_token(key);
                const TextureParamDef* def = find_texture_param(*kind, key);
                if (def && def->form == TextureParamForm::Stops && v.is_array()) {
                    // A colour ramp's stops: [{"position": p, "color": [r, g, b(, a)]}, ...].
                    for (std::size_t i = 0; i < v.size(); ++i) {
                        const json& st = v[i];
                        const std::string sp = p + "/" + std::to_string(i);
                        expect_object(st, sp);
                        check_keys(st, sp, {"position", "color"});
                        TextureStop stop;
                        stop.position = get_number(require(st, sp, "position"), sp + "/position");
                        const json& c = require(st, sp, "color");
                        if (!c.is_array() || (c.size() != 3 && c.size() != 4))
                            fail(sp + "/color",
                                 "expected [r, g, b] or [r, g, b, a], got " + type_name(c));
                        for (std::size_t k = 0; k < c.size(); ++k)
                            stop.color[int(k)] =
                                get_number(c[k], sp + "/color/" + std::to_string(k));
                        d.stops.push_back(stop);
                    }
                } else if (v.is_number()) {
                    d.params.set(key, get_number(v, p));
                } else if (v.is_string()) {
                    d.params.set(key, v.get<std::string>());
                } else if (v.is_boolean()) {
                    d.params.set(key, v.get<bool>());
                } else if (v.is_array() && v.size() == 3) {
                    d.params.set(key, Rgb(get_vec3(v, p)));
                } else if (v.is_object()) {
                    // An input fed by a texture (a composite kind's; build_scene checks that
                    // the parameter takes one).
                    d.inputs.push_back({key, read_texture(v, p)});
                } else {
                    fail(p, "expected a number, a name, a colour [r, g, b] or a texture, got " +
                                type_name(v));
                }
            }
            if (t.contains("coordinates"))
                d.coordinates = get_string(t["coordinates"], ptr + "/coordinates");
            if (t.contains("mapping")) d.mapping = read_mapping(t["mapping"], ptr + "/mapping");
            if (t.contains("channel")) d.channel = get_string(t["channel"], ptr + "/channel");
        } else {
            std::vector<const char*> keys = {"texture",     "colorspace", "filter",
                                             "wrap",        "uv_scale",   "uv_offset",
                                             "uv_rotation", "scale",      "channel"};
            keys.insert(keys.end(), extra_keys.begin(), extra_keys.end());
            check_keys_v(t, ptr, keys);
            d.file = get_string(require(t, ptr, "texture"), ptr + "/texture");
            if (d.file.empty()) fail(ptr + "/texture", "must name an image file");
            if (t.contains("colorspace"))
                d.colorspace = get_string(t["colorspace"], ptr + "/colorspace");
            if (t.contains("filter")) d.filter = get_string(t["filter"], ptr + "/filter");
            if (t.contains("wrap")) d.wrap = get_string(t["wrap"], ptr + "/wrap");
            if (t.contains("channel")) d.channel = get_string(t["channel"], ptr + "/channel");
        }
        if (t.contains("uv_scale")) d.uv_scale = vec2(t["uv_scale"], ptr + "/uv_scale");
        if (t.contains("uv_offset")) d.uv_offset = vec2(t["uv_offset"], ptr + "/uv_offset");
        if (t.contains("uv_rotation"))
            d.uv_rotation = get_number(t["uv_rotation"], ptr + "/uv_rotation");
        if (t.contains("scale")) {
            if (t["scale"].is_array())
                d.color_scale = get_color(t["scale"], ptr + "/scale", "a colour multiplier");
            else
                d.scale = get_number(t["scale"], ptr + "/scale");
        }
        return d;
    }

    MaterialDesc read_material(const json& m, const std::string& ptr) const {
        expect_object(m, ptr);
        MaterialDesc d;
        d.model = get_string(require(m, ptr, "model"), ptr + "/model");
        for (const auto& [key, v] : m.items()) {
            if (key == "model") continue;
            std::string p = ptr + "/" + escape_pointer_token(key);
            if (key == "normal_map") {
                expect_object(v, p);
                MaterialDesc::NormalMap nm;
                nm.texture = read_texture(v, p, {"strength", "xy_scale"});
                if (v.contains("strength"))
                    nm.strength = get_number(v["strength"], p + "/strength");
                if (v.contains("xy_scale"))
                    nm.xy_scale = get_number(v["xy_scale"], p + "/xy_scale");
                d.normal_map = nm;
            } else if (key == "bump") {
                expect_object(v, p);
                MaterialDesc::Bump b;
                b.texture = read_texture(v, p, {"distance", "strength"});
                if (v.contains("distance")) b.distance = get_number(v["distance"], p + "/distance");
                if (v.contains("strength")) b.strength = get_number(v["strength"], p + "/strength");
                d.bump = b;
            } else if (key == "materials") {  // a combination's sub-materials (mix, add)
                if (!v.is_array())
                    fail(p, "expected an array of materials [a, b], got " + type_name(v));
                for (std::size_t k = 0; k < v.size(); ++k) {
                    const json& c = v[k];
                    const std::string cp = p + "/" + std::to_string(k);
                    if (c.is_string()) {
                        MaterialDesc ref;
                        ref.ref = c.get<std::string>();
                        if (ref.ref.empty()) fail(cp, "unknown material ''");
                        d.materials.push_back(std::move(ref));
                    } else if (c.is_object()) {
                        d.materials.push_back(read_material(c, cp));
                    } else {
                        fail(cp,
                             "expected a material name or an inline {\"model\": ...} object, "
                             "got " +
                                 type_name(c));
                    }
                }
            } else if (v.is_number()) {
                d.params.set(key, get_number(v, p));
            } else if (v.is_boolean()) {
                d.params.set(key, v.get<bool>());
            } else if (v.is_string()) {
                d.params.set(key, v.get<std::string>());
            } else if (v.is_array() && v.size() == 3) {
                d.params.set(key, Rgb(get_vec3(v, p)));
            } else if (v.is_object()) {
                d.textures[key] = read_texture(v, p);
            } else {
                fail(p,
                     "expected a number, a colour [r, g, b], a string, a boolean or a texture "
                     "{\"texture\": ...} / {\"checker\": ...} / {\"vertex_color\": true}, "
                     "got " +
                         type_name(v));
            }
        }
        return d;
    }

    // --- transforms ----------------------------------------------------------------------------

    glm::dmat4 read_transform_step(const json& t, const std::string& ptr) const {
        expect_object(t, ptr);
        check_keys(t, ptr, {"matrix", "scale", "rotate", "translate"});
        if (t.contains("matrix")) {
            if (t.size() != 1) {
                fail(ptr + "/matrix",
                     "a \"matrix\" cannot be combined with scale, rotate or "
                     "translate in the same object (use a list of transforms)");
            }
            const json& m = t["matrix"];
            if (!m.is_array() || m.size() != 16) {
                fail(ptr + "/matrix",
                     "expected 16 numbers (a 4x4 matrix, row-major), got " +
                         (m.is_array() ? std::to_string(m.size()) + " elements" : type_name(m)));
            }
            glm::dmat4 r(1.0);
            for (int row = 0; row < 4; ++row) {
                for (int col = 0; col < 4; ++col) {
                    r[col][row] = get_number(m[std::size_t(4 * row + col)],
                                             ptr + "/matrix/" + std::to_string(4 * row + col));
                }
            }
            if (r[0][3] != 0.0 || r[1][3] != 0.0 || r[2][3] != 0.0 || r[3][3] != 1.0) {
                fail(ptr + "/matrix", "the last row must be [0, 0, 0, 1] (affine transforms only)");
            }
            return r;
        }
        glm::dmat4 s(1.0), rot(1.0), tr(1.0);
        if (t.contains("scale")) {
            const json& v = t["scale"];
            glm::dvec3 k = v.is_number() ? glm::dvec3(get_number(v, ptr + "/scale"))
                                         : glm::dvec3(get_vec3(v, ptr + "/scale"));
            s[0][0] = k.x;
            s[1][1] = k.y;
            s[2][2] = k.z;
        }
        if (t.contains("rotate")) {
            const json& r = t["rotate"];
            std::string p = ptr + "/rotate";
            expect_object(r, p);
            check_keys(r, p, {"axis", "angle"});
            glm::dvec3 axis = glm::dvec3(get_direction(require(r, p, "axis"), p + "/axis"));
            double angle = get_number(require(r, p, "angle"), p + "/angle") * kPiD / 180.0;
            // Rodrigues' rotation formula, right-handed (counter-clockwise about the axis).
            double c = std::cos(angle), sn = std::sin(angle), k = 1.0 - c;
            glm::dmat3 m;
            m[0] = {c + axis.x * axis.x * k, axis.y * axis.x * k + axis.z * sn,
                    axis.z * axis.x * k - axis.y * sn};
            m[1] = {axis.x * axis.y * k - axis.z * sn, c + axis.y * axis.y * k,
                    axis.z * axis.y * k + axis.x * sn};
            m[2] = {axis.x * axis.z * k + axis.y * sn, axis.y * axis.z * k - axis.x * sn,
                    c + axis.z * axis.z * k};
            rot = glm::dmat4(m);
        }
        if (t.contains("translate")) {
            glm::dvec3 d(get_vec3(t["translate"], ptr + "/translate"));
            tr[3] = glm::dvec4(d, 1.0);
        }
        return tr * rot * s;
    }

    glm::dmat4 read_transform(const json& t, const std::string& ptr) const {
        glm::dmat4 m(1.0);
        if (t.is_array()) {
            for (std::size_t i = 0; i < t.size(); ++i) {
                m = read_transform_step(t[i], ptr + "/" + std::to_string(i)) * m;
            }
        } else {
            m = read_transform_step(t, ptr);
        }
        return m;
    }

    // --- shapes and lights: read by their kind's fields (kinds.h) -------------------------------

    template <class Desc>
    void read_field(const json& obj, const std::string& ptr, const Field<Desc>& f, Desc& d) const {
        const std::string key(f.key);
        const std::string p = ptr + "/" + key;
        if (f.type == FieldType::MeshArrays)
            return read_mesh(obj, ptr, d.*std::get<MeshData Desc::*>(f.member));
        if (f.type == FieldType::CurveArrays)
            return read_curves(obj, ptr, d.*std::get<CurveData Desc::*>(f.member));
        if (!obj.contains(key)) {
            if (f.required) require(obj, ptr, key.c_str());
            return;
        }
        const json& v = obj[key];
        std::visit(
            [&](auto member) {
                using T = std::remove_reference_t<decltype(d.*member)>;
                T& out = d.*member;
                if constexpr (std::is_same_v<T, Vec3> || std::is_same_v<T, std::optional<Vec3>>) {
                    out =
                        f.type == FieldType::Color ? get_color(v, p, f.doc.data()) : get_vec3(v, p);
                } else if constexpr (std::is_same_v<T, double> ||
                                     std::is_same_v<T, std::optional<double>>) {
                    out = get_number(v, p);
                } else if constexpr (std::is_same_v<T, int>) {
                    out = int(get_int(v, p, f.lo, f.hi));
                } else if constexpr (std::is_same_v<T, bool>) {
                    out = get_bool(v, p);
                } else if constexpr (std::is_same_v<T, std::array<Vec3, 4>>) {
                    if (!v.is_array() || v.size() != 4) {
                        fail(p, "expected an array of 4 points, got " +
                                    (v.is_array() ? std::to_string(v.size()) + " elements"
                                                  : type_name(v)));
                    }
                    for (std::size_t i = 0; i < 4; ++i)
                        out[i] = get_vec3(v[i], p + "/" + std::to_string(i));
                } else if constexpr (std::is_same_v<T, std::string>) {
                    out = get_string(v, p);
                    if (out.empty()) fail(p, "must not be empty");
                } else if constexpr (std::is_same_v<T, std::optional<AxisAngle>>) {
                    // Values (a zero axis, the angle's range) are build_scene's to check.
                    expect_object(v, p);
                    check_keys(v, p, {"axis", "angle"});
                    out = AxisAngle{get_vec3(require(v, p, "axis"), p + "/axis"),
                                    get_number(require(v, p, "angle"), p + "/angle")};
                } else {
                    fail(p, "internal: no reader for this field");
                }
            },
            f.member);
    }

    // "unknown <what> 'name'" with a did-you-mean among `names`, or the list of them.
    static std::string unknown_name(const char* what, const std::string& name,
                                    const std::vector<std::string>& names) {
        std::string msg = "unknown " + std::string(what) + " '" + name + "'";
        const std::string g = closest_name(name, names);
        if (!g.empty()) return msg + " (did you mean '" + g + "'?)";
        msg += " (expected one of:";
        for (const std::string& n : names) msg += " " + n;
        return msg + ")";
    }

    // Keys of an element: the common ones, then the kind's (mesh arrays are three keys).
    template <class Def>
    static std::vector<const char*> kind_keys(const Def& k, std::vector<const char*> keys) {
        for (const auto& f : k.fields) {
            if (f.type == FieldType::MeshArrays) {
                keys.insert(keys.end(), kMeshArrayKeys.begin(), kMeshArrayKeys.end());
                keys.insert(keys.end(), kMeshMotionKeys.begin(), kMeshMotionKeys.end());
            } else if (f.type == FieldType::CurveArrays) {
                keys.insert(keys.end(), kCurveArrayKeys.begin(), kCurveArrayKeys.end());
                keys.push_back(kMeshMotionKeys[0]);  // motion_positions (deformation)
            } else {
                keys.push_back(f.key.data());
            }
        }
        return keys;
    }

    ShapeDesc read_shape(const json& s, const std::string& ptr) const {
        expect_object(s, ptr);
        std::string type = get_string(require(s, ptr, "type"), ptr + "/type");
        const ShapeKindDef* k = find_shape_kind(type);
        if (!k) fail(ptr + "/type", unknown_name("shape type", type, shape_kind_names()));
        ShapeDesc d;
        d.kind = k->kind;
        std::vector<const char*> keys;
        for (std::string_view c : common_shape_keys()) keys.push_back(c.data());
        check_keys_v(s, ptr, kind_keys(*k, keys));
        if (s.contains("name")) d.name = get_string(s["name"], ptr + "/name");
        if (s.contains("two_sided")) d.two_sided = get_bool(s["two_sided"], ptr + "/two_sided");
        if (s.contains("flip_normals")) {
            d.flip_normals = get_bool(s["flip_normals"], ptr + "/flip_normals");
        }
        if (s.contains("holdout")) d.holdout = get_bool(s["holdout"], ptr + "/holdout");
        if (s.contains("shadow_catcher"))
            d.shadow_catcher = get_bool(s["shadow_catcher"], ptr + "/shadow_catcher");
        if (s.contains("visibility")) {
            const std::string vp = ptr + "/visibility";
            const json& v = s["visibility"];
            expect_object(v, vp);
            check_keys_v(v, vp, {kRayVisibilityNames.begin(), kRayVisibilityNames.end()});
            for (std::size_t i = 0; i < kRayVisibilityNames.size(); ++i) {
                const char* name = kRayVisibilityNames[i];
                if (v.contains(name) && !get_bool(v[name], vp + "/" + name))
                    d.visibility = std::uint8_t(d.visibility & ~(1u << i));
            }
        }
        if (s.contains("light_path")) {
            const std::string lp = ptr + "/light_path";
            const json& l = s["light_path"];
            if (!l.is_array()) fail(lp, "expected an array of switches, got " + type_name(l));
            const std::vector<std::string> rays(kLightPathRayNames.begin(),
                                                kLightPathRayNames.end());
            for (std::size_t i = 0; i < l.size(); ++i) {
                const std::string ep = lp + "/" + std::to_string(i);
                const json& e = l[i];
                expect_object(e, ep);
                check_keys(e, ep, {"ray", "material", "emission"});
                ShapeDesc::LightPathEntry entry;
                const std::string ray = get_string(require(e, ep, "ray"), ep + "/ray");
                const auto it = std::find(rays.begin(), rays.end(), ray);
                if (it == rays.end())
                    fail(ep + "/ray", unknown_name("Light Path ray output", ray, rays));
                entry.ray = std::uint8_t(1u << (it - rays.begin()));
                if (e.contains("material")) {
                    const json& m = e["material"];
                    if (m.is_string()) {
                        MaterialDesc ref;
                        ref.ref = m.get<std::string>();
                        if (ref.ref.empty()) fail(ep + "/material", "unknown material ''");
                        entry.material = std::move(ref);
                    } else if (m.is_object()) {
                        entry.material = read_material(m, ep + "/material");
                    } else {
                        fail(ep + "/material",
                             "expected a material name or an inline {\"model\": ...} object, "
                             "got " +
                                 type_name(m));
                    }
                }
                if (e.contains("emission"))
                    entry.emission =
                        get_color(e["emission"], ep + "/emission", "an emitted radiance");
                d.light_path.push_back(std::move(entry));
            }
        }
        if (s.contains("texture_space")) {
            const std::string tp = ptr + "/texture_space";
            const json& t = s["texture_space"];
            expect_object(t, tp);
            check_keys(t, tp, {"location", "size"});
            ShapeDesc::TextureSpace ts;
            ts.location = get_vec3(require(t, tp, "location"), tp + "/location");
            ts.size = get_vec3(require(t, tp, "size"), tp + "/size");
            d.texture_space = ts;
        }
        if (s.contains("emission")) {
            if (s["emission"].is_object())
                d.emission_texture = read_texture(s["emission"], ptr + "/emission");
            else
                d.emission = get_color(s["emission"], ptr + "/emission", "an emitted radiance");
        }
        if (s.contains("material")) {
            const json& m = s["material"];
            if (m.is_string()) {
                d.material_ref = m.get<std::string>();
                if (d.material_ref.empty()) fail(ptr + "/material", "unknown material ''");
            } else if (m.is_object()) {
                d.material = read_material(m, ptr + "/material");
            } else {
                fail(ptr + "/material",
                     "expected a material name or an inline {\"model\": ...} object, got " +
                         type_name(m));
            }
        }
        if (s.contains("transform"))
            d.transform = read_transform(s["transform"], ptr + "/transform");
        if (s.contains("motion")) {
            const json& m = s["motion"];
            if (!m.is_array())
                fail(ptr + "/motion", "expected an array of transforms, got " + type_name(m));
            for (std::size_t i = 0; i < m.size(); ++i)
                d.motion.push_back(read_transform(m[i], ptr + "/motion/" + std::to_string(i)));
        }
        for (const Field<ShapeDesc>& f : k->fields) read_field(s, ptr, f, d);
        // Deformation motion: arrays of per-step flat arrays (their sizes and values are
        // build_scene's to check against the mesh).
        auto read_steps = [&](const char* key, std::vector<std::vector<float>>& out) {
            if (!s.contains(key)) return;
            const json& a = s[key];
            const std::string p = ptr + "/" + key;
            if (!a.is_array())
                fail(p, "expected an array of steps (each a flat array of 3n numbers), got " +
                            type_name(a));
            for (std::size_t step = 0; step < a.size(); ++step) {
                const json& st = a[step];
                const std::string sp = p + "/" + std::to_string(step);
                if (!st.is_array())
                    fail(sp, "expected a flat array of 3n numbers (x0, y0, z0, x1, ...), got " +
                                 type_name(st));
                std::vector<float> v(st.size());
                for (std::size_t i = 0; i < st.size(); ++i)
                    v[i] = float(get_number(st[i], sp + "/" + std::to_string(i)));
                out.push_back(std::move(v));
            }
        };
        read_steps("motion_positions", d.motion_positions);
        read_steps("motion_normals", d.motion_normals);
        return d;
    }

    // A curves kind's arrays: "points" (3n numbers), "radius" (a number, or an array: one per
    // point), optional "counts" (control points per strand), "root_uvs" (a (u, v) pair per
    // strand) and "strand_random" (a number per strand). Their lengths against each other and their
    // values are build_scene's to check.
    void read_curves(const json& s, const std::string& ptr, CurveData& out) const {
        auto numbers = [&](const json& a, const std::string& p, const char* what) {
            if (!a.is_array()) fail(p, std::string("expected ") + what + ", got " + type_name(a));
            std::vector<float> v(a.size());
            for (std::size_t i = 0; i < a.size(); ++i)
                v[i] = float(get_number(a[i], p + "/" + std::to_string(i)));
            return v;
        };
        out.points = numbers(require(s, ptr, "points"), ptr + "/points",
                             "a flat array of 3n numbers (x0, y0, z0, x1, ...)");
        const json& r = require(s, ptr, "radius");
        if (r.is_number())
            out.radius = {float(get_number(r, ptr + "/radius"))};
        else
            out.radius =
                numbers(r, ptr + "/radius", "a number or an array of one radius per point");
        if (s.contains("counts")) {
            const json& c = s["counts"];
            if (!c.is_array())
                fail(ptr + "/counts",
                     "expected an array of control-point counts (one per strand), got " +
                         type_name(c));
            out.counts.resize(c.size());
            for (std::size_t i = 0; i < c.size(); ++i)
                out.counts[i] = std::uint32_t(
                    get_int(c[i], ptr + "/counts/" + std::to_string(i), 0, 0xFFFFFFFFll));
        }
        if (s.contains("root_uvs"))
            out.root_uvs = numbers(s["root_uvs"], ptr + "/root_uvs",
                                   "a flat array of one (u, v) pair per strand");
        if (s.contains("strand_random"))
            out.strand_random = numbers(s["strand_random"], ptr + "/strand_random",
                                        "an array of one number per strand");
    }

    // "positions", "indices" and optional "normals", or (the mesh kind's Path field) "file".
    void read_mesh(const json& s, const std::string& ptr, MeshData& out) const {
        if (s.contains("file")) {
            for (const char* k : kMeshArrayKeys) {
                if (s.contains(k)) {
                    fail(ptr + "/" + k, "cannot be combined with \"file\" (give one or the other)");
                }
            }
            return;
        }
        const json& pos = require(s, ptr, "positions");
        const json& idx = require(s, ptr, "indices");
        auto read_floats = [&](const json& a, const std::string& p) {
            if (!a.is_array() || a.size() % 3 != 0 || a.empty()) {
                fail(p, "expected a flat array of 3n numbers (x0, y0, z0, x1, ...)");
            }
            std::vector<float> out(a.size());
            for (std::size_t i = 0; i < a.size(); ++i) {
                out[i] = float(get_number(a[i], p + "/" + std::to_string(i)));
            }
            return out;
        };
        std::vector<float> positions = read_floats(pos, ptr + "/positions");
        if (!idx.is_array() || idx.size() % 3 != 0 || idx.empty()) {
            fail(ptr + "/indices", "expected a flat array of 3n vertex indices");
        }
        std::vector<std::uint32_t> indices(idx.size());
        const std::int64_t last = std::int64_t(positions.size() / 3) - 1;
        for (std::size_t i = 0; i < idx.size(); ++i) {
            indices[i] =
                std::uint32_t(get_int(idx[i], ptr + "/indices/" + std::to_string(i), 0, last));
        }
        std::vector<float> normals;
        if (s.contains("normals")) normals = read_floats(s["normals"], ptr + "/normals");
        std::vector<float> uvs;
        if (s.contains("uvs")) {
            const json& a = s["uvs"];
            if (!a.is_array() || a.size() != 2 * (positions.size() / 3)) {
                fail(ptr + "/uvs", "expected a flat array of one (u, v) pair per position (" +
                                       std::to_string(2 * (positions.size() / 3)) +
                                       " numbers), got " +
                                       (a.is_array() ? std::to_string(a.size()) : type_name(a)));
            }
            uvs.resize(a.size());
            for (std::size_t i = 0; i < a.size(); ++i)
                uvs[i] = float(get_number(a[i], ptr + "/uvs/" + std::to_string(i)));
        }
        std::vector<float> tangents;
        if (s.contains("tangents")) {
            const json& a = s["tangents"];
            if (!a.is_array() || a.size() != 4 * (positions.size() / 3)) {
                fail(ptr + "/tangents",
                     "expected a flat array of 4 numbers (x, y, z, bitangent sign) per position (" +
                         std::to_string(4 * (positions.size() / 3)) + " numbers), got " +
                         (a.is_array() ? std::to_string(a.size()) : type_name(a)));
            }
            tangents.resize(a.size());
            for (std::size_t i = 0; i < a.size(); ++i)
                tangents[i] = float(get_number(a[i], ptr + "/tangents/" + std::to_string(i)));
        }
        std::vector<float> colors;
        if (s.contains("colors")) {
            const json& a = s["colors"];
            const std::size_t n = positions.size() / 3;
            if (!a.is_array() || (a.size() != 3 * n && a.size() != 4 * n)) {
                fail(ptr + "/colors",
                     "expected a flat array of 3 (r, g, b) or 4 (r, g, b, a) numbers per position "
                     "(" +
                         std::to_string(3 * n) + " or " + std::to_string(4 * n) +
                         " numbers), got " +
                         (a.is_array() ? std::to_string(a.size()) : type_name(a)));
            }
            colors.resize(a.size());
            for (std::size_t i = 0; i < a.size(); ++i)
                colors[i] = float(get_number(a[i], ptr + "/colors/" + std::to_string(i)));
        }
        out = MeshData::copy_of(std::move(positions), std::move(indices), std::move(normals),
                                std::move(uvs), std::move(tangents), std::move(colors));
    }

    LightDesc read_light(const json& l, const std::string& ptr) const {
        expect_object(l, ptr);
        std::string type = get_string(require(l, ptr, "type"), ptr + "/type");
        const LightKindDef* k = find_light_kind(type);
        if (!k) {
            std::string msg = "unknown light type '" + type + "'";
            std::string g = closest_name(type, light_kind_names());
            if (!g.empty()) {
                msg += " (did you mean '" + g + "'?)";
            } else {
                msg += " (expected";
                const auto names = light_kind_names();
                for (std::size_t i = 0; i < names.size(); ++i)
                    msg += (i == 0 ? " " : i + 1 == names.size() ? " or " : ", ") + names[i];
                msg += "; area lights are shapes with \"emission\")";
            }
            fail(ptr + "/type", msg);
        }
        LightDesc d;
        d.kind = k->kind;
        check_keys_v(l, ptr, kind_keys(*k, {"type"}));
        for (const auto& [a, b] : k->exactly_one_of) {
            if (l.contains(std::string(a)) == l.contains(std::string(b))) {
                fail(ptr, "give exactly one of \"" + std::string(a) + "\" and \"" + std::string(b) +
                              "\"");
            }
        }
        for (const Field<LightDesc>& f : k->fields) read_field(l, ptr, f, d);
        return d;
    }

    MediumDesc read_medium(const json& m, const std::string& ptr) const {
        expect_object(m, ptr);
        const std::string kind = get_string(require(m, ptr, "kind"), ptr + "/kind");
        const MediumKindDef* k = find_medium_kind(kind);
        if (!k) fail(ptr + "/kind", unknown_name("medium kind", kind, medium_kind_names()));
        MediumDesc d;
        d.kind = k->kind;
        // A grid is placed in the world like a shape ("transform"; a homogeneous medium has
        // no place).
        const bool placed = k->kind == MediumKind::Grid;
        check_keys_v(m, ptr,
                     placed ? kind_keys(*k, {"kind", "transform"}) : kind_keys(*k, {"kind"}));
        for (const Field<MediumDesc>& f : k->fields) read_field(m, ptr, f, d);
        if (placed && m.contains("transform"))
            d.transform = read_transform(m["transform"], ptr + "/transform");
        return d;
    }

    std::string m_name, m_base;
};

// --- writer ------------------------------------------------------------------------------------

json vec_json(const Vec3& v) {
    return json::array({double(v.x), double(v.y), double(v.z)});
}

std::uint64_t fnv1a(const void* data, std::size_t n, std::uint64_t h);

// `hashed`: for the fingerprint, where an in-memory image stands as a hash of its texels; a
// scene file cannot hold one (an error: save the array as an image file and name it).
json texture_json(const TextureDesc& d, bool hashed) {
    json j = json::object();
    if (d.image) {
        if (!hashed)
            throw SceneError(d.file +
                             ": an in-memory (numpy) texture cannot be written to a scene file; "
                             "save it as an image file and give its path");
        j["texture"] = d.file;
        j["texels"] =
            std::to_string(d.image->texels.size()) + ":" +
            std::to_string(fnv1a(d.image->texels.data(), d.image->texels.size() * sizeof(float),
                                 1469598103934665603ull));
    }
    if (d.times_vertex_color)
        throw SceneError(d.file + ": an importer's vertex-tinted texture cannot be written");
    if (d.kind == "vertex_color") {
        j["vertex_color"] = true;
        if (!d.channel.empty()) j["channel"] = d.channel;
    } else if (d.kind == "checker") {
        j["checker"] = {{"colors", json::array({vec_json(d.colors[0]), vec_json(d.colors[1])})},
                        {"scale", d.checker_scale}};
    } else if (d.kind != "image") {
        json params = json::object();
        for (const auto& [key, v] : d.params.values()) {
            if (const double* x = std::get_if<double>(&v))
                params[key] = *x;
            else if (const std::string* t = std::get_if<std::string>(&v))
                params[key] = *t;
            else if (const bool* b = std::get_if<bool>(&v))
                params[key] = *b;
            else if (const Rgb* c = std::get_if<Rgb>(&v))
                params[key] = vec_json(*c);
        }
        for (const TextureInputDesc& in : d.inputs)
            params[in.name] = texture_json(in.texture, hashed);
        if (!d.stops.empty()) {
            json stops = json::array();
            for (const TextureStop& st : d.stops)
                stops.push_back(
                    {{"position", st.position},
                     {"color", json::array({st.color.r, st.color.g, st.color.b, st.color.a})}});
            params["stops"] = stops;
        }
        j[d.kind] = params;
        if (!d.channel.empty()) j["channel"] = d.channel;
        if (!d.coordinates.empty()) j["coordinates"] = d.coordinates;
        if (d.mapping != glm::dmat4(1.0)) {
            json rows = json::array();
            for (int r = 0; r < 3; ++r)
                rows.push_back(json::array(
                    {d.mapping[0][r], d.mapping[1][r], d.mapping[2][r], d.mapping[3][r]}));
            j["mapping"] = {{"matrix", rows}};
        }
    } else {
        if (!d.image) j["texture"] = d.file;
        if (!d.colorspace.empty()) j["colorspace"] = d.colorspace;
        if (!d.filter.empty()) j["filter"] = d.filter;
        if (!d.wrap.empty()) j["wrap"] = d.wrap;
        if (!d.channel.empty()) j["channel"] = d.channel;
    }
    if (d.uv_scale != Vec2(1.f))
        j["uv_scale"] = json::array({double(d.uv_scale.x), double(d.uv_scale.y)});
    if (d.uv_offset != Vec2(0.f))
        j["uv_offset"] = json::array({double(d.uv_offset.x), double(d.uv_offset.y)});
    if (d.uv_rotation != 0.0) j["uv_rotation"] = d.uv_rotation;
    if (d.color_scale != Rgb(1.f)) {
        // A colour multiplier; a number one is folded in (only one "scale" key).
        j["scale"] = vec_json(d.color_scale * float(d.scale));
    } else if (d.scale != 1.0) {
        j["scale"] = d.scale;
    }
    return j;
}

json material_json(const MaterialDesc& m, bool hashed) {
    json j = json::object();
    j["model"] = m.model;
    if (!m.materials.empty()) {
        json children = json::array();
        for (const MaterialDesc& c : m.materials)
            children.push_back(c.ref.empty() ? material_json(c, hashed) : json(c.ref));
        j["materials"] = children;
    }
    for (const auto& [name, t] : m.textures) j[name] = texture_json(t, hashed);
    if (m.normal_map) {
        json n = texture_json(m.normal_map->texture, hashed);
        if (m.normal_map->strength != 1.0) n["strength"] = m.normal_map->strength;
        if (m.normal_map->xy_scale != 1.0) n["xy_scale"] = m.normal_map->xy_scale;
        j["normal_map"] = n;
    }
    if (m.bump) {
        json b = texture_json(m.bump->texture, hashed);
        if (m.bump->distance != 1.0) b["distance"] = m.bump->distance;
        if (m.bump->strength != 1.0) b["strength"] = m.bump->strength;
        j["bump"] = b;
    }
    for (const auto& [name, v] : m.params.values()) {
        const std::string& key = name;  // (clang 14 cannot capture a structured binding)
        std::visit(
            [&](const auto& x) {
                using T = std::decay_t<decltype(x)>;
                if constexpr (std::is_same_v<T, Rgb>)
                    j[key] = vec_json(x);
                else
                    j[key] = x;
            },
            v);
    }
    return j;
}

json matrix_json(const glm::dmat4& m) {
    json a = json::array();
    for (int row = 0; row < 4; ++row)
        for (int col = 0; col < 4; ++col) a.push_back(m[col][row]);
    return json{{"matrix", a}};
}

std::uint64_t fnv1a(const void* data, std::size_t n, std::uint64_t h = 1469598103934665603ull) {
    const auto* p = static_cast<const unsigned char*>(data);
    for (std::size_t i = 0; i < n; ++i) {
        h ^= p[i];
        h *= 1099511628211ull;
    }
    return h;
}

// Mesh arrays by value, or (for the fingerprint) by a hash of their bytes.
template <class T>
json array_json(std::span<const T> a, bool hashed) {
    if (hashed)
        return std::to_string(a.size()) + ":" + std::to_string(fnv1a(a.data(), a.size_bytes()));
    json j = json::array();
    for (const T& x : a) {
        if constexpr (std::is_floating_point_v<T>)
            j.push_back(double(x));
        else
            j.push_back(x);
    }
    return j;
}
// One field of a shape or light: required and set-by-default values always, optional ones
// (std::optional, a mesh file or arrays) when present.
template <class Desc>
void write_field(json& j, const Field<Desc>& f, const Desc& d, bool hashed) {
    const std::string key(f.key);
    std::visit(
        [&](auto member) {
            using T = std::remove_cvref_t<decltype(d.*member)>;
            const T& v = d.*member;
            if constexpr (std::is_same_v<T, Vec3>) {
                j[key] = vec_json(v);
            } else if constexpr (std::is_same_v<T, std::optional<Vec3>>) {
                if (v) j[key] = vec_json(*v);
            } else if constexpr (std::is_same_v<T, std::optional<double>>) {
                if (v) j[key] = *v;
            } else if constexpr (std::is_same_v<T, std::array<Vec3, 4>>) {
                json a = json::array();
                for (const Vec3& p : v) a.push_back(vec_json(p));
                j[key] = a;
            } else if constexpr (std::is_same_v<T, std::string>) {
                if (!v.empty()) j[key] = v;
            } else if constexpr (std::is_same_v<T, std::optional<AxisAngle>>) {
                if (v) j[key] = json{{"axis", vec_json(v->axis)}, {"angle", v->angle}};
            } else if constexpr (std::is_same_v<T, MeshData>) {
                if (!v.positions.empty() || !v.indices.empty()) {
                    j["positions"] = array_json(v.positions, hashed);
                    j["indices"] = array_json(v.indices, hashed);
                    if (!v.normals.empty()) j["normals"] = array_json(v.normals, hashed);
                    if (!v.uvs.empty()) j["uvs"] = array_json(v.uvs, hashed);
                    if (!v.tangents.empty()) j["tangents"] = array_json(v.tangents, hashed);
                    if (!v.colors.empty()) j["colors"] = array_json(v.colors, hashed);
                }
            } else if constexpr (std::is_same_v<T, CurveData>) {
                j["points"] = array_json(std::span<const float>(v.points), hashed);
                if (v.radius.size() == 1 && !hashed)
                    j["radius"] = double(v.radius[0]);
                else
                    j["radius"] = array_json(std::span<const float>(v.radius), hashed);
                if (!v.counts.empty())
                    j["counts"] = array_json(std::span<const std::uint32_t>(v.counts), hashed);
                if (!v.root_uvs.empty())
                    j["root_uvs"] = array_json(std::span<const float>(v.root_uvs), hashed);
                if (!v.strand_random.empty())
                    j["strand_random"] =
                        array_json(std::span<const float>(v.strand_random), hashed);
            } else {
                j[key] = v;
            }
        },
        f.member);
}

json description_json(const SceneDescription& d, bool hashed_arrays) {
    json root = json::object();
    root["format"] = "facet-scene";
    root["version"] = 1;
    if (!d.description.empty()) root["description"] = d.description;
    const CameraDesc& c = d.camera;
    json cam = {{"position", vec_json(c.position)},
                {"look_at", vec_json(c.look_at)},
                {"up", vec_json(c.up)},
                {"width", c.width},
                {"height", c.height}};
    // Only what differs from the pinhole perspective camera, so that existing scenes (and
    // their fingerprints) are unchanged.
    if (c.type != "perspective") cam["type"] = c.type;
    if (c.type == "orthographic") {
        cam["scale"] = c.scale.value_or(0.0);
    } else {
        cam["fov"] = c.fov;
    }
    if (c.shift_x != 0.0) cam["shift_x"] = c.shift_x;
    if (c.shift_y != 0.0) cam["shift_y"] = c.shift_y;
    const std::pair<const char*, const std::optional<double>*> lens[] = {
        {"aperture_radius", &c.aperture_radius},
        {"fstop", &c.fstop},
        {"focal_length", &c.focal_length},
        {"focus_distance", &c.focus_distance}};
    for (const auto& [key, v] : lens)
        if (v->has_value()) cam[key] = **v;
    if (c.blades != 0) cam["blades"] = c.blades;
    if (c.rotation != 0.0) cam["rotation"] = c.rotation;
    if (!c.motion.empty()) {
        json steps = json::array();
        for (const CameraDesc::Step& st : c.motion)
            steps.push_back({{"position", vec_json(st.position)},
                             {"look_at", vec_json(st.look_at)},
                             {"up", vec_json(st.up)}});
        cam["motion"] = steps;
    }
    root["camera"] = cam;
    json mats = json::object();
    for (const auto& [name, m] : d.materials) mats[name] = material_json(m, hashed_arrays);
    root["materials"] = mats;
    auto shape_json = [&](const ShapeDesc& s) {
        json j = json::object();
        j["type"] = shape_kind(s.kind).name;
        if (!s.name.empty()) j["name"] = s.name;
        if (s.material)
            j["material"] = material_json(*s.material, hashed_arrays);
        else if (!s.material_ref.empty())
            j["material"] = s.material_ref;
        if (s.emission != Rgb(0.f)) j["emission"] = vec_json(s.emission);
        if (s.emission_texture) j["emission"] = texture_json(*s.emission_texture, hashed_arrays);
        if (!s.two_sided) j["two_sided"] = false;
        if (s.flip_normals) j["flip_normals"] = true;
        if (s.holdout) j["holdout"] = true;
        if (s.shadow_catcher) j["shadow_catcher"] = true;
        if (!s.light_path.empty()) {
            json l = json::array();
            for (const ShapeDesc::LightPathEntry& e : s.light_path) {
                json je = json::object();
                for (std::size_t i = 0; i < kLightPathRayNames.size(); ++i)
                    if (e.ray == (1u << i)) je["ray"] = kLightPathRayNames[i];
                if (e.material)
                    je["material"] = e.material->ref.empty()
                                         ? material_json(*e.material, hashed_arrays)
                                         : json(e.material->ref);
                if (e.emission != Rgb(0.f)) je["emission"] = vec_json(e.emission);
                l.push_back(je);
            }
            j["light_path"] = l;
        }
        if (s.visibility != kRayAll) {
            json v = json::object();
            for (std::size_t i = 0; i < kRayVisibilityNames.size(); ++i)
                if ((s.visibility & (1u << i)) == 0) v[kRayVisibilityNames[i]] = false;
            j["visibility"] = v;
        }
        if (s.texture_space)
            j["texture_space"] = {{"location", vec_json(s.texture_space->location)},
                                  {"size", vec_json(s.texture_space->size)}};
        if (s.transform) j["transform"] = matrix_json(*s.transform);
        if (!s.motion.empty()) {
            json steps = json::array();
            for (const glm::dmat4& m : s.motion) steps.push_back(matrix_json(m));
            j["motion"] = steps;
        }
        for (const Field<ShapeDesc>& f : shape_kind(s.kind).fields)
            write_field(j, f, s, hashed_arrays);
        auto steps_json = [&](const std::vector<std::vector<float>>& steps) {
            json a = json::array();
            for (const std::vector<float>& st : steps)
                a.push_back(array_json(std::span<const float>(st), hashed_arrays));
            return a;
        };
        if (!s.motion_positions.empty()) j["motion_positions"] = steps_json(s.motion_positions);
        if (!s.motion_normals.empty()) j["motion_normals"] = steps_json(s.motion_normals);
        return j;
    };
    json shapes = json::array();
    for (const ShapeDesc& s : d.shapes) shapes.push_back(shape_json(s));
    root["shapes"] = shapes;
    // Only when there are any: files without instances (and their fingerprints) are unchanged.
    if (!d.prototypes.empty()) {
        json protos = json::object();
        for (const auto& [pname, list] : d.prototypes) {
            json a = json::array();
            for (const ShapeDesc& s : list) a.push_back(shape_json(s));
            protos[pname] = a;
        }
        root["prototypes"] = protos;
    }
    // Media only when there are any: files without media (and their fingerprints) are
    // unchanged.
    if (!d.media.empty()) {
        json media = json::object();
        for (const auto& [mname, m] : d.media) {
            json j = json::object();
            const MediumKindDef& k = medium_kind(m.kind);
            j["kind"] = k.name;
            for (const Field<MediumDesc>& f : k.fields) write_field(j, f, m, hashed_arrays);
            if (m.transform) j["transform"] = matrix_json(*m.transform);
            media[mname] = j;
        }
        root["media"] = media;
    }
    if (!d.world_medium.empty()) root["world_medium"] = d.world_medium;
    json lights = json::array();
    for (const LightDesc& l : d.lights) {
        json j = json::object();
        const LightKindDef& k = light_kind(l.kind);
        j["type"] = k.name;
        for (const Field<LightDesc>& f : k.fields) write_field(j, f, l, hashed_arrays);
        lights.push_back(j);
    }
    root["lights"] = lights;
    const RenderSettings& r = d.render;
    root["render"] = {{"integrator", r.integrator},
                      {"spp", r.spp},
                      {"time_budget", r.time_budget_s},
                      {"max_depth", r.max_depth},
                      {"seed", r.seed}};
    // Adaptive sampling only when on: scenes without it keep their files as they were.
    if (r.adaptive_threshold > 0.0) {
        root["render"]["adaptive_threshold"] = r.adaptive_threshold;
        root["render"]["adaptive_min_samples"] = r.adaptive_min_samples;
    }
    // Film transparency only when on: scenes without it keep their files (and fingerprints).
    if (r.film_transparent) root["render"]["film_transparent"] = true;
    // Motion blur only when given: scenes without it keep their files as they were.
    if (r.motion_blur) {
        const RenderSettings::MotionBlur& mb = *r.motion_blur;
        json m = {{"enabled", mb.enabled}, {"shutter", mb.shutter}, {"position", mb.position}};
        if (!mb.curve.empty()) m["curve"] = mb.curve;
        root["render"]["motion_blur"] = m;
    }
    return root;
}

}  // namespace

SceneDescription parse_scene_description(const std::string& json_text, const std::string& name,
                                         const std::string& base_dir) {
    return Reader(name, base_dir).read(json_text);
}

SceneDescription read_scene_description(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw SceneError(path + ": cannot open the scene file");
    std::ostringstream ss;
    ss << in.rdbuf();
    if (in.bad()) throw SceneError(path + ": cannot read the scene file");
    std::string base = std::filesystem::path(path).parent_path().string();
    return parse_scene_description(ss.str(), path, base.empty() ? "." : base);
}

std::string write_scene_json(const SceneDescription& desc) {
    // nlohmann prints doubles with the shortest representation that reads back exactly.
    return description_json(desc, false).dump(2) + "\n";
}

void write_scene_file(const SceneDescription& desc, const std::string& path) {
    std::ofstream out(path, std::ios::binary);
    if (!out) throw SceneError(path + ": cannot create the scene file");
    out << write_scene_json(desc);
    if (!out) throw SceneError(path + ": cannot write the scene file");
}

std::uint64_t fingerprint(const SceneDescription& desc) {
    const std::string text = description_json(desc, true).dump();
    return fnv1a(text.data(), text.size());
}

Scene load_scene_from_string(const std::string& json_text, const std::string& name_for_errors,
                             const std::string& base_dir, const SceneLimits& limits) {
    return build_scene(parse_scene_description(json_text, name_for_errors, base_dir),
                       name_for_errors, limits);
}

Scene load_scene(const std::string& path, const SceneLimits& limits) {
    SceneDescription d = read_scene_description(path);
    return build_scene(d, path, limits);
}

}  // namespace facet::render
