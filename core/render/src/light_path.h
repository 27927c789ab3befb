// Light Path switches at a hit (scene.h LightPathSwitch; integrator.h "Ray visibility"), shared
// by the media kernel and the AOV pass.
#pragma once

#include <cstdint>

#include "facet/render/scene.h"

namespace facet::render {

// A hit as a ray with Light Path outputs `lp` (LightPathRay bits) along `d` sees it, on a shape
// with switch `index` (ShapeSurface::light_path >= 0): the first matching entry's material and
// emission (front side only) instead of the shape's; nothing changes when no entry matches. An
// emitting entry on a shape that is no light source makes the hit kEmitterNotSampled (taken
// at full weight).
void apply_light_path(const Scene& scene, std::int32_t index, std::uint8_t lp, const Vec3& d,
                      SurfaceHit& hit);

}  // namespace facet::render
