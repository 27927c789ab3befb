// An environment map: radiance arriving from every direction, read from an equirectangular
// (latitude-longitude) image, and its importance sampling.
//
// Conventions:
//  - Mapping (Blender's Environment Texture, equirectangular, Z up; checked in Blender 3.4).
//    A direction d is first taken into the map's frame, l = M^T d (M below), then
//        u = 0.5 - atan2(l.y, l.x) / (2 pi)   in [0, 1], from the image's LEFT edge,
//        v = acos(l.z) / pi                   in [0, 1], from the image's TOP row,
//    so the centre column looks toward +X, u = 0.25 toward +Y, u = 0.75 toward -Y, the seam
//    (u = 0 and 1) toward -X, the top row straight up (+Z) and the middle row the horizon.
//    Inversely, with phi = pi - 2 pi u and theta = pi v: l = (sin theta cos phi,
//    sin theta sin phi, cos theta).
//  - Orientation M (world = M l, a rotation): M = R_rotate * R_up. R_up is the smallest rotation
//    taking +Z to the unit `up` (the identity for up = +Z; a half turn about X for up = -Z),
//    R_rotate the right-handed rotation by `angle` about `axis` (counter-clockwise seen from the
//    axis' tip, as a shape's "rotate"), applied in world space after R_up. Blender's Mapping
//    node rotating the lookup vector by a corresponds to angle -a.
//  - Texel lookup: bilinear (Blender's default "Linear" interpolation), texel (x, y) centred at
//    ((x + 0.5) / W, (y + 0.5) / H); wrapping around in u (the seam is continuous), clamped to
//    the first and last row in v. Radiance = multiplier * lookup (RGB; a grey image is grey,
//    alpha is ignored).
//  - Importance sampling: a density proportional to the luminance Y of the bilinear lookup
//    itself (Rec. 709 of the texels as stored, multiplier included), per (u, v)
//        p(u, v) = Y(u, v) sin(theta_y) W H / sum w,   theta_y = pi (y + 0.5) / H,
//    y the texel row of v, and per solid angle (d omega = 2 pi^2 sin theta du dv)
//        pdf(d) = p(u, v) / (2 pi^2 sin theta),
//    0 at the poles (sin theta = 0) and wherever the lookup is black. Sampling takes two steps:
//     1. the texel's cell by facet::LatLongDistribution (facet/latlong.h, shared with the
//        POV-Ray bridge), one cell per texel with weight w(x, y) = Ybar(x, y) sin(theta_y),
//        Ybar the mean of Y over the cell (the 3x3 neighbourhood weighted by the tent-filter
//        cell means [1/8, 3/4, 1/8] in each axis); full resolution, no coarser table;
//     2. the point within the cell by Y: the cell's four quadrants (split at the texel's
//        centre) are each bilinear between Y at the cell's corners, edge midpoints and centre,
//        so a quadrant is chosen by its mean and the point within it by the bilinear density
//        (marginal in v, then u given v; both linear), from the cell's uniform offset, which
//        keeps the sample stratified.
//    For a grey map every light sample then carries the same weight L / pdf up to
//    sin theta / sin theta_y; a density constant over each cell (step 1 alone) varies by the
//    lookup's range within the cell, tens of times beside a one-texel sun. sample() and pdf()
//    agree up to float round-off.
#pragma once

#include <memory>
#include <vector>

#include "facet/latlong.h"
#include "facet/types.h"

namespace facet::render {

struct TexelImage;

class EnvironmentMap {
  public:
    // `image` as read by load_texel_image (row 0 at the top, >= 1 channel, validated finite and
    // non-negative); `multiplier` >= 0 per channel; `frame` = M (columns: the map's X, Y, Z
    // axes in world space, orthonormal, right-handed).
    EnvironmentMap(const TexelImage& image, const Rgb& multiplier, const glm::mat3& frame);

    int width() const { return m_width; }
    int height() const { return m_height; }

    // Radiance arriving along world direction d (unit), i.e. seen when looking toward d.
    Rgb eval(const Vec3& d) const;
    // Solid-angle density with which sample() returns the unit world direction d.
    float pdf(const Vec3& d) const;
    // eval(d), and pdf(d) in `pdf`, from one (u, v) and one lookup (an escaping ray's MIS).
    Rgb eval_pdf(const Vec3& d, float& pdf) const;
    struct Sample {
        Vec3 wi{0.f};  // unit, world space
        float pdf = 0.f;
        Rgb radiance{0.f};
    };
    // Direction by the importance density from u in [0, 1)^2; pdf 0 (to be discarded) when the
    // map is black or the sample lands on a pole.
    Sample sample(Vec2 u) const;
    // Radiance averaged over the sphere: (1 / 4 pi) * integral of eval over all directions,
    // per texel (the bilinear lookup's cell means weighted by the cells' solid angles).
    Rgb mean_radiance() const { return m_mean; }

    // (u, v) of a world direction and back (see conventions); exposed for tests and exporters.
    Vec2 direction_to_uv(const Vec3& d) const;
    Vec3 uv_to_direction(Vec2 uv) const;

  private:
    Rgb texel(int x, int y) const { return m_texels[std::size_t(y) * m_width + x]; }
    Rgb lookup(Vec2 uv) const;  // bilinear, without the multiplier
    // The density at (u, v) whose lookup is `radiance`, sin_theta = sin(pi v) (the same pdf for
    // sample() and pdf()).
    float pdf_at(Vec2 uv, const Rgb& radiance, float sin_theta) const;

    int m_width = 0, m_height = 0;
    std::vector<Rgb> m_texels;       // RGB per texel, multiplier applied
    std::vector<float> m_luminance;  // the texels' luminances (sample(): the point in a cell)
    glm::mat3 m_frame{1.f};          // M: map -> world
    glm::mat3 m_inverse{1.f};        // M^T: world -> map
    Rgb m_mean{0.f};
    LatLongDistribution m_distribution;  // the cells' choice (their mean luminances)
    std::vector<float> m_row_factor;     // sin(theta_y) W H / sum w per row
};

}  // namespace facet::render
