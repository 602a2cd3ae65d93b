#include "apps/cli_conventions.h"

#include <cstdio>
#include <sstream>

#include "core/render/backend.h"
#include "core/util/build_info.h"
#include "core/util/standard_output.h"

namespace prism::app {
namespace {

bool quiet_flag = false;

std::string version_text() {
    std::string backends = "cpu-ref";
    for (const BackendFactory& factory : registered_backends()) backends += " " + factory.name;
    return std::string("prism ") + PRISM_VERSION + "\ncommit " + build_commit() + " (" + build_type() +
           " build)\nbackends built: " + backends;
}

// The subcommand whose arguments were being read when parsing stopped: its help is the one to point at.
const CLI::App* innermost_subcommand(const CLI::App& app) {
    const CLI::App* current = &app;
    for (;;) {
        std::vector<const CLI::App*> parsed =
            current->get_subcommands([](const CLI::App* sub) { return sub->parsed(); });
        if (parsed.empty()) return current;
        current = parsed.back();
    }
}

std::string command_path(const CLI::App* command) {
    std::string path;
    for (const CLI::App* c = command; c->get_parent(); c = c->get_parent()) path = " " + c->get_name() + path;
    return "prism" + path;  // as typed, whatever path the binary was run by
}

// CLI11 names a missing required option by its first long name; name every spelling, so "-o" is found too.
std::string name_every_spelling(const CLI::App* command, const std::string& message) {
    const std::string suffix = " is required";
    if (message.size() <= suffix.size() || message.compare(message.size() - suffix.size(), suffix.size(), suffix))
        return message;
    std::string name = message.substr(0, message.size() - suffix.size());
    for (const CLI::Option* option : command->get_options())
        if (option->get_name() == name) return option->get_name(false, true) + suffix;
    return message;
}

}  // namespace

void add_global_options(CLI::App& app) {
    app.set_version_flag("--version", version_text, "Print the version, commit and backends built, and exit");
    app.add_flag("-q,--quiet", quiet_flag, "No progress and no informational output: only errors (and data on stdout)");
    app.fallthrough();  // `prism render ... --quiet` as well as `prism --quiet render ...`
}

bool quiet() { return quiet_flag; }

CLI::Option* add_output_option(CLI::App* command, std::string& path, const std::string& description) {
    return command->add_option("-o,--out,--output", path, description);
}

CLI::Option* add_json_option(CLI::App* command, std::string& path, const std::string& description) {
    return command->add_option("--json", path, description + " (\"-\": standard output, human text then on stderr)");
}

void route_output(const std::string& json_path) {
    if (json_path == "-") reserve_standard_output_for_data();
    if (quiet_flag) silence_standard_output();
}

int report_parse_error(CLI::App& app, const CLI::ParseError& error) {
    if (error.get_exit_code() == 0) return app.exit(error);  // --help, --help-all, --version
    const CLI::App* command = innermost_subcommand(app);
    std::string message = name_every_spelling(command, error.what());
    // CLI11 checks required options before it complains about words it did not expect; the unexpected word is the
    // more useful news (a misspelt option often is the required one).
    std::vector<std::string> extras = app.remaining(true);
    if (!extras.empty() && command == &app && !extras.front().empty() && extras.front()[0] != '-') {
        std::string known;
        for (const CLI::App* sub : app.get_subcommands({})) known += (known.empty() ? "" : ", ") + sub->get_name();
        message = "unknown subcommand '" + extras.front() + "' (one of " + known + ")";
    } else if (!extras.empty()) {
        message =
            std::string(extras.front()[0] == '-' ? "unknown option '" : "unexpected argument '") + extras.front() + "'";
    }
    std::fprintf(stderr, "%s: error: %s; see '%s --help'\n", command_path(command).c_str(), message.c_str(),
                 command_path(command).c_str());
    return 2;
}

std::vector<std::string> comma_list(const std::string& text) {
    std::vector<std::string> out;
    std::stringstream stream(text);
    for (std::string item; std::getline(stream, item, ',');)
        if (!item.empty()) out.push_back(item);
    return out;
}

}  // namespace prism::app
