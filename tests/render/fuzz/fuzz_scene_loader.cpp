// libFuzzer entry point for the scene loader: any input must either load or throw SceneError.
// Any other exception, crash, leak or sanitizer report is a bug. Limits keep each input cheap
// and file access is off (a fuzzed "file" must not read the disk).
#include <cstddef>
#include <cstdint>
#include <string>

#include "facet/render/scene.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace facet::render;
    std::string text(reinterpret_cast<const char*>(data), size);
    SceneLimits limits;
    limits.max_triangles = 200000;
    limits.max_pixels = 1 << 20;
    limits.allow_files = false;
    try {
        Scene scene = load_scene_from_string(text, "fuzz.json", "/nonexistent", limits);
        // Exercise the built scene a little: a primary ray, its hit, a light sample.
        const Camera& cam = scene.camera();
        Ray ray = cam.generate_ray({0.5f * float(cam.width), 0.5f * float(cam.height)});
        SurfaceHit hit;
        if (scene.intersect(ray, hit)) {
            for (const Light& light : scene.lights()) {
                auto ls = light.sample_li({hit.p, hit.ns}, {0.25f, 0.75f});
                if (ls) (void)scene.occluded(hit, *ls);
            }
        }
        (void)scene.features().describe();
    } catch (const SceneError&) {
        // The documented failure mode.
    }
    return 0;
}
