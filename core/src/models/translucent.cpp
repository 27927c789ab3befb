// translucent: Blender's Translucent BSDF (Cycles' bsdf_translucent): Lambertian transmission,
//   f(wo, wi) = rho / pi   when wo and wi lie on opposite sides of the surface, else 0,
// sampled by a cosine-weighted hemisphere on wi's side. Symmetric in wo and wi (reciprocal);
// the albedo is rho at every angle (int f |cos_i| dwi over the far hemisphere).
// Conventions: facet/inline_bxdf.h; flagged Transmission, so the frame is the shape's and wo
// may lie on either side (facet/dielectric.h); no refraction, so no 1/eta^2 in either mode.
#include "facet/sampling.h"
#include "model_unit.h"

namespace facet {

namespace {

class TranslucentTransmission {
  public:
    explicit TranslucentTransmission(const Rgb& rho) : m_rho(rho) {}
    BSDFEval eval(const Vec3& wo, const Vec3& wi) const {
        if (!(wo.z * wi.z < 0.f)) return {};
        return {m_rho * kInvPi, cosine_hemisphere_pdf(std::fabs(wi.z))};
    }
    std::optional<BSDFSample> sample_f(const Vec3& wo, float /*uc*/, Vec2 u) const {
        if (wo.z == 0.f) return std::nullopt;
        Vec3 wi = sample_cosine_hemisphere(u);
        if (!(wi.z > 0.f)) return std::nullopt;
        if (wo.z > 0.f) wi.z = -wi.z;
        return BSDFSample{m_rho * kInvPi, wi, cosine_hemisphere_pdf(std::fabs(wi.z)), flags()};
    }
    BxDFFlags flags() const { return BxDFFlags::Diffuse | BxDFFlags::Transmission; }

  private:
    Rgb m_rho;
};

}  // namespace

const ModelInfo& translucent_model() {
    static const ModelInfo m{
        .name = "translucent",
        .summary =
            "Lambertian transmission as Blender's Translucent BSDF: f = rho/pi for wo "
            "and wi on opposite sides of the surface, 0 on the same side",
        .params = {models::color("transmittance", "0.8",
                                 "the transmitted fraction rho (Blender's Color), in [0, 1]")},
        .read = [](ParamReader& r,
                   ParamValues& v) { r.color(v, 0, Rgb(0.8f), 0.0, 1.0); },  // transmittance
        .make = [](const ParamValues& v,
                   Children) { return Material(InlineBxDF(TranslucentTransmission(v.color(0)))); },
        .pov_finish = false};
    return m;
}

}  // namespace facet
