// Environment maps (environment_map.h, the "environment" light with "file"): the sampler against
// its pdf by chi-square, the pdf's total mass, analytic renders (furnace, half sky over a
// plane), the mapping convention seen through a camera, orientation, and bad input.
//
// The maps are written here with OpenImageIO (float EXR), so the texels are known exactly.
#include <gtest/gtest.h>

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include <unistd.h>

#include "../core/chi2.h"
#include "facet/latlong.h"
#include "facet/render/environment_map.h"
#include "facet/render/light.h"
#include "facet/render/pov_export.h"
#include "facet/render/render.h"
#include "facet/render/scene_description.h"
#include "facet/testsupport/render_test_util.h"

namespace fr = facet::render;
using facet::Rgb;
using facet::Vec2;
using facet::Vec3;
using fr::testing::scene_from;

namespace {

constexpr double kPi = facet::kPiD;

// Monte Carlo counts scale with FACET_STRESS_SCALE (as the other Monte Carlo tests).
double stress_scale() {
    const char* s = std::getenv("FACET_STRESS_SCALE");
    const double v = s ? std::atof(s) : 1.0;
    return v > 0.0 ? v : 1.0;
}

std::string temp_path(const std::string& name) {
    return (std::filesystem::temp_directory_path() /
            ("facet_envmap_" + std::to_string(::getpid()) + "_" + name))
        .string();
}

// Writes a float RGB EXR of w x h texels, texel (x, y) = fn(x, y), row 0 at the top.
std::string write_map(const std::string& name, int w, int h,
                      const std::function<Rgb(int, int)>& fn) {
    const std::string path = temp_path(name);
    std::vector<float> data(std::size_t(w) * h * 3);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const Rgb c = fn(x, y);
            for (int k = 0; k < 3; ++k) data[(std::size_t(y) * w + x) * 3 + k] = c[k];
        }
    auto out = OIIO::ImageOutput::create(path);
    EXPECT_TRUE(out) << OIIO::geterror();
    OIIO::ImageSpec spec(w, h, 3, OIIO::TypeDesc::FLOAT);
    EXPECT_TRUE(out->open(path, spec));
    EXPECT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, data.data()));
    out->close();
    return path;
}

// A scene of one environment light `light` (JSON object body after "type") and `rest` (more
// members: camera, materials, shapes).
std::string env_scene(const std::string& light, const std::string& rest = "") {
    return R"("camera": {"position": [0, 0, 0], "look_at": [1, 0, 0], "up": [0, 0, 1], "fov": 10,
                 "width": 1, "height": 1},
              "lights": [{"type": "environment", )" +
           light + "}]" + (rest.empty() ? "" : ", " + rest);
}

std::string file_key(const std::string& path) {
    return R"("file": ")" + path + R"(")";
}

// The environment light as a "BxDF" for the chi-square harness (tests/core/chi2.h): wo is
// ignored, f is the radiance, the sample's pdf the light's. No ctx: the map ignores it.
struct EnvAsSampler {
    const fr::Light& light;
    std::optional<facet::BSDFSample> sample_f(Vec3, float, Vec2 u) const {
        const auto s = light.sample_li({}, u);
        if (!s) return std::nullopt;
        facet::BSDFSample b;
        b.f = s->li;
        b.wi = s->wi;
        b.pdf = s->pdf;
        b.flags = facet::BxDFFlags::Glossy;
        return b;
    }
    float pdf(Vec3, Vec3 wi) const { return light.pdf_li({}, wi, Vec3(0.f), Vec3(0.f)); }
    Rgb f(Vec3, Vec3 wi) const { return light.le_escape(wi); }
};

// Per sample: the pdf and radiance a sample reports are pdf_li and le_escape at its
// direction, up to float round-off of the (u, v) round trip. A sample within round-off of a
// texel edge may see the neighbour's value: allow 1 in 1000 such samples.
void check_sample_consistency(const fr::Light& env, const char* what) {
    pcg32 rng(11);
    int mismatches = 0;
    const int n = 20000;
    for (int i = 0; i < n; ++i) {
        const Vec2 u(facet::test::uniform_float(rng), facet::test::uniform_float(rng));
        const auto ls = env.sample_li({}, u);
        if (!ls) continue;
        const float pdf = env.pdf_li({}, ls->wi, Vec3(0.f), Vec3(0.f));
        const Rgb le = env.le_escape(ls->wi);
        bool bad = std::fabs(pdf - ls->pdf) > 1e-3f * ls->pdf;
        for (int c = 0; c < 3; ++c)
            bad |= std::fabs(le[c] - ls->li[c]) > 1e-3f * std::fmax(le[c], ls->li[c]) + 1e-6f;
        mismatches += bad;
    }
    EXPECT_LE(mismatches, n / 1000) << what;
}

// Sidak over the chi-square tests of this file (5) at alpha = 1%.
const double kAlpha = facet::test::sidak_alpha(0.01, 5);

// Chi-square of sample_li against pdf_li over the whole sphere with the BSDF tests' harness
// (tests/core/chi2.h): bins in (cos theta, phi) about world z (cos_min = -1: the fine grid
// covers the sphere), expected counts by adaptive quadrature of pdf_li. The pdf grows as
// 1 / sin(theta) toward the map's poles and jumps at texel edges, which the quadrature resolves
// only for a smooth map: used for the constant map; the others are binned in (u, v) below.
void check_sampling_world_bins(const fr::Scene& scene, const char* what) {
    const fr::Light* env = scene.environment();
    ASSERT_NE(env, nullptr);
    ASSERT_NE(env->map(), nullptr);
    facet::test::Chi2Options o;
    o.n_samples = int(200000 * stress_scale());
    o.theta_bins = 12;
    o.phi_bins = 24;
    o.cos_min = -1.0;
    // 1e-3 relative is < 1/3 of the sampling noise sqrt(e)/e of every cell with e < 1e5
    // expected samples (at most 200000 / 288 here).
    o.quad_rel_tol = 1e-3;
    o.quad_depth = 6;
    o.n_consistency = 0;  // check_sample_consistency
    const EnvAsSampler s{*env};
    const facet::test::Chi2Result r = facet::test::chi2_sampling_test(s, Vec3(0, 0, 1), o);
    EXPECT_GT(r.chi2.p_value, kAlpha) << what << ": " << r.describe();
    EXPECT_EQ(r.not_unit, 0) << what;
    EXPECT_EQ(r.bad_values, 0) << what;
    // The pdf's total mass: quadrature error only (the 1 / sin(theta) poles).
    EXPECT_NEAR(r.pdf_integral, 1.0, 2e-3) << what;
    check_sample_consistency(*env, what);
}

// Mean over the pixels of the channels' mean.
double mean_grey(const fr::Image& img) {
    double sum = 0.0;
    for (const Rgb& p : img.pixels()) sum += (double(p.r) + p.g + p.b) / 3.0;
    return sum / double(img.pixels().size());
}

// Chi-square of sample_li against pdf_li with bins of bx x by texels in the map's (u, v): each
// sample's direction is binned by `to_uv`, and a bin's expected probability is exact, the sum
// over its texels' four quadrants of pdf_li at the quadrant's centre times the solid angle
// Jacobian 2 pi^2 sin(theta) du dv (pdf * sin(theta) is bilinear over each quadrant, so its
// value at the centre is its mean: PdfFollowsTheBilinearLookup checks the form).
void check_sampling_uv_bins(const fr::Scene& scene, int bx, int by,
                            const std::function<Vec2(const Vec3&)>& to_uv, const char* what) {
    const fr::Light& env = *scene.environment();
    const fr::EnvironmentMap& m = *env.map();
    const int W = m.width(), H = m.height(), nx = W / bx, ny = H / by;
    const int n = int(200000 * stress_scale());
    std::vector<double> observed(std::size_t(nx * ny) + 1, 0.0), expected(observed.size(), 0.0);
    pcg32 rng(7);
    long failed = 0;
    for (int i = 0; i < n; ++i) {
        const Vec2 u(facet::test::uniform_float(rng), facet::test::uniform_float(rng));
        const auto ls = env.sample_li({}, u);
        if (!ls) {
            ++failed;
            observed.back() += 1;
            continue;
        }
        ASSERT_NEAR(glm::length(ls->wi), 1.f, 1e-5f);
        const Vec2 uv = to_uv(ls->wi);
        const int x = std::clamp(int(uv.x * float(nx)), 0, nx - 1);
        const int y = std::clamp(int(uv.y * float(ny)), 0, ny - 1);
        observed[std::size_t(y * nx + x)] += 1;
    }
    double mass = 0.0;
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x)
            for (int q = 0; q < 4; ++q) {
                const Vec2 c((x + 0.25f + 0.5f * float(q % 2)) / W,
                             (y + 0.25f + 0.5f * float(q / 2)) / H);
                const double p =
                    double(env.pdf_li({}, m.uv_to_direction(c), Vec3(0.f), Vec3(0.f))) * 2.0 * kPi *
                    kPi * std::sin(kPi * c.y) / (4.0 * W * H);
                expected[std::size_t((y / by) * nx + x / bx)] += n * p;
                mass += p;
            }
    EXPECT_NEAR(mass, 1.0, 1e-5) << what;
    expected.back() = std::max(0.0, n * (1.0 - mass));
    const facet::test::Chi2Statistic st = facet::test::chi2_statistic(observed, expected);
    EXPECT_FALSE(st.zero_expected_hit) << what;
    EXPECT_GT(st.p_value, kAlpha) << what << ": chi2 " << st.statistic << " dof " << st.dof
                                  << " cells " << st.cells_used << " failed " << failed;
    check_sample_consistency(env, what);
}

// (u, v) of a direction with the map unrotated, written out here (environment_map.h).
Vec2 blender_uv(const Vec3& d) {
    const double u = 0.5 - std::atan2(double(d.y), double(d.x)) / (2.0 * kPi);
    const double v = std::acos(std::clamp(double(d.z), -1.0, 1.0)) / kPi;
    return Vec2(float(u), float(v));
}

// Rec. 709 luminance of a 64 x 32 "sky": a blue gradient above the horizon brightening toward
// it, a bright warm disc (the sun, 3 texels wide) and a dark ground.
Rgb sky_texel(int x, int y) {
    const int H = 32;
    const double theta = kPi * (y + 0.5) / H;
    if (y >= H / 2) return Rgb(0.05f, 0.04f, 0.03f);  // ground
    const float elev = float(0.5 * kPi - theta);
    Rgb sky = Rgb(0.3f, 0.5f, 1.0f) * (0.4f + 0.6f * std::exp(-3.f * elev));
    const int dx = std::abs(x - 40), dy = std::abs(y - 9);
    if (dx <= 1 && dy <= 1) sky += Rgb(500.f, 450.f, 400.f) / float(1 + dx + dy);
    return sky;
}
}  // namespace

TEST(EnvironmentMap, ChiSquareConstantMap) {
    const std::string path = write_map("const.exr", 32, 16, [](int, int) { return Rgb(1.f); });
    const fr::Scene scene = scene_from(env_scene(file_key(path)));
    check_sampling_world_bins(scene, "constant map, world bins");
    check_sampling_uv_bins(scene, 2, 2, blender_uv, "constant map, (u, v) bins");
}

TEST(EnvironmentMap, ChiSquareTinySun) {
    // One texel at 1e4 times the background of a 64 x 32 map: most samples go to the sun
    // (binned alone: 1 x 1 texel bins), and the background still gets its share.
    const std::string path = write_map(
        "sun.exr", 64, 32, [](int x, int y) { return x == 20 && y == 11 ? Rgb(1e4f) : Rgb(1.f); });
    check_sampling_uv_bins(scene_from(env_scene(file_key(path))), 1, 1, blender_uv, "tiny sun");
}

TEST(EnvironmentMap, ChiSquareSkyRotatedAndTilted) {
    const std::string path = write_map("sky.exr", 64, 32, sky_texel);
    check_sampling_uv_bins(scene_from(env_scene(file_key(path))), 2, 2, blender_uv, "sky");
    const fr::Scene tilted = scene_from(env_scene(file_key(path) +
                                                  R"(, "up": [1, 1, 0.5],
                                             "rotate": {"axis": [0.3, -1, 2], "angle": 37})"));
    const fr::EnvironmentMap& m = *tilted.environment()->map();
    check_sampling_uv_bins(
        tilted, 2, 2, [&](const Vec3& d) { return m.direction_to_uv(d); },
        "sky, tilted and rotated");
}

TEST(EnvironmentMap, PdfFollowsTheBilinearLookup) {
    // pdf(d) = Y(d) s(y) / (2 pi^2 sin theta) (environment_map.h): Y the luminance of the
    // bilinear lookup, s(y) constant along a texel row. At 3 x 3 points inside every texel,
    // pdf * 2 pi^2 sin(theta) / Y is the row's one value (a wrong Jacobian, e.g. sin theta of
    // the row's centre, varies within the row; a density constant over the texel varies with
    // Y), and pdf * 2 pi^2 sin(theta) integrates to 1 over the unit square (its value at each
    // texel quadrant's centre is the quadrant's mean). Tolerance: float round-off of the
    // direction and (u, v) round trip, 1e-4 relative.
    const std::string path = write_map("pdfsky.exr", 64, 32, sky_texel);
    const fr::Scene scene = scene_from(env_scene(file_key(path) + R"(, "up": [0, 1, 1],
                                     "rotate": {"axis": [1, 0, 0], "angle": 20})"));
    const fr::Light& env = *scene.environment();
    const fr::EnvironmentMap& m = *env.map();
    const int W = m.width(), H = m.height();
    auto density = [&](Vec2 uv) {  // pdf per unit (u, v) square
        const Vec3 d = m.uv_to_direction(uv);
        return double(env.pdf_li({}, d, Vec3(0.f), Vec3(0.f))) * 2.0 * kPi * kPi *
               std::sin(kPi * uv.y);
    };
    auto lum = [&](Vec2 uv) {
        const Rgb c = m.eval(m.uv_to_direction(uv));
        return 0.2126 * c.r + 0.7152 * c.g + 0.0722 * c.b;
    };
    double total = 0.0;
    for (int y = 0; y < H; ++y) {
        double row = -1.0;
        for (int x = 0; x < W; ++x) {
            for (int j = 0; j < 3; ++j)
                for (int i = 0; i < 3; ++i) {
                    const Vec2 uv((x + 0.2f + 0.3f * i) / W, (y + 0.2f + 0.3f * j) / H);
                    const double r = density(uv) / lum(uv);
                    if (row < 0.0) row = r;
                    ASSERT_NEAR(r, row, 1e-4 * row) << "texel " << x << ", " << y;
                }
            for (int q = 0; q < 4; ++q)
                total += density({(x + 0.25f + 0.5f * float(q % 2)) / W,
                                  (y + 0.25f + 0.5f * float(q / 2)) / H}) /
                         (4.0 * W * H);
        }
    }
    EXPECT_NEAR(total, 1.0, 1e-5);
}

TEST(EnvironmentMap, GreyMapSampleWeightIsConstantAlongARow) {
    // For a grey map the density is proportional to the radiance the lookup returns, so every
    // light sample carries the same weight L / pdf up to sin(theta) against the row's
    // sin(theta_y): L / pdf * sin(theta_y) / sin(theta) is one constant, the map's integral
    // 2 pi^2 / scale. A density constant over each texel (the cell mean of the bilinear lookup)
    // fails this next to a bright texel: L / pdf then varies by the lookup's range within the
    // cell (tens of times here), the rare large samples next to an HDRI's sun. Tolerance:
    // float round-off, 1e-3 relative.
    const int W = 64, H = 32;
    const std::string path = write_map("greysun.exr", W, H, [](int x, int y) {
        if (x == 20 && y == 11) return Rgb(1e4f);
        if (x == 21 && y == 11) return Rgb(50.f);
        return Rgb(0.2f + 0.01f * float((x * 7 + y * 3) % 11));
    });
    const fr::Scene scene = scene_from(env_scene(file_key(path)));
    const fr::Light& env = *scene.environment();
    const fr::EnvironmentMap& m = *env.map();
    pcg32 rng(5);
    double ref = -1.0;
    int near_sun = 0;
    const int n = 20000;
    for (int i = 0; i < n; ++i) {
        const auto ls =
            env.sample_li({}, {facet::test::uniform_float(rng), facet::test::uniform_float(rng)});
        ASSERT_TRUE(ls);
        const Vec2 uv = m.direction_to_uv(ls->wi);
        const int y = std::min(int(uv.y * H), H - 1);
        const double w =
            double(ls->li.g) / ls->pdf * std::sin(kPi * (y + 0.5) / H) / std::sin(kPi * uv.y);
        if (ref < 0.0) ref = w;
        ASSERT_NEAR(w, ref, 1e-3 * ref) << "sample " << i << " at u " << uv.x << " v " << uv.y;
        near_sun += std::fabs(uv.x * W - 20.5f) < 1.f && std::fabs(uv.y * H - 11.5f) < 1.f;
    }
    EXPECT_GT(near_sun, n / 4);  // the sun holds most of the power
}

TEST(EnvironmentMap, BrightTexelKeepsItsOwnCell) {
    // A 1-texel sun of a 512 x 256 map (its texel 1/131072 of the map) holds the share of
    // samples its power gives, at full resolution, and is sampled only where the bilinear
    // lookup is non-zero: within one texel of the sun's centre, by the lookup's shape (half
    // the density half-way to the next texel centre, none at that centre).
    const int W = 512, H = 256, sx = 300, sy = 70;
    const std::string path = write_map("sun512.exr", W, H, [&](int x, int y) {
        return x == sx && y == sy ? Rgb(1e4f) : Rgb(0.f);
    });
    const fr::Scene scene = scene_from(env_scene(file_key(path)));
    const fr::EnvironmentMap& m = *scene.environment()->map();
    const Vec3 sun = m.uv_to_direction({(sx + 0.5f) / W, (sy + 0.5f) / H});
    const Vec3 half = m.uv_to_direction({(sx + 1.f) / W, (sy + 0.5f) / H});
    const Vec3 next = m.uv_to_direction({(sx + 1.5f) / W, (sy + 0.5f) / H});
    pcg32 rng(3);
    for (int i = 0; i < 1000; ++i) {
        const auto ls = scene.environment()->sample_li(
            {}, {facet::test::uniform_float(rng), facet::test::uniform_float(rng)});
        ASSERT_TRUE(ls);
        const Vec2 uv = m.direction_to_uv(ls->wi);
        EXPECT_LE(std::fabs(uv.x * W - (sx + 0.5f)), 1.f + 1e-3f);
        EXPECT_LE(std::fabs(uv.y * H - (sy + 0.5f)), 1.f + 1e-3f);
    }
    EXPECT_NEAR(m.pdf(sun) / m.pdf(half), 2.0, 2e-3);
    EXPECT_EQ(m.pdf(next), 0.f);
}

TEST(EnvironmentMap, FurnaceLambertSphereInConstantMapFileRendersRho) {
    // A convex Lambertian sphere under a uniform radiance 1 reflects L = rho exactly (it does
    // not see itself). The camera sees only the sphere.
    const std::string path = write_map("one.exr", 16, 8, [](int, int) { return Rgb(1.f); });
    const double rho = 0.6;
    const fr::Scene scene = scene_from(
        R"("camera": {"position": [0, -4, 0], "look_at": [0, 0, 0], "up": [0, 0, 1], "fov": 8,
                      "width": 8, "height": 8},
           "materials": {"m": {"model": "lambert", "reflectance": 0.6}},
           "shapes": [{"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": "m"}],
           "lights": [{"type": "environment", )" +
        file_key(path) + "}]");
    // 64 spp, not scaled by FACET_STRESS_SCALE: the render takes milliseconds even under
    // ASan, and the tolerances below are set from its noise.
    const int spp = 64;
    const fr::Image img = fr::render(scene, fr::testing::test_options("path", spp, 5));
    // Noise: measured over seeds 1-10, the image mean's standard deviation is 0.07% (path,
    // uniform density of the constant map with MIS against the cosine-sampled BSDF): 0.5% is
    // 7 sigma.
    EXPECT_NEAR(mean_grey(img), rho, 0.005 * rho);
    // The same through the direct integrator (light sampling only: the sampler alone must be
    // unbiased); its standard deviation is 0.32%: 2% is 6 sigma.
    const fr::Image d = fr::render(scene, fr::testing::test_options("direct", spp, 5));
    EXPECT_NEAR(mean_grey(d), rho, 0.02 * rho);
}

TEST(EnvironmentMap, HalfSkyOverLambertPlaneGivesRho) {
    // White above the horizon, black below, over an upward Lambertian plane: E = pi, L = rho,
    // except for the bilinear blend of the two rows at the horizon (the lookup falls from 1 to
    // 1/2 over the last half texel above it): E = pi (1 - delta^2 / 6), delta = pi / (2 H),
    // 1e-4 relative for H = 64.
    const int H = 64;
    const std::string path =
        write_map("half.exr", 128, H, [&](int, int y) { return y < H / 2 ? Rgb(1.f) : Rgb(0.f); });
    const double rho = 0.5;
    const fr::Scene scene = scene_from(
        R"("camera": {"position": [0, 0, 3], "look_at": [0, 0, 0], "up": [0, 1, 0], "fov": 20,
                      "width": 8, "height": 8},
           "materials": {"m": {"model": "lambert", "reflectance": 0.5}},
           "shapes": [{"type": "plane", "point": [0, 0, 0], "normal": [0, 0, 1], "material": "m"}],
           "lights": [{"type": "environment", )" +
        file_key(path) + "}]");
    const int spp = 64;  // not scaled (see the furnace test)
    const fr::Image img = fr::render(scene, fr::testing::test_options("path", spp, 9));
    const double delta = kPi / (2.0 * H);
    const double expected = rho * (1.0 - delta * delta / 6.0);
    // Noise: the image mean's standard deviation over seeds 1-10 is 0.05%: 0.3% is 6 sigma
    // (and 30 times the horizon blend).
    EXPECT_NEAR(mean_grey(img), expected, 0.003 * rho);
}

namespace {

// An 8 x 4 map whose columns have distinct colours in rows 1 and 2 (the horizon is between
// them), a red top row and a blue bottom row.
Rgb column_colour(int x) {
    return Rgb(float(x + 1), float((x + 1) * (x + 1)), 1.f);
}
Rgb mapping_texel(int x, int y) {
    if (y == 0) return Rgb(50.f, 0.f, 0.f);
    if (y == 3) return Rgb(0.f, 0.f, 50.f);
    return column_colour(x);
}

// The pixel-centre radiance (1 x 1 image, 1 spp traces the pixel centre) seen looking along
// `dir` (camera up `up`) in the map of `light`.
Rgb look(const std::string& light, const Vec3& dir, const Vec3& up) {
    auto v = [](const Vec3& a) {
        return "[" + std::to_string(a.x) + ", " + std::to_string(a.y) + ", " + std::to_string(a.z) +
               "]";
    };
    const fr::Scene scene = scene_from(R"("camera": {"position": [0, 0, 0], "look_at": )" + v(dir) +
                                       R"(, "up": )" + v(up) +
                                       R"(, "fov": 1, "width": 1, "height": 1},
           "lights": [{"type": "environment", )" +
                                       light + "}]");
    return fr::render(scene, fr::testing::test_options("path", 1, 1)).at(0, 0);
}

void expect_rgb(const Rgb& got, const Rgb& want, const char* what) {
    // Float round-off of the direction and (u, v): 1e-4 relative.
    for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(got[c], want[c], 1e-4f * std::fmax(1.f, want[c])) << what << " channel " << c;
}

}  // namespace

TEST(EnvironmentMap, MappingIsBlendersEquirectangularZUp) {
    const std::string path = write_map("cols.exr", 8, 4, mapping_texel);
    const std::string light = file_key(path);
    // u = 0.5 - atan2(y, x) / 2pi; texel centres at (x + 0.5) / 8, so u = 0.5 lies between
    // columns 3 and 4 (bilinear: their mean), u = 0.25 between 1 and 2, u = 0.75 between 5 and
    // 6, and the seam u = 0 between 7 and 0 (wrapping).
    auto mean = [](int a, int b) { return 0.5f * (column_colour(a) + column_colour(b)); };
    expect_rgb(look(light, {1, 0, 0}, {0, 0, 1}), mean(3, 4), "+X: centre column");
    expect_rgb(look(light, {0, 1, 0}, {0, 0, 1}), mean(1, 2), "+Y: u = 0.25");
    expect_rgb(look(light, {0, -1, 0}, {0, 0, 1}), mean(5, 6), "-Y: u = 0.75");
    expect_rgb(look(light, {-1, 0, 0}, {0, 0, 1}), mean(7, 0), "-X: the seam");
    // Off the column centres: 45 degrees from +X toward +Y is u = 0.375, fx = 2.5.
    expect_rgb(look(light, {1, 1, 0}, {0, 0, 1}), mean(2, 3), "+X+Y");
    expect_rgb(look(light, {0, 0, 1}, {1, 0, 0}), Rgb(50.f, 0.f, 0.f), "up: the top row");
    expect_rgb(look(light, {0, 0, -1}, {1, 0, 0}), Rgb(0.f, 0.f, 50.f), "down: the bottom row");
    // "radiance" multiplies.
    expect_rgb(look(light + R"(, "radiance": [2, 3, 0.5])", {1, 0, 0}, {0, 0, 1}),
               mean(3, 4) * Rgb(2.f, 3.f, 0.5f), "multiplier");
}

// latlong_uv takes its angles from atan2_approx (a polynomial, latlong.h): against the exact
// (u, v) in double, over random directions and the axes, poles and signed zeros. Tolerance
// 2.5e-7: the polynomial's 2e-8 rad plus float rounding of u = 0.5 - phi / 2pi near 1 (ulp
// 6e-8) and of the polynomial's terms; an error of 1e-5 (a cruder approximation) would move
// lookups by 1% of a texel of a 1024-wide map and fail here.
TEST(EnvironmentMap, LatLongUvMatchesTheExactAnglesClosely) {
    auto exact = [](const Vec3& l) {
        const double x = l.x, y = l.y, z = l.z;
        const double u = 0.5 - std::atan2(y, x) / (2.0 * kPi);
        const double v = std::atan2(std::sqrt(x * x + y * y), z) / kPi;
        return std::pair<double, double>(std::clamp(u, 0.0, 1.0), std::clamp(v, 0.0, 1.0));
    };
    double worst = 0.0;
    auto check = [&](Vec3 l) {
        float sin_theta = -1.f;
        const Vec2 uv = facet::latlong_uv(l, sin_theta);
        const auto [u, v] = exact(l);
        worst = std::max({worst, std::abs(double(uv.x) - u), std::abs(double(uv.y) - v)});
        ASSERT_NEAR(uv.x, u, 2.5e-7) << l.x << " " << l.y << " " << l.z;
        ASSERT_NEAR(uv.y, v, 2.5e-7) << l.x << " " << l.y << " " << l.z;
        EXPECT_NEAR(sin_theta, std::sqrt(double(l.x) * l.x + double(l.y) * l.y), 1e-7);
    };
    for (const Vec3& l :
         {Vec3(1, 0, 0), Vec3(-1, 0, 0), Vec3(-1, -0.f, 0), Vec3(0, 1, 0), Vec3(0, -1, 0),
          Vec3(0, 0, 1), Vec3(0, 0, -1), Vec3(1, 1, 0), Vec3(-1, 1e-30f, 0), Vec3(1e-30f, -1, 0)})
        check(glm::normalize(l));
    std::uint64_t state = 12345;
    auto next = [&] {
        state = state * 6364136223846793005ull + 1442695040888963407ull;
        return float(double(state >> 11) * 0x1.0p-53);
    };
    for (int i = 0; i < 200000; ++i) {
        const Vec3 d(2.f * next() - 1.f, 2.f * next() - 1.f, 2.f * next() - 1.f);
        if (glm::length(d) > 1e-3f) check(glm::normalize(d));
    }
    EXPECT_EQ(facet::atan2_approx(0.f, 0.f), 0.f);
    EXPECT_EQ(facet::atan2_approx(-0.f, -1.f), -float(kPi));
    EXPECT_TRUE(std::isnan(facet::atan2_approx(std::nanf(""), 1.f)));
    RecordProperty("worst_uv_error", std::to_string(worst));
}

TEST(EnvironmentMap, RotateAndUpOrientTheMapAsDocumented) {
    const std::string path = write_map("cols2.exr", 8, 4, mapping_texel);
    const std::string light = file_key(path);
    auto mean = [](int a, int b) { return 0.5f * (column_colour(a) + column_colour(b)); };
    // rotate 90 degrees about +Z (counter-clockwise from above): the map's +X turns to world
    // +Y, its +Y to world -X.
    const std::string rot = light + R"(, "rotate": {"axis": [0, 0, 1], "angle": 90})";
    expect_rgb(look(rot, {0, 1, 0}, {0, 0, 1}), mean(3, 4), "rotated: +Y sees the centre");
    expect_rgb(look(rot, {-1, 0, 0}, {0, 0, 1}), mean(1, 2), "rotated: -X sees u = 0.25");
    // up = +Y: the smallest rotation from +Z to +Y is about -X, which keeps +X: world +Y sees
    // the top row, world +X still the centre column, world -Z the map's +Y (u = 0.25).
    const std::string up = light + R"(, "up": [0, 2, 0])";
    expect_rgb(look(up, {0, 1, 0}, {1, 0, 0}), Rgb(50.f, 0.f, 0.f), "up +Y: top row");
    expect_rgb(look(up, {1, 0, 0}, {0, 1, 0}), mean(3, 4), "up +Y: +X centre");
    expect_rgb(look(up, {0, 0, -1}, {0, 1, 0}), mean(1, 2), "up +Y: -Z is the map's +Y");
    // up = -Z: a half turn about X (the map's +Y to world -Y).
    const std::string down = light + R"(, "up": [0, 0, -1])";
    expect_rgb(look(down, {0, 0, -1}, {1, 0, 0}), Rgb(50.f, 0.f, 0.f), "up -Z: top row below");
    expect_rgb(look(down, {0, -1, 0}, {0, 0, 1}), mean(1, 2), "up -Z: -Y is the map's +Y");
    // up is applied before rotate: up +Y then 90 degrees about +Y takes the map's +X to -Z.
    const std::string both =
        light + R"(, "up": [0, 1, 0], "rotate": {"axis": [0, 1, 0], "angle": 90})";
    expect_rgb(look(both, {0, 0, -1}, {0, 1, 0}), mean(3, 4), "up then rotate");
}

TEST(EnvironmentMap, MirrorReflectsTheMap) {
    // A mirror facing the camera (camera along +X sees the mirror; the reflection goes back
    // along -X): the seam columns at the mirror's reflectance (the mirror model's scale 1).
    const std::string path = write_map("cols3.exr", 8, 4, mapping_texel);
    const fr::Scene scene = scene_from(
        R"("camera": {"position": [0, 0, 0], "look_at": [1, 0, 0], "up": [0, 0, 1], "fov": 1,
                      "width": 1, "height": 1},
           "materials": {"m": {"model": "mirror"}},
           "shapes": [{"type": "quad", "material": "m",
                       "vertices": [[2, -1, -1], [2, -1, 1], [2, 1, 1], [2, 1, -1]]}],
           "lights": [{"type": "environment", )" +
        file_key(path) + "}]");
    const Rgb got = fr::render(scene, fr::testing::test_options("path", 1, 1)).at(0, 0);
    expect_rgb(got, 0.5f * (column_colour(7) + column_colour(0)), "mirror: the seam");
}

namespace {

std::string error_of(const std::string& body) {
    try {
        scene_from(body);
    } catch (const std::exception& e) {
        return e.what();
    }
    return "";
}

std::string build_error_of(const fr::LightDesc& l) {
    fr::SceneDescription d;
    d.camera.width = d.camera.height = 1;
    d.lights.push_back(l);
    try {
        fr::build_scene(d, "test");
    } catch (const std::exception& e) {
        return e.what();
    }
    return "";
}

}  // namespace

TEST(EnvironmentMap, BadInputNamesThePointerAndTheFile) {
    const std::string good = write_map("good.exr", 4, 2, [](int, int) { return Rgb(1.f); });
    const std::string missing = temp_path("missing.exr");
    std::string e = error_of(env_scene(file_key(missing)));
    EXPECT_NE(e.find("/lights/0/file"), std::string::npos) << e;
    EXPECT_NE(e.find(missing), std::string::npos) << e;
    EXPECT_NE(e.find("no such image file"), std::string::npos) << e;

    const std::string corrupt = temp_path("corrupt.exr");
    std::ofstream(corrupt) << "not an image";
    e = error_of(env_scene(file_key(corrupt)));
    EXPECT_NE(e.find("/lights/0/file"), std::string::npos) << e;
    EXPECT_NE(e.find(corrupt), std::string::npos) << e;

    // A map of zero size: a PPM header of 0 x 0 texels (OpenImageIO refuses it, or reads a
    // 0 x 0 image that texel_image_oiio.cpp refuses; either error names file and pointer).
    const std::string empty = temp_path("empty.ppm");
    std::ofstream(empty) << "P3\n0 0\n255\n";
    e = error_of(env_scene(file_key(empty)));
    EXPECT_NE(e.find("/lights/0/file"), std::string::npos) << e;
    EXPECT_NE(e.find(empty), std::string::npos) << e;

    const float nan = std::numeric_limits<float>::quiet_NaN();
    const float inf = std::numeric_limits<float>::infinity();
    for (const float bad : {nan, inf, -1.f}) {
        const std::string p = write_map("bad.exr", 4, 2, [&](int x, int y) {
            return x == 2 && y == 1 ? Rgb(1.f, bad, 1.f) : Rgb(1.f);
        });
        e = error_of(env_scene(file_key(p)));
        EXPECT_NE(e.find("/lights/0/file"), std::string::npos) << e;
        EXPECT_NE(e.find(p), std::string::npos) << e;
        EXPECT_NE(e.find("texel (2, 1) channel 1"), std::string::npos) << e;
    }

    e = error_of(env_scene(file_key(good) + R"(, "up": [0, 0, 0])"));
    EXPECT_NE(e.find("/lights/0/up"), std::string::npos) << e;
    e = error_of(env_scene(file_key(good) + R"(, "rotate": {"axis": [0, 0, 0], "angle": 3})"));
    EXPECT_NE(e.find("/lights/0/rotate/axis"), std::string::npos) << e;
    e = error_of(env_scene(file_key(good) + R"(, "rotate": {"axis": [0, 0, 1]})"));
    EXPECT_NE(e.find("/lights/0/rotate"), std::string::npos) << e;
    EXPECT_NE(e.find("angle"), std::string::npos) << e;
    e = error_of(env_scene(file_key(good) + R"(, "radiance": -1)"));
    EXPECT_NE(e.find("/lights/0/radiance"), std::string::npos) << e;
    // Orientation without a map, and a constant environment without its radiance.
    e = error_of(env_scene(R"("radiance": 1, "up": [0, 1, 0])"));
    EXPECT_NE(e.find("/lights/0/up"), std::string::npos) << e;
    e = error_of(env_scene(R"("rotate": {"axis": [0, 0, 1], "angle": 3})"));
    EXPECT_NE(e.find("/lights/0/rotate"), std::string::npos) << e;
    fr::LightDesc l;
    l.kind = fr::LightKind::Environment;
    e = build_error_of(l);
    EXPECT_NE(e.find("/lights/0/radiance"), std::string::npos) << e;

    // What JSON cannot write, a front end can: a non-finite angle or up.
    l.file = good;
    l.rotate = fr::AxisAngle{Vec3(0.f, 0.f, 1.f), std::numeric_limits<double>::infinity()};
    e = build_error_of(l);
    EXPECT_NE(e.find("/lights/0/rotate/angle"), std::string::npos) << e;
    l.rotate = fr::AxisAngle{Vec3(0.f, nan, 1.f), 10.0};
    e = build_error_of(l);
    EXPECT_NE(e.find("/lights/0/rotate/axis"), std::string::npos) << e;
    l.rotate.reset();
    l.up = Vec3(0.f, 0.f, inf);
    e = build_error_of(l);
    EXPECT_NE(e.find("/lights/0/up"), std::string::npos) << e;
}

TEST(EnvironmentMap, ConstantEnvironmentBuildsNoTableAndRoundTrips) {
    // No file: the constant light of before (no map, not sampled by next-event estimation).
    const fr::Scene c = scene_from(env_scene(R"("radiance": 0.8)"));
    ASSERT_NE(c.environment(), nullptr);
    EXPECT_EQ(c.environment()->map(), nullptr);
    EXPECT_FALSE(fr::nee_samples(*c.environment()));
    // A map: sampled by next-event estimation, power from its mean radiance (4 pi^2 R^2 L).
    const std::string path = write_map("rt.exr", 8, 4, mapping_texel);
    const std::string text = R"({"format": "facet-scene", "version": 1, )" +
                             env_scene(file_key(path) + R"(, "radiance": 2, "up": [0, 1, 0],
                     "rotate": {"axis": [1, 0, 0], "angle": 30})") +
                             "}";
    const fr::SceneDescription d = fr::parse_scene_description(text, "rt.json");
    const fr::SceneDescription again =
        fr::parse_scene_description(fr::write_scene_json(d), "again.json");
    EXPECT_TRUE(again == d);
    ASSERT_TRUE(d.lights[0].rotate);
    EXPECT_EQ(d.lights[0].rotate->angle, 30.0);
    const fr::Scene m = fr::build_scene(d, "rt");
    EXPECT_TRUE(fr::nee_samples(*m.environment()));
    // A NaN direction (never traced, but cheap to make safe) reads finite values.
    const float nan = std::numeric_limits<float>::quiet_NaN();
    EXPECT_TRUE(facet::is_finite(m.environment()->le_escape(Vec3(nan))));
    EXPECT_TRUE(std::isfinite(m.environment()->pdf_li({}, Vec3(nan), Vec3(0.f), Vec3(0.f))));
    const Rgb mean = m.environment()->map()->mean_radiance();
    EXPECT_GT(mean.r, 0.f);
    const float r = 3.f;
    EXPECT_NEAR(m.environment()->power(r).r, mean.r * 4.f * float(kPi * kPi) * r * r,
                1e-5f * mean.r * 4.f * float(kPi * kPi) * r * r);
}

namespace {

// The SDL of a scene with the environment light `light` (export-pov --environment background).
std::string export_sdl(const std::string& light, const std::string& environment = "background") {
    const fr::SceneDescription d = fr::parse_scene_description(
        R"({"format": "facet-scene", "version": 1, )" + env_scene(light) + "}", "t.json");
    fr::PovExportOptions o;
    o.environment = environment;
    return fr::export_pov(d, "t.json", o);
}

std::string export_error(const std::string& light, const std::string& environment = "background") {
    try {
        (void)export_sdl(light, environment);
    } catch (const std::exception& e) {
        return e.what();
    }
    return "";
}

}  // namespace

TEST(EnvironmentMap, PovExportIsASkySphereWithBlendersOrientation) {
    const std::string path = write_map("pov.exr", 8, 4, mapping_texel);
    const std::string light = file_key(path) + R"(, "up": [0.2, 0.3, 1],
                                                  "rotate": {"axis": [0, 0.5, 1], "angle": 40})";
    const std::string sdl = export_sdl(light);
    ASSERT_NE(sdl.find("sky_sphere"), std::string::npos) << sdl;
    ASSERT_NE(sdl.find("image_map { exr \"" + path + "\" map_type 1 interpolate 2 }"),
              std::string::npos)
        << sdl;
    // POV-Ray's matrix <a, b, c, d, e, f, g, h, i, 0, 0, 0> maps a pattern point q (a row
    // vector) to q * [[a, b, c], [d, e, f], [g, h, i]] in the world; a direction d is looked
    // up at q = d * inverse. POV-Ray's spherical map (map_type 1, its spherical_image_map):
    // u = angle from +x toward +z in the x-z plane / 2pi, v from the top = polar angle from +y /
    // pi. That must be Facet's (Blender's) (u, v) of d.
    const std::size_t at = sdl.find("matrix <");
    ASSERT_NE(at, std::string::npos);
    double m[12];
    std::istringstream in(sdl.substr(at + 8));
    for (double& x : m) {
        in >> x;
        in.ignore(1);  // the comma or '>'
    }
    // Column-vector form: world = T q, T's columns the rows (a, b, c), (d, e, f), (g, h, i).
    const glm::dmat3 t(glm::dvec3(m[0], m[1], m[2]), glm::dvec3(m[3], m[4], m[5]),
                       glm::dvec3(m[6], m[7], m[8]));
    const glm::dmat3 inverse = glm::inverse(t);
    const fr::Scene scene = scene_from(env_scene(light));
    const fr::EnvironmentMap& map = *scene.environment()->map();
    pcg32 rng(5);
    for (int i = 0; i < 1000; ++i) {
        const Vec3 d = facet::sample_uniform_sphere(
            {facet::test::uniform_float(rng), facet::test::uniform_float(rng)});
        const glm::dvec3 q = glm::normalize(inverse * glm::dvec3(d));
        double u = std::atan2(q.z, q.x) / (2.0 * kPi);
        if (u < 0.0) u += 1.0;
        const double v = std::acos(std::clamp(q.y, -1.0, 1.0)) / kPi;
        const Vec2 want = map.direction_to_uv(d);
        // Float round-off of Facet's lookup (1e-5), across the seam modulo 1.
        const double du = std::fabs(u - want.x);
        EXPECT_LT(std::min(du, 1.0 - du), 1e-5) << d.x << " " << d.y << " " << d.z;
        EXPECT_NEAR(v, want.y, 1e-5);
    }
}

TEST(EnvironmentMap, PovExportErrorsNameThePointer) {
    const std::string path = write_map("pov2.exr", 8, 4, mapping_texel);
    std::string e = export_error(file_key(path), "error");
    EXPECT_NE(e.find("/lights/0: an environment light"), std::string::npos) << e;
    e = export_error(file_key(path) + R"(, "radiance": 2)");
    EXPECT_NE(e.find("/lights/0/radiance"), std::string::npos) << e;
    e = export_error(file_key(temp_path("sky.png")));
    EXPECT_NE(e.find("/lights/0/file"), std::string::npos) << e;
    e = export_error(file_key(path) + R"(, "up": [0, 0, 0])");
    EXPECT_NE(e.find("/lights/0/up"), std::string::npos) << e;
}

// Lossy EXR codecs undershoot near black (Blender's own studio-light HDRIs hold texels down to
// 2.5% of their mean below zero): a negative texel within 5% of the map's mean reads as 0 with
// one warning naming the pointer and the file; one below that stays an error
// (BadInputNamesThePointerAndTheFile).
TEST(EnvironmentMap, CompressionNoiseBelowZeroReadsZeroWithAWarning) {
    const std::string path = write_map("noise.exr", 4, 2, [](int x, int y) {
        return x == 2 && y == 1 ? Rgb(1.f, -1e-4f, 1.f) : Rgb(1.f);
    });
    const fr::Scene scene = scene_from(env_scene(file_key(path)));
    ASSERT_EQ(scene.warnings().size(), 1u);
    const std::string& w = scene.warnings()[0];
    EXPECT_NE(w.find("/lights/0/file"), std::string::npos) << w;
    EXPECT_NE(w.find(path), std::string::npos) << w;
    EXPECT_NE(w.find("1 slightly negative texel value"), std::string::npos) << w;
    // The clamped texel is exactly 0: at its centre the bilinear lookup is the texel itself.
    const fr::EnvironmentMap& m = *scene.environment()->map();
    const Rgb c = m.eval(m.uv_to_direction(Vec2(2.5f / 4.f, 1.5f / 2.f)));
    EXPECT_NEAR(c.y, 0.f, 1e-6f);
    EXPECT_NEAR(c.x, 1.f, 1e-6f);
    // 0.06 below zero with a mean of ~1 is more than noise.
    const std::string bad = write_map("noise_bad.exr", 4, 2, [](int x, int y) {
        return x == 2 && y == 1 ? Rgb(1.f, -0.06f, 1.f) : Rgb(1.f);
    });
    const std::string e = error_of(env_scene(file_key(bad)));
    EXPECT_NE(e.find("/lights/0/file"), std::string::npos) << e;
    EXPECT_NE(e.find("texel (2, 1) channel 1 is negative"), std::string::npos) << e;
}

// Real content: every studio-light HDRI Blender 3.4 ships (CC0) loads as an environment map, its
// compression-noise texels (down to -0.0039) read as 0 with at most one warning; none fails.
TEST(EnvironmentMap, BlenderStudioHdrisLoad) {
    const std::filesystem::path dir = "/usr/share/blender/datafiles/studiolights/world";
    if (!std::filesystem::is_directory(dir)) GTEST_SKIP() << dir << " is not installed (blender)";
    int maps = 0;
    for (const auto& entry : std::filesystem::directory_iterator(dir)) {
        if (entry.path().extension() != ".exr") continue;
        ++maps;
        const fr::Scene scene = scene_from(env_scene(file_key(entry.path().string())));
        EXPECT_LE(scene.warnings().size(), 1u) << entry.path();
        EXPECT_NE(scene.environment()->map(), nullptr) << entry.path();
    }
    EXPECT_GE(maps, 8);
}

// --environment light: the map as the sky_sphere plus povray-facet's brdf_sky_sampling in
// global_settings (--sky-samples); a constant as a plain sky_sphere pigment; refused with
// --radiosity (the sky would light diffuse surfaces twice).
TEST(EnvironmentMap, PovExportLightIsASkySphereWithBrdfSkySampling) {
    const std::string path = write_map("povlight.exr", 8, 4, mapping_texel);
    std::string sdl = export_sdl(file_key(path), "light");
    EXPECT_NE(sdl.find("brdf_sky_sampling 16"), std::string::npos) << sdl;
    EXPECT_LT(sdl.find("global_settings"), sdl.find("brdf_sky_sampling"));
    EXPECT_NE(sdl.find("image_map { exr \"" + path + "\" map_type 1 interpolate 2 }"),
              std::string::npos)
        << sdl;
    sdl = export_sdl(R"("radiance": [0.5, 0.25, 1])", "light");
    EXPECT_NE(sdl.find("sky_sphere { pigment { rgb <0.5, 0.25, 1> } }"), std::string::npos) << sdl;
    EXPECT_NE(sdl.find("brdf_sky_sampling 16"), std::string::npos) << sdl;
    // Without --environment light the keyword is never written.
    sdl = export_sdl(file_key(path), "background");
    EXPECT_EQ(sdl.find("brdf_sky_sampling"), std::string::npos) << sdl;
    fr::PovExportOptions o;
    o.environment = "light";
    o.radiosity = "low";
    EXPECT_THROW(fr::check_pov_options(o), std::invalid_argument);
    o.radiosity = "off";
    o.sky_samples = 0;
    EXPECT_THROW(fr::check_pov_options(o), std::invalid_argument);
}

// The lat-long mapping and the table live in the core (facet/latlong.h) and are shared with the
// POV-Ray bridge: the map's (u, v) is the core's of the direction in the map's frame, and the
// map's pdf is the core table's.
TEST(EnvironmentMap, UsesTheCoresLatLongTable) {
    const std::string path = write_map("core.exr", 8, 4, mapping_texel);
    const fr::Scene scene = scene_from(env_scene(file_key(path) + R"(, "up": [0, 1, 0])"));
    const fr::EnvironmentMap& m = *scene.environment()->map();
    pcg32 rng(11);
    for (int i = 0; i < 200; ++i) {
        const Vec2 uv(facet::test::uniform_float(rng),
                      0.05f + 0.9f * facet::test::uniform_float(rng));
        const Vec3 d = m.uv_to_direction(uv);
        // up [0, 1, 0]: the map's +Z is world +Y, so the core's direction is rotated.
        const Vec3 l = facet::latlong_direction(uv);
        EXPECT_NEAR(d.y, l.z, 1e-5f);
        const Vec2 back = m.direction_to_uv(d);
        EXPECT_NEAR(back.x, uv.x, 1e-4f);
        EXPECT_NEAR(back.y, uv.y, 1e-4f);
    }
}
