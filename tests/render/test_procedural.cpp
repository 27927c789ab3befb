// Procedural texture kinds (texture_kinds.h: noise, white noise, voronoi, gradient, musgrave,
// wave, magic, brick) against Blender 3.4's own evaluation of the same
// nodes at the same points (procedural_blender.json, made by bench/procedural_blender.py:
// Geometry Nodes evaluate each texture node at 44 points, through Blender's CPU port of Cycles'
// kernels, code independent of Facet's). Tolerance 2e-5 absolute (values are O(1)): float
// evaluation in a different operation order (Blender's SIMD Perlin, its fused vector
// arithmetic) differs by a few ulps per step, and fBm sums up to 16 octaves of them.
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>

#include "facet/render/scene.h"
#include "facet/render/texture_kinds.h"

namespace fr = facet::render;
using facet::Rgb;
using facet::Vec3;
using nlohmann::json;

namespace {

json reference() {
    std::ifstream in(FACET_PROCEDURAL_BLENDER_JSON);
    return json::parse(in);
}

// An emission quad whose radiance is texture `tex` (object coordinates, identity mapping).
fr::Scene scene_with(const json& tex) {
    json s = {{"format", "facet-scene"},
              {"version", 1},
              {"camera",
               {{"position", {0, 0, 5}},
                {"look_at", {0, 0, 0}},
                {"up", {0, 1, 0}},
                {"fov", 40},
                {"width", 4},
                {"height", 4}}},
              {"shapes",
               {{{"type", "quad"},
                 {"vertices", {{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}}},
                 {"emission", tex}}}}};
    return fr::load_scene_from_string(s.dump(), "procedural");
}

}  // namespace

TEST(Procedural, MatchesBlender) {
    const json ref = reference();
    const json& points = ref["points"];
    int compared = 0;
    double worst = 0.0;
    for (const json& c : ref["cases"]) {
        const json& pr = c["params"];
        // Blender 3.4's Geometry Nodes evaluation of 4D Minkowski F1 disagrees with Cycles' (its
        // F2 and every other 4D case agree): blender.procedural renders it with Cycles instead.
        if (c["kind"] == "voronoi" && pr["dimensions"] == 4 && pr["distance"] == "minkowski" &&
            pr["feature"] == "f1")
            continue;
        // Cycles saturates the Gradient Texture to [0, 1] (svm_node_tex_gradient); Geometry
        // Nodes do not.
        const bool saturate = c["kind"] == "gradient";
        // Through a scene's emission (the JSON reader and build_scene), or, for Musgrave, whose
        // values may be negative (no emission), built alone.
        json tex = {{std::string(c["kind"]), c["params"]}, {"coordinates", "object"}};
        std::optional<fr::Scene> scene;
        std::optional<fr::Texture> alone;
        const fr::Texture* t = nullptr;
        if (c["kind"] == "musgrave") {
            fr::TextureDesc d;
            d.kind = "musgrave";
            d.coordinates = "object";
            for (const auto& [key, v] : pr.items()) {
                if (v.is_string())
                    d.params.set(key, std::string(v));
                else
                    d.params.set(key, double(v));
            }
            alone = fr::build_procedural_texture(d, false);
            t = &*alone;
        } else {
            scene = scene_with(tex);
            t = scene->shapes()[0].emission_texture;
        }
        ASSERT_NE(t, nullptr);
        for (std::size_t i = 0; i < points.size(); ++i) {
            fr::TexturePoint p;
            p.object = Vec3(float(points[i][0]), float(points[i][1]), float(points[i][2]));
            const Rgb got = t->eval(p);
            // Musgrave's and Magic's values are unclamped: their ranges (for the validation and
            // the clamp where a material reads them) must hold every value.
            if (c["kind"] == "musgrave" || c["kind"] == "magic" || c["kind"] == "wave") {
                EXPECT_GE(got.r, t->min_value().r) << pr.dump() << " point " << i;
                EXPECT_LE(got.r, t->max_value().r) << pr.dump() << " point " << i;
            }
            const json& want = c["values"][i];
            for (std::size_t k = 0; k < want.size(); ++k) {
                // Facet clamps nothing here (an emission): compare the raw value.
                const double w = saturate ? std::clamp(double(want[k]), 0.0, 1.0) : double(want[k]);
                const double diff = std::fabs(double(got[int(k)]) - w);
                worst = std::max(worst, diff);
                EXPECT_NEAR(got[int(k)], w, 2e-5)
                    << c["kind"] << " " << c["params"].dump() << " point " << i << " channel " << k;
                ++compared;
            }
        }
    }
    EXPECT_GT(compared, 5000);
    std::cout << "compared " << compared << " values, largest difference " << worst << "\n";
}

// A Voronoi F1 value that Blender's reference does not decide: the cell structure itself, from
// the definition. With randomness 0 every feature point is its cell's corner, so F1 (Euclidean)
// is the distance to the nearest integer lattice point.
TEST(Procedural, VoronoiLatticeWithoutRandomness) {
    const fr::Scene scene =
        scene_with({{"voronoi", {{"scale", 1}, {"randomness", 0}}}, {"coordinates", "object"}});
    const fr::Texture* t = scene.shapes()[0].emission_texture;
    for (const Vec3 x : {Vec3(0.2f, 0.3f, 0.9f), Vec3(-1.4f, 2.6f, 0.5f), Vec3(3.f, 0.f, -0.1f)}) {
        fr::TexturePoint p;
        p.object = x;
        const Vec3 d = x - glm::round(x);
        EXPECT_NEAR(t->eval(p).r, glm::length(d), 1e-6f) << x.x;
    }
}

// Errors name the JSON path of the bad parameter.
TEST(Procedural, BadParametersNameTheirPath) {
    auto error_of = [](const json& tex) {
        try {
            scene_with(tex);
        } catch (const std::exception& e) {
            return std::string(e.what());
        }
        return std::string("no error");
    };
    EXPECT_NE(error_of({{"noise", {{"detail", 20}}}}).find("/shapes/0/emission/noise/detail"),
              std::string::npos);
    EXPECT_NE(error_of({{"noise", {{"detial", 2}}}}).find("did you mean 'detail'"),
              std::string::npos);
    EXPECT_NE(
        error_of({{"voronoi", {{"feature", "f3"}}}}).find("/shapes/0/emission/voronoi/feature"),
        std::string::npos);
    EXPECT_NE(error_of({{"gradient", json::object()}, {"coordinates", "generatd"}})
                  .find("/shapes/0/emission/coordinates"),
              std::string::npos);
    EXPECT_NE(error_of({{"noise", {{"dimensions", 2.5}}}}).find("must be an integer"),
              std::string::npos);
}

// Generated coordinates: the hit's object-space point normalised to the shape's bounding box
// (Blender's automatic texture space), so that a linear gradient along x runs from 0 at the
// box's -x side to 1 at its +x side, whatever the shape's transform.
TEST(Procedural, GeneratedCoordinatesSpanTheBox) {
    json s = {{"format", "facet-scene"},
              {"version", 1},
              {"camera",
               {{"type", "orthographic"},
                {"scale", 8},
                {"position", {1, 0, 5}},
                {"look_at", {1, 0, 0}},
                {"up", {0, 1, 0}},
                {"width", 64},
                {"height", 64}}},
              {"shapes",
               {{{"type", "quad"},
                 {"vertices", {{-2, -1, 0}, {2, -1, 0}, {2, 1, 0}, {-2, 1, 0}}},
                 {"transform", {{"translate", {1, 0, 0}}}},
                 {"emission", {{"gradient", json::object()}}}}}}};
    const fr::Scene scene = fr::load_scene_from_string(s.dump(), "generated");
    for (const float x : {-0.9f, 0.f, 1.f, 2.5f}) {
        fr::Ray r;
        r.o = Vec3(x, 0.3f, 5.f);
        r.d = Vec3(0.f, 0.f, -1.f);
        r.tmax = 100.f;
        fr::SurfaceHit hit;
        ASSERT_TRUE(scene.intersect(r, hit));
        // World x in [-1, 3] is object x in [-2, 2]: generated x = (x + 1) / 4.
        EXPECT_NEAR(hit.emitted_radiance.r, (x + 1.f) / 4.f, 1e-6f) << x;
    }
}

namespace {

// One shape under an orthographic camera at (0, 0, 5) looking down -z, 8 x 4 units over
// 64 x 32 pixels; the hit of ray (o, d).
fr::SurfaceHit view_hit(const json& shape, const Vec3& o, const Vec3& d,
                        const json& prototypes = nullptr, const json& materials = nullptr) {
    json s = {{"format", "facet-scene"},
              {"version", 1},
              {"camera",
               {{"type", "orthographic"},
                {"scale", 8},
                {"position", {0, 0, 5}},
                {"look_at", {0, 0, 0}},
                {"up", {0, 1, 0}},
                {"width", 64},
                {"height", 32}}},
              {"lights", {{{"type", "environment"}, {"radiance", 0.1}}}},
              {"shapes", {shape}}};
    if (!prototypes.is_null()) s["prototypes"] = prototypes;
    if (!materials.is_null()) s["materials"] = materials;
    const fr::Scene scene = fr::load_scene_from_string(s.dump(), "view");
    fr::Ray r;
    r.o = o;
    r.d = glm::normalize(d);
    r.tmax = 100.f;
    fr::SurfaceHit hit;
    EXPECT_TRUE(scene.intersect(r, hit));
    return hit;
}

// A linear gradient (its value: x clamped to [0, 1]) at coordinates `c`, x = row . (c, 1).
json gradient_of(const std::string& coordinates, const json& row) {
    return {{"gradient", json::object()},
            {"coordinates", coordinates},
            {"mapping", {{"matrix", {row, {0, 1, 0, 0}, {0, 0, 1, 0}}}}}};
}

}  // namespace

// The view-dependent coordinates at single hits, against their definitions (Cycles 3.4's
// svm_node_tex_coord): 0.5 + 0.5 x a component read through a gradient. Tolerance 1e-6: float
// arithmetic on O(1) values.
TEST(Procedural, ViewCoordinatesAtHits) {
    // Normal: a unit sphere turned by 90 degrees about z; the ray down -z at x = 0.6 hits
    // (0.6, 0, 0.8), world normal (0.6, 0, 0.8), object normal (0, -0.6, 0.8).
    const json sphere = {{"type", "sphere"},
                         {"center", {0, 0, 0}},
                         {"radius", 1},
                         {"transform", {{"rotate", {{"axis", {0, 0, 1}}, {"angle", 90}}}}}};
    json s = sphere;
    s["emission"] = gradient_of("normal", {0, 0.5, 0, 0.5});
    EXPECT_NEAR(view_hit(s, Vec3(0.6f, 0.f, 5.f), Vec3(0, 0, -1)).emitted_radiance.r, 0.2f, 1e-6f);
    s["emission"] = gradient_of("normal", {0, 0, 0.5, 0.5});
    EXPECT_NEAR(view_hit(s, Vec3(0.6f, 0.f, 5.f), Vec3(0, 0, -1)).emitted_radiance.r, 0.9f, 1e-6f);
    // Reflection (world space): a quad in z = 0 seen along d = (0.3, 0, -1) / L reflects to
    // (0.3, 0, 1) / L, whatever the quad's transform.
    const float l = std::sqrt(1.09f);
    json q = {{"type", "quad"},
              {"vertices", {{-3, -1.5, 0}, {3, -1.5, 0}, {3, 1.5, 0}, {-3, 1.5, 0}}},
              {"transform", {{"rotate", {{"axis", {0, 0, 1}}, {"angle", 30}}}}}};
    q["emission"] = gradient_of("reflection", {0.5, 0, 0, 0.5});
    EXPECT_NEAR(view_hit(q, Vec3(0.f, 0.f, 5.f), Vec3(0.3f, 0.f, -1.f)).emitted_radiance.r,
                0.5f + 0.15f / l, 1e-6f);
    q["emission"] = gradient_of("reflection", {0, 0, 0.5, 0.5});
    EXPECT_NEAR(view_hit(q, Vec3(0.f, 0.f, 5.f), Vec3(0.3f, 0.f, -1.f)).emitted_radiance.r,
                0.5f + 0.5f / l, 1e-6f);
    // Camera: (x right, y up, z forward) from the camera's position: (1, -0.5, 5) at the hit
    // (1, -0.5, 0).
    q["emission"] = gradient_of("camera", {0.25, 0, 0, 0.25});
    EXPECT_NEAR(view_hit(q, Vec3(1.f, -0.5f, 5.f), Vec3(0, 0, -1)).emitted_radiance.r, 0.5f, 1e-6f);
    q["emission"] = gradient_of("camera", {0, 0.5, 0, 0.5});
    EXPECT_NEAR(view_hit(q, Vec3(1.f, -0.5f, 5.f), Vec3(0, 0, -1)).emitted_radiance.r, 0.25f,
                1e-6f);
    q["emission"] = gradient_of("camera", {0, 0, 0.1, 0});
    EXPECT_NEAR(view_hit(q, Vec3(1.f, -0.5f, 5.f), Vec3(0, 0, -1)).emitted_radiance.r, 0.5f, 1e-6f);
    // Window: x = 1 / 8 + 0.5, y = -0.5 / 4 + 0.5 from the bottom.
    q["emission"] = gradient_of("window", {1, 0, 0, 0});
    EXPECT_NEAR(view_hit(q, Vec3(1.f, -0.5f, 5.f), Vec3(0, 0, -1)).emitted_radiance.r, 0.625f,
                1e-6f);
    q["emission"] = gradient_of("window", {0, 1, 0, 0});
    EXPECT_NEAR(view_hit(q, Vec3(1.f, -0.5f, 5.f), Vec3(0, 0, -1)).emitted_radiance.r, 0.375f,
                1e-6f);
}

// An instanced shape's object space is its own frame within the prototype (the instance's
// transform is not in it), as for object coordinates: the hit keeps its object-space normal in
// po (scene.h), the shape's turn within the prototype undone, the instance's too.
TEST(Procedural, NormalCoordinatesOfInstances) {
    const json materials = {
        {"m", {{"model", "lambert"}, {"reflectance", gradient_of("normal", {0, 0.5, 0, 0.5})}}}};
    // A quad in its own plane y = 0 (normal -y), turned by 90 degrees about z within the
    // prototype (normal +x there), placed turned by -90 degrees about y (normal +z in the
    // world, toward the ray): object, prototype and world normals all differ.
    const json quad = {{"type", "quad"},
                       {"vertices", {{-1, 0, -1}, {1, 0, -1}, {1, 0, 1}, {-1, 0, 1}}},
                       {"material", "m"},
                       {"transform", {{"rotate", {{"axis", {0, 0, 1}}, {"angle", 90}}}}}};
    const json prototypes = {{"card", {quad}}};
    const json instance = {
        {"type", "instance"},
        {"of", "card"},
        {"transform",
         {{"rotate", {{"axis", {0, 1, 0}}, {"angle", -90}}}, {"translate", {0.5, 0, 0}}}}};
    const fr::SurfaceHit hit =
        view_hit(instance, Vec3(1.1f, 0.2f, 5.f), Vec3(0, 0, -1), prototypes, materials);
    EXPECT_NEAR(std::fabs(hit.ng.z), 1.f, 1e-5f);
    EXPECT_NEAR(hit.po.x, 0.f, 1e-5f);
    EXPECT_NEAR(hit.po.y, -1.f, 1e-5f);
    EXPECT_NEAR(hit.po.z, 0.f, 1e-5f);
    // Object coordinates beside normal ones on a prototype's shape: refused by name.
    try {
        json mm = materials;
        mm["m"]["reflectance"] = {{"mix_rgb",
                                   {{"fac", 0.5},
                                    {"color1", gradient_of("normal", {0, 0.5, 0, 0.5})},
                                    {"color2", gradient_of("object", {0.5, 0, 0, 0.5})}}}};
        view_hit(instance, Vec3(1.1f, 0.2f, 5.f), Vec3(0, 0, -1), prototypes, mm);
        ADD_FAILURE() << "normal and object coordinates on a prototype's shape load";
    } catch (const std::exception& e) {
        EXPECT_NE(std::string(e.what()).find("prototype's shape"), std::string::npos) << e.what();
    }
}
