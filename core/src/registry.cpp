// The model table: one line per model unit (core/src/models/<model>.cpp defines its
// parameters, documentation and builder). This table is the documentation of the models too
// (docs/models.md is printed from it by `facet brdf models --markdown`).
#include "facet/registry.h"

#include <algorithm>
#include <functional>
#include <limits>

#include "models/model_unit.h"

namespace facet {

const ModelInfo& lambert_model();
const ModelInfo& mirror_model();
const ModelInfo& ggx_model();
const ModelInfo& beckmann_model();
const ModelInfo& blinn_model();
const ModelInfo& composite_model();
const ModelInfo& dielectric_model();
const ModelInfo& principled_model();
const ModelInfo& oren_nayar_model();
const ModelInfo& mix_model();
const ModelInfo& add_model();
const ModelInfo& thin_dielectric_model();
const ModelInfo& translucent_model();
const ModelInfo& velvet_model();
const ModelInfo& principled_hair_model();
const ModelInfo& hair_model();
const ModelInfo& null_model();
const ModelInfo& holdout_model();
const ModelInfo& subsurface_model();

namespace {

size_t edit_distance(std::string_view a, std::string_view b) {
    std::vector<size_t> prev(b.size() + 1), cur(b.size() + 1);
    for (size_t j = 0; j <= b.size(); ++j) prev[j] = j;
    for (size_t i = 1; i <= a.size(); ++i) {
        cur[0] = i;
        for (size_t j = 1; j <= b.size(); ++j) {
            size_t sub = prev[j - 1] + (std::tolower(a[i - 1]) == std::tolower(b[j - 1]) ? 0 : 1);
            cur[j] = std::min({prev[j] + 1, cur[j - 1] + 1, sub});
        }
        std::swap(prev, cur);
    }
    return prev[b.size()];
}

}  // namespace

const std::vector<ModelInfo>& model_table() {
    // Documentation order.
    static const std::vector<ModelInfo> table = {
        lambert_model(),     mirror_model(),     ggx_model(),
        beckmann_model(),    blinn_model(),      composite_model(),
        dielectric_model(),  principled_model(), oren_nayar_model(),
        mix_model(),         add_model(),        thin_dielectric_model(),
        translucent_model(), velvet_model(),     principled_hair_model(),
        hair_model(),        null_model(),       holdout_model(),
        subsurface_model()};
    return table;
}

const ModelInfo* find_model(std::string_view name) {
    for (const auto& m : model_table())
        if (m.name == name) return &m;
    return nullptr;
}

Material make_material(std::string_view model, const ParamSet& params,
                       std::span<const std::shared_ptr<const Material>> children) {
    const ModelInfo* info = find_model(model);
    if (!info) {
        std::vector<std::string> names;
        for (const auto& m : model_table()) names.push_back(m.name);
        std::string msg = "unknown model '" + std::string(model) + "'";
        std::string guess = closest_name(model, names);
        if (!guess.empty()) msg += " (did you mean '" + guess + "'?)";
        msg += "; models:";
        for (const auto& n : names) msg += " " + n;
        throw ParamError("", msg);
    }
    ParamReader r(*info, params);
    if (r.has("materials"))
        throw r.error("materials",
                      "sub-materials are not a parameter value (give materials [a, b])");
    if (std::ptrdiff_t(children.size()) != info->children) {
        if (info->children == 0) throw r.error("materials", "this model takes no sub-materials");
        throw r.error("materials", "needs exactly " + std::to_string(info->children) +
                                       " sub-materials (got " + std::to_string(children.size()) +
                                       ")");
    }
    for (const auto& c : children)
        if (!c) throw r.error("materials", "a sub-material is missing");
    if (!info->make) return info->build(r, children);
    ParamValues v;
    info->read(r, v);
    return info->make(v, children);
}

std::string closest_name(std::string_view name, const std::vector<std::string>& candidates) {
    std::string best;
    size_t best_d = std::numeric_limits<size_t>::max();
    for (const auto& c : candidates) {
        size_t d = edit_distance(name, c);
        if (d < best_d) best_d = d, best = c;
    }
    // Close enough: at most a third of the name's letters wrong (and at least 2 allowed).
    size_t limit = std::max<size_t>(2, name.size() / 3);
    return best_d <= limit ? best : std::string();
}

}  // namespace facet
