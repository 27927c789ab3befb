// Fresnel terms against closed forms and known limits.
#include <gtest/gtest.h>

#include "facet/fresnel.h"
#include "reference_double.h"

namespace facet {
namespace {

// Normal incidence: ((eta - 1) / (eta + 1))^2 exactly; tolerance 1e-6 is float round-off.
TEST(Fresnel, DielectricNormalIncidence) {
    for (float eta : {1.0f, 1.0001f, 1.33f, 1.5f, 2.4f}) {
        float expected = sqr((eta - 1.f) / (eta + 1.f));
        EXPECT_NEAR(fresnel_dielectric(1.f, eta), expected, 1e-6f) << "eta " << eta;
    }
}

// Grazing incidence reflects everything; eta < 1 past the critical angle is total reflection.
TEST(Fresnel, DielectricLimits) {
    EXPECT_FLOAT_EQ(fresnel_dielectric(0.f, 1.5f), 1.f);
    float critical_cos = std::sqrt(1.f - sqr(1.f / 1.5f));
    EXPECT_FLOAT_EQ(fresnel_dielectric(critical_cos * 0.99f, 1.f / 1.5f), 1.f);
}

// Conductor normal incidence: ((n-1)^2 + k^2) / ((n+1)^2 + k^2); k = 0 reduces to dielectric.
TEST(Fresnel, ConductorNormalIncidenceAndDielectricLimit) {
    float n = 0.2f, k = 3.9f;  // roughly gold at 600 nm
    float expected = (sqr(n - 1.f) + k * k) / (sqr(n + 1.f) + k * k);
    EXPECT_NEAR(fresnel_conductor(1.f, n, k), expected, 1e-6f);
    for (float c : {0.05f, 0.3f, 0.7f, 1.f})
        EXPECT_NEAR(fresnel_conductor(c, 1.5f, 0.f), fresnel_dielectric(c, 1.5f), 1e-6f);
}

// The real-arithmetic conductor formula against the complex-arithmetic oracle of
// reference_double.h, over metals, k -> 0, eta -> 1, eta < 1 (total reflection), huge k, and
// cosines from grazing to normal. Tolerance: 2e-7 absolute + 1e-6 relative: the float result
// of a double computation is within half a float ulp (6e-8 relative) of the exact value; the
// margin covers the oracle's own round-off near eta = 1 (a difference of nearly equal numbers
// in both forms).
TEST(Fresnel, ConductorMatchesComplexOracle) {
    const float etas[] = {0.05f, 0.2f, 0.7f, 0.9999f, 1.f, 1.0001f, 1.5f, 3.f, 20.f};
    const float ks[] = {0.f, 1e-6f, 1e-3f, 0.1f, 1.f, 3.9f, 50.f};
    const float cosines[] = {0.f,  1e-9f,   1e-4f, 0.01f,  0.1f, 0.3f,
                             0.5f, 0.7071f, 0.9f,  0.999f, 1.f};
    int checked = 0;
    for (float eta : etas)
        for (float k : ks)
            for (float c : cosines) {
                if (eta == 1.f && k == 0.f && c == 0.f) continue;  // 0/0 in the oracle
                double expected = ref::fresnel_exact(c, eta, k);
                float got = fresnel_conductor(c, eta, k);
                EXPECT_NEAR(got, expected, 2e-7 + 1e-6 * expected)
                    << "eta " << eta << " k " << k << " cos " << c;
                ++checked;
            }
    EXPECT_EQ(checked, 9 * 7 * 11 - 1);
}

// Schlick's average has a closed form: F0 + (1 - F0) * 2/42 = F0 + (1 - F0) / 21.
TEST(Fresnel, SchlickAverageClosedForm) {
    Rgb f0(0.04f, 0.5f, 0.9f);
    Rgb avg = Fresnel::schlick(f0).average();
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(avg[c], f0[c] + (1.f - f0[c]) / 21.f, 1e-6f);
}

}  // namespace
}  // namespace facet
