// The JSON scene loader, format "facet-scene" version 1 (scenes/FORMAT.md), and the scene
// analysis (SceneFeatures). Every error is a SceneError "<file>: <JSON pointer>: <message>";
// unknown keys and names are errors with a "did you mean" suggestion.
#include <glm/gtc/matrix_transform.hpp>
#include <nlohmann/json.hpp>

#include <array>

#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include "facet/frame.h"
#include "facet/registry.h"
#include "scene_impl.h"

namespace facet::render {

namespace {

using json = nlohmann::json;

// Limits that keep a hostile or mistyped file from exhausting memory (documented in FORMAT.md).
constexpr int kMaxImageSide = 1 << 16;
constexpr int kMaxIcosphereSubdivisions = 9;     // 20 * 4^9 = 5.2M triangles
constexpr std::int64_t kMaxGridCells = 1 << 24;  // 33.5M triangles
constexpr int kMaxSpp = 1 << 20;
constexpr int kMaxDepth = 1024;

std::string escape_pointer_token(const std::string& key) {
    std::string out;
    for (char c : key) {
        if (c == '~')
            out += "~0";
        else if (c == '/')
            out += "~1";
        else
            out += c;
    }
    return out;
}

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

struct BuiltShape {
    Bounds3 bounds;  // world bounds (empty for planes)
};

class Loader {
  public:
    Loader(std::string name, std::string base_dir, const SceneLimits& limits)
        : m_name(std::move(name)), m_base(std::move(base_dir)), m_limits(limits) {}

    Scene load(const std::string& text) {
        json root = parse(text);
        expect_object(root, "");
        check_keys(root, "",
                   {"format", "version", "description", "camera", "materials", "shapes", "lights",
                    "render"});
        std::string fmt = get_string(require(root, "", "format"), "/format");
        if (fmt != "facet-scene") fail("/format", "expected \"facet-scene\", got \"" + fmt + "\"");
        std::int64_t version = get_int(require(root, "", "version"), "/version", 0, 1 << 30);
        if (version != 1) {
            fail("/version", "unsupported version " + std::to_string(version) +
                                 " (this build reads version 1)");
        }
        if (root.contains("description")) get_string(root["description"], "/description");

        m_builder.name() = m_name;
        load_camera(require(root, "", "camera"), "/camera");
        if (root.contains("materials")) load_materials(root["materials"], "/materials");
        if (root.contains("shapes")) {
            const json& shapes = root["shapes"];
            expect_array(shapes, "/shapes");
            for (std::size_t i = 0; i < shapes.size(); ++i) {
                load_shape(shapes[i], "/shapes/" + std::to_string(i), std::uint32_t(i));
            }
        }
        if (root.contains("lights")) {
            const json& lights = root["lights"];
            expect_array(lights, "/lights");
            for (std::size_t i = 0; i < lights.size(); ++i) {
                load_light(lights[i], "/lights/" + std::to_string(i));
            }
        }
        if (m_builder.lights().empty()) {
            fail(root.contains("lights") ? "/lights" : "",
                 "the scene has no light source (no entry in \"lights\" and no shape with "
                 "\"emission\")");
        }
        RenderSettings& rs = m_builder.settings();
        if (root.contains("render")) load_render(root["render"], "/render");
        rs.width = m_builder.camera().width;
        rs.height = m_builder.camera().height;

        m_builder.impl().build(m_name);
        analyse();
        m_builder.light_distribution() =
            LightDistribution(m_builder.scene.lights(), m_builder.scene.radius());
        return std::move(m_builder.scene);
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
    double get_number(const json& v, const std::string& ptr, double lo, double hi,
                      const char* range_text) const {
        double d = get_number(v, ptr);
        if (!(d >= lo && d <= hi)) {
            std::ostringstream s;
            s << "value " << d << " is out of range: must be " << range_text;
            fail(ptr, s.str());
        }
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
        if (i < lo || i > hi) {
            fail(ptr, "value " + std::to_string(i) + " is out of range: must be in [" +
                          std::to_string(lo) + ", " + std::to_string(hi) + "]");
        }
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
    // A non-negative radiometric colour: a number (grey) or [r, g, b].
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
        for (int i = 0; i < 3; ++i) {
            if (c[i] < 0.f) fail(ptr, std::string(what) + " must be >= 0");
        }
        return c;
    }

    // --- camera, render ------------------------------------------------------------------------

    void load_camera(const json& c, const std::string& ptr) {
        expect_object(c, ptr);
        check_keys(c, ptr, {"position", "look_at", "up", "fov", "width", "height"});
        Vec3 pos = get_vec3(require(c, ptr, "position"), ptr + "/position");
        Vec3 at = get_vec3(require(c, ptr, "look_at"), ptr + "/look_at");
        Vec3 up = c.contains("up") ? get_vec3(c["up"], ptr + "/up") : Vec3(0.f, 1.f, 0.f);
        double fov = get_number(require(c, ptr, "fov"), ptr + "/fov", 1e-3, 179.0,
                                "in [0.001, 179] degrees (full vertical angle)");
        int w = int(get_int(require(c, ptr, "width"), ptr + "/width", 1, kMaxImageSide));
        int h = int(get_int(require(c, ptr, "height"), ptr + "/height", 1, kMaxImageSide));
        if (std::int64_t(w) * h > m_limits.max_pixels) {
            fail(ptr, "the image has too many pixels (limit " +
                          std::to_string(m_limits.max_pixels) + ")");
        }
        glm::dvec3 f = glm::dvec3(at) - glm::dvec3(pos);
        double flen = glm::length(f);
        if (!(flen > 0.0)) fail(ptr + "/look_at", "must differ from the camera position");
        glm::dvec3 cr = glm::cross(f / flen, glm::dvec3(up));
        if (!(glm::length(cr) > 1e-6 * glm::length(glm::dvec3(up)))) {
            fail(ptr + "/up", "must not be zero or parallel to the view direction");
        }
        m_builder.camera() = Camera::make(pos, at, up, float(fov), w, h);
    }

    void load_render(const json& r, const std::string& ptr) {
        expect_object(r, ptr);
        check_keys(r, ptr, {"integrator", "spp", "time_budget", "max_depth", "seed"});
        RenderSettings& s = m_builder.settings();
        if (r.contains("integrator")) {
            s.integrator = get_string(r["integrator"], ptr + "/integrator");
            std::vector<std::string> known = {"direct", "path"};
            if (std::find(known.begin(), known.end(), s.integrator) == known.end()) {
                std::string msg = "unknown integrator '" + s.integrator + "'";
                std::string g = closest_name(s.integrator, known);
                msg += g.empty() ? " (expected direct or path)" : " (did you mean '" + g + "'?)";
                fail(ptr + "/integrator", msg);
            }
        }
        if (r.contains("spp")) s.spp = int(get_int(r["spp"], ptr + "/spp", 1, kMaxSpp));
        if (r.contains("time_budget")) {
            s.time_budget_s =
                get_number(r["time_budget"], ptr + "/time_budget", 0.0, 1e7, "in [0, 1e7] seconds");
        }
        if (r.contains("max_depth")) {
            s.max_depth = int(get_int(r["max_depth"], ptr + "/max_depth", 0, kMaxDepth));
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

    // --- materials -----------------------------------------------------------------------------

    // Builds a material from {"model": ..., params...} at `ptr`. Parameter errors from the
    // registry come back with the parameter's name, which becomes part of the pointer.
    const Material* build_material(const json& m, const std::string& ptr) {
        expect_object(m, ptr);
        std::string model = get_string(require(m, ptr, "model"), ptr + "/model");
        if (!find_model(model)) {
            std::vector<std::string> names;
            for (const auto& mi : model_table()) names.push_back(mi.name);
            std::string msg = "unknown model '" + model + "'";
            std::string g = closest_name(model, names);
            if (!g.empty()) {
                msg += " (did you mean '" + g + "'?)";
            } else {
                msg += " (expected one of:";
                for (const auto& n : names) msg += " " + n;
                msg += ")";
            }
            fail(ptr + "/model", msg);
        }
        ParamSet params;
        for (const auto& [key, v] : m.items()) {
            if (key == "model") continue;
            std::string p = ptr + "/" + escape_pointer_token(key);
            if (v.is_number()) {
                params.set(key, get_number(v, p));
            } else if (v.is_boolean()) {
                params.set(key, v.get<bool>());
            } else if (v.is_string()) {
                params.set(key, v.get<std::string>());
            } else if (v.is_array() && v.size() == 3) {
                params.set(key, Rgb(get_vec3(v, p)));
            } else {
                fail(p, "expected a number, a colour [r, g, b], a string or a boolean, got " +
                            type_name(v));
            }
        }
        try {
            m_builder.materials().push_back(
                std::make_unique<Material>(make_material(model, params)));
        } catch (const ParamError& e) {
            fail(e.param().empty() ? ptr + "/model" : ptr + "/" + escape_pointer_token(e.param()),
                 e.what());
        }
        return m_builder.materials().back().get();
    }

    void load_materials(const json& mats, const std::string& ptr) {
        expect_object(mats, ptr);
        for (const auto& [name, m] : mats.items()) {
            m_named[name] = build_material(m, ptr + "/" + escape_pointer_token(name));
        }
    }

    const Material* black_material() {
        if (!m_black) {
            m_builder.materials().push_back(
                std::make_unique<Material>(std::nullopt, std::nullopt, std::nullopt));
            m_black = m_builder.materials().back().get();
        }
        return m_black;
    }

    // --- transforms ----------------------------------------------------------------------------

    glm::dmat4 load_transform_step(const json& t, const std::string& ptr) const {
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

    glm::dmat4 load_transform(const json& t, const std::string& ptr) const {
        glm::dmat4 m(1.0);
        if (t.is_array()) {
            for (std::size_t i = 0; i < t.size(); ++i) {
                m = load_transform_step(t[i], ptr + "/" + std::to_string(i)) * m;
            }
        } else {
            m = load_transform_step(t, ptr);
        }
        double det = glm::determinant(glm::dmat3(m));
        if (!(std::fabs(det) > 1e-300) || !std::isfinite(det)) {
            fail(ptr, "the transform is singular (zero scale?) or not finite");
        }
        return m;
    }

    // --- shapes --------------------------------------------------------------------------------

    void load_shape(const json& s, const std::string& ptr, std::uint32_t index) {
        expect_object(s, ptr);
        std::string type = get_string(require(s, ptr, "type"), ptr + "/type");
        static const std::vector<std::string> kTypes = {"sphere", "plane", "box",       "quad",
                                                        "disc",   "mesh",  "icosphere", "grid"};
        auto it = std::find(kTypes.begin(), kTypes.end(), type);
        if (it == kTypes.end()) {
            std::string msg = "unknown shape type '" + type + "'";
            std::string g = closest_name(type, kTypes);
            if (!g.empty()) {
                msg += " (did you mean '" + g + "'?)";
            } else {
                msg += " (expected one of: sphere plane box quad disc mesh icosphere grid)";
            }
            fail(ptr + "/type", msg);
        }
        ShapeKind kind = ShapeKind(it - kTypes.begin());
        std::vector<const char*> keys = {"type",      "name",      "material",    "emission",
                                         "two_sided", "transform", "flip_normals"};
        switch (kind) {
            case ShapeKind::Sphere:
                keys.insert(keys.end(), {"center", "radius"});
                break;
            case ShapeKind::Plane:
                keys.insert(keys.end(), {"point", "normal"});
                break;
            case ShapeKind::Box:
                keys.insert(keys.end(), {"min", "max"});
                break;
            case ShapeKind::Quad:
                keys.insert(keys.end(), {"vertices"});
                break;
            case ShapeKind::Disc:
                keys.insert(keys.end(), {"center", "normal", "radius"});
                break;
            case ShapeKind::Mesh:
                keys.insert(keys.end(), {"positions", "indices", "normals", "file"});
                break;
            case ShapeKind::Icosphere:
                keys.insert(keys.end(), {"center", "radius", "subdivisions", "smooth"});
                break;
            case ShapeKind::Grid:
                keys.insert(keys.end(), {"nx", "ny", "amplitude", "frequency"});
                break;
        }
        check_keys_v(s, ptr, keys);
        if (s.contains("name")) get_string(s["name"], ptr + "/name");

        ShapeInfo info;
        info.kind = kind;
        if (s.contains("two_sided")) info.two_sided = get_bool(s["two_sided"], ptr + "/two_sided");
        bool flip_normals =
            s.contains("flip_normals") ? get_bool(s["flip_normals"], ptr + "/flip_normals") : false;
        if (s.contains("emission")) {
            info.emission = get_color(s["emission"], ptr + "/emission", "an emitted radiance");
        }
        bool emissive = max_component(info.emission) > 0.f;
        if (s.contains("material")) {
            const json& m = s["material"];
            if (m.is_string()) {
                std::string name = m.get<std::string>();
                auto found = m_named.find(name);
                if (found == m_named.end()) {
                    std::vector<std::string> names;
                    for (const auto& [n, _] : m_named) names.push_back(n);
                    std::string msg = "unknown material '" + name + "'";
                    std::string g = closest_name(name, names);
                    if (!g.empty()) {
                        msg += " (did you mean '" + g + "'?)";
                    } else if (names.empty()) {
                        msg += " (the scene defines no \"materials\")";
                    }
                    fail(ptr + "/material", msg);
                }
                info.material = found->second;
                info.material_name = name;
            } else if (m.is_object()) {
                info.material = build_material(m, ptr + "/material");
                info.material_name = "<inline>";
            } else {
                fail(ptr + "/material",
                     "expected a material name or an inline {\"model\": ...} object, got " +
                         type_name(m));
            }
        } else if (emissive) {
            info.material = black_material();
            info.material_name = "<black>";
        } else {
            fail(ptr, "missing required key 'material' (only emissive shapes may omit it)");
        }

        glm::dmat4 xf(1.0);
        if (s.contains("transform")) xf = load_transform(s["transform"], ptr + "/transform");
        glm::dmat3 lin(xf);
        glm::dmat3 normal_mat = glm::transpose(glm::inverse(lin));
        auto to_world = [&](const glm::dvec3& p) { return glm::dvec3(xf * glm::dvec4(p, 1.0)); };

        Scene::Impl& impl = m_builder.impl();
        std::vector<Light>& lights = m_builder.lights();
        Bounds3 bounds;
        auto grow = [&](const glm::dvec3& p) {
            bounds.lo = glm::min(bounds.lo, Vec3(p));
            bounds.hi = glm::max(bounds.hi, Vec3(p));
        };
        auto add_prim = [&](AnalyticPrim::Kind k, const glm::dmat4& local) {
            AnalyticPrim prim;
            prim.kind = k;
            prim.shape = index;
            prim.flip = flip_normals;
            prim.to_world = xf * local;
            prim.to_object = glm::inverse(prim.to_world);
            prim.normal_to_world = glm::transpose(glm::inverse(glm::dmat3(prim.to_world)));
            double zr = k == AnalyticPrim::Kind::Sphere ? 1.0 : 0.0;
            for (int i = 0; i < 8; ++i) {
                glm::dvec3 c(i & 1 ? 1.0 : -1.0, i & 2 ? 1.0 : -1.0, i & 4 ? zr : -zr);
                grow(glm::dvec3(prim.to_world * glm::dvec4(c, 1.0)));
            }
            impl.prims.push_back(prim);
            return impl.prims.back();
        };
        auto check_finite_bounds = [&]() {
            if (!is_finite(bounds.lo) || !is_finite(bounds.hi)) {
                fail(ptr, "the shape's extent overflows float (transform or size too large)");
            }
        };

        TriangleMesh mesh;
        bool is_mesh = false;
        Vec3 tangent(0.f);
        switch (kind) {
            case ShapeKind::Sphere:
            case ShapeKind::Disc: {
                Vec3 c = get_vec3(require(s, ptr, "center"), ptr + "/center");
                double r = get_number(require(s, ptr, "radius"), ptr + "/radius", 0.0,
                                      std::numeric_limits<float>::max(), "> 0");
                if (!(r > 0.0)) fail(ptr + "/radius", "must be > 0");
                glm::dmat4 local = glm::translate(glm::dmat4(1.0), glm::dvec3(c));
                if (kind == ShapeKind::Disc) {
                    Vec3 n = get_direction(require(s, ptr, "normal"), ptr + "/normal");
                    Frame f = Frame::from_z(n);
                    glm::dmat4 rot(1.0);
                    rot[0] = glm::dvec4(glm::dvec3(f.x), 0.0);
                    rot[1] = glm::dvec4(glm::dvec3(f.y), 0.0);
                    rot[2] = glm::dvec4(glm::dvec3(f.z), 0.0);
                    local = local * rot;
                }
                local = glm::scale(local, glm::dvec3(r));
                const AnalyticPrim& prim =
                    add_prim(kind == ShapeKind::Sphere ? AnalyticPrim::Kind::Sphere
                                                       : AnalyticPrim::Kind::Disc,
                             local);
                check_finite_bounds();
                if (emissive) {
                    glm::dmat3 L(prim.to_world);
                    Vec3 center(glm::dvec3(prim.to_world[3]));
                    if (kind == ShapeKind::Disc) {
                        info.light = std::int32_t(lights.size());
                        // cross(L e1, L e2) = det(L) L^-T z: swap the axes when that disagrees
                        // with the hit normal (mirroring transform XOR flip_normals).
                        bool swap = (glm::determinant(L) < 0.0) != flip_normals;
                        Vec3 e1(L[0]), e2(L[1]);
                        if (swap) std::swap(e1, e2);
                        lights.push_back(Light::area_disc(center, e1, e2, info.emission, index));
                    } else {
                        // Light sampling needs a true sphere: the transform must be a similarity.
                        double s2 = glm::dot(L[0], L[0]);
                        glm::dmat3 g = glm::transpose(L) * L;
                        for (int a = 0; a < 3; ++a) {
                            for (int b = 0; b < 3; ++b) {
                                if (std::fabs(g[a][b] - (a == b ? s2 : 0.0)) > 1e-6 * s2) {
                                    fail(ptr + "/emission",
                                         "an emissive sphere cannot be non-uniformly scaled or "
                                         "sheared (use an icosphere for an emissive ellipsoid)");
                                }
                            }
                        }
                        info.light = std::int32_t(lights.size());
                        lights.push_back(Light::area_sphere(center, float(std::sqrt(s2)),
                                                            info.emission, index, flip_normals));
                    }
                }
                break;
            }
            case ShapeKind::Plane: {
                if (emissive) {
                    fail(ptr + "/emission",
                         "an infinite plane cannot emit (infinite power); use "
                         "a quad or a disc");
                }
                Vec3 p = get_vec3(require(s, ptr, "point"), ptr + "/point");
                Vec3 n = get_direction(require(s, ptr, "normal"), ptr + "/normal");
                PlaneGeom pl;
                pl.shape = index;
                pl.point = to_world(glm::dvec3(p));
                pl.normal = glm::normalize(normal_mat * glm::dvec3(n));
                if (flip_normals) pl.normal = -pl.normal;
                pl.tangent = Vec3(glm::normalize(lin * glm::dvec3(Frame::from_z(n).x)));
                if (!is_finite(Vec3(pl.point)) || !is_finite(Vec3(pl.normal))) {
                    fail(ptr, "the transformed plane is not finite");
                }
                impl.planes.push_back(pl);
                break;
            }
            case ShapeKind::Box: {
                Vec3 lo = get_vec3(require(s, ptr, "min"), ptr + "/min");
                Vec3 hi = get_vec3(require(s, ptr, "max"), ptr + "/max");
                if (!(lo.x < hi.x && lo.y < hi.y && lo.z < hi.z)) {
                    fail(ptr + "/max", "must be greater than \"min\" on every axis");
                }
                mesh = make_box(lo, hi);
                tangent = Vec3(1.f, 0.f, 0.f);
                is_mesh = true;
                break;
            }
            case ShapeKind::Quad: {
                const json& v = require(s, ptr, "vertices");
                if (!v.is_array() || v.size() != 4) {
                    fail(
                        ptr + "/vertices",
                        "expected an array of 4 points, got " +
                            (v.is_array() ? std::to_string(v.size()) + " elements" : type_name(v)));
                }
                std::array<Vec3, 4> p;
                for (std::size_t i = 0; i < 4; ++i) {
                    p[i] = get_vec3(v[i], ptr + "/vertices/" + std::to_string(i));
                }
                mesh = make_quad(p);
                if (glm::length(glm::cross(p[1] - p[0], p[2] - p[0])) == 0.f ||
                    glm::length(glm::cross(p[2] - p[0], p[3] - p[0])) == 0.f) {
                    fail(ptr + "/vertices", "the quad is degenerate (collinear vertices)");
                }
                tangent = p[1] - p[0];
                is_mesh = true;
                break;
            }
            case ShapeKind::Mesh:
                mesh = load_mesh_shape(s, ptr);
                reserve_triangles(mesh.num_triangles(), ptr);
                is_mesh = true;
                break;
            case ShapeKind::Icosphere: {
                Vec3 c = get_vec3(require(s, ptr, "center"), ptr + "/center");
                double r = get_number(require(s, ptr, "radius"), ptr + "/radius", 0.0,
                                      std::numeric_limits<float>::max(), "> 0");
                if (!(r > 0.0)) fail(ptr + "/radius", "must be > 0");
                int sub = int(get_int(require(s, ptr, "subdivisions"), ptr + "/subdivisions", 0,
                                      kMaxIcosphereSubdivisions));
                bool smooth = s.contains("smooth") ? get_bool(s["smooth"], ptr + "/smooth") : true;
                reserve_triangles(20ull << (2 * sub), ptr + "/subdivisions");
                mesh = make_icosphere(sub, smooth);
                for (Vec3& p : mesh.positions) p = c + float(r) * p;
                is_mesh = true;
                break;
            }
            case ShapeKind::Grid: {
                std::int64_t nx = get_int(require(s, ptr, "nx"), ptr + "/nx", 1, 1 << 20);
                std::int64_t ny = get_int(require(s, ptr, "ny"), ptr + "/ny", 1, 1 << 20);
                if (nx * ny > kMaxGridCells) {
                    fail(ptr,
                         "grid too large: nx * ny must be <= " + std::to_string(kMaxGridCells));
                }
                double amp = s.contains("amplitude")
                                 ? get_number(s["amplitude"], ptr + "/amplitude", -1e6, 1e6,
                                              "in [-1e6, 1e6]")
                                 : 0.0;
                double freq =
                    s.contains("frequency")
                        ? get_number(s["frequency"], ptr + "/frequency", 0.0, 1e6, "in [0, 1e6]")
                        : 0.0;
                reserve_triangles(2ull * std::uint64_t(nx) * std::uint64_t(ny), ptr);
                mesh = make_grid(int(nx), int(ny), float(amp), float(freq));
                tangent = Vec3(1.f, 0.f, 0.f);
                is_mesh = true;
                break;
            }
        }

        if (is_mesh) {
            // A mirroring transform reverses the winding: undo it so the authored front stays
            // the front; "flip_normals" reverses it on purpose.
            bool flip = (glm::determinant(lin) < 0.0) != flip_normals;
            for (Vec3& p : mesh.positions) {
                p = Vec3(to_world(glm::dvec3(p)));
                grow(glm::dvec3(p));
            }
            for (Vec3& n : mesh.normals) {
                glm::dvec3 w = normal_mat * glm::dvec3(n);
                double l = glm::length(w);
                n = l > 0.0 ? Vec3(w / l) : Vec3(0.f, 0.f, 1.f);
            }
            if (flip) {
                for (std::size_t i = 0; i + 2 < mesh.indices.size(); i += 3) {
                    std::swap(mesh.indices[i + 1], mesh.indices[i + 2]);
                }
            }
            check_finite_bounds();
            if (std::string err = validate_mesh(mesh); !err.empty()) fail(ptr, err);
            info.triangles = mesh.num_triangles();
            if (emissive) {
                std::vector<Vec3> tri;
                tri.reserve(mesh.indices.size());
                for (std::uint32_t i : mesh.indices) tri.push_back(mesh.positions[i]);
                Light l = Light::area_triangles(std::move(tri), info.emission, index);
                if (!(l.area() > 0.f)) fail(ptr + "/emission", "the emitting shape has no area");
                info.light = std::int32_t(lights.size());
                lights.push_back(std::move(l));
            }
            MeshGeom g;
            g.shape = index;
            g.mesh = std::move(mesh);
            if (tangent != Vec3(0.f)) g.tangent = Vec3(lin * glm::dvec3(tangent));
            impl.meshes.push_back(std::move(g));
        }
        if (!bounds.empty()) {
            m_builder.bounds().lo = glm::min(m_builder.bounds().lo, bounds.lo);
            m_builder.bounds().hi = glm::max(m_builder.bounds().hi, bounds.hi);
        }
        m_shape_bounds.push_back(bounds);
        m_builder.shapes().push_back(info);
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

    TriangleMesh load_mesh_shape(const json& s, const std::string& ptr) {
        if (s.contains("file")) {
            for (const char* k : {"positions", "indices", "normals"}) {
                if (s.contains(k)) {
                    fail(ptr + "/" + k, "cannot be combined with \"file\" (give one or the other)");
                }
            }
            std::string file = get_string(s["file"], ptr + "/file");
            if (!m_limits.allow_files) fail(ptr + "/file", "mesh files are disabled here");
            std::filesystem::path p(file);
            if (p.is_relative()) p = std::filesystem::path(m_base) / p;
            std::string ext = p.extension().string();
            std::transform(ext.begin(), ext.end(), ext.begin(),
                           [](unsigned char c) { return char(std::tolower(c)); });
            try {
                if (ext == ".obj") return load_obj(p.string());
                if (ext == ".ply") return load_ply(p.string());
            } catch (const std::exception& e) {
                fail(ptr + "/file", e.what());
            }
            fail(ptr + "/file", "unsupported mesh file extension '" + ext + "' (use .obj or .ply)");
        }
        TriangleMesh m;
        const json& pos = require(s, ptr, "positions");
        const json& idx = require(s, ptr, "indices");
        auto read_vec3s = [&](const json& a, const std::string& p, std::vector<Vec3>& out) {
            if (!a.is_array() || a.size() % 3 != 0 || a.empty()) {
                fail(p, "expected a flat array of 3n numbers (x0, y0, z0, x1, ...)");
            }
            out.resize(a.size() / 3);
            for (std::size_t i = 0; i < a.size(); ++i) {
                double d = get_number(a[i], p + "/" + std::to_string(i));
                out[i / 3][int(i % 3)] = float(d);
            }
        };
        read_vec3s(pos, ptr + "/positions", m.positions);
        if (!idx.is_array() || idx.size() % 3 != 0 || idx.empty()) {
            fail(ptr + "/indices", "expected a flat array of 3n vertex indices");
        }
        m.indices.resize(idx.size());
        for (std::size_t i = 0; i < idx.size(); ++i) {
            std::string p = ptr + "/indices/" + std::to_string(i);
            m.indices[i] =
                std::uint32_t(get_int(idx[i], p, 0, std::int64_t(m.positions.size()) - 1));
        }
        if (s.contains("normals")) {
            read_vec3s(s["normals"], ptr + "/normals", m.normals);
            if (m.normals.size() != m.positions.size()) {
                fail(ptr + "/normals", "expected one normal per position (" +
                                           std::to_string(m.positions.size()) + "), got " +
                                           std::to_string(m.normals.size()));
            }
            for (Vec3& n : m.normals) {
                float l = glm::length(n);
                if (!(l > 0.f)) fail(ptr + "/normals", "contains a zero normal");
                n /= l;
            }
        }
        return m;
    }

    // --- lights --------------------------------------------------------------------------------

    void load_light(const json& l, const std::string& ptr) {
        expect_object(l, ptr);
        std::string type = get_string(require(l, ptr, "type"), ptr + "/type");
        std::vector<Light>& lights = m_builder.lights();
        if (type == "point") {
            check_keys(l, ptr, {"type", "position", "power"});
            Vec3 p = get_vec3(require(l, ptr, "position"), ptr + "/position");
            Rgb phi = get_color(require(l, ptr, "power"), ptr + "/power", "a power (W)");
            lights.push_back(Light::point(p, phi));
        } else if (type == "spot") {
            check_keys(l, ptr,
                       {"type", "position", "direction", "look_at", "power", "inner_angle",
                        "outer_angle"});
            Vec3 p = get_vec3(require(l, ptr, "position"), ptr + "/position");
            Vec3 dir;
            if (l.contains("direction") == l.contains("look_at")) {
                fail(ptr, "give exactly one of \"direction\" and \"look_at\"");
            }
            if (l.contains("direction")) {
                dir = get_direction(l["direction"], ptr + "/direction");
            } else {
                Vec3 at = get_vec3(l["look_at"], ptr + "/look_at");
                float len = glm::length(at - p);
                if (!(len > 0.f)) fail(ptr + "/look_at", "must differ from the position");
                dir = (at - p) / len;
            }
            Rgb phi = get_color(require(l, ptr, "power"), ptr + "/power", "a power (W)");
            double outer = get_number(require(l, ptr, "outer_angle"), ptr + "/outer_angle", 0.0,
                                      180.0, "in (0, 180) degrees (half-angle)");
            if (!(outer > 0.0 && outer < 180.0)) {
                fail(ptr + "/outer_angle", "must be in (0, 180) degrees (half-angle)");
            }
            double inner = l.contains("inner_angle")
                               ? get_number(l["inner_angle"], ptr + "/inner_angle", 0.0, outer,
                                            "in [0, outer_angle] degrees")
                               : outer;
            lights.push_back(Light::spot(p, dir, phi, float(inner), float(outer)));
        } else if (type == "directional") {
            check_keys(l, ptr, {"type", "direction", "irradiance"});
            Vec3 dir = get_direction(require(l, ptr, "direction"), ptr + "/direction");
            Rgb e = get_color(require(l, ptr, "irradiance"), ptr + "/irradiance",
                              "an irradiance (W/m^2)");
            lights.push_back(Light::directional(dir, e));
        } else if (type == "environment") {
            check_keys(l, ptr, {"type", "radiance"});
            if (m_builder.environment() >= 0) {
                fail(ptr, "only one environment light is allowed");
            }
            Rgb le = get_color(require(l, ptr, "radiance"), ptr + "/radiance", "a radiance");
            m_builder.environment() = std::int32_t(lights.size());
            lights.push_back(Light::environment(le));
        } else {
            std::vector<std::string> known = {"point", "spot", "directional", "environment"};
            std::string msg = "unknown light type '" + type + "'";
            std::string g = closest_name(type, known);
            if (!g.empty()) {
                msg += " (did you mean '" + g + "'?)";
            } else {
                msg +=
                    " (expected point, spot, directional or environment; area lights are "
                    "shapes with \"emission\")";
            }
            fail(ptr + "/type", msg);
        }
    }

    // --- analysis ------------------------------------------------------------------------------

    static bool reflects(const Material& m) {
        if (m.diffuse() && max_component(m.diffuse()->rho()) > 0.f) return true;
        if (m.glossy()) return true;
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
        for (int i = 0; i < 8; ++i) {
            Vec3 p(i & 1 ? b.hi.x : b.lo.x, i & 2 ? b.hi.y : b.lo.y, i & 4 ? b.hi.z : b.lo.z);
            Vec3 v = p - c.position;
            float z = glm::dot(v, c.forward), x = glm::dot(v, c.right), y = glm::dot(v, c.true_up);
            all_behind &= z <= 0.f;
            all_left &= x < -z * tx;
            all_right &= x > z * tx;
            all_below &= y < -z * ty;
            all_above &= y > z * ty;
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
            BxDFFlags fl = s.material->flags();
            f.lobes = f.lobes | fl;
            if (fl != BxDFFlags::Diffuse && fl != BxDFFlags::None) f.lambert_only = false;
            if (reflects(*s.material)) f.can_reflect = true;
            f.num_triangles += s.triangles;
            if (s.kind == ShapeKind::Sphere) ++f.num_spheres;
            if (s.kind == ShapeKind::Plane) ++f.num_planes;
            if (s.kind == ShapeKind::Disc) ++f.num_discs;
            if (s.light >= 0 && maybe_visible(m_shape_bounds[i])) f.emitter_visible = true;
        }
        f.has_diffuse = any(f.lobes & BxDFFlags::Diffuse);
        f.has_glossy = any(f.lobes & BxDFFlags::Glossy);
        f.has_specular = any(f.lobes & BxDFFlags::Specular);
        for (const Light& l : scene.lights()) {
            switch (l.kind()) {
                case Light::Kind::Point:
                    f.has_point = true;
                    break;
                case Light::Kind::Spot:
                    f.has_spot = true;
                    break;
                case Light::Kind::Directional:
                    f.has_directional = true;
                    break;
                case Light::Kind::Area:
                    f.has_area = true;
                    break;
                case Light::Kind::Environment:
                    f.has_environment = true;
                    f.emitter_visible = true;  // escaping camera rays see it
                    break;
            }
            if (!l.is_delta()) f.any_non_delta_light = true;
        }
        f.all_lights_delta = !f.any_non_delta_light;
    }

    // Counts triangles against the limit before they are generated.
    void reserve_triangles(std::uint64_t n, const std::string& ptr) {
        m_triangles += n;
        if (n > m_limits.max_triangles || m_triangles > m_limits.max_triangles) {
            fail(ptr, "the scene exceeds the limit of " + std::to_string(m_limits.max_triangles) +
                          " triangles");
        }
    }

    std::string m_name, m_base;
    SceneLimits m_limits;
    std::uint64_t m_triangles = 0;
    Scene::Builder m_builder;
    std::map<std::string, const Material*> m_named;
    const Material* m_black = nullptr;
    std::vector<Bounds3> m_shape_bounds;
};

}  // namespace

std::string SceneFeatures::describe() const {
    std::ostringstream s;
    auto yn = [](bool b) { return b ? "yes" : "no"; };
    s << "geometry: " << num_shapes << " shapes (" << num_triangles << " triangles, " << num_spheres
      << " exact spheres, " << num_discs << " discs, " << num_planes << " infinite planes), "
      << num_materials << " materials\n";
    s << "lobes: diffuse " << yn(has_diffuse) << ", glossy " << yn(has_glossy) << ", specular "
      << yn(has_specular) << (lambert_only ? " (Lambert only)" : "") << "\n";
    s << "lights: " << num_lights << " (point " << yn(has_point) << ", spot " << yn(has_spot)
      << ", directional " << yn(has_directional) << ", area " << yn(has_area) << ", environment "
      << yn(has_environment) << "); all delta: " << yn(all_lights_delta) << "\n";
    s << "emitter visible to the camera: " << yn(emitter_visible)
      << "; surfaces reflect (indirect light possible): " << yn(can_reflect) << "\n";
    return s.str();
}

Scene load_scene_from_string(const std::string& json_text, const std::string& name_for_errors,
                             const std::string& base_dir, const SceneLimits& limits) {
    Loader loader(name_for_errors, base_dir, limits);
    return loader.load(json_text);
}

Scene load_scene(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw SceneError(path + ": cannot open the scene file");
    std::ostringstream ss;
    ss << in.rdbuf();
    if (in.bad()) throw SceneError(path + ": cannot read the scene file");
    std::string base = std::filesystem::path(path).parent_path().string();
    return load_scene_from_string(ss.str(), path, base.empty() ? "." : base);
}

}  // namespace facet::render
