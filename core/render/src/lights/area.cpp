// Light kind "area": Blender's area lamp, a flat one-sided emitter of uniform radiance that is
// not part of the traced geometry (light.h: not hittable), and its light type (area_lamp).
//
// Sampling: a rectangle lamp is sampled uniformly in the solid angle it subtends (Urena,
// Fajardo & King 2013, "An Area-Preserving Parametrization for Spherical Rectangles"; pdf =
// 1 / Omega), in double precision. A disc or ellipse lamp is sampled the same way over its
// bounding rectangle when the point is near (height h above its plane below kLampEllipseNear =
// 1 times its larger half-axis); a sample that falls outside the ellipse is lost (nullopt), so
// the density over the ellipse is exactly 1 / Omega_rect, unbiased, with pi/4 of the samples
// kept far off (more near); farther away the ellipse is sampled uniformly by area, whose
// solid-angle density is then nearly uniform (see kLampEllipseNear for the measured crossover).
// Either shape falls back to area sampling when Omega < kLampMinSolidAngle (precision: Omega is
// a sum of four angles minus 2 pi). Lamps emit from the front only: from behind or in the
// plane, nullopt.
//
// Frame (Blender's lamp object): local +z = -direction (the lamp emits along its local -z),
// local +y = `up` made perpendicular to z, local +x = y x z. The lamp spans `size` along x and
// `size_y` (rectangle, ellipse; else `size`) along y, centred on `position`.
#include <cmath>

#include "../io/pov_writer.h"
#include "../kind_build.h"
#include "facet/render/light_units.h"
#include "sampling.h"

namespace facet::render {

namespace {

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

// Whether a lamp is sampled by solid angle from a point at height h > 0 above it (see above):
// rectangles always, ellipses when near (kLampEllipseNear).
bool lamp_near(double h, const Vec3& e1, const Vec3& e2, bool ellipse) {
    if (!ellipse) return true;
    return h < kLampEllipseNear * double(std::max(glm::length(e1), glm::length(e2)));
}

enum class AreaShape { Square, Rectangle, Disc, Ellipse };

AreaShape parse_shape(const LightBuild& b) {
    const std::string& s = b.light.shape;
    if (s == "square") return AreaShape::Square;
    if (s == "rectangle") return AreaShape::Rectangle;
    if (s == "disc") return AreaShape::Disc;
    if (s == "ellipse") return AreaShape::Ellipse;
    b.fail(b.ptr + "/shape",
           "unknown area light shape '" + s + "' (expected square, rectangle, disc or ellipse)");
    return AreaShape::Square;  // not reached: fail() throws
}

void build(LightBuild& b) {
    const LightDesc& l = b.light;
    b.check_finite(l.position, b.ptr + "/position");
    const glm::dvec3 dir(b.aim(l.position));
    const AreaShape shape = parse_shape(b);
    const bool two_sizes = shape == AreaShape::Rectangle || shape == AreaShape::Ellipse;
    const double sx = b.positive_length(l.size, b.ptr + "/size");
    double sy = sx;
    if (two_sizes) {
        if (!l.size_y) b.fail(b.ptr, "missing required key 'size_y' (shape " + l.shape + ")");
        sy = b.positive_length(*l.size_y, b.ptr + "/size_y");
    } else if (l.size_y) {
        b.fail(b.ptr + "/size_y", "only the rectangle and ellipse shapes take size_y");
    }
    // The lamp's frame (see the top of the file).
    const glm::dvec3 up =
        l.up ? glm::dvec3(b.unit_direction(*l.up, b.ptr + "/up"))
             : (std::fabs(dir.y) < 0.999 ? glm::dvec3(0, 1, 0) : glm::dvec3(0, 0, 1));
    const glm::dvec3 z = -dir;
    glm::dvec3 y = up - glm::dot(up, z) * z;
    if (!(glm::length(y) > 1e-6)) b.fail(b.ptr + "/up", "must not be parallel to the direction");
    y = glm::normalize(y);
    const glm::dvec3 x = glm::cross(y, z);
    const glm::dvec3 hx = 0.5 * sx * x, hy = 0.5 * sy * y;
    const glm::dvec3 c(l.position);
    // Cycles 3.4: radiance P / (4 A) (light_units.h).
    const bool round = shape == AreaShape::Disc || shape == AreaShape::Ellipse;
    const Rgb power = b.check_color(l.power, b.ptr + "/power", "a power (W)");
    const Rgb radiance(area_lamp_radiance(glm::dvec3(power), area_lamp_area(round, sx, sy)));
    if (!is_finite(radiance))
        b.fail(b.ptr + "/size", "too small for the power: the radiance P / (4 A) overflows");
    // Front side (the side emitting) = dir: cross(e1, e2) must point along -z, so e1 = hy,
    // e2 = hx (cross(y, x) = -z).
    b.add_light(Light::area_lamp(Vec3(c), Vec3(hy), Vec3(hx), radiance, round, l.camera_visible));
}

void pov(PovLightOut& o) {
    o.fail(o.pointer,
           "POV-Ray has no flat emitter of uniform radiance (its area_light is a grid of point "
           "lights); an emissive quad or disc shape of radiance P / (4 A) is exported as "
           "such a grid (--area-grid) and renders the same in Facet, but is also seen by rays");
}

// The solid-angle pdf 1 / Omega of the spherical-rectangle branch from p: 0 from behind, -1
// when p is sampled by area instead.
float lamp_pdf_rect(const AreaLamp& l, const Vec3& p_) {
    const glm::dvec3 p(p_);
    const double h = glm::dot(p - glm::dvec3(l.center), glm::dvec3(l.normal));
    if (!(h > 0.0)) return 0.f;
    if (!lamp_near(h, l.e1, l.e2, l.ellipse)) return -1.f;
    const SphericalRect r = lamp_rect(p, l.center, l.e1, l.e2);
    if (!(r.omega >= kLampMinSolidAngle)) return -1.f;
    return float(1.0 / r.omega);
}

}  // namespace

std::optional<LightLiSample> AreaLamp::sample_li(const LightSampleContext& ctx, Vec2 u) const {
    const glm::dvec3 p(ctx.p);
    const double h = glm::dot(p - glm::dvec3(center), glm::dvec3(normal));
    if (!(h > 0.0)) return std::nullopt;  // behind the one-sided lamp, or in its plane
    LightLiSample s;
    s.n_light = normal;
    s.p_light_err = sample_err;
    if (lamp_near(h, e1, e2, ellipse)) {
        const SphericalRect r = lamp_rect(p, center, e1, e2);
        if (r.omega >= kLampMinSolidAngle) {
            const glm::dvec3 q = r.sample(u);
            const glm::dvec3 v = q - p;
            if (ellipse) {
                // Keep the samples inside the ellipse a^2 + b^2 <= 1.
                const glm::dvec3 w = q - glm::dvec3(center);
                const double a =
                    glm::dot(w, glm::dvec3(e1)) / glm::dot(glm::dvec3(e1), glm::dvec3(e1));
                const double b =
                    glm::dot(w, glm::dvec3(e2)) / glm::dot(glm::dvec3(e2), glm::dvec3(e2));
                if (a * a + b * b > 1.0) return std::nullopt;
            }
            const double dist = glm::length(v);
            if (!(dist > 0.0)) return std::nullopt;
            s.p_light = Vec3(q);
            s.wi = Vec3(v / dist);
            s.dist = float(dist);
            s.pdf = float(1.0 / r.omega);
            s.li = radiance;
            if (!std::isfinite(s.pdf)) return std::nullopt;
            s.p_light_err += gamma_bound(4) * glm::abs(s.p_light);  // one more rounding of q
            return s;
        }
    }
    // Far (or tiny): uniform by area, converted to solid angle.
    if (ellipse) {
        const Vec2 d = sample_uniform_disk_concentric(u);
        s.p_light = center + d.x * e1 + d.y * e2;
    } else {
        s.p_light = center + (2.f * u.x - 1.f) * e1 + (2.f * u.y - 1.f) * e2;
    }
    return finish_area_sample(ctx, s, inv_area, radiance);
}

float AreaLamp::pdf_li(const LightSampleContext& ctx, const Vec3& wi, const Vec3& p_light,
                       const Vec3& n_light) const {
    const float pdf = lamp_pdf_rect(*this, ctx.p);  // < 0: sampled by area from ctx.p
    if (pdf >= 0.f) return pdf;
    if (!(area > 0.f)) return 0.f;
    return area_to_solid_angle_pdf(ctx.p, wi, p_light, n_light, inv_area);
}

float AreaLamp::camera_hit(const Vec3& o_, const Vec3& d_) const {
    const glm::dvec3 o(o_), d(d_), n(normal), c(center);
    const double dn = glm::dot(d, n);
    if (!(dn < 0.0)) return kInfinity;  // parallel, or its back side (it emits along n)
    const double t = glm::dot(c - o, n) / dn;
    if (!(t > 0.0)) return kInfinity;
    const glm::dvec3 w = o + t * d - c;
    const glm::dvec3 a1(e1), a2(e2);
    const double a = glm::dot(w, a1) / glm::dot(a1, a1), b = glm::dot(w, a2) / glm::dot(a2, a2);
    const bool inside = ellipse ? a * a + b * b <= 1.0 : std::fabs(a) <= 1.0 && std::fabs(b) <= 1.0;
    return inside ? float(t) : kInfinity;
}

void AreaLamp::note(SceneFeatures& f) {
    f.has_area = true;
}

Light Light::area_lamp(const Vec3& center, const Vec3& e1, const Vec3& e2, const Rgb& radiance,
                       bool ellipse, bool camera_visible) {
    AreaLamp l;
    l.center = center;
    l.e1 = e1;
    l.e2 = e2;
    const glm::dvec3 c = glm::cross(glm::dvec3(e1), glm::dvec3(e2));  // double: see area_triangles
    l.normal = Vec3(glm::normalize(c));
    l.radiance = radiance;
    l.ellipse = ellipse;
    // Ellipse: pi |e1| |e2|; rectangle: 4 |e1| |e2|.
    l.area = ellipse ? float(kPiD * glm::length(c)) : float(4.0 * glm::length(c));
    l.inv_area = 1.f / l.area;
    // Every sample c + a e1 + b e2 (|a|, |b| <= 1): centre and axes as given, then two products
    // and two sums.
    l.sample_err = gamma_bound(5) * (glm::abs(center) + glm::abs(e1) + glm::abs(e2));
    const float area = l.area;
    return make(
        l,
        {.emission = radiance, .position = center, .area = area, .camera_visible = camera_visible});
}

extern const LightKindDef kAreaLightKind{
    LightKind::Area,
    "area",
    "Blender's area lamp: a flat one-sided emitter of `shape` square (side `size`), rectangle "
    "(`size` × `size_y`), disc (diameter `size`) or ellipse (diameters `size`, `size_y`), "
    "centred on `position`, emitting toward `direction` (its local −z; or toward `look_at`); "
    "its local +y is `up` made perpendicular to the direction, +x = y × z. `power` P is "
    "Blender's (Cycles 3.4): uniform radiance L = P / (4A) with A = size·size_y (square, "
    "rectangle) or π/4·size·size_y (disc, ellipse), so the emitted flux is π L A = π P / 4. "
    "Irradiance on the axis at distance d, facing it: disc of radius R: E = π L R²/(R² + d²); "
    "rectangle of half-sides a, b: E = 2 L [a/√(a²+d²) atan(b/√(a²+d²)) + "
    "b/√(b²+d²) atan(a/√(b²+d²))]. Sampled by solid angle: rectangles exactly (Ureña, Fajardo "
    "& King 2013's spherical rectangle, pdf 1/Ω), discs and ellipses over their bounding "
    "spherical rectangle when near (height < the larger half-axis; samples outside the "
    "ellipse are lost), by area when farther. Camera rays see it only with `camera_visible` "
    "(as Blender 3.4, whose lamps have Object > Visibility > Camera off by default); reflected "
    "and diffuse rays never (only light samples find it): give an emissive quad or disc shape "
    "for an emitter seen in mirrors",
    {{"position", FieldType::Point, true, &LightDesc::position, "-", "centre"},
     {"direction", FieldType::Direction, false, &LightDesc::direction, "-",
      "the way it emits (give this or look_at)"},
     {"look_at", FieldType::Point, false, &LightDesc::look_at, "-",
      "a point on its axis (give this or direction)"},
     {"up", FieldType::Direction, false, &LightDesc::up, "[0, 1, 0]",
      "its local +y, made perpendicular to the direction ([0, 0, 1] by default when the "
      "direction is within 2.6° of ±y)"},
     {"shape", FieldType::Text, false, &LightDesc::shape, "square",
      "square, rectangle, disc or ellipse"},
     {"size", FieldType::Number, true, &LightDesc::size, "-",
      "side (square, rectangle: along x) or diameter (disc, ellipse: along x), > 0"},
     {"size_y", FieldType::Number, false, &LightDesc::size_y, "-",
      "rectangle and ellipse only (required there): the extent along y, > 0"},
     {"power", FieldType::Color, true, &LightDesc::power, "-", "Blender's power P (W)"},
     {"camera_visible", FieldType::Bool, false, &LightDesc::camera_visible, "false",
      "camera rays see its front side, of radiance L (Blender: Object > Visibility > Camera)"}},
    {{"direction", "look_at"}},
    build,
    pov};

std::optional<LightBounds> AreaLamp::bounds() const {
    return flat_bounds(center, e1, e2, normal, power(0.f));
}

}  // namespace facet::render
