// Sub-commands of the conceptmesh command. Each file cmd_*.cpp adds its own.
#pragma once
#include <functional>
#include <string>

#include <CLI/CLI.hpp>

namespace cm::cli {

struct GlobalOptions {
    bool quiet = false;
    bool verbose = false;
};

/// Prints "conceptmesh: error: <text>" on stderr, one line.
void print_error(const std::string& text);
void print_warning(const std::string& text);
/// Prints the plugin loader's warnings (unless quiet).
void print_plugin_diagnostics(const GlobalOptions& g);

/// Each adds its sub-command(s) to `app`; the callback stored in `action` runs it
/// and returns the exit code.
void add_pipeline_commands(CLI::App& app, GlobalOptions& g, std::function<int()>& action);
void add_tool_commands(CLI::App& app, GlobalOptions& g, std::function<int()>& action);
void add_check_command(CLI::App& app, GlobalOptions& g, std::function<int()>& action);

} // namespace cm::cli
