// Image comparison metrics for `facet diff`, the cross-checks and the benchmarks.
//
// Conventions:
//  - `a` is the test image, `b` the reference. Both are linear RGB (facet/render/image.h) of
//    the same size; a size mismatch throws std::invalid_argument with both sizes in the message.
//  - Metrics run over every channel of every pixel whose six values are all finite; pixels
//    with a NaN or infinity in either image are counted in `nonfinite_pixels`, excluded from the
//    averages and counted as outside the tolerance.
//  - rmse     = sqrt(mean (a - b)^2)
//  - rel_mse  = mean (a - b)^2 / (b^2 + kRelMseEpsilon)   (Rousselle et al. 2011 form; the
//               epsilon keeps black reference pixels from dominating)
//  - max_abs  = max |a - b|;  max_rel = max |a - b| / max(|b|, kRelFloor)
//  - a pixel is within tolerance when every channel has
//        |a - b| <= max(rel_tolerance * |b|, abs_tolerance).
#pragma once

#include <cstddef>

#include "facet/render/image.h"

namespace facet::render {

inline constexpr double kRelMseEpsilon = 1e-2;
// Reference values below this count as this for max_rel: relative error of near-black pixels
// is noise, not signal.
inline constexpr double kRelFloor = 1e-3;

struct DiffTolerance {
    double rel = 1e-2;  // relative tolerance per channel
    double abs = 0.0;   // absolute floor per channel
};

struct DiffStats {
    int width = 0, height = 0;
    double rmse = 0, rel_mse = 0, max_abs = 0, max_rel = 0;
    double mean_a = 0, mean_b = 0;  // mean over finite pixels and channels
    double fraction_within = 0;     // of all pixels
    std::size_t pixels_within = 0;
    std::size_t nonfinite_pixels = 0;
    int max_abs_x = -1, max_abs_y = -1;  // where max_abs occurs (-1 when images are empty)
};

// Throws std::invalid_argument on a size mismatch.
DiffStats diff_images(const Image& a, const Image& b, const DiffTolerance& tolerance);

// Error heat map: per pixel e = max over channels of |a - b| / max(rel*|b|, abs, tiny), i.e. the
// error in units of the tolerance, mapped through a perceptual ramp with e = 0 black, e = 1
// (exactly at the tolerance) mid-ramp green-yellow and e >= 2 white-hot; non-finite pixels are
// magenta. Returned as a linear image ready for write_image(..., ".png").
Image error_heatmap(const Image& a, const Image& b, const DiffTolerance& tolerance);

}  // namespace facet::render
