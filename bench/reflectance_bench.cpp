// Time against error for rho(wi -> 2pi): the deterministic quadrature of facet/reflectance.h
// against plain Monte Carlo with the material's own importance sampling (the peer), measured in
// the same run. For each model and incidence angle the table gives, per method and effort, the
// median time of 5 runs and the absolute error against an order-256 reference, and the ratio of
// the Monte Carlo time needed to reach the quadrature's error (extrapolated by 1/sqrt(N) from
// the largest MC run) to the quadrature's time.
#include <fmt/format.h>
#include <pcg_random.hpp>

#include <algorithm>
#include <chrono>
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

int main() {
    struct Case {
        const char* label;
        const char* model;
        ParamSet params;
    };
    auto p = [](std::initializer_list<std::pair<std::string, ParamValue>> l) {
        ParamSet s;
        for (const auto& [k, v] : l) s.set(k, v);
        return s;
    };
    std::vector<Case> cases = {
        {"ggx a=0.3 dielectric", "ggx",
         p({{"alpha", 0.3}, {"fresnel", std::string("dielectric")}})},
        {"beckmann a=0.05", "beckmann", p({{"alpha", 0.05}})},
        {"blinn k=1e4", "blinn", p({{"exponent", 1e4}})},
        {"composite ggx a=0.2", "composite", p({{"alpha", 0.2}})},
    };
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
            double ref = luminance(directional_hemispherical(m, wi, 128).value);
            double q = 0.0;
            double tq =
                median_seconds([&] { q = luminance(directional_hemispherical(m, wi, 16).value); });
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
