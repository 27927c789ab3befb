// RenderSession and render() (facet/render/render.h): tiles over TBB, passes, progress,
// cancellation, continuation, regions and sample ranges.
#include <tbb/blocked_range.h>
#include <tbb/info.h>
#include <tbb/parallel_for.h>
#include <tbb/partitioner.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <stdexcept>
#include <vector>

#include "facet/render/render.h"

#include "facet/render/aov.h"

namespace facet::render {

namespace {

struct Tile {
    Region r;
    int next = 0;  // the first sample this tile has not taken yet
    // Adaptive sampling (render.h): the tile's previous and next checkpoints, and whether it
    // has converged (it then takes no more samples).
    int last_checkpoint = 0, checkpoint = 0;
    bool converged = false;
    // The kernel's counters for this tile, summed over the tiles when render() returns: written
    // only by the thread rendering the tile, where shared atomics took 4 contended read-modify-
    // writes per tile-pass (32 per tile in a 32-pass session).
    KernelCounters counters;
};

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t) {
    return std::chrono::duration<double>(Clock::now() - t).count();
}

std::uint64_t mix(std::uint64_t h, std::uint64_t v) {
    // splitmix64 finaliser over h ^ v: order-dependent, well spread.
    std::uint64_t z = h ^ (v + 0x9e3779b97f4a7c15ull + (h << 6) + (h >> 2));
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
}

}  // namespace

ResolvedSettings resolve_settings(const Scene& scene, const RenderOptions& o) {
    const RenderSettings& s = scene.settings();
    ResolvedSettings r{};
    r.integrator = parse_integrator(o.integrator.empty() ? s.integrator : o.integrator);
    r.spp = o.spp != 0 ? o.spp : s.spp;
    if (r.spp < 1)
        throw std::invalid_argument("--spp: must be >= 1 (got " + std::to_string(r.spp) + ")");
    r.max_depth = o.max_depth >= 0 ? o.max_depth : s.max_depth;
    if (r.max_depth < 0) throw std::invalid_argument("--max-depth: must be >= 0");
    r.time_budget_s = o.time_budget_s ? *o.time_budget_s : s.time_budget_s;
    if (!(r.time_budget_s >= 0.0))
        throw std::invalid_argument("--time: the time budget must be >= 0 seconds");
    r.seed = o.seed ? *o.seed : s.seed;
    if (o.threads < 0) throw std::invalid_argument("--threads: must be >= 0 (0 = all cores)");
    r.threads = o.threads > 0 ? o.threads : int(tbb::info::default_concurrency());
    if (o.tile_size < 1) throw std::invalid_argument("tile size must be >= 1");
    r.tile_size = o.tile_size;
    const int w = scene.camera().width, h = scene.camera().height;
    if (w < 1 || h < 1) throw std::invalid_argument("camera: empty image");
    r.region = o.region ? *o.region : Region{0, 0, w, h};
    if (r.region.empty() || r.region.x0 < 0 || r.region.y0 < 0 || r.region.x1 > w ||
        r.region.y1 > h) {
        throw std::invalid_argument(
            "--region: " + std::to_string(r.region.x0) + "," + std::to_string(r.region.y0) + "," +
            std::to_string(r.region.x1) + "," + std::to_string(r.region.y1) +
            " must be a non-empty x0,y0,x1,y1 rectangle inside the " + std::to_string(w) + "x" +
            std::to_string(h) + " image (x1, y1 exclusive)");
    }
    r.sample_begin = o.sample_begin;
    r.sample_end = o.sample_end != 0 ? o.sample_end : r.spp;
    if (r.sample_begin < 0 || r.sample_end <= r.sample_begin || r.sample_end > r.spp) {
        throw std::invalid_argument("--samples: " + std::to_string(r.sample_begin) + ":" +
                                    std::to_string(r.sample_end) +
                                    " must be a non-empty range s0:s1 with 0 <= s0 < s1 <= spp (" +
                                    std::to_string(r.spp) + ")");
    }
    if (r.time_budget_s > 0.0 && (r.sample_begin != 0 || r.sample_end != r.spp)) {
        throw std::invalid_argument("--samples: cannot be combined with a time budget (--time)");
    }
    r.adaptive_threshold = o.adaptive_threshold ? *o.adaptive_threshold : s.adaptive_threshold;
    if (!(r.adaptive_threshold >= 0.0 && r.adaptive_threshold <= 1.0))
        throw std::invalid_argument("--adaptive-threshold: must be in [0, 1] (0 = off)");
    if (o.adaptive_min_samples < -1)
        throw std::invalid_argument("--adaptive-min-samples: must be >= 0 (0 = automatic)");
    const int min_samples =
        o.adaptive_min_samples >= 0 ? o.adaptive_min_samples : s.adaptive_min_samples;
    r.adaptive_min_samples = 0;
    if (r.adaptive_threshold > 0.0) {
        if (r.sample_begin != 0 || r.sample_end != r.spp)
            throw std::invalid_argument(
                "--samples: an adaptive render cannot be split by sample range (its tiles stop at "
                "sample counts of their own); split it by --region");
        r.adaptive_min_samples =
            min_samples > 0 ? min_samples
                            : std::max(16, int(std::ceil(2.0 / std::sqrt(r.adaptive_threshold))));
        r.adaptive_min_samples = std::max(r.adaptive_min_samples, 2);
    }
    return r;
}

namespace {

// Adaptive sampling (render.h): how far above the threshold a tile's worst pixel may lie.
constexpr double kAdaptiveWorst = 4.0;

// Adaptive sampling's per-pixel error (render.h): sums over the samples [0, a) and [0, n).
double adaptive_error(const FixedRgb& sum_a, int a, const FixedRgb& sum_n, int n) {
    double difference = 0.0, intensity = 0.0;
    for (int c = 0; c < 3; ++c) {
        const double first = from_fixed(sum_a.c[c]) / double(a);
        const double second = from_fixed(sum_n.c[c] - sum_a.c[c]) / double(n - a);
        difference += std::fabs(first - second);
        intensity += from_fixed(sum_n.c[c]) / double(n);
    }
    difference *= std::sqrt(double(a) * double(n - a)) / double(n);
    const double normalize = intensity < 1.0 ? std::sqrt(std::max(intensity, 0.0)) : intensity;
    return difference / (1e-4 + normalize);
}

}  // namespace

LightSelection resolve_light_selection(const Scene& scene, LightSelection selection) {
    if (selection != LightSelection::Auto) return selection;
    int local = 0;
    for (const Light& l : scene.lights())
        if (nee_samples(l) && l.bounds()) ++local;
    return local >= kTreeMinLocalLights ? LightSelection::Tree : LightSelection::View;
}

const char* light_selection_name(LightSelection selection) {
    switch (selection) {
        case LightSelection::View:
            return "view";
        case LightSelection::Power:
            return "power";
        case LightSelection::Uniform:
            return "uniform";
        case LightSelection::Tree:
            return "tree";
        case LightSelection::Auto:
            break;
    }
    return "auto";
}

std::uint64_t part_fingerprint(const Scene& scene, const ResolvedSettings& rs,
                               const RenderOptions& o) {
    const LightSelection ls = resolve_light_selection(scene, o.light_selection);
    std::uint64_t h = mix(0x46414345545041ull, scene.fingerprint());
    h = mix(h, std::uint64_t(rs.integrator));
    h = mix(h, std::uint64_t(rs.max_depth));
    h = mix(h, rs.seed);
    h = mix(h, rs.spp == 1 ? 1u : 0u);  // pixel-centre camera rays
    h = mix(h, (o.independent_samples ? 1u : 0u) | (std::uint64_t(ls) << 3) |
                   (ls == LightSelection::Uniform ? 2u : 0u) | (o.force_general_kernel ? 4u : 0u));
    if (o.volume_sampling != VolumeSampling::MultipleImportance)
        h = mix(h, 0x564f4c0000ull | std::uint64_t(o.volume_sampling));
    if (rs.adaptive_threshold > 0.0) {
        std::uint64_t bits;
        std::memcpy(&bits, &rs.adaptive_threshold, sizeof bits);
        h = mix(mix(h, bits), std::uint64_t(rs.adaptive_min_samples));
    }
    return h;
}

struct RenderSession::State {
    const Scene& scene;
    RenderOptions options;
    ResolvedSettings rs;
    KernelChoice choice;
    TileKernel kernel = nullptr;
    LightDistribution light_dist;
    std::vector<Tile> tiles;
    Film film;
    // Adaptive sampling: each pixel's sum at its tile's last checkpoint (film layout).
    std::vector<FixedRgb> checkpoint_sums;
    // The Depth pass's sums and counts (RenderOptions::depth_pass, TileJob::depth; film
    // layout), empty when not taken.
    std::vector<FixedSum> depth_sums;
    std::vector<std::uint32_t> depth_hits;
    RenderStats stats;
    int target = 0;  // sample end the session renders toward
    // Read before every tile: kept off the cache lines the render loop writes.
    alignas(64) std::atomic<bool> cancel{false};

    State(const Scene& s, const RenderOptions& o)
        : scene(s), options(o), rs(resolve_settings(s, o)) {}

    // The film's per-pixel counts, written from the tiles' sample positions when the film is
    // read (every pixel of a tile holds samples [sample_begin, tile.next)), not per pass: at
    // 1-sample passes a per-pixel count update is a measurable share of the pass.
    void sync_counts() {
        std::uint32_t* counts = film.counts();
        const std::size_t w = std::size_t(rs.region.width());
        for (const Tile& t : tiles) {
            const std::uint32_t n = std::uint32_t(t.next - rs.sample_begin);
            for (int y = t.r.y0; y < t.r.y1; ++y) {
                std::uint32_t* row =
                    counts + std::size_t(y - rs.region.y0) * w - std::size_t(rs.region.x0);
                std::fill(row + t.r.x0, row + t.r.x1, n);
            }
        }
    }

    // Where a tile stands toward the target: a converged tile is done.
    int done_at(const Tile& t) const { return t.converged ? target : t.next; }
    int min_next() const {
        int m = target;
        for (const Tile& t : tiles) m = std::min(m, done_at(t));
        return m;
    }

    bool adaptive() const { return rs.adaptive_threshold > 0.0; }
    // Adaptive sampling at a tile's checkpoint (render.h): at the first, the sums are kept; at
    // the others the tile converges when every pixel's error is below the threshold.
    void at_checkpoint(Tile& t) {
        const int n = t.checkpoint, a = t.last_checkpoint;
        const std::size_t w = std::size_t(rs.region.width());
        double sum_sq = 0.0, worst = 0.0;
        for (int y = t.r.y0; y < t.r.y1; ++y) {
            const std::size_t row = std::size_t(y - rs.region.y0) * w;
            for (int x = t.r.x0; x < t.r.x1; ++x) {
                const std::size_t i = row + std::size_t(x - rs.region.x0);
                const FixedRgb& now = film.sums()[i];
                if (a > 0) {
                    const double e = adaptive_error(checkpoint_sums[i], a, now, n);
                    sum_sq += e * e;
                    worst = std::max(worst, e);
                }
                checkpoint_sums[i] = now;
            }
        }
        // Each pixel's error is one draw of |A - B|: the tile's root mean square is its typical
        // pixel's, and its worst pixel may lie up to kAdaptiveWorst times above (render.h).
        const double pixels = double(t.r.width()) * double(t.r.height());
        t.converged = a > 0 && std::sqrt(sum_sq / pixels) < rs.adaptive_threshold &&
                      worst < kAdaptiveWorst * rs.adaptive_threshold;
        t.last_checkpoint = n;
        t.checkpoint = n + std::max(4, n / 4);
    }

    // Takes every tile with next < end to `end` (unless cancelled first).
    void run_pass(tbb::task_arena& arena, int end, Progress& progress) {
        TileJob proto{};
        proto.film_x0 = rs.region.x0;
        proto.film_y0 = rs.region.y0;
        proto.film_width = rs.region.width();
        proto.spp_total = rs.spp;
        proto.seed = rs.seed;
        proto.max_depth = choice.max_depth;
        proto.light_distribution = &light_dist;
        proto.independent_samples = options.independent_samples;
        proto.volume_sampling = options.volume_sampling;
        proto.alpha = film.alpha_sums();
        proto.catcher = film.catcher_sums();
        if (!depth_sums.empty()) {
            proto.depth = depth_sums.data();
            proto.depth_hits = depth_hits.data();
        }
        arena.execute([&] {
            tbb::parallel_for(
                tbb::blocked_range<std::size_t>(0, tiles.size(), 1),
                [&](const tbb::blocked_range<std::size_t>& range) {
                    for (std::size_t t = range.begin(); t != range.end(); ++t) {
                        Tile& tile = tiles[t];
                        // Adaptive: the tile-pass stops at each checkpoint it reaches.
                        while (!tile.converged && tile.next < end &&
                               !cancel.load(std::memory_order_relaxed)) {
                            const int stop = adaptive() ? std::min(end, tile.checkpoint) : end;
                            TileJob job = proto;
                            job.x0 = tile.r.x0;
                            job.y0 = tile.r.y0;
                            job.x1 = tile.r.x1;
                            job.y1 = tile.r.y1;
                            job.first_sample = tile.next;
                            job.end_sample = stop;
                            KernelCounters c;  // on this thread's stack while the kernel runs
                            kernel(scene, job, film.sums(), c);
                            tile.counters += c;
                            const std::uint32_t added = std::uint32_t(stop - tile.next);
                            tile.next = stop;
                            progress.add(std::uint64_t(tile.r.width()) *
                                         std::uint64_t(tile.r.height()) * added);
                            if (adaptive() && stop == tile.checkpoint) at_checkpoint(tile);
                        }
                    }
                },
                tbb::simple_partitioner());
        });
    }
};

RenderSession::RenderSession(const Scene& scene, const RenderOptions& options)
    : m(std::make_unique<State>(scene, options)) {
    State& s = *m;
    s.choice = choose_kernel(scene.features(), s.rs.integrator, s.rs.max_depth,
                             options.force_general_kernel);
    s.kernel = kernel_function(s.choice);
    switch (resolve_light_selection(scene, options.light_selection)) {
        case LightSelection::Auto:  // resolved above
        case LightSelection::View:
            s.light_dist = scene.view_light_distribution();
            break;
        case LightSelection::Power:
            s.light_dist = scene.light_distribution();
            break;
        case LightSelection::Uniform:
            s.light_dist = LightDistribution::uniform(scene.lights());
            break;
        case LightSelection::Tree:
            s.light_dist = LightDistribution::tree(scene.lights(), scene.radius());
    }
    if (!(options.pass_seconds > 0.0)) throw std::invalid_argument("pass_seconds must be > 0");
    const Region& reg = s.rs.region;
    const int ts = s.rs.tile_size;
    // Tiles: the cells of a fixed grid over the whole image, cut to the region.
    for (int gy = reg.y0 - reg.y0 % ts; gy < reg.y1; gy += ts) {
        for (int gx = reg.x0 - reg.x0 % ts; gx < reg.x1; gx += ts) {
            Tile t;
            t.r = Region{std::max(gx, reg.x0), std::max(gy, reg.y0), std::min(gx + ts, reg.x1),
                         std::min(gy + ts, reg.y1)};
            t.next = s.rs.sample_begin;
            t.checkpoint = s.rs.adaptive_min_samples;
            s.tiles.push_back(t);
        }
    }
    s.film = Film(reg, scene.settings().film_transparent, scene.features().has_shadow_catcher);
    // (A kernel with motion blur, e.g. the general one when forced, does not sum the pass.)
    if (options.depth_pass && depth_pass_available(scene) &&
        (s.choice.features & kFeatMotion) == 0) {
        const std::size_t pixels = std::size_t(reg.width()) * std::size_t(reg.height());
        s.depth_sums.assign(pixels, FixedSum(0));
        s.depth_hits.assign(pixels, 0u);
    }
    if (s.adaptive()) s.checkpoint_sums.assign(s.film.sum_values().size(), FixedRgb{});
    s.target = s.rs.sample_end;
    s.stats.kernel = s.choice;
    s.stats.threads = s.rs.threads;
}

RenderSession::~RenderSession() = default;

void RenderSession::cancel() {
    m->cancel.store(true);
}

void RenderSession::continue_to(int spp) {
    if (m->rs.spp == 1) {
        throw std::invalid_argument(
            "continue_to: a 1-spp render traces pixel centres and cannot be continued (start "
            "with spp >= 2)");
    }
    if (spp < m->target) {
        throw std::invalid_argument("continue_to: " + std::to_string(spp) +
                                    " is below the current target of " + std::to_string(m->target) +
                                    " samples");
    }
    if (spp > (1 << 20)) throw std::invalid_argument("continue_to: at most 2^20 samples");
    m->target = spp;
}

bool RenderSession::render(const PassCallback& on_pass) {
    State& s = *m;
    s.cancel.store(false);
    const ResolvedSettings& rs = s.rs;
    const std::uint64_t pixels =
        std::uint64_t(rs.region.width()) * std::uint64_t(rs.region.height());
    const int start_done = s.min_next();
    Progress progress(std::string("render ") + s.scene.name(),
                      pixels * std::uint64_t(s.target - start_done), s.options.progress);
    const bool budgeted = rs.time_budget_s > 0.0;
    if (budgeted) progress.set_time_budget(rs.time_budget_s);
    tbb::task_arena arena(rs.threads);
    const auto start = Clock::now();
    const double elapsed_before = s.stats.seconds;

    bool completed = true;
    int affordable = s.target;  // samples per pixel the remaining budget allows (estimated)
    while (true) {
        const int done = s.min_next();
        if (done >= s.target) break;
        // Pass size (render.h): budgeted 1, 1, 2, 4, ... cut to the budget; watched: about
        // pass_seconds at the cost so far; otherwise everything, in steps of kMaxPassSpp so
        // that a tile in flight is short when cancel() comes.
        const int taken = done - start_done;
        int pass = s.target - done;
        if (budgeted) {
            pass = std::min({pass, std::max(1, taken), kMaxPassSpp, affordable});
        } else if (on_pass) {
            const double t = seconds_since(start);
            const int fit = taken > 0 ? int(std::floor(s.options.pass_seconds * taken / t)) : 1;
            pass = std::clamp(fit, 1, pass);
        } else {
            pass = std::min(pass, kMaxPassSpp);
        }
        s.run_pass(arena, done + pass, progress);
        ++s.stats.passes;
        if (s.cancel.load()) {
            completed = false;
            break;
        }
        const double t = seconds_since(start);
        const int now_done = s.min_next();
        if (on_pass) {
            PassInfo info;
            info.pass = s.stats.passes;
            info.samples_done = now_done - rs.sample_begin;
            info.samples_target = s.target - rs.sample_begin;
            info.elapsed_s = elapsed_before + t;
            const int taken_now = now_done - start_done;
            info.eta_s = taken_now > 0 ? t / double(taken_now) * double(s.target - now_done) : 0.0;
            s.stats.seconds = elapsed_before + t;
            if (!on_pass(info)) {
                completed = false;
                break;
            }
        }
        if (budgeted) {
            // Stop when not even one more sample per pixel fits (at this run's mean cost).
            const double per_spp = t / double(now_done - start_done);
            const double fit = std::floor((rs.time_budget_s - t) / per_spp);
            if (!(fit >= 1.0)) break;
            affordable = int(std::min(fit, double(kMaxPassSpp)));
        }
    }
    const double seconds = seconds_since(start);
    RenderStats& st = s.stats;
    st.seconds = elapsed_before + seconds;
    st.spp = s.min_next() - rs.sample_begin;
    if (s.adaptive()) {
        st.spp = s.target - rs.sample_begin;
        for (const Tile& t : s.tiles) st.spp = std::min(st.spp, t.next - rs.sample_begin);
    }
    double taken = 0.0;
    for (const Tile& t : s.tiles)
        taken += double(t.next - rs.sample_begin) * double(t.r.width()) * double(t.r.height());
    st.mean_spp = taken / double(pixels);
    KernelCounters total;
    for (const Tile& t : s.tiles) total += t.counters;
    st.paths = total.camera_rays;
    st.rays = total.rays;
    st.shadow_rays = total.shadow_rays;
    st.nonfinite = total.nonfinite;
    st.cancelled = !completed;
    char adaptive[64] = "";
    if (s.adaptive())
        std::snprintf(adaptive, sizeof adaptive, " (adaptive: mean %.3g spp)", st.mean_spp);
    char summary[320];
    std::snprintf(summary, sizeof summary,
                  "%d spp%s, %.3g M paths/s, %.3g M rays/s (+%.3g M shadow rays/s), kernel %s%s",
                  st.spp, adaptive, double(st.paths) / st.seconds * 1e-6,
                  double(st.rays) / st.seconds * 1e-6, double(st.shadow_rays) / st.seconds * 1e-6,
                  s.choice.name.c_str(), completed ? "" : " (cancelled)");
    progress.finish(summary);
    return completed;
}

Image RenderSession::image() const {
    m->sync_counts();
    return m->film.resolve(m->options.shadow_catcher_pass);
}
Image RenderSession::shadow_catcher_pass() const {
    m->sync_counts();
    return m->film.resolve_shadow_catcher_pass();
}
Image RenderSession::depth() const {
    const State& s = *m;
    if (s.depth_sums.empty()) return Image();
    Image img(s.rs.region.width(), s.rs.region.height());
    for (std::size_t i = 0; i < s.depth_sums.size(); ++i)
        img.pixels()[i] = Rgb(resolved_depth(s.depth_sums[i], s.depth_hits[i]));
    return img;
}
bool depth_pass_available(const Scene& scene) {
    return !scene.features().has_motion && !scene.features().has_ray_visibility;
}
const Film& RenderSession::film() const {
    m->sync_counts();
    return m->film;
}
const RenderStats& RenderSession::stats() const {
    return m->stats;
}
const ResolvedSettings& RenderSession::settings() const {
    return m->rs;
}
int RenderSession::samples_done() const {
    return m->min_next() - m->rs.sample_begin;
}

RenderPart RenderSession::part() const {
    const State& s = *m;
    if (s.adaptive())
        throw std::invalid_argument(
            "part: an adaptive render's pixels have sample counts of their own, which part files "
            "do not carry; render it whole (a --region render gives the same pixels as the "
            "whole image's)");
    for (const Tile& t : s.tiles) {
        if (s.done_at(t) != s.target)
            throw std::logic_error("RenderSession::part: the render is incomplete (cancelled)");
    }
    RenderPart p;
    p.info.scene = s.scene.name();
    p.info.fingerprint = part_fingerprint(s.scene, s.rs, s.options);
    p.info.width = s.scene.camera().width;
    p.info.height = s.scene.camera().height;
    p.info.region = s.rs.region;
    p.info.sample_begin = s.rs.sample_begin;
    p.info.sample_end = s.target;
    p.info.seed = s.rs.seed;
    m->sync_counts();
    p.film = s.film;
    return p;
}

Image render(const Scene& scene, const RenderOptions& options, RenderStats* stats) {
    RenderSession session(scene, options);
    session.render();
    if (stats) *stats = session.stats();
    return session.image();
}

}  // namespace facet::render
