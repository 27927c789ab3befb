// build_scene's parts on a 1M-triangle mesh given as caller-owned arrays (what the Python
// module passes: spans, no copy): the whole build_scene() against its BVH alone (the same
// triangles, flags and build quality in bare Embree calls, as embree_scene.cpp builds them).
// The difference is the description's cost before (and around) the BVH build; issue 9's
// target is <= 0.1 s. Medians of --reps runs (default 5). Prints a table.
#include <embree3/rtcore.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "facet/render/scene_description.h"

using namespace facet;
using namespace facet::render;

namespace {

double now_s() {
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch())
        .count();
}

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
}

// n x n vertices over [0, 1]^2: 2 (n-1)^2 triangles.
void grid(int n, std::vector<float>& p, std::vector<std::uint32_t>& idx) {
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) {
            p.push_back(float(x) / float(n - 1));
            p.push_back(float(y) / float(n - 1));
            p.push_back(0.f);
        }
    for (int y = 0; y + 1 < n; ++y)
        for (int x = 0; x + 1 < n; ++x) {
            const std::uint32_t k = std::uint32_t(y * n + x);
            const std::uint32_t q[4] = {k, k + 1, k + std::uint32_t(n) + 1, k + std::uint32_t(n)};
            idx.insert(idx.end(), {q[0], q[1], q[2], q[0], q[2], q[3]});
        }
}

SceneDescription description(const std::vector<float>& p, const std::vector<std::uint32_t>& idx) {
    SceneDescription d;
    d.camera.position = {0.5f, 0.5f, 2.f};
    d.camera.look_at = {0.5f, 0.5f, 0.f};
    d.camera.width = d.camera.height = 64;
    MaterialDesc white;
    white.model = "lambert";
    d.materials.emplace_back("white", white);
    ShapeDesc mesh;
    mesh.kind = ShapeKind::Mesh;
    mesh.material_ref = "white";
    mesh.mesh.positions = p;  // spans over the caller's arrays
    mesh.mesh.indices = idx;
    d.shapes.push_back(mesh);
    LightDesc light;
    light.position = {0.5f, 0.5f, 1.f};
    light.power = Rgb(10.f);
    d.lights.push_back(light);
    return d;
}

// The BVH alone, as embree_scene.cpp builds it.
void embree_only(const std::vector<float>& p, const std::vector<std::uint32_t>& idx) {
    RTCDevice device = rtcNewDevice(nullptr);
    RTCScene scene = rtcNewScene(device);
    rtcSetSceneFlags(scene, RTC_SCENE_FLAG_ROBUST);
    rtcSetSceneBuildQuality(scene, RTC_BUILD_QUALITY_HIGH);
    RTCGeometry g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(
        g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), p.size() / 3));
    auto* t = static_cast<unsigned*>(rtcSetNewGeometryBuffer(
        g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), idx.size() / 3));
    std::memcpy(v, p.data(), p.size() * sizeof(float));
    std::memcpy(t, idx.data(), idx.size() * sizeof(unsigned));
    rtcCommitGeometry(g);
    rtcAttachGeometry(scene, g);
    rtcReleaseGeometry(g);
    rtcCommitScene(scene);
    rtcReleaseScene(scene);
    rtcReleaseDevice(device);
}

}  // namespace

int main(int argc, char** argv) {
    int reps = 5;
    for (int i = 1; i + 1 < argc; ++i)
        if (std::string(argv[i]) == "--reps") reps = std::max(1, std::atoi(argv[i + 1]));
    std::vector<float> p;
    std::vector<std::uint32_t> idx;
    grid(709, p, idx);
    const SceneDescription d = description(p, idx);
    std::vector<double> total, bvh;
    for (int r = 0; r < reps; ++r) {
        // Alternating, so that both see the same machine state.
        double t0 = now_s();
        {
            Scene s = build_scene(d, "bench");
            total.push_back(now_s() - t0);
        }
        t0 = now_s();
        embree_only(p, idx);
        bvh.push_back(now_s() - t0);
    }
    const double mt = median(total), mb = median(bvh);
    std::printf("build_scene of %zu triangles from caller arrays, medians of %d runs\n",
                idx.size() / 3, reps);
    std::printf("  %-46s %9.1f ms   (min %.1f)\n", "build_scene (total)", mt * 1e3,
                *std::min_element(total.begin(), total.end()) * 1e3);
    std::printf("  %-46s %9.1f ms   (min %.1f)\n", "BVH alone (bare Embree, same flags/quality)",
                mb * 1e3, *std::min_element(bvh.begin(), bvh.end()) * 1e3);
    std::printf("  %-46s %9.1f ms   (target <= 100 ms)\n", "difference: before/around the BVH",
                (mt - mb) * 1e3);
    return 0;
}
