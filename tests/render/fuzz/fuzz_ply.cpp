// libFuzzer entry point for the PLY reader (mesh files are off in the scene fuzzer, so the
// binary parser gets its own target): any input must parse or throw std::runtime_error.
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string_view>

#include "facet/render/mesh.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    try {
        facet::render::TriangleMesh m =
            facet::render::parse_ply(std::string_view(reinterpret_cast<const char*>(data), size));
        (void)facet::render::validate_mesh(m);
    } catch (const std::runtime_error&) {
        // The documented failure mode.
    }
    return 0;
}
