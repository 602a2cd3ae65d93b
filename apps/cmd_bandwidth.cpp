#include "apps/commands.h"
#include "core/error.h"

namespace prism::app {

void add_bandwidth_command(CLI::App& app) {
    auto* command = app.add_subcommand("bandwidth", "(not built yet)");
    command->callback([] { throw Error("prism bandwidth: not implemented yet"); });
}

}  // namespace prism::app
