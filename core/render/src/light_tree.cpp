// The light tree (facet/render/light_tree.h: conventions and references).
#include "facet/render/light_tree.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include "facet/render/light.h"

namespace facet::render {

namespace {

constexpr float kPiF = 3.14159265358979323846f;
constexpr float kOneMinusEpsilon = 0x1.fffffep-1f;

float safe_sqrt_f(float x) {
    return std::sqrt(std::max(0.f, x));
}

// cos and sin of max(0, a - b) for angles a, b in [0, pi] given by their cos and sin.
void cos_sin_reduced(float cos_a, float sin_a, float cos_b, float sin_b, float& c, float& s) {
    if (cos_a >= cos_b) {  // a <= b
        c = 1.f;
        s = 0.f;
        return;
    }
    c = cos_a * cos_b + sin_a * sin_b;
    s = sin_a * cos_b - cos_a * sin_b;
}

}  // namespace

LightTree::NodeBounds LightTree::NodeBounds::of(const LightBounds& b) {
    NodeBounds nb;
    nb.centre = 0.5f * (b.lo + b.hi);
    const Vec3 diag = b.hi - b.lo;
    nb.r2 = 0.25f * glm::dot(diag, diag);  // the box's half diagonal, squared
    nb.w = b.w;
    nb.cos_o = b.cos_theta_o;
    nb.sin_o = safe_sqrt_f(1.f - b.cos_theta_o * b.cos_theta_o);
    nb.cos_e = b.cos_theta_e;
    nb.phi = b.phi;
    nb.two_sided = b.two_sided;
    // theta_o = pi: theta_w - theta_o <= 0 for every p, so theta' = 0 (cos 1) whatever w and
    // theta_b are: the cone's terms need not be computed (the same value, bit for bit).
    nb.omni = b.cos_theta_o == -1.f;
    return nb;
}

namespace {

// light_importance of a node, inlined into the traversals (each evaluates two nodes per level).
[[gnu::always_inline]] inline float node_importance(const LightTree::NodeBounds& b, const Vec3& p,
                                                    const Vec3& n) {
    if (!(b.phi > 0.f)) return 0.f;
    const Vec3 dv = p - b.centre;
    const float dist2 = glm::dot(dv, dv);
    const float d2 = std::max(dist2, b.r2);
    const bool normal = n != Vec3(0.f);
    if (b.omni && !normal) {
        const float importance = b.phi / d2;
        return std::isfinite(importance) && importance > 0.f ? importance : 0.f;
    }
    // theta_b: the cone the box (its bounding sphere) subtends from p; all of it from inside.
    const float cos_b = dist2 > b.r2 ? safe_sqrt_f(1.f - b.r2 / dist2) : -1.f;
    const float sin_b = safe_sqrt_f(1.f - cos_b * cos_b);
    const Vec3 wi = dist2 > 0.f ? dv / std::sqrt(dist2) : Vec3(0.f, 0.f, 1.f);
    float cos_x = 1.f;
    if (!b.omni) {
        // theta_w: from the cone's axis to the direction toward p.
        float cos_w = glm::dot(b.w, wi);
        if (b.two_sided) cos_w = std::fabs(cos_w);
        const float sin_w = safe_sqrt_f(1.f - cos_w * cos_w);
        float cos_wo, sin_wo, sin_x;
        cos_sin_reduced(cos_w, sin_w, b.cos_o, b.sin_o, cos_wo, sin_wo);  // theta_w - theta_o
        cos_sin_reduced(cos_wo, sin_wo, cos_b, sin_b, cos_x, sin_x);      // ... - theta_b
        if (cos_x < b.cos_e || !(cos_x >= -1.f)) return 0.f;  // beyond theta_o + theta_e
    }
    float importance = b.phi * cos_x / d2;
    if (normal) {
        // theta_i: from the normal at p to the direction toward the box, less theta_b.
        const float cos_i = std::fabs(glm::dot(wi, n));
        const float sin_i = safe_sqrt_f(1.f - cos_i * cos_i);
        float cos_ip, sin_ip;
        cos_sin_reduced(cos_i, sin_i, cos_b, sin_b, cos_ip, sin_ip);
        importance *= std::max(0.f, cos_ip);
    }
    return std::isfinite(importance) && importance > 0.f ? importance : 0.f;
}

}  // namespace

float light_importance(const LightBounds& b, const Vec3& p, const Vec3& n) {
    return node_importance(LightTree::NodeBounds::of(b), p, n);
}

LightBounds union_bounds(const LightBounds& a, const LightBounds& b) {
    if (!(a.phi > 0.f)) return b.phi > 0.f ? b : a;
    if (!(b.phi > 0.f)) return a;
    LightBounds u;
    u.lo = glm::min(a.lo, b.lo);
    u.hi = glm::max(a.hi, b.hi);
    u.phi = a.phi + b.phi;
    u.cos_theta_e = std::min(a.cos_theta_e, b.cos_theta_e);
    u.two_sided = a.two_sided || b.two_sided;
    // The smallest cone holding both cones (angles theta_a, theta_b about w_a, w_b, theta_d
    // apart): one holds the other, or the cone of half-angle (theta_a + theta_d + theta_b) / 2
    // about w_a turned toward w_b by that minus theta_a.
    const float ta = std::acos(std::clamp(a.cos_theta_o, -1.f, 1.f));
    const float tb = std::acos(std::clamp(b.cos_theta_o, -1.f, 1.f));
    const float td = std::acos(std::clamp(glm::dot(a.w, b.w), -1.f, 1.f));
    if (std::min(td + tb, kPiF) <= ta) {
        u.w = a.w;
        u.cos_theta_o = a.cos_theta_o;
        return u;
    }
    if (std::min(td + ta, kPiF) <= tb) {
        u.w = b.w;
        u.cos_theta_o = b.cos_theta_o;
        return u;
    }
    const float to = 0.5f * (ta + td + tb);
    const Vec3 k = glm::cross(a.w, b.w);
    const float klen = glm::length(k);
    if (to >= kPiF || !(klen > 0.f)) {
        u.w = a.w;
        u.cos_theta_o = -1.f;  // every direction
        return u;
    }
    const float tr = to - ta;
    const Vec3 kn = k / klen;
    u.w = glm::normalize(a.w * std::cos(tr) + glm::cross(kn, a.w) * std::sin(tr));
    u.cos_theta_o = std::cos(to);
    return u;
}

void LightTree::build(std::span<const Light> lights, std::vector<std::uint32_t>& ids) {
    m_trail.assign(lights.size(), 0);
    m_depth.assign(lights.size(), -1);
    m_infinite_slot.assign(lights.size(), -1);
    std::vector<std::pair<std::uint32_t, LightBounds>> items;
    for (std::uint32_t i : ids) {
        const std::optional<LightBounds> b = lights[i].bounds();
        if (b) {
            items.emplace_back(i, *b);
        } else {
            m_infinite_slot[i] = std::int32_t(m_infinite.size());
            m_infinite.push_back(i);
        }
    }
    if (!items.empty()) build_node(items, 0, items.size(), 0, 0);
}

std::uint32_t LightTree::build_node(std::vector<std::pair<std::uint32_t, LightBounds>>& items,
                                    std::size_t begin, std::size_t end, std::uint64_t trail,
                                    int depth) {
    const std::uint32_t index = std::uint32_t(m_nodes.size());
    m_nodes.emplace_back();
    if (end - begin == 1 || depth >= 63) {
        // A leaf: one light (a deeper tree than the trail's 63 bits cannot arise from the
        // median split below with fewer than 2^63 lights).
        Node& leaf = m_nodes[index];
        leaf.leaf = true;
        leaf.child_or_light = items[begin].first;
        leaf.bounds = NodeBounds::of(items[begin].second);
        leaf.full = items[begin].second;
        m_trail[items[begin].first] = trail;
        m_depth[items[begin].first] = depth;
        return index;
    }
    Vec3 lo(INFINITY), hi(-INFINITY);
    for (std::size_t i = begin; i < end; ++i) {
        const Vec3 c = 0.5f * (items[i].second.lo + items[i].second.hi);
        lo = glm::min(lo, c);
        hi = glm::max(hi, c);
    }
    const Vec3 ext = hi - lo;
    const int axis = ext.x >= ext.y && ext.x >= ext.z ? 0 : ext.y >= ext.z ? 1 : 2;
    const std::size_t mid = begin + (end - begin) / 2;
    std::nth_element(items.begin() + std::ptrdiff_t(begin), items.begin() + std::ptrdiff_t(mid),
                     items.begin() + std::ptrdiff_t(end), [axis](const auto& x, const auto& y) {
                         const float cx = x.second.lo[axis] + x.second.hi[axis];
                         const float cy = y.second.lo[axis] + y.second.hi[axis];
                         return cx < cy || (cx == cy && x.first < y.first);
                     });
    const std::uint32_t first = build_node(items, begin, mid, trail, depth + 1);
    const std::uint32_t second =
        build_node(items, mid, end, trail | (std::uint64_t(1) << depth), depth + 1);
    m_nodes[index].child_or_light = second;
    m_nodes[index].full = union_bounds(m_nodes[first].full, m_nodes[second].full);
    m_nodes[index].bounds = NodeBounds::of(m_nodes[index].full);
    return index;
}

float LightTree::infinite_share() const {
    if (m_infinite.empty()) return 0.f;
    if (m_nodes.empty()) return 1.f;
    return float(m_infinite.size()) / float(m_infinite.size() + 1);
}

std::uint32_t LightTree::sample_reusing(const Vec3& p, const Vec3& n, float& u, float& pmf) const {
    pmf = 0.f;
    const float p_inf = infinite_share();
    if (u < p_inf) {
        const float x = u / p_inf * float(m_infinite.size());
        const std::size_t k = std::min(std::size_t(x), m_infinite.size() - 1);
        u = std::clamp(x - float(k), 0.f, kOneMinusEpsilon);
        pmf = p_inf / float(m_infinite.size());
        return m_infinite[k];
    }
    if (m_nodes.empty()) return 0;
    u = std::min((u - p_inf) / (1.f - p_inf), kOneMinusEpsilon);
    float prob = 1.f - p_inf;
    std::uint32_t node = 0;
    // A chosen child's importance is > 0 (its share of u is), so only a root leaf needs its
    // own evaluation.
    bool positive = false;
    while (!m_nodes[node].leaf) {
        const std::uint32_t c0 = node + 1, c1 = m_nodes[node].child_or_light;
        const float i0 = node_importance(m_nodes[c0].bounds, p, n);
        const float i1 = node_importance(m_nodes[c1].bounds, p, n);
        if (!(i0 + i1 > 0.f)) return 0;
        const float p0 = i0 / (i0 + i1);
        if (u < p0) {
            node = c0;
            u = std::min(u / p0, kOneMinusEpsilon);
            prob *= p0;
            positive = i0 > 0.f;
        } else {
            node = c1;
            u = std::min((u - p0) / (1.f - p0), kOneMinusEpsilon);
            prob *= 1.f - p0;
            positive = i1 > 0.f;
        }
    }
    if (!positive && !(node_importance(m_nodes[node].bounds, p, n) > 0.f)) return 0;
    pmf = prob;
    return m_nodes[node].child_or_light;
}

float LightTree::pmf(const Vec3& p, const Vec3& n, std::uint32_t light) const {
    if (light >= m_depth.size()) return 0.f;
    const float p_inf = infinite_share();
    if (m_infinite_slot[light] >= 0) return p_inf / float(m_infinite.size());
    const int depth = m_depth[light];
    if (depth < 0) return 0.f;
    float prob = 1.f - p_inf;
    std::uint32_t node = 0;
    bool positive = false;  // as in sample_reusing, but this path may take a child of 0
    for (int k = 0; k < depth; ++k) {
        const std::uint32_t c0 = node + 1, c1 = m_nodes[node].child_or_light;
        const float i0 = node_importance(m_nodes[c0].bounds, p, n);
        const float i1 = node_importance(m_nodes[c1].bounds, p, n);
        if (!(i0 + i1 > 0.f)) return 0.f;
        const float p0 = i0 / (i0 + i1);
        if ((m_trail[light] >> k) & 1u) {
            node = c1;
            prob *= 1.f - p0;
            positive = i1 > 0.f;
        } else {
            node = c0;
            prob *= p0;
            positive = i0 > 0.f;
        }
    }
    if (!positive && !(node_importance(m_nodes[node].bounds, p, n) > 0.f)) return 0.f;
    return prob;
}

}  // namespace facet::render
