// The scene part of the module: SceneDescription (camera, materials, shapes with meshes from
// numpy arrays, lights, render settings), JSON read/parse/write, build_scene and load_scene.
//
// Conventions:
//  - facet.SceneDescription holds Python objects: `shapes` and `lights` are Python lists of
//    ShapeDesc / LightDesc objects, `materials` a dict name -> MaterialDesc (in insertion order,
//    the order the JSON writer writes them), `camera` and `render` a CameraDesc and a
//    RenderSettings. Mutating them mutates the description (desc.shapes[0].radius = 2). The C++
//    SceneDescription is assembled from them when it is needed (build_scene, the JSON writer,
//    fingerprint, ==): shapes are copied, mesh arrays never are.
//  - Meshes (MeshData) are spans over numpy arrays: positions float32 (n, 3), indices int32 or
//    uint32 (m, 3), normals float32 (n, 3) or None. Arrays of exactly that dtype and C layout
//    are used in place (zero copy) and kept alive by MeshData::owner; other real float dtypes
//    (positions, normals) and integer dtypes (indices) are converted once, and non-contiguous
//    arrays copied. Do not modify an array while a description using it is being built.
//  - Bad arrays raise ValueError naming the argument (and the row): wrong dtype or shape,
//    NaN/Inf, negative or out-of-range indices, a normal count different from the positions'.
//    Everything else is build_scene's validation (SceneError -> ValueError with the JSON pointer
//    the JSON writer would give: "python: /shapes/3 ('Suzanne'): ...").
//  - Enum values use the scene format's words: ShapeKind.sphere, LightKind.spot; strings
//    ("sphere") are accepted wherever a kind is set.
#include <algorithm>
#include <deque>
#include <limits>
#include <map>
#include <optional>
#include <set>
#include <sstream>

#include "bindings.h"
#include "facet/render/kinds.h"
#include "facet/render/light_units.h"
#include "facet/render/pov_export.h"
#include "facet/render/scene.h"
#include "facet/render/scene_description.h"
#include "facet/render/texture_kinds.h"

namespace facet::python {

using namespace facet::render;

namespace {

// ---------------------------------------------------------------------------------------------
// numpy arrays -> MeshData

// A shared_ptr owning one reference to a Python object; released with the GIL held.
std::shared_ptr<const void> python_owner(py::object o) {
    PyObject* p = o.release().ptr();
    return std::shared_ptr<const void>(p, [](const void* q) {
        if (!Py_IsInitialized()) return;
        py::gil_scoped_acquire gil;
        Py_DECREF(static_cast<PyObject*>(const_cast<void*>(q)));
    });
}

std::string shape_str(const py::array& a) {
    return std::string(py::str(py::tuple(a.attr("shape"))));
}
std::string dtype_str(const py::array& a) {
    return std::string(py::str(a.dtype()));
}

py::array as_array(py::handle obj, const char* what, const char* expected) {
    py::array a = py::array::ensure(obj);
    if (!a) {
        PyErr_Clear();
        bad_argument(what, std::string("expected a numpy array ") + expected);
    }
    return a;
}

// numpy array -> an in-memory texture (facet.Texture(array, ...)): H x W or H x W x {1, 3, 4},
// float32 or uint8, finite; decoded now by colorspace (texel_image_from_memory).
TextureDesc texture_from_array(py::handle obj, const std::string& colorspace) {
    const char* what = "Texture: array";
    const py::array a = as_array(obj, what, "H x W or H x W x C (C = 1, 3, 4) of float32 or uint8");
    const bool u8 = a.dtype().is(py::dtype::of<std::uint8_t>());
    if (!u8 && !a.dtype().is(py::dtype::of<float>()))
        bad_argument(what, "dtype " + dtype_str(a) + ", expected float32 or uint8");
    if (!(a.ndim() == 2 ||
          (a.ndim() == 3 && (a.shape(2) == 1 || a.shape(2) == 3 || a.shape(2) == 4))))
        bad_argument(what, "shape " + shape_str(a) + ", expected (H, W) or (H, W, C), C = 1, 3, 4");
    if (a.size() == 0) bad_argument(what, "shape " + shape_str(a) + " is empty");
    if (!colorspace.empty() && colorspace != "srgb" && colorspace != "linear")
        bad_argument("Texture: colorspace",
                     "'" + colorspace + "', expected 'srgb', 'linear' or '' (default)");
    const int h = int(a.shape(0)), w = int(a.shape(1)), c = a.ndim() == 3 ? int(a.shape(2)) : 1;
    TexelImageOptions opt;
    opt.color_space = colorspace.empty()     ? ColorSpace::Auto
                      : colorspace == "srgb" ? ColorSpace::Srgb
                                             : ColorSpace::Linear;
    TextureDesc d;
    d.file = "<numpy array " + std::to_string(h) + "x" + std::to_string(w) + "x" +
             std::to_string(c) + " " + dtype_str(a) + ">";
    try {
        if (u8) {
            const auto p = py::array_t<std::uint8_t, py::array::c_style>::ensure(a);
            d.image = std::make_shared<const TexelImage>(
                texel_image_from_memory(p.data(), nullptr, w, h, c, opt, d.file, what));
        } else {
            const auto p = py::array_t<float, py::array::c_style>::ensure(a);
            d.image = std::make_shared<const TexelImage>(
                texel_image_from_memory(nullptr, p.data(), w, h, c, opt, d.file, what));
        }
    } catch (const TexelImageError& e) {
        throw py::value_error(e.what());
    }
    return d;
}

// Float rows (n, 3): float32 C-contiguous in place, else converted. Checks finiteness.
py::array_t<float, py::array::c_style> float_rows(py::handle obj, const char* what,
                                                  py::ssize_t cols = 3) {
    const std::string shape = "(n, " + std::to_string(cols) + ")";
    py::array a = as_array(obj, what, ("of float32, shape " + shape).c_str());
    if (a.dtype().kind() != 'f')
        bad_argument(what, "dtype " + dtype_str(a) + ", expected float32 (or another float dtype)");
    if (a.ndim() != 2 || a.shape(1) != cols)
        bad_argument(what, "shape " + shape_str(a) + ", expected " + shape);
    auto f = py::array_t<float, py::array::c_style | py::array::forcecast>::ensure(a);
    if (!f) throw py::error_already_set();
    const float* p = f.data();
    const py::ssize_t n = f.shape(0);
    // The check reads every value; the message is only formatted for the row that fails.
    for (py::ssize_t i = 0; i < n; ++i) {
        bool finite = true;
        for (py::ssize_t j = 0; j < cols; ++j) finite = finite && std::isfinite(p[cols * i + j]);
        if (finite) continue;
        std::string row;
        for (py::ssize_t j = 0; j < cols; ++j)
            row += (j ? ", " : "") + std::to_string(p[cols * i + j]);
        bad_argument(what, "row " + std::to_string(i) + " is not finite (" + row + ")");
    }
    return f;
}

// Index rows (m, 3) as uint32: int32/uint32 C-contiguous in place, other integer dtypes
// converted. Checks 0 <= index < num_vertices.
py::array index_rows(py::handle obj, const char* what, std::size_t num_vertices) {
    py::array a = as_array(obj, what, "of int32, shape (m, 3)");
    const char kind = a.dtype().kind();
    if (kind != 'i' && kind != 'u')
        bad_argument(what, "dtype " + dtype_str(a) + ", expected int32 (or another integer dtype)");
    if (a.ndim() != 2 || a.shape(1) != 3)
        bad_argument(what, "shape " + shape_str(a) + ", expected (m, 3)");
    const bool c_layout = (a.flags() & py::array::c_style) != 0 &&
                          (a.flags() & py::detail::npy_api::NPY_ARRAY_ALIGNED_) != 0;
    const auto bad_index = [&](py::ssize_t k, long long v) {
        const std::string at =
            "row " + std::to_string(k / 3) + " (index " + std::to_string(v) + ")";
        if (v < 0) bad_argument(what, at + " is negative");
        bad_argument(what, at + " is out of range: there are " + std::to_string(num_vertices) +
                               " positions");
    };
    const py::ssize_t count = a.size();
    if (c_layout && a.itemsize() == 4) {
        // In place: int32 (no negatives) or uint32, both read as uint32.
        const bool is_signed = kind == 'i';
        const auto* p = static_cast<const std::uint32_t*>(a.data());
        for (py::ssize_t k = 0; k < count; ++k) {
            const std::uint32_t v = p[k];
            if (v >= num_vertices)
                bad_index(k, is_signed ? (long long)std::int32_t(v) : (long long)v);
        }
        return a;
    }
    // Converted: read as int64 (uint64 values beyond int64 become negative: still rejected).
    auto wide = py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>::ensure(a);
    if (!wide) throw py::error_already_set();
    py::array_t<std::uint32_t> out({a.shape(0), py::ssize_t(3)});
    const std::int64_t* p = wide.data();
    std::uint32_t* q = out.mutable_data();
    for (py::ssize_t k = 0; k < count; ++k) {
        const std::int64_t v = p[k];
        if (v < 0 || std::uint64_t(v) >= num_vertices) bad_index(k, v);
        q[k] = std::uint32_t(v);
    }
    return out;
}

MeshData mesh_from_arrays(py::handle positions, py::handle indices, py::handle normals,
                          py::handle uvs, py::handle tangents = py::none(),
                          py::handle colors = py::none()) {
    auto pos = float_rows(positions, "positions");
    const std::size_t n = std::size_t(pos.shape(0));
    py::array idx = index_rows(indices, "indices", n);
    MeshData mesh;
    mesh.positions = {pos.data(), std::size_t(pos.size())};
    mesh.indices = {static_cast<const std::uint32_t*>(idx.data()), std::size_t(idx.size())};
    // An optional (n, cols) float array per position: its span in `out`; the array (kept alive
    // by the mesh's owner) or None.
    auto per_position = [&](py::handle h, const char* what, py::ssize_t cols,
                            std::span<const float>& out) -> py::object {
        if (h.is_none()) return py::none();
        auto a = float_rows(h, what, cols);
        if (std::size_t(a.shape(0)) != n)
            bad_argument(what, std::to_string(a.shape(0)) + " rows, expected one per position (" +
                                   std::to_string(n) + ")");
        out = {a.data(), std::size_t(a.size())};
        return a;
    };
    py::object nrm = per_position(normals, "normals", 3, mesh.normals);
    py::object uv = per_position(uvs, "uvs", 2, mesh.uvs);
    py::object tan = per_position(tangents, "tangents", 4, mesh.tangents);
    // Colours: (n, 3) linear RGB or (n, 4) linear RGBA (the JSON "colors").
    py::ssize_t color_cols = 3;
    if (!colors.is_none()) {
        const py::array a = py::array::ensure(colors);
        if (a && a.ndim() == 2 && a.shape(1) == 4) color_cols = 4;
    }
    py::object col = per_position(colors, "colors", color_cols, mesh.colors);
    mesh.owner = python_owner(py::make_tuple(pos, idx, nrm, uv, tan, col));
    return mesh;
}

// A read-only (rows, 3) numpy view of a mesh span, kept alive by the mesh's owner (copied when
// the mesh has no owner).
template <class T>
py::array mesh_view(std::span<const T> s, const MeshData& mesh, py::ssize_t cols = 3) {
    using Out = std::conditional_t<std::is_same_v<T, float>, float, std::int32_t>;
    const std::vector<py::ssize_t> shape{py::ssize_t(s.size()) / cols, cols};
    const std::vector<py::ssize_t> strides{py::ssize_t(cols * sizeof(T)), py::ssize_t(sizeof(T))};
    const auto* data = reinterpret_cast<const Out*>(s.data());
    if (!mesh.owner || s.empty()) return py::array_t<Out>(shape, strides, data);  // a copy
    auto* keep = new std::shared_ptr<const void>(mesh.owner);
    py::capsule base(keep, [](void* p) { delete static_cast<std::shared_ptr<const void>*>(p); });
    py::array a(py::dtype::of<Out>(), shape, strides, data, base);
    a.attr("flags").attr("writeable") = false;
    return a;
}

// ---------------------------------------------------------------------------------------------
// Kinds <-> strings

// Kind names come from the kind table (facet/render/kinds.h).
template <class E>
E kind_from(py::handle v, const char* what) {
    if (py::isinstance<py::str>(v)) {
        const std::string s = v.cast<std::string>();
        std::vector<std::string> names;
        if constexpr (std::is_same_v<E, ShapeKind>) {
            if (const ShapeKindDef* k = find_shape_kind(s)) return k->kind;
            names = shape_kind_names();
        } else if constexpr (std::is_same_v<E, LightKind>) {
            if (const LightKindDef* k = find_light_kind(s)) return k->kind;
            names = light_kind_names();
        } else {
            if (const MediumKindDef* k = find_medium_kind(s)) return k->kind;
            names = medium_kind_names();
        }
        std::string msg = "unknown " + std::string(what) + " '" + s + "'";
        const std::string guess = closest_name(s, names);
        if (!guess.empty()) msg += " (did you mean '" + guess + "'?)";
        throw py::value_error(msg);
    }
    try {
        return v.cast<E>();
    } catch (const py::cast_error&) {
        throw py::type_error(std::string(what) + ": expected a string or a facet enum value");
    }
}

std::string kind_name(ShapeKind kind) {
    const ShapeKindDef* k = find_shape_kind(kind);
    return k ? std::string(k->name) : "?";
}
std::string kind_name(LightKind kind) {
    const LightKindDef* k = find_light_kind(kind);
    return k ? std::string(k->name) : "?";
}
std::string kind_name(MediumKind kind) {
    const MediumKindDef* k = find_medium_kind(kind);
    return k ? std::string(k->name) : "?";
}

// The Python attribute of a kind's field: its JSON key, except the mesh arrays ("mesh", a
// MeshData) and the curve arrays ("curves", a CurveData).
template <class Desc>
std::string attribute_name(const Field<Desc>& f) {
    if (f.type == FieldType::MeshArrays) return "mesh";
    if (f.type == FieldType::CurveArrays) return "curves";
    return std::string(f.key);
}

// One read-write property per field key of every kind (fields shared by several kinds, such as
// "center", once), documented with the kinds that read it.
template <class Desc, class Kinds>
void def_kind_fields(py::class_<Desc>& cls, const Kinds& kinds) {
    static std::deque<std::string> docs;  // pybind keeps the pointer
    std::map<std::string, std::string> users;
    for (const auto* k : kinds)
        for (const auto& f : k->fields) {
            std::string& u = users[attribute_name(f)];
            u += (u.empty() ? "" : ", ") + std::string(k->name);
        }
    std::set<std::string> done;
    for (const auto* k : kinds) {
        for (const auto& f : k->fields) {
            const std::string name = attribute_name(f);
            if (!done.insert(name).second) continue;
            docs.push_back(std::string(f.doc) + " (kinds: " + users[name] + ")");
            const char* doc = docs.back().c_str();
            std::visit(
                [&](auto member) {
                    using T = std::remove_cvref_t<decltype(std::declval<Desc&>().*member)>;
                    cls.def_property(
                        name.c_str(), [member](const Desc& d) -> T { return d.*member; },
                        [member](Desc& d, T v) { d.*member = std::move(v); }, doc);
                },
                f.member);
        }
    }
}

// The kind table's entry of a light or medium kind.
const LightKindDef& kind_def(LightKind k) {
    return light_kind(k);
}
const MediumKindDef& kind_def(MediumKind k) {
    return medium_kind(k);
}

// Keyword arguments a ShapeDesc / LightDesc of `kind` takes besides its fields.
const std::set<std::string> kCommonShapeAttributes = {
    "name",          "material_ref",     "material",
    "emission",      "emission_texture", "two_sided",
    "flip_normals",  "transform",        "motion",
    "texture_space", "motion_positions", "motion_normals",
    "holdout",       "shadow_catcher",   "visibility",
    "light_path"};

// Ray visibility (ShapeDesc::visibility) as {"camera": bool, ...}, every kind named; set from a
// dict naming some of them (the others: visible).
py::dict visibility_dict(std::uint8_t mask) {
    py::dict d;
    for (std::size_t i = 0; i < kRayVisibilityNames.size(); ++i)
        d[kRayVisibilityNames[i]] = (mask & (1u << i)) != 0;
    return d;
}
std::uint8_t visibility_mask(const py::dict& d) {
    std::uint8_t mask = kRayAll;
    for (const auto& [key, value] : d) {
        const std::string name = py::str(key);
        const auto* it = std::find_if(kRayVisibilityNames.begin(), kRayVisibilityNames.end(),
                                      [&](const char* n) { return name == n; });
        if (it == kRayVisibilityNames.end())
            throw py::value_error("visibility: unknown ray kind '" + name +
                                  "' (camera, diffuse, glossy, transmission, volume_scatter, "
                                  "shadow)");
        if (!py::isinstance<py::bool_>(value))
            throw py::type_error("visibility['" + name + "']: expected a bool");
        if (!value.cast<bool>())
            mask = std::uint8_t(mask & ~(1u << (it - kRayVisibilityNames.begin())));
    }
    return mask;
}

// Light Path switches (ShapeDesc::light_path) as [{"ray": name, "material": name, MaterialDesc
// or None, "emission": colour}], and back from such dicts ("material" and "emission" optional).
py::list light_path_list(const std::vector<ShapeDesc::LightPathEntry>& entries) {
    py::list out;
    for (const ShapeDesc::LightPathEntry& e : entries) {
        py::dict d;
        for (std::size_t i = 0; i < kLightPathRayNames.size(); ++i)
            if (e.ray == (1u << i)) d["ray"] = kLightPathRayNames[i];
        if (!e.material)
            d["material"] = py::none();
        else if (!e.material->ref.empty())
            d["material"] = e.material->ref;
        else
            d["material"] = py::cast(*e.material);
        d["emission"] = py::cast(e.emission);
        out.append(d);
    }
    return out;
}
std::vector<ShapeDesc::LightPathEntry> light_path_entries(const py::list& l) {
    std::vector<ShapeDesc::LightPathEntry> out;
    for (const py::handle& h : l) {
        if (!py::isinstance<py::dict>(h))
            throw py::type_error(
                "light_path: each switch is a dict {'ray': ..., 'material': "
                "..., 'emission': ...}");
        const py::dict d = py::reinterpret_borrow<py::dict>(h);
        ShapeDesc::LightPathEntry e;
        for (const auto& [key, value] : d) {
            const std::string k = py::str(key);
            if (k == "ray") {
                const std::string name = py::str(value);
                const auto* it = std::find_if(kLightPathRayNames.begin(), kLightPathRayNames.end(),
                                              [&](const char* n) { return name == n; });
                if (it == kLightPathRayNames.end())
                    throw py::value_error("light_path: unknown ray output '" + name +
                                          "' (camera, shadow, diffuse, glossy, singular, "
                                          "reflection, transmission)");
                e.ray = std::uint8_t(1u << (it - kLightPathRayNames.begin()));
            } else if (k == "material") {
                if (value.is_none()) continue;
                if (py::isinstance<py::str>(value)) {
                    MaterialDesc ref;
                    ref.ref = value.cast<std::string>();
                    e.material = std::move(ref);
                } else {
                    e.material = value.cast<MaterialDesc>();
                }
            } else if (k == "emission") {
                e.emission = value.cast<Rgb>();
            } else {
                throw py::value_error("light_path: unknown key '" + k +
                                      "' (ray, material, emission)");
            }
        }
        if (e.ray == 0) throw py::value_error("light_path: each switch needs a 'ray'");
        out.push_back(std::move(e));
    }
    return out;
}

// Deformation steps (ShapeDesc::motion_positions, motion_normals): a list of float32 arrays,
// and back from any iterable of float sequences (each flattened).
py::list float_steps(const std::vector<std::vector<float>>& steps) {
    py::list out;
    for (const std::vector<float>& st : steps) {
        py::array_t<float> a(py::ssize_t(st.size()));
        std::copy(st.begin(), st.end(), a.mutable_data());
        out.append(a);
    }
    return out;
}
std::vector<std::vector<float>> float_steps(const py::iterable& steps, const char* name) {
    std::vector<std::vector<float>> out;
    for (const py::handle& h : steps) {
        if (py::isinstance<py::str>(h))
            throw py::type_error(std::string(name) + ": each step is a sequence of numbers");
        const auto a = py::array_t<float, py::array::c_style | py::array::forcecast>::ensure(h);
        if (!a) throw py::type_error(std::string(name) + ": each step is a sequence of numbers");
        out.emplace_back(a.data(), a.data() + a.size());
    }
    return out;
}

// TypeError for a keyword that is no field of the kind (a typo, or another kind's key).
template <class Def>
void check_kind_keywords(const py::kwargs& kw, const Def& kind, const std::set<std::string>& common,
                         const char* type) {
    std::set<std::string> allowed = common;
    std::string list;
    for (const auto& f : kind.fields) {
        allowed.insert(attribute_name(f));
        list += (list.empty() ? "" : ", ") + attribute_name(f);
    }
    for (auto [key, value] : kw) {
        const std::string k = py::cast<std::string>(key);
        if (!allowed.count(k))
            throw py::type_error(std::string(type) + " has no field '" + k + "' for kind '" +
                                 std::string(kind.name) + "' (its fields: " + list + ")");
    }
}

// Sets each keyword argument as an attribute of `self` (TypeError for unknown names).
void set_fields(py::object self, const py::kwargs& kw, const char* type) {
    for (auto [key, value] : kw) {
        const std::string k = key.cast<std::string>();
        if (!py::hasattr(self, k.c_str()) || k.rfind("_", 0) == 0)
            throw py::type_error(std::string(type) + " has no field '" + k + "'");
        self.attr(key) = value;
    }
}

// A light or medium description class: Desc(kind, **fields) (the fields checked against the
// kind's), `kind` as a name or enum value, ==, repr, and the kind table's fields as attributes.
template <class Desc, class Kind, class Kinds>
void def_kind_desc(py::class_<Desc>& cls, const char* type, const char* what, const Kinds& kinds) {
    const std::string name = type;
    cls.def(py::init([name](py::object kind, py::kwargs kw) {
                py::object self = py::cast(Desc{});
                if (!kind.is_none()) {
                    self.attr("kind") = kind;
                    check_kind_keywords(kw, kind_def(self.cast<const Desc&>().kind), {},
                                        name.c_str());
                }
                set_fields(self, kw, name.c_str());
                return self.cast<Desc>();
            }),
            py::arg("kind") = py::none())
        .def_property(
            "kind", [](const Desc& d) { return d.kind; },
            [what](Desc& d, py::handle v) { d.kind = kind_from<Kind>(v, what); })
        .def(py::self == py::self)
        .def("__repr__",
             [name](const Desc& d) { return "facet." + name + "('" + kind_name(d.kind) + "')"; });
    def_kind_fields(cls, kinds);
}

template <class T>
T from_kwargs(const py::kwargs& kw, const char* type) {
    py::object self = py::cast(T{});
    set_fields(self, kw, type);
    return self.cast<T>();
}

// ---------------------------------------------------------------------------------------------
// The Python-side description

struct PySceneDescription {
    std::string description;
    py::object camera;    // CameraDesc
    py::dict materials;   // str -> MaterialDesc
    py::list shapes;      // [ShapeDesc]
    py::dict prototypes;  // str -> [ShapeDesc] (instancing: scenes/FORMAT.md, "Instances")
    py::list lights;      // [LightDesc]
    py::dict media;       // str -> MediumDesc (scenes/FORMAT.md, "Media")
    std::string world_medium;
    py::object render;  // RenderSettings
    std::string base_dir = ".";

    PySceneDescription() : camera(py::cast(CameraDesc{})), render(py::cast(RenderSettings{})) {}
};

template <class T>
const T& element(py::handle item, const std::string& where, const char* type) {
    if (!py::isinstance<T>(item))
        throw py::type_error(where + ": expected a facet." + type + ", got " +
                             std::string(py::str(py::type::of(item).attr("__name__"))));
    return item.cast<const T&>();
}

SceneDescription to_cpp(const PySceneDescription& d) {
    SceneDescription s;
    s.description = d.description;
    s.camera = element<CameraDesc>(d.camera, "camera", "CameraDesc");
    s.render = element<RenderSettings>(d.render, "render", "RenderSettings");
    s.base_dir = d.base_dir;
    for (auto [key, value] : d.materials) {
        if (!py::isinstance<py::str>(key)) throw py::type_error("materials: keys must be strings");
        const std::string name = key.cast<std::string>();
        s.materials.emplace_back(
            name, element<MaterialDesc>(value, "materials['" + name + "']", "MaterialDesc"));
    }
    s.shapes.reserve(d.shapes.size());
    for (std::size_t i = 0; i < d.shapes.size(); ++i)
        s.shapes.push_back(
            element<ShapeDesc>(d.shapes[i], "shapes[" + std::to_string(i) + "]", "ShapeDesc"));
    for (auto [key, value] : d.prototypes) {
        if (!py::isinstance<py::str>(key)) throw py::type_error("prototypes: keys must be strings");
        const std::string name = key.cast<std::string>();
        if (!py::isinstance<py::sequence>(value) || py::isinstance<py::str>(value))
            throw py::type_error("prototypes['" + name + "']: expected a list of ShapeDesc");
        std::vector<ShapeDesc> list;
        const py::sequence seq = value.cast<py::sequence>();
        for (std::size_t i = 0; i < seq.size(); ++i)
            list.push_back(element<ShapeDesc>(
                seq[i], "prototypes['" + name + "'][" + std::to_string(i) + "]", "ShapeDesc"));
        s.prototypes.emplace_back(name, std::move(list));
    }
    for (std::size_t i = 0; i < d.lights.size(); ++i)
        s.lights.push_back(
            element<LightDesc>(d.lights[i], "lights[" + std::to_string(i) + "]", "LightDesc"));
    for (auto [key, value] : d.media) {
        if (!py::isinstance<py::str>(key)) throw py::type_error("media: keys must be strings");
        const std::string name = key.cast<std::string>();
        s.media.emplace_back(name,
                             element<MediumDesc>(value, "media['" + name + "']", "MediumDesc"));
    }
    s.world_medium = d.world_medium;
    return s;
}

PySceneDescription from_cpp(SceneDescription&& s) {
    PySceneDescription d;
    d.description = std::move(s.description);
    d.camera = py::cast(s.camera);
    d.render = py::cast(s.render);
    d.base_dir = std::move(s.base_dir);
    for (auto& [name, mat] : s.materials) d.materials[py::str(name)] = py::cast(std::move(mat));
    for (auto& shape : s.shapes) d.shapes.append(py::cast(std::move(shape)));
    for (auto& light : s.lights) d.lights.append(py::cast(std::move(light)));
    for (auto& [name, medium] : s.media) d.media[py::str(name)] = py::cast(std::move(medium));
    d.world_medium = std::move(s.world_medium);
    for (auto& [name, list] : s.prototypes) {
        py::list shapes;
        for (auto& shape : list) shapes.append(py::cast(std::move(shape)));
        d.prototypes[py::str(name)] = shapes;
    }
    return d;
}

// The description argument: a facet.SceneDescription.
SceneDescription description_arg(py::handle desc) {
    return to_cpp(element<PySceneDescription>(desc, "desc", "SceneDescription"));
}

std::string vec_str(const Vec3& v) {
    std::ostringstream s;
    s << "(" << v.x << ", " << v.y << ", " << v.z << ")";
    return s.str();
}

SceneHandle make_handle(Scene&& scene, const BuildReport& report = {}) {
    return {std::make_shared<const Scene>(std::move(scene)), report.degenerate_triangles,
            report.seconds_before_bvh, report.seconds_bvh};
}

}  // namespace

void bind_scene(py::module_& m) {
    py::enum_<ShapeKind> shape_kind_enum(m, "ShapeKind",
                                         "Shape types (the scene format's \"type\")");
    for (const ShapeKindDef* k : shape_kinds()) shape_kind_enum.value(k->name.data(), k->kind);
    py::enum_<LightKind> light_kind_enum(m, "LightKind",
                                         "Light types (the scene format's \"type\")");
    for (const LightKindDef* k : light_kinds()) light_kind_enum.value(k->name.data(), k->kind);
    py::enum_<MediumKind> medium_kind_enum(m, "MediumKind",
                                           "Medium kinds (the scene format's media \"kind\")");
    for (const MediumKindDef* k : medium_kinds()) medium_kind_enum.value(k->name.data(), k->kind);
    m.def(
        "light_kind_keys",
        [] {
            py::dict out;
            for (const LightKindDef* k : light_kinds()) {
                py::list keys;
                for (const auto& f : k->fields) keys.append(attribute_name(f));
                out[py::str(std::string(k->name))] = py::tuple(keys);
            }
            return out;
        },
        "{light kind: (its keys, the LightDesc attributes, in the kind table's order)}: what a "
        "front end copies between a LightDesc and its own data (the Blender addon).");

    // Light unit conversions (light_units.h), for front ends that convert a light's units (the
    // Blender addon's units.py): the core's functions under their C++ names, so that each
    // formula exists once. Powers are per channel: a number or [r, g, b]; results are
    // (r, g, b) tuples.
    const auto rgb3 = [](const glm::dvec3& v) { return py::make_tuple(v.x, v.y, v.z); };
    const auto dvec = [](const py::object& o) {
        if (py::isinstance<py::sequence>(o) && !py::isinstance<py::str>(o)) {
            const py::sequence q = o.cast<py::sequence>();
            if (q.size() != 3) throw py::value_error("power: expected a number or [r, g, b]");
            return glm::dvec3(q[0].cast<double>(), q[1].cast<double>(), q[2].cast<double>());
        }
        return glm::dvec3(o.cast<double>());
    };
    m.def(
        "point_intensity",
        [=](const py::object& power) { return rgb3(point_intensity(dvec(power))); },
        py::arg("power"),
        "Radiant intensity (W/sr) of an isotropic point light of power Phi: Phi / (4 pi) "
        "(light_units.h).");
    m.def(
        "spot_intensity",
        [=](const py::object& power, double inner_deg, double outer_deg) {
            return rgb3(spot_intensity(dvec(power), inner_deg, outer_deg));
        },
        py::arg("power"), py::arg("inner_deg"), py::arg("outer_deg"),
        "On-axis intensity I0 (W/sr) of Facet's spot of power Phi, linear in cos theta between "
        "the inner and the outer half-angle (degrees): Phi = 2 pi I0 [(1 - cos inner) + "
        "(cos inner - cos outer) / 2] (light_units.h).");
    m.def(
        "cycles_spot_intensity",
        [=](const py::object& power, double outer_deg, double blend) {
            return rgb3(cycles_spot_intensity(dvec(power), outer_deg, blend));
        },
        py::arg("power"), py::arg("outer_deg"), py::arg("blend"),
        "K (W/sr) of a spot in Blender's form (Cycles 3.4's fall-off I = K g(cos theta)) of "
        "power Phi, half-angle outer (degrees, <= 90) and spot_blend: Phi = 2 pi K int_c^1 g "
        "(light_units.h).");
    m.def(
        "cycles_volume",
        [=](double density, const py::object& color, const py::object& absorption_color) {
            const MediumCoefficients c =
                cycles_volume(density, Rgb(dvec(color)), Rgb(dvec(absorption_color)));
            return py::make_tuple(rgb3(glm::dvec3(c.sigma_a)), rgb3(glm::dvec3(c.sigma_s)));
        },
        py::arg("density"), py::arg("color"), py::arg("absorption_color"),
        "(sigma_a, sigma_s) per scene unit of Cycles' Principled Volume (Blender 3.4): sigma_s = "
        "density color, sigma_a = density max(1 - color, 0) max(1 - sqrt(absorption_color), 0) "
        "(medium.h).");
    m.def("cycles_spot_attenuation", &cycles_spot_attenuation, py::arg("mu"), py::arg("c"),
          py::arg("smooth"),
          "Cycles 3.4's spot fall-off g(mu) for c = cos(spot_size / 2) and smooth = (1 - c) "
          "spot_blend (light_units.h).");

    py::class_<CameraDesc::Step>(m, "CameraStep",
                                 "One step of a camera motion (scenes/FORMAT.md, Motion blur): "
                                 "position, look_at, up.")
        .def(
            py::init([](py::kwargs kw) { return from_kwargs<CameraDesc::Step>(kw, "CameraStep"); }))
        .def_readwrite("position", &CameraDesc::Step::position)
        .def_readwrite("look_at", &CameraDesc::Step::look_at)
        .def_readwrite("up", &CameraDesc::Step::up)
        .def(py::self == py::self)
        .def("__repr__", [](const CameraDesc::Step& c) {
            return "facet.CameraStep(position=" + vec_str(c.position) +
                   ", look_at=" + vec_str(c.look_at) + ", up=" + vec_str(c.up) + ")";
        });

    py::class_<RenderSettings::MotionBlur>(
        m, "MotionBlur",
        "Motion blur settings (scenes/FORMAT.md, Motion blur): enabled, shutter (frames, > 0), "
        "position ('start' | 'center' | 'end'), curve (shutter curve weights; [] = uniform).")
        .def(py::init([](py::kwargs kw) {
            return from_kwargs<RenderSettings::MotionBlur>(kw, "MotionBlur");
        }))
        .def_readwrite("enabled", &RenderSettings::MotionBlur::enabled)
        .def_readwrite("shutter", &RenderSettings::MotionBlur::shutter)
        .def_readwrite("position", &RenderSettings::MotionBlur::position)
        .def_readwrite("curve", &RenderSettings::MotionBlur::curve)
        .def(py::self == py::self)
        .def("__repr__", [](const RenderSettings::MotionBlur& b) {
            return std::string("facet.MotionBlur(enabled=") + (b.enabled ? "True" : "False") +
                   ", shutter=" + std::to_string(b.shutter) + ", position='" + b.position +
                   "', curve=[" + std::to_string(b.curve.size()) + " values])";
        });

    py::class_<CameraDesc>(m, "CameraDesc",
                           "The camera (scenes/FORMAT.md): position, look_at, up, fov (full "
                           "vertical, degrees), width, height; type ('perspective' | "
                           "'orthographic'), scale (orthographic: extent of the larger side), "
                           "shift_x, shift_y (fractions of the larger side); thin lens: "
                           "aperture_radius, or fstop with focal_length (mm), focus_distance, "
                           "blades, rotation (degrees). Unset optional keys are None.")
        .def(py::init([](py::kwargs kw) { return from_kwargs<CameraDesc>(kw, "CameraDesc"); }))
        .def_readwrite("position", &CameraDesc::position)
        .def_readwrite("look_at", &CameraDesc::look_at)
        .def_readwrite("up", &CameraDesc::up)
        .def_readwrite("fov", &CameraDesc::fov)
        .def_readwrite("width", &CameraDesc::width)
        .def_readwrite("height", &CameraDesc::height)
        .def_readwrite("type", &CameraDesc::type)
        .def_readwrite("scale", &CameraDesc::scale)
        .def_readwrite("shift_x", &CameraDesc::shift_x)
        .def_readwrite("shift_y", &CameraDesc::shift_y)
        .def_readwrite("aperture_radius", &CameraDesc::aperture_radius)
        .def_readwrite("fstop", &CameraDesc::fstop)
        .def_readwrite("focal_length", &CameraDesc::focal_length)
        .def_readwrite("focus_distance", &CameraDesc::focus_distance)
        .def_readwrite("blades", &CameraDesc::blades)
        .def_readwrite("rotation", &CameraDesc::rotation)
        .def_readwrite("motion", &CameraDesc::motion,
                       "camera motion: a list of >= 2 facet.CameraStep at uniform steps over the "
                       "open shutter (scenes/FORMAT.md, Motion blur); [] = none")
        .def(py::self == py::self)
        .def("__repr__", [](const CameraDesc& c) {
            return "facet.CameraDesc(position=" + vec_str(c.position) +
                   ", look_at=" + vec_str(c.look_at) +
                   (c.type == "perspective" ? ", fov=" + std::to_string(c.fov)
                                            : ", type='" + c.type + "', scale=" +
                                                  std::to_string(c.scale.value_or(0.0))) +
                   ", width=" + std::to_string(c.width) + ", height=" + std::to_string(c.height) +
                   ")";
        });

    py::class_<RenderSettings>(
        m, "RenderSettings",
        "The scene's render settings: integrator ('path' | 'direct'), spp, "
        "time_budget_s, max_depth, seed, adaptive_threshold, adaptive_min_samples")
        .def(py::init(
            [](py::kwargs kw) { return from_kwargs<RenderSettings>(kw, "RenderSettings"); }))
        .def_readwrite("integrator", &RenderSettings::integrator)
        .def_readwrite("spp", &RenderSettings::spp)
        .def_readwrite("time_budget_s", &RenderSettings::time_budget_s)
        .def_readwrite("max_depth", &RenderSettings::max_depth)
        .def_readwrite("seed", &RenderSettings::seed)
        .def_readwrite("adaptive_threshold", &RenderSettings::adaptive_threshold)
        .def_readwrite("adaptive_min_samples", &RenderSettings::adaptive_min_samples)
        .def_readwrite("motion_blur", &RenderSettings::motion_blur,
                       "a facet.MotionBlur, or None (no motion blur)")
        .def_readwrite("film_transparent", &RenderSettings::film_transparent,
                       "Film > Transparent: the environment seen by camera rays is left out and "
                       "images are RGBA (h, w, 4), colour premultiplied")
        .def_readonly("width", &RenderSettings::width)
        .def_readonly("height", &RenderSettings::height)
        .def(py::self == py::self)
        .def("__repr__", [](const RenderSettings& r) {
            return "facet.RenderSettings(integrator='" + r.integrator +
                   "', spp=" + std::to_string(r.spp) +
                   ", max_depth=" + std::to_string(r.max_depth) +
                   ", seed=" + std::to_string(r.seed) + ")";
        });

    py::class_<TextureDesc>(
        m, "Texture",
        "A texture as a parameter value (scenes/FORMAT.md, Textures): Texture('wood.png', "
        "colorspace='srgb', filter='closest', wrap='repeat', uv_scale=(1, 1), uv_offset=(0, 0), "
        "uv_rotation=0, scale=1, channel='r'), or Texture.checker(c0, c1, scale=1, "
        "uv_scale=(1, 1), uv_offset=(0, 0), uv_rotation=0, value_scale=1) (scale: cells per "
        "unit; value_scale: the JSON's \"scale\"). Values are checked by build_scene (errors "
        "name the JSON pointer and the file).")
        .def(py::init([](const py::object& file, std::string colorspace, std::string filter,
                         std::string wrap, std::array<float, 2> uv_scale,
                         std::array<float, 2> uv_offset, double uv_rotation, double scale,
                         std::string channel) {
                 TextureDesc d;
                 if (py::isinstance<py::str>(file))
                     d.file = file.cast<std::string>();
                 else if (py::isinstance<py::array>(file))
                     d = texture_from_array(file, colorspace);
                 else
                     bad_argument("Texture", "expected a file name (str) or a numpy array, got " +
                                                 std::string(py::str(file.get_type())));
                 d.colorspace = std::move(colorspace);
                 d.filter = std::move(filter);
                 d.wrap = std::move(wrap);
                 d.uv_scale = {uv_scale[0], uv_scale[1]};
                 d.uv_offset = {uv_offset[0], uv_offset[1]};
                 d.uv_rotation = uv_rotation;
                 d.scale = scale;
                 d.channel = std::move(channel);
                 return d;
             }),
             "Texture(file, ...): file is an image file (relative to the description's "
             "base_dir), or a numpy array: H x W (grey) or H x W x C with C = 1 (grey), 3 (RGB) "
             "or 4 (RGBA), float32 or uint8, array[0] the TOP row of the picture (as image files "
             "and PIL store it: uv (0, 0) is array[-1, 0]). uint8 codes are value / 255 and "
             "sRGB-decoded by default (colorspace='linear' keeps them); float32 values are linear "
             "by default (colorspace='srgb' decodes them). Texels must be finite. The texels are "
             "copied; a scene holding one cannot be written to a JSON file.",
             py::arg("file"), py::arg("colorspace") = "", py::arg("filter") = "",
             py::arg("wrap") = "", py::arg("uv_scale") = std::array<float, 2>{1.f, 1.f},
             py::arg("uv_offset") = std::array<float, 2>{0.f, 0.f}, py::arg("uv_rotation") = 0.0,
             py::arg("scale") = 1.0, py::arg("channel") = "")
        .def_property_readonly("shape",
                               [](const TextureDesc& d) -> py::object {
                                   if (!d.image) return py::none();
                                   return py::make_tuple(d.image->height, d.image->width,
                                                         d.image->channels);
                               })
        .def_static(
            "checker",
            [](Vec3 c0, Vec3 c1, double cells, std::array<float, 2> uv_scale,
               std::array<float, 2> uv_offset, double uv_rotation, double value_scale) {
                TextureDesc d;
                d.kind = "checker";
                d.colors = {Rgb(c0), Rgb(c1)};
                d.checker_scale = cells;
                d.uv_scale = {uv_scale[0], uv_scale[1]};
                d.uv_offset = {uv_offset[0], uv_offset[1]};
                d.uv_rotation = uv_rotation;
                d.scale = value_scale;
                return d;
            },
            py::arg("c0"), py::arg("c1"), py::arg("scale") = 1.0,
            py::arg("uv_scale") = std::array<float, 2>{1.f, 1.f},
            py::arg("uv_offset") = std::array<float, 2>{0.f, 0.f}, py::arg("uv_rotation") = 0.0,
            py::arg("value_scale") = 1.0)
        .def_static(
            "vertex_color",
            [](std::string channel, double scale) {
                TextureDesc d;
                d.kind = "vertex_color";
                d.channel = std::move(channel);
                d.scale = scale;
                return d;
            },
            "The mesh's interpolated vertex colour as a texture (the JSON {\"vertex_color\": "
            "true}): channel '' (RGB) or 'r', 'g', 'b', 'a', 'luminance'; times scale.",
            py::arg("channel") = "", py::arg("scale") = 1.0)
        .def_static(
            "procedural",
            [](const std::string& kind, const std::string& coordinates, const py::object& mapping,
               double scale, const std::string& channel, const py::kwargs& params) {
                TextureDesc d;
                d.channel = channel;
                const TextureKindDef* k = find_texture_kind(kind);
                if (!k || !k->procedural) {
                    std::string names;
                    for (const TextureKindDef* x : texture_kinds())
                        if (x->procedural) names += " " + std::string(x->name);
                    bad_argument("Texture.procedural",
                                 "unknown procedural kind '" + kind + "' (one of" + names + ")");
                }
                d.kind = kind;
                d.coordinates = coordinates;
                d.scale = scale;
                if (!mapping.is_none()) {
                    const auto rows = mapping.cast<std::vector<std::vector<double>>>();
                    if (rows.size() != 3 || rows[0].size() != 4 || rows[1].size() != 4 ||
                        rows[2].size() != 4)
                        bad_argument("Texture.procedural",
                                     "mapping: expected 3 rows of 4 numbers (an affine map)");
                    for (int r = 0; r < 3; ++r)
                        for (int c = 0; c < 4; ++c) d.mapping[c][r] = rows[r][c];
                }
                for (const auto& [key, value] : params) {
                    const std::string name = py::str(key);
                    if (py::isinstance<py::str>(value)) {
                        d.params.set(name, value.cast<std::string>());
                    } else if (py::isinstance<py::bool_>(value)) {
                        d.params.set(name, value.cast<bool>());
                    } else if (py::isinstance<TextureDesc>(value)) {
                        // A composite kind's input fed by a texture.
                        d.inputs.push_back({name, value.cast<TextureDesc>()});
                    } else if (name == "stops") {
                        // A colour ramp's stops: [(position, (r, g, b[, a])), ...].
                        for (const auto& st : value.cast<py::list>()) {
                            const auto pair = st.cast<py::tuple>();
                            if (pair.size() != 2)
                                bad_argument("Texture.procedural",
                                             "stops: expected (position, (r, g, b[, a])) pairs");
                            TextureStop stop;
                            stop.position = pair[0].cast<double>();
                            const auto c = pair[1].cast<std::vector<double>>();
                            if (c.size() != 3 && c.size() != 4)
                                bad_argument("Texture.procedural",
                                             "stops: a colour has 3 or 4 components");
                            for (std::size_t k = 0; k < c.size(); ++k) stop.color[int(k)] = c[k];
                            d.stops.push_back(stop);
                        }
                    } else if (py::isinstance<py::sequence>(value)) {
                        const auto c = value.cast<std::vector<double>>();
                        if (c.size() != 3)
                            bad_argument("Texture.procedural",
                                         name +
                                             ": expected a number, a name, a colour (r, g, b) "
                                             "or a Texture");
                        d.params.set(name, Rgb(float(c[0]), float(c[1]), float(c[2])));
                    } else {
                        d.params.set(name, value.cast<double>());
                    }
                }
                return d;
            },
            "A procedural texture (scenes/FORMAT.md, Procedural textures): "
            "Texture.procedural('noise', coordinates='object', mapping=[[1, 0, 0, 0], [0, 1, 0, "
            "0], [0, 0, 1, 0]], value_scale=1, scale=5, detail=2, ...): the kind's parameters as "
            "keywords "
            "(numbers, names, booleans, colours (r, g, b), Textures for a composite kind's inputs "
            "(math, vector_math, mix_rgb, color_ramp), a colour ramp's "
            "stops=[(position, (r, g, b[, a])), ...]; checked by build_scene against the kind's "
            "table), the point "
            "'generated' (default), 'object', 'uv', 'normal', 'reflection', 'camera' or 'window', "
            "an optional affine mapping (3 rows of 4), "
            "a value multiplier (the JSON's \"scale\" beside the kind's object), and an optional "
            "channel ('r', 'g', 'b' or 'luminance': that channel of the colour, as grey).",
            py::arg("kind"), py::arg("coordinates") = "", py::arg("mapping") = py::none(),
            py::arg("value_scale") = 1.0, py::arg("channel") = "")
        .def_static(
            "mapping_point",
            [](Vec3 location, Vec3 rotation, Vec3 scale) {
                const glm::dmat4 m = mapping_point_matrix(glm::dvec3(location),
                                                          glm::dvec3(rotation), glm::dvec3(scale));
                std::vector<std::vector<double>> rows(3, std::vector<double>(4));
                for (int r = 0; r < 3; ++r)
                    for (int c = 0; c < 4; ++c) rows[r][c] = m[c][r];
                return rows;
            },
            "Blender's Mapping node of type Point as the rows of an affine map (rotation in "
            "radians, Euler XYZ): the `mapping` of Texture.procedural.",
            py::arg("location"), py::arg("rotation"), py::arg("scale"))
        .def_readonly("file", &TextureDesc::file)
        .def_readonly("kind", &TextureDesc::kind)
        .def_readonly("coordinates", &TextureDesc::coordinates)
        .def_property_readonly("is_checker",
                               [](const TextureDesc& d) { return d.kind == "checker"; })
        .def_property_readonly("is_vertex_color",
                               [](const TextureDesc& d) { return d.kind == "vertex_color"; })
        .def_readonly("channel", &TextureDesc::channel)
        .def_readonly("scale", &TextureDesc::scale)
        .def(py::self == py::self)
        .def("__repr__", [](const TextureDesc& d) {
            return d.kind == "vertex_color" ? "facet.Texture.vertex_color('" + d.channel + "')"
                   : d.kind == "checker"    ? std::string("facet.Texture.checker(...)")
                   : d.kind != "image"      ? "facet.Texture.procedural('" + d.kind + "', ...)"
                                            : "facet.Texture('" + d.file + "')";
        });

    // A combination's sub-materials (mix, add): names (str) or MaterialDesc objects.
    auto sub_materials_from = [](py::handle v) {
        if (!py::isinstance<py::list>(v) && !py::isinstance<py::tuple>(v))
            bad_argument("materials", "expected a list [a, b] of material names or MaterialDesc");
        std::vector<MaterialDesc> out;
        for (py::handle c : v) {
            if (py::isinstance<py::str>(c)) {
                MaterialDesc r;
                r.ref = c.cast<std::string>();
                out.push_back(std::move(r));
            } else if (py::isinstance<MaterialDesc>(c)) {
                out.push_back(c.cast<MaterialDesc>());
            } else {
                bad_argument("materials", "expected a material name or a MaterialDesc");
            }
        }
        return out;
    };
    // A material's normal map and bump map (scenes/FORMAT.md "Normal maps", "Bump maps"): a
    // dict {"texture": facet.Texture, "strength": s, "xy_scale": k} / {"texture": ...,
    // "distance": d, "strength": s}, the texture required, the numbers optional (the format's
    // defaults); any other key is an error.
    auto map_dict = [](py::handle v, const char* what, std::initializer_list<const char*> keys) {
        if (!py::isinstance<py::dict>(v))
            bad_argument(what, "expected a dict {\"texture\": facet.Texture, ...}");
        auto d = py::reinterpret_borrow<py::dict>(v);
        if (!d.contains("texture") || !py::isinstance<TextureDesc>(d["texture"]))
            bad_argument(what, "\"texture\": expected a facet.Texture");
        for (auto [k, unused] : d) {
            const std::string name = k.cast<std::string>();
            if (name != "texture" &&
                std::none_of(keys.begin(), keys.end(), [&](const char* x) { return name == x; }))
                bad_argument(what, "unknown key '" + name + "'");
        }
        return d;
    };
    auto number_or = [](const py::dict& d, const char* key, const char* what, double def) {
        if (!d.contains(key)) return def;
        try {
            return d[key].cast<double>();
        } catch (const py::cast_error&) {
            bad_argument(what, std::string("\"") + key + "\": expected a number");
        }
    };
    auto normal_map_from = [map_dict, number_or](py::handle v) {
        const py::dict d = map_dict(v, "normal_map", {"strength", "xy_scale"});
        return MaterialDesc::NormalMap{d["texture"].cast<TextureDesc>(),
                                       number_or(d, "strength", "normal_map", 1.0),
                                       number_or(d, "xy_scale", "normal_map", 1.0)};
    };
    auto bump_from = [map_dict, number_or](py::handle v) {
        const py::dict d = map_dict(v, "bump", {"distance", "strength"});
        return MaterialDesc::Bump{d["texture"].cast<TextureDesc>(),
                                  number_or(d, "distance", "bump", 1.0),
                                  number_or(d, "strength", "bump", 1.0)};
    };
    // The normal_map / bump properties: a dict of the map's keys, None without one.
    auto normal_map_dict = [](const MaterialDesc::NormalMap& n, py::dict& out) {
        out["strength"] = n.strength;
        out["xy_scale"] = n.xy_scale;
    };
    auto bump_dict = [](const MaterialDesc::Bump& b, py::dict& out) {
        out["distance"] = b.distance;
        out["strength"] = b.strength;
    };
    auto map_getter = [](auto member, auto fill) {
        return [member, fill](const MaterialDesc& d) -> py::object {
            const auto& map = d.*member;
            if (!map) return py::none();
            py::dict out;
            out["texture"] = map->texture;
            fill(*map, out);
            return out;
        };
    };
    auto map_setter = [](auto member, auto from) {
        return [member, from](MaterialDesc& d, py::object v) {
            if (v.is_none())
                (d.*member).reset();
            else
                d.*member = from(v);
        };
    };
    py::class_<MaterialDesc>(m, "MaterialDesc",
                             "A named material: model name (facet.models()) and parameters, "
                             "e.g. MaterialDesc('ggx', alpha=0.3); a facet.Texture may stand "
                             "for any colour or number parameter; mix and add take "
                             "materials=[a, b] (names or MaterialDesc); normal_map={'texture': "
                             "facet.Texture, 'strength', 'xy_scale'} and bump={'texture', "
                             "'distance', 'strength'} as in the scene format")
        .def(py::init([sub_materials_from, normal_map_from, bump_from](
                          std::string model, py::object params, py::kwargs kw) {
                 MaterialDesc d;
                 d.model = std::move(model);
                 // Textures go to `textures`, every other value to the ParamSet.
                 for (py::handle src : {py::handle(params), py::handle(kw)}) {
                     if (src.is_none()) continue;
                     if (!py::isinstance<py::dict>(src))
                         bad_argument("params", "expected a dict of parameters");
                     py::dict constants;
                     for (auto [k, v] : py::reinterpret_borrow<py::dict>(src)) {
                         if (k.cast<std::string>() == "materials")
                             d.materials = sub_materials_from(v);
                         else if (k.cast<std::string>() == "normal_map")
                             d.normal_map = normal_map_from(v);
                         else if (k.cast<std::string>() == "bump")
                             d.bump = bump_from(v);
                         else if (py::isinstance<TextureDesc>(v))
                             d.textures[k.cast<std::string>()] = v.cast<TextureDesc>();
                         else
                             constants[k] = v;
                     }
                     const ParamSet set = params_from_dict(constants, "params");
                     for (const auto& [k, v] : set.values()) d.params.set(k, v);
                 }
                 return d;
             }),
             py::arg("model") = "", py::arg("params") = py::none())
        .def_readwrite("model", &MaterialDesc::model)
        .def_property(
            "materials",
            [](const MaterialDesc& d) {
                py::list out;
                for (const MaterialDesc& c : d.materials)
                    out.append(c.ref.empty() ? py::cast(c) : py::object(py::str(c.ref)));
                return out;
            },
            [sub_materials_from](MaterialDesc& d, py::object v) {
                d.materials = sub_materials_from(v);
            })
        .def_property("normal_map", map_getter(&MaterialDesc::normal_map, normal_map_dict),
                      map_setter(&MaterialDesc::normal_map, normal_map_from))
        .def_property("bump", map_getter(&MaterialDesc::bump, bump_dict),
                      map_setter(&MaterialDesc::bump, bump_from))
        .def_property(
            "params", [](const MaterialDesc& d) { return params_to_dict(d.params); },
            [](MaterialDesc& d, py::object p) { d.params = params_from_dict(p, "params"); })
        .def_property_readonly("textures",
                               [](const MaterialDesc& d) {
                                   py::dict out;
                                   for (const auto& [k, t] : d.textures) out[py::str(k)] = t;
                                   return out;
                               })
        .def(py::self == py::self)
        .def("__repr__", [](const MaterialDesc& d) {
            return "facet.MaterialDesc('" + d.model + "', " +
                   std::string(py::repr(params_to_dict(d.params))) + ")";
        });

    py::class_<MeshData>(
        m, "MeshData",
        "Triangle-mesh arrays: positions float32 (n, 3), indices int32 (m, 3), "
        "normals float32 (n, 3) or None, uvs float32 (n, 2) or None (texture coordinates, "
        "(0, 0) the bottom-left of an image), tangents float32 (n, 4) or None (xyz and the "
        "bitangent sign, glTF's TANGENT), colors float32 (n, 3) or (n, 4) or None (linear "
        "RGB(A) vertex colours in [0, 1], read by Texture.vertex_color()). Used in place when of "
        "exactly these dtypes and C-contiguous (kept alive by the mesh), else converted once.")
        .def(py::init([](py::handle positions, py::handle indices, py::handle normals,
                         py::handle uvs, py::handle tangents, py::handle colors) {
                 return mesh_from_arrays(positions, indices, normals, uvs, tangents, colors);
             }),
             py::arg("positions"), py::arg("indices"), py::arg("normals") = py::none(),
             py::arg("uvs") = py::none(), py::arg("tangents") = py::none(),
             py::arg("colors") = py::none())
        .def_property_readonly("positions",
                               [](const MeshData& d) { return mesh_view(d.positions, d); })
        .def_property_readonly("indices", [](const MeshData& d) { return mesh_view(d.indices, d); })
        .def_property_readonly("normals",
                               [](const MeshData& d) -> py::object {
                                   if (d.normals.empty()) return py::none();
                                   return mesh_view(d.normals, d);
                               })
        .def_property_readonly("uvs",
                               [](const MeshData& d) -> py::object {
                                   if (d.uvs.empty()) return py::none();
                                   return mesh_view(d.uvs, d, 2);
                               })
        .def_property_readonly("tangents",
                               [](const MeshData& d) -> py::object {
                                   if (d.tangents.empty()) return py::none();
                                   return mesh_view(d.tangents, d, 4);
                               })
        .def_property_readonly(
            "colors",
            [](const MeshData& d) -> py::object {
                if (d.colors.empty() || d.num_vertices() == 0) return py::none();
                return mesh_view(d.colors, d, py::ssize_t(d.colors.size() / d.num_vertices()));
            })
        .def_property_readonly("num_vertices", &MeshData::num_vertices)
        .def_property_readonly("num_triangles", &MeshData::num_triangles)
        .def(py::self == py::self)
        .def("__repr__", [](const MeshData& d) {
            return "facet.MeshData(" + std::to_string(d.num_vertices()) + " vertices, " +
                   std::to_string(d.num_triangles()) + " triangles" +
                   (d.normals.empty() ? "" : ", normals") + ")";
        });

    // Curve arrays (ShapeDesc::curves): copied in and out as float32 / uint32 numpy arrays.
    auto floats_in = [](py::handle a, const char* name) {
        if (a.is_none()) return std::vector<float>{};
        if (py::isinstance<py::str>(a))
            throw py::type_error(std::string(name) + ": expected a sequence of numbers");
        const auto arr = py::array_t<float, py::array::c_style | py::array::forcecast>::ensure(a);
        if (!arr) throw py::type_error(std::string(name) + ": expected a sequence of numbers");
        return std::vector<float>(arr.data(), arr.data() + arr.size());
    };
    auto floats_out = [](const std::vector<float>& v, py::ssize_t cols) -> py::object {
        if (v.empty()) return py::none();
        py::array_t<float> a(cols > 1 ? std::vector<py::ssize_t>{py::ssize_t(v.size()) / cols, cols}
                                      : std::vector<py::ssize_t>{py::ssize_t(v.size())});
        std::copy(v.begin(), v.end(), a.mutable_data());
        return std::move(a);
    };
    m.def(
        "curve_random",
        [](py::handle indices) {
            const auto a =
                py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>::ensure(
                    indices);
            if (!a) throw py::type_error("indices: expected a sequence of integers");
            py::array_t<float> out(a.size());
            for (py::ssize_t i = 0; i < a.size(); ++i) {
                if (a.data()[i] < 0 || a.data()[i] > 0xFFFFFFFFll)
                    throw py::value_error("indices[" + std::to_string(i) +
                                          "]: must be in [0, 2^32)");
                out.mutable_data()[i] = facet::render::curve_random(std::uint32_t(a.data()[i]));
            }
            return out;
        },
        py::arg("indices"),
        "Cycles 3.4's random values of the strands of these indices in a hair geometry "
        "(hash_uint2_to_float(i, 0): what a curves shape without strand_random gives strand i), "
        "float32.");
    py::class_<CurveData>(
        m, "CurveData",
        "Curve arrays of a 'curves' shape (scenes/FORMAT.md, \"Curves\"): points float32 (n, 3), "
        "radius (a number, or float32 (n,): one per point), counts uint32 (strands,) or None "
        "(the control points of each strand; None: one strand), root_uvs float32 (strands, 2) or "
        "None (each strand's texture coordinates), strand_random float32 (strands,) or None "
        "(each strand's random value in [0, 1]; None: Cycles' hash of its index). Copied in as "
        "float32/uint32.")
        .def(py::init([floats_in](py::handle points, py::handle radius, py::handle counts,
                                  py::handle root_uvs, py::handle strand_random) {
                 CurveData c;
                 c.points = floats_in(points, "points");
                 if (py::isinstance<py::float_>(radius) || py::isinstance<py::int_>(radius))
                     c.radius = {radius.cast<float>()};
                 else
                     c.radius = floats_in(radius, "radius");
                 if (!counts.is_none()) {
                     const auto a =
                         py::array_t<std::int64_t,
                                     py::array::c_style | py::array::forcecast>::ensure(counts);
                     if (!a) throw py::type_error("counts: expected a sequence of integers");
                     for (py::ssize_t i = 0; i < a.size(); ++i) {
                         if (a.data()[i] < 0 || a.data()[i] > 0xFFFFFFFFll)
                             throw py::value_error("counts[" + std::to_string(i) +
                                                   "]: must be in [0, 2^32)");
                         c.counts.push_back(std::uint32_t(a.data()[i]));
                     }
                 }
                 c.root_uvs = floats_in(root_uvs, "root_uvs");
                 c.strand_random = floats_in(strand_random, "strand_random");
                 return c;
             }),
             py::arg("points"), py::arg("radius"), py::arg("counts") = py::none(),
             py::arg("root_uvs") = py::none(), py::arg("strand_random") = py::none())
        .def_property_readonly("points",
                               [floats_out](const CurveData& c) { return floats_out(c.points, 3); })
        .def_property_readonly("radius",
                               [floats_out](const CurveData& c) -> py::object {
                                   if (c.radius.size() == 1) return py::float_(c.radius[0]);
                                   return floats_out(c.radius, 1);
                               })
        .def_property_readonly("counts",
                               [](const CurveData& c) -> py::object {
                                   if (c.counts.empty()) return py::none();
                                   py::array_t<std::uint32_t> a(py::ssize_t(c.counts.size()));
                                   std::copy(c.counts.begin(), c.counts.end(), a.mutable_data());
                                   return std::move(a);
                               })
        .def_property_readonly(
            "root_uvs", [floats_out](const CurveData& c) { return floats_out(c.root_uvs, 2); })
        .def_property_readonly(
            "strand_random",
            [floats_out](const CurveData& c) { return floats_out(c.strand_random, 1); })
        .def_property_readonly("num_points", &CurveData::num_points)
        .def(py::self == py::self)
        .def("__repr__", [](const CurveData& c) {
            return "facet.CurveData(" + std::to_string(c.num_points()) + " points, " +
                   std::to_string(c.counts.empty() ? 1 : c.counts.size()) + " strands)";
        });

    py::class_<ShapeDesc> shape_desc(
        m, "ShapeDesc",
        "One shape (scenes/FORMAT.md; `facet scene-format` lists the kinds and their fields): "
        "kind and the fields of that kind. ShapeDesc('mesh', positions=P, indices=I, "
        "material_ref='white') builds the MeshData from arrays.");
    shape_desc
        .def(py::init([](py::object kind, py::kwargs kw) {
                 py::object self = py::cast(ShapeDesc{});
                 if (!kind.is_none()) self.attr("kind") = kind;
                 py::kwargs rest;
                 py::object positions = py::none(), indices = py::none(), normals = py::none(),
                            uvs = py::none(), tangents = py::none(), colors = py::none();
                 for (auto [key, value] : kw) {
                     const std::string k = key.cast<std::string>();
                     if (k == "positions")
                         positions = py::reinterpret_borrow<py::object>(value);
                     else if (k == "indices")
                         indices = py::reinterpret_borrow<py::object>(value);
                     else if (k == "normals")
                         normals = py::reinterpret_borrow<py::object>(value);
                     else if (k == "uvs")
                         uvs = py::reinterpret_borrow<py::object>(value);
                     else if (k == "tangents")
                         tangents = py::reinterpret_borrow<py::object>(value);
                     else if (k == "colors")
                         colors = py::reinterpret_borrow<py::object>(value);
                     else
                         rest[key] = value;
                 }
                 if (!positions.is_none() || !indices.is_none()) {
                     if (positions.is_none() || indices.is_none())
                         throw py::value_error("ShapeDesc: give positions and indices together");
                     self.attr("mesh") = py::cast(
                         mesh_from_arrays(positions, indices, normals, uvs, tangents, colors));
                     if (kind.is_none()) self.attr("kind") = py::str("mesh");
                 } else if (!normals.is_none() || !uvs.is_none() || !tangents.is_none() ||
                            !colors.is_none()) {
                     throw py::value_error(
                         "ShapeDesc: normals, uvs, tangents and colors need positions and "
                         "indices");
                 }
                 if (!kind.is_none())
                     check_kind_keywords(rest, shape_kind(self.cast<const ShapeDesc&>().kind),
                                         kCommonShapeAttributes, "ShapeDesc");
                 set_fields(self, rest, "ShapeDesc");
                 return self.cast<ShapeDesc>();
             }),
             py::arg("kind") = py::none())
        .def_property(
            "kind", [](const ShapeDesc& s) { return s.kind; },
            [](ShapeDesc& s, py::handle v) { s.kind = kind_from<ShapeKind>(v, "shape kind"); })
        .def_readwrite("name", &ShapeDesc::name)
        .def_readwrite("material_ref", &ShapeDesc::material_ref)
        .def_readwrite("material", &ShapeDesc::material)
        .def_readwrite("emission", &ShapeDesc::emission)
        .def_readwrite(
            "emission_texture", &ShapeDesc::emission_texture,
            "a facet.Texture instead of `emission` (scenes/FORMAT.md, Textures), or None")
        .def_readwrite("two_sided", &ShapeDesc::two_sided)
        .def_readwrite("flip_normals", &ShapeDesc::flip_normals)
        .def_readwrite("holdout", &ShapeDesc::holdout,
                       "a holdout: alpha 0 and colour 0 where camera rays see it")
        .def_readwrite("shadow_catcher", &ShapeDesc::shadow_catcher,
                       "a shadow catcher: only the shadows cast on it are kept, as alpha "
                       "(scenes/FORMAT.md, Shadow catchers)")
        .def_property(
            "visibility", [](const ShapeDesc& d) { return visibility_dict(d.visibility); },
            [](ShapeDesc& d, const py::dict& v) { d.visibility = visibility_mask(v); },
            "ray visibility: {'camera': bool, 'diffuse', 'glossy', 'transmission', "
            "'volume_scatter', 'shadow'}; a kind left out is visible (scenes/FORMAT.md, Ray "
            "visibility)")
        .def_property(
            "light_path", [](const ShapeDesc& d) { return light_path_list(d.light_path); },
            [](ShapeDesc& d, const py::list& l) { d.light_path = light_path_entries(l); },
            "Light Path switches: [{'ray': 'camera' | 'shadow' | 'diffuse' | 'glossy' | "
            "'singular' | 'reflection' | 'transmission', 'material': name or MaterialDesc, "
            "'emission': colour}] (scenes/FORMAT.md, Light Path switches)")
        .def_readwrite("transform", &ShapeDesc::transform)
        .def_readwrite("motion", &ShapeDesc::motion,
                       "transformation motion: a list of >= 2 object-to-world (4, 4) transforms "
                       "at uniform steps over the open shutter (scenes/FORMAT.md, Motion blur); "
                       "with motion blur on it replaces `transform`; [] = none")
        .def_property(
            "motion_positions", [](const ShapeDesc& s) { return float_steps(s.motion_positions); },
            [](ShapeDesc& s, const py::iterable& v) {
                s.motion_positions = float_steps(v, "motion_positions");
            },
            "deformation motion (mesh, curves): a list of >= 2 flat float arrays of 3n "
            "object-space vertex positions (curves: control points) at uniform steps over the "
            "open shutter (scenes/FORMAT.md, Motion blur); [] = none")
        .def_property(
            "motion_normals", [](const ShapeDesc& s) { return float_steps(s.motion_normals); },
            [](ShapeDesc& s, const py::iterable& v) {
                s.motion_normals = float_steps(v, "motion_normals");
            },
            "the vertex normals per step of `motion_positions` (exactly when the mesh has "
            "normals); [] = none")
        .def_property(
            "texture_space",
            [](const ShapeDesc& s) -> py::object {
                if (!s.texture_space) return py::none();
                return py::make_tuple(s.texture_space->location, s.texture_space->size);
            },
            [](ShapeDesc& s, const py::object& v) {
                if (v.is_none()) {
                    s.texture_space.reset();
                    return;
                }
                const auto t = v.cast<std::pair<Vec3, Vec3>>();
                s.texture_space = ShapeDesc::TextureSpace{t.first, t.second};
            },
            "(location, size): the Generated coordinates' texture space (Blender's "
            "texspace_location, texspace_size), or None: the shape's bounding box")
        .def(py::self == py::self)
        .def("__repr__", [](const ShapeDesc& s) {
            return "facet.ShapeDesc('" + kind_name(s.kind) + "'" +
                   (s.name.empty() ? "" : ", name='" + s.name + "'") +
                   (s.material_ref.empty() ? "" : ", material_ref='" + s.material_ref + "'") + ")";
        });
    def_kind_fields(shape_desc, shape_kinds());

    py::class_<LightDesc> light_desc(
        m, "LightDesc",
        "One light (scenes/FORMAT.md; `facet scene-format` lists the kinds and their fields): "
        "kind and its fields");
    def_kind_desc<LightDesc, LightKind>(light_desc, "LightDesc", "light kind", light_kinds());

    py::class_<MediumDesc> medium_desc(
        m, "MediumDesc",
        "One medium (scenes/FORMAT.md, \"Media\"; `facet scene-format` lists the kinds and "
        "their fields): kind and its fields");
    def_kind_desc<MediumDesc, MediumKind>(medium_desc, "MediumDesc", "medium kind", medium_kinds());
    medium_desc.def_readwrite("transform", &MediumDesc::transform,
                              "grid kind: the file's space to world, a (4, 4) affine matrix; "
                              "None = identity");

    py::class_<PySceneDescription>(
        m, "SceneDescription",
        "The plain-data scene (scene_description.h): description, camera (CameraDesc), materials "
        "(dict name -> MaterialDesc), shapes (list of ShapeDesc), prototypes (dict name -> list "
        "of ShapeDesc, placed by ShapeDesc('instance', of=name, transform=M)), lights (list of "
        "LightDesc), media (dict name -> MediumDesc), world_medium (a name of media or ''), "
        "render (RenderSettings), base_dir. Mutable in place; build it with "
        "build_scene().")
        .def(py::init([](py::kwargs kw) {
            py::object self = py::cast(PySceneDescription{});
            set_fields(self, kw, "SceneDescription");
            return self.cast<PySceneDescription>();
        }))
        .def_readwrite("description", &PySceneDescription::description)
        .def_property(
            "camera", [](const PySceneDescription& d) { return d.camera; },
            [](PySceneDescription& d, py::object c) {
                element<CameraDesc>(c, "camera", "CameraDesc");
                d.camera = c;
            })
        .def_property(
            "render", [](const PySceneDescription& d) { return d.render; },
            [](PySceneDescription& d, py::object r) {
                element<RenderSettings>(r, "render", "RenderSettings");
                d.render = r;
            })
        .def_property(
            "materials", [](const PySceneDescription& d) { return d.materials; },
            [](PySceneDescription& d, py::dict v) { d.materials = v; })
        .def_property(
            "shapes", [](const PySceneDescription& d) { return d.shapes; },
            [](PySceneDescription& d, py::iterable v) { d.shapes = py::list(v); })
        .def_property(
            "prototypes", [](const PySceneDescription& d) { return d.prototypes; },
            [](PySceneDescription& d, py::dict v) { d.prototypes = v; })
        .def_property(
            "lights", [](const PySceneDescription& d) { return d.lights; },
            [](PySceneDescription& d, py::iterable v) { d.lights = py::list(v); })
        .def_property(
            "media", [](const PySceneDescription& d) { return d.media; },
            [](PySceneDescription& d, py::dict v) { d.media = v; })
        .def_readwrite("world_medium", &PySceneDescription::world_medium)
        .def_readwrite("base_dir", &PySceneDescription::base_dir)
        .def("__eq__",
             [](const PySceneDescription& a, py::handle b) -> py::object {
                 if (!py::isinstance<PySceneDescription>(b))
                     return py::reinterpret_borrow<py::object>(Py_NotImplemented);
                 return py::bool_(to_cpp(a) == to_cpp(b.cast<const PySceneDescription&>()));
             })
        .def(
            "to_json", [](const PySceneDescription& d) { return write_scene_json(to_cpp(d)); },
            "write_scene_json(self)")
        .def(
            "fingerprint", [](const PySceneDescription& d) { return fingerprint(to_cpp(d)); },
            "fingerprint(self)")
        .def(py::pickle(
            [](const PySceneDescription& d) {
                return py::make_tuple(write_scene_json(to_cpp(d)), d.base_dir);
            },
            [](py::tuple t) {
                return from_cpp(parse_scene_description(t[0].cast<std::string>(), "<pickle>",
                                                        t[1].cast<std::string>()));
            }))
        .def("__repr__", [](const PySceneDescription& d) {
            return "facet.SceneDescription(" + std::to_string(d.materials.size()) + " materials, " +
                   std::to_string(d.shapes.size()) + " shapes, " + std::to_string(d.lights.size()) +
                   " lights)";
        });

    m.def(
        "read_scene_description",
        [](const std::string& path) {
            SceneDescription d;
            {
                py::gil_scoped_release release;
                d = read_scene_description(path);
            }
            return from_cpp(std::move(d));
        },
        py::arg("path"), "Reads a JSON scene file (scenes/FORMAT.md) into a SceneDescription.");
    m.def(
        "parse_scene_description",
        [](const std::string& text, const std::string& name, const std::string& base_dir) {
            return from_cpp(parse_scene_description(text, name, base_dir));
        },
        py::arg("text"), py::arg("name") = "<string>", py::arg("base_dir") = ".",
        "Parses JSON scene text; `name` prefixes error messages.");
    m.def(
        "write_scene_json", [](py::handle desc) { return write_scene_json(description_arg(desc)); },
        py::arg("desc"), "The description as JSON text (FORMAT.md version 1).");
    m.def(
        "write_scene_file",
        [](py::handle desc, const std::string& path) {
            write_scene_file(description_arg(desc), path);
        },
        py::arg("desc"), py::arg("path"), "Writes the description as a JSON scene file.");
    m.def(
        "export_pov",
        [](py::handle desc, const std::string& path, int area_grid, int glossy_samples,
           const std::string& environment, const std::string& radiosity, const std::string& ini,
           const std::string& name, const std::string& mipmap, int media_intervals) {
            const SceneDescription d = description_arg(desc);
            PovExportOptions o;
            o.mipmap = mipmap;
            o.media_intervals = media_intervals;
            o.area_grid = area_grid;
            o.glossy_samples = glossy_samples;
            o.environment = environment;
            o.radiosity = radiosity;
            py::gil_scoped_release release;
            export_pov_file(d, name, path, o, ini);
        },
        py::arg("desc"), py::arg("path"), py::arg("area_grid") = 8, py::arg("glossy_samples") = 0,
        py::arg("environment") = "error", py::arg("radiosity") = "off", py::arg("ini") = "",
        py::arg("name") = "python", py::arg("mipmap") = "error", py::arg("media_intervals") = 128,
        "Writes the description as POV-Ray SDL for povray-facet (facet export-pov; "
        "docs/povray.md). What POV-Ray cannot express raises ValueError naming the JSON path; a "
        "bad option raises ValueError naming it.");
    m.def(
        "fingerprint", [](py::handle desc) { return fingerprint(description_arg(desc)); },
        py::arg("desc"),
        "64-bit fingerprint of everything in the description that changes the image.");

    py::class_<SceneHandle>(m, "Scene",
                            "A built, renderable scene (immutable). From build_scene() or "
                            "load_scene().")
        .def_property_readonly("name", [](const SceneHandle& s) { return s.scene->name(); })
        .def_property_readonly("warnings",
                               [](const SceneHandle& s) {
                                   auto w = s.scene->warnings();
                                   return std::vector<std::string>(w.begin(), w.end());
                               })
        .def_readonly("degenerate_triangles", &SceneHandle::degenerate_triangles)
        .def_readonly("seconds_before_bvh", &SceneHandle::seconds_before_bvh,
                      "build_scene's time before the BVH build (BuildReport)")
        .def_readonly("seconds_bvh", &SceneHandle::seconds_bvh,
                      "build_scene's BVH build time (BuildReport)")
        .def_property_readonly("fingerprint",
                               [](const SceneHandle& s) { return s.scene->fingerprint(); })
        .def_property_readonly("width",
                               [](const SceneHandle& s) { return s.scene->camera().width; })
        .def_property_readonly("height",
                               [](const SceneHandle& s) { return s.scene->camera().height; })
        .def_property_readonly("settings", [](const SceneHandle& s) { return s.scene->settings(); })
        .def_property_readonly("num_shapes",
                               [](const SceneHandle& s) { return s.scene->shapes().size(); })
        .def_property_readonly("num_lights",
                               [](const SceneHandle& s) { return s.scene->lights().size(); })
        .def_property_readonly(
            "num_triangles", [](const SceneHandle& s) { return s.scene->features().num_triangles; })
        .def(
            "light_pmfs",
            [](const SceneHandle& s, const std::string& selection) {
                const Scene& sc = *s.scene;
                LightDistribution d;
                if (selection == "power")
                    d = sc.light_distribution();
                else if (selection == "view")
                    d = sc.view_light_distribution();
                else if (selection == "uniform")
                    d = LightDistribution::uniform(sc.lights());
                else
                    bad_argument("selection",
                                 "expected 'view', 'power' or 'uniform' (the tree's choice "
                                 "depends on the shaded point), got '" +
                                     selection + "'");
                std::vector<float> p(sc.lights().size(), 0.f);
                if (!d.empty())
                    for (std::size_t i = 0; i < p.size(); ++i) p[i] = d.pmf(i);
                return p;
            },
            py::arg("selection") = "view",
            "Next-event estimation's probability of choosing each light (light_selection "
            "'view', 'power' or 'uniform'); 0 for lights it never samples.")
        .def(
            "explain", [](const SceneHandle& s) { return s.scene->features().describe(); },
            "What the scene contains (facet render --explain)")
        .def("__repr__", [](const SceneHandle& s) {
            return "facet.Scene('" + s.scene->name() + "', " +
                   std::to_string(s.scene->camera().width) + "x" +
                   std::to_string(s.scene->camera().height) + ")";
        });

    m.def(
        "build_scene",
        [](py::handle desc, const std::string& name, std::optional<std::uint64_t> max_triangles,
           bool allow_files) {
            SceneDescription d = description_arg(desc);
            SceneLimits limits;
            if (max_triangles) limits.max_triangles = *max_triangles;
            limits.allow_files = allow_files;
            BuildReport report;
            std::optional<Scene> scene;
            {
                py::gil_scoped_release release;
                scene.emplace(build_scene(d, name, limits, &report));
            }
            return make_handle(std::move(*scene), report);
        },
        py::arg("desc"), py::arg("name") = "python", py::arg("max_triangles") = py::none(),
        py::arg("allow_files") = true,
        "Validates the description and builds the scene (Embree BVH). Errors raise ValueError "
        "naming the shape or material ('<name>: /shapes/3 ('Suzanne'): ...'); dropped zero-area "
        "triangles are counted in Scene.warnings and Scene.degenerate_triangles.");
    m.def(
        "load_scene",
        [](const std::string& path) {
            std::optional<Scene> scene;
            {
                py::gil_scoped_release release;
                scene.emplace(load_scene(path));
            }
            return make_handle(std::move(*scene));
        },
        py::arg("path"), "Loads a JSON scene file (read_scene_description + build_scene).");
    m.def(
        "load_scene_from_string",
        [](const std::string& json, const std::string& name, const std::string& base_dir) {
            std::optional<Scene> scene;
            {
                py::gil_scoped_release release;
                scene.emplace(load_scene_from_string(json, name, base_dir));
            }
            return make_handle(std::move(*scene));
        },
        py::arg("json"), py::arg("name") = "<string>", py::arg("base_dir") = ".",
        "Loads a scene from JSON text.");
}

}  // namespace facet::python
