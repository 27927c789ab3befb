// Chi-square statistic, Sidak correction and adaptive quadrature for tests/core/chi2.h.
#include "chi2.h"

#include <boost/math/special_functions/gamma.hpp>

#include <algorithm>
#include <sstream>

#include "facet/quadrature.h"

namespace facet::test {

double sidak_alpha(double alpha, int n_tests) {
    return -std::expm1(std::log1p(-alpha) / double(std::max(n_tests, 1)));
}

double chi2_survival(double statistic, int dof) {
    if (dof < 1) return 1.0;
    if (!(statistic > 0.0)) return 1.0;
    if (!std::isfinite(statistic)) return 0.0;
    return boost::math::gamma_q(0.5 * dof, 0.5 * statistic);
}

namespace {

// 4x4 Gauss-Legendre rule on a rectangle (exact for bicubic... up to degree 7 per axis).
double gl_rect(const std::function<double(double, double)>& f, double x0, double x1, double y0,
               double y1) {
    const QuadratureRule& q = gauss_legendre(4);
    double sum = 0.0;
    for (size_t i = 0; i < q.nodes.size(); ++i) {
        double x = x0 + (x1 - x0) * q.nodes[i];
        double row = 0.0;
        for (size_t j = 0; j < q.nodes.size(); ++j)
            row += q.weights[j] * f(x, y0 + (y1 - y0) * q.nodes[j]);
        sum += q.weights[i] * row;
    }
    return sum * (x1 - x0) * (y1 - y0);
}

double adapt(const std::function<double(double, double)>& f, double x0, double x1, double y0,
             double y1, double whole, double tol_per_area, double rel_tol, int depth,
             int min_depth) {
    double xm = 0.5 * (x0 + x1), ym = 0.5 * (y0 + y1);
    double q00 = gl_rect(f, x0, xm, y0, ym), q01 = gl_rect(f, x0, xm, ym, y1);
    double q10 = gl_rect(f, xm, x1, y0, ym), q11 = gl_rect(f, xm, x1, ym, y1);
    double fine = q00 + q01 + q10 + q11;
    double area = (x1 - x0) * (y1 - y0);
    // Relative criterion: the integrand is a float function, so refining below its round-off
    // (~1e-7 relative) would never converge.
    double tol = std::fmax(tol_per_area * area, rel_tol * std::fabs(fine));
    if (depth <= 0 || (min_depth <= 0 && std::fabs(fine - whole) <= tol)) return fine;
    return adapt(f, x0, xm, y0, ym, q00, tol_per_area, rel_tol, depth - 1, min_depth - 1) +
           adapt(f, x0, xm, ym, y1, q01, tol_per_area, rel_tol, depth - 1, min_depth - 1) +
           adapt(f, xm, x1, y0, ym, q10, tol_per_area, rel_tol, depth - 1, min_depth - 1) +
           adapt(f, xm, x1, ym, y1, q11, tol_per_area, rel_tol, depth - 1, min_depth - 1);
}

}  // namespace

double adaptive_integrate_2d(const std::function<double(double, double)>& f, double x0, double x1,
                             double y0, double y1, double abs_tol, double rel_tol, int max_depth,
                             int min_depth) {
    return adapt(f, x0, x1, y0, y1, gl_rect(f, x0, x1, y0, y1), abs_tol, rel_tol, max_depth,
                 min_depth);
}

Chi2Statistic chi2_statistic(const std::vector<double>& observed,
                             const std::vector<double>& expected, double min_expected) {
    Chi2Statistic s;
    struct Cell {
        double o, e;
    };
    std::vector<Cell> kept;
    Cell pooled{0.0, 0.0};
    for (size_t i = 0; i < observed.size(); ++i) {
        if (expected[i] == 0.0 && observed[i] > 0.0) s.zero_expected_hit = true;
        if (expected[i] < min_expected) {
            pooled.o += observed[i];
            pooled.e += expected[i];
            if (expected[i] > 0.0 || observed[i] > 0.0) ++s.cells_pooled;
        } else {
            kept.push_back({observed[i], expected[i]});
        }
    }
    if (pooled.e > 0.0 || pooled.o > 0.0) {
        if (pooled.e < min_expected && !kept.empty()) {
            auto it = std::min_element(kept.begin(), kept.end(),
                                       [](const Cell& a, const Cell& b) { return a.e < b.e; });
            it->o += pooled.o;
            it->e += pooled.e;
        } else {
            kept.push_back(pooled);
        }
    }
    for (const Cell& c : kept)
        if (c.e > 0.0) s.statistic += (c.o - c.e) * (c.o - c.e) / c.e;
    s.cells_used = int(kept.size());
    s.dof = s.cells_used - 1;
    s.p_value = s.zero_expected_hit ? 0.0 : chi2_survival(s.statistic, s.dof);
    return s;
}

std::string Chi2Result::describe() const {
    std::ostringstream os;
    os << "chi2 " << chi2.statistic << " dof " << chi2.dof << " p " << chi2.p_value << " (cells "
       << chi2.cells_used << ", pooled " << chi2.cells_pooled
       << (chi2.zero_expected_hit ? ", SAMPLE IN A ZERO-PDF CELL" : "") << "); n " << n
       << " specular " << specular << " (p_spec " << p_spec << ") failed " << failed
       << " below_horizon " << below_horizon << " not_unit " << not_unit << " bad_values "
       << bad_values << "; integral of pdf " << pdf_integral << "; max rel err sample vs pdf() "
       << max_pdf_rel_err << ", vs f() " << max_f_rel_err;
    return os.str();
}

}  // namespace facet::test
