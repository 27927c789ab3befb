// `facet`: the command-line front end of the reflection core and the standalone renderer.
#include <CLI/CLI.hpp>

#include <cstdio>
#include <exception>

#include "commands.h"

int main(int argc, char** argv) {
    CLI::App app{"facet: physically based reflection models and renderer"};
    app.require_subcommand(1);
    facet::cli::add_brdf_commands(app);
    facet::cli::add_reflectance_command(app);
    facet::cli::add_render_command(app);
    facet::cli::add_diff_command(app);
    facet::cli::add_export_pov_command(app);
    facet::cli::add_scene_format_command(app);
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        return app.exit(e);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "facet: %s\n", e.what());
        return 1;
    }
    return 0;
}
