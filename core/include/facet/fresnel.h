// Fresnel reflectance F(cos theta_i) for the mirror and microfacet lobes.
//
// Conventions: `eval(cos_i)` takes the cosine between the incident direction and the (micro)
// surface normal, from the side of the incident medium; values <= 0 are clamped to grazing
// (F at cos = 0). It returns the unpolarised reflectance per RGB channel, in [0, 1].
//  - Constant: F = value (also "none": value = 1); not physically based, for artistic use.
//  - Dielectric: exact unpolarised Fresnel equations for relative IOR eta = n_t / n_i (real).
//    eta < 1 gives total internal reflection past the critical angle.
//  - Conductor: exact Fresnel equations for a complex IOR eta + i k per channel.
//  - Schlick: F0 + (1 - F0)(1 - cos)^5 (Schlick 1994), with F0 per channel.
#pragma once

#include "facet/types.h"

namespace facet {

class Fresnel {
  public:
    enum class Kind : std::uint8_t { Constant, Dielectric, Conductor, Schlick };

    static Fresnel constant(const Rgb& value) { return Fresnel(Kind::Constant, value, Rgb(0.f)); }
    static Fresnel none() { return constant(Rgb(1.f)); }
    static Fresnel dielectric(float eta) { return Fresnel(Kind::Dielectric, Rgb(eta), Rgb(0.f)); }
    static Fresnel conductor(const Rgb& eta, const Rgb& k) {
        return Fresnel(Kind::Conductor, eta, k);
    }
    static Fresnel schlick(const Rgb& f0) { return Fresnel(Kind::Schlick, f0, Rgb(0.f)); }

    // Constant and Schlick are inline (the hot microfacet path); the exact equations are not.
    Rgb eval(float cos_i) const {
        if (m_kind == Kind::Schlick) {
            float m = 1.f - std::clamp(cos_i, 0.f, 1.f);
            float m5 = (m * m) * (m * m) * m;
            return m_a + (Rgb(1.f) - m_a) * m5;
        }
        if (m_kind == Kind::Constant) return m_a;
        return eval_exact(cos_i);
    }
    Kind kind() const { return m_kind; }
    // True when F does not depend on the angle (Constant); lets models skip the evaluation.
    bool is_constant() const { return m_kind == Kind::Constant; }
    // Hemispherical average F_avg = 2 * integral_0^1 F(mu) mu dmu (Kulla & Conty 2017, eq. 15),
    // by 64-point Gauss-Legendre quadrature (smooth integrand: error < 1e-6).
    Rgb average() const;

    const Rgb& eta() const { return m_a; }
    const Rgb& k() const { return m_b; }
    const Rgb& f0() const { return m_a; }  // Schlick's F0

  private:
    Rgb eval_exact(float cos_i) const;  // Dielectric and Conductor
    Fresnel(Kind kind, const Rgb& a, const Rgb& b) : m_kind(kind), m_a(a), m_b(b) {}
    Kind m_kind;
    Rgb m_a;  // Constant: value; Dielectric: eta (all channels); Conductor: eta; Schlick: F0
    Rgb m_b;  // Conductor: k
};

// Scalar exact dielectric Fresnel (unpolarised) for relative IOR eta; cos_i in [0, 1].
float fresnel_dielectric(float cos_i, float eta);
// Scalar exact conductor Fresnel for complex IOR eta + i k; cos_i in [0, 1].
float fresnel_conductor(float cos_i, float eta, float k);

}  // namespace facet
