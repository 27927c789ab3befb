// Helpers shared by the light-sampling tests: Monte Carlo estimates over uniform points of the
// unit square, their check against an expected value, and one light sample's irradiance.
//
// expect_mc allows 4 standard errors of the estimate, computed from the samples (a false
// failure has probability ~6e-5 per check), plus 1e-6 relative for float round-off.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>

#include "facet/render/light.h"
#include "facet/testsupport/render_test_util.h"

namespace facet::render::testing {

// n scaled by FACET_STRESS_SCALE (stress_scale()), at least 2000 samples.
inline int scaled(int n) {
    return std::max(2000, int(n * stress_scale()));
}

// The mean of f(u) over n independent uniform points u of [0, 1)^2 (mt19937 from `seed`), and
// its standard error.
template <class F>
McResult mc_unit_square(int n, std::uint32_t seed, F f) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(0.f, 1.f);
    return mc(n, [&](int) { return f(Vec2(u(rng), u(rng))); });
}

inline void expect_mc(const McResult& m, double expected) {
    EXPECT_NEAR(m.mean, expected, 4.0 * m.stderr_ + 1e-6 * std::fabs(expected))
        << "mean " << m.mean << " +- " << m.stderr_ << ", expected " << expected;
}

// Irradiance estimate of one light sample on a surface of normal ctx.n (red channel).
inline double irradiance(const Light& l, const LightSampleContext& ctx, Vec2 u) {
    const auto s = l.sample_li(ctx, u);
    if (!s) return 0.0;
    const double c = glm::dot(s->wi, ctx.n);
    return c > 0.0 ? double(s->li.r) * c / double(s->pdf) : 0.0;
}

}  // namespace facet::render::testing
