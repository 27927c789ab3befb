#include "facet/reflectance.h"

#include "facet/quadrature.h"

namespace facet {

namespace {

// Directions with cos(theta) below this are treated as the horizon: the lobe samplers are
// not asked for wo exactly at the horizon, where their densities are undefined.
constexpr float kMinCos = 1e-6f;

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

// value = Q(2n); error = twice the larger of the last two successive differences among Q(n/2),
// Q(n), Q(2n). One difference alone can vanish by coincidence: the integrands have kinks where
// the half-vector map crosses the horizon, so Gauss-Legendre converges irregularly there.
template <class Eval>
Reflectance with_error(const Eval& eval, int order) {
    DVec3 coarsest = eval(std::max(1, order / 2)), coarse = eval(order), fine = eval(2 * order);
    // Factor 2: safety margin for the irregular convergence (checked against order-256
    // references over models, angles and orders in tests/core/test_reflectance.cpp).
    return {Rgb(fine), Rgb(2.0 * glm::max(glm::abs(fine - coarse), glm::abs(coarse - coarsest)))};
}

Vec3 clamp_above_horizon(Vec3 w) {
    if (w.z < kMinCos) {
        float s = std::sqrt(std::fmax(0.f, 1.f - kMinCos * kMinCos));
        float t = std::sqrt(w.x * w.x + w.y * w.y);
        w = t > 0.f ? Vec3(w.x / t * s, w.y / t * s, kMinCos) : Vec3(s, 0.f, kMinCos);
    }
    return w;
}

// int f cos dw over the free direction with `fixed_in` held: fixed = wo when fixed_is_wo
// (integrating over wi), else fixed = wi (integrating over wo). No reciprocity is assumed.
Reflectance hemispherical_integral(const Material& m, const Vec3& fixed_in, bool fixed_is_wo,
                                   int order) {
    Vec3 fixed = clamp_above_horizon(glm::normalize(fixed_in));
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

}  // namespace

Reflectance hemispherical_directional(const Material& m, const Vec3& wo, int order) {
    return hemispherical_integral(m, wo, true, order);
}

Reflectance directional_hemispherical(const Material& m, const Vec3& wi, int order) {
    return hemispherical_integral(m, wi, false, order);
}

Reflectance bihemispherical(const Material& m, int order) {
    // rho(2pi->2pi) = (1/pi) int rho(wi->2pi) cos dwi = 2 int_0^1 <rho(mu, .)>_phi mu dmu.
    // Outer Gauss-Legendre in mu and phi (phi over a quarter turn: the models are symmetric
    // under x -> -x and y -> -y), inner directional_hemispherical at its own order.
    bool isotropic = true;
    if (const MicrofacetDistribution* d = glossy_distribution(m))
        isotropic = (d->alpha_x() == d->alpha_y());
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
                Rgb r = directional_hemispherical(m, wi, n).value;
                sum += qm.weights[i] * qp.weights[j] * 2.0 * double(mu) * DVec3(r);
            }
        }
        return sum;
    };
    return with_error(eval, order);
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
