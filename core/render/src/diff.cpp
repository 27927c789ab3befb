// Image comparison metrics; definitions in facet/render/diff.h.
#include "facet/render/diff.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <string>

namespace facet::render {

namespace {

void check_sizes(const Image& a, const Image& b) {
    if (a.width() != b.width() || a.height() != b.height())
        throw std::invalid_argument("image sizes differ: " + std::to_string(a.width()) + "x" +
                                    std::to_string(a.height()) + " vs " +
                                    std::to_string(b.width()) + "x" + std::to_string(b.height()));
}

bool finite_pixel(const Rgb& a, const Rgb& b) {
    return is_finite(a) && is_finite(b);
}

// Error of one pixel in units of the tolerance (max over channels).
double tolerance_units(const Rgb& a, const Rgb& b, const DiffTolerance& t) {
    double e = 0;
    for (int c = 0; c < 3; ++c) {
        const double d = std::fabs(double(a[c]) - double(b[c]));
        const double allowed = std::max({t.rel * std::fabs(double(b[c])), t.abs, 1e-30});
        e = std::max(e, d / allowed);
    }
    return e;
}

}  // namespace

DiffStats diff_images(const Image& a, const Image& b, const DiffTolerance& tolerance) {
    check_sizes(a, b);
    DiffStats s;
    s.width = a.width();
    s.height = a.height();
    // Sums in double: a 4K image has 25M terms and float sums would lose digits.
    double sum_sq = 0, sum_rel = 0, sum_a = 0, sum_b = 0;
    std::size_t n_finite = 0;
    for (int y = 0; y < a.height(); ++y) {
        for (int x = 0; x < a.width(); ++x) {
            const Rgb& pa = a.at(x, y);
            const Rgb& pb = b.at(x, y);
            if (!finite_pixel(pa, pb)) {
                ++s.nonfinite_pixels;
                continue;
            }
            ++n_finite;
            bool within = true;
            for (int c = 0; c < 3; ++c) {
                const double va = pa[c], vb = pb[c];
                const double d = std::fabs(va - vb);
                sum_sq += d * d;
                sum_rel += d * d / (vb * vb + kRelMseEpsilon);
                sum_a += va;
                sum_b += vb;
                if (d > s.max_abs || s.max_abs_x < 0) {
                    s.max_abs = d;
                    s.max_abs_x = x;
                    s.max_abs_y = y;
                }
                s.max_rel = std::max(s.max_rel, d / std::max(std::fabs(vb), kRelFloor));
                if (d > std::max(tolerance.rel * std::fabs(vb), tolerance.abs)) within = false;
            }
            if (within) ++s.pixels_within;
        }
    }
    const double n = double(n_finite) * 3.0;
    if (n > 0) {
        s.rmse = std::sqrt(sum_sq / n);
        s.rel_mse = sum_rel / n;
        s.mean_a = sum_a / n;
        s.mean_b = sum_b / n;
    }
    const std::size_t total = std::size_t(a.width()) * std::size_t(a.height());
    s.fraction_within = total > 0 ? double(s.pixels_within) / double(total) : 1.0;
    return s;
}

Image error_heatmap(const Image& a, const Image& b, const DiffTolerance& tolerance) {
    check_sizes(a, b);
    // Ramp stops in sRGB (black -> blue -> green-yellow at the tolerance -> red -> white), taken
    // at t = e / 2; interpolated in sRGB and decoded so the PNG shows exactly these colours.
    static constexpr std::array<std::array<float, 3>, 5> kStops = {{{0.f, 0.f, 0.f},
                                                                    {0.1f, 0.2f, 0.7f},
                                                                    {0.6f, 0.85f, 0.1f},
                                                                    {0.9f, 0.1f, 0.05f},
                                                                    {1.f, 1.f, 1.f}}};
    Image out(a.width(), a.height());
    for (int y = 0; y < a.height(); ++y) {
        for (int x = 0; x < a.width(); ++x) {
            const Rgb& pa = a.at(x, y);
            const Rgb& pb = b.at(x, y);
            Rgb srgb;
            if (!finite_pixel(pa, pb)) {
                srgb = Rgb(1.f, 0.f, 1.f);
            } else {
                const float t = float(std::min(tolerance_units(pa, pb, tolerance) / 2.0, 1.0));
                const float pos = t * float(kStops.size() - 1);
                const int i = std::min(int(pos), int(kStops.size()) - 2);
                const float f = pos - float(i);
                for (int c = 0; c < 3; ++c)
                    srgb[c] = kStops[i][c] + f * (kStops[i + 1][c] - kStops[i][c]);
            }
            for (int c = 0; c < 3; ++c) out.at(x, y)[c] = srgb_decode(srgb[c]);
        }
    }
    return out;
}

}  // namespace facet::render
