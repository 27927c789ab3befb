// Normal maps and the valid-reflection bend of shading normals (facet/render/shading_normal.h).
#include "facet/render/shading_normal.h"

#include <algorithm>
#include <cmath>

#include "facet/render/scene.h"

namespace facet::render {

namespace {

Vec3 normalized_or_zero(const Vec3& v) {
    const float l = glm::length(v);
    return l > 0.f && std::isfinite(l) ? v / l : Vec3(0.f);
}

}  // namespace

Vec3 apply_normal_map(const Vec3& n, const Vec3& t, float sign, const Vec3& c, float s, float k) {
    Vec3 m = 2.f * (c - Vec3(0.5f));
    m.x *= k;
    m.y *= k;
    if (m == Vec3(0.f, 0.f, 1.f) || t == Vec3(0.f)) return n;
    const Vec3 b = sign * glm::cross(n, t);
    Vec3 mapped = normalized_or_zero(m.x * t + m.y * b + m.z * n);
    if (mapped == Vec3(0.f)) return n;
    if (s != 1.f) mapped = normalized_or_zero(n + s * (mapped - n));
    return mapped == Vec3(0.f) ? n : mapped;
}

Vec3 valid_reflection_normal(const Vec3& ng, const Vec3& wo, const Vec3& n) {
    const float iz = glm::dot(ng, wo);
    // The reflected direction may be as shallow as the incoming one, but not below 0.01.
    const float t = std::min(0.9f * iz, 0.01f);
    const Vec3 r = 2.f * glm::dot(n, wo) * n - wo;
    if (glm::dot(ng, r) >= t) return n;
    // Look for n' = x X + z ng (x, z >= 0, x^2 + z^2 = 1) in the plane of ng and n, X the unit
    // part of n across ng. With ix = wo.X (wo's component out of that plane does not change
    // n'.wo), the reflection's height R.ng = 2 (x ix + z iz) z - iz must equal t. Writing
    // w = z^2 and squaring 2 x z ix = t + iz - 2 w iz gives
    //     4 a w^2 - 4 (a + t iz) w + (t + iz)^2 = 0,   a = ix^2 + iz^2,
    // whose discriminant reduces to 16 ix^2 (a - t^2):
    //     w = ((a + t iz) +- |ix| sqrt(a - t^2)) / (2 a).
    // Squaring admits a root of the wrong sign of x; each root is checked by its R.ng, and of
    // the valid ones the one nearest n (the least bend) is kept.
    // In double: the roots lose float precision where a - t^2 nearly cancels (grazing views),
    // and this runs only on mapped normals.
    const glm::dvec3 gd(ng), nd(n), wd(wo);
    glm::dvec3 x = nd - glm::dot(nd, gd) * gd;
    const double xl = glm::length(x);
    if (!(xl > 0.0)) return ng;
    x /= xl;
    const double izd = glm::dot(wd, gd), td = double(t);
    const double ix = glm::dot(wd, x);
    const double a = ix * ix + izd * izd;
    if (!(a > 0.0)) return ng;
    const double root = std::fabs(ix) * std::sqrt(std::max(0.0, a - td * td));
    Vec3 best = ng;
    double best_cos = -2.0;
    for (const double sg : {1.0, -1.0}) {
        const double w = (a + td * izd + sg * root) / (2.0 * a);
        // Cycles' bounds on z^2: a normal in (not on) the geometric surface's hemisphere.
        if (!(w > 1e-5 && w <= 1.0 + 1e-5)) continue;
        const double z = std::sqrt(std::min(w, 1.0)), xs = std::sqrt(std::max(0.0, 1.0 - w));
        const double rz = 2.0 * (xs * ix + z * izd) * z - izd;
        // Tolerance: round-off of the quadratic, far below the gap to a spurious root.
        if (!(std::fabs(rz - td) <= 1e-6)) continue;
        const glm::dvec3 cand = xs * x + z * gd;
        const double c = glm::dot(cand, nd);
        if (c > best_cos) {
            best = normalized_or_zero(Vec3(cand));
            best_cos = c;
        }
    }
    return best == Vec3(0.f) ? ng : best;
}

Vec3 ray_side_valid_normal(const Vec3& ng, const Vec3& wo, const Vec3& ns) {
    // On the viewer's side (make_shading turns both normals toward the viewer the same way).
    const bool front = glm::dot(ng, wo) > 0.f;
    const Vec3 bent = valid_reflection_normal(front ? ng : -ng, wo, front ? ns : -ns);
    return front ? bent : -bent;
}

Vec3 apply_bump(const Vec3& n, const Vec3& dpdu, const Vec3& dpdv, float h, float hu, float hv,
                float step, float distance, float strength) {
    const Vec3 rx = glm::cross(step * dpdv, n), ry = glm::cross(n, step * dpdu);
    const Vec3 grad = (hu - h) * rx + (hv - h) * ry;
    if (grad == Vec3(0.f)) return n;
    const float det = glm::dot(step * dpdu, rx);
    Vec3 b = normalized_or_zero(std::fabs(det) * n - distance * std::copysign(1.f, det) * grad);
    if (b == Vec3(0.f)) return n;
    if (strength != 1.f) b = normalized_or_zero(strength * b + (1.f - strength) * n);
    return b == Vec3(0.f) ? n : b;
}

void Scene::shade_normal(SurfaceHit& hit, const Vec3& wo) const {
    const TexturedMaterial& tm = m_textured[std::size_t(hit.textured)];
    if (!tm.normal_map && !tm.bump) return;
    Vec3 n = hit.ns;
    if (tm.normal_map) {
        const Vec3 c = tm.normal_map->eval(hit.uv);
        n = apply_normal_map(n, hit.dpdu, hit.tangent_sign, c, tm.normal_strength,
                             tm.normal_xy_scale);
    }
    if (tm.bump) {
        // Forward differences in u and v (as Cycles' bump takes them at P + dP/dx, dP/dy).
        const float d = tm.bump_step;
        const float h = tm.bump->eval(hit.uv).r;
        const float hu = tm.bump->eval(hit.uv + Vec2(d, 0.f)).r;
        const float hv = tm.bump->eval(hit.uv + Vec2(0.f, d)).r;
        n = apply_bump(n, hit.dpdu_uv, hit.dpdv_uv, h, hu, hv, d, tm.bump_distance,
                       tm.bump_strength);
    }
    if (n == hit.ns) return;  // unchanged: keep the normal bit for bit
    hit.ns = ray_side_valid_normal(hit.ng, wo, n);
}

}  // namespace facet::render
