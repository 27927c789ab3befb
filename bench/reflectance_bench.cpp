// Time against error for rho(wi -> 2pi), two tables from the same run.
// 1. The adaptive default (tolerance 1e-6) against the older fixed order-32 path (Q(16), Q(32),
//    Q(64)), interleaved repetitions (median of 7 each): time, error against a tight reference
//    (the adaptive quadrature at tolerance 1e-8, itself checked against double references in
//    tests/core/test_reflectance.cpp), the printed error estimate, and the time ratio
//    adaptive / order-32.
// 2. The fixed-order quadrature against plain Monte Carlo with the material's own importance
//    sampling: the ratio of the Monte Carlo time needed to reach the quadrature's error
//    (extrapolated by 1/sqrt(N) from the largest MC run) to the quadrature's time.
#include <fmt/format.h>
#include <pcg_random.hpp>

#include <algorithm>
#include <chrono>
#include <string>
#include <vector>

#include "facet/reflectance.h"
#include "facet/registry.h"

using namespace facet;

namespace {

template <class F>
double median_seconds(F&& f, int reps = 5) {
    std::vector<double> t;
    for (int i = 0; i < reps; ++i) {
        auto a = std::chrono::steady_clock::now();
        f();
        t.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - a).count());
    }
    std::sort(t.begin(), t.end());
    return t[t.size() / 2];
}

double monte_carlo(const Material& m, const Vec3& wi, int n, std::uint64_t seed) {
    // rho(wi -> 2pi) = int f(wo, wi) cos(theta_o) dwo, sampling wo ~ sample_f(wi) (reciprocity
    // of f lets the sampler be driven from wi).
    pcg32 rng(seed);
    auto uniform = [&] { return std::min(float(rng() >> 8) * 0x1p-24f, kOneMinusEpsilon); };
    double sum = 0.0;
    for (int i = 0; i < n; ++i) {
        float uc = uniform();
        Vec2 u(uniform(), uniform());
        if (auto s = m.sample_f(wi, uc, u)) sum += double(luminance(s->f)) * s->wi.z / s->pdf;
    }
    return sum / n;
}

}  // namespace

// Table 1 (see the header comment).
double adaptive_against_fixed(const Material& m, const char* label, float deg, long& evals) {
    Vec3 wi = spherical_direction(deg * kPi / 180.f, 0.f);
    QuadratureSettings tight;
    tight.tolerance = 1e-8;
    const double ref = directional_hemispherical(m, wi, tight).value.g;
    std::vector<double> ta, tf;
    Reflectance a, f;
    for (int rep = 0; rep < 7; ++rep) {  // interleaved: drift of the machine cancels
        auto t0 = std::chrono::steady_clock::now();
        a = directional_hemispherical(m, wi);
        auto t1 = std::chrono::steady_clock::now();
        f = directional_hemispherical(m, wi, 32);
        auto t2 = std::chrono::steady_clock::now();
        ta.push_back(std::chrono::duration<double>(t1 - t0).count());
        tf.push_back(std::chrono::duration<double>(t2 - t1).count());
    }
    std::sort(ta.begin(), ta.end());
    std::sort(tf.begin(), tf.end());
    const double ma = ta[ta.size() / 2], mf = tf[tf.size() / 2];
    fmt::print(
        "{:<24} {:>6.1f} {:>12.9f} {:>9.3f}ms {:>10.2e} {:>10.2e} {:>8} {:>9.3f}ms {:>10.2e} "
        "{:>10.2e} {:>8.2f}\n",
        label, deg, ref, ma * 1e3, std::fabs(a.value.g - ref), a.error.g, a.evaluations, mf * 1e3,
        std::fabs(f.value.g - ref), f.error.g, ma / mf);
    evals = a.evaluations;
    return ma / mf;
}

int main() {
    struct Case {
        const char* label;
        const char* model;
        ParamSet params;
    };
    auto p = [](std::initializer_list<std::pair<std::string, ParamValue>> l) {
        return ParamSet(l);
    };
    std::vector<Case> cases = {
        {"ggx a=0.3 dielectric", "ggx",
         p({{"alpha", 0.3}, {"fresnel", std::string("dielectric")}})},
        {"beckmann a=0.05", "beckmann", p({{"alpha", 0.05}})},
        {"blinn k=1e4", "blinn", p({{"exponent", 1e4}})},
        {"composite ggx a=0.2", "composite", p({{"alpha", 0.2}})},
    };
    fmt::print(
        "rho(wi -> 2pi), green channel: adaptive default (tolerance 1e-6) vs fixed order 32, same "
        "run, interleaved, medians of 7; reference = adaptive at tolerance 1e-8\n");
    fmt::print("{:<24} {:>6} {:>12} {:>11} {:>10} {:>10} {:>8} {:>11} {:>10} {:>10} {:>8}\n",
               "case", "theta", "reference", "adapt time", "adapt err", "adapt est", "evals",
               "Q32 time", "Q32 err", "Q32 est", "time a/Q");
    std::vector<double> ratios, low, grazing;  // all; incidence <= 70; >= 85 degrees
    double worst = 0.0;
    std::string worst_label;
    long total_evals = 0;
    {
        std::vector<Case> table1 = cases;
        table1.push_back({"ggx a=0.2", "ggx", p({{"alpha", 0.2}})});
        table1.push_back({"ggx a=1", "ggx", p({{"alpha", 1.0}})});
        table1.push_back({"ggx aniso 0.05/0.5", "ggx", p({{"alpha_u", 0.05}, {"alpha_v", 0.5}})});
        table1.push_back({"beckmann a=0.8 conductor", "beckmann",
                          p({{"alpha", 0.8}, {"fresnel", std::string("conductor")}})});
        table1.push_back({"blinn k=50", "blinn", p({})});
        table1.push_back(
            {"ggx a=0.5 compensated", "ggx", p({{"alpha", 0.5}, {"energy_compensation", true}})});
        table1.push_back({"lambert", "lambert", p({})});
        for (const auto& c : table1) {
            Material m = make_material(c.model, c.params);
            for (float deg : {0.f, 30.f, 70.f, 85.f, 89.f, 89.9f}) {
                long evals = 0;
                const double r = adaptive_against_fixed(m, c.label, deg, evals);
                ratios.push_back(r);
                (deg <= 70.f ? low : grazing).push_back(r);
                total_evals += evals;
                if (r > worst) worst = r, worst_label = fmt::format("{} at {}", c.label, deg);
            }
        }
    }
    auto median = [](std::vector<double> v) {
        std::sort(v.begin(), v.end());
        return v[v.size() / 2];
    };
    std::sort(ratios.begin(), ratios.end());
    fmt::print(
        "time ratio adaptive / order-32 over the {} cases: median {:.2f}, min {:.2f}, max {:.2f} "
        "({}); median at <= 70 degrees {:.2f} ({} cases), at >= 85 degrees {:.2f} ({} cases); "
        "adaptive evaluations {} in all\n",
        ratios.size(), median(ratios), ratios.front(), ratios.back(), worst_label, median(low),
        low.size(), median(grazing), grazing.size(), total_evals);
    fmt::print("\n");
    fmt::print(
        "rho(wi -> 2pi), luminance: quadrature (Q) vs Monte Carlo with importance sampling "
        "(MC), same run, medians of 5\n");
    fmt::print("{:<22} {:>6} {:>10} {:>11} {:>11} {:>12} {:>11} {:>11} {:>14}\n", "case", "theta",
               "reference", "Q32 time", "Q32 error", "MC 1e5 time", "MC error", "MC std.err",
               "MC/Q time@err");
    for (const auto& c : cases) {
        Material m = make_material(c.model, c.params);
        for (float deg : {0.f, 60.f, 85.f}) {
            Vec3 wi = spherical_direction(deg * kPi / 180.f, 0.f);
            double ref = luminance(Rgb(directional_hemispherical(m, wi, 128).value));
            double q = 0.0;
            double tq = median_seconds(
                [&] { q = luminance(Rgb(directional_hemispherical(m, wi, 16).value)); });
            const int n = 100000;
            double mc = 0.0;
            double tmc = median_seconds([&] { mc = monte_carlo(m, wi, n, 7); }, 3);
            // Standard error from 8 independent smaller runs (spread of the mean).
            std::vector<double> runs;
            for (int s = 0; s < 8; ++s) runs.push_back(monte_carlo(m, wi, n / 8, 100 + s));
            double mean = 0.0, var = 0.0;
            for (double r : runs) mean += r / runs.size();
            for (double r : runs) var += (r - mean) * (r - mean) / (runs.size() - 1);
            double stderr_n = std::sqrt(var / 8.0);  // std. error of a run with n samples
            double q_err = std::max(std::fabs(q - ref), 1e-9);
            // MC needs (stderr_n / q_err)^2 times n samples for the quadrature's error.
            double mc_time_at_q_err = tmc * (stderr_n / q_err) * (stderr_n / q_err);
            fmt::print(
                "{:<22} {:>6.0f} {:>10.6f} {:>9.2f}ms {:>11.2e} {:>10.2f}ms {:>11.2e} {:>11.2e} "
                "{:>14.3g}\n",
                c.label, deg, ref, tq * 1e3, std::fabs(q - ref), tmc * 1e3, std::fabs(mc - ref),
                stderr_n, mc_time_at_q_err / tq);
        }
    }
    return 0;
}
