// The scene of bench/cycles_sphere.py in Facet's format, for the tests that compare with its
// Cycles renders (test_principled_render.cpp, test_multiscatter_render.cpp): a sphere of radius
// 1 at the origin, an orthographic camera along -z spanning [-scale/2, scale/2]^2 in size x size
// pixels, the path integrator with Cycles' bounce limit. The statistics are the Cycles script's:
// the mean over the pixels whose centres lie within mask_radius of the centre and, when the
// reference's scene has "rings" edges, the mean per ring of pixel centres, per channel.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "facet/render/render.h"
#include "facet/render/scene.h"
#include "facet/testsupport/render_test_util.h"

namespace facet::render::testing {

struct CyclesSphereStats {
    double mean[3], se[3];  // over `seeds` renders: the mean of the masked means and its error
    std::vector<std::array<double, 3>> rings;  // of all seeds' pixels, one per ring
};

// `scene`: the reference JSON's "scene" object; `material`: a Facet material; `lights`: the
// JSON array of the scene's lights. Seeds seed0, seed0 + 1, ...
inline CyclesSphereStats render_cycles_sphere(const nlohmann::json& scene,
                                              const nlohmann::json& material,
                                              const std::string& lights, int spp, int seeds,
                                              std::uint64_t seed0) {
    const int size = scene["size"];
    const double scale = scene["ortho_scale"], mask = scene["mask_radius"];
    const std::vector<double> edges = scene.value("rings", std::vector<double>{});
    std::ostringstream body;
    body << R"("camera": {"type": "orthographic", "position": [0, 0, 5], "look_at": [0, 0, 0],
                "up": [0, 1, 0], "scale": )"
         << scale << R"(, "width": )" << size << R"(, "height": )" << size << R"(},
        "render": {"integrator": "path", "max_depth": )"
         << int(scene["max_bounces"]) << R"(},
        "shapes": [{"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": )"
         << material.dump() << "}], \"lights\": " << lights;
    const Scene s = scene_from(body.str());
    double sum[3] = {0, 0, 0}, sum2[3] = {0, 0, 0};
    CyclesSphereStats r{};
    const std::size_t n_rings = edges.empty() ? 0 : edges.size() - 1;
    r.rings.assign(n_rings, {0, 0, 0});
    std::vector<int> ring_n(n_rings, 0);
    for (int seed = 0; seed < seeds; ++seed) {
        const Image img = render(s, test_options("path", spp, seed0 + std::uint64_t(seed)));
        double m[3] = {0, 0, 0};
        int n = 0;
        for (int y = 0; y < size; ++y) {
            for (int x = 0; x < size; ++x) {
                const double px = ((x + 0.5) / size - 0.5) * scale;
                const double py = ((y + 0.5) / size - 0.5) * scale;
                const double rho = std::hypot(px, py);
                const Rgb& v = img.at(x, y);
                if (rho < mask) {
                    for (int c = 0; c < 3; ++c) m[c] += v[c];
                    ++n;
                }
                for (std::size_t b = 0; b < n_rings; ++b) {
                    if (rho < edges[b] || rho >= edges[b + 1]) continue;
                    for (int c = 0; c < 3; ++c) r.rings[b][c] += v[c];
                    ++ring_n[b];
                }
            }
        }
        for (int c = 0; c < 3; ++c) {
            m[c] /= n;
            sum[c] += m[c], sum2[c] += m[c] * m[c];
        }
    }
    for (std::size_t b = 0; b < n_rings; ++b)
        for (int c = 0; c < 3; ++c) r.rings[b][c] /= ring_n[b];
    for (int c = 0; c < 3; ++c) {
        r.mean[c] = sum[c] / seeds;
        const double var =
            std::max(0.0, sum2[c] / seeds - r.mean[c] * r.mean[c]) * seeds / (seeds - 1);
        r.se[c] = std::sqrt(var / seeds);
    }
    return r;
}

}  // namespace facet::render::testing
