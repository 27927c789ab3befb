// Private to facet_render: the limits of the scene format and the wording of value errors,
// shared by the JSON reader (which checks what JSON can get wrong: types, keys, integer ranges)
// and build_scene (which checks every value, whoever filled the description), so that both
// report a bad value with the same message.
#pragma once

#include <cstdint>
#include <filesystem>
#include <sstream>
#include <string>

namespace facet::render::detail {

// Limits that keep a hostile or mistyped file from exhausting memory (documented in FORMAT.md).
inline constexpr int kMaxImageSide = 1 << 16;
inline constexpr int kMaxIcosphereSubdivisions = 9;     // 20 * 4^9 = 5.2M triangles
inline constexpr std::int64_t kMaxGridCells = 1 << 24;  // 33.5M triangles
inline constexpr int kMaxGridSide = 1 << 20;
inline constexpr int kMaxSpp = 1 << 20;
inline constexpr int kMaxDepth = 1024;

inline std::string int_range_message(std::int64_t value, std::int64_t lo, std::int64_t hi) {
    return "value " + std::to_string(value) + " is out of range: must be in [" +
           std::to_string(lo) + ", " + std::to_string(hi) + "]";
}

inline std::string number_range_message(double value, const char* range_text) {
    std::ostringstream s;
    s << "value " << value << " is out of range: must be " << range_text;
    return s.str();
}

// RFC 6901 escaping of one reference token.
inline std::string escape_pointer_token(const std::string& key) {
    std::string out;
    for (char c : key) {
        if (c == '~')
            out += "~0";
        else if (c == '/')
            out += "~1";
        else
            out += c;
    }
    return out;
}

}  // namespace facet::render::detail
