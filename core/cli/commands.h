// Sub-commands of the `facet` tool. Each front-end-facing command lives in its own file and
// registers itself on the CLI11 app; errors are reported as "facet: <place>: <message>" with a
// non-zero exit code by main().
#pragma once

namespace CLI {
class App;
}

namespace facet::cli {

void add_brdf_commands(CLI::App& app);        // brdf_cmd.cpp: brdf eval | sample | plot
void add_reflectance_command(CLI::App& app);  // reflectance_cmd.cpp
void add_render_command(CLI::App& app);       // render_cmd.cpp (renderer, issue 3)
void add_diff_command(CLI::App& app);         // diff_cmd.cpp (image comparison, convert)
void add_export_pov_command(CLI::App& app);   // export_pov_cmd.cpp (POV-Ray SDL)
void add_scene_format_command(CLI::App& app);  // scene_format_cmd.cpp (kind tables)

}  // namespace facet::cli
