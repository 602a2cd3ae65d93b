#include "apps/commands.h"
#include "core/error.h"

namespace prism::app {

void add_render_command(CLI::App& app) {
    auto* command = app.add_subcommand("render", "(not built yet)");
    command->callback([] { throw Error("prism render: not implemented yet"); });
}

}  // namespace prism::app
