// Microfacet distributions and reflection; see facet/microfacet.h for the conventions.
#include "facet/microfacet.h"

#include <boost/math/special_functions/beta.hpp>
#include <boost/math/special_functions/erf.hpp>
#include <boost/math/special_functions/gamma.hpp>
#include <cmath>
#include <vector>

#include "albedo_table.h"
#include "facet/quadrature.h"
#include "facet/sampling.h"
#include "microfacet_formulas.h"

namespace facet {

namespace {

// Boost.Math policy for the hot paths: never throw, never promote double to long double
// (which would be several times slower and is not needed for a float result).
using namespace boost::math::policies;
using BoostPolicy =
    policy<domain_error<ignore_error>, pole_error<ignore_error>, overflow_error<ignore_error>,
           underflow_error<ignore_error>, evaluation_error<ignore_error>,
           rounding_error<ignore_error>, promote_float<false>, promote_double<false>>;

constexpr double kInvSqrtPiD = 0.56418958354775628695;  // 1 / sqrt(pi)

// Lambda values above this are treated as +inf's square-root regime: for t > 1e30 the GGX form
// t / (2 (1 + sqrt(1 + t))) would compute inf / inf; sqrt(t) / 2 is exact to float precision.
constexpr float kGgxLargeT = 1e30f;

// Beckmann Lambda: for a = cot / alpha >= 9 the exact value is below 1e-37 (exp(-81) / a^3),
// which is 0 next to the 1 in 1 + Lambda; returning 0 avoids computing two denormals.
constexpr double kBeckmannZeroLambdaA = 9.0;

// Beckmann visible-slope inversion: slopes of the unit distribution beyond +-9 have
// probability below erfc(9) ~ 4e-37, far below the 2^-24 resolution of a float sample.
constexpr double kBeckmannMaxSlope = 9.0;
// Newton/bisection stop: |step| below this (relative to 1 + |x|); a float result needs 6e-8.
constexpr double kBeckmannSlopeTolerance = 1e-10;
constexpr int kBeckmannMaxIterations = 60;

Vec3 normalize_or_normal(double x, double y, double z) {
    double len2 = x * x + y * y + z * z;
    if (!(len2 > 0.0) || !std::isfinite(len2)) return {0.f, 0.f, 1.f};
    double inv = 1.0 / std::sqrt(len2);
    return Vec3(float(x * inv), float(y * inv), float(z * inv));
}

// std::fmax(a, b) for floats, inline (GCC calls libm's fmaxf): b when a is NaN, a when b is.
inline float fmax_inline(float a, float b) {
    return a > b ? a : (b == b ? b : a);
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// Construction

MicrofacetDistribution MicrofacetDistribution::ggx(float alpha_u, float alpha_v) {
    MicrofacetDistribution d;
    d.m_kind = DistributionKind::GGX;
    d.m_ax = fmax_inline(alpha_u, kMinAlpha);
    d.m_ay = fmax_inline(alpha_v, kMinAlpha);
    d.m_inv_ax = 1.f / d.m_ax;
    d.m_inv_ay = 1.f / d.m_ay;
    d.m_equivalent_alpha = std::sqrt(fmax_inline(alpha_u, 0.f) * fmax_inline(alpha_v, 0.f));
    d.m_norm = float(1.0 / (kPiD * double(d.m_ax) * double(d.m_ay)));
    return d;
}

MicrofacetDistribution MicrofacetDistribution::beckmann(float alpha_u, float alpha_v) {
    MicrofacetDistribution d = ggx(alpha_u, alpha_v);
    d.m_kind = DistributionKind::Beckmann;
    d.m_log_norm = float(-std::log(kPiD * double(d.m_ax) * double(d.m_ay)));
    return d;
}

MicrofacetDistribution MicrofacetDistribution::blinn(float exponent_u, float exponent_v) {
    MicrofacetDistribution d;
    d.m_kind = DistributionKind::Blinn;
    double ku = std::fmax(double(exponent_u), 0.0), kv = std::fmax(double(exponent_v), 0.0);
    // Stretched Student-t: nu = sqrt((ku + 2)(kv + 2)), stretches with alpha_u alpha_v = 1.
    double nu = ku == kv ? ku + 2.0 : std::sqrt((ku + 2.0) * (kv + 2.0));
    d.m_nu = nu;
    d.m_ax = ku == kv ? 1.f : std::fmax(float(std::sqrt(nu / (ku + 2.0))), kMinAlpha);
    d.m_ay = ku == kv ? 1.f : std::fmax(float(std::sqrt(nu / (kv + 2.0))), kMinAlpha);
    d.m_equivalent_alpha = float(std::sqrt(2.0 / nu));
    d.m_log_norm = float(std::log(nu / (2.0 * kPiD)));
    // c / (nu - 1), c = Gamma((nu + 1) / 2) / (Gamma(nu / 2) sqrt(pi)). Boost's
    // tgamma_delta_ratio(a, 1/2) = Gamma(a) / Gamma(a + 1/2) keeps full double precision for
    // any nu (an lgamma difference loses ~1e-16 lgamma(nu) absolute: 1e-8 at nu = 1e7 and
    // garbage beyond 1e15, where the lobe is a mirror anyway but lambda() is still callable).
    double c =
        1.0 / (std::sqrt(kPiD) * boost::math::tgamma_delta_ratio(0.5 * nu, 0.5, BoostPolicy()));
    d.m_blinn_k = c / (nu - 1.0);
    // rho table (header comment): rho(v) = Lambda(mu) / first(mu), mu = s v / (1 - v), with
    // Lambda = first - tail the Student-t closed form (first in log space, tail by ibeta), with
    // the limits rho(0) = 1 (the ibeta tail is bounded while first ~ k / mu) and rho(1) = 1 / nu
    // (both terms ~ x^(nu/2), x = 1 / (1 + mu^2), with ratio (nu - 1) / nu (1 - x) -> (nu - 1) /
    // nu). Where first < exp(-200) Lambda is 0 in float whatever rho is: the node copies its
    // neighbour so that the interpolant stays bounded there.
    const int n = kBlinnTableSize;
    const double s = std::sqrt(2.0 / nu);
    d.m_blinn_s = float(s);
    d.m_blinn_kf = float(d.m_blinn_k);
    d.m_blinn_half_nu_m1 = float(0.5 * (nu - 1.0));
    auto table = std::make_shared<std::vector<float>>(size_t(n) + 2);
    std::vector<double> r(static_cast<size_t>(n));
    r[0] = 1.0;
    r[size_t(n - 1)] = 1.0 / nu;
    for (int j = 1; j + 1 < n; ++j) {
        double v = double(j) / (n - 1), mu = s * v / (1.0 - v);
        double e = 0.5 * (nu - 1.0) * std::log1p(mu * mu);
        if (e > 200.0) {
            r[size_t(j)] = r[size_t(j - 1)];
            continue;
        }
        double first = d.m_blinn_k * std::exp(-e) / mu;
        double tail = 0.5 * boost::math::ibeta(0.5 * nu, 0.5, 1.0 / (1.0 + mu * mu), BoostPolicy());
        r[size_t(j)] = (first - tail) / first;
    }
    for (int j = 0; j < n; ++j) (*table)[size_t(j) + 1] = float(r[size_t(j)]);
    (*table)[0] = float(3.0 * r[0] - 3.0 * r[1] + r[2]);
    (*table)[size_t(n) + 1] =
        float(3.0 * r[size_t(n - 1)] - 3.0 * r[size_t(n - 2)] + r[size_t(n - 3)]);
    d.m_blinn_rho = std::move(table);
    return d;
}

float MicrofacetDistribution::blinn_rho(float v) const {
    return formulas::blinn_rho(m_blinn_rho->data(), v);
}

// ---------------------------------------------------------------------------------------------
// D and Lambda

float MicrofacetDistribution::D(const Vec3& wm) const {
    float cos2 = wm.z * wm.z;
    if (!(wm.z > 0.f)) return 0.f;
    // Stretched tangential part from the x, y components: no 1 - cos^2 cancellation.
    float sx = wm.x / m_ax, sy = wm.y / m_ay;
    float s = sx * sx + sy * sy;
    switch (m_kind) {
        case DistributionKind::GGX: {
            // D = 1 / (pi ax ay (cos^2 + sin^2 (cos^2 phi / ax^2 + sin^2 phi / ay^2))^2).
            float q = cos2 + s;
            return m_norm / (q * q);
        }
        case DistributionKind::Beckmann: {
            // D = exp(-tan^2 (...)) / (pi ax ay cos^4), as a single exp: no 0 / 0 at grazing.
            float e = s / cos2;
            if (!(e < kInfinity)) return 0.f;
            return std::exp(m_log_norm - e - 2.f * std::log(cos2));
        }
        case DistributionKind::Blinn: {
            // D = nu / (2 pi) cos^-4 (1 + tan^2 (...))^(-(nu + 2) / 2); the power in log space
            // (log1p keeps kappa = 1e7 exact near the peak).
            float t = s / cos2;
            if (!(t < kInfinity)) return 0.f;
            return formulas::blinn_d<formulas::StdMath>(m_log_norm, float(0.5 * (m_nu + 2.0)), t,
                                                        cos2);
        }
    }
    return 0.f;
}

double MicrofacetDistribution::mu(const Vec3& w) const {
    double x = double(m_ax) * double(w.x), y = double(m_ay) * double(w.y);
    double r = std::sqrt(x * x + y * y);
    double z = std::fabs(double(w.z));
    if (r == 0.0) return std::numeric_limits<double>::infinity();
    return z / r;
}

double MicrofacetDistribution::lambda_of_mu(double mu) const {
    if (std::isinf(mu)) return 0.0;
    if (!(mu > 0.0)) return std::numeric_limits<double>::infinity();
    switch (m_kind) {
        case DistributionKind::GGX: {
            double t = 1.0 / (mu * mu);
            return t / (2.0 * (1.0 + std::sqrt(1.0 + t)));
        }
        case DistributionKind::Beckmann: {
            // Lambda(a) = (exp(-a^2) / (a sqrt(pi)) - erfc(a)) / 2, a = mu. In double the
            // cancellation costs log10(2 a^2) < 3 digits for a < 9.
            double a = mu;
            if (a >= kBeckmannZeroLambdaA) return 0.0;
            return std::fmax(0.0, 0.5 * (std::exp(-a * a) * kInvSqrtPiD / a - std::erfc(a)));
        }
        case DistributionKind::Blinn:
            break;  // lambda() reads the rho table built by blinn()
    }
    return 0.0;
}

float MicrofacetDistribution::lambda(const Vec3& w) const {
    if (m_kind == DistributionKind::GGX) {
        // Float fast path: t = alpha_phi^2 tan^2 from the tangential components;
        // Lambda = t / (2 (1 + sqrt(1 + t))) (= (sqrt(1 + t) - 1) / 2 without cancellation).
        float x = m_ax * w.x, y = m_ay * w.y;
        float z2 = w.z * w.z;
        if (!(z2 > 0.f)) return kInfinity;
        float t = (x * x + y * y) / z2;
        if (!(t < kGgxLargeT)) return 0.5f * std::sqrt(t);
        return t / (2.f * (1.f + std::sqrt(1.f + t)));
    }
    if (w.z == 0.f) return kInfinity;
    if (m_kind == DistributionKind::Blinn) {
        // Lambda = first(mu) rho(v) (header comment); mu = z / |(ax x, ay y)| and
        // v = mu / (mu + s) from the tangential components. first carries the whole dynamic
        // range (k / mu at grazing, (1 + mu^2)^((1 - nu) / 2) in the tail) in closed form.
        float x = m_ax * w.x, y = m_ay * w.y, z = std::fabs(w.z);
        float r = std::sqrt(x * x + y * y);
        if (r == 0.f) return 0.f;  // mu = inf
        float mu = z / r;
        float e = formulas::blinn_lambda_exponent<formulas::StdMath>(m_blinn_half_nu_m1, mu);
        if (!(e < blinn_zero_lambda_exponent())) return 0.f;
        return formulas::blinn_lambda<formulas::StdMath>(
            m_blinn_kf, e, mu, blinn_rho(formulas::blinn_lambda_v(m_blinn_s, z, r)));
    }
    return float(lambda_of_mu(mu(w)));
}

// ---------------------------------------------------------------------------------------------
// Visible normals and sampling

float MicrofacetDistribution::D(const Vec3& w, const Vec3& wm) const {
    if (!(w.z > 0.f)) return 0.f;
    float c = glm::dot(w, wm);
    if (!(c > 0.f)) return 0.f;
    // G1(w) / cos = 1 / (cos + cos Lambda): finite as cos -> 0 (Lambda ~ 1 / cos).
    float lam = lambda(w);
    float denom = w.z + w.z * lam;
    if (!(denom < kInfinity)) return 0.f;
    return D(wm) * c / denom;
}

float MicrofacetDistribution::pdf(const Vec3& w, const Vec3& wm) const {
    if (!(w.z > 0.f)) return 0.f;
    if (m_kind == DistributionKind::Blinn) return D(wm) * std::fmax(wm.z, 0.f);
    return D(w, wm);
}

Vec3 MicrofacetDistribution::sample_wm(const Vec3& w, Vec2 u) const {
    switch (m_kind) {
        case DistributionKind::GGX:
            return sample_ggx_visible(w, u);
        case DistributionKind::Beckmann:
            return sample_beckmann_visible(w, u);
        case DistributionKind::Blinn:
            return sample_d_cos(u);
    }
    return {0.f, 0.f, 1.f};
}

Vec3 MicrofacetDistribution::sample_ggx_visible(const Vec3& w, Vec2 u) const {
    // Dupuy & Benyoub 2023, "Sampling Visible GGX Normals with Spherical Caps": in the
    // configuration stretched to alpha = 1, the visible normals of the view direction wh are
    // h = c + wh with c uniform on the spherical cap z >= -wh.z; then unstretch the normal.
    Vec3 wh = glm::normalize(Vec3(m_ax * w.x, m_ay * w.y, std::fabs(w.z)));
    if (!std::isfinite(wh.z)) return {0.f, 0.f, 1.f};
    float phi = 2.f * kPi * u.x;
    float z = std::fma(1.f - u.y, 1.f + wh.z, -wh.z);
    float sin_t = safe_sqrt(1.f - z * z);
    float hx = sin_t * std::cos(phi) + wh.x;
    float hy = sin_t * std::sin(phi) + wh.y;
    float hz = std::fmax(z + wh.z, 0.f);
    return normalize_or_normal(double(m_ax) * hx, double(m_ay) * hy, double(hz));
}

Vec3 MicrofacetDistribution::sample_beckmann_visible(const Vec3& w, Vec2 u) const {
    // Heitz & d'Eon 2014, "Importance Sampling Microfacet-Based BSDFs using the Distribution of
    // Visible Normals": stretch w to the alpha = 1 configuration, sample the visible slopes of
    // the unit Beckmann distribution for that incidence, rotate, unstretch.
    double wx = double(m_ax) * w.x, wy = double(m_ay) * w.y, wz = std::fabs(double(w.z));
    double sin_t = std::sqrt(wx * wx + wy * wy);
    double len = std::sqrt(sin_t * sin_t + wz * wz);
    if (!(len > 0.0) || !std::isfinite(len)) return {0.f, 0.f, 1.f};
    double cos_p = sin_t > 0.0 ? wx / sin_t : 1.0, sin_p = sin_t > 0.0 ? wy / sin_t : 0.0;
    sin_t /= len;
    double cos_t = wz / len;

    // Incidence in the xz plane at theta: the visible slope x (normal (-x, -y, 1)) has density
    // proportional to exp(-x^2) (cos - x sin) on x < cot, so its CDF is
    //   F(x) = [p erfc(-x) + q exp(-x^2) / sqrt(pi)] / [p erfc(-cot) + q exp(-cot^2) / sqrt(pi)]
    // with (p, q) = (cot, 1), or the same divided by cot, (1, tan), near normal incidence; the
    // two forms keep cot = 0 (grazing) and cot = inf (normal) finite.
    double cot = sin_t > 0.0 ? cos_t / sin_t : std::numeric_limits<double>::infinity();
    double p, q;
    if (cot < 1.0) {
        p = cot, q = 1.0;
    } else {
        p = 1.0, q = sin_t / cos_t;
    }
    double hi = std::fmin(cot, kBeckmannMaxSlope), lo = -kBeckmannMaxSlope;
    double norm = p * std::erfc(-hi) + q * std::exp(-hi * hi) * kInvSqrtPiD;
    double target = double(u.x) * norm;  // solve p erfc(-x) + q exp(-x^2)/sqrt(pi) = target
    auto cdf = [&](double x) { return p * std::erfc(-x) + q * std::exp(-x * x) * kInvSqrtPiD; };

    // Initial guess: the normal-incidence (Gaussian) quantile, or the grazing one
    // (density ~ -x exp(-x^2): x = -sqrt(-log u)); the safeguarded Newton loop fixes the rest.
    double ux = std::fmin(std::fmax(double(u.x), 1e-300), 1.0 - 1e-16);
    double x = cot >= 1.0 ? boost::math::erf_inv(2.0 * ux - 1.0, BoostPolicy())
                          : -std::sqrt(-std::log(ux)) + cot;
    if (!(x > lo && x < hi)) x = 0.5 * (lo + hi);
    for (int it = 0; it < kBeckmannMaxIterations; ++it) {
        double r = cdf(x) - target;
        if (r == 0.0) break;  // exact root (e.g. the normal-incidence guess)
        if (r > 0.0) {
            hi = x;
        } else {
            lo = x;
        }
        // dF/dx = 2 / sqrt(pi) exp(-x^2) (p - q x) >= 0 on the bracket.
        double dens = 2.0 * kInvSqrtPiD * std::exp(-x * x) * (p - q * x);
        double xn = dens > 0.0 ? x - r / dens : 0.5 * (lo + hi);
        if (!(xn > lo && xn < hi)) xn = 0.5 * (lo + hi);  // bisection (also catches NaN)
        bool done = std::fabs(xn - x) <= kBeckmannSlopeTolerance * (1.0 + std::fabs(x)) ||
                    hi - lo <= kBeckmannSlopeTolerance;
        x = xn;
        if (done) break;
    }
    // y is independent: the unit Gaussian slope, by the inverse error function.
    double uy = 2.0 * double(u.y) - 1.0;
    uy = std::fmin(std::fmax(uy, -1.0 + 1e-16), 1.0 - 1e-16);
    double y = boost::math::erf_inv(uy, BoostPolicy());
    if (!std::isfinite(y)) y = 0.0;

    // Rotate back to the incidence azimuth, unstretch.
    double sx = cos_p * x - sin_p * y, sy = sin_p * x + cos_p * y;
    return normalize_or_normal(-double(m_ax) * sx, -double(m_ay) * sy, 1.0);
}

Vec3 MicrofacetDistribution::sample_d_cos(Vec2 u) const {
    // Exact sampling of the slope density P22 = D(wm) cos^4 (i.e. of D cos per solid angle):
    // radius of the unit isotropic slope distribution by inverting its radial CDF, azimuth
    // uniform, then stretch.
    float r2 = 0.f;
    switch (m_kind) {
        case DistributionKind::GGX:  // CDF r^2 / (1 + r^2)
            r2 = u.x / (1.f - u.x);
            break;
        case DistributionKind::Beckmann:  // CDF 1 - exp(-r^2)
            r2 = -std::log1p(-u.x);
            break;
        case DistributionKind::Blinn:  // CDF 1 - (1 + r^2)^(-nu / 2)
            r2 = float(std::expm1(-2.0 / m_nu * std::log1p(-double(u.x))));
            break;
    }
    float r = std::sqrt(std::fmax(r2, 0.f));
    float phi = 2.f * kPi * u.y;
    return normalize_or_normal(-double(m_ax) * r * std::cos(phi), -double(m_ay) * r * std::sin(phi),
                               1.0);
}

// ---------------------------------------------------------------------------------------------
// MicrofacetReflection

namespace {

constexpr int kAlbedoGrid = 24;        // Gauss-Legendre nodes per slope dimension
constexpr float kAlbedoMinMu = 1e-4f;  // mu where the first node (mu = 0) is evaluated
}  // namespace

namespace {
// E(wo) = int f_{F=1} cos_i dwi for one direction wo = (sin_o cp, sin_o sp, mu_o). Through the
// half vector (dwi = 4 <wo, m> dm) and the slopes of m (D cos dm = P22 dx dy) this is
//     E = 1 / mu_o int P22(x, y) (mu_o - x' sin_o) G(wo, wi(m)) dx dy,
// x' = x cp + y sp the slope along wo's azimuth, y' across it. wi is above the horizon iff
// 1 + x'^2 + y'^2 < 2 (1 - x' tan_o), i.e. (x' + tan_o)^2 + y'^2 < sec_o^2: a disc, rotation
// invariant, so in the lobe's frame (x + tan_o cp)^2 + (y + tan_o sp)^2 < sec_o^2; the disc
// lies inside x' < cot_o, so (mu_o - x' sin_o) > 0 on it and G -> 0 at its edge.
// We integrate in *unstretched* slopes (xt, yt), x = ax xt, y = ay yt, where the slope density
// is isotropic with unit scale whatever the anisotropy (in stretched slopes a 1e-3 x 10 lobe is
// a thin ridge no fixed grid resolves), over the exact domain: the disc becomes the
// axis-aligned ellipse (ax xt + tan_o cp)^2 + (ay yt + tan_o sp)^2 < sec_o^2. Outer xt over
// the ellipse's extent, inner yt over its chord, both through xt = tan(a) (maps the unit-scale
// density onto a finite angle and resolves chords of any length: |yt| < 0.1 for ay = 10 at
// normal incidence, where integrating yt over R left ~1 node in the support and E was
// overestimated by 2%), tensor Gauss-Legendre.
float albedo_quadrature(const Vec3& wo, double ax, double ay, double cp, double sp,
                        const QuadratureRule& gu, const MicrofacetDistribution& dist) {
    const double lam_o = dist.lambda(wo);
    const double mu_o = wo.z, sin_o = std::sqrt(std::fmax(0.0, 1.0 - mu_o * mu_o));
    const double tan_o = sin_o / mu_o, sec_o = 1.0 / mu_o;
    const double cx = tan_o * cp, cy = tan_o * sp;  // ellipse: (ax xt + cx)^2 + (ay yt + cy)^2
    const double a_lo = std::atan((-cx - sec_o) / ax), a_hi = std::atan((-cx + sec_o) / ax);
    double e = 0.0;
    for (size_t i = 0; i < gu.nodes.size(); ++i) {
        const double ang_a = a_lo + (a_hi - a_lo) * gu.nodes[i];
        const double ca = std::cos(ang_a), xt = std::tan(ang_a);
        const double wa = gu.weights[i] * (a_hi - a_lo) / (ca * ca);
        const double x = ax * xt, u = x + cx, half2 = sec_o * sec_o - u * u;
        if (!(half2 > 0.0)) continue;
        const double half = std::sqrt(half2);
        const double b_lo = std::atan((-cy - half) / ay), b_hi = std::atan((-cy + half) / ay);
        for (size_t j = 0; j < gu.nodes.size(); ++j) {
            const double ang_b = b_lo + (b_hi - b_lo) * gu.nodes[j];
            const double cb = std::cos(ang_b), yt = std::tan(ang_b);
            const double wb = gu.weights[j] * (b_hi - b_lo) / (cb * cb);
            const double y = ay * yt;
            const double proj = mu_o - (x * cp + y * sp) * sin_o;
            if (!(proj > 0.0)) continue;
            const double n2 = 1.0 + x * x + y * y;
            const Vec3 wm = normalize_or_normal(-x, -y, 1.0);
            const double p22 = double(dist.D(wm)) / (n2 * n2) * ax * ay;  // dx dy = ax ay dxt dyt
            if (!(p22 > 0.0)) continue;
            const Vec3 wi = reflect(wo, wm);
            if (!(wi.z > 0.f)) continue;
            const double g = 1.0 / (1.0 + lam_o + double(dist.lambda(wi)));
            e += wa * wb * p22 * proj * g;
        }
    }
    return float(std::fmin(std::fmax(e / mu_o, 0.0), 1.0));
}
}  // namespace

MicrofacetReflection::MicrofacetReflection(const MicrofacetDistribution& d, const Fresnel& fresnel,
                                           const Rgb& scale, bool energy_compensation)
    : m_distribution(d),
      m_fresnel(fresnel),
      m_scale(scale),
      m_energy_compensation(energy_compensation),
      m_smooth(d.effectively_smooth()) {
    if (!m_energy_compensation || m_smooth) return;

    // E(mu_o, phi_o) by albedo_quadrature (above), tabulated.
    const MicrofacetDistribution& dist = m_distribution;
    double s_blinn =
        dist.kind() == DistributionKind::Blinn ? std::sqrt(2.0 / double(dist.nu())) : 1.0;
    double ax = s_blinn * dist.alpha_x(), ay = s_blinn * dist.alpha_y();

    const QuadratureRule& gu = gauss_legendre(kAlbedoGrid);
    // Anisotropic lobes: E depends on phi_o too, and a phi-averaged E lets f_ms create energy
    // where the true E exceeds the average (measured: rho 1.86 for GGX 1e-4 x 1 at 89 deg).
    // Over (mu_o, phi_o) E has ridges near grazing as sharp as the anisotropy (GGX 0.01 x 1 at
    // 89 deg: E 0.52 at phi 0, 0.66 at 2 deg, 0.79 at 5 deg), which a table in (mu_o, phi_o)
    // misses by up to 0.12 (measured). E is smooth in the *stretched* direction
    // ws = normalize(ax wo.x, ay wo.y, wo.z), the variable of Lambda(wo) (Heitz 2014 sec. 5.3),
    // so anisotropic lobes tabulate E over (sqrt(mu_s), phi_s), phi_s in [0, pi/2] (the models
    // are symmetric under x -> -x and y -> -y), bilinear; isotropic lobes over sqrt(mu_o).
    m_phi_count = dist.alpha_x() != dist.alpha_y() ? kPhiTableSize : 1;
    m_stretch = Vec2(float(ax), float(ay));
    std::vector<float> rows(m_phi_count > 1 ? std::size_t(m_phi_count * kTableSize) : 0);
    float* const e = m_phi_count > 1 ? rows.data() : m_e.emplace().data();
    for (int k = 0; k < kTableSize; ++k) {
        double s_k = double(k) / (kTableSize - 1);  // nodes uniform in sqrt(mu)
        double mu = std::fmax(s_k * s_k, double(kAlbedoMinMu));
        double sin_t = std::sqrt(std::fmax(0.0, 1.0 - mu * mu));
        for (int p = 0; p < m_phi_count; ++p) {
            double phi = m_phi_count > 1 ? double(p) / (m_phi_count - 1) * kPiD / 2.0 : 0.0;
            // Isotropic: wo itself. Anisotropic: (mu, phi) is ws; wo = normalize(A^-1 ws).
            double wx = sin_t * std::cos(phi), wy = sin_t * std::sin(phi), wz = mu;
            if (m_phi_count > 1) wx /= ax, wy /= ay;
            double len = std::sqrt(wx * wx + wy * wy + wz * wz);
            wx /= len, wy /= len, wz /= len;
            if (!(wz >= double(kAlbedoMinMu) * 1e-4)) wz = double(kAlbedoMinMu) * 1e-4;
            double st = std::sqrt(std::fmax(0.0, 1.0 - wz * wz)), sxy = std::hypot(wx, wy);
            double cp = sxy > 0.0 ? wx / sxy : 1.0, sp = sxy > 0.0 ? wy / sxy : 0.0;
            Vec3 wo(float(st * cp), float(st * sp), float(wz));
            e[size_t(p) * kTableSize + k] = albedo_quadrature(wo, ax, ay, cp, sp, gu, dist);
        }
    }
    if (m_phi_count > 1) m_e_rows = std::make_shared<const std::vector<float>>(std::move(rows));
    m_has_table = true;
    m_e_avg = m_phi_count == 1 ? isotropic_average() : anisotropic_average(gu);
    finish_compensation();
}

MicrofacetReflection::MicrofacetReflection(const MicrofacetDistribution& d, const Fresnel& fresnel,
                                           const Rgb& scale, const Compensation& c,
                                           const Rgb* f_avg)
    : m_distribution(d),
      m_fresnel(fresnel),
      m_scale(scale),
      m_energy_compensation(true),
      m_smooth(d.effectively_smooth()) {
    if (m_smooth) return;
    // The first constructor's stretch of an isotropic lobe (its table is over mu itself).
    const double s_blinn =
        d.kind() == DistributionKind::Blinn ? std::sqrt(2.0 / double(d.nu())) : 1.0;
    m_stretch = Vec2(float(s_blinn * d.alpha_x()), float(s_blinn * d.alpha_y()));
    m_e.emplace(c.e);
    m_has_table = true;
    m_e_avg = c.e_avg;
    finish_compensation(f_avg);
}

MicrofacetReflection::Compensation MicrofacetReflection::compensation() const {
    Compensation c;
    if (!m_has_table)
        c.e.fill(1.f);
    else if (m_e)
        c.e = *m_e;  // an anisotropic lobe's rows are not one table: e stays 0
    c.e_avg = m_e_avg;
    return c;
}

void MicrofacetReflection::finish_compensation(const Rgb* given_f_avg) {
    if (1.f - m_e_avg < kMinMissingEnergy) return;

    const Rgb f_avg = given_f_avg ? *given_f_avg : m_fresnel.average();
    Rgb f_ms = f_avg * f_avg * m_e_avg / (Rgb(1.f) - f_avg * (1.f - m_e_avg));
    m_ms_factor = m_scale * f_ms / (kPi * (1.f - m_e_avg));
    m_w_ss = std::fmax(luminance(f_avg * m_scale), 0.f);
    m_w_ms = std::fmax(luminance(f_ms * m_scale), 0.f);
    m_has_ms = is_finite(m_ms_factor) && m_w_ms > 0.f;
    if (!m_has_ms) m_ms_factor = Rgb(0.f);
}

// E_avg = 2 int E(mu) mu dmu of the table's interpolant, exactly (albedo_table.h), so that
// f_ms integrates to exactly (1 - E(mu_o)) F_ms.
float MicrofacetReflection::isotropic_average() const {
    return sqrt_mu_table_average(m_e->data(), kTableSize);
}

// E_avg = (1 / pi) int E_tab(wo) cos_o dwo of the (mu_s, phi_s) interpolant, which must be
// exact for the same reason. With v = cos^2 theta_o, cos_o dwo = dv dphi_o / 2, and by
// symmetry E_avg = (2 / pi) int_0^{pi/2} dphi_o int_0^1 dv E_tab. The interpolant is smooth
// inside each table cell but not across cells, so we integrate cell by cell: phi_s cell
// [phi_j, phi_j+1] is phi_o in [atan(ax / ay tan phi_j), ...] (tan phi_s = ay / ax tan phi_o)
// and, at fixed phi_o, the s cell [s_k, s_k+1] is a v interval (mu_s is monotone in theta_o:
// tan^2 theta_o = (mu_s^-2 - 1) / alpha_o^2, alpha_o^2 = ax^2 cos^2 phi_o + ay^2 sin^2 phi_o);
// Gauss-Legendre of kAlbedoGrid nodes in each, on the runtime lookup itself (polynomial of low
// degree in smooth coordinates inside a cell: error far below float).
float MicrofacetReflection::anisotropic_average(const QuadratureRule& gu) const {
    const double ax = m_stretch.x, ay = m_stretch.y;
    auto phi_o_of = [&](double phi_s) {
        return phi_s >= kPiD / 2.0 ? kPiD / 2.0 : std::atan(ax / ay * std::tan(phi_s));
    };
    // v = cos^2 theta_o where mu_s = s^2 at azimuth phi_o.
    auto v_of = [&](double s, double a2) {
        double mu_s = s * s;
        if (!(mu_s > 0.0)) return 0.0;
        double t2 = (1.0 / (mu_s * mu_s) - 1.0) / a2;
        return 1.0 / (1.0 + t2);
    };
    double total = 0.0;
    for (int j = 0; j + 1 < m_phi_count; ++j) {
        double p0 = phi_o_of(double(j) / (m_phi_count - 1) * kPiD / 2.0);
        double p1 = phi_o_of(double(j + 1) / (m_phi_count - 1) * kPiD / 2.0);
        for (size_t i = 0; i < gu.nodes.size(); ++i) {
            double phi_o = p0 + (p1 - p0) * gu.nodes[i], wphi = gu.weights[i] * (p1 - p0);
            double c = std::cos(phi_o), sn = std::sin(phi_o);
            double a2 = ax * ax * c * c + ay * ay * sn * sn;
            for (int k = 0; k + 1 < kTableSize; ++k) {
                double v0 = v_of(double(k) / (kTableSize - 1), a2);
                double v1 = v_of(double(k + 1) / (kTableSize - 1), a2);
                for (size_t l = 0; l < gu.nodes.size(); ++l) {
                    double v = v0 + (v1 - v0) * gu.nodes[l];
                    double ct = std::sqrt(v), st = std::sqrt(std::fmax(0.0, 1.0 - v));
                    Vec3 wo(float(st * c), float(st * sn), float(ct));
                    total += wphi * gu.weights[l] * (v1 - v0) * double(albedo_table(wo));
                }
            }
        }
    }
    return float(std::fmin(total * 2.0 / kPiD, 1.0));
}

float MicrofacetReflection::albedo_row(int row, float mu) const {
    if (!m_has_table) return 1.f;
    // Nodes uniform in sqrt(mu) (albedo_table.h).
    const float* e = m_e_rows ? m_e_rows->data() + size_t(row) * kTableSize : m_e->data();
    return sqrt_mu_table_lookup(e, kTableSize, mu);
}

float MicrofacetReflection::albedo_table(const Vec3& w) const {
    if (m_phi_count == 1) return albedo_row(0, w.z);
    // The stretched direction ws = normalize(ax w.x, ay w.y, w.z) (see the constructor); phi_s
    // folded into [0, pi/2] by symmetry.
    float x = std::fabs(m_stretch.x * w.x), y = std::fabs(m_stretch.y * w.y), z = w.z;
    float len = std::sqrt(x * x + y * y + z * z);
    float mu_s = len > 0.f ? z / len : 1.f;
    float phi = std::atan2(y, x);
    float u = clamp_unit(phi / kPiOver2) * float(m_phi_count - 1);
    int j = std::min(int(u), m_phi_count - 2);
    float t = u - float(j);
    return (1.f - t) * albedo_row(j, mu_s) + t * albedo_row(j + 1, mu_s);
}

float MicrofacetReflection::ms_probability(const Vec3& wo) const {
    if (!m_has_ms) return 0.f;
    float e = albedo_table(wo);
    float ws = e * m_w_ss, wm = (1.f - e) * m_w_ms;
    return ws + wm > 0.f ? wm / (ws + wm) : 0.f;
}

// f_ms = factor (1 - E(mu_o)) (1 - E(mu_i)) (Kulla & Conty 2017), E the albedo table.
inline Rgb MicrofacetReflection::ms_lobe(const Vec3& wo, const Vec3& wi) const {
    return m_ms_factor * ((1.f - albedo_table(wo)) * (1.f - albedo_table(wi)));
}

void MicrofacetReflection::evaluate(const Vec3& wo, const Vec3& wi, Rgb* f_out, float* pdf_out,
                                    bool with_ms) const {
    if (f_out) *f_out = Rgb(0.f);
    if (pdf_out) *pdf_out = 0.f;
    if (m_smooth) return;
    float cos_o = wo.z, cos_i = wi.z;
    if (!(cos_o > 0.f && cos_i > 0.f)) return;
    if (m_distribution.kind() == DistributionKind::GGX)
        return evaluate_ggx(wo, wi, f_out, pdf_out, with_ms);
    Vec3 wm;
    float c, d;
    if (!half_vector_terms(wo, wi, wm, c, d)) return;
    bool blinn = m_distribution.kind() == DistributionKind::Blinn;
    // Lambda(wo) serves both G and the visible-normal pdf (Blinn's pdf does not need it).
    float lam_o = f_out || !blinn ? m_distribution.lambda(wo) : 0.f;
    if (f_out) {
        Rgb result = single_from(c, d, lam_o, m_distribution.lambda(wi), cos_o, cos_i);
        if (m_has_ms && with_ms) result += ms_lobe(wo, wi);
        *f_out = result;
    }
    if (pdf_out) {
        // Half-vector Jacobian dwm / dwi = 1 / (4 <wo, wm>) (Walter et al. 2007, eq. 14).
        float p = 0.f;
        if (c > 0.f) {
            if (blinn) {
                p = d * wm.z / (4.f * c);
            } else {
                // Visible normals: G1(wo) D <wo, wm> / cos_o / (4 <wo, wm>) = G1 D / (4 cos_o).
                float denom = 4.f * (cos_o + cos_o * lam_o);
                p = denom < kInfinity ? d / denom : 0.f;
            }
        }
        if (m_has_ms) {
            float pm = ms_probability(wo);
            p = (1.f - pm) * p + pm * cosine_hemisphere_pdf(cos_i);
        }
        *pdf_out = p;
    }
}

// The half vector's terms of the general path: the unit microfacet normal wm = normalize(wo +
// wi), c = <wo, wm> and D(wm); false when wo + wi = 0.
bool MicrofacetReflection::half_vector_terms(const Vec3& wo, const Vec3& wi, Vec3& wm, float& c,
                                             float& d) const {
    Vec3 h = wo + wi;
    float len2 = glm::dot(h, h);
    if (!(len2 > 0.f)) return false;
    wm = h / std::sqrt(len2);
    c = glm::dot(wo, wm);
    d = m_distribution.D(wm);
    return true;
}

// f_single of the general path from those terms and the two Lambdas: f = D G F / (4 cos_o
// cos_i) (eq. 2.37), height-correlated G (Heitz 2014, eq. 99); one cosine divided at a time (no
// underflow of the product at grazing angles; G ~ cos there keeps the quotient finite).
Rgb MicrofacetReflection::single_from(float c, float d, float lam_o, float lam_i, float cos_o,
                                      float cos_i) const {
    float g = 1.f / (1.f + lam_o + lam_i);
    float s = d * g / (4.f * cos_o) / cos_i;
    // Constant Fresnel stores its value in eta(): skip the evaluation.
    Rgb fr = m_fresnel.is_constant() ? m_fresnel.eta() : m_fresnel.eval(c);
    return m_scale * fr * s;
}

// GGX fast path, algebraically equal to the general one with fewer divisions and roots.
// With A = sqrt(cos^2 + alpha_phi^2 sin^2) per direction, Lambda = (A - cos) / (2 cos), so
//   1 + Lambda_o + Lambda_i = (A_o cos_i + A_i cos_o) / (2 cos_o cos_i)   and
//   G2 / (4 cos_o cos_i) = 1 / (2 (A_o cos_i + A_i cos_o))   (Heitz 2014 eq. 99 rearranged;
// sums of positive terms: no cancellation, finite at grazing angles). D is evaluated from the
// unnormalised half vector h: D = 1 / (pi ax ay) |h|^4 / Q^2, Q = hz^2 + (hx/ax)^2 + (hy/ay)^2.
// The visible-normal pdf G1(wo) D / (4 cos_o) becomes D / (2 (A_o + cos_o)).
void MicrofacetReflection::evaluate_ggx(const Vec3& wo, const Vec3& wi, Rgb* f_out, float* pdf_out,
                                        bool with_ms) const {
    const MicrofacetDistribution& d = m_distribution;
    float cos_o = wo.z, cos_i = wi.z;
    Vec3 h = wo + wi;  // h.z > 0: both directions are above the surface
    float len2 = glm::dot(h, h);
    float hx = h.x * d.m_inv_ax, hy = h.y * d.m_inv_ay;
    float q = h.z * h.z + hx * hx + hy * hy;
    float dd = d.m_norm * (len2 / q) * (len2 / q);
    float a_o = std::sqrt(sqr(cos_o) + sqr(d.m_ax * wo.x) + sqr(d.m_ay * wo.y));
    if (f_out) {
        float a_i = std::sqrt(sqr(cos_i) + sqr(d.m_ax * wi.x) + sqr(d.m_ay * wi.y));
        float s = dd / (2.f * (a_o * cos_i + a_i * cos_o));
        Rgb fr;
        if (m_fresnel.is_constant()) {
            fr = m_fresnel.eta();  // Constant Fresnel stores its value in eta()
        } else {
            float c = glm::dot(wo, h) / std::sqrt(len2);
            fr = m_fresnel.eval(c);
        }
        Rgb result = m_scale * fr * s;
        if (m_has_ms && with_ms) result += ms_lobe(wo, wi);
        *f_out = result;
    }
    if (pdf_out) {
        float p = dd / (2.f * (a_o + cos_o));
        if (m_has_ms) {
            float pm = ms_probability(wo);
            p = (1.f - pm) * p + pm * cosine_hemisphere_pdf(cos_i);
        }
        *pdf_out = p;
    }
}

Rgb MicrofacetReflection::f(const Vec3& wo, const Vec3& wi) const {
    Rgb result;
    evaluate(wo, wi, &result, nullptr);
    return result;
}

Rgb MicrofacetReflection::f_single(const Vec3& wo, const Vec3& wi) const {
    Rgb result;
    evaluate(wo, wi, &result, nullptr, false);
    return result;
}

Rgb MicrofacetReflection::f_multiple(const Vec3& wo, const Vec3& wi) const {
    if (!m_has_ms || m_smooth || !(wo.z > 0.f && wi.z > 0.f)) return Rgb(0.f);
    return ms_lobe(wo, wi);
}

float MicrofacetReflection::pdf(const Vec3& wo, const Vec3& wi) const {
    float p;
    evaluate(wo, wi, nullptr, &p);
    return p;
}

BSDFEval MicrofacetReflection::eval(const Vec3& wo, const Vec3& wi) const {
    BSDFEval e;
    evaluate(wo, wi, &e.f, &e.pdf);
    return e;
}

std::optional<BSDFSample> MicrofacetReflection::sample_f(const Vec3& wo, float uc, Vec2 u) const {
    if (!(wo.z > 0.f)) return std::nullopt;
    if (m_smooth) {
        // The lobe is the mirror (Cohen & Wallace eq. 2.27-2.29): a true delta.
        Vec3 wi(-wo.x, -wo.y, wo.z);
        return BSDFSample{m_scale * m_fresnel.eval(wo.z) / wo.z, wi, 1.f, BxDFFlags::Specular};
    }
    Vec3 wi;
    if (m_has_ms && uc < ms_probability(wo)) {
        wi = sample_cosine_hemisphere(u);
    } else {
        Vec3 wm = m_distribution.sample_wm(wo, u);
        wi = reflect(wo, wm);
    }
    if (!(wi.z > 0.f)) return std::nullopt;
    Rgb f_value;
    float p;
    evaluate(wo, wi, &f_value, &p);
    if (!(p > 0.f) || !(p < kInfinity)) return std::nullopt;
    return BSDFSample{f_value, wi, p, BxDFFlags::Glossy};
}

}  // namespace facet
