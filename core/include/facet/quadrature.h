// Gauss-Legendre quadrature rules, the deterministic integrator behind the reflectance functions.
//
// Convention: nodes and weights for the interval [0, 1] (weights sum to 1). A rule with n nodes
// integrates polynomials of degree 2n-1 exactly.
#pragma once

#include <span>
#include <vector>

namespace facet {

struct QuadratureRule {
    std::vector<double> nodes;    // in (0, 1), increasing
    std::vector<double> weights;  // positive, sum to 1
};

// The n-point Gauss-Legendre rule on [0, 1] (n >= 1), computed by Newton iteration on the
// Legendre recurrence to full double precision. Cached: repeated calls are cheap.
const QuadratureRule& gauss_legendre(int n);

}  // namespace facet
