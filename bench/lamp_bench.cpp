// Noise of Blender's area lamps (the "area" kind, light.h "Area lamps"): the 16-sample estimate
// of the irradiance on a surface facing a lamp, by the lamp's own sampling (Light::sample_li: by
// solid angle, light.h) against uniform sampling by area (pdf r^2 / (A cos_l)). Lamps of size
// 1 x 1 (rectangle, and the disc of diameter 1) emitting down, radiance 1; receivers at height
// h below their centre, on the axis and offset by 0.75 (outside the lamp's footprint). Variance
// over T trials, medians of K runs (different seeds), and the ratio area / solid angle.
// Prints Markdown.
//
//   facet_lamp_bench [--trials T] [--runs K]
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "bench_stats.h"
#include "facet/render/light.h"
#include "facet/sampling.h"

using namespace facet;
using namespace facet::render;
using facet::bench::median;

namespace {

struct Variances {
    double lamp, area, mean;
};

// Variances of the two 16-sample irradiance estimators at p (normal +y) over `trials` trials.
Variances variances(const Light& lamp, bool disc, const Vec3& p, int trials, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> U(0.f, 1.f);
    auto u2 = [&] {
        return Vec2(std::min(U(rng), kOneMinusEpsilon), std::min(U(rng), kOneMinusEpsilon));
    };
    constexpr int kSpp = 16;
    const LightSampleContext ctx{p, {0, 1, 0}};
    const Vec3 c = lamp.position();
    double s[2] = {0, 0}, s2[2] = {0, 0};
    for (int t = 0; t < trials; ++t) {
        double e[2] = {0, 0};
        for (int k = 0; k < kSpp; ++k) {
            if (auto ls = lamp.sample_li(ctx, u2())) {
                const float cs = ls->wi.y;
                if (cs > 0.f) e[0] += double(ls->li.r) * cs / ls->pdf;
            }
            // Uniform by area: a point of the lamp (plane y = c.y, normal -y).
            const Vec2 u = u2();
            Vec3 q;
            if (disc) {
                const Vec2 d = sample_uniform_disk_concentric(u);
                q = c + Vec3(0.5f * d.x, 0.f, 0.5f * d.y);
            } else {
                q = c + Vec3(u.x - 0.5f, 0.f, u.y - 0.5f);
            }
            const Vec3 v = q - p;
            const float r2 = glm::dot(v, v), r = std::sqrt(r2);
            const float cos_r = v.y / r;  // receiver and lamp cosines are equal (parallel)
            const float area = disc ? 0.25f * kPi : 1.f;
            if (cos_r > 0.f) e[1] += double(lamp.emission().r) * cos_r * cos_r * area / r2;
        }
        for (int i = 0; i < 2; ++i) {
            const double v = e[i] / kSpp;
            s[i] += v;
            s2[i] += v * v;
        }
    }
    double var[2], mean = s[0] / trials;
    for (int i = 0; i < 2; ++i) {
        const double m = s[i] / trials;
        var[i] = s2[i] / trials - m * m;
    }
    return {var[0], var[1], mean};
}

}  // namespace

int main(int argc, char** argv) {
    const auto [trials, runs] = facet::bench::trial_options(argc, argv);
    std::printf(
        "Area lamps 1 x 1 (disc: diameter 1), radiance 1, emitting down; irradiance on a "
        "surface facing up at height h below the centre, offset x; 16 samples per estimate, %d "
        "trials, medians of %d runs.\n\n",
        trials, runs);
    std::printf(
        "| lamp | h | offset | E | variance: lamp sampling | by area | area / lamp |\n"
        "|---|---|---|---|---|---|---|\n");
    for (const bool disc : {false, true}) {
        for (const double h : {0.05, 0.2, 0.35, 0.5, 1.0, 3.0}) {
            // Lamp centre at (0, h, 0); e1 along x, e2 along z with cross(e1, e2) = -y.
            const Light lamp = Light::area_lamp({0.f, float(h), 0.f}, {0.5f, 0.f, 0.f},
                                                {0.f, 0.f, 0.5f}, Rgb(1.f), disc);
            for (const float off : {0.f, 0.75f}) {
                std::vector<double> vl, va, ratio, mean;
                for (int r = 0; r < runs; ++r) {
                    const Variances v =
                        variances(lamp, disc, {off, 0.f, 0.f}, trials, 99u + 31u * r);
                    vl.push_back(v.lamp);
                    va.push_back(v.area);
                    ratio.push_back(v.area / v.lamp);
                    mean.push_back(v.mean);
                }
                std::printf("| %s | %.2f | %.2f | %.4g | %.3g | %.3g | %.2f |\n",
                            disc ? "disc" : "square", h, off, median(mean), median(vl), median(va),
                            median(ratio));
            }
        }
    }
    return 0;
}
