// Grid (heterogeneous) media (facet/render/density_grid.h, facet/render/medium.h; the `grid`
// medium kind, media/grid.cpp): the grid's interpolation and majorants, ratio tracking and
// spectral delta tracking against analytic transmittance, renders from OpenVDB files written
// here with OpenVDB's own API (a furnace, an absorbing box against Beer-Lambert), and the
// errors for bad files and grids, each naming its JSON pointer. Monte Carlo counts scale with
// FACET_STRESS_SCALE.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include <openvdb/io/File.h>
#include <openvdb/openvdb.h>

#include "facet/blackbody.h"
#include "facet/render/density_grid.h"
#include "facet/render/medium.h"
#include "facet/render/render.h"
#include "facet/render/scene.h"
#include "facet/testsupport/render_test_util.h"

namespace fr = facet::render;
using facet::Rgb;
using facet::Vec3;

namespace {

// A grid of resolution n over [lo, hi] whose voxel values are f(voxel centre).
template <class F>
fr::DensityGrid grid_of(std::array<int, 3> n, const Vec3& lo, const Vec3& hi, F f) {
    std::vector<float> v;
    const Vec3 h = (hi - lo) / Vec3(float(n[0]), float(n[1]), float(n[2]));
    for (int k = 0; k < n[2]; ++k)
        for (int j = 0; j < n[1]; ++j)
            for (int i = 0; i < n[0]; ++i)
                v.push_back(f(lo + h * Vec3(float(i) + 0.5f, float(j) + 0.5f, float(k) + 0.5f)));
    return fr::DensityGrid(n, lo, hi, std::move(v));
}

// A uniform generator for the tracking functions (the renderer's is a PCG32; any will do).
struct Uniform {
    std::mt19937 rng;
    explicit Uniform(unsigned seed) : rng(seed) {}
    float operator()() { return std::uniform_real_distribution<float>(0.f, 1.f)(rng); }
};

struct MeanSe {
    double mean, se;
};
MeanSe mean_se(const std::vector<double>& x) {
    double s = 0.0, s2 = 0.0;
    for (double v : x) s += v, s2 += v * v;
    const double n = double(x.size()), m = s / n;
    return {m, std::sqrt(std::max(0.0, s2 / n - m * m) / (n - 1.0))};
}

std::string temp_dir() {
    const std::filesystem::path d =
        std::filesystem::temp_directory_path() /
        ("facet_grid_media_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) +
         "_" + ::testing::UnitTest::GetInstance()->current_test_info()->name());
    std::filesystem::create_directories(d);
    return d.string();
}

// Writes `grids` to an OpenVDB file.
void write_vdb(const std::string& path, openvdb::GridPtrVec grids) {
    openvdb::initialize();
    openvdb::io::File f(path);
    f.write(grids);
    f.close();
}

// A float grid of voxel size `voxel` whose voxels (i, j, k) in [0, n)^3 hold f(i, j, k), voxel
// (i, j, k) covering [i, i + 1] x [j, j + 1] x [k, k + 1] times `voxel` (OpenVDB puts voxel
// centres at integer index coordinates: the transform moves them by half a voxel).
template <class F>
openvdb::FloatGrid::Ptr float_grid(const std::string& name, int n, double voxel, F f) {
    openvdb::FloatGrid::Ptr g = openvdb::FloatGrid::create(0.f);
    g->setName(name);
    openvdb::math::Transform::Ptr xf = openvdb::math::Transform::createLinearTransform(voxel);
    xf->postTranslate(openvdb::Vec3d(0.5 * voxel));
    g->setTransform(xf);
    auto acc = g->getAccessor();
    for (int k = 0; k < n; ++k)
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i) acc.setValue(openvdb::Coord(i, j, k), f(i, j, k));
    return g;
}

}  // namespace

// Voxel centres hold the values exactly, the interpolant is linear between them (a linear
// function is reproduced to float rounding), constant beyond the outermost centres inside the
// box, and 0 outside it.
TEST(DensityGrid, InterpolatesBetweenCentresAndIsZeroOutside) {
    const fr::DensityGrid g =
        grid_of({4, 3, 5}, Vec3(-1.f, 0.f, 2.f), Vec3(3.f, 3.f, 7.f),
                [](const Vec3& p) { return 1.f + p.x + 2.f * p.y + 0.5f * p.z; });
    EXPECT_FLOAT_EQ(g.density(Vec3(-0.5f, 0.5f, 2.5f)), 1.f - 0.5f + 1.f + 1.25f);
    EXPECT_NEAR(g.density(Vec3(0.7f, 1.3f, 4.1f)), 1.f + 0.7f + 2.6f + 2.05f, 1e-5);
    // Between the box face x = -1 and the first centre x = -0.5: the first centre's value.
    EXPECT_NEAR(g.density(Vec3(-0.9f, 1.5f, 4.5f)), g.density(Vec3(-0.5f, 1.5f, 4.5f)), 1e-6);
    EXPECT_EQ(g.density(Vec3(-1.01f, 1.f, 4.f)), 0.f);
    EXPECT_EQ(g.density(Vec3(0.f, 3.01f, 4.f)), 0.f);
    EXPECT_EQ(g.memory_bytes(), (4u * 3u * 5u + 1u) * sizeof(float));
}

// march() covers exactly the part of the ray inside the box (before t_max) with contiguous
// pieces, and each piece's majorant bounds the density everywhere on it (checked at 16 points
// per piece), on random rays through a random grid with empty regions (where pieces have
// majorant 0 and tracking skips them).
TEST(DensityGrid, MajorantPiecesCoverTheBoxAndBoundTheDensity) {
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> u(0.f, 1.f);
    const Vec3 lo(-2.f, -1.f, -1.5f), hi(2.f, 1.5f, 1.f);
    const fr::DensityGrid g = grid_of({37, 21, 19}, lo, hi, [&](const Vec3& p) {
        return p.x < -0.5f ? 0.f : (p.y > 0.7f ? 5.f * u(rng) : u(rng));
    });
    int pieces = 0, empty = 0;
    for (int n = 0; n < 400; ++n) {
        // From a random point toward a random point of the box (a quarter of the rays toward
        // a random point anywhere, most of which miss it).
        const Vec3 o(6.f * u(rng) - 3.f, 6.f * u(rng) - 3.f, 6.f * u(rng) - 3.f);
        const Vec3 target = n % 4 == 0
                                ? Vec3(6.f * u(rng) - 3.f, 6.f * u(rng) - 3.f, 6.f * u(rng) - 3.f)
                                : lo + (hi - lo) * Vec3(u(rng), u(rng), u(rng));
        const Vec3 d = glm::normalize(target - o);
        const float t_max = n % 3 == 0 ? 2.f : INFINITY;
        // The box's span along the ray, by the slab test in double.
        double t0 = 0.0, t1 = double(t_max);
        for (int a = 0; a < 3; ++a) {
            double ta = (double(lo[a]) - double(o[a])) / double(d[a]);
            double tb = (double(hi[a]) - double(o[a])) / double(d[a]);
            if (ta > tb) std::swap(ta, tb);
            t0 = std::max(t0, ta), t1 = std::min(t1, tb);
        }
        float expect_t = float(t0), last = -1.f;
        g.march(o, d, t_max, [&](float a, float b, float maj) {
            EXPECT_NEAR(a, expect_t, 1e-5f) << "ray " << n;
            EXPECT_LT(a, b);
            ++pieces;
            if (maj == 0.f) ++empty;
            for (int s = 0; s <= 15; ++s) {
                const float t = a + (b - a) * (float(s) + 0.5f) / 16.f;
                EXPECT_LE(g.density(o + d * t), maj * (1.f + 1e-6f)) << "ray " << n << " t " << t;
            }
            expect_t = b;
            last = b;
            return true;
        });
        if (t0 < t1)
            EXPECT_NEAR(last, float(t1), 1e-4f) << "ray " << n;
        else
            EXPECT_EQ(last, -1.f) << "ray " << n << " misses the box";
    }
    EXPECT_GT(pieces, 400);
    EXPECT_GT(empty, 10);
}

// Ratio tracking against the analytic transmittance: density rising linearly along x
// (rho = 0.2 + 0.6 x over the voxel centres' range), a ray along +x from x = a to b inside that
// range: optical depth sigma_t (0.2 (b - a) + 0.3 (b^2 - a^2)), chromatic sigma_t. Also a ray
// that only grazes empty space (transmittance exactly 1). The mean of N estimates within 4.5
// standard errors (a wrong majorant, a biased step or a missed piece fails by far more; N = 4000
// at scale 1 gives a standard error of ~0.003).
TEST(GridTracking, RatioTrackingMatchesAnalyticTransmittance) {
    const fr::DensityGrid g = grid_of({40, 4, 4}, Vec3(0.f, -1.f, -1.f), Vec3(4.f, 1.f, 1.f),
                                      [](const Vec3& p) { return 0.2f + 0.6f * p.x; });
    const Rgb sigma_a(0.3f, 0.1f, 0.f), sigma_s(0.2f, 0.6f, 1.1f);
    const fr::Medium m =
        fr::Medium::grid(std::make_shared<const fr::DensityGrid>(g), sigma_a, sigma_s, 0.f);
    const double a = 0.3, b = 3.7;
    const double depth = 0.2 * (b - a) + 0.3 * (b * b - a * a);
    const int n = std::max(400, int(4000 * fr::testing::stress_scale()));
    Uniform uni(11);
    std::vector<std::vector<double>> est(3);
    for (int i = 0; i < n; ++i) {
        const Rgb tr = m.ratio_transmittance(Vec3(float(a), 0.1f, -0.2f), Vec3(1.f, 0.f, 0.f),
                                             float(b - a), uni);
        for (int c = 0; c < 3; ++c) est[std::size_t(c)].push_back(double(tr[c]));
    }
    for (int c = 0; c < 3; ++c) {
        const double expect = std::exp(-double(sigma_a[c] + sigma_s[c]) * depth);
        const MeanSe ms = mean_se(est[std::size_t(c)]);
        EXPECT_NEAR(ms.mean, expect, 4.5 * ms.se + 1e-9) << "channel " << c;
    }
    // Outside the box: no collision, exactly 1.
    EXPECT_EQ(m.ratio_transmittance(Vec3(-1.f, 3.f, 0.f), Vec3(1.f, 0.f, 0.f), 10.f, uni),
              Rgb(1.f));
}

// Spectral delta tracking's estimator on the same ramp: E[beta_c at the end] = T_c(L) (the
// ray passes), and E[beta_c at a scattering event] = int sigma_s,c rho T_c = (sigma_s,c /
// sigma_t,c)(1 - T_c(L)) for coefficients proportional to one density. Within 4.5 standard
// errors per channel; dropping the null-collision weights or the channel mixture fails.
TEST(GridTracking, SpectralDeltaTrackingIsUnbiased) {
    const fr::DensityGrid g = grid_of({40, 4, 4}, Vec3(0.f, -1.f, -1.f), Vec3(4.f, 1.f, 1.f),
                                      [](const Vec3& p) { return 0.2f + 0.6f * p.x; });
    const Rgb sigma_a(0.3f, 0.1f, 0.f), sigma_s(0.2f, 0.6f, 1.1f);
    const fr::Medium m =
        fr::Medium::grid(std::make_shared<const fr::DensityGrid>(g), sigma_a, sigma_s, 0.4f);
    const double a = 0.3, b = 3.7, depth = 0.2 * (b - a) + 0.3 * (b * b - a * a);
    const int n = std::max(800, int(8000 * fr::testing::stress_scale()));
    Uniform uni(5);
    std::vector<std::vector<double>> pass(3), scatter(3);
    for (int i = 0; i < n; ++i) {
        Rgb beta(1.f);
        const float t_max = float(b - a);
        const float t =
            m.sample_free_flight(Vec3(float(a), 0.f, 0.f), Vec3(1.f, 0.f, 0.f), t_max, uni, beta);
        for (int c = 0; c < 3; ++c) {
            pass[std::size_t(c)].push_back(t < t_max ? 0.0 : double(beta[c]));
            scatter[std::size_t(c)].push_back(t < t_max ? double(beta[c]) : 0.0);
        }
    }
    for (int c = 0; c < 3; ++c) {
        const double st = double(sigma_a[c] + sigma_s[c]), tr = std::exp(-st * depth);
        const MeanSe p = mean_se(pass[std::size_t(c)]), s = mean_se(scatter[std::size_t(c)]);
        EXPECT_NEAR(p.mean, tr, 4.5 * p.se + 1e-9) << "channel " << c;
        EXPECT_NEAR(s.mean, double(sigma_s[c]) / st * (1.0 - tr), 4.5 * s.se + 1e-9)
            << "channel " << c;
    }
}

// Renders from OpenVDB files. An absorbing grid of constant density 2 filling [0, 1]^3 (a
// 16^3 grid of voxel size 1/16) inside a null box of the same extent, in front of an emitter of
// radiance 2, seen along -z by an orthographic camera: every pixel is 2 exp(-2 sigma_a depth) in
// expectation (ratio tracking is exact in the mean, noisy per pixel); the mean of the pixels
// within 5 standard errors. Placed by a transform (scaled to depth 1.5 along z, turned 90
// degrees about z and moved back over [0, 1]^2) the depth is 1.5: the map from world to the
// file's space is applied to points and directions alike.
TEST(GridMedia, AbsorbingGridFromVdbMatchesBeerLambert) {
    const std::string dir = temp_dir();
    write_vdb(dir + "/cube.vdb",
              {float_grid("density", 16, 1.0 / 16.0, [](int, int, int) { return 2.f; })});
    struct Case {
        std::string transform, box_max;
        double depth;
    };
    const std::vector<Case> cases = {
        {"", "[1, 1, 1]", 1.0},
        {R"(, "transform": [{"scale": [1, 1, 1.5]}, {"rotate": {"axis": [0, 0, 1], "angle": 90}},
                            {"translate": [1, 0, 0]}])",
         "[1, 1, 1.5]", 1.5},
    };
    for (const Case& k : cases) {
        const std::string body = R"(
            "camera": {"type": "orthographic", "scale": 0.8, "position": [0.5, 0.5, 5],
                       "look_at": [0.5, 0.5, 0], "width": 16, "height": 16},
            "media": {"smoke": {"kind": "grid", "file": "cube.vdb", "sigma_a": [0.25, 0.5, 1])" +
                                 k.transform + R"(}},
            "materials": {"boundary": {"model": "null", "interior": "smoke"}},
            "shapes": [{"type": "box", "min": [0, 0, 0], "max": )" +
                                 k.box_max + R"(, "material": "boundary"},
                       {"type": "quad", "vertices": [[-5, -5, -3], [5, -5, -3], [5, 5, -3],
                                                     [-5, 5, -3]], "emission": 2}])";
        const fr::Scene scene = fr::testing::scene_in_dir(dir, body, "grid.json");
        const int spp = std::max(8, int(64 * fr::testing::stress_scale()));
        const fr::Image img = fr::render(scene, fr::testing::test_options("path", spp, 3));
        const Rgb sigma_a(0.25f, 0.5f, 1.f);
        for (int c = 0; c < 3; ++c) {
            std::vector<double> px;
            for (const Rgb& p : img.pixels()) px.push_back(double(p[c]));
            const MeanSe ms = mean_se(px);
            const double expect = 2.0 * std::exp(-2.0 * double(sigma_a[c]) * k.depth);
            EXPECT_NEAR(ms.mean, expect, 5.0 * ms.se + 1e-6)
                << "depth " << k.depth << " channel " << c;
            EXPECT_GT(ms.se, 0.0) << "channel " << c << ": tracking should be noisy per pixel";
        }
    }
    std::filesystem::remove_all(dir);
}

// The furnace with a grid: a smoke-like blob of density (a Gaussian with random voxel noise)
// of albedo 1 (chromatic sigma_s) inside a null box under a constant environment of radiance
// 0.5: every pixel converges to 0.5. The mean over the box's pixels within 5 standard errors.
TEST(GridMedia, ScatteringGridFurnaceConservesEnergy) {
    const std::string dir = temp_dir();
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> u(0.5f, 1.5f);
    write_vdb(dir + "/blob.vdb", {float_grid("density", 24, 1.0 / 24.0, [&](int i, int j, int k) {
                  const double x = (i - 11.5) / 6.0, y = (j - 11.5) / 6.0, z = (k - 11.5) / 6.0;
                  return float(4.0 * std::exp(-(x * x + y * y + z * z))) * u(rng);
              })});
    const fr::Scene scene = fr::testing::scene_in_dir(dir, R"(
        "camera": {"position": [0.5, 0.5, 3.5], "look_at": [0.5, 0.5, 0.5], "fov": 25,
                   "width": 20, "height": 20},
        "media": {"smoke": {"kind": "grid", "file": "blob.vdb", "density": 3,
                            "color": [1, 0.8, 0.6], "absorption_color": [1, 1, 1], "g": 0.3}},
        "materials": {"boundary": {"model": "null", "interior": "smoke"}},
        "shapes": [{"type": "box", "min": [0, 0, 0], "max": [1, 1, 1], "material": "boundary"}],
        "lights": [{"type": "environment", "radiance": 0.5}],
        "render": {"max_depth": 1000})",
                                                      "furnace.json");
    const int spp = std::max(16, int(128 * fr::testing::stress_scale()));
    const fr::Image img = fr::render(scene, fr::testing::test_options("path", spp, 9));
    std::vector<std::vector<double>> px(3);
    int inside = 0;
    for (const Rgb& p : img.pixels()) {
        if (p == Rgb(0.5f)) continue;
        ++inside;
        for (int c = 0; c < 3; ++c) px[std::size_t(c)].push_back(double(p[c]));
    }
    ASSERT_GT(inside, 40) << "the smoke was not seen";
    for (int c = 0; c < 3; ++c) {
        const MeanSe ms = mean_se(px[std::size_t(c)]);
        EXPECT_NEAR(ms.mean, 0.5, 5.0 * ms.se + 1e-6) << "channel " << c;
    }
    std::filesystem::remove_all(dir);
}

// Cycles 3.4's blackbody colour: its Blackbody node (which clamps the colour to >= 0) rendered
// by Cycles on an emission plane (Standard view, 32-bit EXR, values printed to 7 digits) at
// temperatures in every range of the fit and beyond both ends. The Principled Volume uses the
// same fit unclamped: below 1902 K the fit's blue is negative (checked here), below 965 K its
// green. 2e-6 relative plus 3e-6: the printed digits, float rounding, and Cycles' float
// Rec.709-to-scene-linear matrix (an identity to about 4e-7, times a red of up to 5.4).
TEST(Blackbody, MatchesCyclesBlackbodyNode) {
    struct Sample {
        float t;
        Rgb cycles;
    };
    const std::vector<Sample> samples = {
        {700.f, {5.413295f, 0.f, 0.f}},
        {900.f, {4.983961f, 0.f, 0.f}},
        {1000.f, {4.601362f, 0.03904079f, 0.f}},
        {1100.f, {4.263807f, 0.1394406f, 0.f}},
        {1300.f, {3.702684f, 0.3055366f, 0.f}},
        {1500.f, {3.264307f, 0.4340453f, 0.f}},
        {1700.f, {2.917671f, 0.5342917f, 0.f}},
        {2500.f, {2.06763f, 0.7693219f, 0.1394299f}},
        {4000.f, {1.414115f, 0.923641f, 0.5336742f}},
        {6500.f, {1.042551f, 0.9840515f, 1.035271f}},
        {9000.f, {0.9041031f, 0.9939572f, 1.342972f}},
        {13000.f, {0.8262937f, 0.9945068f, 1.566307f}},
    };
    for (const Sample& s : samples) {
        const Rgb ours = facet::blackbody_rec709(s.t);
        for (int c = 0; c < 3; ++c)
            EXPECT_NEAR(std::max(ours[c], 0.f), s.cycles[c], 2e-6f * s.cycles[c] + 3e-6f)
                << s.t << " K, channel " << c;
    }
    EXPECT_LT(facet::blackbody_rec709(1500.f).b, -0.05f) << "the fit is used unclamped";
    // Principled Volume: sigma mix(1, T^4, b) rgb(T) tint, sigma = 5.670373e-14 / pi.
    const Rgb tint(1.f, 0.5f, 0.25f);
    const Rgb e = facet::principled_volume_blackbody(0.75f, 2500.f, tint);
    const double intensity = 5.670373e-14 / 3.141592653589793 * (0.25 + 0.75 * std::pow(2500.0, 4));
    for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(e[c], intensity * tint[c] * facet::blackbody_rec709(2500.f)[c],
                    1e-5 * std::fabs(e[c]));
    // Below Cycles' closure cut-off (1e-8) nothing is emitted.
    EXPECT_EQ(facet::principled_volume_blackbody(0.5f, 0.f, Rgb(1.f)), Rgb(0.f));
}

// Emitting grids against the exact integral along the ray. A 1 x 1 x 1 box of grid medium
// (absorbing, sigma_a per unit density) in front of an emitter of radiance 2, seen along -z by
// an orthographic camera: each pixel's expectation is 2 T(1) + int_0^1 T(s) e(s) ds (s the depth
// from the top, T(s) = exp(-sigma_a int_0^s rho)). Cases:
//  - a constant density 2 with a constant emission e: (e / sigma_t) (1 - exp(-sigma_t)),
//    sigma_t = 2 sigma_a, exactly the homogeneous emitting medium's closed form;
//  - the same with the emission scaled by the density grid itself (emission e / 2);
//  - a density of 2 in the bottom quarter only (32^3 voxels: the top half is majorant cells of
//    0, the emission there is gathered on the empty pieces) and the emission scaled by a
//    separate grid of value 1: the integral by the trapezoidal rule over the density's
//    piecewise-linear profile (2e5 steps);
//  - blackbody emission from a temperature grid of 1.5 times temperature 1000 (1500 K, whose
//    blue is negative, kept as Cycles keeps it), intensity 0.8 and a tint, no other emission.
// The mean over the pixels within 5 standard errors per channel; without emission the pixels
// would be the transmitted 2 T(1) alone, which each case's expectation exceeds by more than 20
// standard errors in some channel (checked: a dropped emission fails).
TEST(GridMedia, EmittingGridMatchesTheExactIntegral) {
    const std::string dir = temp_dir();
    write_vdb(dir + "/const.vdb",
              {float_grid("density", 16, 1.0 / 16.0, [](int, int, int) { return 2.f; }),
               float_grid("heat", 16, 1.0 / 16.0, [](int, int, int) { return 1.5f; })});
    write_vdb(
        dir + "/half.vdb",
        {float_grid("density", 32, 1.0 / 32.0, [](int, int, int k) { return k < 8 ? 2.f : 0.f; }),
         float_grid("glow", 32, 1.0 / 32.0, [](int, int, int) { return 1.f; })});
    const Rgb sigma_a(0.25f, 0.5f, 1.f), e(1.f, 2.f, 3.f);
    // The density profile of half.vdb along z (trilinear between voxel centres, clamped).
    auto half_density = [](double z) {
        const double q = z * 32.0 - 0.5, fl = std::floor(q), f = q - fl;
        auto v = [](int k) { return std::clamp(k, 0, 31) < 8 ? 2.0 : 0.0; };
        return v(int(fl)) * (1.0 - f) + v(int(fl) + 1) * f;
    };
    auto integral = [&](int c, auto rho, Rgb emit) {
        const int n = 200000;
        double tau = 0.0, sum = 0.0, prev_f = 0.0, prev_rho = rho(1.0);
        for (int i = 0; i <= n; ++i) {
            const double s = double(i) / n, r = rho(1.0 - s);
            if (i > 0) tau += 0.5 * (r + prev_rho) / n * double(sigma_a[c]);
            const double f = std::exp(-tau) * double(emit[c]);
            if (i > 0) sum += 0.5 * (f + prev_f) / n;
            prev_f = f;
            prev_rho = r;
        }
        return 2.0 * std::exp(-tau) + sum;
    };
    const Rgb bb = facet::principled_volume_blackbody(0.8f, 1500.f, Rgb(1.f, 0.5f, 0.25f));
    ASSERT_LT(bb.b, 0.f);
    struct Case {
        std::string name, medium;
        Rgb expected;
    };
    std::vector<Case> cases;
    Rgb constant, transmitted;
    for (int c = 0; c < 3; ++c) {
        const double st = 2.0 * double(sigma_a[c]);
        constant[c] = float(2.0 * std::exp(-st) + double(e[c]) * -std::expm1(-st) / st);
        transmitted[c] = float(2.0 * std::exp(-st));
    }
    const std::string coef = R"("sigma_a": [0.25, 0.5, 1])";
    cases.push_back(
        {"constant emission", R"("file": "const.vdb", "emission": [1, 2, 3], )" + coef, constant});
    cases.push_back(
        {"emission x density",
         R"("file": "const.vdb", "emission": [0.5, 1, 1.5], "emission_grid": "density", )" + coef,
         constant});
    Rgb half;
    for (int c = 0; c < 3; ++c) half[c] = float(integral(c, half_density, e));
    cases.push_back(
        {"sparse density, emission grid",
         R"("file": "half.vdb", "emission": [1, 2, 3], "emission_grid": "glow", )" + coef, half});
    Rgb blackbody;
    for (int c = 0; c < 3; ++c) {
        const double st = 2.0 * double(sigma_a[c]);
        blackbody[c] = float(2.0 * std::exp(-st) + double(bb[c]) * -std::expm1(-st) / st);
    }
    cases.push_back({"blackbody",
                     R"("file": "const.vdb", "blackbody_intensity": 0.8, "temperature": 1000,
                        "temperature_grid": "heat", "blackbody_tint": [1, 0.5, 0.25], )" +
                         coef,
                     blackbody});
    for (const Case& k : cases) {
        const std::string body = R"(
            "camera": {"type": "orthographic", "scale": 0.8, "position": [0.5, 0.5, 5],
                       "look_at": [0.5, 0.5, 0], "width": 16, "height": 16},
            "media": {"smoke": {"kind": "grid", )" +
                                 k.medium + R"(}},
            "materials": {"boundary": {"model": "null", "interior": "smoke"}},
            "shapes": [{"type": "box", "min": [0, 0, 0], "max": [1, 1, 1], "material": "boundary"},
                       {"type": "quad", "vertices": [[-5, -5, -3], [5, -5, -3], [5, 5, -3],
                                                     [-5, 5, -3]], "emission": 2}])";
        const fr::Scene scene = fr::testing::scene_in_dir(dir, body, "glow.json");
        const int spp = std::max(8, int(64 * fr::testing::stress_scale()));
        const fr::Image img = fr::render(scene, fr::testing::test_options("path", spp, 5));
        double visible = 0.0;  // the largest emission term in standard errors
        for (int c = 0; c < 3; ++c) {
            std::vector<double> px;
            for (const Rgb& p : img.pixels()) px.push_back(double(p[c]));
            const MeanSe ms = mean_se(px);
            EXPECT_NEAR(ms.mean, k.expected[c], 5.0 * ms.se + 1e-6) << k.name << ", channel " << c;
            visible = std::max(visible, std::fabs(k.expected[c] - transmitted[c]) / ms.se);
        }
        EXPECT_GT(visible, 20.0) << k.name << ": the emission must stand out of the noise";
    }
    std::filesystem::remove_all(dir);
}

// Bad files and grids: each error names the JSON pointer and says what is wrong.
TEST(GridMediaErrors, NameTheJsonPointer) {
    const std::string dir = temp_dir();
    write_vdb(dir + "/good.vdb",
              {float_grid("density", 4, 0.25, [](int, int, int) { return 1.f; })});
    write_vdb(dir + "/negative.vdb", {float_grid("density", 4, 0.25, [](int i, int j, int k) {
                  return i == 1 && j == 2 && k == 3 ? -0.5f : 1.f;
              })});
    write_vdb(dir + "/neg_glow.vdb",
              {float_grid("density", 4, 0.25, [](int, int, int) { return 1.f; }),
               float_grid("glow", 4, 0.25, [](int i, int j, int k) {
                   return i == 1 && j == 2 && k == 3 ? -0.5f : 1.f;
               })});
    {
        openvdb::Vec3SGrid::Ptr v = openvdb::Vec3SGrid::create();
        v->setName("velocity");
        v->tree().setValue(openvdb::Coord(0, 0, 0), openvdb::Vec3s(1.f));
        write_vdb(dir + "/vector.vdb", {v});
    }
    {
        std::ofstream f(dir + "/garbage.vdb");
        f << "not a vdb file";
    }
    {
        openvdb::FloatGrid::Ptr e = openvdb::FloatGrid::create(0.f);
        e->setName("density");
        write_vdb(dir + "/empty.vdb", {e});
    }
    const std::string head = R"(
        "camera": {"position": [0, 0, 5], "look_at": [0, 0, 0], "fov": 30, "width": 8,
                   "height": 8},
        "lights": [{"type": "environment", "radiance": 1}],
        "media": {"smoke": )";
    struct Case {
        std::string medium, pointer, words;
    };
    const std::vector<Case> cases = {
        {R"({"kind": "grid", "sigma_s": 1})", "/media/smoke", "missing required key 'file'"},
        {R"({"kind": "grid", "file": "missing.vdb", "sigma_s": 1})", "/media/smoke/file",
         "cannot read as an OpenVDB file"},
        {R"({"kind": "grid", "file": "garbage.vdb", "sigma_s": 1})", "/media/smoke/file",
         "cannot read as an OpenVDB file"},
        {R"({"kind": "grid", "file": "good.vdb", "grid": "temperature", "sigma_s": 1})",
         "/media/smoke/grid", "has no grid 'temperature' (it has: density)"},
        {R"({"kind": "grid", "file": "vector.vdb", "grid": "velocity", "sigma_s": 1})",
         "/media/smoke/grid", "is a vec3s grid, not float"},
        {R"({"kind": "grid", "file": "negative.vdb", "sigma_s": 1})", "/media/smoke/grid",
         "voxel (1, 2, 3) is -0.5"},
        {R"({"kind": "grid", "file": "empty.vdb", "sigma_s": 1})", "/media/smoke/grid",
         "has no active voxels"},
        {R"({"kind": "grid", "file": "good.vdb", "density": -1})", "/media/smoke/density", ">= 0"},
        {R"({"kind": "grid", "file": "good.vdb", "sigma_s": 1, "density": 2})",
         "/media/smoke/sigma_s", "not both"},
        {R"({"kind": "grid", "file": "good.vdb", "sigma_s": 1, "g": 1})", "/media/smoke/g",
         "anisotropy"},
        {R"({"kind": "grid", "file": "good.vdb", "emission": -1})", "/media/smoke/emission", ""},
        {R"({"kind": "grid", "file": "good.vdb", "emission": 1, "emission_grid": "flame"})",
         "/media/smoke/emission_grid", "has no grid 'flame' (it has: density)"},
        {R"({"kind": "grid", "file": "good.vdb", "emission_grid": "density"})",
         "/media/smoke/emission_grid", "needs \"emission\" > 0"},
        {R"({"kind": "grid", "file": "neg_glow.vdb", "emission": 1, "emission_grid": "glow"})",
         "/media/smoke/emission_grid", "voxel (1, 2, 3) is -0.5"},
        {R"({"kind": "grid", "file": "good.vdb", "blackbody_intensity": -0.5})",
         "/media/smoke/blackbody_intensity", "in [0, 1]"},
        {R"({"kind": "grid", "file": "good.vdb", "blackbody_intensity": 1, "temperature": -5})",
         "/media/smoke/temperature", "kelvin"},
        {R"({"kind": "grid", "file": "good.vdb", "blackbody_intensity": 1,
             "temperature_grid": "temperature"})",
         "/media/smoke/temperature_grid", "has no grid 'temperature' (it has: density)"},
        {R"({"kind": "grid", "file": "good.vdb", "temperature_grid": "density"})",
         "/media/smoke/temperature_grid", "needs \"blackbody_intensity\" > 0"},
        {R"({"kind": "grid", "file": "good.vdb", "blackbody_intensity": 1,
             "blackbody_tint": [1, -1, 1]})",
         "/media/smoke/blackbody_tint", ""},
        {R"({"kind": "grid", "file": "good.vdb", "sigma_s": 1, "transform": {"scale": [1, 0, 1]}})",
         "/media/smoke/transform", "invertible"},
        {R"({"kind": "homogeneous", "sigma_s": 1, "transform": {"scale": 2}})",
         "/media/smoke/transform", ""},
    };
    for (const Case& c : cases) {
        const std::string e = fr::testing::scene_error(dir, head + c.medium + "}", "bad.json");
        EXPECT_NE(e.find("bad.json: " + c.pointer), std::string::npos) << c.medium << "\n -> " << e;
        EXPECT_NE(e.find(c.words), std::string::npos) << c.medium << "\n -> " << e;
    }
    std::filesystem::remove_all(dir);
}
