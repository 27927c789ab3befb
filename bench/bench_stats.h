// Small statistics and options shared by the benchmark programs (bench/*.cpp).
#pragma once

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <vector>

namespace facet::bench {

// The median of v (the mean of the two middle values for an even count); v is taken by value.
inline double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    const std::size_t n = v.size();
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

// The Monte Carlo benchmarks' options: --trials T (estimates per run) and --runs K (runs with
// different seeds, of which the tables give medians).
struct TrialOptions {
    int trials = 20000, runs = 5;
};
inline TrialOptions trial_options(int argc, char** argv) {
    TrialOptions o;
    for (int i = 1; i + 1 < argc; i += 2) {
        if (!std::strcmp(argv[i], "--trials")) o.trials = std::atoi(argv[i + 1]);
        if (!std::strcmp(argv[i], "--runs")) o.runs = std::atoi(argv[i + 1]);
    }
    return o;
}

}  // namespace facet::bench
