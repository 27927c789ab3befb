// The tiled render loop (facet/render/render.h).
#include "facet/render/render.h"

#include <tbb/blocked_range.h>
#include <tbb/info.h>
#include <tbb/parallel_for.h>
#include <tbb/partitioner.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <stdexcept>
#include <vector>

#include "facet/render/film.h"

namespace facet::render {

namespace {

struct Tile {
    int x0, y0, x1, y1;
};

std::vector<Tile> make_tiles(int width, int height, int size) {
    std::vector<Tile> tiles;
    for (int y = 0; y < height; y += size)
        for (int x = 0; x < width; x += size)
            tiles.push_back({x, y, std::min(x + size, width), std::min(y + size, height)});
    return tiles;
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
    if (scene.camera().width < 1 || scene.camera().height < 1)
        throw std::invalid_argument("camera: empty image");
    return r;
}

Image render(const Scene& scene, const RenderOptions& options, RenderStats* stats_out) {
    const ResolvedSettings rs = resolve_settings(scene, options);
    const KernelChoice choice =
        choose_kernel(scene.features(), rs.integrator, rs.max_depth, options.force_general_kernel);
    const TileKernel kernel = kernel_function(choice);
    const int width = scene.camera().width, height = scene.camera().height;
    const std::vector<Tile> tiles = make_tiles(width, height, rs.tile_size);
    const LightDistribution light_dist = options.uniform_light_selection
                                             ? LightDistribution::uniform(scene.lights().size())
                                             : scene.light_distribution();
    Film film(width, height);

    std::atomic<std::uint64_t> camera_rays{0}, rays{0}, shadow_rays{0}, nonfinite{0};
    const std::uint64_t pixels = std::uint64_t(width) * std::uint64_t(height);
    Progress progress(std::string("render ") + scene.name(), pixels * std::uint64_t(rs.spp),
                      options.progress);
    const bool budgeted = rs.time_budget_s > 0.0;
    if (budgeted) progress.set_time_budget(rs.time_budget_s);

    tbb::task_arena arena(rs.threads);
    const auto start = std::chrono::steady_clock::now();
    auto elapsed = [&] {
        return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    };

    int done = 0, passes = 0;
    int affordable = rs.spp;  // samples per pixel the remaining budget allows (estimated)
    while (done < rs.spp) {
        // Pass size: everything at once without a budget; 1, 1, 2, 4, ... (capped, and cut to
        // what the remaining budget affords) with one.
        int pass = rs.spp - done;
        if (budgeted) pass = std::min({pass, std::max(1, done), kMaxPassSpp, affordable});
        TileJob proto{0,          0, 0, 0, done, done + pass, rs.spp, rs.seed, choice.max_depth,
                      &light_dist};
        proto.independent_samples = options.independent_samples;
        arena.execute([&] {
            tbb::parallel_for(
                tbb::blocked_range<std::size_t>(0, tiles.size(), 1),
                [&](const tbb::blocked_range<std::size_t>& r) {
                    for (std::size_t t = r.begin(); t != r.end(); ++t) {
                        TileJob job = proto;
                        job.x0 = tiles[t].x0;
                        job.y0 = tiles[t].y0;
                        job.x1 = tiles[t].x1;
                        job.y1 = tiles[t].y1;
                        KernelCounters c;
                        kernel(scene, job, film.sums(), c);
                        camera_rays.fetch_add(c.camera_rays, std::memory_order_relaxed);
                        rays.fetch_add(c.rays, std::memory_order_relaxed);
                        shadow_rays.fetch_add(c.shadow_rays, std::memory_order_relaxed);
                        nonfinite.fetch_add(c.nonfinite, std::memory_order_relaxed);
                        progress.add(std::uint64_t(job.x1 - job.x0) *
                                     std::uint64_t(job.y1 - job.y0) * std::uint64_t(pass));
                    }
                },
                tbb::simple_partitioner());
        });
        done += pass;
        ++passes;
        if (budgeted) {
            // Stop when not even one more sample per pixel fits (at this run's mean cost).
            const double t = elapsed();
            const double per_spp = t / double(done);
            const double fit = std::floor((rs.time_budget_s - t) / per_spp);
            if (!(fit >= 1.0)) break;
            affordable = int(std::min(fit, double(kMaxPassSpp)));
        }
    }
    const double seconds = elapsed();

    RenderStats st;
    st.kernel = choice;
    st.seconds = seconds;
    st.spp = done;
    st.passes = passes;
    st.threads = rs.threads;
    st.paths = camera_rays.load();
    st.rays = rays.load();
    st.shadow_rays = shadow_rays.load();
    st.nonfinite = nonfinite.load();
    char summary[256];
    std::snprintf(summary, sizeof summary,
                  "%d spp, %.3g M paths/s, %.3g M rays/s (+%.3g M shadow rays/s), kernel %s", done,
                  double(st.paths) / seconds * 1e-6, double(st.rays) / seconds * 1e-6,
                  double(st.shadow_rays) / seconds * 1e-6, choice.name.c_str());
    progress.finish(summary);
    if (stats_out) *stats_out = st;
    return film.resolve(done);
}

}  // namespace facet::render
