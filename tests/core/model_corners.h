// The parameter corners shared by the model-wide suites (reciprocity, energy, stress): every
// distribution at roughness extremes, anisotropy ratios up to 1e4, every Fresnel kind including
// IOR near 1 and below 1, with and without energy compensation; plus registry materials.
// Test-only code. Each lobe spec also yields its double-precision oracle (reference_double.h).
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "facet/microfacet.h"
#include "facet/registry.h"
#include "reference_double.h"

namespace facet::test {

struct FresnelChoice {
    std::string name;
    Fresnel fresnel;
    ref::FresnelSpec ref;
};

inline std::vector<FresnelChoice> fresnel_corners() {
    using K = ref::FresnelSpec::Kind;
    std::vector<FresnelChoice> v;
    v.push_back({"none", Fresnel::none(), {K::None}});
    for (float eta : {1.5f, 1.0001f, 0.7f, 1.f}) {
        ref::FresnelSpec r{K::Dielectric};
        r.eta = DVec3(eta);
        v.push_back({"dielectric" + std::to_string(eta), Fresnel::dielectric(eta), r});
    }
    Rgb eta(0.18f, 0.42f, 1.37f), k(3.42f, 2.35f, 1.77f);  // gold
    ref::FresnelSpec rc{K::Conductor};
    rc.eta = DVec3(eta);
    rc.k = DVec3(k);
    v.push_back({"conductor_gold", Fresnel::conductor(eta, k), rc});
    ref::FresnelSpec rs{K::Schlick};
    rs.f0 = DVec3(0.04, 0.5, 0.95);
    v.push_back({"schlick", Fresnel::schlick(Rgb(0.04f, 0.5f, 0.95f)), rs});
    return v;
}

struct LobeSpec {
    ref::Dist dist;
    float ax, ay;  // alphas, or Blinn exponents
    FresnelChoice fresnel;
    bool energy_compensation;

    std::string name() const {
        const char* d = dist == ref::Dist::GGX        ? "ggx"
                        : dist == ref::Dist::Beckmann ? "beckmann"
                                                      : "blinn";
        char buf[160];
        std::snprintf(buf, sizeof buf, "%s(%g,%g) F=%s ec=%d", d, double(ax), double(ay),
                      fresnel.name.c_str(), int(energy_compensation));
        return buf;
    }
    MicrofacetDistribution distribution() const {
        switch (dist) {
            case ref::Dist::GGX:
                return MicrofacetDistribution::ggx(ax, ay);
            case ref::Dist::Beckmann:
                return MicrofacetDistribution::beckmann(ax, ay);
            case ref::Dist::Blinn:
                return MicrofacetDistribution::blinn(ax, ay);
        }
        return MicrofacetDistribution::ggx(ax, ay);
    }
    MicrofacetReflection lobe(Rgb scale = Rgb(1.f)) const {
        return MicrofacetReflection(distribution(), fresnel.fresnel, scale, energy_compensation);
    }
    ref::Distribution ref_distribution() const { return {dist, double(ax), double(ay)}; }
};

// Roughness corners per distribution: (u, v) pairs. Includes the mirror threshold (alpha 1e-4,
// Blinn exponent 2e8 - 2), values far below it (1e-7), the largest allowed values and
// anisotropy ratios of 1e4 both ways.
inline std::vector<std::pair<float, float>> roughness_corners(ref::Dist d, bool full) {
    if (d == ref::Dist::Blinn) {
        std::vector<std::pair<float, float>> v = {
            {0.f, 0.f},   {1e-3f, 1e-3f}, {1.f, 1.f},   {10.f, 10.f}, {100.f, 100.f}, {1e3f, 1e3f},
            {1e5f, 1e5f}, {1e7f, 1e7f},   {1e9f, 1e9f}, {1.f, 1e4f},  {1e4f, 1.f},    {1e3f, 1e7f}};
        if (full) v.insert(v.end(), {{1e8f, 1e8f}, {0.f, 1e4f}, {1e7f, 1e3f}, {30.f, 3.f}});
        return v;
    }
    std::vector<std::pair<float, float>> v = {
        {1e-7f, 1e-7f}, {1e-4f, 1e-4f}, {1e-3f, 1e-3f}, {0.01f, 0.01f}, {0.1f, 0.1f}, {0.5f, 0.5f},
        {1.f, 1.f},     {10.f, 10.f},   {1e-4f, 1.f},   {1.f, 1e-4f},   {1e-3f, 10.f}};
    if (full) v.insert(v.end(), {{3.f, 3.f}, {10.f, 1e-3f}, {0.05f, 0.5f}, {2e-4f, 1e-4f}});
    return v;
}

// All lobe corners: distributions x roughness x Fresnel x compensation. `full` adds more
// roughness corners (the stress test); the compensated lobes use a subset of Fresnel kinds
// (their tables cost ~ms to build).
inline std::vector<LobeSpec> lobe_corners(bool full) {
    std::vector<LobeSpec> v;
    auto fr = fresnel_corners();
    for (ref::Dist d : {ref::Dist::GGX, ref::Dist::Beckmann, ref::Dist::Blinn}) {
        for (auto [u, w] : roughness_corners(d, full)) {
            for (size_t i = 0; i < fr.size(); ++i) {
                v.push_back({d, u, w, fr[i], false});
                if (i == 0 || fr[i].name == "conductor_gold") v.push_back({d, u, w, fr[i], true});
            }
        }
    }
    return v;
}

// Registry materials covering every model name, including composites with all three lobes.
struct MaterialSpec {
    std::string name, model;
    ParamSet params;
};

inline std::vector<MaterialSpec> material_corners() {
    std::vector<MaterialSpec> v;
    auto add = [&](std::string name, std::string model,
                   std::vector<std::pair<std::string, ParamValue>> ps) {
        MaterialSpec m{std::move(name), std::move(model), {}};
        for (auto& [k, val] : ps) m.params.set(k, val);
        v.push_back(std::move(m));
    };
    add("lambert_white", "lambert", {{"reflectance", 1.0}});
    add("lambert_black", "lambert", {{"reflectance", 0.0}});
    add("mirror_white", "mirror", {});
    add("mirror_dielectric", "mirror", {{"fresnel", std::string("dielectric")}, {"ior", 1.0001}});
    add("ggx_default", "ggx", {});
    add("ggx_ec_conductor", "ggx",
        {{"alpha", 0.7}, {"fresnel", std::string("conductor")}, {"energy_compensation", true}});
    add("beckmann_aniso", "beckmann", {{"alpha_u", 0.01}, {"alpha_v", 0.5}});
    add("blinn_default", "blinn", {});
    add("blinn_huge", "blinn", {{"exponent", 1e7}});
    add("composite_default", "composite", {});
    add("composite_all_lobes", "composite",
        {{"glossy_reflectance", 0.6},
         {"mirror_reflectance", 0.4},
         {"alpha", 0.3},
         {"diffuse_reflectance", 1.0}});
    add("composite_blinn_ec", "composite",
        {{"distribution", std::string("blinn")},
         {"exponent", 5.0},
         {"energy_compensation", true},
         {"fresnel", std::string("conductor")},
         {"diffuse_reflectance", 0.8}});
    add("composite_smooth_glossy", "composite",
        {{"alpha", 1e-6},
         {"mirror_reflectance", 0.5},
         {"glossy_reflectance", 0.5},
         {"diffuse_reflectance", 1.0}});
    add("composite_beckmann_rough_ior1", "composite",
        {{"distribution", std::string("beckmann")},
         {"alpha", 10.0},
         {"ior", 1.0001},
         {"diffuse_reflectance", 1.0}});
    add("velvet_default", "velvet", {});
    add("velvet_narrow", "velvet", {{"sigma", 0.15}, {"reflectance", Rgb(0.9f, 0.4f, 0.2f)}});
    return v;
}

}  // namespace facet::test
