// Microfacet distributions (Blinn, Beckmann, GGX; isotropic and anisotropic) and the microfacet
// reflection BxDF f = D G F / (4 cos_i cos_o) (Cohen & Wallace eq. 2.37; Walter et al. 2007).
//
// Conventions (facet/bxdf.h and facet/frame.h hold for everything here):
//  - Local shading frame, z = shading normal n; x is the "u" tangent: alpha_u / exponent_u act
//    along x, alpha_v / exponent_v along y. Directions are unit and point away from the surface.
//  - A microfacet normal wm is a unit vector; D(wm) is a density per unit solid angle of wm,
//    normalised so that int D(wm) cos(theta_m) dwm = 1 (projected-area normalisation).
//  - Slopes: a normal wm = (-x, -y, 1) / |(-x, -y, 1)| has slopes (x, y); P22(x, y) =
//    D(wm) cos^4(theta_m) is the slope density. Anisotropy stretches slopes: x by alpha_u,
//    y by alpha_v ("stretch invariance", Heitz 2014 §5).
//  - Lambda(w) is the exact Smith Lambda of the distribution; G1 = 1 / (1 + Lambda) and the
//    height-correlated G = 1 / (1 + Lambda(wo) + Lambda(wi)) (Heitz 2014, eq. 99). Lambda is
//    even in w.z: it depends on the angle to the normal only through |cos theta|.
//  - Visible normals D_w(wm) = G1(w) / cos(theta_w) D(wm) <w, wm>+ (Heitz 2014, eq. 38).
//  - pdf(w, wm) is the density of sample_wm(w, u) per unit solid angle of wm:
//      GGX, Beckmann: the visible-normal density D_w(wm) (exact visible-normal samplers);
//      Blinn:         D(wm) cos(theta_m), independent of w (exact sampler of D cos).
//  - Roughness. GGX / Beckmann take alpha >= 0 (alpha = RMS slope * sqrt 2 for Beckmann).
//    Blinn takes exponents kappa >= 0 (D proportional to (n.h)^kappa, eq. 2.38). Alphas below
//    kMinAlpha are clamped to it internally (only to keep D finite; such lobes are mirrors).
//  - equivalent_alpha(): sqrt(alpha_u alpha_v) for GGX / Beckmann; sqrt(2 / nu) for Blinn,
//    nu = sqrt((kappa_u + 2)(kappa_v + 2)) (the classical Blinn <-> Beckmann match
//    alpha^2 = 2 / (kappa + 2)). A lobe with equivalent_alpha() < kSmoothAlpha is *the mirror*:
//    MicrofacetReflection then behaves exactly like MirrorReflection (delta lobe).
//
// Blinn as a Student-t slope distribution (Ribardiere et al. 2017, "STD: Student's
// t-Distribution of Slopes"): P22(r) = (kappa + 2) / (2 pi) (1 + r^2)^(-(kappa + 4) / 2) is a
// bivariate Student-t with nu = kappa + 2 degrees of freedom and scale 1 / sqrt(nu). Its exact
// Smith Lambda, with mu = cot(theta) / alpha_phi and c = Gamma((nu + 1) / 2) / (Gamma(nu / 2)
// sqrt(pi)), is
//     Lambda(mu) = c / ((nu - 1) mu) (1 + mu^2)^((1 - nu) / 2) - 1/2 I_{1 / (1 + mu^2)}(nu/2, 1/2)
// (I = regularised incomplete beta). kappa = 0 gives exactly GGX with alpha = 1. The anisotropic
// Blinn (kappa_u, kappa_v) is the stretched Student-t with nu = sqrt((ku + 2)(kv + 2)) and
// stretches alpha_u = sqrt(nu / (ku + 2)), alpha_v = sqrt(nu / (kv + 2)) (alpha_u alpha_v = 1);
// its normalisation equals Ashikhmin-Shirley's sqrt((ku + 2)(kv + 2)) / (2 pi).
// Cost: the ibeta term costs 0.1-3 us per call, so lambda() factors Lambda = first(mu) rho(mu)
// with first = c / ((nu - 1) mu) (1 + mu^2)^((1 - nu) / 2) in closed form (it carries the whole
// dynamic range: ~k / mu at grazing, the power tail) and the slowly varying ratio rho in (0, 1]
// (1 at mu = 0, 1 / nu at mu = inf, ~1 / (2 a^2) in the Beckmann-like range a = mu / s >> 1)
// tabulated per distribution at construction (kBlinnTableSize ibeta calls, ~0.3 ms) on
// v = mu / (mu + s), s = sqrt(2 / nu) the slope scale, Catmull-Rom. Lambda and G1 stay
// relatively accurate from the horizon to the underflow (tests: BlinnLambdaTable and the
// stress test against the double oracle).
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "facet/bxdf.h"
#include "facet/fresnel.h"

namespace facet {

struct QuadratureRule;

enum class DistributionKind : std::uint8_t { Blinn, Beckmann, GGX };

// Below this equivalent alpha a microfacet lobe *is* the mirror. At alpha = 1e-4 the lobe is
// 1e-4 rad (0.006 degrees) wide: far below a pixel's footprint in any realistic image, while D
// peaks at 1 / (pi alpha^2) ~ 3e7, still comfortably inside float range together with the
// 1 / cos factors of f.
inline constexpr float kSmoothAlpha = 1e-4f;

// Alphas are clamped to at least this inside D, Lambda and the samplers so that
// (m_x / alpha)^4 stays finite in float; any lobe this narrow is already the mirror.
inline constexpr float kMinAlpha = 1e-8f;

class MicrofacetDistribution {
  public:
    // Blinn with exponents along x and y (kappa >= 0; equal exponents = isotropic Blinn).
    static MicrofacetDistribution blinn(float exponent_u, float exponent_v);
    // Beckmann (alpha >= 0) and GGX / Trowbridge-Reitz (alpha >= 0), roughness along x and y.
    static MicrofacetDistribution beckmann(float alpha_u, float alpha_v);
    static MicrofacetDistribution ggx(float alpha_u, float alpha_v);

    DistributionKind kind() const { return m_kind; }

    // Distribution of normals, per unit solid angle of wm; 0 for wm.z <= 0.
    float D(const Vec3& wm) const;
    // Exact Smith Lambda for direction w (depends on |w.z|); +inf at w.z = 0.
    float lambda(const Vec3& w) const;
    // Smith masking 1 / (1 + Lambda(w)), in [0, 1].
    float G1(const Vec3& w) const { return 1.f / (1.f + lambda(w)); }
    // Height-correlated masking-shadowing (Heitz 2014, eq. 99), in [0, 1].
    float G(const Vec3& wo, const Vec3& wi) const { return 1.f / (1.f + lambda(wo) + lambda(wi)); }
    // Distribution of visible normals from w: G1(w) / cos(theta_w) D(wm) <w, wm>+, per solid
    // angle of wm; 0 when w.z <= 0.
    float D(const Vec3& w, const Vec3& wm) const;
    // Density of sample_wm(w, .) per unit solid angle of wm (see the header comment: visible
    // normals for GGX / Beckmann, D(wm) cos(theta_m) for Blinn). 0 when w.z <= 0.
    float pdf(const Vec3& w, const Vec3& wm) const;
    // Draws a microfacet normal (unit, wm.z >= 0) for w in the upper hemisphere, u in [0,1)^2.
    // Never returns NaN; a degenerate draw returns n = (0, 0, 1).
    Vec3 sample_wm(const Vec3& w, Vec2 u) const;

    bool effectively_smooth() const { return m_equivalent_alpha < kSmoothAlpha; }
    float equivalent_alpha() const { return m_equivalent_alpha; }

    // The slope stretches along x and y (alpha for GGX / Beckmann, the Student-t stretches for
    // Blinn, clamped to kMinAlpha) and, for Blinn, the degrees of freedom nu (0 otherwise).
    float alpha_x() const { return m_ax; }
    float alpha_y() const { return m_ay; }
    float nu() const { return float(m_nu); }

  private:
    friend class MicrofacetReflection;
    friend class MicrofacetBatch;  // reads the Blinn constants for its vectorised kernel
    MicrofacetDistribution() = default;

    // Blinn Lambda: when (nu - 1) / 2 log(1 + mu^2) reaches this, Lambda is 0 in float (both
    // of its terms are below exp(-110) ~ 2e-48 times c / ((nu - 1) mu) <= 1).
    static constexpr float blinn_zero_lambda_exponent() { return 110.f; }

    // mu = cot(theta) / alpha_phi = |w.z| / |(alpha_x w.x, alpha_y w.y)| (stretched cotangent).
    double mu(const Vec3& w) const;
    // Lambda of the unit (unstretched) distribution as a function of mu (double precision);
    // Beckmann only in practice (GGX and Blinn have float paths in lambda()).
    double lambda_of_mu(double mu) const;
    // Draws slopes of D(wm) cos(theta_m) (not visible normals) and returns the normal; used by
    // the Blinn sampler and the albedo quadrature.
    Vec3 sample_d_cos(Vec2 u) const;
    Vec3 sample_beckmann_visible(const Vec3& w, Vec2 u) const;
    Vec3 sample_ggx_visible(const Vec3& w, Vec2 u) const;

    DistributionKind m_kind = DistributionKind::GGX;
    float m_ax = 1.f, m_ay = 1.f;          // slope stretches along x, y
    float m_inv_ax = 1.f, m_inv_ay = 1.f;  // GGX: 1 / m_ax, 1 / m_ay (the fast path multiplies)
    float m_equivalent_alpha = 1.f;
    float m_norm = 0.f;      // GGX: 1 / (pi ax ay)
    float m_log_norm = 0.f;  // Beckmann: log(1 / (pi ax ay)); Blinn: log(nu / (2 pi))
    double m_nu = 0.0;       // Blinn degrees of freedom (nu = kappa + 2 when isotropic)
    double m_blinn_k = 0.0;  // Blinn: c / (nu - 1), see the header comment
    // Blinn: rho(v) at kBlinnTableSize nodes v_j = j / (kBlinnTableSize - 1), stored from
    // index 1, with one extrapolated ghost node at each end for Catmull-Rom; shared by copies
    // (the distribution is a value type).
    std::shared_ptr<const std::vector<float>> m_blinn_rho;
    float m_blinn_s = 1.f;           // Blinn: sqrt(2 / nu), the scale of v = mu / (mu + s)
    float m_blinn_kf = 0.f;          // Blinn: m_blinn_k in float
    float m_blinn_half_nu_m1 = 0.f;  // Blinn: (nu - 1) / 2
    // The Blinn rho table at v = mu / (mu + s) in [0, 1].
    float blinn_rho(float v) const;

  public:
    static constexpr int kBlinnTableSize = 256;
};

// Microfacet reflection f = scale * D G F / (4 cos_i cos_o) (Cohen & Wallace eq. 2.37),
// optionally plus the Kulla & Conty (2017) multiple-scattering compensation lobe
//     f_ms = scale * (1 - E(mu_o)) (1 - E(mu_i)) / (pi (1 - E_avg)) * F_ms,
//     F_ms = F_avg^2 E_avg / (1 - F_avg (1 - E_avg)),
// where E(mu) is the F = 1 single-scattering albedo of this distribution (for anisotropic
// lobes E(mu, phi), tabulated over the stretched direction, see albedo_table), tabulated at
// construction on kTableSize nodes uniform in sqrt(mu) (linear interpolation in sqrt(mu)) by
// Gauss-Legendre quadrature in slope space, and
// E_avg = 2 int E(mu) mu dmu of that interpolant, exactly.
//
// Conventions: facet/bxdf.h. Sampling draws the distribution's sample_wm and reflects
// (Jacobian 1 / (4 |wo.wm|)); with compensation, the cosine-weighted f_ms lobe is chosen with
// probability p_ms(wo) = w_ms / (w_ss + w_ms), w_ss = E(mu_o) lum(F_avg), w_ms = (1 - E(mu_o))
// lum(F_ms), and pdf() returns the matching mixture. Samples below the horizon -> nullopt.
// When the distribution is effectively smooth the lobe IS the mirror: f = pdf = 0, sample_f
// returns the reflected direction with pdf 1 and f = scale F(cos) / cos, flags Specular.
class MicrofacetReflection {
  public:
    MicrofacetReflection(const MicrofacetDistribution& d, const Fresnel& fresnel, const Rgb& scale,
                         bool energy_compensation);

    static constexpr int kTableSize = 64;    // nodes in sqrt(mu)
    static constexpr int kPhiTableSize = 9;  // nodes in phi over [0, pi/2], anisotropic only

    // The compensation table of an isotropic lobe: E(mu_k) at the nodes (see albedo_table) and
    // E_avg. It depends on the distribution only (F = 1), so the staged build of a textured
    // roughness (facet/staged_material.h) tabulates it over alpha once and interpolates.
    struct Compensation {
        std::array<float, kTableSize> e{};
        float e_avg = 1.f;
    };
    // The compensated lobe with its table given instead of computed (d isotropic; ignored when
    // d is effectively smooth): bit for bit the lobe of the first constructor when `c` is that
    // lobe's compensation(). `f_avg`, when given, is fresnel.average() (the staged build
    // computes it once for a Fresnel that no texture changes).
    MicrofacetReflection(const MicrofacetDistribution& d, const Fresnel& fresnel, const Rgb& scale,
                         const Compensation& c, const Rgb* f_avg = nullptr);
    // This lobe's table (isotropic lobes with energy compensation; smooth: E = 1).
    Compensation compensation() const;

    Rgb f(const Vec3& wo, const Vec3& wi) const;
    float pdf(const Vec3& wo, const Vec3& wi) const;
    BSDFEval eval(const Vec3& wo, const Vec3& wi) const;  // f and pdf together
    std::optional<BSDFSample> sample_f(const Vec3& wo, float uc, Vec2 u) const;
    BxDFFlags flags() const { return m_smooth ? BxDFFlags::Specular : BxDFFlags::Glossy; }

    // The two terms of f separately (f = f_single + f_multiple): the single-scattering
    // D G F / (4 cos_i cos_o), and the compensation lobe f_ms (0 without compensation). The
    // reflectance quadrature integrates them through different maps: f_single is peaked,
    // f_ms is cosine-like with kinks at the table nodes.
    Rgb f_single(const Vec3& wo, const Vec3& wi) const;
    Rgb f_multiple(const Vec3& wo, const Vec3& wi) const;
    bool has_multiple_scattering() const { return m_has_ms; }
    // Anisotropic compensation tables depend on the azimuth too (see albedo_table).
    bool multiple_scattering_is_isotropic() const { return m_phi_count == 1; }

    const MicrofacetDistribution& distribution() const { return m_distribution; }
    const Fresnel& fresnel() const { return m_fresnel; }
    const Rgb& scale() const { return m_scale; }
    bool energy_compensation() const { return m_energy_compensation; }

    // The tabulated F = 1 single-scattering albedo E(mu) (linear interpolation; 1 when the lobe
    // is smooth, and also 1 when compensation is off, since no table is built then) and E_avg.
    // For anisotropic lobes E depends on phi too: albedo_table(w) reads the table over the
    // stretched direction (mu_s, phi_s); albedo_table(mu) is its phi_s = 0 row.
    float albedo_table(float mu) const { return albedo_row(0, mu); }
    float albedo_table(const Vec3& w) const;
    float albedo_average() const { return m_e_avg; }

  private:
    friend class MicrofacetBatch;  // the batch's non-vectorised path shares the helpers below
    // f and / or pdf (either pointer may be null) sharing the half vector, D and Lambda(wo).
    // with_ms = false leaves out f_ms from f (f_single); pdf is unaffected.
    void evaluate(const Vec3& wo, const Vec3& wi, Rgb* f_out, float* pdf_out,
                  bool with_ms = true) const;
    void evaluate_ggx(const Vec3& wo, const Vec3& wi, Rgb* f_out, float* pdf_out,
                      bool with_ms) const;
    // The general (Blinn, Beckmann) path's pieces: the half vector's terms (false when wo + wi
    // = 0) and f_single from them and the two Lambdas.
    bool half_vector_terms(const Vec3& wo, const Vec3& wi, Vec3& wm, float& c, float& d) const;
    Rgb single_from(float c, float d, float lam_o, float lam_i, float cos_o, float cos_i) const;
    // The compensation lobe's value f_ms(wo, wi) (both above the horizon, m_has_ms).
    Rgb ms_lobe(const Vec3& wo, const Vec3& wi) const;
    // Probability of sampling the f_ms lobe at cos theta_o = mu_o.
    float ms_probability(const Vec3& wo) const;
    float albedo_row(int row, float mu) const;
    // The constructors' last step: F_ms and the lobe weights from m_e_avg (table built) and
    // F_avg (`f_avg`, or computed from the Fresnel when null).
    void finish_compensation(const Rgb* f_avg = nullptr);
    // E_avg of the table's interpolant, exactly (isotropic) / by cellwise quadrature.
    float isotropic_average() const;
    float anisotropic_average(const QuadratureRule& gu) const;

    MicrofacetDistribution m_distribution;
    Fresnel m_fresnel;
    Rgb m_scale;
    bool m_energy_compensation;
    bool m_smooth;
    bool m_has_ms = false;  // compensation on and the lobe misses some energy
    // E(mu_k, phi_j), mu_k = (k / (kTableSize - 1))^2, phi_j = j / (m_phi_count - 1) * pi / 2
    // (of the stretched direction when anisotropic): isotropic lobes in m_e (row 0), anisotropic
    // ones at (*m_e_rows)[j * kTableSize + k], shared by copies. Only with compensation
    // (m_has_table): a lobe without reads E = 1 and is built and copied per textured hit, so
    // its row is an empty optional, neither filled nor copied.
    std::optional<std::array<float, kTableSize>> m_e;
    std::shared_ptr<const std::vector<float>> m_e_rows;
    bool m_has_table = false;
    int m_phi_count = 1;
    Vec2 m_stretch{1.f};  // (ax, ay): anisotropic tables are indexed by normalize(ax x, ay y, z)
    float m_e_avg = 1.f;
    Rgb m_ms_factor{0.f};              // scale * F_ms / (pi (1 - E_avg))
    float m_w_ss = 0.f, m_w_ms = 0.f;  // lum(F_avg), lum(F_ms) for lobe selection
};

}  // namespace facet
