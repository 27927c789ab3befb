// Multiscatter GGX against Blender 3.4's Cycles: tests/render/multiscatter_cycles.json (made by
// bench/multiscatter_cycles.py, which documents the scenes and Cycles' settings) holds a sphere
// under a constant white environment ("env") and under a sun behind the camera ("sun"), for
// Principled, Glossy and Glass nodes, each with Cycles' Multiscatter GGX and with GGX. Facet
// renders the same views with its conversions of those nodes (what the Blender add-on exports:
// principled with "distribution" "multi_ggx" / "ggx"; ggx with fresnel none and
// energy_compensation; dielectric with energy_compensation) and takes the same pixel mask.
//
// Asserted: the points where the two models must agree. Every Principled GGX point (the same
// single-scattering lobes), and every point whose multiple scattering the analytic white
// furnace fixes: with F = 1 (white metal, white glossy, white glass) a multiple-scattering
// model reflects (or reflects plus transmits) everything in a constant environment, Cycles'
// random walk and Facet's compensation alike. Printed only, the differences docs/principled.md
// explains: where F < 1 (coloured metal, dielectric specular) the random walk applies the
// Fresnel colour at every bounce (its multiply scattered light is more saturated than
// Kulla-Conty's F_ms), and the lobe's shape under the sun (back-scattering).
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "facet/render/render.h"
#include "facet/render/scene.h"
#include "facet/testsupport/render_test_util.h"

namespace fr = facet::render;
using facet::Rgb;

namespace {

nlohmann::json references() {
    std::ifstream in(FACET_MULTISCATTER_CYCLES_JSON);
    return nlohmann::json::parse(in);
}

// The Blender node of a point -> Facet's material (the add-on's conversion).
nlohmann::json facet_material(const nlohmann::json& p) {
    const bool multi = p["distribution"] == "MULTI_GGX";
    const nlohmann::json& in = p["params"];
    nlohmann::json m;
    const std::string node = p["node"];
    if (node == "principled") {
        m = in;
        m["model"] = "principled";
        m["distribution"] = multi ? "multi_ggx" : "ggx";
        return m;
    }
    const double r = in["roughness"];
    if (node == "glossy") {
        m = {{"model", "ggx"},
             {"fresnel", "none"},
             {"alpha", r * r},
             {"reflectance", in["color"]},
             {"energy_compensation", multi}};
    } else {  // glass
        m = {{"model", "dielectric"},
             {"ior", in["ior"]},
             {"alpha", r * r},
             {"transmittance", in["color"]},
             {"energy_compensation", multi}};
    }
    return m;
}

struct Stats {
    double mean[3], se[3];
    std::vector<std::array<double, 3>> rings;
};

Stats render_point(const nlohmann::json& scene, const nlohmann::json& p, int spp, int seeds) {
    const int size = scene["size"];
    const double scale = scene["ortho_scale"], mask = scene["mask_radius"];
    const std::vector<double> edges = scene["rings"];
    const bool sun = p["scene"] == "sun";
    std::ostringstream body;
    body << R"("camera": {"type": "orthographic", "position": [0, 0, 5], "look_at": [0, 0, 0],
                "up": [0, 1, 0], "scale": )"
         << scale << R"(, "width": )" << size << R"(, "height": )" << size << R"(},
        "render": {"integrator": "path", "max_depth": )"
         << int(scene["max_bounces"]) << R"(},
        "shapes": [{"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": )"
         << facet_material(p).dump() << "}], \"lights\": [";
    if (sun)
        body << R"({"type": "directional", "direction": [0, 0, -1], "irradiance": 1}])";
    else
        body << R"({"type": "environment", "radiance": )" << double(scene["environment"]) << "}]";
    const fr::Scene s = fr::testing::scene_from(body.str());
    double sum[3] = {0, 0, 0}, sum2[3] = {0, 0, 0};
    Stats r{};
    r.rings.assign(edges.size() - 1, {0, 0, 0});
    std::vector<int> ring_n(edges.size() - 1, 0);
    for (int seed = 0; seed < seeds; ++seed) {
        const fr::Image img = fr::render(s, fr::testing::test_options("path", spp, 301 + seed));
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
                for (std::size_t b = 0; b + 1 < edges.size(); ++b) {
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
    for (std::size_t b = 0; b < r.rings.size(); ++b)
        for (int c = 0; c < 3; ++c) r.rings[b][c] /= ring_n[b];
    for (int c = 0; c < 3; ++c) {
        r.mean[c] = sum[c] / seeds;
        const double var =
            std::max(0.0, sum2[c] / seeds - r.mean[c] * r.mean[c]) * seeds / (seeds - 1);
        r.se[c] = std::sqrt(var / seeds);
    }
    return r;
}

// The points the white furnace (or identical single-scattering lobes) decides; header comment.
// Glossy and Glass GGX are not asserted: Cycles 3.4 evaluates them with the separable Smith G,
// Facet's ggx and dielectric with the height-correlated one (docs/principled.md: 2.6% at
// alpha 0.81). Anisotropic Multiscatter is compensated approximately (docs/principled.md).
bool must_agree(const nlohmann::json& p) {
    if (p["distribution"] == "GGX") return p["node"] == "principled" && p["scene"] == "env";
    const std::string name = p["name"];
    if (p["scene"] == "sun") return false;
    for (const char* white : {"metal_white", "glossy_white", "glass_white", "transmission_r"})
        if (name.rfind(white, 0) == 0) return true;
    return false;
}

// Tolerance of an asserted point, per channel: 4 combined standard errors plus 0.6% of the value
// for what differs besides the BSDF (Cycles' faceted icosphere and 1.5 px pixel filter, as in
// test_principled_render.cpp), plus the compensation's own error where it applies: 3e-3 (the
// white furnace tolerance of Principled.MultiscatterWhiteMetalIsAWhiteFurnace and of the
// dielectric's compensation).
double allowance(const nlohmann::json& p, double value) {
    double a = 0.006 * value;
    if (p["distribution"] == "MULTI_GGX") a += 3e-3;
    return a;
}

TEST(MultiscatterRender, MatchesCyclesWhereTheWhiteFurnaceDecides) {
    const nlohmann::json ref = references();
    const int spp = std::max(4, int(16 * fr::testing::stress_scale()));
    const int seeds = 4;
    int asserted = 0;
    for (const nlohmann::json& p : ref["points"]) {
        const std::string name = p["name"], dist = p["distribution"];
        const bool check = must_agree(p);
        const Stats f = render_point(ref["scene"], p, spp, seeds);
        std::printf("%-24s %-9s Facet/Cycles", name.c_str(), dist.c_str());
        for (int c = 0; c < 3; ++c) {
            const double cy = p["mean"][c], cy_se = p["se"][c];
            std::printf(" %.4f", f.mean[c] / cy);
            if (!check) continue;
            const double tol =
                4.0 * std::sqrt(f.se[c] * f.se[c] + cy_se * cy_se) + allowance(p, cy);
            EXPECT_NEAR(f.mean[c], cy, tol) << name << " " << dist << " channel " << c;
        }
        asserted += check;
        std::printf("  rings (R) Facet/Cycles");
        for (std::size_t b = 0; b < f.rings.size(); ++b)
            std::printf(" %.3f", f.rings[b][0] / double(p["rings"][b][0]));
        std::printf("%s\n", check ? "" : "  [documented difference, not asserted]");
    }
    EXPECT_GE(asserted, 14);
}

}  // namespace
