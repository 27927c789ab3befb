// Motion blur (scenes/FORMAT.md, "Motion blur"; facet/render/motion.h): a quad moving at
// constant speed against the analytic box-filtered coverage profile, the shutter curve's
// sampling and its effect on that profile, camera motion against the opposite object motion,
// a rotating instance's hits against their error boxes, static scenes unchanged bit for bit,
// splits and merges bit-exact with time sampling, the JSON round trip and bad input.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "facet/render/integrator.h"
#include "facet/render/motion.h"
#include "facet/render/pov_export.h"
#include "facet/render/render.h"
#include "facet/render/scene.h"
#include "facet/render/scene_description.h"
#include "facet/testsupport/render_test_util.h"

namespace fr = facet::render;
using facet::Rgb;
using facet::Vec3;

namespace {

const char* const kHead = R"({"format": "facet-scene", "version": 1, )";

fr::SceneDescription describe(const std::string& body) {
    return fr::parse_scene_description(std::string(kHead) + body + "}", "motion.json");
}

fr::Scene scene_of(const std::string& body) {
    return fr::build_scene(describe(body), "motion.json");
}

std::string error_of(const std::string& body) {
    try {
        scene_of(body);
    } catch (const fr::SceneError& e) {
        return e.what();
    }
    return "";
}

// An orthographic camera looking down -z at x in [-2, 2] (64 pixels of 1/16) and y in
// [-0.25, 0.25] (8 rows); `motion` is the camera's "motion" key or "".
std::string camera(const std::string& motion = "") {
    return R"("camera": {"type": "orthographic", "scale": 4, "position": [0, 0, 5],
               "look_at": [0, 0, 0], "up": [0, 1, 0], "width": 64, "height": 8)" +
           (motion.empty() ? std::string() : ", \"motion\": " + motion) + "},";
}

// A black quad x in [-0.5, 0.5], y in [-1, 1] (taller than the view) in front of a constant
// environment of radiance 1, with max_depth 0: a pixel is 1 minus the fraction of its area and
// of the shutter the quad covers. `motion`: the quad's "motion" key or ""; `blur`: the render's
// "motion_blur" value.
std::string quad_scene(const std::string& motion, const std::string& blur,
                       const std::string& camera_motion = "") {
    return camera(camera_motion) + R"(
      "materials": {"black": {"model": "lambert", "reflectance": 0}},
      "shapes": [{"type": "quad", "material": "black",
                  "vertices": [[-0.5, -1, 0], [0.5, -1, 0], [0.5, 1, 0], [-0.5, 1, 0]])" +
           (motion.empty() ? std::string() : ", \"motion\": " + motion) + R"(}],
      "lights": [{"type": "environment", "radiance": 1}],
      "render": {"max_depth": 0)" +
           (blur.empty() ? std::string() : ", \"motion_blur\": " + blur) + "}";
}

const char* const kMoveRight = R"([{"translate": [0, 0, 0]}, {"translate": [1.5, 0, 0]}])";

// The expected value of column i: 1 minus the quad's coverage averaged over the pixel's x
// extent and over the shutter, the quad at [-0.5 + D tau, 0.5 + D tau] with tau of density
// `pdf` (piecewise constant on equal cells; empty = uniform). The coverage of a point x is the
// probability that tau lies in [(x - 0.5) / D, (x + 0.5) / D]: a trapezoid in x, integrated
// here by the midpoint rule on 4096 points per pixel (exact to 1e-6 for this piecewise-linear
// profile).
double expected_column(int i, double D, const std::vector<double>& pdf) {
    const fr::ShutterCurve curve(pdf);
    auto cdf = [&](double t) {  // P(tau < t), from the curve's own density
        t = std::clamp(t, 0.0, 1.0);
        const int n = 4096;
        double acc = 0.0;
        for (int k = 0; k < n; ++k) {
            const double a = t * (k + 0.5) / n;
            acc += curve.pdf(float(a));
        }
        return acc * t / n;
    };
    const double x0 = -2.0 + 4.0 * i / 64.0, x1 = x0 + 4.0 / 64.0;
    const int n = 64;
    double cover = 0.0;
    for (int k = 0; k < n; ++k) {
        const double x = x0 + (x1 - x0) * (k + 0.5) / n;
        cover += cdf((x + 0.5) / D) - cdf((x - 0.5) / D);
    }
    return 1.0 - cover / n;
}

// Column means over the image's 8 rows.
std::vector<double> column_means(const fr::Image& img) {
    std::vector<double> m(std::size_t(img.width()), 0.0);
    for (int x = 0; x < img.width(); ++x) {
        for (int y = 0; y < img.height(); ++y) m[std::size_t(x)] += double(img.at(x, y).x);
        m[std::size_t(x)] /= img.height();
    }
    return m;
}

// The largest |column mean - expected| and the column where it is.
double worst_column(const fr::Image& img, double D, const std::vector<double>& pdf, int& where) {
    const std::vector<double> m = column_means(img);
    double worst = 0.0;
    for (int i = 0; i < 64; ++i) {
        const double e = std::fabs(m[std::size_t(i)] - expected_column(i, D, pdf));
        if (e > worst) {
            worst = e;
            where = i;
        }
    }
    return worst;
}

int spp() {
    return std::max(64, int(1024 * fr::testing::stress_scale()));
}

// Tolerance of a column mean: each sample is 0 or 1, so its standard deviation is at most
// 0.5 / sqrt(8 spp) (0.0055 at 1024 spp; stratification only lowers it); 0.03 is over 5 of
// them, and far below the 0.5 a sharp edge leaves where the smear should be.
double column_tolerance() {
    return std::max(0.03, 5.0 * 0.5 / std::sqrt(8.0 * spp()));
}

bool identical(const fr::Image& a, const fr::Image& b) {
    return a.pixels().size() == b.pixels().size() &&
           std::memcmp(a.pixels().data(), b.pixels().data(), a.pixels().size() * sizeof(Rgb)) == 0;
}

}  // namespace

// A quad moving 1.5 units over the shutter: each column is the analytic trapezoid of coverage
// box-filtered over the pixel. The same quad rendered without motion blur (the control) misses
// the profile by far more than the tolerance, so the test can fail.
TEST(Motion, MovingQuadGivesTheAnalyticCoverageProfile) {
    const fr::Scene moving = scene_of(quad_scene(kMoveRight, R"({"shutter": 0.5})"));
    EXPECT_TRUE(moving.features().has_motion);
    const fr::Image img = fr::render(moving, fr::testing::test_options("path", spp(), 3));
    int where = -1;
    const double worst = worst_column(img, 1.5, {}, where);
    EXPECT_LT(worst, column_tolerance()) << "column " << where;
    // The control: blur off renders the still quad (its `transform`: none, so at rest).
    const fr::Scene still = scene_of(quad_scene(kMoveRight, R"({"enabled": false})"));
    EXPECT_FALSE(still.features().has_motion);
    const fr::Image sharp = fr::render(still, fr::testing::test_options("path", spp(), 3));
    EXPECT_GT(worst_column(sharp, 1.5, {}, where), 0.3);
    // The direct integrator traces the same time-stamped camera rays.
    const fr::Image direct = fr::render(moving, fr::testing::test_options("direct", spp(), 3));
    EXPECT_LT(worst_column(direct, 1.5, {}, where), column_tolerance()) << "column " << where;
}

// The media kernel with time: the moving quad in a world medium that neither absorbs nor
// scatters gives the same analytic profile (its rays, continuation and shadow rays carry the
// path's time as the surface kernels' do).
TEST(Motion, MediaKernelTracesAtTheShutterTime) {
    std::string body = quad_scene(kMoveRight, R"({"shutter": 0.5})");
    body += R"(, "media": {"air": {"kind": "homogeneous", "sigma_a": 0, "sigma_s": 0}},
               "world_medium": "air")";
    const fr::Scene s = scene_of(body);
    ASSERT_TRUE(s.features().has_motion && s.features().has_media);
    const fr::Image img = fr::render(s, fr::testing::test_options("path", spp(), 3));
    int where = -1;
    EXPECT_LT(worst_column(img, 1.5, {}, where), column_tolerance()) << "column " << where;
}

// A shutter curve open only over the second half of the interval: the quad is seen between
// 0.75 and 1.5 of its travel, as the analytic profile with that density says; the uniform
// shutter's profile is far off it (control).
TEST(Motion, ShutterCurveWeightsTheTime) {
    const std::vector<double> curve = {0, 0, 1, 3};
    const fr::Scene s =
        scene_of(quad_scene(kMoveRight, R"({"shutter": 0.5, "curve": [0, 0, 1, 3]})"));
    const fr::Image img = fr::render(s, fr::testing::test_options("path", spp(), 5));
    int where = -1;
    EXPECT_LT(worst_column(img, 1.5, curve, where), column_tolerance()) << "column " << where;
    EXPECT_GT(worst_column(img, 1.5, {}, where), 0.15);
}

// ShutterCurve: inverting the cumulative distribution of stratified numbers puts exactly the
// weight's share of them in each cell (to one sample: float rounding at a boundary), and the
// mean time of random numbers is the density's mean within 5 standard errors.
TEST(Motion, ShutterCurveSamplesItsDensity) {
    const std::vector<double> w = {1, 0, 2, 0.5, 4, 0, 0, 1.5};
    const fr::ShutterCurve curve(w);
    const int n = 1 << 16;
    std::vector<int> count(w.size(), 0);
    double total = 0.0;
    for (double v : w) total += v;
    for (int i = 0; i < n; ++i) {
        const float tau = curve.sample((float(i) + 0.5f) / float(n));
        ASSERT_GE(tau, 0.f);
        ASSERT_LT(tau, 1.f);
        ++count[std::min(w.size() - 1, std::size_t(tau * float(w.size())))];
    }
    for (std::size_t c = 0; c < w.size(); ++c)
        EXPECT_NEAR(count[c], n * w[c] / total, 1.0) << "cell " << c;
    // The density integrates to 1 and is the weights' shape.
    double integral = 0.0, mean = 0.0, second = 0.0;
    for (int k = 0; k < 8000; ++k) {
        const double t = (k + 0.5) / 8000.0;
        integral += curve.pdf(float(t)) / 8000.0;
        mean += t * curve.pdf(float(t)) / 8000.0;
        second += t * t * curve.pdf(float(t)) / 8000.0;
    }
    EXPECT_NEAR(integral, 1.0, 1e-5);
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> u01(0.f, 1.f);
    const int m = 200000;
    double sum = 0.0;
    for (int i = 0; i < m; ++i) sum += curve.sample(u01(rng));
    const double se = std::sqrt((second - mean * mean) / m);
    EXPECT_NEAR(sum / m, mean, 5.0 * se);
    // No weights: uniform, tau = u.
    const fr::ShutterCurve box;
    EXPECT_EQ(box.sample(0.375f), 0.375f);
    EXPECT_EQ(box.pdf(0.9f), 1.f);
}

// The camera moving 1.5 units to the left over the shutter sees the still quad where the
// still camera sees the quad moving 1.5 units to the right: the same rays relative to the quad
// for the same samples, so the images agree to a few samples flipping at the edges (float
// rounding of the two placements: at most 4 of spp samples in a pixel).
TEST(Motion, CameraMotionEqualsOppositeObjectMotion) {
    const std::string cam_motion = R"([
        {"position": [0, 0, 5], "look_at": [0, 0, 0]},
        {"position": [-1.5, 0, 5], "look_at": [-1.5, 0, 0]}])";
    const fr::Scene cam = scene_of(quad_scene("", R"({"shutter": 1})", cam_motion));
    const fr::Scene obj = scene_of(quad_scene(kMoveRight, R"({"shutter": 1})"));
    EXPECT_TRUE(cam.features().has_motion);
    const int n = 256;
    const fr::Image a = fr::render(cam, fr::testing::test_options("path", n, 11));
    const fr::Image b = fr::render(obj, fr::testing::test_options("path", n, 11));
    double worst = 0.0, sum_a = 0.0;
    for (std::size_t i = 0; i < a.pixels().size(); ++i) {
        worst = std::max(worst, double(std::fabs(a.pixels()[i].x - b.pixels()[i].x)));
        sum_a += a.pixels()[i].x;
    }
    EXPECT_LE(worst, 4.0 / n);
    // Not trivially equal: the smear is there (a still image would have mean 60/64).
    EXPECT_LT(sum_a / double(a.pixels().size()), 0.95);
    int where = -1;
    EXPECT_LT(worst_column(a, 1.5, {}, where), std::max(0.03, 5.0 * 0.5 / std::sqrt(8.0 * n)))
        << "column " << where;
}

// A rotating instance: every hit's point, found by Embree at the ray's time, lies within its
// error box of the surface Facet interpolates (motion.h), so rays leaving it cannot hit it
// again; a hit's normal is the rotated one.
TEST(Motion, RotatingInstanceHitsLieWithinTheirErrorBox) {
    const fr::Scene s = scene_of(R"(
      "camera": {"position": [0, -6, 0.5], "look_at": [0, 0, 0], "up": [0, 0, 1], "fov": 40,
                 "width": 8, "height": 8},
      "materials": {"white": {"model": "lambert", "reflectance": 0.5}},
      "prototypes": {"plate": [{"type": "quad", "material": "white",
                                "vertices": [[-1, 0, -1], [1, 0, -1], [1, 0, 1], [-1, 0, 1]]}]},
      "shapes": [{"type": "instance", "of": "plate",
                  "motion": [{"rotate": {"axis": [0, 0, 1], "angle": -40}, "translate": [0, 0.3, 0]},
                             {"rotate": {"axis": [0, 0, 1], "angle": 0}, "translate": [0, 0.3, 0]},
                             {"rotate": {"axis": [0, 0, 1], "angle": 50}, "translate": [0, 0.3, 0]}]}],
      "lights": [{"type": "environment", "radiance": 1}],
      "render": {"motion_blur": {"shutter": 0.5}})");
    ASSERT_TRUE(s.features().has_motion);
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> u(-0.7f, 0.7f), ut(0.f, 1.f);
    int hits = 0;
    double worst_ratio = 0.0;
    for (int i = 0; i < 4000; ++i) {
        fr::Ray r;
        r.o = Vec3(u(rng), -6.f, u(rng));
        r.d = Vec3(0.f, 1.f, 0.f);
        const float time = ut(rng);
        fr::SurfaceHit h;
        if (!s.intersect(r, time, h)) continue;
        ++hits;
        // The plate's plane at this time: through (0, 0.3, 0), normal the rotated +-y.
        const double deg = time < 0.5 ? -40.0 + 80.0 * time : 100.0 * (time - 0.5);
        const double a = deg * 3.14159265358979 / 180.0;
        const glm::dvec3 n(-std::sin(a), std::cos(a), 0.0);
        EXPECT_GT(std::fabs(glm::dot(glm::dvec3(h.ng), n)), 1.0 - 1e-5) << "t=" << time;
        // Embree's point: o + t d (its float t); its distance from Facet's plane against the
        // hit's error box along the normal, with the rounding of t itself (2^-23 |o + t d|).
        const glm::dvec3 q = glm::dvec3(r.o) + double(h.t) * glm::dvec3(r.d);
        const double dist = std::fabs(glm::dot(q - glm::dvec3(0.0, 0.3, 0.0), n));
        const double box = glm::dot(glm::abs(n), glm::dvec3(h.p_err)) + 0x1p-23 * 7.0;
        worst_ratio = std::max(worst_ratio, dist / box);
        EXPECT_LE(dist, box) << "t=" << time << " dist " << dist << " box " << box;
        // And Facet's own point lies on the plane (its projection).
        EXPECT_LE(std::fabs(glm::dot(glm::dvec3(h.p) - glm::dvec3(0.0, 0.3, 0.0), n)), box);
    }
    EXPECT_GT(hits, 2000);
    RecordProperty("worst_distance_over_box", std::to_string(worst_ratio));
}

// Scenes that do not move render as before, bit for bit: with motion blur settings present,
// and with motion keys present but motion blur off (the still transform and camera render);
// their kernels draw no time.
TEST(Motion, StaticScenesAreBitIdentical) {
    fr::SceneDescription plain =
        fr::read_scene_description(std::string(FACET_SCENES_DIR) + "/cornell_box.json");
    plain.camera.width = 48;
    plain.camera.height = 48;
    fr::SceneDescription with = plain;
    with.render.motion_blur = fr::RenderSettings::MotionBlur{};
    const fr::Scene a = fr::build_scene(plain, "cornell");
    const fr::Scene b = fr::build_scene(with, "cornell");
    EXPECT_FALSE(b.features().has_motion);
    EXPECT_EQ(fr::choose_kernel(a.features(), fr::IntegratorKind::Path, 8, false).name,
              fr::choose_kernel(b.features(), fr::IntegratorKind::Path, 8, false).name);
    EXPECT_TRUE(identical(fr::render(a, fr::testing::test_options("path", 4, 2)),
                          fr::render(b, fr::testing::test_options("path", 4, 2))));
    // Motion keys with blur off: the still scene.
    const std::string cam_motion = R"([
        {"position": [0, 0, 5], "look_at": [0, 0, 0]},
        {"position": [-1.5, 0, 5], "look_at": [-1.5, 0, 0]}])";
    const fr::Scene still = scene_of(quad_scene("", ""));
    const fr::Scene off = scene_of(quad_scene(kMoveRight, R"({"enabled": false})", cam_motion));
    const fr::Scene off2 = scene_of(quad_scene(kMoveRight, "false", cam_motion));
    const fr::Scene no_key = scene_of(quad_scene(kMoveRight, "", cam_motion));
    for (const fr::Scene* s : {&off, &off2, &no_key}) {
        EXPECT_FALSE(s->features().has_motion);
        EXPECT_TRUE(identical(fr::render(still, fr::testing::test_options("path", 4, 2)),
                              fr::render(*s, fr::testing::test_options("path", 4, 2))));
    }
}

// Time sampling keeps renders exact under splitting: 1 and 2 threads, a region alone and two
// sample ranges merged give the same image bit for bit.
TEST(Motion, ImagesAreBitIdenticalAcrossThreadsAndSplits) {
    const fr::Scene s = scene_of(quad_scene(kMoveRight, R"({"shutter": 0.5})"));
    const fr::Image one = fr::render(s, fr::testing::test_options("path", 8, 9, 1));
    const fr::Image two = fr::render(s, fr::testing::test_options("path", 8, 9, 2));
    EXPECT_TRUE(identical(one, two));
    fr::RenderOptions crop = fr::testing::test_options("path", 8, 9, 2);
    crop.region = fr::Region{5, 2, 40, 7};
    const fr::Image part = fr::render(s, crop);
    for (int y = 2; y < 7; ++y)
        for (int x = 5; x < 40; ++x) ASSERT_EQ(part.at(x - 5, y - 2), one.at(x, y));
    std::vector<fr::RenderPart> halves;
    for (int h = 0; h < 2; ++h) {
        fr::RenderOptions o = fr::testing::test_options("path", 8, 9, 2);
        o.sample_begin = 4 * h;
        o.sample_end = 4 * h + 4;
        fr::RenderSession session(s, o);
        session.render();
        halves.push_back(session.part());
    }
    EXPECT_TRUE(identical(one, fr::merge_parts(halves, {"s0", "s1"}).resolve()));
}

// The JSON writer writes what the reader reads: camera and shape motion, the shutter settings.
TEST(Motion, JsonRoundTrip) {
    const std::string cam_motion = R"([
        {"position": [0, 0, 5], "look_at": [0, 0, 0]},
        {"position": [-1.5, 0, 5], "look_at": [-1.5, 0, 0], "up": [0, 1, 0.5]}])";
    const fr::SceneDescription d = describe(quad_scene(
        kMoveRight, R"({"shutter": 0.25, "position": "start", "curve": [1, 2]})", cam_motion));
    ASSERT_EQ(d.camera.motion.size(), 2u);
    ASSERT_EQ(d.shapes[0].motion.size(), 2u);
    ASSERT_TRUE(d.render.motion_blur.has_value());
    EXPECT_EQ(d.render.motion_blur->position, "start");
    const fr::SceneDescription back =
        fr::parse_scene_description(fr::write_scene_json(d), "back.json");
    EXPECT_TRUE(back == d);
    EXPECT_EQ(back.camera.motion[1].up, Vec3(0.f, 1.f, 0.5f));
}

// Bad input: an error naming the JSON pointer.
TEST(Motion, BadInputNamesThePlace) {
    const std::string on = R"({"shutter": 0.5})";
    auto expect = [](const std::string& err, const std::string& where) {
        EXPECT_NE(err.find(where), std::string::npos) << err;
    };
    expect(error_of(quad_scene(kMoveRight, R"({"shutter": 0})")), "/render/motion_blur/shutter");
    expect(error_of(quad_scene(kMoveRight, R"({"shutter": -1})")), "/render/motion_blur/shutter");
    expect(error_of(quad_scene(kMoveRight, R"({"position": "middle"})")),
           "/render/motion_blur/position");
    expect(error_of(quad_scene(kMoveRight, R"({"curve": [1, -1]})")),
           "/render/motion_blur/curve/1");
    expect(error_of(quad_scene(kMoveRight, R"({"curve": [0, 0]})")), "/render/motion_blur/curve");
    expect(error_of(quad_scene(R"([{"translate": [0, 0, 0]}])", on)), "/shapes/0/motion");
    expect(error_of(quad_scene(R"([{"translate": [0, 0, 0]}, {"scale": 0}])", on)),
           "/shapes/0/motion/1");
    expect(error_of(quad_scene(R"([{"translate": [0, 0, 0]},
                                   {"matrix": [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 1, 1]}])",
                               on)),
           "/shapes/0/motion/1");
    expect(error_of(quad_scene("", on, R"([{"position": [0, 0, 5], "look_at": [0, 0, 0]}])")),
           "/camera/motion");
    expect(error_of(quad_scene("", on,
                               R"([{"position": [0, 0, 5], "look_at": [0, 0, 0]},
                                   {"position": [0, 0, 5], "look_at": [0, 0, 5]}])")),
           "/camera/motion/1/look_at");
    // Only triangle shapes, curves and instances move.
    expect(error_of(camera() + R"(
      "materials": {"m": {"model": "lambert", "reflectance": 0.5}},
      "shapes": [{"type": "sphere", "material": "m", "center": [0, 0, 0], "radius": 0.5,
                  "motion": [{"translate": [0, 0, 0]},
                                                               {"translate": [1, 0, 0]}]}],
      "lights": [{"type": "environment", "radiance": 1}], "render": {"motion_blur": true})"),
           "/shapes/0/motion");
    // Wrong types in the JSON.
    expect(error_of(quad_scene(R"({"translate": [1, 0, 0]})", on)), "/shapes/0/motion");
    expect(error_of(quad_scene(kMoveRight, R"({"shutter": "long"})")),
           "/render/motion_blur/shutter");
}

// export-pov: a scene that moves with motion blur on is not expressible in POV-Ray (an error
// naming the first motion, as export-pov names what it cannot express); with motion blur off
// the still scene is written.
TEST(Motion, PovExportReportsMotionBlur) {
    const fr::SceneDescription moving = describe(quad_scene(kMoveRight, R"({"shutter": 0.5})"));
    std::string err;
    try {
        fr::export_pov(moving, "motion.json", fr::PovExportOptions{.environment = "background"});
    } catch (const fr::SceneError& e) {
        err = e.what();
    }
    EXPECT_NE(err.find("motion.json: /shapes/0/motion: motion blur is not expressible in POV-Ray"),
              std::string::npos)
        << err;
    const fr::SceneDescription still = describe(quad_scene(kMoveRight, R"({"enabled": false})"));
    fr::PovExportOptions background;
    background.environment = "background";
    std::string sdl;
    EXPECT_NO_THROW(sdl = fr::export_pov(still, "motion.json", background));
    EXPECT_NE(sdl.find("camera"), std::string::npos);
}

// --- deformation motion (ShapeDesc::motion_positions) -----------------------------------------

namespace {

// The quad of quad_scene as a "mesh" whose vertices are translated by dx[k] along x at step k
// (motion_positions; "" when dx is empty), with an optional shape "motion" and more keys.
std::string deform_scene(const std::vector<double>& dx, const std::string& blur,
                         const std::string& motion = "", const std::string& extra = "") {
    const double base[4][3] = {{-0.5, -1, 0}, {0.5, -1, 0}, {0.5, 1, 0}, {-0.5, 1, 0}};
    auto positions = [&](double d) {
        std::string s = "[";
        for (int i = 0; i < 4; ++i)
            for (int c = 0; c < 3; ++c)
                s += (i + c ? ", " : "") + std::to_string(base[i][c] + (c == 0 ? d : 0.0));
        return s + "]";
    };
    std::string steps;
    for (std::size_t k = 0; k < dx.size(); ++k) steps += (k ? ", " : "") + positions(dx[k]);
    return camera() + R"(
      "materials": {"black": {"model": "lambert", "reflectance": 0}},
      "shapes": [{"type": "mesh", "material": "black", "positions": )" +
           positions(0.0) + R"(, "indices": [0, 1, 2, 0, 2, 3])" +
           (dx.empty() ? std::string() : ", \"motion_positions\": [" + steps + "]") +
           (motion.empty() ? std::string() : ", \"motion\": " + motion) + extra + R"(}],
      "lights": [{"type": "environment", "radiance": 1}],
      "render": {"max_depth": 0)" +
           (blur.empty() ? std::string() : ", \"motion_blur\": " + blur) + "}";
}

}  // namespace

// A mesh whose vertices translate 1.5 units at constant speed (three steps) gives the analytic
// coverage profile of the quad moved by transformation motion, and the same image as that
// quad to within noise; with blur off (the control) the still mesh renders, far off the
// profile. Deformation and transformation motion compose: 0.75 units of each give the profile
// of 1.5.
TEST(Motion, DeformingMeshGivesTheAnalyticCoverageProfile) {
    const fr::Scene deforming = scene_of(deform_scene({0.0, 0.75, 1.5}, R"({"shutter": 0.5})"));
    EXPECT_TRUE(deforming.features().has_motion);
    const fr::Image img = fr::render(deforming, fr::testing::test_options("path", spp(), 3));
    int where = -1;
    EXPECT_LT(worst_column(img, 1.5, {}, where), column_tolerance()) << "column " << where;
    const fr::Image moved = fr::render(scene_of(quad_scene(kMoveRight, R"({"shutter": 0.5})")),
                                       fr::testing::test_options("path", spp(), 3));
    const std::vector<double> a = column_means(img), b = column_means(moved);
    double worst = 0.0;
    for (std::size_t i = 0; i < a.size(); ++i) worst = std::max(worst, std::fabs(a[i] - b[i]));
    // Two independent estimates: each within the column tolerance of the same expectation.
    EXPECT_LT(worst, 2.0 * column_tolerance());
    const fr::Scene still = scene_of(deform_scene({0.0, 0.75, 1.5}, R"({"enabled": false})"));
    EXPECT_FALSE(still.features().has_motion);
    const fr::Image sharp = fr::render(still, fr::testing::test_options("path", spp(), 3));
    EXPECT_GT(worst_column(sharp, 1.5, {}, where), 0.3);
    const fr::Scene both =
        scene_of(deform_scene({0.0, 0.75}, R"({"shutter": 0.5})",
                              R"([{"translate": [0, 0, 0]}, {"translate": [0.75, 0, 0]}])"));
    const fr::Image composed = fr::render(both, fr::testing::test_options("path", spp(), 3));
    EXPECT_LT(worst_column(composed, 1.5, {}, where), column_tolerance()) << "column " << where;
    // The direct integrator as well.
    const fr::Image direct = fr::render(deforming, fr::testing::test_options("direct", spp(), 3));
    EXPECT_LT(worst_column(direct, 1.5, {}, where), column_tolerance()) << "column " << where;
}

// A deforming mesh's hit at time tau is on the triangle interpolated at tau: a square whose
// right edge rises (z = 0.5 tau (x + 1) over the shutter, two steps) with vertex normals
// turning from +z to the tilted plane's normal. Every hit lies within its error box of that
// plane, its geometric normal is the plane's, and its shading normal the interpolated one.
TEST(Motion, DeformingMeshHitsAreTheInterpolatedTriangle) {
    const double k = 0.5;  // the slope at tau = 1
    const glm::dvec3 n1 = glm::normalize(glm::dvec3(-k, 0.0, 1.0));
    const std::string body =
        R"(
      "camera": {"position": [0, 0, 5], "look_at": [0, 0, 0], "up": [0, 1, 0], "fov": 40,
                 "width": 8, "height": 8},
      "materials": {"white": {"model": "lambert", "reflectance": 0.5}},
      "shapes": [{"type": "mesh", "material": "white",
                  "positions": [-1, -1, 0, 1, -1, 0, 1, 1, 0, -1, 1, 0],
                  "normals": [0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1],
                  "indices": [0, 1, 2, 0, 2, 3],
                  "motion_positions": [[-1, -1, 0, 1, -1, 0, 1, 1, 0, -1, 1, 0],
                                       [-1, -1, 0, 1, -1, 1, 1, 1, 1, -1, 1, 0]],
                  "motion_normals": [[0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1],
                                     [)" +
        [&] {
            std::string s;
            for (int i = 0; i < 4; ++i)
                s += (i ? ", " : "") + std::to_string(n1.x) + ", 0, " + std::to_string(n1.z);
            return s;
        }() +
        R"(]]}],
      "lights": [{"type": "environment", "radiance": 1}],
      "render": {"motion_blur": {"shutter": 0.5}})";
    const fr::Scene s = scene_of(body);
    ASSERT_TRUE(s.features().has_motion);
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> u(-0.9f, 0.9f), ut(0.f, 1.f);
    int hits = 0;
    double worst_ratio = 0.0, worst_ns = 0.0;
    for (int i = 0; i < 4000; ++i) {
        fr::Ray r;
        r.o = Vec3(u(rng), u(rng), 5.f);
        r.d = Vec3(0.f, 0.f, -1.f);
        const float time = ut(rng);
        fr::SurfaceHit h;
        ASSERT_TRUE(s.intersect(r, time, h)) << "t=" << time;
        ++hits;
        const double slope = k * double(time);
        const glm::dvec3 n = glm::normalize(glm::dvec3(-slope, 0.0, 1.0));
        const glm::dvec3 p0(-1.0, 0.0, 0.0);  // on the plane z = slope (x + 1)
        EXPECT_GT(glm::dot(glm::dvec3(h.ng), n), 1.0 - 1e-5) << "t=" << time;
        const glm::dvec3 q = glm::dvec3(r.o) + double(h.t) * glm::dvec3(r.d);
        const double dist = std::fabs(glm::dot(q - p0, n));
        const double box = glm::dot(glm::abs(n), glm::dvec3(h.p_err)) + 0x1p-23 * 7.0;
        worst_ratio = std::max(worst_ratio, dist / box);
        EXPECT_LE(dist, box) << "t=" << time;
        EXPECT_LE(std::fabs(glm::dot(glm::dvec3(h.p) - p0, n)), box);
        // Every corner has the same normal per step: the shading normal is their lerp.
        const glm::dvec3 ns =
            glm::normalize((1.0 - time) * glm::dvec3(0.0, 0.0, 1.0) + double(time) * n1);
        worst_ns = std::max(worst_ns, glm::length(glm::dvec3(h.ns) - ns));
    }
    EXPECT_EQ(hits, 4000);
    EXPECT_LT(worst_ns, 1e-5);
    RecordProperty("worst_distance_over_box", std::to_string(worst_ratio));
}

// Deformation keys with motion blur off render the still mesh bit for bit, and choose the
// still kernels.
TEST(Motion, DeformationOffRendersTheStillMesh) {
    const fr::Scene still = scene_of(deform_scene({}, ""));
    for (const std::string& blur : {std::string(R"({"enabled": false})"), std::string()}) {
        const fr::Scene off = scene_of(deform_scene({0.0, 1.5}, blur));
        EXPECT_FALSE(off.features().has_motion);
        EXPECT_TRUE(identical(fr::render(still, fr::testing::test_options("path", 4, 2)),
                              fr::render(off, fr::testing::test_options("path", 4, 2))));
    }
}

// The JSON writer writes the deformation steps the reader reads; export-pov names them.
TEST(Motion, DeformationJsonRoundTripAndPovExport) {
    const fr::SceneDescription d = describe(deform_scene({0.0, 0.5, 1.5}, R"({"shutter": 0.5})"));
    ASSERT_EQ(d.shapes[0].motion_positions.size(), 3u);
    const fr::SceneDescription back =
        fr::parse_scene_description(fr::write_scene_json(d), "back.json");
    EXPECT_TRUE(back == d);
    EXPECT_FLOAT_EQ(back.shapes[0].motion_positions[2][0], 1.0f);
    std::string err;
    try {
        fr::export_pov(d, "deform.json", fr::PovExportOptions{.environment = "background"});
    } catch (const fr::SceneError& e) {
        err = e.what();
    }
    EXPECT_NE(err.find("deform.json: /shapes/0/motion_positions: motion blur is not expressible"),
              std::string::npos)
        << err;
}

// Bad deformation input: an error naming the JSON pointer, checked with motion blur on or off.
TEST(Motion, BadDeformationNamesThePlace) {
    auto expect = [](const std::string& err, const std::string& where) {
        EXPECT_NE(err.find(where), std::string::npos) << err;
    };
    for (const std::string blur : {R"({"shutter": 0.5})", R"({"enabled": false})"}) {
        // Fewer than 2 steps.
        expect(error_of(deform_scene({0.0}, blur)), "/shapes/0/motion_positions");
        // A step with the wrong vertex count.
        expect(error_of(deform_scene({}, blur, "", R"(, "motion_positions": [
                                         [0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0],
                                         [0, 0, 0, 1, 0, 0, 1, 1, 0]])")),
               "/shapes/0/motion_positions/1: expected 12 numbers");
        // Step counts that differ from the shape's motion.
        expect(error_of(deform_scene({0.0, 0.5, 1.0}, blur,
                                     R"([{"translate": [0, 0, 0]}, {"translate": [1, 0, 0]}])")),
               "/shapes/0/motion_positions: has 3 steps but the shape's \"motion\" has 2");
        // Normals: required per step when the mesh has normals, refused when it has none.
        expect(
            error_of(deform_scene({}, blur, "", R"(, "motion_normals": [[0, 0, 1], [0, 0, 1]])")),
            "/shapes/0/motion_normals");
        expect(error_of(deform_scene({0.0, 1.0}, blur, "",
                                     R"(, "motion_normals": [[0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1],
                                                             [0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1]])")),
               "/shapes/0/motion_normals: the mesh has no normals");
        // Wrong JSON types.
        expect(error_of(deform_scene({}, blur, "", R"(, "motion_positions": 3)")),
               "/shapes/0/motion_positions");
        expect(error_of(deform_scene({}, blur, "", R"(, "motion_positions": [[0, "a"]])")),
               "/shapes/0/motion_positions/0/1");
    }
    // Only meshes deform.
    std::string quad = quad_scene("", R"({"shutter": 0.5})");
    quad.insert(quad.find("\"vertices\""), R"("motion_positions": [[0], [0]], )");
    expect(error_of(quad), "/shapes/0/motion_positions");
    // Not finite (a description built in C++: JSON has no NaN).
    fr::SceneDescription d = describe(deform_scene({0.0, 1.0}, R"({"shutter": 0.5})"));
    d.shapes[0].motion_positions[1][4] = std::nanf("");
    std::string err;
    try {
        fr::build_scene(d, "deform.json");
    } catch (const fr::SceneError& e) {
        err = e.what();
    }
    expect(err, "/shapes/0/motion_positions/1/4: must be a finite number");
}

// --- Curves under motion blur (scenes/FORMAT.md, "Motion blur" and "Curves") ---------------

namespace {

// A black round strand along y (taller than the view), radius 0.25, in front of the constant
// environment of quad_scene: a pixel is 1 minus the fraction of its area and of the shutter
// the tube's silhouette [x - 0.25, x + 0.25] covers. `basis` "linear" (2 points at y = +-1.5)
// or "catmull_rom" (4 collinear points, y = -4.5, -1.5, 1.5, 4.5: a straight segment from -1.5
// to 1.5). `points_x`: each point's x (the still points); `extra`: more keys of the shape
// ("motion", "motion_positions").
constexpr double kStrandRadius = 0.25;

std::string strand_points(const std::string& basis, double x) {
    const auto num = [](double v) { return std::to_string(v); };
    if (basis == "linear") return num(x) + ", -1.5, 0, " + num(x) + ", 1.5, 0";
    return num(x) + ", -4.5, 0, " + num(x) + ", -1.5, 0, " + num(x) + ", 1.5, 0, " + num(x) +
           ", 4.5, 0";
}

std::string strand_scene(const std::string& basis, const std::string& extra,
                         const std::string& blur) {
    return camera() + R"(
      "materials": {"black": {"model": "lambert", "reflectance": 0}},
      "shapes": [{"type": "curves", "material": "black", "basis": ")" +
           basis + R"(", "radius": 0.25, "points": [)" + strand_points(basis, 0.0) + "]" + extra +
           R"(}],
      "lights": [{"type": "environment", "radiance": 1}],
      "render": {"max_depth": 0)" +
           (blur.empty() ? std::string() : ", \"motion_blur\": " + blur) + "}";
}

// The strand's deformation moving it `D` along x: its points at x = 0 and x = D.
std::string strand_deformation(const std::string& basis, double D) {
    return R"(, "motion_positions": [[)" + strand_points(basis, 0.0) + "], [" +
           strand_points(basis, D) + "]]";
}

// As worst_column for the strand's silhouette (half width kStrandRadius) moving D over a
// uniform shutter: the quad's profile with its half width 0.5 replaced (expected_column with
// x scaled by 0.5 / kStrandRadius maps the strand onto the quad of travel D * 0.5 / r).
double worst_strand_column(const fr::Image& img, double D, int& where) {
    const std::vector<double> m = column_means(img);
    const fr::ShutterCurve uniform;
    double worst = 0.0;
    for (int i = 0; i < 64; ++i) {
        const double x0 = -2.0 + 4.0 * i / 64.0, x1 = x0 + 4.0 / 64.0;
        const int n = 256;
        double cover = 0.0;
        for (int k = 0; k < n; ++k) {
            const double x = x0 + (x1 - x0) * (k + 0.5) / n;
            // P(|x - D tau| <= r) for tau uniform in [0, 1].
            const double lo = std::clamp((x - kStrandRadius) / D, 0.0, 1.0);
            const double hi = std::clamp((x + kStrandRadius) / D, 0.0, 1.0);
            cover += hi - lo;
        }
        const double e = std::fabs(m[std::size_t(i)] - (1.0 - cover / n));
        if (e > worst) {
            worst = e;
            where = i;
        }
    }
    return worst;
}

}  // namespace

// A strand moving 1.5 units over the shutter, by its transform's motion (linear and
// Catmull-Rom strands) and by its points' deformation: each column is the analytic coverage of
// the moving silhouette box-filtered over the pixel (tolerance as the quad's). The control, the
// same strands with motion blur off, miss it by far more.
TEST(Motion, MovingStrandGivesTheAnalyticCoverageProfile) {
    const std::string blur = R"({"shutter": 0.5})";
    for (const std::string basis : {"linear", "catmull_rom"}) {
        for (const std::string& motion :
             {std::string(", \"motion\": ") + kMoveRight, strand_deformation(basis, 1.5)}) {
            SCOPED_TRACE(basis + motion.substr(0, 20));
            const fr::Scene moving = scene_of(strand_scene(basis, motion, blur));
            EXPECT_TRUE(moving.features().has_motion);
            const fr::Image img = fr::render(moving, fr::testing::test_options("path", spp(), 3));
            int where = -1;
            const double worst = worst_strand_column(img, 1.5, where);
            EXPECT_LT(worst, column_tolerance()) << "column " << where;
            RecordProperty(
                "worst_column_" + basis +
                    (motion.find("motion_positions") == std::string::npos ? "_motion" : "_deform"),
                std::to_string(worst));
            const fr::Scene still = scene_of(strand_scene(basis, motion, R"({"enabled": false})"));
            EXPECT_FALSE(still.features().has_motion);
            const fr::Image sharp = fr::render(still, fr::testing::test_options("path", spp(), 3));
            EXPECT_GT(worst_strand_column(sharp, 1.5, where), 0.3);
        }
    }
}

// Deformation and transformation describing the same motion give the same hits: at each time
// a ray's hit on the strand lies on the tube the strand's axis at that time defines (x = 1.5
// tau), within its error box, and the two scenes' images agree but for samples flipping at
// the silhouette (float rounding of the two placements: at most 4 of spp samples in a pixel,
// as camera against object motion).
TEST(Motion, StrandDeformationEqualsTransformation) {
    const std::string blur = R"({"shutter": 0.5})";
    for (const std::string basis : {"linear", "catmull_rom"}) {
        SCOPED_TRACE(basis);
        const fr::Scene moved =
            scene_of(strand_scene(basis, std::string(", \"motion\": ") + kMoveRight, blur));
        const fr::Scene deformed =
            scene_of(strand_scene(basis, strand_deformation(basis, 1.5), blur));
        std::mt19937 rng(7);
        std::uniform_real_distribution<float> ut(0.f, 1.f), off(-0.24f, 0.24f);
        double worst_ratio = 0.0;
        for (int i = 0; i < 2000; ++i) {
            const float time = ut(rng);
            const double axis = 1.5 * double(time);
            fr::Ray r;
            r.o = Vec3(float(axis) + off(rng), 0.1f * off(rng), 5.f);
            r.d = Vec3(0.f, 0.f, -1.f);
            const double dx = double(r.o.x) - axis;
            const glm::dvec3 expected(r.o.x, r.o.y,
                                      std::sqrt(kStrandRadius * kStrandRadius - dx * dx));
            for (const fr::Scene* s : {&moved, &deformed}) {
                fr::SurfaceHit h;
                ASSERT_TRUE(s->intersect(r, time, h)) << "t=" << time << " x=" << r.o.x;
                const glm::dvec3 d = glm::abs(glm::dvec3(h.p) - expected);
                // The tube's point: within the error box (plus Embree's float t on a ray from
                // z = 5 and the float axis position, 2^-20 of it).
                const glm::dvec3 box = glm::dvec3(h.p_err) + 0x1p-20 * 5.0;
                worst_ratio = std::max({worst_ratio, d.x / box.x, d.y / box.y, d.z / box.z});
                EXPECT_TRUE(d.x <= box.x && d.y <= box.y && d.z <= box.z)
                    << "t=" << time << " p " << h.p.x << " " << h.p.y << " " << h.p.z
                    << " expected z " << expected.z << " err " << h.p_err.z;
                const glm::dvec3 n = (expected - glm::dvec3(axis, expected.y, 0.0)) / kStrandRadius;
                EXPECT_GT(glm::dot(glm::dvec3(h.ng), n), 1.0 - 1e-4) << "t=" << time;
            }
        }
        RecordProperty("worst_distance_over_box_" + basis, std::to_string(worst_ratio));
        const int n = 64;
        const fr::Image a = fr::render(moved, fr::testing::test_options("path", n, 2));
        const fr::Image b = fr::render(deformed, fr::testing::test_options("path", n, 2));
        float worst = 0.f;
        for (std::size_t k = 0; k < a.pixels().size(); ++k)
            worst = std::max(worst, std::fabs(a.pixels()[k].x - b.pixels()[k].x));
        EXPECT_LE(worst, 4.f / float(n));
    }
}

// Curves' motion keys: bad input names the place; with motion blur off they are checked and
// the still strand renders bit for bit as without them.
TEST(Motion, StrandMotionBadInputNamesThePlace) {
    const std::string on = R"({"shutter": 0.5})";
    auto expect = [](const std::string& err, const std::string& where) {
        EXPECT_NE(err.find(where), std::string::npos) << err;
    };
    for (const std::string& blur : {on, std::string(R"({"enabled": false})")}) {
        SCOPED_TRACE(blur);
        // One step.
        expect(error_of(strand_scene("linear", R"(, "motion_positions": [[0, -1.5, 0, 0, 1.5, 0]])",
                                     blur)),
               "/shapes/0/motion_positions: needs at least 2 steps");
        // A step of the wrong size.
        expect(error_of(strand_scene(
                   "linear", R"(, "motion_positions": [[0, -1.5, 0, 0, 1.5, 0], [0, -1.5, 0]])",
                   blur)),
               "/shapes/0/motion_positions/1: expected 6 numbers (3 per control point: the "
               "curves have 2 points), got 3");
        // Not finite (1e39 overflows float).
        expect(error_of(strand_scene(
                   "linear",
                   R"(, "motion_positions": [[0, -1.5, 0, 0, 1.5, 0], [0, -1.5, 0, 1e39, 1.5, 0]])",
                   blur)),
               "/shapes/0/motion_positions/1/3: must be a finite number");
        // Steps other than the motion's.
        expect(error_of(strand_scene("linear",
                                     std::string(", \"motion\": ") + kMoveRight +
                                         R"(, "motion_positions": [[0, -1.5, 0, 0, 1.5, 0],
                                            [0, -1.5, 0, 0, 1.5, 0], [0, -1.5, 0, 0, 1.5, 0]])",
                                     blur)),
               "/shapes/0/motion_positions: has 3 steps but the shape's \"motion\" has 2");
        // Curves have no normals.
        expect(error_of(strand_scene("linear",
                                     std::string(strand_deformation("linear", 1.0)) +
                                         R"(, "motion_normals": [[0, 0, 1, 0, 0, 1],
                                                                  [0, 0, 1, 0, 0, 1]])",
                                     blur)),
               "/shapes/0/motion_normals: unknown key");
    }
    // A prototype's curves do not move (the instance does).
    expect(error_of(camera() + R"(
      "materials": {"m": {"model": "lambert", "reflectance": 0.5}},
      "prototypes": {"hair": [{"type": "curves", "material": "m", "basis": "linear",
                               "radius": 0.1, "points": [0, -1, 0, 0, 1, 0],
                               "motion_positions": [[0, -1, 0, 0, 1, 0], [1, -1, 0, 1, 1, 0]]}]},
      "shapes": [{"type": "instance", "of": "hair"}],
      "render": {"motion_blur": true})"),
           "/prototypes/hair/0/motion_positions");
    // Blur off: the still strand, bit for bit.
    const fr::Scene plain = scene_of(strand_scene("catmull_rom", "", ""));
    const fr::Scene off = scene_of(strand_scene(
        "catmull_rom",
        std::string(", \"motion\": ") + kMoveRight + strand_deformation("catmull_rom", 1.5),
        R"({"enabled": false})"));
    EXPECT_FALSE(off.features().has_motion);
    EXPECT_TRUE(identical(fr::render(plain, fr::testing::test_options("path", 4, 2)),
                          fr::render(off, fr::testing::test_options("path", 4, 2))));
}

// The JSON writer writes a strand's motion and deformation as the reader reads them.
TEST(Motion, StrandMotionJsonRoundTrip) {
    const fr::SceneDescription d = describe(strand_scene(
        "linear", std::string(", \"motion\": ") + kMoveRight + strand_deformation("linear", 1.5),
        R"({"shutter": 0.5})"));
    ASSERT_EQ(d.shapes[0].motion_positions.size(), 2u);
    const fr::SceneDescription back =
        fr::parse_scene_description(fr::write_scene_json(d), "back.json");
    EXPECT_TRUE(back == d);
}
