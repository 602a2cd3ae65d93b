#include "apps/commands.h"
#include "core/error.h"

namespace prism::app {

void add_bench_command(CLI::App& app) {
    auto* command = app.add_subcommand("bench", "(not built yet)");
    command->callback([] { throw Error("prism bench: not implemented yet"); });
}

}  // namespace prism::app
