// Arbitrary output variables (AOVs): per-pixel data about what camera rays see first, for a
// compositor (Blender's render passes Albedo, Normal, Depth and Emission).
//
// Conventions:
//  - A separate pass over the image, after or instead of the beauty render: nothing here runs
//    unless render_aovs() is called, so a render without AOVs costs exactly what it did.
//  - Each pixel averages `spp` camera samples at the same film positions the renderer's sample
//    indices would use for dimension 0 (stratified, Owen-scrambled Sobol: sampler.h; pixel
//    centres for spp = 1), with the seed's pixel randomisation: a pure function of (pixel,
//    sample index, seed), so the result is deterministic and independent of the thread count.
//    Thin-lens cameras take their lens sample as the integrator does (kLensDimension).
//  - At the first surface a camera ray hits (after opacity and ray visibility, with its Light
//    Path switch's camera material and emission: as the renderer sees it), with the
//    shading normal after normal and bump maps and the valid-reflection bend (scene.h),
//    turned toward the viewer (Cycles' backfacing flip):
//      albedo   = rho(wo) = integral of f(wo, wi) |cos theta_i| over the sphere: the fraction of
//                 light from the viewer's direction the material sends back (reflection and
//                 transmission), estimated with one BSDF sample per camera sample
//                 (f |cos| / pdf; exact for Lambert, whose sampling is proportional to f cos);
//      normal   = the unit shading normal in world space;
//      depth    = distance from the camera along its view axis (forward . (p - position)),
//                 as Cycles 3.4's Z pass for perspective and orthographic cameras;
//      emission = the radiance the surface emits toward the camera (emitted_radiance).
//    Samples that miss every surface add 0 to albedo, normal and emission (the background is
//    not an emitter here: Blender's Environment pass, not its Emit pass); depth averages the
//    samples that hit and is kMissDepth (1e10, Cycles' value) where none does.
//  - Sums are the film's fixed point (film.h): exact, so a pixel's value does not depend on the
//    order of its samples.
//  - Variances (AovOptions::variances, for the denoiser: denoise.h): per pixel and channel the
//    variance of the albedo's, normal's and depth's mean, s^2 / n with s^2 the unbiased sample
//    variance of the pixel's n samples (for depth: of the n samples that hit), from the sums of
//    the samples and of their squares (squared in double, exact for a float). They are
//    non-zero where the first hit varies within a pixel: edges, depth of field, motion blur,
//    glossy or rough first hits (the albedo's one BSDF sample). 0 for n < 2, and where the
//    spread is at most 2^-44 of the mean square (rounding: a float's is ~2^-48), so a constant
//    feature has variance exactly 0. Depths are clamped to 2^20 scene units before they are
//    squared (fixed-point range), so beyond that their variance is not estimated (0 or low;
//    the denoiser's inverse depth is below 1e-6 there). The squares are summed only when
//    asked: the pass without variances does no extra work per sample.
//  - Images are RGB (depth in all three channels), width x height of the camera, top row first.
#pragma once

#include <cstdint>
#include <optional>

#include "facet/render/film.h"
#include "facet/render/image.h"
#include "facet/render/scene.h"

namespace facet::render {

inline constexpr float kMissDepth = 1e10f;

// The depth of a point p seen by the camera (conventions: along its view axis), and a pixel's
// Depth value from the fixed-point sum of its hits' depths and their count (the mean;
// kMissDepth where none hit). Shared by render_aovs and RenderSession::depth.
inline float view_axis_depth(const Camera& cam, const Vec3& p) {
    return glm::dot(p - cam.position, cam.forward);
}
inline float resolved_depth(FixedSum sum, std::uint32_t hits) {
    return hits ? float(from_fixed(sum) / double(hits)) : kMissDepth;
}

enum AovBits : std::uint32_t {
    kAovAlbedo = 1u << 0,
    kAovNormal = 1u << 1,
    kAovDepth = 1u << 2,
    kAovEmission = 1u << 3,
};

struct AovOptions {
    std::uint32_t which = 0;  // AovBits
    int spp = 16;             // >= 1
    std::uint64_t seed = 0;
    int threads = 0;  // 0 = every hardware thread
    // Also the variances of the albedo, normal and depth requested (conventions).
    bool variances = false;
    // Only these pixels (inside the image): the images are then of the region's size, and
    // equal that part of the whole image's, bit for bit (a pixel's value depends on its own
    // samples only). Unset: the whole image.
    std::optional<Region> region;
};

struct Aovs {
    Image albedo, normal, depth, emission;  // empty (0 x 0) unless requested
    // With AovOptions::variances: the variance of each requested feature's mean per channel
    // (depth's in all three), else empty.
    Image albedo_variance, normal_variance, depth_variance;
};

// Throws std::invalid_argument for spp < 1 or a region that is empty or not inside the image.
Aovs render_aovs(const Scene& scene, const AovOptions& options);

}  // namespace facet::render
