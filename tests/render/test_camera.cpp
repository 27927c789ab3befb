// Camera tests (issue 22): the thin lens's circle of confusion against the thin-lens equation,
// the uniformity of the round and polygonal apertures, orthographic framing (Blender's Ortho
// Scale), lens shift (fractions of the larger image side), generate_ray / project round trips,
// the loader's errors, the JSON round trip, and that a closed aperture renders the pinhole's
// image bit for bit.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>

#include "facet/render/camera.h"
#include "facet/render/render.h"
#include "facet/render/scene_description.h"
#include "facet/testsupport/render_test_util.h"

using namespace facet;
using namespace facet::render;
using facet::render::testing::scene_from;
using facet::render::testing::test_options;

namespace {

constexpr int kGrid = 64;  // lens samples: the centres of a kGrid x kGrid grid of [0,1)^2

Vec2 grid_sample(int i, int j) {
    return {(float(i) + 0.5f) / float(kGrid), (float(j) + 0.5f) / float(kGrid)};
}

// Distance from point p to the ray's line.
float distance_to_ray(const Ray& r, const Vec3& p) {
    const Vec3 v = p - r.o;
    return glm::length(v - glm::dot(v, r.d) * r.d);
}

// A camera at the origin looking down -z, 200 x 150 px, fov 40 degrees.
Camera lens_camera(float radius, float focus, int blades = 0, float rotation = 0.f) {
    CameraOptions o;
    o.aperture_radius = radius;
    o.focus_distance = focus;
    o.blades = blades;
    o.rotation_deg = rotation;
    return Camera::make({0, 0, 0}, {0, 0, -1}, {0, 1, 0}, 40.f, 200, 150, o);
}

// The radius (pixels) of the circle of confusion of a point at depth z, for a thin lens of
// aperture radius R focused at depth fd, from the thin-lens equation 1/F = 1/v + 1/fd: a point
// at depth z focuses at v_z with 1/v_z = 1/F - 1/z, so on the sensor at v its blur disc has
// diameter 2R v |1/v_z - 1/v| = 2R v |1/fd - 1/z|; the sensor's half-height is v tan(fov_y/2)
// (its edge is seen through the lens centre), i.e. height/2 pixels. F and v cancel:
//   r_px = R |1/fd - 1/z| (height / 2) / tan(fov_y / 2).
double coc_radius_px(double R, double fd, double z, int height, double fov_y_deg) {
    return R * std::fabs(1.0 / fd - 1.0 / z) * 0.5 * height /
           std::tan(0.5 * fov_y_deg * kPiD / 180.0);
}

bool same_pixels(const Image& a, const Image& b) {
    return a.width() == b.width() && a.height() == b.height() &&
           std::memcmp(a.pixels().data(), b.pixels().data(), a.pixels().size() * sizeof(Rgb)) == 0;
}

std::string error_of(const std::string& camera) {
    try {
        scene_from(R"("camera": )" + camera + R"(,
            "lights": [{"type": "point", "position": [0, 5, 0], "power": 1}])");
    } catch (const SceneError& e) {
        return e.what();
    }
    return "";
}

}  // namespace

// --- thin lens ------------------------------------------------------------------------------

TEST(Camera, ThinLensBlurDiscFollowsTheThinLensEquation) {
    const float R = 0.5f, fd = 5.f;
    const Camera c = lens_camera(R, fd);
    ASSERT_TRUE(c.has_lens());
    for (const Vec3 p : {Vec3(0.f, 0.f, -10.f), Vec3(1.f, -0.5f, -10.f), Vec3(0.3f, 0.2f, -2.5f)}) {
        SCOPED_TRACE(p.z);
        const double r = coc_radius_px(R, fd, -p.z, c.height, 40.0);
        const Vec2 centre = *c.project(p);  // the lens-centre image: the disc's centre
        double max_r = 0.0;
        int inner = 0;
        for (int i = 0; i < kGrid; ++i) {
            for (int j = 0; j < kGrid; ++j) {
                const Vec2 u = grid_sample(i, j);
                const auto film = c.project(p, u);
                ASSERT_TRUE(film.has_value());
                const double d = glm::length(*film - centre);
                max_r = std::max(max_r, d);
                inner += d < 0.5 * r;
                // Round trip: the ray of (film, u) passes through p. Tolerance: float round-off
                // of the projection and the ray over |p| <= 10 (~1e-6 relative, 1e-4 margin).
                EXPECT_LT(distance_to_ray(c.generate_ray(*film, u), p), 1e-4f * glm::length(p));
            }
        }
        // The disc's radius: the outermost grid centres sit at 1 - 1/kGrid of the lens radius
        // (concentric map), so max_r is in [r (1 - 1/kGrid), r]; 1e-4 relative for float.
        EXPECT_LE(max_r, r * (1.0 + 1e-4));
        EXPECT_GE(max_r, r * (1.0 - 1.0 / kGrid - 1e-4));
        // Uniform disc: a quarter of its area lies within half its radius. The grid is
        // stratified, so the fraction is off by the boundary cells only (~1/kGrid).
        EXPECT_NEAR(double(inner) / (kGrid * kGrid), 0.25, 1.0 / kGrid);
    }
    // Sharp at the focus distance: every lens point sees the point at one film position
    // (tolerance: float round-off, 1e-3 px).
    const Vec3 f(0.7f, -0.4f, -fd);
    const Vec2 centre = *c.project(f);
    for (int i = 0; i < kGrid; i += 7) {
        for (int j = 0; j < kGrid; j += 5) {
            const Vec2 film = *c.project(f, grid_sample(i, j));
            EXPECT_NEAR(film.x, centre.x, 1e-3f);
            EXPECT_NEAR(film.y, centre.y, 1e-3f);
        }
    }
}

TEST(Camera, PolygonalApertureIsUniformAndRotated) {
    const float R = 0.2f, rotation_deg = 20.f;
    for (int n : {3, 5, 6}) {
        SCOPED_TRACE(n);
        const Camera c = lens_camera(R, 3.f, n, rotation_deg);
        const double rot = rotation_deg * kPiD / 180.0, sector = 2.0 * kPiD / n;
        const double apothem = R * std::cos(kPiD / n);
        // Cells: the n triangles between the centre and two adjacent corners, each split into
        // the inner polygon scaled by 1/sqrt(2) and the outer band: 2n cells of equal area.
        std::vector<int> cells(2 * std::size_t(n), 0);
        double corner_r = 0.0, corner_angle = 0.0;
        for (int i = 0; i < kGrid; ++i) {
            for (int j = 0; j < kGrid; ++j) {
                const Vec2 l = c.sample_aperture(grid_sample(i, j));
                const double a = std::atan2(double(l.y), double(l.x)) - rot;
                // The sector whose edge midpoint is nearest, and the polygon's radius there.
                const double k = std::round(a / sector);
                const double off = a - k * sector;
                const double boundary = apothem / std::cos(off);
                const double rl = glm::length(l);
                ASSERT_LE(rl, boundary * (1.0 + 1e-5));  // inside the polygon (float)
                const int kk = int(((long(k) % n) + n) % n);
                cells[std::size_t(2 * kk + (rl > boundary / std::sqrt(2.0)))]++;
                if (rl > corner_r) corner_r = rl, corner_angle = a;
            }
        }
        // Uniform: each of the 2n cells holds 1/(2n) of the stratified samples, up to the
        // cells crossing cell boundaries (a few per cent of the 4096 samples at most).
        for (int count : cells) EXPECT_NEAR(double(count) / (kGrid * kGrid), 0.5 / n, 0.1 / n);
        // The farthest sample lies near a corner: at rot + pi/n + 2 pi k / n, radius R.
        EXPECT_NEAR(corner_r, R, 0.03 * R);
        const double from_corner = std::remainder(corner_angle - kPiD / n, sector);
        EXPECT_NEAR(from_corner, 0.0, 0.1 * sector);
    }
}

// The integrator draws the lens sample: a small emitter beyond the focus plane renders as a
// blur disc whose radius the thin-lens equation gives, with the pinhole image's energy.
TEST(Camera, OutOfFocusEmitterRendersAsTheCircleOfConfusion) {
    auto scene = [](const std::string& lens) {
        return scene_from(R"("camera": {"position": [0, 0, 0], "look_at": [0, 0, -1], "fov": 10,
                                          "width": 48, "height": 48)" +
                          lens + R"(},
            "shapes": [{"type": "sphere", "center": [0, 0, -10], "radius": 0.15, "emission": 1}])");
    };
    const Scene pinhole = scene(""), lens = scene(R"(, "aperture_radius": 0.5,
                                                   "focus_distance": 5)");
    // Radius (px) and energy of an image: sqrt(2 E[rho^2]) of the intensity about its centroid
    // is the radius of a uniform disc.
    auto moments = [](const Image& img, double& radius, double& energy) {
        double s = 0, sx = 0, sy = 0, sxx = 0;
        for (int y = 0; y < img.height(); ++y) {
            for (int x = 0; x < img.width(); ++x) {
                const double v = img.at(x, y).x, px = x + 0.5, py = y + 0.5;
                s += v, sx += v * px, sy += v * py, sxx += v * (px * px + py * py);
            }
        }
        const double cx = sx / s, cy = sy / s;
        radius = std::sqrt(2.0 * (sxx / s - cx * cx - cy * cy));
        energy = s;
    };
    double r_pin, e_pin, r_lens, e_lens;
    moments(facet::render::render(pinhole, test_options("direct", 64, 1)), r_pin, e_pin);
    moments(facet::render::render(lens, test_options("direct", 256, 1)), r_lens, e_lens);
    // The pinhole image is the sphere's disc, radius b = (0.15 / 10) / tan(5 deg) * 24 px; the
    // blurred image is that disc convolved with the circle of confusion (radius a): second
    // moments add, so the disc-equivalent radius is sqrt(a^2 + b^2) (the pixel box filter adds
    // 1/6 px^2 to E[rho^2] in both, < 0.5% here).
    const double a = coc_radius_px(0.5, 5.0, 10.0, 48, 10.0);
    const double b = 0.015 / std::tan(5.0 * kPiD / 180.0) * 24.0;
    EXPECT_NEAR(r_pin, b, 0.05 * b);  // 5%: the disc's edge pixels are partly covered
    // 3%: Monte Carlo noise of 256 samples (the sphere covers ~10% of the lens seen from a
    // blurred pixel) and the edge pixels.
    EXPECT_NEAR(r_lens, std::sqrt(a * a + b * b), 0.03 * std::sqrt(a * a + b * b));
    // Depth of field moves light on the film without adding or losing any (3%: noise).
    EXPECT_NEAR(e_lens, e_pin, 0.03 * e_pin);
}

TEST(Camera, ClosedApertureRendersThePinholeImageBitForBit) {
    const std::string cam = R"("camera": {"position": [0, 1, 4], "look_at": [0, 0, 0], "fov": 40,
                                            "width": 32, "height": 24)";
    const std::string rest = std::string("}, ") + facet::render::testing::kQuadLightOverPlane;
    const Scene a = scene_from(cam + rest);
    const Scene b = scene_from(cam + R"(, "aperture_radius": 0, "focus_distance": 3,
                                        "blades": 6, "rotation": 10)" +
                               rest);
    EXPECT_FALSE(b.camera().has_lens());
    EXPECT_TRUE(same_pixels(facet::render::render(a, test_options("path", 4, 7)),
                            facet::render::render(b, test_options("path", 4, 7))));
    // An open aperture changes the image (the test can fail).
    const Scene c = scene_from(cam + R"(, "aperture_radius": 0.1, "focus_distance": 3)" + rest);
    EXPECT_FALSE(same_pixels(facet::render::render(a, test_options("path", 4, 7)),
                             facet::render::render(c, test_options("path", 4, 7))));
}

// --- orthographic and lens shift -------------------------------------------------------------

TEST(Camera, OrthographicScaleIsTheLargerImageSide) {
    CameraOptions o;
    o.projection = Projection::Orthographic;
    o.ortho_scale = 4.f;
    // Landscape 200 x 100: the window is 4 x 2 scene units; portrait 100 x 200: 2 x 4.
    const Camera land = Camera::make({0, 0, 10}, {0, 0, 0}, {0, 1, 0}, 40.f, 200, 100, o);
    const Camera port = Camera::make({0, 0, 10}, {0, 0, 0}, {0, 1, 0}, 40.f, 100, 200, o);
    // Tolerance: float round-off (1e-4 px).
    auto expect_at = [](const Camera& c, Vec3 p, float x, float y) {
        const auto f = c.project(p);
        ASSERT_TRUE(f.has_value());
        EXPECT_NEAR(f->x, x, 1e-4f);
        EXPECT_NEAR(f->y, y, 1e-4f);
    };
    expect_at(land, {1.f, 0.5f, 0.f}, 150.f, 25.f);    // x = (1/2 + 1)/2 200, y = (1 - 1/1)/2...
    expect_at(land, {-2.f, -1.f, -50.f}, 0.f, 100.f);  // bottom-left corner, at any depth
    expect_at(port, {1.f, 2.f, 3.f}, 100.f, 0.f);      // top-right corner
    expect_at(port, {0.f, 0.f, 9.f}, 50.f, 100.f);
    // Rays: parallel to the view direction, from the window in the plane of the camera.
    for (const Vec2 film : {Vec2(0.f, 0.f), Vec2(37.5f, 81.f), Vec2(200.f, 100.f)}) {
        const Ray r = land.generate_ray(film);
        EXPECT_EQ(r.d, Vec3(0.f, 0.f, -1.f));
        EXPECT_EQ(r.o.z, 10.f);
        const auto back = land.project(r.o + 7.f * r.d);
        ASSERT_TRUE(back.has_value());
        EXPECT_NEAR(back->x, film.x, 1e-4f);
        EXPECT_NEAR(back->y, film.y, 1e-4f);
    }
    EXPECT_FALSE(land.project({0.f, 0.f, 11.f}).has_value());  // behind the camera plane
}

TEST(Camera, LensShiftMovesTheWindowByFractionsOfTheLargerSide) {
    CameraOptions o;
    o.shift_x = 0.25f;
    o.shift_y = 0.1f;
    const Camera c = Camera::make({0, 0, 0}, {0, 0, -1}, {0, 1, 0}, 40.f, 200, 100, o);
    // h_y = tan 20, h_x = 2 h_y (the larger side); the window centre moves by
    // 2 h_x (0.25, 0.1) = (h_x / 2, 0.2 h_x) = (h_x / 2, 0.4 h_y), so a point on the optical
    // axis is at x = (1 - 1/2) 100 = 50 and y = (1 + 0.4) 50 = 70 (film y grows downward).
    // Tolerance: float round-off (1e-3 px).
    const auto axis = c.project({0.f, 0.f, -5.f});
    ASSERT_TRUE(axis.has_value());
    EXPECT_NEAR(axis->x, 50.f, 1e-3f);
    EXPECT_NEAR(axis->y, 70.f, 1e-3f);
    // The image centre's ray points at the shifted window centre.
    const float hx = 2.f * std::tan(20.f * kPi / 180.f);
    const Ray centre = c.generate_ray({100.f, 50.f});
    EXPECT_NEAR(centre.d.x / -centre.d.z, 0.5f * hx, 1e-6f);
    EXPECT_NEAR(centre.d.y / -centre.d.z, 0.2f * hx, 1e-6f);
    // Orthographic: the shift is in scene units of the larger side (scale 4: 1 and 0.4).
    o.projection = Projection::Orthographic;
    o.ortho_scale = 4.f;
    const Camera oc = Camera::make({0, 0, 0}, {0, 0, -1}, {0, 1, 0}, 40.f, 200, 100, o);
    const Ray r = oc.generate_ray({100.f, 50.f});
    EXPECT_NEAR(r.o.x, 1.f, 1e-6f);
    EXPECT_NEAR(r.o.y, 0.4f, 1e-6f);
    // Round trips with shift and a lens, both projections (tolerance as above).
    o.aperture_radius = 0.1f;
    o.focus_distance = 4.f;
    for (Projection proj : {Projection::Perspective, Projection::Orthographic}) {
        o.projection = proj;
        const Camera lc = Camera::make({0, 0, 0}, {0, 0, -1}, {0, 1, 0}, 40.f, 200, 100, o);
        const Vec3 p(0.9f, 0.3f, -6.f);
        for (int i = 0; i < kGrid; i += 9) {
            const Vec2 u = grid_sample(i, kGrid - 1 - i);
            const auto film = lc.project(p, u);
            ASSERT_TRUE(film.has_value());
            EXPECT_LT(distance_to_ray(lc.generate_ray(*film, u), p), 1e-5f * 6.f);
        }
    }
}

// The scene analysis decides from the camera's frustum whether emitters are visible (and the
// kernel then adds emission on camera rays): the frustum must be the camera's, shifted and
// orthographic. An emissive disc only an orthographic window (or a shifted one) sees, at the
// image centre: its pixel must show the emission, 2, exactly (direct, 1 spp, pixel centre).
TEST(Camera, EmittersSeenThroughShiftedAndOrthographicWindowsAreRendered) {
    const std::string shapes = R"(, "width": 9, "height": 9},
        "shapes": [{"type": "disc", "center": [3, 0, -0.5], "normal": [0, 0, 1], "radius": 0.5,
                    "emission": 2}])";
    // Orthographic, scale 1 around x = 3: the disc is 0.5 in front of the camera plane, where
    // a perspective frustum of half-width 0.5 would reach x = 0.25 only.
    const Scene ortho = scene_from(
        R"("camera": {"position": [3, 0, 0], "look_at": [3, 0, -1], "type": "orthographic",
                      "scale": 1)" +
        shapes);
    // Perspective from the origin, fov 10, shifted right by 6 / (2 tan 5 deg) larger sides:
    // the window centre is at x/z = 6, the disc's direction, far outside the unshifted
    // frustum (|x/z| <= tan 5 deg).
    const double shift = 6.0 / (2.0 * std::tan(5.0 * kPiD / 180.0));
    const Scene shifted = scene_from(
        R"("camera": {"position": [0, 0, 0], "look_at": [0, 0, -1], "fov": 10, "shift_x": )" +
        std::to_string(shift) + shapes);
    for (const Scene* s : {&ortho, &shifted}) {
        const Image img = facet::render::render(*s, test_options("direct", 1, 1));
        EXPECT_EQ(img.at(4, 4).x, 2.f);
    }
}

// --- scene format -----------------------------------------------------------------------------

TEST(Camera, BadInputNamesTheJsonPointer) {
    const std::string base = R"({"position": [0, 0, 5], "look_at": [0, 0, 0], "width": 8,
                                 "height": 8, )";
    auto err = [&](const std::string& keys) { return error_of(base + keys + "}"); };
    // {camera keys, the error}
    const std::pair<const char*, const char*> cases[] = {
        {R"("fov": 40, "aperture_radius": 0.1, "focus_distance": 0)",
         "test.json: /camera/focus_distance: must be > 0"},
        {R"("fov": 40, "aperture_radius": 0.1)",
         "test.json: /camera/focus_distance: required with an aperture (aperture_radius or "
         "fstop)"},
        {R"("fov": 40, "aperture_radius": -0.1, "focus_distance": 2)",
         "test.json: /camera/aperture_radius: value -0.1 is out of range: must be >= 0 "
         "(scene units)"},
        {R"("fov": 40, "fstop": -2, "focal_length": 50, "focus_distance": 2)",
         "test.json: /camera/fstop: value -2 is out of range: must be > 0"},
        {R"("fov": 40, "fstop": 2, "focus_distance": 2)",
         "test.json: /camera/focal_length: required with fstop (millimetres)"},
        {R"("fov": 40, "fstop": 2, "focal_length": 50, "aperture_radius": 1,
                     "focus_distance": 2)",
         "test.json: /camera/fstop: give aperture_radius or fstop (with focal_length), not "
         "both"},
        {R"("fov": 40, "blades": 2)",
         "test.json: /camera/blades: must be 0 (round aperture) or at least 3, got 2"},
        {R"("fov": 40, "blades": 1)",
         "test.json: /camera/blades: must be 0 (round aperture) or at least 3, got 1"},
        {R"("fov": 40, "shift_x": 1e300)",
         "test.json: /camera/shift_x: value 1e+300 is out of range: must be in [-1000, "
         "1000]"},
        {R"("type": "orthographic", "scale": 0)", "test.json: /camera/scale: must be > 0"},
        {R"("type": "orthographic", "scale": -3)",
         "test.json: /camera/scale: value -3 is out of range: must be > 0"},
        {R"("type": "orthographic")", "test.json: /camera: missing required key 'scale'"},
        {R"("type": "orthographic", "scale": 2, "fov": 40)",
         "test.json: /camera/fov: an orthographic camera has no fov (its framing is "
         "'scale')"},
        {R"("fov": 40, "scale": 2)",
         "test.json: /camera/scale: 'scale' is for orthographic cameras (\"type\": "
         "\"orthographic\")"},
        {R"("type": "orthographc", "scale": 2)",
         "test.json: /camera/type: unknown camera type 'orthographc' (did you mean "
         "'orthographic'?)"},
        {R"("type": "orthographic", "scale": 2, "fstop": 2, "focal_length": 50,
                     "focus_distance": 2)",
         "test.json: /camera/fstop: an orthographic camera has no focal length: give "
         "aperture_radius (Cycles uses 1 / (2 fstop))"},
    };
    for (const auto& [keys, message] : cases) EXPECT_EQ(err(keys), message);
    // fstop and focal_length give Cycles' radius focal_length 1e-3 / (2 fstop).
    EXPECT_EQ(err(R"("fov": 40, "fstop": 2.8, "focal_length": 50, "focus_distance": 2)"), "");
    const Scene s = scene_from(
        R"("camera": {"position": [0, 0, 5], "look_at": [0, 0, 0], "width": 8, "height": 8,
                      "fov": 40, "fstop": 2.5, "focal_length": 50, "focus_distance": 2},
           "lights": [{"type": "point", "position": [0, 5, 0], "power": 1}])");
    EXPECT_FLOAT_EQ(s.camera().lens_radius, 0.05f / 5.f);
}

TEST(Camera, DescriptionRoundTripsThroughJson) {
    const std::string lights = R"(, "lights": [{"type": "point", "position": [0, 5, 0],
                                                "power": 1}]})";
    for (const std::string cam :
         {R"("fov": 30, "fstop": 4, "focal_length": 35, "focus_distance": 3.5, "blades": 7,
             "rotation": 12.5, "shift_x": -0.1, "shift_y": 0.05)",
          R"("type": "orthographic", "scale": 6, "aperture_radius": 0.02, "focus_distance": 4,
             "shift_y": 0.2)"}) {
        SCOPED_TRACE(cam);
        const std::string text =
            R"({"format": "facet-scene", "version": 1, "camera": {"position": [0, 0, 5],
                "look_at": [0, 0, 0], "width": 8, "height": 6, )" +
            cam + "}" + lights;
        const SceneDescription a = parse_scene_description(text, "a.json", ".");
        const std::string written = write_scene_json(a);
        const SceneDescription b = parse_scene_description(written, "b.json", ".");
        EXPECT_TRUE(a == b) << written;
        EXPECT_EQ(fingerprint(a), fingerprint(b));
        // Every camera field is part of the description and its fingerprint.
        SceneDescription c = a;
        c.camera.shift_y += 0.01;
        EXPECT_FALSE(a == c);
        EXPECT_NE(fingerprint(a), fingerprint(c));
        c = a;
        c.camera.blades = 5;
        EXPECT_NE(fingerprint(a), fingerprint(c));
    }
}

// The tile loop's camera rays (camera_packet: four lanes at a time for a perspective camera)
// are generate_ray's bit for bit, and generate_ray's perspective direction is still
// glm::normalize(f + s_x r + s_y u) bit for bit (the images of earlier versions). Bitwise:
// any difference is a different operation order, which would change images.
TEST(Camera, PacketRaysEqualGenerateRayBitForBit) {
    auto same_bits = [](const Vec3& a, const Vec3& b) { return std::memcmp(&a, &b, 12) == 0; };
    std::uint32_t state = 7u;
    auto uniform = [&] {
        state = state * 1664525u + 1013904223u;
        return float(state >> 8) * 0x1p-24f;
    };
    int lanes = 0;
    for (int c = 0; c < 24; ++c) {
        CameraOptions o;
        o.projection = c % 4 == 3 ? Projection::Orthographic : Projection::Perspective;
        o.ortho_scale = 3.f;
        o.shift_x = c % 3 == 1 ? 0.25f * uniform() - 0.1f : 0.f;
        o.shift_y = c % 3 == 2 ? 0.25f * uniform() - 0.1f : 0.f;
        const int width = 17 + 61 * c, height = 9 + 37 * (c % 5);
        const Camera cam =
            Camera::make(Vec3(uniform(), 2.f * uniform(), 5.f + uniform()),
                         Vec3(uniform() - 0.5f, 0.f, uniform() - 0.5f), Vec3(0.f, 1.f, 0.f),
                         10.f + 150.f * uniform(), width, height, o);
        for (int p = 0; p < 40; ++p) {
            const int y = int(uniform() * float(height));
            const int x0 = int(uniform() * float(width)) & ~7;
            const std::size_t n = std::min<std::size_t>(RayPacket::kSize, std::size_t(width - x0));
            float fx[RayPacket::kSize], fy[RayPacket::kSize];
            for (std::size_t k = 0; k < RayPacket::kSize; ++k) {
                fx[k] = uniform();
                fy[k] = uniform();
            }
            RayPacket rays;
            camera_packet(cam, x0, y, fx, fy, n, rays);
            for (std::size_t k = 0; k < n; ++k, ++lanes) {
                const Vec2 film(float(x0 + int(k)) + fx[k], float(y) + fy[k]);
                const Ray ref = cam.generate_ray(film);
                const Ray got = rays.get(k);
                ASSERT_TRUE(same_bits(got.o, ref.o) && same_bits(got.d, ref.d) &&
                            got.tmax == ref.tmax)
                    << "camera " << c << " lane " << k << " film " << film.x << ", " << film.y;
                if (cam.projection == Projection::Perspective) {
                    const float sx =
                        (2.f * film.x / float(width) - 1.f) * cam.tan_half_x + cam.center_x;
                    const float sy =
                        (1.f - 2.f * film.y / float(height)) * cam.tan_half_y + cam.center_y;
                    const Vec3 d = glm::normalize(cam.forward + sx * cam.right + sy * cam.true_up);
                    ASSERT_TRUE(same_bits(ref.d, d)) << "camera " << c << " lane " << k;
                }
            }
        }
    }
    EXPECT_GT(lanes, 5000);
}
