// The POV-Ray bridge's sky sampling: `global_settings { brdf_sky_sampling N }` makes a
// `finish { brdf { ... } }` light itself by importance-sampling the scene's sky_sphere as an
// environment light, combined with the glossy rays by multiple importance sampling.
//
// Like facet_pov_bridge.h, this header includes no Facet and no POV-Ray header and speaks plain
// doubles and floats.
//
// Conventions:
//  - Directions are POV-Ray world-space unit vectors (the sky_sphere is looked up along the
//    ray direction; POV-Ray's frame is y-up and left-handed, which needs no special case here:
//    the table's frame below maps it).
//  - The table is facet::LatLongDistribution (facet/latlong.h, the standalone renderer's
//    environment map uses the same one) over W x H cells of the lat-long parametrisation in
//    the table's `frame` F (columns: the table's X, Y, Z axes in world space, orthonormal):
//    a direction d has table coordinates l = F^T d, u = 0.5 - atan2(l.y, l.x) / 2pi,
//    v = acos(l.z) / pi. The patch chooses F and W x H so that the cells are the texels of the
//    sky_sphere's spherical image map (`map_type 1`) when its transform is a rotation; any
//    other sky is still sampled without bias, only less well.
//  - Cell weight: the Rec. 709 luminance of the sky radiance averaged over the cell by the
//    trapezoid rule on a 3 x 3 grid (corners, edge midpoints, centre; shared between cells, so
//    (2W + 1) (2H + 1) lookups in all). For a bilinear image map whose texel centres are the
//    cell centres this is the exact cell mean (the lookup is linear on each half-cell), the same
//    tent-filtered mean as the standalone renderer's table. A floor of 1e-4 of the mean weight
//    keeps every direction's density positive, so that no radiance is missed even where the
//    grid does not see it.
//  - The radiance of a sampled direction is not the table's: the patch looks the sky_sphere up
//    along it, so the estimator is unbiased for any sky the table only approximates.
#pragma once

namespace facet_pov {

class Sky;

// The sky's RGB radiance along the world direction d (the patch's sky_sphere lookup).
using SkyRadianceFn = void (*)(void* context, const double d[3], float rgb[3]);

// The setting of `brdf_sky_sampling N` (N >= 1); lives until the process ends.
Sky* sky_create(int samples);
// Sky samples at one hit: N at the first hit of a camera ray (trace level 1), 1 deeper.
int sky_sample_count(const Sky* sky, unsigned trace_level);
// -1 before sky_prepare has built the table, then 0 for a black sky (nothing to sample), 1 ready:
// the patch's cheap test before it works out the table's frame.
int sky_state(const Sky* sky);
// Builds the table once (thread-safe: the first caller builds, the others wait): W x H cells in
// the frame `frame` (column-major 3 x 3, columns X, Y, Z), radiance by `fn(context, d, rgb)`.
// false when the sky is black (nothing to sample).
bool sky_prepare(Sky* sky, int width, int height, const double frame[9], SkyRadianceFn fn,
                 void* context);
// Sample `index` at one hit: the renderer's Owen-scrambled Sobol point of the sequence seeded
// by (seed, trace level), decorrelated from glossy_sample's.
void sky_sample_u(unsigned seed, unsigned trace_level, int index, double u[2]);
// A direction by the table's density, and its solid-angle pdf; false for a black sky or a pole.
bool sky_sample(const Sky* sky, const double u[2], double wi[3], double& pdf);
// The solid-angle density with which sky_sample returns the unit direction wi.
double sky_pdf(const Sky* sky, const double wi[3]);
// Veach's power heuristic for n_a samples of density pdf_a against n_b of pdf_b.
double power_heuristic(int n_a, double pdf_a, int n_b, double pdf_b);

}  // namespace facet_pov
