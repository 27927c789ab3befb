// Interpolated shading normals never make a hit black (SurfaceHit::ns, ray_side_valid_normal):
// random triangles with random corner normals rendered one pixel at a time under a constant
// environment, and a coarse smooth-shaded sheet (an OBJ whose corner normals point to both
// sides of its faces, as a thin chair seat modelled as one sheet) seen at grazing angles.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include <unistd.h>

#include "facet/render/aov.h"
#include "facet/render/render.h"
#include "facet/render/scene.h"
#include "facet/render/scene_description.h"
#include "facet/testsupport/render_test_util.h"

namespace fr = facet::render;
using facet::Rgb;
using facet::Vec3;

namespace {

// The Lambertian reflectance of every test surface. Below 1 so that a pixel tells a hit from a
// miss: under an environment of radiance 1 a flat surface alone (no interreflection) returns
// at most rho per sample, a miss returns 1.
constexpr float kRho = 0.5f;

std::string temp_dir() {
    const auto d = std::filesystem::temp_directory_path() /
                   ("facet_shading_normals_" + std::to_string(::getpid()));
    std::filesystem::create_directories(d);
    return d.string();
}

// A number written so that it reads back exactly.
std::string exact(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.17g", v);
    return buf;
}

// One triangle (positions p, unit corner normals n) of a white-ish two-sided Lambert under a
// constant environment of radiance 1, seen by a one-pixel orthographic camera from direction
// wo (unit, toward the camera) at point `at`, its window 1e-5 wide: every sample hits within
// 1e-5 / |cos| of `at`.
fr::SceneDescription triangle_scene(const Vec3 p[3], const Vec3 n[3], const Vec3& at,
                                    const Vec3& wo) {
    fr::SceneDescription d;
    d.camera.type = "orthographic";
    d.camera.scale = 1e-5;
    d.camera.position = at + 3.f * wo;
    d.camera.look_at = at;
    // Any up that is not along the view: the axis least aligned with it.
    const Vec3 a = glm::abs(wo);
    d.camera.up = a.x <= a.y && a.x <= a.z ? Vec3(1.f, 0.f, 0.f)
                  : a.y <= a.z             ? Vec3(0.f, 1.f, 0.f)
                                           : Vec3(0.f, 0.f, 1.f);
    d.camera.width = d.camera.height = 1;
    fr::MaterialDesc white;
    white.model = "lambert";
    white.params.set("reflectance", double(kRho));
    d.materials.push_back({"white", white});
    fr::ShapeDesc s;
    s.kind = fr::ShapeKind::Mesh;
    s.material_ref = "white";
    std::vector<float> pos, nor;
    for (int i = 0; i < 3; ++i) {
        pos.insert(pos.end(), {p[i].x, p[i].y, p[i].z});
        nor.insert(nor.end(), {n[i].x, n[i].y, n[i].z});
    }
    s.mesh = fr::MeshData::copy_of(std::move(pos), {0, 1, 2}, std::move(nor));
    d.shapes.push_back(s);
    fr::LightDesc env;
    env.kind = fr::LightKind::Environment;
    env.radiance = Rgb(1.f);
    d.lights.push_back(env);
    d.render.max_depth = 4;
    return d;
}

Vec3 random_unit(std::mt19937& rng) {
    std::normal_distribution<float> g;
    for (;;) {
        const Vec3 v(g(rng), g(rng), g(rng));
        const float l = glm::length(v);
        if (l > 1e-3f) return v / l;
    }
}

}  // namespace

// Random triangles with random unit corner normals: independent ones (they disagree across the
// face), two opposite corners (the interpolation passes through zero inside the face) and three
// corners a, -a, -a seen at the point where (b0 - b1 - b2) a nearly vanishes (interpolated
// lengths within a few 1e-5 of zero, both signs, inside one pixel). Each is seen from random
// directions on both sides, a quarter of them within 3 degrees of grazing, with the path and
// the direct integrator (32 samples) and the albedo pass. Every pixel must be finite, above 0
// and at most rho (so the camera did hit the triangle: a miss sees the environment, 1). A
// Lambertian lobe under the constant environment returns rho times the part of its cosine
// lobe above the geometric surface, at least rho / 2 for any shading normal in ng's
// hemisphere; 0 would mean the hit shaded nothing. The test also counts the views in which the
// interpolated normal, turned to the viewer's side with ng, faces away from the viewer (a
// Lambertian frame there sees wo below its horizon and reflects nothing): without the bend
// each of those pixels is exactly 0, and they must be a good share of the cases.
TEST(ShadingNormals, RandomTrianglesNeverShadeZeroOrNaN) {
    std::mt19937 rng(35);
    std::uniform_real_distribution<float> u01(0.f, 1.f);
    const int triangles = std::max(12, int(300 * fr::testing::stress_scale()));
    int views = 0, facing_away = 0;
    for (int t = 0; t < triangles; ++t) {
        Vec3 p[3], ng;
        // Triangles of size ~1 whose altitudes all exceed 0.3, so that a point at barycentrics
        // >= 0.15 lies >= 0.045 inside: far beyond the 5e-3 footprint of the grazing views.
        for (;;) {
            for (Vec3& q : p) q = Vec3(u01(rng), u01(rng), u01(rng)) * 2.f - 1.f;
            const Vec3 c = glm::cross(p[1] - p[0], p[2] - p[0]);
            const float area2 = glm::length(c);
            bool fat = area2 > 0.f;
            for (int i = 0; i < 3 && fat; ++i)
                fat = area2 / glm::length(p[(i + 2) % 3] - p[(i + 1) % 3]) > 0.3f;
            if (!fat) continue;
            ng = c / area2;
            break;
        }
        Vec3 n[3];
        float b[3];
        const int kind = t % 3;
        if (kind == 0) {
            for (Vec3& c : n) c = random_unit(rng);
        } else {
            n[0] = random_unit(rng);
            n[1] = -n[0];
            n[2] = kind == 1 ? random_unit(rng) : -n[0];
        }
        if (kind == 2) {
            // b0 = b1 + b2 (+ 1e-5 at most): the interpolation's length is |b0 - b1 - b2|.
            const float e = (u01(rng) - 0.5f) * 2e-5f;
            b[0] = 0.5f + e;
            b[1] = 0.15f + 0.2f * u01(rng);
            b[2] = 1.f - b[0] - b[1];
        } else {
            for (;;) {
                b[0] = 0.15f + 0.7f * u01(rng);
                b[1] = 0.15f + 0.7f * u01(rng);
                b[2] = 1.f - b[0] - b[1];
                if (b[2] >= 0.15f) break;
            }
        }
        const Vec3 at = b[0] * p[0] + b[1] * p[1] + b[2] * p[2];
        const Vec3 interp = b[0] * n[0] + b[1] * n[1] + b[2] * n[2];
        for (int k = 0; k < 4; ++k) {
            // A random direction; for k == 3 one within 3 degrees of the surface.
            Vec3 wo = random_unit(rng);
            if (k == 3) {
                const Vec3 tangent = glm::normalize(wo - glm::dot(wo, ng) * ng);
                const float el = (0.05f + 2.95f * u01(rng)) * 3.14159265f / 180.f;
                wo = std::cos(el) * tangent + std::sin(el) * (u01(rng) < 0.5f ? ng : -ng);
            }
            const float side = glm::dot(wo, ng);
            if (std::fabs(side) < 8e-4f) continue;  // edge-on: the ray would miss the face
            ++views;
            // The old shading: interpolated normal into ng's hemisphere, both turned to wo.
            if (glm::length(interp) > 1e-6f) {
                Vec3 ns = glm::normalize(interp);
                if (glm::dot(ns, ng) < 0.f) ns = -ns;
                if (glm::dot(side > 0.f ? ns : -ns, wo) <= 0.f) ++facing_away;
            }
            const fr::Scene scene = fr::build_scene(triangle_scene(p, n, at, wo), "tri");
            for (const char* integrator : {"path", "direct"}) {
                const fr::Image img =
                    fr::render(scene, fr::testing::test_options(integrator, 32, 1 + k, 1));
                const Rgb px = img.at(0, 0);
                EXPECT_TRUE(std::isfinite(px.r) && px.r > 0.f && px.r <= kRho * (1.f + 1e-5f))
                    << integrator << ": triangle " << t << " (kind " << kind << ") view " << k
                    << ": pixel " << px.r << ", cos(wo, ng) " << side;
            }
            fr::AovOptions ao;
            ao.which = fr::kAovAlbedo;
            ao.spp = 4;
            ao.threads = 1;
            const float albedo = fr::render_aovs(scene, ao).albedo.at(0, 0).r;
            EXPECT_TRUE(std::isfinite(albedo) && albedo > 0.f)
                << "albedo: triangle " << t << " view " << k << ": " << albedo;
        }
    }
    // Measured with seed 35: 428 of 1200 views (36%) face away; the old shading left each of
    // those pixels at 0 with both integrators (and 432 albedo pixels).
    EXPECT_GT(facing_away, views / 8) << facing_away << " of " << views;
}

// A coarse smooth-shaded sheet from an OBJ file: a 4 x 4 grid of quads in z = 0 whose vertex
// normals tilt 0.4 along the grid and point up or down at random (as a chair seat modelled as
// one sheet), seen from three azimuths at 2 degrees above, 2 below and 1 above, with the path
// integrator (16 samples) under a constant environment: every pixel sees the sheet (the camera's
// view lies inside it) and none may be black or NaN.
TEST(ShadingNormals, GrazingViewsOfAnInconsistentSheetHaveNoBlackPixels) {
    const std::string dir = temp_dir();
    {
        std::ofstream obj(dir + "/sheet.obj");
        std::mt19937 rng(7);
        constexpr int kN = 4;  // quads per side; the sheet spans [-4, 4]^2
        for (int j = 0; j <= kN; ++j)
            for (int i = 0; i <= kN; ++i) obj << "v " << 2 * i - kN << " " << 2 * j - kN << " 0\n";
        for (int j = 0; j <= kN; ++j)
            for (int i = 0; i <= kN; ++i) {
                const Vec3 n =
                    glm::normalize(Vec3(0.4f * float(i % 2 ? 1 : -1), 0.4f * float(j % 2 ? 1 : -1),
                                        rng() % 2 ? 1.f : -1.f));
                obj << "vn " << exact(n.x) << " " << exact(n.y) << " " << exact(n.z) << "\n";
            }
        for (int j = 0; j < kN; ++j)
            for (int i = 0; i < kN; ++i) {
                const int a = j * (kN + 1) + i + 1, b = a + 1, c = a + kN + 2, e = a + kN + 1;
                obj << "f " << a << "//" << a << " " << b << "//" << b << " " << c << "//" << c
                    << " " << e << "//" << e << "\n";
            }
    }
    for (const float az : {0.f, 90.f, 200.f}) {
        for (const float el : {2.f, -2.f, 1.f}) {
            const float a = az * 3.14159265f / 180.f, e = el * 3.14159265f / 180.f;
            const Vec3 wo(std::cos(e) * std::cos(a), std::cos(e) * std::sin(a), std::sin(e));
            const Vec3 cam = 10.f * wo;  // above the window's lowest ray (0.045 from centre)
            // An orthographic window 0.15 x 0.09 wide: at 1 degree its rays meet the sheet
            // within 0.045 / sin(1 deg) = 2.6 of the origin, inside the sheet's [-4, 4]^2.
            const std::string body =
                R"("camera": {"type": "orthographic", "position": [)" + exact(cam.x) + ", " +
                exact(cam.y) + ", " + exact(cam.z) +
                R"(], "look_at": [0, 0, 0], "up": [0, 0, 1], "scale": 0.15, "width": 20,
                    "height": 12},
                   "render": {"integrator": "path", "spp": 16, "max_depth": 4},
                   "lights": [{"type": "environment", "radiance": 1}],
                   "shapes": [{"type": "mesh", "file": "sheet.obj",
                               "material": {"model": "lambert", "reflectance": )" +
                exact(kRho) + "}}]";
            const fr::Scene scene = fr::testing::scene_in_dir(dir, body, "sheet.json");
            const fr::Image img = fr::render(scene, fr::testing::test_options("path", 16, 3, 2));
            int bad = 0;
            for (const Rgb& px : img.pixels()) {
                // On the sheet (<= rho; a miss would see 1), never black, never NaN.
                const bool ok = std::isfinite(px.r) && px.r > 0.f && px.r <= kRho * (1.f + 1e-5f);
                if (!ok && bad < 3) ADD_FAILURE() << "pixel " << px.r;  // the first few
                bad += !ok;
            }
            EXPECT_EQ(bad, 0) << "azimuth " << az << ", elevation " << el;
        }
    }
}
