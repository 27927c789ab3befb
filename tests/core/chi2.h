// Chi-square goodness-of-fit test of a BxDF sampler against its own pdf, and the deterministic
// quadrature it needs. Test-only code (not part of facet::core).
//
// Conventions (as facet/bxdf.h): directions in the local shading frame, z = normal, wo toward
// the viewer, pdf per unit solid angle of wi. The sampler under test is any type B with
//   std::optional<BSDFSample> B::sample_f(Vec3 wo, float uc, Vec2 u) const,
//   float B::pdf(Vec3 wo, Vec3 wi) const,  Rgb B::f(Vec3 wo, Vec3 wi) const.
//
// Method (pbrt-v4 bsdfs_test.cpp and Mitsuba's chi2 module do the same thing):
//  - The sphere is binned in (cos theta, phi) about an axis (by default the normal): `theta_bins`
//    equal bands of cos theta over [cos_min, 1] times `phi_bins` equal sectors, plus one band
//    [-1, cos_min] cut in `phi_bins` sectors. With the default axis z and cos_min = 0 the lower
//    band is the lower hemisphere, where a reflection sampler must never put a sample.
//  - Expected counts are N times the integral of pdf over each cell, by adaptive 2D
//    Gauss-Legendre quadrature in (cos theta, phi), where the solid-angle measure is
//    d(cos theta) d(phi) (no Jacobian).
//  - Non-grid outcomes get their own cells: specular (delta) samples, expected N * p_spec where
//    p_spec is the discrete lobe probability the specular samples report; and failed samples
//    (nullopt), expected N * (1 - integral of pdf - p_spec). So the test also checks that the
//    pdf carries the right total mass and that lobe selection matches the specular probability.
//  - Cells with expected count < 5 are pooled (Cochran's rule); the pooled cell joins the
//    smallest remaining cell if it is still below 5. A sample in a cell whose expected count is
//    exactly 0 is an immediate failure (p = 0).
//  - The statistic sum (O - E)^2 / E is compared with the chi-square distribution with
//    (cells - 1) degrees of freedom; the caller compares the p-value with a Sidak-corrected
//    significance level.
#pragma once

#include <gtest/gtest.h>
#include <pcg_random.hpp>

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "facet/bxdf.h"
#include "facet/dielectric.h"
#include "facet/frame.h"
#include "facet/types.h"

namespace facet::test {

inline constexpr double kDeg = kPiD / 180.0;

// Direction at polar angle theta (degrees from +z; > 90 is below the surface) and azimuth phi.
inline Vec3 dir(double theta_deg, double phi_deg) {
    const double t = theta_deg * kDeg, p = phi_deg * kDeg;
    return Vec3(
        glm::normalize(DVec3(std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t))));
}

// Monte Carlo tests scale their sample counts by FACET_STRESS_SCALE (default 1).
inline double stress_scale() {
    const char* s = std::getenv("FACET_STRESS_SCALE");
    return s ? std::atof(s) : 1.0;
}

// Uniform float in [0, 1) from the top 24 bits of a 32-bit PCG draw (exactly representable).
inline float uniform_float(pcg32& rng) {
    return float(rng() >> 8) * 0x1p-24f;
}

// Sidak-corrected per-test significance: 1 - (1 - alpha)^(1 / n_tests), so that the chance of
// at least one false rejection among n independent tests is alpha.
double sidak_alpha(double alpha, int n_tests);

// P(X >= statistic) for X ~ chi-square with dof degrees of freedom (regularised upper
// incomplete gamma Q(dof/2, statistic/2)).
double chi2_survival(double statistic, int dof);

// Integral of f(x, y) over [x0, x1] x [y0, y1] by adaptive 2D Gauss-Legendre quadrature: a
// 4x4 rule on a rectangle is compared with the sum of the same rule on its four quarters; the
// quarters are refined until they agree to max(abs_tol * area, rel_tol * |value|) or max_depth
// is reached. The first min_depth levels are always refined, so that a narrow peak that all
// the nodes of a coarse rule miss (the estimate and its check both 0) is still found.
double adaptive_integrate_2d(const std::function<double(double, double)>& f, double x0, double x1,
                             double y0, double y1, double abs_tol, double rel_tol, int max_depth,
                             int min_depth = 0);

// Pools cells and evaluates the chi-square statistic (see header comment).
struct Chi2Statistic {
    double statistic = 0.0;
    int dof = 0;
    double p_value = 1.0;
    int cells_used = 0;    // cells after pooling
    int cells_pooled = 0;  // original cells merged into the pooled cell
    bool zero_expected_hit = false;
};
Chi2Statistic chi2_statistic(const std::vector<double>& observed,
                             const std::vector<double>& expected, double min_expected = 5.0);

struct Chi2Options {
    int n_samples = 200000;
    int theta_bins = 10;
    int phi_bins = 20;
    std::uint64_t seed = 7;
    Vec3 axis{0.f, 0.f, 1.f};  // binning axis; z = the normal
    double cos_min = 0.0;      // the fine grid covers cos(angle to axis) in [cos_min, 1]
    // Quadrature tolerances. A cell with expected count e has sampling noise sqrt(e), so its
    // expected probability m = e / N needs an error << sqrt(e) / N: relative 1e-5 is < 1/100 of
    // that for any e <= 1e6, and absolute 1e-9 per unit (cos, phi) area (4 pi in all) is < 1/100
    // of it for the smallest useful cell (e = 5) at N <= 1e6.
    double quad_abs_tol = 1e-9;
    double quad_rel_tol = 1e-5;
    int quad_depth = 8;
    int quad_min_depth = 2;  // >= 16 x 4 x 16 nodes per cell before adapting
    // The per-sample consistency check (sample pdf / f vs pdf() / f()) runs on this many samples.
    int n_consistency = 20000;
};

struct Chi2Result {
    Chi2Statistic chi2;
    long n = 0;
    long specular = 0;          // delta samples (excluded from the grid, own cell)
    long failed = 0;            // sample_f returned nullopt
    long below_horizon = 0;     // non-specular samples with wi.z <= 0 (a reflection model bug)
    long not_unit = 0;          // | |wi| - 1 | > 1e-5
    long bad_values = 0;        // NaN/Inf/negative f or pdf <= 0 in a returned sample
    double p_spec = 0.0;        // discrete probability reported by specular samples
    double pdf_integral = 0.0;  // integral of pdf over the sphere (quadrature)
    // Largest relative difference between a sample's pdf / f and pdf() / f() at its wi.
    double max_pdf_rel_err = 0.0;
    double max_f_rel_err = 0.0;
    std::string describe() const;
};

namespace detail {
// Direction at (cos theta, phi) about the frame's z axis, in double, returned as float.
inline Vec3 cell_direction(const Frame& fr, double c, double phi) {
    double s = std::sqrt(std::fmax(0.0, 1.0 - c * c));
    DVec3 d = s * std::cos(phi) * DVec3(fr.x) + s * std::sin(phi) * DVec3(fr.y) + c * DVec3(fr.z);
    return Vec3(glm::normalize(d));
}
inline double rel_diff(double a, double b) {
    double m = std::fmax(std::fabs(a), std::fabs(b));
    return m == 0.0 ? 0.0 : std::fabs(a - b) / m;
}
// Cell bounds of the grid described in the header comment.
struct Grid {
    int nt, np;
    double cos_min;
    int cells() const { return (nt + 1) * np; }
    // band 0 is [-1, cos_min]; bands 1..nt split [cos_min, 1].
    double band_lo(int b) const { return b == 0 ? -1.0 : cos_min + (1.0 - cos_min) * (b - 1) / nt; }
    double band_hi(int b) const { return b == 0 ? cos_min : cos_min + (1.0 - cos_min) * b / nt; }
    int index(double c, double phi) const {
        int b;
        if (c < cos_min) {
            b = 0;
        } else {
            b = 1 + int((c - cos_min) / (1.0 - cos_min) * nt);
            b = std::min(b, nt);
        }
        double t = phi / (2.0 * kPiD);
        t -= std::floor(t);
        int p = std::min(int(t * np), np - 1);
        return b * np + p;
    }
};
}  // namespace detail

// Runs the chi-square test of b.sample_f against b.pdf at a fixed wo (see header comment).
template <class B>
Chi2Result chi2_sampling_test(const B& b, const Vec3& wo, const Chi2Options& opt = {}) {
    Chi2Result r;
    r.n = opt.n_samples;
    Frame fr = Frame::from_z(glm::normalize(opt.axis));
    detail::Grid grid{opt.theta_bins, opt.phi_bins, opt.cos_min};
    std::vector<double> observed(grid.cells() + 2, 0.0), expected(grid.cells() + 2, 0.0);
    const int spec_cell = grid.cells(), fail_cell = grid.cells() + 1;

    pcg32 rng(opt.seed);
    for (int i = 0; i < opt.n_samples; ++i) {
        float uc = uniform_float(rng);
        Vec2 u(uniform_float(rng), uniform_float(rng));
        std::optional<BSDFSample> s = b.sample_f(wo, uc, u);
        if (!s) {
            ++r.failed;
            observed[fail_cell] += 1;
            continue;
        }
        if (std::fabs(glm::length(s->wi) - 1.f) > 1e-5f) ++r.not_unit;
        bool bad = !is_finite(s->f) || s->f.r < 0.f || s->f.g < 0.f || s->f.b < 0.f ||
                   !std::isfinite(s->pdf) || !(s->pdf > 0.f);
        if (bad) ++r.bad_values;
        if (s->is_specular()) {
            ++r.specular;
            observed[spec_cell] += 1;
            r.p_spec = s->pdf;
            continue;
        }
        if (!(s->wi.z > 0.f)) ++r.below_horizon;
        // The sample's own pdf and f must be what pdf() and f() say at its direction.
        if (i < opt.n_consistency) {
            r.max_pdf_rel_err =
                std::fmax(r.max_pdf_rel_err, detail::rel_diff(s->pdf, b.pdf(wo, s->wi)));
            Rgb fv = b.f(wo, s->wi);
            for (int c = 0; c < 3; ++c)
                r.max_f_rel_err = std::fmax(r.max_f_rel_err, detail::rel_diff(s->f[c], fv[c]));
        }
        Vec3 l = fr.to_local(s->wi);
        double cz = glm::clamp(double(l.z), -1.0, 1.0);
        observed[grid.index(cz, std::atan2(double(l.y), double(l.x)))] += 1;
    }

    // Expected counts: N * integral of pdf over each cell.
    auto pdf_at = [&](double c, double phi) {
        return double(b.pdf(wo, detail::cell_direction(fr, c, phi)));
    };
    double total = 0.0;
    for (int band = 0; band <= grid.nt; ++band) {
        for (int p = 0; p < grid.np; ++p) {
            double p0 = 2.0 * kPiD * p / grid.np, p1 = 2.0 * kPiD * (p + 1) / grid.np;
            double mass = adaptive_integrate_2d(pdf_at, grid.band_lo(band), grid.band_hi(band), p0,
                                                p1, opt.quad_abs_tol, opt.quad_rel_tol,
                                                opt.quad_depth, opt.quad_min_depth);
            total += mass;
            expected[band * grid.np + p] = mass * opt.n_samples;
        }
    }
    r.pdf_integral = total;
    expected[spec_cell] = r.p_spec * opt.n_samples;
    expected[fail_cell] = std::fmax(0.0, 1.0 - total - r.p_spec) * opt.n_samples;
    r.chi2 = chi2_statistic(observed, expected);
    return r;
}

// The whole-sphere chi-square of a material's sample_f against its pdf at wo = dir(theta, 30)
// (16 x 16 cells over the sphere; 1e5 samples times the stress scale, at least 2e4), shared
// by the rough-glass, principled and combination tests.
template <typename B>
Chi2Result sphere_chi2(const B& b, double theta_deg) {
    Chi2Options o;
    o.cos_min = -1.0;  // the whole sphere is the fine grid
    o.theta_bins = 16;
    o.phi_bins = 16;
    o.n_samples = std::max(20000, int(100000 * stress_scale()));
    return chi2_sampling_test(b, dir(theta_deg, 30.0), o);
}

// Directional albedo at wo by Monte Carlo over n sample weights f |cos_i| / pdf in importance
// mode (no etap^2 factor) of channel `channel` (0 r, 1 g, 2 b): the mean and its standard error.
struct SampledAlbedo {
    double mean, se;
};
template <class B>
SampledAlbedo sampled_albedo(const B& b, const Vec3& wo, int n, std::uint64_t seed, int channel) {
    pcg32 rng(seed);
    double s = 0.0, s2 = 0.0;
    for (int i = 0; i < n; ++i) {
        const float uc = uniform_float(rng);
        const Vec2 u(uniform_float(rng), uniform_float(rng));
        auto smp = b.sample_f(wo, uc, u, TransportMode::Importance);
        if (!smp) continue;
        const double w = double(smp->f[channel]) * std::fabs(smp->wi.z) / smp->pdf;
        s += w, s2 += w * w;
    }
    const double mean = s / n;
    return {mean, std::sqrt(std::max(0.0, s2 / n - mean * mean) / n)};
}

// The expectations every sphere_chi2 result meets: p-value >= `level` (Sidak-corrected by the
// caller), no sample in a cell of zero expectation, no NaN/Inf or non-unit direction, and
// per-sample f and pdf within 1e-3 of f() / pdf() (recomputed half vectors: a few float
// roundings).
inline void expect_sphere_chi2(const Chi2Result& r, double level) {
    EXPECT_GE(r.chi2.p_value, level) << r.describe();
    EXPECT_FALSE(r.chi2.zero_expected_hit);
    EXPECT_EQ(r.bad_values, 0);
    EXPECT_EQ(r.not_unit, 0);
    EXPECT_LT(r.max_pdf_rel_err, 1e-3);
    EXPECT_LT(r.max_f_rel_err, 1e-3);
}

// A sampler with a deliberately wrong pdf, to show that the test can fail: the pdf is tilted by
// (1 + tilt * wi.x). For a lobe symmetric under x -> -x (e.g. Lambert, or any lobe at phi_o = 90
// degrees) the tilted pdf still integrates to 1, so only the *shape* is wrong.
template <class B>
struct TiltedPdf {
    const B& base;
    float tilt;
    std::optional<BSDFSample> sample_f(const Vec3& wo, float uc, Vec2 u) const {
        auto s = base.sample_f(wo, uc, u);
        if (s) s->pdf *= 1.f + tilt * s->wi.x;
        return s;
    }
    float pdf(const Vec3& wo, const Vec3& wi) const {
        return base.pdf(wo, wi) * (1.f + tilt * wi.x);
    }
    Rgb f(const Vec3& wo, const Vec3& wi) const { return base.f(wo, wi); }
    BxDFFlags flags() const { return base.flags(); }
};

}  // namespace facet::test
