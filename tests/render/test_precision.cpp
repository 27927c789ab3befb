// Coordinates far from the origin (precision.h, scene_precision.h): the error boxes of hit
// points and light samples contain the exact surface, rays spawned off them start strictly on
// their side and never re-hit it, a scene whose features float resolves renders the same at any
// distance from the origin and any scale, a scene whose details float merges gets one warning,
// and a shape float cannot represent is an error naming it.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "facet/frame.h"
#include "facet/render/precision.h"
#include "facet/render/render.h"
#include "facet/render/scene.h"
#include "facet/render/scene_description.h"
#include "facet/sampling.h"
#include "facet/testsupport/render_test_util.h"

namespace fr = facet::render;
using facet::Rgb;
using facet::Vec2;
using facet::Vec3;

namespace {

const std::string kScenes = FACET_SCENES_DIR;

struct LV3 {
    long double x, y, z;
    explicit LV3(const Vec3& v) : x(v.x), y(v.y), z(v.z) {}
    LV3(long double a, long double b, long double c) : x(a), y(b), z(c) {}
    LV3 operator-(const LV3& o) const { return {x - o.x, y - o.y, z - o.z}; }
    long double dot(const LV3& o) const { return x * o.x + y * o.y + z * o.z; }
    LV3 cross(const LV3& o) const {
        return {y * o.z - z * o.y, z * o.x - x * o.z, x * o.y - y * o.x};
    }
    long double length() const { return std::sqrt(dot(*this)); }
};

// Signed distance of p from the plane through v0 with normal n (any length), in long double.
long double plane_distance(const LV3& p, const LV3& v0, const LV3& n) {
    return (p - v0).dot(n) / n.length();
}

// Whether the box p +- err meets the plane through v0 with normal n: |d| <= dot(|n|, err) / |n|.
bool box_meets_plane(const Vec3& p, const Vec3& err, const LV3& v0, const LV3& n) {
    const long double reach =
        (std::fabs(n.x) * err.x + std::fabs(n.y) * err.y + std::fabs(n.z) * err.z) / n.length();
    return std::fabs(plane_distance(LV3(p), v0, n)) <= reach;
}

// Whether the box p +- err contains a point of the sphere (centre c, radius r): the box's nearest
// point to c is inside the sphere and its farthest corner outside (the box is connected).
bool box_meets_sphere(const Vec3& p, const Vec3& err, const Vec3& c, double r) {
    long double near2 = 0.0L, far2 = 0.0L;
    for (int i = 0; i < 3; ++i) {
        const long double lo = (long double)(p[i]) - err[i], hi = (long double)(p[i]) + err[i];
        const long double ci = c[i];
        const long double dn = ci < lo ? lo - ci : (ci > hi ? ci - hi : 0.0L);
        const long double df = std::max(std::fabs(ci - lo), std::fabs(hi - ci));
        near2 += dn * dn;
        far2 += df * df;
    }
    const long double r2 = (long double)(r) * (long double)(r);
    return near2 <= r2 && r2 <= far2;
}

fr::SceneDescription empty_scene(const Vec3& camera_at) {
    fr::SceneDescription d;
    d.camera.position = camera_at + Vec3(0.f, 0.f, 10.f + 1e-3f * glm::length(camera_at));
    d.camera.look_at = camera_at;
    d.camera.width = 8;
    d.camera.height = 8;
    d.materials.push_back({"white", {"lambert", {}, {}}});
    fr::LightDesc l;
    l.kind = fr::LightKind::Directional;
    l.direction = Vec3(0.f, -1.f, 0.f);
    l.irradiance = Rgb(1.f);
    d.lights.push_back(l);
    return d;
}

Vec3 random_unit(std::mt19937& rng) {
    std::uniform_real_distribution<float> u(0.f, 1.f);
    return facet::sample_uniform_sphere({u(rng), u(rng)});
}

// Magnitudes of the coordinates the bound tests place shapes at.
const double kMagnitudes[] = {0.0, 1.0, 1e3, 1e5, 1e7, 1e8, 1e10};

// A ray spawned from `h` into the cosine-weighted hemisphere about `n` (direction from `u`)
// hits the shape it left.
bool spawned_ray_rehits(const fr::Scene& scene, const fr::SurfaceHit& h, const Vec3& n,
                        const Vec2& u) {
    const Vec3 dir = facet::Frame::from_z(n).from_local(facet::sample_cosine_hemisphere(u));
    fr::SurfaceHit h2;
    return scene.intersect(fr::Scene::spawn_ray(h, dir), h2) && h2.shape == h.shape;
}

}  // namespace

// For random triangles (one mesh shape each) at coordinates up to 1e10 and random rays aimed
// at them: the hit's error box meets the triangle's exact plane (checked in long double), the
// origins offset_ray_origin gives on either side lie strictly on that side, and no spawned ray
// re-hits its triangle. Exact checks: the bounds are conservative, so no tolerance.
TEST(Precision, TriangleHitBoundsContainTheSurface) {
    std::mt19937 rng(17);
    std::uniform_real_distribution<float> u(0.f, 1.f);
    int checked = 0;
    for (double mag : kMagnitudes) {
        SCOPED_TRACE(mag);
        const Vec3 centre = float(mag) * random_unit(rng);
        // Triangles of 1e-3 .. 1 times max(1, 1e-3 |centre|): from tiny to large against the
        // float spacing there, never below the 4-spacing limit.
        const float size = std::max(1.f, 1e-3f * float(mag));
        fr::SceneDescription d = empty_scene(centre);
        std::vector<std::array<Vec3, 3>> tris;
        for (int t = 0; t < 20; ++t) {
            const float s = size * std::pow(10.f, -3.f * u(rng));
            const Vec3 c = centre + 4.f * size * Vec3(float(t), 0.f, 0.f);
            std::array<Vec3, 3> v = {c + s * random_unit(rng), c + s * random_unit(rng),
                                     c + s * random_unit(rng)};
            tris.push_back(v);
            fr::ShapeDesc sh;
            sh.kind = fr::ShapeKind::Mesh;
            sh.material_ref = "white";
            std::vector<float> pos;
            for (const Vec3& p : v) pos.insert(pos.end(), {p.x, p.y, p.z});
            sh.mesh = fr::MeshData::copy_of(pos, {0, 1, 2});
            d.shapes.push_back(sh);
        }
        const fr::Scene scene = fr::build_scene(d, "tris");
        for (std::size_t t = 0; t < tris.size(); ++t) {
            const LV3 v0(tris[t][0]), n = (LV3(tris[t][1]) - v0).cross(LV3(tris[t][2]) - v0);
            if (!(n.length() > 0.0L)) continue;
            for (int i = 0; i < 200; ++i) {
                // A point inside the triangle (barycentrics away from the edges) and a ray to it
                // from a random direction.
                float b1 = 0.05f + 0.9f * u(rng), b2 = 0.05f + 0.9f * u(rng);
                if (b1 + b2 > 0.95f) {
                    b1 = 1.f - b1;
                    b2 = 1.f - b2;
                }
                const Vec3 target =
                    tris[t][0] + b1 * (tris[t][1] - tris[t][0]) + b2 * (tris[t][2] - tris[t][0]);
                const Vec3 from = target + 3.f * size * random_unit(rng);
                fr::Ray ray{from, glm::normalize(target - from), facet::kInfinity};
                fr::SurfaceHit h;
                if (!scene.intersect(ray, h) || h.shape != t) continue;
                ++checked;
                ASSERT_TRUE(box_meets_plane(h.p, h.p_err, v0, n))
                    << "triangle " << t << " distance " << double(plane_distance(LV3(h.p), v0, n));
                for (float side : {1.f, -1.f}) {
                    const Vec3 o = fr::offset_ray_origin(h.p, h.p_err, h.ng, side * h.ng);
                    const long double dist =
                        plane_distance(LV3(o), v0, n) * (LV3(h.ng).dot(n) > 0.0L ? 1.0L : -1.0L);
                    ASSERT_GT(side * dist, 0.0L) << "offset origin on the wrong side";
                    ASSERT_FALSE(spawned_ray_rehits(scene, h, side * h.ng, {u(rng), u(rng)}))
                        << "the spawned ray re-hit its triangle";
                }
            }
        }
    }
    EXPECT_GT(checked, 15000);
}

// The same for exact spheres, discs and infinite planes (solved in double, then rounded): the
// error box contains the nearest point of the exact surface (sphere: the radial projection;
// disc and plane: the box meets the plane), and spawned rays leave the surface.
TEST(Precision, AnalyticHitBoundsContainTheSurface) {
    std::mt19937 rng(23);
    std::uniform_real_distribution<float> u(0.f, 1.f);
    int checked = 0;
    for (double mag : kMagnitudes) {
        SCOPED_TRACE(mag);
        const Vec3 centre = float(mag) * random_unit(rng);
        const float r = std::max(1.f, 1e-3f * float(mag));
        fr::SceneDescription d = empty_scene(centre);
        fr::ShapeDesc sphere;
        sphere.kind = fr::ShapeKind::Sphere;
        sphere.material_ref = "white";
        sphere.center = centre;
        sphere.radius = r;
        d.shapes.push_back(sphere);
        fr::ShapeDesc disc = sphere;
        disc.kind = fr::ShapeKind::Disc;
        disc.center = centre + Vec3(4.f * r, 0.f, 0.f);
        disc.normal = random_unit(rng);
        d.shapes.push_back(disc);
        fr::ShapeDesc plane;
        plane.kind = fr::ShapeKind::Plane;
        plane.material_ref = "white";
        plane.point = centre - Vec3(0.f, 4.f * r, 0.f);
        plane.normal = glm::normalize(Vec3(0.1f, 1.f, 0.2f));
        d.shapes.push_back(plane);
        const fr::Scene scene = fr::build_scene(d, "analytic");
        const Vec3 disc_n = glm::normalize(disc.normal);
        const Vec3 plane_n = plane.normal;  // unit in float; the plane uses it in double
        for (int i = 0; i < 3000; ++i) {
            const std::uint32_t shape = std::uint32_t(i % 3);
            Vec3 target;
            if (shape == 0) {
                target = centre + 0.9f * r * random_unit(rng);
            } else if (shape == 1) {
                const facet::Frame f = facet::Frame::from_z(disc_n);
                const Vec2 q = facet::sample_uniform_disk_concentric({u(rng), u(rng)});
                target = disc.center + 0.9f * r * (q.x * f.x + q.y * f.y);
            } else {
                target = plane.point + 3.f * r * Vec3(u(rng) - 0.5f, 0.f, u(rng) - 0.5f);
            }
            Vec3 from = target + 3.f * r * random_unit(rng);
            if (shape == 2 && glm::dot(from - plane.point, plane_n) < 0.f)
                from = target + (target - from);
            fr::SurfaceHit h;
            if (!scene.intersect({from, glm::normalize(target - from), facet::kInfinity}, h) ||
                h.shape != shape)
                continue;
            ++checked;
            if (shape == 0) {
                ASSERT_TRUE(box_meets_sphere(h.p, h.p_err, centre, r));
            } else {
                const Vec3 n = shape == 1 ? disc_n : plane_n;
                const Vec3 p0 = shape == 1 ? disc.center : plane.point;
                ASSERT_TRUE(box_meets_plane(h.p, h.p_err, LV3(p0), LV3(n))) << shape;
            }
            ASSERT_FALSE(spawned_ray_rehits(scene, h, h.ng, {u(rng), u(rng)}))
                << "the spawned ray re-hit its surface " << shape;
        }
    }
    EXPECT_GT(checked, 12000);
}

// Light samples far out: the error box of a point sampled on a quad light (a parallelogram),
// a triangle light, a disc light and a sphere light meets the traced surface, and the shadow
// ray from a point below ends before the light's own surface (it is not blocked by it).
TEST(Precision, LightSampleBoundsAndShadowRays) {
    std::mt19937 rng(29);
    std::uniform_real_distribution<float> u(0.f, 1.f);
    for (double mag : {1.0, 1e4, 1e7, 1e9}) {
        SCOPED_TRACE(mag);
        const Vec3 c = float(mag) * glm::normalize(Vec3(1.f, 2.f, 3.f));
        const float s = std::max(1.f, 1e-3f * float(mag));
        fr::SceneDescription d = empty_scene(c);
        d.lights.clear();
        fr::ShapeDesc quad;
        quad.kind = fr::ShapeKind::Quad;
        quad.emission = Rgb(1.f);
        const Vec3 a = s * Vec3(1.f, 0.f, 0.3f), b = s * Vec3(0.2f, 0.f, 1.f);
        const Vec3 q0 = c + s * Vec3(0.f, 2.f, 0.f);
        quad.vertices = {q0, q0 + a, q0 + a + b, q0 + b};  // facing down
        d.shapes.push_back(quad);
        fr::ShapeDesc disc;
        disc.kind = fr::ShapeKind::Disc;
        disc.emission = Rgb(1.f);
        disc.center = c + s * Vec3(3.f, 2.f, 0.f);
        disc.normal = glm::normalize(Vec3(0.1f, -1.f, 0.2f));
        disc.radius = s;
        d.shapes.push_back(disc);
        fr::ShapeDesc sphere = disc;
        sphere.kind = fr::ShapeKind::Sphere;
        sphere.center = c + s * Vec3(-3.f, 2.f, 0.f);
        d.shapes.push_back(sphere);
        const fr::Scene scene = fr::build_scene(d, "lights");
        ASSERT_EQ(scene.lights().size(), 3u);
        const fr::LightSampleContext ctx{c + s * Vec3(0.5f, 0.f, 0.5f), Vec3(0.f, 1.f, 0.f)};
        fr::SurfaceHit at;
        at.p = ctx.p;
        at.p_err = fr::rounding_error(ctx.p);
        at.ng = ctx.n;
        int samples = 0;
        for (std::size_t li = 0; li < 3; ++li) {
            for (int i = 0; i < 500; ++i) {
                const auto ls = scene.lights()[li].sample_li(ctx, {u(rng), u(rng)});
                if (!ls) continue;
                ++samples;
                if (li == 0) {
                    const LV3 n =
                        (LV3(quad.vertices[1]) - LV3(q0)).cross(LV3(quad.vertices[2]) - LV3(q0));
                    ASSERT_TRUE(box_meets_plane(ls->p_light, ls->p_light_err, LV3(q0), n));
                } else if (li == 1) {
                    ASSERT_TRUE(box_meets_plane(ls->p_light, ls->p_light_err, LV3(disc.center),
                                                LV3(disc.normal)));
                } else {
                    ASSERT_TRUE(box_meets_sphere(ls->p_light, ls->p_light_err, sphere.center, s));
                }
                ASSERT_FALSE(scene.occluded(at, *ls)) << "light " << li << " shadows itself";
            }
        }
        EXPECT_GT(samples, 1000);
    }
}

namespace {

// scenes/cornell_box.json at 64 x 64 with its light 20 units below the ceiling (the shipped
// light is 0.1 below it), every coordinate of shapes and camera mapped x -> x * scale + shift
// in double and rounded to float.
fr::SceneDescription gap_box(double shift, double scale, bool gap20 = true) {
    fr::SceneDescription d = fr::read_scene_description(kScenes + "/cornell_box.json");
    d.camera.width = 64;
    d.camera.height = 64;
    auto map = [&](Vec3& v) { v = Vec3(glm::dvec3(v) * scale + glm::dvec3(shift)); };
    map(d.camera.position);
    map(d.camera.look_at);
    for (fr::ShapeDesc& s : d.shapes) {
        EXPECT_EQ(s.kind, fr::ShapeKind::Quad);
        for (Vec3& v : s.vertices) {
            if (gap20 && s.name == "light") v.y = 528.8f;
            map(v);
        }
    }
    return d;
}

// The same float geometry moved back by `shift` (exact: a float near the shift minus the shift
// is a multiple of its spacing below 2^24 spacings), so that it differs from the shifted box
// only in where it lies.
fr::SceneDescription shifted_back(fr::SceneDescription d, double shift) {
    auto back = [&](Vec3& v) { v = Vec3(glm::dvec3(v) - glm::dvec3(shift)); };
    back(d.camera.position);
    back(d.camera.look_at);
    for (fr::ShapeDesc& s : d.shapes)
        for (Vec3& v : s.vertices) back(v);
    return d;
}

double image_mean(const fr::Image& img) {
    double sum = 0.0;
    for (const Rgb& p : img.pixels()) sum += double(p.r) + double(p.g) + double(p.b);
    return sum / double(3 * img.pixels().size());
}

// 64 spp; 16 in the Debug + ASan tree (FACET_STRESS_SCALE 0.1), where the noise bound below
// doubles and still resolves 1%.
fr::Image render_box(const fr::SceneDescription& d, std::uint64_t seed) {
    const int spp = std::max(16, int(64 * fr::testing::stress_scale()));
    return fr::render(fr::build_scene(d, "box"), fr::testing::test_options("path", spp, seed));
}

}  // namespace

// The box with the 20-unit gap shifted by 1e3 .. 1e8 renders within noise and quantisation of
// the same float geometry at the origin; scaled by 1e-8 .. 1e9 within noise of the unscaled box
// (a scale rounds each coordinate by half a float spacing, relative 3e-8).
// Bound: noise, 4 sigma of the difference of two image means (sigma^2 = 2 Var(mean), Var(mean)
// from two seeds of the reference; ~0.4% of the mean), plus quantisation: with float spacing h
// at the shift every hit point and light sample is rounded by up to h/2 per axis, which changes
// the distances and angles of the light transport by up to (h/2) / 275 relative (275: the box's
// half-width); 1.5% at 1e8 (h = 8), 0.09% at 1e7, 1e-5 at 1e3. Measured at 1e8: -0.6% (wall
// points within h/2 under the light's plane round onto it and lose their light); below 1e8
// within the noise. The geometry itself is quantised too (at 1e8 the light grows from 130 x 105
// to 128 x 112 units, +5% power): the shifted render is compared with that geometry moved back,
// not with the authored one. Before the error-bound offsets (old offset 1e-5 |p|, 300 units at
// 3e7) the box read -17% at 3e7 and -15% at 1e8.
TEST(Precision, GapBoxRendersTheSameShiftedAndScaled) {
    const fr::SceneDescription ref_desc = gap_box(0.0, 1.0);
    const fr::Image ref = render_box(ref_desc, 5), ref2 = render_box(ref_desc, 6);
    double var = 0.0;
    for (std::size_t i = 0; i < ref.pixels().size(); ++i) {
        for (int c = 0; c < 3; ++c) {
            const double e = double(ref.pixels()[i][c]) - double(ref2.pixels()[i][c]);
            var += 0.5 * e * e;  // per-pixel variance of one render
        }
    }
    const double n = double(3 * ref.pixels().size());
    const double sigma_mean = std::sqrt(var / n / n);
    const double bound = 4.0 * std::sqrt(2.0) * sigma_mean;
    const double ref_mean = image_mean(ref);
    EXPECT_LT(bound / ref_mean, 0.01);  // the test can see a 1% error
    for (double shift : {1e3, 1e5, 1e6, 1e7, 3e7, 1e8}) {
        SCOPED_TRACE(shift);
        const fr::SceneDescription far = gap_box(shift, 1.0);
        const double m = image_mean(render_box(far, 5));
        const double m0 = image_mean(render_box(shifted_back(far, shift), 5));
        const double quantisation = 0.5 * fr::float_spacing(shift) / 275.0 * m0;
        EXPECT_NEAR(m, m0, bound + quantisation) << "shifted " << m << ", at the origin " << m0;
    }
    for (double scale : {1e-8, 1e-4, 1e3, 1e6, 1e9}) {
        SCOPED_TRACE(scale);
        const double m = image_mean(render_box(gap_box(0.0, scale), 5));
        EXPECT_NEAR(m, ref_mean, bound);
    }
}

// The shipped box (light 0.1 under the ceiling) shifted by 3e6, where the float spacing is 0.25:
// one warning that says so; unshifted, none.
TEST(Precision, CoarseSpacingWarnsOnce) {
    const fr::Scene near = fr::build_scene(gap_box(0.0, 1.0, false), "box");
    EXPECT_TRUE(near.warnings().empty());
    fr::BuildReport report;
    const fr::Scene far = fr::build_scene(gap_box(3e6, 1.0, false), "box", {}, &report);
    ASSERT_EQ(far.warnings().size(), 1u);
    EXPECT_EQ(report.warnings,
              std::vector<std::string>(far.warnings().begin(), far.warnings().end()));
    const std::string& w = far.warnings()[0];
    EXPECT_NE(w.find("float spacing is 0.25"), std::string::npos) << w;
    EXPECT_NE(w.find("details smaller than 0.25 units may merge"), std::string::npos) << w;
}

// A shape smaller than 4 float spacings where it lies is an error naming it: a sphere of radius
// 1 at 1e8 (spacing 8), a quad with a 10-unit edge there; the same shapes near the origin load.
TEST(Precision, UnrepresentableShapeIsAnErrorNamingIt) {
    auto with = [](const Vec3& at, fr::ShapeKind kind) {
        fr::SceneDescription d = empty_scene(at);
        fr::ShapeDesc s;
        s.kind = kind;
        s.name = "speck";
        s.material_ref = "white";
        s.center = at;
        s.radius = 1.0;
        s.vertices = {at, at + Vec3(10.f, 0.f, 0.f), at + Vec3(10.f, 0.f, 1e3f),
                      at + Vec3(0.f, 0.f, 1e3f)};
        fr::ShapeDesc big;
        big.kind = fr::ShapeKind::Sphere;
        big.material_ref = "white";
        big.center = at - Vec3(0.f, 1e4f, 0.f);
        big.radius = 100.0;
        d.shapes = {big, s};
        return d;
    };
    for (fr::ShapeKind kind : {fr::ShapeKind::Sphere, fr::ShapeKind::Quad}) {
        EXPECT_NO_THROW(fr::build_scene(with(Vec3(0.f), kind), "near"));
        try {
            fr::build_scene(with(Vec3(1e8f, 0.f, 0.f), kind), "far");
            ADD_FAILURE() << "no error";
        } catch (const fr::SceneError& e) {
            const std::string m = e.what();
            EXPECT_EQ(m.rfind("far: /shapes/1 ('speck'): the shape cannot be represented", 0), 0u)
                << m;
            EXPECT_NE(m.find(kind == fr::ShapeKind::Sphere ? "the radius is 1" : "an edge is 8"),
                      std::string::npos)
                << m;
        }
    }
}
