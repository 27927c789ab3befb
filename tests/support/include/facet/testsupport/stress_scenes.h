// Scene generators and counters shared by the scene-level stress test
// (tests/render/test_scene_stress.cpp, small) and its longer run (bench/stress_bench.cpp):
// a furnace (camera inside a closed emitting sphere reflecting with a material), a grazing-light
// scene with coincident surfaces and sliver / degenerate triangles, each at a scale and offset;
// and the counts the checks read: NaN/Inf pixels, samples the film dropped
// (RenderStats::nonfinite), the image mean and its standard error.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "facet/render/render.h"
#include "facet/render/scene_description.h"

namespace facet::stress {

namespace fr = facet::render;

struct Stats {
    double mean = 0, std_error = 0, max = 0;
    std::size_t nonfinite_pixels = 0;
    std::uint64_t dropped = 0;
};

inline Stats render_stats(const fr::SceneDescription& d, int spp, int threads = 2) {
    const fr::Scene scene = fr::build_scene(d, "stress");
    fr::RenderOptions o;
    o.spp = spp;
    o.threads = threads;
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

inline fr::MaterialDesc mat(const std::string& model,
                            std::vector<std::pair<std::string, facet::ParamValue>> p) {
    fr::MaterialDesc m;
    m.model = model;
    for (auto& [k, v] : p) m.params.set(k, v);
    return m;
}

// Camera inside a closed sphere of radius `scale` centred at `offset`, emitting Le and
// reflecting with `material` (turned inside out). Radiance does not depend on either.
inline fr::SceneDescription furnace(const fr::MaterialDesc& material, float le, float scale = 1.f,
                                    Vec3 offset = Vec3(0.f), int size = 16) {
    fr::SceneDescription d;
    d.camera.position = offset;
    d.camera.look_at = offset + Vec3(0.f, 0.f, -scale);
    d.camera.fov = 90.0;
    d.camera.width = size;
    d.camera.height = size;
    fr::ShapeDesc s;
    s.kind = fr::ShapeKind::Sphere;
    s.center = offset;
    s.radius = scale;
    s.flip_normals = true;
    s.emission = Rgb(le);
    s.material = material;
    d.shapes.push_back(s);
    d.render.max_depth = 256;
    return d;
}

// A furnace material and what its furnace must read (see furnace_cases()).
struct FurnaceCase {
    std::string label;
    fr::MaterialDesc m;
    bool exact;           // the albedo is exactly `albedo` at every angle
    double albedo = 0.8;  // the largest albedo over all angles
};

// Extreme materials: roughness 1e-7 .. 10, kappa 0 .. 1e7, anisotropy, compensation,
// composites. Every material reflects at most 80% (its reflectance scale 0.8 on a lobe of
// albedo <= 1), so L <= Le / (1 - 0.8) = 2.5 Le; lobes whose albedo is exactly 0.8 (Lambert,
// mirror, compensated microfacets) must reach it. A composite's albedo is Es + rho_d (1 - Es)
// (docs/models.md, "Composite energy"): with glossy and diffuse scales 0.8 it is at most
// 0.8 + 0.2 * 0.8 = 0.96, exactly 0.96 when the glossy lobe is compensated (Es = 0.8 at every
// angle), so L <= Le / 0.04 = 12.5 Le there.
inline std::vector<FurnaceCase> furnace_cases() {
    return {
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
}

// Floor and an exactly coincident second floor (z-fighting), a quad light `light_angle` rad
// above grazing facing the floor, sliver triangles (height 1e-6 of their length) and degenerate
// ones in one mesh (unless !slivers: away from the origin float quantises them to zero area and
// build_scene rejects the mesh), and a directional sun `sun_angle` rad above the horizon;
// every coordinate multiplied by `scale` and moved by `offset`.
inline fr::SceneDescription grazing_scene(float scale = 1.f, Vec3 offset = Vec3(0.f),
                                          float light_angle = 1e-4f, float sun_angle = 1e-6f,
                                          bool slivers = true, int width = 24, int height = 16) {
    auto at = [&](Vec3 p) { return p * scale + offset; };
    fr::SceneDescription d;
    d.camera.position = at({0.f, 1.f, 3.f});
    d.camera.look_at = at({0.f, 0.f, 0.f});
    d.camera.fov = 50.0;
    d.camera.width = width;
    d.camera.height = height;
    d.materials.push_back(
        {"rough", mat("ggx", {{"alpha", 1e-3}, {"fresnel", std::string("schlick")}})});
    d.materials.push_back({"white", mat("lambert", {{"reflectance", 0.9}})});
    auto quad = [&](std::array<Vec3, 4> v, const char* material, Rgb emission = Rgb(0.f)) {
        fr::ShapeDesc s;
        s.kind = fr::ShapeKind::Quad;
        for (auto& p : v) p = at(p);
        s.vertices = v;
        s.material_ref = material;
        s.emission = emission;
        d.shapes.push_back(s);
    };
    quad({Vec3{-2, 0, -2}, {-2, 0, 2}, {2, 0, 2}, {2, 0, -2}}, "white");
    quad({Vec3{-2, 0, -2}, {-2, 0, 2}, {2, 0, 2}, {2, 0, -2}}, "rough");
    quad({Vec3{-1, light_angle, -1.5f},
          {1, light_angle, -1.5f},
          {1, 0.5f, -1.5f},
          {-1, 0.5f, -1.5f}},
         "", Rgb(10.f));
    d.shapes.back().material_ref.clear();
    fr::LightDesc grazing;
    grazing.kind = fr::LightKind::Directional;
    grazing.direction = Vec3(std::cos(sun_angle), -std::sin(sun_angle), 0.f);
    grazing.irradiance = Rgb(3.f);
    d.lights.push_back(grazing);
    if (!slivers) return d;
    std::vector<float> p = {-1, 0.2f, 0, 1, 0.2f, 0, 0, 0.2f + 1e-6f, 0, -1, 0.4f, 0, 1, 0.4f, 0};
    for (size_t i = 0; i < p.size(); i += 3) {
        const Vec3 q = at({p[i], p[i + 1], p[i + 2]});
        p[i] = q.x, p[i + 1] = q.y, p[i + 2] = q.z;
    }
    std::vector<std::uint32_t> ix = {0, 1, 2, 0, 2, 1, 3, 4, 3, 0, 0, 0};
    fr::ShapeDesc mesh;
    mesh.kind = fr::ShapeKind::Mesh;
    mesh.material_ref = "rough";
    mesh.mesh = fr::MeshData::copy_of(p, ix);
    d.shapes.push_back(mesh);
    return d;
}

}  // namespace facet::stress
