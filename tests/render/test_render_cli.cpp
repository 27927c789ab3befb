// The `facet render` and `facet diff` commands: documented errors and exit codes, outputs.
#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <utility>

#include "facet/render/image.h"

#ifndef FACET_CLI
#error "FACET_CLI must be the path of the facet executable"
#endif

namespace fr = facet::render;

namespace {

struct CmdResult {
    int code;
    std::string output;  // stdout + stderr
};

CmdResult run(const std::string& args) {
    const std::string cmd = std::string(FACET_CLI) + " " + args + " 2>&1";
    CmdResult r{-1, ""};
    FILE* p = popen(cmd.c_str(), "r");
    if (!p) return r;
    std::array<char, 4096> buf;
    size_t n;
    while ((n = fread(buf.data(), 1, buf.size(), p)) > 0) r.output.append(buf.data(), n);
    const int status = pclose(p);
    r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    return r;
}

class CliTest : public ::testing::Test {
  protected:
    void SetUp() override {
        m_dir = std::filesystem::temp_directory_path() /
                ("facet_cli_" + std::to_string(::getpid()) + "_" +
                 ::testing::UnitTest::GetInstance()->current_test_info()->name());
        std::filesystem::create_directories(m_dir);
    }
    void TearDown() override { std::filesystem::remove_all(m_dir); }
    std::string write(const std::string& name, const std::string& text) {
        const std::string path = (m_dir / name).string();
        std::ofstream(path) << text;
        return path;
    }
    std::string path(const std::string& name) const { return (m_dir / name).string(); }
    std::filesystem::path m_dir;
};

const char* kScene = R"({"format": "facet-scene", "version": 1,
  "camera": {"position": [0, 3, 3], "look_at": [0, 0, 0], "fov": 50, "width": 16, "height": 12},
  "materials": {"glossy": {"model": "ggx", "alpha": 0.3}, "white": {"model": "lambert"}},
  "shapes": [{"type": "plane", "point": [0, 0, 0], "normal": [0, 1, 0], "material": "white"}],
  "lights": [{"type": "point", "position": [0, 2, 0], "power": 50}],
  "render": {"integrator": "direct", "spp": 1}})";

}  // namespace

TEST_F(CliTest, RenderWritesExrAndPngAndExplains) {
    const std::string scene = write("s.json", kScene);
    const CmdResult r =
        run("render " + scene + " -o " + path("a.exr") + " -o " + path("a.png") + " --explain -q");
    ASSERT_EQ(r.code, 0) << r.output;
    EXPECT_NE(r.output.find("kernel direct<lambert-only"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("skipped: light sampling"), std::string::npos) << r.output;
    const fr::Image a = fr::read_image(path("a.exr"));
    EXPECT_EQ(a.width(), 16);
    EXPECT_EQ(a.height(), 12);
    EXPECT_EQ(fr::read_image(path("a.png")).width(), 16);
    // diff of an image with itself: zero error, exit 0; --json is machine readable.
    const CmdResult d = run("diff " + path("a.exr") + " " + path("a.exr") + " --json");
    ASSERT_EQ(d.code, 0) << d.output;
    EXPECT_NE(d.output.find("\"rmse\": 0.0"), std::string::npos) << d.output;
    EXPECT_NE(d.output.find("\"fraction_within\": 1.0"), std::string::npos) << d.output;
}

TEST_F(CliTest, BadSceneNamesFileAndJsonPath) {
    std::string text = kScene;
    text.replace(text.find("\"material\": \"white\""), 19, "\"material\": \"glosy\"");
    const std::string scene = write("bad.json", text);
    const CmdResult r = run("render " + scene + " -o " + path("x.exr"));
    EXPECT_NE(r.code, 0);
    EXPECT_NE(r.output.find("bad.json: /shapes/0/material: unknown material 'glosy' (did you "
                            "mean 'glossy'?)"),
              std::string::npos)
        << r.output;
    EXPECT_FALSE(std::filesystem::exists(path("x.exr")));
    const CmdResult missing = run("render " + path("nope.json") + " -o " + path("x.exr"));
    EXPECT_NE(missing.code, 0);
    EXPECT_NE(missing.output.find("nope.json"), std::string::npos) << missing.output;
}

TEST_F(CliTest, BadFlagsFailWithMessages) {
    const std::string scene = write("s.json", kScene);
    struct Case {
        std::string args, message;
    };
    const Case cases[] = {
        {"render " + scene + " -o " + path("x.bmp"), "unknown output extension"},
        {"render " + scene + " -o " + path("x.exr") + " --integrator pth", "did you mean 'path'"},
        {"render " + scene + " -o " + path("x.exr") + " --spp 0", "--spp"},
        {"render " + scene + " -o " + path("x.exr") + " --threads -2", "--threads"},
        {"render " + scene + " -o " + path("x.exr") + " --kernel fast", "--kernel"},
        {"render " + scene, "no output"},
        {"render " + scene + " -o " + path("x.exr") + " --bogus", "--bogus"},
        // The texture memory bound: at least 1 MiB, a number (NaN fails every comparison).
        {"render " + scene + " -o " + path("x.exr") + " --texture-memory 0", "--texture-memory"},
        {"render " + scene + " -o " + path("x.exr") + " --texture-memory -4", "--texture-memory"},
        {"render " + scene + " -o " + path("x.exr") + " --texture-memory 0.5", "from 1 to"},
        {"render " + scene + " -o " + path("x.exr") + " --texture-memory nan", "--texture-memory"},
        {"render " + scene + " -o " + path("x.exr") + " --texture-memory lots", "--texture-memory"},
    };
    for (const Case& c : cases) {
        const CmdResult r = run(c.args);
        EXPECT_NE(r.code, 0) << c.args << "\n" << r.output;
        EXPECT_NE(r.output.find(c.message), std::string::npos) << c.args << "\n" << r.output;
    }
}

TEST_F(CliTest, DiffSizeMismatchAndRequire) {
    fr::Image a(4, 4), b(5, 4), c(4, 4);
    for (auto& p : c.pixels()) p = facet::Rgb(1.f);
    fr::write_image(a, path("a.exr"));
    fr::write_image(b, path("b.exr"));
    fr::write_image(c, path("c.exr"));
    const CmdResult r = run("diff " + path("a.exr") + " " + path("b.exr"));
    EXPECT_EQ(r.code, 1) << r.output;
    EXPECT_NE(r.output.find("is 4x4 but"), std::string::npos) << r.output;
    // a = 0 vs c = 1 everywhere: nothing within 1% -> --require 0.5 fails with exit code 2.
    const CmdResult q = run("diff " + path("a.exr") + " " + path("c.exr") +
                            " --require 0.5 --heatmap " + path("h.png"));
    EXPECT_EQ(q.code, 2) << q.output;
    EXPECT_NE(q.output.find("RMSE              1"), std::string::npos) << q.output;
    EXPECT_TRUE(std::filesystem::exists(path("h.png")));
}

TEST_F(CliTest, RegionAndSamplePartsMergeIntoTheSingleRender) {
    std::string text = kScene;
    text.replace(text.find("\"spp\": 1"), 8, "\"spp\": 4");
    const std::string scene = write("s.json", text);
    ASSERT_EQ(run("render " + scene + " -q -o " + path("whole.exr")).code, 0);
    // Left half, and the right half in two sample ranges on different thread counts.
    const std::string parts[] = {
        "render " + scene + " -q --region 0,0,7,12 -o " + path("left.fpart"),
        "render " + scene + " -q --region 7,0,16,12 --samples 0:1 --threads 1 -o " +
            path("r0.fpart"),
        "render " + scene + " -q --region 7,0,16,12 --samples 1:4 -o " + path("r1.fpart")};
    for (const std::string& p : parts) {
        const CmdResult r = run(p);
        ASSERT_EQ(r.code, 0) << p << "\n" << r.output;
    }
    const CmdResult m = run("merge " + path("left.fpart") + " " + path("r0.fpart") + " " +
                            path("r1.fpart") + " -o " + path("merged.exr"));
    ASSERT_EQ(m.code, 0) << m.output;
    const fr::Image a = fr::read_image(path("whole.exr")), b = fr::read_image(path("merged.exr"));
    ASSERT_EQ(a.pixels().size(), b.pixels().size());
    for (std::size_t i = 0; i < a.pixels().size(); ++i)
        ASSERT_EQ(a.pixels()[i], b.pixels()[i]) << i;
    // Errors name the part: a missing range, an overlap, a different seed, a bad flag.
    const CmdResult gap =
        run("merge " + path("left.fpart") + " " + path("r1.fpart") + " -o " + path("x.exr"));
    EXPECT_NE(gap.code, 0);
    EXPECT_NE(gap.output.find("pixel (7, 0) has 3 of samples [0, 4)"), std::string::npos)
        << gap.output;
    const CmdResult overlap =
        run("merge " + path("left.fpart") + " " + path("left.fpart") + " -o " + path("x.exr"));
    EXPECT_NE(overlap.output.find("left.fpart overlap"), std::string::npos) << overlap.output;
    ASSERT_EQ(
        run("render " + scene + " -q --seed 9 --region 7,0,16,12 -o " + path("s9.fpart")).code, 0);
    const CmdResult seed =
        run("merge " + path("left.fpart") + " " + path("s9.fpart") + " -o " + path("x.exr"));
    EXPECT_NE(seed.output.find("s9.fpart: rendered with seed 9"), std::string::npos) << seed.output;
    EXPECT_FALSE(std::filesystem::exists(path("x.exr")));
    const CmdResult flag = run("render " + scene + " -q --region 0,0,7 -o " + path("y.fpart"));
    EXPECT_NE(flag.output.find("--region: expected x0,y0,x1,y1"), std::string::npos) << flag.output;
    const CmdResult range = run("render " + scene + " -q --samples 2:9 -o " + path("y.fpart"));
    EXPECT_NE(range.output.find("--samples: 2:9 must be a non-empty range"), std::string::npos)
        << range.output;
}

// --shadow-catcher-pass (scenes/FORMAT.md "Shadow catchers") on a scene whose plane is a shadow
// catcher: render writes the pass beside the image (Combined then the matte: RGBA, the lit
// plane transparent), and merge of two region parts writes the same two files' pixels bit for
// bit. The pass is 1 where nothing is shadowed and below 1 under the sphere. Errors: a bad
// extension, and --denoise with the pass.
TEST_F(CliTest, ShadowCatcherPassFromRenderAndMerge) {
    std::string text = kScene;
    text.replace(text.find("\"material\": \"white\"}"), 20,
                 "\"material\": \"white\", \"shadow_catcher\": true}, {\"type\": \"sphere\", "
                 "\"center\": [0, 0.6, 0], \"radius\": 0.4, \"material\": \"white\"}");
    text.replace(text.find("\"spp\": 1"), 8, "\"spp\": 4");
    const std::string scene = write("c.json", text);
    const CmdResult r = run("render " + scene + " -q -o " + path("whole.exr") +
                            " --shadow-catcher-pass " + path("pass.exr"));
    ASSERT_EQ(r.code, 0) << r.output;
    const std::pair<const char*, const char*> parts[] = {{"0,0,16,5", "top.fpart"},
                                                         {"0,5,16,12", "low.fpart"}};
    for (const auto& [region, name] : parts) {
        const CmdResult p = run("render " + scene + " -q --region " + region + " -o " + path(name));
        ASSERT_EQ(p.code, 0) << p.output;
    }
    const CmdResult m = run("merge " + path("top.fpart") + " " + path("low.fpart") + " -o " +
                            path("merged.exr") + " --shadow-catcher-pass " + path("mpass.exr"));
    ASSERT_EQ(m.code, 0) << m.output;
    const fr::Image a = fr::read_image(path("whole.exr")), b = fr::read_image(path("merged.exr"));
    const fr::Image pa = fr::read_image(path("pass.exr")), pb = fr::read_image(path("mpass.exr"));
    ASSERT_TRUE(a.has_alpha());
    EXPECT_FALSE(pa.has_alpha());
    EXPECT_TRUE(a.pixels() == b.pixels() && a.alpha() == b.alpha());
    EXPECT_TRUE(pa.pixels() == pb.pixels());
    int lit = 0, shadowed = 0;
    for (std::size_t i = 0; i < pa.pixels().size(); ++i) {
        lit += pa.pixels()[i] == facet::Rgb(1.f) && a.alpha()[i] == 0.f;
        shadowed += pa.pixels()[i].x < 0.9f;
    }
    EXPECT_GT(lit, 20);
    EXPECT_GT(shadowed, 3);
    const CmdResult ext = run("render " + scene + " -q -o " + path("x.exr") +
                              " --shadow-catcher-pass " + path("pass.fpart"));
    EXPECT_NE(ext.output.find("--shadow-catcher-pass " + path("pass.fpart") +
                              ": unknown image extension"),
              std::string::npos)
        << ext.output;
    const CmdResult dn = run("render " + scene + " -q --denoise -o " + path("x.exr") +
                             " --shadow-catcher-pass " + path("y.exr"));
    EXPECT_NE(dn.output.find("--shadow-catcher-pass: not with --denoise"), std::string::npos)
        << dn.output;
}

// `facet render model.gltf` on a bare glTF file: it frames the model and lights it with a
// constant environment, and says both on stderr; a broken file names its glTF pointer.
TEST_F(CliTest, RendersABareGltfFileAndSaysHow) {
    const std::string dir = FACET_GLTF_TEST_DIR;
    const CmdResult r = run("render " + dir + "/box.gltf -o " + path("g.exr") + " --spp 1 -q");
    ASSERT_EQ(r.code, 0) << r.output;
    EXPECT_NE(r.output.find("box.gltf: the file has no camera: framing its bounding box"),
              std::string::npos)
        << r.output;
    EXPECT_NE(r.output.find("box.gltf: lit by a constant white environment"), std::string::npos)
        << r.output;
    const fr::Image img = fr::read_image(path("g.exr"));
    EXPECT_EQ(img.width(), 640);
    EXPECT_EQ(img.height(), 480);
    // The centre pixel sees the box: it emits (3, 1.5, 0) on top of what it reflects, so its
    // red exceeds the environment's 1 seen around it.
    EXPECT_GT(img.at(320, 240).r, 2.f);
    EXPECT_NEAR(img.at(2, 2).r, 1.f, 1e-6f);

    const CmdResult bad = run("render " + dir + "/bad_index.gltf -o " + path("b.png") + " -q");
    EXPECT_NE(bad.code, 0);
    EXPECT_NE(bad.output.find("bad_index.gltf#/accessors/1: index 2 is 3"), std::string::npos)
        << bad.output;
}
