#pragma once
// The subcommands of build/heightmarch. Each declares its options on its CLI11 subcommand and
// returns what runs it (after parsing), which returns the process exit status.
#include <CLI/CLI.hpp>
#include <functional>
#include <stdexcept>

namespace heightmarch::cli {

using Command = std::function<int()>;

// A failure a child process (the report) has told the user in its own one line: the command ends
// with the child's exit status and prints nothing more.
struct ChildFailed : std::runtime_error {
  explicit ChildFailed(int status) : std::runtime_error("a child process failed"), status(status) {}
  int status;
};

Command add_trace_command(CLI::App& app);
Command add_glsl_command(CLI::App& app);
Command add_suite_command(CLI::App& app);
Command add_claims_command(CLI::App& app);
Command add_recommend_command(CLI::App& app);
Command add_report_command(CLI::App& app);

}  // namespace heightmarch::cli
