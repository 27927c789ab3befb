// The Blinn (Student-t) formulas of facet/microfacet.h written once, for the scalar model
// (microfacet.cpp) and the vectorised batch (microfacet_batch.cpp). The math functions are a
// parameter M (static exp, log, log1p, max): the scalar path instantiates them with the libm
// functions (StdMath: its results are the model's own, bit for bit), the batch with
// branch-free polynomials that vectorise. Each function is the arithmetic only; the callers
// apply the guards (horizon, underflow, r = 0), the scalar path by branching, the batch by
// selecting.
#pragma once

#include <algorithm>
#include <cmath>

#include "facet/microfacet.h"

namespace facet::formulas {

// The libm functions (float overloads).
struct StdMath {
    static float exp(float x) { return std::exp(x); }
    static float log(float x) { return std::log(x); }
    static float log1p(float x) { return std::log1p(x); }
    static float max(float a, float b) { return std::fmax(a, b); }
};

// Blinn D of a unit normal with cos2 = wm.z^2 and t = tan^2 of its stretched angle
// ((wm.x / ax)^2 + (wm.y / ay)^2) / cos2: D = nu / (2 pi) cos^-4 (1 + t)^(-(nu + 2) / 2), the
// power in log space (log1p keeps kappa = 1e7 exact near the peak). log_norm = log(nu / (2 pi)),
// half_nu_p2 = (nu + 2) / 2. Valid for wm.z > 0 and t < inf (0 otherwise).
template <class M>
inline float blinn_d(float log_norm, float half_nu_p2, float t, float cos2) {
    return M::exp(log_norm - half_nu_p2 * M::log1p(t) - 2.f * M::log(cos2));
}

// The rho table of the Blinn Lambda (facet/microfacet.h) at v = mu / (mu + s), Catmull-Rom on
// the uniform v grid with a ghost node at each end. v is clamped to [0, 1] (NaN to 0) so that
// the read stays inside the table for any input: a no-op for the scalar path's v, needed by the
// batch, which evaluates lanes that its guards discard afterwards.
inline float blinn_rho(const float* table, float v) {
    v = v > 0.f ? v : 0.f;
    v = v < 1.f ? v : 1.f;
    constexpr int n = MicrofacetDistribution::kBlinnTableSize;
    float x = v * float(n - 1);
    // i = min(int(x), n - 2), with the minimum taken in float (the same i: x <= n - 1), which
    // lets the batch's four table reads vectorise as gathers.
    float xc = x < float(n - 2) ? x : float(n - 2);
    int i = int(xc);
    float u = x - float(i);
    float p0 = table[i], p1 = table[i + 1], p2 = table[i + 2], p3 = table[i + 3];
    return p1 + 0.5f * u *
                    ((p2 - p0) +
                     u * ((2.f * p0 - 5.f * p1 + 4.f * p2 - p3) + u * (3.f * (p1 - p2) + p3 - p0)));
}

// Blinn Lambda = first(mu) rho(v) with first = k exp(-e) / mu, e = (nu - 1) / 2 log(1 + mu^2)
// (facet/microfacet.h): the exponent, the table's argument v and Lambda from them. mu = z / r
// with z = |w.z| and r = |(ax w.x, ay w.y)|; half_nu_m1 = (nu - 1) / 2, k = c / (nu - 1),
// s = sqrt(2 / nu), rho = blinn_rho(table, v). Valid for z > 0, r > 0 and e below the
// underflow bound (Lambda = inf, 0, 0 there).
template <class M>
inline float blinn_lambda_exponent(float half_nu_m1, float mu) {
    return half_nu_m1 * M::log1p(mu * mu);
}
inline float blinn_lambda_v(float s, float z, float r) {
    return z / (z + s * r);
}
template <class M>
inline float blinn_lambda(float k, float e, float mu, float rho) {
    float l = k * M::exp(-e) / mu * rho;
    return l < kInfinity ? M::max(l, 0.f) : kInfinity;
}

}  // namespace facet::formulas
