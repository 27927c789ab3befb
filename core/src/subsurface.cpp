// Random-walk subsurface scattering: the coefficients of Cycles 3.4 (facet/subsurface.h).
#include "facet/subsurface.h"

#include <algorithm>

namespace facet {

float subsurface_single_scattering_albedo(float albedo, float g) {
    // The fit of subsurface_random_walk_remap: alpha = (1 - b) A' atan(B' A)^C' + b D'
    // atan(E' A)^F', b = A^(1/4), each coefficient a polynomial (or an exponential of one) in g
    // of degree 7 (Wrenninge et al.'s extension of Chiang et al. 2016 to anisotropy).
    const float g2 = g * g, g3 = g2 * g, g4 = g3 * g, g5 = g4 * g, g6 = g5 * g, g7 = g6 * g;
    const float a = 1.8260523782f + -1.28451056436f * g + -1.79904629312f * g2 +
                    9.19393289202f * g3 + -22.8215585862f * g4 + 32.0234874259f * g5 +
                    -23.6264803333f * g6 + 7.21067002658f * g7;
    const float b =
        4.98511194385f +
        0.127355959438f * std::exp(31.1491581433f * g + -201.847017512f * g2 + 841.576016723f * g3 +
                                   -2018.09288505f * g4 + 2731.71560286f * g5 +
                                   -1935.41424244f * g6 + 559.009054474f * g7);
    const float c = 1.09686102424f + -0.394704063468f * g + 1.05258115941f * g2 +
                    -8.83963712726f * g3 + 28.8643230661f * g4 + -46.8802913581f * g5 +
                    38.5402837518f * g6 + -12.7181042538f * g7;
    const float d = 0.496310210422f + 0.360146581622f * g + -2.15139309747f * g2 +
                    17.8896899217f * g3 + -55.2984010333f * g4 + 82.065982243f * g5 +
                    -58.5106008578f * g6 + 15.8478295021f * g7;
    const float e =
        4.23190299701f + 0.00310603949088f * std::exp(76.7316253952f * g + -594.356773233f * g2 +
                                                      2448.8834203f * g3 + -5576.68528998f * g4 +
                                                      7116.60171912f * g5 + -4763.54467887f * g6 +
                                                      1303.5318055f * g7);
    const float f = 2.40602999408f + -2.51814844609f * g + 9.18494908356f * g2 +
                    -79.2191708682f * g3 + 259.082868209f * g4 + -403.613804597f * g5 +
                    302.85712436f * g6 + -87.4370473567f * g7;
    const float blend = std::pow(albedo, 0.25f);
    const float alpha = (1.f - blend) * a * std::pow(std::atan(b * albedo), c) +
                        blend * d * std::pow(std::atan(e * albedo), f);
    return std::clamp(alpha, 0.f, 0.999999f);
}

float subsurface_dipole_rd(float alpha_prime, float four_thirds_a) {
    const float s = std::sqrt(3.f * (1.f - alpha_prime));
    return 0.5f * alpha_prime * (1.f + std::exp(-four_thirds_a * s)) * std::exp(-s);
}

float subsurface_dipole_alpha_prime(float rd, float four_thirds_a) {
    if (rd < 1e-4f) return 0.f;
    if (rd >= 0.995f) return 0.999999f;
    float x0 = 0.f, x1 = 1.f, xmid = 0.5f;
    for (int i = 0; i < 12; ++i) {  // Cycles' 12 bisection steps
        xmid = 0.5f * (x0 + x1);
        if (subsurface_dipole_rd(xmid, four_thirds_a) < rd)
            x0 = xmid;
        else
            x1 = xmid;
    }
    return xmid;
}

Rgb subsurface_effective_radius(const Rgb& radius, const Rgb& albedo, float ior,
                                SubsurfaceMethod method) {
    if (method == SubsurfaceMethod::RandomWalkFixedRadius) return radius * (0.25f * kInvPi);
    // Jensen et al. 2001's F_dr fit and the dipole's boundary term A = (1 + F_dr) / (1 - F_dr).
    const float inv_eta = 1.f / ior;
    const float f_dr = inv_eta * (-1.440f * inv_eta + 0.710f) + 0.668f + 0.0636f * ior;
    const float four_thirds_a = (4.f / 3.f) * (1.f + f_dr) / (1.f - f_dr);
    Rgb r;
    for (int c = 0; c < 3; ++c)
        r[c] = radius[c] *
               std::sqrt(3.f * (1.f - subsurface_dipole_alpha_prime(albedo[c], four_thirds_a)));
    return r;
}

SubsurfaceWalk SubsurfaceWalk::make(const Rgb& albedo, const Rgb& radius, float g) {
    SubsurfaceWalk w;
    w.g = g;
    for (int c = 0; c < 3; ++c) {
        float alpha = subsurface_single_scattering_albedo(albedo[c], g);
        w.sigma_t[c] = 1.f / std::fmax(radius[c], 1e-16f) / (1.f - g);
        // The closure weight holds A: divide it out (Cycles' safe_divide: 0 where A = 0).
        float weight = albedo[c] != 0.f ? 1.f / albedo[c] : 0.f;
        if (alpha < SubsurfaceLimits::kMinAlpha) {
            weight *= alpha / SubsurfaceLimits::kMinAlpha;
            alpha = SubsurfaceLimits::kMinAlpha;
        }
        w.alpha[c] = alpha;
        w.entry_weight[c] = weight;
    }
    return from_coefficients(w.sigma_t, w.alpha, w.entry_weight, g);
}

SubsurfaceWalk SubsurfaceWalk::from_coefficients(const Rgb& sigma_t, const Rgb& alpha,
                                                 const Rgb& entry_weight, float g) {
    SubsurfaceWalk w;
    w.sigma_t = sigma_t, w.alpha = alpha, w.entry_weight = entry_weight, w.g = g;
    // Dwivedi's diffusion length (d'Eon & Křivánek 2020, eq. 67) for the largest alpha.
    const float a = std::fmax(w.alpha.r, std::fmax(w.alpha.g, w.alpha.b));
    w.diffusion_length =
        1.f / std::sqrt(1.f - std::pow(a, 2.44294f - 0.0215813f * a + 0.578637f / a));
    w.phase_log = w.diffusion_length > 1.f
                      ? std::log((w.diffusion_length + 1.f) / (w.diffusion_length - 1.f))
                      : 0.f;
    return w;
}

}  // namespace facet
