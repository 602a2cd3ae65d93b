#include "apps/commands.h"
#include "core/error.h"

namespace prism::app {

void add_rays_command(CLI::App& app) {
    auto* command = app.add_subcommand("rays", "(not built yet)");
    command->callback([] { throw Error("prism rays: not implemented yet"); });
}

}  // namespace prism::app
