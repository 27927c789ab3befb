// Reflectances of a material (Cohen & Wallace §2.5.3, table 2.2) by deterministic quadrature.
//
// Conventions: directions in the local frame (facet/frame.h); `wo` toward the viewer, `wi`
// toward the light. Reflectances are per RGB channel, dimensionless, in [0, 1] for a physically
// plausible material.
//  - hemispherical_directional(m, wo) = rho(2pi -> wo)  = int f(wo, wi) cos(theta_i) dwi
//    (radiance reflected toward wo under uniform unit incident radiance)
//  - directional_hemispherical(m, wi) = rho(wi -> 2pi)  = int f(wo, wi) cos(theta_o) dwo
//    (fraction of the flux arriving from wi that is reflected); equal to the former by
//    reciprocity (eq. 2.24), but computed over the outgoing directions so tests can check that.
//  - bihemispherical(m)  = rho(2pi -> 2pi) = (1/pi) int rho(wi -> 2pi) cos(theta_i) dwi
//  - biconical(m, in, out) = int_in int_out f cos_i cos_o dwo dwi / int_in cos_i dwi
//
// Method: each lobe is integrated over the free direction through its own warp of the unit
// square — the diffuse lobe through a cosine-weighted polar map, the glossy lobe through its
// own half-vector sampler — by an n x n Gauss-Legendre product rule. Sharp lobes
// (Blinn kappa = 1e7) are then resolved exactly as well as broad ones, because in the
// sampler's coordinates the integrand is smooth. Delta lobes are added in closed form.
// `error` is an a-posteriori estimate, 2 max(|Q(n/2) - Q(n)|, |Q(n) - Q(2n)|) where `value` is
// Q(2n): one difference alone can vanish by coincidence, because the integrand has kinks where
// the half-vector map crosses the horizon and Gauss-Legendre then converges irregularly. Biconical
// reflectances whose cones cut the mirror direction converge slowly (the indicator of the cone
// is discontinuous): read their error estimate.
#pragma once

#include "facet/material.h"

namespace facet {

struct Reflectance {
    Rgb value{0.f};
    Rgb error{0.f};  // estimated absolute quadrature error of value, per channel
};

// A cone of directions: unit axis (local frame) and half-angle in radians, in (0, pi/2].
struct Cone {
    Vec3 axis{0, 0, 1};
    float half_angle = 0.1f;
};

Reflectance hemispherical_directional(const Material& m, const Vec3& wo, int order = 32);
Reflectance directional_hemispherical(const Material& m, const Vec3& wi, int order = 32);
Reflectance bihemispherical(const Material& m, int order = 16);
Reflectance biconical(const Material& m, const Cone& in, const Cone& out, int order = 32);

// Albedo int f cos dwi of a glossy lobe at cos(theta_o) = mu, averaged over phi_o for
// anisotropic lobes; one Q(order) evaluation (no error estimate). Used for Material's tables.
Rgb phi_averaged_albedo(const MicrofacetReflection& lobe, float mu, int order = 16);

}  // namespace facet
