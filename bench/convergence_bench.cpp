// Time to error of the renderer's sampling: RMSE against a converged reference as a function of
// samples per pixel, for the renderer's Owen-scrambled Sobol samples and for independent
// uniform samples (the peer), on the same scene in the same run. Prints a table.
//
//   facet_convergence_bench [--threads N] [--res R] [--ref-spp S] [--max-spp M] [--seeds K]
//                           [scene.json ...]
//
// The peer is the renderer itself with RenderOptions::independent_samples (independent uniform
// samples, same kernel, same number of draws): same cost per sample, so "independent needs X
// times the samples for Sobol's error" is X times the render time; the table also gives the
// measured time per sample of both (medians over seeds).
//
// Error. MSE is averaged over K seeds per (sampler, spp) and taken against a Sobol reference of
// S samples with its own seed; the reference's own noise adds about MSE(1 spp) / S to every
// row, which the table subtracts (estimated from the independent 2-spp MSE, an upper bound for
// the Sobol reference). Rows start at 2 spp: with spp = 1 both samplers shoot through pixel
// centres (integrator.h). The resolution is overridden to R x R to keep the reference short.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "facet/render/diff.h"
#include "facet/render/render.h"
#include "facet/render/scene.h"

#ifndef FACET_SCENES_DIR
#define FACET_SCENES_DIR "scenes"
#endif

namespace fr = facet::render;

namespace {

struct Options {
    int threads = 2, res = 64, ref_spp = 4096, max_spp = 64, seeds = 4;
    std::vector<std::string> scenes;
};

int parse_int(const char* flag, const char* value, int lo) {
    char* end = nullptr;
    long v = value ? std::strtol(value, &end, 10) : 0;
    if (!value || *end != '\0' || v < lo || v > (1 << 24)) {
        std::fprintf(stderr, "facet_convergence_bench: %s needs an integer >= %d, got '%s'\n", flag,
                     lo, value ? value : "");
        std::exit(2);
    }
    return int(v);
}

// The scene with its resolution overridden to res x res.
fr::Scene load_resized(const std::string& path, int res) {
    std::ifstream in(path);
    if (!in) throw std::runtime_error(path + ": cannot open");
    std::stringstream text;
    text << in.rdbuf();
    nlohmann::json j = nlohmann::json::parse(text.str());
    j["camera"]["width"] = res;
    j["camera"]["height"] = res;
    const std::string dir = path.find('/') == std::string::npos
                                ? std::string(".")
                                : path.substr(0, path.find_last_of('/'));
    return fr::load_scene_from_string(j.dump(), path, dir);
}

double mse(const fr::Image& a, const fr::Image& b) {
    const double r = fr::diff_images(a, b, {}).rmse;
    return r * r;
}

fr::Image render(const fr::Scene& scene, int spp, std::uint64_t seed, int threads, bool independent,
                 double* seconds) {
    fr::RenderOptions o;
    o.spp = spp;
    o.seed = seed;
    o.threads = threads;
    o.time_budget_s = 0.0;
    o.independent_samples = independent;
    fr::RenderStats st;
    fr::Image img = fr::render(scene, o, &st);
    if (seconds) *seconds = st.seconds;
    return img;
}

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    const size_t n = v.size();
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

void run_scene(const std::string& path, const Options& opt) {
    const fr::Scene scene = load_resized(path, opt.res);
    const std::string name = path.substr(path.find_last_of('/') + 1);
    double ref_s = 0.0;
    const fr::Image ref = render(scene, opt.ref_spp, 0x5eed5eedull, opt.threads, false, &ref_s);

    std::vector<int> spps;  // 2, 4, ... <= max_spp (1 spp means pixel centres: not a sampler test)
    for (int s = 2; s <= std::max(opt.max_spp, 2); s *= 2) spps.push_back(s);
    std::vector<double> acc[2], tps[2];  // [independent, sobol]: summed MSE, time per sample
    for (int m = 0; m < 2; ++m) {
        acc[m].assign(spps.size(), 0.0);
        tps[m].assign(spps.size(), 0.0);
        for (size_t i = 0; i < spps.size(); ++i) {
            std::vector<double> t;
            for (int k = 0; k < opt.seeds; ++k) {
                double s = 0.0;
                const fr::Image img =
                    render(scene, spps[i], 7919ull * std::uint64_t(k + 1), opt.threads, m == 0, &s);
                acc[m][i] += mse(img, ref);
                t.push_back(s / double(spps[i]));
            }
            tps[m][i] = median(t);
        }
    }
    const std::vector<double>& acc_ind = acc[0];
    const std::vector<double>& acc_sobol = acc[1];
    const double ref_noise = acc_ind[0] / opt.seeds * double(spps[0]) / double(opt.ref_spp);

    std::printf("\n%s: %dx%d, reference %d spp (%.1f s), %d seeds per row, %d threads\n",
                name.c_str(), opt.res, opt.res, opt.ref_spp, ref_s, opt.seeds, opt.threads);
    std::printf(
        "| spp | RMSE independent (peer) | RMSE Sobol | MSE ratio indep/Sobol | ms per spp |\n");
    std::printf("|---:|---:|---:|---:|---:|\n");
    std::vector<double> m_ind(spps.size()), m_sob(spps.size());
    for (size_t i = 0; i < spps.size(); ++i) {
        m_ind[i] = std::max(acc_ind[i] / opt.seeds - ref_noise, 1e-30);
        m_sob[i] = std::max(acc_sobol[i] / opt.seeds - ref_noise, 1e-30);
        std::printf("| %d | %.4g | %.4g | %.2f | %.2f / %.2f |\n", spps[i], std::sqrt(m_ind[i]),
                    std::sqrt(m_sob[i]), m_ind[i] / m_sob[i], 1e3 * tps[0][i], 1e3 * tps[1][i]);
    }
    // Convergence rates: least-squares slope of log MSE against log spp.
    auto slope = [&](const std::vector<double>& m) {
        double sx = 0, sy = 0, sxx = 0, sxy = 0, n = double(m.size());
        for (size_t i = 0; i < m.size(); ++i) {
            double x = std::log(double(spps[i])), y = std::log(m[i]);
            sx += x, sy += y, sxx += x * x, sxy += x * y;
        }
        return (n * sxy - sx * sy) / (n * sxx - sx * sx);
    };
    // Time to error at the largest spp: independent samples needed for Sobol's MSE, by the
    // peer's fitted rate (MSE ~ spp^slope) from its largest-spp point.
    const double s_ind = slope(m_ind), s_sob = slope(m_sob);
    const double need = double(spps.back()) * std::pow(m_sob.back() / m_ind.back(), 1.0 / s_ind);
    std::printf(
        "MSE ~ spp^%.2f (independent), spp^%.2f (Sobol); at %d spp Sobol's error needs "
        "%.0f independent spp: %.2fx the render time\n",
        s_ind, s_sob, spps.back(), need, need / double(spps.back()));
}

}  // namespace

int main(int argc, char** argv) {
    Options opt;
    for (int i = 1; i < argc; ++i) {
        const char* a = argv[i];
        const char* v = i + 1 < argc ? argv[i + 1] : nullptr;
        if (!std::strcmp(a, "--threads"))
            opt.threads = parse_int(a, v, 1), ++i;
        else if (!std::strcmp(a, "--res"))
            opt.res = parse_int(a, v, 1), ++i;
        else if (!std::strcmp(a, "--ref-spp"))
            opt.ref_spp = parse_int(a, v, 1), ++i;
        else if (!std::strcmp(a, "--max-spp"))
            opt.max_spp = parse_int(a, v, 1), ++i;
        else if (!std::strcmp(a, "--seeds"))
            opt.seeds = parse_int(a, v, 1), ++i;
        else if (!std::strcmp(a, "--help") || !std::strcmp(a, "-h")) {
            std::printf(
                "facet_convergence_bench [--threads N] [--res R] [--ref-spp S] "
                "[--max-spp M] [--seeds K] [scene.json ...]\n");
            return 0;
        } else if (a[0] == '-') {
            std::fprintf(stderr, "facet_convergence_bench: unknown option '%s' (see --help)\n", a);
            return 2;
        } else {
            opt.scenes.push_back(a);
        }
    }
    if (opt.scenes.empty()) opt.scenes = {std::string(FACET_SCENES_DIR) + "/cornell_box.json"};
    try {
        for (const auto& s : opt.scenes) run_scene(s, opt);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "facet_convergence_bench: %s\n", e.what());
        return 1;
    }
    return 0;
}
