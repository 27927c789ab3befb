// null: an invisible surface, only the boundary of a medium (a material's "interior",
// scenes/FORMAT.md "Media"; pbrt-v4's "interface" material, Mitsuba's null BSDF, Cycles'
// Transparent BSDF of colour 1). It is one delta transmission straight on:
//   sample_f(wo) = {wi = -wo, f = 1/|cos theta_i|, pdf 1, Specular | Transmission},
// so f |cos| / pdf = 1 and the ray continues as if the surface were not there; f = pdf = 0 for
// every pair of directions (a true delta, facet/bxdf.h). Reciprocal, energy exactly conserved.
// Conventions: facet/inline_bxdf.h; flagged Transmission, so the frame is the shape's and wo
// may lie on either side (facet/dielectric.h). The media kernel (integrator.h) does not even
// shade it: it crosses it without a vertex and lets shadow rays through (ModelInfo::
// pass_through); other kernels see the delta transmission above.
#include "model_unit.h"

namespace facet {

namespace {

class NullTransmission {
  public:
    BSDFEval eval(const Vec3& /*wo*/, const Vec3& /*wi*/) const { return {}; }
    std::optional<BSDFSample> sample_f(const Vec3& wo, float /*uc*/, Vec2 /*u*/) const {
        if (wo.z == 0.f) return std::nullopt;
        return BSDFSample{Rgb(1.f / std::fabs(wo.z)), -wo, 1.f, flags()};
    }
    BxDFFlags flags() const { return BxDFFlags::Specular | BxDFFlags::Transmission; }
};

}  // namespace

const ModelInfo& null_model() {
    static const ModelInfo m{
        .name = "null",
        .summary =
            "an invisible surface: rays pass straight through (wi = -wo, weight 1); the "
            "boundary of a material's interior medium",
        .params = {},
        .read = [](ParamReader&, ParamValues&) {},
        .make = [](const ParamValues&,
                   Children) { return Material(InlineBxDF(NullTransmission())); },
        .pov_finish = false,
        .pass_through = true};
    return m;
}

}  // namespace facet
