// Fresnel terms against closed forms and known limits.
#include <gtest/gtest.h>

#include "facet/fresnel.h"

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

// Schlick's average has a closed form: F0 + (1 - F0) * 2/42 = F0 + (1 - F0) / 21.
TEST(Fresnel, SchlickAverageClosedForm) {
    Rgb f0(0.04f, 0.5f, 0.9f);
    Rgb avg = Fresnel::schlick(f0).average();
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(avg[c], f0[c] + (1.f - f0[c]) / 21.f, 1e-6f);
}

}  // namespace
}  // namespace facet
