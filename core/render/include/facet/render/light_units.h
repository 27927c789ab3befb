// Light unit conversions: one function per quantity, used by the renderer's light types
// (lights/*.cpp), by every exporter (`facet export-pov`) and, through the Python module under
// the same names (point_intensity, spot_intensity, cycles_spot_intensity,
// cycles_spot_attenuation), by the Blender addon's units.py, so that a unit is converted in
// exactly one place.
//
// Conventions:
//  - Facet's units are scenes/FORMAT.md's: point and spot lights by radiant power Phi (W),
//    directional lights by irradiance E (W m^-2), emitters by radiance L (W sr^-1 m^-2), angles
//    in degrees. Everything here is per RGB channel and in double precision.
//  - POV-Ray colours are those of povray-facet (the POV-Ray patch): a light of colour c with
//    `physical_falloff` gives a surface of BRDF f the radiance pi f cos(theta_i) c / d^2 (the
//    patch's scale, chosen so that Lambert rho/pi equals classic `diffuse rho`), so c is the
//    radiant intensity divided by pi; a `parallel` light (no falloff) gives pi f cos c, so c is
//    the irradiance divided by pi.
#pragma once

#include <cmath>

#include "facet/types.h"

namespace facet::render {

// Radiant intensity (W/sr) of an isotropic point light of power Phi: I = Phi / (4 pi)
// (Cohen & Wallace eq. 2.40).
inline glm::dvec3 point_intensity(const glm::dvec3& power) {
    return power / (4.0 * kPiD);
}

// On-axis intensity I0 (W/sr) of a spot light of power Phi whose intensity is I0 inside the
// inner cone, 0 outside the outer cone and linear in cos(theta) between them (half-angles in
// degrees): Phi = 2 pi I0 [(1 - cos inner) + (cos inner - cos outer) / 2]. 1 - cos is written
// as 2 sin^2(theta / 2) to keep precision for narrow cones. A zero-width cone gives 0.
inline glm::dvec3 spot_intensity(const glm::dvec3& power, double inner_deg, double outer_deg) {
    const double half_in = 0.5 * inner_deg * kPiD / 180.0;
    const double half_out = 0.5 * outer_deg * kPiD / 180.0;
    const double one_minus_ci = 2.0 * std::sin(half_in) * std::sin(half_in);
    const double one_minus_co = 2.0 * std::sin(half_out) * std::sin(half_out);
    const double solid = 2.0 * kPiD * 0.5 * (one_minus_ci + one_minus_co);
    return solid > 0.0 ? power / solid : glm::dvec3(0.0);
}

// Blender's spot fall-off, as Cycles 3.4 computes it (spot_light_attenuation): with mu = cos
// theta from the axis, c = cos(spot_size / 2) and smooth = (1 - c) spot_blend,
//   g(mu) = 0 for mu <= c, mu * smoothstep((mu - c) / smooth) for c < mu < c + smooth,
//   mu otherwise, smoothstep(x) = 3x^2 - 2x^3.
// (The factor mu is Cycles': its spot intensity is P / (4 pi) g(mu) for a lamp of power P.)
inline double cycles_spot_attenuation(double mu, double c, double smooth) {
    if (mu <= c) return 0.0;
    const double t = mu - c;
    if (t < smooth && smooth != 0.0) {
        const double x = t / smooth;
        return mu * x * x * (3.0 - 2.0 * x);
    }
    return mu;
}

// K (W/sr) of a spot of power Phi with intensity I = K g(mu) (cycles_spot_attenuation) for the
// half-angle outer (degrees, <= 90) and blend: Phi = 2 pi K int_c^1 g, where
//   int_c^1 g dmu = (1 - (c + s)^2) / 2 + s (c / 2 + 0.35 s), s = (1 - c) blend
// (int_0^1 smoothstep = 1/2, int_0^1 x smoothstep = 3/4 - 2/5). A Blender spot of power P has
// K = P / (4 pi), so Phi = P / 2 int_c^1 g. A zero-width cone gives 0.
inline glm::dvec3 cycles_spot_intensity(const glm::dvec3& power, double outer_deg, double blend) {
    const double c = std::cos(outer_deg * kPiD / 180.0);
    const double s = (1.0 - c) * blend;
    const double integral = 0.5 * (1.0 - (c + s) * (c + s)) + s * (0.5 * c + 0.35 * s);
    return integral > 0.0 ? power / (2.0 * kPiD * integral) : glm::dvec3(0.0);
}

// The area (m^2) Blender's area lamp divides its power by (Cycles 3.4, scene/light.cpp): size
// x size_y for the square (size_y = size) and the rectangle, pi/4 of that for the disc and the
// ellipse. `round`: disc or ellipse.
inline double area_lamp_area(bool round, double size, double size_y) {
    return round ? 0.25 * kPiD * size * size_y : size * size_y;
}

// Radiance (W sr^-1 m^-2) of Blender's area lamp of power P (W) and area A (area_lamp_area):
// L = P / (4 A) (Cycles 3.4: eval_fac = 1/4 invarea), so the emitted flux is pi L A = pi P / 4.
// The `area` light kind applies it to its `power` (lights/area.cpp), so the Blender addon
// passes Blender's Power through unchanged and converts nothing itself (units.py).
inline glm::dvec3 area_lamp_radiance(const glm::dvec3& power, double area) {
    return power / (4.0 * area);
}

// On-axis intensity (W/sr) of a flat Lambertian emitter of radiance L and area A:
// I(theta) = L A cos(theta), so I0 = L A.
inline glm::dvec3 emitter_intensity(const glm::dvec3& radiance, double area) {
    return radiance * area;
}

// povray-facet light colour of a `physical_falloff` light of radiant intensity I (W/sr):
// c = I / pi (see conventions).
inline glm::dvec3 pov_light_colour(const glm::dvec3& intensity) {
    return intensity / kPiD;
}

// povray-facet colour of a `parallel` light giving irradiance E (W m^-2) on a surface facing
// it: c = E / pi (see conventions).
inline glm::dvec3 pov_parallel_colour(const glm::dvec3& irradiance) {
    return irradiance / kPiD;
}

}  // namespace facet::render
