// A dense voxel grid of density over an axis-aligned box, with the majorant grid that delta and
// ratio tracking step through (pbrt-v4's MajorantGrid and DDAMajorantIterator, §11.4).
//
// Conventions:
//  - Voxel (i, j, k) of a grid of resolution n = (nx, ny, nz) covers the box
//    [lo + (i, j, k) h, lo + (i + 1, j + 1, k + 1) h] of the world, h = (hi - lo) / n, and holds
//    the density at its centre (OpenVDB's convention: values at voxel centres). density(p)
//    interpolates the centres trilinearly, clamped to the outermost centres inside the box, and
//    is 0 outside [lo, hi].
//  - The majorant grid has one cell per kMajorantVoxels^3 voxels; a cell holds the largest value
//    the trilinear interpolant takes in it (the maximum over the voxels whose centres it mixes,
//    one voxel beyond the cell on each side), so it bounds density() everywhere in the cell.
//  - march(o, d, t_max, fn) calls fn(t0, t1, majorant) for the consecutive pieces [t0, t1) of the
//    ray o + t d (d need not be unit length; t is the ray's parameter) inside the box and before
//    t_max, one per majorant cell, front to back; fn returns false to stop.
//  - The box is in the grid's own space; set_world_to_grid() places it in the world with an
//    affine map (a rotated or scaled volume object). density() and march() take world points
//    and directions and map them; t stays the world ray's parameter, so distances sampled along
//    a unit world direction are world distances whatever the map's scale.
//  - Memory: 4 bytes per voxel plus 4 per majorant cell (memory_bytes()).
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "facet/types.h"

namespace facet::render {

class DensityGrid {
  public:
    static constexpr int kMajorantVoxels = 8;

    // values.size() == nx * ny * nz, x fastest; every value finite and >= 0; lo < hi (the
    // builder checks and names the file).
    DensityGrid(std::array<int, 3> res, const Vec3& lo, const Vec3& hi, std::vector<float> values);

    // The affine map from world to grid space: p_grid = linear p + offset.
    void set_world_to_grid(const glm::mat3& linear, const Vec3& offset) {
        m_w2g = linear;
        m_w2g_offset = offset;
        m_has_map = true;
    }

    const std::array<int, 3>& resolution() const { return m_res; }
    const Vec3& lo() const { return m_lo; }
    const Vec3& hi() const { return m_hi; }
    float max_value() const { return m_max; }
    std::size_t memory_bytes() const {
        return (m_values.size() + m_majorant.size()) * sizeof(float);
    }

    float voxel(int i, int j, int k) const {
        return m_values[(std::size_t(k) * std::size_t(m_res[1]) + std::size_t(j)) *
                            std::size_t(m_res[0]) +
                        std::size_t(i)];
    }

    // The trilinearly interpolated density at world point p (0 outside the box).
    float density(const Vec3& world) const {
        return density_in_grid(m_has_map ? m_w2g * world + m_w2g_offset : world);
    }
    float density_in_grid(const Vec3& p) const {
        if (!(p.x >= m_lo.x && p.y >= m_lo.y && p.z >= m_lo.z && p.x <= m_hi.x && p.y <= m_hi.y &&
              p.z <= m_hi.z))
            return 0.f;
        std::array<int, 3> i0, i1;
        std::array<float, 3> f;
        for (int a = 0; a < 3; ++a) {
            const float q = (p[a] - m_lo[a]) * m_inv_h[a] - 0.5f;
            const float fl = std::floor(q);
            f[std::size_t(a)] = q - fl;
            const int n = m_res[std::size_t(a)];
            const int b = int(fl);
            i0[std::size_t(a)] = std::clamp(b, 0, n - 1);
            i1[std::size_t(a)] = std::clamp(b + 1, 0, n - 1);
        }
        auto lerp = [](float a, float b, float t) { return a + (b - a) * t; };
        const float c00 = lerp(voxel(i0[0], i0[1], i0[2]), voxel(i1[0], i0[1], i0[2]), f[0]);
        const float c10 = lerp(voxel(i0[0], i1[1], i0[2]), voxel(i1[0], i1[1], i0[2]), f[0]);
        const float c01 = lerp(voxel(i0[0], i0[1], i1[2]), voxel(i1[0], i0[1], i1[2]), f[0]);
        const float c11 = lerp(voxel(i0[0], i1[1], i1[2]), voxel(i1[0], i1[1], i1[2]), f[0]);
        return lerp(lerp(c00, c10, f[1]), lerp(c01, c11, f[1]), f[2]);
    }

    // The majorant pieces of the ray o + t d, t in [0, t_max) (see the conventions).
    template <class Fn>
    void march(const Vec3& world_o, const Vec3& world_d, float t_max, Fn&& fn) const {
        const Vec3 o = m_has_map ? m_w2g * world_o + m_w2g_offset : world_o;
        const Vec3 d = m_has_map ? m_w2g * world_d : world_d;
        float t0 = 0.f, t1 = t_max;
        for (int a = 0; a < 3; ++a) {  // slab test against the box
            const float inv = 1.f / d[a];
            float ta = (m_lo[a] - o[a]) * inv, tb = (m_hi[a] - o[a]) * inv;
            if (ta > tb) std::swap(ta, tb);
            if (std::isnan(ta) || std::isnan(tb)) {  // d[a] == 0 with o[a] on a slab plane
                if (o[a] < m_lo[a] || o[a] > m_hi[a]) return;
                continue;
            }
            t0 = std::max(t0, ta);
            t1 = std::min(t1, tb);
        }
        if (!(t0 < t1)) return;
        // 3-D DDA over the majorant cells from the entry point (Amanatides & Woo 1987).
        const Vec3 entry = o + d * t0;
        std::array<int, 3> cell, step, last;
        std::array<float, 3> t_next, t_delta;
        for (int a = 0; a < 3; ++a) {
            const std::size_t s = std::size_t(a);
            const float c = (entry[a] - m_lo[a]) * m_inv_cell[a];
            cell[s] = std::clamp(int(std::floor(c)), 0, m_cells[s] - 1);
            if (d[a] > 0.f) {
                step[s] = 1;
                last[s] = m_cells[s];
                t_next[s] = t0 + ((float(cell[s] + 1) / m_inv_cell[a] + m_lo[a]) - entry[a]) / d[a];
                t_delta[s] = 1.f / (m_inv_cell[a] * d[a]);
            } else if (d[a] < 0.f) {
                step[s] = -1;
                last[s] = -1;
                t_next[s] = t0 + ((float(cell[s]) / m_inv_cell[a] + m_lo[a]) - entry[a]) / d[a];
                t_delta[s] = -1.f / (m_inv_cell[a] * d[a]);
            } else {
                step[s] = 0;
                last[s] = -2;
                t_next[s] = INFINITY;
                t_delta[s] = INFINITY;
            }
        }
        float t = t0;
        while (t < t1) {
            const int a = t_next[0] < t_next[1] ? (t_next[0] < t_next[2] ? 0 : 2)
                                                : (t_next[1] < t_next[2] ? 1 : 2);
            const std::size_t s = std::size_t(a);
            const float t_end = std::min(t_next[s], t1);
            const float maj =
                m_majorant[(std::size_t(cell[2]) * std::size_t(m_cells[1]) + std::size_t(cell[1])) *
                               std::size_t(m_cells[0]) +
                           std::size_t(cell[0])];
            if (t_end > t && !fn(t, t_end, maj)) return;
            t = t_end;
            cell[s] += step[s];
            if (cell[s] == last[s]) return;
            t_next[s] += t_delta[s];
        }
    }

  private:
    std::array<int, 3> m_res, m_cells;
    Vec3 m_lo, m_hi, m_inv_h, m_inv_cell;
    std::vector<float> m_values, m_majorant;
    float m_max = 0.f;
    glm::mat3 m_w2g{1.f};
    Vec3 m_w2g_offset{0.f};
    bool m_has_map = false;
};

}  // namespace facet::render
