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
// Method (the default, adaptive): each lobe is integrated over the free direction through a map
// of a parameter rectangle in which its integrand is smooth, by global adaptive cubature:
//  - the glossy single-scattering term through the half vector h in polar coordinates of the
//    stretched slope plane (rho, phi), rho = s tan(t A) (a Cauchy-like radial law at the lobe's
//    slope scale s), and the domain cut exactly at the horizon of the reflected direction:
//    rho <= rho*(phi), the positive root of (w.z = 0) (a quadratic in rho). The integrand is
//    then smooth up to the boundary (a map over the whole hemisphere of h has a kink there);
//  - the diffuse lobe and the compensation lobe f_ms through (mu, phi) with dw = dmu dphi, the
//    mu panels starting at the nodes of the albedo tables (piecewise linear in mu or sqrt(mu)),
//    one-dimensional when the integrand does not depend on phi.
// Where the glossy integrand is mirror-symmetric about the plane of incidence (isotropic lobes;
// anisotropic ones with the fixed direction in a symmetry plane, x = 0 or y = 0) only half of
// the azimuths is integrated, each cell counting twice in the value and in the error sums.
// Each cell carries a nested product rule: Gauss 7 (x) Gauss 7 inside Kronrod 15 (x) Kronrod 15.
// `value` is the sum of the Gauss values; with d the cells' signed differences Gauss - Kronrod
// (Kronrod being far more accurate, d is the Gauss value's error), `error` =
// 3 (|sum d| + sqrt(sum d^2)): the signed sum is the value's error, the root sum of squares
// covers a coincidental cancellation and the float noise of the integrand, the factor 3 the
// Kronrod error (that the estimate is never below the true error and within 10x of it is
// checked against double references in tests/core/test_reflectance.cpp). The cell with
// the largest estimate is bisected (in the direction whose nested-rule difference is larger)
// until the sum is below `tolerance`. Maps, weights and sums are in double; the BxDFs
// evaluate in float, which limits the answer to ~1e-7 relative (see the tests).
// Float directions: the BxDF sees each node's direction rounded to float, and near the mirror
// direction at grazing incidence its half vector fixed + w is a difference of nearly opposite
// vectors, so half an ulp of w moves a sharp lobe's f by up to ~1e-3 relative (GGX alpha = 1e-3
// at 85 degrees: 5e-4 per ulp of w.x). Each value is therefore rescaled by D(h) / D(h_f) (h of
// the node, h_f of the rounded direction, in double from the slope law of the distribution);
// without that the noise drove the refinement (210,600 evaluations) and put the estimate below
// the error (2.3e-6 off, estimate 1.0e-6).
// Delta lobes are added in closed form.
// Limits: sharp lobes at incidence >= ~88 degrees: the model's albedo itself depends on the float
// rounding of the fixed direction (|w| - 1 of a few 1e-8 shifts the half vector of a sharp lobe
// by ~(|w| - 1) / cos(theta), and the lobe straddles the horizon): GGX alpha = 0.01 at 89.5
// degrees reads 0.8946609 or 0.8945451 for two float roundings of the same direction, the
// double reference of the tests 0.8946610 or 0.8947767. The answer is the quadrature of the
// model for the direction as given (normalised in float); its estimate covers the quadrature
// only. Tolerances below ~1e-7 meet the float noise of the BxDFs and spend max_evaluations.
// Fixed order (int overloads, the CLI's --order): the older n x n Gauss-Legendre product rule
// through the lobe's own half-vector sampler, value Q(2n), error 2 max(|Q(n/2) - Q(n)|,
// |Q(n) - Q(2n)|); it converges slowly at grazing angles (kink at the horizon).
// Biconical reflectances use the fixed-order rule only; cones that cut the mirror direction
// converge slowly (the indicator of the cone is discontinuous): read their error estimate.
#pragma once

#include "facet/material.h"

namespace facet {

struct Reflectance {
    DVec3 value{0.0};
    DVec3 error{0.0};      // estimated absolute quadrature error of value, per channel
    long evaluations = 0;  // integrand evaluations spent
};

// Settings of the adaptive quadrature.
struct QuadratureSettings {
    double tolerance = 1e-6;            // target absolute error per channel, > 0
    long max_evaluations = 20'000'000;  // stop refining here (error then reports what is left)
};

// A cone of directions: unit axis (local frame) and half-angle in radians, in (0, pi/2].
struct Cone {
    Vec3 axis{0, 0, 1};
    float half_angle = 0.1f;
};

// Adaptive, to settings.tolerance (see the header comment).
Reflectance hemispherical_directional(const Material& m, const Vec3& wo,
                                      const QuadratureSettings& settings = {});
Reflectance directional_hemispherical(const Material& m, const Vec3& wi,
                                      const QuadratureSettings& settings = {});
Reflectance bihemispherical(const Material& m, const QuadratureSettings& settings = {});

// Fixed Gauss-Legendre order (see the header comment).
Reflectance hemispherical_directional(const Material& m, const Vec3& wo, int order);
Reflectance directional_hemispherical(const Material& m, const Vec3& wi, int order);
Reflectance bihemispherical(const Material& m, int order);
Reflectance biconical(const Material& m, const Cone& in, const Cone& out, int order = 32);

// Reflectance and transmittance of any material, transmissive ones included, for the flux
// arriving from `w` (unit, local frame: for a transmissive material its z is the shape's outward
// normal and w may lie on either side): the fractions of that flux scattered back to w's side
// and through to the other, rho(w -> same side) = int f |cos_o| dwo over that side and
// tau(w -> other side) likewise, with f in importance transport (TransportMode::Importance: a
// transmitted ray carries flux, so a non-absorbing interface has rho + tau = 1). Computed through
// the material's own sampler (sample_f, the hook every model implements) as a deterministic
// midpoint rule over its random numbers: sum of f |cos| / pdf over the strata, split by the
// side of the sampled direction. Delta lobes (whose pdf is their choice probability) on a uc
// grid of `delta_strata` with u at the centre: exact but for the strata that straddle a choice
// boundary (at most 1 / delta_strata per boundary); the other lobes on a uc x u1 x u2 grid of
// strata x n x n. `error`: |Q - Q_half| with Q_half the same rule on half the strata per axis.
struct Scattering {
    Reflectance reflected, transmitted;
};
Scattering directional_scattering(const Material& m, const Vec3& w, int n = 128, int strata = 64,
                                  int delta_strata = 1 << 16);

// Albedo int f cos dwi of a glossy lobe at cos(theta_o) = mu, averaged over phi_o for
// anisotropic lobes; one Q(order) evaluation (no error estimate). Used for Material's tables.
Rgb phi_averaged_albedo(const MicrofacetReflection& lobe, float mu, int order = 16);

}  // namespace facet
