// Shading normals from normal maps, and the bend that keeps them from producing black facets.
//
// Conventions:
//  - World space, unit vectors. `ng` is the geometric normal and `wo` the unit direction toward
//    the viewer, on the same side: dot(ng, wo) > 0 (callers turn both toward the viewer).
//  - Tangent space (Blender's Normal Map node, "Tangent Space"; glTF's normalTexture): a
//    texel c in [0, 1]^3, read linearly, is the normal m = 2c - 1 in the frame (t, b, n) with
//    t the UV map's tangent (dp/du), b = sign * cross(n, t) (along dp/dv: +Y is up, +v) and n
//    the interpolated shading normal, with the map's x and y scaled by k (glTF's
//    normalTexture.scale; 1 in Blender):
//        n' = normalize(k m.x t + k m.y b + m.z n),
//    then with a strength s != 1 (Cycles' svm_node_normal_map):
//        n'' = normalize(n + s (n' - n)).
#pragma once

#include "facet/types.h"

namespace facet::render {

// The tangent-space normal map applied to shading normal n (unit) with tangent t (not
// necessarily unit: a mesh's interpolated tangent, as Cycles uses it), bitangent sign `sign`,
// texel value c (linear RGB), strength s >= 0 and xy scale k (see conventions). Returns n
// unchanged when the texel is exactly (0.5, 0.5, 1) (m = (0, 0, 1)), when t is zero (no
// tangent: Cycles' fallback) or when the result is zero.
Vec3 apply_normal_map(const Vec3& n, const Vec3& t, float sign, const Vec3& c, float s,
                      float k = 1.f);

// Blender's Bump node (Cycles' svm_node_set_bump) on shading normal n (unit) with the UV map's
// surface derivatives dpdu, dpdv, the heights h = H(u, v), hu = H(u + step, v),
// hv = H(u, v + step), `distance` d and `strength` s >= 0: with the differentials
// dPdx = step dpdu and dPdy = step dpdv,
//     Rx = dPdy x n,  Ry = n x dPdx,  det = dPdx . Rx,
//     g = (hu - h) Rx + (hv - h) Ry,
//     n' = normalize(|det| n - d sign(det) g),
// which, as step -> 0, is the normal of the surface displaced by d H along n (Blinn 1978);
// then, for s != 1, n'' = normalize(s n' + (1 - s) n) (Cycles' strength). Returns n unchanged
// when g = 0 (flat height) or the result is zero.
Vec3 apply_bump(const Vec3& n, const Vec3& dpdu, const Vec3& dpdv, float h, float hu, float hv,
                float step, float distance, float strength = 1.f);

// A shading normal n (unit, any side) bent toward ng, within the plane of n and ng, just enough
// that the mirror reflection of wo about it leaves the geometric surface at least as steeply as
// t = min(0.9 dot(ng, wo), 0.01) (Cycles' ensure_valid_reflection, kernel/closure/bsdf_util.h:
// the same criterion; the closed form is derived in shading_normal.cpp). Returns n itself when
// it already satisfies that, ng when no bend does. The result n' then faces the viewer:
// dot(n', wo) >= (t + dot(ng, wo)) / 2 > 0, because the reflection's height
// 2 dot(n', wo) dot(n', ng) - dot(ng, wo) is at least t and dot(n', ng) is at most 1.
Vec3 valid_reflection_normal(const Vec3& ng, const Vec3& wo, const Vec3& n);

// The shading normal of a hit as the integrators use it (SurfaceHit::ns): ns (unit; an
// interpolated normal is in ng's hemisphere, a mapped one may not be) turned with ng to the side
// of wo (the unit direction toward the ray's origin), bent there by valid_reflection_normal, and
// turned back. An ns in ng's hemisphere stays there and, seen from wo's side, faces the viewer
// (valid_reflection_normal), so a Lambertian frame never sees wo below its horizon: Cycles flips
// both normals to the ray's side and applies ensure_valid_reflection.
Vec3 ray_side_valid_normal(const Vec3& ng, const Vec3& wo, const Vec3& ns);

}  // namespace facet::render
