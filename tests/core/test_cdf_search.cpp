// The cutpoint search (facet/cdf_search.h) against std::upper_bound, the answer it must give
// bit for bit (an index, so the tolerance is exact): on cdfs with zero-probability runs at the
// start, in the middle and at the end, one spike holding almost all the mass, uniform ones,
// n = 1 and n = 2^16 + 3, at u on and one ulp either side of every cdf value and of every
// guide cut k / n (where float rounding of u n can land in the next guide cell).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include "facet/cdf_search.h"
#include "facet/types.h"

namespace {

// The running cdf of `w` in float, ending exactly at 1 (as LatLongDistribution builds it).
std::vector<float> cdf_of(const std::vector<double>& w) {
    double total = 0.0;
    for (double x : w) total += x;
    std::vector<float> cdf(w.size());
    double run = 0.0;
    for (std::size_t i = 0; i < w.size(); ++i) {
        run += w[i];
        cdf[i] = float(run / total);
    }
    const float last = cdf.back();
    for (std::size_t i = cdf.size(); i-- > 0 && cdf[i] == last;) cdf[i] = 1.f;
    return cdf;
}

std::size_t reference(const std::vector<float>& cdf, float u) {
    const auto it = std::upper_bound(cdf.begin(), cdf.end(), u);
    return std::min(std::size_t(it - cdf.begin()), cdf.size() - 1);
}

// Every probe u in [0, 1) that can tell a wrong walk from the right one.
std::vector<float> probes(const std::vector<float>& cdf, std::mt19937& rng) {
    std::vector<float> u = {0.f, facet::kOneMinusEpsilon};
    auto add = [&](float x) {
        for (float y : {std::nextafter(x, 0.f), x, std::nextafter(x, 1.f)})
            if (y >= 0.f && y < 1.f) u.push_back(y);
    };
    for (float c : cdf) add(c);
    const std::size_t n = cdf.size();
    for (std::size_t k = 0; k <= n; ++k) add(float(k) / float(n));
    std::uniform_real_distribution<float> U(0.f, 1.f);
    for (int i = 0; i < 2000; ++i) u.push_back(std::min(U(rng), facet::kOneMinusEpsilon));
    return u;
}

void expect_same_as_binary_search(const std::vector<double>& w, const char* what) {
    const std::vector<float> cdf = cdf_of(w);
    std::vector<std::uint32_t> guide(cdf.size());
    facet::build_cdf_guide(cdf.data(), cdf.size(), guide.data());
    std::mt19937 rng(7);
    std::size_t wrong = 0;
    for (float u : probes(cdf, rng)) {
        const std::size_t got = facet::find_cdf_interval(cdf.data(), guide.data(), cdf.size(), u);
        if (got != reference(cdf, u) && wrong++ < 5)
            ADD_FAILURE() << what << ": u = " << u << " gave " << got << ", binary search "
                          << reference(cdf, u);
    }
    EXPECT_EQ(wrong, 0u) << what;
}

}  // namespace

TEST(CdfSearch, CutpointSearchEqualsBinarySearch) {
    expect_same_as_binary_search({1.0}, "n = 1");
    expect_same_as_binary_search({0.0, 1.0}, "leading zero");
    expect_same_as_binary_search({1.0, 0.0, 0.0}, "trailing zeros");
    std::vector<double> w(1000, 1.0);
    expect_same_as_binary_search(w, "uniform");
    std::fill(w.begin() + 200, w.begin() + 700, 0.0);
    expect_same_as_binary_search(w, "zero run in the middle");
    std::vector<double> spike(4096, 1e-9);
    spike[3001] = 1.0;
    expect_same_as_binary_search(spike, "one spike");
    std::mt19937 rng(3);
    std::exponential_distribution<double> E(1.0);
    std::vector<double> r((1u << 16) + 3);
    for (double& x : r) x = std::pow(E(rng), 6.0);  // heavy-tailed: sun-like texels
    expect_same_as_binary_search(r, "heavy-tailed, n = 2^16 + 3");
}

// The guide must make the walk short: the mean number of cells visited per lookup on a
// heavy-tailed cdf stays O(1) (at most 3; a binary search of n = 2^16 cells takes 16).
TEST(CdfSearch, WalkIsShortOnAverage) {
    std::mt19937 rng(11);
    std::exponential_distribution<double> E(1.0);
    std::vector<double> w(1u << 16);
    for (double& x : w) x = std::pow(E(rng), 6.0);
    const std::vector<float> cdf = cdf_of(w);
    std::vector<std::uint32_t> guide(cdf.size());
    facet::build_cdf_guide(cdf.data(), cdf.size(), guide.data());
    std::uniform_real_distribution<float> U(0.f, 1.f);
    double steps = 0.0;
    constexpr int kDraws = 100000;
    for (int d = 0; d < kDraws; ++d) {
        const float u = std::min(U(rng), facet::kOneMinusEpsilon);
        const std::size_t start =
            guide[std::min(std::size_t(u * float(cdf.size())), cdf.size() - 1)];
        const std::size_t end = facet::find_cdf_interval(cdf.data(), guide.data(), cdf.size(), u);
        steps += double(end >= start ? end - start : start - end);
    }
    EXPECT_LE(steps / kDraws, 3.0);
}
