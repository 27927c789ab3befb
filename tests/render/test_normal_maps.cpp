// Normal maps and tangents (facet/render/shading_normal.h, mesh.h compute_tangents): the mapped
// normal against analytic values, the cases that must leave images bit for bit unchanged,
// MikkTSpace tangents against Blender's own (tests/render/tangents), the valid-reflection bend,
// and the errors for bad input. Test images are written with OpenImageIO directly.
#include <gtest/gtest.h>

#include <OpenImageIO/imageio.h>

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <random>
#include <string>
#include <tuple>
#include <vector>

#include <unistd.h>

#include "facet/render/mesh.h"
#include "facet/render/render.h"
#include "facet/render/scene.h"
#include "facet/render/scene_description.h"
#include "facet/render/shading_normal.h"
#include "facet/testsupport/render_test_util.h"
#include "oiio_test_image.h"

namespace fr = facet::render;
using facet::Rgb;
using facet::Vec2;
using facet::Vec3;

namespace {

constexpr double kPi = 3.14159265358979323846;

std::string temp_dir() {
    const auto d = std::filesystem::temp_directory_path() /
                   ("facet_normal_maps_" + std::to_string(::getpid()));
    std::filesystem::create_directories(d);
    return d.string();
}

// A 2 x 2 float RGB image of one colour (EXR: exact texels, read linearly).
void write_constant_exr(const std::string& path, const Vec3& c) {
    std::vector<float> px;
    for (int i = 0; i < 4; ++i) px.insert(px.end(), {c.x, c.y, c.z});
    fr::testing::write_test_image(path, 2, 2, 3, px, OIIO::TypeDesc::FLOAT);
}

// The texel that encodes the tangent-space normal m (c = (m + 1) / 2).
Vec3 encode(const Vec3& m) {
    return 0.5f * (m + Vec3(1.f));
}

// The scene of a JSON body (the keys after "version"), relative paths resolved in `dir`, and
// the message of the SceneError it throws ("" when it builds).
fr::Scene scene_in(const std::string& dir, const std::string& body) {
    const std::string head = R"({"format": "facet-scene", "version": 1, )";
    return fr::load_scene_from_string(head + body + "}", "nm.json", dir);
}
std::string error_of(const std::string& dir, const std::string& body) {
    try {
        (void)scene_in(dir, body);
        return "";
    } catch (const fr::SceneError& e) {
        return e.what();
    }
}

fr::Image render(const fr::Scene& scene, const std::string& integrator, int spp) {
    return fr::render(scene, fr::testing::test_options(integrator, spp, 7, 1));
}

// An orthographic camera looking straight down -z at a 4 x 4 window of the plane z = 0.
const char* const kTopCamera =
    R"("camera": {"type": "orthographic", "position": [0, 0, 5], "look_at": [0, 0, 0],
                  "up": [0, 1, 0], "scale": 2, "width": 4, "height": 4},)";

// A number written so that it reads back exactly.
std::string exact(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.17g", v);
    return buf;
}

std::string light_from(const Vec3& toward_light) {
    const Vec3 d = -toward_light;
    return R"("lights": [{"type": "directional", "irradiance": 1, "direction": [)" + exact(d.x) +
           ", " + exact(d.y) + ", " + exact(d.z) + "]}]";
}

}  // namespace

// --- MikkTSpace against Blender ------------------------------------------------------------------

// Blender 3.4.1's Mesh.calc_tangents() per corner (make_tangent_fixture.py) against
// compute_tangents on the same corners welded into a TriangleMesh. Tolerance: the bitangent sign
// exactly, the tangent within 2e-5 rad (both accumulate in float, in different orders: a few
// ulp, measured 4.5e-6; the largest difference is printed). The sphere's corners away from the seam
// and poles average 4 to 6 triangles with different dp/du, so a missing or wrong angle weight moves
// them by far more; on the mirrored grid the vertices on x = 0 need the split by UV orientation.
TEST(Tangents, MikkTSpaceMatchesBlendersCalcTangents) {
    std::ifstream in(std::string(FACET_TANGENT_FIXTURE));
    ASSERT_TRUE(in) << FACET_TANGENT_FIXTURE;
    const nlohmann::json fixture = nlohmann::json::parse(in);
    for (const auto& [name, m] : fixture["meshes"].items()) {
        const std::vector<float> p = m["positions"], n = m["normals"], uv = m["uvs"],
                                 tan = m["tangents"];
        const std::size_t corners = p.size() / 3;
        ASSERT_EQ(corners % 3, 0u);
        fr::TriangleMesh mesh;
        std::map<std::vector<float>, std::uint32_t> weld;
        for (std::size_t c = 0; c < corners; ++c) {
            const std::vector<float> key = {p[3 * c],  p[3 * c + 1], p[3 * c + 2],
                                            n[3 * c],  n[3 * c + 1], n[3 * c + 2],
                                            uv[2 * c], uv[2 * c + 1]};
            auto [it, inserted] = weld.try_emplace(key, std::uint32_t(mesh.positions.size()));
            if (inserted) {
                mesh.positions.emplace_back(key[0], key[1], key[2]);
                mesh.normals.emplace_back(key[3], key[4], key[5]);
                mesh.uvs.emplace_back(key[6], key[7]);
            }
            mesh.indices.push_back(it->second);
        }
        const std::vector<glm::vec4> got = fr::compute_tangents(mesh);
        ASSERT_EQ(got.size(), corners);
        double worst = 0.0;
        for (std::size_t c = 0; c < corners; ++c) {
            const Vec3 want(tan[4 * c], tan[4 * c + 1], tan[4 * c + 2]);
            const Vec3 g(got[c]);
            EXPECT_EQ(got[c].w, tan[4 * c + 3]) << name << " corner " << c;
            // atan2 of |cross| and dot in double: acos of a float dot product cannot resolve
            // angles below ~3e-4.
            const glm::dvec3 gd(g), wd(want);
            const double angle = std::atan2(glm::length(glm::cross(gd, wd)), glm::dot(gd, wd));
            worst = std::max(worst, angle);
            EXPECT_LT(angle, 2e-5)
                << name << " corner " << c << ": got (" << g.x << ", " << g.y << ", " << g.z
                << "), Blender (" << want.x << ", " << want.y << ", " << want.z << ")";
        }
        std::printf("%s: %zu corners, largest angle to Blender's tangent %.3g rad\n", name.c_str(),
                    corners, worst);
    }
}

// --- normal maps rendered ------------------------------------------------------------------------

// A flat normal map, texel exactly (0.5, 0.5, 1), leaves every normal as it is: the image is
// bit-identical to the material without a map, on an analytic sphere, a quad and a smooth
// icosphere (interpolated normals), with the path integrator (indirect light, 16 spp).
TEST(NormalMap, FlatMapRendersBitIdenticalToNoMap) {
    const std::string dir = temp_dir();
    write_constant_exr(dir + "/flat.exr", Vec3(0.5f, 0.5f, 1.f));
    auto scene = [&](const std::string& nm) {
        const std::string mat = R"({"model": "lambert", "reflectance": 0.6)" + nm + "}";
        return scene_in(dir, R"("camera": {"position": [0, -6, 2], "look_at": [0, 0, 0.5],
                                   "up": [0, 0, 1], "fov": 40, "width": 24, "height": 16},
            "shapes": [{"type": "sphere", "center": [-1.2, 0, 0.8], "radius": 0.8,
                        "material": )" +
                                 mat + R"(},
                       {"type": "icosphere", "center": [1.2, 0, 0.8], "radius": 0.8,
                        "subdivisions": 1, "material": )" +
                                 mat + R"(},
                       {"type": "quad", "vertices": [[-3, -3, 0], [3, -3, 0], [3, 3, 0],
                        [-3, 3, 0]], "material": )" +
                                 mat + R"(}],
            "lights": [{"type": "point", "position": [2, -3, 4], "power": 500},
                       {"type": "environment", "radiance": 0.2}])");
    };
    const fr::Image plain = render(scene(""), "path", 16);
    const fr::Image mapped =
        render(scene(R"(, "normal_map": {"texture": "flat.exr"})"), "path", 16);
    ASSERT_EQ(plain.pixels().size(), mapped.pixels().size());
    EXPECT_EQ(std::memcmp(plain.pixels().data(), mapped.pixels().data(),
                          plain.pixels().size() * sizeof(Rgb)),
              0);
    // The same map with strength 0 is no map either (and a tilted one, too).
    write_constant_exr(dir + "/tilted.exr", encode(Vec3(0.6f, 0.f, 0.8f)));
    const fr::Image zero =
        render(scene(R"(, "normal_map": {"texture": "tilted.exr", "strength": 0})"), "path", 16);
    EXPECT_EQ(std::memcmp(plain.pixels().data(), zero.pixels().data(),
                          plain.pixels().size() * sizeof(Rgb)),
              0);
    // A bump map of constant height is no bump either.
    const fr::Image flat_bump = render(
        scene(R"(, "bump": {"checker": {"colors": [0.3, 0.3]}, "distance": 2})"), "path", 16);
    EXPECT_EQ(std::memcmp(plain.pixels().data(), flat_bump.pixels().data(),
                          plain.pixels().size() * sizeof(Rgb)),
              0);
    // And the tilted map at full strength does change the picture (the test can fail).
    const fr::Image tilted =
        render(scene(R"(, "normal_map": {"texture": "tilted.exr"})"), "path", 16);
    EXPECT_NE(std::memcmp(plain.pixels().data(), tilted.pixels().data(),
                          plain.pixels().size() * sizeof(Rgb)),
              0);
}

// A Lambertian plane (rho = 0.5) under a directional light of irradiance E = 1, seen straight
// down, with a normal map that tilts every normal by theta = 30 degrees toward +u (texel
// (sin 30, 0, cos 30) encoded) or toward +v ((0, sin 30, cos 30)): L = rho E cos(angle between
// the tilted normal and the light) / pi. With the light straight above that is cos 30; with the
// light tilted by 40 degrees toward +u (or +v) it is cos 10 when the map tilts the normal the
// right way and cos 70 when an axis or the +Y convention is wrong. Also through strength 0.5:
// normalize(n + (n' - n) / 2) bisects n and n', a tilt of theta / 2 exactly. Shapes: a quad (u
// along p1 - p0, v along p3 - p0), a mesh with MikkTSpace tangents from its UVs, and a mesh
// whose given tangents turn the frame by 90 degrees (u along +y). Tolerance 2e-6 relative:
// float rounding of the texel, the frame and the cosine (no sampling: delta light, 1 spp).
TEST(NormalMap, TiltedMapGivesTheCosineOfTheTiltedNormal) {
    const std::string dir = temp_dir();
    const float th = float(30.0 * kPi / 180.0);
    write_constant_exr(dir + "/tilt_u.exr", encode(Vec3(std::sin(th), 0.f, std::cos(th))));
    write_constant_exr(dir + "/tilt_v.exr", encode(Vec3(0.f, std::sin(th), std::cos(th))));
    const std::string quad =
        R"({"type": "quad", "vertices": [[-3, -3, 0], [3, -3, 0], [3, 3, 0], [-3, 3, 0]], )";
    const std::string mesh_arrays =
        R"({"type": "mesh", "positions": [-3, -3, 0, 3, -3, 0, 3, 3, 0, -3, 3, 0],
            "indices": [0, 1, 2, 0, 2, 3], "uvs": [0, 0, 1, 0, 1, 1, 0, 1], )";
    // Given tangents along +y with sign +1: the map's +X is +y, its +Y is cross(z, y) = -x.
    const std::string turned = mesh_arrays + R"("tangents": [0, 1, 0, 1, 0, 1, 0, 1, 0, 1, 0,
                                                            1, 0, 1, 0, 1], )";
    struct Case {
        std::string shape, map;
        Vec3 map_dir;  // world direction the map tilts the normal toward
        float strength;
    };
    const Vec3 x(1.f, 0.f, 0.f), y(0.f, 1.f, 0.f);
    const std::vector<Case> cases = {
        {quad, "tilt_u.exr", x, 1.f},        {quad, "tilt_v.exr", y, 1.f},
        {mesh_arrays, "tilt_u.exr", x, 1.f}, {mesh_arrays, "tilt_v.exr", y, 1.f},
        {turned, "tilt_u.exr", y, 1.f},      {turned, "tilt_v.exr", -x, 1.f},
        {quad, "tilt_u.exr", x, 0.5f},
    };
    for (const Case& c : cases) {
        const float tilt = c.strength == 1.f ? th : 0.5f * th;
        const Vec3 n = std::cos(tilt) * Vec3(0.f, 0.f, 1.f) + std::sin(tilt) * c.map_dir;
        const float beta = float(40.0 * kPi / 180.0);
        for (const Vec3& to_light : {Vec3(0.f, 0.f, 1.f), std::cos(beta) * Vec3(0.f, 0.f, 1.f) +
                                                              std::sin(beta) * c.map_dir}) {
            const fr::Scene s =
                scene_in(dir, std::string(kTopCamera) + R"("shapes": [)" + c.shape +
                                  R"("material": {"model": "lambert", "reflectance": 0.5,
                                         "normal_map": {"texture": ")" +
                                  c.map + R"(", "strength": )" + std::to_string(c.strength) +
                                  "}}}], " + light_from(to_light));
            const fr::Image img = render(s, "direct", 1);
            const double want = 0.5 * double(glm::dot(n, to_light)) / kPi;
            for (const Rgb& px : img.pixels())
                EXPECT_NEAR(px.g, want, 2e-6 * want)
                    << c.shape << c.map << " strength " << c.strength << " light (" << to_light.x
                    << ", " << to_light.y << ", " << to_light.z << ")";
        }
    }
}

// --- bump maps ---------------------------------------------------------------------------------

// A bump map of a linear height ramp on the Lambertian quad [-3, 3]^2 (u = (x + 3) / 6,
// v = (y + 3) / 6): an 8-texel float image, bilinear, clamped, whose texel i holds i, is
// h(u) = 8 u - 1/2 between the first and last texel centres (the view covers u in
// [0.33, 0.67]); with distance d the displaced surface z = d h has slope d * 8 / 6 along x, so
// the normal tilts by atan(4 d / 3) toward -x. d = (3/4) tan 30 gives 30 degrees: under a
// directional light straight above L = rho E cos 30 / pi, and with the light tilted by 40
// degrees toward -x, cos 10 (toward +x: cos 70, which a sign error would give). The same along
// v with a 1 x 8 image whose rows rise upward. Tolerance 1e-5 relative: the forward difference
// of a linear function is exact up to float rounding of the texels' interpolation (~1e-7 over a
// step of 1/16).
TEST(BumpMap, LinearHeightRampGivesTheAnalyticTilt) {
    const std::string dir = temp_dir();
    std::vector<float> ramp;
    for (int i = 0; i < 8; ++i) ramp.push_back(float(i));
    fr::testing::write_test_image(dir + "/ramp_u.exr", 8, 1, 1, ramp, OIIO::TypeDesc::FLOAT);
    std::vector<float> ramp_v;  // row 0 is the top (highest v)
    for (int i = 0; i < 8; ++i) ramp_v.push_back(float(7 - i));
    fr::testing::write_test_image(dir + "/ramp_v.exr", 1, 8, 1, ramp_v, OIIO::TypeDesc::FLOAT);
    const double d = 0.75 * std::tan(30.0 * kPi / 180.0);
    const float th = float(30.0 * kPi / 180.0), beta = float(40.0 * kPi / 180.0);
    // Strength s (Blender's Bump Strength): normalize(s n' + (1 - s) z); 1 is the tilt itself.
    for (const auto& [file, axis, strength] :
         {std::tuple<std::string, Vec3, float>{"ramp_u.exr", Vec3(1, 0, 0), 1.f},
          std::tuple<std::string, Vec3, float>{"ramp_v.exr", Vec3(0, 1, 0), 1.f},
          std::tuple<std::string, Vec3, float>{"ramp_u.exr", Vec3(1, 0, 0), 0.25f}}) {
        const Vec3 tilted = std::cos(th) * Vec3(0.f, 0.f, 1.f) - std::sin(th) * axis;
        const Vec3 n = glm::normalize(strength * tilted + (1.f - strength) * Vec3(0.f, 0.f, 1.f));
        for (const Vec3& to_light :
             {Vec3(0.f, 0.f, 1.f), std::cos(beta) * Vec3(0.f, 0.f, 1.f) - std::sin(beta) * axis}) {
            const fr::Scene s = scene_in(
                dir, std::string(kTopCamera) +
                         R"("shapes": [{"type": "quad", "vertices": [[-3, -3, 0], [3, -3, 0],
                            [3, 3, 0], [-3, 3, 0]], "material": {"model": "lambert",
                            "reflectance": 0.5, "bump": {"texture": ")" +
                         file + R"(", "wrap": "clamp", "distance": )" + exact(d) +
                         R"(, "strength": )" + exact(strength) + "}}}], " + light_from(to_light));
            const fr::Image img = render(s, "direct", 1);
            const double want = 0.5 * double(glm::dot(n, to_light)) / kPi;
            for (const Rgb& px : img.pixels())
                EXPECT_NEAR(px.g, want, 1e-5 * want)
                    << file << " strength " << strength << " light (" << to_light.x << ", "
                    << to_light.y << ", " << to_light.z << ")";
        }
    }
}

// --- the valid-reflection bend
// --------------------------------------------------------------------

// valid_reflection_normal on random geometry: the result is unit, lies in ng's hemisphere, and
// reflects wo to at least min(0.9 dot(ng, wo), 0.01) above the surface (tolerance 1e-4: float
// round-off of the closed form, solved in double); a normal that already does so comes back
// unchanged, bit for bit. Without the bend, about a third of these normals reflect below the
// surface.
TEST(NormalMap, ValidReflectionNormalKeepsTheReflectionAboveTheSurface) {
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> u(-1.f, 1.f);
    auto random_unit = [&] {
        for (;;) {
            const Vec3 v(u(rng), u(rng), u(rng));
            const float l = glm::length(v);
            if (l > 0.1f && l <= 1.f) return v / l;
        }
    };
    int bent = 0;
    for (int i = 0; i < 20000; ++i) {
        const Vec3 ng(0.f, 0.f, 1.f);
        Vec3 wo = random_unit();
        if (wo.z <= 1e-3f) wo.z = -wo.z + 2e-3f;
        wo = glm::normalize(wo);
        Vec3 n = random_unit();
        if (n.z < 0.f) n.z = -n.z;
        const float t = std::min(0.9f * wo.z, 0.01f);
        const Vec3 r0 = 2.f * glm::dot(n, wo) * n - wo;
        const Vec3 got = fr::valid_reflection_normal(ng, wo, n);
        if (r0.z >= t) {
            EXPECT_EQ(got, n);
            continue;
        }
        ++bent;
        EXPECT_NEAR(glm::length(got), 1.f, 1e-5f);
        EXPECT_GT(got.z, 0.f);
        const Vec3 r = 2.f * glm::dot(got, wo) * got - wo;
        EXPECT_GE(r.z, t - 1e-4f) << "wo (" << wo.x << ", " << wo.y << ", " << wo.z << "), n ("
                                  << n.x << ", " << n.y << ", " << n.z << ")";
    }
    EXPECT_GT(bent, 1000);
}

// --- bad input
// ------------------------------------------------------------------------------------

TEST(NormalMap, BadInputNamesTheJsonPointer) {
    const std::string dir = temp_dir();
    write_constant_exr(dir + "/flat.exr", Vec3(0.5f, 0.5f, 1.f));
    const std::string head = std::string(kTopCamera) + R"("lights": [{"type": "directional",
        "irradiance": 1, "direction": [0, 0, -1]}], "shapes": [)";
    const std::string nm =
        R"("material": {"model": "lambert", "normal_map": {"texture": "flat.exr"}})";
    const std::string mesh = R"({"type": "mesh", "positions": [0, 0, 0, 1, 0, 0, 0, 1, 0],
                                 "indices": [0, 1, 2], )";
    // A normal map on a mesh without UVs.
    std::string e = error_of(dir, head + mesh + nm + "}]");
    EXPECT_NE(e.find("/shapes/0/uvs"), std::string::npos) << e;
    EXPECT_NE(e.find("normal map"), std::string::npos) << e;
    // Wrong tangent count (3 per position instead of 4).
    e = error_of(dir, head + mesh + R"("uvs": [0, 0, 1, 0, 0, 1],
                 "tangents": [1, 0, 0, 1, 0, 0, 1, 0, 0], )" +
                          nm + "}]");
    EXPECT_NE(e.find("/shapes/0/tangents"), std::string::npos) << e;
    // A zero bitangent sign, a zero tangent.
    e = error_of(dir, head + mesh + R"("uvs": [0, 0, 1, 0, 0, 1],
                 "tangents": [1, 0, 0, 1, 1, 0, 0, 0, 1, 0, 0, 1], )" +
                          nm + "}]");
    EXPECT_NE(e.find("/shapes/0/tangents/7"), std::string::npos) << e;
    e = error_of(dir, head + mesh + R"("uvs": [0, 0, 1, 0, 0, 1],
                 "tangents": [1, 0, 0, 1, 0, 0, 0, 1, 1, 0, 0, 1], )" +
                          nm + "}]");
    EXPECT_NE(e.find("/shapes/0/tangents/4"), std::string::npos) << e;
    // Negative strength, unknown key, missing image.
    const std::string quad =
        R"({"type": "quad", "vertices": [[-1, -1, 0], [1, -1, 0], [1, 1, 0], [-1, 1, 0]], )";
    e = error_of(dir, head + quad + R"("material": {"model": "lambert", "normal_map":
                 {"texture": "flat.exr", "strength": -1}}}])");
    EXPECT_NE(e.find("/shapes/0/material/normal_map/strength"), std::string::npos) << e;
    e = error_of(dir, head + quad + R"("material": {"model": "lambert", "normal_map":
                 {"texture": "flat.exr", "strenght": 1}}}])");
    EXPECT_NE(e.find("/shapes/0/material/normal_map"), std::string::npos) << e;
    EXPECT_NE(e.find("strength"), std::string::npos) << e;
    e = error_of(dir, head + quad + R"("material": {"model": "lambert", "bump":
                 {"texture": "flat.exr", "strength": -0.5}}}])");
    EXPECT_NE(e.find("/shapes/0/material/bump/strength"), std::string::npos) << e;
    e = error_of(dir, head + quad + R"("material": {"model": "lambert", "normal_map":
                 {"texture": "missing.exr"}}}])");
    EXPECT_NE(e.find("/shapes/0/material/normal_map/texture"), std::string::npos) << e;

    // Non-finite tangents through the description (JSON has no NaN).
    fr::SceneDescription desc = fr::parse_scene_description(
        R"({"format": "facet-scene", "version": 1, )" + head + quad + nm + "}]}", "nm.json", dir);
    fr::ShapeDesc m;
    m.kind = fr::ShapeKind::Mesh;
    m.material = desc.shapes[0].material;
    m.mesh = fr::MeshData::copy_of({0, 0, 0, 1, 0, 0, 0, 1, 0}, {0, 1, 2}, {}, {0, 0, 1, 0, 0, 1},
                                   {1, 0, 0, 1, 1, 0, NAN, 1, 1, 0, 0, 1});
    desc.shapes = {m};
    try {
        fr::build_scene(desc, "nm.json");
        ADD_FAILURE() << "no error";
    } catch (const fr::SceneError& err) {
        EXPECT_NE(std::string(err.what()).find("/shapes/0/tangents/6"), std::string::npos)
            << err.what();
    }
}

// The tangents key reads and writes back exactly.
TEST(Tangents, JsonRoundTrip) {
    const std::string text = std::string(R"({"format": "facet-scene", "version": 1, )") +
                             kTopCamera + R"("lights": [{"type": "directional",
        "irradiance": 1, "direction": [0, 0, -1]}], "shapes": [{"type": "mesh",
        "positions": [0, 0, 0, 1, 0, 0, 0, 1, 0], "indices": [0, 1, 2],
        "uvs": [0, 0, 1, 0, 0, 1], "tangents": [1, 0, 0, 1, 1, 0, 0, -1, 0.5, 0.5, 0, 1],
        "material": {"model": "lambert", "normal_map": {"texture": "n.png", "strength": 0.25}}}]})";
    const fr::SceneDescription a = fr::parse_scene_description(text, "a.json");
    const fr::SceneDescription b = fr::parse_scene_description(fr::write_scene_json(a), "b.json");
    EXPECT_TRUE(a == b);
    ASSERT_EQ(b.shapes[0].mesh.tangents.size(), 12u);
    EXPECT_EQ(b.shapes[0].mesh.tangents[7], -1.f);
    ASSERT_TRUE(b.shapes[0].material->normal_map.has_value());
    EXPECT_EQ(b.shapes[0].material->normal_map->strength, 0.25);
    EXPECT_EQ(b.shapes[0].material->normal_map->texture.file, "n.png");
}
