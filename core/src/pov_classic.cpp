// POV-Ray's classic finish as the core's lobes (facet/pov_classic.h).
#include "facet/pov_classic.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <mutex>

#include "facet/fresnel.h"
#include "facet/material.h"
#include "facet/quadrature.h"
#include "facet/reflectance.h"
#include "facet/registry.h"

namespace facet::pov {
namespace {

constexpr double kPi = 3.14159265358979323846;

Material blinn(double kappa) {
    return make_material(
        "blinn",
        ParamSet{{"exponent", kappa}, {"reflectance", 1.0}, {"fresnel", std::string("none")}});
}

// Albedo int f cos dwi of the unit blinn lobe at cos(theta_o) = mu (adaptive quadrature,
// facet/reflectance.h), cached per exponent: a scene has a handful of distinct finishes.
double blinn_albedo(double kappa, double mu) {
    static std::mutex mutex;
    static std::map<std::pair<double, double>, double> cache;
    std::lock_guard<std::mutex> lock(mutex);
    const auto key = std::make_pair(kappa, mu);
    if (auto it = cache.find(key); it != cache.end()) return it->second;
    const float m = float(std::clamp(mu, 1e-3, 1.0));
    const Vec3 wo(std::sqrt(std::max(0.f, 1.f - m * m)), 0.f, m);
    const double a =
        hemispherical_directional(blinn(kappa), wo, QuadratureSettings{1e-5, 2'000'000}).value.x;
    cache.emplace(key, a);
    return a;
}

// POV-Ray's lobe per unit height toward wi for a view wo (local frame, z the normal).
double pov_lobe(bool phong, double s, const DVec3& wo, const DVec3& wi) {
    if (wi.z <= 0.0) return 0.0;
    if (phong) {
        const DVec3 r(-wo.x, -wo.y, wo.z);
        const double c = glm::dot(r, wi);
        return c > 0.0 ? std::pow(c, s) : 0.0;
    }
    const DVec3 h = glm::normalize(wo + wi);
    return h.z > 0.0 ? std::pow(h.z, s) : 0.0;
}

// int |a L_pov - b L_blinn| dwi and int L_pov dwi over directions in polar coordinates
// (alpha, phi) around the mirror direction of wo; both lobes lie near it. alpha runs to
// alpha_max (the lobes' width times 12, at most pi), Gauss-Legendre panels, phi by the
// trapezoid rule (periodic); at normal incidence the integrand does not depend on phi.
struct LobeIntegrals {
    double diff = 0.0, pov = 0.0, blinn = 0.0;
};
LobeIntegrals lobe_integrals(bool phong, double s, const Material& m, double w, double theta_o) {
    const DVec3 wo(std::sin(theta_o), 0.0, std::cos(theta_o));
    const DVec3 r(-wo.x, 0.0, wo.z);
    const DVec3 t = glm::normalize(glm::cross(DVec3(0, 1, 0), r));
    const DVec3 b = glm::cross(r, t);
    const double width = 1.0 / std::sqrt(std::max(1.0, phong ? s : s / 4.0));
    const double alpha_max = std::min(kPi, 12.0 * width);
    const int panels = 48, n_phi = theta_o == 0.0 ? 1 : 96;
    const QuadratureRule& q = gauss_legendre(8);
    LobeIntegrals out;
    for (int p = 0; p < panels; ++p) {
        const double a0 = alpha_max * p / panels, a1 = alpha_max * (p + 1) / panels;
        for (std::size_t k = 0; k < q.nodes.size(); ++k) {
            const double alpha = a0 + (a1 - a0) * q.nodes[k];
            const double wa = (a1 - a0) * q.weights[k] * std::sin(alpha);
            for (int j = 0; j < n_phi; ++j) {
                const double phi = 2.0 * kPi * (j + 0.5) / n_phi;
                const DVec3 wi =
                    std::cos(alpha) * r + std::sin(alpha) * (std::cos(phi) * t + std::sin(phi) * b);
                if (wi.z <= 0.0) continue;
                const double lp = pov_lobe(phong, s, wo, wi);
                const Rgb f = m.f(Vec3(wo), Vec3(wi));
                const double lb = w * kPi * double(f.x) * wi.z;
                const double dw = wa * 2.0 * kPi / n_phi;
                out.diff += std::abs(lp - lb) * dw;
                out.pov += lp * dw;
                out.blinn += lb * dw;
            }
        }
    }
    return out;
}

double matched_reflectance(bool phong, double s, double kappa) {
    return pov_lobe_albedo(phong, s) / blinn_albedo(kappa, 1.0);
}

void note(ClassicConversion& c, ClassicNote::Level level, std::string kind) {
    for (const ClassicNote& n : c.notes)
        if (n.kind == kind) return;
    c.notes.push_back({level, std::move(kind)});
}

double max3(const std::array<double, 3>& c) {
    return std::max({c[0], c[1], c[2]});
}

double mirror_weight(const ClassicMirror& m, double mu) {
    switch (m.weight) {
        case ClassicMirror::Weight::Constant:
            return 1.0;
        case ClassicMirror::Weight::Dielectric:
            return fresnel_dielectric(float(mu), float(m.ior));
        case ClassicMirror::Weight::Schlick:
            return m.f0 + (1.0 - m.f0) * std::pow(1.0 - mu, 5.0);
    }
    return 0.0;
}

}  // namespace

double pov_lobe_albedo(bool phong, double s) {
    if (phong) return 2.0 / (s + 1.0);
    return 8.0 * (1.0 - std::pow(2.0, -(s + 2.0) / 2.0)) / (s + 2.0);
}

double metallic_tint(double metallic, double pigment, double cos_i) {
    const double x = std::abs(std::acos(std::clamp(cos_i, -1.0, 1.0))) / (kPi / 2.0);
    const double f = std::clamp(0.014567225 / ((x - 1.12) * (x - 1.12)) - 0.011612903, 0.0, 1.0);
    return 1.0 + metallic * (1.0 - f) * (pigment - 1.0);
}

double classic_lobe_error(bool phong, double s, double kappa, double theta_o) {
    const Material m = blinn(kappa);
    const LobeIntegrals i =
        lobe_integrals(phong, s, m, matched_reflectance(phong, s, kappa), theta_o);
    return i.pov > 0.0 ? i.diff / i.pov : 0.0;
}

double fit_phong_exponent(double phong_size) {
    static std::mutex mutex;
    static std::map<double, double> cache;
    {
        std::lock_guard<std::mutex> lock(mutex);
        if (auto it = cache.find(phong_size); it != cache.end()) return it->second;
    }
    // Golden-section search on log kappa around the small-angle match kappa = 4 s
    // ((cos theta)^s ~ exp(-s theta^2 / 2), cos(theta / 2)^kappa ~ exp(-kappa theta^2 / 8)).
    const double s = std::max(phong_size, 1e-3);
    double lo = std::log(std::max(1e-3, 1.0 * s)), hi = std::log(16.0 * s + 1.0);
    const double g = (std::sqrt(5.0) - 1.0) / 2.0;
    auto err = [&](double lk) { return classic_lobe_error(true, s, std::exp(lk), 0.0); };
    double x1 = hi - g * (hi - lo), x2 = lo + g * (hi - lo);
    double f1 = err(x1), f2 = err(x2);
    for (int it = 0; it < 40 && hi - lo > 1e-4; ++it) {
        if (f1 < f2) {
            hi = x2, x2 = x1, f2 = f1;
            x1 = hi - g * (hi - lo), f1 = err(x1);
        } else {
            lo = x1, x1 = x2, f1 = f2;
            x2 = lo + g * (hi - lo), f2 = err(x2);
        }
    }
    const double kappa = std::exp(0.5 * (lo + hi));
    std::lock_guard<std::mutex> lock(mutex);
    cache.emplace(phong_size, kappa);
    return kappa;
}

double ClassicConversion::diffuse_at(double mu) const {
    if (diffuse <= 0.0) return 0.0;
    const double x = std::clamp(mu, 0.0, 1.0) * (kAlbedoNodes - 1);
    const int k = std::min(int(x), kAlbedoNodes - 2);
    const double s = std::max(specular_albedo[k], specular_albedo[k + 1]);
    return std::min(diffuse, std::max(0.0, 1.0 - s));
}

double ClassicConversion::glossy_albedo_at(double mu) const {
    const double x = std::clamp(mu, 0.0, 1.0) * (kAlbedoNodes - 1);
    const int k = std::min(int(x), kAlbedoNodes - 2);
    const double t = x - k;
    return glossy_albedo[k] * (1.0 - t) + glossy_albedo[k + 1] * t;
}

ClassicConversion convert_classic(const ClassicFinish& f) {
    using Level = ClassicNote::Level;
    ClassicConversion c;
    if (f.subsurface) {
        c.converted = false;
        note(c, Level::Reported, "subsurface kept classic");
        return c;
    }

    // Diffuse: Lambert rho = d, exact. brilliance b: d cos^b has no reciprocal equivalent; the
    // Lambert lobe of the same albedo, (1/pi) int d cos^b dwi = 2 d / (b + 1).
    c.diffuse = std::max(0.0, f.diffuse);
    if (f.brilliance != 1.0 && c.diffuse > 0.0) {
        c.diffuse *= 2.0 / (std::max(0.0, f.brilliance) + 1.0);
        note(c, Level::Approximated, "brilliance");
    }
    if (f.diffuse_back > 0.0) note(c, Level::Reported, "diffuse backside dropped");
    if (f.crand > 0.0) note(c, Level::Reported, "crand dropped");
    if (f.irid > 0.0) note(c, Level::Reported, "irid dropped");
    if (f.reflection_exponent != 1.0) note(c, Level::Reported, "reflection exponent dropped");

    // Highlights: one blinn lobe with POV-Ray's albedo at normal incidence. specular's own
    // lobe is (n.h)^kappa, as the blinn D; phong's exponent is fitted (fit_phong_exponent).
    const bool has_phong = f.phong > 0.0, has_specular = f.specular > 0.0;
    const double e_phong = has_phong ? f.phong * pov_lobe_albedo(true, f.phong_size) : 0.0;
    const double e_spec =
        has_specular ? f.specular * pov_lobe_albedo(false, f.specular_exponent) : 0.0;
    if (has_phong || has_specular) {
        const double k_phong = has_phong ? fit_phong_exponent(f.phong_size) : 0.0;
        const double k_spec = f.specular_exponent;
        double kappa = has_phong ? k_phong : k_spec;
        if (has_phong && has_specular) {
            // Both: one lobe of their summed albedo at the albedo-weighted mean log exponent.
            kappa = std::exp((e_phong * std::log(k_phong) + e_spec * std::log(k_spec)) /
                             (e_phong + e_spec));
            note(c, Level::Approximated, "phong and specular as one lobe");
        }
        if (has_phong) note(c, Level::Approximated, "phong as a fitted lobe");
        c.glossy_exponent = kappa;
        c.glossy_reflectance = (e_phong + e_spec) / blinn_albedo(kappa, 1.0);
        c.metallic = std::clamp(f.metallic, 0.0, 1.0);
    }

    // Reflection: r_min + (r_max - r_min) w(theta_o).
    std::array<double, 3> lo = f.reflection_min, delta{};
    for (int k = 0; k < 3; ++k) {
        delta[k] = f.reflection_max[k] - lo[k];
        if (delta[k] < 0.0) {
            // r_max below r_min: the lobe would subtract. The constant at the mean of the two.
            lo[k] += 0.5 * delta[k];
            delta[k] = 0.0;
            note(c, Level::Approximated, "reflection max below min");
        }
    }
    if (max3(delta) > 0.0) {
        ClassicMirror m;
        m.colour = delta;
        if (f.reflection_fresnel) {
            // Exact: POV-Ray's unpolarised Fresnel of the interior's IOR (from outside).
            if (std::abs(f.ior - 1.0) > 1e-9) {
                m.weight = ClassicMirror::Weight::Dielectric;
                m.ior = f.ior;
                c.mirrors.push_back(m);
            }
        } else {
            // (1 - cos)^f: Schlick's (1 - cos)^5 exactly for f = 5; else Schlick scaled to the
            // same cosine-weighted mean 2 / ((f + 1)(f + 2)) (capped at 1, the rest constant).
            const double fo = std::max(0.0, f.reflection_falloff);
            const double mean = 2.0 / ((fo + 1.0) * (fo + 2.0));
            m.weight = ClassicMirror::Weight::Schlick;
            m.f0 = 0.0;
            if (std::abs(fo - 5.0) > 1e-9) {
                const double scale = std::min(1.0, mean * 21.0);
                for (int k = 0; k < 3; ++k) {
                    lo[k] += delta[k] * (mean - scale / 21.0);
                    m.colour[k] = delta[k] * scale;
                }
                note(c, Level::Approximated, "reflection falloff as Schlick");
            }
            if (max3(m.colour) > 0.0) c.mirrors.push_back(m);
        }
    }
    if (max3(lo) > 0.0) {
        ClassicMirror m;
        m.colour = lo;
        c.mirrors.push_back(m);
    }

    // Energy: the specular lobes' albedo S(mu) at the nodes; above 1, every specular lobe is
    // scaled down by its maximum. The diffuse lobe takes what is left (diffuse_at).
    double s_max = 0.0;
    for (int k = 0; k < ClassicConversion::kAlbedoNodes; ++k) {
        const double mu = double(k) / (ClassicConversion::kAlbedoNodes - 1);
        c.glossy_albedo[k] = c.glossy_reflectance > 0.0
                                 ? c.glossy_reflectance * blinn_albedo(c.glossy_exponent, mu)
                                 : 0.0;
        c.specular_albedo[k] = c.glossy_albedo[k];
        for (const ClassicMirror& m : c.mirrors)
            c.specular_albedo[k] += max3(m.colour) * mirror_weight(m, mu);
        s_max = std::max(s_max, c.specular_albedo[k]);
    }
    // Above 1 every specular lobe is scaled down by the maximum; a blinn reflectance above 1
    // (POV-Ray's albedo above the lobe's own, which loses some to shadowing) is capped at the
    // model's range [0, 1].
    const double scale = std::min(s_max > 1.0 ? 1.0 / s_max : 1.0,
                                  c.glossy_reflectance > 1.0 ? 1.0 / c.glossy_reflectance : 1.0);
    if (scale < 1.0) {
        c.glossy_reflectance *= scale;
        for (ClassicMirror& m : c.mirrors)
            for (double& x : m.colour) x *= scale;
        for (double& s : c.specular_albedo) s *= scale;
        for (double& s : c.glossy_albedo) s *= scale;
        note(c, Level::Approximated, "energy: specular scaled down");
    }
    for (int k = 0; k < ClassicConversion::kAlbedoNodes; ++k)
        if (c.diffuse + c.specular_albedo[k] > 1.0 + 1e-9) {
            note(c, Level::Approximated, "energy: diffuse reduced");
            break;
        }

    // How the blinn lobe reflects other objects (lights always shade it): on the mirror ray
    // when there is one, else by one glossy ray at camera hits for an albedo of 10% or more.
    if (c.glossy_reflectance > 0.0) {
        if (!c.mirrors.empty()) {
            c.glossy_folded = true;
            note(c, Level::Approximated, "glossy reflection on the mirror ray");
        } else if (c.glossy_albedo.back() >= 0.1) {
            c.glossy_samples = 1;
        } else {
            note(c, Level::Approximated, "glossy reflection below 10% not traced");
        }
    }
    return c;
}

ClassicLobes classic_lobes(const ClassicConversion& c) {
    ClassicLobes l{make_material("lambert", ParamSet{{"reflectance", 1.0}}), std::nullopt, {}};
    if (c.glossy_reflectance > 0.0)
        l.glossy = make_material("blinn", ParamSet{{"exponent", c.glossy_exponent},
                                                   {"reflectance", c.glossy_reflectance},
                                                   {"fresnel", std::string("none")}});
    for (const ClassicMirror& m : c.mirrors) {
        switch (m.weight) {
            case ClassicMirror::Weight::Constant:
                l.mirrors.push_back(
                    make_material("mirror", ParamSet{{"fresnel", std::string("none")}}));
                break;
            case ClassicMirror::Weight::Dielectric:
                l.mirrors.push_back(make_material(
                    "mirror", ParamSet{{"fresnel", std::string("dielectric")}, {"ior", m.ior}}));
                break;
            case ClassicMirror::Weight::Schlick:
                l.mirrors.push_back(make_material(
                    "mirror", ParamSet{{"fresnel", std::string("schlick")}, {"f0", m.f0}}));
                break;
        }
    }
    return l;
}

}  // namespace facet::pov
