// The renderer as a library (issue 9): SceneDescription round trips, build_scene's checks of
// what a non-JSON producer can get wrong, render sessions (callback, cancel, continue), and
// region / sample-range parts that merge into exactly the single render's image.
//
// Every image comparison here is bit for bit (operator== on float pixels): the film's
// fixed-point sums (film.h) and the image-aligned packets (render.h) make the result independent
// of how the work was split, so any difference is a bug, not noise.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <thread>

#include "facet/render/render.h"
#include "facet/render/scene_description.h"
#include "facet/testsupport/render_test_util.h"

namespace fr = facet::render;
using facet::Rgb;
using facet::Vec3;

namespace {

const std::string kScenes = FACET_SCENES_DIR;

bool same_pixels(const fr::Image& a, const fr::Image& b) {
    if (a.width() != b.width() || a.height() != b.height()) return false;
    return std::memcmp(a.pixels().data(), b.pixels().data(), a.pixels().size() * sizeof(Rgb)) == 0;
}

std::size_t count_nonfinite(const fr::Image& img) {
    std::size_t n = 0;
    for (const Rgb& p : img.pixels()) n += !facet::is_finite(p);
    return n;
}

// The Cornell box at a quarter of its resolution: every feature of the path kernel (area
// light, MIS, indirect light) in a fraction of a second.
fr::SceneDescription small_cornell() {
    fr::SceneDescription d = fr::read_scene_description(kScenes + "/cornell_box.json");
    d.camera.width = 61;  // not a multiple of 8 or of the tile size: ragged packets and tiles
    d.camera.height = 47;
    return d;
}

fr::RenderOptions options(int spp, int threads = 2) {
    return fr::testing::test_options("path", spp, 7, threads);
}

// A flat mesh description: a 1 x 1 quad of two triangles at height 0 under a point light.
fr::SceneDescription mesh_scene(std::vector<float> positions, std::vector<std::uint32_t> indices,
                                std::vector<float> normals = {}) {
    fr::SceneDescription d;
    d.camera.position = {0.f, 2.f, 2.f};
    d.camera.look_at = {0.f, 0.f, 0.f};
    d.camera.fov = 40.0;
    d.camera.width = 16;
    d.camera.height = 12;
    d.materials.push_back({"white", {"lambert", {}, {}}});
    fr::ShapeDesc s;
    s.kind = fr::ShapeKind::Mesh;
    s.name = "floor";
    s.material_ref = "white";
    s.mesh = fr::MeshData::copy_of(std::move(positions), std::move(indices), std::move(normals));
    d.shapes.push_back(s);
    fr::LightDesc l;
    l.kind = fr::LightKind::Point;
    l.position = {0.f, 1.f, 0.f};
    l.power = Rgb(10.f);
    d.lights.push_back(l);
    d.render.integrator = "direct";
    d.render.spp = 1;
    return d;
}

const std::vector<float> kQuad = {-1, 0, -1, 1, 0, -1, 1, 0, 1, -1, 0, 1};
const std::vector<std::uint32_t> kQuadIdx = {0, 2, 1, 0, 3, 2};

std::string build_error(const fr::SceneDescription& d) {
    try {
        fr::build_scene(d, "desc");
    } catch (const fr::SceneError& e) {
        return e.what();
    }
    return "";
}

}  // namespace

// --- description, reader, writer -----------------------------------------------------------

TEST(SceneDescription, EveryShippedSceneRoundTripsToAnEqualDescriptionAndImage) {
    for (const auto& entry : std::filesystem::directory_iterator(kScenes)) {
        if (entry.path().extension() != ".json") continue;
        SCOPED_TRACE(entry.path().string());
        fr::SceneDescription a = fr::read_scene_description(entry.path().string());
        const std::string text = fr::write_scene_json(a);
        fr::SceneDescription b = fr::parse_scene_description(text, "written.json", a.base_dir);
        EXPECT_TRUE(a == b);
        EXPECT_EQ(fr::fingerprint(a), fr::fingerprint(b));
        // Writing again gives the same text (the writer is a function of the description).
        EXPECT_EQ(fr::write_scene_json(b), text);
        // Same image, bit for bit, at a reduced size (both descriptions reduced alike).
        for (fr::SceneDescription* d : {&a, &b}) {
            d->camera.width = std::max(8, d->camera.width / 8);
            d->camera.height = std::max(6, d->camera.height / 8);
        }
        const fr::Scene sa = fr::build_scene(a, "a"), sb = fr::build_scene(b, "b");
        fr::RenderOptions o;
        o.spp = 2;
        o.threads = 2;
        EXPECT_TRUE(same_pixels(fr::render(sa, o), fr::render(sb, o)));
    }
}

TEST(SceneDescription, LoadSceneEqualsReadThenBuild) {
    const std::string path = kScenes + "/mirrors_fresnel.json";
    const fr::Scene direct = fr::load_scene(path);
    const fr::Scene built = fr::build_scene(fr::read_scene_description(path), path);
    EXPECT_EQ(direct.fingerprint(), built.fingerprint());
    fr::RenderOptions o = options(2);
    EXPECT_TRUE(same_pixels(fr::render(direct, o), fr::render(built, o)));
}

TEST(SceneDescription, FingerprintTellsScenesApart) {
    fr::SceneDescription a = small_cornell(), b = a;
    EXPECT_EQ(fr::fingerprint(a), fr::fingerprint(b));
    for (fr::ShapeDesc& s : b.shapes)
        if (s.emission != Rgb(0.f)) s.emission.x *= 1.0001f;  // the light, slightly redder
    EXPECT_NE(fr::fingerprint(a), fr::fingerprint(b));
    fr::SceneDescription m1 = mesh_scene(kQuad, kQuadIdx), m2 = m1;
    std::vector<float> moved = kQuad;
    moved[1] = 1e-3f;
    m2.shapes[0].mesh = fr::MeshData::copy_of(moved, kQuadIdx);
    EXPECT_NE(fr::fingerprint(m1), fr::fingerprint(m2));
    EXPECT_FALSE(m1 == m2);
}

TEST(SceneDescription, MeshFromCallerArraysEqualsItsJsonTwin) {
    // Spans over arrays the caller owns (no owner): build_scene copies what it needs.
    std::vector<float> p = kQuad;
    std::vector<std::uint32_t> ix = kQuadIdx;
    fr::SceneDescription d = mesh_scene({}, {});
    d.shapes[0].mesh = fr::MeshData{p, ix, {}, nullptr, {}};
    const fr::Scene from_arrays = fr::build_scene(d, "arrays");
    const fr::Scene from_json = fr::load_scene_from_string(fr::write_scene_json(d), "twin.json");
    fr::RenderOptions o = fr::testing::test_options("direct", 1, 0);
    EXPECT_TRUE(same_pixels(fr::render(from_arrays, o), fr::render(from_json, o)));
    EXPECT_EQ(from_arrays.fingerprint(), from_json.fingerprint());
}

// --- build_scene checks ----------------------------------------------------------------------

TEST(BuildScene, NamesTheShapeForBadMeshData) {
    const float nan = std::nanf("");
    std::vector<float> p = kQuad;
    p[4] = nan;
    EXPECT_EQ(build_error(mesh_scene(p, kQuadIdx)),
              "desc: /shapes/0 ('floor'): position 1 is not finite");
    std::vector<float> n(12, 0.f);
    for (int i = 0; i < 4; ++i) n[3 * i + 1] = 1.f;
    n[5] = INFINITY;
    EXPECT_EQ(build_error(mesh_scene(kQuad, kQuadIdx, n)),
              "desc: /shapes/0 ('floor'): normal 1 is not finite");
    EXPECT_EQ(build_error(mesh_scene(kQuad, {0, 1, 4})),
              "desc: /shapes/0/indices/2: value 4 is out of range: must be in [0, 3]");
    EXPECT_EQ(build_error(mesh_scene(kQuad, {})),
              "desc: /shapes/0/indices: expected a flat array of 3n vertex indices");
    EXPECT_EQ(build_error(mesh_scene({}, kQuadIdx)),
              "desc: /shapes/0/positions: expected a flat array of 3n numbers (x0, y0, z0, x1, "
              "...)");
    EXPECT_EQ(build_error(mesh_scene(kQuad, kQuadIdx, {0, 1, 0})),
              "desc: /shapes/0/normals: expected one normal per position (4), got 1");
    // Every triangle degenerate: nothing left to render is an error, not an empty shape.
    EXPECT_EQ(build_error(mesh_scene(kQuad, {0, 0, 1, 2, 2, 2})),
              "desc: /shapes/0 ('floor'): mesh has no triangles with non-zero area");
}

TEST(BuildScene, ZeroAreaTrianglesAreDroppedCountedAndNeverNaN) {
    // The quad's two triangles plus three degenerate ones (repeated index, collinear points).
    std::vector<float> p = kQuad;
    p.insert(p.end(), {0.f, 0.f, 0.f, 0.5f, 0.f, 0.5f});  // 4: origin, 5: on the diagonal 0-2
    fr::SceneDescription d = mesh_scene(p, {0, 2, 1, 0, 3, 2, 0, 0, 1, 4, 5, 2, 3, 3, 3});
    fr::BuildReport report;
    const fr::Scene s = fr::build_scene(d, "desc", {}, &report);
    EXPECT_EQ(report.degenerate_triangles, 3u);
    ASSERT_EQ(s.warnings().size(), 1u);
    EXPECT_EQ(s.warnings()[0], "/shapes/0 ('floor'): dropped 3 zero-area triangles");
    EXPECT_EQ(s.shapes()[0].triangles, 2u);
    // Same image as the clean quad.
    const fr::Scene clean = fr::build_scene(mesh_scene(kQuad, kQuadIdx), "clean");
    fr::RenderOptions o = fr::testing::test_options("direct", 1, 0);
    const fr::Image img = fr::render(s, o);
    EXPECT_EQ(count_nonfinite(img), 0u);
    EXPECT_TRUE(same_pixels(img, fr::render(clean, o)));
}

TEST(BuildScene, MaterialsLightsCameraAndTransforms) {
    fr::SceneDescription d = mesh_scene(kQuad, kQuadIdx);
    d.lights.clear();
    EXPECT_EQ(build_error(d),
              "desc: /lights: the scene has no light source (no entry in \"lights\" and no shape "
              "that emits: \"emission\" or a glTF emissive material)");
    d = mesh_scene(kQuad, kQuadIdx);
    d.materials.push_back({"white", {"lambert", {}, {}}});
    EXPECT_EQ(build_error(d), "desc: /materials/white: duplicate material name 'white'");
    d = mesh_scene(kQuad, kQuadIdx);
    d.materials[0].second.params.set("reflectance", std::nan(""));
    EXPECT_EQ(build_error(d), "desc: /materials/white/reflectance: must be a finite number");
    d = mesh_scene(kQuad, kQuadIdx);
    d.shapes[0].material_ref = "whit";
    EXPECT_EQ(build_error(d),
              "desc: /shapes/0/material: unknown material 'whit' (did you mean 'white'?)");
    d = mesh_scene(kQuad, kQuadIdx);
    d.camera.width = 0;
    EXPECT_EQ(build_error(d),
              "desc: /camera/width: value 0 is out of range: must be in [1, 65536]");
    d = mesh_scene(kQuad, kQuadIdx);
    d.camera.position.y = std::nanf("");
    EXPECT_EQ(build_error(d), "desc: /camera/position/1: must be a finite number");
    d = mesh_scene(kQuad, kQuadIdx);
    d.shapes[0].transform = glm::dmat4(0.0);
    EXPECT_EQ(build_error(d),
              "desc: /shapes/0/transform: the last row must be [0, 0, 0, 1] (affine transforms "
              "only)");
    d.shapes[0].transform = glm::dmat4(1.0);
    (*d.shapes[0].transform)[1][1] = 0.0;
    EXPECT_EQ(build_error(d),
              "desc: /shapes/0/transform: the transform is singular (zero scale?) or not finite");
    d = mesh_scene(kQuad, kQuadIdx);
    d.lights[0].kind = fr::LightKind::Spot;
    EXPECT_EQ(build_error(d), "desc: /lights/0: give exactly one of \"direction\" and \"look_at\"");
    d.lights[0].direction = Vec3(0.f);
    EXPECT_EQ(build_error(d), "desc: /lights/0/direction: must be a non-zero direction");
}

// --- sessions --------------------------------------------------------------------------------

TEST(RenderSession, CallbackSeesEveryPassAndTheImageIsTheRenderOfTheTotal) {
    const fr::Scene scene = fr::build_scene(small_cornell(), "cornell");
    fr::RenderOptions o = options(12);
    o.pass_seconds = 1e-4;  // force small passes
    fr::RenderSession session(scene, o);
    std::vector<int> seen;
    ASSERT_TRUE(session.render([&](const fr::PassInfo& p) {
        seen.push_back(p.samples_done);
        EXPECT_EQ(p.samples_target, 12);
        EXPECT_GE(p.eta_s, 0.0);
        const fr::Image now = session.image();  // readable between passes
        EXPECT_EQ(count_nonfinite(now), 0u);
        return true;
    }));
    ASSERT_GE(seen.size(), 2u);
    EXPECT_EQ(seen.front(), 1);
    EXPECT_EQ(seen.back(), 12);
    EXPECT_TRUE(std::is_sorted(seen.begin(), seen.end()));
    EXPECT_TRUE(same_pixels(session.image(), fr::render(scene, options(12))));
}

TEST(RenderSession, CancelFromAnotherThreadKeepsAValidImageAndContinues) {
    fr::SceneDescription d = small_cornell();
    d.camera.width = 160;
    d.camera.height = 120;
    const fr::Scene scene = fr::build_scene(d, "cornell");
    const int spp = 512;  // far more than the test waits for
    fr::RenderSession session(scene, options(spp));
    std::atomic<bool> started{false};
    std::thread canceller([&] {
        while (!started.load()) std::this_thread::yield();
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
        session.cancel();
    });
    started = true;
    const bool complete = session.render();
    canceller.join();
    ASSERT_FALSE(complete) << "the render finished before it was cancelled";
    EXPECT_TRUE(session.stats().cancelled);
    EXPECT_LT(session.samples_done(), spp);
    EXPECT_EQ(count_nonfinite(session.image()), 0u);
    EXPECT_THROW(session.part(), std::logic_error);
    // Continuing from the cancelled state to a small target gives exactly the fresh render.
    fr::RenderSession small(scene, options(8));
    small.render([&](const fr::PassInfo&) { return false; });  // cancelled after one pass
    EXPECT_LT(small.samples_done(), 8);
    ASSERT_TRUE(small.render());
    EXPECT_TRUE(same_pixels(small.image(), fr::render(scene, options(8))));
}

TEST(RenderSession, ContinueToMoreSamplesEqualsAFreshRender) {
    const fr::Scene scene = fr::build_scene(small_cornell(), "cornell");
    fr::RenderSession session(scene, options(4));
    ASSERT_TRUE(session.render());
    const std::uint64_t paths_before = session.stats().paths;
    session.continue_to(10);
    ASSERT_TRUE(session.render());
    EXPECT_EQ(session.samples_done(), 10);
    // Only the 6 new samples were traced.
    EXPECT_EQ(session.stats().paths - paths_before, std::uint64_t(6) * 61 * 47);
    EXPECT_TRUE(same_pixels(session.image(), fr::render(scene, options(10))));
    EXPECT_THROW(session.continue_to(5), std::invalid_argument);
    fr::RenderSession centre(scene, options(1));
    EXPECT_THROW(centre.continue_to(4), std::invalid_argument);
}

// --- regions, sample ranges, merge -----------------------------------------------------------

TEST(RenderParts, RegionAndSampleSplitsMergeBitForBit) {
    const fr::Scene scene = fr::build_scene(small_cornell(), "cornell");
    const int spp = 6;
    const fr::Image whole = fr::render(scene, options(spp));
    auto part = [&](fr::Region r, int s0, int s1, int threads) {
        fr::RenderOptions o = options(spp, threads);
        o.region = r;
        o.sample_begin = s0;
        o.sample_end = s1;
        fr::RenderSession s(scene, o);
        EXPECT_TRUE(s.render());
        return s.part();
    };
    // Regions cut at odd places (inside packets and tiles), in a shuffled order, mixed with
    // sample ranges, on 1 and 2 threads.
    std::vector<fr::RenderPart> parts;
    parts.push_back(part({0, 0, 61, 13}, 0, spp, 1));
    parts.push_back(part({37, 13, 61, 47}, 2, 5, 2));
    parts.push_back(part({0, 13, 37, 47}, 0, spp, 2));
    parts.push_back(part({37, 13, 61, 47}, 0, 2, 1));
    parts.push_back(part({37, 13, 61, 47}, 5, 6, 2));
    const std::vector<std::string> names = {"a", "b", "c", "d", "e"};
    const fr::Film merged = fr::merge_parts(parts, names);
    EXPECT_TRUE(same_pixels(merged.resolve(), whole));
    // The same through part files.
    const auto dir = std::filesystem::temp_directory_path() / "facet_parts_test";
    std::filesystem::create_directories(dir);
    std::vector<fr::RenderPart> reread;
    for (std::size_t i = 0; i < parts.size(); ++i) {
        const std::string path = (dir / (names[i] + ".fpart")).string();
        fr::write_part(parts[i], path);
        reread.push_back(fr::read_part(path));
    }
    EXPECT_TRUE(same_pixels(fr::merge_parts(reread, names).resolve(), whole));
    std::filesystem::remove_all(dir);
    // A region render's own image is the whole render's pixels of that region.
    fr::RenderOptions o = options(spp);
    o.region = fr::Region{5, 3, 29, 40};
    const fr::Image crop = fr::render(scene, o);
    for (int y = 3; y < 40; ++y)
        for (int x = 5; x < 29; ++x)
            ASSERT_EQ(crop.at(x - 5, y - 3), whole.at(x, y)) << x << "," << y;
}

TEST(RenderParts, MergeRejectsOverlapsGapsAndForeignParts) {
    const fr::Scene scene = fr::build_scene(small_cornell(), "cornell");
    auto part = [&](const fr::Scene& sc, fr::Region r, int s0, int s1, std::uint64_t seed) {
        fr::RenderOptions o = options(4);
        o.seed = seed;
        o.region = r;
        o.sample_begin = s0;
        o.sample_end = s1;
        fr::RenderSession s(sc, o);
        s.render();
        return s.part();
    };
    auto error = [](const std::vector<fr::RenderPart>& p) {
        try {
            fr::merge_parts(p, {"p0", "p1", "p2"});
        } catch (const std::runtime_error& e) {
            return std::string(e.what());
        }
        return std::string();
    };
    const fr::RenderPart top = part(scene, {0, 0, 61, 20}, 0, 4, 7);
    const fr::RenderPart bottom = part(scene, {0, 20, 61, 47}, 0, 4, 7);
    EXPECT_EQ(error({top, bottom}), "");
    EXPECT_EQ(error({top, part(scene, {0, 10, 61, 47}, 0, 4, 7)}),
              "p1 and p0 overlap: both cover samples [0, 4) of pixels [0, 10, 61, 20)");
    EXPECT_EQ(error({top, part(scene, {0, 21, 61, 47}, 0, 4, 7)}),
              "merge: pixel (0, 20) has 0 of samples [0, 4): no part covers the rest");
    EXPECT_EQ(error({top, part(scene, {0, 20, 61, 47}, 0, 2, 7)}),
              "merge: pixel (0, 20) has 2 of samples [0, 4): no part covers the rest");
    EXPECT_EQ(error({top, part(scene, {0, 20, 61, 47}, 0, 4, 8)}),
              "p1: rendered with seed 8, p0 with seed 7");
    fr::SceneDescription other = small_cornell();
    other.shapes[0].two_sided = !other.shapes[0].two_sided;
    const fr::Scene other_scene = fr::build_scene(other, "other");
    EXPECT_EQ(error({top, part(other_scene, {0, 20, 61, 47}, 0, 4, 7)})
                  .rfind("p1: from a different scene or render settings than p0", 0),
              0u);
}

TEST(RenderParts, BadOptionsAndPartFilesAreErrors) {
    const fr::Scene scene = fr::build_scene(small_cornell(), "cornell");
    fr::RenderOptions o = options(4);
    o.region = fr::Region{0, 0, 62, 10};
    EXPECT_THROW(fr::RenderSession(scene, o), std::invalid_argument);
    o = options(4);
    o.sample_begin = 2;
    o.sample_end = 5;
    EXPECT_THROW(fr::RenderSession(scene, o), std::invalid_argument);
    const auto path = (std::filesystem::temp_directory_path() / "facet_bad.fpart").string();
    {
        std::ofstream f(path);
        f << "FACETPART 1\n{\"format\": \"facet-part\"}\n";
    }
    try {
        fr::read_part(path);
        FAIL() << "no error";
    } catch (const std::runtime_error& e) {
        EXPECT_EQ(std::string(e.what()).rfind(path + ": not a valid Facet part file", 0), 0u)
            << e.what();
    }
    std::filesystem::remove(path);
}

// --- scale invariance (issue 12) ---------------------------------------------------------------

namespace {

// The Cornell box with every coordinate (shapes and camera) multiplied by `scale`.
fr::SceneDescription scaled_cornell(double scale) {
    fr::SceneDescription d = small_cornell();
    d.camera.width = 32;
    d.camera.height = 32;
    const float s = float(scale);
    d.camera.position *= s;
    d.camera.look_at *= s;
    for (fr::ShapeDesc& sh : d.shapes) {
        EXPECT_EQ(sh.kind, fr::ShapeKind::Quad);
        for (Vec3& v : sh.vertices) v *= s;
    }
    return d;
}

double relative_mse(const fr::Image& a, const fr::Image& b) {
    double sum = 0.0;
    for (std::size_t i = 0; i < a.pixels().size(); ++i) {
        for (int c = 0; c < 3; ++c) {
            const double x = a.pixels()[i][c], y = b.pixels()[i][c];
            sum += (x - y) * (x - y) / (x * x + 1e-4);
        }
    }
    return sum / double(3 * a.pixels().size());
}

}  // namespace

TEST(SceneScale, RadianceDoesNotDependOnTheUnitOfLength) {
    // Same samples at every scale; only the float rounding of the scaled geometry differs
    // (measured relative MSE 3e-14..1e-13 over 1e-8..1e9). Tolerance 1e-9: any systematic error
    // is far above it — before the fix, scale 1e7 lost 42% of the light (relative MSE 0.57: the
    // walls' float cross products overflowed to zero normals) and 1e-6 read 2.7e-3 (an absolute
    // ray-offset floor of 1e-5 against a 5.5e-4 box).
    const fr::Image ref = fr::render(fr::build_scene(scaled_cornell(1.0), "1"), options(4));
    for (double scale : {1e-8, 1e-6, 1e-3, 1e3, 1e6, 1e9}) {
        SCOPED_TRACE(scale);
        const fr::Scene s = fr::build_scene(scaled_cornell(scale), "scaled");
        const fr::Image img = fr::render(s, options(4));
        EXPECT_EQ(count_nonfinite(img), 0u);
        EXPECT_LT(relative_mse(ref, img), 1e-9);
    }
}

TEST(SceneScale, CoordinatesBeyondTheRangeAreErrorsNamingTheShape) {
    // 1e10 puts the camera at 5.6e12: beyond Scene::kMaxCoordinate (Embree's triangle test gave
    // hits at t = inf there, i.e. NaN points, and Embree aborted the process).
    EXPECT_EQ(build_error(scaled_cornell(1e10)),
              "desc: /camera/position: beyond the renderer's coordinate range of +-1e+12");
    fr::SceneDescription d = mesh_scene(kQuad, kQuadIdx);
    std::vector<float> far = kQuad;
    far[0] = 3e12f;
    d.shapes[0].mesh = fr::MeshData::copy_of(far, kQuadIdx);
    EXPECT_EQ(build_error(d).rfind("desc: /shapes/0 ('floor'): the shape reaches coordinate 3e+12, "
                                   "beyond the renderer's range of +-1e+12",
                                   0),
              0u)
        << build_error(d);
}

// The film's float-to-fixed conversion: the int64 fast path (|v| < 2^(63 - kFixedFracBits))
// against the bit arithmetic that serves every magnitude, and both against values worked out by
// hand. Exact integers: any difference is a bug (sums would no longer merge bit for bit).
TEST(Film, ToFixedFastPathEqualsTheBitArithmetic) {
    using fr::FixedSum;
    const FixedSum one = FixedSum(1) << fr::kFixedFracBits;
    EXPECT_TRUE(fr::to_fixed(1.f) == one);
    EXPECT_TRUE(fr::to_fixed(-0.5f) == -(one >> 1));
    EXPECT_TRUE(fr::to_fixed(0x1.8p-60f) == 1);    // 1.5 units: truncated toward zero
    EXPECT_TRUE(fr::to_fixed(-0x1.8p-60f) == -1);  // ... on both sides
    EXPECT_TRUE(fr::to_fixed(0x1p-61f) == 0);
    EXPECT_TRUE(fr::to_fixed(-0.f) == 0);
    EXPECT_TRUE(fr::to_fixed(8.f) == FixedSum(8) * one);  // the first value past the fast path
    // Every exponent, both signs, a spread of mantissas (and denormals), and the neighbours of
    // the fast path's limit.
    std::vector<float> values = {std::nextafter(8.f, 0.f),
                                 -std::nextafter(8.f, 0.f),
                                 8.f,
                                 -8.f,
                                 std::nextafter(fr::kMaxSampleValue, 0.f),
                                 1e-45f,
                                 -1e-45f};
    std::uint32_t state = 12345u;
    for (int e = 0; e < 255; ++e) {
        for (int i = 0; i < 64; ++i) {
            state = state * 1664525u + 1013904223u;
            const std::uint32_t bits = (std::uint32_t(e) << 23) | (state >> 9);
            float v;
            std::memcpy(&v, &bits, 4);
            if (std::fabs(v) < fr::kMaxSampleValue) {
                values.push_back(v);
                values.push_back(-v);
            }
        }
    }
    int checked_fast = 0;
    for (float v : values) {
        ASSERT_TRUE(fr::to_fixed(v) == fr::to_fixed_bits(v)) << "v = " << v;
        checked_fast += std::fabs(v) < 8.f;
    }
    EXPECT_GT(checked_fast, 1000);  // the fast path was exercised, not only the bit path
}
