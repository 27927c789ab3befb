// Light type of emitting triangle shapes that move over the shutter (emissive_moving_triangles;
// built by Light::area_moving_triangles).
//
// Sampling (light.h conventions), as Cycles 3.4's triangle lights under motion blur: the
// triangle is chosen with a fixed probability P_i, its share of the shape's area averaged over
// the shutter; the point uniformly by area on that triangle as it is at the path's time tau
// (its corners interpolated as the scene traces them, motion.h: the deformation steps linearly,
// the placement decomposed). So the density by area at the point is P_i / A_i(tau), and in solid
// angle P_i r^2 / (A_i(tau) |cos theta_l|). A BSDF ray that hits the shape at time tau finds the
// same density through pdf_li with the hit's triangle (SurfaceHit::emitter_prim): multiple
// importance sampling weighs the two strategies at the same time with the same pdf.
//
// What the light selection sees is conservative over the shutter: power pi L max_tau A(tau),
// the largest total area at kTimeSamples times per motion segment; the tree's box holds every
// corner at those times, padded by the largest distance a corner moves between two neighbouring
// times (a corner's path between them, a 1/kTimeSamples part of a segment's interpolation, is
// within that distance of one of its ends as long as it is at most twice as long as its chord);
// the emission cone is the still triangles' when the shape only translates, else every
// direction.
#include <algorithm>

#include "facet/cdf_search.h"
#include "sampling.h"

namespace facet::render {

namespace {

// Times per motion segment at which the factory measures areas and bounds.
constexpr int kTimeSamples = 32;

// Embree interpolates a moving instance's decomposed steps and a deforming mesh's vertex
// buffers in float, and reports no error bound: samples get the margin the scene's hits on
// moving shapes get (embree_scene.cpp, kMotionSlack), of the corners' magnitudes.
constexpr double kMovingSampleSlack = 1e-4;

glm::dmat4 placement_at(const EmissiveMovingTriangles& l, float tau) {
    if (l.motion.empty()) return l.place;
    return interpolate_motion(l.motion, std::clamp(double(tau), 0.0, 1.0));
}

// Triangle i's world corners under placement m at time tau.
void corners_under(const EmissiveMovingTriangles& l, std::uint32_t i, float tau,
                   const glm::dmat4& m, glm::dvec3 out[3]) {
    const std::size_t steps = l.corners.size();
    for (std::size_t j = 0; j < 3; ++j) {
        const std::size_t c = 3 * std::size_t(i) + j;
        glm::dvec3 q;
        if (steps == 1) {
            q = glm::dvec3(l.corners[0][c]);
        } else {
            const double x = std::clamp(double(tau), 0.0, 1.0) * double(steps - 1);
            const std::size_t k = std::min(std::size_t(x), steps - 2);
            const double f = x - double(k);
            q = (1.0 - f) * glm::dvec3(l.corners[k][c]) + f * glm::dvec3(l.corners[k + 1][c]);
        }
        out[j] = glm::dvec3(m * glm::dvec4(q, 1.0));
    }
}

// The front normal's direction (unnormalised, |n| = 2 A): the corners' winding, reversed by a
// mirroring placement (the traced normal is the object-space one through the inverse transpose).
glm::dvec3 front_cross(const glm::dvec3 p[3], const glm::dmat4& m) {
    const glm::dvec3 c = glm::cross(p[1] - p[0], p[2] - p[0]);
    return glm::determinant(glm::dmat3(m)) < 0.0 ? -c : c;
}

double largest_coordinate(const glm::dvec3 p[3]) {
    double m = 0.0;
    for (int j = 0; j < 3; ++j)
        m = std::max({m, std::fabs(p[j].x), std::fabs(p[j].y), std::fabs(p[j].z)});
    return m;
}

}  // namespace

void EmissiveMovingTriangles::corners_at(std::uint32_t i, float tau, glm::dvec3 out[3]) const {
    corners_under(*this, i, tau, placement_at(*this, tau), out);
}

std::optional<LightLiSample> EmissiveMovingTriangles::sample_li(const LightSampleContext& ctx,
                                                                Vec2 u, float time) const {
    if (tri_cdf.empty()) return std::nullopt;
    // Choose a triangle by P_i, then reuse u.x within it.
    const std::size_t i = find_cdf_interval(tri_cdf.data(), tri_guide.data(), tri_cdf.size(), u.x);
    const float lo = i == 0 ? 0.f : tri_cdf[i - 1];
    const float w = tri_cdf[i] - lo;
    const float ux = w > 0.f ? std::min((u.x - lo) / w, kOneMinusEpsilon) : 0.5f;
    const glm::dmat4 m = placement_at(*this, time);
    glm::dvec3 p[3];
    corners_under(*this, std::uint32_t(i), time, m, p);
    const glm::dvec3 c = front_cross(p, m);
    const double len = glm::length(c);
    if (!(len > 0.0) || !std::isfinite(len)) return std::nullopt;  // degenerate at this time
    const Vec2 b = sample_uniform_triangle({ux, u.y});
    const double b0 = double(b.x), b1 = double(b.y);
    const glm::dvec3 x = b0 * p[0] + b1 * p[1] + (1.0 - b0 - b1) * p[2];
    LightLiSample s;
    s.p_light = Vec3(x);
    s.n_light = Vec3(c / len);
    s.p_light_err =
        rounding_error(s.p_light) + Vec3(float(kMovingSampleSlack * largest_coordinate(p)));
    // Density by area P_i / A_i(tau), A_i = |c| / 2.
    const float pdf_area = float(double(tri_pmf[i]) * 2.0 / len);
    return finish_area_sample(ctx, s, pdf_area, radiance);
}

float EmissiveMovingTriangles::pdf_li(const LightSampleContext& ctx, const Vec3& wi,
                                      const Vec3& p_light, const Vec3& n_light, std::uint32_t prim,
                                      float time) const {
    if (prim >= num_triangles()) return 0.f;
    glm::dvec3 p[3];
    corners_at(prim, time, p);
    const double len = glm::length(glm::cross(p[1] - p[0], p[2] - p[0]));
    if (!(len > 0.0) || !std::isfinite(len)) return 0.f;
    const float pdf_area = float(double(tri_pmf[prim]) * 2.0 / len);
    return area_to_solid_angle_pdf(ctx.p, wi, p_light, n_light, pdf_area);
}

void EmissiveMovingTriangles::note(SceneFeatures& f) {
    f.has_area = true;
}

Light Light::area_moving_triangles(std::vector<std::vector<Vec3>> corners,
                                   std::vector<DecomposedTransform> motion, const glm::dmat4& place,
                                   const Rgb& radiance, std::uint32_t shape) {
    EmissiveMovingTriangles l;
    l.radiance = radiance;
    l.corners = std::move(corners);
    l.motion = std::move(motion);
    l.place = place;
    const std::size_t n = l.corners.empty() ? 0 : l.corners[0].size() / 3;
    const std::size_t steps = std::max(l.motion.size(), l.corners.size());
    const int segments = std::max(1, int(steps) - 1);
    const int samples = segments * kTimeSamples;  // intervals; samples + 1 times
    // Areas and corners at the sample times: the time-averaged areas (trapezoidal rule), the
    // largest total, and the box with the largest move of a corner between neighbouring times.
    l.tri_pmf.resize(n);
    std::vector<double> mean(n, 0.0);
    std::vector<glm::dvec3> prev(3 * n);
    glm::dvec3 lo(std::numeric_limits<double>::infinity()), hi(-lo);
    double max_total = 0.0, max_move = 0.0;
    for (int j = 0; j <= samples; ++j) {
        const float tau = float(double(j) / double(samples));
        const glm::dmat4 m = placement_at(l, tau);
        const double wt = (j == 0 || j == samples) ? 0.5 / samples : 1.0 / samples;
        double total = 0.0;
        for (std::size_t i = 0; i < n; ++i) {
            glm::dvec3 p[3];
            corners_under(l, std::uint32_t(i), tau, m, p);
            const double a = 0.5 * glm::length(glm::cross(p[1] - p[0], p[2] - p[0]));
            const double af = std::isfinite(a) ? a : 0.0;
            mean[i] += wt * af;
            total += af;
            for (std::size_t k = 0; k < 3; ++k) {
                lo = glm::min(lo, p[k]);
                hi = glm::max(hi, p[k]);
                if (j > 0) max_move = std::max(max_move, glm::length(p[k] - prev[3 * i + k]));
                prev[3 * i + k] = p[k];
            }
        }
        max_total = std::max(max_total, total);
    }
    double sum = 0.0;
    for (double a : mean) sum += a;
    l.tri_cdf.resize(n);
    double run = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
        l.tri_pmf[i] = sum > 0.0 ? float(mean[i] / sum) : 0.f;
        run += mean[i];
        l.tri_cdf[i] = sum > 0.0 ? float(run / sum) : 0.f;
    }
    if (!l.tri_cdf.empty()) l.tri_cdf.back() = 1.f;
    l.tri_guide.resize(n);
    if (n > 0) build_cdf_guide(l.tri_cdf.data(), n, l.tri_guide.data());
    l.max_area = float(max_total);

    // The emission cone: the still normals' when only the placement's translation changes.
    bool translates = l.corners.size() == 1;
    for (const DecomposedTransform& d : l.motion)
        translates =
            translates && d.rotation == l.motion[0].rotation && d.scale == l.motion[0].scale;
    Vec3 w(0.f, 0.f, 1.f);
    float cos_o = -1.f;
    if (translates && n > 0) {
        const glm::dmat4 m = placement_at(l, 0.f);
        std::vector<glm::dvec3> normals(n);
        glm::dvec3 acc(0.0);
        for (std::size_t i = 0; i < n; ++i) {
            glm::dvec3 p[3];
            corners_under(l, std::uint32_t(i), 0.f, m, p);
            const glm::dvec3 c = front_cross(p, m);
            acc += 0.5 * c;
            const double len = glm::length(c);
            normals[i] = len > 0.0 ? c / len : glm::dvec3(0.0);
        }
        const double len = glm::length(acc);
        if (len > 0.0 && std::isfinite(len)) {
            const glm::dvec3 wd = acc / len;
            double c = 1.0;
            for (const glm::dvec3& nn : normals)
                if (nn != glm::dvec3(0.0)) c = std::min(c, glm::dot(nn, wd));
            w = Vec3(wd);
            cos_o = std::max(-1.f, float(c) - 1e-4f);  // float round-off of the normals
        }
    }
    const glm::dvec3 pad(max_move * (1.0 + 1e-6) +
                         kMovingSampleSlack *
                             std::max(largest_magnitude(lo), largest_magnitude(hi)));
    if (n > 0 && std::isfinite(lo.x) && std::isfinite(hi.x))
        l.box = light_bounds(Vec3(lo - pad), Vec3(hi + pad), l.power(0.f), w, cos_o, 0.f);

    Vec3 position(0.f);
    if (n > 0) {
        glm::dvec3 p[3];
        l.corners_at(0, 0.f, p);
        position = Vec3((p[0] + p[1] + p[2]) / 3.0);
    }
    const Common common{
        .emission = radiance, .position = position, .area = float(sum), .shape = shape};
    return make(std::move(l), common);
}

}  // namespace facet::render
