// The renderer as a library (issue 9), measured in one run. Prints a table of medians and
// same-run ratios.
//
//   facet_library_bench [--reps R] [--threads N] [--only K]   (K in 1, 1b, 2, 3)
//
//  1. Session overhead: the Cornell box rendered by one render() call (passes of at most
//     kMaxPassSpp samples) against a RenderSession forced to its smallest pass (1 sample per
//     pass, a no-op callback after each), same scene, same spp, alternating repetitions; the
//     ratio is the median of per-repetition ratios. Both give the same image bit for bit.
//     Process CPU time (all threads) is reported beside wall time: on a shared machine other
//     tenants' load stretches wall time run by run, CPU time much less.
//     1b: the same on one 16x16 tile (minima of 9), giving the cost a pass adds beyond its
//     samples, which whole-image timings on a loaded machine cannot resolve.
//  2. Cancellation latency at 1920x1080 (Cornell box): cancel() from another thread after a
//     varying delay; the time from cancel() to render() returning, median and maximum, for a
//     plain render (no callback) and a watched one (callback, pass_seconds 0.25).
//  3. build_scene of a 1M-triangle mesh given as flat arrays (a displaced 708 x 708 grid,
//     1,002,528 triangles): time before the BVH build (validation, transforms, copies) and the
//     BVH build itself (Embree, RTC_BUILD_QUALITY_HIGH).
#include <time.h>
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <thread>
#include <vector>

#include "facet/render/render.h"
#include "facet/render/scene_description.h"

namespace fr = facet::render;
using Clock = std::chrono::steady_clock;

namespace {

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    const std::size_t n = v.size();
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

double seconds_since(Clock::time_point t) {
    return std::chrono::duration<double>(Clock::now() - t).count();
}

// CPU seconds used by this process so far (every thread).
double cpu_seconds() {
    timespec ts{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

}  // namespace

int main(int argc, char** argv) {
    int reps = 5, threads = 0;
    std::string only;
    for (int i = 1; i < argc; ++i) {
        if (!std::strcmp(argv[i], "--reps") && i + 1 < argc) {
            reps = std::atoi(argv[++i]);
        } else if (!std::strcmp(argv[i], "--threads") && i + 1 < argc) {
            threads = std::atoi(argv[++i]);
        } else if (!std::strcmp(argv[i], "--only") && i + 1 < argc) {
            only = argv[++i];
        } else {
            std::fprintf(stderr,
                         "usage: facet_library_bench [--reps R] [--threads N] [--only K]\n");
            return 2;
        }
    }
    const std::string cornell = std::string(FACET_SCENES_DIR) + "/cornell_box.json";

    const auto want = [&](const char* k) { return only.empty() || only == k; };

    // 1. Session overhead at the smallest pass size.
    if (want("1")) {
        const fr::Scene scene = fr::load_scene(cornell);
        fr::RenderOptions o;
        o.spp = 32;
        o.threads = threads;
        std::vector<double> plain, watched, ratio, plain_cpu, watched_cpu, cpu_ratio;
        int passes = 0;
        for (int r = 0; r < reps; ++r) {
            auto t = Clock::now();
            double c = cpu_seconds();
            const fr::Image a = fr::render(scene, o);
            plain.push_back(seconds_since(t));
            plain_cpu.push_back(cpu_seconds() - c);
            fr::RenderOptions w = o;
            w.pass_seconds = 1e-9;  // every pass is 1 sample
            fr::RenderSession session(scene, w);
            t = Clock::now();
            c = cpu_seconds();
            session.render([](const fr::PassInfo&) { return true; });
            watched.push_back(seconds_since(t));
            watched_cpu.push_back(cpu_seconds() - c);
            passes = session.stats().passes;
            ratio.push_back(watched.back() / plain.back());
            cpu_ratio.push_back(watched_cpu.back() / plain_cpu.back());
            if (std::memcmp(a.pixels().data(), session.image().pixels().data(),
                            a.pixels().size() * sizeof(facet::Rgb)) != 0) {
                std::fprintf(stderr, "session image differs from render()'s\n");
                return 1;
            }
        }
        const auto range = [](const std::vector<double>& v) {
            return std::make_pair(*std::min_element(v.begin(), v.end()),
                                  *std::max_element(v.begin(), v.end()));
        };
        std::printf("1. session overhead, Cornell box 512x512, 32 spp, %d reps\n", reps);
        std::printf("   %-36s %10s %10s\n", "", "median s", "median CPU s");
        std::printf("   %-36s %10.3f %10.3f\n", "render() (passes of <= 16 spp)", median(plain),
                    median(plain_cpu));
        std::printf("   %-36s %10.3f %10.3f\n",
                    ("session, " + std::to_string(passes) + " passes of 1 spp").c_str(),
                    median(watched), median(watched_cpu));
        std::printf(
            "   session / render(), wall: median per-rep ratio %.4f (range %.4f-%.4f), "
            "ratio of medians %.4f\n",
            median(ratio), range(ratio).first, range(ratio).second,
            median(watched) / median(plain));
        std::printf(
            "   session / render(), CPU:  median per-rep ratio %.4f (range %.4f-%.4f), "
            "ratio of medians %.4f\n\n",
            median(cpu_ratio), range(cpu_ratio).first, range(cpu_ratio).second,
            median(watched_cpu) / median(plain_cpu));
    }

    // 1b. The same on one tile, where a pass is short: the cost a pass adds beyond its samples,
    // from minima over repetitions (robust to other load on the machine, unlike whole renders).
    if (want("1b")) {
        const fr::Scene scene = fr::load_scene(cornell);
        fr::RenderOptions o;
        o.spp = 512;
        o.threads = threads;
        o.region = fr::Region{240, 240, 256, 256};
        double plain = 1e30, watched = 1e30;
        int passes_plain = 0, passes_watched = 0;
        for (int r = 0; r < 9; ++r) {
            fr::RenderSession a(scene, o);
            auto t = Clock::now();
            a.render();
            plain = std::min(plain, seconds_since(t));
            passes_plain = a.stats().passes;
            fr::RenderOptions w = o;
            w.pass_seconds = 1e-9;
            fr::RenderSession b(scene, w);
            t = Clock::now();
            b.render([](const fr::PassInfo&) { return true; });
            watched = std::min(watched, seconds_since(t));
            passes_watched = b.stats().passes;
        }
        std::printf("1b. one 16x16 tile of the Cornell box, 512 spp, minima of 9 reps\n");
        std::printf("   render() %d passes: %.2f ms; session %d passes of 1 spp: %.2f ms\n",
                    passes_plain, plain * 1e3, passes_watched, watched * 1e3);
        std::printf("   cost of a pass beyond its samples: %.1f us\n\n",
                    (watched - plain) / double(passes_watched - passes_plain) * 1e6);
    }

    // 2. Cancellation latency at 1920x1080.
    if (want("2")) {
        fr::SceneDescription d = fr::read_scene_description(cornell);
        d.camera.width = 1920;
        d.camera.height = 1080;
        const fr::Scene scene = fr::build_scene(d, "cornell 1080p");
        std::printf(
            "2. cancellation latency, Cornell box 1920x1080 (cancel() -> render() returns)\n");
        std::printf("   %-28s %12s %12s %8s\n", "", "median ms", "max ms", "trials");
        for (int watched = 0; watched < 2; ++watched) {
            std::vector<double> lat;
            for (int r = 0; r < std::max(reps, 5); ++r) {
                fr::RenderOptions o;
                o.spp = 4096;
                o.threads = threads;
                fr::RenderSession session(scene, o);
                Clock::time_point cancelled_at;
                std::thread canceller([&] {
                    std::this_thread::sleep_for(std::chrono::milliseconds(150 + 97 * r));
                    cancelled_at = Clock::now();
                    session.cancel();
                });
                if (watched)
                    session.render([](const fr::PassInfo&) { return true; });
                else
                    session.render();
                const auto returned = Clock::now();
                canceller.join();
                lat.push_back(std::chrono::duration<double>(returned - cancelled_at).count() * 1e3);
            }
            std::printf("   %-28s %12.2f %12.2f %8zu\n",
                        watched ? "watched (callback)" : "plain render()", median(lat),
                        *std::max_element(lat.begin(), lat.end()), lat.size());
        }
        std::printf("\n");
    }

    // 3. build_scene of a 1M-triangle mesh from arrays.
    if (want("3")) {
        const int n = 708;
        std::vector<float> pos;
        std::vector<std::uint32_t> idx;
        pos.reserve(std::size_t(n + 1) * (n + 1) * 3);
        for (int j = 0; j <= n; ++j) {
            for (int i = 0; i <= n; ++i) {
                const float x = -1.f + 2.f * float(i) / n, y = -1.f + 2.f * float(j) / n;
                pos.insert(pos.end(), {x, 0.05f * std::sin(9.f * x) * std::sin(9.f * y), y});
            }
        }
        for (int j = 0; j < n; ++j) {
            for (int i = 0; i < n; ++i) {
                const std::uint32_t a = std::uint32_t(j * (n + 1) + i), b = a + 1,
                                    c = a + std::uint32_t(n + 1), e = c + 1;
                idx.insert(idx.end(), {a, c, b, b, c, e});
            }
        }
        fr::SceneDescription d;
        d.camera.position = {0.f, 2.f, 3.f};
        d.camera.look_at = {0.f, 0.f, 0.f};
        d.camera.up = {0.f, 1.f, 0.f};
        d.camera.fov = 40.0;
        d.camera.width = d.camera.height = 64;
        d.materials.push_back({"white", {"lambert", {}, {}}});
        fr::ShapeDesc s;
        s.kind = fr::ShapeKind::Mesh;
        s.material_ref = "white";
        s.mesh = fr::MeshData{pos, idx, {}, nullptr, {}};
        d.shapes.push_back(s);
        fr::LightDesc l;
        l.position = {0.f, 3.f, 0.f};
        l.power = facet::Rgb(100.f);
        d.lights.push_back(l);
        std::vector<double> before, bvh;
        for (int r = 0; r < std::max(3, reps / 2); ++r) {
            fr::BuildReport rep;
            const fr::Scene sc = fr::build_scene(d, "grid", {}, &rep);
            before.push_back(rep.seconds_before_bvh);
            bvh.push_back(rep.seconds_bvh);
        }
        std::printf("3. build_scene, %zu triangles from flat arrays, %zu reps\n", idx.size() / 3,
                    before.size());
        std::printf(
            "   before the BVH (validate, transform, copy): median %.4f s (target <= 0.1)\n",
            median(before));
        std::printf("   Embree buffers + BVH build:                median %.4f s\n", median(bvh));
    }
    return 0;
}
