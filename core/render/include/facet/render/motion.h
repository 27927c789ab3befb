// Motion blur: the time of a ray over the shutter, the shutter curve that time is drawn from,
// and the interpolation of transforms and cameras between motion steps (scenes/FORMAT.md,
// "Motion blur").
//
// Conventions:
//  - Time is normalised to the shutter: tau = 0 when the shutter opens, tau = 1 when it closes.
//    A motion with N >= 2 steps has step i at tau = i / (N - 1) (uniform steps, as Embree's
//    time steps and Cycles' motion steps are); between steps the motion is interpolated, outside
//    [0, 1] never asked for.
//  - Transforms are interpolated decomposed, as Cycles (DecomposedTransform) and Embree's
//    quaternion instances (RTCQuaternionDecomposition) do: M = T R S with T the translation,
//    R a rotation (unit quaternion) and S upper triangular (scale and shear); T and S are
//    interpolated linearly, R by spherical linear interpolation along the shorter arc. A pure
//    translation therefore moves at constant speed, and a rotation turns at constant angular
//    speed without shrinking the object half-way.
//  - The camera is interpolated the same way: its position linearly, its orientation (the
//    frame right, true up, -forward) by slerp; the lens, field of view and film stay those of
//    the first step.
//  - Ray time is drawn per path from the shutter curve (ShutterCurve::sample, a random-number
//    argument), and every ray of the path (camera, continuation and shadow rays) carries it.
#pragma once

#include <glm/gtc/quaternion.hpp>
#include <glm/mat3x3.hpp>
#include <glm/mat4x4.hpp>

#include <span>
#include <vector>

#include "facet/render/camera.h"

namespace facet::render {

// An affine transform as M = T R S (conventions): translation, rotation, and the upper
// triangular scale/shear matrix (columns as glm stores them).
struct DecomposedTransform {
    glm::dvec3 translation{0.0};
    glm::dquat rotation{1.0, 0.0, 0.0, 0.0};
    glm::dmat3 scale{1.0};

    // The decomposition of an invertible affine M: R from the Gram-Schmidt orthonormalisation
    // of M's linear columns (a QR decomposition, L = R S with S's diagonal positive except for
    // a mirroring M, whose last diagonal entry carries the sign so that R stays a rotation).
    static DecomposedTransform decompose(const glm::dmat4& m);
    glm::dmat4 matrix() const;
};

// The transform at normalised time tau in [0, 1] of a motion with steps.size() >= 1 uniform
// steps (conventions); one step is the static transform.
glm::dmat4 interpolate_motion(std::span<const DecomposedTransform> steps, double tau);

// The density of the ray time over the shutter (Blender's Shutter Curve): piecewise constant
// on n equal cells of [0, 1) with the given non-negative weights (not all zero); no weights is
// the uniform density (a box shutter). Sampled by inverting its cumulative distribution.
class ShutterCurve {
  public:
    ShutterCurve() = default;
    // Weights: finite and >= 0, not all zero (checked by the caller, which names the place).
    explicit ShutterCurve(std::span<const double> weights);
    // The time tau in [0, 1) for random number u in [0, 1): uniform within the chosen cell.
    float sample(float u) const;
    // The density at tau (per unit tau; integrates to 1 over [0, 1)).
    float pdf(float tau) const;
    bool uniform() const { return m_cdf.empty(); }

  private:
    std::vector<float> m_pdf;  // per cell, normalised
    std::vector<float> m_cdf;  // n + 1 entries, m_cdf[0] = 0, m_cdf[n] = 1
};

// A camera's motion: its steps (each built by Camera::make) at uniform times (conventions).
struct CameraMotion {
    std::vector<Camera> steps;  // empty: the camera does not move
    bool moves() const { return steps.size() >= 2; }
    // The camera at time tau in [0, 1]: position lerp, orientation slerp (conventions).
    Camera at(float tau) const;
};

}  // namespace facet::render
