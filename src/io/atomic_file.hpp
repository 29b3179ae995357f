#pragma once
// Results are written to a temporary file and renamed into place, so an interrupted run never
// leaves a half-written file that looks complete.
#include <string>

namespace heightmarch {

// Throws std::runtime_error naming the path on failure.
void write_file_atomically(const std::string& path, const std::string& content);

}  // namespace heightmarch
