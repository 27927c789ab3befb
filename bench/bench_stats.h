// Small statistics shared by the benchmark programs (bench/*.cpp).
#pragma once

#include <algorithm>
#include <vector>

namespace facet::bench {

// The median of v (the mean of the two middle values for an even count); v is taken by value.
inline double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    const std::size_t n = v.size();
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

}  // namespace facet::bench
