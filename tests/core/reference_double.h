// A straightforward double-precision test oracle for the reflection models: D, Lambda, G, F, f
// and pdf, re-derived from the papers' formulas independently of core/src (test-only code).
//
// Conventions (facet/bxdf.h): local frame, z = normal, wo toward the viewer, both directions
// away from the surface; f without the cosine, pdf per unit solid angle of wi. Inputs are the
// float directions the model saw, widened to double, so that the oracle and the model evaluate
// the same point and any difference is the model's arithmetic.
//
// Where each formula comes from:
//  - GGX / Trowbridge-Reitz, anisotropic (Walter et al. 2007 eq. 33; Heitz 2014 eq. 85):
//      D(m) = 1 / (pi ax ay cos^4 (1 + tan^2 (cos^2 phi / ax^2 + sin^2 phi / ay^2))^2),
//      Lambda(w) = (-1 + sqrt(1 + a^2 tan^2)) / 2 with a^2 = cos^2 phi ax^2 + sin^2 phi ay^2,
//    written as t / (2 (1 + sqrt(1 + t))) so that tiny t keeps its digits.
//  - Beckmann, anisotropic (Walter et al. 2007 eq. 25-27; Heitz 2014 eq. 86):
//      D(m) = exp(-tan^2 (...)) / (pi ax ay cos^4),
//      Lambda(w) = (erf(a) - 1)/2 + exp(-a^2) / (2 a sqrt(pi)), a = 1 / (alpha_phi tan),
//    evaluated in long double (the two terms cancel for large a: we keep 19 digits).
//  - Blinn (Cohen & Wallace eq. 2.38): D = (kappa + 2) / (2 pi) cos^kappa, computed in log
//    space. Anisotropic Blinn follows the project's definition (microfacet.h): the Student-t
//    slope distribution with nu = sqrt((ku+2)(kv+2)) stretched by au = sqrt(nu/(ku+2)),
//    av = sqrt(nu/(kv+2)). Its Smith Lambda is computed here *by quadrature* of Smith's integral
//    over the 1D marginal slope density (Smith 1967; Heitz 2014 eq. 72):
//      Lambda(mu) = (1/mu) int_mu^inf (q - mu) P2(q) dq,
//      P2(q) = nu/(2 pi) B(1/2, (nu+1)/2) (1 + q^2)^(-(nu+1)/2),   mu = cot(theta) / alpha_phi,
//    which is independent of the closed form with the incomplete beta function used by core.
//  - G: height-correlated Smith, G2 = 1 / (1 + Lambda(wo) + Lambda(wi)) (Heitz 2014 eq. 99).
//  - Fresnel: exact unpolarised Fresnel equations with complex arithmetic (Born & Wolf):
//      rs = (ci - n ct) / (ci + n ct), rp = (n ci - ct) / (n ci + ct), ct = sqrt(1 - si^2/n^2),
//    n = eta + i k (k = 0 for a dielectric, which then gives total internal reflection
//    automatically); Schlick 1994: F0 + (1 - F0)(1 - c)^5.
//  - Microfacet f = scale D(h) G2 F(wo.h) / (4 cos_o cos_i), h = normalize(wo + wi)
//    (Cohen & Wallace eq. 2.37). pdf: visible normals D_wo(h) / (4 wo.h) = G1(wo) D(h) /
//    (4 cos_o) for GGX and Beckmann (Heitz 2018), D(h) cos_h / (4 wo.h) for Blinn.
#pragma once

#include <boost/math/quadrature/gauss_kronrod.hpp>
#include <boost/math/special_functions/erf.hpp>

#include <cmath>
#include <complex>

#include "facet/types.h"

namespace facet::ref {

enum class Dist { Blinn, Beckmann, GGX };

struct Distribution {
    Dist kind;
    double ax, ay;  // GGX / Beckmann: alphas; Blinn: exponents ku, kv

    // Blinn's Student-t degrees of freedom and stretch.
    double nu() const { return std::sqrt((ax + 2.0) * (ay + 2.0)); }
    double blinn_au() const { return std::sqrt(nu() / (ax + 2.0)); }
    double blinn_av() const { return std::sqrt(nu() / (ay + 2.0)); }
};

// Stretched tan^2 of a microfacet normal: tan^2 (cos^2 phi / ax^2 + sin^2 phi / ay^2), from the
// tangential components (x^2 / ax^2 + y^2 / ay^2) / z^2.
inline double stretched_tan2(const DVec3& m, double ax, double ay) {
    return (m.x * m.x / (ax * ax) + m.y * m.y / (ay * ay)) / (m.z * m.z);
}

inline double D(const Distribution& d, const DVec3& m_in) {
    DVec3 m = glm::normalize(m_in);
    if (!(m.z > 0.0)) return 0.0;
    double c2 = m.z * m.z, c4 = c2 * c2;
    switch (d.kind) {
        case Dist::GGX: {
            double t = stretched_tan2(m, d.ax, d.ay);
            return 1.0 / (kPiD * d.ax * d.ay * c4 * (1.0 + t) * (1.0 + t));
        }
        case Dist::Beckmann: {
            double t = stretched_tan2(m, d.ax, d.ay);
            return std::exp(-t) / (kPiD * d.ax * d.ay * c4);
        }
        case Dist::Blinn: {
            if (d.ax == d.ay) {  // eq. 2.38 as written: (kappa + 2)/(2 pi) cos^kappa
                double k = d.ax;
                if (k == 0.0) return 1.0 / kPiD;
                return (k + 2.0) / (2.0 * kPiD) * std::exp(k * std::log(m.z));
            }
            double nu = d.nu();
            double t = stretched_tan2(m, d.blinn_au(), d.blinn_av());
            return nu / (2.0 * kPiD * c4) * std::exp(-0.5 * (nu + 2.0) * std::log1p(t));
        }
    }
    return 0.0;
}

// 1 / mu = alpha_phi tan(theta) of a direction for a stretch (ax, ay).
inline double inv_mu(const DVec3& w, double ax, double ay) {
    return std::sqrt(w.x * w.x * ax * ax + w.y * w.y * ay * ay) / std::fabs(w.z);
}

// Smith Lambda for the (unit, isotropic) Student-t slope distribution with nu degrees of
// freedom, by quadrature of Smith's integral (see header comment).
inline double student_lambda(double nu, double mu) {
    if (!(mu < 1e300)) return 0.0;
    const double p = 0.5 * (nu + 1.0);
    // log of nu/(2 pi) B(1/2, p) = the marginal density's constant.
    double log_c =
        std::log(nu / (2.0 * kPiD)) + std::lgamma(0.5) + std::lgamma(p) - std::lgamma(p + 0.5);
    double mu2 = mu * mu;
    // Write q = mu + d. (1+q^2)^-p = (1+mu^2)^-p * (1 + (2 mu d + d^2)/(1+mu^2))^-p. The second
    // factor decays over d ~ 1/sqrt(p) (small mu) or (1+mu^2)/(2 mu p) (large mu): scale d by h.
    double h = 1.0 / (std::sqrt(p) + 2.0 * p * mu / (1.0 + mu2));
    auto g = [&](double s) {
        double dd = s * h;
        return dd * std::exp(-p * std::log1p((2.0 * mu * dd + dd * dd) / (1.0 + mu2)));
    };
    double integral = boost::math::quadrature::gauss_kronrod<double, 61>::integrate(
                          g, 0.0, std::numeric_limits<double>::infinity(), 15, 1e-10) *
                      h;
    double log_front = log_c - p * std::log1p(mu2);
    return std::exp(log_front) * integral / mu;
}

inline double lambda(const Distribution& d, const DVec3& w_in) {
    DVec3 w = glm::normalize(w_in);
    if (w.z == 0.0) return std::numeric_limits<double>::infinity();
    switch (d.kind) {
        case Dist::GGX: {
            double t = (w.x * w.x * d.ax * d.ax + w.y * w.y * d.ay * d.ay) / (w.z * w.z);
            return t / (2.0 * (1.0 + std::sqrt(1.0 + t)));
        }
        case Dist::Beckmann: {
            double im = inv_mu(w, d.ax, d.ay);
            if (im == 0.0) return 0.0;
            long double a = 1.0L / (long double)im;
            if (a > 27.0L) return 0.0;  // exp(-a^2) < 1e-316: Lambda underflows double
            long double sp = std::sqrt(3.141592653589793238462643383279502884L);
            long double v = (std::exp(-a * a) / (a * sp) - std::erfc(a)) / 2.0L;
            return double(v);
        }
        case Dist::Blinn: {
            double im = inv_mu(w, d.blinn_au(), d.blinn_av());
            if (im == 0.0) return 0.0;
            return student_lambda(d.nu(), 1.0 / im);
        }
    }
    return 0.0;
}

inline double G1(const Distribution& d, const DVec3& w) {
    return 1.0 / (1.0 + lambda(d, w));
}
inline double G2(const Distribution& d, const DVec3& wo, const DVec3& wi) {
    return 1.0 / (1.0 + lambda(d, wo) + lambda(d, wi));
}

// Exact unpolarised Fresnel reflectance for relative IOR eta + i k, cos_i in [0, 1].
inline double fresnel_exact(double cos_i, double eta, double k) {
    cos_i = glm::clamp(cos_i, 0.0, 1.0);
    std::complex<double> n(eta, k);
    double sin2 = 1.0 - cos_i * cos_i;
    std::complex<double> ct = std::sqrt(1.0 - sin2 / (n * n));
    std::complex<double> rs = (cos_i - n * ct) / (cos_i + n * ct);
    std::complex<double> rp = (n * cos_i - ct) / (n * cos_i + ct);
    return 0.5 * (std::norm(rs) + std::norm(rp));
}
inline double fresnel_schlick(double cos_i, double f0) {
    double m = 1.0 - glm::clamp(cos_i, 0.0, 1.0);
    return f0 + (1.0 - f0) * m * m * m * m * m;
}

// Fresnel term of a test lobe, per channel.
struct FresnelSpec {
    enum class Kind { None, Dielectric, Conductor, Schlick } kind = Kind::None;
    DVec3 eta{1.0}, k{0.0}, f0{0.0};
    DVec3 eval(double c) const {
        DVec3 r;
        for (int i = 0; i < 3; ++i) {
            switch (kind) {
                case Kind::None:
                    r[i] = 1.0;
                    break;
                case Kind::Dielectric:
                    r[i] = fresnel_exact(c, eta[i], 0.0);
                    break;
                case Kind::Conductor:
                    r[i] = fresnel_exact(c, eta[i], k[i]);
                    break;
                case Kind::Schlick:
                    r[i] = fresnel_schlick(c, f0[i]);
                    break;
            }
        }
        return r;
    }
};

// Microfacet f (no energy compensation), per channel.
inline DVec3 microfacet_f(const Distribution& d, const FresnelSpec& F, const DVec3& scale,
                          const DVec3& wo, const DVec3& wi) {
    if (!(wo.z > 0.0 && wi.z > 0.0)) return DVec3(0.0);
    DVec3 h = glm::normalize(wo + wi);
    return scale * (D(d, h) * G2(d, wo, wi) / (4.0 * wo.z * wi.z)) * F.eval(glm::dot(wo, h));
}

// Density of the lobe's sampler (see header comment), per unit solid angle of wi.
inline double microfacet_pdf(const Distribution& d, const DVec3& wo, const DVec3& wi) {
    if (!(wo.z > 0.0 && wi.z > 0.0)) return 0.0;
    DVec3 h = glm::normalize(wo + wi);
    double oh = glm::dot(wo, h);
    if (!(oh > 0.0)) return 0.0;
    if (d.kind == Dist::Blinn) return D(d, h) * h.z / (4.0 * oh);
    return G1(d, wo) * D(d, h) / (4.0 * wo.z);
}

inline DVec3 lambert_f(const DVec3& rho, const DVec3& wo, const DVec3& wi) {
    return (wo.z > 0.0 && wi.z > 0.0) ? rho / kPiD : DVec3(0.0);
}

}  // namespace facet::ref
