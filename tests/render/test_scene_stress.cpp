// Scene-level numerical stress (issue 12): extreme material parameters in a furnace, grazing
// light, sliver and degenerate triangles, coincident surfaces. What is counted: NaN/Inf pixels,
// samples the film dropped (RenderStats::nonfinite), and energy gain — a furnace brighter than
// its analytic bound. The expected count of each is zero. FACET_STRESS_SCALE (test.sh sets 0.1
// under sanitizers) scales the sample counts; bench/ has no longer variant yet.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdlib>
#include <string>
#include <vector>

#include "facet/render/render.h"
#include "facet/render/scene_description.h"

namespace fr = facet::render;
using facet::ParamSet;
using facet::Rgb;
using facet::Vec3;

namespace {

double stress_scale() {
    const char* s = std::getenv("FACET_STRESS_SCALE");
    return s ? std::max(0.05, std::atof(s)) : 1.0;
}

struct Stats {
    double mean = 0, std_error = 0, max = 0;
    std::size_t nonfinite_pixels = 0;
    std::uint64_t dropped = 0;
};

Stats render_stats(const fr::SceneDescription& d, int spp) {
    const fr::Scene scene = fr::build_scene(d, "stress");
    fr::RenderOptions o;
    o.spp = spp;
    o.threads = 2;
    fr::RenderStats st;
    const fr::Image img = fr::render(scene, o, &st);
    Stats s;
    s.dropped = st.nonfinite;
    double sum = 0, sum2 = 0;
    std::size_t n = 0;
    for (const Rgb& p : img.pixels()) {
        if (!facet::is_finite(p)) {
            ++s.nonfinite_pixels;
            continue;
        }
        const double v = (double(p.x) + p.y + p.z) / 3.0;
        sum += v;
        sum2 += v * v;
        s.max = std::max(s.max, v);
        ++n;
    }
    s.mean = n ? sum / double(n) : 0.0;
    // Pixels are independent estimates of the same value in a furnace: their spread gives the
    // standard error of the mean.
    const double var = n > 1 ? (sum2 - double(n) * s.mean * s.mean) / double(n - 1) : 0.0;
    s.std_error = std::sqrt(std::max(var, 0.0) / double(std::max<std::size_t>(n, 1)));
    return s;
}

// Camera inside a closed sphere emitting Le and reflecting with `material` (turned inside out).
fr::SceneDescription furnace(const fr::MaterialDesc& material, float le) {
    fr::SceneDescription d;
    d.camera.position = {0.f, 0.f, 0.f};
    d.camera.look_at = {0.f, 0.f, -1.f};
    d.camera.fov = 90.0;
    d.camera.width = 16;
    d.camera.height = 16;
    fr::ShapeDesc s;
    s.kind = fr::ShapeKind::Sphere;
    s.radius = 1.0;
    s.flip_normals = true;
    s.emission = Rgb(le);
    s.material = material;
    d.shapes.push_back(s);
    d.render.max_depth = 256;
    return d;
}

fr::MaterialDesc mat(const std::string& model,
                     std::vector<std::pair<std::string, facet::ParamValue>> p) {
    fr::MaterialDesc m;
    m.model = model;
    for (auto& [k, v] : p) m.params.set(k, v);
    return m;
}

}  // namespace

TEST(SceneStress, ExtremeMaterialsInAFurnaceNeitherGainEnergyNorProduceNaN) {
    // Every material reflects at most 80% (its reflectance scale 0.8 on a lobe of albedo <= 1),
    // so L <= Le / (1 - 0.8) = 2.5 Le; lobes whose albedo is exactly 0.8 (Lambert, mirror,
    // compensated microfacets) must reach it. Tolerances: 5 standard errors of the image mean
    // (pixels are i.i.d. estimates in a furnace), and 3e-3 relative for the compensated lobes'
    // tabulated albedo (test_energy.cpp measures it to 2e-4 on white lobes).
    // A composite's albedo is Es + rho_d (1 - Es) (README, "Composite energy"): with glossy and
    // diffuse scales 0.8 it is at most 0.8 + 0.2 * 0.8 = 0.96, exactly 0.96 when the glossy lobe
    // is compensated (Es = 0.8 at every angle), so L <= Le / 0.04 = 12.5 Le there.
    const float le = 0.5f;
    struct Case {
        const char* label;
        fr::MaterialDesc m;
        bool exact;           // the albedo is exactly `albedo` at every angle
        double albedo = 0.8;  // the largest albedo over all angles
    };
    const std::vector<Case> cases = {
        {"lambert", mat("lambert", {{"reflectance", 0.8}}), true},
        {"mirror", mat("mirror", {{"reflectance", 0.8}}), true},
        {"ggx alpha 1e-7 (the mirror)", mat("ggx", {{"reflectance", 0.8}, {"alpha", 1e-7}}), true},
        {"ggx alpha 1e-4", mat("ggx", {{"reflectance", 0.8}, {"alpha", 1e-4}}), false},
        {"ggx alpha 1", mat("ggx", {{"reflectance", 0.8}, {"alpha", 1.0}}), false},
        {"ggx alpha 10", mat("ggx", {{"reflectance", 0.8}, {"alpha", 10.0}}), false},
        {"ggx alpha 1 compensated",
         mat("ggx", {{"reflectance", 0.8}, {"alpha", 1.0}, {"energy_compensation", true}}), true},
        {"beckmann alpha 1e-7", mat("beckmann", {{"reflectance", 0.8}, {"alpha", 1e-7}}), true},
        {"beckmann alpha 1", mat("beckmann", {{"reflectance", 0.8}, {"alpha", 1.0}}), false},
        {"blinn kappa 1e7", mat("blinn", {{"reflectance", 0.8}, {"exponent", 1e7}}), false},
        {"blinn kappa 0", mat("blinn", {{"reflectance", 0.8}, {"exponent", 0.0}}), false},
        {"ggx anisotropic 1e-4 x 1",
         mat("ggx", {{"reflectance", 0.8}, {"alpha_u", 1e-4}, {"alpha_v", 1.0}}), false},
        {"beckmann anisotropic 1e-3 x 10 compensated",
         mat("beckmann", {{"reflectance", 0.8},
                          {"alpha_u", 1e-3},
                          {"alpha_v", 10.0},
                          {"energy_compensation", true}}),
         false},
        {"composite rough",
         mat("composite", {{"diffuse_reflectance", 0.8},
                           {"glossy_reflectance", 0.8},
                           {"alpha", 1.0},
                           {"fresnel", std::string("none")}}),
         false, 0.96},
        {"composite rough compensated",
         mat("composite", {{"diffuse_reflectance", 0.8},
                           {"glossy_reflectance", 0.8},
                           {"alpha", 1.0},
                           {"fresnel", std::string("none")},
                           {"energy_compensation", true}}),
         true, 0.96},
    };
    const int spp = std::max(4, int(64 * stress_scale()));
    for (const Case& c : cases) {
        SCOPED_TRACE(c.label);
        const double bound = le / (1.0 - c.albedo);
        const Stats s = render_stats(furnace(c.m, le), spp);
        EXPECT_EQ(s.nonfinite_pixels, 0u);
        EXPECT_EQ(s.dropped, 0u);
        EXPECT_LE(s.mean, bound + 5.0 * s.std_error + 3e-3 * bound) << "energy gain";
        if (c.exact) EXPECT_NEAR(s.mean, bound, 5.0 * s.std_error + 3e-3 * bound);
    }
}

TEST(SceneStress, GrazingLightSliversAndCoincidentSurfacesStayFinite) {
    fr::SceneDescription d;
    d.camera.position = {0.f, 1.f, 3.f};
    d.camera.look_at = {0.f, 0.f, 0.f};
    d.camera.fov = 50.0;
    d.camera.width = 24;
    d.camera.height = 16;
    d.materials.push_back(
        {"rough", mat("ggx", {{"alpha", 1e-3}, {"fresnel", std::string("schlick")}})});
    d.materials.push_back({"white", mat("lambert", {{"reflectance", 0.9}})});
    auto quad = [&](std::array<Vec3, 4> v, const char* material, Rgb emission = Rgb(0.f)) {
        fr::ShapeDesc s;
        s.kind = fr::ShapeKind::Quad;
        s.vertices = v;
        s.material_ref = material;
        s.emission = emission;
        d.shapes.push_back(s);
    };
    // Floor, and a second floor exactly coincident with it (z-fighting).
    quad({Vec3{-2, 0, -2}, {-2, 0, 2}, {2, 0, 2}, {2, 0, -2}}, "white");
    quad({Vec3{-2, 0, -2}, {-2, 0, 2}, {2, 0, 2}, {2, 0, -2}}, "rough");
    // A light almost edge-on to the floor (1e-4 rad above grazing), facing it.
    quad({Vec3{-1, 1e-4f, -1.5f}, {1, 1e-4f, -1.5f}, {1, 0.5f, -1.5f}, {-1, 0.5f, -1.5f}}, "",
         Rgb(10.f));
    d.shapes.back().material_ref.clear();
    // Sliver triangles (height 1e-6 of their length) and degenerate ones in one mesh.
    std::vector<float> p = {-1, 0.2f, 0, 1, 0.2f, 0, 0, 0.2f + 1e-6f, 0, -1, 0.4f, 0, 1, 0.4f, 0};
    std::vector<std::uint32_t> ix = {0, 1, 2, 0, 2, 1, 3, 4, 3, 0, 0, 0};
    fr::ShapeDesc mesh;
    mesh.kind = fr::ShapeKind::Mesh;
    mesh.material_ref = "rough";
    mesh.mesh = fr::MeshData::copy_of(p, ix);
    d.shapes.push_back(mesh);
    fr::LightDesc grazing;
    grazing.kind = fr::LightKind::Directional;
    grazing.direction = Vec3(1.f, -1e-6f, 0.f);  // grazing sun
    grazing.irradiance = Rgb(3.f);
    d.lights.push_back(grazing);
    for (const char* integrator : {"path", "direct"}) {
        SCOPED_TRACE(integrator);
        d.render.integrator = integrator;
        const Stats s = render_stats(d, std::max(4, int(32 * stress_scale())));
        EXPECT_EQ(s.nonfinite_pixels, 0u);
        EXPECT_EQ(s.dropped, 0u);
        EXPECT_GT(s.mean, 0.0);
    }
}
