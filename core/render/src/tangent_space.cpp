// Per-corner tangents of a UV-mapped triangle mesh as MikkTSpace computes them (Mikkelsen 2008,
// "Simulation of wrinkled surfaces revisited"; the tangent space Blender, glTF and most baking
// tools assume). Written from the paper's and the reference implementation's description; the
// conventions and what is simplified are in facet/render/mesh.h (compute_tangents).
#include <algorithm>
#include <cmath>
#include <cstring>
#include <unordered_map>

#include "facet/render/mesh.h"

namespace facet::render {

namespace {

// A corner's welded vertex: MikkTSpace treats corners with bit-identical position, normal and
// texture coordinate as one vertex.
struct VertexKey {
    float v[8];
    bool operator==(const VertexKey& o) const { return std::memcmp(v, o.v, sizeof v) == 0; }
};
struct VertexKeyHash {
    std::size_t operator()(const VertexKey& k) const {
        std::uint32_t w[8];
        std::memcpy(w, k.v, sizeof w);
        std::uint64_t h = 1469598103934665603ull;  // FNV-1a over the 32-bit words
        for (std::uint32_t x : w) h = (h ^ x) * 1099511628211ull;
        return std::size_t(h);
    }
};

// Component of v perpendicular to unit n, normalised (0 when v is parallel to n or zero).
Vec3 perpendicular_unit(const Vec3& v, const Vec3& n) {
    const Vec3 p = v - glm::dot(n, v) * n;
    const float l = glm::length(p);
    return l > 0.f && std::isfinite(l) ? p / l : Vec3(0.f);
}

}  // namespace

std::vector<glm::vec4> compute_tangents(const TriangleMesh& m) {
    const std::size_t nt = m.num_triangles();
    std::vector<glm::vec4> out(3 * nt, glm::vec4(0.f));
    if (m.uvs.size() != m.positions.size()) return out;

    // Per triangle: unit dp/du (MikkTSpace's vOs), whether the UV map keeps its orientation
    // (signed UV area > 0), and whether the UV area is zero (no tangent of its own).
    struct Tri {
        Vec3 os{0.f};
        bool orient = false, degenerate = true;
    };
    std::vector<Tri> tris(nt);
    std::vector<Vec3> corner_n(3 * nt);
    for (std::size_t t = 0; t < nt; ++t) {
        const std::uint32_t* ix = &m.indices[3 * t];
        const Vec3 &p0 = m.positions[ix[0]], &p1 = m.positions[ix[1]], &p2 = m.positions[ix[2]];
        const Vec2 &t0 = m.uvs[ix[0]], &t1 = m.uvs[ix[1]], &t2 = m.uvs[ix[2]];
        const Vec3 d1 = p1 - p0, d2 = p2 - p0;
        const Vec2 e1 = t1 - t0, e2 = t2 - t0;
        // Twice the signed UV area; os = area * dp/du (Cramer's rule on p(u, v)).
        const float area = e1.x * e2.y - e1.y * e2.x;
        const Vec3 os = e2.y * d1 - e1.y * d2;
        Tri& tr = tris[t];
        tr.orient = area > 0.f;
        const float len = glm::length(os);
        if (area != 0.f && len > 0.f && std::isfinite(len)) {
            tr.os = (tr.orient ? 1.f : -1.f) / len * os;
            tr.degenerate = false;
        }
        // Corner normals: the vertex normals, or the face normal of a flat mesh.
        Vec3 fn = glm::cross(d1, d2);
        const float fl = glm::length(fn);
        fn = fl > 0.f ? fn / fl : Vec3(0.f, 0.f, 1.f);
        for (std::size_t j = 0; j < 3; ++j) {
            Vec3 n = m.normals.empty() ? fn : m.normals[ix[j]];
            const float nl = glm::length(n);
            corner_n[3 * t + j] = nl > 0.f ? n / nl : fn;
        }
    }

    // Welded vertex ids, then one accumulator per (vertex, orientation): the angle-weighted sum
    // of the triangles' dp/du projected into the vertex's tangent plane.
    std::unordered_map<VertexKey, std::uint32_t, VertexKeyHash> weld;
    weld.reserve(3 * nt);
    std::vector<std::uint32_t> vid(3 * nt);
    for (std::size_t c = 0; c < 3 * nt; ++c) {
        const Vec3& p = m.positions[m.indices[c]];
        const Vec3& n = corner_n[c];
        const Vec2& uv = m.uvs[m.indices[c]];
        const VertexKey k{{p.x, p.y, p.z, n.x, n.y, n.z, uv.x, uv.y}};
        vid[c] = weld.try_emplace(k, std::uint32_t(weld.size())).first->second;
    }
    std::vector<Vec3> sum(2 * weld.size(), Vec3(0.f));
    for (std::size_t t = 0; t < nt; ++t) {
        if (tris[t].degenerate) continue;
        for (std::size_t j = 0; j < 3; ++j) {
            const std::size_t c = 3 * t + j;
            const Vec3& n = corner_n[c];
            const Vec3& p = m.positions[m.indices[c]];
            // The corner's angle, measured in the vertex's tangent plane.
            const Vec3 a = perpendicular_unit(m.positions[m.indices[3 * t + (j + 2) % 3]] - p, n);
            const Vec3 b = perpendicular_unit(m.positions[m.indices[3 * t + (j + 1) % 3]] - p, n);
            const float angle = std::acos(std::clamp(glm::dot(a, b), -1.f, 1.f));
            sum[2 * vid[c] + (tris[t].orient ? 1 : 0)] += angle * perpendicular_unit(tris[t].os, n);
        }
    }
    for (std::size_t t = 0; t < nt; ++t) {
        for (std::size_t j = 0; j < 3; ++j) {
            const std::size_t c = 3 * t + j;
            bool orient = tris[t].orient;
            Vec3 s = sum[2 * vid[c] + (orient ? 1 : 0)];
            // A triangle without UV area joins whichever group its vertex has (MikkTSpace's
            // GROUP_WITH_ANY), the orientation-preserving one first.
            if (tris[t].degenerate) {
                for (const bool o : {true, false}) {
                    if (sum[2 * vid[c] + (o ? 1 : 0)] != Vec3(0.f)) {
                        orient = o;
                        s = sum[2 * vid[c] + (o ? 1 : 0)];
                        break;
                    }
                }
            }
            const float l = glm::length(s);
            Vec3 tan;
            if (l > 0.f && std::isfinite(l)) {
                tan = s / l;
            } else {
                // No UV gradient anywhere around the vertex: any unit vector in its tangent
                // plane (Duff et al. 2017's basis), so that shading stays finite.
                const Vec3& n = corner_n[c];
                const float sg = std::copysign(1.f, n.z), q = -1.f / (sg + n.z);
                tan = Vec3(1.f + sg * n.x * n.x * q, sg * n.x * n.y * q, -sg * n.x);
            }
            out[c] = glm::vec4(tan, orient ? 1.f : -1.f);
        }
    }
    return out;
}

}  // namespace facet::render
