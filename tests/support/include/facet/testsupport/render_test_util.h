// Helpers shared by the renderer's scene tests: a scene from the body of a JSON scene file, the
// render options every test render starts from, and the analytic radiance of a Lambertian plane
// under a point light.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <optional>
#include <string>

#include "facet/render/render.h"
#include "facet/render/scene.h"

namespace facet::render::testing {

// A scene from the members of a scene file after "format" and "version" (e.g. R"("camera":
// {...}, "shapes": [...])"); errors name "test.json".
inline Scene scene_from(const std::string& body) {
    return load_scene_from_string(R"({"format": "facet-scene", "version": 1, )" + body + "}",
                                  "test.json");
}

// The same with relative files resolved in `dir`, and errors naming `name`.
inline Scene scene_in_dir(const std::string& dir, const std::string& body,
                          const std::string& name) {
    return load_scene_from_string(R"({"format": "facet-scene", "version": 1, )" + body + "}", name,
                                  dir);
}

// The SceneError message of scene_in_dir(dir, body, name), or "" when the scene loads.
inline std::string scene_error(const std::string& dir, const std::string& body,
                               const std::string& name) {
    try {
        scene_in_dir(dir, body, name);
    } catch (const SceneError& e) {
        return e.what();
    }
    return "";
}

// "materials" and "shapes" of a white Lambertian plane y = 0 (reflectance 0.7) under a 2 x 2
// quad light of radiance 5 at height 0.6 centred over the origin, emitting downward (its front
// side faces the plane), for scene_from after a "camera".
inline const char* const kQuadLightOverPlane = R"(
        "materials": {"white": {"model": "lambert", "reflectance": 0.7}},
        "shapes": [
          {"type": "plane", "point": [0, 0, 0], "normal": [0, 1, 0], "material": "white"},
          {"type": "quad", "emission": 5,
           "vertices": [[-1, 0.6, -1], [1, 0.6, -1], [1, 0.6, 1], [-1, 0.6, 1]]}
        ])";

// Options of a test render: integrator, samples per pixel, seed and thread count; everything
// else as RenderOptions defaults it (the scene's max_depth, Auto light selection, no progress).
// Scale of the Monte Carlo work of slow render tests: FACET_STRESS_SCALE (test.sh sets 0.1 for
// the Debug + ASan/UBSan tree), at least 0.05; 1 when unset.
inline double stress_scale() {
    const char* s = std::getenv("FACET_STRESS_SCALE");
    return s ? std::max(0.05, std::atof(s)) : 1.0;
}

inline RenderOptions test_options(const std::string& integrator, int spp, std::uint64_t seed,
                                  int threads = 2) {
    RenderOptions o;
    o.integrator = integrator;
    o.spp = spp;
    o.threads = threads;
    o.seed = seed;
    return o;
}

// Radiance seen by the pixel-centre camera ray of pixel (x, y) on the Lambertian plane y = 0 of
// reflectance rho, lit by an isotropic point light of power phi at `light`:
// L = rho/pi * phi cos(theta) / (4 pi r^2) (Cohen & Wallace eq. 2.40/2.42), computed in double
// from the float camera ray. nullopt when the ray does not go down to the plane.
inline std::optional<double> point_light_on_plane(const Camera& cam, int x, int y,
                                                  const Vec3& light, double phi, double rho) {
    const Ray ray = cam.generate_ray({float(x) + 0.5f, float(y) + 0.5f});
    const DVec3 o(ray.o), d(ray.d);
    if (!(d.y < 0.0)) return std::nullopt;
    const DVec3 p = o + (-o.y / d.y) * d;
    const DVec3 to_light = DVec3(light) - p;
    const double r2 = glm::dot(to_light, to_light);
    const double cos_t = to_light.y / std::sqrt(r2);
    return rho / kPiD * phi * cos_t / (4.0 * kPiD * r2);
}

// The mean of f(0), ..., f(n - 1) and its standard error (the samples' standard deviation over
// sqrt(n)), for Monte Carlo tests that allow a few standard errors.
struct McResult {
    double mean = 0.0, stderr_ = 0.0;
};
template <class F>
McResult mc(int n, F f) {
    double s = 0.0, s2 = 0.0;
    for (int i = 0; i < n; ++i) {
        const double v = f(i);
        s += v;
        s2 += v * v;
    }
    McResult r;
    r.mean = s / n;
    r.stderr_ = std::sqrt(std::max(0.0, s2 / n - r.mean * r.mean) / n);
    return r;
}

}  // namespace facet::render::testing
