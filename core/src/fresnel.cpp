#include "facet/fresnel.h"

#include "facet/quadrature.h"

namespace facet {

namespace {
// Exact unpolarised Fresnel reflectance for a complex relative IOR eta + i k (Born & Wolf), in
// real double arithmetic (std::complex division guards inf/NaN cases and costs ~4x more).
// With s2 = sin^2, x = eta^2 - k^2 - s2 and t = |(eta + i k)^2 - s2| = sqrt(x^2 + 4 eta^2 k^2),
// the complex cosine-like term a + i b = sqrt((eta + i k)^2 - s2) has
//     a = sqrt((t + x) / 2),  b = sqrt((t - x) / 2),  a b = eta k,
// and (Lagarde 2013, "Memo on Fresnel equations", rearranged as sums of squares)
//     R_s = ((a - c)^2 + b^2) / ((a + c)^2 + b^2),
//     R_p = R_s ((a c - s2)^2 + (b c)^2) / ((a c + s2)^2 + (b c)^2).
// Each of a, b is computed from the sum without cancellation and the other from a b = eta k, so
// the eta -> 1, k -> 0 limit (reflectance ~1e-8) keeps its relative precision. Double
// precision throughout: in float the few-1e-4 reflectance near eta = 1 would be lost.
double fresnel_complex(double c, double eta, double k) {
    c = std::clamp(c, 0.0, 1.0);
    double s2 = 1.0 - c * c;
    double x = eta * eta - k * k - s2;
    double t = std::sqrt(x * x + 4.0 * eta * eta * k * k);
    double a, b;
    if (x >= 0.0) {
        a = std::sqrt(0.5 * (t + x));
        b = a > 0.0 ? eta * k / a : 0.0;
    } else {
        b = std::sqrt(0.5 * (t - x));
        a = eta * k / b;  // b > 0 here: t - x >= -2x > 0
    }
    double den_s = sqr(a + c) + b * b;
    if (!(den_s > 0.0)) return 1.0;  // c = 0 with eta + i k = 1: the grazing limit, as dielectric
    double rs = (sqr(a - c) + b * b) / den_s;
    double den_p = sqr(a * c + s2) + sqr(b * c);
    double rp = den_p > 0.0 ? rs * (sqr(a * c - s2) + sqr(b * c)) / den_p : rs;
    return 0.5 * (rs + rp);
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
    return float(std::clamp(fresnel_complex(cos_i, double(eta), double(k)), 0.0, 1.0));
}

Rgb Fresnel::eval_exact(float cos_i) const {
    cos_i = std::clamp(cos_i, 0.f, 1.f);
    if (m_kind == Kind::Dielectric) return Rgb(fresnel_dielectric(cos_i, m_a.r));
    return {fresnel_conductor(cos_i, m_a.r, m_b.r), fresnel_conductor(cos_i, m_a.g, m_b.g),
            fresnel_conductor(cos_i, m_a.b, m_b.b)};
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
