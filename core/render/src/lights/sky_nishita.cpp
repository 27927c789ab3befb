// Light kind "sky_nishita": Blender 3.4's Sky Texture of type Nishita as the scene's environment
// (at most one environment per scene), reproducing Cycles 3.4 (intern/sky's
// sky_nishita.cpp, scene/shader_nodes.cpp's SkyTextureNode, kernel/svm/sky.h); its light type
// and its model (facet/render/sky_nishita.h).
//
// The model (Nishita et al. 1993, as Blender implements it):
//  - An atmosphere between the radii 6360 km (the ground) and 6420 km, the viewer at
//    `altitude` above the ground. Rayleigh scattering (density exp(-h / 8 km) times
//    `air_density`, a per-wavelength coefficient), Mie scattering by aerosols
//    (exp(-h / 1.2 km) times `dust_density`, 2e-5 m^-1, extinction 1.11 times scattering,
//    Cornette-Shanks phase with g = 0.76) and ozone absorption (a tent from 10 to 40 km peaking
//    at 25 km, times `ozone_density`).
//  - Single scattering along the view ray to the top of the atmosphere in 32 equal segments,
//    evaluated at their midpoints: the sun's extraterrestrial spectral irradiance, attenuated
//    from the top of the atmosphere to the segment (optical depth by an 8-node Gauss-Laguerre
//    rule, Blender's nodes) and from the segment to the viewer, times the density, the
//    scattering coefficient and the phase function. Segments in the Earth's shadow get none.
//  - 21 wavelengths from 380 to 780 nm, integrated against the CIE 1931 colour matching
//    functions (20 nm steps) to XYZ, then to linear Rec. 709 RGB by the D65 matrix (measured:
//    Cycles 3.4's colours of the sky seen in 30 directions agree with this matrix to 1.5%, and
//    the differences are grey, i.e. from the table lookup; another matrix would tint them).
//  - Cycles tabulates the sky (without the sun) in a 512 x 128 table over (longitude, elevation)
//    in the sun's frame: row j at elevation (pi/2 + pi/512) (j / 128)^2 (more rows near the
//    horizon), column i at longitude 2 pi i / 512 - pi, the sun at longitude 0; it looks the
//    table up bilinearly, clamped at the edges, at x = (phi + pi + rho) / 2 pi (minus 1 above
//    1) and y = sqrt(elevation / (pi / 2)), where phi = atan2(l.x, l.y) and rho = 2 pi minus
//    the sun's rotation (in [0, 2 pi)). Facet builds the same table and looks it up the same
//    way, so that it shows the sky Cycles shows, half-texel offsets included.
//  - Below the horizon (l.z < 0): the table's horizon row at the direction's longitude, times
//    (1 + 2.5 l.z)^3, and black below l.z = -0.4 (Cycles' "black ground fade").
//  - The sun's disc (`sun_disc`): directions within half the angular diameter (`sun_size`,
//    at least 0.0005 rad as in Cycles) of the sun replace the sky by the sun's radiance: the
//    extraterrestrial irradiance over the disc's solid angle, attenuated by Rayleigh and Mie
//    extinction (no ozone, as Blender) along the ray toward the disc's bottom and its top
//    (elevations clamped at 0), interpolated linearly in elevation between the two, times
//    `sun_intensity` and the limb darkening 1 - 0.6 (1 - sqrt(1 - (angle / half)^2)).
//  - RGB is clamped at 0 after the lookup, as Cycles' xyz_to_rgb_clamped.
//
// Sampling (light.h conventions, the density in facet/render/sky_nishita.h): with probability
// p_sun the sun's cone (uniform), otherwise the sky's latitude-longitude density; pdf_li is the
// mixture's density, so BSDF rays that hit the sun or the sky are weighed by MIS. p_sun is the
// sun's share of the irradiance (the disc's mean radiance, 0.8 of its centre's with the limb
// darkening, times its solid angle, against 4 pi times the sky's mean), kept in [0.1, 0.9] so
// that neither part starves (the sky still lights what the sun's shadow hides). Its power for
// the light choice is that of its mean radiance, as an environment map's. Measured on
// blender.cycles_sky's lit scene (8 x 8 block RMSE between two seeds over Cycles' own): the
// mixture 0.81x Cycles' noise (p_sun 0.82; a fixed 0.5: 1.00x); the sun left in the sky's
// 512 x 256 density instead (cells weighted by their exact mean radiance, no cone): 9.7x. A
// separate distant light would sample as the mixture does, but rays could not hit it (Facet's
// distant lights are not in the traced scene), and camera and mirror rays must see the disc.
//
// Build cost: the table is 256 x 128 single-scattering integrals (the other half is the mirror
// image), each 32 segments of an 8-node optical depth and 21 wavelengths, plus 512 x 256 x 9
// lookups for the density; measured in SkyNishita.BuildTime (build_seconds()).
#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <mutex>
#include <thread>

#include "../io/pov_writer.h"
#include "../kind_build.h"
#include "facet/render/light.h"
#include "facet/render/sky_nishita.h"
#include "sampling.h"

namespace facet::render {

namespace {

// --- the atmosphere (data as in Blender's intern/sky) ------------------------------------------

constexpr int kWavelengths = 21;                            // 380, 400, ..., 780 nm
constexpr float kLambdaStep = 20.f;                         // nm
constexpr float kRayleighScale = 8e3f, kMieScale = 1.2e3f;  // scale heights (m)
constexpr float kMieScattering = 2e-5f;                     // m^-1
constexpr float kMieExtinctionRatio = 1.11f;                // extinction / scattering
constexpr float kMieG = 0.76f;
constexpr float kEarthRadius = 6360e3f, kAtmosphereRadius = 6420e3f;  // m
constexpr int kSegments = 32;

// The sun's spectral irradiance at the top of the atmosphere (W m^-2 nm^-1).
constexpr float kSolarIrradiance[kWavelengths] = {
    1.45756829855592995315f, 1.56596305559738380175f, 1.65148449067670455293f,
    1.71496242737209314555f, 1.75797983805020541226f, 1.78256407885924539336f,
    1.79095108475838560302f, 1.78541550133410664714f, 1.76815554864306845317f,
    1.74122069647250410362f, 1.70647127164943679389f, 1.66556087452739887134f,
    1.61993437242451854274f, 1.57083597368892080581f, 1.51932335059305478886f,
    1.46628494965214395407f, 1.41245852740172450623f, 1.35844961970384092709f,
    1.30474913844739281998f, 1.25174963272610817455f, 1.19975998755420620867f};
// Rayleigh scattering coefficient at sea level (m^-1).
constexpr float kRayleigh[kWavelengths] = {
    0.00005424820087636473f, 0.00004418549866505454f, 0.00003635151910165377f,
    0.00003017929012024763f, 0.00002526320226989157f, 0.00002130859310621843f,
    0.00001809838025320633f, 0.00001547057129129042f, 0.00001330284977336850f,
    0.00001150184784075764f, 0.00000999557429990163f, 0.00000872799973630707f,
    0.00000765513700977967f, 0.00000674217203751443f, 0.00000596134125832052f,
    0.00000529034598065810f, 0.00000471115687557433f, 0.00000420910481110487f,
    0.00000377218381260133f, 0.00000339051255477280f, 0.00000305591531679811f};
// Ozone absorption coefficient at the layer's peak (m^-1).
constexpr float kOzone[kWavelengths] = {
    0.00000000325126849861f, 0.00000000585395365047f, 0.00000001977191155085f,
    0.00000007309568762914f, 0.00000020084561514287f, 0.00000040383958096161f,
    0.00000063551335912363f, 0.00000096707041180970f, 0.00000154797400424410f,
    0.00000209038647223331f, 0.00000246128056164565f, 0.00000273551299461512f,
    0.00000215125863128643f, 0.00000159051840791988f, 0.00000112356197979857f,
    0.00000073527551487574f, 0.00000046450130357806f, 0.00000033096079921048f,
    0.00000022512612292678f, 0.00000014879129266490f, 0.00000016828623364192f};
// CIE 1931 2-degree colour matching functions x, y, z at the same wavelengths.
constexpr float kCmf[kWavelengths][3] = {{0.00136800000f, 0.00003900000f, 0.00645000100f},
                                         {0.01431000000f, 0.00039600000f, 0.06785001000f},
                                         {0.13438000000f, 0.00400000000f, 0.64560000000f},
                                         {0.34828000000f, 0.02300000000f, 1.74706000000f},
                                         {0.29080000000f, 0.06000000000f, 1.66920000000f},
                                         {0.09564000000f, 0.13902000000f, 0.81295010000f},
                                         {0.00490000000f, 0.32300000000f, 0.27200000000f},
                                         {0.06327000000f, 0.71000000000f, 0.07824999000f},
                                         {0.29040000000f, 0.95400000000f, 0.02030000000f},
                                         {0.59450000000f, 0.99500000000f, 0.00390000000f},
                                         {0.91630000000f, 0.87000000000f, 0.00165000100f},
                                         {1.06220000000f, 0.63100000000f, 0.00080000000f},
                                         {0.85444990000f, 0.38100000000f, 0.00019000000f},
                                         {0.44790000000f, 0.17500000000f, 0.00002000000f},
                                         {0.16490000000f, 0.06100000000f, 0.00000000000f},
                                         {0.04677000000f, 0.01700000000f, 0.00000000000f},
                                         {0.01135916000f, 0.00410200000f, 0.00000000000f},
                                         {0.00289932700f, 0.00104700000f, 0.00000000000f},
                                         {0.00069007860f, 0.00024920000f, 0.00000000000f},
                                         {0.00016615050f, 0.00006000000f, 0.00000000000f},
                                         {0.00004150994f, 0.00001499000f, 0.00000000000f}};
// Optical depth along a ray to the top of the atmosphere: 8-node Gauss-Laguerre nodes scaled
// so that the last one lies inside the ray (x_i / 25), with the exp(x_i) factor folded into
// the weights (Blender's values).
constexpr int kQuadrature = 8;
constexpr float kQuadNodes[kQuadrature] = {0.006811185292f, 0.03614807107f, 0.09004346519f,
                                           0.1706680068f,   0.2818362161f,  0.4303406404f,
                                           0.6296271457f,   0.9145252695f};
constexpr float kQuadWeights[kQuadrature] = {0.01750893642f, 0.04135477391f, 0.06678839063f,
                                             0.09507698807f, 0.1283416365f,  0.1707430204f,
                                             0.2327233347f,  0.3562490486f};

// XYZ -> linear Rec. 709 RGB (D65): Cycles' conversion under Blender 3.4's colour management.
constexpr double kXyzToRgb[3][3] = {{3.2404542, -1.5371385, -0.4985314},
                                    {-0.9692660, 1.8760108, 0.0415560},
                                    {0.0556434, -0.2040259, 1.0572252}};

// Cycles' limb darkening coefficient of the sun's disc, and its mean over the disc's area:
// 1 - 0.6 (1 - int_0^1 sqrt(1 - r^2) 2r dr) = 1 - 0.6 / 3.
constexpr double kLimb = 0.6, kLimbMean = 1.0 - kLimb / 3.0;

// Cycles' lower bound on the sun's angular diameter (SkyTextureNode::get_sun_size), radians.
constexpr double kMinSunSize = 0.0005;

// The share of samples the sun gets is kept in [kMinShare, 1 - kMinShare] (see the top).
constexpr double kMinShare = 0.1;

Rgb xyz_to_rgb(const glm::vec3& xyz) {
    Rgb c;
    for (int i = 0; i < 3; ++i)
        c[i] = float(kXyzToRgb[i][0] * xyz.x + kXyzToRgb[i][1] * xyz.y + kXyzToRgb[i][2] * xyz.z);
    return c;
}

float luminance(const Rgb& c) {
    return 0.2126f * c.x + 0.7152f * c.y + 0.0722f * c.z;
}

glm::vec3 geographic(float latitude, float longitude) {
    return {std::cos(latitude) * std::cos(longitude), std::cos(latitude) * std::sin(longitude),
            std::sin(latitude)};
}

// Density factors (Rayleigh, Mie, ozone) at height h above the ground (m).
glm::vec3 densities(float h) {
    float ozone = 0.f;
    if (h >= 10000.f && h < 25000.f)
        ozone = h / 15000.f - 2.f / 3.f;
    else if (h >= 25000.f && h < 40000.f)
        ozone = 8.f / 3.f - h / 15000.f;
    return {std::exp(-h / kRayleighScale), std::exp(-h / kMieScale), ozone};
}

// Distance from p (inside the atmosphere) along the unit d to the atmosphere's top.
float to_atmosphere_top(const glm::vec3& p, const glm::vec3& d) {
    const float b = glm::dot(d, p);
    const float c = glm::dot(p, p) - kAtmosphereRadius * kAtmosphereRadius;
    return -b + std::sqrt(b * b - c);
}

// Whether the ray from p along the unit d meets the ground (Cycles' test: only rays going
// down in z).
bool meets_ground(const glm::vec3& p, const glm::vec3& d) {
    if (d.z >= 0.f) return false;
    const float b = glm::dot(d, p);
    return b * b - (glm::dot(p, p) - kEarthRadius * kEarthRadius) >= 0.f;
}

// Optical depth factors (Rayleigh, Mie, ozone; times the densities' coefficients they give the
// optical depth) from p along d to the top of the atmosphere.
glm::vec3 optical_depth(const glm::vec3& p, const glm::vec3& d) {
    const float length = to_atmosphere_top(p, d);
    glm::vec3 sum(0.f);
    for (int i = 0; i < kQuadrature; ++i) {
        const glm::vec3 q = p + (kQuadNodes[i] * length) * d;
        sum += densities(glm::length(q) - kEarthRadius) * kQuadWeights[i];
    }
    return sum * length;
}

float phase_rayleigh(float mu) {
    return 3.f / (16.f * kPi) * (1.f + mu * mu);
}
float phase_mie(float mu) {
    const float g2 = kMieG * kMieG;
    return 3.f * (1.f - g2) * (1.f + mu * mu) /
           (8.f * kPi * (2.f + g2) * std::pow(1.f + g2 - 2.f * kMieG * mu, 1.5f));
}

glm::vec3 spectrum_to_xyz(const float* spectrum) {
    glm::vec3 xyz(0.f);
    for (int i = 0; i < kWavelengths; ++i)
        xyz += glm::vec3(kCmf[i][0], kCmf[i][1], kCmf[i][2]) * spectrum[i];
    return xyz * kLambdaStep;
}

// Single-scattered XYZ radiance arriving at `origin` from direction `view` (unit), the sun
// toward `sun` (unit); `scale` the (air, dust, ozone) densities.
glm::vec3 single_scattering(const glm::vec3& view, const glm::vec3& sun, const glm::vec3& origin,
                            const glm::vec3& scale) {
    const float length = to_atmosphere_top(origin, view);
    const float seg = length / float(kSegments);
    const float mu = glm::dot(view, sun);
    const float pr = phase_rayleigh(mu), pm = phase_mie(mu);
    float spectrum[kWavelengths] = {};
    glm::vec3 depth(0.f);  // from the viewer to the current segment's midpoint
    glm::vec3 p = origin + (0.5f * seg) * view;
    for (int s = 0; s < kSegments; ++s, p += seg * view) {
        const glm::vec3 dens = scale * densities(glm::length(p) - kEarthRadius);
        depth += seg * dens;
        if (meets_ground(p, sun)) continue;
        const glm::vec3 total = depth + scale * optical_depth(p, sun);
        for (int w = 0; w < kWavelengths; ++w) {
            const float tau = total.x * kRayleigh[w] +
                              total.y * (kMieExtinctionRatio * kMieScattering) +
                              total.z * kOzone[w];
            const float scatter = pr * dens.x * kRayleigh[w] + pm * dens.y * kMieScattering;
            spectrum[w] += std::exp(-tau) * scatter * kSolarIrradiance[w] * seg;
        }
    }
    return spectrum_to_xyz(spectrum);
}

// XYZ radiance of the sun seen from `altitude` toward `dir` (unit): the extraterrestrial
// irradiance over the disc's solid angle, through Rayleigh and Mie extinction.
glm::vec3 sun_radiance(const glm::vec3& dir, float altitude, float air, float dust,
                       float solid_angle) {
    const glm::vec3 depth = optical_depth(glm::vec3(0.f, 0.f, kEarthRadius + altitude), dir);
    float spectrum[kWavelengths];
    for (int w = 0; w < kWavelengths; ++w) {
        const float tau =
            kRayleigh[w] * depth.x * air + kMieExtinctionRatio * kMieScattering * depth.y * dust;
        spectrum[w] = kSolarIrradiance[w] * std::exp(-tau) / solid_angle;
    }
    return spectrum_to_xyz(spectrum);
}

double radians(double deg) {
    return deg * kPiD / 180.0;
}

}  // namespace

SkyNishita::SkyNishita(const SkyNishitaParams& p, const Rgb& multiplier, const glm::mat3& frame)
    : m_params(p), m_multiplier(multiplier), m_frame(frame), m_inverse(glm::transpose(frame)) {
    const auto t0 = std::chrono::steady_clock::now();
    const float elevation = float(radians(p.sun_elevation));
    const float altitude = std::clamp(float(p.altitude), 1.f, 59999.f);
    const float sun_size = float(std::max(radians(p.sun_size), kMinSunSize));
    const glm::vec3 scale(float(p.air_density), float(p.dust_density), float(p.ozone_density));

    // The table (Cycles' SkyLoader): half the columns, mirrored about the sun's longitude.
    m_table.assign(std::size_t(kTableWidth) * kTableHeight, Rgb(0.f));
    const glm::vec3 origin(0.f, 0.f, kEarthRadius + altitude);
    const glm::vec3 sun = geographic(elevation, 0.f);
    const float lat_step = 0.5f * kPi / kTableHeight, lon_step = 2.f * kPi / kTableWidth;
    auto rows = [&](int y0, int y1) {
        for (int y = y0; y < y1; ++y) {
            const float t = float(y) / float(kTableHeight);
            const float latitude = (0.5f * kPi + 0.5f * lat_step) * t * t;
            for (int x = 0; x < kTableWidth / 2; ++x) {
                const glm::vec3 dir = geographic(latitude, lon_step * float(x) - kPi);
                const Rgb c = xyz_to_rgb(single_scattering(dir, sun, origin, scale));
                m_table[std::size_t(y) * kTableWidth + x] = c;
                m_table[std::size_t(y) * kTableWidth + (kTableWidth - 1 - x)] = c;
            }
        }
    };
    const int threads = int(std::clamp(std::thread::hardware_concurrency(), 1u, 8u));
    {
        std::vector<std::jthread> pool;
        for (int i = 1; i < threads; ++i)
            pool.emplace_back(rows, kTableHeight * i / threads, kTableHeight * (i + 1) / threads);
        rows(0, kTableHeight / threads);
    }

    // The sun (Cycles' precompute_sun and SkyTextureNode): two pixels at the disc's bottom and
    // top elevation (clamped at the horizon), the rotation as the kernel reads it.
    const float half = 0.5f * sun_size;
    const float solid_angle = 2.f * kPi * (1.f - std::cos(half));
    m_sun_bottom = xyz_to_rgb(sun_radiance(geographic(std::max(elevation - half, 0.f), 0.f),
                                           altitude, scale.x, scale.y, solid_angle));
    m_sun_top = xyz_to_rgb(sun_radiance(geographic(std::max(elevation + half, 0.f), 0.f), altitude,
                                        scale.x, scale.y, solid_angle));
    float rotation = std::fmod(float(radians(p.sun_rotation)), 2.f * kPi);
    if (rotation < 0.f) rotation += 2.f * kPi;
    m_rotation = double(2.f * kPi - rotation);
    m_sun_elevation = double(elevation);
    m_angular = p.sun_disc ? double(sun_size) : -1.0;
    m_sun_intensity = p.sun_intensity;
    m_sun_dir = glm::dvec3(geographic(elevation, float(m_rotation) + 0.5f * kPi));
    m_sun_dir = glm::normalize(m_sun_dir);
    m_sun_omc = 2.0 * std::pow(std::sin(0.25 * double(sun_size)), 2.0);

    // The sky's sampling density (conservative cell weights) and its mean radiance.
    std::vector<double> weights(std::size_t(kPdfWidth) * kPdfHeight);
    glm::dvec3 radiant(0.0);
    for (int y = 0; y < kPdfHeight; ++y) {
        const double theta0 = kPiD * y / kPdfHeight, theta1 = kPiD * (y + 1) / kPdfHeight;
        const double cell = 2.0 * kPiD / kPdfWidth * (std::cos(theta0) - std::cos(theta1));
        for (int x = 0; x < kPdfWidth; ++x) {
            float best = 0.f;
            for (int j = 0; j <= 2; ++j)
                for (int i = 0; i <= 2; ++i) {
                    const Vec2 uv((float(x) + 0.5f * float(i)) / kPdfWidth,
                                  (float(y) + 0.5f * float(j)) / kPdfHeight);
                    const Rgb c = sky_only(glm::dvec3(latlong_direction(uv)));
                    best = std::max(best, luminance(c));
                    if (i == 1 && j == 1) radiant += glm::dvec3(c) * cell;
                }
            weights[std::size_t(y) * kPdfWidth + x] = double(best);
        }
    }
    m_sky = LatLongDistribution(kPdfWidth, kPdfHeight, weights);
    const glm::dvec3 sky_mean = radiant / (4.0 * kPiD);

    // The sun's irradiance estimate (its mean radiance times its solid angle) and its share.
    glm::dvec3 sun_irradiance(0.0);
    const bool sun_visible =
        m_angular >= 0.0 && m_sun_intensity > 0.0 && m_sun_elevation + 0.5 * m_angular > 0.0;
    if (sun_visible) {
        const glm::dvec3 brighter = luminance(m_sun_top) > luminance(m_sun_bottom)
                                        ? glm::dvec3(m_sun_top)
                                        : glm::dvec3(m_sun_bottom);
        sun_irradiance = glm::max(brighter, glm::dvec3(0.0)) * m_sun_intensity * kLimbMean *
                         (2.0 * kPiD * m_sun_omc);
    }
    const double sun_y = luminance(Rgb(sun_irradiance));
    const double sky_y = luminance(Rgb(sky_mean * (4.0 * kPiD)));
    if (sun_y > 0.0)
        m_p_sun =
            m_sky.black() ? 1.0 : std::clamp(sun_y / (sun_y + sky_y), kMinShare, 1.0 - kMinShare);
    m_mean = Rgb((sky_mean + sun_irradiance / (4.0 * kPiD)) * glm::dvec3(multiplier));
    m_build_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

std::shared_ptr<const SkyNishita> SkyNishita::shared(const SkyNishitaParams& p,
                                                     const Rgb& multiplier,
                                                     const glm::mat3& frame) {
    static std::mutex mutex;
    static std::shared_ptr<const SkyNishita> last;
    {
        const std::lock_guard<std::mutex> lock(mutex);
        if (last && last->m_params == p && last->m_multiplier == multiplier &&
            last->m_frame == frame)
            return last;
    }
    auto sky = std::make_shared<const SkyNishita>(p, multiplier, frame);
    const std::lock_guard<std::mutex> lock(mutex);
    last = sky;
    return sky;
}

Rgb SkyNishita::table_lookup(double x, double y) const {
    const double fx = x * kTableWidth - 0.5, fy = y * kTableHeight - 0.5;
    const double x0f = std::floor(fx), y0f = std::floor(fy);
    const float tx = float(fx - x0f), ty = float(fy - y0f);
    const int x0 = std::clamp(int(x0f), 0, kTableWidth - 1);
    const int x1 = std::clamp(int(x0f) + 1, 0, kTableWidth - 1);
    const int y0 = std::clamp(int(y0f), 0, kTableHeight - 1);
    const int y1 = std::clamp(int(y0f) + 1, 0, kTableHeight - 1);
    auto at = [&](int xx, int yy) { return m_table[std::size_t(yy) * kTableWidth + xx]; };
    return (1.f - ty) * ((1.f - tx) * at(x0, y0) + tx * at(x1, y0)) +
           ty * ((1.f - tx) * at(x0, y1) + tx * at(x1, y1));
}

Rgb SkyNishita::sky_only(const glm::dvec3& l) const {
    const double phi = std::atan2(l.x, l.y);
    double x = (phi + kPiD + m_rotation) / (2.0 * kPiD);
    if (x > 1.0) x -= 1.0;
    if (l.z >= 0.0) {
        const double elevation = 0.5 * kPiD - std::acos(std::min(l.z, 1.0));
        return glm::max(table_lookup(x, std::sqrt(std::max(elevation / (0.5 * kPiD), 0.0))),
                        Rgb(0.f));
    }
    if (l.z < -0.4) return Rgb(0.f);
    const double fade = std::pow(1.0 + 2.5 * l.z, 3.0);
    return glm::max(table_lookup(x, -0.5) * float(fade), Rgb(0.f));
}

Rgb SkyNishita::sun_centre_radiance() const {
    const double half = 0.5 * m_angular;
    double y = 0.5;
    if (!(m_sun_elevation - half > 0.0)) y = m_sun_elevation / (m_sun_elevation + half);
    return (float(1.0 - y) * m_sun_bottom + float(y) * m_sun_top) * float(m_sun_intensity);
}

Rgb SkyNishita::eval_local(const glm::dvec3& l) const {
    if (l.z >= 0.0 && m_angular >= 0.0) {
        // Cycles' precise_angle: 2 atan2(|a - b|, |a + b|).
        const double angle =
            2.0 * std::atan2(glm::length(l - m_sun_dir), glm::length(l + m_sun_dir));
        const double half = 0.5 * m_angular;
        if (angle < half) {
            const double elevation = 0.5 * kPiD - std::acos(std::min(l.z, 1.0));
            double y;
            if (m_sun_elevation - half > 0.0)
                y = (elevation - m_sun_elevation) / m_angular + 0.5;
            else if (m_sun_elevation + half > 0.0)
                y = elevation / (m_sun_elevation + half);
            else
                return Rgb(0.f);
            const double r = angle / half;
            const double limb = 1.0 - kLimb * (1.0 - std::sqrt(1.0 - r * r));
            const Rgb c = (float(1.0 - y) * m_sun_bottom + float(y) * m_sun_top) *
                          float(m_sun_intensity * limb);
            return glm::max(c, Rgb(0.f));
        }
    }
    return sky_only(l);
}

Rgb SkyNishita::eval(const Vec3& d) const {
    if (!is_finite(d)) return Rgb(0.f);  // never traced; keeps the lookup's indices defined
    return eval_local(glm::dvec3(m_inverse * d)) * m_multiplier;
}

float SkyNishita::pdf(const Vec3& d) const {
    const Vec3 l = m_inverse * d;
    double p = 0.0;
    if (m_p_sun < 1.0) p += (1.0 - m_p_sun) * double(m_sky.pdf(latlong_uv(l)));
    if (m_p_sun > 0.0) {
        // 1 - cos of the angle to the sun's centre, from the chord (precise for small angles).
        const glm::dvec3 chord = glm::dvec3(l) - m_sun_dir;
        if (0.5 * glm::dot(chord, chord) <= m_sun_omc) p += m_p_sun / (2.0 * kPiD * m_sun_omc);
    }
    return float(p);
}

SkyNishita::Sample SkyNishita::sample(Vec2 u) const {
    Sample s;
    Vec3 l;
    if (u.x < float(m_p_sun)) {
        const Vec2 v(std::min(float(double(u.x) / m_p_sun), kOneMinusEpsilon), u.y);
        l = Vec3(sample_cone(Vec3(m_sun_dir), m_sun_omc, v));
    } else {
        const Vec2 v(std::min(float((double(u.x) - m_p_sun) / (1.0 - m_p_sun)), kOneMinusEpsilon),
                     u.y);
        const LatLongDistribution::Sample t = m_sky.sample(v);
        if (!(t.pdf > 0.f)) return s;
        l = latlong_direction(t.uv);
    }
    s.wi = m_frame * l;
    s.pdf = pdf(s.wi);
    if (!(s.pdf > 0.f) || !std::isfinite(s.pdf)) {
        s.pdf = 0.f;
        return s;
    }
    s.radiance = eval_local(glm::dvec3(l)) * m_multiplier;
    return s;
}

namespace {

void build(LightBuild& b) {
    const LightDesc& l = b.light;
    const std::string& ptr = b.ptr;
    SkyNishitaParams p;
    p.sun_disc = l.sun_disc;
    p.sun_size = b.check_range(l.sun_size, ptr + "/sun_size", 0.0, 90.0, "in [0, 90] degrees");
    p.sun_intensity =
        b.check_range(l.sun_intensity, ptr + "/sun_intensity", 0.0, 1e6, "in [0, 1e6]");
    p.sun_elevation =
        b.check_range(l.sun_elevation, ptr + "/sun_elevation", -90.0, 90.0, "in [-90, 90] degrees");
    p.sun_rotation =
        b.check_range(l.sun_rotation, ptr + "/sun_rotation", -1e6, 1e6, "in [-1e6, 1e6] degrees");
    p.altitude = b.check_range(l.altitude, ptr + "/altitude", 0.0, 60000.0,
                               "in [0, 60000] metres (Blender's range)");
    p.air_density = b.check_range(l.air_density, ptr + "/air_density", 0.0, 10.0,
                                  "in [0, 10] (Blender's range)");
    p.dust_density = b.check_range(l.dust_density, ptr + "/dust_density", 0.0, 10.0,
                                   "in [0, 10] (Blender's range)");
    p.ozone_density = b.check_range(l.ozone_density, ptr + "/ozone_density", 0.0, 10.0,
                                    "in [0, 10] (Blender's range)");
    const Rgb multiplier =
        l.radiance ? b.check_color(*l.radiance, ptr + "/radiance", "a radiance multiplier")
                   : Rgb(1.f);
    glm::dmat3 frame(1.0);
    if (l.rotate) {
        const Vec3 axis = b.unit_direction(l.rotate->axis, ptr + "/rotate/axis");
        b.check_finite(l.rotate->angle, ptr + "/rotate/angle");
        frame = glm::dmat3(
            glm::rotate(glm::dmat4(1.0), glm::radians(l.rotate->angle), glm::dvec3(axis)));
    }
    b.add_environment(Light::sky_nishita(SkyNishita::shared(p, multiplier, glm::mat3(frame))));
}

void pov(PovLightOut& o) {
    o.fail(o.pointer,
           "POV-Ray has no Nishita sky: render the sky to an equirectangular EXR and give it as "
           "an \"environment\" light's \"file\" to export it");
}

}  // namespace

std::optional<LightLiSample> SkyNishitaLight::sample_li(const LightSampleContext&, Vec2 u) const {
    const SkyNishita::Sample e = sky->sample(u);
    if (!(e.pdf > 0.f)) return std::nullopt;
    LightLiSample s;
    s.wi = e.wi;
    s.pdf = e.pdf;
    s.li = e.radiance;
    s.dist = kInfinity;
    return s;
}

void SkyNishitaLight::note(SceneFeatures& f) {
    f.has_environment = true;
}

Light Light::sky_nishita(std::shared_ptr<const SkyNishita> sky) {
    const Rgb mean = sky->mean_radiance();
    return make(SkyNishitaLight{std::move(sky)}, {.emission = mean});
}

extern const LightKindDef kSkyNishitaLightKind{
    LightKind::SkyNishita,
    "sky_nishita",
    "Blender 3.4's Sky Texture of type Nishita as the environment (counts as the scene's one "
    "environment), as Cycles 3.4 renders it: single scattering by air, dust and ozone and the "
    "sun's disc (see [Sky](#sky-nishita))",
    {{"sun_disc", FieldType::Bool, false, &LightDesc::sun_disc, "true",
      "whether the sun's disc is seen (and lights the scene)"},
     {"sun_size", FieldType::Number, false, &LightDesc::sun_size, "0.545",
      "the sun's full angular diameter, degrees, in [0, 90] (at least 0.0286°, as Cycles)"},
     {"sun_intensity", FieldType::Number, false, &LightDesc::sun_intensity, "1",
      "multiplies the sun's disc, >= 0"},
     {"sun_elevation", FieldType::Number, false, &LightDesc::sun_elevation, "15",
      "the sun's angle above the horizon, degrees, in [-90, 90]"},
     {"sun_rotation", FieldType::Number, false, &LightDesc::sun_rotation, "0",
      "the sun's rotation about +Z, degrees (0: toward +Y, 90: toward +X)"},
     {"altitude", FieldType::Number, false, &LightDesc::altitude, "0",
      "the viewer's height above the ground, metres, in [0, 60000] (used clamped to [1, "
      "59999], as Cycles)"},
     {"air_density", FieldType::Number, false, &LightDesc::air_density, "1",
      "Rayleigh scattering density factor, in [0, 10]"},
     {"dust_density", FieldType::Number, false, &LightDesc::dust_density, "1",
      "Mie (aerosol) density factor, in [0, 10]"},
     {"ozone_density", FieldType::Number, false, &LightDesc::ozone_density, "1",
      "ozone absorption density factor, in [0, 10]"},
     {"radiance", FieldType::Color, false, &LightDesc::radiance, "1",
      "multiplies the sky's radiance (Blender's Background Strength)"},
     {"rotate", FieldType::Rotation, false, &LightDesc::rotate, "none",
      "rotates the sky by `angle` degrees about `axis`, right-handed, in world space "
      "(Blender's Mapping node rotating the lookup by a is angle −a)"}},
    {},
    build,
    pov};

}  // namespace facet::render
