// Blackbody emission as Cycles 3.4 computes it: the colour of a temperature (Blender's Blackbody
// node, Principled Volume's blackbody emission) and the Principled Volume's emitted radiance.
//
// Conventions:
//  - blackbody_rec709(T) is Cycles' piecewise fit of the blackbody colour in linear Rec.709
//    (svm_math_blackbody_color_rec709, coefficients of Cycles' kernel tables): seven temperature
//    ranges between 800 K and 12000 K, red and green a / T + b T + c, blue a cubic in T;
//    constant colours below 800 K and from 12000 K on. The colour is not clamped: below about
//    1900 K its blue (and below 965 K its green) is negative, a gamut wider than Rec.709, and
//    Cycles emits it so.
//  - principled_volume_blackbody(b, T, tint) is the radiance per unit length of the Principled
//    Volume's blackbody emission: tint * sigma * mix(1, T^4, b) * blackbody_rec709(T), sigma =
//    Stefan-Boltzmann's 5.670373e-8 W m^-2 K^-4 * 1e-6 / pi (Cycles' scale), 0 when that
//    intensity is at most Cycles' closure cut-off 1e-8. T is clamped to >= 0 first.
#pragma once

#include <algorithm>

#include "facet/types.h"

namespace facet {

inline Rgb blackbody_rec709(float t) {
    // Range starts (K) and coefficients, one row per range (Cycles' fit).
    static constexpr float kStart[7] = {800.f, 965.f, 1167.f, 1449.f, 1902.f, 3315.f, 6365.f};
    static constexpr float kR[7][3] = {{1.61919106e+03f, -2.05010916e-03f, 5.02995757e+00f},
                                       {2.48845471e+03f, -1.11330907e-03f, 3.22621544e+00f},
                                       {3.34143193e+03f, -4.86551192e-04f, 1.76486769e+00f},
                                       {4.09461742e+03f, -1.27446582e-04f, 7.25731635e-01f},
                                       {4.67028036e+03f, 2.91258199e-05f, 1.26703442e-01f},
                                       {4.59509185e+03f, 2.87495649e-05f, 1.50345020e-01f},
                                       {3.78717450e+03f, 9.35907826e-06f, 3.99075871e-01f}};
    static constexpr float kG[7][3] = {{-4.88999748e+02f, 6.04330754e-04f, -7.55807526e-02f},
                                       {-7.55994277e+02f, 3.16730098e-04f, 4.78306139e-01f},
                                       {-1.02363977e+03f, 1.20223470e-04f, 9.36662319e-01f},
                                       {-1.26571316e+03f, 4.87340896e-06f, 1.27054498e+00f},
                                       {-1.42529332e+03f, -4.01150431e-05f, 1.43972784e+00f},
                                       {-1.17554822e+03f, -2.16378048e-05f, 1.30408023e+00f},
                                       {-5.00799571e+02f, -4.59832026e-06f, 1.09098763e+00f}};
    static constexpr float kB[7][4] = {
        {5.96945309e-11f, -4.85742887e-08f, -9.70622247e-05f, -4.07936148e-03f},
        {2.40430366e-11f, 5.55021075e-08f, -1.98503712e-04f, 2.89312858e-02f},
        {-1.40949732e-11f, 1.89878968e-07f, -3.56632824e-04f, 9.10767778e-02f},
        {-3.61460868e-11f, 2.84822009e-07f, -4.93211319e-04f, 1.56723440e-01f},
        {-1.97075738e-11f, 1.75359352e-07f, -2.50542825e-04f, -2.22783266e-02f},
        {-1.61997957e-13f, -1.64216008e-08f, 3.86216271e-04f, -7.38077418e-01f},
        {6.72650283e-13f, -2.73078809e-08f, 4.24098264e-04f, -7.52335691e-01f}};
    if (t >= 12000.f) return {0.8262954810464208f, 0.9945080501520986f, 1.566307710274283f};
    if (!(t >= kStart[0])) return {5.413294490189271f, -0.20319390035873933f, -0.0822535242887164f};
    int i = 6;
    while (t < kStart[i]) --i;
    const float inv = 1.f / t;
    const float* r = kR[i];
    const float* g = kG[i];
    const float* b = kB[i];
    return {r[0] * inv + r[1] * t + r[2], g[0] * inv + g[1] * t + g[2],
            ((b[0] * t + b[1]) * t + b[2]) * t + b[3]};
}

inline Rgb principled_volume_blackbody(float intensity_factor, float temperature, const Rgb& tint) {
    const float t = std::max(temperature, 0.f);
    const float t4 = (t * t) * (t * t);
    constexpr float kSigma = 5.670373e-8f * 1e-6f / 3.14159265358979f;
    const float intensity =
        kSigma * ((1.f - intensity_factor) * 1.f + intensity_factor * t4);  // mix(1, T^4, b)
    if (!(intensity > 1e-8f)) return Rgb(0.f);
    return tint * intensity * blackbody_rec709(t);
}

}  // namespace facet
