// Shared pieces of the facet Python module (_facet): type casters for GLM vectors and matrices,
// numpy helpers, and the bind_* functions of each part.
//
// Conventions:
//  - Names mirror the C++ API in snake_case (Mitsuba's bindings do the same).
//  - Vec3 / Rgb arguments accept any sequence of three numbers (tuple, list, numpy array); a
//    single number means grey (the scene format's rule for colours). They are returned as
//    tuples of three floats.
//  - glm::dmat4 transforms are numpy (4, 4) float64 arrays in mathematical row/column order
//    (m[row, col]), i.e. the transpose of glm's m[column][row] storage.
//  - Arrays of directions are (n, 3) or (3,) of any real dtype (converted to float32, copied
//    when not contiguous); results have the same leading shape.
//  - Errors: the C++ exceptions become Python exceptions carrying their message (module.cpp);
//    bad arguments raise ValueError naming the argument.
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/operators.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cmath>
#include <cstdint>
#include <memory>
#include <string>

#include <glm/glm.hpp>

#include "facet/registry.h"
#include "facet/render/scene.h"
#include "facet/render/scene_description.h"
#include "facet/types.h"

namespace pybind11::detail {

template <>
struct type_caster<glm::vec3> {
    PYBIND11_TYPE_CASTER(glm::vec3, const_name("tuple[float, float, float]"));

    bool load(handle src, bool convert) {
        if (!src) return false;
        if (PyBool_Check(src.ptr()) || PyUnicode_Check(src.ptr()) || PyBytes_Check(src.ptr()))
            return false;
        if (!PySequence_Check(src.ptr())) {
            // One number (Python or numpy scalar): grey.
            if (!PyNumber_Check(src.ptr())) return false;
            PyObject* f = PyNumber_Float(src.ptr());
            if (!f) {
                PyErr_Clear();
                return false;
            }
            value = glm::vec3(float(PyFloat_AsDouble(f)));
            Py_DECREF(f);
            return true;
        }
        sequence seq = reinterpret_borrow<sequence>(src);
        if (seq.size() != 3) return false;
        for (size_t i = 0; i < 3; ++i) {
            object item = seq[i];
            PyObject* f = PyNumber_Float(item.ptr());
            if (!f) {
                PyErr_Clear();
                return false;
            }
            value[int(i)] = float(PyFloat_AsDouble(f));
            Py_DECREF(f);
        }
        return true;
    }

    static handle cast(const glm::vec3& v, return_value_policy, handle) {
        return make_tuple(double(v.x), double(v.y), double(v.z)).release();
    }
};

template <>
struct type_caster<glm::dmat4> {
    PYBIND11_TYPE_CASTER(glm::dmat4, const_name("numpy.ndarray[float64, (4, 4)]"));

    bool load(handle src, bool convert) {
        if (!src || src.is_none()) return false;
        array_t<double, array::c_style | array::forcecast> a;
        try {
            a = array_t<double, array::c_style | array::forcecast>::ensure(src);
        } catch (...) {
            return false;
        }
        if (!a || a.ndim() != 2 || a.shape(0) != 4 || a.shape(1) != 4) return false;
        auto r = a.unchecked<2>();
        for (int row = 0; row < 4; ++row)
            for (int col = 0; col < 4; ++col) value[col][row] = r(row, col);
        return true;
    }

    static handle cast(const glm::dmat4& m, return_value_policy, handle) {
        array_t<double> a({4, 4});
        auto w = a.mutable_unchecked<2>();
        for (int row = 0; row < 4; ++row)
            for (int col = 0; col < 4; ++col) w(row, col) = m[col][row];
        return a.release();
    }
};

// A rotation ("rotate" of the environment light): the dict {"axis": (x, y, z), "angle": deg},
// as in the JSON scene format.
template <>
struct type_caster<facet::render::AxisAngle> {
    PYBIND11_TYPE_CASTER(facet::render::AxisAngle,
                         const_name("dict[str, tuple[float, float, float] | float]"));

    bool load(handle src, bool convert) {
        if (!src || !PyDict_Check(src.ptr())) return false;
        dict d = reinterpret_borrow<dict>(src);
        if (d.size() != 2 || !d.contains("axis") || !d.contains("angle")) return false;
        make_caster<glm::vec3> axis;
        make_caster<double> angle;
        if (!axis.load(d["axis"], convert) || !angle.load(d["angle"], convert)) return false;
        value = {cast_op<glm::vec3>(axis), cast_op<double>(angle)};
        return true;
    }

    static handle cast(const facet::render::AxisAngle& r, return_value_policy, handle) {
        dict d;
        d["axis"] = make_tuple(double(r.axis.x), double(r.axis.y), double(r.axis.z));
        d["angle"] = r.angle;
        return d.release();
    }
};

}  // namespace pybind11::detail

namespace facet::python {

namespace py = pybind11;

// Raised as ValueError("<what>: <message>").
[[noreturn]] inline void bad_argument(const std::string& what, const std::string& message) {
    throw py::value_error(what + ": " + message);
}

// A (n, 3) float32 C-contiguous view of `obj` (converted or copied when needed), for direction
// arrays: any real dtype; shape (n, 3) or (3,) (then `single` is set). NaN/Inf raise ValueError
// naming `what` and the row.
py::array_t<float, py::array::c_style> directions(py::handle obj, const char* what, bool& single);

// A (n, 2) / (n,) float32 array of random numbers in [0, 1) (uc: (n,), u: (n, 2)), n given.
py::array_t<float, py::array::c_style> unit_samples(py::handle obj, const char* what, py::ssize_t n,
                                                    int columns);

// ParamSet <-> dict {name: float | bool | str | (r, g, b)}. `what` names the argument.
ParamSet params_from_dict(py::handle params, const std::string& what);
py::dict params_to_dict(const ParamSet& params);

void bind_brdf(py::module_& m);
// facet.Scene: a built scene, shared by the sessions rendering it (they keep it alive).
struct SceneHandle {
    std::shared_ptr<const render::Scene> scene;
    // From build_scene's BuildReport (zero for load_scene).
    std::uint64_t degenerate_triangles = 0;
    double seconds_before_bvh = 0.0, seconds_bvh = 0.0;
};

void bind_scene(py::module_& m);
void bind_render(py::module_& m);

}  // namespace facet::python
