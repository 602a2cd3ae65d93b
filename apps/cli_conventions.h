// The conventions every `prism` subcommand shares (docs/cli.md): -o/--output beside --out, `--json -` for standard
// output, --quiet, --version, and usage errors as one line with exit code 2.
#pragma once

#include <string>
#include <vector>

#include <CLI/CLI.hpp>

namespace prism::app {

// --version and --quiet on the top-level command; both are also accepted after a subcommand.
void add_global_options(CLI::App& app);
// Whether --quiet was given: no progress and no informational output, only errors (and data asked for on stdout).
bool quiet();

// "-o,--out,--output": the output file of `command`.
CLI::Option* add_output_option(CLI::App* command, std::string& path, const std::string& description);
// "--json": a file, or "-" for standard output.
CLI::Option* add_json_option(CLI::App* command, std::string& path, const std::string& description);

// The first call of every subcommand's callback: with `json_path` "-", standard output carries only the JSON and
// the human text goes to stderr; with --quiet, the human text goes nowhere.
void route_output(const std::string& json_path = "");

// The items of a comma-separated option value ("cuda,opencl:nvidia"), empty items dropped.
std::vector<std::string> comma_list(const std::string& text);

// A CLI11 parse error as the user sees it: help and --version print and return 0; every usage error prints one line
// naming the offending option or subcommand and the help to read, and returns 2.
int report_parse_error(CLI::App& app, const CLI::ParseError& error);

}  // namespace prism::app
