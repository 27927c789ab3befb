// Per-hit heap allocations (issue 33: a textured material is built at each hit in place, its
// combination children and walk closures from a per-thread pool). Its own binary: it replaces
// the global operator new with one that counts the calls made while counting is on.
//  - Scene::textured_material, the per-hit path, is called at many uv for textured models of
//    every kind that keeps state (principled with a subsurface walk, a mix of textured
//    children, subsurface, compensated composite and dielectric, principled hair): after one
//    warm-up call per thread (the pool's first use), no call may allocate.
//  - A whole render at 1 and at 8 samples per pixel (1 thread): the 7 extra samples of every
//    pixel (thousands of textured hits) may not add allocations beyond the render's own
//    per-pass bookkeeping, bounded by a small constant.
#include <gtest/gtest.h>

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <atomic>
#include <cstdlib>
#include <memory>
#include <new>
#include <random>
#include <string>
#include <vector>

#include "facet/render/render.h"
#include "facet/render/scene.h"
#include "facet/render/scene_description.h"
#include "facet/testsupport/render_test_util.h"
#include "oiio_test_image.h"

namespace {
std::atomic<bool> g_counting{false};
std::atomic<long> g_allocations{0};
}  // namespace

void* operator new(std::size_t n) {
    if (g_counting.load(std::memory_order_relaxed))
        g_allocations.fetch_add(1, std::memory_order_relaxed);
    if (void* p = std::malloc(n ? n : 1)) return p;
    throw std::bad_alloc();
}
void* operator new[](std::size_t n) {
    return operator new(n);
}
void* operator new(std::size_t n, std::align_val_t a) {
    if (g_counting.load(std::memory_order_relaxed))
        g_allocations.fetch_add(1, std::memory_order_relaxed);
    const std::size_t al = std::size_t(a);
    if (void* p = std::aligned_alloc(al, (std::max<std::size_t>(n, 1) + al - 1) / al * al))
        return p;
    throw std::bad_alloc();
}
void* operator new[](std::size_t n, std::align_val_t a) {
    return operator new(n, a);
}
void operator delete(void* p, std::align_val_t) noexcept {
    std::free(p);
}
void operator delete[](void* p, std::align_val_t) noexcept {
    std::free(p);
}
void operator delete(void* p, std::size_t, std::align_val_t) noexcept {
    std::free(p);
}
void operator delete[](void* p, std::size_t, std::align_val_t) noexcept {
    std::free(p);
}
void operator delete(void* p) noexcept {
    std::free(p);
}
void operator delete[](void* p) noexcept {
    std::free(p);
}
void operator delete(void* p, std::size_t) noexcept {
    std::free(p);
}
void operator delete[](void* p, std::size_t) noexcept {
    std::free(p);
}

namespace fr = facet::render;

namespace {

// Allocations made by f().
template <class F>
long allocations_in(F&& f) {
    g_allocations = 0;
    g_counting = true;
    f();
    g_counting = false;
    return g_allocations.load();
}

std::string temp_dir() {
    return fr::testing::test_temp_dir("facet_alloc");
}

// An 8 x 8 float image of c channels, texels uniform in [lo, 1] (seeded: reproducible).
std::string random_image(const std::string& name, int c, float lo, unsigned seed) {
    return fr::testing::random_test_image(temp_dir(), name, c, lo, seed);
}

std::string tex(const std::string& path, double scale = 1.0) {
    return R"({"texture": ")" + path + R"(", "filter": "linear", "scale": )" +
           std::to_string(scale) + "}";
}

// A sphere of material m (JSON object) under a constant environment, 16 x 16 pixels.
std::string sphere_body(const std::string& m) {
    return R"("camera": {"position": [0, 0, 4], "look_at": [0, 0, 0], "fov": 32, "width": 16,
                         "height": 16},
              "render": {"integrator": "path", "max_depth": 8},
              "materials": {"m": )" +
           m + R"(},
              "shapes": [{"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": "m"}],
              "lights": [{"type": "environment", "radiance": 0.5}])";
}

std::vector<std::string> stateful_materials() {
    const std::string c = tex(random_image("c", 3, 0.f, 1)), g = tex(random_image("g", 1, 0.f, 2));
    return {
        R"({"model": "principled", "base_color": )" + c + R"(, "roughness": )" + g +
            R"(, "subsurface": )" + g + R"(, "subsurface_radius": [1, 0.5, 0.25]})",
        R"({"model": "mix", "weight": )" + g +
            R"(, "materials": [{"model": "lambert", "reflectance": )" + c +
            R"(}, {"model": "ggx", "alpha": )" + g + "}]}",
        R"({"model": "subsurface", "color": )" + c + R"(, "scale": )" +
            tex(random_image("s", 1, 0.1f, 3), 0.5) + "}",
        R"({"model": "composite", "diffuse_reflectance": )" + c +
            R"(, "glossy_reflectance": 0.5, "alpha": )" + g + R"(, "energy_compensation": true})",
        R"({"model": "dielectric", "alpha": )" + tex(random_image("a", 1, 0.05f, 5), 0.5) +
            R"(, "energy_compensation": true})",
        R"({"model": "principled_hair", "roughness": )" + g + "}",
    };
    // Not listed: a textured Blinn exponent, whose Student-t rho table (microfacet.cpp,
    // MicrofacetDistribution::blinn) is computed and allocated at each hit.
}

// The scenes of stateful_materials(), built once for both tests (the compensated dielectric's
// tables take seconds to build).
const std::vector<std::shared_ptr<const fr::Scene>>& scenes() {
    static const std::vector<std::shared_ptr<const fr::Scene>> all = [] {
        std::vector<std::shared_ptr<const fr::Scene>> v;
        for (const std::string& m : stateful_materials())
            v.push_back(std::make_shared<const fr::Scene>(
                fr::testing::scene_in_dir(temp_dir(), sphere_body(m), "t.json")));
        return v;
    }();
    return all;
}

// The hook counts: an allocation made while counting is on is seen (so a per-hit allocation
// could not hide from the tests below).
TEST(PerHitAllocations, TheCounterSeesAnAllocation) {
    std::vector<int>* v = nullptr;
    EXPECT_EQ(allocations_in([&] { v = new std::vector<int>(3); }), 2);
    delete v;
}

TEST(PerHitAllocations, TexturedMaterialsAllocateNothingPerHit) {
    const std::vector<std::string> names = stateful_materials();
    for (std::size_t k = 0; k < names.size(); ++k) {
        const std::string& m = names[k];
        const fr::Scene& s = *scenes()[k];
        ASSERT_FALSE(s.textured_materials().empty()) << m;
        const std::size_t last = s.textured_materials().size() - 1;
        (void)s.textured_material(last, facet::Vec2(0.5f), {});  // the pool's first use
        std::mt19937 rng(3);
        std::uniform_real_distribution<float> u01(0.f, 1.f);
        float sink = 0.f;
        const long n = allocations_in([&] {
            for (int i = 0; i < 1000; ++i) {
                const facet::Material mat =
                    s.textured_material(last, facet::Vec2(u01(rng), u01(rng)), {});
                sink += float(mat.flags() != facet::BxDFFlags::None);
            }
        });
        EXPECT_EQ(n, 0) << "1000 per-hit builds of " << m;
        EXPECT_EQ(sink, 1000.f);
    }
}

// A render's allocations do not grow with its samples: 1 and 8 spp of each textured sphere
// (16 x 16 pixels, 1 thread) differ by at most kSlack allocations, where one allocation per
// textured hit would add at least 7 x 16 x 16 x (the sphere's ~0.6 share of the pixels).
TEST(PerHitAllocations, RenderAllocationsDoNotGrowWithSamples) {
    constexpr long kSlack = 64;  // per-pass bookkeeping (progress, tile jobs): a constant
    const std::vector<std::string> names = stateful_materials();
    for (std::size_t k = 0; k < names.size(); ++k) {
        const std::string& m = names[k];
        const fr::Scene& s = *scenes()[k];
        auto render = [&](int spp) {
            return allocations_in(
                [&] { fr::render(s, fr::testing::test_options("path", spp, 1, 1)); });
        };
        render(1);  // warm-up: thread pools and per-thread pools
        const long a1 = render(1), a8 = render(8);
        EXPECT_LE(a8 - a1, kSlack)
            << m << ": " << a1 << " allocations at 1 spp, " << a8 << " at 8 spp";
    }
}

}  // namespace
