// SceneDescription: the plain-data scene every front end fills or reads — the JSON reader and
// writer (scenes/FORMAT.md version 1), the Python module (numpy arrays), the Blender addon and
// `facet export-pov` — and build_scene(), the one route from a description to a renderable
// Scene.
//
// Conventions:
//  - The vocabulary is the scene format's, field for field (scenes/FORMAT.md): units, colours,
//    degrees, front sides and defaults are exactly as documented there. A default-constructed
//    field means the format's default.
//  - Nothing here is validated when it is filled. build_scene() validates everything and throws
//    SceneError("<name>: <path>: <message>"), where <path> is the JSON pointer of the offending
//    value as the JSON writer would place it ("/shapes/3/indices/17", "/materials/gold/alpha",
//    "/lights/0/power"); for shapes it adds the shape's name when it has one
//    ("/shapes/3 ('Suzanne'): ..."). A description read from JSON therefore reports the same
//    pointers as the file.
//  - Mesh arrays are spans: over the description's own storage (MeshData::copy_of, the JSON
//    reader), or over a caller's arrays (numpy, Blender) kept alive by `owner` or by the caller
//    until build_scene() returns. build_scene() never keeps a pointer into them.
//  - Transforms are object-to-world affine matrices in double precision (column vectors, glm
//    layout m[column][row]); the JSON reader composes the file's transform list into one.
//  - operator== compares every field by value (mesh arrays by content): read -> write -> read
//    gives an equal description.
#pragma once

#include <array>
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "facet/registry.h"
#include "facet/render/medium.h"
#include "facet/render/scene.h"
#include "facet/render/texture.h"
#include "facet/types.h"

namespace facet::render {

struct CameraDesc {
    Vec3 position{0.f};
    Vec3 look_at{0.f, 0.f, -1.f};
    Vec3 up{0.f, 1.f, 0.f};
    double fov = 40.0;  // full vertical field of view, degrees (perspective only)
    int width = 0, height = 0;
    std::string type = "perspective";     // or "orthographic"
    std::optional<double> scale;          // orthographic: extent of the larger image side
    double shift_x = 0.0, shift_y = 0.0;  // lens shift, fractions of the larger image side
    // Thin lens (scenes/FORMAT.md): aperture_radius (scene units), or fstop with focal_length
    // (mm): radius = focal_length / 1000 / (2 fstop), scene units taken as metres (Cycles).
    // None of them, or a zero radius, is the pinhole.
    std::optional<double> aperture_radius, fstop, focal_length;
    std::optional<double> focus_distance;  // along the view direction; required with a lens
    int blades = 0;                        // 0 = round, else >= 3 (polygonal aperture)
    double rotation = 0.0;                 // polygon rotation, degrees
    // Camera motion (scenes/FORMAT.md, "Motion blur"): the camera's position, look_at and up
    // at each of >= 2 uniform steps over the open shutter. Rendered only with motion blur on,
    // instead of position, look_at and up (which are the still camera).
    struct Step {
        Vec3 position{0.f};
        Vec3 look_at{0.f, 0.f, -1.f};
        Vec3 up{0.f, 1.f, 0.f};
        bool operator==(const Step&) const = default;
    };
    std::vector<Step> motion;
    bool operator==(const CameraDesc&) const = default;
};

struct MaterialDesc {
    std::string model;  // a name of the core's model table (facet::model_table())
    ParamSet params;    // constant parameters
    // Parameters given as textures (texture.h) instead of constants; a name is in `params` or
    // here, never both.
    std::map<std::string, TextureDesc> textures;
    // "normal_map": a tangent-space normal map, +Y up, read linearly (a texture whose RGB c
    // gives the tangent-space normal 2c - 1), and its strength (>= 0; 0 = no map). JSON: the
    // texture's keys plus "strength" and "xy_scale" (glTF's normalTexture.scale: multiplies
    // the map's x and y before the frame; scenes/FORMAT.md, "Normal maps").
    struct NormalMap {
        TextureDesc texture;
        double strength = 1.0;
        double xy_scale = 1.0;
        bool operator==(const NormalMap&) const = default;
    };
    std::optional<NormalMap> normal_map;
    // "bump": a height texture (a number texture, scene units), Blender's Bump distance d (the
    // heights' multiplier) and strength s (>= 0; 0 = no bump: n'' = normalize(s n' + (1 - s)
    // n)); scenes/FORMAT.md, "Bump maps". JSON: the texture's keys plus "distance" and
    // "strength".
    struct Bump {
        TextureDesc texture;
        double distance = 1.0;
        double strength = 1.0;
        bool operator==(const Bump&) const = default;
    };
    std::optional<Bump> bump;
    // The sub-materials of a combination (mix, add: the "materials" key), in order. A
    // sub-material given by name has only `ref` set (the name in SceneDescription::materials);
    // an inline one has its model and no `ref`.
    std::vector<MaterialDesc> materials =
        {};  // (initialisers: aggregate {model, params} stays warning-free)
    std::string ref = {};
    bool operator==(const MaterialDesc&) const = default;
};

// Flat triangle-mesh arrays: positions x0 y0 z0 x1 ..., 3 indices per triangle, normals empty
// or one per position, uvs empty or one (u, v) pair per position (u0 v0 u1 v1 ...), tangents
// empty or 4 floats per position (x y z and the bitangent sign, glTF's TANGENT: mesh.h).
struct MeshData {
    std::span<const float> positions;
    std::span<const std::uint32_t> indices;
    std::span<const float> normals;
    std::shared_ptr<const void> owner;  // keeps the arrays alive (may be null: see conventions)
    std::span<const float> uvs;         // after `owner`: MeshData{p, i, n, owner} still works
    std::span<const float> tangents;
    // Vertex colours: 3 (linear RGB) or 4 (linear RGBA) floats per position, each in [0, 1]
    // (scenes/FORMAT.md, "Vertex colours"); the count says which.
    std::span<const float> colors = {};

    // A mesh that owns copies of (or takes) the given arrays.
    static MeshData copy_of(std::vector<float> positions, std::vector<std::uint32_t> indices,
                            std::vector<float> normals = {}, std::vector<float> uvs = {},
                            std::vector<float> tangents = {}, std::vector<float> colors = {});
    std::size_t num_vertices() const { return positions.size() / 3; }
    std::size_t num_triangles() const { return indices.size() / 3; }
    bool operator==(const MeshData& o) const;
};

// The arrays of a curves shape (scenes/FORMAT.md, "Curves"; shapes/curves.cpp): control points
// x0 y0 z0 x1 ..., their radius (one number for all of them, or one per point), the number of
// control points of each strand in order (empty: one strand of all of them), optionally one
// (u, v) texture coordinate per strand (its root's) and optionally one random value per strand
// in [0, 1] (empty: curve_random of the strand's index; scene.h).
struct CurveData {
    std::vector<float> points;
    std::vector<float> radius;
    std::vector<std::uint32_t> counts;
    std::vector<float> root_uvs;
    std::vector<float> strand_random;
    std::size_t num_points() const { return points.size() / 3; }
    bool operator==(const CurveData&) const = default;
};

// One element of "shapes". Only the fields of `kind` are read (the table in FORMAT.md).
struct ShapeDesc {
    ShapeKind kind = ShapeKind::Mesh;
    std::string name;  // "" = none
    // The "materials" key (material_ref), or an inline material, or neither (emissive shapes
    // only: they reflect nothing).
    std::string material_ref;
    std::optional<MaterialDesc> material;
    Rgb emission{0.f};
    std::optional<TextureDesc> emission_texture;  // instead of `emission` (texture.h)
    bool two_sided = true;
    bool flip_normals = false;
    // A holdout (Blender's object Holdout, Cycles' is_holdout): where camera rays (directly or
    // through transparent surfaces) hit it, the pixel becomes transparent (alpha 0, colour 0);
    // other rays see its material as usual (scenes/FORMAT.md, "Film transparency and
    // holdouts").
    bool holdout = false;
    // A shadow catcher (Blender's object Shadow Catcher, Cycles 3.4's is_shadow_catcher): where
    // camera rays (directly or through transparent surfaces) hit it, the image keeps only the
    // shadows and darkening that the other objects cast on it, as alpha over a transparent film
    // or over the environment in an opaque one; other rays see it as an ordinary object
    // (scenes/FORMAT.md, "Shadow catchers").
    bool shadow_catcher = false;
    // Ray visibility (Blender's Object > Visibility > Ray Visibility; scenes/FORMAT.md "Ray
    // visibility"): the RayVisibility bits (scene.h) of the kinds of ray that see the shape.
    std::uint8_t visibility = kRayAll;
    // Light Path switches (Blender's Light Path node as a Mix Shader's Fac; scenes/FORMAT.md
    // "Light Path switches"): in order, the first entry whose ray output is 1 for a ray gives
    // that ray's hit the entry's material and emission instead of the shape's.
    struct LightPathEntry {
        std::uint8_t ray = 0;                  // one LightPathRay bit (scene.h)
        std::optional<MaterialDesc> material;  // a name (`ref`) or inline; none: black
        Rgb emission{0.f};                     // radiance, front side only
        bool operator==(const LightPathEntry&) const = default;
    };
    std::vector<LightPathEntry> light_path;
    std::optional<glm::dmat4> transform;  // object to world; none = identity
    // Transformation motion (scenes/FORMAT.md, "Motion blur"): the object-to-world transform
    // at each of >= 2 uniform steps over the open shutter; with motion blur on it replaces
    // `transform` (the still placement). Triangle kinds and instances only.
    std::vector<glm::dmat4> motion;
    // Deformation motion (mesh kind from arrays or a file; scenes/FORMAT.md, "Motion blur"):
    // the vertex positions at each of >= 2 uniform steps over the open shutter, each a flat
    // array of 3n floats in object space (n: the mesh's vertex count, the same indices), and,
    // exactly when the mesh has normals, its vertex normals per step likewise. With motion blur
    // on they replace the mesh's still positions (and normals); with `motion` too, both have
    // the same step count.
    std::vector<std::vector<float>> motion_positions;
    std::vector<std::vector<float>> motion_normals;
    // The texture space of procedural textures' Generated coordinates (texture.h): its centre
    // and half size in object space (Blender's texspace_location, texspace_size); none = the
    // shape's object-space bounding box (a zero half size counts as 1, as Blender's).
    struct TextureSpace {
        Vec3 location{0.f}, size{1.f};
        bool operator==(const TextureSpace&) const = default;
    };
    std::optional<TextureSpace> texture_space;

    Vec3 center{0.f};                         // sphere, disc, icosphere
    double radius = 1.0;                      // sphere, disc, icosphere
    Vec3 point{0.f};                          // plane
    Vec3 normal{0.f, 0.f, 1.f};               // plane, disc (need not be unit)
    Vec3 min{-1.f}, max{1.f};                 // box
    std::array<Vec3, 4> vertices{};           // quad
    MeshData mesh;                            // mesh from arrays
    std::string file;                         // mesh from an .obj/.ply file (instead of arrays)
    int subdivisions = 0;                     // icosphere
    bool smooth = true;                       // icosphere
    int nx = 1, ny = 1;                       // grid
    double amplitude = 0.0, frequency = 0.0;  // grid
    std::string of;                           // instance: the prototype's name
    CurveData curves;                         // curves
    std::string basis;                        // curves: linear | bspline | catmull_rom
    std::string profile;                      // curves: round | flat ("" = round)

    bool operator==(const ShapeDesc&) const = default;
};

enum class LightKind : std::uint8_t { Point, Spot, Directional, Environment, Area, SkyNishita };

// A rotation by `angle` degrees about `axis` (need not be unit; right-handed: counter-clockwise
// seen from the axis' tip). JSON: {"axis": [x, y, z], "angle": degrees}.
struct AxisAngle {
    Vec3 axis{0.f, 0.f, 1.f};
    double angle = 0.0;
    bool operator==(const AxisAngle&) const = default;
};

// One element of "lights".
struct LightDesc {
    LightKind kind = LightKind::Point;
    Vec3 position{0.f};                 // point, spot
    std::optional<Vec3> direction;      // spot (or look_at), directional; need not be unit
    std::optional<Vec3> look_at;        // spot
    Rgb power{0.f};                     // point, spot: W
    double outer_angle = 45.0;          // spot half-angle, degrees
    std::optional<double> inner_angle;  // spot; none = outer_angle
    std::optional<double> spot_blend;   // spot: Blender's blend (instead of inner_angle)
    Rgb irradiance{0.f};                // directional: W/m^2
    std::optional<double> radius;       // point, spot: sphere radius; none = 0 (a point)
    std::optional<double> angle;        // directional: full angular diameter, degrees; none = 0
    // point, spot: "sphere" | "cycles34_disc"; directional: "uniform" | "cycles34" ("" = the
    // first; lights/point.h RadiusModel, lights/directional.h SunAngleModel).
    std::string radius_model, angle_model;
    // Area lamp: shape, size (x), size_y (rectangle, ellipse), up (its local +y); position,
    // direction | look_at (the way it emits, its local -z) and power as above.
    std::string shape = "square";
    double size = 0.0;
    std::optional<double> size_y;
    bool camera_visible = false;  // area lamp: seen by camera rays (Blender's default: no)
    // Environment: W sr^-1 m^-2 (required without a file); with a file, the map's multiplier
    // (none = 1).
    std::optional<Rgb> radiance;
    std::string file;                 // environment map image ("" = a constant environment)
    std::optional<AxisAngle> rotate;  // environment map orientation (environment_map.h)
    // Area lamp: its local +y (none: see the kind); environment map: its up (none = [0, 0, 1]).
    std::optional<Vec3> up;
    // Sky (kind "sky_nishita", Blender's Nishita Sky Texture; facet/render/sky_nishita.h):
    // angles in degrees, altitude in metres; `radiance` is its multiplier, `rotate` orients it.
    bool sun_disc = true;
    double sun_size = 0.545, sun_intensity = 1.0, sun_elevation = 15.0, sun_rotation = 0.0;
    double altitude = 0.0, air_density = 1.0, dust_density = 1.0, ozone_density = 1.0;
    bool operator==(const LightDesc&) const = default;
};

// One element of "media" (scenes/FORMAT.md, "Media"): a named participating medium. Only the
// fields of `kind` are read (kinds.h, MediumKindDef). The coefficients are given either as
// sigma_a and sigma_s, or in Cycles' Principled Volume terms (`density` set; cycles_volume(),
// medium.h), never both.
struct MediumDesc {
    MediumKind kind = MediumKind::Homogeneous;
    Vec3 sigma_a{0.f}, sigma_s{0.f};              // per scene unit, RGB
    double g = 0.0;                               // Henyey-Greenstein anisotropy, in (-1, 1)
    Vec3 emission{0.f};                           // radiance per unit length
    std::optional<double> density;                // Cycles: density (instead of sigma_a, sigma_s)
    std::optional<Vec3> color, absorption_color;  // Cycles: with density (defaults 0.5, 0)
    std::string file;                             // grid: an OpenVDB file
    std::string grid = "density";                 // grid: the float grid's name in `file`
    std::optional<glm::dmat4> transform;  // grid: the file's space to world; none = identity
    // grid: emission (Cycles' Principled Volume): `emission` times the float grid
    // `emission_grid` of `file` ("" = constant), plus blackbody emission of intensity
    // `blackbody_intensity` at `temperature` kelvin (times the grid `temperature_grid`).
    std::string emission_grid, temperature_grid;
    double blackbody_intensity = 0.0, temperature = 1000.0;
    Vec3 blackbody_tint{1.f};
    bool operator==(const MediumDesc&) const = default;
};

struct SceneDescription {
    std::string description;  // free text
    CameraDesc camera;
    // Named materials, in the order they are written (the JSON reader gives them sorted by
    // name, as the JSON library stores objects). Names must be unique.
    std::vector<std::pair<std::string, MaterialDesc>> materials;
    std::vector<ShapeDesc> shapes;
    // Named prototypes ("prototypes": {name: [shapes...]}): groups of shapes stored once and
    // placed by "instance" shapes (scenes/FORMAT.md, "Instances"), in the order they are written
    // (the JSON reader gives them sorted by name). A prototype's shapes are in its own object
    // space; they may not emit, hold instances, or be analytic (sphere, disc, plane).
    std::vector<std::pair<std::string, std::vector<ShapeDesc>>> prototypes;
    std::vector<LightDesc> lights;
    // Named media ("media": {name: {...}}), in the order they are written (the JSON reader
    // gives them sorted by name), and the medium the camera and every escaping ray are in
    // ("world_medium": a name of `media`; "" = vacuum). A material names its interior medium
    // with the key "interior" (a string parameter in MaterialDesc::params).
    std::vector<std::pair<std::string, MediumDesc>> media;
    std::string world_medium;
    RenderSettings render;  // width/height are ignored (the camera's)
    // Directory that relative mesh "file" and texture paths are resolved against (not part of
    // equality).
    std::string base_dir = ".";

    bool operator==(const SceneDescription& o) const;
};

// What build_scene() reports besides errors.
struct BuildReport {
    std::uint64_t degenerate_triangles = 0;  // zero-area triangles dropped (every mesh)
    std::vector<std::string> warnings;       // one line each, naming the shape
    // Wall time of the build before the BVH (validation, generation, transforms, copies into
    // Embree's buffers) and of the BVH build itself, for benchmarks.
    double seconds_before_bvh = 0.0, seconds_bvh = 0.0;
};

// Builds the renderable scene. Validates the whole description (see conventions): NaN/Inf
// positions, normals and parameters, indices out of range, empty meshes, unknown or duplicate
// material names, model parameters (the core's registry), a scene without lights, the limits.
// Zero-area triangles are dropped and counted (a warning per shape, also in Scene::warnings()).
// `name` prefixes every message (a file name, "blender", ...).
// The thin lens's radius in scene units of a camera (not validated: build_scene checks it):
// aperture_radius, or Cycles' focal_length (mm) 1e-3 / (2 fstop) (blender/camera.cpp: scene
// units taken as metres), or 0 (pinhole).
double aperture_radius(const CameraDesc& camera);

Scene build_scene(const SceneDescription& desc, const std::string& name,
                  const SceneLimits& limits = {}, BuildReport* report = nullptr);

// JSON (scenes/FORMAT.md version 1) -> description. Checks the JSON: syntax, types, keys,
// required keys; value checks are build_scene's. Throws SceneError("<name>: <pointer>: ...").
SceneDescription parse_scene_description(const std::string& json_text, const std::string& name,
                                         const std::string& base_dir = ".");
SceneDescription read_scene_description(const std::string& path);

// Description -> JSON text (FORMAT.md version 1, indented). Mesh arrays are written inline,
// mesh files as their path. Numbers are written so that they read back bit for bit.
std::string write_scene_json(const SceneDescription& desc);
void write_scene_file(const SceneDescription& desc, const std::string& path);

// 64-bit fingerprint of everything in the description that changes the image (mesh arrays by
// content; not base_dir), for telling render parts of different scenes apart.
std::uint64_t fingerprint(const SceneDescription& desc);

}  // namespace facet::render
