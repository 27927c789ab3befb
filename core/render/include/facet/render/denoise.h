// A denoiser that needs no trained weights: feature-guided non-local means on two
// half-buffers, with a per-pixel choice between filter strengths by an unbiased error estimate
// (Rousselle, Manzi & Zwicker 2013, "Robust denoising using feature and color information";
// the half-buffer cross-validation of Bitterli et al. 2016, "Nonlinearly weighted first-order
// regression for denoising Monte Carlo renderings").
//
// Conventions:
//  - Inputs are linear RGB images of one size W x H (Image: top row first):
//      half_a, half_b  two independent estimates of the beauty, each the mean of one half of a
//                      pixel's samples (a render's sample ranges [0, n/2) and [n/2, n));
//    or instead of the halves
//      color, variance the beauty (the mean of all of a pixel's samples) and the variance of
//                      that mean per channel (the samples' variance / their count);
//      albedo, normal, depth  the first-hit features of render_aovs (aov.h);
//      albedo_variance, normal_variance, depth_variance  optional: the variance of each
//                      feature's mean per channel (depth in .r), where the features are noisy
//                      (depth of field, motion blur, glossy or rough first hits); a missing one
//                      is treated as 0 (a noise-free feature).
//    Every value must be finite (depth may be kMissDepth where no surface is hit), every
//    variance >= 0.
//  - Output: the denoised estimate of (half_a + half_b) / 2, or of color. It is not an unbiased
//  estimate:
//    a pixel becomes a weighted mean of its neighbours, so detail that no feature shows
//    (shadow edges, caustics, glossy reflections of small objects) can blur.
//  - Method, per half X with the other half Y (both divided by the albedo where it exceeds
//    kMinAlbedo and, given normal_variance or depth_variance, where both are 0 (denoise.cpp),
//    so that texture detail is not filtered and is multiplied back at the end, and the noisy
//    albedo of a pixel whose samples hit different normals or depths is not):
//      V(p)        the variance of one half's value, (X - Y)^2 / 2 averaged over channels and
//                  over a 3 x 3 box;
//      d(p, q)     = mean over channels of ((X_p - X_q)^2 - (V_p + min(V_p, V_q))) /
//                    (kEpsilon + V_p + min(V_p, V_q)), averaged over 3 x 3 patches around p
//                  and q (a bright outlier q, of large V_q, does not pass for p's neighbour)
//                  (non-local means with variance cancellation, Rousselle et al. 2012);
//      f(p, q)     = |a_p - a_q|^2 / s_a^2 + |n_p - n_q|^2 / s_n^2 + r^2 / (s_u u_p)^2 over
//                  albedo a, normal n and inverse depth u = 1 / z, with r = u_q - u_p - (du/dx,
//                  du/dy) . (q - p) the miss of u's first-order prediction (0 on a plane);
//                  bandwidths in denoise.cpp. With feature variances W (summed over
//                  channels; for u, Var(z) / z^4) each term becomes
//                  max(0, D^2 - (W_p + min(W_p, W_q))) / (s^2 + W_p): the difference noise
//                  explains is cancelled and a noisy feature's bandwidth widens;
//      w_k(p, q)   = min(exp(-max(0, d) / k^2), exp(-f)) over the (2 radius + 1)^2 window;
//      F_k(p)      the value at p of the plane c + a dx + b dy fitted to the neighbours' X_q
//                  by least squares with weights w_k (first-order regression in screen space,
//                  as NFOR fits in feature space: it follows lighting gradients without the
//                  bias of a weighted mean), for the strengths k of kStrengths (denoise.cpp);
//      E_k(p)      = (F_k(p) - Y_p)^2, which estimates F_k's squared error up to the same
//                  constant Var(Y_p) for every k (Y is independent of X), averaged over a
//                  (2 kErrorRadius + 1)^2 box.
//    Each pixel keeps the F_k of least E_k; the output is the mean of the two halves' choices,
//    times the albedo divided out.
//    With color and variance there is one image X (colour / albedo), V is the variance input
//    (divided by the albedo squared, averaged over channels and over a 3 x 3 box), and E_k is
//    Stein's unbiased risk estimate (F_k(p) - X_p)^2 + 2 Var(X_p) dF_k(p)/dX_p, with the
//    derivative the fit's weight on the pixel's own value (the weights held fixed). Two
//    halves give the better estimate: their E_k needs no derivative.
//  - Deterministic: every output pixel is a fixed function of the inputs, whatever the thread
//    count. Working memory: the planar copies of the inputs, the candidates F_k and their
//    errors, about 150 bytes per pixel, plus per thread the scratch of one tile of
//    kBandRows x kTileCols pixels (denoise.cpp), about 350 bytes per pixel of the tile.
#pragma once

#include "facet/render/aov.h"
#include "facet/render/image.h"
#include "facet/render/render.h"

namespace facet::render {

struct DenoiseOptions {
    int radius = 4;   // search window (2 radius + 1)^2, 1..20
    int threads = 0;  // 0 = every hardware thread
    // denoise_halves and render_denoised: pass the renderer's feature variances (aov.h) to
    // denoise(). false treats the features as noise free (for comparisons).
    bool feature_variances = true;
};

struct DenoiseInput {
    const Image* half_a = nullptr;
    const Image* half_b = nullptr;
    const Image* albedo = nullptr;
    const Image* normal = nullptr;
    const Image* depth = nullptr;
    // Instead of half_a and half_b (conventions).
    const Image* color = nullptr;
    const Image* variance = nullptr;
    // Optional (null: noise free).
    const Image* albedo_variance = nullptr;
    const Image* normal_variance = nullptr;
    const Image* depth_variance = nullptr;
};

// The denoised beauty (conventions). Throws std::invalid_argument naming the argument for a
// missing (null or empty) input, both or neither of the halves and color/variance, a size
// that differs from half_a's (color's), a non-finite value or negative variance (with its
// pixel) or a radius outside 1..20.
Image denoise(const DenoiseInput& input, const DenoiseOptions& options = {});

// A render and its denoised image, as `facet render --denoise`, Python's
// render(denoise=True) and facet-farm use it.
struct DenoisedRender {
    Image image;        // denoised
    Image raw;          // the plain render: bit for bit the image of one render of `options`
    Aovs features;      // albedo, normal, depth at the render's spp and seed, and their
                        // variances (with DenoiseOptions::feature_variances)
    RenderStats stats;  // of both halves together
};
// The last step of render_denoised for front ends that rendered the two half-buffers themselves
// (Blender's two sessions, facet-farm's merged halves): the features of `scene` at `spp` and
// `seed` (render_aovs on `options.threads`), with their variances unless
// options.feature_variances is false, and the denoised image. Throws as denoise().
struct DenoisedHalves {
    Image image;
    Aovs features;
};
DenoisedHalves denoise_halves(const Scene& scene, const Image& half_a, const Image& half_b, int spp,
                              std::uint64_t seed, const DenoiseOptions& options = {});

// Renders `options` as two sessions over the sample ranges [0, n/2) and [n/2, n) of its n
// samples per pixel (the half-buffers), the features, and denoises. The whole image at a fixed
// sample count only: throws std::invalid_argument starting "denoise: " for a time budget, a
// region, a sample range or fewer than 2 samples per pixel (a denoiser is not split-invariant:
// parts are merged first and the merged halves denoised).
DenoisedRender render_denoised(const Scene& scene, const RenderOptions& options,
                               const DenoiseOptions& denoise_options = {});

}  // namespace facet::render
