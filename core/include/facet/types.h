// Basic numeric types and constants shared by every Facet module.
//
// Conventions (hold for the whole core):
//  - Vectors are GLM single-precision vectors; colours are linear RGB stored in a Vec3 (`Rgb`).
//  - Angles in radians inside the core; the CLI and scene formats speak degrees.
//  - Everything here is header-only and free of third-party types other than GLM.
#pragma once

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

namespace facet {

using Vec2 = glm::vec2;
using Vec3 = glm::vec3;
using Rgb = glm::vec3;  // linear RGB radiometric triple
using DVec3 = glm::dvec3;

inline constexpr float kPi = 3.14159265358979323846f;
inline constexpr float kInvPi = 0.31830988618379067154f;
inline constexpr float kInv2Pi = 0.15915494309189533577f;
inline constexpr float kInv4Pi = 0.07957747154594766788f;
inline constexpr float kPiOver2 = 1.57079632679489661923f;
inline constexpr double kPiD = 3.14159265358979323846;
inline constexpr float kInfinity = std::numeric_limits<float>::infinity();

// Largest float strictly below 1: the upper end for samples in [0, 1).
inline constexpr float kOneMinusEpsilon = 0x1.fffffep-1f;

// Rec. 709 luminance, used to turn RGB albedos into scalar lobe-selection weights.
inline float luminance(const Rgb& c) {
    return 0.2126f * c.r + 0.7152f * c.g + 0.0722f * c.b;
}

inline float max_component(const Rgb& c) {
    return std::fmax(c.r, std::fmax(c.g, c.b));
}

inline bool is_finite(const Rgb& c) {
    return std::isfinite(c.r) && std::isfinite(c.g) && std::isfinite(c.b);
}

inline float sqr(float x) {
    return x * x;
}
inline double sqr(double x) {
    return x * x;
}

// Clamp to [0, 1] mapping NaN to 0: safe to turn into a table index (std::clamp and
// glm::clamp pass NaN through, and int(NaN) is undefined behaviour).
inline float clamp_unit(float x) {
    return x > 0.f ? (x < 1.f ? x : 1.f) : 0.f;
}

// max(x, 0) mapping NaN to 0, like std::fmax(x, 0.f) but one instruction (GCC calls fmaxf
// for std::fmax; the only difference is that -0 becomes +0).
inline float positive_part(float x) {
    return x > 0.f ? x : 0.f;
}

// sqrt that clamps tiny negative round-off to 0 instead of returning NaN.
inline float safe_sqrt(float x) {
    return std::sqrt(positive_part(x));
}
inline double safe_sqrt(double x) {
    return std::sqrt(std::fmax(0.0, x));
}

}  // namespace facet
