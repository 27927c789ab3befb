// The BxDF interface shared by every reflection model of the core.
//
// Conventions (pbrt-v4's, summarised in docs/architecture.md, "Conventions (every BxDF)"; they
// differ from Mitsuba, whose eval includes the cosine and names the directions the other way
// round):
//  - All directions are in the local shading frame (facet/frame.h): z = shading normal, `wo`
//    toward the viewer, `wi` toward the light, both unit and pointing away from the surface.
//  - `f(wo, wi)` is the BRDF value f_r (Cohen & Wallace eq. 2.22), in 1/sr, *without* the
//    cosine factor. It is 0 when wo and wi are not both above the surface (reflection only),
//    except for models flagged Transmission (facet/dielectric.h states their conventions:
//    wo on either side, z not flipped toward the viewer).
//  - `pdf(wo, wi)` is the density of `sample_f` per unit solid angle of wi.
//  - `sample_f(wo, uc, u)` draws wi. `uc` in [0,1) selects a lobe, `u` in [0,1)^2 drives the
//    lobe's warp. Random numbers are arguments: models hold no RNG and are deterministic.
//    It returns std::nullopt when no sample can be made (wo below the surface, a sampled
//    direction below the surface, zero albedo); never a NaN or a zero-pdf sample.
//  - Delta lobes (the mirror) are true Dirac deltas: `f` and `pdf` return 0 for them; their
//    `sample_f` returns the delta direction with pdf = 1 and f = F / |cos theta_i| so that
//    f * |cos| / pdf is the reflected fraction, and flags the sample `Specular`.
//  - For a mixture of a delta lobe and non-delta lobes, a Specular sample carries pdf equal to
//    the probability of choosing the delta lobe (a discrete probability, not a density).
#pragma once

#include <optional>

#include "facet/frame.h"
#include "facet/types.h"

namespace facet {

enum class BxDFFlags : std::uint8_t {
    None = 0,
    Diffuse = 1 << 0,   // Lambertian: constant f
    Glossy = 1 << 1,    // microfacet lobe: smooth, non-delta, directional
    Specular = 1 << 2,  // delta lobe: f = pdf = 0 except via sample_f
    // The model (or a sample) transmits: wi may lie on the other side of the surface than wo
    // (dielectrics, facet/dielectric.h). Without it, f = 0 across the surface.
    Transmission = 1 << 3,
};

constexpr BxDFFlags operator|(BxDFFlags a, BxDFFlags b) {
    return BxDFFlags(std::uint8_t(a) | std::uint8_t(b));
}
constexpr BxDFFlags operator&(BxDFFlags a, BxDFFlags b) {
    return BxDFFlags(std::uint8_t(a) & std::uint8_t(b));
}
constexpr bool any(BxDFFlags f) {
    return std::uint8_t(f) != 0;
}
constexpr bool is_specular(BxDFFlags f) {
    return any(f & BxDFFlags::Specular);
}
constexpr bool is_transmissive(BxDFFlags f) {
    return any(f & BxDFFlags::Transmission);
}
constexpr bool is_non_specular(BxDFFlags f) {
    return any(f & (BxDFFlags::Diffuse | BxDFFlags::Glossy));
}

struct BSDFSample {
    Rgb f{0.f};       // BRDF value for (wo, wi), without cosine (see header comment for deltas)
    Vec3 wi{0.f};     // sampled direction, local frame, pointing away from the surface
    float pdf = 0.f;  // per unit solid angle; for a Specular sample the discrete probability
    BxDFFlags flags = BxDFFlags::None;  // the lobe that produced the sample

    bool is_specular() const { return facet::is_specular(flags); }
};

// f (without cosine) and pdf (per solid angle) of one (wo, wi) pair, for callers that need both
// (MIS weights, one-sample MIS in sample_f): one evaluation shares the half vector, D and Lambda.
struct BSDFEval {
    Rgb f{0.f};
    float pdf = 0.f;
};

}  // namespace facet
