#include <CLI/CLI.hpp>

#include "commands.h"

namespace facet::cli {

void add_reflectance_command(CLI::App& app) { (void)app; }  // placeholder until the command lands

}  // namespace facet::cli
