// Participating media: what a medium is to the integrator, and the Cycles conversion.
//
// Conventions:
//  - Coefficients are per scene unit of length, per RGB channel: absorption sigma_a, scattering
//    sigma_s, extinction sigma_t = sigma_a + sigma_s (1/length). Emission is radiance per unit
//    length (W sr^-1 m^-2 per scene unit), Cycles' volume emission: a segment of length l of a
//    purely emitting medium adds emission * l to the radiance along it. The radiative transfer
//    equation integrated along a ray (pbrt-v4 §11.1, eq. 11.13) is then
//      L(o, w) = int_0^t T(s) [emission + sigma_s int p L_i] ds + T(t) L_surface,
//    with T(s) = exp(-int_0^s sigma_t) the transmittance (Beer-Lambert).
//  - Phase function: Henyey-Greenstein (facet/henyey_greenstein.h), Cycles' anisotropy g.
//  - A medium kind (kinds.h, MediumKindDef: one unit per kind in core/render/src/media/) builds
//    a Medium from its description. `homogeneous` has constant coefficients, so every integral
//    along a segment is closed-form (transmittance(), emitted()). `grid` scales per-unit-density
//    coefficients by a DensityGrid (facet/render/density_grid.h); its segments are sampled by
//    tracking against the grid's majorants: free flights by spectral delta tracking with null
//    collisions (Kutz et al. 2017, "Spectral and decomposition tracking", §4, with no
//    absorption events: absorption stays in the weight) and transmittance by ratio tracking
//    (Novák et al. 2014, eq. 12). Both are unbiased; their random numbers come from a
//    caller's uniform generator. Directions are unit vectors, so t is a distance.
//  - Media are never evaluated per sample in a scene without any (SceneFeatures::has_media:
//    the render kernel with media is chosen only then; integrator.h).
#pragma once

#include <cmath>
#include <cstdint>

#include <memory>

#include "facet/henyey_greenstein.h"
#include "facet/render/density_grid.h"
#include "facet/types.h"

namespace facet::render {

enum class MediumKind : std::uint8_t { Homogeneous, Grid };

// What a grid medium emits at a point x of its density grid's box (0 outside it), radiance per
// unit length as Cycles' Principled Volume (not scaled by the density):
//   e(x) = color * (grid ? grid(x) : 1)
//        + principled_volume_blackbody(blackbody, temperature * (temperature_grid ?
//          max(temperature_grid(x), 0) : 1), tint)            (facet/blackbody.h)
// Grids are read from the density's file; each is 0 outside its own box.
struct GridEmission {
    Rgb color{0.f};
    std::shared_ptr<const DensityGrid> grid;  // none: color is constant over the box
    float blackbody = 0.f;                    // Blackbody Intensity; 0 = no blackbody term
    float temperature = 1000.f;               // kelvin, or a factor on temperature_grid
    Rgb tint{1.f};
    std::shared_ptr<const DensityGrid> temperature_grid;  // none: temperature is constant

    // e(x) (media/grid.cpp: out of line, so that the kernels of scenes without emitting grids
    // are compiled exactly as without it).
    Rgb at(const Vec3& p) const;
};

class Medium {
  public:
    Medium() = default;
    // A homogeneous medium (coefficients >= 0, |g| < 1: the builder checks).
    static Medium homogeneous(const Rgb& sigma_a, const Rgb& sigma_s, float g,
                              const Rgb& emission) {
        Medium m;
        m.m_kind = MediumKind::Homogeneous;
        m.m_sigma_a = sigma_a;
        m.m_sigma_s = sigma_s;
        m.m_sigma_t = sigma_a + sigma_s;
        m.m_phase = HenyeyGreenstein(g);
        m.m_emission = emission;
        return m;
    }

    // A heterogeneous medium: coefficients per unit of the grid's density (>= 0, |g| < 1; the
    // builder checks), and what it emits (none: nothing; emission() stays 0 either way, the
    // emission is gathered by tracking).
    static Medium grid(std::shared_ptr<const DensityGrid> grid, const Rgb& sigma_a,
                       const Rgb& sigma_s, float g,
                       std::shared_ptr<const GridEmission> emission = nullptr) {
        Medium m = homogeneous(sigma_a, sigma_s, g, Rgb(0.f));
        m.m_kind = MediumKind::Grid;
        m.m_grid = std::move(grid);
        m.m_sigma_t_max = max_channel(m.m_sigma_t);
        m.m_grid_emission = std::move(emission);
        return m;
    }

    MediumKind kind() const { return m_kind; }
    bool heterogeneous() const { return m_grid != nullptr; }
    const DensityGrid& density_grid() const { return *m_grid; }
    // Homogeneous: the coefficients; grid: per unit density.
    const Rgb& sigma_a() const { return m_sigma_a; }
    const Rgb& sigma_s() const { return m_sigma_s; }
    // The extinction coefficient; for a heterogeneous kind the majorant of a segment.
    const Rgb& sigma_t() const { return m_sigma_t; }
    const Rgb& emission() const { return m_emission; }
    // A grid medium's emission (nullptr when it emits nothing).
    const GridEmission* grid_emission() const { return m_grid_emission.get(); }
    const HenyeyGreenstein& phase() const { return m_phase; }
    bool emits() const { return m_emission != Rgb(0.f); }
    // Nothing scatters: free-flight sampling is not needed, the transmittance is the whole
    // answer (a purely absorbing medium renders exactly, without noise).
    bool absorbing_only() const { return m_sigma_s == Rgb(0.f); }

    // Transmittance exp(-sigma_t t) of a segment of length t >= 0 (t may be +inf: 0 in every
    // channel with sigma_t > 0, 1 where sigma_t = 0).
    Rgb transmittance(float t) const {
        if (m_sigma_t.r == m_sigma_t.g && m_sigma_t.g == m_sigma_t.b)  // grey: one exp
            return Rgb(channel_transmittance(m_sigma_t.r, t));
        return {channel_transmittance(m_sigma_t.r, t), channel_transmittance(m_sigma_t.g, t),
                channel_transmittance(m_sigma_t.b, t)};
    }
    // The emission a segment [0, t] adds to the radiance at its start, before the throughput:
    // int_0^t T(s) emission ds = emission (1 - exp(-sigma_t t)) / sigma_t per channel
    // (emission t where sigma_t = 0; a segment of infinite length in a medium with sigma_t = 0
    // and emission > 0 gives +inf, which the film drops and counts).
    Rgb emitted(float t) const {
        Rgb e;
        for (int c = 0; c < 3; ++c) {
            const float s = m_sigma_t[c];
            e[c] = s > 0.f ? m_emission[c] * (-std::expm1(-s * t)) / s : m_emission[c] * t;
        }
        return e;
    }

    // Grid media. Ratio tracking: the transmittance of o + t d, t in [0, t_max), estimated
    // without bias as the product of (1 - sigma_t(x) / mu) over the tentative collisions with
    // the grey majorant mu = majorant * max_c sigma_t[c] (>= every channel's sigma_t(x)).
    template <class Uniform>
    Rgb ratio_transmittance(const Vec3& o, const Vec3& d, float t_max, Uniform&& uniform) const {
        Rgb tr(1.f);
        track(
            o, d, t_max, uniform,
            [&](float, float dens, float mu) {
                for (int c = 0; c < 3; ++c) tr[c] *= std::fmax(1.f - m_sigma_t[c] * dens / mu, 0.f);
                return max_channel(tr) > 0.f;
            },
            [](float, float) {});
        return tr;
    }
    // Spectral delta tracking on o + t d, t in [0, t_max): the distance of a real scattering
    // collision (< t_max), or t_max. At a tentative collision x with the grey majorant mu, the
    // collision scatters with probability P_s = <beta, sigma_s(x)> / (<beta, sigma_s(x)> +
    // <beta, sigma_n(x)>), sigma_n = mu - sigma_t(x) (else it is null), and beta takes
    // sigma_s(x) / (mu P_s) or sigma_n(x) / (mu (1 - P_s)): the collision estimator of the
    // null-collision RTE with absorption kept in the weight (the absorbed term has no emission).
    template <class Uniform>
    float sample_free_flight(const Vec3& o, const Vec3& d, float t_max, Uniform&& uniform,
                             Rgb& beta) const {
        Rgb none(0.f);
        return free_flight<false>(o, d, t_max, uniform, beta, none);
    }
    // The same, with the medium's emission along the way added to L (weighted by beta): at each
    // tentative collision x, beta e(x) / mu before the collision's choice (the collision
    // estimator of int T(s) e(s) ds against the majorant's free-flight density: e is radiance per
    // unit length, Cycles' convention, not sigma_a-weighted), and on each piece of majorant 0
    // (no extinction, so T is constant there) beta (t1 - t0) e(x) at one uniformly placed x.
    // Unbiased; exact for constant emission over an empty piece.
    template <class Uniform>
    float sample_free_flight(const Vec3& o, const Vec3& d, float t_max, Uniform&& uniform,
                             Rgb& beta, Rgb& L) const {
        if (m_grid_emission) return free_flight<true>(o, d, t_max, uniform, beta, L);
        return free_flight<false>(o, d, t_max, uniform, beta, L);
    }

  private:
    template <bool Emits, class Uniform>
    float free_flight(const Vec3& o, const Vec3& d, float t_max, Uniform& uniform, Rgb& beta,
                      Rgb& L) const {
        float result = t_max;
        auto collide = [&](float t, float dens, float mu) {
            if constexpr (Emits) L += beta * m_grid_emission->at(o + d * t) / mu;
            const Rgb s_s = m_sigma_s * dens;
            Rgb s_n;
            for (int c = 0; c < 3; ++c) s_n[c] = std::fmax(mu - m_sigma_t[c] * dens, 0.f);
            const float w_s = glm::dot(beta, s_s), w_n = glm::dot(beta, s_n);
            if (!(w_s + w_n > 0.f)) {  // every channel with throughput is absorbed here
                beta = Rgb(0.f);
                result = t;
                return false;
            }
            const float p_s = w_s / (w_s + w_n);
            if (uniform() < p_s) {
                beta *= s_s / (mu * p_s);
                result = t;
                return false;
            }
            beta *= s_n / (mu * (1.f - p_s));
            return true;
        };
        if constexpr (Emits) {
            track(o, d, t_max, uniform, collide, [&](float t0, float t1) {
                const float t = t0 + (t1 - t0) * uniform();
                L += beta * m_grid_emission->at(o + d * t) * (t1 - t0);
            });
        } else {
            track(o, d, t_max, uniform, collide, [](float, float) {});
        }
        return result;
    }

    // The tentative collisions of o + t d, t in [0, t_max), with the grey majorant of each
    // majorant cell (exponential steps of rate mu; cells of majorant 0 are passed to
    // empty(t0, t1)): calls at(t, density(x), mu) at each, front to back, until it returns false.
    template <class Uniform, class At, class Empty>
    void track(const Vec3& o, const Vec3& d, float t_max, Uniform& uniform, At&& at,
               Empty&& empty) const {
        m_grid->march(o, d, t_max, [&](float t0, float t1, float majorant) {
            const float mu = majorant * m_sigma_t_max;
            if (!(mu > 0.f)) {
                empty(t0, t1);
                return true;
            }
            for (float t = t0;;) {
                t -= std::log1p(-uniform()) / mu;
                if (!(t < t1)) return true;
                if (!at(t, m_grid->density(o + d * t), mu)) return false;
            }
        });
    }
    static float max_channel(const Rgb& c) { return std::fmax(std::fmax(c.r, c.g), c.b); }
    static float channel_transmittance(float sigma_t, float t) {
        return sigma_t > 0.f ? std::exp(-sigma_t * t) : 1.f;
    }
    MediumKind m_kind = MediumKind::Homogeneous;
    Rgb m_sigma_a{0.f}, m_sigma_s{0.f}, m_sigma_t{0.f}, m_emission{0.f};
    HenyeyGreenstein m_phase;
    std::shared_ptr<const DensityGrid> m_grid;            // grid kind only
    std::shared_ptr<const GridEmission> m_grid_emission;  // grid kind, when it emits
    float m_sigma_t_max = 0.f;                            // grid kind: max_c sigma_t[c]
};

// Equiangular sampling of a distance along a ray segment toward a point c (Kulla & Fajardo
// 2012, "Importance Sampling Techniques for Path Tracing in Participating Media", §4.1): on
// o + t d, t in [0, t_max) (t_max may be +inf), with density proportional to 1 / |o + t d - c|^2,
// the falloff of a point light's irradiance. With Delta = dot(c - o, d) the foot of c on the
// ray's line and D the distance of c from that line,
//   t = Delta + D tan(theta),  theta uniform in [theta_a, theta_b],
//   theta_a = atan2(-Delta, D), theta_b = atan2(t_max - Delta, D),
//   pdf(t) = D / ((theta_b - theta_a) (D^2 + (t - Delta)^2))   (per unit length).
// d is a unit vector. Not valid (no density) when c lies on the ray's line (D = 0) or the
// segment subtends no angle.
class Equiangular {
  public:
    Equiangular(const Vec3& o, const Vec3& d, float t_max, const Vec3& c)
        : Equiangular(o, d, 0.f, t_max, c) {}
    // Over [t_min, t_max) (0 <= t_min).
    Equiangular(const Vec3& o, const Vec3& d, float t_min, float t_max, const Vec3& c) {
        const Vec3 oc = c - o;
        m_delta = glm::dot(oc, d);
        m_d = glm::length(oc - d * m_delta);  // no cancellation when d points at c
        m_theta_a = std::atan2(t_min - m_delta, m_d);
        m_theta_b = std::atan2(t_max - m_delta, m_d);
        m_t_min = t_min;
        m_t_max = t_max;
    }
    bool valid() const { return m_d > 0.f && m_theta_b > m_theta_a && std::isfinite(m_d); }
    // D, the distance of c from the ray's line: the scale of the density around its peak.
    float distance() const { return m_d; }
    // The distance for u in [0, 1), clamped into [t_min, t_max] against rounding (the caller
    // skips t >= t_max). Call only when valid().
    float sample(float u) const {
        const float t = m_delta + m_d * std::tan(m_theta_a + u * (m_theta_b - m_theta_a));
        return std::fmin(std::fmax(t, m_t_min), m_t_max);
    }
    // pdf(t) per unit length (0 when not valid, or t outside [t_min, t_max)).
    float pdf(float t) const {
        if (!valid() || !(t >= m_t_min && t < m_t_max)) return 0.f;
        const float x = t - m_delta;
        return m_d / ((m_theta_b - m_theta_a) * (m_d * m_d + x * x));
    }

  private:
    float m_delta = 0.f, m_d = 0.f, m_theta_a = 0.f, m_theta_b = 0.f, m_t_min = 0.f, m_t_max = 0.f;
};

// Cycles' Principled Volume parameters (Blender 3.4; Volume Scatter is color = its colour,
// absorption_color = 1: no absorption) as coefficients, the one place this conversion is written
// (the scene format's Cycles keys and the Blender addon both use it):
//   sigma_s = density * color,
//   sigma_a = density * max(1 - color, 0) * max(1 - sqrt(absorption_color), 0),
// with color and absorption_color clamped to >= 0 first, as Cycles does (its node takes the
// square root of the absorption colour so that the control feels linear). Emission is
// emission_strength * emission_color, independent of density (Cycles).
struct MediumCoefficients {
    Rgb sigma_a{0.f}, sigma_s{0.f};
};
inline MediumCoefficients cycles_volume(double density, const Rgb& color,
                                        const Rgb& absorption_color) {
    MediumCoefficients m;
    const float d = float(density);
    for (int c = 0; c < 3; ++c) {
        const float col = std::fmax(color[c], 0.f);
        const float abs_col = std::sqrt(std::fmax(absorption_color[c], 0.f));
        m.sigma_s[c] = d * col;
        m.sigma_a[c] = d * std::fmax(1.f - col, 0.f) * std::fmax(1.f - abs_col, 0.f);
    }
    return m;
}

}  // namespace facet::render
