// `facet scene-format --markdown`: the shape and light kind tables of the scene format, as
// scenes/FORMAT.md holds them (generated from the kind table, facet/render/kinds.h).
#include <CLI/CLI.hpp>

#include <iostream>
#include <memory>

#include "commands.h"
#include "facet/render/kinds.h"
#include "facet/render/texture_kinds.h"

namespace facet::cli {

void add_scene_format_command(CLI::App& app) {
    auto markdown = std::make_shared<bool>(false);
    CLI::App* cmd = app.add_subcommand(
        "scene-format",
        "Print the scene format's shape and light kinds: keys, types, defaults (the tables of "
        "scenes/FORMAT.md)");
    cmd->add_flag("--markdown", *markdown, "print Markdown tables (for scenes/FORMAT.md)");
    auto textures = std::make_shared<bool>(false);
    cmd->add_flag("--textures", *textures,
                  "print the procedural texture kinds' tables instead (scenes/FORMAT.md, "
                  "\"Procedural textures\")");
    cmd->callback([markdown, textures] {
        // The Markdown is also the plain-text form: tables read well in a terminal.
        std::cout << (*textures ? render::texture_kinds_markdown() : render::kinds_markdown());
    });
}

}  // namespace facet::cli
