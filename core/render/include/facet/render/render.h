// The render loop: tiles over TBB, a fixed sample count or a time budget, progress reporting.
//
// Conventions:
//  - Options left at their "unset" value take the scene's render settings (scene.h).
//  - Determinism: every pixel sample is a pure function of (pixel, sample index, seed)
//    (sampler.h) and each pixel is accumulated by one tile in sample order, so for a given spp
//    the image is bit-identical whatever the thread count. (The tile size decides which pixels
//    share an Embree packet, groups of 8 along a tile row; Embree's packet and single-ray
//    kernels can disagree in the last bits on rays that graze an edge.) With a time budget the
//    image is rendered in passes (1, 1, 2, 4, ... samples per pixel, at most kMaxPassSpp per
//    pass, cut to what the remaining budget affords at the mean cost so far); the image is the
//    mean of the completed passes, and equals the fixed-spp image of the same total only up to
//    float summation order across passes.
//  - render() validates its options and throws std::invalid_argument naming the option
//    ("--spp: must be >= 1"); after that it never throws, and it never allocates or logs per
//    sample.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "facet/render/image.h"
#include "facet/render/integrator.h"
#include "facet/render/progress.h"
#include "facet/render/scene.h"

namespace facet::render {

inline constexpr int kDefaultTileSize = 16;
inline constexpr int kMaxPassSpp = 16;

struct RenderOptions {
    std::string integrator;               // "" = scene setting; "direct" | "path"
    int spp = 0;                          // 0 = scene setting
    std::optional<double> time_budget_s;  // unset = scene setting; 0 = no budget
    int max_depth = -1;                   // < 0 = scene setting
    std::optional<std::uint64_t> seed;    // unset = scene setting
    int threads = 0;                      // 0 = every hardware thread
    bool force_general_kernel = false;    // --kernel general
    // Path: choose NEE lights uniformly instead of in proportion to power (comparisons, tests).
    bool uniform_light_selection = false;  // --light-selection uniform
    // Independent uniform samples instead of Owen-scrambled Sobol (the peer of the time-to-error
    // benchmark; --sampler independent). Images converge to the same value, more slowly.
    bool independent_samples = false;
    Progress::Mode progress = Progress::Mode::Silent;
    int tile_size = kDefaultTileSize;
};

struct RenderStats {
    KernelChoice kernel;
    double seconds = 0;  // wall time of the sample loop (excludes scene loading)
    int spp = 0;         // samples per pixel actually taken
    int passes = 0;
    int threads = 0;
    std::uint64_t paths = 0;        // camera samples
    std::uint64_t rays = 0;         // closest-hit rays (camera + continuation)
    std::uint64_t shadow_rays = 0;  // occlusion rays
    std::uint64_t nonfinite = 0;    // samples dropped because their estimate was NaN/inf
};

// Resolved settings (options merged with the scene's); throws std::invalid_argument.
struct ResolvedSettings {
    IntegratorKind integrator;
    int spp, max_depth, threads, tile_size;
    double time_budget_s;
    std::uint64_t seed;
};
ResolvedSettings resolve_settings(const Scene& scene, const RenderOptions& options);

// Renders the scene's camera view. Throws std::invalid_argument for bad options only.
Image render(const Scene& scene, const RenderOptions& options, RenderStats* stats = nullptr);

}  // namespace facet::render
