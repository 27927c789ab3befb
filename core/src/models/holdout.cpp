// holdout: a hole in the image (Blender's Holdout shader, Cycles' holdout closure). Where a
// camera ray, directly or through transparent surfaces, reaches it, the pixel's alpha loses the
// path's throughput and the colour gains nothing (facet/render/integrator.h, "Alpha"); inside a
// `mix` or `add` only its share does (Material::holdout_weight). To every other ray it is a
// black surface: it reflects and transmits nothing and casts shadows, as in Cycles.
#include "model_unit.h"

namespace facet {

const ModelInfo& holdout_model() {
    static const ModelInfo m{
        .name = "holdout",
        .summary =
            "a hole in the image: alpha 0 and colour 0 where camera rays reach it (Blender's "
            "Holdout shader); black to other rays",
        .params = {},
        .read = [](ParamReader&, ParamValues&) {},
        .make = [](const ParamValues&, Children) { return Material::holdout(); },
        .pov_finish = false};
    return m;
}

}  // namespace facet
