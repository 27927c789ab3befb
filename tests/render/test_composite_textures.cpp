// Composite texture kinds (texture_kinds.h: math, vector_math, mix_rgb, color_ramp) against
// Cycles 3.4's evaluation of the same nodes (composite_blender.json, made by
// bench/composite_blender.py: the addon's nodevalues.py, an independent double-precision port of
// Cycles' svm_math, svm_vector_math, svm_mix and rgb_ramp_lookup, with Blender's own
// ColorRamp.evaluate for the ramp table). Tolerance
// 2e-5 x max(1, |value|): Facet evaluates in float as Cycles does, the reference in double;
// the operations compound at most a few float roundings (exp, pow and the HSV round trips
// the most), about 1e-6 relative.
//
// Also: the value ranges composites state (interval arithmetic) hold every value they take,
// inputs fed by textures are evaluated at the hit, errors name the JSON path, and the JSON
// writer round-trips the kinds.
#include <gtest/gtest.h>

#include <algorithm>

#include <fstream>
#include <nlohmann/json.hpp>
#include <optional>
#include <random>

#include "facet/render/scene.h"
#include "facet/render/scene_description.h"
#include "facet/render/texture_kinds.h"

namespace fr = facet::render;
using facet::Rgb;
using facet::Vec3;
using nlohmann::json;

namespace {

json composite_reference() {
    std::ifstream in(FACET_COMPOSITE_BLENDER_JSON);
    return json::parse(in);
}

// A texture description from the JSON of its kind's parameters (as the scene format writes
// them), read by the scene reader: an emission quad's texture, without building the scene.
fr::TextureDesc composite_desc(const json& tex) {
    json s = {{"format", "facet-scene"},
              {"version", 1},
              {"camera",
               {{"position", {0, 0, 5}},
                {"look_at", {0, 0, 0}},
                {"fov", 40},
                {"width", 4},
                {"height", 4}}},
              {"shapes",
               {{{"type", "quad"},
                 {"vertices", {{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}}},
                 {"emission", tex}}}}};
    const fr::SceneDescription d = fr::parse_scene_description(s.dump(), "composite");
    return *d.shapes.at(0).emission_texture;
}

// A gradient along object x, clamped to [0, 1]: the hit's x as a number texture.
const json kX = {{"gradient", {{"type", "linear"}}}, {"coordinates", "object"}};

fr::TexturePoint hit_at(float x, float y = 0.f) {
    fr::TexturePoint p;
    p.object = Vec3(x, y, 0.f);
    return p;
}

// A range is a bound on the exact (real-number) value, computed in double; the float
// evaluation rounds a few times (float sinh, a * b + c, ...), so it may pass the bound by a
// few ulps (users of the range clamp to it). 1e-5 relative is far below any real bound error
// the range tests look for (those miss by whole terms of the operation).
float range_slack(float bound) {
    return 1e-5f * std::max(1.f, std::fabs(bound));
}

std::string composite_error(const json& tex, bool color = true) {
    try {
        fr::build_procedural_texture(composite_desc(tex), color, "/t");
    } catch (const std::exception& e) {
        return e.what();
    }
    return "no error";
}

}  // namespace

TEST(CompositeTextures, MatchCycles) {
    const json ref = composite_reference();
    int compared = 0;
    double worst = 0.0;
    for (const json& c : ref["cases"]) {
        const std::string kind = c["kind"];
        json params = c["params"];
        const bool ramp = kind == "color_ramp";
        if (ramp) params["fac"] = kX;  // fac from a texture: the hit's x
        const fr::Texture t =
            fr::build_procedural_texture(composite_desc({{kind, params}}), true, "/case");
        const std::size_t n = ramp ? c["facs"].size() : 1;
        for (std::size_t i = 0; i < n; ++i) {
            const float f = ramp ? float(c["facs"][i]) : 0.f;
            const Rgb got = t.eval(hit_at(f));
            const json& want = ramp ? c["values"][i] : c["value"];
            for (std::size_t k = 0; k < 3; ++k) {
                const double w = double(want[want.size() == 1 ? 0 : k]);
                const double diff = std::fabs(double(got[int(k)]) - w);
                worst = std::max(worst, diff / std::max(1.0, std::fabs(w)));
                EXPECT_LE(diff, 2e-5 * std::max(1.0, std::fabs(w)))
                    << kind << " " << c["params"].dump() << " fac " << f << " channel " << k << ": "
                    << got[int(k)] << " vs " << w;
                // The stated range holds the value (up to float rounding: range_slack).
                EXPECT_GE(got[int(k)], t.min_value()[int(k)] - range_slack(t.min_value()[int(k)]))
                    << kind << " " << params.dump();
                EXPECT_LE(got[int(k)], t.max_value()[int(k)] + range_slack(t.max_value()[int(k)]))
                    << kind << " " << params.dump();
                ++compared;
            }
        }
    }
    EXPECT_GT(compared, 5000);
    std::cout << "compared " << compared << " values, largest relative difference " << worst
              << "\n";
}

// Inputs fed by textures are evaluated at the hit: x * x, mix(red, green, x) and a ramp of x.
TEST(CompositeTextures, InputsEvaluatedAtTheHit) {
    const fr::Texture sq = fr::build_procedural_texture(
        composite_desc({{"math", {{"operation", "multiply"}, {"a", kX}, {"b", kX}}}}), false, "/t");
    const fr::Texture mix = fr::build_procedural_texture(
        composite_desc({{"mix_rgb", {{"fac", kX}, {"color1", {1, 0, 0}}, {"color2", {0, 1, 0}}}}}),
        true, "/t");
    const fr::Texture nested = fr::build_procedural_texture(
        composite_desc({{"math",
                         {{"operation", "add"},
                          {"a", {{"math", {{"operation", "sqrt"}, {"a", kX}}}}},
                          {"b", 0.25}}}}),
        false, "/t");
    for (float x : {0.f, 0.1f, 0.37f, 0.5f, 0.9f, 1.f}) {
        EXPECT_NEAR(sq.eval(hit_at(x)).r, x * x, 1e-7f);
        EXPECT_NEAR(mix.eval(hit_at(x)).r, 1.f - x, 1e-7f);
        EXPECT_NEAR(mix.eval(hit_at(x)).g, x, 1e-7f);
        EXPECT_NEAR(nested.eval(hit_at(x)).r, std::sqrt(x) + 0.25f, 1e-6f);
    }
    EXPECT_EQ(sq.inputs(), unsigned(fr::kTextureReadsPosition));
    EXPECT_EQ(sq.min_value().r, 0.f);
    EXPECT_EQ(sq.max_value().r, 1.f);
    // Constants only: reads nothing.
    const fr::Texture k = fr::build_procedural_texture(
        composite_desc({{"math", {{"operation", "power"}, {"a", 2}, {"b", 3}}}}), false, "/t");
    EXPECT_EQ(k.inputs(), 0u);
    EXPECT_EQ(k.eval(hit_at(0.f)).r, 8.f);
}

// fac_color (the Mix node's Vector mode with a Non-Uniform factor): one factor per channel,
// a + t_c (b - a) in each channel c, clamped per channel with clamp_factor; the range is the
// per-channel corners. Exact in float for these values (tolerance 1e-7: one rounding).
TEST(CompositeTextures, FactorPerChannel) {
    const json tx = {
        {"mix_rgb",
         {{"fac_color", {{"mix_rgb", {{"fac", kX}, {"color1", {0, 1, 2}}, {"color2", {1, 0, 2}}}}}},
          {"color1", {0.2, 0.2, 0.2}},
          {"color2", {1, 0.6, 0}}}}};
    const fr::Texture t = fr::build_procedural_texture(composite_desc(tx), true, "/t");
    for (float x : {0.f, 0.25f, 0.5f, 1.f}) {
        const Rgb v = t.eval(hit_at(x));
        // t = (x, 1 - x, 2 -> clamped to 1).
        EXPECT_NEAR(v.r, 0.2f + x * 0.8f, 1e-7f) << x;
        EXPECT_NEAR(v.g, 0.2f + (1.f - x) * 0.4f, 1e-7f) << x;
        EXPECT_NEAR(v.b, 0.f, 1e-7f) << x;
    }
    EXPECT_NEAR(t.min_value().r, 0.2f, 1e-7f);
    EXPECT_NEAR(t.max_value().r, 1.f, 1e-7f);
    EXPECT_NEAR(t.max_value().g, 0.6f, 1e-7f);
    json unclamped = tx;
    unclamped["mix_rgb"]["clamp_factor"] = false;
    EXPECT_NEAR(
        fr::build_procedural_texture(composite_desc(unclamped), true, "/t").eval(hit_at(0.5f)).b,
        0.2f - 2.f * 0.2f, 1e-7f);
    auto has = [](const std::string& s, const std::string& what) {
        return s.find(what) != std::string::npos;
    };
    std::string e = composite_error({{"mix_rgb", {{"fac_color", {0.1, 0.2, 0.3}}, {"fac", 0.5}}}});
    EXPECT_TRUE(has(e, "/t/mix_rgb/fac_color") && has(e, "not both")) << e;
    e = composite_error(
        {{"mix_rgb", {{"fac_color", {0.1, 0.2, 0.3}}, {"blend_type", "multiply"}}}});
    EXPECT_TRUE(has(e, "/t/mix_rgb/fac_color") && has(e, "'mix'")) << e;
}

// The ranges are conservative for every operation and blend type over random input ranges:
// inputs a = lo_a + (hi_a - lo_a) x, b likewise in y, c a constant; every value at a grid of
// points lies in [min_value, max_value]. (A range that misses values fails here; the clamp
// where a material reads a texture would otherwise change them.)
TEST(CompositeTextures, RangesHoldEveryValue) {
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> u(-3.0, 3.0);
    auto ramp_in = [](double lo, double hi, bool y) {
        json g = kX;
        if (y) g["mapping"] = {{"matrix", {{0, 1, 0, 0}, {1, 0, 0, 0}, {0, 0, 1, 0}}}};
        return json{{"math", {{"operation", "multiply_add"}, {"a", g}, {"b", hi - lo}, {"c", lo}}}};
    };
    // A colour whose channels differ, each over [lo, hi].
    auto colour_in = [&](double lo, double hi, bool y) {
        const double mid = 0.5 * (lo + hi);
        return json{{"mix_rgb",
                     {{"fac", ramp_in(0.0, 1.0, y)},
                      {"color1", {lo, mid, hi}},
                      {"color2", {hi, lo, mid}}}}};
    };
    const auto* math = fr::find_texture_kind("math");
    const auto* mix = fr::find_texture_kind("mix_rgb");
    const auto* vmath = fr::find_texture_kind("vector_math");
    int checked = 0, bounded = 0;
    for (int trial = 0; trial < 12; ++trial) {
        double la = u(rng), ha = u(rng), lb = u(rng), hb = u(rng);
        if (la > ha) std::swap(la, ha);
        if (lb > hb) std::swap(lb, hb);
        if (trial % 3 == 0)
            la = std::fabs(la), ha = std::fabs(ha) + la, lb = std::fabs(lb),
            hb = std::fabs(hb) + lb;  // non-negative colours (HSV blends)
        const double c = u(rng);
        std::vector<json> texs;
        for (const std::string& op : math->params[0].choices)
            for (bool clamp : {false, true})
                texs.push_back({{"math",
                                 {{"operation", op},
                                  {"use_clamp", clamp},
                                  {"a", ramp_in(la, ha, false)},
                                  {"b", ramp_in(lb, hb, true)},
                                  {"c", c}}}});
        for (const std::string& blend : mix->params[0].choices)
            for (bool cf : {false, true})
                texs.push_back({{"mix_rgb",
                                 {{"blend_type", blend},
                                  {"clamp_factor", cf},
                                  {"fac", ramp_in(-0.2, 1.2, false)},
                                  {"color1", colour_in(la, ha, false)},
                                  {"color2", colour_in(lb, hb, true)}}}});
        for (const std::string& op : vmath->params[0].choices) {
            const bool value = op == "dot_product" || op == "distance" || op == "length";
            texs.push_back({{"vector_math",
                             {{"operation", op},
                              {"output", value ? "value" : "vector"},
                              {"a", colour_in(la, ha, false)},
                              {"b", colour_in(lb, hb, true)},
                              {"c", {c, -0.5 * c, 0.25}},
                              {"scale", ramp_in(-c, 1.0, true)}}}});
        }
        for (const json& tex : texs) {
            std::optional<fr::Texture> built;
            try {
                built = fr::build_procedural_texture(composite_desc(tex), true, "/t");
            } catch (const std::invalid_argument& e) {
                // Unbounded: must say so (never a silent infinite range).
                EXPECT_NE(std::string(e.what()).find("cannot be bounded"), std::string::npos)
                    << e.what();
                continue;
            }
            ++bounded;
            const fr::Texture& t = *built;
            for (int i = 0; i <= 20; ++i)
                for (int j = 0; j <= 20; ++j) {
                    const Rgb v = t.eval(hit_at(float(i) / 20.f, float(j) / 20.f));
                    for (int k = 0; k < 3; ++k) {
                        if (std::isnan(v[k])) continue;
                        ASSERT_GE(v[k], t.min_value()[k] - range_slack(t.min_value()[k]))
                            << tex.dump() << " at " << i << "," << j;
                        ASSERT_LE(v[k], t.max_value()[k] + range_slack(t.max_value()[k]))
                            << tex.dump() << " at " << i << "," << j;
                        ++checked;
                    }
                }
        }
    }
    EXPECT_GT(bounded, 1200);
    std::cout << "checked " << checked << " values of " << bounded << " bounded textures\n";
}

// Constant ramps, and the ramp's table read: Constant holds the entry below, no blend.
TEST(CompositeTextures, RampConstantAndSingleStop) {
    const json stops = {{{"position", 0.5}, {"color", {1, 0, 0}}},
                        {{"position", 0.75}, {"color", {0, 0, 1, 0.5}}}};
    const fr::Texture c = fr::build_procedural_texture(
        composite_desc(
            {{"color_ramp", {{"fac", kX}, {"interpolation", "constant"}, {"stops", stops}}}}),
        true, "/t");
    EXPECT_EQ(c.eval(hit_at(0.2f)), Rgb(1, 0, 0));
    EXPECT_EQ(c.eval(hit_at(0.74f)), Rgb(1, 0, 0));
    EXPECT_EQ(c.eval(hit_at(0.9f)), Rgb(0, 0, 1));
    const fr::Texture a = fr::build_procedural_texture(
        composite_desc({{"color_ramp", {{"fac", kX}, {"output", "alpha"}, {"stops", stops}}}}),
        false, "/t");
    EXPECT_EQ(a.eval(hit_at(0.1f)).r, 1.f);
    EXPECT_EQ(a.eval(hit_at(1.f)).r, 0.5f);
    EXPECT_EQ(a.min_value().r, 0.5f);
    EXPECT_EQ(a.max_value().r, 1.f);
}

// A colour texture read as a number through "channel" (Blender's colour -> number links):
// the luminance 0.2126 R + 0.7152 G + 0.0722 B (as for images) or one channel, grey, with
// the range of the ends' luminance.
TEST(CompositeTextures, ChannelOfAColour) {
    const json mix = {{"mix_rgb", {{"fac", kX}, {"color1", {1, 0, 0}}, {"color2", {0, 0.5, 1}}}},
                      {"channel", "luminance"}};
    const fr::Texture t = fr::build_procedural_texture(composite_desc(mix), false, "/t");
    for (float x : {0.f, 0.3f, 1.f}) {
        const float r = 1.f - x, g = 0.5f * x, b = x;
        EXPECT_NEAR(t.eval(hit_at(x)).r, 0.2126f * r + 0.7152f * g + 0.0722f * b, 1e-6f);
        EXPECT_EQ(t.eval(hit_at(x)).g, t.eval(hit_at(x)).r);
    }
    EXPECT_NEAR(t.min_value().r, 0.f, 1e-7f);
    EXPECT_NEAR(t.max_value().r, 0.2126f + 0.7152f * 0.5f + 0.0722f, 1e-6f);
    const fr::Texture g = fr::build_procedural_texture(
        composite_desc({{"noise", {{"output", "color"}}}, {"channel", "g"}}), false, "/t");
    EXPECT_EQ(g.min_value().r, 0.f);
    std::string e =
        composite_error(json{{"mix_rgb", {{"color1", {1, 0, 0}}}}, {"channel", "a"}}, false);
    EXPECT_NE(e.find("/t/channel"), std::string::npos) << e;
    e = composite_error({{"color_ramp",
                          {{"stops",
                            {{{"position", 0.2}, {"color", {1, 0, 0}}},
                             {{"position", 0.8}, {"color", {0, 0, 1}}}}}}}},
                        false);
    EXPECT_NE(e.find("/t/color_ramp/output"), std::string::npos) << e;
    // A procedural kind's colour output read as a number: needs a channel (its per-channel
    // range [0, 1] looks grey, its values are not).
    e = composite_error({{"noise", {{"output", "color"}}}}, false);
    EXPECT_TRUE(e.find("/t/noise/output") != std::string::npos &&
                e.find("channel") != std::string::npos)
        << e;
    // Gradient's and Wave's colours are grey: read as numbers.
    EXPECT_EQ(composite_error({{"gradient", {{"output", "color"}}}}, false), "no error");
}

// Errors name the JSON path of the bad parameter.
TEST(CompositeTextures, BadInputNamesItsPath) {
    auto has = [](const std::string& s, const std::string& what) {
        return s.find(what) != std::string::npos;
    };
    std::string e = composite_error({{"math", {{"operation", "multiplyy"}}}});
    EXPECT_TRUE(has(e, "/t/math/operation") && has(e, "multiply")) << e;
    e = composite_error({{"math",
                          {{"operation", "divide"},
                           {"a", kX},
                           {"b", {{"math", {{"operation", "subtract"}, {"a", kX}}}}}}}});
    EXPECT_TRUE(has(e, "/t/math") && has(e, "cannot be bounded") && has(e, "divide")) << e;
    e = composite_error({{"color_ramp",
                          {{"stops",
                            {{{"position", 0.5}, {"color", {1, 0, 0}}},
                             {{"position", 0.25}, {"color", {0, 1, 0}}}}}}}});
    EXPECT_TRUE(has(e, "/t/color_ramp/stops/1/position") && has(e, "order")) << e;
    e = composite_error({{"color_ramp", {{"stops", {{{"position", 1.5}, {"color", {1, 0, 0}}}}}}}});
    EXPECT_TRUE(has(e, "/t/color_ramp/stops/0/position") && has(e, "[0, 1]")) << e;
    e = composite_error({{"color_ramp", {{"stops", json::array()}}}});
    EXPECT_TRUE(has(e, "/t/color_ramp/stops") && has(e, "at least one")) << e;
    e = composite_error({{"math", {{"a", {1, 0, 0}}}}}, false);
    EXPECT_TRUE(has(e, "/t/math/a")) << e;
    e = composite_error({{"mix_rgb", {{"color1", {1, 0, 0}}}}}, false);
    EXPECT_TRUE(has(e, "/t/mix_rgb/color1") && has(e, "number")) << e;
    e = composite_error({{"math", {{"operation", "add"}}}, {"coordinates", "object"}});
    EXPECT_TRUE(has(e, "/t/coordinates")) << e;
    e = composite_error({{"noise", {{"scale", kX}}}});
    EXPECT_TRUE(has(e, "/t/noise/scale") && has(e, "constant")) << e;
    e = composite_error({{"math", {{"use_clamp", 1}}}});
    EXPECT_TRUE(has(e, "/t/math/use_clamp") && has(e, "true or false")) << e;
    e = composite_error({{"mix_rgb", {{"blend_type", "exclusion"}}}});
    EXPECT_TRUE(has(e, "/t/mix_rgb/blend_type")) << e;
    e = composite_error({{"math", {{"a", {{"noise", {{"scale", -1}, {"detail", 99}}}}}}}});
    EXPECT_TRUE(has(e, "/t/math/a/noise/detail")) << e;
}

// The writer writes what the reader reads: nested inputs, colours, booleans and stops.
TEST(CompositeTextures, JsonRoundTrip) {
    const json tex = {{"mix_rgb",
                       {{"blend_type", "overlay"},
                        {"use_clamp", true},
                        {"fac",
                         {{"color_ramp",
                           {{"fac", kX},
                            {"interpolation", "b_spline"},
                            {"output", "alpha"},
                            {"stops",
                             {{{"position", 0.1}, {"color", {1, 0.5, 0, 0.25}}},
                              {{"position", 0.9}, {"color", {0, 0, 1, 1}}}}}}}}},
                        {"color1", {0.2, 0.3, 0.4}},
                        {"color2", {{"math", {{"operation", "sine"}, {"a", kX}}}}}}},
                      {"scale", 2.0},
                      {"channel", "luminance"}};
    json s = {{"format", "facet-scene"},
              {"version", 1},
              {"camera",
               {{"position", {0, 0, 5}},
                {"look_at", {0, 0, 0}},
                {"fov", 40},
                {"width", 4},
                {"height", 4}}},
              {"shapes",
               {{{"type", "quad"},
                 {"vertices", {{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}}},
                 {"emission", tex}}}}};
    const fr::SceneDescription d = fr::parse_scene_description(s.dump(), "rt");
    const fr::SceneDescription back = fr::parse_scene_description(fr::write_scene_json(d), "rt");
    ASSERT_TRUE(back.shapes.at(0).emission_texture.has_value());
    EXPECT_TRUE(*back.shapes[0].emission_texture == *d.shapes[0].emission_texture);
    const fr::TextureDesc& t = *back.shapes[0].emission_texture;
    ASSERT_EQ(t.inputs.size(), 2u);
    EXPECT_EQ(t.inputs[1].name, "fac");
    EXPECT_EQ(t.inputs[1].texture.stops.size(), 2u);
    // And it builds and renders as an emitter.
    const fr::Scene scene = fr::build_scene(d, "rt");
    EXPECT_GT(scene.shapes()[0].emission_texture->max_value().r, 0.f);
}

// A Brick Texture's colours fed by textures (Blender's Color1 / Color2 / Mortar linked): at
// every point, the brick with the texture's value there as a constant colour; the range is
// the inputs' hull; the Fac output takes no texture (an error naming the parameter).
TEST(CompositeTextures, BrickColoursFromTextures) {
    const json brick = {
        {"scale", 2},        {"mortar_size", 0.1}, {"mortar_smooth", 0.5},     {"brick_width", 0.4},
        {"row_height", 0.2}, {"output", "color"},  {"color2", {0.1, 0.3, 0.2}}};
    json textured = brick;
    textured["color1"] = kX;
    textured["mortar"] = {{"gradient", {{"type", "linear"}}},
                          {"coordinates", "object"},
                          {"mapping", {{"matrix", {{0, 1, 0, 0.5}, {0, 1, 0, 0}, {0, 0, 1, 0}}}}}};
    const fr::Texture t = fr::build_procedural_texture(
        composite_desc({{"brick", textured}, {"coordinates", "object"}}), true, "/t");
    EXPECT_EQ(t.inputs(), unsigned(fr::kTextureReadsPosition));
    EXPECT_EQ(t.min_value(), Rgb(0.f));
    EXPECT_EQ(t.max_value(), Rgb(1.f));
    int varied = 0;
    for (int i = 0; i < 40; ++i) {
        const float x = 0.023f * float(i), y = 0.37f - 0.017f * float(i);
        json constant = brick;
        constant["color1"] = {x, x, x};
        const float m = std::clamp(y + 0.5f, 0.f, 1.f);
        constant["mortar"] = {m, m, m};
        const fr::Texture c = fr::build_procedural_texture(
            composite_desc({{"brick", constant}, {"coordinates", "object"}}), true, "/t");
        const Rgb want = c.eval(hit_at(x, y)), got = t.eval(hit_at(x, y));
        for (int k = 0; k < 3; ++k) EXPECT_NEAR(got[k], want[k], 1e-6f) << i;
        varied += want != c.eval(hit_at(x + 0.5f, y));  // (the colour varies along the bricks)
    }
    EXPECT_GT(varied, 0);
    json fac = textured;
    fac["output"] = "fac";
    EXPECT_NE(composite_error({{"brick", fac}}).find("/t/brick/color1"), std::string::npos)
        << composite_error({{"brick", fac}});
}

// Vector Math with textures as inputs, evaluated at the hit: a = (x, 1 - x, 0.5), b = (1, 2, x)
// (exact in float up to a few roundings: tolerance 1e-6); the Value output is grey; a number
// texture computes with grey vectors; ranges hold the values.
TEST(CompositeTextures, VectorMathAtTheHit) {
    const json a = {{"mix_rgb", {{"fac", kX}, {"color1", {0, 1, 0.5}}, {"color2", {1, 0, 0.5}}}}};
    const json b = {{"mix_rgb", {{"fac", kX}, {"color1", {1, 2, 0}}, {"color2", {1, 2, 1}}}}};
    auto build = [&](const std::string& op, const std::string& out, bool color = true) {
        return fr::build_procedural_texture(
            composite_desc(
                {{"vector_math", {{"operation", op}, {"output", out}, {"a", a}, {"b", b}}}}),
            color, "/t");
    };
    const fr::Texture cross = build("cross_product", "vector");
    const fr::Texture dot = build("dot_product", "value", false);
    const fr::Texture len = build("length", "value");
    const fr::Texture nrm = build("normalize", "vector");
    for (float x : {0.f, 0.2f, 0.5f, 0.8f, 1.f}) {
        const Vec3 va(x, 1.f - x, 0.5f), vb(1.f, 2.f, x);
        const Vec3 want = glm::cross(va, vb);
        const Rgb got = cross.eval(hit_at(x));
        for (int k = 0; k < 3; ++k) {
            EXPECT_NEAR(got[k], want[k], 1e-6f) << x;
            EXPECT_GE(got[k], cross.min_value()[k] - range_slack(cross.min_value()[k]));
            EXPECT_LE(got[k], cross.max_value()[k] + range_slack(cross.max_value()[k]));
        }
        EXPECT_NEAR(dot.eval(hit_at(x)).r, glm::dot(va, vb), 1e-6f) << x;
        EXPECT_EQ(len.eval(hit_at(x)).g, len.eval(hit_at(x)).r);
        EXPECT_NEAR(len.eval(hit_at(x)).b, glm::length(va), 1e-6f) << x;
        EXPECT_NEAR(nrm.eval(hit_at(x)).r, va.x / glm::length(va), 1e-6f) << x;
    }
    // |a| over the range box [0, 1] x [0, 1] x {0.5} (the channels' ranges, independently):
    // from its point nearest 0, (0, 0, 0.5), to its farthest, sqrt(1 + 1 + 0.25).
    EXPECT_NEAR(len.min_value().r, 0.5f, 1e-6f);
    EXPECT_NEAR(len.max_value().r, 1.5f, 1e-6f);
    EXPECT_EQ(dot.inputs(), unsigned(fr::kTextureReadsPosition));
    // A number texture: grey vectors (a = x), scaled by the number 3.
    const fr::Texture grey = fr::build_procedural_texture(
        composite_desc({{"vector_math", {{"operation", "scale"}, {"a", kX}, {"scale", 3}}}}), false,
        "/t");
    EXPECT_NEAR(grey.eval(hit_at(0.25f)).r, 0.75f, 1e-7f);
    EXPECT_EQ(grey.max_value().r, 3.f);
}

// Vector Math's errors name the JSON path: the output that the operation does not give, an
// unbounded range (divide by a vector whose range holds 0, tangent over a pole), a colour
// vector read by a number parameter without a channel, an unknown operation.
TEST(CompositeTextures, VectorMathErrors) {
    auto has = [](const std::string& s, const std::string& what) {
        return s.find(what) != std::string::npos;
    };
    std::string e = composite_error({{"vector_math", {{"operation", "length"}}}});
    EXPECT_TRUE(has(e, "/t/vector_math/output") && has(e, "value")) << e;
    e = composite_error({{"vector_math", {{"operation", "add"}, {"output", "value"}}}});
    EXPECT_TRUE(has(e, "/t/vector_math/output") && has(e, "vector")) << e;
    e = composite_error({{"vector_math", {{"operation", "divide"}, {"a", {1, 1, 1}}, {"b", kX}}}});
    EXPECT_TRUE(has(e, "/t/vector_math") && has(e, "cannot be bounded") && has(e, "divide")) << e;
    e = composite_error({{"vector_math",
                          {{"operation", "tangent"},
                           {"a", {{"math", {{"operation", "multiply"}, {"a", kX}, {"b", 4}}}}}}}});
    EXPECT_TRUE(has(e, "/t/vector_math") && has(e, "tangent")) << e;
    e = composite_error({{"vector_math", {{"operation", "cross_product"}, {"a", {1, 0, 0}}}}},
                        false);
    EXPECT_TRUE(has(e, "/t/vector_math/a") && has(e, "number")) << e;
    e = composite_error({{"vector_math", {{"operation", "crossproduct"}}}});
    EXPECT_TRUE(has(e, "/t/vector_math/operation") && has(e, "cross_product")) << e;
    e = composite_error({{"vector_math", {{"operation", "scale"}, {"scale", {1, 0, 0}}}}});
    EXPECT_TRUE(has(e, "/t/vector_math/scale")) << e;
    // A number parameter computes with grey vectors: a colour constant is an error, unless the
    // texture reads a channel of the result.
    const json c = {{"vector_math", {{"operation", "cross_product"}, {"a", {1, 0, 0}}, {"b", kX}}}};
    e = composite_error(c, false);
    EXPECT_TRUE(has(e, "/t/vector_math/a") && has(e, "number")) << e;
    json ch = c;
    ch["channel"] = "b";
    EXPECT_EQ(composite_error(ch, false), "no error");
}

// The writer writes what the reader reads: vector_math with nested inputs and the output; the
// scene builds and the texture emits.
TEST(CompositeTextures, VectorMathJsonRoundTrip) {
    const json tex = {
        {"vector_math",
         {{"operation", "dot_product"},
          {"output", "value"},
          {"a", {{"noise", {{"output", "color"}}}, {"coordinates", "object"}}},
          {"b", {{"vector_math", {{"operation", "scale"}, {"a", {0.2, 0.4, 1}}, {"scale", kX}}}}}}},
        {"scale", 0.5}};
    json s = {{"format", "facet-scene"},
              {"version", 1},
              {"camera",
               {{"position", {0, 0, 5}},
                {"look_at", {0, 0, 0}},
                {"fov", 40},
                {"width", 4},
                {"height", 4}}},
              {"shapes",
               {{{"type", "quad"},
                 {"vertices", {{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}}},
                 {"emission", tex}}}}};
    const fr::SceneDescription d = fr::parse_scene_description(s.dump(), "rt");
    const std::string w = fr::write_scene_json(d);
    const fr::SceneDescription back = fr::parse_scene_description(w, "rt");
    ASSERT_TRUE(back.shapes.at(0).emission_texture.has_value());
    EXPECT_TRUE(*back.shapes[0].emission_texture == *d.shapes[0].emission_texture);
    EXPECT_NE(w.find("\"dot_product\""), std::string::npos) << w;
    const fr::Scene scene = fr::build_scene(d, "rt");
    EXPECT_NEAR(scene.shapes()[0].emission_texture->max_value().r, 0.5f * 1.6f, 1e-6f);
}
