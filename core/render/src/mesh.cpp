// Procedural meshes and mesh file readers (conventions in facet/render/mesh.h).
#include "facet/render/mesh.h"

#include "facet/render/texel_image.h"

#include <tiny_obj_loader.h>

#include <charconv>
#include <cstring>
#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>
#include <tuple>
#include <unordered_map>

namespace facet::render {

namespace {

void push_tri(TriangleMesh& m, std::uint32_t a, std::uint32_t b, std::uint32_t c) {
    m.indices.insert(m.indices.end(), {a, b, c});
}

}  // namespace

TriangleMesh make_box(const Vec3& lo, const Vec3& hi) {
    TriangleMesh m;
    // Corner i has x from bit 0, y from bit 1, z from bit 2.
    auto corner = [&](std::uint32_t i) {
        return Vec3(i & 1 ? hi.x : lo.x, i & 2 ? hi.y : lo.y, i & 4 ? hi.z : lo.z);
    };
    // Faces as quads q0 q1 q2 q3, counter-clockwise seen from outside, triangulated as
    // (q0 q1 q2), (q0 q2 q3); `up` is the corner of the quad that gets uv (0, 1): the UV square
    // is turned (never mirrored: both run counter-clockwise) so that v points along +y on the
    // side faces, -z on the top and +z on the bottom (mesh.h).
    struct Face {
        std::uint32_t q[4];
        int up;
    };
    const Face faces[6] = {
        {{0, 4, 6, 2}, 3},  // -x: u along +z, v along +y; (0, 0) at (lo.x, lo.y, lo.z)
        {{1, 3, 7, 5}, 2},  // +x: u along -z, v along +y; (0, 0) at (hi.x, lo.y, hi.z)
        {{0, 1, 5, 4}, 3},  // -y: u along +x, v along +z; (0, 0) at (lo.x, lo.y, lo.z)
        {{2, 6, 7, 3}, 0},  // +y: u along +x, v along -z; (0, 0) at (lo.x, hi.y, hi.z)
        {{0, 2, 3, 1}, 2},  // -z: u along -x, v along +y; (0, 0) at (hi.x, lo.y, lo.z)
        {{4, 5, 7, 6}, 3},  // +z: u along +x, v along +y; (0, 0) at (lo.x, lo.y, hi.z)
    };
    const Vec2 square[4] = {{0.f, 0.f}, {1.f, 0.f}, {1.f, 1.f}, {0.f, 1.f}};
    for (const Face& f : faces) {
        const std::uint32_t base = std::uint32_t(m.positions.size());
        for (int k = 0; k < 4; ++k) {
            m.positions.push_back(corner(f.q[k]));
            // Corner `up` gets (0, 1); the others follow counter-clockwise.
            m.uvs.push_back(square[(k - f.up + 3 + 4) % 4]);
        }
        push_tri(m, base, base + 1, base + 2);
        push_tri(m, base, base + 2, base + 3);
    }
    return m;
}

TriangleMesh make_quad(const std::array<Vec3, 4>& p) {
    TriangleMesh m;
    m.positions.assign(p.begin(), p.end());
    m.uvs = {{0.f, 0.f}, {1.f, 0.f}, {1.f, 1.f}, {0.f, 1.f}};
    push_tri(m, 0, 1, 2);
    push_tri(m, 0, 2, 3);
    return m;
}

TriangleMesh make_icosphere(int subdivisions, bool smooth) {
    TriangleMesh m;
    const float t = (1.f + std::sqrt(5.f)) / 2.f;
    const Vec3 v[12] = {{-1, t, 0},  {1, t, 0},  {-1, -t, 0}, {1, -t, 0}, {0, -1, t},  {0, 1, t},
                        {0, -1, -t}, {0, 1, -t}, {t, 0, -1},  {t, 0, 1},  {-t, 0, -1}, {-t, 0, 1}};
    for (const Vec3& p : v) m.positions.push_back(glm::normalize(p));
    const std::uint32_t f[20][3] = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                                    {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                                    {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                                    {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
    for (const auto& tri : f) {
        // Orient outward whatever the table's winding: the centroid direction is the outside.
        const Vec3 &a = m.positions[tri[0]], &b = m.positions[tri[1]], &c = m.positions[tri[2]];
        if (glm::dot(glm::cross(b - a, c - a), a + b + c) >= 0.f) {
            push_tri(m, tri[0], tri[1], tri[2]);
        } else {
            push_tri(m, tri[0], tri[2], tri[1]);
        }
    }
    for (int s = 0; s < subdivisions; ++s) {
        std::unordered_map<std::uint64_t, std::uint32_t> midpoint;
        midpoint.reserve(m.indices.size());
        auto mid = [&](std::uint32_t a, std::uint32_t b) {
            std::uint64_t key = (std::uint64_t(std::min(a, b)) << 32) | std::max(a, b);
            auto [it, inserted] = midpoint.try_emplace(key, std::uint32_t(m.positions.size()));
            if (inserted) {
                m.positions.push_back(glm::normalize(m.positions[a] + m.positions[b]));
            }
            return it->second;
        };
        std::vector<std::uint32_t> next;
        next.reserve(m.indices.size() * 4);
        for (std::size_t i = 0; i < m.indices.size(); i += 3) {
            std::uint32_t a = m.indices[i], b = m.indices[i + 1], c = m.indices[i + 2];
            std::uint32_t ab = mid(a, b), bc = mid(b, c), ca = mid(c, a);
            next.insert(next.end(), {a, ab, ca, ab, b, bc, ca, bc, c, ab, bc, ca});
        }
        m.indices = std::move(next);
    }
    if (smooth) m.normals = m.positions;
    return m;
}

TriangleMesh make_grid(int nx, int ny, float amplitude, float frequency) {
    TriangleMesh m;
    std::size_t nvx = std::size_t(nx) + 1, nvy = std::size_t(ny) + 1;
    m.positions.reserve(nvx * nvy);
    m.uvs.reserve(nvx * nvy);
    bool displaced = amplitude != 0.f;
    if (displaced) m.normals.reserve(nvx * nvy);
    for (std::size_t j = 0; j < nvy; ++j) {
        for (std::size_t i = 0; i < nvx; ++i) {
            float x = -1.f + 2.f * float(i) / float(nx);
            float y = -1.f + 2.f * float(j) / float(ny);
            float sx = std::sin(frequency * x), sy = std::sin(frequency * y);
            m.positions.emplace_back(x, y, amplitude * sx * sy);
            m.uvs.emplace_back(float(i) / float(nx), float(j) / float(ny));
            if (displaced) {
                // n = (-dz/dx, -dz/dy, 1) normalised.
                float dzdx = amplitude * frequency * std::cos(frequency * x) * sy;
                float dzdy = amplitude * frequency * sx * std::cos(frequency * y);
                m.normals.push_back(glm::normalize(Vec3(-dzdx, -dzdy, 1.f)));
            }
        }
    }
    m.indices.reserve(std::size_t(nx) * std::size_t(ny) * 6);
    for (std::size_t j = 0; j < std::size_t(ny); ++j) {
        for (std::size_t i = 0; i < std::size_t(nx); ++i) {
            auto v = [&](std::size_t a, std::size_t b) { return std::uint32_t(b * nvx + a); };
            push_tri(m, v(i, j), v(i + 1, j), v(i + 1, j + 1));
            push_tri(m, v(i, j), v(i + 1, j + 1), v(i, j + 1));
        }
    }
    return m;
}

namespace {

// A vertex colour from sRGB-encoded channels (alpha linear), for the OBJ and PLY readers. Values
// outside [0, 1] (and NaN) are kept, undecoded, for validate_mesh to report.
glm::vec4 srgb_color(double r, double g, double b, double a) {
    auto decode = [](double e) { return e >= 0.0 && e <= 1.0 ? srgb_decode_exact(e) : float(e); };
    return {decode(r), decode(g), decode(b), float(a)};
}

}  // namespace

TriangleMesh load_obj(const std::string& path) {
    tinyobj::ObjReader reader;
    tinyobj::ObjReaderConfig config;
    config.triangulate = true;
    config.vertex_color = false;
    if (!reader.ParseFromFile(path, config)) {
        std::string err = reader.Error();
        while (!err.empty() && (err.back() == '\n' || err.back() == '\r')) err.pop_back();
        throw std::runtime_error("cannot read OBJ file '" + path +
                                 "': " + (err.empty() ? std::string("unknown error") : err));
    }
    const tinyobj::attrib_t& attrib = reader.GetAttrib();
    TriangleMesh m;
    // tinyobjloader keeps `v x y z r g b` colours only when every vertex has them
    // (config.vertex_color = false: no default fill).
    const bool colors = !attrib.colors.empty() && attrib.colors.size() == attrib.vertices.size();
    bool all_normals = true, all_uvs = true;
    for (const auto& shape : reader.GetShapes()) {
        for (const auto& idx : shape.mesh.indices) {
            if (idx.normal_index < 0) all_normals = false;
            if (idx.texcoord_index < 0) all_uvs = false;
        }
    }
    // One output vertex per distinct (position, normal, texture coordinate).
    std::map<std::tuple<int, int, int>, std::uint32_t> remap;
    std::size_t nverts = attrib.vertices.size() / 3, nnormals = attrib.normals.size() / 3,
                nuvs = attrib.texcoords.size() / 2;
    for (const auto& shape : reader.GetShapes()) {
        std::size_t offset = 0;
        for (std::size_t f = 0; f < shape.mesh.num_face_vertices.size(); ++f) {
            std::size_t fv = shape.mesh.num_face_vertices[f];
            if (fv != 3) {  // triangulation failed for this face (degenerate): skip it
                offset += fv;
                continue;
            }
            for (std::size_t k = 0; k < 3; ++k) {
                const auto& idx = shape.mesh.indices[offset + k];
                int ni = all_normals ? idx.normal_index : -1;
                int ti = all_uvs ? idx.texcoord_index : -1;
                if (idx.vertex_index < 0 || std::size_t(idx.vertex_index) >= nverts ||
                    (ni >= 0 && std::size_t(ni) >= nnormals) ||
                    (ti >= 0 && std::size_t(ti) >= nuvs)) {
                    throw std::runtime_error("OBJ file '" + path + "': face " +
                                             std::to_string(f + 1) + " has an index out of range");
                }
                auto [it, inserted] = remap.try_emplace({idx.vertex_index, ni, ti},
                                                        std::uint32_t(m.positions.size()));
                if (inserted) {
                    const float* p = &attrib.vertices[3 * std::size_t(idx.vertex_index)];
                    m.positions.emplace_back(p[0], p[1], p[2]);
                    if (ni >= 0) {
                        const float* n = &attrib.normals[3 * std::size_t(ni)];
                        Vec3 nn(n[0], n[1], n[2]);
                        float len = glm::length(nn);
                        m.normals.push_back(len > 0.f ? nn / len : Vec3(0.f, 0.f, 1.f));
                    }
                    if (ti >= 0) {
                        const float* t = &attrib.texcoords[2 * std::size_t(ti)];
                        m.uvs.emplace_back(t[0], t[1]);
                    }
                    if (colors) {
                        // sRGB-encoded, as Blender's OBJ exporter writes them (mesh.h).
                        const float* c = &attrib.colors[3 * std::size_t(idx.vertex_index)];
                        m.colors.push_back(srgb_color(c[0], c[1], c[2], 1.f));
                    }
                }
                m.indices.push_back(it->second);
            }
            offset += fv;
        }
    }
    return m;
}

// --- PLY --------------------------------------------------------------------------------------

namespace {

enum class PlyType { Int8, UInt8, Int16, UInt16, Int32, UInt32, Float32, Float64, Invalid };

PlyType ply_type(const std::string& s) {
    if (s == "char" || s == "int8") return PlyType::Int8;
    if (s == "uchar" || s == "uint8") return PlyType::UInt8;
    if (s == "short" || s == "int16") return PlyType::Int16;
    if (s == "ushort" || s == "uint16") return PlyType::UInt16;
    if (s == "int" || s == "int32") return PlyType::Int32;
    if (s == "uint" || s == "uint32") return PlyType::UInt32;
    if (s == "float" || s == "float32") return PlyType::Float32;
    if (s == "double" || s == "float64") return PlyType::Float64;
    return PlyType::Invalid;
}

std::size_t ply_size(PlyType t) {
    switch (t) {
        case PlyType::Int8:
        case PlyType::UInt8:
            return 1;
        case PlyType::Int16:
        case PlyType::UInt16:
            return 2;
        case PlyType::Int32:
        case PlyType::UInt32:
        case PlyType::Float32:
            return 4;
        case PlyType::Float64:
            return 8;
        case PlyType::Invalid:
            break;
    }
    return 0;
}

struct PlyProperty {
    std::string name;
    bool is_list = false;
    PlyType count_type = PlyType::Invalid;
    PlyType type = PlyType::Invalid;  // the value type, or the list's item type
};

struct PlyElement {
    std::string name;
    std::size_t count = 0;
    std::vector<PlyProperty> props;
};

[[noreturn]] void ply_fail(const std::string& msg) {
    throw std::runtime_error("PLY: " + msg);
}

// Reads values either as ascii tokens or little-endian binary, from a byte range.
class PlyReader {
  public:
    PlyReader(std::string_view data, bool binary) : m_data(data), m_binary(binary) {}

    double read(PlyType t) {
        if (m_binary) return read_binary(t);
        std::string_view tok = token();
        double v = 0.0;
        auto [ptr, ec] = std::from_chars(tok.data(), tok.data() + tok.size(), v);
        if (ec != std::errc() || ptr != tok.data() + tok.size()) {
            ply_fail("malformed number '" + std::string(tok.substr(0, 32)) + "'");
        }
        return v;
    }
    bool at_end() const { return m_pos >= m_data.size(); }
    std::size_t remaining() const { return m_data.size() - std::min(m_pos, m_data.size()); }

  private:
    std::string_view token() {
        while (m_pos < m_data.size() && std::isspace(static_cast<unsigned char>(m_data[m_pos]))) {
            ++m_pos;
        }
        std::size_t start = m_pos;
        while (m_pos < m_data.size() && !std::isspace(static_cast<unsigned char>(m_data[m_pos]))) {
            ++m_pos;
        }
        if (start == m_pos) ply_fail("unexpected end of data");
        return m_data.substr(start, m_pos - start);
    }
    double read_binary(PlyType t) {
        std::size_t n = ply_size(t);
        if (m_pos + n > m_data.size()) ply_fail("unexpected end of binary data");
        unsigned char b[8] = {};
        std::memcpy(b, m_data.data() + m_pos, n);
        m_pos += n;
        // Assemble little-endian integers explicitly: no dependence on the host's byte order.
        std::uint64_t u = 0;
        for (std::size_t i = 0; i < n; ++i) u |= std::uint64_t(b[i]) << (8 * i);
        switch (t) {
            case PlyType::Int8:
                return double(std::int8_t(u));
            case PlyType::UInt8:
                return double(std::uint8_t(u));
            case PlyType::Int16:
                return double(std::int16_t(u));
            case PlyType::UInt16:
                return double(std::uint16_t(u));
            case PlyType::Int32:
                return double(std::int32_t(u));
            case PlyType::UInt32:
                return double(std::uint32_t(u));
            case PlyType::Float32: {
                std::uint32_t w = std::uint32_t(u);
                float f;
                std::memcpy(&f, &w, 4);
                return double(f);
            }
            case PlyType::Float64: {
                double d;
                std::memcpy(&d, &u, 8);
                return d;
            }
            case PlyType::Invalid:
                break;
        }
        ply_fail("invalid property type");
    }

    std::string_view m_data;
    bool m_binary;
    std::size_t m_pos = 0;
};

// Largest polygon accepted in a face list (guards against garbage counts).
constexpr double kPlyMaxPolygon = 256;

}  // namespace

TriangleMesh parse_ply(std::string_view data) {
    // Header: lines up to "end_header".
    std::size_t pos = 0;
    auto next_line = [&](std::string& line) {
        if (pos >= data.size()) ply_fail("header ends without 'end_header'");
        std::size_t e = data.find('\n', pos);
        if (e == std::string_view::npos) e = data.size();
        line.assign(data.substr(pos, e - pos));
        if (!line.empty() && line.back() == '\r') line.pop_back();
        pos = e + 1;
    };
    std::string line;
    next_line(line);
    if (line != "ply") ply_fail("missing 'ply' magic on the first line");
    bool binary = false, have_format = false;
    std::vector<PlyElement> elements;
    for (int guard = 0;; ++guard) {
        next_line(line);
        std::istringstream ss(line);
        std::string word;
        ss >> word;
        if (word == "end_header") break;
        if (word == "comment" || word == "obj_info" || word.empty()) continue;
        if (word == "format") {
            std::string fmt, version;
            ss >> fmt >> version;
            if (fmt == "ascii") {
                binary = false;
            } else if (fmt == "binary_little_endian") {
                binary = true;
            } else {
                ply_fail("unsupported format '" + fmt +
                         "' (supported: ascii, binary_little_endian)");
            }
            have_format = true;
        } else if (word == "element") {
            PlyElement e;
            long long count = -1;
            ss >> e.name >> count;
            if (!ss || count < 0) ply_fail("malformed element line '" + line + "'");
            e.count = std::size_t(count);
            elements.push_back(std::move(e));
        } else if (word == "property") {
            if (elements.empty()) ply_fail("property before any element");
            PlyProperty p;
            std::string type;
            ss >> type;
            if (type == "list") {
                std::string ct, it;
                ss >> ct >> it >> p.name;
                p.is_list = true;
                p.count_type = ply_type(ct);
                p.type = ply_type(it);
                if (p.count_type == PlyType::Invalid || p.type == PlyType::Invalid ||
                    p.count_type == PlyType::Float32 || p.count_type == PlyType::Float64) {
                    ply_fail("bad list property '" + line + "'");
                }
            } else {
                p.type = ply_type(type);
                ss >> p.name;
                if (p.type == PlyType::Invalid) ply_fail("unknown property type '" + type + "'");
            }
            if (p.name.empty()) ply_fail("property without a name");
            elements.back().props.push_back(std::move(p));
        } else {
            ply_fail("unknown header line '" + line.substr(0, 64) + "'");
        }
    }
    if (!have_format) ply_fail("missing 'format' line");

    TriangleMesh m;
    PlyReader reader(data.substr(std::min(pos, data.size())), binary);
    bool have_vertices = false;
    for (const PlyElement& e : elements) {
        // Every element takes at least one byte (binary) or two (ascii token + separator): a
        // count above the data left is a lie; refuse it before allocating anything.
        std::size_t min_bytes = 0;
        for (const auto& p : e.props)
            min_bytes += binary ? ply_size(p.is_list ? p.count_type : p.type) : 2;
        if (min_bytes > 0 && e.count > reader.remaining() / min_bytes + 1) {
            ply_fail("element '" + e.name + "' claims " + std::to_string(e.count) +
                     " entries, more than the file holds");
        }
        if (e.name == "vertex") {
            int ix = -1, iy = -1, iz = -1, inx = -1, iny = -1, inz = -1, iu = -1, iv = -1;
            int ir = -1, ig = -1, ib = -1, ia = -1;
            for (std::size_t k = 0; k < e.props.size(); ++k) {
                const std::string& n = e.props[k].name;
                int* slot = n == "x"                                     ? &ix
                            : n == "y"                                   ? &iy
                            : n == "z"                                   ? &iz
                            : n == "nx"                                  ? &inx
                            : n == "ny"                                  ? &iny
                            : n == "nz"                                  ? &inz
                            : (n == "u" || n == "s" || n == "texture_u") ? &iu
                            : (n == "v" || n == "t" || n == "texture_v") ? &iv
                            : (n == "red" || n == "r")                   ? &ir
                            : (n == "green" || n == "g")                 ? &ig
                            : (n == "blue" || n == "b")                  ? &ib
                            : (n == "alpha" || n == "a")                 ? &ia
                                                                         : nullptr;
                if (slot && !e.props[k].is_list) *slot = int(k);
            }
            if (ix < 0 || iy < 0 || iz < 0) ply_fail("vertex element lacks x, y or z");
            bool normals = inx >= 0 && iny >= 0 && inz >= 0;
            m.positions.reserve(e.count);
            if (normals) m.normals.reserve(e.count);
            const bool uvs = iu >= 0 && iv >= 0;
            if (uvs) m.uvs.reserve(e.count);
            const bool colors = ir >= 0 && ig >= 0 && ib >= 0;
            if (colors) m.colors.reserve(e.count);
            // Integer colour channels are bytes (or shorts) of an sRGB-encoded colour, divided
            // by the type's largest value; float channels are linear (mesh.h).
            auto channel_max = [&](int k) {
                switch (e.props[std::size_t(k)].type) {
                    case PlyType::UInt8:
                        return 255.0;
                    case PlyType::UInt16:
                        return 65535.0;
                    case PlyType::Float32:
                    case PlyType::Float64:
                        return 0.0;
                    default:
                        ply_fail("vertex colour property '" + e.props[std::size_t(k)].name +
                                 "' must be uchar, ushort, float or double");
                }
            };
            const double cmax = colors ? channel_max(ir) : 0.0;
            if (colors && (channel_max(ig) != cmax || channel_max(ib) != cmax ||
                           (ia >= 0 && channel_max(ia) != cmax)))
                ply_fail("the vertex colour properties must share one type");
            std::vector<double> vals(e.props.size());
            for (std::size_t i = 0; i < e.count; ++i) {
                for (std::size_t k = 0; k < e.props.size(); ++k) {
                    const PlyProperty& p = e.props[k];
                    if (p.is_list) {
                        double n = reader.read(p.count_type);
                        if (!(n >= 0 && n <= kPlyMaxPolygon)) ply_fail("bad list length");
                        for (int j = 0; j < int(n); ++j) reader.read(p.type);
                        vals[k] = 0.0;
                    } else {
                        vals[k] = reader.read(p.type);
                    }
                }
                m.positions.emplace_back(float(vals[ix]), float(vals[iy]), float(vals[iz]));
                if (normals) {
                    Vec3 n = Vec3(float(vals[inx]), float(vals[iny]), float(vals[inz]));
                    float len = glm::length(n);
                    m.normals.push_back(len > 0.f && std::isfinite(len) ? n / len
                                                                        : Vec3(0.f, 0.f, 1.f));
                }
                if (uvs) m.uvs.emplace_back(float(vals[iu]), float(vals[iv]));
                if (colors) {
                    const double a = ia >= 0 ? vals[ia] : (cmax > 0.0 ? cmax : 1.0);
                    m.colors.push_back(cmax > 0.0 ? srgb_color(vals[ir] / cmax, vals[ig] / cmax,
                                                               vals[ib] / cmax, a / cmax)
                                                  : glm::vec4(float(vals[ir]), float(vals[ig]),
                                                              float(vals[ib]), float(a)));
                }
            }
            have_vertices = true;
        } else if (e.name == "face") {
            int list = -1;
            for (std::size_t k = 0; k < e.props.size(); ++k) {
                if (e.props[k].is_list &&
                    (e.props[k].name == "vertex_indices" || e.props[k].name == "vertex_index")) {
                    list = int(k);
                }
            }
            if (list < 0) ply_fail("face element lacks a vertex_indices list");
            std::vector<std::uint32_t> poly;
            for (std::size_t i = 0; i < e.count; ++i) {
                for (std::size_t k = 0; k < e.props.size(); ++k) {
                    const PlyProperty& p = e.props[k];
                    if (!p.is_list) {
                        reader.read(p.type);
                        continue;
                    }
                    double n = reader.read(p.count_type);
                    if (!(n >= 0 && n <= kPlyMaxPolygon)) {
                        ply_fail("face " + std::to_string(i) + " has a bad vertex count");
                    }
                    poly.clear();
                    for (int j = 0; j < int(n); ++j) {
                        double v = reader.read(p.type);
                        if (!(v >= 0 && v < 4294967295.0) || v != std::floor(v)) {
                            ply_fail("face " + std::to_string(i) + " has a bad vertex index");
                        }
                        poly.push_back(std::uint32_t(v));
                    }
                    if (int(k) != list) continue;
                    if (poly.size() < 3)
                        ply_fail("face " + std::to_string(i) + " has < 3 vertices");
                    for (std::size_t j = 1; j + 1 < poly.size(); ++j) {
                        push_tri(m, poly[0], poly[j], poly[j + 1]);
                    }
                }
            }
        } else {
            // Skip an unknown element. One without properties holds no data whatever its count
            // (and the count check above cannot bound it: looping over a claimed 3e12 entries
            // hung the PLY fuzzer).
            if (e.props.empty()) continue;
            for (std::size_t i = 0; i < e.count; ++i) {
                for (const PlyProperty& p : e.props) {
                    if (p.is_list) {
                        double n = reader.read(p.count_type);
                        if (!(n >= 0 && n <= 1e6)) ply_fail("bad list length");
                        for (int j = 0; j < int(n); ++j) reader.read(p.type);
                    } else {
                        reader.read(p.type);
                    }
                }
            }
        }
    }
    if (!have_vertices) ply_fail("no vertex element");
    return m;
}

TriangleMesh load_ply(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw std::runtime_error("cannot open PLY file '" + path + "'");
    std::ostringstream ss;
    ss << in.rdbuf();
    std::string data = ss.str();
    try {
        return parse_ply(data);
    } catch (const std::runtime_error& e) {
        throw std::runtime_error("'" + path + "': " + e.what());
    }
}

std::string validate_mesh(const TriangleMesh& m) {
    if (m.indices.empty()) return "mesh has no triangles";
    if (m.indices.size() % 3 != 0) return "index count is not a multiple of 3";
    if (!m.normals.empty() && m.normals.size() != m.positions.size()) {
        return "normals must be given once per position (" + std::to_string(m.positions.size()) +
               "), got " + std::to_string(m.normals.size());
    }
    if (!m.uvs.empty() && m.uvs.size() != m.positions.size()) {
        return "uvs must be given once per position (" + std::to_string(m.positions.size()) +
               "), got " + std::to_string(m.uvs.size());
    }
    for (std::size_t i = 0; i < m.uvs.size(); ++i) {
        if (!std::isfinite(m.uvs[i].x) || !std::isfinite(m.uvs[i].y))
            return "uv " + std::to_string(i) + " is not finite";
    }
    if (!m.tangents.empty() && m.tangents.size() != m.positions.size()) {
        return "tangents must be given once per position (" + std::to_string(m.positions.size()) +
               "), got " + std::to_string(m.tangents.size());
    }
    for (std::size_t i = 0; i < m.tangents.size(); ++i) {
        const glm::vec4& t = m.tangents[i];
        if (!std::isfinite(t.x) || !std::isfinite(t.y) || !std::isfinite(t.z) ||
            !std::isfinite(t.w))
            return "tangent " + std::to_string(i) + " is not finite";
    }
    if (!m.colors.empty() && m.colors.size() != m.positions.size()) {
        return "colors must be given once per position (" + std::to_string(m.positions.size()) +
               "), got " + std::to_string(m.colors.size());
    }
    for (std::size_t i = 0; i < m.colors.size(); ++i) {
        for (int c = 0; c < 4; ++c)
            if (!(m.colors[i][c] >= 0.f && m.colors[i][c] <= 1.f))
                return "colour " + std::to_string(i) + " has a channel outside [0, 1]";
    }
    for (std::size_t i = 0; i < m.positions.size(); ++i) {
        if (!is_finite(m.positions[i])) return "position " + std::to_string(i) + " is not finite";
    }
    for (std::size_t i = 0; i < m.normals.size(); ++i) {
        if (!is_finite(m.normals[i])) return "normal " + std::to_string(i) + " is not finite";
    }
    for (std::size_t i = 0; i < m.indices.size(); ++i) {
        if (m.indices[i] >= m.positions.size()) {
            return "index " + std::to_string(i) + " (" + std::to_string(m.indices[i]) +
                   ") is out of range (" + std::to_string(m.positions.size()) + " positions)";
        }
    }
    return "";
}

}  // namespace facet::render
