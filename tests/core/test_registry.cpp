// The model table: every bad parameter is rejected with a message naming it.
#include <gtest/gtest.h>

#include "facet/registry.h"

namespace facet {
namespace {

// Runs make_material and returns the ParamError (fails the test if none is thrown).
ParamError expect_error(const std::string& model, const ParamSet& p) {
    try {
        make_material(model, p);
    } catch (const ParamError& e) {
        return e;
    }
    ADD_FAILURE() << "no ParamError for model " << model;
    return ParamError("", "");
}

ParamSet params(std::initializer_list<std::pair<std::string, ParamValue>> list) {
    return ParamSet(list);
}

// Combinations (mix, add) get their ModelInfo::children sub-materials (two Lambertians).
TEST(Registry, EveryModelBuildsWithDefaults) {
    const auto l = std::make_shared<const Material>(make_material("lambert", {}));
    const std::vector<std::shared_ptr<const Material>> kids{l, l};
    for (const auto& m : model_table()) {
        const std::span<const std::shared_ptr<const Material>> children(kids.data(),
                                                                        std::size_t(m.children));
        EXPECT_NO_THROW(make_material(m.name, ParamSet{}, children)) << m.name;
    }
}

// A unit builds in one stage (build) or two (read and make, ModelInfo), never both or neither,
// and a two-stage unit's parameters fit ParamValues (the indices past kMax would write out of
// the block).
TEST(Registry, EveryModelHasOneBuilder) {
    for (const auto& m : model_table()) {
        EXPECT_EQ(bool(m.read), bool(m.make)) << m.name;
        EXPECT_NE(bool(m.build), bool(m.make)) << m.name;
        if (m.make) {
            EXPECT_LE(m.params.size(), ParamValues::kMax) << m.name;
        }
    }
}

TEST(Registry, UnknownModelSuggestsClosest) {
    ParamError e = expect_error("lamber", {});
    EXPECT_EQ(e.param(), "");
    EXPECT_NE(std::string(e.what()).find("did you mean 'lambert'"), std::string::npos) << e.what();
}

TEST(Registry, UnknownParameterSuggestsClosest) {
    ParamError e = expect_error("ggx", params({{"alpah", 0.3}}));
    EXPECT_EQ(e.param(), "alpah");
    EXPECT_NE(std::string(e.what()).find("did you mean 'alpha'"), std::string::npos) << e.what();
}

TEST(Registry, ReflectanceOutsideUnitIntervalIsRejected) {
    EXPECT_EQ(expect_error("lambert", params({{"reflectance", 1.2}})).param(), "reflectance");
    EXPECT_EQ(expect_error("lambert", params({{"reflectance", Rgb(0.5f, -0.1f, 0.5f)}})).param(),
              "reflectance");
    EXPECT_EQ(expect_error("composite", params({{"diffuse_reflectance", 2.0}})).param(),
              "diffuse_reflectance");
}

TEST(Registry, NegativeRoughnessAndNaNAreRejected) {
    EXPECT_EQ(expect_error("ggx", params({{"alpha", -0.1}})).param(), "alpha");
    EXPECT_EQ(expect_error("beckmann", params({{"alpha", std::nan("")}})).param(), "alpha");
    EXPECT_EQ(expect_error("blinn", params({{"exponent", -1.0}})).param(), "exponent");
    ParamError e = expect_error("ggx", params({{"alpha", std::nan("")}}));
    EXPECT_NE(std::string(e.what()).find("NaN"), std::string::npos) << e.what();
}

TEST(Registry, WrongTypesAreRejected) {
    EXPECT_EQ(expect_error("ggx", params({{"alpha", std::string("rough")}})).param(), "alpha");
    EXPECT_EQ(expect_error("ggx", params({{"energy_compensation", 1.0}})).param(),
              "energy_compensation");
    EXPECT_EQ(expect_error("mirror", params({{"fresnel", std::string("conductr")}})).param(),
              "fresnel");
}

TEST(Registry, ConflictingAndMeaninglessParametersAreRejected) {
    EXPECT_EQ(
        expect_error("ggx", params({{"alpha", 0.1}, {"alpha_u", 0.2}, {"alpha_v", 0.1}})).param(),
        "alpha");
    EXPECT_EQ(expect_error("ggx", params({{"alpha_u", 0.2}})).param(), "alpha_u");
    // ior means nothing to a conductor: an error, not a silently ignored value.
    EXPECT_EQ(expect_error("mirror", params({{"fresnel", std::string("conductor")}, {"ior", 1.5}}))
                  .param(),
              "ior");
    EXPECT_EQ(expect_error("composite",
                           params({{"distribution", std::string("ggx")}, {"exponent", 10.0}}))
                  .param(),
              "exponent");
    EXPECT_EQ(expect_error("composite",
                           params({{"glossy_reflectance", 0.7}, {"mirror_reflectance", 0.5}}))
                  .param(),
              "mirror_reflectance");
}

TEST(Registry, ZeroWeightLobesAreLeftOut) {
    Material m = make_material("composite", params({{"glossy_reflectance", 0.0}}));
    EXPECT_TRUE(m.diffuse().has_value());
    EXPECT_FALSE(m.glossy().has_value());
    EXPECT_FALSE(m.mirror().has_value());
    EXPECT_EQ(m.flags(), BxDFFlags::Diffuse);
}

TEST(Registry, ClosestName) {
    EXPECT_EQ(closest_name("glosy", {"glossy", "mirror"}), "glossy");
    EXPECT_EQ(closest_name("zzzzzz", {"glossy", "mirror"}), "");
}

}  // namespace
}  // namespace facet
