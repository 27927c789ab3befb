// facet._facet: the native part of the `facet` Python package (facet/__init__.py re-exports it).
#include <exception>

#include "bindings.h"
#include "facet/registry.h"
#include "facet/render/scene.h"

namespace facet::python {

py::array_t<float, py::array::c_style> directions(py::handle obj, const char* what, bool& single) {
    py::array arr = py::array::ensure(obj);
    if (!arr) bad_argument(what, "expected an array of directions, shape (n, 3) or (3,)");
    const char kind = arr.dtype().kind();
    if (kind != 'f' && kind != 'i' && kind != 'u')
        bad_argument(what, "dtype " + std::string(py::str(arr.dtype())) +
                               ", expected a real dtype (float32 or float64)");
    single = arr.ndim() == 1;
    if (!((arr.ndim() == 2 && arr.shape(1) == 3) || (arr.ndim() == 1 && arr.shape(0) == 3)))
        bad_argument(what, "shape " + std::string(py::str(py::tuple(arr.attr("shape")))) +
                               ", expected (n, 3) or (3,)");
    auto a = py::array_t<float, py::array::c_style | py::array::forcecast>::ensure(arr);
    if (!a) throw py::error_already_set();
    const float* p = a.data();
    const py::ssize_t n = a.size() / 3;
    for (py::ssize_t i = 0; i < n; ++i)
        for (int c = 0; c < 3; ++c)
            if (!std::isfinite(p[3 * i + c]))
                bad_argument(what, "row " + std::to_string(i) + " is not finite");
    return a;
}

py::array_t<float, py::array::c_style> unit_samples(py::handle obj, const char* what, py::ssize_t n,
                                                    int columns) {
    py::array arr = py::array::ensure(obj);
    if (!arr) bad_argument(what, "expected an array of numbers in [0, 1)");
    const char kind = arr.dtype().kind();
    if (kind != 'f')
        bad_argument(
            what, "dtype " + std::string(py::str(arr.dtype())) + ", expected float32 or float64");
    auto a = py::array_t<float, py::array::c_style | py::array::forcecast>::ensure(arr);
    const bool ok = columns == 1 ? (a.ndim() == 1 && a.shape(0) == n) || (n == 1 && a.ndim() == 0)
                                 : (a.ndim() == 2 && a.shape(0) == n && a.shape(1) == columns) ||
                                       (n == 1 && a.ndim() == 1 && a.shape(0) == columns);
    if (!ok) {
        std::string expected = columns == 1
                                   ? "(" + std::to_string(n) + ",)"
                                   : "(" + std::to_string(n) + ", " + std::to_string(columns) + ")";
        bad_argument(what, "shape " + std::string(py::str(py::tuple(arr.attr("shape")))) +
                               ", expected " + expected + " (one per direction)");
    }
    const float* p = a.data();
    for (py::ssize_t i = 0; i < a.size(); ++i)
        if (!(p[i] >= 0.f && p[i] < 1.f))
            bad_argument(what, "element " + std::to_string(i) + " is not in [0, 1)");
    return a;
}

}  // namespace facet::python

PYBIND11_MODULE(_facet, m) {
    namespace py = pybind11;
    m.doc() =
        "Facet: physically based reflection models (Cohen & Wallace ch. 2) and the Facet "
        "renderer. See docs/python.md.";
    m.attr("__version__") = FACET_VERSION;

    // C++ errors -> Python exceptions with the C++ message. ParamError and SceneError (bad
    // values, with their parameter name or JSON pointer) are ValueErrors, as std::invalid_argument
    // (bad render options) already is by pybind11's defaults; other std::runtime_errors (file
    // I/O, merging) are RuntimeErrors, std::logic_error too.
    py::register_exception_translator([](std::exception_ptr p) {
        try {
            if (p) std::rethrow_exception(p);
        } catch (const facet::ParamError& e) {
            PyErr_SetString(PyExc_ValueError, e.what());
        } catch (const facet::render::SceneError& e) {
            PyErr_SetString(PyExc_ValueError, e.what());
        }
    });

    facet::python::bind_brdf(m);
    facet::python::bind_scene(m);
    facet::python::bind_render(m);
}
