// Random-walk subsurface scattering as Cycles 3.4 defines it (intern/cycles/kernel/closure/
// bssrdf.h, kernel/integrator/subsurface.h and subsurface_random_walk.h): Blender's Subsurface
// Scattering node and Principled BSDF's Subsurface with the methods Random Walk and Random Walk
// (Fixed Radius). docs/subsurface.md derives the parts and lists what differs from Cycles.
//
// Conventions:
//  - The walk is volumetric path tracing inside a closed object with a homogeneous medium whose
//    coefficients come from the material's surface colour ("albedo" A, per channel) and its
//    scattering radius (mean free path, scene units, per channel); the phase function is
//    Henyey-Greenstein (facet/henyey_greenstein.h) with the anisotropy g in [0, 0.9].
//  - Radius setup (bssrdf_setup_radius): Random Walk (Fixed Radius) scales the radius by
//    1 / (4 pi); Random Walk rescales it by sqrt(3 (1 - a')) where a' inverts the dipole's
//    total diffuse reflectance Rd(a') = a'/2 (1 + exp(-4/3 A_f s)) exp(-s), s = sqrt(3 (1 - a')),
//    A_f = (1 + F_dr) / (1 - F_dr) with Jensen's F_dr(eta) fit, at Rd = A (12 bisection steps,
//    as Cycles).
//  - Coefficients (subsurface_random_walk_remap, Chiang, Kutz & Burley 2016 with Wrenninge et
//    al.'s anisotropic fit): the single-scattering albedo alpha(A, g) is a fitted function
//    chosen so that a semi-infinite medium of albedo alpha reflects about A in total;
//    sigma_t = 1 / (radius (1 - g)). The walk's weight starts at 1 / A (the closure weight
//    already holds A) and channels with alpha < 0.2 are walked at alpha = 0.2 with their
//    weight scaled by alpha / 0.2 (Cycles' guard against infinite Dwivedi phase functions).
//  - The walk (subsurface_random_walk): the path enters along a cosine-weighted direction about
//    -N (N the shading normal on the viewer's side; directions below the geometric normal
//    end the path). Each step picks a channel in proportion to |beta alpha| and samples a
//    distance with that channel's sigma_t (one-sample MIS, balance heuristic, over channels);
//    from the second step on, the direction is either the phase function's or, with
//    probability 1 - max(0.5, |g|^(1/8)), Dwivedi's zero-variance-guided one about N (forward,
//    or backward toward an opposite interface found by the first step's long ray, chosen by
//    the logistic weight of Křivánek & d'Eon 2014 / Meng et al. 2016 / d'Eon & Křivánek 2020),
//    with the distance sampled at the stretched sigma_t (1 -+ cos/v); the pdf is the MIS of
//    all of them. After 9 steps the walk switches to the similarity-reduced isotropic medium
//    (sigma_s* = sigma_s (1 - g), guided fraction 0.75). It ends when a segment reaches the
//    object's surface (the exit) or after kMaxBounces steps (no exit: the path ends) or when
//    every channel's weight is below 1e-8.
//  - Random numbers: the entry direction and the first step (channel, distance) take the
//    caller's SubsurfaceWalkStart (a renderer's stratified sample dimensions: they decide most
//    of where a short walk leaves); the later steps draw from a caller's uniform generator
//    `u()` in [0, 1) (their number is unbounded: a generator seeded per walk, deterministic).
//  - Directions are world vectors; distances are in scene units.
#pragma once

#include <cmath>
#include <optional>

#include "facet/frame.h"
#include "facet/henyey_greenstein.h"
#include "facet/sampling.h"
#include "facet/types.h"

namespace facet {

enum class SubsurfaceMethod : std::uint8_t { RandomWalk, RandomWalkFixedRadius };

// Cycles' constants.
struct SubsurfaceLimits {
    static constexpr int kMaxBounces = 256;             // BSSRDF_MAX_BOUNCES
    static constexpr float kMinRadius = 1e-8f;          // BSSRDF_MIN_RADIUS
    static constexpr float kMinAlpha = 0.2f;            // subsurface_random_walk_coefficients
    static constexpr float kThroughputEpsilon = 1e-8f;  // VOLUME_THROUGHPUT_EPSILON
    static constexpr int kSimilarityLevel = 9;          // SUBSURFACE_RANDOM_WALK_SIMILARITY_LEVEL
    // Cycles clamps the IOR to [1.01, 3.8] and the anisotropy to [0, 0.9]: the models' ranges.
};

// The fitted single-scattering albedo alpha(A, g) of Cycles' subsurface_random_walk_remap,
// clamped to [0, 0.999999] (float, as Cycles evaluates it).
float subsurface_single_scattering_albedo(float surface_albedo, float g);

// Rd(a') of the dipole and its inverse by bisection (bssrdf_dipole_compute_Rd/_alpha_prime).
float subsurface_dipole_rd(float alpha_prime, float four_thirds_a);
float subsurface_dipole_alpha_prime(float rd, float four_thirds_a);

// The radius the walk uses for the material's radius, albedo and IOR (bssrdf_setup_radius).
Rgb subsurface_effective_radius(const Rgb& radius, const Rgb& albedo, float ior,
                                SubsurfaceMethod method);

// What a walk needs, fixed per material: extinction, single-scattering albedo and the factor
// the path's weight takes on entering (1 / A, with the minimum-alpha adjustment).
struct SubsurfaceWalk {
    Rgb sigma_t{1.f}, alpha{0.f}, entry_weight{0.f};
    float g = 0.f;
    // Dwivedi's diffusion length v for max(alpha) and log((v + 1) / (v - 1)); v == 1: no walk.
    float diffusion_length = 1.f, phase_log = 0.f;
    // coefficients from the surface albedo A, effective radius and anisotropy (conventions).
    static SubsurfaceWalk make(const Rgb& albedo, const Rgb& radius, float g);
    // The walk of a medium given by its coefficients (alpha in (0, 1)); make() ends here.
    static SubsurfaceWalk from_coefficients(const Rgb& sigma_t, const Rgb& alpha,
                                            const Rgb& entry_weight, float g);
};

// The subsurface lobe of a material (Material::subsurface()): the closure's weight, and what the
// walk and the exit need.
struct SubsurfaceLobe {
    Rgb weight{0.f};  // the closure weight (Cycles' bssrdf->weight: colour times mix weights)
    SubsurfaceWalk walk;
    bool fresnel = false;  // Principled: the exit lobe is (1 - FL/2) / pi (Cycles' LAMBERT_EXIT)
};

// The exit lobe at the walk's exit point, local frame z = the outward shading normal: f for wi
// above the surface (Lambert 1/pi, or with Fresnel (1 - (1 - cos_i)^5 / 2) / pi), cosine
// sampled. Radiance leaves along wi's reflection side only.
inline float subsurface_exit_f(bool fresnel, float cos_i) {
    if (!(cos_i > 0.f)) return 0.f;
    if (!fresnel) return kInvPi;
    const float m = 1.f - cos_i, m2 = m * m;
    return (1.f - 0.5f * m2 * m2 * m) * kInvPi;
}

// The result of a walk: where the path leaves the object.
struct SubsurfaceExit {
    Vec3 p{0.f};    // the exit point (on the surface; the caller's hit record has its normals)
    Vec3 d{0.f};    // the last segment's direction (toward the exit point, from inside)
    int steps = 0;  // segments walked
};

// The random numbers a walk starts with, in [0, 1)^2 each: the entry direction's, and the first
// step's channel choice (x) and distance (y). A renderer takes them from its stratified sample
// dimensions (one pair each): the entry and the first step decide most of where a short walk
// leaves.
struct SubsurfaceWalkStart {
    Vec2 entry{0.f}, first{0.f};
};

namespace subsurface_detail {

inline float dwivedi_eval(float v, float phase_log, float cos_theta) {
    return 1.f / ((v - cos_theta) * phase_log);  // Meng et al. 2016, eq. 9 (per unit cos)
}
inline float dwivedi_sample(float v, float phase_log, float u) {
    return v - (v + 1.f) * std::exp(-u * phase_log);  // eq. 10
}
inline Vec3 direction_about(const Vec3& axis, float cos_t, float u) {
    const float sin_t = std::sqrt(std::fmax(0.f, 1.f - cos_t * cos_t));
    const float phi = 2.f * kPi * u;
    return Frame::from_z(axis).from_local(
        Vec3(sin_t * std::cos(phi), sin_t * std::sin(phi), cos_t));
}
// exp(-sigma_t t) per channel, and the segment's distance density (sigma_t T) or, for a
// segment that reached the surface, its probability (T).
inline Rgb transmittance(const Rgb& sigma_t, float t) {
    return {std::exp(-sigma_t.r * t), std::exp(-sigma_t.g * t), std::exp(-sigma_t.b * t)};
}

}  // namespace subsurface_detail

// One random walk from the entry point p (on the surface) into the object; n is the shading
// normal and ng the geometric normal, both on the viewer's side (outside). beta is the path's
// weight (the closure's weight over its selection probability already in it): on an exit it
// holds the walk's estimate, otherwise it is unspecified.
//   intersect(o, d, t_max, first) -> float: the distance (< t_max) to the nearest surface of
//     the same object along o + t d (d unit), or +inf; `first` is true for the segment that
//     leaves the entry point (the caller keeps it off the entry triangle). It keeps the hit
//     of the last call that found one: the exit's.
//   u() -> float in [0, 1).
//   start: the numbers of the entry direction and of the first step's channel and distance
//     (the caller's stratified sample dimensions); the overload without it draws them from u()
//     (entry, then first step: the order the walk uses them in).
template <class Intersect, class Uniform>
std::optional<SubsurfaceExit> subsurface_random_walk(const SubsurfaceWalk& w, const Vec3& p,
                                                     const Vec3& n, const Vec3& ng, Rgb& beta,
                                                     const SubsurfaceWalkStart& start, Uniform&& u,
                                                     Intersect&& intersect) {
    using namespace subsurface_detail;
    using L = SubsurfaceLimits;
    // Into the object: cosine-weighted about -n (the diffuse transmission of the entry).
    const Vec3 local = sample_cosine_hemisphere(start.entry);
    Vec3 d = Frame::from_z(-n).from_local(local);
    if (!(glm::dot(-ng, d) > 0.f)) return std::nullopt;
    if (!(w.diffusion_length > 1.f)) return std::nullopt;
    const float v = w.diffusion_length, phase_log = w.phase_log;
    beta *= w.entry_weight;

    const Rgb sigma_s_org = w.sigma_t * w.alpha;
    const Rgb sigma_s_star = sigma_s_org * (1.f - w.g);
    const Rgb sigma_t_star = w.sigma_t - sigma_s_org + sigma_s_star;
    const float guided_org = 1.f - std::fmax(0.5f, std::pow(std::fabs(w.g), 0.125f));

    Vec3 x = p;
    bool have_opposite = false;
    float opposite_distance = 0.f;
    for (int bounce = 0; bounce < L::kMaxBounces; ++bounce) {
        const bool similar = bounce > L::kSimilarityLevel;
        const float g = similar ? 0.f : w.g;
        const float guided_fraction = similar ? 0.75f : guided_org;
        const Rgb& sigma_t = similar ? sigma_t_star : w.sigma_t;
        const Rgb& sigma_s = similar ? sigma_s_star : sigma_s_org;

        // The channel, in proportion to |beta alpha| (Chiang et al. 2016).
        Rgb weights = beta * w.alpha;
        for (int c = 0; c < 3; ++c) weights[c] = std::fabs(weights[c]);
        const float sum = weights.r + weights.g + weights.b;
        const Rgb channel_pdf = sum > 0.f ? weights / sum : Rgb(1.f / 3.f);
        const float rc = bounce == 0 ? start.first.x : u();
        const int ch = rc < channel_pdf.r ? 0 : rc < channel_pdf.r + channel_pdf.g ? 1 : 2;
        float sample_sigma_t = sigma_t[ch];
        const float rt = bounce == 0 ? start.first.y : u();

        float backward_fraction = 0.f, forward_pdf_factor = 0.f, backward_pdf_factor = 0.f;
        float forward_stretch = 1.f, backward_stretch = 1.f;
        if (bounce > 0) {
            const bool guided = u() < guided_fraction;
            bool backward = false;
            if (have_opposite) {
                // Logistic choice toward the opposite interface (d'Eon & Křivánek 2020).
                const float depth = glm::clamp(glm::dot(x - p, -n), 0.f, opposite_distance);
                backward_fraction = 1.f / (1.f + std::exp((opposite_distance - 2.f * depth) / v));
                backward = u() < backward_fraction;
            }
            const float su = u(), sv = u();
            float cos_theta, hg_pdf;
            if (guided) {
                cos_theta = dwivedi_sample(v, phase_log, su);
                if (backward) cos_theta = -cos_theta;
                const Vec3 nd = direction_about(n, cos_theta, sv);
                hg_pdf = HenyeyGreenstein::p_of_cos(glm::dot(d, nd), g);
                d = nd;
            } else {
                const PhaseSample ps = *HenyeyGreenstein(g).sample(-d, Vec2(su, sv));
                hg_pdf = ps.pdf;
                d = ps.wi;
                cos_theta = glm::dot(d, n);
            }
            // Guided pdfs relative to the phase function's (which cancels with its value).
            forward_pdf_factor = kInv2Pi * dwivedi_eval(v, phase_log, cos_theta) / hg_pdf;
            backward_pdf_factor = kInv2Pi * dwivedi_eval(v, phase_log, -cos_theta) / hg_pdf;
            forward_stretch = 1.f - cos_theta / v;
            backward_stretch = 1.f + cos_theta / v;
            if (guided) sample_sigma_t *= backward ? backward_stretch : forward_stretch;
        }

        float t = -std::log(1.f - rt) / sample_sigma_t;
        bool hit;
        if (bounce == 0) {
            // A longer ray on the first step finds a nearby opposite side (10 mean free paths).
            const float s_min = std::fmin(sigma_t.r, std::fmin(sigma_t.g, sigma_t.b));
            const float t_hit = intersect(x, d, std::fmax(t, 10.f / s_min), true);
            if (t_hit < kInfinity) {
                have_opposite = true;
                opposite_distance = glm::dot(x + d * t_hit - p, -n);
            }
            hit = t_hit < t;
            if (hit) t = t_hit;
        } else {
            const float t_hit = intersect(x, d, t, false);
            hit = t_hit < t;
            if (hit) t = t_hit;
        }
        x += d * t;

        // The pdf of the segment under each strategy, per channel, then MIS over all.
        auto seg_pdf = [&](const Rgb& st) {
            const Rgb tr = transmittance(st, t);
            return hit ? tr : st * tr;
        };
        const Rgb tr = transmittance(sigma_t, t);
        Rgb pdf = hit ? tr : sigma_t * tr;
        if (bounce > 0) {
            Rgb guided_pdf = seg_pdf(sigma_t * forward_stretch);
            if (have_opposite) {
                const Rgb back = seg_pdf(sigma_t * backward_stretch);
                guided_pdf = guided_pdf * forward_pdf_factor * (1.f - backward_fraction) +
                             back * backward_pdf_factor * backward_fraction;
            } else {
                guided_pdf *= forward_pdf_factor;
            }
            pdf = pdf * (1.f - guided_fraction) + guided_pdf * guided_fraction;
        }
        const float denom = glm::dot(channel_pdf, pdf);
        beta *= (hit ? tr : sigma_s * tr) / denom;
        if (hit) return SubsurfaceExit{x, d, bounce + 1};
        if (beta.r < L::kThroughputEpsilon && beta.g < L::kThroughputEpsilon &&
            beta.b < L::kThroughputEpsilon)
            return std::nullopt;
    }
    return std::nullopt;
}

template <class Intersect, class Uniform>
std::optional<SubsurfaceExit> subsurface_random_walk(const SubsurfaceWalk& w, const Vec3& p,
                                                     const Vec3& n, const Vec3& ng, Rgb& beta,
                                                     Uniform&& u, Intersect&& intersect) {
    SubsurfaceWalkStart start;
    start.entry.x = u();
    start.entry.y = u();
    start.first.x = u();
    start.first.y = u();
    return subsurface_random_walk(w, p, n, ng, beta, start, u, intersect);
}

}  // namespace facet
