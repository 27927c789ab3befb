// Double-precision reference for rho(v -> 2pi) = int f(w, v) cos(theta_w) dw (test-only), by a
// parametrisation independent of core/src/reflectance.cpp: the half vector h in spherical
// coordinates (theta, phi) about the normal, w = reflect(v, h), dw = 4 (v.h) sin(theta) dtheta
// dphi (Walter et al. 2007 eq. 14). The reflected w is above the horizon iff
//   w.z = 2 (v.h) h.z - v.z = B sin(2 theta) + v.z cos(2 theta) > 0,  B = v.x cos phi + v.y sin
//   phi,
// i.e. theta < theta*(phi) = atan2(v.z, -B) / 2, so the inner integral stops exactly at the
// horizon. Nested adaptive Gauss-Kronrod (Boost.Math) in double: outer over phi, split where B
// changes sign; inner over theta, split near the peak at theta = 0 (multiples of the lobe
// width) so that sharp lobes are found.
#pragma once

#include <boost/math/quadrature/gauss_kronrod.hpp>

#include <algorithm>
#include <cmath>
#include <vector>

#include "facet/types.h"

namespace facet::ref {

// g(w) = f(w, v) cos(theta_w) as a double, w a unit double direction above the horizon.
// width: the lobe's angular width (equivalent alpha), for the inner split points.
template <class G>
double directional_albedo(const G& g, const DVec3& v_in, double width, double tol = 1e-12,
                          int depth = 12) {
    using GK = boost::math::quadrature::gauss_kronrod<double, 31>;
    const DVec3 v = glm::normalize(v_in);
    auto inner = [&](double phi) {
        const double cp = std::cos(phi), sp = std::sin(phi);
        const double big_b = v.x * cp + v.y * sp;
        const double theta_star = 0.5 * std::atan2(v.z, -big_b);
        auto integrand = [&](double theta) {
            const double st = std::sin(theta), ct = std::cos(theta);
            const DVec3 h(st * cp, st * sp, ct);
            const double vh = glm::dot(v, h);
            const DVec3 w = 2.0 * vh * h - v;
            if (!(w.z > 0.0 && vh > 0.0)) return 0.0;
            return g(w) * 4.0 * vh * st;
        };
        std::vector<double> cuts{0.0};
        for (double k : {1.0, 3.0, 10.0, 30.0})
            if (k * width < theta_star) cuts.push_back(k * width);
        cuts.push_back(theta_star);
        double sum = 0.0;
        for (size_t i = 0; i + 1 < cuts.size(); ++i)
            sum += GK::integrate(integrand, cuts[i], cuts[i + 1], depth, tol);
        return sum;
    };
    const double phi0 = std::atan2(v.y, v.x);
    double sum = 0.0;
    for (int q = 0; q < 4; ++q)
        sum += GK::integrate(inner, phi0 + (q - 1) * 0.5 * kPiD, phi0 + q * 0.5 * kPiD, depth, tol);
    return sum;
}

}  // namespace facet::ref
