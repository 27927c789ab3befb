// The denoiser (denoise.h): pass-through of constant and noise-free inputs, edges kept across
// albedo and normal discontinuities, no NaN/Inf from degenerate inputs, errors naming the
// argument, determinism over thread counts, and an error reduction on a real render (the
// Cornell box) against a high-spp reference.
#include <gtest/gtest.h>
#include <xmmintrin.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>
#include <string>

#include "facet/render/aov.h"
#include "facet/render/denoise.h"
#include "facet/render/render.h"
#include "facet/render/scene.h"
#include "facet/render/scene_description.h"
#include "facet/testsupport/render_test_util.h"

using namespace facet;
using namespace facet::render;

namespace {

const std::string kScenes = FACET_SCENES_DIR;

Image filled(int w, int h, Rgb c) {
    Image img(w, h);
    for (Rgb& p : img.pixels()) p = c;
    return img;
}

struct Inputs {
    Image a, b, albedo, normal, depth;
    DenoiseInput view() const { return {&a, &b, &albedo, &normal, &depth}; }
};

Inputs constant_inputs(int w, int h, Rgb colour) {
    return {filled(w, h, colour), filled(w, h, colour), filled(w, h, Rgb(0.5f)),
            filled(w, h, Rgb(0.f, 0.f, 1.f)), filled(w, h, Rgb(3.f))};
}

double mse(const Image& x, const Image& ref) {
    double s = 0.0;
    for (std::size_t i = 0; i < x.pixels().size(); ++i)
        for (int c = 0; c < 3; ++c) {
            const double d = double(x.pixels()[i][c]) - double(ref.pixels()[i][c]);
            s += d * d;
        }
    return s / double(3 * x.pixels().size());
}

bool all_finite(const Image& img) {
    for (const Rgb& p : img.pixels())
        if (!is_finite(p)) return false;
    return true;
}

std::string error_of(const DenoiseInput& in, const DenoiseOptions& o = {}) {
    try {
        denoise(in, o);
    } catch (const std::invalid_argument& e) {
        return e.what();
    }
    return "";
}

// A split scene: the left half albedo `left`, the right half `right` (a sharp albedo edge at
// x = w / 2), lit evenly (true radiance = albedo), with Gaussian noise of deviation sigma per
// half-buffer.
Inputs albedo_edge(int w, int h, Rgb left, Rgb right, float sigma, Image& truth) {
    Inputs in = constant_inputs(w, h, Rgb(0.f));
    truth = Image(w, h);
    std::mt19937 rng(5);
    std::normal_distribution<float> N(0.f, sigma);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const Rgb a = x < w / 2 ? left : right;
            in.albedo.at(x, y) = a;
            truth.at(x, y) = a;
            in.a.at(x, y) = a + Rgb(N(rng), N(rng), N(rng));
            in.b.at(x, y) = a + Rgb(N(rng), N(rng), N(rng));
        }
    return in;
}

// Root-mean-square error over the pixel columns next to x = w / 2 (two on each side).
double edge_rmse(const Image& x, const Image& truth) {
    double s = 0.0;
    int n = 0;
    for (int y = 0; y < x.height(); ++y)
        for (int c = x.width() / 2 - 2; c < x.width() / 2 + 2; ++c)
            for (int k = 0; k < 3; ++k) {
                const double d = double(x.at(c, y)[k]) - double(truth.at(c, y)[k]);
                s += d * d;
                ++n;
            }
    return std::sqrt(s / n);
}

}  // namespace

// Every weight multiplies the same value, so the mean is the value up to float rounding of
// the normalised sums (1e-5 relative: ~100 float additions of terms near 1).
TEST(Denoise, ConstantImagePassesThrough) {
    const Rgb c(0.25f, 1.5f, 40.f);
    const Inputs in = constant_inputs(37, 23, c);
    const Image out = denoise(in.view());
    for (const Rgb& p : out.pixels())
        for (int k = 0; k < 3; ++k) EXPECT_NEAR(p[k], c[k], 1e-5 * c[k]);
}

// Equal halves mean zero variance: any colour difference then gives a neighbour the weight
// exp(-d) with d >= (difference^2) / 1e-10, so only neighbours within ~1e-5 of the pixel's own
// value count; 1e-4 relative allows that and float rounding.
TEST(Denoise, NoiseFreeRenderPassesThrough) {
    SceneDescription d = read_scene_description(kScenes + "/cornell_box.json");
    d.camera.width = 48;
    d.camera.height = 48;
    const Scene scene = build_scene(d, "cornell_box.json");
    RenderSession session(scene, facet::render::testing::test_options("path", 16, 1));
    session.render();
    const Image img = session.image();
    AovOptions ao;
    ao.which = kAovAlbedo | kAovNormal | kAovDepth;
    ao.spp = 4;
    const Aovs f = render_aovs(scene, ao);
    const DenoiseInput in{&img, &img, &f.albedo, &f.normal, &f.depth};
    const Image out = denoise(in);
    for (std::size_t i = 0; i < out.pixels().size(); ++i)
        for (int k = 0; k < 3; ++k)
            EXPECT_NEAR(out.pixels()[i][k], img.pixels()[i][k], 1e-4 * img.pixels()[i][k] + 1e-7)
                << "pixel " << i;
}

// A sharp albedo edge (0.8 against 0.1) under noise of deviation 0.1 per half: the albedo
// feature keeps the two sides apart, so the RMSE at the four columns around the edge falls
// below the noise of the mean of the halves (0.1 / sqrt 2 = 0.071); blurring across the edge
// would put an error of ~0.35 on those columns. Bound: a third of the raw noise.
TEST(Denoise, AlbedoEdgeIsKept) {
    Image truth;
    const Inputs in = albedo_edge(64, 48, Rgb(0.8f), Rgb(0.1f), 0.1f, truth);
    const Image out = denoise(in.view());
    EXPECT_LT(edge_rmse(out, truth), 0.071 / 3.0);
    EXPECT_LT(mse(out, truth), mse(in.a, truth) / 10.0);  // the flat sides are denoised
}

// A normal crease: constant albedo, the left half facing +z with radiance 0.45 and the right
// half facing +x with radiance 0.35 (two faces of a box), the same noise: a step of the size of
// the noise, which colour alone cannot see, so the normal feature must keep them apart (same
// bound as above; blurring puts ~0.05 on the columns at the crease).
TEST(Denoise, NormalCreaseIsKept) {
    Image truth;
    Inputs in = albedo_edge(64, 48, Rgb(0.45f), Rgb(0.35f), 0.1f, truth);
    for (int y = 0; y < 48; ++y)
        for (int x = 0; x < 64; ++x) {
            in.albedo.at(x, y) = Rgb(0.5f);
            in.normal.at(x, y) = x < 32 ? Rgb(0.f, 0.f, 1.f) : Rgb(1.f, 0.f, 0.f);
        }
    const Image out = denoise(in.view());
    EXPECT_LT(edge_rmse(out, truth), 0.071 / 3.0);
}

// The test above can fail: without the normal feature (both faces with one normal) the same
// input blurs across the crease.
TEST(Denoise, WithoutTheFeatureTheCreaseBlurs) {
    Image truth;
    Inputs in = albedo_edge(64, 48, Rgb(0.45f), Rgb(0.35f), 0.1f, truth);
    for (Rgb& a : in.albedo.pixels()) a = Rgb(0.5f);
    const Image out = denoise(in.view());
    EXPECT_GT(edge_rmse(out, truth), 0.071 / 3.0);
}

// Zero variance, an all-black image, a 1e4 firefly over a dim image, zero albedo and depth at
// kMissDepth: finite output everywhere, black stays black.
TEST(Denoise, DegenerateInputsGiveFiniteOutput) {
    Inputs black = constant_inputs(20, 20, Rgb(0.f));
    black.albedo = filled(20, 20, Rgb(0.f));
    black.depth = filled(20, 20, Rgb(kMissDepth));
    black.normal = filled(20, 20, Rgb(0.f));
    const Image out = denoise(black.view());
    for (const Rgb& p : out.pixels()) EXPECT_EQ(p, Rgb(0.f));

    Image truth;
    Inputs fire = albedo_edge(32, 32, Rgb(0.1f), Rgb(0.1f), 0.05f, truth);
    fire.a.at(10, 10) = Rgb(1e4f);
    fire.b.at(20, 5) = Rgb(1e4f, 0.f, 1e3f);
    fire.depth.at(3, 3) = Rgb(kMissDepth);
    fire.albedo.at(4, 4) = Rgb(0.f);
    const Image fo = denoise(fire.view());
    EXPECT_TRUE(all_finite(fo));
}

TEST(Denoise, BadInputNamesTheArgument) {
    Inputs in = constant_inputs(8, 8, Rgb(1.f));
    Image small = filled(4, 8, Rgb(0.f));
    DenoiseInput v = in.view();
    v.normal = &small;
    EXPECT_NE(error_of(v).find("normal: 4 x 8 pixels, but half_a is 8 x 8"), std::string::npos)
        << error_of(v);
    v = in.view();
    v.depth = nullptr;
    EXPECT_NE(error_of(v).find("depth: missing"), std::string::npos) << error_of(v);
    Image empty;
    v = in.view();
    v.albedo = &empty;
    EXPECT_NE(error_of(v).find("albedo: missing"), std::string::npos) << error_of(v);
    in.b.at(3, 5) = Rgb(0.f, std::nanf(""), 0.f);
    EXPECT_NE(error_of(in.view()).find("half_b: pixel (3, 5) is not finite"), std::string::npos)
        << error_of(in.view());
    in.b.at(3, 5) = Rgb(0.f);
    DenoiseOptions o;
    o.radius = 0;
    EXPECT_NE(error_of(in.view(), o).find("radius: expected 1..20, got 0"), std::string::npos);
}

TEST(Denoise, SameImageOnOneAndTwoThreads) {
    Image truth;
    const Inputs in = albedo_edge(50, 70, Rgb(0.3f, 0.5f, 0.7f), Rgb(0.9f), 0.2f, truth);
    DenoiseOptions one, two;
    one.threads = 1;
    two.threads = 2;
    EXPECT_EQ(denoise(in.view(), one).pixels(), denoise(in.view(), two).pixels());
}

// The bits do not depend on the calling thread's floating-point mode: with flush-to-zero and
// denormals-are-zero set by the caller (as Embree's render threads run), on one thread so that
// the work runs on the caller, a dim image (values near 1e-38, where values and weights times
// values fall below float's normal range) denoises exactly as in the default mode.
TEST(Denoise, SameImageWhateverTheCallersFloatMode) {
    Image truth;
    Inputs in = albedo_edge(40, 30, Rgb(0.3f), Rgb(0.7f), 0.2f, truth);
    for (Image* img : {&in.a, &in.b})
        for (Rgb& p : img->pixels()) p *= 3e-38f;
    DenoiseOptions one;
    one.threads = 1;
    const Image plain = denoise(in.view(), one);
    const unsigned saved = _mm_getcsr();
    _mm_setcsr(saved | 0x8040u);
    const Image flushed = denoise(in.view(), one);
    _mm_setcsr(saved);
    EXPECT_EQ(plain.pixels(), flushed.pixels());
}

// A real render: the Cornell box at 128 x 128. Its 16-spp render denoised has a lower MSE
// against a 1024-spp reference (whose own noise is 1/64 of the 16-spp variance) than the plain
// 64-spp render, i.e. the denoiser is worth more than 4x the samples (measured: ~2.3x below the
// 64-spp MSE; bench/denoise_bench.py measures against 128 spp at full size). The pixels within
// one pixel of the light (the emission AOV) are left out: their error is the coverage noise
// of the light's outline, which both halves share (the film positions are stratified), so no
// denoiser can see it, and it falls only with samples.
TEST(Denoise, CornellBox16SppDenoisedBeats64SppPlain) {
    const double scale = facet::render::testing::stress_scale();
    SceneDescription d = read_scene_description(kScenes + "/cornell_box.json");
    d.camera.width = 128;
    d.camera.height = 128;
    const Scene scene = build_scene(d, "cornell_box.json");
    const int ref_spp = scale < 1.0 ? 256 : 1024;
    auto render = [&](int spp, int begin, int end, std::uint64_t seed) {
        RenderOptions o = facet::render::testing::test_options("path", spp, seed);
        o.sample_begin = begin;
        o.sample_end = end;
        RenderSession s(scene, o);
        s.render();
        return s.image();
    };
    const Image ref = render(ref_spp, 0, 0, 99);
    const Image plain64 = render(64, 0, 0, 7);
    const Image a = render(16, 0, 8, 7), b = render(16, 8, 16, 7);
    AovOptions ao;
    ao.which = kAovAlbedo | kAovNormal | kAovDepth | kAovEmission;
    ao.spp = 16;
    const Aovs f = render_aovs(scene, ao);
    const Image out = denoise({&a, &b, &f.albedo, &f.normal, &f.depth});
    auto masked_mse = [&](const Image& x) {
        double s = 0.0;
        int n = 0;
        for (int y = 0; y < x.height(); ++y)
            for (int xx = 0; xx < x.width(); ++xx) {
                bool near_light = false;
                for (int dy = -1; dy <= 1; ++dy)
                    for (int dx = -1; dx <= 1; ++dx) {
                        const int u = std::clamp(xx + dx, 0, x.width() - 1);
                        const int v = std::clamp(y + dy, 0, x.height() - 1);
                        near_light = near_light || max_component(f.emission.at(u, v)) > 0.f;
                    }
                if (near_light) continue;
                for (int c = 0; c < 3; ++c) {
                    const double e = double(x.at(xx, y)[c]) - double(ref.at(xx, y)[c]);
                    s += e * e;
                }
                ++n;
            }
        return s / (3.0 * n);
    };
    const double m_den = masked_mse(out), m64 = masked_mse(plain64);
    EXPECT_LT(m_den, m64) << "denoised 16 spp " << m_den << ", plain 64 spp " << m64;
}

namespace {

// The albedo-edge scene as colour and variance: the mean of the halves and the variance of
// that mean, sigma^2 / 2 per channel.
struct ColourInputs {
    Inputs in;
    Image color, variance;
    DenoiseInput view() const {
        DenoiseInput v{nullptr, nullptr, &in.albedo, &in.normal, &in.depth};
        v.color = &color;
        v.variance = &variance;
        return v;
    }
};

ColourInputs as_colour(Inputs in, float sigma) {
    ColourInputs c{std::move(in), Image(), Image()};
    c.color = Image(c.in.a.width(), c.in.a.height());
    for (std::size_t i = 0; i < c.color.pixels().size(); ++i)
        c.color.pixels()[i] = (c.in.a.pixels()[i] + c.in.b.pixels()[i]) * 0.5f;
    c.variance = filled(c.in.a.width(), c.in.a.height(), Rgb(0.5f * sigma * sigma));
    return c;
}

}  // namespace

// Colour and variance instead of halves: the same edge bound as AlbedoEdgeIsKept, and the flat
// sides denoised (MSE a tenth of the input's).
TEST(Denoise, ColourAndVarianceKeepTheEdgeAndDenoise) {
    Image truth;
    const ColourInputs c = as_colour(albedo_edge(64, 48, Rgb(0.8f), Rgb(0.1f), 0.1f, truth), 0.1f);
    const Image out = denoise(c.view());
    EXPECT_LT(edge_rmse(out, truth), 0.071 / 3.0);
    EXPECT_LT(mse(out, truth), mse(c.color, truth) / 10.0);
}

// A constant colour of zero variance passes through (bound as ConstantImagePassesThrough).
TEST(Denoise, ColourOfZeroVariancePassesThrough) {
    const Rgb k(0.25f, 1.5f, 40.f);
    ColourInputs c = as_colour(constant_inputs(37, 23, k), 0.f);
    const Image out = denoise(c.view());
    for (const Rgb& p : out.pixels())
        for (int i = 0; i < 3; ++i) EXPECT_NEAR(p[i], k[i], 1e-5 * k[i]);
}

TEST(Denoise, BadColourInputNamesTheArgument) {
    Image truth;
    ColourInputs c = as_colour(albedo_edge(8, 8, Rgb(0.5f), Rgb(0.5f), 0.1f, truth), 0.1f);
    DenoiseInput v = c.view();
    v.variance = nullptr;
    EXPECT_NE(error_of(v).find("variance: missing"), std::string::npos) << error_of(v);
    v = c.view();
    v.color = nullptr;
    EXPECT_NE(error_of(v).find("color: missing"), std::string::npos) << error_of(v);
    v = c.view();
    v.half_a = &c.in.a;
    v.half_b = &c.in.b;
    EXPECT_NE(error_of(v).find("color: give either half_a and half_b, or color and variance"),
              std::string::npos)
        << error_of(v);
    Image small = filled(4, 8, Rgb(0.f));
    v = c.view();
    v.albedo_variance = &small;
    EXPECT_NE(error_of(v).find("albedo_variance: 4 x 8 pixels, but color is 8 x 8"),
              std::string::npos)
        << error_of(v);
    c.variance.at(2, 6) = Rgb(0.f, -1e-3f, 0.f);
    EXPECT_NE(error_of(c.view()).find("variance: pixel (2, 6) is negative"), std::string::npos)
        << error_of(c.view());
    Image negative = filled(8, 8, Rgb(0.f));
    negative.at(1, 1) = Rgb(-1.f);
    v = c.view();
    c.variance.at(2, 6) = Rgb(0.f);
    v.depth_variance = &negative;
    EXPECT_NE(error_of(v).find("depth_variance: pixel (1, 1) is negative"), std::string::npos)
        << error_of(v);
}

namespace {

// A flat grey (radiance 0.4, noise sigma 0.1 per half) whose normal feature is noisy, as under
// depth of field: (0, 0, 1) plus Gaussian noise of deviation 0.3 per channel.
Inputs noisy_normal_scene(Image& truth, Image& normal_variance) {
    Inputs in = albedo_edge(64, 48, Rgb(0.4f), Rgb(0.4f), 0.1f, truth);
    std::mt19937 rng(11);
    std::normal_distribution<float> N(0.f, 0.3f);
    for (Rgb& n : in.normal.pixels()) n = Rgb(N(rng), N(rng), 1.f + N(rng));
    for (Rgb& a : in.albedo.pixels()) a = Rgb(0.5f);
    normal_variance = filled(64, 48, Rgb(0.09f));
    return in;
}

}  // namespace

// Without its variance the noisy normal blocks the averaging: two pixels' normals differ by
// 2 x 0.09 x 3 = 0.54 in expectation against a bandwidth of 0.2^2 = 0.04, a weight of
// ~exp(-13). With it that difference is cancelled and the bandwidth widened. Measured: the
// MSE falls about tenfold; bound: a third.
TEST(Denoise, NoisyNormalWithItsVarianceIsDownWeighted) {
    Image truth, nv;
    const Inputs in = noisy_normal_scene(truth, nv);
    const Image without = denoise(in.view());
    DenoiseInput v = in.view();
    v.normal_variance = &nv;
    const Image with = denoise(v);
    EXPECT_LT(mse(with, truth), mse(without, truth) / 3.0)
        << mse(with, truth) << " " << mse(without, truth);
}

// Zero feature variances are noise-free features: the same bits as none given.
TEST(Denoise, ZeroFeatureVariancesChangeNothing) {
    Image truth;
    const Inputs in = albedo_edge(40, 30, Rgb(0.3f, 0.5f, 0.7f), Rgb(0.9f), 0.2f, truth);
    const Image zero = filled(40, 30, Rgb(0.f));
    DenoiseInput v = in.view();
    v.albedo_variance = &zero;
    v.normal_variance = &zero;
    v.depth_variance = &zero;
    EXPECT_EQ(denoise(v).pixels(), denoise(in.view()).pixels());
}

// --- the renderer's feature variances (aov.h) ------------------------------------------------

namespace {

// A scene from the JSON of its camera, materials, shapes and lights (scenes/FORMAT.md).
Scene scene_from(const std::string& body) {
    const std::string text = R"({"format": "facet-scene", "version": 1, )" + body + "}";
    return build_scene(parse_scene_description(text, "test.json", "."), "test.json");
}

// A wall facing the camera at depth 4 and, optionally, a red sphere in front of it at depth
// ~1.2, with a thin lens focused on the wall (aperture radius 0.1): the sphere's circle of
// confusion has a radius of 0.1 |1/4 - 1/1.2| (24 / tan 20 deg) = 3.8 pixels (coc_radius_px in
// test_camera.cpp). `wall` is its material.
Scene lens_scene(const std::string& wall, bool sphere) {
    const std::string cam =
        R"("camera": {"position": [0, 0, 0], "look_at": [0, 0, -1], "fov": 40, "width": 64,
                      "height": 48, "aperture_radius": 0.1, "focus_distance": 4},
           "render": {"integrator": "path", "max_depth": 4},)";
    std::string shapes = R"("shapes": [{"type": "quad", "material": )" + wall +
                         R"(, "vertices": [[-3, -3, -4], [3, -3, -4], [3, 3, -4], [-3, 3, -4]]})";
    if (sphere)
        shapes += R"(, {"type": "sphere", "center": [0.25, 0.05, -1.2], "radius": 0.3,
                       "material": {"model": "lambert", "reflectance": [0.7, 0.15, 0.1]}})";
    shapes += "],";
    return scene_from(cam + shapes +
                      R"("lights": [{"type": "environment", "radiance": 0.4},
                                    {"type": "point", "position": [1.5, 2, 0], "power": 60}])");
}

const std::string kPlainWall = R"({"model": "lambert", "reflectance": [0.6, 0.5, 0.4]})";
const std::string kCheckerWall =
    R"({"model": "lambert", "reflectance": {"checker": {"colors": [[0.8, 0.8, 0.75],
        [0.1, 0.12, 0.1]], "scale": 6}}})";

Aovs features_of(const Scene& scene, int spp, int threads = 2) {
    AovOptions ao;
    ao.which = kAovAlbedo | kAovNormal | kAovDepth;
    ao.spp = spp;
    ao.seed = 3;
    ao.threads = threads;
    ao.variances = true;
    return render_aovs(scene, ao);
}

}  // namespace

// A flat wall of one albedo, facing the camera, under a thin lens: every sample of a pixel has
// the same albedo, normal and view-axis depth (the plane is perpendicular to the view axis)
// up to float rounding, which the variance floor (aov.h: a spread of at most 2^-44 of the mean
// square) absorbs. So every variance is exactly 0.
TEST(Denoise, ConstantFeaturesHaveZeroVariance) {
    const Scene scene = lens_scene(kPlainWall, false);
    const Aovs f = features_of(scene, 16);
    ASSERT_EQ(f.albedo_variance.width(), 64);
    for (const Image* v : {&f.albedo_variance, &f.normal_variance, &f.depth_variance})
        for (const Rgb& p : v->pixels()) ASSERT_EQ(p, Rgb(0.f));
    for (const Rgb& d : f.depth.pixels()) ASSERT_NEAR(d.r, 4.f, 1e-5f);
}

// At the edge of a surface against the background a sample's normal z is 1 (the wall's unit
// normal toward the camera) or 0 (a miss), so the variance of the mean of n = 16 is exactly
// m (1 - m) / (n - 1), m the mean: the samples' unbiased variance n m (1 - m) / (n - 1), over
// n. A quarter of the image is covered (a quad corner at the centre, pinhole camera);
// tolerance: float rounding of the resolved values (1e-6 relative, plus 1e-9).
TEST(Denoise, FeatureVarianceIsTheVarianceOfTheMean) {
    const Scene scene = scene_from(
        R"("camera": {"position": [0, 0, 0], "look_at": [0, 0, -1], "fov": 40, "width": 40,
                      "height": 30},
           "shapes": [{"type": "quad", "material": {"model": "lambert", "reflectance": 0.5},
                       "vertices": [[0.013, 0.017, -4], [5, 0.2, -4], [5, 5, -4],
                                    [0.1, 5, -4]]}],
           "lights": [{"type": "environment", "radiance": 1}])");
    const int n = 16;
    const Aovs f = features_of(scene, n);
    int mixed = 0;
    for (int y = 0; y < 30; ++y)
        for (int x = 0; x < 40; ++x) {
            const float m = f.normal.at(x, y).z;
            const double expected = double(m) * (1.0 - m) / (n - 1);
            EXPECT_NEAR(f.normal_variance.at(x, y).z, expected, 1e-6 * expected + 1e-9)
                << x << ", " << y;
            EXPECT_EQ(f.depth_variance.at(x, y).r, 0.f) << x << ", " << y;  // a plane
            mixed += m > 0.f && m < 1.f;
        }
    EXPECT_GT(mixed, 20);  // the quad's two edges cross ~35 pixels
}

// Bit-identical on 1 and 2 threads, and a region's features and variances (as facet-farm
// renders them per tile) are the whole image's pixels there: each pixel's sums are its own.
TEST(Denoise, FeatureVariancesDoNotDependOnTheThreadsOrTheRegion) {
    const Scene scene = lens_scene(kCheckerWall, true);
    const Aovs a = features_of(scene, 8, 1), b = features_of(scene, 8, 2);
    EXPECT_EQ(a.albedo_variance.pixels(), b.albedo_variance.pixels());
    EXPECT_EQ(a.normal_variance.pixels(), b.normal_variance.pixels());
    EXPECT_EQ(a.depth_variance.pixels(), b.depth_variance.pixels());
    AovOptions ao;
    ao.which = kAovAlbedo | kAovNormal | kAovDepth;
    ao.spp = 8;
    ao.seed = 3;
    ao.variances = true;
    ao.region = Region{13, 7, 50, 31};
    const Aovs part = render_aovs(scene, ao);
    ASSERT_EQ(part.depth_variance.width(), 37);
    ASSERT_EQ(part.depth_variance.height(), 24);
    const std::pair<const Image*, const Image*> pairs[] = {
        {&part.albedo, &a.albedo},
        {&part.normal, &a.normal},
        {&part.depth, &a.depth},
        {&part.albedo_variance, &a.albedo_variance},
        {&part.normal_variance, &a.normal_variance},
        {&part.depth_variance, &a.depth_variance}};
    for (const auto& [p, whole] : pairs)
        for (int y = 0; y < 24; ++y)
            for (int x = 0; x < 37; ++x) ASSERT_EQ(p->at(x, y), whole->at(13 + x, 7 + y));
    ao.region = Region{0, 0, 65, 10};
    EXPECT_THROW(render_aovs(scene, ao), std::invalid_argument);
}

// Depth of field: the red sphere in front of the checker wall is out of focus, so its
// silhouette's pixels mix the sphere and the wall, and their features vary between samples;
// the feature variances are non-zero there (and over the curved sphere). Without them the
// feature noise of those pixels (16 samples) keeps the filter from averaging them, and their
// noisy albedo is divided out and multiplied back; with them that noise is cancelled and the
// albedo of a pixel whose normal or depth varies is left in. Error against a 1024-spp reference
// (its own MSE a 64th of the 16-spp render's, the same for both). Measured: over the pixels of
// non-zero normal variance 4.40e-5 with the variances against 7.53e-5 without (0.58), over the
// image 2.44e-5 against 3.73e-5 (0.65). Bounds: 0.8 and 0.85 (the images are deterministic;
// the margin is for a change of the renderer's sampling, which moves both).
TEST(Denoise, DefocusedEdgesDenoiseBetterWithFeatureVariances) {
    const Scene scene = lens_scene(kCheckerWall, true);
    auto render = [&](int spp, int begin, int end, std::uint64_t seed) {
        RenderOptions o = facet::render::testing::test_options("path", spp, seed);
        o.sample_begin = begin;
        o.sample_end = end;
        RenderSession s(scene, o);
        s.render();
        return s.image();
    };
    const Image ref = render(1024, 0, 0, 99);
    const int spp = 16;
    const Image a = render(spp, 0, spp / 2, 3), b = render(spp, spp / 2, spp, 3);
    const Aovs f = features_of(scene, spp);
    DenoiseInput in{&a, &b, &f.albedo, &f.normal, &f.depth};
    const Image without = denoise(in);
    in.albedo_variance = &f.albedo_variance;
    in.normal_variance = &f.normal_variance;
    in.depth_variance = &f.depth_variance;
    const Image with = denoise(in);
    auto region_mse = [&](const Image& x, bool edges_only) {
        double s = 0.0;
        int n = 0;
        for (int y = 0; y < x.height(); ++y)
            for (int xx = 0; xx < x.width(); ++xx) {
                const Rgb v = f.normal_variance.at(xx, y);
                if (edges_only && !(v.x + v.y + v.z > 0.f)) continue;
                for (int c = 0; c < 3; ++c) {
                    const double e = double(x.at(xx, y)[c]) - double(ref.at(xx, y)[c]);
                    s += e * e;
                }
                ++n;
            }
        return std::pair{s / (3.0 * n), n};
    };
    const auto [edge_with, edge_pixels] = region_mse(with, true);
    const double edge_without = region_mse(without, true).first;
    const double all_with = region_mse(with, false).first,
                 all_without = region_mse(without, false).first;
    EXPECT_GT(edge_pixels, 100);  // the sphere (r ~ 16 px) and its blurred rim (3.8 px)
    EXPECT_LT(edge_with, 0.8 * edge_without)
        << "with " << edge_with << ", without " << edge_without;
    EXPECT_LT(all_with, 0.85 * all_without) << "with " << all_with << ", without " << all_without;
}
