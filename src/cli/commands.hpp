#pragma once
// The subcommands of build/heightmarch; each returns the process exit status.
#include <string>
#include <vector>

namespace heightmarch::cli {

int trace_command(const std::vector<std::string>& args);
int glsl_command(const std::vector<std::string>& args);
int suite_command(const std::vector<std::string>& args);
int claims_command(const std::vector<std::string>& args);

}  // namespace heightmarch::cli
