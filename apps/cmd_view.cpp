#include "apps/commands.h"
#include "core/error.h"

namespace prism::app {

void add_view_command(CLI::App& app) {
    auto* command = app.add_subcommand("view", "(not built yet)");
    command->callback([] { throw Error("prism view: not implemented yet"); });
}

}  // namespace prism::app
