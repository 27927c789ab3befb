// Integrators (`direct`, `path`) and the choice of a specialised kernel from the scene analysis.
//
// Conventions:
//  - A kernel computes radiance estimates for camera samples. Radiance is linear RGB in
//    W sr^-1 m^-2; the pixel value is the box-filtered mean of its samples (film.h).
//  - Materials are evaluated in the local shading frame Frame::from_z_x(ns, dpdu), with ns (and
//    ng) flipped toward the viewer on the back of a two-sided surface (scene.h); BRDF values,
//    pdfs and samples come only from facet::Material (or, in the Lambert-only kernel, from the
//    material's own LambertReflection lobe, which is the whole Material in that case).
//  - `direct` (Cohen & Wallace §2.6.1, eq. 2.42): L = Le + sum over lights of f Li |cos| with a
//    shadow ray per light, plus perfect-mirror recursion through the delta lobe up to max_depth
//    mirror bounces. Delta lights (point, spot, directional) are evaluated exactly, so with only
//    delta lights the result is deterministic; area lights and the environment get one light
//    sample per light per camera sample. Glossy lobes receive direct light only.
//  - `path` (the rendering equation, §2.6.2): unidirectional path tracing with next-event
//    estimation (one light per vertex, chosen in proportion to power: LightDistribution,
//    light.h; the constant environment is left to BSDF sampling, which importance-samples its
//    integrand exactly up to visibility: nee_samples()), multiple importance sampling of light
//    and BSDF samples with the power heuristic (Veach eq. 9.13), delta lobes and delta lights
//    handled exactly (no MIS for them), Russian roulette from kRouletteDepth on, and at most
//    max_depth bounces (max_depth = 0: only what camera rays see).
//  - Sample dimensions (sampler.h): 0 is the film position; path vertex k uses the fixed block
//    [1 + kDimsPerVertex k, 1 + kDimsPerVertex (k + 1)): light choice (1D; read by none: the
//    light position's first coordinate chooses the light, through the light tree too, and is
//    rescaled, LightDistribution::sample), light position (2D), lobe choice (1D), BSDF direction
//    (2D), roulette (1D). Fixed blocks keep every kernel variant on the same sample values, so
//    specialised and general kernels agree. The lens sample of a thin-lens camera (camera.h) is
//    the 2D dimension kLensDimension, a reserved index far beyond any vertex block (which end
//    below 1 + kDimsPerVertex (kMaxDepth + 1) in `path`, and (1 + lights) (max_depth + 1) in
//    `direct`), drawn only when the camera has a lens: pinhole renders draw exactly the same
//    samples as before lenses existed, and the other dimensions do not move when the aperture
//    opens.
//  - Transmission (kFeatTransmission; facet/dielectric.h): at a transmissive material the frame
//    is the shape's own (z = outward shading normal, not flipped toward the viewer), light and
//    BSDF directions may lie on either side (the geometric and the shading normal must agree on
//    the side), and each ray starts off the surface on its own side. Shadow rays stop at
//    glass: light through a dielectric arrives by BSDF sampling only (caustics from small lights
//    are noisy, as in any unidirectional path tracer). Transport mode: radiance. Inside and
//    outside are the shape's back and front (its normal points outside). `direct` follows one
//    of a smooth dielectric's two delta lobes, chosen by Fresnel with the depth block's last
//    dimension (1 + number of lights); `path` with the lobe dimension. Russian roulette, NEE
//    and MIS are unchanged: delta lobes skip NEE and MIS (specular bounce), rough dielectrics
//    are non-delta lobes like any other.
//  - Media (kFeatMedia; facet/render/medium.h, scenes/FORMAT.md "Media"): volumetric path
//    tracing, one path at a time (no packets), for `path` and `direct` alike. A path carries
//    the media it is in (a small stack: the world medium below, a shape's interior medium
//    pushed when a ray crosses its boundary against the normal, removed when it leaves). On
//    each segment: the medium's emission along the segment in closed form, then free-flight
//    sampling of the distance, analytic for homogeneous media: a channel c is chosen in
//    proportion to the throughput, t ~ sigma_t,c exp(-sigma_t,c t), and the throughput is
//    weighted by the one-sample MIS (balance heuristic) pdf over the channels, sum_c P(c)
//    sigma_t,c exp(-sigma_t,c t) (pbrt-v4 §14.2.2's spectral MIS with RGB for wavelengths;
//    Cycles' channel choice by throughput). A purely absorbing medium is not sampled: its
//    transmittance is applied exactly. A scattering event is a vertex like a surface's: next-
//    event estimation with the phase function and the transmittance of the shadow ray (which
//    crosses `null` surfaces, multiplying the transmittance of each medium it passes; any
//    other surface blocks it), MIS (power heuristic) against phase-function sampling for
//    lights that rays can hit, then a new direction from the phase function. In a homogeneous
//    scattering medium (VolumeSampling::MultipleImportance, the default) the next-event
//    estimate is instead the segment's (segment_light): before its free flight, a light is
//    chosen (by the distribution's position-independent pmf: a light tree's choice at one
//    point could miss a light that lights another point of the segment) and a point c on it
//    sampled from the segment's origin; the light is then sampled from two points, the
//    free-flight distance (when the flight scatters) and an equiangular distance toward c
//    (medium.h, Equiangular), each weighted by the power heuristic of its distance density
//    against the other's (two-sample MIS; the free-flight density is the channel-MIS one),
//    with the same light numbers; where the medium is thin over the equiangular density's
//    scale (kEquiangularAloneDepth) the equiangular one alone. Without a point to aim at (a
//    distant or environment light, a failed sample, c on the ray's line) the free-flight
//    distance carries it alone. The scattering vertex then only samples the phase function,
//    and a light its direction hits is weighted against the same position-independent pmf.
//    Runs with a shadow catcher and grid media keep the vertex's own estimate. `null` surfaces
//    are crossed without a vertex (max_depth counts surface and medium vertices only). An
//    infinite ray in a world medium with sigma_t > 0 in every channel never reaches the
//    environment (transmittance 0), as in Cycles; a channel with sigma_t = 0 sees it. The
//    camera's media are found once per tile by a ray from the camera position (the
//    boundaries it leaves before entering them again). Sample dimensions: their own block
//    per segment, kMediaDimsPerSegment wide (a `null` crossing is a segment; integrator.cpp
//    lists them). Grid media
//    track against their majorants (medium.h) with a generator seeded from the segment's last
//    dimension, so a segment's tracking never shifts another's dimensions. Area lamps
//    that camera rays see are not attenuated by media.
//  - Subsurface (SceneFeatures::has_subsurface; facet/subsurface.h, docs/subsurface.md): scenes
//    with a subsurface material run the media kernel. At a surface vertex of such a material on
//    a path without a diffuse bounce, the walk is chosen with Material::Subsurface::probability
//    at wo (the lobe dimension); else its surface closures are sampled (NEE and BSDF pdfs
//    scaled by the probability of choosing them). The walk runs inside the hit's shape (rays
//    that meet other shapes pass them), then the exit vertex does NEE and samples its cosine
//    lobe; the entry direction, the first step and the exit's light sample and direction take
//    the segment's sample dimensions (stratified over the pixel's samples), the later steps the
//    segment's tracking generator. Any diffuse sample (and the walk) sets the path's diffuse
//    ancestor (Cycles' flag): later hits on subsurface materials see their fallback BSDF.
//  - Ray visibility (SceneFeatures::has_ray_visibility; scene.h RayVisibility, scenes/FORMAT.md
//    "Ray visibility"): scenes with a shape that some kind of ray does not see run the media
//    kernel, whose paths carry their current ray's kind as Cycles 3.4's path flags give it:
//    camera (kept through straight pass-throughs: `null` crossings, transparent samples), then
//    after each bounce diffuse or glossy (mirrors too) for a reflection, transmission for any
//    sample that crosses the surface, volume scatter (which also sees what diffuse rays see,
//    as in Cycles) after a medium's scattering, diffuse after a subsurface walk. A surface hit
//    on a shape without the ray's bit is crossed without a vertex, like a `null` surface (no
//    emission, no holdout, the ray keeps its kind); shadow rays pass shapes without `shadow`.
//    An emitting shape that no diffuse, glossy or transmission ray sees is no light source
//    (Cycles' object_usable_as_light): rays that see it take its emission at full weight.
//    Other emitters' light samples skip what their flags exclude (Cycles 3.4's
//    SHADER_EXCLUDE_* of a mesh light, light_reaches): purely diffuse materials without
//    `diffuse`, purely glossy ones without `glossy`, media without `volume_scatter`; mixed
//    materials keep the whole sample (Cycles drops the excluded lobes' share), transmissive
//    ones are always lit. Light Path switches (LightPathRay, scene.h): the path also carries
//    its ray's Light Path outputs, and a hit on a shape with a switch takes the first matching
//    entry's material and emission (apply_light_path) before anything reads them; shadow rays
//    read the `shadow` entry's material (a `null` one lets them through).
//  - Alpha (kFeatAlpha), as Cycles defines it: a camera path is "see-through" until its first
//    vertex that is not a straight pass-through (a delta transmission with wi = -wo: the `null`
//    model, a transparent surface; a `null` crossing in the media kernel). Its transparency T
//    gains the mean over RGB of the path's throughput where a see-through ray escapes (only
//    with RenderSettings::film_transparent, and the environment then adds nothing to the
//    colour) and, at a see-through hit, that throughput times the hit's holdout weight (1 on a
//    shape with `holdout`, else Material::holdout_weight); a full holdout ends the path before
//    its emission. The sample's coverage is 1 - T (film.h sums it beside the colour, only
//    for a transparent film: in an opaque one a holdout only blacks out, as in Cycles). Area
//    lamps seen by camera rays add colour and leave alpha alone, as Cycles' lamps do.
//  - Shadow catcher (SceneFeatures::has_shadow_catcher; Cycles 3.4's, approximate): scenes with
//    a catcher run the alpha media kernel (one path at a time, whichever integrator). A camera
//    path that meets a catcher shape while see-through (see "Alpha") splits there: the path
//    goes on as usual, the catcher an ordinary object (what it gathered before the split is
//    the "matte"; its transparency gains the throughput's mean then), and a second run of the
//    same camera sample, with the same sample values, repeats the path up to the split and
//    goes on from it seeing only catchers: its rays and shadow rays pass every other surface
//    as if absent (media stay as they were), and an emitting shape lights it only if it is a
//    catcher (lamps and the environment always do). Each sample adds the matte, the catcher-only
//    radiance, the environment its see-through path sees (throughput times the environment's
//    radiance where it escapes, or straight behind the catcher at the split) and its count to the
//    film's catcher sums (film.h), which resolve them as Cycles' Combined pass: over a transparent
//    film the catcher is transparent except for the light the other objects took from it (alpha = 1
//    - the ratio of the full to the catcher-only radiance), in an opaque one it shows the
//    environment darkened by that.
//  - Camera samples: with spp = 1 the ray goes through the pixel centre (POV-Ray without
//    anti-aliasing does the same); with spp > 1 film positions are stratified over the pixel.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "facet/render/film.h"
#include "facet/render/scene.h"

namespace facet::render {

inline constexpr int kDimsPerVertex = 7;
// The thin lens's 2D sample (see conventions).
inline constexpr std::uint32_t kLensDimension = 0xFFFFFFF0u;
// The shutter time's 1D sample (kFeatMotion), reserved as the lens's is: scenes that do not
// move draw exactly the samples they drew before motion blur existed.
inline constexpr std::uint32_t kTimeDimension = 0xFFFFFFF2u;
// Russian roulette starts after this many bounces; earlier vertices carry most of the image.
// A path then survives each bounce with probability sqrt(max beta) (survivors reweighted by its
// inverse), as Cycles does, instead of max beta: the roulette's kill-or-double decisions are
// noise that stratification does not remove, so at high sample counts they dominate. The rules
// compared (start depth, sqrt or not, no roulette) are in docs/performance.md, "Russian roulette".
inline constexpr int kRouletteDepth = 4;

// Compile-time features of a kernel. The general kernel has every feature except LambertOnly.
enum KernelFeature : std::uint32_t {
    kFeatLambertOnly = 1u << 0,   // every material is a single Lambertian lobe: call it directly
    kFeatSpecular = 1u << 1,      // some material has a delta (mirror) lobe
    kFeatMis = 1u << 2,           // some light is non-delta: MIS of light and BSDF samples
    kFeatEmission = 1u << 3,      // rays can hit emitters / escape to an environment
    kFeatIndirect = 1u << 4,      // paths longer than one bounce (path) / mirror recursion
    kFeatAreaSampling = 1u << 5,  // direct: stochastic light samples (area lights, environment)
    // Some material transmits (dielectrics): two-sided shading frames, rays spawned on the side
    // they leave to. Only the general kernel of each integrator is instantiated with it.
    kFeatTransmission = 1u << 6,
    // Some surface's material depends on the hit (SceneFeatures::has_textured): hits with
    // SurfaceHit::textured >= 0 build their material with Scene::bsdf_at. Only kernels with
    // this bit test it, so an untextured scene's kernel has no such branch (the general kernel
    // of each integrator, with or without Transmission, is instantiated with it).
    kFeatTextured = 1u << 7,
    // The scene has media (SceneFeatures::has_media): the volumetric path kernel (see the
    // conventions' "Media"), instantiated once, with every other feature of the general path
    // kernel. Scenes without media never run it, and the other kernels have no media code.
    kFeatMedia = 1u << 8,
    // Motion blur is on and something moves (SceneFeatures::has_motion): each camera sample
    // draws a shutter time (kTimeDimension, ShutterCurve), its camera ray comes from the camera
    // at that time, and every ray of its path carries it (RayPacket::time, the
    // timed single-ray queries). Instantiated for the
    // general kernel of each integrator (with transmission and textures) and the media kernel;
    // static scenes never run it, and the other kernels draw no time.
    kFeatMotion = 1u << 9,
    // The image has alpha (SceneFeatures::needs_alpha: film transparency or a holdout; see the
    // conventions' "Alpha"): each camera sample also yields its coverage. Instantiated for the
    // general kernel of each integrator (with transmission and textures, with or without
    // motion) and the media kernel; other scenes never run it and keep their images bit for bit.
    kFeatAlpha = 1u << 10
};

enum class IntegratorKind { Direct, Path };

struct KernelChoice {
    IntegratorKind integrator = IntegratorKind::Path;
    std::uint32_t features = 0;                // KernelFeature bits of the kernel that will run
    int max_depth = 0;                         // effective (0 when nothing can reflect)
    bool general = false;                      // the general kernel was forced (--kernel general)
    std::string name;                          // e.g. "path<lambert,no-mis,emission,indirect>"
    std::vector<std::string> chosen, skipped;  // one line each, for --explain
};

// Parses "direct" | "path"; throws std::invalid_argument("unknown integrator 'x' (did you mean
// 'path'?)").
IntegratorKind parse_integrator(const std::string& name);
const char* integrator_name(IntegratorKind kind);

// Picks the kernel for a scene. `force_general` selects the general kernel of the integrator
// (same estimator, every branch present), for benchmarks and the equality test.
KernelChoice choose_kernel(const SceneFeatures& features, IntegratorKind integrator, int max_depth,
                           bool force_general);

// Counters a kernel accumulates (per tile, summed by the render loop).
struct KernelCounters {
    std::uint64_t camera_rays = 0, rays = 0, shadow_rays = 0;
    std::uint64_t nonfinite = 0;  // samples not accepted by the film (NaN/inf/huge; dropped)
    KernelCounters& operator+=(const KernelCounters& o) {
        camera_rays += o.camera_rays;
        rays += o.rays;
        shadow_rays += o.shadow_rays;
        nonfinite += o.nonfinite;
        return *this;
    }
};

// Renders samples [first_sample, end_sample) of every pixel in the tile [x0, x1) x [y0, y1)
// and adds their fixed-point radiance sums (film.h) into `sums`, a film over the region whose
// top-left pixel is (film_x0, film_y0), row-major with film_width pixels per row (the tile lies
// inside it). Rows are traced in packets aligned to multiples of 8 pixels of the image (render.h).
// Never throws, allocates or logs.
// How the media kernel places a homogeneous medium's next-event estimates (the conventions'
// "Media"): at free-flight and equiangular distances combined by MIS (the default), or at the
// free-flight distance alone (its scattering vertex; comparisons and tests). Both converge to
// the same image.
enum class VolumeSampling : std::uint8_t { MultipleImportance, Distance };

struct TileJob {
    int x0, y0, x1, y1;
    int film_x0, film_y0, film_width;
    int first_sample, end_sample;
    int spp_total;  // the full spp of the render (spp = 1 means pixel-centre rays)
    std::uint64_t seed;
    int max_depth;
    // Next-event estimation's light choice (path): the scene's power distribution, or another
    // over the same lights (RenderOptions::light_selection). Never null.
    const LightDistribution* light_distribution;
    // Independent uniform samples instead of the Sobol sequence (RenderOptions).
    bool independent_samples = false;
    VolumeSampling volume_sampling = VolumeSampling::MultipleImportance;  // RenderOptions
    // The film's coverage sums (film.h, same layout as `sums`), written by the alpha kernels
    // only (kFeatAlpha) and only with a transparent film; null otherwise.
    FixedSum* alpha = nullptr;
    // The film's shadow-catcher sums (film.h, CatcherSums; same pixel layout, kCatcherSums a
    // pixel), written by the alpha media kernel in a scene with a catcher; null otherwise.
    FixedSum* catcher = nullptr;
    // The Depth pass's sums (RenderOptions::depth_pass): per film pixel (the layout of `sums`)
    // the fixed-point sum of the camera samples' first-hit view-axis depths and their count,
    // written by kernels without motion blur; null otherwise.
    FixedSum* depth = nullptr;
    std::uint32_t* depth_hits = nullptr;
};
using TileKernel = void (*)(const Scene& scene, const TileJob& job, FixedRgb* sums,
                            KernelCounters& counters);

// The kernel function for a choice (never null).
TileKernel kernel_function(const KernelChoice& choice);

// The lens-centre camera rays of a packet's lanes k < n (n <= RayPacket::kSize), at film
// positions (x0 + k + film_x[k], y + film_y[k]) (arrays of RayPacket::kSize): bit for bit the
// rays cam.generate_ray gives, computed several lanes at once for a perspective camera. The
// lanes from n on may be overwritten.
void camera_packet(const Camera& cam, int x0, int y, const float* film_x, const float* film_y,
                   std::size_t n, RayPacket& rays);

}  // namespace facet::render
