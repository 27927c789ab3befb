// Local shading frame and the angle helpers every BxDF uses.
//
// Conventions (pbrt-v4 style; docs/architecture.md, "Conventions (every BxDF)"):
//  - In the local frame z is the shading normal n, x and y are the tangents (x = "u" direction
//    of anisotropic models, e.g. the brushing direction of brushed aluminium).
//  - Directions are unit vectors pointing *away* from the surface: `wo` toward the viewer,
//    `wi` toward the light. A direction is above the surface when z > 0.
//  - theta is measured from n, phi from the x axis (Cohen & Wallace fig. 2.4).
#pragma once

#include "facet/types.h"

namespace facet {

inline float cos_theta(const Vec3& w) {
    return w.z;
}
inline float cos2_theta(const Vec3& w) {
    return w.z * w.z;
}
inline float abs_cos_theta(const Vec3& w) {
    return std::fabs(w.z);
}
// sin^2 from the tangential components: no 1 - cos^2 cancellation near the normal.
inline float sin2_theta(const Vec3& w) {
    return w.x * w.x + w.y * w.y;
}
inline float sin_theta(const Vec3& w) {
    return std::sqrt(sin2_theta(w));
}
inline float tan2_theta(const Vec3& w) {
    return sin2_theta(w) / cos2_theta(w);
}

// cos/sin of phi; at the pole (sin theta = 0) phi is undefined and we return phi = 0.
inline float cos_phi(const Vec3& w) {
    float s = sin_theta(w);
    return s == 0.f ? 1.f : glm::clamp(w.x / s, -1.f, 1.f);
}
inline float sin_phi(const Vec3& w) {
    float s = sin_theta(w);
    return s == 0.f ? 0.f : glm::clamp(w.y / s, -1.f, 1.f);
}

inline bool same_hemisphere(const Vec3& a, const Vec3& b) {
    return a.z * b.z > 0.f;
}

// Mirror direction of w about n (Cohen & Wallace eq. 2.27): both point away from the surface.
inline Vec3 reflect(const Vec3& w, const Vec3& n) {
    return -w + 2.f * glm::dot(w, n) * n;
}

// Unit direction from spherical angles (radians) in the local frame.
inline Vec3 spherical_direction(float theta, float phi) {
    float st = std::sin(theta);
    return {st * std::cos(phi), st * std::sin(phi), std::cos(theta)};
}

// Orthonormal basis around a unit normal (Duff et al. 2017, "Building an Orthonormal Basis,
// Revisited"): continuous except at n.z = -0 and free of the n.z ~ -1 precision loss of Frisvad's.
struct Frame {
    Vec3 x{1, 0, 0}, y{0, 1, 0}, z{0, 0, 1};

    static Frame from_z(const Vec3& n) {
        float sign = std::copysign(1.f, n.z);
        float a = -1.f / (sign + n.z);
        float b = n.x * n.y * a;
        Frame f;
        f.x = Vec3(1.f + sign * n.x * n.x * a, sign * b, -sign * n.x);
        f.y = Vec3(b, sign + n.y * n.y * a, -n.y);
        f.z = n;
        return f;
    }
    // Frame from a normal and a tangent hint (e.g. a brushing direction); the tangent is
    // Gram-Schmidt orthogonalised against n. Falls back to from_z if the hint is parallel to n.
    static Frame from_z_x(const Vec3& n, const Vec3& tangent_hint) {
        Vec3 t = tangent_hint - glm::dot(tangent_hint, n) * n;
        float len2 = glm::dot(t, t);
        // Relative to the hint's length: a hint of any scale (a scene in km or in nm) that is
        // not within ~1e-6 rad of n gives a tangent; a zero or parallel hint falls back.
        if (!(len2 > 1e-12f * glm::dot(tangent_hint, tangent_hint))) return from_z(n);
        Frame f;
        f.z = n;
        f.x = t / std::sqrt(len2);
        f.y = glm::cross(n, f.x);
        return f;
    }
    // Always inlined: a few multiply-adds that the renderer's kernels call at every vertex. Left
    // to itself GCC stopped inlining them into the grown path kernel (out-of-line calls cost 1.7%
    // of the Cornell box's instructions: docs/performance.md, "Paying only for what is used").
    [[gnu::always_inline]] Vec3 to_local(const Vec3& v) const {
        return {glm::dot(v, x), glm::dot(v, y), glm::dot(v, z)};
    }
    [[gnu::always_inline]] Vec3 from_local(const Vec3& v) const {
        return v.x * x + v.y * y + v.z * z;
    }
};

}  // namespace facet
