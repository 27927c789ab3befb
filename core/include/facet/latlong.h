// The latitude-longitude (equirectangular) parametrisation of the sphere of directions and a
// piecewise-constant importance density over it: the renderer-independent part of sampling an
// environment map, shared by the standalone renderer's environment light
// (facet/render/environment_map.h) and the POV-Ray bridge's sky_sphere sampling
// (povray_patch/bridge), so that both use one implementation.
//
// Conventions:
//  - A direction l is given in the map's own frame (callers rotate world directions into it).
//    Its (u, v) in [0, 1]^2 is
//        u = 0.5 - atan2(l.y, l.x) / (2 pi)  (from the image's LEFT edge),
//        v = theta / pi, theta = angle from +Z (from the image's TOP row),
//    Blender's Environment Texture with Z up; inversely, with phi = pi - 2 pi u, theta = pi v:
//        l = (sin theta cos phi, sin theta sin phi, cos theta).
//  - Solid angle: d omega = 2 pi^2 sin theta du dv.
//  - LatLongDistribution (pbrt-v4's ImageInfiniteLight, Pharr, Jakob & Humphreys 4th ed.
//    §12.5.2): W x H cells over (u, v), cell (x, y) covering [x/W, (x+1)/W] x [y/H, (y+1)/H],
//    given a non-negative weight Y(x, y) (a luminance). The density uses
//        w(x, y) = Y(x, y) * sin(theta_y),  theta_y = pi (y + 0.5) / H   (the Jacobian),
//    sampled as the marginal over rows, then the conditional within the row; per (u, v)
//        p(u, v) = W H w(x, y) / sum w,
//    and per solid angle pdf = p(u, v) / (2 pi^2 sin theta), 0 at the poles. sample() and
//    pdf() agree exactly up to float round-off at cell edges.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "facet/types.h"

namespace facet {

// (u, v) of a unit direction in the map's frame, clamped into [0, 1] (a NaN direction gives 0);
// the second form also gives sin theta = sqrt(l.x^2 + l.y^2). The angles come from
// atan2_approx: within 2.5e-7 of the exact (u, v) (tests/render/test_environment_map.cpp).
Vec2 latlong_uv(const Vec3& l);
Vec2 latlong_uv(const Vec3& l, float& sin_theta);
// The unit direction (map frame) of (u, v); the second form also gives sin theta = sin(pi v).
Vec3 latlong_direction(Vec2 uv);
Vec3 latlong_direction(Vec2 uv, float& sin_theta);
// atan2(y, x) in (-pi, pi] within 3e-7 rad (a polynomial: Abramowitz & Stegun 4.4.49), with
// std::atan2's signs and atan2(0, 0) = 0; NaN in, NaN out.
float atan2_approx(float y, float x);

class LatLongDistribution {
  public:
    LatLongDistribution() = default;
    // `luminance`: W * H non-negative weights, row-major from the top row (y = 0).
    LatLongDistribution(int width, int height, const std::vector<double>& luminance);

    int width() const { return m_width; }
    int height() const { return m_height; }
    // Every weight is 0 (or the sum is not finite): sample() fails, pdf() is 0.
    bool black() const { return m_black; }

    struct Sample {
        Vec2 uv{0.f};
        float pdf = 0.f;  // per solid angle; 0 (discard) when black or on a pole
    };
    // (u, v) by the density from u in [0, 1)^2.
    Sample sample(Vec2 u) const;
    // The cell that sample(u) lands in and where in it: uv = ((x + offset.x) / W,
    // (y + offset.y) / H) with the offset in [0, 1)^2, uniform within the cell given the cell
    // (for a caller that places the sample within the cell by a density of its own).
    struct Cell {
        int x = 0, y = 0;
        Vec2 offset{0.f};
    };
    Cell sample_cell(Vec2 u) const;
    // W H / sum w: the cell density is p = scale() * w(x, y) (0 when black).
    double scale() const { return m_scale; }
    // Solid-angle density of the direction with coordinates uv.
    float pdf(Vec2 uv) const;

  private:
    float cell_pdf(int x, int y) const { return m_cell_pdf[std::size_t(y) * m_width + x]; }

    int m_width = 0, m_height = 0;
    // m_row_cdf[y] = sum of the row weights up to and including row y over the total
    // (m_row_cdf[H - 1] = 1); m_col_cdf[y * W + x] likewise within row y; m_cell_pdf the cell
    // density p(u, v).
    std::vector<float> m_row_cdf, m_col_cdf, m_cell_pdf;
    // Cutpoint tables of the cdfs (facet/cdf_search.h): H entries, and W per row.
    std::vector<std::uint32_t> m_row_guide, m_col_guide;
    double m_scale = 0.0;
    bool m_black = true;
};

}  // namespace facet
