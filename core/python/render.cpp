// The rendering part of the module: render(), RenderSession, render parts and merging, images.
//
// Conventions:
//  - Render options are keyword arguments named as RenderOptions' fields (render.h), with None
//    meaning "the scene's setting": spp, threads (0 = every hardware thread), seed, integrator
//    ('path' | 'direct'), max_depth, region=(x0, y0, x1, y1), samples=(s0, s1), time_budget (s),
//    tile_size, pass_seconds, force_general_kernel, uniform_light_selection,
//    independent_samples, adaptive_threshold, adaptive_min_samples, shadow_catcher_pass,
//    depth_pass (RenderSession only: its depth()). Bad values raise ValueError naming the
//    option.
//  - The GIL is released while a pass renders. Between passes the session calls back into
//    Python with the GIL held: it checks for signals (Ctrl-C), then calls the progress callable
//    (if any) with a PassInfo; a False return cancels. A KeyboardInterrupt (or any exception of
//    the callback) cancels the render, which stops within one pass with a valid partial image,
//    and is raised after it stopped. So every render has a callback, and its passes are sized to
//    take about pass_seconds (render.h); the image does not depend on pass sizes.
//  - A session renders on one thread at a time. cancel() may be called from any thread; image(),
//    part(), stats and samples_done between passes (from the callback, or from another thread
//    while the callback runs) or after render() returned; continue_to() only when no render runs.
//  - Images are float32 numpy arrays (h, w, 3), linear RGB, row 0 at the top (image.h).
#include <algorithm>
#include <cstring>
#include <exception>
#include <optional>

#include "bindings.h"
#include "facet/registry.h"
#include "facet/render/aov.h"
#include "facet/render/denoise.h"
#include "facet/render/film.h"
#include "facet/render/image.h"
#include "facet/render/render.h"

namespace facet::python {

using namespace facet::render;

namespace {

static_assert(sizeof(Rgb) == 3 * sizeof(float), "Image pixels must be packed float RGB");

// The image as a (h, w, 3) float32 array owning it (no copy); an image with alpha (film
// transparency, holdouts) as an (h, w, 4) RGBA array, colour premultiplied (a copy).
py::array_t<float> image_array(Image&& image) {
    if (image.has_alpha()) {
        const py::ssize_t h = image.height(), w = image.width();
        py::array_t<float> out({h, w, py::ssize_t(4)});
        float* d = out.mutable_data();
        for (std::size_t i = 0; i < image.pixels().size(); ++i) {
            const Rgb& c = image.pixels()[i];
            d[4 * i + 0] = c.r;
            d[4 * i + 1] = c.g;
            d[4 * i + 2] = c.b;
            d[4 * i + 3] = image.alpha()[i];
        }
        return out;
    }
    auto* owned = new Image(std::move(image));
    py::capsule base(owned, [](void* p) { delete static_cast<Image*>(p); });
    const py::ssize_t h = owned->height(), w = owned->width();
    return py::array_t<float>(
        {h, w, py::ssize_t(3)},
        {py::ssize_t(w * sizeof(Rgb)), py::ssize_t(sizeof(Rgb)), py::ssize_t(sizeof(float))},
        reinterpret_cast<const float*>(owned->pixels().data()), base);
}

// The image `run(options)` returns (a denoiser call) with the GIL released, as an array.
template <class Run>
py::array_t<float> denoised_array(int radius, int threads, const Run& run) {
    DenoiseOptions o;
    o.radius = radius;
    o.threads = threads;
    Image out;
    {
        py::gil_scoped_release release;
        out = run(o);
    }
    return image_array(std::move(out));
}

Image image_from_array(py::handle obj, const char* what) {
    py::array a = py::array::ensure(obj);
    if (!a) bad_argument(what, "expected a numpy array of shape (h, w, 3)");
    const char kind = a.dtype().kind();
    if (kind != 'f' && kind != 'i' && kind != 'u')
        bad_argument(what, "dtype " + std::string(py::str(a.dtype())) + ", expected float32");
    if (a.ndim() != 3 || (a.shape(2) != 3 && a.shape(2) != 4))
        bad_argument(what, "shape " + std::string(py::str(py::tuple(a.attr("shape")))) +
                               ", expected (h, w, 3) or (h, w, 4)");
    auto f = py::array_t<float, py::array::c_style | py::array::forcecast>::ensure(a);
    Image image(int(f.shape(1)), int(f.shape(0)));
    if (a.shape(2) == 4) {
        // RGBA (premultiplied colour and alpha, image.h).
        image.add_alpha();
        const float* d = f.data();
        for (std::size_t i = 0; i < image.pixels().size(); ++i) {
            image.pixels()[i] = Rgb(d[4 * i], d[4 * i + 1], d[4 * i + 2]);
            image.alpha()[i] = d[4 * i + 3];
        }
        return image;
    }
    if (f.size() > 0)
        std::memcpy(image.pixels().data(), f.data(), std::size_t(f.size()) * sizeof(float));
    return image;
}

py::tuple region_tuple(const Region& r) {
    return py::make_tuple(r.x0, r.y0, r.x1, r.y1);
}

// std::invalid_argument("--max-depth: must be >= 0") -> ValueError("max_depth: must be >= 0"):
// the option named as the keyword argument.
[[noreturn]] void rethrow_option_error(const std::invalid_argument& e) {
    std::string msg = e.what();
    if (msg.rfind("--", 0) == 0) {
        const std::size_t colon = msg.find(':');
        std::string flag =
            msg.substr(2, colon == std::string::npos ? std::string::npos : colon - 2);
        for (char& c : flag)
            if (c == '-') c = '_';
        if (flag == "time") flag = "time_budget";  // the CLI's --time
        msg = flag + (colon == std::string::npos ? "" : msg.substr(colon));
    }
    throw py::value_error(msg);
}

const char* const kOptionNames[] = {"spp",
                                    "threads",
                                    "seed",
                                    "integrator",
                                    "max_depth",
                                    "region",
                                    "samples",
                                    "time_budget",
                                    "tile_size",
                                    "pass_seconds",
                                    "force_general_kernel",
                                    "uniform_light_selection",
                                    "light_selection",
                                    "independent_samples",
                                    "adaptive_threshold",
                                    "adaptive_min_samples",
                                    "shadow_catcher_pass",
                                    "depth_pass"};

template <class T>
T option_value(py::handle v, const char* name, const char* expected) {
    if (PyBool_Check(v.ptr()) && !std::is_same_v<T, bool>)
        bad_argument(name, std::string("expected ") + expected + ", got a bool");
    try {
        return v.cast<T>();
    } catch (const py::cast_error&) {
        bad_argument(name,
                     std::string("expected ") + expected + ", got " + std::string(py::repr(v)));
    }
}

// Keyword arguments -> RenderOptions (see conventions). `progress` receives the "progress"
// argument when non-null; otherwise it is an unknown option.
RenderOptions options_from(const py::kwargs& kw, const char* function, py::object* progress) {
    RenderOptions o;
    o.progress = Progress::Mode::Silent;
    for (auto [key, value] : kw) {
        const std::string k = key.cast<std::string>();
        if (k == "progress" && progress) {
            if (!value.is_none() && !PyCallable_Check(value.ptr()))
                throw py::type_error("progress: expected a callable (PassInfo) -> bool or None");
            *progress = py::reinterpret_borrow<py::object>(value);
            continue;
        }
        if (value.is_none()) {
            bool known = false;
            for (const char* n : kOptionNames) known = known || k == n;
            if (known) continue;  // None: the scene's setting / the default
        }
        if (k == "spp")
            o.spp = option_value<int>(value, "spp", "an int");
        else if (k == "threads")
            o.threads = option_value<int>(value, "threads", "an int");
        else if (k == "seed")
            o.seed = option_value<std::uint64_t>(value, "seed", "an int >= 0");
        else if (k == "integrator")
            o.integrator = option_value<std::string>(value, "integrator", "'path' or 'direct'");
        else if (k == "max_depth")
            o.max_depth = option_value<int>(value, "max_depth", "an int");
        else if (k == "region") {
            auto r = option_value<std::vector<int>>(value, "region", "(x0, y0, x1, y1)");
            if (r.size() != 4) bad_argument("region", "expected (x0, y0, x1, y1)");
            o.region = Region{r[0], r[1], r[2], r[3]};
        } else if (k == "samples") {
            auto s = option_value<std::vector<int>>(value, "samples", "(s0, s1)");
            if (s.size() != 2) bad_argument("samples", "expected (s0, s1)");
            o.sample_begin = s[0];
            o.sample_end = s[1];
        } else if (k == "time_budget")
            o.time_budget_s = option_value<double>(value, "time_budget", "seconds");
        else if (k == "tile_size")
            o.tile_size = option_value<int>(value, "tile_size", "an int");
        else if (k == "pass_seconds") {
            o.pass_seconds = option_value<double>(value, "pass_seconds", "seconds");
        } else if (k == "force_general_kernel")
            o.force_general_kernel = option_value<bool>(value, k.c_str(), "a bool");
        else if (k == "uniform_light_selection") {
            // Kept from before light_selection: True is "uniform", False the default.
            if (option_value<bool>(value, k.c_str(), "a bool"))
                o.light_selection = LightSelection::Uniform;
        } else if (k == "light_selection") {
            const auto s = option_value<std::string>(value, k.c_str(), "a str");
            if (s == "view")
                o.light_selection = LightSelection::View;
            else if (s == "power")
                o.light_selection = LightSelection::Power;
            else if (s == "uniform")
                o.light_selection = LightSelection::Uniform;
            else if (s == "tree")
                o.light_selection = LightSelection::Tree;
            else if (s == "auto")
                o.light_selection = LightSelection::Auto;
            else
                bad_argument("light_selection",
                             "expected 'auto', 'view', 'power', 'uniform' or "
                             "'tree', got '" +
                                 s + "'");
        } else if (k == "independent_samples")
            o.independent_samples = option_value<bool>(value, k.c_str(), "a bool");
        else if (k == "adaptive_threshold")
            o.adaptive_threshold = option_value<double>(value, k.c_str(), "a number >= 0");
        else if (k == "adaptive_min_samples")
            o.adaptive_min_samples = option_value<int>(value, k.c_str(), "an int >= 0");
        else if (k == "shadow_catcher_pass")
            o.shadow_catcher_pass = option_value<bool>(value, k.c_str(), "a bool");
        else if (k == "depth_pass")
            o.depth_pass = option_value<bool>(value, k.c_str(), "a bool");
        else {
            std::vector<std::string> names(std::begin(kOptionNames), std::end(kOptionNames));
            if (progress) names.push_back("progress");
            std::string msg =
                std::string(function) + "() got an unexpected keyword argument '" + k + "'";
            const std::string guess = closest_name(k, names);
            if (!guess.empty()) msg += " (did you mean '" + guess + "'?)";
            throw py::type_error(msg);
        }
    }
    return o;
}

const SceneHandle& scene_arg(py::handle scene) {
    if (!py::isinstance<SceneHandle>(scene))
        throw py::type_error(
            "scene: expected a facet.Scene (from build_scene or load_scene), got " +
            std::string(py::str(py::type::of(scene).attr("__name__"))));
    return scene.cast<const SceneHandle&>();
}

// facet.RenderSession: a RenderSession and the scene it keeps alive.
struct PySession {
    enum class State { Idle, Passing, BetweenPasses };  // read and written with the GIL held

    std::shared_ptr<const Scene> scene;
    std::unique_ptr<RenderSession> session;
    State state = State::Idle;

    PySession(const SceneHandle& s, const RenderOptions& options) : scene(s.scene) {
        try {
            session = std::make_unique<RenderSession>(*scene, options);
        } catch (const std::invalid_argument& e) {
            rethrow_option_error(e);
        }
    }

    // For image(), part(), stats: not while a pass renders on another thread.
    void check_between_passes(const char* what) const {
        if (state == State::Passing)
            throw std::runtime_error(std::string("RenderSession.") + what +
                                     ": a render is running on another thread; call this from "
                                     "its progress callback or after render() returned");
    }

    // Renders toward the target with the GIL released (see conventions).
    bool run(const py::object& callback) {
        if (state != State::Idle)
            throw std::runtime_error("RenderSession.render: this session is already rendering");
        std::exception_ptr error;
        const auto on_pass = [&](const PassInfo& info) -> bool {
            py::gil_scoped_acquire gil;
            state = State::BetweenPasses;
            bool go = true;
            try {
                if (PyErr_CheckSignals() != 0) throw py::error_already_set();
                if (!callback.is_none()) {
                    py::object r = callback(info);
                    if (!r.is_none()) {
                        const int truth = PyObject_IsTrue(r.ptr());
                        if (truth < 0) throw py::error_already_set();
                        go = truth != 0;
                    }
                }
            } catch (...) {
                error = std::current_exception();
                go = false;
            }
            state = State::Passing;
            return go;
        };
        bool done = false;
        state = State::Passing;
        try {
            py::gil_scoped_release release;
            done = session->render(on_pass);
        } catch (...) {
            state = State::Idle;
            throw;
        }
        state = State::Idle;
        if (error) std::rethrow_exception(error);
        return done;
    }
};

// facet.RenderPart: a part and the name merge messages use for it.
struct PyPart {
    RenderPart part;
    std::string name;
};

py::bytes raw_bytes(const void* p, std::size_t n) {
    return py::bytes(static_cast<const char*>(p), n);
}

}  // namespace

void bind_render(py::module_& m) {
    py::class_<PassInfo>(m, "PassInfo", "What a progress callback sees after each pass")
        .def_readonly("pass_", &PassInfo::pass, "passes completed (1 after the first)")
        .def_readonly("samples_done", &PassInfo::samples_done)
        .def_readonly("samples_target", &PassInfo::samples_target)
        .def_readonly("elapsed_s", &PassInfo::elapsed_s)
        .def_readonly("eta_s", &PassInfo::eta_s)
        .def("__repr__", [](const PassInfo& p) {
            return "facet.PassInfo(pass_=" + std::to_string(p.pass) +
                   ", samples_done=" + std::to_string(p.samples_done) + "/" +
                   std::to_string(p.samples_target) + ", elapsed_s=" + std::to_string(p.elapsed_s) +
                   ", eta_s=" + std::to_string(p.eta_s) + ")";
        });

    py::class_<RenderStats>(m, "RenderStats", "Counters of a session (render.h)")
        .def_property_readonly("kernel", [](const RenderStats& s) { return s.kernel.name; })
        .def_readonly("seconds", &RenderStats::seconds)
        .def_readonly("spp", &RenderStats::spp)
        .def_readonly("mean_spp", &RenderStats::mean_spp)
        .def_readonly("passes", &RenderStats::passes)
        .def_readonly("threads", &RenderStats::threads)
        .def_readonly("paths", &RenderStats::paths)
        .def_readonly("rays", &RenderStats::rays)
        .def_readonly("shadow_rays", &RenderStats::shadow_rays)
        .def_readonly("nonfinite", &RenderStats::nonfinite)
        .def_readonly("cancelled", &RenderStats::cancelled)
        .def("__repr__", [](const RenderStats& s) {
            return "facet.RenderStats(kernel='" + s.kernel.name +
                   "', seconds=" + std::to_string(s.seconds) + ", spp=" + std::to_string(s.spp) +
                   ", passes=" + std::to_string(s.passes) + ")";
        });

    py::class_<ResolvedSettings>(m, "ResolvedSettings",
                                 "A session's settings: its options merged with the scene's")
        .def_property_readonly(
            "integrator",
            [](const ResolvedSettings& s) { return std::string(integrator_name(s.integrator)); })
        .def_readonly("spp", &ResolvedSettings::spp)
        .def_readonly("max_depth", &ResolvedSettings::max_depth)
        .def_readonly("threads", &ResolvedSettings::threads)
        .def_readonly("tile_size", &ResolvedSettings::tile_size)
        .def_readonly("time_budget_s", &ResolvedSettings::time_budget_s)
        .def_readonly("seed", &ResolvedSettings::seed)
        .def_property_readonly("region",
                               [](const ResolvedSettings& s) { return region_tuple(s.region); })
        .def_property_readonly("samples", [](const ResolvedSettings& s) {
            return py::make_tuple(s.sample_begin, s.sample_end);
        });

    py::class_<PyPart>(m, "RenderPart",
                       "A rendered part: a region and a sample range of one render, as film sums "
                       "(film.h). Merge parts with merge_parts(); picklable.")
        .def_readwrite("name", &PyPart::name, "what merge_parts' messages call it")
        .def_property_readonly("scene", [](const PyPart& p) { return p.part.info.scene; })
        .def_property_readonly("fingerprint",
                               [](const PyPart& p) { return p.part.info.fingerprint; })
        .def_property_readonly("width", [](const PyPart& p) { return p.part.info.width; })
        .def_property_readonly("height", [](const PyPart& p) { return p.part.info.height; })
        .def_property_readonly("region",
                               [](const PyPart& p) { return region_tuple(p.part.info.region); })
        .def_property_readonly("samples",
                               [](const PyPart& p) {
                                   return py::make_tuple(p.part.info.sample_begin,
                                                         p.part.info.sample_end);
                               })
        .def_property_readonly("seed", [](const PyPart& p) { return p.part.info.seed; })
        .def(
            "write", [](const PyPart& p, const std::string& path) { write_part(p.part, path); },
            py::arg("path"), "Writes a part file (facet-part, .fpart)")
        .def(
            "image", [](const PyPart& p) { return image_array(p.part.film.resolve()); },
            "The part's own image over its region (h, w, 3)")
        .def(py::pickle(
            [](const PyPart& p) {
                const PartInfo& i = p.part.info;
                const Film& f = p.part.film;
                return py::make_tuple(
                    i.scene, i.fingerprint, i.width, i.height, region_tuple(i.region),
                    i.sample_begin, i.sample_end, i.seed, p.name,
                    raw_bytes(f.sum_values().data(), f.sum_values().size() * sizeof(FixedRgb)),
                    raw_bytes(f.count_values().data(),
                              f.count_values().size() * sizeof(std::uint32_t)),
                    raw_bytes(f.alpha_values().data(), f.alpha_values().size() * sizeof(FixedSum)),
                    raw_bytes(f.catcher_values().data(),
                              f.catcher_values().size() * sizeof(FixedSum)));
            },
            [](py::tuple t) {
                if (t.size() != 12 && t.size() != 13)
                    throw std::runtime_error("RenderPart: bad pickle state");
                PyPart p;
                PartInfo& i = p.part.info;
                i.scene = t[0].cast<std::string>();
                i.fingerprint = t[1].cast<std::uint64_t>();
                i.width = t[2].cast<int>();
                i.height = t[3].cast<int>();
                auto r = t[4].cast<std::vector<int>>();
                i.region = Region{r.at(0), r.at(1), r.at(2), r.at(3)};
                i.sample_begin = t[5].cast<int>();
                i.sample_end = t[6].cast<int>();
                i.seed = t[7].cast<std::uint64_t>();
                p.name = t[8].cast<std::string>();
                const std::string sums = t[9].cast<std::string>();
                const std::string counts = t[10].cast<std::string>();
                const std::string alpha = t[11].cast<std::string>();
                const std::string catcher = t.size() > 12 ? t[12].cast<std::string>() : "";
                p.part.film = Film(i.region, !alpha.empty(), !catcher.empty());
                Film& f = p.part.film;
                if (sums.size() != f.sum_values().size() * sizeof(FixedRgb) ||
                    counts.size() != f.count_values().size() * sizeof(std::uint32_t) ||
                    alpha.size() != f.alpha_values().size() * sizeof(FixedSum) ||
                    catcher.size() != f.catcher_values().size() * sizeof(FixedSum))
                    throw std::runtime_error("RenderPart: pickle state does not fit its region");
                if (!sums.empty()) std::memcpy(f.sums(), sums.data(), sums.size());
                if (!alpha.empty()) std::memcpy(f.alpha_sums(), alpha.data(), alpha.size());
                if (!catcher.empty()) std::memcpy(f.catcher_sums(), catcher.data(), catcher.size());
                if (!counts.empty()) std::memcpy(f.counts(), counts.data(), counts.size());
                return p;
            }))
        .def("__repr__", [](const PyPart& p) {
            const PartInfo& i = p.part.info;
            return "facet.RenderPart('" + p.name +
                   "', region=" + std::string(py::str(region_tuple(i.region))) + ", samples=(" +
                   std::to_string(i.sample_begin) + ", " + std::to_string(i.sample_end) + "))";
        });

    m.def(
        "read_part",
        [](const std::string& path) {
            PyPart p;
            {
                py::gil_scoped_release release;
                p.part = read_part(path);
            }
            p.name = path;
            return p;
        },
        py::arg("path"),
        "Reads a part file written by RenderPart.write or `facet render -o x.fpart`");
    m.def(
        "merge_parts",
        [](const std::vector<const PyPart*>& parts, std::optional<std::vector<std::string>> names,
           bool shadow_catcher_pass) -> py::object {
            std::vector<RenderPart> ps;
            std::vector<std::string> ns;
            for (std::size_t i = 0; i < parts.size(); ++i) {
                if (!parts[i]) throw py::type_error("parts[" + std::to_string(i) + "] is None");
                ps.push_back(parts[i]->part);
                ns.push_back(parts[i]->name.empty() ? "part " + std::to_string(i) : parts[i]->name);
            }
            if (names) {
                if (names->size() != parts.size())
                    bad_argument("names", "expected one name per part");
                ns = *names;
            }
            Image image, pass;
            {
                py::gil_scoped_release release;
                const Film film = merge_parts(ps, ns);
                image = film.resolve(shadow_catcher_pass);
                if (shadow_catcher_pass) pass = film.resolve_shadow_catcher_pass();
            }
            if (shadow_catcher_pass)
                return py::make_tuple(image_array(std::move(image)), image_array(std::move(pass)));
            return image_array(std::move(image));
        },
        py::arg("parts"), py::arg("names") = py::none(), py::kw_only(),
        py::arg("shadow_catcher_pass") = false,
        "Assembles parts into the full image (h, w, 3), bit for bit the image of one render; "
        "overlapping, missing or mismatched parts raise RuntimeError naming the part. "
        "shadow_catcher_pass=True: (image, Shadow Catcher pass), as render() with that option.");

    py::class_<PySession>(m, "RenderSession",
                          "Progressive rendering of a scene, pass by pass: render(callback), "
                          "cancel() from any thread, continue_to(spp), image(), part(), stats. "
                          "Options as for render().")
        .def(py::init([](py::handle scene, py::kwargs kw) {
                 return std::make_unique<PySession>(scene_arg(scene),
                                                    options_from(kw, "RenderSession", nullptr));
             }),
             py::arg("scene"))
        .def(
            "render",
            [](PySession& s, py::object callback) {
                if (!callback.is_none() && !PyCallable_Check(callback.ptr()))
                    throw py::type_error(
                        "callback: expected a callable (PassInfo) -> bool or None");
                return s.run(callback);
            },
            py::arg("callback") = py::none(),
            "Renders toward the target; callback(PassInfo) after each pass (GIL held), False "
            "cancels. True when the target was reached, False when cancelled. Ctrl-C cancels and "
            "raises KeyboardInterrupt after the render stopped.")
        .def(
            "cancel", [](PySession& s) { s.session->cancel(); },
            "Stops the render within one pass (thread safe)")
        .def(
            "continue_to",
            [](PySession& s, int spp) {
                if (s.state != PySession::State::Idle)
                    throw std::runtime_error(
                        "RenderSession.continue_to: call it when no render "
                        "runs");
                try {
                    s.session->continue_to(spp);
                } catch (const std::invalid_argument& e) {
                    rethrow_option_error(e);
                }
            },
            py::arg("spp"),
            "Raises the target to spp samples per pixel; the next render() renders only the new "
            "samples")
        .def(
            "image",
            [](const PySession& s) {
                s.check_between_passes("image");
                return image_array(s.session->image());
            },
            "The current image over the region (h, w, 3)")
        .def(
            "shadow_catcher_pass",
            [](const PySession& s) {
                s.check_between_passes("shadow_catcher_pass");
                return image_array(s.session->shadow_catcher_pass());
            },
            "The Shadow Catcher pass over the region (h, w, 3): the light the shadow catchers "
            "kept (scenes/FORMAT.md, Shadow catchers), 1 where none is seen")
        .def(
            "depth",
            [](const PySession& s) -> py::object {
                s.check_between_passes("depth");
                Image d = s.session->depth();
                if (d.width() == 0) return py::none();
                return py::object(image_array(std::move(d)));
            },
            "The Depth pass of the session's camera samples over the region (h, w, 3, the depth "
            "in every channel), as render_aovs' 'depth' at the same spp and seed, when the "
            "session was made with depth_pass=True and the scene allows it (no motion blur, no "
            "ray visibility: render.h's depth_pass_available); None otherwise")
        .def(
            "part",
            [](const PySession& s) {
                s.check_between_passes("part");
                return PyPart{s.session->part(), s.scene->name()};
            },
            "The part this session has rendered (RuntimeError after a cancellation left tiles "
            "behind)")
        .def_property_readonly("stats",
                               [](const PySession& s) {
                                   s.check_between_passes("stats");
                                   return s.session->stats();
                               })
        .def_property_readonly("settings", [](const PySession& s) { return s.session->settings(); })
        .def_property_readonly("samples_done", [](const PySession& s) {
            s.check_between_passes("samples_done");
            return s.session->samples_done();
        });

    m.def(
        "render",
        [](py::handle scene, py::kwargs kw) {
            bool denoised = false;
            if (kw.contains("denoise")) {
                denoised = option_value<bool>(kw["denoise"], "denoise", "a bool");
                PyDict_DelItemString(kw.ptr(), "denoise");
            }
            py::object progress = py::none();
            const RenderOptions options = options_from(kw, "render", &progress);
            if (options.depth_pass)
                bad_argument("depth_pass",
                             "only a RenderSession keeps the Depth pass (RenderSession.depth())");
            if (denoised) {
                if (!progress.is_none())
                    bad_argument("progress", "not available with denoise=True");
                if (options.shadow_catcher_pass)
                    bad_argument("shadow_catcher_pass", "not available with denoise=True");
                const SceneHandle& sh = scene_arg(scene);
                DenoiseOptions d;
                d.threads = options.threads;
                Image image;
                {
                    py::gil_scoped_release release;
                    image = render_denoised(*sh.scene, options, d).image;
                }
                return py::object(image_array(std::move(image)));
            }
            PySession s(scene_arg(scene), options);
            s.run(progress);
            if (options.shadow_catcher_pass)
                return py::object(py::make_tuple(image_array(s.session->image()),
                                                 image_array(s.session->shadow_catcher_pass())));
            return py::object(image_array(s.session->image()));
        },
        py::arg("scene"),
        "Renders the scene (or its region / sample range) and returns the image, float32 "
        "(h, w, 3). denoise=True: the whole image denoised (render_denoised, "
        "facet/render/denoise.h; not with region, samples, time_budget or progress). "
        "Options: spp, threads, seed, integrator, max_depth, region=(x0, y0, x1, y1), "
        "samples=(s0, s1), time_budget, tile_size, pass_seconds, force_general_kernel, "
        "light_selection ('auto' | 'view' | 'power' | 'uniform' | 'tree'), uniform_light_selection "
        "(True = "
        "'uniform'), independent_samples; progress=callable(PassInfo) -> bool "
        "(False cancels: the partial image is returned). Ctrl-C raises KeyboardInterrupt. "
        "shadow_catcher_pass=True returns (image, Shadow Catcher pass (h, w, 3)), the image then "
        "Cycles' Combined of a render with that pass (scenes/FORMAT.md, Shadow catchers).");

    m.def(
        "render_aovs",
        [](py::handle scene, const std::vector<std::string>& passes, int spp, std::uint64_t seed,
           int threads, bool variances, std::optional<std::vector<int>> region) {
            const SceneHandle& sh = scene_arg(scene);
            static const std::pair<const char*, std::uint32_t> kNames[] = {
                {"albedo", kAovAlbedo},
                {"normal", kAovNormal},
                {"depth", kAovDepth},
                {"emission", kAovEmission}};
            AovOptions o;
            for (const std::string& p : passes) {
                const auto* it = std::find_if(std::begin(kNames), std::end(kNames),
                                              [&](const auto& n) { return p == n.first; });
                if (it == std::end(kNames))
                    bad_argument("passes", "unknown pass '" + p +
                                               "' (expected albedo, normal, depth or emission)");
                o.which |= it->second;
            }
            if (spp < 1) bad_argument("spp", "must be >= 1");
            o.spp = spp;
            o.seed = seed;
            o.threads = threads;
            o.variances = variances;
            if (region) {
                if (region->size() != 4) bad_argument("region", "expected (x0, y0, x1, y1)");
                o.region = Region{(*region)[0], (*region)[1], (*region)[2], (*region)[3]};
            }
            Aovs a;
            {
                py::gil_scoped_release release;
                a = render_aovs(*sh.scene, o);
            }
            py::dict out;
            if (o.which & kAovAlbedo) out["albedo"] = image_array(std::move(a.albedo));
            if (o.which & kAovNormal) out["normal"] = image_array(std::move(a.normal));
            if (o.which & kAovDepth) out["depth"] = image_array(std::move(a.depth));
            if (o.which & kAovEmission) out["emission"] = image_array(std::move(a.emission));
            if (variances) {
                if (o.which & kAovAlbedo)
                    out["albedo_variance"] = image_array(std::move(a.albedo_variance));
                if (o.which & kAovNormal)
                    out["normal_variance"] = image_array(std::move(a.normal_variance));
                if (o.which & kAovDepth)
                    out["depth_variance"] = image_array(std::move(a.depth_variance));
            }
            return out;
        },
        py::arg("scene"), py::arg("passes"), py::arg("spp") = 16, py::arg("seed") = 0,
        py::arg("threads") = 0, py::kw_only(), py::arg("variances") = false,
        py::arg("region") = py::none(),
        "First-hit render passes (facet/render/aov.h): {name: float32 (h, w, 3)} for each of "
        "passes ('albedo': directional albedo of the material seen, 'normal': world-space "
        "shading normal facing the viewer, 'depth': distance along the camera's view axis, "
        "1e10 where nothing is hit, 'emission': emitted radiance), averaged over spp camera "
        "samples per pixel; deterministic for a seed. variances=True adds "
        "'albedo_variance', 'normal_variance', 'depth_variance' for those requested: the "
        "variance of each pixel's mean per channel (the denoiser's feature variances). "
        "region=(x0, y0, x1, y1): only those pixels, arrays of the region's size, equal to "
        "that part of the whole image's");

    m.def(
        "denoise",
        [](py::handle half_a, py::handle half_b, py::handle albedo, py::handle normal,
           py::handle depth, int radius, int threads, py::handle color, py::handle variance,
           py::handle albedo_variance, py::handle normal_variance, py::handle depth_variance) {
            // None leaves an input out (a null pointer: denoise() names what is missing).
            auto opt = [](py::handle h, const char* what) {
                return h.is_none() ? std::optional<Image>() : image_from_array(h, what);
            };
            const std::optional<Image> a = opt(half_a, "half_a"), b = opt(half_b, "half_b"),
                                       c = opt(color, "color"), v = opt(variance, "variance"),
                                       av = opt(albedo_variance, "albedo_variance"),
                                       nv = opt(normal_variance, "normal_variance"),
                                       zv = opt(depth_variance, "depth_variance");
            const Image al = image_from_array(albedo, "albedo");
            const Image n = image_from_array(normal, "normal");
            const Image z = image_from_array(depth, "depth");
            auto ptr = [](const std::optional<Image>& i) { return i ? &*i : nullptr; };
            DenoiseInput in;
            in.half_a = ptr(a);
            in.half_b = ptr(b);
            in.color = ptr(c);
            in.variance = ptr(v);
            in.albedo = &al;
            in.normal = &n;
            in.depth = &z;
            in.albedo_variance = ptr(av);
            in.normal_variance = ptr(nv);
            in.depth_variance = ptr(zv);
            return denoised_array(radius, threads,
                                  [&](const DenoiseOptions& o) { return denoise(in, o); });
        },
        py::arg("half_a") = py::none(), py::arg("half_b") = py::none(), py::arg("albedo"),
        py::arg("normal"), py::arg("depth"), py::arg("radius") = 4, py::arg("threads") = 0,
        py::kw_only(), py::arg("color") = py::none(), py::arg("variance") = py::none(),
        py::arg("albedo_variance") = py::none(), py::arg("normal_variance") = py::none(),
        py::arg("depth_variance") = py::none(),
        "The denoised beauty (facet/render/denoise.h) from two half-buffers (renders of the "
        "sample ranges (0, n/2) and (n/2, n)), or from color= and its per-pixel variance= "
        "(of the mean, per channel) instead, and render_aovs' albedo, normal and depth, all "
        "float32 (h, w, 3) of one size; albedo_variance=, normal_variance=, depth_variance= "
        "(optional) down-weight noisy features. ValueError naming the argument for a missing, "
        "mismatched, non-finite or negative-variance input");

    m.def(
        "denoise_halves",
        [](py::handle scene, py::handle half_a, py::handle half_b, int spp, std::uint64_t seed,
           int radius, int threads, bool feature_variances) {
            const SceneHandle& sh = scene_arg(scene);
            const Image a = image_from_array(half_a, "half_a");
            const Image b = image_from_array(half_b, "half_b");
            return denoised_array(radius, threads, [&](DenoiseOptions o) {
                o.feature_variances = feature_variances;
                return denoise_halves(*sh.scene, a, b, spp, seed, o).image;
            });
        },
        py::arg("scene"), py::arg("half_a"), py::arg("half_b"), py::arg("spp"), py::arg("seed") = 0,
        py::arg("radius") = 4, py::arg("threads") = 0, py::kw_only(),
        py::arg("feature_variances") = true,
        "The last step of render(denoise=True) for callers that rendered the two half-buffers "
        "themselves: the scene's albedo, normal and depth at spp and seed with their per-pixel "
        "variances (feature_variances=False: treated as noise free), then denoise() "
        "(facet/render/denoise.h: denoise_halves)");

    m.def(
        "write_image",
        [](py::handle image, const std::string& path) {
            Image img = image_from_array(image, "image");
            py::gil_scoped_release release;
            write_image(img, path);
        },
        py::arg("image"), py::arg("path"),
        "Writes (h, w, 3) linear RGB or (h, w, 4) RGBA (premultiplied): .exr (float) or .png "
        "(sRGB 8-bit)");
    m.def(
        "read_image",
        [](const std::string& path) {
            Image img;
            {
                py::gil_scoped_release release;
                img = read_image(path);
            }
            return image_array(std::move(img));
        },
        py::arg("path"),
        "Reads .exr or .png as linear RGB float32 (h, w, 3); an EXR with alpha as (h, w, 4)");
}

}  // namespace facet::python
