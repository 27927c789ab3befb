// Texture kind "hair_info": an output of Blender 3.4's Hair Info node at the hit, as Cycles 3.4
// gives it on curves (svm_node_hair_info and the curve attributes of blender/curves.cpp):
//  - random: the strand's random value: the shape's strand_random, or curve_random of its
//    index in the shape (scene.h);
//  - intercept: the position along the strand, 0 at the root and 1 at the tip
//    (SurfaceHit::strand_v: uniform in the curve parameter of each segment; Cycles interpolates
//    the keys' fraction of the strand's length, the same where the segments are of equal
//    length);
//  - is_strand: 1 on curves.
// Off curves each is 0, as in Cycles. A composite-like kind: it reads no point (no
// coordinates or mapping), only the hit's strand (kTextureReadsStrand).
#include "composite.h"

namespace facet::render {

namespace {

enum class Output { Random, Intercept, IsStrand };

const std::vector<std::string> kOutputs = {"random", "intercept", "is_strand"};

class HairInfoSource final : public CompositeSource {
  public:
    Output m_output = Output::Random;
    Rgb value(const TexturePoint& p) const override {
        switch (m_output) {
            case Output::Intercept:
                return Rgb(p.strand_v);
            case Output::IsStrand:
                return Rgb(p.on_strand);
            case Output::Random:
            default:
                return Rgb(p.strand_random);
        }
    }
};

Texture build_hair_info(TextureBuild& b) {
    check_texture_params(b, kHairInfoTexture);
    auto s = std::make_shared<HairInfoSource>();
    const CompositeParams p(b, kHairInfoTexture);
    s->m_output = Output(p.choice("output"));
    return make_composite(b, kHairInfoTexture, s, Rgb(0.f), Rgb(1.f), kTextureReadsStrand,
                          "hair_info");
}

}  // namespace

const TextureKindDef kHairInfoTexture{
    "hair_info",
    "Blender's Hair Info node on curves: the strand's `random` value (the shape's "
    "`strand_random`, or Cycles 3.4's hash of the strand's index), its `intercept` (0 at the "
    "root, 1 at the tip) or `is_strand` (1); 0 off curves (no coordinates)",
    {
        {"output", ParamType::String, 0, "random", 0, 0, false, kOutputs, kOutputDoc},
    },
    true,
    build_hair_info,
    true,
};

}  // namespace facet::render
