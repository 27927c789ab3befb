// Shape kind "instance": one placement of a named prototype (SceneDescription::prototypes) by
// the shape's transform. The prototype's geometry is stored once and traced as an Embree
// instance (a two-level BVH: embree_scene.cpp); hits report the prototype's shapes, with their
// materials, in world space (normals by the transform's inverse transpose).
#include "../io/pov_writer.h"
#include "../kind_build.h"

namespace facet::render {

namespace {

void build(ShapeBuild& b) {
    b.add_instance(b.shape.of, b.ptr + "/of");
}

// POV-Ray's own instancing: the prototype as a declared union, placed by `object`.
void pov(PovShapeOut& o) {
    o.instance(o.shape.of);
}

}  // namespace

extern const ShapeKindDef kInstanceKind{
    ShapeKind::Instance,
    "instance",
    "the shapes of a named prototype (top-level `\"prototypes\"`, scenes/FORMAT.md "
    "\"Instances\") placed by `transform` (object to world: each prototype point p goes to "
    "M p, normals to M^-T n); stored once however many instances use it. Only `transform` and "
    "`name` of the common keys apply: the materials are the prototype shapes'",
    {{"of", FieldType::Text, true, &ShapeDesc::of, "-", "the prototype's name"}},
    build,
    nullptr,
    pov,
    false,
    true};

}  // namespace facet::render
