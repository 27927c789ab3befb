// The session's overhead at its smallest pass size, without Python: a RenderSession of 1-spp
// passes with an empty C++ callback against render() (one session, no callback: passes of
// kMaxPassSpp samples) on the same scene, alternating. bench/python_bench.py measures the same
// with a Python callback; the difference between the two is the binding's share.
// Usage: facet_session_bench [--reps 5] [--spp N] [scene.json] (default: the Cornell box).
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "facet/render/render.h"
#include "facet/render/scene.h"

using namespace facet::render;

namespace {

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
}

}  // namespace

int main(int argc, char** argv) {
    int reps = 5, spp = 0;
    std::string path = std::string(FACET_SCENES_DIR) + "/cornell_box.json";
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "--reps" && i + 1 < argc) reps = std::max(1, std::atoi(argv[++i]));
        else if (a == "--spp" && i + 1 < argc) spp = std::atoi(argv[++i]);
        else path = a;
    }
    const Scene scene = load_scene(path);
    RenderOptions plain;
    plain.spp = spp;
    RenderOptions fine = plain;
    fine.pass_seconds = 1e-9;  // every pass 1 spp
    std::vector<double> one, passes;
    int npasses = 0;
    for (int r = 0; r < reps; ++r) {
        RenderSession a(scene, plain);
        a.render();
        one.push_back(a.stats().seconds);
        RenderSession b(scene, fine);
        b.render([](const PassInfo&) { return true; });
        passes.push_back(b.stats().seconds);
        npasses = b.stats().passes;
    }
    const double m1 = median(one), mp = median(passes);
    std::printf("%s, medians of %d alternating runs (sample-loop seconds)\n", path.c_str(), reps);
    std::printf("  %-44s %8.3f s  1.000\n", "render() (no callback)", m1);
    std::printf("  %-44s %8.3f s  %.3f\n",
                ("session, 1-spp passes (" + std::to_string(npasses) + ", C++ callback)").c_str(),
                mp, mp / m1);
    return 0;
}
