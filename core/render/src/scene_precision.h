// Private to facet_render: the scene builder's checks of float precision (scene_precision.cpp).
#pragma once

#include <string>

#include "facet/render/scene_description.h"
#include "scene_impl.h"

namespace facet::render {

// A shape whose smallest feature (quad and box: shortest edge; mesh, icosphere, grid: bounding
// box diagonal; sphere: smallest semi-axis; disc: smallest in-plane semi-axis) spans fewer than
// this many float spacings (ulps) at its largest coordinate cannot be represented: it is an
// error naming the shape.
inline constexpr double kMinFeatureUlps = 4.0;
// The float spacing at the scene's largest coordinate above this fraction of the scene's
// extent (the finite shapes' bounding box diagonal) gets a warning: details that small may
// merge (a light 0.1 under a 550-unit box's ceiling, 1.8e-4 of its extent, merges with it at
// 3e6, where the spacing is 0.25).
inline constexpr double kSpacingWarnFraction = 1e-4;

// Checks the scene being built (before Scene::Impl::build moves the meshes into Embree): throws
// SceneError("<name>: /shapes/<i> ('<shape name>'): ...") for a shape too small for float at its
// coordinates, and appends one warning to the scene's warnings when the float spacing at the
// scene's coordinates is coarse against its extent.
void check_precision(Scene::Builder& builder, const SceneDescription& desc,
                     const std::string& name);

}  // namespace facet::render
