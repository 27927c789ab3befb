// Scene-level numerical stress (issue 12): extreme material parameters in a furnace, grazing
// light, sliver and degenerate triangles, coincident surfaces. What is counted: NaN/Inf pixels,
// samples the film dropped (RenderStats::nonfinite), and energy gain — a furnace brighter than
// its analytic bound. The expected count of each is zero. FACET_STRESS_SCALE (test.sh sets 0.1
// under sanitizers) scales the sample counts. The scenes come from stress_scenes.h, shared with
// the longer run over scales, offsets and light angles in bench/stress_bench.cpp.
#include <gtest/gtest.h>

#include <cstdlib>

#include "facet/testsupport/render_test_util.h"
#include "facet/testsupport/stress_scenes.h"

namespace fs = facet::stress;

using facet::render::testing::stress_scale;

TEST(SceneStress, ExtremeMaterialsInAFurnaceNeitherGainEnergyNorProduceNaN) {
    // Bounds: fs::furnace_cases(). Tolerances: 5 standard errors of the image mean (pixels are
    // i.i.d. estimates in a furnace), and 3e-3 relative for the compensated lobes' tabulated
    // albedo (test_energy.cpp measures it to 2e-4 on white lobes).
    const float le = 0.5f;
    const int spp = std::max(4, int(64 * stress_scale()));
    for (const fs::FurnaceCase& c : fs::furnace_cases()) {
        SCOPED_TRACE(c.label);
        const double bound = le / (1.0 - c.albedo);
        const fs::Stats s = fs::render_stats(fs::furnace(c.m, le), spp);
        EXPECT_EQ(s.nonfinite_pixels, 0u);
        EXPECT_EQ(s.dropped, 0u);
        EXPECT_LE(s.mean, bound + 5.0 * s.std_error + 3e-3 * bound) << "energy gain";
        if (c.exact) {
            EXPECT_NEAR(s.mean, bound, 5.0 * s.std_error + 3e-3 * bound);
        }
    }
}

TEST(SceneStress, GrazingLightSliversAndCoincidentSurfacesStayFinite) {
    facet::render::SceneDescription d = fs::grazing_scene();
    for (const char* integrator : {"path", "direct"}) {
        SCOPED_TRACE(integrator);
        d.render.integrator = integrator;
        const fs::Stats s = fs::render_stats(d, std::max(4, int(32 * stress_scale())));
        EXPECT_EQ(s.nonfinite_pixels, 0u);
        EXPECT_EQ(s.dropped, 0u);
        EXPECT_GT(s.mean, 0.0);
    }
}
