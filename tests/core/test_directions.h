// Helpers shared by the BSDF tests of tests/core: directions by angles in degrees and the
// Monte Carlo scale of the stress runs. Test-only code (not part of facet::core).
#pragma once

#include <cmath>
#include <cstdlib>

#include "facet/types.h"

namespace facet::test {

// Direction at polar angle theta (degrees from +z; > 90 is below / inside) and azimuth phi,
// computed in double and rounded once.
inline Vec3 dir(double theta_deg, double phi_deg) {
    const double t = theta_deg * kPiD / 180.0, p = phi_deg * kPiD / 180.0;
    return Vec3(
        glm::normalize(DVec3(std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t))));
}

// FACET_STRESS_SCALE (the Debug + sanitizer runs set 0.1); 1 when unset.
inline double stress_scale() {
    const char* s = std::getenv("FACET_STRESS_SCALE");
    return s ? std::atof(s) : 1.0;
}

}  // namespace facet::test
