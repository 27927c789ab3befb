#include "model_args.h"

#include <stdexcept>

#include <fmt/format.h>

namespace facet::cli {

std::vector<double> parse_numbers(const std::string& text, const std::string& flag) {
    std::vector<double> out;
    size_t pos = 0;
    while (pos <= text.size()) {
        size_t end = text.find(',', pos);
        if (end == std::string::npos) end = text.size();
        std::string item = text.substr(pos, end - pos);
        size_t used = 0;
        double v = 0.0;
        try {
            v = std::stod(item, &used);
        } catch (const std::exception&) {
            used = 0;
        }
        if (used == 0 || used != item.size() || !std::isfinite(v))
            throw std::runtime_error(fmt::format("{}: '{}' is not a finite number", flag, item));
        out.push_back(v);
        pos = end + 1;
    }
    return out;
}

Vec3 direction_from_degrees(const std::string& text, const std::string& flag) {
    std::vector<double> v = parse_numbers(text, flag);
    if (v.size() != 2) throw std::runtime_error(flag + ": expected theta,phi in degrees");
    if (v[0] < 0.0 || v[0] > 90.0)
        throw std::runtime_error(
            fmt::format("{}: theta must be in [0, 90] degrees (got {})", flag, v[0]));
    const double deg = kPiD / 180.0;
    return spherical_direction(float(v[0] * deg), float(v[1] * deg));
}

Vec2 degrees_of(const Vec3& w) {
    const double rad = 180.0 / kPiD;
    double theta = std::acos(std::clamp(double(w.z), -1.0, 1.0)) * rad;
    double phi = std::atan2(double(w.y), double(w.x)) * rad;
    return {float(theta), float(phi)};
}

Material material_from_args(const std::string& model, const std::vector<std::string>& extras,
                            ParamSet* params_out) {
    const ModelInfo* info = find_model(model);
    ParamSet params;
    if (info) {
        for (size_t i = 0; i < extras.size(); ++i) {
            const std::string& flag = extras[i];
            if (flag.rfind("--", 0) != 0)
                throw std::runtime_error(fmt::format("unexpected argument '{}'", flag));
            std::string name = flag.substr(2), value;
            if (size_t eq = name.find('='); eq != std::string::npos) {
                value = name.substr(eq + 1);
                name = name.substr(0, eq);
            } else {
                if (i + 1 >= extras.size()) throw std::runtime_error(flag + ": needs a value");
                value = extras[++i];
            }
            const ParamInfo* p = nullptr;
            for (const auto& candidate : info->params)
                if (candidate.name == name) p = &candidate;
            if (!p) {
                // Let the registry phrase the error (with its did-you-mean).
                params.set(name, value);
                break;
            }
            switch (p->type) {
                case ParamType::Number:
                    params.set(name, parse_numbers(value, flag).at(0));
                    break;
                case ParamType::Color: {
                    auto v = parse_numbers(value, flag);
                    if (v.size() == 1)
                        params.set(name, v[0]);
                    else if (v.size() == 3)
                        params.set(name, Rgb(float(v[0]), float(v[1]), float(v[2])));
                    else
                        throw std::runtime_error(flag + ": expected one number or r,g,b");
                    break;
                }
                case ParamType::Bool:
                    if (value != "true" && value != "false")
                        throw std::runtime_error(flag + ": expected true or false");
                    params.set(name, value == "true");
                    break;
                case ParamType::String:
                    params.set(name, value);
                    break;
                case ParamType::Materials:
                    throw std::runtime_error(flag + ": model '" + model +
                                             "' combines sub-materials, which only a scene "
                                             "file or the Python SceneDescription can give");
            }
        }
    }
    if (params_out) *params_out = params;
    try {
        return make_material(model, params);
    } catch (const ParamError& e) {
        std::string where = e.param().empty() ? "--model" : "--" + e.param();
        throw std::runtime_error(where + ": " + e.what());
    }
}

}  // namespace facet::cli
