// Light types of emissive triangle shapes (light.h "Structure"): any set of triangles
// (emissive_triangles), and two triangles that form a parallelogram (emissive_parallelogram: a
// quad, the usual area light). Both are built by Light::area_triangles.
//
// Sampling (light.h conventions): uniformly by area, converted to solid angle: pdf = r^2 / (A
// |cos theta_l|) (area_to_solid_angle_pdf). A set of triangles picks a triangle in proportion
// to its area, then a point in it; a parallelogram maps u straight onto it, p = o + u.x e1 +
// u.y e2: the same density, no triangle search, and u's 2D stratification carries over to the
// whole light. One-sided: the front is the counter-clockwise winding's normal. Power: pi A L.
#include <algorithm>

#include "facet/cdf_search.h"
#include "sampling.h"

namespace facet::render {

namespace {

// Two triangles (a, b, c) and (d, e, f) sharing exactly two vertices s0, s1 (the diagonal) form
// a parallelogram when the diagonals bisect each other: o0 + o1 = s0 + s1 for the two other
// vertices. Tolerance: 1e-6 of the coordinates' magnitude (a few float ulps), so sampled points
// stay on the traced triangles to float round-off. Both triangles must face the same way.
// Fills q's geometry and returns true when they do.
bool detect_parallelogram(const EmissiveTriangles& t, EmissiveParallelogram& q) {
    const Vec3* t0 = &t.tri[0];
    const Vec3* t1 = &t.tri[3];
    int shared0[2] = {-1, -1}, shared1[2] = {-1, -1}, nshared = 0;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            if (t0[i] == t1[j] && nshared < 2) {
                shared0[nshared] = i;
                shared1[nshared] = j;
                ++nshared;
            }
    if (nshared != 2) return false;
    const int other0 = 3 - shared0[0] - shared0[1], other1 = 3 - shared1[0] - shared1[1];
    const Vec3 &o0 = t0[other0], &o1 = t1[other1], &s0 = t0[shared0[0]], &s1 = t0[shared0[1]];
    const glm::dvec3 gap = glm::dvec3(o0) + glm::dvec3(o1) - glm::dvec3(s0) - glm::dvec3(s1);
    const double scale = std::max({glm::length(glm::dvec3(o0)), glm::length(glm::dvec3(o1)),
                                   glm::length(glm::dvec3(s0)), glm::length(glm::dvec3(s1))});
    if (!(glm::length(gap) <= 1e-6 * scale)) return false;
    if (!(glm::dot(t.tri_n[0], t.tri_n[1]) > 0.999f)) return false;
    q.corner = o0;
    q.e1 = s0 - o0;
    q.e2 = s1 - o0;
    q.normal = t.tri_n[0];
    // The half beyond the diagonal spans (s0, s1, s0 + s1 - o0) instead of the traced (s0, s1,
    // o1): its distance from that triangle's plane is largest at the fourth corner. Margin: the
    // error box is measured along the normal, within 2.6 degrees of the second triangle's normal.
    const glm::dvec3 n1 = glm::normalize(
        glm::cross(glm::dvec3(t1[1]) - glm::dvec3(t1[0]), glm::dvec3(t1[2]) - glm::dvec3(t1[0])));
    const float plane_dev = float(1.01 * std::fabs(glm::dot(n1, gap)));
    // Every sample o0 + u.x e1 + u.y e2 (u in [0, 1)^2): the edges' rounding (differences of
    // vertices), two products and two sums (gamma(5) of the terms' magnitudes, at most |o0|,
    // |e1|, |e2|), and the second half's distance from its traced triangle along the normal.
    q.sample_err = gamma_bound(5) * (glm::abs(q.corner) + glm::abs(q.e1) + glm::abs(q.e2)) +
                   plane_dev * glm::abs(q.normal);
    return true;
}

}  // namespace

std::optional<LightLiSample> EmissiveTriangles::sample_li(const LightSampleContext& ctx,
                                                          Vec2 u) const {
    if (tri_cdf.empty()) return std::nullopt;
    LightLiSample s;
    // Pick a triangle in proportion to its area, then reuse u.x within it.
    const std::size_t i = find_cdf_interval(tri_cdf.data(), tri_guide.data(), tri_cdf.size(), u.x);
    float lo = i == 0 ? 0.f : tri_cdf[i - 1];
    float w = tri_cdf[i] - lo;
    float ux = w > 0.f ? std::min((u.x - lo) / w, kOneMinusEpsilon) : 0.5f;
    Vec2 b = sample_uniform_triangle({ux, u.y});
    const Vec3& p0 = tri[3 * i];
    const Vec3& p1 = tri[3 * i + 1];
    const Vec3& p2 = tri[3 * i + 2];
    const float b2 = 1.f - b.x - b.y;
    s.p_light = b.x * p0 + b.y * p1 + b2 * p2;
    s.n_light = tri_n[i];
    // Interpolation (pbrt's bound), and b2's own rounding (the weights may not sum to
    // exactly 1), which moves the point by up to gamma(2) |p2|.
    s.p_light_err = gamma_bound(6) * (glm::abs(b.x * p0) + glm::abs(b.y * p1) + glm::abs(b2 * p2)) +
                    gamma_bound(2) * glm::abs(p2);
    return finish_area_sample(ctx, s, inv_area, radiance);
}

void EmissiveTriangles::note(SceneFeatures& f) {
    f.has_area = true;
}

void EmissiveParallelogram::note(SceneFeatures& f) {
    f.has_area = true;
}

Light Light::area_triangles(std::vector<Vec3> tri, const Rgb& radiance, std::uint32_t shape) {
    EmissiveTriangles l;
    l.radiance = radiance;
    // Keep the non-degenerate triangles; areas accumulated in double for large meshes.
    std::vector<Vec3> kept;
    std::vector<double> areas;
    kept.reserve(tri.size());
    double total = 0.0;
    for (std::size_t i = 0; i + 2 < tri.size(); i += 3) {
        glm::dvec3 a(tri[i]), b(tri[i + 1]), c(tri[i + 2]);
        double area = 0.5 * glm::length(glm::cross(b - a, c - a));
        if (!(area > 0.0) || !std::isfinite(area)) continue;
        kept.insert(kept.end(), {tri[i], tri[i + 1], tri[i + 2]});
        areas.push_back(area);
        total += area;
    }
    l.tri = std::move(kept);
    l.area = float(total);
    l.tri_cdf.resize(areas.size());
    double run = 0.0;
    for (std::size_t i = 0; i < areas.size(); ++i) {
        run += areas[i];
        l.tri_cdf[i] = float(run / total);
    }
    if (!l.tri_cdf.empty()) l.tri_cdf.back() = 1.f;
    l.tri_guide.resize(l.tri_cdf.size());
    build_cdf_guide(l.tri_cdf.data(), l.tri_cdf.size(), l.tri_guide.data());
    l.inv_area = total > 0.0 ? float(1.0 / total) : 0.f;
    l.tri_n.resize(areas.size());
    for (std::size_t i = 0; i < areas.size(); ++i) {
        const Vec3 &p0 = l.tri[3 * i], &p1 = l.tri[3 * i + 1], &p2 = l.tri[3 * i + 2];
        // In double: the float cross product's squared length overflows for edges beyond ~4e9
        // (a Cornell box scaled by 1e7 lost its light this way).
        l.tri_n[i] = Vec3(glm::normalize(
            glm::cross(glm::dvec3(p1) - glm::dvec3(p0), glm::dvec3(p2) - glm::dvec3(p0))));
    }
    const Common common{
        .emission = radiance,
        .position = l.tri.empty() ? Vec3(0.f) : (l.tri[0] + l.tri[1] + l.tri[2]) / 3.f,
        .area = l.area,
        .shape = shape};
    EmissiveParallelogram q;
    if (areas.size() == 2 && detect_parallelogram(l, q)) {
        q.radiance = radiance;
        q.area = l.area;
        q.inv_area = l.inv_area;
        return make(q, common);
    }
    return make(std::move(l), common);
}

// The box of every vertex; the cone about the area-weighted mean normal that holds every
// triangle's normal (all directions when they disagree too much to have a mean).
std::optional<LightBounds> EmissiveTriangles::bounds() const {
    if (tri.empty()) return std::nullopt;
    Vec3 lo = tri[0], hi = tri[0];
    for (const Vec3& v : tri) {
        lo = glm::min(lo, v);
        hi = glm::max(hi, v);
    }
    Vec3 sum(0.f);
    for (std::size_t t = 0; t < tri_n.size(); ++t)
        sum += tri_n[t] * (0.5f * glm::length(glm::cross(tri[3 * t + 1] - tri[3 * t],
                                                         tri[3 * t + 2] - tri[3 * t])));
    const float len = glm::length(sum);
    Vec3 w(0.f, 0.f, 1.f);
    float cos_o = -1.f;
    if (len > 0.f && std::isfinite(len)) {
        w = sum / len;
        cos_o = 1.f;
        for (const Vec3& n : tri_n) cos_o = std::min(cos_o, glm::dot(n, w));
        cos_o = std::max(-1.f, cos_o - 1e-4f);  // float round-off of the normals
    }
    return light_bounds(lo, hi, power(0.f), w, cos_o, 0.f);
}

std::optional<LightBounds> EmissiveParallelogram::bounds() const {
    const Vec3 a = corner, b = corner + e1, c = corner + e2, d = corner + e1 + e2;
    return light_bounds(glm::min(glm::min(a, b), glm::min(c, d)),
                        glm::max(glm::max(a, b), glm::max(c, d)), power(0.f), normal, 1.f, 0.f);
}

}  // namespace facet::render
