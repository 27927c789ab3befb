// Renderer throughput against a raw Embree peer, and specialised vs general kernels, measured
// in the same run on the same scene. Prints a table of medians and same-run ratios.
//
//   facet_render_bench [--threads N] [--reps R] [--spp S] [--rays N] [scene.json ...]
//
// Per scene:
//  - raw Embree peer (Scene::trace_raw: bare rtcIntersect1 / rtcOccluded1 loops, no hit
//    records) on a fixed set of path-tracer rays: camera rays plus cosine-distributed bounce
//    rays from the surfaces they hit (closest-hit set), and shadow rays from those points to a
//    sample on a light (occlusion set);
//  - the same rays as Embree packets (Scene::trace_raw_packet: rtcIntersect8 / rtcOccluded8 over
//    consecutive groups of 8 rays of the set, i.e. incoherent packets);
//  - the renderer's Scene::intersect / Scene::occluded(_segment) on the same rays (full
//    SurfaceHit);
//  - the scene's integrator end to end (specialised and general kernel): paths/s and rays/s, where
//    rays = closest-hit + shadow rays; "of raw" compares the renderer's ray rate with the raw
//    single-ray rate of the same ray mix (n_rays / raw_isect_rate + n_shadow / raw_occl_rate).
//    The path tracer traces 8 neighbouring pixels' paths as packets, so that ratio also counts
//    what packets gain; "of raw packets" is the same ratio against the packet peer.
// Every timing is the median of R repetitions; everything uses the same TBB arena of N threads.
// A repetition measures the peers and the renders back to back, and the "of raw" ratios are the
// medians of the per-repetition ratios (their range is printed): on a shared machine whose
// speed drifts, a ratio of two medians taken seconds apart read 0.64-0.76 in runs of one build.
// Infinite planes are intersected outside Embree (scene.h), so on plane-only scenes the raw
// peer traces an empty BVH and its ratio is meaningless.
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "facet/frame.h"
#include "facet/render/render.h"
#include "facet/render/sampler.h"
#include "facet/render/scene.h"
#include "facet/sampling.h"

#ifndef FACET_SCENES_DIR
#define FACET_SCENES_DIR "scenes"
#endif

namespace fr = facet::render;
using facet::Vec2;
using facet::Vec3;

namespace {

double now_s() {
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch())
        .count();
}

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    const size_t n = v.size();
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

// The light sample a surface point tests (Scene::occluded(hit, sample), as the integrators do).
struct ShadowQuery {
    fr::SurfaceHit hit;
    fr::LightLiSample sample;
};

struct RaySets {
    std::vector<fr::Ray> bounce;  // incoherent closest-hit rays
    std::vector<fr::Ray> shadow;  // the shadow rays as raw rays (origin offset, tmax shortened)
    std::vector<ShadowQuery> shadow_queries;  // the same, as Scene::occluded arguments
};

// Uniform float in [0,1) from a counter (hash), for the ray-set construction only.
float rnd(std::uint32_t& state) {
    state = fr::hash_u32(state + 0x9e3779b9u);
    return fr::fixed_to_float(state);
}

// The rays of the first vertex of a path tracer: camera rays, cosine-distributed bounce rays
// from the surfaces they hit (closest-hit set), and shadow rays from those points toward a
// sample on a light chosen like the path tracer does, in proportion to power (occlusion set:
// the rays Scene::occluded(hit, sample) traces).
RaySets make_rays(const fr::Scene& scene, std::size_t count) {
    RaySets sets;
    const fr::Camera& cam = scene.camera();
    const auto lights = scene.lights();
    std::uint32_t state = 12345;
    std::size_t attempts = 0;
    while (sets.bounce.size() < count && attempts < count * 20) {
        ++attempts;
        const Vec2 film(rnd(state) * float(cam.width), rnd(state) * float(cam.height));
        const fr::Ray cam_ray = cam.generate_ray(film);
        sets.bounce.push_back(cam_ray);
        fr::SurfaceHit hit;
        if (!scene.intersect(cam_ray, hit)) continue;
        const Vec3 n = glm::dot(hit.ng, -cam_ray.d) >= 0.f ? hit.ng : -hit.ng;
        const facet::Frame f = facet::Frame::from_z(n);
        const Vec3 d = f.from_local(facet::sample_cosine_hemisphere({rnd(state), rnd(state)}));
        sets.bounce.push_back(fr::Scene::spawn_ray(hit, d));
        if (lights.empty()) continue;
        float pmf = 0.f;
        const fr::Light& light = lights[scene.light_distribution().sample(rnd(state), pmf)];
        const auto ls = light.sample_li({hit.p, n}, {rnd(state), rnd(state)});
        if (!ls || !(glm::dot(ls->wi, n) > 0.f)) continue;
        // The ray the integrators trace (Scene::shadow_ray(hit, sample)).
        fr::Ray r = fr::Scene::shadow_ray(hit, *ls);
        if (!(r.tmax > 0.f)) continue;
        sets.shadow_queries.push_back({hit, *ls});
        sets.shadow.push_back(r);
    }
    return sets;
}

// Runs fn(begin, end) over [0, n) in chunks on the arena; returns seconds.
template <class Fn>
double timed_parallel(tbb::task_arena& arena, std::size_t n, Fn fn) {
    const double t0 = now_s();
    arena.execute([&] {
        tbb::parallel_for(
            tbb::blocked_range<std::size_t>(0, n, 4096),
            [&](const tbb::blocked_range<std::size_t>& r) { fn(r.begin(), r.end()); });
    });
    return now_s() - t0;
}

struct Row {
    std::string scene, what;
    double value;  // per second
    std::string unit;
    std::string note;
};

}  // namespace

int main(int argc, char** argv) {
    int threads = 2, reps = 5, spp = 1;
    std::size_t nrays = 1000000;
    std::vector<std::string> scenes;
    for (int i = 1; i < argc; ++i) {
        auto next = [&](const char* name) -> const char* {
            if (i + 1 >= argc) {
                std::fprintf(stderr, "facet_render_bench: %s needs a value\n", name);
                std::exit(1);
            }
            return argv[++i];
        };
        if (!std::strcmp(argv[i], "--help") || !std::strcmp(argv[i], "-h")) {
            std::printf(
                "usage: facet_render_bench [--threads N] [--reps R] [--spp S] [--rays N] "
                "[scene.json ...]\n"
                "  --threads N  TBB threads (default 2)\n"
                "  --reps R     repetitions; every figure is the median (default 5)\n"
                "  --spp S      samples per pixel of the end-to-end renders, at least (default 1;\n"
                "               raised so that a render lasts >= 0.2 s)\n"
                "  --rays N     rays per ray set of the raw Embree peers (default 1000000)\n"
                "  scenes       default: cornell_box, big_mesh, point_plane from %s\n",
                FACET_SCENES_DIR);
            return 0;
        }
        if (!std::strcmp(argv[i], "--threads"))
            threads = std::atoi(next("--threads"));
        else if (!std::strcmp(argv[i], "--reps"))
            reps = std::atoi(next("--reps"));
        else if (!std::strcmp(argv[i], "--spp"))
            spp = std::atoi(next("--spp"));
        else if (!std::strcmp(argv[i], "--rays"))
            nrays = std::size_t(std::atol(next("--rays")));
        else
            scenes.emplace_back(argv[i]);
    }
    if (threads < 1 || reps < 1 || spp < 1 || nrays < 1) {
        std::fprintf(stderr, "facet_render_bench: --threads, --reps, --spp, --rays must be >= 1\n");
        return 1;
    }
    if (scenes.empty()) {
        scenes = {std::string(FACET_SCENES_DIR) + "/cornell_box.json",
                  std::string(FACET_SCENES_DIR) + "/big_mesh.json",
                  std::string(FACET_SCENES_DIR) + "/point_plane.json"};
    }
    tbb::task_arena arena(threads);
    std::printf(
        "facet render benchmark: %d threads, median of %d reps, >= %d spp per render, %zu "
        "rays per ray set\n\n",
        threads, reps, spp, nrays);
    std::printf("| scene | measure | median | unit | same-run ratio |\n");
    std::printf("|---|---|---:|---|---|\n");

    for (const std::string& path : scenes) {
        fr::Scene scene;
        const double tl = now_s();
        try {
            scene = fr::load_scene(path);
        } catch (const std::exception& e) {
            std::fprintf(stderr, "facet_render_bench: %s\n", e.what());
            return 1;
        }
        const double load_s = now_s() - tl;
        std::string name = path.substr(path.find_last_of('/') + 1);
        const RaySets sets = make_rays(scene, nrays);
        const std::size_t nb = sets.bounce.size(), ns = sets.shadow.size();

        // Samples per pixel of the end-to-end renders: at least --spp, more for tiny scenes so
        // that a render lasts >= ~0.2 s.
        int render_spp = spp;
        {
            fr::RenderOptions o;
            o.integrator = scene.settings().integrator;
            o.spp = spp;
            o.threads = threads;
            fr::RenderStats st;
            (void)fr::render(scene, o, &st);
            if (st.seconds < 0.2)
                render_spp = std::min(
                    64 * spp, int(std::ceil(0.2 / std::max(st.seconds, 1e-4) * double(spp))));
        }

        // Every repetition measures everything once, peers and renders back to back, so that
        // a change in the shared machine's speed hits peer and renderer alike; the "of raw"
        // ratios are the medians of the per-repetition ratios.
        std::vector<double> t_raw_i, t_raw_o, t_ren_i, t_ren_o, t_pk_i, t_pk_o;
        std::vector<double> t_spec, t_gen;
        std::vector<double> of_raw_spec, of_pk_spec, of_raw_gen, of_pk_gen;
        fr::RenderStats st_spec, st_gen;
        std::atomic<std::uint64_t> sink{0};
        for (int r = 0; r < reps; ++r) {
            t_raw_i.push_back(timed_parallel(arena, nb, [&](std::size_t b, std::size_t e) {
                sink += scene.trace_raw(std::span(sets.bounce).subspan(b, e - b), false);
            }));
            t_pk_i.push_back(timed_parallel(arena, nb, [&](std::size_t b, std::size_t e) {
                sink += scene.trace_raw_packet(std::span(sets.bounce).subspan(b, e - b), false);
            }));
            t_pk_o.push_back(timed_parallel(arena, ns, [&](std::size_t b, std::size_t e) {
                sink += scene.trace_raw_packet(std::span(sets.shadow).subspan(b, e - b), true);
            }));
            t_ren_i.push_back(timed_parallel(arena, nb, [&](std::size_t b, std::size_t e) {
                std::uint64_t h = 0;
                for (std::size_t k = b; k < e; ++k) {
                    fr::SurfaceHit hit;
                    h += scene.intersect(sets.bounce[k], hit);
                }
                sink += h;
            }));
            t_raw_o.push_back(timed_parallel(arena, ns, [&](std::size_t b, std::size_t e) {
                sink += scene.trace_raw(std::span(sets.shadow).subspan(b, e - b), true);
            }));
            t_ren_o.push_back(timed_parallel(arena, ns, [&](std::size_t b, std::size_t e) {
                std::uint64_t h = 0;
                for (std::size_t k = b; k < e; ++k) {
                    const ShadowQuery& q = sets.shadow_queries[k];
                    h += scene.occluded(q.hit, q.sample);
                }
                sink += h;
            }));
            // End-to-end path tracing, specialised and general kernels.
            for (bool general : {false, true}) {
                fr::RenderOptions o;
                o.integrator = scene.settings().integrator;
                o.spp = render_spp;
                o.threads = threads;
                o.seed = 1;
                o.force_general_kernel = general;
                fr::RenderStats st;
                (void)fr::render(scene, o, &st);
                (general ? t_gen : t_spec).push_back(st.seconds);
                (general ? st_gen : st_spec) = st;
                // This repetition's peers on the render's ray mix, over the render's time.
                const double raw_mix = double(st.rays) * t_raw_i.back() / double(nb) +
                                       double(st.shadow_rays) * t_raw_o.back() / double(ns);
                const double pk_mix = double(st.rays) * t_pk_i.back() / double(nb) +
                                      double(st.shadow_rays) * t_pk_o.back() / double(ns);
                (general ? of_raw_gen : of_raw_spec).push_back(raw_mix / st.seconds);
                (general ? of_pk_gen : of_pk_spec).push_back(pk_mix / st.seconds);
            }
        }
        const double raw_i = double(nb) / median(t_raw_i), ren_i = double(nb) / median(t_ren_i);
        const double raw_o = double(ns) / median(t_raw_o), ren_o = double(ns) / median(t_ren_o);
        const double pk_i = double(nb) / median(t_pk_i), pk_o = double(ns) / median(t_pk_o);
        const double ts = median(t_spec), tg = median(t_gen);
        const double paths_s = double(st_spec.paths) / ts;
        const double rays_s = double(st_spec.rays + st_spec.shadow_rays) / ts;
        const double paths_g = double(st_gen.paths) / tg;
        const double rays_g = double(st_gen.rays + st_gen.shadow_rays) / tg;
        auto spread = [](const std::vector<double>& v) {
            return std::make_pair(*std::min_element(v.begin(), v.end()),
                                  *std::max_element(v.begin(), v.end()));
        };

        const std::string integ = scene.settings().integrator;
        auto row = [&](const char* what, double v, const char* unit, const std::string& ratio) {
            std::printf("| %s | %s | %.3f | %s | %s |\n", name.c_str(), what, v, unit,
                        ratio.c_str());
        };
        char buf[160];
        std::printf("| %s | scene load + BVH build | %.3f | s | - |\n", name.c_str(), load_s);
        row("raw Embree rtcIntersect1, camera+bounce rays", raw_i * 1e-6, "M rays/s", "1 (peer)");
        std::snprintf(buf, sizeof buf, "%.2f of raw", ren_i / raw_i);
        row("Scene::intersect (SurfaceHit), same rays", ren_i * 1e-6, "M rays/s", buf);
        std::snprintf(buf, sizeof buf, "%.2f x rtcIntersect1", pk_i / raw_i);
        row("raw Embree rtcIntersect8 packets, same rays", pk_i * 1e-6, "M rays/s", buf);
        row("raw Embree rtcOccluded1, shadow rays to lights", raw_o * 1e-6, "M rays/s", "1 (peer)");
        std::snprintf(buf, sizeof buf, "%.2f x rtcOccluded1", pk_o / raw_o);
        row("raw Embree rtcOccluded8 packets, same rays", pk_o * 1e-6, "M rays/s", buf);
        std::snprintf(buf, sizeof buf, "%.2f of raw", ren_o / raw_o);
        row("Scene::occluded, same rays", ren_o * 1e-6, "M rays/s", buf);
        std::snprintf(buf, sizeof buf, "kernel %s, %d spp", st_spec.kernel.name.c_str(),
                      render_spp);
        row((integ + ", specialised: paths").c_str(), paths_s * 1e-6, "M paths/s", buf);
        const auto [lo_spec, hi_spec] = spread(of_raw_spec);
        std::snprintf(buf, sizeof buf,
                      "%.2f of raw on the same ray mix (reps %.2f-%.2f; %.2f of raw packets; "
                      "%.2f rays+shadow/path)",
                      median(of_raw_spec), lo_spec, hi_spec, median(of_pk_spec),
                      double(st_spec.rays + st_spec.shadow_rays) / double(st_spec.paths));
        row((integ + ", specialised: rays (incl. shadow)").c_str(), rays_s * 1e-6, "M rays/s", buf);
        row((integ + ", general: paths").c_str(), paths_g * 1e-6, "M paths/s", "");
        const auto [lo_gen, hi_gen] = spread(of_raw_gen);
        std::snprintf(buf, sizeof buf,
                      "%.2f of raw on the same ray mix (reps %.2f-%.2f; %.2f of raw packets)",
                      median(of_raw_gen), lo_gen, hi_gen, median(of_pk_gen));
        row((integ + ", general: rays (incl. shadow)").c_str(), rays_g * 1e-6, "M rays/s", buf);
        std::snprintf(buf, sizeof buf, "specialised/general time %.3f (%.1f%% saved)", ts / tg,
                      100.0 * (1.0 - ts / tg));
        std::printf("| %s | render time specialised / general | %.4f / %.4f | s | %s |\n",
                    name.c_str(), ts, tg, buf);
        std::fflush(stdout);
        if (sink.load() == 0) std::printf("(no ray hit anything)\n");
    }
    return 0;
}
