// The reflection-model part of the module: the model table, make_material, and a Material whose
// eval / pdf / sample / reflectances are vectorised over numpy arrays of directions.
//
// Conventions are the core's (facet/bxdf.h): local shading frame (z = normal), `wo` toward the
// viewer, `wi` toward the light, both unit and pointing away from the surface; eval = f without
// the cosine; pdf per unit solid angle; delta lobes give f = pdf = 0 and appear only in samples.
#include <optional>
#include <sstream>

#include "bindings.h"
#include "facet/material.h"
#include "facet/reflectance.h"
#include "facet/registry.h"

namespace facet::python {

ParamSet params_from_dict(py::handle params, const std::string& what) {
    ParamSet set;
    if (params.is_none()) return set;
    if (!py::isinstance<py::dict>(params)) bad_argument(what, "expected a dict of parameters");
    for (auto [key, value] : py::reinterpret_borrow<py::dict>(params)) {
        if (!py::isinstance<py::str>(key)) bad_argument(what, "parameter names must be strings");
        const std::string name = key.cast<std::string>();
        PyObject* v = value.ptr();
        if (PyBool_Check(v)) {
            set.set(name, bool(v == Py_True));
        } else if (py::isinstance<py::str>(value)) {
            set.set(name, value.cast<std::string>());
        } else if (!PySequence_Check(v) && PyNumber_Check(v)) {
            set.set(name, py::float_(py::reinterpret_borrow<py::object>(value)).cast<double>());
        } else {
            try {
                set.set(name, value.cast<Vec3>());
            } catch (const py::cast_error&) {
                bad_argument(what + "['" + name + "']",
                             "expected a number, a colour (three numbers), a string or a bool, "
                             "got " +
                                 std::string(py::str(py::type::of(value).attr("__name__"))));
            }
        }
    }
    return set;
}

py::dict params_to_dict(const ParamSet& params) {
    py::dict d;
    for (const auto& [name, value] : params.values())
        std::visit([&](const auto& v) { d[py::str(name)] = py::cast(v); }, value);
    return d;
}

namespace {

// A material together with the model name and parameters it was built from.
struct PyMaterial {
    std::string model;
    ParamSet params;
    Material material;
};

// Results of sample(): one row per wo; rows without a sample have valid = False and zeros.
struct SampleBatch {
    py::object wi, f, pdf, flags, valid;
};

struct ReflectanceResult {
    py::object value, error;
};

std::string param_type_name(ParamType t) {
    switch (t) {
        case ParamType::Number:
            return "number";
        case ParamType::Color:
            return "colour";
        case ParamType::String:
            return "string";
        case ParamType::Bool:
            return "bool";
        case ParamType::Materials:
            return "materials";
    }
    return "?";
}

// (n, 3) float32 output array, or (3,) when `single`.
py::array_t<float> rgb_array(py::ssize_t n, bool single) {
    if (single) return py::array_t<float>(std::vector<py::ssize_t>{3});
    return py::array_t<float>(std::vector<py::ssize_t>{n, 3});
}

py::object scalar_or_array(py::array a, bool single) {
    if (single) return a[py::int_(0)];
    return a;
}

// Two direction arguments of equal row count.
struct DirectionPair {
    py::array_t<float, py::array::c_style> a, b;
    bool single = false;
    py::ssize_t n = 0;
};

DirectionPair direction_pair(py::handle wo, py::handle wi) {
    DirectionPair p;
    bool s0 = false, s1 = false;
    p.a = directions(wo, "wo", s0);
    p.b = directions(wi, "wi", s1);
    const py::ssize_t n0 = p.a.size() / 3, n1 = p.b.size() / 3;
    if (n0 != n1 && n0 != 1 && n1 != 1)
        bad_argument("wi", std::to_string(n1) + " rows, but wo has " + std::to_string(n0) +
                               " (give equal counts, or one direction for either)");
    p.n = std::max(n0, n1);
    p.single = s0 && s1;
    return p;
}

Vec3 row(const float* p, py::ssize_t i, py::ssize_t n) {
    const float* q = p + 3 * (n == 1 ? 0 : i);
    return {q[0], q[1], q[2]};
}

py::array_t<double> rgb_array_d(py::ssize_t n, bool single) {
    if (single) return py::array_t<double>(std::vector<py::ssize_t>{3});
    return py::array_t<double>(std::vector<py::ssize_t>{n, 3});
}

// order: a fixed Gauss-Legendre order, or none for the adaptive quadrature to tolerance.
QuadratureSettings quadrature_settings(std::optional<int> order, double tolerance) {
    if (order && *order < 1) bad_argument("order", "must be >= 1");
    if (!(tolerance >= 1e-9 && tolerance <= 0.1))
        bad_argument("tolerance", "must be in [1e-9, 0.1]");
    QuadratureSettings s;
    s.tolerance = tolerance;
    return s;
}

ReflectanceResult reflectance_over(const Material& m, py::handle dirs, const char* what,
                                   std::optional<int> order, double tolerance,
                                   Reflectance (*fixed)(const Material&, const Vec3&, int),
                                   Reflectance (*adaptive)(const Material&, const Vec3&,
                                                           const QuadratureSettings&)) {
    const QuadratureSettings settings = quadrature_settings(order, tolerance);
    bool single = false;
    auto d = directions(dirs, what, single);
    const py::ssize_t n = d.size() / 3;
    auto value = rgb_array_d(n, single), error = rgb_array_d(n, single);
    double* pv = value.mutable_data();
    double* pe = error.mutable_data();
    const float* pd = d.data();
    {
        py::gil_scoped_release release;
        for (py::ssize_t i = 0; i < n; ++i) {
            Reflectance r =
                order ? fixed(m, row(pd, i, n), *order) : adaptive(m, row(pd, i, n), settings);
            for (int c = 0; c < 3; ++c) pv[3 * i + c] = r.value[c], pe[3 * i + c] = r.error[c];
        }
    }
    return {value, error};
}

ReflectanceResult reflectance_one(const Reflectance& r) {
    auto value = rgb_array_d(1, true), error = rgb_array_d(1, true);
    for (int c = 0; c < 3; ++c)
        value.mutable_data()[c] = r.value[c], error.mutable_data()[c] = r.error[c];
    return {value, error};
}

Reflectance bihemispherical_either(const Material& m, std::optional<int> order, double tolerance) {
    const QuadratureSettings settings = quadrature_settings(order, tolerance);
    py::gil_scoped_release release;
    return order ? bihemispherical(m, *order) : bihemispherical(m, settings);
}

Cone make_cone(const Vec3& axis, float half_angle, const char* what) {
    if (!(glm::length(axis) > 0.f)) bad_argument(what, "axis must be a non-zero vector");
    if (!(half_angle > 0.f && half_angle <= kPiOver2))
        bad_argument(what, "half-angle must be in (0, pi/2] radians");
    return {glm::normalize(axis), half_angle};
}

std::string repr(const PyMaterial& m) {
    std::ostringstream s;
    s << "facet.Material('" << m.model << "'";
    for (const auto& [name, value] : m.params.values()) {
        s << ", " << name << "=";
        std::visit(
            [&](const auto& v) {
                using T = std::decay_t<decltype(v)>;
                if constexpr (std::is_same_v<T, double>)
                    s << v;
                else if constexpr (std::is_same_v<T, bool>)
                    s << (v ? "True" : "False");
                else if constexpr (std::is_same_v<T, std::string>)
                    s << "'" << v << "'";
                else
                    s << "(" << v.x << ", " << v.y << ", " << v.z << ")";
            },
            value);
    }
    s << ")";
    return s.str();
}

}  // namespace

void bind_brdf(py::module_& m) {
    py::enum_<BxDFFlags>(m, "BxDFFlags", py::arithmetic(), "Lobe flags (facet/bxdf.h)")
        .value("none", BxDFFlags::None)
        .value("diffuse", BxDFFlags::Diffuse)
        .value("glossy", BxDFFlags::Glossy)
        .value("specular", BxDFFlags::Specular)
        .value("transmission", BxDFFlags::Transmission);

    py::class_<ParamInfo>(m, "ParamInfo", "A model parameter of the model table (registry.h)")
        .def_readonly("name", &ParamInfo::name)
        .def_property_readonly("type", [](const ParamInfo& p) { return param_type_name(p.type); })
        .def_readonly("default", &ParamInfo::default_value)
        .def_readonly("doc", &ParamInfo::doc)
        .def_readonly("choices", &ParamInfo::choices)
        .def("__repr__", [](const ParamInfo& p) {
            return "facet.ParamInfo('" + p.name + "', " + param_type_name(p.type) + ", default " +
                   p.default_value + ")";
        });
    py::class_<ModelInfo>(m, "ModelInfo", "A reflection model of the model table (registry.h)")
        .def_readonly("name", &ModelInfo::name)
        .def_readonly("summary", &ModelInfo::summary)
        .def_readonly("params", &ModelInfo::params)
        .def_readonly("children", &ModelInfo::children)
        .def_readonly("diffuse_param", &ModelInfo::diffuse_param)
        .def_readonly("pov_finish", &ModelInfo::pov_finish)
        .def("__repr__", [](const ModelInfo& i) { return "facet.ModelInfo('" + i.name + "')"; });

    m.def(
        "models", [] { return model_table(); },
        "Every model the core knows, in documentation order (facet::model_table()).");
    m.def(
        "find_model",
        [](const std::string& name) -> std::optional<ModelInfo> {
            const ModelInfo* i = find_model(name);
            if (!i) return std::nullopt;
            return *i;
        },
        py::arg("name"), "The model called `name`, or None.");

    py::class_<SampleBatch>(m, "BSDFSamples",
                            "Results of Material.sample: wi (n, 3), f (n, 3) without cosine, pdf "
                            "(n,), flags (n,) uint8 (BxDFFlags of the sampled lobe), valid (n,) "
                            "bool (False where no sample could be made; the row is then zero)")
        .def_readonly("wi", &SampleBatch::wi)
        .def_readonly("f", &SampleBatch::f)
        .def_readonly("pdf", &SampleBatch::pdf)
        .def_readonly("flags", &SampleBatch::flags)
        .def_readonly("valid", &SampleBatch::valid)
        .def("__repr__", [](const SampleBatch& s) {
            return "facet.BSDFSamples(wi=" + std::string(py::repr(s.wi)) +
                   ", f=" + std::string(py::repr(s.f)) + ", pdf=" + std::string(py::repr(s.pdf)) +
                   ")";
        });
    py::class_<ReflectanceResult>(m, "Reflectance",
                                  "A reflectance (per RGB channel) and its estimated quadrature "
                                  "error (reflectance.h); arrays of shape (3,) or (n, 3)")
        .def_readonly("value", &ReflectanceResult::value)
        .def_readonly("error", &ReflectanceResult::error)
        .def("__iter__",
             [](const ReflectanceResult& r) { return py::iter(py::make_tuple(r.value, r.error)); })
        .def("__repr__", [](const ReflectanceResult& r) {
            return "facet.Reflectance(value=" + std::string(py::repr(r.value)) +
                   ", error=" + std::string(py::repr(r.error)) + ")";
        });

    py::class_<PyMaterial>(m, "Material",
                           "A Facet material (diffuse + glossy + mirror, material.h) built by "
                           "make_material. Directions are in the local shading frame (z = normal), "
                           "wo toward the viewer, wi toward the light; arrays of shape (n, 3) or "
                           "(3,), any real dtype.")
        .def_readonly("model", &PyMaterial::model)
        .def_property_readonly("params",
                               [](const PyMaterial& p) { return params_to_dict(p.params); })
        .def_property_readonly("flags", [](const PyMaterial& p) { return p.material.flags(); })
        .def(
            "eval",
            [](const PyMaterial& p, py::handle wo, py::handle wi) {
                DirectionPair d = direction_pair(wo, wi);
                auto f = rgb_array(d.n, d.single);
                float* out = f.mutable_data();
                const float *a = d.a.data(), *b = d.b.data();
                const py::ssize_t na = d.a.size() / 3, nb = d.b.size() / 3;
                {
                    py::gil_scoped_release release;
                    for (py::ssize_t i = 0; i < d.n; ++i) {
                        const Rgb v = p.material.f(row(a, i, na), row(b, i, nb));
                        out[3 * i] = v.x, out[3 * i + 1] = v.y, out[3 * i + 2] = v.z;
                    }
                }
                return f;
            },
            py::arg("wo"), py::arg("wi"),
            "f(wo, wi) per row, without the cosine (Material::f), float32 (n, 3)")
        .def(
            "pdf",
            [](const PyMaterial& p, py::handle wo, py::handle wi) -> py::object {
                DirectionPair d = direction_pair(wo, wi);
                py::array_t<float> pdf(std::vector<py::ssize_t>{d.n});
                float* out = pdf.mutable_data();
                const float *a = d.a.data(), *b = d.b.data();
                const py::ssize_t na = d.a.size() / 3, nb = d.b.size() / 3;
                {
                    py::gil_scoped_release release;
                    for (py::ssize_t i = 0; i < d.n; ++i)
                        out[i] = p.material.pdf(row(a, i, na), row(b, i, nb));
                }
                return scalar_or_array(pdf, d.single);
            },
            py::arg("wo"), py::arg("wi"),
            "pdf of sample() per unit solid angle of wi (Material::pdf), float32 (n,)")
        .def(
            "eval_pdf",
            [](const PyMaterial& p, py::handle wo, py::handle wi) {
                DirectionPair d = direction_pair(wo, wi);
                auto f = rgb_array(d.n, d.single);
                py::array_t<float> pdf(std::vector<py::ssize_t>{d.n});
                float* out = f.mutable_data();
                float* outp = pdf.mutable_data();
                const float *a = d.a.data(), *b = d.b.data();
                const py::ssize_t na = d.a.size() / 3, nb = d.b.size() / 3;
                {
                    py::gil_scoped_release release;
                    for (py::ssize_t i = 0; i < d.n; ++i) {
                        const BSDFEval e = p.material.eval(row(a, i, na), row(b, i, nb));
                        out[3 * i] = e.f.x, out[3 * i + 1] = e.f.y, out[3 * i + 2] = e.f.z;
                        outp[i] = e.pdf;
                    }
                }
                return py::make_tuple(f, scalar_or_array(pdf, d.single));
            },
            py::arg("wo"), py::arg("wi"), "(f, pdf) together (Material::eval)")
        .def(
            "sample",
            [](const PyMaterial& p, py::handle wo, py::handle uc, py::handle u) {
                bool single = false;
                auto w = directions(wo, "wo", single);
                const py::ssize_t n = w.size() / 3;
                auto ucs = unit_samples(uc, "uc", n, 1);
                auto us = unit_samples(u, "u", n, 2);
                auto wi = rgb_array(n, single), f = rgb_array(n, single);
                py::array_t<float> pdf(std::vector<py::ssize_t>{n});
                py::array_t<std::uint8_t> flags(std::vector<py::ssize_t>{n});
                py::array_t<bool> valid(std::vector<py::ssize_t>{n});
                float *pwi = wi.mutable_data(), *pf = f.mutable_data(), *pp = pdf.mutable_data();
                std::uint8_t* pfl = flags.mutable_data();
                bool* pv = valid.mutable_data();
                const float *pw = w.data(), *puc = ucs.data(), *pu = us.data();
                {
                    py::gil_scoped_release release;
                    for (py::ssize_t i = 0; i < n; ++i) {
                        const std::optional<BSDFSample> s = p.material.sample_f(
                            row(pw, i, n), puc[i], Vec2(pu[2 * i], pu[2 * i + 1]));
                        const BSDFSample z = s.value_or(BSDFSample{});
                        for (int c = 0; c < 3; ++c)
                            pwi[3 * i + c] = z.wi[c], pf[3 * i + c] = z.f[c];
                        pp[i] = z.pdf;
                        pfl[i] = std::uint8_t(z.flags);
                        pv[i] = s.has_value();
                    }
                }
                return SampleBatch{wi, f, scalar_or_array(pdf, single),
                                   scalar_or_array(flags, single), scalar_or_array(valid, single)};
            },
            py::arg("wo"), py::arg("uc"), py::arg("u"),
            "Draws wi per row (Material::sample_f): uc (n,) selects the lobe, u (n, 2) drives "
            "its warp, both in [0, 1). Returns BSDFSamples.")
        .def(
            "hemispherical_directional",
            [](const PyMaterial& p, py::handle wo, std::optional<int> order, double tolerance) {
                return reflectance_over(p.material, wo, "wo", order, tolerance,
                                        &hemispherical_directional, &hemispherical_directional);
            },
            py::arg("wo"), py::arg("order") = py::none(), py::arg("tolerance") = 1e-6,
            "rho(2pi -> wo) = int f(wo, wi) cos(theta_i) dwi per row (reflectance.h): adaptive "
            "to tolerance, or a fixed Gauss-Legendre order")
        .def(
            "directional_hemispherical",
            [](const PyMaterial& p, py::handle wi, std::optional<int> order, double tolerance) {
                return reflectance_over(p.material, wi, "wi", order, tolerance,
                                        &directional_hemispherical, &directional_hemispherical);
            },
            py::arg("wi"), py::arg("order") = py::none(), py::arg("tolerance") = 1e-6,
            "rho(wi -> 2pi) = int f(wo, wi) cos(theta_o) dwo per row (reflectance.h): adaptive "
            "to tolerance, or a fixed Gauss-Legendre order")
        .def(
            "bihemispherical",
            [](const PyMaterial& p, std::optional<int> order, double tolerance) {
                return reflectance_one(bihemispherical_either(p.material, order, tolerance));
            },
            py::arg("order") = py::none(), py::arg("tolerance") = 1e-6,
            "rho(2pi -> 2pi) (reflectance.h)")
        .def(
            "biconical",
            [](const PyMaterial& p, const Vec3& in_axis, float in_half_angle, const Vec3& out_axis,
               float out_half_angle, int order) {
                if (order < 1) bad_argument("order", "must be >= 1");
                const Cone in = make_cone(in_axis, in_half_angle, "in cone");
                const Cone out = make_cone(out_axis, out_half_angle, "out cone");
                Reflectance r;
                {
                    py::gil_scoped_release release;
                    r = biconical(p.material, in, out, order);
                }
                return reflectance_one(r);
            },
            py::arg("in_axis"), py::arg("in_half_angle"), py::arg("out_axis"),
            py::arg("out_half_angle"), py::arg("order") = 32,
            "Biconical reflectance between two cones (axes in the local frame, half-angles in "
            "radians, reflectance.h)")
        .def(
            "reflectance",
            [](const PyMaterial& p, py::object wo, std::optional<int> order,
               double tolerance) -> ReflectanceResult {
                if (wo.is_none())
                    return reflectance_one(bihemispherical_either(p.material, order, tolerance));
                return reflectance_over(p.material, wo, "wo", order, tolerance,
                                        &hemispherical_directional, &hemispherical_directional);
            },
            py::arg("wo") = py::none(), py::arg("order") = py::none(), py::arg("tolerance") = 1e-6,
            "The albedo rho(2pi -> wo) per row of wo, or with no wo the bihemispherical "
            "reflectance (Cohen & Wallace table 2.2); adaptive to tolerance unless order is given")
        .def("__repr__", &repr);

    m.def(
        "make_material",
        [](const std::string& model, py::kwargs params) {
            ParamSet set = params_from_dict(params, "make_material");
            Material mat = make_material(model, set);
            return PyMaterial{model, std::move(set), std::move(mat)};
        },
        py::arg("model"),
        "Builds a material from a model name and its parameters, e.g. make_material('ggx', "
        "alpha=0.3, fresnel='conductor'). Colours are (r, g, b) or one number (grey). Bad names "
        "or values raise ValueError naming the parameter (facet::make_material).");
}

}  // namespace facet::python
