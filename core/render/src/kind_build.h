// Private to facet_render: what a shape, light or medium kind's builder (kinds.h) gets from
// build_scene. The builder implements it (scene_builder.h: ShapeContext in build_shapes.cpp,
// LightContext in build_lights.cpp, MediumContext in build_materials.cpp); the kind units
// (shapes/*.cpp, lights/*.cpp, media/*.cpp) call it.
//
// Conventions: every check fails with a SceneError naming the JSON pointer (`ptr` + "/key"),
// as build_scene's other errors do. The common keys (material, emission, two_sided,
// transform, flip_normals) are already checked when a kind's build runs.
#pragma once

#include <glm/gtc/matrix_transform.hpp>
#include <glm/mat3x3.hpp>
#include <glm/mat4x4.hpp>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <string>

#include "facet/render/kinds.h"
#include "facet/render/light.h"
#include "facet/render/medium.h"
#include "facet/render/mesh.h"
#include "scene_checks.h"
#include "scene_impl.h"

namespace facet::render {

// Value checks shared by build_scene and the kinds' builders: each fails through fail().
// A kind's own material parameters (e.g. glTF's base colour, metallic, roughness) and the one
// function that maps them onto a core model's (TexturedMaterial::convert): each source may be a
// constant or a texture, as a model parameter may.
struct MaterialConversion {
    std::vector<ParamInfo> sources;  // names and types (colour or number) of the sources
    TexturedMaterial::Convert convert;
    // The same map on values, for the staged per-hit build (TexturedMaterial::convert_values):
    // the model parameters it sets that the sources change, in its outputs' order.
    std::vector<std::string> outputs = {};
    TexturedMaterial::ConvertValues convert_values = nullptr;
};

class BuildChecks {
  public:
    virtual ~BuildChecks() = default;
    [[noreturn]] virtual void fail(const std::string& pointer,
                                   const std::string& message) const = 0;

    void check_finite(const Vec3& v, const std::string& ptr) const {
        for (int i = 0; i < 3; ++i) {
            if (!std::isfinite(v[i]))
                fail(ptr + "/" + std::to_string(i), "must be a finite number");
        }
    }
    void check_finite(double d, const std::string& ptr) const {
        if (!std::isfinite(d)) fail(ptr, "must be a finite number");
    }
    double check_range(double d, const std::string& ptr, double lo, double hi,
                       const char* range_text) const {
        check_finite(d, ptr);
        if (!(d >= lo && d <= hi)) fail(ptr, detail::number_range_message(d, range_text));
        return d;
    }
    std::int64_t check_int(std::int64_t i, const std::string& ptr, std::int64_t lo,
                           std::int64_t hi) const {
        if (i < lo || i > hi) fail(ptr, detail::int_range_message(i, lo, hi));
        return i;
    }
    // Finite and non-zero; returns the unit vector.
    Vec3 unit_direction(const Vec3& d, const std::string& ptr) const {
        check_finite(d, ptr);
        const float len = glm::length(d);
        if (!(len > 0.f) || !std::isfinite(len)) fail(ptr, "must be a non-zero direction");
        return d / len;
    }
    // Finite and >= 0 in every channel.
    Rgb check_color(const Rgb& c, const std::string& ptr, const char* what) const {
        if (!is_finite(c)) fail(ptr, std::string(what) + " must be finite");
        for (int i = 0; i < 3; ++i) {
            if (c[i] < 0.f) fail(ptr, std::string(what) + " must be >= 0");
        }
        return c;
    }
    // A length in (0, float max].
    double positive_length(double r, const std::string& ptr) const {
        const double v = check_range(r, ptr, 0.0, double(std::numeric_limits<float>::max()), "> 0");
        if (!(v > 0.0)) fail(ptr, "must be > 0");
        return v;
    }
};

class ShapeBuild : public BuildChecks {
  public:
    ShapeBuild(const ShapeDesc& s, std::uint32_t i, std::string p)
        : shape(s), index(i), ptr(std::move(p)) {}
    const ShapeDesc& shape;
    // In Scene::shapes(): the description's "shapes" index, or after them a prototype's shape.
    const std::uint32_t index;
    const std::string ptr;  // "/shapes/<index>" or "/prototypes/<name>/<k>"
    Rgb emission{0.f};      // checked
    bool emissive = false;
    glm::dmat4 xf{1.0};  // object to world (checked: finite, affine, not singular)
    // The shape's `motion_positions` render (motion blur on): a deforming kind (mesh, curves)
    // builds its steps through `xf` (the shape is then in a prototype of its own, xf its
    // object space). Without it they are only checked.
    bool deform = false;

    // "/shapes/3" or "/shapes/3 ('Suzanne')".
    virtual std::string place() const = 0;
    // Counts triangles against the scene's limit before they are generated.
    virtual void reserve_triangles(std::uint64_t n, const std::string& ptr) = 0;
    virtual bool files_allowed() const = 0;
    virtual const std::string& base_dir() const = 0;

    // An exact analytic primitive (unit sphere / unit disc in object space) placed by
    // xf * local; returns it with its world transforms filled.
    virtual const AnalyticPrim& add_prim(AnalyticPrim::Kind kind, const glm::dmat4& local) = 0;
    // An infinite plane through a point with a unit normal, in object space.
    virtual void add_plane(const glm::dvec3& point, const Vec3& unit_normal) = 0;
    // Object-space triangles: the builder transforms them, keeps the authored front side,
    // validates them, drops zero-area triangles and makes an emitter of them when the shape
    // emits. `tangent` (object space, 0 = none) orients anisotropic lobes. UVs, when the shape
    // needs them, come from the mesh's `uvs`, or with `sphere` (the unit sphere's placement in
    // object space) from the hit point's direction as on an analytic sphere.
    virtual void add_triangles(TriangleMesh mesh, const Vec3& tangent,
                               const glm::dmat4* sphere = nullptr) = 0;
    // Kinds with their own materials (ShapeKindDef::own_materials, e.g. gltf): builds one of
    // them through the core's registry (errors name `ptr`, e.g. "/shapes/2/file"), once per
    // material however many parts use it; returns its material, textured material and opacity
    // as a surface for add_part (the kind fills the rest).
    // With `conversion`, the material's parameters and textures are the kind's own
    // (MaterialConversion), converted onto the model's at build time and at every hit.
    virtual ShapeSurface add_material(const MaterialDesc& material, const std::string& ptr,
                                      const MaterialConversion* conversion = nullptr) = 0;
    // A texture of the kind's own (e.g. a glTF emissive texture), as a material's textures
    // are built (texture.h; errors name `ptr`); `radiance`: negative texels are errors.
    virtual const Texture* add_texture(const TextureDesc& texture, const std::string& ptr,
                                       bool color, bool radiance) = 0;
    // Whether textured material `textured` (ShapeSurface::textured) reads the hit's uv
    // (TexturedMaterial::uses_uv; a vertex colour alone does not).
    virtual bool textured_uses_uv(std::int32_t textured) const = 0;
    // Object-space triangles as one part of the shape with its own surface (material, emission,
    // sidedness; `surface.light` is filled here): as add_triangles otherwise.
    virtual void add_part(TriangleMesh mesh, ShapeSurface surface) = 0;
    // Places prototype `of` (SceneDescription::prototypes) by the shape's transform `xf`
    // (kind "instance"); errors name `of_ptr`: an unknown name, an instance inside a prototype.
    virtual void add_instance(const std::string& of, const std::string& of_ptr) = 0;
    // Kinds that share their own meshes (gltf: a mesh that several nodes use). Whether the
    // shape may (not inside a prototype: one level of instancing); a new prototype of the
    // shape; a part of it in its own frame (as add_part, but stored once); a placement of it
    // (`local`: its frame to the shape's object space; the shape's transform applies after).
    virtual bool can_instance() const = 0;
    virtual std::uint32_t add_local_prototype() = 0;
    virtual void add_part_to(std::uint32_t prototype, TriangleMesh mesh, ShapeSurface surface) = 0;
    virtual void place_prototype(std::uint32_t prototype, const glm::dmat4& local) = 0;
    // A warning for BuildReport::warnings and Scene::warnings() (what the kind approximates).
    virtual void warn(std::string message) = 0;
    // A curves shape's geometry (shapes/curves.cpp): checked against the shape's surface (no
    // vertex colours, normal map or cut-out; root UVs when textured) and added, in the space
    // `xf` maps to, with its extent there (`extent`) and in object space (`object_extent`).
    virtual void add_curves(CurveGeom curves, const Bounds3& extent,
                            const Bounds3& object_extent) = 0;
    // The shape's area light (emissive analytic shapes).
    virtual void add_light(Light light) = 0;
    // Checks the shape's world extent (after its geometry is added).
    virtual void check_finite_bounds() = 0;

    // An analytic primitive at the shape's "center", scaled by its "radius" (both checked) and
    // oriented by `rotation` (its columns: the object axes), with its extent checked.
    const AnalyticPrim& add_centred_prim(AnalyticPrim::Kind kind,
                                         const glm::dmat4& rotation = glm::dmat4(1.0)) {
        check_finite(shape.center, ptr + "/center");
        const double r = positive_length(shape.radius, ptr + "/radius");
        const glm::dmat4 at = glm::translate(glm::dmat4(1.0), glm::dvec3(shape.center));
        const AnalyticPrim& prim = add_prim(kind, glm::scale(at * rotation, glm::dvec3(r)));
        check_finite_bounds();
        return prim;
    }
};

// What a medium kind's builder gets.
class MediumBuild : public BuildChecks {
  public:
    virtual bool files_allowed() const = 0;           // SceneLimits::allow_files
    virtual const std::string& base_dir() const = 0;  // resolves relative grid files

    // A medium's coefficients and anisotropy, checked: sigma_a and sigma_s, or Cycles'
    // Principled Volume keys converted by cycles_volume(). `density_needed`: a homogeneous
    // medium takes the Cycles keys only with "density"; a grid's density is a factor that
    // defaults to 1, so any Cycles key selects them.
    struct Coefficients {
        Rgb sigma_a, sigma_s;
        float g;
    };
    Coefficients coefficients(const MediumDesc& m, const std::string& ptr, bool density_needed,
                              const char* density_range) const {
        Coefficients c;
        c.g = float(check_range(m.g, ptr + "/g", -HenyeyGreenstein::kMaxAbsG,
                                HenyeyGreenstein::kMaxAbsG,
                                "in [-0.999, 0.999] (Henyey-Greenstein anisotropy)"));
        const bool cycles = m.density || (!density_needed && (m.color || m.absorption_color));
        if (!cycles) {
            const char* cycles_only = "is a Cycles key: give it with \"density\"";
            if (m.color) fail(ptr + "/color", cycles_only);
            if (m.absorption_color) fail(ptr + "/absorption_color", cycles_only);
            c.sigma_a = check_color(m.sigma_a, ptr + "/sigma_a", "an absorption coefficient");
            c.sigma_s = check_color(m.sigma_s, ptr + "/sigma_s", "a scattering coefficient");
            return c;
        }
        if (m.sigma_a != Vec3(0.f) || m.sigma_s != Vec3(0.f))
            fail(ptr + (m.sigma_a != Vec3(0.f) ? "/sigma_a" : "/sigma_s"),
                 "give either sigma_a and sigma_s or Cycles' density and colours, not both");
        const double density =
            check_range(m.density.value_or(1.0), ptr + "/density", 0.0, 1e30, density_range);
        const Rgb color = check_color(m.color.value_or(Vec3(0.5f)), ptr + "/color", "a colour");
        const Rgb absorption = check_color(m.absorption_color.value_or(Vec3(0.f)),
                                           ptr + "/absorption_color", "a colour");
        const MediumCoefficients k = cycles_volume(density, color, absorption);
        c.sigma_a = k.sigma_a;
        c.sigma_s = k.sigma_s;
        return c;
    }
};

class LightBuild : public BuildChecks {
  public:
    LightBuild(const LightDesc& l, std::string p) : light(l), ptr(std::move(p)) {}
    const LightDesc& light;
    const std::string ptr;                            // "/lights/<index>"
    virtual bool files_allowed() const = 0;           // SceneLimits::allow_files
    virtual const std::string& base_dir() const = 0;  // resolves relative image files
    virtual void add_light(Light light) = 0;
    // The scene's environment light (at most one).
    virtual void add_environment(Light light) = 0;
    // A warning for BuildReport::warnings and Scene::warnings() (what the kind approximates).
    virtual void warn(std::string message) = 0;
    // The unit direction a spot or area light points along: its "direction", or toward its
    // "look_at" from `position` (exactly one is given: the reader checks).
    Vec3 aim(const Vec3& position) const {
        if (light.direction.has_value() == light.look_at.has_value())
            fail(ptr, "give exactly one of \"direction\" and \"look_at\"");
        if (light.direction) return unit_direction(*light.direction, ptr + "/direction");
        check_finite(*light.look_at, ptr + "/look_at");
        const float len = glm::length(*light.look_at - position);
        if (!(len > 0.f)) fail(ptr + "/look_at", "must differ from the position");
        return (*light.look_at - position) / len;
    }
    // A point or spot light's "radius" (kLightRadiusField), checked: finite, >= 0; 0 if absent.
    float light_radius() const {
        if (!light.radius) return 0.f;
        return float(check_range(*light.radius, ptr + "/radius", 0.0,
                                 double(std::numeric_limits<float>::max()), ">= 0"));
    }
    // A point or spot light's "radius_model" (kLightRadiusModelField): sphere if absent.
    RadiusModel radius_model() const {
        const std::string& m = light.radius_model;
        if (m.empty() || m == "sphere") return RadiusModel::Sphere;
        if (m != "cycles34_disc")
            fail(ptr + "/radius_model",
                 "unknown radius model '" + m + "' (expected sphere or cycles34_disc)");
        return RadiusModel::Cycles34Disc;
    }
    // A directional light's "angle_model": uniform if absent.
    SunAngleModel angle_model() const {
        const std::string& m = light.angle_model;
        if (m.empty() || m == "uniform") return SunAngleModel::Uniform;
        if (m != "cycles34")
            fail(ptr + "/angle_model",
                 "unknown angle model '" + m + "' (expected uniform or cycles34)");
        return SunAngleModel::Cycles34;
    }
};

// The "radius" key of the point and spot kinds (the sphere light, light.h).
inline const Field<LightDesc> kLightRadiusField = {
    "radius",
    FieldType::Number,
    false,
    &LightDesc::radius,
    "0",
    "radius of the emitting sphere (or disc, see radius_model) in scene units, >= 0 "
    "(0: a point)"};

// The "radius_model" key of the point and spot kinds (RadiusModel, lights/point.h).
inline const Field<LightDesc> kLightRadiusModelField = {
    "radius_model",
    FieldType::Text,
    false,
    &LightDesc::radius_model,
    "sphere",
    "what a light with a radius is: `sphere` (a sphere of uniform radiance, Cycles 4) or "
    "`cycles34_disc` (Blender 3.4's Cycles: a disc of the radius centred on the light, facing "
    "each lit point; on-axis irradiance I₀ / (d² + R²))"};

}  // namespace facet::render
