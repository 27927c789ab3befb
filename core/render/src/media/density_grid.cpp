// DensityGrid's majorant grid (facet/render/density_grid.h).
#include "facet/render/density_grid.h"

namespace facet::render {

DensityGrid::DensityGrid(std::array<int, 3> res, const Vec3& lo, const Vec3& hi,
                         std::vector<float> values)
    : m_res(res), m_lo(lo), m_hi(hi), m_values(std::move(values)) {
    for (int a = 0; a < 3; ++a) {
        const std::size_t s = std::size_t(a);
        m_inv_h[a] = float(m_res[s]) / (m_hi[a] - m_lo[a]);
        m_cells[s] = (m_res[s] + kMajorantVoxels - 1) / kMajorantVoxels;
        m_inv_cell[a] = m_inv_h[a] / float(kMajorantVoxels);
    }
    m_majorant.assign(std::size_t(m_cells[0]) * std::size_t(m_cells[1]) * std::size_t(m_cells[2]),
                      0.f);
    for (float v : m_values) m_max = std::max(m_max, v);
    // A cell's interpolant mixes the voxels of its own range and one more on each side.
    for (int ck = 0; ck < m_cells[2]; ++ck)
        for (int cj = 0; cj < m_cells[1]; ++cj)
            for (int ci = 0; ci < m_cells[0]; ++ci) {
                const std::array<int, 3> c{ci, cj, ck};
                std::array<int, 3> b, e;
                for (std::size_t a = 0; a < 3; ++a) {
                    b[a] = std::max(c[a] * kMajorantVoxels - 1, 0);
                    e[a] = std::min((c[a] + 1) * kMajorantVoxels + 1, m_res[a]);
                }
                float m = 0.f;
                for (int k = b[2]; k < e[2]; ++k)
                    for (int j = b[1]; j < e[1]; ++j)
                        for (int i = b[0]; i < e[0]; ++i) m = std::max(m, voxel(i, j, k));
                m_majorant[(std::size_t(ck) * std::size_t(m_cells[1]) + std::size_t(cj)) *
                               std::size_t(m_cells[0]) +
                           std::size_t(ci)] = m;
            }
}

}  // namespace facet::render
