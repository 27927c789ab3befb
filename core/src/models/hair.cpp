// hair: Blender's Hair BSDF as Cycles 3.4 evaluates it (bsdf_hair.h, from Open Shading
// Language's hair closures: Kajiya-Kay-like lobes about a fibre), for a fibre along the frame's
// x axis (the shape's dpdu). With theta the angles to the normal plane of the fibre (theta_r of
// wo, theta_i of wi), t = (theta_i + theta_r) / 2 - o where o = -offset (Cycles negates Blender's
// Offset), r_u, r_v the roughnesses clamped to [0.001, 1], phi the angle about the fibre between
// wi and wo's projections, and a, b = atan(((+-pi/2 + theta_r) / 2 - o) / r_u):
//   p_theta = r_u / (2 (t^2 + r_u^2) (a - b) cos theta_i),
//   reflection:   p_phi = cos(phi / (2 r_v)) / (4 r_v)  for phi <= pi r_v and |phi| <= pi/2,
//   transmission: p_phi = r_v / (c (q^2 + r_v^2)), q = pi - phi, c = 2 atan(pi / (2 r_v)),
// and Cycles' closure returns F = p_theta p_phi as its eval (the cosine included), so
// f = colour F / |cos theta_i| about z. Reflection gives nothing below the surface, transmission
// nothing above it (the viewer's side); directions within 0.001 rad of the fibre are 0.
//  - Sampling: Cycles' warps, which draw the density F over theta and, for reflection, over phi;
//    for transmission Cycles draws q in [-pi/2, pi/2] while its eval reaches |q| up to pi, so
//    here q is drawn from the same Cauchy shape over [-pi, pi] (c' = 2 atan(pi / r_v) in place
//    of c): pdf = F c / c', and every sample weighs colour c' / c. A direction that falls where
//    F is 0 (the wrong side of the surface) is no sample, so pdf() is the density of the
//    samples returned.
//  - Energy: the albedo is the integral of F over the allowed side: the colour times the part
//    of Cycles' sampling density there for reflection (less where the lobe crosses the surface:
//    r_v > 1/2 reaches |phi| > pi/2, which Cycles' eval drops).
//  - Not reciprocal (theta_r and the azimuth are wo's). Exact functions replace Cycles'
//    fast_acosf / fast_atan2f / fast_cosf approximations.
// Conventions: facet/inline_bxdf.h; transmission is flagged Transmission (the frame is the
// shape's, facet/dielectric.h), reflection is not (z faces the viewer); kReadsTangent.
#include <algorithm>
#include <cmath>

#include "model_unit.h"

namespace facet {

namespace {

class HairFibre {
  public:
    static constexpr bool kReadsTangent = true;

    HairFibre(bool transmission, const Rgb& color, double offset, double ru, double rv)
        : m_color(color),
          m_offset(float(-offset)),
          m_r1(float(std::clamp(ru, 0.001, 1.0))),
          m_r2(float(std::clamp(rv, 0.001, 1.0))),
          m_transmission(transmission) {}

    BSDFEval eval(const Vec3& wo, const Vec3& wi) const {
        const double side = wo.z < 0.f ? -1.0 : 1.0;  // Cycles' N faces the viewer
        const bool above = side * wi.z >= 0.0;
        if (m_transmission ? above : side * wi.z < 0.0) return {};
        const double ro = std::hypot(double(wo.y), double(wo.z));
        const double ri = std::hypot(double(wi.y), double(wi.z));
        if (!(ro > 0.0 && ri > 0.0)) return {};
        const double theta_r = std::asin(std::clamp(double(wo.x), -1.0, 1.0));
        const double theta_i = std::asin(std::clamp(double(wi.x), -1.0, 1.0));
        if (0.5 * kPiD - std::fabs(theta_i) < 0.001) return {};
        const double cos_phi =
            std::clamp((double(wo.y) * wi.y + double(wo.z) * wi.z) / (ro * ri), -1.0, 1.0);
        const double r2 = m_r2;
        double phi_pdf;
        double pdf_scale = 1.0;  // pdf / F
        if (m_transmission) {
            const double q = kPiD - std::acos(cos_phi);
            const double c = 2.0 * std::atan(0.5 * kPiD / r2);
            phi_pdf = r2 / (c * (q * q + r2 * r2));
            pdf_scale = c / (2.0 * std::atan(kPiD / r2));
        } else {
            if (cos_phi < 0.0) return {};
            const double phi = std::min(std::acos(cos_phi) / r2, kPiD);
            phi_pdf = std::cos(0.5 * phi) * 0.25 / r2;
        }
        const double F = phi_pdf * theta_pdf(theta_r, theta_i);
        const float pdf = float(F * pdf_scale);
        const double cos_n = std::fabs(double(wi.z));
        if (!(cos_n > 0.0)) return {Rgb(0.f), pdf};
        return {m_color * float(F / cos_n), pdf};
    }

    std::optional<BSDFSample> sample_f(const Vec3& wo, float /*uc*/, Vec2 u) const {
        const double ro = std::hypot(double(wo.y), double(wo.z));
        if (!(ro > 0.0)) return std::nullopt;
        const DVec3 tg(1.0, 0.0, 0.0), locy(0.0, wo.y / ro, wo.z / ro);
        const DVec3 locx = glm::cross(locy, tg);
        const double theta_r = std::asin(std::clamp(double(wo.x), -1.0, 1.0));
        const auto [a, b] = bounds(theta_r);
        const double t = m_r1 * std::tan(u.x * (a - b) + b);
        const double theta_i = 2.0 * (t + m_offset) - theta_r;
        const double phi = m_transmission
                               ? kPiD + m_r2 * std::tan(2.0 * std::atan(kPiD / m_r2) * (u.y - 0.5))
                               : 2.0 * m_r2 * std::asin(std::clamp(1.0 - 2.0 * u.y, -1.0, 1.0));
        const DVec3 w = (std::cos(phi) * std::cos(theta_i)) * locy -
                        (std::sin(phi) * std::cos(theta_i)) * locx + std::sin(theta_i) * tg;
        const Vec3 wi(glm::normalize(w));
        const BSDFEval e = eval(wo, wi);
        if (!(e.pdf > 0.f) || !(wi.z != 0.f) || !is_finite(e.f)) return std::nullopt;
        return BSDFSample{e.f, wi, e.pdf, flags()};
    }

    BxDFFlags flags() const {
        return m_transmission ? BxDFFlags::Glossy | BxDFFlags::Transmission : BxDFFlags::Glossy;
    }

  private:
    // a, b of the header comment.
    std::pair<double, double> bounds(double theta_r) const {
        return {std::atan(((0.5 * kPiD + theta_r) * 0.5 - m_offset) / m_r1),
                std::atan(((-0.5 * kPiD + theta_r) * 0.5 - m_offset) / m_r1)};
    }
    double theta_pdf(double theta_r, double theta_i) const {
        const auto [a, b] = bounds(theta_r);
        const double t = 0.5 * (theta_i + theta_r) - m_offset, r1 = m_r1;
        return r1 / (2.0 * (t * t + r1 * r1) * (a - b) * std::cos(theta_i));
    }

    Rgb m_color;
    float m_offset, m_r1, m_r2;
    bool m_transmission;
};

// The parameters' indices in the table below (ParamValues); component 1 is transmission.
enum Param : std::size_t { kComponent, kColor, kOffset, kRoughnessU, kRoughnessV };

}  // namespace

const ModelInfo& hair_model() {
    static const ModelInfo m{
        .name = "hair",
        .summary =
            "hair fibre as Blender's Hair BSDF (Cycles 3.4): a reflection or a transmission "
            "lobe about the surface's tangent (dpdu), Kajiya-Kay-like; not reciprocal",
        .params = {models::text("component", "reflection",
                                "the lobe: reflection (the viewer's side) or transmission (the "
                                "far side)",
                                {"reflection", "transmission"}),
                   models::color("color", "0.8", "the colour (the albedo's scale), in [0, 1]"),
                   models::number("offset", "0",
                                  "tilt of the lobes in radians (Blender's Offset), in [-pi/2, "
                                  "pi/2]"),
                   models::number("roughness_u", "0.1",
                                  "roughness along the fibre (Blender's RoughnessU), in [0, 1] "
                                  "(below 0.001 it is 0.001)"),
                   models::number("roughness_v", "1",
                                  "roughness about the fibre (Blender's RoughnessV), in [0, 1] "
                                  "(below 0.001 it is 0.001)")},
        .read =
            [](ParamReader& r, ParamValues& v) {
                r.choice(v, kComponent);
                r.color(v, kColor, Rgb(0.8f), 0.0, 1.0);
                r.number(v, kOffset, 0.0, -0.5 * kPiD, 0.5 * kPiD);
                r.number(v, kRoughnessU, 0.1, 0.0, 1.0);
                r.number(v, kRoughnessV, 1.0, 0.0, 1.0);
            },
        .make =
            [](const ParamValues& v, Children) {
                return Material(InlineBxDF(HairFibre(v.choice(kComponent) == 1, v.color(kColor),
                                                     v.number(kOffset), v.number(kRoughnessU),
                                                     v.number(kRoughnessV))));
            },
        .pov_finish = false};
    return m;
}

}  // namespace facet
