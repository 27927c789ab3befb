// Rendering: RenderSession (progressive passes that can be watched, cancelled, continued and
// split by region or sample range) and render(), one session run to the end.
//
// Conventions:
//  - Options left at their "unset" value take the scene's render settings (scene.h).
//  - Determinism: every pixel sample is a pure function of (pixel, sample index, seed)
//    (sampler.h), and the film's fixed-point sums (film.h) make a pixel's value independent of
//    the order its samples are added in. Tiles lie on a fixed grid of the full image and a tile
//    traces its rows in Embree packets of 8 pixels aligned to multiples of 8 in x, whatever the
//    region (pixels of a packet outside the region are traced and discarded), so every ray is
//    traced in the same packet in every split. Hence for given options the image is bit-identical
//    whatever the thread count, tile order, pass sizes, cancellations and continuations, and
//    regions or sample ranges rendered separately merge into it bit for bit (film.h).
//  - With spp = 1 camera rays go through pixel centres (integrator.h); such a session cannot
//    be continued to more samples (set spp >= 2 to render progressively).
//  - Passes: a pass takes every tile of the region from the samples it has to the pass's end
//    sample. Without a callback and without a time budget the whole range is one pass. With a
//    callback, passes are sized to take about `pass_seconds` each at the cost measured so far
//    (1 sample first). With a time budget, passes are 1, 1, 2, 4, ... samples (at most
//    kMaxPassSpp), cut to what the remaining budget affords at the mean cost so far.
//  - cancel() may be called from any thread (or the callback may return false): no tile starts
//    after it, tiles in flight finish (a tile-pass takes well under a millisecond at one sample),
//    and render() returns false. The film keeps every completed tile-pass: the image is then
//    valid (each pixel the mean of the samples it has), and a later render() continues from
//    exactly there.
//  - Adaptive sampling (RenderOptions::adaptive_threshold > 0): a tile stops taking samples
//    once it has converged: with Cycles 3.4's per-pixel error e (film/adaptive_sampling.h:
//    |I - A| summed over RGB, over sqrt(R + G + B) below 1 and R + G + B above), the root mean
//    square of e over the tile is below the threshold and no pixel's e is above 4 times it
//    (each e is one draw of a noisy difference: requiring every one of 256 below the threshold
//    took 2-9 times the samples Cycles' per-pixel test needs). The decisions are taken at fixed
//    sample counts of each tile (checkpoints: the minimum samples m, then n + max(4, n / 4)), from
//    the tile's own samples: the mean of [0, a) against that of [a, n), a the previous checkpoint,
//    scaled to the expected |I - A| of Cycles' half buffer (sqrt(a (n - a)) / n). So an
//    adaptive image is the same whatever the threads, passes, cancellations and continuations,
//    and a region render on the tile grid gives the whole render's pixels there (a tile the
//    region cuts decides on its pixels inside). Each pixel is the mean of the
//    samples its tile took (film counts); parts (part()) and sample ranges (--samples) refuse
//    it, as they carry no per-pixel counts.
//  - Constructors validate options and throw std::invalid_argument naming the option
//    ("--spp: must be >= 1"); after that nothing throws (but the callback may), allocates or
//    logs per sample.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>

#include "facet/render/film.h"
#include "facet/render/image.h"
#include "facet/render/integrator.h"
#include "facet/render/progress.h"
#include "facet/render/scene.h"

namespace facet::render {

inline constexpr int kDefaultTileSize = 16;
inline constexpr int kMaxPassSpp = 16;

enum class LightSelection : std::uint8_t { View, Power, Uniform, Tree, Auto };

// Auto: the light tree when the scene has at least this many local lights (lights with
// bounds: not the environment or a distant sun) that next-event estimation samples, else View.
// Measured (docs/performance.md, "Light selection measured from the view"): the tree wins from
// 17 lamps on (an interior with 17 lamps: noise^2 x CPU 0.54 of View's; 64 lamps: 0.19) and
// loses with 5 or fewer (5 lamps of Radius 1: 3.8x View's; a hidden strong lamp: ~1500x).
inline constexpr int kTreeMinLocalLights = 12;

struct RenderOptions {
    std::string integrator;               // "" = scene setting; "direct" | "path"
    int spp = 0;                          // 0 = scene setting
    std::optional<double> time_budget_s;  // unset = scene setting; 0 = no budget
    int max_depth = -1;                   // < 0 = scene setting
    std::optional<std::uint64_t> seed;    // unset = scene setting
    int threads = 0;                      // 0 = every hardware thread
    bool force_general_kernel = false;    // --kernel general
    // Path: how next-event estimation chooses the light of a shadow ray (light.h):
    // View: in proportion to each light's contribution measured at the points the camera sees
    // (LightDistribution::view, the default); Power: in proportion to power (pbrt-v4's);
    // Uniform: every light equally often (Cycles 3.4's; comparisons, tests); Tree: the light
    // tree (light_tree.h); Auto (the default): Tree or View by kTreeMinLocalLights.
    LightSelection light_selection = LightSelection::Auto;  // --light-selection
    // Independent uniform samples instead of Owen-scrambled Sobol (the peer of the time-to-error
    // benchmark; --sampler independent). Images converge to the same value, more slowly.
    bool independent_samples = false;
    // The media kernel's next-event distance in homogeneous media (integrator.h,
    // VolumeSampling): free-flight and equiangular by MIS (the default), or free flight alone.
    VolumeSampling volume_sampling = VolumeSampling::MultipleImportance;
    Progress::Mode progress = Progress::Mode::Silent;
    int tile_size = kDefaultTileSize;
    // Crop window of the full image (--region); unset = the whole image.
    std::optional<Region> region;
    // Samples [sample_begin, sample_end) of every pixel (--samples s0:s1); sample_end 0 = spp.
    // The range is part of the spp-sample render (sample_end <= spp).
    int sample_begin = 0, sample_end = 0;
    // Target duration of a pass when a callback watches the session (seconds).
    double pass_seconds = 0.25;
    // Adaptive sampling (conventions): the noise threshold (0 = off; Cycles' Noise Threshold)
    // and the samples every pixel takes first (0 = automatic: max(16, ceil(2 / sqrt(t)))).
    std::optional<double> adaptive_threshold;  // unset = scene setting; --adaptive-threshold
    int adaptive_min_samples = -1;             // < 0 = scene setting; --adaptive-min-samples
    // The Shadow Catcher pass is wanted (--shadow-catcher-pass; Blender's View Layer > Passes >
    // Shadow Catcher): in a scene with a shadow catcher image() is then Cycles' Combined pass of
    // such a render, the matte and its alpha (film.h), instead of the approximation. The pass
    // itself is shadow_catcher_pass(), with or without this.
    bool shadow_catcher_pass = false;
    // The Depth pass of the render's own camera samples (depth()): each pixel's view-axis depth
    // of its camera rays' first hits, as aov.h's kAovDepth (the mean over the samples that hit,
    // kMissDepth where none does), summed while rendering instead of tracing camera rays again.
    // Taken where those first hits are what camera rays see (depth_pass_available()): not
    // under motion blur or ray visibility (render_aovs then).
    bool depth_pass = false;
};

struct RenderStats {
    KernelChoice kernel;
    double seconds = 0;  // wall time of the sample loop (excludes scene loading)
    int spp = 0;         // samples per pixel taken (the least over the region's tiles)
    int passes = 0;
    int threads = 0;
    std::uint64_t paths = 0;        // camera samples
    std::uint64_t rays = 0;         // closest-hit rays (camera + continuation)
    std::uint64_t shadow_rays = 0;  // occlusion rays
    std::uint64_t nonfinite = 0;    // samples dropped: NaN/inf or beyond film.h's kMaxSampleValue
    double mean_spp = 0;            // samples per pixel taken, averaged over the region
                                    // (below spp where adaptive sampling stopped tiles early)
    bool cancelled = false;
};

// Resolved settings (options merged with the scene's); throws std::invalid_argument.
struct ResolvedSettings {
    IntegratorKind integrator;
    int spp, max_depth, threads, tile_size;
    double time_budget_s;
    std::uint64_t seed;
    Region region;
    int sample_begin, sample_end;
    double adaptive_threshold;  // 0: off
    int adaptive_min_samples;   // resolved (>= 2 when adaptive)
};
ResolvedSettings resolve_settings(const Scene& scene, const RenderOptions& options);

// What a pass callback sees.
struct PassInfo {
    int pass = 0;            // passes completed (1 after the first)
    int samples_done = 0;    // samples per pixel completed (within the sample range)
    int samples_target = 0;  // samples per pixel the session is rendering toward
    double elapsed_s = 0;    // session time so far (all render() calls)
    double eta_s = 0;        // estimated seconds to the target (0 when done)
};

class RenderSession {
  public:
    // Called on the thread that called render(), after each pass; return false to cancel.
    using PassCallback = std::function<bool(const PassInfo&)>;

    // The scene must outlive the session. Throws std::invalid_argument for bad options.
    RenderSession(const Scene& scene, const RenderOptions& options);
    ~RenderSession();
    RenderSession(const RenderSession&) = delete;
    RenderSession& operator=(const RenderSession&) = delete;

    // Renders toward the target (see conventions). True when the target was reached (or the
    // time budget spent), false when cancelled. Not re-entrant; one render() at a time.
    bool render(const PassCallback& on_pass = {});
    // Thread safe; see conventions. Clears itself when the next render() starts.
    void cancel();
    // Raises the target to `spp` samples per pixel (>= the current target): the next render()
    // renders only the new samples. Throws std::invalid_argument for spp < target, or for a
    // 1-spp (pixel-centre) session.
    void continue_to(int spp);

    // The current image over the region (call between passes or after render()).
    Image image() const;
    // The Shadow Catcher pass over the region (film.h; all 1 in a scene without a catcher).
    Image shadow_catcher_pass() const;
    // The Depth pass over the region (RenderOptions::depth_pass; one channel repeated in RGB, as
    // render_aovs' depth): an empty image when the options did not ask for it or it is not
    // available (depth_pass_available()).
    Image depth() const;
    const Film& film() const;
    // The part this session has rendered (requires every tile to be complete: throws
    // std::logic_error after a cancellation that left some tile behind; std::invalid_argument
    // for an adaptive render, conventions).
    RenderPart part() const;
    const RenderStats& stats() const;
    const ResolvedSettings& settings() const;
    int samples_done() const;  // the least sample count over the region's tiles

  private:
    struct State;
    std::unique_ptr<State> m;
};

// Renders the scene (or options' region / sample range) to the end: one RenderSession.
Image render(const Scene& scene, const RenderOptions& options, RenderStats* stats = nullptr);

// The fingerprint a part of this scene rendered with these options carries (film.h): the
// scene's and every setting that changes the image.
// What `selection` is for this scene: Auto resolved by kTreeMinLocalLights, others as they are.
LightSelection resolve_light_selection(const Scene& scene, LightSelection selection);
// "view", "power", "uniform", "tree" or "auto".
const char* light_selection_name(LightSelection selection);

std::uint64_t part_fingerprint(const Scene& scene, const ResolvedSettings& settings,
                               const RenderOptions& options);

// Whether a render of this scene can sum the Depth pass of its camera samples
// (RenderOptions::depth_pass): its camera rays' first hits are the surfaces they see (no ray
// visibility) at the still camera (no motion blur).
bool depth_pass_available(const Scene& scene);

}  // namespace facet::render
