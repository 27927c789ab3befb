// Inversion sampling of a discrete distribution by its running cdf in O(1) expected time: the
// cutpoint method (Chen & Asau 1974; Devroye, "Non-Uniform Random Variate Generation", 1986,
// sec. III.2.4).
//
// Conventions:
//  - `cdf` holds n >= 1 non-decreasing floats, cdf[i] = P(index <= i), cdf[n - 1] = 1. Index i
//    is chosen for u in [cdf[i - 1], cdf[i]) (cdf[-1] = 0): the first i with u < cdf[i], the
//    last one (n - 1) at most. This is std::upper_bound's answer, and find_cdf_interval returns
//    it bit for bit for every float u, so a table changes no image.
//  - The guide ("cutpoint table") holds n entries, guide[k] = the index chosen for u = k / n.
//    The search starts at guide[floor(u n)] and walks to the answer: a cell of the guide
//    covers probability 1 / n, so the walk takes about one step on average, whatever the
//    distribution's shape. It walks backward as well as forward, so float rounding of u n
//    cannot change the result.
//  - Unlike an alias table the map from u to indices stays monotone, so stratified and
//    low-discrepancy samples (Sobol) stay stratified over the cells.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>

namespace facet {

// Fills guide[0, n) for cdf[0, n) (conventions).
inline void build_cdf_guide(const float* cdf, std::size_t n, std::uint32_t* guide) {
    std::size_t i = 0;
    for (std::size_t k = 0; k < n; ++k) {
        const float t = float(k) / float(n);
        while (i < n && cdf[i] <= t) ++i;
        guide[k] = std::uint32_t(std::min(i, n - 1));
    }
}

// The index chosen by u in [0, 1) (conventions).
inline std::size_t find_cdf_interval(const float* cdf, const std::uint32_t* guide, std::size_t n,
                                     float u) {
    std::size_t i = guide[std::min(std::size_t(u * float(n)), n - 1)];
    while (i > 0 && cdf[i - 1] > u) --i;
    while (i < n && cdf[i] <= u) ++i;
    return std::min(i, n - 1);
}

}  // namespace facet
