// Sub-commands of the conceptmesh command: each file cmd_<name>.cpp adds one.
#pragma once
#include <functional>
#include <string>

#include <CLI/CLI.hpp>

namespace cm::cli {

struct GlobalOptions {
    bool quiet = false;
    bool verbose = false;
};

/// `text` with every run of more than 240 non-blank characters (a path or value pasted by
/// mistake, megabytes long) cut to its first and last 100, saying how long it was.
std::string shorten_long_words(const std::string& text);

/// Prints "conceptmesh: error: <text>" on stderr, one line (long words shortened).
void print_error(const std::string& text);
void print_warning(const std::string& text);
/// Prints the plugin loader's warnings (unless quiet).
void print_plugin_diagnostics(const GlobalOptions& g);

/// Each adds its sub-command to `app`; once the command line is parsed, `action` runs it
/// and returns the exit code.
void add_run_command(CLI::App& app, GlobalOptions& g, std::function<int()>& action);          // cmd_run.cpp
void add_validate_command(CLI::App& app, GlobalOptions& g, std::function<int()>& action);     // cmd_validate.cpp
void add_stages_command(CLI::App& app, GlobalOptions& g, std::function<int()>& action);       // cmd_stages.cpp
void add_schema_command(CLI::App& app, GlobalOptions& g, std::function<int()>& action);       // cmd_schema.cpp
void add_render_views_command(CLI::App& app, GlobalOptions& g, std::function<int()>& action); // cmd_render_views.cpp
void add_compare_command(CLI::App& app, GlobalOptions& g, std::function<int()>& action);      // cmd_compare.cpp
void add_preview_command(CLI::App& app, GlobalOptions& g, std::function<int()>& action);      // cmd_preview.cpp
void add_check_command(CLI::App& app, GlobalOptions& g, std::function<int()>& action);        // cmd_check.cpp
void add_batch_command(CLI::App& app, GlobalOptions& g, std::function<int()>& action);        // cmd_batch.cpp

} // namespace cm::cli
