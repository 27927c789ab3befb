// `facet export-pov scene.json -o scene.pov [--area-grid N] [--glossy-samples N]
//  [--environment error|background] [--radiosity off|low|medium|high|C,E,R] [--ini scene.ini]`
//
// Writes POV-Ray 3.7 SDL for povray-facet (the patched POV-Ray of povray_patch/) that renders
// the picture `facet render --integrator direct` renders of the same JSON (README, "POV-Ray").
// With --radiosity it adds POV-Ray's radiosity (an interpolated, biased estimate of the indirect
// light that `--integrator path` computes).
// Everything the SDL cannot express exactly is an error naming the JSON pointer, except what
// an option asks to approximate. Decisions (the why is in the README):
//  - camera: explicit location/right/up/direction vectors in Facet's world coordinates, with
//    pixel centres as Facet's (scenes/FORMAT.md);
//  - `assumed_gamma 1.0`, `max_trace_level` = max_depth + 1 (the camera ray is level 0, so
//    max_depth mirror bounces are traced as Facet's direct integrator does), `adc_bailout 0`
//    (no ray dropped for low weight), no ambient; render with antialiasing off and EXR output;
//  - lights in povray-facet's `physical_falloff` (exact 1/d^2), colours from
//    facet/render/light_units.h;
//  - emitters (quads, meshes, discs with `emission`): the visible surface glows with `emission`
//    and casts no shadow, and its light is a set of cos-weighted spotlights, one per cell of a
//    midpoint (centroid) quadrature of the emitter, each with its own shadow ray. Not
//    POV-Ray's `area_light`: that shades an area light with the average visibility of the grid
//    times the average unshadowed shading (trace.cpp ComputeFullAreaDiffuseLight), puts its
//    points on the edges of the light, and its points are isotropic, where a Lambertian
//    emitter's intensity falls off as cos(theta);
//  - materials: `finish { brdf { ... } }` with the core's model and parameter names; the pigment
//    carries the diffuse reflectance (the patch's tinting rule), `samples` (glossy reflection
//    rays) is 0 unless --glossy-samples says otherwise, since the direct integrator traces
//    none;
//  - --radiosity: a `radiosity {}` block (count, error_bound, recursion_limit from the option,
//    the rest fixed below); emitters are then `no_radiosity` with a black twin that only
//    radiosity rays see, because their light is already counted by the cell lights (a
//    radiosity ray that saw the emission would count it twice), as the path tracer's light
//    sampling with MIS counts it once.
#include <fmt/format.h>
#include <CLI/CLI.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "commands.h"
#include "facet/registry.h"
#include "facet/render/light_units.h"
#include "facet/render/mesh.h"
#include "facet/render/scene_description.h"

namespace facet::cli {

namespace {

using render::LightDesc;
using render::LightKind;
using render::MaterialDesc;
using render::SceneDescription;
using render::ShapeDesc;
using render::TriangleMesh;

struct ExportPovOptions {
    std::string scene;
    std::string output;
    std::string ini;
    int area_grid = 8;
    int glossy_samples = 0;
    std::string environment = "error";
    std::string radiosity = "off";
};

// POV-Ray radiosity settings of --radiosity (README, "facet export-pov").
struct RadiosityPreset {
    int count = 0;  // 0: off
    double error_bound = 0.0;
    int recursion_limit = 0;
};

// --radiosity: "off", a preset, or "COUNT,ERROR_BOUND,RECURSION_LIMIT". Ranges: POV-Ray's
// (recursion_limit 1-20, RadiosityFunction::DEPTH_MAX; count at most the 1600 precomputed
// directions, RADIOSITY_MAX_SAMPLE_DIRECTIONS) and an error_bound in (0, 10].
RadiosityPreset parse_radiosity(const std::string& text) {
    if (text == "off") return {};
    if (text == "low") return {50, 1.0, 4};
    if (text == "medium") return {200, 0.4, 8};
    if (text == "high") return {800, 0.15, 16};
    const std::string usage =
        "--radiosity: expected off, low, medium, high or COUNT,ERROR_BOUND,RECURSION_LIMIT "
        "(e.g. 200,0.4,8), got '" +
        text + "'";
    RadiosityPreset r;
    char c1 = 0, c2 = 0, extra = 0;
    std::istringstream in(text);
    if (!(in >> r.count >> c1 >> r.error_bound >> c2 >> r.recursion_limit) || c1 != ',' ||
        c2 != ',' || (in >> extra))
        throw std::runtime_error("export-pov: " + usage);
    if (r.count < 1 || r.count > 1600)
        throw std::runtime_error(
            fmt::format("export-pov: --radiosity: count must be in [1, 1600] (got {})", r.count));
    if (!(r.error_bound > 0.0 && r.error_bound <= 10.0))
        throw std::runtime_error(fmt::format(
            "export-pov: --radiosity: error_bound must be in (0, 10] (got {})", r.error_bound));
    if (r.recursion_limit < 1 || r.recursion_limit > 20)
        throw std::runtime_error(
            fmt::format("export-pov: --radiosity: recursion_limit must be in [1, 20] (got {})",
                        r.recursion_limit));
    return r;
}

// Light cells beyond this make a scene POV-Ray shades very slowly (every cell is a light with a
// shadow ray at every shaded point): an error that names the emitter and the option.
constexpr long long kMaxLightCells = 20000;

// An error of the export: "<file>: <pointer>: <message>".
struct ExportError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

// Shortest text that reads back as the same double.
std::string num(double v) {
    if (v == 0.0) return "0";
    return fmt::format("{}", v);
}
std::string vec(const glm::dvec3& v) {
    return "<" + num(v.x) + ", " + num(v.y) + ", " + num(v.z) + ">";
}
std::string rgb(const glm::dvec3& c) {
    return "rgb " + vec(c);
}

class PovWriter {
  public:
    PovWriter(const SceneDescription& desc, std::string file, const ExportPovOptions& opt)
        : m_desc(desc),
          m_file(std::move(file)),
          m_opt(opt),
          m_rad(parse_radiosity(opt.radiosity)) {}

    std::string write();

  private:
    [[noreturn]] void fail(const std::string& pointer, const std::string& message) const {
        throw ExportError(m_file + ": " + pointer + ": " + message);
    }
    void camera();
    void global_settings();
    std::string texture(const MaterialDesc& m, const std::string& pointer,
                        const glm::dvec3& emission = glm::dvec3(0.0));
    void materials();
    std::string shape_texture(const ShapeDesc& s, const std::string& pointer, bool inside_front);
    void shape(const ShapeDesc& s, std::size_t index);
    void emitter_lights(const ShapeDesc& s, const std::string& pointer,
                        const TriangleMesh* world_mesh);
    void light(const LightDesc& l, std::size_t index);
    void cell_light(const glm::dvec3& p, const glm::dvec3& n, const glm::dvec3& radiance,
                    double area);
    TriangleMesh mesh_of(const ShapeDesc& s, const std::string& pointer) const;

    const SceneDescription& m_desc;
    std::string m_file;
    const ExportPovOptions& m_opt;
    RadiosityPreset m_rad;
    std::ostringstream m_out;
    std::vector<std::string> m_material_ids;  // POV identifier of m_desc.materials[i]
    long long m_cells = 0;
};

glm::dvec3 d3(const Vec3& v) {
    return glm::dvec3(v);
}

// Free text (shape and material names, the file name) for a `//` comment of the SDL: control
// characters become spaces, so that a newline in a name cannot end the comment.
std::string comment_text(std::string text) {
    for (char& c : text)
        if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) c = ' ';
    return text;
}

void PovWriter::camera() {
    // scenes/FORMAT.md, "POV-Ray export": explicit vectors; POV-Ray 3.7 traces the pixel
    // centres itself (TracePixel::CreateCameraRay adds the half pixel).
    const render::CameraDesc& c = m_desc.camera;
    const glm::dvec3 pos = d3(c.position);
    const glm::dvec3 f = glm::normalize(d3(c.look_at) - pos);
    const glm::dvec3 r = glm::normalize(glm::cross(f, d3(c.up)));
    const glm::dvec3 u = glm::cross(r, f);
    const double tan_y = std::tan(0.5 * c.fov * kPiD / 180.0);
    const double tan_x = tan_y * double(c.width) / double(c.height);
    m_out << "// Facet pinhole camera (scenes/FORMAT.md): explicit vectors, pixel centres.\n"
          << "camera {\n  perspective\n"
          << "  location  " << vec(pos) << "\n"
          << "  right     " << vec(2.0 * tan_x * r) << "\n"
          << "  up        " << vec(2.0 * tan_y * u) << "\n"
          << "  direction " << vec(f) << "\n}\n\n";
}

void PovWriter::global_settings() {
    // Mirror bounces are the only recursion of the direct integrator: without a mirror lobe
    // the depth changes nothing, and a deeper limit than POV-Ray's is no error.
    bool mirrors = false;
    auto has_mirror = [](const MaterialDesc& m) {
        return make_material(m.model, m.params).mirror().has_value();
    };
    for (const auto& [name, m] : m_desc.materials) mirrors = mirrors || has_mirror(m);
    for (const ShapeDesc& s : m_desc.shapes)
        if (s.material) mirrors = mirrors || has_mirror(*s.material);
    const int depth = mirrors ? m_desc.render.max_depth : std::min(m_desc.render.max_depth, 255);
    if (depth + 1 > 256)
        fail("/render/max_depth", fmt::format("{} bounces: POV-Ray traces at most 255 (its "
                                              "max_trace_level is at most 256)",
                                              depth));
    // Radiosity sample rays of recursion depth d (0-based) are traced at trace level
    // int(1.5 (d + 1)) (lighting/radiosity.cpp GetRecursionSettings): the limit must let the
    // deepest through, or the last bounces are cut.
    const int rad_level = m_rad.count > 0 ? int(1.5 * m_rad.recursion_limit) + 1 : 0;
    const int level = std::max(depth + 1, rad_level);
    m_out << "global_settings {\n"
          << "  assumed_gamma 1.0\n"
          << "  max_trace_level " << level << "  // camera ray + max_depth " << depth
          << " mirror bounces" << (level > depth + 1 ? "; radiosity recursion needs more" : "")
          << "\n"
          << "  adc_bailout 0\n"
          << "  ambient_light 0\n";
    if (m_rad.count > 0) {
        // count/error_bound/recursion_limit from --radiosity; the rest fixed: nearest_count
        // 10 (POV-Ray's default 5 is blotchier), POV-Ray's pretrace defaults, no brightness
        // or gray change, and an adc_bailout far below the weight POV-Ray assumes for the
        // deepest bounce (0.5^20 ~ 1e-6), so that no recursion level is dropped for weight.
        m_out << "  radiosity {  // --radiosity " << m_opt.radiosity << "\n"
              << "    count " << m_rad.count << "\n"
              << "    error_bound " << num(m_rad.error_bound) << "\n"
              << "    recursion_limit " << m_rad.recursion_limit << "\n"
              << "    nearest_count 10\n"
              << "    low_error_factor 0.5\n"
              << "    pretrace_start 0.08\n"
              << "    pretrace_end 0.04\n"
              << "    brightness 1\n"
              << "    gray_threshold 0\n"
              << "    adc_bailout 1e-7\n"
              << "    normal off\n"
              << "    media off\n"
              << "  }\n";
    }
    m_out << "}\n\n";
}

// " emission rgb <...>" giving the radiance `emission` on a surface of that pigment: POV-Ray
// multiplies `emission` by the pigment (trace.cpp ComputeLightedTexture), so it is divided
// here. "" when there is no emission.
std::string emission_of(const glm::dvec3& emission, const glm::dvec3& pigment,
                        const std::string& pointer, const std::string& file) {
    if (!(std::max({emission.x, emission.y, emission.z}) > 0.0)) return "";
    glm::dvec3 e(0.0);
    for (int c = 0; c < 3; ++c) {
        if (emission[c] == 0.0) continue;
        if (!(pigment[c] > 0.0))
            throw ExportError(file + ": " + pointer +
                              ": an emitter whose diffuse reflectance is 0 in a channel it emits "
                              "cannot be written (POV-Ray tints emission by the pigment)");
        e[c] = emission[c] / pigment[c];
    }
    return " emission " + rgb(e);
}

// `texture { pigment {...} finish { ambient 0 brdf { ... } } }` for a material. The pigment is
// the diffuse reflectance (lambert's reflectance, composite's diffuse_reflectance, with the
// core's default when not given), which povray-facet multiplies into the diffuse lobe; the
// other parameters go into the brdf block under their core names.
std::string PovWriter::texture(const MaterialDesc& m, const std::string& pointer,
                               const glm::dvec3& emission) {
    const ModelInfo* info = find_model(m.model);
    if (!info) fail(pointer + "/model", "unknown model '" + m.model + "'");
    const std::string diffuse_param = m.model == "lambert"     ? "reflectance"
                                      : m.model == "composite" ? "diffuse_reflectance"
                                                               : "";
    glm::dvec3 pigment(1.0);
    if (!diffuse_param.empty()) {
        auto it = m.params.values().find(diffuse_param);
        if (it != m.params.values().end()) {
            if (const double* d = std::get_if<double>(&it->second))
                pigment = glm::dvec3(*d);
            else if (const Rgb* c = std::get_if<Rgb>(&it->second))
                pigment = d3(*c);
        } else {
            for (const ParamInfo& p : info->params)
                if (p.name == diffuse_param) pigment = glm::dvec3(std::stod(p.default_value));
        }
    }
    std::string brdf = m.model;
    for (const auto& [name, value] : m.params.values()) {
        if (name == diffuse_param) continue;
        if (name == "alpha_u" || name == "alpha_v" || name == "exponent_u" || name == "exponent_v")
            fail(pointer + "/" + name,
                 "anisotropic lobes need a surface tangent, which POV-Ray does not provide "
                 "(povray-facet would orient the lobe by an arbitrary frame)");
        brdf += " " + name + " ";
        if (const double* d = std::get_if<double>(&value))
            brdf += num(*d);
        else if (const Rgb* c = std::get_if<Rgb>(&value))
            brdf += rgb(d3(*c));
        else if (const std::string* s = std::get_if<std::string>(&value))
            brdf += *s;
        else
            brdf += std::get<bool>(value) ? "on" : "off";
    }
    const bool glossy =
        m.model == "ggx" || m.model == "beckmann" || m.model == "blinn" || m.model == "composite";
    if (glossy) brdf += " samples " + std::to_string(m_opt.glossy_samples);
    return "texture { pigment { " + rgb(pigment) + " } finish { ambient 0" +
           emission_of(emission, pigment, pointer, m_file) + " brdf { " + brdf + " } } }";
}

void PovWriter::materials() {
    if (m_desc.materials.empty()) return;
    m_out << "// Materials (\"materials\" of the JSON), as povray-facet brdf finishes.\n";
    for (std::size_t i = 0; i < m_desc.materials.size(); ++i) {
        const auto& [name, m] = m_desc.materials[i];
        const std::string id = "Facet_material_" + std::to_string(i);
        m_out << "#declare " << id << " =  // '" << comment_text(name) << "'\n  "
              << texture(m, "/materials/" + name) << ";\n";
        m_material_ids.push_back(id);
    }
    m_out << "\n";
}

// The texture of a shape (front side), and its interior_texture when the back differs: the
// back of a one-sided shape is black, the back of an emitter does not emit (Facet's emission
// is one-sided).
// inside_front: the front is POV-Ray's inside (a flipped sphere or box), so the two are swapped.
std::string PovWriter::shape_texture(const ShapeDesc& s, const std::string& pointer,
                                     bool inside_front) {
    const MaterialDesc* m = s.material ? &*s.material : nullptr;
    std::string mpointer = pointer + "/material";
    if (!m && !s.material_ref.empty()) {
        for (std::size_t i = 0; i < m_desc.materials.size(); ++i)
            if (m_desc.materials[i].first == s.material_ref) {
                m = &m_desc.materials[i].second;
                mpointer = "/materials/" + s.material_ref;
            }
        if (!m) fail(pointer + "/material", "unknown material '" + s.material_ref + "'");
    }
    const glm::dvec3 le = d3(s.emission);
    const bool emits = std::max({le.x, le.y, le.z}) > 0.0;
    const std::string black = "texture { pigment { rgb 0 } finish { ambient 0 diffuse 0 } }";
    auto tex = [&](const glm::dvec3& e) {
        if (m && e == glm::dvec3(0.0) && !s.material)
            for (std::size_t i = 0; i < m_desc.materials.size(); ++i)
                if (m_desc.materials[i].first == s.material_ref)
                    return "texture { " + m_material_ids[i] + " }";
        if (m) return texture(*m, mpointer, e);
        if (!emits || e == glm::dvec3(0.0)) return black;
        return "texture { pigment { rgb 1 } finish { ambient 0 diffuse 0" +
               emission_of(e, glm::dvec3(1.0), pointer, m_file) + " } }";
    };
    std::string front = tex(le);
    std::string back = s.two_sided ? tex(glm::dvec3(0.0)) : black;
    if (inside_front) std::swap(front, back);
    if (!emits && s.two_sided) return front;
    // interior_texture takes the body of a texture: strip "texture { ... }".
    return front + "\n  interior_texture { " + back.substr(10, back.size() - 12) + " }";
}

TriangleMesh PovWriter::mesh_of(const ShapeDesc& s, const std::string& pointer) const {
    TriangleMesh m;
    switch (s.kind) {
        case render::ShapeKind::Box:
            return render::make_box(s.min, s.max);
        case render::ShapeKind::Quad:
            return render::make_quad(s.vertices);
        case render::ShapeKind::Icosphere:
            m = render::make_icosphere(s.subdivisions, s.smooth);
            for (Vec3& p : m.positions) p = s.center + float(s.radius) * p;
            return m;
        case render::ShapeKind::Grid:
            return render::make_grid(s.nx, s.ny, float(s.amplitude), float(s.frequency));
        case render::ShapeKind::Mesh:
            if (!s.file.empty()) {
                std::string path = s.file;
                if (path.front() != '/') path = m_desc.base_dir + "/" + path;
                const auto dot = path.find_last_of('.');
                std::string ext = dot == std::string::npos ? "" : path.substr(dot);
                std::transform(ext.begin(), ext.end(), ext.begin(),
                               [](unsigned char c) { return char(std::tolower(c)); });
                try {
                    return ext == ".ply" ? render::load_ply(path) : render::load_obj(path);
                } catch (const std::exception& e) {
                    fail(pointer + "/file", e.what());
                }
            }
            for (std::size_t i = 0; i + 2 < s.mesh.positions.size(); i += 3)
                m.positions.emplace_back(s.mesh.positions[i], s.mesh.positions[i + 1],
                                         s.mesh.positions[i + 2]);
            for (std::size_t i = 0; i + 2 < s.mesh.normals.size(); i += 3)
                m.normals.emplace_back(s.mesh.normals[i], s.mesh.normals[i + 1],
                                       s.mesh.normals[i + 2]);
            m.indices.assign(s.mesh.indices.begin(), s.mesh.indices.end());
            return m;
        default:
            return m;
    }
}

// POV-Ray `matrix`: rows are the images of x, y, z and the translation (row vectors).
std::string pov_matrix(const glm::dmat4& m) {
    std::string s = "matrix <";
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 3; ++r) s += num(m[c][r]) + (c == 3 && r == 2 ? ">" : ", ");
    return s;
}

// One light cell of an emitter: a spotlight at p aimed along the front normal n whose intensity
// falls off as cos(theta) (tightness 1, hard edge at 90 degrees: Attenuate_Light in POV-Ray's
// lighting/point.cpp gives pow(cos, tightness) for cos > 0 and 0 behind), with the on-axis
// intensity of a Lambertian patch of the cell's area.
void PovWriter::cell_light(const glm::dvec3& p, const glm::dvec3& n, const glm::dvec3& radiance,
                           double area) {
    const glm::dvec3 c = render::pov_light_colour(render::emitter_intensity(radiance, area));
    m_out << "light_source { " << vec(p) << " " << rgb(c) << " spotlight point_at " << vec(p + n)
          << " radius 90 falloff 90 tightness 1 physical_falloff }\n";
    ++m_cells;
}

// The light of an emissive shape: a midpoint quadrature of its surface, N = --area-grid:
// parallelogram quads N x N cells, other triangles N^2 similar sub-triangles (their centroids),
// discs N equal-area rings x 4N sectors. `world_mesh`: the shape's triangles in world space
// with their front winding, or null for a disc.
void PovWriter::emitter_lights(const ShapeDesc& s, const std::string& pointer,
                               const TriangleMesh* world_mesh) {
    const int n = m_opt.area_grid;
    const glm::dvec3 le = d3(s.emission);
    m_out << "// Light of the emitter " << pointer
          << (s.name.empty() ? "" : " ('" + comment_text(s.name) + "')")
          << ": midpoint cells, grid " << n << "\n";
    const glm::dmat4 xf = s.transform.value_or(glm::dmat4(1.0));
    if (!world_mesh) {  // disc
        const glm::dvec3 nn = glm::normalize(d3(s.normal));
        const Frame fr = Frame::from_z(Vec3(nn));
        const glm::dvec3 ex(fr.x), ey(fr.y);
        const glm::dmat3 lin(xf);
        const glm::dmat3 nmat = glm::transpose(glm::inverse(lin));
        glm::dvec3 nw = nmat * nn;
        // Area scale of the plane under the transform: |det| |M^-T n|.
        const double area_scale = std::fabs(glm::determinant(lin)) * glm::length(nw);
        nw = glm::normalize(nw) * (s.flip_normals ? -1.0 : 1.0);
        const int sectors = 4 * n;
        const double cell_area = kPiD * s.radius * s.radius * area_scale / double(n * sectors);
        for (int i = 0; i < n; ++i) {
            const double r = s.radius * std::sqrt((i + 0.5) / n);
            for (int j = 0; j < sectors; ++j) {
                const double phi = 2.0 * kPiD * (j + 0.5) / sectors;
                const glm::dvec3 local =
                    d3(s.center) + r * (std::cos(phi) * ex + std::sin(phi) * ey);
                cell_light(glm::dvec3(xf * glm::dvec4(local, 1.0)), nw, le, cell_area);
            }
        }
        return;
    }
    const TriangleMesh& m = *world_mesh;
    auto P = [&](std::uint32_t i) { return d3(m.positions[i]); };
    // A quad that is a flat parallelogram: one N x N grid over it.
    if (s.kind == render::ShapeKind::Quad && m.num_triangles() == 2) {
        const glm::dvec3 p0 = P(m.indices[0]), p1 = P(m.indices[1]), p2 = P(m.indices[2]);
        const glm::dvec3 p3 = P(m.indices[5]);
        const glm::dvec3 e1 = p1 - p0, e2 = p3 - p0;
        const glm::dvec3 cr = glm::cross(p1 - p0, p2 - p0);
        const double scale = glm::length(e1) + glm::length(e2);
        if (glm::length(p0 + p2 - p1 - p3) <= 1e-9 * scale) {
            const double area = glm::length(glm::cross(e1, e2));
            const glm::dvec3 nw = glm::normalize(cr);
            for (int i = 0; i < n; ++i)
                for (int j = 0; j < n; ++j)
                    cell_light(p0 + ((i + 0.5) / n) * e1 + ((j + 0.5) / n) * e2, nw, le,
                               area / double(n * n));
            return;
        }
    }
    for (std::size_t t = 0; t < m.num_triangles(); ++t) {
        const glm::dvec3 p0 = P(m.indices[3 * t]), p1 = P(m.indices[3 * t + 1]),
                         p2 = P(m.indices[3 * t + 2]);
        const glm::dvec3 cr = glm::cross(p1 - p0, p2 - p0);
        const double area = 0.5 * glm::length(cr);
        if (!(area > 0.0)) continue;  // dropped by the renderer too
        const glm::dvec3 nw = cr / (2.0 * area);
        const glm::dvec3 e1 = p1 - p0, e2 = p2 - p0;
        const double cell = area / double(n * n);
        for (int i = 0; i < n; ++i) {
            for (int j = 0; i + j < n; ++j) {
                // Upright sub-triangle (i, j), (i+1, j), (i, j+1): centroid (3i+1, 3j+1)/3N.
                cell_light(p0 + ((3 * i + 1) / (3.0 * n)) * e1 + ((3 * j + 1) / (3.0 * n)) * e2, nw,
                           le, cell);
                // Inverted one (i+1, j), (i, j+1), (i+1, j+1): centroid (3i+2, 3j+2)/3N.
                if (i + j + 2 <= n)
                    cell_light(p0 + ((3 * i + 2) / (3.0 * n)) * e1 + ((3 * j + 2) / (3.0 * n)) * e2,
                               nw, le, cell);
            }
        }
    }
}

void PovWriter::shape(const ShapeDesc& s, std::size_t index) {
    const std::string pointer = "/shapes/" + std::to_string(index);
    const std::string where = pointer + (s.name.empty() ? "" : " ('" + comment_text(s.name) + "')");
    const bool emits = std::max({s.emission.r, s.emission.g, s.emission.b}) > 0.f;
    // The front side: outside of spheres and boxes, the normal side of planes and discs
    // (POV-Ray's inside is the side opposite the normal); flip_normals reverses it.
    const std::string tex = shape_texture(s, pointer,
                                          s.flip_normals && (s.kind == render::ShapeKind::Sphere ||
                                                             s.kind == render::ShapeKind::Box));
    const double nsign = s.flip_normals ? -1.0 : 1.0;
    const std::string xf = s.transform ? "  " + pov_matrix(*s.transform) + "\n" : "";
    const bool twin = emits && m_rad.count > 0;
    const std::string tail =
        std::string(emits ? "  no_shadow\n" : "") + (twin ? "  no_radiosity\n" : "") + xf + "}\n";
    // With radiosity, an emitter's black twin: seen by radiosity rays only (its light is
    // counted by the cell lights), blocking them as the emitter would.
    const std::string twin_texture =
        "  texture { pigment { rgb 0 } finish { ambient 0 diffuse 0 } }\n  no_image "
        "no_reflection no_shadow\n";
    m_out << "// " << where << "\n";
    switch (s.kind) {
        case render::ShapeKind::Sphere:
            if (emits)
                fail(pointer + "/emission",
                     "an emissive sphere has no exact POV-Ray light (only quads, meshes and "
                     "discs are exported as emitters)");
            m_out << "sphere { " << vec(d3(s.center)) << ", " << num(s.radius) << "\n  " << tex
                  << "\n"
                  << tail;
            return;
        case render::ShapeKind::Plane: {
            const glm::dvec3 n = nsign * glm::normalize(d3(s.normal));
            m_out << "plane { " << vec(n) << ", " << num(glm::dot(n, d3(s.point))) << "\n  " << tex
                  << "\n"
                  << tail;
            return;
        }
        case render::ShapeKind::Disc: {
            const std::string disc = "disc { " + vec(d3(s.center)) + ", " +
                                     vec(nsign * glm::normalize(d3(s.normal))) + ", " +
                                     num(s.radius) + "\n";
            m_out << disc << "  " << tex << "\n" << tail;
            if (twin) m_out << disc << twin_texture << xf << "}\n";
            if (emits) emitter_lights(s, pointer, nullptr);
            return;
        }
        case render::ShapeKind::Box:
            if (!emits) {
                m_out << "box { " << vec(d3(s.min)) << ", " << vec(d3(s.max)) << "\n  " << tex
                      << "\n"
                      << tail;
                return;
            }
            break;  // an emissive box: its triangles, below
        default:
            break;
    }
    // Triangle shapes as mesh2: the renderer's own triangles, in world space as build_scene
    // makes them (positions transformed in double and stored as float, normals by the inverse
    // transpose and normalised per vertex, then interpolated), so that smooth shading under a
    // non-uniform scale agrees too (POV-Ray would interpolate object-space normals and transform
    // the result). A mirroring transform keeps the authored front side, flip_normals reverses it.
    TriangleMesh m = mesh_of(s, pointer);
    const glm::dmat4 x = s.transform.value_or(glm::dmat4(1.0));
    const glm::dmat3 lin(x);
    const glm::dmat3 nmat = glm::transpose(glm::inverse(lin));
    for (Vec3& p : m.positions) p = Vec3(glm::dvec3(x * glm::dvec4(d3(p), 1.0)));
    for (Vec3& nn : m.normals) {
        const glm::dvec3 w = nmat * d3(nn);
        const double l = glm::length(w);
        nn = l > 0.0 ? Vec3(w / l) : Vec3(0.f, 0.f, 1.f);
    }
    if ((glm::determinant(lin) < 0.0) != s.flip_normals)
        for (std::size_t i = 0; i + 2 < m.indices.size(); i += 3)
            std::swap(m.indices[i + 1], m.indices[i + 2]);
    std::ostringstream body;
    body << "mesh2 {\n  vertex_vectors { " << m.positions.size();
    for (const Vec3& p : m.positions) body << ", " << vec(d3(p));
    body << " }\n";
    if (!m.normals.empty()) {
        body << "  normal_vectors { " << m.normals.size();
        for (const Vec3& nn : m.normals) body << ", " << vec(d3(nn));
        body << " }\n";
    }
    // POV-Ray's triangle normal is (p0 - p1) x (p2 - p1) = -(p1 - p0) x (p2 - p0), the reverse
    // of Facet's front (mesh.h), and its interior_texture is on the side that normal points
    // away from: write each triangle as (p0, p2, p1) so that both agree.
    body << "  face_indices { " << m.num_triangles();
    for (std::size_t t = 0; t < m.num_triangles(); ++t)
        body << ", <" << m.indices[3 * t] << ", " << m.indices[3 * t + 2] << ", "
             << m.indices[3 * t + 1] << ">";
    body << " }\n";
    m_out << body.str() << "  " << tex << "\n"
          << (emits ? "  no_shadow\n" : "") << (twin ? "  no_radiosity\n" : "") << "}\n";
    if (twin) m_out << body.str() << twin_texture << "}\n";
    if (emits) emitter_lights(s, pointer, &m);
}

void PovWriter::light(const LightDesc& l, std::size_t index) {
    const std::string pointer = "/lights/" + std::to_string(index);
    switch (l.kind) {
        case LightKind::Point: {
            const glm::dvec3 c = render::pov_light_colour(render::point_intensity(d3(l.power)));
            m_out << "light_source { " << vec(d3(l.position)) << " " << rgb(c)
                  << " physical_falloff }  // " << pointer << ": point, power " << vec(d3(l.power))
                  << " W\n";
            return;
        }
        case LightKind::Spot: {
            const double outer = l.outer_angle;
            const double inner = l.inner_angle.value_or(outer);
            if (inner != outer)
                fail(pointer + "/inner_angle",
                     "POV-Ray's spotlight fades with a smoothstep in cos(theta), Facet's "
                     "linearly: only inner_angle = outer_angle (a hard edge) is exported exactly");
            if (outer > 90.0)
                fail(pointer + "/outer_angle",
                     "POV-Ray's spotlight lights only the front hemisphere: outer_angle must be "
                     "<= 90");
            const glm::dvec3 dir = l.direction ? d3(*l.direction) : d3(*l.look_at) - d3(l.position);
            const glm::dvec3 c =
                render::pov_light_colour(render::spot_intensity(d3(l.power), inner, outer));
            m_out << "light_source { " << vec(d3(l.position)) << " " << rgb(c)
                  << " spotlight point_at " << vec(d3(l.position) + glm::normalize(dir))
                  << " radius " << num(outer) << " falloff " << num(outer)
                  << " tightness 0 physical_falloff }  // " << pointer << "\n";
            return;
        }
        case LightKind::Directional: {
            // A parallel light lights only what lies in front of the plane through its
            // location: put it far beyond the scene.
            const glm::dvec3 dir = glm::normalize(d3(*l.direction));
            const glm::dvec3 far = -1e9 * dir;
            const glm::dvec3 c = render::pov_parallel_colour(d3(l.irradiance));
            m_out << "light_source { " << vec(far) << " " << rgb(c)
                  << " parallel point_at <0, 0, 0> }"
                  << "  // " << pointer << ": directional, irradiance " << vec(d3(l.irradiance))
                  << " W/m^2\n";
            return;
        }
        case LightKind::Environment:
            if (m_opt.environment == "background") {
                m_out << "background { " << rgb(d3(l.radiance)) << " }  // " << pointer
                      << ": environment, seen by camera and mirror rays only (approximation: "
                         "it lights no surface)\n";
                return;
            }
            fail(pointer,
                 "an environment light lights every surface from every unoccluded direction, "
                 "which POV-Ray cannot express exactly (radiosity only approximates it); "
                 "--environment background exports it as the background only");
    }
}

std::string PovWriter::write() {
    const render::CameraDesc& c = m_desc.camera;
    m_out << "// Exported by `facet export-pov` from " << comment_text(m_file)
          << " for povray-facet (povray_patch/).\n"
          << (m_rad.count > 0
                  ? "// With POV-Ray radiosity (--radiosity): an approximation of `facet render "
                    "--integrator path`.\n"
                  : "// It renders what `facet render --integrator direct` renders of that "
                    "scene.\n")
          << "// Render: povray-facet +I<this file> +O<out>.exr +FE32 +W" << c.width << " +H"
          << c.height << " -A +UA- -D\n"
          << "// (no antialiasing: one ray through each pixel centre; +FE32: linear 32-bit "
             "float EXR, +FE: half float).\n"
          << "#version 3.7;\n\n";
    global_settings();
    camera();
    materials();
    for (std::size_t i = 0; i < m_desc.lights.size(); ++i) light(m_desc.lights[i], i);
    m_out << "\n";
    for (std::size_t i = 0; i < m_desc.shapes.size(); ++i) {
        shape(m_desc.shapes[i], i);
        if (m_cells > kMaxLightCells)
            fail("/shapes/" + std::to_string(i) + "/emission",
                 fmt::format("the emitters need more than {} light cells at --area-grid {} "
                             "(every cell is a light with a shadow ray); lower --area-grid",
                             kMaxLightCells, m_opt.area_grid));
    }
    return m_out.str();
}

void run_export_pov(const ExportPovOptions& o) {
    if (o.output.empty()) throw std::runtime_error("export-pov: no output: give -o scene.pov");
    (void)parse_radiosity(o.radiosity);  // a bad --radiosity fails before the scene is read
    const SceneDescription desc = render::read_scene_description(o.scene);
    // Validate everything the renderer would (ranges, names, meshes) before writing: the SDL is
    // only written for scenes that `facet render` accepts.
    (void)render::build_scene(desc, o.scene);
    PovWriter w(desc, o.scene, o);
    std::string text;
    try {
        text = w.write();
    } catch (const ExportError& e) {
        throw std::runtime_error(std::string("export-pov: ") + e.what());
    }
    std::ofstream f(o.output);
    if (!(f << text)) throw std::runtime_error("export-pov: -o " + o.output + ": cannot write");
    if (!o.ini.empty()) {
        std::ofstream ini(o.ini);
        if (!(ini << "; povray-facet settings for " << o.output << " (facet export-pov)\n"
                  << "Input_File_Name=" << o.output << "\n"
                  << "Width=" << desc.camera.width << "\nHeight=" << desc.camera.height << "\n"
                  << "Antialias=Off\nOutput_File_Type=E\nBits_Per_Color=32\nOutput_Alpha=Off\n"
                  << "Display=Off\n"))
            throw std::runtime_error("export-pov: --ini " + o.ini + ": cannot write");
    }
}

}  // namespace

void add_export_pov_command(CLI::App& app) {
    auto o = std::make_shared<ExportPovOptions>();
    CLI::App* cmd = app.add_subcommand(
        "export-pov",
        "Write POV-Ray SDL (for povray-facet) that renders what `facet render --integrator "
        "direct` renders of a JSON scene; what POV-Ray cannot express is an error naming the "
        "JSON path");
    cmd->add_option("scene", o->scene, "scene file (.json)")->required();
    cmd->add_option("-o,--output", o->output, "output SDL file (.pov)")->required();
    cmd->add_option(
        "--ini", o->ini,
        "also write a POV-Ray .ini with the size, no antialiasing and 32-bit float EXR output");
    cmd->add_option("--area-grid", o->area_grid,
                    "emitter quadrature: N x N cells per parallelogram quad, N^2 per triangle, "
                    "N rings x 4N sectors per disc; each cell is one light")
        ->check(CLI::Range(1, 64))
        ->capture_default_str();
    cmd->add_option("--glossy-samples", o->glossy_samples,
                    "glossy reflection rays per hit of brdf finishes (POV `samples`; 0 = lights "
                    "only, as the direct integrator)")
        ->check(CLI::Range(0, 10000))
        ->capture_default_str();
    cmd->add_option("--environment", o->environment,
                    "error: an environment light is an error; background: export it as the "
                    "background only (it then lights no surface: an approximation)")
        ->check(CLI::IsMember({"error", "background"}))
        ->capture_default_str();
    cmd->add_option("--radiosity", o->radiosity,
                    "POV-Ray radiosity for the indirect light (approximates `--integrator path`): "
                    "off, low (50,1.0,4), medium (200,0.4,8), high (800,0.15,16) or "
                    "COUNT,ERROR_BOUND,RECURSION_LIMIT")
        ->capture_default_str();
    cmd->callback([o] { run_export_pov(*o); });
}

}  // namespace facet::cli
