// The light tree: next-event estimation's choice of a light in proportion to an estimate of
// its contribution AT the shaded point, for scenes with many lights (Conty Estevez & Kulla
// 2018, "Importance sampling of many lights with adaptive tree splitting"; pbrt-v4's
// BVHLightSampler). `--light-selection tree` (render.h LightSelection::Tree).
//
// Conventions:
//  - The lights with a position (Light::bounds) are the leaves of a binary tree, built once at
//    load time by splitting the lights' centroids at the median of their widest axis; a node
//    holds the union of its lights' bounds (box, summed phi, a cone of directions holding both
//    children's cones).
//  - importance(bounds, p, n) (pbrt-v4 eq. of LightBounds::Importance): phi cos(theta') / d^2
//    with d the distance from p to the box's centre (at least the box's half diagonal), theta'
//    the angle between the cone's axis and the direction to p, reduced by the cone's theta_o
//    and by the angle theta_b the box subtends from p, and 0 beyond theta_e; times
//    cos(max(0, theta_i - theta_b)) with theta_i the angle to the normal n at p (omitted when
//    n = 0: transmissive surfaces and points in media). It is 0 only where no light of the
//    node can light p: bounds may be loose, so the choice stays unbiased.
//  - Sampling walks from the root choosing a child with probability proportional to its
//    importance, reusing the random number (rescaled), and returns the leaf's light with the
//    product of the choices' probabilities. pmf(p, n, i) walks the same path to light i (its
//    bit trail) and multiplies the same numbers, so it equals the probability sample() gives
//    i, bit for bit. Where both children have importance 0 no light is chosen (pmf 0).
//  - Lights at infinity (directional, environment maps) and their choice: each is chosen with
//    probability 1 / (N_infinite + 1), the tree with the remaining 1 / (N_infinite + 1)
//    (pbrt-v4); with no light of position, the infinite lights uniformly.
//  - Only lights next-event estimation samples (nee_samples) take part.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "facet/render/light_sample.h"

namespace facet::render {

class Light;

// The importance of lights within `b` at p with normal n (conventions); 0 when they cannot
// light p.
float light_importance(const LightBounds& b, const Vec3& p, const Vec3& n);

// The union of two bounds: the box around both, the sum of phi, the smallest cone (about an
// axis between the two) that holds both cones, the larger theta_e.
LightBounds union_bounds(const LightBounds& a, const LightBounds& b);

class LightTree {
  public:
    LightTree() = default;
    // The tree over `lights`, taking the lights for which `candidate(i)` holds.
    template <class Candidate>
    LightTree(std::span<const Light> lights, Candidate candidate) {
        std::vector<std::uint32_t> ids;
        for (std::uint32_t i = 0; i < lights.size(); ++i)
            if (candidate(i)) ids.push_back(i);
        build(lights, ids);
    }
    // No light can be chosen.
    bool empty() const { return m_nodes.empty() && m_infinite.empty(); }
    // Index of the light chosen by u in [0, 1) for the point p with normal n (0: none), and
    // its probability in `pmf` (0 when no light could be chosen; the index is then 0).
    std::uint32_t sample(const Vec3& p, const Vec3& n, float u, float& pmf) const {
        return sample_reusing(p, n, u, pmf);
    }
    // The same, leaving in u what is left of it: the traversal rescales u to [0, 1) over each
    // chosen child's share, so conditioned on the light chosen the final u is uniform on
    // [0, 1) and can serve as a coordinate of that light's sample (light.h,
    // LightDistribution::sample).
    std::uint32_t sample_reusing(const Vec3& p, const Vec3& n, float& u, float& pmf) const;
    // The probability that sample(p, n, .) chooses light i.
    float pmf(const Vec3& p, const Vec3& n, std::uint32_t light) const;

    // A node's bounds as the importance reads them: the box's centre and squared half
    // diagonal and the cone's sin theta_o precomputed, and whether the cone is every direction
    // (theta_o = pi: point lights and their unions), whose cone terms are skipped.
    struct NodeBounds {
        Vec3 centre{0.f};
        float r2 = 0.f;
        Vec3 w{0.f, 0.f, 1.f};
        float cos_o = -1.f, sin_o = 0.f, cos_e = 0.f, phi = 0.f;
        bool two_sided = false, omni = true;
        static NodeBounds of(const LightBounds& b);
    };

  private:
    struct Node {
        NodeBounds bounds;
        LightBounds full;                  // the union the node's bounds come from (build)
        std::uint32_t child_or_light = 0;  // interior: the second child's index; leaf: light
        bool leaf = false;                 // interior nodes' first child follows them
    };
    void build(std::span<const Light> lights, std::vector<std::uint32_t>& ids);
    std::uint32_t build_node(std::vector<std::pair<std::uint32_t, LightBounds>>& items,
                             std::size_t begin, std::size_t end, std::uint64_t trail, int depth);
    float infinite_share() const;

    std::vector<Node> m_nodes;              // root first
    std::vector<std::uint32_t> m_infinite;  // lights at infinity
    // Per light: its leaf's path from the root (bit k: took the second child at depth k) and
    // depth, or depth -1 for lights not in the tree.
    std::vector<std::uint64_t> m_trail;
    std::vector<std::int32_t> m_depth;
    std::vector<std::int32_t> m_infinite_slot;  // per light: its place in m_infinite, or -1
};

}  // namespace facet::render
