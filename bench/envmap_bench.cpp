// Noise of an environment map with a small bright sun: the 16-sample estimate of the light a
// Lambertian surface reflects, Lo = (1/pi) * integral of L(w) cos+(w) dw (reflectance 1), by
//   - importance: the map's own sampling (Light::sample_li, environment_map.h),
//   - uniform: directions uniform over the sphere (pdf 1 / 4pi),
//   - cosine: directions cosine-weighted about the normal (the Lambert BSDF's own sampling,
//     all the constant environment gets),
//   - MIS: 16 map samples and 16 cosine samples, power heuristic (what the path integrator does
//     at a Lambertian vertex, one of each per sample).
// Variance of the 16-sample estimate over T trials; the table gives the medians over K runs
// (different seeds) and the variance ratio against importance sampling. Prints Markdown.
//
//   facet_envmap_bench [--trials T] [--runs K]
//
// Map: 512 x 256 texels of radiance 1 and a 2 x 2-texel sun at 1e4 (elevation ~40 degrees).
// Normals: up (+Z), facing the sun, and facing away from it (the sun below its horizon).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include <unistd.h>

#include "bench_stats.h"
#include "facet/frame.h"
#include "facet/render/image.h"
#include "facet/render/light.h"
#include "facet/render/scene.h"
#include "facet/sampling.h"

using namespace facet;
using namespace facet::render;
using facet::bench::median;

namespace {

struct Estimates {
    double importance, uniform, cosine, mis;
};

// Variance of each 16-sample estimator over `trials` trials.
Estimates variances(const Light& env, const Vec3& n, int trials, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> U(0.f, 1.f);
    auto u2 = [&] {
        return Vec2(std::min(U(rng), kOneMinusEpsilon), std::min(U(rng), kOneMinusEpsilon));
    };
    const Frame frame = Frame::from_z(n);
    constexpr int kSpp = 16;
    double s[4] = {0, 0, 0, 0}, s2[4] = {0, 0, 0, 0};
    for (int t = 0; t < trials; ++t) {
        double e[4] = {0, 0, 0, 0};
        for (int k = 0; k < kSpp; ++k) {
            // Importance (the map's sampler), and its MIS half.
            if (auto ls = env.sample_li({}, u2())) {
                const float c = glm::dot(ls->wi, n);
                if (c > 0.f) {
                    const double f = luminance(ls->li) * c * kInvPi / ls->pdf;
                    e[0] += f;
                    e[3] += f * power_heuristic(ls->pdf, cosine_hemisphere_pdf(c));
                }
            }
            // Uniform over the sphere.
            const Vec3 d = sample_uniform_sphere(u2());
            const float cu = glm::dot(d, n);
            if (cu > 0.f) e[1] += luminance(env.le_escape(d)) * cu * kInvPi / uniform_sphere_pdf();
            // Cosine-weighted about n (the BSDF sample), and its MIS half.
            const Vec3 local = sample_cosine_hemisphere(u2());
            const float pc = cosine_hemisphere_pdf(local.z);
            if (pc > 0.f) {
                const Vec3 w = frame.from_local(local);
                const double f = luminance(env.le_escape(w)) * local.z * kInvPi / pc;
                e[2] += f;
                e[3] += f * power_heuristic(pc, env.pdf_li({}, w, Vec3(0.f), Vec3(0.f)));
            }
        }
        for (int i = 0; i < 4; ++i) {
            const double v = e[i] / kSpp;
            s[i] += v;
            s2[i] += v * v;
        }
    }
    double var[4];
    for (int i = 0; i < 4; ++i) {
        const double m = s[i] / trials;
        var[i] = s2[i] / trials - m * m;
    }
    return {var[0], var[1], var[2], var[3]};
}

}  // namespace

int main(int argc, char** argv) {
    const auto [trials, runs] = facet::bench::trial_options(argc, argv);
    const int W = 512, H = 256, sx = 300, sy = 70;
    Image map(W, H);
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x)
            map.at(x, y) =
                (x == sx || x == sx + 1) && (y == sy || y == sy + 1) ? Rgb(1e4f) : Rgb(1.f);
    const std::string path = (std::filesystem::temp_directory_path() /
                              ("facet_envmap_bench_" + std::to_string(::getpid()) + ".exr"))
                                 .string();
    write_image(map, path);
    const Scene scene = load_scene_from_string(
        R"({"format": "facet-scene", "version": 1,
            "camera": {"position": [0, 0, 0], "look_at": [1, 0, 0], "up": [0, 0, 1], "fov": 40,
                       "width": 1, "height": 1},
            "lights": [{"type": "environment", "file": ")" +
            path + R"("}]})",
        "envmap_bench");
    std::filesystem::remove(path);
    const Light& env = *scene.environment();
    const Vec3 sun = env.map()->uv_to_direction({(sx + 1.f) / W, (sy + 1.f) / H});
    const struct {
        const char* name;
        Vec3 n;
    } normals[] = {
        {"up (+Z)", Vec3(0, 0, 1)}, {"facing the sun", sun}, {"facing away from the sun", -sun}};

    std::printf(
        "Environment map 512 x 256, background 1, 2 x 2-texel sun at 1e4 "
        "(%.1f%% of the texel sum); 16 samples per estimate, %d trials, medians of %d "
        "runs.\n\n",
        100.0 * 4e4 / (4e4 + W * H), trials, runs);
    std::printf(
        "| normal | variance: importance | uniform | cosine (BSDF) | MIS (16 + 16) | "
        "uniform / importance | cosine / importance |\n|---|---|---|---|---|---|---|\n");
    for (const auto& nn : normals) {
        std::vector<double> vi, vu, vc, vm, ru, rc;
        for (int r = 0; r < runs; ++r) {
            const Estimates e = variances(env, glm::normalize(nn.n), trials, 1234u + 77u * r);
            vi.push_back(e.importance);
            vu.push_back(e.uniform);
            vc.push_back(e.cosine);
            vm.push_back(e.mis);
            ru.push_back(e.uniform / e.importance);
            rc.push_back(e.cosine / e.importance);
        }
        std::printf("| %s | %.4g | %.4g | %.4g | %.4g | %.1f | %.1f |\n", nn.name, median(vi),
                    median(vu), median(vc), median(vm), median(ru), median(rc));
    }
    return 0;
}
