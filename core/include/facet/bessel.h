// The modified Bessel function of the first kind of order 0, I0, as the longitudinal lobes of
// hair fibres need it (d'Eon et al. 2011: M = csch(1/v) / (2 v) exp(-sin sin / v) I0(cos cos / v),
// where I0's argument reaches 10^7 for smooth fibres): scaled by exp(a - x) so that neither the
// Bessel function nor the exponential overflows or underflows where their product does not.
//
// Two pieces, each within 1.3e-14 relative of I0(x) exp(-x) in double (tests/core/test_hair.cpp,
// BesselI0ScaledMatchesTheLibrary, against std::cyl_bessel_i):
//  - x <= 5: the power series sum_k (x^2 / 4)^k / (k!)^2 to k = 15 (its remainder below 2e-16
//    of the sum there), times exp(a - x);
//  - x > 5: sqrt(x) exp(-x) I0(x), which tends to 1 / sqrt(2 pi), as a polynomial of degree 24
//    in t = 10 / x - 1 in [-1, 1) (Chebyshev interpolation of that function, written out as
//    monomial coefficients: they are all below 0.41, so Horner's rule loses no digits), over
//    sqrt(x), times exp(a).
#pragma once

#include <cmath>

namespace facet {

// I0(x) exp(a - x) for x >= 0 (and any a): one exponential, no division by a factorial.
inline double bessel_i0_scaled(double x, double a) {
    if (x <= 5.0) {
        // 1 / (k!)^2 for k = 15 down to 0.
        constexpr double kSeries[] = {5.8479113141260385e-25,
                                      1.3157800456783586e-22,
                                      2.5789288895295828e-20,
                                      4.358389823304995e-18,
                                      6.2760813455591933e-16,
                                      7.5940584281266234e-14,
                                      7.5940584281266239e-12,
                                      6.1511873267825652e-10,
                                      3.9367598891408417e-08,
                                      1.9290123456790124e-06,
                                      6.9444444444444444e-05,
                                      0.001736111111111111,
                                      0.027777777777777776,
                                      0.25,
                                      1.0,
                                      1.0};
        const double q = 0.25 * x * x;
        double s = 0.0;
        for (double c : kSeries) s = s * q + c;
        return s * std::exp(a - x);
    }
    // sqrt(x) exp(-x) I0(x) at t = 10 / x - 1, highest degree first.
    constexpr double kTail[] = {
        -1.6148457488609263e-09, -4.7680302855405733e-08, 4.3245527147126897e-08,
        3.1818708141812677e-07,  -2.7328081381889807e-07, -9.4784089657489351e-07,
        8.8932171505167886e-07,  1.6598121557559175e-06,  -1.871740339145574e-06,
        -1.8858105255180424e-06, 2.901476301145422e-06,   1.444939607916667e-06,
        -3.7174125101154227e-06, -8.6102677471876942e-07, 4.4529325846028552e-06,
        1.2144277770943597e-06,  -5.1944293431381672e-06, -4.5453726799121861e-06,
        2.3569308338446077e-06,  1.0055851002287154e-05,  2.1338636743520833e-05,
        6.7194476243177619e-05,  0.00041057661818551711,  0.0056601266565980942,
        0.40424450633668252};
    const double t = 10.0 / x - 1.0;
    double s = 0.0;
    for (double c : kTail) s = s * t + c;
    return s / std::sqrt(x) * std::exp(a);
}

}  // namespace facet
