// `facet scene-format --markdown`: the shape and light kind tables of the scene format, as
// scenes/FORMAT.md holds them (generated from the kind table, facet/render/kinds.h).
#include <CLI/CLI.hpp>

#include <iostream>
#include <memory>

#include "commands.h"
#include "facet/render/kinds.h"

namespace facet::cli {

void add_scene_format_command(CLI::App& app) {
    auto markdown = std::make_shared<bool>(false);
    CLI::App* cmd = app.add_subcommand(
        "scene-format",
        "Print the scene format's shape and light kinds: keys, types, defaults (the tables of "
        "scenes/FORMAT.md)");
    cmd->add_flag("--markdown", *markdown, "print Markdown tables (for scenes/FORMAT.md)");
    cmd->callback([markdown] {
        // The Markdown is also the plain-text form: tables read well in a terminal.
        std::cout << render::kinds_markdown();
    });
}

}  // namespace facet::cli
