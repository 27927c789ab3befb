#include "facet/reflectance.h"

#include <boost/math/quadrature/gauss.hpp>
#include <boost/math/quadrature/gauss_kronrod.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <optional>
#include <queue>
#include <stdexcept>
#include <vector>

#include "facet/microfacet_batch.h"
#include "facet/quadrature.h"

namespace facet {

namespace {

// Directions with cos(theta) below this are treated as the horizon: the lobe samplers are
// not asked for wo exactly at the horizon, where their densities are undefined.
constexpr float kMinCos = 1e-6f;

constexpr double kMaxDouble = std::numeric_limits<double>::max();

// Cosine-weighted polar warp (smooth in u, unlike the concentric map whose kinks slow
// Gauss-Legendre down): r = sqrt(u0), phi = 2 pi u1; density cos(theta)/pi.
Vec3 cosine_polar(Vec2 u) {
    float r = std::sqrt(u.x), phi = 2.f * kPi * u.y;
    return {r * std::cos(phi), r * std::sin(phi), std::sqrt(std::fmax(0.f, 1.f - u.x))};
}

// Q(n) of int g(w) dw over the upper hemisphere through the cosine-weighted polar map;
// g already includes the cosine. Exact for the diffuse lobe (g / p constant up to its weight).
template <class Integrand>
DVec3 cosine_map_quadrature(const Integrand& g, int n) {
    const QuadratureRule& q = gauss_legendre(n);
    DVec3 sum(0.0);
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
            Vec3 w = cosine_polar(Vec2(float(q.nodes[i]), float(q.nodes[j])));
            if (w.z > 0.f) sum += q.weights[i] * q.weights[j] * DVec3(g(w)) / double(w.z * kInvPi);
        }
    return sum;
}

// Q(n) of int g(w) dw through the lobe's own half-vector sampler around `fixed`:
// w = reflect(fixed, wm(u)), density pdf(fixed, wm) / (4 |fixed . wm|) (Walter et al. 2007
// eq. 14). For a microfacet lobe g / density = F G2 / G1 (visible-normal samplers), smooth but
// for a kink where w crosses the horizon, so sharp lobes (kappa = 1e7) are resolved as well as
// broad ones. The samplers give every direction of the hemisphere a positive density, so the
// map covers the whole integrand.
template <class Integrand>
DVec3 half_vector_map_quadrature(const Integrand& g, const MicrofacetDistribution& d,
                                 const Vec3& fixed, int n) {
    const QuadratureRule& q = gauss_legendre(n);
    DVec3 sum(0.0);
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
            Vec3 wm = d.sample_wm(fixed, Vec2(float(q.nodes[i]), float(q.nodes[j])));
            float c = std::fabs(glm::dot(fixed, wm));
            Vec3 w = reflect(fixed, wm);
            if (!(w.z > 0.f) || !(c > 0.f)) continue;
            float p = d.pdf(fixed, wm) / (4.f * c);
            if (p > 0.f)
                sum += q.weights[i] * q.weights[j] * DVec3(g(glm::normalize(w))) / double(p);
        }
    return sum;
}

const MicrofacetDistribution* glossy_distribution(const Material& m) {
    if (m.glossy() && !is_specular(m.glossy()->flags())) return &m.glossy()->distribution();
    return nullptr;
}

// Closed-form part: the delta lobes' reflected fraction at cos(theta) = mu (symmetric in the
// two directions because F depends only on the angle to the normal).
Rgb delta_reflectance(const Material& m, const Vec3& fixed) {
    Rgb r(0.f);
    if (m.mirror()) r += m.mirror()->reflectance(fixed.z);
    if (m.glossy() && is_specular(m.glossy()->flags())) {
        if (auto s = m.glossy()->sample_f(fixed, 0.5f, Vec2(0.5f)))
            r += s->f * std::fabs(s->wi.z) / s->pdf;
    }
    return r;
}

// Model units' lobes (facet/inline_bxdf.h) and combinations, which the lobe-specific routines
// below do not see: a combination's reflectance is linear in its children's, c_a R_a + c_b R_b
// (values and errors), recursing with `of`; a unit's reflection lobe (Oren-Nayar: smooth over
// the hemisphere with a kink where cos(phi) changes sign; velvet) is integrated through the
// cosine map at Q(order) and Q(2 order) with that error estimate.
// nullopt for the other materials.
Reflectance with_error_of(const Material& m, const Vec3& fixed, bool fixed_is_wo, int order);
template <class Of>
std::optional<Reflectance> special_reflectance(const Material& m, const Vec3& fixed,
                                               bool fixed_is_wo, int order, const Of& of) {
    if (const Material::Combination* cm = m.combination()) {
        // A view-dependent weight is constant only when wo is the fixed direction.
        if (cm->weight != Material::MixWeight::Constant && !fixed_is_wo)
            return with_error_of(m, fixed, fixed_is_wo, order);
        const Material::Combination::At c = cm->at(fixed);
        const Reflectance a = of(*cm->a), b = of(*cm->b);
        return Reflectance{double(c.coef_a) * a.value + double(c.coef_b) * b.value,
                           double(c.coef_a) * a.error + double(c.coef_b) * b.error,
                           a.evaluations + b.evaluations};
    }
    if (m.unit() && !m.transmissive()) return with_error_of(m, fixed, fixed_is_wo, order);
    return std::nullopt;
}

// value = Q(2n); error = twice the larger of the last two successive differences among Q(n/2),
// Q(n), Q(2n). One difference alone can vanish by coincidence: the integrands have kinks where
// the half-vector map crosses the horizon, so Gauss-Legendre converges irregularly there.
template <class Eval>
Reflectance with_error(const Eval& eval, int order) {
    DVec3 coarsest = eval(std::max(1, order / 2)), coarse = eval(order), fine = eval(2 * order);
    // Factor 2: safety margin for the irregular convergence (checked against order-256
    // references over models, angles and orders in tests/core/test_reflectance.cpp).
    return {fine, 2.0 * glm::max(glm::abs(fine - coarse), glm::abs(coarse - coarsest))};
}

Vec3 clamp_above_horizon(Vec3 w) {
    if (w.z < kMinCos) {
        float s = std::sqrt(std::fmax(0.f, 1.f - kMinCos * kMinCos));
        float t = std::sqrt(w.x * w.x + w.y * w.y);
        w = t > 0.f ? Vec3(w.x / t * s, w.y / t * s, kMinCos) : Vec3(s, 0.f, kMinCos);
    }
    return w;
}

// The principled model (its own lobes, which the maps below do not know) is integrated through
// its own sampler instead: with p_k its lobe probabilities at the fixed direction w and
// u -> w'(u) lobe k's sampler (sample_f with uc inside lobe k's interval), f cos / pdf of
// the returned sample being the whole mixture's,
//     int f(w, w') cos' dw' = sum_k p_k int_[0,1)^2 f(w, w'(u)) cos' / pdf(w'(u)) du
// (one-sample MIS over the lobes), each square by an n x n Gauss-Legendre rule; delta lobes give
// their constant weight. Value Q(2n), error 2 max(|Q(n/2) - Q(n)|, |Q(n) - Q(2n)|) as the fixed
// order rule; the adaptive call doubles n from 32 until the error is below the tolerance or n
// reaches kPrincipledMaxOrder (the integrand has kinks where samples cross the horizon, so
// convergence is algebraic: read the error estimate). Without transmission the model is
// reciprocal (tests/core/test_principled.cpp), so rho(wi -> 2pi) samples from wi as well.
// Transmissive principled materials are refused (the sum would mix reflection and
// transmission).
constexpr int kPrincipledMaxOrder = 512;

DVec3 principled_quadrature(const Material& m, const Vec3& fixed, int n) {
    const PrincipledBxDF& b = *m.principled();
    const auto p = b.lobe_probabilities(fixed);
    const QuadratureRule& q = gauss_legendre(n);
    DVec3 total(0.0);
    float below = 0.f;
    for (int k = 0; k < PrincipledBxDF::kLobes; ++k) {
        if (!(p[k] > 0.f)) continue;
        const float uc = below + 0.5f * p[k];
        below += p[k];
        DVec3 sum(0.0);
        for (size_t i = 0; i < q.nodes.size(); ++i) {
            for (size_t j = 0; j < q.nodes.size(); ++j) {
                const Vec2 u(float(q.nodes[i]), float(q.nodes[j]));
                const auto s = b.sample_f(fixed, uc, u, TransportMode::Radiance);
                if (!s || !(s->pdf > 0.f)) continue;
                sum += q.weights[i] * q.weights[j] * DVec3(s->f) *
                       (double(std::fabs(s->wi.z)) / double(s->pdf));
            }
        }
        total += double(p[k]) * sum;
    }
    return total;
}

Reflectance principled_reflectance(const Material& m, const Vec3& fixed_in, int order,
                                   double tolerance) {
    if (m.transmissive())
        throw std::invalid_argument(
            "reflectance quadrature: a transmissive principled material (transmission > 0) "
            "would need reflectance and transmittance separately (not done yet)");
    const Vec3 fixed = clamp_above_horizon(glm::normalize(fixed_in));
    auto eval = [&](int n) { return principled_quadrature(m, fixed, n); };
    const int lobes = 6;
    if (order > 0) {
        Reflectance r = with_error(eval, order);
        r.evaluations = long(order) * order * 21 / 4 * lobes;
        return r;
    }
    Reflectance r;
    DVec3 coarsest = eval(16), coarse = eval(32);
    long evaluations = (16 * 16 + 32 * 32) * lobes;
    for (int n = 64;; n *= 2) {
        const DVec3 fine = eval(n);
        evaluations += long(n) * n * lobes;
        r = {fine, 2.0 * glm::max(glm::abs(fine - coarse), glm::abs(coarse - coarsest)),
             evaluations};
        if (std::max({r.error.r, r.error.g, r.error.b}) <= tolerance || n >= kPrincipledMaxOrder)
            return r;
        coarsest = coarse, coarse = fine;
    }
}

// The quadrature maps below know the lobes of the layered (diffuse + glossy + mirror) materials
// only; the principled model goes through principled_reflectance (callers check first).
void require_layered(const Material& m) {
    if (m.principled())
        throw std::invalid_argument(
            "reflectance quadrature: the principled model has no maps here (internal error)");
}

// Fixed order: int f cos dw over the free direction with `fixed_in` held: fixed = wo when
// fixed_is_wo (integrating over wi), else fixed = wi (integrating over wo). No reciprocity is
// assumed.
Reflectance with_error_of(const Material& m, const Vec3& fixed, bool fixed_is_wo, int order) {
    auto g = [&](const Vec3& w) { return (fixed_is_wo ? m.f(fixed, w) : m.f(w, fixed)) * w.z; };
    Reflectance r = with_error([&](int n) { return cosine_map_quadrature(g, n); }, order);
    r.evaluations = long(order) * order * 21 / 4;  // Q(n/2) + Q(n) + Q(2n) nodes
    return r;
}

Reflectance fixed_order_hemispherical(const Material& m, const Vec3& fixed_in, bool fixed_is_wo,
                                      int order) {
    if (m.principled()) return principled_reflectance(m, fixed_in, order, 0.0);
    require_layered(m);
    Vec3 fixed = clamp_above_horizon(glm::normalize(fixed_in));
    if (auto r = special_reflectance(m, fixed, fixed_is_wo, order, [&](const Material& c) {
            return fixed_order_hemispherical(c, fixed_in, fixed_is_wo, order);
        }))
        return *r;
    const MicrofacetDistribution* dist = glossy_distribution(m);
    Rgb delta = delta_reflectance(m, fixed);
    // Each non-delta lobe through its own map: diffuse by the cosine map, glossy by its
    // half-vector sampler (one shared map would leave the other lobe's peak unresolved).
    auto diffuse = [&](const Vec3& w) {
        return (fixed_is_wo ? m.diffuse_f(fixed, w) : m.diffuse_f(w, fixed)) * w.z;
    };
    auto glossy = [&](const Vec3& w) {
        return (fixed_is_wo ? m.glossy()->f(fixed, w) : m.glossy()->f(w, fixed)) * w.z;
    };
    return with_error(
        [&](int n) {
            DVec3 sum(delta);
            if (m.diffuse()) sum += cosine_map_quadrature(diffuse, n);
            if (dist) sum += half_vector_map_quadrature(glossy, *dist, fixed, n);
            return sum;
        },
        order);
}

// ---------------------------------------------------------------------------------------------
// Adaptive cubature (the default; see the header comment).

// Gauss 7 nested in Kronrod 15 on [0, 1]: x, Kronrod weights wk, Gauss weights wg (0 where the
// Kronrod node is not a Gauss node). From Boost.Math's tables, which hold the non-negative half
// of the rule on [-1, 1].
struct NestedRule {
    static constexpr int kSize = 15;
    std::array<double, kSize> x{}, wk{}, wg{};
};

NestedRule make_nested_rule() {
    using Kronrod = boost::math::quadrature::gauss_kronrod<double, 15>;
    using Gauss = boost::math::quadrature::gauss<double, 7>;
    const auto& kx = Kronrod::abscissa();
    const auto& kw = Kronrod::weights();
    const auto& gx = Gauss::abscissa();
    const auto& gw = Gauss::weights();
    NestedRule r;
    int n = 0;
    for (size_t i = 0; i < kx.size(); ++i) {
        double wg = 0.0;
        for (size_t j = 0; j < gx.size(); ++j)
            if (std::fabs(gx[j] - kx[i]) < 1e-14) wg = gw[j];
        for (double sign : {1.0, -1.0}) {
            if (kx[i] == 0.0 && sign < 0.0) continue;
            if (n >= NestedRule::kSize) throw std::logic_error("nested rule: too many nodes");
            r.x[n] = 0.5 * (1.0 + sign * kx[i]);
            r.wk[n] = 0.5 * kw[i];
            r.wg[n] = 0.5 * wg;
            ++n;
        }
    }
    double sk = 0.0, sg = 0.0;
    for (int i = 0; i < n; ++i) sk += r.wk[i], sg += r.wg[i];
    if (n != NestedRule::kSize || std::fabs(sk - 1.0) > 1e-14 || std::fabs(sg - 1.0) > 1e-14)
        throw std::logic_error("nested rule: bad Gauss-Kronrod tables");
    return r;
}

const NestedRule& nested_rule() {
    static const NestedRule rule = make_nested_rule();
    return rule;
}

// An integrand value, and the error it carries itself (nested integrals; 0 otherwise).
struct Sample {
    DVec3 v{0.0};
    DVec3 e{0.0};
};

// A cell [x0, x1] x [y0, y1] of the parameter rectangle with its Gauss value, the signed
// difference Gauss - Kronrod (the Gauss value's error, Kronrod being far more accurate), the
// Gauss-weighted errors its samples carry, and the part of the difference due to each
// direction (Gauss in x only, Gauss in y only), which picks the split.
struct Cell {
    double x0 = 0, x1 = 1, y0 = 0, y1 = 1;
    DVec3 gauss{0.0}, diff{0.0}, carried{0.0};
    double key = 0.0, ex = 0.0, ey = 0.0;
};

double max_of(const DVec3& v) {
    return std::max(v.x, std::max(v.y, v.z));
}

// The integrand of a cell is evaluated on the whole tensor grid at once:
// f(xs, nx, ys, ny, out) fills out[j * nx + i] with the sample at (xs[i], ys[j]), so that an
// integrand can share the work of a row (the slope map's azimuthal terms) and evaluate a cell's
// BxDF values in one batch. pointwise() adapts a function of one point.
template <class G>
auto pointwise(const G& g) {
    return [&g](const double* xs, int nx, const double* ys, int ny, Sample* out) {
        for (int j = 0; j < ny; ++j)
            for (int i = 0; i < nx; ++i) out[j * nx + i] = g(xs[i], ys[j]);
    };
}

// one_d: the integrand does not depend on y; one node at the midpoint, weight 1.
template <class F>
void evaluate_cell(const F& f, Cell& c, bool one_d, long& evaluations) {
    const NestedRule& r = nested_rule();
    constexpr int n = NestedRule::kSize;
    const int ny = one_d ? 1 : n;
    const double hx = c.x1 - c.x0, hy = c.y1 - c.y0;
    std::array<double, n> xs, ys;
    for (int i = 0; i < n; ++i) xs[i] = c.x0 + hx * r.x[i];
    for (int j = 0; j < ny; ++j) ys[j] = one_d ? 0.5 * (c.y0 + c.y1) : c.y0 + hy * r.x[j];
    std::array<Sample, n * n> s;
    f(xs.data(), n, ys.data(), ny, s.data());
    DVec3 kk(0.0), gg(0.0), gk(0.0), kg(0.0), carried(0.0);
    for (int j = 0; j < ny; ++j) {
        const double wky = one_d ? 1.0 : r.wk[j], wgy = one_d ? 1.0 : r.wg[j];
        DVec3 row_k(0.0), row_g(0.0), row_e(0.0);
        for (int i = 0; i < n; ++i) {
            const Sample& v = s[j * n + i];
            row_k += r.wk[i] * v.v;
            row_g += r.wg[i] * v.v;
            row_e += r.wg[i] * v.e;
        }
        kk += wky * row_k;
        gk += wky * row_g;  // Gauss in x, Kronrod in y
        kg += wgy * row_k;  // Kronrod in x, Gauss in y
        gg += wgy * row_g;
        carried += wgy * row_e;
    }
    evaluations += long(n) * ny;
    const double area = hx * hy;
    c.gauss = area * gg;
    c.diff = area * (gg - kk);
    c.carried = area * carried;
    c.key = max_of(glm::abs(c.diff) + c.carried);
    c.ex = area * max_of(glm::abs(gk - kk));
    c.ey = one_d ? 0.0 : area * max_of(glm::abs(kg - kk));
}

struct AdaptiveResult {
    DVec3 value{0.0}, error{0.0};
    long evaluations = 0;
};

// The error of a sum of cells: the value's error is the signed sum of the cells' errors, so
// |sum diff|; plus sqrt(sum diff^2), which covers a coincidental cancellation in that sum (the
// cells' own differences bound what can remain) and the float round-off noise of the
// integrand, which adds up like that (random signs); plus the carried errors.
struct ErrorSums {
    DVec3 diff{0.0}, diff2{0.0}, carried{0.0};
    // count: how many times the cell enters the sum (negative to remove it; 2 for a cell that
    // stands for itself and its mirror image, see adaptive_cubature).
    void add(const Cell& c, double count) {
        diff += count * c.diff;
        diff2 += count * c.diff * c.diff;
        carried += count * c.carried;
    }
    // Factor 3: the Gauss value's error is diff plus the (smaller) Kronrod error; the factor
    // covers a Kronrod error up to twice the size of diff. Calibrated on the cases of
    // tests/core/test_reflectance.cpp: with 2 one case of 78 (a composite at 89 degrees) read
    // 0.57x its true error; with 3 none is below and all are within 10x above.
    DVec3 estimate() const {
        return 3.0 * (glm::abs(diff) + glm::sqrt(glm::max(diff2, DVec3(0.0)))) + carried;
    }
};

// Global adaptive cubature from the initial cells: bisect the cell with the largest
// |diff| + carried until the error estimate is below tol (every channel) or the budget is
// spent. A cell is split along x, y or both, by which nested-rule difference dominates
// (factor 4 either way).
// copies = 2 when the integrand is mirror-symmetric and the cells cover half of the domain:
// each cell then stands for itself and its mirror image, which has the same value and the same
// nested-rule difference, so it enters the value and the error sums twice, exactly as the two
// cells of the whole domain would (the error estimate is the whole domain's), at half the
// evaluations.
template <class F>
AdaptiveResult adaptive_cubature(const F& f, const std::vector<Cell>& initial, bool one_d,
                                 double tol, long max_evaluations, double copies = 1.0) {
    auto lower = [](const Cell& a, const Cell& b) { return a.key < b.key; };
    std::priority_queue<Cell, std::vector<Cell>, decltype(lower)> queue(lower);
    std::vector<Cell> done;  // cells too small to split further
    AdaptiveResult out;
    ErrorSums sums;
    for (Cell c : initial) {
        evaluate_cell(f, c, one_d, out.evaluations);
        sums.add(c, copies);
        queue.push(c);
    }
    while (!queue.empty() && max_of(sums.estimate()) > tol && out.evaluations < max_evaluations) {
        Cell c = queue.top();
        queue.pop();
        bool sx = one_d || c.ex >= 0.25 * c.ey, sy = !one_d && c.ey >= 0.25 * c.ex;
        // Widths below 1e-12 of the unit parameter range are not split (round-off of nodes).
        sx = sx && (c.x1 - c.x0) > 1e-12;
        sy = sy && (c.y1 - c.y0) > 1e-12 * 2.0 * kPiD;
        if (!sx && !sy) {
            done.push_back(c);
            continue;
        }
        sums.add(c, -copies);
        const double xm = 0.5 * (c.x0 + c.x1), ym = 0.5 * (c.y0 + c.y1);
        for (int a = 0; a < (sx ? 2 : 1); ++a)
            for (int b = 0; b < (sy ? 2 : 1); ++b) {
                Cell k = c;
                if (sx) (a == 0 ? k.x1 : k.x0) = xm;
                if (sy) (b == 0 ? k.y1 : k.y0) = ym;
                evaluate_cell(f, k, one_d, out.evaluations);
                sums.add(k, copies);
                queue.push(k);
            }
    }
    // Exact sums (the running sums accumulate round-off from the subtractions).
    for (; !queue.empty(); queue.pop()) done.push_back(queue.top());
    ErrorSums exact;
    for (const Cell& c : done) out.value += copies * c.gauss, exact.add(c, copies);
    out.error = exact.estimate();
    return out;
}

// The half vector h in polar coordinates (rho, phi) of the stretched slope plane, slopes
// (ax rho cos phi, ay rho sin phi), h = (-sx, -sy, 1) / L, L^2 = 1 + sx^2 + sy^2, and
// rho = s tan(t A) with s the slope scale of the lobe's unit distribution (1 for GGX and
// Beckmann, sqrt(2 / nu) for Blinn) and A = atan(rho* / s): a Cauchy-like radial law, flat over
// the peak and heavy enough in the tail (GGX's integrand falls like rho^-2 there at grazing
// incidence; a map through the distribution's own CDF squeezed the horizon into a layer the
// nested rule could not see).
// Solid angles: dw_h = ax ay rho drho dphi / L^3, dw = 4 (v.h) dw_h (Walter et al. 2007 eq. 14)
// for w = reflect(v, h). The reflected w is above the horizon iff
//   N(rho) = v.z - 2 rho b(phi) - v.z rho^2 a(phi) > 0,
//   b = v.x ax cos phi + v.y ay sin phi,  a = ax^2 cos^2 phi + ay^2 sin^2 phi
// (N = L^2 w.z), whose positive root is rho* = v.z / (b + sqrt(b^2 + v.z^2 a)). So t in [0, 1]
// covers exactly the visible part, and the integrand has no kink.
// phi = phi0 + psi, phi0 the azimuth where b is largest, so that b = R cos psi changes sign at
// the cell boundaries psi = +-pi/2 (where rho* varies fastest at grazing incidence).
struct SlopeMap {
    DistributionKind kind;
    double ax, ay, nu;
    DVec3 v;
    double phi0;
    double scale;  // slope scale of the unit distribution: 1, or sqrt(2 / nu) for Blinn
    double iax2 = 1.0, iay2 = 1.0;  // 1 / ax^2, 1 / ay^2

    // The terms of the map that depend on psi only (shared by a row of nodes).
    struct Row {
        double cp, sp, a_star;
    };
    Row row(double psi) const {
        const double phi = phi0 + psi, cp = std::cos(phi), sp = std::sin(phi);
        const double b = v.x * ax * cp + v.y * ay * sp, a = ax * ax * cp * cp + ay * ay * sp * sp;
        const double rho_star = v.z / (b + std::sqrt(b * b + v.z * v.z * a));
        return {cp, sp, std::atan(rho_star / scale)};
    }

    // The reflected directions w at the n <= 15 nodes ts of a row and the Jacobians
    // dw / (dt dpsi), 0 outside the visible domain (and where not finite). rho = s tan(t A),
    // A = atan(rho* / s): radial = rho drho / dt = A s rho (1 + (rho / s)^2). No branch after
    // the tangents, so that loop vectorises (node by node, with branches, the map was most of a
    // GGX reflectance's time).
    void map_row(const Row& r, const double* ts, int n, double* wx, double* wy, double* wz,
                 double* jac) const {
        std::array<double, 16> rho;
        for (int i = 0; i < n; ++i) rho[size_t(i)] = scale * std::tan(ts[i] * r.a_star);
        const double k_radial = r.a_star * scale, inv_s2 = 1.0 / (scale * scale);
        for (int i = 0; i < n; ++i) {
            const double rh = rho[size_t(i)], r2 = rh * rh;
            const double radial = k_radial * rh * (1.0 + r2 * inv_s2);
            const double sx = ax * rh * r.cp, sy = ay * rh * r.sp;
            const double l2 = 1.0 + sx * sx + sy * sy, l = std::sqrt(l2), il = 1.0 / l;
            const double hx = -sx * il, hy = -sy * il, hz = il;
            const double vh = v.x * hx + v.y * hy + v.z * hz;
            const double x = 2.0 * vh * hx - v.x, y = 2.0 * vh * hy - v.y, z = 2.0 * vh * hz - v.z;
            const double j = 4.0 * vh * ax * ay * radial / (l2 * l);
            // Finite and positive only inside the visible domain (the test does not branch).
            const bool ok = (z > 0.0) & (vh > 0.0) & (std::fabs(j) <= kMaxDouble);
            wx[i] = x, wy[i] = y, wz[i] = z;
            jac[i] = ok ? j : 0.0;
        }
    }
};

SlopeMap slope_map(const MicrofacetDistribution& d, const DVec3& v) {
    SlopeMap s{d.kind(), double(d.alpha_x()), double(d.alpha_y()), double(d.nu()), v, 0.0, 1.0};
    if (s.kind == DistributionKind::Blinn && d.nu() == 0.f)
        throw std::logic_error("reflectance: Blinn distribution without nu");
    s.phi0 = std::atan2(v.y * s.ay, v.x * s.ax);
    if (s.kind == DistributionKind::Blinn) s.scale = std::sqrt(2.0 / s.nu);
    s.iax2 = 1.0 / (s.ax * s.ax);
    s.iay2 = 1.0 / (s.ay * s.ay);
    return s;
}

// exp(x), by its Taylor series where |x| < 1e-4 (relative error below x^4 / 24 < 5e-18): the
// corrections below are mostly within 1e-6 of 1, and std::exp / std::log in double cost as much
// as a Blinn or Beckmann BxDF evaluation.
double exp_near_zero(double x) {
    return std::fabs(x) < 1e-4 ? 1.0 + x * (1.0 + x * (0.5 + x * (1.0 / 6.0))) : std::exp(x);
}

// log(r), by its Taylor series in d = r - 1 where |d| < 1e-5 (error below d^4 / 4 < 3e-21).
double log_near_one(double r) {
    const double d = r - 1.0;
    return std::fabs(d) < 1e-5 ? d * (1.0 - d * (0.5 - d * (1.0 / 3.0))) : std::log(r);
}

// f at a node is evaluated at the float direction w_f = float(w), and the BxDF forms the half
// vector h = fixed + w_f: at grazing incidence near the mirror direction a difference of nearly
// opposite vectors, so rounding w by half an ulp (3e-8) moves h by up to ~1e-3 of a sharp lobe's
// width (GGX alpha = 1e-3 at 85 degrees: one ulp of w.x changes f by 5e-4, measured). Those
// errors do not average out (they are coherent along the tensor grid) and they made the
// refinement chase them. Only D varies on that scale (G, F and the cosines change by ~1e-7
// relative), so the value at the node is f(w_f) D(h) / D(h_f), the ratio in double from the
// distribution's slope law: log D = log P22(r) + 2 log(1 + t^2) (D = P22 / cos^4), r the
// stretched and t the plain slope of h (GGX P22 ~ (1 + r^2)^-2, Beckmann exp(-r^2), Blinn's
// Student-t (1 + r^2)^-(nu + 2)/2; see facet/microfacet.h).
// With z2 = h.z^2, q = z2 + (h.x / ax)^2 + (h.y / ay)^2 = z2 (1 + r^2) and p = z2 + h.x^2 + h.y^2
// = z2 (1 + t^2): GGX D ~ (p / q)^2 (one division per node: this runs for every node).
double rounding_correction(const SlopeMap& m, const DVec3& h, const DVec3& hf) {
    const double z2 = h.z * h.z, x2 = h.x * h.x, y2 = h.y * h.y;
    const double z2f = hf.z * hf.z, x2f = hf.x * hf.x, y2f = hf.y * hf.y;
    const double q = z2 + x2 * m.iax2 + y2 * m.iay2, p = z2 + x2 + y2;
    const double qf = z2f + x2f * m.iax2 + y2f * m.iay2, pf = z2f + x2f + y2f;
    switch (m.kind) {
        case DistributionKind::GGX:
            return sqr(p * qf / (q * pf));
        case DistributionKind::Beckmann:
            // exp(-r^2) (1 + t^2)^2: r^2 = q / z2 - 1.
            return exp_near_zero(qf / z2f - q / z2) * sqr(p * z2f / (pf * z2));
        case DistributionKind::Blinn:
            // (1 + r^2)^(-(nu + 2) / 2) (1 + t^2)^2.
            return exp_near_zero(0.5 * (m.nu + 2.0) * log_near_one(qf * z2 / (q * z2f))) *
                   sqr(p * z2f / (pf * z2));
    }
    return 1.0;
}

// Mu knots of the piecewise-linear albedo tables the integrand reads: the material's Es table
// (uniform in mu) for a composite diffuse lobe, the compensation table (uniform in sqrt(mu)).
std::vector<double> mu_knots(bool material_table, bool ms_table) {
    std::vector<double> k{0.0, 1.0};
    if (material_table)
        for (int i = 1; i < Material::kTableSize - 1; ++i)
            k.push_back(double(i) / (Material::kTableSize - 1));
    if (ms_table)
        for (int i = 1; i < MicrofacetReflection::kTableSize - 1; ++i)
            k.push_back(sqr(double(i) / (MicrofacetReflection::kTableSize - 1)));
    std::sort(k.begin(), k.end());
    k.erase(std::unique(k.begin(), k.end(), [](double a, double b) { return b - a < 1e-12; }),
            k.end());
    return k;
}

void check_settings(const QuadratureSettings& s) {
    if (!(s.tolerance > 0.0 && s.tolerance < 1.0))
        throw std::invalid_argument("reflectance: tolerance must be in (0, 1)");
    if (s.max_evaluations < 1)
        throw std::invalid_argument("reflectance: max_evaluations must be >= 1");
}

// Adaptive int f cos dw over the free direction with `fixed_in` held: fixed = wo when
// fixed_is_wo (integrating over wi), else fixed = wi (integrating over wo).
Reflectance adaptive_hemispherical(const Material& m, const Vec3& fixed_in, bool fixed_is_wo,
                                   const QuadratureSettings& settings) {
    check_settings(settings);
    if (m.principled()) return principled_reflectance(m, fixed_in, 0, settings.tolerance);
    require_layered(m);
    const Vec3 fixed = clamp_above_horizon(glm::normalize(fixed_in));
    // Order 64 for Oren-Nayar: its error estimate is reported, not refined to the tolerance.
    if (auto r = special_reflectance(m, fixed, fixed_is_wo, 64, [&](const Material& c) {
            return adaptive_hemispherical(c, fixed_in, fixed_is_wo, settings);
        }))
        return *r;
    const DVec3 v = glm::normalize(DVec3(fixed));
    Reflectance out;
    out.value = DVec3(delta_reflectance(m, fixed));
    const MicrofacetDistribution* dist = glossy_distribution(m);
    const MicrofacetReflection* lobe = dist ? &*m.glossy() : nullptr;
    const bool ms = lobe && lobe->has_multiple_scattering();
    const bool cosine_part = m.diffuse() || ms;
    // Tolerance split: most to the peaked glossy term; the cosine-like terms are piecewise
    // polynomial on their panels and converge at once.
    const double tol_glossy = settings.tolerance * (cosine_part ? 0.75 : 1.0);
    const double tol_cosine = settings.tolerance * (dist ? 0.25 : 1.0);
    auto eval = [&](const auto& fn, const Vec3& w) {
        return fixed_is_wo ? fn(fixed, w) : fn(w, fixed);
    };
    if (dist) {
        const SlopeMap map = slope_map(*dist, v);
        // A cell's 225 values of f_single in one batch against the fixed direction
        // (facet/microfacet_batch.h: GGX and Blinn vectorised, Beckmann with Lambda(fixed) once).
        const MicrofacetBatch batch(*lobe);
        const Vec3 fixed_f(fixed);
        const DVec3 fixed_d(fixed);  // the direction the BxDF sees (not renormalised)
        auto g = [&](const double* ts, int nt, const double* psis, int np, Sample* out) {
            constexpr int kMax = NestedRule::kSize * NestedRule::kSize;
            std::array<float, kMax> wx, wy, wz, fr, fg, fb;
            std::array<double, kMax> weight;
            const int n = nt * np;
            std::array<double, NestedRule::kSize> mx, my, mz, mjac;
            for (int j = 0; j < np; ++j) {
                const SlopeMap::Row row = map.row(psis[j]);
                map.map_row(row, ts, nt, mx.data(), my.data(), mz.data(), mjac.data());
                for (int i = 0; i < nt; ++i) {
                    const int k = j * nt + i;
                    const DVec3 w(mx[size_t(i)], my[size_t(i)], mz[size_t(i)]);
                    const double jac = mjac[size_t(i)];
                    Vec3 wf(w);
                    weight[k] = jac != 0.0 && wf.z > 0.f ? double(wf.z) * jac : 0.0;
                    if (weight[k] == 0.0) {
                        wf = Vec3(0.f, 0.f, 1.f);  // any valid direction
                    } else {
                        const double c = rounding_correction(map, fixed_d + w, fixed_d + DVec3(wf));
                        weight[k] *= std::isfinite(c) ? c : 1.0;
                    }
                    wx[k] = wf.x, wy[k] = wf.y, wz[k] = wf.z;
                }
            }
            batch.f_single_fixed(size_t(n), fixed_f, fixed_is_wo,
                                 Vec3Soa{wx.data(), wy.data(), wz.data()},
                                 RgbSoa{fr.data(), fg.data(), fb.data()});
            for (int k = 0; k < n; ++k)
                out[k] = weight[k] == 0.0
                             ? Sample{}
                             : Sample{DVec3(fr[k], fg[k], fb[k]) * weight[k], DVec3(0.0)};
        };
        std::vector<Cell> cells;
        // Cells in u graded toward the horizon end u = 1 (the tan map's heavy tail, where at
        // grazing incidence the integrand turns from ~1/rho^3 to ~1/rho^2 near rho = v.z / |b|,
        // close to u = 1): a nested pair on one wide cell can miss that.
        const std::vector<double> u_cuts{0.0, 0.9, 0.99, 1.0};
        // Mirror symmetry psi -> -psi (phi0 + psi -> phi0 - psi): D(h) depends on the slopes
        // only through (sx / ax)^2 + (sy / ay)^2, G on the directions' stretched slopes, F on
        // v.h, so the integrand is symmetric when that reflection maps the stretched slope plane
        // onto itself: isotropic lobes (any azimuth), or v in a symmetry plane of an anisotropic
        // one (v.x = 0 or v.y = 0). Then only psi in [0, pi] is integrated, each cell counting
        // twice (half the evaluations; the float rounding of the mirrored nodes differs by an
        // ulp, which the rounding correction below makes immaterial).
        const bool mirror = map.ax == map.ay || fixed.x == 0.f || fixed.y == 0.f;
        for (size_t i = 0; i + 1 < u_cuts.size(); ++i)
            for (int q = mirror ? 1 : 0; q < (mirror ? 3 : 4); ++q) {
                Cell c;
                c.x0 = u_cuts[i];
                c.x1 = u_cuts[i + 1];
                c.y0 = (q - 1) * 0.5 * kPiD;
                c.y1 = q * 0.5 * kPiD;
                cells.push_back(c);
            }
        AdaptiveResult r = adaptive_cubature(g, cells, false, tol_glossy, settings.max_evaluations,
                                             mirror ? 2.0 : 1.0);
        out.value += r.value;
        out.error += r.error;
        out.evaluations += r.evaluations;
    }
    if (cosine_part) {
        const bool one_d = !ms || lobe->multiple_scattering_is_isotropic();
        const bool table = m.diffuse() && (m.glossy() || m.mirror());
        auto g = [&](double mu, double phi) {
            const double s = std::sqrt(std::max(0.0, (1.0 - mu) * (1.0 + mu)));
            const Vec3 wf(DVec3(s * std::cos(phi), s * std::sin(phi), mu));
            if (!(wf.z > 0.f)) return Sample{};
            Rgb f(0.f);
            if (m.diffuse())
                f += eval([&](const Vec3& a, const Vec3& b) { return m.diffuse_f(a, b); }, wf);
            if (ms)
                f += eval([&](const Vec3& a, const Vec3& b) { return lobe->f_multiple(a, b); }, wf);
            return Sample{DVec3(f) * double(wf.z), DVec3(0.0)};
        };
        const std::vector<double> knots = mu_knots(table, ms);
        std::vector<Cell> cells;
        for (size_t i = 0; i + 1 < knots.size(); ++i)
            for (int q = 0; q < (one_d ? 1 : 4); ++q) {
                Cell c;
                c.x0 = knots[i];
                c.x1 = knots[i + 1];
                c.y0 = one_d ? 0.0 : q * 0.5 * kPiD;
                c.y1 = one_d ? 2.0 * kPiD : (q + 1) * 0.5 * kPiD;
                cells.push_back(c);
            }
        const long budget = std::max(1L, settings.max_evaluations - out.evaluations);
        AdaptiveResult r = adaptive_cubature(pointwise(g), cells, one_d, tol_cosine, budget);
        out.value += r.value;
        out.error += r.error;
        out.evaluations += r.evaluations;
    }
    return out;
}

bool is_isotropic(const Material& m) {
    if (m.combination() || m.principled()) return !m.anisotropic();
    if (const MicrofacetDistribution* d = glossy_distribution(m))
        return d->alpha_x() == d->alpha_y();
    return true;
}
}  // namespace

Reflectance hemispherical_directional(const Material& m, const Vec3& wo,
                                      const QuadratureSettings& settings) {
    return adaptive_hemispherical(m, wo, true, settings);
}

Reflectance directional_hemispherical(const Material& m, const Vec3& wi,
                                      const QuadratureSettings& settings) {
    return adaptive_hemispherical(m, wi, false, settings);
}

Reflectance bihemispherical(const Material& m, const QuadratureSettings& settings) {
    // rho(2pi->2pi) = 2 int_0^1 <rho(mu, .)>_phi mu dmu, phi over a quarter turn (the models are
    // symmetric under x -> -x and y -> -y), by the adaptive cubature over (mu, phi / (pi/2)),
    // one-dimensional for isotropic materials. The inner directional reflectances are computed
    // to a fifth of the tolerance; their errors enter the cells' errors (Sample::e).
    check_settings(settings);
    const bool one_d = is_isotropic(m);
    QuadratureSettings inner = settings;
    inner.tolerance = 0.2 * settings.tolerance;
    long evaluations = 0;
    auto g = [&](double mu, double s) {
        const double phi = s * 0.5 * kPiD, st = std::sqrt(std::max(0.0, (1.0 - mu) * (1.0 + mu)));
        const Vec3 wi(DVec3(st * std::cos(phi), st * std::sin(phi), mu));
        inner.max_evaluations = std::max(1L, settings.max_evaluations - evaluations);
        Reflectance r = directional_hemispherical(m, wi, inner);
        evaluations += r.evaluations;
        return Sample{2.0 * mu * r.value, 2.0 * mu * r.error};
    };
    const bool table = m.diffuse() && (m.glossy() || m.mirror());
    const std::vector<double> knots = mu_knots(table, false);
    std::vector<Cell> cells;
    for (size_t i = 0; i + 1 < knots.size(); ++i) {
        Cell c;
        c.x0 = knots[i];
        c.x1 = knots[i + 1];
        cells.push_back(c);
    }
    AdaptiveResult r = adaptive_cubature(pointwise(g), cells, one_d, settings.tolerance, 1L << 40);
    return {r.value, r.error, evaluations};
}

Reflectance hemispherical_directional(const Material& m, const Vec3& wo, int order) {
    return fixed_order_hemispherical(m, wo, true, order);
}

Reflectance directional_hemispherical(const Material& m, const Vec3& wi, int order) {
    return fixed_order_hemispherical(m, wi, false, order);
}

Reflectance bihemispherical(const Material& m, int order) {
    // rho(2pi->2pi) = (1/pi) int rho(wi->2pi) cos dwi = 2 int_0^1 <rho(mu, .)>_phi mu dmu.
    // Outer Gauss-Legendre in mu and phi (phi over a quarter turn: the models are symmetric
    // under x -> -x and y -> -y), inner directional_hemispherical at its own order.
    const bool isotropic = is_isotropic(m);
    auto eval = [&](int n) {
        const QuadratureRule& qm = gauss_legendre(n);
        const QuadratureRule& qp = gauss_legendre(isotropic ? 1 : n / 2);
        DVec3 sum(0.0);
        for (size_t i = 0; i < qm.nodes.size(); ++i) {
            float mu = float(qm.nodes[i]);
            for (size_t j = 0; j < qp.nodes.size(); ++j) {
                float phi = float(qp.nodes[j]) * kPiOver2;
                Vec3 wi(safe_sqrt(1.f - mu * mu) * std::cos(phi),
                        safe_sqrt(1.f - mu * mu) * std::sin(phi), mu);
                DVec3 r = directional_hemispherical(m, wi, n).value;
                sum += qm.weights[i] * qp.weights[j] * 2.0 * double(mu) * r;
            }
        }
        return sum;
    };
    return with_error(eval, order);
}

Scattering directional_scattering(const Material& m, const Vec3& w, int n, int strata,
                                  int delta_strata) {
    if (n < 2 || strata < 2 || delta_strata < 2)
        throw std::invalid_argument("directional_scattering: n, strata and delta_strata >= 2");
    const Vec3 wn = glm::normalize(w);
    // Sums of f |cos| / pdf per side over a midpoint grid with `step` (1: every stratum, 2: every
    // other, i.e. the half-resolution rule on the same nodes' superset). Returns {same, other}.
    struct Sums {
        DVec3 same{0.0}, other{0.0};
    };
    auto add = [&](Sums& acc, const std::optional<BSDFSample>& bs, bool want_delta, double wt) {
        if (!bs || !(bs->pdf > 0.f) || bs->is_specular() != want_delta) return;
        const DVec3 v = DVec3(bs->f) * double(std::fabs(bs->wi.z)) / double(bs->pdf) * wt;
        if (!std::isfinite(v.x + v.y + v.z)) return;
        ((bs->wi.z > 0.f) == (wn.z > 0.f) ? acc.same : acc.other) += v;
    };
    auto delta_pass = [&](int k) {
        Sums acc;
        for (int i = 0; i < k; ++i) {
            const float uc = float((i + 0.5) / k);
            add(acc, m.sample_f(wn, uc, Vec2(0.5f), TransportMode::Importance), true, 1.0 / k);
        }
        return acc;
    };
    auto smooth_pass = [&](int kc, int ku) {
        Sums acc;
        const double wt = 1.0 / (double(kc) * ku * ku);
        for (int c = 0; c < kc; ++c) {
            const float uc = float((c + 0.5) / kc);
            for (int i = 0; i < ku; ++i)
                for (int j = 0; j < ku; ++j) {
                    const Vec2 u(float((i + 0.5) / ku), float((j + 0.5) / ku));
                    add(acc, m.sample_f(wn, uc, u, TransportMode::Importance), false, wt);
                }
        }
        return acc;
    };
    const Sums d = delta_pass(delta_strata), dh = delta_pass(delta_strata / 2);
    const Sums g = smooth_pass(strata, n), gh = smooth_pass(strata / 2, n / 2);
    Scattering out;
    out.reflected.value = d.same + g.same;
    out.transmitted.value = d.other + g.other;
    out.reflected.error = glm::abs(d.same - dh.same) + glm::abs(g.same - gh.same);
    out.transmitted.error = glm::abs(d.other - dh.other) + glm::abs(g.other - gh.other);
    const long evals = long(delta_strata) + delta_strata / 2 + long(strata) * n * n +
                       long(strata / 2) * (n / 2) * (n / 2);
    out.reflected.evaluations = out.transmitted.evaluations = evals;
    return out;
}

Reflectance biconical(const Material& m, const Cone& in, const Cone& out, int order) {
    Frame fin = Frame::from_z(glm::normalize(in.axis));
    Frame fout = Frame::from_z(glm::normalize(out.axis));
    float cin = std::cos(in.half_angle), cout = std::cos(out.half_angle);
    // Cone directions: cos(gamma) in [cos(half), 1] and psi in [0, 2 pi) around the axis;
    // solid angle element d(cos gamma) d psi, so each node weighs (1 - cos half) 2 pi w_i w_j.
    auto cone_dir = [](const Frame& f, float cos_half, double a, double b) {
        float cg = float(1.0 - a * (1.0 - cos_half));
        float sg = safe_sqrt(1.f - cg * cg);
        float psi = float(2.0 * kPiD * b);
        return f.from_local(Vec3(sg * std::cos(psi), sg * std::sin(psi), cg));
    };
    auto eval = [&](int n) {
        const QuadratureRule& q = gauss_legendre(n);
        double area_in = (1.0 - cin) * 2.0 * kPiD, area_out = (1.0 - cout) * 2.0 * kPiD;
        DVec3 num(0.0);
        double den = 0.0;
        for (int a = 0; a < n; ++a)
            for (int b = 0; b < n; ++b) {
                Vec3 wi = cone_dir(fin, cin, q.nodes[a], q.nodes[b]);
                if (!(wi.z > 0.f)) continue;
                double wgt_i = q.weights[a] * q.weights[b] * area_in * wi.z;
                den += wgt_i;
                // Delta lobes: all of their reflected flux leaves along reflect(wi, n).
                Vec3 wr(-wi.x, -wi.y, wi.z);
                if (glm::dot(wr, fout.z) >= cout) num += wgt_i * DVec3(delta_reflectance(m, wi));
                for (int c = 0; c < n; ++c)
                    for (int d = 0; d < n; ++d) {
                        Vec3 wo = cone_dir(fout, cout, q.nodes[c], q.nodes[d]);
                        if (!(wo.z > 0.f)) continue;
                        double wgt_o = q.weights[c] * q.weights[d] * area_out * wo.z;
                        num += wgt_i * wgt_o * DVec3(m.f(wo, wi));
                    }
            }
        return den > 0.0 ? num / den : DVec3(0.0);
    };
    return with_error(eval, order);
}

Rgb phi_averaged_albedo(const MicrofacetReflection& lobe, float mu, int order) {
    mu = std::max(mu, kMinCos);
    const MicrofacetDistribution& d = lobe.distribution();
    if (is_specular(lobe.flags())) {
        auto s = lobe.sample_f(Vec3(safe_sqrt(1.f - mu * mu), 0.f, mu), 0.5f, Vec2(0.5f));
        return s ? s->f * std::fabs(s->wi.z) / s->pdf : Rgb(0.f);
    }
    const QuadratureRule& qp = gauss_legendre((d.alpha_x() == d.alpha_y()) ? 1 : 4);
    DVec3 sum(0.0);
    for (size_t j = 0; j < qp.nodes.size(); ++j) {
        float phi = float(qp.nodes[j]) * kPiOver2;
        float s = safe_sqrt(1.f - mu * mu);
        Vec3 wo(s * std::cos(phi), s * std::sin(phi), mu);
        sum += qp.weights[j] *
               half_vector_map_quadrature([&](const Vec3& wi) { return lobe.f(wo, wi) * wi.z; }, d,
                                          wo, order);
    }
    return Rgb(sum);
}

}  // namespace facet
