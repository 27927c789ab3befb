// One-dimensional albedo tables over sqrt(mu), shared by the energy-compensated conductor
// (MicrofacetReflection, microfacet.cpp) and the energy-compensated rough dielectric
// (DielectricBxDF, dielectric.cpp).
//
// Conventions: n values e[k] at the nodes mu_k = (k / (n - 1))^2 (uniform in s = sqrt(mu)), read
// by linear interpolation in s. Tables are uniform in sqrt(mu) because albedos change fastest
// near grazing (e.g. GGX alpha = 1: 0.85 at mu = 0.05, 0.993 at mu = 1e-3).
#pragma once

#include <algorithm>
#include <cmath>

#include "facet/types.h"

namespace facet {

// Compensation (conductor or dielectric) is skipped when the lobe misses less energy than this on
// average: the table's quadrature error (1e-5 .. 1e-3, worst at grazing mu) would then be of the
// order of what f_ms restores, and 1 / (1 - E_avg) amplifies it (measured: a compensated Blinn
// kappa = 1e7 lobe, which loses ~1e-3, reflected 1.02 at 89.9 deg with a 1e-5 threshold).
inline constexpr float kMinMissingEnergy = 2e-3f;

// E(mu) of the interpolant, mu in [0, 1] (clamped).
inline float sqrt_mu_table_lookup(const float* e, int n, float mu) {
    float x = std::sqrt(clamp_unit(mu)) * float(n - 1);
    int i = std::min(int(x), n - 2);
    float t = x - float(i);
    return e[i] + t * (e[i + 1] - e[i]);
}

// E_avg = 2 int_0^1 E(mu) mu dmu of the interpolant, exactly (Kulla & Conty 2017, eq. 15, so
// that a compensation lobe built from the table integrates exactly to 1 - E): with s = sqrt(mu),
// E = A + B s on each interval and 2 int E mu dmu = 4 int (A s^3 + B s^4) ds. Clamped to 1.
inline float sqrt_mu_table_average(const float* e, int n) {
    double h = 1.0 / (n - 1), avg = 0.0;
    for (int k = 0; k + 1 < n; ++k) {
        double s0 = k * h, s1 = (k + 1) * h;
        double b = (double(e[k + 1]) - double(e[k])) / h, a = double(e[k]) - b * s0;
        avg += a * (std::pow(s1, 4) - std::pow(s0, 4)) / 4.0 +
               b * (std::pow(s1, 5) - std::pow(s0, 5)) / 5.0;
    }
    return float(std::fmin(4.0 * avg, 1.0));
}

}  // namespace facet
