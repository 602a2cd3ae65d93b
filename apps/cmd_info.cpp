#include "apps/commands.h"
#include "core/error.h"

namespace prism::app {

void add_info_command(CLI::App& app) {
    auto* command = app.add_subcommand("info", "(not built yet)");
    command->callback([] { throw Error("prism info: not implemented yet"); });
}

}  // namespace prism::app
