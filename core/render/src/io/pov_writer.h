// Private to facet_render: what a shape or light kind's POV-Ray exporter (kinds.h `pov`) gets
// from the SDL writer (pov_export.cpp), and the SDL number format they share.
#pragma once

#include <glm/vec3.hpp>

#include <ostream>
#include <string>

#include "facet/render/kinds.h"
#include "facet/render/pov_export.h"

namespace facet::render {

// Shortest text that reads back as the same double; "<x, y, z>"; "rgb <r, g, b>".
std::string pov_num(double v);
std::string pov_vec(const glm::dvec3& v);
std::string pov_rgb(const glm::dvec3& c);
// " media_attenuation on" for the light sources of a scene with media (POV-Ray's default is
// off: a light would reach a point unattenuated by the media between), else "".
inline const char* media_keywords_for(bool media) {
    return media ? " media_attenuation on" : "";
}

class PovShapeOut {
  public:
    PovShapeOut(const ShapeDesc& s, std::string p, bool e, bool uv)
        : shape(s), pointer(std::move(p)), emits(e), reads_uv(uv) {}
    virtual ~PovShapeOut() = default;
    const ShapeDesc& shape;
    const std::string pointer;  // "/shapes/<index>" or "/prototypes/<name>/<k>"
    const bool emits;
    // The shape's material (or emission) reads an image or checker through the hit's UVs: the
    // SDL's pigments are then `uv_mapping`, so the object must carry the core's UVs (mesh2
    // uv_vectors, or a sphere whose POV-Ray UVs are the core's: sphere.cpp), or fail_uv().
    const bool reads_uv;

    [[noreturn]] virtual void fail(const std::string& pointer,
                                   const std::string& message) const = 0;
    // Writes `head` (an SDL object without its closing brace, e.g. "sphere { <0, 0, 0>, 1"),
    // the shape's texture, no_shadow / no_radiosity for emitters, its transform and "}", and an
    // emitter's black radiosity twin. inside_front: the shape's front is POV-Ray's inside
    // (a sphere or box with flip_normals).
    virtual void object(const std::string& head, bool inside_front) = 0;
    // Writes the shape as a mesh2 of its kind's `triangles` in world space, and an emitter's
    // light cells (N^2 per triangle; N x N over a flat parallelogram when
    // `parallelogram_cells` and the shape is two triangles).
    virtual void triangles(bool parallelogram_cells) = 0;
    // An emitter's light as cells: begin_cells() writes the comment, then one cell_light per
    // cell (a cos-weighted spotlight of a Lambertian patch of `area`, world space).
    virtual void begin_cells() = 0;
    virtual void cell_light(const glm::dvec3& p, const glm::dvec3& n, const glm::dvec3& radiance,
                            double area) = 0;
    virtual int area_grid() const = 0;
    // The error for a textured shape of a kind whose POV-Ray object has no UVs equal to the
    // core's; `why` says what POV-Ray's object lacks. Throws (through fail).
    void fail_uv(const std::string& why) const {
        fail(pointer + (shape.emission_texture ? "/emission" : "/material"),
             "a texture read through UVs cannot be exported on this shape kind: " + why +
                 " (use a mesh, quad, grid, box or sphere, or render with Facet)");
    }
    // An instance: `object { <the prototype's declared union> <the shape's transform> }`
    // (export_pov declares each prototype once, its shapes written as any shapes are).
    virtual void instance(const std::string& prototype) = 0;
};

class PovLightOut {
  public:
    PovLightOut(const LightDesc& l, std::string p, const PovExportOptions& o, std::string dir,
                bool media)
        : light(l), pointer(std::move(p)), options(o), base_dir(std::move(dir)), in_media(media) {}
    virtual ~PovLightOut() = default;
    const LightDesc& light;
    const std::string pointer;  // "/lights/<index>"
    const PovExportOptions& options;
    const std::string base_dir;  // resolves relative image files (SceneDescription::base_dir)
    // The scene has media: every light_source ends with media_keywords(), so that its light
    // is attenuated by the media it crosses as Facet's shadow rays are.
    const bool in_media;
    [[noreturn]] virtual void fail(const std::string& pointer,
                                   const std::string& message) const = 0;
    virtual std::ostream& out() = 0;
    const char* media_keywords() const { return media_keywords_for(in_media); }
    // Point and spot lights: a sphere light (radius > 0) has no exact POV-Ray equivalent.
    void check_no_radius() const {
        if (light.radius && *light.radius > 0.0)
            fail(pointer + "/radius",
                 "POV-Ray has no sphere light of uniform radiance (its area_light is a grid of "
                 "point lights): only radius 0 is exported exactly");
    }
};

}  // namespace facet::render
