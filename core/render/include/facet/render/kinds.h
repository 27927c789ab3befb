// Shape and light kinds: the one table that says what each kind of the scene format is.
//
// One unit per kind (core/render/src/shapes/<kind>.cpp, core/render/src/lights/<kind>.cpp)
// defines a ShapeKindDef / LightKindDef: its name, its keys with their types, defaults and
// documentation, its builder (description -> renderable geometry or light) and its POV-Ray
// exporter. Everything that deals in kinds reads this table instead of switching on the enum:
//  - the JSON reader and writer (scene_json.cpp): accepted keys, required keys, value types;
//  - build_scene (build_shapes.cpp, build_lights.cpp): calls the kind's `build`;
//  - the POV-Ray exporter (io/pov_export.cpp): calls the kind's `pov`;
//  - the Python module: ShapeDesc / LightDesc attributes and constructor keywords;
//  - the docs: `facet scene-format --markdown` prints the tables of scenes/FORMAT.md (a test
//    checks that the file holds them).
// Adding a kind: its enum value below, one unit, its line in the table (kinds.cpp), its tests.
//
// The renderer's light TYPES (light.h "Structure": how a light samples and evaluates itself)
// have their table in light_types.h: a light kind of the format builds lights of one or more
// types (a spot with and without Blender's fall-off is one type; an emissive shape is a light
// of an emissive_* type, built by its shape kind).
//
// Conventions: a Field names a member of the description struct; the member's default value
// (ShapeDesc{} / LightDesc{}) is the format's default, and `default_text` documents it. Keys
// every shape has (type, name, material, emission, two_sided, transform, flip_normals) are the
// common keys, listed by common_shape_keys(), not in each kind.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "facet/render/mesh.h"
#include "facet/render/scene_description.h"

namespace facet::render {

// How a key's value is written in JSON and checked by the reader.
enum class FieldType : std::uint8_t {
    Point,       // [x, y, z]
    Direction,   // [x, y, z], non-zero (normalised by the builder)
    Color,       // a number (grey) or [r, g, b], >= 0
    Number,      // a finite number
    Integer,     // an integer in [lo, hi]
    Bool,        // true | false
    Quad,        // 4 points [[x, y, z] x 4]
    Path,        // a non-empty string (a file, relative to the scene file)
    Text,        // a non-empty string (a name from a list)
    Rotation,    // {"axis": [x, y, z], "angle": degrees} (AxisAngle)
    MeshArrays,  // "positions" (required unless "file"), "indices", "normals": flat arrays
    CurveArrays  // "points" (required), "radius" (a number or an array), "counts", "root_uvs"
};

template <class Desc>
struct Field {
    using Member = std::variant<Vec3 Desc::*, std::optional<Vec3> Desc::*, double Desc::*,
                                std::optional<double> Desc::*, int Desc::*, bool Desc::*,
                                std::array<Vec3, 4> Desc::*, std::string Desc::*, MeshData Desc::*,
                                std::optional<AxisAngle> Desc::*, CurveData Desc::*>;
    std::string_view key;
    FieldType type;
    bool required;
    Member member;
    std::string_view default_text;  // for the docs ("-" when required or absent by default)
    std::string_view doc;
    std::int64_t lo = 0, hi = 0;  // FieldType::Integer's range
};

class ShapeBuild;   // what a kind's builder gets (core/render/src/shapes/shape_build.h)
class PovShapeOut;  // what a kind's POV-Ray exporter gets (core/render/src/io/pov_writer.h)
class LightBuild;
class PovLightOut;
class BuildChecks;  // value checks naming JSON pointers (core/render/src/kind_build.h)
class MediumBuild;  // what a medium kind's builder gets (kind_build.h)

struct ShapeKindDef {
    ShapeKind kind;
    std::string_view name;
    std::string_view summary;  // one line for the docs
    std::vector<Field<ShapeDesc>> fields;
    // Validates the kind's values (with JSON pointers) and adds its geometry.
    void (*build)(ShapeBuild&);
    // Object-space triangles of a triangle kind from validated values (the builder and every
    // exporter use it, so that they see the same triangles); null for analytic kinds.
    // `base_dir` resolves relative mesh files.
    TriangleMesh (*triangles)(const ShapeDesc&, const std::string& base_dir);
    // Writes the shape as POV-Ray SDL (null: as the triangles of `triangles`).
    void (*pov)(PovShapeOut&);
    // The kind brings its own materials (a glTF file's): "material" is optional, and when given
    // replaces all of them.
    bool own_materials = false;
    // The kind places a prototype (instance): it has no surface of its own, so "material",
    // "emission", "two_sided": false and "flip_normals" are errors on it.
    bool places_prototype = false;
};

struct LightKindDef {
    LightKind kind;
    std::string_view name;
    std::string_view summary;
    std::vector<Field<LightDesc>> fields;
    // Pairs of keys of which exactly one must be given (spot: direction | look_at).
    std::vector<std::pair<std::string_view, std::string_view>> exactly_one_of;
    void (*build)(LightBuild&);
    void (*pov)(PovLightOut&);
};

// A medium kind (medium.h): one unit per kind in core/render/src/media/<kind>.cpp.
struct MediumKindDef {
    MediumKind kind;
    std::string_view name;
    std::string_view summary;
    std::vector<Field<MediumDesc>> fields;
    // Validates the description (errors name `ptr` + "/key" through `checks`) and builds it.
    Medium (*build)(const MediumDesc& desc, const std::string& ptr, const MediumBuild& checks);
};

// The tables, in the scene format's documented order.
std::span<const ShapeKindDef* const> shape_kinds();
std::span<const LightKindDef* const> light_kinds();
// The kind of an enum value (std::logic_error if none: a value outside the enum).
const ShapeKindDef& shape_kind(ShapeKind kind);
const LightKindDef& light_kind(LightKind kind);
// nullptr when no kind has that name or enum value.
const ShapeKindDef* find_shape_kind(std::string_view name);
const LightKindDef* find_light_kind(std::string_view name);
const ShapeKindDef* find_shape_kind(ShapeKind kind);
const LightKindDef* find_light_kind(LightKind kind);
std::vector<std::string> shape_kind_names();
std::vector<std::string> light_kind_names();
std::span<const MediumKindDef* const> medium_kinds();
const MediumKindDef* find_medium_kind(std::string_view name);
const MediumKindDef* find_medium_kind(MediumKind kind);
const MediumKindDef& medium_kind(MediumKind kind);
std::vector<std::string> medium_kind_names();

// Keys every shape accepts besides its kind's fields.
std::span<const std::string_view> common_shape_keys();

// A file named in the scene (mesh, glTF, image): relative paths are relative to `base_dir` (the
// scene file's folder).
std::string resolve_scene_path(const std::string& file, const std::string& base_dir);

// Loads a triangle mesh file, chosen by its extension (.obj, .ply; case-insensitive); throws
// std::runtime_error naming the file for any other extension or a malformed file. The one
// mesh-file loader of the scene builder and every exporter.
TriangleMesh load_mesh_file(const std::string& path);

// Markdown tables of the shape and light kinds (scenes/FORMAT.md holds this text between
// the markers `<!-- kinds:begin -->` and `<!-- kinds:end -->`).
std::string kinds_markdown();

}  // namespace facet::render
