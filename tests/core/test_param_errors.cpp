// Bad parameters produce the documented error (facet/registry.h): make_material throws
// ParamError whose param() is the offending parameter's name and whose message names it, for
// every model of model_table() and every parameter of the right kind - reflectances outside
// [0, 1], negative roughness, NaN (for every numeric or colour parameter), unknown parameter
// names (with a "did you mean" suggestion) and unknown model names.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "facet/registry.h"

namespace facet {
namespace {

bool is_reflectance(const std::string& name) {
    return name.find("reflectance") != std::string::npos || name == "f0";
}
bool is_roughness(const std::string& name) {
    return name.rfind("alpha", 0) == 0 || name.rfind("exponent", 0) == 0;
}

// Companion parameters a parameter needs to be meaningful (otherwise the registry rightly
// rejects it as "has no effect", which would not test the value check).
ParamSet context_for(const ModelInfo& model, const std::string& name) {
    ParamSet p;
    // Dielectrics take ior directly (they have no fresnel parameter).
    const bool has_fresnel = std::any_of(model.params.begin(), model.params.end(),
                                         [](const ParamInfo& q) { return q.name == "fresnel"; });
    if (name == "ior" && has_fresnel) p.set("fresnel", std::string("dielectric"));
    if (name == "eta" || name == "k") p.set("fresnel", std::string("conductor"));
    if (name == "f0") p.set("fresnel", std::string("schlick"));
    if (name == "alpha_u") p.set("alpha_v", 0.3);
    if (name == "alpha_v") p.set("alpha_u", 0.3);
    if (name == "exponent_u") p.set("exponent_v", 10.0);
    if (name == "exponent_v") p.set("exponent_u", 10.0);
    if (name == "mirror_reflectance") p.set("glossy_reflectance", 0.5);  // sum <= 1
    if (model.name == "composite" && name.rfind("exponent", 0) == 0)
        p.set("distribution", std::string("blinn"));
    if (model.name == "mix" && name == "ior") p.set("factor", std::string("fresnel"));
    if (model.name == "mix" && name == "blend") p.set("factor", std::string("layer_facing"));
    if (model.name == "principled_hair") {
        if (name == "melanin" || name == "melanin_redness" || name == "tint" ||
            name == "random_color")
            p.set("parametrization", std::string("melanin"));
        if (name == "absorption_coefficient") p.set("parametrization", std::string("absorption"));
    }
    return p;
}

// The sub-materials a model takes (mix, add: two Lambertians; others none).
std::span<const std::shared_ptr<const Material>> children_for(std::string_view model) {
    static const auto l = std::make_shared<const Material>(make_material("lambert", {}));
    static const std::vector<std::shared_ptr<const Material>> kids{l, l};
    const ModelInfo* info = find_model(model);  // null for the unknown-model tests
    return {kids.data(), info ? std::size_t(info->children) : 0};
}

// Expects make_material to throw ParamError naming `param`; returns the message.
std::string expect_param_error(const std::string& model, const ParamSet& p,
                               const std::string& param) {
    try {
        make_material(model, p, children_for(model));
    } catch (const ParamError& e) {
        EXPECT_EQ(e.param(), param) << model << ": " << e.what();
        if (!param.empty()) {
            EXPECT_NE(std::string(e.what()).find(param), std::string::npos)
                << model << ": message does not name '" << param << "': " << e.what();
        }
        return e.what();
    } catch (const std::exception& e) {
        ADD_FAILURE() << model << "/" << param << ": wrong exception type: " << e.what();
        return {};
    }
    ADD_FAILURE() << model << "/" << param << ": accepted a bad value";
    return {};
}

TEST(ParamErrors, EveryModelBuildsFromDefaultsAndFromEachParameterInContext) {
    for (const ModelInfo& m : model_table()) {
        EXPECT_NO_THROW(make_material(m.name, ParamSet{}, children_for(m.name))) << m.name;
        for (const ParamInfo& p : m.params) {
            ParamSet ps = context_for(m, p.name);
            if (p.type == ParamType::Number || p.type == ParamType::Color) {
                const bool ior = p.name == "ior" || p.name == "eta" || p.name.ends_with("_ior");
                ps.set(p.name, ior ? 1.5 : 0.5);
                EXPECT_NO_THROW(make_material(m.name, ps, children_for(m.name)))
                    << m.name << "/" << p.name;
            }
        }
    }
}

TEST(ParamErrors, NaNIsRejectedForEveryNumericParameter) {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    int checked = 0;
    for (const ModelInfo& m : model_table()) {
        for (const ParamInfo& p : m.params) {
            if (p.type != ParamType::Number && p.type != ParamType::Color) continue;
            ParamSet ps = context_for(m, p.name);
            ps.set(p.name, nan);
            expect_param_error(m.name, ps, p.name);
            if (p.type == ParamType::Color) {  // a NaN in one channel of a colour too
                ParamSet pc = context_for(m, p.name);
                pc.set(p.name, Rgb(0.5f, std::numeric_limits<float>::quiet_NaN(), 0.5f));
                expect_param_error(m.name, pc, p.name);
            }
            ++checked;
        }
    }
    EXPECT_GE(checked, 20);
}

TEST(ParamErrors, ReflectanceOutsideUnitIntervalIsRejected) {
    int checked = 0;
    for (const ModelInfo& m : model_table()) {
        for (const ParamInfo& p : m.params) {
            if (!is_reflectance(p.name)) continue;
            for (double bad : {-0.01, 1.01, -1e30, std::numeric_limits<double>::infinity()}) {
                ParamSet ps = context_for(m, p.name);
                ps.set(p.name, bad);
                expect_param_error(m.name, ps, p.name);
            }
            ParamSet pc = context_for(m, p.name);  // one bad channel in a colour
            pc.set(p.name, Rgb(0.2f, 1.5f, 0.2f));
            expect_param_error(m.name, pc, p.name);
            ++checked;
        }
    }
    EXPECT_GE(checked, 7);  // lambert, mirror, ggx, beckmann, blinn, 3 composite, f0 ...
}

TEST(ParamErrors, NegativeRoughnessIsRejected) {
    int checked = 0;
    for (const ModelInfo& m : model_table()) {
        for (const ParamInfo& p : m.params) {
            if (!is_roughness(p.name)) continue;
            for (double bad : {-1e-9, -0.5}) {
                ParamSet ps = context_for(m, p.name);
                ps.set(p.name, bad);
                expect_param_error(m.name, ps, p.name);
            }
            ++checked;
        }
    }
    EXPECT_GE(checked, 12);
}

TEST(ParamErrors, UnknownParameterIsRejectedWithSuggestion) {
    for (const ModelInfo& m : model_table()) {
        // A one-letter typo of the model's first parameter (`null` has none).
        if (!m.params.empty()) {
            std::string real = m.params.front().name;
            std::string typo = real;
            std::swap(typo[1], typo[2]);
            ParamSet ps;
            ps.set(typo, 0.5);
            std::string msg = expect_param_error(m.name, ps, typo);
            EXPECT_NE(msg.find("did you mean '" + real + "'"), std::string::npos) << msg;
        }
        // Something unrelated: rejected, no suggestion needed.
        ParamSet pu;
        pu.set("zzzzzzzzzz", 1.0);
        expect_param_error(m.name, pu, "zzzzzzzzzz");
    }
}

TEST(ParamErrors, UnknownModelIsRejectedWithSuggestion) {
    std::string msg = expect_param_error("gxx", ParamSet{}, "");
    EXPECT_NE(msg.find("did you mean 'ggx'"), std::string::npos) << msg;
    msg = expect_param_error("lamburt", ParamSet{}, "");
    EXPECT_NE(msg.find("did you mean 'lambert'"), std::string::npos) << msg;
}

}  // namespace
}  // namespace facet
