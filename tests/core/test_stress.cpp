// Numerical stability stress test (issue 2): >= 1e7 random and adversarial queries of f, pdf and
// sample_f over every model corner (tests/core/model_corners.h: roughness down to alpha 1e-7,
// Blinn kappa up to 1e9, anisotropy ratios 1e4, IOR 1, 1.0001 and 0.7, compensation on/off,
// registry materials) must give zero NaN, Inf or negative values; sampled directions are unit
// and above the surface with pdf > 0. Float results are compared with the double-precision
// oracle (tests/core/reference_double.h).
//
// Query count: FACET_STRESS_SCALE (default 1) scales it; Debug and sanitizer builds set 0.1
// from CMake. The total never drops below 1e6.
//
// Oracle tolerance. The oracle evaluates the exact formulas in double at the very float inputs
// the model saw, so the difference is the model's float arithmetic. That error is bounded by
// the problem's conditioning: a float model necessarily rounds its intermediates (the half
// vector, tan^2 from x^2 + y^2, the exponent kappa log cos) at ~6e-8, and a lobe as sharp as
// alpha = 1e-3 or kappa = 1e7 amplifies that by up to ~1e6. So we estimate the relative
// condition c of each oracle value numerically (the largest relative change of the double
// result when wo and wi are perturbed componentwise by 2^-23 relative, 2 random perturbations)
// and require
//     |float - double| / |double| <= 1e-4 + 16 c,
// wherever the double value is in 1e-20 .. 1e20, i.e. far from the float range ends (below
// that, f is a product of intermediates near float underflow, e.g. D ~ 1e-35 times 1/cos^2 ~
// 1e18, whose subnormal rounding is not a defect: measured 5e-4 relative at f = 8e-30); 1e-4 is
// ~1000 ulps of slack for chains of ~20 float operations and library functions (exp, log1p,
// erf, ibeta in float/double mixes). The worst relative error overall and among
// well-conditioned queries (c < 1e-6) is printed.
#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>

#include "chi2.h"
#include "model_corners.h"

namespace facet {
namespace {

double stress_scale() {
    const char* s = std::getenv("FACET_STRESS_SCALE");
    double v = s ? std::atof(s) : 1.0;
    return v > 0.0 ? v : 1.0;
}

constexpr long kFullQueries = 12'000'000;  // >= 1e7 at scale 1
constexpr long kMinQueries = 1'000'000;

struct Counts {
    long queries = 0;
    long bad_f = 0, bad_pdf = 0, bad_sample = 0;
    std::string first_bad;
    void bad(long& counter, const std::string& what) {
        if (counter++ == 0 && first_bad.empty()) first_bad = what;
    }
};

std::string describe(const std::string& model, const Vec3& wo, const Vec3& wi) {
    char buf[256];
    std::snprintf(buf, sizeof buf, "%s wo (%.9g %.9g %.9g) wi (%.9g %.9g %.9g)", model.c_str(),
                  wo.x, wo.y, wo.z, wi.x, wi.y, wi.z);
    return buf;
}

// Direction generator mixing random and adversarial cases.
class Directions {
  public:
    explicit Directions(std::uint64_t seed) : m_rng(seed) {}
    float u() { return test::uniform_float(m_rng); }
    Vec3 random_upper() { return sample_uniform_hemisphere(Vec2(u(), u())); }
    Vec3 at_cos(float c) {
        float phi = 2.f * kPi * u();
        float s = std::sqrt(std::fmax(0.f, 1.f - c * c));
        return Vec3(s * std::cos(phi), s * std::sin(phi), c);
    }
    Vec3 grazing() {
        static const float cs[] = {1e-9f, 3e-9f, 1e-8f, 1e-7f, 1e-6f, 1e-5f, 1e-4f, 1e-3f, 1e-2f};
        return at_cos(cs[m_rng(9)]);
    }
    Vec3 near_normal() {
        static const float ts[] = {0.f, 1e-30f, 1e-20f, 1e-10f, 1e-5f};
        float t = ts[m_rng(5)];
        float phi = 2.f * kPi * u();
        return glm::normalize(Vec3(t * std::cos(phi), t * std::sin(phi), 1.f));
    }
    Vec3 below() {
        switch (m_rng(4)) {
            case 0:
                return sample_uniform_sphere(Vec2(u(), 0.5f + 0.5f * u()));
            case 1:
                return at_cos(0.f);
            case 2: {
                Vec3 w = at_cos(0.f);
                w.z = -0.f;
                return w;
            }
            default:
                return -grazing();
        }
    }
    // A (wo, wi) pair of category k.
    std::pair<Vec3, Vec3> pair(int k) {
        switch (k) {
            case 0:
                return {random_upper(), random_upper()};
            case 1:
                return {grazing(), random_upper()};
            case 2:
                return {random_upper(), grazing()};
            case 3:
                return {grazing(), grazing()};
            case 4:
                return {near_normal(), random_upper()};
            case 5:
                return {near_normal(), near_normal()};
            case 6: {
                Vec3 w = m_rng(2) ? random_upper() : grazing();
                return {w, w};  // wi = wo
            }
            case 7: {
                Vec3 w = m_rng(2) ? random_upper() : grazing();
                return {w, Vec3(-w.x, -w.y, w.z)};  // the mirror direction: the lobe's peak
            }
            case 8: {
                Vec3 g = grazing();
                Vec3 h = grazing();
                return {g, glm::normalize(Vec3(-g.x + 1e-3f * h.x, -g.y + 1e-3f * h.y,
                                               h.z))};  // near-opposite
            }
            case 9:
                return {below(), random_upper()};
            case 10:
                return {random_upper(), below()};
            default:
                return {below(), below()};
        }
    }
    static constexpr int kCategories = 12;
    Vec2 sample_u() {
        static const float special[] = {0.f, 0.5f, kOneMinusEpsilon, 1e-7f, 0.25f};
        if (m_rng(8) == 0) return Vec2(special[m_rng(5)], special[m_rng(5)]);
        return Vec2(u(), u());
    }
    float sample_uc() {
        static const float special[] = {0.f, kOneMinusEpsilon, 0.5f};
        if (m_rng(8) == 0) return special[m_rng(3)];
        return u();
    }
    pcg32& rng() { return m_rng; }

  private:
    pcg32 m_rng;
};

bool bad_rgb(const Rgb& c) {
    return !is_finite(c) || c.r < 0.f || c.g < 0.f || c.b < 0.f;
}

// Runs n queries (each pair: f, pdf and one sample_f = 3 queries) on any model.
template <class B>
void stress_model(const B& b, const std::string& name, long n_queries, std::uint64_t seed,
                  Counts& counts) {
    Directions dirs(seed);
    for (long q = 0; q < n_queries; q += 3) {
        auto [wo, wi] = dirs.pair(int(q / 3 % Directions::kCategories));
        Rgb f = b.f(wo, wi);
        if (bad_rgb(f)) counts.bad(counts.bad_f, "f " + describe(name, wo, wi));
        float p = b.pdf(wo, wi);
        if (!std::isfinite(p) || p < 0.f)
            counts.bad(counts.bad_pdf, "pdf " + describe(name, wo, wi));
        auto s = b.sample_f(wo, dirs.sample_uc(), dirs.sample_u());
        if (s) {
            bool ok = !bad_rgb(s->f) && std::isfinite(s->pdf) && s->pdf > 0.f &&
                      std::fabs(glm::length(s->wi) - 1.f) <= 1e-5f && s->wi.z > 0.f &&
                      std::isfinite(s->wi.x) && std::isfinite(s->wi.y);
            if (!ok) counts.bad(counts.bad_sample, "sample_f " + describe(name, wo, s->wi));
        }
        counts.queries += 3;
    }
}

TEST(Stress, NoNaNInfOrNegativeAnywhere) {
    const long total = std::max(kMinQueries, long(kFullQueries * stress_scale()));
    auto lobes = test::lobe_corners(true);
    auto mats = test::material_corners();
    const long n_models = long(lobes.size() + mats.size() + 2);
    const long per_model = total / n_models + 3;
    Counts counts;
    auto t0 = std::chrono::steady_clock::now();
    std::uint64_t seed = 1;
    for (const auto& spec : lobes) {
        MicrofacetReflection lobe = spec.lobe(Rgb(1.f, 0.5f, 0.25f));
        stress_model(lobe, spec.name(), per_model, seed++, counts);
    }
    for (const auto& m : mats)
        stress_model(make_material(m.model, m.params), m.name, per_model, seed++, counts);
    stress_model(LambertReflection(Rgb(1.f)), "lambert", per_model, seed++, counts);
    stress_model(MirrorReflection(Fresnel::dielectric(1.0001f), Rgb(1.f)), "mirror", per_model,
                 seed++, counts);
    double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::printf("  %ld queries on %ld models in %.1f s: bad f %ld, bad pdf %ld, bad sample %ld\n",
                counts.queries, n_models, secs, counts.bad_f, counts.bad_pdf, counts.bad_sample);
    EXPECT_GE(counts.queries, total);
    EXPECT_GE(counts.queries, kMinQueries);
    EXPECT_EQ(counts.bad_f, 0) << counts.first_bad;
    EXPECT_EQ(counts.bad_pdf, 0) << counts.first_bad;
    EXPECT_EQ(counts.bad_sample, 0) << counts.first_bad;
}

// --- Float versus the double-precision oracle ----------------------------------------------

struct OracleStats {
    long compared = 0, failures = 0;
    double worst_rel = 0.0, worst_ratio = 0.0, worst_rel_well = 0.0;
    std::string worst_where, worst_ratio_where, worst_well_where, first_failure;
};

constexpr double kBaseTol = 1e-4;
constexpr double kCondFactor = 16.0;
constexpr double kWellConditioned = 1e-6;

bool comparable(double v) {
    return std::isfinite(v) && v >= 1e-20 && v <= 1e20;
}

// Compares one float value with its oracle; `exact(wo, wi)` re-evaluates the oracle.
template <class Exact>
void compare(double value, double reference, const DVec3& wo, const DVec3& wi, Exact exact,
             pcg32& rng, const std::string& what, OracleStats& st) {
    if (!comparable(reference)) return;
    // Condition estimate: relative change of the exact value under 2^-23 input perturbations.
    double cond = 0.0;
    for (int k = 0; k < 2; ++k) {
        auto perturb = [&](const DVec3& w) {
            DVec3 r;
            for (int i = 0; i < 3; ++i) r[i] = w[i] * (1.0 + 0x1p-23 * ((rng() & 1) ? 1.0 : -1.0));
            return glm::normalize(r);
        };
        double e = exact(perturb(wo), perturb(wi));
        if (!std::isfinite(e)) {
            cond = 1e300;
            break;
        }
        cond = std::fmax(cond, std::fabs(e - reference) / reference);
    }
    double rel = std::fabs(value - reference) / reference;
    double tol = kBaseTol + kCondFactor * cond;
    ++st.compared;
    if (rel > st.worst_rel) st.worst_rel = rel, st.worst_where = what;
    if (rel / tol > st.worst_ratio) st.worst_ratio = rel / tol, st.worst_ratio_where = what;
    if (cond < kWellConditioned && rel > st.worst_rel_well)
        st.worst_rel_well = rel, st.worst_well_where = what;
    if (!(rel <= tol)) {
        if (st.failures++ == 0) {
            char buf[128];
            std::snprintf(buf, sizeof buf, ": float %.9g double %.9g rel %.3g cond %.3g", value,
                          reference, rel, cond);
            st.first_failure = what + buf;
        }
    }
}

TEST(Stress, FloatAgreesWithDoubleOracle) {
    const long n_per_lobe = std::max(300L, long(1500 * stress_scale()));
    OracleStats st_f, st_pdf, st_d, st_lambda;
    for (const auto& spec : test::lobe_corners(true)) {
        if (spec.energy_compensation) continue;  // the oracle has no compensation lobe
        MicrofacetReflection lobe = spec.lobe(Rgb(1.f, 0.5f, 0.25f));
        const MicrofacetDistribution& d = lobe.distribution();
        if (d.effectively_smooth()) continue;  // a mirror: f = pdf = 0 (checked above)
        ref::Distribution rd = spec.ref_distribution();
        const DVec3 scale(1.0, 0.5, 0.25);
        Directions dirs(777);
        pcg32& rng = dirs.rng();
        for (long q = 0; q < n_per_lobe; ++q) {
            // Upper-hemisphere categories only (0..8): the oracle compares values, not zeros.
            auto [wo, wi] = dirs.pair(int(q % 9));
            if (!(wo.z > 0.f && wi.z > 0.f)) continue;
            DVec3 dwo(wo), dwi(wi);
            std::string where = describe(spec.name(), wo, wi);
            // f: per channel, with one condition estimate for the RGB triple (max channel).
            // IOR exactly 1 has F = 0: the double "value" is round-off, nothing to compare.
            if (spec.fresnel.name != "dielectric1.000000") {
                Rgb f = lobe.f(wo, wi);
                DVec3 rf = ref::microfacet_f(rd, spec.fresnel.ref, scale, dwo, dwi);
                int c = rf[0] >= rf[1] && rf[0] >= rf[2] ? 0 : (rf[1] >= rf[2] ? 1 : 2);
                compare(
                    f[c], rf[c], dwo, dwi,
                    [&](const DVec3& a, const DVec3& b) {
                        return ref::microfacet_f(rd, spec.fresnel.ref, scale, a, b)[c];
                    },
                    rng, "f " + where, st_f);
            }
            compare(
                lobe.pdf(wo, wi), ref::microfacet_pdf(rd, dwo, dwi), dwo, dwi,
                [&](const DVec3& a, const DVec3& b) { return ref::microfacet_pdf(rd, a, b); }, rng,
                "pdf " + where, st_pdf);
            // D at the float half vector the model would use, and Lambda at wo.
            Vec3 h = glm::normalize(wo + wi);
            compare(
                d.D(h), ref::D(rd, DVec3(h)), DVec3(h), DVec3(h),
                [&](const DVec3& a, const DVec3&) { return ref::D(rd, a); }, rng, "D " + where,
                st_d);
            // Lambda below 1e-8 cannot change any float result (1 + Lambda rounds to 1), and
            // there the oracle's quadrature loses relative accuracy: compare above it.
            double rl = ref::lambda(rd, dwo);
            if (rl >= 1e-8)
                compare(
                    d.lambda(wo), rl, dwo, dwo,
                    [&](const DVec3& a, const DVec3&) { return ref::lambda(rd, a); }, rng,
                    "Lambda " + where, st_lambda);
        }
    }
    auto report = [](const char* name, const OracleStats& s) {
        std::printf(
            "  %-6s compared %ld, failures %ld; worst rel %.3g (%s)\n"
            "         worst rel among well-conditioned (cond < 1e-6) %.3g (%s)\n"
            "         worst error / tolerance %.3g (%s)\n",
            name, s.compared, s.failures, s.worst_rel, s.worst_where.c_str(), s.worst_rel_well,
            s.worst_well_where.c_str(), s.worst_ratio, s.worst_ratio_where.c_str());
    };
    report("f", st_f);
    report("pdf", st_pdf);
    report("D", st_d);
    report("Lambda", st_lambda);
    EXPECT_EQ(st_f.failures, 0) << st_f.first_failure;
    EXPECT_EQ(st_pdf.failures, 0) << st_pdf.first_failure;
    EXPECT_EQ(st_d.failures, 0) << st_d.first_failure;
    EXPECT_EQ(st_lambda.failures, 0) << st_lambda.first_failure;
    EXPECT_GT(st_f.compared, 20000);
}

// The oracle itself: Blinn kappa = 0 is exactly GGX alpha = 1 (D and Lambda), and the
// quadrature Lambda of the Student-t matches GGX's closed form there to 1e-9 (GK61 at 1e-10).
TEST(Stress, OracleSelfConsistency) {
    ref::Distribution blinn0{ref::Dist::Blinn, 0.0, 0.0}, ggx1{ref::Dist::GGX, 1.0, 1.0};
    for (double c : {1e-9, 1e-4, 0.1, 0.5, 0.9, 1.0}) {
        DVec3 w(std::sqrt(1.0 - c * c), 0.0, c);
        EXPECT_NEAR(ref::D(blinn0, w), ref::D(ggx1, w), 1e-12 * ref::D(ggx1, w));
        double lg = ref::lambda(ggx1, w), lb = ref::lambda(blinn0, w);
        EXPECT_NEAR(lb, lg, 1e-9 * std::fmax(1.0, lg)) << "cos " << c;
    }
}

}  // namespace
}  // namespace facet
