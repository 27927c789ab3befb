// The table of the renderer's light types (light.h "Structure"): one line per type, each a
// struct of facet/render/lights/<type>.h whose unit is core/render/src/lights/<type>.cpp. A
// Light holds one of them; Light's dispatch (std::visit over this variant) is the only code
// that goes from a light to its type. Adding a type: its header and unit, its line here, its
// factory in light.h, its tests.
#pragma once

#include <variant>

#include "facet/render/lights/area_lamp.h"
#include "facet/render/lights/directional.h"
#include "facet/render/lights/emissive_disc.h"
#include "facet/render/lights/emissive_moving.h"
#include "facet/render/lights/emissive_sphere.h"
#include "facet/render/lights/emissive_triangles.h"
#include "facet/render/lights/environment.h"
#include "facet/render/lights/environment_map.h"
#include "facet/render/lights/point.h"
#include "facet/render/lights/sky_nishita.h"
#include "facet/render/lights/spot.h"

namespace facet::render {

using LightTypes =
    std::variant<EmissiveParallelogram, PointLight, SpotLight, DirectionalLight,
                 ConstantEnvironment, EnvironmentMapLight, AreaLamp, EmissiveTriangles,
                 EmissiveSphere, EmissiveDisc, SkyNishitaLight, EmissiveMovingTriangles>;

}  // namespace facet::render
