// Blender 3.4's Sky Texture of type Nishita (Cycles 3.4): radiance arriving from every direction
// of a clear sky by single scattering in the Earth's atmosphere, with the sun's disc. The light
// kind "sky_nishita" (core/render/src/lights/sky_nishita.cpp, where the model's math is
// documented) builds one; this is its evaluation and importance sampling.
//
// Conventions:
//  - Directions: a world direction d is first taken into the sky's frame, l = M^T d (M a
//    rotation, as an environment map's: environment_map.h); the sky's zenith is +Z of that
//    frame. Cycles' spherical coordinates of l: theta = acos(l.z), phi = atan2(l.x, l.y).
//  - Units: radiance in Facet's units = Cycles' Background radiance for a Sky Texture feeding a
//    Background of strength 1, times the multiplier (the Background's Strength).
//  - eval(d) is Cycles' kernel value (sky_radiance_nishita) exactly as Cycles 3.4 computes it:
//    the sky from a precomputed 512 x 128 XYZ table (bilinear, clamped), the sun's disc
//    analytically, converted from XYZ to linear Rec. 709 RGB and clamped at 0.
//  - Importance sampling: a mixture of (1 - p_sun) times a piecewise-constant density over a
//    latitude-longitude grid of the sky's frame (facet/latlong.h; cell weights conservative:
//    the largest luminance of 9 points of the cell, so every direction with radiance has a
//    non-zero density) and p_sun times the uniform density over the sun's cone.
#pragma once

#include <memory>
#include <vector>

#include "facet/latlong.h"
#include "facet/types.h"

namespace facet::render {

// The Sky Texture's parameters in the scene format's units (degrees, metres); validated by the
// kind's builder (lights/sky_nishita.cpp).
struct SkyNishitaParams {
    bool sun_disc = true;
    double sun_size = 0.545;      // full angular diameter, degrees (Cycles: at least 0.0005 rad)
    double sun_intensity = 1.0;   // multiplies the sun's disc
    double sun_elevation = 15.0;  // degrees above the horizon
    double sun_rotation = 0.0;    // degrees about +Z
    double altitude = 0.0;        // metres (Cycles clamps to [1, 59999])
    double air_density = 1.0, dust_density = 1.0, ozone_density = 1.0;
    bool operator==(const SkyNishitaParams&) const = default;
};

class SkyNishita {
  public:
    // Precomputes the table and the sampling density (build_seconds() says how long it took).
    // `multiplier` >= 0 per channel; `frame` = M (orthonormal, right-handed).
    SkyNishita(const SkyNishitaParams& p, const Rgb& multiplier, const glm::mat3& frame);
    // The sky of these arguments, built once: the last one built is kept (process-wide, thread
    // safe), so that rebuilding a scene with an unchanged sky (Blender's viewport rebuilds the
    // scene on every edit) does not precompute it again.
    static std::shared_ptr<const SkyNishita> shared(const SkyNishitaParams& p,
                                                    const Rgb& multiplier, const glm::mat3& frame);

    // Radiance arriving along the unit world direction d.
    Rgb eval(const Vec3& d) const;
    // Solid-angle density with which sample() returns the unit world direction d.
    float pdf(const Vec3& d) const;
    struct Sample {
        Vec3 wi{0.f};
        float pdf = 0.f;  // 0: discard
        Rgb radiance{0.f};
    };
    Sample sample(Vec2 u) const;
    // Radiance averaged over the sphere (the sky's table mean plus the sun's share).
    Rgb mean_radiance() const { return m_mean; }
    // The sun's share of the samples (0 without a visible sun).
    double sun_probability() const { return m_p_sun; }
    double build_seconds() const { return m_build_seconds; }
    const SkyNishitaParams& params() const { return m_params; }

    // Cycles' sky in its own frame (l = M^T d), without the multiplier: the table part and the
    // sun's disc (for tests).
    Rgb eval_local(const glm::dvec3& l) const;
    // The sun's centre direction in the sky's frame, and its radiance at the disc's centre
    // (limb darkening 1), without the multiplier (for tests).
    glm::dvec3 sun_direction() const { return m_sun_dir; }
    Rgb sun_centre_radiance() const;

    static constexpr int kTableWidth = 512, kTableHeight = 128;  // Cycles' SkyLoader
    static constexpr int kPdfWidth = 512, kPdfHeight = 256;      // sampling grid

  private:
    Rgb table_lookup(double x, double y) const;  // Cycles' linear, clamped lookup
    Rgb sky_only(const glm::dvec3& l) const;     // eval_local without the sun's disc

    SkyNishitaParams m_params;
    std::vector<Rgb> m_table;  // RGB (unclamped) of Cycles' XYZ table, row 0 at the horizon
    Rgb m_sun_bottom{0.f}, m_sun_top{0.f};  // RGB of Cycles' two sun pixels
    double m_sun_elevation = 0.0, m_rotation = 0.0, m_angular = -1.0, m_sun_intensity = 1.0;
    glm::dvec3 m_sun_dir{0.0, 0.0, 1.0};
    double m_sun_omc = 0.0;  // 1 - cos(half angle)
    double m_p_sun = 0.0;
    Rgb m_multiplier{1.f};
    glm::mat3 m_frame{1.f}, m_inverse{1.f};
    Rgb m_mean{0.f};
    LatLongDistribution m_sky;
    double m_build_seconds = 0.0;
};

}  // namespace facet::render
