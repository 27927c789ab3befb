// Turning `facet brdf|reflectance --model M --alpha 0.3 --fresnel conductor ...` into a
// validated Material. Model parameters are the registry's names as long options, so the CLI,
// JSON scenes, POV-Ray and Blender all use the same words.
#pragma once

#include <string>
#include <vector>

#include "facet/registry.h"

namespace facet::cli {

// Parses "--name value" pairs (CLI11's extras) against the model's parameter table and builds
// the material. Throws std::runtime_error naming the flag on a bad or unknown flag.
Material material_from_args(const std::string& model, const std::vector<std::string>& extras,
                            ParamSet* params_out = nullptr);

// Parses "theta,phi" in degrees into a local-frame direction. Throws naming `flag`.
Vec3 direction_from_degrees(const std::string& text, const std::string& flag);

// Degrees of a local-frame direction, for printing.
Vec2 degrees_of(const Vec3& w);

// Splits "a,b,c" into numbers; throws naming `flag`.
std::vector<double> parse_numbers(const std::string& text, const std::string& flag);

}  // namespace facet::cli
