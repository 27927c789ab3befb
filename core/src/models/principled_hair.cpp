// principled_hair: Blender's Principled Hair BSDF as Cycles 3.4 evaluates it (the closure of
// bsdf_hair_principled.h: Chiang et al. 2016's near-field fibre model with d'Eon et al. 2011's
// longitudinal lobes), for a round fibre whose direction is the frame's x axis (the shape's
// dpdu: a curve's tangent, or a mesh's u direction).
//
// The fibre frame (Cycles' thick-curve setup): X = x, Y = normalize(X x wo), Z = X x Y; the offset
// across the fibre is h = dot(Ng x X, Z) with Ng = z turned toward the viewer; wo has longitude
// sin theta_o = wo.x and azimuth phi_o = -pi/2 about X. With theta_i, phi_i those of wi,
//   F(wo, wi) = sum_{p=0..2} A_p M_p(theta_i + shift_p, theta_o) N_p(phi_i - phi_o)
//             + A_3 M(theta_i, theta_o; 4v) / (2 pi),
//   A_0 = f, A_1 = (1 - f)^2 T, A_2 = A_1 T f, A_3 = A_2 T f / (1 - T f),
//   f = Fresnel(cos theta_o cos gamma_o, ior), T = exp(-sigma 2 cos gamma_t / cos theta_t),
//   shift_0 = 2 alpha, shift_1 = -alpha, shift_2 = -4 alpha (alpha = offset, the cuticle tilt),
//   M_p: d'Eon's lobe of variance v_0 (the coat-scaled roughness), v/4, 4v,
//   N_p: a logistic of scale s trimmed to [-pi, pi] about 2 p gamma_t - 2 gamma_o + p pi,
// with v and s Cycles' maps of roughness and radial_roughness. Cycles' closure returns F as its
// eval (the cosine included), so f = F / |cos theta_i| about z and f |cos| is exactly F.
//  - Energy: with alpha = 0 and no absorption each M_p and N_p integrates to 1 and the A_p sum to
//    1, so the albedo is 1 at every wo (tests/core/test_hair.cpp). The tilt alpha moves the
//    lobes without renormalising them, as in Cycles.
//  - Not reciprocal: h, A_p and the N_p centres come from wo alone (Cycles'). Swapping wo and wi
//    gives the same f only where those agree: wo and wi at the same azimuth about the fibre,
//    mirrored in its normal plane, with alpha = 0.
//  - Sampling: the lobe p with probability proportional to the luminance of A_p (Cycles'),
//    theta from d'Eon's lobe (a von Mises-Fisher marginal) and then tilted, phi from N_p (p < 3)
//    or uniform. pdf() is the density this draws, including the Jacobian of the tilt and the
//    fold at the poles, and the R lobe is drawn with its own (coat) variance: Cycles' pdf leaves
//    out the tilt's Jacobian and draws R with v, so its pdf is not its sampler's density there.
//  - Evaluation: the modified Bessel function I0 is evaluated to double precision
//    (facet/bessel.h, 1.2e-14 relative; Cycles' float series stops after ten terms, 0.3% low at
//    x = cos theta_i cos theta_o / v = 10 and 2% at 12, and its asymptote above 12 is 0.6% low
//    there), and the exponent of M_p as (cos(theta_i + theta_o) - 1) / v without cancellation.
//    What depends on wo alone (Setup) is computed once per wo (each thread keeps the last one
//    for the next eval or sample_f with the same wo and parameters: setup_of), the lobes' tilts
//    by the angle-addition formulas from the sine and cosine of alpha, and the density of a
//    tilted lobe reuses the lobe's own M_p where its preimage is theta_i + shift.
// Conventions: facet/inline_bxdf.h; flagged Transmission (wi on either side: a fibre scatters
// over the whole sphere), so the frame is the shape's (facet/dielectric.h); kReadsTangent.
#include <algorithm>
#include <cmath>
#include <cstring>

#include "facet/bessel.h"
#include "facet/fresnel.h"
#include "model_unit.h"

namespace facet {

namespace {

constexpr double kPi2D = 2.0 * kPiD;

// d'Eon's longitudinal lobe M(theta_i, theta_o; v) = csch(1/v) / (2 v) exp(-sin_i sin_o / v)
// I0(cos_i cos_o / v), normalised as int M cos theta_i dtheta_i = 1 over [-pi/2, pi/2], given
// norm = csch(1/v) exp(1/v) / (2 v) = 1 / (v (1 - exp(-2/v))): exp(-1/v) joins the exponent,
// which is written (cos(t_i + t_o) - 1) / v without cancellation.
double longitudinal(double si, double ci, double so, double co, double v, double norm) {
    const double c = ci * co - si * so, s = si * co + ci * so;
    const double cos_sum_m1 = c > 0.0 ? -s * s / (1.0 + c) : c - 1.0;  // cos(t_i + t_o) - 1
    const double inv_v = 1.0 / v;
    return norm * bessel_i0_scaled(ci * co * inv_v, cos_sum_m1 * inv_v);
}

double longitudinal_norm(double v) {
    return 1.0 / (v * -std::expm1(-2.0 / v));
}

double wrap_angle(double a) {
    return a - kPi2D * std::floor((a + kPiD) / kPi2D);
}

// Cycles' map of a roughness in [0, 1] to the logistic variance v.
double variance_of(double r) {
    return std::pow(0.726 * r + 0.812 * r * r + 3.700 * std::pow(r, 20.0), 2.0);
}

class PrincipledHair {
  public:
    static constexpr bool kReadsTangent = true;

    // sigma: absorption per unit diameter; roughness, radial roughness, coat in [0, 1] (after
    // Cycles' randomisation); alpha the tilt in radians; eta >= 1.
    PrincipledHair(const Rgb& sigma, double roughness, double radial, double coat, double alpha,
                   double eta)
        : m_sigma(sigma), m_eta(float(eta)) {
        const double r = std::clamp(roughness, 0.001, 1.0), rs = std::clamp(radial, 0.001, 1.0);
        const double r0 = std::clamp((1.0 - std::clamp(coat, 0.0, 1.0)) * r, 0.001, 1.0);
        m_v = float(variance_of(r));
        m_v0 = float(variance_of(r0));
        m_s = float((0.265 * rs + 1.194 * rs * rs + 5.372 * std::pow(rs, 22.0)) *
                    std::sqrt(kPiD / 8.0));
        for (int p = 0; p < 3; ++p) m_norm[p] = float(longitudinal_norm(lobe_variance(p)));
        const double s = m_s;
        m_logistic = float(1.0 / (s * std::tanh(kPiD / (2.0 * s))));
        m_logistic_cdf = float(1.0 / (1.0 + std::exp(kPiD / s)));
        m_sin_alpha = float(std::sin(double(float(alpha))));
        m_cos_alpha = float(std::cos(double(float(alpha))));
    }

    BSDFEval eval(const Vec3& wo, const Vec3& wi) const {
        const Setup* g = setup_of(wo);
        if (!g) return {};
        return eval(*g, wi);
    }

    std::optional<BSDFSample> sample_f(const Vec3& wo, float uc, Vec2 u) const {
        const Setup* pg = setup_of(wo);
        if (!pg) return std::nullopt;
        const Setup& g = *pg;
        // The lobe, and uc rescaled within its interval for phi.
        int p = 0;
        double rest = uc;
        while (p < 3 && !(rest < g.w[p])) rest -= g.w[p++];
        if (!(g.w[p] > 0.0)) return std::nullopt;
        const double u_phi = std::clamp(rest / g.w[p], 0.0, 1.0 - 1e-9);
        // theta' from d'Eon's lobe: the cosine to its axis (von Mises-Fisher, kappa = 1/v).
        const double v = lobe_variance(p);
        const double l = v * std::log(std::max(u.x + (1.0 - u.x) * std::exp(-2.0 / v), 1e-300));
        const double fac = std::max(1.0 + l, -1.0),
                     sin_fac = std::sqrt(std::max(0.0, -l * (2.0 + l)));
        const double st =
            std::clamp(-fac * g.sin_o + sin_fac * std::cos(kPi2D * u.y) * g.cos_o, -1.0, 1.0);
        // Tilted: theta_i = theta' - shift, folded at the poles (sin kept, |cos|).
        const double ct = std::sqrt(std::max(0.0, 1.0 - st * st));
        double si = st, ci = ct;
        if (p < 3) {
            const Angle a = lobe_shift(p, g);
            si = st * a.c - ct * a.s;
            ci = std::fabs(ct * a.c + st * a.s);
        }
        const double phi = p < 3 ? g.center[p] + sample_trimmed_logistic(u_phi) : kPi2D * u_phi;
        const double phi_i = phi - 0.5 * kPiD;
        const DVec3 w = DVec3(si, 0.0, 0.0) + (ci * std::cos(phi_i)) * DVec3(g.y) +
                        (ci * std::sin(phi_i)) * DVec3(g.z);
        const Vec3 wi(glm::normalize(w));
        const BSDFEval e = eval(g, wi);
        if (!(e.pdf > 0.f) || !(wi.z != 0.f) || !is_finite(e.f)) return std::nullopt;
        return BSDFSample{e.f, wi, e.pdf, flags()};
    }

    BxDFFlags flags() const { return BxDFFlags::Glossy | BxDFFlags::Transmission; }

  private:
    struct Angle {
        double s, c;  // sine and cosine
    };

    // What depends on wo alone: the fibre frame, the angles, the attenuations and the tilts.
    struct Setup {
        Vec3 y, z;  // the fibre frame's Y and Z in the local frame (X = x)
        double sin_o, cos_o;
        double center[3];  // N_p's centres 2 p gamma_t - 2 gamma_o + p pi
        Angle shift[3];    // the lobes' tilts (lobe_shift)
        DVec3 ap[4];
        double w[4];  // lobe probabilities (luminance of A_p, normalised)
    };

    // What setup() reads: wo and the parameters it depends on, compared bit for bit.
    struct SetupKey {
        float wo[3], sigma[3], eta, sin_alpha, cos_alpha;
    };
    static_assert(sizeof(Rgb) == 3 * sizeof(float) && sizeof(SetupKey) == 9 * sizeof(float));

    // The setup for wo: the last one this thread computed when its key matches (a path vertex
    // evaluates its light sample, then samples its next direction, both from the same wo), else
    // computed now. Null when wo has no frame. The same values as computing it each time.
    const Setup* setup_of(const Vec3& wo) const {
        struct Cache {
            SetupKey key;
            Setup g;
            bool ok = false, valid = false;
        };
        thread_local Cache cache;
        SetupKey key;
        std::memcpy(key.wo, &wo, sizeof key.wo);
        std::memcpy(key.sigma, &m_sigma, sizeof key.sigma);
        key.eta = m_eta;
        key.sin_alpha = m_sin_alpha;
        key.cos_alpha = m_cos_alpha;
        if (!cache.valid || std::memcmp(&key, &cache.key, sizeof key) != 0) {
            cache.key = key;
            cache.ok = setup(wo, cache.g);
            cache.valid = true;
        }
        return cache.ok ? &cache.g : nullptr;
    }

    bool setup(const Vec3& wo, Setup& g) const {
        const double r2 = double(wo.y) * wo.y + double(wo.z) * wo.z;
        if (!(r2 > 1e-14)) return false;  // wo along the fibre: no frame (as Cycles' zero Y)
        const double r = std::sqrt(r2);
        g.y = Vec3(0.f, float(-wo.z / r), float(wo.y / r));
        g.z = Vec3(0.f, float(-wo.y / r), float(-wo.z / r));
        const double h = std::clamp((wo.z < 0.f ? 1.0 : -1.0) * wo.y / r, -1.0, 1.0);
        g.sin_o = std::clamp(double(wo.x), -1.0, 1.0);
        g.cos_o = std::sqrt(std::max(0.0, 1.0 - g.sin_o * g.sin_o));
        const double eta = m_eta;
        const double sin_t = g.sin_o / eta, cos_t = std::sqrt(1.0 - sin_t * sin_t);
        const double sin_gt = h * g.cos_o / std::sqrt(eta * eta - g.sin_o * g.sin_o);
        const double cos_go = std::sqrt(std::max(0.0, 1.0 - h * h));
        const double cos_gt = std::sqrt(std::max(0.0, 1.0 - sin_gt * sin_gt));
        const double gamma_o = std::asin(h);
        const double gamma_t = std::asin(std::clamp(sin_gt, -1.0, 1.0));
        for (int p = 0; p < 3; ++p) g.center[p] = 2.0 * p * gamma_t - 2.0 * gamma_o + p * kPiD;
        // The tilt alpha from its sine and cosine (made a unit pair again in double), and the
        // lobes' 2 alpha, -alpha and -4 alpha by the double-angle formulas.
        const double sa0 = m_sin_alpha, ca0 = m_cos_alpha, len = std::sqrt(sa0 * sa0 + ca0 * ca0);
        const double sa = sa0 / len, ca = ca0 / len;
        const double s2 = 2.0 * sa * ca, c2 = ca * ca - sa * sa;
        g.shift[0] = {s2, c2};
        g.shift[1] = {-sa, ca};
        g.shift[2] = {-2.0 * s2 * c2, c2 * c2 - s2 * s2};
        const DVec3 T = glm::exp(-DVec3(m_sigma) * (2.0 * cos_gt / cos_t));
        const double f = fresnel_dielectric(float(g.cos_o * cos_go), m_eta);
        g.ap[0] = DVec3(f);
        DVec3 col = (1.0 - f) * (1.0 - f) * T;
        g.ap[1] = col;
        col *= T * f;
        g.ap[2] = col;
        const DVec3 tf = T * f;
        for (int c = 0; c < 3; ++c) col[c] *= tf[c] < 1.0 ? tf[c] / (1.0 - tf[c]) : 0.0;
        g.ap[3] = col;
        double total = 0.0;
        for (int p = 0; p < 4; ++p) {
            g.w[p] = p == 0 ? f : 0.2126 * g.ap[p].x + 0.7152 * g.ap[p].y + 0.0722 * g.ap[p].z;
            total += g.w[p];
        }
        for (double& w : g.w) w = total > 0.0 ? w / total : 0.0;
        return total > 0.0;
    }

    // f and pdf at wi for the wo of `g`.
    BSDFEval eval(const Setup& g, const Vec3& wi) const {
        const double si = std::clamp(double(wi.x), -1.0, 1.0);
        const double ci = std::sqrt(double(wi.y) * wi.y + double(wi.z) * wi.z);
        const double phi = std::atan2(double(glm::dot(wi, g.z)), double(glm::dot(wi, g.y))) +
                           0.5 * kPiD;  // phi_i - phi_o, phi_o = -pi/2
        DVec3 F(0.0);
        double pdf = 0.0;
        for (int p = 0; p < 3; ++p) {
            const double v = lobe_variance(p), norm = m_norm[p];
            const Angle a = lobe_shift(p, g);
            const double n = trimmed_logistic(wrap_angle(phi - g.center[p]));
            // Cycles' hair_alpha_angles: sin(theta_i + shift), |cos(theta_i + shift)|.
            const double st = si * a.c + ci * a.s, ct = ci * a.c - si * a.s;
            const double m = longitudinal(st, std::fabs(ct), g.sin_o, g.cos_o, v, norm);
            F += g.ap[p] * (m * n);
            pdf += g.w[p] * tilted_density(si, ci, ct, m, a, g, v, norm) * n;
        }
        const double m3 =
            longitudinal(si, ci, g.sin_o, g.cos_o, lobe_variance(3), m_norm[2]) / kPi2D;
        F += g.ap[3] * m3;
        pdf += g.w[3] * m3;
        const double cos_n = std::fabs(double(wi.z));
        if (!(cos_n > 0.0)) return {Rgb(0.f), float(pdf)};
        return {Rgb(F / cos_n), float(pdf)};
    }

    // The tilt of lobe p's peak (Cycles' hair_alpha_angles: R +2 alpha, TT -alpha, TRT -4 alpha
    // on theta_i) and its variance.
    static Angle lobe_shift(int p, const Setup& g) { return g.shift[p]; }
    double lobe_variance(int p) const {
        return p == 0 ? double(m_v0) : p == 1 ? 0.25 * m_v : 4.0 * m_v;  // TRT and the rest: 4v
    }

    // The logistic of scale s trimmed to [-pi, pi] (normalised there) at x, and its inverse CDF.
    double trimmed_logistic(double x) const {
        const double e = std::exp(-std::fabs(x) / double(m_s));
        return e * double(m_logistic) / ((1.0 + e) * (1.0 + e));
    }
    double sample_trimmed_logistic(double u) const {
        const double c = m_logistic_cdf;  // the logistic's CDF at -pi
        const double y = u * (1.0 - 2.0 * c) + c;
        return std::clamp(-double(m_s) * std::log((1.0 - y) / y), -kPiD, kPiD);
    }

    // The density per solid angle at theta_i (sin si, cos ci) of theta' ~ M(theta') cos theta'
    // on [-pi/2, pi/2] moved by -shift (sine and cosine a) and folded back at the poles (sin
    // kept, cos made positive): the sum over theta_i's preimages theta_i + shift and
    // pi - theta_i + shift of M cos theta', over ci, for those at |theta'| <= pi/2 (a
    // non-negative cosine). The first preimage's M at cos ct is m (eval's own lobe value).
    static double tilted_density(double si, double ci, double ct, double m, Angle a, const Setup& g,
                                 double v, double norm) {
        if (!(ci > 0.0)) return 0.0;
        double sum = ct >= 0.0 ? m * ct : 0.0;
        // pi - theta_i + shift: sine sin(theta_i - shift), cosine -cos(theta_i - shift).
        const double ct2 = -(ci * a.c + si * a.s);
        if (ct2 >= 0.0)
            sum += longitudinal(si * a.c - ci * a.s, ct2, g.sin_o, g.cos_o, v, norm) * ct2;
        return sum / ci;
    }

    Rgb m_sigma;
    float m_v, m_v0, m_s;  // variances of TT (x 1/4), TRT (x 4) and R; logistic scale
    float m_norm[3];       // longitudinal_norm of the variances of R, TT, and TRT (and the rest)
    float m_logistic;      // 1 / (s tanh(pi / (2 s))): the trimmed logistic's normalisation
    float m_logistic_cdf;  // the logistic's CDF at -pi, 1 / (1 + exp(pi / s))
    float m_sin_alpha, m_cos_alpha;  // the tilt alpha (offset)
    float m_eta;
};

// Cycles' absorption of a hair of the given colour at azimuthal roughness x (Chiang et al.'s
// fit): sigma = (log(c) / (5.969 - 0.215 x + 2.532 x^2 - 10.73 x^3 + 5.574 x^4 + 0.245 x^5))^2;
// a channel of 0 is taken as 1e-30 (its T is 0 to float precision, as Cycles' log 0).
DVec3 sigma_from_color(const Rgb& c, double x) {
    const double fac = (((((0.245 * x) + 5.574) * x - 10.73) * x + 2.532) * x - 0.215) * x + 5.969;
    DVec3 s;
    for (int k = 0; k < 3; ++k) {
        const double l = std::log(std::max(double(c[k]), 1e-30)) / fac;
        s[k] = l * l;
    }
    return s;
}

// The parameters' indices in the table below (ParamValues), and the parametrizations.
enum Param : std::size_t {
    kParametrization,
    kColor,
    kMelanin,
    kMelaninRedness,
    kTint,
    kAbsorption,
    kRoughness,
    kRadialRoughness,
    kCoat,
    kIor,
    kOffset,
    kRandomRoughness,
    kRandomColor,
    kRandom
};
enum Parametrization : int { kColorKind, kMelaninKind, kAbsorptionKind };
constexpr const char* kParametrizations[] = {"color", "melanin", "absorption"};

}  // namespace

const ModelInfo& principled_hair_model() {
    static const ModelInfo m{
        .name = "principled_hair",
        .summary =
            "hair fibre as Blender's Principled Hair BSDF (Cycles 3.4, Chiang et al. 2016): R, "
            "TT, TRT and residual lobes of a round dielectric fibre along the surface's "
            "tangent (dpdu); transmits (scatters over the whole sphere), not reciprocal",
        .params = {models::text("parametrization", "color",
                                "how the absorption is given: color (Blender's Direct Coloring), "
                                "melanin (Melanin Concentration) or absorption (Absorption "
                                "Coefficient)",
                                {kParametrizations[0], kParametrizations[1], kParametrizations[2]}),
                   models::color("color", "0.017513 0.005763 0.002059",
                                 "the hair's colour (parametrization color), in [0, 1]"),
                   models::number("melanin", "0.8",
                                  "melanin concentration (parametrization melanin), in [0, 1]"),
                   models::number("melanin_redness", "1",
                                  "fraction of pheomelanin (parametrization melanin), in [0, 1]"),
                   models::color("tint", "1",
                                 "dye colour added to the melanin (parametrization melanin), in "
                                 "[0, 1]"),
                   models::color("absorption_coefficient", "0.245531 0.52 1.365",
                                 "absorption per unit fibre diameter (parametrization absorption), "
                                 "in [0, 1000]"),
                   models::number("roughness", "0.3", "longitudinal roughness, in [0, 1]"),
                   models::number("radial_roughness", "0.3", "azimuthal roughness, in [0, 1]"),
                   models::number("coat", "0",
                                  "smooths the primary reflection R: its roughness is (1 - coat) "
                                  "roughness, in [0, 1]"),
                   models::number("ior", "1.55", "index of refraction of the fibre, in [1, 1000]"),
                   models::number(
                       "offset", "0.0349066",
                       "cuticle tilt in radians (Blender's Offset; default 2 degrees), in "
                       "[-pi/2, pi/2]"),
                   models::number("random_roughness", "0",
                                  "scales roughness and radial_roughness by 1 + 2 (random - 0.5) "
                                  "random_roughness, in [0, 1]"),
                   models::number("random_color", "0",
                                  "scales melanin by 1 + 2 (random - 0.5) random_color "
                                  "(parametrization melanin), in [0, 1]"),
                   models::number("random", "0",
                                  "the random value of the strand (Blender's Random), in [0, 1]")},
        .read =
            [](ParamReader& r, ParamValues& v) {
                const int kind = r.choice(v, kParametrization);
                const std::string because =
                    std::string("with parametrization ") + kParametrizations[kind];
                if (kind != kColorKind) r.forbid("color", because);
                if (kind != kAbsorptionKind) r.forbid("absorption_coefficient", because);
                if (kind != kMelaninKind)
                    for (const char* p : {"melanin", "melanin_redness", "tint", "random_color"})
                        r.forbid(p, because);
                r.number(v, kRandom, 0.0, 0.0, 1.0);
                r.number(v, kRandomRoughness, 0.0, 0.0, 1.0);
                r.number(v, kRoughness, 0.3, 0.0, 1.0);
                r.number(v, kRadialRoughness, 0.3, 0.0, 1.0);
                if (kind == kAbsorptionKind) {
                    r.color(v, kAbsorption, Rgb(0.245531f, 0.52f, 1.365f), 0.0, 1000.0);
                } else if (kind == kMelaninKind) {
                    r.number(v, kMelanin, 0.8, 0.0, 1.0);
                    r.number(v, kMelaninRedness, 1.0, 0.0, 1.0);
                    r.number(v, kRandomColor, 0.0, 0.0, 1.0);
                    r.color(v, kTint, Rgb(1.f), 0.0, 1.0);
                } else {
                    r.color(v, kColor, Rgb(0.017513f, 0.005763f, 0.002059f), 0.0, 1.0);
                }
                r.number(v, kCoat, 0.0, 0.0, 1.0);
                r.number(v, kIor, 1.55, 1.0, 1000.0);
                r.number(v, kOffset, 2.0 * kPiD / 180.0, -0.5 * kPiD, 0.5 * kPiD);
            },
        .make =
            [](const ParamValues& v, Children) {
                const int kind = v.choice(kParametrization);
                const double random = v.number(kRandom);
                const double factor = 1.0 + 2.0 * (random - 0.5) * v.number(kRandomRoughness);
                const double roughness = v.number(kRoughness) * factor;
                const double radial = v.number(kRadialRoughness) * factor;
                DVec3 sigma;
                if (kind == kAbsorptionKind) {
                    sigma = DVec3(v.color(kAbsorption));
                } else if (kind == kMelaninKind) {
                    double melanin = v.number(kMelanin);
                    const double redness = v.number(kMelaninRedness);
                    melanin *= 1.0 + 2.0 * (random - 0.5) * v.number(kRandomColor);
                    melanin = -std::log(std::max(1.0 - melanin, 1e-4));
                    const double eu = melanin * (1.0 - redness), pheo = melanin * redness;
                    sigma = eu * DVec3(0.506, 0.841, 1.653) + pheo * DVec3(0.343, 0.733, 1.924) +
                            sigma_from_color(v.color(kTint), radial);
                } else {
                    sigma = sigma_from_color(v.color(kColor), radial);
                }
                return Material(
                    InlineBxDF(PrincipledHair(Rgb(sigma), roughness, radial, v.number(kCoat),
                                              v.number(kOffset), v.number(kIor))));
            },
        .pov_finish = false};
    return m;
}

}  // namespace facet
