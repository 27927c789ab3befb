#include "facet/quadrature.h"

#include <cmath>
#include <map>
#include <memory>
#include <mutex>
#include <stdexcept>

namespace facet {

namespace {
QuadratureRule make_gauss_legendre(int n) {
    QuadratureRule rule;
    rule.nodes.resize(n);
    rule.weights.resize(n);
    const double pi = 3.14159265358979323846;
    for (int i = 0; i < n; ++i) {
        // Initial guess (Tricomi) for the i-th root of P_n on [-1, 1], then Newton.
        double x = std::cos(pi * (i + 0.75) / (n + 0.5));
        double dp = 0.0;
        for (int iter = 0; iter < 100; ++iter) {
            double p0 = 1.0, p1 = x;  // Bonnet recurrence for P_n(x) and P_{n-1}(x)
            for (int k = 2; k <= n; ++k) {
                double p2 = ((2.0 * k - 1.0) * x * p1 - (k - 1.0) * p0) / k;
                p0 = p1;
                p1 = p2;
            }
            if (n == 1) p0 = 1.0, p1 = x;
            dp = n * (x * p1 - p0) / (x * x - 1.0);
            double dx = p1 / dp;
            x -= dx;
            if (std::fabs(dx) < 1e-16) break;
        }
        double w = 2.0 / ((1.0 - x * x) * dp * dp);
        // Map [-1, 1] -> [0, 1]; roots come out decreasing, store increasing.
        rule.nodes[n - 1 - i] = 0.5 * (x + 1.0);
        rule.weights[n - 1 - i] = 0.5 * w;
    }
    return rule;
}
}  // namespace

const QuadratureRule& gauss_legendre(int n) {
    if (n < 1 || n > 4096) throw std::invalid_argument("gauss_legendre: n must be in [1, 4096]");
    static std::mutex mutex;
    static std::map<int, std::unique_ptr<QuadratureRule>> cache;
    std::lock_guard lock(mutex);
    auto& slot = cache[n];
    if (!slot) slot = std::make_unique<QuadratureRule>(make_gauss_legendre(n));
    return *slot;
}

}  // namespace facet
