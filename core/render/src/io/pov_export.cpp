// POV-Ray 3.7 SDL export (facet/render/pov_export.h): the writer of the camera, global
// settings and materials, and the PovShapeOut / PovLightOut that each kind's `pov` writes
// through (kinds.h).
#include "facet/render/pov_export.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <span>
#include <sstream>
#include <stdexcept>

#include "../scene_checks.h"
#include "facet/frame.h"
#include "facet/registry.h"
#include "facet/render/kinds.h"
#include "facet/render/light_units.h"
#include "facet/render/medium.h"
#include "facet/render/scene.h"
#include "facet/render/texel_image.h"
#include "pov_writer.h"

namespace facet::render {

std::string pov_num(double v) {
    if (v == 0.0) return "0";
    return fmt::format("{}", v);
}
std::string pov_vec(const glm::dvec3& v) {
    return "<" + pov_num(v.x) + ", " + pov_num(v.y) + ", " + pov_num(v.z) + ">";
}
std::string pov_rgb(const glm::dvec3& c) {
    return "rgb " + pov_vec(c);
}

namespace {

// POV-Ray radiosity settings of the `radiosity` option (docs/povray.md).
struct RadiosityPreset {
    int count = 0;  // 0: off
    double error_bound = 0.0;
    int recursion_limit = 0;
};

// "off", a preset, or "COUNT,ERROR_BOUND,RECURSION_LIMIT". Ranges: POV-Ray's (recursion_limit
// 1-20, RadiosityFunction::DEPTH_MAX; count at most the 1600 precomputed directions,
// RADIOSITY_MAX_SAMPLE_DIRECTIONS) and an error_bound in (0, 10].
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
        throw std::invalid_argument(usage);
    if (r.count < 1 || r.count > 1600)
        throw std::invalid_argument(
            fmt::format("--radiosity: count must be in [1, 1600] (got {})", r.count));
    if (!(r.error_bound > 0.0 && r.error_bound <= 10.0))
        throw std::invalid_argument(
            fmt::format("--radiosity: error_bound must be in (0, 10] (got {})", r.error_bound));
    if (r.recursion_limit < 1 || r.recursion_limit > 20)
        throw std::invalid_argument(fmt::format(
            "--radiosity: recursion_limit must be in [1, 20] (got {})", r.recursion_limit));
    return r;
}

// Light cells beyond this make a scene POV-Ray shades very slowly (every cell is a light with a
// shadow ray at every shaded point): an error that names the emitter and the option.
constexpr long long kMaxLightCells = 20000;

// Free text (shape and material names, the file name) for a `//` comment of the SDL: control
// characters become spaces, so that a newline in a name cannot end the comment.
std::string comment_text(std::string text) {
    for (char& c : text)
        if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) c = ' ';
    return text;
}

// POV-Ray `matrix`: rows are the images of x, y, z and the translation (row vectors).
std::string pov_matrix(const glm::dmat4& m) {
    std::string s = "matrix <";
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 3; ++r) s += pov_num(m[c][r]) + (c == 3 && r == 2 ? ">" : ", ");
    return s;
}

// The name of a material's interior medium ("interior", scenes/FORMAT.md "Media"), or "".
std::string interior_of(const MaterialDesc& m) {
    const auto it = m.params.values().find("interior");
    if (it == m.params.values().end()) return "";
    const std::string* name = std::get_if<std::string>(&it->second);
    return name ? *name : "";
}

// The material without its "interior" (which belongs to no reflection model).
MaterialDesc without_interior(const MaterialDesc& m) {
    MaterialDesc c = m;
    ParamSet rest;
    for (const auto& [key, v] : m.params.values())
        if (key != "interior") rest.set(key, v);
    c.params = std::move(rest);
    return c;
}

// Whether the material is an invisible boundary (the `null` model: ModelInfo::pass_through).
bool is_pass_through(const MaterialDesc& m) {
    const ModelInfo* info = find_model(m.model);
    return info && info->pass_through;
}

class PovWriter {
  public:
    // `media`: the built scene's media, in the order of desc.media (build_scene).
    PovWriter(const SceneDescription& desc, std::string name, const PovExportOptions& opt,
              std::span<const Medium> media)
        : m_desc(desc),
          m_name(std::move(name)),
          m_opt(opt),
          m_rad(parse_radiosity(opt.radiosity)),
          m_media(media) {}

    std::string write();

    [[noreturn]] void fail(const std::string& pointer, const std::string& message) const {
        throw SceneError(m_name + ": " + pointer + ": " + message);
    }

  private:
    friend class ShapeOut;
    friend class LightOut;
    void camera();
    void global_settings();
    std::string texture(const MaterialDesc& m, const std::string& pointer,
                        const glm::dvec3& emission = glm::dvec3(0.0));
    // `pigment { uv_mapping ... }` of a colour texture (image or checker) at `pointer`, and in
    // `factor` the multiplier of its values (scale x color_scale) that the pigment leaves out.
    std::string uv_pigment(const TextureDesc& t, const std::string& pointer,
                           glm::dvec3& factor) const;
    // Whether material m (its sub-materials too) / shape s reads anything through the UVs.
    bool reads_uv(const MaterialDesc& m) const;
    bool shape_reads_uv(const ShapeDesc& s) const;
    // A clamp-wrapped texture is POV-Ray's `once`, which is transparent outside [0, 1]^2 where
    // the core repeats the edge texels: an error unless the shape's UVs [lo, hi] stay inside
    // after each such texture's UV transform.
    void check_clamp(const ShapeDesc& s, const std::string& pointer, glm::dvec2 lo,
                     glm::dvec2 hi) const;
    // The shape's material (inline or named; null for none) and its JSON pointer.
    const MaterialDesc* shape_material(const ShapeDesc& s, const std::string& pointer,
                                       std::string& mpointer) const;
    // A combination's sub-material k: the named material it refers to, or the inline one; its
    // pointer in `pointer` (build_scene has checked the names and that there is no cycle).
    const MaterialDesc& child(const MaterialDesc& m, std::size_t k, std::string& pointer) const;
    bool has_mirror(const MaterialDesc& m) const;
    void materials();
    std::string shape_texture(const ShapeDesc& s, const std::string& pointer, bool inside_front);
    void shape(const ShapeDesc& s, const std::string& pointer);
    // The POV identifier of prototype `name` (declared by write()).
    std::string prototype_id(const std::string& name) const;
    std::string emission_of(const glm::dvec3& emission, const glm::dvec3& pigment,
                            const std::string& pointer) const;
    // POV-Ray `media { ... }` of medium `name` (scenes/FORMAT.md "Media"; docs/povray.md).
    std::string media_sdl(const std::string& name, const std::string& pointer) const;
    // What follows a shape's texture for its material's medium interface: "hollow" for a null
    // boundary without an interior (the surrounding medium goes on inside it), "hollow" and
    // the interior's `interior { media }`, or "".
    std::string interior_sdl(const ShapeDesc& s, const std::string& pointer) const;
    bool has_media() const { return !m_media.empty(); }

    const SceneDescription& m_desc;
    std::string m_name;
    const PovExportOptions& m_opt;
    RadiosityPreset m_rad;
    std::span<const Medium> m_media;
    std::ostringstream m_out;
    std::vector<std::string> m_material_ids;  // POV identifier of m_desc.materials[i]
    long long m_cells = 0;
};

// A shape kind's view of the writer.
class ShapeOut final : public PovShapeOut {
  public:
    ShapeOut(PovWriter& w, const ShapeDesc& s, std::string pointer)
        : PovShapeOut(s, std::move(pointer),
                      std::max({s.emission.r, s.emission.g, s.emission.b}) > 0.f,
                      w.shape_reads_uv(s)),
          m_w(w) {}
    [[noreturn]] void fail(const std::string& p, const std::string& m) const override {
        m_w.fail(p, m);
    }
    void object(const std::string& head, bool inside_front) override;
    void triangles(bool parallelogram_cells) override;
    void begin_cells() override;
    void cell_light(const glm::dvec3& p, const glm::dvec3& n, const glm::dvec3& radiance,
                    double area) override;
    int area_grid() const override { return m_w.m_opt.area_grid; }
    void instance(const std::string& prototype) override;

  private:
    bool twin() const { return emits && m_w.m_rad.count > 0; }
    std::string xf() const {
        return shape.transform ? "  " + pov_matrix(*shape.transform) + "\n" : "";
    }
    PovWriter& m_w;
};

class LightOut final : public PovLightOut {
  public:
    LightOut(PovWriter& w, const LightDesc& l, std::size_t index)
        : PovLightOut(l, "/lights/" + std::to_string(index), w.m_opt, w.m_desc.base_dir,
                      w.has_media()),
          m_w(w) {}
    [[noreturn]] void fail(const std::string& p, const std::string& m) const override {
        m_w.fail(p, m);
    }
    std::ostream& out() override { return m_w.m_out; }

  private:
    PovWriter& m_w;
};

// With radiosity, an emitter's black twin: seen by radiosity rays only (its light is counted
// by the cell lights), blocking them as the emitter would.
constexpr const char* kTwinTexture =
    "  texture { pigment { rgb 0 } finish { ambient 0 diffuse 0 } }\n  no_image "
    "no_reflection no_shadow\n";

// Every edge of the mesh is shared by exactly two triangles (positions compared exactly).
bool closed_mesh(const TriangleMesh& m) {
    std::map<std::pair<std::array<float, 3>, std::array<float, 3>>, int> edges;
    auto key = [&](std::uint32_t i) {
        const Vec3& p = m.positions[i];
        return std::array<float, 3>{p.x, p.y, p.z};
    };
    for (std::size_t t = 0; t < m.num_triangles(); ++t)
        for (int e = 0; e < 3; ++e) {
            auto a = key(m.indices[3 * t + e]), b = key(m.indices[3 * t + (e + 1) % 3]);
            if (b < a) std::swap(a, b);
            ++edges[{a, b}];
        }
    for (const auto& [edge, n] : edges)
        if (n != 2) return false;
    return !edges.empty();
}

void ShapeOut::object(const std::string& head, bool inside_front) {
    // Only spheres reach here with UVs (their u, v span [0, 1]^2).
    if (reads_uv) m_w.check_clamp(shape, pointer, glm::dvec2(0.0), glm::dvec2(1.0));
    std::ostringstream& out = m_w.m_out;
    out << head << "\n  " << m_w.shape_texture(shape, pointer, inside_front) << "\n"
        << m_w.interior_sdl(shape, pointer) << (emits ? "  no_shadow\n" : "")
        << (twin() ? "  no_radiosity\n" : "") << xf() << "}\n";
    if (twin()) out << head << "\n" << kTwinTexture << xf() << "}\n";
}

// Triangle shapes as mesh2: the renderer's own triangles, in world space as build_scene makes
// them (positions transformed in double and stored as float, normals by the inverse transpose
// and normalised per vertex, then interpolated), so that smooth shading under a non-uniform
// scale agrees too (POV-Ray would interpolate object-space normals and transform the result).
// A mirroring transform keeps the authored front side, flip_normals reverses it.
void ShapeOut::triangles(bool parallelogram_cells) {
    const ShapeKindDef& kind = shape_kind(shape.kind);
    if (!kind.triangles) fail(pointer + "/type", "this shape kind has no triangles");
    TriangleMesh m;
    try {
        m = kind.triangles(shape, m_w.m_desc.base_dir);
    } catch (const std::exception& e) {
        fail(pointer + "/file", e.what());
    }
    const glm::dmat4 x = shape.transform.value_or(glm::dmat4(1.0));
    const glm::dmat3 lin(x);
    const glm::dmat3 nmat = glm::transpose(glm::inverse(lin));
    for (Vec3& p : m.positions) p = Vec3(glm::dvec3(x * glm::dvec4(glm::dvec3(p), 1.0)));
    for (Vec3& nn : m.normals) {
        const glm::dvec3 w = nmat * glm::dvec3(nn);
        const double l = glm::length(w);
        nn = l > 0.0 ? Vec3(w / l) : Vec3(0.f, 0.f, 1.f);
    }
    if ((glm::determinant(lin) < 0.0) != shape.flip_normals)
        for (std::size_t i = 0; i + 2 < m.indices.size(); i += 3)
            std::swap(m.indices[i + 1], m.indices[i + 2]);
    std::ostringstream body;
    body << "mesh2 {\n  vertex_vectors { " << m.positions.size();
    for (const Vec3& p : m.positions) body << ", " << pov_vec(glm::dvec3(p));
    body << " }\n";
    if (!m.normals.empty()) {
        body << "  normal_vectors { " << m.normals.size();
        for (const Vec3& nn : m.normals) body << ", " << pov_vec(glm::dvec3(nn));
        body << " }\n";
    }
    // The core's UVs per vertex, interpolated by POV-Ray over each triangle as by Facet
    // (barycentric; uv_indices default to face_indices).
    if (reads_uv) {
        if (m.uvs.empty()) fail_uv("the mesh has no UVs");
        glm::dvec2 lo(HUGE_VAL), hi(-HUGE_VAL);
        body << "  uv_vectors { " << m.uvs.size();
        for (const Vec2& uv : m.uvs) {
            body << ", <" << pov_num(uv.x) << ", " << pov_num(uv.y) << ">";
            lo = glm::min(lo, glm::dvec2(uv));
            hi = glm::max(hi, glm::dvec2(uv));
        }
        body << " }\n";
        m_w.check_clamp(shape, pointer, lo, hi);
    }
    // POV-Ray's triangle normal is (p0 - p1) x (p2 - p1) = -(p1 - p0) x (p2 - p0), the reverse
    // of Facet's front (mesh.h), and its interior_texture is on the side that normal points
    // away from: write each triangle as (p0, p2, p1) so that both agree.
    body << "  face_indices { " << m.num_triangles();
    for (std::size_t t = 0; t < m.num_triangles(); ++t)
        body << ", <" << m.indices[3 * t] << ", " << m.indices[3 * t + 2] << ", "
             << m.indices[3 * t + 1] << ">";
    body << " }\n";
    std::ostringstream& out = m_w.m_out;
    const std::string interior = m_w.interior_sdl(shape, pointer);
    // A mesh2 has an inside only with an inside_vector, and only a closed one has a true
    // inside (POV-Ray counts crossings along that vector).
    if (!interior.empty() && !closed_mesh(m))
        fail(pointer,
             "a medium boundary (a null material or an interior) must be a closed mesh "
             "for POV-Ray (every edge shared by two triangles): POV-Ray decides "
             "inside and outside by crossings, Facet by each surface's normal");
    out << body.str() << "  " << m_w.shape_texture(shape, pointer, false) << "\n"
        << (interior.empty() ? "" : "  inside_vector <0, 0, 1>\n" + interior)
        << (emits ? "  no_shadow\n" : "") << (twin() ? "  no_radiosity\n" : "") << "}\n";
    if (twin()) out << body.str() << kTwinTexture << "}\n";
    if (!emits) return;

    // The emitter's light: a midpoint quadrature of its surface, N = area_grid.
    begin_cells();
    const int n = area_grid();
    const glm::dvec3 le(shape.emission);
    auto P = [&](std::uint32_t i) { return glm::dvec3(m.positions[i]); };
    // A flat parallelogram: one N x N grid over it.
    if (parallelogram_cells && m.num_triangles() == 2) {
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
    // Other triangles: N^2 similar sub-triangles, at their centroids.
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

void ShapeOut::begin_cells() {
    m_w.m_out << "// Light of the emitter " << pointer
              << (shape.name.empty() ? "" : " ('" + comment_text(shape.name) + "')")
              << ": midpoint cells, grid " << area_grid() << "\n";
}

// One light cell of an emitter: a spotlight at p aimed along the front normal n whose intensity
// falls off as cos(theta) (tightness 1, hard edge at 90 degrees: Attenuate_Light in POV-Ray's
// lighting/point.cpp gives pow(cos, tightness) for cos > 0 and 0 behind), with the on-axis
// intensity of a Lambertian patch of the cell's area.
void ShapeOut::cell_light(const glm::dvec3& p, const glm::dvec3& n, const glm::dvec3& radiance,
                          double area) {
    const glm::dvec3 c = pov_light_colour(emitter_intensity(radiance, area));
    m_w.m_out << "light_source { " << pov_vec(p) << " " << pov_rgb(c) << " spotlight point_at "
              << pov_vec(p + n) << " radius 90 falloff 90 tightness 1 physical_falloff }\n";
    ++m_w.m_cells;
}

void PovWriter::camera() {
    // scenes/FORMAT.md, "POV-Ray export": explicit vectors; POV-Ray 3.7 traces the pixel
    // centres itself (TracePixel::CreateCameraRay adds the half pixel). In double, from the
    // description (the renderer's Camera is float).
    const CameraDesc& c = m_desc.camera;
    const glm::dvec3 pos(c.position);
    const glm::dvec3 f = glm::normalize(glm::dvec3(c.look_at) - pos);
    const glm::dvec3 r = glm::normalize(glm::cross(f, glm::dvec3(c.up)));
    const glm::dvec3 u = glm::cross(r, f);
    const bool ortho = c.type == "orthographic";
    const double aspect = double(c.width) / double(c.height);
    double tan_x, tan_y;  // the window's half-extents (camera.h)
    if (!ortho) {
        tan_y = std::tan(0.5 * c.fov * kPiD / 180.0);
        tan_x = tan_y * aspect;
    } else {
        const double half = 0.5 * c.scale.value_or(0.0);
        tan_x = c.width >= c.height ? half : half * aspect;
        tan_y = c.width >= c.height ? half / aspect : half;
    }
    const double larger = 2.0 * std::max(tan_x, tan_y);
    const glm::dvec3 shift = larger * (c.shift_x * r + c.shift_y * u);
    const double radius = aperture_radius(c);
    if (radius > 0.0) {
        // POV-Ray's focal_blur (tracepixel.cpp JitterCameraRay) moves the origin by a point of
        // the round aperture in the plane normal to `direction`, and aims at the point
        // direction * Focal_Distance of the unnormalised pixel direction: with a unit
        // `direction` along f that is the plane of focus at Focal_Distance = |focal_point -
        // location|, as Facet's. Anything else is not the same camera.
        const std::string what = c.aperture_radius ? "/camera/aperture_radius" : "/camera/fstop";
        if (ortho)
            fail(what,
                 "POV-Ray 3.7's orthographic focal_blur drops the pixel's origin offset "
                 "(JitterCameraRay sets origin = location + deflection): not exported");
        if (c.blades != 0)
            fail("/camera/blades",
                 "POV-Ray's focal_blur aperture is round (a polygonal "
                 "aperture needs a bokeh pigment, which weights samples "
                 "differently): not exported");
        if (c.shift_x != 0.0 || c.shift_y != 0.0)
            fail(c.shift_x != 0.0 ? "/camera/shift_x" : "/camera/shift_y",
                 "with focal_blur POV-Ray's lens plane is normal to the shifted `direction` "
                 "(Facet's is normal to the view direction): not exported");
    }
    if (!ortho && shift == glm::dvec3(0.0) && !(radius > 0.0)) {
        m_out << "// Facet pinhole camera (scenes/FORMAT.md): explicit vectors, pixel centres.\n"
              << "camera {\n  perspective\n"
              << "  location  " << pov_vec(pos) << "\n"
              << "  right     " << pov_vec(2.0 * tan_x * r) << "\n"
              << "  up        " << pov_vec(2.0 * tan_y * u) << "\n"
              << "  direction " << pov_vec(f) << "\n}\n\n";
        return;
    }
    // Orthographic: rays from location + x0 right + y0 up along `direction`, so the shift
    // moves the location. Perspective: direction + x0 right + y0 up, so the shift moves the
    // direction off axis (exact; POV-Ray warns that the vectors are not perpendicular).
    m_out << "// Facet " << c.type << " camera (scenes/FORMAT.md): explicit vectors, pixel "
          << "centres" << (shift != glm::dvec3(0.0) ? ", lens shift" : "")
          << (radius > 0.0 ? ", thin lens as focal_blur" : "") << ".\n"
          << "camera {\n  " << c.type << "\n"
          << "  location  " << pov_vec(ortho ? pos + shift : pos) << "\n"
          << "  right     " << pov_vec(2.0 * tan_x * r) << "\n"
          << "  up        " << pov_vec(2.0 * tan_y * u) << "\n"
          << "  direction " << pov_vec(ortho ? f : f + shift) << "\n";
    if (radius > 0.0) {
        // aperture is the diameter (JitterCameraRay: radius = Aperture / 2). The geometry is
        // exact; the lens samples are POV-Ray's (hex grids of 7/19/37 points, jittered, then
        // random points of the disc, up to blur_samples, stopping by confidence/variance): a
        // different estimator of the same aperture average, equal up to its noise and the
        // grid's non-uniformity (docs/povray.md).
        m_out << "  focal_point " << pov_vec(pos + *c.focus_distance * f) << "\n"
              << "  aperture " << pov_num(2.0 * radius) << "\n"
              << "  blur_samples " << m_opt.blur_samples << "\n";
    }
    m_out << "}\n\n";
}
void PovWriter::global_settings() {
    // Mirror bounces are the only recursion of the direct integrator: without a mirror lobe
    // the depth changes nothing, and a deeper limit than POV-Ray's is no error.
    bool mirrors = false;
    for (const auto& [name, m] : m_desc.materials) mirrors = mirrors || has_mirror(m);
    for (const ShapeDesc& s : m_desc.shapes)
        if (s.material) mirrors = mirrors || has_mirror(*s.material);
    for (const auto& [pname, shapes] : m_desc.prototypes)
        for (const ShapeDesc& s : shapes)
            if (s.material) mirrors = mirrors || has_mirror(*s.material);
    // Null boundaries (media, docs/media.md): POV-Ray spends a trace level on each crossing of
    // a transparent surface, Facet none; the limit grows by two per boundary the camera and
    // mirror rays may cross, so that it cannot also bound mirror bounces as max_depth does.
    long long crossings = 0;
    std::string null_pointer;
    auto count_nulls = [&](const ShapeDesc& s, const std::string& p, long long times) {
        std::string mp;
        if (const MaterialDesc* m = shape_material(s, p, mp); m && is_pass_through(*m)) {
            crossings += 2 * times;
            if (null_pointer.empty()) null_pointer = mp;
        }
    };
    std::map<std::string, long long> placed;  // instances per prototype
    for (const ShapeDesc& s : m_desc.shapes)
        if (!s.of.empty()) ++placed[s.of];
    for (std::size_t i = 0; i < m_desc.shapes.size(); ++i)
        count_nulls(m_desc.shapes[i], "/shapes/" + std::to_string(i), 1);
    for (const auto& [pname, shapes] : m_desc.prototypes)
        for (std::size_t k = 0; k < shapes.size(); ++k)
            count_nulls(
                shapes[k],
                "/prototypes/" + detail::escape_pointer_token(pname) + "/" + std::to_string(k),
                placed[pname]);
    if (!m_desc.world_medium.empty() && mirrors)
        fail("/world_medium",
             "a world medium in a scene with mirror reflection: a mirror ray that leaves the "
             "scene would cross POV-Ray's atmosphere over an unbounded length");
    if (crossings > 0 && mirrors)
        fail(null_pointer,
             "a null boundary in a scene with mirror reflection: POV-Ray spends a trace level on "
             "each crossing, so max_trace_level could not bound the mirror bounces as "
             "max_depth does");
    int depth = mirrors ? m_desc.render.max_depth : std::min(m_desc.render.max_depth, 255);
    if (crossings > 0) depth = int(std::min<long long>(depth + crossings, 255));
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
          << "  max_trace_level " << level << "  // camera ray + "
          << (crossings > 0 ? fmt::format("max_depth {} + {} null boundary crossings",
                                          m_desc.render.max_depth, crossings)
                            : fmt::format("max_depth {} mirror bounces", depth))
          << (level > depth + 1 ? "; radiosity recursion needs more" : "") << "\n"
          << "  adc_bailout 0\n"
          << "  ambient_light 0\n";
    // --environment light: brdf finishes sample the sky_sphere (povray-facet's keyword).
    bool environment = false;
    for (const LightDesc& l : m_desc.lights)
        environment = environment || l.kind == LightKind::Environment;
    if (environment && m_opt.environment == "light")
        m_out << "  brdf_sky_sampling " << m_opt.sky_samples
              << "  // the sky_sphere lights brdf finishes (povray-facet; --sky-samples)\n";
    if (m_rad.count > 0) {
        // count/error_bound/recursion_limit from --radiosity; the rest fixed: nearest_count
        // 10 (POV-Ray's default 5 is blotchier), POV-Ray's pretrace defaults, no brightness
        // or gray change, and an adc_bailout far below the weight POV-Ray assumes for the
        // deepest bounce (0.5^20 ~ 1e-6), so that no recursion level is dropped for weight.
        m_out << "  radiosity {  // --radiosity " << m_opt.radiosity << "\n"
              << "    count " << m_rad.count << "\n"
              << "    error_bound " << pov_num(m_rad.error_bound) << "\n"
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

const MaterialDesc& PovWriter::child(const MaterialDesc& m, std::size_t k,
                                     std::string& pointer) const {
    const MaterialDesc& c = m.materials.at(k);
    if (c.ref.empty()) {
        pointer += "/materials/" + std::to_string(k);
        return c;
    }
    for (const auto& [name, named] : m_desc.materials)
        if (name == c.ref) {
            pointer = "/materials/" + detail::escape_pointer_token(name);
            return named;
        }
    fail(pointer + "/materials/" + std::to_string(k), "unknown material '" + c.ref + "'");
}

bool PovWriter::has_mirror(const MaterialDesc& m) const {
    if (!m.materials.empty()) {
        for (std::size_t k = 0; k < m.materials.size(); ++k) {
            std::string p;
            if (has_mirror(child(m, k, p))) return true;
        }
        return false;
    }
    if (is_pass_through(m)) return false;
    return make_material(m.model, without_interior(m).params).mirror().has_value();
}

// " emission rgb <...>" giving the radiance `emission` on a surface of that pigment: POV-Ray
// multiplies `emission` by the pigment (trace.cpp ComputeLightedTexture), so it is divided
// here. "" when there is no emission.
std::string PovWriter::emission_of(const glm::dvec3& emission, const glm::dvec3& pigment,
                                   const std::string& pointer) const {
    if (!(std::max({emission.x, emission.y, emission.z}) > 0.0)) return "";
    glm::dvec3 e(0.0);
    for (int c = 0; c < 3; ++c) {
        if (emission[c] == 0.0) continue;
        if (!(pigment[c] > 0.0))
            fail(pointer,
                 "an emitter whose diffuse reflectance is 0 in a channel it emits cannot be "
                 "written (POV-Ray tints emission by the pigment)");
        e[c] = emission[c] / pigment[c];
    }
    return " emission " + pov_rgb(e);
}

bool PovWriter::reads_uv(const MaterialDesc& m) const {
    if (m.normal_map || m.bump) return true;
    for (const auto& [key, t] : m.textures)
        if (t.kind != "vertex_color") return true;
    for (std::size_t k = 0; k < m.materials.size(); ++k) {
        std::string p;
        if (reads_uv(child(m, k, p))) return true;
    }
    return false;
}

const MaterialDesc* PovWriter::shape_material(const ShapeDesc& s, const std::string& pointer,
                                              std::string& mpointer) const {
    mpointer = pointer + "/material";
    if (s.material) return &*s.material;
    if (s.material_ref.empty()) return nullptr;
    for (const auto& [name, m] : m_desc.materials)
        if (name == s.material_ref) {
            mpointer = "/materials/" + detail::escape_pointer_token(name);
            return &m;
        }
    fail(pointer + "/material", "unknown material '" + s.material_ref + "'");
}

bool PovWriter::shape_reads_uv(const ShapeDesc& s) const {
    if (s.emission_texture && s.emission_texture->kind != "vertex_color") return true;
    std::string mp;
    const MaterialDesc* m = shape_material(s, "", mp);
    return m && reads_uv(*m);
}

namespace {

// uv' = A uv + b of a texture (texture.h conventions), in double.
void uv_affine(const TextureDesc& t, glm::dmat2& a, glm::dvec2& b) {
    const double r = glm::radians(t.uv_rotation);
    const glm::dmat2 rot(std::cos(r), std::sin(r), -std::sin(r), std::cos(r));  // columns
    a = rot * glm::dmat2(double(t.uv_scale.x), 0.0, 0.0, double(t.uv_scale.y));
    b = glm::dvec2(t.uv_offset);
}

}  // namespace

void PovWriter::check_clamp(const ShapeDesc& s, const std::string& pointer, glm::dvec2 lo,
                            glm::dvec2 hi) const {
    auto check = [&](const TextureDesc& t, const std::string& where) {
        if (t.wrap != "clamp" || t.kind != "image") return;
        glm::dmat2 a;
        glm::dvec2 b;
        uv_affine(t, a, b);
        for (const glm::dvec2 c : {lo, glm::dvec2(hi.x, lo.y), hi, glm::dvec2(lo.x, hi.y)}) {
            const glm::dvec2 q = a * c + b;
            if (q.x < 0.0 || q.x > 1.0 || q.y < 0.0 || q.y > 1.0)
                fail(where + "/wrap",
                     fmt::format(
                         "clamp is POV-Ray's image_map `once`, which is transparent "
                         "outside [0, 1]^2, and the texture coordinates of {} reach "
                         "({:.6g}, {:.6g}): not exported (use repeat, or keep the UVs inside)",
                         pointer, q.x, q.y));
        }
    };
    std::function<void(const MaterialDesc&, const std::string&)> walk = [&](const MaterialDesc& m,
                                                                            const std::string& mp) {
        for (const auto& [key, t] : m.textures)
            check(t, mp + "/" + detail::escape_pointer_token(key));
        for (std::size_t k = 0; k < m.materials.size(); ++k) {
            std::string p = mp;
            walk(child(m, k, p), p);
        }
    };
    std::string mp;
    if (const MaterialDesc* m = shape_material(s, pointer, mp)) walk(*m, mp);
    if (s.emission_texture) check(*s.emission_texture, pointer + "/emission");
}

// An image or checker as a POV-Ray pigment read through the object's UVs. Exact because:
//  - uv_mapping puts the pattern at (u, v, 0); the default planar image_map reads texel
//    column u W and row (1 - v) H from the top (pattern.cpp map_pos: bottom-left at UV (0, 0),
//    as the core's), with no interpolation the texel containing it (`closest`) and with
//    `interpolate 2` the bilinear blend of the four texel centres around it (Interp), the
//    texel indices wrapped (repeat) or, with `once`, clamped to the edge (the core's clamp
//    inside [0, 1]^2; check_clamp);
//  - `gamma srgb` decodes 8- and 16-bit files with the IEC 61966-2-1 curve, `gamma 1.0` keeps
//    them linear (float files are linear), as the core's colorspace;
//  - the UV transform uv' = A uv + b is the pigment's `matrix`, the inverse map (POV-Ray looks
//    its patterns up at T^-1 of the point); a checker's scale n multiplies it, and POV-Ray's
//    `checker` colours cell (floor u', floor v') by the parity of their sum, as the core.
// Object transforms do not move uv_mapping patterns (the UVs are the object's own).
std::string PovWriter::uv_pigment(const TextureDesc& t, const std::string& pointer,
                                  glm::dvec3& factor) const {
    if (t.kind == "vertex_color" || t.times_vertex_color)
        fail(pointer,
             "a vertex colour cannot be exported to POV-Ray exactly (a mesh2 texture_list "
             "blends whole textures per vertex; povray-facet's brdf takes constants)");
    if (t.kind != "image" && t.kind != "checker")
        fail(pointer, "a " + t.kind +
                          " texture cannot be exported to POV-Ray exactly (its patterns are not "
                          "Blender's)");
    if (t.image || t.bytes)
        fail(pointer,
             "an image held in memory (a numpy array, or an image inside a .glb) has no file "
             "POV-Ray can read: save it as a PNG or EXR file and name that");
    if (!t.channel.empty())
        fail(pointer + "/channel",
             "one channel of an image as grey cannot be a POV-Ray image_map pigment (it reads "
             "the colour channels)");
    factor = glm::dvec3(t.color_scale) * t.scale;
    glm::dmat2 a;
    glm::dvec2 b;
    uv_affine(t, a, b);
    std::string body;
    if (t.kind == "checker") {
        a *= t.checker_scale;
        b *= t.checker_scale;
        body =
            "checker " + pov_rgb(glm::dvec3(t.colors[0])) + ", " + pov_rgb(glm::dvec3(t.colors[1]));
    } else {
        const std::string path =
            std::filesystem::absolute(resolve_scene_path(t.file, m_desc.base_dir))
                .lexically_normal()
                .string();
        std::string ext = std::filesystem::path(path).extension().string();
        for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
        // The formats whose decoding was checked against the core's (test
        // povray_export_textures): PNG (8/16-bit), OpenEXR, Radiance HDR.
        const std::string kind = ext == ".png"   ? "png"
                                 : ext == ".exr" ? "exr"
                                 : ext == ".hdr" ? "hdr"
                                                 : "";
        if (kind.empty())
            fail(pointer,
                 "only PNG, OpenEXR and HDR images are exported to POV-Ray (their decoding is "
                 "checked against the core's); convert '" +
                     t.file + "' to one of them");
        if (path.find('"') != std::string::npos)
            fail(pointer,
                 "the image path contains a double quote, which POV-Ray strings cannot hold");
        // The header (channels, float or integer) as the renderer's one image reader sees it.
        TexelImage header;
        TexelRowSink sink{[&](const TexelImage& h) {
                              header = h;
                              return true;
                          },
                          [](int, int, const float*) {}};
        try {
            (void)load_texel_image_rows(path, nullptr, {}, pointer, sink);
        } catch (const std::exception& e) {
            fail(pointer, e.what());
        }
        if (header.alpha_channel >= 0 || header.channels == 2 || header.channels > 4)
            fail(pointer,
                 fmt::format("'{}' has {} channels: POV-Ray's image_map reads an alpha channel "
                             "as transparency, where the core's colour ignores it (save the "
                             "image as RGB or grey)",
                             t.file, header.channels));
        const std::string cs = !t.colorspace.empty() ? t.colorspace
                               : header.float_format ? "linear"
                                                     : "srgb";
        if (header.float_format && cs == "srgb")
            fail(pointer + "/colorspace",
                 "an sRGB-encoded float image: POV-Ray reads float images as linear");
        const std::string filter = t.filter.empty() ? "mipmap" : t.filter;
        if (filter == "mipmap" && m_opt.mipmap != "linear")
            fail(pointer + "/filter",
                 "the mipmap filter (the default) has no POV-Ray equivalent (image_map filters "
                 "the full image only): give \"filter\": \"linear\" or \"closest\", or export "
                 "with --mipmap linear (exact where the texture is magnified)");
        if (t.wrap == "mirror")
            fail(pointer + "/wrap", "POV-Ray's image_map has no mirrored repeat");
        body = "image_map { " + kind + " \"" + path + "\"" +
               (header.float_format ? ""
                : cs == "srgb"      ? " gamma srgb"
                                    : " gamma 1.0") +
               (filter == "closest" ? "" : " interpolate 2") + (t.wrap == "clamp" ? " once" : "") +
               " }";
    }
    std::string xf;
    if (a != glm::dmat2(1.0) || b != glm::dvec2(0.0)) {
        if (glm::determinant(a) == 0.0) fail(pointer + "/uv_scale", "a singular UV transform");
        // The pattern sees T^-1 (u, v, 0) = (A uv + b, 0): T is the inverse, z kept.
        const glm::dmat2 ai = glm::inverse(a);
        const glm::dvec2 bi = -(ai * b);
        glm::dmat4 m(1.0);
        m[0] = glm::dvec4(ai[0], 0.0, 0.0);
        m[1] = glm::dvec4(ai[1], 0.0, 0.0);
        m[3] = glm::dvec4(bi, 0.0, 1.0);
        xf = " " + pov_matrix(m);
    }
    return "pigment { uv_mapping " + body + xf + " }";
}

// `texture { pigment {...} finish { ambient 0 brdf { ... } } }` for a material. The pigment is
// the diffuse reflectance (lambert's reflectance, composite's diffuse_reflectance, with the
// core's default when not given), which povray-facet multiplies into the diffuse lobe; the
// other parameters go into the brdf block under their core names.
std::string PovWriter::texture(const MaterialDesc& m, const std::string& pointer,
                               const glm::dvec3& emission) {
    if (m.params.has("interior")) return texture(without_interior(m), pointer, emission);
    const ModelInfo* info = find_model(m.model);
    if (!info) fail(pointer + "/model", "unknown model '" + m.model + "'");
    if (info->name == "holdout")
        fail(pointer + "/model", "a holdout cannot be exported to POV-Ray (render with Facet)");
    // The fibre models (principled_hair, hair) scatter about the surface's tangent, which
    // POV-Ray does not give a finish (povray-facet does not take them: ModelInfo::pov_finish).
    if (!info->pov_finish && info->children == 0 && !info->pass_through &&
        make_material(m.model, m.params).anisotropic())
        fail(pointer + "/model",
             fmt::format("'{}' scatters about the surface's tangent (a hair fibre), which "
                         "POV-Ray does not provide; not exported (render with Facet)",
                         m.model));
    // null: an invisible boundary, wholly transparent on both sides (POV-Ray's transmit 1
    // passes camera and shadow rays unchanged), reflecting and emitting nothing.
    if (info->pass_through) {
        if (emission != glm::dvec3(0.0))
            fail(pointer, "a null boundary cannot emit (it has no surface to glow)");
        return "texture { pigment { rgbt 1 } finish { ambient 0 diffuse 0 } }";
    }
    // The one parameter the pigment carries (the patch's tinting rule): the reflectance of
    // lambert and oren_nayar (povray-facet multiplies it into their f), composite's
    // diffuse_reflectance; white for principled, whose colours are its own parameters (the
    // pigment then only scales emission, emission_of).
    const std::string& diffuse_param = info->diffuse_param;
    // Textured parameters: only the pigment can vary over a surface (a uv_mapping pigment,
    // uv_pigment); povray-facet's brdf block takes constants, so any other textured parameter
    // is an error, never a silent constant. Vertex colours: a mesh2 texture_list blends whole
    // textures per vertex, which the brdf finish (one constant block per texture) does not
    // interpolate.
    for (const auto& [key, td] : m.textures) {
        if (key == diffuse_param && td.kind != "vertex_color") continue;
        fail(pointer + "/" + detail::escape_pointer_token(key),
             td.kind == "vertex_color"
                 ? "a vertex colour cannot be exported to POV-Ray exactly (a mesh2 texture_list "
                   "would blend whole textures per vertex; povray-facet's brdf takes constants)"
                 : "a textured '" + key +
                       "' cannot be exported to POV-Ray exactly (povray-facet's brdf block takes "
                       "constants; only the diffuse colour, which the pigment carries, can be "
                       "an image or checker)");
    }
    // Normal and bump maps: POV-Ray 3.7 has no tangent-space normal map. Its bump_map is a
    // height image, but differentiated over one texel in image space (pattern.cpp bump_map:
    // the heights of three neighbouring texels), oriented by a frame built from the normal and
    // the object's +y axis rather than the surface's UV tangents, and scaled by bump_size in
    // no scene unit: not the core's bump (scenes/FORMAT.md, "Bump maps").
    if (m.normal_map)
        fail(pointer + "/normal_map",
             "a tangent-space normal map has no POV-Ray 3.7 equivalent (POV-Ray perturbs "
             "normals by the gradient of a scalar pattern, in a frame that is not the "
             "surface's UV tangent frame)");
    if (m.bump)
        fail(pointer + "/bump",
             "POV-Ray's bump_map is not the core's bump: it differentiates the image over one "
             "texel, in a frame built from the object's +y axis instead of the UV tangents, "
             "scaled by bump_size in no scene unit");
    // mix: POV-Ray's `average` texture_map shades each texture and averages the results with
    // the weights [1 - w, w] (their sum is 1, so POV-Ray's normalisation changes nothing):
    // (1 - w) L_a + w L_b, which is what f = (1 - w) f_a + w f_b reflects. Each entry carries
    // the shape's emission, so the average emits it once.
    if (m.model == "mix") {
        const auto it = m.params.values().find("weight");
        const double w = it == m.params.values().end() ? 0.5 : std::get<double>(it->second);
        std::string pa = pointer, pb = pointer;
        const MaterialDesc& a = child(m, 0, pa);
        const MaterialDesc& b = child(m, 1, pb);
        if (w <= 0.0) return texture(a, pa, emission);  // Material::mix: the child itself
        if (w >= 1.0) return texture(b, pb, emission);
        auto body = [](const std::string& t) { return t.substr(10, t.size() - 12); };
        return "texture { average texture_map { [" + pov_num(1.0 - w) + " " +
               body(texture(a, pa, emission)) + "] [" + pov_num(w) + " " +
               body(texture(b, pb, emission)) + "] } }";
    }
    if (m.model == "add")
        fail(pointer + "/model",
             "'add' sums two materials, which POV-Ray cannot express exactly (its average "
             "texture_map normalises the weights to a mean)");
    // principled: povray-facet's brdf finish shades its reflection part (the core's lobes);
    // transmission would be POV-Ray's interior and refraction, which is not the model's glass
    // lobes (rough refraction, the Fresnel split of Cycles, 1/eta^2), so it is reported.
    // Random-walk subsurface scattering (facet/subsurface.h): POV-Ray has no equivalent (its
    // own subsurface light transport is a different model).
    if (m.model == "subsurface" || m.model == "principled") {
        if (make_material(m.model, m.params).subsurface())
            fail(pointer + (m.model == "principled" ? "/subsurface" : "/model"),
                 "random-walk subsurface scattering cannot be exported to POV-Ray (a brdf "
                 "finish would render Cycles' diffuse fallback; docs/subsurface.md)");
    }
    if (m.model == "principled") {
        const Material pm = make_material(m.model, m.params);
        if (pm.transmissive())
            fail(pointer + "/transmission",
                 "principled transmission cannot be exported to POV-Ray exactly (the brdf "
                 "finish is its reflection part; POV-Ray's interior/refraction is not its "
                 "glass lobes)");
        if (pm.anisotropic())
            fail(pointer + "/anisotropic",
                 "anisotropic lobes need a surface tangent, which POV-Ray does not provide "
                 "(povray-facet would orient the lobe by an arbitrary frame)");
    }
    // POV-Ray's own refraction (interior ior, fresnel reflection) neither scales radiance by
    // 1/eta^2 nor sums a thin pane's inter-reflections: not exact, so not exported.
    if (make_material(m.model, m.params).transmissive())
        fail(pointer + "/model",
             fmt::format("'{}' transmits light, which POV-Ray cannot express exactly (the brdf "
                         "finish is reflection only; POV-Ray's interior/refraction differs)",
                         m.model));
    glm::dvec3 pigment(1.0);
    std::string pigment_sdl;  // a textured pigment (uv_pigment), or "" for the constant one
    std::string brdf = m.model;
    if (auto tex = m.textures.find(diffuse_param); tex != m.textures.end()) {
        // The pigment is the texture's values; their multiplier is the brdf parameter, a
        // factor on the pigment (docs/povray.md, "What the pigment tints").
        glm::dvec3 factor;
        const std::string tp = pointer + "/" + detail::escape_pointer_token(diffuse_param);
        pigment_sdl = uv_pigment(tex->second, tp, factor);
        // A texture scale would be the brdf block's diffuse factor, but povray-facet's
        // composite does not treat diffuse_reflectance as a pure factor on the pigment
        // (measured: up to 7% off facet render on a checker x 0.8), and the lambert factor is
        // unchecked: an error rather than an unverified picture.
        if (factor != glm::dvec3(1.0))
            fail(tp + "/scale",
                 "a texture scale on the diffuse colour is not exported (povray-facet's brdf "
                 "factor on a textured pigment does not match the core for composite): scale "
                 "the image's texels instead");
        if (std::max({emission.x, emission.y, emission.z}) > 0.0)
            fail(tp,
                 "an emitter with a textured diffuse colour: POV-Ray multiplies emission by "
                 "the pigment");
    } else if (!diffuse_param.empty()) {
        auto it = m.params.values().find(diffuse_param);
        if (it != m.params.values().end()) {
            if (const double* d = std::get_if<double>(&it->second))
                pigment = glm::dvec3(*d);
            else if (const Rgb* c = std::get_if<Rgb>(&it->second))
                pigment = glm::dvec3(*c);
        } else {
            for (const ParamInfo& p : info->params)
                if (p.name == diffuse_param) pigment = glm::dvec3(std::stod(p.default_value));
        }
    }
    for (const auto& [name, value] : m.params.values()) {
        if (name == diffuse_param) continue;
        if (name == "alpha_u" || name == "alpha_v" || name == "exponent_u" || name == "exponent_v")
            fail(pointer + "/" + name,
                 "anisotropic lobes need a surface tangent, which POV-Ray does not provide "
                 "(povray-facet would orient the lobe by an arbitrary frame)");
        brdf += " " + name + " ";
        if (const double* d = std::get_if<double>(&value))
            brdf += pov_num(*d);
        else if (const Rgb* c = std::get_if<Rgb>(&value))
            brdf += pov_rgb(glm::dvec3(*c));
        else if (const std::string* s = std::get_if<std::string>(&value))
            brdf += *s;
        else
            brdf += std::get<bool>(value) ? "on" : "off";
    }
    if (info->pov_samples) brdf += " samples " + std::to_string(m_opt.glossy_samples);
    if (pigment_sdl.empty()) pigment_sdl = "pigment { " + pov_rgb(pigment) + " }";
    return "texture { " + pigment_sdl + " finish { ambient 0" +
           emission_of(emission, pigment, pointer) + " brdf { " + brdf + " } } }";
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
    const glm::dvec3 le = glm::dvec3(s.emission);
    const std::string black = "texture { pigment { rgb 0 } finish { ambient 0 diffuse 0 } }";
    if (s.emission_texture) {
        // A textured emitter is no light (scenes/FORMAT.md): the direct integrator sees it
        // through camera and mirror rays only. POV-Ray's `emission` is multiplied by the
        // pigment: with the texture as the pigment and its multiplier as `emission`, the
        // surface shows exactly the emission, on its front only, and reflects nothing.
        if (m)
            fail(pointer + "/emission",
                 "a textured emission on a shape with a material: POV-Ray multiplies emission "
                 "by the pigment, which is the material's diffuse colour (export the emitter "
                 "without a material)");
        glm::dvec3 factor;
        const std::string pigment = uv_pigment(*s.emission_texture, pointer + "/emission", factor);
        std::string front = "texture { " + pigment + " finish { ambient 0 diffuse 0 emission " +
                            pov_rgb(factor) + " } }";
        std::string back = black;
        if (inside_front) std::swap(front, back);
        return front + "\n  interior_texture { " + back.substr(10, back.size() - 12) + " }";
    }
    const bool emits = std::max({le.x, le.y, le.z}) > 0.0;
    auto tex = [&](const glm::dvec3& e) {
        if (m && e == glm::dvec3(0.0) && !s.material)
            for (std::size_t i = 0; i < m_desc.materials.size(); ++i)
                if (m_desc.materials[i].first == s.material_ref)
                    return "texture { " + m_material_ids[i] + " }";
        if (m) return texture(*m, mpointer, e);
        if (!emits || e == glm::dvec3(0.0)) return black;
        return "texture { pigment { rgb 1 } finish { ambient 0 diffuse 0" +
               emission_of(e, glm::dvec3(1.0), pointer) + " } }";
    };
    // A null boundary is invisible from both sides, one-sided or not (the media kernel crosses
    // it without a vertex).
    if (m && is_pass_through(*m)) return tex(le);
    std::string front = tex(le);
    std::string back = s.two_sided ? tex(glm::dvec3(0.0)) : black;
    if (inside_front) std::swap(front, back);
    if (!emits && s.two_sided) return front;
    // interior_texture takes the body of a texture: strip "texture { ... }".
    return front + "\n  interior_texture { " + back.substr(10, back.size() - 12) + " }";
}

std::string PovWriter::media_sdl(const std::string& name, const std::string& pointer) const {
    std::size_t index = 0;
    while (index < m_desc.media.size() && m_desc.media[index].first != name) ++index;
    if (index >= m_media.size())
        throw std::logic_error("export_pov: unknown medium (build_scene checks the names)");
    const Medium& md = m_media[index];
    if (md.kind() != MediumKind::Homogeneous)
        fail("/media/" + detail::escape_pointer_token(name) + "/kind",
             "only homogeneous media are exported to POV-Ray");
    // POV-Ray's media emission is seen along rays but lights no surface (its media scatter
    // only light sources' light), where Facet's lights what its paths reach.
    if (md.emits())
        fail("/media/" + detail::escape_pointer_token(name) + "/emission",
             "an emitting medium cannot be exported exactly: POV-Ray's media emission lights no "
             "surface");
    auto rgb = [](const Rgb& c, double k) { return pov_rgb(glm::dvec3(c.r, c.g, c.b) * k); };
    // POV-Ray's constant media (interior/media.cpp): absorption is Facet's coefficient per
    // unit length. Its scattering adds Sc * k * (light colour at the point)
    // with k = 1 isotropic and k = (1 - g^2) / (1 + g^2 - 2 g cos)^1.5 for Henyey-Greenstein
    // (type 5, cos between the directions to the light and along the ray: g > 0 forward, as
    // Facet's), i.e. 4 pi times the normalised phase function; the light colour of a
    // physical_falloff light is I / (pi d^2) (light_units.h). So Sc = sigma_s / 4 reflects
    // sigma_s p(cos) I / d^2, and `extinction 4` keeps sigma_s as the extinction it adds.
    // Constant media are sampled at `intervals` equal steps with two samples each (no jitter):
    // exact for absorption, a quadrature of the lit scattering.
    std::ostringstream o;
    o << "media {  // " << pointer << " ('" << comment_text(name) << "')\n"
      << "    method 3 intervals " << m_opt.media_intervals << " samples 2, 2 jitter 0\n";
    if (md.sigma_a() != Rgb(0.f)) o << "    absorption " << rgb(md.sigma_a(), 1.0) << "\n";
    if (md.sigma_s() != Rgb(0.f))
        o << "    scattering { 5, " << rgb(md.sigma_s(), 0.25) << " eccentricity "
          << pov_num(md.phase().g()) << " extinction 4 }\n";
    o << "  }";
    return o.str();
}

std::string PovWriter::interior_sdl(const ShapeDesc& s, const std::string& pointer) const {
    std::string mpointer;
    const MaterialDesc* m = shape_material(s, pointer, mpointer);
    if (!m) return "";
    const std::string interior = interior_of(*m);
    if (interior.empty()) return is_pass_through(*m) ? "  hollow\n" : "";
    // POV-Ray computes an object's interior media only when it is hollow (and then its
    // atmosphere too: export_pov refuses a world medium with interiors).
    return "  hollow\n  interior { " + media_sdl(interior, mpointer + "/interior") + " }\n";
}

void ShapeOut::instance(const std::string& prototype) {
    m_w.m_out << "object { " << m_w.prototype_id(prototype) << "\n" << xf() << "}\n";
}

std::string PovWriter::prototype_id(const std::string& name) const {
    for (std::size_t p = 0; p < m_desc.prototypes.size(); ++p)
        if (m_desc.prototypes[p].first == name) return "FacetPrototype" + std::to_string(p);
    throw std::logic_error("export_pov: unknown prototype (build_scene checks the names)");
}

void PovWriter::shape(const ShapeDesc& s, const std::string& pointer) {
    ShapeOut out(*this, s, pointer);
    m_out << "// " << out.pointer << (s.name.empty() ? "" : " ('" + comment_text(s.name) + "')")
          << "\n";
    const ShapeKindDef& kind = shape_kind(s.kind);
    if (kind.pov) {
        kind.pov(out);
    } else {
        out.triangles(false);
    }
}

std::string PovWriter::write() {
    const CameraDesc& c = m_desc.camera;
    m_out << "// Exported by `facet export-pov` from " << comment_text(m_name)
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
    // The world medium: POV-Ray's atmospheric media, everywhere outside non-hollow objects.
    if (!m_desc.world_medium.empty())
        m_out << "// The world medium (/world_medium)\n"
              << media_sdl(m_desc.world_medium, "/world_medium") << "\n\n";
    materials();
    for (std::size_t i = 0; i < m_desc.lights.size(); ++i) {
        LightOut out(*this, m_desc.lights[i], i);
        light_kind(m_desc.lights[i].kind).pov(out);
    }
    m_out << "\n";
    // Prototypes: each declared once as a union of its shapes (written as any shapes are, in
    // the prototype's object space), placed by the instances' `object` statements.
    for (std::size_t p = 0; p < m_desc.prototypes.size(); ++p) {
        const auto& [pname, shapes] = m_desc.prototypes[p];
        const std::string pp = "/prototypes/" + detail::escape_pointer_token(pname);
        m_out << "// " << pp << "\n#declare " << prototype_id(pname) << " = union {\n";
        for (std::size_t k = 0; k < shapes.size(); ++k)
            shape(shapes[k], pp + "/" + std::to_string(k));
        m_out << "}\n";
    }
    for (std::size_t i = 0; i < m_desc.shapes.size(); ++i) {
        shape(m_desc.shapes[i], "/shapes/" + std::to_string(i));
        if (m_cells > kMaxLightCells)
            fail("/shapes/" + std::to_string(i) + "/emission",
                 fmt::format("the emitters need more than {} light cells at --area-grid {} "
                             "(every cell is a light with a shadow ray); lower --area-grid",
                             kMaxLightCells, m_opt.area_grid));
    }
    return m_out.str();
}

}  // namespace

// The first pixel whose centre ray leaves the scene (after crossing null boundaries), or -1.
// POV-Ray integrates its atmosphere along an escaping ray over an unbounded length
// (interior/media.cpp samples the ray up to POV-Ray's "infinite" distance), where Facet's
// integral converges: such pixels cannot be exported with a world medium.
long long first_escaping_pixel(const Scene& scene) {
    const Camera& cam = scene.camera();
    for (int y = 0; y < cam.height; ++y)
        for (int x = 0; x < cam.width; ++x) {
            Ray ray = cam.generate_ray({float(x) + 0.5f, float(y) + 0.5f});
            SurfaceHit hit;
            for (int crossing = 0;; ++crossing) {
                if (!scene.intersect(ray, hit)) return (long long)y * cam.width + x;
                const MediumInterface* mi = scene.medium_interface(hit.material);
                if (!mi || !mi->pass_through || crossing > 64) break;
                ray = Scene::spawn_ray(hit, ray.d);
            }
        }
    return -1;
}

void check_pov_options(const PovExportOptions& o) {
    (void)parse_radiosity(o.radiosity);
    if (o.area_grid < 1 || o.area_grid > 64)
        throw std::invalid_argument(
            fmt::format("--area-grid: must be in [1, 64] (got {})", o.area_grid));
    if (o.glossy_samples < 0 || o.glossy_samples > 10000)
        throw std::invalid_argument(
            fmt::format("--glossy-samples: must be in [0, 10000] (got {})", o.glossy_samples));
    if (o.blur_samples < 1 || o.blur_samples > 4096)
        throw std::invalid_argument(
            fmt::format("--blur-samples: must be in [1, 4096] (got {})", o.blur_samples));
    if (o.environment != "error" && o.environment != "background" && o.environment != "light")
        throw std::invalid_argument("--environment: expected error, background or light, got '" +
                                    o.environment + "'");
    if (o.environment == "light" && parse_radiosity(o.radiosity).count > 0)
        throw std::invalid_argument(
            "--environment light with --radiosity: radiosity gathers the sky_sphere's light too, "
            "so the sky would light diffuse surfaces twice");
    if (o.mipmap != "error" && o.mipmap != "linear")
        throw std::invalid_argument("--mipmap: expected error or linear, got '" + o.mipmap + "'");
    if (o.media_intervals < 1 || o.media_intervals > 200)
        throw std::invalid_argument(
            fmt::format("--media-intervals: must be in [1, 200] (got {})", o.media_intervals));
    if (o.sky_samples < 1 || o.sky_samples > 4096)
        throw std::invalid_argument(
            fmt::format("--sky-samples: must be in [1, 4096] (got {})", o.sky_samples));
}

std::string export_pov(const SceneDescription& desc, const std::string& name,
                       const PovExportOptions& options) {
    check_pov_options(options);
    // Validate everything the renderer would (ranges, names, meshes) before writing: the SDL is
    // only written for scenes that `facet render` accepts.
    const Scene scene = build_scene(desc, name);
    // Opacity (cut-outs) is not exported yet: POV-Ray's pigment transmit would blend where
    // Facet chooses stochastically (the same expectation), unchecked against it. Errors, never
    // a silent drop.
    // Motion blur: POV-Ray traces one instant (its clock is per frame, not per ray), so a scene
    // that moves with motion blur on has no SDL; with it off the still scene is exported.
    if (desc.render.motion_blur && desc.render.motion_blur->enabled) {
        std::string moving;
        if (!desc.camera.motion.empty()) moving = "/camera/motion";
        for (std::size_t i = 0; i < desc.shapes.size() && moving.empty(); ++i)
            if (!desc.shapes[i].motion.empty())
                moving = "/shapes/" + std::to_string(i) + "/motion";
            else if (!desc.shapes[i].motion_positions.empty())
                moving = "/shapes/" + std::to_string(i) + "/motion_positions";
        if (!moving.empty())
            throw SceneError(name + ": " + moving +
                             ": motion blur is not expressible in POV-Ray (it renders one "
                             "instant per frame); set /render/motion_blur/enabled to false to "
                             "export the still scene, or render with Facet");
    }
    // Film transparency and holdouts (FORMAT.md): POV-Ray's +UA alpha treats the background
    // alone, and it has no holdout; errors, never a silent drop.
    if (desc.render.film_transparent)
        throw SceneError(name +
                         ": /render/film_transparent: film transparency is not exported to "
                         "POV-Ray (set it to false to export the opaque scene, or render with "
                         "Facet)");
    for (std::size_t i = 0; i < desc.shapes.size(); ++i) {
        if (desc.shapes[i].holdout)
            throw SceneError(name + ": /shapes/" + std::to_string(i) +
                             "/holdout: a holdout cannot be exported to POV-Ray (render with "
                             "Facet)");
        if (desc.shapes[i].shadow_catcher)
            throw SceneError(name + ": /shapes/" + std::to_string(i) +
                             "/shadow_catcher: a shadow catcher cannot be exported to POV-Ray "
                             "(render with Facet)");
        // Ray visibility and Light Path switches (FORMAT.md): POV-Ray's no_image, no_shadow
        // and no_reflection are other rules; errors, never a silent drop.
        if (desc.shapes[i].visibility != kRayAll)
            throw SceneError(name + ": /shapes/" + std::to_string(i) +
                             "/visibility: ray visibility cannot be exported to POV-Ray "
                             "(render with Facet)");
        if (!desc.shapes[i].light_path.empty())
            throw SceneError(name + ": /shapes/" + std::to_string(i) +
                             "/light_path: Light Path switches cannot be exported to POV-Ray "
                             "(render with Facet)");
    }
    // Media (docs/povray.md, "Media"): POV-Ray's media scatter the lights' light once and its
    // surfaces see direct light only, which is Facet's media kernel at max_depth 1 (a path
    // with media is traced whichever integrator is asked).
    std::string interior_pointer;  // the first material with an interior medium
    auto no_opacity = [&](const MaterialDesc& m, const std::string& pointer) {
        for (const char* key : {"opacity", "alpha_cutoff"})
            if (m.params.has(key) || m.textures.count(key))
                throw SceneError(name + ": " + pointer + "/" + key +
                                 ": opacity (cut-outs) cannot be exported to POV-Ray exactly "
                                 "yet (remove it, or render with Facet)");
        if (m.params.has("interior") && interior_pointer.empty())
            interior_pointer = pointer + "/interior";
    };
    for (const auto& [mname, m] : desc.materials)
        no_opacity(m, "/materials/" + detail::escape_pointer_token(mname));
    for (std::size_t i = 0; i < desc.shapes.size(); ++i)
        if (desc.shapes[i].material)
            no_opacity(*desc.shapes[i].material, "/shapes/" + std::to_string(i) + "/material");
    for (const auto& [pname, shapes] : desc.prototypes)
        for (std::size_t k = 0; k < shapes.size(); ++k)
            if (shapes[k].material)
                no_opacity(*shapes[k].material, "/prototypes/" +
                                                    detail::escape_pointer_token(pname) + "/" +
                                                    std::to_string(k) + "/material");
    const std::string media_pointer =
        !desc.world_medium.empty() ? "/world_medium" : interior_pointer;
    if (!media_pointer.empty()) {
        if (desc.render.max_depth != 1)
            throw SceneError(name + ": /render/max_depth: media (" + media_pointer +
                             ") are exported with max_depth 1 only: POV-Ray's media scatter "
                             "light once and its surfaces see direct light, which is Facet's "
                             "path with media at max_depth 1 (got " +
                             std::to_string(desc.render.max_depth) + ")");
        if (!desc.world_medium.empty()) {
            const Camera& cam = scene.camera();
            if (const long long px = first_escaping_pixel(scene); px >= 0)
                throw SceneError(fmt::format(
                    "{}: /world_medium: the camera ray of pixel ({}, {}) leaves the scene, and "
                    "POV-Ray's atmosphere would integrate it over an unbounded length: close "
                    "the scene around the camera's view (or put the medium inside a null "
                    "boundary's interior)",
                    name, px % cam.width, px / cam.width));
            for (const LightDesc& l : desc.lights)
                if (l.kind == LightKind::Environment)
                    throw SceneError(name +
                                     ": /world_medium: an environment light seen through a "
                                     "world medium (POV-Ray's sky would be attenuated over an "
                                     "unbounded length)");
        }
        if (!desc.world_medium.empty() && !interior_pointer.empty())
            throw SceneError(name + ": " + interior_pointer +
                             ": an interior medium in a scene with a world medium: POV-Ray "
                             "computes interior media only in hollow objects, which its "
                             "atmosphere fills too, where Facet's interior replaces the world "
                             "medium");
        if (parse_radiosity(options.radiosity).count > 0)
            throw std::invalid_argument("--radiosity: not with media (" + media_pointer +
                                        "): POV-Ray's radiosity ignores media");
    }
    return PovWriter(desc, name, options, scene.media()).write();
}

void export_pov_file(const SceneDescription& desc, const std::string& name, const std::string& path,
                     const PovExportOptions& options, const std::string& ini_path) {
    const std::string text = export_pov(desc, name, options);
    std::ofstream f(path);
    if (!(f << text)) throw std::runtime_error(path + ": cannot write");
    if (ini_path.empty()) return;
    std::ofstream ini(ini_path);
    if (!(ini << "; povray-facet settings for " << path << " (facet export-pov)\n"
              << "Input_File_Name=" << path << "\n"
              << "Width=" << desc.camera.width << "\nHeight=" << desc.camera.height << "\n"
              << "Antialias=Off\nOutput_File_Type=E\nBits_Per_Color=32\nOutput_Alpha=Off\n"
              << "Display=Off\n"))
        throw std::runtime_error(ini_path + ": cannot write");
}

}  // namespace facet::render
