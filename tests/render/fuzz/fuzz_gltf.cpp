// libFuzzer entry point for the glTF import (core/render/src/io/gltf_import.cpp) from bytes in
// memory (.gltf JSON or .glb; external files refused): any input must import or throw
// std::runtime_error naming the file. tinygltf itself is Debian's uninstrumented shared
// library, so coverage guides through Facet's checks of what it returns.
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string_view>

#include "facet/render/gltf.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    try {
        facet::render::GltfImport g = facet::render::parse_gltf(
            std::string_view(reinterpret_cast<const char*>(data), size), "fuzz.gltf");
        for (const facet::render::GltfPart& p : g.parts) {
            (void)facet::render::validate_mesh(p.mesh);
        }
    } catch (const std::runtime_error&) {
        // The documented failure mode.
    }
    return 0;
}
