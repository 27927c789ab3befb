// Light sampling (conventions in facet/render/light.h).
#include "facet/render/light.h"
#include "facet/render/light_units.h"
#include "facet/render/scene.h"

#include <algorithm>

#include "facet/frame.h"
#include "facet/sampling.h"

namespace facet::render {

namespace {

// Spot falloff, linear in cos theta between the outer and the inner cone (light.h).
float linear_spot_falloff(float cos_theta, float cos_inner, float cos_outer) {
    if (cos_theta >= cos_inner) return 1.f;
    if (cos_theta <= cos_outer) return 0.f;
    return (cos_theta - cos_outer) / (cos_inner - cos_outer);
}

// A point closer than 1e-4 r to an emitting sphere counts as on it. A convex emitter cannot
// light its own surface, but a hit point rounded to just outside the sphere would otherwise see
// a near-hemispherical cone whose samples land at distance ~0 (no shadow ray can block them).
// The excluded shell is 1e-4 r thick: far above float round-off (~1e-7 r), and the light it
// would receive is at grazing angles over a cap of that size.
constexpr double kSphereOutside2 = (1.0 + 1e-4) * (1.0 + 1e-4);

// 1 - cos(theta_max) of the cone subtended by a sphere seen at distance^2 dc2 > r^2, written
// as sin^2 / (1 + cos) so that tiny (distant) spheres lose no precision to cancellation.
double sphere_cone_one_minus_cos(double dc2, double r2) {
    double sin2 = r2 / dc2;
    double cos_max = safe_sqrt(1.0 - sin2);
    return sin2 / (1.0 + cos_max);
}

// A direction uniform in solid angle in the cone about the unit `axis` with 1 - cos theta_max =
// omc (pbrt-v4's SampleUniformCone, in double and in the 1 - cos form so that narrow cones keep
// their precision): 1 - cos theta = u.x omc, phi = 2 pi u.y. Density 1 / (2 pi omc).
glm::dvec3 sample_cone(const Vec3& axis, double omc, Vec2 u) {
    double one_minus_cos = double(u.x) * omc;
    double cos_t = 1.0 - one_minus_cos;
    double sin_t = safe_sqrt(one_minus_cos * (2.0 - one_minus_cos));
    double phi = 2.0 * kPiD * double(u.y);
    Frame f = Frame::from_z(axis);
    return glm::normalize(glm::dvec3(f.x) * (sin_t * std::cos(phi)) +
                          glm::dvec3(f.y) * (sin_t * std::sin(phi)) + glm::dvec3(f.z) * cos_t);
}

// Distance t along the unit wi from p to the sphere of squared radius r2 whose centre is p +
// to_c: the nearer intersection, or with `far` the farther one (from inside) (Ray Tracing Gems
// ch. 7 form, q = the closest approach). At grazing angles round-off may miss: the distance of
// the closest approach then.
double sphere_hit_distance(const glm::dvec3& to_c, const glm::dvec3& wi, double r2, bool far) {
    double b = glm::dot(to_c, wi);
    glm::dvec3 q = to_c - b * wi;
    double disc = r2 - glm::dot(q, q);
    if (!(disc > 0.0)) return b;
    return far ? b + std::sqrt(disc) : b - std::sqrt(disc);
}

// Radiance of a sphere light of on-axis intensity I0 and radius r: L = I0 / (pi r^2) (light.h).
// Zero when r is so small that L overflows a float: the caller keeps the point light.
Rgb sphere_light_radiance(const Rgb& intensity, float radius) {
    const glm::dvec3 l = glm::dvec3(intensity) / (kPiD * double(radius) * double(radius));
    const Rgb lf(l);
    return radius > 0.f && is_finite(lf) ? lf : Rgb(0.f);
}

// --- area lamps (light.h, "Area lamps") ---

// Below this solid angle (sr) an area lamp is sampled uniformly by area: the spherical
// rectangle's Omega = g0 + g1 + g2 + g3 - 2 pi loses its relative precision as Omega -> 0
// (double cancellation: ~1e-15 / Omega), and a lamp this small (under 0.6 degrees across) has a
// nearly uniform solid-angle density under area sampling anyway. pbrt-v4 does the same for its
// spherical triangles and rectangles (MinSphericalSampleArea = 3e-4, in float).
constexpr double kLampMinSolidAngle = 1e-4;

// Disc and ellipse lamps: sampled over their bounding spherical rectangle (with rejection) while
// the point's height above the lamp's plane is below kLampEllipseNear times the larger half-axis,
// else uniformly by area. Variances of the irradiance estimate from a disc of radius R, area
// sampling / rejection (exact integrals, tools-free: E[X^2] = Omega_rect int cos^2 dw for
// rejection, A int cos^4 / r^4 dA for area): on the axis 14.2 at h = 0.4 R, 3.7 at 0.7 R, 1.1 at
// R, 0.57 at 1.2 R, 0.08 at 2 R; offset 1.5 R from the axis 4.5 at 0.7 R, 2.8 at R, 0.74 at 2 R.
// Near the lamp the rejection wins by far (the area pdf's 1 / cos_l and r^2 blow up), far off
// area sampling does (its solid-angle density becomes uniform, while rejection loses 1 - pi/4 of
// its samples). The crossover is at h ~ R on the axis and ~1.7 R off it: h < R.
// bench/lamp_bench.cpp measures the rendered ratio (docs/performance.md).
constexpr double kLampEllipseNear = 1.0;

// Urena, Fajardo & King 2013 (Algorithm 1): the spherical rectangle that a rectangle with corner
// s and edges ex, ey (perpendicular) subtends from o, and its area-preserving sampling. All in
// double. Omega is the rectangle's solid angle.
struct SphericalRect {
    glm::dvec3 o, x, y, z;
    double x0 = 0, y0 = 0, z0 = 0, x1 = 0, y1 = 0, b0 = 0, b1 = 0, k = 0, omega = 0;

    SphericalRect(const glm::dvec3& o_, const glm::dvec3& s, const glm::dvec3& ex,
                  const glm::dvec3& ey)
        : o(o_) {
        const double exl = glm::length(ex), eyl = glm::length(ey);
        x = ex / exl;
        y = ey / eyl;
        z = glm::cross(x, y);
        const glm::dvec3 d = s - o;
        x0 = glm::dot(d, x);
        y0 = glm::dot(d, y);
        z0 = glm::dot(d, z);
        if (z0 > 0.0) {  // the local z points away from the rectangle
            z = -z;
            z0 = -z0;
        }
        x1 = x0 + exl;
        y1 = y0 + eyl;
        // The normals of the four planes through o and an edge, and the interior angles.
        const glm::dvec3 v00(x0, y0, z0), v01(x0, y1, z0), v10(x1, y0, z0), v11(x1, y1, z0);
        const glm::dvec3 n0 = glm::normalize(glm::cross(v00, v10));
        const glm::dvec3 n1 = glm::normalize(glm::cross(v10, v11));
        const glm::dvec3 n2 = glm::normalize(glm::cross(v11, v01));
        const glm::dvec3 n3 = glm::normalize(glm::cross(v01, v00));
        auto angle = [](const glm::dvec3& a, const glm::dvec3& b) {
            return std::acos(std::clamp(-glm::dot(a, b), -1.0, 1.0));
        };
        const double g0 = angle(n0, n1), g1 = angle(n1, n2), g2 = angle(n2, n3), g3 = angle(n3, n0);
        b0 = n0.z;
        b1 = n2.z;
        k = 2.0 * kPiD - g2 - g3;
        omega = g0 + g1 - k;
    }

    // The point of the rectangle at the solid-angle coordinates u in [0, 1)^2.
    glm::dvec3 sample(Vec2 u) const {
        const double au = double(u.x) * omega + k;
        const double fu = (std::cos(au) * b0 - b1) / std::sin(au);
        double cu = std::copysign(1.0, fu) / std::sqrt(fu * fu + b0 * b0);
        cu = std::clamp(cu, -1.0, 1.0);
        double xu = -(cu * z0) / safe_sqrt(1.0 - cu * cu);
        xu = std::clamp(std::isfinite(xu) ? xu : (cu > 0.0 ? x1 : x0), x0, x1);
        const double dd = std::sqrt(xu * xu + z0 * z0);
        const double h0 = y0 / std::sqrt(dd * dd + y0 * y0);
        const double h1 = y1 / std::sqrt(dd * dd + y1 * y1);
        const double hv = h0 + double(u.y) * (h1 - h0), hv2 = hv * hv;
        const double yv = hv2 < 1.0 - 1e-12 ? hv * dd / std::sqrt(1.0 - hv2) : y1;
        return o + xu * x + std::clamp(yv, y0, y1) * y + z0 * z;
    }
};

// The lamp's bounding spherical rectangle seen from p: corner c - e1 - e2, edges 2 e1 and 2 e2.
SphericalRect lamp_rect(const glm::dvec3& p, const Vec3& c, const Vec3& e1, const Vec3& e2) {
    const glm::dvec3 a(e1), b(e2);
    return SphericalRect(p, glm::dvec3(c) - a - b, 2.0 * a, 2.0 * b);
}

// Whether a lamp is sampled by solid angle from a point at height h > 0 above it (light.h):
// rectangles always, ellipses when near (kLampEllipseNear).
bool lamp_near(double h, const Vec3& e1, const Vec3& e2, bool ellipse) {
    if (!ellipse) return true;
    return h < kLampEllipseNear * double(std::max(glm::length(e1), glm::length(e2)));
}

}  // namespace

Light Light::point(const Vec3& position, const Rgb& power, float radius) {
    Light l;
    l.m_kind = Kind::Point;
    l.m_position = position;
    l.m_emission = power;
    l.m_intensity = power * kInv4Pi;  // isotropic: I = Phi / (4 pi)
    l.set_sphere(radius);
    return l;
}

void Light::set_sphere(float radius) {
    m_size_radiance = sphere_light_radiance(m_intensity, radius);
    if (m_size_radiance == Rgb(0.f) && m_intensity != Rgb(0.f)) return;  // a point to float
    if (!(radius > 0.f)) return;
    m_radius = radius;
    m_delta = false;
}

Light Light::spot(const Vec3& position, const Vec3& direction, const Rgb& power,
                  float inner_half_angle_deg, float outer_half_angle_deg, float radius) {
    Light l;
    l.m_kind = Kind::Spot;
    l.m_position = position;
    l.m_direction = glm::normalize(direction);
    l.m_emission = power;
    double ci = std::cos(double(inner_half_angle_deg) * kPiD / 180.0);
    double co = std::cos(double(outer_half_angle_deg) * kPiD / 180.0);
    l.m_cos_inner = float(ci);
    l.m_cos_outer = float(co);
    // Phi = 2 pi I0 int_{cos_out}^{1} falloff(mu) dmu (light_units.h, shared with the exporters).
    l.m_intensity = Rgb(spot_intensity(glm::dvec3(power), double(inner_half_angle_deg),
                                       double(outer_half_angle_deg)));
    l.set_sphere(radius);
    return l;
}

float Light::spot_falloff(float cos_theta) const {
    if (m_spot_smooth < 0.f) return linear_spot_falloff(cos_theta, m_cos_inner, m_cos_outer);
    return float(
        cycles_spot_attenuation(double(cos_theta), double(m_cos_outer), double(m_spot_smooth)));
}

Light Light::spot_blend(const Vec3& position, const Vec3& direction, const Rgb& power,
                        float outer_half_angle_deg, float blend, float radius) {
    Light l = spot(position, direction, power, outer_half_angle_deg, outer_half_angle_deg);
    const double c = std::cos(double(outer_half_angle_deg) * kPiD / 180.0);
    l.m_cos_inner = l.m_cos_outer = float(c);
    l.m_spot_smooth = float((1.0 - c) * double(blend));
    l.m_intensity =
        Rgb(cycles_spot_intensity(glm::dvec3(power), double(outer_half_angle_deg), double(blend)));
    l.set_sphere(radius);
    return l;
}

Light Light::directional(const Vec3& direction, const Rgb& irradiance, float angle_deg) {
    Light l;
    l.m_kind = Kind::Directional;
    l.m_direction = glm::normalize(direction);
    l.m_emission = irradiance;
    // 1 - cos delta = 2 sin^2(delta / 2) and sin^2 delta = omc (2 - omc), delta = angle / 2.
    // Below omc = 1e-30 (angles under ~1e-13 degrees) the cone's pdf and L would overflow a
    // float: such a sun is the parallel light it equals to float precision.
    const double quarter = 0.25 * double(angle_deg) * kPiD / 180.0;
    const double omc = 2.0 * std::sin(quarter) * std::sin(quarter);
    if (omc > 1e-30) {
        l.m_sun_one_minus_cos = omc;
        l.m_size_radiance = Rgb(glm::dvec3(irradiance) / (kPiD * omc * (2.0 - omc)));
        l.m_delta = false;
    }
    return l;
}

Light Light::environment(const Rgb& radiance) {
    Light l;
    l.m_kind = Kind::Environment;
    l.m_delta = false;
    l.m_emission = radiance;
    return l;
}

Light Light::environment_map(std::shared_ptr<const EnvironmentMap> map) {
    Light l;
    l.m_kind = Kind::Environment;
    l.m_delta = false;
    l.m_emission = map->mean_radiance();
    l.m_map = std::move(map);
    return l;
}

Light Light::area_triangles(std::vector<Vec3> tri, const Rgb& radiance, std::uint32_t shape) {
    Light l;
    l.m_kind = Kind::Area;
    l.m_delta = false;
    l.m_area_shape = AreaShape::Triangles;
    l.m_shape = shape;
    l.m_emission = radiance;
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
    l.m_tri = std::move(kept);
    l.m_area = float(total);
    l.m_tri_cdf.resize(areas.size());
    double run = 0.0;
    for (std::size_t i = 0; i < areas.size(); ++i) {
        run += areas[i];
        l.m_tri_cdf[i] = float(run / total);
    }
    if (!l.m_tri_cdf.empty()) l.m_tri_cdf.back() = 1.f;
    l.m_inv_area = total > 0.0 ? float(1.0 / total) : 0.f;
    l.m_tri_n.resize(areas.size());
    for (std::size_t i = 0; i < areas.size(); ++i) {
        const Vec3 &p0 = l.m_tri[3 * i], &p1 = l.m_tri[3 * i + 1], &p2 = l.m_tri[3 * i + 2];
        // In double: the float cross product's squared length overflows for edges beyond ~4e9
        // (a Cornell box scaled by 1e7 lost its light this way).
        l.m_tri_n[i] = Vec3(glm::normalize(
            glm::cross(glm::dvec3(p1) - glm::dvec3(p0), glm::dvec3(p2) - glm::dvec3(p0))));
    }
    if (!l.m_tri.empty()) {
        l.m_position = (l.m_tri[0] + l.m_tri[1] + l.m_tri[2]) / 3.f;
    }
    if (areas.size() == 2) l.detect_parallelogram();
    return l;
}

// Two triangles (a, b, c) and (d, e, f) sharing exactly two vertices s0, s1 (the diagonal) form
// a parallelogram when the diagonals bisect each other: o0 + o1 = s0 + s1 for the two other
// vertices. Tolerance: 1e-6 of the coordinates' magnitude (a few float ulps), so sampled points
// stay on the traced triangles to float round-off. Both triangles must face the same way.
void Light::detect_parallelogram() {
    const Vec3* t0 = &m_tri[0];
    const Vec3* t1 = &m_tri[3];
    int shared0[2] = {-1, -1}, shared1[2] = {-1, -1}, nshared = 0;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            if (t0[i] == t1[j] && nshared < 2) {
                shared0[nshared] = i;
                shared1[nshared] = j;
                ++nshared;
            }
    if (nshared != 2) return;
    const int other0 = 3 - shared0[0] - shared0[1], other1 = 3 - shared1[0] - shared1[1];
    const Vec3 &o0 = t0[other0], &o1 = t1[other1], &s0 = t0[shared0[0]], &s1 = t0[shared0[1]];
    const glm::dvec3 gap = glm::dvec3(o0) + glm::dvec3(o1) - glm::dvec3(s0) - glm::dvec3(s1);
    const double scale = std::max({glm::length(glm::dvec3(o0)), glm::length(glm::dvec3(o1)),
                                   glm::length(glm::dvec3(s0)), glm::length(glm::dvec3(s1))});
    if (!(glm::length(gap) <= 1e-6 * scale)) return;
    if (!(glm::dot(m_tri_n[0], m_tri_n[1]) > 0.999f)) return;
    m_area_shape = AreaShape::Parallelogram;
    m_corner = o0;
    m_e1 = s0 - o0;
    m_e2 = s1 - o0;
    m_normal = m_tri_n[0];
    // The half beyond the diagonal spans (s0, s1, s0 + s1 - o0) instead of the traced (s0, s1,
    // o1): its distance from that triangle's plane is largest at the fourth corner. Margin: the
    // error box is measured along m_normal, within 2.6 degrees of the second triangle's normal.
    const glm::dvec3 n1 = glm::normalize(
        glm::cross(glm::dvec3(t1[1]) - glm::dvec3(t1[0]), glm::dvec3(t1[2]) - glm::dvec3(t1[0])));
    const float plane_dev = float(1.01 * std::fabs(glm::dot(n1, gap)));
    // Every sample o0 + u.x e1 + u.y e2 (u in [0, 1)^2): the edges' rounding (differences of
    // vertices), two products and two sums (gamma(5) of the terms' magnitudes, at most |o0|,
    // |e1|, |e2|), and the second half's distance from its traced triangle along the normal.
    m_sample_err = gamma_bound(5) * (glm::abs(m_corner) + glm::abs(m_e1) + glm::abs(m_e2)) +
                   plane_dev * glm::abs(m_normal);
}

Light Light::area_sphere(const Vec3& center, float radius, const Rgb& radiance, std::uint32_t shape,
                         bool inward) {
    Light l;
    l.m_kind = Kind::Area;
    l.m_delta = false;
    l.m_area_shape = AreaShape::Sphere;
    l.m_shape = shape;
    l.m_position = center;
    l.m_radius = radius;
    l.m_inward = inward;
    l.m_emission = radiance;
    l.m_area = 4.f * kPi * radius * radius;
    l.m_inv_area = 1.f / l.m_area;
    return l;
}

Light Light::area_disc(const Vec3& center, const Vec3& e1, const Vec3& e2, const Rgb& radiance,
                       std::uint32_t shape) {
    Light l;
    l.m_kind = Kind::Area;
    l.m_delta = false;
    l.m_area_shape = AreaShape::Disc;
    l.m_shape = shape;
    l.m_position = center;
    l.m_e1 = e1;
    l.m_e2 = e2;
    const glm::dvec3 c = glm::cross(glm::dvec3(e1), glm::dvec3(e2));  // double: see area_triangles
    l.m_normal = Vec3(glm::normalize(c));
    l.m_emission = radiance;
    l.m_area = float(kPiD * glm::length(c));  // an affine image of the unit disc
    // Every sample c + d.x e1 + d.y e2 (|d| <= 1): centre and axes are roundings of the traced
    // disc's double transform, then two products and two sums.
    l.m_sample_err = gamma_bound(5) * (glm::abs(center) + glm::abs(e1) + glm::abs(e2));
    l.m_inv_area = 1.f / l.m_area;
    return l;
}

Light Light::area_lamp(const Vec3& center, const Vec3& e1, const Vec3& e2, const Rgb& radiance,
                       bool ellipse, bool camera_visible) {
    Light l = area_disc(center, e1, e2, radiance, UINT32_MAX);
    l.m_area_shape = ellipse ? AreaShape::LampEllipse : AreaShape::LampRect;
    l.m_camera_visible = camera_visible;
    // Ellipse: pi |e1| |e2| (as area_disc); rectangle: 4 |e1| |e2|.
    if (!ellipse) {
        l.m_area = float(4.0 * glm::length(glm::cross(glm::dvec3(e1), glm::dvec3(e2))));
        l.m_inv_area = 1.f / l.m_area;
    }
    return l;
}

std::optional<LightLiSample> Light::sample_lamp(const LightSampleContext& ctx, Vec2 u) const {
    const bool ellipse = m_area_shape == AreaShape::LampEllipse;
    const glm::dvec3 p(ctx.p);
    const double h = glm::dot(p - glm::dvec3(m_position), glm::dvec3(m_normal));
    if (!(h > 0.0)) return std::nullopt;  // behind the one-sided lamp, or in its plane
    LightLiSample s;
    s.n_light = m_normal;
    s.p_light_err = m_sample_err;
    if (lamp_near(h, m_e1, m_e2, ellipse)) {
        const SphericalRect r = lamp_rect(p, m_position, m_e1, m_e2);
        if (r.omega >= kLampMinSolidAngle) {
            const glm::dvec3 q = r.sample(u);
            const glm::dvec3 v = q - p;
            if (ellipse) {
                // Keep the samples inside the ellipse a^2 + b^2 <= 1 (light.h).
                const glm::dvec3 w = q - glm::dvec3(m_position);
                const double a =
                    glm::dot(w, glm::dvec3(m_e1)) / glm::dot(glm::dvec3(m_e1), glm::dvec3(m_e1));
                const double b =
                    glm::dot(w, glm::dvec3(m_e2)) / glm::dot(glm::dvec3(m_e2), glm::dvec3(m_e2));
                if (a * a + b * b > 1.0) return std::nullopt;
            }
            const double dist = glm::length(v);
            if (!(dist > 0.0)) return std::nullopt;
            s.p_light = Vec3(q);
            s.wi = Vec3(v / dist);
            s.dist = float(dist);
            s.pdf = float(1.0 / r.omega);
            s.li = m_emission;
            if (!std::isfinite(s.pdf)) return std::nullopt;
            s.p_light_err += gamma_bound(4) * glm::abs(s.p_light);  // one more rounding of q
            return s;
        }
    }
    // Far (or tiny): uniform by area, converted to solid angle.
    if (ellipse) {
        const Vec2 d = sample_uniform_disk_concentric(u);
        s.p_light = m_position + d.x * m_e1 + d.y * m_e2;
    } else {
        s.p_light = m_position + (2.f * u.x - 1.f) * m_e1 + (2.f * u.y - 1.f) * m_e2;
    }
    return finish_area_sample(ctx, s);
}

float Light::pdf_lamp(const Vec3& p_) const {
    const bool ellipse = m_area_shape == AreaShape::LampEllipse;
    const glm::dvec3 p(p_);
    const double h = glm::dot(p - glm::dvec3(m_position), glm::dvec3(m_normal));
    if (!(h > 0.0)) return 0.f;
    if (!lamp_near(h, m_e1, m_e2, ellipse)) return -1.f;
    const SphericalRect r = lamp_rect(p, m_position, m_e1, m_e2);
    if (!(r.omega >= kLampMinSolidAngle)) return -1.f;
    return float(1.0 / r.omega);
}

float Light::lamp_hit(const Vec3& o_, const Vec3& d_) const {
    if (!m_camera_visible) return kInfinity;
    const glm::dvec3 o(o_), d(d_), n(m_normal), c(m_position);
    const double dn = glm::dot(d, n);
    if (!(dn < 0.0)) return kInfinity;  // parallel, or its back side (it emits along n)
    const double t = glm::dot(c - o, n) / dn;
    if (!(t > 0.0)) return kInfinity;
    const glm::dvec3 w = o + t * d - c;
    const glm::dvec3 e1(m_e1), e2(m_e2);
    const double a = glm::dot(w, e1) / glm::dot(e1, e1), b = glm::dot(w, e2) / glm::dot(e2, e2);
    const bool inside = m_area_shape == AreaShape::LampEllipse
                            ? a * a + b * b <= 1.0
                            : std::fabs(a) <= 1.0 && std::fabs(b) <= 1.0;
    return inside ? float(t) : kInfinity;
}

// Error box of a point sampled on the sphere: centre and radius are float roundings of the
// traced (double) sphere's, each off by u of its magnitude; the point itself is one rounding of
// a double value (outward samples) or two products and two sums of floats (inward samples).
Vec3 Light::sphere_sample_error(const Vec3& p) const {
    return gamma_bound(4) * (glm::abs(p) + glm::abs(m_position) + Vec3(m_radius));
}

std::optional<LightLiSample> Light::sample_sphere_light(const LightSampleContext& ctx,
                                                        Vec2 u) const {
    LightLiSample s;
    const glm::dvec3 p(ctx.p);
    const glm::dvec3 to_c = glm::dvec3(m_position) - p;
    const double dc2 = glm::dot(to_c, to_c);
    const double r2 = double(m_radius) * double(m_radius);
    glm::dvec3 wi;
    double t;
    if (dc2 > r2) {
        // Outside: uniform in the subtended cone, sin theta_max = r / d.
        const double omc = sphere_cone_one_minus_cos(dc2, r2);
        wi = sample_cone(Vec3(to_c / std::sqrt(dc2)), omc, u);
        t = sphere_hit_distance(to_c, wi, r2, false);
        s.pdf = float(1.0 / (2.0 * kPiD * omc));
    } else {
        // Inside (or on) the sphere: radiance L from every direction (Cycles does the same),
        // so the best density is the cosine's; the light point is the far intersection.
        if (ctx.n != Vec3(0.f)) {
            const Vec3 local = sample_cosine_hemisphere(u);
            s.pdf = cosine_hemisphere_pdf(local.z);
            wi = glm::dvec3(Frame::from_z(ctx.n).from_local(local));
        } else {
            wi = glm::dvec3(sample_uniform_sphere(u));
            s.pdf = uniform_sphere_pdf();
        }
        t = sphere_hit_distance(to_c, wi, r2, true);
    }
    s.wi = Vec3(wi);
    s.dist = float(t);
    s.p_light = Vec3(p + t * wi);  // not on traced geometry: no error box, no normal
    s.li = m_size_radiance;
    if (m_kind == Kind::Spot) {
        // The radiance leaving the sphere toward p, along -wi: L falloff(-wi . axis).
        const float f = spot_falloff(-glm::dot(s.wi, m_direction));
        if (f == 0.f) return std::nullopt;
        s.li *= f;
    }
    if (!(s.pdf > 0.f) || !std::isfinite(s.pdf) || !(s.dist > 0.f)) return std::nullopt;
    return s;
}

std::optional<LightLiSample> Light::sample_li_other(const LightSampleContext& ctx, Vec2 u) const {
    LightLiSample s;
    switch (m_kind) {
        case Kind::Point:
        case Kind::Spot: {
            if (!m_delta) return sample_sphere_light(ctx, u);
            Vec3 v = m_position - ctx.p;
            float r2 = glm::dot(v, v);
            if (!(r2 > 0.f)) return std::nullopt;
            float r = std::sqrt(r2);
            s.wi = v / r;
            Rgb intensity = m_intensity;
            if (m_kind == Kind::Spot) {
                float f = spot_falloff(-glm::dot(s.wi, m_direction));
                if (f == 0.f) return std::nullopt;
                intensity *= f;
            }
            s.li = intensity / r2;  // I / r^2: eq. 2.40 once the receiver multiplies by cos
            s.pdf = 1.f;
            s.dist = r;
            s.p_light = m_position;
            s.delta = true;
            return s;
        }
        case Kind::Directional:
            if (!m_delta) {
                // The sun's disc: uniform in the cone of half-angle delta about -direction.
                s.wi = Vec3(sample_cone(-m_direction, m_sun_one_minus_cos, u));
                s.li = m_size_radiance;
                s.pdf = float(1.0 / (2.0 * kPiD * m_sun_one_minus_cos));
                s.dist = kInfinity;
                return s;
            }
            s.wi = -m_direction;
            s.li = m_emission;
            s.pdf = 1.f;
            s.dist = kInfinity;
            s.delta = true;
            return s;
        case Kind::Environment: {
            if (m_map) {
                const EnvironmentMap::Sample m = m_map->sample(u);
                if (!(m.pdf > 0.f)) return std::nullopt;
                s.wi = m.wi;
                s.pdf = m.pdf;
                s.li = m.radiance;
                s.dist = kInfinity;
                return s;
            }
            if (ctx.n != Vec3(0.f)) {
                Vec3 local = sample_cosine_hemisphere(u);
                s.pdf = cosine_hemisphere_pdf(local.z);
                s.wi = Frame::from_z(ctx.n).from_local(local);
            } else {
                s.wi = sample_uniform_sphere(u);
                s.pdf = uniform_sphere_pdf();
            }
            if (!(s.pdf > 0.f)) return std::nullopt;
            s.li = m_emission;
            s.dist = kInfinity;
            return s;
        }
        case Kind::Area:
            break;
    }

    // Area lights.
    switch (m_area_shape) {
        case AreaShape::Triangles: {
            if (m_tri_cdf.empty()) return std::nullopt;
            // Pick a triangle in proportion to its area, then reuse u.x within it.
            auto it = std::upper_bound(m_tri_cdf.begin(), m_tri_cdf.end(), u.x);
            std::size_t i = std::min<std::size_t>(it - m_tri_cdf.begin(), m_tri_cdf.size() - 1);
            float lo = i == 0 ? 0.f : m_tri_cdf[i - 1];
            float w = m_tri_cdf[i] - lo;
            float ux = w > 0.f ? std::min((u.x - lo) / w, kOneMinusEpsilon) : 0.5f;
            Vec2 b = sample_uniform_triangle({ux, u.y});
            const Vec3& p0 = m_tri[3 * i];
            const Vec3& p1 = m_tri[3 * i + 1];
            const Vec3& p2 = m_tri[3 * i + 2];
            const float b2 = 1.f - b.x - b.y;
            s.p_light = b.x * p0 + b.y * p1 + b2 * p2;
            s.n_light = m_tri_n[i];
            // Interpolation (pbrt's bound), and b2's own rounding (the weights may not sum to
            // exactly 1), which moves the point by up to gamma(2) |p2|.
            s.p_light_err =
                gamma_bound(6) * (glm::abs(b.x * p0) + glm::abs(b.y * p1) + glm::abs(b2 * p2)) +
                gamma_bound(2) * glm::abs(p2);
            break;
        }
        case AreaShape::Parallelogram:
            s.p_light = m_corner + u.x * m_e1 + u.y * m_e2;
            s.n_light = m_normal;
            s.p_light_err = m_sample_err;
            break;
        case AreaShape::Disc: {
            Vec2 d = sample_uniform_disk_concentric(u);
            s.p_light = m_position + d.x * m_e1 + d.y * m_e2;
            s.n_light = m_normal;
            s.p_light_err = m_sample_err;
            break;
        }
        case AreaShape::LampRect:
        case AreaShape::LampEllipse:
            return sample_lamp(ctx, u);
        case AreaShape::Sphere: {
            if (m_inward) {
                // Inside-out sphere: only its interior is lit; uniform by area from inside.
                Vec3 v = ctx.p - m_position;
                // Points ON the sphere (the usual case: it lights itself) pass despite round-off.
                if (!(glm::dot(v, v) <= m_radius * m_radius * 1.001f)) return std::nullopt;
                Vec3 n = sample_uniform_sphere(u);
                s.p_light = m_position + m_radius * n;
                s.n_light = -n;
                s.p_light_err = sphere_sample_error(s.p_light);
                break;
            }
            // Sample the cone of directions the sphere subtends (uniform in solid angle).
            glm::dvec3 c(m_position), p(ctx.p);
            glm::dvec3 to_c = c - p;
            double dc2 = glm::dot(to_c, to_c);
            double r2 = double(m_radius) * double(m_radius);
            if (!(dc2 > r2 * kSphereOutside2)) return std::nullopt;  // inside or on it: unseen
            double dc = std::sqrt(dc2);
            double omc = sphere_cone_one_minus_cos(dc2, r2);
            glm::dvec3 wi = sample_cone(Vec3(to_c / dc), omc, u);
            double t = sphere_hit_distance(to_c, wi, r2, false);
            glm::dvec3 n = glm::normalize(p + t * wi - c);
            glm::dvec3 pl = c + double(m_radius) * n;
            s.p_light = Vec3(pl);
            s.n_light = Vec3(n);
            s.p_light_err = sphere_sample_error(s.p_light);
            s.wi = Vec3(wi);
            s.dist = float(glm::length(pl - p));
            s.pdf = float(1.0 / (2.0 * kPiD * omc));
            s.li = m_emission;
            if (!(s.pdf > 0.f) || !std::isfinite(s.pdf) || !(s.dist > 0.f)) return std::nullopt;
            return s;
        }
    }
    // Triangles, parallelograms and discs: uniform by area, converted to solid angle.
    return finish_area_sample(ctx, s);
}

float Light::pdf_li(const LightSampleContext& ctx, const Vec3& wi, const Vec3& p_light,
                    const Vec3& n_light) const {
    switch (m_kind) {
        case Kind::Point:
        case Kind::Spot:
        case Kind::Directional:
            return 0.f;
        case Kind::Environment:
            if (m_map) return m_map->pdf(wi);
            if (ctx.n != Vec3(0.f)) return cosine_hemisphere_pdf(glm::dot(ctx.n, wi));
            return uniform_sphere_pdf();
        case Kind::Area:
            break;
    }
    if (m_area_shape == AreaShape::Sphere && m_inward) {
        Vec3 v = ctx.p - m_position;
        if (!(glm::dot(v, v) <= m_radius * m_radius * 1.001f)) return 0.f;  // see sample_li
        return area_to_solid_angle_pdf(ctx.p, wi, p_light, n_light, m_inv_area);
    }
    if (m_area_shape == AreaShape::Sphere) {
        if (!(-glm::dot(n_light, wi) > 0.f)) return 0.f;
        glm::dvec3 to_c = glm::dvec3(m_position) - glm::dvec3(ctx.p);
        double dc2 = glm::dot(to_c, to_c);
        double r2 = double(m_radius) * double(m_radius);
        if (!(dc2 > r2 * kSphereOutside2)) return 0.f;
        return float(1.0 / (2.0 * kPiD * sphere_cone_one_minus_cos(dc2, r2)));
    }
    if (m_area_shape == AreaShape::LampRect || m_area_shape == AreaShape::LampEllipse) {
        const float pdf = pdf_lamp(ctx.p);  // < 0: sampled by area from ctx.p
        if (pdf >= 0.f) return pdf;
    }
    if (!(m_area > 0.f)) return 0.f;
    return area_to_solid_angle_pdf(ctx.p, wi, p_light, n_light, m_inv_area);
}

Rgb Light::le(const Vec3& n_light, const Vec3& w) const {
    if (m_kind != Kind::Area) return Rgb(0.f);
    return glm::dot(n_light, w) > 0.f ? m_emission : Rgb(0.f);
}

Rgb Light::le_escape(const Vec3& d) const {
    if (m_kind != Kind::Environment) return Rgb(0.f);
    return m_map ? m_map->eval(d) : m_emission;
}

Rgb Light::power(float scene_radius) const {
    switch (m_kind) {
        case Kind::Point:
        case Kind::Spot:
            return m_emission;
        case Kind::Directional:
            return m_emission * (kPi * scene_radius * scene_radius);
        case Kind::Environment:
            // Radiance L from every direction through a disc of the scene's cross-section
            // (an environment map: its mean radiance over the sphere, m_emission).
            return m_emission * (4.f * kPi * kPi * scene_radius * scene_radius);
        case Kind::Area:
            return m_emission * (kPi * m_area);  // one-sided Lambertian emitter: Phi = pi A L
    }
    return Rgb(0.f);
}

// --- LightDistribution --------------------------------------------------------------------

LightDistribution::LightDistribution(std::span<const Light> lights, float scene_radius) {
    std::vector<double> w(lights.size());
    for (std::size_t i = 0; i < lights.size(); ++i) {
        if (!nee_samples(lights[i])) {
            w[i] = -1.0;
            continue;
        }
        const Rgb phi = lights[i].power(scene_radius);
        const double avg = (double(phi.r) + double(phi.g) + double(phi.b)) / 3.0;
        w[i] = std::isfinite(avg) && avg > 0.0 ? avg : 0.0;
    }
    build(w);
}

LightDistribution LightDistribution::uniform(std::span<const Light> lights) {
    LightDistribution d;
    std::vector<double> w(lights.size());
    for (std::size_t i = 0; i < lights.size(); ++i) w[i] = nee_samples(lights[i]) ? 1.0 : -1.0;
    d.build(w);
    return d;
}

// The view pilot (light.h). Why not the power estimate alone: the environment's and the
// directional lights' power is pi r^2 times their irradiance over the scene's bounding sphere of
// radius r (pbrt-v4), so a large ground (a 40 m plane around a 2 m asset) makes them r^2 times
// more likely than the lamps beside the asset, whatever the camera sees; and a strong lamp that
// is mostly occluded from the view still takes its power's share. The pilot measures both.
LightDistribution LightDistribution::view(const Scene& scene) {
    const std::span<const Light> lights = scene.lights();
    LightDistribution power(lights, scene.radius());
    std::vector<std::size_t> cand;
    for (std::size_t i = 0; i < lights.size(); ++i)
        if (!power.m_empty && power.pmf(i) > 0.f) cand.push_back(i);
    if (cand.size() < 2) return power;
    // Primary receivers: a gx x gy grid (the film's aspect), each with one bounce.
    const std::size_t receivers = kViewBudget / cand.size() / 2;
    if (receivers < 96) return power;
    const Camera& cam = scene.camera();
    const double aspect = double(cam.width) / double(cam.height);
    const int gy = std::clamp(
        int(std::sqrt(double(std::min<std::size_t>(receivers, 768)) / aspect)), 1, cam.height);
    const int gx =
        std::clamp(int(double(std::min<std::size_t>(receivers, 768)) / gy), 1, cam.width);
    std::vector<double> sum(lights.size(), 0.0);
    std::uint32_t n = 0;  // R2 sequence index (Roberts 2018): well spread, deterministic
    const auto next_u = [&n]() {
        ++n;
        const double a = 0.5 + n * 0.7548776662466927, b = 0.5 + n * 0.5698402909980532;
        return Vec2(float(a - std::floor(a)), float(b - std::floor(b)));
    };
    const auto receive = [&](const SurfaceHit& hit, const Vec3& wo, double weight) {
        const Vec3 nrm = glm::dot(hit.ng, wo) < 0.f ? -hit.ng : hit.ng;
        const LightSampleContext ctx{hit.p, nrm};
        for (std::size_t i : cand) {
            const std::optional<LightLiSample> ls = lights[i].sample_li(ctx, next_u());
            if (!ls || !(ls->pdf > 0.f)) continue;
            const double lum = (double(ls->li.r) + double(ls->li.g) + double(ls->li.b)) / 3.0;
            const double c = lum * std::max(0.0, double(glm::dot(nrm, ls->wi))) / double(ls->pdf);
            if (!(c > 0.0) || !std::isfinite(c) || scene.occluded(hit, *ls)) continue;
            sum[i] += (weight * c) * (weight * c);  // second moment: see the weights below
        }
    };
    for (int y = 0; y < gy; ++y) {
        for (int x = 0; x < gx; ++x) {
            const Vec2 film((float(x) + 0.5f) * float(cam.width) / float(gx),
                            (float(y) + 0.5f) * float(cam.height) / float(gy));
            const Ray ray = cam.generate_ray(film);
            SurfaceHit hit;
            if (!scene.intersect(ray, hit)) continue;
            const Vec3 wo = -ray.d;
            receive(hit, wo, 1.0);
            const Vec3 nrm = glm::dot(hit.ng, wo) < 0.f ? -hit.ng : hit.ng;
            const Vec3 d = Frame::from_z(nrm).from_local(sample_cosine_hemisphere(next_u()));
            SurfaceHit bounce;
            if (scene.intersect(Scene::spawn_ray(hit, d), bounce)) receive(bounce, -d, 0.5);
        }
    }
    // The one-sample estimator f_i / p_i of choosing light i with probability p_i has second
    // moment sum_i E[f_i^2] / p_i, least for p_i proportional to sqrt(E[f_i^2]) (Lagrange):
    // a light whose samples vary (an HDRI) gets more than its mean's share, a steady one (a
    // sun) less. Measured against the mean: bench/light_selection_bench.py.
    double total = 0.0;
    for (std::size_t i : cand) total += (sum[i] = std::sqrt(sum[i]));
    if (!(total > 0.0) || !std::isfinite(total)) return power;
    std::vector<double> w(lights.size(), -1.0);
    for (std::size_t i = 0; i < lights.size(); ++i) {
        if (!nee_samples(lights[i])) continue;
        w[i] = (1.0 - kViewPowerShare) * sum[i] / total + kViewPowerShare * double(power.pmf(i));
    }
    LightDistribution d;
    d.build(w);
    return d;
}

void LightDistribution::build(const std::vector<double>& weights) {
    const std::size_t n = weights.size();
    m_cdf.assign(n, 0.f);
    m_pmf.assign(n, 0.f);
    std::size_t candidates = 0;
    double total = 0.0;
    for (double w : weights) {
        if (w < 0.0) continue;
        ++candidates;
        total += w;
    }
    m_empty = candidates == 0;
    if (m_empty) return;
    const bool uniform = !(total > 0.0) || !std::isfinite(total);
    double run = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
        if (weights[i] >= 0.0) run += uniform ? 1.0 : weights[i];
        m_cdf[i] = float(run / (uniform ? double(candidates) : total));
    }
    // The last entry is exactly 1 so that every u in [0,1) selects some light; the trailing
    // zero-weight lights keep their zero probability.
    const float last = m_cdf[n - 1];
    for (std::size_t i = n; i-- > 0 && m_cdf[i] == last;) m_cdf[i] = 1.f;
    // pmf as the selection actually happens: the width of each light's interval of u.
    for (std::size_t i = 0; i < n; ++i) m_pmf[i] = m_cdf[i] - (i > 0 ? m_cdf[i - 1] : 0.f);
}

}  // namespace facet::render
