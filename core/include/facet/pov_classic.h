// POV-Ray 3.7's classic finish (diffuse, brilliance, phong, specular, metallic, reflection)
// mapped to the core's physically based lobes: what `global_settings { brdf_convert_classic
// on }` in povray-facet builds for every classic finish (docs/povray.md, "Classic finishes").
//
// Conventions: POV-Ray shades a light of colour C with its classic terms as radiance, per unit
// C (trace.cpp, ComputeDiffuseColour / ComputePhongColour / ComputeSpecularColour):
//   diffuse   d cos(theta_i)^brilliance * pigment
//   phong     p (r . wi)^s             r the mirror direction of wo (phong_size s)
//   specular  k (n . h)^kappa          h the half vector, kappa = 1 / roughness
// A BRDF f gives pi f cos(theta_i) per unit C in that scale (the bridge's facet_pov::shade),
// so Lambert rho = d is exact. POV-Ray's `reflection { r_min r_max fresnel falloff f }` weighs
// its mirror ray by r_min + (r_max - r_min) w(theta_o) with w the unpolarised Fresnel
// reflectance of the interior's IOR (fresnel on) or (1 - cos theta_o)^f.
// The result is a sum of lobes, each the core's own model:
//   lambert(rho) times the pigment, one blinn lobe (Cohen & Wallace eq. 2.38, Fresnel none)
//   times `reflectance`, and mirror lobes (constant, dielectric Fresnel or Schlick) times
//   their colours; `metallic` tints the blinn lobe by POV-Ray's own formula (metallic_tint).
// Energy: the sum reflects at most what it receives for any pigment <= 1
// (max over theta_o of the blinn and mirror albedos, plus rho, is <= 1; see convert_classic).
#pragma once

#include <array>
#include <compare>
#include <optional>
#include <string>
#include <vector>

#include "facet/material.h"

namespace facet::pov {

// A classic finish as POV-Ray stores it (frame.h FINISH; `Roughness` there is 1 / roughness).
struct ClassicFinish {
    double diffuse = 0.6, diffuse_back = 0.0, brilliance = 1.0;
    double phong = 0.0, phong_size = 40.0;
    double specular = 0.0, specular_exponent = 20.0;  // 1 / roughness
    double metallic = 0.0;                            // highlights' tint
    std::array<double, 3> reflection_min{0, 0, 0}, reflection_max{0, 0, 0};
    bool reflection_fresnel = false;
    double reflection_falloff = 1.0, reflection_exponent = 1.0;
    double ior = 1.0;  // the interior's IOR over the atmosphere's (1: no interior given)
    double irid = 0.0, crand = 0.0;
    bool subsurface = false;

    auto operator<=>(const ClassicFinish&) const = default;  // equal finishes share a conversion
};

// What a converted finish is made of. A mirror lobe is `colour` times w(theta_o).
struct ClassicMirror {
    enum class Weight { Constant, Dielectric, Schlick } weight = Weight::Constant;
    std::array<double, 3> colour{0, 0, 0};
    double ior = 1.5;  // Dielectric
    double f0 = 0.0;   // Schlick: f0 + (1 - f0)(1 - cos)^5
};

// A note for the conversion's summary: `kind` names the approximation or the dropped term
// (the same short text for every finish, so the summary can count them).
struct ClassicNote {
    enum class Level { Approximated, Reported } level;
    std::string kind;
};

struct ClassicConversion {
    bool converted = true;  // false: the finish stays classic (see notes)
    double diffuse = 0.0;   // Lambert rho, times the pigment
    double glossy_exponent = 0.0, glossy_reflectance = 0.0;  // blinn; reflectance 0: none
    double metallic = 0.0;  // the blinn lobe's tint, metallic_tint()
    std::vector<ClassicMirror> mirrors;
    // How the blinn lobe reflects other objects: with a mirror lobe, its albedo at theta_o rides
    // on the mirror ray (glossy_folded: sharp, no extra ray); without one, glossy_samples rays
    // at a camera hit (1 for an albedo >= 10% at normal incidence, else 0).
    bool glossy_folded = false;
    int glossy_samples = 0;
    // The blinn and mirror lobes' albedo (max over channels) at cos(theta_o) = k / (n - 1),
    // n = kAlbedoNodes: the diffuse lobe is scaled by min(1, (1 - S) / rho) at each view so
    // that the sum never exceeds 1 (linear in cos theta_o between nodes).
    static constexpr int kAlbedoNodes = 17;
    std::array<double, kAlbedoNodes> specular_albedo{};
    std::array<double, kAlbedoNodes> glossy_albedo{};  // the blinn lobe's alone
    std::vector<ClassicNote> notes;

    // The diffuse rho in effect at cos(theta_o) = mu (see specular_albedo; the larger of the
    // two neighbouring nodes, an upper bound of S where it is monotone between them).
    double diffuse_at(double mu) const;
    // The blinn lobe's albedo at cos(theta_o) = mu (linear between the nodes).
    double glossy_albedo_at(double mu) const;
};

ClassicConversion convert_classic(const ClassicFinish& finish);

// The conversion's lobes as core materials, each of unit weight: `diffuse` is Lambert rho = 1
// (times diffuse_at(mu) and the pigment), `glossy` the blinn lobe at its reflectance (times
// metallic_tint), `mirrors[i]` the mirror of conversion.mirrors[i] with weight 1 (times its
// colour). The reflection of the whole is their sum.
struct ClassicLobes {
    Material diffuse;
    std::optional<Material> glossy;
    std::vector<Material> mirrors;
};
ClassicLobes classic_lobes(const ClassicConversion& conversion);

// POV-Ray's `metallic` tint of a highlight lit from cos(theta_i) = cos_i:
// 1 + m (1 - F(x)) (pigment - 1), x = theta_i / (pi/2), with POV-Ray's empirical
// F(x) = 0.014567225 / (x - 1.12)^2 - 0.011612903 clamped to [0, 1] (trace.cpp).
double metallic_tint(double metallic, double pigment, double cos_i);

// The blinn exponent whose lobe (energy-matched) is closest to POV-Ray's phong lobe of size s,
// seen at normal incidence: minimises classic_lobe_error over the exponent.
double fit_phong_exponent(double phong_size);

// Relative L1 difference of the two lobes' reflected radiance over the incident directions,
// int |L_pov - L_blinn| dwi / int L_pov dwi, for a view at theta_o (radians) in the plane
// x-z. `phong` true: POV-Ray's phong lobe of size s; false: its specular lobe of exponent s.
// The blinn lobe has exponent kappa and the reflectance that matches POV-Ray's albedo at
// normal incidence (as convert_classic sets it).
double classic_lobe_error(bool phong, double s, double kappa, double theta_o);

// POV-Ray's albedo of its phong (or specular) lobe per unit height at normal incidence:
// (1/pi) int (r.wi)^s dwi = 2 / (s + 1), (1/pi) int (n.h)^kappa dwi = 8 (1 - 2^(-(kappa+2)/2)) /
// (kappa + 2).
double pov_lobe_albedo(bool phong, double s);

}  // namespace facet::pov
