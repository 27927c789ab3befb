#include "facet/fresnel.h"

#include <complex>

#include "facet/quadrature.h"

namespace facet {

namespace {
// Exact unpolarised Fresnel reflectance for a complex relative IOR (Born & Wolf; pbrt-v4
// FrComplex has the same form). Double precision: for eta -> 1 both amplitudes are differences
// of nearly equal numbers, and float loses the few-1e-4 reflectance entirely.
double fresnel_complex(double cos_i, std::complex<double> eta) {
    cos_i = std::clamp(cos_i, 0.0, 1.0);
    double sin2_i = 1.0 - cos_i * cos_i;
    std::complex<double> sin2_t = sin2_i / (eta * eta);
    std::complex<double> cos_t = std::sqrt(1.0 - sin2_t);
    std::complex<double> r_parl = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    std::complex<double> r_perp = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    return 0.5 * (std::norm(r_parl) + std::norm(r_perp));
}
}  // namespace

float fresnel_dielectric(float cos_i, float eta) {
    double c = std::clamp(double(cos_i), 0.0, 1.0);
    double e = eta;
    double sin2_t = (1.0 - c * c) / (e * e);
    if (sin2_t >= 1.0) return 1.f;  // total internal reflection (eta < 1 only)
    double cos_t = std::sqrt(1.0 - sin2_t);
    double r_parl = (e * c - cos_t) / (e * c + cos_t);
    double r_perp = (c - e * cos_t) / (c + e * cos_t);
    return float(std::clamp(0.5 * (r_parl * r_parl + r_perp * r_perp), 0.0, 1.0));
}

float fresnel_conductor(float cos_i, float eta, float k) {
    return float(std::clamp(fresnel_complex(cos_i, {double(eta), double(k)}), 0.0, 1.0));
}

Rgb Fresnel::eval(float cos_i) const {
    cos_i = std::clamp(cos_i, 0.f, 1.f);
    switch (m_kind) {
        case Kind::Constant:
            return m_a;
        case Kind::Dielectric:
            return Rgb(fresnel_dielectric(cos_i, m_a.r));
        case Kind::Conductor:
            return {fresnel_conductor(cos_i, m_a.r, m_b.r), fresnel_conductor(cos_i, m_a.g, m_b.g),
                    fresnel_conductor(cos_i, m_a.b, m_b.b)};
        case Kind::Schlick: {
            float m = 1.f - cos_i;
            float m5 = (m * m) * (m * m) * m;
            return m_a + (Rgb(1.f) - m_a) * m5;
        }
    }
    return Rgb(0.f);
}

Rgb Fresnel::average() const {
    if (is_constant()) return m_a;
    const QuadratureRule& q = gauss_legendre(64);
    DVec3 sum(0.0);
    for (size_t i = 0; i < q.nodes.size(); ++i) {
        double mu = q.nodes[i];
        sum += q.weights[i] * 2.0 * mu * DVec3(eval(float(mu)));
    }
    return Rgb(sum);
}

}  // namespace facet
