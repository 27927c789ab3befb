// The shape and light kind tables (kinds.h): one line per kind, defined in its unit under
// shapes/ and lights/. Also the one mesh-file loader and the docs' Markdown tables.
#include "facet/render/kinds.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <filesystem>
#include <sstream>
#include <stdexcept>
#include <type_traits>

namespace facet::render {

extern const ShapeKindDef kSphereKind, kPlaneKind, kBoxKind, kQuadKind, kDiscKind, kMeshKind,
    kIcosphereKind, kGridKind, kGltfKind, kInstanceKind, kCurvesKind;
extern const LightKindDef kPointLightKind, kSpotLightKind, kDirectionalLightKind, kAreaLightKind,
    kEnvironmentLightKind, kSkyNishitaLightKind;
extern const MediumKindDef kHomogeneousMediumKind;
extern const MediumKindDef kGridMediumKind;

namespace {

const std::array<const ShapeKindDef*, 11> kShapeKinds = {
    &kSphereKind,    &kPlaneKind, &kBoxKind,  &kQuadKind,     &kDiscKind,  &kMeshKind,
    &kIcosphereKind, &kGridKind,  &kGltfKind, &kInstanceKind, &kCurvesKind};
const std::array<const LightKindDef*, 6> kLightKinds = {
    &kPointLightKind, &kSpotLightKind,        &kDirectionalLightKind,
    &kAreaLightKind,  &kEnvironmentLightKind, &kSkyNishitaLightKind};
const std::array<const MediumKindDef*, 2> kMediumKinds = {&kHomogeneousMediumKind,
                                                          &kGridMediumKind};
const std::array<std::string_view, 13> kCommonShapeKeys = {
    "type",           "name",         "material",  "emission",      "two_sided",
    "transform",      "flip_normals", "motion",    "texture_space", "holdout",
    "shadow_catcher", "visibility",   "light_path"};

// Linear searches: the tables hold a handful of kinds.
template <class Def, std::size_t N, class Key>
const Def* find_in(const std::array<const Def*, N>& table, const Key& key) {
    for (const Def* k : table) {
        if constexpr (std::is_same_v<Key, std::string_view>) {
            if (k->name == key) return k;
        } else {
            if (k->kind == key) return k;
        }
    }
    return nullptr;
}

template <class Def, std::size_t N, class Kind>
const Def& by_kind(const std::array<const Def*, N>& table, Kind kind, const char* what) {
    if (const Def* k = find_in(table, kind)) return *k;
    throw std::logic_error(std::string("no ") + what + " kind has enum value " +
                           std::to_string(int(kind)));
}

template <class Table>
std::vector<std::string> names(const Table& table) {
    std::vector<std::string> out;
    for (const auto* k : table) out.emplace_back(k->name);
    return out;
}

const char* type_text(FieldType t) {
    switch (t) {
        case FieldType::Point:
            return "point [x, y, z]";
        case FieldType::Direction:
            return "direction [x, y, z]";
        case FieldType::Color:
            return "colour (number or [r, g, b])";
        case FieldType::Number:
            return "number";
        case FieldType::Integer:
            return "integer";
        case FieldType::Bool:
            return "bool";
        case FieldType::Quad:
            return "4 points";
        case FieldType::Path:
            return "string (path)";
        case FieldType::Text:
            return "string";
        case FieldType::Rotation:
            return "rotation {\"axis\": [x, y, z], \"angle\": degrees}";
        case FieldType::MeshArrays:
        case FieldType::CurveArrays:
            return "arrays";
    }
    return "";
}

template <class Def>
void kind_table(std::ostringstream& s, const Def& k) {
    s << "#### `" << k.name << "`\n" << k.summary << "\n\n";
    s << "| key | type | required | default | meaning |\n|---|---|---|---|---|\n";
    for (const auto& f : k.fields) {
        s << "| `" << f.key << "` | " << type_text(f.type);
        if (f.type == FieldType::Integer) s << " in [" << f.lo << ", " << f.hi << "]";
        s << " | " << (f.required ? "yes" : "no") << " | " << f.default_text << " | " << f.doc
          << " |\n";
    }
    if constexpr (requires { k.exactly_one_of; }) {
        for (const auto& [a, b] : k.exactly_one_of)
            s << "\nGive exactly one of `" << a << "` and `" << b << "`.\n";
    }
    s << "\n";
}

}  // namespace

std::span<const ShapeKindDef* const> shape_kinds() {
    return kShapeKinds;
}
std::span<const LightKindDef* const> light_kinds() {
    return kLightKinds;
}
const ShapeKindDef& shape_kind(ShapeKind kind) {
    return by_kind(kShapeKinds, kind, "shape");
}
const LightKindDef& light_kind(LightKind kind) {
    return by_kind(kLightKinds, kind, "light");
}
const ShapeKindDef* find_shape_kind(ShapeKind kind) {
    return find_in(kShapeKinds, kind);
}
const LightKindDef* find_light_kind(LightKind kind) {
    return find_in(kLightKinds, kind);
}
const ShapeKindDef* find_shape_kind(std::string_view name) {
    return find_in(kShapeKinds, name);
}
const LightKindDef* find_light_kind(std::string_view name) {
    return find_in(kLightKinds, name);
}
std::vector<std::string> shape_kind_names() {
    return names(kShapeKinds);
}
std::vector<std::string> light_kind_names() {
    return names(kLightKinds);
}
std::span<const MediumKindDef* const> medium_kinds() {
    return kMediumKinds;
}
const MediumKindDef* find_medium_kind(std::string_view name) {
    return find_in(kMediumKinds, name);
}
const MediumKindDef* find_medium_kind(MediumKind kind) {
    return find_in(kMediumKinds, kind);
}
const MediumKindDef& medium_kind(MediumKind kind) {
    return by_kind(kMediumKinds, kind, "medium");
}
std::vector<std::string> medium_kind_names() {
    return names(kMediumKinds);
}
std::span<const std::string_view> common_shape_keys() {
    return kCommonShapeKeys;
}

std::string resolve_scene_path(const std::string& file, const std::string& base_dir) {
    std::filesystem::path p(file);
    if (p.is_relative()) p = std::filesystem::path(base_dir) / p;
    return p.string();
}

TriangleMesh load_mesh_file(const std::string& path) {
    std::string ext = std::filesystem::path(path).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return char(std::tolower(c)); });
    if (ext == ".obj") return load_obj(path);
    if (ext == ".ply") return load_ply(path);
    throw std::runtime_error("unsupported mesh file extension '" + ext + "' (use .obj or .ply)");
}

std::string kinds_markdown() {
    std::ostringstream s;
    s << "<!-- Generated by `facet scene-format --markdown` from the kind table "
         "(core/render/include/facet/render/kinds.h); tests/render checks it. -->\n\n";
    s << "### Shape kinds\n\nEvery shape also takes the common keys:";
    for (std::string_view k : kCommonShapeKeys) s << " `" << k << "`";
    s << ".\n\n";
    for (const ShapeKindDef* k : kShapeKinds) kind_table(s, *k);
    s << "### Light kinds\n\n";
    for (const LightKindDef* k : kLightKinds) kind_table(s, *k);
    s << "### Medium kinds\n\n";
    for (const MediumKindDef* k : kMediumKinds) kind_table(s, *k);
    return s.str();
}

}  // namespace facet::render
